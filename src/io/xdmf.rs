//! XDMF 3 files next to a paraflex HDF5 file, so ParaView and meshio open the mesh and the
//! results without a copy of the data.
//!
//! Every file refers to `<out>.h5` by file name only (relative), so the set can be moved
//! together. [`write_xdmf`] reads the written file back (its `/results` groups) and writes:
//!
//! ```text
//! <out>.xdmf                    Domain / Grid "model" (Uniform): the mesh, Cell attributes
//!                               element_id, property_id; per static subcase the Node attribute
//!                               displacement_<subcase> (n × 6: T1 T2 T3 R1 R2 R3) and, when
//!                               drawable, strain_<dataset>, force_forces and
//!                               stress_<dataset> (Cell; not the corner or ply results)
//! <out>_<subcase>_statics.xdmf  one step (Time 0)                  \  Domain / Grid (Collection,
//! <out>_<subcase>_modes.xdmf    a step per mode, Time = mode 1, 2, …  >  Temporal) / Grid per step
//! <out>_<subcase>_transient.xdmf a step per output time, Time = t  /   (Uniform)
//! ```
//!
//! A step holds the Node vectors `displacement` (T1–T3) and `rotation` (R1–R3), hyperslab
//! references (`out.h5:/results/1/modal/shapes|start:stride:count:shape`) selecting the
//! step's rows and columns of the stored array (statics also the strains). A mode's time value is its number, not its frequency (two equal frequencies would
//! be one time step); the step's grid is named `mode <i>: <f> Hz`. The first step carries the
//! `Topology` and `Geometry`, later steps include them with `xi:include` (the layout meshio's
//! time-series writer uses).
//!
//! Readers: ParaView's XDMF3 reader opens every file ("Xdmf3ReaderS"; warp by `displacement`
//! and play the time steps). `meshio.read("<out>.xdmf")` reads the mesh and its attributes;
//! meshio's `TimeSeriesReader` reads the mesh and the number of steps of a series but not the
//! step data (meshio has no hyperslab support): read those arrays from the HDF5 file.
//!
//! Left out and reported in [`XdmfWritten::skipped`]: element blocks without an XDMF topology
//! (see [`mesh`]), fields of a SET of grids (they do not cover the mesh), complex FRF
//! displacements (a compound type XDMF cannot address), strains, element forces and stresses on
//! a mesh of several element blocks or of part of a block.

mod fields;
mod mesh;
mod xml;

use std::path::{Path, PathBuf};

use super::hdf5_file::{IoError, write_file_atomically};
use crate::model::mesh::MeshArrays;
use fields::{Fields, Series, result_fields};
use mesh::{MeshXml, mesh_xml};

/// Result of [`write_xdmf`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct XdmfWritten {
    /// Path of `<out>.xdmf`.
    pub path: PathBuf,
    /// Paths of the time-series files, in `/results` order.
    pub series: Vec<PathBuf>,
    /// Blocks and fields left out, with the reason (`"CQUAD8: no XDMF topology for 8 nodes
    /// per element"`).
    pub skipped: Vec<String>,
}

/// Path of the XDMF file for an HDF5 output: same name with extension `.xdmf`.
pub fn xdmf_path_for(h5_path: &Path) -> PathBuf {
    h5_path.with_extension("xdmf")
}

/// Writes `<h5 stem>.xdmf` and the time-series files next to `h5_path` (each under a temporary
/// name, then renamed) describing the `/model` group written from `mesh` and the results the
/// file holds.
pub fn write_xdmf(h5_path: &Path, mesh: &MeshArrays) -> Result<XdmfWritten, IoError> {
    let h5_name = h5_path
        .file_name()
        .and_then(|n| n.to_str())
        .ok_or_else(|| {
            IoError::invalid(h5_path, "XDMF file", "HDF5 file name is not valid UTF-8")
        })?;
    let h5 = xml::escape(h5_name);
    let summary = super::describe(h5_path)?;
    let mesh_xml = mesh_xml(&h5, mesh);
    let fields = result_fields(h5_path, &summary, mesh, &h5, mesh_xml.single_block)?;
    let mut series = Vec::new();
    for s in &fields.series {
        let path = series_path_for(h5_path, &s.subcase, s.kind);
        write_file_atomically(&path, series_text(&mesh_xml, s).as_bytes())?;
        series.push(path);
    }
    let path = xdmf_path_for(h5_path);
    write_file_atomically(&path, model_text(&mesh_xml, &fields).as_bytes())?;
    let mut skipped = mesh_xml.skipped;
    skipped.extend(fields.skipped);
    Ok(XdmfWritten {
        path,
        series,
        skipped,
    })
}

/// `<out>_<subcase>_<kind>.xdmf` next to `h5_path`.
fn series_path_for(h5_path: &Path, subcase: &str, kind: &str) -> PathBuf {
    let stem = h5_path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    h5_path.with_file_name(format!("{stem}_{subcase}_{kind}.xdmf"))
}

const HEADER: &str = "<?xml version=\"1.0\" encoding=\"utf-8\"?>\n\
    <Xdmf Version=\"3.0\" xmlns:xi=\"http://www.w3.org/2001/XInclude\">\n<Domain>\n";
const FOOTER: &str = "</Domain>\n</Xdmf>\n";

/// `<out>.xdmf`: one uniform grid with the mesh and the whole-dataset attributes.
fn model_text(mesh: &MeshXml, fields: &Fields) -> String {
    format!(
        "{HEADER}<Grid Name=\"model\" GridType=\"Uniform\">\n{}{}{}</Grid>\n{FOOTER}",
        mesh.shape, mesh.ids, fields.model_attributes
    )
}

/// A time-series file: a temporal collection, the mesh in the first step.
fn series_text(mesh: &MeshXml, series: &Series) -> String {
    let mut s = format!(
        "{HEADER}<Grid Name=\"{} {}\" GridType=\"Collection\" CollectionType=\"Temporal\">\n",
        series.kind,
        xml::escape(&series.subcase)
    );
    for (i, step) in series.steps.iter().enumerate() {
        let shape = if i == 0 {
            mesh.shape.clone()
        } else {
            "<xi:include xpointer=\"xpointer(/Xdmf/Domain/Grid/Grid[1]/*[self::Topology or \
             self::Geometry])\"/>\n"
                .to_owned()
        };
        s += &format!(
            "<Grid Name=\"{}\" GridType=\"Uniform\">\n{shape}<Time Value=\"{}\"/>\n{}</Grid>\n",
            xml::escape(&step.name),
            step.time,
            step.attributes
        );
    }
    s + "</Grid>\n" + FOOTER
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::model_group::test_mesh;
    use crate::io::{ModelInfo, OutputFile, write_f64, write_model};

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

    fn one_block_mesh() -> MeshArrays {
        let mut mesh = test_mesh();
        mesh.blocks.truncate(1);
        mesh
    }

    #[test]
    fn a_one_block_mesh_refers_to_its_datasets() {
        let m = mesh_xml("run.h5", &one_block_mesh());
        assert_eq!(m.single_block, Some("CQUAD4"));
        assert!(m.skipped.is_empty(), "{:?}", m.skipped);
        assert!(m.shape.contains(
            "<Topology TopologyType=\"Quadrilateral\" NumberOfElements=\"2\"><DataItem \
             Dimensions=\"2 4\" NumberType=\"UInt\" Precision=\"4\" \
             Format=\"HDF\">run.h5:/model/elements/CQUAD4/connectivity</DataItem>"
        ));
        assert!(m.shape.contains("Dimensions=\"15 3\""));
        assert!(m.ids.contains("run.h5:/model/elements/CQUAD4/pid"));
    }

    /// Type code, node count of a polyline, then the nodes, for each element in block order.
    #[test]
    fn several_blocks_make_one_mixed_topology() {
        let m = mesh_xml("run.h5", &test_mesh());
        assert_eq!(m.single_block, None);
        let cells = "5 0 1 4 3 5 1 2 5 4 4 2 6 5 9 7 8 9 10 11 12 13 14 2 2 14 14 2 2 0 0";
        let length = cells.split(' ').count();
        assert!(
            m.shape.contains(&format!(
                "<Topology TopologyType=\"Mixed\" NumberOfElements=\"6\"><DataItem \
                 Dimensions=\"{length}\" NumberType=\"UInt\" Precision=\"4\" \
                 Format=\"XML\">{cells}</DataItem>"
            )),
            "{}",
            m.shape
        );
        assert!(m.ids.contains(">101 102 103 201 301 401</DataItem>"));
        assert!(m.ids.contains(">1 1 1 2 0 4</DataItem>"));
    }

    #[test]
    fn unknown_and_empty_blocks_are_reported() {
        let mut mesh = test_mesh();
        mesh.blocks[0].card = "CQUAD4";
        mesh.blocks[0].nodes_per_element = 9;
        mesh.blocks[1].ids.clear();
        let m = mesh_xml("a&amp;b.h5", &mesh);
        assert!(m.shape.contains("a&amp;b.h5:/model/xyz"));
        assert_eq!(m.skipped.len(), 2, "{:?}", m.skipped);
        assert!(m.skipped[0].starts_with("CQUAD4") && m.skipped[1].starts_with("CTRIA3"));
    }

    /// Writes a model with a static displacement and two mode shapes, then the XDMF files;
    /// parses them with Python's xml.etree and checks every heavy-data path exists in the HDF5
    /// file with the declared dimensions (h5py, from the repository's venv).
    #[test]
    fn xdmf_files_next_to_h5_match_its_datasets() {
        let _guard = crate::io::hdf5_file::spawn_test_guard();
        let dir = tempfile::tempdir().expect("tempdir");
        let h5 = dir.path().join("pair.h5");
        let mesh = one_block_mesh();
        let n = mesh.grid_ids.len();
        let f = OutputFile::create(&h5).expect("create");
        write_model(&f, &mesh, &ModelInfo::default()).expect("model");
        let statics = f.group("/results/1/statics").expect("statics");
        write_f64(&statics, "displacement", &vec![0.5; n * 6], &[n, 6]).expect("u");
        let modal = f.group("/results/2/modal").expect("modal");
        write_f64(&modal, "frequency_hz", &[1.5, 2.5], &[2]).expect("f");
        write_f64(&modal, "shapes", &vec![1.0; 2 * n * 6], &[2, n, 6]).expect("shapes");
        f.commit().expect("commit");
        let written = write_xdmf(&h5, &mesh).expect("xdmf");
        assert_eq!(written.path, dir.path().join("pair.xdmf"));
        assert!(written.skipped.is_empty(), "{:?}", written.skipped);
        assert_eq!(
            written.series,
            [
                dir.path().join("pair_1_statics.xdmf"),
                dir.path().join("pair_2_modes.xdmf")
            ]
        );
        let mut names: Vec<_> = std::fs::read_dir(dir.path())
            .unwrap()
            .map(|e| e.unwrap().file_name().into_string().unwrap())
            .collect();
        names.sort();
        assert_eq!(
            names,
            [
                "pair.h5",
                "pair.xdmf",
                "pair_1_statics.xdmf",
                "pair_2_modes.xdmf"
            ],
            "no temporary file left"
        );
        let modes = std::fs::read_to_string(&written.series[1]).unwrap();
        check_well_formed(&modes);
        assert!(modes.contains("<Grid Name=\"mode 2: 2.5 Hz\" GridType=\"Uniform\">"));
        assert!(modes.contains("<Time Value=\"2\"/>"));

        let python = crate::io::hdf5_file::venv_python();
        let script = "import sys, os, h5py, xml.etree.ElementTree as ET\n\
            n = 0\n\
            for x in sys.argv[1:]:\n\
            \x20   for d in ET.parse(x).getroot().iter('DataItem'):\n\
            \x20       if d.get('Format') != 'HDF':\n\
            \x20           continue\n\
            \x20       reference, *slab = d.text.strip().split('|')\n\
            \x20       fname, path = reference.split(':')\n\
            \x20       with h5py.File(os.path.join(os.path.dirname(x), fname), 'r') as f:\n\
            \x20           dims = slab[0].split(':')[3] if slab else d.get('Dimensions')\n\
            \x20           dims = tuple(int(v) for v in dims.split())\n\
            \x20           assert f[path].shape == dims, (path, f[path].shape, dims)\n\
            \x20       n += 1\n\
            assert n == 5 + 4 + 6, n\n";
        let status = std::process::Command::new(python)
            .args(["-c", script])
            .arg(&written.path)
            .args(&written.series)
            .status()
            .expect("run python");
        assert!(status.success());
    }
}
