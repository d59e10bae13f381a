//! Frequency response of a constrained structure (the f-set of [`Constrained`]) to unit loads
//! on its input shapes, as the library call behind SOL 108 and SOL 111:
//!
//! - direct: one sparse complex LU symbolic analysis of K_ff − ω²M_ff + iωC_ff, one numeric LU
//!   (plus one refinement step) per line, lines in parallel ([`direct_receptance`]);
//! - modal: the modes an eigen request asks for (shift-invert Lanczos, mass normalized) and,
//!   on request, the residual vectors of the input shapes ([`residual_vectors`], Nastran's
//!   RESVEC), superposed with modal damping 2ζ_jω_j = α + βω_j² ([`modal_receptance`]). The
//!   residual vectors carry the static part of the modes left out (exact at 0 Hz); on a
//!   free-free model (K singular) they are skipped ([`FullFrf::resvec_skipped`]).
//!
//! Damping: Rayleigh C = αM + βK and structural damping G as Nastran: K(1 + iG) in the direct
//! solution, G on each modal stiffness ω_j²(1 + iG) in the modal one. The element damping
//! matrices of [`Constrained::damping_ff`] (viscous B, structural K₄ = Σ GE_e K_e) enter the
//! direct solution as iωB + iK₄ and the modal one projected on the modes (ΦᵀBΦ, ΦᵀK₄Φ), which
//! couples the modal equations: one dense complex LU per line
//! ([`coupled_modal_receptance`]). The modal solution also takes a modal damping table
//! ([`ModalDampingTable`], Nastran's TABDMP1 with SDAMPING): ζ_j at each basis vector's
//! frequency, as viscous 2ζ_jω_j or (KDAMP = −1) structural 2ζ_jω_j² damping.

use std::time::Duration;

use faer::Par;
use nalgebra_sparse::{CooMatrix, CscMatrix};

use super::{AnalysisError, timed};
use crate::discretize::Constrained;
use crate::discretize::sensors::project_rows;
use crate::dynamics::frf::{
    ModalDampingTable, SparseModel, congruence, coupled_modal_receptance, direct_receptance,
    modal_receptance, residual_vectors, static_stiffness_is_regular,
};
use crate::linalg::dense::product;
use crate::linalg::{
    EigenProblem, EigenRequest, LanczosOptions, Mat, MatRef, Progress, SymbolicFactor, c64,
    solve_modes,
};

/// How the response is computed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Method {
    /// Factor the dynamic stiffness at every line.
    Direct,
    /// Superpose the modes of `request`, with the residual vectors of the inputs when
    /// `residual_vectors` is set.
    Modal {
        request: EigenRequest,
        residual_vectors: bool,
    },
}

/// Rayleigh (α, β) and structural (G) damping, and the modal damping table of the modal
/// solution.
#[derive(Debug, Clone, PartialEq)]
pub struct Damping {
    pub alpha: f64,
    pub beta: f64,
    pub structural: f64,
    pub modal_table: Option<ModalDampingTable>,
}

/// The receptance H(ω) (outputs × inputs per line) and what the modal solution superposed.
#[derive(Debug, Clone)]
pub struct FullFrf {
    pub h: Vec<Mat<c64>>,
    /// Modes superposed (0 for the direct solution).
    pub modes: usize,
    /// Residual vectors superposed with the modes: `Some(count)` when asked and K is regular
    /// (`Some(0)` when the modes already hold the load shapes), `None` otherwise.
    pub residual_vectors: Option<usize>,
    /// Residual vectors asked, but K is singular (free-free or a mechanism): modes only.
    pub resvec_skipped: bool,
}

/// The output operator of a receptance: first the input DOFs (the rows of the unit-load
/// columns `inputs`, n_f × k: their displacement), then each block of f-set rows in order.
pub fn output_rows(inputs: MatRef<'_, f64>, blocks: &[&CscMatrix<f64>]) -> CscMatrix<f64> {
    let (n_f, k) = (inputs.nrows(), inputs.ncols());
    let rows = k + blocks.iter().map(|b| b.nrows()).sum::<usize>();
    let mut coo = CooMatrix::new(rows, n_f);
    for j in 0..k {
        for f in 0..n_f {
            if inputs[(f, j)] != 0.0 {
                coo.push(j, f, inputs[(f, j)]);
            }
        }
    }
    let mut offset = k;
    for block in blocks {
        for (col, column) in block.col_iter().enumerate() {
            for (&row, &v) in column.row_indices().iter().zip(column.values()) {
                coo.push(offset + row, col, v);
            }
        }
        offset += block.nrows();
    }
    CscMatrix::from(&coo)
}

/// H with only its first `rows` outputs at every line (the rest dropped).
pub fn first_rows(h: Vec<Mat<c64>>, rows: usize) -> Vec<Mat<c64>> {
    if h.iter().all(|hw| hw.nrows() == rows) {
        return h;
    }
    h.iter().map(|hw| hw.subrows(0, rows).to_owned()).collect()
}

/// What a receptance run needs besides the structure and the method.
pub struct FrfRun<'a> {
    /// Unit-load columns of the inputs (n_f × k).
    pub inputs: MatRef<'a, f64>,
    /// Output rows (o × n_f), e.g. from [`output_rows`].
    pub outputs: &'a CscMatrix<f64>,
    /// Circular frequencies of the lines (rad/s).
    pub omegas: &'a [f64],
    pub damping: Damping,
    pub par: Par,
    pub progress: &'a dyn Progress,
}

/// H(ω) of `c` by `method`; each phase ("direct FRF", "Lanczos", "residual vectors",
/// "modal FRF") is reported to `record` with its wall time. The modal method is
/// [`modal_basis`] then [`basis_receptance`] (callers whose frequency lines depend on the
/// modes, as FREQ3–FREQ5, call the two in turn).
pub fn receptance(
    c: &Constrained,
    method: Method,
    run: &FrfRun<'_>,
    record: &mut dyn FnMut(String, Duration),
) -> Result<FullFrf, AnalysisError> {
    let basis = match method {
        Method::Direct => None,
        Method::Modal {
            request,
            residual_vectors,
        } => Some(modal_basis(c, &request, residual_vectors, run, record)?),
    };
    basis_receptance(c, basis.as_ref(), run, record)
}

/// The basis of a modal FRF: the modes of an eigen request (mass normalized) and, on request,
/// the residual vectors of the input shapes, with the symbolic factorization of K_ff.
pub struct ModalBasis {
    symbolic: SymbolicFactor,
    /// Generalized stiffnesses (ω_j² of the modes, then of the residual vectors).
    eigenvalues: Vec<f64>,
    /// The basis vectors as columns (modes first).
    phi: Mat<f64>,
    /// How many of the columns are modes.
    pub modes: usize,
    /// As [`FullFrf::residual_vectors`].
    pub residual_vectors: Option<usize>,
    /// As [`FullFrf::resvec_skipped`].
    pub resvec_skipped: bool,
}

impl ModalBasis {
    /// The natural frequencies (Hz) of the modes (residual vectors left out), ascending.
    pub fn natural_frequencies_hz(&self) -> Vec<f64> {
        self.eigenvalues[..self.modes]
            .iter()
            .map(|&l| l.max(0.0).sqrt() / (2.0 * std::f64::consts::PI))
            .collect()
    }
}

/// The modes of `request` and (when `with_residual`) the residual vectors of `run.inputs`;
/// `run.omegas` is not used.
pub fn modal_basis(
    c: &Constrained,
    request: &EigenRequest,
    with_residual: bool,
    run: &FrfRun<'_>,
    record: &mut dyn FnMut(String, Duration),
) -> Result<ModalBasis, AnalysisError> {
    let symbolic = SymbolicFactor::analyze(c.k_ff.pattern())?;
    let problem = EigenProblem {
        k: &c.k_ff,
        m: &c.m_ff,
        symbolic: &symbolic,
    };
    let r = timed(record, "Lanczos".to_string(), || {
        solve_modes(
            &problem,
            request,
            &LanczosOptions::default(),
            run.par,
            run.progress,
        )
    })?;
    let modes = r.eigenvalues.len();
    let extra = if with_residual {
        timed(record, "residual vectors".to_string(), || {
            residual_vectors(&c.k_ff, &c.m_ff, &symbolic, r.vectors.as_ref(), run.inputs)
        })?
    } else {
        None
    };
    let resvec_skipped = with_residual && extra.is_none();
    let residual = extra.as_ref().map(|e| e.eigenvalues.len());
    // the modes, then the residual vectors (the modes alone when there are none)
    let (eigenvalues, phi) = match extra {
        Some(extra) => {
            let psi = &extra.shapes;
            let n_f = r.vectors.nrows();
            let phi = Mat::<f64>::from_fn(n_f, modes + psi.ncols(), |i, j| {
                if j < modes {
                    r.vectors[(i, j)]
                } else {
                    psi[(i, j - modes)]
                }
            });
            (
                r.eigenvalues.into_iter().chain(extra.eigenvalues).collect(),
                phi,
            )
        }
        None => (r.eigenvalues, r.vectors),
    };
    Ok(ModalBasis {
        symbolic,
        eigenvalues,
        phi,
        modes,
        residual_vectors: residual,
        resvec_skipped,
    })
}

/// H(ω) at `run.omegas`: direct when `basis` is `None`, else superposed on the basis.
pub fn basis_receptance(
    c: &Constrained,
    basis: Option<&ModalBasis>,
    run: &FrfRun<'_>,
    record: &mut dyn FnMut(String, Duration),
) -> Result<FullFrf, AnalysisError> {
    let lines = run.omegas.len();
    let d = &run.damping;
    let Some(b) = basis else {
        let model = SparseModel {
            stiffness: &c.k_ff,
            mass: &c.m_ff,
            alpha: d.alpha,
            beta: d.beta,
            structural: d.structural,
            viscous_matrix: c.damping_ff.viscous.as_ref(),
            structural_matrix: c.damping_ff.structural.as_ref(),
        };
        let h = timed(record, format!("direct FRF ({lines} lines)"), || {
            direct_receptance(
                &model,
                run.inputs,
                run.outputs,
                run.omegas,
                run.par != Par::Seq,
            )
        })?;
        return Ok(FullFrf {
            h,
            modes: 0,
            residual_vectors: None,
            resvec_skipped: false,
        });
    };
    if run.omegas.contains(&0.0) {
        static_stiffness_is_regular(&c.k_ff, &b.symbolic)?;
    }
    let (basis, phi, modes) = (&b.eigenvalues, &b.phi, b.modes);
    let name = format!(
        "modal FRF ({modes} modes, {} residual vectors, {lines} lines)",
        basis.len() - modes
    );
    let h = timed(record, name, || -> Result<_, AnalysisError> {
        let modal_in = product(phi.transpose(), run.inputs);
        let modal_out = project_rows(run.outputs, phi);
        if c.damping_ff.is_empty() && d.modal_table.is_none() {
            return Ok(modal_receptance(
                basis,
                d.alpha,
                d.beta,
                d.structural,
                modal_in.as_ref(),
                modal_out.as_ref(),
                run.omegas,
            )?);
        }
        // element damping couples the modal equations
        let project = |a: Option<&CscMatrix<f64>>| match a {
            Some(a) => congruence(a, phi.as_ref()),
            None => Ok(Mat::zeros(basis.len(), basis.len())),
        };
        let mut viscous = project(c.damping_ff.viscous.as_ref())?;
        let mut structural = project(c.damping_ff.structural.as_ref())?;
        if let Some(table) = &d.modal_table {
            for (j, &lambda) in basis.iter().enumerate() {
                let w = lambda.max(0.0).sqrt();
                let zeta = table.critical_ratio(w / (2.0 * std::f64::consts::PI));
                if table.structural {
                    structural[(j, j)] += 2.0 * zeta * lambda;
                } else {
                    viscous[(j, j)] += 2.0 * zeta * w;
                }
            }
        }
        Ok(coupled_modal_receptance(
            basis,
            (d.alpha, d.beta),
            d.structural,
            viscous.as_ref(),
            structural.as_ref(),
            modal_in.as_ref(),
            modal_out.as_ref(),
            run.omegas,
        )?)
    })?;
    Ok(FullFrf {
        h,
        modes,
        residual_vectors: b.residual_vectors,
        resvec_skipped: b.resvec_skipped,
    })
}
