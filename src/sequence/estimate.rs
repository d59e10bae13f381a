//! `SOL ESTIMATE` on a pROM artifact (`ROM = 'file.h5'`): joint estimation of states, unknown
//! inputs and parameters with the augmented EKF of [`crate::estimate`] (thesis ch. 8).
//!
//! Case control: `ESTIM = id` (EKF card with its EKFPAR / EKFINP), `MEAS = id` (MEASF with its
//! MEAS channels), `TSTEP` (the filter step: one Δt for all intervals), `DLOAD` (known inputs,
//! TLOAD1 on pROM input DOFs, as in SOL TRANSIENT), `PVAL` (values of the parameters that are
//! not estimated).
//!
//! Measurements are read from the CSV and interpolated linearly onto t_k = k Δt (thesis §8.7);
//! the window must lie inside the measured time range. CSV columns named like a pROM SENSOR
//! that no MEAS uses serve as references for that (virtual) sensor's AAE; columns named like
//! an estimated parameter (or an unknown input `GRID:COMP`) hold its true value for the error
//! table (numerical validation, §8.6).
//!
//! Before the run, the PBH test ([`crate::estimate::observability`]) runs at operating points
//! of the initial estimate ([`crate::estimate::operating_points`]: the static equilibrium under
//! the loads whose table is constant over the window, plus states of a BDF1 simulation of the
//! time-varying loads; unknown inputs count as static when every measured channel is at the
//! noise level σ of its MEAS card). An unobservable problem stops the run with its cause unless
//! the EKF card says FORCE = YES.
//!
//! Written under `/results/<id>/estimate/`: `time (t)`; `params/<name>`, `params_sigma/<name>`
//! (t: estimate and standard deviation, ±3σ bands are 3 × the latter); `inputs/<GRID:COMP>`,
//! `inputs_sigma/<GRID:COMP>`; `sensors/<name>` (t, every pROM sensor, measured or virtual,
//! posterior; attributes `measured`, and `aae`, `mra` when the CSV has a reference);
//! `innovation/<name>` (t, measured sensors); `error_table` (rows × 3: min, avg, max relative
//! error in % over the last 20 % of the window, attribute `rows`); attributes `rom`,
//! `observability`, `forced`, `steps_per_second`, `coordinates` (`modal`, `rediagonalized` —
//! EKF REDIAG, with `rediagonalizations`, the number of times the modes were recomputed — or
//! `physical`: the filter's coordinates, [`crate::estimate::filter`]), `prediction` (`TRAP` or
//! `BDF1`, the EKF card's PREDICT).

use super::driver::{Basis, Driver};
use crate::deck::Solution;
use std::path::{Path, PathBuf};
use std::time::Instant;

use super::report::{Report, sci};
use super::rom_case::RomAtPoint;
use super::rom_case::extrapolation_warning;
use super::{Clock, RunContext, RunError, SubcaseSummary};
use crate::card_values::Column;
use crate::deck::case_control::Subcase;
use crate::discretize::loads::place_input;
use crate::discretize::loads::{LoadTerm, input_columns, load_into_where, load_terms};
use crate::dynamics::table::Table;
use crate::estimate::errors::{absolute_error, percent_errors};
use crate::estimate::filter::check_initial_stiffness;
use crate::estimate::observability::{self, Unknown};
use crate::estimate::operating_points;
use crate::estimate::prom_linearization::PromLinearization;
use crate::estimate::{Coordinates, Filter, FilterSetup, SensorRows, covariance};
use crate::io::csv_table::{header, read_columns};
use crate::io::{
    read_prom_inputs, read_prom_sensors, set_attr_f64, set_attr_i64, set_attr_str,
    set_attr_strings, write_f64,
};
use crate::rom::modes::ReducedModes;

/// Relative error statistics of one estimated quantity over the last 20 % (thesis Table 8.2).
#[derive(Debug, Clone, PartialEq)]
pub struct ErrorRow {
    pub name: String,
    /// Percent.
    pub min: f64,
    pub avg: f64,
    pub max: f64,
}

/// What one estimation subcase computed.
#[derive(Debug, Clone)]
pub struct EstimateSummary {
    pub rom: PathBuf,
    pub steps: usize,
    /// (name, final estimate, final σ) per estimated parameter.
    pub params: Vec<(String, f64, f64)>,
    pub error_table: Vec<ErrorRow>,
    /// (sensor, AAE, MRA) for sensors with a reference column.
    pub sensor_errors: Vec<(String, f64, f64)>,
    /// The PBH verdict, in words.
    pub observability: String,
    /// Unobservable but run because of FORCE = YES.
    pub forced: bool,
    pub hidden_modes: Vec<(usize, f64)>,
    pub extrapolated: Vec<String>,
    pub steps_per_second: f64,
    /// The filter's coordinates ([`crate::estimate::filter`]): `modal`, `rediagonalized` or
    /// `physical`, as the HDF5 attribute `coordinates`.
    pub coordinates: &'static str,
    /// How many times re-diagonalized coordinates recomputed their modes.
    pub rediagonalizations: Option<usize>,
}

/// The ESTIMATE driver on pROM artifacts.
pub struct Estimate;

impl Driver for Estimate {
    fn name(&self) -> &'static str {
        "ESTIMATE"
    }

    fn solutions(&self) -> &'static [Solution] {
        &[Solution::Estimate]
    }

    fn basis(&self) -> Basis {
        Basis::Rom
    }

    /// Runs every subcase on its pROM.
    fn run(&self, ctx: &RunContext, clock: &mut Clock) -> Result<Vec<SubcaseSummary>, RunError> {
        ctx.model
            .subcases
            .iter()
            .map(|sub| {
                clock.time(format!("subcase {}: estimation", sub.id), || {
                    subcase(ctx, sub)
                })
            })
            .collect()
    }
}

fn subcase(ctx: &RunContext, sub: &Subcase) -> Result<SubcaseSummary, RunError> {
    let id = sub.id;
    let case = |what: String| RunError::Case { subcase: id, what };
    let model = ctx.model;
    let RomAtPoint {
        path,
        prom,
        mut p,
        extrapolated,
        ..
    } = RomAtPoint::load(ctx, sub)?;
    let n = prom.size();
    let selection = Selection::of(model, sub)?;
    let csv = selection.csv();
    let Selection {
        ekf_id,
        ekf,
        meas_id,
        measf,
        channels,
        dt,
        steps,
    } = selection;

    // unknowns
    let param_names: Vec<&str> = prom.parameters.iter().map(|q| q.name.as_str()).collect();
    let mut unknown_params = Vec::new();
    for par in model.ekfpar(ekf_id) {
        let j = param_names
            .iter()
            .position(|q| q.eq_ignore_ascii_case(&par.name))
            .ok_or_else(|| {
                case(format!(
                    "EKFPAR {ekf_id}: {} is not a parameter of {} (parameters: {})",
                    par.name,
                    path.display(),
                    param_names.join(", ")
                ))
            })?;
        if unknown_params.iter().any(|(k, _)| *k == j) {
            return Err(case(format!(
                "EKFPAR {ekf_id}: {} is listed twice",
                par.name
            )));
        }
        p[j] = par.init;
        unknown_params.push((j, par));
    }
    let (input_names, s_r) = read_prom_inputs(&path, n)?;
    let mut unknown_inputs = Vec::new();
    for inp in model.ekfinp(ekf_id) {
        let component = inp.component.ok_or_else(|| {
            case(format!(
                "{}: EKFINP {ekf_id}: field 4 (COMP): a pROM input DOF needs its component 1–6",
                inp.loc
            ))
        })?;
        let name = format!("{}:{component}", inp.grid);
        let j = input_names.iter().position(|x| *x == name).ok_or_else(|| case(format!("EKFINP {ekf_id}: GRID {} component {component} is not an input DOF of the pROM (inputs: {})", inp.grid, input_names.join(", "))))?;
        unknown_inputs.push((j, name, inp));
    }
    let s_un = input_columns(
        &s_r,
        &unknown_inputs
            .iter()
            .map(|(j, _, _)| *j)
            .collect::<Vec<_>>(),
    );

    // sensors and measurements
    let (sensor_names, sensor_kinds, h_r) = read_prom_sensors(&path, n)?;
    let sensors = SensorRows::new(sensor_names, sensor_kinds, h_r)
        .map_err(|e| case(format!("{}: {e}", path.display())))?;
    let window = (dt, steps as f64 * dt);
    let mut measured_rows = Vec::new();
    let mut measured_series = Vec::new();
    for m in &channels {
        let r = sensors
            .names
            .iter()
            .position(|x| x.eq_ignore_ascii_case(&m.sensor))
            .ok_or_else(|| {
                case(format!(
                    "MEAS {meas_id}: {} is not a SENSOR of {} (sensors: {})",
                    m.sensor,
                    path.display(),
                    sensors.names.join(", ")
                ))
            })?;
        measured_rows.push(r);
        measured_series.push(
            resample(&csv, &measf.tcol, &m.column, window, steps)
                .map_err(|e| case(format!("{}: MEAS {meas_id} {}: {e}", m.loc, m.sensor)))?,
        );
    }
    let measured = sensors.select(&measured_rows);
    let sigma: Vec<f64> = channels.iter().map(|m| m.sigma).collect();
    let header = header(&csv).map_err(|e| case(format!("{}: MEASF {meas_id}: {e}", measf.loc)))?;
    let reference = |name: &str| -> Result<Option<Vec<f64>>, RunError> {
        match header.iter().any(|h| h.eq_ignore_ascii_case(name)) {
            true => resample(
                &csv,
                &measf.tcol,
                &Column::Name(name.to_string()),
                window,
                steps,
            )
            .map(Some)
            .map_err(|e| {
                case(format!(
                    "{}: MEASF {meas_id} reference {name}: {e}",
                    measf.loc
                ))
            }),
            false => Ok(None),
        }
    };

    // known loads, filter setup, observability
    let loads = match sub.dload {
        None => Vec::new(),
        Some(dload) => load_terms(
            ctx.model,
            dload,
            n,
            |d, scale, shape| place_input(&input_names, &s_r, d, scale, shape),
            |_| Ok(None),
        )
        .map_err(case)?
        .applied_only("a pROM estimation")
        .map_err(|e| RunError::NotAvailable(format!("subcase {}: {e}", sub.id)))?,
    };
    let load_at = |t: f64, f: &mut [f64], which: &dyn Fn(&LoadTerm) -> bool| {
        load_into_where(&loads, t, f, which)
    };
    let setup = FilterSetup {
        p: p.clone(),
        unknown_params: unknown_params.iter().map(|(j, _)| *j).collect(),
        s_un: s_un.clone(),
        measured: measured.clone(),
        r: sigma.iter().map(|s| s * s).collect(),
        dt,
        q_state: ekf.q_state,
        q_inputs: unknown_inputs
            .iter()
            .map(|(_, _, u)| covariance::input(dt, u.omega, u.amplitude))
            .collect(),
        q_params: unknown_params
            .iter()
            .map(|(_, par)| covariance::parameter(dt, par.delta, par.init))
            .collect(),
        q0: vec![0.0; n],
        v0: vec![0.0; n],
        u0: vec![0.0; unknown_inputs.len()],
        p0_state: ekf.p0_state,
        p0_inputs: unknown_inputs
            .iter()
            .map(|(_, _, u)| u.amplitude * u.amplitude)
            .collect(),
        p0_params: unknown_params.iter().map(|(_, par)| par.p0).collect(),
        coordinates: ekf
            .rediagonalize
            .map_or(Coordinates::Auto, Coordinates::Rediagonalized),
        prediction: ekf.prediction,
        prom: prom.clone(),
    };
    let mut at = prom.workspace();
    prom.evaluate(&p, &mut at)
        .map_err(|e| case(format!("{}: {e}", path.display())))?;
    check_initial_stiffness(at.stiffness(), &p).map_err(|e| case(format!("EKF {ekf_id}: {e}")))?;
    let static_inputs = operating_points::at_noise_level(&measured_series, &sigma);
    let inputs_for_points: Vec<(f64, f64)> = unknown_inputs
        .iter()
        .map(|(_, _, u)| (u.omega, u.amplitude))
        .collect();
    let constant =
        |term: &LoadTerm| (1..=steps).all(|k| term.factor(k as f64 * dt) == term.factor(dt));
    let points = operating_points::of_initial_estimate(
        &at,
        &s_un,
        &inputs_for_points,
        static_inputs,
        dt,
        steps,
        &|t, f, static_part| load_at(t, f, &|term| constant(term) == static_part),
    )
    .map_err(|e| case(format!("observability check: {e}")))?;
    let mut unknowns: Vec<Unknown> = unknown_inputs
        .iter()
        .map(|(_, name, _)| Unknown::Input(name.clone()))
        .collect();
    unknowns.extend(unknown_params.iter().map(|(j, _)| {
        let (stiffness, mass) = at.sensitive_to(*j);
        Unknown::Parameter {
            name: prom.parameters[*j].name.clone(),
            stiffness,
            mass,
        }
    }));
    let modes = ReducedModes::of(&at).map_err(|e| {
        case(format!(
            "{}: modes of the initial estimate: {e}",
            path.display()
        ))
    })?;
    let linearization = PromLinearization {
        at: &at,
        alpha_beta: (prom.alpha, prom.beta),
        s_un: &s_un,
        params: &setup.unknown_params,
        unknowns: &unknowns,
        measured: &measured,
        modes: (&modes.eigenvalues, &modes.shapes),
    };
    let verdict = observability::check(&linearization, &points);
    let observability_text = match &verdict.cause {
        None => format!(
            "observable: PBH(0) rank {} of {} (σ_min/σ_max {:.1e}, tolerance {:e})",
            verdict.rank,
            verdict.columns,
            verdict.ratio,
            observability::RANK_TOLERANCE
        ),
        Some(cause) => format!(
            "unobservable: PBH(0) rank {} of {} (tolerance {:e}): {cause}",
            verdict.rank,
            verdict.columns,
            observability::RANK_TOLERANCE
        ),
    };
    if !verdict.observable() && !ekf.force {
        return Err(case(format!(
            "the estimation problem is {observability_text}. Change the sensors, unknowns or loads, or set FORCE = YES on EKF {ekf_id} to run anyway"
        )));
    }

    // the filter
    let mut filter = Filter::new(setup).map_err(|e| case(e.to_string()))?;
    let mut f0 = vec![0.0; n];
    load_at(0.0, &mut f0, &|_| true);
    filter
        .set_initial_load(&f0)
        .map_err(|e| case(e.to_string()))?;
    let (nu, np) = (unknown_inputs.len(), unknown_params.len());
    let big_n = filter.size();
    let mut time = Vec::with_capacity(steps);
    let mut params_hist = vec![Vec::with_capacity(steps); np];
    let mut params_sigma = vec![Vec::with_capacity(steps); np];
    let mut inputs_hist = vec![Vec::with_capacity(steps); nu];
    let mut inputs_sigma = vec![Vec::with_capacity(steps); nu];
    let mut sensor_hist = vec![Vec::with_capacity(steps); sensors.len()];
    let mut innovation = vec![Vec::with_capacity(steps); measured.len()];
    let (mut f, mut y, mut y_all) = (
        vec![0.0; n],
        vec![0.0; measured.len()],
        vec![0.0; sensors.len()],
    );
    // virtual sensors from the filter's own coordinates (rows remade after a re-diagonalization)
    let mut rows_of = (filter.rediagonalizations(), filter.sensor_rows(&sensors));
    let started = Instant::now();
    for k in 1..=steps {
        let t = k as f64 * dt;
        load_at(t, &mut f, &|_| true);
        y.iter_mut()
            .zip(&measured_series)
            .for_each(|(y, s)| *y = s[k - 1]);
        filter
            .step(&f, &y)
            .map_err(|e| case(format!("t = {t}: {e}")))?;
        if filter.rediagonalizations() != rows_of.0 {
            rows_of = (filter.rediagonalizations(), filter.sensor_rows(&sensors));
        }
        let (x, acceleration) = filter.filter_state();
        time.push(t);
        for c in 0..nu {
            inputs_hist[c].push(x[2 * n + c]);
            inputs_sigma[c].push(filter.variance(2 * n + c).max(0.0).sqrt());
        }
        for c in 0..np {
            let i = big_n - np + c;
            params_hist[c].push(x[i]);
            params_sigma[c].push(filter.variance(i).max(0.0).sqrt());
        }
        rows_of
            .1
            .evaluate(&x[..n], &x[n..2 * n], acceleration, &mut y_all);
        sensor_hist
            .iter_mut()
            .zip(&y_all)
            .for_each(|(h, v)| h.push(*v));
        innovation
            .iter_mut()
            .zip(filter.innovation())
            .for_each(|(h, v)| h.push(*v));
    }
    let elapsed = started.elapsed().as_secs_f64();

    // errors: last 20 % of the window (thesis §8.6, Table 8.2)
    let mut error_table = Vec::new();
    let named_series = unknown_params
        .iter()
        .map(|(j, _)| prom.parameters[*j].name.clone())
        .zip(&params_hist)
        .chain(
            unknown_inputs
                .iter()
                .map(|(_, name, _)| name.clone())
                .zip(&inputs_hist),
        );
    for (name, series) in named_series {
        if let Some(truth) = reference(&name)? {
            let e = percent_errors(series, &truth);
            error_table.push(ErrorRow {
                name,
                min: e.min,
                avg: e.avg,
                max: e.max,
            });
        }
    }
    let mut sensor_errors = Vec::new();
    for (r, name) in sensors.names.iter().enumerate() {
        let truth = match measured_rows.iter().position(|&m| m == r) {
            Some(c) if reference(name)?.is_none() => Some(measured_series[c].clone()),
            _ => reference(name)?,
        };
        if let Some(truth) = truth {
            let (aae, mra) = absolute_error(&sensor_hist[r], &truth);
            sensor_errors.push((name.clone(), aae, mra));
        }
    }

    // output
    let root = format!("results/{id}/estimate");
    let group = ctx.output.group(&root)?;
    write_f64(&group, "time", &time, &[steps])?;
    let series_group =
        |sub_name: &str, names: &[String], data: &[Vec<f64>]| -> Result<(), RunError> {
            if names.is_empty() {
                return Ok(());
            }
            let g = ctx.output.group(&format!("{root}/{sub_name}"))?;
            for (name, series) in names.iter().zip(data) {
                write_f64(&g, name, series, &[series.len()])?;
            }
            Ok(())
        };
    let pnames: Vec<String> = unknown_params
        .iter()
        .map(|(j, _)| prom.parameters[*j].name.clone())
        .collect();
    let inames: Vec<String> = unknown_inputs
        .iter()
        .map(|(_, name, _)| name.clone())
        .collect();
    series_group("params", &pnames, &params_hist)?;
    series_group("params_sigma", &pnames, &params_sigma)?;
    series_group("inputs", &inames, &inputs_hist)?;
    series_group("inputs_sigma", &inames, &inputs_sigma)?;
    series_group("sensors", &sensors.names, &sensor_hist)?;
    series_group("innovation", &measured.names, &innovation)?;
    if !sensors.is_empty() {
        let g = ctx.output.group(&format!("{root}/sensors"))?;
        for (r, name) in sensors.names.iter().enumerate() {
            let ds = g.dataset(name).map_err(|e| {
                crate::io::IoError::hdf5(
                    ctx.output.path(),
                    format!("open {root}/sensors/{name}"),
                    e,
                )
            })?;
            set_attr_i64(&ds, "measured", i64::from(measured_rows.contains(&r)))?;
            if let Some((_, aae, mra)) = sensor_errors.iter().find(|(s, _, _)| s == name) {
                set_attr_f64(&ds, "aae", *aae)?;
                set_attr_f64(&ds, "mra", *mra)?;
            }
        }
    }
    let table: Vec<f64> = error_table
        .iter()
        .flat_map(|r| [r.min, r.avg, r.max])
        .collect();
    let table_ds = write_f64(&group, "error_table", &table, &[error_table.len(), 3])?;
    set_attr_strings(
        &table_ds,
        "rows",
        &error_table
            .iter()
            .map(|r| r.name.as_str())
            .collect::<Vec<_>>(),
    )?;
    set_attr_strings(
        &table_ds,
        "columns",
        &["min_percent", "avg_percent", "max_percent"],
    )?;
    set_attr_str(&group, "rom", &path.display().to_string())?;
    set_attr_str(&group, "observability", &observability_text)?;
    set_attr_i64(&group, "forced", i64::from(!verdict.observable()))?;
    let steps_per_second = steps as f64 / elapsed.max(f64::MIN_POSITIVE);
    set_attr_f64(&group, "steps_per_second", steps_per_second)?;
    let coordinates = match (filter.modal(), filter.rediagonalizations()) {
        (false, _) => "physical",
        (true, None) => "modal",
        (true, Some(count)) => {
            set_attr_i64(
                &group,
                "rediagonalizations",
                i64::try_from(count).unwrap_or(i64::MAX),
            )?;
            "rediagonalized"
        }
    };
    set_attr_str(&group, "coordinates", coordinates)?;
    set_attr_str(&group, "prediction", ekf.prediction.card_name())?;
    let params = (0..np)
        .map(|c| {
            (
                pnames[c].clone(),
                params_hist[c][steps - 1],
                params_sigma[c][steps - 1],
            )
        })
        .collect();
    let summary = EstimateSummary {
        rom: path,
        steps,
        params,
        error_table,
        sensor_errors,
        observability: observability_text,
        forced: !verdict.observable(),
        hidden_modes: verdict.hidden_modes,
        extrapolated,
        steps_per_second,
        coordinates,
        rediagonalizations: filter.rediagonalizations(),
    };
    Ok(SubcaseSummary {
        id,
        autospc: Vec::new(),
        result: Box::new(summary),
    })
}

/// What an estimation subcase selects in case control: the EKF (`ESTIM`), the measurement
/// file and its channels (`MEAS`), and the filter step Δt with the number of steps (`TSTEP`,
/// one Δt for all intervals). Shared by the pROM and the mechanism estimators.
pub(super) struct Selection<'a> {
    pub ekf_id: u32,
    pub ekf: &'a crate::deck::cards::Ekf,
    pub meas_id: u32,
    pub measf: &'a crate::deck::cards::Measf,
    pub channels: Vec<&'a crate::deck::cards::Meas>,
    pub dt: f64,
    pub steps: usize,
}

impl<'a> Selection<'a> {
    /// The selections of `sub`, each missing or dangling one an error naming the statement.
    pub fn of(model: &'a crate::model::Model, sub: &Subcase) -> Result<Self, RunError> {
        let case = |what: String| RunError::Case {
            subcase: sub.id,
            what,
        };
        let ekf_id = sub
            .estim
            .ok_or_else(|| case("SOL ESTIMATE needs ESTIM = <EKF id> in case control".into()))?;
        let ekf = model
            .ekf(ekf_id)
            .ok_or_else(|| case(format!("ESTIM = {ekf_id} selects no EKF card")))?;
        let meas_id = sub
            .meas
            .ok_or_else(|| case("SOL ESTIMATE needs MEAS = <MEASF id> in case control".into()))?;
        let measf = model
            .measf(meas_id)
            .ok_or_else(|| case(format!("MEAS = {meas_id} selects no MEASF card")))?;
        let channels = model.meas(meas_id);
        if channels.is_empty() {
            return Err(case(format!("MEASF {meas_id} has no MEAS channel")));
        }
        let sid = sub
            .tstep
            .ok_or_else(|| case("SOL ESTIMATE needs TSTEP = <sid> for the filter step".into()))?;
        let tstep = model
            .tstep(sid)
            .ok_or_else(|| case(format!("TSTEP = {sid} selects no TSTEP card")))?;
        let dt = tstep.intervals[0].1;
        if tstep.intervals.iter().any(|i| i.1 != dt) {
            return Err(case(format!(
                "TSTEP {sid}: the filter runs with one step Δt; intervals have different DT"
            )));
        }
        let steps = tstep.intervals.iter().map(|i| i.0 as usize).sum();
        Ok(Self {
            ekf_id,
            ekf,
            meas_id,
            measf,
            channels,
            dt,
            steps,
        })
    }

    /// The measurement file's path (MEASF PATH relative to the file holding the card).
    pub fn csv(&self) -> PathBuf {
        let m = self.measf;
        m.loc
            .file
            .parent()
            .map_or_else(|| PathBuf::from(&m.path), |dir| dir.join(&m.path))
    }
}

/// Column `column` of the CSV against its time column, interpolated linearly onto t_k = k Δt,
/// k = 1 … steps (`first` = Δt, `last` = steps Δt); the window must lie inside the measured
/// time range.
pub(super) fn resample(
    csv: &Path,
    tcol: &Column,
    column: &Column,
    (first, last): (f64, f64),
    steps: usize,
) -> Result<Vec<f64>, String> {
    let points = read_columns(csv, tcol, column).map_err(|e| e.to_string())?;
    let table = Table::new(&points).map_err(|e| format!("{}: {e}", csv.display()))?;
    let (t0, t1) = (points[0].0, points[points.len() - 1].0);
    // a relative margin of 1e-9 of the window absorbs round-off of k Δt
    let slack = 1e-9 * last.abs().max(1.0);
    if first < t0 - slack || last > t1 + slack {
        return Err(format!(
            "{} covers t = {t0} … {t1}, the filter runs over {first} … {last}",
            csv.display()
        ));
    }
    Ok((1..=steps).map(|k| table.value(k as f64 * first)).collect())
}

impl Report for EstimateSummary {
    fn render(&self, subcase: u32) -> Vec<String> {
        let e = self;
        let mut out = vec![
            format!(
                "subcase {}: estimation on the pROM {}, {} step(s), {} steps/s",
                subcase,
                e.rom.display(),
                e.steps,
                sci(e.steps_per_second, 3)
            ),
            format!("  {}", e.observability),
        ];
        for (name, value, sigma) in &e.params {
            out.push(format!(
                "  {name} = {} ± {} (3σ) at the end",
                sci(*value, 6),
                sci(3.0 * sigma, 2)
            ));
        }
        if !e.error_table.is_empty() {
            out.push(format!(
                "  error over the last 20 % [%]: {:>10} {:>10} {:>10}",
                "min", "avg", "max"
            ));
            for r in &e.error_table {
                out.push(format!(
                    "  {:<28} {:>10.4} {:>10.4} {:>10.4}",
                    r.name, r.min, r.avg, r.max
                ));
            }
        }
        for (name, aae, mra) in &e.sensor_errors {
            out.push(format!(
                "  sensor {name}: AAE {} MRA {}",
                sci(*aae, 3),
                sci(*mra, 3)
            ));
        }
        out
    }

    fn warnings(&self, subcase: u32) -> Vec<String> {
        let e = self;
        let mut warnings: Vec<String> = extrapolation_warning(subcase, &e.extrapolated, &e.rom)
            .into_iter()
            .collect();
        if e.forced {
            warnings.push(format!(
                "subcase {}: FORCE = YES: the filter ran although the problem is {}",
                subcase, e.observability
            ));
        }
        if !e.hidden_modes.is_empty() {
            let modes: Vec<String> = e
                .hidden_modes
                .iter()
                .map(|(k, f)| format!("{k} ({f:.4e} Hz)"))
                .collect();
            warnings.push(format!("subcase {}: mode(s) {} are not seen by the measured sensors (unobservable at s = λ, but stable: detectable, thesis §7.5.1)", subcase, modes.join(", ")));
        }
        warnings
    }
}
