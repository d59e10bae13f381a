//! The local basis Ψ_i = [Ψ_nm,i Ψ_sm,i] of one parameter sample (thesis §2.3.2, eq. 2.28;
//! §3.4.1 "Local bases and matrices generation"; DESIGN.md §7 step 2).
//!
//! - Normal modes: the shift-invert Lanczos of [`crate::linalg::eigen`] (NMODES modes, or those
//!   below FMAX), sharing the caller's symbolic factorization.
//! - Static modes, `STATIC = ATTACH`: attachment (unit-load) modes K ψ_b = e_b for every boundary
//!   DOF b. When the structure is free (rigid-body modes Φ_r at ≈ 0 Hz) K is singular and the
//!   modes are the inertia-relief ones: the load is made self-equilibrated, f̃ = e_b − M Φ_r Φ_rᵀ e_b,
//!   and ψ_b is the solution of K ψ = f̃ that is M-orthogonal to Φ_r. It is computed with the
//!   regular K − σM (σ = −λ₁/100 < 0) by the fixed-point iteration
//!   ψ ← (K − σM)⁻¹ (f̃ − σ M ψ), projected on the elastic subspace, which converges with the
//!   ratio |σ|/(λ₁ − σ) per step (λ₁ the first elastic eigenvalue).
//! - `RIGID = REMOVE` drops the rigid-body modes from the basis (floating-frame bodies: the
//!   multibody frame carries the rigid motion); `KEEP` keeps them.
//!
//! Rigid-body modes are recognised as λ ≤ [`RIGID_REL`] · λ_max of the modes computed.

use faer::{Mat, Par};
use nalgebra_sparse::CscMatrix;

use crate::linalg::{EigenProblem, EigenRequest, LanczosOptions, LinalgError, Progress, solve_modes, sym_matvec};

/// λ below this fraction of the largest computed eigenvalue counts as a rigid-body mode. The
/// eigen solver returns rigid-body λ at round-off (≈ 1e-12 of ‖K‖/‖M‖ or less); an elastic
/// mode 1e4 times below the highest requested one in frequency (1e-8 in λ) does not occur in a
/// local basis of a few tens of modes.
pub const RIGID_REL: f64 = 1e-8;

/// The inertia-relief shift σ = −RELIEF_SHIFT·λ₁ (λ₁ the first elastic eigenvalue): the
/// iteration then contracts by |σ|/(λ₁ − σ) ≈ 0.01 per step (≈ 7 steps to 1e-13), while
/// K − σM stays as well conditioned on the elastic subspace as K itself.
const RELIEF_SHIFT: f64 = 0.01;

/// Relative change of the inertia-relief iteration at which it stops (‖Δψ‖ ≤ tol·‖ψ‖).
const RELIEF_TOL: f64 = 1e-13;
const RELIEF_MAX_ITERATIONS: usize = 60;

/// Which static modes to add (PMOR STATIC).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StaticModes {
    /// Unit-load (attachment) modes at the boundary DOFs.
    Attach,
    /// No static modes.
    None,
}

/// Rigid-body modes in the basis (PMOR RIGID).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RigidModes {
    Keep,
    Remove,
}

/// What one local basis holds.
#[derive(Debug, Clone)]
pub struct LocalBasisRequest {
    /// Elastic normal modes wanted (NMODES).
    pub n_modes: usize,
    /// Upper frequency of the band (FMAX, Hz): modes above it are not wanted even if fewer
    /// than `n_modes`.
    pub fmax_hz: Option<f64>,
    /// Boundary DOFs (f-set indices) for static modes.
    pub boundary: Vec<usize>,
    pub statics: StaticModes,
    pub rigid: RigidModes,
}

/// Ψ_i with what it is made of.
#[derive(Debug, Clone)]
pub struct LocalBasis {
    /// n × (rigid kept + elastic + static) columns, in that order.
    pub vectors: Mat<f64>,
    /// Frequencies (Hz) of the normal-mode columns (rigid kept, then elastic).
    pub frequencies_hz: Vec<f64>,
    /// Rigid-body modes found (whether kept or not).
    pub n_rigid: usize,
    /// Static-mode columns (last).
    pub n_static: usize,
}

/// Errors of a local basis.
#[derive(Debug, thiserror::Error)]
pub enum LocalBasisError {
    #[error(transparent)]
    Linalg(#[from] LinalgError),
    #[error("boundary DOF index {index} is outside the f-set of size {size}")]
    BoundaryOutOfRange { index: usize, size: usize },
    #[error("the inertia-relief static mode of boundary DOF {dof} did not converge (relative change {change:.1e} after {RELIEF_MAX_ITERATIONS} iterations): the first elastic mode is too close to the shift")]
    ReliefNotConverged { dof: usize, change: f64 },
}

/// Build the local basis of the pencil (K, M).
pub fn local_basis(problem: &EigenProblem<'_>, request: &LocalBasisRequest, par: Par, progress: &dyn Progress) -> Result<LocalBasis, LocalBasisError> {
    let n = problem.k.nrows();
    if let Some(&index) = request.boundary.iter().find(|&&b| b >= n) {
        return Err(LocalBasisError::BoundaryOutOfRange { index, size: n });
    }
    // Ask for 6 more than wanted so the rigid-body modes of a free body do not eat the elastic
    // ones (a free 3-D body has at most 6; mechanisms are refused upstream).
    let wanted = request.n_modes + 6;
    let eigen = solve_modes(problem, &EigenRequest { v1_hz: None, v2_hz: request.fmax_hz, nd: Some(wanted.min(n)), shift_hz: None }, &LanczosOptions::default(), par, progress)?;
    let lambda_max = eigen.eigenvalues.iter().copied().fold(0.0, f64::max);
    let is_rigid: Vec<bool> = eigen.eigenvalues.iter().map(|&l| l <= RIGID_REL * lambda_max).collect();
    let rigid_cols: Vec<usize> = (0..is_rigid.len()).filter(|&j| is_rigid[j]).collect();
    let elastic_cols: Vec<usize> = (0..is_rigid.len()).filter(|&j| !is_rigid[j]).take(request.n_modes).collect();
    let kept_normal: Vec<usize> = match request.rigid {
        RigidModes::Keep => rigid_cols.iter().chain(&elastic_cols).copied().collect(),
        RigidModes::Remove => elastic_cols.clone(),
    };
    let statics = match request.statics {
        StaticModes::None => Mat::zeros(n, 0),
        StaticModes::Attach => {
            let lambda_1 = elastic_cols.first().map(|&j| eigen.eigenvalues[j]).unwrap_or(lambda_max);
            attachment_modes(problem, &eigen.vectors, &rigid_cols, -RELIEF_SHIFT * lambda_1, &request.boundary, par)?
        }
    };
    let n_static = statics.ncols();
    let vectors = Mat::from_fn(n, kept_normal.len() + n_static, |i, c| if c < kept_normal.len() { eigen.vectors[(i, kept_normal[c])] } else { statics[(i, c - kept_normal.len())] });
    Ok(LocalBasis { vectors, frequencies_hz: kept_normal.iter().map(|&j| eigen.frequencies_hz[j]).collect(), n_rigid: rigid_cols.len(), n_static })
}

/// Attachment modes (module doc): plain K ψ = e_b for a supported structure, inertia relief for
/// a free one.
fn attachment_modes(problem: &EigenProblem<'_>, modes: &Mat<f64>, rigid: &[usize], relief_shift: f64, boundary: &[usize], par: Par) -> Result<Mat<f64>, LocalBasisError> {
    let n = problem.k.nrows();
    let mut out = Mat::<f64>::zeros(n, boundary.len());
    if boundary.is_empty() {
        return Ok(out);
    }
    let free = !rigid.is_empty();
    let sigma = if free { relief_shift.min(0.0) } else { 0.0 };
    let shifted = shifted(problem, sigma);
    let factor = if sigma == 0.0 { problem.symbolic.factor_llt(problem.k, par) } else { problem.symbolic.factor_ldlt(&shifted, par) }?;
    let mut scratch = factor.solve_scratch(1)?;
    let mut m_x = vec![0.0; n];
    // M-orthogonal projection on the elastic subspace: x ← x − Φ_r Φ_rᵀ M x.
    let project = |x: &mut [f64], m_x: &mut [f64]| -> Result<(), LinalgError> {
        sym_matvec(problem.m, x, m_x)?;
        for &r in rigid {
            let phi = modes.col_as_slice(r);
            let c: f64 = phi.iter().zip(m_x.iter()).map(|(p, q)| p * q).sum();
            x.iter_mut().zip(phi).for_each(|(xi, p)| *xi -= c * p);
        }
        Ok(())
    };
    for (col, &b) in boundary.iter().enumerate() {
        // self-equilibrated load f̃ = e_b − M Φ_r Φ_rᵀ e_b
        let mut load = vec![0.0; n];
        load[b] = 1.0;
        if free {
            let mut m_phi = vec![0.0; n];
            for &r in rigid {
                let phi = modes.col_as_slice(r);
                sym_matvec(problem.m, phi, &mut m_phi)?;
                let c = phi[b];
                load.iter_mut().zip(&m_phi).for_each(|(l, mp)| *l -= c * mp);
            }
        }
        let mut x = load.clone();
        factor.solve_in_place_with_scratch(faer::MatMut::from_column_major_slice_mut(&mut x, n, 1), &mut scratch)?;
        if free {
            project(&mut x, &mut m_x)?;
            let mut change = f64::INFINITY;
            let mut iterations = 0;
            while change > RELIEF_TOL {
                if iterations == RELIEF_MAX_ITERATIONS {
                    return Err(LocalBasisError::ReliefNotConverged { dof: b, change });
                }
                sym_matvec(problem.m, &x, &mut m_x)?;
                let mut next: Vec<f64> = load.iter().zip(&m_x).map(|(l, mx)| l - sigma * mx).collect();
                factor.solve_in_place_with_scratch(faer::MatMut::from_column_major_slice_mut(&mut next, n, 1), &mut scratch)?;
                project(&mut next, &mut m_x)?;
                let norm = next.iter().map(|v| v * v).sum::<f64>().sqrt();
                change = next.iter().zip(&x).map(|(a, b)| (a - b).powi(2)).sum::<f64>().sqrt() / norm.max(f64::MIN_POSITIVE);
                x = next;
                iterations += 1;
            }
        }
        out.col_as_slice_mut(col).copy_from_slice(&x);
    }
    Ok(out)
}

/// K − σM on K's pattern (M shares it).
fn shifted(problem: &EigenProblem<'_>, sigma: f64) -> CscMatrix<f64> {
    let mut a = problem.k.clone();
    if sigma != 0.0 {
        a.values_mut().iter_mut().zip(problem.m.values()).for_each(|(k, m)| *k -= sigma * m);
    }
    a
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::SymbolicFactor;
    use nalgebra_sparse::CooMatrix;

    /// Spring chain of n unit masses and unit springs; `grounded` adds a spring to ground at
    /// the first mass. Full pattern, M on K's pattern.
    fn chain(n: usize, grounded: bool) -> (CscMatrix<f64>, CscMatrix<f64>) {
        let (mut k, mut m) = (CooMatrix::new(n, n), CooMatrix::new(n, n));
        for i in 0..n - 1 {
            for (a, b, v) in [(i, i, 1.0), (i + 1, i + 1, 1.0), (i, i + 1, -1.0), (i + 1, i, -1.0)] {
                k.push(a, b, v);
                m.push(a, b, 0.0);
            }
        }
        for i in 0..n {
            m.push(i, i, 1.0);
        }
        if grounded {
            k.push(0, 0, 1.0);
        }
        (CscMatrix::from(&k), CscMatrix::from(&m))
    }

    fn quiet() -> impl Progress {
        |_: &str, _: usize, _: usize| {}
    }

    fn basis(k: &CscMatrix<f64>, m: &CscMatrix<f64>, rigid: RigidModes, boundary: Vec<usize>) -> LocalBasis {
        let symbolic = SymbolicFactor::analyze(k.pattern()).unwrap();
        let problem = EigenProblem { k, m, symbolic: &symbolic };
        let request = LocalBasisRequest { n_modes: 3, fmax_hz: None, boundary, statics: StaticModes::Attach, rigid };
        local_basis(&problem, &request, Par::Seq, &quiet()).unwrap()
    }

    fn apply(a: &CscMatrix<f64>, x: &[f64]) -> Vec<f64> {
        let mut y = vec![0.0; x.len()];
        sym_matvec(a, x, &mut y).unwrap();
        y
    }

    /// Grounded chain: attachment modes solve K ψ = e_b to round-off (bound 1e-12 relative to
    /// the load; the chain's condition number is ~4n² = 1.6e3).
    #[test]
    fn supported_attachment_modes_solve_k() {
        let (k, m) = chain(20, true);
        let b = basis(&k, &m, RigidModes::Keep, vec![19, 7]);
        assert_eq!((b.n_rigid, b.n_static, b.vectors.ncols()), (0, 2, 5));
        for (c, &dof) in [19usize, 7].iter().enumerate() {
            let r = apply(&k, b.vectors.col_as_slice(3 + c));
            for (i, v) in r.iter().enumerate() {
                let want = if i == dof { 1.0 } else { 0.0 };
                assert!((v - want).abs() < 1e-12, "dof {dof}, row {i}: {v}");
            }
        }
    }

    /// Free chain: one rigid mode, removed on request; the static mode satisfies the
    /// inertia-relief equations K ψ = e_b − M φ_r φ_rᵀ e_b and φ_rᵀ M ψ = 0 (bounds as above).
    #[test]
    fn free_attachment_modes_are_inertia_relief() {
        let (k, m) = chain(20, false);
        let b = basis(&k, &m, RigidModes::Remove, vec![19]);
        assert_eq!((b.n_rigid, b.n_static, b.vectors.ncols()), (1, 1, 4));
        assert!(b.frequencies_hz.iter().all(|&f| f > 1e-3), "{:?}", b.frequencies_hz);
        let psi = b.vectors.col_as_slice(3);
        let phi_r = 1.0 / (20f64).sqrt(); // M-normalized rigid mode of unit masses
        let r = apply(&k, psi);
        for (i, v) in r.iter().enumerate() {
            let want = if i == 19 { 1.0 } else { 0.0 } - phi_r * phi_r;
            assert!((v - want).abs() < 1e-11, "row {i}: {v} vs {want}");
        }
        // relative to ‖Mψ‖·‖φ_r‖ (ψ grows like n² on a free chain); the projection uses the
        // Lanczos rigid mode, accurate to the solver's Ritz tolerance 1e-10, not the exact one
        let m_psi = apply(&m, psi);
        let mass_weighted: f64 = m_psi.iter().map(|x| x * phi_r).sum();
        let scale = m_psi.iter().map(|x| x * x).sum::<f64>().sqrt();
        assert!(mass_weighted.abs() < 1e-10 * scale, "{mass_weighted} vs scale {scale}");
    }

    #[test]
    fn boundary_outside_the_f_set_is_an_error() {
        let (k, m) = chain(5, true);
        let symbolic = SymbolicFactor::analyze(k.pattern()).unwrap();
        let problem = EigenProblem { k: &k, m: &m, symbolic: &symbolic };
        let request = LocalBasisRequest { n_modes: 1, fmax_hz: None, boundary: vec![5], statics: StaticModes::Attach, rigid: RigidModes::Keep };
        assert!(matches!(local_basis(&problem, &request, Par::Seq, &quiet()), Err(LocalBasisError::BoundaryOutOfRange { index: 5, size: 5 })));
    }
}
