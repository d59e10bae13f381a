//! The augmented extended Kalman filter on a pROM (thesis §8.2–8.3).
//!
//! State x* = [q, q̇, u_un, p] (eq. 8.1), u_un and p random walks (eq. 8.2–8.3). One step:
//!
//! - **Prediction** (eq. 8.22): BDF1 on the first-order form (eq. 8.10–8.13), as the thesis, or
//!   the trapezoidal rule ([`Prediction`], EKF field PREDICT; the default). With u and p held
//!   (their rows of A* are zero), g_d = 0 is linear in (q_k, q̇_k) at fixed p and is solved
//!   exactly by one solve with an effective matrix S at p_{k−1}⁺
//!   ([`crate::dynamics::velocity_form`], on the model's products and factored S):
//!   - BDF1: S q̇_k = M q̇_{k−1} − Δt K q_{k−1} + Δt (S_un u + f_kn(t_k)), q_k = q_{k−1} + Δt q̇_k,
//!     S = M + Δt C + Δt² K; q̈_k = (q̇_k − q̇_{k−1})/Δt is the equation of motion at step k.
//!   - trapezoidal: S q̇_k = (2M − S) q̇_{k−1} − Δt K q_{k−1} + Δt S_un u + Δt/2 (f_kn(t_{k−1}) +
//!     f_kn(t_k)) (written with M q̈_{k−1}, the equation of motion at x⁺_{k−1}),
//!     q_k = q_{k−1} + Δt/2 (q̇_{k−1} + q̇_k), S = M + Δt/2 C + Δt²/4 K; no numerical damping.
//! - **Jacobian** J = −(∂g_d/∂x_k)⁻¹ ∂g_d/∂x_{k−1} (eq. 8.16–8.18, J_c of eq. 8.32). Its rows
//!   for u and p are identity rows and its q rows are e_q + a e_q̇ + b J_v (BDF1: a = 0, b = Δt;
//!   trapezoidal: a = b = Δt/2), so only the q̇ block row J_v (n × N) is computed, by one solve
//!   with S:
//!   - BDF1 (eq. 8.16–8.18 = (I − Δt J_c)⁻¹): J_v = S⁻¹ [−Δt K, M, Δt S_un, −Δt D],
//!     D_j = ∂K/∂p_j q + ∂C/∂p_j q̇ + ∂M/∂p_j q̈ at x_k, q̈_k — the analytic parameter
//!     derivatives of the affine pROM (eq. 8.19–8.20, 8.33–8.35: M D_j = −M ∂q̈/∂p_j);
//!   - trapezoidal: J_v = S⁻¹ [−Δt K, 2M − S, Δt S_un, −Δt D̄] with D̄ the same D at the step's
//!     mid-point (x_{k−1} + x_k)/2, (q̈_{k−1} + q̈_k)/2 (differentiating S q̇_k = (2M − S) q̇_{k−1}
//!     − Δt K q_{k−1} + … in p_j gives S ∂q̇_k/∂p_j = −∂S/∂p_j (q̇_k + q̇_{k−1}) + 2 ∂M/∂p_j q̇_{k−1}
//!     − Δt ∂K/∂p_j q_{k−1} = −Δt D̄_j by the trapezoidal relations; derivation in
//!     docs/estimation.md).
//!
//!   Without unknown parameters J is constant and computed once.
//! - **Covariance** P⁻ = J P Jᵀ + Q (eq. 8.24) by blocks from G = J_v P and H = G J_vᵀ
//!   (`propagation`; the trapezoidal J as a shear of P followed by BDF1-shaped blocks): n N² +
//!   n² N multiply-adds instead of the dense 2 N³, and exactly symmetric.
//! - **Correction** ([`super::ekf`]): measurement Jacobian J_m (eq. 8.37–8.39; [`super::measurement`]), gain
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
//! P ← J P Jᵀ costs (N + 4 n) n (2 + n_un + n_p) (`modal_coordinates`) instead of
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

use faer::{Mat, MatRef};

use super::coordinates::{Model, PromCoordinates};
use super::ekf::{Ekf, ProcessModel};
use super::measurement::SensorRows;
use super::prom_model::PromModel;
use crate::card_values::MAX_REDIAGONALIZATION_TOLERANCE;
pub use crate::card_values::Prediction;
use crate::linalg::dense::{DenseEigenError, product, stiffness_semidefinite};
use crate::rom::prom::Prom;

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

/// The numbers of each prediction ([`Prediction`]: the `EKF` card's PREDICT field).
impl Prediction {
    /// h of S = M + h C + h² K: Δt (BDF1) or Δt/2 (trapezoidal).
    pub fn effective_step(self, dt: f64) -> f64 {
        match self {
            Prediction::Bdf1 => dt,
            Prediction::Trapezoidal => 0.5 * dt,
        }
    }

    /// a and b of q_k = q_{k−1} + a q̇_{k−1} + b q̇_k: (0, Δt) for BDF1, (Δt/2, Δt/2) for the
    /// trapezoidal rule.
    pub fn displacement_weights(self, dt: f64) -> (f64, f64) {
        match self {
            Prediction::Bdf1 => (0.0, dt),
            Prediction::Trapezoidal => (0.5 * dt, 0.5 * dt),
        }
    }
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
    /// The prediction's time discretization (eq. 8.22).
    pub prediction: Prediction,
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
    #[error("{0}")]
    Mechanism(String),
    #[error("re-diagonalization tolerance {0}: expected 0 < τ ≤ {MAX_REDIAGONALIZATION_TOLERANCE}")]
    Tolerance(f64),
    #[error("the pROM at the initial guess {params:?}: {cause}")]
    IndefiniteStart {
        params: Vec<f64>,
        cause: DenseEigenError,
    },
}

/// The augmented EKF on a pROM (see the module documentation): [`Ekf`] over the pROM's
/// process model.
pub struct Filter {
    ekf: Ekf<PromModel>,
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

impl Filter {
    /// Check the setup and prepare step 0.
    pub fn new(setup: FilterSetup) -> Result<Self, FilterError> {
        let (model, x, p) = PromModel::new(setup)?;
        Ok(Filter {
            ekf: Ekf::new(model, x, p),
        })
    }

    /// Augmented state size N = 2 n_r + n_un + n_p.
    pub fn size(&self) -> usize {
        self.ekf.x.len()
    }

    /// Whether the filter runs in modal coordinates (see the module documentation).
    pub fn modal(&self) -> bool {
        matches!(self.ekf.model.model, Model::Modal(_))
    }

    /// How many times re-diagonalized coordinates recomputed their modes (None: the
    /// coordinates are not re-diagonalized ones, or the modes diagonalize the pROM exactly).
    pub fn rediagonalizations(&self) -> Option<usize> {
        match &self.ekf.model.model {
            Model::Modal(md) => md.drift.as_ref().map(|dr| dr.count),
            Model::Physical(_) => None,
        }
    }

    /// x* = [q, q̇, u_un, p] (physical q; modal coordinates: Φ z mapped on the first request
    /// after a step, 2 n² multiply-adds).
    pub fn state(&self) -> &[f64] {
        let pm = &self.ekf.model;
        match &pm.model {
            Model::Physical(_) => &self.ekf.x,
            Model::Modal(md) => &md.physical.get_or_init(|| pm.physical(md, &self.ekf.x)).0,
        }
    }

    /// q̈ at the current estimate (physical; as [`Filter::state`]).
    pub fn acceleration(&self) -> &[f64] {
        let pm = &self.ekf.model;
        match &pm.model {
            Model::Physical(_) => &pm.a,
            Model::Modal(md) => &md.physical.get_or_init(|| pm.physical(md, &self.ekf.x)).1,
        }
    }

    /// x* and q̈ in the filter's coordinates (modal z where the filter runs on modes; u and p
    /// are the same in every coordinates): with [`Filter::sensor_rows`], virtual sensors without
    /// mapping the state back to q.
    pub fn filter_state(&self) -> (&[f64], &[f64]) {
        (&self.ekf.x, &self.ekf.model.a)
    }

    /// Sensor rows in the filter's coordinates (H Φ on modes; n² per row), for
    /// [`Filter::filter_state`]. They change when the filter re-diagonalizes
    /// ([`Filter::rediagonalizations`]).
    pub fn sensor_rows(&self, rows: &SensorRows) -> SensorRows {
        match &self.ekf.model.model {
            Model::Physical(_) => rows.clone(),
            Model::Modal(md) => SensorRows {
                h: product(rows.h.as_ref(), md.form.basis.as_ref()),
                ..rows.clone()
            },
        }
    }

    /// The covariance of x* (physical q: T P Tᵀ in modal coordinates; N³, for checks).
    pub fn covariance(&self) -> Mat<f64> {
        match &self.ekf.model.model {
            Model::Physical(_) => self.ekf.p.clone(),
            Model::Modal(md) => {
                let (n, big_n) = (self.ekf.model.n, self.size());
                let phi = md.form.basis.as_ref();
                let t = Mat::from_fn(big_n, big_n, |i, j| match (i, j) {
                    (i, j) if i < n && j < n => phi[(i, j)],
                    (i, j) if (n..2 * n).contains(&i) && (n..2 * n).contains(&j) => {
                        phi[(i - n, j - n)]
                    }
                    (i, j) if i >= 2 * n && i == j => 1.0,
                    _ => 0.0,
                });
                &t * &self.ekf.p * t.transpose()
            }
        }
    }

    /// The variance of x*_i (physical q), without forming the covariance.
    pub fn variance(&self, i: usize) -> f64 {
        let n = self.ekf.model.n;
        match &self.ekf.model.model {
            Model::Modal(md) if i < 2 * n => {
                let b = if i < n { 0 } else { n };
                let row = |c: usize| md.form.basis[(i - b, c)];
                (0..n)
                    .map(|c| {
                        row(c)
                            * (0..n)
                                .map(|r| self.ekf.p[(b + r, b + c)] * row(r))
                                .sum::<f64>()
                    })
                    .sum()
            }
            _ => self.ekf.p[(i, i)],
        }
    }

    /// Values of every pROM parameter at the current estimate.
    pub fn parameters(&self) -> &[f64] {
        &self.ekf.model.params
    }

    /// y − h(x⁻) of the last step.
    pub fn innovation(&self) -> &[f64] {
        &self.ekf.innovation
    }

    /// J_m of the last step (rows of the measured sensors), in the filter's coordinates.
    pub fn measurement_jacobian(&self) -> &Mat<f64> {
        &self.ekf.jm
    }

    /// The transition Jacobian J of the last step (dense N × N, for checks and tools), in the
    /// filter's coordinates.
    /// Its q rows are e_q + a e_q̇ + b J_v ([`Prediction::displacement_weights`]); the model
    /// keeps J̃_v = J_v A⁻¹ (see `propagation`), so J_v's q̇ columns are J̃_v's plus a times its
    /// q columns.
    pub fn transition(&self) -> Mat<f64> {
        let (n, big_n) = (self.ekf.model.n, self.size());
        let setup = &self.ekf.model.setup;
        let (a, b) = setup.prediction.displacement_weights(setup.dt);
        let sheared = self.ekf.model.model.transition_rows(n, big_n);
        let jv = Mat::from_fn(n, big_n, |i, j| match j {
            j if (n..2 * n).contains(&j) => sheared[(i, j)] + a * sheared[(i, j - n)],
            j => sheared[(i, j)],
        });
        Mat::from_fn(big_n, big_n, |i, j| {
            let e = |i, j| if i == j { 1.0 } else { 0.0 };
            if i < n {
                e(i, j) + a * e(i + n, j) + b * jv[(i, j)]
            } else if i < 2 * n {
                jv[(i - n, j)]
            } else {
                e(i, j)
            }
        })
    }

    /// The known reduced load at t₀ (zero unless given here, before the first step): q̈₀ from
    /// the equation of motion with it. The trapezoidal prediction of the first step starts from
    /// q̈₀; BDF1 does not use it.
    pub fn set_initial_load(&mut self, f_kn: &[f64]) -> Result<(), FilterError> {
        let model = &mut self.ekf.model;
        model.check_input(f_kn)?;
        model.set_load(f_kn);
        model.set_acceleration(&self.ekf.x);
        Ok(())
    }

    /// One filter step: predict to t_k with the known reduced load `f_kn` = S_kn u_kn(t_k), then
    /// correct with the measurements `y` (one per measured row).
    pub fn step(&mut self, f_kn: &[f64], y: &[f64]) -> Result<(), FilterError> {
        self.predict(f_kn)?;
        self.correct(f_kn, y)
    }

    /// The prediction half of a step (eq. 8.22–8.24): x⁻, q̈⁻, J and P⁻.
    pub fn predict(&mut self, f_kn: &[f64]) -> Result<(), FilterError> {
        self.ekf.predict(f_kn)
    }

    /// The correction half of a step (eq. 8.25–8.28) with the same known load as the prediction,
    /// then the refresh at p⁺.
    pub fn correct(&mut self, f_kn: &[f64], y: &[f64]) -> Result<(), FilterError> {
        self.ekf.correct(f_kn, y)
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::dynamics::integrators::{LinearSystem, Method, integrate};
    use crate::fe::affine::{Coefficient, CoefficientValues};
    use crate::rom::prom::{AffineFunction, CoefficientInput, PromParameter};
    use faer::linalg::solvers::Solve;

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
            prediction: Prediction::Bdf1,
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

    /// [`setup`] with the trapezoidal prediction.
    fn trapezoidal(x: &[f64]) -> FilterSetup {
        FilterSetup {
            prediction: Prediction::Trapezoidal,
            ..setup(x)
        }
    }

    /// J of eq. 8.16 (with the analytic parameter columns) against central differences of the
    /// exact prediction map x_{k−1} ↦ x_k, BDF1 and trapezoidal (q̈_{k−1} from the equation of
    /// motion at x_{k−1}: its parameter and state dependence is part of the map). The map is
    /// quadratic-free in (q, q̇, u) and smooth in p; steps of 1e-6 relative give truncation
    /// ~1e-12 and round-off ~1e-10 relative to the column: bound 1e-7.
    #[test]
    fn prediction_jacobian_matches_finite_differences() {
        for make in [setup, trapezoidal] {
            jacobian_matches_finite_differences(make, &X, &LOAD);
        }
    }

    /// The same on the chains of 1 and 3 DOFs of [`chain_of`] (the blocks of J start elsewhere
    /// than on the 2-DOF chain), both predictions.
    #[test]
    fn prediction_jacobian_matches_finite_differences_at_other_sizes() {
        for n in [1, 3] {
            for prediction in [Prediction::Bdf1, Prediction::Trapezoidal] {
                let make = |x: &[f64]| FilterSetup {
                    q0: x[..n].to_vec(),
                    v0: x[n..2 * n].to_vec(),
                    u0: vec![x[2 * n]],
                    p: x[2 * n + 1..].to_vec(),
                    prediction,
                    ..chain_of(n, Coordinates::Physical)
                };
                let x: Vec<f64> = (0..n)
                    .map(|i| 1e-3 * (1.0 + i as f64))
                    .chain((0..n).map(|i| 0.1 - 0.05 * i as f64))
                    .chain([4.0, 1.2, 0.9])
                    .collect();
                let load: Vec<f64> = (0..n).map(|i| 3.0 - 2.0 * i as f64).collect();
                jacobian_matches_finite_differences(make, &x, &load);
            }
        }
    }

    fn jacobian_matches_finite_differences(
        make: impl Fn(&[f64]) -> FilterSetup,
        x0: &[f64],
        load: &[f64],
    ) {
        let size = x0.len();
        let mut base = Filter::new(make(x0)).unwrap();
        base.predict(load).unwrap();
        let j = base.transition();
        let prediction = base.ekf.model.setup.prediction;
        assert_eq!((j.nrows(), j.ncols()), (size, size));
        for c in 0..size {
            let h = 1e-6 * x0[c].abs().max(1e-3);
            let predicted = |sign: f64| {
                let mut x = x0.to_vec();
                x[c] += sign * h;
                let mut f = Filter::new(make(&x)).unwrap();
                f.predict(load).unwrap();
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
                .chain((0..size).map(|r| &j[(r, c)]))
                .fold(0.0_f64, |m, v| m.max(v.abs()));
            for r in 0..size {
                assert!(
                    (fd[r] - j[(r, c)]).abs() <= 1e-7 * scale,
                    "{prediction:?}: J[{r},{c}] = {} vs finite difference {}",
                    j[(r, c)],
                    fd[r]
                );
            }
        }
    }

    /// The blockwise prediction ([`propagate`] from Gᵀ and H) equals the dense J P Jᵀ + Q
    /// (eq. 8.24) with J from [`Filter::transition`], after a few steps have filled P (physical
    /// coordinates, where both are in the same coordinates), and leaves P exactly symmetric in
    /// both coordinate systems, after the prediction and after the correction; BDF1 and
    /// trapezoidal (the shear A P Aᵀ before the BDF1-shaped blocks). Bound 1e-12 of max |P|: the
    /// two evaluations differ only in summation order.
    #[test]
    fn covariance_prediction_is_j_p_jt_plus_q_and_exactly_symmetric() {
        for (coordinates, make) in [
            (Coordinates::Physical, setup as fn(&[f64]) -> FilterSetup),
            (Coordinates::Auto, setup),
            (Coordinates::Physical, trapezoidal),
            (Coordinates::Auto, trapezoidal),
        ] {
            let mut unit = make(&X);
            unit.coordinates = coordinates;
            unit.prom.stiffness[0].fill(0.0); // one material: the modal path applies
            let mut filter = Filter::new(unit).unwrap();
            let exactly_symmetric =
                |p: &Mat<f64>| (0..p.nrows()).all(|i| (0..i).all(|j| p[(i, j)] == p[(j, i)]));
            for step in 0..5 {
                let before = filter.ekf.p.clone();
                filter.predict(&LOAD).unwrap();
                assert!(
                    exactly_symmetric(&filter.ekf.p),
                    "{coordinates:?} step {step}: P⁻ not exactly symmetric"
                );
                if coordinates == Coordinates::Physical {
                    let j = filter.transition();
                    let mut dense = &j * &before * j.transpose();
                    (0..dense.nrows()).for_each(|i| dense[(i, i)] += filter.ekf.model.noise(i));
                    let scale = dense.norm_max();
                    assert!(
                        (&dense - &filter.ekf.p).norm_max() <= 1e-12 * scale,
                        "step {step}: {:e} vs {scale:e}",
                        (&dense - &filter.ekf.p).norm_max()
                    );
                }
                let (n, mut y) = (filter.ekf.model.n, vec![0.0; 2]);
                filter.ekf.model.setup.measured.evaluate(
                    &filter.ekf.x[..n],
                    &filter.ekf.x[n..2 * n],
                    &filter.ekf.model.a,
                    &mut y,
                );
                filter.correct(&LOAD, &[y[0] + 1e-6, y[1] + 1e-3]).unwrap();
                assert!(
                    exactly_symmetric(&filter.ekf.p),
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
            let n = filter.ekf.model.n;
            let mut y = vec![0.0; m];
            for step in 0..3 {
                filter.predict(&LOAD).unwrap();
                let before = filter.ekf.p.clone();
                filter.ekf.model.setup.measured.evaluate(
                    &filter.ekf.x[..n],
                    &filter.ekf.x[n..2 * n],
                    &filter.ekf.model.a,
                    &mut y,
                );
                y.iter_mut()
                    .enumerate()
                    .for_each(|(r, y)| *y += 1e-4 * (r as f64 - 1.5));
                filter.correct(&LOAD, &y).unwrap();
                let (jm, big_n) = (filter.measurement_jacobian().clone(), before.nrows());
                let mut s_y = &jm * &before * jm.transpose();
                (0..m).for_each(|r| s_y[(r, r)] += filter.ekf.model.setup.r[r]);
                let gain = &before
                    * jm.transpose()
                    * s_y.partial_piv_lu().solve(Mat::<f64>::identity(m, m));
                let l = Mat::<f64>::identity(big_n, big_n) - &gain * &jm;
                let r = Mat::from_fn(m, m, |i, j| {
                    if i == j {
                        filter.ekf.model.setup.r[i]
                    } else {
                        0.0
                    }
                });
                let dense = &l * &before * l.transpose() + &gain * &r * gain.transpose();
                let (error, scale) = ((&dense - &filter.ekf.p).norm_max(), before.norm_max());
                assert!(
                    error <= 1e-12 * scale,
                    "m = {m}, step {step}: {error:e} vs max |P⁻| {scale:e}"
                );
                assert!(
                    (0..big_n)
                        .all(|i| (0..i).all(|j| filter.ekf.p[(i, j)] == filter.ekf.p[(j, i)])),
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
        let x = base.ekf.x.clone();
        base.ekf.model.measurement_rows(&x, &mut base.ekf.jm);
        let h_of = |x: &[f64]| {
            let f = Filter::new(setup(x)).unwrap();
            let mut y = vec![0.0; 2];
            f.ekf.model.setup.measured.evaluate(
                &f.ekf.x[..2],
                &f.ekf.x[2..4],
                &f.ekf.model.a,
                &mut y,
            );
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
                let scale = fd.abs().max(base.ekf.jm[(r, c)].abs()).max(1e-30);
                assert!(
                    (fd - base.ekf.jm[(r, c)]).abs() <= 1e-7 * scale,
                    "J_m[{r},{c}] = {} vs finite difference {fd}",
                    base.ekf.jm[(r, c)]
                );
            }
        }
    }

    /// With nothing unknown, the prediction is the BDF1 integrator of the transient sequence
    /// (the filter's model is the one that generates SOL TRANSIENT data): same q, q̇, q̈ to
    /// round-off over 200 steps of a sine load.
    #[test]
    fn prediction_equals_the_bdf1_integrator() {
        let load = |t: f64, f: &mut [f64]| {
            f.iter_mut()
                .zip(LOAD)
                .for_each(|(f, l)| *f = l * (40.0 * t).sin())
        };
        prediction_equals_the_integrator(setup, Method::Bdf1, load);
    }

    /// The trapezoidal prediction is generalized-α with ρ∞ = 1 (the trapezoidal rule on a
    /// linear system) under a load linear in time (generalized-α's load at t_k − Δt/2 is then
    /// the average of t_{k−1} and t_k), from q̈₀ with the load at t₀
    /// ([`Filter::set_initial_load`]): same q, q̇, q̈ to round-off over 200 steps.
    #[test]
    fn trapezoidal_prediction_equals_the_generalized_alpha_integrator() {
        let load = |t: f64, f: &mut [f64]| {
            f.iter_mut()
                .zip(LOAD)
                .for_each(|(f, l)| *f = l * (1.0 + 30.0 * t))
        };
        prediction_equals_the_integrator(
            trapezoidal,
            Method::GeneralizedAlpha { rho_inf: 1.0 },
            load,
        );
    }

    fn prediction_equals_the_integrator(
        make: fn(&[f64]) -> FilterSetup,
        method: Method,
        load: fn(f64, &mut [f64]),
    ) {
        for coordinates in [Coordinates::Physical, Coordinates::Auto] {
            let mut s = make(&X);
            s.unknown_params.clear();
            s.q_params.clear();
            s.p0_params.clear();
            s.s_un = Mat::zeros(2, 0);
            s.q_inputs.clear();
            s.p0_inputs.clear();
            s.u0.clear();
            s.coordinates = coordinates;
            let mut filter = Filter::new(s.clone()).unwrap();
            let mut f0 = [0.0; 2];
            load(0.0, &mut f0);
            filter.set_initial_load(&f0).unwrap();
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
            let mut reference = Vec::new();
            integrate(sys, method, s.dt, 200, &s.q0, &s.v0, load, |st| {
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
                        "{method:?}, {coordinates:?}, step {k}"
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
    /// range, as the filterpy cross-check. The same with the trapezoidal prediction on data
    /// from generalized-α with ρ∞ = 1.
    #[test]
    fn modal_path_equals_physical_path() {
        modal_path_equals_physical_path_with(setup, Method::Bdf1);
        modal_path_equals_physical_path_with(
            trapezoidal,
            Method::GeneralizedAlpha { rho_inf: 1.0 },
        );
    }

    fn modal_path_equals_physical_path_with(make: fn(&[f64]) -> FilterSetup, method: Method) {
        let mut truth = make(&[0.0, 0.0, 0.0, 0.0, 2.0, 1.0, 1.0]);
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
        integrate(sys, method, truth.dt, 400, &q0, &v0, full, |st| {
            data.push([st.q[0], st.a[1]])
        })
        .unwrap();
        let run = |coordinates: Coordinates| {
            let mut s = make(&[q0[0], q0[1], v0[0], v0[1], 0.0, 1.2, 0.9]);
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
            println!(
                "{method:?}: {what}: max |physical − modal| = {worst:.2e} (range {range:.2e})"
            );
            assert!(
                worst <= 1e-9 * range,
                "{method:?}: {what}: {worst:e} vs range {range:e}"
            );
        }
        // the estimate converged (the comparison is not between two diverged runs)
        let last = physical.last().unwrap();
        assert!(
            (last[5] - 1.0).abs() < 0.02
                && (last[6] - 1.0).abs() < 0.02
                && (last[4] - 2.0).abs() < 0.1,
            "{method:?}: {last:?}"
        );
        // the final covariance maps back to the physical one
        let scale = p_physical.norm_max();
        assert!((&p_physical - &p_modal).norm_max() <= 1e-9 * scale);
    }

    /// [`chain`]'s parameters on a chain of `n` DOFs with K = E K¹ (no grounded spring, so
    /// the modes diagonalize every part and modal coordinates apply) and M = ρ M¹; a DISP row
    /// on the first DOF, an ACCEL row and the unknown input on the last, initial covariance
    /// p0_state = 1e-10 on q and q̇, 1 on the input, 0.1 and 0.2 on E and ρ.
    fn chain_of(n: usize, coordinates: Coordinates) -> FilterSetup {
        let k1 = Mat::from_fn(n, n, |i, j| match i.abs_diff(j) {
            0 if i + 1 == n => 1e4,
            0 => 2e4,
            1 => -1e4,
            _ => 0.0,
        });
        let m1 = Mat::from_fn(n, n, |i, j| [2.0, 0.1, 0.0][i.abs_diff(j).min(2)]);
        let mut prom = chain();
        prom.stiffness = vec![Mat::zeros(n, n), k1, Mat::zeros(n, n)];
        prom.mass = vec![Mat::zeros(n, n), Mat::zeros(n, n), m1];
        let ends = Mat::from_fn(2, n, |r, c| f64::from(c == r * (n - 1)));
        let kinds = vec!["DISP".into(), "ACCEL".into()];
        FilterSetup {
            prom,
            p: vec![1.2, 0.9],
            unknown_params: vec![0, 1],
            s_un: Mat::from_fn(n, 1, |i, _| f64::from(i + 1 == n)),
            measured: SensorRows::new(vec!["D".into(), "A".into()], kinds, ends).unwrap(),
            r: vec![1e-12, 1e-6],
            dt: 1e-3,
            q_state: 1e-16,
            q_inputs: vec![1e-2],
            q_params: vec![1e-8, 1e-8],
            q0: vec![1e-3; n],
            v0: vec![0.1; n],
            u0: vec![0.0],
            p0_state: 1e-10,
            p0_inputs: vec![1.0],
            p0_params: vec![0.1, 0.2],
            coordinates,
            prediction: Prediction::Bdf1,
        }
    }

    /// [`Filter::covariance`] and [`Filter::variance`] report the covariance of the physical
    /// x* = [q, q̇, u, p] in whichever coordinates the filter runs, on chains of 1 and 3 DOFs
    /// (the q̇, u and p blocks then start elsewhere than on the 2-DOF chain of the other tests).
    /// Before any step that is the setup's diagonal P₀ (the modal run holds T⁻¹ P₀ T⁻ᵀ and maps
    /// it back: round-off of Φ's conditioning, bound 1e-12 of √(P₀ᵢᵢ P₀ⱼⱼ)); after five steps
    /// the modal run's covariance equals the physical run's (the same EKF under a change of
    /// state: round-off amplified by the gains, bound 1e-9 of the q, q̇ block's largest entry as
    /// in `modal_path_equals_physical_path`), and each variance is its covariance's diagonal.
    #[test]
    fn covariance_is_reported_in_physical_coordinates_at_every_size() {
        for n in [1, 3] {
            let size = 2 * n + 3;
            let p0: Vec<f64> = [1e-10]
                .repeat(2 * n)
                .into_iter()
                .chain([1.0, 0.1, 0.2])
                .collect();
            let mut after = Vec::new();
            for coordinates in [Coordinates::Physical, Coordinates::Auto] {
                let mut filter = Filter::new(chain_of(n, coordinates)).unwrap();
                assert_eq!(filter.modal(), coordinates == Coordinates::Auto, "n = {n}");
                let p = filter.covariance();
                assert_eq!((p.nrows(), p.ncols()), (size, size), "n = {n}");
                for i in 0..size {
                    for j in 0..size {
                        let expected = if i == j { p0[i] } else { 0.0 };
                        assert!(
                            (p[(i, j)] - expected).abs() <= 1e-12 * (p0[i] * p0[j]).sqrt(),
                            "n = {n}, {coordinates:?}: P[{i}, {j}] = {:e} vs {expected:e}",
                            p[(i, j)]
                        );
                    }
                    let v = filter.variance(i);
                    assert!(
                        (v - p0[i]).abs() <= 1e-12 * p0[i],
                        "n = {n}: var {i} = {v:e}"
                    );
                }
                for k in 1..=5 {
                    let y = [1e-3 * (1.0 + 0.1 * k as f64), -2.0];
                    filter.step(&vec![0.0; n], &y).unwrap();
                }
                let p = filter.covariance();
                for i in 0..size {
                    let v = filter.variance(i);
                    assert!(
                        (v - p[(i, i)]).abs() <= 1e-12 * p[(i, i)].abs(),
                        "n = {n}, {coordinates:?}: var {i} = {v:e} vs {:e}",
                        p[(i, i)]
                    );
                }
                after.push(p);
            }
            let states = |p: &Mat<f64>| p.as_ref().submatrix(0, 0, 2 * n, 2 * n).to_owned();
            let (physical, modal) = (states(&after[0]), states(&after[1]));
            let scale = physical.norm_max();
            assert!(scale > 0.0);
            let worst = (&physical - &modal).norm_max();
            assert!(worst <= 1e-9 * scale, "n = {n}: {worst:e} vs {scale:e}");
        }
    }

    /// [`Filter::innovation`] is y − h(x⁻) (eq. 8.25): the measurements minus what the sensor
    /// rows read at the prediction, here q⁻ of the first DOF (DISP) and q̈⁻ of the last (ACCEL),
    /// read through [`Filter::state`] and [`Filter::acceleration`] between the prediction and
    /// the correction. Physical coordinates give the same numbers (bound 1e-14 of the
    /// measurement); modal ones read H Φ z instead of H q with q = Φ z (round-off of Φ's
    /// products: 1e-10).
    #[test]
    fn innovation_is_the_measurement_minus_the_predicted_reading() {
        let n = 3;
        for (coordinates, tol) in [(Coordinates::Physical, 1e-14), (Coordinates::Auto, 1e-10)] {
            let mut filter = Filter::new(chain_of(n, coordinates)).unwrap();
            let (load, y) = (vec![1.0, 0.0, -2.0], [3e-3, -5.0]);
            filter.predict(&load).unwrap();
            let reading = [filter.state()[0], filter.acceleration()[n - 1]];
            filter.correct(&load, &y).unwrap();
            let e = filter.innovation();
            assert_eq!(e.len(), 2);
            for r in 0..2 {
                let expected = y[r] - reading[r];
                assert!(
                    (e[r] - expected).abs() <= tol * y[r].abs(),
                    "{coordinates:?}, row {r}: {} vs {expected}",
                    e[r]
                );
            }
            // the reading is not the measurement: the check above is not 0 = 0
            assert!(
                (e[0] / y[0]).abs() > 0.1 && (e[1] / y[1]).abs() > 0.1,
                "{e:?}"
            );
        }
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
    /// largest entry. BDF1 and trapezoidal (S = M + h C + h² K with h = Δt/2).
    #[test]
    fn prediction_with_coupled_parts_equals_the_physical_one() {
        for prediction in [Prediction::Bdf1, Prediction::Trapezoidal] {
            coupled_prediction_equals_the_physical_one(prediction);
        }
    }

    fn coupled_prediction_equals_the_physical_one(prediction: Prediction) {
        let p_b = [1.25, 0.93];
        let mut coupled = Filter::new(FilterSetup {
            prediction,
            ..setup(Coordinates::Rediagonalized(0.1), [1.2, 0.9])
        })
        .unwrap();
        assert!(
            coupled.modal() && coupled.rediagonalizations() == Some(0),
            "the chain couples: re-diagonalized coordinates"
        );
        let (n, np) = (coupled.ekf.model.n, p_b.len());
        let ekf = &mut coupled.ekf;
        ekf.x[2 * n..2 * n + np].copy_from_slice(&p_b);
        ekf.model.refresh(ekf.step, &mut ekf.x, &mut ekf.p).unwrap();
        ekf.model.set_acceleration(&ekf.x);
        assert_eq!(coupled.rediagonalizations(), Some(0), "4 % is under τ");
        let mut physical = Filter::new(FilterSetup {
            prediction,
            ..setup(Coordinates::Physical, p_b)
        })
        .unwrap();
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
        use super::super::drift::{Drift, solve_modal};
        use super::super::modal::{Coupling, OffDiagonal};
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
            prediction: Prediction::Bdf1,
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
            let q: Vec<f64> = (0..5).map(|i| filter.ekf.model.noise(i)).collect();
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
