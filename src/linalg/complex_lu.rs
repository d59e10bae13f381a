//! Sparse LU of complex square matrices with one symbolic analysis per pattern, for the
//! dynamic stiffness K − ω²M + iωC of frequency responses (complex symmetric, not Hermitian,
//! so the Hermitian LLᴴ / LDLᴴ of [`super::cholesky`] does not apply).
//!
//! faer 0.24 calls: `sparse::linalg::lu::factorize_symbolic_lu` (COLAMD column ordering,
//! elimination tree, supernodal or simplicial layout) once per pattern, then per matrix
//! `SymbolicLu::factorize_numeric_lu::<c64>` (partial pivoting by rows inside the fixed column
//! order) and `LuRef::solve_in_place_with_conj`. The symbolic object is shared (`Arc`) and
//! `Send + Sync`: each rayon task factors its own frequency with `Par::Seq`.
//!
//! Chosen over the real 2n × 2n form [[A, −B], [B, A]] (which would double the order and more
//! than double the fill) because faer's sparse LU is generic over the field.

use std::sync::Arc;

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::LuError;
use faer::sparse::linalg::lu::{NumericLu, SymbolicLu, factorize_symbolic_lu};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Par, c64};
use nalgebra_sparse::pattern::SparsityPattern;

use super::LinalgError;

/// The symbolic LU of one square pattern (column-compressed, sorted rows).
#[derive(Clone)]
pub struct ComplexLuSymbolic {
    n: usize,
    col_ptr: Arc<Vec<usize>>,
    row_idx: Arc<Vec<usize>>,
    inner: Arc<SymbolicLu<usize>>,
}

impl ComplexLuSymbolic {
    /// Column ordering and symbolic structure of `pattern` (n × n, nalgebra CSC layout).
    pub fn analyze(pattern: &SparsityPattern) -> Result<Self, LinalgError> {
        let (n, m) = (pattern.major_dim(), pattern.minor_dim());
        if n != m {
            return Err(LinalgError::NotSquare { nrows: m, ncols: n });
        }
        let col_ptr = pattern.major_offsets().to_vec();
        let row_idx = pattern.minor_indices().to_vec();
        let view = SymbolicSparseColMatRef::new_checked(n, n, &col_ptr, None, &row_idx);
        let inner = factorize_symbolic_lu(view, Default::default()).map_err(|_| LinalgError::OutOfMemory)?;
        Ok(ComplexLuSymbolic { n, col_ptr: Arc::new(col_ptr), row_idx: Arc::new(row_idx), inner: Arc::new(inner) })
    }

    /// Number of rows and columns.
    pub fn size(&self) -> usize {
        self.n
    }

    /// Solves A X = B in place for A with this pattern and `values` (CSC order), with one step
    /// of iterative refinement (the LU's backward error on shell models, whose stiffness mixes
    /// membrane and bending terms, is ~κ·ε; one step recovers most of it for the price of a
    /// solve). Fails with [`LinalgError::Singular`] when A is singular (a zero pivot, or a
    /// non-finite solution).
    pub fn solve_in_place(&self, values: &[c64], mut rhs: MatMut<'_, c64>) -> Result<(), LinalgError> {
        if values.len() != self.row_idx.len() {
            return Err(LinalgError::PatternMismatch { expected: self.row_idx.len(), got: values.len() });
        }
        if rhs.nrows() != self.n {
            return Err(LinalgError::DimensionMismatch { expected: self.n, got: rhs.nrows() });
        }
        let view = SymbolicSparseColMatRef::new_checked(self.n, self.n, &self.col_ptr, None, &self.row_idx);
        let a = SparseColMatRef::new(view, values);
        let mut numeric = NumericLu::<usize, c64>::new();
        let mut factor_mem = MemBuffer::try_new(self.inner.factorize_numeric_lu_scratch::<c64>(Par::Seq, Default::default())).map_err(|_| LinalgError::OutOfMemory)?;
        let lu = self.inner.factorize_numeric_lu(&mut numeric, a, Par::Seq, MemStack::new(&mut factor_mem), Default::default()).map_err(|e| match e {
            LuError::SymbolicSingular { index } => LinalgError::Singular { index },
            LuError::Generic(_) => LinalgError::OutOfMemory,
        })?;
        let k = rhs.ncols();
        let mut solve_mem = MemBuffer::try_new(self.inner.solve_in_place_scratch::<c64>(k, Par::Seq)).map_err(|_| LinalgError::OutOfMemory)?;
        let b = rhs.to_owned();
        lu.solve_in_place_with_conj(Conj::No, rhs.as_mut(), Par::Seq, MemStack::new(&mut solve_mem));
        // r = B − A X, X += A⁻¹ r
        let mut r = b;
        for j in 0..self.n {
            let range = self.col_ptr[j]..self.col_ptr[j + 1];
            for (&i, &v) in self.row_idx[range.clone()].iter().zip(&values[range]) {
                for c in 0..k {
                    r[(i, c)] -= v * rhs[(j, c)];
                }
            }
        }
        lu.solve_in_place_with_conj(Conj::No, r.as_mut(), Par::Seq, MemStack::new(&mut solve_mem));
        for c in 0..k {
            for i in 0..self.n {
                rhs[(i, c)] += r[(i, c)];
            }
        }
        if (0..k).any(|c| (0..self.n).any(|i| !(rhs[(i, c)].re.is_finite() && rhs[(i, c)].im.is_finite()))) {
            return Err(LinalgError::Singular { index: 0 });
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::Mat;
    use nalgebra_sparse::{CooMatrix, CscMatrix};

    /// A 3 × 3 complex symmetric (non-Hermitian) tridiagonal matrix against the dense LU:
    /// the same system, bound 1e-13 relative (two pivoted LUs of a well-conditioned matrix).
    #[test]
    fn matches_the_dense_lu() {
        let entries = [(0, 0, c64::new(4.0, 1.0)), (0, 1, c64::new(-1.0, 0.5)), (1, 0, c64::new(-1.0, 0.5)), (1, 1, c64::new(3.0, -2.0)), (1, 2, c64::new(0.0, 1.0)), (2, 1, c64::new(0.0, 1.0)), (2, 2, c64::new(2.0, 0.0))];
        let mut coo = CooMatrix::new(3, 3);
        for (i, j, v) in entries {
            coo.push(i, j, v);
        }
        let a = CscMatrix::from(&coo);
        let lu = ComplexLuSymbolic::analyze(a.pattern()).unwrap();
        let b = Mat::<c64>::from_fn(3, 2, |i, j| c64::new(1.0 + i as f64, j as f64));
        let mut x = b.clone();
        lu.solve_in_place(a.values(), x.as_mut()).unwrap();
        let dense = Mat::<c64>::from_fn(3, 3, |i, j| entries.iter().find(|e| e.0 == i && e.1 == j).map_or(c64::new(0.0, 0.0), |e| e.2));
        use faer::linalg::solvers::Solve;
        let want = dense.partial_piv_lu().solve(&b);
        for i in 0..3 {
            for j in 0..2 {
                assert!((x[(i, j)] - want[(i, j)]).norm() <= 1e-13 * want[(i, j)].norm().max(1.0));
            }
        }
    }

    #[test]
    fn a_singular_matrix_is_reported() {
        let mut coo = CooMatrix::new(2, 2);
        for (i, j) in [(0, 0), (0, 1), (1, 0), (1, 1)] {
            coo.push(i, j, c64::new(1.0, 1.0));
        }
        let a = CscMatrix::from(&coo);
        let lu = ComplexLuSymbolic::analyze(a.pattern()).unwrap();
        let mut x = Mat::<c64>::from_fn(2, 1, |_, _| c64::new(1.0, 0.0));
        assert!(matches!(lu.solve_in_place(a.values(), x.as_mut()), Err(LinalgError::Singular { .. })));
    }
}
