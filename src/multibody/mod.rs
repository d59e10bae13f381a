//! Flexible multibody dynamics in the floating frame of reference (thesis ch. 2.4, 4.3 and
//! appendix A; DESIGN.md §11): rigid and flexible (reduced, FFR) bodies with Euler-parameter
//! orientations, markers, joints and drives as algebraic constraints, spring-dampers and point
//! forces, and the stabilized index-2 (GGL) equations of motion integrated with BDF1, BDF2 or
//! generalized-α.
//!
//! - [`layout`]: the system coordinates q = [q¹ … q^{n_b}] with qⁱ = [r (3), e (4), q_f (n_r)]
//!   (eq. 2.44–2.45); ground has none.
//! - [`inertia`]: mass matrix, quadratic velocity vector and gravity force of one body from
//!   its mass moments (eq. 2.47–2.50, A.5–A.27); [`body`] and [`flexible`]: rigid and flexible
//!   bodies and the reduced data a flexible body is built from.
//! - [`vectors`]: points and directions fixed to a body (markers), with their first and
//!   second derivatives with respect to q; [`marker`]: markers.
//! - [`constraint`]: scalar constraints written as sums of time-weighted dot products of body
//!   vectors (Φ, Φ_q, Φ_t and Hessian products); [`constraint_set`]: all of them evaluated into
//!   dense storage, with the bodies' rotation matrices computed once per evaluation
//!   ([`rotations`]); [`joints`]: joints and drives built from them; [`redundancy`]: redundant
//!   constraints found by a column-pivoted QR of Φ_qᵀ, and the rows closest to dependent where
//!   a step fails.
//! - [`forces`]: point forces, point-to-point and joint spring-dampers, compliant drives.
//! - [`signal`]: time functions with their first two derivatives; [`schedule`]: bodies whose
//!   data follow time (pROM parameters that are functions of time); [`error`]: what stops a
//!   run.
//! - [`system`]: the assembled system and its residual terms; [`integrator`]: consistent
//!   initial conditions and the GGL step (eq. 2.60–2.61) with the modified Newton of
//!   [`crate::dynamics::newton`]; [`correction`]: the metric of its position correction;
//!   [`dense_lu`]: its iteration matrix's LU; [`scheme`]:
//!   BDF1, BDF2 and generalized-α as one step form; [`statics`]: static equilibrium under
//!   gravity with drives held, with the exact stiffness of the applied forces at rest
//!   ([`stiffness`]); [`poses`]: equilibria over a grid of drive poses, each started
//!   from its neighbour's;
//!   [`output`]: marker kinematics, reactions, drive torques, power and energy;
//!   [`simulation`]: a run over a time grid with the histories of chosen outputs;
//!   [`step_control`]: error-controlled step sizes (local error estimate and controller);
//!   [`derivatives`]: the data-carrying terms of the equations of motion and their exact
//!   derivatives with respect to a body's parameters.
//!
//! A system is built here from plain data; the system of a deck's mechanism, with its flexible
//! bodies read from pROM artifacts, is built by [`crate::discretize::mechanism`].

pub mod block_kkt;
pub mod body;
pub mod constraint;
pub mod constraint_set;
#[cfg(test)]
mod constraint_tests;
pub mod correction;
pub mod dense_lu;
pub mod derivatives;
pub mod error;
pub mod flexible;
pub mod forces;
pub mod inertia;
#[cfg(test)]
mod inertia_tests;
pub mod integrator;
pub mod joints;
pub mod layout;
pub mod marker;
pub mod output;
pub mod poses;
pub mod redundancy;
pub mod rotations;
pub mod schedule;
pub mod scheme;
pub mod sensitivity;
pub mod signal;
pub mod simulation;
pub mod statics;
#[cfg(test)]
mod statics_tests;
pub mod step_control;
pub mod stiffness;
pub mod system;
pub mod vectors;

pub use body::Body;
pub use correction::CorrectionMetric;
pub use derivatives::EomTerms;
pub use error::{Dependence, MultibodyError};
pub use flexible::{FlexibleBodyData, InterfaceRows, MassInvariants};
pub use forces::Force;
pub use integrator::{Ggl, NewtonSettings, StepReport};
pub use joints::{Drive, DriveKind, Joint, JointKind};
pub use marker::Marker;
pub use schedule::BodySchedule;
pub use scheme::Scheme;
pub use sensitivity::{ParameterRate, Sensitivities};
pub use signal::Signal;
pub use simulation::{
    Histories, Output, OutputSensitivities, Start, TimeGrid, simulate, simulate_sensitivities,
};
pub use step_control::StepControl;
pub use system::{BodyId, MarkerId, System};
