//! Affine parts of element matrices (thesis §3.3, eq. 3.12–3.25; DESIGN.md §5).
//!
//! A parameter-dependent element matrix is stored as `K(p) = Σ_i f_i(p) K_i`, where each
//! coefficient function [`Coefficient`] depends on one material, section or lumped parameter
//! and `K_i` is a constant matrix. The element kernels are linear in their material/section
//! data, so the parts are obtained by evaluating a kernel with the "unit" data of each part.

use faer::Mat;

/// A coefficient function f_i(p) of one affine part.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Coefficient {
    /// The constant part (f = 1): everything not parametrized.
    Constant,
    /// Young's modulus E (K ∝ E at fixed ν).
    E,
    /// Density ρ (M ∝ ρ).
    Rho,
    /// 3-D Lamé λ = Eν/((1+ν)(1−2ν)) (eq. 3.13).
    Lambda,
    /// Shear modulus μ = G = E/(2(1+ν)) (eq. 3.14).
    Mu,
    /// Plane-stress λ* = Eν/(1−ν²) (shells; DESIGN.md §5).
    LambdaPlaneStress,
    /// Angle-ply functions of Θ (eq. 3.18): cos⁴, sin⁴, cos²sin², cos·sin³, cos³·sin.
    Cos4,
    Sin4,
    Cos2Sin2,
    CosSin3,
    Cos3Sin,
    /// Ply thickness powers (eq. 3.20–3.22).
    H,
    H2,
    H3,
    /// Lumped stiffness k or mass m (eq. 3.23–3.25).
    Lumped,
}

impl Coefficient {
    /// Value of the coefficient for material constants (E, ν, ρ), angle Θ in degrees, ply
    /// thickness h, and a lumped value.
    pub fn value(self, v: &CoefficientValues) -> f64 {
        let (c, s) = (v.theta_deg.to_radians().cos(), v.theta_deg.to_radians().sin());
        match self {
            Coefficient::Constant => 1.0,
            Coefficient::E => v.e,
            Coefficient::Rho => v.rho,
            Coefficient::Lambda => v.e * v.nu / ((1.0 + v.nu) * (1.0 - 2.0 * v.nu)),
            Coefficient::Mu => v.e / (2.0 * (1.0 + v.nu)),
            Coefficient::LambdaPlaneStress => v.e * v.nu / (1.0 - v.nu * v.nu),
            Coefficient::Cos4 => c.powi(4),
            Coefficient::Sin4 => s.powi(4),
            Coefficient::Cos2Sin2 => c * c * s * s,
            Coefficient::CosSin3 => c * s.powi(3),
            Coefficient::Cos3Sin => c.powi(3) * s,
            Coefficient::H => v.h,
            Coefficient::H2 => v.h * v.h,
            Coefficient::H3 => v.h.powi(3),
            Coefficient::Lumped => v.lumped,
        }
    }
}

/// The parameter values the coefficients are evaluated at.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct CoefficientValues {
    pub e: f64,
    pub nu: f64,
    pub rho: f64,
    pub theta_deg: f64,
    pub h: f64,
    pub lumped: f64,
}

/// An element matrix split into affine parts.
#[derive(Debug, Clone)]
pub struct AffineMatrix {
    /// (coefficient, constant matrix) pairs; coefficients are distinct.
    pub parts: Vec<(Coefficient, Mat<f64>)>,
}

impl AffineMatrix {
    /// Σ f_i(v) K_i.
    pub fn evaluate(&self, v: &CoefficientValues) -> Mat<f64> {
        let n = self.parts.first().map_or(0, |(_, m)| m.nrows());
        let mut out = Mat::<f64>::zeros(n, n);
        for (c, m) in &self.parts {
            let f = c.value(v);
            out += m * faer::Scale(f);
        }
        out
    }
}
