//! The filter's physical coordinates: the pROM's reduced coordinates q with its dense matrices
//! at the current estimate, S and M factored in place ([`super::filter`]).

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::matmul::matmul;
use faer::{Accum, Mat, MatMut, Par};

use super::coordinates::{PromCoordinates, Refused};
use super::filter::Prediction;
use super::kernels::{column, dot, factor_in_place, solve_seq};
use crate::dynamics::velocity_form::Operator;
use crate::rom::prom::{Prom, PromEvaluation};

/// The pROM's dense matrices.
pub(super) struct Physical {
    pub(super) at: PromEvaluation,
    /// Lower Cholesky factors of S = M + h C + h² K and of M at the current parameters.
    pub(super) s_factor: Mat<f64>,
    pub(super) m_factor: Mat<f64>,
    /// The M that `m_factor` factors (refactored only when the estimate changes M).
    pub(super) factored_mass: Mat<f64>,
    /// J̃_v (n × N).
    pub(super) jv: Mat<f64>,
}

impl PromCoordinates for Physical {
    /// Evaluate at `params` and factor S = M + h C + h² K and M (`first`: M was never factored).
    fn evaluate(
        &mut self,
        prom: &Prom,
        params: &[f64],
        _: &[usize],
        h: f64,
        first: bool,
        mem: &mut MemBuffer,
    ) -> Result<(), Refused> {
        prom.evaluate(params, &mut self.at)
            .map_err(|e| Refused::Prom(e.to_string()))?;
        let at = &self.at;
        for c in 0..at.mass().ncols() {
            let (m, cd, k) = (
                column(at.mass(), c),
                column(at.damping(), c),
                column(at.stiffness(), c),
            );
            let s = self.s_factor.col_as_slice_mut(c);
            s.iter_mut()
                .zip(m.iter().zip(cd.iter().zip(k)))
                .for_each(|(s, (m, (cd, k)))| *s = m + h * cd + h * h * k);
        }
        if !factor_in_place(self.s_factor.as_mut(), MemStack::new(mem)) {
            return Err(Refused::NotDefinite(
                "the step matrix S = M + h C + h² K (h = Δt for BDF1, Δt/2 for TRAP)",
            ));
        }
        let m_ok = (!first && self.factored_mass == at.mass()) || {
            self.factored_mass.copy_from(at.mass());
            self.m_factor.copy_from(at.mass());
            factor_in_place(self.m_factor.as_mut(), MemStack::new(mem))
        };
        if !m_ok {
            return Err(Refused::NotDefinite("M"));
        }
        Ok(())
    }

    /// out += scale · A x (A symmetric: entries as dot products with its columns).
    fn mul(&self, op: Operator, x: &[f64], out: &mut [f64], scale: f64) {
        let a = match op {
            Operator::Stiffness => self.at.stiffness(),
            Operator::Damping => self.at.damping(),
            Operator::Mass => self.at.mass(),
        };
        out.iter_mut()
            .enumerate()
            .for_each(|(c, o)| *o += scale * dot(column(a, c), x));
    }

    /// x ← S⁻¹ x (`effective`) or M⁻¹ x.
    fn solve(&mut self, effective: bool, x: &mut [f64]) {
        let n = x.len();
        solve_seq(
            if effective {
                self.s_factor.as_ref()
            } else {
                self.m_factor.as_ref()
            },
            MatMut::from_column_major_slice_mut(x, n, 1),
        );
    }

    /// D (n × n_p) from w_k = q + β q̇ and w_m = q̈ + α q̇ (see [`parameter_columns`]).
    fn parameter_columns(&self, params: &[usize], w_k: &[f64], w_m: &[f64], d: &mut Mat<f64>) {
        parameter_columns_into(&self.at, params, w_k, w_m, d)
    }

    /// J̃_v = S⁻¹ [−Δt K, V, Δt S_un, −Δt D] (eq. 8.16–8.20, 8.33; V of
    /// [`PromCoordinates::set_transition`]).
    fn set_transition(&mut self, dt: f64, prediction: Prediction, s_un: &Mat<f64>, d: &Mat<f64>) {
        let (n, nu) = (s_un.nrows(), s_un.ncols());
        let h = prediction.effective_step(dt);
        for j in 0..self.jv.ncols() {
            let col = self.jv.col_as_slice_mut(j);
            if prediction == Prediction::Trapezoidal && (n..2 * n).contains(&j) {
                let at = &self.at;
                let (m, cd, k) = (
                    column(at.mass(), j - n),
                    column(at.damping(), j - n),
                    column(at.stiffness(), j - n),
                );
                col.iter_mut()
                    .zip(m.iter().zip(cd.iter().zip(k)))
                    .for_each(|(o, (m, (cd, k)))| *o = m - h * cd + h * h * k);
                continue;
            }
            let (src, scale) = match j {
                j if j < n => (column(self.at.stiffness(), j), -dt),
                j if j < 2 * n => (column(self.at.mass(), j - n), 1.0),
                j if j < 2 * n + nu => (s_un.col_as_slice(j - 2 * n), dt),
                j => (d.col_as_slice(j - 2 * n - nu), -dt),
            };
            col.iter_mut().zip(src).for_each(|(o, s)| *o = scale * s);
        }
        solve_seq(self.s_factor.as_ref(), self.jv.as_mut());
    }

    /// J̃_v as a dense n × N matrix.
    fn transition_rows(&self, _: usize, _: usize) -> Mat<f64> {
        self.jv.clone()
    }
}

impl Physical {
    /// Gᵀ = P J_vᵀ (N × n) and H = J_v P J_vᵀ = J_v Gᵀ (n × n), the two products [`super::propagation::propagate`]
    /// needs: two GEMMs, N² n + N n² multiply-adds.
    #[inline(always)]
    pub(super) fn transition_products(&self, p: &Mat<f64>, gt: &mut Mat<f64>, h: &mut Mat<f64>) {
        matmul(
            gt.as_mut(),
            Accum::Replace,
            p.as_ref(),
            self.jv.transpose(),
            1.0,
            Par::Seq,
        );
        matmul(
            h.as_mut(),
            Accum::Replace,
            self.jv.as_ref(),
            gt.as_ref(),
            1.0,
            Par::Seq,
        );
    }
}

/// D (n × n_p): D_j = ∂K/∂p_j (q + β q̇) + ∂M/∂p_j (q̈ + α q̇) = ∂K/∂p_j q + ∂C/∂p_j q̇ +
/// ∂M/∂p_j q̈ for the parameters `params`, so that ∂q̈/∂p_j = −M⁻¹ D_j (eq. 8.33–8.35 with
/// Rayleigh damping, derivatives of the affine pROM, eq. 8.19–8.20).
pub fn parameter_columns(
    at: &PromEvaluation,
    (alpha, beta): (f64, f64),
    params: &[usize],
    q: &[f64],
    v: &[f64],
    a: &[f64],
) -> Mat<f64> {
    let w_k: Vec<f64> = q.iter().zip(v).map(|(q, v)| q + beta * v).collect();
    let w_m: Vec<f64> = a.iter().zip(v).map(|(a, v)| a + alpha * v).collect();
    let mut d = Mat::zeros(q.len(), params.len());
    parameter_columns_into(at, params, &w_k, &w_m, &mut d);
    d
}

/// [`parameter_columns`] into `d` (n × n_p) from w_k = q + β q̇ and w_m = q̈ + α q̇.
fn parameter_columns_into(
    at: &PromEvaluation,
    params: &[usize],
    w_k: &[f64],
    w_m: &[f64],
    d: &mut Mat<f64>,
) {
    for (k, &j) in params.iter().enumerate() {
        let (dk, dm) = (at.d_stiffness(j), at.d_mass(j));
        let out = d.col_as_slice_mut(k);
        out.fill(0.0);
        for c in 0..w_k.len() {
            let (sk, sm) = (w_k[c], w_m[c]);
            out.iter_mut()
                .zip(column(dk, c).iter().zip(column(dm, c)))
                .for_each(|(o, (k, m))| *o += k * sk + m * sm);
        }
    }
}
