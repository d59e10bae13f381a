//! `SOL ESTIMATE` on a mechanism (DESIGN.md §13): the AMANDA-EKF of
//! [`crate::estimate::mechanism`] (thesis ch. 9) on the deck's bodies or on the `/pfmb` of
//! `FMB = 'file.h5'`, joint estimation of the coordinates, velocities and flexible bodies'
//! parameters from measured MSENSORs.
//!
//! Case control as for `SOL FMB` ([`super::fmb`]: the mechanism, `LOAD` (GRAV), `PVAL` — the
//! values of the `BODY.PMPAR` that are not estimated —, `MSENSOR` — the estimated sensors)
//! plus the component estimator's `ESTIM = id` (EKF with its EKFPAR and an optional AMANDA
//! card of the same id), `MEAS = id` (MEASF with its MEAS channels) and `TSTEP` (the filter
//! step, one Δt). The filter predicts with GGL–BDF1 from the kinematic assembly at t = 0
//! (`TINTEG` other than BDF1, `TSTEPVAR`, `FMBSTART = STATIC`, `POSES` and `STRREF = INITIAL`
//! or a subcase id are refused). `STRREF = STATIC` zeroes the STRAIN gauges in the static
//! equilibrium at t = 0 at the initial guesses (eq. 9.24), `STRREF = ADAPTIVE` at the current
//! estimate every step (eq. 9.25; [`crate::estimate::mechanism::reference`]); without it they
//! read absolute strains. The EKF's QSTATE and P0STATE are Q and P₀ of the positions, the AMANDA card's
//! QVEL and P0VEL those of the velocities; an EKFPAR's P0 is the variance of the physical
//! parameter (divided by INIT² for the scaled θ = p / INIT) and DELTA its δ_p (eq. 8.31).
//!
//! Every bad input is reported before any computation, each at its card and field: an
//! EKFPAR that is not `BODY.PMPAR` of a flexible body or is listed twice, a MEAS naming no
//! MSENSOR or one of a kind without a measurement equation (STRAIN, POS and ACCEL have one),
//! more than one AMANDA card, an EKFINP whose GRID is no MFORCE or MMOMENT id, that gives a
//! COMP or is listed twice. An EKFINP makes the MFORCE (MMOMENT) of id GRID an unknown input
//! ([`crate::estimate::mechanism::inputs`]): its amplitude along its direction is estimated
//! from zero instead of read from its table, with Q_u = (Δt OMEGA AMPL)² (eq. 8.30) and
//! P₀ = AMPL². Then the setups that cannot work (accelerations only; no
//! absolute information on free rigid coordinates) are refused unless the EKF says FORCE =
//! YES, and the numerical observability over the first steps is reported
//! ([`crate::estimate::mechanism::observability`]).
//!
//! Measurements are read like the component estimator's ([`super::estimate::resample`]: the
//! CSV interpolated onto t_k = k Δt, k = 1 … steps).
//!
//! Written under `/results/<id>/estimate/`: `time (t)`; `params/<BODY.PMPAR>`,
//! `params_sigma/<BODY.PMPAR>` (t: estimate and standard deviation); `inputs/<MFORCEid>`,
//! `inputs_sigma/<MFORCEid>` (t: the unknown inputs' amplitudes, e.g. `inputs/MFORCE7`, and
//! their standard deviations); `sensors/<name>` (t, the
//! selected STRAIN, POS and ACCEL MSENSORs at the posterior, attribute `measured`);
//! `constraint_residual (t)` and `velocity_residual (t)` (max |Φ| and max |Φ_q v + Φ_t| of the
//! estimate after the AMANDA step), `manifold_iterations (t)`, `sensitivity (t)` (the smallest
//! over the parameters of the largest measurement sensitivity, in noise σ per 100 % change,
//! [`crate::estimate::mechanism`]'s freeze); attributes `mechanism` (`deck` or the FMB file),
//! `filter` (`AMANDA-EKF`), `fallbacks` (AMANDA steps that needed the kinematic assembly),
//! `frozen_steps` (steps at which FREEZE froze a parameter update), `steps_per_second`, the
//! observability of [`crate::estimate::mechanism::observability`] (`observability` in words,
//! `observability_rank`, `observability_columns`, `observability_steps`,
//! `observability_ratio`, `parameter_identifiability`, `input_identifiability`), with
//! AMANDA's OBSEVERY the windows along the run under `observability/` (`time` of each
//! window's start, `steps`, `rank`, `columns`, `ratio`, and per unknown `<BODY.PMPAR>` or
//! `<MFORCEid>` its identifiability; [`crate::estimate::mechanism`]'s model), with AMANDA's
//! RANK the sensor ranking under `ranking/` ([`super::fmb_ranking`]), and `forced` (a refused
//! setup run with FORCE = YES).

use std::time::Instant;

use super::estimate::{Selection, resample};
use super::fmb::PreparedFmb;
use super::fmb_ranking::{SensorRanking, rank_sensors};
use super::report::{Report, sci};
use super::{Basis, Clock, Driver, RunContext, RunError, SubcaseSummary};
use crate::card_values::{FmbStart, ForceKind, MsensorKind};
use crate::deck::Solution;
use crate::deck::case_control::{StrainReference, Subcase};
use crate::deck::error::DeckError;
use crate::deck::fields::RawCard;
use crate::discretize::mechanism::Bodies;
use crate::estimate::mechanism::inputs::{Input, Inputs};
use crate::estimate::mechanism::observability::{self, Observability, Refusal};
use crate::estimate::mechanism::parameters::{EstimatedBody, Parameter, Parameters};
use crate::estimate::mechanism::reference::StrainReference as Gauges;
use crate::estimate::mechanism::sensors::{Sensor, values};
use crate::estimate::mechanism::{Amanda, AmandaSetup, InputNoise, ManifoldSettings};
use crate::io::{set_attr_f64, set_attr_f64s, set_attr_i64, set_attr_str, write_f64, write_u32};
use crate::model::mechanism::Sensor as Msensor;
use crate::multibody::{Force, Ggl, NewtonSettings, Scheme, System};

/// The longest window of the numerical observability check (steps).
const OBSERVABILITY_STEPS: usize = 200;

/// What one mechanism estimation subcase computed.
#[derive(Debug, Clone)]
pub struct MechanismEstimateSummary {
    /// `deck` or the FMB file.
    pub mechanism: String,
    pub bodies: usize,
    pub coordinates: usize,
    pub steps: usize,
    /// (BODY.PMPAR, final estimate, final σ).
    pub params: Vec<(String, f64, f64)>,
    /// (MFORCEid, RMS of the estimate over the run, final σ) of each unknown input.
    pub inputs: Vec<(String, f64, f64)>,
    /// Largest max |Φ| and max |Φ_q v + Φ_t| of the estimates.
    pub position_residual: f64,
    pub velocity_residual: f64,
    /// AMANDA steps that needed the kinematic-assembly fallback.
    pub fallbacks: usize,
    pub seconds_per_step: f64,
    /// Selected MSENSORs of kinds the filter does not estimate.
    pub not_estimated: Vec<String>,
    /// The numerical observability at the start, and the refusal FORCE = YES overrode.
    pub observability: Observability,
    pub forced: Option<Refusal>,
    /// The AMANDA card's FREEZE and the steps at which it froze a parameter update.
    pub freeze: Option<(f64, usize)>,
    /// The AMANDA card's OBSEVERY and the observability windows along the run (start time,
    /// result).
    pub observed: Option<(usize, Vec<(f64, Observability)>)>,
    /// The sensor ranking (AMANDA RANK).
    pub ranking: Option<SensorRanking>,
}

/// The `SOL ESTIMATE` driver on a mechanism.
pub struct MechanismEstimate;

impl Driver for MechanismEstimate {
    fn name(&self) -> &'static str {
        "ESTIMATE"
    }

    fn solutions(&self) -> &'static [Solution] {
        &[Solution::Estimate]
    }

    fn basis(&self) -> Basis {
        Basis::Mesh
    }

    fn run(&self, ctx: &RunContext, clock: &mut Clock) -> Result<Vec<SubcaseSummary>, RunError> {
        ctx.model
            .subcases
            .iter()
            .map(|sub| {
                clock.time(format!("subcase {}: AMANDA-EKF", sub.id), || {
                    subcase(ctx, sub)
                })
            })
            .collect()
    }
}

/// Whether the filter has a measurement equation for an MSENSOR kind.
fn measurable(kind: MsensorKind) -> bool {
    matches!(
        kind,
        MsensorKind::Strain | MsensorKind::Pos | MsensorKind::Accel
    )
}

/// An error at a card's field: `file:line: CARD id: field i (NAME): message`.
fn field_error(loc: &crate::deck::Loc, card: String, i: usize, name: &str, m: String) -> DeckError {
    let mut e = DeckError::at(loc, m).on_card(card);
    e.field = Some(format!("{} ({name})", RawCard::field_label(i)));
    e
}

/// The case-control settings the filter cannot honour, each an error at its statement.
fn refused_settings(ctx: &RunContext, sub: &Subcase) -> Vec<String> {
    let at = |name: &str| sub.loc_of(name).map_or(String::new(), |l| format!("{l}: "));
    let mut refused = Vec::new();
    if let Some(sid) = sub.tstep {
        if let Some(t) = ctx.model.tinteg(sid)
            && !matches!(t.method, crate::deck::cards::TintegMethod::Bdf1)
        {
            refused.push(format!(
                "{}: TINTEG {sid}: the AMANDA-EKF predicts with BDF1 (eq. 9.6); remove the card or set METHOD = BDF1",
                t.loc
            ));
        }
        if let Some(t) = ctx.model.tstepvar(sid) {
            refused.push(format!(
                "{}: TSTEPVAR {sid}: the filter runs with the fixed Δt of its TSTEP; remove the card",
                t.loc
            ));
        }
    }
    if sub.fmbstart == Some(FmbStart::Static) {
        refused.push(format!(
            "{}FMBSTART = STATIC: the filter starts from the kinematic assembly at t = 0 (FMBSTART = ASSEMBLE)",
            at("FMBSTART")
        ));
    }
    if sub.poses.is_some() {
        refused.push(format!(
            "{}POSES: a pose grid is a SOL FMB static study, not an estimation",
            at("POSES")
        ));
    }
    if matches!(
        sub.strref,
        Some(StrainReference::Initial | StrainReference::Subcase(_))
    ) {
        refused.push(format!(
            "{}STRREF: the filter's gauges read absolute strains (NONE), or from the static equilibrium at t = 0 at the initial guesses (STATIC, eq. 9.24) or at the current estimate (ADAPTIVE, eq. 9.25)",
            at("STRREF")
        ));
    }
    if let Some(id) = sub.pval {
        for card in ctx.model.ptables(id) {
            refused.push(format!(
                "{}: PTABLE {id}: field 3 (NAME): the filter's model keeps {} constant; a parameter that changes in time is estimated as a random walk (EKFPAR with a larger DELTA), or given a constant value in the PVAL",
                card.loc, card.name
            ));
        }
    }
    refused
}

/// The estimated parameters from the EKFPAR cards of EKF `ekf_id`, the fixed ones from the
/// subcase's `pval`; every bad card an error.
fn parameters(
    ctx: &RunContext,
    prepared: &PreparedFmb,
    ekf_id: u32,
) -> Result<(Parameters, AmandaParameters), Vec<DeckError>> {
    let pfmb = &prepared.pfmb;
    let mut errors = Vec::new();
    let mut bodies: Vec<EstimatedBody> = Vec::new();
    let mut list: Vec<Parameter> = Vec::new();
    let mut covariances = AmandaParameters::default();
    for par in ctx.model.ekfpar(ekf_id) {
        let error = |m: String| field_error(&par.loc, format!("EKFPAR {ekf_id}"), 2, "NAME", m);
        let resolved = par.name.split_once('.').and_then(|(body, pmpar)| {
            let b =
                (pfmb.mechanism.bodies.iter()).position(|x| x.name.eq_ignore_ascii_case(body))?;
            let model = pfmb.bodies[b].as_ref()?;
            let p = (model.prom.parameters.iter()).find(|q| q.name.eq_ignore_ascii_case(pmpar))?;
            Some((b, p.name.clone()))
        });
        let Some((b, pmpar)) = resolved else {
            errors.push(error(format!(
                "{} is not BODY.PMPAR of a flexible body of this mechanism (parameters: {})",
                par.name,
                pfmb.parameter_names().join(", ")
            )));
            continue;
        };
        let k = match bodies.iter().position(|e| e.body == b) {
            Some(k) => k,
            None => {
                let name = pfmb.mechanism.bodies[b].name.clone();
                bodies.push(EstimatedBody {
                    body: b,
                    name,
                    model: pfmb.bodies[b].clone().expect("a flexible body"),
                    fixed: Vec::new(),
                });
                bodies.len() - 1
            }
        };
        if list.iter().any(|p| p.body == k && p.pmpar == pmpar) {
            errors.push(error(format!("{} is listed twice", par.name)));
            continue;
        }
        list.push(Parameter {
            body: k,
            pmpar,
            initial: par.init,
        });
        covariances.rates.push(par.delta);
        covariances.p0.push(par.p0 / (par.init * par.init));
    }
    if !errors.is_empty() {
        return Err(errors);
    }
    // the parameters of an estimated body that are not estimated keep their PVAL values
    for (k, body) in bodies.iter_mut().enumerate() {
        for (name, value) in &prepared.pval {
            let Some((_, pmpar)) =
                (name.split_once('.')).filter(|(b, _)| b.eq_ignore_ascii_case(&body.name))
            else {
                continue;
            };
            let estimated =
                (list.iter()).any(|p| p.body == k && p.pmpar.eq_ignore_ascii_case(pmpar));
            if !estimated {
                body.fixed.push((pmpar.to_string(), *value));
            }
        }
    }
    Ok((Parameters { bodies, list }, covariances))
}

/// The covariance data of the estimated parameters: δ_p (Hz) and P₀ of θ = p / INIT.
#[derive(Debug, Default)]
struct AmandaParameters {
    rates: Vec<f64>,
    p0: Vec<f64>,
}

/// The unknown inputs from the EKFINP cards of EKF `ekf_id` (GRID an MFORCE or MMOMENT id,
/// COMP blank) in `system`, with their random walks; every bad card an error at its field.
fn unknown_inputs(
    ctx: &RunContext,
    prepared: &PreparedFmb,
    system: &System,
    ekf_id: u32,
) -> Result<(Inputs, Vec<InputNoise>), Vec<DeckError>> {
    let loads = &prepared.pfmb.mechanism.forces;
    // the system's point forces and moments, in the order of the mechanism's loads
    let elements: Vec<usize> = (system.forces.iter().enumerate())
        .filter(|(_, f)| matches!(f, Force::Point { .. } | Force::Moment { .. }))
        .map(|(i, _)| i)
        .collect();
    let (mut errors, mut inputs, mut noise) = (Vec::new(), Inputs::default(), Vec::new());
    for u in ctx.model.ekfinp(ekf_id) {
        let card = || format!("EKFINP {ekf_id}");
        if let Some(c) = u.component {
            errors.push(field_error(&u.loc, card(), 3, "COMP", format!(
                "found {c}: on a mechanism an unknown input is the amplitude of an MFORCE or MMOMENT along its own direction; leave COMP blank"
            )));
            continue;
        }
        let Some(i) = loads.iter().position(|f| f.id == u.grid) else {
            errors.push(field_error(
                &u.loc,
                card(),
                2,
                "GRID",
                format!(
                    "{} is not an MFORCE or MMOMENT id of the mechanism (ids: {})",
                    u.grid,
                    loads
                        .iter()
                        .map(|f| f.id.to_string())
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
            ));
            continue;
        };
        let kind = match loads[i].kind {
            ForceKind::Force => "MFORCE",
            ForceKind::Moment => "MMOMENT",
        };
        let name = format!("{kind}{}", u.grid);
        if inputs.list.iter().any(|x| x.name == name) {
            errors.push(field_error(
                &u.loc,
                card(),
                2,
                "GRID",
                format!("{name} is listed twice"),
            ));
            continue;
        }
        inputs.list.push(Input {
            force: elements[i],
            name,
        });
        noise.push(InputNoise {
            frequency: u.omega,
            amplitude: u.amplitude,
        });
    }
    if errors.is_empty() {
        Ok((inputs, noise))
    } else {
        Err(errors)
    }
}

/// The filter's sensors: one per MEAS channel of `selection`, its MSENSOR by name; every
/// channel naming no MSENSOR or one without a measurement equation an error at its card.
fn measured(
    prepared: &PreparedFmb,
    selection: &Selection,
) -> Result<Vec<(Sensor, Msensor)>, Vec<DeckError>> {
    let sensors = &prepared.pfmb.mechanism.sensors;
    let mut errors = Vec::new();
    let mut found = Vec::new();
    for m in &selection.channels {
        let error = |text: String| {
            field_error(
                &m.loc,
                format!("MEAS {}", selection.meas_id),
                2,
                "SENSOR",
                text,
            )
        };
        let Some(s) = sensors
            .iter()
            .find(|s| s.name.eq_ignore_ascii_case(&m.sensor))
        else {
            errors.push(error(format!(
                "{} is not an MSENSOR of the mechanism (MSENSORs: {})",
                m.sensor,
                sensors
                    .iter()
                    .map(|s| s.name.as_str())
                    .collect::<Vec<_>>()
                    .join(", ")
            )));
            continue;
        };
        if !measurable(s.kind) {
            errors.push(error(format!(
                "{} is a {} MSENSOR: the AMANDA-EKF has measurement equations for STRAIN, POS and ACCEL only",
                s.name,
                s.kind.keyword()
            )));
            continue;
        }
        let output = prepared.flexible.outputs(std::slice::from_ref(s)).remove(0);
        found.push((
            Sensor {
                output,
                reference: 0.0,
                variance: m.sigma * m.sigma,
            },
            s.clone(),
        ));
    }
    if errors.is_empty() {
        Ok(found)
    } else {
        Err(errors)
    }
}

/// The AMANDA card of EKF `id` (defaults without one); two are an error at the second.
fn amanda_card<'a>(
    ctx: &'a RunContext,
    id: u32,
) -> Result<Option<&'a crate::deck::cards::Amanda>, DeckError> {
    match ctx.model.amanda(id)[..] {
        [] => Ok(None),
        [one] => Ok(Some(one)),
        [first, second, ..] => Err(DeckError::at(
            &second.loc,
            format!(
                "a second AMANDA card for EKF {id} (the first is at {})",
                first.loc
            ),
        )
        .on_card(format!("AMANDA {id}"))),
    }
}

/// Joins errors into one message, one per line.
fn joined(errors: &[DeckError]) -> String {
    errors
        .iter()
        .map(ToString::to_string)
        .collect::<Vec<_>>()
        .join("\n")
}

fn subcase(ctx: &RunContext, sub: &Subcase) -> Result<SubcaseSummary, RunError> {
    let id = sub.id;
    let case = |what: String| RunError::Case { subcase: id, what };
    if ctx.model.mechanism.is_empty() && sub.fmb.is_none() {
        return Err(case(
            "the deck has no mechanism and this subcase no FMB = 'file.h5': SOL ESTIMATE on a mechanism needs one of them".into(),
        ));
    }
    let selection = Selection::of(ctx.model, sub)?;
    let refused = refused_settings(ctx, sub);
    if !refused.is_empty() {
        return Err(case(refused.join("\n")));
    }
    let prepared = PreparedFmb::new(ctx, sub)?;
    debug_assert_eq!(prepared.scheme, Scheme::Bdf1);
    let mut errors = Vec::new();
    let params = parameters(ctx, &prepared, selection.ekf_id).map_err(|e| errors.extend(e));
    let sensors = measured(&prepared, &selection).map_err(|e| errors.extend(e));
    let card = amanda_card(ctx, selection.ekf_id).map_err(|e| errors.push(e));
    let inputs = unknown_inputs(ctx, &prepared, &prepared.flexible.system, selection.ekf_id)
        .map_err(|e| errors.extend(e));
    let (Ok((parameters, covariances)), Ok(sensors), Ok(card), Ok((inputs, input_noise)), true) =
        (params, sensors, card, inputs, errors.is_empty())
    else {
        return Err(case(joined(&errors)));
    };
    let steps = selection.steps;
    let csv = selection.csv();
    let window = (selection.dt, steps as f64 * selection.dt);
    let series = (selection.channels.iter())
        .map(|m| {
            resample(&csv, &selection.measf.tcol, &m.column, window, steps).map_err(|e| {
                case(format!(
                    "{}: MEAS {} {}: {e}",
                    m.loc, selection.meas_id, m.sensor
                ))
            })
        })
        .collect::<Result<Vec<_>, _>>()?;

    // the system at the initial guesses, assembled at t = 0
    let pfmb = &prepared.pfmb;
    let mut pval = prepared.pval.clone();
    for (name, p) in parameters.names().into_iter().zip(&parameters.list) {
        pval.retain(|(n, _)| !n.eq_ignore_ascii_case(&name));
        pval.push((name, p.initial));
    }
    let system = (prepared.flexible)
        .at_parameters(pfmb, &pval, Bodies::Flexible)
        .map_err(case)?;
    let ggl = Ggl::new(
        system.system.clone(),
        selection.dt,
        0.0,
        NewtonSettings::default(),
    )
    .map_err(|e| case(format!("kinematic assembly at t = 0: {e}")))?;
    let ekf = selection.ekf;
    let setup = AmandaSetup {
        q_positions: ekf.q_state,
        q_velocities: card.and_then(|c| c.q_velocities).unwrap_or(ekf.q_state),
        inputs: input_noise,
        parameter_rates: covariances.rates,
        p0_positions: ekf.p0_state,
        p0_velocities: card.and_then(|c| c.p0_velocities).unwrap_or(ekf.p0_state),
        p0_parameters: covariances.p0,
        freeze: card.and_then(|c| c.freeze),
        observe_every: card.and_then(|c| c.observe_every).map(|e| e as usize),
        strain_reference: match sub.strref {
            Some(StrainReference::Static) => Gauges::Fixed,
            Some(StrainReference::Adaptive) => Gauges::Adaptive,
            _ => Gauges::Absolute,
        },
        manifold: card.map_or_else(ManifoldSettings::default, |c| ManifoldSettings {
            tolerance: c.tolerance,
            max_iterations: c.max_iterations as usize,
        }),
    };
    let names = parameters.names();
    let input_names = inputs.names();
    let n = ggl.system.size();
    let (filter_sensors, measured_msensors): (Vec<Sensor>, Vec<Msensor>) =
        sensors.into_iter().unzip();
    // the estimated sensors: the selected MSENSORs with a measurement equation
    let (shown, not_estimated): (Vec<&Msensor>, Vec<&Msensor>) =
        prepared.sensors.iter().partition(|s| measurable(s.kind));
    let virtual_sensors: Vec<Sensor> = (shown.iter())
        .map(|s| Sensor {
            output: system.outputs(std::slice::from_ref(*s)).remove(0),
            reference: 0.0,
            variance: 1.0,
        })
        .collect();
    // observability (§9.3.1): the setups that cannot work, refused unless forced, and the
    // numerical observability over the first steps
    let refusal = observability::structural(&ggl, &filter_sensors);
    if let (Some(why), false) = (&refusal, ekf.force) {
        return Err(case(format!(
            "{}: EKF {}: {why}. Set FORCE = YES on the EKF card to run anyway",
            ekf.loc, selection.ekf_id
        )));
    }
    let new_probe = || {
        Ggl::new(
            system.system.clone(),
            selection.dt,
            0.0,
            NewtonSettings::default(),
        )
        .map_err(|e| case(format!("kinematic assembly at t = 0: {e}")))
    };
    let probe = new_probe()?;
    let ranking = card
        .and_then(|c| c.rank)
        .map(|steps| {
            let candidates: Vec<&Msensor> = (shown.iter().copied())
                .filter(|s| s.kind == MsensorKind::Strain)
                .collect();
            let sigma = (filter_sensors.iter())
                .filter(|s| matches!(s.output, crate::multibody::Output::Strain { .. }))
                .map(|s| s.variance.sqrt())
                .fold(0.0, f64::max);
            if candidates.is_empty() || sigma == 0.0 {
                return Err(case(format!(
                    "{}: AMANDA {}: field 9 (RANK): the ranking needs STRAIN MSENSORs among the subcase's sensors and a MEAS on one of them (its σ is the candidates')",
                    card.map(|c| c.loc.to_string()).unwrap_or_default(),
                    selection.ekf_id
                )));
            }
            let measured = (candidates.iter().enumerate())
                .filter(|(_, c)| measured_msensors.iter().any(|m| m.id == c.id))
                .map(|(r, _)| r)
                .collect();
            let sensors = (candidates.iter())
                .map(|c| {
                    let output = system.outputs(std::slice::from_ref(*c)).remove(0);
                    (
                        c.name.clone(),
                        Sensor {
                            output,
                            reference: 0.0,
                            variance: sigma * sigma,
                        },
                    )
                })
                .collect();
            rank_sensors(
                new_probe()?,
                &inputs,
                &parameters,
                sensors,
                measured,
                &setup,
                steps as usize,
            )
            .map_err(|e| case(format!("sensor ranking: {e}")))
        })
        .transpose()?;
    let observed = observability::numerical(
        probe,
        &inputs,
        &parameters,
        &filter_sensors,
        OBSERVABILITY_STEPS,
    )
    .map_err(|e| case(format!("observability check: {e}")))?;
    let mut filter = Amanda::new(ggl, inputs, parameters, filter_sensors, &setup)
        .map_err(|e| case(e.to_string()))?;

    // the run
    let np = names.len();
    let mut time = Vec::with_capacity(steps);
    let (mut estimates, mut sigmas) = (
        vec![Vec::with_capacity(steps); np],
        vec![Vec::with_capacity(steps); np],
    );
    let nu = input_names.len();
    let (mut input_estimates, mut input_sigmas) = (
        vec![Vec::with_capacity(steps); nu],
        vec![Vec::with_capacity(steps); nu],
    );
    let mut sensor_series = vec![Vec::with_capacity(steps); virtual_sensors.len()];
    let (mut position, mut velocity, mut iterations) = (Vec::new(), Vec::new(), Vec::new());
    let mut fallbacks = 0;
    let (mut sensitivity, mut frozen_steps) = (Vec::with_capacity(steps), 0);
    let mut previous = filter.state().1.to_vec();
    let mut y = vec![0.0; virtual_sensors.len()];
    let mut x = vec![0.0; 2 * n];
    let mut measurement = vec![0.0; series.len()];
    let clock = Instant::now();
    for k in 0..steps {
        for (m, s) in measurement.iter_mut().zip(&series) {
            *m = s[k];
        }
        let report = filter.step(&measurement).map_err(|e| {
            case(format!(
                "step {} (t = {}): {e}",
                k + 1,
                (k + 1) as f64 * selection.dt
            ))
        })?;
        time.push(report.time);
        position.push(report.manifold.position_residual);
        velocity.push(report.manifold.velocity_residual);
        iterations.push(report.manifold.iterations as u32);
        fallbacks += usize::from(report.manifold.fallback);
        sensitivity.push(report.sensitivity);
        frozen_steps += usize::from(report.frozen > 0);
        let (p, sigma) = filter.parameters();
        for ((series, deviations), (value, deviation)) in estimates
            .iter_mut()
            .zip(&mut sigmas)
            .zip(p.iter().zip(&sigma))
        {
            series.push(*value);
            deviations.push(*deviation);
        }
        let (u, sigma) = filter.inputs();
        for ((series, deviations), (value, deviation)) in input_estimates
            .iter_mut()
            .zip(&mut input_sigmas)
            .zip(u.iter().zip(&sigma))
        {
            series.push(*value);
            deviations.push(*deviation);
        }
        let (q, v) = filter.state();
        x[..n].copy_from_slice(q);
        x[n..].copy_from_slice(v);
        values(&virtual_sensors, filter.integrator(), &x, &previous, &mut y);
        for (series, value) in sensor_series.iter_mut().zip(&y) {
            series.push(*value);
        }
        previous.copy_from_slice(v);
        ctx.progress.step("AMANDA-EKF", k + 1, steps);
    }
    let elapsed = clock.elapsed().as_secs_f64();

    // output
    let root = format!("results/{id}/estimate");
    let group = ctx.output.group(&root)?;
    write_f64(&group, "time", &time, &[steps])?;
    write_f64(&group, "constraint_residual", &position, &[steps])?;
    write_f64(&group, "velocity_residual", &velocity, &[steps])?;
    write_u32(&group, "manifold_iterations", &iterations, &[steps])?;
    write_f64(&group, "sensitivity", &sensitivity, &[steps])?;
    set_attr_i64(&group, "frozen_steps", frozen_steps as i64)?;
    for (sub_name, labels, data) in [
        ("params", &names, &estimates),
        ("params_sigma", &names, &sigmas),
        ("inputs", &input_names, &input_estimates),
        ("inputs_sigma", &input_names, &input_sigmas),
    ] {
        if !labels.is_empty() {
            let g = ctx.output.group(&format!("{root}/{sub_name}"))?;
            for (name, series) in labels.iter().zip(data) {
                write_f64(&g, name, series, &[steps])?;
            }
        }
    }
    if !shown.is_empty() {
        let g = ctx.output.group(&format!("{root}/sensors"))?;
        for (s, series) in shown.iter().zip(&sensor_series) {
            let ds = write_f64(&g, &s.name, series, &[steps])?;
            let was_measured = measured_msensors.iter().any(|m| m.id == s.id);
            set_attr_i64(&ds, "measured", i64::from(was_measured))?;
        }
    }
    let mechanism = sub.fmb.clone().unwrap_or_else(|| "deck".into());
    set_attr_str(&group, "mechanism", &mechanism)?;
    set_attr_str(&group, "filter", "AMANDA-EKF")?;
    set_attr_i64(&group, "fallbacks", fallbacks as i64)?;
    set_attr_f64(
        &group,
        "steps_per_second",
        steps as f64 / elapsed.max(f64::MIN_POSITIVE),
    )?;
    set_attr_str(
        &group,
        "observability",
        &observability_text(&observed, &names, &input_names),
    )?;
    set_attr_i64(&group, "observability_rank", observed.rank as i64)?;
    set_attr_i64(&group, "observability_columns", observed.columns as i64)?;
    set_attr_i64(&group, "observability_steps", observed.steps as i64)?;
    set_attr_f64(&group, "observability_ratio", observed.ratio)?;
    set_attr_f64s(&group, "parameter_identifiability", &observed.parameters)?;
    set_attr_f64s(&group, "input_identifiability", &observed.inputs)?;
    set_attr_i64(&group, "forced", i64::from(refusal.is_some()))?;
    if let Some(ranking) = &ranking {
        ranking.write(ctx, &root)?;
    }
    let along = filter.observed().to_vec();
    if setup.observe_every.is_some() {
        write_observed(ctx, &root, &along, &names, &input_names)?;
    }
    let last = |s: &[Vec<f64>], j: usize| s[j].last().copied().unwrap_or(f64::NAN);
    let summary = MechanismEstimateSummary {
        mechanism,
        bodies: pfmb.mechanism.bodies.len(),
        coordinates: n,
        steps,
        params: (0..np)
            .map(|j| (names[j].clone(), last(&estimates, j), last(&sigmas, j)))
            .collect(),
        inputs: (0..nu)
            .map(|j| {
                let rms = (input_estimates[j].iter().map(|u| u * u).sum::<f64>()
                    / steps.max(1) as f64)
                    .sqrt();
                (input_names[j].clone(), rms, last(&input_sigmas, j))
            })
            .collect(),
        position_residual: position.iter().fold(0.0, |a, b| a.max(*b)),
        velocity_residual: velocity.iter().fold(0.0, |a, b| a.max(*b)),
        fallbacks,
        seconds_per_step: elapsed / steps.max(1) as f64,
        not_estimated: not_estimated.iter().map(|s| s.name.clone()).collect(),
        observability: observed,
        forced: refusal,
        freeze: setup.freeze.map(|f| (f, frozen_steps)),
        observed: setup.observe_every.map(|e| (e, along)),
        ranking,
    };
    Ok(SubcaseSummary {
        id,
        autospc: Vec::new(),
        result: Box::new(summary),
    })
}

/// The observability windows along the run under `<root>/observability`: `time` (each
/// window's start), `steps`, `rank`, `columns`, `ratio`, and per unknown (parameter or input)
/// its identifiability.
fn write_observed(
    ctx: &RunContext,
    root: &str,
    along: &[(f64, Observability)],
    names: &[String],
    inputs: &[String],
) -> Result<(), RunError> {
    let g = ctx.output.group(&format!("{root}/observability"))?;
    let count = along.len();
    let column = |f: &dyn Fn(&Observability) -> f64| -> Vec<f64> {
        along.iter().map(|(_, o)| f(o)).collect()
    };
    let time: Vec<f64> = along.iter().map(|(t, _)| *t).collect();
    write_f64(&g, "time", &time, &[count])?;
    for (name, values) in [
        ("steps", column(&|o| o.steps as f64)),
        ("rank", column(&|o| o.rank as f64)),
        ("columns", column(&|o| o.columns as f64)),
        ("ratio", column(&|o| o.ratio)),
    ] {
        write_f64(&g, name, &values, &[count])?;
    }
    for (j, name) in names.iter().enumerate() {
        write_f64(&g, name, &column(&|o| o.parameters[j]), &[count])?;
    }
    for (j, name) in inputs.iter().enumerate() {
        write_f64(&g, name, &column(&|o| o.inputs[j]), &[count])?;
    }
    Ok(())
}

/// The observability windows along the run in words: how many, the range of their rank and
/// conditioning, and each unknown's smallest identifiability and when.
fn observed_text(every: usize, along: &[(f64, Observability)], unknowns: &[String]) -> String {
    if along.is_empty() {
        return format!(
            "observability along the run (a window every {every} step(s)): no window finished"
        );
    }
    let ranks = along.iter().map(|(_, o)| o.rank);
    let (low, high) = (ranks.clone().min().unwrap_or(0), ranks.max().unwrap_or(0));
    let worst = along
        .iter()
        .map(|(_, o)| o.ratio)
        .fold(f64::INFINITY, f64::min);
    let per_unknown: Vec<String> = (unknowns.iter().enumerate())
        .map(|(j, name)| {
            let (t, d) = along
                .iter()
                .map(|(t, o)| {
                    (
                        *t,
                        o.parameters
                            .iter()
                            .chain(&o.inputs)
                            .nth(j)
                            .copied()
                            .unwrap_or(0.0),
                    )
                })
                .fold((0.0, f64::INFINITY), |a, b| if b.1 < a.1 { b } else { a });
            format!("{name} {} (window from t = {})", sci(d, 2), sci(t, 3))
        })
        .collect();
    format!(
        "observability along the run: {} window(s) of {} step(s), one every {every} step(s): rank {low} … {high} of {}, smallest σ_min/σ_max {}; least identifiability: {}",
        along.len(),
        along[0].1.steps,
        along[0].1.columns,
        sci(worst, 2),
        if per_unknown.is_empty() {
            "none estimated".to_string()
        } else {
            per_unknown.join(", ")
        }
    )
}

/// The numerical observability in words: rank, conditioning and each parameter's and
/// input's distance from the span of the other columns.
fn observability_text(o: &Observability, names: &[String], inputs: &[String]) -> String {
    let parameters: Vec<String> = (names.iter().zip(&o.parameters))
        .chain(inputs.iter().zip(&o.inputs))
        .map(|(n, d)| format!("{n} {}", sci(*d, 2)))
        .collect();
    format!(
        "observability over the first {} step(s): rank {} of {} (σ_min/σ_max {}, tolerance {:e}); identifiability of the unknowns (0 … 1): {}",
        o.steps,
        o.rank,
        o.columns,
        sci(o.ratio, 2),
        observability::RANK_TOLERANCE,
        if parameters.is_empty() {
            "none estimated".to_string()
        } else {
            parameters.join(", ")
        }
    )
}

impl Report for MechanismEstimateSummary {
    fn render(&self, subcase: u32) -> Vec<String> {
        let mut out = vec![format!(
            "subcase {subcase}: AMANDA-EKF on the mechanism ({}), {} bod(ies), {} coordinate(s), {} step(s), {} ms/step",
            self.mechanism,
            self.bodies,
            self.coordinates,
            self.steps,
            sci(1e3 * self.seconds_per_step, 3)
        )];
        let names: Vec<String> = self.params.iter().map(|p| p.0.clone()).collect();
        let inputs: Vec<String> = self.inputs.iter().map(|p| p.0.clone()).collect();
        out.push(format!(
            "  {}",
            observability_text(&self.observability, &names, &inputs)
        ));
        for (name, value, sigma) in &self.params {
            out.push(format!(
                "  {name} = {} ± {} (3σ) at the end",
                sci(*value, 6),
                sci(3.0 * sigma, 2)
            ));
        }
        for (name, rms, sigma) in &self.inputs {
            out.push(format!(
                "  input {name}: RMS {} over the run, ± {} (3σ) at the end",
                sci(*rms, 4),
                sci(3.0 * sigma, 2)
            ));
        }
        out.push(format!(
            "  estimates on the constraints: largest |Φ| {}, |Φ_q v + Φ_t| {}; {} kinematic-assembly fallback(s)",
            sci(self.position_residual, 2),
            sci(self.velocity_residual, 2),
            self.fallbacks
        ));
        if let Some(ranking) = &self.ranking {
            out.extend(ranking.lines().into_iter().map(|l| format!("  {l}")));
        }
        if let Some((every, along)) = &self.observed {
            let unknowns: Vec<String> = names.iter().chain(&inputs).cloned().collect();
            out.push(format!("  {}", observed_text(*every, along, &unknowns)));
        }
        if let Some((threshold, count)) = self.freeze {
            out.push(format!(
                "  parameter updates frozen at {count} step(s) (a sensitivity below FREEZE = {})",
                sci(threshold, 3)
            ));
        }
        out
    }

    fn warnings(&self, subcase: u32) -> Vec<String> {
        let mut warnings = Vec::new();
        if let Some(why) = &self.forced {
            warnings.push(format!(
                "subcase {subcase}: FORCE = YES: the filter ran although {why}"
            ));
        }
        if !self.not_estimated.is_empty() {
            warnings.push(format!(
                "subcase {subcase}: MSENSOR(s) {} are not estimated (the AMANDA-EKF estimates STRAIN, POS and ACCEL sensors)",
                self.not_estimated.join(", ")
            ));
        }
        warnings
    }
}
