//! Dense symmetric generalized eigenproblems K φ = λ M φ of reduced models (faer).
//!
//! M = L Lᵀ (Cholesky), A = L⁻¹ K L⁻ᵀ (two triangular solves), A = Y Λ Yᵀ, φ = L⁻ᵀ y: the
//! vectors come out M-orthonormal. Before that, the conditioning of M is measured through its
//! own eigenvalues: a reduced mass matrix with μ_min/μ_max below [`MASS_CONDITION_LIMIT`] means
//! the reduction basis is (numerically) dependent or carries massless directions, and the
//! eigenvalues would be noise; that is reported instead of solved.
//!
//! Everything here runs on the calling thread (`Par::Seq`, never faer's global setting, which is
//! a thread pool over all cores): reduced models are small, and waking the pool costs more than
//! it brings. Measured on the estimation filter's re-diagonalization of the n = 36 blade pROM
//! (two eigenproblems and a dozen products): 1.4–3.2 ms of wall time each through the pool on the
//! 2-core machine, 0.5 ms on the calling thread.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::{cholesky_in_place, cholesky_in_place_scratch};
use faer::linalg::evd::{
    ComputeEigenvectors, SelfAdjointEvdParams, self_adjoint_evd, self_adjoint_evd_scratch,
};
use faer::linalg::matmul::matmul;
use faer::linalg::triangular_solve::solve_lower_triangular_in_place;
use faer::{Accum, Mat, MatRef, Par};

/// Smallest accepted μ_min/μ_max of a reduced mass matrix. At 1e-12 the Cholesky factor still
/// exists, but eigenvalue errors reach ε/1e-12 ≈ 1e-4 relative — the limit of usefulness.
pub const MASS_CONDITION_LIMIT: f64 = 1e-12;

/// Errors of the dense generalized eigenproblem.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum DenseEigenError {
    #[error("K and M must be square and of equal size ({k}×{k} vs {m}×{m})")]
    Shape { k: usize, m: usize },
    #[error(
        "the reduced mass matrix is ill-conditioned (smallest/largest eigenvalue {ratio:.1e} < {MASS_CONDITION_LIMIT:e}): the reduction basis has (nearly) dependent or massless directions"
    )]
    IllConditionedMass { ratio: f64 },
    #[error("the eigen decomposition failed to converge")]
    NoConvergence,
    #[error(
        "the stiffness matrix is indefinite (eigenvalue {smallest:e} against {largest:e}): parameter values outside the physical range (e.g. a modulus ≤ 0)"
    )]
    IndefiniteStiffness { smallest: f64, largest: f64 },
}

/// Relative size −κ_min/κ_max of the most negative eigenvalue up to which a reduced stiffness
/// counts as positive semi-definite (rigid-body modes of a free model are zero up to
/// round-off, ~1e-12 relative).
pub const STIFFNESS_ROUNDOFF: f64 = 1e-8;

/// A symmetric reduced stiffness is positive semi-definite up to [`STIFFNESS_ROUNDOFF`], or
/// [`DenseEigenError::IndefiniteStiffness`]. Every consumer of a pROM evaluated at given
/// parameters checks this beside [`mass_conditioning`]: at small time steps the effective
/// matrices M + Δt C + Δt² K stay definite for an indefinite K, so a negative modulus would run.
pub fn stiffness_semidefinite(k: MatRef<'_, f64>) -> Result<(), DenseEigenError> {
    let (kappa, _) = symmetric_eigen(k, ComputeEigenvectors::No)?;
    let (smallest, largest) = kappa
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &v| {
            (lo.min(v), hi.max(v))
        });
    if smallest < -STIFFNESS_ROUNDOFF * largest.abs() || largest <= 0.0 {
        return Err(DenseEigenError::IndefiniteStiffness { smallest, largest });
    }
    Ok(())
}

/// μ_min/μ_max of a symmetric reduced mass matrix, or [`DenseEigenError::IllConditionedMass`]
/// below [`MASS_CONDITION_LIMIT`] (see the module documentation). Every consumer of a reduced
/// model checks its mass with this before solving with it (eigenproblems, time integration).
pub fn mass_conditioning(m: MatRef<'_, f64>) -> Result<f64, DenseEigenError> {
    let (mu, _) = symmetric_eigen(m, ComputeEigenvectors::No)?;
    let (lo, hi) = (
        mu.iter().copied().fold(f64::INFINITY, f64::min),
        mu.iter().copied().fold(0.0_f64, f64::max),
    );
    let ratio = if hi > 0.0 { lo / hi } else { 0.0 };
    if !(ratio >= MASS_CONDITION_LIMIT) {
        return Err(DenseEigenError::IllConditionedMass { ratio });
    }
    Ok(ratio)
}

/// Ascending eigenvalues and M-orthonormal eigenvectors (columns) of K φ = λ M φ.
pub fn generalized_eigen(
    k: MatRef<'_, f64>,
    m: MatRef<'_, f64>,
) -> Result<(Vec<f64>, Mat<f64>), DenseEigenError> {
    let n = k.nrows();
    if k.ncols() != n || m.nrows() != n || m.ncols() != n {
        return Err(DenseEigenError::Shape { k: n, m: m.nrows() });
    }
    if n == 0 {
        return Ok((Vec::new(), Mat::zeros(0, 0)));
    }
    let ratio = mass_conditioning(m)?;
    let mut l = m.to_owned();
    let mut stack = MemBuffer::new(cholesky_in_place_scratch::<f64>(
        n,
        Par::Seq,
        Default::default(),
    ));
    cholesky_in_place(
        l.as_mut(),
        Default::default(),
        Par::Seq,
        MemStack::new(&mut stack),
        Default::default(),
    )
    .map_err(|_| DenseEigenError::IllConditionedMass { ratio })?;
    (0..n).for_each(|j| (0..j).for_each(|i| l[(i, j)] = 0.0));
    let l = l.as_ref();
    // X = L⁻¹ K; A = L⁻¹ Xᵀ = L⁻¹ K L⁻ᵀ
    let mut x = k.to_owned();
    solve_lower_triangular_in_place(l, x.as_mut(), Par::Seq);
    let mut a = x.transpose().to_owned();
    solve_lower_triangular_in_place(l, a.as_mut(), Par::Seq);
    let a = Mat::<f64>::from_fn(n, n, |i, j| 0.5 * (a[(i, j)] + a[(j, i)]));
    let (lambda, mut phi) = symmetric_eigen_vectors(a.as_ref())?;
    // φ = L⁻ᵀ y: solve Lᵀ φ = y, i.e. the upper-triangular Lᵀ
    faer::linalg::triangular_solve::solve_upper_triangular_in_place(
        l.transpose(),
        phi.as_mut(),
        Par::Seq,
    );
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&i, &j| lambda[i].total_cmp(&lambda[j]));
    Ok((
        order.iter().map(|&i| lambda[i]).collect(),
        Mat::from_fn(n, n, |r, c| phi[(r, order[c])]),
    ))
}

/// Eigenvalues (ascending) and orthonormal eigenvectors (columns) of the symmetric `a` (its
/// lower triangle is read).
pub fn symmetric_eigen_vectors(
    a: MatRef<'_, f64>,
) -> Result<(Vec<f64>, Mat<f64>), DenseEigenError> {
    let (values, vectors) = symmetric_eigen(a, ComputeEigenvectors::Yes)?;
    Ok((values, vectors.expect("eigenvectors were requested")))
}

/// Eigenvalues (ascending) and, when asked, orthonormal eigenvectors of the symmetric `a`
/// (its lower triangle is read).
///
/// The tridiagonal eigenproblem is always solved by the implicit QR algorithm, never by faer's
/// divide and conquer (which it takes from n = 128 when vectors are asked): on graded spectra,
/// such as L⁻¹ K L⁻ᵀ of a pROM whose reduced mass spans seven decades, faer 0.24.4's divide and
/// conquer returned a lowest eigenvalue of −4.25e7 where QR (and LAPACK) give +4.93e4, an error
/// of 2e-7 ‖A‖ instead of the ε ‖A‖ of a backward-stable solver (test
/// `graded_spectrum_keeps_its_smallest_eigenvalue`). Its price, measured with vectors on random
/// symmetric matrices (release, one thread): 0.9 ms against divide and conquer's 1.0 ms at
/// n = 130, 15 against 10 ms at n = 300, 102 against 60 ms at n = 600.
fn symmetric_eigen(
    a: MatRef<'_, f64>,
    vectors: ComputeEigenvectors,
) -> Result<(Vec<f64>, Option<Mat<f64>>), DenseEigenError> {
    let n = a.nrows();
    let mut s = faer::diag::Diag::<f64>::zeros(n);
    let mut u = (vectors == ComputeEigenvectors::Yes).then(|| Mat::<f64>::zeros(n, n));
    let mut params: SelfAdjointEvdParams = faer::Auto::<f64>::auto();
    params.recursion_threshold = usize::MAX;
    let mut stack = MemBuffer::new(self_adjoint_evd_scratch::<f64>(
        n,
        vectors,
        Par::Seq,
        params.into(),
    ));
    self_adjoint_evd(
        a,
        s.as_mut(),
        u.as_mut().map(|u| u.as_mut()),
        Par::Seq,
        MemStack::new(&mut stack),
        params.into(),
    )
    .map_err(|_| DenseEigenError::NoConvergence)?;
    Ok(((0..n).map(|i| s.column_vector()[i]).collect(), u))
}

/// ‖Kφ_j − λ_j Mφ_j‖/‖Kφ_j‖ of each eigenpair (λ_j, column j of `phi`).
pub fn eigen_residuals(
    k: MatRef<'_, f64>,
    m: MatRef<'_, f64>,
    lambda: &[f64],
    phi: MatRef<'_, f64>,
) -> Vec<f64> {
    (0..lambda.len())
        .map(|j| {
            let v = phi.col(j);
            let kv = k * v;
            let r = &kv - (m * v) * faer::Scale(lambda[j]);
            r.norm_l2() / kv.norm_l2().max(f64::MIN_POSITIVE)
        })
        .collect()
}

/// A B, sequential (see the module documentation).
pub fn product(a: MatRef<'_, f64>, b: MatRef<'_, f64>) -> Mat<f64> {
    let mut out = Mat::zeros(a.nrows(), b.ncols());
    matmul(out.as_mut(), Accum::Replace, a, b, 1.0, Par::Seq);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// 2-DOF spring–mass chain (k₁ = k₂ = k, m₁ = m₂ = m): λ = (3 ∓ √5)/2 · k/m, vectors
    /// M-orthonormal; bound 1e-13 relative (dense LAPACK-class accuracy on a 2 × 2 problem).
    #[test]
    fn two_dof_chain() {
        let (k, m) = (1000.0, 2.0);
        let km = Mat::<f64>::from_fn(2, 2, |i, j| [[2.0 * k, -k], [-k, k]][i][j]);
        let mm = Mat::<f64>::from_fn(2, 2, |i, j| if i == j { m } else { 0.0 });
        let (lambda, phi) = generalized_eigen(km.as_ref(), mm.as_ref()).unwrap();
        let exact = [
            (3.0 - 5f64.sqrt()) / 2.0 * k / m,
            (3.0 + 5f64.sqrt()) / 2.0 * k / m,
        ];
        for (l, e) in lambda.iter().zip(exact) {
            assert!((l - e).abs() < 1e-13 * e, "{l} vs {e}");
        }
        let gm = phi.transpose() * &mm * &phi;
        assert!((gm - Mat::<f64>::identity(2, 2)).norm_max() < 1e-13);
    }

    /// A = Q Λ Qᵀ with n = 130 (a pROM's size), Λ graded as L⁻¹ K L⁻ᵀ of a pROM whose reduced
    /// mass spans seven decades: 46 eigenvalues from 5e4 to 1e12, then 84 clustered in
    /// [1e14, 2e14]; Q orthogonal (QR of a deterministic dense matrix). A backward-stable
    /// solver gets every eigenvalue within n ε ‖A‖ (≈ 5.8 here, 1.2e-4 of the smallest);
    /// faer 0.24.4's divide and conquer misses the smallest by ~1e5 with vectors.
    #[test]
    fn graded_spectrum_keeps_its_smallest_eigenvalue() {
        let n = 130;
        let exact: Vec<f64> = (0..n)
            .map(|i| {
                let geometric = |a: f64, b: f64, k: usize, of: usize| {
                    a * (b / a).powf(k as f64 / (of - 1) as f64)
                };
                if i < 46 {
                    geometric(5e4, 1e12, i, 46)
                } else {
                    geometric(1e14, 2e14, i - 46, 84)
                }
            })
            .collect();
        let dense = Mat::<f64>::from_fn(n, n, |i, j| ((i * 131 + j * 71) as f64 * 0.618).sin());
        let q = dense.qr().compute_Q();
        let a = Mat::<f64>::from_fn(n, n, |i, j| {
            (0..n)
                .map(|k| q[(i, k)] * exact[k] * q[(j, k)])
                .sum::<f64>()
        });
        let (values, vectors) = symmetric_eigen_vectors(a.as_ref()).unwrap();
        let bound = n as f64 * f64::EPSILON * 2e14;
        for (got, want) in values.iter().zip(&exact) {
            assert!(
                (got - want).abs() <= bound,
                "{got} vs {want} (bound {bound:e})"
            );
        }
        // and the vectors belong to them: ‖A y − λ y‖ within the same bound
        let y = vectors.col(0);
        let r = &a * y - y * faer::Scale(values[0]);
        assert!(r.norm_l2() <= bound, "residual {:e}", r.norm_l2());
    }

    #[test]
    fn nearly_singular_mass_is_reported() {
        let km = Mat::<f64>::identity(2, 2);
        let mm = Mat::<f64>::from_fn(2, 2, |i, j| if i == j { 1.0 } else { 1.0 - 1e-14 });
        assert!(matches!(
            generalized_eigen(km.as_ref(), mm.as_ref()),
            Err(DenseEigenError::IllConditionedMass { .. })
        ));
    }
}
