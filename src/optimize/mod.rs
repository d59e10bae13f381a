//! Multi-objective design optimization (thesis ch. 5–6), usable without a deck: a
//! [`DesignSpace`] of continuous and discrete variables, a batch evaluation interface
//! ([`evaluate`]: designs → responses or errors, on threads), [`Scoring`] of responses into
//! minimized objectives and constraint violations, the searches, and the study's report.
//!
//! - [`space`]: variables and the genome a search works on (discrete values by index).
//! - [`dominance`]: non-dominated sorting and crowding distance.
//! - [`operators`] and [`nsga2`]: NSGA-II as pymoo 0.6 runs it by default, mixed-variable.
//! - [`grid`]: the full-factorial design for validation.
//! - [`hypervolume`]: exact 2-D sweep and k-D slicing.
//! - [`correlation`] (eq. 6.2), [`knee`] (representative designs), [`summary`] (the report).
//!
//! Not here yet: a gradient-based search with parametric sensitivities.

pub mod correlation;
pub mod dominance;
pub mod evaluate;
pub mod gradient;
pub mod grid;
pub mod hypervolume;
pub mod knee;
pub mod nsga2;
pub mod operators;
pub mod scoring;
pub mod space;
pub mod summary;

pub use evaluate::{Batch, EvalError, Evaluated, Responses, Threaded, serial};
pub use nsga2::{Archive, Nsga2};
pub use scoring::{Constraint, Objective, Score, Scoring, Sense};
pub use space::{Design, DesignSpace, Domain, Variable};
pub use summary::{Summary, summarize};
