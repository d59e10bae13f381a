//! `SOL FRF` on the full model: SOL 108 (direct) and SOL 111 (modal); `SOL FRF` is modal when
//! the subcase selects `METHOD`, direct otherwise.
//!
//! Per subcase:
//! - frequencies: `FREQUENCY = sid` (FREQ, FREQ1, FREQ2 of that SID, combined, sorted,
//!   duplicates removed) — [`frequency_lines`], shared with the pROM FRF;
//! - inputs: `DLOAD = sid` (a DLOAD combination S·Σ Sᵢ·Lᵢ or one RLOAD1 set): every DAREA
//!   entry of its RLOAD1s' EXCITEIDs is an input DOF `GRID:component` (components in the
//!   grid's CD frame, as for Nastran's DAREA), loaded by a unit force through Tᵀ (a dependent
//!   RBE DOF spreads to its independent DOFs). A constrained input DOF is an error;
//! - outputs: the input DOFs (receptance, like the pROM FRF) and the SENSORs the subcase selects
//!   ([`sensor_operator`]: DISP and STRAIN per unit force, VEL × iω, ACCEL × −ω², the
//!   measurement equations' (iω)^k of [`crate::dynamics::measurement`]);
//! - damping: Rayleigh C = αM + βK from `PARAM,ALPHA1` / `PARAM,BETA1` (as the pROM build) and
//!   structural damping `PARAM,G` as Nastran: K(1 + iG) in the direct solution, G on each modal
//!   stiffness ω_j²(1 + iG) in the modal one;
//! - direct: one sparse complex LU symbolic analysis of K_ff − ω²M_ff + iωC_ff, one numeric LU
//!   (plus one refinement step) per line, lines in parallel ([`direct_receptance`]);
//! - modal: the modes of `METHOD = sid` (EIGRL, shift-invert Lanczos as SOL 103, mass
//!   normalized) and, unless `PARAM,RESVEC,NO`, the residual vectors of the inputs' load shapes
//!   ([`residual_vectors`], Nastran's RESVEC default in modal frequency response), superposed
//!   with modal damping 2ζ_jω_j = α + βω_j² ([`modal_receptance`]). The residual vectors carry
//!   the static part of the modes left out (exact at 0 Hz); on a free-free model (K singular)
//!   they are skipped with a warning and EIGRL should reach well above the band.
//!
//! Written: `/results/<id>/frf/{frequency_hz (f), H (f × o × i, complex as h5py), inputs (i),
//! outputs (o), response (f × o)}` with attributes `method` (`direct`/`modal`) and `modes`.
//! `response` is the deck's load applied to H: P_d(f) = Σ S·A_d·(C(f) + iD(f))·e^{i(θ − 2πfτ)}
//! over the RLOAD1 terms (TC, TD tables: TABLED1 or TABLEF) and their DAREA scales A_d.
//! Only when the subcase asks `DISPLACEMENT = ALL | set`: `displacement (f × k × 6)`, the
//! complex response of the selected grids to that load in basic (Nastran's SOL 108/111
//! displacement output; `displacement_grid_ids` for a set). Their rows join the outputs of the
//! solve and are dropped from H.

use faer::{Mat, c64};
use nalgebra_sparse::{CooMatrix, CscMatrix};

use super::sensors::{displacement_rows, sensor_operator};
use super::{
    Clock, Constrained, GridRows, RunContext, RunError, Structure, SubcaseResult, SubcaseSummary,
};
use crate::assembly::DofMap;
use crate::deck::Solution;
use crate::deck::case_control::Subcase;
use crate::dynamics::frf::{
    SparseModel, direct_receptance, modal_receptance, residual_vectors, static_stiffness_is_regular,
};
use crate::dynamics::measurement::Reads;
use crate::dynamics::table::Table;
use crate::io::csv_table::read_columns;
use crate::io::{IoError, set_attr_i64, set_attr_str, write_c64, write_f64, write_strings};
use crate::linalg::{EigenProblem, EigenRequest, LanczosOptions, SymbolicFactor, solve_modes};
use crate::model::Model;

/// How the full-model FRF is computed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FrfMethod {
    Direct,
    Modal,
}

impl FrfMethod {
    pub fn name(self) -> &'static str {
        match self {
            FrfMethod::Direct => "direct",
            FrfMethod::Modal => "modal",
        }
    }
}

/// What one full-model FRF subcase computed.
#[derive(Debug, Clone)]
pub struct FrfSummary {
    pub method: FrfMethod,
    pub lines: usize,
    pub inputs: Vec<String>,
    pub outputs: Vec<String>,
    /// Modes superposed (modal) or 0 (direct).
    pub modes: usize,
    /// Residual vectors superposed with the modes: Some(count) when PARAM,RESVEC asked and K is
    /// regular, `Some(0)` when the modes already hold the load shapes; None otherwise (direct,
    /// RESVEC NO, or K singular: see [`Self::resvec_skipped`]).
    pub residual_vectors: Option<usize>,
    /// RESVEC asked, but K is singular (free-free or a mechanism): modes only.
    pub resvec_skipped: bool,
    pub f_size: usize,
    /// Largest |H| over lines and pairs, with its frequency (Hz).
    pub peak: (f64, f64),
}

/// The frequency lines (Hz) of the subcase's `FREQUENCY = sid`: every FREQ, FREQ1, FREQ2 of
/// that SID, sorted, duplicates removed.
pub fn frequency_lines(model: &Model, sub: &Subcase) -> Result<Vec<f64>, RunError> {
    let case = |what: String| RunError::Case {
        subcase: sub.id,
        what,
    };
    let sid = sub
        .frequency
        .ok_or_else(|| case("SOL FRF needs FREQUENCY = <FREQ sid> in case control".into()))?;
    let mut hz: Vec<f64> = model
        .bulk
        .freq
        .iter()
        .filter(|f| f.sid == sid)
        .flat_map(|f| f.frequencies())
        .collect();
    if hz.is_empty() {
        return Err(case(format!(
            "FREQUENCY = {sid} selects no FREQ, FREQ1 or FREQ2 card"
        )));
    }
    hz.sort_by(f64::total_cmp);
    hz.dedup();
    Ok(hz)
}

/// Scales H by each output row's (iω)^k ([`Reads::frequency_factor`]: the input DOFs, DISP and
/// STRAIN read displacement, VEL iω, ACCEL −ω²) and flattens it line-major (f × o × i); also
/// returns the largest |H| and its frequency.
pub fn scaled_flat(h: &[Mat<c64>], hz: &[f64], reads: &[Reads]) -> (Vec<c64>, (f64, f64)) {
    let mut flat = Vec::with_capacity(h.iter().map(|m| m.nrows() * m.ncols()).sum());
    let mut peak = (0.0_f64, 0.0);
    for (hw, f) in h.iter().zip(hz) {
        let w = 2.0 * std::f64::consts::PI * f;
        for (o, row) in reads.iter().enumerate() {
            let factor = row.frequency_factor(w);
            for i in 0..hw.ncols() {
                let z = hw[(o, i)] * factor;
                if z.norm() > peak.0 {
                    peak = (z.norm(), *f);
                }
                flat.push(z);
            }
        }
    }
    (flat, peak)
}

/// Writes `frequency_hz`, `H` (f × o × i), `inputs` and `outputs` into `group`.
pub fn write_frf(
    group: &hdf5_metno::Group,
    hz: &[f64],
    flat: &[c64],
    inputs: &[String],
    outputs: &[String],
) -> Result<(), IoError> {
    write_f64(group, "frequency_hz", hz, &[hz.len()])?;
    write_c64(group, "H", flat, &[hz.len(), outputs.len(), inputs.len()])?;
    let refs: Vec<&str> = inputs.iter().map(String::as_str).collect();
    write_strings(group, "inputs", &refs)?;
    let refs: Vec<&str> = outputs.iter().map(String::as_str).collect();
    write_strings(group, "outputs", &refs)?;
    Ok(())
}

/// A TABLED1 or TABLEF (CSV, path relative to the file holding the card) by id.
pub fn dynamic_table(model: &Model, tid: u32) -> Result<Table, String> {
    let b = &model.bulk;
    match (
        b.tabled1.iter().find(|x| x.id == tid),
        b.tablef.iter().find(|x| x.id == tid),
    ) {
        (Some(x), _) => Table::new(&x.points).map_err(|e| format!("{}: TABLED1 {tid}: {e}", x.loc)),
        (None, Some(x)) => {
            let csv = x.loc.file.parent().map_or_else(
                || std::path::PathBuf::from(&x.path),
                |dir| dir.join(&x.path),
            );
            let points = read_columns(&csv, &x.tcol, &x.ycol)
                .map_err(|e| format!("{}: TABLEF {tid}: {e}", x.loc))?;
            Table::new(&points)
                .map_err(|e| format!("{}: TABLEF {tid} ({}): {e}", x.loc, csv.display()))
        }
        (None, None) => Err(format!("table {tid} is no TABLED1 or TABLEF")),
    }
}

/// One RLOAD1 term on one input: scale · (C(f) + iD(f)) · e^{i(θ − 2πfτ)}.
struct LoadTerm {
    input: usize,
    scale: f64,
    c: Option<Table>,
    d: Option<Table>,
    phase: f64,
    delay: f64,
}

impl LoadTerm {
    fn at(&self, hz: f64) -> c64 {
        let c = self.c.as_ref().map_or(0.0, |t| t.value(hz));
        let d = self.d.as_ref().map_or(0.0, |t| t.value(hz));
        let angle = self.phase - 2.0 * std::f64::consts::PI * hz * self.delay;
        c64::new(c, d) * c64::new(angle.cos(), angle.sin()) * self.scale
    }
}

/// The subcase's inputs: names, f-set unit-load columns (n_f × k) and the RLOAD1 terms.
struct Inputs {
    names: Vec<String>,
    columns: Mat<f64>,
    terms: Vec<LoadTerm>,
}

fn inputs(
    model: &Model,
    st: &Structure,
    c: &Constrained,
    sub: &Subcase,
) -> Result<Inputs, RunError> {
    let id = sub.id;
    let case = |what: String| RunError::Case { subcase: id, what };
    let b = &model.bulk;
    let sid = sub.dload.ok_or_else(|| case("SOL FRF on the full model needs DLOAD = <RLOAD1 or DLOAD sid> (its DAREA DOFs are the inputs)".into()))?;
    let sets: Vec<(f64, u32)> = match b.dload.iter().find(|d| d.sid == sid) {
        Some(d) => d.terms.iter().map(|&(s, l)| (d.scale * s, l)).collect(),
        None => vec![(1.0, sid)],
    };
    let mut dofs: Vec<(u32, usize)> = Vec::new();
    let mut terms = Vec::new();
    for (scale, set) in sets {
        let rloads: Vec<_> = b.rload1.iter().filter(|r| r.sid == set).collect();
        if rloads.is_empty() {
            return Err(case(format!("DLOAD {sid}: load set {set} has no RLOAD1")));
        }
        for r in rloads {
            let table = |tid: u32| {
                if tid == 0 {
                    Ok(None)
                } else {
                    dynamic_table(model, tid)
                        .map(Some)
                        .map_err(|e| case(format!("RLOAD1 {}: {e}", r.sid)))
                }
            };
            let (tc, td) = (table(r.tc)?, table(r.td)?);
            let mut any = false;
            for d in b.darea.iter().filter(|d| d.sid == r.excite_id) {
                for comp in d.components.components() {
                    let input = match dofs.iter().position(|&x| x == (d.grid, comp)) {
                        Some(i) => i,
                        None => {
                            dofs.push((d.grid, comp));
                            dofs.len() - 1
                        }
                    };
                    terms.push(LoadTerm {
                        input,
                        scale: scale * d.scale,
                        c: tc.clone(),
                        d: td.clone(),
                        phase: r.phase_deg.to_radians(),
                        delay: r.delay,
                    });
                    any = true;
                }
            }
            if !any {
                return Err(case(format!(
                    "RLOAD1 {}: EXCITEID {} selects no DAREA",
                    r.sid, r.excite_id
                )));
            }
        }
    }
    let n_f = c.sets.f.len();
    let mut columns = Mat::<f64>::zeros(n_f, dofs.len());
    for (j, &(grid, comp)) in dofs.iter().enumerate() {
        let index = *model
            .grid_index
            .get(&grid)
            .ok_or_else(|| case(format!("DAREA: GRID {grid} does not exist")))?;
        let g = DofMap::dof(index, comp - 1);
        let row = st.rigid.t.row(g);
        let mut any = false;
        for (&n, &t) in row.col_indices().iter().zip(row.values()) {
            if let Some(f) = c.sets.f_in_n.position(n) {
                columns[(f, j)] += t;
                any |= t != 0.0;
            }
        }
        if !any {
            return Err(case(format!(
                "DAREA: GRID {grid} component {comp} is constrained (SPC, AUTOSPC): a load there moves nothing"
            )));
        }
    }
    Ok(Inputs {
        names: dofs.iter().map(|(g, c)| format!("{g}:{c}")).collect(),
        columns,
        terms,
    })
}

/// Runs every subcase of a full-model SOL FRF.
pub fn run(
    ctx: &RunContext,
    st: &Structure,
    clock: &mut Clock,
) -> Result<Vec<SubcaseSummary>, RunError> {
    let model = ctx.model;
    let sol = ctx.deck.executive.sol.as_ref().map(|(s, _)| *s);
    let mut out = Vec::new();
    for sub in &model.subcases {
        let id = sub.id;
        let method = match sol {
            Some(Solution::FrfDirect) => FrfMethod::Direct,
            Some(Solution::FrfModal) => FrfMethod::Modal,
            _ if sub.method.is_some() => FrfMethod::Modal,
            _ => FrfMethod::Direct,
        };
        let c = clock.time(format!("subcase {id}: constraints"), || {
            Constrained::build(model, st, sub.spc)
        })?;
        let hz = frequency_lines(model, sub)?;
        let omegas: Vec<f64> = hz.iter().map(|f| 2.0 * std::f64::consts::PI * f).collect();
        let inputs = inputs(model, st, &c, sub)?;
        let sensors = clock.time(format!("subcase {id}: sensor rows"), || {
            sensor_operator(ctx, st, &c, sub)
        })?;
        // output rows: the input DOFs (their load columns read the displacement there), the
        // sensors, then 6 per grid of a DISPLACEMENT request
        let grid_rows = GridRows::of_subcase(ctx.deck, &st.map, sub, "DISPLACEMENT", None);
        let grids = grid_rows
            .as_ref()
            .map_or_else(Vec::new, |rows| rows.indices(&st.map));
        let grid_outputs = displacement_rows(st, &c, &grids);
        let k = inputs.names.len();
        let n_f = c.sets.f.len();
        let named = k + sensors.len();
        let mut coo = CooMatrix::new(named + grid_outputs.nrows(), n_f);
        for j in 0..k {
            for f in 0..n_f {
                if inputs.columns[(f, j)] != 0.0 {
                    coo.push(j, f, inputs.columns[(f, j)]);
                }
            }
        }
        for (offset, rows) in [(k, &sensors.rows), (named, &grid_outputs)] {
            for (col, column) in rows.col_iter().enumerate() {
                for (&row, &v) in column.row_indices().iter().zip(column.values()) {
                    coo.push(offset + row, col, v);
                }
            }
        }
        let outputs = CscMatrix::from(&coo);
        let (alpha, beta) = (model.params.alpha1, model.params.beta1);
        let frf_error = |e: crate::dynamics::frf::FrfError| RunError::Case {
            subcase: id,
            what: e.to_string(),
        };
        let mut modes = 0;
        // residual vectors added to the modes (None: not asked, direct, or K singular)
        let (mut residual, mut resvec_skipped): (Option<usize>, bool) = (None, false);
        let h = match method {
            FrfMethod::Direct => clock
                .time(
                    format!("subcase {id}: direct FRF ({} lines)", hz.len()),
                    || {
                        direct_receptance(
                            &SparseModel {
                                stiffness: &c.k_ff,
                                mass: &c.m_ff,
                                alpha,
                                beta,
                                structural: model.params.g,
                            },
                            inputs.columns.as_ref(),
                            &outputs,
                            &omegas,
                            ctx.options.parallel,
                        )
                    },
                )
                .map_err(frf_error)?,
            FrfMethod::Modal => {
                let sid = sub.method.ok_or_else(|| RunError::Case {
                    subcase: id,
                    what: "SOL 111 needs METHOD = <EIGRL sid> in case control".into(),
                })?;
                let eigrl = model
                    .bulk
                    .eigrl
                    .iter()
                    .find(|e| e.sid == sid)
                    .ok_or_else(|| RunError::Case {
                        subcase: id,
                        what: format!("METHOD = {sid} selects no EIGRL card"),
                    })?;
                let symbolic =
                    SymbolicFactor::analyze(c.k_ff.pattern()).map_err(|e| RunError::Linalg {
                        subcase: id,
                        source: e,
                    })?;
                if omegas.contains(&0.0) {
                    static_stiffness_is_regular(&c.k_ff, &symbolic).map_err(frf_error)?;
                }
                let request = EigenRequest {
                    v1_hz: eigrl.v1,
                    v2_hz: eigrl.v2,
                    nd: eigrl.nd.map(|n| n as usize),
                    shift_hz: eigrl.shfscl,
                };
                let problem = EigenProblem {
                    k: &c.k_ff,
                    m: &c.m_ff,
                    symbolic: &symbolic,
                };
                let r = clock
                    .time(format!("subcase {id}: Lanczos"), || {
                        solve_modes(
                            &problem,
                            &request,
                            &LanczosOptions::default(),
                            ctx.options.par(),
                            ctx.progress,
                        )
                    })
                    .map_err(|e| c.mechanism(st, id, e))?;
                modes = r.eigenvalues.len();
                let extra = if model.params.resvec {
                    let extra = clock
                        .time(format!("subcase {id}: residual vectors"), || {
                            residual_vectors(
                                &c.k_ff,
                                &c.m_ff,
                                &symbolic,
                                r.vectors.as_ref(),
                                inputs.columns.as_ref(),
                            )
                        })
                        .map_err(frf_error)?;
                    resvec_skipped = extra.is_none();
                    extra
                } else {
                    None
                };
                residual = extra.as_ref().map(|e| e.eigenvalues.len());
                // the modes, then the residual vectors (the modes alone when there are none)
                let (eigenvalues, phi) = match extra {
                    Some(extra) => {
                        let psi = &extra.shapes;
                        let phi = Mat::<f64>::from_fn(n_f, modes + psi.ncols(), |i, j| {
                            if j < modes {
                                r.vectors[(i, j)]
                            } else {
                                psi[(i, j - modes)]
                            }
                        });
                        (
                            r.eigenvalues.into_iter().chain(extra.eigenvalues).collect(),
                            phi,
                        )
                    }
                    None => (r.eigenvalues, r.vectors),
                };
                let basis = eigenvalues.len();
                clock
                    .time(format!("subcase {id}: modal FRF ({modes} modes, {} residual vectors, {} lines)", basis - modes, hz.len()), || {
                        let phi = &phi;
                        let modal_in = phi.transpose() * &inputs.columns;
                        let mut modal_out = Mat::<f64>::zeros(outputs.nrows(), basis);
                        for (col, column) in outputs.col_iter().enumerate() {
                            for (&row, &v) in column.row_indices().iter().zip(column.values()) {
                                for j in 0..basis {
                                    modal_out[(row, j)] += v * phi[(col, j)];
                                }
                            }
                        }
                        modal_receptance(&eigenvalues, alpha, beta, model.params.g, modal_in.as_ref(), modal_out.as_ref(), &omegas)
                    })
                    .map_err(frf_error)?
            }
        };
        // the grids' response to the deck's load, then H without their rows
        let n_disp = grid_outputs.nrows();
        let mut displacement = vec![c64::new(0.0, 0.0); hz.len() * n_disp];
        for (l, (f, hw)) in hz.iter().zip(&h).enumerate() {
            for term in &inputs.terms {
                let p = term.at(*f);
                for o in 0..n_disp {
                    displacement[l * n_disp + o] += hw[(named + o, term.input)] * p;
                }
            }
        }
        let h: Vec<Mat<c64>> = if n_disp == 0 {
            h
        } else {
            h.iter().map(|hw| hw.subrows(0, named).to_owned()).collect()
        };
        let names: Vec<String> = inputs.names.iter().chain(&sensors.names).cloned().collect();
        let reads: Vec<Reads> = (0..k)
            .map(|_| Reads::Displacement)
            .chain(sensors.reads.iter().copied())
            .collect();
        let (flat, peak) = scaled_flat(&h, &hz, &reads);
        clock.time(
            format!("subcase {id}: output"),
            || -> Result<(), RunError> {
                let group = ctx.output.group(&format!("results/{id}/frf"))?;
                write_frf(&group, &hz, &flat, &inputs.names, &names)?;
                let n_out = names.len();
                let mut response = vec![c64::new(0.0, 0.0); hz.len() * n_out];
                for (l, f) in hz.iter().enumerate() {
                    for term in &inputs.terms {
                        let p = term.at(*f);
                        for o in 0..n_out {
                            response[l * n_out + o] += flat[(l * n_out + o) * k + term.input] * p;
                        }
                    }
                }
                write_c64(&group, "response", &response, &[hz.len(), n_out])?;
                if let Some(rows) = &grid_rows {
                    write_c64(
                        &group,
                        "displacement",
                        &displacement,
                        &[hz.len(), grids.len(), 6],
                    )?;
                    rows.write_ids(&group, "displacement", &st.map)?;
                }
                set_attr_str(&group, "method", method.name())?;
                set_attr_i64(&group, "modes", modes as i64)?;
                set_attr_i64(&group, "residual_vectors", residual.unwrap_or(0) as i64)?;
                super::write_autospc(&group, &c.autospc)?;
                Ok(())
            },
        )?;
        let summary = FrfSummary {
            method,
            lines: hz.len(),
            inputs: inputs.names,
            outputs: names,
            modes,
            residual_vectors: residual,
            resvec_skipped,
            f_size: n_f,
            peak,
        };
        out.push(SubcaseSummary {
            id,
            autospc: c.autospc.names.clone(),
            result: SubcaseResult::Frf(summary),
        });
    }
    Ok(out)
}
