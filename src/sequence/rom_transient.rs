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
use super::{Clock, RunContext, RunError, SubcaseResult, SubcaseSummary};
use crate::deck::case_control::Subcase;
use crate::dynamics::integrators::{Dense, LinearSystem, Method, Run, StepState, integrate_with, matvec_add};
use crate::dynamics::table::Table;
use crate::io::csv_table::read_columns;
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

/// One load term: reduced shape × table(t − delay).
struct LoadTerm {
    shape: Vec<f64>,
    table: Table,
    delay: f64,
}

/// Runs every subcase on its pROM.
pub fn run(ctx: &RunContext, clock: &mut Clock) -> Result<Vec<SubcaseSummary>, RunError> {
    ctx.model.subcases.iter().map(|sub| clock.time(format!("subcase {}: pROM transient", sub.id), || subcase(ctx, sub))).collect()
}

fn subcase(ctx: &RunContext, sub: &Subcase) -> Result<SubcaseSummary, RunError> {
    let id = sub.id;
    let case = |what: String| RunError::Case { subcase: id, what };
    let b = &ctx.model.bulk;
    let RomAtPoint { path, prom, p, at, extrapolated } = RomAtPoint::load(ctx, sub)?;
    let (names, s_r) = read_prom_inputs(&path, prom.size())?;
    let (sensor_names, sensor_kinds, h_r) = read_prom_sensors(&path, prom.size())?;
    let sid = sub.tstep.ok_or_else(|| case("SOL TRANSIENT needs TSTEP = <sid> in case control".into()))?;
    let tstep = b.tstep.iter().find(|t| t.sid == sid).ok_or_else(|| case(format!("TSTEP = {sid} selects no TSTEP card")))?;
    let (method, method_name) = match b.tinteg.iter().find(|t| t.id == sid) {
        None => (Method::Bdf1, "BDF1".to_string()),
        Some(t) => match t.method {
            "BDF2" => (Method::Bdf2, "BDF2".to_string()),
            "GALPHA" => (Method::GeneralizedAlpha { rho_inf: t.rho_inf }, format!("GALPHA (rho_inf = {})", t.rho_inf)),
            _ => (Method::Bdf1, "BDF1".to_string()),
        },
    };
    let loads = match sub.dload {
        None => Vec::new(),
        Some(dload) => load_terms(ctx, dload, &names, &s_r).map_err(case)?,
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
        let load = |t: f64, f: &mut [f64]| {
            f.fill(0.0);
            for term in &loads {
                let a = term.table.value(t - term.delay);
                if a != 0.0 {
                    f.iter_mut().zip(&term.shape).for_each(|(fi, s)| *fi += a * s);
                }
            }
        };
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

/// The load terms of `DLOAD = sid`: a DLOAD combination S·Σ Sᵢ·(TLOAD1 Lᵢ), or one TLOAD1.
fn load_terms(ctx: &RunContext, sid: u32, names: &[String], s_r: &Mat<f64>) -> Result<Vec<LoadTerm>, String> {
    let b = &ctx.model.bulk;
    let sets: Vec<(f64, u32)> = match b.dload.iter().find(|d| d.sid == sid) {
        Some(d) => d.terms.iter().map(|&(s, l)| (d.scale * s, l)).collect(),
        None => vec![(1.0, sid)],
    };
    let mut out = Vec::new();
    for (scale, set) in sets {
        let tloads: Vec<_> = b.tload1.iter().filter(|t| t.sid == set).collect();
        if tloads.is_empty() {
            return Err(format!("DLOAD {sid}: load set {set} has no TLOAD1"));
        }
        for t in tloads {
            let table = match (b.tabled1.iter().find(|x| x.id == t.tid), b.tablef.iter().find(|x| x.id == t.tid)) {
                (Some(x), _) => Table::new(&x.points).map_err(|e| format!("TABLED1 {}: {e}", t.tid))?,
                (None, Some(x)) => {
                    let csv = x.loc.file.parent().map_or_else(|| std::path::PathBuf::from(&x.path), |dir| dir.join(&x.path));
                    let points = read_columns(&csv, &x.tcol, &x.ycol).map_err(|e| format!("TABLEF {}: {e}", t.tid))?;
                    Table::new(&points).map_err(|e| format!("TABLEF {} ({}): {e}", t.tid, csv.display()))?
                }
                (None, None) => return Err(format!("TLOAD1 {}: TID {} is no TABLED1 or TABLEF", t.sid, t.tid)),
            };
            let mut shape = vec![0.0; s_r.nrows()];
            let mut any = false;
            for d in b.darea.iter().filter(|d| d.sid == t.excite_id) {
                for comp in d.components.components() {
                    let name = format!("{}:{comp}", d.grid);
                    let j = names.iter().position(|x| *x == name).ok_or_else(|| format!("DAREA {}: GRID {} component {comp} is not an input DOF of the pROM (inputs: {})", d.sid, d.grid, names.join(", ")))?;
                    shape.iter_mut().enumerate().for_each(|(i, s)| *s += scale * d.scale * s_r[(i, j)]);
                    any = true;
                }
            }
            if !any {
                return Err(format!("TLOAD1 {}: EXCITEID {} selects no DAREA", t.sid, t.excite_id));
            }
            out.push(LoadTerm { shape, table, delay: t.delay });
        }
    }
    Ok(out)
}

/// Number of output rows of a TSTEP: the initial state, then every NO-th step of each interval.
fn output_rows(intervals: &[(u32, f64, u32)]) -> usize {
    1 + intervals.iter().map(|&(count, _, every)| count as usize / every.max(1) as usize).sum::<usize>()
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
