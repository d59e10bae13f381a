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
    /// The part superelements (`BEGIN SUPER = n` sections), by increasing SEID; `bulk` is the
    /// main bulk data (the residual). [`crate::model::parts`] assembles them into one model.
    pub parts: Vec<PartBulk>,
}

/// The bulk data section of one part superelement, in its own id namespace.
#[derive(Debug, Clone)]
pub struct PartBulk {
    pub seid: u32,
    /// The `BEGIN SUPER` line.
    pub loc: Loc,
    pub bulk: BulkData,
    /// Each card name read in the section, with its first position.
    pub cards: Vec<(String, Loc)>,
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
            mut parts,
            ..
        } = builder;
        parts.sort_by_key(|p| p.seid);
        let has_control_sections = section_seen;
        let mut warnings = diag.warnings;
        if let (Some(point), true) = (bulk.points.first(), bulk.seloc.is_empty()) {
            warnings.push(Warning {
                loc: Some(point.loc.to_string()),
                message: format!(
                    "POINT accepted and ignored ({} card{}): a POINT is a geometric point without DOF, read only by SELOC",
                    bulk.points.len(),
                    if bulk.points.len() == 1 { "" } else { "s" }
                ),
            });
        }
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
            parts,
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
    /// Part superelement sections read so far.
    parts: Vec<PartBulk>,
    /// The part whose section is being read (index in `parts`), `None` in the main bulk data.
    part: Option<usize>,
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
            parts: Vec::new(),
            part: None,
        }
    }

    fn parse(&mut self, card: fields::RawCard, diag: &mut Diagnostics) {
        let bulk = match self.part {
            Some(i) => {
                let part = &mut self.parts[i];
                if !part.cards.iter().any(|(n, _)| *n == card.name) {
                    part.cards.push((card.name.clone(), card.loc.clone()));
                }
                &mut part.bulk
            }
            None => &mut self.bulk,
        };
        match cards::parser_for(&card.name) {
            Some(parse) => {
                if let Err(errors) = parse(&card, bulk) {
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

    /// Start reading the section of part superelement `seid`.
    fn open_part(&mut self, seid: u32, loc: &Loc, diag: &mut Diagnostics) {
        if let Some(first) = self.parts.iter().find(|p| p.seid == seid) {
            diag.error(DeckError::at(
                loc,
                format!(
                    "a second BEGIN SUPER = {seid} section (the first is at {}); a part's bulk data is one section",
                    first.loc
                ),
            ));
        }
        self.parts.push(PartBulk {
            seid,
            loc: loc.clone(),
            bulk: BulkData::default(),
            cards: Vec::new(),
        });
        self.part = Some(self.parts.len() - 1);
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

/// What a `BEGIN` line other than `BEGIN BULK` opens.
enum OtherBegin {
    /// `BEGIN SUPER = n` or `BEGIN BULK SUPER = n` (also without `=`): part superelement n.
    Part(u32),
    /// `BEGIN AUXMODEL = n` and the like, or a malformed `BEGIN SUPER`: an error at its line.
    Refused(DeckError),
}

/// `BEGIN SUPER = n`, `BEGIN BULK SUPER = n`, `BEGIN AUXMODEL = n` …: a bulk section of its
/// own. Part superelement sections are read; the others (auxiliary models …) are refused.
fn other_begin_section(loc: &Loc, text: &str) -> Option<OtherBegin> {
    if first_word(text) != "BEGIN" || is_begin_bulk(text) {
        return None;
    }
    let upper = text.trim().to_ascii_uppercase();
    let words: Vec<&str> = upper
        .split(|c: char| c.is_whitespace() || c == '=' || c == ',')
        .filter(|w| !w.is_empty())
        .collect();
    let rest = match words.get(1) {
        Some(&"BULK") => &words[2..],
        _ => &words[1..],
    };
    if rest.first() == Some(&"SUPER") {
        return Some(match rest {
            [_, n] => match n.parse::<u32>() {
                Ok(seid) if seid > 0 && seid <= u32::MAX / 2 => OtherBegin::Part(seid),
                _ => OtherBegin::Refused(DeckError::at(
                    loc,
                    format!(
                        "'{}': expected a part superelement id > 0 after SUPER =",
                        text.trim()
                    ),
                )),
            },
            [_, _, ..] => OtherBegin::Refused(DeckError::at(
                loc,
                format!(
                    "'{}': options after BEGIN SUPER = n ({}) are not supported",
                    text.trim(),
                    rest[2..].join(" ")
                ),
            )),
            _ => OtherBegin::Refused(DeckError::at(
                loc,
                format!(
                    "'{}': expected BEGIN SUPER = n with a superelement id n > 0",
                    text.trim()
                ),
            )),
        });
    }
    Some(OtherBegin::Refused(DeckError::at(
        loc,
        format!(
            "'{}': paraflex reads the main bulk data section (BEGIN BULK) and part superelement sections (BEGIN SUPER = n); other BEGIN sections are not supported",
            text.trim()
        ),
    )))
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
                if let Some(begin) = other_begin_section(line.loc, text) {
                    // a part section may end case control (the main bulk data follows later)
                    self.section = Section::Bulk;
                    match begin {
                        OtherBegin::Part(seid) => self.open_part(seid, line.loc, diag),
                        OtherBegin::Refused(error) => diag.error(error),
                    }
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
                    // back to the main bulk data after a part section
                    if let Some(card) = self.assembler.finish() {
                        self.parse(card, diag);
                    }
                    self.part = None;
                    return;
                }
                if let Some(begin) = other_begin_section(line.loc, text) {
                    if let Some(card) = self.assembler.finish() {
                        self.parse(card, diag);
                    }
                    return match begin {
                        OtherBegin::Part(seid) => self.open_part(seid, line.loc, diag),
                        OtherBegin::Refused(error) => diag.error(error),
                    };
                }
                if let Some(card) = self.assembler.push_line(line.loc, text, diag) {
                    self.parse(card, diag);
                }
            }
        }
    }
}
