//! The pROM of the black-box route (thesis §3.3.5, §3.4.1.1): stiffness and mass matrices,
//! local bases Ψ_h and optionally strain bases N_s,h sampled by another FE code at parameter
//! samples p_h. The affine components X^i come from least squares over the samples (eq. 3.29,
//! [`super::lsq::extract_matrices`]); the global basis V from the Ψ_h through
//! [`Concatenation`] (column scaling, MAC filter eq. 3.39 in the mass and stiffness of the fitted
//! components at each sample, SVD eq. 3.33–3.34, truncated at the
//! numerical rank [`RANK_TOL`]); the reduced components by projection K_r^i = Vᵀ K^i V,
//! M_r^i = Vᵀ M^i V (eq. 3.31); the strain rows from the N_s,h by eq. 3.36–3.38
//! ([`Concatenation::companion`]), since the external code's strain operator B_e is unknown.
//!
//! The affine functions of the samples are known only by name and value, so each becomes a
//! parameter of the pROM with f = p (a function named `1` that is 1 at every sample is the
//! constant): the pROM is evaluated at the function values, its box is their range over the
//! samples and its nominal point the box centre.

use faer::{Mat, MatRef};
use nalgebra_sparse::CscMatrix;

use super::basis::{CompanionError, Concatenation, ConcatenationError, PencilError, SampledPencil};
use super::build::RANK_TOL;
use super::lsq::MatrixFit;
use super::prom::{AffineFunction, CoefficientInput, Prom, PromParameter};
use crate::fe::affine::{Coefficient, CoefficientValues};

/// What the black-box route needs beyond the fitted components.
pub struct BlackBoxInput<'a> {
    pub functions: &'a [String],
    /// f_i(p_h), one row per sample.
    pub values: &'a [Vec<f64>],
    /// Ψ_h: n × k_h, one per sample.
    pub bases: &'a [Mat<f64>],
    /// N_s,h: s × k_h, one per sample, or none.
    pub strains: &'a [Mat<f64>],
    /// Load input DOFs (0-based rows of the n-vector): S_r = Vᵀ S.
    pub inputs: &'a [usize],
    /// MAC threshold of the filter (eq. 3.39; 0.99 in the thesis).
    pub mac_tol: f64,
}

/// The built pROM with its input shapes S_r (n_r × inputs) and strain rows H_r (s × n_r).
pub struct BlackBox {
    pub prom: Prom,
    pub inputs: Mat<f64>,
    pub strains: Mat<f64>,
    /// Columns of the concatenation and columns the MAC filter kept.
    pub concatenated: usize,
    pub kept: usize,
    pub singular_values: Vec<f64>,
}

/// Why the black-box build was refused.
#[derive(Debug, thiserror::Error)]
pub enum BlackBoxError {
    #[error("{got} local bases for {expected} samples (one Ψ per sample)")]
    BasisCount { expected: usize, got: usize },
    #[error("local basis of sample {sample}: {got} rows, the matrices are {expected} × {expected}")]
    BasisRows {
        sample: usize,
        expected: usize,
        got: usize,
    },
    #[error("the local bases have no column")]
    EmptyBasis,
    #[error("strain bases: {0}")]
    Strain(#[from] CompanionError),
    #[error("input DOF {index} is not in 0..{size}")]
    Input { index: usize, size: usize },
    #[error("MAC filter: {0}")]
    Pencil(PencilError),
    #[error("SVD of the concatenated local bases failed: {0:?}")]
    Svd(faer::linalg::svd::SvdError),
}

/// Build the pROM (module doc) from the fitted components `fit` and `input`.
pub fn build_black_box(
    fit: &MatrixFit,
    input: &BlackBoxInput<'_>,
) -> Result<BlackBox, BlackBoxError> {
    let n = fit.stiffness.first().map_or(0, CscMatrix::nrows);
    if input.bases.len() != input.values.len() {
        return Err(BlackBoxError::BasisCount {
            expected: input.values.len(),
            got: input.bases.len(),
        });
    }
    if let Some((h, b)) = input.bases.iter().enumerate().find(|(_, b)| b.nrows() != n) {
        return Err(BlackBoxError::BasisRows {
            sample: h + 1,
            expected: n,
            got: b.nrows(),
        });
    }
    if let Some(&index) = input.inputs.iter().find(|&&i| i >= n) {
        return Err(BlackBoxError::Input { index, size: n });
    }
    if input.bases.iter().all(|b| b.ncols() == 0) {
        return Err(BlackBoxError::EmptyBasis);
    }
    let views: Vec<MatRef<'_, f64>> = input.bases.iter().map(Mat::as_ref).collect();
    let pencil = SampledPencil {
        stiffness: &fit.stiffness,
        mass: &fit.mass,
        weights: input.values,
    };
    let concatenation =
        Concatenation::new(&views, &pencil, input.mac_tol).map_err(|e| match e {
            ConcatenationError::Svd(e) => BlackBoxError::Svd(e),
            ConcatenationError::Pencil(e) => BlackBoxError::Pencil(e),
        })?;
    let rank = concatenation.global.numerical_rank(RANK_TOL);
    let strains = if input.strains.is_empty() {
        Mat::zeros(0, rank)
    } else {
        let views: Vec<MatRef<'_, f64>> = input.strains.iter().map(Mat::as_ref).collect();
        concatenation.companion(&views, rank)?
    };
    let v = concatenation.global.truncated(rank);
    let project = |x: &CscMatrix<f64>| -> Mat<f64> {
        let mut xv = Mat::<f64>::zeros(n, rank);
        for (j, col) in x.col_iter().enumerate() {
            for (&i, &value) in col.row_indices().iter().zip(col.values()) {
                for k in 0..rank {
                    xv[(i, k)] += value * v[(j, k)];
                }
            }
        }
        v.transpose() * &xv
    };
    let (parameters, functions) = parameters_of(input.functions, input.values);
    let prom = Prom {
        parameters,
        functions,
        stiffness: fit.stiffness.iter().map(project).collect(),
        mass: fit.mass.iter().map(project).collect(),
        alpha: 0.0,
        beta: 0.0,
    };
    let inputs = Mat::<f64>::from_fn(rank, input.inputs.len(), |i, j| v[(input.inputs[j], i)]);
    Ok(BlackBox {
        prom,
        inputs,
        strains,
        concatenated: concatenation.concatenated(),
        kept: concatenation.kept(),
        singular_values: concatenation.global.singular_values().to_vec(),
    })
}

/// The pROM parameters and functions of named sampled functions (module doc): `1` at value 1
/// everywhere is the constant, every other function f_i is its own parameter with f_i = p.
fn parameters_of(
    names: &[String],
    values: &[Vec<f64>],
) -> (Vec<PromParameter>, Vec<AffineFunction>) {
    let mut parameters = Vec::new();
    let mut functions = Vec::new();
    for (i, name) in names.iter().enumerate() {
        let column = values.iter().map(|row| row[i]);
        if name == "1" && column.clone().all(|x| x == 1.0) {
            functions.push(AffineFunction::constant());
            continue;
        }
        let (low, high) = column.fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), x| {
            (l.min(x), h.max(x))
        });
        functions.push(AffineFunction {
            coefficient: Coefficient::Lumped,
            fixed: CoefficientValues::default(),
            driven_by: vec![(CoefficientInput::Lumped, parameters.len())],
        });
        parameters.push(PromParameter {
            name: name.clone(),
            low,
            high,
            nominal: 0.5 * (low + high),
        });
    }
    (parameters, functions)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn functions_become_parameters_except_the_constant() {
        let names: Vec<String> = ["1", "E", "RHO"].iter().map(|s| s.to_string()).collect();
        let values = vec![vec![1.0, 2.0, 10.0], vec![1.0, 4.0, 30.0]];
        let (params, functions) = parameters_of(&names, &values);
        assert_eq!(
            params
                .iter()
                .map(|p| (p.name.as_str(), p.low, p.high, p.nominal))
                .collect::<Vec<_>>(),
            vec![("E", 2.0, 4.0, 3.0), ("RHO", 10.0, 30.0, 20.0)]
        );
        let p = [3.5, 12.0];
        assert_eq!(
            functions.iter().map(|f| f.value(&p)).collect::<Vec<_>>(),
            vec![1.0, 3.5, 12.0]
        );
        assert_eq!(functions[2].derivative(&p, 1), 1.0);
    }
}
