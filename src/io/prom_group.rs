//! The `/prom` group (DESIGN.md §8): a pROM's parameters, affine functions and reduced
//! components, written by a `SOL PROM` run and read back by any deck with `ROM = 'file.h5'`.
//!
//! ```text
//! /prom            attrs n_full, n_red, params (names), ranges (low, high per parameter),
//!                        nominal (per parameter), functions (JSON: one entry per component i)
//! /prom/K/<i>, /prom/M/<i>   n_red × n_red, row-major; i = 0 .. n_f − 1, f_0 = 1 (constant)
//! /prom/damping    attrs alpha, beta (Rayleigh)
//! (written when PMOR RIGID = REMOVE: a floating-frame body for multibody, DESIGN.md §11)
//! /prom/nodal_mass/grids       n_g grid ids (u32)
//! /prom/nodal_mass/positions   n_g × 3, undeformed positions r_0,j in basic
//! /prom/nodal_mass/<i>         n_g, m_j^i: nodal mass of grid j in component i (eq. 4.1)
//! /prom/invariants/<k>/<i>     invariant k of component i (eq. 4.8): k = 0 the mass m^i
//!                              (eq. 4.2, shape 1), k = 1 … 9 M̂₁ … M̂₉ (eq. A.11–A.19, shapes
//!                              in `rom::invariants`), row-major
//! /prom/interface/grids        n_b interface grid ids (the ASET1 grids)
//! /prom/interface/rows         n_b × 6 × n_red: basis rows T1 T2 T3 R1 R2 R3 in basic
//! (written when the SOL PROM subcase has `DISPLACEMENT = ALL | set`; any PMOR RIGID)
//! /prom/basis/grids            n_s ids of the selected grids, in /model/grid_ids order
//! /prom/basis/rows             n_s × 6 × n_red: their basis rows T1 T2 T3 R1 R2 R3 in basic
//! ```
//! Component i of the body datasets uses the function of `/prom/K/<i>` and `/prom/M/<i>`: at p,
//! m_j(p) = Σ_i f_i(p) m_j^i, and likewise every invariant (eq. 4.8).
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
use crate::rom::invariants::{InterfaceRows, MassInvariants};
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

/// What a `RIGID = REMOVE` artifact holds for a multibody body (module doc): the affine nodal
/// masses with their grids, the affine components of the mass invariants (one per component,
/// in the pROM's function order) and the interface rows.
#[derive(Debug, Clone, PartialEq)]
pub struct PromBody {
    pub grids: Vec<u32>,
    pub masses: AffineMasses,
    pub invariants: Vec<MassInvariants>,
    pub interface: InterfaceRows,
}

/// Write `body` into `prom` (normally the output file's `/prom`, module doc).
pub fn write_prom_body(prom: &Group, body: &PromBody) -> Result<(), IoError> {
    let masses = &body.masses;
    let n_g = body.grids.len();
    if masses.positions.len() != n_g
        || masses.nodal.iter().any(|m| m.len() != n_g)
        || masses.nodal.len() != body.invariants.len()
    {
        return Err(IoError::invalid(
            prom.filename(),
            "/prom/nodal_mass",
            format!(
                "{n_g} grid ids for {} positions; {} mass components for {} invariant components",
                masses.positions.len(),
                masses.nodal.len(),
                body.invariants.len()
            ),
        ));
    }
    let nodal = create_group(prom, "nodal_mass")?;
    write_u32(&nodal, "grids", &body.grids, &[n_g])?;
    write_f64(&nodal, "positions", &masses.positions.concat(), &[n_g, 3])?;
    for (i, m) in masses.nodal.iter().enumerate() {
        write_f64(&nodal, &i.to_string(), m, &[n_g])?;
    }
    write_invariants(prom, &body.invariants)?;
    write_grid_rows(&create_group(prom, "interface")?, &body.interface)
}

/// Write the basis rows of the grids a `DISPLACEMENT` request of the `SOL PROM` subcase selects
/// as `/prom/basis/{grids, rows}` into `prom` (module doc).
pub fn write_prom_basis(prom: &Group, rows: &InterfaceRows) -> Result<(), IoError> {
    write_grid_rows(&create_group(prom, "basis")?, rows)
}

/// `grids` (n_b ids) and `rows` (n_b × 6 × n_red) of `rows` into `group`.
fn write_grid_rows(group: &Group, rows: &InterfaceRows) -> Result<(), IoError> {
    let n_b = rows.grids.len();
    let n_r = rows.rows.first().map_or(0, |r| r.ncols());
    write_u32(group, "grids", &rows.grids, &[n_b])?;
    let values: Vec<f64> = rows
        .rows
        .iter()
        .flat_map(|r| (0..6).flat_map(move |c| (0..n_r).map(move |k| r[(c, k)])))
        .collect();
    write_f64(group, "rows", &values, &[n_b, 6, n_r])?;
    Ok(())
}

/// The mass and the nine invariants of `/prom/invariants`.
const INVARIANTS: usize = 10;

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

/// The multibody data of a pROM artifact (module doc), `None` when the build did not write
/// them (RIGID = KEEP). `n_red` and `n_f` (functions) are the pROM's, from [`read_prom`].
pub fn read_prom_body(
    path: impl AsRef<Path>,
    n_red: usize,
    n_f: usize,
) -> Result<Option<PromBody>, IoError> {
    let path = path.as_ref();
    let file = open_artifact(path)?;
    let Ok(nodal) = file.group("prom/nodal_mass") else {
        return Ok(None);
    };
    let read = |group: &Group, name: &str| {
        group
            .dataset(name)
            .and_then(|d| d.read_raw::<f64>())
            .map_err(|e| IoError::hdf5(path, format!("read {}/{name}", group.name()), e))
    };
    let ids = |group: &Group| {
        group
            .dataset("grids")
            .and_then(|d| d.read_raw::<u32>())
            .map_err(|e| IoError::hdf5(path, format!("read {}/grids", group.name()), e))
    };
    let open = |name: &str| {
        file.group(name)
            .map_err(|e| IoError::hdf5(path, format!("open /{name}"), e))
    };
    let grids = ids(&nodal)?;
    let positions = read(&nodal, "positions")?;
    let n_g = grids.len();
    let masses = (0..n_f)
        .map(|i| read(&nodal, &i.to_string()))
        .collect::<Result<Vec<_>, _>>()?;
    if positions.len() != 3 * n_g || masses.iter().any(|m| m.len() != n_g) {
        return Err(IoError::malformed(
            path,
            "/prom/nodal_mass",
            format!(
                "{n_g} grids, {} position values, nodal mass lengths {:?}",
                positions.len(),
                masses.iter().map(Vec::len).collect::<Vec<_>>()
            ),
        ));
    }
    let invariants = read_invariants(path, &open("prom/invariants")?, n_red, n_f)?;
    let interface = open("prom/interface")?;
    let interface_grids = ids(&interface)?;
    let rows = read(&interface, "rows")?;
    let per_grid = 6 * n_red;
    if rows.len() != interface_grids.len() * per_grid {
        return Err(IoError::malformed(
            path,
            "/prom/interface/rows",
            format!(
                "{} values for {} grids × 6 × n_red = {n_red}",
                rows.len(),
                interface_grids.len()
            ),
        ));
    }
    let interface = InterfaceRows {
        rows: (0..interface_grids.len())
            .map(|b| Mat::from_fn(6, n_red, |c, k| rows[b * per_grid + c * n_red + k]))
            .collect(),
        grids: interface_grids,
    };
    Ok(Some(PromBody {
        grids,
        masses: AffineMasses {
            positions: positions.chunks(3).map(|r| [r[0], r[1], r[2]]).collect(),
            nodal: masses,
        },
        invariants,
        interface,
    }))
}

/// The affine components of the mass invariants written into `group` (`<k>/<i>`, module doc)
/// for `n_f` components over a basis of size `n_red`.
pub(crate) fn read_invariants(
    path: &Path,
    group: &Group,
    n_red: usize,
    n_f: usize,
) -> Result<Vec<MassInvariants>, IoError> {
    let read = |group: &Group, name: &str| {
        group
            .dataset(name)
            .and_then(|d| d.read_raw::<f64>())
            .map_err(|e| IoError::hdf5(path, format!("read {}/{name}", group.name()), e))
    };
    let invariant_groups = (0..INVARIANTS)
        .map(|k| {
            group
                .group(&k.to_string())
                .map_err(|e| IoError::hdf5(path, format!("open {}/{k}", group.name()), e))
        })
        .collect::<Result<Vec<_>, _>>()?;
    (0..n_f)
        .map(|i| {
            let arrays = invariant_groups
                .iter()
                .map(|g| read(g, &i.to_string()))
                .collect::<Result<Vec<_>, _>>()?;
            MassInvariants::from_arrays(&arrays, n_red).ok_or_else(|| {
                IoError::malformed(
                    path,
                    group.name(),
                    format!("component {i}: array lengths do not match n_red = {n_red}"),
                )
            })
        })
        .collect()
}

/// Writes the affine components of the mass invariants into `parent/invariants` (module doc).
pub(crate) fn write_invariants(
    parent: &Group,
    components: &[MassInvariants],
) -> Result<(), IoError> {
    let invariants = create_group(parent, "invariants")?;
    for k in 0..INVARIANTS {
        let group = create_group(&invariants, &k.to_string())?;
        for (i, component) in components.iter().enumerate() {
            let (values, shape) = &component.to_arrays()[k];
            write_f64(&group, &i.to_string(), values, shape)?;
        }
    }
    Ok(())
}

pub(crate) fn create_group(parent: &Group, name: &str) -> Result<Group, IoError> {
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
    read_prom_group(path, &prom)
}

/// The pROM written by [`write_prom`] into `prom` (a group of the file at `path`, named in
/// messages); returns it with `n_full`.
pub(crate) fn read_prom_group(path: &Path, prom: &Group) -> Result<(Prom, usize), IoError> {
    let root = prom.name();
    let bad = |what: &str, reason: String| IoError::malformed(path, what, reason);
    let hdf = |what: String| move |e| IoError::hdf5(path, what, e);
    let int = |name: &str| {
        prom.attr(name)
            .and_then(|a| a.read_scalar::<i64>())
            .map_err(hdf(format!("read attribute {root} {name}")))
    };
    let f64s = |name: &str| {
        prom.attr(name)
            .and_then(|a| a.read_raw::<f64>())
            .map_err(hdf(format!("read attribute {root} {name}")))
    };
    let (n_full, n_red) = (int("n_full")?, int("n_red")?);
    let names: Vec<String> = prom
        .attr("params")
        .and_then(|a| a.read_raw::<hdf5::types::VarLenUnicode>())
        .map_err(hdf(format!("read attribute {root} params")))?
        .iter()
        .map(|s| s.as_str().to_string())
        .collect();
    let (ranges, nominal) = (f64s("ranges")?, f64s("nominal")?);
    if ranges.len() != 2 * names.len() || nominal.len() != names.len() {
        return Err(bad(
            &root,
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
        .map_err(hdf(format!("read attribute {root} functions")))?;
    let functions: Vec<AffineFunction> = serde_json::from_str(json.as_str())
        .map_err(|e| bad(&format!("{root} functions"), e.to_string()))?;
    let n = usize::try_from(n_red)
        .map_err(|_| bad(&format!("{root} n_red"), format!("{n_red} is negative")))?;
    let read_parts = |name: &str| -> Result<Vec<Mat<f64>>, IoError> {
        (0..functions.len())
            .map(|i| {
                let what = format!("{root}/{name}/{i}");
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
        .map_err(hdf(format!("open {root}/damping")))?;
    let coefficient = |name: &str| {
        damping
            .attr(name)
            .and_then(|a| a.read_scalar::<f64>())
            .map_err(hdf(format!("read attribute {root}/damping {name}")))
    };
    let result = Prom {
        parameters,
        functions,
        stiffness,
        mass,
        alpha: coefficient("alpha")?,
        beta: coefficient("beta")?,
    };
    result.validate().map_err(|e| bad(&root, e.to_string()))?;
    let n_full = usize::try_from(n_full)
        .map_err(|_| bad(&format!("{root} n_full"), format!("{n_full} is negative")))?;
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
