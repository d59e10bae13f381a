//! `SOL PROM`: build a parametric reduced-order model (DESIGN.md §7; thesis §3.4, §4.2) and
//! write it as the `/prom` group of the run's output, loadable by other decks with
//! `ROM = 'file.h5'`.
//!
//! One subcase selects the `PMOR` card (`PROM = id`) and optionally an `SPC` set. The PMPARs
//! give the parameter box; the affine f-set operators of [`Structure`] (every part reduced
//! g → n → f on one pattern) are handed to [`build_prom`]. `BSET` > 0 takes the deck's a-set
//! (every ASET1) as the boundary DOFs: static modes, FRF-error inputs/outputs and the pROM's
//! load inputs (`/prom/inputs`). Damping: Rayleigh α, β from `PARAM,ALPHA1` / `PARAM,BETA1`.
//!
//! Written: `/prom` ([`write_prom`]), `/prom/inputs/{names, S_r}` (n_red × n_in),
//! `/prom/sensors/{names, kind, H_r}` (s × n_red): H_r = H Φ with the f-set rows H of the
//! subcase's SENSORs ([`crate::discretize::sensors`]: DISP, VEL, ACCEL and STRAIN, eq. 2.32, 2.34),
//! `/prom/nodal_mass`, `/prom/invariants` and `/prom/interface` ([`crate::io::write_prom_body`]: affine
//! nodal masses eq. 4.1–4.3, the affine components of the mass invariants eq. 4.8, A.11–A.19,
//! and the basis rows of the ASET1 grids; only with `RIGID = REMOVE`, the floating-frame bodies
//! of a multibody scene, which are the only users), `/prom/basis/{grids, rows}` (the basis rows
//! of the grids a `DISPLACEMENT = ALL | set` request selects, with any RIGID: what a peer code
//! that takes the mode shapes at every node, e.g. an FFRF body of another multibody program,
//! needs), and
//! `/prom/build/{samples, singular_values, size_history, error_history, timings}` with
//! attributes `mac_kept`, `concatenated`, `converged`, `singular_lines`.

use super::driver::{Basis, Driver};
use super::shared::structure;
use crate::deck::Solution;
use std::collections::HashMap;

use super::GridRows;
use super::report::{Report, sci};
use super::{Clock, RunContext, RunError, SubcaseSummary};
use crate::assembly::DofMap;
use crate::deck::cards::{Pmor, PmorRigid, PmorStatic};
use crate::discretize::sensors::sensor_kind_name;
use crate::discretize::{
    Constrained, Structure, affine_fom, affine_keys, basic_columns, flexible_body,
};
use crate::io::{
    IoError, set_attr_i64, set_attr_strings, write_f64, write_mat, write_prom, write_prom_basis,
    write_prom_body, write_strings,
};
use crate::rom::build::{BuildLog, Built, PromSettings, build_prom};
use crate::rom::invariants::InterfaceRows;
use crate::rom::local_basis::{RigidModes, StaticModes};
use crate::rom::mass::AffineMasses;

/// What a pROM build reports.
#[derive(Debug, Clone)]
pub struct PromSummary {
    pub n_full: usize,
    pub n_red: usize,
    pub parameters: Vec<String>,
    pub inputs: usize,
    /// SENSOR rows projected (DISP, VEL, ACCEL, STRAIN).
    pub sensors: usize,
    pub log: BuildLog,
    /// The PMPARs whose CQUAD4 condensation is frozen at the deck's values
    /// ([`Structure::frozen_condensation`]).
    pub frozen_condensation: Vec<String>,
}

/// The PROM driver on the mesh.
pub struct PromBuild;

impl Driver for PromBuild {
    fn name(&self) -> &'static str {
        "PROM"
    }

    fn solutions(&self) -> &'static [Solution] {
        &[Solution::Prom]
    }

    fn basis(&self) -> Basis {
        Basis::Mesh
    }

    fn honoured(&self) -> &'static [&'static str] {
        &["DISPLACEMENT"]
    }

    fn run(&self, ctx: &RunContext, clock: &mut Clock) -> Result<Vec<SubcaseSummary>, RunError> {
        let st = structure(ctx, clock)?;
        run(ctx, &st, clock)
    }
}

/// Runs the (single) PROM subcase.
fn run(
    ctx: &RunContext,
    st: &Structure,
    clock: &mut Clock,
) -> Result<Vec<SubcaseSummary>, RunError> {
    let model = ctx.model;
    let subs: Vec<_> = model.subcases.iter().filter(|s| s.prom.is_some()).collect();
    let sub = match subs.as_slice() {
        [one] => *one,
        [] => {
            return Err(RunError::Case {
                subcase: model.subcases.first().map_or(1, |s| s.id),
                what: "SOL PROM needs PROM = <PMOR id> in case control".into(),
            });
        }
        more => {
            return Err(RunError::Case {
                subcase: more[1].id,
                what: "SOL PROM builds one pROM per run: only one subcase may select PROM".into(),
            });
        }
    };
    let id = sub.id;
    let pmor = sub
        .prom
        .and_then(|pid| model.pmor(pid))
        .ok_or_else(|| RunError::Case {
            subcase: id,
            what: "PMOR missing".into(),
        })?;
    if st.params.is_empty() {
        return Err(RunError::Case {
            subcase: id,
            what: "SOL PROM needs at least one PMPAR (the parameters of the pROM)".into(),
        });
    }
    let c = clock.time(format!("subcase {id}: constraints"), || {
        Constrained::build(model, st, sub.spc)
    })?;
    let (k_ff, m_ff) = c.affine_ff(st)?;
    let keys = affine_keys(&k_ff, &m_ff);
    let fom = affine_fom(st, &keys, &k_ff, &m_ff)?;
    let masses = match settings_rigid(pmor) {
        RigidModes::Remove => Some(AffineMasses::lump(
            st.mass_gg(),
            &keys,
            &st.frames,
            model.grids.iter().map(|g| g.xyz).collect(),
        )?),
        RigidModes::Keep => None,
    };
    let (boundary, names) = boundary(ctx, &c, pmor, id)?;
    let settings = settings(pmor, model.params.alpha1, model.params.beta1);
    let Built {
        prom,
        inputs,
        basis,
        log,
    } = clock
        .time(format!("subcase {id}: pROM build"), || {
            build_prom(&fom, &boundary, &settings, ctx.progress)
        })
        .map_err(|e| RunError::Case {
            subcase: id,
            what: format!("pROM build: {e}"),
        })?;
    let sensors = clock.time(format!("subcase {id}: sensor rows"), || {
        super::subcase_sensors(ctx, st, &c, sub)
    })?;
    let h_r = sensors.project(&basis);
    let requested_rows = GridRows::of_subcase(ctx.deck, &st.map, sub, "DISPLACEMENT", None);
    let columns = if masses.is_some() || requested_rows.is_some() {
        basic_columns(st, &c, &basis)?
    } else {
        Vec::new()
    };
    drop(basis);
    let body = masses.map(|masses| flexible_body(model, st, &columns, masses));
    let basis_rows = requested_rows.map(|rows| {
        let indices = rows.indices(&st.map);
        let ids = indices.iter().filter_map(|&g| st.map.grid_id(g)).collect();
        InterfaceRows::from_grid_columns(&columns, ids, &indices)
    });
    drop(columns);
    let n_full = k_ff.nrows();
    clock.time(
        format!("subcase {id}: output"),
        || -> Result<(), IoError> {
            let group = ctx.output.group("prom")?;
            write_prom(&group, &prom, n_full)?;
            let inputs_group = ctx.output.group("prom/inputs")?;
            let name_refs: Vec<&str> = names.iter().map(String::as_str).collect();
            write_strings(&inputs_group, "names", &name_refs)?;
            write_mat(&inputs_group, "S_r", &inputs)?;
            if !sensors.names.is_empty() {
                let g = ctx.output.group("prom/sensors")?;
                let names: Vec<&str> = sensors.names.iter().map(String::as_str).collect();
                write_strings(&g, "names", &names)?;
                let kinds: Vec<&str> = sensors.kinds.iter().map(|k| sensor_kind_name(*k)).collect();
                write_strings(&g, "kind", &kinds)?;
                write_mat(&g, "H_r", &h_r)?;
            }
            if let Some(body) = &body {
                write_prom_body(&group, body)?;
            }
            if let Some(rows) = &basis_rows {
                write_prom_basis(&group, rows)?;
            }
            write_log(ctx, &log)
        },
    )?;
    let summary = PromSummary {
        n_full,
        n_red: prom.size(),
        parameters: prom.parameters.iter().map(|p| p.name.clone()).collect(),
        inputs: names.len(),
        sensors: sensors.len(),
        log,
        frozen_condensation: st.frozen_condensation.clone(),
    };
    Ok(vec![SubcaseSummary {
        id,
        autospc: c.autospc.names.clone(),
        result: Box::new(summary),
    }])
}

/// BSET: every ASET1 DOF, as f-set indices, with "GRID:component" names.
fn boundary(
    ctx: &RunContext,
    c: &Constrained,
    pmor: &Pmor,
    subcase: u32,
) -> Result<(Vec<usize>, Vec<String>), RunError> {
    if pmor.bset.is_none() {
        return Ok((Vec::new(), Vec::new()));
    }
    let model = ctx.model;
    let f_of: HashMap<usize, usize> = c
        .sets
        .f
        .members()
        .iter()
        .enumerate()
        .map(|(i, &g)| (g, i))
        .collect();
    let mut out = Vec::new();
    let mut names = Vec::new();
    for card in model.aset1() {
        for &grid in &card.grids {
            let index = *model.grid_index.get(&grid).ok_or_else(|| RunError::Case {
                subcase,
                what: format!("ASET1 grid {grid} does not exist"),
            })?;
            for comp in card.components.components() {
                let g = DofMap::dof(index, comp - 1);
                let f = *f_of.get(&g).ok_or_else(|| RunError::Case {
                    subcase,
                    what: format!("PMOR {} BSET: GRID {grid} component {comp} is constrained (SPC, AUTOSPC) or dependent (RBE); boundary DOFs must be free", pmor.id),
                })?;
                if !out.contains(&f) {
                    out.push(f);
                    names.push(format!("{grid}:{comp}"));
                }
            }
        }
    }
    if out.is_empty() {
        return Err(RunError::Case {
            subcase,
            what: format!("PMOR {} asks for BSET but the deck has no ASET1", pmor.id),
        });
    }
    Ok((out, names))
}

fn settings_rigid(p: &Pmor) -> RigidModes {
    match p.rigid {
        PmorRigid::Keep => RigidModes::Keep,
        PmorRigid::Remove => RigidModes::Remove,
    }
}

fn settings(p: &Pmor, alpha: f64, beta: f64) -> PromSettings {
    let statics = match p.static_modes {
        PmorStatic::Attach => StaticModes::Attach,
        PmorStatic::Constr => StaticModes::Constr,
        PmorStatic::None => StaticModes::None,
    };
    let rigid = settings_rigid(p);
    PromSettings {
        n_samples: p.nsamp as usize,
        n_modes: p.nmodes as usize,
        fmax_hz: p.fmax,
        fmin_hz: p.fmin,
        n_freq: p.nfreq as usize,
        errtol: p.errtol,
        dsize: p.dsize as usize,
        mac_tol: p.mactol,
        seed: p.seed,
        statics,
        rigid,
        alpha,
        beta,
    }
}

fn write_log(ctx: &RunContext, log: &BuildLog) -> Result<(), IoError> {
    let g = ctx.output.group("prom/build")?;
    let n_p = log.samples.first().map_or(0, Vec::len);
    write_f64(
        &g,
        "samples",
        &log.samples.concat(),
        &[log.samples.len(), n_p],
    )?;
    write_f64(
        &g,
        "singular_values",
        &log.singular_values,
        &[log.singular_values.len()],
    )?;
    let sizes: Vec<f64> = log.error_history.iter().map(|(s, _)| *s as f64).collect();
    let errors: Vec<f64> = log.error_history.iter().map(|(_, e)| *e).collect();
    write_f64(&g, "size_history", &sizes, &[sizes.len()])?;
    write_f64(&g, "error_history", &errors, &[errors.len()])?;
    let seconds: Vec<f64> = log.timings.iter().map(|(_, t)| *t).collect();
    write_f64(&g, "timings", &seconds, &[seconds.len()])?;
    let phases: Vec<&str> = log.timings.iter().map(|(n, _)| n.as_str()).collect();
    set_attr_strings(&g, "timing_phases", &phases)?;
    set_attr_i64(&g, "mac_kept", log.mac_kept as i64)?;
    set_attr_i64(&g, "concatenated", log.concatenated as i64)?;
    set_attr_i64(&g, "converged", i64::from(log.converged))?;
    set_attr_i64(&g, "singular_lines", log.singular_lines as i64)
}

impl Report for PromSummary {
    fn render(&self, subcase: u32) -> Vec<String> {
        let p = self;
        let log = &p.log;
        let mut out = vec![format!(
            "subcase {}: pROM of {} DOFs → {} (parameters {}; {} input(s), {} sensor(s))",
            subcase,
            p.n_full,
            p.n_red,
            p.parameters.join(", "),
            p.inputs,
            p.sensors
        )];
        out.push(format!(
            "  samples {}, local bases {} columns, {} after the MAC filter, numerical rank {}",
            log.samples.len(),
            log.concatenated,
            log.mac_kept,
            log.singular_values
                .iter()
                .filter(|&&s| s > crate::rom::build::RANK_TOL
                    * log.singular_values.first().copied().unwrap_or(0.0))
                .count()
        ));
        for (size, e) in &log.error_history {
            out.push(format!(
                "  size {size:>5}: FRF change (eq. 3.35) {}",
                sci(*e, 2)
            ));
        }
        out.push(format!(
            "  {}",
            match (p.inputs, log.converged) {
                (0, _) =>
                    "no input DOFs (ASET1): no FRF to choose the size, the whole numerical rank is kept (see warnings)",
                (_, true) => "converged (FRF change below ERRTOL)",
                (_, false) => "stopped at the numerical rank of the local bases (see warnings)",
            }
        ));
        out
    }

    fn warnings(&self, subcase: u32) -> Vec<String> {
        let p = self;
        let mut warnings = Vec::new();
        if !p.frozen_condensation.is_empty() {
            warnings.push(format!(
                "subcase {}: PMPAR {} change(s) by more than a scale the section of CQUAD4s whose incompatible membrane modes are condensed once with the deck's section (PARAM,QINCOMP,YES, the default; docs/elements.md \"Frozen condensation\"): the pROM is exact for that model, but differs from a deck rebuilt at parameter values far from the nominal ones (second order in the change); PARAM,QINCOMP,NO restores exact agreement at the cost of in-plane bending accuracy (the membrane without modes is ≈ 1/(1−ν²) too stiff on rectangles and locks on distorted quads)",
                subcase,
                p.frozen_condensation.join(", ")
            ));
        }
        if p.inputs == 0 {
            warnings.push(format!(
                "subcase {}: the pROM has no input DOFs (no ASET1, or PMOR BSET blank): the FRF error of eq. 3.35 cannot choose its size, so all {} basis vectors are kept; give the load and support DOFs as ASET1 to get inputs and a size chosen by ERRTOL",
                subcase, p.n_red
            ));
        } else if !p.log.converged {
            let last = p
                .log
                .error_history
                .last()
                .map_or("not measured".to_string(), |(size, e)| {
                    format!("{e:.2e} at size {size}")
                });
            warnings.push(format!(
                "subcase {}: the pROM uses the whole numerical rank of the local bases ({}) but the last growth step still changed the FRFs by {last} (eq. 3.35, summed over {} input/output pairs), above ERRTOL; more samples or modes would make the basis richer",
                subcase,
                p.n_red,
                p.inputs * p.inputs
            ));
        }
        warnings
    }
}
