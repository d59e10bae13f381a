//! Temperatures and temperature-dependent material data: `TEMP`, `TEMPD`, `MATT1`.

use crate::deck::error::{DeckError, Loc};
use crate::deck::fields::RawCard;
use crate::deck::reader::FieldReader;

/// `MATT1` — temperature tables of a MAT1's properties.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | MID | int > 0 | required | the MAT1 it applies to |
/// | 3–7 | T(E) T(G) T(NU) T(RHO) T(A) | int > 0 | blank | TABLEM1–TABLEM4 ids of E, G, NU, RHO, A against temperature |
/// | 9 | T(GE) | int > 0 | blank | table of GE |
/// | cont. 2–4 | T(ST) T(SC) T(SS) | int > 0 | blank | tables of the stress limits |
///
/// The tables apply only at the temperatures of a material temperature set (Nastran's
/// `TEMPERATURE(MATERIAL)` / `TEMPERATURE(INITIAL)` / `TEMPERATURE(BOTH)`); paraflex evaluates
/// no table, so a deck selecting such a set with a MATT1 is refused and otherwise the MAT1's own
/// values apply, as in Nastran without one. The card and its table ids are checked.
#[derive(Debug, Clone, PartialEq)]
pub struct Matt1 {
    pub mid: u32,
    /// (field index, field name, table id) of every table given.
    pub tables: Vec<(usize, &'static str, u32)>,
    pub loc: Loc,
}

impl Matt1 {
    /// Read a `MATT1` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let mid = f.id(1, "MID");
        f.set_id(mid);
        let names = [
            (2, "T(E)"),
            (3, "T(G)"),
            (4, "T(NU)"),
            (5, "T(RHO)"),
            (6, "T(A)"),
            (8, "T(GE)"),
            (9, "T(ST)"),
            (10, "T(SC)"),
            (11, "T(SS)"),
        ];
        let tables = names
            .into_iter()
            .filter_map(|(i, name)| f.opt_id(i, name).map(|id| (i, name, id)))
            .collect();
        if !f.value(7).is_blank() {
            f.error(7, "blank", "field 8 of MATT1 must be blank");
        }
        let loc = f.loc();
        f.finish(11)?;
        Ok(Matt1 { mid, tables, loc })
    }
}

/// `TEMP` — grid temperatures of a temperature set.
///
/// The set is a thermal load when case control selects it by `TEMPERATURE(LOAD) = SID`.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | SID | int > 0 | required | temperature set |
/// | 3, 5, 7 | G1 G2 G3 | int > 0 | G1 required | grid |
/// | 4, 6, 8 | T1 T2 T3 | real | required with its grid | temperature of the grid |
#[derive(Debug, Clone, PartialEq)]
pub struct Temp {
    pub sid: u32,
    /// (grid id, temperature) of each pair given.
    pub values: Vec<(u32, f64)>,
    pub loc: Loc,
}

impl Temp {
    /// Read a `TEMP` card (one to three grids).
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let sid = f.id(1, "SID");
        f.set_id(sid);
        let mut values = Vec::new();
        for (k, first) in [2, 4, 6].into_iter().enumerate() {
            if k > 0 && f.value(first).is_blank() && f.value(first + 1).is_blank() {
                continue;
            }
            let grid = f.id(first, ["G1", "G2", "G3"][k]);
            let t = f.real(first + 1, ["T1", "T2", "T3"][k]);
            values.push((grid, t));
        }
        let loc = f.loc();
        f.finish(7)?;
        Ok(Temp { sid, values, loc })
    }
}

/// `TEMPD` — default temperatures of temperature sets.
///
/// Every grid without a `TEMP` in the set has the set's TEMPD temperature.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2, 4, 6, 8 | SID1 … SID4 | int > 0 | SID1 required | temperature set |
/// | 3, 5, 7, 9 | T1 … T4 | real | required with its set | default temperature of the set |
#[derive(Debug, Clone, PartialEq)]
pub struct Tempd {
    pub sid: u32,
    pub t: f64,
    pub loc: Loc,
}

impl Tempd {
    /// Read a `TEMPD` card (one to four sets).
    pub fn from_card(card: &RawCard) -> Result<Vec<Self>, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let loc = f.loc();
        let mut out = Vec::new();
        for k in 0..4 {
            let first = 1 + 2 * k;
            if k > 0 && f.value(first).is_blank() && f.value(first + 1).is_blank() {
                continue;
            }
            let sid = f.id(first, ["SID1", "SID2", "SID3", "SID4"][k]);
            let t = f.real(first + 1, ["T1", "T2", "T3", "T4"][k]);
            out.push(Tempd {
                sid,
                t,
                loc: loc.clone(),
            });
        }
        f.finish(8)?;
        Ok(out)
    }
}
