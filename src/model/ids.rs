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

/// A map keyed by card id: FxHash (rustc-hash), a multiply and a rotate per key, instead of the
/// standard SipHash, whose hashing of a million grid ids was the reader's largest single cost
/// (`Refs::grid`, 12 % of `paraflex check` on a 1M-quad deck). Card ids come from the deck, not
/// from an adversary, so SipHash's resistance to crafted collisions buys nothing here.
pub type IdMap<V> = rustc_hash::FxHashMap<u32, V>;

/// One entry of an id space: the id, the card name, where it is, and what to store.
pub struct Entry<'a, K, T> {
    pub id: K,
    pub card: &'static str,
    pub loc: &'a Loc,
    pub value: T,
}

/// Index the entries by id; every repeated id is an error at the repeat, naming the first.
///
/// `space` names the id space in the message (`"element"`, `"property"` …). Repeats are found
/// by sorting the entries' positions by id (4 bytes an entry) rather than in a second map of
/// every id, which on a million-element deck was the largest block alive while it ran.
pub fn index<'a, K, T>(
    entries: Vec<Entry<'a, K, T>>,
    space: &str,
    errors: &mut Vec<DeckError>,
) -> HashMap<K, T>
where
    K: Hash + Ord + Clone + std::fmt::Display,
{
    let mut order: Vec<u32> = (0..entries.len() as u32).collect();
    let id = |i: u32| &entries[i as usize].id;
    order.sort_unstable_by(|&a, &b| id(a).cmp(id(b)).then(a.cmp(&b)));
    // (repeat, first) positions; within a run of one id the first position is the original
    let mut repeats: Vec<(usize, usize)> = Vec::new();
    for run in order.chunk_by(|&a, &b| id(a) == id(b)) {
        repeats.extend(run[1..].iter().map(|&r| (r as usize, run[0] as usize)));
    }
    drop(order);
    repeats.sort_unstable();
    for &(r, f) in &repeats {
        let (repeat, first) = (&entries[r], &entries[f]);
        errors.push(
            DeckError::at(
                repeat.loc,
                format!(
                    "duplicate {space} id {}: {} {} at {} has the same id",
                    repeat.id, first.card, repeat.id, first.loc
                ),
            )
            .on_card(format!("{} {}", repeat.card, repeat.id)),
        );
    }
    let mut skip = repeats.iter().map(|&(r, _)| r).peekable();
    let mut map: HashMap<K, T> = HashMap::with_capacity(entries.len() - repeats.len());
    for (i, e) in entries.into_iter().enumerate() {
        if skip.next_if_eq(&i).is_none() {
            map.insert(e.id, e.value);
        }
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

#[cfg(test)]
mod tests {
    use std::path::Path;
    use std::sync::Arc;

    use super::*;

    #[test]
    fn every_repeat_is_reported_in_input_order_naming_the_first_and_the_first_value_is_kept() {
        let file: Arc<Path> = Arc::from(Path::new("deck.dat"));
        let locs: Vec<Loc> = (1..=7).map(|line| Loc::new(&file, line)).collect();
        let ids = [5, 3, 5, 7, 3, 5, 9];
        let entries = ids
            .iter()
            .zip(&locs)
            .enumerate()
            .map(|(i, (&id, loc))| entry(id, if i == 1 { "CTRIA3" } else { "CQUAD4" }, loc, i))
            .collect();
        let mut errors = Vec::new();
        let map = index(entries, "element", &mut errors);
        assert_eq!(map.len(), 4);
        assert_eq!((map[&5], map[&3], map[&7], map[&9]), (0, 1, 3, 6));
        let lines: Vec<u32> = errors.iter().map(|e| e.loc.line).collect();
        assert_eq!(lines, [3, 5, 6]);
        let messages: Vec<String> = errors.iter().map(|e| e.message.clone()).collect();
        assert_eq!(
            messages,
            [
                "duplicate element id 5: CQUAD4 5 at deck.dat:1 has the same id",
                "duplicate element id 3: CTRIA3 3 at deck.dat:2 has the same id",
                "duplicate element id 5: CQUAD4 5 at deck.dat:1 has the same id",
            ]
        );
    }
}
