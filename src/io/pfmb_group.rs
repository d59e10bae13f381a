//! The `/pfmb` group (DESIGN.md §11): the assembled mechanism of a `SOL FMB` run as an artifact
//! another deck loads with `FMB = 'file.h5'` (and the optimizer and the estimator from Rust),
//! holding only what the mechanism needs at any parameter point: no FE data.
//!
//! ```text
//! /pfmb          attrs layout_version (PFMB_VERSION), params (BODY.PMPAR), low, high (their box)
//! /pfmb/bodies/{ids, names, kinds (FLEXIBLE | RIGID), origin (b × 3), axes (b × 3 × 3),
//!               mass (b), inertia (b × 3 × 3), source (artifact path as the deck gave it)}
//!        a flexible body: origin and axes place its artifact's basic system (rows of axes: its
//!        x, y, z in basic; mass and inertia 0); a rigid body: origin is its centre of mass,
//!        mass and inertia about it in basic (axes 0)
//! /pfmb/bodies/<id>/   (a flexible body) its pROM as `/prom` holds it (attrs params, ranges,
//!        nominal, functions, n_red, n_full; K/<i>, M/<i>, damping), invariants/<k>/<i> (eq. 4.8),
//!        interface/{grids (n_b), positions (n_b × 3), rows (n_b × 6 × n_red)},
//!        strain/{names (s), rows (s × n_red)} (its STRAIN sensors, eq. 2.57)
//! /pfmb/markers/{ids, body (body id, 0 = ground), grid (0: a point), point (m × 3)}
//! /pfmb/joints/{ids, types (REV …), first, second (marker ids, 0 = ground), axis (j × 3)}
//! /pfmb/drives/{ids, joint (joint id), table, scale, compliant (0 | 1), stiffness, damping}
//! /pfmb/joint_springs/{ids, joint, stiffness, damping, rest}
//! /pfmb/point_springs/{ids, first, second, stiffness, damping, length (NaN: initial distance)}
//! /pfmb/forces/{ids, marker, table, scale, direction (f × 3), kinds (MFORCE | MMOMENT)}
//! /pfmb/sensors/{ids, names, kinds (POS …), ref (marker, joint or drive id by kind; 0 for KE
//!                and STRAIN), body (STRAIN: body id, else 0), gauge (STRAIN: the artifact's
//!                sensor name, else ""), direction (s × 3)}
//! /pfmb/tables/<tid>/{x, y} (points), or {series (X1, X2, X3, X4), coefficients} (TABLED4)
//! /pfmb/gravity/{sids (k), vectors (k × 3)}
//! ```
//! Every position and direction is in the basic system of the initial configuration. A
//! change of this layout increments [`PFMB_VERSION`]; a reader refuses any other version.

use std::path::{Path, PathBuf};

use hdf5::Group;
use hdf5::types::VarLenUnicode;
use hdf5_metno as hdf5;

use super::hdf5_file::{
    IoError, set_attr_f64s, set_attr_i64, set_attr_strings, write_f64, write_rows3, write_strings,
    write_u32,
};
use super::prom_group::{
    create_group, open_artifact, read_invariants, read_prom_group, write_invariants, write_prom,
};
use crate::card_values::{ForceKind, JointType, MsensorKind};
use crate::deck::Loc;
use crate::discretize::pfmb::Pfmb;
use crate::discretize::prom_body::ParametricBody;
use crate::dynamics::table::{PowerSeries, Table};
use crate::model::mechanism::{
    Body, BodyKind, Drive, Joint, JointSpring, Marker, MarkerPlace, Mechanism, PointForce,
    PointSpring, Sensor, SensorTarget,
};
use crate::multibody::InterfaceRows;

/// Version of the `/pfmb` layout (module doc).
pub const PFMB_VERSION: i64 = 2;

fn rows9(m: &[[f64; 3]; 3]) -> [f64; 9] {
    std::array::from_fn(|k| m[k / 3][k % 3])
}

/// Writes `pfmb` into `group` (normally the output file's `/pfmb`, module doc).
pub fn write_pfmb(group: &Group, pfmb: &Pfmb) -> Result<(), IoError> {
    let m = &pfmb.mechanism;
    set_attr_i64(group, "layout_version", PFMB_VERSION)?;
    let (mut names, mut low, mut high) = (Vec::new(), Vec::new(), Vec::new());
    for (body, p) in pfmb.flexible() {
        for q in &p.prom.parameters {
            names.push(format!("{body}.{}", q.name));
            low.push(q.low);
            high.push(q.high);
        }
    }
    let refs: Vec<&str> = names.iter().map(String::as_str).collect();
    set_attr_strings(group, "params", &refs)?;
    set_attr_f64s(group, "low", &low)?;
    set_attr_f64s(group, "high", &high)?;

    let bodies = create_group(group, "bodies")?;
    let b = m.bodies.len();
    let (mut kinds, mut origin, mut axes, mut mass, mut inertia, mut source) = (
        Vec::new(),
        Vec::new(),
        Vec::new(),
        Vec::new(),
        Vec::new(),
        Vec::new(),
    );
    for (body, parametric) in m.bodies.iter().zip(&pfmb.bodies) {
        match (&body.kind, parametric) {
            (
                BodyKind::Flexible {
                    artifact,
                    origin: o,
                    axes: a,
                },
                Some(p),
            ) => {
                kinds.push("FLEXIBLE");
                origin.push(*o);
                axes.extend(rows9(a));
                mass.push(0.0);
                inertia.extend([0.0; 9]);
                source.push(artifact.display().to_string());
                write_flexible(&create_group(&bodies, &body.id.to_string())?, p)?;
            }
            (
                BodyKind::Rigid {
                    mass: m,
                    centre,
                    inertia: i,
                },
                _,
            ) => {
                kinds.push("RIGID");
                origin.push(*centre);
                axes.extend([0.0; 9]);
                mass.push(*m);
                inertia.extend(rows9(i));
                source.push(String::new());
            }
            (BodyKind::Flexible { .. }, None) => {
                return Err(IoError::invalid(
                    group.filename(),
                    "/pfmb/bodies",
                    format!("flexible body {} has no pROM data", body.name),
                ));
            }
        }
    }
    let ids: Vec<u32> = m.bodies.iter().map(|x| x.id).collect();
    write_u32(&bodies, "ids", &ids, &[b])?;
    let body_names: Vec<&str> = m.bodies.iter().map(|x| x.name.as_str()).collect();
    write_strings(&bodies, "names", &body_names)?;
    write_strings(&bodies, "kinds", &kinds)?;
    write_rows3(&bodies, "origin", &origin)?;
    write_f64(&bodies, "axes", &axes, &[b, 3, 3])?;
    write_f64(&bodies, "mass", &mass, &[b])?;
    write_f64(&bodies, "inertia", &inertia, &[b, 3, 3])?;
    let source: Vec<&str> = source.iter().map(String::as_str).collect();
    write_strings(&bodies, "source", &source)?;

    let body_id = |index: Option<usize>| index.map_or(0, |i| m.bodies[i].id);
    let marker_id = |index: usize| m.markers[index].id;
    let markers = create_group(group, "markers")?;
    let n = m.markers.len();
    u32_column(&markers, "ids", &m.markers, |x| x.id)?;
    u32_column(&markers, "body", &m.markers, |x| body_id(x.body))?;
    let (grids, points): (Vec<u32>, Vec<[f64; 3]>) = m
        .markers
        .iter()
        .map(|x| match x.place {
            MarkerPlace::Grid(g) => (g, [0.0; 3]),
            MarkerPlace::Point(p) => (0, p),
        })
        .unzip();
    write_u32(&markers, "grid", &grids, &[n])?;
    write_rows3(&markers, "point", &points)?;

    let joints = create_group(group, "joints")?;
    u32_column(&joints, "ids", &m.joints, |x| x.id)?;
    let types: Vec<&str> = m.joints.iter().map(|x| x.kind.keyword()).collect();
    write_strings(&joints, "types", &types)?;
    u32_column(&joints, "first", &m.joints, |x| marker_id(x.first))?;
    u32_column(&joints, "second", &m.joints, |x| {
        x.second.map_or(0, marker_id)
    })?;
    write_rows3(
        &joints,
        "axis",
        &m.joints.iter().map(|x| x.axis).collect::<Vec<_>>(),
    )?;

    let joint_id = |index: usize| m.joints[index].id;
    let drives = create_group(group, "drives")?;
    u32_column(&drives, "ids", &m.drives, |x| x.id)?;
    u32_column(&drives, "joint", &m.drives, |x| joint_id(x.joint))?;
    u32_column(&drives, "table", &m.drives, |x| x.table)?;
    f64_column(&drives, "scale", &m.drives, |x| x.scale)?;
    let d = &m.drives;
    u32_column(&drives, "compliant", d, |x| {
        u32::from(x.compliance.is_some())
    })?;
    f64_column(&drives, "stiffness", d, |x| {
        x.compliance.map_or(0.0, |(k, _)| k)
    })?;
    f64_column(&drives, "damping", d, |x| {
        x.compliance.map_or(0.0, |(_, c)| c)
    })?;

    let springs = create_group(group, "joint_springs")?;
    let s = &m.joint_springs;
    u32_column(&springs, "ids", s, |x| x.id)?;
    u32_column(&springs, "joint", s, |x| joint_id(x.joint))?;
    f64_column(&springs, "stiffness", s, |x| x.stiffness)?;
    f64_column(&springs, "damping", s, |x| x.damping)?;
    f64_column(&springs, "rest", s, |x| x.rest)?;

    let springs = create_group(group, "point_springs")?;
    let s = &m.point_springs;
    u32_column(&springs, "ids", s, |x| x.id)?;
    u32_column(&springs, "first", s, |x| marker_id(x.first))?;
    u32_column(&springs, "second", s, |x| marker_id(x.second))?;
    f64_column(&springs, "stiffness", s, |x| x.stiffness)?;
    f64_column(&springs, "damping", s, |x| x.damping)?;
    f64_column(&springs, "length", s, |x| x.length.unwrap_or(f64::NAN))?;

    let forces = create_group(group, "forces")?;
    let f = &m.forces;
    u32_column(&forces, "ids", f, |x| x.id)?;
    u32_column(&forces, "marker", f, |x| marker_id(x.marker))?;
    u32_column(&forces, "table", f, |x| x.table)?;
    f64_column(&forces, "scale", f, |x| x.scale)?;
    write_rows3(
        &forces,
        "direction",
        &f.iter().map(|x| x.direction).collect::<Vec<_>>(),
    )?;
    let kinds: Vec<&str> = f.iter().map(|x| force_keyword(x.kind)).collect();
    write_strings(&forces, "kinds", &kinds)?;

    let sensors = create_group(group, "sensors")?;
    let s = &m.sensors;
    let n = s.len();
    u32_column(&sensors, "ids", s, |x| x.id)?;
    write_strings(
        &sensors,
        "names",
        &s.iter().map(|x| x.name.as_str()).collect::<Vec<_>>(),
    )?;
    write_strings(
        &sensors,
        "kinds",
        &s.iter().map(|x| x.kind.keyword()).collect::<Vec<_>>(),
    )?;
    let (mut reference, mut body, mut gauge) = (Vec::new(), Vec::new(), Vec::new());
    for x in s {
        let (r, b, g) = match &x.target {
            SensorTarget::Marker(i) => (marker_id(*i), 0, ""),
            SensorTarget::Joint(i) => (joint_id(*i), 0, ""),
            SensorTarget::Drive(i) => (m.drives[*i].id, 0, ""),
            SensorTarget::Strain { body, sensor } => (0, m.bodies[*body].id, sensor.as_str()),
            SensorTarget::System => (0, 0, ""),
        };
        reference.push(r);
        body.push(b);
        gauge.push(g);
    }
    write_u32(&sensors, "ref", &reference, &[n])?;
    write_u32(&sensors, "body", &body, &[n])?;
    write_strings(&sensors, "gauge", &gauge)?;
    write_rows3(
        &sensors,
        "direction",
        &s.iter().map(|x| x.direction).collect::<Vec<_>>(),
    )?;

    let tables = create_group(group, "tables")?;
    for (tid, table) in &pfmb.tables {
        let t = create_group(&tables, &tid.to_string())?;
        match (table.points(), table.series()) {
            (Some((x, y)), _) => {
                write_f64(&t, "x", x, &[x.len()])?;
                write_f64(&t, "y", y, &[y.len()])?;
            }
            (None, Some(s)) => {
                let (low, high) = s.range;
                write_f64(&t, "series", &[s.shift, s.scale, low, high], &[4])?;
                write_f64(&t, "coefficients", &s.coefficients, &[s.coefficients.len()])?;
            }
            (None, None) => unreachable!("a table is points or a power series"),
        }
    }
    let gravity = create_group(group, "gravity")?;
    let sids: Vec<u32> = pfmb.gravity.iter().map(|(sid, _)| *sid).collect();
    write_u32(&gravity, "sids", &sids, &[sids.len()])?;
    let vectors: Vec<[f64; 3]> = pfmb.gravity.iter().map(|(_, g)| *g).collect();
    write_rows3(&gravity, "vectors", &vectors)?;
    Ok(())
}

/// A flexible body's group (module doc).
fn write_flexible(group: &Group, body: &ParametricBody) -> Result<(), IoError> {
    let n = body.prom.size();
    write_prom(group, &body.prom, 0)?;
    write_invariants(group, &body.invariants)?;
    let interface = create_group(group, "interface")?;
    let b = body.interfaces.len();
    let grids: Vec<u32> = body.interfaces.iter().map(|r| r.grid).collect();
    write_u32(&interface, "grids", &grids, &[b])?;
    let positions: Vec<[f64; 3]> = body.interfaces.iter().map(|r| r.position).collect();
    write_rows3(&interface, "positions", &positions)?;
    let rows: Vec<f64> = body
        .interfaces
        .iter()
        .flat_map(|r| {
            (0..6).flat_map(move |c| {
                let (part, a) = if c < 3 {
                    (&r.translation, c)
                } else {
                    (&r.rotation, c - 3)
                };
                part.iter().map(move |column| column[a])
            })
        })
        .collect();
    write_f64(&interface, "rows", &rows, &[b, 6, n])?;
    let strain = create_group(group, "strain")?;
    let s = body.strain_sensors.len();
    let names: Vec<&str> = body
        .strain_sensors
        .iter()
        .map(|(n, _)| n.as_str())
        .collect();
    write_strings(&strain, "names", &names)?;
    let rows: Vec<f64> = body
        .strain_sensors
        .iter()
        .flat_map(|(_, r)| r.clone())
        .collect();
    write_f64(&strain, "rows", &rows, &[s, n])?;
    Ok(())
}

/// Reads datasets of one group of the file at `path`, every failure naming the object.
struct Reader<'a> {
    path: &'a Path,
    group: Group,
}

impl Reader<'_> {
    fn f64s(&self, name: &str) -> Result<Vec<f64>, IoError> {
        self.group
            .dataset(name)
            .and_then(|d| d.read_raw::<f64>())
            .map_err(|e| IoError::hdf5(self.path, format!("read {}/{name}", self.group.name()), e))
    }

    fn u32s(&self, name: &str) -> Result<Vec<u32>, IoError> {
        self.group
            .dataset(name)
            .and_then(|d| d.read_raw::<u32>())
            .map_err(|e| IoError::hdf5(self.path, format!("read {}/{name}", self.group.name()), e))
    }

    fn strings(&self, name: &str) -> Result<Vec<String>, IoError> {
        Ok(self
            .group
            .dataset(name)
            .and_then(|d| d.read_raw::<VarLenUnicode>())
            .map_err(|e| IoError::hdf5(self.path, format!("read {}/{name}", self.group.name()), e))?
            .iter()
            .map(|s| s.as_str().to_string())
            .collect())
    }

    /// `n × 3` rows of dataset `name`.
    fn rows3(&self, name: &str, n: usize) -> Result<Vec<[f64; 3]>, IoError> {
        let v = self.f64s(name)?;
        self.check(
            name,
            v.len() == 3 * n,
            format!("{} values for {n} rows of 3", v.len()),
        )?;
        Ok(v.chunks(3).map(|r| [r[0], r[1], r[2]]).collect())
    }

    fn malformed(&self, what: &str, reason: String) -> IoError {
        IoError::malformed(self.path, format!("{}/{what}", self.group.name()), reason)
    }

    fn check(&self, what: &str, ok: bool, reason: String) -> Result<(), IoError> {
        if ok {
            Ok(())
        } else {
            Err(self.malformed(what, reason))
        }
    }

    fn sub(&self, name: &str) -> Result<Reader<'_>, IoError> {
        let group = self.group.group(name).map_err(|e| {
            IoError::hdf5(self.path, format!("open {}/{name}", self.group.name()), e)
        })?;
        Ok(Reader {
            path: self.path,
            group,
        })
    }

    /// Index of `id` in `ids` (`what` names the referring dataset).
    fn index(&self, ids: &[u32], id: u32, what: &str) -> Result<usize, IoError> {
        ids.iter()
            .position(|&x| x == id)
            .ok_or_else(|| self.malformed(what, format!("{id} is no stored id")))
    }
}

/// Reads the pFMB of the file at `path` (module doc); every card of its mechanism takes the
/// position `loc` (the deck statement that loads it), so later errors still name a line.
pub fn read_pfmb(path: &Path, loc: &Loc) -> Result<Pfmb, IoError> {
    let file = open_artifact(path)?;
    let group = file.group("pfmb").map_err(|_| IoError::NotParaflex {
        path: path.into(),
        reason: "no /pfmb group (was it written by a SOL FMB run?)".into(),
    })?;
    let version = group
        .attr("layout_version")
        .and_then(|a| a.read_scalar::<i64>())
        .map_err(|e| IoError::hdf5(path, "read attribute /pfmb layout_version", e))?;
    if version != PFMB_VERSION {
        return Err(IoError::malformed(
            path,
            "/pfmb layout_version",
            format!(
                "the file's pFMB layout is version {version}, this paraflex reads version {PFMB_VERSION}: rerun the SOL FMB deck that wrote it"
            ),
        ));
    }
    let root = Reader { path, group };
    let mut mechanism = Mechanism::default();
    let mut parametric = Vec::new();

    let r = root.sub("bodies")?;
    let body_ids = r.u32s("ids")?;
    let b = body_ids.len();
    let (names, kinds) = (r.strings("names")?, r.strings("kinds")?);
    let origin = r.rows3("origin", b)?;
    let (axes, mass, inertia) = (r.f64s("axes")?, r.f64s("mass")?, r.f64s("inertia")?);
    r.check(
        "ids",
        names.len() == b
            && kinds.len() == b
            && axes.len() == 9 * b
            && mass.len() == b
            && inertia.len() == 9 * b,
        format!("{b} bodies but inconsistent names, kinds, axes, mass or inertia lengths"),
    )?;
    let mat3 = |v: &[f64], i: usize| -> [[f64; 3]; 3] {
        std::array::from_fn(|row| std::array::from_fn(|col| v[9 * i + 3 * row + col]))
    };
    for i in 0..b {
        let kind = match kinds[i].as_str() {
            "FLEXIBLE" => {
                parametric.push(Some(read_flexible(&r.sub(&body_ids[i].to_string())?)?));
                BodyKind::Flexible {
                    artifact: PathBuf::from(format!(
                        "{}:/pfmb/bodies/{}",
                        path.display(),
                        body_ids[i]
                    )),
                    origin: origin[i],
                    axes: mat3(&axes, i),
                }
            }
            "RIGID" => {
                parametric.push(None);
                BodyKind::Rigid {
                    mass: mass[i],
                    centre: origin[i],
                    inertia: mat3(&inertia, i),
                }
            }
            other => return Err(r.malformed("kinds", format!("unknown body kind {other:?}"))),
        };
        mechanism.bodies.push(Body {
            id: body_ids[i],
            name: names[i].clone(),
            kind,
            loc: loc.clone(),
        });
    }
    let body_of = |id: u32, what: &str| -> Result<Option<usize>, IoError> {
        (id != 0).then(|| r.index(&body_ids, id, what)).transpose()
    };

    let r = root.sub("markers")?;
    let marker_ids = r.u32s("ids")?;
    let n = marker_ids.len();
    let (bodies, grids, points) = (r.u32s("body")?, r.u32s("grid")?, r.rows3("point", n)?);
    r.check(
        "body",
        bodies.len() == n && grids.len() == n,
        format!("{n} markers"),
    )?;
    for i in 0..n {
        mechanism.markers.push(Marker {
            id: marker_ids[i],
            body: body_of(bodies[i], "markers/body")?,
            place: if grids[i] == 0 {
                MarkerPlace::Point(points[i])
            } else {
                MarkerPlace::Grid(grids[i])
            },
            loc: loc.clone(),
        });
    }
    let marker = |id: u32, what: &str| r.index(&marker_ids, id, what);

    let j = root.sub("joints")?;
    let joint_ids = j.u32s("ids")?;
    let n = joint_ids.len();
    let (types, first, second) = (j.strings("types")?, j.u32s("first")?, j.u32s("second")?);
    let axis = j.rows3("axis", n)?;
    j.check(
        "ids",
        types.len() == n && first.len() == n && second.len() == n,
        format!("{n} joints"),
    )?;
    for i in 0..n {
        let kind = JointType::KEYWORDS
            .iter()
            .find(|(k, _)| *k == types[i])
            .map(|(_, t)| *t)
            .ok_or_else(|| j.malformed("types", format!("unknown joint type {:?}", types[i])))?;
        mechanism.joints.push(Joint {
            id: joint_ids[i],
            kind,
            first: marker(first[i], "joints/first")?,
            second: (second[i] != 0)
                .then(|| marker(second[i], "joints/second"))
                .transpose()?,
            axis: axis[i],
            loc: loc.clone(),
        });
    }
    let joint = |id: u32, what: &str| j.index(&joint_ids, id, what);

    let d = root.sub("drives")?;
    let drive_ids = d.u32s("ids")?;
    let n = drive_ids.len();
    let (joints, tables, scale) = (d.u32s("joint")?, d.u32s("table")?, d.f64s("scale")?);
    let (compliant, k, c) = (
        d.u32s("compliant")?,
        d.f64s("stiffness")?,
        d.f64s("damping")?,
    );
    d.check(
        "ids",
        [
            joints.len(),
            tables.len(),
            scale.len(),
            compliant.len(),
            k.len(),
            c.len(),
        ]
        .iter()
        .all(|&l| l == n),
        format!("{n} drives"),
    )?;
    for i in 0..n {
        mechanism.drives.push(Drive {
            id: drive_ids[i],
            joint: joint(joints[i], "drives/joint")?,
            table: tables[i],
            scale: scale[i],
            compliance: (compliant[i] != 0).then_some((k[i], c[i])),
            loc: loc.clone(),
        });
    }

    let s = root.sub("joint_springs")?;
    let ids = s.u32s("ids")?;
    let n = ids.len();
    let (joints, k, c, rest) = (
        s.u32s("joint")?,
        s.f64s("stiffness")?,
        s.f64s("damping")?,
        s.f64s("rest")?,
    );
    s.check(
        "ids",
        [joints.len(), k.len(), c.len(), rest.len()]
            .iter()
            .all(|&l| l == n),
        format!("{n} joint springs"),
    )?;
    for i in 0..n {
        mechanism.joint_springs.push(JointSpring {
            id: ids[i],
            joint: joint(joints[i], "joint_springs/joint")?,
            stiffness: k[i],
            damping: c[i],
            rest: rest[i],
            loc: loc.clone(),
        });
    }

    let s = root.sub("point_springs")?;
    let ids = s.u32s("ids")?;
    let n = ids.len();
    let (first, second) = (s.u32s("first")?, s.u32s("second")?);
    let (k, c, length) = (s.f64s("stiffness")?, s.f64s("damping")?, s.f64s("length")?);
    s.check(
        "ids",
        [first.len(), second.len(), k.len(), c.len(), length.len()]
            .iter()
            .all(|&l| l == n),
        format!("{n} point springs"),
    )?;
    for i in 0..n {
        mechanism.point_springs.push(PointSpring {
            id: ids[i],
            first: marker(first[i], "point_springs/first")?,
            second: marker(second[i], "point_springs/second")?,
            stiffness: k[i],
            damping: c[i],
            length: (!length[i].is_nan()).then_some(length[i]),
            loc: loc.clone(),
        });
    }

    let f = root.sub("forces")?;
    let ids = f.u32s("ids")?;
    let n = ids.len();
    let (markers, tables, scale) = (f.u32s("marker")?, f.u32s("table")?, f.f64s("scale")?);
    let (direction, kinds) = (f.rows3("direction", n)?, f.strings("kinds")?);
    f.check(
        "ids",
        [markers.len(), tables.len(), scale.len(), kinds.len()]
            .iter()
            .all(|&l| l == n),
        format!("{n} forces"),
    )?;
    for i in 0..n {
        let kind = [ForceKind::Force, ForceKind::Moment]
            .into_iter()
            .find(|&k| force_keyword(k) == kinds[i])
            .ok_or_else(|| f.malformed("kinds", format!("unknown force kind {:?}", kinds[i])))?;
        mechanism.forces.push(PointForce {
            id: ids[i],
            kind,
            marker: marker(markers[i], "forces/marker")?,
            table: tables[i],
            scale: scale[i],
            direction: direction[i],
            loc: loc.clone(),
        });
    }

    let s = root.sub("sensors")?;
    let ids = s.u32s("ids")?;
    let n = ids.len();
    let (names, kinds, reference) = (s.strings("names")?, s.strings("kinds")?, s.u32s("ref")?);
    let (bodies, gauge) = (s.u32s("body")?, s.strings("gauge")?);
    let direction = s.rows3("direction", n)?;
    s.check(
        "ids",
        [
            names.len(),
            kinds.len(),
            reference.len(),
            bodies.len(),
            gauge.len(),
        ]
        .iter()
        .all(|&l| l == n),
        format!("{n} sensors"),
    )?;
    for i in 0..n {
        let kind = MsensorKind::KEYWORDS
            .iter()
            .find(|(k, _)| *k == kinds[i])
            .map(|(_, t)| *t)
            .ok_or_else(|| s.malformed("kinds", format!("unknown MSENSOR kind {:?}", kinds[i])))?;
        let target = match kind {
            MsensorKind::Pos | MsensorKind::Accel | MsensorKind::Dev => {
                SensorTarget::Marker(marker(reference[i], "sensors/ref")?)
            }
            MsensorKind::Jforce | MsensorKind::Jtorq => {
                SensorTarget::Joint(joint(reference[i], "sensors/ref")?)
            }
            MsensorKind::Power | MsensorKind::Energy if reference[i] == 0 => SensorTarget::System,
            MsensorKind::Power | MsensorKind::Energy => {
                SensorTarget::Drive(s.index(&drive_ids, reference[i], "ref")?)
            }
            MsensorKind::Ke => SensorTarget::System,
            MsensorKind::Strain => SensorTarget::Strain {
                body: body_of(bodies[i], "sensors/body")?
                    .ok_or_else(|| s.malformed("body", "a STRAIN output on the ground".into()))?,
                sensor: gauge[i].clone(),
            },
        };
        mechanism.sensors.push(Sensor {
            id: ids[i],
            name: names[i].clone(),
            kind,
            target,
            direction: direction[i],
            loc: loc.clone(),
        });
    }

    let t = root.sub("tables")?;
    let mut tables = Vec::new();
    let tids = t
        .group
        .member_names()
        .map_err(|e| IoError::hdf5(path, "list /pfmb/tables", e))?;
    for name in tids {
        let tid: u32 = name
            .parse()
            .map_err(|_| t.malformed(&name, "a table's group is named by its id".into()))?;
        let g = t.sub(&name)?;
        let table = if g.group.link_exists("series") {
            let series = g.f64s("series")?;
            g.check(
                "series",
                series.len() == 4,
                format!("{} values, 4 expected", series.len()),
            )?;
            Table::power_series(PowerSeries {
                shift: series[0],
                scale: series[1],
                range: (series[2], series[3]),
                coefficients: g.f64s("coefficients")?,
            })
            .map_err(|e| g.malformed("series", e.to_string()))?
        } else {
            let (x, y) = (g.f64s("x")?, g.f64s("y")?);
            g.check(
                "y",
                x.len() == y.len(),
                format!("{} x for {} y", x.len(), y.len()),
            )?;
            let points: Vec<(f64, f64)> = x.into_iter().zip(y).collect();
            Table::new(&points).map_err(|e| g.malformed("x", e.to_string()))?
        };
        tables.push((tid, table));
    }
    tables.sort_by_key(|(id, _)| *id);
    let g = root.sub("gravity")?;
    let sids = g.u32s("sids")?;
    let vectors = g.rows3("vectors", sids.len())?;
    Ok(Pfmb {
        mechanism,
        bodies: parametric,
        tables,
        gravity: sids.into_iter().zip(vectors).collect(),
    })
}

/// A flexible body's group (module doc).
fn read_flexible(r: &Reader<'_>) -> Result<ParametricBody, IoError> {
    let (prom, _) = read_prom_group(r.path, &r.group)?;
    let n = prom.size();
    let invariants = read_invariants(r.path, &r.sub("invariants")?.group, n, prom.functions.len())?;
    let i = r.sub("interface")?;
    let grids = i.u32s("grids")?;
    let positions = i.rows3("positions", grids.len())?;
    let rows = i.f64s("rows")?;
    i.check(
        "rows",
        rows.len() == grids.len() * 6 * n,
        format!(
            "{} values for {} grids × 6 × n_red = {n}",
            rows.len(),
            grids.len()
        ),
    )?;
    let interfaces = grids
        .iter()
        .zip(positions)
        .enumerate()
        .map(|(b, (&grid, position))| {
            let row = |c: usize| -> Vec<[f64; 3]> {
                (0..n)
                    .map(|k| std::array::from_fn(|a| rows[(b * 6 + c + a) * n + k]))
                    .collect()
            };
            InterfaceRows {
                grid,
                position,
                translation: row(0),
                rotation: row(3),
            }
        })
        .collect();
    let s = r.sub("strain")?;
    let names = s.strings("names")?;
    let rows = s.f64s("rows")?;
    s.check(
        "rows",
        rows.len() == names.len() * n,
        format!(
            "{} values for {} sensors × n_red = {n}",
            rows.len(),
            names.len()
        ),
    )?;
    let strain_sensors = names
        .into_iter()
        .enumerate()
        .map(|(k, name)| (name, rows[k * n..(k + 1) * n].to_vec()))
        .collect();
    Ok(ParametricBody {
        prom,
        invariants,
        interfaces,
        strain_sensors,
    })
}

/// One 1-D u32 dataset `name` of `group`: `value` of each item.
fn u32_column<T>(
    group: &Group,
    name: &str,
    items: &[T],
    value: impl Fn(&T) -> u32,
) -> Result<(), IoError> {
    let column: Vec<u32> = items.iter().map(value).collect();
    write_u32(group, name, &column, &[column.len()]).map(drop)
}

/// One 1-D f64 dataset `name` of `group`: `value` of each item.
fn f64_column<T>(
    group: &Group,
    name: &str,
    items: &[T],
    value: impl Fn(&T) -> f64,
) -> Result<(), IoError> {
    let column: Vec<f64> = items.iter().map(value).collect();
    write_f64(group, name, &column, &[column.len()]).map(drop)
}

/// The stored name of a marker load's kind: its card.
fn force_keyword(kind: ForceKind) -> &'static str {
    match kind {
        ForceKind::Force => "MFORCE",
        ForceKind::Moment => "MMOMENT",
    }
}
