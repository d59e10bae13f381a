//! The AMANDA-EKF's process model of a pFMB ([`ProcessModel`], thesis §9.2.3): x* = (q, v, u,
//! θ) (eq. 9.4; u the unknown inputs' amplitudes, [`super::inputs`]; θ the parameters scaled
//! by their initial guesses, [`super::parameters`]), the
//! prediction by one GGL–BDF1 step of the system at the current θ (eq. 9.15), the transition
//! Jacobian of [`super::transition`] (eq. 9.17) and P⁻ = J P⁺ Jᵀ + Q (eq. 9.18), the
//! measurements of [`super::sensors`] (eq. 9.16, 9.19), and after the correction the AMANDA
//! step of [`super::manifold`] (eq. 9.23), whose residuals the step's [`StepReport`] keeps.
//!
//! The freeze of §9.3.2: the model carries the sensitivity S_k = ∂(q_k, v_k)/∂θ of the prior
//! trajectory (S_k = J_z S_{k−1} + J_θ, from the transition Jacobian's blocks, S_0 = 0); a
//! parameter j whose largest measurement sensitivity max_i |(J_m,z S_k + J_m,θ)_ij| / σ_i
//! (J_m,θ the adaptive strain reference's direct dependence, [`super::reference`]) — the change
//! of a reading, in noise standard deviations, per 100 % change of the parameter — is below
//! the threshold is not updated by that step's correction (its gain row is zero).
//!
//! The observability along the run (§9.3.1): every `every` steps a window of
//! [`super::observability::Window`] starts at the posterior and takes the filter's own
//! augmented transition Jacobians and measurement rows of the steps that follow, so the
//! linearization is the estimate's, at no extra prediction; each finished window is kept with
//! the time it started.

use faer::linalg::matmul::matmul;
use faer::{Accum, Mat, Par};

use super::AmandaSetup;
use super::inputs::Inputs;
use super::manifold::{Manifold, ManifoldReport, ManifoldSettings};
use super::nullspace::Partition;
use super::observability::{Observability, Window};
use super::parameters::Parameters;
use super::reference::Reference;
use super::sensors::{Sensor, measure};
use super::transition::transition;
use crate::estimate::ekf::ProcessModel;
use crate::estimate::filter::FilterError;
use crate::multibody::Ggl;

/// What one estimation step did.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct StepReport {
    pub time: f64,
    /// Newton iterations of the prediction's GGL step.
    pub newton_iterations: usize,
    /// max |Φ| after the prediction.
    pub predicted_residual: f64,
    /// The AMANDA step after the correction (its residuals: the estimate's).
    pub manifold: ManifoldReport,
    /// Times the dependent coordinates have been chosen so far.
    pub partition_choices: usize,
    /// The smallest over the parameters of their largest measurement sensitivity
    /// max_i |∂h_i/∂θ_j| / σ_i (see [`MechanismModel`]); zero without parameters.
    pub sensitivity: f64,
    /// Parameters whose update this step froze (sensitivity below the threshold).
    pub frozen: usize,
}

/// The process model (module docs).
pub struct MechanismModel {
    pub ggl: Ggl,
    pub inputs: Inputs,
    pub parameters: Parameters,
    pub sensors: Vec<Sensor>,
    noise: Vec<f64>,
    /// Diagonal of Q.
    process_noise: Vec<f64>,
    partition: Partition,
    /// z_{k−1} = (q, v) of the last posterior, and q_k⁻ of the last prediction.
    previous: Vec<f64>,
    prior_q: Vec<f64>,
    /// J (augmented) and J P.
    jacobian: Mat<f64>,
    product: Mat<f64>,
    manifold: ManifoldSettings,
    /// ∂(q, v)/∂θ along the prior trajectory: S_k = J_z S_{k−1} + J_θ (eq. 9.8's blocks).
    sensitivity: Mat<f64>,
    /// The sensitivity below which a parameter's update is frozen (§9.3.2), and the frozen
    /// entries of x this step.
    freeze: Option<f64>,
    frozen: Vec<usize>,
    /// The observability along the run: the period (steps), the step at which the next window
    /// starts (or the first after the current one ends), the window being accumulated (with
    /// its start time) and the finished windows (start time, result).
    every: Option<usize>,
    next_window: usize,
    /// The gauges' reference configuration (eq. 9.24, 9.25), if not absolute.
    reference: Option<Reference>,
    window: Option<(f64, Window)>,
    pub observed: Vec<(f64, Observability)>,
    pub report: StepReport,
}

fn mechanism_error(e: impl std::fmt::Display) -> FilterError {
    FilterError::Mechanism(e.to_string())
}

impl MechanismModel {
    /// The model of `ggl`'s system (integrated with BDF1) with `inputs`, `parameters`,
    /// `sensors`, the diagonal `process_noise` of Q (2n + n_u + n_θ), the manifold step, freeze
    /// and observability period of `setup`, and the gauges' `reference`.
    pub fn new(
        ggl: Ggl,
        inputs: Inputs,
        parameters: Parameters,
        sensors: Vec<Sensor>,
        process_noise: Vec<f64>,
        setup: &AmandaSetup,
        reference: Option<Reference>,
    ) -> Result<Self, FilterError> {
        let (n, m) = (ggl.system.size(), ggl.constraint_count());
        let parameters_len = parameters.len();
        let big_n = 2 * n + inputs.len() + parameters_len;
        if process_noise.len() != big_n {
            return Err(FilterError::Shape {
                what: "process noise",
                expected: big_n,
                got: process_noise.len(),
            });
        }
        let mut phi_q = Mat::zeros(m, n);
        ggl.equations
            .constraints
            .jacobian(&ggl.system.layout, &ggl.q, ggl.time, phi_q.as_mut());
        let partition = Partition::choose(phi_q.as_ref()).map_err(mechanism_error)?;
        let mut previous = ggl.q.clone();
        previous.extend(&ggl.v);
        let mut sensors = sensors;
        if let Some(r) = &reference {
            r.apply(&mut sensors, &ggl);
        }
        Ok(Self {
            noise: sensors.iter().map(|s| s.variance).collect(),
            prior_q: ggl.q.clone(),
            ggl,
            inputs,
            parameters,
            sensors,
            process_noise,
            partition,
            previous,
            jacobian: Mat::identity(big_n, big_n),
            product: Mat::zeros(big_n, big_n),
            manifold: setup.manifold,
            sensitivity: Mat::zeros(2 * n, parameters_len),
            freeze: setup.freeze,
            frozen: Vec::new(),
            every: setup.observe_every,
            next_window: 0,
            reference,
            window: None,
            observed: Vec::new(),
            report: StepReport::default(),
        })
    }
}

impl ProcessModel for MechanismModel {
    type Input = ();

    fn size(&self) -> usize {
        2 * self.ggl.system.size() + self.inputs.len() + self.parameters.len()
    }

    fn measurement_noise(&self) -> &[f64] {
        &self.noise
    }

    fn check_input(&self, _: &()) -> Result<(), FilterError> {
        Ok(())
    }

    fn predict(
        &mut self,
        _step: usize,
        _: &(),
        x: &mut [f64],
        p: &mut Mat<f64>,
    ) -> Result<(), FilterError> {
        let n = self.ggl.system.size();
        let (m, z, nu) = (self.ggl.constraint_count(), 2 * n, self.inputs.len());
        self.previous.copy_from_slice(&x[..z]);
        let theta = x[z + nu..].to_vec();
        self.parameters
            .apply(&theta, &mut self.ggl.system)
            .map_err(mechanism_error)?;
        self.inputs.apply(&x[z..z + nu], &mut self.ggl.system);
        self.ggl.q.copy_from_slice(&x[..n]);
        self.ggl.v.copy_from_slice(&x[n..z]);
        let step = self.ggl.step().map_err(mechanism_error)?;
        x[..n].copy_from_slice(&self.ggl.q);
        x[n..z].copy_from_slice(&self.ggl.v);
        self.prior_q.copy_from_slice(&self.ggl.q);
        let ggl = &self.ggl;
        let rates = self
            .parameters
            .rates(&theta, &ggl.system, &ggl.q, &ggl.v)
            .map_err(mechanism_error)?;
        let mut phi_q = Mat::zeros(m, n);
        ggl.equations
            .constraints
            .jacobian(&ggl.system.layout, &ggl.q, ggl.time, phi_q.as_mut());
        let nullspace = self
            .partition
            .nullspace(phi_q.as_ref())
            .map_err(mechanism_error)?;
        let loads = self.inputs.unit_loads(&ggl.system, &ggl.q, ggl.time);
        let j = transition(
            ggl,
            (&self.previous[..n], &self.previous[n..]),
            &nullspace,
            &loads,
            &rates,
        )
        .ok_or_else(|| {
            mechanism_error(format!(
                "at t = {}: the projected step equations are singular",
                ggl.time
            ))
        })?;
        let np = self.parameters.len();
        self.jacobian
            .as_mut()
            .submatrix_mut(0, 0, z, z)
            .copy_from(&j.states);
        self.jacobian
            .as_mut()
            .submatrix_mut(0, z, z, nu)
            .copy_from(&j.inputs);
        self.jacobian
            .as_mut()
            .submatrix_mut(0, z + nu, z, np)
            .copy_from(&j.parameters);
        // S_k = J_z S_{k−1} + J_θ
        let mut next = j.parameters.clone();
        matmul(
            next.as_mut(),
            Accum::Add,
            j.states.as_ref(),
            self.sensitivity.as_ref(),
            1.0,
            Par::Seq,
        );
        self.sensitivity = next;
        // P⁻ = J P Jᵀ + Q (eq. 9.18)
        matmul(
            self.product.as_mut(),
            Accum::Replace,
            self.jacobian.as_ref(),
            p.as_ref(),
            1.0,
            Par::Seq,
        );
        matmul(
            p.as_mut(),
            Accum::Replace,
            self.product.as_ref(),
            self.jacobian.transpose(),
            1.0,
            Par::Seq,
        );
        for (i, q) in self.process_noise.iter().enumerate() {
            p[(i, i)] += q;
        }
        if let Some(r) = &mut self.reference {
            let u = &x[z..z + nu];
            (r.update(&mut self.ggl, &self.inputs, u, &self.parameters, &theta))
                .map_err(|e| mechanism_error(format!("at t = {}: {e}", self.ggl.time)))?;
            r.apply(&mut self.sensors, &self.ggl);
        }
        let ggl = &self.ggl;
        self.report = StepReport {
            time: ggl.time,
            newton_iterations: step.iterations,
            predicted_residual: step.constraint_residual,
            manifold: ManifoldReport::default(),
            partition_choices: self.partition.choices,
            sensitivity: 0.0,
            frozen: 0,
        };
        Ok(())
    }

    fn measure(&mut self, x: &[f64], predicted: &mut [f64], jm: &mut Mat<f64>) {
        let n = self.ggl.system.size();
        measure(
            &self.sensors,
            &self.ggl,
            x,
            &self.previous[n..],
            predicted,
            jm,
        );
        let z = 2 * n;
        if let Some(r) = &self.reference {
            r.add_rows(&self.sensors, &self.ggl, jm, z + self.inputs.len());
        }
        let (rows, np) = (self.sensors.len(), self.parameters.len());
        let largest = |j: usize| {
            (0..rows)
                .map(|i| {
                    let d: f64 = (0..z)
                        .map(|l| jm[(i, l)] * self.sensitivity[(l, j)])
                        .sum::<f64>()
                        + jm[(i, z + self.inputs.len() + j)];
                    d.abs() / self.noise[i].sqrt()
                })
                .fold(0.0, f64::max)
        };
        let sensitivities: Vec<f64> = (0..np).map(largest).collect();
        self.report.sensitivity = sensitivities.iter().copied().fold(f64::INFINITY, f64::min);
        if np == 0 {
            self.report.sensitivity = 0.0;
        }
        self.frozen.clear();
        if let Some(threshold) = self.freeze {
            self.frozen.extend(
                (0..np)
                    .filter(|&j| sensitivities[j] < threshold)
                    .map(|j| z + self.inputs.len() + j),
            );
        }
        self.report.frozen = self.frozen.len();
        if let Some((_, window)) = &mut self.window
            && window.add(&self.jacobian, jm, &self.noise)
        {
            let (time, window) = self.window.take().expect("a window");
            self.observed.push((time, window.finish()));
        }
    }

    fn frozen(&self) -> &[usize] {
        &self.frozen
    }

    fn corrected(
        &mut self,
        step: usize,
        _: &(),
        x: &mut [f64],
        _p: &mut Mat<f64>,
    ) -> Result<(), FilterError> {
        self.correct_onto_constraints(x)?;
        if let Some(every) = self.every
            && self.window.is_none()
            && step >= self.next_window
        {
            self.next_window = step + every;
            let (n, m) = (self.ggl.system.size(), self.ggl.constraint_count());
            let mut phi_q = Mat::zeros(m, n);
            (self.ggl.equations.constraints).jacobian(
                &self.ggl.system.layout,
                &x[..n],
                self.ggl.time,
                phi_q.as_mut(),
            );
            let mut partition = self.partition.clone();
            let unknowns = (self.inputs.len(), self.parameters.len());
            let window = Window::start(
                &phi_q,
                &mut partition,
                unknowns,
                self.sensors.len(),
                usize::MAX,
            )
            .map_err(mechanism_error)?;
            self.window = Some((self.ggl.time, window));
        }
        Ok(())
    }
}

impl MechanismModel {
    /// The AMANDA step of the posterior `x` back onto the constraints.
    fn correct_onto_constraints(&mut self, x: &mut [f64]) -> Result<(), FilterError> {
        let n = self.ggl.system.size();
        let manifold = Manifold {
            layout: &self.ggl.system.layout,
            constraints: &self.ggl.equations.constraints,
            time: self.ggl.time,
            settings: self.manifold,
        };
        let (q, rest) = x.split_at_mut(n);
        self.report.manifold = manifold
            .step(&self.prior_q, q, &mut rest[..n])
            .map_err(|e| {
                mechanism_error(format!(
                    "at t = {}: the AMANDA step left |Φ| = {:e}",
                    self.ggl.time, e.residual
                ))
            })?;
        Ok(())
    }
}
