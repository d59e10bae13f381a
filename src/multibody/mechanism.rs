//! The [`System`] of a model's mechanism ([`crate::model::mechanism`]): flexible bodies from
//! their pROM artifacts at the parameter values ([`super::prom_body`]), placed by their
//! coordinate systems, rigid bodies with their frame at the centre of mass, markers, joints
//! whose two marker frames share the joint frame (z = the joint axis) in the initial
//! configuration, drives and forces with their tables as [`Signal`]s, spring-dampers, gravity.
//!
//! [`simulate`] runs it with GGL and a chosen [`Scheme`] (BDF1, BDF2, generalized-α) over
//! TSTEP intervals and returns the output histories of the MSENSORs and drives.
//!
//! Errors that need the artifacts (a file that is no `RIGID = REMOVE` pROM, a PVAL name that
//! is no parameter of the body's artifact, a marker GRID that is no interface grid) are
//! collected over all bodies and markers and point at the card.

use super::body::Body;
use super::error::MultibodyError;
use super::forces::Force;
use super::integrator::{Ggl, NewtonSettings};
use super::joints::{DriveKind, JointKind};
use super::marker::Marker;
use super::prom_body::{PromBodyAtPoint, load_prom_body};
use super::scheme::Scheme;
use super::signal::Signal;
use super::statics;
use super::system::System;
use crate::card_values::{FmbStart, JointType, MsensorKind};
use crate::deck::DeckError;
use crate::discretize::loads::dynamic_table;
use crate::geometry::euler_parameters::from_rotation_matrix;
use crate::geometry::mat3::{IDENTITY, Mat3, mul_vec, transpose};
use crate::geometry::vec3::{add, dot, norm, sub};
use crate::model::Model;
use crate::model::mechanism::{BodyKind, MarkerPlace, Mechanism, Sensor, SensorTarget};

/// The system of a mechanism and where each card went in it.
#[derive(Debug, Clone)]
pub struct MechanismSystem {
    pub system: System,
    /// System marker of each MARKER (its point, frame aligned with the body).
    pub markers: Vec<usize>,
    /// System joint of each JOINT.
    pub joints: Vec<usize>,
    /// System drive of each JDRIVE.
    pub drives: Vec<usize>,
    /// Each flexible body's name and pROM evaluation point (parameters, values, extrapolated).
    pub flexible: Vec<(String, PromBodyAtPoint)>,
}

/// Where a body sits initially: position of its frame origin and rotation A (body → global).
struct Placement {
    origin: [f64; 3],
    rotation: Mat3,
}

impl Placement {
    fn to_global(&self, local: [f64; 3]) -> [f64; 3] {
        add(self.origin, mul_vec(&self.rotation, local))
    }
}

fn joint_kind(t: JointType) -> JointKind {
    match t {
        JointType::Revolute => JointKind::Revolute,
        JointType::Fixed => JointKind::Fixed,
        JointType::Spherical => JointKind::Spherical,
        JointType::Prismatic => JointKind::Prismatic,
        JointType::Cylindrical => JointKind::Cylindrical,
        JointType::Universal => JointKind::Universal,
        JointType::Inline => JointKind::Inline,
        JointType::Inplane => JointKind::Inplane,
    }
}

/// SCALE · TABLE(t) with its slope (a piecewise-linear table has no second derivative).
fn table_signal(model: &Model, tid: u32, scale: f64) -> Result<Signal, String> {
    let table = dynamic_table(model, tid)?;
    Ok(Signal::new(move |t| {
        [scale * table.value(t), scale * table.slope(t), 0.0]
    }))
}

/// The PVAL values `BODY.PMPAR` of body `name` as (PMPAR, value).
fn values_of(name: &str, pval: &[(String, f64)]) -> Vec<(String, f64)> {
    pval.iter()
        .filter_map(|(n, v)| {
            let (body, parameter) = n.split_once('.')?;
            body.eq_ignore_ascii_case(name)
                .then(|| (parameter.to_string(), *v))
        })
        .collect()
}

/// Builds the system of `model`'s mechanism with gravity `gravity` (basic) and the PVAL
/// values `pval` (`BODY.PMPAR`, value). Every error found is returned, at its card.
pub fn build_system(
    model: &Model,
    gravity: [f64; 3],
    pval: &[(String, f64)],
) -> Result<MechanismSystem, Vec<DeckError>> {
    let mech: &Mechanism = &model.mechanism;
    let mut errors = Vec::new();
    let error = |loc: &crate::deck::Loc, card: String, message: String| {
        DeckError::at(loc, message).on_card(card)
    };
    let mut system = System::new(gravity);
    let mut placements = Vec::new();
    let mut flexible = Vec::new();
    let mut interfaces: Vec<Vec<super::flexible::InterfaceRows>> = Vec::new();
    for b in &mech.bodies {
        match &b.kind {
            BodyKind::Flexible {
                artifact,
                origin,
                axes,
            } => {
                let rotation = transpose(axes);
                match load_prom_body(artifact, &values_of(&b.name, pval)) {
                    Ok(at) => {
                        interfaces.push(at.data.interfaces.clone());
                        system.add_body(
                            Body::flexible(at.data.clone()),
                            *origin,
                            from_rotation_matrix(&rotation),
                        );
                        flexible.push((b.name.clone(), at));
                    }
                    Err(message) => {
                        errors.push(error(&b.loc, format!("FLEXB {}", b.id), message));
                        interfaces.push(Vec::new());
                        system.add_body(Body::rigid(1.0, IDENTITY), *origin, [1.0, 0.0, 0.0, 0.0]);
                    }
                }
                placements.push(Placement {
                    origin: *origin,
                    rotation,
                });
            }
            BodyKind::Rigid {
                mass,
                centre,
                inertia,
            } => {
                system.add_body(Body::rigid(*mass, *inertia), *centre, [1.0, 0.0, 0.0, 0.0]);
                interfaces.push(Vec::new());
                placements.push(Placement {
                    origin: *centre,
                    rotation: IDENTITY,
                });
            }
        }
    }
    let ground = Placement {
        origin: [0.0; 3],
        rotation: IDENTITY,
    };
    let placement = |body: Option<usize>| body.map_or(&ground, |b| &placements[b]);
    // markers: each MARKER's point, frame aligned with its body
    let mut points: Vec<Option<Marker>> = Vec::new();
    for m in &mech.markers {
        let marker = match (m.place, m.body) {
            (MarkerPlace::Point(x), None) => Some(Marker::new(None, x)),
            (MarkerPlace::Point(x), Some(b)) => {
                let p = &placements[b];
                Some(Marker::new(
                    Some(b),
                    mul_vec(&transpose(&p.rotation), sub(x, p.origin)),
                ))
            }
            (MarkerPlace::Grid(g), Some(b)) => {
                let rows = interfaces[b].iter().find(|r| r.grid == g);
                if rows.is_none() && !errors.iter().any(|e| e.loc == mech.bodies[b].loc) {
                    let mut e = error(
                        &m.loc,
                        format!("MARKER {}", m.id),
                        format!(
                            "GRID {g} is not an interface grid of {} (interface grids: {})",
                            match &mech.bodies[b].kind {
                                BodyKind::Flexible { artifact, .. } =>
                                    artifact.display().to_string(),
                                BodyKind::Rigid { .. } => String::new(),
                            },
                            interfaces[b]
                                .iter()
                                .map(|r| r.grid.to_string())
                                .collect::<Vec<_>>()
                                .join(" ")
                        ),
                    );
                    e.field = Some("field 4 (GRID)".into());
                    errors.push(e);
                }
                rows.map(|r| Marker::at_grid(b, r))
            }
            (MarkerPlace::Grid(_), None) => None,
        };
        points.push(marker);
    }
    if !errors.is_empty() {
        return Err(errors);
    }
    let points: Vec<Marker> = points.into_iter().map(|m| m.expect("checked")).collect();
    let global = |m: &Marker| placement(m.body).to_global(m.position);
    let markers: Vec<usize> = points
        .iter()
        .map(|m| system.add_marker(m.clone()))
        .collect();
    // joints: both markers take the joint frame (z = axis), expressed in their bodies
    let mut joints = Vec::new();
    for j in &mech.joints {
        let frame = Marker::new(None, [0.0; 3]).with_z_axis(j.axis).axes;
        let first = &points[j.first];
        let second = j
            .second
            .map_or_else(|| Marker::new(None, global(first)), |s| points[s].clone());
        let oriented = |m: &Marker, frame: Mat3| {
            let r = placement(m.body).rotation;
            let mut out = m.clone();
            out.axes = frame.map(|axis| mul_vec(&transpose(&r), axis));
            out
        };
        // a universal joint's cross: z on the first side is the frame's x, perpendicular to N
        let first_frame = if j.kind == JointType::Universal {
            [frame[1], frame[2], frame[0]]
        } else {
            frame
        };
        let m1 = system.add_marker(oriented(first, first_frame));
        let m2 = system.add_marker(oriented(&second, frame));
        joints.push(system.add_joint(joint_kind(j.kind), m1, m2));
    }
    // the initial slide of a prismatic joint (revolute: the frames coincide, angle 0)
    let initial_coordinate = |joint: usize| {
        let j = &mech.joints[joint];
        match j.kind {
            JointType::Prismatic => {
                let p1 = global(&points[j.first]);
                let p2 = j.second.map_or(p1, |s| global(&points[s]));
                dot(j.axis, sub(p1, p2))
            }
            _ => 0.0,
        }
    };
    let mut drives = Vec::new();
    for d in &mech.drives {
        let signal = match table_signal(model, d.table, d.scale) {
            Ok(s) => s,
            Err(message) => {
                errors.push(error(&d.loc, format!("JDRIVE {}", d.id), message));
                continue;
            }
        };
        let kind = d
            .compliance
            .map_or(DriveKind::Rigid, |(stiffness, damping)| {
                DriveKind::Compliant { stiffness, damping }
            });
        match system.add_drive(joints[d.joint], signal, kind) {
            Ok(i) => drives.push(i),
            Err(e) => errors.push(error(&d.loc, format!("JDRIVE {}", d.id), e.to_string())),
        }
    }
    for s in &mech.joint_springs {
        system.add_force(Force::JointSpringDamper {
            joint: joints[s.joint],
            stiffness: s.stiffness,
            damping: s.damping,
            rest: initial_coordinate(s.joint) + s.rest,
        });
    }
    for s in &mech.point_springs {
        let length = s
            .length
            .unwrap_or_else(|| norm(sub(global(&points[s.first]), global(&points[s.second]))));
        system.add_force(Force::PointSpringDamper {
            first: markers[s.first],
            second: markers[s.second],
            stiffness: s.stiffness,
            damping: s.damping,
            length,
        });
    }
    for f in &mech.forces {
        match table_signal(model, f.table, f.scale) {
            Ok(signal) => system.add_force(Force::Point {
                marker: markers[f.marker],
                direction: f.direction,
                signal,
            }),
            Err(message) => errors.push(error(&f.loc, format!("MFORCE {}", f.id), message)),
        }
    }
    if !errors.is_empty() {
        return Err(errors);
    }
    Ok(MechanismSystem {
        system,
        markers,
        joints,
        drives,
        flexible,
    })
}

/// Output histories of a run of a mechanism: one row at t₀ and after every `every`-th step.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Histories {
    pub time: Vec<f64>,
    /// One series per output, in the order given to [`simulate`].
    pub sensors: Vec<Vec<f64>>,
    /// Per JDRIVE: coordinate (angle or slide), rate, effort (torque or force), power.
    pub drives: Vec<[Vec<f64>; 4]>,
    /// max |Φᵢ| at each row.
    pub constraint_residual: Vec<f64>,
    /// Newton iterations of the step ending at each row (0 at t₀).
    pub newton_iterations: Vec<u32>,
    /// Steps taken, largest iteration count of a step, labels of removed redundant constraints.
    pub steps: usize,
    pub max_iterations: usize,
    pub redundant: Vec<String>,
    /// Size of the system: coordinates and constraints.
    pub coordinates: usize,
    pub constraints: usize,
}

impl MechanismSystem {
    /// A drive's coordinate, rate, effort and power at the integrator's state.
    fn drive_row(&self, ggl: &Ggl, drive: usize) -> [f64; 4] {
        let d = self.drives[drive];
        let [coordinate, rate] = ggl.drive_coordinate(d);
        let effort = ggl.drive_effort(d);
        [coordinate, rate, effort, effort * rate]
    }

    /// The value of output `sensor` at the integrator's state; `energy` holds the actuation
    /// energy integrated so far of each drive (ENERGY reads it).
    fn sensor_value(&self, ggl: &Ggl, sensor: &Sensor, energy: &[f64]) -> f64 {
        match (sensor.kind, sensor.target) {
            (MsensorKind::Pos, SensorTarget::Marker(m)) => {
                dot(sensor.direction, ggl.marker_position(self.markers[m]))
            }
            (MsensorKind::Accel, SensorTarget::Marker(m)) => {
                dot(sensor.direction, ggl.marker_acceleration(self.markers[m]))
            }
            (MsensorKind::Jforce, SensorTarget::Joint(j)) => ggl
                .joint_force(self.joints[j])
                .map_or(f64::NAN, |f| dot(sensor.direction, f)),
            (MsensorKind::Jtorq, SensorTarget::Joint(j)) => self
                .driving(j)
                .map_or(f64::NAN, |d| ggl.drive_effort(self.drives[d])),
            (MsensorKind::Power, SensorTarget::Drive(d)) => self.drive_row(ggl, d)[3],
            (MsensorKind::Energy, SensorTarget::Drive(d)) => energy[d],
            (MsensorKind::Ke, _) => ggl.kinetic_energy(),
            _ => f64::NAN,
        }
    }

    /// The JDRIVE (index) of joint `joint` (index into the JOINTs), if it has one.
    fn driving(&self, joint: usize) -> Option<usize> {
        let system_joint = self.joints[joint];
        self.drives
            .iter()
            .position(|&d| self.system.drives[d].joint == system_joint)
    }
}

/// Runs the mechanism from `start` at t = 0 (its assembled initial configuration, or the static
/// equilibrium under gravity reached from it with the drives held, [`statics`]) with GGL and
/// `scheme` over the TSTEP intervals `(steps, Δt, every)` (none: only the start is recorded),
/// recording `sensors` and every drive. The
/// actuation energy ∫ ω T dt (eq. 6.1 f₂) is summed over every step with the power at the
/// step's end (the rectangle rule of BDF1).
pub fn simulate(
    ms: &MechanismSystem,
    sensors: &[Sensor],
    intervals: &[(u32, f64, u32)],
    settings: NewtonSettings,
    scheme: Scheme,
    start: FmbStart,
) -> Result<Histories, MultibodyError> {
    let dt0 = intervals.first().map_or(1.0, |i| i.1);
    let mut system = ms.system.clone();
    if start == FmbStart::Static {
        let assembled = Ggl::new(system.clone(), dt0, 0.0, settings)?;
        let rest = statics::equilibrium(
            &assembled.system,
            &assembled.equations,
            &assembled.q,
            0.0,
            settings.tolerance,
            settings.assembly_tolerance,
        )?;
        system.set_initial_state(&rest.q, &vec![0.0; rest.q.len()]);
    }
    let mut ggl = Ggl::with_scheme(system, dt0, 0.0, settings, scheme)?;
    let mut h = Histories {
        sensors: vec![Vec::new(); sensors.len()],
        drives: vec![Default::default(); ms.drives.len()],
        redundant: ggl.redundant.clone(),
        coordinates: ggl.system.size(),
        constraints: ggl.constraint_count(),
        ..Histories::default()
    };
    let mut energy = vec![0.0; ms.drives.len()];
    let mut phi = vec![0.0; ggl.equations.constraints.len()];
    ggl.equations
        .constraints
        .values(&ggl.system.layout, &ggl.q, 0.0, &mut phi);
    let residual0 = phi.iter().fold(0.0_f64, |a, x| a.max(x.abs()));
    let record = |ggl: &Ggl, h: &mut Histories, energy: &[f64], residual: f64, its: usize| {
        h.time.push(ggl.time);
        for (series, s) in h.sensors.iter_mut().zip(sensors) {
            series.push(ms.sensor_value(ggl, s, energy));
        }
        for (d, series) in h.drives.iter_mut().enumerate() {
            for (x, v) in series.iter_mut().zip(ms.drive_row(ggl, d)) {
                x.push(v);
            }
        }
        h.constraint_residual.push(residual);
        h.newton_iterations.push(its as u32);
    };
    record(&ggl, &mut h, &energy, residual0, 0);
    for &(count, dt, every) in intervals {
        ggl.step_size = dt;
        let every = every.max(1) as usize;
        for step in 1..=count as usize {
            let report = ggl.step()?;
            h.steps += 1;
            h.max_iterations = h.max_iterations.max(report.iterations);
            for (d, e) in energy.iter_mut().enumerate() {
                *e += ms.drive_row(&ggl, d)[3] * dt;
            }
            if step % every == 0 {
                record(
                    &ggl,
                    &mut h,
                    &energy,
                    report.constraint_residual,
                    report.iterations,
                );
            }
        }
    }
    Ok(h)
}
