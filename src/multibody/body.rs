//! Bodies: a rigid body is the zero-mode case of the reduced flexible body, so both share one
//! inertia kernel ([`super::inertia`]) and one set of data ([`FlexibleBodyData`]).

use super::flexible::{FlexibleBodyData, MassInvariants};
use crate::geometry::mat3::Mat3;
use faer::Mat;

/// A body of the system: its mass moments, reduced matrices and interface rows (none and
/// 0 × 0 for a rigid body).
#[derive(Debug, Clone)]
pub struct Body {
    pub data: FlexibleBodyData,
}

impl Body {
    /// A rigid body of mass m and inertia J about its centre of mass in body components; its
    /// frame origin is the centre of mass (M_R = m I, M_ΘΘ = 4 Gᵀ J G + 2 tr(J) e eᵀ).
    pub fn rigid(mass: f64, inertia: Mat3) -> Self {
        Self {
            data: FlexibleBodyData {
                invariants: MassInvariants::rigid(mass, inertia),
                mass: Mat::zeros(0, 0),
                stiffness: Mat::zeros(0, 0),
                damping: Mat::zeros(0, 0),
                interfaces: Vec::new(),
            },
        }
    }

    /// A flexible body from its reduced data at p.
    pub fn flexible(data: FlexibleBodyData) -> Self {
        Self { data }
    }

    /// Number of flexible coordinates.
    pub fn modes(&self) -> usize {
        self.data.invariants.modes()
    }
}
