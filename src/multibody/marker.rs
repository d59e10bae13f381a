//! Markers: a point with an orthonormal frame (axes x, y, z) fixed to a body. On a rigid body
//! or the ground they are constant in body (global) components; on a flexible body the point
//! moves with its interface grid's translation rows and the frame turns with its rotation rows
//! (small rotation θ(q_f) = Σₖ θₖ q_fk, so an axis d̄ becomes d̄ + θ × d̄; eq. 2.58).

use super::flexible::InterfaceRows;
use super::vectors::BodyVector;
use crate::geometry::mat3::{IDENTITY, Mat3};
use crate::geometry::vec3::cross;

/// A point and frame on a body (see module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct Marker {
    /// The body index, `None` for the ground.
    pub body: Option<usize>,
    /// Undeformed position in body (ground: global) components.
    pub position: [f64; 3],
    /// Rows are the unit axes x, y, z in body (ground: global) components.
    pub axes: Mat3,
    /// Translation rows ψₖ of the marker's grid (flexible bodies only).
    pub translation: Vec<[f64; 3]>,
    /// Rotation rows θₖ of the marker's grid (flexible bodies only).
    pub rotation: Vec<[f64; 3]>,
}

impl Marker {
    /// A marker on a rigid body (position relative to its centre of mass) or, with
    /// `body = None`, on the ground; frame aligned with the body (global) axes.
    pub fn new(body: Option<usize>, position: [f64; 3]) -> Self {
        Self {
            body,
            position,
            axes: IDENTITY,
            translation: Vec::new(),
            rotation: Vec::new(),
        }
    }

    /// A marker at an interface grid of a flexible body.
    pub fn at_grid(body: usize, rows: &InterfaceRows) -> Self {
        Self {
            body: Some(body),
            position: rows.position,
            axes: IDENTITY,
            translation: rows.translation.clone(),
            rotation: rows.rotation.clone(),
        }
    }

    /// The same marker with the frame whose z axis is `axis` (normalized), x the unit vector
    /// most perpendicular to it made orthogonal, y = z × x.
    pub fn with_z_axis(mut self, axis: [f64; 3]) -> Self {
        let z = crate::geometry::vec3::normalize(axis).unwrap_or([0.0, 0.0, 1.0]);
        let pick = (0..3)
            .min_by(|&a, &b| z[a].abs().total_cmp(&z[b].abs()))
            .unwrap_or(0);
        let mut t = [0.0; 3];
        t[pick] = 1.0;
        let x = crate::geometry::vec3::normalize(cross(cross(z, t), z)).unwrap_or([1.0, 0.0, 0.0]);
        self.axes = [x, cross(z, x), z];
        self
    }

    /// The marker point as a body vector.
    pub fn point(&self) -> BodyVector {
        BodyVector {
            body: self.body,
            is_point: true,
            local: self.position,
            modal: self.translation.clone(),
        }
    }

    /// Axis `i` (0 = x, 1 = y, 2 = z) as a body vector.
    pub fn axis(&self, i: usize) -> BodyVector {
        let d = self.axes[i];
        BodyVector {
            body: self.body,
            is_point: false,
            local: d,
            modal: self.rotation.iter().map(|theta| cross(*theta, d)).collect(),
        }
    }
}
