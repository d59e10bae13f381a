//! Static loads: `FORCE`, `MOMENT`, `FORCE1`, `FORCE2`, `MOMENT1`, `MOMENT2`, `SLOAD`, `GRAV`,
//! `LOAD`, pressures `PLOAD4`, `PLOAD2`, `PLOAD`, and loads along beams `PLOAD1`.

use crate::card_values::ForceKind;
use crate::deck::error::{DeckError, Loc};
use crate::deck::fields::RawCard;
use crate::deck::reader::FieldReader;
use crate::deck::value::Value;

/// `FORCE` / `MOMENT` — concentrated load at a grid: F · (N1, N2, N3) in system CID.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | SID | int > 0 | required | load set id |
/// | 3 | G | int > 0 | required | grid |
/// | 4 | CID | int ≥ 0 | 0 | system of the direction |
/// | 5 | F / M | real | 0.0 | scale factor |
/// | 6–8 | N1 N2 N3 | real | 0.0 | direction (need not be unit) |
#[derive(Debug, Clone, PartialEq)]
pub struct Force {
    pub kind: ForceKind,
    pub sid: u32,
    pub grid: u32,
    pub cid: u32,
    pub scale: f64,
    pub direction: [f64; 3],
    pub loc: Loc,
}

impl Force {
    /// Read a `FORCE` or `MOMENT` card.
    pub fn from_card(card: &RawCard, kind: ForceKind) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let sid = f.id(1, "SID");
        f.set_id(sid);
        let grid = f.id(2, "G");
        let cid = f.id0_or(3, "CID", 0);
        let scale = f.real_or(4, if kind == ForceKind::Force { "F" } else { "M" }, 0.0);
        let direction = [
            f.real_or(5, "N1", 0.0),
            f.real_or(6, "N2", 0.0),
            f.real_or(7, "N3", 0.0),
        ];
        let loc = f.loc();
        f.finish(7)?;
        Ok(Force {
            kind,
            sid,
            grid,
            cid,
            scale,
            direction,
            loc,
        })
    }
}

/// `FORCE1` / `MOMENT1` / `FORCE2` / `MOMENT2` — a force or moment of magnitude F at a grid,
/// its direction given by grids: from G1 to G2 (FORCE1, MOMENT1), or the cross product
/// (G2 − G1) × (G4 − G3) (FORCE2, MOMENT2), both normalized, from the grids' basic positions.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | SID | int > 0 | required | load set id |
/// | 3 | G | int > 0 | required | loaded grid |
/// | 4 | F / M | real | required | magnitude |
/// | 5, 6 | G1 G2 | int > 0 | required | the direction's grids (G1 ≠ G2) |
/// | 7, 8 | G3 G4 | int > 0 | required (FORCE2, MOMENT2) | the second vector's grids |
///
/// A direction of zero length (coincident grids, parallel vectors) is an error at the card.
#[derive(Debug, Clone, PartialEq)]
pub struct ForceByGrids {
    pub kind: ForceKind,
    pub sid: u32,
    pub grid: u32,
    pub magnitude: f64,
    /// G1 G2 (FORCE1, MOMENT1) or G1 G2 G3 G4 (FORCE2, MOMENT2).
    pub grids: Vec<u32>,
    pub loc: Loc,
}

impl ForceByGrids {
    /// Read a FORCE1/MOMENT1 (`cross` false) or FORCE2/MOMENT2 (`cross` true) card.
    pub fn from_card(card: &RawCard, kind: ForceKind, cross: bool) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let sid = f.id(1, "SID");
        f.set_id(sid);
        let grid = f.id(2, "G");
        let magnitude = f.real(3, if kind == ForceKind::Force { "F" } else { "M" });
        let names: &[&str] = if cross {
            &["G1", "G2", "G3", "G4"]
        } else {
            &["G1", "G2"]
        };
        let grids: Vec<u32> = (names.iter().enumerate())
            .map(|(k, n)| f.id(4 + k, n))
            .collect();
        if grids[0] == grids[1] {
            f.error(
                5,
                "G2",
                "G1 and G2 are the same grid: the direction has no length",
            );
        }
        if cross && grids[2] == grids[3] {
            f.error(
                7,
                "G4",
                "G3 and G4 are the same grid: the direction has no length",
            );
        }
        let loc = f.loc();
        f.finish(3 + names.len())?;
        Ok(ForceByGrids {
            kind,
            sid,
            grid,
            magnitude,
            grids,
            loc,
        })
    }

    /// The card name.
    pub fn card(&self) -> &'static str {
        match (self.kind, self.grids.len()) {
            (ForceKind::Force, 2) => "FORCE1",
            (ForceKind::Moment, 2) => "MOMENT1",
            (ForceKind::Force, _) => "FORCE2",
            (ForceKind::Moment, _) => "MOMENT2",
        }
    }
}

/// `SLOAD` — loads on scalar points or grids (up to three per card).
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | SID | int > 0 | required | load set id |
/// | 3, 4 | S1 F1 | int > 0, real | required | scalar point (SPOINT) or grid (its component T1 in its CD system, as Nastran) and its load |
/// | 5–8 | S2 F2 S3 F3 | | blank | two more pairs |
#[derive(Debug, Clone, PartialEq)]
pub struct Sload {
    pub sid: u32,
    /// (scalar point id, load).
    pub loads: Vec<(u32, f64)>,
    pub loc: Loc,
}

impl Sload {
    /// Read an `SLOAD` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let sid = f.id(1, "SID");
        f.set_id(sid);
        let mut loads = Vec::new();
        for (k, i) in [2, 4, 6].into_iter().enumerate() {
            if k > 0 && f.value(i).is_blank() && f.value(i + 1).is_blank() {
                continue;
            }
            let point = f.id(i, &format!("S{}", k + 1));
            loads.push((point, f.real(i + 1, &format!("F{}", k + 1))));
        }
        let loc = f.loc();
        f.finish(7)?;
        Ok(Sload { sid, loads, loc })
    }
}

/// `GRAV` — acceleration load: A · (N1, N2, N3) in system CID.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | SID | int > 0 | required | load set id |
/// | 3 | CID | int ≥ 0 | 0 | system of the direction |
/// | 4 | A | real | required | acceleration magnitude |
/// | 5–7 | N1 N2 N3 | real | 0.0 | direction (not all zero) |
/// | 8 | MB | int | 0 | 0 = CID in the basic system (only 0 supported) |
#[derive(Debug, Clone, PartialEq)]
pub struct Grav {
    pub sid: u32,
    pub cid: u32,
    pub a: f64,
    pub direction: [f64; 3],
    pub loc: Loc,
}

impl Grav {
    /// Read a `GRAV` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let sid = f.id(1, "SID");
        f.set_id(sid);
        let cid = f.id0_or(2, "CID", 0);
        let a = f.real(3, "A");
        let direction = [
            f.real_or(4, "N1", 0.0),
            f.real_or(5, "N2", 0.0),
            f.real_or(6, "N3", 0.0),
        ];
        if direction == [0.0; 3] {
            f.error(4, "N1", "the direction vector is zero");
        }
        let mb = f.int_or(7, "MB", 0);
        if mb != 0 {
            f.error(7, "MB", "only MB = 0 (main bulk data) is supported");
        }
        let loc = f.loc();
        f.finish(7)?;
        Ok(Grav {
            sid,
            cid,
            a,
            direction,
            loc,
        })
    }
}

/// A combination card read by [`combination`]: set id, overall scale, (scale, set id) terms and
/// the card's location.
pub(crate) type Combination = (u32, f64, Vec<(f64, u32)>, Loc);

/// Read `SID S S1 L1 S2 L2 …` combination cards (`LOAD`, `DLOAD`).
pub(crate) fn combination(card: &RawCard) -> Result<Combination, Vec<DeckError>> {
    let mut f = FieldReader::new(card);
    let sid = f.id(1, "SID");
    f.set_id(sid);
    let scale = f.real(2, "S");
    let mut terms = Vec::new();
    let len = f.len();
    let mut i = 3;
    while i <= len {
        if f.value(i).is_blank() && f.value(i + 1).is_blank() {
            i += 2;
            continue;
        }
        let k = terms.len() + 1;
        let s = f.real(i, &format!("S{k}"));
        let l = f.id(i + 1, &format!("L{k}"));
        terms.push((s, l));
        i += 2;
    }
    if terms.is_empty() {
        f.card_error("no (Si, Li) pair given");
    }
    let loc = f.loc();
    f.finish(len.max(2))?;
    Ok((sid, scale, terms, loc))
}

/// `LOAD` — linear combination of static load sets: S · Σ Si · (set Li).
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | SID | int > 0 | required | new load set id |
/// | 3 | S | real | required | overall scale |
/// | 4, 5, … | S1 L1 S2 L2 … | real, int > 0 | ≥ 1 pair | scale and FORCE/MOMENT/FORCE1/FORCE2/MOMENT1/MOMENT2/SLOAD/GRAV/PLOAD4/PLOAD2/PLOAD/PLOAD1/SPCD set id |
#[derive(Debug, Clone, PartialEq)]
pub struct Load {
    pub sid: u32,
    pub scale: f64,
    pub terms: Vec<(f64, u32)>,
    pub loc: Loc,
}

impl Load {
    /// Read a `LOAD` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let (sid, scale, terms, loc) = combination(card)?;
        Ok(Load {
            sid,
            scale,
            terms,
            loc,
        })
    }
}

/// Where a `PLOAD4` acts: one element's face, or every shell element of an id range.
#[derive(Debug, Clone, PartialEq)]
pub enum Pload4Target {
    /// One element; for a solid, the face through G1 and G3 (CHEXA, CPENTA quadrilateral
    /// faces: diagonally opposite corners), through G1 alone (CPENTA triangular faces) or
    /// opposite G4 (CTETRA).
    Element {
        eid: u32,
        g1: Option<u32>,
        g34: Option<u32>,
    },
    /// `EID1 THRU EID2`: every CQUAD4 / CTRIA3 with an id in the range (other ids are skipped).
    Range { first: u32, last: u32 },
}

/// `PLOAD4` — pressure on a face of a shell or solid element.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | SID | int > 0 | required | load set id |
/// | 3 | EID | int > 0 | required | element (EID1 of a THRU range) |
/// | 4 | P1 | real | required | pressure at the face's first corner |
/// | 5–7 | P2 P3 P4 | real | P1 | pressures at the other corners (P4 unused on a triangle) |
/// | 8 | G1 or THRU | int > 0 or `THRU` | blank | solids: a corner grid of the face; `THRU`: shells EID … EID2 |
/// | 9 | G3/G4 or EID2 | int > 0 | blank | CHEXA, CPENTA quadrilateral face: the corner diagonally opposite G1; CTETRA: the corner not on the face; after THRU: EID2 |
/// | cont. 2 | CID | int ≥ 0 | blank | system of N (rectangular) |
/// | cont. 3–5 | N1 N2 N3 | real | blank | direction of the load; blank: normal to the face |
///
/// Shells: positive pressure acts along the normal of G1 → G2 → G3 (right-hand rule), P1…P4 at
/// G1…G4. Solids: positive pressure pushes into the element; P1 is at G1 and P2, P3, P4 follow
/// around the face counter-clockwise seen from inside the element. With N the load per area is
/// |p| along N (the pressure's sign kept) instead of along the normal. The consistent nodal forces
/// ∫ N_i p dA are used (bilinear, linear or, on a 10-node CTETRA's face, quadratic shape
/// functions). Line loads (cont. 6–7, SORL LDIR) are not supported.
#[derive(Debug, Clone, PartialEq)]
pub struct Pload4 {
    pub sid: u32,
    pub target: Pload4Target,
    pub pressures: [f64; 4],
    /// The load direction (CID, N) when given.
    pub direction: Option<(u32, [f64; 3])>,
    pub loc: Loc,
}

impl Pload4 {
    /// Read a `PLOAD4` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let sid = f.id(1, "SID");
        f.set_id(sid);
        let eid = f.id(2, "EID");
        let p1 = f.real(3, "P1");
        let pressures = [
            p1,
            f.real_or(4, "P2", p1),
            f.real_or(5, "P3", p1),
            f.real_or(6, "P4", p1),
        ];
        let thru = matches!(f.value(7), Value::Text(t) if t.eq_ignore_ascii_case("THRU"));
        let target = if thru {
            let last = f.id(8, "EID2");
            if last < eid {
                f.error(8, "EID2", format!("EID2 = {last} is below EID1 = {eid}"));
            }
            Pload4Target::Range { first: eid, last }
        } else {
            Pload4Target::Element {
                eid,
                g1: f.opt_id(7, "G1"),
                g34: f.opt_id(8, "G3/G4"),
            }
        };
        let n = [
            f.opt_real(10, "N1"),
            f.opt_real(11, "N2"),
            f.opt_real(12, "N3"),
        ];
        let cid = f.id0_or(9, "CID", 0);
        let direction = if n.iter().all(Option::is_none) {
            None
        } else {
            let n = n.map(|v| v.unwrap_or(0.0));
            if n == [0.0; 3] {
                f.error(10, "N1", "the direction vector is zero");
            }
            Some((cid, n))
        };
        for (i, name) in [(13, "SORL"), (14, "LDIR")] {
            if !f.value(i).is_blank() {
                f.error(
                    i,
                    name,
                    "line loads on element edges are not supported (leave SORL and LDIR blank)",
                );
            }
        }
        let loc = f.loc();
        f.finish(14)?;
        Ok(Pload4 {
            sid,
            target,
            pressures,
            direction,
            loc,
        })
    }
}

/// `PLOAD2` — uniform pressure on shell elements (CQUAD4, CTRIA3).
///
/// Positive along each element's normal of G1 → G2 → G3.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | SID | int > 0 | required | load set id |
/// | 3 | P | real | required | pressure |
/// | 4–9 | EID1 … | int > 0 or `THRU` | ≥ 1 | elements, or `EID1 THRU EID2` (ids in the range that are not shells are skipped) |
#[derive(Debug, Clone, PartialEq)]
pub struct Pload2 {
    pub sid: u32,
    pub pressure: f64,
    /// Listed element ids, and the `THRU` range when given.
    pub elements: Vec<u32>,
    pub range: Option<(u32, u32)>,
    pub loc: Loc,
}

impl Pload2 {
    /// Read a `PLOAD2` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let sid = f.id(1, "SID");
        f.set_id(sid);
        let pressure = f.real(2, "P");
        let thru = matches!(f.value(4), Value::Text(t) if t.eq_ignore_ascii_case("THRU"));
        let (elements, range) = if thru {
            let (first, last) = (f.id(3, "EID1"), f.id(5, "EID2"));
            if last < first {
                f.error(5, "EID2", format!("EID2 = {last} is below EID1 = {first}"));
            }
            (Vec::new(), Some((first, last)))
        } else {
            let ids: Vec<u32> = (3..=8).filter_map(|i| f.opt_id(i, "EID")).collect();
            if ids.is_empty() {
                f.error(3, "EID1", "expected at least one element id");
            }
            (ids, None)
        };
        let loc = f.loc();
        f.finish(8)?;
        Ok(Pload2 {
            sid,
            pressure,
            elements,
            range,
            loc,
        })
    }
}

/// `PLOAD` — pressure on the triangle or quadrilateral through three or four grids.
///
/// Positive along the normal of G1 → G2 → G3; the consistent nodal forces of a linear triangle
/// (a third of p·A each when flat) or a bilinear quadrilateral (Nastran splits a quadrilateral's
/// load by sub-triangles: the same for a parallelogram, slightly different otherwise).
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | SID | int > 0 | required | load set id |
/// | 3 | P | real | required | pressure |
/// | 4–7 | G1 … G4 | int > 0 | G4 blank or 0: triangle | corners, in order around the face |
#[derive(Debug, Clone, PartialEq)]
pub struct Pload {
    pub sid: u32,
    pub pressure: f64,
    pub grids: Vec<u32>,
    pub loc: Loc,
}

impl Pload {
    /// Read a `PLOAD` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let sid = f.id(1, "SID");
        f.set_id(sid);
        let pressure = f.real(2, "P");
        let mut grids = vec![f.id(3, "G1"), f.id(4, "G2"), f.id(5, "G3")];
        if let g4 @ 1.. = f.id0_or(6, "G4", 0) {
            grids.push(g4);
        }
        let loc = f.loc();
        f.finish(6)?;
        Ok(Pload {
            sid,
            pressure,
            grids,
            loc,
        })
    }
}

/// How `PLOAD1` positions and intensities are measured.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Pload1Scale {
    /// Positions as lengths from end A; intensities per unit length.
    Length,
    /// Positions as fractions of the length.
    Fraction,
    /// As `Length`, intensities per unit projected length.
    LengthProjected,
    /// As `Fraction`, intensities per unit projected length.
    FractionProjected,
}

impl Pload1Scale {
    /// Positions are fractions of the element length.
    pub fn fractional(self) -> bool {
        matches!(self, Pload1Scale::Fraction | Pload1Scale::FractionProjected)
    }

    /// Intensities are per unit of projected length.
    pub fn projected(self) -> bool {
        matches!(
            self,
            Pload1Scale::LengthProjected | Pload1Scale::FractionProjected
        )
    }
}

/// `PLOAD1` — a concentrated or linearly distributed force or moment on a CBAR, CBEAM or CBEND.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | SID | int > 0 | required | load set id |
/// | 3 | EID | int > 0 | required | CBAR, CBEAM or CBEND id (on a CBEND: positions and intensities along the arc, basic TYPEs only, no PR scales) |
/// | 4 | TYPE | FX FY FZ MX MY MZ (basic), FXE … MZE (element axes) | required | force or moment and its direction |
/// | 5 | SCALE | LE FR LEPR FRPR | required | positions as lengths (LE) or fractions (FR) of the axis from end A; PR: intensities per unit length projected on a plane normal to the load (for an element TYPE the plane normal to that element axis: FXE/MXE projected loads are zero, FYE … MZE are not reduced) |
/// | 6 | X1 | real ≥ 0 | required | first position |
/// | 7 | P1 | real | required | value at X1 |
/// | 8 | X2 | real ≥ X1 | X1 | second position; X2 = X1: P1 is a concentrated load |
/// | 9 | P2 | real | 0.0 | intensity at X2 (linear in between; blank is 0.0, as MSC Nastran computes it) |
#[derive(Debug, Clone, PartialEq)]
pub struct Pload1 {
    pub sid: u32,
    pub eid: u32,
    pub kind: ForceKind,
    /// Direction axis 0, 1, 2 (x, y, z).
    pub axis: usize,
    /// The direction is along the element's axes (TYPE ending in E), else basic.
    pub element_axes: bool,
    pub scale: Pload1Scale,
    pub x: [f64; 2],
    pub p: [f64; 2],
    pub loc: Loc,
}

impl Pload1 {
    /// Read a `PLOAD1` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        const TYPES: [&str; 12] = [
            "FX", "FY", "FZ", "MX", "MY", "MZ", "FXE", "FYE", "FZE", "MXE", "MYE", "MZE",
        ];
        let mut f = FieldReader::new(card);
        let sid = f.id(1, "SID");
        f.set_id(sid);
        let eid = f.id(2, "EID");
        let kind = f.keyword(3, "TYPE", &TYPES, None);
        let t = TYPES.iter().position(|&n| n == kind).unwrap_or(0);
        let scale = f.choice(
            4,
            "SCALE",
            &[
                ("LE", Pload1Scale::Length),
                ("FR", Pload1Scale::Fraction),
                ("LEPR", Pload1Scale::LengthProjected),
                ("FRPR", Pload1Scale::FractionProjected),
            ],
            None,
        );
        let x1 = f.real(5, "X1");
        let p1 = f.real(6, "P1");
        let x2 = f.real_or(7, "X2", x1);
        let p2 = f.real_or(8, "P2", 0.0);
        let element_axes = t >= 6;
        if x1 < 0.0 {
            f.error(
                5,
                "X1",
                format!("X1 = {x1} is negative: positions start at end A"),
            );
        }
        if x2 < x1 {
            f.error(7, "X2", format!("X2 = {x2} is below X1 = {x1}"));
        }
        if scale.fractional() && x2 > 1.0 {
            f.error(
                7,
                "X2",
                format!("X2 = {x2} exceeds 1 (SCALE = FR/FRPR: fractions of the length)"),
            );
        }
        let loc = f.loc();
        f.finish(8)?;
        Ok(Pload1 {
            sid,
            eid,
            kind: if t % 6 < 3 {
                ForceKind::Force
            } else {
                ForceKind::Moment
            },
            axis: t % 3,
            element_axes,
            scale,
            x: [x1, x2],
            p: [p1, p2],
            loc,
        })
    }
}
