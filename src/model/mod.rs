//! The cross-referenced, validated model built from a [`Deck`](crate::deck::Deck).
//!
//! [`Model::build`] runs every check in one pass and returns either the model or *all* errors,
//! each located at the offending card:
//! - [`ids`]: duplicate ids per id space;
//! - [`coords`]: `CORD2R`/`CORD2C` resolution (RID chains, cycles, degenerate definitions);
//! - [`build`]: grids in basic, elements and rigid elements with their grids and properties;
//! - [`xref`]: every other reference (materials, sets, loads, tables, sensors, parameters);
//! - [`values`]: out-of-range material, property and mass values;
//! - [`pmpar`]: `PMPAR` references, bounds and nominal values;
//! - [`geometry`]: exact element integrals and shape checks;
//! - [`params`]: the `PARAM`s paraflex uses ([`params::KNOWN_PARAMS`]);
//! - [`case`]: case-control selections and output requests, and sets nothing selects;
//! - [`mass_check`]: a dynamic solution on a model without mass;
//! - [`mechanism`]: the multibody cards of `SOL FMB` as a typed mechanism;
//! - [`mass`]: mass properties; [`summary`]: the check summary and mesh arrays;
//! - [`lookup`]: solution-control data by id (EIGRL, FREQ, TSTEP, PMOR, PVAL, EKF, …).
//!
//! The cards stay private to this module: later modules read typed, cross-referenced data
//! through [`Model`]'s methods: [`materials`], [`properties`] (shell, solid, spring),
//! [`sets`] (SPC and static load sets, combinations expanded), [`dynamic_loads`] (DLOAD,
//! TLOAD1/RLOAD1 with their DAREA entries, tables), [`pmpar`] ([`Model::parameters`]),
//! [`sensors`]; rigid elements carry their own data ([`RigidKind`]).

pub mod bend;
pub mod build;
pub mod bush;
pub mod case;
pub mod coords;
pub mod damping;
pub mod dynamic_loads;
pub mod geometry;
pub mod grid_loads;
pub mod ids;
pub mod line_loads;
pub mod lines;
pub mod lookup;
pub mod mass;
pub mod mass_check;
pub mod materials;
pub mod mechanism;
pub mod mesh;
pub mod params;
pub mod parts;
pub mod pmpar;
pub mod pressure;
pub mod properties;
pub mod rsscon;
pub mod scalar_points;
pub mod sensors;
pub mod sets;
pub mod summary;
pub mod temperature;
pub mod values;
pub mod xref;

use std::collections::HashMap;
use std::sync::Arc;

use crate::deck::case_control::Subcase;
use crate::deck::{BulkData, Loc, Solution, Warning};
use crate::fe::solid::SolidKind;
use crate::fe::solid_midside::Midsides;

pub use crate::card_values::Dofs;
pub use coords::CoordSystem;
pub use mass::MassProperties;
pub use mesh::{ElementBlock, MeshArrays};
pub use params::ModelParams;
pub use summary::CheckSummary;

/// A grid point with its location in the basic system.
#[derive(Debug, Clone, PartialEq)]
pub struct GridPoint {
    pub id: u32,
    /// Location in the basic system.
    pub xyz: [f64; 3],
    /// System the card's coordinates were given in.
    pub cp: u32,
    /// Displacement (output) system; resolved in [`Model::coords`].
    pub cd: u32,
    /// Permanent single-point constraints.
    pub ps: Dofs,
    pub loc: Loc,
}

/// Element types of the model (the mass element CONM2 and the springs included).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum ElementKind {
    Quad4,
    Tria3,
    /// CQUADR: a CQUAD4 by another name (same kernel).
    QuadR,
    /// CTRIAR: a CTRIA3 by another name (same kernel).
    TriaR,
    /// CQUAD8: eight-node curved shell.
    Quad8,
    /// CTRIA6: six-node curved shell.
    Tria6,
    Cshear,
    Hexa8,
    Penta6,
    Tetra4,
    Tetra10,
    /// CHEXA with mid-side grids (20 nodes, blank mid-sides allowed).
    Hexa20,
    /// CPENTA with mid-side grids (15 nodes, blank mid-sides allowed).
    Penta15,
    /// CPYRAM with 5 grids.
    Pyram5,
    Celas1,
    Celas2,
    Celas3,
    Celas4,
    Cdamp1,
    Cdamp2,
    Cdamp3,
    Cdamp4,
    Cvisc,
    Cbush,
    /// CMASS2: a scalar mass between two DOFs (or a DOF and ground).
    Cmass2,
    Conm2,
    Crod,
    Conrod,
    Ctube,
    Cbar,
    Cbeam,
    /// CBEND: a curved beam (circular arc).
    Cbend,
}

impl ElementKind {
    /// The bulk-data card name (a 10-node tetra is a `CTETRA`).
    pub fn card(self) -> &'static str {
        match self {
            ElementKind::Quad4 => "CQUAD4",
            ElementKind::Tria3 => "CTRIA3",
            ElementKind::QuadR => "CQUADR",
            ElementKind::TriaR => "CTRIAR",
            ElementKind::Quad8 => "CQUAD8",
            ElementKind::Tria6 => "CTRIA6",
            ElementKind::Cshear => "CSHEAR",
            ElementKind::Hexa8 | ElementKind::Hexa20 => "CHEXA",
            ElementKind::Penta6 | ElementKind::Penta15 => "CPENTA",
            ElementKind::Tetra4 | ElementKind::Tetra10 => "CTETRA",
            ElementKind::Pyram5 => "CPYRAM",
            ElementKind::Celas1 => "CELAS1",
            ElementKind::Celas2 => "CELAS2",
            ElementKind::Celas3 => "CELAS3",
            ElementKind::Celas4 => "CELAS4",
            ElementKind::Cdamp1 => "CDAMP1",
            ElementKind::Cdamp2 => "CDAMP2",
            ElementKind::Cdamp3 => "CDAMP3",
            ElementKind::Cdamp4 => "CDAMP4",
            ElementKind::Cvisc => "CVISC",
            ElementKind::Cbush => "CBUSH",
            ElementKind::Cmass2 => "CMASS2",
            ElementKind::Conm2 => "CONM2",
            ElementKind::Crod => "CROD",
            ElementKind::Conrod => "CONROD",
            ElementKind::Ctube => "CTUBE",
            ElementKind::Cbar => "CBAR",
            ElementKind::Cbeam => "CBEAM",
            ElementKind::Cbend => "CBEND",
        }
    }

    /// Name of the output block (`CTETRA10`, `CHEXA20`, `CPENTA15` for the quadratic solids),
    /// see [`ElementBlock::card`].
    pub fn block_name(self) -> &'static str {
        match self {
            ElementKind::Tetra10 => "CTETRA10",
            ElementKind::Hexa20 => "CHEXA20",
            ElementKind::Penta15 => "CPENTA15",
            k => k.card(),
        }
    }

    /// The solid kernel's topology of a solid element, `None` for other elements.
    pub fn solid_kind(self) -> Option<SolidKind> {
        match self {
            ElementKind::Hexa8 => Some(SolidKind::Hexa8),
            ElementKind::Penta6 => Some(SolidKind::Penta6),
            ElementKind::Tetra4 => Some(SolidKind::Tetra4),
            ElementKind::Tetra10 => Some(SolidKind::Tetra10),
            ElementKind::Hexa20 => Some(SolidKind::Hexa20),
            ElementKind::Penta15 => Some(SolidKind::Penta15),
            ElementKind::Pyram5 => Some(SolidKind::Pyram5),
            _ => None,
        }
    }

    /// True for the scalar springs CELAS1–CELAS4.
    pub fn is_scalar_spring(self) -> bool {
        matches!(
            self,
            ElementKind::Celas1 | ElementKind::Celas2 | ElementKind::Celas3 | ElementKind::Celas4
        )
    }

    /// True for the viscous dampers CDAMP1–CDAMP4 and CVISC: no stiffness or mass, a damping
    /// matrix that statics and real modes ignore (as Nastran does).
    pub fn is_damper(self) -> bool {
        matches!(
            self,
            ElementKind::Cdamp1
                | ElementKind::Cdamp2
                | ElementKind::Cdamp3
                | ElementKind::Cdamp4
                | ElementKind::Cvisc
        )
    }

    /// True for CQUAD4, CTRIA3, CQUADR, CTRIAR, CQUAD8 and CTRIA6.
    pub fn is_shell(self) -> bool {
        matches!(
            self,
            ElementKind::Quad4
                | ElementKind::Tria3
                | ElementKind::QuadR
                | ElementKind::TriaR
                | ElementKind::Quad8
                | ElementKind::Tria6
        )
    }

    /// True for the rods and beams (CROD, CONROD, CTUBE, CBAR, CBEAM).
    pub fn is_line(self) -> bool {
        matches!(
            self,
            ElementKind::Crod
                | ElementKind::Conrod
                | ElementKind::Ctube
                | ElementKind::Cbar
                | ElementKind::Cbeam
        )
    }
}

/// A property by kind and position in its [`BulkData`] vector.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PropertyRef {
    Pshell(usize),
    Pcomp(usize),
    Psolid(usize),
    Pshear(usize),
    Pelas(usize),
    Pdamp(usize),
    Pvisc(usize),
    Pbush(usize),
    Prod(usize),
    Ptube(usize),
    Pbar(usize),
    Pbarl(usize),
    Pbeam(usize),
    Pbeaml(usize),
    Pbend(usize),
}

impl PropertyRef {
    /// Card name.
    pub fn card(self) -> &'static str {
        match self {
            PropertyRef::Pshell(_) => "PSHELL",
            PropertyRef::Pcomp(_) => "PCOMP",
            PropertyRef::Psolid(_) => "PSOLID",
            PropertyRef::Pshear(_) => "PSHEAR",
            PropertyRef::Pelas(_) => "PELAS",
            PropertyRef::Pdamp(_) => "PDAMP",
            PropertyRef::Pvisc(_) => "PVISC",
            PropertyRef::Pbush(_) => "PBUSH",
            PropertyRef::Prod(_) => "PROD",
            PropertyRef::Ptube(_) => "PTUBE",
            PropertyRef::Pbar(_) => "PBAR",
            PropertyRef::Pbarl(_) => "PBARL",
            PropertyRef::Pbeam(_) => "PBEAM",
            PropertyRef::Pbeaml(_) => "PBEAML",
            PropertyRef::Pbend(_) => "PBEND",
        }
    }
}

/// A material by kind and position in its [`BulkData`] vector.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MaterialRef {
    Mat1(usize),
    Mat8(usize),
    Mat2(usize),
}

impl MaterialRef {
    /// Card name.
    pub fn card(self) -> &'static str {
        match self {
            MaterialRef::Mat1(_) => "MAT1",
            MaterialRef::Mat8(_) => "MAT8",
            MaterialRef::Mat2(_) => "MAT2",
        }
    }
}

/// A cross-referenced element.
#[derive(Debug, Clone, PartialEq)]
pub struct Element {
    pub id: u32,
    pub kind: ElementKind,
    /// Position of the card in its [`BulkData`] vector (`bulk.cquad4[card]`, …).
    pub card: usize,
    /// The property, for elements that have one.
    pub property: Option<PropertyRef>,
    /// Grid indices into [`Model::grids`], in card order (grounded and scalar-point ends of
    /// scalar elements omitted).
    pub nodes: Vec<usize>,
}

/// Kind of a rigid element with what it ties beyond its hub and legs.
#[derive(Debug, Clone, PartialEq)]
pub enum RigidKind {
    /// RBE2: components CM of every leg follow the hub rigidly.
    Rbe2 { cm: Dofs },
    /// RBE3: components REFC of the reference grid are the weighted average of the groups'
    /// motion.
    Rbe3 {
        refc: Dofs,
        groups: Vec<WeightedGroup>,
    },
    /// RSSCON: each shell grid follows the solid edge through it ([`rsscon`]).
    Rsscon { links: Vec<rsscon::RssconLink> },
}

impl RigidKind {
    /// Card name.
    pub fn card(&self) -> &'static str {
        match self {
            RigidKind::Rbe2 { .. } => "RBE2",
            RigidKind::Rbe3 { .. } => "RBE3",
            RigidKind::Rsscon { .. } => "RSSCON",
        }
    }
}

/// One weight group of an RBE3: grids, the components they contribute, their weight.
#[derive(Debug, Clone, PartialEq)]
pub struct WeightedGroup {
    pub weight: f64,
    pub components: Dofs,
    /// Grid indices into [`Model::grids`].
    pub grids: Vec<usize>,
}

/// A cross-referenced rigid element.
#[derive(Debug, Clone, PartialEq)]
pub struct Rigid {
    pub id: u32,
    pub kind: RigidKind,
    /// RBE2: the independent grid GN; RBE3: the reference grid (grid indices).
    pub hub: usize,
    /// RBE2: dependent grids; RBE3: independent grids of all groups (grid indices).
    pub legs: Vec<usize>,
    pub loc: Loc,
}

/// The validated model.
#[derive(Debug, Clone)]
pub struct Model {
    /// The solution sequence requested by `SOL`.
    pub sol: Option<Solution>,
    /// Grids sorted by id.
    pub grids: Vec<GridPoint>,
    /// Grid id → index into [`Model::grids`].
    pub grid_index: ids::IdMap<usize>,
    /// Scalar point ids, sorted ([`scalar_points`]).
    pub scalar_points: Vec<u32>,
    /// Scalar point id → index into [`Model::scalar_points`].
    pub scalar_index: HashMap<u32, usize>,
    /// Coordinate systems by id (basic = 0 included).
    pub coords: HashMap<u32, CoordSystem>,
    /// Elements sorted by id.
    pub elements: Vec<Element>,
    /// Element id → index into [`Model::elements`].
    pub element_index: ids::IdMap<usize>,
    /// Rigid elements sorted by id.
    pub rigids: Vec<Rigid>,
    /// Property id → property (a PSOLID with the id of another property, which its solid
    /// elements name, is in their [`Element::property`] only).
    pub properties: HashMap<u32, PropertyRef>,
    /// Material id → material.
    pub materials: HashMap<u32, MaterialRef>,
    /// The cards themselves (the typed structs the references point into); later modules read
    /// them through the typed data `Model` offers. Shared with the deck, not copied.
    bulk: Arc<BulkData>,
    /// The subcases with the global defaults applied.
    pub subcases: Vec<Subcase>,
    /// Values of the PARAMs paraflex uses.
    pub params: ModelParams,
    /// The multibody mechanism (`SOL FMB`; empty without multibody cards).
    pub mechanism: mechanism::Mechanism,
    /// Accepted input worth mentioning (the deck's warnings first).
    pub warnings: Vec<Warning>,
}

impl Model {
    /// Grid by id.
    pub fn grid(&self, id: u32) -> Option<&GridPoint> {
        self.grid_index.get(&id).and_then(|&i| self.grids.get(i))
    }

    /// Element by id.
    pub fn element(&self, id: u32) -> Option<&Element> {
        self.element_index
            .get(&id)
            .and_then(|&i| self.elements.get(i))
    }

    /// The solid kernel's topology and given nodes of a solid element (blank mid-side grids of
    /// a CHEXA 20 / CPENTA 15 from its card), `None` for other elements.
    pub fn solid_midsides(&self, e: &Element) -> Option<Midsides> {
        let kind = e.kind.solid_kind()?;
        let card = match e.kind {
            ElementKind::Hexa20 => self.bulk.chexa.get(e.card).map(|c| &c.nodes),
            ElementKind::Penta15 => self.bulk.cpenta.get(e.card).map(|c| &c.nodes),
            ElementKind::Tetra10 => self.bulk.ctetra.get(e.card).map(|c| &c.nodes),
            _ => None,
        };
        Some(match card {
            Some(ids) => Midsides::new(kind, &ids.iter().map(|&g| g != 0).collect::<Vec<_>>()),
            None => Midsides::complete(kind),
        })
    }

    /// Basic locations of an element's grids.
    pub fn positions(&self, element: &Element) -> Vec<[f64; 3]> {
        element
            .nodes
            .iter()
            .filter_map(|&i| self.grids.get(i))
            .map(|g| g.xyz)
            .collect()
    }

    /// Mass density of a material (MAT1, MAT8 or MAT2 RHO).
    pub fn rho(&self, mid: u32) -> Option<f64> {
        match self.materials.get(&mid)? {
            MaterialRef::Mat1(i) => self.bulk.mat1.get(*i).map(|m| m.rho),
            MaterialRef::Mat8(i) => self.bulk.mat8.get(*i).map(|m| m.rho),
            MaterialRef::Mat2(i) => self.bulk.mat2.get(*i).map(|m| m.rho),
        }
    }
}

/// Building models from deck text in unit tests of later modules.
#[cfg(test)]
pub(crate) mod testing {
    use std::io::Write;

    use super::Model;
    use crate::deck::Deck;

    /// The model of a deck given as text, read from a temporary `.bdf` file; panics with every
    /// error.
    pub fn model_of_text(text: &str) -> Model {
        let mut file = tempfile::Builder::new()
            .suffix(".bdf")
            .tempfile()
            .expect("temp file");
        file.write_all(text.as_bytes()).expect("write deck");
        let deck = Deck::read(file.path()).unwrap_or_else(|e| panic!("deck: {e}"));
        Model::build(&deck).unwrap_or_else(|e| {
            panic!(
                "model: {:?}",
                e.iter().map(|x| x.to_string()).collect::<Vec<_>>()
            )
        })
    }
}
