//! Static equilibrium of a constrained system: the GGL equations (eq. 2.60) with zero velocities
//! and accelerations,
//!
//! ```text
//! Φ_qᵀ λ − f(q, 0, t) = 0,   Φ(q, t) = 0,
//! ```
//!
//! f the applied forces (gravity through the mass invariants, the bodies' K q_f, spring-dampers,
//! point forces) and λ the constraint forces; drives hold their coordinates at t. Newton's method
//! on (q, λ) with the matrix
//!
//! ```text
//! ⎡ Σ λᵢ ∇²Φᵢ − ∂f/∂q   Φ_qᵀ ⎤
//! ⎣ Φ_q                 0    ⎦
//! ```
//!
//! where ∂f/∂q is taken by central differences (gravity's dependence on the orientation and the
//! modal coordinates enters through the invariants, which have no analytic q-derivative here),
//! the constraint Hessians are analytic. A correction that does not lower the residual is halved
//! (up to ten times) so a start far from equilibrium does not overshoot.

use super::error::MultibodyError;
use super::system::{Equations, System};
use faer::Mat;
use faer::linalg::solvers::Solve;

/// Iterations of the equilibrium Newton solve before it gives up.
const MAX_ITERATIONS: usize = 50;

/// A static equilibrium.
#[derive(Debug, Clone, PartialEq)]
pub struct Equilibrium {
    pub q: Vec<f64>,
    /// Constraint forces, one per constraint of the equations solved.
    pub lambda: Vec<f64>,
    pub iterations: usize,
    /// max |Φ_qᵀ λ − f| and max |Φ| at the equilibrium.
    pub force_residual: f64,
    pub constraint_residual: f64,
}

/// The residual [Φ_qᵀ λ − f; Φ] at (q, λ) and Φ_q.
fn residual(
    system: &System,
    equations: &Equations,
    q: &[f64],
    lambda: &[f64],
    t: f64,
    phi_q: &mut Mat<f64>,
) -> Vec<f64> {
    let (n, m) = (q.len(), lambda.len());
    let c = &equations.constraints;
    let mut r = vec![0.0; n + m];
    system.applied_forces(equations, q, &vec![0.0; n], t, &mut r[..n], None);
    for x in &mut r[..n] {
        *x = -*x;
    }
    c.jacobian(&system.layout, q, t, phi_q.as_mut());
    for i in 0..m {
        for j in 0..n {
            r[j] += phi_q[(i, j)] * lambda[i];
        }
    }
    c.values(&system.layout, q, t, &mut r[n..]);
    r
}

fn max_abs(x: &[f64]) -> f64 {
    x.iter().fold(0.0, |a, b| a.max(b.abs()))
}

/// Solves for the equilibrium of `system` with the (redundancy-free) `equations` at time `t`,
/// starting from the configuration `q0` (an assembled one). Converged when the full Newton
/// correction of q is below `tolerance` relative to 1 + |q| and |Φ| is below
/// `assembly_tolerance`.
pub fn equilibrium(
    system: &System,
    equations: &Equations,
    q0: &[f64],
    t: f64,
    tolerance: f64,
    assembly_tolerance: f64,
) -> Result<Equilibrium, MultibodyError> {
    let (n, m) = (q0.len(), equations.constraints.len());
    let mut q = q0.to_vec();
    let mut lambda = vec![0.0; m];
    let mut phi_q = Mat::zeros(m, n);
    let mut r = residual(system, equations, &q, &lambda, t, &mut phi_q);
    let mut force = vec![0.0; n];
    let mut shifted = vec![0.0; n];
    for iteration in 1..=MAX_ITERATIONS {
        let mut matrix = Mat::<f64>::zeros(n + m, n + m);
        equations.constraints.add_weighted_hessian(
            &system.layout,
            &q,
            t,
            &lambda,
            1.0,
            matrix.as_mut().submatrix_mut(0, 0, n, n),
        );
        let zero = vec![0.0; n];
        for j in 0..n {
            let h = 1e-6 * (1.0 + q[j].abs());
            shifted.copy_from_slice(&q);
            shifted[j] = q[j] + h;
            system.applied_forces(equations, &shifted, &zero, t, &mut force, None);
            for i in 0..n {
                matrix[(i, j)] -= force[i] / (2.0 * h);
            }
            shifted[j] = q[j] - h;
            system.applied_forces(equations, &shifted, &zero, t, &mut force, None);
            for i in 0..n {
                matrix[(i, j)] += force[i] / (2.0 * h);
            }
        }
        for i in 0..m {
            for j in 0..n {
                matrix[(j, n + i)] = phi_q[(i, j)];
                matrix[(n + i, j)] = phi_q[(i, j)];
            }
        }
        let mut dx = Mat::from_fn(n + m, 1, |i, _| -r[i]);
        matrix.partial_piv_lu().solve_in_place(dx.as_mut());
        if (0..n + m).any(|i| !dx[(i, 0)].is_finite()) {
            return Err(MultibodyError::Singular {
                what: "static equilibrium matrix",
                time: t,
            });
        }
        let before = max_abs(&r);
        let mut scale = 1.0;
        let (mut q_try, mut lambda_try) = (q.clone(), lambda.clone());
        for _ in 0..10 {
            for j in 0..n {
                q_try[j] = q[j] + scale * dx[(j, 0)];
            }
            for i in 0..m {
                lambda_try[i] = lambda[i] + scale * dx[(n + i, 0)];
            }
            r = residual(system, equations, &q_try, &lambda_try, t, &mut phi_q);
            if max_abs(&r) <= before {
                break;
            }
            scale *= 0.5;
        }
        let newton_step = (0..n).fold(0.0_f64, |a, j| a.max(dx[(j, 0)].abs()));
        (q, lambda) = (q_try, lambda_try);
        let constraint_residual = max_abs(&r[n..]);
        if newton_step <= tolerance * (1.0 + max_abs(&q))
            && constraint_residual <= assembly_tolerance
        {
            return Ok(Equilibrium {
                force_residual: max_abs(&r[..n]),
                constraint_residual,
                q,
                lambda,
                iterations: iteration,
            });
        }
    }
    let constraint = max_abs(&r[n..]);
    let worst = (0..m)
        .max_by(|&a, &b| r[n + a].abs().total_cmp(&r[n + b].abs()))
        .map_or_else(String::new, |i| equations.constraints.labels[i].clone());
    Err(MultibodyError::NoEquilibrium {
        time: t,
        iterations: MAX_ITERATIONS,
        residual: max_abs(&r[..n]),
        worst,
        constraint,
    })
}
