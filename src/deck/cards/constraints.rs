//! Constraints and DOF sets: `SPC`, `SPC1`, `SPCADD`, `ASET1`.

use crate::card_values::Dofs;
use crate::deck::error::{DeckError, Loc};
use crate::deck::fields::RawCard;
use crate::deck::reader::FieldReader;

/// `SPC` — single-point constraint with an enforced value (one entry per grid on the card).
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | SID | int > 0 | required | constraint set id |
/// | 3, 4, 5 | G1 C1 D1 | int, components, real | G1 C1 required; D1 0.0 | grid, components, enforced value |
/// | 6, 7, 8 | G2 C2 D2 | | blank | an optional second grid |
#[derive(Debug, Clone, PartialEq)]
pub struct Spc {
    pub sid: u32,
    pub grid: u32,
    pub components: Dofs,
    pub value: f64,
    pub loc: Loc,
}

impl Spc {
    /// Read an `SPC` card (one or two constraints).
    pub fn from_card(card: &RawCard) -> Result<Vec<Self>, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let sid = f.id(1, "SID");
        f.set_id(sid);
        let loc = f.loc();
        let out = f
            .grid_component_values(["G", "C", "D"], Some(0.0))
            .into_iter()
            .map(|(grid, components, value)| Spc {
                sid,
                grid,
                components,
                value,
                loc: loc.clone(),
            })
            .collect();
        f.finish(7)?;
        Ok(out)
    }
}

/// `SPC1` — the same components constrained to zero at a list of grids.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | SID | int > 0 | required | constraint set id |
/// | 3 | C | components | required | components |
/// | 4 … | G1 G2 … | int > 0 (`THRU` allowed) | ≥ 1 required | grids |
#[derive(Debug, Clone, PartialEq)]
pub struct Spc1 {
    pub sid: u32,
    pub components: Dofs,
    pub grids: Vec<u32>,
    pub loc: Loc,
}

impl Spc1 {
    /// Read an `SPC1` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let sid = f.id(1, "SID");
        f.set_id(sid);
        let components = f.dofs(2, "C");
        if components.is_empty() {
            f.error(2, "C", "expected the constrained components, e.g. 123");
        }
        let grids = f.id_list(3, "G");
        if grids.is_empty() {
            f.card_error("no grid given");
        }
        let loc = f.loc();
        let len = f.len();
        f.finish(len)?;
        Ok(Spc1 {
            sid,
            components,
            grids,
            loc,
        })
    }
}

/// `SPCADD` — union of constraint sets.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | SID | int > 0 | required | new set id |
/// | 3 … | S1 S2 … | int > 0 | ≥ 1 required | SPC/SPC1 set ids |
#[derive(Debug, Clone, PartialEq)]
pub struct Spcadd {
    pub sid: u32,
    pub sets: Vec<u32>,
    pub loc: Loc,
}

impl Spcadd {
    /// Read an `SPCADD` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let sid = f.id(1, "SID");
        f.set_id(sid);
        let sets = f.id_list(2, "S");
        if sets.is_empty() {
            f.card_error("no set id given");
        }
        let loc = f.loc();
        let len = f.len();
        f.finish(len)?;
        Ok(Spcadd { sid, sets, loc })
    }
}

/// `ASET1` — DOFs of the analysis (boundary) set, in Nastran's layout. All `ASET1` cards of a
/// deck together form its a-set; paraflex uses it as the boundary DOFs of a `PMOR` (static modes,
/// pROM inputs).
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | C | components | required | components |
/// | 3 … | G1 G2 … | int > 0 (`THRU` allowed) | ≥ 1 required | grids |
#[derive(Debug, Clone, PartialEq)]
pub struct Aset1 {
    pub components: Dofs,
    pub grids: Vec<u32>,
    pub loc: Loc,
}

impl Aset1 {
    /// Read an `ASET1` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let components = f.dofs(1, "C");
        if components.is_empty() {
            f.error(1, "C", "expected components, e.g. 123456");
        }
        let grids = f.id_list(2, "G");
        if grids.is_empty() {
            f.card_error("no grid given");
        }
        let loc = f.loc();
        let len = f.len();
        f.finish(len)?;
        Ok(Aset1 {
            components,
            grids,
            loc,
        })
    }
}
