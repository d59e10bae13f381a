//! Solution sequences (DESIGN.md §1–§2): the only place that turns case control into calls.
//!
//! One driver per sequence and basis (the deck's mesh, or pROM artifacts when every subcase
//! has `ROM =`), each a [`Driver`] listed in [`DRIVERS`] and chosen by the deck's `SOL`
//! statement ([`runnable`]); its `run` takes a [`RunContext`] (deck, model, output file,
//! progress sink, options):
//!
//! | `SOL` | driver | per subcase |
//! |---|---|---|
//! | `101`, `STATICS` | [`statics`] | `SPC`, `LOAD` → u, SPC forces, centroid strains |
//! | `103`, `MODAL` | [`modal`] (mesh), [`rom_modal`] (`ROM =`) | `SPC`, `METHOD` (EIGRL) → frequencies, generalized masses, residuals, shapes |
//! | `PROM` | [`prom`] | `PROM` (PMOR), `SPC` → the pROM artifact |
//! | `108`, `111`, `FRF` | [`frf`] (mesh), [`rom_frf`] (`ROM =`) | `SPC`, `FREQUENCY`, `DLOAD` (RLOAD1/DAREA inputs), `METHOD` (111) → complex FRFs at inputs and SENSORs |
//! | `109`, `112`, `TRANSIENT` | [`transient`] (mesh), [`rom_transient`] (`ROM =`) | `TSTEP` (+`TINTEG`), `DLOAD`, `IC` → sensor histories |
//! | `ESTIMATE` | [`estimate`] (`ROM =`), [`fmb_estimate`] (a mechanism) | `ESTIM` (EKF), `MEAS` (MEASF) → states, inputs, parameters (the AMANDA-EKF on a mechanism: `EKFPAR` `BODY.PMPAR`, `AMANDA`) |
//! | `FMB` | [`fmb`] | the mechanism, `TSTEP`, `LOAD` (GRAV), `PVAL` (`BODY.PMPAR`) → MSENSOR and drive histories |
//! | `OPTIMIZE` | [`optimize`] | the mechanism run as `FMB` per design: `DESVAR`/`DDVAL`, `DVMAP`, `DOBJ`, `DCONSTR`, `MOOPT` → designs, responses, Pareto set, hypervolume, correlations, representative histories |
//!
//! The mesh drivers share the discretization of [`crate::discretize`] ([`shared::structure`]):
//! one [`Structure`] (element matrices, one grid-block pattern for K and M, rigid elimination
//! g → n with one plan) and per SPC set the f-set with AUTOSPC ([`Constrained`]). Everything
//! the user must see (AUTOSPC lists, Sturm check, warnings, timings) is returned in a
//! [`RunSummary`], each subcase's part rendered by the driver's summary type through
//! [`Report`]; the library never prints, long steps report through [`Progress`]. Output
//! requests a driver does not write ([`Driver::honoured`]) are warned by
//! [`request_warnings`].
//!
//! A new sequence is one driver file (a unit struct implementing [`Driver`], its summary type
//! implementing [`Report`]) plus one entry in [`DRIVERS`]; what several drivers share lives
//! in [`shared`] and [`rom_case`], never in another driver.
//!
//! Output (HDF5, DESIGN.md §8; full layout in docs/hdf5-schema.md):
//!
//! ```text
//! /results/<subcase>/modal/{frequency_hz (m), generalized_mass (m), residual (m), eigenvalue (m),
//!                           shapes (m×k×6, only with DISPLACEMENT)}
//!     attrs (of the group modal): sturm_shift, sturm_count, sturm_found, sturm_consistent,
//!            sturm_note (a multiple root cut by ND), shift, norm, autospc_count, massless_count,
//!            finite_exhausted
//! /results/<subcase>/statics/{displacement (k×6; all grids without a DISPLACEMENT request,
//!                             none with DISPLACEMENT = NONE), spc_force (k×6, only with
//!                             SPCFORCES), strain/<CARD>/... (only with STRAIN)}
//! ```
//!
//! Grid-point outputs keep the rows their request selects ([`GridRows`]): k = n for `ALL`
//! (rows in `/model/grid_ids` order), the SET's grids otherwise, listed in `<name>_grid_ids`.
//!
//! Vectors are written in the basic system (rotated back from the grids' CD frames).

pub mod driver;
pub mod estimate;
pub mod fmb;
pub mod fmb_estimate;
pub mod fmb_ranking;
pub mod frf;
pub mod modal;
pub mod optimize;
pub mod optimize_engine;
pub mod optimize_gradient;
pub mod optimize_journal;
pub mod optimize_library;
mod optimize_output;
pub mod optimize_study;
pub mod prom;
pub mod random;
pub mod report;
pub mod rom_case;
pub mod rom_frf;
pub mod rom_modal;
pub mod rom_transient;
pub mod shared;
pub mod statics;
pub mod statics_stress;
pub mod transient;
pub mod usage;

use std::time::Duration;

use crate::analysis::AnalysisError;
use crate::assembly::error::DofName;
use crate::assembly::spc::AutoSpcReport;
use crate::assembly::{AssemblyError, DofMap};
use crate::deck::Deck;
use crate::deck::case_control::{OutputRequest, Subcase, Target};
use crate::discretize::sensors::{SensorOperator, sensor_operator};
use crate::discretize::{BuildOptions, Constrained, DiscretizeError, Structure};
use crate::io::{IoError, OutputFile};
use crate::linalg::{LinalgError, Progress};
use crate::model::sensors::Sensor;

use crate::model::Model;
pub use driver::{Basis, DRIVERS, Driver, request_warnings, runnable};
pub use report::Report;

/// Everything a driver needs.
pub struct RunContext<'a> {
    pub deck: &'a Deck,
    pub model: &'a Model,
    /// The output file (already holding `/model`); drivers add `/results`.
    pub output: &'a OutputFile,
    pub progress: &'a dyn Progress,
    pub options: BuildOptions,
    /// The command of an evaluation engine outside this process for `SOL OPTIMIZE`'s batches
    /// (`paraflex run --engine`, [`optimize_engine`]); `None`: NPAR threads here.
    pub engine: Option<&'a str>,
}

/// Result of a run, for the console.
#[derive(Debug)]
pub struct RunSummary {
    /// The sequence's name ([`Driver::name`]).
    pub sequence: &'static str,
    /// Model-level lines printed before the subcases (the grid-point weight table).
    pub model_lines: Vec<String>,
    pub subcases: Vec<SubcaseSummary>,
    /// Wall-clock time of each step, in order.
    pub timings: Vec<(String, Duration)>,
    /// Wall time, CPU time and memory of each step, in order ([`usage`]); the binary puts the
    /// reading of the deck in front.
    pub phases: Vec<usage::Phase>,
    /// Things the user should know (AUTOSPC lists, inconsistent Sturm checks, …).
    pub warnings: Vec<String>,
}

/// One subcase's outcome.
#[derive(Debug)]
pub struct SubcaseSummary {
    pub id: u32,
    /// DOFs AUTOSPC constrained (empty when none or AUTOSPC is off).
    pub autospc: Vec<DofName>,
    /// The driver's summary of the subcase (its type is the driver's, e.g.
    /// [`modal::ModalSummary`]; [`Self::result`] gives it back).
    pub result: Box<dyn Report>,
}

impl SubcaseSummary {
    /// The driver's summary as its own type `T`, or `None` when another driver wrote it.
    pub fn result<T: Report>(&self) -> Option<&T> {
        let any: &dyn std::any::Any = self.result.as_ref();
        any.downcast_ref()
    }
}

/// Errors of a run. Each says where (element, GRID and component, subcase) and what to do.
#[derive(Debug, thiserror::Error)]
pub enum RunError {
    /// The deck's SOL has no driver (exit code 3: nothing is run or written).
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
    #[error(transparent)]
    Weight(#[from] crate::analysis::weight::WeightError),
}

/// Runs the deck's solution sequence (see the module documentation).
pub fn run(ctx: &RunContext) -> Result<RunSummary, RunError> {
    let driver = runnable(ctx.deck, ctx.model)?;
    let mut clock = Clock::new();
    let subcases = driver.run(ctx, &mut clock)?;
    let mut warnings = driver.warnings(ctx.model);
    warnings.extend(driver::element_damping_warning(driver, ctx.model));
    if ctx.model.has_suport() && !matches!(driver.name(), "STATICS" | "MODAL") {
        warnings.push(format!(
            "SUPORT/SUPORT1 cards are ignored by {} (only SOL 101 and SOL 103 use the r-set)",
            driver.name()
        ));
    }
    if let Some((sol, _)) = &ctx.deck.executive.sol {
        warnings.extend(driver::sdamping_warnings(driver, ctx.model, *sol));
    }
    for s in &subcases {
        if !s.autospc.is_empty() {
            let (n, id) = (s.autospc.len(), s.id);
            let listed = "listed in the summary and in the results group's `autospc` dataset";
            warnings.push(if ctx.model.params.autospc {
                format!("subcase {id}: AUTOSPC constrained {n} DOF(s) without stiffness ({listed})")
            } else {
                format!(
                    "subcase {id}: {n} DOF(s) that no element reaches (null rows of the solution's matrices) removed although AUTOSPC is off, as MSC Nastran removes them ({listed})"
                )
            });
        }
        warnings.extend(s.result.warnings(s.id));
    }
    Ok(RunSummary {
        sequence: driver.name(),
        model_lines: clock.model_lines,
        subcases,
        timings: clock.steps,
        phases: clock.phases,
        warnings,
    })
}

/// Step timings of a run with each step's resources ([`usage`]), and the model-level lines its
/// steps report (the grid-point weight table of `PARAM,GRDPNT`), printed before the subcases.
#[derive(Debug)]
pub struct Clock {
    steps: Vec<(String, Duration)>,
    phases: Vec<usage::Phase>,
    /// The reading at the end of the last step: the CPU time of a step recorded with
    /// [`Clock::record`] is counted from it.
    mark: usage::Usage,
    model_lines: Vec<String>,
}

impl Clock {
    /// A clock starting now.
    pub fn new() -> Self {
        Clock {
            steps: Vec::new(),
            phases: Vec::new(),
            mark: usage::Usage::now(),
            model_lines: Vec::new(),
        }
    }

    /// Runs `f` and records its duration and resources under `name`.
    pub fn time<T>(&mut self, name: impl Into<String>, f: impl FnOnce() -> T) -> T {
        let start = usage::Usage::now();
        let out = f();
        self.push(start.phase(name));
        out
    }

    /// [`Clock::time`] for work that reports progress: `f` gets a [`Progress`] forwarding to
    /// `progress` that also splits the step into sub-phases at each new event name
    /// ([`usage::PhaseSplitter`]); they are listed before the step's own line.
    pub fn time_split<T>(
        &mut self,
        name: impl Into<String>,
        progress: &dyn Progress,
        f: impl FnOnce(&dyn Progress) -> T,
    ) -> T {
        let start = usage::Usage::now();
        let split = usage::PhaseSplitter::new(progress);
        let out = f(&split);
        for sub in split.finish() {
            self.phases.push(usage::Phase {
                name: format!("  · {}", sub.name),
                ..sub
            });
        }
        self.push(start.phase(name));
        out
    }

    /// Records a step timed elsewhere that took `duration`; its CPU time is the process's since
    /// the previous step ended.
    pub fn record(&mut self, name: impl Into<String>, duration: Duration) {
        let phase = usage::Phase {
            wall: duration,
            ..self.mark.phase(name)
        };
        self.push(phase);
    }

    fn push(&mut self, phase: usage::Phase) {
        self.steps.push((phase.name.clone(), phase.wall));
        self.phases.push(phase);
        self.mark = usage::Usage::now();
    }

    /// Adds model-level report lines.
    pub fn report_model(&mut self, lines: impl IntoIterator<Item = String>) {
        self.model_lines.extend(lines);
    }
}

impl Default for Clock {
    fn default() -> Self {
        Self::new()
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

/// The error of an analysis of subcase `subcase` on `c`: a failing factorization is reported
/// as the mechanism it comes from ([`mechanism`]), an FRF error as the subcase's.
pub fn analysis_error(c: &Constrained, st: &Structure, subcase: u32, e: AnalysisError) -> RunError {
    match e {
        AnalysisError::Linalg(e) => mechanism(c, st, subcase, e),
        AnalysisError::Frf(e) => RunError::Case {
            subcase,
            what: e.to_string(),
        },
        AnalysisError::Assembly(e) => RunError::Assembly(e),
        AnalysisError::Discretize(e) => RunError::Discretize(e),
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

    /// Writes `values` (`lead` blocks of n × 6 grid rows in `/model/grid_ids` order followed by
    /// the values of the scalar points, e.g. `[modes]` or none) as dataset `name` of shape
    /// lead × k × 6 holding the selected rows, and [`Self::write_ids`]. A model with scalar
    /// points also gets `<name>_scalar` (lead × n_s, every scalar point) and `scalar_point_ids`.
    /// One writer for every real grid-point output of every sequence (the complex FRF
    /// displacement solves only the selected rows and writes them itself).
    pub fn write(
        &self,
        group: &hdf5_metno::Group,
        name: &str,
        values: &[f64],
        lead: &[usize],
        map: &DofMap,
    ) -> Result<(), IoError> {
        let (n, n_s) = (map.grids(), map.scalar_points());
        let block = 6 * n + n_s;
        let shape = |k: usize| lead.iter().copied().chain([k, 6]).collect::<Vec<_>>();
        let rows: Vec<usize> = self.indices(map);
        let kept: Vec<f64> = values
            .chunks_exact(block)
            .flat_map(|b| {
                rows.iter()
                    .flat_map(move |&g| b[6 * g..6 * g + 6].iter().copied())
            })
            .collect();
        crate::io::write_f64(group, name, &kept, &shape(rows.len()))?;
        if n_s > 0 {
            let scalar: Vec<f64> = values
                .chunks_exact(block)
                .flat_map(|b| b[6 * n..].iter().copied())
                .collect();
            let scalar_shape: Vec<usize> = lead.iter().copied().chain([n_s]).collect();
            crate::io::write_f64(group, &format!("{name}_scalar"), &scalar, &scalar_shape)?;
            if !group.link_exists("scalar_point_ids") {
                crate::io::write_u32(group, "scalar_point_ids", map.scalar_ids(), &[n_s])?;
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
