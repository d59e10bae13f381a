//! The rotation matrix A(e) of every body at one configuration q (eq. A.4), computed once per
//! evaluation and shared by all body vectors of the constraints: a body carries several
//! markers, each in several constraint rows, and every one of them turns with the same A.

use super::layout::Layout;
use crate::geometry::euler_parameters::rotation_matrix;
use crate::geometry::mat3::{IDENTITY, Mat3};

/// A(e) of each body at one q (see module docs).
#[derive(Debug, Clone, Default)]
pub struct Rotations {
    matrices: Vec<Mat3>,
}

impl Rotations {
    /// The rotations of the bodies of `layout` at q.
    pub fn at(layout: &Layout, q: &[f64]) -> Self {
        let mut rotations = Self::default();
        rotations.update(layout, q);
        rotations
    }

    /// Recomputes the rotations at q (no allocation once sized for the layout).
    pub fn update(&mut self, layout: &Layout, q: &[f64]) {
        self.matrices.resize(layout.slices().len(), IDENTITY);
        for (a, s) in self.matrices.iter_mut().zip(layout.slices()) {
            *a = rotation_matrix(&s.euler_parameters(q));
        }
    }

    /// A(e) of `body`; the identity for the ground (`None`).
    pub fn of(&self, body: Option<usize>) -> &Mat3 {
        body.map_or(&IDENTITY, |b| &self.matrices[b])
    }
}
