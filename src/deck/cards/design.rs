//! Design variables: `DESVAR`, `DDVAL` (used by `SOL OPTIMIZE`).

use crate::deck::error::{DeckError, Loc};
use crate::deck::fields::RawCard;
use crate::deck::reader::FieldReader;
use crate::deck::value::Value;

/// `DESVAR` — design variable.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | ID | int > 0 | required | id |
/// | 3 | LABEL | name | required | label |
/// | 4 | XINIT | real | required | initial value (where `MOOPT GRAD` starts; NSGA2 and GRID do not use it) |
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

/// Whether field `i` is the keyword `word`.
fn is_word(f: &FieldReader, i: usize, word: &str) -> bool {
    matches!(f.value(i), Value::Text(t) if t.eq_ignore_ascii_case(word))
}

/// Most values a `THRU … BY` range may generate (a typo such as BY 1.E-9 is an error, not a
/// billion designs).
const MAX_RANGE_VALUES: f64 = 10_000.0;

/// The values of a DDVAL's fields 3 … `len`: single reals and `V1 THRU V2 BY INC` ranges.
fn values(f: &mut FieldReader, len: usize) -> Vec<f64> {
    let mut out = Vec::new();
    let mut i = 2;
    while i <= len {
        if f.value(i).is_blank() {
            i += 1;
            continue;
        }
        let first = f.real(i, "DVAL");
        if !is_word(f, i + 1, "THRU") {
            out.push(first);
            i += 1;
            continue;
        }
        let last = f.real(i + 2, "DVAL");
        if !is_word(f, i + 3, "BY") {
            f.error(
                i + 3,
                "BY",
                "a THRU range needs BY and its increment: V1 THRU V2 BY INC",
            );
            return out;
        }
        let step = f.real(i + 4, "INC");
        let count = (last - first) / step;
        if !(step > 0.0) || last < first || count > MAX_RANGE_VALUES {
            f.error(
                i + 4,
                "INC",
                format!(
                    "{first:e} THRU {last:e} BY {step:e}: expected V2 ≥ V1 and an increment > 0 giving at most {MAX_RANGE_VALUES} values"
                ),
            );
            return out;
        }
        let steps = (count + 1e-6).floor() as usize;
        out.extend((0..=steps).map(|k| first + k as f64 * step));
        i += 5;
    }
    out
}

/// `DDVAL` — discrete design values.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | ID | int > 0 | required | id |
/// | 3 … | DVAL1 DVAL2 … | real | ≥ 1 | allowed values; `V1 THRU V2 BY INC` gives V1, V1 + INC, … up to V2 (V2 included when the steps reach it to within 10⁻⁶ INC), and may follow or precede single values |
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
        let values = values(&mut f, len);
        if values.is_empty() {
            f.card_error("no value given");
        }
        let loc = f.loc();
        f.finish(len.max(1))?;
        Ok(Ddval { id, values, loc })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    use crate::deck::fields::card_from_line as card;

    #[test]
    fn ddval_ranges_expand_between_single_values() {
        let d = Ddval::from_card(&card("DDVAL,3,1.,6.,THRU,12.,BY,2.,20.")).unwrap();
        assert_eq!(d.values, vec![1.0, 6.0, 8.0, 10.0, 12.0, 20.0]);
        let d = Ddval::from_card(&card("DDVAL,3,0.,THRU,0.3,BY,0.1")).unwrap();
        assert_eq!(d.values.len(), 4, "{:?}", d.values);
        let e = Ddval::from_card(&card("DDVAL,3,6.,THRU,12.")).unwrap_err();
        assert!(e[0].to_string().contains("needs BY"), "{}", e[0]);
        let e = Ddval::from_card(&card("DDVAL,3,6.,THRU,12.,BY,-2.")).unwrap_err();
        assert!(e[0].to_string().contains("increment > 0"), "{}", e[0]);
    }
}
