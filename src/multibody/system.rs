//! The multibody system: bodies, markers, joints, drives and forces as the user adds them,
//! and the terms of the equations of motion (eq. 2.46, 4.4) that the integrator combines:
//! the block-diagonal mass matrix (eq. 2.48), the applied generalized forces
//! f = f_v + f_g + f_e − K q − C q̇ (eq. 2.47, 2.52–2.55) and the constraints.

use super::body::Body;
use super::constraint_set::ConstraintSet;
use super::error::MultibodyError;
use super::forces::{Coordinate, Force, SpringDamper};
use super::inertia;
use super::joints::{Drive, DriveKind, Joint, JointKind, coordinate_parts, drive_constraint};
use super::layout::Layout;
use super::marker::Marker;
use super::schedule::BodySchedule;
use super::signal::Signal;
use crate::geometry::euler_parameters::{EulerParameters, rates_from_global_angular_velocity};
use faer::MatMut;

/// Index of a body (the ground is `None` wherever a body is optional).
pub type BodyId = usize;
/// Index of a marker.
pub type MarkerId = usize;

/// A multibody system (see module docs).
#[derive(Debug, Clone, Default)]
pub struct System {
    pub layout: Layout,
    pub bodies: Vec<Body>,
    pub markers: Vec<Marker>,
    pub joints: Vec<Joint>,
    pub drives: Vec<Drive>,
    pub forces: Vec<Force>,
    /// Gravity acceleration in global components.
    pub gravity: [f64; 3],
    /// Bodies whose data follow time ([`super::schedule`]), set at each step's end time.
    pub schedules: Vec<BodySchedule>,
    initial_q: Vec<f64>,
    initial_v: Vec<f64>,
}

/// Where the output of a drive comes from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum DriveSource {
    /// A constraint row (index into the full, unreduced set).
    Row(usize),
    /// A spring-damper (index into the springs).
    Spring(usize),
}

/// The equations built from a [`System`] at its initial configuration: constraints (every
/// row, before redundancy removal), spring-dampers, and where joints and drives live in them.
#[derive(Debug, Clone)]
pub struct Equations {
    pub constraints: ConstraintSet,
    pub springs: Vec<SpringDamper>,
    /// Constraint rows of each joint.
    pub joint_rows: Vec<std::ops::Range<usize>>,
    /// Source of each drive's torque.
    pub drive_sources: Vec<DriveSource>,
    /// Initial coordinate of each drive's joint.
    pub drive_initial: Vec<f64>,
}

impl System {
    /// An empty system with gravity g.
    pub fn new(gravity: [f64; 3]) -> Self {
        Self {
            gravity,
            ..Self::default()
        }
    }

    /// Adds a body with its frame at `position` and orientation `orientation`, at rest.
    pub fn add_body(
        &mut self,
        body: Body,
        position: [f64; 3],
        orientation: EulerParameters,
    ) -> BodyId {
        let slice = self.layout.push(body.modes());
        self.initial_q.extend(position);
        self.initial_q.extend(orientation);
        self.initial_q.extend(std::iter::repeat_n(0.0, slice.modes));
        self.initial_v.extend(std::iter::repeat_n(0.0, slice.len()));
        self.bodies.push(body);
        self.bodies.len() - 1
    }

    /// Sets the initial velocity of a body's frame origin and its angular velocity (global
    /// components); the assembly makes them consistent with the constraints.
    pub fn set_initial_velocity(&mut self, body: BodyId, velocity: [f64; 3], omega: [f64; 3]) {
        let s = self.layout.slice(body);
        let e = s.euler_parameters(&self.initial_q);
        self.initial_v[s.offset..s.offset + 3].copy_from_slice(&velocity);
        let e_dot = rates_from_global_angular_velocity(&e, omega);
        self.initial_v[s.euler()..s.euler() + 4].copy_from_slice(&e_dot);
    }

    /// Replaces the whole initial configuration and velocities (e.g. by a static equilibrium).
    pub fn set_initial_state(&mut self, q: &[f64], v: &[f64]) {
        self.initial_q.copy_from_slice(q);
        self.initial_v.copy_from_slice(v);
    }

    /// Sets the data of every scheduled body to its value at t.
    pub fn apply_schedules(&mut self, t: f64) {
        for schedule in &self.schedules {
            self.bodies[schedule.body].data = schedule.at(t);
        }
    }

    /// Sets the initial flexible coordinates of a body.
    pub fn set_initial_modal(&mut self, body: BodyId, modal: &[f64]) {
        let s = self.layout.slice(body);
        self.initial_q[s.flexible()..s.flexible() + s.modes].copy_from_slice(modal);
    }

    /// Adds a marker.
    pub fn add_marker(&mut self, marker: Marker) -> MarkerId {
        self.markers.push(marker);
        self.markers.len() - 1
    }

    /// Adds a joint between two markers and returns its index.
    pub fn add_joint(&mut self, kind: JointKind, first: MarkerId, second: MarkerId) -> usize {
        self.joints.push(Joint {
            kind,
            first,
            second,
        });
        self.joints.len() - 1
    }

    /// Adds a drive of joint `joint`'s coordinate: initial value + `motion`.
    pub fn add_drive(
        &mut self,
        joint: usize,
        motion: Signal,
        kind: DriveKind,
    ) -> Result<usize, MultibodyError> {
        let Some(j) = self.joints.get(joint) else {
            return Err(MultibodyError::Input(format!(
                "drive on joint {joint}, which does not exist"
            )));
        };
        if !j.kind.is_drivable() {
            return Err(MultibodyError::Input(format!(
                "drive on joint {joint}: a {:?} joint has no coordinate to drive (only revolute and prismatic joints)",
                j.kind
            )));
        }
        self.drives.push(Drive {
            joint,
            motion,
            kind,
        });
        Ok(self.drives.len() - 1)
    }

    /// Adds an applied force.
    pub fn add_force(&mut self, force: Force) {
        self.forces.push(force);
    }

    /// Number of coordinates.
    pub fn size(&self) -> usize {
        self.layout.size()
    }

    /// The initial guesses (q₀, v₀) as added.
    pub fn initial_state(&self) -> (&[f64], &[f64]) {
        (&self.initial_q, &self.initial_v)
    }

    /// The relative coordinate of a revolute (angle) or prismatic (slide) joint.
    pub fn joint_coordinate(&self, joint: usize) -> Coordinate {
        let j = &self.joints[joint];
        let (m1, m2) = (&self.markers[j.first], &self.markers[j.second]);
        let mut parts = coordinate_parts(j.kind, m1, m2);
        match j.kind {
            JointKind::Revolute => {
                let c = parts.pop().expect("two parts");
                let s = parts.pop().expect("two parts");
                Coordinate::Angle([s, c])
            }
            _ => Coordinate::Slide(parts.pop().expect("one part")),
        }
    }

    /// Builds the constraints and spring-dampers at configuration q (drives take their initial
    /// coordinate from it).
    pub fn equations(&self, q: &[f64]) -> Result<Equations, MultibodyError> {
        let n = self.size();
        for (i, m) in self.markers.iter().enumerate() {
            if let Some(b) = m.body.filter(|&b| b >= self.bodies.len()) {
                return Err(MultibodyError::Input(format!(
                    "marker {i} is on body {b}, which does not exist"
                )));
            }
            if let Some(b) = m.body {
                let modes = self.bodies[b].modes();
                if m.translation.len() != modes || m.rotation.len() != modes {
                    return Err(MultibodyError::Input(format!(
                        "marker {i} has {} translation and {} rotation rows, body {b} has {modes} modes",
                        m.translation.len(),
                        m.rotation.len()
                    )));
                }
            }
        }
        let mut constraints = ConstraintSet::default();
        for b in 0..self.bodies.len() {
            constraints.push(
                super::constraint::Constraint::Normalization { body: b },
                format!("Euler-parameter normalization of body {b}"),
            );
        }
        let mut joint_rows = Vec::new();
        for (ji, j) in self.joints.iter().enumerate() {
            let marker = |m: usize| {
                self.markers.get(m).ok_or_else(|| {
                    MultibodyError::Input(format!(
                        "joint {ji} uses marker {m}, which does not exist"
                    ))
                })
            };
            let (m1, m2) = (marker(j.first)?, marker(j.second)?);
            let start = constraints.len();
            for (row, c) in j.kind.constraints(m1, m2).into_iter().enumerate() {
                constraints.push(c, format!("joint {ji} ({:?}) row {row}", j.kind));
            }
            joint_rows.push(start..constraints.len());
        }
        let mut springs = Vec::new();
        let mut gradient = vec![0.0; n];
        for f in &self.forces {
            match f {
                Force::PointSpringDamper {
                    first,
                    second,
                    stiffness,
                    damping,
                    length,
                } => springs.push(SpringDamper {
                    coordinate: Coordinate::Distance(super::constraint::VectorSum::difference(
                        self.markers[*first].point(),
                        self.markers[*second].point(),
                    )),
                    stiffness: *stiffness,
                    damping: *damping,
                    rest: *length,
                    motion: None,
                }),
                Force::JointSpringDamper {
                    joint,
                    stiffness,
                    damping,
                    rest,
                } => springs.push(SpringDamper {
                    coordinate: self.joint_coordinate(*joint),
                    stiffness: *stiffness,
                    damping: *damping,
                    rest: *rest,
                    motion: None,
                }),
                Force::Point { .. } | Force::Moment { .. } => {}
            }
        }
        let mut drive_sources = Vec::new();
        let mut drive_initial = Vec::new();
        for (di, d) in self.drives.iter().enumerate() {
            let coordinate = self.joint_coordinate(d.joint);
            let initial = coordinate.evaluate(&self.layout, q, &mut gradient);
            drive_initial.push(initial);
            let j = &self.joints[d.joint];
            match d.kind {
                DriveKind::Rigid => {
                    let (m1, m2) = (&self.markers[j.first], &self.markers[j.second]);
                    drive_sources.push(DriveSource::Row(constraints.len()));
                    constraints.push(
                        drive_constraint(j.kind, m1, m2, initial, &d.motion),
                        format!("drive {di} of joint {}", d.joint),
                    );
                }
                DriveKind::Compliant { stiffness, damping } => {
                    drive_sources.push(DriveSource::Spring(springs.len()));
                    springs.push(SpringDamper {
                        coordinate,
                        stiffness,
                        damping,
                        rest: initial,
                        motion: Some(d.motion.clone()),
                    });
                }
            }
        }
        Ok(Equations {
            constraints,
            springs,
            joint_rows,
            drive_sources,
            drive_initial,
        })
    }

    /// The block-diagonal mass matrix M(q) (eq. 2.48) into `out` (n × n, overwritten).
    pub fn mass_matrix(&self, q: &[f64], mut out: MatMut<'_, f64>) {
        out.fill(0.0);
        for (body, s) in self.bodies.iter().zip(self.layout.slices()) {
            inertia::mass_matrix(
                &body.data.invariants,
                body.data.mass.as_ref(),
                &s.euler_parameters(q),
                s.modal(q),
                out.as_mut()
                    .submatrix_mut(s.offset, s.offset, s.len(), s.len()),
            );
        }
    }

    /// ½ q̇ᵀ M(q) q̇, body by body.
    pub fn kinetic_energy(&self, q: &[f64], v: &[f64]) -> f64 {
        let mut e = 0.0;
        for (body, s) in self.bodies.iter().zip(self.layout.slices()) {
            let inv = &body.data.invariants;
            let configuration =
                inertia::Configuration::new(inv, &s.euler_parameters(q), s.modal(q));
            let vb = &v[s.offset..s.offset + s.len()];
            let mut momentum = vec![0.0; s.len()];
            configuration.mass_product(inv, body.data.mass.as_ref(), vb, &mut momentum);
            e += 0.5 * vb.iter().zip(&momentum).map(|(a, b)| a * b).sum::<f64>();
        }
        e
    }

    /// The applied generalized forces f(q, q̇, t) into `force` (overwritten). With
    /// `iteration = Some((dq, dv, c))` adds −c ∂f/∂q to dq and −c ∂f/∂q̇ to dv for the terms
    /// the Newton matrix keeps: K, C, ∂f_v/∂q̇ and the spring-dampers' K ∇ℓ∇ℓᵀ, C ∇ℓ∇ℓᵀ.
    pub fn applied_forces(
        &self,
        equations: &Equations,
        q: &[f64],
        v: &[f64],
        t: f64,
        force: &mut [f64],
        iteration: Option<(MatMut<'_, f64>, MatMut<'_, f64>, f64)>,
    ) {
        self.forces_and_momentum(equations, q, v, t, force, None, iteration);
    }

    /// [`System::applied_forces`] and, with `momentum = Some((w, out))`, M(q) w into `out`,
    /// body by body from the same configuration moments (no n × n matrix).
    #[allow(clippy::too_many_arguments)]
    pub fn forces_and_momentum(
        &self,
        equations: &Equations,
        q: &[f64],
        v: &[f64],
        t: f64,
        force: &mut [f64],
        mut momentum: Option<(&[f64], &mut [f64])>,
        mut iteration: Option<(MatMut<'_, f64>, MatMut<'_, f64>, f64)>,
    ) {
        force.fill(0.0);
        let largest = 7 + self.bodies.iter().map(Body::modes).max().unwrap_or(0);
        let mut scratch = vec![0.0; largest];
        // the rate Jacobian's body block, only when the iteration matrix is asked for
        let size = if iteration.is_some() { largest } else { 0 };
        let mut block = faer::Mat::zeros(size, size);
        for (body, s) in self.bodies.iter().zip(self.layout.slices()) {
            let inv = &body.data.invariants;
            let (e, qf) = (s.euler_parameters(q), s.modal(q));
            let (e_dot, qf_dot) = (s.euler_parameters(v), s.modal(v));
            let configuration = inertia::Configuration::moving(inv, &e, qf, qf_dot);
            let local = &mut scratch[..s.len()];
            configuration.quadratic_velocity(inv, &e_dot, qf_dot, local);
            let out = &mut force[s.offset..s.offset + s.len()];
            for (o, x) in out.iter_mut().zip(local.iter()) {
                *o += x;
            }
            configuration.gravity_force(inv, self.gravity, local);
            for (o, x) in out.iter_mut().zip(local.iter()) {
                *o += x;
            }
            let (k, c) = (&body.data.stiffness, &body.data.damping);
            for j in 0..s.modes {
                let (kj, cj) = (k.col(j), c.col(j));
                for (i, o) in out[7..].iter_mut().enumerate() {
                    *o -= kj[i] * qf[j] + cj[i] * qf_dot[j];
                }
            }
            if let Some((w, product)) = momentum.as_mut() {
                let range = s.offset..s.offset + s.len();
                configuration.mass_product(
                    inv,
                    body.data.mass.as_ref(),
                    &w[range.clone()],
                    &mut product[range],
                );
            }
            if let Some((dq, dv, coef)) = iteration.as_mut() {
                let mut block = block.as_mut().submatrix_mut(0, 0, s.len(), s.len());
                configuration.quadratic_velocity_rate_jacobian(inv, &e_dot, qf_dot, block.as_mut());
                for i in 0..s.len() {
                    for j in 0..s.len() {
                        dv[(s.offset + i, s.offset + j)] -= *coef * block[(i, j)];
                    }
                }
                s.add_modal_block(dq, k.as_ref(), *coef);
                s.add_modal_block(dv, c.as_ref(), *coef);
            }
        }
        for f in &self.forces {
            f.add_load(&self.markers, &self.layout, q, t, force);
        }
        let mut gradient = vec![0.0; self.size()];
        for spring in &equations.springs {
            let jac = iteration
                .as_mut()
                .map(|(dq, dv, c)| (dq.as_mut(), dv.as_mut(), *c, *c));
            spring.apply(&self.layout, q, v, t, &mut gradient, force, jac);
        }
    }
}
