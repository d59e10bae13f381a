//! Implicit time integration of nonlinear second-order systems in residual form,
//! r(t, q, q̇, q̈) = 0 (e.g. r = M(q) q̈ + f_int(q, q̇) − f_ext(t)), with Newton's method in each
//! step: the same BDF1 (thesis eq. 2.61), BDF2 and generalized-α as
//! [`super::integrators`], whose linear formulas they reduce to for a linear residual (test
//! `a_linear_system_through_the_residual_form_equals_the_linear_integrators`).
//!
//! Each method writes the new state as an affine function of one unknown, the displacement
//! x = q_{n+1}, and the balance as r at one evaluation point (t_e, q_e, v_e, a_e), itself affine
//! in x:
//!
//! - BDF1 / BDF2: v = (c x − r_q)/Δt, a = (c v − r_v)/Δt with (c, r) = (1, x_n) for BDF1 and
//!   (3/2, 2 x_n − x_{n−1}/2) for BDF2 (started with one BDF1 step), evaluated at t_{n+1};
//! - generalized-α (Chung & Hulbert 1993): a_{n+1} = (x − q̃)/(βΔt²), v_{n+1} = ṽ + γΔt a_{n+1}
//!   (q̃, ṽ of [`super::integrators`]), evaluated at the generalized midpoints
//!   q_e = (1−α_f) x + α_f q_n, v_e = (1−α_f) v_{n+1} + α_f v_n, a_e = (1−α_m) a_{n+1} + α_m a_n,
//!   t_e = t_{n+1} − α_f Δt: for a linear residual, the method's balance
//!   M a_{n+1−α_m} + C v_{n+1−α_f} + K q_{n+1−α_f} = f(t_{n+1−α_f}).
//!
//! The Newton iteration matrix dr/dx = c_a ∂r/∂a + c_v ∂r/∂v + c_q ∂r/∂q at the evaluation point
//! has the coefficients of the linear methods' effective matrix ([`Combination`] order
//! [c_a, c_v, c_q], as [c_m, c_c, c_k]); the system factors and solves it
//! ([`NonlinearSystem::factor`], [`NonlinearSystem::solve`]), so that a dense, sparse or block
//! (KKT) factorization and its reuse stay the system's choice. [`JacobianUpdate`] says how often
//! the integrator asks for a new factorization; every step reports its iterations, the residual
//! and the factorizations to the observer ([`NewtonStats`]), and a step that does not converge
//! stops the run with its time and residual ([`IntegrationError::Newton`]).

use super::integrators::{Combination, IntegrationError, Method, Run, StepState};
pub use super::newton::{JacobianUpdate, NewtonStats};
use super::newton::{NewtonDriver, NewtonPolicy, StepEquations, max_abs};

/// A second-order system in residual form (see the module documentation).
pub trait NonlinearSystem {
    /// Number of unknowns.
    fn size(&self) -> usize;
    /// r(t, q, q̇, q̈) into `r`: zero where the equation of motion holds.
    fn residual(
        &mut self,
        t: f64,
        q: &[f64],
        v: &[f64],
        a: &[f64],
        r: &mut [f64],
    ) -> Result<(), IntegrationError>;
    /// Factor the iteration matrix c[0] ∂r/∂q̈ + c[1] ∂r/∂q̇ + c[2] ∂r/∂q at (t, q, q̇, q̈).
    #[allow(clippy::too_many_arguments)]
    fn factor(
        &mut self,
        t: f64,
        q: &[f64],
        v: &[f64],
        a: &[f64],
        c: Combination,
    ) -> Result<(), IntegrationError>;
    /// x ← (the last factored iteration matrix)⁻¹ x.
    fn solve(&mut self, x: &mut [f64]) -> Result<(), IntegrationError>;
}

/// Newton settings ([`super::newton`]; with `Reuse` the matrix is refactored when the
/// corrections contract by less than half). A step has converged when its last correction
/// satisfies ‖δ‖∞ ≤ `relative` ‖q_{n+1}‖∞ + `absolute`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Newton {
    pub relative: f64,
    /// In the units of q: the smallest displacement of interest.
    pub absolute: f64,
    pub max_iterations: usize,
    pub update: JacobianUpdate,
}

impl Default for Newton {
    fn default() -> Self {
        Newton {
            relative: 1e-10,
            absolute: 1e-14,
            max_iterations: 20,
            update: JacobianUpdate::EveryIteration,
        }
    }
}

/// Integrate `run.steps` steps of size `run.dt` from (q0, v0) at t0 with `newton`. `observe`
/// sees the initial state (step 0, q̈₀ from r(t0, q0, v0, q̈₀) = 0) and every step, with its
/// Newton statistics. A step allocates nothing.
pub fn integrate_nonlinear<S: NonlinearSystem>(
    system: &mut S,
    method: Method,
    run: Run,
    newton: Newton,
    q0: &[f64],
    v0: &[f64],
    mut observe: impl FnMut(&StepState<'_>, &NewtonStats),
) -> Result<(), IntegrationError> {
    let n = system.size();
    super::integrators::check_start(n, q0, v0, run.dt)?;
    let scheme = Scheme::new(method, run.dt)?;
    let mut solver = Solver::new(n, newton);
    let mut now = Kinematics {
        q: q0.to_vec(),
        v: v0.to_vec(),
        a: vec![0.0; n],
    };
    let stats = solver.initial_acceleration(system, run.t0, &mut now)?;
    observe(&now.at(0, run.t0), &stats);
    let mut before = now.clone();
    let mut form = StepForm::new(n);
    for step in 1..=run.steps {
        let t = run.t0 + step as f64 * run.dt;
        scheme.fill(step, &now, &before, &mut form);
        let stats = solver.step(system, &form, step, t, &now)?;
        std::mem::swap(&mut before, &mut now);
        now.copy_from(&solver.new);
        observe(&now.at(step, t), &stats);
    }
    Ok(())
}

/// q, q̇, q̈ at one instant.
#[derive(Debug, Clone)]
struct Kinematics {
    q: Vec<f64>,
    v: Vec<f64>,
    a: Vec<f64>,
}

impl Kinematics {
    fn zeros(n: usize) -> Self {
        Kinematics {
            q: vec![0.0; n],
            v: vec![0.0; n],
            a: vec![0.0; n],
        }
    }

    fn copy_from(&mut self, other: &Kinematics) {
        self.q.copy_from_slice(&other.q);
        self.v.copy_from_slice(&other.v);
        self.a.copy_from_slice(&other.a);
    }

    fn at(&self, step: usize, time: f64) -> StepState<'_> {
        StepState {
            step,
            time,
            q: &self.q,
            v: &self.v,
            a: &self.a,
            motion: &[],
        }
    }
}

/// The generalized-α parameters of Chung & Hulbert (J. Appl. Mech. 60, 1993) for the spectral
/// radius at infinity ρ∞ ∈ [0, 1]: α_m = (2ρ∞ − 1)/(ρ∞ + 1), α_f = ρ∞/(ρ∞ + 1),
/// γ = ½ − α_m + α_f, β = ¼ (γ + ½)² (also the GGL multibody scheme's, `multibody::scheme`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AlphaParameters {
    pub alpha_m: f64,
    pub alpha_f: f64,
    pub gamma: f64,
    pub beta: f64,
}

impl AlphaParameters {
    /// Chung & Hulbert's optimal set for ρ∞.
    pub fn from_spectral_radius(rho: f64) -> Self {
        let alpha_m = (2.0 * rho - 1.0) / (rho + 1.0);
        let alpha_f = rho / (rho + 1.0);
        let gamma = 0.5 - alpha_m + alpha_f;
        Self {
            alpha_m,
            alpha_f,
            gamma,
            beta: 0.25 * (gamma + 0.5).powi(2),
        }
    }
}

/// A method's constants (see the module documentation).
enum Scheme {
    Bdf {
        dt: f64,
        second_order: bool,
    },
    GeneralizedAlpha {
        dt: f64,
        am: f64,
        af: f64,
        beta: f64,
        gamma: f64,
    },
}

impl Scheme {
    fn new(method: Method, dt: f64) -> Result<Self, IntegrationError> {
        Ok(match method {
            Method::Bdf1 | Method::Bdf2 => Scheme::Bdf {
                dt,
                second_order: method == Method::Bdf2,
            },
            Method::GeneralizedAlpha { rho_inf } => {
                if !(0.0..=1.0).contains(&rho_inf) {
                    return Err(IntegrationError::SpectralRadius(rho_inf));
                }
                let p = AlphaParameters::from_spectral_radius(rho_inf);
                Scheme::GeneralizedAlpha {
                    dt,
                    am: p.alpha_m,
                    af: p.alpha_f,
                    gamma: p.gamma,
                    beta: p.beta,
                }
            }
        })
    }

    /// The affine maps of step `step` from the current state `now` (and the one `before` it).
    fn fill(&self, step: usize, now: &Kinematics, before: &Kinematics, form: &mut StepForm) {
        let n = now.q.len();
        let off = &mut form.offsets;
        match *self {
            Scheme::Bdf { dt, second_order } => {
                let c = if second_order && step >= 2 { 1.5 } else { 1.0 };
                // v = (c x − r_q)/Δt, a = (c v − r_v)/Δt
                for i in 0..n {
                    let (r_q, r_v) = if c == 1.0 {
                        (now.q[i], now.v[i])
                    } else {
                        (
                            2.0 * now.q[i] - 0.5 * before.q[i],
                            2.0 * now.v[i] - 0.5 * before.v[i],
                        )
                    };
                    off.v[i] = -r_q / dt;
                    off.a[i] = (c * off.v[i] - r_v) / dt;
                }
                form.slopes = [1.0, c / dt, c * c / (dt * dt)];
                form.weights = [1.0; 3];
                form.time_offset = 0.0;
            }
            Scheme::GeneralizedAlpha {
                dt,
                am,
                af,
                beta,
                gamma,
            } => {
                let bdt2 = beta * dt * dt;
                // a_{n+1} = (x − q̃)/(βΔt²), v_{n+1} = ṽ + γΔt a_{n+1}
                for i in 0..n {
                    let q_pred = now.q[i] + dt * now.v[i] + (0.5 - beta) * dt * dt * now.a[i];
                    let v_pred = now.v[i] + (1.0 - gamma) * dt * now.a[i];
                    off.a[i] = -q_pred / bdt2;
                    off.v[i] = v_pred + gamma * dt * off.a[i];
                }
                form.slopes = [1.0, gamma * dt / bdt2, 1.0 / bdt2];
                form.weights = [1.0 - af, 1.0 - af, 1.0 - am];
                form.time_offset = -af * dt;
            }
        }
    }
}

/// One step's affine maps: the new state is (q, v, a)_{n+1} = slopes · x + offsets (q's
/// offset is zero), and the evaluation point w ∘ (q, v, a)_{n+1} + (1 − w) ∘ (q, v, a)_n at
/// t_{n+1} + time_offset, with w = `weights` per kinematic quantity.
struct StepForm {
    slopes: [f64; 3],
    offsets: Kinematics,
    weights: [f64; 3],
    time_offset: f64,
}

impl StepForm {
    fn new(n: usize) -> Self {
        StepForm {
            slopes: [0.0; 3],
            offsets: Kinematics::zeros(n),
            weights: [1.0; 3],
            time_offset: 0.0,
        }
    }

    /// Iteration-matrix coefficients [c_a, c_v, c_q] = w ∘ slopes, q̈ first.
    fn coefficients(&self) -> Combination {
        let (s, w) = (self.slopes, self.weights);
        [w[2] * s[2], w[1] * s[1], w[0] * s[0]]
    }
}

/// The contraction rate above which `JacobianUpdate::Reuse` refactors.
const SLOW_RATE: f64 = 0.5;

/// Newton's driver and the step's states.
struct Solver {
    newton: Newton,
    driver: NewtonDriver,
    /// The state at t_{n+1} and at the evaluation point.
    new: Kinematics,
    eval: Kinematics,
    /// The coefficients of the system's current factorization (None: none, or stale).
    factored: Option<Combination>,
}

/// The equations of one step in x = q_{n+1}: r at the evaluation point.
struct Step<'a, S> {
    system: &'a mut S,
    form: &'a StepForm,
    old: &'a Kinematics,
    new: &'a mut Kinematics,
    eval: &'a mut Kinematics,
    t_eval: f64,
    newton: Newton,
}

impl<S: NonlinearSystem> StepEquations for Step<'_, S> {
    type Error = IntegrationError;
    fn residual(&mut self, x: &[f64], r: &mut [f64]) -> Result<(), IntegrationError> {
        evaluate(self.form, self.old, x, self.new, self.eval);
        let Kinematics { q, v, a } = &*self.eval;
        self.system.residual(self.t_eval, q, v, a, r)
    }
    fn factor(&mut self, _: &[f64]) -> Result<(), IntegrationError> {
        let Kinematics { q, v, a } = &*self.eval;
        self.system
            .factor(self.t_eval, q, v, a, self.form.coefficients())
    }
    fn solve(&mut self, r: &mut [f64]) -> Result<(), IntegrationError> {
        self.system.solve(r)
    }
    fn correction_size(&self, x: &[f64], dx: &[f64]) -> f64 {
        scaled_correction(&self.newton, x, dx)
    }
}

/// The equation of the initial acceleration in x = q̈₀: r(t0, q0, v0, x).
struct InitialAcceleration<'a, S> {
    system: &'a mut S,
    t0: f64,
    q: &'a [f64],
    v: &'a [f64],
    newton: Newton,
}

impl<S: NonlinearSystem> StepEquations for InitialAcceleration<'_, S> {
    type Error = IntegrationError;
    fn residual(&mut self, x: &[f64], r: &mut [f64]) -> Result<(), IntegrationError> {
        self.system.residual(self.t0, self.q, self.v, x, r)
    }
    fn factor(&mut self, x: &[f64]) -> Result<(), IntegrationError> {
        self.system
            .factor(self.t0, self.q, self.v, x, [1.0, 0.0, 0.0])
    }
    fn solve(&mut self, r: &mut [f64]) -> Result<(), IntegrationError> {
        self.system.solve(r)
    }
    fn correction_size(&self, x: &[f64], dx: &[f64]) -> f64 {
        scaled_correction(&self.newton, x, dx)
    }
}

/// ‖δ‖∞ / (`relative` ‖x‖∞ + `absolute`).
fn scaled_correction(newton: &Newton, x: &[f64], dx: &[f64]) -> f64 {
    let correction = max_abs(dx);
    if correction == 0.0 {
        return 0.0;
    }
    correction / (newton.relative * max_abs(x) + newton.absolute)
}

impl Solver {
    fn new(n: usize, newton: Newton) -> Self {
        let policy = NewtonPolicy {
            max_iterations: newton.max_iterations,
            update: newton.update,
            slow_rate: SLOW_RATE,
        };
        Solver {
            newton,
            driver: NewtonDriver::new(n, policy),
            new: Kinematics::zeros(n),
            eval: Kinematics::zeros(n),
            factored: None,
        }
    }

    /// q̈₀ from r(t0, q0, v0, q̈₀) = 0 by Newton in q̈ (iteration matrix ∂r/∂q̈), into `now.a`.
    fn initial_acceleration<S: NonlinearSystem>(
        &mut self,
        system: &mut S,
        t0: f64,
        now: &mut Kinematics,
    ) -> Result<NewtonStats, IntegrationError> {
        self.driver.invalidate();
        self.driver.predictor_mut().copy_from_slice(&now.a);
        let mut equations = InitialAcceleration {
            system,
            t0,
            q: &now.q,
            v: &now.v,
            newton: self.newton,
        };
        let outcome = self.driver.solve(&mut equations)?;
        self.driver.invalidate();
        if !outcome.converged {
            return Err(IntegrationError::Newton {
                step: 0,
                time: t0,
                iterations: outcome.stats.iterations,
                residual: outcome.stats.residual,
            });
        }
        now.a.copy_from_slice(self.driver.solution());
        Ok(outcome.stats)
    }

    /// One step from `now` to t: Newton on x = q_{n+1} from the predictor x = q_n, into `new`.
    fn step<S: NonlinearSystem>(
        &mut self,
        system: &mut S,
        form: &StepForm,
        step: usize,
        t: f64,
        now: &Kinematics,
    ) -> Result<NewtonStats, IntegrationError> {
        let coefficients = form.coefficients();
        if self.factored != Some(coefficients) {
            self.driver.invalidate();
        }
        self.driver.predictor_mut().copy_from_slice(&now.q);
        let mut equations = Step {
            system,
            form,
            old: now,
            new: &mut self.new,
            eval: &mut self.eval,
            t_eval: t + form.time_offset,
            newton: self.newton,
        };
        let outcome = self.driver.solve(&mut equations)?;
        self.factored = Some(coefficients);
        if !outcome.converged {
            return Err(IntegrationError::Newton {
                step,
                time: t,
                iterations: outcome.stats.iterations,
                residual: outcome.stats.residual,
            });
        }
        evaluate(
            form,
            now,
            self.driver.solution(),
            &mut self.new,
            &mut self.eval,
        );
        Ok(outcome.stats)
    }
}

/// The state at t_{n+1} (`new`) and at the evaluation point (`eval`) for the iterate x.
fn evaluate(
    form: &StepForm,
    old: &Kinematics,
    x: &[f64],
    new: &mut Kinematics,
    eval: &mut Kinematics,
) {
    let [s_q, s_v, s_a] = form.slopes;
    let [w_q, w_v, w_a] = form.weights;
    let off = &form.offsets;
    for (i, &x) in x.iter().enumerate() {
        new.q[i] = s_q * x;
        new.v[i] = s_v * x + off.v[i];
        new.a[i] = s_a * x + off.a[i];
        eval.q[i] = w_q * new.q[i] + (1.0 - w_q) * old.q[i];
        eval.v[i] = w_v * new.v[i] + (1.0 - w_v) * old.v[i];
        eval.a[i] = w_a * new.a[i] + (1.0 - w_a) * old.a[i];
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamics::integrators::tests::{ForcedSdof, METHODS};
    use crate::dynamics::integrators::{LinearSystem, integrate};
    use faer::Mat;
    use faer::linalg::solvers::{PartialPivLu, Solve};

    /// r = M a + C v + K q − f(t) through the residual form, with a dense LU of the iteration
    /// matrix.
    struct Linear<'a, F: Fn(f64, &mut [f64])> {
        m: &'a Mat<f64>,
        c: &'a Mat<f64>,
        k: &'a Mat<f64>,
        load: F,
        lu: Option<PartialPivLu<f64>>,
        factorizations: usize,
    }

    impl<F: Fn(f64, &mut [f64])> NonlinearSystem for Linear<'_, F> {
        fn size(&self) -> usize {
            self.m.nrows()
        }
        fn residual(
            &mut self,
            t: f64,
            q: &[f64],
            v: &[f64],
            a: &[f64],
            r: &mut [f64],
        ) -> Result<(), IntegrationError> {
            (self.load)(t, r);
            r.iter_mut().for_each(|r| *r = -*r);
            for (mat, x) in [(self.m, a), (self.c, v), (self.k, q)] {
                for (i, r) in r.iter_mut().enumerate() {
                    *r += (0..x.len()).map(|j| mat[(i, j)] * x[j]).sum::<f64>();
                }
            }
            Ok(())
        }
        fn factor(
            &mut self,
            _: f64,
            _: &[f64],
            _: &[f64],
            _: &[f64],
            c: Combination,
        ) -> Result<(), IntegrationError> {
            let n = self.size();
            let j = Mat::from_fn(n, n, |i, j| {
                c[0] * self.m[(i, j)] + c[1] * self.c[(i, j)] + c[2] * self.k[(i, j)]
            });
            self.lu = Some(j.partial_piv_lu());
            self.factorizations += 1;
            Ok(())
        }
        fn solve(&mut self, x: &mut [f64]) -> Result<(), IntegrationError> {
            let n = x.len();
            let lu = self.lu.as_ref().expect("factor before solve");
            let y = lu.solve(Mat::from_fn(n, 1, |i, _| x[i]));
            x.iter_mut().enumerate().for_each(|(i, x)| *x = y[(i, 0)]);
            Ok(())
        }
    }

    /// (a) A damped, loaded 3-DOF linear system through the residual form gives the linear
    /// integrators' histories to round-off (1e-12 of the largest displacement), with each
    /// Jacobian update; one factorization per run is enough with reuse (plus BDF2's start
    /// and the initial acceleration's), and Newton stops after two corrections (the second at
    /// round-off).
    #[test]
    fn a_linear_system_through_the_residual_form_equals_the_linear_integrators() {
        let m = Mat::from_fn(3, 3, |i, j| {
            [[2.0, 0.5, 0.0], [0.5, 1.0, 0.2], [0.0, 0.2, 1.5]][i][j]
        });
        let k = Mat::from_fn(3, 3, |i, j| {
            [
                [400.0, -200.0, 0.0],
                [-200.0, 400.0, -200.0],
                [0.0, -200.0, 200.0],
            ][i][j]
        });
        let c = Mat::from_fn(3, 3, |i, j| 0.1 * m[(i, j)] + 1e-3 * k[(i, j)]);
        let load = |t: f64, f: &mut [f64]| {
            f[0] = 3.0 * (7.0 * t).sin();
            f[1] = 0.0;
            f[2] = 1.0 + t;
        };
        let (q0, v0) = ([0.01, 0.0, -0.02], [0.0, 0.3, 0.0]);
        let (dt, steps) = (0.01, 300);
        let sys = LinearSystem {
            mass: m.as_ref(),
            damping: c.as_ref(),
            stiffness: k.as_ref(),
        };
        for (method, _) in METHODS {
            let mut linear = Vec::new();
            integrate(sys, method, dt, steps, &q0, &v0, load, |s| {
                linear.push([s.q.to_vec(), s.v.to_vec(), s.a.to_vec()])
            })
            .unwrap();
            let scale = linear
                .iter()
                .flat_map(|s| s[0].iter())
                .fold(0.0_f64, |m, q| m.max(q.abs()));
            for update in [
                JacobianUpdate::EveryIteration,
                JacobianUpdate::EveryStep,
                JacobianUpdate::Reuse,
            ] {
                let mut system = Linear {
                    m: &m,
                    c: &c,
                    k: &k,
                    load,
                    lu: None,
                    factorizations: 0,
                };
                let newton = Newton {
                    update,
                    ..Newton::default()
                };
                let run = Run { dt, steps, t0: 0.0 };
                let mut worst = [0.0_f64; 3];
                let mut most_iterations = 0;
                integrate_nonlinear(&mut system, method, run, newton, &q0, &v0, |s, stats| {
                    let reference = &linear[s.step];
                    for (w, (x, y)) in worst.iter_mut().zip([s.q, s.v, s.a].iter().zip(reference)) {
                        *w = x.iter().zip(y).fold(*w, |w, (x, y)| w.max((x - y).abs()));
                    }
                    if s.step > 0 {
                        most_iterations = most_iterations.max(stats.iterations);
                    }
                })
                .unwrap();
                let what = format!("{method:?} with {update:?}");
                assert!(
                    worst[0] <= 1e-12 * scale,
                    "{what}: q differs by {:e}",
                    worst[0]
                );
                // v and a carry the round-off of q divided by Δt and Δt²
                assert!(
                    worst[1] <= 1e-12 * scale / dt,
                    "{what}: v differs by {:e}",
                    worst[1]
                );
                assert!(
                    worst[2] <= 1e-12 * scale / (dt * dt),
                    "{what}: a differs by {:e}",
                    worst[2]
                );
                assert_eq!(most_iterations, 2, "{what}: Newton iterations");
                if update == JacobianUpdate::Reuse {
                    let expected = if method == Method::Bdf2 { 3 } else { 2 };
                    assert_eq!(system.factorizations, expected, "{what}: factorizations");
                }
            }
        }
    }

    /// (c) The forced SDOF through the residual form converges to the exact forced response
    /// at each method's order (the linear integrators' test of the same name).
    #[test]
    fn forced_sdof_through_the_residual_form_converges_at_each_methods_order() {
        let sdof = ForcedSdof::new();
        let error = |method: Method, dt: f64| {
            let (m, c, k) = (
                Mat::from_fn(1, 1, |_, _| sdof.m),
                Mat::from_fn(1, 1, |_, _| sdof.c),
                Mat::from_fn(1, 1, |_, _| sdof.k),
            );
            let mut system = Linear {
                m: &m,
                c: &c,
                k: &k,
                load: |t: f64, f: &mut [f64]| f[0] = sdof.load(t),
                lu: None,
                factorizations: 0,
            };
            let run = Run {
                dt,
                steps: (1.0 / dt).round() as usize,
                t0: 0.0,
            };
            let mut error: f64 = 0.0;
            integrate_nonlinear(
                &mut system,
                method,
                run,
                Newton::default(),
                &[0.0],
                &[0.0],
                |s, _| error = error.max((s.q[0] - sdof.exact(s.time)).abs()),
            )
            .unwrap();
            error
        };
        for (method, order) in METHODS {
            let (e1, e2) = (error(method, 1.0 / 200.0), error(method, 1.0 / 400.0));
            let observed = (e1 / e2).log2();
            assert!(
                (observed - order).abs() < 0.15,
                "{method:?}: errors {e1:e}, {e2:e}, observed order {observed}"
            );
        }
    }

    /// A forced, damped Duffing oscillator q̈ + 2ζω q̇ + ω² q + κ q³ = F cos(Ωt) with a hardening
    /// spring as strong as the linear one at |q| = 1.
    struct Duffing {
        jacobian: f64,
    }

    const DUFFING: (f64, f64, f64, f64, f64) = (0.05, 2.0 * std::f64::consts::PI, 40.0, 30.0, 9.0);

    fn duffing_acceleration(t: f64, q: f64, v: f64) -> f64 {
        let (zeta, w, kappa, force, big_w) = DUFFING;
        force * (big_w * t).cos() - 2.0 * zeta * w * v - w * w * q - kappa * q * q * q
    }

    impl NonlinearSystem for Duffing {
        fn size(&self) -> usize {
            1
        }
        fn residual(
            &mut self,
            t: f64,
            q: &[f64],
            v: &[f64],
            a: &[f64],
            r: &mut [f64],
        ) -> Result<(), IntegrationError> {
            r[0] = a[0] - duffing_acceleration(t, q[0], v[0]);
            Ok(())
        }
        fn factor(
            &mut self,
            _: f64,
            q: &[f64],
            _: &[f64],
            _: &[f64],
            c: Combination,
        ) -> Result<(), IntegrationError> {
            let (zeta, w, kappa, _, _) = DUFFING;
            self.jacobian =
                c[0] + c[1] * 2.0 * zeta * w + c[2] * (w * w + 3.0 * kappa * q[0] * q[0]);
            Ok(())
        }
        fn solve(&mut self, x: &mut [f64]) -> Result<(), IntegrationError> {
            x[0] /= self.jacobian;
            Ok(())
        }
    }

    /// q(1 s) of the Duffing oscillator from q = 0.5, q̇ = 0 by classical Runge–Kutta with
    /// 2¹⁶ steps (error ~1e-15, far below the implicit methods' at the steps compared).
    fn duffing_reference() -> f64 {
        let steps = 1 << 16;
        let h = 1.0 / steps as f64;
        let f = |t: f64, (q, v): (f64, f64)| (v, duffing_acceleration(t, q, v));
        let (mut t, mut y) = (0.0, (0.5, 0.0));
        for _ in 0..steps {
            let k1 = f(t, y);
            let k2 = f(t + h / 2.0, (y.0 + h / 2.0 * k1.0, y.1 + h / 2.0 * k1.1));
            let k3 = f(t + h / 2.0, (y.0 + h / 2.0 * k2.0, y.1 + h / 2.0 * k2.1));
            let k4 = f(t + h, (y.0 + h * k3.0, y.1 + h * k3.1));
            y.0 += h / 6.0 * (k1.0 + 2.0 * k2.0 + 2.0 * k3.0 + k4.0);
            y.1 += h / 6.0 * (k1.1 + 2.0 * k2.1 + 2.0 * k3.1 + k4.1);
            t += h;
        }
        y.0
    }

    /// (b) Δt study on the forced Duffing oscillator against a Runge–Kutta reference: observed
    /// orders log2(e(Δt)/e(Δt/2)) of q(1 s) within 0.2 of 1 (BDF1) and 2 (BDF2, generalized-α)
    /// at Δt = 1/400 and 1/800; full Newton needs at most 4 iterations a step, and reusing the
    /// factorization across steps converges to the same q within the Newton tolerance with
    /// fewer factorizations than steps.
    #[test]
    fn nonlinear_oscillator_converges_at_each_methods_order() {
        let reference = duffing_reference();
        let run = |method: Method, dt: f64, update: JacobianUpdate| {
            let mut last = 0.0;
            let (mut iterations, mut factorizations) = (0, 0);
            let newton = Newton {
                update,
                ..Newton::default()
            };
            let steps = (1.0 / dt).round() as usize;
            integrate_nonlinear(
                &mut Duffing { jacobian: 0.0 },
                method,
                Run { dt, steps, t0: 0.0 },
                newton,
                &[0.5],
                &[0.0],
                |s, stats| {
                    last = s.q[0];
                    iterations = iterations.max(stats.iterations);
                    factorizations += stats.factorizations;
                },
            )
            .unwrap();
            (last, iterations, factorizations)
        };
        for (method, order) in METHODS {
            let (q1, iterations, _) = run(method, 1.0 / 400.0, JacobianUpdate::EveryIteration);
            let (q2, ..) = run(method, 1.0 / 800.0, JacobianUpdate::EveryIteration);
            let (e1, e2) = ((q1 - reference).abs(), (q2 - reference).abs());
            let observed = (e1 / e2).log2();
            assert!(
                (observed - order).abs() < 0.2,
                "{method:?}: errors {e1:e}, {e2:e}, observed order {observed}"
            );
            assert!(
                iterations <= 4,
                "{method:?}: {iterations} Newton iterations"
            );
            // modified Newton stops within the tolerance of the same solution
            let (q_reuse, _, factorizations) = run(method, 1.0 / 400.0, JacobianUpdate::Reuse);
            assert!(
                (q_reuse - q1).abs() <= 1e-7,
                "{method:?}: reuse moved q(1 s) from {q1} to {q_reuse}"
            );
            assert!(
                factorizations < 200,
                "{method:?}: {factorizations} factorizations with reuse"
            );
        }
    }

    /// A step that cannot converge stops the run with its time and residual: the Duffing
    /// oscillator at Δt = 0.5 s (far beyond its period) with two Newton iterations allowed.
    #[test]
    fn a_step_that_does_not_converge_is_reported() {
        let newton = Newton {
            max_iterations: 2,
            ..Newton::default()
        };
        let dt = 0.5;
        let result = integrate_nonlinear(
            &mut Duffing { jacobian: 0.0 },
            Method::Bdf1,
            Run {
                dt,
                steps: 10,
                t0: 0.0,
            },
            newton,
            &[0.5],
            &[0.0],
            |_, _| {},
        );
        match result {
            Err(IntegrationError::Newton {
                step,
                time,
                iterations,
                residual,
            }) => assert!(
                step >= 1
                    && (time - step as f64 * dt).abs() < 1e-12
                    && iterations <= 2
                    && residual > 0.0,
                "step {step}, t = {time}, {iterations} iterations, residual {residual:e}"
            ),
            other => panic!("expected a Newton failure, got {other:?}"),
        }
    }
}
