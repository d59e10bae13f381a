//! The pROM's matrices in the coordinates the filter runs in ([`super::filter`]): what the
//! prediction (eq. 8.22), its Jacobian (eq. 8.16–8.20, 8.33), the covariance propagation
//! (eq. 8.24) and the measurement rows (eq. 8.37–8.39) need, written once as
//! [`PromCoordinates`] and implemented by the physical ([`super::physical`]) and the modal
//! ([`super::modal_coordinates`]) coordinates.

use faer::Mat;
use faer::dyn_stack::MemBuffer;

use super::filter::Prediction;
use super::modal_coordinates::Modal;
use super::physical::Physical;
use crate::dynamics::velocity_form::{Operator, VelocityForm};
use crate::rom::prom::Prom;

/// Why an evaluation of the model failed.
pub(super) enum Refused {
    Prom(String),
    NotDefinite(&'static str),
}

/// The pROM's M, C, K, S = M + h C + h² K (h of [`Prediction::effective_step`]) and the q̇ block
/// row J̃_v of the transition in one system of coordinates.
pub(super) trait PromCoordinates {
    /// Evaluate at `params` and factor S = M + h C + h² K and M (`first`: M was never factored).
    fn evaluate(
        &mut self,
        prom: &Prom,
        params: &[f64],
        unknown: &[usize],
        h: f64,
        first: bool,
        mem: &mut MemBuffer,
    ) -> Result<(), Refused>;
    /// out += scale · A x for A = M, C or K.
    fn mul(&self, op: Operator, x: &[f64], out: &mut [f64], scale: f64);
    /// x ← S⁻¹ x (`effective`) or M⁻¹ x.
    fn solve(&mut self, effective: bool, x: &mut [f64]);
    /// D (n × n_p) from w_k = q + β q̇ and w_m = q̈ + α q̇ (see
    /// [`super::physical::parameter_columns`]).
    fn parameter_columns(&self, params: &[usize], w_k: &[f64], w_m: &[f64], d: &mut Mat<f64>);
    /// J̃_v = S⁻¹ [−Δt K, V, Δt S_un, −Δt D] (eq. 8.16–8.20, 8.33) with V = M (BDF1) or
    /// M − h C + h² K (trapezoidal: J_v = S⁻¹ [−Δt K, 2M − S, Δt S_un, −Δt D̄] minus Δt/2 times
    /// its q columns in the q̇ columns, J_v A⁻¹ of [`super::propagation`]).
    fn set_transition(&mut self, dt: f64, prediction: Prediction, s_un: &Mat<f64>, d: &Mat<f64>);
    /// J̃_v as a dense n × N matrix.
    fn transition_rows(&self, n: usize, big_n: usize) -> Mat<f64>;
}

/// The coordinates of a filter, chosen at construction ([`super::Coordinates`]). One value per
/// filter, used in every step: the physical variant stays inline to avoid a pointer chase.
#[allow(clippy::large_enum_variant)]
pub(super) enum Model {
    Physical(Physical),
    Modal(Box<Modal>),
}

impl PromCoordinates for Model {
    fn evaluate(
        &mut self,
        prom: &Prom,
        params: &[f64],
        unknown: &[usize],
        h: f64,
        first: bool,
        mem: &mut MemBuffer,
    ) -> Result<(), Refused> {
        match self {
            Model::Physical(ph) => ph.evaluate(prom, params, unknown, h, first, mem),
            Model::Modal(md) => md.evaluate(prom, params, unknown, h, first, mem),
        }
    }
    #[inline(always)]
    fn mul(&self, op: Operator, x: &[f64], out: &mut [f64], scale: f64) {
        match self {
            Model::Physical(ph) => ph.mul(op, x, out, scale),
            Model::Modal(md) => md.mul(op, x, out, scale),
        }
    }
    #[inline(always)]
    fn solve(&mut self, effective: bool, x: &mut [f64]) {
        match self {
            Model::Physical(ph) => ph.solve(effective, x),
            Model::Modal(md) => md.solve(effective, x),
        }
    }
    fn parameter_columns(&self, params: &[usize], w_k: &[f64], w_m: &[f64], d: &mut Mat<f64>) {
        match self {
            Model::Physical(ph) => ph.parameter_columns(params, w_k, w_m, d),
            Model::Modal(md) => md.parameter_columns(params, w_k, w_m, d),
        }
    }
    fn set_transition(&mut self, dt: f64, prediction: Prediction, s_un: &Mat<f64>, d: &Mat<f64>) {
        match self {
            Model::Physical(ph) => ph.set_transition(dt, prediction, s_un, d),
            Model::Modal(md) => md.set_transition(dt, prediction, s_un, d),
        }
    }
    fn transition_rows(&self, n: usize, big_n: usize) -> Mat<f64> {
        match self {
            Model::Physical(ph) => ph.transition_rows(n, big_n),
            Model::Modal(md) => md.transition_rows(n, big_n),
        }
    }
}

/// The prediction's step (eq. 8.22) runs on the model's products and its factored S.
impl VelocityForm for Model {
    #[inline(always)]
    fn add_product(&self, op: Operator, x: &[f64], out: &mut [f64], scale: f64) {
        self.mul(op, x, out, scale);
    }
    #[inline(always)]
    fn solve_effective(&mut self, x: &mut [f64]) {
        self.solve(true, x);
    }
}
