//! The sensor ranking of `SOL ESTIMATE` on a mechanism (`AMANDA` field RANK, beyond the
//! thesis: [`crate::estimate::mechanism::ranking`]). Before the run, every selected STRAIN
//! MSENSOR is a candidate gauge (noise σ: the largest of the MEAS on strain gauges); over the
//! first RANK steps of the prior trajectory the candidates are ranked greedily by log det of
//! the unknowns' predicted covariance, and the measured set's prediction is given beside.
//!
//! Written under `/results/<id>/estimate/ranking`: `sensors` (the candidates in ranked order),
//! `log_det` (after each addition), `sigma/<unknown>` (the unknown's predicted standard
//! deviation after each addition: relative to the initial guess for a parameter, in the
//! input's unit for an input), attributes `steps`, `sigma_gauge`, `measured` (the measured
//! gauges), `measured_log_det` and `measured_sigma` (per unknown, in `unknowns` order).

use super::report::sci;
use super::{RunContext, RunError};
use crate::estimate::mechanism::AmandaSetup;
use crate::estimate::mechanism::inputs::Inputs;
use crate::estimate::mechanism::observability::{Window, along_prior};
use crate::estimate::mechanism::parameters::Parameters;
use crate::estimate::mechanism::ranking::{Information, Prediction, Stage};
use crate::estimate::mechanism::sensors::Sensor;
use crate::io::{
    set_attr_f64, set_attr_f64s, set_attr_i64, set_attr_strings, write_f64, write_strings,
};
use crate::multibody::Ggl;

/// A finished ranking (module docs).
#[derive(Debug, Clone)]
pub struct SensorRanking {
    pub steps: usize,
    /// The candidates' MSENSOR names and σ.
    pub candidates: Vec<String>,
    pub sigma: f64,
    pub stages: Vec<Stage>,
    /// The measured candidates and their prediction.
    pub measured: Vec<usize>,
    pub measured_prediction: Option<Prediction>,
    /// The unknowns (parameters, then inputs: the filter's order is inputs, then
    /// parameters; `unknown_order` maps).
    pub unknowns: Vec<String>,
    /// Per unknown of `unknowns`, its column among the filter's (inputs first).
    unknown_order: Vec<usize>,
    /// Per unknown, whether it is a parameter (σ shown in per cent of its initial guess).
    relative: Vec<bool>,
}

/// The ranking of `candidates` (name, sensor with its noise variance) of which `measured`
/// are measured, over `steps` steps of the prior trajectory of `probe` (the filter's
/// integrator at its start), with the filter's prior `setup`.
pub fn rank_sensors(
    probe: Ggl,
    inputs: &Inputs,
    parameters: &Parameters,
    candidates: Vec<(String, Sensor)>,
    measured: Vec<usize>,
    setup: &AmandaSetup,
    steps: usize,
) -> Result<SensorRanking, String> {
    let (nu, np) = (inputs.len(), parameters.len());
    let (names, sensors): (Vec<String>, Vec<Sensor>) = candidates.into_iter().unzip();
    let sigma = sensors.first().map_or(0.0, |s| s.variance.sqrt());
    let window = along_prior(probe, inputs, parameters, &sensors, |phi_q, partition| {
        Window::of_length(phi_q, partition, (nu, np), sensors.len(), steps)
    })?;
    let prior: Vec<f64> = (setup.inputs.iter())
        .map(|u| u.amplitude * u.amplitude)
        .chain(setup.p0_parameters.iter().copied())
        .collect();
    let information = Information::of_window(
        &window,
        sensors.len(),
        setup.p0_positions,
        setup.p0_velocities,
        &prior,
    );
    let unknowns: Vec<String> = parameters
        .names()
        .into_iter()
        .chain(inputs.names())
        .collect();
    Ok(SensorRanking {
        steps,
        candidates: names,
        sigma,
        stages: information.rank(),
        measured_prediction: information.predict(&measured),
        measured,
        unknowns,
        unknown_order: (nu..nu + np).chain(0..nu).collect(),
        relative: (0..np + nu).map(|j| j < np).collect(),
    })
}

impl SensorRanking {
    /// The predicted σ of each unknown (in `unknowns` order) from the filter-ordered `sigma`.
    fn ordered(&self, sigma: &[f64]) -> Vec<f64> {
        self.unknown_order.iter().map(|&j| sigma[j]).collect()
    }

    /// A σ as shown: per cent for a parameter.
    fn shown(&self, j: usize, sigma: f64) -> String {
        if self.relative[j] {
            format!("{} %", sci(100.0 * sigma, 3))
        } else {
            sci(sigma, 3)
        }
    }

    /// The measured set's predicted σ per unknown (NaN when it could not be computed).
    pub fn measured_sigma(&self) -> Vec<f64> {
        self.measured_prediction.as_ref().map_or_else(
            || vec![f64::NAN; self.unknowns.len()],
            |p| self.ordered(&p.sigma),
        )
    }

    /// The console table.
    pub fn lines(&self) -> Vec<String> {
        let mut out = vec![format!(
            "sensor ranking over the first {} step(s) of the prior trajectory ({} candidate gauge(s), σ {}): log det of the unknowns' predicted covariance and their predicted σ",
            self.steps,
            self.candidates.len(),
            sci(self.sigma, 2)
        )];
        let row = |label: String, log_det: f64, sigma: &[f64]| {
            let columns: Vec<String> = (self.ordered(sigma).into_iter().enumerate())
                .map(|(j, s)| format!("{} {}", self.unknowns[j], self.shown(j, s)))
                .collect();
            format!(
                "  {label:<28} log det {:>10.3}  {}",
                log_det,
                columns.join(", ")
            )
        };
        for (k, stage) in self.stages.iter().enumerate() {
            out.push(row(
                format!("{}. + {}", k + 1, self.candidates[stage.candidate]),
                stage.log_det,
                &stage.sigma,
            ));
        }
        let measured: Vec<&str> = self
            .measured
            .iter()
            .map(|&r| self.candidates[r].as_str())
            .collect();
        match &self.measured_prediction {
            Some(p) => out.push(row(
                format!("measured ({})", measured.join(", ")),
                p.log_det,
                &p.sigma,
            )),
            None => out.push(format!(
                "  measured ({}): the information matrix could not be factored",
                measured.join(", ")
            )),
        }
        out
    }

    /// Writes the ranking under `<root>/ranking` (module docs).
    pub fn write(&self, ctx: &RunContext, root: &str) -> Result<(), RunError> {
        let g = ctx.output.group(&format!("{root}/ranking"))?;
        let count = self.stages.len();
        let order: Vec<&str> = (self.stages.iter())
            .map(|s| self.candidates[s.candidate].as_str())
            .collect();
        write_strings(&g, "sensors", &order)?;
        let log_det: Vec<f64> = self.stages.iter().map(|s| s.log_det).collect();
        write_f64(&g, "log_det", &log_det, &[count])?;
        let sigmas = ctx.output.group(&format!("{root}/ranking/sigma"))?;
        for (j, name) in self.unknowns.iter().enumerate() {
            let series: Vec<f64> = (self.stages.iter())
                .map(|s| self.ordered(&s.sigma)[j])
                .collect();
            write_f64(&sigmas, name, &series, &[count])?;
        }
        set_attr_i64(&g, "steps", self.steps as i64)?;
        set_attr_f64(&g, "sigma_gauge", self.sigma)?;
        let measured: Vec<&str> = self
            .measured
            .iter()
            .map(|&r| self.candidates[r].as_str())
            .collect();
        set_attr_strings(&g, "measured", &measured)?;
        let unknowns: Vec<&str> = self.unknowns.iter().map(String::as_str).collect();
        set_attr_strings(&g, "unknowns", &unknowns)?;
        set_attr_f64(
            &g,
            "measured_log_det",
            self.measured_prediction
                .as_ref()
                .map_or(f64::NAN, |p| p.log_det),
        )?;
        set_attr_f64s(&g, "measured_sigma", &self.measured_sigma())?;
        Ok(())
    }
}
