//! Time integration of the stabilized index-2 (GGL) equations of motion, eq. 2.60, with BDF1
//! (eq. 2.61), BDF2 or generalized-α ([`super::scheme`]), and consistent initial conditions.
//!
//! With the step h, the scheme's predictions (q̂, v̂) and factors (c_q, c_v), the scaled
//! multipliers λ̂ = c_v λ (λ the constraint forces of eq. 2.46) and μ (the GGL multipliers,
//! scaled likewise), one step solves for x = (q, v, λ̂, μ) at t = t_n + h
//!
//! ```text
//! R₁ = q − q̂ − c_q v − Φ_qᵀ μ                        = 0   (q̇ − v = Φ_qᵀ μ)
//! R₂ = M(q) (v − v̂) − c_v f(q, v, t) + Φ_qᵀ λ̂          = 0   (M v̇ + C v + K q + Φ_qᵀ λ = f_e + f_v)
//! R₃ = Φ_q v + Φ_t                                   = 0   (velocity constraints)
//! R₄ = Φ(q, t)                                       = 0   (position constraints)
//! ```
//!
//! (for BDF1 q̂ = q_n, v̂ = v_n, c_q = c_v = h) by Newton's method on the dense KKT matrix (faer
//! LU with partial pivoting)
//!
//! ```text
//! ⎡ I − Σ μᵢ∇²Φᵢ          −c_q I        0      −Φ_qᵀ ⎤
//! ⎢ c_v K̂ + Σ λ̂ᵢ∇²Φᵢ      M + c_v Ĉ     Φ_qᵀ    0    ⎥
//! ⎢ ∂(Φ_q v + Φ_t)/∂q      Φ_q           0      0    ⎥
//! ⎣ Φ_q                    0             0      0    ⎦
//! ```
//!
//! with K̂ = K + the spring-dampers' K ∇ℓ∇ℓᵀ and Ĉ = C − ∂f_v/∂v + their C ∇ℓ∇ℓᵀ; the
//! derivatives of M(q)(v − v̂), f_v and gravity with respect to q (of relative size h² ω²)
//! are left out, so the iteration is a modified Newton method. Its factorization is kept across
//! iterations and steps (while c_q and c_v stay the same) and refreshed when the contraction
//! rate of the corrections exceeds `slow_rate`. Corrections that grow under a matrix just
//! factored at the current iterate mean divergence: the attempt stops there. A step that does
//! not converge in `max_iterations` (after one retry from the predictor with a fresh matrix
//! when the first attempt began with an older one) is an error naming the time, the largest
//! residual entry and the worst position constraint (its joint or drive and |Φ|).
//!
//! The time-stepping family of [`crate::dynamics`] integrates unconstrained second-order
//! residuals in q alone; this step keeps v and the two multiplier sets as unknowns, so it is
//! written here against the same shape (predict, iterate with a reused factorization, report
//! per step).

use super::constraint_set::ConstraintSet;
use super::error::MultibodyError;
use super::scheme::{History, Scheme, StepForm};
use super::system::{DriveSource, Equations, System};
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
}

impl Default for NewtonSettings {
    fn default() -> Self {
        Self {
            tolerance: 1e-10,
            max_iterations: 12,
            slow_rate: 0.3,
            redundancy_tolerance: 1e-9,
            assembly_tolerance: 1e-12,
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
    lu: Option<faer::linalg::solvers::PartialPivLu<f64>>,
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
    matrix: Mat<f64>,
    force: Vec<f64>,
    phi: Vec<f64>,
    phi_t: Vec<f64>,
    rhs: Mat<f64>,
}

impl Workspace {
    fn new(n: usize, m: usize) -> Self {
        Self {
            mass: Mat::zeros(n, n),
            dq: Mat::zeros(n, n),
            dv: Mat::zeros(n, n),
            phi_q: Mat::zeros(m, n),
            velocity_q: Mat::zeros(m, n),
            matrix: Mat::zeros(2 * n + 2 * m, 2 * n + 2 * m),
            force: vec![0.0; n],
            phi: vec![0.0; m],
            phi_t: vec![0.0; m],
            rhs: Mat::zeros(2 * n + 2 * m, 1),
        }
    }
}

fn max_abs(x: &[f64]) -> f64 {
    x.iter().fold(0.0, |a, b| a.max(b.abs()))
}

/// Index and value of the largest |Φᵢ|.
fn worst(phi: &[f64]) -> (usize, f64) {
    phi.iter().enumerate().fold(
        (0, 0.0),
        |(i, a), (j, b)| if b.abs() > a { (j, b.abs()) } else { (i, a) },
    )
}

/// y = Aᵀ x (A m × n, x m).
fn transpose_mul(a: MatRef<'_, f64>, x: &[f64], y: &mut [f64]) {
    y.fill(0.0);
    for i in 0..a.nrows() {
        if x[i] != 0.0 {
            for j in 0..a.ncols() {
                y[j] += a[(i, j)] * x[i];
            }
        }
    }
}

/// Minimum-norm solution of A Δ = b for A (m × n) of full row rank: Δ = Aᵀ (A Aᵀ)⁻¹ b.
fn minimum_norm(
    a: MatRef<'_, f64>,
    b: &[f64],
    out: &mut [f64],
    time: f64,
) -> Result<(), MultibodyError> {
    let m = a.nrows();
    let gram = a * a.transpose();
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
            out[j] += a[(i, j)] * y[(i, 0)];
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
    /// drives included; an error if a row removed as redundant is violated there), projects the initial velocities onto Φ_q v + Φ_t = 0 (the
    /// minimum-norm change of the given ones, so a drive's rate at t₀ sets the velocities of
    /// its mechanism) and, for generalized-α, solves for the consistent accelerations.
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
        assemble(
            &system,
            &equations.constraints,
            &mut q,
            start,
            &settings,
            &mut work,
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
        // velocities: v ← v − Φ_qᵀ (Φ_q Φ_qᵀ)⁻¹ (Φ_q v + Φ_t)
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
        minimum_norm(work.phi_q.as_ref(), &violation, &mut correction, start)?;
        for (x, d) in v.iter_mut().zip(&correction) {
            *x -= d;
        }
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
            lu: None,
            factored_for: (0.0, 0.0),
            work,
            q,
            v,
            equations,
        };
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
        self.history.form(
            self.scheme,
            h,
            &self.q,
            &self.v,
            &self.acceleration,
            &mut self.form,
        );
        if self.factored_for != (self.form.c_q, self.form.c_v) {
            self.lu = None;
        }
        let mut iterations = 0;
        let mut factorizations = 0;
        let fresh_start = self.lu.is_none();
        for attempt in 0..2 {
            if attempt == 1 {
                if fresh_start {
                    break;
                }
                self.lu = None;
            }
            match self.attempt(t, &mut iterations, &mut factorizations)? {
                Some(x) => {
                    let (n, m) = (self.system.size(), self.constraint_count());
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
                    self.equations.constraints.values(
                        &self.system.layout,
                        &self.q,
                        t,
                        &mut self.work.phi,
                    );
                    return Ok(StepReport {
                        time: t,
                        iterations,
                        factorizations,
                        constraint_residual: max_abs(&self.work.phi),
                    });
                }
                None => continue,
            }
        }
        // not converged: report at the last iterate
        let residual = max_abs(&self.work.rhs.col(0).iter().copied().collect::<Vec<_>>());
        let (row, constraint) = worst(&self.work.phi);
        Err(MultibodyError::NotConverged {
            time: t,
            iterations,
            residual,
            worst: self
                .equations
                .constraints
                .labels
                .get(row)
                .cloned()
                .unwrap_or_default(),
            constraint,
        })
    }

    /// One Newton attempt from the predictor; `Some(x)` when converged.
    fn attempt(
        &mut self,
        t: f64,
        iterations: &mut usize,
        factorizations: &mut usize,
    ) -> Result<Option<Vec<f64>>, MultibodyError> {
        let (n, m) = (self.system.size(), self.constraint_count());
        let h = self.step_size;
        let mut x = vec![0.0; 2 * n + 2 * m];
        for i in 0..n {
            x[i] = self.q[i] + h * self.v[i];
            x[n + i] = self.v[i];
        }
        for k in 0..m {
            x[2 * n + k] = self.form.c_v * self.lambda[k];
            x[2 * n + m + k] = self.mu[k];
        }
        let mut previous_error = f64::INFINITY;
        for _ in 0..self.settings.max_iterations {
            *iterations += 1;
            self.residual(&x, t);
            let fresh = self.lu.is_none();
            if fresh {
                self.factor(&x, t)?;
                *factorizations += 1;
            }
            let lu = self.lu.as_ref().expect("factored above");
            lu.solve_in_place(self.work.rhs.as_mut());
            let (q_scale, v_scale) = (1.0 + max_abs(&x[..n]), 1.0 + max_abs(&x[n..2 * n]));
            let mut error: f64 = 0.0;
            for (i, xi) in x.iter_mut().enumerate() {
                let d = -self.work.rhs[(i, 0)];
                if !d.is_finite() {
                    return Err(MultibodyError::Singular {
                        what: "GGL iteration matrix",
                        time: t,
                    });
                }
                *xi += d;
                if i < n {
                    error = error.max(d.abs() / q_scale);
                } else if i < 2 * n {
                    error = error.max(d.abs() / v_scale);
                }
            }
            if error <= self.settings.tolerance {
                return Ok(Some(x));
            }
            if fresh && error > previous_error {
                break;
            }
            if error > self.settings.slow_rate * previous_error {
                self.lu = None;
            }
            previous_error = error;
        }
        self.residual(&x, t);
        Ok(None)
    }

    /// R(x) into `work.rhs`, Φ into `work.phi`.
    fn residual(&mut self, x: &[f64], t: f64) {
        let (n, m) = (self.system.size(), self.constraint_count());
        let StepForm {
            q_hat,
            v_hat,
            c_q,
            c_v,
        } = &self.form;
        let (q, v) = (&x[..n], &x[n..2 * n]);
        let (lam, mu) = (&x[2 * n..2 * n + m], &x[2 * n + m..]);
        let layout = &self.system.layout;
        let c = &self.equations.constraints;
        let w = &mut self.work;
        c.jacobian(layout, q, t, w.phi_q.as_mut());
        c.values(layout, q, t, &mut w.phi);
        c.time_rates(layout, q, t, &mut w.phi_t);
        self.system.mass_matrix(q, w.mass.as_mut());
        self.system
            .applied_forces(&self.equations, q, v, t, &mut w.force, None);
        let mut gq_mu = vec![0.0; n];
        let mut gq_lam = vec![0.0; n];
        transpose_mul(w.phi_q.as_ref(), mu, &mut gq_mu);
        transpose_mul(w.phi_q.as_ref(), lam, &mut gq_lam);
        for i in 0..n {
            w.rhs[(i, 0)] = q[i] - q_hat[i] - c_q * v[i] - gq_mu[i];
            let mut r2 = -c_v * w.force[i] + gq_lam[i];
            for (j, (vj, v0j)) in v.iter().zip(v_hat).enumerate() {
                r2 += w.mass[(i, j)] * (vj - v0j);
            }
            w.rhs[(n + i, 0)] = r2;
        }
        for k in 0..m {
            let mut r3 = w.phi_t[k];
            for (j, vj) in v.iter().enumerate() {
                r3 += w.phi_q[(k, j)] * vj;
            }
            w.rhs[(2 * n + k, 0)] = r3;
            w.rhs[(2 * n + m + k, 0)] = w.phi[k];
        }
    }

    /// Builds and factors the iteration matrix at x (module docs).
    fn factor(&mut self, x: &[f64], t: f64) -> Result<(), MultibodyError> {
        let (n, m) = (self.system.size(), self.constraint_count());
        let (c_q, c_v) = (self.form.c_q, self.form.c_v);
        let (q, v) = (&x[..n], &x[n..2 * n]);
        let (lam, mu) = (&x[2 * n..2 * n + m], &x[2 * n + m..]);
        let layout = &self.system.layout;
        let c = &self.equations.constraints;
        let w = &mut self.work;
        w.dq.fill(0.0);
        w.dv.fill(0.0);
        self.system.applied_forces(
            &self.equations,
            q,
            v,
            t,
            &mut w.force,
            Some((w.dq.as_mut(), w.dv.as_mut(), c_v)),
        );
        self.system.mass_matrix(q, w.mass.as_mut());
        c.jacobian(layout, q, t, w.phi_q.as_mut());
        c.velocity_equation_jacobian(layout, q, v, t, w.velocity_q.as_mut());
        let j = &mut w.matrix;
        j.fill(0.0);
        // R₁ rows
        for i in 0..n {
            j[(i, i)] = 1.0;
            j[(i, n + i)] = -c_q;
        }
        c.add_weighted_hessian(layout, q, t, mu, -1.0, j.as_mut().submatrix_mut(0, 0, n, n));
        // R₂ rows
        c.add_weighted_hessian(layout, q, t, lam, 1.0, j.as_mut().submatrix_mut(n, 0, n, n));
        for a in 0..n {
            for b in 0..n {
                j[(n + a, b)] += w.dq[(a, b)];
                j[(n + a, n + b)] = w.mass[(a, b)] + w.dv[(a, b)];
            }
        }
        for k in 0..m {
            for a in 0..n {
                let g = w.phi_q[(k, a)];
                j[(a, 2 * n + m + k)] = -g;
                j[(n + a, 2 * n + k)] = g;
                j[(2 * n + k, a)] = w.velocity_q[(k, a)];
                j[(2 * n + k, n + a)] = g;
                j[(2 * n + m + k, a)] = g;
            }
        }
        self.lu = Some(j.partial_piv_lu());
        self.factored_for = (c_q, c_v);
        Ok(())
    }
}

/// Kinematic assembly: Newton with minimum-norm corrections Δq = −Φ_qᵀ (Φ_q Φ_qᵀ)⁻¹ Φ until
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
) -> Result<(), MultibodyError> {
    let layout = &system.layout;
    let mut correction = vec![0.0; q.len()];
    for _ in 0..50 {
        constraints.values(layout, q, t, &mut work.phi);
        if max_abs(&work.phi) <= settings.assembly_tolerance {
            return Ok(());
        }
        constraints.jacobian(layout, q, t, work.phi_q.as_mut());
        if minimum_norm(work.phi_q.as_ref(), &work.phi, &mut correction, t).is_err() {
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
