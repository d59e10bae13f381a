//! Bodies whose data follow time: a flexible body's reduced matrices and mass invariants
//! evaluated at parameters that are functions of time (a pROM's affine sums at p(t), e.g. a
//! Young's modulus degrading in time). The integrator sets every scheduled body's data at
//! the end time of each step before its Newton iterations ([`super::Ggl::step`]), so BDF1
//! takes K(p(t_{k+1})), C(p(t_{k+1})) and M(p(t_{k+1})) implicitly, like the step's forces; a
//! mass that changes in time enters as M(t) q̈ with no Ṁ q̇ term (the parameters are
//! properties of the material, not a flow of mass).

use std::fmt;
use std::sync::Arc;

use super::flexible::FlexibleBodyData;
use super::system::BodyId;

/// The data of `body` as a function of time.
#[derive(Clone)]
pub struct BodySchedule {
    pub body: BodyId,
    data: Arc<dyn Fn(f64) -> FlexibleBodyData + Send + Sync>,
}

impl fmt::Debug for BodySchedule {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "BodySchedule {{ body: {} }}", self.body)
    }
}

impl BodySchedule {
    /// Body `body` with data `data(t)` (same number of modes and interfaces at every t).
    pub fn new(
        body: BodyId,
        data: impl Fn(f64) -> FlexibleBodyData + Send + Sync + 'static,
    ) -> Self {
        Self {
            body,
            data: Arc::new(data),
        }
    }

    /// The body's data at t.
    pub fn at(&self, t: f64) -> FlexibleBodyData {
        (self.data)(t)
    }
}
