//! `PARAM` — named solution parameters. Which names paraflex uses, and their checks, is the
//! model's business ([`crate::model`]); here a PARAM is a name and a value.

use crate::deck::error::{DeckError, Loc};
use crate::deck::fields::RawCard;
use crate::deck::reader::FieldReader;
use crate::deck::value::Value;

/// The value of a `PARAM`.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub enum ParamValue {
    Int(i64),
    Real(f64),
    Text(String),
    /// Two reals (Nastran complex parameters).
    Complex(f64, f64),
}

/// `PARAM` — a named parameter.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | N | name | required | parameter name |
/// | 3 | V1 | int, real or name | required | value |
/// | 4 | V2 | real | blank | imaginary part for complex parameters |
#[derive(Debug, Clone, PartialEq)]
pub struct Param {
    pub name: String,
    pub value: ParamValue,
    pub loc: Loc,
}

impl Param {
    /// Read a `PARAM` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let name = f.text(1, "N");
        f.set_id(&name);
        let value = match (f.value(2), f.value(3)) {
            (Value::Real(a), Value::Real(b)) => ParamValue::Complex(*a, *b),
            (Value::Int(i), _) => ParamValue::Int(*i),
            (Value::Real(r), _) => ParamValue::Real(*r),
            (Value::Text(t), _) | (Value::Quoted(t), _) => ParamValue::Text(t.to_ascii_uppercase()),
            _ => {
                let found = f.value(2).describe();
                f.error(2, "V1", format!("expected a value, found {found}"));
                ParamValue::Int(0)
            }
        };
        let loc = f.loc();
        f.finish(3)?;
        Ok(Param { name, value, loc })
    }
}
