//! `SOL TRANSIENT` (109/112) on the full model by direct integration of the f-set
//! M_ff ü + C_ff u̇ + K_ff u = p_f(t), C = αM + βK + B + (1/W4)·Σ GE_e K_e (`PARAM,ALPHA1` /
//! `BETA1` with (G/W3)·K added to βK; the elements' viscous damping B; their structural damping
//! GE turned viscous at `PARAM,W4` as Nastran, left out while W4 = 0), with the
//! `TINTEG` of the `TSTEP` (BDF1 by default, eq. 2.61; BDF2; generalized-α) from rest or from
//! the TIC state of `IC = sid`; a TLOAD of TYPE = DISP, VELO or ACCE moves the DOFs of its SPCD
//! set ([`crate::dynamics::prescribed`], [`crate::discretize::enforced::EnforcedMotion`]). Each
//! TSTEP interval has a constant Δt: one sparse Cholesky of the effective matrix per interval
//! (two for BDF2, whose first step is BDF1), one symbolic analysis for the run.
//!
//! Written: `/results/<id>/transient/{time (t)}`, `sensors/<name> (t)` for the subcase's
//! SENSORs (DISP and STRAIN from u, VEL from u̇, ACCEL from ü; [`crate::discretize::sensors`]), and only
//! when the subcase asks `DISPLACEMENT = ALL | set`, `displacement (t × k × 6)` in basic —
//! full histories are large, so none by default. Attributes `method`, `f_size`,
//! `factorizations`.

use super::driver::{Basis, Driver, ElementDampingUse};
use super::report::{Report, sci};
use super::shared::structure;
use super::shared::{damping_warning, w4_warning};
use super::shared::{method_of, output_rows};
use super::{Clock, GridRows, RunContext, RunError, SubcaseSummary};
use crate::assembly::recover::expand_f_to_n;
use crate::deck::Solution;
use crate::deck::case_control::Subcase;
use crate::discretize::enforced::{EnforcedMotion, MovedState};
use crate::discretize::loads::{
    TimeLoads, initial_state, load_into, load_terms, place_darea, static_shape,
};
use crate::discretize::{Constrained, Structure};
use crate::dynamics::integrators::{IntegrationError, Run, integrate_prescribed};
use crate::dynamics::sparse_backend::SparseBackend;
use crate::io::{set_attr_i64, set_attr_str, write_f64};
use crate::model::Model;

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

/// The TRANSIENT driver on the mesh.
pub struct Transient;

/// The output requests TRANSIENT (109, 112) writes: displacement histories on request.
pub const HONOURED: &[&str] = &["DISPLACEMENT"];

impl Driver for Transient {
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
        Basis::Mesh
    }

    fn element_damping(&self) -> ElementDampingUse {
        ElementDampingUse::Applied
    }

    fn honoured(&self) -> &'static [&'static str] {
        HONOURED
    }

    fn warnings(&self, model: &Model) -> Vec<String> {
        damping_warning(model)
            .into_iter()
            .chain(w4_warning(model))
            .collect()
    }

    fn run(&self, ctx: &RunContext, clock: &mut Clock) -> Result<Vec<SubcaseSummary>, RunError> {
        let st = structure(ctx, clock)?;
        run(ctx, &st, clock)
    }
}

/// Runs every subcase on the full model.
fn run(
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
            result: Box::new(summary),
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
    let (tstep, method, method_name) = method_of(ctx.model, sub)?;
    let n_f = c.sets.f.len();
    let TimeLoads {
        applied: loads,
        enforced,
    } = match sub.dload {
        None => TimeLoads {
            applied: Vec::new(),
            enforced: Vec::new(),
        },
        Some(dload) => load_terms(
            ctx.model,
            dload,
            n_f,
            |d, scale, shape| place_darea(ctx.model, st, c, d, scale, shape),
            |excite| static_shape(ctx.model, st, c, excite, sub.loadset),
        )
        .map_err(case)?,
    };
    let moved = EnforcedMotion::new(ctx.model, st, c, &enforced).map_err(case)?;
    let mut motion = moved.prescribed(&enforced, 0.0);
    let sensors = super::subcase_sensors(ctx, st, c, sub)?;
    let rows = output_rows(&tstep.intervals);
    let s = sensors.len();
    let mut series = vec![0.0; s * rows];
    let mut y = vec![0.0; s];
    let mut time = Vec::with_capacity(rows);
    let grid_rows = GridRows::of_subcase(ctx.deck, &st.map, sub, "DISPLACEMENT", None);
    let mut history: Vec<f64> = Vec::new();
    let mut recovery_error = None;
    let mut moved_state = MovedState::new(c.sets.s.len());
    let mut enforced_g = c.spc.enforced.clone();
    let params = &ctx.model.params;
    // the elements' viscous B and, with PARAM,W4, their structural damping as (1/W4)·Σ GE K_e
    let damping: Vec<(f64, &nalgebra_sparse::CscMatrix<f64>)> = [
        (1.0, c.damping_ff.viscous.as_ref()),
        (
            if params.w4 > 0.0 {
                1.0 / params.w4
            } else {
                0.0
            },
            c.damping_ff.structural.as_ref(),
        ),
    ]
    .into_iter()
    .filter_map(|(w, d)| d.filter(|_| w != 0.0).map(|d| (w, d)))
    .collect();
    let mut backend = SparseBackend::new(
        &c.k_ff,
        &c.m_ff,
        params.alpha1,
        params.transient_beta(),
        ctx.options.par(),
    )
    .and_then(|b| b.with_damping(&damping))
    .map_err(|e| case(e.to_string()))?;
    let (mut u, mut v) = initial_state(ctx.model, c, sub.ic).map_err(case)?;
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
        integrate_prescribed(
            &mut backend,
            method,
            run,
            &u0,
            &v0,
            |t, f| load_into(&loads, t, f),
            &mut motion,
            |state| {
                if (state.step > 0 || interval == 0) && state.step % every == 0 && time.len() < rows
                {
                    let r = time.len();
                    time.push(state.time);
                    moved_state.set(&moved.patterns, state.motion);
                    sensors.evaluate(state.q, state.v, state.a, &mut y);
                    sensors.add_constrained(&moved_state.u, &moved_state.v, &moved_state.a, &mut y);
                    for (i, yi) in y.iter().enumerate() {
                        series[i * rows + r] = *yi;
                    }
                    if grid_rows.is_some() {
                        moved_state.scatter_displacement(c.sets.s.members(), &mut enforced_g);
                        match expand_f_to_n(state.q, &c.sets, &enforced_g)
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

impl Report for TransientSummary {
    fn render(&self, subcase: u32) -> Vec<String> {
        let r = self;
        let mut out = vec![format!(
            "subcase {}: transient of the full model (f-set {} DOFs, {}), {} step(s), {} factorization(s), {} sensor(s)",
            subcase, r.f_size, r.method, r.steps, r.factorizations, r.sensors
        )];
        if let Some((name, value, t)) = &r.peak {
            out.push(format!(
                "  largest |sensor| {} ({name}) at t = {} s",
                sci(*value, 4),
                sci(*t, 4)
            ));
        }
        out
    }
}
