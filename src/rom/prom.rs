//! The parametric reduced-order model and its online evaluation (thesis eq. 3.31–3.32).
//!
//! M_r(p) = Σ_i f_i(p) M_r^i, K_r(p) = Σ_i f_i(p) K_r^i, C_r(p) = α M_r(p) + β K_r(p) (eq. 3.28
//! with Rayleigh damping), and the parameter derivatives ∂K_r/∂p_j = Σ_i ∂f_i/∂p_j K_r^i (the
//! estimator's eq. 8.19–8.20). Evaluation only sums small dense matrices into a preallocated
//! [`PromEvaluation`]: no allocation after [`Prom::workspace`].
//!
//! The workspace decides once which components are identically zero (the five fibre-angle
//! functions of a PCOMP THETA leave the mass constant: five of its six mass components are zero)
//! and stacks the others, stiffness and mass, as the columns of one n_r² × m matrix; an
//! evaluation is then one product of that stack with the m × (3 + d) matrix of the weights of
//! each component in K_r, M_r, C_r and the d derivatives that are not identically zero (f_i(p),
//! α f_i, β f_i, ∂f_i/∂p_j), written by faer's vectorized matrix product into the workspace,
//! whose columns are the results: every component is read once per evaluation.

use faer::linalg::matmul::matmul;
use faer::{Accum, Mat, MatRef, Par};

use crate::fe::affine::{Coefficient, CoefficientValues};

/// A parameter of a pROM: a PMPAR's name, box and nominal value.
#[derive(Debug, Clone, PartialEq)]
pub struct PromParameter {
    pub name: String,
    pub low: f64,
    pub high: f64,
    pub nominal: f64,
}

/// Which input of a coefficient function a parameter drives.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum CoefficientInput {
    E,
    Nu,
    Rho,
    ThetaDeg,
    H,
    Lumped,
}

impl CoefficientInput {
    /// The slot of this input in a [`CoefficientValues`].
    pub fn slot(self, v: &mut CoefficientValues) -> &mut f64 {
        match self {
            CoefficientInput::E => &mut v.e,
            CoefficientInput::Nu => &mut v.nu,
            CoefficientInput::Rho => &mut v.rho,
            CoefficientInput::ThetaDeg => &mut v.theta_deg,
            CoefficientInput::H => &mut v.h,
            CoefficientInput::Lumped => &mut v.lumped,
        }
    }
}

/// One affine function f_i(p): a [`Coefficient`] whose inputs are fixed at `fixed` except those
/// driven by parameters (e.g. λ of a material whose E is a parameter and ν is not).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct AffineFunction {
    pub coefficient: Coefficient,
    pub fixed: CoefficientValues,
    /// (input, parameter index) pairs.
    pub driven_by: Vec<(CoefficientInput, usize)>,
}

impl AffineFunction {
    /// The constant function f = 1.
    pub fn constant() -> Self {
        AffineFunction {
            coefficient: Coefficient::Constant,
            fixed: CoefficientValues::default(),
            driven_by: Vec::new(),
        }
    }

    fn inputs(&self, p: &[f64]) -> CoefficientValues {
        let mut v = self.fixed;
        for &(input, j) in &self.driven_by {
            *input.slot(&mut v) = p[j];
        }
        v
    }

    /// f(p).
    pub fn value(&self, p: &[f64]) -> f64 {
        self.coefficient.value(&self.inputs(p))
    }

    /// ∂f/∂p_j.
    pub fn derivative(&self, p: &[f64], j: usize) -> f64 {
        let mut gradient = self.coefficient.gradient(&self.inputs(p));
        self.driven_by
            .iter()
            .filter(|(_, k)| *k == j)
            .map(|&(input, _)| *input.slot(&mut gradient))
            .sum()
    }
}

/// A pROM: parameters, affine functions and the reduced affine components.
#[derive(Debug, Clone)]
pub struct Prom {
    pub parameters: Vec<PromParameter>,
    /// f_i; `stiffness[i]` and `mass[i]` are the components that multiply it.
    pub functions: Vec<AffineFunction>,
    pub stiffness: Vec<Mat<f64>>,
    pub mass: Vec<Mat<f64>>,
    /// Rayleigh α, β (C = αM + βK, eq. 2.23).
    pub alpha: f64,
    pub beta: f64,
}

/// Why a pROM is malformed or an evaluation is refused.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PromError {
    #[error("{what}: expected {expected}, got {got}")]
    Shape {
        what: &'static str,
        expected: usize,
        got: usize,
    },
    #[error("parameter {name} = {value} is not finite")]
    NotFinite { name: String, value: f64 },
    #[error("function {function} refers to parameter {index}, but the pROM has {count} parameters")]
    UnknownParameter {
        function: usize,
        index: usize,
        count: usize,
    },
}

/// M_r, C_r, K_r at one parameter point and their derivatives, read through
/// [`PromEvaluation::stiffness`] and friends after [`Prom::evaluate`].
#[derive(Debug, Clone)]
pub struct PromEvaluation {
    n: usize,
    /// Indices i of the stiffness (`false`) and mass (`true`) components that are not
    /// identically zero, in stacking order.
    parts: Vec<(bool, usize)>,
    /// n_r² × parts.len(): column k holds the component parts[k], column after column (a copy:
    /// a workspace serves the pROM it was made from, with its components as they were).
    stacked: Mat<f64>,
    /// What each column of `sums` is.
    outputs: Vec<Output>,
    /// The column of `sums` holding ∂K_r/∂p_j and ∂M_r/∂p_j (`None`: identically zero).
    d_stiffness: Vec<Option<usize>>,
    d_mass: Vec<Option<usize>>,
    /// parts.len() × outputs.len(): the weight of each component in each output.
    coefficients: Mat<f64>,
    /// n_r² × outputs.len(): K_r, M_r, C_r and the non-zero derivatives, column after column.
    sums: Mat<f64>,
    /// n_r² zeros: the derivatives that are identically zero.
    zero: Vec<f64>,
}

/// One output of an evaluation.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Output {
    Stiffness,
    Mass,
    Damping,
    DStiffness(usize),
    DMass(usize),
}

impl PromEvaluation {
    fn view(&self, column: Option<usize>) -> MatRef<'_, f64> {
        let values = column.map_or(self.zero.as_slice(), |c| self.sums.col_as_slice(c));
        MatRef::from_column_major_slice(values, self.n, self.n)
    }

    /// K_r(p).
    pub fn stiffness(&self) -> MatRef<'_, f64> {
        self.view(Some(0))
    }

    /// M_r(p).
    pub fn mass(&self) -> MatRef<'_, f64> {
        self.view(Some(1))
    }

    /// C_r(p) = α M_r(p) + β K_r(p).
    pub fn damping(&self) -> MatRef<'_, f64> {
        self.view(Some(2))
    }

    /// ∂K_r/∂p_j.
    pub fn d_stiffness(&self, j: usize) -> MatRef<'_, f64> {
        self.view(self.d_stiffness[j])
    }

    /// ∂M_r/∂p_j (∂C_r/∂p_j = α ∂M_r/∂p_j + β ∂K_r/∂p_j).
    pub fn d_mass(&self, j: usize) -> MatRef<'_, f64> {
        self.view(self.d_mass[j])
    }

    /// Whether (K_r, M_r) change with p_j at this point: (∂K_r/∂p_j ≠ 0, ∂M_r/∂p_j ≠ 0).
    pub fn sensitive_to(&self, j: usize) -> (bool, bool) {
        (
            self.d_stiffness(j).norm_max() > 0.0,
            self.d_mass(j).norm_max() > 0.0,
        )
    }
}

impl Prom {
    /// Check the shapes: one K and one M component per function, all n × n, parameters known.
    pub fn validate(&self) -> Result<(), PromError> {
        let count = self.functions.len();
        for (what, parts) in [
            ("stiffness components", &self.stiffness),
            ("mass components", &self.mass),
        ] {
            if parts.len() != count {
                return Err(PromError::Shape {
                    what,
                    expected: count,
                    got: parts.len(),
                });
            }
        }
        let n = self.size();
        for m in self.stiffness.iter().chain(&self.mass) {
            for got in [m.nrows(), m.ncols()] {
                if got != n {
                    return Err(PromError::Shape {
                        what: "reduced matrix size",
                        expected: n,
                        got,
                    });
                }
            }
        }
        for (function, f) in self.functions.iter().enumerate() {
            if let Some(&(_, index)) = f
                .driven_by
                .iter()
                .find(|(_, j)| *j >= self.parameters.len())
            {
                return Err(PromError::UnknownParameter {
                    function,
                    index,
                    count: self.parameters.len(),
                });
            }
        }
        Ok(())
    }

    /// Reduced size n_r.
    pub fn size(&self) -> usize {
        self.stiffness.first().map_or(0, |m| m.nrows())
    }

    /// Buffers for [`Prom::evaluate`], and the stack of the components that are not
    /// identically zero (decided here, once: a workspace serves this pROM as it is now).
    pub fn workspace(&self) -> PromEvaluation {
        let n = self.size();
        let nonzero = |is_mass: bool, parts: &[Mat<f64>]| {
            (0..parts.len())
                .filter(|&i| parts[i].norm_max() != 0.0)
                .map(move |i| (is_mass, i))
                .collect::<Vec<_>>()
        };
        let parts: Vec<(bool, usize)> =
            [nonzero(false, &self.stiffness), nonzero(true, &self.mass)].concat();
        let stacked = Mat::from_fn(n * n, parts.len(), |r, k| {
            let (is_mass, i) = parts[k];
            (if is_mass { &self.mass } else { &self.stiffness })[i][(r % n, r / n)]
        });
        let mut outputs = vec![Output::Stiffness, Output::Mass, Output::Damping];
        let derived = |is_mass: bool, j: usize| {
            parts.iter().any(|&(m, i)| {
                m == is_mass && self.functions[i].driven_by.iter().any(|&(_, q)| q == j)
            })
        };
        let mut column = |is_mass: bool, j: usize, output: Output| {
            derived(is_mass, j).then(|| {
                outputs.push(output);
                outputs.len() - 1
            })
        };
        let d_stiffness: Vec<Option<usize>> = (0..self.parameters.len())
            .map(|j| column(false, j, Output::DStiffness(j)))
            .collect();
        let d_mass: Vec<Option<usize>> = (0..self.parameters.len())
            .map(|j| column(true, j, Output::DMass(j)))
            .collect();
        PromEvaluation {
            n,
            coefficients: Mat::zeros(parts.len(), outputs.len()),
            sums: Mat::zeros(n * n, outputs.len()),
            zero: vec![0.0; n * n],
            parts,
            stacked,
            outputs,
            d_stiffness,
            d_mass,
        }
    }

    /// Names of the parameters of `p` outside their box (extrapolation: allowed, but the
    /// caller warns, naming them).
    pub fn outside_box(&self, p: &[f64]) -> Vec<&str> {
        self.parameters
            .iter()
            .zip(p)
            .filter(|(q, v)| **v < q.low || **v > q.high)
            .map(|(q, _)| q.name.as_str())
            .collect()
    }

    /// Evaluate M_r, C_r, K_r and their derivatives at `p` into `out` (eq. 3.32), without
    /// allocating.
    pub fn evaluate(&self, p: &[f64], out: &mut PromEvaluation) -> Result<(), PromError> {
        if p.len() != self.parameters.len() {
            return Err(PromError::Shape {
                what: "parameter values",
                expected: self.parameters.len(),
                got: p.len(),
            });
        }
        if let Some((q, &value)) = self.parameters.iter().zip(p).find(|(_, v)| !v.is_finite()) {
            return Err(PromError::NotFinite {
                name: q.name.clone(),
                value,
            });
        }
        if out.n != self.size()
            || out.d_mass.len() != p.len()
            || out.parts.iter().any(|&(_, i)| i >= self.functions.len())
        {
            return Err(PromError::Shape {
                what: "workspace size (made for another pROM)",
                expected: self.size(),
                got: out.n,
            });
        }
        for (k, &(is_mass, i)) in out.parts.iter().enumerate() {
            let f = &self.functions[i];
            let value = f.value(p);
            for (c, output) in out.outputs.iter().enumerate() {
                out.coefficients[(k, c)] = match *output {
                    Output::Stiffness if !is_mass => value,
                    Output::Mass if is_mass => value,
                    Output::Damping => value * if is_mass { self.alpha } else { self.beta },
                    Output::DStiffness(j) if !is_mass => f.derivative(p, j),
                    Output::DMass(j) if is_mass => f.derivative(p, j),
                    _ => 0.0,
                };
            }
        }
        if !out.parts.is_empty() {
            matmul(
                out.sums.as_mut(),
                Accum::Replace,
                out.stacked.as_ref(),
                out.coefficients.as_ref(),
                1.0,
                Par::Seq,
            );
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 3 × 3 pROM with E, ν (through Lamé parts) and ρ of one material plus a constant part.
    fn sample() -> Prom {
        let fixed = CoefficientValues {
            e: 2.0e11,
            nu: 0.3,
            rho: 7800.0,
            ..Default::default()
        };
        let driven = |c, inputs: Vec<(CoefficientInput, usize)>| AffineFunction {
            coefficient: c,
            fixed,
            driven_by: inputs,
        };
        let functions = vec![
            AffineFunction::constant(),
            driven(
                Coefficient::Lambda,
                vec![(CoefficientInput::E, 0), (CoefficientInput::Nu, 1)],
            ),
            driven(
                Coefficient::Mu,
                vec![(CoefficientInput::E, 0), (CoefficientInput::Nu, 1)],
            ),
            driven(Coefficient::Rho, vec![(CoefficientInput::Rho, 2)]),
        ];
        let sym = |seed: f64| {
            Mat::<f64>::from_fn(3, 3, |i, j| {
                ((i + j) as f64 + seed).cos() + if i == j { 3.0 } else { 0.0 }
            })
        };
        let zero = Mat::<f64>::zeros(3, 3);
        let parameters = ["E", "NU", "RHO"]
            .iter()
            .zip([
                (1e11, 3e11, 2e11),
                (0.2, 0.4, 0.3),
                (7000.0, 9000.0, 7800.0),
            ])
            .map(|(n, (low, high, nominal))| PromParameter {
                name: n.to_string(),
                low,
                high,
                nominal,
            })
            .collect();
        Prom {
            parameters,
            functions,
            stiffness: vec![
                sym(0.1),
                sym(0.5) * faer::Scale(1e-11),
                sym(0.9) * faer::Scale(1e-11),
                zero.clone(),
            ],
            mass: vec![
                sym(0.2) * faer::Scale(0.1),
                zero.clone(),
                zero,
                sym(0.7) * faer::Scale(1e-4),
            ],
            alpha: 0.5,
            beta: 1e-4,
        }
    }

    #[test]
    fn evaluation_sums_the_components() {
        let prom = sample();
        prom.validate().unwrap();
        let p = [2.5e11, 0.33, 8100.0];
        let mut out = prom.workspace();
        prom.evaluate(&p, &mut out).unwrap();
        let (lam, mu) = (
            p[0] * p[1] / ((1.0 + p[1]) * (1.0 - 2.0 * p[1])),
            p[0] / (2.0 * (1.0 + p[1])),
        );
        let k = &prom.stiffness[0]
            + &prom.stiffness[1] * faer::Scale(lam)
            + &prom.stiffness[2] * faer::Scale(mu);
        let m = &prom.mass[0] + &prom.mass[3] * faer::Scale(p[2]);
        let c = &m * faer::Scale(prom.alpha) + &k * faer::Scale(prom.beta);
        assert!((out.stiffness() - &k).norm_max() <= 1e-14 * k.norm_max());
        assert!((out.mass() - &m).norm_max() <= 1e-14 * m.norm_max());
        assert!((out.damping() - &c).norm_max() <= 1e-14 * c.norm_max());
    }

    /// ∂K_r/∂p_j and ∂M_r/∂p_j against central differences (relative step 1e-6: truncation
    /// ~1e-12, round-off ~1e-10 relative; bound 1e-7).
    #[test]
    fn derivatives_match_central_differences() {
        let prom = sample();
        let p = [1.7e11, 0.27, 7500.0];
        let mut at = prom.workspace();
        prom.evaluate(&p, &mut at).unwrap();
        for j in 0..3 {
            let h = 1e-6 * p[j];
            let (mut up, mut down) = (p, p);
            up[j] += h;
            down[j] -= h;
            let (mut a, mut b) = (prom.workspace(), prom.workspace());
            prom.evaluate(&up, &mut a).unwrap();
            prom.evaluate(&down, &mut b).unwrap();
            for (analytic, plus, minus) in [
                (at.d_stiffness(j), a.stiffness(), b.stiffness()),
                (at.d_mass(j), a.mass(), b.mass()),
            ] {
                let fd = (plus - minus) * faer::Scale(1.0 / (2.0 * h));
                let scale = fd.norm_max().max(analytic.norm_max());
                assert!(
                    (&fd - analytic).norm_max() <= 1e-7 * scale.max(f64::MIN_POSITIVE),
                    "parameter {j}"
                );
            }
        }
    }

    /// The zero components (K for ρ, M for λ and μ) are left out of the stack once, and a
    /// derivative no non-zero component depends on (∂M_r/∂ν) is the zero matrix.
    #[test]
    fn identically_zero_components_are_skipped() {
        let prom = sample();
        let mut out = prom.workspace();
        assert_eq!(
            out.parts,
            vec![(false, 0), (false, 1), (false, 2), (true, 0), (true, 3)]
        );
        assert_eq!((out.d_mass[1], out.d_stiffness[2]), (None, None));
        prom.evaluate(&[2.5e11, 0.33, 8100.0], &mut out).unwrap();
        assert_eq!(
            (out.d_mass(1).norm_max(), out.d_stiffness(2).norm_max()),
            (0.0, 0.0)
        );
        assert!(out.d_mass(2).norm_max() > 0.0 && out.d_stiffness(1).norm_max() > 0.0);
    }

    #[test]
    fn refuses_bad_evaluations_and_names_extrapolated_parameters() {
        let prom = sample();
        let mut out = prom.workspace();
        assert!(matches!(
            prom.evaluate(&[1e11, 0.3], &mut out),
            Err(PromError::Shape { .. })
        ));
        assert!(matches!(
            prom.evaluate(&[f64::NAN, 0.3, 7800.0], &mut out),
            Err(PromError::NotFinite { .. })
        ));
        assert_eq!(prom.outside_box(&[3.5e11, 0.3, 6000.0]), vec!["E", "RHO"]);
        let small = Prom {
            stiffness: prom
                .stiffness
                .iter()
                .map(|m| m.submatrix(0, 0, 2, 2).to_owned())
                .collect(),
            mass: prom
                .mass
                .iter()
                .map(|m| m.submatrix(0, 0, 2, 2).to_owned())
                .collect(),
            ..prom.clone()
        };
        assert!(matches!(
            prom.evaluate(&[2e11, 0.3, 7800.0], &mut small.workspace()),
            Err(PromError::Shape { .. })
        ));
        let mut broken = prom.clone();
        broken.mass.pop();
        assert!(matches!(
            broken.validate(),
            Err(PromError::Shape {
                what: "mass components",
                ..
            })
        ));
    }
}
