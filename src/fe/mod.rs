//! Element formulations (DESIGN.md §4–§5): shells, solids, springs and masses, each returning
//! its matrices split into affine parts so that K(p) = Σ f_i(p) K_i exactly.
//!
//! Conventions for every element here:
//! - six DOFs per grid (T1 T2 T3 R1 R2 R3) in the basic system, grid-major: row `6·a + c` is
//!   component `c` of the element's grid `a` (in the order the grids are given);
//! - matrices are dense `faer::Mat<f64>` of size `6·nodes`, symmetric — except the solids,
//!   which have no rotational DOFs and return `3·nodes` translational matrices
//!   (the assembly takes them as translations only);
//! - element kernels are pure functions of geometry (basic coordinates) and material/section
//!   data, and know nothing of decks, cards or global DOF numbering.

pub mod affine;
pub mod beam;
pub mod beam_load;
pub mod beam_section;
#[cfg(test)]
mod beam_tests;
pub mod bend;
pub mod bush;
pub mod failure;
pub mod laminate;
pub mod lumped;
pub mod pressure;
pub mod shear_panel;
pub mod shell;
pub mod shell_quadratic;
#[cfg(test)]
mod shell_quadratic_tests;
#[cfg(test)]
mod shell_tests;
pub mod solid;
pub mod solid_midside;
mod solid_shape;
#[cfg(test)]
mod solid_tests;
pub mod stress;
