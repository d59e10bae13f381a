//! Design-optimization cards of `SOL OPTIMIZE` (DESIGN.md §12): `DVMAP` (what a design
//! variable sets), `DOBJ` (objectives), `DCONSTR` (constraints), `MOOPT` (the search). The
//! design variables themselves are Nastran's `DESVAR` and `DDVAL` ([`super::design`]).

use crate::deck::error::{DeckError, Loc};
use crate::deck::fields::RawCard;
use crate::deck::reader::FieldReader;

/// `DVMAP` — the parameters a design variable sets, or the bodies whose artifact it chooses.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | ID | int > 0 | required | id |
/// | 3 | DESVAR | int > 0 | required | the DESVAR id |
/// | 4 … | TARGET1 TARGET2 … | name | ≥ 1 | `BODY.PMPAR` parameters set to the variable's value (one variable may set both sides of a link), or a body's `NAME` alone: the (discrete) variable chooses that body's artifact from its `PROMLIB` |
#[derive(Debug, Clone, PartialEq)]
pub struct Dvmap {
    pub id: u32,
    pub desvar: u32,
    pub targets: Vec<String>,
    pub loc: Loc,
}

impl Dvmap {
    /// Read a `DVMAP` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let id = f.id(1, "ID");
        f.set_id(id);
        let desvar = f.id(2, "DESVAR");
        let len = f.len();
        let mut targets: Vec<String> = Vec::new();
        for i in 3..=len {
            if f.value(i).is_blank() {
                continue;
            }
            let name = f.text(i, "TARGET");
            if targets.contains(&name) {
                f.error(i, "TARGET", format!("{name} listed twice"));
            }
            targets.push(name);
        }
        if targets.is_empty() {
            f.card_error("no TARGET (BODY.PMPAR) given");
        }
        let loc = f.loc();
        f.finish(len.max(3))?;
        Ok(Dvmap {
            id,
            desvar,
            targets,
            loc,
        })
    }
}

/// `PROMLIB` — a library of pROM artifacts for one flexible body, one per value of a discrete
/// design variable (e.g. the ply count of a composite link, thesis §6.3.1); a `DVMAP` whose
/// TARGET is the body's NAME makes the variable choose the artifact.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | ID | int > 0 | required | id |
/// | 3 | BODY | name | required | the FLEXB's NAME |
/// | 4, 6, … | V1 V2 … | real | ≥ 1 pair | a value of the discrete variable (each once) |
/// | 5, 7, … | PATH1 PATH2 … | quoted string | required with its value | the body's pROM artifact for that value (`RIGID = REMOVE`, the FLEXB artifact's interface grids at the same positions), relative to the file holding the card |
#[derive(Debug, Clone, PartialEq)]
pub struct Promlib {
    pub id: u32,
    pub body: String,
    /// (value, path as written), in card order.
    pub entries: Vec<(f64, String)>,
    pub loc: Loc,
}

impl Promlib {
    /// Read a `PROMLIB` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let id = f.id(1, "ID");
        f.set_id(id);
        let body = f.text(2, "BODY");
        let len = f.len();
        let mut entries: Vec<(f64, String)> = Vec::new();
        let mut i = 3;
        while i <= len {
            if f.value(i).is_blank() && f.value(i + 1).is_blank() {
                i += 2;
                continue;
            }
            let k = entries.len() + 1;
            let value = f.real(i, &format!("V{k}"));
            let path = f.path(i + 1, &format!("PATH{k}"));
            if entries.iter().any(|(v, _)| *v == value) {
                f.error(i, &format!("V{k}"), format!("value {value:e} listed twice"));
            }
            entries.push((value, path));
            i += 2;
        }
        if entries.is_empty() {
            f.card_error("no value and artifact (V1 'PATH1') given");
        }
        let loc = f.loc();
        f.finish(len.max(4))?;
        Ok(Promlib {
            id,
            body,
            entries,
            loc,
        })
    }
}

/// How a response is reduced over the time history.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Statistic {
    /// Time average (trapezoidal over the output times; eq. 6.1 f₁).
    Mean,
    /// Value at the last output time (an `ENERGY` sensor's gives eq. 6.1 f₂).
    Final,
    /// Largest absolute value.
    Max,
    /// Root mean square (trapezoidal).
    Rms,
}

const STATISTICS: &[(&str, Statistic)] = &[
    ("MEAN", Statistic::Mean),
    ("FINAL", Statistic::Final),
    ("MAX", Statistic::Max),
    ("RMS", Statistic::Rms),
];

/// What a response is computed from.
#[derive(Debug, Clone, PartialEq)]
pub enum ResponseSource {
    /// An `MSENSOR` (by name) reduced by a statistic.
    Sensor { name: String, statistic: Statistic },
    /// The mechanism's mass at the design (`MASS`).
    Mass,
    /// The `mode`-th natural frequency (Hz, 1-based, ascending) of flexible body `body`'s
    /// pROM at the design (`FREQ`).
    Frequency { body: String, mode: u32 },
}

/// Reads SOURCE and STAT at fields `i`, `i + 1` and, for `FREQ`, BODY at field `body`.
fn source(f: &mut FieldReader, i: usize, body: usize) -> ResponseSource {
    let name = f.text(i, "SOURCE");
    let not_freq = |f: &mut FieldReader| {
        if !f.value(body).is_blank() {
            f.error(body, "BODY", "BODY is read only for SOURCE = FREQ");
        }
    };
    match name.as_str() {
        "MASS" => {
            if !f.value(i + 1).is_blank() {
                f.error(i + 1, "STAT", "MASS takes no STAT (leave it blank)");
            }
            not_freq(f);
            ResponseSource::Mass
        }
        "FREQ" => {
            let mode = f.count(i + 1, "STAT");
            let body = f.text(body, "BODY");
            ResponseSource::Frequency { body, mode }
        }
        _ => {
            let statistic = f.choice(i + 1, "STAT", STATISTICS, None);
            not_freq(f);
            ResponseSource::Sensor { name, statistic }
        }
    }
}

/// `DOBJ` — an objective.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | ID | int > 0 | required | id |
/// | 3 | NAME | name | required | the objective's name in the output |
/// | 4 | SENSE | `MIN`/`MAX` | required | minimize or maximize |
/// | 5 | SOURCE | name | required | an `MSENSOR` name; `MASS` (the mechanism's mass at the design: its bodies' invariants, exact in p, eq. 4.8); `FREQ` (a natural frequency of a flexible body's pROM at the design) |
/// | 6 | STAT | `MEAN`/`FINAL`/`MAX`/`RMS`; int > 0 | required (blank for MASS) | reduction over time; for FREQ the mode number n (1: the lowest flexible mode) |
/// | 7 | BODY | name | FREQ: required | the flexible body (FLEXB NAME) of FREQ |
#[derive(Debug, Clone, PartialEq)]
pub struct Dobj {
    pub id: u32,
    pub name: String,
    pub maximize: bool,
    pub source: ResponseSource,
    pub loc: Loc,
}

impl Dobj {
    /// Read a `DOBJ` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let id = f.id(1, "ID");
        f.set_id(id);
        let name = f.text(2, "NAME");
        let maximize = f.choice(3, "SENSE", &[("MIN", false), ("MAX", true)], None);
        let source = source(&mut f, 4, 6);
        let loc = f.loc();
        f.finish(6)?;
        Ok(Dobj {
            id,
            name,
            maximize,
            source,
            loc,
        })
    }
}

/// `DCONSTR` — a constraint: a response kept within bounds.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | ID | int > 0 | required | id |
/// | 3 | NAME | name | required | the constraint's name in the output |
/// | 4 | SOURCE | name | required | as DOBJ's: an `MSENSOR` name, `MASS` or `FREQ` |
/// | 5 | STAT | `MEAN`/`FINAL`/`MAX`/`RMS`; int > 0 | required (blank for MASS) | as DOBJ's |
/// | 6 | LOW | real | blank: none | lower bound |
/// | 7 | HIGH | real | blank: none | upper bound (at least one bound) |
/// | 8 | BODY | name | FREQ: required | as DOBJ's |
#[derive(Debug, Clone, PartialEq)]
pub struct Dconstr {
    pub id: u32,
    pub name: String,
    pub source: ResponseSource,
    pub low: Option<f64>,
    pub high: Option<f64>,
    pub loc: Loc,
}

impl Dconstr {
    /// Read a `DCONSTR` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let id = f.id(1, "ID");
        f.set_id(id);
        let name = f.text(2, "NAME");
        let source = source(&mut f, 3, 7);
        let low = f.opt_real(5, "LOW");
        let high = f.opt_real(6, "HIGH");
        match (low, high) {
            (None, None) => f.card_error("neither LOW nor HIGH given"),
            (Some(l), Some(h)) if l > h => f.error(
                5,
                "LOW",
                format!("LOW = {l:e} is greater than HIGH = {h:e}"),
            ),
            _ => {}
        }
        let loc = f.loc();
        f.finish(7)?;
        Ok(Dconstr {
            id,
            name,
            source,
            low,
            high,
            loc,
        })
    }
}

/// The search a `MOOPT` selects.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SearchMethod {
    /// NSGA-II for mixed continuous/discrete variables.
    Nsga2,
    /// Full-factorial grid, for validation.
    Grid,
    /// Gradient-based: a weighted-sum sweep per combination of the discrete values, each
    /// scalarization descended with the responses' sensitivities ([`crate::optimize::gradient`]).
    Grad,
}

/// `MOOPT` — the search of a `SOL OPTIMIZE` run (a deck has one).
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | ID | int > 0 | required | id |
/// | 3 | METHOD | `NSGA2`/`GRID`/`GRAD` | required | the search: NSGA-II, a full-factorial grid, or gradient-based (a weighted-sum sweep per combination of the discrete values, with the responses' exact sensitivities) |
/// | 4 | NEVAL | int > 0 | 100 | NSGA2, GRAD: evaluation budget; GRID: largest grid accepted |
/// | 5 | POP | int > 0 | NSGA2: 20; GRID: 3; GRAD: 5 | NSGA2: population size; GRID: levels of each continuous variable (bounds included; a discrete variable takes all its values); GRAD: most weights of the sweep per combination |
/// | 6 | SEED | int ≥ 0 | 1 | random seed (GRAD: unused, the search is deterministic) |
/// | 7 | NPAR | int ≥ 0 | 0 | parallel evaluations (0: one per core; GRAD evaluates one design after the other) |
/// | 8 | START | `NEW`/`RESUME` | `NEW` | `NEW`: a new journal of the evaluations (`<output>.designs-<subcase>.jsonl`); `RESUME`: the designs the existing journal holds are not evaluated again (the study, deterministic, proposes the same designs; not with GRAD, whose journal keeps no gradients) |
#[derive(Debug, Clone, PartialEq)]
pub struct Moopt {
    pub id: u32,
    pub method: SearchMethod,
    pub neval: u32,
    pub pop: u32,
    pub seed: u64,
    pub npar: usize,
    /// START = RESUME.
    pub resume: bool,
    pub loc: Loc,
}

impl Moopt {
    /// Read a `MOOPT` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let id = f.id(1, "ID");
        f.set_id(id);
        let keyword = f.keyword(2, "METHOD", &["NSGA2", "GRID", "GRAD"], None);
        let method = match keyword {
            "GRID" => SearchMethod::Grid,
            "GRAD" => SearchMethod::Grad,
            _ => SearchMethod::Nsga2,
        };
        let neval = f.opt_count(3, "NEVAL").unwrap_or(100);
        let default_pop = match method {
            SearchMethod::Grid => 3,
            SearchMethod::Grad => 5,
            SearchMethod::Nsga2 => 20,
        };
        let pop = f.opt_count(4, "POP").unwrap_or(default_pop);
        let seed = f.int_or(5, "SEED", 1);
        if seed < 0 {
            f.error(5, "SEED", format!("expected an integer ≥ 0, found {seed}"));
        }
        let npar = f.int_or(6, "NPAR", 0);
        if npar < 0 {
            f.error(6, "NPAR", format!("expected an integer ≥ 0, found {npar}"));
        }
        let resume = f.choice(7, "START", &[("NEW", false), ("RESUME", true)], Some(false));
        if resume && method == SearchMethod::Grad {
            f.error(
                7,
                "START",
                "RESUME with GRAD: the journal keeps no gradients to go on from (use NEW)",
            );
        }
        let loc = f.loc();
        f.finish(7)?;
        Ok(Moopt {
            id,
            method,
            neval,
            pop,
            seed: seed.max(0) as u64,
            npar: npar.max(0) as usize,
            resume,
            loc,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    use crate::deck::fields::card_from_line as card;

    /// The messages of a card that must be refused.
    fn refused<T: std::fmt::Debug>(r: Result<T, Vec<DeckError>>) -> String {
        r.expect_err("refused")
            .iter()
            .map(|e| e.to_string())
            .collect::<Vec<_>>()
            .join("\n")
    }

    #[test]
    fn cards_read_with_defaults() {
        let m = Dvmap::from_card(&card("DVMAP,1,10,IC.E,OC.E")).unwrap();
        assert_eq!(
            (m.desvar, m.targets),
            (10, vec!["IC.E".into(), "OC.E".into()])
        );
        let o = Dobj::from_card(&card("DOBJ,1,DEV,MIN,CDEV,MEAN")).unwrap();
        assert!(!o.maximize);
        assert_eq!(
            o.source,
            ResponseSource::Sensor {
                name: "CDEV".into(),
                statistic: Statistic::Mean
            }
        );
        let l = Promlib::from_card(&card("PROMLIB,3,C,6.,'c6.h5',8.,c8.h5")).unwrap();
        assert_eq!(
            (l.body.as_str(), l.entries),
            ("C", vec![(6.0, "c6.h5".into()), (8.0, "c8.h5".into())])
        );
        let m = Dobj::from_card(&card("DOBJ,2,M,MIN,MASS")).unwrap();
        assert_eq!(m.source, ResponseSource::Mass);
        let f = Dconstr::from_card(&card("DCONSTR,3,F2,FREQ,2,50.,,C")).unwrap();
        assert_eq!(
            f.source,
            ResponseSource::Frequency {
                body: "C".into(),
                mode: 2
            }
        );
        let c = Dconstr::from_card(&card("DCONSTR,2,TQ,TORQUE,MAX,,12.5")).unwrap();
        assert_eq!((c.low, c.high), (None, Some(12.5)));
        let g = Moopt::from_card(&card("MOOPT,1,GRID")).unwrap();
        assert_eq!(
            (g.method, g.neval, g.pop, g.seed, g.npar),
            (SearchMethod::Grid, 100, 3, 1, 0)
        );
        let n = Moopt::from_card(&card("MOOPT,1,NSGA2,40,8,7,2")).unwrap();
        assert_eq!(
            (n.method, n.neval, n.pop, n.seed, n.npar, n.resume),
            (SearchMethod::Nsga2, 40, 8, 7, 2, false)
        );
        let g = Moopt::from_card(&card("MOOPT,1,GRAD,30")).unwrap();
        assert_eq!((g.method, g.neval, g.pop), (SearchMethod::Grad, 30, 5));
        assert!(
            Moopt::from_card(&card("MOOPT,1,NSGA2,40,8,7,2,RESUME"))
                .unwrap()
                .resume
        );
    }

    #[test]
    fn bad_cards_are_refused_at_their_field() {
        let m = refused(Moopt::from_card(&card("MOOPT,1,GRAD,10,5,1,1,RESUME")));
        assert!(
            m.contains("field 8 (START)") && m.contains("RESUME with GRAD"),
            "{m}"
        );
        let m = refused(Dobj::from_card(&card("DOBJ,1,M,MIN,MASS,FINAL")));
        assert!(
            m.contains("field 6 (STAT)") && m.contains("MASS takes no STAT"),
            "{m}"
        );
        let m = refused(Dobj::from_card(&card("DOBJ,1,F,MAX,FREQ,1")));
        assert!(m.contains("field 7 (BODY)"), "{m}");
        let m = refused(Dobj::from_card(&card("DOBJ,1,F,MAX,FREQ,0,C")));
        assert!(m.contains("field 6 (STAT)"), "{m}");
        let m = refused(Dconstr::from_card(&card("DCONSTR,1,D,CDEV,MEAN,,1.,C")));
        assert!(
            m.contains("field 8 (BODY)") && m.contains("only for SOURCE = FREQ"),
            "{m}"
        );
        let m = refused(Dobj::from_card(&card("DOBJ,1,D,LOW,CDEV,MEAN")));
        assert!(m.contains("SENSE"), "{m}");
        let m = refused(Dconstr::from_card(&card("DCONSTR,1,D,CDEV,MEAN")));
        assert!(m.contains("neither LOW nor HIGH"), "{m}");
        let m = refused(Dconstr::from_card(&card("DCONSTR,1,D,CDEV,MEAN,2.,1.")));
        assert!(m.contains("LOW = 2e0 is greater than HIGH"), "{m}");
        let m = refused(Dvmap::from_card(&card("DVMAP,1,10")));
        assert!(m.contains("no TARGET"), "{m}");
        let m = refused(Promlib::from_card(&card("PROMLIB,1,C,4.,'a.h5',4.,'b.h5'")));
        assert!(
            m.contains("field 6 (V2)") && m.contains("listed twice"),
            "{m}"
        );
        let m = refused(Promlib::from_card(&card("PROMLIB,1,C")));
        assert!(m.contains("no value and artifact"), "{m}");
    }
}
