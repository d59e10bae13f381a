//! Properties: `PSHELL`, `PCOMP`, `PCOMPG`, `PSOLID`, `PELAS`, `PDAMP`, `PVISC`, `PBUSH`.

use crate::deck::error::{DeckError, Loc};
use crate::deck::fields::RawCard;
use crate::deck::reader::FieldReader;
use crate::deck::value::Value;

/// `PSHELL` — homogeneous shell property (Nastran semantics: each role has its own material).
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | PID | int > 0 | required | property id |
/// | 3 | MID1 | int > 0 | blank | membrane material (MAT1 or MAT8): A = T·Q1; blank: no membrane stiffness |
/// | 4 | T | real > 0 | required | membrane thickness |
/// | 5 | MID2 | int > 0 | blank | bending material (MAT1 or MAT8): D = (12I/T³)·T³/12·Q2; blank: membrane only (no bending, no transverse shear); −1 (plane strain) is refused |
/// | 6 | 12I/T³ | real > 0 | 1.0 | bending inertia ratio |
/// | 7 | MID3 | int > 0 | blank | transverse-shear material: S = (TS/T)·T·G3 with G3 = G·I (MAT1), diag(G1Z, G2Z) (MAT8); must be blank unless MID2 is given; blank: rigid in transverse shear (stiff penalty, see `fe::laminate`) |
/// | 8 | TS/T | real > 0 | 0.833333 | transverse shear thickness ratio |
/// | 9 | NSM | real | 0.0 | non-structural mass per area |
/// | cont. 2–3 | Z1 Z2 | real | −T/2, T/2 | fibre distances for strain output |
/// | cont. 4 | MID4 | int > 0 | blank | membrane–bending coupling material: B = T²·Q4; needs MID1 and MID2, differs from both |
///
/// Mass per area ρT + NSM with ρ of MID1 (of MID2 when MID1 is blank). ZOFFS on the element
/// needs MID1 and MID2, as in Nastran.
#[derive(Debug, Clone, PartialEq)]
pub struct Pshell {
    pub id: u32,
    pub mid1: Option<u32>,
    pub t: f64,
    pub mid2: Option<u32>,
    pub bending_ratio: f64,
    pub mid3: Option<u32>,
    pub ts_t: f64,
    pub nsm: f64,
    pub z1: f64,
    pub z2: f64,
    pub mid4: Option<u32>,
    pub loc: Loc,
}

impl Pshell {
    /// Read a `PSHELL` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let id = f.id(1, "PID");
        f.set_id(id);
        let mid1 = f.opt_id(2, "MID1");
        let t = f.real(3, "T");
        let mid2 = if let Value::Int(-1) = f.value(4) {
            f.error(
                4,
                "MID2",
                "MID2 = -1 (plane strain) is not supported; paraflex shells are plane stress",
            );
            None
        } else {
            f.opt_id(4, "MID2")
        };
        let bending_ratio = f.real_or(5, "12I/T**3", 1.0);
        let mid3 = f.opt_id(6, "MID3");
        let ts_t = f.real_or(7, "TS/T", 0.833333);
        let nsm = f.real_or(8, "NSM", 0.0);
        let z1 = f.real_or(9, "Z1", -t / 2.0);
        let z2 = f.real_or(10, "Z2", t / 2.0);
        let mid4 = f.opt_id(11, "MID4");
        let loc = f.loc();
        f.finish(11)?;
        Ok(Pshell {
            id,
            mid1,
            t,
            mid2,
            bending_ratio,
            mid3,
            ts_t,
            nsm,
            z1,
            z2,
            mid4,
            loc,
        })
    }
}

/// One ply of a `PCOMP`.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Ply {
    pub mid: u32,
    pub t: f64,
    /// Fibre angle in degrees from the element material x axis.
    pub theta: f64,
    /// Stress/strain output requested for this ply (`SOUT = YES`).
    pub sout: bool,
}

/// `PCOMP` — layered composite shell property (classical lamination theory).
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | PID | int > 0 | required | property id |
/// | 3 | Z0 | real | −(total thickness)/2 | distance from the reference plane to the bottom surface |
/// | 4 | NSM | real | 0.0 | non-structural mass per area |
/// | 5 | SB | real | 0.0 | allowable interlaminar shear (kept, unused: no bonding index) |
/// | 6 | FT | name | blank | ply failure theory of the SOL 101 STRESS output: `HILL`, `HOFF`, `TSAI`, `STRN` (formulas in [elements.md](elements.md#stress-recovery)); another name, a MAT1 ply or missing MAT8 allowables give NaN indices and one warning per PCOMP and material |
/// | 7 | TREF | real | 0.0 | reference (stress-free) temperature of every ply (the plies' material TREFs are not used) |
/// | 8 | GE | real | 0.0 | structural damping coefficient |
/// | 9 | LAM | blank or `SYM` | blank | `SYM`: plies given are the lower half of a symmetric laminate |
/// | cont. | MIDi Ti THETAi SOUTi | int, real, real, YES/NO | previous ply's MID and T; THETA 0.0; NO | plies from bottom to top, two per line (SOUT is not consulted: STRESS writes every ply) |
///
/// `PCOMPG` has the same first line and one ply per continuation line:
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | cont. 2 | GPLYIDi | int > 0 | required | global ply id (unique on the card; kept, output numbers plies by position) |
/// | cont. 3–6 | MIDi Ti THETAi SOUTi | int, real, real, YES/NO | as PCOMP | the ply, bottom to top |
#[derive(Debug, Clone, PartialEq)]
pub struct Pcomp {
    pub id: u32,
    /// Z0 as given (blank = −total/2, resolved once the plies are known).
    pub z0: Option<f64>,
    pub nsm: f64,
    pub sb: f64,
    pub ft: Option<String>,
    pub tref: f64,
    pub ge: f64,
    /// True for `LAM = SYM`.
    pub symmetric: bool,
    /// Plies as written (the lower half when symmetric).
    pub plies: Vec<Ply>,
    /// PCOMPG: the global ply id of each ply of `plies` (empty for a PCOMP).
    pub global_ply_ids: Vec<u32>,
    pub loc: Loc,
}

impl Pcomp {
    /// Read a `PCOMP` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        Self::read(card, false)
    }

    /// Read a `PCOMPG` card: the PCOMP header, then one ply per continuation line,
    /// `GPLYID MID T THETA SOUT`. The global ply ids are kept (unique, > 0) and the laminate is
    /// the PCOMP's; paraflex's ply output numbers plies by position, not by these ids.
    pub fn from_pcompg(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        Self::read(card, true)
    }

    /// `global`: the PCOMPG layout (8 fields a ply, its global id first) instead of the
    /// PCOMP's 4 fields a ply.
    fn read(card: &RawCard, global: bool) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let id = f.id(1, "PID");
        f.set_id(id);
        let z0 = f.opt_real(2, "Z0");
        let nsm = f.real_or(3, "NSM", 0.0);
        let sb = f.real_or(4, "SB", 0.0);
        let ft = f.opt_text(5, "FT");
        let tref = f.real_or(6, "TREF", 0.0);
        let ge = f.real_or(7, "GE", 0.0);
        let lam = f.keyword(
            8,
            "LAM",
            &["SYM", "MEM", "BEND", "SMEAR", "SMCORE"],
            Some(""),
        );
        let symmetric = lam == "SYM";
        if !lam.is_empty() && !symmetric {
            f.error(
                8,
                "LAM",
                format!("LAM = {lam} is not supported; paraflex supports blank and SYM"),
            );
        }
        let mut plies: Vec<Ply> = Vec::new();
        let mut global_ply_ids: Vec<u32> = Vec::new();
        let len = f.len();
        let (stride, mut i) = if global { (8, 10) } else { (4, 9) };
        while i <= len {
            let blank_ply = (i..i + 4).all(|k| f.value(k).is_blank());
            // a PCOMPG ply is there when its line has a global id or any ply field
            let present = !blank_ply || (global && !f.value(i - 1).is_blank());
            if global && present {
                let k = plies.len() + 1;
                let id = f.id(i - 1, &format!("GPLYID{k}"));
                if global_ply_ids.contains(&id) {
                    f.error(
                        i - 1,
                        &format!("GPLYID{k}"),
                        format!("global ply id {id} is repeated"),
                    );
                }
                global_ply_ids.push(id);
            }
            if present {
                let k = plies.len() + 1;
                let prev = plies.last().cloned();
                let mid = match (f.opt_id(i, &format!("MID{k}")), &prev) {
                    (Some(m), _) => m,
                    (None, Some(p)) => p.mid,
                    (None, None) => {
                        f.error(i, "MID1", "the first ply needs a material id");
                        0
                    }
                };
                let t = match (f.opt_real(i + 1, &format!("T{k}")), &prev) {
                    (Some(t), _) => t,
                    (None, Some(p)) => p.t,
                    (None, None) => {
                        f.error(i + 1, "T1", "the first ply needs a thickness");
                        0.0
                    }
                };
                let theta = f.real_or(i + 2, &format!("THETA{k}"), 0.0);
                let sout =
                    f.keyword(i + 3, &format!("SOUT{k}"), &["YES", "NO"], Some("NO")) == "YES";
                plies.push(Ply {
                    mid,
                    t,
                    theta,
                    sout,
                });
            }
            i += stride;
        }
        if plies.is_empty() {
            f.card_error("no ply given (MID1 T1 THETA1 SOUT1 on the continuation)");
        }
        let loc = f.loc();
        f.finish(len.max(8))?;
        Ok(Pcomp {
            id,
            z0,
            nsm,
            sb,
            ft,
            tref,
            ge,
            symmetric,
            plies,
            global_ply_ids,
            loc,
        })
    }

    /// Every ply through the thickness, bottom to top (the mirror image appended for `SYM`).
    pub fn full_stack(&self) -> Vec<Ply> {
        let mut stack = self.plies.clone();
        if self.symmetric {
            stack.extend(self.plies.iter().rev().cloned());
        }
        stack
    }

    /// Total laminate thickness.
    pub fn thickness(&self) -> f64 {
        let half: f64 = self.plies.iter().map(|p| p.t).sum();
        if self.symmetric { 2.0 * half } else { half }
    }

    /// Z0 with its default (−thickness/2) applied.
    pub fn z0_resolved(&self) -> f64 {
        self.z0.unwrap_or(-0.5 * self.thickness())
    }
}

/// `PSOLID` — solid element property.
///
/// Its PID may repeat the id of a shell or line property: a solid element's PID names a PSOLID,
/// any other element's PID the other property (MSC Nastran runs such decks, e.g. its `rs321h`).
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | PID | int > 0 | required | property id |
/// | 3 | MID | int > 0 | required | MAT1 id |
/// | 4 | CORDM | int ≥ −1 | 0 | material coordinate system (no effect for isotropic MAT1) |
/// | 5 | IN | int or name | blank | integration network: kept, not used (paraflex picks its own rule) |
/// | 6 | STRESS | int or name | blank | stress output location: kept, not used |
/// | 7 | ISOP | int or name | blank | integration scheme: kept, not used |
/// | 8 | FCTN | name | SMECH | only SMECH (structural) is supported |
#[derive(Debug, Clone, PartialEq)]
pub struct Psolid {
    /// The card it was read from: `PSOLID`, or `PCOMPS` for a one-material solid laminate.
    pub card: &'static str,
    pub id: u32,
    pub mid: u32,
    pub cordm: i64,
    /// IN, STRESS, ISOP as written (kept and noted, no effect on paraflex's formulation).
    pub kept: Vec<String>,
    pub loc: Loc,
}

impl Psolid {
    /// Read a `PSOLID` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let id = f.id(1, "PID");
        f.set_id(id);
        let mid = f.id(2, "MID");
        let cordm = f.int_or(3, "CORDM", 0);
        if cordm < -1 {
            f.error(
                3,
                "CORDM",
                format!("expected -1 or a system id >= 0, found {cordm}"),
            );
        }
        let mut kept = Vec::new();
        for (i, name) in [(4, "IN"), (5, "STRESS"), (6, "ISOP")] {
            let v = f.value(i);
            if !v.is_blank() {
                kept.push(format!("{name}={}", v.describe()));
            }
        }
        let fctn = f.keyword(7, "FCTN", &["SMECH", "PFLUID", "FFLUID"], Some("SMECH"));
        if fctn != "SMECH" {
            f.error(
                7,
                "FCTN",
                format!("FCTN = {fctn} is not supported; only SMECH (structural)"),
            );
        }
        let loc = f.loc();
        f.finish(7)?;
        Ok(Psolid {
            card: "PSOLID",
            id,
            mid,
            cordm,
            kept,
            loc,
        })
    }

    /// Its card and id, e.g. `PCOMPS 2`.
    pub fn label(&self) -> String {
        format!("{} {}", self.card, self.id)
    }
}

/// `PCOMPS` — layered solid property (NX), read when all plies share one MAT1.
///
/// For CHEXA and CPENTA; read as the homogeneous PSOLID it then is.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | PID | int > 0 | required | property id |
/// | 3 | CORDM | int ≥ −1 | 0 | material coordinate system (no effect for one isotropic MAT1) |
/// | 4 | PSDIR | 12, 13, 21, 23, 31, 32 | 13 | ply plane and stacking directions (no effect with one material) |
/// | 5, 6 | SB NB | real > 0 | blank | inter-laminar shear and normal allowables (kept, unused) |
/// | 7 | TREF | real | 0.0 | reference temperature (kept, unused) |
/// | 8 | GE | real | 0.0 | structural damping: only 0 (the MAT1's GE applies, as for a PSOLID) |
/// | per ply row: 2 | GPLYID | int > 0 | required | global ply id |
/// | 3 | MID | int > 0 | required | the ply's MAT1: the same on every ply |
/// | 4 | T | real > 0 | required | ply thickness (relative: the element's thickness is shared in these proportions) |
/// | 5 | THETA | real | 0.0 | ply angle (no effect for an isotropic MAT1) |
/// | 6–9 | FT, IR, SOUT, … | | blank | failure theory and ply output options (kept, unused) |
///
/// With one isotropic material in every ply, the ply-wise integration through the thickness
/// gives the homogeneous solid's stiffness and mass whatever the ply thicknesses, angles and
/// stacking direction, so the element is a PSOLID of that MAT1. Plies of different materials
/// (a real laminate, which needs ply-wise integration in the solid kernels) are refused at the
/// first MID that differs.
pub fn pcomps(card: &RawCard) -> Result<Psolid, Vec<DeckError>> {
    let mut f = FieldReader::new(card);
    let id = f.id(1, "PID");
    f.set_id(id);
    let cordm = f.int_or(2, "CORDM", 0);
    if cordm < -1 {
        f.error(
            2,
            "CORDM",
            format!("expected -1 or a system id >= 0, found {cordm}"),
        );
    }
    let psdir = f.int_or(3, "PSDIR", 13);
    if ![12, 13, 21, 23, 31, 32].contains(&psdir) {
        f.error(
            3,
            "PSDIR",
            format!("expected 12, 13, 21, 23, 31 or 32, found {psdir}"),
        );
    }
    for (i, name) in [(4, "SB"), (5, "NB"), (6, "TREF")] {
        f.opt_real(i, name);
    }
    if f.real_or(7, "GE", 0.0) != 0.0 {
        f.error(
            7,
            "GE",
            "a PCOMPS GE is not supported: leave it blank (the MAT1's GE gives the damping, as for a PSOLID)",
        );
    }
    let mut mid = None;
    let len = f.len();
    let mut i = 9;
    while i <= len {
        let k = (i - 9) / 8 + 1;
        if (i..i + 8).all(|j| f.value(j).is_blank()) {
            i += 8;
            continue;
        }
        f.id(i, &format!("GPLYID{k}"));
        let m = f.id(i + 1, &format!("MID{k}"));
        let t = f.real(i + 2, &format!("T{k}"));
        if t <= 0.0 {
            f.error(i + 2, &format!("T{k}"), format!("T{k} = {t} must be > 0"));
        }
        f.real_or(i + 3, &format!("THETA{k}"), 0.0);
        match mid {
            None => mid = Some(m),
            Some(first) if first != m => f.error(
                i + 1,
                &format!("MID{k}"),
                format!("ply {k} has MID {m} and ply 1 MID {first}: paraflex reads a PCOMPS whose plies share one MAT1 (a homogeneous solid); plies of different materials need ply-wise integration, which is not supported"),
            ),
            Some(_) => {}
        }
        i += 8;
    }
    let Some(mid) = mid else {
        f.card_error("a PCOMPS needs at least one ply");
        return Err(f.finish(len).err().unwrap_or_default());
    };
    let loc = f.loc();
    f.finish(len)?;
    Ok(Psolid {
        card: "PCOMPS",
        id,
        mid,
        cordm,
        kept: Vec::new(),
        loc,
    })
}

/// `PELAS` — scalar spring property (one or two per card).
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | PID1 | int > 0 | required | property id |
/// | 3 | K1 | real | required | stiffness |
/// | 4 | GE1 | real | 0.0 | structural damping coefficient |
/// | 5 | S1 | real | 0.0 | stress coefficient (kept, unused) |
/// | 6–9 | PID2 K2 GE2 S2 | | blank | an optional second property |
#[derive(Debug, Clone, PartialEq)]
pub struct Pelas {
    pub id: u32,
    pub k: f64,
    pub ge: f64,
    pub s: f64,
    pub loc: Loc,
}

impl Pelas {
    /// Read a `PELAS` card (one or two properties).
    pub fn from_card(card: &RawCard) -> Result<Vec<Self>, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let mut out = Vec::new();
        for first in [1, 5] {
            if first == 5 && (5..=8).all(|i| f.value(i).is_blank()) {
                break;
            }
            let id = f.id(first, "PID");
            f.set_id(id);
            let k = f.real(first + 1, "K");
            let ge = f.real_or(first + 2, "GE", 0.0);
            let s = f.real_or(first + 3, "S", 0.0);
            out.push(Pelas {
                id,
                k,
                ge,
                s,
                loc: f.loc(),
            });
        }
        f.finish(8)?;
        Ok(out)
    }
}

/// `PDAMP` — scalar damper property (up to four per card).
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2, 3 | PID1 B1 | int > 0, real | required | property id and damping |
/// | 4–9 | PID2 B2 … PID4 B4 | | blank | further properties |
#[derive(Debug, Clone, PartialEq)]
pub struct Pdamp {
    pub id: u32,
    pub b: f64,
    pub loc: Loc,
}

impl Pdamp {
    /// Read a `PDAMP` card (one to four properties).
    pub fn from_card(card: &RawCard) -> Result<Vec<Self>, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let mut out = Vec::new();
        for first in [1, 3, 5, 7] {
            if first > 1 && (first..=first + 1).all(|i| f.value(i).is_blank()) {
                continue;
            }
            let id = f.id(first, "PID");
            f.set_id(id);
            let b = f.real(first + 1, "B");
            out.push(Pdamp {
                id,
                b,
                loc: f.loc(),
            });
        }
        f.finish(8)?;
        Ok(out)
    }
}

/// `PVISC` — viscous damper property of a CVISC (one or two per card).
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | PID1 | int > 0 | required | property id |
/// | 3 | CE1 | real | 0.0 | axial damping (force per velocity) |
/// | 4 | CR1 | real | 0.0 | torsional damping (moment per angular velocity) |
/// | 6–8 | PID2 CE2 CR2 | | blank | an optional second property |
#[derive(Debug, Clone, PartialEq)]
pub struct Pvisc {
    pub id: u32,
    pub ce: f64,
    pub cr: f64,
    pub loc: Loc,
}

impl Pvisc {
    /// Read a `PVISC` card (one or two properties).
    pub fn from_card(card: &RawCard) -> Result<Vec<Self>, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let mut out = Vec::new();
        for first in [1, 5] {
            if first == 5 && (5..=7).all(|i| f.value(i).is_blank()) {
                break;
            }
            let id = f.id(first, "PID");
            f.set_id(id);
            let ce = f.real_or(first + 1, "CE", 0.0);
            let cr = f.real_or(first + 2, "CR", 0.0);
            out.push(Pvisc {
                id,
                ce,
                cr,
                loc: f.loc(),
            });
        }
        f.finish(7)?;
        Ok(out)
    }
}

/// `PBUSH` — CBUSH property: lines of six values, each introduced by its keyword in field 3.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | PID | int > 0 | required | property id |
/// | 3, 4–9 | `K` K1–K6 | real | 0.0 | stiffnesses along and about the element axes |
/// | next line 3, 4–9 | `B` B1–B6 | real | 0.0 | viscous damping |
/// | next line 3, 4–9 | `GE` GE1–GE6 | real | 0.0 | structural damping: GE1 alone is the element GE (GE1·K), GE2–GE6 given make one per direction (GEᵢ·Kᵢ) |
/// | next line 3, 4–7 | `RCV` SA ST EA ET | real | 1.0 | stress and strain recovery coefficients (kept, unused: no CBUSH force output) |
///
/// The lines may come in any order; `M` (mass) lines are refused.
#[derive(Debug, Clone, PartialEq)]
pub struct Pbush {
    pub id: u32,
    pub k: [f64; 6],
    pub b: [f64; 6],
    pub ge: [f64; 6],
    pub rcv: [f64; 4],
    pub loc: Loc,
}

impl Pbush {
    /// Read a `PBUSH` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let id = f.id(1, "PID");
        f.set_id(id);
        let (mut k, mut b, mut ge, mut rcv) = ([0.0; 6], [0.0; 6], [0.0; 6], [1.0; 4]);
        let mut key = 2;
        while key <= f.len() {
            let word = f.opt_text(key, "keyword").unwrap_or_default();
            let read = |f: &mut FieldReader, out: &mut [f64], name: &str, default: f64| {
                for (j, v) in out.iter_mut().enumerate() {
                    *v = f.real_or(key + 1 + j, &format!("{name}{}", j + 1), default);
                }
            };
            match word.to_ascii_uppercase().as_str() {
                "K" => read(&mut f, &mut k, "K", 0.0),
                "B" => read(&mut f, &mut b, "B", 0.0),
                "GE" => read(&mut f, &mut ge, "GE", 0.0),
                "RCV" => read(&mut f, &mut rcv, "S", 1.0),
                "" if (key..key + 8).all(|i| f.value(i).is_blank()) => {}
                other => f.error(
                    key,
                    "keyword",
                    format!("expected K, B, GE or RCV, found '{other}' (paraflex reads no PBUSH mass line)"),
                ),
            }
            key += 8;
        }
        let loc = f.loc();
        let len = f.len();
        f.finish(len)?;
        Ok(Pbush {
            id,
            k,
            b,
            ge,
            rcv,
            loc,
        })
    }
}
