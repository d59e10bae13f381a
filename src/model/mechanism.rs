//! The mechanism of a `SOL FMB` deck (DESIGN.md §11) as typed, cross-referenced data: bodies
//! (flexible from a pROM artifact, rigid), markers, joints, drives, spring-dampers, point forces
//! and outputs, every position and direction in the basic system and every reference an index.
//!
//! Checked here, each error at its card with the field: ids unique per card kind; a marker on
//! an existing body (0 = ground), with a GRID on a flexible body and a point on a rigid body or
//! the ground; joints between existing markers on two different bodies; drives and joint
//! spring-dampers on `REV` or `PRIS` joints only, at most one drive per joint; tables that
//! exist; rectangular coordinate systems; outputs that refer to what their kind needs, with
//! unique names; PVAL names of the form `BODY.PMPAR` with BODY a FLEXB name. What needs the
//! artifacts (a GRID that is an interface grid, the artifact's `RIGID = REMOVE` data, the
//! PMPAR names) is checked when the artifacts are read, with the card's position.

use std::collections::HashMap;
use std::path::PathBuf;

use crate::deck::cards::{BulkData, CordKind};
use crate::deck::{DeckError, Loc};
use crate::geometry::mat3::{Mat3, transpose};
use crate::geometry::rotation::rotate_tensor;
use crate::geometry::vec3::normalize;

use super::coords::CoordSystem;
use super::ids::{entry, index};
use crate::card_values::{ForceKind, JointType, MsensorKind};

/// What a body is.
#[derive(Debug, Clone, PartialEq)]
pub enum BodyKind {
    /// A pROM artifact whose basic system is placed at `origin` with axes `axes` (rows: the
    /// artifact's x, y, z in basic).
    Flexible {
        artifact: PathBuf,
        origin: [f64; 3],
        axes: Mat3,
    },
    /// Mass, centre of mass and inertia about it, in basic.
    Rigid {
        mass: f64,
        centre: [f64; 3],
        inertia: Mat3,
    },
}

/// A body (`FLEXB`, `RIGIDB`).
#[derive(Debug, Clone, PartialEq)]
pub struct Body {
    pub id: u32,
    pub name: String,
    pub kind: BodyKind,
    pub loc: Loc,
}

/// Where a marker is.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum MarkerPlace {
    /// A grid of a flexible body's artifact.
    Grid(u32),
    /// A point in basic (initial configuration).
    Point([f64; 3]),
}

/// A marker (`MARKER`).
#[derive(Debug, Clone, PartialEq)]
pub struct Marker {
    pub id: u32,
    /// Index into [`Mechanism::bodies`], `None` for the ground.
    pub body: Option<usize>,
    pub place: MarkerPlace,
    pub loc: Loc,
}

/// A joint (`JOINT`).
#[derive(Debug, Clone, PartialEq)]
pub struct Joint {
    pub id: u32,
    pub kind: JointType,
    /// Marker indices; `second = None`: the ground at the first marker's initial position.
    pub first: usize,
    pub second: Option<usize>,
    /// Unit axis in basic.
    pub axis: [f64; 3],
    pub loc: Loc,
}

/// A drive (`JDRIVE`): joint coordinate = initial value + scale · table(t).
#[derive(Debug, Clone, PartialEq)]
pub struct Drive {
    pub id: u32,
    /// Index into [`Mechanism::joints`].
    pub joint: usize,
    /// TABLED1 or TABLEF id.
    pub table: u32,
    pub scale: f64,
    /// (K, C) of a compliant drive, `None` for a rigid one.
    pub compliance: Option<(f64, f64)>,
    pub loc: Loc,
}

/// A spring-damper on a joint coordinate (`JSPRD`), at rest at initial value + `rest`.
#[derive(Debug, Clone, PartialEq)]
pub struct JointSpring {
    pub id: u32,
    pub joint: usize,
    pub stiffness: f64,
    pub damping: f64,
    pub rest: f64,
    pub loc: Loc,
}

/// A point-to-point spring-damper (`SPDMP`); `length = None`: the initial distance.
#[derive(Debug, Clone, PartialEq)]
pub struct PointSpring {
    pub id: u32,
    pub first: usize,
    pub second: usize,
    pub stiffness: f64,
    pub damping: f64,
    pub length: Option<f64>,
    pub loc: Loc,
}

/// A force (`MFORCE`) or moment (`MMOMENT`) at a marker: scale · table(t) along (about) a
/// unit direction in basic.
#[derive(Debug, Clone, PartialEq)]
pub struct PointForce {
    pub id: u32,
    pub kind: ForceKind,
    pub marker: usize,
    pub table: u32,
    pub scale: f64,
    pub direction: [f64; 3],
    pub loc: Loc,
}

/// What an output refers to.
#[derive(Debug, Clone, PartialEq)]
pub enum SensorTarget {
    Marker(usize),
    Joint(usize),
    Drive(usize),
    /// A STRAIN sensor (by name) of the artifact of a flexible body (index into the bodies);
    /// that the artifact has it is checked when the artifact is read.
    Strain {
        body: usize,
        sensor: String,
    },
    System,
}

/// An output (`MSENSOR`).
#[derive(Debug, Clone, PartialEq)]
pub struct Sensor {
    pub id: u32,
    pub name: String,
    pub kind: MsensorKind,
    pub target: SensorTarget,
    /// Unit direction in basic (zero where the kind has none).
    pub direction: [f64; 3],
    pub loc: Loc,
}

/// The mechanism of a deck (see module docs); empty for decks without multibody cards.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Mechanism {
    pub bodies: Vec<Body>,
    pub markers: Vec<Marker>,
    pub joints: Vec<Joint>,
    pub drives: Vec<Drive>,
    pub joint_springs: Vec<JointSpring>,
    pub point_springs: Vec<PointSpring>,
    pub forces: Vec<PointForce>,
    pub sensors: Vec<Sensor>,
}

impl Mechanism {
    /// True when the deck has no body.
    pub fn is_empty(&self) -> bool {
        self.bodies.is_empty()
    }

    /// The body named `name` (case-insensitive).
    pub fn body_named(&self, name: &str) -> Option<usize> {
        self.bodies
            .iter()
            .position(|b| b.name.eq_ignore_ascii_case(name))
    }
}

/// A card of a mechanism by its index, for what is found after the model is built (in the
/// artifacts or during the run), so that the error still points at the card.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Card {
    /// Index into [`Mechanism::bodies`].
    Body(usize),
    Marker(usize),
    Drive(usize),
    Force(usize),
    Sensor(usize),
}

impl Mechanism {
    /// An error with `message` at `card`'s position, with its field (number and name) if any.
    pub fn error_at(&self, card: Card, field: Option<&str>, message: String) -> DeckError {
        let (loc, label) = match card {
            Card::Body(i) => {
                let b = &self.bodies[i];
                let kind = match b.kind {
                    BodyKind::Flexible { .. } => "FLEXB",
                    BodyKind::Rigid { .. } => "RIGIDB",
                };
                (&b.loc, format!("{kind} {}", b.id))
            }
            Card::Marker(i) => (
                &self.markers[i].loc,
                format!("MARKER {}", self.markers[i].id),
            ),
            Card::Drive(i) => (&self.drives[i].loc, format!("JDRIVE {}", self.drives[i].id)),
            Card::Force(i) => {
                let f = &self.forces[i];
                (&f.loc, format!("{} {}", load_card(f.kind), f.id))
            }
            Card::Sensor(i) => (
                &self.sensors[i].loc,
                format!("MSENSOR {}", self.sensors[i].id),
            ),
        };
        let mut e = DeckError::at(loc, message).on_card(label);
        e.field = field.map(String::from);
        e
    }
}

/// The card name of a marker load.
fn load_card(kind: ForceKind) -> &'static str {
    match kind {
        ForceKind::Force => "MFORCE",
        ForceKind::Moment => "MMOMENT",
    }
}

/// An error at `loc` on card `card` (with its id), field `field` (number and name).
fn at(loc: &Loc, card: &str, id: u32, field: &str, message: String) -> DeckError {
    let mut e = DeckError::at(loc, message).on_card(format!("{card} {id}"));
    e.field = Some(field.to_string());
    e
}

/// Resolves a rectangular system for a multibody card.
fn rectangular<'a>(
    coords: &'a HashMap<u32, CoordSystem>,
    cid: u32,
    (loc, card, id, field): (&Loc, &str, u32, &str),
    errors: &mut Vec<DeckError>,
) -> Option<&'a CoordSystem> {
    match coords.get(&cid) {
        Some(c) if c.kind == CordKind::Rectangular => Some(c),
        Some(_) => {
            errors.push(at(
                loc,
                card,
                id,
                field,
                format!("CID = {cid} is cylindrical: multibody cards take rectangular systems"),
            ));
            None
        }
        None => {
            errors.push(at(
                loc,
                card,
                id,
                field,
                format!("CID = {cid} does not exist (no CORD2R {cid})"),
            ));
            None
        }
    }
}

/// A unit vector in basic from components in `c` (the cards reject zero vectors).
fn unit_in_basic(c: Option<&CoordSystem>, v: [f64; 3]) -> [f64; 3] {
    let basic = c.map_or(v, |c| c.vector_to_basic(v));
    normalize(basic).unwrap_or([0.0; 3])
}

/// Builds the mechanism of `bulk` (see module docs), pushing every error found.
pub fn build(
    bulk: &BulkData,
    coords: &HashMap<u32, CoordSystem>,
    errors: &mut Vec<DeckError>,
) -> Mechanism {
    let mut m = Mechanism::default();
    index(
        bulk.flexb
            .iter()
            .map(|b| entry(b.id, "FLEXB", &b.loc, ()))
            .chain(
                bulk.rigidb
                    .iter()
                    .map(|b| entry(b.id, "RIGIDB", &b.loc, ())),
            )
            .collect(),
        "body",
        errors,
    );
    for b in &bulk.flexb {
        let c = rectangular(
            coords,
            b.cid,
            (&b.loc, "FLEXB", b.id, "field 5 (CID)"),
            errors,
        );
        let artifact = b
            .loc
            .file
            .parent()
            .map_or_else(|| PathBuf::from(&b.path), |dir| dir.join(&b.path));
        let (origin, axes) = c.map_or(([0.0; 3], crate::geometry::mat3::IDENTITY), |c| {
            (c.origin, c.axes)
        });
        m.bodies.push(Body {
            id: b.id,
            name: b.name.clone(),
            kind: BodyKind::Flexible {
                artifact,
                origin,
                axes,
            },
            loc: b.loc.clone(),
        });
    }
    for b in &bulk.rigidb {
        let c = rectangular(
            coords,
            b.cid,
            (&b.loc, "RIGIDB", b.id, "field 5 (CID)"),
            errors,
        );
        let (centre, inertia) = c.map_or((b.centre, b.inertia), |c| {
            // the system's axes are the rows of c.axes, so components map to basic by its transpose
            let inertia = rotate_tensor(&transpose(&c.axes), &b.inertia);
            (c.point_to_basic(b.centre), inertia)
        });
        m.bodies.push(Body {
            id: b.id,
            name: b.name.clone(),
            kind: BodyKind::Rigid {
                mass: b.mass,
                centre,
                inertia,
            },
            loc: b.loc.clone(),
        });
    }
    for (i, a) in m.bodies.iter().enumerate() {
        if m.bodies[..i]
            .iter()
            .any(|b| b.name.eq_ignore_ascii_case(&a.name))
        {
            errors.push(at(
                &a.loc,
                if matches!(a.kind, BodyKind::Flexible { .. }) {
                    "FLEXB"
                } else {
                    "RIGIDB"
                },
                a.id,
                "field 3 (NAME)",
                format!("body name {} is used twice", a.name),
            ));
        }
    }
    let body_of: HashMap<u32, usize> = m
        .bodies
        .iter()
        .enumerate()
        .map(|(i, b)| (b.id, i))
        .collect();

    index(
        bulk.markers
            .iter()
            .map(|x| entry(x.id, "MARKER", &x.loc, ()))
            .collect(),
        "marker",
        errors,
    );
    for x in &bulk.markers {
        let e = |field: &str, message: String| at(&x.loc, "MARKER", x.id, field, message);
        let body = if x.body == 0 {
            None
        } else if let Some(&b) = body_of.get(&x.body) {
            Some(b)
        } else {
            errors.push(e(
                "field 3 (BODY)",
                format!(
                    "BODY = {} does not exist (no FLEXB or RIGIDB {})",
                    x.body, x.body
                ),
            ));
            continue;
        };
        let flexible = body.is_some_and(|b| matches!(m.bodies[b].kind, BodyKind::Flexible { .. }));
        let place = match (flexible, x.grid) {
            (true, Some(g)) => MarkerPlace::Grid(g),
            (true, None) => {
                errors.push(e(
                    "field 4 (GRID)",
                    format!(
                        "BODY = {} is a flexible body: the marker needs a GRID (an interface grid of its artifact)",
                        x.body
                    ),
                ));
                continue;
            }
            (false, Some(_)) => {
                errors.push(e(
                    "field 4 (GRID)",
                    format!(
                        "BODY = {} is {}: give the point X1 X2 X3, not a GRID",
                        x.body,
                        if body.is_some() {
                            "a rigid body"
                        } else {
                            "the ground"
                        }
                    ),
                ));
                continue;
            }
            (false, None) => {
                let c = rectangular(
                    coords,
                    x.cid,
                    (&x.loc, "MARKER", x.id, "field 8 (CID)"),
                    errors,
                );
                MarkerPlace::Point(c.map_or(x.point, |c| c.point_to_basic(x.point)))
            }
        };
        m.markers.push(Marker {
            id: x.id,
            body,
            place,
            loc: x.loc.clone(),
        });
    }
    let marker_of: HashMap<u32, usize> = m
        .markers
        .iter()
        .enumerate()
        .map(|(i, x)| (x.id, i))
        .collect();
    let marker =
        |id: u32, (loc, card, cid, field): (&Loc, &str, u32, &str), errors: &mut Vec<DeckError>| {
            let found = marker_of.get(&id).copied();
            if found.is_none() && !bulk.markers.iter().any(|x| x.id == id) {
                errors.push(at(
                    loc,
                    card,
                    cid,
                    field,
                    format!(
                        "{} = {id} does not exist (no MARKER {id})",
                        field_name(field)
                    ),
                ));
            }
            found
        };

    index(
        bulk.joints
            .iter()
            .map(|x| entry(x.id, "JOINT", &x.loc, ()))
            .collect(),
        "joint",
        errors,
    );
    for j in &bulk.joints {
        let first = marker(j.first, (&j.loc, "JOINT", j.id, "field 4 (MK1)"), errors);
        let second = match j.second {
            None => Some(None),
            Some(id) => marker(id, (&j.loc, "JOINT", j.id, "field 5 (MK2)"), errors).map(Some),
        };
        let c = rectangular(
            coords,
            j.cid,
            (&j.loc, "JOINT", j.id, "field 9 (CID)"),
            errors,
        );
        let (Some(first), Some(second)) = (first, second) else {
            continue;
        };
        let body2 = second.and_then(|s| m.markers[s].body);
        if m.markers[first].body == body2 {
            errors.push(at(
                &j.loc,
                "JOINT",
                j.id,
                "field 5 (MK2)",
                format!(
                    "MK1 and MK2 are both on {}: a joint connects two different bodies",
                    body2.map_or("the ground".to_string(), |b| format!(
                        "body {}",
                        m.bodies[b].id
                    ))
                ),
            ));
            continue;
        }
        m.joints.push(Joint {
            id: j.id,
            kind: j.kind,
            first,
            second,
            axis: unit_in_basic(c, j.axis),
            loc: j.loc.clone(),
        });
    }
    let joint_of: HashMap<u32, usize> = m
        .joints
        .iter()
        .enumerate()
        .map(|(i, x)| (x.id, i))
        .collect();
    let joint =
        |id: u32, (loc, card, cid, field): (&Loc, &str, u32, &str), errors: &mut Vec<DeckError>| {
            let found = joint_of.get(&id).copied();
            if found.is_none() && !bulk.joints.iter().any(|x| x.id == id) {
                errors.push(at(
                    loc,
                    card,
                    cid,
                    field,
                    format!("JOINT = {id} does not exist (no JOINT {id})"),
                ));
            }
            found
        };
    let drivable =
        |j: usize, (loc, card, cid): (&Loc, &str, u32), what: &str, errors: &mut Vec<DeckError>| {
            let kind = m.joints[j].kind;
            let ok = kind.has_coordinate();
            if !ok {
                errors.push(at(
                    loc,
                    card,
                    cid,
                    "field 3 (JOINT)",
                    format!(
                        "JOINT {} is {}: {what} acts on the coordinate of a REV or PRIS joint only",
                        m.joints[j].id,
                        kind.keyword()
                    ),
                ));
            }
            ok
        };
    let table = |tid: u32,
                 (loc, card, cid, field): (&Loc, &str, u32, &str),
                 errors: &mut Vec<DeckError>| {
        if !bulk.dynamic_tables().any(|(id, _, _)| id == tid) {
            errors.push(at(
                loc,
                card,
                cid,
                field,
                format!("TID = {tid} does not exist (no TABLED1–TABLED4 or TABLEF {tid})"),
            ));
        }
    };

    index(
        bulk.jdrive
            .iter()
            .map(|x| entry(x.id, "JDRIVE", &x.loc, ()))
            .collect(),
        "drive",
        errors,
    );
    for d in &bulk.jdrive {
        table(d.tid, (&d.loc, "JDRIVE", d.id, "field 4 (TID)"), errors);
        let Some(j) = joint(d.joint, (&d.loc, "JDRIVE", d.id, "field 3 (JOINT)"), errors) else {
            continue;
        };
        if !drivable(j, (&d.loc, "JDRIVE", d.id), "a drive", errors) {
            continue;
        }
        if let Some(other) = m.drives.iter().find(|o| o.joint == j) {
            errors.push(at(
                &d.loc,
                "JDRIVE",
                d.id,
                "field 3 (JOINT)",
                format!("JOINT {} is already driven by JDRIVE {}", d.joint, other.id),
            ));
            continue;
        }
        m.drives.push(Drive {
            id: d.id,
            joint: j,
            table: d.tid,
            scale: d.scale,
            compliance: d.compliance,
            loc: d.loc.clone(),
        });
    }
    for s in &bulk.jsprd {
        let Some(j) = joint(s.joint, (&s.loc, "JSPRD", s.id, "field 3 (JOINT)"), errors) else {
            continue;
        };
        if drivable(j, (&s.loc, "JSPRD", s.id), "a joint spring-damper", errors) {
            m.joint_springs.push(JointSpring {
                id: s.id,
                joint: j,
                stiffness: s.stiffness,
                damping: s.damping,
                rest: s.rest,
                loc: s.loc.clone(),
            });
        }
    }
    for s in &bulk.spdmp {
        let first = marker(s.first, (&s.loc, "SPDMP", s.id, "field 3 (MK1)"), errors);
        let second = marker(s.second, (&s.loc, "SPDMP", s.id, "field 4 (MK2)"), errors);
        if let (Some(first), Some(second)) = (first, second) {
            m.point_springs.push(PointSpring {
                id: s.id,
                first,
                second,
                stiffness: s.stiffness,
                damping: s.damping,
                length: s.length,
                loc: s.loc.clone(),
            });
        }
    }
    index(
        bulk.mforce
            .iter()
            .map(|x| entry(x.id, load_card(x.kind), &x.loc, ()))
            .collect(),
        "marker load (MFORCE, MMOMENT)",
        errors,
    );
    for f in &bulk.mforce {
        let card = load_card(f.kind);
        table(f.tid, (&f.loc, card, f.id, "field 4 (TID)"), errors);
        let c = rectangular(coords, f.cid, (&f.loc, card, f.id, "field 9 (CID)"), errors);
        let Some(mk) = marker(f.marker, (&f.loc, card, f.id, "field 3 (MK)"), errors) else {
            continue;
        };
        if m.markers[mk].body.is_none() {
            errors.push(at(
                &f.loc,
                card,
                f.id,
                "field 3 (MK)",
                format!(
                    "MK = {} is on the ground, which nothing can move: put the marker on a body",
                    f.marker
                ),
            ));
            continue;
        }
        m.forces.push(PointForce {
            id: f.id,
            kind: f.kind,
            marker: mk,
            table: f.tid,
            scale: f.scale,
            direction: unit_in_basic(c, f.direction),
            loc: f.loc.clone(),
        });
    }

    index(
        bulk.msensors
            .iter()
            .map(|x| entry(x.id, "MSENSOR", &x.loc, ()))
            .collect(),
        "MSENSOR",
        errors,
    );
    for s in &bulk.msensors {
        let e = |field: &str, message: String| at(&s.loc, "MSENSOR", s.id, field, message);
        if bulk
            .msensors
            .iter()
            .take_while(|o| !std::ptr::eq(*o, s))
            .any(|o| o.name == s.name)
        {
            errors.push(e(
                "field 3 (NAME)",
                format!("MSENSOR name {} is used twice", s.name),
            ));
        }
        let reference = s.reference.unwrap_or(0);
        let target = match s.kind {
            MsensorKind::Pos | MsensorKind::Accel => marker(
                reference,
                (&s.loc, "MSENSOR", s.id, "field 6 (REF)"),
                errors,
            )
            .map(SensorTarget::Marker),
            MsensorKind::Jforce | MsensorKind::Jtorq => {
                let j = joint_of.get(&reference).copied();
                if j.is_none() {
                    errors.push(e(
                        "field 6 (REF)",
                        format!("REF = {reference} does not exist (no JOINT {reference})"),
                    ));
                }
                if let Some(kind) = j.map(|j| m.joints[j].kind)
                    && s.kind == MsensorKind::Jforce
                    && !kind.makes_points_coincide()
                {
                    errors.push(e(
                        "field 6 (REF)",
                        format!(
                            "JOINT {reference} is {}: JFORCE reads the reaction force of joints that make two points coincide (REV, FIX, SPH, UNIV)",
                            kind.keyword()
                        ),
                    ));
                }
                if s.kind == MsensorKind::Jtorq
                    && j.is_some_and(|j| !m.drives.iter().any(|d| d.joint == j))
                {
                    errors.push(e(
                        "field 6 (REF)",
                        format!("JOINT {reference} has no JDRIVE: JTORQ is the torque (force) of a joint's drive"),
                    ));
                }
                j.map(SensorTarget::Joint)
            }
            // REF blank: every drive, the total of eq. 6.1 f₂
            MsensorKind::Power | MsensorKind::Energy if s.reference.is_none() => {
                Some(SensorTarget::System)
            }
            MsensorKind::Power | MsensorKind::Energy => {
                let d = m.drives.iter().position(|d| d.id == reference);
                if d.is_none() {
                    errors.push(e(
                        "field 6 (REF)",
                        format!("REF = {reference} does not exist (no JDRIVE {reference})"),
                    ));
                }
                d.map(SensorTarget::Drive)
            }
            MsensorKind::Ke => Some(SensorTarget::System),
            MsensorKind::Strain => {
                let body = m.bodies.iter().position(|b| b.id == s.body);
                let flexible =
                    body.filter(|&b| matches!(m.bodies[b].kind, BodyKind::Flexible { .. }));
                if flexible.is_none() && s.body != 0 {
                    errors.push(e(
                        "field 5 (BODY)",
                        format!(
                            "BODY = {} is no FLEXB: a STRAIN output reads a flexible body's artifact",
                            s.body
                        ),
                    ));
                }
                flexible
                    .zip(s.strain_sensor.clone())
                    .map(|(body, sensor)| SensorTarget::Strain { body, sensor })
            }
            MsensorKind::Dev => {
                if !m
                    .bodies
                    .iter()
                    .any(|b| matches!(b.kind, BodyKind::Flexible { .. }))
                {
                    errors.push(e(
                        "field 4 (KIND)",
                        "DEV is a marker's distance from the rigid twin of the mechanism's flexible bodies, and this mechanism has none (only RIGIDB bodies): it would be 0; use POS".into(),
                    ));
                }
                marker(
                    reference,
                    (&s.loc, "MSENSOR", s.id, "field 6 (REF)"),
                    errors,
                )
                .map(SensorTarget::Marker)
            }
        };
        if let Some(target) = target {
            m.sensors.push(Sensor {
                id: s.id,
                name: s.name.clone(),
                kind: s.kind,
                target,
                direction: normalize(s.direction).unwrap_or([0.0; 3]),
                loc: s.loc.clone(),
            });
        }
    }
    if !m.is_empty() {
        for p in &bulk.pval {
            for (pair, (name, _)) in p.values.iter().enumerate() {
                let body = name.split_once('.').map(|(b, _)| b);
                let flexible = body
                    .and_then(|b| m.body_named(b))
                    .is_some_and(|b| matches!(m.bodies[b].kind, BodyKind::Flexible { .. }));
                if !flexible {
                    errors.push(at(
                        &p.loc,
                        "PVAL",
                        p.id,
                        &format!("field {} (NAME)", 3 + 2 * pair),
                        format!(
                            "{name} is not BODY.PMPAR with BODY a FLEXB name (flexible bodies: {})",
                            m.bodies
                                .iter()
                                .filter(|b| matches!(b.kind, BodyKind::Flexible { .. }))
                                .map(|b| b.name.as_str())
                                .collect::<Vec<_>>()
                                .join(", ")
                        ),
                    ));
                }
            }
        }
    }
    pose_grids(bulk, &m, errors);
    m
}

/// The FMBPOSE checks: unique ids and, for a deck with its own mechanism, every axis on one
/// of its JDRIVEs (a deck loading a mechanism with `FMB =` has its axes checked against the
/// loaded drives when it runs).
fn pose_grids(bulk: &BulkData, m: &Mechanism, errors: &mut Vec<DeckError>) {
    index(
        bulk.fmbpose
            .iter()
            .map(|x| entry(x.id, "FMBPOSE", &x.loc, ()))
            .collect(),
        "pose grid",
        errors,
    );
    if m.is_empty() {
        return;
    }
    for p in &bulk.fmbpose {
        for axis in p.axes.iter().filter(|a| a.drive > 0) {
            if !m.drives.iter().any(|d| d.id == axis.drive) {
                errors.push(at(
                    &axis.loc,
                    "FMBPOSE",
                    p.id,
                    &format!("{} (JDRIVE)", axis.field),
                    format!(
                        "JDRIVE = {} does not exist (drives: {})",
                        axis.drive,
                        drive_list(m)
                    ),
                ));
            }
        }
    }
}

/// The JDRIVE ids of a mechanism, for messages.
pub fn drive_list(m: &Mechanism) -> String {
    if m.drives.is_empty() {
        return "none".to_string();
    }
    m.drives
        .iter()
        .map(|d| d.id.to_string())
        .collect::<Vec<_>>()
        .join(" ")
}

/// "MK1" from "field 4 (MK1)".
fn field_name(field: &str) -> &str {
    field
        .split_once('(')
        .and_then(|(_, r)| r.strip_suffix(')'))
        .unwrap_or(field)
}

impl super::Model {
    /// The FMBPOSE of `POSES = id`.
    pub fn fmbpose(&self, id: u32) -> Option<&crate::deck::cards::Fmbpose> {
        self.bulk.fmbpose.iter().find(|p| p.id == id)
    }

    /// Whether static load set `sid` has a GRAV or a LOAD card.
    pub fn has_load_set(&self, sid: u32) -> bool {
        self.bulk.grav.iter().any(|g| g.sid == sid) || self.bulk.load.iter().any(|l| l.sid == sid)
    }

    /// The gravity acceleration in basic of static load set `sid`: its GRAV cards, directly or
    /// through a LOAD combination (zero when the set has none).
    pub fn gravity(&self, sid: u32) -> [f64; 3] {
        let b = &self.bulk;
        let of_set = |set: u32, scale: f64, g: &mut [f64; 3]| {
            for grav in b.grav.iter().filter(|x| x.sid == set) {
                let c = self.coords.get(&grav.cid);
                let d = c.map_or(grav.direction, |c| c.vector_to_basic(grav.direction));
                for (gi, di) in g.iter_mut().zip(d) {
                    *gi += scale * grav.a * di;
                }
            }
        };
        let mut g = [0.0; 3];
        of_set(sid, 1.0, &mut g);
        for load in b.load.iter().filter(|l| l.sid == sid) {
            for &(s, set) in &load.terms {
                of_set(set, load.scale * s, &mut g);
            }
        }
        g
    }
}
