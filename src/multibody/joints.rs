//! Joints between two markers and drives of a joint's relative coordinate, as scalar
//! constraints ([`Constraint`]). With p = p₁ − p₂ and the axes (x, y, z) of each marker, the
//! frame of marker 2 being the joint frame (z its axis):
//!
//! | joint | rows |
//! |---|---|
//! | spherical | p = 0 (3) |
//! | revolute about z₂ | p = 0, z₂·x₁ = 0, z₂·y₁ = 0 |
//! | fixed | p = 0, z₂·x₁ = 0, z₂·y₁ = 0, y₂·x₁ = 0 |
//! | universal (cross axes z₁, z₂) | p = 0, z₁·z₂ = 0 |
//! | prismatic along z₂ | x₂·p = 0, y₂·p = 0, z₂·x₁ = 0, z₂·y₁ = 0, y₂·x₁ = 0 |
//! | cylindrical along z₂ | x₂·p = 0, y₂·p = 0, z₂·x₁ = 0, z₂·y₁ = 0 |
//! | inline (p₁ on the line through p₂ along z₂) | x₂·p = 0, y₂·p = 0 |
//! | in-plane (p₁ in the plane through p₂ normal to z₂) | z₂·p = 0 |
//!
//! The relative coordinate of a revolute joint is the angle θ from x₂ to x₁ about z₂,
//! θ = atan2(x₁·y₂, x₁·x₂); of a prismatic joint the slide s = z₂·p. A rigid drive
//! prescribes θ_d(t) = θ₀ + f(t) through the rheonomic constraint
//! cos θ_d (x₁·y₂) − sin θ_d (x₁·x₂) = sin(θ − θ_d) = 0 (its multiplier is minus the drive
//! torque), or s − s₀ − f(t) = 0; a compliant drive applies K(θ_d − θ) + C(θ̇_d − θ̇) instead
//! (DESIGN.md §11 `JDRIVE`).

use super::constraint::{Constraint, DotTerm, VectorSum, Weight};
use super::marker::Marker;
use super::signal::Signal;

/// Joint types (DESIGN.md §11 `JOINT`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum JointKind {
    Revolute,
    Fixed,
    Spherical,
    Prismatic,
    Cylindrical,
    Universal,
    Inline,
    Inplane,
}

/// A joint between markers `first` and `second` (indices into the system's markers).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Joint {
    pub kind: JointKind,
    pub first: usize,
    pub second: usize,
}

/// How a drive acts.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum DriveKind {
    /// A rheonomic constraint; its multiplier gives the drive torque (force).
    Rigid,
    /// A spring-damper toward the prescribed coordinate (Fig. 4.15b).
    Compliant { stiffness: f64, damping: f64 },
}

/// A drive of a revolute or prismatic joint's coordinate: initial value + f(t).
#[derive(Debug, Clone)]
pub struct Drive {
    pub joint: usize,
    pub motion: Signal,
    pub kind: DriveKind,
}

fn dot_rows(pairs: &[(VectorSum, VectorSum)]) -> Vec<Constraint> {
    pairs
        .iter()
        .map(|(u, w)| Constraint::dot(u.clone(), w.clone()))
        .collect()
}

impl JointKind {
    /// The scalar constraints of this joint between markers `m1` and `m2` (table above).
    pub fn constraints(self, m1: &Marker, m2: &Marker) -> Vec<Constraint> {
        let sep = || VectorSum::difference(m1.point(), m2.point());
        let axis1 = |i| VectorSum::of(m1.axis(i));
        let axis2 = |i| VectorSum::of(m2.axis(i));
        let unit = |i: usize| {
            let mut e = [0.0; 3];
            e[i] = 1.0;
            VectorSum::constant(e)
        };
        let coincident = || (0..3).map(|i| (unit(i), sep())).collect::<Vec<_>>();
        let parallel_axes = || vec![(axis2(2), axis1(0)), (axis2(2), axis1(1))];
        let lateral = || vec![(axis2(0), sep()), (axis2(1), sep())];
        let pairs: Vec<(VectorSum, VectorSum)> = match self {
            JointKind::Spherical => coincident(),
            JointKind::Revolute => [coincident(), parallel_axes()].concat(),
            JointKind::Fixed => {
                [coincident(), parallel_axes(), vec![(axis2(1), axis1(0))]].concat()
            }
            JointKind::Universal => [coincident(), vec![(axis1(2), axis2(2))]].concat(),
            JointKind::Prismatic => {
                [lateral(), parallel_axes(), vec![(axis2(1), axis1(0))]].concat()
            }
            JointKind::Cylindrical => [lateral(), parallel_axes()].concat(),
            JointKind::Inline => lateral(),
            JointKind::Inplane => vec![(axis2(2), sep())],
        };
        dot_rows(&pairs)
    }

    /// Whether a drive can prescribe this joint's coordinate.
    pub fn is_drivable(self) -> bool {
        matches!(self, JointKind::Revolute | JointKind::Prismatic)
    }
}

fn angle_pairs(m1: &Marker, m2: &Marker) -> [(VectorSum, VectorSum); 2] {
    [
        (VectorSum::of(m1.axis(0)), VectorSum::of(m2.axis(1))),
        (VectorSum::of(m1.axis(0)), VectorSum::of(m2.axis(0))),
    ]
}

fn slide_pair(m1: &Marker, m2: &Marker) -> (VectorSum, VectorSum) {
    (
        VectorSum::of(m2.axis(2)),
        VectorSum::difference(m1.point(), m2.point()),
    )
}

/// The joint coordinate as functions of q: for a revolute joint the two dot products
/// (x₁·y₂, x₁·x₂) whose atan2 is θ, for a prismatic joint the slide z₂·p alone.
pub fn coordinate_parts(kind: JointKind, m1: &Marker, m2: &Marker) -> Vec<Constraint> {
    match kind {
        JointKind::Revolute => dot_rows(&angle_pairs(m1, m2)),
        _ => dot_rows(&[slide_pair(m1, m2)]),
    }
}

/// The rheonomic constraint of a rigid drive with initial coordinate `initial`.
pub fn drive_constraint(
    kind: JointKind,
    m1: &Marker,
    m2: &Marker,
    initial: f64,
    motion: &Signal,
) -> Constraint {
    match kind {
        JointKind::Revolute => {
            let [(su, sw), (cu, cw)] = angle_pairs(m1, m2);
            Constraint::Dots {
                terms: vec![
                    DotTerm {
                        weight: Weight::CosOf(initial, motion.clone()),
                        u: su,
                        w: sw,
                    },
                    DotTerm {
                        weight: Weight::NegSinOf(initial, motion.clone()),
                        u: cu,
                        w: cw,
                    },
                ],
                offset: None,
            }
        }
        _ => {
            let (u, w) = slide_pair(m1, m2);
            Constraint::Dots {
                terms: vec![DotTerm {
                    weight: Weight::Constant(1.0),
                    u,
                    w,
                }],
                offset: Some(Weight::NegOf(initial, motion.clone())),
            }
        }
    }
}
