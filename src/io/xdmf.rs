//! XDMF 3 description of `/model` so ParaView opens the mesh of a paraflex HDF5 file.
//!
//! `<out>.xdmf` sits next to `<out>.h5` and refers to it by file name only (relative), so the
//! pair can be moved together. Layout:
//!
//! ```text
//! Domain
//!   Grid "model" (Collection, Spatial)
//!     Grid "<CARD>" (Uniform), one per element block
//!       Topology  <type>, DataItem  file.h5:/model/elements/<CARD>/connectivity (m×k, UInt32)
//!       Geometry  XYZ,    DataItem "XYZ" file.h5:/model/xyz (n×3, Float64)
//!       Attribute element_id  (Cell) file.h5:/model/elements/<CARD>/ids
//!       Attribute property_id (Cell) file.h5:/model/elements/<CARD>/pid
//! ```
//!
//! Every block's Geometry names the same heavy dataset `/model/xyz`. It is written out in each
//! Grid rather than pulled in with `xi:include`: XInclude is textual, so readers parse the same
//! DataItem either way, and the inline form works in every XDMF reader (ParaView's XDMF2 and
//! XDMF3 readers, meshio).
//!
//! Node orderings: `/model` connectivity is in Nastran grid order, which equals the XDMF (= VTK)
//! order for every supported topology, so no reordered copy is needed:
//!
//! | card | XDMF topology | note |
//! |---|---|---|
//! | CQUAD4 | Quadrilateral | G1..G4 |
//! | CTRIA3 | Triangle | G1..G3 |
//! | CHEXA (8) | Hexahedron | G1..G4 bottom, G5..G8 top, as VTK_HEXAHEDRON |
//! | CPENTA (6) | Wedge | G1..G3, G4..G6 with G4 over G1, as VTK_WEDGE (a deck whose first face points inward renders the same; only the sign of the cell volume differs) |
//! | CTETRA (4) | Tetrahedron | |
//! | CTETRA10 | Tetrahedron_10 | Nastran G5..G10 = edges 1-2, 2-3, 3-1, 1-4, 2-4, 3-4; VTK_QUADRATIC_TETRA (which ParaView maps Tetrahedron_10 to) uses edges (0,1),(1,2),(2,0),(0,3),(1,3),(2,3): identical |
//! | CELAS1, CELAS2, RBE2, RBE3, other 2-node cards | Polyline, 2 nodes | a grounded spring repeats its grid (zero-length line) |
//! | CONM2, other 1-node cards | Polyvertex | |
//!
//! Blocks with another card and node count, or with no elements, are left out of the XDMF and
//! reported in [`XdmfWritten::skipped`].

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use super::hdf5_file::{IoError, write_file_atomically};
use crate::model::mesh::{ElementBlock, MeshArrays};

/// Result of [`write_xdmf`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct XdmfWritten {
    /// Path of the `.xdmf` file.
    pub path: PathBuf,
    /// Blocks left out, with the reason (`"CQUAD8: no XDMF topology for 8 nodes"`).
    pub skipped: Vec<String>,
}

/// XDMF topology of one block.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Topology {
    Quadrilateral,
    Triangle,
    Hexahedron,
    Wedge,
    Tetrahedron,
    Tetrahedron10,
    Polyline2,
    Polyvertex,
}

impl Topology {
    /// Topology for a card with `k` nodes per element, or `None` when there is none.
    fn for_block(card: &str, k: usize) -> Option<Self> {
        let t = match (card, k) {
            ("CQUAD4", 4) => Topology::Quadrilateral,
            ("CTRIA3", 3) => Topology::Triangle,
            ("CHEXA", 8) => Topology::Hexahedron,
            ("CPENTA", 6) => Topology::Wedge,
            ("CTETRA", 4) => Topology::Tetrahedron,
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
            Topology::Hexahedron => r#"TopologyType="Hexahedron""#,
            Topology::Wedge => r#"TopologyType="Wedge""#,
            Topology::Tetrahedron => r#"TopologyType="Tetrahedron""#,
            Topology::Tetrahedron10 => r#"TopologyType="Tetrahedron_10""#,
            Topology::Polyline2 => r#"TopologyType="Polyline" NodesPerElement="2""#,
            Topology::Polyvertex => r#"TopologyType="Polyvertex" NodesPerElement="1""#,
        }
    }
}

/// Path of the XDMF file for an HDF5 output: same name with extension `.xdmf`.
pub fn xdmf_path_for(h5_path: &Path) -> PathBuf {
    h5_path.with_extension("xdmf")
}

/// Writes `<h5 stem>.xdmf` next to `h5_path` (temporary name, then rename) describing the
/// `/model` group that [`write_model`](super::write_model) wrote from the same `mesh`.
pub fn write_xdmf(h5_path: &Path, mesh: &MeshArrays) -> Result<XdmfWritten, IoError> {
    let h5_name = h5_path
        .file_name()
        .and_then(|n| n.to_str())
        .ok_or_else(|| {
            IoError::invalid(h5_path, "XDMF file", "HDF5 file name is not valid UTF-8")
        })?;
    let (xml, skipped) = xdmf_text(h5_name, mesh);
    let path = xdmf_path_for(h5_path);
    write_file_atomically(&path, xml.as_bytes())?;
    Ok(XdmfWritten { path, skipped })
}

/// The XDMF document for `mesh` with heavy data in `h5_name`, and the skipped blocks.
pub fn xdmf_text(h5_name: &str, mesh: &MeshArrays) -> (String, Vec<String>) {
    let h5 = xml_escape(h5_name);
    let n = mesh.grid_ids.len();
    let mut skipped = Vec::new();
    let mut s = String::new();
    s.push_str("<?xml version=\"1.0\" encoding=\"utf-8\"?>\n");
    s.push_str("<Xdmf Version=\"3.0\" xmlns:xi=\"http://www.w3.org/2001/XInclude\">\n");
    s.push_str("  <Domain>\n");
    s.push_str("    <Grid Name=\"model\" GridType=\"Collection\" CollectionType=\"Spatial\">\n");
    for block in &mesh.blocks {
        let k = block.nodes_per_element;
        let Some(topology) = Topology::for_block(block.card, k) else {
            skipped.push(format!(
                "{}: no XDMF topology for {k} nodes per element",
                block.card
            ));
            continue;
        };
        if block.ids.is_empty() {
            skipped.push(format!("{}: no elements", block.card));
            continue;
        }
        // Writing to a String cannot fail.
        let _ = write_grid(&mut s, &h5, n, block, topology);
    }
    s.push_str("    </Grid>\n  </Domain>\n</Xdmf>\n");
    (s, skipped)
}

fn write_grid(
    s: &mut String,
    h5: &str,
    n: usize,
    block: &ElementBlock,
    topology: Topology,
) -> std::fmt::Result {
    let card = xml_escape(block.card);
    let m = block.ids.len();
    let k = block.nodes_per_element;
    let heavy = |what: &str| format!("{h5}:/model/elements/{card}/{what}");
    writeln!(s, "      <Grid Name=\"{card}\" GridType=\"Uniform\">")?;
    writeln!(
        s,
        "        <Topology {} NumberOfElements=\"{m}\">",
        topology.xml_attrs()
    )?;
    writeln!(
        s,
        "          <DataItem Dimensions=\"{m} {k}\" NumberType=\"UInt\" Precision=\"4\" \
         Format=\"HDF\">{}</DataItem>",
        heavy("connectivity")
    )?;
    writeln!(s, "        </Topology>")?;
    writeln!(s, "        <Geometry GeometryType=\"XYZ\">")?;
    writeln!(
        s,
        "          <DataItem Name=\"XYZ\" Dimensions=\"{n} 3\" NumberType=\"Float\" \
         Precision=\"8\" Format=\"HDF\">{h5}:/model/xyz</DataItem>"
    )?;
    writeln!(s, "        </Geometry>")?;
    for (name, dataset) in [("element_id", "ids"), ("property_id", "pid")] {
        writeln!(
            s,
            "        <Attribute Name=\"{name}\" AttributeType=\"Scalar\" Center=\"Cell\">"
        )?;
        writeln!(
            s,
            "          <DataItem Dimensions=\"{m}\" NumberType=\"UInt\" Precision=\"4\" \
             Format=\"HDF\">{}</DataItem>",
            heavy(dataset)
        )?;
        writeln!(s, "        </Attribute>")?;
    }
    writeln!(s, "      </Grid>")
}

/// Escapes the five XML special characters.
fn xml_escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            c => out.push(c),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::model_group::test_mesh;
    use crate::io::{ModelInfo, OutputFile, write_model};

    /// Minimal well-formedness check: tags nest and close, attribute quotes balance.
    fn check_well_formed(xml: &str) {
        let mut stack: Vec<&str> = Vec::new();
        let mut rest = xml;
        while let Some(start) = rest.find('<') {
            let end = rest[start..].find('>').expect("unclosed tag") + start;
            let tag = &rest[start + 1..end];
            assert_eq!(
                tag.matches('"').count() % 2,
                0,
                "unbalanced quotes in <{tag}>"
            );
            if tag.starts_with('?') || tag.ends_with('/') {
                // declaration or empty element
            } else if let Some(name) = tag.strip_prefix('/') {
                assert_eq!(stack.pop(), Some(name), "mismatched </{name}>");
            } else {
                stack.push(tag.split_whitespace().next().expect("tag name"));
            }
            rest = &rest[end + 1..];
        }
        assert!(stack.is_empty(), "unclosed elements {stack:?}");
    }

    #[test]
    fn one_grid_per_block_with_relative_heavy_data() {
        let (xml, skipped) = xdmf_text("run.h5", &test_mesh());
        check_well_formed(&xml);
        assert!(skipped.is_empty(), "{skipped:?}");
        assert_eq!(xml.matches("GridType=\"Uniform\"").count(), 5);
        assert_eq!(xml.matches("run.h5:/model/xyz").count(), 5);
        assert!(xml.contains(
            "TopologyType=\"Quadrilateral\" NumberOfElements=\"2\">\n          \
             <DataItem Dimensions=\"2 4\" NumberType=\"UInt\" Precision=\"4\" \
             Format=\"HDF\">run.h5:/model/elements/CQUAD4/connectivity</DataItem>"
        ));
        assert!(xml.contains("TopologyType=\"Hexahedron\" NumberOfElements=\"1\""));
        assert!(
            xml.contains(
                "TopologyType=\"Polyvertex\" NodesPerElement=\"1\" NumberOfElements=\"1\""
            )
        );
        assert!(
            xml.contains("TopologyType=\"Polyline\" NodesPerElement=\"2\" NumberOfElements=\"1\"")
        );
        assert!(xml.contains("Dimensions=\"15 3\""));
        assert!(xml.contains("run.h5:/model/elements/CTRIA3/ids"));
        assert!(!xml.contains("/tmp"));
    }

    #[test]
    fn unknown_and_empty_blocks_are_reported() {
        let mut mesh = test_mesh();
        mesh.blocks[0].card = "CQUAD8";
        mesh.blocks[0].nodes_per_element = 8;
        mesh.blocks[1].ids.clear();
        let (xml, skipped) = xdmf_text("a&b.h5", &mesh);
        check_well_formed(&xml);
        assert!(xml.contains("a&amp;b.h5:/model/xyz"));
        assert_eq!(skipped.len(), 2, "{skipped:?}");
        assert!(skipped[0].starts_with("CQUAD8") && skipped[1].starts_with("CTRIA3"));
    }

    /// Writes the .h5/.xdmf pair; parses the XDMF with Python's xml.etree and checks every
    /// heavy-data path exists in the HDF5 file with the declared dimensions (h5py, from the
    /// repository's venv).
    #[test]
    fn xdmf_next_to_h5_matches_its_datasets() {
        let _guard = crate::io::hdf5_file::spawn_test_guard();
        let dir = tempfile::tempdir().expect("tempdir");
        let h5 = dir.path().join("pair.h5");
        let mesh = test_mesh();
        let f = OutputFile::create(&h5).expect("create");
        write_model(&f, &mesh, &ModelInfo::default()).expect("model");
        f.commit().expect("commit");
        let written = write_xdmf(&h5, &mesh).expect("xdmf");
        assert_eq!(written.path, dir.path().join("pair.xdmf"));
        let names: Vec<_> = std::fs::read_dir(dir.path())
            .unwrap()
            .map(|e| e.unwrap().file_name().into_string().unwrap())
            .collect();
        assert_eq!(names.len(), 2, "no temporary file left: {names:?}");
        check_well_formed(&std::fs::read_to_string(&written.path).unwrap());

        let python = crate::io::hdf5_file::venv_python();
        let script = "import sys, os, h5py, xml.etree.ElementTree as ET\n\
            root = ET.parse(sys.argv[1]).getroot()\n\
            n = 0\n\
            for d in root.iter('DataItem'):\n\
            \x20   fname, path = d.text.strip().split(':')\n\
            \x20   with h5py.File(os.path.join(os.path.dirname(sys.argv[1]), fname), 'r') as f:\n\
            \x20       dims = tuple(int(x) for x in d.get('Dimensions').split())\n\
            \x20       assert f[path].shape == dims, (path, f[path].shape, dims)\n\
            \x20   n += 1\n\
            assert n == 5 * 4, n\n";
        let status = std::process::Command::new(python)
            .args(["-c", script])
            .arg(&written.path)
            .status()
            .expect("run python");
        assert!(status.success());
    }
}
