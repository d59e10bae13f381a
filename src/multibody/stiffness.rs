//! The static stiffness K_s = −∂f/∂q of the applied forces at rest (q̇ = 0), exact: what the
//! Newton matrix of [`super::statics`] needs besides the constraint terms. At rest the
//! quadratic velocity vector and the damping forces vanish with their q-derivatives (f_v is
//! quadratic in q̇), so
//!
//! ```text
//! K_s = Σ_bodies (K_ff − ∇²(gᵀ A(e) S(q_f))) + Σ_springs (K ∇ℓ∇ℓᵀ − T ∇²ℓ) − Σ_loads ∂Q/∂q
//! ```
//!
//! The gravity force of a body is the gradient of gᵀ (m r + A(e) S(q_f)), S = Σ m ū the first
//! mass moment, affine in q_f through the invariants (S = M̂₁ + M̂₂ q_f, eq. A.11–A.12): the
//! potential of a body vector with v̄₀ = M̂₁ and v̄ₖ = M̂₂'s columns, whose Hessian is
//! [`super::vectors`]' exact polynomial one. K_ff enters as the integrator's iteration matrix
//! has it ([`super::layout::BodySlice::add_modal_block`]); the springs' and the point loads'
//! terms are those of [`super::forces`].

use super::system::{Equations, System};
use super::vectors::BodyVector;
use faer::MatMut;

impl System {
    /// K_s = −∂f/∂q at (q, q̇ = 0, t) into `out` (n × n, overwritten; module docs).
    pub fn static_stiffness(
        &self,
        equations: &Equations,
        q: &[f64],
        t: f64,
        mut out: MatMut<'_, f64>,
    ) {
        out.fill(0.0);
        for (b, (body, s)) in self.bodies.iter().zip(self.layout.slices()).enumerate() {
            s.add_modal_block(&mut out, body.data.stiffness.as_ref(), 1.0);
            let inv = &body.data.invariants;
            let first_moment = BodyVector {
                body: Some(b),
                is_point: false,
                local: inv.first,
                modal: inv.first_modal.clone(),
            };
            first_moment.hessian(&self.layout, q, self.gravity, |i, j, x| out[(i, j)] -= x);
        }
        for f in &self.forces {
            f.add_load_stiffness(&self.markers, &self.layout, q, t, &mut out);
        }
        let mut gradient = vec![0.0; q.len()];
        for spring in &equations.springs {
            spring.add_static_stiffness(&self.layout, q, t, &mut gradient, &mut out);
        }
    }
}
