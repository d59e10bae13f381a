//! System-level virtual sensing on pFMB models: the AMANDA-EKF (thesis ch. 9, §9.2), joint
//! estimation of a mechanism's states and its flexible bodies' parameters, usable from Rust
//! without a deck.
//!
//! - [`parameters`]: the estimated `BODY.PMPAR`s, the bodies' data at them and the exact
//!   parameter rates of the equations of motion;
//! - [`nullspace`]: Φ_q's nullspace by coordinate partitioning (Yen–Petzold, eq. 9.2) and the
//!   derivative of the projection;
//! - [`transition`]: the Jacobian of a GGL–BDF1 step from the projected equations (eq. 9.3,
//!   9.8);
//! - [`sensors`]: strain, marker position and acceleration measurements and their rows;
//! - [`manifold`]: the AMANDA step back onto the constraints (eq. 9.9–9.14);
//! - `model`: the [`crate::estimate::ekf::ProcessModel`] that ties them to the EKF's gain and
//!   Joseph update ([`crate::estimate::ekf::Ekf`], eq. 9.20–9.22).

mod model;

pub mod manifold;
pub mod nullspace;
pub mod parameters;
pub mod sensors;
pub mod transition;

use faer::Mat;

use super::ekf::Ekf;
use super::filter::FilterError;
use crate::multibody::{Ggl, Scheme};
pub use manifold::{ManifoldReport, ManifoldSettings};
use model::MechanismModel;
pub use model::StepReport;
use parameters::Parameters;
use sensors::Sensor;

/// Covariances of the filter: Q and P₀ diagonal per block (eq. 8.29), the parameters' Q from
/// the rule of thumb of eq. 8.31 in the scaled θ = p / a_p: Q_θ = (Δt δ_p)².
#[derive(Debug, Clone, PartialEq)]
pub struct AmandaSetup {
    /// Q of each position and velocity coordinate (model uncertainty).
    pub q_positions: f64,
    pub q_velocities: f64,
    /// δ_p of each parameter (Hz).
    pub parameter_rates: Vec<f64>,
    /// P₀ of each position and velocity coordinate.
    pub p0_positions: f64,
    pub p0_velocities: f64,
    /// P₀ of each parameter, relative (variance of θ).
    pub p0_parameters: Vec<f64>,
    pub manifold: ManifoldSettings,
}

/// The AMANDA-EKF on a pFMB (module docs).
pub struct Amanda {
    ekf: Ekf<MechanismModel>,
}

impl Amanda {
    /// The filter of `ggl`'s system (assembled at its start, integrated with BDF1, its bodies'
    /// data at the initial guesses of `parameters`), estimating `parameters` from `sensors`.
    pub fn new(
        ggl: Ggl,
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
        let np = parameters.len();
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
        let block = |a: f64, b: f64, c: &[f64]| -> Vec<f64> {
            let mut d = vec![a; n];
            d.extend(std::iter::repeat_n(b, n));
            d.extend(c);
            d
        };
        let q_theta: Vec<f64> = (setup.parameter_rates.iter())
            .map(|d| super::covariance::parameter(dt, *d, 1.0))
            .collect();
        let process = block(setup.q_positions, setup.q_velocities, &q_theta);
        let p0 = block(
            setup.p0_positions,
            setup.p0_velocities,
            &setup.p0_parameters,
        );
        let mut x = ggl.q.clone();
        x.extend(&ggl.v);
        x.extend(std::iter::repeat_n(1.0, np));
        let mut ggl = ggl;
        parameters
            .apply(&x[2 * n..], &mut ggl.system)
            .map_err(FilterError::Mechanism)?;
        let model = MechanismModel::new(ggl, parameters, sensors, process, setup.manifold)?;
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

    /// The estimated parameters (physical values) and their standard deviations.
    pub fn parameters(&self) -> (Vec<f64>, Vec<f64>) {
        let z = 2 * self.ekf.model.ggl.system.size();
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

    /// The integrator the filter predicts with (its system at the current estimate).
    pub fn integrator(&self) -> &Ggl {
        &self.ekf.model.ggl
    }
}
