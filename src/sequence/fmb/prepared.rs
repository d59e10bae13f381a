//! A `SOL FMB` subcase made ready to run, and run as a pure function of the parameters: the
//! mechanism gathered once (the bodies' artifacts and the tables read, [`Pfmb`]), its system
//! and, when a `DEV` output asks for it, its rigid twin built once at the subcase's `PVAL`,
//! the selected MSENSORs turned into outputs, the time grid and the GGL scheme. [`simulate`]
//! runs it at the subcase's values; [`systems_at`] builds the systems at other values of
//! some `BODY.PMPAR`, recomputing only the flexible bodies' affine sums
//! ([`MechanismSystem::at_parameters`]), or with other artifacts for some flexible bodies
//! (rebuilding the systems), and [`simulate_systems`] runs them, writing nothing — one design
//! evaluation of `SOL OPTIMIZE`.
//!
//! [`simulate`]: PreparedFmb::simulate
//! [`systems_at`]: PreparedFmb::systems_at
//! [`simulate_systems`]: PreparedFmb::simulate_systems

use std::path::PathBuf;

use super::super::shared::parameter_tables;
use super::super::{RunContext, RunError};
use super::{control_of, mechanism_errors, mechanism_of, scheme_of, selected};
use crate::card_values::{FmbStart, MsensorKind};
use crate::deck::case_control::Subcase;
use crate::discretize::mechanism::{Bodies, MechanismSystem, build_system};
use crate::discretize::pfmb::Pfmb;
use crate::discretize::prom_body::ParametricBody;
use crate::dynamics::table::Table;
use crate::model::mechanism::{BodyKind, Sensor};
use crate::multibody::{
    Histories, MultibodyError, NewtonSettings, Output, OutputSensitivities, ParameterRate, Scheme,
    Start, TimeGrid, simulate, simulate_sensitivities,
};

/// A flexible body's pROM artifact read once: where from, and its parametric data.
#[derive(Debug, Clone)]
pub struct LoadedArtifact {
    pub path: PathBuf,
    pub data: ParametricBody,
}

/// A subcase's mechanism, systems, outputs and time integration, ready to run.
pub struct PreparedFmb {
    pub pfmb: Pfmb,
    /// The system at the subcase's `PVAL`.
    pub flexible: MechanismSystem,
    /// Its rigid twin (eq. 4.10), built only when a selected output is a `DEV`.
    pub twin: Option<MechanismSystem>,
    /// The MSENSORs the subcase selects, in card order, and their outputs.
    pub sensors: Vec<Sensor>,
    pub outputs: Vec<Output>,
    /// The time grid (empty for a static subcase), the scheme and its label.
    pub grid: TimeGrid,
    pub scheme: Scheme,
    pub method: String,
    pub start: Start,
    /// The subcase's `PVAL` values (`BODY.PMPAR`, value), constant in time.
    pub pval: Vec<(String, f64)>,
    /// The `BODY.PMPAR`s of the subcase's PTABLEs (same id as its PVAL) and their p(t).
    pub tables: Vec<(String, Table)>,
    /// The subcase's gravity (basic).
    pub gravity: [f64; 3],
}

impl PreparedFmb {
    /// Gathers subcase `sub`'s mechanism, builds its systems and reads its time grid, gravity
    /// and parameter values; every error at its card or statement.
    pub fn new(ctx: &RunContext, sub: &Subcase) -> Result<Self, RunError> {
        let id = sub.id;
        let case = |what: String| RunError::Case { subcase: id, what };
        let pfmb = mechanism_of(ctx, sub)?;
        let start = sub.fmbstart.unwrap_or(FmbStart::Assemble);
        // a subcase without TSTEP is a static one with FMBSTART = STATIC or POSES (the model
        // refuses POSES with TSTEP): the equilibrium at t = 0, or at each pose of the grid
        let (grid, scheme, method) = match (sub.tstep, start) {
            (None, start) if start == FmbStart::Static || sub.poses.is_some() => {
                (TimeGrid::default(), Scheme::Bdf1, "STATICS".to_string())
            }
            (None, _) => {
                return Err(case(
                    "SOL FMB needs TSTEP = <sid> in case control (or FMBSTART = STATIC without TSTEP for a static subcase)".into(),
                ));
            }
            (Some(sid), _) => {
                let tstep = ctx
                    .model
                    .tstep(sid)
                    .ok_or_else(|| case(format!("TSTEP = {sid} selects no TSTEP card")))?;
                let (scheme, method) = scheme_of(ctx.model.tinteg(sid));
                let dt0 = tstep.intervals.first().map_or(1.0, |i| i.1);
                let grid = TimeGrid {
                    intervals: tstep.intervals.clone(),
                    control: ctx.model.tstepvar(sid).map(|c| control_of(c, dt0)),
                };
                (grid, scheme, method)
            }
        };
        let gravity = match sub.load {
            None => [0.0; 3],
            Some(sid) if ctx.model.has_load_set(sid) => ctx.model.gravity(sid),
            Some(sid) => pfmb.gravity_of(sid).ok_or_else(|| {
                case(format!(
                    "LOAD = {sid} selects no GRAV or LOAD set {sid} of the deck, nor a gravity stored with the mechanism (sets: {})",
                    pfmb.gravity
                        .iter()
                        .map(|(s, _)| s.to_string())
                        .collect::<Vec<_>>()
                        .join(" ")
                ))
            })?,
        };
        let pval: Vec<(String, f64)> = match sub.pval {
            None => Vec::new(),
            Some(pid) if ctx.model.pval(pid).is_none() && !ctx.model.ptables(pid).is_empty() => {
                Vec::new()
            }
            Some(pid) => {
                let card = ctx
                    .model
                    .pval(pid)
                    .ok_or_else(|| case(format!("PVAL {pid} missing")))?;
                if sub.fmb.is_some() {
                    pfmb.check_parameter_names(&card.values)
                        .map_err(|e| case(format!("{}: PVAL {pid}: {e}", card.loc)))?;
                }
                card.values.clone()
            }
        };
        let tables = match sub.pval {
            None => Vec::new(),
            Some(id) => parameter_tables(
                ctx.model,
                id,
                |name| pval.iter().any(|(n, _)| n.eq_ignore_ascii_case(name)),
                |name| {
                    pfmb.check_parameter_names(&[(name.to_string(), 0.0)])
                        .map(|_| name.to_string())
                },
            )
            .map_err(case)?,
        };
        // the systems are built at p(0) and follow the tables from the first step on
        let at_start = with_tables_at(&pval, &tables, 0.0);
        let mechanism = &pfmb.mechanism;
        let build = |bodies: Bodies| {
            let mut system = build_system(&pfmb, gravity, &at_start, bodies)
                .map_err(|errors| mechanism_errors(mechanism, errors, case))?;
            scheduled(&mut system, &pfmb, &pval, &tables, bodies).map_err(case)?;
            Ok::<_, RunError>(system)
        };
        let flexible = build(Bodies::Flexible)?;
        let sensors: Vec<Sensor> = selected(ctx, &mechanism.sensors, sub)
            .into_iter()
            .cloned()
            .collect();
        // the rigid twin runs only when a DEV output asks for it
        let twin = sensors
            .iter()
            .any(|s| s.kind == MsensorKind::Dev)
            .then(|| build(Bodies::RigidTwin))
            .transpose()?;
        let outputs = flexible.outputs(&sensors);
        let start = match start {
            FmbStart::Assemble => Start::Assembled,
            FmbStart::Static => Start::Equilibrium,
        };
        Ok(PreparedFmb {
            pfmb,
            flexible,
            twin,
            sensors,
            outputs,
            grid,
            scheme,
            method,
            start,
            pval,
            tables,
            gravity,
        })
    }

    /// The run at the subcase's own parameter values.
    pub fn simulate(&self) -> Result<Histories, MultibodyError> {
        self.run(&self.flexible, self.twin.as_ref(), &self.outputs)
    }

    /// The run of `flexible` and its `twin` (built from this run's mechanism, with other
    /// parameters or artifacts), the outputs taken on them (a STRAIN output's rows are the
    /// artifact's).
    pub fn simulate_systems(
        &self,
        flexible: &MechanismSystem,
        twin: Option<&MechanismSystem>,
    ) -> Result<Histories, String> {
        let outputs = flexible.outputs(&self.sensors);
        self.run(flexible, twin, &outputs)
            .map_err(|e| e.to_string())
    }

    /// [`PreparedFmb::simulate_systems`] with the outputs' derivatives with respect to the
    /// parameters whose data rates are `rates` (forward sensitivities,
    /// [`crate::multibody::sensitivity`]).
    pub fn simulate_sensitivities(
        &self,
        flexible: &MechanismSystem,
        twin: Option<&MechanismSystem>,
        rates: Vec<ParameterRate>,
    ) -> Result<(Histories, OutputSensitivities), String> {
        let outputs = flexible.outputs(&self.sensors);
        simulate_sensitivities(
            &flexible.system,
            twin.map(|t| &t.system),
            &outputs,
            &self.grid,
            NewtonSettings::default(),
            self.scheme,
            self.start,
            rates,
        )
        .map_err(|e| e.to_string())
    }

    /// The subcase's `PVAL` with `values` set over it.
    pub(crate) fn pval_with(&self, values: &[(String, f64)]) -> Vec<(String, f64)> {
        let mut pval = self.pval.clone();
        for (name, value) in values {
            match pval.iter_mut().find(|(n, _)| n.eq_ignore_ascii_case(name)) {
                Some(entry) => entry.1 = *value,
                None => pval.push((name.clone(), *value)),
            }
        }
        pval
    }

    /// The flexible system and its twin (when the subcase has one) with the parameters of
    /// `values` (`BODY.PMPAR`, value) set and the others at the subcase's values, and the
    /// flexible bodies of `artifacts` (index into the mechanism's bodies, artifact) taking
    /// those artifacts in place of their FLEXB's (the systems rebuilt: the basis is another).
    /// An unknown name or a mechanism the swapped artifact does not fit is the error's
    /// message.
    pub fn systems_at(
        &self,
        values: &[(String, f64)],
        artifacts: &[(usize, &LoadedArtifact)],
    ) -> Result<(MechanismSystem, Option<MechanismSystem>), String> {
        let pval = self.pval_with(values);
        let at_start = with_tables_at(&pval, &self.tables, 0.0);
        if artifacts.is_empty() {
            let at = |system: &MechanismSystem, bodies| {
                let mut out = system.at_parameters(&self.pfmb, &at_start, bodies)?;
                scheduled(&mut out, &self.pfmb, &pval, &self.tables, bodies)?;
                Ok::<_, String>(out)
            };
            let flexible = at(&self.flexible, Bodies::Flexible)?;
            let twin = (self.twin.as_ref())
                .map(|t| at(t, Bodies::RigidTwin))
                .transpose()?;
            return Ok((flexible, twin));
        }
        let mut pfmb = self.pfmb.clone();
        for (body, artifact) in artifacts {
            pfmb.bodies[*body] = Some(artifact.data.clone());
            if let BodyKind::Flexible { artifact: path, .. } =
                &mut pfmb.mechanism.bodies[*body].kind
            {
                path.clone_from(&artifact.path);
            }
        }
        let mechanism = &pfmb.mechanism;
        let build = |bodies: Bodies| {
            let mut system =
                build_system(&pfmb, self.gravity, &at_start, bodies).map_err(|errors| {
                    (errors.into_iter())
                        .map(|e| mechanism.error_at(e.card, e.field, e.message).to_string())
                        .collect::<Vec<_>>()
                        .join("\n")
                })?;
            scheduled(&mut system, &pfmb, &pval, &self.tables, bodies)?;
            Ok::<_, String>(system)
        };
        let flexible = build(Bodies::Flexible)?;
        let twin = (self.twin.is_some())
            .then(|| build(Bodies::RigidTwin))
            .transpose()?;
        Ok((flexible, twin))
    }

    fn run(
        &self,
        flexible: &MechanismSystem,
        twin: Option<&MechanismSystem>,
        outputs: &[Output],
    ) -> Result<Histories, MultibodyError> {
        simulate(
            &flexible.system,
            twin.map(|t| &t.system),
            outputs,
            &self.grid,
            NewtonSettings::default(),
            self.scheme,
            self.start,
        )
    }
}

/// `pval` with the tabulated parameters' values at t.
fn with_tables_at(
    pval: &[(String, f64)],
    tables: &[(String, Table)],
    t: f64,
) -> Vec<(String, f64)> {
    let mut values = pval.to_vec();
    values.extend(tables.iter().map(|(n, table)| (n.clone(), table.value(t))));
    values
}

/// `system` (built from `pfmb` with `bodies`) with its bodies following `tables` over the
/// constant `pval`, replacing any schedule it had.
fn scheduled(
    system: &mut MechanismSystem,
    pfmb: &Pfmb,
    pval: &[(String, f64)],
    tables: &[(String, Table)],
    bodies: Bodies,
) -> Result<(), String> {
    system.system.schedules.clear();
    system.schedule(pfmb, pval, tables, bodies)
}
