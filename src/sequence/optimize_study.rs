//! The study a `SOL OPTIMIZE` deck describes, checked against its mechanism before any run:
//! the design variables (`DESVAR`, with a `DDVAL` discrete) and the `BODY.PMPAR` parameters
//! each sets (`DVMAP`), the responses (`DOBJ`, `DCONSTR`: an MSENSOR history reduced over
//! time), the objectives and constraints over them, and the search (`MOOPT`).
//!
//! Refused, each at its card and field: a DESVAR no DVMAP maps, a DVMAP onto a missing DESVAR
//! or onto a name that is no `BODY.PMPAR` of the mechanism, bounds (or discrete values)
//! outside the box the parameter's pROM was built for (the pROM would extrapolate), a response
//! on an MSENSOR the mechanism does not have or the subcase does not select, no DOBJ, no or
//! several MOOPT, a GRID larger than its NEVAL.

use super::fmb::PreparedFmb;
use crate::deck::cards::{BulkData, Ddval, Desvar, Moopt, ResponseSource, SearchMethod, Statistic};
use crate::deck::error::{DeckError, Loc};
use crate::discretize::pfmb::Pfmb;
use crate::optimize::grid::grid_size;
use crate::optimize::{
    Constraint, DesignSpace, Domain, EvalError, Objective, Responses, Scoring, Sense, Variable,
};

/// One response: an MSENSOR's history reduced by a statistic.
#[derive(Debug, Clone, PartialEq)]
pub struct Response {
    /// The DOBJ's or DCONSTR's NAME.
    pub name: String,
    /// Index into the prepared run's sensors.
    pub sensor: usize,
    pub statistic: Statistic,
}

/// A checked study.
#[derive(Debug, Clone)]
pub struct Study {
    pub space: DesignSpace,
    /// Per variable: the `BODY.PMPAR` parameters it sets.
    pub targets: Vec<Vec<String>>,
    /// The DOBJs' responses, then the DCONSTRs'.
    pub responses: Vec<Response>,
    pub scoring: Scoring,
    pub search: Moopt,
}

/// An error at `loc` on `card`, field `field` (number and name).
fn at(loc: &Loc, card: String, field: &str, message: String) -> String {
    let mut e = DeckError::at(loc, message).on_card(card);
    e.field = Some(field.to_string());
    e.to_string()
}

/// The box `[low, high]` of parameter `target` (`BODY.PMPAR`) of the mechanism's pROMs.
fn parameter_box(pfmb: &Pfmb, target: &str) -> Option<(f64, f64)> {
    let (body, parameter) = target.split_once('.')?;
    pfmb.flexible()
        .find(|(b, _)| b.eq_ignore_ascii_case(body))?
        .1
        .prom
        .parameters
        .iter()
        .find(|q| q.name.eq_ignore_ascii_case(parameter))
        .map(|q| (q.low, q.high))
}

/// The values a DESVAR takes: its DDVAL's, or its bounds.
fn variable(desvar: &Desvar, ddvals: &[Ddval]) -> Variable {
    match desvar
        .ddval
        .and_then(|id| ddvals.iter().find(|d| d.id == id))
    {
        Some(set) => Variable::discrete(&desvar.label, &set.values),
        None => Variable::continuous(&desvar.label, desvar.xlb, desvar.xub),
    }
}

/// Checks that every value `variable` takes lies in the box of `target`; the message names
/// the DESVAR's field at fault.
fn within_box(desvar: &Desvar, v: &Variable, target: &str, (low, high): (f64, f64)) -> Vec<String> {
    let card = format!("DESVAR {}", desvar.id);
    let outside = |x: f64| x < low || x > high;
    let shown = format!("the box [{low:e}, {high:e}] of {target} (the pROM would extrapolate)");
    match &v.domain {
        Domain::Continuous {
            low: xlb,
            high: xub,
        } => [
            (*xlb, "field 5 (XLB)", "XLB"),
            (*xub, "field 6 (XUB)", "XUB"),
        ]
        .into_iter()
        .filter(|(x, _, _)| outside(*x))
        .map(|(x, field, name)| {
            at(
                &desvar.loc,
                card.clone(),
                field,
                format!("{name} = {x:e} is outside {shown}"),
            )
        })
        .collect(),
        Domain::Discrete { values } => values
            .iter()
            .filter(|x| outside(**x))
            .map(|x| {
                at(
                    &desvar.loc,
                    card.clone(),
                    "field 8 (DDVAL)",
                    format!("the discrete value {x:e} is outside {shown}"),
                )
            })
            .collect(),
    }
}

impl Study {
    /// The study of the deck's design cards `bulk` on the prepared run `prepared`; every
    /// error found, each at its card and field.
    pub fn of_deck(bulk: &BulkData, prepared: &PreparedFmb) -> Result<Study, Vec<String>> {
        let mut errors = Vec::new();
        let pfmb = &prepared.pfmb;
        for m in &bulk.dvmap {
            if !bulk.desvar.iter().any(|d| d.id == m.desvar) {
                errors.push(at(
                    &m.loc,
                    format!("DVMAP {}", m.id),
                    "field 3 (DESVAR)",
                    format!(
                        "DESVAR = {} does not exist (no DESVAR {})",
                        m.desvar, m.desvar
                    ),
                ));
            }
        }
        let mut variables = Vec::new();
        let mut targets = Vec::new();
        for d in &bulk.desvar {
            let v = variable(d, &bulk.ddval);
            let mut names = Vec::new();
            for m in bulk.dvmap.iter().filter(|m| m.desvar == d.id) {
                for (i, target) in m.targets.iter().enumerate() {
                    match parameter_box(pfmb, target) {
                        Some(bounds) => errors.extend(within_box(d, &v, target, bounds)),
                        None => errors.push(at(
                            &m.loc,
                            format!("DVMAP {}", m.id),
                            &format!("field {} (TARGET{})", i + 4, i + 1),
                            format!(
                                "{target} is not BODY.PMPAR of this mechanism (parameters: {})",
                                pfmb.parameter_names().join(", ")
                            ),
                        )),
                    }
                    names.push(target.clone());
                }
            }
            if names.is_empty() {
                errors.push(at(
                    &d.loc,
                    format!("DESVAR {}", d.id),
                    "field 2 (ID)",
                    format!("no DVMAP maps DESVAR {} onto a BODY.PMPAR", d.id),
                ));
            }
            variables.push(v);
            targets.push(names);
        }
        if bulk.desvar.is_empty() {
            errors.push("SOL OPTIMIZE needs at least one DESVAR (with its DVMAP)".to_string());
        }
        if bulk.dobj.is_empty() {
            errors.push("SOL OPTIMIZE needs at least one DOBJ (objective)".to_string());
        }
        let mut responses = Vec::new();
        let mut scoring = Scoring::default();
        let sources = (bulk.dobj.iter())
            .map(|o| {
                (
                    &o.source,
                    &o.name,
                    &o.loc,
                    format!("DOBJ {}", o.id),
                    "field 5 (SOURCE)",
                )
            })
            .chain(bulk.dconstr.iter().map(|c| {
                (
                    &c.source,
                    &c.name,
                    &c.loc,
                    format!("DCONSTR {}", c.id),
                    "field 4 (SOURCE)",
                )
            }));
        for (source, name, loc, card, field) in sources {
            let ResponseSource::Sensor {
                name: sensor,
                statistic,
            } = source;
            match sensor_index(prepared, sensor) {
                Ok(index) => responses.push(Response {
                    name: name.clone(),
                    sensor: index,
                    statistic: *statistic,
                }),
                Err(message) => errors.push(at(loc, card, field, message)),
            }
        }
        for (response, o) in bulk.dobj.iter().enumerate() {
            scoring.objectives.push(Objective {
                response,
                sense: if o.maximize { Sense::Max } else { Sense::Min },
            });
        }
        for (i, c) in bulk.dconstr.iter().enumerate() {
            scoring.constraints.push(Constraint {
                response: bulk.dobj.len() + i,
                low: c.low,
                high: c.high,
            });
        }
        let space = DesignSpace::new(variables);
        let search = match bulk.moopt.as_slice() {
            [one] => Some(one.clone()),
            [] => {
                errors.push("SOL OPTIMIZE needs a MOOPT card (the search)".to_string());
                None
            }
            [_, second, ..] => {
                errors.push(at(
                    &second.loc,
                    format!("MOOPT {}", second.id),
                    "field 2 (ID)",
                    "a deck has one MOOPT".to_string(),
                ));
                None
            }
        };
        if let Some(m) = &search
            && m.method == SearchMethod::Grid
            && errors.is_empty()
        {
            let size = grid_size(&space, m.pop as usize);
            if size > m.neval as usize {
                errors.push(at(
                    &m.loc,
                    format!("MOOPT {}", m.id),
                    "field 4 (NEVAL)",
                    format!(
                        "the full-factorial grid of {} level(s) per continuous variable has {size} designs, more than NEVAL = {}: raise NEVAL or lower POP",
                        m.pop, m.neval
                    ),
                ));
            }
        }
        match search {
            Some(search) if errors.is_empty() => Ok(Study {
                space,
                targets,
                responses,
                scoring,
                search,
            }),
            _ => Err(errors),
        }
    }

    /// The parameter values (`BODY.PMPAR`, value) of `design`.
    pub fn parameters(&self, design: &[f64]) -> Vec<(String, f64)> {
        self.targets
            .iter()
            .zip(design)
            .flat_map(|(names, x)| names.iter().map(move |n| (n.clone(), *x)))
            .collect()
    }

    /// One design evaluation: the prepared run at the design's parameters, its responses
    /// reduced over time.
    pub fn evaluate(&self, prepared: &PreparedFmb, design: &[f64]) -> Result<Responses, EvalError> {
        let h = prepared
            .simulate_at(&self.parameters(design))
            .map_err(EvalError)?;
        Ok(self
            .responses
            .iter()
            .map(|r| reduce(r.statistic, &h.time, &h.outputs[r.sensor]))
            .collect())
    }

    /// The evaluation budget: the grid's size, or NEVAL.
    pub fn budget(&self) -> usize {
        match self.search.method {
            SearchMethod::Grid => grid_size(&self.space, self.search.pop as usize),
            SearchMethod::Nsga2 => self.search.neval as usize,
        }
    }
}

/// The index of MSENSOR `name` among the prepared run's sensors, or why it has none.
fn sensor_index(prepared: &PreparedFmb, name: &str) -> Result<usize, String> {
    if let Some(i) = (prepared.sensors.iter()).position(|s| s.name.eq_ignore_ascii_case(name)) {
        return Ok(i);
    }
    let all = &prepared.pfmb.mechanism.sensors;
    if all.iter().any(|s| s.name.eq_ignore_ascii_case(name)) {
        return Err(format!(
            "MSENSOR {name} is not selected by the subcase's MSENSOR = set: add it to the set"
        ));
    }
    Err(format!(
        "{name} is no MSENSOR of this mechanism (MSENSORs: {})",
        all.iter()
            .map(|s| s.name.as_str())
            .collect::<Vec<_>>()
            .join(" ")
    ))
}

/// `values` over `time` reduced by `statistic`: the trapezoidal time average (eq. 6.1 f₁),
/// the last value (an `ENERGY` sensor's is eq. 6.1 f₂), the largest absolute value, or the
/// trapezoidal root mean square. One row is its own mean and RMS.
pub fn reduce(statistic: Statistic, time: &[f64], values: &[f64]) -> f64 {
    let average = |f: &dyn Fn(f64) -> f64| {
        let span = time.last().copied().unwrap_or(0.0) - time.first().copied().unwrap_or(0.0);
        if values.len() < 2 || span <= 0.0 {
            return values.first().map_or(f64::NAN, |&v| f(v));
        }
        let area: f64 = (time.windows(2).zip(values.windows(2)))
            .map(|(t, v)| 0.5 * (t[1] - t[0]) * (f(v[0]) + f(v[1])))
            .sum();
        area / span
    };
    match statistic {
        Statistic::Mean => average(&|v| v),
        Statistic::Final => values.last().copied().unwrap_or(f64::NAN),
        Statistic::Max => values.iter().fold(f64::NAN, |m, v| m.max(v.abs())),
        Statistic::Rms => average(&|v| v * v).sqrt(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn statistics_of_a_ramp() {
        let t = [0.0, 1.0, 2.0];
        let v = [0.0, -1.0, -2.0];
        assert_eq!(reduce(Statistic::Mean, &t, &v), -1.0);
        assert_eq!(reduce(Statistic::Final, &t, &v), -2.0);
        assert_eq!(reduce(Statistic::Max, &t, &v), 2.0);
        // trapezoid of v²: (0 + 1)/2 + (1 + 4)/2 = 3 over 2 s
        assert_eq!(reduce(Statistic::Rms, &t, &v), 1.5_f64.sqrt());
    }
}
