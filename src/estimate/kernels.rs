//! Dense kernels of the filter: column-major storage as slices, vector updates, in-place
//! Cholesky factors and their solves, and the runtime SIMD dispatch (the systems are a few dozen
//! DOFs: everything runs sequentially on the calling thread).

use faer::dyn_stack::MemStack;
use faer::linalg::cholesky::llt::factor::cholesky_in_place;
use faer::{Mat, MatMut, MatRef, Par};

/// The entries of a column-major matrix as one slice, (i, j) at i + j · stride, and the stride.
pub(super) fn storage(m: &Mat<f64>) -> (&[f64], usize) {
    let stride = m.col_stride().unsigned_abs();
    let len = if m.ncols() == 0 {
        0
    } else {
        stride * (m.ncols() - 1) + m.nrows()
    };
    // SAFETY: a `Mat` owns one column-major allocation with columns `stride` ≥ nrows apart, so
    // the first `len` entries from its pointer are initialized, and they are borrowed with `m`.
    (
        unsafe { std::slice::from_raw_parts(m.as_ptr(), len) },
        stride,
    )
}

/// [`storage`], mutable.
pub(super) fn storage_mut(m: &mut Mat<f64>) -> (&mut [f64], usize) {
    let stride = m.col_stride().unsigned_abs();
    let len = if m.ncols() == 0 {
        0
    } else {
        stride * (m.ncols() - 1) + m.nrows()
    };
    // SAFETY: as in `storage`, borrowed mutably with `m`.
    (
        unsafe { std::slice::from_raw_parts_mut(m.as_ptr_mut(), len) },
        stride,
    )
}

/// out += scale · A x for a dense A (column by column).
pub(super) fn add_product(a: &Mat<f64>, x: &[f64], out: &mut [f64], scale: f64) {
    vectorized(
        #[inline(always)]
        || {
            for (c, &xc) in x.iter().enumerate() {
                if xc != 0.0 {
                    axpy(out, scale * xc, a.col_as_slice(c));
                }
            }
        },
    );
}

/// Cholesky factor A = L Lᵀ in place, sequential (L in the lower triangle; the strict upper
/// triangle is left as it was and never read). False when A is not positive definite.
pub(super) fn factor_in_place(a: MatMut<'_, f64>, stack: &mut MemStack) -> bool {
    cholesky_in_place(a, Default::default(), Par::Seq, stack, Default::default()).is_ok()
}

/// x ← A⁻¹ x for A = L Lᵀ with L the lower triangle of `l`, sequential (the filter's systems
/// are small: threads cost more than they bring).
pub(super) fn solve_seq(l: MatRef<'_, f64>, mut x: MatMut<'_, f64>) {
    faer::linalg::triangular_solve::solve_lower_triangular_in_place(l, x.as_mut(), Par::Seq);
    faer::linalg::triangular_solve::solve_upper_triangular_in_place(l.transpose(), x, Par::Seq);
}

/// Runs `f` compiled for the widest SIMD instruction set the CPU has (pulp's runtime dispatch,
/// AVX2 on current x86-64; the crate itself is built for baseline x86-64, whose SSE2 vectors are
/// half as wide): the filter's strided loops run 4 doubles per instruction. The same operations
/// in the same order (no fused multiply-adds, no reassociation), so the results do not depend on
/// the CPU.
#[inline(always)]
pub(super) fn vectorized<R>(f: impl FnOnce() -> R) -> R {
    pulp::Arch::new().dispatch(f)
}

/// y += a x.
#[inline(always)]
pub(super) fn axpy(y: &mut [f64], a: f64, x: &[f64]) {
    y.iter_mut().zip(x).for_each(|(y, x)| *y += a * x);
}

/// a · b with four interleaved partial sums (a strict left-to-right sum is one dependent
/// chain of additions and cannot use vector lanes).
#[inline(always)]
pub(super) fn dot(a: &[f64], b: &[f64]) -> f64 {
    let len = a.len().min(b.len());
    let (a, b) = (&a[..len], &b[..len]);
    let mut partial = [0.0; 4];
    let (chunks_a, chunks_b) = (a.chunks_exact(4), b.chunks_exact(4));
    let tail: f64 = chunks_a
        .remainder()
        .iter()
        .zip(chunks_b.remainder())
        .map(|(a, b)| a * b)
        .sum();
    for (x, y) in chunks_a.zip(chunks_b) {
        for l in 0..4 {
            partial[l] += x[l] * y[l];
        }
    }
    (partial[0] + partial[1]) + (partial[2] + partial[3]) + tail
}

/// Column `c` of a column-major matrix view as a slice ([`crate::rom::prom::PromEvaluation`]'s
/// views are column-major over one contiguous buffer, so every column is contiguous).
pub(super) fn column(m: MatRef<'_, f64>, c: usize) -> &[f64] {
    m.col(c)
        .try_as_col_major()
        .expect("column-major matrix view")
        .as_slice()
}
