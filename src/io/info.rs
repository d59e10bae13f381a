//! `paraflex info FILE.h5`: a summary of any paraflex HDF5 file (DESIGN.md §8).
//!
//! [`describe`] reads metadata (attributes and dataset shapes) and, of the arrays, only the
//! frequencies of modal results (one number per mode), so it is instant on large result files. [`FileSummary`] implements [`Display`](std::fmt::Display)
//! for the text form and [`serde::Serialize`] for `--json`.

use std::collections::BTreeMap;
use std::fmt;
use std::path::{Path, PathBuf};

use hdf5::types::{VarLenAscii, VarLenUnicode};
use hdf5_metno as hdf5;
use serde::Serialize;

use super::hdf5_file::IoError;

/// What `describe` found in a paraflex HDF5 file.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FileSummary {
    /// The file described.
    pub path: PathBuf,
    /// `schema` attribute of `/`.
    pub schema: i64,
    /// `paraflex_version` attribute of `/` (empty if absent).
    pub paraflex_version: String,
    /// `/model`, if present.
    pub model: Option<ModelSummary>,
    /// `/prom`, if present.
    pub prom: Option<PromSummary>,
    /// One entry per `/results/<subcase>/<kind>` group, subcases in numeric order.
    pub results: Vec<ResultSummary>,
    /// Other top-level members, by name.
    pub other: Vec<String>,
}

/// Counts and attributes of `/model`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ModelSummary {
    /// `title` attribute.
    pub title: Option<String>,
    /// `deck` attribute.
    pub deck: Option<String>,
    /// `sol` attribute.
    pub sol: Option<String>,
    /// Rows of `/model/grid_ids`.
    pub n_grids: usize,
    /// Rows of `/model/elements/<CARD>/ids` per card (RBE legs count one row each).
    pub elements: BTreeMap<String, usize>,
}

/// Attributes of `/prom`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PromSummary {
    /// Full-model DOF count.
    pub n_full: Option<i64>,
    /// Reduced basis size.
    pub n_red: Option<i64>,
    /// Parameter names.
    pub params: Vec<String>,
    /// (low, high) per parameter.
    pub ranges: Vec<(f64, f64)>,
    /// Nominal value per parameter.
    pub nominal: Vec<f64>,
    /// Input DOFs ("GRID:component") of `/prom/inputs/names`.
    pub inputs: Vec<String>,
    /// Members of `/prom` by name (`K`, `M`, `inputs`, ...).
    pub members: Vec<String>,
}

/// The datasets of one `/results/<subcase>/<kind>` group.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ResultSummary {
    /// Subcase id as written (decimal).
    pub subcase: String,
    /// `modal`, `statics`, `frf`, ... (empty for datasets directly under the subcase).
    pub kind: String,
    /// Datasets below the kind group, recursively, by relative path (`sensors/tip`).
    pub datasets: Vec<DatasetSummary>,
    /// For a `modal` group: its frequencies and Sturm check.
    pub modal: Option<ModalResultSummary>,
}

/// The frequencies and the Sturm check of a `modal` results group.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ModalResultSummary {
    /// `frequency_hz`, ascending.
    pub frequencies_hz: Vec<f64>,
    /// `sturm_shift` converted to Hz.
    pub sturm_shift_hz: Option<f64>,
    /// `sturm_count`: eigenvalues below the shift.
    pub sturm_count: Option<i64>,
    /// `sturm_found`: modes found below the shift.
    pub sturm_found: Option<i64>,
    /// `sturm_consistent`.
    pub sturm_consistent: Option<bool>,
    /// `sturm_note` (a multiple root cut by ND).
    pub sturm_note: Option<String>,
}

/// Name, shape and element type of one dataset.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct DatasetSummary {
    /// Path relative to the group being summarised.
    pub name: String,
    /// Dimensions (empty for a scalar).
    pub shape: Vec<usize>,
    /// Element type as HDF5 describes it (`float64`, `uint32`, `compound (2 fields)`, ...).
    pub dtype: String,
}

/// Opens `path` read-only and summarises it; see the module documentation.
///
/// Errors, all naming `path`: missing or unreadable → [`IoError::Fs`]; not HDF5 or corrupt →
/// [`IoError::Hdf5`]; a directory, or an HDF5 file without the root `schema` attribute →
/// [`IoError::NotParaflex`].
pub fn describe(path: impl AsRef<Path>) -> Result<FileSummary, IoError> {
    let path = path.as_ref();
    let err = |what: &str| {
        let what = what.to_owned();
        move |e| IoError::hdf5(path, what, e)
    };
    // Plain file-system problems get the OS message rather than HDF5's verbose one.
    let meta = std::fs::metadata(path).map_err(|e| IoError::fs(path, "open", e))?;
    if meta.is_dir() {
        return Err(IoError::NotParaflex {
            path: path.to_owned(),
            reason: "is a directory".into(),
        });
    }
    let file = hdf5::File::open(path).map_err(err("open as HDF5"))?;
    let names = file.attr_names().map_err(err("list attributes of /"))?;
    if !names.iter().any(|n| n == "schema") {
        return Err(IoError::NotParaflex {
            path: path.to_owned(),
            reason: "no `schema` attribute on the root group".into(),
        });
    }
    let schema = file
        .attr("schema")
        .and_then(|a| a.read_scalar::<i64>())
        .map_err(err("read attribute schema of /"))?;
    let paraflex_version = read_str_attr(&file, "paraflex_version").unwrap_or_default();

    let mut summary = FileSummary {
        path: path.to_owned(),
        schema,
        paraflex_version,
        model: None,
        prom: None,
        results: Vec::new(),
        other: Vec::new(),
    };
    for name in file.member_names().map_err(err("list members of /"))? {
        match name.as_str() {
            "model" => summary.model = Some(describe_model(&file, path)?),
            "prom" => summary.prom = Some(describe_prom(&file, path)?),
            "results" => summary.results = describe_results(&file, path)?,
            _ => summary.other.push(name),
        }
    }
    Ok(summary)
}

fn describe_model(file: &hdf5::File, path: &Path) -> Result<ModelSummary, IoError> {
    let model = file
        .group("model")
        .map_err(|e| IoError::hdf5(path, "open /model", e))?;
    let n_grids = match model.dataset("grid_ids") {
        Ok(ds) => ds.shape().first().copied().unwrap_or(0),
        Err(_) => 0,
    };
    let mut elements = BTreeMap::new();
    if model.link_exists("elements") {
        let groups = model
            .group("elements")
            .and_then(|g| g.groups())
            .map_err(|e| IoError::hdf5(path, "list /model/elements", e))?;
        for g in groups {
            // Distinct ids: rigid elements are stored as one row per leg.
            let count = g
                .dataset("ids")
                .and_then(|d| d.read_raw::<u32>())
                .map(|ids| {
                    let mut ids = ids;
                    ids.sort_unstable();
                    ids.dedup();
                    ids.len()
                });
            elements.insert(basename(&g.name()), count.unwrap_or(0));
        }
    }
    Ok(ModelSummary {
        title: read_str_attr(&model, "title"),
        deck: read_str_attr(&model, "deck"),
        sol: read_str_attr(&model, "sol"),
        n_grids,
        elements,
    })
}

fn describe_prom(file: &hdf5::File, path: &Path) -> Result<PromSummary, IoError> {
    let prom = file
        .group("prom")
        .map_err(|e| IoError::hdf5(path, "open /prom", e))?;
    let int = |name: &str| prom.attr(name).and_then(|a| a.read_scalar::<i64>()).ok();
    let params = read_strs_attr(&prom, "params").unwrap_or_default();
    let f64s = |name: &str| {
        prom.attr(name)
            .and_then(|a| a.read_raw::<f64>())
            .unwrap_or_default()
    };
    let ranges = f64s("ranges")
        .chunks_exact(2)
        .map(|c| (c[0], c[1]))
        .collect();
    let nominal = f64s("nominal");
    let inputs = prom
        .dataset("inputs/names")
        .and_then(|d| d.read_raw::<VarLenUnicode>())
        .map(|v| v.iter().map(|s| s.as_str().to_string()).collect())
        .unwrap_or_default();
    let members = prom
        .member_names()
        .map_err(|e| IoError::hdf5(path, "list /prom", e))?;
    Ok(PromSummary {
        n_full: int("n_full"),
        n_red: int("n_red"),
        params,
        ranges,
        nominal,
        inputs,
        members,
    })
}

fn describe_results(file: &hdf5::File, path: &Path) -> Result<Vec<ResultSummary>, IoError> {
    let err = |what: String| move |e| IoError::hdf5(path, what, e);
    let results = file.group("results").map_err(err("open /results".into()))?;
    let mut subcases = results.groups().map_err(err("list /results".into()))?;
    // Numeric order: 1, 2, 10 rather than 1, 10, 2.
    subcases.sort_by_key(|g| {
        let name = basename(&g.name());
        (name.parse::<u64>().unwrap_or(u64::MAX), name)
    });
    let mut out = Vec::new();
    for sub in subcases {
        let subcase = basename(&sub.name());
        let direct = sub
            .datasets()
            .map_err(err(format!("list {}", sub.name())))?;
        if !direct.is_empty() {
            let datasets = direct
                .iter()
                .map(|d| dataset_summary(d, &sub.name()))
                .collect();
            out.push(ResultSummary {
                subcase: subcase.clone(),
                kind: String::new(),
                datasets,
                modal: None,
            });
        }
        for kind in sub.groups().map_err(err(format!("list {}", sub.name())))? {
            let mut datasets = Vec::new();
            collect_datasets(&kind, &kind.name(), &mut datasets, path)?;
            let name = basename(&kind.name());
            let modal = (name == "modal").then(|| describe_modal(&kind));
            out.push(ResultSummary {
                subcase: subcase.clone(),
                kind: name,
                datasets,
                modal,
            });
        }
    }
    Ok(out)
}

/// The frequencies and Sturm attributes of a `modal` group (absent ones as `None`/empty).
fn describe_modal(group: &hdf5::Group) -> ModalResultSummary {
    let int = |name: &str| group.attr(name).and_then(|a| a.read_scalar::<i64>()).ok();
    let sturm_shift_hz = group
        .attr("sturm_shift")
        .and_then(|a| a.read_scalar::<f64>())
        .ok()
        .map(|lambda| lambda.max(0.0).sqrt() / (2.0 * std::f64::consts::PI));
    ModalResultSummary {
        frequencies_hz: group
            .dataset("frequency_hz")
            .and_then(|d| d.read_raw::<f64>())
            .unwrap_or_default(),
        sturm_shift_hz,
        sturm_count: int("sturm_count"),
        sturm_found: int("sturm_found"),
        sturm_consistent: int("sturm_consistent").map(|v| v != 0),
        sturm_note: read_str_attr(group, "sturm_note"),
    }
}

impl fmt::Display for ModalResultSummary {
    /// `  frequencies [Hz]` (six per line) and `  Sturm check` lines.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (k, row) in self.frequencies_hz.chunks(6).enumerate() {
            let label = if k == 0 { "frequencies [Hz]" } else { "" };
            let values: Vec<String> = row.iter().map(|v| format!("{v:.6e}")).collect();
            writeln!(f, "  {label:<16}  {}", values.join("  "))?;
        }
        if let (Some(shift), Some(count), Some(found)) =
            (self.sturm_shift_hz, self.sturm_count, self.sturm_found)
        {
            let verdict = match self.sturm_consistent {
                Some(true) => "consistent",
                Some(false) => "INCONSISTENT (modes missing)",
                None => "?",
            };
            writeln!(
                f,
                "  {:<16}  {count} eigenvalue(s) below {shift:.6e} Hz, {found} found: {verdict}",
                "Sturm check"
            )?;
        }
        if let Some(note) = &self.sturm_note {
            writeln!(f, "  {:<16}  {note}", "note")?;
        }
        Ok(())
    }
}

/// Appends every dataset below `group` (recursively), named relative to `base`.
fn collect_datasets(
    group: &hdf5::Group,
    base: &str,
    out: &mut Vec<DatasetSummary>,
    path: &Path,
) -> Result<(), IoError> {
    let err = |e| IoError::hdf5(path, format!("list {}", group.name()), e);
    for ds in group.datasets().map_err(err)? {
        out.push(dataset_summary(&ds, base));
    }
    for sub in group.groups().map_err(err)? {
        collect_datasets(&sub, base, out, path)?;
    }
    Ok(())
}

fn dataset_summary(ds: &hdf5::Dataset, base: &str) -> DatasetSummary {
    let full = ds.name();
    let name = full
        .strip_prefix(base)
        .unwrap_or(&full)
        .trim_start_matches('/')
        .to_owned();
    let dtype = ds
        .dtype()
        .and_then(|t| t.to_descriptor())
        .map(|d| d.to_string())
        .unwrap_or_else(|_| "unknown".into());
    DatasetSummary {
        name,
        shape: ds.shape(),
        dtype,
    }
}

/// Last component of an HDF5 object name.
fn basename(name: &str) -> String {
    name.rsplit('/').next().unwrap_or(name).to_owned()
}

/// A scalar string attribute written by paraflex (UTF-8) or h5py/other tools (ASCII).
fn read_str_attr(loc: &hdf5::Location, name: &str) -> Option<String> {
    let attr = loc.attr(name).ok()?;
    if let Ok(v) = attr.read_scalar::<VarLenUnicode>() {
        return Some(v.as_str().to_owned());
    }
    attr.read_scalar::<VarLenAscii>()
        .ok()
        .map(|v| v.as_str().to_owned())
}

/// A 1-D string-array attribute (UTF-8 or ASCII, variable length).
fn read_strs_attr(loc: &hdf5::Location, name: &str) -> Option<Vec<String>> {
    let attr = loc.attr(name).ok()?;
    if let Ok(v) = attr.read_raw::<VarLenUnicode>() {
        return Some(v.iter().map(|s| s.as_str().to_owned()).collect());
    }
    attr.read_raw::<VarLenAscii>()
        .ok()
        .map(|v| v.iter().map(|s| s.as_str().to_owned()).collect())
}

fn fmt_shape(shape: &[usize]) -> String {
    if shape.is_empty() {
        return "scalar".into();
    }
    let dims: Vec<String> = shape.iter().map(|d| d.to_string()).collect();
    format!("({})", dims.join("×"))
}

impl fmt::Display for FileSummary {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let version = if self.paraflex_version.is_empty() {
            "?"
        } else {
            &self.paraflex_version
        };
        writeln!(
            f,
            "{}: paraflex {version}, schema {}",
            self.path.display(),
            self.schema
        )?;
        if let Some(m) = &self.model {
            let n_el: usize = m.elements.values().sum();
            writeln!(f, "/model: {} grids, {n_el} elements", m.n_grids)?;
            for (label, value) in [("title", &m.title), ("deck", &m.deck), ("sol", &m.sol)] {
                if let Some(v) = value {
                    writeln!(f, "  {label:<9} {v}")?;
                }
            }
            for (card, count) in &m.elements {
                writeln!(f, "  {card:<9} {count}")?;
            }
        }
        if let Some(p) = &self.prom {
            let opt = |v: Option<i64>| v.map_or("?".to_string(), |v| v.to_string());
            writeln!(f, "/prom: n_full {}, n_red {}", opt(p.n_full), opt(p.n_red))?;
            for (k, name) in p.params.iter().enumerate() {
                let range = p
                    .ranges
                    .get(k)
                    .map_or(String::new(), |(lo, hi)| format!(" in [{lo:e}, {hi:e}]"));
                let nominal = p
                    .nominal
                    .get(k)
                    .map_or(String::new(), |v| format!(", nominal {v:e}"));
                writeln!(f, "  param     {name}{range}{nominal}")?;
            }
            if !p.inputs.is_empty() {
                writeln!(
                    f,
                    "  inputs    {} ({})",
                    p.inputs.len(),
                    p.inputs.join(", ")
                )?;
            }
            if !p.members.is_empty() {
                writeln!(f, "  members   {}", p.members.join(", "))?;
            }
        }
        for r in &self.results {
            if r.kind.is_empty() {
                writeln!(f, "/results/{}", r.subcase)?;
            } else {
                writeln!(f, "/results/{}/{}", r.subcase, r.kind)?;
            }
            let width = r.datasets.iter().map(|d| d.name.len()).max().unwrap_or(0);
            for d in &r.datasets {
                writeln!(
                    f,
                    "  {:<width$}  {} {}",
                    d.name,
                    fmt_shape(&d.shape),
                    d.dtype
                )?;
            }
            if let Some(modal) = &r.modal {
                write!(f, "{modal}")?;
            }
        }
        if !self.other.is_empty() {
            writeln!(f, "other: {}", self.other.join(", "))?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::hdf5_file::hdf5_test_guard;
    use crate::io::model_group::test_mesh;
    use crate::io::{
        ModelInfo, OutputFile, set_attr_f64, set_attr_i64, set_attr_strings, write_f64, write_model,
    };

    fn write_sample(path: &Path) {
        let f = OutputFile::create(path).expect("create");
        let info = ModelInfo {
            sol: Some("MODES".into()),
            ..ModelInfo::default()
        };
        write_model(&f, &test_mesh(), &info).expect("model");
        let prom = f.group("prom").expect("prom");
        set_attr_i64(&prom, "n_full", 90).expect("attr");
        set_attr_i64(&prom, "n_red", 6).expect("attr");
        set_attr_strings(&prom, "params", &["t", "E"]).expect("attr");
        f.group("prom/K").expect("K");
        for sub in ["10", "2"] {
            let g = f.group(&format!("results/{sub}/modal")).expect("modal");
            write_f64(&g, "frequency_hz", &[1.0, 2.0, 3.0, 4.0], &[4]).expect("freq");
            set_attr_f64(
                &g,
                "sturm_shift",
                (2.0 * std::f64::consts::PI * 5.0_f64).powi(2),
            )
            .expect("attr");
            set_attr_i64(&g, "sturm_count", 4).expect("attr");
            set_attr_i64(&g, "sturm_found", 4).expect("attr");
            set_attr_i64(&g, "sturm_consistent", 1).expect("attr");
            write_f64(&g, "shapes", &vec![0.0; 4 * 15 * 6], &[4, 15, 6]).expect("shapes");
        }
        let s = f.group("results/2/transient/sensors").expect("sensors");
        write_f64(&s, "tip", &[0.0; 3], &[3]).expect("tip");
        f.group("extra").expect("extra");
        f.commit().expect("commit");
    }

    #[test]
    fn describes_written_file() {
        let _guard = hdf5_test_guard();
        let dir = tempfile::tempdir().expect("tempdir");
        let path = dir.path().join("s.h5");
        write_sample(&path);
        let s = describe(&path).expect("describe");
        assert_eq!(s.schema, 1);
        assert_eq!(s.paraflex_version, crate::VERSION);
        let m = s.model.as_ref().expect("model");
        assert_eq!(m.n_grids, 15);
        assert_eq!(m.sol.as_deref(), Some("MODES"));
        assert_eq!(m.elements["CQUAD4"], 2);
        assert_eq!(m.elements.values().sum::<usize>(), 6);
        let p = s.prom.as_ref().expect("prom");
        assert_eq!((p.n_full, p.n_red), (Some(90), Some(6)));
        assert_eq!(p.params, ["t", "E"]);
        let keys: Vec<_> = s
            .results
            .iter()
            .map(|r| (r.subcase.as_str(), r.kind.as_str()))
            .collect();
        assert_eq!(keys, [("2", "modal"), ("2", "transient"), ("10", "modal")]);
        assert_eq!(s.results[0].datasets[1].shape, [4, 15, 6]);
        assert_eq!(s.results[0].datasets[1].dtype, "float64");
        assert_eq!(s.results[1].datasets[0].name, "sensors/tip");
        assert_eq!(s.other, ["extra"]);

        let text = s.to_string();
        assert!(text.contains("/model: 15 grids, 6 elements"), "{text}");
        assert!(text.contains("shapes        (4×15×6) float64"), "{text}");
        assert!(
            text.contains("frequencies [Hz]  1.000000e0  2.000000e0  3.000000e0  4.000000e0"),
            "{text}"
        );
        assert!(
            text.contains(
                "Sturm check       4 eigenvalue(s) below 5.000000e0 Hz, 4 found: consistent"
            ),
            "{text}"
        );
        assert_eq!(
            s.results[0].modal.as_ref().map(|m| m.frequencies_hz.len()),
            Some(4)
        );
        assert_eq!(s.results[1].modal, None);
        let json = serde_json::to_value(&s).expect("json");
        assert_eq!(json["model"]["elements"]["CHEXA"], 1);
        assert_eq!(json["results"][0]["datasets"][0]["name"], "frequency_hz");
    }

    #[test]
    fn garbage_missing_and_foreign_files_are_errors_naming_the_path() {
        let _guard = hdf5_test_guard();
        let dir = tempfile::tempdir().expect("tempdir");
        let garbage = dir.path().join("garbage.h5");
        std::fs::write(&garbage, b"this is not HDF5 at all\n").expect("write");
        let missing = dir.path().join("missing.h5");
        for path in [&garbage, &missing, &dir.path().to_path_buf()] {
            let msg = describe(path).unwrap_err().to_string();
            assert!(msg.contains(&path.display().to_string()), "{msg}");
        }

        // Valid HDF5 but not written by paraflex.
        let foreign = dir.path().join("foreign.h5");
        hdf5::File::create(&foreign)
            .and_then(|f| f.create_group("x"))
            .expect("foreign");
        let err = describe(&foreign).unwrap_err();
        assert!(matches!(err, IoError::NotParaflex { .. }), "{err}");
        assert!(err.to_string().contains("foreign.h5"));

        // Truncated paraflex file.
        let good = dir.path().join("good.h5");
        write_sample(&good);
        let bytes = std::fs::read(&good).expect("read");
        let cut = dir.path().join("cut.h5");
        std::fs::write(&cut, &bytes[..bytes.len() / 2]).expect("write");
        match describe(&cut) {
            Ok(s) => assert_eq!(s.schema, 1), // metadata may survive in the first half
            Err(e) => assert!(e.to_string().contains("cut.h5"), "{e}"),
        }
    }
}
