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
//! - **Covariance** P⁻ = J P Jᵀ + Q (eq. 8.24) by blocks from G = J_v P and H = G J_vᵀ
//!   (see [`propagate`]): n N² + n² N multiply-adds instead of the dense 2 N³, and exactly
//!   symmetric.
//! - **Correction**: measurement Jacobian J_m (eq. 8.37–8.39; [`super::measurement`]), gain
//!   (eq. 8.26), state update (eq. 8.27) and the Joseph-form covariance (eq. 8.28)
//!   L P Lᵀ + 𝒦 R 𝒦ᵀ, L = I − 𝒦 J_m, expanded with U = P J_mᵀ, S_y = J_m U + R into
//!   P − 𝒦 Uᵀ − U 𝒦ᵀ + 𝒦 S_y 𝒦ᵀ (no term dropped: first-order insensitive to errors of 𝒦, as
//!   the Joseph form is), a symmetric rank-2m update: 2 N² m multiply-adds.
//! - **Refresh**: the pROM is evaluated at the new p⁺ (eq. 3.32, allocation-free), S and M are
//!   factored for the next step, and q̈⁺ comes from the equation of motion at x⁺.
//!
//! **Modal coordinates.** When every part of the pROM that the estimated parameters change is
//! diagonal in the modes Φ of the initial estimate ([`super::modal`]: E and ρ of one material,
//! or no parameter at all), the filter runs on z (q = Φ z), the same EKF under the linear change
//! of state x* = T z*, T = diag(Φ, Φ, I, I): J ↦ T⁻¹ J T, J_m ↦ J_m T, P ↦ T⁻¹ P T⁻ᵀ,
//! Q ↦ T⁻¹ Q T⁻ᵀ (its q and q̇ blocks become q_state Φ⁻¹ Φ⁻ᵀ, as the initial covariance's). M, C,
//! K, S and the derivatives are then diagonal, so J_v = [diag, diag, S⁻¹ [Δt S_un, −Δt D]],
//! P ← J P Jᵀ costs (N + 4 n) n (2 + n_un + n_p) ([`Modal::propagate`]) instead of
//! n N² + n² N, the solves are divisions and the pROM evaluation sums vectors. Sensor rows
//! (H Φ), input shapes (Φᵀ S_un), the known load (Φᵀ f) and the initial state are transformed
//! once or per step; [`Filter::state`], [`Filter::acceleration`], [`Filter::variance`] and
//! [`Filter::covariance`] map back to q on request ([`Filter::filter_state`] and
//! [`Filter::sensor_rows`] read sensors without it).
//! [`Coordinates::Physical`] keeps the physical path (and every other pROM uses it).
//!
//! **Re-diagonalized modal coordinates** ([`Coordinates::Rediagonalized`], EKF field REDIAG).
//! When a part the estimate changes is not diagonal in any modes (E of the bolted blade beside
//! its constant bolt springs), the filter still runs on the modes Φ of the estimate p₀ at which
//! they were last computed. K̃(p) and M̃(p) are then their diagonals plus the off-diagonal
//! couplings Σ (f_i(p) − f_i(p₀)) (Ã_i − diag Ã_i) ([`super::modal`]), which vanish at p₀:
//! - the **mean** stays exact: products use the full K̃, C̃, M̃ (a coupling of low rank as V Θ Vᵀ
//!   minus its diagonal: [`super::modal::OffDiagonal`]), and solves with S̃ or M̃ iterate
//!   x ← diag⁻¹ (b − off x) (Jacobi) to 4 ε. For a semi-definite part and its semi-definite
//!   remainder the iteration contracts by about the relative drift |f_i(p) − f_i(p₀)| / |f_i(p₀)|
//!   per step (the scaled coupling D^{-½} f_i Ã_i D^{-½} has eigenvalues in [0, 1]); if it has not
//!   converged after [`JACOBI_ITERATIONS`] the solve falls back to a dense LU (allocating) and
//!   the next refresh re-diagonalizes;
//! - the **Jacobian** takes its q and q̇ blocks from the diagonals of S̃, K̃, M̃ (J_v's input and
//!   parameter columns use the exact D but the diagonal of S̃): an error proportional to the drift
//!   in the covariance propagation only, which the EKF absorbs like any linearization error;
//! - when the largest drift exceeds the tolerance τ (or a solve stalled), the modes are
//!   recomputed at the current estimate and x*, P, S_un, the sensor rows and Q's blocks are
//!   transformed exactly (T P Tᵀ with T = diag(Φ₂⁻¹ Φ₁, Φ₂⁻¹ Φ₁, I, I); N³ and an n × n
//!   eigenproblem, a few hundred µs, while the estimate converges and rarely after).
//!
//! With τ below every change of the estimate the filter re-diagonalizes every step and is the
//! physical EKF under a change of state (test `rediagonalized_coordinates_follow_the_physical_path`).
//!
//! A step allocates nothing: every product, factor and right-hand side lives in buffers sized
//! at construction, the Cholesky factors are computed in place, and everything runs on the
//! calling thread (the systems are a few dozen DOFs: a thread hand-off costs more than it saves).

use std::cell::OnceCell;

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::{cholesky_in_place, cholesky_in_place_scratch};
use faer::linalg::matmul::matmul;
use faer::linalg::solvers::Solve;
use faer::{Accum, Mat, MatMut, MatRef, Par};

use super::measurement::{Reads, SensorRows};
use super::modal::{Coupling, ModalForm, modal_form, modal_form_after};
use crate::linalg::dense::{DenseEigenError, product, stiffness_semidefinite};
use crate::rom::prom::{Prom, PromError, PromEvaluation};

/// The coordinates the filter may run in.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum Coordinates {
    /// Modal coordinates when the pROM allows them (see the module documentation), the
    /// pROM's reduced coordinates q otherwise.
    #[default]
    Auto,
    /// Always the reduced coordinates q with the pROM's dense matrices.
    Physical,
    /// Modal coordinates on every pROM: exact where [`Coordinates::Auto`] takes them, and
    /// otherwise re-diagonalized modal coordinates whose modes are recomputed when the weight of
    /// a coupled part has drifted by more than this relative tolerance (0 < τ ≤ 0.1; see the
    /// module documentation).
    Rediagonalized(f64),
}

/// Largest re-diagonalization tolerance accepted: the coupled solves contract by about τ per
/// iteration (module documentation).
pub const MAX_REDIAGONALIZATION_TOLERANCE: f64 = 0.1;

/// Whether τ is an accepted re-diagonalization tolerance, 0 < τ ≤
/// [`MAX_REDIAGONALIZATION_TOLERANCE`] (false for NaN).
pub fn valid_rediagonalization_tolerance(tolerance: f64) -> bool {
    tolerance > 0.0 && tolerance <= MAX_REDIAGONALIZATION_TOLERANCE
}

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
    pub coordinates: Coordinates,
}

/// Why the filter cannot run.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FilterError {
    #[error("{what}: expected {expected}, got {got}")]
    Shape {
        what: &'static str,
        expected: usize,
        got: usize,
    },
    #[error(
        "at step {step}: {what} is not positive definite at parameters {params:?} (estimate left the physical range?)"
    )]
    NotDefinite {
        step: usize,
        what: &'static str,
        params: Vec<f64>,
    },
    #[error("at step {step}: the innovation covariance J_m P J_mᵀ + R is not positive definite")]
    Innovation { step: usize },
    #[error("at step {step}: the estimate became non-finite")]
    NonFinite { step: usize },
    #[error("{0}")]
    Prom(String),
    #[error("re-diagonalization tolerance {0}: expected 0 < τ ≤ {MAX_REDIAGONALIZATION_TOLERANCE}")]
    Tolerance(f64),
    #[error("the pROM at the initial guess {params:?}: {cause}")]
    IndefiniteStart {
        params: Vec<f64>,
        cause: DenseEigenError,
    },
}

/// The augmented EKF (see the module documentation).
pub struct Filter {
    /// The setup with S_un and the sensor rows in the filter's coordinates.
    setup: FilterSetup,
    n: usize,
    nu: usize,
    np: usize,
    /// x* = [q, q̇, u, p] in the filter's coordinates.
    x: Vec<f64>,
    /// q̈ at x (prior after predict, posterior after correct).
    a: Vec<f64>,
    p: Mat<f64>,
    params: Vec<f64>,
    model: Model,
    /// J_v is up to date (kept between steps when no parameter is estimated).
    jv_valid: bool,
    jm: Mat<f64>,
    /// Gᵀ = P J_vᵀ (N × n) and H = J_v P J_vᵀ (n × n) of the covariance prediction.
    gt: Mat<f64>,
    h: Mat<f64>,
    innovation: Vec<f64>,
    step: usize,
    scratch: Scratch,
}

/// Buffers of one step (sizes fixed by n, N, m, n_p).
struct Scratch {
    /// Known load in the filter's coordinates, reduced force, q̇ before the step, q + β q̇ and
    /// q̈ + α q̇, right-hand side, M⁻¹ h of an ACCEL row and a product with it (n each).
    load: Vec<f64>,
    /// The modes (re-diagonalization count) and the physical load that `load` was made from
    /// (modal coordinates: the correction reuses the prediction's Φᵀ f; NaN: none yet).
    load_of: (usize, Vec<f64>),
    force: Vec<f64>,
    v_old: Vec<f64>,
    w_k: Vec<f64>,
    w_m: Vec<f64>,
    rhs: Vec<f64>,
    g: Vec<f64>,
    t: Vec<f64>,
    /// D (n × n_p).
    d: Mat<f64>,
    /// h(x⁻) (m); U = P J_mᵀ, 𝒦, W = 𝒦 S_y / 2 − U (N × m); S_y = J_m U + R and its factor
    /// (m × m).
    predicted: Vec<f64>,
    pht: Mat<f64>,
    gain: Mat<f64>,
    w: Mat<f64>,
    sy: Mat<f64>,
    sy_factor: Mat<f64>,
    /// The transposed q block of Gᵀ and H̄ (n × 2n) for [`propagate`].
    mirror: Mat<f64>,
    /// The columns of [`Modal::propagate`].
    columns: ModalColumns,
    /// Workspace of the in-place Cholesky factorizations.
    mem: MemBuffer,
}

/// M, C, K, S and the transition rows in the filter's coordinates.
enum Model {
    Physical(Physical),
    Modal(Box<Modal>),
}

/// The pROM's dense matrices.
struct Physical {
    at: PromEvaluation,
    /// Lower Cholesky factors of S = M + Δt C + Δt² K and of M at the current parameters.
    s_factor: Mat<f64>,
    m_factor: Mat<f64>,
    /// The M that `m_factor` factors (refactored only when the estimate changes M).
    factored_mass: Mat<f64>,
    /// J_v (n × N).
    jv: Mat<f64>,
}

/// Diagonal matrices in modal coordinates z (q = Φ z).
struct Modal {
    form: ModalForm,
    /// Φ⁻¹ Φ⁻ᵀ: the q and q̇ blocks of Q and P₀ for a unit physical diagonal.
    gram: Mat<f64>,
    /// diag of K, M, C, S.
    k: Vec<f64>,
    m: Vec<f64>,
    c: Vec<f64>,
    s: Vec<f64>,
    /// diag of ∂K/∂p_j, ∂M/∂p_j per estimated parameter (n × n_p).
    dk: Mat<f64>,
    dm: Mat<f64>,
    /// J_v = [diag(jk), diag(jm), jw] (jw: n × (n_un + n_p)).
    jk: Vec<f64>,
    jm: Vec<f64>,
    jw: Mat<f64>,
    /// x* and q̈ in the physical coordinates, mapped on the first request after a step
    /// ([`Filter::state`], [`Filter::acceleration`]): a step itself never needs them.
    physical: OnceCell<(Vec<f64>, Vec<f64>)>,
    /// Δt and the Rayleigh α, β (for the off-diagonal parts of C and S).
    dt: f64,
    alpha: f64,
    beta: f64,
    /// The off-diagonal couplings (re-diagonalized coordinates only).
    drift: Option<Drift>,
}

/// What re-diagonalized modal coordinates add to [`Modal`] (see the module documentation).
struct Drift {
    tolerance: f64,
    /// f_i(p) − f_i(p₀) of each coupling: the off-diagonal parts of K̃(p) and M̃(p) are
    /// Σ (f_i(p) − f_i(p₀)) (Ã_i − diag Ã_i), applied part by part (never summed into a matrix).
    weights: Vec<f64>,
    /// ∂f_i/∂p_j of each coupling at p (n_c × n_p), for the parameter columns D.
    derivatives: Mat<f64>,
    /// Largest relative drift of a coupled weight from the modes' parameters.
    current: f64,
    /// S_un and the sensor rows in the physical coordinates, to transform after a
    /// re-diagonalization.
    s_un: Mat<f64>,
    h: Mat<f64>,
    /// Iterate and product buffers of the coupled solves (n).
    iterate: Vec<f64>,
    product: Vec<f64>,
    /// A coupled solve did not converge in [`JACOBI_ITERATIONS`]: re-diagonalize at the next
    /// refresh.
    stalled: bool,
    /// Re-diagonalizations so far.
    count: usize,
}

/// Iterations of a coupled solve before it falls back to a dense factorization (the iteration
/// contracts by about the drift per step, ≤ 0.1: 16 iterations reach round-off).
const JACOBI_ITERATIONS: usize = 40;

impl Modal {
    /// The factors (f_M, f_K) with which the off-diagonal parts of M̃ and K̃ enter `op`
    /// (C = α M + β K).
    fn off_factors(&self, op: Operator) -> (f64, f64) {
        match op {
            Operator::Stiffness => (0.0, 1.0),
            Operator::Damping => (self.alpha, self.beta),
            Operator::Mass => (1.0, 0.0),
        }
    }

    /// [`Modal::off_factors`] of S = M + Δt C + Δt² K.
    fn effective_factors(&self) -> (f64, f64) {
        (1.0 + self.dt * self.alpha, self.dt * (self.beta + self.dt))
    }
}

/// out += scale (f_M M̃_off + f_K K̃_off) x, the off-diagonal parts of the couplings at their
/// current weights.
fn add_coupled(
    couplings: &[Coupling],
    weights: &[f64],
    (f_m, f_k): (f64, f64),
    x: &[f64],
    out: &mut [f64],
    scale: f64,
) {
    for (coupling, &w) in couplings.iter().zip(weights) {
        for (f, off) in [(f_m, &coupling.mass), (f_k, &coupling.stiffness)] {
            if let (true, Some(off)) = (f * w != 0.0, off) {
                off.add_product(x, out, scale * f * w);
            }
        }
    }
}

/// x ← A⁻¹ x for A = diag(d) + f_M M̃_off + f_K K̃_off (the couplings' off-diagonal parts at
/// the weights of `drift`; none: a division). With couplings, by Jacobi iteration
/// x ← diag(d)⁻¹ (b − A_off x), which contracts by about the drift per iteration (module
/// documentation), until the update is below 4 ε of x; if it has not converged after
/// [`JACOBI_ITERATIONS`] (a coupled part that is not semi-definite), by a dense LU
/// factorization — allocating — and the drift is marked stalled, so the next refresh
/// re-diagonalizes.
fn solve_modal(
    d: &[f64],
    couplings: &[Coupling],
    drift: Option<&mut Drift>,
    factors: (f64, f64),
    x: &mut [f64],
) {
    let (f_m, f_k) = factors;
    let coupled = |dr: &&mut Drift| {
        couplings.iter().zip(&dr.weights).any(|(c, &w)| {
            w != 0.0 && ((f_m != 0.0 && c.mass.is_some()) || (f_k != 0.0 && c.stiffness.is_some()))
        })
    };
    let Some(dr) = drift.filter(coupled) else {
        x.iter_mut().zip(d).for_each(|(x, d)| *x /= d);
        return;
    };
    let (iterate, product, weights) = (&mut dr.iterate, &mut dr.product, &dr.weights);
    iterate
        .iter_mut()
        .zip(x.iter().zip(d))
        .for_each(|(z, (b, d))| *z = b / d);
    for _ in 0..JACOBI_ITERATIONS {
        product.fill(0.0);
        add_coupled(couplings, weights, factors, iterate, product, 1.0);
        let (mut change, mut size) = (0.0_f64, 0.0_f64);
        for i in 0..d.len() {
            let next = (x[i] - product[i]) / d[i];
            change = change.max((next - iterate[i]).abs());
            size = size.max(next.abs());
            iterate[i] = next;
        }
        if change <= 4.0 * f64::EPSILON * size {
            x.copy_from_slice(iterate);
            return;
        }
    }
    dr.stalled = true;
    let n = d.len();
    let mut a = Mat::from_fn(n, n, |i, j| if i == j { d[i] } else { 0.0 });
    let mut unit = vec![0.0; n];
    for j in 0..n {
        unit[j] = 1.0;
        add_coupled(
            couplings,
            &dr.weights,
            factors,
            &unit,
            a.col_as_slice_mut(j),
            1.0,
        );
        unit[j] = 0.0;
    }
    let solution = a
        .partial_piv_lu()
        .solve(MatRef::from_column_major_slice(x, n, 1));
    x.iter_mut()
        .enumerate()
        .for_each(|(i, x)| *x = solution[(i, 0)]);
}

/// out += scale · A x for a dense A (column by column).
pub(super) fn add_product(a: &Mat<f64>, x: &[f64], out: &mut [f64], scale: f64) {
    vectorized(
        #[inline(always)]
        || {
            for (c, &xc) in x.iter().enumerate() {
                if xc != 0.0 {
                    axpy(out, scale * xc, a.col_as_slice(c));
                }
            }
        },
    );
}

/// Which matrix a product uses.
#[derive(Clone, Copy)]
enum Operator {
    Stiffness,
    Damping,
    Mass,
}

/// Why an evaluation of the model failed.
enum Refused {
    Prom(String),
    NotDefinite(&'static str),
}

impl Model {
    /// Evaluate at `params` and factor S and M (`first`: M was never factored).
    fn evaluate(
        &mut self,
        prom: &Prom,
        params: &[f64],
        unknown: &[usize],
        dt: f64,
        first: bool,
        mem: &mut MemBuffer,
    ) -> Result<(), Refused> {
        match self {
            Model::Physical(ph) => {
                prom.evaluate(params, &mut ph.at)
                    .map_err(|e| Refused::Prom(e.to_string()))?;
                let at = &ph.at;
                for c in 0..at.mass().ncols() {
                    let (m, cd, k) = (
                        column(at.mass(), c),
                        column(at.damping(), c),
                        column(at.stiffness(), c),
                    );
                    let s = ph.s_factor.col_as_slice_mut(c);
                    s.iter_mut()
                        .zip(m.iter().zip(cd.iter().zip(k)))
                        .for_each(|(s, (m, (cd, k)))| *s = m + dt * cd + dt * dt * k);
                }
                if !factor_in_place(ph.s_factor.as_mut(), MemStack::new(mem)) {
                    return Err(Refused::NotDefinite("M + Δt C + Δt² K"));
                }
                let m_ok = (!first && ph.factored_mass == at.mass()) || {
                    ph.factored_mass.copy_from(at.mass());
                    ph.m_factor.copy_from(at.mass());
                    factor_in_place(ph.m_factor.as_mut(), MemStack::new(mem))
                };
                if !m_ok {
                    return Err(Refused::NotDefinite("M"));
                }
            }
            Model::Modal(md) => {
                if let Some((q, &value)) = prom
                    .parameters
                    .iter()
                    .zip(params)
                    .find(|(_, v)| !v.is_finite())
                {
                    return Err(Refused::Prom(
                        PromError::NotFinite {
                            name: q.name.clone(),
                            value,
                        }
                        .to_string(),
                    ));
                }
                md.k.fill(0.0);
                md.m.fill(0.0);
                md.dk.fill(0.0);
                md.dm.fill(0.0);
                for (function, kd, mdiag) in &md.form.parts {
                    let f = function.map(|i| &prom.functions[i]);
                    let w = f.map_or(1.0, |f| f.value(params));
                    axpy(&mut md.k, w, kd);
                    axpy(&mut md.m, w, mdiag);
                    for (c, &j) in unknown.iter().enumerate() {
                        let d = f.map_or(0.0, |f| f.derivative(params, j));
                        if d != 0.0 {
                            axpy(md.dk.col_as_slice_mut(c), d, kd);
                            axpy(md.dm.col_as_slice_mut(c), d, mdiag);
                        }
                    }
                }
                let (alpha, beta) = (prom.alpha, prom.beta);
                for i in 0..md.k.len() {
                    md.c[i] = alpha * md.m[i] + beta * md.k[i];
                    md.s[i] = md.m[i] + dt * md.c[i] + dt * dt * md.k[i];
                }
                if let Some(dr) = &mut md.drift {
                    dr.current = 0.0;
                    for (c, coupling) in md.form.couplings.iter().enumerate() {
                        let f = &prom.functions[coupling.function];
                        let w = f.value(params);
                        dr.current = dr.current.max(coupling.drift(w));
                        dr.weights[c] = w - coupling.reference;
                        for (k, &j) in unknown.iter().enumerate() {
                            dr.derivatives[(c, k)] = f.derivative(params, j);
                        }
                    }
                }
                if !md.s.iter().all(|&s| s > 0.0) {
                    return Err(Refused::NotDefinite("M + Δt C + Δt² K"));
                }
                if !md.m.iter().all(|&m| m > 0.0) {
                    return Err(Refused::NotDefinite("M"));
                }
            }
        }
        Ok(())
    }

    /// out += scale · A x (A symmetric: entries as dot products with its columns).
    fn mul(&self, op: Operator, x: &[f64], out: &mut [f64], scale: f64) {
        match self {
            Model::Physical(ph) => {
                let a = match op {
                    Operator::Stiffness => ph.at.stiffness(),
                    Operator::Damping => ph.at.damping(),
                    Operator::Mass => ph.at.mass(),
                };
                out.iter_mut()
                    .enumerate()
                    .for_each(|(c, o)| *o += scale * dot(column(a, c), x));
            }
            Model::Modal(md) => {
                let d = match op {
                    Operator::Stiffness => &md.k,
                    Operator::Damping => &md.c,
                    Operator::Mass => &md.m,
                };
                out.iter_mut()
                    .zip(d.iter().zip(x))
                    .for_each(|(o, (d, x))| *o += scale * d * x);
                if let Some(dr) = &md.drift {
                    add_coupled(
                        &md.form.couplings,
                        &dr.weights,
                        md.off_factors(op),
                        x,
                        out,
                        scale,
                    );
                }
            }
        }
    }

    /// x ← S⁻¹ x (`effective`) or M⁻¹ x.
    fn solve(&mut self, effective: bool, x: &mut [f64]) {
        match self {
            Model::Physical(ph) => {
                let n = x.len();
                solve_seq(
                    if effective {
                        ph.s_factor.as_ref()
                    } else {
                        ph.m_factor.as_ref()
                    },
                    MatMut::from_column_major_slice_mut(x, n, 1),
                );
            }
            Model::Modal(md) => {
                let factors = if effective {
                    md.effective_factors()
                } else {
                    md.off_factors(Operator::Mass)
                };
                solve_modal(
                    if effective { &md.s } else { &md.m },
                    &md.form.couplings,
                    md.drift.as_mut(),
                    factors,
                    x,
                );
            }
        }
    }

    /// D (n × n_p) from w_k = q + β q̇ and w_m = q̈ + α q̇ (see [`parameter_columns`]).
    fn parameter_columns(&self, params: &[usize], w_k: &[f64], w_m: &[f64], d: &mut Mat<f64>) {
        match self {
            Model::Physical(ph) => parameter_columns_into(&ph.at, params, w_k, w_m, d),
            Model::Modal(md) => {
                for c in 0..params.len() {
                    let (dk, dm) = (md.dk.col_as_slice(c), md.dm.col_as_slice(c));
                    let out = d.col_as_slice_mut(c);
                    for i in 0..out.len() {
                        out[i] = dk[i] * w_k[i] + dm[i] * w_m[i];
                    }
                    if let Some(dr) = &md.drift {
                        for (k, coupling) in md.form.couplings.iter().enumerate() {
                            let f = dr.derivatives[(k, c)];
                            for (part, w) in [(&coupling.stiffness, w_k), (&coupling.mass, w_m)] {
                                if let (true, Some(part)) = (f != 0.0, part) {
                                    part.add_product(w, out, f);
                                }
                            }
                        }
                    }
                }
            }
        }
    }

    /// J_v = S⁻¹ [−Δt K, M, Δt S_un, −Δt D] (eq. 8.16–8.20, 8.33).
    fn set_transition(&mut self, dt: f64, s_un: &Mat<f64>, d: &Mat<f64>) {
        match self {
            Model::Physical(ph) => {
                let (n, nu) = (s_un.nrows(), s_un.ncols());
                for j in 0..ph.jv.ncols() {
                    let col = ph.jv.col_as_slice_mut(j);
                    let (src, scale) = match j {
                        j if j < n => (column(ph.at.stiffness(), j), -dt),
                        j if j < 2 * n => (column(ph.at.mass(), j - n), 1.0),
                        j if j < 2 * n + nu => (s_un.col_as_slice(j - 2 * n), dt),
                        j => (d.col_as_slice(j - 2 * n - nu), -dt),
                    };
                    col.iter_mut().zip(src).for_each(|(o, s)| *o = scale * s);
                }
                solve_seq(ph.s_factor.as_ref(), ph.jv.as_mut());
            }
            Model::Modal(md) => {
                let nu = s_un.ncols();
                for i in 0..md.s.len() {
                    md.jk[i] = -dt * md.k[i] / md.s[i];
                    md.jm[i] = md.m[i] / md.s[i];
                }
                for j in 0..md.jw.ncols() {
                    let (src, scale) = if j < nu {
                        (s_un.col_as_slice(j), dt)
                    } else {
                        (d.col_as_slice(j - nu), -dt)
                    };
                    md.jw
                        .col_as_slice_mut(j)
                        .iter_mut()
                        .zip(src.iter().zip(&md.s))
                        .for_each(|(o, (v, s))| *o = scale * v / s);
                }
            }
        }
    }

    /// J_v as a dense n × N matrix.
    fn transition_rows(&self, n: usize, big_n: usize) -> Mat<f64> {
        match self {
            Model::Physical(ph) => ph.jv.clone(),
            Model::Modal(md) => Mat::from_fn(n, big_n, |i, j| match j {
                j if j < n => {
                    if i == j {
                        md.jk[i]
                    } else {
                        0.0
                    }
                }
                j if j < 2 * n => {
                    if i == j - n {
                        md.jm[i]
                    } else {
                        0.0
                    }
                }
                j => md.jw[(i, j - 2 * n)],
            }),
        }
    }
}

impl Physical {
    /// Gᵀ = P J_vᵀ (N × n) and H = J_v P J_vᵀ = J_v Gᵀ (n × n), the two products [`propagate`]
    /// needs: two GEMMs, N² n + N n² multiply-adds.
    #[inline(always)]
    fn transition_products(&self, p: &Mat<f64>, gt: &mut Mat<f64>, h: &mut Mat<f64>) {
        matmul(
            gt.as_mut(),
            Accum::Replace,
            p.as_ref(),
            self.jv.transpose(),
            1.0,
            Par::Seq,
        );
        matmul(
            h.as_mut(),
            Accum::Replace,
            self.jv.as_ref(),
            gt.as_ref(),
            1.0,
            Par::Seq,
        );
    }
}

/// Columns j and n + j of P ← J P Jᵀ (eq. 8.24) from G = J_v P and H = G J_vᵀ: with
/// q' = q + Δt q̇', q̇' = J_v x, (u, p)' = (u, p) and w = (u, p),
///
/// ```text
/// P_q̇'q̇' = H,  P_q'q̇' = G_qᵀ + Δt H,  P_q'q' = P_qq + Δt (G_q + G_qᵀ) + Δt² H,
/// P_wq̇' = G_wᵀ,  P_wq' = P_wq + Δt G_wᵀ,  P_ww unchanged,
/// ```
///
/// so J P Jᵀ costs the two products only. `gt_j` is column j of Gᵀ (N), `g_j` column j of G's
/// q block (n: row j of Gᵀ) and `h_j` column j of H̄ = (H + Hᵀ)/2. Writes the q and q̇ rows of
/// columns j and n + j whole (contiguous) and their w rows; reads only P_qq's column j. Every
/// entry is computed from expressions symmetric in its two indices, so a symmetric P stays
/// exactly symmetric once [`mirror_w_rows`] has copied the w rows to the w columns.
/// `noise` = (column j of Φ⁻¹ Φ⁻ᵀ, q) adds the q and q̇ blocks of Q (modal coordinates) in
/// the same pass.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn propagate_column(
    p: &mut [f64],
    ps: usize,
    (n, j): (usize, usize),
    gt_j: &[f64],
    g_j: &[f64],
    h_j: &[f64],
    noise: Option<(&[f64], f64)>,
    dt: f64,
) {
    let (left, right) = p.split_at_mut((n + j) * ps);
    let (pq, pv) = left[j * ps..j * ps + 2 * n].split_at_mut(n);
    let (pqv, pvv) = right[..2 * n].split_at_mut(n);
    let blocks = pq
        .iter_mut()
        .zip(pv.iter_mut())
        .zip(pqv.iter_mut().zip(pvv.iter_mut()));
    let sources = gt_j[..n].iter().zip(&g_j[..n]).zip(&h_j[..n]);
    match noise {
        Some((gram, q)) => {
            for (((pq, pv), (pqv, pvv)), (((g_ij, g_ji), h_sym), gram)) in
                blocks.zip(sources.zip(gram))
            {
                *pq = (*pq + (dt * (g_ij + g_ji) + dt * dt * h_sym)) + q * gram;
                *pv = g_ji + dt * h_sym;
                *pqv = g_ij + dt * h_sym;
                *pvv = h_sym + q * gram;
            }
        }
        None => {
            for (((pq, pv), (pqv, pvv)), ((g_ij, g_ji), h_sym)) in blocks.zip(sources) {
                *pq += dt * (g_ij + g_ji) + dt * dt * h_sym;
                *pv = g_ji + dt * h_sym;
                *pqv = g_ij + dt * h_sym;
                *pvv = *h_sym;
            }
        }
    }
    for (k, &g_kj) in gt_j.iter().enumerate().skip(2 * n) {
        p[k + j * ps] += dt * g_kj;
        p[k + (n + j) * ps] = g_kj;
    }
}

/// The q and q̇ rows of P's w columns from its w rows (after [`propagate_column`]).
#[inline(always)]
fn mirror_w_rows(p: &mut [f64], ps: usize, n: usize, big_n: usize) {
    for k in 2 * n..big_n {
        for i in 0..2 * n {
            p[i + k * ps] = p[k + i * ps];
        }
    }
}

/// P ← J P Jᵀ (eq. 8.24 without Q; physical coordinates) by [`propagate_column`] from Gᵀ and H
/// ([`Physical::transition_products`]). `mirror` (n × 2n) receives the transposed q block of
/// Gᵀ and H̄ first, so that the main loop reads and writes whole columns only.
#[inline(always)]
fn propagate(p: &mut Mat<f64>, gt: &Mat<f64>, h: &Mat<f64>, mirror: &mut Mat<f64>, dt: f64) {
    let (n, big_n) = (h.nrows(), p.nrows());
    assert!(
        p.ncols() == big_n
            && gt.nrows() == big_n
            && gt.ncols() == n
            && h.ncols() == n
            && mirror.nrows() == n
            && mirror.ncols() == 2 * n,
        "propagate: shapes"
    );
    let ((g, gs), (h, hs)) = (storage(gt), storage(h));
    let (mirror, ms) = storage_mut(mirror);
    for j in 0..n {
        for i in 0..n {
            mirror[i + j * ms] = g[j + i * gs];
            mirror[i + (n + j) * ms] = 0.5 * (h[i + j * hs] + h[j + i * hs]);
        }
    }
    let (p, ps) = storage_mut(p);
    for j in 0..n {
        propagate_column(
            p,
            ps,
            (n, j),
            &g[j * gs..j * gs + big_n],
            &mirror[j * ms..j * ms + n],
            &mirror[(n + j) * ms..(n + j) * ms + n],
            None,
            dt,
        );
    }
    mirror_w_rows(p, ps, n, big_n);
}

/// Buffers of [`Modal::propagate`]: column j of Gᵀ (N), columns j and n + j of G and column j
/// of H and of Hᵀ (n each), and G's w columns (n × (n_un + n_p)).
struct ModalColumns {
    gt: Vec<f64>,
    g_q: Vec<f64>,
    g_v: Vec<f64>,
    h: Vec<f64>,
    h_t: Vec<f64>,
    g_w: Mat<f64>,
}

impl ModalColumns {
    fn new(n: usize, big_n: usize) -> Self {
        ModalColumns {
            gt: vec![0.0; big_n],
            g_q: vec![0.0; n],
            g_v: vec![0.0; n],
            h: vec![0.0; n],
            h_t: vec![0.0; n],
            g_w: Mat::zeros(n, big_n - 2 * n),
        }
    }
}

impl Modal {
    /// P ← J P Jᵀ + the q and q̇ blocks of Q (eq. 8.24) in modal coordinates, one column pair
    /// at a time without forming G or H: J_v = [diag(jk), diag(jm), jw] is diagonal in its q
    /// and q̇ blocks, so column j of Gᵀ = P J_vᵀ combines columns j, n + j and the w columns of
    /// P, and — P being exactly symmetric — column j of G = J_v P (row j of Gᵀ) combines
    /// three rows of P's column j, as does column n + j of G from P's column n + j; column j of
    /// H = J_v Gᵀ and of Hᵀ (row j of H) follow from those. Every sum is the one a transposed
    /// copy of Gᵀ and H would give (bit for bit, P symmetric), with whole-column reads only:
    /// (N + 4 n)(2 + n_un + n_p) multiply-adds per column pair (instead of
    /// (N + n)(2 + n_un + n_p) and two n × n transpositions with strided reads, which cost more
    /// on the blade). P's q and q̇ columns are rewritten in place in order: column j's old values are read before they are written,
    /// and the w columns only change at the end ([`mirror_w_rows`]).
    #[inline(always)]
    fn propagate(&self, p: &mut Mat<f64>, cols: &mut ModalColumns, q_state: f64, dt: f64) {
        let (n, big_n, nw) = (self.jk.len(), p.nrows(), self.jw.ncols());
        let (jk, jm, jw) = (&self.jk[..n], &self.jm[..n], &self.jw);
        for k in 0..nw {
            g_of_column(
                jk,
                jm,
                jw,
                p.col_as_slice(2 * n + k),
                cols.g_w.col_as_slice_mut(k),
            );
        }
        let (p, ps) = storage_mut(p);
        for j in 0..n {
            let (pj, pv) = (
                &p[j * ps..j * ps + big_n],
                &p[(n + j) * ps..(n + j) * ps + big_n],
            );
            let gt = &mut cols.gt[..];
            gt.iter_mut()
                .zip(pj.iter().zip(pv))
                .for_each(|(o, (z, v))| *o = jk[j] * z + jm[j] * v);
            for k in 0..nw {
                let c = jw[(j, k)];
                if c != 0.0 {
                    axpy(gt, c, &p[(2 * n + k) * ps..(2 * n + k) * ps + big_n]);
                }
            }
            g_of_column(jk, jm, jw, pj, &mut cols.g_q);
            g_of_column(jk, jm, jw, pv, &mut cols.g_v);
            let (h, h_t) = (&mut cols.h[..n], &mut cols.h_t[..n]);
            h.iter_mut()
                .zip(jk.iter().zip(jm).zip(gt[..n].iter().zip(&gt[n..2 * n])))
                .for_each(|(o, ((a, b), (z, v)))| *o = a * z + b * v);
            h_t.iter_mut()
                .zip(cols.g_q.iter().zip(&cols.g_v))
                .for_each(|(o, (z, v))| *o = jk[j] * z + jm[j] * v);
            for k in 0..nw {
                let x = gt[2 * n + k];
                if x != 0.0 {
                    axpy(h, x, jw.col_as_slice(k));
                }
                let c = jw[(j, k)];
                h_t.iter_mut()
                    .zip(cols.g_w.col_as_slice(k))
                    .for_each(|(o, g)| *o += g * c);
            }
            h.iter_mut()
                .zip(h_t.iter())
                .for_each(|(h, h_t)| *h = 0.5 * (*h + h_t));
            propagate_column(
                p,
                ps,
                (n, j),
                &cols.gt,
                &cols.g_q,
                &cols.h,
                Some((self.gram.col_as_slice(j), q_state)),
                dt,
            );
        }
        mirror_w_rows(p, ps, n, big_n);
    }
}

/// J_v x (n) for a column x of P (N): jk ∘ x_q + jm ∘ x_q̇ + Σ_k jw_k x_{2n+k}, entry i summed
/// as entry (row of x, i) of Gᵀ = P J_vᵀ ([`Modal::propagate`]).
#[inline(always)]
fn g_of_column(jk: &[f64], jm: &[f64], jw: &Mat<f64>, x: &[f64], out: &mut [f64]) {
    let n = jk.len();
    out.iter_mut()
        .zip(jk.iter().zip(jm).zip(x[..n].iter().zip(&x[n..2 * n])))
        .for_each(|(o, ((a, b), (z, v)))| *o = a * z + b * v);
    for (k, &s) in x[2 * n..].iter().enumerate() {
        out.iter_mut()
            .zip(jw.col_as_slice(k))
            .for_each(|(o, c)| *o += c * s);
    }
}

/// K of the pROM at the initial parameters `params` is positive semi-definite
/// ([`stiffness_semidefinite`]: S = M + Δt C + Δt² K and M, checked at every step, stay
/// definite for an indefinite K at small Δt, so a negative modulus would otherwise run). Called
/// by [`Filter::new`] and, before its observability check, by SOL ESTIMATE.
pub fn check_initial_stiffness(k: MatRef<'_, f64>, params: &[f64]) -> Result<(), FilterError> {
    stiffness_semidefinite(k).map_err(|cause| FilterError::IndefiniteStart {
        params: params.to_vec(),
        cause,
    })
}

/// The entries of a column-major matrix as one slice, (i, j) at i + j · stride, and the stride.
fn storage(m: &Mat<f64>) -> (&[f64], usize) {
    let stride = m.col_stride().unsigned_abs();
    let len = if m.ncols() == 0 {
        0
    } else {
        stride * (m.ncols() - 1) + m.nrows()
    };
    // SAFETY: a `Mat` owns one column-major allocation with columns `stride` ≥ nrows apart, so
    // the first `len` entries from its pointer are initialized, and they are borrowed with `m`.
    (
        unsafe { std::slice::from_raw_parts(m.as_ptr(), len) },
        stride,
    )
}

/// [`storage`], mutable.
fn storage_mut(m: &mut Mat<f64>) -> (&mut [f64], usize) {
    let stride = m.col_stride().unsigned_abs();
    let len = if m.ncols() == 0 {
        0
    } else {
        stride * (m.ncols() - 1) + m.nrows()
    };
    // SAFETY: as in `storage`, borrowed mutably with `m`.
    (
        unsafe { std::slice::from_raw_parts_mut(m.as_ptr_mut(), len) },
        stride,
    )
}

impl Filter {
    /// Check the setup and prepare step 0.
    pub fn new(mut setup: FilterSetup) -> Result<Self, FilterError> {
        let n = setup.prom.size();
        let (nu, np, m) = (
            setup.s_un.ncols(),
            setup.unknown_params.len(),
            setup.measured.len(),
        );
        for (what, expected, got) in [
            ("S_un rows", n, setup.s_un.nrows()),
            (
                "parameter values",
                setup.prom.parameters.len(),
                setup.p.len(),
            ),
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
                return Err(FilterError::Shape {
                    what,
                    expected,
                    got,
                });
            }
        }
        let mut at = setup.prom.workspace();
        setup
            .prom
            .evaluate(&setup.p, &mut at)
            .map_err(|e| FilterError::Prom(e.to_string()))?;
        check_initial_stiffness(at.stiffness(), &setup.p)?;
        let big_n = 2 * n + nu + np;
        let mut x = vec![0.0; big_n];
        x[..n].copy_from_slice(&setup.q0);
        x[n..2 * n].copy_from_slice(&setup.v0);
        x[2 * n..2 * n + nu].copy_from_slice(&setup.u0);
        for (k, &j) in setup.unknown_params.iter().enumerate() {
            x[2 * n + nu + k] = setup.p[j];
        }
        let diag: Vec<f64> = std::iter::repeat_n(setup.p0_state, 2 * n)
            .chain(setup.p0_inputs.iter().copied())
            .chain(setup.p0_params.iter().copied())
            .collect();
        let mut p = Mat::from_fn(big_n, big_n, |i, j| if i == j { diag[i] } else { 0.0 });
        let form = match setup.coordinates {
            Coordinates::Auto => modal_form(&setup.prom, &setup.p, &setup.unknown_params, false),
            Coordinates::Rediagonalized(tolerance)
                if !valid_rediagonalization_tolerance(tolerance) =>
            {
                return Err(FilterError::Tolerance(tolerance));
            }
            Coordinates::Rediagonalized(_) => {
                modal_form(&setup.prom, &setup.p, &setup.unknown_params, true)
            }
            Coordinates::Physical => None,
        };
        let model = match form {
            None => Model::Physical(Physical {
                at: setup.prom.workspace(),
                s_factor: Mat::zeros(n, n),
                m_factor: Mat::zeros(n, n),
                factored_mass: Mat::zeros(n, n),
                jv: Mat::zeros(n, big_n),
            }),
            Some(form) => {
                let drift = match setup.coordinates {
                    Coordinates::Rediagonalized(tolerance) if !form.couplings.is_empty() => Some(
                        Drift::new(&form, tolerance, np, &setup.s_un, &setup.measured.h),
                    ),
                    _ => None,
                };
                // z₀ = Φ⁻¹ q₀, P₀ and (per step) Q: the q and q̇ blocks times Φ⁻¹ Φ⁻ᵀ
                setup.s_un = form.basis.transpose() * &setup.s_un;
                setup.measured.h = &setup.measured.h * &form.basis;
                for block in [0..n, n..2 * n] {
                    let z =
                        &form.inverse * MatRef::from_column_major_slice(&x[block.clone()], n, 1);
                    x[block]
                        .iter_mut()
                        .enumerate()
                        .for_each(|(i, x)| *x = z[(i, 0)]);
                }
                let gram = gram(&form.inverse);
                for b in [0, n] {
                    p.as_mut()
                        .submatrix_mut(b, b, n, n)
                        .copy_from(&gram * faer::Scale(setup.p0_state));
                }
                Model::Modal(Box::new(Modal {
                    form,
                    gram,
                    k: vec![0.0; n],
                    m: vec![0.0; n],
                    c: vec![0.0; n],
                    s: vec![0.0; n],
                    dk: Mat::zeros(n, np),
                    dm: Mat::zeros(n, np),
                    jk: vec![0.0; n],
                    jm: vec![0.0; n],
                    jw: Mat::zeros(n, nu + np),
                    physical: OnceCell::new(),
                    dt: setup.dt,
                    alpha: setup.prom.alpha,
                    beta: setup.prom.beta,
                    drift,
                }))
            }
        };
        let params = setup.p.clone();
        let scratch = Scratch {
            load: vec![0.0; n],
            load_of: (0, vec![f64::NAN; n]),
            force: vec![0.0; n],
            v_old: vec![0.0; n],
            w_k: vec![0.0; n],
            w_m: vec![0.0; n],
            rhs: vec![0.0; n],
            g: vec![0.0; n],
            t: vec![0.0; n],
            d: Mat::zeros(n, np),
            predicted: vec![0.0; m],
            pht: Mat::zeros(big_n, m),
            gain: Mat::zeros(big_n, m),
            w: Mat::zeros(big_n, m),
            sy: Mat::zeros(m, m),
            sy_factor: Mat::zeros(m, m),
            mirror: Mat::zeros(n, 2 * n),
            columns: ModalColumns::new(n, big_n),
            mem: MemBuffer::new(cholesky_in_place_scratch::<f64>(
                n.max(m),
                Par::Seq,
                Default::default(),
            )),
        };
        let mut filter = Filter {
            n,
            nu,
            np,
            x,
            a: vec![0.0; n],
            p,
            params,
            model,
            jv_valid: false,
            jm: Mat::zeros(m, big_n),
            gt: Mat::zeros(big_n, n),
            h: Mat::zeros(n, n),
            innovation: vec![0.0; m],
            step: 0,
            scratch,
            setup,
        };
        filter.refresh()?;
        filter.set_acceleration();
        Ok(filter)
    }

    /// Augmented state size N = 2 n_r + n_un + n_p.
    pub fn size(&self) -> usize {
        self.x.len()
    }

    /// Whether the filter runs in modal coordinates (see the module documentation).
    pub fn modal(&self) -> bool {
        matches!(self.model, Model::Modal(_))
    }

    /// How many times re-diagonalized coordinates recomputed their modes (None: the
    /// coordinates are not re-diagonalized ones, or the modes diagonalize the pROM exactly).
    pub fn rediagonalizations(&self) -> Option<usize> {
        match &self.model {
            Model::Modal(md) => md.drift.as_ref().map(|dr| dr.count),
            Model::Physical(_) => None,
        }
    }

    /// x* = [q, q̇, u_un, p] (physical q; modal coordinates: Φ z mapped on the first request
    /// after a step, 2 n² multiply-adds).
    pub fn state(&self) -> &[f64] {
        match &self.model {
            Model::Physical(_) => &self.x,
            Model::Modal(md) => &md.physical.get_or_init(|| self.physical(md)).0,
        }
    }

    /// q̈ at the current estimate (physical; as [`Filter::state`]).
    pub fn acceleration(&self) -> &[f64] {
        match &self.model {
            Model::Physical(_) => &self.a,
            Model::Modal(md) => &md.physical.get_or_init(|| self.physical(md)).1,
        }
    }

    /// x* and q̈ in the filter's coordinates (modal z where the filter runs on modes; u and p
    /// are the same in every coordinates): with [`Filter::sensor_rows`], virtual sensors without
    /// mapping the state back to q.
    pub fn filter_state(&self) -> (&[f64], &[f64]) {
        (&self.x, &self.a)
    }

    /// Sensor rows in the filter's coordinates (H Φ on modes; n² per row), for
    /// [`Filter::filter_state`]. They change when the filter re-diagonalizes
    /// ([`Filter::rediagonalizations`]).
    pub fn sensor_rows(&self, rows: &SensorRows) -> SensorRows {
        match &self.model {
            Model::Physical(_) => rows.clone(),
            Model::Modal(md) => SensorRows {
                h: product(rows.h.as_ref(), md.form.basis.as_ref()),
                ..rows.clone()
            },
        }
    }

    /// The covariance of x* (physical q: T P Tᵀ in modal coordinates; N³, for checks).
    pub fn covariance(&self) -> Mat<f64> {
        match &self.model {
            Model::Physical(_) => self.p.clone(),
            Model::Modal(md) => {
                let (n, big_n) = (self.n, self.size());
                let phi = md.form.basis.as_ref();
                let t = Mat::from_fn(big_n, big_n, |i, j| match (i, j) {
                    (i, j) if i < n && j < n => phi[(i, j)],
                    (i, j) if (n..2 * n).contains(&i) && (n..2 * n).contains(&j) => {
                        phi[(i - n, j - n)]
                    }
                    (i, j) if i >= 2 * n && i == j => 1.0,
                    _ => 0.0,
                });
                &t * &self.p * t.transpose()
            }
        }
    }

    /// The variance of x*_i (physical q), without forming the covariance.
    pub fn variance(&self, i: usize) -> f64 {
        match &self.model {
            Model::Modal(md) if i < 2 * self.n => {
                let (n, b) = (self.n, if i < self.n { 0 } else { self.n });
                let row = |c: usize| md.form.basis[(i - b, c)];
                (0..n)
                    .map(|c| row(c) * (0..n).map(|r| self.p[(b + r, b + c)] * row(r)).sum::<f64>())
                    .sum()
            }
            _ => self.p[(i, i)],
        }
    }

    /// Values of every pROM parameter at the current estimate.
    pub fn parameters(&self) -> &[f64] {
        &self.params
    }

    /// y − h(x⁻) of the last step.
    pub fn innovation(&self) -> &[f64] {
        &self.innovation
    }

    /// J_m of the last step (rows of the measured sensors), in the filter's coordinates.
    pub fn measurement_jacobian(&self) -> &Mat<f64> {
        &self.jm
    }

    /// The transition Jacobian J of the last step (dense N × N, for checks and tools), in the
    /// filter's coordinates.
    pub fn transition(&self) -> Mat<f64> {
        let (n, big_n) = (self.n, self.size());
        let jv = self.model.transition_rows(n, big_n);
        Mat::from_fn(big_n, big_n, |i, j| {
            let e = if i == j { 1.0 } else { 0.0 };
            if i < n {
                e + self.setup.dt * jv[(i, j)]
            } else if i < 2 * n {
                jv[(i - n, j)]
            } else {
                e
            }
        })
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
        self.evaluate()?;
        let drifted = match &self.model {
            Model::Modal(md) => md
                .drift
                .as_ref()
                .is_some_and(|dr| dr.stalled || dr.current > dr.tolerance),
            Model::Physical(_) => false,
        };
        if drifted {
            self.rediagonalize()?;
            self.evaluate()?;
        }
        Ok(())
    }

    /// [`Model::evaluate`] at the current parameters.
    fn evaluate(&mut self) -> Result<(), FilterError> {
        let s = &self.setup;
        match self.model.evaluate(
            &s.prom,
            &self.params,
            &s.unknown_params,
            s.dt,
            self.step == 0,
            &mut self.scratch.mem,
        ) {
            Ok(()) => {
                self.jv_valid = false;
                Ok(())
            }
            Err(Refused::Prom(e)) => Err(FilterError::Prom(e)),
            Err(Refused::NotDefinite(what)) => Err(FilterError::NotDefinite {
                step: self.step,
                what,
                params: self.params.clone(),
            }),
        }
    }

    /// Move re-diagonalized coordinates to the modes Φ₂ at the current parameters: z₂ = R z₁
    /// with R = Φ₂⁻¹ Φ₁ on the q and q̇ blocks of x* and P (P ↦ T P Tᵀ, T = diag(R, R, I, I)),
    /// S_un, the sensor rows and Q's blocks transformed from the physical ones. N³, rare: only
    /// when the estimate has drifted by the tolerance (module documentation).
    fn rediagonalize(&mut self) -> Result<(), FilterError> {
        let (n, big_n) = (self.n, self.size());
        let Model::Modal(md) = &mut self.model else {
            return Ok(());
        };
        let Some(dr) = md.drift.as_mut() else {
            return Ok(());
        };
        let s = &mut self.setup;
        let form = modal_form_after(&s.prom, &self.params, &s.unknown_params, &md.form)
            .ok_or_else(|| {
                FilterError::Prom(format!(
                    "at step {}: no modes of the pROM at parameters {:?} (re-diagonalization)",
                    self.step, self.params
                ))
            })?;
        let r = product(form.inverse.as_ref(), md.form.basis.as_ref());
        for start in [0, n] {
            let z = product(
                r.as_ref(),
                MatRef::from_column_major_slice(&self.x[start..start + n], n, 1),
            );
            self.x[start..start + n].copy_from_slice(z.col_as_slice(0));
        }
        // T P Tᵀ by blocks: the q and q̇ rows of P times R, then those columns times Rᵀ
        let mut rows = self.p.clone();
        for start in [0, n] {
            matmul(
                rows.as_mut().subrows_mut(start, n),
                Accum::Replace,
                r.as_ref(),
                self.p.as_ref().subrows(start, n),
                1.0,
                Par::Seq,
            );
        }
        self.p.copy_from(&rows);
        for start in [0, n] {
            matmul(
                self.p.as_mut().subcols_mut(start, n),
                Accum::Replace,
                rows.as_ref().subcols(start, n),
                r.transpose(),
                1.0,
                Par::Seq,
            );
        }
        for j in 0..big_n {
            for i in 0..j {
                let mean = 0.5 * (self.p[(i, j)] + self.p[(j, i)]);
                (self.p[(i, j)], self.p[(j, i)]) = (mean, mean);
            }
        }
        s.s_un = product(form.basis.transpose(), dr.s_un.as_ref());
        s.measured.h = product(dr.h.as_ref(), form.basis.as_ref());
        md.gram = gram(&form.inverse);
        *dr = Drift {
            count: dr.count + 1,
            ..Drift::new(&form, dr.tolerance, self.np, &dr.s_un, &dr.h)
        };
        md.form = form;
        Ok(())
    }

    /// The known load in the filter's coordinates (Φᵀ f in modal ones) into `scratch.load`.
    fn set_load(&mut self, f_kn: &[f64]) {
        let (load, load_of) = (&mut self.scratch.load, &mut self.scratch.load_of);
        match &self.model {
            Model::Physical(_) => load.copy_from_slice(f_kn),
            Model::Modal(md) => {
                let modes = md.drift.as_ref().map_or(0, |dr| dr.count);
                if load_of.0 == modes && load_of.1 == f_kn {
                    return;
                }
                load.iter_mut()
                    .enumerate()
                    .for_each(|(c, l)| *l = dot(column(md.form.basis.as_ref(), c), f_kn));
                load_of.0 = modes;
                load_of.1.copy_from_slice(f_kn);
            }
        }
    }

    /// Reduced force S_un u + f_kn at the current estimate, into `scratch.force`.
    fn set_force(&mut self) {
        let (n, nu) = (self.n, self.nu);
        let f = &mut self.scratch.force;
        f.copy_from_slice(&self.scratch.load);
        for j in 0..nu {
            axpy(f, self.x[2 * n + j], self.setup.s_un.col_as_slice(j));
        }
    }

    /// q̈ = M⁻¹(f − K q − C q̇) at the current x with the load of `scratch.load`, into `a`.
    fn set_acceleration(&mut self) {
        let n = self.n;
        self.set_force();
        let rhs = &mut self.scratch.rhs;
        rhs.copy_from_slice(&self.scratch.force);
        self.model.mul(Operator::Stiffness, &self.x[..n], rhs, -1.0);
        self.model
            .mul(Operator::Damping, &self.x[n..2 * n], rhs, -1.0);
        self.model.solve(false, rhs);
        self.a.copy_from_slice(rhs);
    }

    /// The physical x* and q̈ of the modal path: q = Φ z, q̇ = Φ ż, q̈ = Φ z̈.
    fn physical(&self, md: &Modal) -> (Vec<f64>, Vec<f64>) {
        let n = self.n;
        let phi = md.form.basis.as_ref();
        let map = |z: &[f64], out: &mut [f64]| (0..n).for_each(|c| axpy(out, z[c], column(phi, c)));
        let (mut x, mut a) = (vec![0.0; self.x.len()], vec![0.0; n]);
        x[2 * n..].copy_from_slice(&self.x[2 * n..]);
        map(&self.x[..n], &mut x[..n]);
        map(&self.x[n..2 * n], &mut x[n..2 * n]);
        map(&self.a, &mut a);
        (x, a)
    }

    /// Forget the physical x* and q̈ of the previous step (modal coordinates).
    fn unpublish(&mut self) {
        if let Model::Modal(md) = &mut self.model {
            md.physical.take();
        }
    }

    /// One filter step: predict to t_k with the known reduced load `f_kn` = S_kn u_kn(t_k), then
    /// correct with the measurements `y` (one per measured row).
    pub fn step(&mut self, f_kn: &[f64], y: &[f64]) -> Result<(), FilterError> {
        self.predict(f_kn)?;
        self.correct(f_kn, y)
    }

    /// The prediction half of a step (eq. 8.22–8.24): x⁻, q̈⁻, J and P⁻.
    pub fn predict(&mut self, f_kn: &[f64]) -> Result<(), FilterError> {
        let n = self.n;
        if f_kn.len() != n {
            return Err(FilterError::Shape {
                what: "known load",
                expected: n,
                got: f_kn.len(),
            });
        }
        self.unpublish();
        self.step += 1;
        let dt = self.setup.dt;
        // prediction (eq. 8.22)
        self.set_load(f_kn);
        self.set_force();
        self.scratch.v_old.copy_from_slice(&self.x[n..2 * n]);
        let rhs = &mut self.scratch.rhs;
        rhs.iter_mut()
            .zip(&self.scratch.force)
            .for_each(|(r, f)| *r = dt * f);
        self.model
            .mul(Operator::Mass, &self.scratch.v_old, rhs, 1.0);
        self.model.mul(Operator::Stiffness, &self.x[..n], rhs, -dt);
        self.model.solve(true, rhs);
        let (q, v) = self.x.split_at_mut(n);
        for (i, &vn) in rhs.iter().enumerate() {
            v[i] = vn;
            q[i] += dt * vn;
            self.a[i] = (vn - self.scratch.v_old[i]) / dt;
        }
        // Jacobian block row J_v (eq. 8.16–8.20, 8.33) at the predicted x_k, q̈_k (D of g_d's q_k terms)
        if !self.jv_valid || self.np > 0 {
            self.parameter_columns();
            self.model
                .set_transition(dt, &self.setup.s_un, &self.scratch.d);
            self.jv_valid = true;
        }
        // P⁻ = J P Jᵀ + Q (eq. 8.24)
        let (p, sc) = (&mut self.p, &mut self.scratch);
        match &self.model {
            Model::Physical(ph) => vectorized(
                #[inline(always)]
                || {
                    ph.transition_products(p, &mut self.gt, &mut self.h);
                    propagate(p, &self.gt, &self.h, &mut sc.mirror, dt);
                },
            ),
            Model::Modal(md) => vectorized(
                #[inline(always)]
                || md.propagate(p, &mut sc.columns, self.setup.q_state, dt),
            ),
        }
        self.add_noise();
        Ok(())
    }

    /// P += Q (eq. 8.29) but for the modal q and q̇ blocks of T⁻¹ Q T⁻ᵀ, which [`Modal::propagate`]
    /// adds.
    fn add_noise(&mut self) {
        let n = self.n;
        let s = &self.setup;
        if let Model::Physical(_) = &self.model {
            (0..2 * n).for_each(|i| self.p[(i, i)] += s.q_state);
        }
        for (i, q) in s.q_inputs.iter().chain(&s.q_params).enumerate() {
            self.p[(2 * n + i, 2 * n + i)] += q;
        }
    }

    /// The correction half of a step (eq. 8.25–8.28) with the same known load as the prediction,
    /// then the refresh at p⁺.
    pub fn correct(&mut self, f_kn: &[f64], y: &[f64]) -> Result<(), FilterError> {
        let (n, m) = (self.n, self.setup.measured.len());
        if y.len() != m {
            return Err(FilterError::Shape {
                what: "measurements",
                expected: m,
                got: y.len(),
            });
        }
        if f_kn.len() != n {
            return Err(FilterError::Shape {
                what: "known load",
                expected: n,
                got: f_kn.len(),
            });
        }
        self.unpublish();
        self.measurement_rows();
        let sc = &mut self.scratch;
        self.setup
            .measured
            .evaluate(&self.x[..n], &self.x[n..2 * n], &self.a, &mut sc.predicted);
        self.innovation
            .iter_mut()
            .zip(y.iter().zip(&sc.predicted))
            .for_each(|(e, (y, h))| *e = y - h);
        // U = P J_mᵀ: columns of P combined by the nonzero entries of J_m's rows
        let ((p, ps), (jm, js)) = (storage(&self.p), storage(&self.jm));
        let big_n = self.p.nrows();
        vectorized(
            #[inline(always)]
            || {
                let (u, us) = storage_mut(&mut sc.pht);
                u.fill(0.0);
                for c in 0..big_n {
                    let column = &p[c * ps..c * ps + big_n];
                    for k in 0..m {
                        let a = jm[k + c * js];
                        if a != 0.0 {
                            axpy(&mut u[k * us..k * us + big_n], a, column);
                        }
                    }
                }
            },
        );
        matmul(
            sc.sy.as_mut(),
            Accum::Replace,
            self.jm.as_ref(),
            sc.pht.as_ref(),
            1.0,
            Par::Seq,
        );
        for (i, r) in self.setup.r.iter().enumerate() {
            sc.sy[(i, i)] += r;
        }
        sc.sy_factor.copy_from(&sc.sy);
        if !factor_in_place(sc.sy_factor.as_mut(), MemStack::new(&mut sc.mem)) {
            return Err(FilterError::Innovation { step: self.step });
        }
        // 𝒦ᵀ = S_y⁻¹ Uᵀ, solved on the transposed view of 𝒦 (N × m)
        sc.gain.copy_from(&sc.pht);
        solve_seq(sc.sy_factor.as_ref(), sc.gain.as_mut().transpose_mut());
        for (j, e) in self.innovation.iter().enumerate() {
            axpy(&mut self.x, *e, sc.gain.col_as_slice(j));
        }
        // Joseph form (eq. 8.28) L P Lᵀ + 𝒦 R 𝒦ᵀ = P − 𝒦 Uᵀ − U 𝒦ᵀ + 𝒦 S_y 𝒦ᵀ = P + 𝒦 Wᵀ + W 𝒦ᵀ
        // with W = 𝒦 S_y / 2 − U, column by column; entry (i, j) adds 𝒦_ik W_jk + W_ik 𝒦_jk per k,
        // the same two products as entry (j, i): P stays exactly symmetric.
        matmul(
            sc.w.as_mut(),
            Accum::Replace,
            sc.gain.as_ref(),
            sc.sy.as_ref(),
            0.5,
            Par::Seq,
        );
        sc.w -= &sc.pht;
        let big_n = self.p.nrows();
        let ((gain, gs), (w, ws)) = (storage(&sc.gain), storage(&sc.w));
        let (p, ps) = storage_mut(&mut self.p);
        vectorized(
            #[inline(always)]
            || {
                // up to three sensors per pass over the column (one load and store of P per group):
                // the same sums in the same order as one pass per sensor
                let (gain_of, w_of) = (
                    |k: usize| &gain[k * gs..k * gs + big_n],
                    |k: usize| &w[k * ws..k * ws + big_n],
                );
                for j in 0..big_n {
                    let col = &mut p[j * ps..j * ps + big_n];
                    let mut k = 0;
                    while m - k >= 3 {
                        joseph_pass(
                            col,
                            j,
                            [0, 1, 2].map(|s| gain_of(k + s)),
                            [0, 1, 2].map(|s| w_of(k + s)),
                        );
                        k += 3;
                    }
                    match m - k {
                        2 => joseph_pass(
                            col,
                            j,
                            [gain_of(k), gain_of(k + 1)],
                            [w_of(k), w_of(k + 1)],
                        ),
                        1 => joseph_pass(col, j, [gain_of(k)], [w_of(k)]),
                        _ => {}
                    }
                }
            },
        );
        if !self.x.iter().all(|v| v.is_finite()) {
            return Err(FilterError::NonFinite { step: self.step });
        }
        self.refresh()?;
        self.set_load(f_kn);
        self.set_acceleration();
        Ok(())
    }

    /// Diagonal of Q at augmented index i (eq. 8.29), in physical coordinates.
    #[cfg(test)]
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
        let (alpha, beta) = (self.setup.prom.alpha, self.setup.prom.beta);
        let sc = &mut self.scratch;
        let (q, v) = (&self.x[..n], &self.x[n..2 * n]);
        for c in 0..n {
            sc.w_k[c] = q[c] + beta * v[c];
            sc.w_m[c] = self.a[c] + alpha * v[c];
        }
        self.model
            .parameter_columns(&self.setup.unknown_params, &sc.w_k, &sc.w_m, &mut sc.d);
    }

    /// Rows of J_m (eq. 8.38 for DISP/STRAIN, q̇ rows for VEL, eq. 8.39 for ACCEL with
    /// g = M⁻¹ hᵀ: [−gᵀ K, −gᵀ C, gᵀ S_un, −gᵀ D]).
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
                    let (g, t) = (&mut self.scratch.g, &mut self.scratch.t);
                    (0..n).for_each(|i| g[i] = rows.h[(r, i)]);
                    self.model.solve(false, g);
                    for (op, offset) in [(Operator::Stiffness, 0), (Operator::Damping, n)] {
                        t.fill(0.0);
                        self.model.mul(op, g, t, -1.0);
                        (0..n).for_each(|c| self.jm[(r, offset + c)] = t[c]);
                    }
                    for c in 0..nu {
                        self.jm[(r, 2 * n + c)] = dot(g, self.setup.s_un.col_as_slice(c));
                    }
                    for c in 0..self.np {
                        self.jm[(r, 2 * n + nu + c)] = -dot(g, self.scratch.d.col_as_slice(c));
                    }
                }
            }
        }
    }
}

impl Drift {
    /// Empty buffers for the couplings of `form`; `s_un` and `h` in physical coordinates.
    fn new(form: &ModalForm, tolerance: f64, np: usize, s_un: &Mat<f64>, h: &Mat<f64>) -> Self {
        let n = form.basis.nrows();
        Drift {
            tolerance,
            weights: vec![0.0; form.couplings.len()],
            derivatives: Mat::zeros(form.couplings.len(), np),
            current: 0.0,
            s_un: s_un.clone(),
            h: h.clone(),
            iterate: vec![0.0; n],
            product: vec![0.0; n],
            stalled: false,
            count: 0,
        }
    }
}

/// Φ⁻¹ Φ⁻ᵀ, made exactly symmetric so that P stays so (GEMM need not sum (i, j) and (j, i)
/// alike): the q and q̇ blocks of Q and P₀ in modal coordinates for a unit physical diagonal.
fn gram(inverse: &Mat<f64>) -> Mat<f64> {
    let g = product(inverse.as_ref(), inverse.transpose());
    Mat::from_fn(g.nrows(), g.ncols(), |i, j| 0.5 * (g[(i, j)] + g[(j, i)]))
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

/// Runs `f` compiled for the widest SIMD instruction set the CPU has (pulp's runtime dispatch,
/// AVX2 on current x86-64; the crate itself is built for baseline x86-64, whose SSE2 vectors are
/// half as wide): the filter's strided loops run 4 doubles per instruction. The same operations
/// in the same order (no fused multiply-adds, no reassociation), so the results do not depend on
/// the CPU.
#[inline(always)]
fn vectorized<R>(f: impl FnOnce() -> R) -> R {
    pulp::Arch::new().dispatch(f)
}

/// Column j of the Joseph update (eq. 8.28) for K sensors: col += Σ_s 𝒦_s W_s[j] + W_s 𝒦_s[j],
/// added sensor by sensor (`gain` = 𝒦 and `w` = W columns, each as long as `col`).
#[inline(always)]
fn joseph_pass<const K: usize>(col: &mut [f64], j: usize, gain: [&[f64]; K], w: [&[f64]; K]) {
    let len = col.len();
    let (gain, w) = (gain.map(|g| &g[..len]), w.map(|w| &w[..len]));
    let (a, b): ([f64; K], [f64; K]) = (w.map(|w| w[j]), gain.map(|g| g[j]));
    for i in 0..len {
        let mut v = col[i];
        for s in 0..K {
            v += gain[s][i] * a[s] + w[s][i] * b[s];
        }
        col[i] = v;
    }
}

/// y += a x.
#[inline(always)]
pub(super) fn axpy(y: &mut [f64], a: f64, x: &[f64]) {
    y.iter_mut().zip(x).for_each(|(y, x)| *y += a * x);
}

/// a · b with four interleaved partial sums (a strict left-to-right sum is one dependent
/// chain of additions and cannot use vector lanes).
#[inline(always)]
pub(super) fn dot(a: &[f64], b: &[f64]) -> f64 {
    let len = a.len().min(b.len());
    let (a, b) = (&a[..len], &b[..len]);
    let mut partial = [0.0; 4];
    let (chunks_a, chunks_b) = (a.chunks_exact(4), b.chunks_exact(4));
    let tail: f64 = chunks_a
        .remainder()
        .iter()
        .zip(chunks_b.remainder())
        .map(|(a, b)| a * b)
        .sum();
    for (x, y) in chunks_a.zip(chunks_b) {
        for l in 0..4 {
            partial[l] += x[l] * y[l];
        }
    }
    (partial[0] + partial[1]) + (partial[2] + partial[3]) + tail
}

/// D (n × n_p): D_j = ∂K/∂p_j (q + β q̇) + ∂M/∂p_j (q̈ + α q̇) = ∂K/∂p_j q + ∂C/∂p_j q̇ +
/// ∂M/∂p_j q̈ for the parameters `params`, so that ∂q̈/∂p_j = −M⁻¹ D_j (eq. 8.33–8.35 with
/// Rayleigh damping, derivatives of the affine pROM, eq. 8.19–8.20).
pub fn parameter_columns(
    at: &PromEvaluation,
    (alpha, beta): (f64, f64),
    params: &[usize],
    q: &[f64],
    v: &[f64],
    a: &[f64],
) -> Mat<f64> {
    let w_k: Vec<f64> = q.iter().zip(v).map(|(q, v)| q + beta * v).collect();
    let w_m: Vec<f64> = a.iter().zip(v).map(|(a, v)| a + alpha * v).collect();
    let mut d = Mat::zeros(q.len(), params.len());
    parameter_columns_into(at, params, &w_k, &w_m, &mut d);
    d
}

/// [`parameter_columns`] into `d` (n × n_p) from w_k = q + β q̇ and w_m = q̈ + α q̇.
fn parameter_columns_into(
    at: &PromEvaluation,
    params: &[usize],
    w_k: &[f64],
    w_m: &[f64],
    d: &mut Mat<f64>,
) {
    for (k, &j) in params.iter().enumerate() {
        let (dk, dm) = (at.d_stiffness(j), at.d_mass(j));
        let out = d.col_as_slice_mut(k);
        out.fill(0.0);
        for c in 0..w_k.len() {
            let (sk, sm) = (w_k[c], w_m[c]);
            out.iter_mut()
                .zip(column(dk, c).iter().zip(column(dm, c)))
                .for_each(|(o, (k, m))| *o += k * sk + m * sm);
        }
    }
}

/// Column `c` of a column-major matrix view as a slice ([`crate::rom::prom::PromEvaluation`]'s
/// views are column-major over one contiguous buffer, so every column is contiguous).
fn column(m: MatRef<'_, f64>, c: usize) -> &[f64] {
    m.col(c)
        .try_as_col_major()
        .expect("column-major matrix view")
        .as_slice()
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
        let fixed = CoefficientValues {
            e: 1.0,
            rho: 1.0,
            ..Default::default()
        };
        let k1 = Mat::from_fn(2, 2, |i, j| [[2.0, -1.0], [-1.0, 1.0]][i][j] * 1e4);
        let k0 = Mat::from_fn(2, 2, |i, j| if i == j && i == 0 { 5e3 } else { 0.0 });
        let m1 = Mat::from_fn(2, 2, |i, j| [[2.0, 0.1], [0.1, 1.0]][i][j]);
        Prom {
            parameters: vec![
                PromParameter {
                    name: "E".into(),
                    low: 0.5,
                    high: 2.0,
                    nominal: 1.0,
                },
                PromParameter {
                    name: "RHO".into(),
                    low: 0.5,
                    high: 2.0,
                    nominal: 1.0,
                },
            ],
            functions: vec![
                AffineFunction::constant(),
                AffineFunction {
                    coefficient: Coefficient::E,
                    fixed,
                    driven_by: vec![(CoefficientInput::E, 0)],
                },
                AffineFunction {
                    coefficient: Coefficient::Rho,
                    fixed,
                    driven_by: vec![(CoefficientInput::Rho, 1)],
                },
            ],
            stiffness: vec![k0, k1, Mat::zeros(2, 2)],
            mass: vec![Mat::zeros(2, 2), Mat::zeros(2, 2), m1],
            alpha: 0.8,
            beta: 2e-4,
        }
    }

    /// Steps `filter` through the measurements `data` (from step 1) with the known load
    /// `known(t)`: after each step, x* and the standard deviation of every entry.
    pub(crate) fn history(
        filter: &mut Filter,
        data: &[[f64; 2]],
        known: impl Fn(f64, &mut [f64]),
        dt: f64,
    ) -> Vec<Vec<f64>> {
        let mut history = Vec::new();
        for (k, y) in data.iter().enumerate().skip(1) {
            let mut f = [0.0; 2];
            known(k as f64 * dt, &mut f);
            filter.step(&f, y).unwrap();
            let sigma = (0..filter.size()).map(|i| filter.variance(i).sqrt());
            history.push(filter.state().iter().copied().chain(sigma).collect());
        }
        history
    }

    /// Unknown E, ρ and one input at DOF 2; a DISP row on DOF 1 and an ACCEL row on DOF 2.
    pub(crate) fn setup(x: &[f64]) -> FilterSetup {
        let sensors = SensorRows::new(
            vec!["D1".into(), "A2".into()],
            vec!["DISP".into(), "ACCEL".into()],
            Mat::from_fn(2, 2, |i, j| if i == j { 1.0 } else { 0.0 }),
        )
        .unwrap();
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
            coordinates: Coordinates::Physical,
        }
    }

    const X: [f64; 7] = [1e-3, -2e-3, 0.3, 0.1, 4.0, 1.2, 0.9];
    const LOAD: [f64; 2] = [3.0, -1.0];

    /// A negative initial E makes the chain's K = K⁰ + E K¹ indefinite while S and M stay
    /// definite at Δt = 1e-3 (Δt² K ≈ 1e-2 M): [`Filter::new`] refuses it through K, in physical
    /// and in re-diagonalized modal coordinates; the positive E of the other tests passes.
    #[test]
    fn negative_initial_modulus_is_refused() {
        for coordinates in [Coordinates::Physical, Coordinates::Rediagonalized(0.1)] {
            let mut negative = setup(&X);
            negative.p[0] = -X[5];
            negative.coordinates = coordinates;
            assert!(
                matches!(Filter::new(negative), Err(FilterError::IndefiniteStart { cause: DenseEigenError::IndefiniteStiffness { smallest, .. }, .. }) if smallest < 0.0),
                "{coordinates:?}"
            );
            let positive = FilterSetup {
                coordinates,
                ..setup(&X)
            };
            assert!(Filter::new(positive).is_ok(), "{coordinates:?}");
        }
    }

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
            let fd: Vec<f64> = up
                .iter()
                .zip(&down)
                .map(|(a, b)| (a - b) / (2.0 * h))
                .collect();
            let scale = fd
                .iter()
                .chain((0..7).map(|r| &j[(r, c)]))
                .fold(0.0_f64, |m, v| m.max(v.abs()));
            for r in 0..7 {
                assert!(
                    (fd[r] - j[(r, c)]).abs() <= 1e-7 * scale,
                    "J[{r},{c}] = {} vs finite difference {}",
                    j[(r, c)],
                    fd[r]
                );
            }
        }
    }

    /// The blockwise prediction ([`propagate`] from Gᵀ and H) equals the dense J P Jᵀ + Q
    /// (eq. 8.24) with J from [`Filter::transition`], after a few steps have filled P (physical
    /// coordinates, where both are in the same coordinates), and leaves P exactly symmetric in
    /// both coordinate systems, after the prediction and after the correction. Bound 1e-12 of
    /// max |P|: the two evaluations differ only in summation order.
    #[test]
    fn covariance_prediction_is_j_p_jt_plus_q_and_exactly_symmetric() {
        for coordinates in [Coordinates::Physical, Coordinates::Auto] {
            let mut unit = setup(&X);
            unit.coordinates = coordinates;
            unit.prom.stiffness[0].fill(0.0); // one material: the modal path applies
            let mut filter = Filter::new(unit).unwrap();
            let exactly_symmetric =
                |p: &Mat<f64>| (0..p.nrows()).all(|i| (0..i).all(|j| p[(i, j)] == p[(j, i)]));
            for step in 0..5 {
                let before = filter.p.clone();
                filter.predict(&LOAD).unwrap();
                assert!(
                    exactly_symmetric(&filter.p),
                    "{coordinates:?} step {step}: P⁻ not exactly symmetric"
                );
                if coordinates == Coordinates::Physical {
                    let j = filter.transition();
                    let mut dense = &j * &before * j.transpose();
                    (0..dense.nrows()).for_each(|i| dense[(i, i)] += filter.noise(i));
                    let scale = dense.norm_max();
                    assert!(
                        (&dense - &filter.p).norm_max() <= 1e-12 * scale,
                        "step {step}: {:e} vs {scale:e}",
                        (&dense - &filter.p).norm_max()
                    );
                }
                let (n, mut y) = (filter.n, vec![0.0; 2]);
                filter.setup.measured.evaluate(
                    &filter.x[..n],
                    &filter.x[n..2 * n],
                    &filter.a,
                    &mut y,
                );
                filter.correct(&LOAD, &[y[0] + 1e-6, y[1] + 1e-3]).unwrap();
                assert!(
                    exactly_symmetric(&filter.p),
                    "{coordinates:?} step {step}: P⁺ not exactly symmetric"
                );
            }
        }
    }

    /// The Joseph update (eq. 8.28), applied in groups of up to three sensors per pass over P,
    /// equals the dense (I − 𝒦 J_m) P⁻ (I − 𝒦 J_m)ᵀ + 𝒦 R 𝒦ᵀ for m = 1 … 5 sensors (groups 1, 2,
    /// 3, 3 + 1, 3 + 2) and leaves P exactly symmetric. Bound 1e-12 of max |P⁻|: the two differ
    /// in summation order and in the solve for 𝒦 (S_y is 5 × 5 at most, well conditioned here).
    #[test]
    fn joseph_update_in_sensor_groups_equals_the_dense_form() {
        let kinds = ["DISP", "ACCEL", "STRAIN", "VEL", "ACCEL"];
        for m in 1..=5 {
            let mut unit = setup(&X);
            let h = Mat::from_fn(m, 2, |r, c| {
                [1.0, -0.5, 0.3, 2.0, 0.7][r] * if c == r % 2 { 1.0 } else { 0.25 }
            });
            unit.measured = SensorRows::new(
                (0..m).map(|r| format!("S{r}")).collect(),
                kinds[..m].iter().map(|k| k.to_string()).collect(),
                h,
            )
            .unwrap();
            unit.r = (0..m).map(|r| 1e-8 * (1 + r) as f64).collect();
            let mut filter = Filter::new(unit).unwrap();
            let n = filter.n;
            let mut y = vec![0.0; m];
            for step in 0..3 {
                filter.predict(&LOAD).unwrap();
                let before = filter.p.clone();
                filter.setup.measured.evaluate(
                    &filter.x[..n],
                    &filter.x[n..2 * n],
                    &filter.a,
                    &mut y,
                );
                y.iter_mut()
                    .enumerate()
                    .for_each(|(r, y)| *y += 1e-4 * (r as f64 - 1.5));
                filter.correct(&LOAD, &y).unwrap();
                let (jm, big_n) = (filter.measurement_jacobian().clone(), before.nrows());
                let mut s_y = &jm * &before * jm.transpose();
                (0..m).for_each(|r| s_y[(r, r)] += filter.setup.r[r]);
                let gain = &before
                    * jm.transpose()
                    * s_y.partial_piv_lu().solve(Mat::<f64>::identity(m, m));
                let l = Mat::<f64>::identity(big_n, big_n) - &gain * &jm;
                let r = Mat::from_fn(m, m, |i, j| if i == j { filter.setup.r[i] } else { 0.0 });
                let dense = &l * &before * l.transpose() + &gain * &r * gain.transpose();
                let (error, scale) = ((&dense - &filter.p).norm_max(), before.norm_max());
                assert!(
                    error <= 1e-12 * scale,
                    "m = {m}, step {step}: {error:e} vs max |P⁻| {scale:e}"
                );
                assert!(
                    (0..big_n).all(|i| (0..i).all(|j| filter.p[(i, j)] == filter.p[(j, i)])),
                    "m = {m}, step {step}: P⁺ not exactly symmetric"
                );
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
            f.setup
                .measured
                .evaluate(&f.x[..2], &f.x[2..4], &f.a, &mut y);
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
                assert!(
                    (fd - base.jm[(r, c)]).abs() <= 1e-7 * scale,
                    "J_m[{r},{c}] = {} vs finite difference {fd}",
                    base.jm[(r, c)]
                );
            }
        }
    }

    /// With nothing unknown, the prediction is the BDF1 integrator of the transient sequence
    /// (the filter's model is the one that generates SOL TRANSIENT data): same q, q̇, q̈ to
    /// round-off over 200 steps of a sine load.
    #[test]
    fn prediction_equals_the_bdf1_integrator() {
        for coordinates in [Coordinates::Physical, Coordinates::Auto] {
            let mut s = setup(&X);
            s.unknown_params.clear();
            s.q_params.clear();
            s.p0_params.clear();
            s.s_un = Mat::zeros(2, 0);
            s.q_inputs.clear();
            s.p0_inputs.clear();
            s.u0.clear();
            s.coordinates = coordinates;
            let mut filter = Filter::new(s.clone()).unwrap();
            assert_eq!(
                filter.modal(),
                coordinates == Coordinates::Auto,
                "nothing estimated: modal coordinates apply"
            );
            let mut at = s.prom.workspace();
            s.prom.evaluate(&s.p, &mut at).unwrap();
            let sys = LinearSystem {
                mass: at.mass(),
                damping: at.damping(),
                stiffness: at.stiffness(),
            };
            let load = |t: f64, f: &mut [f64]| {
                f.iter_mut()
                    .zip(LOAD)
                    .for_each(|(f, l)| *f = l * (40.0 * t).sin())
            };
            let mut reference = Vec::new();
            integrate(sys, Method::Bdf1, s.dt, 200, &s.q0, &s.v0, load, |st| {
                reference.push((st.q.to_vec(), st.v.to_vec(), st.a.to_vec()))
            })
            .unwrap();
            for (k, (q, v, a)) in reference.iter().enumerate().skip(1) {
                let mut f = [0.0; 2];
                load(k as f64 * s.dt, &mut f);
                filter.predict(&f).unwrap();
                let (x, acc) = (filter.state(), filter.acceleration());
                for i in 0..2 {
                    assert!(
                        (x[i] - q[i]).abs() <= 1e-12 * 1e-2
                            && (x[2 + i] - v[i]).abs() <= 1e-12
                            && (acc[i] - a[i]).abs() <= 1e-9,
                        "{coordinates:?}, step {k}"
                    );
                }
            }
        }
    }

    /// The modal path is the same EKF as the physical one (a linear change of state): on the
    /// chain of one material (no grounded spring: E and ρ scale all of K and M, so both paths
    /// apply), with E, ρ and one input unknown, a non-zero initial state of variance 1e-10, DISP and
    /// ACCEL rows and data from the BDF1 integrator at the true values, the estimates of q, q̇, u,
    /// E, ρ and their standard deviations agree over 400 steps. They differ by round-off only —
    /// of Φ and Φ⁻¹ = Φᵀ M₀ (Φ⁻¹ Φ = I to ~1e-15) and of the order of operations — amplified by
    /// the gain's dependence on P, whose entries span 1e-20 … 1: bound 1e-9 of each series'
    /// range, as the filterpy cross-check.
    #[test]
    fn modal_path_equals_physical_path() {
        let mut truth = setup(&[0.0, 0.0, 0.0, 0.0, 2.0, 1.0, 1.0]);
        truth.prom.stiffness[0].fill(0.0);
        let mut at = truth.prom.workspace();
        truth.prom.evaluate(&truth.p, &mut at).unwrap();
        let sys = LinearSystem {
            mass: at.mass(),
            damping: at.damping(),
            stiffness: at.stiffness(),
        };
        let known = |t: f64, f: &mut [f64]| {
            f.iter_mut()
                .zip(LOAD)
                .for_each(|(f, l)| *f = 1e2 * l * (40.0 * t).sin())
        };
        let (q0, v0) = ([2e-3, -1e-3], [0.1, 0.3]);
        let mut data = Vec::new();
        let full = |t: f64, f: &mut [f64]| {
            known(t, f);
            f[1] += 2.0;
        };
        integrate(sys, Method::Bdf1, truth.dt, 400, &q0, &v0, full, |st| {
            data.push([st.q[0], st.a[1]])
        })
        .unwrap();
        let run = |coordinates: Coordinates| {
            let mut s = setup(&[q0[0], q0[1], v0[0], v0[1], 0.0, 1.2, 0.9]);
            s.prom.stiffness[0].fill(0.0);
            s.coordinates = coordinates;
            s.p0_state = 1e-10;
            s.p0_params = vec![1e-2, 1e-2];
            let mut filter = Filter::new(s).unwrap();
            assert_eq!(filter.modal(), coordinates == Coordinates::Auto);
            let history = history(&mut filter, &data, known, truth.dt);
            let p = filter.covariance();
            (history, p)
        };
        let ((physical, p_physical), (modal, p_modal)) =
            (run(Coordinates::Physical), run(Coordinates::Auto));
        let names = ["q1", "q2", "v1", "v2", "u", "E", "RHO"];
        for c in 0..14 {
            let range = physical.iter().map(|x| x[c].abs()).fold(0.0, f64::max);
            let worst = physical
                .iter()
                .zip(&modal)
                .map(|(a, b)| (a[c] - b[c]).abs())
                .fold(0.0, f64::max);
            let what = if c < 7 {
                names[c].to_string()
            } else {
                format!("σ of {}", names[c - 7])
            };
            println!("{what}: max |physical − modal| = {worst:.2e} (range {range:.2e})");
            assert!(
                worst <= 1e-9 * range,
                "{what}: {worst:e} vs range {range:e}"
            );
        }
        // the estimate converged (the comparison is not between two diverged runs)
        let last = physical.last().unwrap();
        assert!(
            (last[5] - 1.0).abs() < 0.02
                && (last[6] - 1.0).abs() < 0.02
                && (last[4] - 2.0).abs() < 0.1,
            "{last:?}"
        );
        // the final covariance maps back to the physical one
        let scale = p_physical.norm_max();
        assert!((&p_physical - &p_modal).norm_max() <= 1e-9 * scale);
    }
}

/// Re-diagonalized modal coordinates on the chain with its grounded spring (E's part is not
/// diagonal in any modes).
#[cfg(test)]
mod rediagonalized {
    use super::*;
    use crate::dynamics::integrators::{LinearSystem, Method, integrate};

    /// [`super::tests::setup`] with E and ρ unknown from `p`, no unknown input, q₀ = (2e-3, −1e-3),
    /// q̇₀ = (0.1, 0.3) of variance 1e-10, parameter variance 1e-2.
    fn setup(coordinates: Coordinates, p: [f64; 2]) -> FilterSetup {
        let mut s = super::tests::setup(&[2e-3, -1e-3, 0.1, 0.3, 0.0, p[0], p[1]]);
        s.s_un = Mat::zeros(2, 0);
        (s.q_inputs, s.p0_inputs, s.u0) = (vec![], vec![], vec![]);
        s.p0_state = 1e-10;
        s.p0_params = vec![1e-2, 1e-2];
        s.coordinates = coordinates;
        s
    }

    const LOAD: [f64; 2] = [300.0, -100.0];

    /// The mean is exact with couplings: modes at p_a = (1.2, 0.9), parameters moved to
    /// p_b = (1.25, 0.93) (drift 4 %, under τ = 0.1, so the coupled parts are in use), one
    /// prediction from the same physical state equals the physical path's BDF1 step at p_b.
    /// Both solve the same linear system (Jacobi to 4 ε against Cholesky): bound 1e-12 of the
    /// largest entry.
    #[test]
    fn prediction_with_coupled_parts_equals_the_physical_one() {
        let p_b = [1.25, 0.93];
        let mut coupled = Filter::new(setup(Coordinates::Rediagonalized(0.1), [1.2, 0.9])).unwrap();
        assert!(
            coupled.modal() && coupled.rediagonalizations() == Some(0),
            "the chain couples: re-diagonalized coordinates"
        );
        let (n, np) = (coupled.n, coupled.np);
        coupled.x[2 * n..2 * n + np].copy_from_slice(&p_b);
        coupled.refresh().unwrap();
        coupled.set_acceleration();
        assert_eq!(coupled.rediagonalizations(), Some(0), "4 % is under τ");
        let mut physical = Filter::new(setup(Coordinates::Physical, p_b)).unwrap();
        coupled.predict(&LOAD).unwrap();
        physical.predict(&LOAD).unwrap();
        let (a, b) = (coupled.state(), physical.state());
        let scale = b.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        for i in 0..b.len() {
            assert!(
                (a[i] - b[i]).abs() <= 1e-12 * scale,
                "x[{i}]: {} vs {}",
                a[i],
                b[i]
            );
        }
        let (a, b) = (coupled.acceleration(), physical.acceleration());
        let scale = b.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        assert!(
            (0..n).all(|i| (a[i] - b[i]).abs() <= 1e-12 * scale),
            "q̈ {a:?} vs {b:?}"
        );
    }

    /// Data from BDF1 at (1, 1); estimates from (1.2, 0.9) over 400 steps, as in
    /// `modal_path_equals_physical_path`. Returns the history of x* and σ, and the number of
    /// re-diagonalizations.
    fn run(coordinates: Coordinates) -> (Vec<Vec<f64>>, Option<usize>) {
        let truth = setup(Coordinates::Physical, [1.0, 1.0]);
        let mut at = truth.prom.workspace();
        truth.prom.evaluate(&truth.p, &mut at).unwrap();
        let sys = LinearSystem {
            mass: at.mass(),
            damping: at.damping(),
            stiffness: at.stiffness(),
        };
        let known = |t: f64, f: &mut [f64]| {
            f.iter_mut()
                .zip(LOAD)
                .for_each(|(f, l)| *f = l * (40.0 * t).sin())
        };
        let mut data = Vec::new();
        integrate(
            sys,
            Method::Bdf1,
            truth.dt,
            400,
            &truth.q0,
            &truth.v0,
            known,
            |st| data.push([st.q[0], st.a[1]]),
        )
        .unwrap();
        let mut filter = Filter::new(setup(coordinates, [1.2, 0.9])).unwrap();
        (
            super::tests::history(&mut filter, &data, known, truth.dt),
            filter.rediagonalizations(),
        )
    }

    /// With a tolerance below every change of the estimate, the modes are recomputed at every
    /// step, J_v is exact and the filter is the physical one under a change of state: same
    /// estimates and σ. Round-off of one re-diagonalization per step (Φ, Φ⁻¹ and T P Tᵀ, each
    /// ~1e-15) accumulates over 400 steps and is amplified like the modal path's: bound 1e-8 of
    /// each series' range. With τ = 0.1 (J_v's q and q̇ blocks from the diagonals of S̃, K̃, M̃,
    /// an error ≤ 10 % of the couplings) the estimate still converges: E and ρ within 2 % of
    /// the truth, as the physical path (the same bound as the modal path's test), with far fewer
    /// re-diagonalizations.
    #[test]
    fn rediagonalized_coordinates_follow_the_physical_path() {
        let (physical, _) = run(Coordinates::Physical);
        let (every_step, count) = run(Coordinates::Rediagonalized(1e-14));
        assert!(count.is_some_and(|c| c > 300), "{count:?}");
        let names = ["q1", "q2", "v1", "v2", "E", "RHO"];
        for c in 0..12 {
            let range = physical.iter().map(|x| x[c].abs()).fold(0.0, f64::max);
            let worst = physical
                .iter()
                .zip(&every_step)
                .map(|(a, b)| (a[c] - b[c]).abs())
                .fold(0.0, f64::max);
            let what = if c < 6 {
                names[c].to_string()
            } else {
                format!("σ of {}", names[c - 6])
            };
            assert!(
                worst <= 1e-8 * range,
                "{what}: {worst:e} vs range {range:e}"
            );
        }
        let (loose, count) = run(Coordinates::Rediagonalized(0.1));
        assert!(count.is_some_and(|c| c < 10), "{count:?}");
        for x in [physical.last().unwrap(), loose.last().unwrap()] {
            assert!(
                (x[4] - 1.0).abs() < 0.02 && (x[5] - 1.0).abs() < 0.02,
                "{x:?}"
            );
        }
    }

    /// Virtual sensors read in the filter's coordinates ([`Filter::sensor_rows`] with
    /// [`Filter::filter_state`], as SOL ESTIMATE reads them) equal the rows applied to the
    /// physical state and q̈ after every step, across re-diagonalizations (τ = 1e-3 moves the
    /// modes several times in 400 steps; the rows are remade when the count changes). Both are
    /// H Φ z in a different order: round-off, bound 1e-12 of each sensor's range.
    #[test]
    fn virtual_sensors_in_filter_coordinates_equal_the_physical_ones() {
        let truth = setup(Coordinates::Physical, [1.0, 1.0]);
        let rows = SensorRows::new(
            vec!["D1".into(), "V2".into(), "A1".into()],
            vec!["DISP".into(), "VEL".into(), "ACCEL".into()],
            Mat::from_fn(3, 2, |i, j| [[0.7, -0.2], [0.1, 1.0], [1.0, 0.3]][i][j]),
        )
        .unwrap();
        let mut filter = Filter::new(setup(Coordinates::Rediagonalized(1e-3), [1.2, 0.9])).unwrap();
        let mut rows_of = (filter.rediagonalizations(), filter.sensor_rows(&rows));
        let (mut from_modes, mut from_q) = (Vec::new(), Vec::new());
        for k in 1..400 {
            let f = LOAD.map(|l| l * (40.0 * k as f64 * truth.dt).sin());
            filter
                .step(&f, &[1e-3 * (30.0 * k as f64 * truth.dt).sin(), 0.0])
                .unwrap();
            if filter.rediagonalizations() != rows_of.0 {
                rows_of = (filter.rediagonalizations(), filter.sensor_rows(&rows));
            }
            let (mut a, mut b) = (vec![0.0; 3], vec![0.0; 3]);
            let (z, z_acc) = filter.filter_state();
            rows_of.1.evaluate(&z[..2], &z[2..4], z_acc, &mut a);
            let x = filter.state();
            rows.evaluate(&x[..2], &x[2..4], filter.acceleration(), &mut b);
            from_modes.push(a);
            from_q.push(b);
        }
        assert!(
            filter.rediagonalizations().is_some_and(|c| c >= 2),
            "{:?}",
            filter.rediagonalizations()
        );
        for s in 0..3 {
            let range = from_q.iter().map(|y| y[s].abs()).fold(0.0, f64::max);
            let worst = from_q
                .iter()
                .zip(&from_modes)
                .map(|(a, b)| (a[s] - b[s]).abs())
                .fold(0.0, f64::max);
            assert!(
                range > 0.0 && worst <= 1e-12 * range,
                "{}: {worst:e} vs range {range:e}",
                rows.names[s]
            );
        }
    }

    /// A tolerance outside (0, 0.1] is refused.
    #[test]
    fn tolerance_out_of_range_is_refused() {
        for t in [0.0, -1e-3, 0.5, f64::NAN] {
            assert!(
                matches!(
                    Filter::new(setup(Coordinates::Rediagonalized(t), [1.2, 0.9])),
                    Err(FilterError::Tolerance(_))
                ),
                "{t}"
            );
        }
    }

    /// A coupled solve whose Jacobi iteration diverges (an indefinite coupling, spectral radius
    /// 2) falls back to the dense factorization and marks the drift stalled: x = A⁻¹ b exact.
    #[test]
    fn diverging_coupled_solve_falls_back_to_a_factorization() {
        use super::super::modal::OffDiagonal;
        let off = Mat::from_fn(2, 2, |i, j| if i == j { 0.0 } else { 1.0 });
        let couplings = [Coupling {
            function: 0,
            reference: 1.0,
            stiffness: Some(OffDiagonal::Dense(off)),
            mass: None,
        }];
        let mut drift = Drift {
            tolerance: 0.1,
            weights: vec![2.0],
            derivatives: Mat::zeros(1, 0),
            current: 0.0,
            s_un: Mat::zeros(2, 0),
            h: Mat::zeros(0, 2),
            iterate: vec![0.0; 2],
            product: vec![0.0; 2],
            stalled: false,
            count: 0,
        };
        let mut x = [3.0, 3.0];
        solve_modal(
            &[1.0, 1.0],
            &couplings,
            Some(&mut drift),
            (0.0, 1.0),
            &mut x,
        );
        assert!(drift.stalled);
        assert!(
            (x[0] - 1.0).abs() <= 1e-14 && (x[1] - 1.0).abs() <= 1e-14,
            "{x:?}"
        ); // [[1,2],[2,1]] x = [3,3]
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
        let sensors = SensorRows::new(
            vec!["D1".into(), "A2".into()],
            vec!["DISP".into(), "ACCEL".into()],
            Mat::from_fn(2, 2, |i, j| if i == j { 1.0 } else { 0.0 }),
        )
        .unwrap();
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
            coordinates: Coordinates::Physical,
        };
        let z = (1..=STEPS)
            .map(|k| k as f64 * 1e-3)
            .map(|t| [1e-3 * (30.0 * t).sin(), 0.5 * (50.0 * t).cos()])
            .collect();
        (setup, z)
    }

    fn rows(m: &Mat<f64>) -> Vec<Vec<f64>> {
        (0..m.nrows())
            .map(|i| (0..m.ncols()).map(|j| m[(i, j)]).collect())
            .collect()
    }

    /// The filter's estimates equal filterpy's KalmanFilter (Joseph update) run on the same
    /// F = J, H = J_m, Q, R, x₀, P₀ and measurements. Reference:
    /// reference/estimate/filterpy_linear.json, made by tools/estimate/filterpy_reference.py
    /// from the case this test writes when PARAFLEX_WRITE_KF_CASE names a file. The two
    /// implementations differ in operation order only (J (J P)ᵀ vs F P Fᵀ, the expanded vs
    /// literal Joseph product, q̈⁻ from the BDF1 difference vs J_m x⁻): round-off, amplified
    /// by the conditioning of P (entries from 1e-12 to 1): bound 1e-9 of each state's range.
    /// The matrices are the physical path's; the modal path (which applies: nothing is
    /// estimated) is held to the same reference and bound.
    #[test]
    fn linear_case_equals_filterpy() {
        let (setup, z) = linear_case();
        let mut filter = Filter::new(setup.clone()).unwrap();
        let mut modal = Filter::new(FilterSetup {
            coordinates: Coordinates::Auto,
            ..setup.clone()
        })
        .unwrap();
        assert!(
            modal.modal(),
            "no parameter estimated: the modal path applies"
        );
        let mut modal_states = Vec::new();
        let zero = [0.0; 2];
        let mut states = Vec::new();
        let mut jacobians = None;
        for y in &z {
            filter.step(&zero, y).unwrap();
            states.push(filter.state().to_vec());
            modal.step(&zero, y).unwrap();
            modal_states.push(modal.state().to_vec());
            jacobians.get_or_insert_with(|| {
                (filter.transition(), filter.measurement_jacobian().clone())
            });
        }
        let (f, h) = jacobians.unwrap();
        if let Ok(path) = std::env::var("PARAFLEX_WRITE_KF_CASE") {
            let q: Vec<f64> = (0..5).map(|i| filter.noise(i)).collect();
            let p0: Vec<f64> = vec![1e-6, 1e-6, 1e-6, 1e-6, 1.0];
            let x0: Vec<f64> = [setup.q0.clone(), setup.v0.clone(), setup.u0.clone()].concat();
            let case = serde_json::json!({ "F": rows(&f), "H": rows(&h), "Q_diag": q, "R_diag": setup.r, "x0": x0, "P0_diag": p0, "z": z });
            std::fs::write(&path, serde_json::to_string_pretty(&case).unwrap()).unwrap();
        }
        let reference = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("reference/estimate/filterpy_linear.json");
        let text =
            std::fs::read_to_string(&reference).expect("reference/estimate/filterpy_linear.json");
        let r: serde_json::Value = serde_json::from_str(&text).unwrap();
        let matrix = |key: &str| -> Vec<Vec<f64>> {
            serde_json::from_value(r["case"][key].clone()).unwrap()
        };
        // the reference was made from these very matrices
        for (key, ours) in [("F", rows(&f)), ("H", rows(&h))] {
            for (a, b) in matrix(key).iter().flatten().zip(ours.iter().flatten()) {
                assert!(
                    (a - b).abs() <= 1e-14 * a.abs().max(1e-300) + 1e-300,
                    "{key}: {a} vs {b}"
                );
            }
        }
        let expected: Vec<Vec<f64>> = serde_json::from_value(r["x"].clone()).unwrap();
        assert_eq!(expected.len(), STEPS);
        for c in 0..5 {
            let range = expected.iter().map(|x| x[c].abs()).fold(0.0, f64::max);
            for (path, states) in [("physical", &states), ("modal", &modal_states)] {
                let worst = expected
                    .iter()
                    .zip(states)
                    .map(|(e, s)| (e[c] - s[c]).abs())
                    .fold(0.0, f64::max);
                println!(
                    "state {c}, {path} path: max |paraflex − filterpy| = {worst:.2e} (range {range:.2e})"
                );
                assert!(
                    worst <= 1e-9 * range,
                    "state {c}, {path} path: {worst:e} vs range {range:e}"
                );
            }
        }
    }
}
