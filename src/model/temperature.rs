//! MATT1 cross-references: its MAT1 and its TABLEM1–TABLEM4 tables must exist. The tables apply
//! only at a material temperature set, which paraflex does not read (TEMP, TEMPD and
//! `TEMPERATURE` are refused), so every MATT1 leaves its MAT1's values in force, as Nastran
//! does without `TEMPERATURE(MATERIAL)` or `TEMPERATURE(INITIAL)`; one warning says so.

use std::collections::HashSet;

use super::MaterialRef;
use super::build::Refs;
use crate::deck::fields::RawCard;
use crate::deck::{DeckError, Warning};

/// Check every MATT1 and warn once that the MAT1 values apply.
pub fn check(refs: &Refs, errors: &mut Vec<DeckError>, warnings: &mut Vec<Warning>) {
    let b = refs.bulk;
    if b.matt1.is_empty() {
        return;
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
            "MATT1 ({n} card{}): no material temperature set is selected (paraflex reads no TEMP, TEMPD or TEMPERATURE request), so each MAT1 keeps its own values, as in Nastran without TEMPERATURE(MATERIAL) or TEMPERATURE(INITIAL)",
            if n == 1 { "" } else { "s" }
        ),
    });
}
