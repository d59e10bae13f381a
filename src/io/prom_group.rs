//! The `/prom` group (DESIGN.md §8): a pROM's parameters, affine functions and reduced
//! components, written by a `SOL PROM` run and read back by any deck with `ROM = 'file.h5'`.
//!
//! ```text
//! /prom            attrs n_full, n_red, params (names), ranges (low, high per parameter),
//!                        nominal (per parameter), functions (JSON: one entry per component i)
//! /prom/K/<i>, /prom/M/<i>   n_red × n_red, row-major; i = 0 .. n_f − 1, f_0 = 1 (constant)
//! /prom/damping    attrs alpha, beta (Rayleigh)
//! /prom/mass       (written when PMOR RIGID = REMOVE: a floating-frame body for multibody)
//!   grids          n_g grid ids (u32)
//!   positions      n_g × 3, undeformed positions r_0,j in basic
//!   nodal          n_f × n_g, m_j^k: nodal mass of grid j in component k (eq. 4.1)
//!   total          n_f, m^k (eq. 4.2)
//!   first_moment   n_f × 3, M̂_1^k = Σ_j m_j^k r_0,j (eq. A.11)
//!   second_moment  n_f × 3 × 3, M̂_3^k = Σ_j m_j^k r̃_0,j r̃_0,j (eq. A.13)
//! ```
//! Component k of `/prom/mass` uses the function of `/prom/K/<k>` and `/prom/M/<k>`: at p,
//! m_j(p) = Σ_k f_k(p) m_j^k, and likewise for the other mass datasets (eq. 4.8).
//! `functions` is JSON because a function is a small tree (coefficient kind, fixed inputs,
//! which parameter drives which input) that h5py users can still read with `json.loads`.

use std::path::Path;

use faer::Mat;
use hdf5::Group;
use hdf5_metno as hdf5;

use super::hdf5_file::{
    IoError, set_attr_f64, set_attr_f64s, set_attr_i64, set_attr_str, set_attr_strings, stamp,
    write_f64, write_u32,
};
use crate::rom::mass::AffineMasses;
use crate::rom::prom::{AffineFunction, Prom, PromParameter};

/// Write `prom` into `group` (normally the output file's `/prom`); `n_full` is the size of the
/// full model it was reduced from.
pub fn write_prom(group: &Group, prom: &Prom, n_full: usize) -> Result<(), IoError> {
    let invalid = |reason: String| IoError::invalid(group.filename(), "/prom", reason);
    prom.validate().map_err(|e| invalid(e.to_string()))?;
    set_attr_i64(group, "n_full", n_full as i64)?;
    set_attr_i64(group, "n_red", prom.size() as i64)?;
    let names: Vec<&str> = prom.parameters.iter().map(|p| p.name.as_str()).collect();
    set_attr_strings(group, "params", &names)?;
    let ranges: Vec<f64> = prom
        .parameters
        .iter()
        .flat_map(|p| [p.low, p.high])
        .collect();
    set_attr_f64s(group, "ranges", &ranges)?;
    set_attr_f64s(
        group,
        "nominal",
        &prom
            .parameters
            .iter()
            .map(|p| p.nominal)
            .collect::<Vec<_>>(),
    )?;
    let functions =
        serde_json::to_string(&prom.functions).map_err(|e| invalid(format!("functions: {e}")))?;
    set_attr_str(group, "functions", &functions)?;
    for (name, parts) in [("K", &prom.stiffness), ("M", &prom.mass)] {
        let sub = create_group(group, name)?;
        for (i, m) in parts.iter().enumerate() {
            let n = m.nrows();
            let row_major: Vec<f64> = (0..n * n).map(|k| m[(k / n, k % n)]).collect();
            write_f64(&sub, &i.to_string(), &row_major, &[n, n])?;
        }
    }
    let damping = create_group(group, "damping")?;
    set_attr_f64(&damping, "alpha", prom.alpha)?;
    set_attr_f64(&damping, "beta", prom.beta)?;
    Ok(())
}

/// Write the affine nodal masses of the body into `group` (normally `/prom/mass`, module doc);
/// `grids` are the ids of the grids in `masses.positions` order.
pub fn write_prom_masses(
    group: &Group,
    grids: &[u32],
    masses: &AffineMasses,
) -> Result<(), IoError> {
    let (n_f, n_g) = (masses.nodal.len(), grids.len());
    if masses.positions.len() != n_g || masses.nodal.iter().any(|m| m.len() != n_g) {
        return Err(IoError::invalid(
            group.filename(),
            "/prom/mass",
            format!("{n_g} grid ids for {} positions", masses.positions.len()),
        ));
    }
    write_u32(group, "grids", grids, &[n_g])?;
    write_f64(group, "positions", &masses.positions.concat(), &[n_g, 3])?;
    write_f64(group, "nodal", &masses.nodal.concat(), &[n_f, n_g])?;
    write_f64(group, "total", &masses.total(), &[n_f])?;
    write_f64(
        group,
        "first_moment",
        &masses.first_moment().concat(),
        &[n_f, 3],
    )?;
    write_f64(
        group,
        "second_moment",
        &masses.second_moment().concat(),
        &[n_f, 3, 3],
    )?;
    Ok(())
}

/// Opens a pROM artifact read-only, without HDF5 file locking: artifacts are inputs that many
/// runs (and the tests' threads) read at once, and paraflex never writes a file in place (each
/// output is written under a temporary name and renamed when complete), so a reader cannot see
/// a partial file; the lock would only make concurrent readers fail with EAGAIN.
pub(crate) fn open_artifact(path: &Path) -> Result<hdf5::File, IoError> {
    hdf5::File::with_options()
        .with_fapl(|fapl| fapl.file_locking(false))
        .open(path)
        .map_err(|e| IoError::hdf5(path, "open for reading", e))
}

/// The affine nodal masses of a pROM artifact (`/prom/mass`: grid ids and masses), `None` when
/// the build did not write them (RIGID = KEEP).
pub fn read_prom_masses(
    path: impl AsRef<Path>,
) -> Result<Option<(Vec<u32>, AffineMasses)>, IoError> {
    let path = path.as_ref();
    let file = open_artifact(path)?;
    let Ok(group) = file.group("prom/mass") else {
        return Ok(None);
    };
    let grids = group
        .dataset("grids")
        .and_then(|d| d.read_raw::<u32>())
        .map_err(|e| IoError::hdf5(path, "read /prom/mass/grids", e))?;
    let read = |name: &str| {
        group
            .dataset(name)
            .and_then(|d| d.read_raw::<f64>())
            .map_err(|e| IoError::hdf5(path, format!("read /prom/mass/{name}"), e))
    };
    let (positions, nodal) = (read("positions")?, read("nodal")?);
    let n_g = grids.len();
    if positions.len() != 3 * n_g || n_g == 0 || nodal.len() % n_g != 0 {
        return Err(IoError::malformed(
            path,
            "/prom/mass",
            format!(
                "{n_g} grids, {} position values, {} nodal mass values",
                positions.len(),
                nodal.len()
            ),
        ));
    }
    let masses = AffineMasses {
        positions: positions.chunks(3).map(|r| [r[0], r[1], r[2]]).collect(),
        nodal: nodal.chunks(n_g).map(<[f64]>::to_vec).collect(),
    };
    Ok(Some((grids, masses)))
}

fn create_group(parent: &Group, name: &str) -> Result<Group, IoError> {
    let group = parent.create_group(name).map_err(|e| {
        IoError::hdf5(
            parent.filename(),
            format!("create group {}/{name}", parent.name()),
            e,
        )
    })?;
    stamp(&group)?;
    Ok(group)
}

/// Read the pROM of a paraflex output file; returns it with `n_full`. Anything missing or
/// inconsistent is an error naming the file and the object.
pub fn read_prom(path: impl AsRef<Path>) -> Result<(Prom, usize), IoError> {
    let path = path.as_ref();
    let file = open_artifact(path)?;
    let prom = file.group("prom").map_err(|_| IoError::NotParaflex {
        path: path.into(),
        reason: "no /prom group (was it written by a SOL PROM run?)".into(),
    })?;
    let bad = |what: &str, reason: String| IoError::malformed(path, what, reason);
    let hdf = |what: String| move |e| IoError::hdf5(path, what, e);
    let int = |name: &str| {
        prom.attr(name)
            .and_then(|a| a.read_scalar::<i64>())
            .map_err(hdf(format!("read attribute /prom {name}")))
    };
    let f64s = |name: &str| {
        prom.attr(name)
            .and_then(|a| a.read_raw::<f64>())
            .map_err(hdf(format!("read attribute /prom {name}")))
    };
    let (n_full, n_red) = (int("n_full")?, int("n_red")?);
    let names: Vec<String> = prom
        .attr("params")
        .and_then(|a| a.read_raw::<hdf5::types::VarLenUnicode>())
        .map_err(hdf("read attribute /prom params".into()))?
        .iter()
        .map(|s| s.as_str().to_string())
        .collect();
    let (ranges, nominal) = (f64s("ranges")?, f64s("nominal")?);
    if ranges.len() != 2 * names.len() || nominal.len() != names.len() {
        return Err(bad(
            "/prom",
            format!(
                "{} parameters but {} range values and {} nominal values",
                names.len(),
                ranges.len(),
                nominal.len()
            ),
        ));
    }
    let parameters = names
        .into_iter()
        .enumerate()
        .map(|(j, name)| PromParameter {
            name,
            low: ranges[2 * j],
            high: ranges[2 * j + 1],
            nominal: nominal[j],
        })
        .collect();
    let json = prom
        .attr("functions")
        .and_then(|a| a.read_scalar::<hdf5::types::VarLenUnicode>())
        .map_err(hdf("read attribute /prom functions".into()))?;
    let functions: Vec<AffineFunction> =
        serde_json::from_str(json.as_str()).map_err(|e| bad("/prom functions", e.to_string()))?;
    let n =
        usize::try_from(n_red).map_err(|_| bad("/prom n_red", format!("{n_red} is negative")))?;
    let read_parts = |name: &str| -> Result<Vec<Mat<f64>>, IoError> {
        (0..functions.len())
            .map(|i| {
                let what = format!("/prom/{name}/{i}");
                let data = prom
                    .dataset(&format!("{name}/{i}"))
                    .and_then(|d| d.read_raw::<f64>())
                    .map_err(hdf(format!("read {what}")))?;
                if data.len() != n * n {
                    return Err(bad(
                        &what,
                        format!("{} values, expected n_red² = {}", data.len(), n * n),
                    ));
                }
                Ok(Mat::from_fn(n, n, |r, c| data[r * n + c]))
            })
            .collect()
    };
    let (stiffness, mass) = (read_parts("K")?, read_parts("M")?);
    let damping = prom
        .group("damping")
        .map_err(hdf("open /prom/damping".into()))?;
    let coefficient = |name: &str| {
        damping
            .attr(name)
            .and_then(|a| a.read_scalar::<f64>())
            .map_err(hdf(format!("read attribute /prom/damping {name}")))
    };
    let result = Prom {
        parameters,
        functions,
        stiffness,
        mass,
        alpha: coefficient("alpha")?,
        beta: coefficient("beta")?,
    };
    result.validate().map_err(|e| bad("/prom", e.to_string()))?;
    let n_full = usize::try_from(n_full)
        .map_err(|_| bad("/prom n_full", format!("{n_full} is negative")))?;
    Ok((result, n_full))
}

/// The load inputs of a pROM (`/prom/inputs`): DOF names ("GRID:component") and S_r
/// (n_red × k). A pROM built without BSET has none (empty names, n_red × 0).
pub fn read_prom_inputs(
    path: impl AsRef<Path>,
    n_red: usize,
) -> Result<(Vec<String>, Mat<f64>), IoError> {
    let path = path.as_ref();
    let file = open_artifact(path)?;
    let Ok(group) = file.group("prom/inputs") else {
        return Ok((Vec::new(), Mat::zeros(n_red, 0)));
    };
    let names: Vec<String> = group
        .dataset("names")
        .and_then(|d| d.read_raw::<hdf5::types::VarLenUnicode>())
        .map_err(|e| IoError::hdf5(path, "read /prom/inputs/names", e))?
        .iter()
        .map(|s| s.as_str().to_string())
        .collect();
    let data = group
        .dataset("S_r")
        .and_then(|d| d.read_raw::<f64>())
        .map_err(|e| IoError::hdf5(path, "read /prom/inputs/S_r", e))?;
    let k = names.len();
    if data.len() != n_red * k {
        return Err(IoError::malformed(
            path,
            "/prom/inputs/S_r",
            format!(
                "{} values, expected n_red × inputs = {n_red} × {k}",
                data.len()
            ),
        ));
    }
    Ok((names, Mat::from_fn(n_red, k, |i, j| data[i * k + j])))
}

/// A pROM's sensors as stored: names, kinds and H_r (s × n_red).
pub type PromSensors = (Vec<String>, Vec<String>, Mat<f64>);

/// The sensors of a pROM (`/prom/sensors`): names, kinds (`DISP`, `VEL`, `ACCEL`) and H_r
/// (s × n_red). None when the build had no SENSOR.
pub fn read_prom_sensors(path: impl AsRef<Path>, n_red: usize) -> Result<PromSensors, IoError> {
    let path = path.as_ref();
    let file = open_artifact(path)?;
    let Ok(group) = file.group("prom/sensors") else {
        return Ok((Vec::new(), Vec::new(), Mat::zeros(0, n_red)));
    };
    let strings = |name: &str| -> Result<Vec<String>, IoError> {
        Ok(group
            .dataset(name)
            .and_then(|d| d.read_raw::<hdf5::types::VarLenUnicode>())
            .map_err(|e| IoError::hdf5(path, format!("read /prom/sensors/{name}"), e))?
            .iter()
            .map(|s| s.as_str().to_string())
            .collect())
    };
    let (names, kinds) = (strings("names")?, strings("kind")?);
    let data = group
        .dataset("H_r")
        .and_then(|d| d.read_raw::<f64>())
        .map_err(|e| IoError::hdf5(path, "read /prom/sensors/H_r", e))?;
    let s = names.len();
    if data.len() != s * n_red || kinds.len() != s {
        return Err(IoError::malformed(
            path,
            "/prom/sensors",
            format!(
                "{s} names, {} kinds, {} values for n_red = {n_red}",
                kinds.len(),
                data.len()
            ),
        ));
    }
    Ok((
        names,
        kinds,
        Mat::from_fn(s, n_red, |i, j| data[i * n_red + j]),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fe::affine::{Coefficient, CoefficientValues};
    use crate::io::OutputFile;
    use crate::rom::prom::CoefficientInput;

    fn sample() -> Prom {
        let fixed = CoefficientValues {
            e: 7e10,
            nu: 0.33,
            rho: 2700.0,
            ..Default::default()
        };
        Prom {
            parameters: vec![
                PromParameter {
                    name: "E_AL".into(),
                    low: 4.2e10,
                    high: 9.8e10,
                    nominal: 7e10,
                },
                PromParameter {
                    name: "RHO_AL".into(),
                    low: 2000.0,
                    high: 3000.0,
                    nominal: 2700.0,
                },
            ],
            functions: vec![
                AffineFunction::constant(),
                AffineFunction {
                    coefficient: Coefficient::E,
                    fixed,
                    driven_by: vec![(CoefficientInput::E, 0)],
                },
                AffineFunction {
                    coefficient: Coefficient::Rho,
                    fixed,
                    driven_by: vec![(CoefficientInput::Rho, 1)],
                },
            ],
            stiffness: (0..3)
                .map(|s| Mat::from_fn(2, 2, |i, j| (s * 4 + i * 2 + j) as f64 + 0.5))
                .collect(),
            mass: (0..3)
                .map(|s| Mat::from_fn(2, 2, |i, j| -((s * 4 + i * 2 + j) as f64) / 3.0))
                .collect(),
            alpha: 0.25,
            beta: 1e-5,
        }
    }

    /// Everything written is read back bit for bit (HDF5 stores f64 exactly; JSON uses
    /// round-trip float formatting), including the row-major layout of non-symmetric data.
    #[test]
    fn round_trip_is_exact() {
        let _guard = crate::io::hdf5_file::hdf5_test_guard();
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("p.h5");
        let prom = sample();
        let out = OutputFile::create(&path).unwrap();
        write_prom(&out.group("prom").unwrap(), &prom, 1234).unwrap();
        out.commit().unwrap();
        let (back, n_full) = read_prom(&path).unwrap();
        assert_eq!(n_full, 1234);
        assert_eq!(back.parameters, prom.parameters);
        assert_eq!(back.functions, prom.functions);
        assert_eq!((back.alpha, back.beta), (prom.alpha, prom.beta));
        for (a, b) in back
            .stiffness
            .iter()
            .chain(&back.mass)
            .zip(prom.stiffness.iter().chain(&prom.mass))
        {
            assert_eq!(a, b);
        }
    }

    #[test]
    fn a_file_without_prom_is_refused_with_its_name() {
        let _guard = crate::io::hdf5_file::hdf5_test_guard();
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("plain.h5");
        OutputFile::create(&path).unwrap().commit().unwrap();
        let message = read_prom(&path).unwrap_err().to_string();
        assert!(
            message.contains("plain.h5") && message.contains("no /prom group"),
            "{message}"
        );
    }
}
