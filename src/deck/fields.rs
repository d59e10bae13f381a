//! Bulk-data lines → fields → raw cards.
//!
//! Each physical line is sliced by its own format, as Nastran and pyNastran's `to_fields` do:
//! - free field: a comma anywhere in the line; entries separated by commas, 10 per line (name or
//!   continuation marker, 8 data fields, continuation marker); a longer small-field line runs on
//!   into the next rows, all its fields data;
//! - large field: the first field ends in `*` (`GRID*`) or the line is a `*` continuation; four
//!   16-column data fields (columns 9–72);
//! - small field: eight 8-column data fields (columns 9–72).
//!
//! Columns 73–80 hold a continuation marker and are ignored. A line whose first field is blank
//! or starts with `+` or `*` continues the card above it. Fields of a card are flattened row by
//! row, 8 data fields per row (a large-field row is two physical lines), so that field index
//! `i` (1-based) is Nastran field `(i-1) % 8 + 2` of row `(i-1) / 8`.
//!
//! A quoted value (`'path.csv'`) in a fixed-format line may be longer than its field: it is read
//! up to its closing quote and counts as one field; the next field starts at the next field
//! boundary after the quote.

use super::error::{DeckError, Diagnostics, Loc};
use super::value::{Value, lex};

/// One bulk-data card after continuations are joined: name, data fields, and positions.
#[derive(Debug, Clone)]
pub struct RawCard {
    /// Card name in upper case, without the large-field `*`.
    pub name: String,
    /// Position of the card's first line.
    pub loc: Loc,
    /// Data fields (Nastran fields 2–9 of each row), in order. Index 0 here is field 2 of row 0.
    pub fields: Vec<Value>,
    /// Line number of each row after the first (rows are 8 fields).
    pub row_lines: Vec<u32>,
}

impl RawCard {
    /// Line on which flattened field `index` (1-based, as in [`FieldReader`](super::reader::FieldReader)) was written.
    pub fn line_of(&self, index: usize) -> u32 {
        let row = index.saturating_sub(1) / 8;
        if row == 0 {
            self.loc.line
        } else {
            self.row_lines
                .get(row - 1)
                .copied()
                .unwrap_or(self.loc.line)
        }
    }

    /// The location of flattened field `index`.
    pub fn loc_of(&self, index: usize) -> Loc {
        Loc {
            file: self.loc.file.clone(),
            line: self.line_of(index),
        }
    }

    /// Human description of flattened field `index`: `field 4` or `field 3 of continuation 2`.
    pub fn field_label(index: usize) -> String {
        let row = index.saturating_sub(1) / 8;
        let field = (index.saturating_sub(1)) % 8 + 2;
        if row == 0 {
            format!("field {field}")
        } else {
            format!("field {field} of continuation {row}")
        }
    }
}

/// A card from a free-field line (`NAME,field,…`) at t.bdf:1, for the card readers' unit tests.
#[cfg(test)]
pub fn card_from_line(line: &str) -> RawCard {
    let mut parts = line.split(',');
    let name = parts.next().unwrap_or_default().to_string();
    RawCard {
        name,
        loc: Loc::new(&std::sync::Arc::from(std::path::Path::new("t.bdf")), 1),
        fields: parts.map(super::value::lex).collect(),
        row_lines: vec![2],
    }
}

/// The format of one physical line.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Format {
    Small,
    Large,
    Free,
}

/// A physical line sliced into its first field and its data fields.
struct SlicedLine<'a> {
    first: &'a str,
    data: Vec<&'a str>,
    format: Format,
}

fn slice_fixed(text: &str, width: usize, count: usize) -> Vec<&str> {
    let mut data = Vec::with_capacity(count);
    let mut start = 8;
    let end_of_data = 72.min(text.len());
    while data.len() < count && start < end_of_data {
        let mut end = (start + width).min(end_of_data);
        // A quoted string runs to its closing quote, then to the next field boundary.
        let field_text = text.get(start..end).unwrap_or("");
        if field_text.trim_start().starts_with('\'') && field_text.matches('\'').count() < 2 {
            let open = start + field_text.find('\'').unwrap_or(0);
            if let Some(close) = text[open + 1..].find('\'') {
                let close = open + 1 + close + 1;
                end = close;
                data.push(&text[start..end]);
                start = start + (close - start).div_ceil(width) * width;
                continue;
            }
        }
        data.push(text.get(start..end).unwrap_or(""));
        start += width;
    }
    data
}

fn slice_line(text: &str) -> SlicedLine<'_> {
    if text.contains(',') {
        let mut parts = text.split(',');
        let first = parts.next().unwrap_or("");
        let data: Vec<&str> = parts.collect();
        return SlicedLine {
            first,
            data,
            format: Format::Free,
        };
    }
    let first = text.get(..8.min(text.len())).unwrap_or(text);
    if is_large_marker(first) {
        SlicedLine {
            first,
            data: slice_fixed(text, 16, 4),
            format: Format::Large,
        }
    } else {
        SlicedLine {
            first,
            data: slice_fixed(text, 8, 8),
            format: Format::Small,
        }
    }
}

/// Joins bulk lines into [`RawCard`]s and hands each finished card on.
pub struct CardAssembler {
    pending: Option<RawCard>,
    /// True when the pending card's last row is half-filled by a large-field line.
    half_row: bool,
}

impl Default for CardAssembler {
    fn default() -> Self {
        Self::new()
    }
}

impl CardAssembler {
    /// An assembler with no card in progress.
    pub fn new() -> Self {
        CardAssembler {
            pending: None,
            half_row: false,
        }
    }

    /// Feed one bulk-data line; returns the previous card when this line starts a new one.
    pub fn push_line(&mut self, loc: &Loc, text: &str, diag: &mut Diagnostics) -> Option<RawCard> {
        let sliced = slice_line(text);
        let first = sliced.first.trim();
        let is_continuation = first.is_empty() || first.starts_with('+') || first.starts_with('*');
        if is_continuation {
            match self.pending.as_mut() {
                Some(card) => {
                    Self::append(card, &mut self.half_row, &sliced, loc, diag);
                }
                None => diag.error(DeckError::at(
                    loc,
                    format!("continuation line '{}' has no card before it", text.trim()),
                )),
            }
            return None;
        }
        let finished = self.pending.take();
        let name = first.trim_end_matches('*').to_ascii_uppercase();
        let mut card = RawCard {
            name,
            loc: loc.clone(),
            fields: Vec::new(),
            row_lines: Vec::new(),
        };
        self.half_row = false;
        Self::append(&mut card, &mut self.half_row, &sliced, loc, diag);
        self.pending = Some(card);
        finished
    }

    /// The card still in progress at the end of the input.
    pub fn finish(&mut self) -> Option<RawCard> {
        self.pending.take()
    }

    fn append(
        card: &mut RawCard,
        half_row: &mut bool,
        line: &SlicedLine<'_>,
        loc: &Loc,
        diag: &mut Diagnostics,
    ) {
        let large = match line.format {
            Format::Large => true,
            Format::Free => is_large_marker(line.first),
            Format::Small => false,
        };
        let starts_row = !(large && *half_row);
        if starts_row {
            // Pad the previous row to a multiple of 8 before a new row starts.
            let padded = card.fields.len().div_ceil(8) * 8;
            card.fields.resize(padded, Value::Blank);
            if !card.fields.is_empty() {
                card.row_lines.push(loc.line);
            }
        }
        let per_line = if large { 4 } else { 8 };
        // A small-field free line longer than one row runs on: its fields after the name are all
        // data, 8 to a row, with no continuation markers between them (MSC Nastran reads
        // `CORD2C,1,0, 0.,0.,0., 0.,0.,1., 0.,1.,0.` as one card with C = (0, 1, 0)).
        let runs_on = line.format == Format::Free && !large && line.data.len() > per_line + 1;
        if line.format == Format::Free && large && line.data.len() > per_line + 1 {
            diag.error(
                DeckError::at(
                    loc,
                    format!(
                        "large-field free-field line has {} fields; at most {} are allowed (name, {per_line} data fields, continuation marker)",
                        line.data.len() + 1,
                        per_line + 2
                    ),
                )
                .on_card(card.name.clone()),
            );
        }
        let data = if runs_on {
            &line.data[..]
        } else {
            &line.data[..line.data.len().min(per_line)]
        };
        let row_start = card.fields.len() / 8 * 8;
        card.fields.extend(data.iter().map(|s| lex(s)));
        if runs_on {
            let rows = card.fields.len().div_ceil(8);
            let first_extra_row = row_start / 8 + 1;
            card.row_lines
                .extend((first_extra_row..rows).map(|_| loc.line));
            card.fields.resize(rows * 8, Value::Blank);
            *half_row = false;
            return;
        }
        // Every physical line fills its share of the row even when written short.
        let filled = if large && starts_row {
            row_start + 4
        } else {
            row_start + 8
        };
        if card.fields.len() < filled {
            card.fields.resize(filled, Value::Blank);
        }
        *half_row = large && starts_row;
    }
}

fn is_large_marker(first: &str) -> bool {
    let first = first.trim();
    first.ends_with('*') || first.starts_with('*')
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;
    use std::sync::Arc;

    fn cards(text: &str) -> (Vec<RawCard>, Diagnostics) {
        let file: Arc<Path> = Arc::from(Path::new("t.bdf"));
        let mut asm = CardAssembler::new();
        let mut diag = Diagnostics::default();
        let mut out = Vec::new();
        for (i, line) in text.lines().enumerate() {
            if let Some(c) = asm.push_line(&Loc::new(&file, i as u32 + 1), line, &mut diag) {
                out.push(c);
            }
        }
        out.extend(asm.finish());
        (out, diag)
    }

    fn trimmed(card: &RawCard) -> Vec<Value> {
        let mut f = card.fields.clone();
        while f.last().is_some_and(Value::is_blank) {
            f.pop();
        }
        f
    }

    #[test]
    fn small_field_with_plus_continuation() {
        let (c, d) = cards(
            "CHEXA   1       1       1       2       3       4       5       6       +C1\n+C1     7       8",
        );
        assert!(d.is_ok());
        assert_eq!(c.len(), 1);
        let f = trimmed(&c[0]);
        assert_eq!(f.len(), 10);
        assert_eq!(f[9], Value::Int(8));
        assert_eq!(c[0].line_of(9), 2);
        assert_eq!(c[0].line_of(8), 1);
    }

    #[test]
    fn blank_first_field_continuation() {
        let (c, _) = cards(
            "RBE2    1       10      123456  1       2       3       4       5\n        6       7",
        );
        assert_eq!(trimmed(&c[0]).len(), 10);
    }

    #[test]
    fn large_field_grid_matches_small() {
        let (large, d) =
            cards("GRID*   1                               1.5             2.5\n*       3.5");
        assert!(d.is_ok());
        let (small, _) = cards("GRID    1               1.5     2.5     3.5");
        assert_eq!(trimmed(&large[0]), trimmed(&small[0]));
        assert_eq!(large[0].name, "GRID");
    }

    #[test]
    fn large_field_two_rows() {
        let text = "CHEXA*  1               1               1               2\n*       3               4               5               6\n*       7               8";
        let (c, d) = cards(text);
        assert!(d.is_ok());
        let f = trimmed(&c[0]);
        assert_eq!(f.len(), 10);
        assert_eq!(f[8], Value::Int(7));
        assert_eq!(c[0].line_of(9), 3);
    }

    #[test]
    fn free_field_and_free_continuation() {
        let (c, d) = cards("CHEXA,1,,1,2,3,4,5,6\n+,7,8\nGRID,2,,1.,2.,3.");
        assert!(d.is_ok());
        assert_eq!(c.len(), 2);
        assert_eq!(trimmed(&c[0])[9], Value::Int(8));
        assert_eq!(c[0].fields[1], Value::Blank);
        assert_eq!(
            trimmed(&c[1]),
            vec![
                Value::Int(2),
                Value::Blank,
                Value::Real(1.),
                Value::Real(2.),
                Value::Real(3.)
            ]
        );
    }

    #[test]
    fn large_free_field() {
        let (c, d) = cards("GRID*,1,,1.,2.\n*,3.");
        assert!(d.is_ok());
        assert_eq!(
            trimmed(&c[0]),
            vec![
                Value::Int(1),
                Value::Blank,
                Value::Real(1.),
                Value::Real(2.),
                Value::Real(3.)
            ]
        );
    }

    #[test]
    fn long_free_field_line_runs_on_into_the_next_rows() {
        let (c, d) = cards("CORD2C,1,0, 0.,0.,0., 0.,0.,1., 0.,1.,0.\n+,9\nGRID,2");
        assert!(d.is_ok());
        assert_eq!(c.len(), 2);
        let f = &c[0].fields;
        // Row 0: CID RID A B; row 1: C; row 2: the continuation line.
        assert_eq!(f.len(), 24);
        assert_eq!(f[7], Value::Real(1.));
        assert_eq!(
            &f[8..11],
            &[Value::Real(0.), Value::Real(1.), Value::Real(0.)]
        );
        assert!(f[11..16].iter().all(Value::is_blank));
        assert_eq!(f[16], Value::Int(9));
        assert_eq!((c[0].line_of(9), c[0].line_of(17)), (1, 2));
    }

    #[test]
    fn too_many_large_free_fields_is_an_error() {
        let (_, d) = cards("GRID*,1,,1.,2.,3.,4.");
        assert_eq!(d.errors.len(), 1);
    }

    #[test]
    fn continuation_without_card() {
        let (_, d) = cards("+C1     7       8");
        assert!(d.errors[0].to_string().contains("t.bdf:1"));
    }

    #[test]
    fn long_quoted_string_in_small_field() {
        let (c, d) = cards("TABLEF  7       'data/measured.csv'     1       2");
        assert!(d.is_ok());
        assert_eq!(
            trimmed(&c[0]),
            vec![
                Value::Int(7),
                Value::Quoted("data/measured.csv".into()),
                Value::Int(1),
                Value::Int(2)
            ]
        );
    }
}
