//! An HDF5 output file that appears under its final name only when complete.
//!
//! [`OutputFile::create`] writes to `<out>.tmp-<pid>` in the same directory;
//! [`OutputFile::commit`] flushes, closes and renames it to `<out>`. Dropping an `OutputFile`
//! without committing deletes the temporary file, so a run that fails (validation, solver,
//! I/O) never leaves a half-written output behind (DESIGN.md §3: "Nothing is written to the
//! output file of a run that failed validation"). The rename is atomic on POSIX file systems:
//! an older `<out>` is replaced in one step.
//!
//! Every group created through [`OutputFile::group`], and the root group, carries the attributes
//! `paraflex_version` ([`crate::VERSION`]) and `schema` ([`SCHEMA_VERSION`]) (DESIGN.md §8).
//! The free functions write typed datasets with explicit shapes (row-major) and attributes;
//! they take any [`Group`] / [`Location`] so other modules can fill their own groups.

use std::path::{Path, PathBuf};

use hdf5::types::VarLenUnicode;
use hdf5::{Dataset, Group, H5Type, Location};
use hdf5_metno as hdf5;

/// Schema version written into the `schema` attribute of every group.
pub const SCHEMA_VERSION: i64 = 1;

/// Errors of HDF5/XDMF output and inspection. Every variant names the file it concerns.
#[derive(Debug, thiserror::Error)]
pub enum IoError {
    /// The HDF5 library refused an operation.
    #[error("{}: cannot {what}: {cause}", .path.display())]
    Hdf5 {
        /// File concerned.
        path: PathBuf,
        /// What was being done, e.g. "write dataset /model/xyz".
        what: String,
        /// The HDF5 library's error.
        cause: hdf5::Error,
    },
    /// A file-system operation failed (rename, remove, write of the XDMF file).
    #[error("{}: cannot {what}: {cause}", .path.display())]
    Fs {
        /// File concerned.
        path: PathBuf,
        /// What was being done.
        what: String,
        /// The operating system's error.
        cause: std::io::Error,
    },
    /// The file is a valid HDF5 file but was not written by paraflex.
    #[error("{}: not a paraflex output file: {reason}", .path.display())]
    NotParaflex {
        /// File concerned.
        path: PathBuf,
        /// Why it was rejected.
        reason: String,
    },
    /// A text input file (Matrix Market, manifest) cannot be read as what it should be.
    #[error("{}:{line}: {reason}", .path.display())]
    Parse {
        /// File concerned.
        path: PathBuf,
        /// 1-based line (0: the file as a whole).
        line: usize,
        /// What is wrong.
        reason: String,
    },
    /// Data read from a file is not what it should be (missing or misshapen dataset, value out
    /// of range, ...).
    #[error("{}: {what}: {reason}", .path.display())]
    Malformed {
        /// File concerned.
        path: PathBuf,
        /// Object being read, e.g. "/prom/inputs/S_r".
        what: String,
        /// What is wrong.
        reason: String,
    },
    /// The data handed to a writer is inconsistent (shape mismatch, index out of range, ...).
    #[error("{}: cannot write {what}: {reason}", .path.display())]
    InvalidData {
        /// File concerned.
        path: PathBuf,
        /// Object being written, e.g. "/model/elements/CQUAD4/connectivity".
        what: String,
        /// What is inconsistent.
        reason: String,
    },
}

impl IoError {
    /// Wraps an HDF5 library error with the file and the operation.
    pub(crate) fn hdf5(
        path: impl Into<PathBuf>,
        what: impl Into<String>,
        cause: hdf5::Error,
    ) -> Self {
        IoError::Hdf5 {
            path: path.into(),
            what: what.into(),
            cause,
        }
    }

    /// Wraps an operating-system error with the file and the operation.
    pub(crate) fn fs(
        path: impl Into<PathBuf>,
        what: impl Into<String>,
        cause: std::io::Error,
    ) -> Self {
        IoError::Fs {
            path: path.into(),
            what: what.into(),
            cause,
        }
    }

    /// Reports data read from a file that is not what it should be.
    pub(crate) fn malformed(
        path: impl Into<PathBuf>,
        what: impl Into<String>,
        reason: impl Into<String>,
    ) -> Self {
        IoError::Malformed {
            path: path.into(),
            what: what.into(),
            reason: reason.into(),
        }
    }

    /// Reports inconsistent data handed to a writer.
    pub(crate) fn invalid(
        path: impl Into<PathBuf>,
        what: impl Into<String>,
        reason: impl Into<String>,
    ) -> Self {
        IoError::InvalidData {
            path: path.into(),
            what: what.into(),
            reason: reason.into(),
        }
    }
}

/// An HDF5 file being written under a temporary name; see the module documentation.
pub struct OutputFile {
    /// `None` after commit (or after a failed close).
    file: Option<hdf5::File>,
    tmp_path: PathBuf,
    final_path: PathBuf,
}

impl OutputFile {
    /// Creates `<path>.tmp-<pid>` (truncating a stale one) with a stamped root group.
    ///
    /// The final file `path` is not touched until [`commit`](Self::commit).
    pub fn create(path: impl AsRef<Path>) -> Result<Self, IoError> {
        let final_path = path.as_ref().to_path_buf();
        // refuse before any work a name the final rename cannot take
        if final_path.is_dir() {
            return Err(IoError::Fs {
                path: final_path,
                what: "write the output there".into(),
                cause: std::io::Error::new(std::io::ErrorKind::IsADirectory, "it is a directory"),
            });
        }
        if let Some(dir) = final_path
            .parent()
            .filter(|d| !d.as_os_str().is_empty() && !d.is_dir())
        {
            return Err(IoError::Fs {
                path: final_path.clone(),
                what: "write the output there".into(),
                cause: std::io::Error::new(
                    std::io::ErrorKind::NotFound,
                    format!("directory {} does not exist", dir.display()),
                ),
            });
        }
        let tmp_path = temp_path_for(&final_path);
        // Strong close degree: `close()` really closes the file even if a caller still holds a
        // group or dataset handle, so the rename below never races an open HDF5 file.
        let file = hdf5::File::with_options()
            .with_fapl(|fapl| fapl.fclose_degree(hdf5::file::FileCloseDegree::Strong))
            .create(&tmp_path)
            .map_err(|e| IoError::hdf5(&tmp_path, "create HDF5 file", e))?;
        let out = OutputFile {
            file: Some(file),
            tmp_path,
            final_path,
        };
        stamp(out.root()?)?;
        Ok(out)
    }

    /// The name the file will have after [`commit`](Self::commit).
    pub fn path(&self) -> &Path {
        &self.final_path
    }

    /// The temporary name the file is being written under.
    pub fn temp_path(&self) -> &Path {
        &self.tmp_path
    }

    /// The root group `/`.
    pub fn root(&self) -> Result<&Group, IoError> {
        match &self.file {
            Some(file) => Ok(file),
            None => Err(IoError::invalid(
                &self.final_path,
                "/",
                "file is already closed",
            )),
        }
    }

    /// Opens the group at `path` (e.g. `"model/elements/CQUAD4"` or `"/results/1/modal"`),
    /// creating missing levels; each newly created level gets the `paraflex_version` and
    /// `schema` attributes.
    pub fn group(&self, path: &str) -> Result<Group, IoError> {
        let mut group = self.root()?.clone();
        for part in path.split('/').filter(|p| !p.is_empty()) {
            group = if group.link_exists(part) {
                group
                    .group(part)
                    .map_err(|e| IoError::hdf5(&self.tmp_path, format!("open group {path}"), e))?
            } else {
                let created = group.create_group(part).map_err(|e| {
                    IoError::hdf5(&self.tmp_path, format!("create group {path}"), e)
                })?;
                stamp(&created)?;
                created
            };
        }
        Ok(group)
    }

    /// Flushes and closes the file, then renames it to its final name. Returns the final path.
    pub fn commit(mut self) -> Result<PathBuf, IoError> {
        if let Some(file) = self.file.take() {
            file.flush()
                .map_err(|e| IoError::hdf5(&self.tmp_path, "flush", e))?;
            file.close()
                .map_err(|e| IoError::hdf5(&self.tmp_path, "close", e))?;
        }
        std::fs::rename(&self.tmp_path, &self.final_path).map_err(|e| {
            IoError::fs(
                &self.final_path,
                format!("rename {} to it", self.tmp_path.display()),
                e,
            )
        })?;
        // Nothing left for `Drop` to remove.
        self.tmp_path = PathBuf::new();
        Ok(self.final_path.clone())
    }
}

impl Drop for OutputFile {
    fn drop(&mut self) {
        if let Some(file) = self.file.take() {
            // Errors are irrelevant: the file is being discarded.
            let _ = file.close();
        }
        if !self.tmp_path.as_os_str().is_empty() {
            let _ = std::fs::remove_file(&self.tmp_path);
        }
    }
}

impl std::fmt::Debug for OutputFile {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("OutputFile")
            .field("final_path", &self.final_path)
            .field("tmp_path", &self.tmp_path)
            .field("open", &self.file.is_some())
            .finish()
    }
}

/// `<path>.tmp-<pid>`, in the same directory so the final rename stays on one file system.
pub fn temp_path_for(path: &Path) -> PathBuf {
    let mut name = path.as_os_str().to_owned();
    name.push(format!(".tmp-{}", std::process::id()));
    PathBuf::from(name)
}

/// Writes `bytes` to `<path>.tmp-<pid>` and renames it to `path`; removes the temporary file if
/// anything fails.
pub(crate) fn write_file_atomically(path: &Path, bytes: &[u8]) -> Result<(), IoError> {
    let tmp = temp_path_for(path);
    let result = std::fs::write(&tmp, bytes)
        .map_err(|e| IoError::fs(&tmp, "write", e))
        .and_then(|()| {
            std::fs::rename(&tmp, path)
                .map_err(|e| IoError::fs(path, format!("rename {} to it", tmp.display()), e))
        });
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}

/// Adds the `paraflex_version` and `schema` attributes to a group.
/// Sets the `paraflex_version` and `schema` attributes every group carries (DESIGN.md §8).
pub(crate) fn stamp(group: &Group) -> Result<(), IoError> {
    set_attr_str(group, "paraflex_version", crate::VERSION)?;
    set_attr_i64(group, "schema", SCHEMA_VERSION)
}

/// Full HDF5 name of `name` inside `group`, for messages.
fn object_name(group: &Location, name: &str) -> String {
    let parent = group.name();
    if parent.ends_with('/') {
        format!("{parent}{name}")
    } else {
        format!("{parent}/{name}")
    }
}

/// Writes a dataset of `shape` (row-major) from a flat slice.
fn write_array<T: H5Type>(
    group: &Group,
    name: &str,
    data: &[T],
    shape: &[usize],
) -> Result<Dataset, IoError> {
    let what = object_name(group, name);
    let expected: usize = shape.iter().product();
    if expected != data.len() {
        return Err(IoError::invalid(
            group.filename(),
            &what,
            format!(
                "shape {shape:?} needs {expected} values, got {}",
                data.len()
            ),
        ));
    }
    let ds = group
        .new_dataset::<T>()
        .shape(shape)
        .create(name)
        .map_err(|e| IoError::hdf5(group.filename(), format!("create dataset {what}"), e))?;
    if !data.is_empty() {
        ds.write_raw(data)
            .map_err(|e| IoError::hdf5(group.filename(), format!("write dataset {what}"), e))?;
    }
    Ok(ds)
}

/// Writes an `f64` dataset of `shape` (row-major, e.g. `[n, 3]`) from a flat slice.
pub fn write_f64(
    group: &Group,
    name: &str,
    data: &[f64],
    shape: &[usize],
) -> Result<Dataset, IoError> {
    write_array(group, name, data, shape)
}

/// Writes a dense matrix as a row-major `f64` dataset of its shape.
pub fn write_mat(group: &Group, name: &str, m: &faer::Mat<f64>) -> Result<Dataset, IoError> {
    let data: Vec<f64> = (0..m.nrows())
        .flat_map(|i| (0..m.ncols()).map(move |j| m[(i, j)]))
        .collect();
    write_array(group, name, &data, &[m.nrows(), m.ncols()])
}

/// Writes a complex dataset of `shape` (row-major) as h5py does (compound of `r`, `i`), so
/// `h5py` reads it as a numpy complex array.
pub fn write_c64(
    group: &Group,
    name: &str,
    data: &[faer::c64],
    shape: &[usize],
) -> Result<Dataset, IoError> {
    write_array(group, name, data, shape)
}

/// Writes a `u32` dataset of `shape` (row-major) from a flat slice.
pub fn write_u32(
    group: &Group,
    name: &str,
    data: &[u32],
    shape: &[usize],
) -> Result<Dataset, IoError> {
    write_array(group, name, data, shape)
}

/// Writes an `n × 3` `f64` dataset from rows.
pub fn write_rows3(group: &Group, name: &str, rows: &[[f64; 3]]) -> Result<Dataset, IoError> {
    write_array(group, name, rows.as_flattened(), &[rows.len(), 3])
}

/// Converts strings to HDF5 variable-length UTF-8 (what h5py writes for `str`).
fn to_varlen(loc: &Location, what: &str, values: &[&str]) -> Result<Vec<VarLenUnicode>, IoError> {
    values
        .iter()
        .map(|s| {
            s.parse::<VarLenUnicode>().map_err(|e| {
                IoError::invalid(
                    loc.filename(),
                    what,
                    format!("string {s:?} not storable: {e}"),
                )
            })
        })
        .collect()
}

/// Writes a 1-D dataset of variable-length UTF-8 strings (h5py reads them as `bytes`/`str`).
pub fn write_strings(group: &Group, name: &str, values: &[&str]) -> Result<Dataset, IoError> {
    let what = object_name(group, name);
    let data = to_varlen(group, &what, values)?;
    write_array(group, name, &data, &[data.len()])
}

/// Creates or replaces attribute `name` with the value written by `write`.
fn replace_attr<T: H5Type>(
    loc: &Location,
    name: &str,
    shape: &[usize],
    write: impl FnOnce(&hdf5::Attribute) -> hdf5::Result<()>,
) -> Result<(), IoError> {
    let what = format!("attribute {name} of {}", loc.name());
    let err = |e| IoError::hdf5(loc.filename(), format!("write {what}"), e);
    if loc.attr_names().map_err(err)?.iter().any(|n| n == name) {
        loc.delete_attr(name).map_err(err)?;
    }
    let builder = loc.new_attr::<T>();
    let attr = if shape.is_empty() {
        builder.create(name)
    } else {
        builder.shape(shape).create(name)
    }
    .map_err(err)?;
    write(&attr).map_err(err)
}

/// Sets a scalar UTF-8 string attribute.
pub fn set_attr_str(loc: &Location, name: &str, value: &str) -> Result<(), IoError> {
    let v = to_varlen(loc, &format!("attribute {name}"), &[value])?;
    replace_attr::<VarLenUnicode>(loc, name, &[], |a| a.write_scalar(&v[0]))
}

/// Sets a 1-D array-of-strings attribute.
pub fn set_attr_strings(loc: &Location, name: &str, values: &[&str]) -> Result<(), IoError> {
    let v = to_varlen(loc, &format!("attribute {name}"), values)?;
    replace_attr::<VarLenUnicode>(loc, name, &[v.len()], |a| a.write_raw(&v[..]))
}

/// Sets a scalar 64-bit integer attribute.
pub fn set_attr_i64(loc: &Location, name: &str, value: i64) -> Result<(), IoError> {
    replace_attr::<i64>(loc, name, &[], |a| a.write_scalar(&value))
}

/// Sets a scalar `f64` attribute.
pub fn set_attr_f64(loc: &Location, name: &str, value: f64) -> Result<(), IoError> {
    replace_attr::<f64>(loc, name, &[], |a| a.write_scalar(&value))
}

/// Sets a 1-D `f64` array attribute.
pub fn set_attr_f64s(loc: &Location, name: &str, values: &[f64]) -> Result<(), IoError> {
    replace_attr::<f64>(loc, name, &[values.len()], |a| a.write_raw(values))
}

/// Serializes tests that spawn processes against tests that hold HDF5 files open.
///
/// HDF5 opens files without `O_CLOEXEC` and holds an `flock` on them; a child process spawned
/// while another test thread has a file open inherits the descriptor and keeps the lock after
/// the parent closes it, so a later open fails with "unable to lock file". Tests that open
/// HDF5 files take [`shared`](std::sync::RwLock::read) access, tests that spawn take exclusive.
#[cfg(test)]
pub(crate) static TEST_SPAWN_LOCK: std::sync::RwLock<()> = std::sync::RwLock::new(());

/// Shared guard for tests that open HDF5 files (see [`TEST_SPAWN_LOCK`]).
#[cfg(test)]
pub(crate) fn hdf5_test_guard() -> std::sync::RwLockReadGuard<'static, ()> {
    TEST_SPAWN_LOCK.read().unwrap_or_else(|e| e.into_inner())
}

/// Exclusive guard for tests that spawn child processes (see [`TEST_SPAWN_LOCK`]).
#[cfg(test)]
pub(crate) fn spawn_test_guard() -> std::sync::RwLockWriteGuard<'static, ()> {
    TEST_SPAWN_LOCK.write().unwrap_or_else(|e| e.into_inner())
}

/// The repository's Python (`.venv/bin/python`, with h5py) for the checks that read paraflex's
/// files with the users' tools. `make test` creates the venv before `cargo test`; without it
/// these checks fail rather than pass unchecked.
#[cfg(test)]
pub(crate) fn venv_python() -> std::path::PathBuf {
    let python = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(".venv/bin/python");
    assert!(
        python.exists(),
        "{} is missing: run `make test` (it creates the venv from tools/requirements.txt)",
        python.display()
    );
    python
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn commit_renames_and_stamps_groups() {
        let _guard = hdf5_test_guard();
        let dir = tempfile::tempdir().expect("tempdir");
        let out = dir.path().join("a.h5");
        let f = OutputFile::create(&out).expect("create");
        assert!(f.temp_path().exists());
        assert!(!out.exists());
        let g = f.group("/results/1/modal").expect("group");
        write_f64(&g, "frequency_hz", &[1.0, 2.0], &[2]).expect("write");
        write_strings(&g, "names", &["a", "b"]).expect("strings");
        set_attr_f64s(&g, "range", &[0.5, 2.0]).expect("attr");
        set_attr_i64(&g, "n", 3).expect("attr");
        set_attr_i64(&g, "n", 4).expect("attr replaced");
        let tmp = f.temp_path().to_path_buf();
        assert_eq!(f.commit().expect("commit"), out);
        assert!(out.exists() && !tmp.exists());

        let h = hdf5::File::open(&out).expect("open");
        for path in ["/", "/results", "/results/1", "/results/1/modal"] {
            let g = h.group(path).expect("group");
            let v: VarLenUnicode = g.attr("paraflex_version").unwrap().read_scalar().unwrap();
            assert_eq!(v.as_str(), crate::VERSION);
            assert_eq!(g.attr("schema").unwrap().read_scalar::<i64>().unwrap(), 1);
        }
        let g = h.group("results/1/modal").unwrap();
        assert_eq!(g.attr("n").unwrap().read_scalar::<i64>().unwrap(), 4);
        assert_eq!(
            g.dataset("frequency_hz")
                .unwrap()
                .read_raw::<f64>()
                .unwrap(),
            [1.0, 2.0]
        );
        let names = g
            .dataset("names")
            .unwrap()
            .read_raw::<VarLenUnicode>()
            .unwrap();
        assert_eq!(
            names.iter().map(|s| s.as_str()).collect::<Vec<_>>(),
            ["a", "b"]
        );
    }

    #[test]
    fn drop_without_commit_leaves_nothing() {
        let _guard = hdf5_test_guard();
        let dir = tempfile::tempdir().expect("tempdir");
        let out = dir.path().join("b.h5");
        {
            let f = OutputFile::create(&out).expect("create");
            let g = f.group("model").expect("group");
            write_u32(&g, "grid_ids", &[1, 2, 3], &[3]).expect("write");
        }
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
    }

    #[test]
    fn shape_mismatch_is_an_error_naming_the_dataset() {
        let _guard = hdf5_test_guard();
        let dir = tempfile::tempdir().expect("tempdir");
        let f = OutputFile::create(dir.path().join("c.h5")).expect("create");
        let g = f.group("x").expect("group");
        let err = write_f64(&g, "bad", &[1.0, 2.0, 3.0], &[2, 3]).unwrap_err();
        let msg = err.to_string();
        assert!(msg.contains("/x/bad") && msg.contains("c.h5"), "{msg}");
        // Empty datasets are fine.
        write_f64(&g, "empty", &[], &[0, 3]).expect("empty");
    }

    #[test]
    fn create_in_missing_directory_names_the_path() {
        let _guard = hdf5_test_guard();
        let dir = tempfile::tempdir().expect("tempdir");
        let out = dir.path().join("no/such/dir/d.h5");
        let msg = OutputFile::create(&out).unwrap_err().to_string();
        assert!(
            msg.contains("no/such/dir/d.h5") && msg.contains("does not exist"),
            "{msg}"
        );
    }

    /// An output name that is a directory is refused at creation, before the run computes
    /// anything (the final rename used to fail only at the end).
    #[test]
    fn create_over_a_directory_is_refused_up_front() {
        let _guard = hdf5_test_guard();
        let dir = tempfile::tempdir().expect("tempdir");
        let out = dir.path().join("taken.h5");
        std::fs::create_dir(&out).expect("dir");
        let msg = OutputFile::create(&out).unwrap_err().to_string();
        assert!(
            msg.contains("taken.h5") && msg.contains("directory"),
            "{msg}"
        );
        assert_eq!(
            std::fs::read_dir(dir.path()).expect("list").count(),
            1,
            "no temporary file left"
        );
    }
}
