//! Line elements: rods `CROD`, `CONROD`, `CTUBE`, beams `CBAR`, `CBEAM` and the curved beam
//! `CBEND`.

use crate::card_values::Dofs;
use crate::deck::error::{DeckError, Loc};
use crate::deck::fields::RawCard;
use crate::deck::reader::FieldReader;
use crate::deck::value::Value;

/// `CROD` / `CTUBE` — a rod with a PROD / PTUBE property.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | EID | int > 0 | required | element id |
/// | 3 | PID | int > 0 | EID | PROD (CROD) or PTUBE (CTUBE) id |
/// | 4, 5 | G1 G2 | int > 0 | required | end grids |
#[derive(Debug, Clone, PartialEq)]
pub struct Crod {
    pub id: u32,
    pub pid: u32,
    pub nodes: [u32; 2],
    pub loc: Loc,
}

impl Crod {
    /// Read a `CROD` or `CTUBE` card (same layout).
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let id = f.id(1, "EID");
        f.set_id(id);
        let pid = f.opt_id(2, "PID").unwrap_or(id);
        let nodes = [f.id(3, "G1"), f.id(4, "G2")];
        let loc = f.loc();
        f.finish(4)?;
        Ok(Crod {
            id,
            pid,
            nodes,
            loc,
        })
    }
}

/// `CONROD` — a rod with its properties on the card.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | EID | int > 0 | required | element id |
/// | 3, 4 | G1 G2 | int > 0 | required | end grids |
/// | 5 | MID | int > 0 | required | MAT1 id |
/// | 6 | A | real | 0.0 | area |
/// | 7 | J | real | 0.0 | torsion constant |
/// | 8 | C | real | 0.0 | torsional stress coefficient (kept, unused) |
/// | 9 | NSM | real | 0.0 | non-structural mass per length |
#[derive(Debug, Clone, PartialEq)]
pub struct Conrod {
    pub id: u32,
    pub nodes: [u32; 2],
    pub mid: u32,
    pub a: f64,
    pub j: f64,
    pub c: f64,
    pub nsm: f64,
    pub loc: Loc,
}

impl Conrod {
    /// Read a `CONROD` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let id = f.id(1, "EID");
        f.set_id(id);
        let nodes = [f.id(2, "G1"), f.id(3, "G2")];
        let mid = f.id(4, "MID");
        let a = f.real_or(5, "A", 0.0);
        let j = f.real_or(6, "J", 0.0);
        let c = f.real_or(7, "C", 0.0);
        let nsm = f.real_or(8, "NSM", 0.0);
        let loc = f.loc();
        f.finish(8)?;
        Ok(Conrod {
            id,
            nodes,
            mid,
            a,
            j,
            c,
            nsm,
            loc,
        })
    }
}

/// The orientation of a beam: a vector v or a grid G0 (v from GA to G0).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum BeamOrientation {
    Vector([f64; 3]),
    Grid(u32),
}

/// The OFFT flags of a CBAR / CBEAM: the frame of the orientation vector (basic or GA's
/// displacement system); the offsets are always in the grids' displacement systems (offsets in
/// the element system are refused on the card).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Offt {
    /// True for `B..`: v in the basic system; false for `G..`: in GA's displacement system.
    pub vector_in_basic: bool,
}

/// `CBAR` / `CBEAM` — a beam between two grids.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | EID | int > 0 | required | element id |
/// | 3 | PID | int > 0 | EID | PBAR/PBARL (CBAR) or PBEAM/PBEAML (CBEAM) id |
/// | 4, 5 | GA GB | int > 0 | required | end grids |
/// | 6 | X1 or G0 | real or int | required | orientation vector v (X1 X2 X3) or grid G0 (v from GA to G0); BAROR/BEAMOR defaults are not supported |
/// | 7, 8 | X2 X3 | real | 0.0 | |
/// | 9 | OFFT | GGG, BGG, GGO, BGO, GOG, BOG, GOO, BOO | GGG | first letter: v in GA's displacement system (G) or basic (B); second/third: offsets at A/B in the grid's displacement system (G) or the element system (O: refused unless that offset is zero); CBEAM's real BIT (p-version twist) is refused |
/// | cont. 2, 3 | PA PB | components | blank | pin flags: components released at each end (element system) |
/// | cont. 4–6 | W1A W2A W3A | real | 0.0 | offset of end A |
/// | cont. 7–9 | W1B W2B W3B | real | 0.0 | offset of end B |
/// | cont. 2 (CBEAM) | SA SB | int | blank | warping scalar points: refused |
#[derive(Debug, Clone, PartialEq)]
pub struct Cbar {
    pub id: u32,
    pub pid: u32,
    pub nodes: [u32; 2],
    pub orientation: BeamOrientation,
    pub offt: Offt,
    pub pins: [Dofs; 2],
    pub offsets: [[f64; 3]; 2],
    pub loc: Loc,
}

impl Cbar {
    /// Read a `CBAR` (`beam` false) or `CBEAM` (`beam` true) card.
    pub fn from_card(card: &RawCard, beam: bool) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let id = f.id(1, "EID");
        f.set_id(id);
        let pid = f.opt_id(2, "PID").unwrap_or(id);
        let nodes = [f.id(3, "GA"), f.id(4, "GB")];
        let orientation = orientation(
            &mut f,
            nodes,
            if beam {
                "the BEAMOR defaults are not supported"
            } else {
                "the BAROR defaults are not supported"
            },
        );
        let offt_text = match f.value(8) {
            Value::Real(_) if beam => {
                f.error(
                    8,
                    "BIT",
                    "a built-in twist (p-version CBEAM) is not supported",
                );
                String::from("GGG")
            }
            _ => f.opt_text(8, "OFFT").unwrap_or_else(|| String::from("GGG")),
        };
        let pins = [f.dofs(9, "PA"), f.dofs(10, "PB")];
        let offsets = [
            [
                f.real_or(11, "W1A", 0.0),
                f.real_or(12, "W2A", 0.0),
                f.real_or(13, "W3A", 0.0),
            ],
            [
                f.real_or(14, "W1B", 0.0),
                f.real_or(15, "W2B", 0.0),
                f.real_or(16, "W3B", 0.0),
            ],
        ];
        let offt = offt_flags(&mut f, &offt_text, &offsets);
        let last = if beam {
            for (i, name) in [(17, "SA"), (18, "SB")] {
                if !f.value(i).is_blank() {
                    f.error(
                        i,
                        name,
                        "warping scalar points are not supported (paraflex beams have no warping DOF)",
                    );
                }
            }
            18
        } else {
            16
        };
        let loc = f.loc();
        f.finish(last)?;
        Ok(Cbar {
            id,
            pid,
            nodes,
            orientation,
            offt,
            pins,
            offsets,
            loc,
        })
    }
}

/// `CBEND` — a curved beam (circular arc) between two grids.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | EID | int > 0 | required | element id |
/// | 3 | PID | int > 0 | EID | PBEND id |
/// | 4, 5 | GA GB | int > 0 | required | end grids |
/// | 6 | X1 or G0 | real or int | required | orientation vector v (X1 X2 X3, in GA's displacement system) or grid G0 (v from GA to G0); its use depends on GEOM |
/// | 7, 8 | X2 X3 | real | 0.0 | |
/// | 9 | GEOM | 1–4 | required | 1: the centre of curvature is on the line from A along v; 2: the arc's tangent at A is along v, the arc on v's side of the chord AB; 3: radius RB of the PBEND, the centre on the side of AB opposite to v; 4: arc angle THETAB of the PBEND, the centre on the side of AB opposite to v |
#[derive(Debug, Clone, PartialEq)]
pub struct Cbend {
    pub id: u32,
    pub pid: u32,
    pub nodes: [u32; 2],
    pub orientation: BeamOrientation,
    pub geom: u8,
    pub loc: Loc,
}

impl Cbend {
    /// Read a `CBEND` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let id = f.id(1, "EID");
        f.set_id(id);
        let pid = f.opt_id(2, "PID").unwrap_or(id);
        let nodes = [f.id(3, "GA"), f.id(4, "GB")];
        let orientation = orientation(&mut f, nodes, "GEOM needs one");
        let geom = f.int(8, "GEOM");
        if !(1..=4).contains(&geom) {
            f.error(8, "GEOM", format!("expected 1, 2, 3 or 4, found {geom}"));
        }
        let loc = f.loc();
        f.finish(8)?;
        Ok(Cbend {
            id,
            pid,
            nodes,
            orientation,
            geom: geom.clamp(1, 4) as u8,
            loc,
        })
    }
}

/// The orientation vector X1–X3 or grid G0 of fields 6–8 of a CBAR, CBEAM or CBEND; `blank`
/// says why a blank orientation is refused.
fn orientation(f: &mut FieldReader, nodes: [u32; 2], blank: &str) -> BeamOrientation {
    match f.value(5) {
        Value::Int(_) => {
            let g0 = f.id(5, "G0");
            if nodes.contains(&g0) {
                f.error(5, "G0", format!("G0 = {g0} is an end grid of the element"));
            }
            for (i, name) in [(6, "X2"), (7, "X3")] {
                if !f.value(i).is_blank() {
                    f.error(i, name, "must be blank when G0 is given");
                }
            }
            BeamOrientation::Grid(g0)
        }
        Value::Blank if f.value(6).is_blank() && f.value(7).is_blank() => {
            f.error(
                5,
                "X1/G0",
                format!("give the orientation vector X1 X2 X3 or a grid G0 ({blank})"),
            );
            BeamOrientation::Vector([0.0; 3])
        }
        _ => BeamOrientation::Vector([
            f.real_or(5, "X1", 0.0),
            f.real_or(6, "X2", 0.0),
            f.real_or(7, "X3", 0.0),
        ]),
    }
}

/// The OFFT flags; an `O` (element-system offset) is refused when its offset is not zero.
fn offt_flags(f: &mut FieldReader, text: &str, offsets: &[[f64; 3]; 2]) -> Offt {
    const ALLOWED: [&str; 8] = ["GGG", "BGG", "GGO", "BGO", "GOG", "BOG", "GOO", "BOO"];
    if !ALLOWED.contains(&text) {
        f.error(
            8,
            "OFFT",
            format!("expected one of {}, found {text}", ALLOWED.join(", ")),
        );
        return Offt {
            vector_in_basic: false,
        };
    }
    for (end, letter) in text.chars().skip(1).enumerate() {
        if letter == 'O' && offsets[end] != [0.0; 3] {
            f.error(
                8,
                "OFFT",
                format!(
                    "OFFT = {text}: offsets in the element system are not supported; give W1{e}-W3{e} in the grid's displacement system (G)",
                    e = ["A", "B"][end]
                ),
            );
        }
    }
    Offt {
        vector_in_basic: text.starts_with('B'),
    }
}
