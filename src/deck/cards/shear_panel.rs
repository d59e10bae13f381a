//! The shear panel: element `CSHEAR` and property `PSHEAR`.

use crate::deck::error::{DeckError, Loc};
use crate::deck::fields::RawCard;
use crate::deck::reader::FieldReader;

/// `CSHEAR` — four-node shear panel (in-plane shear only, translations only).
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | EID | int > 0 | required | element id |
/// | 3 | PID | int > 0 | EID | PSHEAR id |
/// | 4–7 | G1–G4 | int > 0 | required | grids, in order around the panel |
#[derive(Debug, Clone, PartialEq)]
pub struct Cshear {
    pub id: u32,
    pub pid: u32,
    pub nodes: [u32; 4],
    pub loc: Loc,
}

impl Cshear {
    /// Read a `CSHEAR` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let id = f.id(1, "EID");
        f.set_id(id);
        let pid = f.opt_id(2, "PID").unwrap_or(id);
        let nodes = [f.id(3, "G1"), f.id(4, "G2"), f.id(5, "G3"), f.id(6, "G4")];
        let loc = f.loc();
        f.finish(6)?;
        Ok(Cshear {
            id,
            pid,
            nodes,
            loc,
        })
    }
}

/// `PSHEAR` — shear panel property.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | PID | int > 0 | required | property id |
/// | 3 | MID | int > 0 | required | MAT1 id (its G carries the shear, its RHO the mass) |
/// | 4 | T | real > 0 | required | thickness |
/// | 5 | NSM | real | 0.0 | non-structural mass per area |
/// | 6 | F1 | real | 0.0 | extensional effectiveness along edges 1–2 and 3–4: only 0 (none) is supported |
/// | 7 | F2 | real | 0.0 | extensional effectiveness along edges 2–3 and 1–4: only 0 (none) is supported |
#[derive(Debug, Clone, PartialEq)]
pub struct Pshear {
    pub id: u32,
    pub mid: u32,
    pub t: f64,
    pub nsm: f64,
    pub loc: Loc,
}

impl Pshear {
    /// Read a `PSHEAR` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let id = f.id(1, "PID");
        f.set_id(id);
        let mid = f.id(2, "MID");
        let t = f.positive_real(3, "T");
        let nsm = f.real_or(4, "NSM", 0.0);
        for (i, name) in [(5, "F1"), (6, "F2")] {
            let factor = f.real_or(i, name, 0.0);
            if factor != 0.0 {
                f.error(
                    i,
                    name,
                    format!(
                        "extensional effectiveness {name} = {factor:e} is not supported: paraflex's shear panel carries shear only (give 0 or blank, and model the edge members as rods)"
                    ),
                );
            }
        }
        let loc = f.loc();
        f.finish(6)?;
        Ok(Pshear {
            id,
            mid,
            t,
            nsm,
            loc,
        })
    }
}
