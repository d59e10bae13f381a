//! Id spaces and duplicate detection.
//!
//! Nastran id spaces checked here (one id may appear once per space):
//!
//! | space | cards |
//! |---|---|
//! | grids | GRID |
//! | coordinate systems | CORD2R CORD2C |
//! | elements | CQUAD4 CTRIA3 CHEXA CPENTA CTETRA CELAS1 CELAS2 RBE2 RBE3 and the other element cards |
//! | mass elements | CONM2 (may share an id with another element, with a warning) |
//! | properties | PSHELL PCOMP PSOLID PELAS |
//! | materials | MAT1 MAT8 |
//! | tables | TABLED1 TABLEF |
//! | one space each | EIGRL, TSTEP, TINTEG, DESVAR, DDVAL, PMPAR (id and name), PMOR, PVAL, SENSOR (id and name) |
//!
//! Set ids (SPC, LOAD, FREQ, DAREA …) are not unique: cards with the same SID combine.

use std::collections::HashMap;
use std::hash::Hash;

use crate::deck::{DeckError, Loc};

/// One entry of an id space: the id, the card name, where it is, and what to store.
pub struct Entry<'a, K, T> {
    pub id: K,
    pub card: &'static str,
    pub loc: &'a Loc,
    pub value: T,
}

/// Index the entries by id; every repeated id is an error at the repeat, naming the first.
///
/// `space` names the id space in the message (`"element"`, `"property"` …).
pub fn index<'a, K, T>(
    entries: Vec<Entry<'a, K, T>>,
    space: &str,
    errors: &mut Vec<DeckError>,
) -> HashMap<K, T>
where
    K: Hash + Eq + Clone + std::fmt::Display,
{
    let mut map: HashMap<K, T> = HashMap::with_capacity(entries.len());
    let mut first: HashMap<K, (&'static str, &'a Loc)> = HashMap::with_capacity(entries.len());
    for e in entries {
        if let Some((card, loc)) = first.get(&e.id) {
            errors.push(
                DeckError::at(
                    e.loc,
                    format!(
                        "duplicate {space} id {}: {card} {} at {loc} has the same id",
                        e.id, e.id
                    ),
                )
                .on_card(format!("{} {}", e.card, e.id)),
            );
            continue;
        }
        first.insert(e.id.clone(), (e.card, e.loc));
        map.insert(e.id, e.value);
    }
    map
}

/// Shorthand for an [`Entry`].
pub fn entry<'a, K, T>(id: K, card: &'static str, loc: &'a Loc, value: T) -> Entry<'a, K, T> {
    Entry {
        id,
        card,
        loc,
        value,
    }
}
