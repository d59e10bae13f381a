//! Newton's method for the implicit equations R(x) = 0 of one time step, shared by the
//! integrators of second-order residuals ([`super::nonlinear`], x = q_{n+1}) and the GGL
//! multibody integrator (eq. 2.60 with BDF1 eq. 2.61, BDF2 or generalized-α; x = (q, v, λ̂, μ)
//! at t_{n+1}, [`crate::multibody::Ggl`]).
//!
//! The equations supply the residual, the factorization of their iteration matrix (exact or
//! approximate, dense, sparse or block: their choice) and the solve with it
//! ([`StepEquations`]); [`NewtonDriver`] iterates x ← x − J⁻¹ R(x) from the step's predictor
//! under a [`JacobianUpdate`] policy:
//!
//! - a correction of size ≤ 1 (the equations' scaled measure) ends the step; with
//!   [`NewtonDriver::estimate_remaining_error`], so does a correction whose estimated remaining
//!   error θ/(1 − θ)·size is ≤ 1, θ < 1 the contraction rate of the last two corrections (the
//!   error left after a contraction by θ per iteration; Hairer & Wanner II, sec. IV.8);
//! - a correction that grows under a matrix factored at the current iterate (or, with
//!   `EveryStep`, at the predictor) means divergence: the attempt stops;
//! - with `Reuse`, the factorization is kept across iterations and steps and refactored at the
//!   current iterate when the corrections contract by less than `slow_rate` per iteration;
//! - an attempt that began with a factorization of an earlier step and did not converge is
//!   repeated once from the predictor with a fresh factorization.
//!
//! The caller invalidates the factorization when the matrix's coefficients change (a new step
//! size or scheme start). A step allocates nothing.

/// The equations of one step in the unknowns x.
pub trait StepEquations {
    type Error;
    /// R(x) into `r`.
    fn residual(&mut self, x: &[f64], r: &mut [f64]) -> Result<(), Self::Error>;
    /// Factors the iteration matrix (≈ ∂R/∂x) at x; called after `residual` at the same x.
    fn factor(&mut self, x: &[f64]) -> Result<(), Self::Error>;
    /// r ← (the last factored matrix)⁻¹ r.
    fn solve(&mut self, r: &mut [f64]) -> Result<(), Self::Error>;
    /// The size of the correction `dx` just applied to the iterate `x`, scaled by the
    /// tolerance: ≤ 1 means converged.
    fn correction_size(&self, x: &[f64], dx: &[f64]) -> f64;
}

/// When the driver refactors the iteration matrix.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum JacobianUpdate {
    /// At every iteration (full Newton: quadratic convergence).
    EveryIteration,
    /// Once per step, at the predictor (modified Newton).
    EveryStep,
    /// Kept across iterations and steps; refactored when the contraction rate of the
    /// corrections exceeds the driver's `slow_rate`, and when a step begun with an older
    /// factorization does not converge (the step then restarts from its predictor).
    Reuse,
}

/// Newton's iteration policy.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NewtonPolicy {
    /// Iterations per attempt.
    pub max_iterations: usize,
    pub update: JacobianUpdate,
    /// With `Reuse`: the contraction rate above which the matrix is refactored.
    pub slow_rate: f64,
}

/// What Newton did in one step.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct NewtonStats {
    /// Iterations (corrections) of all attempts.
    pub iterations: usize,
    /// ‖R‖∞ at the last iterate evaluated: before the final correction when converged, at the
    /// final iterate otherwise.
    pub residual: f64,
    /// Factorizations in this step (0 when a previous one was reused).
    pub factorizations: usize,
}

/// The outcome of [`NewtonDriver::solve`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NewtonOutcome {
    pub converged: bool,
    pub stats: NewtonStats,
}

/// Newton's buffers and the state of the equations' factorization (module docs).
#[derive(Debug, Clone)]
pub struct NewtonDriver {
    pub policy: NewtonPolicy,
    predictor: Vec<f64>,
    x: Vec<f64>,
    r: Vec<f64>,
    factored: bool,
    /// Whether a contraction-rate estimate of the remaining error may end the step.
    rate_estimate: bool,
}

impl NewtonDriver {
    /// A driver for n unknowns, with no factorization yet.
    pub fn new(n: usize, policy: NewtonPolicy) -> Self {
        Self {
            policy,
            predictor: vec![0.0; n],
            x: vec![0.0; n],
            r: vec![0.0; n],
            factored: false,
            rate_estimate: false,
        }
    }

    /// Also ends a step when the error left after the last correction, estimated from the
    /// contraction rate θ of the last two corrections as θ/(1 − θ)·size, is ≤ 1 (module docs).
    pub fn estimate_remaining_error(&mut self) {
        self.rate_estimate = true;
    }

    /// Forgets the factorization (its coefficients changed).
    pub fn invalidate(&mut self) {
        self.factored = false;
    }

    /// The predictor of the next [`NewtonDriver::solve`], to fill.
    pub fn predictor_mut(&mut self) -> &mut [f64] {
        &mut self.predictor
    }

    /// The last iterate (the solution after a converged solve).
    pub fn solution(&self) -> &[f64] {
        &self.x
    }

    /// Solves the step's equations from the predictor (module docs). Errors of the equations
    /// pass through; a step that does not converge returns `converged: false` with the
    /// residual at its last iterate.
    pub fn solve<E: StepEquations>(
        &mut self,
        equations: &mut E,
    ) -> Result<NewtonOutcome, E::Error> {
        let mut stats = NewtonStats::default();
        let stale = self.factored && self.policy.update == JacobianUpdate::Reuse;
        let mut converged = self.attempt(equations, &mut stats)?;
        if !converged && stale {
            self.factored = false;
            converged = self.attempt(equations, &mut stats)?;
        }
        if !converged {
            equations.residual(&self.x, &mut self.r)?;
            stats.residual = max_abs(&self.r);
        }
        Ok(NewtonOutcome { converged, stats })
    }

    /// One attempt from the predictor; whether it converged.
    fn attempt<E: StepEquations>(
        &mut self,
        equations: &mut E,
        stats: &mut NewtonStats,
    ) -> Result<bool, E::Error> {
        let NewtonPolicy {
            max_iterations,
            update,
            slow_rate,
        } = self.policy;
        self.x.copy_from_slice(&self.predictor);
        let mut previous = f64::INFINITY;
        for iteration in 0..max_iterations {
            equations.residual(&self.x, &mut self.r)?;
            stats.residual = max_abs(&self.r);
            if !stats.residual.is_finite() {
                return Ok(false);
            }
            let fresh = match update {
                JacobianUpdate::EveryIteration => true,
                JacobianUpdate::EveryStep => iteration == 0,
                JacobianUpdate::Reuse => !self.factored,
            };
            if fresh {
                equations.factor(&self.x)?;
                self.factored = true;
                stats.factorizations += 1;
            }
            equations.solve(&mut self.r)?;
            self.x.iter_mut().zip(&self.r).for_each(|(x, d)| *x -= d);
            stats.iterations += 1;
            let size = equations.correction_size(&self.x, &self.r);
            if !size.is_finite() {
                return Ok(false);
            }
            // θ of the last two corrections (none at the first)
            let rate = size / previous;
            let estimated = self.rate_estimate
                && previous.is_finite()
                && rate < 1.0
                && rate / (1.0 - rate) * size <= 1.0;
            if size <= 1.0 || estimated {
                return Ok(true);
            }
            if size > previous && (fresh || update == JacobianUpdate::EveryStep) {
                return Ok(false);
            }
            if update == JacobianUpdate::Reuse && size > slow_rate * previous {
                self.factored = false;
            }
            previous = size;
        }
        Ok(false)
    }
}

/// ‖x‖∞.
pub fn max_abs(x: &[f64]) -> f64 {
    x.iter().fold(0.0, |m, v| m.max(v.abs()))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// x² − 2 = 0 with the iteration matrix frozen at the factoring iterate.
    struct Root {
        slope: f64,
        factorizations: usize,
    }

    impl StepEquations for Root {
        type Error = ();
        fn residual(&mut self, x: &[f64], r: &mut [f64]) -> Result<(), ()> {
            r[0] = x[0] * x[0] - 2.0;
            Ok(())
        }
        fn factor(&mut self, x: &[f64]) -> Result<(), ()> {
            self.slope = 2.0 * x[0];
            self.factorizations += 1;
            Ok(())
        }
        fn solve(&mut self, r: &mut [f64]) -> Result<(), ()> {
            r[0] /= self.slope;
            Ok(())
        }
        fn correction_size(&self, _: &[f64], dx: &[f64]) -> f64 {
            dx[0].abs() / 1e-12
        }
    }

    /// With the slope frozen at the predictor the corrections contract linearly; the
    /// contraction-rate estimate ends the step earlier with the error still within the
    /// tolerance.
    #[test]
    fn rate_estimate_ends_a_linearly_contracting_step_earlier_within_the_tolerance() {
        let policy = NewtonPolicy {
            max_iterations: 50,
            update: JacobianUpdate::EveryStep,
            slow_rate: 0.3,
        };
        let mut iterations = Vec::new();
        for estimate in [false, true] {
            let mut driver = NewtonDriver::new(1, policy);
            if estimate {
                driver.estimate_remaining_error();
            }
            let mut root = Root {
                slope: 0.0,
                factorizations: 0,
            };
            driver.predictor_mut()[0] = 1.6;
            let outcome = driver.solve(&mut root).unwrap();
            assert!(outcome.converged);
            let error = (driver.solution()[0] - 2f64.sqrt()).abs();
            assert!(error < 1e-12, "estimate {estimate}: error {error:e}");
            iterations.push(outcome.stats.iterations);
        }
        assert!(iterations[1] < iterations[0], "{iterations:?}");
    }

    #[test]
    fn each_update_policy_finds_the_root_and_reuse_factors_least() {
        let mut counts = Vec::new();
        for update in [
            JacobianUpdate::EveryIteration,
            JacobianUpdate::EveryStep,
            JacobianUpdate::Reuse,
        ] {
            let policy = NewtonPolicy {
                max_iterations: 50,
                update,
                slow_rate: 0.3,
            };
            let mut driver = NewtonDriver::new(1, policy);
            let mut root = Root {
                slope: 0.0,
                factorizations: 0,
            };
            for start in [1.5, 1.45, 1.42] {
                driver.predictor_mut()[0] = start;
                let outcome = driver.solve(&mut root).unwrap();
                assert!(outcome.converged, "{update:?} from {start}");
                assert!((driver.solution()[0] - 2f64.sqrt()).abs() < 1e-12);
            }
            counts.push(root.factorizations);
        }
        assert!(counts[0] > counts[1], "{counts:?}");
        assert!(counts[2] < counts[1], "{counts:?}");
    }
}
