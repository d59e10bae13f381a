//! Typed access to the fields of a [`RawCard`], collecting every bad field of a card.
//!
//! Card constructors read their fields through a [`FieldReader`], like pyNastran's
//! `assign_type.integer(card, ifield, name)`: each accessor names the field, checks its type and
//! range, and on a problem records an error that says where (file:line), which card and id,
//! which field (number and name), what was found and what was expected — then returns a
//! placeholder so that the remaining fields are still checked. [`FieldReader::finish`] also
//! rejects non-blank fields past the card's layout (a field paraflex does not know could change
//! the physics, so it is never dropped silently).
//!
//! One bad field gives one error: a later error on the same field, or about the card as a whole
//! (a rule combining fields, such as MAT1's "at least one of E and G"), would only follow from
//! the placeholder and is not reported.

use super::error::{DeckError, Loc};
use super::fields::RawCard;
use super::value::Value;
use crate::card_values::Column;
use crate::card_values::Dofs;

/// Reads the fields of one card; see the module documentation.
pub struct FieldReader<'a> {
    card: &'a RawCard,
    label: String,
    errors: Vec<DeckError>,
    /// Fields with an error already reported.
    bad_fields: Vec<usize>,
}

const BLANK: Value = Value::Blank;

impl<'a> FieldReader<'a> {
    /// Start reading `card`.
    pub fn new(card: &'a RawCard) -> Self {
        FieldReader {
            card,
            label: card.name.clone(),
            errors: Vec::new(),
            bad_fields: Vec::new(),
        }
    }

    /// The card being read.
    pub fn card(&self) -> &'a RawCard {
        self.card
    }

    /// Position of the card's first line.
    pub fn loc(&self) -> Loc {
        self.card.loc.clone()
    }

    /// Name the card's id in later messages (`CQUAD4 101`).
    pub fn set_id(&mut self, id: impl std::fmt::Display) {
        self.label = format!("{} {id}", self.card.name);
    }

    /// The card label used in messages.
    pub fn label(&self) -> &str {
        &self.label
    }

    /// Raw value of flattened field `i` (1-based: 1 = Nastran field 2); blank past the end.
    pub fn value(&self, i: usize) -> &'a Value {
        if i == 0 {
            &BLANK
        } else {
            self.card.fields.get(i - 1).unwrap_or(&BLANK)
        }
    }

    /// Number of fields up to the last non-blank one.
    pub fn len(&self) -> usize {
        self.card
            .fields
            .iter()
            .rposition(|v| !v.is_blank())
            .map_or(0, |p| p + 1)
    }

    /// True when the card has no non-blank field.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Record an error on field `i`, unless the field already has one.
    pub fn error(&mut self, i: usize, name: &str, message: impl Into<String>) {
        if self.bad_fields.contains(&i) {
            return;
        }
        self.bad_fields.push(i);
        let mut e = DeckError::at(&self.card.loc_of(i), message).on_card(self.label.clone());
        e.field = Some(format!("{} ({name})", RawCard::field_label(i)));
        self.errors.push(e);
    }

    /// Record an error about the card as a whole, unless a field of the card already has one
    /// (the card-level rules read the fields, and a bad field reads as its placeholder).
    pub fn card_error(&mut self, message: impl Into<String>) {
        if !self.bad_fields.is_empty() {
            return;
        }
        self.errors
            .push(DeckError::at(&self.card.loc, message).on_card(self.label.clone()));
    }

    fn mismatch(&mut self, i: usize, name: &str, expected: &str) {
        let found = self.value(i).describe();
        self.error(i, name, format!("expected {expected}, found {found}"));
    }

    /// An optional integer.
    pub fn opt_int(&mut self, i: usize, name: &str) -> Option<i64> {
        match self.value(i) {
            Value::Blank => None,
            Value::Int(v) => Some(*v),
            _ => {
                self.mismatch(i, name, "an integer");
                None
            }
        }
    }

    /// A required integer.
    pub fn int(&mut self, i: usize, name: &str) -> i64 {
        if self.value(i).is_blank() {
            self.mismatch(i, name, "an integer");
            return 0;
        }
        self.opt_int(i, name).unwrap_or(0)
    }

    /// An integer with a default for a blank field.
    pub fn int_or(&mut self, i: usize, name: &str, default: i64) -> i64 {
        self.opt_int(i, name).unwrap_or(default)
    }

    fn check_id(&mut self, i: usize, name: &str, v: i64, allow_zero: bool) -> u32 {
        let expected = if allow_zero {
            "an id >= 0"
        } else {
            "an id > 0"
        };
        self.check_positive(i, name, v, allow_zero, expected)
    }

    /// `v` as a u32 in [0 or 1, u32::MAX / 2], else an error "expected {expected} …" and 0.
    fn check_positive(
        &mut self,
        i: usize,
        name: &str,
        v: i64,
        allow_zero: bool,
        expected: &str,
    ) -> u32 {
        let ok = if allow_zero { v >= 0 } else { v > 0 };
        if !ok || v > i64::from(u32::MAX / 2) {
            self.error(
                i,
                name,
                format!("expected {expected} (at most {}), found {v}", u32::MAX / 2),
            );
            return 0;
        }
        v as u32
    }

    /// A required count (number of modes, steps, samples …): an integer > 0.
    pub fn count(&mut self, i: usize, name: &str) -> u32 {
        if self.value(i).is_blank() {
            self.mismatch(i, name, "an integer > 0");
            return 0;
        }
        match self.opt_int(i, name) {
            Some(v) => self.check_positive(i, name, v, false, "an integer > 0"),
            None => 0,
        }
    }

    /// An optional count (blank → `None`): an integer > 0.
    pub fn opt_count(&mut self, i: usize, name: &str) -> Option<u32> {
        let v = self.opt_int(i, name)?;
        Some(self.check_positive(i, name, v, false, "an integer > 0"))
    }

    /// A required positive id.
    pub fn id(&mut self, i: usize, name: &str) -> u32 {
        if self.value(i).is_blank() {
            self.mismatch(i, name, "an id > 0");
            return 0;
        }
        match self.opt_int(i, name) {
            Some(v) => self.check_id(i, name, v, false),
            None => 0,
        }
    }

    /// An optional positive id (blank → `None`).
    pub fn opt_id(&mut self, i: usize, name: &str) -> Option<u32> {
        let v = self.opt_int(i, name)?;
        Some(self.check_id(i, name, v, false))
    }

    /// An id that may be 0 (e.g. a coordinate system), with a default for blank.
    pub fn id0_or(&mut self, i: usize, name: &str, default: u32) -> u32 {
        match self.opt_int(i, name) {
            Some(v) => self.check_id(i, name, v, true),
            None => default,
        }
    }

    /// An optional real.
    pub fn opt_real(&mut self, i: usize, name: &str) -> Option<f64> {
        match self.value(i) {
            Value::Blank => None,
            Value::Real(v) => Some(*v),
            Value::Int(_) => {
                self.mismatch(i, name, "a real (with a decimal point)");
                None
            }
            _ => {
                self.mismatch(i, name, "a real");
                None
            }
        }
    }

    /// A required real.
    pub fn real(&mut self, i: usize, name: &str) -> f64 {
        if self.value(i).is_blank() {
            self.mismatch(i, name, "a real");
            return 0.0;
        }
        self.opt_real(i, name).unwrap_or(0.0)
    }

    /// A real with a default for a blank field.
    pub fn real_or(&mut self, i: usize, name: &str, default: f64) -> f64 {
        self.opt_real(i, name).unwrap_or(default)
    }

    /// A real that must be strictly positive.
    pub fn positive_real(&mut self, i: usize, name: &str) -> f64 {
        let v = self.real(i, name);
        if v <= 0.0 && !self.value(i).is_blank() && matches!(self.value(i), Value::Real(_)) {
            self.error(i, name, format!("expected a real > 0, found {v:e}"));
        }
        v
    }

    /// An optional name (upper-cased).
    pub fn opt_text(&mut self, i: usize, name: &str) -> Option<String> {
        match self.value(i) {
            Value::Blank => None,
            Value::Text(t) => Some(t.to_ascii_uppercase()),
            _ => {
                self.mismatch(i, name, "a name");
                None
            }
        }
    }

    /// A required name (upper-cased).
    pub fn text(&mut self, i: usize, name: &str) -> String {
        if self.value(i).is_blank() {
            self.mismatch(i, name, "a name");
            return String::new();
        }
        self.opt_text(i, name).unwrap_or_default()
    }

    /// One of a fixed set of keywords; blank gives `default` (or an error when there is none).
    pub fn keyword(
        &mut self,
        i: usize,
        name: &str,
        allowed: &[&'static str],
        default: Option<&'static str>,
    ) -> &'static str {
        let fallback = default.unwrap_or(allowed[0]);
        match self.value(i) {
            Value::Blank => match default {
                Some(d) => d,
                None => {
                    self.mismatch(i, name, &format!("one of {}", allowed.join(", ")));
                    fallback
                }
            },
            Value::Text(t) => match allowed.iter().find(|k| k.eq_ignore_ascii_case(t)) {
                Some(k) => k,
                None => {
                    self.mismatch(i, name, &format!("one of {}", allowed.join(", ")));
                    fallback
                }
            },
            _ => {
                self.mismatch(i, name, &format!("one of {}", allowed.join(", ")));
                fallback
            }
        }
    }

    /// A keyword field read as the value it names in `choices` (name, value; case-insensitive),
    /// `default` when blank (required when `None`); an error lists the names.
    pub fn choice<T: Copy + PartialEq>(
        &mut self,
        i: usize,
        name: &str,
        choices: &[(&'static str, T)],
        default: Option<T>,
    ) -> T {
        let names: Vec<&'static str> = choices.iter().map(|(n, _)| *n).collect();
        let default_name =
            default.and_then(|d| choices.iter().find(|(_, v)| *v == d).map(|(n, _)| *n));
        let keyword = self.keyword(i, name, &names, default_name);
        choices
            .iter()
            .find(|(n, _)| *n == keyword)
            .map_or(choices[0].1, |(_, v)| *v)
    }

    /// A quoted string (a file path); an unquoted name is accepted as written.
    pub fn path(&mut self, i: usize, name: &str) -> String {
        match self.value(i) {
            Value::Quoted(s) => s.to_string(),
            Value::Text(s) => s.to_string(),
            _ => {
                self.mismatch(i, name, "a quoted file name such as 'data.csv'");
                String::new()
            }
        }
    }

    /// A column reference: 1-based index or header name.
    pub fn column(&mut self, i: usize, name: &str) -> Column {
        match self.value(i) {
            Value::Int(v) if *v >= 1 => Column::Index(*v as usize),
            Value::Text(s) | Value::Quoted(s) => Column::Name(s.to_string()),
            _ => {
                self.mismatch(i, name, "a 1-based column index or a column name");
                Column::Index(1)
            }
        }
    }

    /// A component code (`123456`); blank gives [`Dofs::NONE`].
    pub fn dofs(&mut self, i: usize, name: &str) -> Dofs {
        match self.opt_int(i, name) {
            None => Dofs::NONE,
            Some(code) => Dofs::parse(code).unwrap_or_else(|| {
                self.error(
                    i,
                    name,
                    format!("expected a component code of distinct digits 1-6, found {code}"),
                );
                Dofs::NONE
            }),
        }
    }

    /// A list of ids starting at field `from` to the end of the card, with `id1 THRU id2` ranges
    /// expanded. Blank fields are skipped.
    pub fn id_list(&mut self, from: usize, name: &str) -> Vec<u32> {
        let end = self.len();
        self.id_list_until(from, end, name)
    }

    /// [`id_list`](Self::id_list) over fields `from..=end` only.
    pub fn id_list_until(&mut self, from: usize, end: usize, name: &str) -> Vec<u32> {
        let mut ids = Vec::new();
        let mut i = from;
        while i <= end {
            let is_thru = matches!(self.value(i), Value::Text(t) if t.eq_ignore_ascii_case("THRU"));
            if is_thru {
                let (Some(&lo), Some(hi)) = (ids.last(), self.opt_id(i + 1, name)) else {
                    self.error(i, name, "THRU needs an id before and after it");
                    i += 2;
                    continue;
                };
                if let Err(message) = expand_thru(&mut ids, lo, hi) {
                    self.error(i + 1, name, message);
                }
                i += 2;
                continue;
            }
            if let Some(id) = self.opt_id(i, name) {
                ids.push(id);
            }
            i += 1;
        }
        ids
    }

    /// The one or two (grid, components, value) triples of `SPC`/`DAREA`-style cards, at fields
    /// 3–5 and 6–8. `names` are the field names; a blank value is `default`, or an error when
    /// `default` is `None`.
    pub fn grid_component_values(
        &mut self,
        names: [&str; 3],
        default: Option<f64>,
    ) -> Vec<(u32, Dofs, f64)> {
        let mut out = Vec::new();
        for first in [2, 5] {
            if first == 5 && (5..=7).all(|i| self.value(i).is_blank()) {
                break;
            }
            let grid = self.id(first, names[0]);
            let components = self.dofs(first + 1, names[1]);
            let value = match default {
                Some(d) => self.real_or(first + 2, names[2], d),
                None => self.real(first + 2, names[2]),
            };
            out.push((grid, components, value));
        }
        out
    }

    /// Every non-blank field from `from` to the end of the card, read as reals.
    pub fn real_list(&mut self, from: usize, name: &str) -> Vec<f64> {
        let end = self.len();
        let mut out = Vec::new();
        for i in from..=end {
            if !self.value(i).is_blank() {
                out.push(self.real(i, name));
            }
        }
        out
    }

    /// Finish reading: fields past `last` (1-based) must be blank. Returns the errors found.
    pub fn finish(mut self, last: usize) -> Result<(), Vec<DeckError>> {
        let len = self.len();
        if len > last {
            let found = self.value(len).describe();
            let e =
                format!("unexpected field: the card has at most {last} data fields, found {found}");
            self.error(len, "extra", e);
        }
        if self.errors.is_empty() {
            Ok(())
        } else {
            Err(self.errors)
        }
    }

    /// Errors recorded so far (for cards that finish without a fixed layout).
    pub fn into_errors(self) -> Vec<DeckError> {
        self.errors
    }
}

/// The most ids one list (a card's or a case-control SET's, `THRU` ranges expanded) may hold:
/// 10 million, 40 MB of ids — far above any real model's set, small enough that a typo such as
/// `1 THRU 4000000000` is an error instead of exhausting memory.
pub const MAX_LISTED_IDS: usize = 10_000_000;

/// Append `lo+1 ..= hi` to `ids` (which ends with `lo`), refusing decreasing ranges and lists
/// longer than [`MAX_LISTED_IDS`].
pub fn expand_thru(ids: &mut Vec<u32>, lo: u32, hi: u32) -> Result<(), String> {
    if hi < lo {
        return Err(format!("THRU range {lo} THRU {hi} is decreasing"));
    }
    let total = ids.len() as u64 + u64::from(hi - lo);
    if total > MAX_LISTED_IDS as u64 {
        return Err(format!(
            "THRU range {lo} THRU {hi} makes the list longer than {MAX_LISTED_IDS} ids"
        ));
    }
    ids.extend((lo..=hi).skip(1));
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::deck::value::lex;
    use std::path::Path;
    use std::sync::Arc;

    fn card(fields: &[&str]) -> RawCard {
        RawCard {
            name: "TEST".into(),
            loc: Loc::new(&Arc::from(Path::new("x.bdf")), 3),
            fields: fields.iter().map(|f| lex(f)).collect(),
            row_lines: vec![4],
        }
    }

    /// An integer E on MAT1 is one error: the "at least one of E and G" rule that would
    /// follow from its placeholder is not reported.
    #[test]
    fn a_bad_field_gives_one_error_without_knock_on() {
        let mut c = card(&["1", "210000", "", "0.3", "7850."]);
        c.name = "MAT1".into();
        let errs = crate::deck::cards::Mat1::from_card(&c).unwrap_err();
        assert_eq!(errs.len(), 1, "{errs:?}");
        assert!(
            errs[0].to_string().contains("field 3 (E): expected a real"),
            "{}",
            errs[0]
        );
    }

    #[test]
    fn errors_name_field_and_expected_type() {
        let c = card(&["1", "1.5"]);
        let mut r = FieldReader::new(&c);
        r.set_id(1);
        assert_eq!(r.id(1, "EID"), 1);
        r.id(2, "PID");
        let errs = r.finish(2).unwrap_err();
        assert_eq!(
            errs[0].to_string(),
            "x.bdf:3: TEST 1: field 3 (PID): expected an integer, found real 1.5e0"
        );
    }

    #[test]
    fn integer_in_real_field_is_rejected() {
        let c = card(&["1"]);
        let mut r = FieldReader::new(&c);
        r.real(1, "E");
        assert!(
            r.finish(1).unwrap_err()[0]
                .message
                .contains("decimal point")
        );
    }

    #[test]
    fn extra_fields_are_rejected_with_the_continuation_line() {
        let c = card(&["1", "", "", "", "", "", "", "", "9"]);
        let mut r = FieldReader::new(&c);
        r.id(1, "ID");
        let e = r.finish(2).unwrap_err();
        assert!(e[0].to_string().starts_with("x.bdf:4:"), "{}", e[0]);
        assert!(
            e[0].to_string().contains("field 2 of continuation 1"),
            "{}",
            e[0]
        );
    }

    #[test]
    fn id_list_with_thru() {
        let c = card(&["1", "123", "5", "THRU", "8", "", "20"]);
        let mut r = FieldReader::new(&c);
        assert_eq!(r.id_list(3, "G"), vec![5, 6, 7, 8, 20]);
        assert!(r.finish(8).is_ok());
    }

    #[test]
    fn keyword_default_and_error() {
        let c = card(&["", "XX"]);
        let mut r = FieldReader::new(&c);
        assert_eq!(r.keyword(1, "M", &["BDF1", "BDF2"], Some("BDF1")), "BDF1");
        r.keyword(2, "M", &["BDF1", "BDF2"], Some("BDF1"));
        assert!(
            r.finish(2).unwrap_err()[0]
                .message
                .contains("one of BDF1, BDF2")
        );
    }
}
