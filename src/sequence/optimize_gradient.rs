//! The gradients of a study's responses with respect to its continuous design variables, by
//! forward sensitivities of the transient ([`crate::multibody::sensitivity`]): what the
//! gradient-based search (`MOOPT GRAD`) steps with.
//!
//! A continuous variable sets one or more `BODY.PMPAR` parameters (`DVMAP`); its rate is the
//! sum of their data rates ∂D/∂p (exact: a pROM body's data are affine in p,
//! [`crate::discretize::prom_body::ParametricBody::derivative`]). The responses follow by the
//! chain rule through their statistic ([`reduce_rate`]); `MASS` from the bodies' mass rates
//! (exact). A `FREQ` response and a parameter a `PTABLE` schedules have no gradient here
//! (an error naming them).

use super::fmb::PreparedFmb;
use super::optimize_study::{Quantity, Study, mass, reduce};
use crate::deck::cards::Statistic;
use crate::discretize::mechanism::values_of;
use crate::multibody::ParameterRate;
use crate::optimize::{Domain, Responses};

/// The responses at a design and their gradients: `gradient[k][i]` = ∂(response k)/∂(variable i)
/// for a continuous variable i, NaN for a discrete one.
#[derive(Debug, Clone, PartialEq)]
pub struct Gradient {
    pub responses: Responses,
    pub gradient: Vec<Vec<f64>>,
    /// The sensitivity iterations of the run, over every step and continuous variable.
    pub iterations: usize,
}

impl Study {
    /// The data rate of continuous variable `i` at `design` (module docs).
    fn variable_rate(
        &self,
        prepared: &PreparedFmb,
        design: &[f64],
        i: usize,
    ) -> Result<ParameterRate, String> {
        let pval = prepared.pval_with(&self.parameters(design));
        let artifacts = self.libraries.artifacts_of(design)?;
        let pfmb = &prepared.pfmb;
        let mut bodies = Vec::new();
        for target in self.targets[i].iter().filter(|t| t.contains('.')) {
            if prepared
                .tables
                .iter()
                .any(|(n, _)| n.eq_ignore_ascii_case(target))
            {
                return Err(format!(
                    "{target} follows a PTABLE: a scheduled parameter has no gradient"
                ));
            }
            let (name, parameter) = target.split_once('.').expect("BODY.PMPAR");
            let body = (pfmb.mechanism.bodies.iter())
                .position(|b| b.name.eq_ignore_ascii_case(name))
                .ok_or_else(|| format!("{target}: no body {name}"))?;
            let data = match artifacts.iter().find(|(b, _)| *b == body) {
                Some((_, artifact)) => &artifact.data,
                None => pfmb.bodies[body]
                    .as_ref()
                    .ok_or_else(|| format!("{target}: body {name} is not flexible"))?,
            };
            let j = (data.prom.parameters.iter())
                .position(|q| q.name.eq_ignore_ascii_case(parameter))
                .ok_or_else(|| format!("{target}: no parameter {parameter} of body {name}"))?;
            let shown = &pfmb.mechanism.bodies[body].name;
            let rate = data.derivative(&values_of(shown, &pval), j, shown)?;
            bodies.push((body, rate));
        }
        Ok(ParameterRate { bodies })
    }

    /// The responses at `design` and their gradients with respect to the continuous
    /// variables (module docs): one transient with the forward sensitivities.
    pub fn gradient(&self, prepared: &PreparedFmb, design: &[f64]) -> Result<Gradient, String> {
        let continuous: Vec<usize> = (self.space.variables.iter().enumerate())
            .filter(|(_, v)| matches!(v.domain, Domain::Continuous { .. }))
            .map(|(i, _)| i)
            .collect();
        let rates = (continuous.iter())
            .map(|&i| self.variable_rate(prepared, design, i))
            .collect::<Result<Vec<_>, _>>()?;
        let mass_rates: Vec<f64> = (rates.iter())
            .map(|r| r.bodies.iter().map(|(_, d)| d.invariants.mass).sum())
            .collect();
        let (flexible, twin) = self.systems(prepared, design)?;
        let (histories, sensitivities) =
            prepared.simulate_sensitivities(&flexible, twin.as_ref(), rates)?;
        let n = self.space.len();
        let mut responses = Vec::new();
        let mut gradient = Vec::new();
        for r in &self.responses {
            let mut row = vec![f64::NAN; n];
            let value = match r.quantity {
                Quantity::Sensor { index, statistic } => {
                    let (t, y) = (&histories.time, &histories.outputs[index]);
                    for (c, &i) in continuous.iter().enumerate() {
                        row[i] = reduce_rate(statistic, t, y, &sensitivities.outputs[c][index]);
                    }
                    reduce(statistic, t, y)
                }
                Quantity::Mass => {
                    for (c, &i) in continuous.iter().enumerate() {
                        row[i] = mass_rates[c];
                    }
                    mass(&flexible)
                }
                Quantity::Frequency { .. } => {
                    return Err(format!(
                        "response {} ({}): a FREQ response has no gradient",
                        r.name, r.source
                    ));
                }
            };
            responses.push(value);
            gradient.push(row);
        }
        Ok(Gradient {
            responses,
            gradient,
            iterations: sensitivities.iterations,
        })
    }
}

/// The derivative of [`reduce`]`(statistic, time, values)` when the values change at the
/// rates `rates`: the mean and the last value are linear; the largest absolute value moves
/// with the value where it is reached (sign × rate there); the RMS as Σ y ẏ / (span RMS),
/// trapezoidal like the RMS.
pub fn reduce_rate(statistic: Statistic, time: &[f64], values: &[f64], rates: &[f64]) -> f64 {
    match statistic {
        Statistic::Mean => reduce(Statistic::Mean, time, rates),
        Statistic::Final => rates.last().copied().unwrap_or(f64::NAN),
        Statistic::Max => {
            let at = (values.iter().enumerate())
                .fold(None, |best: Option<(usize, f64)>, (i, v)| match best {
                    Some((_, b)) if b >= v.abs() => best,
                    _ => Some((i, v.abs())),
                })
                .map(|(i, _)| i);
            at.map_or(f64::NAN, |i| values[i].signum() * rates[i])
        }
        Statistic::Rms => {
            let rms = reduce(Statistic::Rms, time, values);
            let product: Vec<f64> = values.iter().zip(rates).map(|(y, r)| y * r).collect();
            reduce(Statistic::Mean, time, &product) / rms
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn statistic_rates_are_the_derivatives_of_the_statistics() {
        // y(t; a) = a sin t + t on 11 rows: each rate against a central difference in a
        let time: Vec<f64> = (0..11).map(|i| 0.3 * i as f64).collect();
        let y = |a: f64| -> Vec<f64> { time.iter().map(|t| a * t.sin() - t).collect() };
        let rates: Vec<f64> = time.iter().map(|t| t.sin()).collect();
        let (a, da) = (0.7, 1e-6);
        for statistic in [
            Statistic::Mean,
            Statistic::Final,
            Statistic::Max,
            Statistic::Rms,
        ] {
            let exact = reduce_rate(statistic, &time, &y(a), &rates);
            let fd = (reduce(statistic, &time, &y(a + da)) - reduce(statistic, &time, &y(a - da)))
                / (2.0 * da);
            // central difference of smooth functions of a: O(da²) ≈ 1e-12 and round-off
            // 1e-16/1e-6 = 1e-10 relative
            assert!(
                (exact - fd).abs() <= 1e-8 * fd.abs(),
                "{statistic:?}: {exact} vs {fd}"
            );
        }
    }
}
