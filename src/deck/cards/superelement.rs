//! Part superelement cards of the main bulk data section (MSC Quick Reference: `SEBULK`,
//! `SECONCT`, `SELOC`), read for [`crate::model::parts`], which assembles the parts
//! (`BEGIN SUPER = n` sections) into one model, and the reduction-set cards (`ASET`, `QSET`,
//! `QSET1`) that paraflex reads and does not honour.

use crate::card_values::Dofs;
use crate::deck::error::{DeckError, Loc};
use crate::deck::fields::RawCard;
use crate::deck::reader::FieldReader;

/// How a part's boundary points are found (`SEBULK` METHOD).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SeMethod {
    /// Grids coincident (within TOL) with a grid of another part or of the residual connect.
    Auto,
    /// Only the pairs listed by `SECONCT` connect.
    Manual,
}

/// `SEBULK` — how part superelement SEID connects.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | SEID | int > 0 | required | part superelement |
/// | 3 | TYPE | `PRIMARY` | required | paraflex reads primary parts; `REPEAT`, `MIRROR`, `COLLCTR`, `EXTERNAL`, `EXTOP2`, `EXTOP4`, `FRFOP2` are refused at this field |
/// | 4 | RSEID | int ≥ 0 | 0 | the primary of a repeated or mirrored part (blank for `PRIMARY`) |
/// | 5 | METHOD | `AUTO`/`MANUAL` | `AUTO` | boundary search: by coincident location, or only the `SECONCT` pairs |
/// | 6 | TOL | real ≥ 0 | 1.0E-5 | coincidence tolerance (a distance) of the `AUTO` search |
/// | 7 | LOC | `YES`/`NO` | `YES` | whether `SECONCT` pairs must be coincident |
/// | 8 | UNITNO | int | blank | unit of an external part's file (external parts are refused) |
#[derive(Debug, Clone)]
pub struct Sebulk {
    pub seid: u32,
    pub method: SeMethod,
    pub tol: f64,
    pub check_location: bool,
    pub loc: Loc,
}

/// The default coincidence tolerance of `SEBULK` and `SECONCT` (MSC Quick Reference).
pub const DEFAULT_SE_TOL: f64 = 1.0e-5;

impl Sebulk {
    /// Read a `SEBULK` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let seid = f.id(1, "SEID");
        f.set_id(seid);
        let kind = f.keyword(
            2,
            "TYPE",
            &[
                "PRIMARY", "REPEAT", "MIRROR", "COLLCTR", "EXTERNAL", "EXTOP2", "EXTOP4", "FRFOP2",
            ],
            None,
        );
        if kind != "PRIMARY" {
            f.error(
                2,
                "TYPE",
                format!(
                    "a {kind} superelement is not supported: paraflex assembles primary part superelements (BEGIN SUPER sections) only"
                ),
            );
        }
        let rseid = f.id0_or(3, "RSEID", 0);
        if rseid != 0 && kind == "PRIMARY" {
            f.error(
                3,
                "RSEID",
                "a PRIMARY superelement has no RSEID (leave it blank)",
            );
        }
        let method = f.choice(
            4,
            "METHOD",
            &[("AUTO", SeMethod::Auto), ("MANUAL", SeMethod::Manual)],
            Some(SeMethod::Auto),
        );
        let tol = f.real_or(5, "TOL", DEFAULT_SE_TOL);
        if tol < 0.0 {
            f.error(5, "TOL", format!("expected a real >= 0, found {tol:e}"));
        }
        let check_location = f.choice(6, "LOC", &[("YES", true), ("NO", false)], Some(true));
        f.opt_int(7, "UNITNO");
        let loc = f.loc();
        f.finish(7)?;
        Ok(Sebulk {
            seid,
            method,
            tol,
            check_location,
            loc,
        })
    }
}

/// `SECONCT` — grid pairs that connect part SEIDA to part SEIDB (0 = the residual).
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | SEIDA | int ≥ 0 | required | first superelement |
/// | 3 | SEIDB | int ≥ 0 | required | second superelement, ≠ SEIDA |
/// | 4 | TOL | real ≥ 0 | 1.0E-5 | how far apart a pair may be when LOC = YES |
/// | 5 | LOC | `YES`/`NO` | `YES` | whether each pair must be coincident |
/// | 10 … | GIDAi GIDBi | int > 0 | – | pairs: grid GIDAi of SEIDA connects to grid GIDBi of SEIDB; or `GIDA1 THRU GIDA2 GIDB1 THRU GIDB2`, two equally long ranges |
#[derive(Debug, Clone)]
pub struct Seconct {
    pub seid_a: u32,
    pub seid_b: u32,
    pub tol: f64,
    pub check_location: bool,
    pub pairs: Vec<(u32, u32)>,
    pub loc: Loc,
}

impl Seconct {
    /// Read a `SECONCT` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let seid_a = f.id0_or(1, "SEIDA", 0);
        f.set_id(seid_a);
        if f.value(1).is_blank() {
            f.error(1, "SEIDA", "expected a superelement id >= 0, found a blank");
        }
        let seid_b = f.id0_or(2, "SEIDB", 0);
        if f.value(2).is_blank() {
            f.error(2, "SEIDB", "expected a superelement id >= 0, found a blank");
        } else if seid_b == seid_a {
            f.error(2, "SEIDB", format!("SEIDB equals SEIDA ({seid_a})"));
        }
        let tol = f.real_or(3, "TOL", DEFAULT_SE_TOL);
        if tol < 0.0 {
            f.error(3, "TOL", format!("expected a real >= 0, found {tol:e}"));
        }
        let check_location = f.choice(4, "LOC", &[("YES", true), ("NO", false)], Some(true));
        for i in 5..=8 {
            if !f.value(i).is_blank() {
                f.error(i, "blank", "expected a blank field");
            }
        }
        let pairs = grid_pairs(&mut f, 9);
        if pairs.is_empty() {
            f.card_error("no grid pair given (GIDA1 GIDB1 … on the continuation)");
        }
        let loc = f.loc();
        let len = f.len();
        f.finish(len)?;
        Ok(Seconct {
            seid_a,
            seid_b,
            tol,
            check_location,
            pairs,
            loc,
        })
    }
}

/// The pairs of a `SECONCT` from field `from` on: `A B` pairs or `A1 THRU A2 B1 THRU B2`.
fn grid_pairs(f: &mut FieldReader, from: usize) -> Vec<(u32, u32)> {
    let is_thru = |f: &FieldReader, i: usize| matches!(f.value(i), crate::deck::value::Value::Text(t) if t.eq_ignore_ascii_case("THRU"));
    let mut pairs = Vec::new();
    let end = f.len();
    let mut i = from;
    while i <= end {
        if is_thru(f, i + 1) {
            let a1 = f.id(i, "GIDA1");
            let a2 = f.id(i + 2, "GIDA2");
            let b1 = f.id(i + 3, "GIDB1");
            if !is_thru(f, i + 4) {
                f.error(
                    i + 4,
                    "THRU",
                    "expected THRU (GIDA1 THRU GIDA2 GIDB1 THRU GIDB2)",
                );
            }
            let b2 = f.id(i + 5, "GIDB2");
            if a2 < a1 || b2 < b1 || a2 - a1 != b2 - b1 {
                f.error(
                    i + 5,
                    "GIDB2",
                    format!("the ranges {a1} THRU {a2} and {b1} THRU {b2} differ in length"),
                );
            } else {
                pairs.extend((0..=a2 - a1).map(|k| (a1 + k, b1 + k)));
            }
            i += 6;
            continue;
        }
        if f.value(i).is_blank() && f.value(i + 1).is_blank() {
            i += 2;
            continue;
        }
        let a = f.id(i, "GIDA");
        let b = f.id(i + 1, "GIDB");
        pairs.push((a, b));
        i += 2;
    }
    pairs
}

/// `POINT` — a geometric point without DOF, read by `SELOC` only.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | ID | int > 0 | required | point id (shares GRID's id space in Nastran) |
/// | 3 | CP | int ≥ 0 | 0 | system of X1–X3 |
/// | 4–6 | X1–X3 | real | 0.0 | location |
#[derive(Debug, Clone)]
pub struct Point {
    pub id: u32,
    pub cp: u32,
    pub x: [f64; 3],
    pub loc: Loc,
}

impl Point {
    /// Read a `POINT` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let id = f.id(1, "ID");
        f.set_id(id);
        let cp = f.id0_or(2, "CP", 0);
        let x = [
            f.real_or(3, "X1", 0.0),
            f.real_or(4, "X2", 0.0),
            f.real_or(5, "X3", 0.0),
        ];
        let loc = f.loc();
        f.finish(5)?;
        Ok(Point { id, cp, x, loc })
    }
}

/// `SELOC` — moves part superelement SEID rigidly before it is connected.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | SEID | int > 0 | required | part superelement to move |
/// | 3–5 | PA1–PA3 | int > 0 | required | three non-collinear GRID or POINT ids of part SEID |
/// | 6–8 | PB1–PB3 | int > 0 | required | three GRID or POINT ids of the main bulk data that PA1–PA3 are moved onto |
///
/// The motion takes PA1 onto PB1, the line PA1–PA2 onto the line PB1–PB2 and the plane of
/// PA1–PA3 onto the plane of PB1–PB3.
#[derive(Debug, Clone)]
pub struct Seloc {
    pub seid: u32,
    pub pa: [u32; 3],
    pub pb: [u32; 3],
    pub loc: Loc,
}

impl Seloc {
    /// Read a `SELOC` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let seid = f.id(1, "SEID");
        f.set_id(seid);
        let pa = [f.id(2, "PA1"), f.id(3, "PA2"), f.id(4, "PA3")];
        let pb = [f.id(5, "PB1"), f.id(6, "PB2"), f.id(7, "PB3")];
        let loc = f.loc();
        f.finish(7)?;
        Ok(Seloc { seid, pa, pb, loc })
    }
}

/// `ASET`, `QSET`, `QSET1` (and `ASET1` in a part) — reduction sets: read, not honoured.
///
/// `ASET`/`QSET` hold (grid, components) pairs, `ASET1`/`QSET1` components then grids (`THRU`
/// allowed): the boundary and generalized-coordinate sets by which Nastran reduces a part or
/// the residual. paraflex solves unreduced: in a part they are read (grids
/// checked) and not honoured, with a warning; in the main bulk data likewise in SOL 101
/// (static condensation is exact), refused in the other solutions (Guyan reduction changes
/// their answer). A main-bulk `ASET1` keeps its own meaning (the a-set of `PMOR BSET`).
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2, 4, 6, 8 | IDi | int > 0 | – | `ASET`/`QSET`: grid |
/// | 3, 5, 7, 9 | Ci | components | blank | `ASET`/`QSET`: its components |
/// | 2 | C | components | blank | `QSET1`: components |
/// | 3 … | Gi | int > 0 (`THRU`) | – | `QSET1`: grids |
#[derive(Debug, Clone)]
pub struct ReductionSet {
    pub card: String,
    pub points: Vec<(u32, Dofs)>,
    pub loc: Loc,
}

impl ReductionSet {
    /// Read an `ASET` or `QSET` card: up to four (grid, components) pairs.
    pub fn pairs(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let mut points = Vec::new();
        let len = f.len();
        let mut i = 1;
        while i <= len {
            if !(f.value(i).is_blank() && f.value(i + 1).is_blank()) {
                let g = f.id(i, "ID");
                points.push((g, f.dofs(i + 1, "C")));
            }
            i += 2;
        }
        if points.is_empty() {
            f.card_error("no grid given");
        }
        let loc = f.loc();
        f.finish(len.max(1))?;
        Ok(ReductionSet {
            card: card.name.clone(),
            points,
            loc,
        })
    }

    /// Read an `ASET1` or `QSET1` card: components, then grids (`THRU` allowed).
    pub fn list(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let components = f.dofs(1, "C");
        let grids = f.id_list(2, "G");
        if grids.is_empty() {
            f.card_error("no grid given");
        }
        let loc = f.loc();
        let len = f.len();
        f.finish(len.max(1))?;
        Ok(ReductionSet {
            card: card.name.clone(),
            points: grids.into_iter().map(|g| (g, components)).collect(),
            loc,
        })
    }
}
