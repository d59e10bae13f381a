//! Multibody cards of `SOL FMB` (DESIGN.md §11): bodies (`FLEXB`, `RIGIDB`), points on them
//! (`MARKER`), joints and drives (`JOINT`, `JDRIVE`), spring-dampers (`JSPRD`, `SPDMP`), point
//! forces and moments (`MFORCE`, `MMOMENT`) and outputs (`MSENSOR`). Ids of each card live in their own id space;
//! the model cross-references them ([`crate::model::mechanism`]).

use crate::card_values::{ForceKind, JointType, MsensorKind};
use crate::deck::error::{DeckError, Loc};
use crate::deck::fields::RawCard;
use crate::deck::reader::FieldReader;
use crate::deck::value::Value;

/// Reads an optional direction (three reals, blank = `default`); an explicit zero vector is an
/// error on the first field.
fn direction(f: &mut FieldReader, first: usize, default: [f64; 3]) -> [f64; 3] {
    let names = ["N1", "N2", "N3"];
    if (first..first + 3).all(|i| f.value(i).is_blank()) {
        return default;
    }
    let n: [f64; 3] = std::array::from_fn(|k| f.real_or(first + k, names[k], 0.0));
    if n == [0.0; 3] {
        f.error(first, "N1", "the direction vector is zero");
    }
    n
}

/// `FLEXB` — a flexible body: a pROM artifact built with `RIGID = REMOVE`.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | ID | int > 0 | required | body id |
/// | 3 | NAME | name | required | body name; its parameters are `NAME.PMPAR` in PVAL |
/// | 4 | PATH | quoted string | required | the pROM artifact (HDF5), relative to the file holding the card |
/// | 5 | CID | int ≥ 0 | 0 | rectangular system that places the artifact's basic system (origin and axes) |
#[derive(Debug, Clone, PartialEq)]
pub struct Flexb {
    pub id: u32,
    pub name: String,
    pub path: String,
    pub cid: u32,
    pub loc: Loc,
}

impl Flexb {
    /// Read a `FLEXB` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let id = f.id(1, "ID");
        f.set_id(id);
        let name = f.text(2, "NAME");
        if name.contains('.') {
            f.error(2, "NAME", format!("body name {name} must not contain '.'"));
        }
        let path = f.path(3, "PATH");
        let cid = f.id0_or(4, "CID", 0);
        let loc = f.loc();
        f.finish(4)?;
        Ok(Flexb {
            id,
            name,
            path,
            cid,
            loc,
        })
    }
}

/// `RIGIDB` — a rigid body: mass, centre of mass and inertia about it.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | ID | int > 0 | required | body id (shares the id space of FLEXB) |
/// | 3 | NAME | name | required | body name |
/// | 4 | MASS | real > 0 | required | mass |
/// | 5 | CID | int ≥ 0 | 0 | rectangular system of X and of the inertia components |
/// | 6–8 | X1 X2 X3 | real | 0.0 | centre of mass in CID (initial configuration) |
/// | cont. 2–7 | I11 I21 I22 I31 I32 I33 | real | 0.0 | inertia tensor about the centre of mass in CID (I11, I22, I33 ≥ 0) |
#[derive(Debug, Clone, PartialEq)]
pub struct Rigidb {
    pub id: u32,
    pub name: String,
    pub mass: f64,
    pub cid: u32,
    pub centre: [f64; 3],
    /// The symmetric inertia tensor, rows.
    pub inertia: [[f64; 3]; 3],
    pub loc: Loc,
}

impl Rigidb {
    /// Read a `RIGIDB` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let id = f.id(1, "ID");
        f.set_id(id);
        let name = f.text(2, "NAME");
        let mass = f.positive_real(3, "MASS");
        let cid = f.id0_or(4, "CID", 0);
        let centre = [
            f.real_or(5, "X1", 0.0),
            f.real_or(6, "X2", 0.0),
            f.real_or(7, "X3", 0.0),
        ];
        let names = ["I11", "I21", "I22", "I31", "I32", "I33"];
        let i: [f64; 6] = std::array::from_fn(|k| f.real_or(9 + k, names[k], 0.0));
        for (k, field) in [(0, 9), (2, 11), (5, 14)] {
            if i[k] < 0.0 {
                f.error(
                    field,
                    names[k],
                    format!("expected a moment of inertia >= 0, found {:e}", i[k]),
                );
            }
        }
        let inertia = [[i[0], i[1], i[3]], [i[1], i[2], i[4]], [i[3], i[4], i[5]]];
        let loc = f.loc();
        f.finish(14)?;
        Ok(Rigidb {
            id,
            name,
            mass,
            cid,
            centre,
            inertia,
            loc,
        })
    }
}

/// `MARKER` — a point on a body.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | ID | int > 0 | required | marker id |
/// | 3 | BODY | int ≥ 0 | 0 | FLEXB or RIGIDB id; 0 = the ground |
/// | 4 | GRID | int > 0 | blank | on a flexible body: an interface grid of its artifact (required there, blank elsewhere) |
/// | 5–7 | X1 X2 X3 | real | 0.0 | on a rigid body or the ground: the point in CID (initial configuration); blank on a flexible body |
/// | 8 | CID | int ≥ 0 | 0 | rectangular system of X |
#[derive(Debug, Clone, PartialEq)]
pub struct Marker {
    pub id: u32,
    pub body: u32,
    pub grid: Option<u32>,
    pub point: [f64; 3],
    pub cid: u32,
    pub loc: Loc,
}

impl Marker {
    /// Read a `MARKER` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let id = f.id(1, "ID");
        f.set_id(id);
        let body = f.id0_or(2, "BODY", 0);
        let grid = f.opt_id(3, "GRID");
        let point = [
            f.real_or(4, "X1", 0.0),
            f.real_or(5, "X2", 0.0),
            f.real_or(6, "X3", 0.0),
        ];
        if grid.is_some() && (4..=6).any(|i| !f.value(i).is_blank()) {
            f.error(
                4,
                "X1",
                "a marker is either a GRID (flexible body) or a point X (rigid body, ground): not both",
            );
        }
        let cid = f.id0_or(7, "CID", 0);
        let loc = f.loc();
        f.finish(7)?;
        Ok(Marker {
            id,
            body,
            grid,
            point,
            cid,
            loc,
        })
    }
}

/// `JOINT` — a joint between two markers.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | ID | int > 0 | required | joint id |
/// | 3 | TYPE | `REV` `FIX` `SPH` `PRIS` `CYL` `UNIV` `INLINE` `INPLANE` | required | revolute about N, bracket, spherical, prismatic along N, cylindrical along N, universal (cross axes: N on MK2's side and a perpendicular one on MK1's), MK1 on the line through MK2 along N, MK1 in the plane through MK2 normal to N |
/// | 4 | MK1 | int > 0 | required | first marker |
/// | 5 | MK2 | int ≥ 0 | 0 | second marker; 0 = the ground at MK1's initial position |
/// | 6–8 | N1 N2 N3 | real | 0.0 0.0 1.0 | joint axis in CID (not zero) |
/// | 9 | CID | int ≥ 0 | 0 | rectangular system of N |
#[derive(Debug, Clone, PartialEq)]
pub struct Joint {
    pub id: u32,
    pub kind: JointType,
    pub first: u32,
    pub second: Option<u32>,
    pub axis: [f64; 3],
    pub cid: u32,
    pub loc: Loc,
}

impl Joint {
    /// Read a `JOINT` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let id = f.id(1, "ID");
        f.set_id(id);
        let kind = f.choice(2, "TYPE", &JointType::KEYWORDS, None);
        let first = f.id(3, "MK1");
        let second = Some(f.id0_or(4, "MK2", 0)).filter(|&m| m != 0);
        if second == Some(first) {
            f.error(
                4,
                "MK2",
                format!("MK2 = MK1 = {first}: a joint needs two markers"),
            );
        }
        let axis = direction(&mut f, 5, [0.0, 0.0, 1.0]);
        let cid = f.id0_or(8, "CID", 0);
        let loc = f.loc();
        f.finish(8)?;
        Ok(Joint {
            id,
            kind,
            first,
            second,
            axis,
            cid,
            loc,
        })
    }
}

/// `JDRIVE` — a prescribed relative coordinate of a `REV` or `PRIS` joint: initial value +
/// SCALE · TABLE(t) (radians for rotations).
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | ID | int > 0 | required | drive id |
/// | 3 | JOINT | int > 0 | required | the driven joint (REV or PRIS) |
/// | 4 | TID | int > 0 | required | TABLED1 or TABLEF of the motion (piecewise linear: its rate is the slope) |
/// | 5 | SCALE | real | 1.0 | scale of the table |
/// | 6 | K | real > 0 | blank | blank: rigid drive (a constraint; its reaction is the drive torque). Given: compliant drive with torque K(θ_d − θ) + C(θ̇_d − θ̇) (Fig. 4.15b) |
/// | 7 | C | real ≥ 0 | 0.0 | damping of a compliant drive (needs K) |
#[derive(Debug, Clone, PartialEq)]
pub struct Jdrive {
    pub id: u32,
    pub joint: u32,
    pub tid: u32,
    pub scale: f64,
    /// (K, C) of a compliant drive; `None`: rigid.
    pub compliance: Option<(f64, f64)>,
    pub loc: Loc,
}

impl Jdrive {
    /// Read a `JDRIVE` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let id = f.id(1, "ID");
        f.set_id(id);
        let joint = f.id(2, "JOINT");
        let tid = f.id(3, "TID");
        let scale = f.real_or(4, "SCALE", 1.0);
        let k = f.opt_real(5, "K");
        let c = f.opt_real(6, "C");
        if let Some(k) = k.filter(|&k| k <= 0.0) {
            f.error(5, "K", format!("expected K > 0 (or blank), found {k:e}"));
        }
        if let Some(c) = c.filter(|&c| c < 0.0) {
            f.error(6, "C", format!("expected C >= 0, found {c:e}"));
        }
        if k.is_none() && c.is_some() {
            f.error(6, "C", "C needs K: a rigid drive (K blank) has no damping");
        }
        let compliance = k.map(|k| (k, c.unwrap_or(0.0)));
        let loc = f.loc();
        f.finish(6)?;
        Ok(Jdrive {
            id,
            joint,
            tid,
            scale,
            compliance,
            loc,
        })
    }
}

/// Reads a non-negative real with a default.
fn non_negative(f: &mut FieldReader, i: usize, name: &str, default: f64) -> f64 {
    let v = f.real_or(i, name, default);
    if v < 0.0 {
        f.error(i, name, format!("expected {name} >= 0, found {v:e}"));
    }
    v
}

/// `JSPRD` — a spring-damper on the relative coordinate of a `REV` or `PRIS` joint.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | ID | int > 0 | required | id |
/// | 3 | JOINT | int > 0 | required | the joint (REV or PRIS) |
/// | 4 | K | real ≥ 0 | 0.0 | stiffness (torque per radian or force per length) |
/// | 5 | C | real ≥ 0 | 0.0 | damping |
/// | 6 | X0 | real | 0.0 | rest coordinate, relative to the initial one |
#[derive(Debug, Clone, PartialEq)]
pub struct Jsprd {
    pub id: u32,
    pub joint: u32,
    pub stiffness: f64,
    pub damping: f64,
    pub rest: f64,
    pub loc: Loc,
}

impl Jsprd {
    /// Read a `JSPRD` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let id = f.id(1, "ID");
        f.set_id(id);
        let joint = f.id(2, "JOINT");
        let stiffness = non_negative(&mut f, 3, "K", 0.0);
        let damping = non_negative(&mut f, 4, "C", 0.0);
        let rest = f.real_or(5, "X0", 0.0);
        let loc = f.loc();
        f.finish(5)?;
        Ok(Jsprd {
            id,
            joint,
            stiffness,
            damping,
            rest,
            loc,
        })
    }
}

/// `SPDMP` — a point-to-point spring-damper between two markers.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | ID | int > 0 | required | id |
/// | 3 | MK1 | int > 0 | required | first marker |
/// | 4 | MK2 | int > 0 | required | second marker |
/// | 5 | K | real ≥ 0 | 0.0 | stiffness |
/// | 6 | C | real ≥ 0 | 0.0 | damping |
/// | 7 | L0 | real > 0 | blank | free length; blank = the initial distance |
#[derive(Debug, Clone, PartialEq)]
pub struct Spdmp {
    pub id: u32,
    pub first: u32,
    pub second: u32,
    pub stiffness: f64,
    pub damping: f64,
    pub length: Option<f64>,
    pub loc: Loc,
}

impl Spdmp {
    /// Read a `SPDMP` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let id = f.id(1, "ID");
        f.set_id(id);
        let first = f.id(2, "MK1");
        let second = f.id(3, "MK2");
        if first == second {
            f.error(
                3,
                "MK2",
                format!("MK2 = MK1 = {first}: the spring needs two markers"),
            );
        }
        let stiffness = non_negative(&mut f, 4, "K", 0.0);
        let damping = non_negative(&mut f, 5, "C", 0.0);
        let length = f.opt_real(6, "L0");
        if let Some(l) = length.filter(|&l| l <= 0.0) {
            f.error(6, "L0", format!("expected L0 > 0 (or blank), found {l:e}"));
        }
        let loc = f.loc();
        f.finish(6)?;
        Ok(Spdmp {
            id,
            first,
            second,
            stiffness,
            damping,
            length,
            loc,
        })
    }
}

/// `MFORCE` / `MMOMENT` — a force (moment) SCALE · TABLE(t) at a marker along (about) a fixed global direction.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | ID | int > 0 | required | id (MFORCE and MMOMENT share the id space) |
/// | 3 | MK | int > 0 | required | marker (not on the ground); a moment turns the marker's frame, so on a flexible body it loads the interface grid's rotations |
/// | 4 | TID | int > 0 | required | TABLED1 or TABLEF of the amplitude |
/// | 5 | SCALE | real | 1.0 | scale of the table (force, or moment in force × length) |
/// | 6–8 | N1 N2 N3 | real | required | direction (moment axis, right-hand rule) in CID (not zero; normalized); it stays fixed in space as the body turns |
/// | 9 | CID | int ≥ 0 | 0 | rectangular system of N |
#[derive(Debug, Clone, PartialEq)]
pub struct Mforce {
    pub id: u32,
    /// Force (`MFORCE`) or moment (`MMOMENT`).
    pub kind: ForceKind,
    pub marker: u32,
    pub tid: u32,
    pub scale: f64,
    pub direction: [f64; 3],
    pub cid: u32,
    pub loc: Loc,
}

impl Mforce {
    /// Read a `MFORCE` (`kind` force) or `MMOMENT` (`kind` moment) card.
    pub fn from_card(card: &RawCard, kind: ForceKind) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let id = f.id(1, "ID");
        f.set_id(id);
        let marker = f.id(2, "MK");
        let tid = f.id(3, "TID");
        let scale = f.real_or(4, "SCALE", 1.0);
        if (5..=7).all(|i| f.value(i).is_blank()) {
            f.error(5, "N1", "expected a direction N1 N2 N3, found blank fields");
        }
        let direction = direction(&mut f, 5, [0.0; 3]);
        let cid = f.id0_or(8, "CID", 0);
        let loc = f.loc();
        f.finish(8)?;
        Ok(Mforce {
            id,
            kind,
            marker,
            tid,
            scale,
            direction,
            cid,
            loc,
        })
    }
}

/// `MSENSOR` — a multibody output, written as `/results/<sc>/fmb/sensors/<NAME>`.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | ID | int > 0 | required | id |
/// | 3 | NAME | name | required | output name (unique) |
/// | 4 | KIND | `POS` `ACCEL` `JFORCE` `JTORQ` `POWER` `ENERGY` `KE` `STRAIN` `DEV` | required | global position (eq. 2.58) or acceleration (eq. 2.59) of marker REF along N; reaction force of joint REF (REV, FIX, SPH or UNIV) on MK1's body along N; torque (force) of the JDRIVE of joint REF; power ω·T and actuation energy ∫ω·T dt of JDRIVE REF, or with REF blank summed over every JDRIVE (eq. 6.1 f₂); kinetic energy of the system (REF blank); strain ε = C_ε q_f of the flexible body BODY at the STRAIN sensor REF of its artifact (eq. 2.57; relative to the configuration case control `STRREF` names); `DEV`: the distance ‖x − x_R‖ of marker REF from the same marker of the rigid twin (eq. 4.10: the mechanism with its flexible bodies rigid, with their undeformed mass properties at p; run only when a DEV output is selected) |
/// | 5 | BODY | int ≥ 0 | 0 | the FLEXB of a STRAIN output; blank otherwise |
/// | 6 | REF | int > 0 or name | blank | marker (POS, ACCEL, DEV), joint (JFORCE, JTORQ) or JDRIVE (POWER, ENERGY; blank: every JDRIVE) id; the name of a STRAIN sensor of BODY's artifact (STRAIN); blank for KE |
/// | 7–9 | N1 N2 N3 | real | required for POS, ACCEL, JFORCE | direction in the global (basic) system, normalized |
#[derive(Debug, Clone, PartialEq)]
pub struct Msensor {
    pub id: u32,
    pub name: String,
    pub kind: MsensorKind,
    pub body: u32,
    /// The id REF (every kind but STRAIN and KE).
    pub reference: Option<u32>,
    /// The artifact's sensor name REF of a STRAIN output.
    pub strain_sensor: Option<String>,
    pub direction: [f64; 3],
    pub loc: Loc,
}

impl Msensor {
    /// Read a `MSENSOR` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let id = f.id(1, "ID");
        f.set_id(id);
        let name = f.text(2, "NAME");
        let kind = f.choice(3, "KIND", &MsensorKind::KEYWORDS, None);
        let body = f.id0_or(4, "BODY", 0);
        let strain = kind == MsensorKind::Strain;
        if strain && body == 0 {
            f.error(
                4,
                "BODY",
                "a STRAIN output needs the FLEXB whose artifact holds the sensor, found 0 (blank)",
            );
        }
        let strain_sensor = strain.then(|| f.text(5, "REF"));
        let reference = if strain { None } else { f.opt_id(5, "REF") };
        match (kind, reference) {
            (MsensorKind::Strain, _) => {}
            (MsensorKind::Ke, Some(_)) => {
                f.error(5, "REF", "KE is the system's: REF must be blank")
            }
            // POWER and ENERGY with REF blank: the sum over every JDRIVE (eq. 6.1 f₂)
            (MsensorKind::Ke | MsensorKind::Power | MsensorKind::Energy, None) => {}
            (_, None) => f.error(
                5,
                "REF",
                "expected the id this sensor refers to, found blank",
            ),
            _ => {}
        }
        let needs_direction = matches!(
            kind,
            MsensorKind::Pos | MsensorKind::Accel | MsensorKind::Jforce
        );
        if needs_direction && (6..=8).all(|i| f.value(i).is_blank()) {
            f.error(6, "N1", "expected a direction N1 N2 N3, found blank fields");
        }
        if !needs_direction && (6..=8).any(|i| matches!(f.value(i), Value::Real(_))) {
            f.error(6, "N1", "a direction applies to POS, ACCEL and JFORCE only");
        }
        let direction = direction(&mut f, 6, [0.0; 3]);
        let loc = f.loc();
        f.finish(8)?;
        Ok(Msensor {
            id,
            name,
            kind,
            body,
            reference,
            strain_sensor,
            direction,
            loc,
        })
    }
}

/// `FMBPOSE` — a grid of drive poses for the static subcases of `SOL FMB` (`POSES = id`).
///
/// The Cartesian product of one axis per drive, each axis N evenly spaced values from START
/// to STOP (START alone for N = 1) of the drive's coordinate relative to its initial value, in
/// the JDRIVE's units (what SCALE · TABLE(t) gives: radians for a REV joint, length for a
/// PRIS joint). Each axis takes four fields, the axes following each other across
/// continuation lines (as PVAL's pairs do).
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | ID | int > 0 | required | pose grid id |
/// | 3–6 | JDRIVE1 START1 STOP1 N1 | int > 0, real, real, int > 0 | required | first axis: the JDRIVE whose coordinate it sets, first and last value, number of values |
/// | 7–9, cont. 1 field 2 | JDRIVE2 START2 STOP2 N2 | as above | blank | second axis (its drive different from the first's) |
/// | cont. 1 fields 3–6, … | JDRIVE3 … | as above | blank | further axes, four fields each, each on its own drive |
#[derive(Debug, Clone, PartialEq)]
pub struct Fmbpose {
    pub id: u32,
    pub axes: Vec<PoseAxis>,
    pub loc: Loc,
}

/// One axis of an `FMBPOSE`: the JDRIVE id and its values.
#[derive(Debug, Clone, PartialEq)]
pub struct PoseAxis {
    pub drive: u32,
    pub start: f64,
    pub stop: f64,
    pub count: u32,
    /// Where the JDRIVE field was written, for cross-reference messages.
    pub loc: Loc,
    /// The JDRIVE field's label (`field 3`, `field 3 of continuation 1` …).
    pub field: String,
}

impl PoseAxis {
    /// The N evenly spaced values START … STOP.
    pub fn values(&self) -> Vec<f64> {
        if self.count <= 1 {
            return vec![self.start];
        }
        let last = f64::from(self.count - 1);
        (0..self.count)
            .map(|i| self.start + (self.stop - self.start) * f64::from(i) / last)
            .collect()
    }
}

impl Fmbpose {
    /// Read an `FMBPOSE` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let id = f.id(1, "ID");
        f.set_id(id);
        let len = f.len();
        let mut axes: Vec<PoseAxis> = Vec::new();
        let mut i = 2;
        while i <= len {
            if (i..i + 4).all(|k| f.value(k).is_blank()) {
                i += 4;
                continue;
            }
            let drive = f.id(i, "JDRIVE");
            let start = f.real(i + 1, "START");
            let stop = f.real(i + 2, "STOP");
            let count = f.count(i + 3, "N");
            if drive > 0 && axes.iter().any(|a| a.drive == drive) {
                f.error(
                    i,
                    "JDRIVE",
                    format!("JDRIVE {drive} has two axes on this card"),
                );
            }
            axes.push(PoseAxis {
                drive,
                start,
                stop,
                count,
                loc: card.loc_of(i),
                field: RawCard::field_label(i),
            });
            i += 4;
        }
        if axes.is_empty() {
            f.card_error("no (JDRIVE, START, STOP, N) group given");
        }
        let loc = f.loc();
        f.finish(len.max(5))?;
        Ok(Fmbpose { id, axes, loc })
    }
}
