//! Solution sequences (DESIGN.md §1–§2): the only place that turns case control into calls.
//!
//! One driver per sequence, selected by [`Sequence`] from the deck's `SOL` statement, each
//! taking a [`RunContext`] (deck, model, output file, progress sink, options):
//!
//! | `SOL` | driver | per subcase |
//! |---|---|---|
//! | `101`, `STATICS` | [`statics::run`] | `SPC`, `LOAD` → u, SPC forces, centroid strains |
//! | `103`, `MODAL` | [`modal::run`] | `SPC`, `METHOD` (EIGRL) → frequencies, generalized masses, residuals, shapes |
//! | `108`, `111`, `FRF` | [`frf::run`] | `SPC`, `FREQUENCY`, `DLOAD` (RLOAD1/DAREA inputs), `METHOD` (111) → complex FRFs at inputs and SENSORs |
//! | `109`, `112`, `TRANSIENT` | [`transient::run`] (full model), [`rom_transient::run`] (`ROM =`) | `TSTEP` (+`TINTEG`), `DLOAD`, `IC` → sensor histories |
//! | any with `ROM =` | [`rom_modal`], [`rom_frf`], [`rom_transient`] | the pROM artifact at `PVAL` |
//!
//! Both drivers share the structure setup of [`Structure::build`]: element matrices
//! ([`elements`]), one grid-block pattern for K and M, rigid elimination g → n with one plan,
//! and per SPC set the f-set with AUTOSPC. Everything the user must see (AUTOSPC lists, Sturm
//! check, timings) is returned in a [`RunSummary`]; the library never prints, long steps report
//! through [`Progress`].
//!
//! Output (HDF5, DESIGN.md §8; full layout in the README "Output file" section):
//!
//! ```text
//! /results/<subcase>/modal/{frequency_hz (m), generalized_mass (m), residual (m), eigenvalue (m),
//!                           shapes (m×k×6, only with DISPLACEMENT)}
//!     attrs: sturm_shift, sturm_count, sturm_found, sturm_consistent, shift, norm, autospc,
//!            massless_count, finite_exhausted
//! /results/<subcase>/statics/{displacement (k×6; all grids without a DISPLACEMENT request,
//!                             none with DISPLACEMENT = NONE), spc_force (k×6, only with
//!                             SPCFORCES), strain/<CARD>/... (only with STRAIN)}
//! ```
//!
//! Grid-point outputs keep the rows their request selects ([`GridRows`]): k = n for `ALL`
//! (rows in `/model/grid_ids` order), the SET's grids otherwise, listed in `<name>_grid_ids`.
//!
//! Vectors are written in the basic system (rotated back from the grids' CD frames).

pub mod elements;
pub mod estimate;
pub mod frf;
pub mod modal;
pub mod parameters;
pub mod prom;
pub mod rom_case;
pub mod rom_frf;
pub mod rom_modal;
pub mod rom_transient;
pub mod sensors;
pub mod statics;
pub mod transient;

use std::sync::Arc;
use std::time::{Duration, Instant};

use faer::Par;
use nalgebra_sparse::CscMatrix;

use crate::assembly::error::DofName;
use crate::assembly::reduce::{GToN, Partition};
use crate::assembly::spc::{AutoSpcReport, SpcSet, autospc};
use crate::assembly::{AffineOperator, AssemblyError, DofMap, GridFrames, RigidElimination, Sets};
use crate::deck::case_control::{OutputRequest, Subcase, Target};
use crate::deck::{Deck, Solution};
use crate::io::{IoError, OutputFile};
use crate::linalg::{LinalgError, Progress, SturmCheck};
use crate::model::Model;

/// The solution sequences paraflex can run.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Sequence {
    /// SOL 101: linear statics.
    Statics,
    /// SOL 103: normal modes.
    Modal,
    /// SOL PROM: parametric reduced-order model.
    Prom,
    /// SOL FRF (108/111): frequency response, full model (direct or modal) or pROM artifact.
    Frf,
    /// SOL TRANSIENT (109/112): time response, on pROM artifacts ([`rom_transient`]) and on the
    /// full model by direct integration ([`transient`]; SOL 112 too: no modal superposition).
    Transient,
    /// SOL ESTIMATE: states, inputs and parameters from measurements (augmented EKF) on a pROM.
    Estimate,
}

impl Sequence {
    /// The driver for a `SOL`, or `None` when that solution is not available yet.
    pub fn of_solution(sol: Solution) -> Option<Self> {
        match sol {
            Solution::Statics => Some(Sequence::Statics),
            Solution::Modal => Some(Sequence::Modal),
            Solution::Prom => Some(Sequence::Prom),
            Solution::Frf | Solution::FrfDirect | Solution::FrfModal => Some(Sequence::Frf),
            Solution::Transient | Solution::TransientDirect | Solution::TransientModal => {
                Some(Sequence::Transient)
            }
            Solution::Estimate => Some(Sequence::Estimate),
            _ => None,
        }
    }

    /// Name as in DESIGN.md (`STATICS`, `MODAL`).
    pub fn name(self) -> &'static str {
        match self {
            Sequence::Statics => "STATICS",
            Sequence::Modal => "MODAL",
            Sequence::Prom => "PROM",
            Sequence::Frf => "FRF",
            Sequence::Transient => "TRANSIENT",
            Sequence::Estimate => "ESTIMATE",
        }
    }
}

/// Options of a run that are not in the deck.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RunOptions {
    /// Use rayon / faer parallelism (element matrices, assembly, factorization).
    pub parallel: bool,
}

impl Default for RunOptions {
    fn default() -> Self {
        RunOptions { parallel: true }
    }
}

impl RunOptions {
    fn par(&self) -> Par {
        if self.parallel {
            Par::rayon(0)
        } else {
            Par::Seq
        }
    }
}

/// Everything a driver needs.
pub struct RunContext<'a> {
    pub deck: &'a Deck,
    pub model: &'a Model,
    /// The output file (already holding `/model`); drivers add `/results`.
    pub output: &'a OutputFile,
    pub progress: &'a dyn Progress,
    pub options: RunOptions,
}

/// Result of a run, for the console.
#[derive(Debug, Clone)]
pub struct RunSummary {
    pub sequence: Sequence,
    pub subcases: Vec<SubcaseSummary>,
    /// Wall-clock time of each step, in order.
    pub timings: Vec<(String, Duration)>,
    /// Things the user should know (AUTOSPC lists, inconsistent Sturm checks, …).
    pub warnings: Vec<String>,
}

/// One subcase's outcome.
#[derive(Debug, Clone)]
pub struct SubcaseSummary {
    pub id: u32,
    /// DOFs AUTOSPC constrained (empty when none or AUTOSPC is off).
    pub autospc: Vec<DofName>,
    pub result: SubcaseResult,
}

/// Per-sequence outcome of a subcase.
#[derive(Debug, Clone)]
pub enum SubcaseResult {
    Modal(modal::ModalSummary),
    Statics(statics::StaticsSummary),
    Prom(prom::PromSummary),
    Frf(frf::FrfSummary),
    RomModal(rom_modal::RomModalSummary),
    RomFrf(rom_frf::RomFrfSummary),
    RomTransient(rom_transient::RomTransientSummary),
    Transient(transient::TransientSummary),
    Estimate(estimate::EstimateSummary),
}

/// Errors of a run. Each says where (element, GRID and component, subcase) and what to do.
#[derive(Debug, thiserror::Error)]
pub enum RunError {
    /// The deck's SOL has no driver yet.
    #[error("SOL {0} is not available in this version of paraflex")]
    NotAvailable(String),
    /// The deck has no SOL statement.
    #[error("the deck has no SOL statement; nothing to run")]
    NoSolution,
    /// An element whose property or material combination is not supported, or whose
    /// geometry the element kernel rejects.
    #[error("{card} {id}: {reason}")]
    Element {
        card: &'static str,
        id: u32,
        reason: String,
    },
    /// K_ff is singular: a mechanism or a missing constraint.
    #[error(
        "subcase {subcase}: the stiffness matrix is singular at {dof} ({detail}); the structure is a mechanism or is not constrained there — add an SPC (or GRID PS) for this DOF, or let PARAM,AUTOSPC,YES remove DOFs without stiffness"
    )]
    Mechanism {
        subcase: u32,
        dof: DofName,
        detail: String,
    },
    /// A PMPAR that cannot be applied (e.g. its nominal value cannot be read).
    #[error("PMPAR {name}: {reason}")]
    Parameter { name: String, reason: String },
    /// A subcase lacks a selection the sequence needs.
    #[error("subcase {subcase}: {what}")]
    Case { subcase: u32, what: String },
    #[error(transparent)]
    Assembly(#[from] AssemblyError),
    #[error("subcase {subcase}: {source}")]
    Linalg { subcase: u32, source: LinalgError },
    #[error(transparent)]
    Io(#[from] IoError),
}

/// The sequence that runs `model`'s SOL, or why none can: no SOL, a SOL without a driver, or
/// subcases that mix `ROM =` with full-model subcases (one run is either on pROM artifacts or
/// on the deck's mesh), or an estimation on the full model (this version runs it on pROMs
/// only). The CLI asks before running, to write the model and exit with "not available".
pub fn runnable(deck: &Deck, model: &Model) -> Result<Sequence, RunError> {
    let (sol, text) = deck.executive.sol.as_ref().ok_or(RunError::NoSolution)?;
    let sequence = Sequence::of_solution(*sol)
        .ok_or_else(|| RunError::NotAvailable(format!("{text} ({})", sol.name())))?;
    let on_rom: Vec<u32> = model
        .subcases
        .iter()
        .filter(|s| s.rom.is_some())
        .map(|s| s.id)
        .collect();
    if !on_rom.is_empty() && !rom_case::applies(model) {
        let full: Vec<String> = model
            .subcases
            .iter()
            .filter(|s| s.rom.is_none())
            .map(|s| s.id.to_string())
            .collect();
        return Err(RunError::NotAvailable(format!(
            "{text} ({}) with ROM = in subcase(s) {on_rom:?} but not in subcase(s) {}: a run is either on pROM artifacts (ROM = in every subcase) or on the full model; split the deck",
            sol.name(),
            full.join(", ")
        )));
    }
    if rom_case::applies(model) && matches!(sequence, Sequence::Statics | Sequence::Prom) {
        return Err(RunError::NotAvailable(format!(
            "{text} ({}) on a pROM artifact (ROM =): pROMs run SOL 103, FRF, TRANSIENT and ESTIMATE",
            sol.name()
        )));
    }
    if sequence == Sequence::Estimate && !rom_case::applies(model) {
        return Err(RunError::NotAvailable(format!(
            "{text} ({}) on the full model (this version runs it on pROM artifacts: every subcase needs ROM = 'file.h5')",
            sol.name()
        )));
    }
    Ok(sequence)
}

/// Runs the deck's solution sequence (see the module documentation).
pub fn run(ctx: &RunContext) -> Result<RunSummary, RunError> {
    let sequence = runnable(ctx.deck, ctx.model)?;
    let mut clock = Clock::default();
    let subcases = match (sequence, rom_case::applies(ctx.model)) {
        (Sequence::Modal, true) => rom_modal::run(ctx, &mut clock)?,
        (Sequence::Frf, true) => rom_frf::run(ctx, &mut clock)?,
        (Sequence::Transient, true) => rom_transient::run(ctx, &mut clock)?,
        (Sequence::Estimate, true) => estimate::run(ctx, &mut clock)?,
        (Sequence::Estimate, false) => {
            return Err(RunError::NotAvailable(format!(
                "{} on the full model",
                sequence.name()
            )));
        }
        (
            Sequence::Statics
            | Sequence::Modal
            | Sequence::Prom
            | Sequence::Frf
            | Sequence::Transient,
            _,
        ) => {
            let structure = Structure::build(ctx, &mut clock)?;
            match sequence {
                Sequence::Statics => statics::run(ctx, &structure, &mut clock)?,
                Sequence::Prom => prom::run(ctx, &structure, &mut clock)?,
                Sequence::Frf => frf::run(ctx, &structure, &mut clock)?,
                Sequence::Transient => transient::run(ctx, &structure, &mut clock)?,
                _ => modal::run(ctx, &structure, &mut clock)?,
            }
        }
    };
    let mut warnings = Vec::new();
    if sequence == Sequence::Transient && ctx.model.params.g != 0.0 && ctx.model.params.w3 == 0.0 {
        // Nastran turns G into viscous damping (G/W3)·K in transient response only with
        // PARAM,W3, whose default 0 leaves it out
        warnings.push(format!("PARAM,G = {} is not applied by SOL TRANSIENT without PARAM,W3 (as Nastran): set W3 (rad/s) for (G/W3)·K, or use Rayleigh damping (PARAM,ALPHA1 / BETA1)", ctx.model.params.g));
    }
    for s in &subcases {
        if !s.autospc.is_empty() {
            warnings.push(format!(
                "subcase {}: AUTOSPC constrained {} DOF(s) without stiffness (listed in the summary and in the results group's `autospc` dataset)",
                s.id,
                s.autospc.len()
            ));
        }
        let extrapolated = match &s.result {
            SubcaseResult::RomModal(r) => Some((&r.extrapolated, &r.rom)),
            SubcaseResult::RomFrf(r) => Some((&r.extrapolated, &r.rom)),
            SubcaseResult::RomTransient(r) => Some((&r.extrapolated, &r.rom)),
            SubcaseResult::Estimate(r) => Some((&r.extrapolated, &r.rom)),
            _ => None,
        };
        if let Some((names, rom)) = extrapolated.filter(|(names, _)| !names.is_empty()) {
            warnings.push(format!("subcase {}: parameter(s) {} lie outside the box the pROM {} was built for: extrapolated", s.id, names.join(", "), rom.display()));
        }
        if let SubcaseResult::Frf(f) = &s.result
            && f.resvec_skipped
        {
            warnings.push(format!("subcase {}: no residual vectors (PARAM,RESVEC): K is singular (a free-free model or a mechanism), so the {} modes alone are superposed; the modes left out are missing, so EIGRL should reach well above the band", s.id, f.modes));
        }
        if let SubcaseResult::RomModal(r) = &s.result
            && let Some(nd) = r.nd_short
        {
            warnings.push(format!("subcase {}: EIGRL ND = {nd} asks for more modes than the pROM {} has in the band (size {}): all {} returned", s.id, r.rom.display(), r.n_red, r.frequencies_hz.len()));
        }
        if let SubcaseResult::Estimate(e) = &s.result {
            if e.forced {
                warnings.push(format!(
                    "subcase {}: FORCE = YES: the filter ran although the problem is {}",
                    s.id, e.observability
                ));
            }
            if !e.hidden_modes.is_empty() {
                let modes: Vec<String> = e
                    .hidden_modes
                    .iter()
                    .map(|(k, f)| format!("{k} ({f:.4e} Hz)"))
                    .collect();
                warnings.push(format!("subcase {}: mode(s) {} are not seen by the measured sensors (unobservable at s = λ, but stable: detectable, thesis §7.5.1)", s.id, modes.join(", ")));
            }
        }
        if let SubcaseResult::Prom(p) = &s.result {
            if !p.frozen_condensation.is_empty() {
                warnings.push(format!(
                    "subcase {}: PMPAR {} change(s) by more than a scale the section of CQUAD4s whose incompatible membrane modes are condensed once with the deck's section (PARAM,QINCOMP,YES, the default; README \"Frozen condensation\"): the pROM is exact for that model, but differs from a deck rebuilt at parameter values far from the nominal ones (measured on a [±Θ]2s link: ~5e-4 in frequency 10° from nominal, ~1e-1 on single membrane modes 30° away); PARAM,QINCOMP,NO restores exact agreement at the cost of in-plane bending accuracy (the plain membrane is ≈ 1/(1−ν²) too stiff there)",
                    s.id,
                    p.frozen_condensation.join(", ")
                ));
            }
            if p.inputs == 0 {
                warnings.push(format!(
                    "subcase {}: the pROM has no input DOFs (no ASET1, or PMOR BSET blank): the FRF error of eq. 3.35 cannot choose its size, so all {} basis vectors are kept; give the load and support DOFs as ASET1 to get inputs and a size chosen by ERRTOL",
                    s.id, p.n_red
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
                    s.id,
                    p.n_red,
                    p.inputs * p.inputs
                ));
            }
        }
        if let SubcaseResult::Modal(m) = &s.result {
            let bad: Vec<String> = m
                .residuals
                .iter()
                .enumerate()
                .filter(|(_, r)| !(**r <= RESIDUAL_WARNING))
                .map(|(k, r)| format!("{} ({r:.1e})", k + 1))
                .collect();
            if !bad.is_empty() {
                warnings.push(format!(
                    "subcase {}: mode(s) {} have residual ‖Kφ − λMφ‖/‖Kφ‖ above {RESIDUAL_WARNING:e}: not trustworthy (more modes requested than the mass matrix has finite ones, or masses many orders of magnitude apart, as in the large-mass method, where the frequencies stay accurate but the shapes lose digits)",
                    s.id,
                    bad.join(", ")
                ));
            }
            if m.finite_exhausted {
                let why = if m.massless > 0 {
                    format!(
                        "M is singular on {} massless f-set DOF(s) (no mass on that row)",
                        m.massless
                    )
                } else {
                    "M is rank-deficient on DOFs that have mass (e.g. an offset CONM2 without inertia)".to_string()
                };
                warnings.push(format!(
                    "subcase {}: only {} finite mode(s) exist above the lower bound, ND = {} asked for more: {why}; the other eigenvalues are infinite and are not returned",
                    s.id,
                    m.eigenvalues.len(),
                    m.nd.map_or("(blank)".to_string(), |n| n.to_string()),
                ));
            }
            if !m.sturm.is_consistent() {
                warnings.push(format!(
                    "subcase {}: Sturm check found {} eigenvalue(s) below {:.6e} Hz that Lanczos did not return",
                    s.id,
                    m.sturm.missing(),
                    lambda_to_hz(m.sturm.shift)
                ));
            }
        }
    }
    Ok(RunSummary {
        sequence,
        subcases,
        timings: clock.steps,
        warnings,
    })
}

/// Modes with a larger residual are flagged in the run's warnings.
pub const RESIDUAL_WARNING: f64 = 1e-6;

/// f = √max(λ, 0)/2π.
pub fn lambda_to_hz(lambda: f64) -> f64 {
    lambda.max(0.0).sqrt() / (2.0 * std::f64::consts::PI)
}

/// Step timings.
#[derive(Debug, Default)]
pub struct Clock {
    steps: Vec<(String, Duration)>,
}

impl Clock {
    /// Runs `f` and records its duration under `name`.
    pub fn time<T>(&mut self, name: impl Into<String>, f: impl FnOnce() -> T) -> T {
        let start = Instant::now();
        let out = f();
        self.steps.push((name.into(), start.elapsed()));
        out
    }
}

/// The assembled structure shared by every subcase: K and M on one g pattern, reduced to n.
pub struct Structure {
    pub map: DofMap,
    pub frames: GridFrames,
    pub rigid: RigidElimination,
    /// K_nn and M_nn as affine operators on one shared pattern.
    pub k_nn: AffineOperator,
    pub m_nn: AffineOperator,
    /// M_gg when rigid elements make n ≠ g (GRAV loads need it; see [`Structure::mass_gg`]).
    m_gg: Option<AffineOperator>,
    /// Recovery data of each shell (strains), by index into `model.elements`.
    pub shells: Vec<(usize, elements::ShellRecovery)>,
    /// The PMPARs the affine parts are functions of.
    pub params: parameters::Parameters,
    /// The PMPARs that freeze the condensation of a CQUAD4's incompatible modes at the deck's
    /// section ([`elements::ElementMatrices::frozen_condensation`]).
    pub frozen_condensation: Vec<String>,
}

impl Structure {
    /// Element matrices, assembly on one pattern, rigid elimination.
    pub fn build(ctx: &RunContext, clock: &mut Clock) -> Result<Self, RunError> {
        let model = ctx.model;
        let map = DofMap::of_model(model);
        let frames = GridFrames::of_model(model);
        let params = parameters::Parameters::of_model(model)?;
        let elements = clock.time("element matrices", || {
            elements::element_matrices(model, &frames, &params, ctx.options.parallel, ctx.progress)
        })?;
        let (k_gg, m_gg) = clock.time("assembly", || -> Result<_, RunError> {
            ctx.progress.step("assembly", 0, 2);
            let lists = elements
                .stiffness
                .iter()
                .chain(&elements.mass)
                .map(|c| c.dofs.as_slice());
            let pattern = Arc::new(crate::assembly::pattern::grid_block_pattern(
                map.grids(),
                lists,
            )?);
            let k = AffineOperator::assemble(
                pattern.clone(),
                &elements.stiffness,
                ctx.options.parallel,
            )?;
            ctx.progress.step("assembly", 1, 2);
            let m = AffineOperator::assemble(pattern, &elements.mass, ctx.options.parallel)?;
            ctx.progress.step("assembly", 2, 2);
            Ok((k, m))
        })?;
        // the element matrices are assembled: only the shells' recovery data stay
        let shells = elements.shells;
        let frozen_condensation =
            params.names_on(&elements.frozen_condensation, &elements::SECTION_STIFFNESS);
        let (rigid, k_nn, m_nn, m_gg) =
            clock.time("rigid elimination g → n", || -> Result<_, RunError> {
                let rigid = RigidElimination::of_model(model, &frames, &map)?;
                if rigid.m_mask.iter().any(|&m| m) {
                    let plan = GToN::new(k_gg.pattern().clone(), &rigid.t)?;
                    let (k_nn, m_nn) = (plan.apply(&k_gg)?, plan.apply(&m_gg)?);
                    Ok((rigid, k_nn, m_nn, Some(m_gg)))
                } else {
                    // no dependent DOFs: n = g in the same order and T = I, so K_nn = K_gg (no copy)
                    Ok((rigid, k_gg, m_gg, None))
                }
            })?;
        Ok(Structure {
            map,
            frames,
            rigid,
            k_nn,
            m_nn,
            m_gg,
            shells,
            params,
            frozen_condensation,
        })
    }

    /// M_gg (GRAV loads): M_nn itself when the model has no dependent DOFs (n = g).
    pub fn mass_gg(&self) -> &AffineOperator {
        self.m_gg.as_ref().unwrap_or(&self.m_nn)
    }

    /// Weights of an operator's affine parts at the parameter values the run uses (the
    /// PMPAR nominal values; all weights are 1 for the constant part).
    pub fn weights(&self, op: &AffineOperator) -> Vec<f64> {
        self.params.weights(op, &self.params.nominal())
    }

    /// u_g (global frames) → n × 6 rows in basic.
    pub fn to_basic_rows(&self, u_g: &[f64]) -> Vec<f64> {
        let mut out = vec![0.0; u_g.len()];
        for grid in 0..self.map.grids() {
            let b = 6 * grid;
            let t = self.frames.to_basic(grid, [u_g[b], u_g[b + 1], u_g[b + 2]]);
            let r = self
                .frames
                .to_basic(grid, [u_g[b + 3], u_g[b + 4], u_g[b + 5]]);
            out[b..b + 3].copy_from_slice(&t);
            out[b + 3..b + 6].copy_from_slice(&r);
        }
        out
    }
}

/// The constrained system of one SPC set: sets, AUTOSPC, K_ff / M_ff on one pattern.
pub struct Constrained {
    pub spc: SpcSet,
    pub sets: Sets,
    pub autospc: AutoSpcReport,
    /// K_nn at the nominal parameters (values on `k_nn`'s pattern).
    pub k_nn_values: Vec<f64>,
    pub k_ff: CscMatrix<f64>,
    pub m_ff: CscMatrix<f64>,
    /// K_fs for enforced displacements.
    pub k_fs: AffineOperator,
}

impl Constrained {
    /// The s-set of `SPC = sid` (plus GRID PS and AUTOSPC when enabled) and the f-set matrices.
    pub fn build(model: &Model, st: &Structure, sid: Option<u32>) -> Result<Self, RunError> {
        let mut spc = SpcSet::of_model(model, &st.map, sid)?;
        spc.check_against_rigids(&st.rigid, &st.map)?;
        let mut k_nn_values = vec![0.0; st.k_nn.pattern().nnz()];
        st.k_nn
            .evaluate_into(&st.weights(&st.k_nn), &mut k_nn_values)?;
        let autospc = if model.params.autospc {
            autospc(&st.k_nn, &k_nn_values, &st.rigid.n, &spc.mask, &st.map)?
        } else {
            AutoSpcReport::default()
        };
        spc.add_autospc(&autospc);
        let sets = Sets::new(&st.map, &st.rigid.m_mask, &spc.mask)?;
        let ff = Partition::new(st.k_nn.pattern().clone(), &sets.f_in_n, &sets.f_in_n)?;
        let k_ff = ff.apply(&st.k_nn)?;
        let m_ff = ff.apply(&st.m_nn)?;
        let k_ff = k_ff.evaluate(&st.weights(&k_ff))?;
        let m_ff = m_ff.evaluate(&st.weights(&m_ff))?;
        let k_fs = crate::assembly::reduce::partition(&st.k_nn, &sets.f_in_n, &sets.s_in_n)?;
        Ok(Constrained {
            spc,
            sets,
            autospc,
            k_nn_values,
            k_ff,
            m_ff,
            k_fs,
        })
    }

    /// K_ff and M_ff with every affine part (for a pROM build), on one pattern.
    pub fn affine_ff(&self, st: &Structure) -> Result<(AffineOperator, AffineOperator), RunError> {
        let ff = Partition::new(
            st.k_nn.pattern().clone(),
            &self.sets.f_in_n,
            &self.sets.f_in_n,
        )?;
        Ok((ff.apply(&st.k_nn)?, ff.apply(&st.m_nn)?))
    }

    /// Whether K_ff has (relatively) no stiffness on the diagonal at f index `i`.
    fn no_stiffness(&self, i: usize) -> bool {
        let diag = |j: usize| {
            self.k_ff
                .get_entry(j, j)
                .map_or(0.0, |v| v.into_value().abs())
        };
        let max = (0..self.k_ff.nrows()).map(diag).fold(0.0_f64, f64::max);
        diag(i) <= crate::assembly::spc::AUTOSPC_RATIO * max
    }

    /// Map a factorization failure at f index `index` to (GRID, component).
    pub fn mechanism(&self, st: &Structure, subcase: u32, e: LinalgError) -> RunError {
        // LLᵀ of K_ff failing is a mechanism; a zero pivot of K − σM (eigen) is one only when
        // K_ff itself has no stiffness there (otherwise σ hit an eigenvalue: report it as is).
        let index = match e {
            LinalgError::NotPositiveDefinite { index, .. } => Some(index),
            LinalgError::Singular { index } if self.no_stiffness(index) => Some(index),
            _ => None,
        };
        match index
            .and_then(|i| self.sets.f.members().get(i))
            .and_then(|&g| st.map.dof_name(g))
        {
            Some(dof) => RunError::Mechanism {
                subcase,
                dof,
                detail: e.to_string(),
            },
            None => RunError::Linalg { subcase, source: e },
        }
    }
}

/// The AUTOSPC list of a result group: attribute `autospc_count` and, when non-empty, the
/// dataset `autospc` (k×2 u32: GRID id, component 1–6). A dataset, not an attribute: the lists
/// of solid models (three rotations per grid) exceed HDF5's 64 KiB attribute limit.
pub fn write_autospc(group: &hdf5_metno::Group, report: &AutoSpcReport) -> Result<(), IoError> {
    crate::io::set_attr_i64(group, "autospc_count", report.names.len() as i64)?;
    if !report.names.is_empty() {
        let flat: Vec<u32> = report
            .names
            .iter()
            .flat_map(|d| [d.grid, u32::from(d.component)])
            .collect();
        crate::io::write_u32(group, "autospc", &flat, &[report.names.len(), 2])?;
    }
    Ok(())
}

/// The output request `name` of a subcase, unless absent or `= NONE`.
pub fn requested<'a>(sub: &'a Subcase, name: &str) -> Option<&'a OutputRequest> {
    sub.outputs
        .iter()
        .rev()
        .find(|o| o.name == name)
        .filter(|o| o.target != Target::None)
}

/// The grids a grid-point output request (`DISPLACEMENT`, `SPCFORCES`) writes.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum GridRows {
    /// Every grid, rows in `/model/grid_ids` order (`= ALL`).
    All,
    /// The grids of a case-control `SET` (0-based grid indices, increasing id); SET ids that
    /// are no grid are ignored, as in Nastran.
    Set(Vec<usize>),
}

impl GridRows {
    /// What the subcase's last `name` request selects: `None` for `= NONE`, and `absent` when
    /// the subcase (and the case-control defaults) has no such request.
    pub fn of_subcase(
        deck: &Deck,
        map: &DofMap,
        sub: &Subcase,
        name: &str,
        absent: Option<GridRows>,
    ) -> Option<GridRows> {
        let Some(request) = sub.outputs.iter().rev().find(|o| o.name == name) else {
            return absent;
        };
        match request.target {
            Target::None => None,
            Target::All => Some(GridRows::All),
            Target::Set(_) => Some(GridRows::Set(
                (0..map.grids())
                    .filter(|&g| map.grid_id(g).is_some_and(|id| selected(deck, request, id)))
                    .collect(),
            )),
        }
    }

    /// The selected grid indices (every grid for `ALL`), in `/model/grid_ids` order.
    pub fn indices(&self, map: &DofMap) -> Vec<usize> {
        match self {
            GridRows::All => (0..map.grids()).collect(),
            GridRows::Set(rows) => rows.clone(),
        }
    }

    /// For a SET, `<name>_grid_ids` (k, u32): the ids of the rows of dataset `name`; nothing
    /// for `ALL` (the rows are `/model/grid_ids`).
    pub fn write_ids(
        &self,
        group: &hdf5_metno::Group,
        name: &str,
        map: &DofMap,
    ) -> Result<(), IoError> {
        if let GridRows::Set(rows) = self {
            let ids: Vec<u32> = rows.iter().filter_map(|&g| map.grid_id(g)).collect();
            crate::io::write_u32(group, &format!("{name}_grid_ids"), &ids, &[ids.len()])?;
        }
        Ok(())
    }

    /// Writes `values` (`lead` blocks of n × 6 grid rows in `/model/grid_ids` order, e.g.
    /// `[modes]` or none) as dataset `name` of shape lead × k × 6 holding the selected rows, and
    /// [`Self::write_ids`]. One writer for every real grid-point output of every sequence (the
    /// complex FRF displacement solves only the selected rows and writes them itself).
    pub fn write(
        &self,
        group: &hdf5_metno::Group,
        name: &str,
        values: &[f64],
        lead: &[usize],
        map: &DofMap,
    ) -> Result<(), IoError> {
        let n = map.grids();
        let shape = |k: usize| lead.iter().copied().chain([k, 6]).collect::<Vec<_>>();
        match self {
            GridRows::All => {
                crate::io::write_f64(group, name, values, &shape(n))?;
            }
            GridRows::Set(rows) => {
                let kept: Vec<f64> = values
                    .chunks_exact(6 * n)
                    .flat_map(|block| {
                        rows.iter()
                            .flat_map(move |&g| block[6 * g..6 * g + 6].iter().copied())
                    })
                    .collect();
                crate::io::write_f64(group, name, &kept, &shape(rows.len()))?;
            }
        }
        self.write_ids(group, name, map)
    }
}

/// Whether an id passes an output request's target (`ALL` or a `SET`).
pub fn selected(deck: &Deck, request: &OutputRequest, id: u32) -> bool {
    match request.target {
        Target::All => true,
        Target::None => false,
        Target::Set(s) => deck.case.set(s).is_some_and(|set| set.ids.contains(&id)),
    }
}

/// Sturm check as stored in the output and printed.
pub fn sturm_line(s: &SturmCheck) -> String {
    format!(
        "Sturm check at {:.6e} Hz: {} eigenvalue(s) below, {} found + {} below the shift — {}",
        lambda_to_hz(s.shift),
        s.negative_pivots,
        s.found,
        s.below_lower,
        if s.is_consistent() {
            "consistent".to_string()
        } else {
            format!("{} MISSING", s.missing())
        }
    )
}
