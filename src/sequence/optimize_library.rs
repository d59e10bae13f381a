//! `PROMLIB` in a study: a discrete design variable that chooses a flexible body's pROM
//! artifact (thesis §6.3.1: the ply count of a composite link), one artifact per value.
//!
//! A `DVMAP` target that is a body's NAME (no `.PMPAR`) makes its DESVAR choose that body's
//! artifact from the body's `PROMLIB`. Each artifact a value of the variable names is read
//! once, when the study is checked (one read per distinct path), and checked against the
//! mechanism: the system is built with it in place of the FLEXB's artifact (every MARKER
//! grid an interface grid, every STRAIN sensor present) and each MARKER grid of the body must
//! sit where it sits in the FLEXB's artifact (the joints are assembled from those positions).
//!
//! Refused, each at its card and field: a target that is neither `BODY.PMPAR` nor a FLEXB, a
//! body without a `PROMLIB` or with two, a continuous variable choosing an artifact, two
//! variables choosing one body's artifact, a value of the variable with no artifact, an
//! artifact that cannot be read or does not fit, a `PROMLIB` no `DVMAP` uses.

use std::path::PathBuf;

use super::fmb::{LoadedArtifact, PreparedFmb};
use super::optimize_study::at;
use crate::deck::cards::{BulkData, Desvar, Dvmap, Promlib};
use crate::discretize::prom_body::read_parametric_body;
use crate::model::mechanism::{BodyKind, MarkerPlace};
use crate::optimize::{Domain, Variable};

/// A body whose artifact a variable chooses.
#[derive(Debug, Clone)]
pub struct Library {
    /// Index of the variable in the design space.
    pub variable: usize,
    /// Index of the body in the mechanism.
    pub body: usize,
    /// For every value of the variable: the value and its artifact (index into
    /// [`Libraries::artifacts`]).
    pub choices: Vec<(f64, usize)>,
}

/// The study's libraries and their artifacts, each read once.
#[derive(Debug, Clone, Default)]
pub struct Libraries {
    pub libraries: Vec<Library>,
    pub artifacts: Vec<LoadedArtifact>,
}

/// What a `DVMAP` target that names a body is checked against.
pub struct Target<'a> {
    pub desvar: &'a Desvar,
    pub variable: &'a Variable,
    /// The variable's index in the design space.
    pub index: usize,
    pub dvmap: &'a Dvmap,
    /// The target's position among the DVMAP's targets (0-based).
    pub position: usize,
    pub body: &'a str,
}

/// The field of the DVMAP's target.
fn target_field(t: &Target) -> String {
    format!("field {} (TARGET{})", t.position + 4, t.position + 1)
}

/// The field of a PROMLIB's `k`-th path (0-based).
fn path_field(k: usize) -> String {
    format!("field {} (PATH{})", 2 * k + 5, k + 1)
}

impl Libraries {
    /// The artifacts `design` chooses: (body index, artifact) per library.
    pub fn artifacts_of(&self, design: &[f64]) -> Result<Vec<(usize, &LoadedArtifact)>, String> {
        self.libraries
            .iter()
            .map(|l| {
                let x = design[l.variable];
                let (_, a) = (l.choices.iter()).find(|(v, _)| *v == x).ok_or_else(|| {
                    format!(
                        "no artifact for the value {x:e} of variable {}",
                        l.variable + 1
                    )
                })?;
                Ok((l.body, &self.artifacts[*a]))
            })
            .collect()
    }

    /// The artifacts body `body` may take, when a variable chooses its artifact.
    pub fn candidates(&self, body: usize) -> Option<Vec<(f64, &LoadedArtifact)>> {
        let library = self.libraries.iter().find(|l| l.body == body)?;
        Some(
            (library.choices.iter())
                .map(|(v, a)| (*v, &self.artifacts[*a]))
                .collect(),
        )
    }

    /// Adds the library of target `t` (its DESVAR chooses body `t.body`'s artifact): every
    /// error pushed onto `errors`, at its card and field.
    pub fn add(
        &mut self,
        bulk: &BulkData,
        prepared: &PreparedFmb,
        t: &Target,
        errors: &mut Vec<String>,
    ) {
        let dvmap_error = |message: String| {
            at(
                &t.dvmap.loc,
                format!("DVMAP {}", t.dvmap.id),
                &target_field(t),
                message,
            )
        };
        let mechanism = &prepared.pfmb.mechanism;
        let Some(body) = (mechanism.bodies.iter()).position(|b| {
            b.name.eq_ignore_ascii_case(t.body) && matches!(b.kind, BodyKind::Flexible { .. })
        }) else {
            errors.push(dvmap_error(format!(
                "{} is neither BODY.PMPAR nor the NAME of a FLEXB of this mechanism (parameters: {}; flexible bodies: {})",
                t.body,
                prepared.pfmb.parameter_names().join(", "),
                prepared.pfmb.flexible().map(|(n, _)| n).collect::<Vec<_>>().join(" ")
            )));
            return;
        };
        let name = &mechanism.bodies[body].name;
        let Some(card) = (bulk.promlib.iter()).find(|p| p.body.eq_ignore_ascii_case(name)) else {
            errors.push(dvmap_error(format!(
                "body {name} has no PROMLIB (the artifacts DESVAR {} chooses from)",
                t.desvar.id
            )));
            return;
        };
        let Domain::Discrete { values } = &t.variable.domain else {
            errors.push(dvmap_error(format!(
                "DESVAR {} is continuous: a variable choosing body {name}'s artifact (PROMLIB {}) takes discrete values (give the DESVAR a DDVAL)",
                t.desvar.id, card.id
            )));
            return;
        };
        if let Some(other) = self.libraries.iter().find(|l| l.body == body) {
            errors.push(dvmap_error(format!(
                "body {name}'s artifact is already chosen by variable {} (one variable per body)",
                other.variable + 1
            )));
            return;
        }
        let mut choices = Vec::new();
        for &value in values {
            let Some(k) = card.entries.iter().position(|(v, _)| *v == value) else {
                errors.push(at(
                    &card.loc,
                    format!("PROMLIB {}", card.id),
                    "field 4 (V1)",
                    format!(
                        "DESVAR {} takes the value {value:e} (its DDVAL), which has no artifact here (values: {})",
                        t.desvar.id,
                        (card.entries.iter())
                            .map(|(v, _)| format!("{v:e}"))
                            .collect::<Vec<_>>()
                            .join(" ")
                    ),
                ));
                continue;
            };
            match self.artifact(prepared, card, k, body) {
                Ok(a) => choices.push((value, a)),
                Err(message) => {
                    let e = at(
                        &card.loc,
                        format!("PROMLIB {}", card.id),
                        &path_field(k),
                        message,
                    );
                    if !errors.contains(&e) {
                        errors.push(e);
                    }
                }
            }
        }
        self.libraries.push(Library {
            variable: t.index,
            body,
            choices,
        });
    }

    /// The index of the `k`-th artifact of `card` for body `body`: read and checked against
    /// the mechanism on first use.
    fn artifact(
        &mut self,
        prepared: &PreparedFmb,
        card: &Promlib,
        k: usize,
        body: usize,
    ) -> Result<usize, String> {
        let (value, written) = &card.entries[k];
        let path: PathBuf = (card.loc.file.parent())
            .map_or_else(|| PathBuf::from(written), |dir| dir.join(written));
        if let Some(i) = self.artifacts.iter().position(|a| a.path == path) {
            return Ok(i);
        }
        let shown = format!("'{written}' (value {value:e})");
        let data = read_parametric_body(&path).map_err(|e| format!("{shown}: {e}"))?;
        let artifact = LoadedArtifact { path, data };
        fits(prepared, body, &artifact).map_err(|e| {
            format!(
                "{shown} does not fit body {}: {e}",
                prepared.pfmb.mechanism.bodies[body].name
            )
        })?;
        self.artifacts.push(artifact);
        Ok(self.artifacts.len() - 1)
    }

    /// The PROMLIB cards no DVMAP targets (or that name no FLEXB, or repeat a body), as
    /// errors.
    pub fn unused(bulk: &BulkData, prepared: &PreparedFmb, errors: &mut Vec<String>) {
        let mechanism = &prepared.pfmb.mechanism;
        for (i, card) in bulk.promlib.iter().enumerate() {
            let error = |message: String| {
                at(
                    &card.loc,
                    format!("PROMLIB {}", card.id),
                    "field 3 (BODY)",
                    message,
                )
            };
            let same_body = |p: &Promlib| p.body.eq_ignore_ascii_case(&card.body);
            if bulk.promlib[..i].iter().any(same_body) {
                errors.push(error(format!("body {} has a PROMLIB already", card.body)));
                continue;
            }
            match (mechanism.bodies.iter()).position(|b| b.name.eq_ignore_ascii_case(&card.body)) {
                Some(b) if matches!(mechanism.bodies[b].kind, BodyKind::Flexible { .. }) => {
                    let targeted = (bulk.dvmap.iter().flat_map(|m| &m.targets))
                        .any(|t| t.eq_ignore_ascii_case(&card.body));
                    if !targeted {
                        errors.push(error(format!(
                            "no DVMAP chooses body {}'s artifact: map a discrete DESVAR onto {}",
                            card.body, card.body
                        )));
                    }
                }
                _ => errors.push(error(format!(
                    "{} is no FLEXB of this mechanism",
                    card.body
                ))),
            }
        }
    }
}

/// Checks that `artifact` can stand in for body `body`'s FLEXB artifact: the system builds
/// with it (interface grids of the MARKERs, STRAIN sensors) and every MARKER grid of the body
/// sits where it sits in the FLEXB's artifact.
fn fits(prepared: &PreparedFmb, body: usize, artifact: &LoadedArtifact) -> Result<(), String> {
    let pfmb = &prepared.pfmb;
    let own = pfmb.bodies[body]
        .as_ref()
        .expect("a PROMLIB's body is a FLEXB");
    for m in pfmb
        .mechanism
        .markers
        .iter()
        .filter(|m| m.body == Some(body))
    {
        let MarkerPlace::Grid(grid) = m.place else {
            continue;
        };
        let position = |data: &crate::discretize::prom_body::ParametricBody| {
            (data.interfaces.iter())
                .find(|r| r.grid == grid)
                .map(|r| r.position)
        };
        let (Some(want), Some(got)) = (position(own), position(&artifact.data)) else {
            continue; // a missing interface grid is the system's error, below
        };
        // the same mesh gives the same coordinates to the last bit; a tolerance of 1e-9
        // relative to the coordinates' size admits only round-off of another writer
        let scale = want
            .iter()
            .chain(&got)
            .fold(1e-30_f64, |s, x| s.max(x.abs()));
        if want
            .iter()
            .zip(&got)
            .any(|(a, b)| (a - b).abs() > 1e-9 * scale)
        {
            return Err(format!(
                "interface grid {grid} (MARKER {}) is at {got:?} in it and at {want:?} in the FLEXB's artifact",
                m.id
            ));
        }
    }
    prepared.systems_at(&[], &[(body, artifact)]).map(|_| ())
}
