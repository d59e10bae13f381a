//! Time discretizations of the GGL equations (eq. 2.60) as one step form. Each scheme turns a
//! step from t_n to t_{n+1} = t_n + h into equations in the unknowns (q, v, λ̂, μ) at t_{n+1}
//!
//! ```text
//! q − q̂ − c_q v − W Φ_qᵀ μ = 0,   M(q) (v − v̂) − c_v f(q, v, t) + Φ_qᵀ λ̂ = 0,
//! Φ_q v + Φ_t = 0,                Φ(q, t) = 0,
//! ```
//!
//! with λ̂ = c_v λ, q̈_{n+1} = (v − v̂)/c_v and W the weight of the position correction, the same
//! for every scheme ([`super::correction`]); the predictions (q̂, v̂) and the factors c_q, c_v
//! come from the scheme and the past states:
//!
//! | scheme | q̂ | v̂ | c_q | c_v |
//! |---|---|---|---|---|
//! | BDF1 (eq. 2.61) | q_n | v_n | h | h |
//! | BDF2 | (4 q_n − q_{n−1})/3 | (4 v_n − v_{n−1})/3 | 2h/3 | 2h/3 |
//! | generalized-α | q_n + h(1 − β/γ) v_n + h²(½ − β/γ) a_n | v_n + h(1 − γ) a_n − c_v (α_m a_n − α_f q̈_n)/(1 − α_f) | hβ/γ | h γ (1 − α_f)/(1 − α_m) |
//!
//! BDF2 starts with one BDF1 step (its local error O(h²) keeps the global order 2). On fixed
//! steps it restarts so whenever the step size changes; under step-size control
//! ([`History::vary_steps`]) it takes the variable-step coefficients instead: with the ratio
//! ω = h/h_{n−1}, q̂ = ((1 + ω)² q_n − ω² q_{n−1})/(1 + 2ω) and c_q = c_v = h (1 + ω)/(1 + 2ω)
//! (Hairer, Nørsett & Wanner I, sec. III.5), the constant-step row at ω = 1 and zero-stable
//! for ω < 1 + √2. The generalized-α rows are the scheme of Chung & Hulbert
//! (J. Appl. Mech. 60, 1993) in the form of Arnold & Brüls (Multibody Syst. Dyn. 18, 2007),
//!
//! ```text
//! q_{n+1} = q_n + h v_n + h² (½ − β) a_n + h² β a_{n+1} + W Φ_qᵀ μ,
//! v_{n+1} = v_n + h (1 − γ) a_n + h γ a_{n+1},
//! (1 − α_m) a_{n+1} + α_m a_n = (1 − α_f) q̈_{n+1} + α_f q̈_n,
//! ```
//!
//! with a the pseudo-acceleration, eliminated through the v row; the W Φ_qᵀ μ term and the
//! velocity constraint are the stabilized index-2 variant whose global errors in q, v, q̈ and λ
//! are O(h²) (Arnold, Brüls & Cardona, Numer. Math. 129, 2015), without the index-3 form's
//! order reduction in λ. The parameters follow from the spectral radius at infinity ρ∞ ∈ [0, 1]:
//! α_m = (2ρ∞ − 1)/(ρ∞ + 1), α_f = ρ∞/(ρ∞ + 1), γ = ½ − α_m + α_f, β = ¼ (γ + ½)².
//! ρ∞ = 1 dissipates nothing (the trapezoidal rule's energy behaviour), ρ∞ = 0 damps the
//! modes above 1/h in one step. The scheme starts from the consistent accelerations q̈₀ = a₀.

use super::error::MultibodyError;
pub use crate::dynamics::nonlinear::AlphaParameters;

/// The time discretization of a [`super::Ggl`] integrator.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Scheme {
    /// Backward Euler (thesis eq. 2.61): first order, dissipative.
    Bdf1,
    /// Two-step backward differentiation: second order, L-stable.
    Bdf2,
    /// Generalized-α with the spectral radius ρ∞ at infinite frequency: second order.
    GeneralizedAlpha { spectral_radius: f64 },
}

impl Scheme {
    /// Refuses parameters outside the scheme's range.
    pub fn check(&self) -> Result<(), MultibodyError> {
        match *self {
            Scheme::GeneralizedAlpha { spectral_radius }
                if !(0.0..=1.0).contains(&spectral_radius) =>
            {
                Err(MultibodyError::Input(format!(
                    "generalized-α spectral radius {spectral_radius} must lie in [0, 1]"
                )))
            }
            _ => Ok(()),
        }
    }

    /// Whether the scheme needs the consistent accelerations at the start.
    pub fn needs_initial_accelerations(&self) -> bool {
        matches!(self, Scheme::GeneralizedAlpha { .. })
    }

    /// The order of the global error: 1 for BDF1, 2 for BDF2 and generalized-α.
    pub fn order(&self) -> u32 {
        match self {
            Scheme::Bdf1 => 1,
            Scheme::Bdf2 | Scheme::GeneralizedAlpha { .. } => 2,
        }
    }
}

/// The past a scheme needs beyond (q_n, v_n, q̈_n).
#[derive(Debug, Clone, Default)]
pub struct History {
    /// (q_{n−1}, v_{n−1}) and the size of the step that left them, once one step is done.
    previous: Option<(Vec<f64>, Vec<f64>, f64)>,
    /// The generalized-α pseudo-acceleration a_n.
    pseudo_acceleration: Vec<f64>,
    /// BDF2 with variable-step coefficients rather than a restart when h changes.
    variable: bool,
}

/// The step form of the module docs.
#[derive(Debug, Clone, Default)]
pub struct StepForm {
    pub q_hat: Vec<f64>,
    pub v_hat: Vec<f64>,
    pub c_q: f64,
    pub c_v: f64,
}

impl History {
    /// The history at the start, with the accelerations q̈₀ (a₀ = q̈₀).
    pub fn start(acceleration: &[f64]) -> Self {
        Self {
            previous: None,
            pseudo_acceleration: acceleration.to_vec(),
            variable: false,
        }
    }

    /// BDF2 keeps its order across step-size changes (module docs) instead of restarting.
    pub fn vary_steps(&mut self) {
        self.variable = true;
    }

    /// The step form of `scheme` for a step of size h from (q_n, v_n, q̈_n) into `form`.
    pub fn form(
        &self,
        scheme: Scheme,
        h: f64,
        q: &[f64],
        v: &[f64],
        acceleration: &[f64],
        form: &mut StepForm,
    ) {
        form.q_hat.clear();
        form.v_hat.clear();
        match (scheme, &self.previous) {
            (Scheme::Bdf2, Some((q1, v1, h1))) if *h1 == h => {
                let c = 2.0 * h / 3.0;
                form.q_hat
                    .extend(q.iter().zip(q1).map(|(a, b)| (4.0 * a - b) / 3.0));
                form.v_hat
                    .extend(v.iter().zip(v1).map(|(a, b)| (4.0 * a - b) / 3.0));
                (form.c_q, form.c_v) = (c, c);
            }
            (Scheme::Bdf2, Some((q1, v1, h1))) if self.variable => {
                let w = h / h1;
                let (a, b, d) = ((1.0 + w) * (1.0 + w), w * w, 1.0 + 2.0 * w);
                form.q_hat
                    .extend(q.iter().zip(q1).map(|(x, y)| (a * x - b * y) / d));
                form.v_hat
                    .extend(v.iter().zip(v1).map(|(x, y)| (a * x - b * y) / d));
                let c = h * (1.0 + w) / d;
                (form.c_q, form.c_v) = (c, c);
            }
            (Scheme::GeneralizedAlpha { spectral_radius }, _) => {
                let p = AlphaParameters::from_spectral_radius(spectral_radius);
                let a = &self.pseudo_acceleration;
                let c_v = h * p.gamma * (1.0 - p.alpha_f) / (1.0 - p.alpha_m);
                for i in 0..q.len() {
                    form.q_hat.push(
                        q[i] + h * (1.0 - p.beta / p.gamma) * v[i]
                            + h * h * (0.5 - p.beta / p.gamma) * a[i],
                    );
                    form.v_hat.push(
                        v[i] + h * (1.0 - p.gamma) * a[i]
                            - c_v * (p.alpha_m * a[i] - p.alpha_f * acceleration[i])
                                / (1.0 - p.alpha_f),
                    );
                }
                (form.c_q, form.c_v) = (h * p.beta / p.gamma, c_v);
            }
            _ => {
                form.q_hat.extend_from_slice(q);
                form.v_hat.extend_from_slice(v);
                (form.c_q, form.c_v) = (h, h);
            }
        }
    }

    /// Records a converged step of size h from (q_n, v_n) to velocities `v_next`.
    pub fn advance(&mut self, scheme: Scheme, h: f64, q: &[f64], v: &[f64], v_next: &[f64]) {
        if let Scheme::GeneralizedAlpha { spectral_radius } = scheme {
            // v_{n+1} = v_n + h (1 − γ) a_n + h γ a_{n+1}
            let gamma = AlphaParameters::from_spectral_radius(spectral_radius).gamma;
            for (i, a) in self.pseudo_acceleration.iter_mut().enumerate() {
                *a = (v_next[i] - v[i] - h * (1.0 - gamma) * *a) / (h * gamma);
            }
        }
        match &mut self.previous {
            Some((q1, v1, h1)) => {
                q1.copy_from_slice(q);
                v1.copy_from_slice(v);
                *h1 = h;
            }
            None => self.previous = Some((q.to_vec(), v.to_vec(), h)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chung_hulbert_parameters_at_the_ends_of_the_range() {
        // ρ∞ = 1: α_m = α_f = ½, γ = ½, β = ¼ (the trapezoidal rule)
        let p = AlphaParameters::from_spectral_radius(1.0);
        assert_eq!(
            (p.alpha_m, p.alpha_f, p.gamma, p.beta),
            (0.5, 0.5, 0.5, 0.25)
        );
        // ρ∞ = 0: α_m = −1, α_f = 0, γ = 3/2, β = 1
        let p = AlphaParameters::from_spectral_radius(0.0);
        assert_eq!(
            (p.alpha_m, p.alpha_f, p.gamma, p.beta),
            (-1.0, 0.0, 1.5, 1.0)
        );
    }

    #[test]
    fn variable_step_bdf2_is_exact_for_constant_acceleration() {
        // steps 0.1, 0.15, 0.06, 0.12: after the BDF1 start every step is exact on q = ½ g t²
        let g = 3.0;
        let mut history = History::start(&[g]);
        history.vary_steps();
        let mut form = StepForm::default();
        let (mut t, mut q, mut v) = (0.0, vec![0.0], vec![0.0]);
        for (n, h) in [0.1, 0.15, 0.06, 0.12].into_iter().enumerate() {
            history.form(Scheme::Bdf2, h, &q, &v, &[g], &mut form);
            t += h;
            let (q_next, v_next) = (0.5 * g * t * t, g * t);
            if n > 0 {
                assert!((q_next - form.q_hat[0] - form.c_q * v_next).abs() < 1e-12);
                assert!((v_next - form.v_hat[0] - form.c_v * g).abs() < 1e-12);
            }
            history.advance(Scheme::Bdf2, h, &q, &v, &[v_next]);
            (q, v) = (vec![q_next], vec![v_next]);
        }
    }

    #[test]
    fn every_scheme_is_exact_for_constant_acceleration() {
        // q = ½ g t², v = g t, q̈ = g: BDF1 has O(h²) local error, BDF2 and generalized-α none
        let (g, h) = (3.0, 0.1);
        for scheme in [
            Scheme::Bdf2,
            Scheme::GeneralizedAlpha {
                spectral_radius: 0.6,
            },
        ] {
            let mut history = History::start(&[g]);
            let mut form = StepForm::default();
            let (mut q, mut v) = (vec![0.0], vec![0.0]);
            for n in 0..5 {
                history.form(scheme, h, &q, &v, &[g], &mut form);
                let t = (n + 1) as f64 * h;
                let (q_next, v_next) = (0.5 * g * t * t, g * t);
                if n > 0 || scheme != Scheme::Bdf2 {
                    assert!((q_next - form.q_hat[0] - form.c_q * v_next).abs() < 1e-12);
                    assert!((v_next - form.v_hat[0] - form.c_v * g).abs() < 1e-12);
                }
                history.advance(scheme, h, &q, &v, &[v_next]);
                (q, v) = (vec![q_next], vec![v_next]);
            }
        }
    }
}
