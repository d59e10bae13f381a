//! Lexing the content of one field into a typed [`Value`].
//!
//! Nastran fields are self-typed: an integer has no decimal point, a real has a decimal point or
//! an exponent (with the Nastran shorthands `1.-3` = 1e-3, `7.+10` = 7e10 and `1.D-3`), a
//! character field starts with a letter. The small nom parsers here each recognise one of these
//! forms; [`lex`] tries them in turn. Something that is none of them (e.g. `1.2.3`, `12AB`, an
//! integer that overflows) becomes [`Value::Invalid`] with the reason, and the card that reads the
//! field reports it with its position and the type it expected.

use nom::branch::alt;
use nom::bytes::complete::{tag, take_while, take_while1};
use nom::character::complete::{digit0, digit1, one_of};
use nom::combinator::{all_consuming, opt};
use nom::sequence::pair;
use nom::{IResult, Parser};

/// The lexical content of one field.
#[derive(Debug, Clone, PartialEq)]
pub enum Value {
    /// An empty field.
    Blank,
    /// An integer (no decimal point).
    Int(i64),
    /// A real number.
    Real(f64),
    /// A character value (starts with a letter), kept as written; compare case-insensitively.
    Text(Box<str>),
    /// A quoted string (`'path/to/file.csv'`), case preserved, quotes removed.
    Quoted(Box<str>),
    /// Text that is not a valid field value, with the reason.
    Invalid {
        text: Box<str>,
        reason: &'static str,
    },
}

impl Value {
    /// A short description of the value for error messages: `integer 3`, `real 1.5`, `'ABC'`.
    pub fn describe(&self) -> String {
        match self {
            Value::Blank => "a blank field".to_string(),
            Value::Int(i) => format!("integer {i}"),
            Value::Real(r) => format!("real {r:e}"),
            Value::Text(t) => format!("'{t}'"),
            Value::Quoted(t) => format!("quoted string '{t}'"),
            Value::Invalid { text, reason } => format!("'{text}' ({reason})"),
        }
    }

    /// True for a blank field.
    pub fn is_blank(&self) -> bool {
        matches!(self, Value::Blank)
    }
}

/// The text a parser consumed. (Used instead of `nom::combinator::recognize`, which in nom
/// 8.0.0 returns a short slice when a tuple parser ends in `digit0` at the end of input.)
fn spanned<'a, O>(
    mut parser: impl Parser<&'a str, Output = O, Error = nom::error::Error<&'a str>>,
) -> impl Parser<&'a str, Output = &'a str, Error = nom::error::Error<&'a str>> {
    move |input: &'a str| {
        let (rest, _) = parser.parse(input)?;
        Ok((rest, &input[..input.len() - rest.len()]))
    }
}

fn sign(input: &str) -> IResult<&str, Option<char>> {
    opt(one_of("+-")).parse(input)
}

/// `[+-]digits`
fn integer(input: &str) -> IResult<&str, &str> {
    spanned(pair(sign, digit1)).parse(input)
}

/// Mantissa with a decimal point: `1.`, `1.5`, `.5` (with optional sign).
fn mantissa_with_point(input: &str) -> IResult<&str, &str> {
    spanned((
        sign,
        alt((
            spanned((digit1, tag("."), digit0)),
            spanned((tag("."), digit1)),
        )),
    ))
    .parse(input)
}

/// Exponent: `E±n`, `D±n` or the Nastran shorthand `±n` directly after the mantissa.
fn exponent(input: &str) -> IResult<&str, &str> {
    alt((
        spanned((one_of("eEdD"), sign, digit1)),
        spanned((one_of("+-"), digit1)),
    ))
    .parse(input)
}

/// A real: mantissa with a point and optional exponent, or an integer mantissa with an E/D
/// exponent (`1E3`).
fn real(input: &str) -> IResult<&str, (&str, Option<&str>)> {
    alt((
        pair(mantissa_with_point, opt(exponent)),
        pair(integer, opt(spanned((one_of("eEdD"), sign, digit1)))),
    ))
    .parse(input)
}

/// A character value: a letter followed by letters, digits or a few punctuation characters.
fn text(input: &str) -> IResult<&str, &str> {
    spanned(pair(
        take_while1(|c: char| c.is_ascii_alphabetic()),
        take_while(|c: char| c.is_ascii_alphanumeric() || "_-.+*/()#@".contains(c)),
    ))
    .parse(input)
}

fn real_value(mantissa: &str, exponent: Option<&str>) -> Option<f64> {
    let mut s = String::with_capacity(mantissa.len() + 6);
    s.push_str(mantissa);
    if let Some(e) = exponent {
        s.push('e');
        s.push_str(e.trim_start_matches(['e', 'E', 'd', 'D']));
    }
    s.parse::<f64>().ok().filter(|v| v.is_finite())
}

/// Lex one field (already trimmed of surrounding blanks).
pub fn lex(field: &str) -> Value {
    let field = field.trim();
    if field.is_empty() {
        return Value::Blank;
    }
    if let Some(inner) = field.strip_prefix('\'') {
        return match inner.strip_suffix('\'') {
            Some(s) => Value::Quoted(s.into()),
            None => Value::Invalid {
                text: field.into(),
                reason: "unterminated quoted string",
            },
        };
    }
    if let Ok((_, i)) = all_consuming(integer).parse(field) {
        return match i.parse::<i64>() {
            Ok(v) => Value::Int(v),
            Err(_) => Value::Invalid {
                text: field.into(),
                reason: "integer out of range",
            },
        };
    }
    if let Ok((_, (m, e))) = all_consuming(real).parse(field) {
        return match real_value(m, e) {
            Some(v) => Value::Real(v),
            None => Value::Invalid {
                text: field.into(),
                reason: "real number out of range",
            },
        };
    }
    if all_consuming(text).parse(field).is_ok() {
        return Value::Text(field.into());
    }
    Value::Invalid {
        text: field.into(),
        reason: "not an integer, a real or a name",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn integers() {
        assert_eq!(lex("12"), Value::Int(12));
        assert_eq!(lex(" -7 "), Value::Int(-7));
        assert_eq!(lex("+3"), Value::Int(3));
        assert!(matches!(
            lex("99999999999999999999999"),
            Value::Invalid { .. }
        ));
    }

    #[test]
    fn reals_with_nastran_shorthand() {
        assert_eq!(lex("1."), Value::Real(1.0));
        assert_eq!(lex(".5"), Value::Real(0.5));
        assert_eq!(lex("-.5"), Value::Real(-0.5));
        assert_eq!(lex("1.-3"), Value::Real(1e-3));
        assert_eq!(lex("7.+10"), Value::Real(7e10));
        assert_eq!(lex("1.D-3"), Value::Real(1e-3));
        assert_eq!(lex("1.5d+2"), Value::Real(150.0));
        assert_eq!(lex("2.5E-1"), Value::Real(0.25));
        assert_eq!(lex("1E3"), Value::Real(1000.0));
        assert_eq!(lex("-1.234+5"), Value::Real(-1.234e5));
    }

    #[test]
    fn reals_out_of_range_are_invalid() {
        assert!(matches!(
            lex("1.+999"),
            Value::Invalid {
                reason: "real number out of range",
                ..
            }
        ));
    }

    #[test]
    fn names_and_quoted_strings() {
        assert_eq!(lex("ALL"), Value::Text("ALL".into()));
        assert_eq!(lex("thru"), Value::Text("thru".into()));
        assert_eq!(lex("'Data/x.csv'"), Value::Quoted("Data/x.csv".into()));
        assert!(matches!(lex("'open"), Value::Invalid { .. }));
    }

    #[test]
    fn garbage_is_invalid() {
        for bad in ["1.2.3", "12AB", "1.e", "--1", "1..", "#"] {
            assert!(
                matches!(lex(bad), Value::Invalid { .. }),
                "{bad} should be invalid, got {:?}",
                lex(bad)
            );
        }
    }

    #[test]
    fn nan_and_inf_are_names_not_numbers() {
        assert_eq!(lex("NaN"), Value::Text("NaN".into()));
        assert_eq!(lex("inf"), Value::Text("inf".into()));
    }

    #[test]
    fn blank() {
        assert_eq!(lex("        "), Value::Blank);
    }
}
