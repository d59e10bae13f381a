//! Least-squares extraction of affine components from sampled matrices (thesis eq. 3.29, §3.3.5).
//!
//! For matrices that come from outside (another FE code's FOM matrices at `n_s` parameter
//! samples), the affine components X⁰, X¹, … of X(p) = Σ_i f_i(p) X^i are found entry by entry
//! as the least-squares solution of F x = b, where F (n_s × n_f) holds f_i(p_h) and b the
//! sampled entries. All entries share F, so F is decomposed once (SVD) and applied to every
//! entry. Matrices are passed as value arrays on one shared sparsity pattern (or dense,
//! flattened): the extraction does not care which.
//!
//! Refused, with the reason: fewer samples than functions (underdetermined), and affine
//! functions that are linearly dependent at the samples — e.g. the five fibre-angle functions
//! of eq. 3.18 with a constant term, since cos⁴ + sin⁴ + 2 cos² sin² = 1 (§3.3.5).

use faer::Mat;
use nalgebra_sparse::CscMatrix;

/// Relative singular-value threshold of the (column-scaled) function matrix F below which the
/// functions count as linearly dependent. An exact identity such as cos⁴ + sin⁴ + 2cos²sin² = 1
/// leaves σ_min/σ_max at round-off (~1e-16); independent functions sampled by a Latin hypercube
/// stay far above 1e-10. Between the two, F is so ill-conditioned that the components would
/// carry ≥ 1e-6 relative noise from round-off in the samples, which is refused as well.
pub const DEPENDENCE_TOL: f64 = 1e-10;

/// Affine components found by least squares.
#[derive(Debug, Clone)]
pub struct AffineFit {
    /// One value array per function, in the order of the function names.
    pub parts: Vec<Vec<f64>>,
    /// max over samples of ‖X_h − Σ_i f_i(p_h) X^i‖ / ‖X_h‖: round-off when the sampled
    /// matrices really are affine in the functions, larger when they are not.
    pub max_relative_residual: f64,
}

/// Why an extraction is refused.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FitError {
    #[error(
        "{samples} sampled matrices for {functions} affine functions: the least-squares problem of eq. 3.29 needs at least as many samples as functions"
    )]
    TooFewSamples { samples: usize, functions: usize },
    #[error("sample {sample} has {got} function values / entries, expected {expected}")]
    Shape {
        sample: usize,
        got: usize,
        expected: usize,
    },
    #[error(
        "sample {sample}: {what} is {rows} × {cols}, expected {expected} × {expected} like the first stiffness matrix"
    )]
    Size {
        sample: usize,
        what: &'static str,
        rows: usize,
        cols: usize,
        expected: usize,
    },
    #[error(
        "the affine functions are linearly dependent at these samples: {relation} (σ_min/σ_max = {ratio:.1e}); remove one of them (e.g. the constant term next to the fibre-angle functions, thesis §3.3.5) or sample the parameters independently"
    )]
    LinearlyDependent { relation: String, ratio: f64 },
}

/// Extract the affine components of sampled matrices.
///
/// `function_values[h]` holds f_i(p_h) for every function i (names in `names`, used in error
/// messages); `samples[h]` the entries of X(p_h), all of equal length.
pub fn extract(
    names: &[&str],
    function_values: &[Vec<f64>],
    samples: &[&[f64]],
) -> Result<AffineFit, FitError> {
    let (n_s, n_f) = (function_values.len(), names.len());
    if samples.len() != n_s {
        return Err(FitError::Shape {
            sample: samples.len().min(n_s),
            got: samples.len(),
            expected: n_s,
        });
    }
    if n_s < n_f {
        return Err(FitError::TooFewSamples {
            samples: n_s,
            functions: n_f,
        });
    }
    let n_entries = samples.first().map_or(0, |s| s.len());
    for (h, (f, x)) in function_values.iter().zip(samples).enumerate() {
        if f.len() != n_f {
            return Err(FitError::Shape {
                sample: h,
                got: f.len(),
                expected: n_f,
            });
        }
        if x.len() != n_entries {
            return Err(FitError::Shape {
                sample: h,
                got: x.len(),
                expected: n_entries,
            });
        }
    }
    // Column scaling, so that E ~ 1e11 next to a constant 1 does not fake a dependence.
    let scale: Vec<f64> = (0..n_f)
        .map(|i| {
            function_values
                .iter()
                .map(|f| f[i] * f[i])
                .sum::<f64>()
                .sqrt()
        })
        .map(|norm| if norm > 0.0 { norm } else { 1.0 })
        .collect();
    let f = Mat::<f64>::from_fn(n_s, n_f, |h, i| function_values[h][i] / scale[i]);
    let svd = f
        .thin_svd()
        .expect("SVD of a small dense matrix with finite entries");
    let sigma: Vec<f64> = (0..n_f).map(|i| svd.S().column_vector()[i]).collect();
    let ratio = sigma[n_f - 1] / sigma[0].max(f64::MIN_POSITIVE);
    if !(ratio > DEPENDENCE_TOL) {
        let null = svd.V().col(n_f - 1);
        return Err(FitError::LinearlyDependent {
            relation: relation(names, &scale, |i| null[i]),
            ratio,
        });
    }
    // pinv = V Σ⁻¹ Uᵀ, rows rescaled back to the unscaled functions.
    let pinv = Mat::<f64>::from_fn(n_f, n_s, |i, h| {
        (0..n_f)
            .map(|k| svd.V()[(i, k)] * svd.U()[(h, k)] / sigma[k])
            .sum::<f64>()
            / scale[i]
    });
    let mut parts = vec![vec![0.0; n_entries]; n_f];
    for (i, part) in parts.iter_mut().enumerate() {
        for (h, x) in samples.iter().enumerate() {
            let w = pinv[(i, h)];
            part.iter_mut()
                .zip(x.iter())
                .for_each(|(p, &v)| *p += w * v);
        }
    }
    let max_relative_residual = samples
        .iter()
        .zip(function_values)
        .map(|(x, fv)| {
            let norm = x.iter().map(|v| v * v).sum::<f64>().sqrt();
            let err = (0..n_entries)
                .map(|k| {
                    let fit: f64 = (0..n_f).map(|i| fv[i] * parts[i][k]).sum();
                    (x[k] - fit).powi(2)
                })
                .sum::<f64>()
                .sqrt();
            if norm > 0.0 { err / norm } else { err }
        })
        .fold(0.0, f64::max);
    Ok(AffineFit {
        parts,
        max_relative_residual,
    })
}

/// Affine components of sampled stiffness and mass matrices, on the union of their patterns.
#[derive(Debug, Clone)]
pub struct MatrixFit {
    /// K^i and M^i, one per function, all on one pattern (full, as `linalg` wants).
    pub stiffness: Vec<CscMatrix<f64>>,
    pub mass: Vec<CscMatrix<f64>>,
    /// [`AffineFit::max_relative_residual`] of K and of M.
    pub residual_stiffness: f64,
    pub residual_mass: f64,
}

/// [`extract`] for sampled sparse K_h and M_h (eq. 3.29) whose patterns may differ: every
/// sample is laid out on the union pattern of all of them (absent entries are zeros).
pub fn extract_matrices(
    names: &[&str],
    function_values: &[Vec<f64>],
    stiffness: &[CscMatrix<f64>],
    mass: &[CscMatrix<f64>],
) -> Result<MatrixFit, FitError> {
    let n = stiffness.first().map_or(0, CscMatrix::nrows);
    for (what, list) in [
        ("the stiffness matrix", stiffness),
        ("the mass matrix", mass),
    ] {
        if let Some((h, x)) = list
            .iter()
            .enumerate()
            .find(|(_, x)| x.nrows() != n || x.ncols() != n)
        {
            return Err(FitError::Size {
                sample: h + 1,
                what,
                rows: x.nrows(),
                cols: x.ncols(),
                expected: n,
            });
        }
    }
    let mut union = nalgebra_sparse::CooMatrix::<f64>::new(n, n);
    for x in stiffness.iter().chain(mass) {
        x.triplet_iter().for_each(|(i, j, _)| union.push(i, j, 0.0));
    }
    let pattern = CscMatrix::from(&union).pattern().clone();
    let on_union = |x: &CscMatrix<f64>| -> Vec<f64> {
        let mut values = vec![0.0; pattern.nnz()];
        let (offsets, rows) = (pattern.major_offsets(), pattern.minor_indices());
        for (i, j, v) in x.triplet_iter() {
            let k = offsets[j]
                + rows[offsets[j]..offsets[j + 1]]
                    .binary_search(&i)
                    .expect("the union holds every entry");
            values[k] += v;
        }
        values
    };
    let fit = |list: &[CscMatrix<f64>]| -> Result<(Vec<CscMatrix<f64>>, f64), FitError> {
        let values: Vec<Vec<f64>> = list.iter().map(on_union).collect();
        let refs: Vec<&[f64]> = values.iter().map(Vec::as_slice).collect();
        let AffineFit {
            parts,
            max_relative_residual,
        } = extract(names, function_values, &refs)?;
        let matrices = parts
            .into_iter()
            .map(|v| {
                CscMatrix::try_from_pattern_and_values(pattern.clone(), v)
                    .expect("values on the union pattern")
            })
            .collect();
        Ok((matrices, max_relative_residual))
    };
    let (stiffness, residual_stiffness) = fit(stiffness)?;
    let (mass, residual_mass) = fit(mass)?;
    Ok(MatrixFit {
        stiffness,
        mass,
        residual_stiffness,
        residual_mass,
    })
}

/// "1·cos4 + 1·sin4 + 2·cos2sin2 − 1·constant = 0": the dependence a null vector of the scaled
/// F expresses, in the unscaled functions, normalised to a largest coefficient of magnitude 1
/// positive, and rounded to what matters for a message.
fn relation(names: &[&str], scale: &[f64], null: impl Fn(usize) -> f64) -> String {
    let coef: Vec<f64> = (0..names.len()).map(|i| null(i) / scale[i]).collect();
    let largest = coef
        .iter()
        .copied()
        .fold(0.0_f64, |m, c| if c.abs() > m.abs() { c } else { m });
    let (big, lead) = (largest.abs(), largest.signum());
    let terms: Vec<String> = coef
        .iter()
        .zip(names)
        .filter(|(c, _)| c.abs() > 1e-8 * big)
        .map(|(c, n)| format!("{:+.4}·{n}", lead * c / big))
        .collect();
    format!("{} = 0", terms.join(" "))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fe::affine::{Coefficient, CoefficientValues};

    /// Affine data in three functions: recovered to round-off from more samples than functions;
    /// the residual reports round-off. Tolerance 1e-12: the components are O(1) combinations of
    /// O(1) entries through a well-conditioned 5 × 3 pseudo-inverse.
    #[test]
    fn recovers_exact_affine_components() {
        let truth = [
            vec![1.0, -2.0, 0.5, 3.0],
            vec![0.25, 0.0, -1.0, 2.0],
            vec![4.0, 1.0, 1.0, -3.0],
        ];
        let ps = [0.1, 0.7, 1.3, 2.2, 3.1];
        let fv: Vec<Vec<f64>> = ps.iter().map(|&p: &f64| vec![1.0, p, p * p]).collect();
        let xs: Vec<Vec<f64>> = fv
            .iter()
            .map(|f| {
                (0..4)
                    .map(|k| (0..3).map(|i| f[i] * truth[i][k]).sum())
                    .collect()
            })
            .collect();
        let refs: Vec<&[f64]> = xs.iter().map(|x| x.as_slice()).collect();
        let fit = extract(&["constant", "p", "p²"], &fv, &refs).unwrap();
        for (got, want) in fit.parts.iter().zip(&truth) {
            for (g, w) in got.iter().zip(want) {
                assert!((g - w).abs() < 1e-12, "{got:?} vs {want:?}");
            }
        }
        assert!(
            fit.max_relative_residual < 1e-13,
            "{}",
            fit.max_relative_residual
        );
    }

    /// Non-affine data (p³ fitted by 1, p) leaves a visible residual instead of pretending.
    #[test]
    fn reports_the_residual_of_non_affine_data() {
        let ps = [0.0, 1.0, 2.0];
        let fv: Vec<Vec<f64>> = ps.iter().map(|&p| vec![1.0, p]).collect();
        let xs: Vec<Vec<f64>> = ps.iter().map(|&p: &f64| vec![p.powi(3)]).collect();
        let refs: Vec<&[f64]> = xs.iter().map(|x| x.as_slice()).collect();
        let fit = extract(&["constant", "p"], &fv, &refs).unwrap();
        assert!(
            fit.max_relative_residual > 0.1,
            "{}",
            fit.max_relative_residual
        );
    }

    /// Samples on different patterns are laid out on their union; K and M share it.
    #[test]
    fn matrices_on_different_patterns_share_the_union() {
        let csc = |entries: &[(usize, usize, f64)]| {
            let mut coo = nalgebra_sparse::CooMatrix::new(2, 2);
            entries.iter().for_each(|&(i, j, v)| coo.push(i, j, v));
            CscMatrix::from(&coo)
        };
        // K(p) = K⁰ + p K¹ with K⁰ = diag(1, 0), K¹ = offdiag(1); M = I on the diagonal only
        let k = [
            csc(&[(0, 0, 1.0)]),
            csc(&[(0, 0, 1.0), (0, 1, 2.0), (1, 0, 2.0)]),
        ];
        let m = [
            csc(&[(0, 0, 1.0), (1, 1, 1.0)]),
            csc(&[(0, 0, 1.0), (1, 1, 1.0)]),
        ];
        let fit = extract_matrices(&["1", "p"], &[vec![1.0, 0.0], vec![1.0, 2.0]], &k, &m).unwrap();
        assert_eq!(fit.stiffness[0].nnz(), 4);
        let dense = |x: &CscMatrix<f64>| {
            x.triplet_iter()
                .map(|(i, j, v)| ((i, j), (v * 1e12).round() / 1e12))
                .collect::<Vec<_>>()
        };
        assert_eq!(
            dense(&fit.stiffness[0]),
            vec![((0, 0), 1.0), ((1, 0), 0.0), ((0, 1), 0.0), ((1, 1), 0.0)]
        );
        assert_eq!(
            dense(&fit.stiffness[1]),
            vec![((0, 0), 0.0), ((1, 0), 1.0), ((0, 1), 1.0), ((1, 1), 0.0)]
        );
        assert_eq!(
            dense(&fit.mass[0]),
            vec![((0, 0), 1.0), ((1, 0), 0.0), ((0, 1), 0.0), ((1, 1), 1.0)]
        );
        let wrong = extract_matrices(
            &["1", "p"],
            &[vec![1.0, 0.0], vec![1.0, 2.0]],
            &k,
            &[m[0].clone(), csc(&[])],
        );
        assert!(wrong.is_ok(), "an empty 2 × 2 mass is a valid sample");
        let bad = extract_matrices(
            &["1", "p"],
            &[vec![1.0, 0.0], vec![1.0, 2.0]],
            &k,
            &[m[0].clone(), CscMatrix::zeros(3, 3)],
        )
        .unwrap_err();
        assert_eq!(
            bad,
            FitError::Size {
                sample: 2,
                what: "the mass matrix",
                rows: 3,
                cols: 3,
                expected: 2
            }
        );
    }

    #[test]
    fn refuses_too_few_samples() {
        let fv = vec![vec![1.0, 2.0, 4.0]; 2];
        let xs = [vec![1.0], vec![2.0]];
        let refs: Vec<&[f64]> = xs.iter().map(|x| x.as_slice()).collect();
        assert_eq!(
            extract(&["a", "b", "c"], &fv, &refs).unwrap_err(),
            FitError::TooFewSamples {
                samples: 2,
                functions: 3
            }
        );
    }

    /// Thesis §3.3.5: the fibre-angle functions with a constant term are dependent
    /// (cos⁴ + sin⁴ + 2cos²sin² = 1); the error names that relation.
    #[test]
    fn refuses_angle_functions_with_a_constant_term() {
        let functions = [
            Coefficient::Constant,
            Coefficient::Cos4,
            Coefficient::Sin4,
            Coefficient::Cos2Sin2,
            Coefficient::CosSin3,
            Coefficient::Cos3Sin,
        ];
        let names = ["constant", "cos4", "sin4", "cos2sin2", "cossin3", "cos3sin"];
        let angles = [0.0, 11.0, 23.0, 37.0, 45.0, 58.0, 71.0, 90.0];
        let fv: Vec<Vec<f64>> = angles
            .iter()
            .map(|&t| {
                functions
                    .iter()
                    .map(|c| {
                        c.value(&CoefficientValues {
                            theta_deg: t,
                            ..Default::default()
                        })
                    })
                    .collect()
            })
            .collect();
        let xs: Vec<Vec<f64>> = fv.iter().map(|f| vec![f.iter().sum()]).collect();
        let refs: Vec<&[f64]> = xs.iter().map(|x| x.as_slice()).collect();
        match extract(&names, &fv, &refs) {
            Err(FitError::LinearlyDependent { relation, ratio }) => {
                assert!(ratio < 1e-12, "{ratio}");
                for term in [
                    "-0.5000·constant",
                    "+0.5000·cos4",
                    "+0.5000·sin4",
                    "+1.0000·cos2sin2",
                ] {
                    assert!(relation.contains(term), "{relation}");
                }
            }
            other => panic!("expected a dependence, got {other:?}"),
        }
        // Without the constant term the same samples are fine.
        let fv5: Vec<Vec<f64>> = fv.iter().map(|f| f[1..].to_vec()).collect();
        assert!(extract(&names[1..], &fv5, &refs).is_ok());
    }
}
