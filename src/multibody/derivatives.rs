//! The terms of the equations of motion (eq. 4.4) that carry the bodies' data, and their
//! derivatives with respect to a body's parameters, for the optimizer's sensitivities (thesis
//! ch. 5–6) and the parameter Jacobian of the AMANDA-EKF's state equation (ch. 9).
//!
//! Each term is linear in a body's data: M(q) (eq. 2.48, A.24–A.27) in the mass invariants and
//! M_ff, the quadratic velocity vector f_v (eq. 2.47, 4.9) and the gravity force in the
//! invariants, the elastic and damping forces K_ff q_f and C_ff q̇_f in K_ff and C_ff. A pROM
//! body's data are affine in p (eq. 3.31 for the matrices, eq. 4.1–4.3 and 4.8 for the
//! invariants: D(p) = Σᵢ fᵢ(p) Dⁱ), so ∂term/∂pⱼ is the same term evaluated with the body's data
//! replaced by ∂D/∂pⱼ = Σᵢ ∂fᵢ/∂pⱼ Dⁱ: exact, no differencing.

use faer::Mat;

use super::flexible::FlexibleBodyData;
use super::inertia;
use super::layout::BodySlice;
use super::system::{BodyId, System};

/// The data-carrying terms of the equations of motion at (q, q̇), in system coordinates:
/// M(q) q̈ = f_v + f_g − K q − C q̇ + (constraint and other applied forces).
#[derive(Debug, Clone, PartialEq)]
pub struct EomTerms {
    /// M(q) (n × n).
    pub mass: Mat<f64>,
    /// The quadratic velocity vector f_v(q, q̇) (eq. 2.47, 4.9).
    pub quadratic_velocity: Vec<f64>,
    /// The generalized gravity force f_g(q) = Σⱼ mⱼ Lⱼᵀ g.
    pub gravity: Vec<f64>,
    /// K_ff q_f in each flexible body's modal rows.
    pub elastic: Vec<f64>,
    /// C_ff q̇_f in each flexible body's modal rows.
    pub damping: Vec<f64>,
}

impl EomTerms {
    fn zeros(n: usize) -> Self {
        Self {
            mass: Mat::zeros(n, n),
            quadratic_velocity: vec![0.0; n],
            gravity: vec![0.0; n],
            elastic: vec![0.0; n],
            damping: vec![0.0; n],
        }
    }

    /// Adds the terms of one body with data `data` at slice `s` of (q, q̇).
    fn add_body(
        &mut self,
        data: &FlexibleBodyData,
        s: &BodySlice,
        g: [f64; 3],
        q: &[f64],
        v: &[f64],
    ) {
        let inv = &data.invariants;
        let (e, qf) = (s.euler_parameters(q), s.modal(q));
        let (e_dot, qf_dot) = (s.euler_parameters(v), s.modal(v));
        let mut block = Mat::zeros(s.len(), s.len());
        inertia::mass_matrix(inv, data.mass.as_ref(), &e, qf, block.as_mut());
        let mut local = vec![0.0; s.len()];
        for i in 0..s.len() {
            for j in 0..s.len() {
                self.mass[(s.offset + i, s.offset + j)] += block[(i, j)];
            }
        }
        inertia::quadratic_velocity(inv, &e, qf, &e_dot, qf_dot, &mut local);
        for (o, x) in self.quadratic_velocity[s.offset..].iter_mut().zip(&local) {
            *o += x;
        }
        inertia::gravity_force(inv, &e, qf, g, &mut local);
        for (o, x) in self.gravity[s.offset..].iter_mut().zip(&local) {
            *o += x;
        }
        for i in 0..s.modes {
            for j in 0..s.modes {
                self.elastic[s.flexible() + i] += data.stiffness[(i, j)] * qf[j];
                self.damping[s.flexible() + i] += data.damping[(i, j)] * qf_dot[j];
            }
        }
    }
}

impl System {
    /// The data-carrying terms of the equations of motion at (q, q̇) ([`EomTerms`]).
    pub fn eom_terms(&self, q: &[f64], v: &[f64]) -> EomTerms {
        let mut out = EomTerms::zeros(self.size());
        for (body, s) in self.bodies.iter().zip(self.layout.slices()) {
            out.add_body(&body.data, s, self.gravity, q, v);
        }
        out
    }

    /// The rate of change of the terms at (q, q̇) when the data of body `body` change at the
    /// rate `rate` (e.g. ∂D/∂pⱼ of a pROM body): the terms are linear in a body's data
    /// (module doc), so this is the body's terms evaluated with `rate` as its data; zero in
    /// every other body's rows.
    pub fn eom_terms_rate(
        &self,
        body: BodyId,
        rate: &FlexibleBodyData,
        q: &[f64],
        v: &[f64],
    ) -> EomTerms {
        let mut out = EomTerms::zeros(self.size());
        out.add_body(rate, &self.layout.slice(body), self.gravity, q, v);
        out
    }
}
