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
//! Written: `/results/<id>/transient/{time (t), displacement, velocity, acceleration (t × k)}`
//! at the pROM's input DOFs (`outputs`, k names), `sensors/<name> (t)` for the pROM's SENSORs
//! (DISP from q, VEL from q̇, ACCEL from q̈), attributes `rom`, `params`, `values`, `method`.

use faer::Mat;

use super::rom_case::RomAtPoint;
use super::transient::{load_into, load_terms, method_of, output_rows};
use crate::deck::cards::Darea;
use super::{Clock, RunContext, RunError, SubcaseResult, SubcaseSummary};
use crate::deck::case_control::Subcase;
use crate::dynamics::integrators::{Dense, LinearSystem, Run, StepState, integrate_with, matvec_add};
use crate::io::{read_prom_inputs, read_prom_sensors, set_attr_f64s, set_attr_str, set_attr_strings, write_f64, write_strings};

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
}

/// Runs every subcase on its pROM.
pub fn run(ctx: &RunContext, clock: &mut Clock) -> Result<Vec<SubcaseSummary>, RunError> {
    ctx.model.subcases.iter().map(|sub| clock.time(format!("subcase {}: pROM transient", sub.id), || subcase(ctx, sub))).collect()
}

fn subcase(ctx: &RunContext, sub: &Subcase) -> Result<SubcaseSummary, RunError> {
    let id = sub.id;
    let case = |what: String| RunError::Case { subcase: id, what };
    let RomAtPoint { path, prom, p, at, extrapolated } = RomAtPoint::load(ctx, sub)?;
    let (names, s_r) = read_prom_inputs(&path, prom.size())?;
    let (sensor_names, sensor_kinds, h_r) = read_prom_sensors(&path, prom.size())?;
    let (tstep, method, method_name) = method_of(ctx, sub)?;
    let loads = match sub.dload {
        None => Vec::new(),
        Some(dload) => load_terms(ctx, dload, prom.size(), |d, comp, scale, shape| place_input(&names, &s_r, d, comp, scale, shape), |_| Ok(None)).map_err(case)?,
    };
    let n = prom.size();
    let k = names.len();
    let sys = LinearSystem { mass: at.mass.as_ref(), damping: at.damping.as_ref(), stiffness: at.stiffness.as_ref() };
    let mut backend = Dense::new(sys).map_err(|e| case(format!("{}: {e}", path.display())))?;
    let rows = output_rows(&tstep.intervals);
    let mut rec = Recorder::new(&s_r, &sensor_kinds, &h_r, rows);
    let (mut q, mut v) = (vec![0.0; n], vec![0.0; n]);
    let mut t0 = 0.0;
    let mut steps = 0;
    for (interval, &(count, dt, every)) in tstep.intervals.iter().enumerate() {
        let every = every.max(1) as usize;
        let load = |t: f64, f: &mut [f64]| load_into(&loads, t, f);
        let run = Run { dt, steps: count as usize, t0 };
        integrate_with(&mut backend, method, run, &q.clone(), &v.clone(), load, |s| {
            // the first interval reports its initial state; later ones continue the series
            if (s.step > 0 || interval == 0) && s.step % every == 0 {
                rec.record(s);
            }
            if s.step == count as usize {
                q.copy_from_slice(s.q);
                v.copy_from_slice(s.v);
            }
        })
        .map_err(|e| case(format!("{}: {e}", path.display())))?;
        t0 += count as f64 * dt;
        steps += count as usize;
    }
    let Recorder { time, disp, vel, acc, sensors, .. } = rec;
    let peak = disp.iter().enumerate().fold((0.0_f64, 0.0), |acc, (i, x)| if x.abs() > acc.0 { (x.abs(), time[i / k.max(1)]) } else { acc });
    let group = ctx.output.group(&format!("results/{id}/transient"))?;
    let rows = time.len();
    write_f64(&group, "time", &time, &[rows])?;
    write_f64(&group, "displacement", &disp, &[rows, k])?;
    write_f64(&group, "velocity", &vel, &[rows, k])?;
    write_f64(&group, "acceleration", &acc, &[rows, k])?;
    let name_refs: Vec<&str> = names.iter().map(String::as_str).collect();
    write_strings(&group, "outputs", &name_refs)?;
    if !sensor_names.is_empty() {
        let sg = ctx.output.group(&format!("results/{id}/transient/sensors"))?;
        for (name, series) in sensor_names.iter().zip(sensors.chunks_exact(rows.max(1))) {
            write_f64(&sg, name, series, &[rows])?;
        }
    }
    set_attr_str(&group, "rom", &path.display().to_string())?;
    set_attr_str(&group, "method", &method_name)?;
    let params: Vec<&str> = prom.parameters.iter().map(|q| q.name.as_str()).collect();
    set_attr_strings(&group, "params", &params)?;
    set_attr_f64s(&group, "values", &p)?;
    let summary = RomTransientSummary { rom: path, method: method_name, steps, outputs: names, extrapolated, peak };
    Ok(SubcaseSummary { id, autospc: Vec::new(), result: SubcaseResult::RomTransient(summary) })
}

/// Adds a DAREA entry, which must name a pROM input DOF (`GRID:component`), to a reduced load
/// shape: scale × column of S_r.
fn place_input(names: &[String], s_r: &Mat<f64>, d: &Darea, comp: usize, scale: f64, shape: &mut [f64]) -> Result<(), String> {
    let name = format!("{}:{comp}", d.grid);
    let j = names.iter().position(|x| *x == name).ok_or_else(|| format!("DAREA {}: GRID {} component {comp} is not an input DOF of the pROM (inputs: {})", d.sid, d.grid, names.join(", ")))?;
    shape.iter_mut().enumerate().for_each(|(i, s)| *s += scale * s_r[(i, j)]);
    Ok(())
}

/// Output buffers sized before the run, filled by matrix–vector products (no allocation in the
/// time loop): input-DOF series rows × k (row-major, column r of a k × rows column-major
/// buffer), and per sensor a series of `rows` values (sensor-major).
struct Recorder {
    /// S_rᵀ (k × n).
    s_t: Mat<f64>,
    /// Per sensor kind (DISP from q, VEL from q̇, ACCEL from q̈): its rows of H_r and their
    /// sensor indices.
    by_kind: [(Mat<f64>, Vec<usize>); 3],
    scratch: Vec<f64>,
    rows: usize,
    time: Vec<f64>,
    disp: Vec<f64>,
    vel: Vec<f64>,
    acc: Vec<f64>,
    sensors: Vec<f64>,
}

impl Recorder {
    fn new(s_r: &Mat<f64>, kinds: &[String], h_r: &Mat<f64>, rows: usize) -> Self {
        let (n, k) = (s_r.nrows(), s_r.ncols());
        let of_kind = |kind: &str| {
            let idx: Vec<usize> = kinds.iter().enumerate().filter(|(_, x)| match kind {
                "VEL" | "ACCEL" => x.as_str() == kind,
                _ => x.as_str() != "VEL" && x.as_str() != "ACCEL",
            }).map(|(i, _)| i).collect();
            (Mat::from_fn(idx.len(), n, |r, c| h_r[(idx[r], c)]), idx)
        };
        Recorder {
            s_t: s_r.transpose().to_owned(),
            by_kind: [of_kind("DISP"), of_kind("VEL"), of_kind("ACCEL")],
            scratch: vec![0.0; kinds.len()],
            rows,
            time: Vec::with_capacity(rows),
            disp: Vec::with_capacity(rows * k),
            vel: Vec::with_capacity(rows * k),
            acc: Vec::with_capacity(rows * k),
            sensors: vec![0.0; kinds.len() * rows],
        }
    }

    fn record(&mut self, s: &StepState<'_>) {
        let r = self.time.len();
        if r == self.rows {
            return;
        }
        self.time.push(s.time);
        let k = self.s_t.nrows();
        for (out, x) in [(&mut self.disp, s.q), (&mut self.vel, s.v), (&mut self.acc, s.a)] {
            out.resize(out.len() + k, 0.0);
            let end = out.len();
            matvec_add(&self.s_t, x, &mut out[end - k..]);
        }
        for ((h, idx), x) in self.by_kind.iter().zip([s.q, s.v, s.a]) {
            let y = &mut self.scratch[..idx.len()];
            y.fill(0.0);
            matvec_add(h, x, y);
            for (&j, value) in idx.iter().zip(y.iter()) {
                self.sensors[j * self.rows + r] = *value;
            }
        }
    }
}
