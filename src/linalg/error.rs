//! Typed errors of the linear-algebra layer. Every variant carries the data that locates the
//! problem (a DOF index in the caller's numbering, a dimension, a shift), so the caller can map
//! it to (GRID, component) or to the offending request field before a human sees it.

/// Error of a factorization, solve or eigen analysis.
#[derive(Copy, Clone, Debug, PartialEq, thiserror::Error)]
pub enum LinalgError {
    /// The matrix is not square.
    #[error("matrix is {nrows}×{ncols}, expected a square matrix")]
    NotSquare { nrows: usize, ncols: usize },
    /// The stored pattern is not structurally symmetric: entry (row, col) has no mirror.
    #[error("pattern is not symmetric: entry ({row}, {col}) has no mirror entry ({col}, {row})")]
    PatternNotSymmetric { row: usize, col: usize },
    /// An upper-triangle input holds an entry below the diagonal.
    #[error("entry ({row}, {col}) lies below the diagonal of an upper-triangle matrix")]
    NotUpperTriangular { row: usize, col: usize },
    /// A matrix handed to a numeric step does not have the analysed pattern.
    #[error("sparsity pattern differs from the analysed one (nnz {got}, analysed nnz {expected})")]
    PatternMismatch { expected: usize, got: usize },
    /// A vector or matrix argument has the wrong size.
    #[error("dimension mismatch: expected {expected}, got {got}")]
    DimensionMismatch { expected: usize, got: usize },
    /// LLᵀ failed at DOF `index` (caller numbering): the pivot was non-positive, or the ratio
    /// `diagonal / pivot` exceeded the allowed maximum (`ratio` = ∞ for a non-positive pivot).
    /// For a stiffness matrix this is a mechanism or a missing constraint at that DOF.
    #[error("matrix is not positive definite at DOF {index} (diagonal/pivot ratio {ratio:e})")]
    NotPositiveDefinite { index: usize, ratio: f64 },
    /// LDLᵀ met an exactly zero (or non-finite) pivot at DOF `index` (caller numbering).
    #[error("matrix is singular at DOF {index} (zero pivot)")]
    Singular { index: usize },
    /// The eigen request is inconsistent (`what` names the offending field).
    #[error("invalid eigenvalue request: {what}")]
    InvalidRequest { what: &'static str },
    /// K − σM has negative eigenvalues below the negative shift σ: K is not positive
    /// semi-definite (or the shift is too close to zero for the model's round-off).
    #[error(
        "{count} eigenvalue(s) lie below the negative shift {shift:e}: stiffness is indefinite"
    )]
    NegativeEigenvalues { count: usize, shift: f64 },
    /// The Lanczos iteration reached its restart limit.
    #[error("Lanczos did not converge: {converged} of {wanted} modes after {restarts} restarts")]
    NotConverged {
        converged: usize,
        wanted: usize,
        restarts: usize,
    },
    /// A dimension or entry count does not fit the 32-bit indices of METIS.
    #[error("{value} exceeds the 32-bit index range of the METIS ordering")]
    IndexOverflow { value: usize },
    /// METIS returned an error status (or an invalid permutation) for a valid graph.
    #[error("METIS nested-dissection ordering failed with status {status}")]
    OrderingFailed { status: i32 },
    /// faer ran out of memory or overflowed an index type.
    #[error("out of memory or index overflow in the sparse factorization")]
    OutOfMemory,
}
