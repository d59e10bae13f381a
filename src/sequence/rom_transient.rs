//! `SOL TRANSIENT` (109/112) on a pROM artifact (`ROM = 'file.h5'`): M_r q̈ + C_r q̇ + K_r q =
//! S_r u(t) at the subcase's `PVAL` values (thesis eq. 3.31), integrated with the `TINTEG` of
//! the `TSTEP` (BDF1 by default, eq. 2.61; BDF2; generalized-α) from rest.
//!
//! Loads: `DLOAD = sid` selects a DLOAD combination or a TLOAD1 directly; each TLOAD1 takes its
//! DAREA entries, which must name pROM input DOFs (`GRID:component` of `/prom/inputs`), and its
//! TABLED1 or TABLEF (CSV, path relative to the file holding the card) F(t − DELAY), end values
//! held outside the table. TSTEP intervals run one after the
//! other with one factorization each; output every NO steps.
//!
//! Initial conditions: `IC = sid` with TIC cards on input DOFs ([`initial_state`]). Parameters
//! may follow tables of time: PTABLE cards selected by the same `PVAL = id` ([`VaryingProm`]).
//!
//! Written: `/results/<id>/transient/{time (t), displacement, velocity, acceleration (t × k)}`
//! at the pROM's input DOFs (`outputs`, k names), `sensors/<name> (t)` for the pROM's SENSORs
//! (DISP from q, VEL from q̇, ACCEL from q̈), attributes `rom`, `params`, `values` (at the end), `method`, `evaluations`.

use super::driver::{Basis, Driver};
use super::report::{Report, sci};
use super::rom_case::RomAtPoint;
use super::rom_case::extrapolation_warning;
use super::shared::damping_warning;
use super::shared::{method_of, output_rows, parameter_tables};
use super::{Clock, RunContext, RunError, SubcaseSummary};
use crate::deck::Solution;
use crate::deck::case_control::Subcase;
use crate::discretize::loads::place_input;
use crate::discretize::loads::{load_into, load_terms};
use crate::dynamics::integrators::{Backend, Run, integrate_with};
use crate::dynamics::measurement::{Recorder, SensorRows};
use crate::io::{
    read_prom_inputs, read_prom_sensors, set_attr_f64s, set_attr_i64, set_attr_str,
    set_attr_strings, write_f64, write_strings,
};
use crate::model::Model;
use crate::rom::transient::{InputStaticShapes, VaryingProm};

/// What one pROM transient subcase computed.
#[derive(Debug, Clone)]
pub struct RomTransientSummary {
    pub rom: std::path::PathBuf,
    pub method: String,
    pub steps: usize,
    pub outputs: Vec<String>,
    pub extrapolated: Vec<String>,
    /// Largest |displacement| over the outputs and its time.
    pub peak: (f64, f64),
    /// Evaluations of the pROM (1 + the changes of tabulated parameters).
    pub evaluations: usize,
}

/// The TRANSIENT driver on pROM artifacts.
pub struct RomTransient;

impl Driver for RomTransient {
    fn name(&self) -> &'static str {
        "TRANSIENT"
    }

    fn solutions(&self) -> &'static [Solution] {
        &[
            Solution::TransientDirect,
            Solution::TransientModal,
            Solution::Transient,
        ]
    }

    fn basis(&self) -> Basis {
        Basis::Rom
    }

    fn warnings(&self, model: &Model) -> Vec<String> {
        damping_warning(model).into_iter().collect()
    }

    /// Runs every subcase on its pROM.
    fn run(&self, ctx: &RunContext, clock: &mut Clock) -> Result<Vec<SubcaseSummary>, RunError> {
        ctx.model
            .subcases
            .iter()
            .map(|sub| {
                clock.time(format!("subcase {}: pROM transient", sub.id), || {
                    subcase(ctx, sub)
                })
            })
            .collect()
    }
}

fn subcase(ctx: &RunContext, sub: &Subcase) -> Result<SubcaseSummary, RunError> {
    let id = sub.id;
    let case = |what: String| RunError::Case { subcase: id, what };
    let RomAtPoint {
        path,
        prom,
        p,
        at,
        extrapolated,
    } = RomAtPoint::load(ctx, sub)?;
    if ctx.model.params.g != 0.0 && ctx.model.params.w3 > 0.0 {
        return Err(case(format!(
            "PARAM,G = {} with W3 = {}: structural damping is applied by the full-model transient only; a pROM carries the Rayleigh damping of its build (PARAM,ALPHA1 / BETA1)",
            ctx.model.params.g, ctx.model.params.w3
        )));
    }
    let (names, s_r) = read_prom_inputs(&path, prom.size())?;
    let (sensor_names, sensor_kinds, h_r) = read_prom_sensors(&path, prom.size())?;
    let sensors = SensorRows::new(sensor_names, sensor_kinds, h_r)
        .map_err(|e| case(format!("{}: {e}", path.display())))?;
    let (tstep, method, method_name) = method_of(ctx.model, sub)?;
    let loads = match sub.dload {
        None => Vec::new(),
        Some(dload) => load_terms(
            ctx.model,
            dload,
            prom.size(),
            |d, scale, shape| place_input(&names, &s_r, d, scale, shape),
            |_| Ok(None),
        )
        .map_err(case)?
        .applied_only("a reduced model")
        .map_err(|e| RunError::NotAvailable(format!("subcase {}: {e}", sub.id)))?,
    };
    let k = names.len();
    let tables = match sub.pval {
        None => Vec::new(),
        Some(id) => parameter_tables(
            ctx.model,
            id,
            |name| {
                (ctx.model.pval(id).iter())
                    .any(|c| c.values.iter().any(|(n, _)| n.eq_ignore_ascii_case(name)))
            },
            |name| {
                (prom.parameters.iter())
                    .position(|q| q.name.eq_ignore_ascii_case(name))
                    .ok_or_else(|| {
                        let names: Vec<&str> =
                            prom.parameters.iter().map(|q| q.name.as_str()).collect();
                        format!(
                            "{name} is not a parameter of the pROM (parameters: {})",
                            names.join(", ")
                        )
                    })
            },
        )
        .map_err(case)?,
    };
    let mut backend = VaryingProm::new(&prom, at, p, tables, extrapolated);
    backend
        .advance(0.0)
        .map_err(|e| case(format!("{}: {e}", path.display())))?;
    let (mut q, mut v) = initial_state(
        ctx,
        sub,
        &names,
        || InputStaticShapes::new(backend.at.stiffness(), &s_r),
        prom.size(),
    )
    .map_err(case)?;
    let rows = output_rows(&tstep.intervals);
    let mut rec = Recorder::new(&s_r, &sensors, rows);
    let mut t0 = 0.0;
    let mut steps = 0;
    for (interval, &(count, dt, every)) in tstep.intervals.iter().enumerate() {
        let every = every.max(1) as usize;
        let load = |t: f64, f: &mut [f64]| load_into(&loads, t, f);
        let run = Run {
            dt,
            steps: count as usize,
            t0,
        };
        integrate_with(
            &mut backend,
            method,
            run,
            &q.clone(),
            &v.clone(),
            load,
            |s| {
                // the first interval reports its initial state; later ones continue the series
                if (s.step > 0 || interval == 0) && s.step % every == 0 {
                    rec.record(s);
                }
                if s.step == count as usize {
                    q.copy_from_slice(s.q);
                    v.copy_from_slice(s.v);
                }
            },
        )
        .map_err(|e| case(format!("{}: {e}", path.display())))?;
        t0 += count as f64 * dt;
        steps += count as usize;
    }
    let Recorder {
        time,
        disp,
        vel,
        acc,
        series,
        ..
    } = rec;
    let peak = disp.iter().enumerate().fold((0.0_f64, 0.0), |acc, (i, x)| {
        if x.abs() > acc.0 {
            (x.abs(), time[i / k.max(1)])
        } else {
            acc
        }
    });
    let group = ctx.output.group(&format!("results/{id}/transient"))?;
    let rows = time.len();
    write_f64(&group, "time", &time, &[rows])?;
    write_f64(&group, "displacement", &disp, &[rows, k])?;
    write_f64(&group, "velocity", &vel, &[rows, k])?;
    write_f64(&group, "acceleration", &acc, &[rows, k])?;
    let name_refs: Vec<&str> = names.iter().map(String::as_str).collect();
    write_strings(&group, "outputs", &name_refs)?;
    if !sensors.is_empty() {
        let sg = ctx
            .output
            .group(&format!("results/{id}/transient/sensors"))?;
        for (name, series) in sensors.names.iter().zip(series.chunks_exact(rows.max(1))) {
            write_f64(&sg, name, series, &[rows])?;
        }
    }
    set_attr_str(&group, "rom", &path.display().to_string())?;
    set_attr_str(&group, "method", &method_name)?;
    let params: Vec<&str> = prom.parameters.iter().map(|q| q.name.as_str()).collect();
    set_attr_strings(&group, "params", &params)?;
    set_attr_f64s(&group, "values", &backend.p)?;
    set_attr_i64(&group, "evaluations", backend.evaluations as i64)?;
    let summary = RomTransientSummary {
        rom: path,
        method: method_name,
        steps,
        outputs: names,
        extrapolated: backend.outside,
        peak,
        evaluations: backend.evaluations,
    };
    Ok(SubcaseSummary {
        id,
        autospc: Vec::new(),
        result: Box::new(summary),
    })
}

/// The reduced initial state of `IC = sid`. TIC cards name pROM input DOFs (`GRID:component`);
/// inputs without a TIC start at zero. The pROM has no mesh, so the state is defined on its
/// inputs: q0 is the static shape that produces the requested input displacements u0
/// ([`InputStaticShapes`]), and likewise v0 from the initial velocities.
fn initial_state(
    ctx: &RunContext,
    sub: &Subcase,
    names: &[String],
    shapes: impl FnOnce() -> InputStaticShapes,
    n: usize,
) -> Result<(Vec<f64>, Vec<f64>), String> {
    let Some(sid) = sub.ic else {
        return Ok((vec![0.0; n], vec![0.0; n]));
    };
    let cards = ctx.model.tic(sid);
    if cards.is_empty() {
        return Err(format!("IC = {sid} selects no TIC card"));
    }
    let k = names.len();
    let (mut u0, mut v0) = (vec![0.0; k], vec![0.0; k]);
    for c in cards {
        let name = format!("{}:{}", c.grid, c.component);
        let j = names.iter().position(|x| *x == name).ok_or_else(|| format!("TIC {sid}: GRID {} component {} is not an input DOF of the pROM (inputs: {}); a pROM's initial state is defined on its inputs", c.grid, c.component, names.join(", ")))?;
        u0[j] += c.u0;
        v0[j] += c.v0;
    }
    let shapes = shapes();
    let shape = |u: &[f64]| {
        shapes.shape(u).ok_or_else(|| format!(
            "TIC {sid}: the pROM's stiffness (or its input flexibility) is singular, so no static shape gives the requested input displacements (a free-free pROM needs initial conditions through its rigid-body-free inputs)"
        ))
    };
    Ok((shape(&u0)?, shape(&v0)?))
}

impl Report for RomTransientSummary {
    fn render(&self, subcase: u32) -> Vec<String> {
        let r = self;
        vec![
            format!(
                "subcase {}: transient of the pROM {} ({}), {} step(s), outputs {}",
                subcase,
                r.rom.display(),
                r.method,
                r.steps,
                r.outputs.join(", ")
            ),
            format!(
                "  largest |displacement| {} at t = {} s",
                sci(r.peak.0, 4),
                sci(r.peak.1, 4)
            ),
        ]
    }

    fn warnings(&self, subcase: u32) -> Vec<String> {
        extrapolation_warning(subcase, &self.extrapolated, &self.rom)
            .into_iter()
            .collect()
    }
}
