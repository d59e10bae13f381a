//! Sparse symmetric factorizations with one symbolic analysis per pattern.
//!
//! [`SymbolicFactor::analyze`] computes a fill-reducing ordering (see [`Ordering`]: faer's
//! built-in AMD for small problems, METIS nested dissection on the supervariable graph from
//! [`ND_THRESHOLD`] unknowns on), the elimination tree, column counts and — when the flop count
//! makes it worthwhile — the supernode partition, exactly once per sparsity pattern. Every numeric factorization (K at each
//! parameter sample, K − σM at each shift) reuses it through [`SymbolicFactor::factor_llt`] or
//! [`SymbolicFactor::factor_ldlt`]. The symbolic object is reference-counted and `Send + Sync`:
//! clone it into rayon tasks and factor samples in parallel (with `Par::Seq` inside each task).
//!
//! Numbering: the ordering is internal. Every index this module reports (failing pivot DOF)
//! is in the caller's numbering, i.e. a row of the matrix that was passed in.
//!
//! Pivot diagnostics (P = permutation, PAPᵀ = L D Lᵀ, d_k the k-th pivot, a_kk the matching
//! diagonal entry of A):
//! - LLᵀ fails with [`LinalgError::NotPositiveDefinite`] at the first pivot (in elimination
//!   order) that is non-positive or whose ratio a_kk / d_k exceeds the maximum ratio (default
//!   [`DEFAULT_MAX_RATIO`] = 10⁷, the default of Nastran's MAXRATIO). In exact arithmetic an
//!   unconstrained mechanism gives d_k = 0; in floating point it gives d_k ≈ ε·a_kk of either
//!   sign, which the ratio test catches.
//! - LDLᵀ (no pivoting, so D is diagonal) fails with [`LinalgError::Singular`] only on an exactly
//!   zero or non-finite pivot, and otherwise returns the [`Inertia`] of A: by Sylvester's law of
//!   inertia the signs of the d_k are the signs of the eigenvalues of A. Pivots with
//!   |d_k| ≤ [`ZERO_PIVOT_TOL`]·|a_kk| are counted as zero.
//!
//! faer 0.24 calls: `factorize_symbolic_cholesky(pattern, Side::Upper, SymmetricOrdering::{Amd,
//! Custom(PermRef::new_checked(fwd, inv, n))}, CholeskySymbolicParams)` with `fwd[k]` = caller
//! index of the k-th pivot (the convention of faer's AMD and of METIS' `perm`), `SymbolicCholesky::factorize_numeric_{llt,ldlt}` with their
//! `_scratch` sizes, `LltRef`/`LdltRef::solve_in_place_with_conj`. faer's failing pivot index is
//! in the permuted numbering and is 1-based for the simplicial variant but 0-based for the
//! supernodal one; [`SymbolicFactor`] normalizes both (tested for each variant).

use std::sync::Arc;

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::ldlt::factor::LdltError;
use faer::linalg::cholesky::llt::factor::LltError;
use faer::perm::PermRef;
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::linalg::cholesky::supernodal::SupernodalLdltRef;
use faer::sparse::linalg::cholesky::{
    CholeskySymbolicParams, LdltRef, LltRef, SymbolicCholesky, SymbolicCholeskyRaw,
    SymmetricOrdering, factorize_symbolic_cholesky,
};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Par, Side};
use nalgebra_sparse::CscMatrix;
use nalgebra_sparse::pattern::SparsityPattern;

use super::LinalgError;
use super::ordering::{inverse, nested_dissection};

/// Default maximum ratio a_kk / d_k accepted by [`SymbolicFactor::factor_llt`] (Nastran MAXRATIO).
pub const DEFAULT_MAX_RATIO: f64 = 1e7;

/// Pivots with |d_k| ≤ `ZERO_PIVOT_TOL`·|a_kk| count as zero in the [`Inertia`].
pub const ZERO_PIVOT_TOL: f64 = 1e-12;

/// Numeric layout chosen by the symbolic analysis.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
pub enum FactorVariant {
    /// Let faer choose from the flop count (simplicial for very sparse factors).
    #[default]
    Auto,
    /// Column-by-column (good for banded or tiny problems).
    Simplicial,
    /// Dense supernodes with BLAS-3 kernels (good for 2-D/3-D meshes).
    Supernodal,
}

/// Dimension from which [`Ordering::Auto`] switches from AMD to nested dissection. Below it
/// AMD's fill is close to ND's and AMD is cheaper; above it, on 3-D meshes, ND's fill and
/// flops are far smaller (300k-unknown 7-point Laplacian: nnz(L) 3.4·10⁸ → see the benchmark
/// in `eigen`).
pub const ND_THRESHOLD: usize = 20_000;

/// Fill-reducing ordering used by the symbolic analysis.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
pub enum Ordering {
    /// AMD below [`ND_THRESHOLD`] unknowns, nested dissection from there on.
    #[default]
    Auto,
    /// faer's approximate minimum degree.
    Amd,
    /// METIS nested dissection on the supervariable graph ([`super::ordering`]).
    NestedDissection,
}

/// Which factorization a [`Factor`] holds.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum FactorKind {
    /// A = L Lᵀ (A positive definite).
    Llt,
    /// A = L D Lᵀ with diagonal D, no pivoting (A symmetric, possibly indefinite).
    Ldlt,
}

/// Counts of negative, (numerically) zero and positive pivots of an LDLᵀ factorization.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
pub struct Inertia {
    pub negative: usize,
    pub zero: usize,
    pub positive: usize,
}

/// Largest |a_kk / d_k| of a factorization and the DOF (caller numbering) where it occurs.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct PivotRatio {
    pub ratio: f64,
    pub index: usize,
}

struct SymbolicInner {
    chol: SymbolicCholesky<usize>,
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    /// Position of entry (k, k) in the values array, `None` if structurally absent.
    diag_pos: Vec<Option<usize>>,
}

/// Ordering and symbolic factorization of one symmetric sparsity pattern (full storage).
/// Cheap to clone (reference-counted), shareable across threads.
#[derive(Clone)]
pub struct SymbolicFactor {
    inner: Arc<SymbolicInner>,
    max_ratio: f64,
}

impl std::fmt::Debug for SymbolicFactor {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SymbolicFactor")
            .field("n", &self.nrows())
            .field("nnz", &self.nnz())
            .field("len_factor", &self.inner.chol.len_val())
            .field("max_ratio", &self.max_ratio)
            .finish()
    }
}

impl SymbolicFactor {
    /// Analyses a square, structurally symmetric pattern stored in full (both triangles):
    /// ordering ([`Ordering::Auto`]) and symbolic Cholesky, variant chosen automatically.
    pub fn analyze(pattern: &SparsityPattern) -> Result<Self, LinalgError> {
        Self::analyze_with(pattern, FactorVariant::Auto, Ordering::Auto)
    }

    /// [`analyze`](Self::analyze) with an explicit simplicial/supernodal choice and ordering.
    pub fn analyze_with(
        pattern: &SparsityPattern,
        variant: FactorVariant,
        ordering: Ordering,
    ) -> Result<Self, LinalgError> {
        let n = pattern.major_dim();
        if pattern.minor_dim() != n {
            return Err(LinalgError::NotSquare {
                nrows: pattern.minor_dim(),
                ncols: n,
            });
        }
        let col_ptr = pattern.major_offsets();
        let row_idx = pattern.minor_indices();
        let lane = |j: usize| &row_idx[col_ptr[j]..col_ptr[j + 1]];
        let mut diag_pos = vec![None; n];
        for (j, slot) in diag_pos.iter_mut().enumerate() {
            for (p, &i) in lane(j).iter().enumerate() {
                if lane(i).binary_search(&j).is_err() {
                    return Err(LinalgError::PatternNotSymmetric { row: i, col: j });
                }
                if i == j {
                    *slot = Some(col_ptr[j] + p);
                }
            }
        }
        let threshold = match variant {
            FactorVariant::Auto => SupernodalThreshold::AUTO,
            FactorVariant::Simplicial => SupernodalThreshold::FORCE_SIMPLICIAL,
            FactorVariant::Supernodal => SupernodalThreshold::FORCE_SUPERNODAL,
        };
        let params = CholeskySymbolicParams {
            supernodal_flop_ratio_threshold: threshold,
            ..Default::default()
        };
        let view = SymbolicSparseColMatRef::new_checked(n, n, col_ptr, None, row_idx);
        let nested = match ordering {
            Ordering::Auto => n >= ND_THRESHOLD,
            Ordering::Amd => false,
            Ordering::NestedDissection => true,
        };
        let chol = if nested {
            let fwd = nested_dissection(pattern)?;
            let inv = inverse(&fwd);
            let perm = PermRef::new_checked(&fwd, &inv, n);
            factorize_symbolic_cholesky(view, Side::Upper, SymmetricOrdering::Custom(perm), params)
        } else {
            factorize_symbolic_cholesky(view, Side::Upper, SymmetricOrdering::Amd, params)
        }
        .map_err(|_| LinalgError::OutOfMemory)?;
        Ok(Self {
            inner: Arc::new(SymbolicInner {
                chol,
                col_ptr: col_ptr.to_vec(),
                row_idx: row_idx.to_vec(),
                diag_pos,
            }),
            max_ratio: DEFAULT_MAX_RATIO,
        })
    }

    /// Sets the maximum a_kk / d_k accepted by [`factor_llt`](Self::factor_llt) (Nastran MAXRATIO).
    pub fn with_max_ratio(mut self, max_ratio: f64) -> Self {
        self.max_ratio = max_ratio;
        self
    }

    /// Dimension n of the analysed pattern.
    pub fn nrows(&self) -> usize {
        self.inner.col_ptr.len() - 1
    }

    /// Number of stored entries of the analysed (full) pattern.
    pub fn nnz(&self) -> usize {
        self.inner.row_idx.len()
    }

    /// Number of stored entries of the factor L.
    pub fn factor_nnz(&self) -> usize {
        self.inner.chol.len_val()
    }

    /// Layout chosen for the numeric factor: [`FactorVariant::Simplicial`] or
    /// [`FactorVariant::Supernodal`] (never `Auto`).
    pub fn variant(&self) -> FactorVariant {
        match self.inner.chol.raw() {
            SymbolicCholeskyRaw::Simplicial(_) => FactorVariant::Simplicial,
            SymbolicCholeskyRaw::Supernodal(_) => FactorVariant::Supernodal,
        }
    }

    /// Checks that `a` has exactly the analysed pattern and returns its values.
    pub(crate) fn values_of<'a>(&self, a: &'a CscMatrix<f64>) -> Result<&'a [f64], LinalgError> {
        if a.col_offsets() != self.inner.col_ptr.as_slice()
            || a.row_indices() != self.inner.row_idx.as_slice()
        {
            return Err(LinalgError::PatternMismatch {
                expected: self.nnz(),
                got: a.nnz(),
            });
        }
        Ok(a.values())
    }

    /// LLᵀ of a symmetric positive definite matrix with the analysed pattern.
    /// Fails with [`LinalgError::NotPositiveDefinite`] at the first bad pivot (see module doc).
    pub fn factor_llt(&self, a: &CscMatrix<f64>, par: Par) -> Result<Factor, LinalgError> {
        self.factor_llt_values(self.values_of(a)?, par)
    }

    /// LDLᵀ (no pivoting) of a symmetric matrix with the analysed pattern; the factor carries
    /// the inertia. Fails with [`LinalgError::Singular`] on an exactly zero pivot.
    pub fn factor_ldlt(&self, a: &CscMatrix<f64>, par: Par) -> Result<Factor, LinalgError> {
        self.factor_ldlt_values(self.values_of(a)?, par)
    }

    /// [`factor_llt`](Self::factor_llt) from a values array laid out like the analysed pattern
    /// (e.g. K(p) values summed from affine parts into a caller buffer).
    pub fn factor_llt_values(&self, values: &[f64], par: Par) -> Result<Factor, LinalgError> {
        let chol = &self.inner.chol;
        let mut l = self.alloc_factor(values)?;
        let req = chol.factorize_numeric_llt_scratch::<f64>(par, Default::default());
        let mut mem = MemBuffer::try_new(req).map_err(|_| LinalgError::OutOfMemory)?;
        let result = chol.factorize_numeric_llt(
            &mut l,
            self.view(values),
            Side::Upper,
            Default::default(),
            par,
            MemStack::new(&mut mem),
            Default::default(),
        );
        match result {
            Ok(_) => {}
            Err(LltError::NonPositivePivot { index }) => {
                return Err(LinalgError::NotPositiveDefinite {
                    index: self.caller_index(index),
                    ratio: f64::INFINITY,
                });
            }
        }
        let mut worst = PivotRatio {
            ratio: 0.0,
            index: 0,
        };
        let mut failure = None;
        self.for_each_pivot(&l, |k, l_kk| {
            let (index, a_kk) = self.diagonal(values, k);
            let ratio = a_kk / (l_kk * l_kk);
            if ratio > worst.ratio {
                worst = PivotRatio { ratio, index };
            }
            if failure.is_none() && ratio > self.max_ratio {
                failure = Some(LinalgError::NotPositiveDefinite { index, ratio });
            }
        });
        match failure {
            Some(err) => Err(err),
            None => Ok(Factor {
                symbolic: self.clone(),
                values: l,
                kind: FactorKind::Llt,
                inertia: Inertia {
                    positive: self.nrows(),
                    ..Default::default()
                },
                max_ratio: worst,
                par,
            }),
        }
    }

    /// [`factor_ldlt`](Self::factor_ldlt) from a values array laid out like the analysed pattern
    /// (e.g. K − σM formed into a caller buffer).
    pub fn factor_ldlt_values(&self, values: &[f64], par: Par) -> Result<Factor, LinalgError> {
        let chol = &self.inner.chol;
        let mut l = self.alloc_factor(values)?;
        let req = chol.factorize_numeric_ldlt_scratch::<f64>(par, Default::default());
        let mut mem = MemBuffer::try_new(req).map_err(|_| LinalgError::OutOfMemory)?;
        let result = chol.factorize_numeric_ldlt(
            &mut l,
            self.view(values),
            Side::Upper,
            Default::default(),
            par,
            MemStack::new(&mut mem),
            Default::default(),
        );
        if let Err(LdltError::ZeroPivot { index }) = result {
            return Err(LinalgError::Singular {
                index: self.caller_index(index),
            });
        }
        let mut inertia = Inertia::default();
        let mut worst = PivotRatio {
            ratio: 0.0,
            index: 0,
        };
        self.for_each_pivot(&l, |k, d| {
            let (index, a_kk) = self.diagonal(values, k);
            let ratio = (a_kk / d).abs();
            if ratio > worst.ratio {
                worst = PivotRatio { ratio, index };
            }
            if d.abs() <= ZERO_PIVOT_TOL * a_kk.abs() {
                inertia.zero += 1;
            } else if d < 0.0 {
                inertia.negative += 1;
            } else {
                inertia.positive += 1;
            }
        });
        Ok(Factor {
            symbolic: self.clone(),
            values: l,
            kind: FactorKind::Ldlt,
            inertia,
            max_ratio: worst,
            par,
        })
    }

    fn alloc_factor(&self, values: &[f64]) -> Result<Vec<f64>, LinalgError> {
        if values.len() != self.nnz() {
            return Err(LinalgError::DimensionMismatch {
                expected: self.nnz(),
                got: values.len(),
            });
        }
        let len = self.inner.chol.len_val();
        let mut l = Vec::new();
        l.try_reserve_exact(len)
            .map_err(|_| LinalgError::OutOfMemory)?;
        l.resize(len, 0.0);
        Ok(l)
    }

    fn view<'a>(&'a self, values: &'a [f64]) -> SparseColMatRef<'a, usize, f64> {
        let n = self.nrows();
        let symbolic = SymbolicSparseColMatRef::new_checked(
            n,
            n,
            &self.inner.col_ptr,
            None,
            &self.inner.row_idx,
        );
        SparseColMatRef::new(symbolic, values)
    }

    /// Maps faer's failing-pivot index (permuted; 1-based simplicial, 0-based supernodal) to
    /// the caller's numbering.
    fn caller_index(&self, faer_index: usize) -> usize {
        let k = match self.inner.chol.raw() {
            SymbolicCholeskyRaw::Simplicial(_) => faer_index.saturating_sub(1),
            SymbolicCholeskyRaw::Supernodal(_) => faer_index,
        };
        self.permuted_to_caller(k.min(self.nrows().saturating_sub(1)))
    }

    fn permuted_to_caller(&self, k: usize) -> usize {
        match self.inner.chol.perm() {
            Some(perm) => perm.arrays().0[k],
            None => k,
        }
    }

    /// (caller index, a_kk) of the k-th eliminated DOF.
    fn diagonal(&self, values: &[f64], k: usize) -> (usize, f64) {
        let index = self.permuted_to_caller(k);
        (index, self.inner.diag_pos[index].map_or(0.0, |p| values[p]))
    }

    /// Calls `f(k, L_kk)` for every pivot in elimination order; L_kk holds d_k for LDLᵀ and
    /// √d_k for LLᵀ (both variants store the diagonal block entry (k, k)).
    fn for_each_pivot(&self, l: &[f64], mut f: impl FnMut(usize, f64)) {
        match self.inner.chol.raw() {
            SymbolicCholeskyRaw::Simplicial(s) => {
                for (k, &p) in s.col_ptr()[..self.nrows()].iter().enumerate() {
                    f(k, l[p]);
                }
            }
            SymbolicCholeskyRaw::Supernodal(s) => {
                let factor = SupernodalLdltRef::new(s, l);
                for node in 0..s.n_supernodes() {
                    let node = factor.supernode(node);
                    let val = node.val();
                    for j in 0..val.ncols() {
                        f(node.start() + j, val[(j, j)]);
                    }
                }
            }
        }
    }
}

/// Numeric factorization (LLᵀ or LDLᵀ) bound to its [`SymbolicFactor`].
#[derive(Clone)]
pub struct Factor {
    symbolic: SymbolicFactor,
    values: Vec<f64>,
    kind: FactorKind,
    inertia: Inertia,
    max_ratio: PivotRatio,
    par: Par,
}

impl std::fmt::Debug for Factor {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Factor")
            .field("kind", &self.kind)
            .field("inertia", &self.inertia)
            .field("max_ratio", &self.max_ratio)
            .finish()
    }
}

/// Workspace for [`Factor::solve_in_place_with_scratch`], sized once for up to `ncols`
/// right-hand sides so that repeated solves do not allocate.
pub struct SolveScratch {
    mem: MemBuffer,
    ncols: usize,
}

impl Factor {
    /// LLᵀ or LDLᵀ.
    pub fn kind(&self) -> FactorKind {
        self.kind
    }

    /// Pivot sign counts (all positive for LLᵀ).
    pub fn inertia(&self) -> Inertia {
        self.inertia
    }

    /// Largest |a_kk / d_k| (Nastran MAXRATIO diagnostic) and its DOF.
    pub fn max_pivot_ratio(&self) -> PivotRatio {
        self.max_ratio
    }

    /// Dimension n.
    pub fn nrows(&self) -> usize {
        self.symbolic.nrows()
    }

    /// The symbolic analysis this factor was computed with.
    pub fn symbolic(&self) -> &SymbolicFactor {
        &self.symbolic
    }

    /// Workspace for solves with up to `ncols` right-hand sides.
    pub fn solve_scratch(&self, ncols: usize) -> Result<SolveScratch, LinalgError> {
        let req = self
            .symbolic
            .inner
            .chol
            .solve_in_place_scratch::<f64>(ncols, self.par);
        let mem = MemBuffer::try_new(req).map_err(|_| LinalgError::OutOfMemory)?;
        Ok(SolveScratch { mem, ncols })
    }

    /// Solves A x = b for one right-hand side, overwriting `rhs` (b on entry, x on exit).
    /// Allocates its workspace; loops should use [`solve_in_place_with_scratch`](Self::solve_in_place_with_scratch).
    pub fn solve_in_place(&self, rhs: &mut [f64]) -> Result<(), LinalgError> {
        let mut scratch = self.solve_scratch(1)?;
        let n = rhs.len();
        self.solve_in_place_with_scratch(
            MatMut::from_column_major_slice_mut(rhs, n, 1),
            &mut scratch,
        )
    }

    /// Solves A X = B for the columns of the caller's n×k buffer `rhs` (B on entry, X on exit),
    /// using `scratch` sized for at least k columns; no allocation.
    pub fn solve_in_place_with_scratch(
        &self,
        rhs: MatMut<'_, f64>,
        scratch: &mut SolveScratch,
    ) -> Result<(), LinalgError> {
        if rhs.nrows() != self.nrows() {
            return Err(LinalgError::DimensionMismatch {
                expected: self.nrows(),
                got: rhs.nrows(),
            });
        }
        if rhs.ncols() > scratch.ncols {
            return Err(LinalgError::DimensionMismatch {
                expected: scratch.ncols,
                got: rhs.ncols(),
            });
        }
        let chol = &self.symbolic.inner.chol;
        let stack = MemStack::new(&mut scratch.mem);
        match self.kind {
            FactorKind::Llt => LltRef::new(chol, &self.values).solve_in_place_with_conj(
                Conj::No,
                rhs,
                self.par,
                stack,
            ),
            FactorKind::Ldlt => LdltRef::new(chol, &self.values).solve_in_place_with_conj(
                Conj::No,
                rhs,
                self.par,
                stack,
            ),
        }
        Ok(())
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::linalg::sym_matvec;
    use nalgebra_sparse::CooMatrix;

    /// Spring chain with `n` DOFs and unit springs between neighbours; `ground_left/right`
    /// adds a unit spring to ground at the ends; `cut` removes the spring between DOF cut−1
    /// and cut (the entries stay in the pattern as explicit zeros).
    pub(crate) fn chain(
        n: usize,
        ground_left: bool,
        ground_right: bool,
        cut: Option<usize>,
    ) -> CscMatrix<f64> {
        let mut coo = CooMatrix::new(n, n);
        for i in 0..n {
            coo.push(i, i, 0.0);
        }
        if ground_left {
            coo.push(0, 0, 1.0);
        }
        if ground_right {
            coo.push(n - 1, n - 1, 1.0);
        }
        for i in 1..n {
            let k = if cut == Some(i) { 0.0 } else { 1.0 };
            coo.push(i - 1, i - 1, k);
            coo.push(i, i, k);
            coo.push(i - 1, i, -k);
            coo.push(i, i - 1, -k);
        }
        CscMatrix::from(&coo)
    }

    fn residual(a: &CscMatrix<f64>, x: &[f64], b: &[f64]) -> f64 {
        let mut ax = vec![0.0; x.len()];
        sym_matvec(a, x, &mut ax).unwrap();
        ax.iter()
            .zip(b)
            .map(|(p, q)| (p - q).powi(2))
            .sum::<f64>()
            .sqrt()
    }

    const VARIANTS: [FactorVariant; 2] = [FactorVariant::Simplicial, FactorVariant::Supernodal];
    const ORDERINGS: [Ordering; 2] = [Ordering::Amd, Ordering::NestedDissection];

    fn combinations() -> impl Iterator<Item = (FactorVariant, Ordering)> {
        VARIANTS.into_iter().flat_map(|v| ORDERINGS.map(|o| (v, o)))
    }

    /// Solves A x = b with `sym`'s LDLᵀ for b_i = sin(i) + 1.
    fn solve_ldlt(sym: &SymbolicFactor, a: &CscMatrix<f64>) -> Vec<f64> {
        let mut x = solve_rhs(a.nrows());
        sym.factor_ldlt(a, Par::Seq)
            .unwrap()
            .solve_in_place(&mut x)
            .unwrap();
        x
    }

    fn relative_difference(x: &[f64], y: &[f64]) -> f64 {
        let norm = |v: &mut dyn Iterator<Item = f64>| v.map(|t| t * t).sum::<f64>().sqrt();
        norm(&mut x.iter().zip(y).map(|(a, b)| a - b)) / norm(&mut x.iter().copied())
    }

    /// ND-ordered and AMD-ordered factors solve identically (to round-off) on a 3-D Laplacian
    /// of 20 412 unknowns (where `Auto` picks ND) and on a 6-DOF-per-node block pattern; the
    /// factor stores exactly METIS' permutation with `fwd[k]` = caller index of pivot k.
    #[test]
    fn nested_dissection_solves_match_amd() {
        let lap = crate::linalg::eigen::tests::laplacian(&[28, 27, 27]);
        let block = crate::linalg::ordering::tests::block_grid([10, 9, 8], 6);
        for a in [&lap, &block] {
            let amd = SymbolicFactor::analyze_with(a.pattern(), FactorVariant::Auto, Ordering::Amd)
                .unwrap();
            let reference = solve_ldlt(&amd, a);
            assert!(residual(a, &reference, &solve_rhs(a.nrows())) < 1e-10);
            // Both layouts on the small pattern; the 20k one keeps `Auto` (supernodal) because
            // faer's kernels, monomorphized in this crate, are unoptimized in test builds.
            let variants: &[FactorVariant] = if a.nrows() < ND_THRESHOLD {
                &VARIANTS
            } else {
                &[FactorVariant::Supernodal]
            };
            for &variant in variants {
                let nd =
                    SymbolicFactor::analyze_with(a.pattern(), variant, Ordering::NestedDissection)
                        .unwrap();
                assert_eq!(nd.variant(), variant);
                let diff = relative_difference(&solve_ldlt(&nd, a), &reference);
                assert!(diff < 1e-12, "n = {}, {variant:?}: {diff:e}", a.nrows());
            }
            let nd = SymbolicFactor::analyze(a.pattern()).unwrap();
            let fwd = crate::linalg::ordering::nested_dissection(a.pattern()).unwrap();
            let order = |s: &SymbolicFactor| -> Vec<usize> {
                (0..a.nrows()).map(|k| s.permuted_to_caller(k)).collect()
            };
            if a.nrows() >= ND_THRESHOLD {
                assert_eq!(order(&nd), fwd);
                // On a 3-D mesh the correctly oriented ND ordering has less fill than AMD.
                assert!(nd.factor_nnz() < amd.factor_nnz());
                assert_eq!(nd.variant(), FactorVariant::Supernodal);
            } else {
                assert_eq!(order(&nd), order(&amd));
            }
        }
    }

    fn solve_rhs(n: usize) -> Vec<f64> {
        (0..n).map(|i| (i as f64).sin() + 1.0).collect()
    }

    #[test]
    fn llt_and_ldlt_solve_fixed_chain() {
        let k = chain(50, true, true, None);
        let b: Vec<f64> = (0..50).map(|i| (i as f64).sin()).collect();
        for variant in VARIANTS {
            let sym = SymbolicFactor::analyze_with(k.pattern(), variant, Ordering::Auto).unwrap();
            for factor in [
                sym.factor_llt(&k, Par::Seq).unwrap(),
                sym.factor_ldlt(&k, Par::Seq).unwrap(),
            ] {
                let mut x = b.clone();
                factor.solve_in_place(&mut x).unwrap();
                assert!(
                    residual(&k, &x, &b) < 1e-10,
                    "{variant:?} {:?}",
                    factor.kind()
                );
                assert_eq!(
                    factor.inertia(),
                    Inertia {
                        negative: 0,
                        zero: 0,
                        positive: 50
                    }
                );
            }
        }
    }

    #[test]
    fn multi_rhs_solve_matches_single() {
        let k = chain(30, true, false, None);
        let sym = SymbolicFactor::analyze(k.pattern()).unwrap();
        let f = sym.factor_ldlt(&k, Par::Seq).unwrap();
        let mut rhs = faer::Mat::<f64>::from_fn(30, 3, |i, j| (i * (j + 1)) as f64);
        let mut scratch = f.solve_scratch(3).unwrap();
        f.solve_in_place_with_scratch(rhs.as_mut(), &mut scratch)
            .unwrap();
        for j in 0..3 {
            let mut x: Vec<f64> = (0..30).map(|i| (i * (j + 1)) as f64).collect();
            f.solve_in_place(&mut x).unwrap();
            for i in 0..30 {
                assert!((x[i] - rhs[(i, j)]).abs() < 1e-12 * x[i].abs().max(1.0));
            }
        }
        let mut too_many = faer::Mat::<f64>::zeros(30, 4);
        assert_eq!(
            f.solve_in_place_with_scratch(too_many.as_mut(), &mut scratch)
                .unwrap_err(),
            LinalgError::DimensionMismatch {
                expected: 3,
                got: 4
            }
        );
    }

    /// A chain grounded at the left with the spring between DOF 29 and 30 removed: DOFs 30..50
    /// float freely. LLᵀ must report a DOF of the floating part, in caller numbering, for
    /// both faer variants (their raw indices differ by one).
    #[test]
    fn llt_reports_mechanism_dof() {
        let k = chain(50, true, false, Some(30));
        for (variant, ordering) in combinations() {
            let sym = SymbolicFactor::analyze_with(k.pattern(), variant, ordering).unwrap();
            match sym.factor_llt(&k, Par::Seq) {
                Err(LinalgError::NotPositiveDefinite { index, ratio }) => {
                    assert!(
                        (30..50).contains(&index),
                        "{variant:?} {ordering:?}: index {index}"
                    );
                    assert!(ratio > DEFAULT_MAX_RATIO);
                }
                other => panic!("{variant:?} {ordering:?}: {other:?}"),
            }
        }
    }

    /// A DOF with no stiffness at all (zero row and column): the failing index is exactly it.
    #[test]
    fn zero_dof_is_located_exactly() {
        let mut coo = CooMatrix::new(5, 5);
        for i in 0..5 {
            coo.push(i, i, if i == 3 { 0.0 } else { 2.0 });
        }
        coo.push(0, 1, -1.0);
        coo.push(1, 0, -1.0);
        let a = CscMatrix::from(&coo);
        for (variant, ordering) in combinations() {
            let sym = SymbolicFactor::analyze_with(a.pattern(), variant, ordering).unwrap();
            assert!(matches!(
                sym.factor_llt(&a, Par::Seq),
                Err(LinalgError::NotPositiveDefinite { index: 3, .. })
            ));
            assert_eq!(
                sym.factor_ldlt(&a, Par::Seq).unwrap_err(),
                LinalgError::Singular { index: 3 }
            );
        }
    }

    /// A pivot within `ZERO_PIVOT_TOL` of its diagonal counts as zero, a negative one as
    /// negative: [[1, 1, 0], [1, 1 + ε, 0], [0, 0, −2]] has the pivots 1, ε and −2 in the
    /// natural order (ε = 1e-14 ≤ 1e-12·(1 + ε)), whatever order the factorization takes, since
    /// the inertia of a matrix does not depend on it (Sylvester) and ε is far below the
    /// tolerance in any order.
    #[test]
    fn ldlt_inertia_counts_near_zero_and_negative_pivots() {
        let mut coo = CooMatrix::new(3, 3);
        for (i, j, v) in [
            (0, 0, 1.0),
            (0, 1, 1.0),
            (1, 0, 1.0),
            (1, 1, 1.0 + 1e-14),
            (2, 2, -2.0),
        ] {
            coo.push(i, j, v);
        }
        let a = CscMatrix::from(&coo);
        for variant in VARIANTS {
            let sym = SymbolicFactor::analyze_with(a.pattern(), variant, Ordering::Auto).unwrap();
            let inertia = sym.factor_ldlt(&a, Par::Seq).unwrap().inertia();
            assert_eq!(
                inertia,
                Inertia {
                    negative: 1,
                    zero: 1,
                    positive: 1
                },
                "{variant:?}"
            );
        }
    }

    /// Inertia of a diagonal-shifted chain equals the count of analytic eigenvalues below
    /// the shift: fixed–fixed unit chain, λ_k = 4 sin²(kπ / (2(n+1))).
    #[test]
    fn ldlt_inertia_counts_eigenvalues_below_shift() {
        let n = 40;
        let k = chain(n, true, true, None);
        let lambda = |j: usize| {
            4.0 * (j as f64 * std::f64::consts::PI / (2.0 * (n + 1) as f64))
                .sin()
                .powi(2)
        };
        for variant in VARIANTS {
            let sym = SymbolicFactor::analyze_with(k.pattern(), variant, Ordering::Auto).unwrap();
            for shift in [0.05, 0.5, 1.7, 3.3] {
                let mut shifted = k.clone();
                for (i, j, v) in shifted.triplet_iter_mut() {
                    if i == j {
                        *v -= shift;
                    }
                }
                let inertia = sym.factor_ldlt(&shifted, Par::Seq).unwrap().inertia();
                let below = (1..=n).filter(|&j| lambda(j) < shift).count();
                assert_eq!(
                    inertia,
                    Inertia {
                        negative: below,
                        zero: 0,
                        positive: n - below
                    }
                );
            }
        }
    }

    #[test]
    fn pattern_errors_are_typed() {
        let k = chain(10, true, true, None);
        let sym = SymbolicFactor::analyze(k.pattern()).unwrap();
        let other = chain(11, true, true, None);
        assert!(matches!(
            sym.factor_llt(&other, Par::Seq),
            Err(LinalgError::PatternMismatch { .. })
        ));
        let mut coo = CooMatrix::new(3, 3);
        coo.push(0, 0, 1.0);
        coo.push(2, 0, 1.0);
        let unsym = CscMatrix::from(&coo);
        assert_eq!(
            SymbolicFactor::analyze(unsym.pattern()).unwrap_err(),
            LinalgError::PatternNotSymmetric { row: 2, col: 0 }
        );
    }

    /// A matrix whose columns hold as many entries as the analysed pattern's, in other rows,
    /// is refused: the column offsets alone do not identify a pattern.
    #[test]
    fn same_column_counts_in_other_rows_are_a_pattern_mismatch() {
        let full = |entries: &[(usize, usize)]| {
            let mut coo = CooMatrix::new(3, 3);
            for &(i, j) in entries {
                coo.push(i, j, if i == j { 4.0 } else { 1.0 });
            }
            CscMatrix::from(&coo)
        };
        let a = full(&[(0, 0), (1, 0), (0, 1), (1, 1), (2, 2)]);
        let b = full(&[(0, 0), (2, 0), (1, 1), (2, 1), (2, 2)]);
        let sym = SymbolicFactor::analyze(a.pattern()).unwrap();
        assert_eq!(a.col_offsets(), b.col_offsets());
        assert_ne!(a.row_indices(), b.row_indices());
        assert!(matches!(
            sym.factor_llt(&b, Par::Seq),
            Err(LinalgError::PatternMismatch { .. })
        ));
    }

    /// The reported pivot ratio is a_kk / l_kk²: for [[4, 2], [2, 2]], L = [[2, 0], [1, 1]], the
    /// ratios are 4/4 and 2/1, so the worst is 2 at the second row.
    #[test]
    fn pivot_ratio_is_the_diagonal_over_the_squared_pivot() {
        let mut coo = CooMatrix::new(2, 2);
        for (i, j, v) in [(0, 0, 4.0), (1, 0, 2.0), (0, 1, 2.0), (1, 1, 2.0)] {
            coo.push(i, j, v);
        }
        let a = CscMatrix::from(&coo);
        let sym = SymbolicFactor::analyze(a.pattern()).unwrap();
        let worst = sym.factor_llt(&a, Par::Seq).unwrap().max_pivot_ratio();
        assert!((worst.ratio - 2.0).abs() < 1e-14, "{worst:?}");
        assert_eq!(worst.index, 1);
        // MAXRATIO refuses a ratio above it, not one equal to it (2 is exact here: L has
        // integer entries)
        let at = sym.clone().with_max_ratio(2.0).factor_llt(&a, Par::Seq);
        assert!(at.is_ok(), "{:?}", at.err());
        assert!(matches!(
            sym.clone().with_max_ratio(1.999).factor_llt(&a, Par::Seq),
            Err(LinalgError::NotPositiveDefinite { index: 1, ratio }) if ratio == 2.0
        ));
    }

    /// LDLᵀ reports the largest |a_kk / d_k| and its DOF: [[4, 2], [2, 2]] has d = (4, 1), ratios
    /// 1 and 2; the indefinite [[4, 2], [2, −2]] has d = (4, −3), ratios 1 and 2/3 (the first
    /// row is the worst).
    #[test]
    fn ldlt_pivot_ratio_is_the_largest_diagonal_over_pivot() {
        for (a11, ratio, index) in [(2.0, 2.0, 1), (-2.0, 1.0, 0)] {
            let mut coo = CooMatrix::new(2, 2);
            for (i, j, v) in [(0, 0, 4.0), (1, 0, 2.0), (0, 1, 2.0), (1, 1, a11)] {
                coo.push(i, j, v);
            }
            let a = CscMatrix::from(&coo);
            let sym = SymbolicFactor::analyze(a.pattern()).unwrap();
            assert_eq!(
                sym.permuted_to_caller(0),
                0,
                "the ratios above assume row 0 first"
            );
            let worst = sym.factor_ldlt(&a, Par::Seq).unwrap().max_pivot_ratio();
            assert!(
                (worst.ratio - ratio).abs() < 1e-14,
                "a11 = {a11}: {worst:?}"
            );
            assert_eq!(worst.index, index, "a11 = {a11}");
        }
    }

    /// One symbolic object, factors of K and K − σM computed in parallel threads, equal to the
    /// factors of fresh analyses.
    #[test]
    fn symbolic_reuse_matches_fresh_factorization() {
        let k = chain(60, true, true, None);
        let sigma = 0.3;
        let mut shifted = k.clone();
        for (i, j, v) in shifted.triplet_iter_mut() {
            if i == j {
                *v -= sigma;
            }
        }
        let sym = SymbolicFactor::analyze(k.pattern()).unwrap();
        let b: Vec<f64> = (0..60).map(|i| 1.0 + i as f64).collect();
        let solve = |f: &Factor| {
            let mut x = b.clone();
            f.solve_in_place(&mut x).unwrap();
            x
        };
        let (shared_k, shared_s) = std::thread::scope(|s| {
            let a = s.spawn(|| solve(&sym.factor_ldlt(&k, Par::Seq).unwrap()));
            let c = s.spawn(|| solve(&sym.factor_ldlt(&shifted, Par::Seq).unwrap()));
            (a.join().unwrap(), c.join().unwrap())
        });
        let fresh = |a: &CscMatrix<f64>| {
            solve(
                &SymbolicFactor::analyze(a.pattern())
                    .unwrap()
                    .factor_ldlt(a, Par::Seq)
                    .unwrap(),
            )
        };
        assert_eq!(shared_k, fresh(&k));
        assert_eq!(shared_s, fresh(&shifted));
        fn send_sync<T: Send + Sync>() {}
        send_sync::<SymbolicFactor>();
        send_sync::<Factor>();
    }
}
