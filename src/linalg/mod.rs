//! Thin wrappers over faer (DESIGN.md §6): sparse Cholesky/LDLᵀ with one symbolic analysis
//! reused by every numeric factorization, and a shift-invert eigen solver.
