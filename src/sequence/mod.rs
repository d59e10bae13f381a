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
//! The full-model drivers share the discretization of [`crate::discretize`]: one
//! [`Structure`] (element matrices, one grid-block pattern for K and M, rigid elimination
//! g → n with one plan) and per SPC set the f-set with AUTOSPC ([`Constrained`]). Everything
//! the user must see (AUTOSPC lists, Sturm check, warnings, timings) is returned in a
//! [`RunSummary`], each driver's part rendered by its [`Report`]; the library never prints,
//! long steps report through [`Progress`].
//!
//! A new sequence is one driver file (its `run`, its summary type implementing [`Report`]) plus
//! one arm in [`Sequence`], [`SubcaseResult`] and the dispatch of [`run`]; what several drivers
//! share lives in [`shared`] and [`rom_case`], never in another driver.
//!
//! Output (HDF5, DESIGN.md §8; full layout in docs/hdf5-schema.md):
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

pub mod estimate;
pub mod frf;
pub mod modal;
pub mod prom;
pub mod report;
pub mod rom_case;
pub mod rom_frf;
pub mod rom_modal;
pub mod rom_transient;
pub mod shared;
pub mod statics;
pub mod transient;

use std::time::{Duration, Instant};

use crate::assembly::error::DofName;
use crate::assembly::spc::AutoSpcReport;
use crate::assembly::{AssemblyError, DofMap};
use crate::deck::case_control::{OutputRequest, Subcase, Target};
use crate::deck::{Deck, Solution};
use crate::discretize::sensors::{SensorOperator, sensor_operator};
use crate::discretize::{BuildOptions, Constrained, DiscretizeError, Structure};
use crate::io::{IoError, OutputFile};
use crate::linalg::{LinalgError, Progress};
use crate::model::sensors::Sensor;

use crate::model::Model;
pub use report::Report;

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

/// Everything a driver needs.
pub struct RunContext<'a> {
    pub deck: &'a Deck,
    pub model: &'a Model,
    /// The output file (already holding `/model`); drivers add `/results`.
    pub output: &'a OutputFile,
    pub progress: &'a dyn Progress,
    pub options: BuildOptions,
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

impl SubcaseResult {
    /// The console lines and warnings of this result.
    pub fn report(&self) -> &dyn Report {
        match self {
            SubcaseResult::Modal(r) => r,
            SubcaseResult::Statics(r) => r,
            SubcaseResult::Prom(r) => r,
            SubcaseResult::Frf(r) => r,
            SubcaseResult::RomModal(r) => r,
            SubcaseResult::RomFrf(r) => r,
            SubcaseResult::RomTransient(r) => r,
            SubcaseResult::Transient(r) => r,
            SubcaseResult::Estimate(r) => r,
        }
    }
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
    /// K_ff is singular: a mechanism or a missing constraint.
    #[error(
        "subcase {subcase}: the stiffness matrix is singular at {dof} ({detail}); the structure is a mechanism or is not constrained there — add an SPC (or GRID PS) for this DOF, or let PARAM,AUTOSPC,YES remove DOFs without stiffness"
    )]
    Mechanism {
        subcase: u32,
        dof: DofName,
        detail: String,
    },
    /// A subcase lacks a selection the sequence needs.
    #[error("subcase {subcase}: {what}")]
    Case { subcase: u32, what: String },
    /// An element or a PMPAR the discretization rejects.
    #[error(transparent)]
    Discretize(#[from] DiscretizeError),
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
            let structure =
                Structure::build_timed(ctx.model, &ctx.options, ctx.progress, &mut |name, d| {
                    clock.record(name, d)
                })?;
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
    if sequence == Sequence::Transient {
        warnings.extend(transient::damping_warning(ctx.model));
    }
    for s in &subcases {
        if !s.autospc.is_empty() {
            warnings.push(format!(
                "subcase {}: AUTOSPC constrained {} DOF(s) without stiffness (listed in the summary and in the results group's `autospc` dataset)",
                s.id,
                s.autospc.len()
            ));
        }
        warnings.extend(s.result.report().warnings(s.id));
    }
    Ok(RunSummary {
        sequence,
        subcases,
        timings: clock.steps,
        warnings,
    })
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
        self.record(name, start.elapsed());
        out
    }

    /// Records a step timed elsewhere.
    pub fn record(&mut self, name: impl Into<String>, duration: Duration) {
        self.steps.push((name.into(), duration));
    }
}

/// The error of a factorization of K_ff (or K − σM) of subcase `subcase`: a mechanism at its
/// (GRID, component) when it is one ([`Constrained::mechanism_dof`]), the solver's error
/// otherwise.
pub fn mechanism(c: &Constrained, st: &Structure, subcase: u32, e: LinalgError) -> RunError {
    match c.mechanism_dof(st, &e) {
        Some(dof) => RunError::Mechanism {
            subcase,
            dof,
            detail: e.to_string(),
        },
        None => RunError::Linalg { subcase, source: e },
    }
}

/// The SENSOR cards `sub` selects (`SENSOR = ALL | NONE | set`, every card without a request),
/// in card order.
pub fn selected_sensors(deck: &Deck, model: &Model, sub: &Subcase) -> Vec<Sensor> {
    let sensors = model.sensors();
    match &sub.sensor {
        None | Some(Target::All) => sensors,
        Some(Target::None) => Vec::new(),
        Some(Target::Set(id)) => {
            let set = deck.case.set(*id);
            sensors
                .into_iter()
                .filter(|s| set.is_some_and(|set| set.ids.contains(&s.id)))
                .collect()
        }
    }
}

/// The f-set sensor rows of the SENSORs `sub` selects; an error is the subcase's.
pub fn subcase_sensors(
    ctx: &RunContext,
    st: &Structure,
    c: &Constrained,
    sub: &Subcase,
) -> Result<SensorOperator, RunError> {
    let sensors = selected_sensors(ctx.deck, ctx.model, sub);
    sensor_operator(ctx.model, st, c, &sensors).map_err(|what| RunError::Case {
        subcase: sub.id,
        what,
    })
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
