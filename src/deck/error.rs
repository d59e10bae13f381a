//! Source positions and deck diagnostics.
//!
//! Every card and value keeps the file and line it came from ([`Loc`]). Errors are collected in a
//! [`Diagnostics`] sink during the whole read so that one run reports every problem at once
//! (DESIGN.md §3: "Bad input never panics").

use std::fmt;
use std::path::Path;
use std::sync::Arc;

/// A position in the input: file and 1-based line number.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Loc {
    /// The file as it was named (include paths as found by the INCLUDE search, [`super::source`]).
    pub file: Arc<Path>,
    /// 1-based line number.
    pub line: u32,
}

impl Loc {
    /// A position at `line` of `file`.
    pub fn new(file: &Arc<Path>, line: u32) -> Self {
        Loc {
            file: Arc::clone(file),
            line,
        }
    }
}

impl fmt::Display for Loc {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}", self.file.display(), self.line)
    }
}

/// One problem found in a deck: where, on which card and field, and what was wrong.
///
/// Rendered as `file:line: CARD id field N (NAME): message`.
#[derive(Debug, Clone, PartialEq)]
pub struct DeckError {
    /// Where the problem is.
    pub loc: Loc,
    /// The card (or statement) name and, when known, its id, e.g. `CQUAD4 101`.
    pub card: Option<String>,
    /// Field description, e.g. `field 4 (G2)`.
    pub field: Option<String>,
    /// What was wrong and what was expected.
    pub message: String,
}

impl DeckError {
    /// An error at `loc` with no card context.
    pub fn at(loc: &Loc, message: impl Into<String>) -> Self {
        DeckError {
            loc: loc.clone(),
            card: None,
            field: None,
            message: message.into(),
        }
    }

    /// Attach the card name (and id) the error belongs to.
    pub fn on_card(mut self, card: impl Into<String>) -> Self {
        self.card = Some(card.into());
        self
    }
}

impl fmt::Display for DeckError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: ", self.loc)?;
        if let Some(card) = &self.card {
            write!(f, "{card}: ")?;
        }
        if let Some(field) = &self.field {
            write!(f, "{field}: ")?;
        }
        write!(f, "{}", self.message)
    }
}

impl std::error::Error for DeckError {}

/// A warning: accepted input that the user should know about (ignored PARAMs, kept-but-unused
/// fields, output requests a solution cannot honour yet).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Warning {
    /// `file:line` of the cause, when there is one place to point at.
    pub loc: Option<String>,
    /// The text shown to the user.
    pub message: String,
}

impl fmt::Display for Warning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.loc {
            Some(loc) => write!(f, "{loc}: {}", self.message),
            None => write!(f, "{}", self.message),
        }
    }
}

/// Collector of errors and warnings for one read or validation pass.
#[derive(Debug, Default)]
pub struct Diagnostics {
    /// Problems that make the input unusable.
    pub errors: Vec<DeckError>,
    /// Accepted input worth mentioning.
    pub warnings: Vec<Warning>,
}

impl Diagnostics {
    /// Record an error.
    pub fn error(&mut self, error: DeckError) {
        self.errors.push(error);
    }

    /// Record a warning tied to a position.
    pub fn warn_at(&mut self, loc: &Loc, message: impl Into<String>) {
        self.warnings.push(Warning {
            loc: Some(loc.to_string()),
            message: message.into(),
        });
    }

    /// Record a warning about the deck as a whole.
    pub fn warn(&mut self, message: impl Into<String>) {
        self.warnings.push(Warning {
            loc: None,
            message: message.into(),
        });
    }

    /// True when no error was recorded.
    pub fn is_ok(&self) -> bool {
        self.errors.is_empty()
    }
}

/// The error returned when a deck cannot be used: every problem found, in input order.
#[derive(Debug, Clone, PartialEq)]
pub struct DeckErrors {
    /// All errors, sorted by file and line.
    pub errors: Vec<DeckError>,
}

impl fmt::Display for DeckErrors {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for e in &self.errors {
            writeln!(f, "error: {e}")?;
        }
        write!(f, "{} error(s)", self.errors.len())
    }
}

impl std::error::Error for DeckErrors {}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn error_renders_file_line_card_and_field() {
        let file: Arc<Path> = Arc::from(Path::new("deck.dat"));
        let mut e = DeckError::at(&Loc::new(&file, 12), "expected integer, found '1.5'")
            .on_card("CQUAD4 7");
        e.field = Some("field 4 (G2)".into());
        assert_eq!(
            e.to_string(),
            "deck.dat:12: CQUAD4 7: field 4 (G2): expected integer, found '1.5'"
        );
    }
}
