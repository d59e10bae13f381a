//! Set reductions on affine operators, each split into a symbolic plan (computed once per
//! pattern) and a numeric application (per affine part), after MYSTRAN's `REDUCE_KGG_TO_KNN`
//! and `REDUCE_KNN_TO_KFF`:
//!
//! ```text
//! g → n:  K_nn = Tᵀ K_gg T          (u_g = T u_n, RBE2 / RBE3 eliminated)
//! n → f:  K_ff = K_nn[f, f],  K_fs = K_nn[f, s]
//! ```
//!
//! K and M share the g pattern, so one [`GToN`] plan reduces every part of both; likewise one
//! [`Partition`] per (rows, columns) pair. All results keep one shared pattern per operator.

use std::sync::Arc;

use nalgebra_sparse::pattern::SparsityPattern;
use nalgebra_sparse::{CscMatrix, CsrMatrix};

use super::assemble::AffineOperator;
use super::dofs::{DofSet, check_len};
use super::error::AssemblyError;
use super::pattern::{entry_position, from_columns};

/// The symbolic plan of K_nn = Tᵀ K_gg T: for each g entry k, the n entries it adds to and the
/// factor T_ia T_jb.
#[derive(Debug, Clone)]
pub struct GToN {
    g_pattern: Arc<SparsityPattern>,
    n_pattern: Arc<SparsityPattern>,
    /// Offsets into `targets` per g entry.
    offsets: Vec<usize>,
    /// (n entry, factor).
    targets: Vec<(usize, f64)>,
}

impl GToN {
    /// Plan the reduction of operators on the square `g_pattern` by T (g × n).
    pub fn new(g_pattern: Arc<SparsityPattern>, t: &CsrMatrix<f64>) -> Result<Self, AssemblyError> {
        let g = g_pattern.major_dim();
        check_len("rows of T (g-set size)", g, t.nrows())?;
        let n = t.ncols();
        let t_row = |i: usize| {
            let row = t.row(i);
            row.col_indices()
                .iter()
                .copied()
                .zip(row.values().iter().copied())
                .collect::<Vec<_>>()
        };
        let rows_of_t: Vec<Vec<(usize, f64)>> = (0..g).map(t_row).collect();
        let (offs, minor) = (g_pattern.major_offsets(), g_pattern.minor_indices());
        let mut columns: Vec<Vec<usize>> = vec![Vec::new(); n];
        for j in 0..g {
            for &(b, _) in &rows_of_t[j] {
                for &i in &minor[offs[j]..offs[j + 1]] {
                    columns[b].extend(rows_of_t[i].iter().map(|&(a, _)| a));
                }
            }
        }
        for c in &mut columns {
            c.sort_unstable();
            c.dedup();
        }
        let n_pattern = from_columns(n, &columns)?;
        let mut offsets = Vec::with_capacity(g_pattern.nnz() + 1);
        let mut targets = Vec::with_capacity(g_pattern.nnz());
        offsets.push(0);
        for j in 0..g {
            for &i in &minor[offs[j]..offs[j + 1]] {
                for &(b, tb) in &rows_of_t[j] {
                    for &(a, ta) in &rows_of_t[i] {
                        let k = entry_position(&n_pattern, a, b).ok_or(
                            AssemblyError::PatternMismatch {
                                what: "internal: Tᵀ K T entry",
                            },
                        )?;
                        targets.push((k, ta * tb));
                    }
                }
                offsets.push(targets.len());
            }
        }
        Ok(GToN {
            g_pattern,
            n_pattern: Arc::new(n_pattern),
            offsets,
            targets,
        })
    }

    /// The pattern of every reduced operator.
    pub fn n_pattern(&self) -> &Arc<SparsityPattern> {
        &self.n_pattern
    }

    /// Tᵀ K T for one value array on the g pattern.
    pub fn apply_values(&self, g_values: &[f64]) -> Result<Vec<f64>, AssemblyError> {
        check_len("g values", self.g_pattern.nnz(), g_values.len())?;
        let mut out = vec![0.0; self.n_pattern.nnz()];
        for (k, &v) in g_values.iter().enumerate() {
            if v != 0.0 {
                for &(t, f) in &self.targets[self.offsets[k]..self.offsets[k + 1]] {
                    out[t] += f * v;
                }
            }
        }
        Ok(out)
    }

    /// Tᵀ K T for every part of an operator on the g pattern.
    pub fn apply(&self, op: &AffineOperator) -> Result<AffineOperator, AssemblyError> {
        if !Arc::ptr_eq(op.pattern(), &self.g_pattern) && **op.pattern() != *self.g_pattern {
            return Err(AssemblyError::PatternMismatch {
                what: "operator is not on the planned g pattern",
            });
        }
        let parts = op
            .parts()
            .iter()
            .map(|(k, v)| Ok((*k, self.apply_values(v)?)))
            .collect::<Result<Vec<_>, AssemblyError>>()?;
        AffineOperator::from_parts(self.n_pattern.clone(), parts)
    }
}

/// K_nn = Tᵀ K_gg T for one operator (plans and applies; reuse a [`GToN`] for K and M).
pub fn reduce_g_to_n(
    op: &AffineOperator,
    t: &CsrMatrix<f64>,
) -> Result<AffineOperator, AssemblyError> {
    GToN::new(op.pattern().clone(), t)?.apply(op)
}

/// The symbolic plan of a sub-matrix A\[rows, cols\] (rows and columns subsets of the parent).
#[derive(Debug, Clone)]
pub struct Partition {
    parent: Arc<SparsityPattern>,
    pattern: Arc<SparsityPattern>,
    /// Parent entry of each sub-matrix entry.
    source: Vec<usize>,
}

impl Partition {
    /// Plan A\[rows, cols\] of operators on `parent`.
    pub fn new(
        parent: Arc<SparsityPattern>,
        rows: &DofSet,
        cols: &DofSet,
    ) -> Result<Self, AssemblyError> {
        check_len(
            "row set parent size",
            parent.minor_dim(),
            rows.parent_size(),
        )?;
        check_len(
            "column set parent size",
            parent.major_dim(),
            cols.parent_size(),
        )?;
        let (offs, minor) = (parent.major_offsets(), parent.minor_indices());
        let mut columns: Vec<Vec<usize>> = Vec::with_capacity(cols.len());
        let mut source = Vec::new();
        for &j in cols.members() {
            let mut c = Vec::new();
            for (k, &i) in minor.iter().enumerate().take(offs[j + 1]).skip(offs[j]) {
                if let Some(r) = rows.position(i) {
                    c.push(r);
                    source.push(k);
                }
            }
            columns.push(c);
        }
        let pattern = Arc::new(from_columns(rows.len(), &columns)?);
        Ok(Partition {
            parent,
            pattern,
            source,
        })
    }

    /// The sub-matrix pattern.
    pub fn pattern(&self) -> &Arc<SparsityPattern> {
        &self.pattern
    }

    /// The sub-matrix of every part of `op`.
    pub fn apply(&self, op: &AffineOperator) -> Result<AffineOperator, AssemblyError> {
        if !Arc::ptr_eq(op.pattern(), &self.parent) && **op.pattern() != *self.parent {
            return Err(AssemblyError::PatternMismatch {
                what: "operator is not on the planned parent pattern",
            });
        }
        let parts = op
            .parts()
            .iter()
            .map(|(k, v)| (*k, self.source.iter().map(|&s| v[s]).collect()))
            .collect();
        AffineOperator::from_parts(self.pattern.clone(), parts)
    }
}

impl Partition {
    /// The sub-matrix of `op` evaluated at `weights` (one per part, [`AffineOperator::keys`]
    /// order): Σᵢ wᵢ Aᵢ\[rows, cols\] summed entry by entry in the order of
    /// [`AffineOperator::evaluate_into`], so it equals `self.apply(op)?.evaluate(weights)` bit
    /// for bit without the sub-matrices of the parts in between.
    pub fn evaluate(
        &self,
        op: &AffineOperator,
        weights: &[f64],
    ) -> Result<CscMatrix<f64>, AssemblyError> {
        if !Arc::ptr_eq(op.pattern(), &self.parent) && **op.pattern() != *self.parent {
            return Err(AssemblyError::PatternMismatch {
                what: "operator is not on the planned parent pattern",
            });
        }
        check_len("weights (one per part)", op.parts().len(), weights.len())?;
        let mut values = vec![0.0; self.source.len()];
        for ((_, part), &w) in op.parts().iter().zip(weights) {
            if w != 0.0 {
                for (v, &s) in values.iter_mut().zip(&self.source) {
                    *v += w * part[s];
                }
            }
        }
        CscMatrix::try_from_pattern_and_values((*self.pattern).clone(), values).map_err(|_| {
            AssemblyError::PatternMismatch {
                what: "internal: pattern rejected by CscMatrix",
            }
        })
    }
}

/// A\[rows, cols\] for one operator.
pub fn partition(
    op: &AffineOperator,
    rows: &DofSet,
    cols: &DofSet,
) -> Result<AffineOperator, AssemblyError> {
    Partition::new(op.pattern().clone(), rows, cols)?.apply(op)
}

/// K_ff = K_nn\[f, f\] (`f_in_n` from [`Sets`](super::dofs::Sets)).
pub fn reduce_n_to_f(
    op: &AffineOperator,
    f_in_n: &DofSet,
) -> Result<AffineOperator, AssemblyError> {
    partition(op, f_in_n, f_in_n)
}
