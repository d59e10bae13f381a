//! The study a `SOL OPTIMIZE` deck describes, checked against its mechanism before any run:
//! the design variables (`DESVAR`, with a `DDVAL` discrete) and the `BODY.PMPAR` parameters
//! each sets or the bodies whose artifact it chooses from a `PROMLIB` (`DVMAP`,
//! [`super::optimize_library`]), the responses (`DOBJ`, `DCONSTR`: an MSENSOR history reduced over
//! time, the mechanism's mass, a body's natural frequency), the objectives and constraints over them, and the search (`MOOPT`).
//!
//! Refused, each at its card and field: a DESVAR no DVMAP maps, a DVMAP onto a missing DESVAR
//! or onto a name that is no `BODY.PMPAR` of the mechanism, bounds (or discrete values)
//! outside the box the parameter's pROM was built for (in every artifact its body may take: the
//! pROM would extrapolate), a response
//! on an MSENSOR the mechanism does not have or the subcase does not select, no DOBJ, no or
//! several MOOPT, a GRID larger than its NEVAL.

use super::fmb::PreparedFmb;
use super::optimize_library::{Libraries, Target};
use super::report::lambda_to_hz;
use crate::deck::cards::{BulkData, Ddval, Desvar, Moopt, ResponseSource, SearchMethod, Statistic};
use crate::deck::error::{DeckError, Loc};
use crate::discretize::mechanism::MechanismSystem;
use crate::discretize::pfmb::Pfmb;
use crate::discretize::prom_body::ParametricBody;
use crate::linalg::dense::generalized_eigen;
use crate::multibody::Histories;
use crate::optimize::grid::grid_size;
use crate::optimize::{
    Constraint, Design, DesignSpace, Domain, EvalError, Objective, Responses, Scoring, Sense,
    Variable,
};

/// What a response measures.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Quantity {
    /// An MSENSOR's history (index into the prepared run's sensors) reduced by a statistic.
    Sensor { index: usize, statistic: Statistic },
    /// The mechanism's mass: the sum of its bodies' masses at the design (a flexible body's
    /// is the affine sum of its invariants' components, eq. 4.8: exact in p).
    Mass,
    /// The `mode`-th (1-based) natural frequency in Hz of the pROM of body `body` (index into
    /// the mechanism's bodies) at the design: the eigenvalues of (K_ff(p), M_ff(p)), the
    /// free-free flexible modes of the body as its artifact reduces them (`RIGID = REMOVE`).
    Frequency { body: usize, mode: usize },
}

/// One response: its name and what it measures.
#[derive(Debug, Clone, PartialEq)]
pub struct Response {
    /// The DOBJ's or DCONSTR's NAME.
    pub name: String,
    /// Its SOURCE: the MSENSOR's name, `MASS` or `FREQ <body>`.
    pub source: String,
    pub quantity: Quantity,
}

/// A checked study.
#[derive(Debug, Clone)]
pub struct Study {
    pub space: DesignSpace,
    /// Per variable: the `BODY.PMPAR` parameters it sets and the bodies (NAME) whose
    /// artifact it chooses.
    pub targets: Vec<Vec<String>>,
    /// The bodies whose artifact a variable chooses, with their artifacts.
    pub libraries: Libraries,
    /// The DOBJs' responses, then the DCONSTRs'.
    pub responses: Vec<Response>,
    pub scoring: Scoring,
    pub search: Moopt,
    /// Each DESVAR's XINIT (within its bounds): where `MOOPT GRAD` starts (the discrete
    /// values are each combination's).
    pub start: Design,
}

/// An error at `loc` on `card`, field `field` (number and name).
pub(super) fn at(loc: &Loc, card: String, field: &str, message: String) -> String {
    let mut e = DeckError::at(loc, message).on_card(card);
    e.field = Some(field.to_string());
    e.to_string()
}

/// The boxes `[low, high]` of parameter `target` (`BODY.PMPAR`) in every artifact its body may
/// take: its FLEXB's, or those of its `PROMLIB` a variable chooses from (each with the label
/// the messages show); `None` when BODY is no flexible body or PMPAR no parameter of one of
/// them.
fn parameter_boxes(
    pfmb: &Pfmb,
    libraries: &Libraries,
    target: &str,
) -> Option<Vec<(String, (f64, f64))>> {
    let (body, parameter) = target.split_once('.')?;
    let index = (pfmb.mechanism.bodies.iter()).position(|b| b.name.eq_ignore_ascii_case(body))?;
    let artifacts: Vec<(String, &ParametricBody)> = match libraries.candidates(index) {
        Some(choices) => (choices.into_iter())
            .map(|(v, a)| {
                (
                    format!("{target} in '{}' (value {v:e})", a.path.display()),
                    &a.data,
                )
            })
            .collect(),
        None => vec![(target.to_string(), pfmb.bodies[index].as_ref()?)],
    };
    artifacts
        .into_iter()
        .map(|(shown, a)| {
            (a.prom.parameters.iter())
                .find(|q| q.name.eq_ignore_ascii_case(parameter))
                .map(|q| (shown, (q.low, q.high)))
        })
        .collect()
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
        // the artifacts' libraries first: a parameter's box is checked in each artifact its
        // body may take
        let mut libraries = Libraries::default();
        for (index, d) in bulk.desvar.iter().enumerate() {
            let v = variable(d, &bulk.ddval);
            for m in bulk.dvmap.iter().filter(|m| m.desvar == d.id) {
                for (position, body) in m.targets.iter().enumerate() {
                    if body.contains('.') {
                        continue;
                    }
                    let target = Target {
                        desvar: d,
                        variable: &v,
                        index,
                        dvmap: m,
                        position,
                        body,
                    };
                    libraries.add(bulk, prepared, &target, &mut errors);
                }
            }
        }
        Libraries::unused(bulk, prepared, &mut errors);
        let mut variables = Vec::new();
        let mut targets = Vec::new();
        for d in &bulk.desvar {
            let v = variable(d, &bulk.ddval);
            let mut names = Vec::new();
            for m in bulk.dvmap.iter().filter(|m| m.desvar == d.id) {
                for (i, target) in m.targets.iter().enumerate() {
                    names.push(target.clone());
                    if !target.contains('.') {
                        continue;
                    }
                    match parameter_boxes(pfmb, &libraries, target) {
                        Some(boxes) => {
                            for (shown, bounds) in boxes {
                                errors.extend(within_box(d, &v, &shown, bounds));
                            }
                        }
                        None => errors.push(at(
                            &m.loc,
                            format!("DVMAP {}", m.id),
                            &format!("field {} (TARGET{})", i + 4, i + 1),
                            format!(
                                "{target} is not BODY.PMPAR of this mechanism{} (parameters: {})",
                                if libraries.libraries.is_empty() {
                                    ""
                                } else {
                                    " (in every artifact of its body's PROMLIB)"
                                },
                                pfmb.parameter_names().join(", ")
                            ),
                        )),
                    }
                }
            }
            if names.is_empty() {
                errors.push(at(
                    &d.loc,
                    format!("DESVAR {}", d.id),
                    "field 2 (ID)",
                    format!(
                        "no DVMAP maps DESVAR {} onto a BODY.PMPAR or a body's PROMLIB",
                        d.id
                    ),
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
        let gradient = (bulk.moopt.first()).is_some_and(|m| m.method == SearchMethod::Grad);
        for (source, name, loc, card, field) in sources {
            if gradient && matches!(source, ResponseSource::Frequency { .. }) {
                errors.push(at(
                    loc,
                    card.clone(),
                    field,
                    "MOOPT GRAD: a FREQ response has no gradient (GRAD takes MSENSOR and MASS responses)".to_string(),
                ));
                continue;
            }
            let quantity = match source {
                ResponseSource::Sensor {
                    name: sensor,
                    statistic,
                } => sensor_index(prepared, sensor).map(|index| Quantity::Sensor {
                    index,
                    statistic: *statistic,
                }),
                ResponseSource::Mass => Ok(Quantity::Mass),
                ResponseSource::Frequency { body, mode } => {
                    frequency_of(prepared, &libraries, body, *mode as usize)
                }
            };
            match quantity {
                Ok(quantity) => responses.push(Response {
                    name: name.clone(),
                    source: match (source, quantity) {
                        (_, Quantity::Sensor { index, .. }) => prepared.sensors[index].name.clone(),
                        (ResponseSource::Frequency { body, .. }, _) => format!("FREQ {body}"),
                        _ => "MASS".to_string(),
                    },
                    quantity,
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
                start: (bulk.desvar.iter().zip(&space.variables))
                    .map(|(d, v)| match &v.domain {
                        Domain::Continuous { low, high } => d.xinit.clamp(*low, *high),
                        Domain::Discrete { values } => values[0],
                    })
                    .collect(),
                space,
                targets,
                libraries,
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
            .flat_map(|(names, x)| {
                (names.iter())
                    .filter(|n| n.contains('.'))
                    .map(move |n| (n.clone(), *x))
            })
            .collect()
    }

    /// The systems of the prepared run at `design`: its parameters set and its bodies'
    /// artifacts chosen.
    pub(crate) fn systems(
        &self,
        prepared: &PreparedFmb,
        design: &[f64],
    ) -> Result<(MechanismSystem, Option<MechanismSystem>), String> {
        let artifacts = self.libraries.artifacts_of(design)?;
        prepared.systems_at(&self.parameters(design), &artifacts)
    }

    /// The histories of the prepared run at `design`.
    pub fn histories(&self, prepared: &PreparedFmb, design: &[f64]) -> Result<Histories, String> {
        let (flexible, twin) = self.systems(prepared, design)?;
        prepared.simulate_systems(&flexible, twin.as_ref())
    }

    /// One design evaluation: the systems at the design, the transient run when a response
    /// reads an MSENSOR, each response computed.
    pub fn evaluate(&self, prepared: &PreparedFmb, design: &[f64]) -> Result<Responses, EvalError> {
        let (flexible, twin) = self.systems(prepared, design).map_err(EvalError)?;
        let histories = (self.responses.iter())
            .any(|r| matches!(r.quantity, Quantity::Sensor { .. }))
            .then(|| prepared.simulate_systems(&flexible, twin.as_ref()))
            .transpose()
            .map_err(EvalError)?;
        self.responses
            .iter()
            .map(|r| match r.quantity {
                Quantity::Sensor { index, statistic } => {
                    let h = histories
                        .as_ref()
                        .expect("run when a response reads a sensor");
                    Ok(reduce(statistic, &h.time, &h.outputs[index]))
                }
                Quantity::Mass => Ok(mass(&flexible)),
                Quantity::Frequency { body, mode } => {
                    frequency(&flexible, body, mode).map_err(EvalError)
                }
            })
            .collect()
    }

    /// The evaluation budget: the grid's size, or NEVAL.
    pub fn budget(&self) -> usize {
        match self.search.method {
            SearchMethod::Grid => grid_size(&self.space, self.search.pop as usize),
            SearchMethod::Nsga2 | SearchMethod::Grad => self.search.neval as usize,
        }
    }
}

/// The mass of the mechanism `system`: the sum of its bodies' masses (the invariants' mass,
/// at the parameters the system was built at).
pub fn mass(system: &MechanismSystem) -> f64 {
    (system.system.bodies.iter())
        .map(|b| b.data.invariants.mass)
        .sum()
}

/// The `mode`-th (1-based) natural frequency in Hz of body `body`'s pROM in `system`: the
/// ascending eigenvalues λ of K_ff φ = λ M_ff φ, f = √λ / 2π.
pub fn frequency(system: &MechanismSystem, body: usize, mode: usize) -> Result<f64, String> {
    let f = system.flexible_of[body].ok_or("FREQ of a body that is not flexible")?;
    let (name, at) = &system.flexible[f];
    let (lambda, _) = generalized_eigen(at.data.stiffness.as_ref(), at.data.mass.as_ref())
        .map_err(|e| format!("FREQ of body {name}: {e}"))?;
    // a negative eigenvalue (a reduced stiffness that is not positive semi-definite at p)
    // leaves the numbering of the modes without meaning: no frequency is returned
    if let Some(&negative) = lambda.first().filter(|l| **l < 0.0) {
        return Err(format!(
            "FREQ {mode} of body {name}: the pROM's reduced stiffness is indefinite at this design (eigenvalue {negative:e}): no mode numbering"
        ));
    }
    let l = lambda.get(mode - 1).ok_or_else(|| {
        format!(
            "FREQ {mode} of body {name}: its pROM has {} modal coordinate(s)",
            lambda.len()
        )
    })?;
    Ok(lambda_to_hz(*l))
}

/// The FREQ response `mode` of body `name`: the body is flexible and every artifact it may
/// take has at least `mode` modal coordinates.
fn frequency_of(
    prepared: &PreparedFmb,
    libraries: &Libraries,
    name: &str,
    mode: usize,
) -> Result<Quantity, String> {
    let pfmb = &prepared.pfmb;
    let body = (pfmb.mechanism.bodies.iter())
        .position(|b| b.name.eq_ignore_ascii_case(name))
        .filter(|&b| pfmb.bodies[b].is_some())
        .ok_or_else(|| {
            format!(
                "FREQ of {name}: no FLEXB of this mechanism has that NAME (flexible bodies: {})",
                pfmb.flexible()
                    .map(|(n, _)| n)
                    .collect::<Vec<_>>()
                    .join(" ")
            )
        })?;
    let sizes: Vec<usize> = match libraries.candidates(body) {
        Some(choices) => choices.iter().map(|(_, a)| a.data.prom.size()).collect(),
        None => vec![pfmb.bodies[body].as_ref().map_or(0, |p| p.prom.size())],
    };
    match sizes.iter().min() {
        Some(&n) if n < mode => Err(format!(
            "FREQ {mode} of body {name}: its pROM has {n} modal coordinate(s)"
        )),
        _ => Ok(Quantity::Frequency { body, mode }),
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
