//! Design-optimization cards of `SOL OPTIMIZE` (DESIGN.md §12): `DVMAP` (what a design
//! variable sets), `DOBJ` (objectives), `DCONSTR` (constraints), `MOOPT` (the search). The
//! design variables themselves are Nastran's `DESVAR` and `DDVAL` ([`super::design`]).

use crate::deck::error::{DeckError, Loc};
use crate::deck::fields::RawCard;
use crate::deck::reader::FieldReader;

/// `DVMAP` — the parameters a design variable sets.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | ID | int > 0 | required | id |
/// | 3 | DESVAR | int > 0 | required | the DESVAR id |
/// | 4 … | TARGET1 TARGET2 … | name | ≥ 1 | `BODY.PMPAR` parameters set to the variable's value (one variable may set both sides of a link) |
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
}

/// Reads SOURCE and STAT at fields `i`, `i + 1`.
fn source(f: &mut FieldReader, i: usize) -> ResponseSource {
    let name = f.text(i, "SOURCE");
    if name == "MASS" || name == "FREQ" {
        f.error(
            i,
            "SOURCE",
            format!("{name} responses are not available in this version (use an MSENSOR name)"),
        );
    }
    let statistic = f.choice(i + 1, "STAT", STATISTICS, None);
    ResponseSource::Sensor { name, statistic }
}

/// `DOBJ` — an objective.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | ID | int > 0 | required | id |
/// | 3 | NAME | name | required | the objective's name in the output |
/// | 4 | SENSE | `MIN`/`MAX` | required | minimize or maximize |
/// | 5 | SOURCE | name | required | an `MSENSOR` name |
/// | 6 | STAT | `MEAN`/`FINAL`/`MAX`/`RMS` | required | reduction over time |
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
        let source = source(&mut f, 4);
        let loc = f.loc();
        f.finish(5)?;
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
/// | 4 | SOURCE | name | required | an `MSENSOR` name |
/// | 5 | STAT | `MEAN`/`FINAL`/`MAX`/`RMS` | required | reduction over time |
/// | 6 | LOW | real | blank: none | lower bound |
/// | 7 | HIGH | real | blank: none | upper bound (at least one bound) |
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
        let source = source(&mut f, 3);
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
        f.finish(6)?;
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
}

/// `MOOPT` — the search of a `SOL OPTIMIZE` run (a deck has one).
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | ID | int > 0 | required | id |
/// | 3 | METHOD | `NSGA2`/`GRID` | required | the search (`GRAD` is refused: not available in this version) |
/// | 4 | NEVAL | int > 0 | 100 | NSGA2: evaluation budget; GRID: largest grid accepted |
/// | 5 | POP | int > 0 | NSGA2: 20; GRID: 3 | NSGA2: population size; GRID: levels of each continuous variable (bounds included; a discrete variable takes all its values) |
/// | 6 | SEED | int ≥ 0 | 1 | random seed |
/// | 7 | NPAR | int ≥ 0 | 0 | parallel evaluations (0: one per core) |
#[derive(Debug, Clone, PartialEq)]
pub struct Moopt {
    pub id: u32,
    pub method: SearchMethod,
    pub neval: u32,
    pub pop: u32,
    pub seed: u64,
    pub npar: usize,
    pub loc: Loc,
}

impl Moopt {
    /// Read a `MOOPT` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let id = f.id(1, "ID");
        f.set_id(id);
        let keyword = f.keyword(2, "METHOD", &["NSGA2", "GRID", "GRAD"], None);
        if keyword == "GRAD" {
            f.error(
                2,
                "METHOD",
                "GRAD (gradient-based search with parametric sensitivities) is not available in this version: use NSGA2 or GRID",
            );
        }
        let method = if keyword == "GRID" {
            SearchMethod::Grid
        } else {
            SearchMethod::Nsga2
        };
        let neval = f.opt_count(3, "NEVAL").unwrap_or(100);
        let default_pop = if method == SearchMethod::Grid { 3 } else { 20 };
        let pop = f.opt_count(4, "POP").unwrap_or(default_pop);
        let seed = f.int_or(5, "SEED", 1);
        if seed < 0 {
            f.error(5, "SEED", format!("expected an integer ≥ 0, found {seed}"));
        }
        let npar = f.int_or(6, "NPAR", 0);
        if npar < 0 {
            f.error(6, "NPAR", format!("expected an integer ≥ 0, found {npar}"));
        }
        let loc = f.loc();
        f.finish(6)?;
        Ok(Moopt {
            id,
            method,
            neval,
            pop,
            seed: seed.max(0) as u64,
            npar: npar.max(0) as usize,
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
        let c = Dconstr::from_card(&card("DCONSTR,2,TQ,TORQUE,MAX,,12.5")).unwrap();
        assert_eq!((c.low, c.high), (None, Some(12.5)));
        let g = Moopt::from_card(&card("MOOPT,1,GRID")).unwrap();
        assert_eq!(
            (g.method, g.neval, g.pop, g.seed, g.npar),
            (SearchMethod::Grid, 100, 3, 1, 0)
        );
        let n = Moopt::from_card(&card("MOOPT,1,NSGA2,40,8,7,2")).unwrap();
        assert_eq!(
            (n.method, n.neval, n.pop, n.seed, n.npar),
            (SearchMethod::Nsga2, 40, 8, 7, 2)
        );
    }

    #[test]
    fn bad_cards_are_refused_at_their_field() {
        let m = refused(Moopt::from_card(&card("MOOPT,1,GRAD")));
        assert!(m.contains("GRAD") && m.contains("not available"), "{m}");
        let m = refused(Dobj::from_card(&card("DOBJ,1,M,MIN,MASS,FINAL")));
        assert!(m.contains("MASS responses are not available"), "{m}");
        let m = refused(Dobj::from_card(&card("DOBJ,1,D,LOW,CDEV,MEAN")));
        assert!(m.contains("SENSE"), "{m}");
        let m = refused(Dconstr::from_card(&card("DCONSTR,1,D,CDEV,MEAN")));
        assert!(m.contains("neither LOW nor HIGH"), "{m}");
        let m = refused(Dconstr::from_card(&card("DCONSTR,1,D,CDEV,MEAN,2.,1.")));
        assert!(m.contains("LOW = 2e0 is greater than HIGH"), "{m}");
        let m = refused(Dvmap::from_card(&card("DVMAP,1,10")));
        assert!(m.contains("no TARGET"), "{m}");
    }
}
