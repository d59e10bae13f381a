//! The result fields of a written HDF5 file that the XDMF files draw, found by reading its
//! `/results` groups back.
//!
//! Node fields (rows in `/model/grid_ids` order, columns T1 T2 T3 R1 R2 R3) become two vector
//! attributes, `displacement` (T1–T3) and `rotation` (R1–R3), hyperslabs of the stored array;
//! a time series is one [`Series`] with a step per mode or output time. Fields of a SET of
//! grids (a `<name>_grid_ids` dataset) cover only part of the mesh and are left out; so are the
//! complex FRF displacements, whose compound type XDMF cannot address.

use hdf5_metno as hdf5;
use std::path::Path;

use super::xml::{Number, attribute, hdf_item, hyperslab_item};
use crate::io::hdf5_file::IoError;
use crate::io::info::{DatasetSummary, FileSummary, ResultSummary};
use crate::model::mesh::MeshArrays;

/// One step of a series: a grid at one time value with its attributes.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Step {
    /// Grid name (`mode 2: 12.5 Hz`, `t = 0.01`).
    pub name: String,
    /// XDMF `Time` value.
    pub time: f64,
    /// `Attribute` elements.
    pub attributes: String,
}

/// A temporal collection written to `<out>_<subcase>_<kind>.xdmf`.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Series {
    /// Subcase id as written in `/results`.
    pub subcase: String,
    /// `statics`, `modes` or `transient`.
    pub kind: &'static str,
    /// The steps, in time order.
    pub steps: Vec<Step>,
}

/// What the XDMF files draw of the results.
#[derive(Debug, Clone, Default, PartialEq)]
pub(super) struct Fields {
    /// Attributes of the mesh grid of `<out>.xdmf`: every static displacement as one 6-column
    /// array (`displacement_<subcase>`, whole datasets, which every reader takes), and strains.
    pub model_attributes: String,
    /// One series per subcase and kind.
    pub series: Vec<Series>,
    /// Fields left out, with the reason.
    pub skipped: Vec<String>,
}

/// Reads the `/results` of `h5_path` (described in `summary`) and lists the fields to draw on
/// `mesh`; `h5` is the escaped file name used in the XDMF text and `single_block` the card of
/// the mesh's only drawn block, if any (cell fields are drawn only then).
pub(super) fn result_fields(
    h5_path: &Path,
    summary: &FileSummary,
    mesh: &MeshArrays,
    h5: &str,
    single_block: Option<&str>,
) -> Result<Fields, IoError> {
    let file = hdf5::File::open(h5_path).map_err(|e| IoError::hdf5(h5_path, "open", e))?;
    let n = mesh.grid_ids.len();
    let mut fields = Fields::default();
    for result in &summary.results {
        let base = format!("/results/{}/{}", result.subcase, result.kind);
        match result.kind.as_str() {
            "statics" => {
                let Some(shape) = full_field(result, "displacement", n, &mut fields.skipped) else {
                    continue;
                };
                let dataset = format!("{base}/displacement");
                fields.model_attributes += &attribute(
                    &format!("displacement_{}", result.subcase),
                    "Matrix",
                    "Node",
                    &hdf_item(h5, &dataset, &shape, Number::Float8),
                );
                let mut attributes = node_vectors(h5, &dataset, &shape, None);
                for (group, what) in CELL_GROUPS {
                    let cells = cell_fields(
                        &file,
                        h5_path,
                        result,
                        &base,
                        (group, what),
                        mesh,
                        h5,
                        single_block,
                    )?;
                    match cells {
                        Ok(cells) => {
                            fields.model_attributes += &cells;
                            attributes += &cells;
                        }
                        Err(reason) => fields.skipped.push(reason),
                    }
                }
                fields.series.push(Series {
                    subcase: result.subcase.clone(),
                    kind: "statics",
                    steps: vec![Step {
                        name: format!("subcase {}", result.subcase),
                        time: 0.0,
                        attributes,
                    }],
                });
            }
            "modal" => {
                let Some(shape) = full_field(result, "shapes", n, &mut fields.skipped) else {
                    continue;
                };
                let frequencies = read_f64(&file, h5_path, &format!("{base}/frequency_hz"))?;
                let dataset = format!("{base}/shapes");
                let steps = frequencies
                    .iter()
                    .take(shape[0])
                    .enumerate()
                    .map(|(i, f)| Step {
                        name: format!("mode {}: {f} Hz", i + 1),
                        time: (i + 1) as f64,
                        attributes: node_vectors(h5, &dataset, &shape, Some(i)),
                    })
                    .collect();
                fields.series.push(Series {
                    subcase: result.subcase.clone(),
                    kind: "modes",
                    steps,
                });
            }
            "transient" => {
                // A pROM transient stores input-DOF histories (t × k), not grid fields.
                if node_field(result, "displacement").is_none() {
                    continue;
                }
                let Some(shape) = full_field(result, "displacement", n, &mut fields.skipped) else {
                    continue;
                };
                let times = read_f64(&file, h5_path, &format!("{base}/time"))?;
                let dataset = format!("{base}/displacement");
                let steps = times
                    .iter()
                    .take(shape[0])
                    .enumerate()
                    .map(|(i, &t)| Step {
                        name: format!("t = {t}"),
                        time: t,
                        attributes: node_vectors(h5, &dataset, &shape, Some(i)),
                    })
                    .collect();
                fields.series.push(Series {
                    subcase: result.subcase.clone(),
                    kind: "transient",
                    steps,
                });
            }
            "frf" => {
                for name in ["displacement", "velocity", "acceleration"] {
                    if dataset(result, name).is_some() {
                        fields.skipped.push(format!(
                            "{base}/{name}: complex values, which XDMF cannot address \
                             (read them from the HDF5 file)"
                        ));
                    }
                }
            }
            _ => {}
        }
    }
    Ok(fields)
}

/// The shape of the node field `name` of `result` (`k × 6`, or `steps × k × 6`), if it is one.
fn node_field(result: &ResultSummary, name: &str) -> Option<Vec<usize>> {
    let d = dataset(result, name)?;
    let ok = d.dtype == "float64" && matches!(d.shape.as_slice(), [_, 6] | [_, _, 6]);
    ok.then(|| d.shape.clone())
}

/// The shape of the node field `name` when it covers every grid; a field of a SET is reported
/// in `skipped` and gives `None`.
fn full_field(
    result: &ResultSummary,
    name: &str,
    n: usize,
    skipped: &mut Vec<String>,
) -> Option<Vec<usize>> {
    let shape = node_field(result, name)?;
    let k = shape[shape.len() - 2];
    let set = dataset(result, &format!("{name}_grid_ids")).is_some();
    if set || k != n {
        skipped.push(format!(
            "/results/{}/{}/{name}: {k} grids of a SET, not the {n} of the mesh",
            result.subcase, result.kind
        ));
        return None;
    }
    Some(shape)
}

fn dataset<'a>(result: &'a ResultSummary, name: &str) -> Option<&'a DatasetSummary> {
    result.datasets.iter().find(|d| d.name == name)
}

/// `displacement` and `rotation` vector attributes: columns 0–2 and 3–5 of the `k × 6` node
/// field `dataset`, or of its row `step` when it is `steps × k × 6`.
fn node_vectors(h5: &str, dataset: &str, shape: &[usize], step: Option<usize>) -> String {
    let k = shape[shape.len() - 2];
    [("displacement", 0), ("rotation", 3)]
        .iter()
        .map(|&(name, column)| {
            let (start, count) = match step {
                None => (vec![0, column], vec![k, 3]),
                Some(i) => (vec![i, 0, column], vec![1, k, 3]),
            };
            let item = hyperslab_item(h5, dataset, shape, &start, &count);
            attribute(name, "Vector", "Node", &item)
        })
        .collect()
}

/// The element-result groups of a static subcase drawn as Cell attributes `<group>_<dataset>`:
/// strains, element forces and stresses (the corner stresses and ply results are not one value
/// per cell and stay in the HDF5 file).
/// Each with the plural its skip reasons name.
const CELL_GROUPS: [(&str, &str); 3] = [
    ("strain", "strains"),
    ("force", "element forces"),
    ("stress", "stresses"),
];

/// Cell attributes of the element results `<base>/<group>/<card>/...` of a static subcase:
/// `Ok("")` when it has none, `Err` with the reason when they cannot be drawn (several element
/// blocks, or not every element).
#[allow(clippy::too_many_arguments)]
fn cell_fields(
    file: &hdf5::File,
    h5_path: &Path,
    result: &ResultSummary,
    base: &str,
    (group, what): (&str, &str),
    mesh: &MeshArrays,
    h5: &str,
    single_block: Option<&str>,
) -> Result<Result<String, String>, IoError> {
    let cards: Vec<&str> = result
        .datasets
        .iter()
        .filter_map(|d| {
            d.name
                .strip_prefix(&format!("{group}/"))?
                .strip_suffix("/ids")
        })
        .collect();
    let [card] = cards.as_slice() else {
        return Ok(if cards.is_empty() {
            Ok(String::new())
        } else {
            Err(format!(
                "{base}/{group}: {what} of several element types ({}) on a mesh drawn as one \
                 mixed grid",
                cards.join(", ")
            ))
        });
    };
    let block = mesh.blocks.iter().find(|b| b.card == *card);
    let ids = read_u32(file, h5_path, &format!("{base}/{group}/{card}/ids"))?;
    let covers = single_block == Some(*card) && block.is_some_and(|b| b.ids == ids);
    if !covers {
        return Ok(Err(format!(
            "{base}/{group}/{card}: drawn only when the mesh is this one element block and the \
             {what} cover all of it"
        )));
    }
    let attributes = result
        .datasets
        .iter()
        .filter_map(|d| {
            let name = d.name.strip_prefix(&format!("{group}/{card}/"))?;
            (name != "ids" && !name.starts_with("corner")).then(|| {
                let item = hdf_item(h5, &format!("{base}/{}", d.name), &d.shape, Number::Float8);
                // Shell fibres hold [εx, εy, γxy] or [σx, σy, τxy]; solid centroids six
                // engineering strains or stresses and shell forces eight resultants, which are
                // not the components of a tensor; von Mises one value per cell (solids) or one
                // per fibre (shells).
                let kind = match d.shape.get(1) {
                    None => "Scalar",
                    Some(3) => "Vector",
                    Some(_) => "Matrix",
                };
                attribute(&format!("{group}_{name}"), kind, "Cell", &item)
            })
        })
        .collect();
    Ok(Ok(attributes))
}

fn read_f64(file: &hdf5::File, h5_path: &Path, name: &str) -> Result<Vec<f64>, IoError> {
    file.dataset(name)
        .and_then(|d| d.read_raw::<f64>())
        .map_err(|e| IoError::hdf5(h5_path, format!("read {name}"), e))
}

fn read_u32(file: &hdf5::File, h5_path: &Path, name: &str) -> Result<Vec<u32>, IoError> {
    file.dataset(name)
        .and_then(|d| d.read_raw::<u32>())
        .map_err(|e| IoError::hdf5(h5_path, format!("read {name}"), e))
}
