//! A `SOL FMB` static subcase over a pose grid (`POSES = id`, FMBPOSE card): the static
//! equilibrium under the subcase's gravity at every pose ([`crate::multibody::poses`]), one
//! value per pose of every selected MSENSOR.
//!
//! Written: `/results/<id>/fmb/poses/{values (poses × drives), drives (the JDRIVE ids, as
//! text), shape (the axis lengths), converged (1/0), iterations, force_residual,
//! constraint_residual, sensors/<name>}` (per pose, row-major: the first axis varies slowest),
//! attributes `method` (`STATICS`), `fmbpose`, `coordinates`, `constraints`, `redundant`,
//! `assemblies` (poses solved from the kinematic assembly), `factorizations`, `params` and
//! `values`. A pose without an equilibrium has `converged` 0 and NaN outputs. STRAIN outputs
//! follow `STRREF` with the grid's first pose as `INITIAL`.

use super::super::report::{Report, sci};
use super::super::{RunContext, RunError};
use super::{StrainFinals, strain_relative_to, system_warnings, write_parameters};
use crate::deck::case_control::Subcase;
use crate::discretize::mechanism::MechanismSystem;
use crate::discretize::pfmb::Pfmb;
use crate::io::{
    set_attr_i64, set_attr_str, set_attr_strings, write_f64, write_strings, write_u32,
};
use crate::model::mechanism::{Sensor, drive_list};
use crate::multibody::poses::{PoseGrid, PoseHistories, Start, solve_grid};
use crate::multibody::{NewtonSettings, System};

/// What a pose-grid subcase computed.
#[derive(Debug, Clone)]
pub struct PosesSummary {
    pub fmbpose: u32,
    /// JDRIVE ids of the axes and the axis lengths.
    pub drives: Vec<u32>,
    pub shape: Vec<usize>,
    pub coordinates: usize,
    pub constraints: usize,
    pub redundant: Vec<String>,
    pub iterations: Vec<u32>,
    pub assemblies: usize,
    pub factorizations: usize,
    pub max_residual: [f64; 2],
    /// Poses without an equilibrium: (drive values, why).
    pub failures: Vec<(Vec<f64>, String)>,
    pub extrapolated: Vec<String>,
}

/// The mechanism's systems and outputs a pose-grid subcase runs.
pub struct PoseRun<'a> {
    pub pfmb: &'a Pfmb,
    pub flexible: &'a MechanismSystem,
    pub twin: Option<&'a System>,
    pub sensors: &'a [Sensor],
}

/// The pose grid of FMBPOSE `pid` on the drives of `run`: each axis's JDRIVE (checked against
/// the deck's own mechanism when the model is built, against a loaded one here).
fn grid_of(ctx: &RunContext, pid: u32, run: &PoseRun) -> Result<PoseGrid, String> {
    let card = ctx
        .model
        .fmbpose(pid)
        .ok_or_else(|| format!("POSES = {pid} selects no FMBPOSE {pid}"))?;
    let mechanism = &run.pfmb.mechanism;
    let mut grid = PoseGrid {
        drives: Vec::new(),
        axes: Vec::new(),
    };
    for axis in &card.axes {
        let index = mechanism
            .drives
            .iter()
            .position(|d| d.id == axis.drive)
            .ok_or_else(|| {
                format!(
                    "{}: FMBPOSE {pid}, {} (JDRIVE): JDRIVE = {} does not exist in the mechanism (drives: {})",
                    axis.loc,
                    axis.field,
                    axis.drive,
                    drive_list(mechanism)
                )
            })?;
        grid.drives.push(run.flexible.drives[index]);
        grid.axes.push(axis.values());
    }
    Ok(grid)
}

/// Runs the pose grid `pid` of subcase `sub` and writes its outputs (module docs). Returns the
/// summary and the last pose's absolute STRAIN values (for a later `STRREF`).
pub fn run(
    ctx: &RunContext,
    sub: &Subcase,
    pid: u32,
    run: &PoseRun,
    earlier: &[(u32, StrainFinals)],
) -> Result<(PosesSummary, StrainFinals), RunError> {
    let case = |what: String| RunError::Case {
        subcase: sub.id,
        what,
    };
    let grid = grid_of(ctx, pid, run).map_err(case)?;
    let mut h: PoseHistories = solve_grid(
        &run.flexible.system,
        run.twin,
        &run.flexible.outputs(run.sensors),
        &grid,
        NewtonSettings::default(),
        Start::Neighbour,
    )
    .map_err(|e| case(e.to_string()))?;
    let finals =
        strain_relative_to(sub.strref, run.sensors, &mut h.outputs, earlier).map_err(case)?;

    let group = ctx.output.group(&format!("results/{}/fmb/poses", sub.id))?;
    let (poses, drives) = (grid.len(), grid.drives.len());
    let values: Vec<f64> = (0..poses).flat_map(|k| grid.values(k)).collect();
    write_f64(&group, "values", &values, &[poses, drives])?;
    let card = ctx.model.fmbpose(pid).expect("grid_of found it");
    let ids: Vec<u32> = card.axes.iter().map(|a| a.drive).collect();
    let names: Vec<String> = ids.iter().map(u32::to_string).collect();
    let name_refs: Vec<&str> = names.iter().map(String::as_str).collect();
    write_strings(&group, "drives", &name_refs)?;
    let shape: Vec<u32> = grid.axes.iter().map(|a| a.len() as u32).collect();
    write_u32(&group, "shape", &shape, &[drives])?;
    let converged: Vec<u32> = h.converged.iter().map(|&c| u32::from(c)).collect();
    write_u32(&group, "converged", &converged, &[poses])?;
    write_u32(&group, "iterations", &h.iterations, &[poses])?;
    write_f64(&group, "force_residual", &h.force_residual, &[poses])?;
    write_f64(
        &group,
        "constraint_residual",
        &h.constraint_residual,
        &[poses],
    )?;
    if !run.sensors.is_empty() {
        let sg = ctx
            .output
            .group(&format!("results/{}/fmb/poses/sensors", sub.id))?;
        for (s, series) in run.sensors.iter().zip(&h.outputs) {
            write_f64(&sg, &s.name, series, &[poses])?;
        }
    }
    set_attr_str(&group, "method", "STATICS")?;
    set_attr_i64(&group, "fmbpose", i64::from(pid))?;
    set_attr_i64(&group, "coordinates", h.coordinates as i64)?;
    set_attr_i64(&group, "constraints", h.constraints as i64)?;
    let redundant: Vec<&str> = h.redundant.iter().map(String::as_str).collect();
    set_attr_strings(&group, "redundant", &redundant)?;
    set_attr_i64(&group, "assemblies", h.assemblies as i64)?;
    set_attr_i64(&group, "factorizations", h.factorizations as i64)?;
    let extrapolated = write_parameters(&group, run.flexible)?;

    let largest = |x: &[f64]| {
        x.iter()
            .filter(|v| v.is_finite())
            .fold(0.0_f64, |a, v| a.max(*v))
    };
    let summary = PosesSummary {
        fmbpose: pid,
        drives: ids,
        shape: grid.axes.iter().map(Vec::len).collect(),
        coordinates: h.coordinates,
        constraints: h.constraints,
        redundant: h.redundant,
        iterations: h.iterations,
        assemblies: h.assemblies,
        factorizations: h.factorizations,
        max_residual: [largest(&h.force_residual), largest(&h.constraint_residual)],
        failures: h
            .failures
            .into_iter()
            .map(|(pose, why)| (grid.values(pose), why))
            .collect(),
        extrapolated,
    };
    Ok((summary, finals))
}

impl Report for PosesSummary {
    fn render(&self, subcase: u32) -> Vec<String> {
        let poses: usize = self.shape.iter().product();
        let solved = poses - self.failures.len();
        let total: u32 = self.iterations.iter().sum();
        let max = self.iterations.iter().max().copied().unwrap_or(0);
        vec![
            format!(
                "subcase {subcase}: multibody statics over FMBPOSE {}: {} pose(s) ({} of JDRIVE {}), {} coordinate(s), {} constraint(s)",
                self.fmbpose,
                poses,
                self.shape
                    .iter()
                    .map(usize::to_string)
                    .collect::<Vec<_>>()
                    .join(" x "),
                self.drives
                    .iter()
                    .map(u32::to_string)
                    .collect::<Vec<_>>()
                    .join(", "),
                self.coordinates,
                self.constraints
            ),
            format!(
                "  Newton: {total} iteration(s) in all, {:.2} per solved pose, at most {max}; {} factorization(s); {} pose(s) from the assembly",
                f64::from(total) / solved.max(1) as f64,
                self.factorizations,
                self.assemblies
            ),
            format!(
                "  {solved} of {poses} pose(s) in equilibrium; largest residuals: force {}, constraint {}",
                sci(self.max_residual[0], 3),
                sci(self.max_residual[1], 3)
            ),
        ]
    }

    fn warnings(&self, subcase: u32) -> Vec<String> {
        let mut w = Vec::new();
        if let Some((values, why)) = self.failures.first() {
            let poses: usize = self.shape.iter().product();
            w.push(format!(
                "subcase {subcase}: {} of {poses} pose(s) have no equilibrium (out of reach or no convergence): converged = 0 and NaN outputs there; the first, at drive values {}: {why}",
                self.failures.len(),
                values
                    .iter()
                    .map(|v| sci(*v, 4))
                    .collect::<Vec<_>>()
                    .join(", ")
            ));
        }
        w.extend(system_warnings(
            subcase,
            &self.redundant,
            &self.extrapolated,
        ));
        w
    }
}
