//! The mesh part of the XDMF files: `Topology`, `Geometry` and the element/property id cell
//! attributes of `/model`.
//!
//! A mesh with one drawable element block refers to that block's connectivity and ids in the
//! HDF5 file. A mesh with several blocks becomes one `Mixed` topology, the only form readers
//! of a single uniform grid (meshio) accept; its cell list interleaves a type code with the
//! nodes of each element, a layout `/model` does not hold, so it and the id attributes are
//! written inline. Node orderings: `/model` connectivity is in Nastran grid order, which equals
//! the XDMF (= VTK) order for every supported topology:
//!
//! | card | XDMF topology (mixed code) | note |
//! |---|---|---|
//! | CQUAD4, CQUADR, CSHEAR | Quadrilateral (5) | G1..G4 |
//! | CTRIA3, CTRIAR | Triangle (4) | G1..G3 |
//! | CQUAD8 | Quadrilateral_8 (37) | corners, then mid-sides of edges 1-2, 2-3, 3-4, 4-1, as VTK_QUADRATIC_QUAD |
//! | CTRIA6 | Triangle_6 (36) | corners, then mid-sides of edges 1-2, 2-3, 3-1, as VTK_QUADRATIC_TRIANGLE |
//! | CHEXA (8) | Hexahedron (9) | G1..G4 bottom, G5..G8 top, as VTK_HEXAHEDRON |
//! | CPENTA (6) | Wedge (8) | G1..G3, G4..G6 with G4 over G1, as VTK_WEDGE (a deck whose first face points inward renders the same; only the sign of the cell volume differs) |
//! | CTETRA (4) | Tetrahedron (6) | |
//! | CPYRAM (5) | Pyramid (7) | G1..G4 the base, G5 the apex, as VTK_PYRAMID |
//! | CHEXA20, CPENTA15 | Hexahedron (9), Wedge (8) | the corner grids only: `/model` holds their corner cells (a blank mid-side grid has no grid to draw); results at the mid-side grids are in the grid datasets |
//! | CTETRA10 | Tetrahedron_10 (38) | Nastran G5..G10 = edges 1-2, 2-3, 3-1, 1-4, 2-4, 3-4; VTK_QUADRATIC_TETRA uses edges (0,1),(1,2),(2,0),(0,3),(1,3),(2,3): identical |
//! | CROD, CONROD, CTUBE, CBAR, CBEAM, CBEND (drawn as its chord), CELAS1, CELAS2, RBE2, RBE3, other 2-node cards | Polyline, 2 nodes (2, then the node count 2) | a grounded spring repeats its grid (zero-length line); a beam is drawn between its grids (offsets are not drawn) |
//! | CONM2, other 1-node cards | Polyvertex; in a mixed topology a Polyline from the grid to itself (2, 2, p, p) | see below |
//!
//! Blocks with another card and node count, or with no elements, are left out and reported.
//!
//! meshio 5 reads a single CQUAD8, CTRIA6 or CTETRA10 block, but its `Mixed` reader knows no
//! codes 36–38 (ParaView reads both).
//!
//! In a `Mixed` list XDMF puts the node count after the code of a polyvertex, as of a
//! polyline (ParaView reads it so), while meshio reads a polyvertex without one; a one-node
//! element is therefore written as a zero-length polyline, which both read alike.

use super::xml::{Number, attribute, hdf_item, inline_item};
use crate::model::mesh::{ElementBlock, MeshArrays};

/// XDMF topology of one block.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Topology {
    Quadrilateral,
    Triangle,
    Quadrilateral8,
    Triangle6,
    Hexahedron,
    Wedge,
    Pyramid,
    Tetrahedron,
    Tetrahedron10,
    Polyline2,
    Polyvertex,
}

impl Topology {
    /// Topology for a card with `k` nodes per element, or `None` when there is none.
    fn for_block(card: &str, k: usize) -> Option<Self> {
        let t = match (card, k) {
            ("CQUAD4" | "CQUADR" | "CSHEAR" | "CQUAD8_CORNERS", 4) => Topology::Quadrilateral,
            ("CTRIA3" | "CTRIAR" | "CTRIA6_CORNERS", 3) => Topology::Triangle,
            ("CQUAD8", 8) => Topology::Quadrilateral8,
            ("CTRIA6", 6) => Topology::Triangle6,
            ("CHEXA" | "CHEXA20", 8) => Topology::Hexahedron,
            ("CPENTA" | "CPENTA15", 6) => Topology::Wedge,
            ("CPYRAM", 5) => Topology::Pyramid,
            ("CTETRA" | "CTETRA10_CORNERS", 4) => Topology::Tetrahedron,
            ("CTETRA10" | "CTETRA", 10) => Topology::Tetrahedron10,
            (_, 2) => Topology::Polyline2,
            (_, 1) => Topology::Polyvertex,
            _ => return None,
        };
        Some(t)
    }

    /// `TopologyType` plus, for poly types, `NodesPerElement`.
    fn xml_attrs(self) -> &'static str {
        match self {
            Topology::Quadrilateral => r#"TopologyType="Quadrilateral""#,
            Topology::Triangle => r#"TopologyType="Triangle""#,
            Topology::Quadrilateral8 => r#"TopologyType="Quadrilateral_8""#,
            Topology::Triangle6 => r#"TopologyType="Triangle_6""#,
            Topology::Hexahedron => r#"TopologyType="Hexahedron""#,
            Topology::Wedge => r#"TopologyType="Wedge""#,
            Topology::Pyramid => r#"TopologyType="Pyramid""#,
            Topology::Tetrahedron => r#"TopologyType="Tetrahedron""#,
            Topology::Tetrahedron10 => r#"TopologyType="Tetrahedron_10""#,
            Topology::Polyline2 => r#"TopologyType="Polyline" NodesPerElement="2""#,
            Topology::Polyvertex => r#"TopologyType="Polyvertex" NodesPerElement="1""#,
        }
    }

    /// Appends an element's entry to a `Mixed` cell list: the type code, for a polyline its
    /// node count, then the nodes (a one-node element as a zero-length polyline).
    fn push_mixed(self, element: &[u32], cells: &mut Vec<u32>) {
        let code = match self {
            Topology::Polyvertex => {
                cells.extend_from_slice(&[2, 2, element[0], element[0]]);
                return;
            }
            Topology::Polyline2 => {
                cells.extend_from_slice(&[2, 2]);
                cells.extend_from_slice(element);
                return;
            }
            Topology::Triangle => 4,
            Topology::Quadrilateral => 5,
            Topology::Tetrahedron => 6,
            Topology::Wedge => 8,
            Topology::Pyramid => 7,
            Topology::Hexahedron => 9,
            Topology::Tetrahedron10 => 38,
            Topology::Triangle6 => 36,
            Topology::Quadrilateral8 => 37,
        };
        cells.push(code);
        cells.extend_from_slice(element);
    }
}

/// The mesh elements shared by every grid of the XDMF files.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(super) struct MeshXml {
    /// `Topology` and `Geometry` elements.
    pub shape: String,
    /// `element_id` and `property_id` cell attributes.
    pub ids: String,
    /// The card of the only drawn block, when there is exactly one (its cell data can then be
    /// referred to directly).
    pub single_block: Option<&'static str>,
    /// Blocks left out, with the reason.
    pub skipped: Vec<String>,
}

/// The mesh of `mesh` with heavy data in `h5` (an escaped file name).
pub(super) fn mesh_xml(h5: &str, mesh: &MeshArrays) -> MeshXml {
    let mut skipped = Vec::new();
    let mut drawn: Vec<(&ElementBlock, Topology)> = Vec::new();
    for block in &mesh.blocks {
        let k = block.nodes_per_element;
        match Topology::for_block(block.card, k) {
            None => skipped.push(format!(
                "{}: no XDMF topology for {k} nodes per element",
                block.card
            )),
            Some(_) if block.ids.is_empty() => {
                skipped.push(format!("{}: no elements", block.card));
            }
            Some(t) => drawn.push((block, t)),
        }
    }
    let n = mesh.grid_ids.len();
    let geometry = format!(
        "<Geometry GeometryType=\"XYZ\">{}</Geometry>\n",
        hdf_item(h5, "/model/xyz", &[n, 3], Number::Float8)
    );
    let (topology, ids, single_block) = match drawn.as_slice() {
        [(block, topology)] => {
            let (topology, ids) = block_by_reference(h5, block, *topology);
            (topology, ids, Some(block.card))
        }
        _ => {
            let (topology, ids) = mixed_inline(&drawn);
            (topology, ids, None)
        }
    };
    MeshXml {
        shape: topology + &geometry,
        ids,
        single_block,
        skipped,
    }
}

/// Topology and id attributes of a one-block mesh, referring to `/model/elements/<CARD>`.
fn block_by_reference(h5: &str, block: &ElementBlock, topology: Topology) -> (String, String) {
    let m = block.ids.len();
    let k = block.nodes_per_element;
    let heavy = |what: &str| format!("/model/elements/{}/{what}", block.card);
    let topology = format!(
        "<Topology {} NumberOfElements=\"{m}\">{}</Topology>\n",
        topology.xml_attrs(),
        hdf_item(h5, &heavy("connectivity"), &[m, k], Number::UInt4)
    );
    let ids = [("element_id", "ids"), ("property_id", "pid")]
        .iter()
        .map(|(name, dataset)| {
            let item = hdf_item(h5, &heavy(dataset), &[m], Number::UInt4);
            attribute(name, "Scalar", "Cell", &item)
        })
        .collect();
    (topology, ids)
}

/// `Mixed` topology and id attributes of the drawn blocks, inline.
fn mixed_inline(drawn: &[(&ElementBlock, Topology)]) -> (String, String) {
    let mut cells = Vec::new();
    let mut element_ids = Vec::new();
    let mut property_ids = Vec::new();
    for (block, topology) in drawn {
        for element in block.connectivity.chunks(block.nodes_per_element) {
            topology.push_mixed(element, &mut cells);
        }
        element_ids.extend_from_slice(&block.ids);
        property_ids.extend_from_slice(&block.pids);
    }
    let m = element_ids.len();
    let topology = format!(
        "<Topology TopologyType=\"Mixed\" NumberOfElements=\"{m}\">{}</Topology>\n",
        inline_item(&cells, &[cells.len()])
    );
    let ids = attribute(
        "element_id",
        "Scalar",
        "Cell",
        &inline_item(&element_ids, &[m]),
    ) + &attribute(
        "property_id",
        "Scalar",
        "Cell",
        &inline_item(&property_ids, &[m]),
    );
    (topology, ids)
}
