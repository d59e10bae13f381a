//! Forward sensitivities of the GGL steps ([`super::integrator`]) with respect to parameters
//! of the flexible bodies' data (thesis §6.2 and its future work: gradients of the responses
//! for a gradient-based design search).
//!
//! A converged step solves R(x; x̂, p) = 0 for x = (q, v, λ̂, μ), with x̂ = (q̂, v̂) the scheme's
//! predictions, linear in the past states. Differentiating with respect to a parameter p,
//!
//! ```text
//! J s = −(∂R/∂x̂ ŝ + ∂R/∂p),     s = dx/dp,  ŝ = dx̂/dp (the same recurrence on the past s),
//! ```
//!
//! with J = ∂R/∂x at the converged x. ∂R/∂p is exact from the bodies' data rates
//! ([`super::derivatives`]: the data are affine in p): in R₂, ∂M(q)/∂p (v − v̂) − c_v ∂f/∂p with
//! ∂f = ∂f_v + ∂f_g − ∂K q_f − ∂C q̇_f; in R₁, −∂W/∂p Φ_qᵀ μ (the correction's metric holds
//! M_ff and K_ff, [`super::correction::CorrectionWeight::rate_product`]). The step's iteration
//! matrix J̃ is not J (a modified Newton matrix: it leaves out ∂(M(q) w)/∂q, ∂f_v/∂q, ∂f_g/∂q
//! and, factored by runs of bodies, the Hessian blocks between runs), so one solve with it
//! would leave an error of the size of its contraction rate (up to 0.3). The system is solved
//! instead by the iteration s ← s − J̃⁻¹ (J s + ∂R/∂x̂ ŝ + ∂R/∂p) with the step's factored J̃,
//! which contracts as the step's Newton iteration does, to a relative change of
//! [`TOLERANCE`] (or until it stops contracting below [`NOISE_FLOOR`], the round-off of the
//! differences); J s + ∂R/∂x̂ ŝ, the derivative of R along (s, ŝ), is a central difference
//! of the step's residual (exact for the terms linear or quadratic in x — λ̂, μ, v, x̂ — and
//! with an O(ε²) error from the rotations in q, ε relative to |q| ~ 10⁻⁵).
//!
//! The start is the assembly at t₀, which does not depend on p: the constraints do not (the
//! markers sit on interface rows the pROM keeps constant) and the assembly moves the frames,
//! so s₀ = 0. Schemes and starts whose first state depends on p are refused: generalized-α
//! (its consistent accelerations) and the static equilibrium; so are controlled steps (the
//! accepted step sizes depend on p).

use super::error::MultibodyError;
use super::flexible::FlexibleBodyData;
use super::integrator::Ggl;
use super::scheme::{History, Scheme, StepForm};
use super::system::BodyId;
use crate::dynamics::newton::max_abs;
use faer::Mat;

/// Relative change of a sensitivity iterate (in q and in v) below which it has converged.
pub const TOLERANCE: f64 = 1e-8;
/// The relative change below which an iteration that no longer contracts has reached the
/// round-off of the central differences (measured on the four-bar: it wanders at 2e-9 – 1e-8
/// in v with a difference step of 1e-6).
const NOISE_FLOOR: f64 = 1e-6;
/// Iterations of one step's sensitivity before it is an error.
const MAX_ITERATIONS: usize = 60;
/// The central differences' step: ε |s_q| = DIFFERENCE_STEP (1 + |q|): truncation
/// O(DIFFERENCE_STEP²) ≈ 1e-10 relative from the rotations, round-off ≈ 1e-16/1e-5 of the
/// residual's terms.
const DIFFERENCE_STEP: f64 = 1e-5;

/// The rate of the bodies' data with respect to one parameter: ∂D/∂p of each body the
/// parameter acts on (a design variable may set parameters of several bodies).
#[derive(Debug, Clone)]
pub struct ParameterRate {
    pub bodies: Vec<(BodyId, FlexibleBodyData)>,
}

/// The sensitivity of the integrator's state to one parameter.
#[derive(Debug, Clone)]
pub struct StateSensitivity {
    pub q: Vec<f64>,
    pub v: Vec<f64>,
    /// Of the physical multipliers λ.
    pub lambda: Vec<f64>,
    /// Of q̈ = (v − v̂)/c_v.
    pub acceleration: Vec<f64>,
    mu: Vec<f64>,
    history: History,
    form: StepForm,
}

/// The forward sensitivities of a [`Ggl`] run, one per parameter (module docs).
#[derive(Debug, Clone)]
pub struct Sensitivities {
    pub rates: Vec<ParameterRate>,
    pub states: Vec<StateSensitivity>,
    /// Sensitivity iterations so far, over every step and parameter.
    pub iterations: usize,
}

impl Sensitivities {
    /// Zero sensitivities at the assembled start of `ggl` (module docs), or why a run of
    /// `scheme` has none.
    pub fn start(ggl: &Ggl, rates: Vec<ParameterRate>) -> Result<Self, MultibodyError> {
        if let Scheme::GeneralizedAlpha { .. } = ggl.scheme() {
            return Err(MultibodyError::Input(
                "forward sensitivities need BDF1 or BDF2 (generalized-α starts from accelerations that depend on the parameters)".into(),
            ));
        }
        let (n, m) = (ggl.system.size(), ggl.constraint_count());
        let zero = StateSensitivity {
            q: vec![0.0; n],
            v: vec![0.0; n],
            lambda: vec![0.0; m],
            acceleration: vec![0.0; n],
            mu: vec![0.0; m],
            history: History::start(&vec![0.0; n]),
            form: StepForm::default(),
        };
        Ok(Self {
            states: vec![zero; rates.len()],
            rates,
            iterations: 0,
        })
    }

    /// Advances every sensitivity over the step `ggl` has just taken (of size
    /// `ggl.step_size`, its factorization still in place).
    pub fn advance(&mut self, ggl: &mut Ggl) -> Result<(), MultibodyError> {
        let (x, form) = ggl.last_step();
        let form = form.clone();
        let (n, m) = (ggl.system.size(), ggl.constraint_count());
        let mut r = vec![0.0; x.len()];
        let mut phi_q = Mat::zeros(m, n);
        ggl.step_residual(&x, &form, &mut r, Some(&mut phi_q))?;
        // Φ_qᵀ μ, which ∂W/∂p acts on in R₁
        let gq_mu: Vec<f64> = (0..n)
            .map(|j| (0..m).map(|k| phi_q[(k, j)] * x[2 * n + m + k]).sum())
            .collect();
        for (rate, s) in self.rates.iter().zip(&mut self.states) {
            let b = parameter_term(ggl, &x, &form, &gq_mu, rate);
            self.iterations += s.advance(ggl, &x, &form, &b)?;
        }
        Ok(())
    }
}

/// ∂R/∂p at the converged x of the last step (module docs).
fn parameter_term(
    ggl: &mut Ggl,
    x: &[f64],
    form: &StepForm,
    gq_mu: &[f64],
    rate: &ParameterRate,
) -> Vec<f64> {
    let n = ggl.system.size();
    let (q, v) = (&x[..n], &x[n..2 * n]);
    let mut b = vec![0.0; x.len()];
    for (body, data_rate) in &rate.bodies {
        let slice = ggl.system.layout.slice(*body);
        let data = ggl.system.bodies[*body].data.clone();
        let dw = ggl.correction_weight().rate_product(
            (slice.flexible(), slice.modes),
            &data,
            data_rate,
            gq_mu,
        );
        for (bi, d) in b.iter_mut().zip(&dw) {
            *bi -= d;
        }
        let terms = ggl.system.eom_terms_rate(*body, data_rate, q, v);
        for i in 0..n {
            let momentum: f64 = (0..n)
                .map(|j| terms.mass[(i, j)] * (v[j] - form.v_hat[j]))
                .sum();
            let force = terms.quadratic_velocity[i] + terms.gravity[i]
                - terms.elastic[i]
                - terms.damping[i];
            b[n + i] += momentum - form.c_v * force;
        }
    }
    b
}

/// ε of a central difference along a direction whose q part is `dq` (and predictions `dq_hat`)
/// at positions q; `rest` the size of the rest of the direction, used when it does not move q;
/// `None` for a zero direction.
fn difference_step(q: &[f64], dq: &[f64], dq_hat: &[f64], rest: f64) -> Option<f64> {
    let size = max_abs(dq).max(max_abs(dq_hat));
    let size = if size > 0.0 { size } else { rest };
    (size > 0.0).then(|| DIFFERENCE_STEP * (1.0 + max_abs(q)) / size)
}

impl StateSensitivity {
    /// One step of this parameter's sensitivity (module docs), with b = ∂R/∂p; the number of
    /// iterations it took.
    fn advance(
        &mut self,
        ggl: &mut Ggl,
        x: &[f64],
        form: &StepForm,
        b: &[f64],
    ) -> Result<usize, MultibodyError> {
        let (n, m) = (ggl.system.size(), ggl.constraint_count());
        let h = ggl.step_size;
        let scheme = ggl.scheme();
        self.history.form(
            scheme,
            h,
            &self.q,
            &self.v,
            &self.acceleration,
            &mut self.form,
        );
        let c_v = form.c_v;
        // the predictor of the step, differentiated
        let mut s: Vec<f64> = (self.q.iter().zip(&self.v).map(|(a, b)| a + h * b))
            .chain(self.v.iter().copied())
            .chain(self.lambda.iter().map(|l| c_v * l))
            .chain(self.mu.iter().copied())
            .collect();
        let mut shifted = form.clone();
        let (mut plus, mut minus) = (vec![0.0; x.len()], vec![0.0; x.len()]);
        let mut moved = vec![0.0; x.len()];
        let mut previous = f64::INFINITY;
        for iteration in 1..=MAX_ITERATIONS {
            // r = J s + ∂R/∂x̂ ŝ + ∂R/∂p
            let mut r = b.to_vec();
            let step = difference_step(&x[..n], &s[..n], &self.form.q_hat, max_abs(&s));
            if let Some(eps) = step {
                for sign in [1.0, -1.0] {
                    let e = sign * eps;
                    for (i, m) in moved.iter_mut().enumerate() {
                        *m = x[i] + e * s[i];
                    }
                    for i in 0..n {
                        shifted.q_hat[i] = form.q_hat[i] + e * self.form.q_hat[i];
                        shifted.v_hat[i] = form.v_hat[i] + e * self.form.v_hat[i];
                    }
                    let out = if sign > 0.0 { &mut plus } else { &mut minus };
                    ggl.step_residual(&moved, &shifted, out, None)?;
                }
                for (ri, (p, m)) in r.iter_mut().zip(plus.iter().zip(&minus)) {
                    *ri += (p - m) / (2.0 * eps);
                }
            }
            ggl.iteration_solve(&mut r)?;
            for (si, d) in s.iter_mut().zip(&r) {
                *si -= d;
            }
            let relative = |range: std::ops::Range<usize>| {
                let size = max_abs(&s[range.clone()]);
                let change = max_abs(&r[range]);
                if change == 0.0 { 0.0 } else { change / size }
            };
            let change = relative(0..n).max(relative(n..2 * n));
            // converged, or stalled at the differences' round-off
            let stalled = change <= NOISE_FLOOR && change >= previous;
            previous = change;
            if change <= TOLERANCE || stalled {
                self.history
                    .advance(scheme, h, &self.q, &self.v, &s[n..2 * n]);
                for i in 0..n {
                    self.acceleration[i] = (s[n + i] - self.form.v_hat[i]) / c_v;
                }
                self.q.copy_from_slice(&s[..n]);
                self.v.copy_from_slice(&s[n..2 * n]);
                for k in 0..m {
                    self.lambda[k] = s[2 * n + k] / c_v;
                    self.mu[k] = s[2 * n + m + k];
                }
                return Ok(iteration);
            }
        }
        Err(MultibodyError::Input(format!(
            "the forward sensitivities did not converge in {MAX_ITERATIONS} iterations at t = {}",
            ggl.time
        )))
    }

    /// The derivative along this sensitivity of a quantity `f` of the integrator's state
    /// (q, v, λ, q̈): a central difference, the state restored after.
    pub fn along(&self, ggl: &mut Ggl, f: impl Fn(&Ggl) -> f64) -> f64 {
        let Some(eps) = difference_step(
            &ggl.q,
            &self.q,
            &[],
            [&self.v, &self.lambda, &self.acceleration]
                .map(|x| max_abs(x))
                .into_iter()
                .fold(0.0, f64::max),
        ) else {
            return 0.0;
        };
        let saved = [&ggl.q, &ggl.v, &ggl.lambda, &ggl.acceleration].map(|x| x.to_vec());
        let at = |e: f64, ggl: &mut Ggl| {
            let pairs = [
                (&mut ggl.q, &self.q),
                (&mut ggl.v, &self.v),
                (&mut ggl.lambda, &self.lambda),
                (&mut ggl.acceleration, &self.acceleration),
            ];
            for ((state, rate), base) in pairs.into_iter().zip(&saved) {
                for ((x, r), b) in state.iter_mut().zip(rate).zip(base) {
                    *x = b + e * r;
                }
            }
            f(ggl)
        };
        let (plus, minus) = (at(eps, ggl), at(-eps, ggl));
        let [q, v, lambda, a] = saved;
        (ggl.q, ggl.v, ggl.lambda, ggl.acceleration) = (q, v, lambda, a);
        (plus - minus) / (2.0 * eps)
    }
}

/// ½ q̇ᵀ ∂M/∂p q̇ at the integrator's state: the kinetic energy's change with the
/// bodies' data at a fixed state (its change with the state is [`StateSensitivity::along`]).
pub fn kinetic_energy_rate(ggl: &Ggl, rate: &ParameterRate) -> f64 {
    let (q, v) = (&ggl.q, &ggl.v);
    (rate.bodies.iter())
        .map(|(body, data)| {
            let m = ggl.system.eom_terms_rate(*body, data, q, v).mass;
            let product: f64 = (0..v.len())
                .map(|i| v[i] * (0..v.len()).map(|j| m[(i, j)] * v[j]).sum::<f64>())
                .sum();
            0.5 * product
        })
        .sum()
}
