//! Design variables: `DESVAR`, `DDVAL` (used by `SOL OPTIMIZE`).

use crate::deck::error::{DeckError, Loc};
use crate::deck::fields::RawCard;
use crate::deck::reader::FieldReader;

/// `DESVAR` — design variable.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | ID | int > 0 | required | id |
/// | 3 | LABEL | name | required | label |
/// | 4 | XINIT | real | required | initial value |
/// | 5 | XLB | real | −1.0E20 | lower bound |
/// | 6 | XUB | real | 1.0E20 | upper bound |
/// | 7 | DELXV | real | blank | move limit (kept) |
/// | 8 | DDVAL | int > 0 | blank | DDVAL id of allowed discrete values |
#[derive(Debug, Clone, PartialEq)]
pub struct Desvar {
    pub id: u32,
    pub label: String,
    pub xinit: f64,
    pub xlb: f64,
    pub xub: f64,
    pub delxv: Option<f64>,
    pub ddval: Option<u32>,
    pub loc: Loc,
}

impl Desvar {
    /// Read a `DESVAR` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let id = f.id(1, "ID");
        f.set_id(id);
        let label = f.text(2, "LABEL");
        let xinit = f.real(3, "XINIT");
        let xlb = f.real_or(4, "XLB", -1.0e20);
        let xub = f.real_or(5, "XUB", 1.0e20);
        if xlb > xub {
            f.error(
                4,
                "XLB",
                format!("XLB = {xlb:e} is greater than XUB = {xub:e}"),
            );
        }
        let delxv = f.opt_real(6, "DELXV");
        let ddval = f.opt_id(7, "DDVAL");
        if let (Some(_), Some(set)) = (delxv, ddval) {
            f.error(
                6,
                "DELXV",
                format!(
                    "a move limit DELXV for a discrete variable (DDVAL = {set}): leave DELXV blank"
                ),
            );
        }
        let loc = f.loc();
        f.finish(7)?;
        Ok(Desvar {
            id,
            label,
            xinit,
            xlb,
            xub,
            delxv,
            ddval,
            loc,
        })
    }
}

/// `DDVAL` — discrete design values.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | ID | int > 0 | required | id |
/// | 3 … | DVAL1 DVAL2 … | real | ≥ 1 | allowed values (the `THRU … BY` form is not supported) |
#[derive(Debug, Clone, PartialEq)]
pub struct Ddval {
    pub id: u32,
    pub values: Vec<f64>,
    pub loc: Loc,
}

impl Ddval {
    /// Read a `DDVAL` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let id = f.id(1, "ID");
        f.set_id(id);
        let len = f.len();
        let values = f.real_list(2, "DVAL");
        if values.is_empty() {
            f.card_error("no value given");
        }
        let loc = f.loc();
        f.finish(len.max(1))?;
        Ok(Ddval { id, values, loc })
    }
}
