//! The full-model (f-set) [`Backend`] of the integrators: K_ff and M_ff on one sparse pattern,
//! Rayleigh damping C = αM + βK (eq. 2.23) plus, when given, a damping matrix D on the same
//! pattern (the elements' viscous and equivalent structural damping, PSD), so every
//! combination c_m M + c_c C + c_k K is (c_m + αc_c) M + (βc_c + c_k) K + c_c D on the same
//! pattern. The effective matrix is factored by the
//! crate's sparse Cholesky with one symbolic analysis: with M positive definite on the f-set and
//! K positive semi-definite, α, β ≥ 0, c_m > 0 and c_c, c_k ≥ 0 (true of BDF1, BDF2 and
//! generalized-α with ρ∞ ∈ [0, 1], whose c_k = 1 − α_f > 0), it is symmetric positive
//! definite. With massless f-set DOFs (M only semi-definite) it stays definite as long as K is
//! definite there; LLᵀ reports the DOF otherwise.

use faer::{MatMut, Par};
use nalgebra_sparse::CscMatrix;

use super::integrators::{Backend, Combination, IntegrationError};
use crate::linalg::{Factor, LinalgError, SolveScratch, SymbolicFactor};

/// K_ff, M_ff and Rayleigh α, β with the prepared operators.
pub struct SparseBackend<'a> {
    k: &'a CscMatrix<f64>,
    m: &'a CscMatrix<f64>,
    alpha: f64,
    beta: f64,
    /// Values of the extra damping matrix D on the pattern.
    extra: Option<Vec<f64>>,
    symbolic: SymbolicFactor,
    par: Par,
    factor: Option<(Factor, SolveScratch)>,
    /// Values of each prepared product on the shared pattern.
    products: Vec<Vec<f64>>,
    /// Number of numeric factorizations so far (reported with the run's timings).
    pub factorizations: usize,
}

impl<'a> SparseBackend<'a> {
    /// Analyse the shared pattern of K_ff and M_ff once.
    pub fn new(
        k: &'a CscMatrix<f64>,
        m: &'a CscMatrix<f64>,
        alpha: f64,
        beta: f64,
        par: Par,
    ) -> Result<Self, IntegrationError> {
        if k.pattern() != m.pattern() {
            return Err(IntegrationError::Backend(
                "K_ff and M_ff must share one sparsity pattern".into(),
            ));
        }
        let symbolic = SymbolicFactor::analyze(k.pattern())
            .map_err(|e| IntegrationError::Backend(e.to_string()))?;
        Ok(SparseBackend {
            k,
            m,
            alpha,
            beta,
            extra: None,
            symbolic,
            par,
            factor: None,
            products: Vec::new(),
            factorizations: 0,
        })
    }

    /// Adds the damping matrix Σ wᵢ Dᵢ of `terms` (each on K_ff's pattern) to C.
    pub fn with_damping(
        mut self,
        terms: &[(f64, &CscMatrix<f64>)],
    ) -> Result<Self, IntegrationError> {
        for &(w, d) in terms {
            if d.pattern() != self.k.pattern() {
                return Err(IntegrationError::Backend(
                    "the damping matrix must share K_ff's sparsity pattern".into(),
                ));
            }
            let extra = self.extra.get_or_insert_with(|| vec![0.0; d.nnz()]);
            extra
                .iter_mut()
                .zip(d.values())
                .for_each(|(e, v)| *e += w * v);
        }
        Ok(self)
    }

    /// Values of c_m M + c_c C + c_k K on the pattern.
    fn values(&self, c: Combination) -> Vec<f64> {
        let (wm, wk) = (c[0] + self.alpha * c[1], self.beta * c[1] + c[2]);
        let mut out: Vec<f64> = self
            .m
            .values()
            .iter()
            .zip(self.k.values())
            .map(|(m, k)| wm * m + wk * k)
            .collect();
        if let Some(d) = &self.extra {
            out.iter_mut().zip(d).for_each(|(o, d)| *o += c[1] * d);
        }
        out
    }
}

impl Backend for SparseBackend<'_> {
    fn size(&self) -> usize {
        self.k.nrows()
    }

    fn prepare(
        &mut self,
        effective: Combination,
        products: &[Combination],
        what: &'static str,
    ) -> Result<(), IntegrationError> {
        let factor = self
            .symbolic
            .factor_llt_values(&self.values(effective), self.par)
            .map_err(|e| match e {
                LinalgError::NotPositiveDefinite { .. } if what == "mass" => {
                    IntegrationError::Singular(what)
                }
                e => IntegrationError::Backend(format!("the {what} matrix: {e}")),
            })?;
        self.factorizations += 1;
        let scratch = factor
            .solve_scratch(1)
            .map_err(|e| IntegrationError::Backend(e.to_string()))?;
        self.factor = Some((factor, scratch));
        self.products = products.iter().map(|&c| self.values(c)).collect();
        Ok(())
    }

    fn apply(&self, j: usize, x: &[f64], y: &mut [f64]) {
        let (offsets, rows, values) = (
            self.k.col_offsets(),
            self.k.row_indices(),
            &self.products[j],
        );
        for (col, &xj) in x.iter().enumerate() {
            if xj != 0.0 {
                let range = offsets[col]..offsets[col + 1];
                rows[range.clone()]
                    .iter()
                    .zip(&values[range])
                    .for_each(|(&i, a)| y[i] += a * xj);
            }
        }
    }

    fn solve(&mut self, x: &mut [f64]) -> Result<(), IntegrationError> {
        let (factor, scratch) = self
            .factor
            .as_mut()
            .ok_or_else(|| IntegrationError::Backend("solve before prepare".into()))?;
        let n = x.len();
        factor
            .solve_in_place_with_scratch(MatMut::from_column_major_slice_mut(x, n, 1), scratch)
            .map_err(|e| IntegrationError::Backend(e.to_string()))
    }
}
