//! Global assembly, set reduction, loads and recovery (DESIGN.md §4–§6).
//!
//! # Sets (Nastran / MYSTRAN naming)
//!
//! Every grid has six DOFs (T1 T2 T3 R1 R2 R3) in its *global* system — the displacement system
//! CD of the grid (basic when CD = 0). Global DOF numbers are grid-major,
//! `6 · grid_index + component` (0-based component), see [`dofs::DofMap`].
//!
//! ```text
//! g   all DOFs
//! ├── m   dependent DOFs of RBE2 / RBE3, eliminated: u_m = G_mn u_n
//! └── n = g − m
//!     ├── s   SPC / SPC1 / SPCADD, GRID PS, AUTOSPC (enforced values u_s, usually 0)
//!     └── f = n − s   the DOFs that are solved for
//! ```
//!
//! # Data flow
//!
//! 1. [`frames::GridFrames`]: the CD rotation of every grid; element matrices (basic) are
//!    rotated to global when they are scattered.
//! 2. [`pattern::grid_block_pattern`]: the symmetric, full (both triangles) CSC pattern of
//!    K_gg, computed ONCE from the element connectivity.
//! 3. [`assemble::AffineOperator::assemble`]: every affine part K_i (and M_i) scattered into a
//!    value array on that one pattern, K(p) = Σ f_i(p) K_i by summing value arrays.
//! 4. [`constraints::RigidElimination`]: RBE2 / RBE3 relations → the sparse transformation
//!    T (g × n) with u_g = T u_n.
//! 5. [`reduce::reduce_g_to_n`]: K_nn = Tᵀ K_gg T for every part, on one symbolic pattern.
//! 6. [`spc::SpcSet`] + [`spc::autospc`]: the s-set and its enforced values;
//!    [`reduce::reduce_n_to_f`] / [`reduce::partition`]: K_ff and K_fs.
//! 7. [`loads`]: P_g for a LOAD set, reduced with [`loads::reduce_load`]
//!    (P_f = (Tᵀ P_g)_f − K_fs u_s).
//! 8. [`recover`]: u_g from u_f, and the SPC forces.

pub mod assemble;
pub mod constraints;
pub mod dofs;
pub mod error;
pub mod frames;
pub mod loads;
pub mod pattern;
pub mod recover;
pub mod reduce;
pub mod rsscon;
pub mod spc;

#[cfg(test)]
mod tests;

pub use assemble::{AffineOperator, Contribution, ParamKey, ParamTarget};
pub use constraints::RigidElimination;
pub use dofs::{DofMap, DofSet, Sets};
pub use error::AssemblyError;
pub use frames::GridFrames;
