//! SOL 101 (STATICS): K_ff u_f = P_f for every subcase, by sparse Cholesky
//! ([`crate::analysis::statics`]).
//!
//! Order (as `assembly::tests::solve`, with the sparse LLᵀ):
//! 1. f-set of `SPC = sid` (+ GRID PS, AUTOSPC) — [`Constrained`];
//! 2. K_ff = LLᵀ: one symbolic analysis *and* one numeric factor per distinct f-set, shared by
//!    every subcase with that f-set (K does not depend on the load). A failing pivot is a
//!    mechanism, reported with its GRID and component;
//! 3. P_g of `LOAD = sid` (FORCE, MOMENT, GRAV with M_gg) plus the thermal load of
//!    `TEMPERATURE(LOAD) = sid` ([`crate::discretize::thermal`]), P_f = (Tᵀ P_g)_f − K_fs u_s;
//! 4. u_f by the factor plus one step of iterative refinement (shell models mix membrane and
//!    bending stiffness, condition numbers 1e8–1e10);
//! 5. u_g = T [u_f; u_s]; SPC forces q_s = (K_nn u_n − P_n)_s.
//!
//! Output in the basic system, as the case-control requests select (grid rows by
//! [`GridRows`], shared with SOL 103): `displacement` (k×6) for `DISPLACEMENT = ALL | SET`, and
//! for every grid when the subcase has no DISPLACEMENT request (the documented default, unlike
//! Nastran, which prints nothing; `DISPLACEMENT = NONE` writes none); `spc_force` (k×6) only with
//! `SPCFORCES`; a SET adds `<name>_grid_ids`. Centroid strains only with `STRAIN` (elements of
//! its SET, or ALL):
//! `strain/<CQUAD4|CTRIA3>/{ids (m), top (m×3), bottom (m×3)}` — [εx, εy, γxy] in the element
//! material system at the fibres Z2 (top) and Z1 (bottom) of the PSHELL (the laminate's top and
//! bottom surfaces for PCOMP) — and `strain/<CHEXA|CPENTA|CTETRA|CTETRA10>/{ids (m),
//! centroid (m×6)}` — [εxx, εyy, εzz, γxy, γyz, γzx] in basic (engineering shear strains).
//! Element forces with `FORCE` and stresses with `STRESS` (the same element selection), in the
//! layout of [`super::statics_stress`], from the mechanical strains (total less thermal) of the
//! subcase's `TEMPERATURE(LOAD)` set; a SUBCOM's stresses take its own `TEMPERATURE(LOAD)` set
//! (Nastran's rule), so a combination of thermal subcases needs one.
//! A `SUBCOM` writes the same outputs for Σ cᵢ (uᵢ, Pᵢ, qᵢ) over the preceding SUBCASEs
//! (`SUBSEQ` coefficients aligned on the most recent: the last for the last SUBCASE, as
//! Nastran's SUBSEQ, so fewer coefficients than SUBCASEs combine the latest ones; stresses, strains and forces are recovered from the
//! combined displacements, so von Mises and failure indices are those of the combined state).
//! The SPC forces are always computed (one K·u product): the console summary's reaction sum
//! uses them.

use super::driver::{Basis, Driver, ElementDampingUse};
use super::report::{Report, sci};
use super::shared::structure;
use super::{Clock, GridRows, RunContext, RunError, SubcaseSummary, requested, selected};
use crate::analysis::statics::{
    ElementStrains, StaticFactors, StaticSolution, element_strains, resultant,
};
use crate::analysis::stress::{element_forces, element_stresses, failure_warnings};
use crate::assembly::spc::suport_dofs;
use crate::deck::Solution;
use crate::deck::cards::ParamValue;
use crate::deck::case_control::Subcase;
use crate::discretize::thermal::{ThermalStrains, thermal_load};
use crate::discretize::{Constrained, Structure};
use crate::io::{write_f64, write_u32};
use crate::linalg::LinalgError;
use crate::model::Model;

/// What one static subcase found (basic system).
#[derive(Debug, Clone)]
pub struct StaticsSummary {
    /// Largest translation magnitude: (GRID id, |u|).
    pub max_translation: (u32, f64),
    /// Largest |component| of all six: (GRID id, component 1–6, value).
    pub max_component: (u32, u8, f64),
    /// Σ applied forces and moments about the origin (basic): [Fx, Fy, Fz, Mx, My, Mz].
    pub applied: [f64; 6],
    /// Σ SPC forces and moments about the origin (basic).
    pub reaction: [f64; 6],
    /// Size of K_ff.
    pub f_size: usize,
    /// A pivot ratio above MAXRATIO let through by PARAM,BAILOUT < 0, on the subcase that
    /// factored K_ff.
    pub pivot_warning: Option<String>,
}

/// The STATICS driver on the mesh.
pub struct Statics;

/// The output requests STATICS writes: displacements (every grid when not requested at all, none for `= NONE`), SPC forces, strains, element forces and stresses on request.
pub const HONOURED: &[&str] = &["DISPLACEMENT", "SPCFORCES", "STRAIN", "FORCE", "STRESS"];

impl Driver for Statics {
    fn name(&self) -> &'static str {
        "STATICS"
    }

    fn solutions(&self) -> &'static [Solution] {
        &[Solution::Statics]
    }

    fn basis(&self) -> Basis {
        Basis::Mesh
    }

    fn element_damping(&self) -> ElementDampingUse {
        ElementDampingUse::Ignored
    }

    fn honoured(&self) -> &'static [&'static str] {
        HONOURED
    }

    /// PCOMP failure theories that give no index, when some subcase asks for STRESS; the note
    /// that SUPORT DOFs are held like SPCs.
    fn warnings(&self, model: &Model) -> Vec<String> {
        let mut out = if model
            .subcases
            .iter()
            .any(|s| requested(s, "STRESS").is_some())
        {
            failure_warnings(model)
        } else {
            Vec::new()
        };
        if model.has_suport() {
            out.push("SUPORT/SUPORT1 in SOL 101 without PARAM,INREL: the SUPORT DOFs are held like SPCs (as MSC Nastran does); their reactions are the SPC forces there and should be near zero for a balanced load".into());
        }
        out
    }

    fn run(&self, ctx: &RunContext, clock: &mut Clock) -> Result<Vec<SubcaseSummary>, RunError> {
        let inertia_relief = (ctx.deck.bulk.params.iter())
            .any(|p| p.name == "INREL" && matches!(p.value, ParamValue::Int(v) if v < 0));
        if inertia_relief {
            return Err(RunError::NotAvailable(
                "PARAM,INREL (inertia relief) is not available in SOL 101 in this version; without it the SUPORT DOFs are held like SPCs".into(),
            ));
        }
        let st = structure(ctx, clock)?;
        run(ctx, &st, clock)
    }
}

/// Runs every subcase.
fn run(
    ctx: &RunContext,
    st: &Structure,
    clock: &mut Clock,
) -> Result<Vec<SubcaseSummary>, RunError> {
    let params = &ctx.model.params;
    // BAILOUT < 0: factor with no ratio bound, then warn about a ratio above MAXRATIO
    let bound = if params.bailout < 0 {
        f64::INFINITY
    } else {
        params.maxratio
    };
    let mut factors = StaticFactors::new(bound, ctx.options.par());
    let m_gg_values = st.mass_gg_values()?;
    let mut out = Vec::new();
    // the solutions of the SUBCASEs so far, in deck order, when a SUBCOM combines them
    let combines = ctx.model.subcases.iter().any(|s| s.combination.is_some());
    let mut solved: Vec<StaticSolution> = Vec::new();
    for sub in &ctx.model.subcases {
        let id = sub.id;
        let suport = suport_dofs(ctx.model, &st.map, sub.suport1).map_err(|e| RunError::Case {
            subcase: id,
            what: e.to_string(),
        })?;
        let c = clock.time(format!("subcase {id}: constraints"), || {
            Constrained::build_holding(ctx.model, st, sub.spc, &suport)
        })?;
        if let Some(coefficients) = &sub.combination {
            let summary = clock.time(format!("subcase {id}: combination and output"), || {
                write_subcase(
                    ctx,
                    st,
                    &c,
                    sub,
                    &StaticSolution::combine(&solved, coefficients),
                )
            })?;
            out.push(SubcaseSummary {
                id,
                autospc: c.autospc.names.clone(),
                result: Box::new(summary),
            });
            continue;
        }
        let mut pivot_warning = None;
        if factors.get(&c).is_none() {
            let symbolic = clock
                .time(format!("subcase {id}: symbolic analysis"), || {
                    StaticFactors::analyze(&c)
                })
                .map_err(|e| RunError::Linalg {
                    subcase: id,
                    source: e,
                })?;
            ctx.progress.step("factorization", 0, 1);
            clock
                .time(format!("subcase {id}: Cholesky"), || {
                    factors.factor(&c, symbolic)
                })
                .map_err(|e| {
                    let ratio_only = matches!(e, LinalgError::NotPositiveDefinite { ratio, .. } if ratio.is_finite());
                    let err = super::mechanism(&c, st, id, e);
                    if ratio_only { bailout_hint(err) } else { err }
                })?;
            ctx.progress.step("factorization", 1, 1);
            let worst = factors
                .get(&c)
                .map(|f| f.max_pivot_ratio())
                .filter(|w| w.ratio > params.maxratio);
            pivot_warning = worst.map(|w| {
                let ratio = LinalgError::NotPositiveDefinite {
                    index: w.index,
                    ratio: w.ratio,
                };
                let at = c
                    .mechanism_dof(st, &ratio)
                    .map_or_else(|| format!("f-set DOF {}", w.index), |d| d.to_string());
                format!(
                    "subcase {id}: the diagonal/pivot ratio {:e} at {at} exceeds PARAM,MAXRATIO = {:e}: the structure is nearly singular there; the run goes on because PARAM,BAILOUT is negative (check the results)",
                    w.ratio, params.maxratio
                )
            });
        }
        let factor = factors.get(&c).ok_or(RunError::NoSolution)?;
        let summary = clock.time(format!("subcase {id}: solve and output"), || {
            let thermal = match &thermal_strains(ctx, sub)? {
                Some(strains) => {
                    Some(
                        thermal_load(ctx.model, st, strains).map_err(|e| RunError::Case {
                            subcase: id,
                            what: e.to_string(),
                        })?,
                    )
                }
                None => None,
            };
            let solution = StaticSolution::solve(
                ctx.model,
                st,
                &c,
                (sub.load, thermal.as_deref()),
                factor,
                &m_gg_values,
            )
            .map_err(|e| super::analysis_error(&c, st, id, e))?;
            let mut summary = write_subcase(ctx, st, &c, sub, &solution)?;
            summary.pivot_warning = pivot_warning;
            if combines {
                solved.push(solution);
            }
            Ok::<_, RunError>(summary)
        })?;
        out.push(SubcaseSummary {
            id,
            autospc: c.autospc.names.clone(),
            result: Box::new(summary),
        });
    }
    Ok(out)
}

/// A mechanism found by a finite pivot ratio above MAXRATIO (not a zero or negative pivot)
/// says how to go on, as Nastran's UFM 9050 does.
fn bailout_hint(e: RunError) -> RunError {
    match e {
        RunError::Mechanism {
            subcase,
            dof,
            detail,
        } => RunError::Mechanism {
            subcase,
            dof,
            detail: format!(
                "{detail}; PARAM,BAILOUT,-1 lets the run go on with a warning, as in MSC Nastran"
            ),
        },
        e => e,
    }
}

/// Writes one subcase's requested outputs and sums it up for the console.
fn write_subcase(
    ctx: &RunContext,
    st: &Structure,
    c: &Constrained,
    sub: &Subcase,
    solution: &StaticSolution,
) -> Result<StaticsSummary, RunError> {
    let model = ctx.model;
    let n = st.map.grids();
    let thermal = thermal_strains(ctx, sub)?.unwrap_or_default();
    let u = st.to_basic_rows(&solution.u_g);
    let q = st.to_basic_rows(&solution.q_g);
    let p = st.to_basic_rows(&solution.p_g);
    let group = ctx.output.group(&format!("results/{}/statics", sub.id))?;
    // Without a DISPLACEMENT request every grid is written (DESIGN.md §8 makes `displacement`
    // part of every statics result); Nastran would print nothing. `DISPLACEMENT = NONE` opts out.
    if let Some(rows) =
        GridRows::of_subcase(ctx.deck, &st.map, sub, "DISPLACEMENT", Some(GridRows::All))
    {
        rows.write(&group, "displacement", &u, &[], &st.map)?;
    }
    if let Some(rows) = GridRows::of_subcase(ctx.deck, &st.map, sub, "SPCFORCES", None) {
        rows.write(&group, "spc_force", &q, &[], &st.map)?;
    }
    super::write_autospc(&group, &c.autospc)?;
    if let Some(req) = requested(sub, "STRAIN") {
        let strains = element_strains(model, st, &u, |eid| selected(ctx.deck, req, eid))?;
        write_strains(ctx, &group, &strains)?;
    }
    if let Some(req) = requested(sub, "FORCE") {
        let forces = element_forces(model, st, &u, &thermal, |eid| selected(ctx.deck, req, eid))?;
        super::statics_stress::write_forces(ctx, &group, &forces)?;
    }
    if let Some(req) = requested(sub, "STRESS") {
        let stresses =
            element_stresses(model, st, &u, &thermal, |eid| selected(ctx.deck, req, eid))?;
        super::statics_stress::write_stresses(ctx, &group, &stresses)?;
    }

    let grid_id = |g: usize| st.map.grid_id(g).unwrap_or(0);
    let mut max_translation: (u32, f64) = (0, 0.0);
    let mut max_component: (u32, u8, f64) = (0, 1, 0.0);
    for g in 0..n {
        let r = &u[6 * g..6 * g + 6];
        let mag = crate::geometry::vec3::norm([r[0], r[1], r[2]]);
        if mag > max_translation.1 {
            max_translation = (grid_id(g), mag);
        }
        for (k, v) in r.iter().enumerate() {
            if v.abs() > max_component.2.abs() {
                max_component = (grid_id(g), k as u8 + 1, *v);
            }
        }
    }
    Ok(StaticsSummary {
        max_translation,
        max_component,
        applied: resultant(model, &p),
        reaction: resultant(model, &q),
        f_size: c.sets.f.len(),
        pivot_warning: None,
    })
}

/// The thermal strains of the subcase's `TEMPERATURE(LOAD)` set, if it has one (a SUBCOM's
/// own set: the temperatures of the combined state, as Nastran's stress recovery of a SUBCOM
/// reads them).
fn thermal_strains(ctx: &RunContext, sub: &Subcase) -> Result<Option<ThermalStrains>, RunError> {
    sub.temperature_load
        .map(|sid| ThermalStrains::of_set(ctx.model, sid))
        .transpose()
        .map_err(|e| RunError::Case {
            subcase: sub.id,
            what: e.to_string(),
        })
}

/// Writes `strain/<block>/{ids, top, bottom}` (shells) and `strain/<block>/{ids, centroid}`
/// (solids) under `group`.
fn write_strains(
    ctx: &RunContext,
    group: &hdf5_metno::Group,
    strains: &ElementStrains,
) -> Result<(), RunError> {
    for (name, b) in &strains.shells {
        let g = ctx
            .output
            .group(&format!("{}/strain/{name}", group.name()))?;
        write_u32(&g, "ids", &b.ids, &[b.ids.len()])?;
        write_f64(&g, "top", &b.first, &[b.ids.len(), 3])?;
        write_f64(&g, "bottom", &b.second, &[b.ids.len(), 3])?;
    }
    for (name, b) in &strains.solids {
        let g = ctx
            .output
            .group(&format!("{}/strain/{name}", group.name()))?;
        write_u32(&g, "ids", &b.ids, &[b.ids.len()])?;
        write_f64(&g, "centroid", &b.first, &[b.ids.len(), 6])?;
    }
    Ok(())
}

impl Report for StaticsSummary {
    fn render(&self, subcase: u32) -> Vec<String> {
        let st = self;
        let mut out = vec![format!("subcase {}: f-set {} DOFs", subcase, st.f_size)];
        if st.max_component.2 == 0.0 {
            out.push(
                "  displacements are all zero (see the applied load and SPC reaction below)"
                    .to_string(),
            );
        } else {
            out.push(format!(
                "  max |u| (translation)  {} at GRID {}",
                sci(st.max_translation.1, 6),
                st.max_translation.0
            ));
            out.push(format!(
                "  max |component|        {} at GRID {} component {}",
                sci(st.max_component.2, 6),
                st.max_component.0,
                st.max_component.1
            ));
        }
        let f =
            |v: &[f64; 6]| format!("F = [{}, {}, {}]", sci(v[0], 6), sci(v[1], 6), sci(v[2], 6));
        out.push(format!("  applied load           {}", f(&st.applied)));
        out.push(format!("  SPC reaction           {}", f(&st.reaction)));
        out
    }

    fn warnings(&self, _subcase: u32) -> Vec<String> {
        self.pivot_warning.iter().cloned().collect()
    }
}
