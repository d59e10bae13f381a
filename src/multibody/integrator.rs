//! Time integration of the stabilized index-2 (GGL) equations of motion, eq. 2.60, with BDF1
//! (eq. 2.61), BDF2 or generalized-α ([`super::scheme`]), and consistent initial conditions.
//!
//! With the step h, the scheme's predictions (q̂, v̂) and factors (c_q, c_v), the scaled
//! multipliers λ̂ = c_v λ (λ the constraint forces of eq. 2.46) and μ (the GGL multipliers,
//! scaled likewise), one step solves for x = (q, v, λ̂, μ) at t = t_n + h
//!
//! ```text
//! R₁ = q − q̂ − c_q v − W Φ_qᵀ μ                      = 0   (q̇ − v = W Φ_qᵀ μ)
//! R₂ = M(q) (v − v̂) − c_v f(q, v, t) + Φ_qᵀ λ̂          = 0   (M v̇ + C v + K q + Φ_qᵀ λ = f_e + f_v)
//! R₃ = Φ_q v + Φ_t                                   = 0   (velocity constraints)
//! R₄ = Φ(q, t)                                       = 0   (position constraints)
//! ```
//!
//! (for BDF1 q̂ = q_n, v̂ = v_n, c_q = c_v = h, eq. 2.61; W = I is eq. 2.60 as written; the
//! default keeps I on the frames and gives each body's flexible coordinates the small share
//! ε m (M_ff + c_q c_v K_ff)⁻¹, which does not depend on their units, [`super::correction`]) by
//! Newton's method on the KKT matrix
//!
//! ```text
//! ⎡ I − W Σ μᵢ∇²Φᵢ        −c_q I        0      −W Φ_qᵀ ⎤
//! ⎢ c_v K̂ + Σ λ̂ᵢ∇²Φᵢ      M + c_v Ĉ     Φ_qᵀ    0      ⎥
//! ⎢ ∂(Φ_q v + Φ_t)/∂q      Φ_q           0      0      ⎥
//! ⎣ Φ_q                    0             0      0      ⎦
//! ```
//!
//! with K̂ = K + the spring-dampers' K ∇ℓ∇ℓᵀ and Ĉ = C − ∂f_v/∂v + their C ∇ℓ∇ℓᵀ; the
//! derivatives of M(q)(v − v̂), f_v and gravity with respect to q (of relative size h² ω²)
//! are left out, so the iteration is a modified Newton method: [`crate::dynamics::newton`]'s
//! driver with `JacobianUpdate::Reuse`, shared with the integrators of
//! [`crate::dynamics::nonlinear`]. The matrix is factored by runs of bodies — a body alone,
//! or the consecutive bodies that forces couple (M, K̂ and Ĉ are block diagonal over the
//! runs) — with a Schur complement on the multiplier rows ([`BlockKkt`]; it also leaves out
//! the constraint Hessians' blocks between two runs and the μ-Hessian); when one run would
//! span the system, as one dense LU (sequential, in place, [`DenseLu`]). The
//! factorization is kept across iterations and steps while c_q and c_v stay the same, and
//! refreshed when the contraction rate of the corrections exceeds `slow_rate`. A step ends when
//! its last correction is within the tolerance; with BDF1 and BDF2 also when the error left
//! after it, estimated from the contraction rate ([`NewtonDriver::estimate_remaining_error`]),
//! is. Corrections that grow under a
//! matrix just factored at the current iterate mean divergence: the attempt stops there. A
//! step that does not converge in `max_iterations` (after one retry from the predictor with a
//! fresh matrix when the first attempt began with an older one) is an error naming the time,
//! the largest residual entry, the worst position constraint (its joint or drive and |Φ|) and
//! the constraints whose rows came closest to depending on each other at the last iterate
//! (the weakest combination of Φ_q's rows, [`weakest_combination`]: at a dead centre, the
//! loop's joints); so is a singular iteration matrix.
//!
//! The predictor is q_n + h v_n, v_n and the multipliers of the last step. Extrapolating the
//! accelerations (v = v̂ + c_v q̈_n, or q̈ linear in the last two steps) cuts the iterations of
//! the flexible four-bar by 10–20 % but doubles its factorizations: the predictor's
//! remaining error lies in the links' stiff modes, which a factorization from earlier steps
//! does not contract (docs/fourbar.md, "Speed"). Refactoring at every step's predictor
//! brings the four-bar to 3.9 iterations per step but costs more than it saves; so does
//! leaving the constraint Hessians out of the matrix (cheaper factorizations, more of them).

use super::block_kkt::BlockKkt;
use super::constraint_set::{ConstraintSet, RowSupport};
use super::correction::{CorrectionMetric, CorrectionWeight};
use super::dense_lu::DenseLu;
use super::error::{Dependence, MultibodyError};
use super::redundancy::weakest_combination;
use super::rotations::Rotations;
use super::scheme::{History, Scheme, StepForm};
use super::system::{DriveSource, Equations, System};
use crate::dynamics::newton::{JacobianUpdate, NewtonDriver, NewtonPolicy, StepEquations, max_abs};
use faer::linalg::solvers::Solve;
use faer::{Mat, MatRef};

/// Newton and assembly settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NewtonSettings {
    /// Relative tolerance on the corrections: |Δq| / (1 + |q|) and |Δv| / (1 + |v|).
    pub tolerance: f64,
    /// Iterations per attempt.
    pub max_iterations: usize,
    /// Contraction rate above which the matrix is refactored.
    pub slow_rate: f64,
    /// Relative pivot tolerance of the redundancy test.
    pub redundancy_tolerance: f64,
    /// Tolerance on |Φ| of the kinematic assembly.
    pub assembly_tolerance: f64,
    /// The metric of the GGL position correction ([`super::correction`]).
    pub correction: CorrectionMetric,
}

impl Default for NewtonSettings {
    fn default() -> Self {
        Self {
            tolerance: 1e-10,
            max_iterations: 12,
            slow_rate: 0.3,
            redundancy_tolerance: 1e-9,
            assembly_tolerance: 1e-12,
            correction: CorrectionMetric::StepInertia,
        }
    }
}

/// What one step did.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepReport {
    pub time: f64,
    /// Newton iterations (all attempts).
    pub iterations: usize,
    /// Factorizations of the iteration matrix in this step.
    pub factorizations: usize,
    /// max |Φᵢ(q, t)| at the end of the step.
    pub constraint_residual: f64,
}

/// The GGL integrator and its state (see module docs).
pub struct Ggl {
    pub system: System,
    pub equations: Equations,
    /// Labels of the constraints removed as redundant.
    pub redundant: Vec<String>,
    /// Row of each constraint of `equations` before removal in the kept set (`None`: removed).
    pub active_row: Vec<Option<usize>>,
    pub settings: NewtonSettings,
    pub step_size: f64,
    pub time: f64,
    pub q: Vec<f64>,
    pub v: Vec<f64>,
    /// q̈ = (v − v̂)/c_v of the last step (BDF1: (v − v_previous)/h); at the start zero, or
    /// the consistent accelerations when the scheme needs them.
    pub acceleration: Vec<f64>,
    /// Constraint forces λ (physical), one per kept constraint.
    pub lambda: Vec<f64>,
    mu: Vec<f64>,
    scheme: Scheme,
    history: History,
    form: StepForm,
    /// The weight W of the position correction for `form`.
    weight: CorrectionWeight,
    newton: NewtonDriver,
    /// The iteration matrix and its factors: dense, or by runs of bodies ([`BlockKkt`]).
    lu: DenseLu,
    block: BlockKkt,
    /// Which of the two holds the current factorization.
    factored_by_bodies: bool,
    /// (c_q, c_v) of the factored matrix.
    factored_for: (f64, f64),
    work: Workspace,
}

struct Workspace {
    mass: Mat<f64>,
    dq: Mat<f64>,
    dv: Mat<f64>,
    phi_q: Mat<f64>,
    velocity_q: Mat<f64>,
    force: Vec<f64>,
    phi: Vec<f64>,
    phi_t: Vec<f64>,
    /// Φ_qᵀ μ and Φ_qᵀ λ̂.
    gq_mu: Vec<f64>,
    gq_lam: Vec<f64>,
    /// v − v̂ and M(q) (v − v̂).
    relative: Vec<f64>,
    momentum: Vec<f64>,
    /// The bodies' rotation matrices at the iterate.
    rotations: Rotations,
    /// Where the rows of Φ_q can be nonzero.
    support: RowSupport,
}

impl Workspace {
    fn new(n: usize, m: usize) -> Self {
        Self {
            mass: Mat::zeros(n, n),
            dq: Mat::zeros(n, n),
            dv: Mat::zeros(n, n),
            phi_q: Mat::zeros(m, n),
            velocity_q: Mat::zeros(m, n),
            force: vec![0.0; n],
            phi: vec![0.0; m],
            phi_t: vec![0.0; m],
            gq_mu: vec![0.0; n],
            gq_lam: vec![0.0; n],
            relative: vec![0.0; n],
            momentum: vec![0.0; n],
            rotations: Rotations::default(),
            support: RowSupport::default(),
        }
    }
}

/// Index and value of the largest |Φᵢ|.
fn worst(phi: &[f64]) -> (usize, f64) {
    phi.iter().enumerate().fold(
        (0, 0.0),
        |(i, a), (j, b)| if b.abs() > a { (j, b.abs()) } else { (i, a) },
    )
}

/// Minimum-norm solution of A Δ = b for A (m × n) of full row rank in the metric W⁻¹ of the
/// position correction: Δ = W Aᵀ (A W Aᵀ)⁻¹ b.
fn minimum_norm(
    a: MatRef<'_, f64>,
    b: &[f64],
    out: &mut [f64],
    time: f64,
    weight: &mut CorrectionWeight,
) -> Result<(), MultibodyError> {
    let m = a.nrows();
    let mut weighted = a.transpose().to_owned();
    for k in 0..m {
        weight.apply(weighted.col_as_slice_mut(k));
    }
    let gram = a * &weighted;
    let mut y = Mat::from_fn(m, 1, |i, _| b[i]);
    gram.partial_piv_lu().solve_in_place(y.as_mut());
    if (0..m).any(|i| !y[(i, 0)].is_finite()) {
        return Err(MultibodyError::Singular {
            what: "constraint Jacobian Φ_q Φ_qᵀ",
            time,
        });
    }
    out.fill(0.0);
    for i in 0..m {
        for j in 0..a.ncols() {
            out[j] += weighted[(j, i)] * y[(i, 0)];
        }
    }
    Ok(())
}

impl Ggl {
    /// A BDF1 integrator ([`Ggl::with_scheme`]).
    pub fn new(
        system: System,
        step_size: f64,
        start: f64,
        settings: NewtonSettings,
    ) -> Result<Self, MultibodyError> {
        Self::with_scheme(system, step_size, start, settings, Scheme::Bdf1)
    }

    /// Builds the equations at the system's initial guess, removes redundant constraints,
    /// assembles the configuration at t₀ (Newton with minimum-norm corrections on Φ = 0,
    /// drives included; an error if a row removed as redundant is violated there), projects
    /// the initial velocities onto Φ_q v + Φ_t = 0 (the minimum-norm change of the given ones,
    /// so a drive's rate at t₀ sets the velocities of its mechanism; both norms in the metric
    /// of the position correction, [`super::correction`]) and, for generalized-α, solves for
    /// the consistent accelerations.
    pub fn with_scheme(
        system: System,
        step_size: f64,
        start: f64,
        settings: NewtonSettings,
        scheme: Scheme,
    ) -> Result<Self, MultibodyError> {
        scheme.check()?;
        if !(step_size > 0.0 && step_size.is_finite()) {
            return Err(MultibodyError::Input(format!(
                "time step {step_size} must be positive and finite"
            )));
        }
        let (q0, v0) = system.initial_state();
        let (mut q, mut v) = (q0.to_vec(), v0.to_vec());
        let mut equations = system.equations(&q)?;
        let every_row = equations.constraints.clone();
        let split = equations.constraints.remove_redundant(
            &system.layout,
            &q,
            start,
            settings.redundancy_tolerance,
        );
        let mut active_row = vec![None; split.independent.len() + split.redundant.len()];
        for (k, &i) in split.independent.iter().enumerate() {
            active_row[i] = Some(k);
        }
        let (n, m) = (system.size(), equations.constraints.len());
        let mut work = Workspace::new(n, m);
        work.support = equations.constraints.support(&system.layout);
        // the start's projections in the metric of a BDF1 step of size h
        let mut weight = CorrectionWeight::new(settings.correction);
        weight.form(&system, step_size, step_size)?;
        assemble(
            &system,
            &equations.constraints,
            &mut q,
            start,
            &settings,
            &mut work,
            &mut weight,
        )?;
        // rows judged redundant at the guess must hold at the assembled pose as consequences
        // of the kept ones (to far better than √tol when those hold to tol); one violated
        // means the guess sat at a dead centre (a loop drawn straight) where Φ_q lost rank
        // the mechanism has
        let mut phi = vec![0.0; every_row.len()];
        every_row.values(&system.layout, &q, start, &mut phi);
        if split
            .redundant
            .iter()
            .any(|&i| phi[i].abs() > settings.assembly_tolerance.sqrt())
        {
            return Err(unsatisfied(&every_row, &phi, start, &settings));
        }
        // velocities: v ← v − W Φ_qᵀ (Φ_q W Φ_qᵀ)⁻¹ (Φ_q v + Φ_t)
        let c = &equations.constraints;
        c.jacobian(&system.layout, &q, start, work.phi_q.as_mut());
        c.time_rates(&system.layout, &q, start, &mut work.phi_t);
        let mut violation = work.phi_t.clone();
        for (i, x) in violation.iter_mut().enumerate() {
            *x += v
                .iter()
                .enumerate()
                .map(|(j, vj)| work.phi_q[(i, j)] * vj)
                .sum::<f64>();
        }
        let mut correction = vec![0.0; n];
        minimum_norm(
            work.phi_q.as_ref(),
            &violation,
            &mut correction,
            start,
            &mut weight,
        )?;
        for (x, d) in v.iter_mut().zip(&correction) {
            *x -= d;
        }
        let block = BlockKkt::new(&system.layout, m);
        let mut ggl = Self {
            system,
            redundant: split
                .redundant
                .iter()
                .map(|&i| every_row.labels[i].clone())
                .collect(),
            active_row,
            settings,
            step_size,
            time: start,
            acceleration: vec![0.0; n],
            lambda: vec![0.0; m],
            mu: vec![0.0; m],
            scheme,
            history: History::default(),
            form: StepForm::default(),
            weight,
            newton: NewtonDriver::new(
                2 * n + 2 * m,
                NewtonPolicy {
                    max_iterations: settings.max_iterations,
                    update: JacobianUpdate::Reuse,
                    slow_rate: settings.slow_rate,
                },
            ),
            lu: DenseLu::new(2 * n + 2 * m),
            block,
            factored_by_bodies: false,
            factored_for: (0.0, 0.0),
            work,
            q,
            v,
            equations,
        };
        // the BDF schemes damp what a step's iteration leaves behind; generalized-α with
        // ρ∞ near 1 keeps it, and there the tighter stop keeps the conserved quantities'
        // drift at the scheme's own order
        if matches!(scheme, Scheme::Bdf1 | Scheme::Bdf2) {
            ggl.newton.estimate_remaining_error();
        }
        if scheme.needs_initial_accelerations() {
            ggl.solve_accelerations()?;
        }
        ggl.history = History::start(&ggl.acceleration);
        Ok(ggl)
    }

    /// The time discretization.
    pub fn scheme(&self) -> Scheme {
        self.scheme
    }

    /// Sets `acceleration` and `lambda` to the consistent accelerations and constraint forces
    /// of the current state: M q̈ + Φ_qᵀ λ = f, Φ_q q̈ = γ (the second time derivative of Φ = 0,
    /// [`ConstraintSet::acceleration_rhs`]), one dense KKT solve.
    pub fn solve_accelerations(&mut self) -> Result<(), MultibodyError> {
        let (n, m) = (self.system.size(), self.constraint_count());
        let (layout, c, t) = (&self.system.layout, &self.equations.constraints, self.time);
        let w = &mut self.work;
        self.system.mass_matrix(&self.q, w.mass.as_mut());
        self.system
            .applied_forces(&self.equations, &self.q, &self.v, t, &mut w.force, None);
        c.jacobian(layout, &self.q, t, w.phi_q.as_mut());
        c.acceleration_rhs(layout, &self.q, &self.v, t, &mut w.phi);
        let kkt = Mat::from_fn(n + m, n + m, |i, j| match (i < n, j < n) {
            (true, true) => w.mass[(i, j)],
            (true, false) => w.phi_q[(j - n, i)],
            (false, true) => w.phi_q[(i - n, j)],
            (false, false) => 0.0,
        });
        let mut x = Mat::from_fn(
            n + m,
            1,
            |i, _| {
                if i < n { w.force[i] } else { w.phi[i - n] }
            },
        );
        kkt.partial_piv_lu().solve_in_place(x.as_mut());
        if (0..n + m).any(|i| !x[(i, 0)].is_finite()) {
            return Err(MultibodyError::Singular {
                what: "KKT matrix of the consistent accelerations",
                time: t,
            });
        }
        for i in 0..n {
            self.acceleration[i] = x[(i, 0)];
        }
        for k in 0..m {
            self.lambda[k] = x[(n + k, 0)];
        }
        Ok(())
    }

    /// Number of kept constraints.
    pub fn constraint_count(&self) -> usize {
        self.equations.constraints.len()
    }

    /// The multipliers λ of the rows of a joint (removed rows give 0).
    pub fn joint_multipliers(&self, joint: usize) -> Vec<f64> {
        self.equations.joint_rows[joint]
            .clone()
            .map(|i| self.active_row[i].map_or(0.0, |k| self.lambda[k]))
            .collect()
    }

    /// The generalized force a drive applies along its joint coordinate (torque or force).
    pub fn drive_effort(&self, drive: usize) -> f64 {
        match self.equations.drive_sources[drive] {
            // Φ = sin(θ − θ_d) (or s − s_d) enters as Φ_qᵀ λ on the left: the drive applies −λ
            DriveSource::Row(row) => self.active_row[row].map_or(0.0, |k| -self.lambda[k]),
            DriveSource::Spring(i) => {
                let spring = &self.equations.springs[i];
                let mut gradient = vec![0.0; self.system.size()];
                let mut force = vec![0.0; self.system.size()];
                spring.apply(
                    &self.system.layout,
                    &self.q,
                    &self.v,
                    self.time,
                    &mut gradient,
                    &mut force,
                    None,
                )
            }
        }
    }

    /// Advances one step of size h.
    pub fn step(&mut self) -> Result<StepReport, MultibodyError> {
        let t = self.time + self.step_size;
        let h = self.step_size;
        self.system.apply_schedules(t);
        self.history.form(
            self.scheme,
            h,
            &self.q,
            &self.v,
            &self.acceleration,
            &mut self.form,
        );
        self.weight
            .form(&self.system, self.form.c_q, self.form.c_v)?;
        if self.factored_for != (self.form.c_q, self.form.c_v) {
            self.newton.invalidate();
        }
        self.predict();
        let solved = self.with_step_equations(t, None, |equations, newton| {
            match newton.solve(equations) {
                Err(MultibodyError::Singular { .. }) => {
                    // the last iterate is the one whose matrix could not be solved with
                    let mut r = vec![0.0; newton.solution().len()];
                    equations.residual(newton.solution(), &mut r)?;
                    Ok(Err(max_abs(&r)))
                }
                other => other.map(Ok),
            }
        })?;
        let outcome = match solved {
            Ok(outcome) => outcome,
            Err(residual) => {
                let (row, constraint) = worst(&self.work.phi);
                return Err(MultibodyError::SingularStep {
                    time: t,
                    residual,
                    worst: self.row_label(row),
                    constraint,
                    dependent: self.dependence(t),
                });
            }
        };
        if !outcome.converged {
            // the driver left the residual of the last iterate (and its Φ) behind
            let (row, constraint) = worst(&self.work.phi);
            return Err(MultibodyError::NotConverged {
                time: t,
                iterations: outcome.stats.iterations,
                residual: outcome.stats.residual,
                worst: self.row_label(row),
                constraint,
                dependent: self.dependence(t),
            });
        }
        let (n, m) = (self.system.size(), self.constraint_count());
        let x = self.newton.solution();
        let c_v = self.form.c_v;
        for i in 0..n {
            self.acceleration[i] = (x[n + i] - self.form.v_hat[i]) / c_v;
        }
        self.history
            .advance(self.scheme, h, &self.q, &self.v, &x[n..2 * n]);
        self.q.copy_from_slice(&x[..n]);
        self.v.copy_from_slice(&x[n..2 * n]);
        for k in 0..m {
            self.lambda[k] = x[2 * n + k] / c_v;
            self.mu[k] = x[2 * n + m + k];
        }
        self.time = t;
        self.equations
            .constraints
            .values(&self.system.layout, &self.q, t, &mut self.work.phi);
        Ok(StepReport {
            time: t,
            iterations: outcome.stats.iterations,
            factorizations: outcome.stats.factorizations,
            constraint_residual: max_abs(&self.work.phi),
        })
    }

    /// Runs `f` on the equations of a step ending at t (with the step form `form`, or the
    /// integrator's) and the Newton driver.
    fn with_step_equations<T>(
        &mut self,
        t: f64,
        form: Option<&StepForm>,
        f: impl FnOnce(&mut GglStep<'_>, &mut NewtonDriver) -> T,
    ) -> T {
        let mut equations = GglStep {
            system: &self.system,
            equations: &self.equations,
            form: form.unwrap_or(&self.form),
            weight: &mut self.weight,
            work: &mut self.work,
            lu: &mut self.lu,
            block: &mut self.block,
            factored_by_bodies: &mut self.factored_by_bodies,
            factored_for: &mut self.factored_for,
            t,
            tolerance: self.settings.tolerance,
        };
        f(&mut equations, &mut self.newton)
    }

    /// The unknowns x = (q, v, λ̂, μ) of the last step and its step form: what the forward
    /// sensitivities differentiate ([`super::sensitivity`]).
    pub(super) fn last_step(&self) -> (Vec<f64>, &StepForm) {
        let c_v = self.form.c_v;
        let x = (self.q.iter().chain(&self.v).copied())
            .chain(self.lambda.iter().map(|l| c_v * l))
            .chain(self.mu.iter().copied())
            .collect();
        (x, &self.form)
    }

    /// The residual R(x) of the last step's equations (at the integrator's time) with the
    /// step form `form` in place of the step's, and Φ_q at x into `phi_q` (m × n).
    pub(super) fn step_residual(
        &mut self,
        x: &[f64],
        form: &StepForm,
        r: &mut [f64],
        phi_q: Option<&mut Mat<f64>>,
    ) -> Result<(), MultibodyError> {
        let t = self.time;
        self.with_step_equations(t, Some(form), |equations, _| {
            equations.residual(x, r)?;
            if let Some(out) = phi_q {
                out.copy_from(&equations.work.phi_q);
            }
            Ok(())
        })
    }

    /// r ← J̃⁻¹ r with the factored iteration matrix of the last step.
    pub(super) fn iteration_solve(&mut self, r: &mut [f64]) -> Result<(), MultibodyError> {
        let t = self.time;
        self.with_step_equations(t, None, |equations, _| equations.solve(r))
    }

    /// The weight of the position correction for the last step's form.
    pub(super) fn correction_weight(&mut self) -> &mut CorrectionWeight {
        &mut self.weight
    }

    /// The label of kept constraint row `row`.
    fn row_label(&self, row: usize) -> String {
        self.equations
            .constraints
            .labels
            .get(row)
            .cloned()
            .unwrap_or_default()
    }

    /// The constraints whose rows come closest to depending on each other at the Newton
    /// driver's last iterate, at time t: each joint named once, drives and normalizations by
    /// their labels.
    fn dependence(&mut self, t: f64) -> Dependence {
        let n = self.system.size();
        let q = &self.newton.solution()[..n];
        self.equations
            .constraints
            .jacobian(&self.system.layout, q, t, self.work.phi_q.as_mut());
        let weakest = weakest_combination(self.work.phi_q.as_ref());
        let mut constraints: Vec<String> = Vec::new();
        for k in weakest.rows {
            let full = self.active_row.iter().position(|&a| a == Some(k));
            let joint = full.and_then(|i| {
                self.equations
                    .joint_rows
                    .iter()
                    .position(|rows| rows.contains(&i))
            });
            let name = match joint {
                Some(j) => format!("joint {j} ({:?})", self.system.joints[j].kind),
                None => self.row_label(k),
            };
            if !constraints.contains(&name) {
                constraints.push(name);
            }
        }
        Dependence {
            ratio: weakest.ratio,
            constraints,
        }
    }

    /// The predictor of the step (module docs) into the Newton driver.
    fn predict(&mut self) {
        let (n, m) = (self.system.size(), self.constraint_count());
        let h = self.step_size;
        let x = self.newton.predictor_mut();
        for i in 0..n {
            x[i] = self.q[i] + h * self.v[i];
            x[n + i] = self.v[i];
        }
        for k in 0..m {
            x[2 * n + k] = self.form.c_v * self.lambda[k];
            x[2 * n + m + k] = self.mu[k];
        }
    }

    /// The state a rejected step of [`super::step_control`] returns to.
    pub fn checkpoint(&self) -> Checkpoint {
        Checkpoint {
            time: self.time,
            state: [&self.q, &self.v, &self.acceleration, &self.lambda, &self.mu]
                .map(|x| x.to_vec()),
            history: self.history.clone(),
        }
    }

    /// Returns to a [`Ggl::checkpoint`].
    pub fn restore(&mut self, c: &Checkpoint) {
        self.time = c.time;
        let [q, v, a, lambda, mu] = &c.state;
        self.q.copy_from_slice(q);
        self.v.copy_from_slice(v);
        self.acceleration.copy_from_slice(a);
        self.lambda.copy_from_slice(lambda);
        self.mu.copy_from_slice(mu);
        self.history = c.history.clone();
    }

    /// Prepares error-controlled steps: the consistent accelerations at the current state
    /// (the local error estimate starts from them) and BDF2's variable-step coefficients.
    pub fn vary_steps(&mut self) -> Result<(), MultibodyError> {
        self.solve_accelerations()?;
        self.history.vary_steps();
        Ok(())
    }
}

/// Time, (q, v, q̈, λ, μ) and the scheme's history of a [`Ggl`].
pub struct Checkpoint {
    time: f64,
    state: [Vec<f64>; 5],
    history: History,
}

/// The equations of one GGL step at t in x = (q, v, λ̂, μ) (module docs).
struct GglStep<'a> {
    system: &'a System,
    equations: &'a Equations,
    form: &'a StepForm,
    weight: &'a mut CorrectionWeight,
    work: &'a mut Workspace,
    lu: &'a mut DenseLu,
    block: &'a mut BlockKkt,
    factored_by_bodies: &'a mut bool,
    factored_for: &'a mut (f64, f64),
    t: f64,
    /// Relative tolerance on the corrections of q and v.
    tolerance: f64,
}

impl StepEquations for GglStep<'_> {
    type Error = MultibodyError;

    /// R(x) into `r`, Φ into `work.phi`.
    fn residual(&mut self, x: &[f64], r: &mut [f64]) -> Result<(), MultibodyError> {
        let (n, m) = (self.system.size(), self.equations.constraints.len());
        let StepForm {
            q_hat,
            v_hat,
            c_q,
            c_v,
        } = self.form;
        let (q, v) = (&x[..n], &x[n..2 * n]);
        let (lam, mu) = (&x[2 * n..2 * n + m], &x[2 * n + m..]);
        let (layout, t) = (&self.system.layout, self.t);
        let c = &self.equations.constraints;
        let w = &mut *self.work;
        c.evaluate(
            layout,
            q,
            t,
            &mut w.rotations,
            &mut w.phi,
            &mut w.phi_t,
            w.phi_q.as_mut(),
        );
        for i in 0..n {
            w.relative[i] = v[i] - v_hat[i];
        }
        self.system.forces_and_momentum(
            self.equations,
            q,
            v,
            t,
            &mut w.force,
            Some((&w.relative, &mut w.momentum)),
            None,
        );
        w.support.transpose_mul(w.phi_q.as_ref(), mu, &mut w.gq_mu);
        self.weight.apply(&mut w.gq_mu);
        w.support
            .transpose_mul(w.phi_q.as_ref(), lam, &mut w.gq_lam);
        for i in 0..n {
            r[i] = q[i] - q_hat[i] - c_q * v[i] - w.gq_mu[i];
            r[n + i] = w.momentum[i] - c_v * w.force[i] + w.gq_lam[i];
        }
        let (r3, r4) = r[2 * n..].split_at_mut(m);
        r3.copy_from_slice(&w.phi_t);
        w.support.mul_add(w.phi_q.as_ref(), v, r3);
        r4.copy_from_slice(&w.phi);
        Ok(())
    }

    /// Builds and factors the iteration matrix at x (module docs).
    fn factor(&mut self, x: &[f64]) -> Result<(), MultibodyError> {
        let (n, m) = (self.system.size(), self.equations.constraints.len());
        let (c_q, c_v) = (self.form.c_q, self.form.c_v);
        let (q, v) = (&x[..n], &x[n..2 * n]);
        let (lam, mu) = (&x[2 * n..2 * n + m], &x[2 * n + m..]);
        let (layout, t) = (&self.system.layout, self.t);
        let c = &self.equations.constraints;
        let w = &mut *self.work;
        w.dq.fill(0.0);
        w.dv.fill(0.0);
        self.system.applied_forces(
            self.equations,
            q,
            v,
            t,
            &mut w.force,
            Some((w.dq.as_mut(), w.dv.as_mut(), c_v)),
        );
        self.system.mass_matrix(q, w.mass.as_mut());
        c.jacobian(layout, q, t, w.phi_q.as_mut());
        *self.factored_for = (c_q, c_v);
        *self.factored_by_bodies = self.block.applies(&[w.dq.as_ref(), w.dv.as_ref()]);
        if *self.factored_by_bodies {
            // P = c_v K̂ + Σ λ̂ᵢ∇²Φᵢ and A₀ = M + c_v Ĉ
            c.velocity_jacobian_and_weighted_hessian(
                layout,
                q,
                v,
                t,
                lam,
                1.0,
                w.velocity_q.as_mut(),
                w.dq.as_mut(),
            );
            for b in 0..n {
                for a in 0..n {
                    w.dv[(a, b)] += w.mass[(a, b)];
                }
            }
            self.block.factor(
                w.dv.as_ref(),
                w.dq.as_ref(),
                w.phi_q.as_ref(),
                w.velocity_q.as_ref(),
                c_q,
                self.weight,
            );
            return Ok(());
        }
        let mut j = self.lu.matrix_mut();
        j.fill(0.0);
        // R₁ rows
        for i in 0..n {
            j[(i, i)] = 1.0;
            j[(i, n + i)] = -c_q;
        }
        c.add_weighted_hessian(layout, q, t, mu, -1.0, j.as_mut().submatrix_mut(0, 0, n, n));
        // I − W Σ μᵢ∇²Φᵢ and −W Φ_qᵀ, column by column
        let mut column = vec![0.0; n];
        for b in 0..n {
            for (a, x) in column.iter_mut().enumerate() {
                *x = j[(a, b)];
            }
            self.weight.apply_beside_identity(b, &mut column);
            for (a, x) in column.iter().enumerate() {
                j[(a, b)] = *x;
            }
        }
        for k in 0..m {
            for (a, x) in column.iter_mut().enumerate() {
                *x = -w.phi_q[(k, a)];
            }
            self.weight.apply(&mut column);
            for (a, x) in column.iter().enumerate() {
                j[(a, 2 * n + m + k)] = *x;
            }
        }
        // R₂ rows
        c.velocity_jacobian_and_weighted_hessian(
            layout,
            q,
            v,
            t,
            lam,
            1.0,
            w.velocity_q.as_mut(),
            j.as_mut().submatrix_mut(n, 0, n, n),
        );
        for a in 0..n {
            for b in 0..n {
                j[(n + a, b)] += w.dq[(a, b)];
                j[(n + a, n + b)] = w.mass[(a, b)] + w.dv[(a, b)];
            }
        }
        for k in 0..m {
            for a in 0..n {
                let g = w.phi_q[(k, a)];
                j[(n + a, 2 * n + k)] = g;
                j[(2 * n + k, a)] = w.velocity_q[(k, a)];
                j[(2 * n + k, n + a)] = g;
                j[(2 * n + m + k, a)] = g;
            }
        }
        self.lu.factor();
        Ok(())
    }

    fn solve(&mut self, r: &mut [f64]) -> Result<(), MultibodyError> {
        if *self.factored_by_bodies {
            self.block.solve(r);
        } else {
            self.lu.solve(r);
        }
        if r.iter().any(|d| !d.is_finite()) {
            return Err(MultibodyError::Singular {
                what: "GGL iteration matrix",
                time: self.t,
            });
        }
        Ok(())
    }

    /// max(|Δq| / (1 + |q|), |Δv| / (1 + |v|)) / tolerance.
    fn correction_size(&self, x: &[f64], dx: &[f64]) -> f64 {
        let n = self.system.size();
        let q = max_abs(&dx[..n]) / (1.0 + max_abs(&x[..n]));
        let v = max_abs(&dx[n..2 * n]) / (1.0 + max_abs(&x[n..2 * n]));
        q.max(v) / self.tolerance
    }
}

/// Kinematic assembly: Newton with minimum-norm corrections Δq = −W Φ_qᵀ (Φ_q W Φ_qᵀ)⁻¹ Φ
/// (W the weight of the position correction: the frames take what they can) until
/// |Φ| ≤ the assembly tolerance. A loop that cannot close stops on a singular Φ_q Φ_qᵀ (the
/// closest configuration is a dead centre) or after 50 iterations; either way the error
/// lists every constraint still violated.
fn assemble(
    system: &System,
    constraints: &ConstraintSet,
    q: &mut [f64],
    t: f64,
    settings: &NewtonSettings,
    work: &mut Workspace,
    weight: &mut CorrectionWeight,
) -> Result<(), MultibodyError> {
    let layout = &system.layout;
    let mut correction = vec![0.0; q.len()];
    for _ in 0..50 {
        constraints.values(layout, q, t, &mut work.phi);
        if max_abs(&work.phi) <= settings.assembly_tolerance {
            return Ok(());
        }
        constraints.jacobian(layout, q, t, work.phi_q.as_mut());
        if minimum_norm(work.phi_q.as_ref(), &work.phi, &mut correction, t, weight).is_err() {
            break;
        }
        for (x, d) in q.iter_mut().zip(&correction) {
            *x -= d;
        }
    }
    constraints.values(layout, q, t, &mut work.phi);
    Err(unsatisfied(constraints, &work.phi, t, settings))
}

/// The assembly error: the worst row and every row above the assembly tolerance, largest
/// first.
fn unsatisfied(
    constraints: &ConstraintSet,
    phi: &[f64],
    t: f64,
    settings: &NewtonSettings,
) -> MultibodyError {
    let (row, residual) = worst(phi);
    let mut violated: Vec<(usize, f64)> = phi
        .iter()
        .enumerate()
        .filter(|(_, x)| x.abs() > settings.assembly_tolerance)
        .map(|(i, x)| (i, x.abs()))
        .collect();
    violated.sort_by(|a, b| b.1.total_cmp(&a.1));
    MultibodyError::Assembly {
        time: t,
        residual,
        worst: constraints.labels.get(row).cloned().unwrap_or_default(),
        violated: violated
            .iter()
            .map(|&(i, x)| format!("{} (|Φ| = {x:.3e})", constraints.labels[i]))
            .collect(),
    }
}
