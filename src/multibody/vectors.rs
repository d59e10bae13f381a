//! Vectors fixed to a body, the building blocks of every constraint and force:
//!
//! ```text
//! v(q) = [r if a point] + A(e) (v̄₀ + Σₖ v̄ₖ q_fk)
//! ```
//!
//! A point of a rigid body has constant body components v̄₀; a marker on a flexible body adds
//! its grid's translation rows (v̄ₖ = ψₖ, eq. 2.58), and a marker direction d̄ turns with the
//! grid's small rotation rows θₖ (v̄ₖ = θₖ × d̄). On the ground (body `None`) v = v̄₀.
//!
//! A(e) is quadratic in e and v̄ affine in q_f, so v is a polynomial in q: its Jacobian and the
//! second derivatives of wᵀ v (for constraint Hessians) are exact and cheap:
//! ∂v/∂e = ∂(A v̄)/∂e, ∂v/∂q_fk = A v̄ₖ, ∂²(wᵀv)/∂eₐ∂e_b = wᵀ ∂(A(u_b) v̄)/∂eₐ (u_b the unit
//! 4-vector), ∂²(wᵀv)/∂eₐ∂q_fk = wᵀ ∂(A v̄ₖ)/∂eₐ, and the q_f–q_f block is zero.

use super::layout::Layout;
use crate::geometry::euler_parameters::{rotated_vector_jacobian, rotation_matrix};
use crate::geometry::mat3::{self, Mat3};

/// A point or direction fixed to a body (see module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct BodyVector {
    /// The body, `None` for the ground.
    pub body: Option<usize>,
    /// A point (includes the body origin r) or a direction.
    pub is_point: bool,
    /// v̄₀ in body components.
    pub local: [f64; 3],
    /// v̄ₖ per flexible coordinate (empty on rigid bodies and the ground).
    pub modal: Vec<[f64; 3]>,
}

impl BodyVector {
    fn deformed(&self, qf: &[f64]) -> [f64; 3] {
        let mut v = self.local;
        for (vk, &x) in self.modal.iter().zip(qf) {
            for i in 0..3 {
                v[i] += x * vk[i];
            }
        }
        v
    }

    /// v(q) in global components.
    pub fn value(&self, layout: &Layout, q: &[f64]) -> [f64; 3] {
        let a = self.body.map_or(mat3::IDENTITY, |b| {
            rotation_matrix(&layout.slice(b).euler_parameters(q))
        });
        self.value_rotated(layout, q, &a)
    }

    /// v(q) with A(e) of its body given (`rotations`: computed once for all vectors).
    pub fn value_rotated(&self, layout: &Layout, q: &[f64], a: &Mat3) -> [f64; 3] {
        let Some(b) = self.body else {
            return self.local;
        };
        let s = layout.slice(b);
        let v = mat3::mul_vec(a, self.deformed(s.modal(q)));
        if self.is_point {
            let r = s.position(q);
            [r[0] + v[0], r[1] + v[1], r[2] + v[2]]
        } else {
            v
        }
    }

    /// Calls `sink(j, gᵀ ∂v/∂q_j)` for every structurally nonzero entry, A(e) of its body
    /// given: the Jacobian contracted with g, g on r, gᵀ ∂(A v̄)/∂e on e and (Aᵀ g) · v̄ₖ on
    /// q_fk (three flops per mode where the full Jacobian takes nine).
    pub fn contracted_jacobian(
        &self,
        layout: &Layout,
        q: &[f64],
        a: &Mat3,
        g: [f64; 3],
        mut sink: impl FnMut(usize, f64),
    ) {
        let Some(b) = self.body else {
            return;
        };
        let s = layout.slice(b);
        if self.is_point {
            for (i, &x) in g.iter().enumerate() {
                sink(s.offset + i, x);
            }
        }
        let de = rotated_vector_jacobian(&s.euler_parameters(q), self.deformed(s.modal(q)));
        for (k, x) in contract(g, &de).into_iter().enumerate() {
            sink(s.euler() + k, x);
        }
        let local = mat3::transpose_mul_vec(a, g);
        for (k, vk) in self.modal.iter().enumerate() {
            sink(
                s.flexible() + k,
                local[0] * vk[0] + local[1] * vk[1] + local[2] * vk[2],
            );
        }
    }

    /// Calls `sink(i, j, ∂vᵢ/∂q_j)` for every structurally nonzero entry of ∂v/∂q.
    pub fn jacobian(&self, layout: &Layout, q: &[f64], mut sink: impl FnMut(usize, usize, f64)) {
        let Some(b) = self.body else {
            return;
        };
        let s = layout.slice(b);
        let e = s.euler_parameters(q);
        if self.is_point {
            for i in 0..3 {
                sink(i, s.offset + i, 1.0);
            }
        }
        let de = rotated_vector_jacobian(&e, self.deformed(s.modal(q)));
        for (i, row) in de.iter().enumerate() {
            for (a, &x) in row.iter().enumerate() {
                sink(i, s.euler() + a, x);
            }
        }
        let a = rotation_matrix(&e);
        for (k, vk) in self.modal.iter().enumerate() {
            let column = mat3::mul_vec(&a, *vk);
            for (i, &x) in column.iter().enumerate() {
                sink(i, s.flexible() + k, x);
            }
        }
    }

    /// Calls `sink(i, j, ∂²(wᵀv)/∂qᵢ∂q_j)` for every structurally nonzero entry (both halves of
    /// the symmetric matrix).
    pub fn hessian(
        &self,
        layout: &Layout,
        q: &[f64],
        w: [f64; 3],
        mut sink: impl FnMut(usize, usize, f64),
    ) {
        let Some(b) = self.body else {
            return;
        };
        let s = layout.slice(b);
        let e = s.euler_parameters(q);
        let v = self.deformed(s.modal(q));
        for bcol in 0..4 {
            let mut unit = [0.0; 4];
            unit[bcol] = 1.0;
            let d = rotated_vector_jacobian(&unit, v);
            for (a, x) in contract(w, &d).into_iter().enumerate() {
                sink(s.euler() + a, s.euler() + bcol, x);
            }
        }
        for (k, vk) in self.modal.iter().enumerate() {
            let d = rotated_vector_jacobian(&e, *vk);
            for (a, x) in contract(w, &d).into_iter().enumerate() {
                sink(s.euler() + a, s.flexible() + k, x);
                sink(s.flexible() + k, s.euler() + a, x);
            }
        }
    }

    /// v̇ = (∂v/∂q) q̇.
    pub fn rate(&self, layout: &Layout, q: &[f64], v: &[f64]) -> [f64; 3] {
        let mut out = [0.0; 3];
        self.jacobian(layout, q, |i, j, x| out[i] += x * v[j]);
        out
    }

    /// q̇ᵀ ∂²(wᵀv)/∂q² q̇ for each unit w: the velocity-dependent part of v̈.
    pub fn convective_acceleration(&self, layout: &Layout, q: &[f64], v: &[f64]) -> [f64; 3] {
        std::array::from_fn(|i| {
            let mut w = [0.0; 3];
            w[i] = 1.0;
            let mut out = 0.0;
            self.hessian(layout, q, w, |a, b, x| out += v[a] * x * v[b]);
            out
        })
    }
}

/// wᵀ D for a 3 × 4 matrix D.
fn contract(w: [f64; 3], d: &[[f64; 4]; 3]) -> [f64; 4] {
    std::array::from_fn(|a| w[0] * d[0][a] + w[1] * d[1][a] + w[2] * d[2][a])
}
