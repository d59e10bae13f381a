//! System-level virtual sensing on pFMB models: the AMANDA-EKF (thesis ch. 9, §9.2), joint
//! estimation of a mechanism's states and its flexible bodies' parameters, usable from Rust
//! without a deck.
//!
//! - [`inputs`]: the unknown inputs (point forces and moments whose amplitude is estimated)
//!   and their unit generalized forces;
//! - [`parameters`]: the estimated `BODY.PMPAR`s, the bodies' data at them and the exact
//!   parameter rates of the equations of motion;
//! - [`nullspace`]: Φ_q's nullspace by coordinate partitioning (Yen–Petzold, eq. 9.2) and the
//!   derivative of the projection;
//! - [`transition`]: the Jacobian of a GGL–BDF1 step from the projected equations (eq. 9.3,
//!   9.8);
//! - [`sensors`]: strain, marker position and acceleration measurements and their rows;
//! - [`reference`]: the strain gauges' reference configuration, fixed (eq. 9.24) or adaptive
//!   (eq. 9.25);
//! - [`manifold`]: the AMANDA step back onto the constraints (eq. 9.9–9.14);
//! - [`observability`]: the setups that cannot work (§9.3.1) and the numerical observability
//!   of the linearized system over the first steps;
//! - [`ranking`]: candidate sensors ranked by the information they add about the unknowns
//!   along the prior trajectory (greedy, log det of the unknowns' covariance);
//! - `model`: the [`crate::estimate::ekf::ProcessModel`] that ties them to the EKF's gain and
//!   Joseph update ([`crate::estimate::ekf::Ekf`], eq. 9.20–9.22).

mod model;

pub mod inputs;
pub mod manifold;
pub mod nullspace;
pub mod observability;
pub mod parameters;
pub mod ranking;
pub mod reference;
pub mod sensors;
pub mod transition;

use faer::Mat;

use super::ekf::Ekf;
use super::filter::FilterError;
use crate::multibody::{Ggl, Scheme};
use inputs::Inputs;
pub use manifold::{ManifoldReport, ManifoldSettings};
use model::MechanismModel;
pub use model::StepReport;
use parameters::Parameters;
use reference::{Reference, StrainReference};
use sensors::Sensor;

/// The random walk of an unknown input (eq. 8.30): expected frequency ω_u (Hz) and amplitude
/// a_u; Q_u = (Δt ω_u a_u)², P₀ = a_u² (the component filter's choice), u₀ = 0.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InputNoise {
    pub frequency: f64,
    pub amplitude: f64,
}

/// Covariances of the filter: Q and P₀ diagonal per block (eq. 8.29), the inputs' from
/// [`InputNoise`], the parameters' Q from the rule of thumb of eq. 8.31 in the scaled
/// θ = p / a_p: Q_θ = (Δt δ_p)².
#[derive(Debug, Clone, PartialEq)]
pub struct AmandaSetup {
    /// Q of each position and velocity coordinate (model uncertainty).
    pub q_positions: f64,
    pub q_velocities: f64,
    /// The random walk of each unknown input.
    pub inputs: Vec<InputNoise>,
    /// δ_p of each parameter (Hz).
    pub parameter_rates: Vec<f64>,
    /// P₀ of each position and velocity coordinate.
    pub p0_positions: f64,
    pub p0_velocities: f64,
    /// P₀ of each parameter, relative (variance of θ).
    pub p0_parameters: Vec<f64>,
    pub manifold: ManifoldSettings,
    /// The sensitivity below which parameter updates are frozen (§9.3.2, [`StepReport`]'s
    /// `sensitivity`); `None`: never.
    pub freeze: Option<f64>,
    /// The period (steps) of the observability windows along the run
    /// ([`Amanda::observed`]); `None`: none.
    pub observe_every: Option<usize>,
    /// The strain gauges' reference configuration.
    pub strain_reference: StrainReference,
}

/// The AMANDA-EKF on a pFMB (module docs).
pub struct Amanda {
    ekf: Ekf<MechanismModel>,
}

impl Amanda {
    /// The filter of `ggl`'s system (assembled at its start, integrated with BDF1, its bodies'
    /// data at the initial guesses of `parameters`), estimating `inputs` (from zero) and
    /// `parameters` from `sensors`.
    pub fn new(
        ggl: Ggl,
        inputs: Inputs,
        parameters: Parameters,
        sensors: Vec<Sensor>,
        setup: &AmandaSetup,
    ) -> Result<Self, FilterError> {
        if ggl.scheme() != Scheme::Bdf1 {
            return Err(FilterError::Mechanism(format!(
                "the AMANDA-EKF predicts with BDF1 (eq. 9.6), not {:?}",
                ggl.scheme()
            )));
        }
        if let Some(s) = sensors.iter().find(|s| !s.is_supported()) {
            return Err(FilterError::Mechanism(format!(
                "{:?} has no measurement equation in the AMANDA-EKF (strain, position and acceleration do)",
                s.output
            )));
        }
        inputs.check(&ggl.system).map_err(FilterError::Mechanism)?;
        let (nu, np) = (inputs.len(), parameters.len());
        if setup.inputs.len() != nu {
            return Err(FilterError::Shape {
                what: "input random walks",
                expected: nu,
                got: setup.inputs.len(),
            });
        }
        for (what, got) in [
            ("parameter rates δ_p", setup.parameter_rates.len()),
            ("parameter P₀", setup.p0_parameters.len()),
        ] {
            if got != np {
                return Err(FilterError::Shape {
                    what,
                    expected: np,
                    got,
                });
            }
        }
        let n = ggl.system.size();
        let dt = ggl.step_size;
        let block = |a: f64, b: f64, u: &[f64], c: &[f64]| -> Vec<f64> {
            let mut d = vec![a; n];
            d.extend(std::iter::repeat_n(b, n));
            d.extend(u);
            d.extend(c);
            d
        };
        let q_theta: Vec<f64> = (setup.parameter_rates.iter())
            .map(|d| super::covariance::parameter(dt, *d, 1.0))
            .collect();
        let (q_u, p0_u): (Vec<f64>, Vec<f64>) = (setup.inputs.iter())
            .map(|u| {
                (
                    super::covariance::input(dt, u.frequency, u.amplitude),
                    u.amplitude * u.amplitude,
                )
            })
            .unzip();
        let process = block(setup.q_positions, setup.q_velocities, &q_u, &q_theta);
        let p0 = block(
            setup.p0_positions,
            setup.p0_velocities,
            &p0_u,
            &setup.p0_parameters,
        );
        let mut x = ggl.q.clone();
        x.extend(&ggl.v);
        x.extend(std::iter::repeat_n(0.0, nu));
        x.extend(std::iter::repeat_n(1.0, np));
        let mut ggl = ggl;
        parameters
            .apply(&x[2 * n + nu..], &mut ggl.system)
            .map_err(FilterError::Mechanism)?;
        inputs.apply(&x[2 * n..2 * n + nu], &mut ggl.system);
        let reference = Reference::new(
            setup.strain_reference,
            &mut ggl,
            &inputs,
            &x[2 * n..2 * n + nu],
            &parameters,
            &x[2 * n + nu..],
        )
        .map_err(FilterError::Mechanism)?;
        let model =
            MechanismModel::new(ggl, inputs, parameters, sensors, process, setup, reference)?;
        let p = Mat::from_fn(p0.len(), p0.len(), |i, j| if i == j { p0[i] } else { 0.0 });
        Ok(Self {
            ekf: Ekf::new(model, x, p),
        })
    }

    /// One step with the measurements `y` at the next time: prediction, correction and the
    /// AMANDA step.
    pub fn step(&mut self, y: &[f64]) -> Result<StepReport, FilterError> {
        self.ekf.predict(&())?;
        self.ekf.correct(&(), y)?;
        Ok(self.ekf.model.report)
    }

    /// The time of the estimate.
    pub fn time(&self) -> f64 {
        self.ekf.model.ggl.time
    }

    /// The estimated inputs (amplitudes) and their standard deviations.
    pub fn inputs(&self) -> (Vec<f64>, Vec<f64>) {
        let z = 2 * self.ekf.model.ggl.system.size();
        let nu = self.ekf.model.inputs.len();
        let sigma = (z..z + nu).map(|i| self.ekf.p[(i, i)].sqrt()).collect();
        (self.ekf.x[z..z + nu].to_vec(), sigma)
    }

    /// The estimated parameters (physical values) and their standard deviations.
    pub fn parameters(&self) -> (Vec<f64>, Vec<f64>) {
        let z = 2 * self.ekf.model.ggl.system.size() + self.ekf.model.inputs.len();
        let params = &self.ekf.model.parameters;
        let sigma = (params.list.iter().enumerate())
            .map(|(i, p)| p.initial * self.ekf.p[(z + i, z + i)].sqrt())
            .collect();
        (params.values(&self.ekf.x[z..]), sigma)
    }

    /// The estimated coordinates q and velocities v.
    pub fn state(&self) -> (&[f64], &[f64]) {
        let n = self.ekf.model.ggl.system.size();
        (&self.ekf.x[..n], &self.ekf.x[n..2 * n])
    }

    /// The observability windows finished so far along the run (their start time and result;
    /// [`AmandaSetup::observe_every`]).
    pub fn observed(&self) -> &[(f64, observability::Observability)] {
        &self.ekf.model.observed
    }

    /// The integrator the filter predicts with (its system at the current estimate).
    pub fn integrator(&self) -> &Ggl {
        &self.ekf.model.ggl
    }
}

#[cfg(test)]
mod tests {
    use super::parameters::{EstimatedBody, Parameter};
    use super::*;
    use crate::discretize::prom_body::ParametricBody;
    use crate::estimate::filter::tests::chain;
    use crate::estimate::filter::{Coordinates, Filter, FilterSetup, Prediction};
    use crate::estimate::measurement::SensorRows;
    use crate::multibody::{Body, NewtonSettings, Output, System};
    use crate::rom::invariants::{MassInvariants, TranslationRows};

    const DT: f64 = 1e-3;
    const E_TRUE: f64 = 1.2;
    const E_GUESS: f64 = 1.5;
    const Q0: [f64; 2] = [1e-3, -2e-3];

    /// The 2-DOF chain pROM of the component filter's tests as one floating body: its modal
    /// block M(ρ), K(E), C = αM + βK, and a rigid frame (unit masses on the axes, in the
    /// constant affine part) that the modes do not load (every modal mass invariant zero).
    fn chain_body() -> ParametricBody {
        let prom = chain();
        let positions = [
            [0.1, 0.0, 0.0],
            [-0.1, 0.0, 0.0],
            [0.0, 0.1, 0.0],
            [0.0, -0.1, 0.0],
            [0.0, 0.0, 0.1],
            [0.0, 0.0, -0.1],
        ];
        let rows = TranslationRows {
            axes: std::array::from_fn(|_| Mat::zeros(6, 2)),
        };
        let invariants = (0..prom.functions.len())
            .map(|f| MassInvariants::new(&[if f == 0 { 1.0 } else { 0.0 }; 6], &positions, &rows))
            .collect();
        ParametricBody {
            prom,
            invariants,
            interfaces: Vec::new(),
            strain_sensors: Vec::new(),
        }
    }

    /// The body alone (no joint, no gravity), its modes displaced by [`Q0`], at E = `e`.
    fn one_body(model: &ParametricBody, e: f64) -> Ggl {
        let data = model
            .at(&[("E".into(), e)], "chain")
            .expect("chain at E")
            .data;
        let mut system = System::new([0.0; 3]);
        let b = system.add_body(Body::flexible(data), [0.0; 3], [1.0, 0.0, 0.0, 0.0]);
        system.set_initial_modal(b, &Q0);
        Ggl::new(system, DT, 0.0, NewtonSettings::default()).expect("assembly")
    }

    /// A one-body system with no joints, the chain pROM's free vibration: the AMANDA-EKF and
    /// the component EKF (physical coordinates, BDF1) estimate E from the same data — the first
    /// mode's displacement of the run at the true E plus a fixed ±1e-6 pattern — with the same
    /// covariances (θ = E / E_guess: P₀ and Q divided by E_guess²). The modal block is the
    /// component's BDF1 and the frame stays uncoupled, so the estimates agree to the GGL
    /// Newton tolerance: within 1e-7 relative at every step.
    #[test]
    fn one_body_without_joints_reproduces_the_component_estimator() {
        let model = chain_body();
        let mut truth = one_body(&model, E_TRUE);
        let steps = 300;
        let data: Vec<f64> = (1..=steps)
            .map(|k| {
                truth.step().expect("truth step");
                let n = truth.system.size();
                truth.q[n - 2] + 1e-6 * if k % 3 == 0 { 1.0 } else { -0.5 }
            })
            .collect();
        let (q_state, p0_state, r, q_e, p0_e) = (1e-14, 1e-12, 1e-12, 1e-6, 0.1);
        let component = FilterSetup {
            prom: chain(),
            p: vec![E_GUESS, 1.0],
            unknown_params: vec![0],
            s_un: Mat::zeros(2, 0),
            measured: SensorRows::new(
                vec!["D1".into()],
                vec!["DISP".into()],
                Mat::from_fn(1, 2, |_, j| if j == 0 { 1.0 } else { 0.0 }),
            )
            .expect("rows"),
            r: vec![r],
            dt: DT,
            q_state,
            q_inputs: vec![],
            q_params: vec![q_e],
            q0: Q0.to_vec(),
            v0: vec![0.0; 2],
            u0: vec![],
            p0_state,
            p0_inputs: vec![],
            p0_params: vec![p0_e],
            coordinates: Coordinates::Physical,
            prediction: Prediction::Bdf1,
        };
        let mut reference = Filter::new(component).expect("component filter");
        let parameters = Parameters {
            bodies: vec![EstimatedBody {
                body: 0,
                name: "chain".into(),
                model: model.clone(),
                fixed: vec![("RHO".into(), 1.0)],
            }],
            list: vec![Parameter {
                body: 0,
                pmpar: "E".into(),
                initial: E_GUESS,
            }],
        };
        let sensors = vec![Sensor {
            output: Output::Strain {
                body: 0,
                rows: vec![1.0, 0.0],
            },
            reference: 0.0,
            variance: r,
        }];
        let setup = AmandaSetup {
            q_positions: q_state,
            q_velocities: q_state,
            inputs: Vec::new(),
            parameter_rates: vec![q_e.sqrt() / (E_GUESS * DT)],
            p0_positions: p0_state,
            p0_velocities: p0_state,
            p0_parameters: vec![p0_e / (E_GUESS * E_GUESS)],
            manifold: ManifoldSettings::default(),
            freeze: None,
            observe_every: None,
            strain_reference: StrainReference::Absolute,
        };
        let mut amanda = Amanda::new(
            one_body(&model, E_GUESS),
            Inputs::default(),
            parameters,
            sensors,
            &setup,
        )
        .expect("AMANDA");
        let mut worst = 0.0_f64;
        for y in &data {
            reference.step(&[0.0, 0.0], &[*y]).expect("component step");
            amanda.step(&[*y]).expect("AMANDA step");
            let (a, b) = (amanda.parameters().0[0], reference.parameters()[0]);
            worst = worst.max((a - b).abs() / b);
        }
        let last = (amanda.parameters().0[0], reference.parameters()[0]);
        println!(
            "E after {steps} steps: AMANDA {}, component {}; largest relative difference {worst:.1e}",
            last.0, last.1
        );
        assert!(
            (last.1 - E_TRUE).abs() < 0.05 * E_TRUE,
            "the component filter converges"
        );
        assert!(worst < 1e-7, "{worst:e}");
    }

    /// A strain relative to a fixed reference configuration (eq. 9.24) reads zero there and
    /// C_ε (q_f − q_f,ref) elsewhere, with the absolute gauge's row.
    #[test]
    fn relative_strain_reads_zero_at_its_reference() {
        let ggl = one_body(&chain_body(), E_TRUE);
        let n = ggl.system.size();
        let rows = vec![0.5, -2.0];
        let relative = Sensor::relative_strain(0, rows.clone(), &Q0, 1.0);
        let absolute = Sensor {
            output: Output::Strain { body: 0, rows },
            reference: 0.0,
            variance: 1.0,
        };
        let mut x: Vec<f64> = ggl.q.iter().chain(&ggl.v).copied().collect();
        let (mut y, mut jm) = (vec![0.0; 2], Mat::zeros(2, 2 * n));
        let sensors = [relative, absolute];
        sensors::measure(&sensors, &ggl, &x, &ggl.v, &mut y, &mut jm);
        assert_eq!(y[0], 0.0);
        assert!((y[1] - (0.5 * Q0[0] - 2.0 * Q0[1])).abs() < 1e-18);
        x[n - 1] += 1e-3;
        sensors::measure(&sensors, &ggl, &x, &ggl.v, &mut y, &mut jm);
        assert!((y[0] + 2e-3).abs() < 1e-15);
        assert!((0..2 * n).all(|j| jm[(0, j)] == jm[(1, j)]));
    }
}
