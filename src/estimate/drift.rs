//! Re-diagonalized modal coordinates ([`super::filter`]'s module documentation): the
//! off-diagonal couplings of the parts the estimate changes, their products and the Jacobi
//! solves with them, and what a re-diagonalization transforms.

use faer::Mat;
use faer::MatRef;
use faer::linalg::solvers::Solve;

use super::modal::{Coupling, ModalForm};
use crate::linalg::dense::product;

/// What re-diagonalized modal coordinates add to [`Modal`] (see the module documentation).
pub(super) struct Drift {
    pub(super) tolerance: f64,
    /// f_i(p) − f_i(p₀) of each coupling: the off-diagonal parts of K̃(p) and M̃(p) are
    /// Σ (f_i(p) − f_i(p₀)) (Ã_i − diag Ã_i), applied part by part (never summed into a matrix).
    pub(super) weights: Vec<f64>,
    /// ∂f_i/∂p_j of each coupling at p (n_c × n_p), for the parameter columns D.
    pub(super) derivatives: Mat<f64>,
    /// Largest relative drift of a coupled weight from the modes' parameters.
    pub(super) current: f64,
    /// S_un and the sensor rows in the physical coordinates, to transform after a
    /// re-diagonalization.
    pub(super) s_un: Mat<f64>,
    pub(super) h: Mat<f64>,
    /// Iterate and product buffers of the coupled solves (n).
    pub(super) iterate: Vec<f64>,
    pub(super) product: Vec<f64>,
    /// A coupled solve did not converge in [`JACOBI_ITERATIONS`]: re-diagonalize at the next
    /// refresh.
    pub(super) stalled: bool,
    /// Re-diagonalizations so far.
    pub(super) count: usize,
}

/// Iterations of a coupled solve before it falls back to a dense factorization (the iteration
/// contracts by about the drift per step, ≤ 0.1: 16 iterations reach round-off).
pub(super) const JACOBI_ITERATIONS: usize = 40;

/// out += scale (f_M M̃_off + f_K K̃_off) x, the off-diagonal parts of the couplings at their
/// current weights.
pub(super) fn add_coupled(
    couplings: &[Coupling],
    weights: &[f64],
    (f_m, f_k): (f64, f64),
    x: &[f64],
    out: &mut [f64],
    scale: f64,
) {
    for (coupling, &w) in couplings.iter().zip(weights) {
        for (f, off) in [(f_m, &coupling.mass), (f_k, &coupling.stiffness)] {
            if let (true, Some(off)) = (f * w != 0.0, off) {
                off.add_product(x, out, scale * f * w);
            }
        }
    }
}

/// x ← A⁻¹ x for A = diag(d) + f_M M̃_off + f_K K̃_off (the couplings' off-diagonal parts at
/// the weights of `drift`; none: a division). With couplings, by Jacobi iteration
/// x ← diag(d)⁻¹ (b − A_off x), which contracts by about the drift per iteration (module
/// documentation), until the update is below 4 ε of x; if it has not converged after
/// [`JACOBI_ITERATIONS`] (a coupled part that is not semi-definite), by a dense LU
/// factorization — allocating — and the drift is marked stalled, so the next refresh
/// re-diagonalizes.
pub(super) fn solve_modal(
    d: &[f64],
    couplings: &[Coupling],
    drift: Option<&mut Drift>,
    factors: (f64, f64),
    x: &mut [f64],
) {
    let (f_m, f_k) = factors;
    let coupled = |dr: &&mut Drift| {
        couplings.iter().zip(&dr.weights).any(|(c, &w)| {
            w != 0.0 && ((f_m != 0.0 && c.mass.is_some()) || (f_k != 0.0 && c.stiffness.is_some()))
        })
    };
    let Some(dr) = drift.filter(coupled) else {
        x.iter_mut().zip(d).for_each(|(x, d)| *x /= d);
        return;
    };
    let (iterate, product, weights) = (&mut dr.iterate, &mut dr.product, &dr.weights);
    iterate
        .iter_mut()
        .zip(x.iter().zip(d))
        .for_each(|(z, (b, d))| *z = b / d);
    for _ in 0..JACOBI_ITERATIONS {
        product.fill(0.0);
        add_coupled(couplings, weights, factors, iterate, product, 1.0);
        let (mut change, mut size) = (0.0_f64, 0.0_f64);
        for i in 0..d.len() {
            let next = (x[i] - product[i]) / d[i];
            change = change.max((next - iterate[i]).abs());
            size = size.max(next.abs());
            iterate[i] = next;
        }
        if change <= 4.0 * f64::EPSILON * size {
            x.copy_from_slice(iterate);
            return;
        }
    }
    dr.stalled = true;
    let n = d.len();
    let mut a = Mat::from_fn(n, n, |i, j| if i == j { d[i] } else { 0.0 });
    let mut unit = vec![0.0; n];
    for j in 0..n {
        unit[j] = 1.0;
        add_coupled(
            couplings,
            &dr.weights,
            factors,
            &unit,
            a.col_as_slice_mut(j),
            1.0,
        );
        unit[j] = 0.0;
    }
    let solution = a
        .partial_piv_lu()
        .solve(MatRef::from_column_major_slice(x, n, 1));
    x.iter_mut()
        .enumerate()
        .for_each(|(i, x)| *x = solution[(i, 0)]);
}

impl Drift {
    /// Empty buffers for the couplings of `form`; `s_un` and `h` in physical coordinates.
    pub(super) fn new(
        form: &ModalForm,
        tolerance: f64,
        np: usize,
        s_un: &Mat<f64>,
        h: &Mat<f64>,
    ) -> Self {
        let n = form.basis.nrows();
        Drift {
            tolerance,
            weights: vec![0.0; form.couplings.len()],
            derivatives: Mat::zeros(form.couplings.len(), np),
            current: 0.0,
            s_un: s_un.clone(),
            h: h.clone(),
            iterate: vec![0.0; n],
            product: vec![0.0; n],
            stalled: false,
            count: 0,
        }
    }
}

/// Φ⁻¹ Φ⁻ᵀ, made exactly symmetric so that P stays so (GEMM need not sum (i, j) and (j, i)
/// alike): the q and q̇ blocks of Q and P₀ in modal coordinates for a unit physical diagonal.
pub(super) fn gram(inverse: &Mat<f64>) -> Mat<f64> {
    let g = product(inverse.as_ref(), inverse.transpose());
    Mat::from_fn(g.nrows(), g.ncols(), |i, j| 0.5 * (g[(i, j)] + g[(j, i)]))
}
