//! Frequency and time response (thesis §2.4; DESIGN.md §2).
//!
//! - [`frf`]: receptance of a dense (reduced) model, H(ω) = S_out (K − ω²M + iωC)⁻¹ S_in;
//! - [`measurement`]: sensor equations y = h(q, q̇, q̈) and their factors (iω)^k in frequency,
//!   shared by the FRF, transient and estimation sequences;
//! - [`integrators`]: BDF1 (eq. 2.61), BDF2 and generalized-α with a constant step;
//! - [`nonlinear`]: the same methods on nonlinear systems in residual form, with Newton;
//! - [`newton`]: Newton's method for one implicit step (residual, factor, solve supplied by
//!   the equations; Jacobian update policy), shared by [`nonlinear`] and the GGL multibody
//!   integrator;
//! - [`velocity_form`]: one BDF1 step in velocity form over the caller's operators (the
//!   estimator's prediction);
//! - [`sparse_backend`]: the integrators' full-model (sparse f-set) backend;
//! - [`table`]: tabulated functions of time or frequency (TABLED1–TABLED4, TABLEF);
//! - [`prescribed`]: enforced motion of constrained DOFs, advanced by each method's own update;
//! - [`pulse`]: the TLOAD2 pulse;
//! - [`random`]: output spectral densities, RMS, N0 and autocorrelation of a random response.

pub mod frf;
pub mod integrators;
pub mod measurement;
pub mod newton;
pub mod nonlinear;
pub mod prescribed;
pub mod pulse;
pub mod random;
pub mod sparse_backend;
pub mod table;
pub mod velocity_form;
