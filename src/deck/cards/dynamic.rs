//! Dynamics cards: `EIGRL`, `FREQ`/`FREQ1`/`FREQ2`, `TSTEP`, `TLOAD1`, `RLOAD1`, `DAREA`,
//! `TABLED1`, `DLOAD`.

use super::loads::combination;
use crate::card_values::Dofs;
use crate::deck::error::{DeckError, Loc};
use crate::deck::fields::RawCard;
use crate::deck::reader::FieldReader;
use crate::deck::value::Value;

/// `EIGRL` — real eigenvalue extraction (Lanczos).
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | SID | int > 0 | required | set id (selected by `METHOD`) |
/// | 3 | V1 | real | blank | lower frequency bound (Hz) |
/// | 4 | V2 | real | blank | upper frequency bound (Hz) |
/// | 5 | ND | int > 0 | blank | number of roots wanted |
/// | 6 | MSGLVL | int | 0 | diagnostics level (kept, unused) |
/// | 7 | MAXSET | int | blank | block size (kept, unused) |
/// | 8 | SHFSCL | real | blank | estimate of the first flexible mode (Hz) for free-free shifts |
/// | 9 | NORM | `MASS` / `MAX` | MASS | eigenvector normalization |
///
/// With neither V2 nor ND the lowest root (above V1 when given) is found, ND = 1, as the
/// MSC/NX and OptiStruct EIGRL tables of V1, V2, ND say. With massless DOFs (springs without
/// mass, rotations without rotary inertia) the mass matrix is singular and only rank(M) finite
/// modes exist: ND larger than that returns the finite modes with a warning (`only N finite
/// mode(s) exist …`), never modes at an "infinite" frequency.
#[derive(Debug, Clone, PartialEq)]
pub struct Eigrl {
    pub sid: u32,
    pub v1: Option<f64>,
    pub v2: Option<f64>,
    pub nd: Option<u32>,
    pub shfscl: Option<f64>,
    pub norm: EigenNorm,
    pub loc: Loc,
}

/// EIGRL NORM: how eigenvectors are normalized.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EigenNorm {
    /// φᵀMφ = 1.
    Mass,
    /// Largest component 1.
    Max,
}

impl EigenNorm {
    /// The keywords of NORM.
    pub const KEYWORDS: [(&'static str, EigenNorm); 2] =
        [("MASS", EigenNorm::Mass), ("MAX", EigenNorm::Max)];

    /// The keyword (`MASS`, `MAX`).
    pub fn name(self) -> &'static str {
        match self {
            EigenNorm::Mass => "MASS",
            EigenNorm::Max => "MAX",
        }
    }
}

impl Eigrl {
    /// Read an `EIGRL` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let sid = f.id(1, "SID");
        f.set_id(sid);
        let v1 = f.opt_real(2, "V1");
        let v2 = f.opt_real(3, "V2");
        let nd = f.opt_count(4, "ND");
        let nd = if v2.is_none() && nd.is_none() && f.value(4).is_blank() {
            Some(1)
        } else {
            nd
        };
        f.int_or(5, "MSGLVL", 0);
        f.opt_int(6, "MAXSET");
        let shfscl = f.opt_real(7, "SHFSCL");
        let norm = f.choice(8, "NORM", &EigenNorm::KEYWORDS, Some(EigenNorm::Mass));
        if let (Some(a), Some(b)) = (v1, v2)
            && b <= a
        {
            f.error(
                3,
                "V2",
                format!("V2 = {b:e} must be greater than V1 = {a:e}"),
            );
        }
        let loc = f.loc();
        f.finish(8)?;
        Ok(Eigrl {
            sid,
            v1,
            v2,
            nd,
            shfscl,
            norm,
            loc,
        })
    }
}

/// How a frequency card lists its frequencies.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub enum FreqKind {
    /// `FREQ SID F1 F2 …`: explicit list.
    List(Vec<f64>),
    /// `FREQ1 SID F1 DF NDF`: F1 + k·DF, k = 0 … NDF.
    Linear { f1: f64, df: f64, ndf: u32 },
    /// `FREQ2 SID F1 F2 NF`: NF logarithmic intervals from F1 to F2.
    Log { f1: f64, f2: f64, nf: u32 },
}

/// `FREQ`, `FREQ1`, `FREQ2` — excitation frequencies (Hz). All cards with the same SID combine.
///
/// | card | fields 2 … | defaults |
/// |---|---|---|
/// | FREQ | SID F1 F2 F3 … | — |
/// | FREQ1 | SID F1 DF NDF | NDF = 1 |
/// | FREQ2 | SID F1 F2 NF | NF = 1; F1 > 0 |
#[derive(Debug, Clone, PartialEq)]
pub struct Freq {
    pub sid: u32,
    pub kind: FreqKind,
    pub loc: Loc,
}

impl Freq {
    /// Read a `FREQ`, `FREQ1` or `FREQ2` card (`name` says which).
    pub fn from_card(card: &RawCard, name: &str) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let sid = f.id(1, "SID");
        f.set_id(sid);
        let len = f.len();
        let kind = match name {
            "FREQ1" => {
                let f1 = f.real_or(2, "F1", 0.0);
                let df = f.real(3, "DF");
                let ndf = f.opt_count(4, "NDF").unwrap_or(1);
                if df <= 0.0 && matches!(f.value(3), Value::Real(_)) {
                    f.error(3, "DF", format!("expected DF > 0, found {df:e}"));
                }
                FreqKind::Linear { f1, df, ndf }
            }
            "FREQ2" => {
                let f1 = f.real(2, "F1");
                let f2 = f.real(3, "F2");
                let nf = f.opt_count(4, "NF").unwrap_or(1);
                if !(f1 > 0.0 && f2 > f1)
                    && matches!((f.value(2), f.value(3)), (Value::Real(_), Value::Real(_)))
                {
                    f.card_error(format!(
                        "FREQ2 needs 0 < F1 < F2, found F1 = {f1:e}, F2 = {f2:e}"
                    ));
                }
                FreqKind::Log { f1, f2, nf }
            }
            _ => {
                let list = f.real_list(2, "F");
                if list.is_empty() {
                    f.card_error("no frequency given");
                }
                FreqKind::List(list)
            }
        };
        let loc = f.loc();
        f.finish(if name == "FREQ" { len.max(1) } else { 4 })?;
        Ok(Freq { sid, kind, loc })
    }

    /// The frequencies this card lists (Hz).
    pub fn frequencies(&self) -> Vec<f64> {
        match &self.kind {
            FreqKind::List(v) => v.clone(),
            FreqKind::Linear { f1, df, ndf } => {
                (0..=*ndf).map(|k| f1 + f64::from(k) * df).collect()
            }
            FreqKind::Log { f1, f2, nf } => {
                let d = (f2 / f1).ln() / f64::from(*nf);
                (0..=*nf).map(|k| f1 * (d * f64::from(k)).exp()).collect()
            }
        }
    }
}

/// `TSTEP` — time step intervals.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | SID | int > 0 | required | set id |
/// | 3 | N1 | int > 0 | required | number of steps |
/// | 4 | DT1 | real > 0 | required | step size |
/// | 5 | NO1 | int > 0 | 1 | output every NO1 steps |
/// | cont. 3–5 | N2 DT2 NO2 … | | | further intervals |
#[derive(Debug, Clone, PartialEq)]
pub struct Tstep {
    pub sid: u32,
    /// (N, DT, NO) per interval.
    pub intervals: Vec<(u32, f64, u32)>,
    pub loc: Loc,
}

impl Tstep {
    /// Read a `TSTEP` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let sid = f.id(1, "SID");
        f.set_id(sid);
        let mut intervals = Vec::new();
        let len = f.len();
        let mut first = 2;
        while first <= len.max(2) {
            if first > 2 && (first..first + 3).all(|i| f.value(i).is_blank()) {
                first += 8;
                continue;
            }
            let n = f.count(first, "N");
            let dt = f.positive_real(first + 1, "DT");
            let no = f.opt_count(first + 2, "NO").unwrap_or(1);
            intervals.push((n, dt, no));
            first += 8;
        }
        let loc = f.loc();
        let mut last = 4;
        while last < len {
            last += 8;
        }
        f.finish(last)?;
        Ok(Tstep {
            sid,
            intervals,
            loc,
        })
    }
}

/// `TLOAD1` — transient load: u(t) = A · F(t − τ), A from `DAREA` (or a static load set).
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | SID | int > 0 | required | load set id |
/// | 3 | EXCITEID | int > 0 | required | DAREA (or static load) set id |
/// | 4 | DELAY | real | 0.0 | time delay τ (a DELAY card id is not supported) |
/// | 5 | TYPE | `LOAD` / `DISP` / `VELO` / `ACCE` or 0–3 | LOAD | excitation type (only LOAD supported) |
/// | 6 | TID | int > 0 | required | TABLED1 or TABLEF id of F(t) |
/// | 7, 8 | US0 VS0 | real | 0.0 | enforced-motion initial values (kept, unused) |
#[derive(Debug, Clone, PartialEq)]
pub struct Tload1 {
    pub sid: u32,
    pub excite_id: u32,
    pub delay: f64,
    pub tid: u32,
    pub loc: Loc,
}

/// Read an excitation TYPE field (`LOAD`/0 only) and report the others as unsupported.
fn excitation_type(f: &mut FieldReader, i: usize) {
    let ok = match f.value(i) {
        Value::Blank => true,
        Value::Int(0) => true,
        Value::Text(t) => {
            t.eq_ignore_ascii_case("LOAD")
                || t.eq_ignore_ascii_case("L")
                || t.eq_ignore_ascii_case("LO")
        }
        _ => false,
    };
    if !ok {
        let found = f.value(i).describe();
        f.error(
            i,
            "TYPE",
            format!("only applied loads (TYPE = LOAD or 0) are supported, found {found}"),
        );
    }
}

/// Read a DELAY field: a real delay, or an error for a DELAY card reference.
fn delay(f: &mut FieldReader, i: usize) -> f64 {
    match f.value(i) {
        Value::Int(_) => {
            f.error(
                i,
                "DELAY",
                "DELAY card references are not supported; give the delay as a real",
            );
            0.0
        }
        _ => f.real_or(i, "DELAY", 0.0),
    }
}

impl Tload1 {
    /// Read a `TLOAD1` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let sid = f.id(1, "SID");
        f.set_id(sid);
        let excite_id = f.id(2, "EXCITEID");
        let delay = delay(&mut f, 3);
        excitation_type(&mut f, 4);
        let tid = f.id(5, "TID");
        f.opt_real(6, "US0");
        f.opt_real(7, "VS0");
        let loc = f.loc();
        f.finish(7)?;
        Ok(Tload1 {
            sid,
            excite_id,
            delay,
            tid,
            loc,
        })
    }
}

/// `RLOAD1` — frequency-dependent load: A · (C(f) + i D(f)) · e^{i(θ − 2πfτ)}.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | SID | int > 0 | required | load set id |
/// | 3 | EXCITEID | int > 0 | required | DAREA (or static load) set id |
/// | 4 | DELAY | real | 0.0 | time delay τ |
/// | 5 | DPHASE | real | 0.0 | phase θ in degrees (a DPHASE card id is not supported) |
/// | 6 | TC | int ≥ 0 | 0 | TABLED1/TABLEF id of C(f); 0 = none |
/// | 7 | TD | int ≥ 0 | 0 | TABLED1/TABLEF id of D(f); 0 = none |
/// | 8 | TYPE | | LOAD | only LOAD supported |
#[derive(Debug, Clone, PartialEq)]
pub struct Rload1 {
    pub sid: u32,
    pub excite_id: u32,
    pub delay: f64,
    pub phase_deg: f64,
    pub tc: u32,
    pub td: u32,
    pub loc: Loc,
}

impl Rload1 {
    /// Read an `RLOAD1` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let sid = f.id(1, "SID");
        f.set_id(sid);
        let excite_id = f.id(2, "EXCITEID");
        let delay = delay(&mut f, 3);
        let phase_deg = match f.value(4) {
            Value::Int(_) => {
                f.error(
                    4,
                    "DPHASE",
                    "DPHASE card references are not supported; give the phase as a real",
                );
                0.0
            }
            _ => f.real_or(4, "DPHASE", 0.0),
        };
        let tc = f.id0_or(5, "TC", 0);
        let td = f.id0_or(6, "TD", 0);
        if tc == 0 && td == 0 {
            f.card_error("give TC or TD (a table of the load's frequency dependence)");
        }
        excitation_type(&mut f, 7);
        let loc = f.loc();
        f.finish(7)?;
        Ok(Rload1 {
            sid,
            excite_id,
            delay,
            phase_deg,
            tc,
            td,
            loc,
        })
    }
}

/// `DAREA` — load scale factor at a grid component (one entry per grid on the card).
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | SID | int > 0 | required | set id |
/// | 3, 4, 5 | P1 C1 A1 | int, component, real | required | grid, component, scale |
/// | 6, 7, 8 | P2 C2 A2 | | blank | optional second entry |
#[derive(Debug, Clone, PartialEq)]
pub struct Darea {
    pub sid: u32,
    pub grid: u32,
    pub components: Dofs,
    pub scale: f64,
    pub loc: Loc,
}

impl Darea {
    /// Read a `DAREA` card (one or two entries).
    pub fn from_card(card: &RawCard) -> Result<Vec<Self>, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let sid = f.id(1, "SID");
        f.set_id(sid);
        let loc = f.loc();
        let out = f
            .grid_component_values(["P", "C", "A"], None)
            .into_iter()
            .map(|(grid, components, scale)| Darea {
                sid,
                grid,
                components,
                scale,
                loc: loc.clone(),
            })
            .collect();
        f.finish(7)?;
        Ok(out)
    }
}

/// `TIC` — transient initial condition of one grid component, selected by case control
/// `IC = SID`. On a pROM (`ROM =`) the grid component must be an input DOF of the pROM; the
/// reduced initial state is then the static shape with these input displacements (see
/// "Initial conditions" in docs/dynamics.md).
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | SID | int > 0 | required | set id |
/// | 3 | G | int > 0 | required | grid |
/// | 4 | C | one component 1–6 | required | component (grid's displacement frame) |
/// | 5 | U0 | real | 0.0 | initial displacement |
/// | 6 | V0 | real | 0.0 | initial velocity |
#[derive(Debug, Clone, PartialEq)]
pub struct Tic {
    pub sid: u32,
    pub grid: u32,
    /// Component 1–6.
    pub component: usize,
    pub u0: f64,
    pub v0: f64,
    pub loc: Loc,
}

impl Tic {
    /// Read a `TIC` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let sid = f.id(1, "SID");
        f.set_id(sid);
        let grid = f.id(2, "G");
        let c = f.int(3, "C");
        if !(1..=6).contains(&c) {
            f.error(3, "C", format!("expected one component 1-6, found {c}"));
        }
        let u0 = f.real_or(4, "U0", 0.0);
        let v0 = f.real_or(5, "V0", 0.0);
        let loc = f.loc();
        f.finish(5)?;
        Ok(Tic {
            sid,
            grid,
            component: c.clamp(1, 6) as usize,
            u0,
            v0,
            loc,
        })
    }
}

/// `TABLED1` — tabular function y(x) with linear interpolation.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | TID | int > 0 | required | table id |
/// | 3 | XAXIS | `LINEAR` / `LOG` | LINEAR | (only LINEAR supported) |
/// | 4 | YAXIS | `LINEAR` / `LOG` | LINEAR | (only LINEAR supported) |
/// | cont. | x1 y1 x2 y2 … `ENDT` | real pairs | ≥ 2 points | x increasing |
#[derive(Debug, Clone, PartialEq)]
pub struct Tabled1 {
    pub id: u32,
    pub points: Vec<(f64, f64)>,
    pub loc: Loc,
}

impl Tabled1 {
    /// Read a `TABLED1` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let id = f.id(1, "TID");
        f.set_id(id);
        for (i, name) in [(2, "XAXIS"), (3, "YAXIS")] {
            f.keyword(i, name, &["LINEAR"], Some("LINEAR"));
        }
        let mut points: Vec<(f64, f64)> = Vec::new();
        let len = f.len();
        let mut i = 9;
        let mut ended = false;
        while i <= len {
            if matches!(f.value(i), Value::Text(t) if t.eq_ignore_ascii_case("ENDT")) {
                ended = true;
                break;
            }
            if matches!(f.value(i), Value::Text(t) if t.eq_ignore_ascii_case("SKIP")) {
                i += 2;
                continue;
            }
            let x = f.real(i, "x");
            let y = f.real(i + 1, "y");
            if let Some(&(px, _)) = points.last()
                && x < px
            {
                f.error(
                    i,
                    "x",
                    format!("x values must not decrease: {x:e} after {px:e}"),
                );
            }
            points.push((x, y));
            i += 2;
        }
        if !ended {
            f.card_error("the table does not end with ENDT");
        }
        if points.len() < 2 {
            f.card_error("a table needs at least two points");
        }
        let loc = f.loc();
        f.finish(len)?;
        Ok(Tabled1 { id, points, loc })
    }
}

/// `DLOAD` — linear combination of dynamic load sets (TLOAD1 or RLOAD1): S · Σ Si · (set Li).
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | SID | int > 0 | required | new set id |
/// | 3 | S | real | required | overall scale |
/// | 4, 5, … | S1 L1 S2 L2 … | real, int > 0 | ≥ 1 pair | scale and TLOAD1/RLOAD1 set id |
#[derive(Debug, Clone, PartialEq)]
pub struct Dload {
    pub sid: u32,
    pub scale: f64,
    pub terms: Vec<(f64, u32)>,
    pub loc: Loc,
}

impl Dload {
    /// Read a `DLOAD` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let (sid, scale, terms, loc) = combination(card)?;
        Ok(Dload {
            sid,
            scale,
            terms,
            loc,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::deck::cards::geometry::tests::raw;

    /// With neither V2 nor ND, EIGRL asks for the lowest root (above V1), as Nastran does.
    #[test]
    fn eigrl_without_v2_and_nd_finds_the_lowest_root() {
        let e = Eigrl::from_card(&raw("EIGRL", &["1", "0."])).expect("valid");
        assert_eq!((e.v1, e.v2, e.nd), (Some(0.0), None, Some(1)));
        let e = Eigrl::from_card(&raw("EIGRL", &["1", "", "100."])).expect("valid");
        assert_eq!((e.v2, e.nd), (Some(100.0), None));
    }
}
