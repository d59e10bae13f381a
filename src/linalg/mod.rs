//! Thin wrappers over faer (DESIGN.md §6): sparse Cholesky/LDLᵀ with one symbolic analysis
//! reused by every numeric factorization, and a shift-invert eigen solver.
//!
//! Storage convention: every symmetric sparse matrix handed to this module is a
//! `nalgebra_sparse::CscMatrix<f64>` holding the **full** pattern (both triangles, as produced
//! by COO → CSC assembly). Matrices that arrive as one triangle (symmetric Matrix Market
//! files) are converted with [`full_from_upper`]. All matrices of one analysis (K, M, K − σM,
//! K(p) at every parameter sample) must share one identical pattern: assembly stores explicit
//! zeros where M has no entry, so that `values()` slices line up entry by entry.
//!
//! - [`cholesky`]: [`SymbolicFactor`] (ordering + symbolic analysis, once per pattern) and
//!   [`Factor`] (numeric LLᵀ or LDLᵀ, many per pattern, in parallel if wanted).
//! - [`ordering`]: METIS nested dissection on the supervariable (compressed) graph, used by
//!   the symbolic analysis of large patterns.
//! - [`eigen`]: shift-invert Lanczos for K φ = λ M φ with EIGRL request semantics and a
//!   Sturm-sequence missed-mode check ([`solve_modes`]).
//! - [`random`]: the seeded SplitMix64 stream of LHS samples, Lanczos start vectors and test noise.
//! - [`complex_lu`]: sparse complex LU with one symbolic analysis per pattern (dynamic
//!   stiffness of frequency responses, [`ComplexLuSymbolic`]).

pub mod cholesky;
pub mod complex_lu;
pub mod dense;
pub mod eigen;
mod error;
pub mod ordering;
mod progress;
pub mod random;
mod sparse;

pub use cholesky::{
    Factor, FactorKind, FactorVariant, Inertia, Ordering, SolveScratch, SymbolicFactor,
};
pub use complex_lu::ComplexLuSymbolic;
pub use eigen::{
    EigenProblem, EigenRequest, EigenResult, LanczosOptions, SturmCheck, solve_modes, sturm_check,
    sturm_count,
};
pub use error::LinalgError;
pub use progress::Progress;
pub use sparse::{full_from_upper, sym_matvec};

/// The dense matrix and complex scalar types the library's results carry (faer's).
pub use faer::{Mat, MatRef, c64};
