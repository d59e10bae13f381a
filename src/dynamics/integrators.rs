//! Implicit time integration of linear second-order systems M q̈ + C q̇ + K q = f(t) with a
//! constant step, for dense (reduced) models: one factorization of the effective matrix, then
//! one solve per step. The caller observes each step through a closure (sensors, energy…), so
//! no state history is stored unless the caller keeps one.
//!
//! - BDF1 (backward Euler on the first-order form, thesis eq. 2.61): x_k = x_{k−1} + Δt ẋ_k for
//!   x = (q, v); first order, L-stable, strongly dissipative at large ωΔt.
//! - BDF2: x_k = (4x_{k−1} − x_{k−2} + 2Δt ẋ_k)/3, started with one BDF1 step; second order,
//!   L-stable.
//! - Generalized-α (Chung & Hulbert 1993, J. Appl. Mech. 60:371) with spectral radius at
//!   infinity ρ∞ ∈ [0, 1]: α_m = (2ρ∞ − 1)/(ρ∞ + 1), α_f = ρ∞/(ρ∞ + 1), γ = ½ − α_m + α_f,
//!   β = ¼(1 − α_m + α_f)²; second order, unconditionally stable; ρ∞ = 1 is the trapezoidal
//!   rule (no numerical dissipation), ρ∞ < 1 damps the high frequencies only.

use faer::linalg::solvers::{PartialPivLu, Solve};
use faer::{Mat, MatRef};

/// Integration method (TINTEG).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Method {
    Bdf1,
    Bdf2,
    GeneralizedAlpha { rho_inf: f64 },
}

/// Why an integration cannot run.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum IntegrationError {
    #[error("{what}: expected {expected}, got {got}")]
    Shape { what: &'static str, expected: usize, got: usize },
    #[error("time step {0} must be positive and finite")]
    Step(f64),
    #[error("generalized-α needs 0 ≤ ρ∞ ≤ 1, got {0}")]
    SpectralRadius(f64),
    #[error("the {0} matrix is singular: the system has a DOF without mass (and, for the effective matrix, without stiffness or damping)")]
    Singular(&'static str),
    #[error("the solution became non-finite at step {step} (t = {time})")]
    NonFinite { step: usize, time: f64 },
}

/// The dense linear system.
#[derive(Clone, Copy)]
pub struct LinearSystem<'a> {
    pub mass: MatRef<'a, f64>,
    pub damping: MatRef<'a, f64>,
    pub stiffness: MatRef<'a, f64>,
}

/// One step's state, handed to the observer.
pub struct StepState<'s> {
    pub step: usize,
    pub time: f64,
    pub q: &'s [f64],
    pub v: &'s [f64],
    /// q̈ from the method's own update (BDF: difference of velocities; generalized-α: a_{n+1}).
    pub a: &'s [f64],
}

/// Integrate `steps` steps of size `dt` from (q0, v0) at t = 0. `load(t, f)` fills f(t);
/// `observe` sees the initial state (step 0) and every step.
pub fn integrate(
    sys: LinearSystem<'_>,
    method: Method,
    dt: f64,
    steps: usize,
    q0: &[f64],
    v0: &[f64],
    mut load: impl FnMut(f64, &mut [f64]),
    mut observe: impl FnMut(&StepState<'_>),
) -> Result<(), IntegrationError> {
    let n = sys.mass.nrows();
    for (what, got) in [
        ("mass columns", sys.mass.ncols()),
        ("damping rows", sys.damping.nrows()),
        ("damping columns", sys.damping.ncols()),
        ("stiffness rows", sys.stiffness.nrows()),
        ("stiffness columns", sys.stiffness.ncols()),
        ("initial displacement", q0.len()),
        ("initial velocity", v0.len()),
    ] {
        if got != n {
            return Err(IntegrationError::Shape { what, expected: n, got });
        }
    }
    if !(dt > 0.0 && dt.is_finite()) {
        return Err(IntegrationError::Step(dt));
    }
    let mut f = vec![0.0; n];
    load(0.0, &mut f);
    // a_0 from the equation of motion (needs M regular).
    let mut a = vec![0.0; n];
    let mut rhs = Mat::<f64>::zeros(n, 1);
    for i in 0..n {
        rhs[(i, 0)] = f[i] - dot_row(sys.damping, i, v0) - dot_row(sys.stiffness, i, q0);
    }
    let mass_lu = sys.mass.partial_piv_lu();
    solve_checked(&mass_lu, &mut rhs, "mass")?;
    a.iter_mut().enumerate().for_each(|(i, x)| *x = rhs[(i, 0)]);
    let mut state = State { q: q0.to_vec(), v: v0.to_vec(), a, f };
    observe(&StepState { step: 0, time: 0.0, q: &state.q, v: &state.v, a: &state.a });
    let run = Stepping { sys, dt, steps };
    match method {
        Method::Bdf1 | Method::Bdf2 => bdf(run, method == Method::Bdf2, &mut state, load, observe),
        Method::GeneralizedAlpha { rho_inf } => {
            if !(0.0..=1.0).contains(&rho_inf) {
                return Err(IntegrationError::SpectralRadius(rho_inf));
            }
            generalized_alpha(run, rho_inf, &mut state, load, observe)
        }
    }
}

/// The fixed data of a run.
#[derive(Clone, Copy)]
struct Stepping<'a> {
    sys: LinearSystem<'a>,
    dt: f64,
    steps: usize,
}

/// The evolving state (q, v, a) and the load buffer.
struct State {
    q: Vec<f64>,
    v: Vec<f64>,
    a: Vec<f64>,
    f: Vec<f64>,
}

fn dot_row(m: MatRef<'_, f64>, i: usize, x: &[f64]) -> f64 {
    x.iter().enumerate().map(|(j, xj)| m[(i, j)] * xj).sum()
}

/// Effective matrix c_m M + c_c C + c_k K, factored.
fn effective(sys: LinearSystem<'_>, cm: f64, cc: f64, ck: f64) -> PartialPivLu<f64> {
    let n = sys.mass.nrows();
    Mat::<f64>::from_fn(n, n, |i, j| cm * sys.mass[(i, j)] + cc * sys.damping[(i, j)] + ck * sys.stiffness[(i, j)]).partial_piv_lu()
}

fn solve_checked(lu: &PartialPivLu<f64>, rhs: &mut Mat<f64>, what: &'static str) -> Result<(), IntegrationError> {
    lu.solve_in_place(rhs.as_mut());
    if (0..rhs.nrows()).any(|i| !rhs[(i, 0)].is_finite()) {
        return Err(IntegrationError::Singular(what));
    }
    Ok(())
}

/// BDF1 / BDF2 on x = (q, v): with v_k = (c q_k − r_q)/Δt and a_k = (c v_k − r_v)/Δt, where
/// (c, r) = (1, x_{k−1}) for BDF1 and (3/2, 2x_{k−1} − x_{k−2}/2) for BDF2, the equation of
/// motion becomes (c²/Δt² M + c/Δt C + K) q_k = f_k + M (c r_q + Δt r_v)/Δt² + C r_q/Δt.
fn bdf(run: Stepping<'_>, second_order: bool, state: &mut State, mut load: impl FnMut(f64, &mut [f64]), mut observe: impl FnMut(&StepState<'_>)) -> Result<(), IntegrationError> {
    let Stepping { sys, dt, steps } = run;
    let State { q, v, a, f } = state;
    let n = q.len();
    let factor = |c: f64| effective(sys, c * c / (dt * dt), c / dt, 1.0);
    let first = factor(1.0);
    let second = second_order.then(|| factor(1.5));
    let (mut q_prev, mut v_prev) = (q.to_vec(), v.to_vec());
    let (mut r_q, mut r_v) = (vec![0.0; n], vec![0.0; n]);
    let (mut mq, mut cq) = (vec![0.0; n], vec![0.0; n]);
    let mut rhs = Mat::<f64>::zeros(n, 1);
    for step in 1..=steps {
        let t = step as f64 * dt;
        let (lu, c) = match (&second, step) {
            (Some(lu), s) if s >= 2 => (lu, 1.5),
            _ => (&first, 1.0),
        };
        for i in 0..n {
            if c == 1.0 {
                r_q[i] = q[i];
                r_v[i] = v[i];
            } else {
                r_q[i] = 2.0 * q[i] - 0.5 * q_prev[i];
                r_v[i] = 2.0 * v[i] - 0.5 * v_prev[i];
            }
            mq[i] = (c * r_q[i] + dt * r_v[i]) / (dt * dt);
            cq[i] = r_q[i] / dt;
        }
        load(t, f);
        for i in 0..n {
            rhs[(i, 0)] = f[i] + dot_row(sys.mass, i, &mq) + dot_row(sys.damping, i, &cq);
        }
        solve_checked(lu, &mut rhs, "effective")?;
        q_prev.copy_from_slice(q);
        v_prev.copy_from_slice(v);
        for i in 0..n {
            q[i] = rhs[(i, 0)];
            v[i] = (c * q[i] - r_q[i]) / dt;
            a[i] = (c * v[i] - r_v[i]) / dt;
        }
        finite(step, t, q)?;
        observe(&StepState { step, time: t, q, v, a });
    }
    Ok(())
}

/// Generalized-α in displacement form: with q̃ = q_n + Δt v_n + (½−β)Δt² a_n and
/// ṽ = v_n + (1−γ)Δt a_n, a_{n+1} = (q_{n+1} − q̃)/(βΔt²) and v_{n+1} = ṽ + γΔt a_{n+1}; the
/// balance M a_{n+1−α_m} + C v_{n+1−α_f} + K q_{n+1−α_f} = f(t_{n+1−α_f}) becomes
/// [(1−α_m)/(βΔt²) M + (1−α_f)γ/(βΔt) C + (1−α_f) K] q_{n+1}
///   = f − M[α_m a_n − (1−α_m) q̃/(βΔt²)] − C[(1−α_f)(ṽ − γ q̃/(βΔt)) + α_f v_n] − α_f K q_n.
/// Solving for the displacement (not the acceleration) keeps round-off at ε·‖q‖ when stiff
/// modes with ωΔt ≫ 1 are present: the acceleration form multiplies K by Δt²·a_n, which for
/// such modes is (ωΔt)² times larger than q and pollutes the slow modes.
fn generalized_alpha(run: Stepping<'_>, rho_inf: f64, state: &mut State, mut load: impl FnMut(f64, &mut [f64]), mut observe: impl FnMut(&StepState<'_>)) -> Result<(), IntegrationError> {
    let Stepping { sys, dt, steps } = run;
    let State { q, v, a, f } = state;
    let n = q.len();
    let am = (2.0 * rho_inf - 1.0) / (rho_inf + 1.0);
    let af = rho_inf / (rho_inf + 1.0);
    let gamma = 0.5 - am + af;
    let beta = 0.25 * (1.0 - am + af).powi(2);
    let bdt2 = beta * dt * dt;
    let lu = effective(sys, (1.0 - am) / bdt2, (1.0 - af) * gamma / (beta * dt), 1.0 - af);
    let (mut q_pred, mut v_pred) = (vec![0.0; n], vec![0.0; n]);
    let (mut ma, mut cv, mut kq) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    let mut rhs = Mat::<f64>::zeros(n, 1);
    for step in 1..=steps {
        let t = step as f64 * dt;
        load(t - af * dt, f);
        for i in 0..n {
            q_pred[i] = q[i] + dt * v[i] + (0.5 - beta) * dt * dt * a[i];
            v_pred[i] = v[i] + (1.0 - gamma) * dt * a[i];
            ma[i] = am * a[i] - (1.0 - am) * q_pred[i] / bdt2;
            cv[i] = (1.0 - af) * (v_pred[i] - gamma * q_pred[i] / (beta * dt)) + af * v[i];
            kq[i] = af * q[i];
        }
        for i in 0..n {
            rhs[(i, 0)] = f[i] - dot_row(sys.mass, i, &ma) - dot_row(sys.damping, i, &cv) - dot_row(sys.stiffness, i, &kq);
        }
        solve_checked(&lu, &mut rhs, "effective")?;
        for i in 0..n {
            q[i] = rhs[(i, 0)];
            a[i] = (q[i] - q_pred[i]) / bdt2;
            v[i] = v_pred[i] + gamma * dt * a[i];
        }
        finite(step, t, q)?;
        observe(&StepState { step, time: t, q, v, a });
    }
    Ok(())
}

fn finite(step: usize, time: f64, q: &[f64]) -> Result<(), IntegrationError> {
    if q.iter().all(|x| x.is_finite()) { Ok(()) } else { Err(IntegrationError::NonFinite { step, time }) }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    const METHODS: [(Method, f64); 4] = [(Method::Bdf1, 1.0), (Method::Bdf2, 2.0), (Method::GeneralizedAlpha { rho_inf: 0.8 }, 2.0), (Method::GeneralizedAlpha { rho_inf: 1.0 }, 2.0)];

    fn one(v: f64) -> Mat<f64> {
        Mat::from_fn(1, 1, |_, _| v)
    }

    /// Final displacement of a damped SDOF (ω = 2π, ζ = 0.05) released from q = 1 after one
    /// second, against the closed form.
    fn sdof_error(method: Method, dt: f64) -> f64 {
        let (m, k, zeta) = (1.0, (2.0 * PI).powi(2), 0.05);
        let w = (k / m).sqrt();
        let c = 2.0 * zeta * w * m;
        let (mm, cm, km) = (one(m), one(c), one(k));
        let sys = LinearSystem { mass: mm.as_ref(), damping: cm.as_ref(), stiffness: km.as_ref() };
        let steps = (1.0 / dt).round() as usize;
        let mut last = 0.0;
        integrate(sys, method, dt, steps, &[1.0], &[0.0], |_, f| f[0] = 0.0, |s| last = s.q[0]).unwrap();
        let wd = w * (1.0 - zeta * zeta).sqrt();
        let t = steps as f64 * dt;
        let exact = (-zeta * w * t).exp() * ((wd * t).cos() + zeta * w / wd * (wd * t).sin());
        (last - exact).abs()
    }

    /// Observed order log2(e(Δt)/e(Δt/2)) within 0.15 of the theoretical order, at steps small
    /// enough (ωΔt ≤ 0.05) to be in the asymptotic range, large enough to stay far above
    /// round-off.
    #[test]
    fn convergence_orders() {
        for (method, order) in METHODS {
            let (e1, e2) = (sdof_error(method, 1.0 / 200.0), sdof_error(method, 1.0 / 400.0));
            let observed = (e1 / e2).log2();
            assert!((observed - order).abs() < 0.15, "{method:?}: errors {e1:e}, {e2:e}, observed order {observed}");
        }
    }

    /// Undamped oscillator, ωΔt = 0.063: the trapezoidal rule (generalized-α with ρ∞ = 1)
    /// conserves the energy ½(mv² + kq²) to round-off; BDF1 loses energy every step; BDF2 and
    /// ρ∞ < 1 are stable in a norm of their own (which includes a_n or q_{n−1}), so their
    /// (q, v) energy may wiggle by O((ωΔt)²) ≈ 0.4 % per step but never grows beyond 1 % and
    /// ends lower.
    #[test]
    fn energy_behaviour_on_an_undamped_oscillator() {
        let (mm, cm, km) = (one(1.0), one(0.0), one((2.0 * PI).powi(2)));
        let sys = LinearSystem { mass: mm.as_ref(), damping: cm.as_ref(), stiffness: km.as_ref() };
        for (method, _) in METHODS {
            let mut energies = Vec::new();
            integrate(sys, method, 0.01, 500, &[1.0], &[0.0], |_, f| f[0] = 0.0, |s| energies.push(0.5 * (s.v[0] * s.v[0] + km[(0, 0)] * s.q[0] * s.q[0]))).unwrap();
            let (e0, e_end) = (energies[0], *energies.last().unwrap());
            let max = energies.iter().copied().fold(0.0, f64::max);
            assert!(max <= e0 * 1.01, "{method:?} gained energy: {e0} → max {max}");
            if method == Method::Bdf1 {
                assert!(energies.windows(2).all(|w| w[1] <= w[0] * (1.0 + 1e-12)), "BDF1 gained energy in a step");
            }
            if method == (Method::GeneralizedAlpha { rho_inf: 1.0 }) {
                assert!((e_end - e0).abs() < 1e-10 * e0, "{method:?}: {e0} → {e_end}");
            } else {
                // generalized-α with ρ∞ = 0.8 dissipates only O((ωΔt)³) per period at low ωΔt:
                // require a loss clearly above round-off (1e-9), not a large one
                assert!(e_end < e0 * (1.0 - 1e-9), "{method:?} should dissipate: {e0} → {e_end}");
            }
        }
    }

    /// Δt a thousand times the period of a stiff mode: every method stays bounded, and the
    /// L-stable ones (BDF1/2, ρ∞ = 0) annihilate that mode.
    #[test]
    fn bounded_far_above_the_highest_period() {
        let k = Mat::<f64>::from_fn(2, 2, |i, j| [[1e8 + 1.0, -1e8], [-1e8, 1e8 + 1.0]][i][j]);
        let (mm, cm) = (Mat::<f64>::identity(2, 2), Mat::<f64>::zeros(2, 2));
        let sys = LinearSystem { mass: mm.as_ref(), damping: cm.as_ref(), stiffness: k.as_ref() };
        let period_stiff = 2.0 * PI / (2e8_f64 + 1.0).sqrt();
        for method in [Method::Bdf1, Method::Bdf2, Method::GeneralizedAlpha { rho_inf: 0.0 }, Method::GeneralizedAlpha { rho_inf: 1.0 }] {
            let mut max_q: f64 = 0.0;
            let mut last = [0.0; 2];
            integrate(sys, method, 1000.0 * period_stiff, 200, &[1.0, -1.0], &[0.0, 0.0], |_, f| f.fill(0.0), |s| {
                max_q = max_q.max(s.q[0].abs()).max(s.q[1].abs());
                last = [s.q[0], s.q[1]];
            })
            .unwrap();
            assert!(max_q <= 1.0 + 1e-9, "{method:?}: max |q| = {max_q}");
            if method != (Method::GeneralizedAlpha { rho_inf: 1.0 }) {
                assert!((last[0] + last[1]).abs() < 1e-6 && last[0].abs() < 1e-3, "{method:?}: stiff mode left {last:?}");
            }
        }
    }

    #[test]
    fn refuses_bad_settings() {
        let (mm, cm, km) = (one(1.0), one(0.0), one(1.0));
        let sys = LinearSystem { mass: mm.as_ref(), damping: cm.as_ref(), stiffness: km.as_ref() };
        let run = |method, dt| integrate(sys, method, dt, 1, &[0.0], &[0.0], |_, _| {}, |_| {});
        assert_eq!(run(Method::Bdf1, 0.0), Err(IntegrationError::Step(0.0)));
        assert_eq!(run(Method::GeneralizedAlpha { rho_inf: 1.5 }, 0.1), Err(IntegrationError::SpectralRadius(1.5)));
        let (zero, cz, kz) = (one(0.0), one(0.0), one(1.0));
        let massless = LinearSystem { mass: zero.as_ref(), damping: cz.as_ref(), stiffness: kz.as_ref() };
        assert_eq!(integrate(massless, Method::Bdf1, 0.1, 1, &[1.0], &[0.0], |_, _| {}, |_| {}), Err(IntegrationError::Singular("mass")));
    }
}
