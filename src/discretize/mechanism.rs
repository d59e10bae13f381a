//! The multibody [`System`] of a mechanism ([`crate::model::mechanism`], gathered with its
//! bodies' pROM data and its tables as a [`Pfmb`]): flexible bodies evaluated at the parameter
//! values ([`super::prom_body`]), placed by their coordinate systems, rigid bodies with their
//! frame at the centre of mass, markers, joints whose two marker frames share the joint frame
//! (z = the joint axis) in the initial configuration, drives and forces with their tables as
//! [`Signal`]s, spring-dampers, gravity.
//!
//! [`MechanismSystem::outputs`] turns MSENSORs into the [`Output`]s that
//! [`crate::multibody::simulate`] records.
//!
//! Errors that need the artifacts (a PVAL name that is no parameter of the body's artifact, a
//! marker GRID that is no interface grid; a file that is no `RIGID = REMOVE` pROM is found by
//! [`Pfmb::of_model`]) are collected over all bodies and markers as [`MechanismError`]s at
//! their [`Card`] ([`crate::model::mechanism::Mechanism::error_at`] gives their file and
//! line).

use super::pfmb::Pfmb;
use super::prom_body::PromBodyAtPoint;
use crate::card_values::{ForceKind, JointType, MsensorKind};
use crate::dynamics::table::Table;
use crate::geometry::euler_parameters::from_rotation_matrix;
use crate::geometry::mat3::{IDENTITY, Mat3, mul_vec, transpose};
use crate::geometry::vec3::{add, dot, norm, sub};
use crate::model::mechanism::{BodyKind, Card, MarkerPlace, Mechanism, Sensor, SensorTarget};
use crate::multibody::{
    Body, BodySchedule, DriveKind, FlexibleBodyData, Force, InterfaceRows, JointKind, Marker,
    MassInvariants, Output, Signal, System,
};
use faer::Mat;

/// A problem found while building the system, at the card it concerns (`field`: number and
/// name of the field at fault, if one is).
#[derive(Debug, Clone, PartialEq)]
pub struct MechanismError {
    pub card: Card,
    pub field: Option<&'static str>,
    pub message: String,
}

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
    /// Per body (FLEXB and RIGIDB in card order): its entry in `flexible`, if it is flexible.
    pub flexible_of: Vec<Option<usize>>,
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

/// SCALE · TABLE(t) with its first and second derivatives (a piecewise-linear table's second
/// derivative is zero between its points).
fn table_signal(table: &Table, scale: f64) -> Signal {
    let table = table.clone();
    Signal::new(move |t| {
        [
            scale * table.value(t),
            scale * table.slope(t),
            scale * table.curvature(t),
        ]
    })
}

/// The PVAL values `BODY.PMPAR` of body `name` as (PMPAR, value).
pub(crate) fn values_of(name: &str, pval: &[(String, f64)]) -> Vec<(String, f64)> {
    pval.iter()
        .filter_map(|(n, v)| {
            let (body, parameter) = n.split_once('.')?;
            body.eq_ignore_ascii_case(name)
                .then(|| (parameter.to_string(), *v))
        })
        .collect()
}

/// Which bodies a system is built with.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Bodies {
    /// The flexible bodies of the pROM artifacts.
    Flexible,
    /// The rigid twin (eq. 4.10): every flexible body rigid with its undeformed mass
    /// properties at p (mass, first and second moments of the invariants, no modes), its
    /// markers at the grids' undeformed positions; everything else as in the mechanism.
    RigidTwin,
}

/// A flexible body's data without its modes: the rigid body of its undeformed mass
/// properties, in the same frame (the zero-mode case of [`FlexibleBodyData`]).
fn rigid(data: &FlexibleBodyData) -> FlexibleBodyData {
    let i = &data.invariants;
    FlexibleBodyData {
        invariants: MassInvariants {
            mass: i.mass,
            first: i.first,
            first_modal: Vec::new(),
            second: i.second,
            second_mixed: Vec::new(),
            second_modal: Vec::new(),
        },
        mass: Mat::zeros(0, 0),
        stiffness: Mat::zeros(0, 0),
        damping: Mat::zeros(0, 0),
        interfaces: data
            .interfaces
            .iter()
            .map(|r| InterfaceRows {
                grid: r.grid,
                position: r.position,
                translation: Vec::new(),
                rotation: Vec::new(),
            })
            .collect(),
    }
}

/// Builds the system of the mechanism `pfmb`, with `bodies`, gravity `gravity` (basic) and the
/// PVAL values `pval` (`BODY.PMPAR`, value). Every error found is returned, at its card.
pub fn build_system(
    pfmb: &Pfmb,
    gravity: [f64; 3],
    pval: &[(String, f64)],
    bodies: Bodies,
) -> Result<MechanismSystem, Vec<MechanismError>> {
    let mech: &Mechanism = &pfmb.mechanism;
    let mut errors = Vec::new();
    let error = |card: Card, message: String| MechanismError {
        card,
        field: None,
        message,
    };
    let mut system = System::new(gravity);
    let mut placements = Vec::new();
    let mut flexible = Vec::new();
    let mut flexible_of = Vec::new();
    let mut interfaces: Vec<Vec<InterfaceRows>> = Vec::new();
    for (index, b) in mech.bodies.iter().enumerate() {
        match &b.kind {
            BodyKind::Flexible {
                artifact,
                origin,
                axes,
            } => {
                let rotation = transpose(axes);
                let parametric = pfmb.bodies[index]
                    .as_ref()
                    .expect("a pFMB holds every flexible body's data");
                let shown = artifact.display().to_string();
                match parametric.at(&values_of(&b.name, pval), &shown) {
                    Ok(at) => {
                        let data = match bodies {
                            Bodies::Flexible => at.data.clone(),
                            Bodies::RigidTwin => rigid(&at.data),
                        };
                        interfaces.push(data.interfaces.clone());
                        system.add_body(
                            Body::flexible(data),
                            *origin,
                            from_rotation_matrix(&rotation),
                        );
                        flexible_of.push(Some(flexible.len()));
                        flexible.push((b.name.clone(), at));
                    }
                    Err(message) => {
                        errors.push(error(Card::Body(index), message));
                        flexible_of.push(None);
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
                flexible_of.push(None);
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
    for (index, m) in mech.markers.iter().enumerate() {
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
                if rows.is_none() && !errors.iter().any(|e| e.card == Card::Body(b)) {
                    errors.push(MechanismError {
                        card: Card::Marker(index),
                        field: Some("field 4 (GRID)"),
                        message: format!(
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
                    });
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
    for (index, d) in mech.drives.iter().enumerate() {
        let signal = table_signal(
            pfmb.table(d.table).expect("a pFMB holds its tables"),
            d.scale,
        );
        let kind = d
            .compliance
            .map_or(DriveKind::Rigid, |(stiffness, damping)| {
                DriveKind::Compliant { stiffness, damping }
            });
        match system.add_drive(joints[d.joint], signal, kind) {
            Ok(i) => drives.push(i),
            Err(e) => errors.push(error(Card::Drive(index), e.to_string())),
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
        let (marker, direction) = (markers[f.marker], f.direction);
        let signal = table_signal(
            pfmb.table(f.table).expect("a pFMB holds its tables"),
            f.scale,
        );
        system.add_force(match f.kind {
            ForceKind::Force => Force::Point {
                marker,
                direction,
                signal,
            },
            ForceKind::Moment => Force::Moment {
                marker,
                direction,
                signal,
            },
        });
    }
    for (index, s) in mech.sensors.iter().enumerate() {
        let SensorTarget::Strain { body, sensor } = &s.target else {
            continue;
        };
        let Some((name, at)) = flexible_of[*body].map(|f| &flexible[f]) else {
            continue; // the body's artifact could not be read: reported at its FLEXB
        };
        if !at
            .strain_sensors
            .iter()
            .any(|(n, _)| n.eq_ignore_ascii_case(sensor))
        {
            errors.push(MechanismError {
                card: Card::Sensor(index),
                field: Some("field 6 (REF)"),
                message: format!(
                    "{sensor} is not a STRAIN sensor of the artifact of body {name} (its STRAIN sensors: {})",
                    if at.strain_sensors.is_empty() {
                        "none: give SENSOR cards of KIND STRAIN to its SOL PROM build".to_string()
                    } else {
                        at.strain_sensors
                            .iter()
                            .map(|(n, _)| n.as_str())
                            .collect::<Vec<_>>()
                            .join(" ")
                    }
                ),
            });
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
        flexible_of,
    })
}

impl MechanismSystem {
    /// This system with its flexible bodies evaluated at the PVAL values `pval` (`BODY.PMPAR`,
    /// value; nominal where not given) instead: only the bodies' affine sums of eq. 4.8 and
    /// the pROM's matrices are recomputed ([`super::prom_body::ParametricBody::at`]); markers,
    /// joints, drives and forces do not depend on p (the basis is constant). `pfmb` is the
    /// mechanism this system was built from with `bodies`; a name that is no parameter of its
    /// body's artifact is an error naming the body.
    pub fn at_parameters(
        &self,
        pfmb: &Pfmb,
        pval: &[(String, f64)],
        bodies: Bodies,
    ) -> Result<MechanismSystem, String> {
        let mut out = self.clone();
        for (index, b) in pfmb.mechanism.bodies.iter().enumerate() {
            let (Some(parametric), Some(f)) = (&pfmb.bodies[index], self.flexible_of[index]) else {
                continue;
            };
            let at = parametric.at(&values_of(&b.name, pval), &b.name)?;
            out.system.bodies[index] = Body::flexible(match bodies {
                Bodies::Flexible => at.data.clone(),
                Bodies::RigidTwin => rigid(&at.data),
            });
            out.flexible[f].1 = at;
        }
        Ok(out)
    }

    /// Makes the flexible bodies named in `tables` (`BODY.PMPAR`, p(t)) follow time: each such
    /// body's data become its pROM's affine sums at the tables' values at t and the constant
    /// values of `pval` for its other parameters ([`crate::multibody::schedule`]), the rigid
    /// twin's its undeformed mass properties at them. `pfmb` is the mechanism this system was
    /// built from with `bodies`; the names are `BODY.PMPAR`s of its flexible bodies
    /// ([`Pfmb::check_parameter_names`]), a PMPAR its body's pROM lacks is the error.
    pub fn schedule(
        &mut self,
        pfmb: &Pfmb,
        pval: &[(String, f64)],
        tables: &[(String, Table)],
        bodies: Bodies,
    ) -> Result<(), String> {
        for (index, b) in pfmb.mechanism.bodies.iter().enumerate() {
            let Some(parametric) = &pfmb.bodies[index] else {
                continue;
            };
            let varying: Vec<(String, Table)> = (tables.iter())
                .filter_map(|(n, table)| {
                    let (body, parameter) = n.split_once('.')?;
                    body.eq_ignore_ascii_case(&b.name)
                        .then(|| (parameter.to_string(), table.clone()))
                })
                .collect();
            if varying.is_empty() {
                continue;
            }
            let constant = values_of(&b.name, pval);
            let values = move |t: f64| {
                let mut values = constant.clone();
                values.extend(varying.iter().map(|(n, table)| (n.clone(), table.value(t))));
                values
            };
            // the names are checked here, once: at any later t only the values differ
            parametric.at(&values(0.0), &b.name)?;
            let (parametric, name) = (parametric.clone(), b.name.clone());
            self.system
                .schedules
                .push(BodySchedule::new(index, move |t| {
                    let at = parametric
                        .at(&values(t), &name)
                        .expect("the parameter names were checked when the schedule was built");
                    match bodies {
                        Bodies::Flexible => at.data,
                        Bodies::RigidTwin => rigid(&at.data),
                    }
                }));
        }
        Ok(())
    }

    /// The outputs of `sensors` (MSENSORs of the model this system was built from) on the
    /// system's markers, joints and drives.
    pub fn outputs(&self, sensors: &[Sensor]) -> Vec<Output> {
        sensors
            .iter()
            .map(|s| match (s.kind, s.target.clone()) {
                (MsensorKind::Pos, SensorTarget::Marker(m)) => Output::Position {
                    marker: self.markers[m],
                    direction: s.direction,
                },
                (MsensorKind::Accel, SensorTarget::Marker(m)) => Output::Acceleration {
                    marker: self.markers[m],
                    direction: s.direction,
                },
                (MsensorKind::Jforce, SensorTarget::Joint(j)) => Output::JointForce {
                    joint: self.joints[j],
                    direction: s.direction,
                },
                (MsensorKind::Jtorq, SensorTarget::Joint(j)) => {
                    Output::DriveEffort(self.drives[self.driving(j)])
                }
                (MsensorKind::Power, SensorTarget::Drive(d)) => Output::DrivePower(self.drives[d]),
                (MsensorKind::Energy, SensorTarget::Drive(d)) => {
                    Output::DriveEnergy(self.drives[d])
                }
                (MsensorKind::Power, SensorTarget::System) => Output::DrivesPower,
                (MsensorKind::Energy, SensorTarget::System) => Output::DrivesEnergy,
                (MsensorKind::Ke, _) => Output::KineticEnergy,
                (MsensorKind::Dev, SensorTarget::Marker(m)) => Output::Deviation(self.markers[m]),
                (MsensorKind::Strain, SensorTarget::Strain { body, sensor }) => Output::Strain {
                    body,
                    rows: self.strain_rows(body, &sensor),
                },
                (kind, target) => unreachable!(
                    "the model pairs MSENSOR {} with its target kind, not {target:?}",
                    kind.keyword()
                ),
            })
            .collect()
    }

    /// The row C_ε of the STRAIN sensor `sensor` of a flexible body's artifact; the sensors
    /// are checked by [`build_system`].
    fn strain_rows(&self, body: usize, sensor: &str) -> Vec<f64> {
        let (_, at) = &self.flexible[self.flexible_of[body].expect("a STRAIN body is a FLEXB")];
        at.strain_sensors
            .iter()
            .find(|(n, _)| n.eq_ignore_ascii_case(sensor))
            .map(|(_, rows)| rows.clone())
            .expect("build_system checks the STRAIN sensors")
    }

    /// The JDRIVE (index) of joint `joint` (index into the JOINTs); the model checks that a
    /// JTORQ's joint has one.
    fn driving(&self, joint: usize) -> usize {
        let system_joint = self.joints[joint];
        self.drives
            .iter()
            .position(|&d| self.system.drives[d].joint == system_joint)
            .expect("the model checks that a JTORQ joint has a JDRIVE")
    }
}
