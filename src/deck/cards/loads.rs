//! Static loads: `FORCE`, `MOMENT`, `GRAV`, `LOAD`.

use crate::card_values::ForceKind;
use crate::deck::error::{DeckError, Loc};
use crate::deck::fields::RawCard;
use crate::deck::reader::FieldReader;

/// `FORCE` / `MOMENT` — concentrated load at a grid: F · (N1, N2, N3) in system CID.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | SID | int > 0 | required | load set id |
/// | 3 | G | int > 0 | required | grid |
/// | 4 | CID | int ≥ 0 | 0 | system of the direction |
/// | 5 | F / M | real | 0.0 | scale factor |
/// | 6–8 | N1 N2 N3 | real | 0.0 | direction (need not be unit) |
#[derive(Debug, Clone, PartialEq)]
pub struct Force {
    pub kind: ForceKind,
    pub sid: u32,
    pub grid: u32,
    pub cid: u32,
    pub scale: f64,
    pub direction: [f64; 3],
    pub loc: Loc,
}

impl Force {
    /// Read a `FORCE` or `MOMENT` card.
    pub fn from_card(card: &RawCard, kind: ForceKind) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let sid = f.id(1, "SID");
        f.set_id(sid);
        let grid = f.id(2, "G");
        let cid = f.id0_or(3, "CID", 0);
        let scale = f.real_or(4, if kind == ForceKind::Force { "F" } else { "M" }, 0.0);
        let direction = [
            f.real_or(5, "N1", 0.0),
            f.real_or(6, "N2", 0.0),
            f.real_or(7, "N3", 0.0),
        ];
        let loc = f.loc();
        f.finish(7)?;
        Ok(Force {
            kind,
            sid,
            grid,
            cid,
            scale,
            direction,
            loc,
        })
    }
}

/// `GRAV` — acceleration load: A · (N1, N2, N3) in system CID.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | SID | int > 0 | required | load set id |
/// | 3 | CID | int ≥ 0 | 0 | system of the direction |
/// | 4 | A | real | required | acceleration magnitude |
/// | 5–7 | N1 N2 N3 | real | 0.0 | direction (not all zero) |
/// | 8 | MB | int | 0 | 0 = CID in the basic system (only 0 supported) |
#[derive(Debug, Clone, PartialEq)]
pub struct Grav {
    pub sid: u32,
    pub cid: u32,
    pub a: f64,
    pub direction: [f64; 3],
    pub loc: Loc,
}

impl Grav {
    /// Read a `GRAV` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let sid = f.id(1, "SID");
        f.set_id(sid);
        let cid = f.id0_or(2, "CID", 0);
        let a = f.real(3, "A");
        let direction = [
            f.real_or(4, "N1", 0.0),
            f.real_or(5, "N2", 0.0),
            f.real_or(6, "N3", 0.0),
        ];
        if direction == [0.0; 3] {
            f.error(4, "N1", "the direction vector is zero");
        }
        let mb = f.int_or(7, "MB", 0);
        if mb != 0 {
            f.error(7, "MB", "only MB = 0 (main bulk data) is supported");
        }
        let loc = f.loc();
        f.finish(7)?;
        Ok(Grav {
            sid,
            cid,
            a,
            direction,
            loc,
        })
    }
}

/// A combination card read by [`combination`]: set id, overall scale, (scale, set id) terms and
/// the card's location.
pub(crate) type Combination = (u32, f64, Vec<(f64, u32)>, Loc);

/// Read `SID S S1 L1 S2 L2 …` combination cards (`LOAD`, `DLOAD`).
pub(crate) fn combination(card: &RawCard) -> Result<Combination, Vec<DeckError>> {
    let mut f = FieldReader::new(card);
    let sid = f.id(1, "SID");
    f.set_id(sid);
    let scale = f.real(2, "S");
    let mut terms = Vec::new();
    let len = f.len();
    let mut i = 3;
    while i <= len {
        if f.value(i).is_blank() && f.value(i + 1).is_blank() {
            i += 2;
            continue;
        }
        let k = terms.len() + 1;
        let s = f.real(i, &format!("S{k}"));
        let l = f.id(i + 1, &format!("L{k}"));
        terms.push((s, l));
        i += 2;
    }
    if terms.is_empty() {
        f.card_error("no (Si, Li) pair given");
    }
    let loc = f.loc();
    f.finish(len.max(2))?;
    Ok((sid, scale, terms, loc))
}

/// `LOAD` — linear combination of static load sets: S · Σ Si · (set Li).
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | SID | int > 0 | required | new load set id |
/// | 3 | S | real | required | overall scale |
/// | 4, 5, … | S1 L1 S2 L2 … | real, int > 0 | ≥ 1 pair | scale and FORCE/MOMENT/GRAV set id |
#[derive(Debug, Clone, PartialEq)]
pub struct Load {
    pub sid: u32,
    pub scale: f64,
    pub terms: Vec<(f64, u32)>,
    pub loc: Loc,
}

impl Load {
    /// Read a `LOAD` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let (sid, scale, terms, loc) = combination(card)?;
        Ok(Load {
            sid,
            scale,
            terms,
            loc,
        })
    }
}
