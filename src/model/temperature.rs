//! Temperature sets and temperature-dependent materials.
//!
//! - `TEMP` / `TEMPD`: a temperature set `sid` gives each grid its TEMP value in the set, or
//!   else the set's TEMPD default ([`Model::grid_temperatures`]); every TEMP grid must exist.
//!   The sets are the thermal loads of case control `TEMPERATURE(LOAD)` (SOL 101,
//!   [`crate::discretize::thermal`]).
//! - MATT1 cross-references: its MAT1 and its TABLEM1–TABLEM4 tables must exist. The tables
//!   are never evaluated: a deck selecting a material temperature set
//!   (`TEMPERATURE(MATERIAL | INITIAL | BOTH)`) with a MATT1 is refused, and otherwise every
//!   MATT1 leaves its MAT1's values in force, as Nastran does without such a set; one warning
//!   says so.

use std::collections::HashSet;

use super::build::Refs;
use super::{MaterialRef, Model};
use crate::deck::fields::RawCard;
use crate::deck::{Deck, DeckError, Solution, Warning};

impl Model {
    /// The temperature of every grid (by grid index) in temperature set `sid`: its TEMP value,
    /// else the set's TEMPD, else `None`. `None` when no TEMP or TEMPD has SID = `sid`.
    pub fn grid_temperatures(&self, sid: u32) -> Option<Vec<Option<f64>>> {
        let b = &self.bulk;
        let default = b.tempd.iter().rev().find(|d| d.sid == sid).map(|d| d.t);
        let mut cards = b.temp.iter().filter(|t| t.sid == sid).peekable();
        if default.is_none() && cards.peek().is_none() {
            return None;
        }
        let mut out = vec![default; self.grids.len()];
        for card in cards {
            for &(grid, t) in &card.values {
                if let Some(&g) = self.grid_index.get(&grid) {
                    out[g] = Some(t);
                }
            }
        }
        Some(out)
    }
}

/// Check the TEMP grids, the MATT1 cards, and refuse a material temperature set with MATT1s.
pub fn check(deck: &Deck, refs: &Refs, errors: &mut Vec<DeckError>, warnings: &mut Vec<Warning>) {
    let b = refs.bulk;
    for t in &b.temp {
        let card = format!("TEMP {}", t.sid);
        for (k, &(grid, _)) in t.values.iter().enumerate() {
            refs.grid(grid, ["G1", "G2", "G3"][k], &card, &t.loc, errors);
        }
    }
    let statics = matches!(deck.executive.sol, Some((Solution::Statics, _)));
    if !statics
        && deck
            .case
            .subcases()
            .iter()
            .any(|s| s.temperature_load.is_some())
    {
        warnings.push(Warning {
            loc: None,
            message: "TEMPERATURE(LOAD): thermal loads are applied by SOL 101 only; this solution ignores them, as Nastran's dynamic and modal solutions do".into(),
        });
    }
    if b.matt1.is_empty() {
        return;
    }
    for sub in deck.case.subcases() {
        if let Some(sid) = sub.temperature_material {
            let at = sub
                .loc_of("TEMPERATURE(MATERIAL)")
                .cloned()
                .unwrap_or_else(|| b.matt1[0].loc.clone());
            errors.push(
                DeckError::at(
                    &at,
                    format!("TEMPERATURE(MATERIAL | INITIAL | BOTH) = {sid} with MATT1 cards: temperature-dependent material properties are not available in this version (use TEMPERATURE(LOAD) for the thermal load alone)"),
                )
                .on_card("TEMPERATURE"),
            );
            break;
        }
    }
    let tables: HashSet<u32> = (b.tablem.iter().map(|t| t.id))
        .chain(b.tablem4.iter().map(|t| t.id))
        .collect();
    for m in &b.matt1 {
        let card = format!("MATT1 {}", m.mid);
        let at = |index: usize, name: &str, message: String| {
            let mut e = DeckError::at(&m.loc, message).on_card(&card);
            e.field = Some(format!("{} ({name})", RawCard::field_label(index)));
            e
        };
        match refs.materials.get(&m.mid) {
            Some(MaterialRef::Mat1(_)) => {}
            Some(other) => errors.push(at(
                1,
                "MID",
                format!(
                    "MID = {} is a {}; a MATT1 applies to a MAT1",
                    m.mid,
                    other.card()
                ),
            )),
            None => errors.push(at(
                1,
                "MID",
                format!("MID = {} does not exist (no MAT1 {})", m.mid, m.mid),
            )),
        }
        for &(index, name, id) in &m.tables {
            if !tables.contains(&id) {
                errors.push(at(
                    index,
                    name,
                    format!("{name} = {id} does not exist (no TABLEM1, TABLEM2, TABLEM3 or TABLEM4 {id})"),
                ));
            }
        }
    }
    let n = b.matt1.len();
    warnings.push(Warning {
        loc: None,
        message: format!(
            "MATT1 ({n} card{}): no material temperature set is selected, so each MAT1 keeps its own values, as in Nastran without TEMPERATURE(MATERIAL) or TEMPERATURE(INITIAL)",
            if n == 1 { "" } else { "s" }
        ),
    });
}
