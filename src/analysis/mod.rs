//! The analyses of a discretized structure as library calls: a Rust user (and the optimizer)
//! runs them on a [`Structure`](crate::discretize::Structure) and the f-sets of its SPC sets
//! ([`Constrained`](crate::discretize::Constrained)) without a deck or an output file. The
//! solution sequences only choose them from case control and write what they return.
//!
//! - [`statics`]: K_ff u_f = P_f per load set with one factor per f-set, SPC forces, load
//!   resultants, centroid strains (SOL 101);
//! - [`stress`]: element forces and stresses of a static displacement field (SOL 101's FORCE
//!   and STRESS);
//! - [`modal`]: normal modes by shift-invert Lanczos with one symbolic analysis per f-set,
//!   NORM = MAX scaling, shapes on every grid (SOL 103);
//! - [`weight`]: the grid-point weight generator (PARAM,GRDPNT): rigid-body mass matrix,
//!   centres of gravity and inertias of the assembled mass;
//! - [`frf`]: the receptance of the f-set, direct or by modes with residual vectors (SOL 108,
//!   SOL 111).

pub mod frf;
pub mod modal;
pub mod statics;
pub mod stress;
pub mod suport;
pub mod weight;

use std::time::{Duration, Instant};

use crate::assembly::AssemblyError;
use crate::discretize::DiscretizeError;
use crate::dynamics::frf::FrfError;
use crate::linalg::LinalgError;

/// Errors of an analysis, by the layer that raised them.
#[derive(Debug, thiserror::Error)]
pub enum AnalysisError {
    /// A factorization or eigen solve (a singular K_ff is a mechanism: see
    /// [`Constrained::mechanism_dof`](crate::discretize::Constrained::mechanism_dof)).
    #[error(transparent)]
    Linalg(#[from] LinalgError),
    #[error(transparent)]
    Frf(#[from] FrfError),
    #[error(transparent)]
    Assembly(#[from] AssemblyError),
    #[error(transparent)]
    Discretize(#[from] DiscretizeError),
}

/// Runs `f`, reporting its wall time to `record` under `name`.
fn timed<T>(record: &mut dyn FnMut(String, Duration), name: String, f: impl FnOnce() -> T) -> T {
    let start = Instant::now();
    let out = f();
    record(name, start.elapsed());
    out
}
