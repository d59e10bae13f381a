//! Applied forces: point forces and moments at markers from a time function, and spring-dampers on a
//! scalar coordinate ℓ(q) — the distance between two markers (point-to-point), a joint's
//! relative angle or slide (joint spring-damper) or the error of a compliant drive (Fig. 4.15b):
//!
//! ```text
//! T = −K (ℓ − ℓ_d(t)) − C (ℓ̇ − ℓ̇_d(t)),   Q = T ∇ℓ,   ℓ̇ = ∇ℓ · q̇
//! ```
//!
//! with ℓ_d = ℓ₀ + f(t) (ℓ₀ the free length, rest angle or the drive's initial value). Angle
//! differences are taken in (−π, π]. The integrator's Newton matrix gets K ∇ℓ ∇ℓᵀ and
//! C ∇ℓ ∇ℓᵀ (the curvature of ℓ times T is left out); the static stiffness −∂Q/∂q at rest is
//! exact, K ∇ℓ ∇ℓᵀ − T ∇²ℓ, with for θ = atan2(s, c), ρ² = s² + c², a = ∇s, b = ∇c
//!
//! ```text
//! ∇²θ = (c ∇²s − s ∇²c) / ρ² + (2cs (b bᵀ − a aᵀ) + (s² − c²)(a bᵀ + b aᵀ)) / ρ⁴,
//! ∇²|d| = ∇²(d·d) / (2 |d|) − ∇|d| ∇|d|ᵀ / |d|,
//! ```
//!
//! and a slide's ∇²ℓ the Hessian of its dot product.
//!
//! A force F n at a marker point p does the virtual work F nᵀ δp, so Q = F (∂p/∂q)ᵀ n. A moment
//! M n does M nᵀ δθ with δθ the small rotation of the marker's frame; its axes uₖ move by
//! δuₖ = δθ × uₖ, so ½ Σₖ uₖ × δuₖ = δθ (an orthonormal triad) and
//!
//! ```text
//! Q = M · ½ Σₖ (∂uₖ/∂q)ᵀ (n × uₖ)
//! ```
//!
//! which on a rigid body is the Euler-parameter form Q_e = 2 Gᵀ (M n) and on a flexible body
//! adds the interface grid's rotation rows. Neither load's derivative enters the integrator's
//! iteration matrix (the direction n is fixed in space, the loads are given); the static
//! stiffness takes them exactly: ∂Q/∂q = F ∇²(nᵀp) for the force and, for the moment,
//!
//! ```text
//! ∂Q/∂q = ½ M Σₖ (J_kᵀ [n]× J_k + ∇²((n × uₖ)ᵀ uₖ) with n × uₖ held),   J_k = ∂uₖ/∂q.
//! ```

use super::constraint::{Constraint, VectorSum};
use super::layout::Layout;
use super::marker::Marker;
use super::signal::Signal;
use crate::geometry::vec3::cross;
use faer::MatMut;

/// Adds scale · g gᵀ to `out` over the entries `nonzero` of g.
fn add_outer(out: &mut MatMut<'_, f64>, nonzero: &[usize], g: &[f64], scale: f64) {
    for &i in nonzero {
        for &j in nonzero {
            out[(i, j)] += scale * (g[i] * g[j]);
        }
    }
}

/// The indices of the nonzero entries of g.
fn nonzero(g: &[f64]) -> Vec<usize> {
    (0..g.len()).filter(|&j| g[j] != 0.0).collect()
}

/// An applied force element (user-facing).
#[derive(Debug, Clone)]
pub enum Force {
    /// F(t) = f(t) n at a marker, n in global components.
    Point {
        marker: usize,
        direction: [f64; 3],
        signal: Signal,
    },
    /// M(t) = f(t) n at a marker: a moment about the global unit axis n that turns the
    /// marker's frame.
    Moment {
        marker: usize,
        direction: [f64; 3],
        signal: Signal,
    },
    /// Spring-damper between two marker points with free length L₀.
    PointSpringDamper {
        first: usize,
        second: usize,
        stiffness: f64,
        damping: f64,
        length: f64,
    },
    /// Spring-damper on the relative coordinate of a revolute or prismatic joint, at rest at
    /// `rest`.
    JointSpringDamper {
        joint: usize,
        stiffness: f64,
        damping: f64,
        rest: f64,
    },
}

impl Force {
    /// Adds the generalized force of a point force or moment at time t to `force` (module
    /// docs); spring-dampers add nothing here ([`SpringDamper::apply`]).
    pub fn add_load(
        &self,
        markers: &[Marker],
        layout: &Layout,
        q: &[f64],
        t: f64,
        force: &mut [f64],
    ) {
        match self {
            Force::Point {
                marker,
                direction,
                signal,
            } => {
                let amplitude = signal.at(t)[0];
                markers[*marker].point().jacobian(layout, q, |i, j, x| {
                    force[j] += x * amplitude * direction[i]
                });
            }
            Force::Moment {
                marker,
                direction,
                signal,
            } => {
                let amplitude = 0.5 * signal.at(t)[0];
                for k in 0..3 {
                    let axis = markers[*marker].axis(k);
                    let w = cross(*direction, axis.value(layout, q));
                    axis.jacobian(layout, q, |i, j, x| force[j] += x * amplitude * w[i]);
                }
            }
            Force::PointSpringDamper { .. } | Force::JointSpringDamper { .. } => {}
        }
    }

    /// Adds −∂Q/∂q of a point force or moment at time t to `out` (n × n; module docs);
    /// spring-dampers add nothing here ([`SpringDamper::add_static_stiffness`]).
    pub fn add_load_stiffness(
        &self,
        markers: &[Marker],
        layout: &Layout,
        q: &[f64],
        t: f64,
        out: &mut MatMut<'_, f64>,
    ) {
        match self {
            Force::Point {
                marker,
                direction,
                signal,
            } => {
                let amplitude = signal.at(t)[0];
                markers[*marker]
                    .point()
                    .hessian(layout, q, *direction, |i, j, x| {
                        out[(i, j)] -= amplitude * x
                    });
            }
            Force::Moment {
                marker,
                direction,
                signal,
            } => {
                let amplitude = 0.5 * signal.at(t)[0];
                let mut jacobian = Vec::new();
                for k in 0..3 {
                    let axis = markers[*marker].axis(k);
                    let w = cross(*direction, axis.value(layout, q));
                    axis.hessian(layout, q, w, |i, j, x| out[(i, j)] -= amplitude * x);
                    jacobian.clear();
                    axis.jacobian(layout, q, |r, j, x| jacobian.push((r, j, x)));
                    // (n × ∂u/∂qᵢ) · ∂u/∂q_j, row by row of the Jacobian
                    for &(r, i, x) in &jacobian {
                        let mut unit = [0.0; 3];
                        unit[r] = 1.0;
                        let turned = cross(*direction, unit);
                        for &(s, j, y) in &jacobian {
                            out[(j, i)] -= amplitude * turned[s] * x * y;
                        }
                    }
                }
            }
            Force::PointSpringDamper { .. } | Force::JointSpringDamper { .. } => {}
        }
    }
}

/// A scalar coordinate ℓ(q) with its gradient.
#[derive(Debug, Clone)]
pub enum Coordinate {
    /// θ = atan2(s, c) from the two dot products [s, c].
    Angle([Constraint; 2]),
    /// A single dot product (a slide).
    Slide(Constraint),
    /// |p₁ − p₂|.
    Distance(VectorSum),
}

impl Coordinate {
    /// ℓ(q), with ∇ℓ written into `gradient` (length n, overwritten).
    pub fn evaluate(&self, layout: &Layout, q: &[f64], gradient: &mut [f64]) -> f64 {
        gradient.fill(0.0);
        match self {
            Coordinate::Angle([s_part, c_part]) => {
                let (s, c) = (s_part.value(layout, q, 0.0), c_part.value(layout, q, 0.0));
                let rho2 = s * s + c * c;
                s_part.jacobian(layout, q, 0.0, 0, |j, x| gradient[j] += c * x / rho2);
                c_part.jacobian(layout, q, 0.0, 0, |j, x| gradient[j] -= s * x / rho2);
                s.atan2(c)
            }
            Coordinate::Slide(part) => {
                part.jacobian(layout, q, 0.0, 0, |j, x| gradient[j] += x);
                part.value(layout, q, 0.0)
            }
            Coordinate::Distance(sep) => {
                let d = Constraint::dot(sep.clone(), sep.clone());
                let length = d.value(layout, q, 0.0).sqrt();
                // ∇|d| = ∇(d·d) / (2 |d|)
                d.jacobian(layout, q, 0.0, 0, |j, x| gradient[j] += 0.5 * x / length);
                length
            }
        }
    }

    /// Adds weight · ∇²ℓ at q to `out` (n × n; module docs).
    pub fn add_hessian(&self, layout: &Layout, q: &[f64], weight: f64, out: &mut MatMut<'_, f64>) {
        match self {
            Coordinate::Angle([s_part, c_part]) => {
                let (s, c) = (s_part.value(layout, q, 0.0), c_part.value(layout, q, 0.0));
                let rho2 = s * s + c * c;
                s_part.hessian(layout, q, 0.0, weight * c / rho2, |i, j, x| {
                    out[(i, j)] += x
                });
                c_part.hessian(layout, q, 0.0, -weight * s / rho2, |i, j, x| {
                    out[(i, j)] += x
                });
                let (mut a, mut b) = (vec![0.0; q.len()], vec![0.0; q.len()]);
                s_part.jacobian(layout, q, 0.0, 0, |j, x| a[j] += x);
                c_part.jacobian(layout, q, 0.0, 0, |j, x| b[j] += x);
                let w = weight / (rho2 * rho2);
                let either: Vec<usize> = (0..q.len())
                    .filter(|&j| a[j] != 0.0 || b[j] != 0.0)
                    .collect();
                add_outer(out, &either, &b, 2.0 * c * s * w);
                add_outer(out, &either, &a, -2.0 * c * s * w);
                let mixed = (s * s - c * c) * w;
                for &j in &either {
                    for &i in &either {
                        out[(i, j)] += mixed * (a[i] * b[j] + b[i] * a[j]);
                    }
                }
            }
            Coordinate::Slide(part) => {
                part.hessian(layout, q, 0.0, weight, |i, j, x| out[(i, j)] += x);
            }
            Coordinate::Distance(sep) => {
                let mut gradient = vec![0.0; q.len()];
                let length = self.evaluate(layout, q, &mut gradient);
                let d = Constraint::dot(sep.clone(), sep.clone());
                d.hessian(layout, q, 0.0, 0.5 * weight / length, |i, j, x| {
                    out[(i, j)] += x
                });
                add_outer(out, &nonzero(&gradient), &gradient, -weight / length);
            }
        }
    }

    fn difference(&self, value: f64, target: f64) -> f64 {
        match self {
            Coordinate::Angle(_) => {
                let d = value - target;
                d.sin().atan2(d.cos())
            }
            _ => value - target,
        }
    }
}

/// A spring-damper on a coordinate toward ℓ₀ + f(t) (see module docs).
#[derive(Debug, Clone)]
pub struct SpringDamper {
    pub coordinate: Coordinate,
    pub stiffness: f64,
    pub damping: f64,
    pub rest: f64,
    pub motion: Option<Signal>,
}

impl SpringDamper {
    /// Adds Q to `force`; returns T. With `iteration = Some((dq, dv))` adds K ∇ℓ∇ℓᵀ·cq to dq and
    /// C ∇ℓ∇ℓᵀ·cv to dv, the coefficients given.
    #[allow(clippy::too_many_arguments)]
    pub fn apply(
        &self,
        layout: &Layout,
        q: &[f64],
        v: &[f64],
        t: f64,
        gradient: &mut [f64],
        force: &mut [f64],
        iteration: Option<(MatMut<'_, f64>, MatMut<'_, f64>, f64, f64)>,
    ) -> f64 {
        let tension = self.tension(layout, q, v, t, gradient);
        let nonzero = nonzero(gradient);
        for &j in &nonzero {
            force[j] += tension * gradient[j];
        }
        if let Some((mut dq, mut dv, cq, cv)) = iteration {
            add_outer(&mut dq, &nonzero, gradient, cq * self.stiffness);
            add_outer(&mut dv, &nonzero, gradient, cv * self.damping);
        }
        tension
    }

    /// T at (q, q̇, t), with ∇ℓ written into `gradient` (length n, overwritten).
    fn tension(&self, layout: &Layout, q: &[f64], v: &[f64], t: f64, gradient: &mut [f64]) -> f64 {
        let value = self.coordinate.evaluate(layout, q, gradient);
        let rate: f64 = gradient.iter().zip(v).map(|(g, x)| g * x).sum();
        let [target, target_rate, _] = self.motion.as_ref().map_or([0.0; 3], |m| m.at(t));
        let error = self.coordinate.difference(value, self.rest + target);
        -self.stiffness * error - self.damping * (rate - target_rate)
    }

    /// Adds the static stiffness −∂Q/∂q = K ∇ℓ∇ℓᵀ − T ∇²ℓ at (q, q̇ = 0, t) to `out` (n × n;
    /// module docs); `gradient` is scratch of length n.
    pub fn add_static_stiffness(
        &self,
        layout: &Layout,
        q: &[f64],
        t: f64,
        gradient: &mut [f64],
        out: &mut MatMut<'_, f64>,
    ) {
        let tension = self.tension(layout, q, &vec![0.0; q.len()], t, gradient);
        add_outer(out, &nonzero(gradient), gradient, self.stiffness);
        self.coordinate.add_hessian(layout, q, -tension, out);
    }
}
