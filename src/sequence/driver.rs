//! The one interface of a solution sequence: each driver file implements [`Driver`] (its name,
//! the `SOL`s it runs, whether it runs on the deck's mesh or on pROM artifacts, the output
//! requests it writes, its run-wide warnings and its `run`), and [`DRIVERS`] lists them. Which
//! deck can run ([`runnable`]) and which output requests get a "not honoured" warning
//! ([`request_warnings`]) follow from that list.

use std::collections::HashSet;

use super::{
    Clock, RunContext, RunError, SubcaseSummary, estimate, fmb, fmb_estimate, frf, modal, optimize,
    prom, rom_case, rom_frf, rom_modal, rom_transient, statics, transient,
};
use crate::deck::case_control::Subcase;
use crate::deck::{Deck, Solution, Warning};
use crate::model::Model;

/// What a driver runs on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Basis {
    /// The deck's own bulk data: its mesh, or its mechanism for `SOL FMB` (no subcase has
    /// `ROM =`).
    Mesh,
    /// pROM artifacts (`ROM = 'file.h5'` in every subcase).
    Rom,
}

/// What a driver does with the elements' damping (the viscous dampers' and PBUSH's B, the
/// structural damping GE).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ElementDampingUse {
    /// Assembled and applied (full-model FRF and transient).
    Applied,
    /// Not part of the problem (statics and real modes, as Nastran).
    Ignored,
    /// The basis it runs on cannot carry it (pROM artifacts carry Rayleigh damping only): a
    /// viscous damper is refused ([`runnable`]), GE left out with a warning.
    NotCarried,
}

/// One solution sequence on one [`Basis`]: a unit struct in its own file of `src/sequence/`.
pub trait Driver: Sync {
    /// The sequence's name as in DESIGN.md (`STATICS`, `MODAL`), the report's header.
    fn name(&self) -> &'static str;

    /// The `SOL`s it runs.
    fn solutions(&self) -> &'static [Solution];

    /// Whether it runs on the mesh or on pROM artifacts.
    fn basis(&self) -> Basis;

    /// The output requests it writes (each for `ALL` or the ids of its SET); every other
    /// request of its subcases gets a "not honoured" warning.
    fn honoured(&self) -> &'static [&'static str] {
        &[]
    }

    /// What it does with the elements' damping.
    fn element_damping(&self) -> ElementDampingUse {
        ElementDampingUse::NotCarried
    }

    /// Warnings about the whole run, before those of its subcases.
    fn warnings(&self, _model: &Model) -> Vec<String> {
        Vec::new()
    }

    /// Runs every subcase, recording the steps' timings in `clock`.
    fn run(&self, ctx: &RunContext, clock: &mut Clock) -> Result<Vec<SubcaseSummary>, RunError>;
}

/// Every driver paraflex has.
pub const DRIVERS: &[&dyn Driver] = &[
    &statics::Statics,
    &modal::Modal,
    &prom::PromBuild,
    &frf::Frf,
    &transient::Transient,
    &rom_modal::RomModal,
    &rom_frf::RomFrf,
    &rom_transient::RomTransient,
    &estimate::Estimate,
    &fmb::Fmb,
    &fmb_estimate::MechanismEstimate,
    &optimize::Optimize,
];

/// The driver of `sol` on `basis`, if there is one.
pub fn driver(sol: Solution, basis: Basis) -> Option<&'static dyn Driver> {
    DRIVERS
        .iter()
        .copied()
        .find(|d| d.basis() == basis && d.solutions().contains(&sol))
}

/// The driver that runs `model`'s SOL, or why none can: no SOL, a SOL without a driver, or
/// subcases that mix `ROM =` with full-model subcases (one run is either on pROM artifacts or
/// on the deck's mesh), or a SOL without a driver on that basis. The CLI asks before opening
/// the output file, to exit with "not available" without writing anything.
pub fn runnable(deck: &Deck, model: &Model) -> Result<&'static dyn Driver, RunError> {
    let (sol, text) = deck.executive.sol.as_ref().ok_or(RunError::NoSolution)?;
    if !DRIVERS.iter().any(|d| d.solutions().contains(sol)) {
        return Err(RunError::NotAvailable(format!("{text} ({})", sol.name())));
    }
    let chosen = choose(model, *sol, text)?;
    let dampers = model.viscous_damping_elements(4);
    if !dampers.is_empty() && chosen.element_damping() == ElementDampingUse::NotCarried {
        return Err(RunError::NotAvailable(format!(
            "{text} ({}) {} with viscous damping elements ({}{}): their damping matrix is not carried by pROMs or this sequence; SOL 108, 109, 111 and 112 on the full model apply them, statics and real modes ignore them",
            sol.name(),
            if chosen.basis() == Basis::Rom {
                "on a pROM".to_string()
            } else {
                format!("by the sequence {}", chosen.name())
            },
            dampers.join(", "),
            if dampers.len() == 4 { ", …" } else { "" }
        )));
    }
    Ok(chosen)
}

/// The warning of a run whose driver cannot carry the elements' structural damping GE.
pub fn element_damping_warning(driver: &dyn Driver, model: &Model) -> Option<String> {
    if driver.element_damping() != ElementDampingUse::NotCarried {
        return None;
    }
    let some = model.structural_damping_elements(4);
    (!some.is_empty()).then(|| {
        format!(
            "the structural damping GE of {}{} is not applied by the sequence {} (pROM artifacts carry Rayleigh damping only)",
            some.join(", "),
            if some.len() == 4 { ", …" } else { "" },
            driver.name()
        )
    })
}

/// The warnings of subcases whose `SDAMPING` is left out: only the modal full-model FRF
/// (SOL 111, or SOL FRF with METHOD) applies a modal damping table, as Nastran applies it in
/// modal solutions only (full-model SOL 112 integrates the full model directly).
pub fn sdamping_warnings(driver: &dyn Driver, model: &Model, sol: Solution) -> Vec<String> {
    let modal = driver.name() == "FRF" && driver.basis() == Basis::Mesh;
    model
        .subcases
        .iter()
        .filter_map(|sub| {
            let tid = sub.sdamping?;
            let applied = modal
                && match sol {
                    Solution::FrfModal => true,
                    Solution::Frf => sub.method.is_some(),
                    _ => false,
                };
            (!applied).then(|| format!("subcase {}: SDAMPING = {tid} is not applied by SOL {} here: a modal damping table acts in the modal FRF on the full model only (SOL 111)", sub.id, sol.name()))
        })
        .collect()
}

/// The driver of `sol` on the basis the subcases ask for (module doc of [`runnable`]).
fn choose(model: &Model, sol: Solution, text: &str) -> Result<&'static dyn Driver, RunError> {
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
    if rom_case::applies(model) {
        driver(sol, Basis::Rom).ok_or_else(|| {
            let names: Vec<&str> = DRIVERS
                .iter()
                .filter(|d| d.basis() == Basis::Rom)
                .map(|d| d.name())
                .collect();
            RunError::NotAvailable(format!(
                "{text} ({}) on a pROM artifact (ROM =): pROMs run SOL {}",
                sol.name(),
                list(&names)
            ))
        })
    } else if sol == Solution::Estimate
        && model.mechanism.is_empty()
        && model.subcases.iter().all(|s| s.fmb.is_none())
    {
        Err(RunError::NotAvailable(format!(
            "{text} ({}) on the full model: the estimators run on pROM artifacts (ROM = 'file.h5' in every subcase) or on a mechanism (FLEXB or RIGIDB bodies, or FMB = 'file.h5')",
            sol.name()
        )))
    } else {
        driver(sol, Basis::Mesh).ok_or_else(|| {
            RunError::NotAvailable(format!(
                "{text} ({}) on the full model (this version runs it on pROM artifacts: every subcase needs ROM = 'file.h5')",
                sol.name()
            ))
        })
    }
}

/// "A, B and C".
fn list(names: &[&str]) -> String {
    match names {
        [] => String::new(),
        [one] => one.to_string(),
        [first @ .., last] => format!("{} and {last}", first.join(", ")),
    }
}

/// One warning per output request (at its statement) that the driver of its subcase does not
/// write ([`Driver::honoured`]): "not honoured by SOL x in this version". A request of the
/// case-control defaults, repeated in every subcase, is warned once.
pub fn request_warnings(deck: &Deck, model: &Model) -> Vec<Warning> {
    let sol = deck
        .executive
        .sol
        .as_ref()
        .map(|(_, text)| text.clone())
        .unwrap_or_else(|| "(none)".into());
    let mut warned = HashSet::new();
    let mut warnings = Vec::new();
    for sub in &model.subcases {
        let honoured = honoured_requests(deck, sub);
        for out in &sub.outputs {
            if !honoured.contains(&out.name) && warned.insert(out.loc.clone()) {
                warnings.push(Warning {
                    loc: Some(out.loc.to_string()),
                    message: format!(
                        "output request {} is not honoured by SOL {sol} in this version",
                        out.name
                    ),
                });
            }
        }
    }
    warnings
}

/// The output requests the driver of subcase `sub` writes (none without one).
fn honoured_requests(deck: &Deck, sub: &Subcase) -> &'static [&'static str] {
    let basis = if sub.rom.is_some() {
        Basis::Rom
    } else {
        Basis::Mesh
    };
    deck.executive
        .sol
        .as_ref()
        .and_then(|(sol, _)| driver(*sol, basis))
        .map_or(&[], |d| d.honoured())
}
