//! SOL 101 (STATICS): K_ff u_f = P_f for every subcase, by sparse Cholesky.
//!
//! Order (as `assembly::tests::solve`, with the sparse LLᵀ):
//! 1. f-set of `SPC = sid` (+ GRID PS, AUTOSPC) — [`Constrained`];
//! 2. K_ff = LLᵀ: one symbolic analysis *and* one numeric factor per distinct f-set, shared by
//!    every subcase with that f-set (K does not depend on the load). A failing pivot is a
//!    mechanism, reported with its GRID and component;
//! 3. P_g of `LOAD = sid` (FORCE, MOMENT, GRAV with M_gg), P_f = (Tᵀ P_g)_f − K_fs u_s;
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
//! The SPC forces are always computed (one K·u product): the console summary's reaction sum
//! uses them.

use super::driver::{Basis, Driver};
use super::report::{Report, sci};
use super::shared::structure;
use super::{Clock, GridRows, RunContext, RunError, SubcaseSummary, requested, selected};
use crate::assembly::loads::{Mass, load_vector, reduce_load};
use crate::assembly::recover::{expand_f_to_n, spc_forces};
use crate::deck::Solution;
use crate::deck::case_control::Subcase;
use crate::discretize::elements::{element_displacements, shell_strains, solid_kind_of};
use crate::discretize::{Constrained, DiscretizeError, Structure};
use crate::fe::solid;
use crate::io::{write_f64, write_u32};
use crate::linalg::{Factor, SymbolicFactor};

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
}

/// The STATICS driver on the mesh.
pub struct Statics;

/// The output requests STATICS writes: displacements (every grid when not requested at all, none for `= NONE`), SPC forces and strains on request.
pub const HONOURED: &[&str] = &["DISPLACEMENT", "SPCFORCES", "STRAIN"];

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

    fn honoured(&self) -> &'static [&'static str] {
        HONOURED
    }

    fn run(&self, ctx: &RunContext, clock: &mut Clock) -> Result<Vec<SubcaseSummary>, RunError> {
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
    let mut factors: Vec<(Vec<usize>, Factor)> = Vec::new();
    let mut symbolic: Option<(Vec<usize>, SymbolicFactor)> = None;
    let par = ctx.options.par();
    let m_gg = st.mass_gg();
    let mut m_gg_values = vec![0.0; m_gg.pattern().nnz()];
    m_gg.evaluate_into(&st.weights(m_gg), &mut m_gg_values)?;
    let mut out = Vec::new();
    for sub in &ctx.model.subcases {
        let id = sub.id;
        let c = clock.time(format!("subcase {id}: constraints"), || {
            Constrained::build(ctx.model, st, sub.spc)
        })?;
        let f = c.sets.f.members().to_vec();
        if !factors.iter().any(|(key, _)| *key == f) {
            let sym = match &symbolic {
                Some((key, s)) if *key == f => s.clone(),
                _ => {
                    let s = clock
                        .time(format!("subcase {id}: symbolic analysis"), || {
                            SymbolicFactor::analyze(c.k_ff.pattern())
                        })
                        .map_err(|e| RunError::Linalg {
                            subcase: id,
                            source: e,
                        })?;
                    symbolic = Some((f.clone(), s.clone()));
                    s
                }
            };
            ctx.progress.step("factorization", 0, 1);
            let factor = clock
                .time(format!("subcase {id}: Cholesky"), || {
                    sym.clone()
                        .with_max_ratio(ctx.model.params.maxratio)
                        .factor_llt(&c.k_ff, par)
                })
                .map_err(|e| super::mechanism(&c, st, id, e))?;
            ctx.progress.step("factorization", 1, 1);
            factors.push((f.clone(), factor));
        }
        let factor = &factors
            .iter()
            .find(|(key, _)| *key == f)
            .map(|(_, fa)| fa)
            .ok_or(RunError::NoSolution)?;
        let summary = clock.time(format!("subcase {id}: solve and output"), || {
            solve_subcase(ctx, st, &c, sub, factor, &m_gg_values)
        })?;
        out.push(SubcaseSummary {
            id,
            autospc: c.autospc.names.clone(),
            result: Box::new(summary),
        });
    }
    Ok(out)
}

fn solve_subcase(
    ctx: &RunContext,
    st: &Structure,
    c: &Constrained,
    sub: &Subcase,
    factor: &Factor,
    m_gg_values: &[f64],
) -> Result<StaticsSummary, RunError> {
    let id = sub.id;
    let model = ctx.model;
    let p_g = match sub.load {
        Some(sid) => load_vector(
            model,
            &st.frames,
            &st.map,
            sid,
            Some(Mass {
                operator: st.mass_gg(),
                values: m_gg_values,
            }),
        )?,
        None => vec![0.0; st.map.size()],
    };
    let k_fs_values = c.k_fs.evaluate(&st.weights(&c.k_fs))?.values().to_vec();
    let p_f = reduce_load(
        &p_g,
        &st.rigid,
        &c.sets,
        &c.k_fs,
        &k_fs_values,
        &c.spc.enforced,
    )?;
    let u_f = c.solve_static(factor, &p_f).map_err(|e| RunError::Linalg {
        subcase: id,
        source: e,
    })?;
    let u_n = expand_f_to_n(&u_f, &c.sets, &c.spc.enforced)?;
    let u_g = st.rigid.expand(&u_n)?;
    let p_n = st.rigid.reduce_vector(&p_g)?;
    let q_s = spc_forces(&st.k_nn, &c.k_nn_values, &u_n, &p_n, &c.sets)?;
    let mut q_g = vec![0.0; st.map.size()];
    c.sets.s.scatter_into(&q_s, &mut q_g)?;

    let n = st.map.grids();
    let u = st.to_basic_rows(&u_g);
    let q = st.to_basic_rows(&q_g);
    let p = st.to_basic_rows(&p_g);
    let group = ctx.output.group(&format!("results/{id}/statics"))?;
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
        write_strains(ctx, st, &group, &u, |eid| selected(ctx.deck, req, eid))?;
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
    })
}

/// Σ forces and Σ (moments + x × F) about the basic origin of n×6 basic rows.
fn resultant(model: &crate::model::Model, rows: &[f64]) -> [f64; 6] {
    let mut out = [0.0; 6];
    for (g, grid) in model.grids.iter().enumerate() {
        let r = &rows[6 * g..6 * g + 6];
        let f = [r[0], r[1], r[2]];
        let m = crate::geometry::vec3::cross(grid.xyz, f);
        for k in 0..3 {
            out[k] += f[k];
            out[3 + k] += r[3 + k] + m[k];
        }
    }
    out
}

/// Strain blocks by output name, in element order.
#[derive(Default)]
struct Block {
    ids: Vec<u32>,
    a: Vec<f64>,
    b: Vec<f64>,
}

fn write_strains(
    ctx: &RunContext,
    st: &Structure,
    group: &hdf5_metno::Group,
    u: &[f64],
    keep: impl Fn(u32) -> bool,
) -> Result<(), RunError> {
    let model = ctx.model;
    let mut shells: std::collections::BTreeMap<&'static str, Block> = Default::default();
    for (idx, rec) in &st.shells {
        let e = &model.elements[*idx];
        if !keep(e.id) {
            continue;
        }
        let strains = shell_strains(model, e, rec, &element_displacements(u, &e.nodes))?;
        let block = shells.entry(e.kind.block_name()).or_default();
        block.ids.push(e.id);
        block.a.extend(strains.top);
        block.b.extend(strains.bottom);
    }
    for (name, b) in &shells {
        let g = ctx
            .output
            .group(&format!("{}/strain/{name}", group.name()))?;
        write_u32(&g, "ids", &b.ids, &[b.ids.len()])?;
        write_f64(&g, "top", &b.a, &[b.ids.len(), 3])?;
        write_f64(&g, "bottom", &b.b, &[b.ids.len(), 3])?;
    }
    let mut solids: std::collections::BTreeMap<&'static str, Block> = Default::default();
    for e in &model.elements {
        let Some(kind) = solid_kind_of(e.kind) else {
            continue;
        };
        if !keep(e.id) {
            continue;
        }
        let xyz = model.positions(e);
        let ut: Vec<f64> = e
            .nodes
            .iter()
            .flat_map(|&a| u[6 * a..6 * a + 3].iter().copied())
            .collect();
        let eps =
            solid::strain_at_centroid(kind, &xyz, &ut).map_err(|x| DiscretizeError::Element {
                card: e.kind.card(),
                id: e.id,
                reason: x.to_string(),
            })?;
        let block = solids.entry(e.kind.block_name()).or_default();
        block.ids.push(e.id);
        block.a.extend(eps);
    }
    for (name, b) in &solids {
        let g = ctx
            .output
            .group(&format!("{}/strain/{name}", group.name()))?;
        write_u32(&g, "ids", &b.ids, &[b.ids.len()])?;
        write_f64(&g, "centroid", &b.a, &[b.ids.len(), 6])?;
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
}
