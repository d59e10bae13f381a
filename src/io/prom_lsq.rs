//! The black-box route to a pROM (thesis eq. 3.29, §3.3.5): stiffness and mass
//! matrices sampled by another FE code at known parameter values, read from Matrix Market files
//! listed in a CSV manifest or from one HDF5 file, and their affine components found by least
//! squares ([`crate::rom::lsq::extract_matrices`]); `paraflex prom-lsq samples.csv -o parts.h5`
//! or `paraflex prom-lsq samples.h5 -o parts.h5` ([`read_samples`] tells the two apart by the
//! HDF5 signature, not by the name).
//!
//! Manifest (CSV; blank lines and `#` lines skipped; paths relative to the manifest):
//!
//! ```text
//! K, M, 1, E, RHO
//! k_01.mtx, m_01.mtx, 1, 2.1e11, 7850.
//! k_02.mtx, m_02.mtx, 1, 1.8e11, 8300.
//! ```
//!
//! The header names the affine functions f_i of X(p) = Σ_i f_i(p) X^i; each row gives the two
//! matrices of one sample and the values f_i(p_h) (for E or ρ the parameter itself; for a fibre
//! angle the functions of eq. 3.18 — without a constant column, §3.3.5 — and so on).
//!
//! HDF5 input (as h5py writes it; n_s samples, n_f functions, n × n matrices):
//!
//! ```text
//! /functions        n_f strings: the names of the affine functions
//! /values           n_s × n_f f64: f_i(p_h), row h = sample h
//! /K/<h>, /M/<h>    h = 0 … n_s − 1, the matrices of sample h, each either
//!                   a dense n × n f64 dataset, or
//!                   a group with `row`, `col` (0-based integer indices), `data` (f64) of equal
//!                   length and the attribute `shape` = (n, n): coordinate form, duplicates
//!                   summed (scipy.sparse.coo_matrix's fields)
//! ```
//!
//! Optional, for the pROM of the black-box route ([`crate::rom::black_box`]; thesis §3.4.1.1):
//!
//! ```text
//! /basis/<h>        n × k_h f64: the external code's local basis Ψ_h of sample h (its modes,
//!                   static shapes, …; one per sample)
//! /strain/<h>       s × k_h f64: N_s,h, the strains at the s sensors of the columns of Ψ_h
//! /sensors          s strings: the strain sensors' names (with /strain)
//! /inputs/names     k strings: the load inputs' names
//! /inputs/dofs      k integers: their rows in the n-vector (0-based)
//! ```
//!
//! With `/basis` the output also holds the pROM (`/prom`, DESIGN.md §8): `/prom/inputs` from
//! `/inputs`, `/prom/sensors` (kind `STRAIN`, H_r by eq. 3.36–3.38) from `/strain`.
//!
//! Output group `/lsq`: attrs `functions` (names), `n`, `residual_K`, `residual_M` (max over the
//! samples of ‖X_h − Σ f_i X^i‖/‖X_h‖); datasets `col_offsets` (n + 1), `row_indices` (nnz) of
//! the shared full CSC pattern, `K` and `M` (n_f × nnz, row i = the values of X^i).

use std::path::{Path, PathBuf};

use faer::Mat;
use hdf5::Group;
use hdf5_metno as hdf5;
use nalgebra_sparse::{CooMatrix, CscMatrix};

use super::hdf5_file::{
    IoError, set_attr_f64, set_attr_i64, set_attr_strings, write_f64, write_u32,
};
use super::matrix_market::read_matrix_market;
use super::prom_group::{open_artifact, write_prom};
use super::{OutputFile, write_mat, write_strings};
use crate::rom::black_box::{BlackBox, BlackBoxError, BlackBoxInput, build_black_box};
use crate::rom::lsq::{FitError, MatrixFit, extract_matrices};

/// One sampled model of a manifest.
#[derive(Debug, Clone, PartialEq)]
pub struct Sample {
    pub stiffness: PathBuf,
    pub mass: PathBuf,
    /// f_i(p_h), in header order.
    pub values: Vec<f64>,
}

/// A manifest: function names and samples.
#[derive(Debug, Clone, PartialEq)]
pub struct Manifest {
    pub functions: Vec<String>,
    pub samples: Vec<Sample>,
}

/// Why the black-box route failed.
#[derive(Debug, thiserror::Error)]
pub enum LsqInputError {
    #[error(transparent)]
    Io(#[from] IoError),
    #[error("{}: {source}", .manifest.display())]
    Fit { manifest: PathBuf, source: FitError },
    #[error("{}: {source}", .samples.display())]
    BlackBox {
        samples: PathBuf,
        source: BlackBoxError,
    },
}

/// Read a manifest (module doc).
pub fn read_manifest(path: &Path) -> Result<Manifest, IoError> {
    let text = std::fs::read_to_string(path).map_err(|cause| IoError::Fs {
        path: path.into(),
        what: "read the manifest".into(),
        cause,
    })?;
    let bad = |line: usize, reason: String| IoError::Parse {
        path: path.into(),
        line,
        reason,
    };
    let mut rows = text
        .lines()
        .enumerate()
        .map(|(k, l)| (k + 1, l.trim()))
        .filter(|(_, l)| !l.is_empty() && !l.starts_with('#'));
    let (header_line, header) = rows.next().ok_or_else(|| {
        bad(
            0,
            "empty manifest: expected a header 'K, M, <function names>'".into(),
        )
    })?;
    let names: Vec<String> = header.split(',').map(|f| f.trim().to_string()).collect();
    if names.len() < 3
        || !names[0].eq_ignore_ascii_case("K")
        || !names[1].eq_ignore_ascii_case("M")
        || names.iter().any(String::is_empty)
    {
        return Err(bad(
            header_line,
            format!("expected a header 'K, M, <function names>', found '{header}'"),
        ));
    }
    let functions = names[2..].to_vec();
    let dir = path.parent().unwrap_or(Path::new("."));
    let mut samples = Vec::new();
    for (line, row) in rows {
        let fields: Vec<&str> = row.split(',').map(str::trim).collect();
        if fields.len() != names.len() {
            return Err(bad(
                line,
                format!("{} fields, the header has {}", fields.len(), names.len()),
            ));
        }
        let values = fields[2..]
            .iter()
            .zip(&functions)
            .map(|(v, name)| {
                v.parse::<f64>()
                    .ok()
                    .filter(|x| x.is_finite())
                    .ok_or_else(|| bad(line, format!("{name}: '{v}' is not a finite number")))
            })
            .collect::<Result<_, _>>()?;
        samples.push(Sample {
            stiffness: dir.join(fields[0]),
            mass: dir.join(fields[1]),
            values,
        });
    }
    Ok(Manifest { functions, samples })
}

/// The sampled models of the black-box route, whatever the input format.
#[derive(Debug, Clone)]
pub struct SampleSet {
    pub functions: Vec<String>,
    /// f_i(p_h): one row per sample, in `functions` order.
    pub values: Vec<Vec<f64>>,
    pub stiffness: Vec<CscMatrix<f64>>,
    pub mass: Vec<CscMatrix<f64>>,
    /// Ψ_h (`/basis`; empty when not given or from a CSV manifest).
    pub bases: Vec<Mat<f64>>,
    /// N_s,h (`/strain`; empty when not given) and the sensor names.
    pub strains: Vec<Mat<f64>>,
    pub sensors: Vec<String>,
    /// Load inputs: (name, 0-based row).
    pub inputs: Vec<(String, usize)>,
}

/// The first bytes of every HDF5 file (superblock signature at offset 0, as h5py and paraflex
/// write them).
const HDF5_SIGNATURE: &[u8; 8] = b"\x89HDF\r\n\x1a\n";

/// Read the samples of `path`: an HDF5 file (by its signature) or a CSV manifest of Matrix
/// Market files (module doc).
pub fn read_samples(path: &Path) -> Result<SampleSet, IoError> {
    let mut head = [0u8; 8];
    let is_hdf5 = std::fs::File::open(path)
        .and_then(|mut f| std::io::Read::read(&mut f, &mut head))
        .map_err(|cause| IoError::Fs {
            path: path.into(),
            what: "read the samples".into(),
            cause,
        })?
        == 8
        && &head == HDF5_SIGNATURE;
    if is_hdf5 {
        return read_samples_hdf5(path);
    }
    let manifest = read_manifest(path)?;
    let read = |files: &dyn Fn(&Sample) -> &Path| {
        manifest
            .samples
            .iter()
            .map(|s| read_matrix_market(files(s)))
            .collect::<Result<Vec<_>, _>>()
    };
    let (stiffness, mass) = (read(&|s| &s.stiffness)?, read(&|s| &s.mass)?);
    let values = manifest.samples.iter().map(|s| s.values.clone()).collect();
    Ok(SampleSet {
        functions: manifest.functions,
        values,
        stiffness,
        mass,
        bases: Vec::new(),
        strains: Vec::new(),
        sensors: Vec::new(),
        inputs: Vec::new(),
    })
}

/// The HDF5 layout of the module doc.
fn read_samples_hdf5(path: &Path) -> Result<SampleSet, IoError> {
    let file = open_artifact(path)?;
    let hdf = |what: String| move |e| IoError::hdf5(path, what, e);
    let bad = |what: &str, reason: String| IoError::malformed(path, what, reason);
    let functions: Vec<String> = file
        .dataset("functions")
        .and_then(|d| d.read_raw::<hdf5::types::VarLenUnicode>())
        .map_err(hdf(
            "read /functions (the names of the affine functions)".into()
        ))?
        .iter()
        .map(|s| s.as_str().trim().to_string())
        .collect();
    if functions.is_empty() || functions.iter().any(String::is_empty) {
        return Err(bad(
            "/functions",
            format!("expected the names of the affine functions, found {functions:?}"),
        ));
    }
    let values_set = file.dataset("values").map_err(hdf("open /values".into()))?;
    let n_f = functions.len();
    let shape = values_set.shape();
    if shape.len() != 2 || shape[1] != n_f {
        return Err(bad(
            "/values",
            format!("shape {shape:?}, expected n_samples × {n_f} (one column per function)"),
        ));
    }
    let flat: Vec<f64> = values_set.read_raw().map_err(hdf("read /values".into()))?;
    if let Some(x) = flat.iter().find(|x| !x.is_finite()) {
        return Err(bad("/values", format!("{x} is not a finite number")));
    }
    let values: Vec<Vec<f64>> = flat.chunks(n_f).map(<[f64]>::to_vec).collect();
    let matrices = |which: &str| -> Result<Vec<CscMatrix<f64>>, IoError> {
        (0..values.len())
            .map(|h| read_matrix_hdf5(&file, path, &format!("{which}/{h}")))
            .collect()
    };
    let (stiffness, mass) = (matrices("K")?, matrices("M")?);
    let n = stiffness.first().map_or(0, CscMatrix::nrows);
    let strings = |name: &str| -> Result<Vec<String>, IoError> {
        Ok(file
            .dataset(name)
            .and_then(|d| d.read_raw::<hdf5::types::VarLenUnicode>())
            .map_err(hdf(format!("read /{name}")))?
            .iter()
            .map(|s| s.as_str().trim().to_string())
            .collect())
    };
    let per_sample = |group: &str, rows: Option<usize>| -> Result<Vec<Mat<f64>>, IoError> {
        if file.group(group).is_err() {
            return Ok(Vec::new());
        }
        (0..values.len())
            .map(|h| read_dense_hdf5(&file, path, &format!("{group}/{h}"), rows))
            .collect()
    };
    let bases = per_sample("basis", Some(n))?;
    let strains = per_sample("strain", None)?;
    let sensors = if strains.is_empty() {
        Vec::new()
    } else {
        strings("sensors")?
    };
    if let Some(first) = strains.first()
        && sensors.len() != first.nrows()
    {
        return Err(bad(
            "/sensors",
            format!("{} names for {} strain rows", sensors.len(), first.nrows()),
        ));
    }
    let inputs = if file.group("inputs").is_ok() {
        let names = strings("inputs/names")?;
        let dofs: Vec<i64> = file
            .dataset("inputs/dofs")
            .and_then(|d| d.read_raw::<i64>())
            .map_err(hdf("read /inputs/dofs".into()))?;
        if dofs.len() != names.len() {
            return Err(bad(
                "/inputs",
                format!("{} names and {} dofs", names.len(), dofs.len()),
            ));
        }
        let rows =
            dofs.iter()
                .map(|&i| {
                    usize::try_from(i).ok().filter(|&i| i < n).ok_or_else(|| {
                        bad("/inputs/dofs", format!("{i} is not in 0..{n} (0-based)"))
                    })
                })
                .collect::<Result<Vec<_>, _>>()?;
        names.into_iter().zip(rows).collect()
    } else {
        Vec::new()
    };
    Ok(SampleSet {
        functions,
        values,
        stiffness,
        mass,
        bases,
        strains,
        sensors,
        inputs,
    })
}

/// A dense 2-D f64 dataset at `name` (row-major, as h5py writes numpy arrays), with `rows` rows
/// when given.
fn read_dense_hdf5(
    file: &hdf5::File,
    path: &Path,
    name: &str,
    rows: Option<usize>,
) -> Result<Mat<f64>, IoError> {
    let what = format!("/{name}");
    let bad = |reason: String| IoError::malformed(path, what.as_str(), reason);
    let set = file
        .dataset(name)
        .map_err(|_| bad("missing: one dense 2-D dataset per sample".into()))?;
    let shape = set.shape();
    let [r, c] = shape[..] else {
        return Err(bad(format!("shape {shape:?}, expected a 2-D matrix")));
    };
    if let Some(n) = rows
        && r != n
    {
        return Err(bad(format!("{r} rows, the matrices are {n} × {n}")));
    }
    let data: Vec<f64> = set
        .read_raw()
        .map_err(|e| IoError::hdf5(path, format!("read {what}"), e))?;
    if let Some(x) = data.iter().find(|x| !x.is_finite()) {
        return Err(bad(format!("{x} is not a finite number")));
    }
    Ok(Mat::from_fn(r, c, |i, j| data[i * c + j]))
}

/// One square matrix at `name`: a dense 2-D dataset or a coordinate-form group (module doc).
fn read_matrix_hdf5(file: &hdf5::File, path: &Path, name: &str) -> Result<CscMatrix<f64>, IoError> {
    let what = format!("/{name}");
    let hdf = |op: &str| {
        let what = format!("{op} {what}");
        move |e| IoError::hdf5(path, what, e)
    };
    let bad = |reason: String| IoError::malformed(path, what.as_str(), reason);
    if let Ok(set) = file.dataset(name) {
        let shape = set.shape();
        let [n, m] = shape[..] else {
            return Err(bad(format!(
                "shape {shape:?}, expected a square 2-D matrix"
            )));
        };
        if n != m {
            return Err(bad(format!(
                "{n} × {m}: a stiffness or mass matrix is square"
            )));
        }
        let data: Vec<f64> = set.read_raw().map_err(hdf("read"))?;
        let mut coo = CooMatrix::new(n, n);
        for (k, &v) in data.iter().enumerate() {
            if !v.is_finite() {
                return Err(bad(format!(
                    "entry ({}, {}) = {v} is not a finite number",
                    k / n,
                    k % n
                )));
            }
            if v != 0.0 {
                coo.push(k / n, k % n, v);
            }
        }
        return Ok(CscMatrix::from(&coo));
    }
    let group = file.group(name).map_err(|_| {
        bad(
            "missing: expected a dense dataset or a group with row, col, data and attribute shape"
                .into(),
        )
    })?;
    let shape: Vec<i64> = group
        .attr("shape")
        .and_then(|a| a.read_raw::<i64>())
        .map_err(hdf("read attribute shape of"))?;
    let n = match shape[..] {
        [n, m] if n == m && n > 0 => n as usize,
        _ => {
            return Err(bad(format!(
                "attribute shape {shape:?}: expected (n, n) with n > 0"
            )));
        }
    };
    let indices = |field: &str| -> Result<Vec<usize>, IoError> {
        let raw: Vec<i64> = group
            .dataset(field)
            .and_then(|d| d.read_raw::<i64>())
            .map_err(hdf(&format!("read {field} of")))?;
        raw.iter()
            .map(|&i| {
                usize::try_from(i).ok().filter(|&i| i < n).ok_or_else(|| {
                    bad(format!(
                        "{field} index {i} is not in 0..{n} (indices are 0-based)"
                    ))
                })
            })
            .collect()
    };
    let (rows, cols) = (indices("row")?, indices("col")?);
    let data: Vec<f64> = group
        .dataset("data")
        .and_then(|d| d.read_raw::<f64>())
        .map_err(hdf("read data of"))?;
    if rows.len() != data.len() || cols.len() != data.len() {
        return Err(bad(format!(
            "row, col and data have {}, {} and {} entries",
            rows.len(),
            cols.len(),
            data.len()
        )));
    }
    let mut coo = CooMatrix::new(n, n);
    for ((&i, &j), &v) in rows.iter().zip(&cols).zip(&data) {
        if !v.is_finite() {
            return Err(bad(format!(
                "entry ({i}, {j}) = {v} is not a finite number"
            )));
        }
        coo.push(i, j, v);
    }
    Ok(CscMatrix::from(&coo))
}

/// Read the samples of `path` ([`read_samples`]) and extract the affine components.
pub fn fit_samples(path: &Path) -> Result<(SampleSet, MatrixFit), LsqInputError> {
    let samples = read_samples(path)?;
    let names: Vec<&str> = samples.functions.iter().map(String::as_str).collect();
    let fit = extract_matrices(&names, &samples.values, &samples.stiffness, &samples.mass)
        .map_err(|source| LsqInputError::Fit {
            manifest: path.into(),
            source,
        })?;
    Ok((samples, fit))
}

/// The pROM of the black-box route ([`build_black_box`], MAC threshold 0.99 as in the thesis)
/// when the samples carry local bases (`/basis`), else `None`.
pub fn build_samples(
    path: &Path,
    samples: &SampleSet,
    fit: &MatrixFit,
) -> Result<Option<BlackBox>, LsqInputError> {
    if samples.bases.is_empty() {
        return Ok(None);
    }
    let rows: Vec<usize> = samples.inputs.iter().map(|(_, row)| *row).collect();
    let input = BlackBoxInput {
        functions: &samples.functions,
        values: &samples.values,
        bases: &samples.bases,
        strains: &samples.strains,
        inputs: &rows,
        mac_tol: 0.99,
    };
    build_black_box(fit, &input)
        .map(Some)
        .map_err(|source| LsqInputError::BlackBox {
            samples: path.into(),
            source,
        })
}

/// Write the pROM of [`build_samples`] into `prom` (normally `/prom`, module doc): the
/// components, `/prom/inputs` and, with strain bases, `/prom/sensors`.
pub fn write_black_box(
    file: &OutputFile,
    samples: &SampleSet,
    built: &BlackBox,
) -> Result<(), IoError> {
    let n = samples.stiffness.first().map_or(0, CscMatrix::nrows);
    write_prom(&file.group("prom")?, &built.prom, n)?;
    let inputs = file.group("prom/inputs")?;
    let names: Vec<&str> = samples
        .inputs
        .iter()
        .map(|(name, _)| name.as_str())
        .collect();
    write_strings(&inputs, "names", &names)?;
    write_mat(&inputs, "S_r", &built.inputs)?;
    if !samples.sensors.is_empty() {
        let sensors = file.group("prom/sensors")?;
        let names: Vec<&str> = samples.sensors.iter().map(String::as_str).collect();
        write_strings(&sensors, "names", &names)?;
        write_strings(&sensors, "kind", &vec!["STRAIN"; names.len()])?;
        write_mat(&sensors, "H_r", &built.strains)?;
    }
    Ok(())
}

/// Write the components into `group` (normally `/lsq`, module doc).
pub fn write_lsq(group: &Group, functions: &[String], fit: &MatrixFit) -> Result<(), IoError> {
    let names: Vec<&str> = functions.iter().map(String::as_str).collect();
    set_attr_strings(group, "functions", &names)?;
    let first = fit
        .stiffness
        .first()
        .ok_or_else(|| IoError::invalid(group.filename(), "/lsq", "no components"))?;
    let n = first.nrows();
    set_attr_i64(group, "n", n as i64)?;
    set_attr_f64(group, "residual_K", fit.residual_stiffness)?;
    set_attr_f64(group, "residual_M", fit.residual_mass)?;
    let to_u32 = |v: &[usize]| -> Result<Vec<u32>, IoError> {
        v.iter()
            .map(|&x| {
                u32::try_from(x).map_err(|_| {
                    IoError::invalid(group.filename(), "/lsq", format!("index {x} exceeds u32"))
                })
            })
            .collect()
    };
    let pattern = first.pattern();
    write_u32(
        group,
        "col_offsets",
        &to_u32(pattern.major_offsets())?,
        &[n + 1],
    )?;
    write_u32(
        group,
        "row_indices",
        &to_u32(pattern.minor_indices())?,
        &[pattern.nnz()],
    )?;
    for (name, parts) in [("K", &fit.stiffness), ("M", &fit.mass)] {
        let values: Vec<f64> = parts
            .iter()
            .flat_map(|x| x.values().iter().copied())
            .collect();
        write_f64(group, name, &values, &[parts.len(), pattern.nnz()])?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn manifest_rows_and_errors() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("samples.csv");
        std::fs::write(
            &path,
            "# sampled\nK, M, 1, E\nk1.mtx, m1.mtx, 1, 2.e11\n\nk2.mtx, m2.mtx, 1, 1.e11\n",
        )
        .unwrap();
        let m = read_manifest(&path).unwrap();
        assert_eq!(m.functions, vec!["1", "E"]);
        assert_eq!(
            m.samples[1],
            Sample {
                stiffness: dir.path().join("k2.mtx"),
                mass: dir.path().join("m2.mtx"),
                values: vec![1.0, 1.0e11]
            }
        );
        for (text, needle) in [
            ("M, K, E\n", ":1: expected a header"),
            ("K, M, E\nk, m\n", ":2: 2 fields"),
            ("K, M, E\nk, m, x\n", ":2: E: 'x'"),
        ] {
            std::fs::write(&path, text).unwrap();
            let message = read_manifest(&path).unwrap_err().to_string();
            assert!(message.contains(needle), "{message}");
        }
    }
}
