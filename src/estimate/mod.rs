//! Virtual sensing on pROMs (thesis ch. 7–8): joint estimation of states, unknown inputs and
//! parameters with the augmented EKF, usable from Rust without a deck.
//!
//! - [`ekf`]: the EKF's correction (gain and Joseph update, eq. 8.25–8.28) written once over a
//!   [`ekf::ProcessModel`] that predicts and measures, and the [`ekf::Linearization`] the
//!   observability tests read.
//! - [`filter`]: the augmented EKF with a BDF1 or trapezoidal prediction and analytic Jacobians (eq. 8.1–8.35), the
//!   process model of a pROM (`prom_model`) in one of the pROM's coordinates (`coordinates`: the trait they implement): [`physical`] (the
//!   reduced coordinates q) or modal (`modal_coordinates`, with the couplings of re-diagonalized
//!   modes in `drift`); `propagation` holds the covariance prediction by blocks and `kernels`
//!   the dense kernels.
//! - [`modal`]: the modes in which the filter's modal coordinates are taken, when the pROM
//!   allows them.
//! - [`measurement`]: sensor equations y = h(x*) (eq. 8.36): [`crate::dynamics::measurement`],
//!   shared with the FRF and transient drivers and re-exported here.
//! - [`observability`]: the PBH test before a run (eq. 8.40–8.41, §8.4.3–8.4.4) of any
//!   [`ekf::Linearization`], at the [`operating_points`] of the initial estimate; the pROM's
//!   linearization is [`prom_linearization`].
//! - [`errors`]: the accuracy of an estimate against a reference (Table 8.2's percent errors,
//!   the sensors' average absolute error).
//! - [`mechanism`]: the AMANDA-EKF on pFMB models (thesis ch. 9), over the same [`ekf::Ekf`].
//! - [`covariance`]: the rules of thumb for Q of inputs and parameters (eq. 8.30–8.31).

mod coordinates;
mod drift;
pub mod ekf;
pub mod errors;
pub mod filter;
mod kernels;
pub mod mechanism;
pub use crate::dynamics::measurement;
pub mod modal;
mod modal_coordinates;
pub mod observability;
pub mod operating_points;
pub mod physical;
pub mod prom_linearization;
mod prom_model;
mod propagation;

pub use filter::{Coordinates, Filter, FilterError, FilterSetup, Prediction};
pub use measurement::{Reads, SensorRows};

/// Rules of thumb for the random-walk covariances (thesis §8.3).
pub mod covariance {
    /// Q_u = (Δt ω_u a_u)² for an input of expected frequency ω_u (Hz, as the EKFINP card
    /// gives it) and amplitude a_u (eq. 8.30).
    pub fn input(dt: f64, omega_hz: f64, amplitude: f64) -> f64 {
        (dt * omega_hz * amplitude).powi(2)
    }

    /// Q_p = (Δt δ_p a_p)² for a parameter with scaling δ_p (Hz) and tentative value a_p
    /// (eq. 8.31).
    pub fn parameter(dt: f64, delta_hz: f64, initial: f64) -> f64 {
        (dt * delta_hz * initial).powi(2)
    }
}
