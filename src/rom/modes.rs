//! The modes of a pROM evaluated at a parameter point: the dense generalized eigenproblem of
//! (K_r(p), M_r(p)), and the check that the evaluated matrices can be used at all.

use super::prom::PromEvaluation;
use crate::linalg::Mat;
use crate::linalg::dense::{
    DenseEigenError, eigen_residuals, generalized_eigen, mass_conditioning, stiffness_semidefinite,
};

/// Every mode of a pROM at p, ascending, M_r-normalized.
#[derive(Debug, Clone)]
pub struct ReducedModes {
    /// λ_j = ω_j² (rad²/s²).
    pub eigenvalues: Vec<f64>,
    /// The mode shapes in reduced coordinates (n_r × n_r), column j for λ_j.
    pub shapes: Mat<f64>,
}

impl ReducedModes {
    /// The modes of (K_r(p), M_r(p)) at the point `at` was evaluated at.
    pub fn of(at: &PromEvaluation) -> Result<Self, DenseEigenError> {
        let (eigenvalues, shapes) = generalized_eigen(at.stiffness(), at.mass())?;
        Ok(ReducedModes {
            eigenvalues,
            shapes,
        })
    }

    /// The eigenvalues of the modes `keep` (indices, in that order) and their residuals
    /// ‖K_r φ − λ M_r φ‖/‖K_r φ‖.
    pub fn kept(&self, at: &PromEvaluation, keep: &[usize]) -> (Vec<f64>, Vec<f64>) {
        let lambda: Vec<f64> = keep.iter().map(|&j| self.eigenvalues[j]).collect();
        let phi = Mat::<f64>::from_fn(self.shapes.nrows(), keep.len(), |i, c| {
            self.shapes[(i, keep[c])]
        });
        let residuals = eigen_residuals(at.stiffness(), at.mass(), &lambda, phi.as_ref());
        (lambda, residuals)
    }
}

/// Whether a pROM evaluated at p is usable: a well-conditioned M_r(p) and a positive
/// semidefinite K_r(p) ([`mass_conditioning`], [`stiffness_semidefinite`]; a pROM without
/// coordinates passes).
pub fn check_evaluation(at: &PromEvaluation) -> Result<(), DenseEigenError> {
    if at.mass().nrows() == 0 {
        return Ok(());
    }
    mass_conditioning(at.mass()).and_then(|_| stiffness_semidefinite(at.stiffness()))
}
