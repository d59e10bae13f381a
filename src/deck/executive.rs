//! Executive control: `SOL`, `CEND` and the statements other solvers' decks carry (`ID`, `TIME`,
//! `DIAG`, `APP`), which are accepted and recorded.

use super::error::{DeckError, Diagnostics, Loc};

/// The solution sequence requested by `SOL`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub enum Solution {
    /// `SOL 101`, `SESTATIC`, `STATICS`.
    Statics,
    /// `SOL 103`, `SEMODES`, `MODAL`.
    Modal,
    /// `SOL 108`, `SEDFREQ`: direct frequency response.
    FrfDirect,
    /// `SOL 111`, `SEMFREQ`: modal frequency response.
    FrfModal,
    /// `SOL FRF`: frequency response, method chosen by paraflex (direct on a mesh, reduced on a ROM).
    Frf,
    /// `SOL 109`, `SEDTRAN`: direct transient response.
    TransientDirect,
    /// `SOL 112`, `SEMTRAN`: modal transient response.
    TransientModal,
    /// `SOL TRANSIENT`.
    Transient,
    /// `SOL PROM`: parametric reduced-order model build.
    Prom,
    /// `SOL FMB`: flexible multibody.
    Fmb,
    /// `SOL ESTIMATE`: virtual sensing.
    Estimate,
    /// `SOL OPTIMIZE`: multi-objective design optimization.
    Optimize,
    /// A Nastran solution sequence paraflex knows but does not run (buckling, nonlinear,
    /// cyclic, aeroelastic, heat transfer, design optimization …): its name from
    /// [`Solution::NOT_RUN`]. The deck is read and checked; `run` stops with "not available".
    NotRun(&'static str),
}

impl Solution {
    const NAMES: &'static [(&'static str, Solution)] = &[
        ("101", Solution::Statics),
        ("SESTATIC", Solution::Statics),
        ("STATICS", Solution::Statics),
        ("103", Solution::Modal),
        ("SEMODES", Solution::Modal),
        ("MODAL", Solution::Modal),
        ("108", Solution::FrfDirect),
        ("SEDFREQ", Solution::FrfDirect),
        ("111", Solution::FrfModal),
        ("SEMFREQ", Solution::FrfModal),
        ("FRF", Solution::Frf),
        ("109", Solution::TransientDirect),
        ("SEDTRAN", Solution::TransientDirect),
        ("112", Solution::TransientModal),
        ("SEMTRAN", Solution::TransientModal),
        ("TRANSIENT", Solution::Transient),
        ("PROM", Solution::Prom),
        ("FMB", Solution::Fmb),
        ("ESTIMATE", Solution::Estimate),
        ("OPTIMIZE", Solution::Optimize),
    ];

    /// The Nastran solution sequences paraflex recognizes without running them, by number
    /// and by name: (number, name, what it solves). The one list of them.
    pub const NOT_RUN: &'static [(&'static str, &'static str, &'static str)] = &[
        ("105", "SEBUCKL", "linear buckling"),
        ("106", "NLSTATIC", "nonlinear statics"),
        ("107", "SEDCEIG", "direct complex eigenvalues"),
        ("110", "SEMCEIG", "modal complex eigenvalues"),
        ("114", "CYCSTATX", "cyclic symmetry statics"),
        ("115", "CYCMODE", "cyclic symmetry normal modes"),
        ("116", "CYCBUCKL", "cyclic symmetry buckling"),
        ("118", "CYCFREQ", "cyclic symmetry frequency response"),
        ("128", "SENLHARM", "nonlinear harmonic response"),
        ("129", "NLTRAN", "nonlinear transient response"),
        ("144", "AESTAT", "static aeroelastic response"),
        ("145", "SEFLUTTR", "aerodynamic flutter"),
        ("146", "SEAERO", "dynamic aeroelastic response"),
        ("153", "NLSCSH", "steady nonlinear heat transfer"),
        ("159", "NLTCSH", "transient nonlinear heat transfer"),
        ("187", "DDAM", "dynamic design analysis"),
        ("200", "DESOPT", "design optimization"),
        ("400", "NONLIN", "implicit nonlinear"),
        ("401", "NLSTAT", "multi-step nonlinear statics"),
        ("402", "NLDYN", "multi-step nonlinear dynamics"),
        ("600", "SOL600", "nonlinear (Marc)"),
        ("601", "ADVNL", "advanced nonlinear"),
        ("700", "SOL700", "explicit nonlinear"),
        ("701", "ADVNLEXP", "advanced explicit nonlinear"),
    ];

    /// Parse the argument of `SOL` (number or name, case-insensitive): a sequence paraflex
    /// has, or one of [`Self::NOT_RUN`].
    pub fn parse(text: &str) -> Option<Solution> {
        let t = text.trim();
        Self::NAMES
            .iter()
            .find(|(n, _)| n.eq_ignore_ascii_case(t))
            .map(|(_, s)| *s)
            .or_else(|| {
                Self::NOT_RUN
                    .iter()
                    .find(|(number, name, _)| {
                        number.eq_ignore_ascii_case(t) || name.eq_ignore_ascii_case(t)
                    })
                    .map(|(_, _, what)| Solution::NotRun(what))
            })
    }

    /// The name paraflex uses for the sequence.
    pub fn name(self) -> &'static str {
        match self {
            Solution::Statics => "STATICS",
            Solution::Modal => "MODAL",
            Solution::FrfDirect | Solution::FrfModal | Solution::Frf => "FRF",
            Solution::TransientDirect | Solution::TransientModal | Solution::Transient => {
                "TRANSIENT"
            }
            Solution::Prom => "PROM",
            Solution::Fmb => "FMB",
            Solution::Estimate => "ESTIMATE",
            Solution::Optimize => "OPTIMIZE",
            Solution::NotRun(what) => what,
        }
    }
}

/// The executive control section.
#[derive(Debug, Clone, Default, serde::Serialize)]
pub struct Executive {
    /// The requested solution and the text it was given as (`103`, `SEMODES`, …).
    pub sol: Option<(Solution, String)>,
    /// Position of the `SOL` statement.
    #[serde(skip)]
    pub sol_loc: Option<Loc>,
    /// Statements accepted and recorded without effect (`ID`, `TIME`, `DIAG`, `APP`, …), as written.
    pub recorded: Vec<String>,
}

/// Statements from other solvers' decks that paraflex records without acting on them.
const RECORDED: &[&str] = &[
    "ID",
    "TIME",
    "DIAG",
    "APP",
    "ECHOON",
    "ECHOOFF",
    "GEOMCHECK",
    "NASTRAN",
    "INIT",
    "ASSIGN",
];

impl Executive {
    /// Read one executive-control line (comments already removed).
    pub fn read_line(&mut self, loc: &Loc, text: &str, diag: &mut Diagnostics) {
        let text = text.trim();
        let keyword: String = text
            .chars()
            .take_while(|c| c.is_ascii_alphanumeric())
            .collect::<String>()
            .to_ascii_uppercase();
        let rest = text[keyword.len()..].trim().trim_start_matches(',').trim();
        match keyword.as_str() {
            "SOL" => {
                let arg = rest.split([' ', ',']).next().unwrap_or("");
                match Solution::parse(arg) {
                    Some(sol) => {
                        if self.sol.is_some() {
                            diag.error(DeckError::at(loc, "SOL given twice").on_card("SOL"));
                        }
                        self.sol = Some((sol, arg.to_ascii_uppercase()));
                        self.sol_loc = Some(loc.clone());
                    }
                    None => diag.error(
                        DeckError::at(
                            loc,
                            format!(
                                "unknown solution '{arg}'; expected one of {}",
                                Solution::NAMES.iter().map(|(n, _)| *n).collect::<Vec<_>>().join(", ")
                            ),
                        )
                        .on_card("SOL"),
                    ),
                }
            }
            k if RECORDED.contains(&k) => self.recorded.push(text.to_string()),
            _ => diag.error(DeckError::at(
                loc,
                format!(
                    "unsupported executive control statement '{}': paraflex accepts SOL, CEND and records {}",
                    text,
                    RECORDED.join(", ")
                ),
            )),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;
    use std::sync::Arc;

    #[test]
    fn sol_numbers_and_names() {
        assert_eq!(Solution::parse("103"), Some(Solution::Modal));
        assert_eq!(Solution::parse("semodes"), Some(Solution::Modal));
        assert_eq!(Solution::parse("PROM"), Some(Solution::Prom));
        assert_eq!(Solution::parse("999"), None);
    }

    /// Nastran sequences paraflex does not run are recognized (by number or name) so that
    /// `run` can say "not available" instead of "unknown solution".
    #[test]
    fn known_nastran_sequences_are_recognized_not_run() {
        for (text, what) in [
            ("200", "design optimization"),
            ("106", "nonlinear statics"),
            ("144", "static aeroelastic response"),
            ("sebuckl", "linear buckling"),
        ] {
            assert_eq!(
                Solution::parse(text),
                Some(Solution::NotRun(what)),
                "{text}"
            );
        }
        assert_eq!(Solution::parse("104"), None);
    }

    #[test]
    fn records_and_rejects() {
        let loc = Loc::new(&Arc::from(Path::new("d.dat")), 1);
        let mut e = Executive::default();
        let mut d = Diagnostics::default();
        e.read_line(&loc, "ID MSC, TEST", &mut d);
        e.read_line(&loc, "TIME 600", &mut d);
        e.read_line(&loc, "sol 101", &mut d);
        e.read_line(&loc, "COMPILE SEMODES", &mut d);
        assert_eq!(e.sol.as_ref().unwrap().0, Solution::Statics);
        assert_eq!(e.recorded.len(), 2);
        assert_eq!(d.errors.len(), 1);
        assert!(d.errors[0].to_string().contains("COMPILE"));
    }
}
