//! The AMANDA step (thesis §9.2.2, eq. 9.9–9.14): the corrected positions q⁺ of the Kalman
//! update do not satisfy the constraints; the step finds the configuration on Φ(q, t) = 0
//! closest to q⁺ (eq. 9.9) and velocities consistent with it.
//!
//! The minimization min ‖q̂ − q⁺‖ subject to Φ(q̂) = 0 is solved by Gauss–Newton with
//! minimum-norm steps, from the prior q⁻ (on the manifold, as the thesis starts it):
//!
//! ```text
//! q̂ⁱ⁺¹ = q⁺ − Φ_qᵀ (Φ_q Φ_qᵀ)⁻¹ (Φ(q̂ⁱ) + Φ_q (q⁺ − q̂ⁱ)),   Φ_q at q̂ⁱ
//! ```
//!
//! the exact minimizer over the tangent plane at q̂ⁱ: its fixed point satisfies Φ = 0 and
//! q̂ − q⁺ ∈ range Φ_qᵀ, the optimality condition of eq. 9.9. It replaces eq. 9.12–9.13's
//! descent along N N ᵀ (a projector only for an orthonormal nullspace basis) by the orthogonal
//! projection, which needs no step length. When it has not reached the tolerance after the
//! allowed iterations, the kinematic assembly (Newton with minimum-norm corrections on Φ = 0,
//! from q⁺) is the fallback. The velocities are then the minimum-norm change of v⁺ onto
//! Φ_q v + Φ_t = 0 at q̂. The parameters and inputs are not changed (§9.2.2).

use faer::linalg::solvers::Solve;
use faer::{Mat, MatRef};

use crate::multibody::constraint_set::ConstraintSet;
use crate::multibody::layout::Layout;

/// Tolerances and iterations of the step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ManifoldSettings {
    /// max |Φ| and max |Φ_q v + Φ_t| accepted.
    pub tolerance: f64,
    /// Gauss–Newton iterations before the fallback (and of the fallback).
    pub max_iterations: usize,
}

impl Default for ManifoldSettings {
    fn default() -> Self {
        Self {
            tolerance: 1e-10,
            max_iterations: 10,
        }
    }
}

/// What one AMANDA step did.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ManifoldReport {
    /// Gauss–Newton iterations (and fallback iterations).
    pub iterations: usize,
    /// Whether the kinematic assembly was needed.
    pub fallback: bool,
    /// max |Φ(q̂)| and max |Φ_q v̂ + Φ_t| at the end.
    pub position_residual: f64,
    pub velocity_residual: f64,
    /// ‖q̂ − q⁺‖: how far the update had left the manifold.
    pub distance: f64,
}

/// Where the step failed: Φ_q Φ_qᵀ singular, or the fallback not converged.
#[derive(Debug, Clone, PartialEq)]
pub struct ManifoldError {
    pub residual: f64,
}

fn max_abs(x: &[f64]) -> f64 {
    x.iter().fold(0.0, |a, b| a.max(b.abs()))
}

/// Δ = Φ_qᵀ (Φ_q Φ_qᵀ)⁻¹ b (m × n Φ_q of full row rank).
fn minimum_norm(phi_q: MatRef<'_, f64>, b: &[f64]) -> Option<Vec<f64>> {
    let gram = phi_q * phi_q.transpose();
    let mut y = Mat::from_fn(b.len(), 1, |i, _| b[i]);
    gram.partial_piv_lu().solve_in_place(y.as_mut());
    let d = phi_q.transpose() * &y;
    let out: Vec<f64> = (0..d.nrows()).map(|i| d[(i, 0)]).collect();
    out.iter().all(|x| x.is_finite()).then_some(out)
}

/// The constraints of a system at one time, evaluated for the step.
pub struct Manifold<'a> {
    pub layout: &'a Layout,
    pub constraints: &'a ConstraintSet,
    pub time: f64,
    pub settings: ManifoldSettings,
}

impl Manifold<'_> {
    fn evaluate(&self, q: &[f64]) -> (Vec<f64>, Mat<f64>) {
        let m = self.constraints.len();
        let mut phi = vec![0.0; m];
        let mut phi_q = Mat::zeros(m, q.len());
        self.constraints.values(self.layout, q, self.time, &mut phi);
        self.constraints
            .jacobian(self.layout, q, self.time, phi_q.as_mut());
        (phi, phi_q)
    }

    /// q̂ closest to `corrected` on Φ = 0 from `prior`, into `q`; v⁺ (`v`) onto the velocity
    /// constraints at q̂ (module docs).
    pub fn step(
        &self,
        prior: &[f64],
        q: &mut [f64],
        v: &mut [f64],
    ) -> Result<ManifoldReport, ManifoldError> {
        let corrected = q.to_vec();
        let n = q.len();
        let mut report = ManifoldReport::default();
        q.copy_from_slice(prior);
        let mut converged = false;
        for _ in 0..self.settings.max_iterations {
            let (mut phi, phi_q) = self.evaluate(q);
            for (k, p) in phi.iter_mut().enumerate() {
                *p += (0..n)
                    .map(|j| phi_q[(k, j)] * (corrected[j] - q[j]))
                    .sum::<f64>();
            }
            let Some(d) = minimum_norm(phi_q.as_ref(), &phi) else {
                break;
            };
            let change = (0..n).fold(0.0_f64, |a, j| a.max((corrected[j] - d[j] - q[j]).abs()));
            for j in 0..n {
                q[j] = corrected[j] - d[j];
            }
            report.iterations += 1;
            let (phi, _) = self.evaluate(q);
            if max_abs(&phi) <= self.settings.tolerance
                && change <= self.settings.tolerance.sqrt() * (1.0 + max_abs(q))
            {
                converged = true;
                break;
            }
        }
        if !converged {
            report.fallback = true;
            q.copy_from_slice(&corrected);
            for _ in 0..self.settings.max_iterations {
                let (phi, phi_q) = self.evaluate(q);
                if max_abs(&phi) <= self.settings.tolerance {
                    converged = true;
                    break;
                }
                let d = minimum_norm(phi_q.as_ref(), &phi).ok_or(ManifoldError {
                    residual: max_abs(&phi),
                })?;
                q.iter_mut().zip(&d).for_each(|(x, d)| *x -= d);
                report.iterations += 1;
            }
        }
        let (phi, phi_q) = self.evaluate(q);
        report.position_residual = max_abs(&phi);
        if !converged && report.position_residual > self.settings.tolerance {
            return Err(ManifoldError {
                residual: report.position_residual,
            });
        }
        report.distance = q
            .iter()
            .zip(&corrected)
            .map(|(a, b)| (a - b) * (a - b))
            .sum::<f64>()
            .sqrt();
        // v ← v − Φ_qᵀ (Φ_q Φ_qᵀ)⁻¹ (Φ_q v + Φ_t)
        let velocity_residual = |v: &[f64]| {
            let mut r = vec![0.0; phi.len()];
            self.constraints
                .time_rates(self.layout, q, self.time, &mut r);
            for (k, x) in r.iter_mut().enumerate() {
                *x += (0..n).map(|j| phi_q[(k, j)] * v[j]).sum::<f64>();
            }
            r
        };
        let d = minimum_norm(phi_q.as_ref(), &velocity_residual(v)).ok_or(ManifoldError {
            residual: report.position_residual,
        })?;
        v.iter_mut().zip(&d).for_each(|(x, d)| *x -= d);
        report.velocity_residual = max_abs(&velocity_residual(v));
        Ok(report)
    }
}
