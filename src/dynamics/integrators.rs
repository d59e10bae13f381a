//! Implicit time integration of linear second-order systems M q̈ + C q̇ + K q = f(t) with a
//! constant step: the effective matrix is factored once per step size (and again only when
//! the backend's matrices change, e.g. a pROM whose parameters follow a table), then each step
//! is a few operator products and one solve. The caller observes each step through a closure
//! (sensors, energy…), so no state history is stored unless the caller keeps one.
//!
//! The method formulas are written once, over a [`Backend`] that provides the linear algebra:
//! products y += (c_m M + c_c C + c_k K) x with combinations prepared once, and solves with the
//! factored effective matrix. [`Dense`] serves reduced models (faer, explicit inverse of the
//! small effective matrix), `SparseBackend` (in [`super::sparse_backend`]) the full f-set
//! (sparse Cholesky).
//!
//! - BDF1 (backward Euler on the first-order form, thesis eq. 2.61): x_k = x_{k−1} + Δt ẋ_k for
//!   x = (q, v); first order, L-stable, strongly dissipative at large ωΔt.
//! - BDF2: x_k = (4x_{k−1} − x_{k−2} + 2Δt ẋ_k)/3, started with one BDF1 step (so two
//!   factorizations per step size); second order, L-stable.
//! - Generalized-α (Chung & Hulbert 1993, J. Appl. Mech. 60:371) with spectral radius at
//!   infinity ρ∞ ∈ [0, 1]: α_m = (2ρ∞ − 1)/(ρ∞ + 1), α_f = ρ∞/(ρ∞ + 1), γ = ½ − α_m + α_f,
//!   β = ¼(1 − α_m + α_f)²; second order, unconditionally stable; ρ∞ = 1 is the trapezoidal
//!   rule (no numerical dissipation), ρ∞ < 1 damps the high frequencies only.

use faer::linalg::solvers::DenseSolveCore;
use faer::{Mat, MatRef};

use super::prescribed::{AlphaUpdate, PrescribedMotion};

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
    Shape {
        what: &'static str,
        expected: usize,
        got: usize,
    },
    #[error("time step {0} must be positive and finite")]
    Step(f64),
    #[error("generalized-α needs 0 ≤ ρ∞ ≤ 1, got {0}")]
    SpectralRadius(f64),
    #[error(
        "the {0} matrix is singular: the system has a DOF without mass (and, for the effective matrix, without stiffness or damping)"
    )]
    Singular(&'static str),
    #[error("the solution became non-finite at step {step} (t = {time})")]
    NonFinite { step: usize, time: f64 },
    #[error(
        "Newton did not converge at step {step} (t = {time}) after {iterations} iterations: residual ‖r‖∞ = {residual:e}"
    )]
    Newton {
        step: usize,
        time: f64,
        iterations: usize,
        residual: f64,
    },
    /// A backend-specific failure (sparse factorization, parameter evaluation).
    #[error("{0}")]
    Backend(String),
}

/// A combination c_m M + c_c C + c_k K.
pub type Combination = [f64; 3];

/// The linear algebra a method needs. The integrator calls [`prepare`](Backend::prepare) with
/// the effective matrix and the combinations its right-hand side uses, then per step
/// [`apply`](Backend::apply) and [`solve`](Backend::solve); [`advance`](Backend::advance) lets a
/// backend whose matrices depend on time (pROM parameters following tables) update them before
/// a step, after which the integrator prepares again.
pub trait Backend {
    /// Number of unknowns.
    fn size(&self) -> usize;
    /// Factor `effective` (named `what` in errors) and precompute the `products`.
    fn prepare(
        &mut self,
        effective: Combination,
        products: &[Combination],
        what: &'static str,
    ) -> Result<(), IntegrationError>;
    /// y += (products[j]) x.
    fn apply(&self, j: usize, x: &[f64], y: &mut [f64]);
    /// x ← effective⁻¹ x.
    fn solve(&mut self, x: &mut [f64]) -> Result<(), IntegrationError>;
    /// Update the matrices for the step ending at `t`; `true` when they changed.
    fn advance(&mut self, _t: f64) -> Result<bool, IntegrationError> {
        Ok(false)
    }
}

/// The dense linear system.
#[derive(Clone, Copy)]
pub struct LinearSystem<'a> {
    pub mass: MatRef<'a, f64>,
    pub damping: MatRef<'a, f64>,
    pub stiffness: MatRef<'a, f64>,
}

impl LinearSystem<'_> {
    fn check(&self) -> Result<usize, IntegrationError> {
        let n = self.mass.nrows();
        for (what, got) in [
            ("mass columns", self.mass.ncols()),
            ("damping rows", self.damping.nrows()),
            ("damping columns", self.damping.ncols()),
            ("stiffness rows", self.stiffness.nrows()),
            ("stiffness columns", self.stiffness.ncols()),
        ] {
            if got != n {
                return Err(IntegrationError::Shape {
                    what,
                    expected: n,
                    got,
                });
            }
        }
        Ok(n)
    }
}

/// Prepared dense operators: the inverse of the effective matrix (one matrix–vector product
/// per solve: for the small reduced systems this is several times faster than triangular
/// solves, and as accurate for the well-conditioned effective matrices of implicit steps) and
/// the product combinations. Reused by every dense backend.
#[derive(Debug, Clone)]
pub struct DenseOperators {
    inverse: Mat<f64>,
    products: Vec<Mat<f64>>,
    scratch: Vec<f64>,
}

impl Default for DenseOperators {
    fn default() -> Self {
        DenseOperators {
            inverse: Mat::zeros(0, 0),
            products: Vec::new(),
            scratch: Vec::new(),
        }
    }
}

impl DenseOperators {
    /// Form and invert `effective`, form the `products` of `sys`.
    pub fn prepare(
        &mut self,
        sys: LinearSystem<'_>,
        effective: Combination,
        products: &[Combination],
        what: &'static str,
    ) -> Result<(), IntegrationError> {
        let n = sys.check()?;
        let combine = |c: Combination| {
            Mat::<f64>::from_fn(n, n, |i, j| {
                c[0] * sys.mass[(i, j)] + c[1] * sys.damping[(i, j)] + c[2] * sys.stiffness[(i, j)]
            })
        };
        let e = combine(effective);
        self.inverse = e.partial_piv_lu().inverse();
        let scale = e.norm_max();
        // an exactly or numerically singular matrix gives non-finite or huge entries
        if !self.inverse.as_ref().is_all_finite() || !(self.inverse.norm_max() * scale < 1e15) {
            return Err(IntegrationError::Singular(what));
        }
        self.products = products.iter().map(|&c| combine(c)).collect();
        self.scratch.resize(n, 0.0);
        Ok(())
    }

    /// y += products[j] x.
    pub fn apply(&self, j: usize, x: &[f64], y: &mut [f64]) {
        matvec_add(&self.products[j], x, y);
    }

    /// x ← effective⁻¹ x.
    pub fn solve(&mut self, x: &mut [f64]) {
        self.scratch.fill(0.0);
        matvec_add(&self.inverse, x, &mut self.scratch);
        x.copy_from_slice(&self.scratch);
    }
}

/// y += A x, as column updates y += A_j x_j over A's contiguous columns (no allocation). For
/// the reduced sizes (n ≈ 10–100) this loop, which the compiler vectorizes, is several times
/// faster than faer's general `matmul`, whose dispatch costs more than the product itself.
pub fn matvec_add(a: &Mat<f64>, x: &[f64], y: &mut [f64]) {
    debug_assert!(a.ncols() == x.len() && a.nrows() == y.len());
    for (j, &xj) in x.iter().enumerate() {
        if xj != 0.0 {
            y.iter_mut()
                .zip(a.col_as_slice(j))
                .for_each(|(yi, aij)| *yi += aij * xj);
        }
    }
}

/// A dense (reduced) system with constant matrices.
pub struct Dense<'a> {
    sys: LinearSystem<'a>,
    ops: DenseOperators,
}

impl<'a> Dense<'a> {
    pub fn new(sys: LinearSystem<'a>) -> Result<Self, IntegrationError> {
        sys.check()?;
        Ok(Dense {
            sys,
            ops: DenseOperators::default(),
        })
    }
}

impl Backend for Dense<'_> {
    fn size(&self) -> usize {
        self.sys.mass.nrows()
    }
    fn prepare(
        &mut self,
        effective: Combination,
        products: &[Combination],
        what: &'static str,
    ) -> Result<(), IntegrationError> {
        self.ops.prepare(self.sys, effective, products, what)
    }
    fn apply(&self, j: usize, x: &[f64], y: &mut [f64]) {
        self.ops.apply(j, x, y);
    }
    fn solve(&mut self, x: &mut [f64]) -> Result<(), IntegrationError> {
        self.ops.solve(x);
        Ok(())
    }
}

/// One step's state, handed to the observer.
pub struct StepState<'s> {
    pub step: usize,
    pub time: f64,
    pub q: &'s [f64],
    pub v: &'s [f64],
    /// q̈ from the method's own update (BDF: difference of velocities; generalized-α: a_{n+1}).
    pub a: &'s [f64],
    /// (g, ġ, g̈) of each prescribed-motion term ([`PrescribedMotion::kinematics`]; empty
    /// without prescribed motion).
    pub motion: &'s [[f64; 3]],
}

/// Integrate a dense system: [`integrate_with`] on [`Dense`].
#[allow(clippy::too_many_arguments)]
pub fn integrate(
    sys: LinearSystem<'_>,
    method: Method,
    dt: f64,
    steps: usize,
    q0: &[f64],
    v0: &[f64],
    load: impl FnMut(f64, &mut [f64]),
    observe: impl FnMut(&StepState<'_>),
) -> Result<(), IntegrationError> {
    integrate_with(
        &mut Dense::new(sys)?,
        method,
        Run { dt, steps, t0: 0.0 },
        q0,
        v0,
        load,
        observe,
    )
}

/// Step size, number of steps and start time of a run.
#[derive(Debug, Clone, Copy)]
pub struct Run {
    pub dt: f64,
    pub steps: usize,
    /// Time of the initial state; the load and the backend see absolute times t0 + kΔt.
    pub t0: f64,
}

/// Integrate `run.steps` steps of size `run.dt` from (q0, v0) at t0. `load(t, f)` fills f(t);
/// `observe` sees the initial state (step 0, with a_0 from the equation of motion) and every
/// step.
pub fn integrate_with<B: Backend>(
    backend: &mut B,
    method: Method,
    run: Run,
    q0: &[f64],
    v0: &[f64],
    load: impl FnMut(f64, &mut [f64]),
    observe: impl FnMut(&StepState<'_>),
) -> Result<(), IntegrationError> {
    let mut none = PrescribedMotion::default();
    integrate_prescribed(backend, method, run, q0, v0, load, &mut none, observe)
}

/// [`integrate_with`] with constrained DOFs in prescribed motion: each step's load is f(t)
/// minus the coupling of `motion`'s terms at that step's kinematics ([`PrescribedMotion`]).
#[allow(clippy::too_many_arguments)]
pub fn integrate_prescribed<B: Backend>(
    backend: &mut B,
    method: Method,
    run: Run,
    q0: &[f64],
    v0: &[f64],
    mut load: impl FnMut(f64, &mut [f64]),
    motion: &mut PrescribedMotion<'_>,
    mut observe: impl FnMut(&StepState<'_>),
) -> Result<(), IntegrationError> {
    let n = backend.size();
    check_start(n, q0, v0, run.dt)?;
    if let Some(got) = motion.columns().filter(|&m| m != n) {
        return Err(IntegrationError::Shape {
            what: "prescribed-motion coupling",
            expected: n,
            got,
        });
    }
    if let Method::GeneralizedAlpha { rho_inf } = method
        && !(0.0..=1.0).contains(&rho_inf)
    {
        return Err(IntegrationError::SpectralRadius(rho_inf));
    }
    backend.advance(run.t0)?;
    let mut state = State {
        q: q0.to_vec(),
        v: v0.to_vec(),
        a: vec![0.0; n],
        f: vec![0.0; n],
        rhs: vec![0.0; n],
    };
    motion.start();
    let mut load = |t: f64, f: &mut [f64], motion: &PrescribedMotion<'_>| {
        load(t, f);
        motion.subtract_coupling(f);
    };
    initial_acceleration(backend, run.t0, &mut state, |t, f| load(t, f, motion))?;
    observe(&StepState {
        step: 0,
        time: run.t0,
        q: &state.q,
        v: &state.v,
        a: &state.a,
        motion: motion.kinematics(),
    });
    match method {
        Method::Bdf1 | Method::Bdf2 => bdf(
            backend,
            run,
            method == Method::Bdf2,
            &mut state,
            motion,
            load,
            observe,
        ),
        Method::GeneralizedAlpha { rho_inf } => {
            generalized_alpha(backend, run, rho_inf, &mut state, motion, load, observe)
        }
    }
}

/// The evolving state (q, v, a) and the load and right-hand-side buffers.
struct State {
    q: Vec<f64>,
    v: Vec<f64>,
    a: Vec<f64>,
    f: Vec<f64>,
    rhs: Vec<f64>,
}

/// a_0 = M⁻¹(f_0 − C v_0 − K q_0). When M cannot be factored (massless DOFs of a full model)
/// and the system starts at rest and unloaded, a_0 = 0; otherwise the singular mass is an error.
fn initial_acceleration<B: Backend>(
    backend: &mut B,
    t0: f64,
    state: &mut State,
    mut load: impl FnMut(f64, &mut [f64]),
) -> Result<(), IntegrationError> {
    let State { q, v, a, f, .. } = state;
    load(t0, f);
    if f.iter().chain(q.iter()).chain(v.iter()).all(|x| *x == 0.0) {
        a.fill(0.0);
        return Ok(());
    }
    backend.prepare(
        [1.0, 0.0, 0.0],
        &[[0.0, -1.0, 0.0], [0.0, 0.0, -1.0]],
        "mass",
    )?;
    a.copy_from_slice(f);
    backend.apply(0, v, a);
    backend.apply(1, q, a);
    backend.solve(a)?;
    if a.iter().all(|x| x.is_finite()) {
        Ok(())
    } else {
        Err(IntegrationError::Singular("mass"))
    }
}

/// BDF1 / BDF2 on x = (q, v): with v_k = (c q_k − r_q)/Δt and a_k = (c v_k − r_v)/Δt, where
/// (c, r) = (1, x_{k−1}) for BDF1 and (3/2, 2x_{k−1} − x_{k−2}/2) for BDF2, the equation of
/// motion becomes (c²/Δt² M + c/Δt C + K) q_k = f_k + (c/Δt² M + 1/Δt C) r_q + M r_v/Δt.
fn bdf<B: Backend>(
    backend: &mut B,
    run: Run,
    second_order: bool,
    state: &mut State,
    motion: &mut PrescribedMotion<'_>,
    mut load: impl FnMut(f64, &mut [f64], &PrescribedMotion<'_>),
    mut observe: impl FnMut(&StepState<'_>),
) -> Result<(), IntegrationError> {
    let Run { dt, steps, t0 } = run;
    let State { q, v, a, f, rhs } = state;
    let n = q.len();
    let prepare = |b: &mut B, c: f64| {
        b.prepare(
            [c * c / (dt * dt), c / dt, 1.0],
            &[[c / (dt * dt), 1.0 / dt, 0.0], [1.0 / dt, 0.0, 0.0]],
            "effective",
        )
    };
    let (mut q_prev, mut v_prev) = (q.to_vec(), v.to_vec());
    let (mut r_q, mut r_v) = (vec![0.0; n], vec![0.0; n]);
    let mut prepared = None;
    for step in 1..=steps {
        let t = t0 + step as f64 * dt;
        let c = if second_order && step >= 2 { 1.5 } else { 1.0 };
        if backend.advance(t)? || prepared != Some(c) {
            prepare(backend, c)?;
            prepared = Some(c);
        }
        for i in 0..n {
            if c == 1.0 {
                r_q[i] = q[i];
                r_v[i] = v[i];
            } else {
                r_q[i] = 2.0 * q[i] - 0.5 * q_prev[i];
                r_v[i] = 2.0 * v[i] - 0.5 * v_prev[i];
            }
        }
        motion.advance_bdf(t, dt, c);
        load(t, f, motion);
        rhs.copy_from_slice(f);
        backend.apply(0, &r_q, rhs);
        backend.apply(1, &r_v, rhs);
        backend.solve(rhs)?;
        q_prev.copy_from_slice(q);
        v_prev.copy_from_slice(v);
        for i in 0..n {
            q[i] = rhs[i];
            v[i] = (c * q[i] - r_q[i]) / dt;
            a[i] = (c * v[i] - r_v[i]) / dt;
        }
        finite(step, t, q)?;
        observe(&StepState {
            step,
            time: t,
            q,
            v,
            a,
            motion: motion.kinematics(),
        });
    }
    Ok(())
}

/// Generalized-α in displacement form: with q̃ = q_n + Δt v_n + (½−β)Δt² a_n and
/// ṽ = v_n + (1−γ)Δt a_n, a_{n+1} = (q_{n+1} − q̃)/(βΔt²) and v_{n+1} = ṽ + γΔt a_{n+1}; the
/// balance M a_{n+1−α_m} + C v_{n+1−α_f} + K q_{n+1−α_f} = f(t_{n+1−α_f}) becomes
/// [(1−α_m)/(βΔt²) M + (1−α_f)γ/(βΔt) C + (1−α_f) K] q_{n+1}
///   = f − M[α_m a_n − (1−α_m) q̃/(βΔt²)] − C[(1−α_f)(ṽ − γ q̃/(βΔt)) + α_f v_n] − α_f K q_n,
/// whose right-hand side is f + G_q q_n + G_v v_n + G_a a_n with the three combinations below
/// (expanding q̃ and ṽ). Solving for the displacement (not the acceleration) keeps round-off at
/// ε·‖q‖ when stiff modes with ωΔt ≫ 1 are present: the acceleration form multiplies K by
/// Δt²·a_n, which for such modes is (ωΔt)² times larger than q and pollutes the slow modes.
fn generalized_alpha<B: Backend>(
    backend: &mut B,
    run: Run,
    rho_inf: f64,
    state: &mut State,
    motion: &mut PrescribedMotion<'_>,
    mut load: impl FnMut(f64, &mut [f64], &PrescribedMotion<'_>),
    mut observe: impl FnMut(&StepState<'_>),
) -> Result<(), IntegrationError> {
    let Run { dt, steps, t0 } = run;
    let State { q, v, a, f, rhs } = state;
    let n = q.len();
    let am = (2.0 * rho_inf - 1.0) / (rho_inf + 1.0);
    let af = rho_inf / (rho_inf + 1.0);
    let gamma = 0.5 - am + af;
    let beta = 0.25 * (1.0 - am + af).powi(2);
    let bdt2 = beta * dt * dt;
    let effective = [
        (1.0 - am) / bdt2,
        (1.0 - af) * gamma / (beta * dt),
        1.0 - af,
    ];
    let g_q = [(1.0 - am) / bdt2, (1.0 - af) * gamma / (beta * dt), -af];
    let g_v = [
        (1.0 - am) / (beta * dt),
        -(1.0 - af) * (1.0 - gamma / beta) - af,
        0.0,
    ];
    let g_a = [
        -am + (1.0 - am) * (0.5 - beta) / beta,
        -(1.0 - af) * dt * ((1.0 - gamma) - gamma * (0.5 - beta) / beta),
        0.0,
    ];
    let mut prepared = false;
    for step in 1..=steps {
        let t = t0 + step as f64 * dt;
        if backend.advance(t)? || !prepared {
            backend.prepare(effective, &[g_q, g_v, g_a], "effective")?;
            prepared = true;
        }
        motion.advance_alpha(
            t,
            AlphaUpdate {
                dt,
                beta,
                gamma,
                alpha_m: am,
                alpha_f: af,
            },
        );
        load(t - af * dt, f, motion);
        rhs.copy_from_slice(f);
        backend.apply(0, q, rhs);
        backend.apply(1, v, rhs);
        backend.apply(2, a, rhs);
        backend.solve(rhs)?;
        for i in 0..n {
            let q_pred = q[i] + dt * v[i] + (0.5 - beta) * dt * dt * a[i];
            let v_pred = v[i] + (1.0 - gamma) * dt * a[i];
            q[i] = rhs[i];
            a[i] = (q[i] - q_pred) / bdt2;
            v[i] = v_pred + gamma * dt * a[i];
        }
        finite(step, t, q)?;
        observe(&StepState {
            step,
            time: t,
            q,
            v,
            a,
            motion: motion.kinematics(),
        });
    }
    Ok(())
}

fn finite(step: usize, time: f64, q: &[f64]) -> Result<(), IntegrationError> {
    if q.iter().all(|x| x.is_finite()) {
        Ok(())
    } else {
        Err(IntegrationError::NonFinite { step, time })
    }
}
/// The initial state has `n` entries and the step is positive and finite.
pub(crate) fn check_start(
    n: usize,
    q0: &[f64],
    v0: &[f64],
    dt: f64,
) -> Result<(), IntegrationError> {
    for (what, got) in [
        ("initial displacement", q0.len()),
        ("initial velocity", v0.len()),
    ] {
        if got != n {
            return Err(IntegrationError::Shape {
                what,
                expected: n,
                got,
            });
        }
    }
    if !(dt > 0.0 && dt.is_finite()) {
        return Err(IntegrationError::Step(dt));
    }
    Ok(())
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use std::f64::consts::PI;

    pub(crate) const METHODS: [(Method, f64); 4] = [
        (Method::Bdf1, 1.0),
        (Method::Bdf2, 2.0),
        (Method::GeneralizedAlpha { rho_inf: 0.8 }, 2.0),
        (Method::GeneralizedAlpha { rho_inf: 1.0 }, 2.0),
    ];

    pub(crate) fn one(v: f64) -> Mat<f64> {
        Mat::from_fn(1, 1, |_, _| v)
    }

    /// Final displacement of a damped SDOF (ω = 2π, ζ = 0.05) released from q = 1 after one
    /// second, against the closed form.
    fn sdof_error(method: Method, dt: f64) -> f64 {
        let (m, k, zeta) = (1.0, (2.0 * PI).powi(2), 0.05);
        let w = (k / m).sqrt();
        let c = 2.0 * zeta * w * m;
        let (mm, cm, km) = (one(m), one(c), one(k));
        let sys = LinearSystem {
            mass: mm.as_ref(),
            damping: cm.as_ref(),
            stiffness: km.as_ref(),
        };
        let steps = (1.0 / dt).round() as usize;
        let mut last = 0.0;
        integrate(
            sys,
            method,
            dt,
            steps,
            &[1.0],
            &[0.0],
            |_, f| f[0] = 0.0,
            |s| last = s.q[0],
        )
        .unwrap();
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
            let (e1, e2) = (
                sdof_error(method, 1.0 / 200.0),
                sdof_error(method, 1.0 / 400.0),
            );
            let observed = (e1 / e2).log2();
            assert!(
                (observed - order).abs() < 0.15,
                "{method:?}: errors {e1:e}, {e2:e}, observed order {observed}"
            );
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
        let sys = LinearSystem {
            mass: mm.as_ref(),
            damping: cm.as_ref(),
            stiffness: km.as_ref(),
        };
        for (method, _) in METHODS {
            let mut energies = Vec::new();
            integrate(
                sys,
                method,
                0.01,
                500,
                &[1.0],
                &[0.0],
                |_, f| f[0] = 0.0,
                |s| energies.push(0.5 * (s.v[0] * s.v[0] + km[(0, 0)] * s.q[0] * s.q[0])),
            )
            .unwrap();
            let (e0, e_end) = (energies[0], *energies.last().unwrap());
            let max = energies.iter().copied().fold(0.0, f64::max);
            assert!(
                max <= e0 * 1.01,
                "{method:?} gained energy: {e0} → max {max}"
            );
            if method == Method::Bdf1 {
                assert!(
                    energies.windows(2).all(|w| w[1] <= w[0] * (1.0 + 1e-12)),
                    "BDF1 gained energy in a step"
                );
            }
            if method == (Method::GeneralizedAlpha { rho_inf: 1.0 }) {
                assert!(
                    (e_end - e0).abs() < 1e-10 * e0,
                    "{method:?}: {e0} → {e_end}"
                );
            } else {
                // generalized-α with ρ∞ = 0.8 dissipates only O((ωΔt)³) per period at low ωΔt:
                // require a loss clearly above round-off (1e-9), not a large one
                assert!(
                    e_end < e0 * (1.0 - 1e-9),
                    "{method:?} should dissipate: {e0} → {e_end}"
                );
            }
        }
    }

    /// Δt a thousand times the period of a stiff mode: every method stays bounded, and the
    /// L-stable ones (BDF1/2, ρ∞ = 0) annihilate that mode.
    #[test]
    fn bounded_far_above_the_highest_period() {
        let k = Mat::<f64>::from_fn(2, 2, |i, j| [[1e8 + 1.0, -1e8], [-1e8, 1e8 + 1.0]][i][j]);
        let (mm, cm) = (Mat::<f64>::identity(2, 2), Mat::<f64>::zeros(2, 2));
        let sys = LinearSystem {
            mass: mm.as_ref(),
            damping: cm.as_ref(),
            stiffness: k.as_ref(),
        };
        let period_stiff = 2.0 * PI / (2e8_f64 + 1.0).sqrt();
        for method in [
            Method::Bdf1,
            Method::Bdf2,
            Method::GeneralizedAlpha { rho_inf: 0.0 },
            Method::GeneralizedAlpha { rho_inf: 1.0 },
        ] {
            let mut max_q: f64 = 0.0;
            let mut last = [0.0; 2];
            integrate(
                sys,
                method,
                1000.0 * period_stiff,
                200,
                &[1.0, -1.0],
                &[0.0, 0.0],
                |_, f| f.fill(0.0),
                |s| {
                    max_q = max_q.max(s.q[0].abs()).max(s.q[1].abs());
                    last = [s.q[0], s.q[1]];
                },
            )
            .unwrap();
            assert!(max_q <= 1.0 + 1e-9, "{method:?}: max |q| = {max_q}");
            if method != (Method::GeneralizedAlpha { rho_inf: 1.0 }) {
                assert!(
                    (last[0] + last[1]).abs() < 1e-6 && last[0].abs() < 1e-3,
                    "{method:?}: stiff mode left {last:?}"
                );
            }
        }
    }

    /// Undamped oscillator at steps far above its period (ωΔt = 10 and 1000). BDF1 and BDF2
    /// never exceed the initial (q, v) energy, and BDF1 loses energy in every step (backward
    /// Euler divides the energy norm by √(1 + (ωΔt)²) per step). Generalized-α with ρ∞ < 1
    /// overshoots in velocity in the first steps (a known property of the method, Chung &
    /// Hulbert 1993 §4: the first update v₁ = v₀ + Δt[(1−γ)a₀ + γa₁] carries Δt·a₀ = ωΔt·ωq₀, so
    /// the energy can reach O((ωΔt)²)·E₀ — measured 7× at ωΔt = 10 and 6e4× at 1000 for ρ∞ = 0):
    /// bounded by (ωΔt)² E₀, then annihilated. After 20 steps every method with ρ∞ < 1 has
    /// removed more than 99 % of the energy; the trapezoidal rule (ρ∞ = 1) keeps it to
    /// round-off.
    #[test]
    fn energy_never_grows_for_steps_far_above_the_period() {
        let w = 2.0 * PI;
        let (mm, cm, km) = (one(1.0), one(0.0), one(w * w));
        let sys = LinearSystem {
            mass: mm.as_ref(),
            damping: cm.as_ref(),
            stiffness: km.as_ref(),
        };
        for wdt in [10.0, 1000.0] {
            for method in [
                Method::Bdf1,
                Method::Bdf2,
                Method::GeneralizedAlpha { rho_inf: 0.0 },
                Method::GeneralizedAlpha { rho_inf: 0.5 },
                Method::GeneralizedAlpha { rho_inf: 1.0 },
            ] {
                let mut energies = Vec::new();
                integrate(
                    sys,
                    method,
                    wdt / w,
                    20,
                    &[1.0],
                    &[0.0],
                    |_, f| f[0] = 0.0,
                    |s| energies.push(0.5 * (s.v[0] * s.v[0] + w * w * s.q[0] * s.q[0])),
                )
                .unwrap();
                let e0 = energies[0];
                let max = energies.iter().copied().fold(0.0, f64::max);
                println!(
                    "{method:?} ωΔt = {wdt}: max E/E0 = {:.3e}, final {:.3e}",
                    max / e0,
                    energies[20] / e0
                );
                if matches!(method, Method::GeneralizedAlpha { rho_inf } if rho_inf < 1.0) {
                    assert!(
                        max <= e0 * wdt * wdt,
                        "{method:?} at ωΔt = {wdt}: overshoot {max} above (ωΔt)² E0"
                    );
                } else {
                    assert!(
                        max <= e0 * (1.0 + 1e-12),
                        "{method:?} at ωΔt = {wdt}: energy grew to {max} from {e0}"
                    );
                }
                if method == Method::Bdf1 {
                    assert!(
                        energies.windows(2).all(|p| p[1] < p[0]),
                        "BDF1 at ωΔt = {wdt} did not lose energy in every step"
                    );
                }
                if method == (Method::GeneralizedAlpha { rho_inf: 1.0 }) {
                    assert!(
                        (energies[20] - e0).abs() <= 1e-9 * e0,
                        "trapezoidal rule at ωΔt = {wdt}: {e0} → {}",
                        energies[20]
                    );
                } else {
                    assert!(
                        energies[20] < 1e-2 * e0,
                        "{method:?} at ωΔt = {wdt}: {e0} → {}",
                        energies[20]
                    );
                }
            }
        }
    }

    /// A damped SDOF m q̈ + c q̈ + k q = F sin(Ωt) started at rest (ω = 2π, ζ = 0.05, Ω = 1.7ω,
    /// F = k): m, c, k, the load and the exact response q(t), the steady-state particular
    /// solution A sin Ωt + B cos Ωt plus the free response that cancels its initial q and q̇.
    pub(crate) struct ForcedSdof {
        pub m: f64,
        pub c: f64,
        pub k: f64,
        force: f64,
        omega: f64,
    }

    impl ForcedSdof {
        pub fn new() -> Self {
            let w = 2.0 * PI;
            ForcedSdof {
                m: 1.0,
                c: 2.0 * 0.05 * w,
                k: w * w,
                force: w * w,
                omega: 1.7 * w,
            }
        }

        pub fn load(&self, t: f64) -> f64 {
            self.force * (self.omega * t).sin()
        }

        pub fn exact(&self, t: f64) -> f64 {
            let (m, c, k, big_w) = (self.m, self.c, self.k, self.omega);
            // (k − mΩ²) A − cΩ B = F, cΩ A + (k − mΩ²) B = 0
            let (d, e) = (k - m * big_w * big_w, c * big_w);
            let det = d * d + e * e;
            let (a, b) = (self.force * d / det, -self.force * e / det);
            let w = (k / m).sqrt();
            let zeta = c / (2.0 * m * w);
            let wd = w * (1.0 - zeta * zeta).sqrt();
            // free response with q(0) = −B, q̇(0) = −AΩ
            let (c1, c2) = (-b, (-a * big_w + zeta * w * (-b)) / wd);
            a * (big_w * t).sin()
                + b * (big_w * t).cos()
                + (-zeta * w * t).exp() * (c1 * (wd * t).cos() + c2 * (wd * t).sin())
        }

        /// Largest error of q over one second of steps `dt` of `integrate`.
        pub fn error(&self, method: Method, dt: f64) -> f64 {
            let (mm, cm, km) = (one(self.m), one(self.c), one(self.k));
            let sys = LinearSystem {
                mass: mm.as_ref(),
                damping: cm.as_ref(),
                stiffness: km.as_ref(),
            };
            let mut error: f64 = 0.0;
            integrate(
                sys,
                method,
                dt,
                (1.0 / dt).round() as usize,
                &[0.0],
                &[0.0],
                |t, f| f[0] = self.load(t),
                |s| error = error.max((s.q[0] - self.exact(s.time)).abs()),
            )
            .unwrap();
            error
        }
    }

    /// Forced response (the other tests run unloaded): each method converges to the exact
    /// response at its order, observed as log2(e(Δt)/e(Δt/2)) within 0.15 at ΩΔt ≤ 0.053.
    /// Generalized-α is second order only when the load is taken at t_{n+1} − α_f Δt, as its
    /// balance equation says: at t_{n+1} it falls to first order.
    #[test]
    fn forced_sdof_converges_to_the_exact_response_at_each_methods_order() {
        let sdof = ForcedSdof::new();
        for (method, order) in METHODS {
            let (e1, e2) = (
                sdof.error(method, 1.0 / 200.0),
                sdof.error(method, 1.0 / 400.0),
            );
            let observed = (e1 / e2).log2();
            assert!(
                (observed - order).abs() < 0.15,
                "{method:?}: errors {e1:e}, {e2:e}, observed order {observed}"
            );
        }
    }

    #[test]
    fn refuses_bad_settings() {
        let (mm, cm, km) = (one(1.0), one(0.0), one(1.0));
        let sys = LinearSystem {
            mass: mm.as_ref(),
            damping: cm.as_ref(),
            stiffness: km.as_ref(),
        };
        let run = |method, dt| integrate(sys, method, dt, 1, &[0.0], &[0.0], |_, _| {}, |_| {});
        assert_eq!(run(Method::Bdf1, 0.0), Err(IntegrationError::Step(0.0)));
        assert_eq!(
            run(Method::GeneralizedAlpha { rho_inf: 1.5 }, 0.1),
            Err(IntegrationError::SpectralRadius(1.5))
        );
        let (zero, cz, kz) = (one(0.0), one(0.0), one(1.0));
        let massless = LinearSystem {
            mass: zero.as_ref(),
            damping: cz.as_ref(),
            stiffness: kz.as_ref(),
        };
        assert_eq!(
            integrate(
                massless,
                Method::Bdf1,
                0.1,
                1,
                &[1.0],
                &[0.0],
                |_, _| {},
                |_| {}
            ),
            Err(IntegrationError::Singular("mass"))
        );
    }

    /// A dense backend that records the name of every factorization it is asked for.
    struct Counting<'a> {
        dense: Dense<'a>,
        prepared: Vec<&'static str>,
    }

    impl Backend for Counting<'_> {
        fn size(&self) -> usize {
            self.dense.size()
        }
        fn prepare(
            &mut self,
            effective: Combination,
            products: &[Combination],
            what: &'static str,
        ) -> Result<(), IntegrationError> {
            self.prepared.push(what);
            self.dense.prepare(effective, products, what)
        }
        fn apply(&self, j: usize, x: &[f64], y: &mut [f64]) {
            self.dense.apply(j, x, y);
        }
        fn solve(&mut self, x: &mut [f64]) -> Result<(), IntegrationError> {
            self.dense.solve(x)
        }
    }

    /// Constant matrices are factored once per step size (module doc): the mass once for a_0,
    /// then the effective matrix once (BDF1, generalized-α) or twice (BDF2: its BDF1 start and
    /// its own), however many steps follow.
    #[test]
    fn constant_matrices_are_factored_once_per_step_size() {
        let (mm, cm, km) = (one(1.0), one(0.1), one(4.0));
        let sys = LinearSystem {
            mass: mm.as_ref(),
            damping: cm.as_ref(),
            stiffness: km.as_ref(),
        };
        for (method, expected) in [
            (Method::Bdf1, vec!["mass", "effective"]),
            (Method::Bdf2, vec!["mass", "effective", "effective"]),
            (
                Method::GeneralizedAlpha { rho_inf: 0.8 },
                vec!["mass", "effective"],
            ),
        ] {
            let mut backend = Counting {
                dense: Dense::new(sys).unwrap(),
                prepared: Vec::new(),
            };
            let run = Run {
                dt: 0.01,
                steps: 20,
                t0: 0.0,
            };
            integrate_with(
                &mut backend,
                method,
                run,
                &[1.0],
                &[0.0],
                |_, f| f[0] = 0.0,
                |_| {},
            )
            .unwrap();
            assert_eq!(backend.prepared, expected, "{method:?}");
        }
    }

    /// M, C, K of a coupled 2-DOF system with every entry non-zero: M = [[2, 0.5], [0.5, 1]],
    /// C = [[0.3, −0.1], [−0.1, 0.2]], K = [[5, −2], [−2, 3]].
    fn coupled_two_dof() -> [Mat<f64>; 3] {
        let mat = |a: [[f64; 2]; 2]| Mat::<f64>::from_fn(2, 2, |i, j| a[i][j]);
        [
            mat([[2.0, 0.5], [0.5, 1.0]]),
            mat([[0.3, -0.1], [-0.1, 0.2]]),
            mat([[5.0, -2.0], [-2.0, 3.0]]),
        ]
    }

    /// The observer's step 0 is the initial state with a_0 = M⁻¹(f(t0) − C v_0 − K q_0), on a
    /// coupled 2-DOF system whose every input is non-zero. By hand: f − Cv − Kq = (0.05, −0.25)
    /// and M⁻¹ = [[1, −0.5], [−0.5, 2]] / 1.75, so a_0 = (0.1, −0.3).
    #[test]
    fn step_zero_carries_the_acceleration_of_the_equation_of_motion() {
        let [m, c, k] = coupled_two_dof();
        let sys = LinearSystem {
            mass: m.as_ref(),
            damping: c.as_ref(),
            stiffness: k.as_ref(),
        };
        for (method, _) in METHODS {
            let mut first = None;
            let run = Run {
                dt: 0.01,
                steps: 1,
                t0: 0.5,
            };
            integrate_with(
                &mut Dense::new(sys).unwrap(),
                method,
                run,
                &[0.1, -0.2],
                &[0.3, 0.4],
                |t, f| f.copy_from_slice(&[1.0 + 2.0 * (t - 0.5), -1.0]),
                |s| {
                    if s.step == 0 {
                        first = Some((s.time, s.q.to_vec(), s.v.to_vec(), s.a.to_vec()));
                    }
                },
            )
            .unwrap();
            let (time, q, v, a) = first.unwrap();
            assert_eq!((time, q, v), (0.5, vec![0.1, -0.2], vec![0.3, 0.4]));
            assert!(
                (a[0] - 0.1).abs() < 1e-14 && (a[1] + 0.3).abs() < 1e-14,
                "{method:?}: a_0 = {a:?}"
            );
        }
    }

    /// A DOF without mass is allowed when the run starts at rest and unloaded (a_0 = 0): the
    /// effective matrix holds its stiffness. With C = 0 and no mass, that DOF's row of the
    /// equation of motion is static at every step: −q_1 + q_2 = f_2(t) (for generalized-α the
    /// balance at t_{n+1−α_f} interpolates q and f alike, so with f linear in t it holds at the
    /// step times too).
    #[test]
    fn a_massless_dof_at_rest_follows_its_static_balance() {
        let m = Mat::<f64>::from_fn(2, 2, |i, j| if i == 0 && j == 0 { 1.0 } else { 0.0 });
        let c = Mat::<f64>::zeros(2, 2);
        let k = Mat::<f64>::from_fn(2, 2, |i, j| [[2.0, -1.0], [-1.0, 1.0]][i][j]);
        let sys = LinearSystem {
            mass: m.as_ref(),
            damping: c.as_ref(),
            stiffness: k.as_ref(),
        };
        for (method, _) in METHODS {
            let mut balance: f64 = 0.0;
            let mut a0 = None;
            integrate(
                sys,
                method,
                0.01,
                50,
                &[0.0, 0.0],
                &[0.0, 0.0],
                |t, f| f.copy_from_slice(&[0.0, t]),
                |s| {
                    a0.get_or_insert_with(|| s.a.to_vec());
                    balance = balance.max((s.q[1] - s.q[0] - s.time).abs());
                },
            )
            .unwrap();
            assert_eq!(a0.unwrap(), vec![0.0, 0.0], "{method:?}");
            assert!(balance < 1e-12, "{method:?}: static row off by {balance:e}");
        }
    }

    /// A load that turns non-finite stops the run at the step it spoils, with that step's time.
    #[test]
    fn a_non_finite_solution_stops_the_run() {
        let (mm, cm, km) = (one(1.0), one(0.0), one(1.0));
        let sys = LinearSystem {
            mass: mm.as_ref(),
            damping: cm.as_ref(),
            stiffness: km.as_ref(),
        };
        for (method, _) in METHODS {
            let result = integrate(
                sys,
                method,
                0.25,
                3,
                &[1.0],
                &[0.0],
                |t, f| f[0] = if t > 0.0 { f64::NAN } else { 0.0 },
                |_| {},
            );
            assert_eq!(
                result,
                Err(IntegrationError::NonFinite {
                    step: 1,
                    time: 0.25
                }),
                "{method:?}"
            );
        }
    }

    /// The singularity test of the dense effective/mass matrix is relative: a mass whose
    /// condition number is about 2/ε = 9e15 is refused whether its entries are of order 1e3 or
    /// 1e-3, and a well-conditioned one with tiny entries (1e-6 I) is accepted.
    #[test]
    fn numerical_singularity_is_judged_relative_to_the_matrix_scale() {
        let k = Mat::<f64>::identity(2, 2);
        let c = Mat::<f64>::zeros(2, 2);
        let start = |m: &Mat<f64>| {
            let sys = LinearSystem {
                mass: m.as_ref(),
                damping: c.as_ref(),
                stiffness: k.as_ref(),
            };
            integrate(
                sys,
                Method::Bdf1,
                0.1,
                1,
                &[1.0, 0.0],
                &[0.0, 0.0],
                |_, f| f.fill(0.0),
                |_| {},
            )
        };
        let delta = 2.0 * f64::EPSILON;
        for scale in [1e3, 1e-3] {
            let nearly_singular = Mat::<f64>::from_fn(2, 2, |i, j| {
                scale * if i + j == 2 { 1.0 + delta } else { 1.0 }
            });
            assert_eq!(
                start(&nearly_singular),
                Err(IntegrationError::Singular("mass")),
                "scale {scale}"
            );
        }
        let tiny = Mat::<f64>::identity(2, 2) * faer::Scale(1e-6);
        assert_eq!(start(&tiny), Ok(()));
    }

    /// Every step of every method satisfies the method's defining equations, checked from the
    /// observed states of a damped, loaded 2-DOF system started off rest at t0 ≠ 0 (so that
    /// every term of every update matters):
    /// - BDF1: v_k = (q_k − q_{k−1})/Δt, a_k = (v_k − v_{k−1})/Δt; BDF2 from its second step:
    ///   v_k = (3q_k − 4q_{k−1} + q_{k−2})/(2Δt), a_k likewise from v (thesis eq. 2.61 and its
    ///   second-order sibling); both with M a_k + C v_k + K q_k = f(t_k).
    /// - Generalized-α (Chung & Hulbert 1993, eqs. 9–11 with α_m, α_f, γ, β from ρ∞, eqs. 25, 17,
    ///   20): the Newmark updates q_{n+1} = q_n + Δt v_n + Δt²((½−β)a_n + β a_{n+1}),
    ///   v_{n+1} = v_n + Δt((1−γ)a_n + γ a_{n+1}), and the balance
    ///   M((1−α_m)a_{n+1} + α_m a_n) + (1−α_f)(C v_{n+1} + K q_{n+1}) + α_f(C v_n + K q_n)
    ///   = f(t_{n+1} − α_f Δt).
    #[test]
    fn every_step_satisfies_the_methods_defining_equations() {
        let [m, c, k] = coupled_two_dof();
        let sys = LinearSystem {
            mass: m.as_ref(),
            damping: c.as_ref(),
            stiffness: k.as_ref(),
        };
        let load = |t: f64| [(3.0 * t).sin(), (2.0 * t).cos()];
        let times = |a: &Mat<f64>, x: &[f64]| {
            [
                a[(0, 0)] * x[0] + a[(0, 1)] * x[1],
                a[(1, 0)] * x[0] + a[(1, 1)] * x[1],
            ]
        };
        let dt = 0.05;
        let run = Run {
            dt,
            steps: 20,
            t0: 0.3,
        };
        let close = |what: &str, method: Method, step: usize, lhs: [f64; 2], rhs: [f64; 2]| {
            for i in 0..2 {
                assert!(
                    (lhs[i] - rhs[i]).abs() < 1e-10,
                    "{method:?} step {step}, {what}[{i}]: {} vs {}",
                    lhs[i],
                    rhs[i]
                );
            }
        };
        let methods = [
            Method::Bdf1,
            Method::Bdf2,
            Method::GeneralizedAlpha { rho_inf: 0.0 },
            Method::GeneralizedAlpha { rho_inf: 0.5 },
            Method::GeneralizedAlpha { rho_inf: 1.0 },
        ];
        for method in methods {
            let mut states = Vec::new();
            integrate_with(
                &mut Dense::new(sys).unwrap(),
                method,
                run,
                &[0.1, -0.2],
                &[0.3, 0.4],
                |t, f| f.copy_from_slice(&load(t)),
                |s| states.push((s.time, [s.q[0], s.q[1]], [s.v[0], s.v[1]], [s.a[0], s.a[1]])),
            )
            .unwrap();
            assert_eq!(states.len(), 21, "{method:?}");
            for n in 1..states.len() {
                let (t, q, v, a) = states[n];
                let (t_prev, q0, v0, a0) = states[n - 1];
                assert!((t - (0.3 + n as f64 * dt)).abs() < 1e-14 && t > t_prev);
                let (cv, kq, ma) = (times(&c, &v), times(&k, &q), times(&m, &a));
                match method {
                    Method::Bdf1 | Method::Bdf2 => {
                        let (vk, ak) = if method == Method::Bdf2 && n >= 2 {
                            let (_, q00, v00, _) = states[n - 2];
                            let d = |x: [f64; 2], x1: [f64; 2], x2: [f64; 2]| {
                                [0, 1].map(|i| (3.0 * x[i] - 4.0 * x1[i] + x2[i]) / (2.0 * dt))
                            };
                            (d(q, q0, q00), d(v, v0, v00))
                        } else {
                            (
                                [0, 1].map(|i| (q[i] - q0[i]) / dt),
                                [0, 1].map(|i| (v[i] - v0[i]) / dt),
                            )
                        };
                        close("v", method, n, v, vk);
                        close("a", method, n, a, ak);
                        let balance = [0, 1].map(|i| ma[i] + cv[i] + kq[i]);
                        close("balance", method, n, balance, load(t));
                    }
                    Method::GeneralizedAlpha { rho_inf } => {
                        let am = (2.0 * rho_inf - 1.0) / (rho_inf + 1.0);
                        let af = rho_inf / (rho_inf + 1.0);
                        let gamma = 0.5 - am + af;
                        let beta = 0.25 * (1.0 - am + af).powi(2);
                        let q_newmark = [0, 1].map(|i| {
                            q0[i] + dt * v0[i] + dt * dt * ((0.5 - beta) * a0[i] + beta * a[i])
                        });
                        let v_newmark =
                            [0, 1].map(|i| v0[i] + dt * ((1.0 - gamma) * a0[i] + gamma * a[i]));
                        close("q", method, n, q, q_newmark);
                        close("v", method, n, v, v_newmark);
                        let (cv0, kq0, ma0) = (times(&c, &v0), times(&k, &q0), times(&m, &a0));
                        let balance = [0, 1].map(|i| {
                            (1.0 - am) * ma[i]
                                + am * ma0[i]
                                + (1.0 - af) * (cv[i] + kq[i])
                                + af * (cv0[i] + kq0[i])
                        });
                        close("balance", method, n, balance, load(t - af * dt));
                    }
                }
            }
        }
    }
}
