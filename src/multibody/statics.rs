//! Static equilibrium of a constrained system: the GGL equations (eq. 2.60) with zero velocities
//! and accelerations,
//!
//! ```text
//! Φ_qᵀ λ − f(q, 0, t) = 0,   Φ(q, t) = 0,
//! ```
//!
//! f the applied forces (gravity through the mass invariants, the bodies' K q_f, spring-dampers,
//! compliant drives, point forces) and λ the constraint forces; drives hold their coordinates
//! at t. Newton's method on (q, λ) with the matrix
//!
//! ```text
//! ⎡ Σ λᵢ ∇²Φᵢ − ∂f/∂q   Φ_qᵀ ⎤
//! ⎣ Φ_q                 0    ⎦
//! ```
//!
//! with −∂f/∂q the exact static stiffness of [`super::stiffness`] (elastic, gravity through the
//! invariants, springs and compliant drives with their curvature, point loads) and the
//! constraint Hessians of [`super::constraint`]: the exact tangent, so the iteration converges
//! quadratically. A correction that does not lower the residual is halved (up to ten times) so
//! a start far from equilibrium does not overshoot.
//!
//! [`Refresh::Every`] factors the matrix at every iterate (full Newton, what [`equilibrium`]
//! does). [`Refresh::WhenSlow`] keeps a factorization — across iterations and across calls,
//! through the caller's [`KeptMatrix`] — while the corrections contract: it is refreshed at the
//! current iterate when the ratio of two successive corrections exceeds the given rate or a
//! correction had to be halved (the modified Newton policy of [`crate::dynamics::newton`]).
//! Neighbouring poses of a grid ([`super::poses`]) share one matrix this way.

use super::dense_lu::DenseLu;
use super::error::MultibodyError;
use super::system::{Equations, System};
use faer::{Mat, MatMut};

/// Iterations of the equilibrium Newton solve before it gives up.
const MAX_ITERATIONS: usize = 50;

/// A static equilibrium.
#[derive(Debug, Clone, PartialEq)]
pub struct Equilibrium {
    pub q: Vec<f64>,
    /// Constraint forces, one per constraint of the equations solved.
    pub lambda: Vec<f64>,
    pub iterations: usize,
    /// Factorizations of the iteration matrix.
    pub factorizations: usize,
    /// max |Φ_qᵀ λ − f| and max |Φ| at the equilibrium.
    pub force_residual: f64,
    pub constraint_residual: f64,
}

/// When the iteration matrix is factored again (module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Refresh {
    /// At every iterate: full Newton.
    Every,
    /// When the ratio of successive corrections exceeds this rate, or a correction is halved.
    WhenSlow(f64),
}

/// Convergence tolerances and matrix policy of one equilibrium solve.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StaticSettings {
    /// Newton correction of q relative to 1 + |q|.
    pub tolerance: f64,
    /// max |Φ|.
    pub assembly_tolerance: f64,
    pub refresh: Refresh,
}

/// A factored iteration matrix kept between solves of the same system (module docs): the
/// integrator's sequential in-place LU, its storage reused from one factorization to the next.
#[derive(Default)]
pub struct KeptMatrix {
    lu: Option<DenseLu>,
    factored: bool,
}

impl KeptMatrix {
    /// Drops the factorization (the next iteration factors afresh).
    pub fn clear(&mut self) {
        self.factored = false;
    }

    /// The LU storage for a matrix of `size` rows.
    fn storage(&mut self, size: usize) -> &mut DenseLu {
        if self.lu.as_ref().is_none_or(|lu| lu.size() != size) {
            self.lu = Some(DenseLu::new(size));
        }
        self.lu.as_mut().expect("set above")
    }
}

/// The residual [Φ_qᵀ λ − f; Φ] at (q, λ) and Φ_q.
pub(super) fn residual(
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

/// The iteration matrix of the module docs at (q, λ), Φ_q given, into `matrix` ((n + m)
/// square, overwritten).
pub(super) fn iteration_matrix(
    system: &System,
    equations: &Equations,
    (q, lambda): (&[f64], &[f64]),
    t: f64,
    phi_q: &Mat<f64>,
    mut matrix: MatMut<'_, f64>,
) {
    let (n, m) = (q.len(), lambda.len());
    matrix.fill(0.0);
    system.static_stiffness(equations, q, t, matrix.as_mut().submatrix_mut(0, 0, n, n));
    equations.constraints.add_weighted_hessian(
        &system.layout,
        q,
        t,
        lambda,
        1.0,
        matrix.as_mut().submatrix_mut(0, 0, n, n),
    );
    for i in 0..m {
        for j in 0..n {
            matrix[(j, n + i)] = phi_q[(i, j)];
            matrix[(n + i, j)] = phi_q[(i, j)];
        }
    }
}

fn max_abs(x: &[f64]) -> f64 {
    x.iter().fold(0.0, |a, b| a.max(b.abs()))
}

/// Solves for the equilibrium of `system` with the (redundancy-free) `equations` at time `t`,
/// starting from the configuration `q0` (an assembled one) with zero constraint forces, by
/// full Newton. Converged when the full Newton correction of q is below `tolerance` relative
/// to 1 + |q| and |Φ| is below `assembly_tolerance`.
pub fn equilibrium(
    system: &System,
    equations: &Equations,
    q0: &[f64],
    t: f64,
    tolerance: f64,
    assembly_tolerance: f64,
) -> Result<Equilibrium, MultibodyError> {
    let settings = StaticSettings {
        tolerance,
        assembly_tolerance,
        refresh: Refresh::Every,
    };
    let lambda0 = vec![0.0; equations.constraints.len()];
    equilibrium_from(
        system,
        equations,
        (q0, &lambda0),
        t,
        settings,
        &mut KeptMatrix::default(),
    )
}

/// The derivatives (∂q/∂pⱼ) of the equilibrium `eq` of `system` at time `t` with respect to
/// parameters whose applied-force rates ∂f/∂pⱼ at (eq.q, v = 0) are `rates` (n each): the
/// residual [Φ_qᵀ λ − f; Φ] stays zero, so the iteration matrix A (the exact tangent) gives
/// A [∂q/∂pⱼ; ∂λ/∂pⱼ] = [∂f/∂pⱼ; 0], one factorization for all j.
pub fn equilibrium_rates(
    system: &System,
    equations: &Equations,
    eq: &Equilibrium,
    t: f64,
    rates: &[Vec<f64>],
) -> Result<Vec<Vec<f64>>, MultibodyError> {
    let (n, m) = (eq.q.len(), eq.lambda.len());
    let mut phi_q = Mat::zeros(m, n);
    equations
        .constraints
        .jacobian(&system.layout, &eq.q, t, phi_q.as_mut());
    let mut lu = DenseLu::new(n + m);
    iteration_matrix(
        system,
        equations,
        (&eq.q, &eq.lambda),
        t,
        &phi_q,
        lu.matrix_mut(),
    );
    lu.factor();
    rates
        .iter()
        .map(|rate| {
            let mut x = rate.clone();
            x.resize(n + m, 0.0);
            lu.solve(&mut x);
            if x.iter().any(|d| !d.is_finite()) {
                return Err(MultibodyError::Singular {
                    what: "static equilibrium matrix",
                    time: t,
                });
            }
            x.truncate(n);
            Ok(x)
        })
        .collect()
}

/// [`equilibrium`] from the configuration and constraint forces `(q0, λ0)` (e.g. a
/// neighbouring pose's equilibrium), with the matrix policy of `settings`; `kept` holds the
/// factorization between calls under [`Refresh::WhenSlow`].
pub fn equilibrium_from(
    system: &System,
    equations: &Equations,
    (q0, lambda0): (&[f64], &[f64]),
    t: f64,
    settings: StaticSettings,
    kept: &mut KeptMatrix,
) -> Result<Equilibrium, MultibodyError> {
    let (n, m) = (q0.len(), equations.constraints.len());
    let mut q = q0.to_vec();
    let mut lambda = lambda0.to_vec();
    let mut phi_q = Mat::zeros(m, n);
    let mut r = residual(system, equations, &q, &lambda, t, &mut phi_q);
    let mut factorizations = 0;
    let mut previous_step = f64::INFINITY;
    if settings.refresh == Refresh::Every {
        kept.clear();
    }
    for iteration in 1..=MAX_ITERATIONS {
        if !kept.factored {
            let lu = kept.storage(n + m);
            iteration_matrix(system, equations, (&q, &lambda), t, &phi_q, lu.matrix_mut());
            lu.factor();
            kept.factored = true;
            factorizations += 1;
        }
        let mut dx: Vec<f64> = r.iter().map(|x| -x).collect();
        kept.storage(n + m).solve(&mut dx);
        if dx.iter().any(|d| !d.is_finite()) {
            kept.clear();
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
                q_try[j] = q[j] + scale * dx[j];
            }
            for i in 0..m {
                lambda_try[i] = lambda[i] + scale * dx[n + i];
            }
            r = residual(system, equations, &q_try, &lambda_try, t, &mut phi_q);
            if max_abs(&r) <= before {
                break;
            }
            scale *= 0.5;
        }
        let newton_step = max_abs(&dx[..n]);
        (q, lambda) = (q_try, lambda_try);
        let stale = match settings.refresh {
            Refresh::Every => true,
            Refresh::WhenSlow(rate) => scale < 1.0 || newton_step > rate * previous_step,
        };
        if stale {
            kept.clear();
        }
        previous_step = newton_step;
        let constraint_residual = max_abs(&r[n..]);
        if newton_step <= settings.tolerance * (1.0 + max_abs(&q))
            && constraint_residual <= settings.assembly_tolerance
        {
            return Ok(Equilibrium {
                force_residual: max_abs(&r[..n]),
                constraint_residual,
                q,
                lambda,
                iterations: iteration,
                factorizations,
            });
        }
    }
    kept.clear();
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
