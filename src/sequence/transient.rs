//! `SOL TRANSIENT` (109/112) on the full model by direct integration of the f-set
//! M_ff ü + C_ff u̇ + K_ff u = p_f(t), C = αM + βK (`PARAM,ALPHA1` / `BETA1`), with the
//! `TINTEG` of the `TSTEP` (BDF1 by default, eq. 2.61; BDF2; generalized-α) from rest or from
//! the TIC state of `IC = sid`. Each
//! TSTEP interval has a constant Δt: one sparse Cholesky of the effective matrix per interval
//! (two for BDF2, whose first step is BDF1), one symbolic analysis for the run.
//!
//! What the pROM transient ([`super::rom_transient`]) shares lives here: the method of a
//! TSTEP ([`method_of`]), the load terms of `DLOAD` ([`load_terms`]: TLOAD1 × DAREA with a
//! TABLED1 or TABLEF), and the output row count ([`output_rows`]).
//!
//! Written: `/results/<id>/transient/{time (t)}`, `sensors/<name> (t)` for the subcase's
//! SENSORs (DISP and STRAIN from u, VEL from u̇, ACCEL from ü; [`super::sensors`]), and only
//! when the subcase asks `DISPLACEMENT = ALL | set`, `displacement (t × k × 6)` in basic —
//! full histories are large, so none by default. Attributes `method`, `f_size`,
//! `factorizations`.

use faer::Par;

use super::sensors::sensor_operator;
use super::{
    Clock, Constrained, GridRows, RunContext, RunError, Structure, SubcaseResult, SubcaseSummary,
};
use crate::assembly::DofMap;
use crate::assembly::loads::load_vector;
use crate::assembly::recover::expand_f_to_n;
use crate::deck::cards::Darea;
use crate::deck::case_control::Subcase;
use crate::dynamics::integrators::{IntegrationError, Method, Run, integrate_with};
use crate::dynamics::sparse_backend::SparseBackend;
use crate::dynamics::table::Table;
use crate::io::{set_attr_i64, set_attr_str, write_f64};

/// What one full-model transient subcase computed.
#[derive(Debug, Clone)]
pub struct TransientSummary {
    pub method: String,
    pub steps: usize,
    pub f_size: usize,
    pub sensors: usize,
    pub factorizations: usize,
    /// Largest |sensor value| and its sensor name and time.
    pub peak: Option<(String, f64, f64)>,
}

/// One load term: shape × table(t − delay).
pub struct LoadTerm {
    pub shape: Vec<f64>,
    pub table: Table,
    pub delay: f64,
}

/// f(t) = Σ shape · table(t − delay) into `f`.
pub fn load_into(terms: &[LoadTerm], t: f64, f: &mut [f64]) {
    f.fill(0.0);
    for term in terms {
        let a = term.table.value(t - term.delay);
        if a != 0.0 {
            f.iter_mut()
                .zip(&term.shape)
                .for_each(|(fi, s)| *fi += a * s);
        }
    }
}

/// The TSTEP of a subcase, its method (TINTEG with the TSTEP's id; BDF1 without one) and the
/// method's name for output.
pub fn method_of<'a>(
    ctx: &'a RunContext,
    sub: &Subcase,
) -> Result<(&'a crate::deck::cards::Tstep, Method, String), RunError> {
    let case = |what: String| RunError::Case {
        subcase: sub.id,
        what,
    };
    let b = &ctx.model.bulk;
    let sid = sub
        .tstep
        .ok_or_else(|| case("SOL TRANSIENT needs TSTEP = <sid> in case control".into()))?;
    let tstep = b
        .tstep
        .iter()
        .find(|t| t.sid == sid)
        .ok_or_else(|| case(format!("TSTEP = {sid} selects no TSTEP card")))?;
    let (method, name) = match b.tinteg.iter().find(|t| t.id == sid) {
        Some(t) if t.method == "BDF2" => (Method::Bdf2, "BDF2".to_string()),
        Some(t) if t.method == "GALPHA" => (
            Method::GeneralizedAlpha { rho_inf: t.rho_inf },
            format!("GALPHA (rho_inf = {})", t.rho_inf),
        ),
        _ => (Method::Bdf1, "BDF1".to_string()),
    };
    Ok((tstep, method, name))
}

/// Number of output rows of a TSTEP: the initial state, then every NO-th step of each interval.
pub fn output_rows(intervals: &[(u32, f64, u32)]) -> usize {
    1 + intervals
        .iter()
        .map(|&(count, _, every)| count as usize / every.max(1) as usize)
        .sum::<usize>()
}

/// A TLOAD1's (or PTABLE's) table, [`super::frf::dynamic_table`], with `user` naming the card in
/// errors.
pub fn table_of(ctx: &RunContext, tid: u32, user: &str) -> Result<Table, String> {
    super::frf::dynamic_table(ctx.model, tid).map_err(|e| format!("{user}: {e}"))
}

/// The load terms of `DLOAD = sid`: a DLOAD combination S·Σ Sᵢ·(TLOAD1 Lᵢ), or one TLOAD1.
/// `place(darea, component, scale, shape)` adds one DAREA entry (component 1–6, scale including
/// the DLOAD factors) to a shape vector of length `len`; when a TLOAD1's EXCITEID selects no
/// DAREA, `static_set(excite_id)` may supply the shape of a static load set (FORCE, LOAD) as the
/// full model does, or `None` (pROMs: loads act on input DOFs only).
pub fn load_terms(
    ctx: &RunContext,
    sid: u32,
    len: usize,
    mut place: impl FnMut(&Darea, usize, f64, &mut [f64]) -> Result<(), String>,
    mut static_set: impl FnMut(u32) -> Result<Option<Vec<f64>>, String>,
) -> Result<Vec<LoadTerm>, String> {
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
            let table = table_of(ctx, t.tid, &format!("TLOAD1 {}", t.sid))?;
            let mut shape = vec![0.0; len];
            let mut any = false;
            for d in b.darea.iter().filter(|d| d.sid == t.excite_id) {
                for comp in d.components.components() {
                    place(d, comp, scale * d.scale, &mut shape)?;
                    any = true;
                }
            }
            if !any {
                let p = static_set(t.excite_id)?.ok_or_else(|| {
                    format!(
                        "TLOAD1 {}: EXCITEID {} selects no DAREA",
                        t.sid, t.excite_id
                    )
                })?;
                shape.iter_mut().zip(&p).for_each(|(s, p)| *s += scale * p);
            }
            out.push(LoadTerm {
                shape,
                table,
                delay: t.delay,
            });
        }
    }
    Ok(out)
}

/// Runs every subcase on the full model.
pub fn run(
    ctx: &RunContext,
    st: &Structure,
    clock: &mut Clock,
) -> Result<Vec<SubcaseSummary>, RunError> {
    let mut out = Vec::new();
    for sub in &ctx.model.subcases {
        let c = clock.time(format!("subcase {}: constraints", sub.id), || {
            Constrained::build(ctx.model, st, sub.spc)
        })?;
        let summary = clock.time(format!("subcase {}: transient", sub.id), || {
            subcase(ctx, st, &c, sub)
        })?;
        out.push(SubcaseSummary {
            id: sub.id,
            autospc: c.autospc.names.clone(),
            result: SubcaseResult::Transient(summary),
        });
    }
    Ok(out)
}

fn subcase(
    ctx: &RunContext,
    st: &Structure,
    c: &Constrained,
    sub: &Subcase,
) -> Result<TransientSummary, RunError> {
    let id = sub.id;
    let case = |what: String| RunError::Case { subcase: id, what };
    if c.spc.enforced.iter().any(|x| *x != 0.0) {
        return Err(case("enforced displacements (SPC with a non-zero value) are not supported by SOL TRANSIENT in this version".into()));
    }
    let (tstep, method, method_name) = method_of(ctx, sub)?;
    let n_f = c.sets.f.len();
    let loads = match sub.dload {
        None => Vec::new(),
        Some(dload) => load_terms(
            ctx,
            dload,
            n_f,
            |d, comp, scale, shape| place_darea(ctx, st, c, d, comp, scale, shape),
            |excite| static_shape(ctx, st, c, excite),
        )
        .map_err(case)?,
    };
    let sensors = sensor_operator(ctx, st, c, sub)?;
    let rows = output_rows(&tstep.intervals);
    let s = sensors.len();
    let mut series = vec![0.0; s * rows];
    let mut y = vec![0.0; s];
    let mut time = Vec::with_capacity(rows);
    let grid_rows = GridRows::of_subcase(ctx.deck, &st.map, sub, "DISPLACEMENT", None);
    let mut history: Vec<f64> = Vec::new();
    let mut recovery_error = None;
    let par = if ctx.options.parallel {
        Par::rayon(0)
    } else {
        Par::Seq
    };
    let mut backend = SparseBackend::new(
        &c.k_ff,
        &c.m_ff,
        ctx.model.params.alpha1,
        ctx.model.params.transient_beta(),
        par,
    )
    .map_err(|e| case(e.to_string()))?;
    let (mut u, mut v) = initial_state(ctx, c, sub).map_err(case)?;
    let mut t0 = 0.0;
    let mut steps = 0;
    for (interval, &(count, dt, every)) in tstep.intervals.iter().enumerate() {
        let every = every.max(1) as usize;
        let (u0, v0) = (u.clone(), v.clone());
        let run = Run {
            dt,
            steps: count as usize,
            t0,
        };
        integrate_with(
            &mut backend,
            method,
            run,
            &u0,
            &v0,
            |t, f| load_into(&loads, t, f),
            |state| {
                if (state.step > 0 || interval == 0) && state.step % every == 0 && time.len() < rows
                {
                    let r = time.len();
                    time.push(state.time);
                    sensors.evaluate(state.q, state.v, state.a, &mut y);
                    for (i, yi) in y.iter().enumerate() {
                        series[i * rows + r] = *yi;
                    }
                    if grid_rows.is_some() {
                        match expand_f_to_n(state.q, &c.sets, &c.spc.enforced)
                            .and_then(|u_n| st.rigid.expand(&u_n))
                        {
                            Ok(u_g) => history.extend(st.to_basic_rows(&u_g)),
                            Err(e) => recovery_error = Some(e),
                        }
                    }
                }
                if state.step == count as usize {
                    u.copy_from_slice(state.q);
                    v.copy_from_slice(state.v);
                }
            },
        )
        .map_err(|e| {
            case(match e {
                IntegrationError::Singular("mass") => massless(st, c, &e),
                e => e.to_string(),
            })
        })?;
        if let Some(e) = recovery_error.take() {
            return Err(e.into());
        }
        t0 += count as f64 * dt;
        steps += count as usize;
    }
    let rows = time.len();
    let group = ctx.output.group(&format!("results/{id}/transient"))?;
    write_f64(&group, "time", &time, &[rows])?;
    let mut peak: Option<(String, f64, f64)> = None;
    if !sensors.is_empty() {
        let sg = ctx
            .output
            .group(&format!("results/{id}/transient/sensors"))?;
        for (name, y) in sensors
            .names
            .iter()
            .zip(series.chunks_exact(series.len() / s))
        {
            let y = &y[..rows];
            write_f64(&sg, name, y, &[rows])?;
            for (r, x) in y.iter().enumerate() {
                if peak.as_ref().is_none_or(|p| x.abs() > p.1) {
                    peak = Some((name.clone(), x.abs(), time[r]));
                }
            }
        }
    }
    if let Some(grid_rows) = grid_rows {
        grid_rows.write(&group, "displacement", &history, &[rows], &st.map)?;
    }
    set_attr_str(&group, "method", &method_name)?;
    set_attr_i64(&group, "f_size", n_f as i64)?;
    set_attr_i64(&group, "factorizations", backend.factorizations as i64)?;
    super::write_autospc(&group, &c.autospc)?;
    Ok(TransientSummary {
        method: method_name,
        steps,
        f_size: n_f,
        sensors: s,
        factorizations: backend.factorizations,
        peak,
    })
}

/// The error of a mass matrix that cannot be factored for the initial acceleration
/// a₀ = M⁻¹(f₀ − C v₀ − K q₀): the integrators need it whenever the run does not start at rest
/// and unloaded (then a₀ = 0, consistent for massless DOFs too). Names the f-set DOFs without
/// mass (zero diagonal: lumped masses leave rotations massless, CELAS-only grids have none).
fn massless(st: &Structure, c: &Constrained, e: &IntegrationError) -> String {
    let zero: Vec<String> = c
        .m_ff
        .col_iter()
        .enumerate()
        .filter(|(j, col)| {
            !col.row_indices()
                .iter()
                .zip(col.values())
                .any(|(i, m)| i == j && *m != 0.0)
        })
        .filter_map(|(j, _)| {
            c.sets
                .f
                .members()
                .get(j)
                .and_then(|&g| st.map.dof_name(g))
                .map(|d| d.to_string())
        })
        .collect();
    let which = match zero.len() {
        0 => {
            return format!(
                "{e} (no DOF has a zero mass diagonal: the mass matrix is singular through coupling)"
            );
        }
        1..=3 => zero.join(", "),
        n => format!("{} and {} more", zero[..3].join(", "), n - 3),
    };
    format!(
        "{which} without mass: the initial acceleration M⁻¹(f₀ − C v₀ − K q₀) does not exist; start at rest with loads that are zero at the first time (e.g. a TABLED1 ramp from 0), or give those DOFs mass (CONM2 inertia, PARAM,COUPMASS,1)"
    )
}

/// The f-set state of `IC = sid`: each TIC sets u and u̇ of one free grid component (its
/// displacement frame); components without a TIC start at zero. A TIC on a constrained (SPC,
/// AUTOSPC) or dependent (RBE) DOF is an error: its value would be ignored.
fn initial_state(
    ctx: &RunContext,
    c: &Constrained,
    sub: &Subcase,
) -> Result<(Vec<f64>, Vec<f64>), String> {
    let n_f = c.sets.f.len();
    let (mut u, mut v) = (vec![0.0; n_f], vec![0.0; n_f]);
    let Some(sid) = sub.ic else { return Ok((u, v)) };
    let cards: Vec<_> = ctx.model.bulk.tic.iter().filter(|t| t.sid == sid).collect();
    if cards.is_empty() {
        return Err(format!("IC = {sid} selects no TIC card"));
    }
    for t in cards {
        let grid = ctx
            .model
            .grid_index
            .get(&t.grid)
            .copied()
            .ok_or_else(|| format!("TIC {sid}: GRID {} does not exist", t.grid))?;
        let i = c.sets.f.position(DofMap::dof(grid, t.component - 1)).ok_or_else(|| format!("TIC {sid}: GRID {} component {} is not a free DOF (constrained by SPC/AUTOSPC or dependent in an RBE)", t.grid, t.component))?;
        u[i] += t.u0;
        v[i] += t.v0;
    }
    Ok((u, v))
}

/// The f-set shape of a static load set (FORCE, MOMENT, LOAD combinations) used as a TLOAD1's
/// EXCITEID (as MSC Nastran accepts without LSEQ).
fn static_shape(
    ctx: &RunContext,
    st: &Structure,
    c: &Constrained,
    sid: u32,
) -> Result<Option<Vec<f64>>, String> {
    let p_g = load_vector(ctx.model, &st.frames, &st.map, sid, None)
        .map_err(|e| format!("TLOAD1 EXCITEID {sid}: no DAREA and {e}"))?;
    let p_n = st.rigid.reduce_vector(&p_g).map_err(|e| e.to_string())?;
    c.sets
        .f_in_n
        .gather(&p_n)
        .map(Some)
        .map_err(|e| e.to_string())
}

/// Adds a DAREA entry to an f-set load shape: the g-set entry (grid's displacement frame, as
/// DAREA components are) reduced to n through the rigid elimination (Tᵀ) and restricted to f;
/// an entry on a constrained DOF is an error (it would be lost).
fn place_darea(
    ctx: &RunContext,
    st: &Structure,
    c: &Constrained,
    d: &Darea,
    comp: usize,
    scale: f64,
    shape: &mut [f64],
) -> Result<(), String> {
    let grid = ctx
        .model
        .grid_index
        .get(&d.grid)
        .copied()
        .ok_or_else(|| format!("DAREA {}: GRID {} does not exist", d.sid, d.grid))?;
    let mut p_g = vec![0.0; st.map.size()];
    p_g[DofMap::dof(grid, comp - 1)] = scale;
    let p_n = st.rigid.reduce_vector(&p_g).map_err(|e| e.to_string())?;
    let p_f = c.sets.f_in_n.gather(&p_n).map_err(|e| e.to_string())?;
    if p_f.iter().all(|x| *x == 0.0) {
        return Err(format!(
            "DAREA {}: GRID {} component {comp} is constrained (SPC or AUTOSPC): the load would not act",
            d.sid, d.grid
        ));
    }
    shape.iter_mut().zip(&p_f).for_each(|(s, p)| *s += p);
    Ok(())
}
