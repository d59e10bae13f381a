//! Error-controlled step sizes for the GGL integrator: a local error estimate of the
//! coordinates q after each step, and the controller that accepts or rejects the step and
//! chooses the next size.
//!
//! **Estimate.** With the accelerations q̈ₙ and q̈ₙ₊₁ at both ends of a step of size h, the cubic
//! that matches qₙ, q̇ₙ = vₙ, q̈ₙ and q̈ₙ₊₁ ends at
//!
//! ```text
//! q̃ₙ₊₁ = qₙ + h vₙ + h² (q̈ₙ/3 + q̈ₙ₊₁/6),     exact to O(h⁴),
//! ```
//!
//! and the local error of the scheme's qₙ₊₁ is estimated by e = qₙ₊₁ − q̃ₙ₊₁. The difference is
//! O(h²) for BDF1 (whose own local error h² q̈/2 it reproduces to leading order) and O(h³) for
//! BDF2 and generalized-α, whose accelerations are second-order accurate (Arnold, Brüls &
//! Cardona, Numer. Math. 129, 2015), so the errors of q̈ enter e only at O(h⁴). The same
//! estimate serves every scheme, needs no second solve, and measures what the outputs of a
//! run are made of: marker positions and orientations (r, e) and the flexible coordinates
//! q_f (strains, deviations).
//!
//! **Norm.** The tolerance is meant for the outputs over the whole run, so each step may use
//! the share h/T of it (error per unit step, T the run's duration): if local errors add up
//! without growing, the global error stays below the tolerance (it grows along unstable
//! motions, so it is checked, docs/multibody-benchmarks.md). With the weight
//! wᵢ = ATOL + RTOL max(|qₙ,ᵢ|, |qₙ₊₁,ᵢ|),
//!
//! ```text
//! err = maxᵢ |eᵢ| / wᵢ · T/h,    accepted when err ≤ 1.
//! ```
//!
//! **Controller.** err is O(h^p) with p the scheme's order (1 for BDF1, 2 otherwise), so the
//! next size is h · clamp(0.9 err^(−1/p), 0.2, 2): the elementary controller with the usual
//! safety factor and bounds (Hairer, Nørsett & Wanner I, sec. II.4), whose steps, like fixed
//! ones, shrink as tolerance^(1/p). A growth below 1.2 is not taken, so
//! the iteration matrix, factored for the step's (c_q, c_v), is reused over runs of equal
//! steps. The ratio 2 keeps variable-step BDF2 zero-stable (ratios below 1 + √2). A rejected
//! step (err > 1, or a Newton iteration that does not converge: then h/4) is retried from the
//! state before it; a step below HMIN stops the run with the time and the estimate.

use super::error::MultibodyError;

/// Safety factor on the asymptotic step size.
const SAFETY: f64 = 0.9;
/// Bounds of the step-size ratio.
const MIN_RATIO: f64 = 0.2;
const MAX_RATIO: f64 = 2.0;
/// Growth below this ratio is not taken (the iteration matrix stays factored).
const KEEP_BELOW: f64 = 1.2;
/// Ratio after a step whose Newton iteration did not converge.
pub const NOT_CONVERGED_RATIO: f64 = 0.25;

/// Tolerances and bounds of error-controlled steps (module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepControl {
    /// Relative tolerance on the local error of q.
    pub relative: f64,
    /// Absolute tolerance on the local error of q.
    pub absolute: f64,
    /// Smallest step allowed: below it the run stops.
    pub min_step: f64,
    /// Largest step allowed.
    pub max_step: f64,
}

impl StepControl {
    /// Refuses tolerances and bounds that cannot be met.
    pub fn check(&self) -> Result<(), MultibodyError> {
        let ok = self.relative >= 0.0
            && self.absolute >= 0.0
            && self.relative + self.absolute > 0.0
            && self.min_step > 0.0
            && self.max_step >= self.min_step;
        if ok {
            Ok(())
        } else {
            Err(MultibodyError::Input(format!(
                "step control needs RTOL, ATOL >= 0 (not both zero) and 0 < HMIN <= HMAX, found RTOL = {}, ATOL = {}, HMIN = {}, HMAX = {}",
                self.relative, self.absolute, self.min_step, self.max_step
            )))
        }
    }

    /// err of the module docs for a step of size h, out of a run of duration `span`, from
    /// (q0, v0, a0) to (q1, a1).
    pub fn error(
        &self,
        h: f64,
        span: f64,
        [q0, v0, a0]: [&[f64]; 3],
        [q1, a1]: [&[f64]; 2],
    ) -> f64 {
        let mut worst = 0.0_f64;
        for i in 0..q0.len() {
            let cubic = q0[i] + h * v0[i] + h * h * (a0[i] / 3.0 + a1[i] / 6.0);
            let scale = self.absolute + self.relative * q0[i].abs().max(q1[i].abs());
            worst = worst.max((q1[i] - cubic).abs() / scale);
        }
        worst * span / h
    }

    /// The ratio of the next step to this one after a step with estimate `error` (tolerance
    /// units) by a scheme of order `order`; 1 when the growth would be small.
    pub fn ratio(&self, error: f64, order: u32) -> f64 {
        let ratio = if error > 0.0 {
            (SAFETY * error.powf(-1.0 / f64::from(order))).clamp(MIN_RATIO, MAX_RATIO)
        } else {
            MAX_RATIO
        };
        if (1.0..KEEP_BELOW).contains(&ratio) {
            1.0
        } else {
            ratio
        }
    }

    /// `h` within [HMIN, HMAX]; an error naming the time and the estimate when h < HMIN.
    pub fn bounded(&self, h: f64, time: f64, error: f64) -> Result<f64, MultibodyError> {
        if h < self.min_step {
            return Err(MultibodyError::StepTooSmall {
                time,
                step: h,
                min_step: self.min_step,
                error,
            });
        }
        Ok(h.min(self.max_step))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn control() -> StepControl {
        StepControl {
            relative: 1e-6,
            absolute: 1e-6,
            min_step: 1e-9,
            max_step: 1.0,
        }
    }

    #[test]
    fn the_estimate_vanishes_on_cubics_and_finds_the_quartic_term() {
        // q = t³: the cubic through q, v, q̈ at both ends is exact
        let (t, h) = (0.3, 0.01);
        let c = control();
        let at = |t: f64| [t * t * t, 3.0 * t * t, 6.0 * t];
        let ([q0, v0, a0], [q1, _, a1]) = (at(t), at(t + h));
        assert!(c.error(h, h, [&[q0], &[v0], &[a0]], [&[q1], &[a1]]) < 1e-9);
        // q = t⁴: the defect is −h⁴ q⁗/24, a sixteenth at h/2
        let at = |t: f64| [t.powi(4), 4.0 * t.powi(3), 12.0 * t * t];
        let ([q0, v0, a0], [q1, _, a1]) = (at(t), at(t + h));
        let e = c.error(h, h, [&[q0], &[v0], &[a0]], [&[q1], &[a1]]) * (1e-6 + 1e-6 * q1);
        let e2 = {
            let h = h / 2.0;
            let ([q0, v0, a0], [q1, _, a1]) = (at(t), at(t + h));
            c.error(h, h, [&[q0], &[v0], &[a0]], [&[q1], &[a1]]) * (1e-6 + 1e-6 * q1)
        };
        assert!((e / e2 - 16.0).abs() < 0.5, "{e} / {e2}");
    }

    #[test]
    fn the_estimate_reproduces_backward_eulers_local_error() {
        // one BDF1 step of q̈ = g from rest: q₁ = h v₁ = g h², exact g h²/2, q̈ = g at both ends
        let (g, h) = (2.0, 0.1);
        let c = StepControl {
            relative: 0.0,
            absolute: 1.0,
            ..control()
        };
        let e = c.error(h, h, [&[0.0], &[0.0], &[g]], [&[g * h * h], &[g]]);
        assert!((e - 0.5 * g * h * h).abs() < 1e-15);
    }

    #[test]
    fn the_controller_keeps_small_growth_and_bounds_the_ratio() {
        let c = control();
        assert_eq!(c.ratio(0.0, 2), MAX_RATIO);
        assert_eq!(c.ratio(1e6, 1), MIN_RATIO);
        // 0.9 · 0.6^(−1/2) = 1.16: kept
        assert_eq!(c.ratio(0.6, 2), 1.0);
        assert!((c.ratio(2.0, 2) - 0.9 / 2f64.sqrt()).abs() < 1e-15);
        assert!((c.ratio(2.0, 1) - 0.45).abs() < 1e-15);
        assert!(matches!(
            c.bounded(1e-10, 0.5, 3.0),
            Err(MultibodyError::StepTooSmall { .. })
        ));
        assert_eq!(c.bounded(5.0, 0.0, 0.1), Ok(1.0));
        assert!(
            StepControl {
                min_step: 2.0,
                ..control()
            }
            .check()
            .is_err()
        );
    }
}
