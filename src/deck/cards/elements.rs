//! Elements: shells `CQUAD4`, `CTRIA3`; solids `CHEXA`, `CPENTA`, `CTETRA`; springs `CELAS1`,
//! `CELAS2`; concentrated mass `CONM2`.

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

/// Read the corner-thickness continuation (TFLAG at `first`, then `count` corner values).
/// Returns `None` when all are blank.
fn corner_thickness(f: &mut FieldReader, first: usize, count: usize) -> Option<CornerThickness> {
    if (first..=first + count).all(|i| f.value(i).is_blank()) {
        return None;
    }
    let relative = match f.int_or(first, "TFLAG", 0) {
        0 => false,
        1 => true,
        other => {
            f.error(first, "TFLAG", format!("expected 0 or 1, found {other}"));
            false
        }
    };
    let mut t = [None; 4];
    for (k, slot) in t.iter_mut().take(count).enumerate() {
        *slot = f.opt_real(first + 1 + k, &format!("T{}", k + 1));
        if let Some(v) = *slot
            && v <= 0.0
        {
            f.error(
                first + 1 + k,
                &format!("T{}", k + 1),
                format!("expected a thickness > 0, found {v:e}"),
            );
        }
    }
    Some(CornerThickness { relative, t })
}

/// `CQUAD4` — four-node shell.
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
    /// Read a `CQUAD4` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let id = f.id(1, "EID");
        f.set_id(id);
        let pid = f.opt_id(2, "PID").unwrap_or(id);
        let nodes = [f.id(3, "G1"), f.id(4, "G2"), f.id(5, "G3"), f.id(6, "G4")];
        let orientation = orientation(&mut f, 7);
        let zoffs = f.real_or(8, "ZOFFS", 0.0);
        let corner_thickness = corner_thickness(&mut f, 10, 4);
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

/// `CTRIA3` — three-node shell.
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
    /// Read a `CTRIA3` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let id = f.id(1, "EID");
        f.set_id(id);
        let pid = f.opt_id(2, "PID").unwrap_or(id);
        let nodes = [f.id(3, "G1"), f.id(4, "G2"), f.id(5, "G3")];
        let orientation = orientation(&mut f, 6);
        let zoffs = f.real_or(7, "ZOFFS", 0.0);
        let corner_thickness = corner_thickness(&mut f, 10, 3);
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

/// Read a solid element: EID, PID, then grids; `counts` are the accepted numbers of grids and
/// `supported` those paraflex has formulations for.
fn solid_nodes(
    card: &RawCard,
    max_nodes: usize,
    supported: &[usize],
) -> Result<(u32, u32, Vec<u32>, Loc), Vec<DeckError>> {
    let mut f = FieldReader::new(card);
    let id = f.id(1, "EID");
    f.set_id(id);
    let pid = f.opt_id(2, "PID").unwrap_or(id);
    let last = f.len().max(3);
    let mut nodes = Vec::with_capacity(last - 2);
    for i in 3..=last.min(max_nodes + 2) {
        let name = format!("G{}", i - 2);
        nodes.push(f.id(i, &name));
    }
    if !supported.contains(&nodes.len()) {
        let counts: Vec<String> = supported.iter().map(|n| n.to_string()).collect();
        f.card_error(format!(
            "{} grids given; paraflex supports {} grids for this element",
            nodes.len(),
            counts.join(" or ")
        ));
    }
    let loc = f.loc();
    f.finish(max_nodes + 2)?;
    Ok((id, pid, nodes, loc))
}

/// `CHEXA` — eight-node hexahedron (linear; incompatible modes in the formulation).
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | EID | int > 0 | required | element id |
/// | 3 | PID | int > 0 | EID | PSOLID id |
/// | 4–9, cont. 2–3 | G1–G8 | int > 0 | required | corner grids (G1–G4 one face, G5–G8 opposite) |
///
/// The 20-node form is rejected (not supported).
#[derive(Debug, Clone, PartialEq)]
pub struct Chexa {
    pub id: u32,
    pub pid: u32,
    pub nodes: [u32; 8],
    pub loc: Loc,
}

impl Chexa {
    /// Read a `CHEXA` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let (id, pid, nodes, loc) = solid_nodes(card, 20, &[8])?;
        Ok(Chexa {
            id,
            pid,
            nodes: nodes.try_into().unwrap_or([0; 8]),
            loc,
        })
    }
}

/// `CPENTA` — six-node pentahedron (wedge).
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | EID | int > 0 | required | element id |
/// | 3 | PID | int > 0 | EID | PSOLID id |
/// | 4–9 | G1–G6 | int > 0 | required | G1–G3 one triangle, G4–G6 the opposite |
///
/// The 15-node form is rejected (not supported).
#[derive(Debug, Clone, PartialEq)]
pub struct Cpenta {
    pub id: u32,
    pub pid: u32,
    pub nodes: [u32; 6],
    pub loc: Loc,
}

impl Cpenta {
    /// Read a `CPENTA` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let (id, pid, nodes, loc) = solid_nodes(card, 15, &[6])?;
        Ok(Cpenta {
            id,
            pid,
            nodes: nodes.try_into().unwrap_or([0; 6]),
            loc,
        })
    }
}

/// `CTETRA` — four- or ten-node tetrahedron.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | EID | int > 0 | required | element id |
/// | 3 | PID | int > 0 | EID | PSOLID id |
/// | 4–7 | G1–G4 | int > 0 | required | corner grids |
/// | 8–9, cont. 2–5 | G5–G10 | int > 0 | blank | mid-edge grids (G1G2, G2G3, G3G1, G1G4, G2G4, G3G4) |
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
        let (id, pid, nodes, loc) = solid_nodes(card, 10, &[4, 10])?;
        Ok(Ctetra {
            id,
            pid,
            nodes,
            loc,
        })
    }
}

fn spring_end(f: &mut FieldReader, i: usize, gname: &str, cname: &str) -> SpringEnd {
    let grid = f.opt_id(i, gname);
    let code = f.int_or(i + 1, cname, 0);
    let component = match (grid, code) {
        (None, 0) => 0,
        (Some(_), 1..=6) => code as u8,
        (Some(_), _) => {
            f.error(
                i + 1,
                cname,
                format!("expected a single component 1-6, found {code}"),
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

fn spring_ends(f: &mut FieldReader, first: usize) -> [SpringEnd; 2] {
    let ends = [
        spring_end(f, first, "G1", "C1"),
        spring_end(f, first + 2, "G2", "C2"),
    ];
    if ends[0].grid.is_none() && ends[1].grid.is_none() {
        f.card_error("both ends are grounded; give at least one grid and component");
    }
    if let (Some(g), true) = (ends[0].grid, ends[0] == ends[1] && ends[0].component > 0) {
        f.card_error(format!(
            "both ends are GRID {g} component {}: the spring would connect a DOF to itself",
            ends[0].component
        ));
    }
    ends
}

/// `CELAS1` — scalar spring with a PELAS property.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | EID | int > 0 | required | element id |
/// | 3 | PID | int > 0 | EID | PELAS id |
/// | 4, 5 | G1 C1 | int | blank | first end (blank grid = ground) |
/// | 6, 7 | G2 C2 | int | blank | second end (blank grid = ground) |
#[derive(Debug, Clone, PartialEq)]
pub struct Celas1 {
    pub id: u32,
    pub pid: u32,
    pub ends: [SpringEnd; 2],
    pub loc: Loc,
}

impl Celas1 {
    /// Read a `CELAS1` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let id = f.id(1, "EID");
        f.set_id(id);
        let pid = f.opt_id(2, "PID").unwrap_or(id);
        let ends = spring_ends(&mut f, 3);
        let loc = f.loc();
        f.finish(6)?;
        Ok(Celas1 { id, pid, ends, loc })
    }
}

/// `CELAS2` — scalar spring with its properties on the card.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | EID | int > 0 | required | element id |
/// | 3 | K | real | required | stiffness |
/// | 4, 5 | G1 C1 | int | blank | first end (blank grid = ground) |
/// | 6, 7 | G2 C2 | int | blank | second end |
/// | 8 | GE | real | 0.0 | structural damping coefficient |
/// | 9 | S | real | 0.0 | stress coefficient (kept, unused) |
#[derive(Debug, Clone, PartialEq)]
pub struct Celas2 {
    pub id: u32,
    pub k: f64,
    pub ends: [SpringEnd; 2],
    pub ge: f64,
    pub s: f64,
    pub loc: Loc,
}

impl Celas2 {
    /// Read a `CELAS2` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let id = f.id(1, "EID");
        f.set_id(id);
        let k = f.real(2, "K");
        let ends = spring_ends(&mut f, 3);
        let ge = f.real_or(7, "GE", 0.0);
        let s = f.real_or(8, "S", 0.0);
        let loc = f.loc();
        f.finish(8)?;
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
