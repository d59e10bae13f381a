//! Assembly of affine element contributions into operators that share one pattern.
//!
//! An element contributes `K_e(p) = Σ_i f_i(p) K_e^i` (DESIGN.md §5). Scattering every part
//! into its own value array on the common pattern ([`pattern`](super::pattern)) gives
//!
//! ```text
//! K(p) = Σ_i f_i(p) K_i,   K_i = Σ_e Aᵀ_e K_e^i A_e   (same col_offsets / row_indices for all i)
//! ```
//!
//! so evaluating K(p) is a sum of value arrays, allocation-free with
//! [`AffineOperator::evaluate_into`]. Each part is identified by a [`ParamKey`]: the constant
//! term, or a (parametrized entity, coefficient function) pair; a pROM build iterates
//! [`AffineOperator::parts`].

use std::sync::Arc;

use faer::Mat;
use nalgebra_sparse::CscMatrix;
use nalgebra_sparse::pattern::SparsityPattern;
use rayon::prelude::*;

use super::dofs::DofMap;
use super::error::AssemblyError;
use super::frames::GridFrames;
use super::pattern::entry_position;
use crate::fe::affine::{AffineMatrix, Coefficient};

/// The model entity a `PMPAR` acts on (its REFID, by KIND): the coefficient functions of the
/// elements that use it become affine parts of their own.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum ParamTarget {
    /// A MAT1 (KIND = E, RHO, NU).
    Material(u32),
    /// A PCOMP (KIND = THETA, TPLY).
    Pcomp(u32),
    /// A PELAS (KIND = K).
    Pelas(u32),
    /// A CONM2 element (KIND = MASS).
    Conm2(u32),
}

/// Identifies one affine part: the constant term or one coefficient function of a
/// parametrized entity (which may depend on several parameters of it, e.g. λ(E, ν)).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ParamKey {
    /// f = 1: everything not parametrized (and parametrized terms frozen at nominal values).
    Constant,
    /// The coefficient function `function` of the parameters acting on `target`.
    Param {
        target: ParamTarget,
        function: Coefficient,
    },
}

/// How the wiring layer binds one element coefficient: to a parametrized entity, or frozen at a
/// value (e.g. E of a material no PMPAR varies) and folded into the constant term.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Binding {
    /// The coefficient varies with the parameters of this entity.
    Param(ParamTarget),
    /// The coefficient is fixed at this value.
    Fixed(f64),
}

/// One element's contribution: its g-set DOFs and its affine parts (global frames).
#[derive(Debug, Clone)]
pub struct Contribution {
    /// g indices of the rows/columns of every part.
    pub dofs: Vec<usize>,
    /// Parts; every matrix is `dofs.len()` square.
    pub parts: Vec<(ParamKey, Mat<f64>)>,
}

impl Contribution {
    /// A constant matrix on explicit DOFs (springs, test elements).
    pub fn constant(dofs: Vec<usize>, matrix: Mat<f64>) -> Self {
        Contribution {
            dofs,
            parts: vec![(ParamKey::Constant, matrix)],
        }
    }

    /// An element of `nodes` (grid indices) whose parts are matrices in basic, grid-major, of
    /// size 6·nodes (all six components of each grid) or 3·nodes (translations only: solids,
    /// which then add no rotational entries to the pattern); rotated to the global frames.
    pub fn element(frames: &GridFrames, nodes: &[usize], parts: Vec<(ParamKey, Mat<f64>)>) -> Self {
        let size = parts.first().map_or(6 * nodes.len(), |(_, m)| m.nrows());
        let per_node = if size == 3 * nodes.len() && !nodes.is_empty() {
            3
        } else {
            6
        };
        let dofs = nodes
            .iter()
            .flat_map(|&a| DofMap::grid_dofs(a).take(per_node))
            .collect();
        let parts = parts
            .into_iter()
            .map(|(key, mut m)| {
                frames.rotate_element(nodes, per_node, &mut m);
                (key, m)
            })
            .collect();
        Contribution { dofs, parts }
    }

    /// An element from the `fe` affine matrix: each coefficient is bound by `bind` to a PMPAR
    /// parameter or frozen (and folded into the constant part).
    pub fn from_affine(
        frames: &GridFrames,
        nodes: &[usize],
        matrix: &AffineMatrix,
        bind: impl Fn(Coefficient) -> Binding,
    ) -> Self {
        let mut parts: Vec<(ParamKey, Mat<f64>)> = Vec::new();
        for (c, m) in &matrix.parts {
            let (key, scale) = match (*c, bind(*c)) {
                (Coefficient::Constant, _) => (ParamKey::Constant, 1.0),
                (_, Binding::Fixed(v)) => (ParamKey::Constant, v),
                (function, Binding::Param(target)) => (ParamKey::Param { target, function }, 1.0),
            };
            let scaled = m * faer::Scale(scale);
            match parts.iter_mut().find(|(k, _)| *k == key) {
                Some((_, acc)) => *acc += &scaled,
                None => parts.push((key, scaled)),
            }
        }
        Contribution::element(frames, nodes, parts)
    }
}

/// Affine parts of one global operator on one shared pattern.
#[derive(Debug, Clone)]
pub struct AffineOperator {
    pattern: Arc<SparsityPattern>,
    nrows: usize,
    parts: Vec<(ParamKey, Vec<f64>)>,
}

impl AffineOperator {
    /// Operator from a pattern and parts (each value array of length nnz).
    pub fn from_parts(
        pattern: Arc<SparsityPattern>,
        parts: Vec<(ParamKey, Vec<f64>)>,
    ) -> Result<Self, AssemblyError> {
        for (_, v) in &parts {
            super::dofs::check_len("affine part values", pattern.nnz(), v.len())?;
        }
        Ok(AffineOperator {
            nrows: pattern.minor_dim(),
            pattern,
            parts,
        })
    }

    /// Scatter every contribution's parts into value arrays on `pattern` (square, g × g).
    /// The constant part is always present (first); the others follow in first-seen order.
    /// With `parallel`, contributions are split into one chunk per rayon thread, each summed
    /// into its own buffers (memory: threads × parts × nnz).
    pub fn assemble(
        pattern: Arc<SparsityPattern>,
        contributions: &[Contribution],
        parallel: bool,
    ) -> Result<Self, AssemblyError> {
        let mut keys: Vec<ParamKey> = vec![ParamKey::Constant];
        for c in contributions {
            for (k, _) in &c.parts {
                if !keys.contains(k) {
                    keys.push(*k);
                }
            }
        }
        let nnz = pattern.nnz();
        let scatter_chunk = |chunk: &[Contribution]| -> Result<Vec<Vec<f64>>, AssemblyError> {
            let mut values = vec![vec![0.0; nnz]; keys.len()];
            for c in chunk {
                scatter(&pattern, c, &keys, &mut values)?;
            }
            Ok(values)
        };
        let values = if parallel && contributions.len() > 1 {
            let chunk = contributions
                .len()
                .div_ceil(rayon::current_num_threads().max(1));
            let partial: Vec<Vec<Vec<f64>>> = contributions
                .par_chunks(chunk.max(1))
                .map(scatter_chunk)
                .collect::<Result<_, _>>()?;
            let mut iter = partial.into_iter();
            let mut total = iter
                .next()
                .unwrap_or_else(|| vec![vec![0.0; nnz]; keys.len()]);
            for p in iter {
                for (t, v) in total.iter_mut().zip(p) {
                    t.iter_mut().zip(v).for_each(|(a, b)| *a += b);
                }
            }
            total
        } else {
            scatter_chunk(contributions)?
        };
        AffineOperator::from_parts(pattern, keys.into_iter().zip(values).collect())
    }

    /// The shared pattern (CSC: major = columns).
    pub fn pattern(&self) -> &Arc<SparsityPattern> {
        &self.pattern
    }

    /// Rows.
    pub fn nrows(&self) -> usize {
        self.nrows
    }

    /// Columns.
    pub fn ncols(&self) -> usize {
        self.pattern.major_dim()
    }

    /// The parts: (key, values on the pattern).
    pub fn parts(&self) -> &[(ParamKey, Vec<f64>)] {
        &self.parts
    }

    /// The keys in part order (the order of the weights of [`AffineOperator::evaluate_into`]).
    pub fn keys(&self) -> Vec<ParamKey> {
        self.parts.iter().map(|(k, _)| *k).collect()
    }

    /// Values of one part.
    pub fn part(&self, key: ParamKey) -> Option<&[f64]> {
        self.parts
            .iter()
            .find(|(k, _)| *k == key)
            .map(|(_, v)| v.as_slice())
    }

    /// out = Σ_i weights\[i\] · values_i (no allocation).
    pub fn evaluate_into(&self, weights: &[f64], out: &mut [f64]) -> Result<(), AssemblyError> {
        super::dofs::check_len("weights (one per part)", self.parts.len(), weights.len())?;
        super::dofs::check_len("output values", self.pattern.nnz(), out.len())?;
        out.fill(0.0);
        for ((_, v), &w) in self.parts.iter().zip(weights) {
            if w != 0.0 {
                out.iter_mut().zip(v).for_each(|(o, x)| *o += w * x);
            }
        }
        Ok(())
    }

    /// The weights of the parts from a function of the key (1 for the constant term is the
    /// caller's choice; usually `|k| if k == Constant { 1.0 } else { f_k(p) }`).
    pub fn weights(&self, f: impl Fn(ParamKey) -> f64) -> Vec<f64> {
        self.parts.iter().map(|(k, _)| f(*k)).collect()
    }

    /// K(p) as a CSC matrix (copies the pattern; use [`AffineOperator::evaluate_into`] in loops).
    pub fn evaluate(&self, weights: &[f64]) -> Result<CscMatrix<f64>, AssemblyError> {
        let mut values = vec![0.0; self.pattern.nnz()];
        self.evaluate_into(weights, &mut values)?;
        self.matrix(values)
    }

    /// A CSC matrix of this operator's pattern with the given values.
    pub fn matrix(&self, values: Vec<f64>) -> Result<CscMatrix<f64>, AssemblyError> {
        super::dofs::check_len("values for the pattern", self.pattern.nnz(), values.len())?;
        CscMatrix::try_from_pattern_and_values((*self.pattern).clone(), values).map_err(|_| {
            AssemblyError::PatternMismatch {
                what: "internal: pattern rejected by CscMatrix",
            }
        })
    }

    /// y = A x for values on this operator's pattern.
    pub fn mul_values(&self, values: &[f64], x: &[f64]) -> Result<Vec<f64>, AssemblyError> {
        super::dofs::check_len("values", self.pattern.nnz(), values.len())?;
        super::dofs::check_len("vector x", self.ncols(), x.len())?;
        let mut y = vec![0.0; self.nrows];
        let (offsets, rows) = (self.pattern.major_offsets(), self.pattern.minor_indices());
        for (j, &xj) in x.iter().enumerate() {
            if xj == 0.0 {
                continue;
            }
            for k in offsets[j]..offsets[j + 1] {
                y[rows[k]] += values[k] * xj;
            }
        }
        Ok(y)
    }

    /// Diagonal of values on this (square) operator's pattern (0 where not stored).
    pub fn diagonal(&self, values: &[f64]) -> Vec<f64> {
        (0..self.ncols().min(self.nrows))
            .map(|j| {
                entry_position(&self.pattern, j, j)
                    .and_then(|k| values.get(k))
                    .copied()
                    .unwrap_or(0.0)
            })
            .collect()
    }
}

/// Add one contribution's parts into the value arrays (one per key).
fn scatter(
    pattern: &SparsityPattern,
    c: &Contribution,
    keys: &[ParamKey],
    values: &mut [Vec<f64>],
) -> Result<(), AssemblyError> {
    let n = c.dofs.len();
    let size = pattern.major_dim();
    if let Some(&d) = c.dofs.iter().find(|&&d| d >= size) {
        return Err(AssemblyError::DofOutOfRange { index: d, size });
    }
    for (key, m) in &c.parts {
        if m.nrows() != n || m.ncols() != n {
            return Err(AssemblyError::SizeMismatch {
                what: "element matrix size (DOF list length)",
                expected: n,
                found: m.nrows(),
            });
        }
        let Some(slot) = keys.iter().position(|k| k == key) else {
            continue;
        };
        let target = &mut values[slot];
        for (j, &col) in c.dofs.iter().enumerate() {
            for (i, &row) in c.dofs.iter().enumerate() {
                let v = m[(i, j)];
                if v == 0.0 {
                    continue;
                }
                let k =
                    entry_position(pattern, row, col).ok_or(AssemblyError::PatternMismatch {
                        what: "element entry outside the pattern",
                    })?;
                target[k] += v;
            }
        }
    }
    Ok(())
}
