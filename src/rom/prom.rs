//! The parametric reduced-order model and its online evaluation (thesis eq. 3.31–3.32).
//!
//! M_r(p) = Σ_i f_i(p) M_r^i, K_r(p) = Σ_i f_i(p) K_r^i, C_r(p) = α M_r(p) + β K_r(p) (eq. 3.28
//! with Rayleigh damping), and the parameter derivatives ∂K_r/∂p_j = Σ_i ∂f_i/∂p_j K_r^i (the
//! estimator's eq. 8.19–8.20). Evaluation only sums small dense matrices into a preallocated
//! [`PromEvaluation`]: no allocation after [`Prom::workspace`].

use faer::Mat;

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
        AffineFunction { coefficient: Coefficient::Constant, fixed: CoefficientValues::default(), driven_by: Vec::new() }
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
        self.driven_by.iter().filter(|(_, k)| *k == j).map(|&(input, _)| *input.slot(&mut gradient)).sum()
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
    Shape { what: &'static str, expected: usize, got: usize },
    #[error("parameter {name} = {value} is not finite")]
    NotFinite { name: String, value: f64 },
    #[error("function {function} refers to parameter {index}, but the pROM has {count} parameters")]
    UnknownParameter { function: usize, index: usize, count: usize },
}

/// M_r, C_r, K_r at one parameter point and their derivatives.
#[derive(Debug, Clone)]
pub struct PromEvaluation {
    pub mass: Mat<f64>,
    pub damping: Mat<f64>,
    pub stiffness: Mat<f64>,
    /// ∂M_r/∂p_j, ∂K_r/∂p_j per parameter j (∂C_r/∂p_j = α ∂M_r/∂p_j + β ∂K_r/∂p_j).
    pub d_mass: Vec<Mat<f64>>,
    pub d_stiffness: Vec<Mat<f64>>,
}

impl Prom {
    /// Check the shapes: one K and one M component per function, all n × n, parameters known.
    pub fn validate(&self) -> Result<(), PromError> {
        let count = self.functions.len();
        for (what, parts) in [("stiffness components", &self.stiffness), ("mass components", &self.mass)] {
            if parts.len() != count {
                return Err(PromError::Shape { what, expected: count, got: parts.len() });
            }
        }
        let n = self.size();
        for m in self.stiffness.iter().chain(&self.mass) {
            for got in [m.nrows(), m.ncols()] {
                if got != n {
                    return Err(PromError::Shape { what: "reduced matrix size", expected: n, got });
                }
            }
        }
        for (function, f) in self.functions.iter().enumerate() {
            if let Some(&(_, index)) = f.driven_by.iter().find(|(_, j)| *j >= self.parameters.len()) {
                return Err(PromError::UnknownParameter { function, index, count: self.parameters.len() });
            }
        }
        Ok(())
    }

    /// Reduced size n_r.
    pub fn size(&self) -> usize {
        self.stiffness.first().map_or(0, |m| m.nrows())
    }

    /// Buffers for [`Prom::evaluate`].
    pub fn workspace(&self) -> PromEvaluation {
        let n = self.size();
        let zeros = || Mat::<f64>::zeros(n, n);
        let per_param = || (0..self.parameters.len()).map(|_| zeros()).collect();
        PromEvaluation { mass: zeros(), damping: zeros(), stiffness: zeros(), d_mass: per_param(), d_stiffness: per_param() }
    }

    /// Names of the parameters of `p` outside their box (extrapolation: allowed, but the
    /// caller warns, naming them).
    pub fn outside_box(&self, p: &[f64]) -> Vec<&str> {
        self.parameters.iter().zip(p).filter(|(q, v)| **v < q.low || **v > q.high).map(|(q, _)| q.name.as_str()).collect()
    }

    /// Evaluate M_r, C_r, K_r and their derivatives at `p` into `out` (eq. 3.32), without
    /// allocating.
    pub fn evaluate(&self, p: &[f64], out: &mut PromEvaluation) -> Result<(), PromError> {
        if p.len() != self.parameters.len() {
            return Err(PromError::Shape { what: "parameter values", expected: self.parameters.len(), got: p.len() });
        }
        if let Some((q, &value)) = self.parameters.iter().zip(p).find(|(_, v)| !v.is_finite()) {
            return Err(PromError::NotFinite { name: q.name.clone(), value });
        }
        let clear = |m: &mut Mat<f64>| m.fill(0.0);
        clear(&mut out.mass);
        clear(&mut out.stiffness);
        out.d_mass.iter_mut().chain(out.d_stiffness.iter_mut()).for_each(clear);
        for (i, f) in self.functions.iter().enumerate() {
            let value = f.value(p);
            add_scaled(&mut out.stiffness, value, &self.stiffness[i]);
            add_scaled(&mut out.mass, value, &self.mass[i]);
            for &(_, j) in &f.driven_by {
                let d = f.derivative(p, j);
                add_scaled(&mut out.d_stiffness[j], d, &self.stiffness[i]);
                add_scaled(&mut out.d_mass[j], d, &self.mass[i]);
            }
        }
        let n = self.size();
        for c in 0..n {
            let (m, k) = (out.mass.col_as_slice(c), out.stiffness.col_as_slice(c));
            let (alpha, beta) = (self.alpha, self.beta);
            let damping: &mut [f64] = out.damping.col_as_slice_mut(c);
            damping.iter_mut().zip(m.iter().zip(k)).for_each(|(d, (m, k))| *d = alpha * m + beta * k);
        }
        Ok(())
    }
}

/// out += s · x, column by column (contiguous, no temporaries).
fn add_scaled(out: &mut Mat<f64>, s: f64, x: &Mat<f64>) {
    if s == 0.0 {
        return;
    }
    for c in 0..x.ncols() {
        let src = x.col_as_slice(c);
        out.col_as_slice_mut(c).iter_mut().zip(src).for_each(|(o, v)| *o += s * v);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 3 × 3 pROM with E, ν (through Lamé parts) and ρ of one material plus a constant part.
    fn sample() -> Prom {
        let fixed = CoefficientValues { e: 2.0e11, nu: 0.3, rho: 7800.0, ..Default::default() };
        let driven = |c, inputs: Vec<(CoefficientInput, usize)>| AffineFunction { coefficient: c, fixed, driven_by: inputs };
        let functions = vec![
            AffineFunction::constant(),
            driven(Coefficient::Lambda, vec![(CoefficientInput::E, 0), (CoefficientInput::Nu, 1)]),
            driven(Coefficient::Mu, vec![(CoefficientInput::E, 0), (CoefficientInput::Nu, 1)]),
            driven(Coefficient::Rho, vec![(CoefficientInput::Rho, 2)]),
        ];
        let sym = |seed: f64| Mat::<f64>::from_fn(3, 3, |i, j| ((i + j) as f64 + seed).cos() + if i == j { 3.0 } else { 0.0 });
        let zero = Mat::<f64>::zeros(3, 3);
        let parameters = ["E", "NU", "RHO"]
            .iter()
            .zip([(1e11, 3e11, 2e11), (0.2, 0.4, 0.3), (7000.0, 9000.0, 7800.0)])
            .map(|(n, (low, high, nominal))| PromParameter { name: n.to_string(), low, high, nominal })
            .collect();
        Prom {
            parameters,
            functions,
            stiffness: vec![sym(0.1), sym(0.5) * faer::Scale(1e-11), sym(0.9) * faer::Scale(1e-11), zero.clone()],
            mass: vec![sym(0.2) * faer::Scale(0.1), zero.clone(), zero, sym(0.7) * faer::Scale(1e-4)],
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
        let (lam, mu) = (p[0] * p[1] / ((1.0 + p[1]) * (1.0 - 2.0 * p[1])), p[0] / (2.0 * (1.0 + p[1])));
        let k = &prom.stiffness[0] + &prom.stiffness[1] * faer::Scale(lam) + &prom.stiffness[2] * faer::Scale(mu);
        let m = &prom.mass[0] + &prom.mass[3] * faer::Scale(p[2]);
        let c = &m * faer::Scale(prom.alpha) + &k * faer::Scale(prom.beta);
        assert!((&out.stiffness - &k).norm_max() <= 1e-14 * k.norm_max());
        assert!((&out.mass - &m).norm_max() <= 1e-14 * m.norm_max());
        assert!((&out.damping - &c).norm_max() <= 1e-14 * c.norm_max());
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
            for (analytic, plus, minus) in [(&at.d_stiffness[j], &a.stiffness, &b.stiffness), (&at.d_mass[j], &a.mass, &b.mass)] {
                let fd = (plus - minus) * faer::Scale(1.0 / (2.0 * h));
                let scale = fd.norm_max().max(analytic.norm_max());
                assert!((&fd - analytic).norm_max() <= 1e-7 * scale.max(f64::MIN_POSITIVE), "parameter {j}");
            }
        }
    }

    #[test]
    fn refuses_bad_evaluations_and_names_extrapolated_parameters() {
        let prom = sample();
        let mut out = prom.workspace();
        assert!(matches!(prom.evaluate(&[1e11, 0.3], &mut out), Err(PromError::Shape { .. })));
        assert!(matches!(prom.evaluate(&[f64::NAN, 0.3, 7800.0], &mut out), Err(PromError::NotFinite { .. })));
        assert_eq!(prom.outside_box(&[3.5e11, 0.3, 6000.0]), vec!["E", "RHO"]);
        let mut broken = prom.clone();
        broken.mass.pop();
        assert!(matches!(broken.validate(), Err(PromError::Shape { what: "mass components", .. })));
    }
}
