//! Sparse LU of complex square matrices with one symbolic analysis per pattern, for the
//! dynamic stiffness K − ω²M + iωC of frequency responses (complex symmetric, not Hermitian,
//! so the Hermitian LLᴴ / LDLᴴ of [`super::cholesky`] does not apply).
//!
//! Ordering. faer's high-level `sparse::linalg::lu::factorize_symbolic_lu` always computes its
//! own COLAMD column order. For a structurally symmetric pattern (every FE dynamic stiffness)
//! this module instead orders the columns by nested dissection of the pattern's graph
//! ([`super::ordering::nested_dissection`], METIS on the supervariables) and builds faer's
//! supernodal symbolic LU on that order through the lower-level calls the high-level one makes:
//! `qr::col_etree`, `qr::postorder`, `qr::column_counts_ata` (column elimination tree and
//! column counts of AᵀA, the static structure that holds L and U for any row pivoting) and
//! `lu::supernodal::factorize_supernodal_symbolic_lu`; per matrix
//! `lu::supernodal::factorize_supernodal_numeric_lu` (partial pivoting by rows inside the fixed
//! column order; it takes Aᵀ's values too, gathered through the mirror positions of the
//! symmetric pattern) and `SupernodalLu::solve_in_place_with_conj`. Other patterns keep faer's
//! default path (`SymbolicLu::factorize_numeric_lu`, `LuRef::solve_in_place_with_conj`).
//! The symbolic object is shared (`Arc`) and `Send + Sync`: each rayon task factors its own
//! frequency with `Par::Seq`.
//!
//! Chosen over the real 2n × 2n form [[A, −B], [B, A]] (which would double the order and more
//! than double the fill) because faer's sparse LU is generic over the field.

use std::sync::Arc;

use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::perm::PermRef;
use faer::sparse::linalg::LuError;
use faer::sparse::linalg::lu::supernodal::{self, SupernodalLu, SymbolicSupernodalLu};
use faer::sparse::linalg::lu::{NumericLu, SymbolicLu, factorize_symbolic_lu};
use faer::sparse::linalg::qr;
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, Mat, MatMut, Par, c64};
use nalgebra_sparse::pattern::SparsityPattern;

use super::LinalgError;
use super::ordering::{inverse, nested_dissection};

/// The symbolic LU of one square pattern (column-compressed, sorted rows).
#[derive(Clone)]
pub struct ComplexLuSymbolic {
    n: usize,
    col_ptr: Arc<Vec<usize>>,
    row_idx: Arc<Vec<usize>>,
    inner: Arc<Inner>,
}

/// Which symbolic analysis was made (module documentation).
enum Inner {
    /// faer's own: COLAMD column order, simplicial or supernodal.
    Colamd(SymbolicLu<usize>),
    /// A structurally symmetric pattern: nested-dissection column order, supernodal layout;
    /// `mirror[k]` is the position of the transpose of entry k.
    Symmetric {
        symbolic: SymbolicSupernodalLu<usize>,
        fwd: Vec<usize>,
        inv: Vec<usize>,
        mirror: Vec<usize>,
    },
}

/// For each entry (i, j) of a CSC pattern, the position of (j, i); `None` when the pattern is
/// not structurally symmetric.
fn mirror_positions(col_ptr: &[usize], row_idx: &[usize]) -> Option<Vec<usize>> {
    let n = col_ptr.len().saturating_sub(1);
    let mut mirror = vec![0; row_idx.len()];
    for j in 0..n {
        for p in col_ptr[j]..col_ptr[j + 1] {
            let i = row_idx[p];
            let q = row_idx[col_ptr[i]..col_ptr[i + 1]].binary_search(&j).ok()?;
            mirror[p] = col_ptr[i] + q;
        }
    }
    Some(mirror)
}

impl ComplexLuSymbolic {
    /// Column ordering and symbolic structure of `pattern` (n × n, nalgebra CSC layout; see the
    /// module documentation for the two paths).
    pub fn analyze(pattern: &SparsityPattern) -> Result<Self, LinalgError> {
        let (n, m) = (pattern.major_dim(), pattern.minor_dim());
        if n != m {
            return Err(LinalgError::NotSquare { nrows: m, ncols: n });
        }
        let col_ptr = pattern.major_offsets().to_vec();
        let row_idx = pattern.minor_indices().to_vec();
        let view = SymbolicSparseColMatRef::new_checked(n, n, &col_ptr, None, &row_idx);
        let inner = match mirror_positions(&col_ptr, &row_idx) {
            Some(mirror) if n > 0 => {
                let fwd = nested_dissection(pattern)?;
                let inv = inverse(&fwd);
                let perm = PermRef::new_checked(&fwd, &inv, n);
                let req = StackReq::any_of(&[
                    qr::col_etree_scratch::<usize>(n, n),
                    qr::postorder_scratch::<usize>(n),
                    qr::column_counts_aat_scratch::<usize>(n, n),
                    supernodal::factorize_supernodal_symbolic_lu_scratch::<usize>(n, n),
                ]);
                let mut mem = MemBuffer::try_new(req).map_err(|_| LinalgError::OutOfMemory)?;
                let stack = MemStack::new(&mut mem);
                let mut etree = vec![0usize; n];
                let tree = qr::col_etree(view, Some(perm), &mut etree, stack);
                let mut post = vec![0usize; n];
                qr::postorder(&mut post, tree, stack);
                let (mut col_counts, mut min_col) = (vec![0usize; n], vec![0usize; n]);
                // column_counts_ata takes Aᵀ's pattern: the pattern itself
                qr::column_counts_ata(
                    &mut col_counts,
                    &mut min_col,
                    view,
                    Some(perm),
                    tree,
                    &post,
                    stack,
                );
                let symbolic = supernodal::factorize_supernodal_symbolic_lu(
                    view,
                    Some(perm),
                    &min_col,
                    tree,
                    &col_counts,
                    stack,
                    Default::default(),
                )
                .map_err(|_| LinalgError::OutOfMemory)?;
                Inner::Symmetric {
                    symbolic,
                    fwd,
                    inv,
                    mirror,
                }
            }
            _ => Inner::Colamd(
                factorize_symbolic_lu(view, Default::default())
                    .map_err(|_| LinalgError::OutOfMemory)?,
            ),
        };
        Ok(ComplexLuSymbolic {
            n,
            col_ptr: Arc::new(col_ptr),
            row_idx: Arc::new(row_idx),
            inner: Arc::new(inner),
        })
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
    pub fn solve_in_place(&self, values: &[c64], rhs: MatMut<'_, c64>) -> Result<(), LinalgError> {
        if values.len() != self.row_idx.len() {
            return Err(LinalgError::PatternMismatch {
                expected: self.row_idx.len(),
                got: values.len(),
            });
        }
        if rhs.nrows() != self.n {
            return Err(LinalgError::DimensionMismatch {
                expected: self.n,
                got: rhs.nrows(),
            });
        }
        let (n, k) = (self.n, rhs.ncols());
        let view = SymbolicSparseColMatRef::new_checked(n, n, &self.col_ptr, None, &self.row_idx);
        let a = SparseColMatRef::new(view, values);
        let singular = |e: LuError| match e {
            LuError::SymbolicSingular { index } => LinalgError::Singular { index },
            LuError::Generic(_) => LinalgError::OutOfMemory,
        };
        let memory = |req: StackReq| MemBuffer::try_new(req).map_err(|_| LinalgError::OutOfMemory);
        match &*self.inner {
            Inner::Colamd(inner) => {
                let mut numeric = NumericLu::<usize, c64>::new();
                let mut factor_mem = memory(
                    inner.factorize_numeric_lu_scratch::<c64>(Par::Seq, Default::default()),
                )?;
                let lu = inner
                    .factorize_numeric_lu(
                        &mut numeric,
                        a,
                        Par::Seq,
                        MemStack::new(&mut factor_mem),
                        Default::default(),
                    )
                    .map_err(singular)?;
                let mut solve_mem = memory(inner.solve_in_place_scratch::<c64>(k, Par::Seq))?;
                self.refined(values, rhs, |x| {
                    lu.solve_in_place_with_conj(
                        Conj::No,
                        x,
                        Par::Seq,
                        MemStack::new(&mut solve_mem),
                    )
                })
            }
            Inner::Symmetric {
                symbolic,
                fwd,
                inv,
                mirror,
            } => {
                let transposed: Vec<c64> = mirror.iter().map(|&p| values[p]).collect();
                let at = SparseColMatRef::new(view, &transposed);
                let col = PermRef::new_checked(fwd, inv, n);
                let (mut row_fwd, mut row_inv) = (vec![0usize; n], vec![0usize; n]);
                let mut lu = SupernodalLu::<usize, c64>::new();
                let mut factor_mem =
                    memory(supernodal::factorize_supernodal_numeric_lu_scratch::<
                        usize,
                        c64,
                    >(symbolic, Default::default()))?;
                supernodal::factorize_supernodal_numeric_lu(
                    &mut row_fwd,
                    &mut row_inv,
                    &mut lu,
                    a,
                    at,
                    col,
                    symbolic,
                    Par::Seq,
                    MemStack::new(&mut factor_mem),
                    Default::default(),
                )
                .map_err(singular)?;
                let row = PermRef::new_checked(&row_fwd, &row_inv, n);
                let mut solve_mem = memory(supernodal::solve_in_place_scratch::<usize, c64>(
                    n,
                    k,
                    Par::Seq,
                ))?;
                self.refined(values, rhs, |x| {
                    lu.solve_in_place_with_conj(
                        row,
                        col,
                        Conj::No,
                        x,
                        Par::Seq,
                        MemStack::new(&mut solve_mem),
                    )
                })
            }
        }
    }

    /// X = A⁻¹B by `solve` (in place) plus one refinement step r = B − A X, X += A⁻¹ r.
    fn refined(
        &self,
        values: &[c64],
        mut rhs: MatMut<'_, c64>,
        mut solve: impl FnMut(MatMut<'_, c64>),
    ) -> Result<(), LinalgError> {
        let (n, k) = (self.n, rhs.ncols());
        let mut r: Mat<c64> = rhs.to_owned();
        solve(rhs.as_mut());
        for j in 0..n {
            let range = self.col_ptr[j]..self.col_ptr[j + 1];
            for (&i, &v) in self.row_idx[range.clone()].iter().zip(&values[range]) {
                for c in 0..k {
                    r[(i, c)] -= v * rhs[(j, c)];
                }
            }
        }
        solve(r.as_mut());
        for c in 0..k {
            for i in 0..n {
                rhs[(i, c)] += r[(i, c)];
            }
        }
        if (0..k)
            .any(|c| (0..n).any(|i| !(rhs[(i, c)].re.is_finite() && rhs[(i, c)].im.is_finite())))
        {
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
        let entries = [
            (0, 0, c64::new(4.0, 1.0)),
            (0, 1, c64::new(-1.0, 0.5)),
            (1, 0, c64::new(-1.0, 0.5)),
            (1, 1, c64::new(3.0, -2.0)),
            (1, 2, c64::new(0.0, 1.0)),
            (2, 1, c64::new(0.0, 1.0)),
            (2, 2, c64::new(2.0, 0.0)),
        ];
        let mut coo = CooMatrix::new(3, 3);
        for (i, j, v) in entries {
            coo.push(i, j, v);
        }
        let a = CscMatrix::from(&coo);
        let lu = ComplexLuSymbolic::analyze(a.pattern()).unwrap();
        assert!(matches!(*lu.inner, Inner::Symmetric { .. }));
        let b = Mat::<c64>::from_fn(3, 2, |i, j| c64::new(1.0 + i as f64, j as f64));
        let mut x = b.clone();
        lu.solve_in_place(a.values(), x.as_mut()).unwrap();
        let dense = Mat::<c64>::from_fn(3, 3, |i, j| {
            entries
                .iter()
                .find(|e| e.0 == i && e.1 == j)
                .map_or(c64::new(0.0, 0.0), |e| e.2)
        });
        use faer::linalg::solvers::Solve;
        let want = dense.partial_piv_lu().solve(&b);
        for i in 0..3 {
            for j in 0..2 {
                assert!((x[(i, j)] - want[(i, j)]).norm() <= 1e-13 * want[(i, j)].norm().max(1.0));
            }
        }
    }

    /// A structurally unsymmetric pattern takes faer's COLAMD path: same check against the
    /// dense LU (bound as above).
    #[test]
    fn an_unsymmetric_pattern_matches_the_dense_lu() {
        let entries = [
            (0, 0, c64::new(4.0, 1.0)),
            (0, 2, c64::new(-1.0, 0.5)),
            (1, 0, c64::new(2.0, 0.0)),
            (1, 1, c64::new(3.0, -2.0)),
            (2, 1, c64::new(0.0, 1.0)),
            (2, 2, c64::new(2.0, 0.0)),
        ];
        let mut coo = CooMatrix::new(3, 3);
        for (i, j, v) in entries {
            coo.push(i, j, v);
        }
        let a = CscMatrix::from(&coo);
        let lu = ComplexLuSymbolic::analyze(a.pattern()).unwrap();
        assert!(matches!(*lu.inner, Inner::Colamd(_)));
        let b = Mat::<c64>::from_fn(3, 1, |i, _| c64::new(1.0, -(i as f64)));
        let mut x = b.clone();
        lu.solve_in_place(a.values(), x.as_mut()).unwrap();
        let dense = Mat::<c64>::from_fn(3, 3, |i, j| {
            entries
                .iter()
                .find(|e| e.0 == i && e.1 == j)
                .map_or(c64::new(0.0, 0.0), |e| e.2)
        });
        use faer::linalg::solvers::Solve;
        let want = dense.partial_piv_lu().solve(&b);
        for i in 0..3 {
            assert!((x[(i, 0)] - want[(i, 0)]).norm() <= 1e-13 * want[(i, 0)].norm().max(1.0));
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
        assert!(matches!(
            lu.solve_in_place(a.values(), x.as_mut()),
            Err(LinalgError::Singular { .. })
        ));
    }
}
