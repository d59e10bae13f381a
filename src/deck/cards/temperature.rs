//! Temperature-dependent material data: `MATT1`.

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
/// `TEMPERATURE(MATERIAL)` / `TEMPERATURE(INITIAL)`); paraflex reads no temperature set, so the
/// MAT1's own values apply, as in Nastran without one. The card and its table ids are checked.
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
