//! Reading Nastran input decks: executive control, case control and bulk data.
//!
//! The reader follows Nastran conventions (DESIGN.md §3) so that decks written by Nastran users,
//! pyNastran or meshio are read as Nastran reads them:
//! - [`source`] walks the files (comments, tabs, `INCLUDE`);
//! - [`fields`] slices bulk lines into small, large or free fields and joins continuations;
//! - [`value`] lexes each field (integers, reals with Nastran shorthand, names);
//! - [`cards`] turns raw cards into one typed struct per card through [`reader::FieldReader`];
//! - [`executive`] and [`case_control`] read the sections above `BEGIN BULK`;
//! - [`suggest`] finds the supported card closest to an unsupported one ("did you mean").
//!
//! Every error is collected with its `file:line`, card and field; [`Deck::read`] returns them
//! all at once. The deck module computes nothing physical.

pub mod cards;
pub mod case_control;
pub mod error;
pub mod executive;
pub mod fields;
pub mod reader;
pub mod source;
pub mod suggest;
pub mod value;

use std::path::{Path, PathBuf};
use std::sync::Arc;

pub use cards::BulkData;
pub use case_control::CaseControl;
pub use error::{DeckError, DeckErrors, Diagnostics, Loc, Warning};
pub use executive::{Executive, Solution};

use fields::CardAssembler;
use source::{Line, LineVisitor, SourceWalker};

/// A deck as read: the three sections, every file it came from, and the warnings.
#[derive(Debug, Clone)]
pub struct Deck {
    /// The main deck file.
    pub path: PathBuf,
    /// Every file read (main deck first, then includes in reading order).
    pub files: Vec<PathBuf>,
    pub executive: Executive,
    pub case: CaseControl,
    /// The bulk data cards, shared with the [`Model`](crate::model::Model) built from them.
    pub bulk: Arc<BulkData>,
    /// False for a bulk-data-only file (no `CEND` / `BEGIN BULK`).
    pub has_control_sections: bool,
    /// Accepted input worth mentioning.
    pub warnings: Vec<Warning>,
}

impl Deck {
    /// Read a deck and everything it includes. On any error, returns all errors found.
    pub fn read(path: &Path) -> Result<Deck, DeckErrors> {
        Self::build(path, |walker, builder, diag| {
            walker.walk(path, None, builder, diag)
        })
    }

    /// Read a deck from `text` held in memory, as if it were the file `path` (which need not
    /// exist; its INCLUDEs resolve relative to it, and errors name it).
    pub fn parse(path: &Path, text: &str) -> Result<Deck, DeckErrors> {
        Self::build(path, |walker, builder, diag| {
            walker.walk_str(path, text, builder, diag)
        })
    }

    fn build(
        path: &Path,
        walk: impl FnOnce(&mut SourceWalker, &mut Builder, &mut Diagnostics),
    ) -> Result<Deck, DeckErrors> {
        let mut builder = Builder::new(path);
        let mut diag = Diagnostics::default();
        let mut walker = SourceWalker::new();
        walk(&mut walker, &mut builder, &mut diag);
        builder.finish(&mut diag);
        if !diag.is_ok() {
            return Err(DeckErrors {
                errors: diag.errors,
            });
        }
        let Builder {
            executive,
            case,
            bulk,
            section_seen,
            ..
        } = builder;
        let has_control_sections = section_seen;
        let mut warnings = diag.warnings;
        if !has_control_sections {
            warnings.push(Warning {
                loc: None,
                message: "no executive or case control section (no CEND / BEGIN BULK): read as bulk data only".into(),
            });
        }
        Ok(Deck {
            path: path.to_path_buf(),
            files: walker.files,
            executive,
            case,
            bulk: Arc::new(bulk),
            has_control_sections,
            warnings,
        })
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Section {
    /// Before the first significant line.
    Start,
    Executive,
    Case,
    Bulk,
    /// After `ENDDATA`: everything is ignored.
    Done,
}

/// Executive statements that mark a file as a full deck when they come first.
const EXECUTIVE_WORDS: &[&str] = &[
    "SOL",
    "ID",
    "TIME",
    "DIAG",
    "APP",
    "CEND",
    "NASTRAN",
    "ASSIGN",
    "INIT",
    "ECHOON",
    "ECHOOFF",
    "GEOMCHECK",
];

struct Builder {
    section: Section,
    section_seen: bool,
    executive: Executive,
    case: CaseControl,
    bulk: BulkData,
    assembler: CardAssembler,
    /// Position of the last line read, for errors about the end of the deck.
    last_loc: Loc,
    /// Whether an unsupported card's error already listed the supported cards.
    supported_listed: bool,
    /// Cards read and set aside ([`cards::ignored_card`]): name, reason, first position, count.
    ignored: Vec<(String, &'static str, Loc, usize)>,
}

impl Builder {
    fn new(path: &Path) -> Self {
        Builder {
            last_loc: Loc {
                file: std::sync::Arc::from(path),
                line: 1,
            },
            section: Section::Start,
            section_seen: false,
            executive: Executive::default(),
            case: CaseControl::default(),
            bulk: BulkData::default(),
            assembler: CardAssembler::new(),
            supported_listed: false,
            ignored: Vec::new(),
        }
    }

    fn parse(&mut self, card: fields::RawCard, diag: &mut Diagnostics) {
        match cards::parser_for(&card.name) {
            Some(parse) => {
                if let Err(errors) = parse(&card, &mut self.bulk) {
                    diag.errors.extend(errors);
                }
            }
            None => match cards::ignored_card(&card.name) {
                Some((why, check)) => match check.map_or(Ok(()), |c| c(&card)) {
                    Ok(()) => self.set_aside(card, why),
                    Err(errors) => diag.errors.extend(errors),
                },
                None => {
                    diag.error(cards::unsupported_card(&card, !self.supported_listed));
                    self.supported_listed = true;
                }
            },
        }
    }

    fn set_aside(&mut self, card: fields::RawCard, why: &'static str) {
        match self.ignored.iter_mut().find(|(n, ..)| *n == card.name) {
            Some((.., count)) => *count += 1,
            None => self.ignored.push((card.name, why, card.loc, 1)),
        }
    }

    fn finish(&mut self, diag: &mut Diagnostics) {
        if let Some(card) = self.assembler.finish() {
            self.parse(card, diag);
        }
        self.case.finish(diag);
        for (name, why, loc, count) in &self.ignored {
            let cards = if *count == 1 { "card" } else { "cards" };
            diag.warn_at(
                loc,
                format!("{name} accepted and ignored ({count} {cards}): {why}"),
            );
        }
        match self.section {
            Section::Start => diag.error(DeckError::at(
                &self.last_loc,
                "the deck is empty: no statement or card found",
            )),
            Section::Executive | Section::Case => {
                let missing = if self.section == Section::Executive {
                    "CEND"
                } else {
                    "BEGIN BULK"
                };
                diag.error(DeckError::at(
                    &self.last_loc,
                    format!("the deck ends before {missing}: no bulk data was read"),
                ));
            }
            Section::Bulk | Section::Done => {}
        }
    }
}

fn first_word(text: &str) -> String {
    text.trim_start()
        .chars()
        .take_while(|c| c.is_ascii_alphanumeric())
        .collect::<String>()
        .to_ascii_uppercase()
}

/// `BEGIN BULK` alone: the main bulk data section. `BEGIN BULK SUPER = n` (the older spelling
/// of `BEGIN SUPER = n`) opens a part superelement's section and is not this.
fn is_begin_bulk(text: &str) -> bool {
    let t = text.trim().to_ascii_uppercase();
    let Some(rest) = t.strip_prefix("BEGIN") else {
        return false;
    };
    rest.trim_start()
        .strip_prefix("BULK")
        .is_some_and(|after| after.trim().is_empty())
}

/// `BEGIN SUPER = n`, `BEGIN BULK SUPER = n`, `BEGIN AUXMODEL = n` …: a bulk section of its own
/// (part superelements, auxiliary models), which paraflex does not read, as an error at its line.
fn other_begin_section(loc: &Loc, text: &str) -> Option<DeckError> {
    (first_word(text) == "BEGIN" && !is_begin_bulk(text)).then(|| {
        DeckError::at(
            loc,
            format!(
                "'{}': paraflex reads one bulk data section, after BEGIN BULK; part superelements (BEGIN SUPER) and other BEGIN sections are not supported",
                text.trim()
            ),
        )
    })
}

impl LineVisitor for Builder {
    fn line(&mut self, line: Line<'_>, diag: &mut Diagnostics) {
        let text = line.text;
        self.last_loc.clone_from(line.loc);
        if self.section == Section::Start {
            let word = first_word(text);
            self.section = if EXECUTIVE_WORDS.contains(&word.as_str()) {
                self.section_seen = true;
                Section::Executive
            } else if is_begin_bulk(text) {
                self.section_seen = true;
                Section::Case
            } else {
                Section::Bulk
            };
        }
        match self.section {
            Section::Start | Section::Done => {}
            Section::Executive => {
                if first_word(text) == "CEND" {
                    self.section = Section::Case;
                } else {
                    self.executive.read_line(line.loc, text, diag);
                }
            }
            Section::Case => {
                if let Some(error) = other_begin_section(line.loc, text) {
                    diag.error(error);
                    self.section = Section::Bulk;
                } else if is_begin_bulk(text) {
                    self.section = Section::Bulk;
                } else {
                    self.case.read_line(line.loc, text, diag);
                }
            }
            Section::Bulk => {
                if first_word(text) == "ENDDATA" {
                    self.section = Section::Done;
                    if let Some(card) = self.assembler.finish() {
                        self.parse(card, diag);
                    }
                    return;
                }
                if is_begin_bulk(text) {
                    return;
                }
                if let Some(error) = other_begin_section(line.loc, text) {
                    return diag.error(error);
                }
                if let Some(card) = self.assembler.push_line(line.loc, text, diag) {
                    self.parse(card, diag);
                }
            }
        }
    }
}
