//! paraflex extension cards (DESIGN.md §3): `PMPAR`, `PMOR`, `PVAL`, `SENSOR`, `TABLEF`, `TINTEG`.
//! Same field rules as the standard cards; the layouts are the contract decks rely on.

use crate::card_values::Column;
use crate::card_values::{PmparKind, SensorKind};
use crate::deck::error::{DeckError, Loc};
use crate::deck::fields::RawCard;
use crate::deck::reader::FieldReader;
use crate::deck::value::Value;

/// `PMPAR` — a model parameter of a parametric ROM.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | ID | int > 0 | required | id |
/// | 3 | NAME | name | required | parameter name (unique) |
/// | 4 | KIND | `E` `RHO` `NU` `THETA` `TPLY` `K` `MASS` | required | what it scales |
/// | 5 | REFID | int > 0 | required | MAT1 (E, RHO, NU), PCOMP (THETA, TPLY), PELAS (K) or CONM2 element (MASS) id |
/// | 6 | LOW | real | required | lower bound (absolute); [LOW, HIGH] must contain the nominal value and stay inside what the card accepts (E > 0, −1 < NU < 0.5, RHO ≥ 0, ply thickness > 0, CONM2 M ≥ 0) |
/// | 7 | HIGH | real | required | upper bound (absolute) |
#[derive(Debug, Clone, PartialEq)]
pub struct Pmpar {
    pub id: u32,
    pub name: String,
    pub kind: PmparKind,
    pub refid: u32,
    pub low: f64,
    pub high: f64,
    pub loc: Loc,
}

impl Pmpar {
    /// Read a `PMPAR` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let id = f.id(1, "ID");
        f.set_id(id);
        let name = f.text(2, "NAME");
        let names: Vec<&str> = PmparKind::ALL.iter().map(|(n, _)| *n).collect();
        let kw = f.keyword(3, "KIND", &names, None);
        let kind = PmparKind::ALL
            .iter()
            .find(|(n, _)| *n == kw)
            .map_or(PmparKind::E, |(_, k)| *k);
        let refid = f.id(4, "REFID");
        let low = f.real(5, "LOW");
        let high = f.real(6, "HIGH");
        if low > high {
            f.error(
                5,
                "LOW",
                format!("LOW = {low:e} is greater than HIGH = {high:e}"),
            );
        }
        let loc = f.loc();
        f.finish(6)?;
        Ok(Pmpar {
            id,
            name,
            kind,
            refid,
            low,
            high,
            loc,
        })
    }
}

/// `PMOR` — pROM build settings (`SOL PROM`, selected by case control `PROM = id`).
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | ID | int > 0 | required | id |
/// | 3 | NSAMP | int > 0 | required | LHS samples |
/// | 4 | NMODES | int > 0 | required | normal modes per local basis |
/// | 5 | FMAX | real > 0 | required | band upper limit (Hz) |
/// | 6 | ERRTOL | real > 0 | 1.0E-3 | FRF error tolerance (thesis eq. 3.35) |
/// | 7 | DSIZE | int > 0 | NMODES/2 | basis-size step |
/// | 8 | MACTOL | real in (0, 1] | 0.99 | MAC filter threshold (eq. 3.39) |
/// | 9 | SEED | int ≥ 0 | 1 | LHS seed |
/// | cont. 2 | BSET | int > 0 | blank | boundary DOFs: any positive value selects the deck's a-set (all ASET1 cards); blank = none (then the pROM has no inputs and keeps the whole numerical rank: the FRF error of eq. 3.35 needs inputs) |
/// | cont. 3 | STATIC | `ATTACH` `CONSTR` `NONE` | ATTACH | static modes |
/// | cont. 4 | RIGID | `KEEP` `REMOVE` | KEEP | rigid-body modes |
/// | cont. 5 | NFREQ | int > 0 | 200 | frequency lines of the FRF error |
/// | cont. 6 | FMIN | real ≥ 0 | 0.0 | band lower limit (Hz) |
#[derive(Debug, Clone, PartialEq)]
pub struct Pmor {
    pub id: u32,
    pub nsamp: u32,
    pub nmodes: u32,
    pub fmax: f64,
    pub errtol: f64,
    pub dsize: u32,
    pub mactol: f64,
    pub seed: u64,
    pub bset: Option<u32>,
    pub static_modes: PmorStatic,
    pub rigid: PmorRigid,
    pub nfreq: u32,
    pub fmin: f64,
    pub loc: Loc,
}

/// PMOR STATIC: the static modes of each local basis.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PmorStatic {
    /// Unit-load (attachment) modes at the boundary DOFs.
    Attach,
    /// Craig–Bampton constraint modes.
    Constr,
    /// No static modes.
    None,
}

/// PMOR RIGID: what happens to rigid-body modes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PmorRigid {
    Keep,
    /// Removed (free bodies for multibody).
    Remove,
}

impl Pmor {
    /// Read a `PMOR` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let id = f.id(1, "ID");
        f.set_id(id);
        let nsamp = f.count(2, "NSAMP");
        let nmodes = f.count(3, "NMODES");
        let fmax = f.positive_real(4, "FMAX");
        let errtol = f.real_or(5, "ERRTOL", 1.0e-3);
        if errtol <= 0.0 {
            f.error(
                5,
                "ERRTOL",
                format!("expected ERRTOL > 0, found {errtol:e}"),
            );
        }
        let dsize = f.opt_count(6, "DSIZE").unwrap_or((nmodes / 2).max(1));
        let mactol = f.real_or(7, "MACTOL", 0.99);
        if !(mactol > 0.0 && mactol <= 1.0) {
            f.error(
                7,
                "MACTOL",
                format!("expected 0 < MACTOL <= 1, found {mactol:e}"),
            );
        }
        let seed = f.id0_or(8, "SEED", 1) as u64;
        let bset = f.opt_id(9, "BSET");
        let static_modes = f.choice(
            10,
            "STATIC",
            &[
                ("ATTACH", PmorStatic::Attach),
                ("CONSTR", PmorStatic::Constr),
                ("NONE", PmorStatic::None),
            ],
            Some(PmorStatic::Attach),
        );
        let rigid = f.choice(
            11,
            "RIGID",
            &[("KEEP", PmorRigid::Keep), ("REMOVE", PmorRigid::Remove)],
            Some(PmorRigid::Keep),
        );
        let nfreq = f.opt_count(12, "NFREQ").unwrap_or(200);
        let fmin = f.real_or(13, "FMIN", 0.0);
        if fmin < 0.0 || (fmin >= fmax && fmax > 0.0) {
            f.error(
                13,
                "FMIN",
                format!("expected 0 <= FMIN < FMAX = {fmax:e}, found {fmin:e}"),
            );
        }
        let loc = f.loc();
        f.finish(13)?;
        Ok(Pmor {
            id,
            nsamp,
            nmodes,
            fmax,
            errtol,
            dsize,
            mactol,
            seed,
            bset,
            static_modes,
            rigid,
            nfreq,
            fmin,
            loc,
        })
    }
}

/// `PVAL` — parameter values for evaluating a pROM; parameters not listed keep their nominal value.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | ID | int > 0 | required | id (selected by case control `PVAL = id`) |
/// | 3, 4, … | NAME1 VAL1 NAME2 VAL2 … | name, real | ≥ 1 pair | PMPAR name and value |
#[derive(Debug, Clone, PartialEq)]
pub struct Pval {
    pub id: u32,
    pub values: Vec<(String, f64)>,
    pub loc: Loc,
}

impl Pval {
    /// Read a `PVAL` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let id = f.id(1, "ID");
        f.set_id(id);
        let len = f.len();
        let mut values: Vec<(String, f64)> = Vec::new();
        let mut i = 2;
        while i <= len {
            if f.value(i).is_blank() && f.value(i + 1).is_blank() {
                i += 2;
                continue;
            }
            let name = f.text(i, "NAME");
            let v = f.real(i + 1, "VAL");
            if values.iter().any(|(n, _)| *n == name) {
                f.error(i, "NAME", format!("parameter {name} listed twice"));
            }
            values.push((name, v));
            i += 2;
        }
        if values.is_empty() {
            f.card_error("no (NAME, VAL) pair given");
        }
        let loc = f.loc();
        f.finish(len.max(1))?;
        Ok(Pval { id, values, loc })
    }
}

/// `SENSOR` — a virtual sensor.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | ID | int > 0 | required | id |
/// | 3 | NAME | name | required | sensor name (unique) |
/// | 4 | KIND | `DISP` `VEL` `ACCEL` `STRAIN` | required | quantity |
/// | 5 | REF | int > 0 | required | grid (DISP, VEL, ACCEL) or element (STRAIN) |
/// | 6 | SURF | `TOP` `BOT` `MID` | blank | shell surface for STRAIN on shells (MID if blank); blank for solids |
/// | 7–9 | X Y Z | real | required | measuring direction in the basic system (not zero) |
#[derive(Debug, Clone, PartialEq)]
pub struct Sensor {
    pub id: u32,
    pub name: String,
    pub kind: SensorKind,
    pub reference: u32,
    /// `TOP`, `BOT`, `MID` or `None` (blank).
    pub surface: Option<&'static str>,
    pub direction: [f64; 3],
    pub loc: Loc,
}

impl Sensor {
    /// Read a `SENSOR` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let id = f.id(1, "ID");
        f.set_id(id);
        let name = f.text(2, "NAME");
        let kind = match f.keyword(3, "KIND", &["DISP", "VEL", "ACCEL", "STRAIN"], None) {
            "VEL" => SensorKind::Vel,
            "ACCEL" => SensorKind::Accel,
            "STRAIN" => SensorKind::Strain,
            _ => SensorKind::Disp,
        };
        let reference = f.id(4, "REF");
        let surface = match f.value(5) {
            Value::Blank => None,
            _ => Some(f.keyword(5, "SURF", &["TOP", "BOT", "MID"], None)),
        };
        if surface.is_some() && kind != SensorKind::Strain {
            f.error(5, "SURF", "SURF applies to STRAIN sensors only");
        }
        let direction = [f.real(6, "X"), f.real(7, "Y"), f.real(8, "Z")];
        if direction == [0.0; 3] && (6..=8).all(|i| matches!(f.value(i), Value::Real(_))) {
            f.error(6, "X", "the direction vector is zero");
        }
        let loc = f.loc();
        f.finish(8)?;
        Ok(Sensor {
            id,
            name,
            kind,
            reference,
            surface,
            direction,
            loc,
        })
    }
}

/// `TABLEF` — a time or frequency table read from a CSV file; usable wherever a `TABLED1` id is.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | ID | int > 0 | required | table id (shares the id space of TABLED1) |
/// | 3 | PATH | quoted string | required | CSV file, relative to the deck |
/// | 4 | TCOL | int ≥ 1 or name | 1 | column of the abscissa (time or frequency) |
/// | 5 | YCOL | int ≥ 1 or name | 2 | column of the values |
#[derive(Debug, Clone, PartialEq)]
pub struct Tablef {
    pub id: u32,
    pub path: String,
    pub tcol: Column,
    pub ycol: Column,
    pub loc: Loc,
}

impl Tablef {
    /// Read a `TABLEF` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let id = f.id(1, "ID");
        f.set_id(id);
        let path = f.path(2, "PATH");
        let tcol = if f.value(3).is_blank() {
            Column::Index(1)
        } else {
            f.column(3, "TCOL")
        };
        let ycol = if f.value(4).is_blank() {
            Column::Index(2)
        } else {
            f.column(4, "YCOL")
        };
        let loc = f.loc();
        f.finish(4)?;
        Ok(Tablef {
            id,
            path,
            tcol,
            ycol,
            loc,
        })
    }
}

/// `PTABLE` — a pROM parameter that follows a table of time in a transient (`SOL 109/112` with
/// `ROM =`, or `SOL FMB` on a mechanism), e.g. E degrading 10 %/s (thesis §8.6.2, §9.4.1.4).
/// Selected together with the constant values by the subcase's `PVAL = ID`: one id names the
/// whole parameter state of a run, and a parameter is either constant (PVAL) or tabulated
/// (PTABLE), never both. In `SOL FMB` NAME is `BODY.PMPAR` of a flexible body: the run starts
/// (assembly or statics) at p(0) and each time step takes the body's pROM at p(t) at the
/// step's end time (exact affine sums, no Ṁ term). `SOL ESTIMATE` refuses it (the filter
/// estimates a varying parameter as a random walk).
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | ID | int > 0 | required | id (selected by case control `PVAL = id`) |
/// | 3 | NAME | name | required | PMPAR name; on a mechanism `BODY.PMPAR` of a flexible body |
/// | 4 | TID | int > 0 | required | TABLED1 or TABLEF id of the value p(t) |
#[derive(Debug, Clone, PartialEq)]
pub struct Ptable {
    pub id: u32,
    pub name: String,
    pub tid: u32,
    pub loc: Loc,
}

impl Ptable {
    /// Read a `PTABLE` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let id = f.id(1, "ID");
        f.set_id(id);
        let name = f.text(2, "NAME");
        let tid = f.id(3, "TID");
        let loc = f.loc();
        f.finish(3)?;
        Ok(Ptable { id, name, tid, loc })
    }
}

/// `TINTEG` — time integrator for the `TSTEP` of the same id.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | ID | int > 0 | required | the TSTEP id it applies to |
/// | 3 | METHOD | `BDF1` `BDF2` `GALPHA` | BDF1 | integrator (BDF1 is the thesis's, eq. 2.61) |
/// | 4 | RHOINF | real in [0, 1] | 0.9 | spectral radius at infinity for GALPHA |
///
/// A TSTEP without a TINTEG is integrated by BDF1 in `SOL TRANSIENT` and `SOL FMB`, and by the
/// trapezoidal rule (GALPHA with ρ∞ = 1: no numerical damping, as Nastran's Newmark-β) in the
/// Nastran sequences SOL 109 and 112.
#[derive(Debug, Clone, PartialEq)]
pub struct Tinteg {
    pub id: u32,
    pub method: TintegMethod,
    pub rho_inf: f64,
    pub loc: Loc,
}

/// `TSTEPVAR` — error-controlled steps for the `TSTEP` of the same id (`SOL FMB`); delete the card to return to the TSTEP's fixed Δt.
///
/// The TSTEP keeps its output times (every NO-th step of each interval) and its first Δt is the first step; between outputs the GGL integrator chooses each step so that the estimated local error of every coordinate of q stays below ATOL + RTOL·|q| (docs/multibody-benchmarks.md). The achieved steps, rejections and largest estimate are written as attributes of `/results/<id>/fmb`. SOL TRANSIENT (109/112) refuses a TSTEP with a TSTEPVAR rather than run fixed steps in its place.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | ID | int > 0 | required | the TSTEP id it applies to |
/// | 3 | RTOL | real ≥ 0 | required | relative tolerance on the local error of q (positions, Euler parameters, flexible coordinates) |
/// | 4 | ATOL | real ≥ 0 | RTOL | absolute tolerance (not both zero) |
/// | 5 | HMIN | real > 0 | 1.0E-6 × the first Δt | smallest step: below it the run stops with the time and the error estimate |
/// | 6 | HMAX | real ≥ HMIN | no bound | largest step (steps never pass an output time either) |
#[derive(Debug, Clone, PartialEq)]
pub struct Tstepvar {
    pub id: u32,
    pub rtol: f64,
    pub atol: Option<f64>,
    pub hmin: Option<f64>,
    pub hmax: Option<f64>,
    pub loc: Loc,
}

impl Tstepvar {
    /// Read a `TSTEPVAR` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let id = f.id(1, "ID");
        f.set_id(id);
        let rtol = f.real(2, "RTOL");
        let atol = f.opt_real(3, "ATOL");
        for (i, name, v) in [(2, "RTOL", Some(rtol)), (3, "ATOL", atol)] {
            if v.is_some_and(|v| v < 0.0) {
                f.error(
                    i,
                    name,
                    format!("expected a real >= 0, found {:e}", v.unwrap_or(0.0)),
                );
            }
        }
        if rtol == 0.0 && atol.is_none_or(|a| a == 0.0) {
            f.error(
                2,
                "RTOL",
                "RTOL and ATOL are both zero: no step could be accepted",
            );
        }
        let hmin = f.opt_real(4, "HMIN");
        let hmax = f.opt_real(5, "HMAX");
        if hmin.is_some_and(|h| h <= 0.0) {
            f.error(4, "HMIN", "expected a real > 0");
        }
        if let (Some(lo), Some(hi)) = (hmin, hmax)
            && hi < lo
        {
            f.error(5, "HMAX", format!("HMAX = {hi:e} is below HMIN = {lo:e}"));
        }
        if hmax.is_some_and(|h| h <= 0.0) {
            f.error(5, "HMAX", "expected a real > 0");
        }
        let loc = f.loc();
        f.finish(5)?;
        Ok(Tstepvar {
            id,
            rtol,
            atol,
            hmin,
            hmax,
            loc,
        })
    }
}

/// TINTEG METHOD.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TintegMethod {
    Bdf1,
    Bdf2,
    /// Generalized-α with the card's RHOINF.
    Galpha,
}

impl Tinteg {
    /// Read a `TINTEG` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let id = f.id(1, "ID");
        f.set_id(id);
        let method = f.choice(
            2,
            "METHOD",
            &[
                ("BDF1", TintegMethod::Bdf1),
                ("BDF2", TintegMethod::Bdf2),
                ("GALPHA", TintegMethod::Galpha),
            ],
            Some(TintegMethod::Bdf1),
        );
        let rho_inf = f.real_or(3, "RHOINF", 0.9);
        if !(0.0..=1.0).contains(&rho_inf) {
            f.error(
                3,
                "RHOINF",
                format!("expected 0 <= RHOINF <= 1, found {rho_inf:e}"),
            );
        }
        if method != TintegMethod::Galpha && !f.value(3).is_blank() {
            f.error(3, "RHOINF", "RHOINF applies to GALPHA only");
        }
        let loc = f.loc();
        f.finish(3)?;
        Ok(Tinteg {
            id,
            method,
            rho_inf,
            loc,
        })
    }
}
