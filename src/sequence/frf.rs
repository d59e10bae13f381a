//! `SOL FRF` on the full model: SOL 108 (direct) and SOL 111 (modal); `SOL FRF` is modal when
//! the subcase selects `METHOD`, direct otherwise.
//!
//! Per subcase:
//! - frequencies: `FREQUENCY = sid` (FREQ, FREQ1–FREQ5 of that SID, combined, sorted,
//!   duplicates removed) — [`frequency_lines`], shared with the pROM FRF. FREQ3–FREQ5 place
//!   lines from the natural frequencies of the modal solution, computed before the lines
//!   ([`frf::modal_basis`]); the direct solution ignores them with a warning, as Nastran;
//! - inputs: `DLOAD = sid` (a DLOAD combination S·Σ Sᵢ·Lᵢ or one RLOAD1 set): every DAREA
//!   entry of its RLOAD1s' EXCITEIDs is an input DOF `GRID:component` (components in the
//!   grid's CD frame, as for Nastran's DAREA), loaded by a unit force through Tᵀ (a dependent
//!   RBE DOF spreads to its independent DOFs). A constrained input DOF is an error;
//! - outputs: the input DOFs (receptance, like the pROM FRF) and the SENSORs the subcase selects
//!   ([`crate::discretize::sensors`]: DISP and STRAIN per unit force, VEL × iω, ACCEL × −ω², the
//!   measurement equations' (iω)^k of [`crate::dynamics::measurement`]);
//! - damping: Rayleigh C = αM + βK from `PARAM,ALPHA1` / `PARAM,BETA1` (as the pROM build) and
//!   structural damping `PARAM,G` as Nastran: K(1 + iG) in the direct solution, G on each modal
//!   stiffness ω_j²(1 + iG) in the modal one;
//! - direct: one sparse complex LU symbolic analysis of K_ff − ω²M_ff + iωC_ff, one numeric LU
//!   (plus one refinement step) per line, lines in parallel ([`direct_receptance`]);
//! - modal: the modes of `METHOD = sid` (EIGRL, shift-invert Lanczos as SOL 103, mass
//!   normalized) and, unless `PARAM,RESVEC,NO`, the residual vectors of the inputs' load shapes
//!   ([`residual_vectors`], Nastran's RESVEC default in modal frequency response), superposed
//!   with modal damping 2ζ_jω_j = α + βω_j² ([`modal_receptance`]) plus the TABDMP1 of
//!   `SDAMPING` (viscous, or structural with `PARAM,KDAMP,-1`). The residual vectors carry
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

use super::driver::{Basis, Driver, ElementDampingUse};
use super::random::{GridResponse, QUANTITIES, RandomSummary};
use super::report::{Report, sci};
use super::shared::{frequency_lines, structure, write_frf};
use super::{Clock, GridRows, RunContext, RunError, SubcaseSummary};
use crate::analysis::frf::{self, Damping, FrfRun, FullFrf, ModalBasis, first_rows, output_rows};
use crate::deck::Solution;
use crate::deck::cards::ExcitationKind;
use crate::discretize::enforced::EnforcedColumns;
use crate::discretize::loads::{FrequencyInputs, frequency_inputs};
use crate::discretize::sensors::{SensorOperator, displacement_rows, displacement_rows_s};
use crate::discretize::{Constrained, Structure};
use crate::dynamics::frf::{ModalDampingTable, scaled_flat};
use crate::dynamics::measurement::Reads;
use crate::io::{set_attr_i64, set_attr_str, write_c64};
use crate::linalg::EigenRequest;
use crate::linalg::{Mat, c64};
use nalgebra_sparse::CscMatrix;

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
    /// FREQ3–FREQ5 cards the direct solution left out (`CARD at file:line`).
    pub ignored: Vec<String>,
    /// The random analyses (RANDOM) whose first subcase this is.
    pub random: Vec<RandomSummary>,
}

/// The FRF driver on the mesh.
pub struct Frf;

/// The output requests FRF (108, 111) writes: complex displacement responses on request.
pub const HONOURED: &[&str] = &["DISPLACEMENT", "VELOCITY", "ACCELERATION"];

impl Driver for Frf {
    fn name(&self) -> &'static str {
        "FRF"
    }

    fn solutions(&self) -> &'static [Solution] {
        &[Solution::FrfDirect, Solution::FrfModal, Solution::Frf]
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

    fn run(&self, ctx: &RunContext, clock: &mut Clock) -> Result<Vec<SubcaseSummary>, RunError> {
        let st = structure(ctx, clock)?;
        run(ctx, &st, clock)
    }
}

/// Runs every subcase of a full-model SOL FRF.
fn run(
    ctx: &RunContext,
    st: &Structure,
    clock: &mut Clock,
) -> Result<Vec<SubcaseSummary>, RunError> {
    let model = ctx.model;
    let sol = ctx.deck.executive.sol.as_ref().map(|(s, _)| *s);
    let (mut done, mut responses) = (Vec::new(), Vec::new());
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
        let sid = sub.dload.ok_or_else(|| RunError::Case { subcase: id, what: "SOL FRF on the full model needs DLOAD = <RLOAD1 or DLOAD sid> (its DAREA DOFs are the inputs)".into() })?;
        let inputs = frequency_inputs(model, st, &c, sid, sub.loadset)
            .map_err(|what| RunError::Case { subcase: id, what })?;
        let sensors = clock.time(format!("subcase {id}: sensor rows"), || {
            super::subcase_sensors(ctx, st, &c, sub)
        })?;
        // output rows: the input DOFs (their load columns read the displacement there), the
        // sensors, then 6 per grid of a DISPLACEMENT, VELOCITY or ACCELERATION request (the
        // union of their grids)
        let requests: Vec<Option<GridRows>> = QUANTITIES
            .iter()
            .map(|(name, _)| GridRows::of_subcase(ctx.deck, &st.map, sub, name, None))
            .collect();
        let mut grids: Vec<usize> = requests
            .iter()
            .flatten()
            .flat_map(|r| r.indices(&st.map))
            .collect();
        grids.sort_unstable();
        grids.dedup();
        let grid_outputs = displacement_rows(st, &c, &grids);
        let k = inputs.names.len();
        let n_f = c.sets.f.len();
        let named = k + sensors.len();
        let outputs = output_rows(inputs.columns.as_ref(), &[&sensors.rows, &grid_outputs]);
        let enforced = enforced_motion(ctx, st, &c, &inputs, &sensors, &grids)
            .map_err(|what| RunError::Case { subcase: id, what })?;
        let applied = k - inputs.enforced.len();
        let solve_inputs = match &enforced {
            Some((e, _)) => e.solve_columns(&inputs.columns, applied),
            None => inputs.columns.clone(),
        };
        let eigen_request = match method {
            FrfMethod::Direct => None,
            FrfMethod::Modal => {
                let sid = sub.method.ok_or_else(|| RunError::Case {
                    subcase: id,
                    what: "SOL 111 needs METHOD = <EIGRL or EIGR sid> in case control".into(),
                })?;
                let eigrl = model.eigrl(sid).ok_or_else(|| RunError::Case {
                    subcase: id,
                    what: format!("METHOD = {sid} selects no EIGRL or EIGR card"),
                })?;
                Some(EigenRequest {
                    v1_hz: eigrl.v1,
                    v2_hz: eigrl.v2,
                    nd: eigrl.nd.map(|n| n as usize),
                    shift_hz: eigrl.shfscl,
                })
            }
        };
        let mut run = FrfRun {
            inputs: solve_inputs.as_ref(),
            outputs: &outputs,
            omegas: &[],
            damping: Damping {
                alpha: model.params.alpha1,
                beta: model.params.beta1,
                structural: model.params.g,
                modal_table: match (method, sub.sdamping) {
                    (FrfMethod::Modal, Some(tid)) => {
                        let t = model.tabdmp1(tid).ok_or_else(|| RunError::Case {
                            subcase: id,
                            what: format!("SDAMPING = {tid} selects no TABDMP1 card"),
                        })?;
                        Some(ModalDampingTable::new(
                            &t.points,
                            t.units,
                            model.params.kdamp == -1,
                        ))
                    }
                    _ => None,
                },
            },
            par: ctx.options.par(),
            progress: ctx.progress,
        };
        let mut record = |name, d| clock.record(format!("subcase {id}: {name}"), d);
        let basis = eigen_request
            .map(|request| frf::modal_basis(&c, &request, model.params.resvec, &run, &mut record))
            .transpose()
            .map_err(|e| super::analysis_error(&c, st, id, e))?;
        let modes_hz = basis.as_ref().map(ModalBasis::natural_frequencies_hz);
        let (hz, ignored) = frequency_lines(model, sub, modes_hz.as_deref())?;
        let ignored: Vec<String> = ignored
            .iter()
            .map(|f| format!("{} at {}", f.card_name(), f.loc))
            .collect();
        check_enforced_lines(&inputs, &hz).map_err(|what| RunError::Case { subcase: id, what })?;
        let omegas: Vec<f64> = hz.iter().map(|f| 2.0 * std::f64::consts::PI * f).collect();
        run.omegas = &omegas;
        let FullFrf {
            h,
            modes,
            residual_vectors: residual,
            resvec_skipped,
        } = frf::basis_receptance(&c, basis.as_ref(), &run, &mut record)
            .map_err(|e| super::analysis_error(&c, st, id, e))?;
        let h = match &enforced {
            Some((e, outputs_s)) => e.compose(&h, applied, &omegas, &outputs, outputs_s),
            None => h,
        };
        // the grids' response to the deck's load, then H without their rows
        let n_disp = grid_outputs.nrows();
        let displacement = inputs.response(&hz, n_disp, |l, o, i| h[l][(named + o, i)]);
        let h = first_rows(h, named);
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
                let response = inputs.response(&hz, n_out, |l, o, i| flat[(l * n_out + o) * k + i]);
                write_c64(&group, "response", &response, &[hz.len(), n_out])?;
                for ((name, power), rows) in QUANTITIES.iter().zip(&requests) {
                    let Some(rows) = rows else { continue };
                    let at = positions(&grids, &rows.indices(&st.map));
                    let values = grid_quantity(&displacement, &omegas, grids.len(), &at, *power);
                    let name = name.to_lowercase();
                    write_c64(&group, &name, &values, &[hz.len(), at.len(), 6])?;
                    rows.write_ids(&group, &name, &st.map)?;
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
            ignored,
            random: Vec::new(),
        };
        responses.push(GridResponse {
            subcase: id,
            random: sub.random,
            requests: std::array::from_fn(|q| {
                requests[q]
                    .as_ref()
                    .map(|rows| positions(&grids, &rows.indices(&st.map)))
            }),
            grid_ids: grids.iter().filter_map(|&g| st.map.grid_id(g)).collect(),
            hz,
            displacement,
        });
        done.push((id, c.autospc.names.clone(), summary));
    }
    let mut analyses = clock.time("random response".to_string(), || {
        super::random::run(ctx, &responses)
    })?;
    // each random analysis is reported with the first subcase it combines
    let mut out = Vec::new();
    for (id, autospc, mut summary) in done {
        let (mine, rest) = analyses.into_iter().partition(|a| a.subcases[0] == id);
        (summary.random, analyses) = (mine, rest);
        out.push(SubcaseSummary {
            id,
            autospc,
            result: Box::new(summary),
        });
    }
    Ok(out)
}

/// The positions of the grid indices `wanted` in the sorted list `grids` (which holds them).
fn positions(grids: &[usize], wanted: &[usize]) -> Vec<usize> {
    wanted
        .iter()
        .map(|g| {
            grids
                .binary_search(g)
                .expect("a requested grid is in the union")
        })
        .collect()
}

/// (iω)^power × the displacement response (lines × grids × 6) of the grids at `at`.
fn grid_quantity(
    displacement: &[c64],
    omegas: &[f64],
    grids: usize,
    at: &[usize],
    power: i32,
) -> Vec<c64> {
    let mut out = Vec::with_capacity(omegas.len() * at.len() * 6);
    for (l, &w) in omegas.iter().enumerate() {
        let factor = c64::new(0.0, w).powi(power);
        for &g in at {
            let row = &displacement[(l * grids + g) * 6..(l * grids + g + 1) * 6];
            out.extend(row.iter().map(|&z| z * factor));
        }
    }
    out
}

impl Report for FrfSummary {
    fn render(&self, subcase: u32) -> Vec<String> {
        let r = self;
        let modes = match (r.modes, r.residual_vectors) {
            (0, _) => String::new(),
            (m, Some(k)) => format!(", {m} modes + {k} residual vector(s)"),
            (m, None) => format!(", {m} modes"),
        };
        vec![
            format!(
                "subcase {}: {} FRF, f-set {} DOFs{modes}, {} line(s), {} input(s) ({}) × {} output(s)",
                subcase,
                r.method.name(),
                r.f_size,
                r.lines,
                r.inputs.len(),
                r.inputs.join(", "),
                r.outputs.len()
            ),
            format!(
                "  largest |H| {} at {} Hz",
                sci(r.peak.0, 4),
                sci(r.peak.1, 4)
            ),
        ]
        .into_iter()
        .chain(r.random.iter().flat_map(RandomSummary::lines))
        .collect()
    }

    fn warnings(&self, subcase: u32) -> Vec<String> {
        let f = self;
        let mut warnings = Vec::new();
        for r in f.random.iter().filter(|r| !r.ignored.is_empty()) {
            warnings.push(format!(
                "random {}: RANDPS at {} left out: it names a subcase this deck does not run",
                r.sid,
                r.ignored.join(", ")
            ));
        }
        for r in f.random.iter().filter(|r| !r.ignored.is_empty()) {
            warnings.push(format!(
                "random {}: RANDPS at {} left out: it names a subcase this deck does not run",
                r.sid,
                r.ignored.join(", ")
            ));
        }
        for r in f.random.iter().filter(|r| r.outputs.is_empty()) {
            warnings.push(format!("random {}: its subcases ask no DISPLACEMENT, VELOCITY or ACCELERATION, the quantities paraflex gives spectral densities of, so /random/{} holds only the frequency lines", r.sid, r.sid));
        }
        if !f.ignored.is_empty() {
            warnings.push(format!("subcase {}: {} ignored: FREQ3/FREQ4/FREQ5 place lines from natural frequencies, which the direct frequency response does not compute (Nastran ignores them in SOL 108 too)", subcase, f.ignored.join(", ")));
        }
        if f.resvec_skipped {
            warnings.push(format!("subcase {}: no residual vectors (PARAM,RESVEC): K is singular (a free-free model or a mechanism), so the {} modes alone are superposed; the modes left out are missing, so EIGRL should reach well above the band", subcase, f.modes));
        }
        warnings
    }
}

/// Refuses a 0 Hz line when an enforced motion is a velocity or an acceleration (it has no
/// displacement there).
fn check_enforced_lines(inputs: &FrequencyInputs, hz: &[f64]) -> Result<(), String> {
    if inputs.enforced.is_empty() {
        return Ok(());
    }
    let integrated = inputs.terms.iter().find(|t| {
        matches!(
            t.kind,
            ExcitationKind::Velocity | ExcitationKind::Acceleration
        )
    });
    if let (Some(t), true) = (integrated, hz.contains(&0.0)) {
        return Err(format!(
            "an enforced {} (TYPE = {}) has no displacement at 0 Hz: start the FREQ lines above 0",
            if t.kind == ExcitationKind::Velocity {
                "velocity"
            } else {
                "acceleration"
            },
            t.kind.name()
        ));
    }
    Ok(())
}

/// The enforced-motion columns of a subcase whose RLOADs move SPCD DOFs, with the output rows
/// on the s-set (input rows: each enforced DOF reads itself; sensors; grid displacements);
/// `None` without enforced motion.
fn enforced_motion(
    ctx: &RunContext,
    st: &Structure,
    c: &Constrained,
    inputs: &FrequencyInputs,
    sensors: &SensorOperator,
    grids: &[usize],
) -> Result<Option<(EnforcedColumns, CscMatrix<f64>)>, String> {
    if inputs.enforced.is_empty() {
        return Ok(None);
    }
    let model = ctx.model;
    let columns = EnforcedColumns::new(
        st,
        c,
        &inputs.enforced,
        model.params.alpha1,
        model.params.maxratio,
    )?;
    let k = inputs.names.len();
    let first = k - inputs.enforced.len();
    let mut reads_self = Mat::<f64>::zeros(c.sets.s.len(), k);
    for (j, &s) in columns.s_positions.iter().enumerate() {
        reads_self[(s, first + j)] = 1.0;
    }
    let outputs_s = output_rows(
        reads_self.as_ref(),
        &[&sensors.rows_s, &displacement_rows_s(st, c, grids)],
    );
    Ok(Some((columns, outputs_s)))
}
