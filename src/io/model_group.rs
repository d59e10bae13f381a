//! The `/model` group: grids and element connectivity (DESIGN.md §8).
//!
//! ```text
//! /model                      attrs: title?, deck?, sol? (strings), n_grids, n_elements
//! /model/grid_ids   (n)       u32, sorted
//! /model/xyz        (n×3)     f64, basic system
//! /model/elements/<CARD>/ids          (m)    u32 element ids (repeated per RBE leg)
//! /model/elements/<CARD>/connectivity (m×k)  u32, attr indexing = "0-based rows of /model/grid_ids"
//! /model/elements/<CARD>/pid          (m)    u32 property ids, 0 when none
//! ```

use hdf5_metno as hdf5;

use super::hdf5_file::{IoError, OutputFile, set_attr_i64, set_attr_str, write_rows3, write_u32};
use crate::model::mesh::{ElementBlock, MeshArrays};

/// Value of the `indexing` attribute of every `connectivity` dataset.
pub const CONNECTIVITY_INDEXING: &str = "0-based rows of /model/grid_ids";

/// Descriptive attributes of `/model`; each is written only when present.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct ModelInfo {
    /// `TITLE` from case control.
    pub title: Option<String>,
    /// Path of the input deck, as given on the command line.
    pub deck: Option<String>,
    /// Solution sequence name, e.g. `MODES`, `PROM`.
    pub sol: Option<String>,
}

/// Writes `/model` (see the module documentation) after checking the arrays are consistent.
///
/// Errors name the block and the first inconsistency (lengths, index out of range, duplicate
/// card block); nothing is written in that case beyond groups already created, and the caller
/// discards the uncommitted file anyway.
pub fn write_model(file: &OutputFile, mesh: &MeshArrays, info: &ModelInfo) -> Result<(), IoError> {
    check_mesh(file, mesh)?;
    let model = file.group("model")?;
    for (name, value) in [
        ("title", &info.title),
        ("deck", &info.deck),
        ("sol", &info.sol),
    ] {
        if let Some(value) = value {
            set_attr_str(&model, name, value)?;
        }
    }
    set_attr_i64(&model, "n_grids", mesh.grid_ids.len() as i64)?;
    let n_elements: usize = mesh.blocks.iter().map(|b| b.ids.len()).sum();
    set_attr_i64(&model, "n_elements", n_elements as i64)?;

    write_u32(&model, "grid_ids", &mesh.grid_ids, &[mesh.grid_ids.len()])?;
    write_rows3(&model, "xyz", &mesh.xyz)?;
    file.group("model/elements")?;
    for block in &mesh.blocks {
        write_block(file, block)?;
    }
    Ok(())
}

fn write_block(file: &OutputFile, block: &ElementBlock) -> Result<(), IoError> {
    let group = file.group(&format!("model/elements/{}", block.card))?;
    let m = block.ids.len();
    write_u32(&group, "ids", &block.ids, &[m])?;
    let conn = write_u32(
        &group,
        "connectivity",
        &block.connectivity,
        &[m, block.nodes_per_element],
    )?;
    set_attr_str(&conn, "indexing", CONNECTIVITY_INDEXING)?;
    write_u32(&group, "pid", &block.pids, &[m])?;
    Ok(())
}

/// Checks lengths, index ranges and block names before anything is written.
fn check_mesh(file: &OutputFile, mesh: &MeshArrays) -> Result<(), IoError> {
    let bad = |what: &str, reason: String| Err(IoError::invalid(file.temp_path(), what, reason));
    let n = mesh.grid_ids.len();
    if mesh.xyz.len() != n {
        return bad(
            "/model/xyz",
            format!("{} rows for {n} grid ids", mesh.xyz.len()),
        );
    }
    if let Some(w) = mesh.grid_ids.windows(2).find(|w| w[0] >= w[1]) {
        return bad(
            "/model/grid_ids",
            format!("not sorted increasing at {} then {}", w[0], w[1]),
        );
    }
    let mut seen = std::collections::BTreeSet::new();
    for block in &mesh.blocks {
        let what = format!("/model/elements/{}", block.card);
        let card_ok = !block.card.is_empty()
            && block
                .card
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || c == '_');
        if !card_ok {
            return bad(
                &what,
                "card name must be non-empty ASCII letters/digits/_".into(),
            );
        }
        if !seen.insert(block.card) {
            return bad(&what, "two blocks with the same card name".into());
        }
        let m = block.ids.len();
        if block.pids.len() != m {
            return bad(&what, format!("{} pids for {m} ids", block.pids.len()));
        }
        if block.nodes_per_element == 0 {
            return bad(&what, "nodes_per_element is 0".into());
        }
        if block.connectivity.len() != m * block.nodes_per_element {
            return bad(
                &what,
                format!(
                    "connectivity has {} entries, expected {m} elements × {} nodes",
                    block.connectivity.len(),
                    block.nodes_per_element
                ),
            );
        }
        if let Some(pos) = block.connectivity.iter().position(|&i| i as usize >= n) {
            let row = pos / block.nodes_per_element;
            return bad(
                &what,
                format!(
                    "element {} node {} has grid index {} but there are {n} grids",
                    block.ids[row],
                    pos % block.nodes_per_element + 1,
                    block.connectivity[pos]
                ),
            );
        }
    }
    Ok(())
}

/// Reads `/model/grid_ids` back (used by readers of result files to map rows to grid ids).
pub fn read_grid_ids(file: &hdf5::File) -> Result<Vec<u32>, IoError> {
    file.dataset("model/grid_ids")
        .and_then(|d| d.read_raw::<u32>())
        .map_err(|e| IoError::hdf5(file.filename(), "read /model/grid_ids", e))
}

/// A small mixed mesh shared by the tests of this module tree.
#[cfg(test)]
pub(crate) fn test_mesh() -> MeshArrays {
    // Plate grids 1..7 (two quads and a tria), a unit hexa on 11..18, a CONM2 on 18 and a
    // spring from grid 1 to ground.
    let grid_ids = vec![1, 2, 3, 4, 5, 6, 7, 11, 12, 13, 14, 15, 16, 17, 18];
    let xyz = vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [2.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [1.0, 1.0, 0.0],
        [2.0, 1.0, 0.0],
        [3.0, 0.5, 0.0],
        [0.0, 0.0, 1.0],
        [1.0, 0.0, 1.0],
        [1.0, 1.0, 1.0],
        [0.0, 1.0, 1.0],
        [0.0, 0.0, 2.0],
        [1.0, 0.0, 2.0],
        [1.0, 1.0, 2.0],
        [0.0, 1.0, 2.0],
    ];
    let blocks = vec![
        ElementBlock {
            card: "CQUAD4",
            ids: vec![101, 102],
            pids: vec![1, 1],
            nodes_per_element: 4,
            connectivity: vec![0, 1, 4, 3, 1, 2, 5, 4],
        },
        ElementBlock {
            card: "CTRIA3",
            ids: vec![103],
            pids: vec![1],
            nodes_per_element: 3,
            connectivity: vec![2, 6, 5],
        },
        ElementBlock {
            card: "CHEXA",
            ids: vec![201],
            pids: vec![2],
            nodes_per_element: 8,
            connectivity: (7..15).collect(),
        },
        ElementBlock {
            card: "CONM2",
            ids: vec![301],
            pids: vec![0],
            nodes_per_element: 1,
            connectivity: vec![14],
        },
        ElementBlock {
            card: "CELAS1",
            ids: vec![401],
            pids: vec![4],
            nodes_per_element: 2,
            connectivity: vec![0, 0],
        },
    ];
    MeshArrays {
        grid_ids,
        xyz,
        blocks,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use hdf5::types::VarLenUnicode;

    fn read_str_attr(loc: &hdf5::Location, name: &str) -> String {
        let v: VarLenUnicode = loc.attr(name).unwrap().read_scalar().unwrap();
        v.as_str().to_owned()
    }

    #[test]
    fn model_round_trip() {
        let _guard = crate::io::hdf5_file::hdf5_test_guard();
        let dir = tempfile::tempdir().expect("tempdir");
        let out = dir.path().join("m.h5");
        let mesh = test_mesh();
        let info = ModelInfo {
            title: Some("two quads and friends".into()),
            deck: Some("decks/verify/mixed.bdf".into()),
            sol: None,
        };
        let f = OutputFile::create(&out).expect("create");
        write_model(&f, &mesh, &info).expect("write_model");
        f.commit().expect("commit");

        let h = hdf5::File::open(&out).expect("open");
        let model = h.group("model").unwrap();
        assert_eq!(read_str_attr(&model, "title"), "two quads and friends");
        assert_eq!(read_str_attr(&model, "deck"), "decks/verify/mixed.bdf");
        assert!(model.attr("sol").is_err());
        assert_eq!(
            model
                .attr("n_elements")
                .unwrap()
                .read_scalar::<i64>()
                .unwrap(),
            6
        );
        assert_eq!(read_grid_ids(&h).unwrap(), mesh.grid_ids);
        let xyz = model.dataset("xyz").unwrap();
        assert_eq!(xyz.shape(), [15, 3]);
        assert_eq!(xyz.read_raw::<f64>().unwrap(), mesh.xyz.as_flattened());

        for block in &mesh.blocks {
            let g = h.group(&format!("model/elements/{}", block.card)).unwrap();
            assert_eq!(read_str_attr(&g, "paraflex_version"), crate::VERSION);
            assert_eq!(
                g.dataset("ids").unwrap().read_raw::<u32>().unwrap(),
                block.ids
            );
            assert_eq!(
                g.dataset("pid").unwrap().read_raw::<u32>().unwrap(),
                block.pids
            );
            let conn = g.dataset("connectivity").unwrap();
            assert_eq!(conn.shape(), [block.ids.len(), block.nodes_per_element]);
            assert_eq!(conn.read_raw::<u32>().unwrap(), block.connectivity);
            assert_eq!(read_str_attr(&conn, "indexing"), CONNECTIVITY_INDEXING);
        }
    }

    #[test]
    fn inconsistent_mesh_is_rejected_with_the_element() {
        let _guard = crate::io::hdf5_file::hdf5_test_guard();
        let dir = tempfile::tempdir().expect("tempdir");
        let out = dir.path().join("bad.h5");
        let mut mesh = test_mesh();
        mesh.blocks[0].connectivity[5] = 99;
        let f = OutputFile::create(&out).expect("create");
        let msg = write_model(&f, &mesh, &ModelInfo::default())
            .unwrap_err()
            .to_string();
        assert!(
            msg.contains("CQUAD4") && msg.contains("element 102") && msg.contains("99"),
            "{msg}"
        );
        drop(f);
        assert!(!out.exists());

        let mut mesh = test_mesh();
        mesh.blocks[1].card = "CQUAD4";
        let f = OutputFile::create(&out).expect("create");
        let msg = write_model(&f, &mesh, &ModelInfo::default())
            .unwrap_err()
            .to_string();
        assert!(msg.contains("same card"), "{msg}");
    }

    /// h5py (the users' tool) reads the file, with the repository's venv.
    #[test]
    fn h5py_reads_model() {
        let python = crate::io::hdf5_file::venv_python();
        let _guard = crate::io::hdf5_file::spawn_test_guard();
        let dir = tempfile::tempdir().expect("tempdir");
        let out = dir.path().join("py.h5");
        let f = OutputFile::create(&out).expect("create");
        write_model(&f, &test_mesh(), &ModelInfo::default()).expect("write");
        f.commit().expect("commit");
        let script = "import sys, h5py\n\
            f = h5py.File(sys.argv[1], 'r')\n\
            assert f['model/xyz'].shape == (15, 3)\n\
            c = f['model/elements/CQUAD4/connectivity']\n\
            assert c.shape == (2, 4) and c[1, 2] == 5\n\
            assert f['model'].attrs['schema'] == 1\n\
            v = f['model'].attrs['paraflex_version']\n\
            assert (v.decode() if isinstance(v, bytes) else v) == sys.argv[2]\n\
            assert f['model/grid_ids'][7] == 11\n";
        let status = std::process::Command::new(python)
            .args(["-c", script])
            .arg(&out)
            .arg(crate::VERSION)
            .status()
            .expect("run python");
        assert!(status.success());
    }
}
