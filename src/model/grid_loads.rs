//! Loads whose direction or target the model resolves: FORCE1/FORCE2/MOMENT1/MOMENT2 (direction
//! by grids) and SLOAD (scalar points).
//!
//! - FORCE1/MOMENT1: n = (x_G2 − x_G1)/|x_G2 − x_G1|; FORCE2/MOMENT2: n = a × b/|a × b| with
//!   a = x_G2 − x_G1, b = x_G4 − x_G3; x in the basic system (the grids' positions), the load
//!   F·n in basic as a FORCE's.
//! - SLOAD: F on the scalar point's one DOF, or on component T1 of a grid's displacement
//!   system (CD), as the Nastran QRG says for an Si that is a grid.
//!
//! [`check`] reports, at its card, a direction of no length relative to the grids' distances
//! and an SLOAD on a point that is neither an SPOINT nor a GRID.

use crate::deck::DeckError;
use crate::deck::cards::ForceByGrids;
use crate::geometry::vec3::{cross, norm};

use super::Model;

impl Model {
    /// The unit direction of a FORCE1/FORCE2/MOMENT1/MOMENT2 in basic (see the module
    /// documentation); an error when a grid is missing or the direction has no length.
    pub fn direction_by_grids(&self, c: &ForceByGrids) -> Result<[f64; 3], String> {
        let x = |id: u32| {
            (self.grid_index.get(&id))
                .map(|&g| self.grids[g].xyz)
                .ok_or_else(|| format!("GRID {id} does not exist"))
        };
        let p: Vec<[f64; 3]> = c.grids.iter().map(|&g| x(g)).collect::<Result<_, _>>()?;
        let diff = |a: [f64; 3], b: [f64; 3]| [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
        let a = diff(p[0], p[1]);
        let (n, scale) = match p.len() {
            2 => (a, norm(a)),
            _ => {
                let b = diff(p[2], p[3]);
                (cross(a, b), norm(a) * norm(b))
            }
        };
        let length = norm(n);
        // relative to the grids' distances: coincident grids or parallel vectors
        if !(length > 1e-12 * scale) || scale == 0.0 {
            return Err(format!(
                "the direction from grids {:?} has no length (coincident grids or parallel vectors)",
                c.grids
            ));
        }
        Ok(n.map(|v| v / length))
    }
}

/// Every FORCE1/FORCE2/MOMENT1/MOMENT2 without a direction and every SLOAD on a point that is
/// neither a scalar point nor a grid, as deck errors at their cards. Missing grids are the reference check's.
pub fn check(model: &Model) -> Vec<DeckError> {
    let b = &model.bulk;
    let mut errors = Vec::new();
    for c in &b.forces_by_grids {
        let known = (c.grids.iter().chain([&c.grid])).all(|g| model.grid_index.contains_key(g));
        if let (true, Err(e)) = (known, model.direction_by_grids(c)) {
            errors.push(DeckError::at(&c.loc, e).on_card(format!("{} {}", c.card(), c.sid)));
        }
    }
    for c in &b.sload {
        for (k, &(point, _)) in c.loads.iter().enumerate() {
            if !model.scalar_index.contains_key(&point) && !model.grid_index.contains_key(&point) {
                let what = format!(
                    "S{} = {point} does not exist (no SPOINT or GRID {point})",
                    k + 1
                );
                errors.push(DeckError::at(&c.loc, what).on_card(format!("SLOAD {}", c.sid)));
            }
        }
    }
    errors
}
