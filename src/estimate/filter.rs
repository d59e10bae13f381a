//! The augmented extended Kalman filter on a pROM (thesis §8.2–8.3).
//!
//! State x* = [q, q̇, u_un, p] (eq. 8.1), u_un and p random walks (eq. 8.2–8.3). One step:
//!
//! - **Prediction** (eq. 8.22): BDF1 on the first-order form (eq. 8.10–8.13). With u and p held
//!   (their rows of A* are zero), g_d = 0 is linear in (q_k, q̇_k) at fixed p and is solved
//!   exactly: S q̇_k = M q̇_{k−1} − Δt K q_{k−1} + Δt (S_un u + f_kn(t_k)), q_k = q_{k−1} + Δt q̇_k,
//!   with the effective matrix S = M + Δt C + Δt² K at p_{k−1}⁺. q̈_k = (q̇_k − q̇_{k−1})/Δt
//!   is the equation of motion at step k.
//! - **Jacobian** J = −(∂g_d/∂x_k)⁻¹ ∂g_d/∂x_{k−1} = (I − Δt J_c)⁻¹ (eq. 8.16–8.18, J_c of
//!   eq. 8.32). Its rows for u and p are identity rows and its q rows are e_q + Δt (q̇ rows), so
//!   only the q̇ block row J_v (n × N) is computed, by one solve with S:
//!   J_v = S⁻¹ [−Δt K, M, Δt S_un, −Δt D], D_j = ∂K/∂p_j q + ∂C/∂p_j q̇ + ∂M/∂p_j q̈ — the
//!   analytic parameter derivatives of the affine pROM (eq. 8.19–8.20, 8.33–8.35: M D_j =
//!   −M ∂q̈/∂p_j). Without unknown parameters J is constant and computed once.
//! - **Covariance** P⁻ = J P Jᵀ + Q (eq. 8.24) as J (J P)ᵀ with the block rows above: 2 n N²
//!   multiply-adds instead of the dense 2 N³.
//! - **Correction**: measurement Jacobian J_m (eq. 8.37–8.39; [`super::measurement`]), gain
//!   (eq. 8.26), state update (eq. 8.27) and the Joseph-form covariance (eq. 8.28) evaluated as
//!   L P Lᵀ + 𝒦 R 𝒦ᵀ with L = I − 𝒦 J_m applied in O(N² m).
//! - **Refresh**: the pROM is evaluated at the new p⁺ (eq. 3.32, allocation-free), S and M are
//!   factored for the next step, and q̈⁺ comes from the equation of motion at x⁺.
//!
//! A step allocates nothing: every product, factor and right-hand side lives in buffers sized
//! at construction, the Cholesky factors are computed in place, and everything runs on the
//! calling thread (the systems are a few dozen DOFs: a thread hand-off costs more than it saves).

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::{cholesky_in_place, cholesky_in_place_scratch};
use faer::linalg::matmul::matmul;
use faer::{Accum, Mat, MatMut, MatRef, Par};

use super::measurement::{Reads, SensorRows};
use crate::rom::prom::{Prom, PromEvaluation};

/// Everything the filter needs; no deck involved.
#[derive(Debug, Clone)]
pub struct FilterSetup {
    pub prom: Prom,
    /// Values of every pROM parameter; the unknown ones are the initial guesses.
    pub p: Vec<f64>,
    /// Indices (into the pROM's parameters) of the estimated parameters.
    pub unknown_params: Vec<usize>,
    /// S_un (n_r × n_un): the reduced shapes of the unknown inputs.
    pub s_un: Mat<f64>,
    /// The measured sensor rows and their noise variances R (diagonal).
    pub measured: SensorRows,
    pub r: Vec<f64>,
    /// Filter step Δt.
    pub dt: f64,
    /// Diagonal of Q: model states (one value for q and q̇), inputs, parameters.
    pub q_state: f64,
    pub q_inputs: Vec<f64>,
    pub q_params: Vec<f64>,
    /// Initial state (q, q̇: length n_r each) and initial diagonal covariance.
    pub q0: Vec<f64>,
    pub v0: Vec<f64>,
    /// Initial unknown inputs.
    pub u0: Vec<f64>,
    pub p0_state: f64,
    pub p0_inputs: Vec<f64>,
    pub p0_params: Vec<f64>,
}

/// Why the filter cannot run.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FilterError {
    #[error("{what}: expected {expected}, got {got}")]
    Shape { what: &'static str, expected: usize, got: usize },
    #[error("at step {step}: {what} is not positive definite at parameters {params:?} (estimate left the physical range?)")]
    NotDefinite { step: usize, what: &'static str, params: Vec<f64> },
    #[error("at step {step}: the innovation covariance J_m P J_mᵀ + R is not positive definite")]
    Innovation { step: usize },
    #[error("at step {step}: the estimate became non-finite")]
    NonFinite { step: usize },
    #[error("{0}")]
    Prom(String),
}

/// The augmented EKF (see the module documentation).
pub struct Filter {
    setup: FilterSetup,
    n: usize,
    nu: usize,
    np: usize,
    /// x* = [q, q̇, u, p].
    x: Vec<f64>,
    /// q̈ at x (prior after predict, posterior after correct).
    a: Vec<f64>,
    p: Mat<f64>,
    at: PromEvaluation,
    params: Vec<f64>,
    /// Lower Cholesky factors of S = M + Δt C + Δt² K and of M at the current parameters.
    s_factor: Mat<f64>,
    m_factor: Mat<f64>,
    /// The M that `m_factor` factors (refactored only when the estimate changes M).
    factored_mass: Mat<f64>,
    /// J_v (n × N), kept between steps when no parameter is estimated.
    jv: Mat<f64>,
    jv_valid: bool,
    jm: Mat<f64>,
    /// N × N scratch (J P, L P).
    work: Mat<f64>,
    innovation: Vec<f64>,
    step: usize,
    scratch: Scratch,
}

/// Buffers of one step (sizes fixed by n, N, m, n_p).
struct Scratch {
    /// Reduced force, q̇ before the step, q + β q̇ and q̈ + α q̇ (n each).
    force: Vec<f64>,
    v_old: Vec<f64>,
    w_k: Vec<f64>,
    w_m: Vec<f64>,
    /// n × 1 right-hand side.
    rhs: Mat<f64>,
    /// D (n × n_p).
    d: Mat<f64>,
    /// h M⁻¹ of the ACCEL rows (n × 1).
    g: Mat<f64>,
    /// h(x⁻) (m), P J_mᵀ, 𝒦, 𝒦 R − L P J_mᵀ (N × m), J_m P J_mᵀ + R (m × m).
    predicted: Vec<f64>,
    pht: Mat<f64>,
    gain: Mat<f64>,
    kr: Mat<f64>,
    sy: Mat<f64>,
    /// Workspace of the in-place Cholesky factorizations.
    mem: MemBuffer,
}

impl Filter {
    /// Check the setup and prepare step 0.
    pub fn new(setup: FilterSetup) -> Result<Self, FilterError> {
        let n = setup.prom.size();
        let (nu, np, m) = (setup.s_un.ncols(), setup.unknown_params.len(), setup.measured.len());
        for (what, expected, got) in [
            ("S_un rows", n, setup.s_un.nrows()),
            ("parameter values", setup.prom.parameters.len(), setup.p.len()),
            ("noise variances", m, setup.r.len()),
            ("sensor row length", n, setup.measured.h.ncols()),
            ("input noise variances", nu, setup.q_inputs.len()),
            ("parameter noise variances", np, setup.q_params.len()),
            ("initial q", n, setup.q0.len()),
            ("initial q̇", n, setup.v0.len()),
            ("initial inputs", nu, setup.u0.len()),
            ("initial input variances", nu, setup.p0_inputs.len()),
            ("initial parameter variances", np, setup.p0_params.len()),
        ] {
            if expected != got {
                return Err(FilterError::Shape { what, expected, got });
            }
        }
        let big_n = 2 * n + nu + np;
        let mut x = vec![0.0; big_n];
        x[..n].copy_from_slice(&setup.q0);
        x[n..2 * n].copy_from_slice(&setup.v0);
        x[2 * n..2 * n + nu].copy_from_slice(&setup.u0);
        for (k, &j) in setup.unknown_params.iter().enumerate() {
            x[2 * n + nu + k] = setup.p[j];
        }
        let diag: Vec<f64> = std::iter::repeat_n(setup.p0_state, 2 * n).chain(setup.p0_inputs.iter().copied()).chain(setup.p0_params.iter().copied()).collect();
        let p = Mat::from_fn(big_n, big_n, |i, j| if i == j { diag[i] } else { 0.0 });
        let at = setup.prom.workspace();
        let params = setup.p.clone();
        let scratch = Scratch {
            force: vec![0.0; n],
            v_old: vec![0.0; n],
            w_k: vec![0.0; n],
            w_m: vec![0.0; n],
            rhs: Mat::zeros(n, 1),
            d: Mat::zeros(n, np),
            g: Mat::zeros(n, 1),
            predicted: vec![0.0; m],
            pht: Mat::zeros(big_n, m),
            gain: Mat::zeros(big_n, m),
            kr: Mat::zeros(big_n, m),
            sy: Mat::zeros(m, m),
            mem: MemBuffer::new(cholesky_in_place_scratch::<f64>(n.max(m), Par::Seq, Default::default())),
        };
        let mut filter = Filter {
            factored_mass: Mat::zeros(n, n),
            n,
            nu,
            np,
            x,
            a: vec![0.0; n],
            p,
            at,
            params,
            s_factor: Mat::zeros(n, n),
            m_factor: Mat::zeros(n, n),
            jv: Mat::zeros(n, big_n),
            jv_valid: false,
            jm: Mat::zeros(m, big_n),
            work: Mat::zeros(big_n, big_n),
            innovation: vec![0.0; m],
            step: 0,
            scratch,
            setup,
        };
        filter.refresh()?;
        filter.set_acceleration(&vec![0.0; n]);
        Ok(filter)
    }

    /// Augmented state size N = 2 n_r + n_un + n_p.
    pub fn size(&self) -> usize {
        self.x.len()
    }

    /// x* = [q, q̇, u_un, p].
    pub fn state(&self) -> &[f64] {
        &self.x
    }

    /// q̈ at the current estimate.
    pub fn acceleration(&self) -> &[f64] {
        &self.a
    }

    pub fn covariance(&self) -> &Mat<f64> {
        &self.p
    }

    /// Values of every pROM parameter at the current estimate.
    pub fn parameters(&self) -> &[f64] {
        &self.params
    }

    /// y − h(x⁻) of the last step.
    pub fn innovation(&self) -> &[f64] {
        &self.innovation
    }

    /// J_m of the last step (rows of the measured sensors).
    pub fn measurement_jacobian(&self) -> &Mat<f64> {
        &self.jm
    }

    /// The transition Jacobian J of the last step (dense N × N, for checks and tools).
    pub fn transition(&self) -> Mat<f64> {
        let (n, big_n) = (self.n, self.size());
        Mat::from_fn(big_n, big_n, |i, j| {
            let e = if i == j { 1.0 } else { 0.0 };
            if i < n {
                e + self.setup.dt * self.jv[(i, j)]
            } else if i < 2 * n {
                self.jv[(i - n, j)]
            } else {
                e
            }
        })
    }

    /// The pROM at the current parameters (M_r, C_r, K_r and derivatives).
    pub fn evaluation(&self) -> &PromEvaluation {
        &self.at
    }

    /// Evaluate the pROM at the estimated parameters and factor S and M (the callers set q̈ from
    /// the equation of motion; with zero known load before the first step).
    fn refresh(&mut self) -> Result<(), FilterError> {
        let (n, nu) = (self.n, self.nu);
        for (k, &j) in self.setup.unknown_params.iter().enumerate() {
            self.params[j] = self.x[2 * n + nu + k];
        }
        if self.step > 0 && self.np == 0 {
            return Ok(());
        }
        self.setup.prom.evaluate(&self.params, &mut self.at).map_err(|e| FilterError::Prom(e.to_string()))?;
        let dt = self.setup.dt;
        let at = &self.at;
        for c in 0..n {
            let (m, cd, k) = (column(at.mass(), c), column(at.damping(), c), column(at.stiffness(), c));
            let s = self.s_factor.col_as_slice_mut(c);
            s.iter_mut().zip(m.iter().zip(cd.iter().zip(k))).for_each(|(s, (m, (cd, k)))| *s = m + dt * cd + dt * dt * k);
        }
        let s_ok = factor_in_place(self.s_factor.as_mut(), MemStack::new(&mut self.scratch.mem));
        let m_ok = (self.step > 0 && self.factored_mass == at.mass()) || {
            self.factored_mass.copy_from(&at.mass());
            self.m_factor.copy_from(&at.mass());
            factor_in_place(self.m_factor.as_mut(), MemStack::new(&mut self.scratch.mem))
        };
        let not_definite = |what| FilterError::NotDefinite { step: self.step, what, params: self.params.clone() };
        if !s_ok {
            return Err(not_definite("M + Δt C + Δt² K"));
        }
        if !m_ok {
            return Err(not_definite("M"));
        }
        self.jv_valid = false;
        Ok(())
    }

    /// Reduced force S_un u + f_kn at the current estimate, into `scratch.force`.
    fn set_force(&mut self, f_kn: &[f64]) {
        let (n, nu) = (self.n, self.nu);
        let f = &mut self.scratch.force;
        f.copy_from_slice(f_kn);
        for j in 0..nu {
            let u = self.x[2 * n + j];
            f.iter_mut().zip(self.setup.s_un.col_as_slice(j)).for_each(|(f, s)| *f += s * u);
        }
    }

    /// q̈ = M⁻¹(f − K q − C q̇) at the current x, into `a`.
    fn set_acceleration(&mut self, f_kn: &[f64]) {
        let n = self.n;
        self.set_force(f_kn);
        let rhs = self.scratch.rhs.col_as_slice_mut(0);
        rhs.copy_from_slice(&self.scratch.force);
        for c in 0..n {
            let (q, v) = (self.x[c], self.x[n + c]);
            let (k, cd) = (column(self.at.stiffness(), c), column(self.at.damping(), c));
            rhs.iter_mut().zip(k.iter().zip(cd)).for_each(|(r, (k, cd))| *r -= k * q + cd * v);
        }
        solve_seq(self.m_factor.as_ref(), self.scratch.rhs.as_mut());
        self.a.copy_from_slice(self.scratch.rhs.col_as_slice(0));
    }

    /// One filter step: predict to t_k with the known reduced load `f_kn` = S_kn u_kn(t_k), then
    /// correct with the measurements `y` (one per measured row).
    pub fn step(&mut self, f_kn: &[f64], y: &[f64]) -> Result<(), FilterError> {
        self.predict(f_kn)?;
        self.correct(f_kn, y)
    }

    /// The prediction half of a step (eq. 8.22–8.24): x⁻, q̈⁻, J and P⁻.
    pub fn predict(&mut self, f_kn: &[f64]) -> Result<(), FilterError> {
        let (n, nu, np) = (self.n, self.nu, self.np);
        if f_kn.len() != n {
            return Err(FilterError::Shape { what: "known load", expected: n, got: f_kn.len() });
        }
        self.step += 1;
        let dt = self.setup.dt;
        let big_n = self.size();
        // prediction (eq. 8.22)
        self.set_force(f_kn);
        self.scratch.v_old.copy_from_slice(&self.x[n..2 * n]);
        let rhs = self.scratch.rhs.col_as_slice_mut(0);
        rhs.iter_mut().zip(&self.scratch.force).for_each(|(r, f)| *r = dt * f);
        for c in 0..n {
            let (v, q) = (self.scratch.v_old[c], self.x[c]);
            let (m, k) = (column(self.at.mass(), c), column(self.at.stiffness(), c));
            rhs.iter_mut().zip(m.iter().zip(k)).for_each(|(r, (m, k))| *r += m * v - dt * k * q);
        }
        solve_seq(self.s_factor.as_ref(), self.scratch.rhs.as_mut());
        let v_new = self.scratch.rhs.col_as_slice(0);
        let (q, v) = self.x.split_at_mut(n);
        for (i, &vn) in v_new.iter().enumerate() {
            v[i] = vn;
            q[i] += dt * vn;
            self.a[i] = (vn - self.scratch.v_old[i]) / dt;
        }
        // Jacobian block row J_v (eq. 8.16–8.20, 8.33) at the predicted x_k, q̈_k (D of g_d's q_k terms)
        if !self.jv_valid || np > 0 {
            self.parameter_columns();
            let (at, s_un, d) = (&self.at, &self.setup.s_un, &self.scratch.d);
            for j in 0..big_n {
                let col = self.jv.col_as_slice_mut(j);
                let (src, scale) = match j {
                    j if j < n => (column(at.stiffness(), j), -dt),
                    j if j < 2 * n => (column(at.mass(), j - n), 1.0),
                    j if j < 2 * n + nu => (s_un.col_as_slice(j - 2 * n), dt),
                    j => (d.col_as_slice(j - 2 * n - nu), -dt),
                };
                col.iter_mut().zip(src).for_each(|(o, s)| *o = scale * s);
            }
            solve_seq(self.s_factor.as_ref(), self.jv.as_mut());
            self.jv_valid = true;
        }
        // P⁻ = J (J P)ᵀ + Q (eq. 8.24), in place: JP in `work`, then J (JP)ᵀ back into P
        let mut work = std::mem::replace(&mut self.work, Mat::new());
        self.apply_transition(self.p.as_ref(), &mut work);
        let mut p = std::mem::replace(&mut self.p, Mat::new());
        self.apply_transition(work.transpose(), &mut p);
        symmetrize(&mut p);
        for i in 0..big_n {
            p[(i, i)] += self.noise(i);
        }
        self.p = p;
        self.work = work;
        Ok(())
    }

    /// The correction half of a step (eq. 8.25–8.28) with the same known load as the prediction,
    /// then the refresh at p⁺.
    pub fn correct(&mut self, f_kn: &[f64], y: &[f64]) -> Result<(), FilterError> {
        let (n, m) = (self.n, self.setup.measured.len());
        if y.len() != m {
            return Err(FilterError::Shape { what: "measurements", expected: m, got: y.len() });
        }
        self.measurement_rows();
        let sc = &mut self.scratch;
        self.setup.measured.evaluate(&self.x[..n], &self.x[n..2 * n], &self.a, &mut sc.predicted);
        self.innovation.iter_mut().zip(y.iter().zip(&sc.predicted)).for_each(|(e, (y, h))| *e = y - h);
        matmul(sc.pht.as_mut(), Accum::Replace, self.p.as_ref(), self.jm.transpose(), 1.0, Par::Seq); // P J_mᵀ
        matmul(sc.sy.as_mut(), Accum::Replace, self.jm.as_ref(), sc.pht.as_ref(), 1.0, Par::Seq);
        for (i, r) in self.setup.r.iter().enumerate() {
            sc.sy[(i, i)] += r;
        }
        if !factor_in_place(sc.sy.as_mut(), MemStack::new(&mut sc.mem)) {
            return Err(FilterError::Innovation { step: self.step });
        }
        // 𝒦ᵀ = S_y⁻¹ (P J_mᵀ)ᵀ, solved on the transposed view of 𝒦 (N × m)
        sc.gain.copy_from(&sc.pht);
        solve_seq(sc.sy.as_ref(), sc.gain.as_mut().transpose_mut());
        for (j, e) in self.innovation.iter().enumerate() {
            self.x.iter_mut().zip(sc.gain.col_as_slice(j)).for_each(|(x, k)| *x += k * e);
        }
        // Joseph form (eq. 8.28): L P Lᵀ + 𝒦 R 𝒦ᵀ with L P = P − 𝒦 (J_m P) and
        // (L P) Lᵀ = L P − (L P J_mᵀ) 𝒦ᵀ: L P in `work`, then P⁺ = L P + (𝒦 R − L P J_mᵀ) 𝒦ᵀ
        self.work.copy_from(&self.p);
        matmul(self.work.as_mut(), Accum::Add, sc.gain.as_ref(), sc.pht.transpose(), -1.0, Par::Seq);
        for (j, r) in self.setup.r.iter().enumerate() {
            sc.kr.col_as_slice_mut(j).iter_mut().zip(sc.gain.col_as_slice(j)).for_each(|(o, k)| *o = k * r);
        }
        matmul(sc.kr.as_mut(), Accum::Add, self.work.as_ref(), self.jm.transpose(), -1.0, Par::Seq);
        self.p.copy_from(&self.work);
        matmul(self.p.as_mut(), Accum::Add, sc.kr.as_ref(), sc.gain.transpose(), 1.0, Par::Seq);
        symmetrize(&mut self.p);
        if !self.x.iter().all(|v| v.is_finite()) {
            return Err(FilterError::NonFinite { step: self.step });
        }
        self.refresh()?;
        self.set_acceleration(f_kn);
        Ok(())
    }

    /// Diagonal of Q at augmented index i (eq. 8.29).
    fn noise(&self, i: usize) -> f64 {
        let (n, nu) = (self.n, self.nu);
        if i < 2 * n {
            self.setup.q_state
        } else if i < 2 * n + nu {
            self.setup.q_inputs[i - 2 * n]
        } else {
            self.setup.q_params[i - 2 * n - nu]
        }
    }

    /// D at the current x and q̈ into `scratch.d` (see [`parameter_columns`]).
    fn parameter_columns(&mut self) {
        let n = self.n;
        let ab = (self.setup.prom.alpha, self.setup.prom.beta);
        let sc = &mut self.scratch;
        parameter_columns_into(&self.at, ab, &self.setup.unknown_params, (&self.x[..n], &self.x[n..2 * n], &self.a), (&mut sc.w_k, &mut sc.w_m), &mut sc.d);
    }

    /// Rows of J_m (eq. 8.38 for DISP/STRAIN, q̇ rows for VEL, eq. 8.39 for ACCEL with
    /// g = h M⁻¹: [−g K, −g C, g S_un, −g D]).
    fn measurement_rows(&mut self) {
        let (n, nu) = (self.n, self.nu);
        self.jm.fill(0.0);
        let any_accel = self.setup.measured.reads.contains(&Reads::Acceleration);
        if any_accel && self.np > 0 {
            self.parameter_columns();
        }
        let rows = &self.setup.measured;
        for r in 0..rows.len() {
            match rows.reads[r] {
                Reads::Displacement => (0..n).for_each(|i| self.jm[(r, i)] = rows.h[(r, i)]),
                Reads::Velocity => (0..n).for_each(|i| self.jm[(r, n + i)] = rows.h[(r, i)]),
                Reads::Acceleration => {
                    // g = M⁻¹ hᵀ (M symmetric), then each entry is g · (column)
                    let g = &mut self.scratch.g;
                    (0..n).for_each(|i| g[(i, 0)] = rows.h[(r, i)]);
                    solve_seq(self.m_factor.as_ref(), g.as_mut());
                    let g = g.col_as_slice(0);
                    let gk = |col: &[f64]| g.iter().zip(col).map(|(a, b)| a * b).sum::<f64>();
                    for c in 0..n {
                        self.jm[(r, c)] = -gk(column(self.at.stiffness(), c));
                        self.jm[(r, n + c)] = -gk(column(self.at.damping(), c));
                    }
                    for c in 0..nu {
                        self.jm[(r, 2 * n + c)] = gk(self.setup.s_un.col_as_slice(c));
                    }
                    for c in 0..self.np {
                        self.jm[(r, 2 * n + nu + c)] = -gk(self.scratch.d.col_as_slice(c));
                    }
                }
            }
        }
    }

    /// out = J X for the structured J: q̇ rows J_v X, q rows X_q + Δt (q̇ rows), other rows X
    /// (one n × N × N product instead of N³).
    fn apply_transition(&self, x: MatRef<'_, f64>, out: &mut Mat<f64>) {
        let (n, dt) = (self.n, self.setup.dt);
        out.copy_from(x);
        matmul(out.as_mut().subrows_mut(n, n), Accum::Replace, self.jv.as_ref(), x, 1.0, Par::Seq);
        for c in 0..out.ncols() {
            let col = out.col_as_slice_mut(c);
            let (q, v) = col.split_at_mut(n);
            q.iter_mut().zip(&v[..n]).for_each(|(q, v)| *q += dt * v);
        }
    }
}

/// Cholesky factor A = L Lᵀ in place, sequential (L in the lower triangle; the strict upper
/// triangle is left as it was and never read). False when A is not positive definite.
fn factor_in_place(a: MatMut<'_, f64>, stack: &mut MemStack) -> bool {
    cholesky_in_place(a, Default::default(), Par::Seq, stack, Default::default()).is_ok()
}

/// x ← A⁻¹ x for A = L Lᵀ with L the lower triangle of `l`, sequential (the filter's systems
/// are small: threads cost more than they bring).
fn solve_seq(l: MatRef<'_, f64>, mut x: MatMut<'_, f64>) {
    faer::linalg::triangular_solve::solve_lower_triangular_in_place(l, x.as_mut(), Par::Seq);
    faer::linalg::triangular_solve::solve_upper_triangular_in_place(l.transpose(), x, Par::Seq);
}

/// p ← (p + pᵀ)/2.
fn symmetrize(p: &mut Mat<f64>) {
    let n = p.nrows();
    for j in 0..n {
        for i in (j + 1)..n {
            let s = 0.5 * (p[(i, j)] + p[(j, i)]);
            p[(i, j)] = s;
            p[(j, i)] = s;
        }
    }
}

/// D (n × n_p): D_j = ∂K/∂p_j (q + β q̇) + ∂M/∂p_j (q̈ + α q̇) = ∂K/∂p_j q + ∂C/∂p_j q̇ +
/// ∂M/∂p_j q̈ for the parameters `params`, so that ∂q̈/∂p_j = −M⁻¹ D_j (eq. 8.33–8.35 with
/// Rayleigh damping, derivatives of the affine pROM, eq. 8.19–8.20).
pub fn parameter_columns(at: &PromEvaluation, alpha_beta: (f64, f64), params: &[usize], q: &[f64], v: &[f64], a: &[f64]) -> Mat<f64> {
    let n = q.len();
    let mut d = Mat::zeros(n, params.len());
    parameter_columns_into(at, alpha_beta, params, (q, v, a), (&mut vec![0.0; n], &mut vec![0.0; n]), &mut d);
    d
}

/// [`parameter_columns`] into `d` (n × n_p), column by column, with `w` two n-vectors of scratch.
fn parameter_columns_into(at: &PromEvaluation, (alpha, beta): (f64, f64), params: &[usize], (q, v, a): (&[f64], &[f64], &[f64]), w: (&mut [f64], &mut [f64]), d: &mut Mat<f64>) {
    let (w_k, w_m) = w;
    for c in 0..q.len() {
        w_k[c] = q[c] + beta * v[c];
        w_m[c] = a[c] + alpha * v[c];
    }
    for (k, &j) in params.iter().enumerate() {
        let (dk, dm) = (at.d_stiffness(j), at.d_mass(j));
        let out = d.col_as_slice_mut(k);
        out.fill(0.0);
        for c in 0..q.len() {
            let (sk, sm) = (w_k[c], w_m[c]);
            out.iter_mut().zip(column(dk, c).iter().zip(column(dm, c))).for_each(|(o, (k, m))| *o += k * sk + m * sm);
        }
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::dynamics::integrators::{LinearSystem, Method, integrate};
    use crate::fe::affine::{Coefficient, CoefficientValues};
    use crate::rom::prom::{AffineFunction, CoefficientInput, PromParameter};

    /// 2-DOF chain: K = E K¹ + K⁰ (a grounded spring that does not scale), M = ρ M¹,
    /// Rayleigh α, β; parameters E (index 0) and ρ (index 1).
    pub(crate) fn chain() -> Prom {
        let fixed = CoefficientValues { e: 1.0, rho: 1.0, ..Default::default() };
        let k1 = Mat::from_fn(2, 2, |i, j| [[2.0, -1.0], [-1.0, 1.0]][i][j] * 1e4);
        let k0 = Mat::from_fn(2, 2, |i, j| if i == j && i == 0 { 5e3 } else { 0.0 });
        let m1 = Mat::from_fn(2, 2, |i, j| [[2.0, 0.1], [0.1, 1.0]][i][j]);
        Prom {
            parameters: vec![
                PromParameter { name: "E".into(), low: 0.5, high: 2.0, nominal: 1.0 },
                PromParameter { name: "RHO".into(), low: 0.5, high: 2.0, nominal: 1.0 },
            ],
            functions: vec![
                AffineFunction::constant(),
                AffineFunction { coefficient: Coefficient::E, fixed, driven_by: vec![(CoefficientInput::E, 0)] },
                AffineFunction { coefficient: Coefficient::Rho, fixed, driven_by: vec![(CoefficientInput::Rho, 1)] },
            ],
            stiffness: vec![k0, k1, Mat::zeros(2, 2)],
            mass: vec![Mat::zeros(2, 2), Mat::zeros(2, 2), m1],
            alpha: 0.8,
            beta: 2e-4,
        }
    }

    /// Unknown E, ρ and one input at DOF 2; a DISP row on DOF 1 and an ACCEL row on DOF 2.
    fn setup(x: &[f64]) -> FilterSetup {
        let sensors = SensorRows::new(vec!["D1".into(), "A2".into()], vec!["DISP".into(), "ACCEL".into()], Mat::from_fn(2, 2, |i, j| if i == j { 1.0 } else { 0.0 })).unwrap();
        FilterSetup {
            prom: chain(),
            p: vec![x[5], x[6]],
            unknown_params: vec![0, 1],
            s_un: Mat::from_fn(2, 1, |i, _| i as f64),
            measured: sensors,
            r: vec![1e-12, 1e-6],
            dt: 1e-3,
            q_state: 1e-16,
            q_inputs: vec![1e-2],
            q_params: vec![1e-8, 1e-8],
            q0: x[0..2].to_vec(),
            v0: x[2..4].to_vec(),
            u0: vec![x[4]],
            p0_state: 1e-20,
            p0_inputs: vec![1.0],
            p0_params: vec![0.1, 0.1],
        }
    }

    const X: [f64; 7] = [1e-3, -2e-3, 0.3, 0.1, 4.0, 1.2, 0.9];
    const LOAD: [f64; 2] = [3.0, -1.0];

    /// J of eq. 8.16 (with the analytic parameter columns) against central differences of the
    /// exact BDF1 prediction map x_{k−1} ↦ x_k. The map is quadratic-free in (q, q̇, u) and
    /// smooth in p; steps of 1e-6 relative give truncation ~1e-12 and round-off ~1e-10 relative
    /// to the column: bound 1e-7.
    #[test]
    fn prediction_jacobian_matches_finite_differences() {
        let mut base = Filter::new(setup(&X)).unwrap();
        base.predict(&LOAD).unwrap();
        let j = base.transition();
        for c in 0..7 {
            let h = 1e-6 * X[c].abs().max(1e-3);
            let predicted = |sign: f64| {
                let mut x = X;
                x[c] += sign * h;
                let mut f = Filter::new(setup(&x)).unwrap();
                f.predict(&LOAD).unwrap();
                f.state().to_vec()
            };
            let (up, down) = (predicted(1.0), predicted(-1.0));
            let fd: Vec<f64> = up.iter().zip(&down).map(|(a, b)| (a - b) / (2.0 * h)).collect();
            let scale = fd.iter().chain((0..7).map(|r| &j[(r, c)])).fold(0.0_f64, |m, v| m.max(v.abs()));
            for r in 0..7 {
                assert!((fd[r] - j[(r, c)]).abs() <= 1e-7 * scale, "J[{r},{c}] = {} vs finite difference {}", j[(r, c)], fd[r]);
            }
        }
    }

    /// J_m (eq. 8.38 for DISP, eq. 8.39 for ACCEL) against central differences of h(x*) with
    /// q̈ from the equation of motion; same step and bound as above.
    #[test]
    fn measurement_jacobian_matches_finite_differences() {
        let mut base = Filter::new(setup(&X)).unwrap();
        base.measurement_rows();
        let h_of = |x: &[f64]| {
            let f = Filter::new(setup(x)).unwrap();
            let mut y = vec![0.0; 2];
            f.setup.measured.evaluate(&f.x[..2], &f.x[2..4], &f.a, &mut y);
            y
        };
        for c in 0..7 {
            let h = 1e-6 * X[c].abs().max(1e-3);
            let (mut up, mut down) = (X, X);
            up[c] += h;
            down[c] -= h;
            let (yu, yd) = (h_of(&up), h_of(&down));
            for r in 0..2 {
                let fd = (yu[r] - yd[r]) / (2.0 * h);
                let scale = fd.abs().max(base.jm[(r, c)].abs()).max(1e-30);
                assert!((fd - base.jm[(r, c)]).abs() <= 1e-7 * scale, "J_m[{r},{c}] = {} vs finite difference {fd}", base.jm[(r, c)]);
            }
        }
    }

    /// With nothing unknown, the prediction is the BDF1 integrator of the transient sequence
    /// (the filter's model is the one that generates SOL TRANSIENT data): same q, q̇, q̈ to
    /// round-off over 200 steps of a sine load.
    #[test]
    fn prediction_equals_the_bdf1_integrator() {
        let mut s = setup(&X);
        s.unknown_params.clear();
        s.q_params.clear();
        s.p0_params.clear();
        s.s_un = Mat::zeros(2, 0);
        s.q_inputs.clear();
        s.p0_inputs.clear();
        s.u0.clear();
        let mut filter = Filter::new(s.clone()).unwrap();
        let mut at = s.prom.workspace();
        s.prom.evaluate(&s.p, &mut at).unwrap();
        let sys = LinearSystem { mass: at.mass(), damping: at.damping(), stiffness: at.stiffness() };
        let load = |t: f64, f: &mut [f64]| f.iter_mut().zip(LOAD).for_each(|(f, l)| *f = l * (40.0 * t).sin());
        let mut reference = Vec::new();
        integrate(sys, Method::Bdf1, s.dt, 200, &s.q0, &s.v0, load, |st| reference.push((st.q.to_vec(), st.v.to_vec(), st.a.to_vec()))).unwrap();
        for (k, (q, v, a)) in reference.iter().enumerate().skip(1) {
            let mut f = [0.0; 2];
            load(k as f64 * s.dt, &mut f);
            filter.predict(&f).unwrap();
            let x = filter.state();
            for i in 0..2 {
                assert!((x[i] - q[i]).abs() <= 1e-12 * 1e-2 && (x[2 + i] - v[i]).abs() <= 1e-12 && (filter.a[i] - a[i]).abs() <= 1e-9, "step {k}");
            }
        }
    }
}

/// The linear cross-check against filterpy (tools/estimate/filterpy_reference.py).
#[cfg(test)]
mod filterpy_check {
    use super::tests::chain;
    use super::*;

    const STEPS: usize = 200;

    /// No unknown parameter, one unknown input at DOF 2 (a linear augmented system), a DISP
    /// row on DOF 1 and an ACCEL row on DOF 2; arbitrary deterministic measurements.
    fn linear_case() -> (FilterSetup, Vec<[f64; 2]>) {
        let sensors = SensorRows::new(vec!["D1".into(), "A2".into()], vec!["DISP".into(), "ACCEL".into()], Mat::from_fn(2, 2, |i, j| if i == j { 1.0 } else { 0.0 })).unwrap();
        let setup = FilterSetup {
            prom: chain(),
            p: vec![1.0, 1.0],
            unknown_params: vec![],
            s_un: Mat::from_fn(2, 1, |i, _| i as f64),
            measured: sensors,
            r: vec![1e-8, 1e-4],
            dt: 1e-3,
            q_state: 1e-12,
            q_inputs: vec![1e-2],
            q_params: vec![],
            q0: vec![1e-4, 0.0],
            v0: vec![0.0, 0.01],
            u0: vec![0.5],
            p0_state: 1e-6,
            p0_inputs: vec![1.0],
            p0_params: vec![],
        };
        let z = (1..=STEPS).map(|k| k as f64 * 1e-3).map(|t| [1e-3 * (30.0 * t).sin(), 0.5 * (50.0 * t).cos()]).collect();
        (setup, z)
    }

    fn rows(m: &Mat<f64>) -> Vec<Vec<f64>> {
        (0..m.nrows()).map(|i| (0..m.ncols()).map(|j| m[(i, j)]).collect()).collect()
    }

    /// The filter's estimates equal filterpy's KalmanFilter (Joseph update) run on the same
    /// F = J, H = J_m, Q, R, x₀, P₀ and measurements. Reference:
    /// reference/estimate/filterpy_linear.json, made by tools/estimate/filterpy_reference.py
    /// from the case this test writes when PARAFLEX_WRITE_KF_CASE names a file. The two
    /// implementations differ in operation order only (J (J P)ᵀ vs F P Fᵀ, the expanded vs
    /// literal Joseph product, q̈⁻ from the BDF1 difference vs J_m x⁻): round-off, amplified
    /// by the conditioning of P (entries from 1e-12 to 1): bound 1e-9 of each state's range.
    #[test]
    fn linear_case_equals_filterpy() {
        let (setup, z) = linear_case();
        let mut filter = Filter::new(setup.clone()).unwrap();
        let zero = [0.0; 2];
        let mut states = Vec::new();
        let mut jacobians = None;
        for y in &z {
            filter.step(&zero, y).unwrap();
            states.push(filter.state().to_vec());
            jacobians.get_or_insert_with(|| (filter.transition(), filter.measurement_jacobian().clone()));
        }
        let (f, h) = jacobians.unwrap();
        if let Ok(path) = std::env::var("PARAFLEX_WRITE_KF_CASE") {
            let q: Vec<f64> = (0..5).map(|i| filter.noise(i)).collect();
            let p0: Vec<f64> = vec![1e-6, 1e-6, 1e-6, 1e-6, 1.0];
            let x0: Vec<f64> = [setup.q0.clone(), setup.v0.clone(), setup.u0.clone()].concat();
            let case = serde_json::json!({ "F": rows(&f), "H": rows(&h), "Q_diag": q, "R_diag": setup.r, "x0": x0, "P0_diag": p0, "z": z });
            std::fs::write(&path, serde_json::to_string_pretty(&case).unwrap()).unwrap();
        }
        let reference = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("reference/estimate/filterpy_linear.json");
        let text = std::fs::read_to_string(&reference).expect("reference/estimate/filterpy_linear.json");
        let r: serde_json::Value = serde_json::from_str(&text).unwrap();
        let matrix = |key: &str| -> Vec<Vec<f64>> { serde_json::from_value(r["case"][key].clone()).unwrap() };
        // the reference was made from these very matrices
        for (key, ours) in [("F", rows(&f)), ("H", rows(&h))] {
            for (a, b) in matrix(key).iter().flatten().zip(ours.iter().flatten()) {
                assert!((a - b).abs() <= 1e-14 * a.abs().max(1e-300) + 1e-300, "{key}: {a} vs {b}");
            }
        }
        let expected: Vec<Vec<f64>> = serde_json::from_value(r["x"].clone()).unwrap();
        assert_eq!(expected.len(), STEPS);
        for c in 0..5 {
            let range = expected.iter().map(|x| x[c].abs()).fold(0.0, f64::max);
            let worst = expected.iter().zip(&states).map(|(e, s)| (e[c] - s[c]).abs()).fold(0.0, f64::max);
            println!("state {c}: max |paraflex − filterpy| = {worst:.2e} (range {range:.2e})");
            assert!(worst <= 1e-9 * range, "state {c}: {worst:e} vs range {range:e}");
        }
    }
}

/// Column `c` of a pROM evaluation's matrix as a slice: [`crate::rom::prom::PromEvaluation`]'s
/// views are column-major over one contiguous buffer, so every column is contiguous.
fn column(m: MatRef<'_, f64>, c: usize) -> &[f64] {
    m.col(c).try_as_col_major().expect("pROM evaluation views are column-major").as_slice()
}
