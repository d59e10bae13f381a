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
//! subcase's SENSORs ([`sensor_operator`]: DISP, VEL, ACCEL and STRAIN, eq. 2.32, 2.34),
//! `/prom/nodal_mass`, `/prom/invariants` and `/prom/interface` ([`write_prom_body`]: affine
//! nodal masses eq. 4.1–4.3, the affine components of the mass invariants eq. 4.8, A.11–A.19,
//! and the basis rows of the ASET1 grids; only with `RIGID = REMOVE`, the floating-frame bodies
//! of a multibody scene, which are the only users), and
//! `/prom/build/{samples, singular_values, size_history, error_history, timings}` with
//! attributes `mac_kept`, `concatenated`, `converged`, `singular_lines`.

use std::collections::HashMap;

use faer::Mat;
use nalgebra_sparse::CscMatrix;

use super::sensors::{sensor_kind_name, sensor_operator};
use super::{Clock, Constrained, RunContext, RunError, Structure, SubcaseResult, SubcaseSummary};
use crate::assembly::recover::recover_g;
use crate::assembly::{AffineOperator, DofMap, ParamKey};
use crate::deck::cards::Pmor;
use crate::io::{
    IoError, PromBody, set_attr_i64, set_attr_strings, write_f64, write_prom, write_prom_body,
    write_strings,
};
use crate::rom::build::{AffineFom, BuildLog, Built, PromSettings, build_prom};
use crate::rom::invariants::{InterfaceRows, MassInvariants, TranslationRows};
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

/// Runs the (single) PROM subcase.
pub fn run(
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
    let pmor = model
        .bulk
        .pmor
        .iter()
        .find(|p| Some(p.id) == sub.prom)
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
        sensor_operator(ctx, st, &c, sub)
    })?;
    let h_r = sensors.project(&basis);
    let body = masses
        .map(|masses| flexible_body(ctx, st, &c, &basis, masses))
        .transpose()?;
    drop(basis);
    let n_full = k_ff.nrows();
    clock.time(
        format!("subcase {id}: output"),
        || -> Result<(), IoError> {
            let group = ctx.output.group("prom")?;
            write_prom(&group, &prom, n_full)?;
            let inputs_group = ctx.output.group("prom/inputs")?;
            let name_refs: Vec<&str> = names.iter().map(String::as_str).collect();
            write_strings(&inputs_group, "names", &name_refs)?;
            let (n, k) = (inputs.nrows(), inputs.ncols());
            write_f64(&inputs_group, "S_r", &row_major(&inputs), &[n, k])?;
            if !sensors.names.is_empty() {
                let g = ctx.output.group("prom/sensors")?;
                let names: Vec<&str> = sensors.names.iter().map(String::as_str).collect();
                write_strings(&g, "names", &names)?;
                let kinds: Vec<&str> = sensors.kinds.iter().map(|k| sensor_kind_name(*k)).collect();
                write_strings(&g, "kind", &kinds)?;
                write_f64(&g, "H_r", &row_major(&h_r), &[h_r.nrows(), h_r.ncols()])?;
            }
            if let Some(body) = &body {
                write_prom_body(&group, body)?;
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
        result: SubcaseResult::Prom(summary),
    }])
}

fn row_major(m: &Mat<f64>) -> Vec<f64> {
    (0..m.nrows())
        .flat_map(|i| (0..m.ncols()).map(move |j| m[(i, j)]))
        .collect()
}

/// The multibody data of a `RIGID = REMOVE` body: the basis columns expanded to every grid in
/// basic (dependent DOFs recovered, constrained ones zero), the invariants of each affine mass
/// component (eq. 4.8, A.11–A.19) and the rows of the interface grids (every ASET1 grid).
fn flexible_body(
    ctx: &RunContext,
    st: &Structure,
    c: &Constrained,
    basis: &Mat<f64>,
    masses: AffineMasses,
) -> Result<PromBody, RunError> {
    let model = ctx.model;
    let zero = vec![0.0; st.map.size()];
    let columns = (0..basis.ncols())
        .map(|k| {
            Ok(st.to_basic_rows(&recover_g(
                basis.col_as_slice(k),
                &c.sets,
                &zero,
                &st.rigid,
            )?))
        })
        .collect::<Result<Vec<_>, RunError>>()?;
    let rows = TranslationRows::from_grid_columns(&columns, st.map.grids());
    let invariants = masses
        .nodal
        .iter()
        .map(|m| MassInvariants::new(m, &masses.positions, &rows))
        .collect();
    let (mut ids, mut indices) = (Vec::new(), Vec::new());
    for &grid in model.bulk.aset1.iter().flat_map(|card| &card.grids) {
        if let (false, Some(&index)) = (ids.contains(&grid), model.grid_index.get(&grid)) {
            ids.push(grid);
            indices.push(index);
        }
    }
    Ok(PromBody {
        grids: model.grids.iter().map(|g| g.id).collect(),
        masses,
        invariants,
        interface: InterfaceRows::from_grid_columns(&columns, ids, &indices),
    })
}

/// The part keys of K and M, K's first: the pROM's component order.
fn affine_keys(k: &AffineOperator, m: &AffineOperator) -> Vec<ParamKey> {
    let mut keys: Vec<ParamKey> = k.keys();
    for key in m.keys() {
        if !keys.contains(&key) {
            keys.push(key);
        }
    }
    keys
}

/// The affine FOM on the f-set: one function per key (a zero matrix where an operator lacks
/// that key).
fn affine_fom(
    st: &Structure,
    keys: &[ParamKey],
    k: &AffineOperator,
    m: &AffineOperator,
) -> Result<AffineFom, RunError> {
    let matrices = |op: &AffineOperator| -> Result<Vec<CscMatrix<f64>>, RunError> {
        keys.iter()
            .map(|&key| {
                Ok(op.matrix(
                    op.part(key)
                        .map_or_else(|| vec![0.0; op.pattern().nnz()], <[f64]>::to_vec),
                )?)
            })
            .collect()
    };
    Ok(AffineFom {
        parameters: st.params.list.clone(),
        functions: keys.iter().map(|&key| st.params.function(key)).collect(),
        stiffness: matrices(k)?,
        mass: matrices(m)?,
    })
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
    for card in &model.bulk.aset1 {
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
    if p.rigid == "REMOVE" {
        RigidModes::Remove
    } else {
        RigidModes::Keep
    }
}

fn settings(p: &Pmor, alpha: f64, beta: f64) -> PromSettings {
    let statics = match p.static_modes {
        "CONSTR" => StaticModes::Constr,
        "NONE" => StaticModes::None,
        _ => StaticModes::Attach,
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
