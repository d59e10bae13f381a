//! Scalar points: points with one DOF and no location, declared by `SPOINT` or, as in Nastran,
//! implicitly by a scalar element (CELAS, CDAMP) end whose component is 0 or blank and whose id
//! is no GRID.
//!
//! A scalar point id shares the id space of the grids: an `SPOINT` id that is also a GRID is an
//! error, and so is a component 0 on an end that names a GRID (a grid needs a component 1–6).

use std::collections::HashMap;

use crate::card_values::SpringEnd;
use crate::deck::cards::BulkData;
use crate::deck::{DeckError, Loc};

/// The DOF of one scalar-element end, resolved.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PointDof {
    /// Component `component0` (0-based, 0..6) of the grid with this index into
    /// [`Model::grids`](super::Model::grids).
    Grid { grid: usize, component0: usize },
    /// The scalar point with this index into [`Model::scalar_points`](super::Model::scalar_points).
    Scalar(usize),
}

/// Every end of a scalar element in the deck, with its card name, id and location.
pub(super) fn scalar_element_ends(b: &BulkData) -> Vec<(&'static str, u32, [SpringEnd; 2], &Loc)> {
    let mut out = Vec::new();
    let with_pid = [
        ("CELAS1", &b.celas1),
        ("CELAS3", &b.celas3),
        ("CDAMP1", &b.cdamp1),
        ("CDAMP3", &b.cdamp3),
    ];
    for (name, cards) in with_pid {
        out.extend(cards.iter().map(|c| (name, c.id, c.ends, &c.loc)));
    }
    let on_card = [
        ("CELAS2", &b.celas2),
        ("CELAS4", &b.celas4),
        ("CDAMP2", &b.cdamp2),
        ("CDAMP4", &b.cdamp4),
    ];
    for (name, cards) in on_card {
        out.extend(cards.iter().map(|c| (name, c.id, c.ends, &c.loc)));
    }
    out
}

/// The scalar points of a deck, sorted by id, and id → index. Errors: an `SPOINT` id that is
/// also a GRID.
pub(super) fn build(
    b: &BulkData,
    grid_index: &super::ids::IdMap<usize>,
    errors: &mut Vec<DeckError>,
) -> (Vec<u32>, HashMap<u32, usize>) {
    let mut ids: Vec<u32> = Vec::new();
    for s in &b.spoints {
        for &id in &s.ids {
            if grid_index.contains_key(&id) {
                errors.push(
                    DeckError::at(
                        &s.loc,
                        format!("scalar point {id} is also a GRID id (grids and scalar points share one id space)"),
                    )
                    .on_card("SPOINT"),
                );
            } else {
                ids.push(id);
            }
        }
    }
    for (_, _, ends, _) in scalar_element_ends(b) {
        for end in ends {
            if let (Some(id), 0) = (end.grid, end.component)
                && !grid_index.contains_key(&id)
            {
                ids.push(id);
            }
        }
    }
    ids.sort_unstable();
    ids.dedup();
    let index = ids.iter().enumerate().map(|(i, &id)| (id, i)).collect();
    (ids, index)
}
