//! The black-box route of the pROM issue (item 2; thesis eq. 3.29, §3.3.5): stiffness and mass
//! matrices sampled by another FE code at known parameter values, read from Matrix Market
//! files listed in a manifest, and their affine components found by least squares
//! ([`crate::rom::lsq::extract_matrices`]); `paraflex prom-lsq manifest.csv -o parts.h5`.
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
//! Output group `/lsq`: attrs `functions` (names), `n`, `residual_K`, `residual_M` (max over the
//! samples of ‖X_h − Σ f_i X^i‖/‖X_h‖); datasets `col_offsets` (n + 1), `row_indices` (nnz) of
//! the shared full CSC pattern, `K` and `M` (n_f × nnz, row i = the values of X^i).

use std::path::{Path, PathBuf};

use hdf5::Group;
use hdf5_metno as hdf5;

use super::hdf5_file::{IoError, set_attr_f64, set_attr_i64, set_attr_strings, write_f64, write_u32};
use super::matrix_market::read_matrix_market;
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
}

/// Read a manifest (module doc).
pub fn read_manifest(path: &Path) -> Result<Manifest, IoError> {
    let text = std::fs::read_to_string(path).map_err(|cause| IoError::Fs { path: path.into(), what: "read the manifest".into(), cause })?;
    let bad = |line: usize, reason: String| IoError::Parse { path: path.into(), line, reason };
    let mut rows = text.lines().enumerate().map(|(k, l)| (k + 1, l.trim())).filter(|(_, l)| !l.is_empty() && !l.starts_with('#'));
    let (header_line, header) = rows.next().ok_or_else(|| bad(0, "empty manifest: expected a header 'K, M, <function names>'".into()))?;
    let names: Vec<String> = header.split(',').map(|f| f.trim().to_string()).collect();
    if names.len() < 3 || !names[0].eq_ignore_ascii_case("K") || !names[1].eq_ignore_ascii_case("M") || names.iter().any(String::is_empty) {
        return Err(bad(header_line, format!("expected a header 'K, M, <function names>', found '{header}'")));
    }
    let functions = names[2..].to_vec();
    let dir = path.parent().unwrap_or(Path::new("."));
    let mut samples = Vec::new();
    for (line, row) in rows {
        let fields: Vec<&str> = row.split(',').map(str::trim).collect();
        if fields.len() != names.len() {
            return Err(bad(line, format!("{} fields, the header has {}", fields.len(), names.len())));
        }
        let values = fields[2..]
            .iter()
            .zip(&functions)
            .map(|(v, name)| v.parse::<f64>().ok().filter(|x| x.is_finite()).ok_or_else(|| bad(line, format!("{name}: '{v}' is not a finite number"))))
            .collect::<Result<_, _>>()?;
        samples.push(Sample { stiffness: dir.join(fields[0]), mass: dir.join(fields[1]), values });
    }
    Ok(Manifest { functions, samples })
}

/// Read a manifest and its matrices and extract the affine components.
pub fn fit_manifest(path: &Path) -> Result<(Manifest, MatrixFit), LsqInputError> {
    let manifest = read_manifest(path)?;
    let read = |files: &dyn Fn(&Sample) -> &Path| manifest.samples.iter().map(|s| read_matrix_market(files(s))).collect::<Result<Vec<_>, _>>();
    let (k, m) = (read(&|s| &s.stiffness)?, read(&|s| &s.mass)?);
    let names: Vec<&str> = manifest.functions.iter().map(String::as_str).collect();
    let values: Vec<Vec<f64>> = manifest.samples.iter().map(|s| s.values.clone()).collect();
    let fit = extract_matrices(&names, &values, &k, &m).map_err(|source| LsqInputError::Fit { manifest: path.into(), source })?;
    Ok((manifest, fit))
}

/// Write the components into `group` (normally `/lsq`, module doc).
pub fn write_lsq(group: &Group, functions: &[String], fit: &MatrixFit) -> Result<(), IoError> {
    let names: Vec<&str> = functions.iter().map(String::as_str).collect();
    set_attr_strings(group, "functions", &names)?;
    let first = fit.stiffness.first().ok_or_else(|| IoError::invalid(group.filename(), "/lsq", "no components"))?;
    let n = first.nrows();
    set_attr_i64(group, "n", n as i64)?;
    set_attr_f64(group, "residual_K", fit.residual_stiffness)?;
    set_attr_f64(group, "residual_M", fit.residual_mass)?;
    let to_u32 = |v: &[usize]| -> Result<Vec<u32>, IoError> { v.iter().map(|&x| u32::try_from(x).map_err(|_| IoError::invalid(group.filename(), "/lsq", format!("index {x} exceeds u32")))).collect() };
    let pattern = first.pattern();
    write_u32(group, "col_offsets", &to_u32(pattern.major_offsets())?, &[n + 1])?;
    write_u32(group, "row_indices", &to_u32(pattern.minor_indices())?, &[pattern.nnz()])?;
    for (name, parts) in [("K", &fit.stiffness), ("M", &fit.mass)] {
        let values: Vec<f64> = parts.iter().flat_map(|x| x.values().iter().copied()).collect();
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
        std::fs::write(&path, "# sampled\nK, M, 1, E\nk1.mtx, m1.mtx, 1, 2.e11\n\nk2.mtx, m2.mtx, 1, 1.e11\n").unwrap();
        let m = read_manifest(&path).unwrap();
        assert_eq!(m.functions, vec!["1", "E"]);
        assert_eq!(m.samples[1], Sample { stiffness: dir.path().join("k2.mtx"), mass: dir.path().join("m2.mtx"), values: vec![1.0, 1.0e11] });
        for (text, needle) in [("M, K, E\n", ":1: expected a header"), ("K, M, E\nk, m\n", ":2: 2 fields"), ("K, M, E\nk, m, x\n", ":2: E: 'x'")] {
            std::fs::write(&path, text).unwrap();
            let message = read_manifest(&path).unwrap_err().to_string();
            assert!(message.contains(needle), "{message}");
        }
    }
}
