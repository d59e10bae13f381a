//! Frequency response H(ω) = S_out (K − ω²M + iωC)⁻¹ S_in (thesis eq. 2.24 in the frequency
//! domain), receptance (displacement per force), three ways:
//! - [`receptance`]: dense models (reduced models, pROMs evaluated at a point), one dense
//!   complex LU per frequency;
//! - [`direct_receptance`]: sparse full models with Rayleigh damping C = αM + βK and structural
//!   damping G (Nastran's PARAM,G: the complex stiffness K(1 + iG)), one symbolic analysis of the
//!   pattern ([`ComplexLuSymbolic`]) and one numeric LU per frequency;
//! - [`rayleigh_receptance`]: dense models with Rayleigh damping (pROMs), all their modes
//!   from one dense eigenproblem and then modal superposition — the dense solution at O(n)
//!   per line and output–input pair;
//! - [`modal_receptance`]: modal superposition over mass-normalized modes,
//!   H = Σ_j (S_out φ_j)(φ_jᵀ S_in) / (ω_j²(1 + iG) − ω² + iω(α + βω_j²)) (Rayleigh modal
//!   damping 2ζ_jω_j = α + βω_j², G on the modal stiffness as Nastran's SOL 111); the mode
//!   set can be augmented by [`residual_vectors`] (Nastran's RESVEC on applied loads), which
//!   carry the static part of the modes left out.
//!
//! Frequencies run in parallel (rayon) in every variant.

use faer::linalg::solvers::Solve;
use faer::{Mat, MatRef, Par, c64};
use nalgebra_sparse::CscMatrix;
use rayon::prelude::*;

use super::measurement::Reads;
use crate::deck::cards::ModalDampingUnits;
use crate::linalg::dense::generalized_eigen;
use crate::linalg::{ComplexLuSymbolic, LinalgError, SymbolicFactor, sym_matvec};

/// Why a frequency response cannot be computed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FrfError {
    #[error("{what}: expected {expected}, got {got}")]
    Shape {
        what: &'static str,
        expected: usize,
        got: usize,
    },
    #[error(
        "the dynamic stiffness K − ω²M + iωC is singular at {hz} Hz (an undamped resonance or a rigid-body mode at 0 Hz): add damping or move the frequency line"
    )]
    Singular { hz: f64 },
    #[error(
        "at 0 Hz the dynamic stiffness is K (1 + iG), and K is singular (a free-free structure or a mechanism: no static response exists): start the frequency list above 0 Hz or constrain the model"
    )]
    StaticSingular,
    #[error("K, M and the damping matrices must share one sparsity pattern (nnz {k} and {m})")]
    Pattern { k: usize, m: usize },
    #[error("sparse LU: {0}")]
    Linalg(LinalgError),
    #[error("residual vectors: {0}")]
    Residual(String),
    #[error("modes of the reduced model: {0}")]
    Eigen(crate::linalg::dense::DenseEigenError),
}

/// A sparse model with Rayleigh damping C = αM + βK and structural damping G (stiffness
/// K(1 + iG)), plus the element damping matrices: viscous B (C = αM + βK + B) and structural
/// K₄ = Σ GE_e K_e (stiffness K(1 + iG) + iK₄); all on one pattern.
pub struct SparseModel<'a> {
    pub stiffness: &'a CscMatrix<f64>,
    pub mass: &'a CscMatrix<f64>,
    pub alpha: f64,
    pub beta: f64,
    pub structural: f64,
    pub viscous_matrix: Option<&'a CscMatrix<f64>>,
    pub structural_matrix: Option<&'a CscMatrix<f64>>,
}

/// H(ω_l) (outputs × inputs) of a sparse model by direct solution at every angular frequency:
/// A(ω) = (1 + i(ωβ + G)) K + (iωα − ω²) M + iωB + iK₄ factored by sparse LU on the one symbolic analysis,
/// lines in parallel when `parallel`. `inputs` is n × n_in, `outputs` n_out × n (sparse rows).
pub fn direct_receptance(
    model: &SparseModel<'_>,
    inputs: MatRef<'_, f64>,
    outputs: &CscMatrix<f64>,
    omegas: &[f64],
    parallel: bool,
) -> Result<Vec<Mat<c64>>, FrfError> {
    let (k, m) = (model.stiffness, model.mass);
    let n = k.nrows();
    for (what, got) in [
        ("stiffness columns", k.ncols()),
        ("mass size", m.nrows()),
        ("input shape rows", inputs.nrows()),
        ("output row length", outputs.ncols()),
    ] {
        if got != n {
            return Err(FrfError::Shape {
                what,
                expected: n,
                got,
            });
        }
    }
    let extra = [model.viscous_matrix, model.structural_matrix];
    if let Some(other) = std::iter::once(m)
        .chain(extra.into_iter().flatten())
        .find(|x| x.pattern() != k.pattern())
    {
        return Err(FrfError::Pattern {
            k: k.nnz(),
            m: other.nnz(),
        });
    }
    let (b, k4) = (
        model.viscous_matrix.map(CscMatrix::values),
        model.structural_matrix.map(CscMatrix::values),
    );
    if omegas.contains(&0.0) {
        static_stiffness_is_regular(
            k,
            &SymbolicFactor::analyze(k.pattern()).map_err(FrfError::Linalg)?,
        )?;
    }
    let symbolic = ComplexLuSymbolic::analyze(k.pattern()).map_err(FrfError::Linalg)?;
    let line = |&w: &f64| -> Result<Mat<c64>, FrfError> {
        let (ck, cm) = (
            c64::new(1.0, w * model.beta + model.structural),
            c64::new(-w * w, w * model.alpha),
        );
        let mut values: Vec<c64> = k
            .values()
            .iter()
            .zip(m.values())
            .map(|(&kv, &mv)| ck * kv + cm * mv)
            .collect();
        for (x, scale) in [(b, w), (k4, 1.0)] {
            if let Some(x) = x {
                values
                    .iter_mut()
                    .zip(x)
                    .for_each(|(v, &xv)| v.im += scale * xv);
            }
        }
        let mut x = Mat::<c64>::from_fn(n, inputs.ncols(), |i, j| c64::new(inputs[(i, j)], 0.0));
        symbolic
            .solve_in_place(&values, x.as_mut())
            .map_err(|e| match e {
                LinalgError::Singular { .. } => FrfError::Singular {
                    hz: w / (2.0 * std::f64::consts::PI),
                },
                other => FrfError::Linalg(other),
            })?;
        let mut h = Mat::<c64>::zeros(outputs.nrows(), inputs.ncols());
        for (col, column) in outputs.col_iter().enumerate() {
            for (&row, &v) in column.row_indices().iter().zip(column.values()) {
                for j in 0..inputs.ncols() {
                    h[(row, j)] += x[(col, j)] * v;
                }
            }
        }
        Ok(h)
    };
    if parallel {
        omegas.par_iter().map(line).collect()
    } else {
        omegas.iter().map(line).collect()
    }
}

/// At ω = 0 the dynamic stiffness is (1 + iG) K: a free-free structure or a mechanism makes it
/// singular, but the pivoted complex LU only fails on exactly zero pivots and would return the
/// round-off solution of a numerically singular K (and modal superposition would divide by the
/// round-off λ of the rigid-body modes). Checked on K's LDLᵀ (`symbolic`: the analysis of K's
/// pattern) instead, with the zero pivots of the eigen solver's Sturm counts
/// (|d_k| ≤ 1e-12 |k_kk|, [`crate::linalg::Inertia`]).
pub fn static_stiffness_is_regular(
    k: &CscMatrix<f64>,
    symbolic: &SymbolicFactor,
) -> Result<(), FrfError> {
    match symbolic.factor_ldlt_values(k.values(), Par::Seq) {
        Ok(f) if f.inertia().zero == 0 => Ok(()),
        Ok(_) | Err(LinalgError::Singular { .. }) => Err(FrfError::StaticSingular),
        Err(e) => Err(FrfError::Linalg(e)),
    }
}

/// Residual vectors of the load shapes `loads` (n × k) for the mass-normalized `modes`
/// (n × m), as Nastran's RESVEC on applied loads: the static responses K⁻¹ loads, made
/// M-orthogonal to the modes (twice, classical Gram–Schmidt) and to each other (dropping a
/// shape whose remaining M-norm is below 1e-8 of its static response: the modes already hold
/// it), then diagonalized by Rayleigh–Ritz in their span (K̃ = Rᵀ K R, M̃ = Rᵀ M R). Returns
/// their ω̃² and M-normalized shapes ([`ResidualVectors`]), to be superposed with the modes: the augmented basis
/// holds K⁻¹ loads, so the response to these loads is exact at ω = 0 and the modes left out
/// contribute their static part at every line. `None` when K is singular (a free-free
/// structure or a mechanism: no static response; Nastran would use inertia relief).
pub fn residual_vectors(
    stiffness: &CscMatrix<f64>,
    mass: &CscMatrix<f64>,
    symbolic: &SymbolicFactor,
    modes: MatRef<'_, f64>,
    loads: MatRef<'_, f64>,
) -> Result<Option<ResidualVectors>, FrfError> {
    let n = stiffness.nrows();
    let factor = match symbolic.factor_ldlt_values(stiffness.values(), Par::Seq) {
        Ok(f) if f.inertia().zero == 0 && f.inertia().negative == 0 => f,
        Ok(_) | Err(LinalgError::Singular { .. }) => return Ok(None),
        Err(e) => return Err(FrfError::Linalg(e)),
    };
    let m_norm = |x: &[f64], mx: &mut [f64]| -> Result<f64, FrfError> {
        sym_matvec(mass, x, mx).map_err(FrfError::Linalg)?;
        Ok(x.iter()
            .zip(mx.iter())
            .map(|(a, b)| a * b)
            .sum::<f64>()
            .max(0.0)
            .sqrt())
    };
    let mut kept: Vec<Vec<f64>> = Vec::new();
    let mut mx = vec![0.0; n];
    for j in 0..loads.ncols() {
        let mut x: Vec<f64> = (0..n).map(|i| loads[(i, j)]).collect();
        factor.solve_in_place(&mut x).map_err(FrfError::Linalg)?;
        // mx = M x before each pass; the last m_norm is the norm of what is left
        let static_norm = m_norm(&x, &mut mx)?;
        let mut norm = static_norm;
        for _ in 0..2 {
            for c in 0..modes.ncols() {
                let a: f64 = (0..n).map(|i| modes[(i, c)] * mx[i]).sum();
                (0..n).for_each(|i| x[i] -= a * modes[(i, c)]);
            }
            for r in &kept {
                let a: f64 = r.iter().zip(&mx).map(|(a, b)| a * b).sum();
                x.iter_mut().zip(r).for_each(|(x, r)| *x -= a * r);
            }
            norm = m_norm(&x, &mut mx)?;
        }
        if norm > 1e-8 * static_norm {
            x.iter_mut().for_each(|v| *v /= norm);
            kept.push(x);
        }
    }
    let r = kept.len();
    let basis = Mat::<f64>::from_fn(n, r, |i, c| kept[c][i]);
    let project = |a| congruence(a, basis.as_ref()).map_err(FrfError::Linalg);
    let (k_r, m_r) = (project(stiffness)?, project(mass)?);
    let (lambda, q) = generalized_eigen(k_r.as_ref(), m_r.as_ref())
        .map_err(|e| FrfError::Residual(e.to_string()))?;
    Ok(Some(ResidualVectors {
        eigenvalues: lambda,
        shapes: &basis * &q,
    }))
}

/// Vᵀ A V of a symmetric sparse `a` (full pattern) and a basis `v` (n × r), made exactly
/// symmetric (for the dense eigen solver and the modal matrices).
pub fn congruence(a: &CscMatrix<f64>, v: MatRef<'_, f64>) -> Result<Mat<f64>, LinalgError> {
    let (n, r) = (v.nrows(), v.ncols());
    let mut out = Mat::<f64>::zeros(r, r);
    let (mut x, mut ax) = (vec![0.0; n], vec![0.0; n]);
    for c in 0..r {
        x.iter_mut().enumerate().for_each(|(i, x)| *x = v[(i, c)]);
        sym_matvec(a, &x, &mut ax)?;
        for row in 0..r {
            out[(row, c)] = (0..n).map(|i| v[(i, row)] * ax[i]).sum();
        }
    }
    Ok(Mat::from_fn(r, r, |i, j| 0.5 * (out[(i, j)] + out[(j, i)])))
}

/// Residual vectors ([`residual_vectors`]): Rayleigh–Ritz ω̃² and M-normalized shapes (n × r).
pub struct ResidualVectors {
    pub eigenvalues: Vec<f64>,
    pub shapes: Mat<f64>,
}

/// H(ω_l) by modal superposition (module doc): `eigenvalues` ω_j² of mass-normalized modes,
/// Rayleigh `alpha`, `beta` and structural damping `g`, `modal_inputs` = Φᵀ S_in (m × n_in),
/// `modal_outputs` = S_out Φ (n_out × m).
pub fn modal_receptance(
    eigenvalues: &[f64],
    alpha: f64,
    beta: f64,
    g: f64,
    modal_inputs: MatRef<'_, f64>,
    modal_outputs: MatRef<'_, f64>,
    omegas: &[f64],
) -> Result<Vec<Mat<c64>>, FrfError> {
    let m = eigenvalues.len();
    for (what, got) in [
        ("modal input rows", modal_inputs.nrows()),
        ("modal output columns", modal_outputs.ncols()),
    ] {
        if got != m {
            return Err(FrfError::Shape {
                what,
                expected: m,
                got,
            });
        }
    }
    omegas
        .par_iter()
        .map(|&w| {
            let mut h = Mat::<c64>::zeros(modal_outputs.nrows(), modal_inputs.ncols());
            for (j, &lambda) in eigenvalues.iter().enumerate() {
                let d = c64::new(lambda - w * w, w * (alpha + beta * lambda) + g * lambda);
                if d.norm() == 0.0 {
                    return Err(FrfError::Singular {
                        hz: w / (2.0 * std::f64::consts::PI),
                    });
                }
                let g = c64::new(1.0, 0.0) / d;
                for o in 0..modal_outputs.nrows() {
                    let a = g * modal_outputs[(o, j)];
                    for i in 0..modal_inputs.ncols() {
                        h[(o, i)] += a * modal_inputs[(j, i)];
                    }
                }
            }
            Ok(h)
        })
        .collect()
}

/// H(ω_l) of a dense model with Rayleigh damping C = αM + βK (a pROM at a point, whose C_r is
/// α M_r + β K_r exactly): one dense generalized eigenproblem K φ = λ M φ, then
/// [`modal_receptance`] over all n modes. The modes diagonalize K, M and C, so this is the
/// dense [`receptance`] up to round-off, at O(n · n_out · n_in) per line instead of a dense
/// complex LU (O(n³)).
pub fn rayleigh_receptance(
    stiffness: MatRef<'_, f64>,
    mass: MatRef<'_, f64>,
    (alpha, beta): (f64, f64),
    inputs: MatRef<'_, f64>,
    outputs: MatRef<'_, f64>,
    omegas: &[f64],
) -> Result<Vec<Mat<c64>>, FrfError> {
    let n = stiffness.nrows();
    for (what, got) in [
        ("input shape rows", inputs.nrows()),
        ("output row length", outputs.ncols()),
    ] {
        if got != n {
            return Err(FrfError::Shape {
                what,
                expected: n,
                got,
            });
        }
    }
    let (lambda, phi) = generalized_eigen(stiffness, mass).map_err(FrfError::Eigen)?;
    let modal_inputs = phi.transpose() * inputs;
    let modal_outputs = outputs * &phi;
    modal_receptance(
        &lambda,
        alpha,
        beta,
        0.0,
        modal_inputs.as_ref(),
        modal_outputs.as_ref(),
        omegas,
    )
}

/// H(ω_l) by coupled modal equations, for element damping that the modes do not diagonalize:
/// (Λ(1 + iG) + iΦᵀK₄Φ − ω² I + iω(αI + βΛ + ΦᵀBΦ)) q = Φᵀ S_in, one dense complex LU per
/// line. `eigenvalues` Λ of mass-normalized modes, `viscous` ΦᵀBΦ and `structural` ΦᵀK₄Φ
/// (m × m), `modal_inputs` Φᵀ S_in, `modal_outputs` S_out Φ.
#[allow(clippy::too_many_arguments)]
pub fn coupled_modal_receptance(
    eigenvalues: &[f64],
    rayleigh: (f64, f64),
    g: f64,
    viscous: MatRef<'_, f64>,
    structural: MatRef<'_, f64>,
    modal_inputs: MatRef<'_, f64>,
    modal_outputs: MatRef<'_, f64>,
    omegas: &[f64],
) -> Result<Vec<Mat<c64>>, FrfError> {
    let m = eigenvalues.len();
    let (alpha, beta) = rayleigh;
    let diagonal = |i: usize, j: usize, d: f64| if i == j { d } else { 0.0 };
    let stiffness = Mat::<f64>::from_fn(m, m, |i, j| diagonal(i, j, eigenvalues[i]));
    let mass = Mat::<f64>::from_fn(m, m, |i, j| diagonal(i, j, 1.0));
    let damping = Mat::<f64>::from_fn(m, m, |i, j| {
        viscous[(i, j)] + diagonal(i, j, alpha + beta * eigenvalues[i])
    });
    let imaginary = Mat::<f64>::from_fn(m, m, |i, j| {
        structural[(i, j)] + diagonal(i, j, g * eigenvalues[i])
    });
    let model = DenseModel {
        stiffness: stiffness.as_ref(),
        mass: mass.as_ref(),
        damping: damping.as_ref(),
        structural: Some(imaginary.as_ref()),
    };
    receptance(&model, modal_inputs, modal_outputs, omegas)
}

/// Modal damping as a function of the natural frequency (Nastran's TABDMP1 selected by
/// SDAMPING): linear between the points, linear extrapolation from the two end points, the
/// values converted to ζ after the look-up.
#[derive(Debug, Clone, PartialEq)]
pub struct ModalDampingTable {
    /// (f Hz, value) by increasing f.
    points: Vec<(f64, f64)>,
    units: ModalDampingUnits,
    /// Structural damping ω_j²·2iζ_j (Nastran's PARAM,KDAMP,-1) instead of viscous 2ζ_jω_j.
    pub structural: bool,
}

impl ModalDampingTable {
    /// The table of `points` (increasing or decreasing f) in `units`.
    pub fn new(points: &[(f64, f64)], units: ModalDampingUnits, structural: bool) -> Self {
        let mut points = points.to_vec();
        if points.first().map(|p| p.0) > points.last().map(|p| p.0) {
            points.reverse();
        }
        ModalDampingTable {
            points,
            units,
            structural,
        }
    }

    /// ζ at the natural frequency `hz`.
    pub fn critical_ratio(&self, hz: f64) -> f64 {
        let p = &self.points;
        let n = p.len();
        let line = |a: (f64, f64), b: (f64, f64)| {
            if b.0 == a.0 {
                a.1
            } else {
                a.1 + (b.1 - a.1) * (hz - a.0) / (b.0 - a.0)
            }
        };
        let value = if n < 2 {
            p.first().map_or(0.0, |q| q.1)
        } else if hz <= p[0].0 {
            line(p[0], p[1])
        } else if hz >= p[n - 1].0 {
            line(p[n - 1], p[n - 2])
        } else {
            crate::dynamics::table::Table::new(p).map_or(0.0, |t| t.value(hz))
        };
        self.units.critical_ratio(value)
    }
}

/// The dense model of one frequency-response evaluation.
pub struct DenseModel<'a> {
    pub stiffness: MatRef<'a, f64>,
    pub mass: MatRef<'a, f64>,
    pub damping: MatRef<'a, f64>,
    /// The imaginary part of the stiffness (structural damping), if any: K + iK₄.
    pub structural: Option<MatRef<'a, f64>>,
}

/// H(ω_l) (outputs × inputs) at every angular frequency in `omegas` (rad/s).
/// `inputs` is n × n_in (load shapes), `outputs` n_out × n (output rows).
pub fn receptance(
    model: &DenseModel<'_>,
    inputs: MatRef<'_, f64>,
    outputs: MatRef<'_, f64>,
    omegas: &[f64],
) -> Result<Vec<Mat<c64>>, FrfError> {
    let n = model.stiffness.nrows();
    if let Some(k4) = model.structural
        && (k4.nrows(), k4.ncols()) != (n, n)
    {
        return Err(FrfError::Shape {
            what: "structural damping size",
            expected: n,
            got: k4.nrows(),
        });
    }
    for (what, got) in [
        ("stiffness columns", model.stiffness.ncols()),
        ("mass size", model.mass.nrows()),
        ("mass columns", model.mass.ncols()),
        ("damping size", model.damping.nrows()),
        ("damping columns", model.damping.ncols()),
        ("input shape rows", inputs.nrows()),
        ("output row length", outputs.ncols()),
    ] {
        if got != n {
            return Err(FrfError::Shape {
                what,
                expected: n,
                got,
            });
        }
    }
    let rhs = Mat::<c64>::from_fn(n, inputs.ncols(), |i, j| c64::new(inputs[(i, j)], 0.0));
    let out = Mat::<c64>::from_fn(outputs.nrows(), n, |i, j| c64::new(outputs[(i, j)], 0.0));
    omegas
        .par_iter()
        .map(|&w| {
            let a = Mat::<c64>::from_fn(n, n, |i, j| {
                c64::new(
                    model.stiffness[(i, j)] - w * w * model.mass[(i, j)],
                    w * model.damping[(i, j)] + model.structural.map_or(0.0, |k4| k4[(i, j)]),
                )
            });
            let x = a.partial_piv_lu().solve(&rhs);
            if (0..x.ncols()).any(|j| {
                x.col(j)
                    .iter()
                    .any(|z| !(z.re.is_finite() && z.im.is_finite()))
            }) {
                return Err(FrfError::Singular {
                    hz: w / (2.0 * std::f64::consts::PI),
                });
            }
            Ok(&out * &x)
        })
        .collect()
}

/// Scales H by each output row's (iω)^k ([`Reads::frequency_factor`]: the input DOFs, DISP and
/// STRAIN read displacement, VEL iω, ACCEL −ω²) and flattens it line-major (f × o × i); also
/// returns the largest |H| and its frequency.
pub fn scaled_flat(h: &[Mat<c64>], hz: &[f64], reads: &[Reads]) -> (Vec<c64>, (f64, f64)) {
    let mut flat = Vec::with_capacity(h.iter().map(|m| m.nrows() * m.ncols()).sum());
    let mut peak = (0.0_f64, 0.0);
    for (hw, f) in h.iter().zip(hz) {
        let w = 2.0 * std::f64::consts::PI * f;
        for (o, row) in reads.iter().enumerate() {
            let factor = row.frequency_factor(w);
            for i in 0..hw.ncols() {
                let z = hw[(o, i)] * factor;
                if z.norm() > peak.0 {
                    peak = (z.norm(), *f);
                }
                flat.push(z);
            }
        }
    }
    (flat, peak)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// SDOF: H = 1/(k − ω²m + iωc) exactly (one complex division; bound 1e-14 relative).
    #[test]
    fn single_dof_matches_the_closed_form() {
        let (k, m, c) = (4.0e4, 2.0, 8.0);
        let one = |v: f64| Mat::<f64>::from_fn(1, 1, |_, _| v);
        let (km, mm, cm, unit) = (one(k), one(m), one(c), one(1.0));
        let model = DenseModel {
            stiffness: km.as_ref(),
            mass: mm.as_ref(),
            damping: cm.as_ref(),
            structural: None,
        };
        let omegas = [0.0, 50.0, (k / m).sqrt(), 400.0];
        let h = receptance(&model, unit.as_ref(), unit.as_ref(), &omegas).unwrap();
        for (w, hw) in omegas.iter().zip(&h) {
            let exact = c64::new(1.0, 0.0) / c64::new(k - w * w * m, w * c);
            assert!(
                (hw[(0, 0)] - exact).norm() <= 1e-14 * exact.norm(),
                "ω = {w}"
            );
        }
    }

    #[test]
    fn undamped_resonance_is_reported() {
        let one = |v: f64| Mat::<f64>::from_fn(1, 1, |_, _| v);
        let (km, mm, cm, unit) = (one(1.0), one(1.0), one(0.0), one(1.0));
        let model = DenseModel {
            stiffness: km.as_ref(),
            mass: mm.as_ref(),
            damping: cm.as_ref(),
            structural: None,
        };
        match receptance(&model, unit.as_ref(), unit.as_ref(), &[1.0]) {
            Err(FrfError::Singular { hz }) => {
                assert!((hz - 1.0 / (2.0 * std::f64::consts::PI)).abs() < 1e-15)
            }
            other => panic!("{other:?}"),
        }
    }

    /// A 3-DOF spring chain with Rayleigh damping: the sparse direct solution, the modal
    /// superposition over all three modes (given, and from the dense model's own eigenproblem)
    /// against the dense receptance; all are exact,
    /// bound 1e-12 relative to max |H| (a handful of 3 × 3 complex solves and an eigen solve).
    #[test]
    fn direct_and_modal_agree_with_the_dense_receptance() {
        let kd = [
            [3.0e4, -1.0e4, 0.0],
            [-1.0e4, 2.5e4, -1.5e4],
            [0.0, -1.5e4, 1.5e4],
        ];
        let md = [[2.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.5]];
        let (alpha, beta) = (0.8, 3.0e-4);
        let sparse = |a: &[[f64; 3]; 3]| {
            let mut coo = nalgebra_sparse::CooMatrix::new(3, 3);
            for i in 0..3 {
                for j in 0..3 {
                    if kd[i][j] != 0.0 || i == j {
                        coo.push(i, j, a[i][j]);
                    }
                }
            }
            CscMatrix::from(&coo)
        };
        let (ks, ms) = (sparse(&kd), sparse(&md));
        let dense = |a: &[[f64; 3]; 3]| Mat::<f64>::from_fn(3, 3, |i, j| a[i][j]);
        let (km, mm) = (dense(&kd), dense(&md));
        let cm = Mat::<f64>::from_fn(3, 3, |i, j| alpha * md[i][j] + beta * kd[i][j]);
        let inputs = Mat::<f64>::from_fn(3, 2, |i, j| if i == 2 * j { 1.0 } else { 0.0 });
        let outputs = Mat::<f64>::from_fn(2, 3, |i, j| if j == 1 + i { 1.0 } else { 0.0 });
        let omegas = [0.0, 60.0, 150.0, 300.0];
        let want = receptance(
            &DenseModel {
                stiffness: km.as_ref(),
                mass: mm.as_ref(),
                damping: cm.as_ref(),
                structural: None,
            },
            inputs.as_ref(),
            outputs.as_ref(),
            &omegas,
        )
        .unwrap();
        let mut coo = nalgebra_sparse::CooMatrix::new(2, 3);
        coo.push(0, 1, 1.0);
        coo.push(1, 2, 1.0);
        let out_sparse = CscMatrix::from(&coo);
        let direct = direct_receptance(
            &SparseModel {
                stiffness: &ks,
                mass: &ms,
                alpha,
                beta,
                structural: 0.0,
                viscous_matrix: None,
                structural_matrix: None,
            },
            inputs.as_ref(),
            &out_sparse,
            &omegas,
            true,
        )
        .unwrap();
        let (lambda, phi) =
            crate::linalg::dense::generalized_eigen(km.as_ref(), mm.as_ref()).unwrap();
        let modal = modal_receptance(
            &lambda,
            alpha,
            beta,
            0.0,
            (phi.transpose() * &inputs).as_ref(),
            (&outputs * &phi).as_ref(),
            &omegas,
        )
        .unwrap();
        let rayleigh = rayleigh_receptance(
            km.as_ref(),
            mm.as_ref(),
            (alpha, beta),
            inputs.as_ref(),
            outputs.as_ref(),
            &omegas,
        )
        .unwrap();
        let scale = want
            .iter()
            .flat_map(|h| (0..2).flat_map(move |o| (0..2).map(move |i| h[(o, i)].norm())))
            .fold(0.0, f64::max);
        for l in 0..omegas.len() {
            for o in 0..2 {
                for i in 0..2 {
                    assert!(
                        (rayleigh[l][(o, i)] - want[l][(o, i)]).norm() <= 1e-12 * scale,
                        "Rayleigh modal, line {l}"
                    );
                    assert!(
                        (direct[l][(o, i)] - want[l][(o, i)]).norm() <= 1e-12 * scale,
                        "direct, line {l}"
                    );
                    assert!(
                        (modal[l][(o, i)] - want[l][(o, i)]).norm() <= 1e-12 * scale,
                        "modal, line {l}"
                    );
                }
            }
        }
    }

    /// A free–free 3-DOF chain (springs ≈ 1e10 between masses of 1e-3: K singular, its rigid
    /// pivot round-off) at 0 Hz is refused as a static singularity, also with structural
    /// damping G (which multiplies K at 0 Hz), while the lines above 0 Hz solve; grounded, 0 Hz
    /// solves.
    #[test]
    fn free_free_static_line_is_refused() {
        let chain = |ground: f64| {
            // spring rates whose eliminations do not cancel exactly: the last pivot is round-off
            let (a, b) = (1e10 / 3.0, 1.1e10 / 7.0);
            let k = [[a + ground, -a, 0.0], [-a, a + b, -b], [0.0, -b, b]];
            let mut coo = nalgebra_sparse::CooMatrix::new(3, 3);
            let mut mass = nalgebra_sparse::CooMatrix::new(3, 3);
            for (i, row) in k.iter().enumerate() {
                for (j, &kij) in row.iter().enumerate() {
                    if i.abs_diff(j) <= 1 {
                        coo.push(i, j, kij);
                        mass.push(i, j, if i == j { 1e-3 } else { 0.0 });
                    }
                }
            }
            (CscMatrix::from(&coo), CscMatrix::from(&mass))
        };
        let inputs = Mat::<f64>::from_fn(3, 1, |i, _| if i == 2 { 1.0 } else { 0.0 });
        let mut coo = nalgebra_sparse::CooMatrix::new(1, 3);
        coo.push(0, 2, 1.0);
        let outputs = CscMatrix::from(&coo);
        let (k, m) = chain(0.0);
        for structural in [0.0, 0.02] {
            let model = SparseModel {
                stiffness: &k,
                mass: &m,
                alpha: 0.0,
                beta: 0.0,
                structural,
                viscous_matrix: None,
                structural_matrix: None,
            };
            assert_eq!(
                direct_receptance(&model, inputs.as_ref(), &outputs, &[0.0, 100.0], false)
                    .unwrap_err(),
                FrfError::StaticSingular
            );
            assert!(
                direct_receptance(&model, inputs.as_ref(), &outputs, &[100.0, 1e4], false).is_ok()
            );
        }
        let (k, m) = chain(1e10);
        let model = SparseModel {
            stiffness: &k,
            mass: &m,
            alpha: 0.0,
            beta: 0.0,
            structural: 0.0,
            viscous_matrix: None,
            structural_matrix: None,
        };
        assert!(direct_receptance(&model, inputs.as_ref(), &outputs, &[0.0], false).is_ok());
    }
}
