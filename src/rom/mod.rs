//! Parametric reduced-order models (thesis ch. 3, §4.2; DESIGN.md §5, §7).
//!
//! - [`lsq`]: least-squares affine extraction of eq. 3.29 for matrices that come from outside;
//! - [`basis`]: the offline building blocks of the global basis: seeded Latin hypercube samples,
//!   the MAC filter of eq. 3.39, the truncated SVD of eq. 3.34 and the strain-basis transformation
//!   of eq. 3.36–3.38;
//! - [`black_box`]: the pROM of matrices, local bases and strain bases sampled by another FE
//!   code (eq. 3.29, 3.31, 3.36–3.38);
//! - [`local_basis`]: normal modes plus attachment (or inertia-relief) static modes of one
//!   sample, rigid-body modes kept or removed (eq. 2.28), or Craig–Bampton fixed-interface and
//!   constraint modes;
//! - [`mass`]: affine nodal masses for the multibody step (eq. 4.1–4.3);
//! - [`invariants`]: the nine mass invariants of a floating-frame body and their affine
//!   components (eq. 4.8, A.11–A.19), and the basis rows of its interface grids;
//! - [`modes`]: the modes of a pROM at p (dense generalized eigenproblem) and the check that
//!   the evaluated matrices are usable;
//! - [`prom`]: the [`prom::Prom`] type, evaluated online at any parameter value with its
//!   parameter derivatives (eq. 3.32; eq. 8.19–8.20 need the derivatives);
//! - [`transient`]: a pROM as a time integrator backend, its parameters following tables of
//!   time, and the reduced static shapes of given input displacements.

pub mod basis;
pub mod black_box;
pub mod build;
pub mod invariants;
pub mod local_basis;
pub mod lsq;
pub mod mass;
pub mod modes;
pub mod prom;
pub mod transient;
