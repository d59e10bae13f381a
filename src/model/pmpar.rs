//! `PMPAR` checks: unique ids and names, REFID by KIND, bounds and nominal value.
//!
//! | KIND | REFID | nominal value |
//! |---|---|---|
//! | E, RHO, NU | MAT1 | E, RHO, NU of the MAT1 |
//! | THETA | PCOMP | the common magnitude Θ of the ply angles, which must all be +Θ or −Θ |
//! | TPLY | PCOMP | the common ply thickness, which all plies must share |
//! | K | PELAS | K |
//! | MASS | CONM2 (element id) | M |
//!
//! Errors: LOW > HIGH, nominal outside [LOW, HIGH], non-finite bounds, a range leaving the
//! values its card accepts ([`domain`]: a pROM is sampled and evaluated anywhere in the box), a
//! THETA laminate whose angles are not ±Θ of one Θ, a TPLY laminate with unequal ply
//! thicknesses.

use crate::deck::cards::Pmpar;
use crate::deck::{BulkData, DeckError};

use super::Model;
use crate::card_values::PmparKind;

use super::build::Refs;
use super::ids::{entry, index};

/// Relative tolerance for "equal" ply angle magnitudes and thicknesses.
pub const EQUAL_REL: f64 = 1e-9;

/// Run the checks.
pub fn check(refs: &Refs, errors: &mut Vec<DeckError>) {
    let b = refs.bulk;
    index(
        b.pmpar
            .iter()
            .map(|p| entry(p.id, "PMPAR", &p.loc, ()))
            .collect(),
        "PMPAR",
        errors,
    );
    index(
        b.pmpar
            .iter()
            .map(|p| entry(p.name.to_ascii_uppercase(), "PMPAR", &p.loc, ()))
            .collect(),
        "PMPAR name",
        errors,
    );
    for p in &b.pmpar {
        let card = format!("PMPAR {}", p.id);
        let err = |m: String| DeckError::at(&p.loc, m).on_card(card.clone());
        if !p.low.is_finite() || !p.high.is_finite() {
            errors.push(err("LOW and HIGH must be finite".into()));
            continue;
        }
        if p.low > p.high {
            errors.push(err(format!("LOW = {} > HIGH = {}", p.low, p.high)));
        }
        if let Some(d) = domain(p.kind)
            && !((d.contains)(p.low) && (d.contains)(p.high))
        {
            errors.push(err(format!("[LOW, HIGH] = [{:e}, {:e}] leaves the values {} {} accepts ({}): the pROM is sampled and evaluated over the whole range", p.low, p.high, p.kind.target_card(), p.kind.name(), d.rule)));
        }
        match nominal(refs.bulk, p) {
            Err(message) => errors.push(err(message)),
            Ok(value) if value < p.low || value > p.high => errors.push(err(format!(
                "nominal {} = {value} (from {} {}) lies outside [LOW, HIGH] = [{}, {}]",
                p.kind.name(),
                p.kind.target_card(),
                p.refid,
                p.low,
                p.high
            ))),
            Ok(_) => {}
        }
    }
}

/// The values the referenced card accepts for a parameter, as the card checks
/// (`super::values`).
pub struct Domain {
    /// The rule as text, e.g. "E > 0".
    pub rule: &'static str,
    /// Whether one value satisfies it.
    pub contains: fn(f64) -> bool,
}

/// The [`Domain`] of a parameter of `kind`: MAT1 E > 0, −1 < NU < 0.5, RHO ≥ 0; PCOMP ply
/// thickness > 0; CONM2 M ≥ 0. None: any finite value (ply angle, PELAS K).
pub fn domain(kind: PmparKind) -> Option<Domain> {
    let (rule, contains): (&'static str, fn(f64) -> bool) = match kind {
        PmparKind::E => ("E > 0", |v| v > 0.0),
        PmparKind::Nu => ("−1 < NU < 0.5", |v| v > -1.0 && v < 0.5),
        PmparKind::Rho => ("RHO ≥ 0", |v| v >= 0.0),
        PmparKind::Tply => ("ply thickness > 0", |v| v > 0.0),
        PmparKind::Mass => ("M ≥ 0", |v| v >= 0.0),
        PmparKind::Theta | PmparKind::K => return None,
    };
    Some(Domain { rule, contains })
}

/// A PMPAR with its nominal value: what it scales (KIND on the entity REFID) within
/// [LOW, HIGH].
#[derive(Debug, Clone, PartialEq)]
pub struct Parameter {
    pub name: String,
    pub kind: PmparKind,
    /// Id of the MAT1, PCOMP, PELAS or CONM2 element it acts on.
    pub entity: u32,
    pub low: f64,
    pub high: f64,
    /// The referenced card's value ([`nominal`]).
    pub nominal: f64,
}

/// A parameter whose nominal value cannot be read.
#[derive(Debug, Clone, PartialEq)]
pub struct ParameterError {
    pub name: String,
    pub reason: String,
}

impl Model {
    /// The PMPARs in card order, each with its nominal value; the first one without a value is
    /// an error (a built model has none).
    pub fn parameters(&self) -> Result<Vec<Parameter>, ParameterError> {
        self.bulk
            .pmpar
            .iter()
            .map(|p| {
                let nominal = nominal(&self.bulk, p).map_err(|reason| ParameterError {
                    name: p.name.clone(),
                    reason,
                })?;
                Ok(Parameter {
                    name: p.name.clone(),
                    kind: p.kind,
                    entity: p.refid,
                    low: p.low,
                    high: p.high,
                    nominal,
                })
            })
            .collect()
    }
}

/// The nominal value of a parameter: the referenced card's value.
pub fn nominal(b: &BulkData, p: &Pmpar) -> Result<f64, String> {
    let missing = || {
        format!(
            "REFID = {} does not exist (no {} {}) for KIND = {}",
            p.refid,
            p.kind.target_card(),
            p.refid,
            p.kind.name()
        )
    };
    match p.kind {
        PmparKind::E | PmparKind::Rho | PmparKind::Nu => {
            if b.mat2.iter().any(|m| m.id == p.refid) {
                return Err(format!(
                    "REFID = {} is a MAT2; KIND = {} acts on a MAT1 (a MAT2 gives its matrix G11 … G33 directly, with no E or NU the affine split could scale)",
                    p.refid,
                    p.kind.name()
                ));
            }
            let m = b
                .mat1
                .iter()
                .find(|m| m.id == p.refid)
                .ok_or_else(missing)?;
            Ok(match p.kind {
                PmparKind::E => m.e,
                PmparKind::Rho => m.rho,
                _ => m.nu,
            })
        }
        PmparKind::Theta => {
            let c = b
                .pcomp
                .iter()
                .find(|c| c.id == p.refid)
                .ok_or_else(missing)?;
            let first = c
                .plies
                .first()
                .map(|ply| ply.theta.abs())
                .ok_or_else(|| "the PCOMP has no ply".to_string())?;
            for (k, ply) in c.plies.iter().enumerate() {
                if (ply.theta.abs() - first).abs() > EQUAL_REL * first.max(1.0) {
                    return Err(format!(
                        "KIND = THETA needs every ply angle of PCOMP {} to be +Θ or −Θ of one Θ; ply 1 has {} and ply {} has {}",
                        c.id,
                        c.plies[0].theta,
                        k + 1,
                        ply.theta
                    ));
                }
            }
            Ok(first)
        }
        PmparKind::Tply => {
            let c = b
                .pcomp
                .iter()
                .find(|c| c.id == p.refid)
                .ok_or_else(missing)?;
            let first = c
                .plies
                .first()
                .map(|ply| ply.t)
                .ok_or_else(|| "the PCOMP has no ply".to_string())?;
            for (k, ply) in c.plies.iter().enumerate() {
                if (ply.t - first).abs() > EQUAL_REL * first.abs() {
                    return Err(format!(
                        "KIND = TPLY needs equal ply thicknesses in PCOMP {}; ply 1 has {} and ply {} has {}",
                        c.id,
                        first,
                        k + 1,
                        ply.t
                    ));
                }
            }
            Ok(first)
        }
        PmparKind::K => b
            .pelas
            .iter()
            .find(|e| e.id == p.refid)
            .map(|e| e.k)
            .ok_or_else(missing),
        PmparKind::Mass => b
            .conm2
            .iter()
            .find(|c| c.id == p.refid)
            .map(|c| c.mass)
            .ok_or_else(missing),
    }
}
