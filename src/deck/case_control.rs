//! Case control: subcases, sets, titles, selections (`SPC = 1`, `METHOD = 10`, …), output
//! requests with describers (`DISPLACEMENT(PRINT,SORT1) = ALL`) and the paraflex extension
//! statements (`PROM`, `ROM`, `PVAL`, `SENSOR`, `ESTIM`, `MEAS`).
//!
//! Command names may be abbreviated to their first four characters, as in Nastran
//! (`DISP`, `SPCF`, `FREQ`). Statements above the first `SUBCASE` are defaults for every
//! subcase ([`CaseControl::subcases`] resolves them).

use super::error::{DeckError, Diagnostics, Loc};
use super::reader::expand_thru;
use super::value::{Value, lex};
use crate::card_values::FmbStart;

/// What an output request or `SENSOR` selects.
#[derive(Debug, Clone, PartialEq, Eq, serde::Serialize)]
pub enum Target {
    /// `ALL`.
    All,
    /// `NONE`.
    None,
    /// A `SET` id.
    Set(u32),
}

/// Case control `STRREF`: the configuration the STRAIN outputs of a `SOL FMB` subcase are
/// measured from (eq. 9.24: a gauge zeroed in a reference configuration).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub enum StrainReference {
    /// The undeformed body (absolute strain), the default.
    None,
    /// The subcase's own state at t = 0 (after `FMBSTART`).
    Initial,
    /// The last state of an earlier subcase of the same deck (e.g. a static subcase: the
    /// equilibrium under gravity).
    Subcase(u32),
    /// `SOL ESTIMATE` on a mechanism: the static equilibrium at t = 0 at the initial
    /// parameter guesses (eq. 9.24).
    Static,
    /// `SOL ESTIMATE` on a mechanism: the static equilibrium at t = 0 at the current estimate,
    /// every step (eq. 9.25).
    Adaptive,
}

/// An output request such as `STRAIN(PLOT,FIBER) = 5`.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct OutputRequest {
    /// Canonical command name (`DISPLACEMENT`, `SPCFORCES`, `STRAIN`, …).
    pub name: &'static str,
    /// Describers in upper case, as written.
    pub describers: Vec<String>,
    /// What is requested.
    pub target: Target,
    /// Where it was written.
    #[serde(skip)]
    pub loc: Loc,
}

/// A case-control `SET n = …` list of ids (`THRU` ranges expanded).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct CaseSet {
    pub id: u32,
    pub ids: Vec<u32>,
    #[serde(skip)]
    pub loc: Loc,
}

/// The statements of one subcase (or the defaults above the first `SUBCASE`).
#[derive(Debug, Clone, Default, serde::Serialize)]
pub struct Subcase {
    /// Subcase id (0 for the global defaults).
    pub id: u32,
    pub title: Option<String>,
    pub subtitle: Option<String>,
    pub label: Option<String>,
    pub spc: Option<u32>,
    /// `MPC = sid` (MPC / MPCADD set).
    pub mpc: Option<u32>,
    pub load: Option<u32>,
    pub method: Option<u32>,
    pub frequency: Option<u32>,
    /// `SDAMPING = tid`: the TABDMP1 of the modal damping.
    pub sdamping: Option<u32>,
    /// `RANDOM = sid`: the RANDPS (and RANDT1) cards of a random response.
    pub random: Option<u32>,
    pub dload: Option<u32>,
    pub tstep: Option<u32>,
    /// `IC = sid` (TIC cards of a transient).
    pub ic: Option<u32>,
    /// `PROM = id` (PMOR card of a `SOL PROM` run).
    pub prom: Option<u32>,
    /// `ROM = 'path.h5'`, relative to the deck.
    pub rom: Option<String>,
    /// `FMB = 'path.h5'`, relative to the deck: the mechanism of a `SOL FMB` run's `/pfmb`.
    pub fmb: Option<String>,
    pub pval: Option<u32>,
    /// `SENSOR = ALL | set`.
    pub sensor: Option<Target>,
    /// `ESTIM = id` (EKF card).
    pub estim: Option<u32>,
    /// `MEAS = id` (MEASF card).
    pub meas: Option<u32>,
    /// `MSENSOR = ALL | NONE | set` (the MSENSOR outputs of `SOL FMB`).
    pub msensor: Option<Target>,
    /// `FMBSTART = ASSEMBLE | STATIC` (the start of a `SOL FMB` run).
    pub fmbstart: Option<FmbStart>,
    /// `POSES = id` (FMBPOSE card: the pose grid of a static `SOL FMB` subcase).
    pub poses: Option<u32>,
    /// `SUPORT1 = sid` (SUPORT1 set of the r-set, with every SUPORT card).
    pub suport1: Option<u32>,
    /// `LOADSET = sid` (LSEQ cards: static load sets as dynamic excitations).
    pub loadset: Option<u32>,
    /// `TEMPERATURE(LOAD) = sid` or `TEMPERATURE(BOTH) = sid` (TEMP/TEMPD set of the thermal
    /// load).
    pub temperature_load: Option<u32>,
    /// `TEMPERATURE(MATERIAL) = sid`, `TEMPERATURE(INITIAL) = sid` or `TEMPERATURE(BOTH) = sid`:
    /// the set temperature-dependent material properties would be evaluated at (paraflex
    /// evaluates none; see `model::temperature`).
    pub temperature_material: Option<u32>,
    /// `STRREF = NONE | INITIAL | id` (what the STRAIN outputs of a `SOL FMB` run are relative
    /// to).
    pub strref: Option<StrainReference>,
    pub outputs: Vec<OutputRequest>,
    /// `SUBCOM`: the coefficients of its `SUBSEQ`, the last one for the most recent preceding
    /// `SUBCASE`, the one before for the one before it, … (empty until `SUBSEQ` is read);
    /// `None` for a `SUBCASE`.
    pub combination: Option<Vec<f64>>,
    /// Positions of the selections, by canonical name, for cross-reference messages.
    #[serde(skip)]
    pub locs: Vec<(&'static str, Loc)>,
}

impl Subcase {
    /// Where selection `name` (canonical) was written, if it was.
    pub fn loc_of(&self, name: &str) -> Option<&Loc> {
        self.locs
            .iter()
            .rev()
            .find(|(n, _)| *n == name)
            .map(|(_, l)| l)
    }

    /// This subcase's statements on top of `defaults`.
    fn over(&self, defaults: &Subcase) -> Subcase {
        let mut out = self.clone();
        macro_rules! inherit { ($($f:ident),*) => { $( if out.$f.is_none() { out.$f = defaults.$f.clone(); } )* } }
        inherit!(
            title,
            subtitle,
            label,
            spc,
            mpc,
            load,
            method,
            frequency,
            sdamping,
            random,
            dload,
            tstep,
            ic,
            prom,
            rom,
            fmb,
            pval,
            sensor,
            estim,
            meas,
            msensor,
            fmbstart,
            poses,
            strref,
            suport1,
            loadset,
            temperature_load,
            temperature_material
        );
        let own: Vec<&str> = out.outputs.iter().map(|o| o.name).collect();
        let inherited: Vec<OutputRequest> = defaults
            .outputs
            .iter()
            .filter(|o| !own.contains(&o.name))
            .cloned()
            .collect();
        out.outputs.splice(0..0, inherited);
        let mut locs = defaults.locs.clone();
        locs.extend(out.locs);
        out.locs = locs;
        out
    }
}

/// The case control section.
#[derive(Debug, Clone, Default, serde::Serialize)]
pub struct CaseControl {
    /// Statements above the first `SUBCASE`.
    pub global: Subcase,
    /// Explicit subcases in input order.
    pub explicit: Vec<Subcase>,
    /// `SET` definitions (global scope, as paraflex does not scope sets to subcases).
    pub sets: Vec<CaseSet>,
    /// `PARAM` statements given in case control, as `(name, value text, position)`.
    #[serde(skip)]
    pub params: Vec<(String, String, Loc)>,
    /// A `SET` statement still waiting for its continuation line.
    #[serde(skip)]
    pending_set: Option<(Loc, String)>,
    /// Whether an `ECHO` asking for an echo was already warned about.
    #[serde(skip)]
    echo_warned: bool,
    /// An `OUTPUT(PLOT)`-style section being skipped: where it starts, its name and the number
    /// of statements skipped so far.
    #[serde(skip)]
    plotter_section: Option<(Loc, String, usize)>,
}

/// The describers of `OUTPUT(…)` that open a plotter or post-processing section (structure and
/// XY plots, their printer and punch copies, the OUTPUT(POST) surfaces and volumes). Such a
/// section runs to `BEGIN BULK`; paraflex draws no plots (the HDF5 and XDMF files replace them),
/// so it is skipped with one warning instead of reading its SET, AXES, VIEW, FIND, PLOT,
/// XYPLOT, XYPRINT … statements as case control.
const PLOTTER_SECTIONS: &[&str] = &["PLOT", "XYPLOT", "XYOUT", "XYPUNCH", "POST", "CARDS"];

/// Canonical case-control commands that select a bulk-data id.
const SELECTIONS: &[&str] = &[
    "SPC",
    "MPC",
    "LOAD",
    "METHOD",
    "FREQUENCY",
    "SDAMPING",
    "RANDOM",
    "DLOAD",
    "TSTEP",
    "IC",
    "PROM",
    "PVAL",
    "ESTIM",
    "MEAS",
    "POSES",
    "SUPORT1",
    "LOADSET",
];

/// Output requests paraflex parses.
const OUTPUTS: &[&str] = &[
    "DISPLACEMENT",
    "VELOCITY",
    "ACCELERATION",
    "SPCFORCES",
    "STRAIN",
    "STRESS",
    "FORCE",
    "OLOAD",
    "GPFORCE",
    "ESE",
    "MPCFORCES",
    "GPWG",
    "ELSTRESS",
    "ELFORCE",
    "VECTOR",
    "PRESSURE",
    "EKE",
    "EDE",
    "GPKE",
    "GPSTRESS",
    "STRFIELD",
    "GPSTRAIN",
    // stress discontinuity estimates (grid point and element), mesh-quality outputs
    "GPSDCON",
    "ELSDCON",
    // random response: cross-spectra and grid-point sorting (not computed)
    "RCROSS",
    "GPRSORT",
];

/// Statements accepted and ignored (printing and bookkeeping options that do not change results).
const IGNORED: &[&str] = &[
    "LINE",
    // MSC reads `LINES = n` as LINE
    "LINES",
    "MAXLINES",
    "ANALYSIS",
    "GROUNDCHECK",
    "WEIGHTCHECK",
    "MEFFMASS",
    "SEALL",
    "SUPER",
    "OUTPUT",
];

/// Match `word` to a canonical name: exact, or an abbreviation of at least four characters.
fn canonical(word: &str, names: &[&'static str]) -> Option<&'static str> {
    let w = word.to_ascii_uppercase();
    if let Some(n) = names.iter().find(|n| **n == w) {
        return Some(n);
    }
    if w.len() < 4 {
        return None;
    }
    names.iter().find(|n| n.starts_with(&w)).copied()
}

/// `word[(describers)] = value` split into its parts.
struct Statement<'a> {
    word: &'a str,
    describers: Vec<String>,
    value: Option<&'a str>,
}

fn split_statement(text: &str) -> Statement<'_> {
    let end_word = text
        .find(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
        .unwrap_or(text.len());
    let word = &text[..end_word];
    let mut rest = text[end_word..].trim_start();
    let mut describers = Vec::new();
    if let Some(inner) = rest.strip_prefix('(') {
        let close = inner.find(')').unwrap_or(inner.len());
        describers = inner[..close]
            .split(',')
            .map(|d| d.trim().to_ascii_uppercase())
            .filter(|d| !d.is_empty())
            .collect();
        rest = inner.get(close + 1..).unwrap_or("").trim_start();
    }
    let value = rest.strip_prefix('=').map(str::trim);
    Statement {
        word,
        describers,
        value,
    }
}

/// A positive id in the range bulk-data ids use (1 … 2³¹ − 1).
fn parse_id(text: &str) -> Option<u32> {
    text.parse::<u32>()
        .ok()
        .filter(|&id| id > 0 && id <= u32::MAX / 2)
}

/// Parse a `SET` list: ids, `THRU` ranges, `ALL` not allowed. Errors are messages.
fn parse_set_list(text: &str) -> Result<Vec<u32>, String> {
    let mut ids: Vec<u32> = Vec::new();
    let tokens: Vec<&str> = text
        .split([',', ' '])
        .map(str::trim)
        .filter(|t| !t.is_empty())
        .collect();
    let mut i = 0;
    while i < tokens.len() {
        let t = tokens[i];
        if t.eq_ignore_ascii_case("THRU") {
            let lo = *ids.last().ok_or("THRU needs an id before it")?;
            let hi = tokens
                .get(i + 1)
                .and_then(|h| parse_id(h))
                .ok_or("THRU needs an id after it")?;
            expand_thru(&mut ids, lo, hi)?;
            i += 2;
            continue;
        }
        if t.eq_ignore_ascii_case("EXCEPT") {
            return Err("EXCEPT in SET lists is not supported; list the ids explicitly".into());
        }
        let id = parse_id(t).ok_or_else(|| {
            format!(
                "expected an id (1 to {}) or THRU, found '{t}'",
                u32::MAX / 2
            )
        })?;
        ids.push(id);
        i += 1;
    }
    if ids.is_empty() {
        return Err("SET has no ids".into());
    }
    Ok(ids)
}

/// The real coefficients of `SUBSEQ = c1, c2, …` (commas or blanks between them).
fn parse_coefficients(value: &str) -> Result<Vec<f64>, String> {
    let tokens: Vec<&str> = value
        .split([',', ' '])
        .map(str::trim)
        .filter(|t| !t.is_empty())
        .collect();
    if tokens.is_empty() {
        return Err("SUBSEQ has no coefficients".into());
    }
    tokens
        .iter()
        .map(|t| match lex(t) {
            Value::Real(x) => Ok(x),
            Value::Int(i) => Ok(i as f64),
            _ => Err(format!(
                "expected a real coefficient, found '{t}' (SUBSEQ lists one real per preceding subcase, on one line)"
            )),
        })
        .collect()
}

fn parse_target(value: &str) -> Result<Target, String> {
    match value.to_ascii_uppercase().as_str() {
        "ALL" => Ok(Target::All),
        "NONE" => Ok(Target::None),
        v => v
            .parse::<u32>()
            .map(Target::Set)
            .map_err(|_| format!("expected ALL, NONE or a SET id, found '{value}'")),
    }
}

fn strip_quotes(value: &str) -> Option<&str> {
    let v = value.trim();
    v.strip_prefix('\'')
        .and_then(|s| s.strip_suffix('\''))
        .or_else(|| (!v.is_empty()).then_some(v))
}

impl CaseControl {
    fn current(&mut self) -> &mut Subcase {
        self.explicit.last_mut().unwrap_or(&mut self.global)
    }

    /// Read one case-control line (comments already removed).
    pub fn read_line(&mut self, loc: &Loc, text: &str, diag: &mut Diagnostics) {
        if let Some((set_loc, mut acc)) = self.pending_set.take() {
            acc.push_str(text);
            return self.read_set(&set_loc, acc, diag);
        }
        if let Some((_, _, skipped)) = &mut self.plotter_section {
            *skipped += 1;
            return;
        }
        let text = text.trim();
        let st = split_statement(text);
        // TITLE, SUBTITLE and LABEL may be abbreviated like every command (`SUBTIT`, `TITL`)
        let word = canonical(st.word, &["TITLE", "SUBTITLE", "LABEL"])
            .map_or_else(|| st.word.to_ascii_uppercase(), str::to_string);
        let err = |msg: String| DeckError::at(loc, msg).on_card(word.clone());
        if word == "OUTPUT"
            && let Some(section) = st
                .describers
                .iter()
                .find(|d| PLOTTER_SECTIONS.contains(&d.as_str()))
        {
            self.plotter_section = Some((loc.clone(), section.clone(), 0));
            return;
        }
        match word.as_str() {
            "TITLE" | "SUBTITLE" | "LABEL" => {
                let value = text
                    .split_once('=')
                    .map(|(_, v)| v.trim().to_string())
                    .unwrap_or_default();
                let sub = self.current();
                match word.as_str() {
                    "TITLE" => sub.title = Some(value),
                    "SUBTITLE" => sub.subtitle = Some(value),
                    _ => sub.label = Some(value),
                }
            }
            "SUBCASE" => {
                let rest = text[st.word.len()..].trim();
                match rest.parse::<u32>() {
                    Ok(id) if id > 0 => {
                        if self.explicit.iter().any(|s| s.id == id) {
                            diag.error(err(format!("SUBCASE {id} defined twice")));
                        }
                        self.explicit.push(Subcase {
                            id,
                            ..Subcase::default()
                        });
                    }
                    _ => diag.error(err(format!(
                        "expected a positive subcase id, found '{rest}'"
                    ))),
                }
            }
            "SUBCOM" => {
                let rest = text[st.word.len()..].trim();
                match rest.parse::<u32>() {
                    Ok(id) if id > 0 => {
                        if self.explicit.iter().any(|s| s.id == id) {
                            diag.error(err(format!("SUBCOM {id}: subcase {id} defined twice")));
                        }
                        self.explicit.push(Subcase {
                            id,
                            combination: Some(Vec::new()),
                            locs: vec![("SUBCOM", loc.clone())],
                            ..Subcase::default()
                        });
                    }
                    _ => diag.error(err(format!(
                        "expected a positive subcase id, found '{rest}'"
                    ))),
                }
            }
            "SUBSEQ" => match (st.value.map(parse_coefficients), self.current()) {
                (Some(Ok(c)), Subcase {
                    combination: Some(combination),
                    locs,
                    ..
                }) => {
                    *combination = c;
                    locs.push(("SUBSEQ", loc.clone()));
                }
                (Some(Ok(_)), _) => diag.error(err(
                    "SUBSEQ outside a SUBCOM: it gives the coefficients of a SUBCOM's combination of the preceding subcases".into(),
                )),
                (Some(Err(m)), _) => diag.error(err(m)),
                (None, _) => diag.error(err("expected SUBSEQ = c1, c2, …".into())),
            },
            "SET" => self.read_set(loc, text.to_string(), diag),
            "PARAM" => {
                // commas or blanks between the fields, as Nastran reads `PARAM POST 0`
                let parts: Vec<&str> = text
                    .split(|c: char| c == ',' || c.is_whitespace())
                    .filter(|p| !p.is_empty())
                    .collect();
                if parts.len() >= 3 {
                    self.params.push((
                        parts[1].to_ascii_uppercase(),
                        parts[2..].join(","),
                        loc.clone(),
                    ));
                } else {
                    diag.error(err("expected PARAM,NAME,VALUE".into()));
                }
            }
            // MSC's case-control AUTOSPC(describers) = YES | NO: the same switch as PARAM,AUTOSPC
            // (run-wide in paraflex, like every PARAM)
            "AUTOSPC" => match st.value.map(|v| v.trim().to_ascii_uppercase()) {
                Some(v) if v == "YES" || v == "NO" => {
                    self.params.push(("AUTOSPC".into(), v, loc.clone()));
                }
                _ => diag.error(err("expected AUTOSPC = YES | NO".into())),
            },
            "ROM" => match st.value.and_then(strip_quotes) {
                Some(path) => {
                    let sub = self.current();
                    sub.rom = Some(path.to_string());
                    sub.locs.push(("ROM", loc.clone()));
                }
                None => diag.error(err("expected ROM = 'file.h5'".into())),
            },
            "FMB" => match st.value.and_then(strip_quotes) {
                Some(path) => {
                    let sub = self.current();
                    sub.fmb = Some(path.to_string());
                    sub.locs.push(("FMB", loc.clone()));
                }
                None => diag.error(err("expected FMB = 'file.h5'".into())),
            },
            "MSENSOR" => match st.value.map(parse_target) {
                Some(Ok(t)) => {
                    let sub = self.current();
                    sub.msensor = Some(t);
                    sub.locs.push(("MSENSOR", loc.clone()));
                }
                Some(Err(m)) => diag.error(err(m)),
                None => diag.error(err("expected MSENSOR = ALL | NONE | set id".into())),
            },
            "FMBSTART" => match st.value.map(str::to_ascii_uppercase).as_deref() {
                Some("ASSEMBLE") => self.current().fmbstart = Some(FmbStart::Assemble),
                Some("STATIC") => {
                    let sub = self.current();
                    sub.fmbstart = Some(FmbStart::Static);
                    sub.locs.push(("FMBSTART", loc.clone()));
                }
                other => diag.error(err(format!(
                    "expected FMBSTART = ASSEMBLE | STATIC, found '{}'",
                    other.unwrap_or("")
                ))),
            },
            "STRREF" => match st.value.map(str::to_ascii_uppercase).as_deref() {
                Some(v @ ("NONE" | "INITIAL" | "STATIC" | "ADAPTIVE")) => {
                    let sub = self.current();
                    sub.strref = Some(match v {
                        "NONE" => StrainReference::None,
                        "STATIC" => StrainReference::Static,
                        "ADAPTIVE" => StrainReference::Adaptive,
                        _ => StrainReference::Initial,
                    });
                    sub.locs.push(("STRREF", loc.clone()));
                }
                Some(v) if v.parse::<u32>().is_ok_and(|id| id > 0) => {
                    let sub = self.current();
                    sub.strref = v.parse().ok().map(StrainReference::Subcase);
                    sub.locs.push(("STRREF", loc.clone()));
                }
                other => diag.error(err(format!(
                    "expected STRREF = NONE | INITIAL | STATIC | ADAPTIVE | subcase id, found '{}'",
                    other.unwrap_or("")
                ))),
            },
            "SENSOR" => match st.value.map(parse_target) {
                Some(Ok(t)) => {
                    let sub = self.current();
                    sub.sensor = Some(t);
                    sub.locs.push(("SENSOR", loc.clone()));
                }
                Some(Err(m)) => diag.error(err(m)),
                None => diag.error(err("expected SENSOR = ALL | NONE | set id".into())),
            },
            _ => self.read_command(loc, &word, st, diag),
        }
    }

    fn read_command(&mut self, loc: &Loc, word: &str, st: Statement<'_>, diag: &mut Diagnostics) {
        let err = |msg: String| DeckError::at(loc, msg).on_card(word.to_string());
        if let Some(name) = canonical(word, SELECTIONS) {
            let Some(value) = st.value else {
                return diag.error(err(format!("expected {name} = id")));
            };
            let Ok(id) = value.parse::<u32>() else {
                return diag.error(err(format!(
                    "expected {name} = a positive id, found '{value}'"
                )));
            };
            let sub = self.current();
            let slot = match name {
                "SPC" => &mut sub.spc,
                "MPC" => &mut sub.mpc,
                "LOAD" => &mut sub.load,
                "METHOD" => &mut sub.method,
                "FREQUENCY" => &mut sub.frequency,
                "SDAMPING" => &mut sub.sdamping,
                "RANDOM" => &mut sub.random,
                "DLOAD" => &mut sub.dload,
                "TSTEP" => &mut sub.tstep,
                "IC" => &mut sub.ic,
                "PROM" => &mut sub.prom,
                "PVAL" => &mut sub.pval,
                "ESTIM" => &mut sub.estim,
                "POSES" => &mut sub.poses,
                "SUPORT1" => &mut sub.suport1,
                "LOADSET" => &mut sub.loadset,
                _ => &mut sub.meas,
            };
            *slot = Some(id);
            sub.locs.push((name, loc.clone()));
        } else if let Some(name) = canonical(word, OUTPUTS) {
            let target = match st.value.map(parse_target) {
                Some(Ok(t)) => t,
                Some(Err(m)) => return diag.error(err(m)),
                None => {
                    return diag.error(err(format!(
                        "expected {name}(describers) = ALL | NONE | set id"
                    )));
                }
            };
            let req = OutputRequest {
                name,
                describers: st.describers,
                target,
                loc: loc.clone(),
            };
            self.current().outputs.push(req);
        } else if canonical(word, &["TEMPERATURE"]).is_some() {
            self.read_temperature(loc, &st, diag);
        } else if canonical(word, &["ECHO"]).is_some() {
            self.read_echo(loc, st.value, diag);
        } else if let Some(name) = canonical(word, IGNORED) {
            diag.warn_at(
                loc,
                format!("case control '{name}' is accepted and ignored"),
            );
        } else {
            diag.error(err(format!(
                "unsupported case control command '{word}': paraflex reads TITLE SUBTITLE LABEL SUBCASE SUBCOM SUBSEQ SET PARAM AUTOSPC ROM FMB SENSOR MSENSOR FMBSTART STRREF TEMPERATURE ECHO {} and output requests {}",
                SELECTIONS.join(" "),
                OUTPUTS.join(" ")
            )));
        }
    }

    /// `TEMPERATURE(LOAD | MATERIAL | INITIAL | BOTH) = sid` (BOTH when no describer), as
    /// Nastran: LOAD selects the thermal load, MATERIAL and INITIAL the temperatures of
    /// temperature-dependent material properties, BOTH the two.
    fn read_temperature(&mut self, loc: &Loc, st: &Statement<'_>, diag: &mut Diagnostics) {
        let err = |msg: String| DeckError::at(loc, msg).on_card("TEMPERATURE");
        let Some(sid) = st.value.and_then(parse_id) else {
            return diag.error(err(format!(
                "expected TEMPERATURE(LOAD | MATERIAL | INITIAL | BOTH) = a TEMP/TEMPD set id, found '{}'",
                st.value.unwrap_or("")
            )));
        };
        let kind = match st.describers.as_slice() {
            [] => "BOTH",
            [one] => match canonical(one, &["LOAD", "MATERIAL", "INITIAL", "BOTH"]) {
                Some(k) => k,
                None => {
                    return diag.error(err(format!(
                        "TEMPERATURE({one}): expected LOAD, MATERIAL, INITIAL or BOTH"
                    )));
                }
            },
            _ => {
                return diag.error(err(format!(
                    "TEMPERATURE({}): expected one of LOAD, MATERIAL, INITIAL, BOTH",
                    st.describers.join(",")
                )));
            }
        };
        let sub = self.current();
        if matches!(kind, "LOAD" | "BOTH") {
            sub.temperature_load = Some(sid);
            sub.locs.push(("TEMPERATURE(LOAD)", loc.clone()));
        }
        if kind != "LOAD" {
            sub.temperature_material = Some(sid);
            sub.locs.push(("TEMPERATURE(MATERIAL)", loc.clone()));
        }
    }

    /// `ECHO = NONE` is what paraflex does (it never echoes the input); any other ECHO
    /// (`SORT`, `UNSORT`, `BOTH`, `PUNCH`, or a bare `ECHO`, Nastran's SORT) asks for an echo
    /// paraflex does not print, and the first of them is warned about.
    fn read_echo(&mut self, loc: &Loc, value: Option<&str>, diag: &mut Diagnostics) {
        let option = value
            .unwrap_or("SORT")
            .split(['(', ','])
            .next()
            .unwrap_or("")
            .trim()
            .to_ascii_uppercase();
        if option == "NONE" || self.echo_warned {
            return;
        }
        self.echo_warned = true;
        diag.warn_at(
            loc,
            format!(
                "ECHO = {option} is not honoured: paraflex prints no echo of the input deck (as with ECHO = NONE)"
            ),
        );
    }

    fn read_set(&mut self, loc: &Loc, text: String, diag: &mut Diagnostics) {
        if text.trim_end().ends_with(',') {
            self.pending_set = Some((loc.clone(), text));
            return;
        }
        let Some((head, list)) = text.split_once('=') else {
            return diag
                .error(DeckError::at(loc, "expected SET n = id, id THRU id, ...").on_card("SET"));
        };
        let id_text = head.trim().get(3..).unwrap_or("").trim();
        let id = match parse_id(id_text) {
            Some(id) => id,
            None => {
                return diag.error(
                    DeckError::at(
                        loc,
                        format!("expected a positive SET id, found '{id_text}'"),
                    )
                    .on_card("SET"),
                );
            }
        };
        match parse_set_list(list) {
            Ok(ids) => {
                if self.sets.iter().any(|s| s.id == id) {
                    diag.error(
                        DeckError::at(loc, format!("SET {id} defined twice")).on_card("SET"),
                    );
                }
                self.sets.push(CaseSet {
                    id,
                    ids,
                    loc: loc.clone(),
                });
            }
            Err(m) => diag.error(DeckError::at(loc, m).on_card(format!("SET {id}"))),
        }
    }

    /// Report a `SET` left open by a trailing comma at the end of the section.
    pub fn finish(&mut self, diag: &mut Diagnostics) {
        if let Some((loc, section, skipped)) = self.plotter_section.take() {
            diag.warn_at(
                &loc,
                format!(
                    "the OUTPUT({section}) section ({skipped} statement(s) up to BEGIN BULK) is not read: paraflex draws no plots; its results are in the HDF5 file (and the XDMF files for ParaView)"
                ),
            );
        }
        if let Some((loc, _)) = self.pending_set.take() {
            diag.error(
                DeckError::at(
                    &loc,
                    "SET list ends with ',' but no continuation line follows",
                )
                .on_card("SET"),
            );
        }
    }

    /// The subcases to run, each with the global defaults applied. A deck without `SUBCASE`
    /// has one subcase, id 1.
    pub fn subcases(&self) -> Vec<Subcase> {
        if self.explicit.is_empty() {
            let mut only = self.global.clone();
            only.id = 1;
            return vec![only];
        }
        self.explicit.iter().map(|s| s.over(&self.global)).collect()
    }

    /// The `SET` with this id.
    pub fn set(&self, id: u32) -> Option<&CaseSet> {
        self.sets.iter().find(|s| s.id == id)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;
    use std::sync::Arc;

    fn read(lines: &[&str]) -> (CaseControl, Diagnostics) {
        let file: Arc<Path> = Arc::from(Path::new("c.dat"));
        let mut cc = CaseControl::default();
        let mut d = Diagnostics::default();
        for (i, l) in lines.iter().enumerate() {
            cc.read_line(&Loc::new(&file, i as u32 + 1), l, &mut d);
        }
        cc.finish(&mut d);
        (cc, d)
    }

    #[test]
    fn subcases_inherit_globals() {
        let (cc, d) = read(&[
            "TITLE = Plate test",
            "SPC = 1",
            "DISP(PRINT,SORT1) = ALL",
            "SUBCASE 10",
            "  LOAD = 5",
            "  STRAIN(FIBER) = 3",
            "SUBCASE 20",
            "  METH = 7",
            "  DISPLACEMENT = NONE",
            "SET 3 = 1, 2,",
            "   10 THRU 12",
        ]);
        assert!(d.is_ok(), "{:?}", d.errors);
        let subs = cc.subcases();
        assert_eq!(subs.len(), 2);
        assert_eq!(
            (subs[0].spc, subs[0].load, subs[0].title.as_deref()),
            (Some(1), Some(5), Some("Plate test"))
        );
        assert_eq!(subs[0].outputs.len(), 2);
        assert_eq!(subs[1].method, Some(7));
        assert_eq!(subs[1].outputs.len(), 1);
        assert_eq!(subs[1].outputs[0].target, Target::None);
        assert_eq!(cc.set(3).unwrap().ids, vec![1, 2, 10, 11, 12]);
    }

    #[test]
    fn extension_statements() {
        let (cc, d) = read(&[
            "ROM = 'out/blade.h5'",
            "PVAL = 3",
            "SENSOR = ALL",
            "PROM = 1",
            "MSENSOR = 7",
            "FMBSTART = assemble",
            "STRREF = 2",
            "FMB = 'fourbar.h5'",
        ]);
        assert!(d.is_ok(), "{:?}", d.errors);
        let s = &cc.subcases()[0];
        assert_eq!(s.rom.as_deref(), Some("out/blade.h5"));
        assert_eq!(s.fmb.as_deref(), Some("fourbar.h5"));
        assert_eq!(
            (s.pval, s.prom, s.sensor.clone()),
            (Some(3), Some(1), Some(Target::All))
        );
        assert_eq!(
            (s.msensor.clone(), s.fmbstart),
            (Some(Target::Set(7)), Some(FmbStart::Assemble))
        );
        assert_eq!(s.strref, Some(StrainReference::Subcase(2)));
    }

    #[test]
    fn bad_statements_are_located() {
        let (_, d) = read(&["SPC = X", "MPC = X", "SET 4 = 1 THRU", "ECHO = NONE"]);
        assert_eq!(d.errors.len(), 3, "{:?}", d.errors);
        assert!(d.errors[1].to_string().starts_with("c.dat:2: MPC"));
        assert!(d.warnings.is_empty(), "{:?}", d.warnings);
    }

    /// PARAM in case control takes commas or blanks between its fields.
    #[test]
    fn case_control_param_fields_may_be_blank_separated() {
        let (cc, d) = read(&[
            "PARAM,POST,-1",
            "param post 0",
            "PARAM, G , 0.02",
            "PARAM X",
        ]);
        let got: Vec<(&str, &str)> = cc
            .params
            .iter()
            .map(|(n, v, _)| (n.as_str(), v.as_str()))
            .collect();
        assert_eq!(got, [("POST", "-1"), ("POST", "0"), ("G", "0.02")]);
        assert_eq!(d.errors.len(), 1, "{:?}", d.errors);
    }

    /// ECHO = NONE is honoured silently; an ECHO asking for an echo is warned about once.
    #[test]
    fn echo_warns_once_and_only_when_an_echo_is_asked_for() {
        let (_, d) = read(&["ECHO = NONE", "ECHO = NONE(BULK)"]);
        assert!(d.warnings.is_empty(), "{:?}", d.warnings);
        let (_, d) = read(&[
            "ECHO = SORT",
            "SUBCASE 1",
            "ECHO = UNSORT(PARAM)",
            "ECHO = BOTH",
        ]);
        assert!(d.is_ok(), "{:?}", d.errors);
        assert_eq!(d.warnings.len(), 1, "{:?}", d.warnings);
        assert!(
            d.warnings[0]
                .to_string()
                .starts_with("c.dat:1: ECHO = SORT is not honoured"),
            "{}",
            d.warnings[0]
        );
    }

    /// An OUTPUT(XYPLOT) section at the end of case control (Nastran's XY plotter: SET, XTITLE,
    /// XYPRINT … up to BEGIN BULK) is skipped with one warning saying where it starts and how
    /// many statements it held; the subcases above it are read as usual.
    #[test]
    fn plotter_sections_are_skipped_with_one_warning() {
        let (cc, d) = read(&[
            "SUBCASE 1",
            "  LOAD = 2",
            "OUTPUT(XYPLOT)",
            "SET 9 = ALL QUAD4",
            "XTITLE = TIME",
            "XYPRINT DISP /1(T3)",
            "GRID",
        ]);
        assert!(d.is_ok(), "{:?}", d.errors);
        assert_eq!(cc.subcases()[0].load, Some(2));
        assert!(
            cc.set(9).is_none(),
            "a plotter SET is not a case-control set"
        );
        assert_eq!(d.warnings.len(), 1, "{:?}", d.warnings);
        assert!(
            d.warnings[0]
                .to_string()
                .starts_with("c.dat:3: the OUTPUT(XYPLOT) section (4 statement(s)"),
            "{}",
            d.warnings[0]
        );
        let (_, plain) = read(&["OUTPUT", "XYPRINT DISP /1(T3)"]);
        assert_eq!(
            plain.errors.len(),
            1,
            "a bare OUTPUT opens no plotter section"
        );
    }
}
