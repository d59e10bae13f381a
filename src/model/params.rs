//! The `PARAM`s paraflex uses, in one table ([`KNOWN_PARAMS`]), and their values.
//!
//! Bulk `PARAM` cards and case-control `PARAM` statements are both read; a case-control value
//! overrides a bulk value (they apply to every subcase, as paraflex does not scope PARAMs).
//! A bad value of a known PARAM is an error; unknown names are accepted and listed in ONE
//! warning ("accepted and ignored: …"). Integer values are accepted for real PARAMs.

use crate::deck::cards::{Param, ParamValue};
use crate::deck::{CaseControl, DeckError, Loc, Warning};

/// Type of a PARAM value.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ParamType {
    /// `YES` / `NO`.
    YesNo,
    /// Integer.
    Int,
    /// Real (an integer is accepted).
    Real,
}

/// One known PARAM: name, type, the rule its value must satisfy, and what it does.
pub struct KnownParam {
    pub name: &'static str,
    pub kind: ParamType,
    /// The rule, as shown in error messages.
    pub rule: &'static str,
    /// Check of a numeric value (ignored for YES/NO).
    pub ok: fn(f64) -> bool,
    /// Meaning and default.
    pub doc: &'static str,
}

/// The PARAMs paraflex reads.
pub const KNOWN_PARAMS: &[KnownParam] = &[
    KnownParam {
        name: "AUTOSPC",
        kind: ParamType::YesNo,
        rule: "YES or NO",
        ok: |_| true,
        doc: "constrain singular DOFs automatically; default YES",
    },
    KnownParam {
        name: "WTMASS",
        kind: ParamType::Real,
        rule: "a real > 0",
        ok: |v| v > 0.0,
        doc: "mass scale (mass matrix = WTMASS × input mass); default 1.0",
    },
    KnownParam {
        name: "COUPMASS",
        kind: ParamType::Int,
        rule: "-1 (lumped) or 1 (coupled)",
        ok: |v| v == -1.0 || v == 1.0,
        doc: "mass formulation; default -1 (lumped), as Nastran",
    },
    KnownParam {
        name: "K6ROT",
        kind: ParamType::Real,
        rule: "a real >= 0",
        ok: |v| v >= 0.0,
        doc: "shell drilling stiffness factor; default 100.0 (MSC Nastran)",
    },
    KnownParam {
        name: "GRDPNT",
        kind: ParamType::Int,
        rule: "an integer >= -1",
        ok: |v| v >= -1.0,
        doc: "grid-point weight generator reference grid; -1 (default) = off, 0 = basic origin",
    },
    KnownParam {
        name: "ALPHA1",
        kind: ParamType::Real,
        rule: "a real >= 0",
        ok: |v| v >= 0.0,
        doc: "Rayleigh damping α (C = αM + βK); default 0",
    },
    KnownParam {
        name: "BETA1",
        kind: ParamType::Real,
        rule: "a real >= 0",
        ok: |v| v >= 0.0,
        doc: "Rayleigh damping β; default 0",
    },
    KnownParam {
        name: "G",
        kind: ParamType::Real,
        rule: "a real >= 0",
        ok: |v| v >= 0.0,
        doc: "overall structural damping coefficient: K(1 + iG) in SOL 108, G on the modal stiffness in SOL 111, viscous (G/W3)·K in full-model SOL 109/112 when PARAM,W3 > 0; refused on pROMs; default 0",
    },
    KnownParam {
        name: "W3",
        kind: ParamType::Real,
        rule: "a real >= 0",
        ok: |v| v >= 0.0,
        doc: "frequency (rad/s) at which PARAM,G is turned into viscous damping (G/W3)·K in transient response, as Nastran; default 0 = G left out of transient response",
    },
    KnownParam {
        name: "W4",
        kind: ParamType::Real,
        rule: "a real >= 0",
        ok: |v| v >= 0.0,
        doc: "frequency (rad/s) at which the element structural damping GE (MAT1, MAT8, PCOMP, PELAS, CELAS2, PBUSH) is turned into viscous damping (1/W4)·Σ GE·K_e in full-model transient response, as Nastran; default 0 = element GE left out of transient response",
    },
    KnownParam {
        name: "KDAMP",
        kind: ParamType::Int,
        rule: "1 or -1",
        ok: |v| v == 1.0 || v == -1.0,
        doc: "SOL 111: the modal damping of SDAMPING's TABDMP1 as viscous 2ζ_jω_j (1, default) or as structural damping ω_j²(1 + 2iζ_j) (-1), as Nastran",
    },
    KnownParam {
        name: "QINCOMP",
        kind: ParamType::YesNo,
        rule: "YES or NO",
        ok: |_| true,
        doc: "CQUAD4 incompatible membrane modes; default YES: in-plane bending exact on rectangles and parallelograms (MacNeal–Harder 0.993 / 0.952), the modes condensed once with the deck's section, so a pROM with NU, THETA or TPLY parameters differs from a deck rebuilt far from the nominal values (second order in the change); NO: the bilinear membrane with element-mean shear, 1/(1−ν²) too stiff in in-plane bending of rectangles (0.904) and locking on distorted shapes (parallelogram 0.033), and pROMs agree exactly with rebuilt decks",
    },
    KnownParam {
        name: "RESVEC",
        kind: ParamType::YesNo,
        rule: "YES or NO",
        ok: |_| true,
        doc: "SOL 111: augment the modes with residual vectors of the DLOAD's load shapes (static responses M-orthogonal to the modes), as Nastran's RESVEC default in modal frequency response; default YES; skipped with a warning when K is singular (free-free)",
    },
    KnownParam {
        name: "MAXRATIO",
        kind: ParamType::Real,
        rule: "a real > 1",
        ok: |v| v > 1.0,
        doc: "largest diagonal/pivot ratio the SOL 101 Cholesky accepts before reporting a mechanism; default 1e7 (Nastran)",
    },
    KnownParam {
        name: "BAILOUT",
        kind: ParamType::Int,
        rule: "an integer",
        ok: |_| true,
        doc: "SOL 101: a diagonal/pivot ratio above MAXRATIO stops the run (≥ 0, default 0) or is a warning and the run goes on (< 0), as MSC Nastran (UFM 9050 / BAILOUT); a zero or negative pivot stops it either way",
    },
];

/// Values of the known PARAMs (defaults as in [`KNOWN_PARAMS`]).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct ModelParams {
    pub autospc: bool,
    pub wtmass: f64,
    /// −1 lumped, 1 coupled.
    pub coupmass: i64,
    pub k6rot: f64,
    pub grdpnt: i64,
    pub alpha1: f64,
    pub beta1: f64,
    pub g: f64,
    /// Nastran W3 (rad/s): transient response adds (G/W3)·K when > 0.
    pub w3: f64,
    /// Nastran W4 (rad/s): transient response adds (1/W4)·Σ GE_e K_e when > 0.
    pub w4: f64,
    /// Modal damping tables as viscous (1) or structural (−1) damping (Nastran KDAMP).
    pub kdamp: i64,
    /// SOL 101: a negative value turns a pivot ratio above MAXRATIO into a warning (Nastran
    /// BAILOUT).
    pub bailout: i64,
    /// SOL 101 factorization: largest a_kk / d_k accepted (Nastran MAXRATIO).
    pub maxratio: f64,
    /// CQUAD4 incompatible membrane modes (PARAM,QINCOMP; [`crate::fe::shell::Incompatible`]).
    pub qincomp: bool,
    /// SOL 111 residual vectors (PARAM,RESVEC; [`crate::dynamics::frf::residual_vectors`]).
    pub resvec: bool,
}

impl ModelParams {
    /// The stiffness-proportional damping factor of transient response: β₁ + G/W3 (Nastran's
    /// equivalent viscous structural damping; G is left out while W3 = 0).
    pub fn transient_beta(&self) -> f64 {
        if self.w3 > 0.0 {
            self.beta1 + self.g / self.w3
        } else {
            self.beta1
        }
    }
}

impl Default for ModelParams {
    fn default() -> Self {
        ModelParams {
            autospc: true,
            wtmass: 1.0,
            coupmass: -1,
            k6rot: 100.0,
            grdpnt: -1,
            alpha1: 0.0,
            beta1: 0.0,
            g: 0.0,
            w3: 0.0,
            w4: 0.0,
            kdamp: 1,
            bailout: 0,
            maxratio: crate::linalg::cholesky::DEFAULT_MAX_RATIO,
            qincomp: true,
            resvec: true,
        }
    }
}

/// A PARAM value reduced to what the table needs.
enum Value {
    Num(f64, bool),
    Text(String),
}

fn from_card(v: &ParamValue) -> Value {
    match v {
        ParamValue::Int(i) => Value::Num(*i as f64, true),
        ParamValue::Real(r) => Value::Num(*r, false),
        ParamValue::Complex(r, _) => Value::Num(*r, false),
        ParamValue::Text(t) => Value::Text(t.to_ascii_uppercase()),
    }
}

fn from_text(t: &str) -> Value {
    let t = t.trim();
    if let Ok(i) = t.parse::<i64>() {
        return Value::Num(i as f64, true);
    }
    match t.replace(['D', 'd'], "E").parse::<f64>() {
        Ok(r) => Value::Num(r, false),
        Err(_) => Value::Text(t.to_ascii_uppercase()),
    }
}

/// Read every PARAM: validate the known ones, warn once about the rest.
pub fn read(
    bulk_params: &[Param],
    case: &CaseControl,
    errors: &mut Vec<DeckError>,
    warnings: &mut Vec<Warning>,
) -> ModelParams {
    let mut out = ModelParams::default();
    let mut unknown: Vec<String> = Vec::new();
    let items = bulk_params
        .iter()
        .map(|p| (p.name.to_ascii_uppercase(), from_card(&p.value), &p.loc))
        .chain(
            case.params
                .iter()
                .map(|(n, v, loc)| (n.to_ascii_uppercase(), from_text(v), loc)),
        );
    for (name, value, loc) in items {
        match KNOWN_PARAMS.iter().find(|k| k.name == name) {
            None => {
                if !unknown.contains(&name) {
                    unknown.push(name);
                }
            }
            Some(known) => apply(known, value, loc, &mut out, errors),
        }
    }
    if !unknown.is_empty() {
        warnings.push(Warning {
            loc: None,
            message: format!("PARAMs accepted and ignored: {}", unknown.join(", ")),
        });
    }
    out
}

fn apply(
    known: &KnownParam,
    value: Value,
    loc: &Loc,
    out: &mut ModelParams,
    errors: &mut Vec<DeckError>,
) {
    let fail = |errors: &mut Vec<DeckError>, found: String| {
        errors.push(
            DeckError::at(
                loc,
                format!("{} must be {}, found {found}", known.name, known.rule),
            )
            .on_card(format!("PARAM {}", known.name)),
        );
    };
    match (known.kind, value) {
        (ParamType::YesNo, Value::Text(t)) if t == "YES" || t == "NO" => match known.name {
            "AUTOSPC" => out.autospc = t == "YES",
            "QINCOMP" => out.qincomp = t == "YES",
            "RESVEC" => out.resvec = t == "YES",
            _ => {}
        },
        (ParamType::YesNo, Value::Text(t)) => fail(errors, t),
        (ParamType::YesNo, Value::Num(v, _)) => fail(errors, v.to_string()),
        (ParamType::Int, Value::Num(v, true)) | (ParamType::Real, Value::Num(v, _))
            if v.is_finite() && (known.ok)(v) =>
        {
            match known.name {
                "WTMASS" => out.wtmass = v,
                "COUPMASS" => out.coupmass = v as i64,
                "K6ROT" => out.k6rot = v,
                "GRDPNT" => out.grdpnt = v as i64,
                "ALPHA1" => out.alpha1 = v,
                "BETA1" => out.beta1 = v,
                "G" => out.g = v,
                "W3" => out.w3 = v,
                "W4" => out.w4 = v,
                "KDAMP" => out.kdamp = v as i64,
                "BAILOUT" => out.bailout = v as i64,
                "MAXRATIO" => out.maxratio = v,
                _ => {}
            }
        }
        (_, Value::Num(v, _)) => fail(errors, v.to_string()),
        (_, Value::Text(t)) => fail(errors, format!("'{t}'")),
    }
}
