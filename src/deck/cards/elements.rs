//! Elements: shells `CQUAD4`, `CTRIA3` (and `CQUADR`, `CTRIAR` in their layouts), `CQUAD8`, `CTRIA6`; solids `CHEXA`, `CPENTA`, `CTETRA`, `CPYRAM`; scalar springs
//! `CELAS1`–`CELAS4` and dampers `CDAMP1`–`CDAMP4`; the viscous damper `CVISC`; the bush
//! `CBUSH`; concentrated mass `CONM2`; scalar points `SPOINT`.

use crate::card_values::{CornerThickness, ShellOrientation, SpringEnd};
use crate::deck::error::{DeckError, Loc};
use crate::deck::fields::RawCard;
use crate::deck::reader::FieldReader;
use crate::deck::value::Value;

fn orientation(f: &mut FieldReader, i: usize) -> ShellOrientation {
    match f.value(i) {
        Value::Int(_) => ShellOrientation::Mcid(f.id0_or(i, "MCID", 0)),
        _ => ShellOrientation::Theta(f.real_or(i, "THETA", 0.0)),
    }
}

/// Read corner thicknesses: TFLAG at field `tflag`, the corner values T1, T2, … at the fields
/// `fields`. Returns `None` when all are blank.
fn corner_thickness(
    f: &mut FieldReader,
    tflag: usize,
    fields: &[usize],
) -> Option<CornerThickness> {
    if f.value(tflag).is_blank() && fields.iter().all(|&i| f.value(i).is_blank()) {
        return None;
    }
    let relative = match f.int_or(tflag, "TFLAG", 0) {
        0 => false,
        1 => true,
        other => {
            f.error(tflag, "TFLAG", format!("expected 0 or 1, found {other}"));
            false
        }
    };
    let mut t = [None; 4];
    for (k, (slot, &i)) in t.iter_mut().zip(fields).enumerate() {
        *slot = f.opt_real(i, &format!("T{}", k + 1));
        if let Some(v) = *slot
            && v <= 0.0
        {
            f.error(
                i,
                &format!("T{}", k + 1),
                format!("expected a thickness > 0, found {v:e}"),
            );
        }
    }
    Some(CornerThickness { relative, t })
}

/// `CQUAD4` / `CQUADR` — four-node shell.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | EID | int > 0 | required | element id |
/// | 3 | PID | int > 0 | EID | PSHELL or PCOMP id |
/// | 4–7 | G1–G4 | int > 0 | required | grids, in order around the element |
/// | 8 | THETA/MCID | real or int | 0.0 | material orientation angle (deg) or system id |
/// | 9 | ZOFFS | real | 0.0 | offset of the reference plane from the grids |
/// | cont. 3 | TFLAG | 0 or 1 | 0 | 1: T1–T4 are ratios of the property thickness |
/// | cont. 4–7 | T1–T4 | real > 0 | property T | corner thicknesses (bilinear over the element) |
///
/// A CQUADR is read and computed as a CQUAD4 (docs/departures.md).
#[derive(Debug, Clone, PartialEq)]
pub struct Cquad4 {
    pub id: u32,
    pub pid: u32,
    pub nodes: [u32; 4],
    pub orientation: ShellOrientation,
    pub zoffs: f64,
    pub corner_thickness: Option<CornerThickness>,
    pub loc: Loc,
}

impl Cquad4 {
    /// Read a `CQUAD4` or `CQUADR` card (same layout).
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let id = f.id(1, "EID");
        f.set_id(id);
        let pid = f.opt_id(2, "PID").unwrap_or(id);
        let nodes = [f.id(3, "G1"), f.id(4, "G2"), f.id(5, "G3"), f.id(6, "G4")];
        let orientation = orientation(&mut f, 7);
        let zoffs = f.real_or(8, "ZOFFS", 0.0);
        let corner_thickness = corner_thickness(&mut f, 10, &[11, 12, 13, 14]);
        let loc = f.loc();
        f.finish(14)?;
        Ok(Cquad4 {
            id,
            pid,
            nodes,
            orientation,
            zoffs,
            corner_thickness,
            loc,
        })
    }
}

/// `CTRIA3` / `CTRIAR` — three-node shell.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | EID | int > 0 | required | element id |
/// | 3 | PID | int > 0 | EID | PSHELL or PCOMP id |
/// | 4–6 | G1–G3 | int > 0 | required | grids |
/// | 7 | THETA/MCID | real or int | 0.0 | material orientation angle (deg) or system id |
/// | 8 | ZOFFS | real | 0.0 | offset of the reference plane from the grids |
/// | cont. 3 | TFLAG | 0 or 1 | 0 | 1: T1–T3 are ratios of the property thickness |
/// | cont. 4–6 | T1–T3 | real > 0 | property T | corner thicknesses (linear over the element) |
///
/// A CTRIAR is read and computed as a CTRIA3 (docs/departures.md).
#[derive(Debug, Clone, PartialEq)]
pub struct Ctria3 {
    pub id: u32,
    pub pid: u32,
    pub nodes: [u32; 3],
    pub orientation: ShellOrientation,
    pub zoffs: f64,
    pub corner_thickness: Option<CornerThickness>,
    pub loc: Loc,
}

impl Ctria3 {
    /// Read a `CTRIA3` or `CTRIAR` card (same layout).
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let id = f.id(1, "EID");
        f.set_id(id);
        let pid = f.opt_id(2, "PID").unwrap_or(id);
        let nodes = [f.id(3, "G1"), f.id(4, "G2"), f.id(5, "G3")];
        let orientation = orientation(&mut f, 6);
        let zoffs = f.real_or(7, "ZOFFS", 0.0);
        let corner_thickness = corner_thickness(&mut f, 10, &[11, 12, 13]);
        let loc = f.loc();
        f.finish(13)?;
        Ok(Ctria3 {
            id,
            pid,
            nodes,
            orientation,
            zoffs,
            corner_thickness,
            loc,
        })
    }
}

/// `CQUAD8` / `CTRIA6` — eight- and six-node curved shells (`fe::shell_quadratic`).
///
/// CQUAD8:
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | EID | int > 0 | required | element id |
/// | 3 | PID | int > 0 | EID | PSHELL or PCOMP id |
/// | 4–7 | G1–G4 | int > 0 | required | corner grids, in order around the element |
/// | 8–9, cont. 2–3 | G5–G8 | int ≥ 0 | blank | mid-side grids of edges 1-2, 2-3, 3-4, 4-1; blank or 0: that edge is straight and the displacement along it linear |
/// | cont. 4–7 | T1–T4 | real > 0 | property T | corner thicknesses (bilinear over the element) |
/// | cont. 8 | THETA/MCID | real or int | 0.0 | material orientation angle (deg) or system id |
/// | cont. 9 | ZOFFS | real | 0.0 | offset of the reference surface from the grids |
/// | 2nd cont. 2 | TFLAG | 0 or 1 | 0 | 1: T1–T4 are ratios of the property thickness |
///
/// CTRIA6:
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | EID | int > 0 | required | element id |
/// | 3 | PID | int > 0 | EID | PSHELL or PCOMP id |
/// | 4–6 | G1–G3 | int > 0 | required | corner grids |
/// | 7–9 | G4–G6 | int ≥ 0 | blank | mid-side grids of edges 1-2, 2-3, 3-1; blank or 0: that edge is straight and the displacement along it linear |
/// | cont. 2 | THETA/MCID | real or int | 0.0 | material orientation angle (deg) or system id |
/// | cont. 3 | ZOFFS | real | 0.0 | offset of the reference surface from the grids |
/// | cont. 4–6 | T1–T3 | real > 0 | property T | corner thicknesses (linear over the element) |
/// | cont. 7 | TFLAG | 0 or 1 | 0 | 1: T1–T3 are ratios of the property thickness |
#[derive(Debug, Clone, PartialEq)]
pub struct QuadraticShell {
    pub id: u32,
    pub pid: u32,
    /// Corner grids, then mid-side grids (8 for a CQUAD8, 6 for a CTRIA6); 0 for a blank
    /// mid-side grid.
    pub nodes: Vec<u32>,
    pub orientation: ShellOrientation,
    pub zoffs: f64,
    pub corner_thickness: Option<CornerThickness>,
    pub loc: Loc,
}

impl QuadraticShell {
    /// Read a `CQUAD8` card.
    pub fn cquad8(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        Self::read(
            card,
            4,
            &[3, 4, 5, 6, 7, 8, 9, 10],
            (15, 16),
            (17, &[11, 12, 13, 14]),
            17,
        )
    }

    /// Read a `CTRIA6` card.
    pub fn ctria6(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        Self::read(
            card,
            3,
            &[3, 4, 5, 6, 7, 8],
            (9, 10),
            (14, &[11, 12, 13]),
            14,
        )
    }

    /// The card with `corners` corner grids followed by mid-side grids at the fields `grids`,
    /// THETA/MCID and ZOFFS at `placement`, TFLAG and T1… at `thickness`, `last` data fields.
    fn read(
        card: &RawCard,
        corners: usize,
        grids: &[usize],
        (orient, zoffs): (usize, usize),
        (tflag, t): (usize, &[usize]),
        last: usize,
    ) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let id = f.id(1, "EID");
        f.set_id(id);
        let pid = f.opt_id(2, "PID").unwrap_or(id);
        let mut nodes = Vec::with_capacity(grids.len());
        for (k, &i) in grids.iter().enumerate() {
            let name = format!("G{}", k + 1);
            if k >= corners {
                // blank or 0: no mid-side grid on this edge
                nodes.push(f.id0_or(i, &name, 0));
            } else {
                nodes.push(f.id(i, &name));
            }
        }
        let orientation = orientation(&mut f, orient);
        let zoffs = f.real_or(zoffs, "ZOFFS", 0.0);
        let corner_thickness = corner_thickness(&mut f, tflag, t);
        let loc = f.loc();
        f.finish(last)?;
        Ok(QuadraticShell {
            id,
            pid,
            nodes,
            orientation,
            zoffs,
            corner_thickness,
            loc,
        })
    }
}

/// Read a solid element: EID, PID, `corners` required corner grids, then up to `midsides`
/// optional mid-side grids. Without any mid-side grid the element is linear (`corners` grids);
/// with at least one it is quadratic (`corners + midsides` entries, 0 for a blank mid-side,
/// whose edge is then straight and linear, as in Nastran).
fn solid_nodes(
    card: &RawCard,
    corners: usize,
    midsides: usize,
) -> Result<(u32, u32, Vec<u32>, Loc), Vec<DeckError>> {
    let mut f = FieldReader::new(card);
    let id = f.id(1, "EID");
    f.set_id(id);
    let pid = f.opt_id(2, "PID").unwrap_or(id);
    let mut nodes = Vec::with_capacity(corners + midsides);
    for k in 0..corners {
        nodes.push(f.id(3 + k, &format!("G{}", k + 1)));
    }
    let mids: Vec<Option<u32>> = (corners..corners + midsides)
        .map(|k| f.opt_id(3 + k, &format!("G{}", k + 1)))
        .collect();
    if mids.iter().any(Option::is_some) {
        nodes.extend(mids.iter().map(|g| g.unwrap_or(0)));
    }
    let loc = f.loc();
    f.finish(corners + midsides + 2)?;
    Ok((id, pid, nodes, loc))
}

/// `CHEXA` — hexahedron with 8 corner grids and up to 12 mid-side grids.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | EID | int > 0 | required | element id |
/// | 3 | PID | int > 0 | EID | PSOLID id |
/// | 4–9, cont. 2–3 | G1–G8 | int > 0 | required | corner grids (G1–G4 one face, G5–G8 opposite) |
/// | cont. 4–9, 2nd cont. 2–7 | G9–G20 | int > 0 | blank | mid-side grids of edges 1-2, 2-3, 3-4, 4-1, 1-5, 2-6, 3-7, 4-8, 5-6, 6-7, 7-8, 8-5 |
///
/// With no mid-side grid the element is the 8-node CHEXA; with any, the 20-node one, each
/// blank mid-side making its edge straight with a linear displacement.
#[derive(Debug, Clone, PartialEq)]
pub struct Chexa {
    pub id: u32,
    pub pid: u32,
    /// 8 grids, or 20 with 0 for a blank mid-side grid.
    pub nodes: Vec<u32>,
    pub loc: Loc,
}

impl Chexa {
    /// Read a `CHEXA` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let (id, pid, nodes, loc) = solid_nodes(card, 8, 12)?;
        Ok(Chexa {
            id,
            pid,
            nodes,
            loc,
        })
    }
}

/// `CPENTA` — pentahedron (wedge) with 6 corner grids and up to 9 mid-side grids.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | EID | int > 0 | required | element id |
/// | 3 | PID | int > 0 | EID | PSOLID id |
/// | 4–9 | G1–G6 | int > 0 | required | G1–G3 one triangle, G4–G6 the opposite |
/// | cont. 2–9, 2nd cont. 2 | G7–G15 | int > 0 | blank | mid-side grids of edges 1-2, 2-3, 3-1, 1-4, 2-5, 3-6, 4-5, 5-6, 6-4 |
///
/// With no mid-side grid the element is the 6-node CPENTA; with any, the 15-node one, each
/// blank mid-side making its edge straight with a linear displacement.
#[derive(Debug, Clone, PartialEq)]
pub struct Cpenta {
    pub id: u32,
    pub pid: u32,
    /// 6 grids, or 15 with 0 for a blank mid-side grid.
    pub nodes: Vec<u32>,
    pub loc: Loc,
}

impl Cpenta {
    /// Read a `CPENTA` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let (id, pid, nodes, loc) = solid_nodes(card, 6, 9)?;
        Ok(Cpenta {
            id,
            pid,
            nodes,
            loc,
        })
    }
}

/// `CTETRA` — four- or ten-node tetrahedron; in a ten-node one a blank mid-edge grid makes its
/// edge straight with a linear displacement.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | EID | int > 0 | required | element id |
/// | 3 | PID | int > 0 | EID | PSOLID id |
/// | 4–7 | G1–G4 | int > 0 | required | corner grids |
/// | 8–9, cont. 2–5 | G5–G10 | int ≥ 0 | blank | mid-edge grids (G1G2, G2G3, G3G1, G1G4, G2G4, G3G4); with any of them given, the others may be blank or 0 |
#[derive(Debug, Clone, PartialEq)]
pub struct Ctetra {
    pub id: u32,
    pub pid: u32,
    /// 4 or 10 grids.
    pub nodes: Vec<u32>,
    pub loc: Loc,
}

impl Ctetra {
    /// Read a `CTETRA` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let (id, pid, nodes, loc) = solid_nodes(card, 4, 6)?;
        Ok(Ctetra {
            id,
            pid,
            nodes,
            loc,
        })
    }
}

/// `CPYRAM` — pyramid with 4 base grids and an apex (the 13-node one, with mid-side grids, is
/// refused).
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | EID | int > 0 | required | element id |
/// | 3 | PID | int > 0 | EID | PSOLID id |
/// | 4–8 | G1–G5 | int > 0 | required | base G1–G4 (in order around it), apex G5 |
/// | 9, cont. 2–9 | G6–G13 | int > 0 | blank | mid-side grids: not supported |
#[derive(Debug, Clone, PartialEq)]
pub struct Cpyram {
    pub id: u32,
    pub pid: u32,
    /// The 5 grids.
    pub nodes: Vec<u32>,
    pub loc: Loc,
}

impl Cpyram {
    /// Read a `CPYRAM` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let (id, pid, nodes, loc) = solid_nodes(card, 5, 8)?;
        if nodes.len() > 5 {
            let mut f = FieldReader::new(card);
            f.set_id(id);
            f.card_error(
                "the 13-node CPYRAM (mid-side grids G6–G13) is not supported; give the 5 corner grids only",
            );
            return Err(f.into_errors());
        }
        Ok(Cpyram {
            id,
            pid,
            nodes,
            loc,
        })
    }
}

/// A scalar element's grid or scalar point: blank or 0 is ground (QRG: integer ≥ 0).
fn end_point(f: &mut FieldReader, i: usize, name: &str) -> Option<u32> {
    Some(f.id0_or(i, name, 0)).filter(|&g| g != 0)
}

fn spring_end(f: &mut FieldReader, i: usize, gname: &str, cname: &str) -> SpringEnd {
    let grid = end_point(f, i, gname);
    let code = f.int_or(i + 1, cname, 0);
    let component = match (grid, code) {
        // a blank or zero component names a scalar point (or ground without a point)
        (_, 0) => 0,
        (Some(_), 1..=6) => code as u8,
        (Some(_), _) => {
            f.error(
                i + 1,
                cname,
                format!(
                    "expected a single component 1-6 (0 or blank for a scalar point), found {code}"
                ),
            );
            0
        }
        (None, _) => {
            f.error(i, gname, "a component is given without a grid");
            0
        }
    };
    SpringEnd { grid, component }
}

/// The two ends of a scalar element; `scalar_only`: both are scalar points (no component field).
fn spring_ends(f: &mut FieldReader, first: usize, scalar_only: bool) -> [SpringEnd; 2] {
    let ends = if scalar_only {
        [
            SpringEnd {
                grid: end_point(f, first, "S1"),
                component: 0,
            },
            SpringEnd {
                grid: end_point(f, first + 1, "S2"),
                component: 0,
            },
        ]
    } else {
        [
            spring_end(f, first, "G1", "C1"),
            spring_end(f, first + 2, "G2", "C2"),
        ]
    };
    if ends[0].grid.is_none() && ends[1].grid.is_none() {
        f.card_error("both ends are grounded; give at least one grid or scalar point");
    }
    if let (Some(g), true) = (ends[0].grid, ends[0] == ends[1]) {
        let what = match ends[0].component {
            0 => format!("point {g}"),
            c => format!("GRID {g} component {c}"),
        };
        f.card_error(format!(
            "both ends are {what}: the element would connect a DOF to itself"
        ));
    }
    ends
}

/// `CELAS1` — scalar spring with a PELAS property (also the layout of `CDAMP1`).
///
/// `CDAMP1` is a scalar damper with a PDAMP property.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | EID | int > 0 | required | element id |
/// | 3 | PID | int > 0 | EID | PELAS id (CDAMP1: PDAMP id) |
/// | 4, 5 | G1 C1 | int | blank | first end: a grid and component 1–6, a scalar point with C1 0 or blank, or ground (blank or 0 G1) |
/// | 6, 7 | G2 C2 | int | blank | second end, as the first |
///
/// `CELAS3` / `CDAMP3` carry two scalar points instead (fields 4, 5: S1 S2, blank or 0 = ground),
/// read into the same struct with components 0.
#[derive(Debug, Clone, PartialEq)]
pub struct Celas1 {
    pub id: u32,
    pub pid: u32,
    pub ends: [SpringEnd; 2],
    pub loc: Loc,
}

/// `CELAS3` — scalar spring between scalar points with a PELAS property (EID, PID, S1, S2).
pub type Celas3 = Celas1;
/// `CDAMP1` / `CDAMP3` — scalar damper with a PDAMP property (layouts of CELAS1 / CELAS3).
pub type Cdamp1 = Celas1;

impl Celas1 {
    /// Read a `CELAS1` / `CDAMP1` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        Self::read(card, false)
    }

    /// Read a `CELAS3` / `CDAMP3` card (two scalar points).
    pub fn from_scalar_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        Self::read(card, true)
    }

    fn read(card: &RawCard, scalar_only: bool) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let id = f.id(1, "EID");
        f.set_id(id);
        let pid = f.opt_id(2, "PID").unwrap_or(id);
        let ends = spring_ends(&mut f, 3, scalar_only);
        let loc = f.loc();
        f.finish(if scalar_only { 4 } else { 6 })?;
        Ok(Celas1 { id, pid, ends, loc })
    }
}

/// `CELAS2` — scalar spring with its properties on the card (also the layout of `CDAMP2`).
///
/// `CDAMP2` carries B instead of K and no GE or S.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | EID | int > 0 | required | element id |
/// | 3 | K | real | required | stiffness (CDAMP2: damping B) |
/// | 4, 5 | G1 C1 | int | blank | first end (grid and component, scalar point with C1 0 or blank, or ground) |
/// | 6, 7 | G2 C2 | int | blank | second end |
/// | 8 | GE | real | 0.0 | structural damping coefficient (not on CDAMP2) |
/// | 9 | S | real | 0.0 | stress coefficient (kept, unused; not on CDAMP2) |
///
/// `CELAS4` (EID, K, S1, S2) and `CDAMP4` (EID, B, S1, S2) carry two scalar points instead.
/// `CMASS2` (EID, M, G1, C1, G2, C2) has the layout of `CDAMP2` with the mass M.
#[derive(Debug, Clone, PartialEq)]
pub struct Celas2 {
    pub id: u32,
    /// K (springs) or B (dampers).
    pub k: f64,
    pub ends: [SpringEnd; 2],
    pub ge: f64,
    pub s: f64,
    pub loc: Loc,
}

/// `CELAS4` — scalar spring between scalar points with K on the card (EID, K, S1, S2).
pub type Celas4 = Celas2;
/// `CDAMP2` / `CDAMP4` — scalar damper with B on the card (layouts of CELAS2 / CELAS4).
pub type Cdamp2 = Celas2;
/// `CMASS2` — scalar mass with M on the card (the layout of CDAMP2).
pub type Cmass2 = Celas2;

/// Which layout of a scalar element with its value on the card.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum OnCardLayout {
    /// CELAS2: grids and components, GE and S.
    Celas2,
    /// CELAS4: scalar points, nothing after them.
    Celas4,
    /// CDAMP2: grids and components, nothing after them.
    Cdamp2,
    /// CDAMP4: scalar points.
    Cdamp4,
    /// CMASS2: grids and components, nothing after them.
    Cmass2,
}

impl Celas2 {
    /// Read a `CELAS2` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        Self::read(card, OnCardLayout::Celas2)
    }

    /// Read a `CELAS2`, `CELAS4`, `CDAMP2`, `CDAMP4` or `CMASS2` card.
    pub fn read(card: &RawCard, layout: OnCardLayout) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let id = f.id(1, "EID");
        f.set_id(id);
        let damper = matches!(layout, OnCardLayout::Cdamp2 | OnCardLayout::Cdamp4);
        let value = match layout {
            OnCardLayout::Cmass2 => "M",
            _ if damper => "B",
            _ => "K",
        };
        let k = f.real(2, value);
        let scalar_only = matches!(layout, OnCardLayout::Celas4 | OnCardLayout::Cdamp4);
        let ends = spring_ends(&mut f, 3, scalar_only);
        let (ge, s, last) = match layout {
            OnCardLayout::Celas2 => (f.real_or(7, "GE", 0.0), f.real_or(8, "S", 0.0), 8),
            OnCardLayout::Cdamp2 | OnCardLayout::Cmass2 => (0.0, 0.0, 6),
            OnCardLayout::Celas4 | OnCardLayout::Cdamp4 => (0.0, 0.0, 4),
        };
        let loc = f.loc();
        f.finish(last)?;
        Ok(Celas2 {
            id,
            k,
            ends,
            ge,
            s,
            loc,
        })
    }
}

/// `CVISC` — viscous damper between two grids (axial and torsional, PVISC property).
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | EID | int > 0 | required | element id |
/// | 3 | PID | int > 0 | EID | PVISC id |
/// | 4, 5 | G1 G2 | int > 0 | required | grids |
#[derive(Debug, Clone, PartialEq)]
pub struct Cvisc {
    pub id: u32,
    pub pid: u32,
    pub grids: [u32; 2],
    pub loc: Loc,
}

impl Cvisc {
    /// Read a `CVISC` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let id = f.id(1, "EID");
        f.set_id(id);
        let pid = f.opt_id(2, "PID").unwrap_or(id);
        let grids = [f.id(3, "G1"), f.id(4, "G2")];
        if grids[0] == grids[1] {
            f.error(
                4,
                "G2",
                format!("G2 = G1 = {}: the damper needs two grids", grids[0]),
            );
        }
        let loc = f.loc();
        f.finish(4)?;
        Ok(Cvisc {
            id,
            pid,
            grids,
            loc,
        })
    }
}

/// How the element axes of a `CBUSH` are given.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub enum BushAxes {
    /// CID given: the axes of that system (0 = basic).
    System(u32),
    /// GO: x from GA to GB, y in the plane of x and the vector GA→GO.
    Grid(u32),
    /// X1–X3: x from GA to GB, y in the plane of x and this vector (in GA's displacement system).
    Vector([f64; 3]),
    /// Nothing given: basic axes (coincident grids; refused for non-coincident grids).
    Blank,
}

/// `CBUSH` — generalized spring-damper with six stiffnesses (PBUSH property).
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | EID | int > 0 | required | element id |
/// | 3 | PID | int > 0 | EID | PBUSH id |
/// | 4 | GA | int > 0 | required | first grid |
/// | 5 | GB | int > 0 | blank | second grid (blank: grounded) |
/// | 6–8 | GO/X1 X2 X3 | int or reals | blank | orientation grid, or vector in GA's displacement system |
/// | 9 | CID | int ≥ 0 | blank | element system (overrides GO/X) |
/// | cont. 2 | S | real 0–1 | 0.5 | location of the spring between GA (0) and GB (1) |
/// | cont. 3 | OCID | int ≥ −1 | −1 | −1: the spring sits on the line GA–GB at S; ≥ 0: at the offset S1–S3 from GA in system OCID |
/// | cont. 4–6 | S1 S2 S3 | real | 0.0 | offset of the spring from GA (OCID ≥ 0) |
#[derive(Debug, Clone, PartialEq)]
pub struct Cbush {
    pub id: u32,
    pub pid: u32,
    pub ga: u32,
    pub gb: Option<u32>,
    pub axes: BushAxes,
    pub s: f64,
    pub ocid: i32,
    pub offset: [f64; 3],
    pub loc: Loc,
}

impl Cbush {
    /// Read a `CBUSH` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let id = f.id(1, "EID");
        f.set_id(id);
        let pid = f.opt_id(2, "PID").unwrap_or(id);
        let ga = f.id(3, "GA");
        let gb = f.opt_id(4, "GB");
        let cid = f.opt_int(8, "CID");
        let axes = match (cid, f.value(5)) {
            (Some(c), _) if c >= 0 => BushAxes::System(c as u32),
            (Some(c), _) => {
                f.error(8, "CID", format!("expected a system id ≥ 0, found {c}"));
                BushAxes::Blank
            }
            (None, Value::Int(_)) => BushAxes::Grid(f.id(5, "GO")),
            (None, Value::Blank) if (6..=7).all(|i| f.value(i).is_blank()) => BushAxes::Blank,
            (None, _) => BushAxes::Vector([
                f.real_or(5, "X1", 0.0),
                f.real_or(6, "X2", 0.0),
                f.real_or(7, "X3", 0.0),
            ]),
        };
        let s = f.real_or(9, "S", 0.5);
        if !(0.0..=1.0).contains(&s) {
            f.error(9, "S", format!("expected a location 0 to 1, found {s}"));
        }
        let ocid = f.int_or(10, "OCID", -1);
        if ocid < -1 {
            f.error(
                10,
                "OCID",
                format!("expected -1 or a system id, found {ocid}"),
            );
        }
        let offset = [
            f.real_or(11, "S1", 0.0),
            f.real_or(12, "S2", 0.0),
            f.real_or(13, "S3", 0.0),
        ];
        let loc = f.loc();
        f.finish(13)?;
        Ok(Cbush {
            id,
            pid,
            ga,
            gb,
            axes,
            s,
            ocid: ocid as i32,
            offset,
            loc,
        })
    }
}

/// `SPOINT` — scalar points: one DOF each, no location.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 … | ID1 ID2 … | int > 0 (`THRU` allowed) | ≥ 1 required | scalar point ids |
#[derive(Debug, Clone, PartialEq)]
pub struct Spoint {
    pub ids: Vec<u32>,
    pub loc: Loc,
}

impl Spoint {
    /// Read an `SPOINT` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let ids = f.id_list(1, "ID");
        if ids.is_empty() {
            f.card_error("no scalar point id given");
        }
        let loc = f.loc();
        let len = f.len();
        f.finish(len)?;
        Ok(Spoint { ids, loc })
    }
}

/// `CONM2` — concentrated mass and inertia at a grid, with offset.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | EID | int > 0 | required | element id |
/// | 3 | G | int > 0 | required | grid |
/// | 4 | CID | int ≥ −1 | 0 | system of the offset and inertia; −1: X1–X3 are the basic coordinates of the centre of gravity |
/// | 5 | M | real | 0.0 | mass |
/// | 6–8 | X1 X2 X3 | real | 0.0 | offset from the grid (or CG location when CID = −1) |
/// | cont. 2–7 | I11 I21 I22 I31 I32 I33 | real | 0.0 | inertia about the CG (Nastran sign convention: Iij = −∫ xi xj dm off the diagonal) |
#[derive(Debug, Clone, PartialEq)]
pub struct Conm2 {
    pub id: u32,
    pub grid: u32,
    /// −1 means X is the CG location in the basic system.
    pub cid: i32,
    pub mass: f64,
    pub offset: [f64; 3],
    /// I11 I21 I22 I31 I32 I33.
    pub inertia: [f64; 6],
    pub loc: Loc,
}

impl Conm2 {
    /// Read a `CONM2` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let id = f.id(1, "EID");
        f.set_id(id);
        let grid = f.id(2, "G");
        let cid = match f.opt_int(3, "CID") {
            None => 0,
            Some(c) if (-1..=i64::from(i32::MAX)).contains(&c) => c as i32,
            Some(c) => {
                f.error(
                    3,
                    "CID",
                    format!("expected -1 or a system id >= 0, found {c}"),
                );
                0
            }
        };
        let mass = f.real_or(4, "M", 0.0);
        let offset = [
            f.real_or(5, "X1", 0.0),
            f.real_or(6, "X2", 0.0),
            f.real_or(7, "X3", 0.0),
        ];
        let names = ["I11", "I21", "I22", "I31", "I32", "I33"];
        let mut inertia = [0.0; 6];
        for (k, name) in names.iter().enumerate() {
            inertia[k] = f.real_or(9 + k, name, 0.0);
        }
        let loc = f.loc();
        f.finish(14)?;
        Ok(Conm2 {
            id,
            grid,
            cid,
            mass,
            offset,
            inertia,
            loc,
        })
    }
}
