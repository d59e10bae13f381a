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

use faer::linalg::matmul::matmul;
use faer::linalg::solvers::Llt;
use faer::{Accum, Mat, MatRef, Par, Side};

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
    s_factor: Llt<f64>,
    m_factor: Llt<f64>,
    /// J_v (n × N), kept between steps when no parameter is estimated.
    jv: Mat<f64>,
    jv_valid: bool,
    jm: Mat<f64>,
    /// N × N scratch (J P, L P).
    work: Mat<f64>,
    innovation: Vec<f64>,
    step: usize,
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
        let placeholder = Mat::<f64>::identity(n.max(1), n.max(1)).llt(Side::Lower).map_err(|_| FilterError::Prom("identity factor".into()))?;
        let mut filter = Filter {
            n,
            nu,
            np,
            x,
            a: vec![0.0; n],
            p,
            at,
            params,
            s_factor: placeholder.clone(),
            m_factor: placeholder,
            jv: Mat::zeros(n, big_n),
            jv_valid: false,
            jm: Mat::zeros(m, big_n),
            work: Mat::zeros(big_n, big_n),
            innovation: vec![0.0; m],
            step: 0,
            setup,
        };
        filter.refresh()?;
        filter.a = filter.acceleration_at(&vec![0.0; n]);
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
        let s = Mat::from_fn(n, n, |i, j| at.mass[(i, j)] + dt * at.damping[(i, j)] + dt * dt * at.stiffness[(i, j)]);
        let not_definite = |what| FilterError::NotDefinite { step: self.step, what, params: self.params.clone() };
        self.s_factor = s.llt(Side::Lower).map_err(|_| not_definite("M + Δt C + Δt² K"))?;
        self.m_factor = at.mass.llt(Side::Lower).map_err(|_| not_definite("M"))?;
        self.jv_valid = false;
        Ok(())
    }

    /// Reduced force S_un u + f_kn at the current estimate.
    fn force(&self, f_kn: &[f64]) -> Vec<f64> {
        let (n, nu) = (self.n, self.nu);
        let u = &self.x[2 * n..2 * n + nu];
        (0..n).map(|i| f_kn[i] + (0..nu).map(|j| self.setup.s_un[(i, j)] * u[j]).sum::<f64>()).collect()
    }

    /// q̈ = M⁻¹(f − K q − C q̇) at the current x.
    fn acceleration_at(&self, f_kn: &[f64]) -> Vec<f64> {
        let n = self.n;
        let f = self.force(f_kn);
        let (q, v) = (&self.x[..n], &self.x[n..2 * n]);
        let mut a = Mat::from_fn(n, 1, |i, _| f[i] - (0..n).map(|j| self.at.stiffness[(i, j)] * q[j] + self.at.damping[(i, j)] * v[j]).sum::<f64>());
        solve_seq(&self.m_factor, a.as_mut());
        (0..n).map(|i| a[(i, 0)]).collect()
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
        let f = self.force(f_kn);
        let v_old: Vec<f64> = self.x[n..2 * n].to_vec();
        let at = &self.at;
        let mut v_new = Mat::from_fn(n, 1, |i, _| (0..n).map(|j| at.mass[(i, j)] * v_old[j] - dt * at.stiffness[(i, j)] * self.x[j]).sum::<f64>() + dt * f[i]);
        solve_seq(&self.s_factor, v_new.as_mut());
        for i in 0..n {
            self.x[n + i] = v_new[(i, 0)];
            self.x[i] += dt * v_new[(i, 0)];
            self.a[i] = (v_new[(i, 0)] - v_old[i]) / dt;
        }
        // Jacobian block row J_v (eq. 8.16–8.20, 8.33)
        if !self.jv_valid || np > 0 {
            let d = self.parameter_columns();
            let at = &self.at;
            let s_un = &self.setup.s_un;
            let mut rhs = Mat::from_fn(n, big_n, |i, j| match j {
                j if j < n => -dt * at.stiffness[(i, j)],
                j if j < 2 * n => at.mass[(i, j - n)],
                j if j < 2 * n + nu => dt * s_un[(i, j - 2 * n)],
                j => -dt * d[(i, j - 2 * n - nu)],
            });
            solve_seq(&self.s_factor, rhs.as_mut());
            self.jv = rhs;
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
        let big_n = self.size();
        self.measurement_rows();
        let p = &self.p;
        let mut predicted = vec![0.0; m];
        self.setup.measured.evaluate(&self.x[..n], &self.x[n..2 * n], &self.a, &mut predicted);
        self.innovation.iter_mut().zip(y.iter().zip(&predicted)).for_each(|(e, (y, h))| *e = y - h);
        let mut pht = Mat::zeros(big_n, m); // P J_mᵀ
        matmul(pht.as_mut(), Accum::Replace, p.as_ref(), self.jm.transpose(), 1.0, Par::Seq);
        let mut sy = Mat::zeros(m, m);
        matmul(sy.as_mut(), Accum::Replace, self.jm.as_ref(), pht.as_ref(), 1.0, Par::Seq);
        for (i, r) in self.setup.r.iter().enumerate() {
            sy[(i, i)] += r;
        }
        let sy_factor = sy.llt(Side::Lower).map_err(|_| FilterError::Innovation { step: self.step })?;
        let mut gain_t = pht.transpose().to_owned();
        solve_seq(&sy_factor, gain_t.as_mut());
        let gain = gain_t.transpose().to_owned(); // N × m
        for i in 0..big_n {
            self.x[i] += (0..m).map(|j| gain[(i, j)] * self.innovation[j]).sum::<f64>();
        }
        // Joseph form (eq. 8.28): L P Lᵀ + 𝒦 R 𝒦ᵀ with L P = P − 𝒦 (J_m P) and
        // (L P) Lᵀ = L P − (L P J_mᵀ) 𝒦ᵀ: L P in `work`, then P⁺ = L P + (𝒦 R − L P J_mᵀ) 𝒦ᵀ
        let mut work = std::mem::replace(&mut self.work, Mat::new());
        work.copy_from(p);
        matmul(work.as_mut(), Accum::Add, gain.as_ref(), pht.transpose(), -1.0, Par::Seq);
        let mut kr_minus = Mat::from_fn(big_n, m, |i, j| gain[(i, j)] * self.setup.r[j]);
        matmul(kr_minus.as_mut(), Accum::Add, work.as_ref(), self.jm.transpose(), -1.0, Par::Seq);
        let mut post = std::mem::replace(&mut self.p, Mat::new());
        post.copy_from(&work);
        matmul(post.as_mut(), Accum::Add, kr_minus.as_ref(), gain.transpose(), 1.0, Par::Seq);
        symmetrize(&mut post);
        self.work = work;
        self.p = post;
        if !self.x.iter().all(|v| v.is_finite()) {
            return Err(FilterError::NonFinite { step: self.step });
        }
        self.refresh()?;
        self.a = self.acceleration_at(f_kn);
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

    /// D at the current x and q̈ (see [`parameter_columns`]).
    fn parameter_columns(&self) -> Mat<f64> {
        let n = self.n;
        let ab = (self.setup.prom.alpha, self.setup.prom.beta);
        parameter_columns(&self.at, ab, &self.setup.unknown_params, &self.x[..n], &self.x[n..2 * n], &self.a)
    }

    /// Rows of J_m (eq. 8.38 for DISP/STRAIN, q̇ rows for VEL, eq. 8.39 for ACCEL with
    /// g = h M⁻¹: [−g K, −g C, g S_un, −g D]).
    fn measurement_rows(&mut self) {
        let (n, nu) = (self.n, self.nu);
        let rows = &self.setup.measured;
        self.jm.fill(0.0);
        let accel: Vec<usize> = (0..rows.len()).filter(|&r| rows.reads[r] == Reads::Acceleration).collect();
        let d = if accel.is_empty() { Mat::zeros(n, 0) } else { self.parameter_columns() };
        let mut g_t = Mat::from_fn(n, accel.len(), |i, k| rows.h[(accel[k], i)]);
        solve_seq(&self.m_factor, g_t.as_mut());
        let g = g_t.transpose().to_owned();
        for r in 0..rows.len() {
            match rows.reads[r] {
                Reads::Displacement => (0..n).for_each(|i| self.jm[(r, i)] = rows.h[(r, i)]),
                Reads::Velocity => (0..n).for_each(|i| self.jm[(r, n + i)] = rows.h[(r, i)]),
                Reads::Acceleration => {
                    let k = accel.iter().position(|&x| x == r).unwrap_or(0);
                    let gk = |mat: &Mat<f64>, c: usize| (0..n).map(|i| g[(k, i)] * mat[(i, c)]).sum::<f64>();
                    for c in 0..n {
                        self.jm[(r, c)] = -gk(&self.at.stiffness, c);
                        self.jm[(r, n + c)] = -gk(&self.at.damping, c);
                    }
                    for c in 0..nu {
                        self.jm[(r, 2 * n + c)] = gk(&self.setup.s_un, c);
                    }
                    for c in 0..self.np {
                        self.jm[(r, 2 * n + nu + c)] = -gk(&d, c);
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

/// x ← A⁻¹ x for A = L Lᵀ, sequential (the filter's systems are small: threads cost more
/// than they bring).
fn solve_seq(factor: &Llt<f64>, mut x: faer::MatMut<'_, f64>) {
    let l = factor.L();
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
pub fn parameter_columns(at: &PromEvaluation, (alpha, beta): (f64, f64), params: &[usize], q: &[f64], v: &[f64], a: &[f64]) -> Mat<f64> {
    let n = q.len();
    Mat::from_fn(n, params.len(), |i, k| {
        let (dk, dm) = (&at.d_stiffness[params[k]], &at.d_mass[params[k]]);
        (0..n).map(|c| dk[(i, c)] * (q[c] + beta * v[c]) + dm[(i, c)] * (a[c] + alpha * v[c])).sum()
    })
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
        let sys = LinearSystem { mass: at.mass.as_ref(), damping: at.damping.as_ref(), stiffness: at.stiffness.as_ref() };
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
