//! paraflex: a file-driven solver for structural and flexible-multibody dynamics in the style of
//! a Nastran-type FE code, implementing the parametric reduced-order modelling, multibody and
//! virtual-sensing methods of the thesis in `shared/seed/thesis.txt`.
//!
//! Data flow (see `DESIGN.md` §1): [`deck`] (text → typed cards with source positions) →
//! [`model`] (cross-referenced, validated) → [`discretize`] (element matrices, assembled
//! parametric operators K(p), M(p), constrained f-set) → [`analysis`], [`rom`], [`dynamics`],
//! [`multibody`], [`estimate`] (the numerics, callable without a deck) → [`sequence`] (one
//! driver per solution sequence, turning case control into those calls) → [`io`] (HDF5 +
//! XDMF).
//! The library never prints; the binary renders errors and progress.

pub mod analysis;
pub mod assembly;
pub mod card_values;
pub mod deck;
pub mod discretize;
pub mod dynamics;
pub mod estimate;
pub mod fe;
pub mod geometry;
pub mod io;
pub mod linalg;
pub mod model;
pub mod multibody;
pub mod optimize;
pub mod rom;
pub mod sequence;

/// Version string written into every HDF5 group (`paraflex_version` attribute).
pub const VERSION: &str = env!("CARGO_PKG_VERSION");
