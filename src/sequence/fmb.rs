//! `SOL FMB`: the deck's mechanism (DESIGN.md §11) integrated in time, one run per subcase.
//!
//! Per subcase: `TSTEP` (time grid; `TINTEG` selects the GGL scheme of eq. 2.60: BDF1, the
//! thesis's eq. 2.61 and the default, BDF2 or GALPHA with its RHOINF; `TSTEPVAR` replaces the
//! fixed Δt by error-controlled steps onto the same output times),
//! `LOAD` (GRAV: gravity), `PVAL` (values of `BODY.PMPAR` for the flexible bodies' pROMs;
//! the PTABLE cards of the same id make a `BODY.PMPAR` follow a table of time, its body's data
//! re-evaluated from the pROM's affine sums at every step, [`crate::multibody::schedule`]),
//! `MSENSOR = ALL | NONE | set` (all MSENSORs without the statement), `FMBSTART = ASSEMBLE`
//! (kinematic assembly at t = 0, the default) or `STATIC` (the static equilibrium under the
//! subcase's gravity reached from the assembly, drives held at their t = 0 values), `STRREF =
//! NONE | INITIAL | id` (STRAIN outputs absolute, the default; relative to the subcase's state
//! at t = 0; or relative to the last state of the earlier subcase `id`, e.g. a static subcase's
//! equilibrium under gravity: eq. 9.24's gauge zeroed in a reference configuration). A subcase
//! with `FMBSTART = STATIC` and no `TSTEP` is a static subcase: its output is the one row of
//! the equilibrium at t = 0, `method` = `STATICS`; with `POSES = id` (and no `TSTEP`) it is
//! solved at every pose of the FMBPOSE grid instead ([`poses`]). The mechanism is the deck's bulk data or,
//! with `FMB = 'file.h5'`, the `/pfmb` of an earlier run (a [`Pfmb`] either way; a deck with
//! both is refused; `LOAD = sid` takes the deck's own set `sid` if it has one, else the
//! gravity stored with the loaded mechanism). The system is built by
//! [`crate::discretize::mechanism::build_system`] and run by [`crate::multibody::simulate`].
//!
//! Written: `/results/<id>/fmb/{time (t), sensors/<name> (t), drives/<JDRIVE id>/{angle, rate,
//! torque, power} (t), constraint_residual (t), newton_iterations (t)}`, attributes `method`,
//! `coordinates`, `constraints`, `redundant` (labels of removed constraints), `params` and
//! `values` (the flexible bodies' `BODY.PMPAR` values used, at t = 0 for a PTABLE's); under `TSTEPVAR` also `rtol`,
//! `atol`, `steps`, `rejected_steps`, `max_local_error` (the largest estimate of an accepted
//! step in units of the tolerance) and `step_range` (smallest and largest step); and once per
//! run the first subcase's mechanism as the pFMB artifact `/pfmb` ([`crate::io::write_pfmb`]).

use std::path::PathBuf;

use super::report::{Report, sci};
use super::{Basis, Clock, Driver, RunContext, RunError, SubcaseSummary};
use crate::card_values::MsensorKind;
use crate::deck::Solution;
use crate::deck::cards::{Tinteg, TintegMethod, Tstepvar};
use crate::deck::case_control::{StrainReference, Subcase, Target};
use crate::discretize::mechanism::{MechanismError, MechanismSystem};
use crate::discretize::pfmb::Pfmb;
use crate::io::{
    read_pfmb, set_attr_f64s, set_attr_i64, set_attr_str, set_attr_strings, write_f64, write_pfmb,
    write_u32,
};
use crate::model::mechanism::{Mechanism, Sensor};
use crate::multibody::{Scheme, StepControl};

mod poses;
mod prepared;

pub use prepared::{LoadedArtifact, PreparedFmb};

/// What one `SOL FMB` subcase computed.
#[derive(Debug, Clone)]
pub struct FmbSummary {
    pub bodies: usize,
    /// The GGL scheme's label (BDF1, BDF2, GALPHA with ρ∞).
    pub method: String,
    pub coordinates: usize,
    pub constraints: usize,
    pub redundant: Vec<String>,
    pub steps: usize,
    pub end_time: f64,
    pub max_iterations: usize,
    pub max_residual: f64,
    /// `BODY.PMPAR` parameters outside their pROM's box.
    pub extrapolated: Vec<String>,
    /// Final value of each written output.
    pub finals: Vec<(String, f64)>,
    /// Under `TSTEPVAR`: rejected steps, the largest local error estimate of an accepted step
    /// (in units of the tolerance), the smallest and largest step.
    pub control: Option<(usize, f64, [f64; 2])>,
}

/// The `SOL FMB` driver: the deck's mechanism (its bodies' pROMs are read from their artifacts,
/// so no subcase has `ROM =`).
pub struct Fmb;

impl Driver for Fmb {
    fn name(&self) -> &'static str {
        "FMB"
    }

    fn solutions(&self) -> &'static [Solution] {
        &[Solution::Fmb]
    }

    fn basis(&self) -> Basis {
        Basis::Mesh
    }

    fn run(&self, ctx: &RunContext, clock: &mut Clock) -> Result<Vec<SubcaseSummary>, RunError> {
        run(ctx, clock)
    }
}

/// The GGL scheme a subcase's `TINTEG` selects (BDF1 without one) and its label.
fn scheme_of(tinteg: Option<&Tinteg>) -> (Scheme, String) {
    match tinteg.map(|t| (t.method, t.rho_inf)) {
        None | Some((TintegMethod::Bdf1, _)) => (Scheme::Bdf1, "BDF1".to_string()),
        Some((TintegMethod::Bdf2, _)) => (Scheme::Bdf2, "BDF2".to_string()),
        Some((TintegMethod::Galpha, spectral_radius)) => (
            Scheme::GeneralizedAlpha { spectral_radius },
            format!("GALPHA (rho_inf = {spectral_radius})"),
        ),
    }
}

/// The step control of a `TSTEPVAR` over intervals whose first Δt is `dt0`.
fn control_of(card: &Tstepvar, dt0: f64) -> StepControl {
    StepControl {
        relative: card.rtol,
        absolute: card.atol.unwrap_or(card.rtol),
        min_step: card.hmin.unwrap_or(1e-6 * dt0),
        max_step: card.hmax.unwrap_or(f64::INFINITY),
    }
}

/// The last absolute value of each STRAIN output of a subcase, by name.
type StrainFinals = Vec<(String, f64)>;

/// The error of an estimation-only strain reference (`STATIC`, `ADAPTIVE`) in `SOL FMB`.
fn estimation_reference(reference: StrainReference) -> String {
    format!(
        "STRREF = {}: a reference of the AMANDA-EKF (SOL ESTIMATE on a mechanism); in SOL FMB use STRREF = INITIAL with FMBSTART = STATIC, or the id of a static subcase",
        if reference == StrainReference::Static {
            "STATIC"
        } else {
            "ADAPTIVE"
        }
    )
}

/// Runs every subcase, in order (a later subcase's `STRREF = id` reads an earlier one's
/// strains); an estimation-only STRREF is refused before any subcase runs.
fn run(ctx: &RunContext, clock: &mut Clock) -> Result<Vec<SubcaseSummary>, RunError> {
    for sub in &ctx.model.subcases {
        if let Some(r @ (StrainReference::Static | StrainReference::Adaptive)) = sub.strref {
            let at = sub
                .loc_of("STRREF")
                .map_or(String::new(), |l| format!("{l}: "));
            return Err(RunError::Case {
                subcase: sub.id,
                what: format!("{at}{}", estimation_reference(r)),
            });
        }
    }
    let mut earlier: Vec<(u32, StrainFinals)> = Vec::new();
    let mut summaries = Vec::new();
    for sub in &ctx.model.subcases {
        let (summary, finals, pfmb) = clock
            .time(format!("subcase {}: multibody", sub.id), || {
                subcase(ctx, sub, &earlier)
            })?;
        if summaries.is_empty() {
            write_pfmb(&ctx.output.group("pfmb")?, &pfmb)?;
        }
        earlier.push((sub.id, finals));
        summaries.push(summary);
    }
    Ok(summaries)
}

/// Makes the STRAIN series of `sensors` relative to the reference configuration `STRREF`
/// selects (eq. 9.24): the subcase's state at t = 0 (`INITIAL`) or the last state of an
/// earlier subcase (`id`); absolute without it. Returns the last absolute values.
fn strain_relative_to(
    reference: Option<StrainReference>,
    sensors: &[Sensor],
    series: &mut [Vec<f64>],
    earlier: &[(u32, StrainFinals)],
) -> Result<StrainFinals, String> {
    let mut finals = Vec::new();
    for (s, values) in sensors.iter().zip(series) {
        if s.kind != MsensorKind::Strain {
            continue;
        }
        finals.push((s.name.clone(), values.last().copied().unwrap_or(f64::NAN)));
        let zero = match reference {
            None | Some(StrainReference::None) => continue,
            Some(StrainReference::Initial) => values.first().copied().unwrap_or(0.0),
            Some(r @ (StrainReference::Static | StrainReference::Adaptive)) => {
                return Err(estimation_reference(r));
            }
            Some(StrainReference::Subcase(id)) => earlier
                .iter()
                .find(|(sub, _)| *sub == id)
                .and_then(|(_, f)| f.iter().find(|(n, _)| *n == s.name))
                .map(|(_, v)| *v)
                .ok_or_else(|| {
                    format!(
                        "STRREF = {id}: subcase {id} did not output the STRAIN {} (select it there too)",
                        s.name
                    )
                })?,
        };
        values.iter_mut().for_each(|v| *v -= zero);
    }
    Ok(finals)
}

/// The MSENSORs `sub` selects, in card order.
fn selected<'a>(ctx: &RunContext, sensors: &'a [Sensor], sub: &Subcase) -> Vec<&'a Sensor> {
    match &sub.msensor {
        None | Some(Target::All) => sensors.iter().collect(),
        Some(Target::None) => Vec::new(),
        Some(Target::Set(id)) => {
            let set = ctx.deck.case.set(*id);
            sensors
                .iter()
                .filter(|s| set.is_some_and(|set| set.ids.contains(&s.id)))
                .collect()
        }
    }
}

/// The mechanism of `sub`: the `/pfmb` of the file its `FMB =` names (relative to the deck),
/// or the deck's own mechanism bulk data with its artifacts and tables. A deck with both is
/// refused: the two would describe one mechanism twice.
fn mechanism_of(ctx: &RunContext, sub: &Subcase) -> Result<Pfmb, RunError> {
    let case = |what: String| RunError::Case {
        subcase: sub.id,
        what,
    };
    let own = &ctx.model.mechanism;
    let Some(file) = &sub.fmb else {
        if own.is_empty() {
            return Err(case(
                "SOL FMB needs a mechanism: FLEXB or RIGIDB bodies, MARKERs and JOINTs (or FMB = 'file.h5', the /pfmb of an earlier SOL FMB run)".into(),
            ));
        }
        return Pfmb::of_model(ctx.model).map_err(|errors| mechanism_errors(own, errors, case));
    };
    let loc = sub
        .loc_of("FMB")
        .cloned()
        .expect("the case control records where FMB = was written");
    if !own.is_empty() {
        return Err(case(format!(
            "{loc}: FMB = '{file}' loads a mechanism, and the deck has its own (FLEXB or RIGIDB {}): keep one of the two",
            own.bodies[0].id
        )));
    }
    let path = ctx
        .deck
        .path
        .parent()
        .map_or_else(|| PathBuf::from(file), |dir| dir.join(file));
    read_pfmb(&path, &loc).map_err(|e| case(format!("{loc}: FMB = '{file}': {e}")))
}

/// The errors of building a mechanism, each at its card.
fn mechanism_errors(
    mechanism: &Mechanism,
    errors: Vec<MechanismError>,
    case: impl Fn(String) -> RunError,
) -> RunError {
    case(
        errors
            .into_iter()
            .map(|e| mechanism.error_at(e.card, e.field, e.message).to_string())
            .collect::<Vec<_>>()
            .join("\n"),
    )
}

fn subcase(
    ctx: &RunContext,
    sub: &Subcase,
    earlier: &[(u32, StrainFinals)],
) -> Result<(SubcaseSummary, StrainFinals, Pfmb), RunError> {
    let id = sub.id;
    let case = |what: String| RunError::Case { subcase: id, what };
    let prepared = PreparedFmb::new(ctx, sub)?;
    let sensors = &prepared.sensors;
    if let Some(pid) = sub.poses {
        let run = poses::PoseRun {
            pfmb: &prepared.pfmb,
            flexible: &prepared.flexible,
            twin: prepared.twin.as_ref().map(|t| &t.system),
            sensors,
        };
        let (result, finals) = poses::run(ctx, sub, pid, &run, earlier)?;
        let summary = SubcaseSummary {
            id,
            autospc: Vec::new(),
            result: Box::new(result),
        };
        return Ok((summary, finals, prepared.pfmb));
    }
    let mut h = prepared.simulate().map_err(|e| case(e.to_string()))?;
    let strain_finals =
        strain_relative_to(sub.strref, sensors, &mut h.outputs, earlier).map_err(case)?;
    let (mechanism, grid, method) = (&prepared.pfmb.mechanism, &prepared.grid, &prepared.method);

    let group = ctx.output.group(&format!("results/{id}/fmb"))?;
    let rows = h.time.len();
    write_f64(&group, "time", &h.time, &[rows])?;
    write_f64(
        &group,
        "constraint_residual",
        &h.constraint_residual,
        &[rows],
    )?;
    write_u32(&group, "newton_iterations", &h.newton_iterations, &[rows])?;
    if !sensors.is_empty() {
        let sg = ctx.output.group(&format!("results/{id}/fmb/sensors"))?;
        for (s, series) in sensors.iter().zip(&h.outputs) {
            write_f64(&sg, &s.name, series, &[rows])?;
        }
    }
    for (d, series) in mechanism.drives.iter().zip(&h.drives) {
        let dg = ctx
            .output
            .group(&format!("results/{id}/fmb/drives/{}", d.id))?;
        for (name, values) in ["angle", "rate", "torque", "power"].iter().zip(series) {
            write_f64(&dg, name, values, &[rows])?;
        }
    }
    set_attr_str(&group, "method", method)?;
    set_attr_i64(&group, "coordinates", h.coordinates as i64)?;
    set_attr_i64(&group, "constraints", h.constraints as i64)?;
    let redundant: Vec<&str> = h.redundant.iter().map(String::as_str).collect();
    set_attr_strings(&group, "redundant", &redundant)?;
    if let Some(c) = grid.control {
        set_attr_f64s(&group, "rtol", &[c.relative])?;
        set_attr_f64s(&group, "atol", &[c.absolute])?;
        set_attr_i64(&group, "steps", h.steps as i64)?;
        set_attr_i64(&group, "rejected_steps", h.rejected as i64)?;
        set_attr_f64s(&group, "max_local_error", &[h.max_error])?;
        set_attr_f64s(&group, "step_range", &h.step_range)?;
    }
    let extrapolated = write_parameters(&group, &prepared.flexible)?;

    let summary = SubcaseSummary {
        id,
        autospc: Vec::new(),
        result: Box::new(FmbSummary {
            bodies: mechanism.bodies.len(),
            method: method.clone(),
            coordinates: h.coordinates,
            constraints: h.constraints,
            redundant: h.redundant.clone(),
            steps: h.steps,
            end_time: h.time.last().copied().unwrap_or(0.0),
            max_iterations: h.max_iterations,
            max_residual: h.constraint_residual.iter().fold(0.0, |a, x| a.max(*x)),
            extrapolated,
            finals: sensors
                .iter()
                .zip(&h.outputs)
                .map(|(s, v)| (s.name.clone(), v.last().copied().unwrap_or(f64::NAN)))
                .collect(),
            control: grid
                .control
                .map(|_| (h.rejected, h.max_error, h.step_range)),
        }),
    };
    Ok((summary, strain_finals, prepared.pfmb))
}

/// Writes the flexible bodies' `BODY.PMPAR` names and values used as the attributes `params`
/// and `values` of `group`; returns those outside their pROM's box.
fn write_parameters(
    group: &hdf5_metno::Group,
    ms: &MechanismSystem,
) -> Result<Vec<String>, RunError> {
    let (mut names, mut values, mut extrapolated) = (Vec::new(), Vec::new(), Vec::new());
    for (body, at) in &ms.flexible {
        for (name, value) in &at.parameters {
            names.push(format!("{body}.{name}"));
            values.push(*value);
        }
        extrapolated.extend(at.extrapolated.iter().map(|n| format!("{body}.{n}")));
    }
    let name_refs: Vec<&str> = names.iter().map(String::as_str).collect();
    set_attr_strings(group, "params", &name_refs)?;
    set_attr_f64s(group, "values", &values)?;
    Ok(extrapolated)
}

/// The warnings every multibody subcase may give: constraints removed as redundant and
/// parameters extrapolated beyond their pROM's box.
fn system_warnings(subcase: u32, redundant: &[String], extrapolated: &[String]) -> Vec<String> {
    let mut w = Vec::new();
    if !redundant.is_empty() {
        w.push(format!(
            "subcase {subcase}: {} redundant constraint(s) removed: {}",
            redundant.len(),
            redundant.join("; ")
        ));
    }
    if !extrapolated.is_empty() {
        w.push(format!(
            "subcase {subcase}: parameter(s) {} lie outside the box their pROM was built for: extrapolated",
            extrapolated.join(", ")
        ));
    }
    w
}

impl Report for FmbSummary {
    fn render(&self, subcase: u32) -> Vec<String> {
        let mut out = vec![
            format!(
                "subcase {subcase}: multibody, {} bod(ies), {} coordinate(s), {} constraint(s), GGL/{} {} step(s) to t = {} s",
                self.bodies,
                self.coordinates,
                self.constraints,
                self.method,
                self.steps,
                sci(self.end_time, 4)
            ),
            format!(
                "  Newton: at most {} iteration(s) per step; largest |constraint| {}",
                self.max_iterations,
                sci(self.max_residual, 3)
            ),
        ];
        if let Some((rejected, error, [smallest, largest])) = self.control {
            out.push(format!(
                "  step control: {rejected} step(s) rejected; steps from {} to {} s; largest local error estimate {} x the tolerance",
                sci(smallest, 3),
                sci(largest, 3),
                sci(error, 3)
            ));
        }
        if !self.finals.is_empty() {
            out.push(format!(
                "  at the end: {}",
                self.finals
                    .iter()
                    .map(|(n, v)| format!("{n} = {}", sci(*v, 5)))
                    .collect::<Vec<_>>()
                    .join(", ")
            ));
        }
        out
    }

    fn warnings(&self, subcase: u32) -> Vec<String> {
        system_warnings(subcase, &self.redundant, &self.extrapolated)
    }
}
