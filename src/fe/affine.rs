//! Affine parts of element matrices (thesis §3.3, eq. 3.12–3.25; DESIGN.md §5).
//!
//! A parameter-dependent element matrix is stored as `K(p) = Σ_i f_i(p) K_i`, where each
//! coefficient function [`Coefficient`] depends on one material, section or lumped parameter
//! and `K_i` is a constant matrix. The element kernels are linear in their material/section
//! data, so the parts are obtained by evaluating a kernel with the "unit" data of each part.

use faer::Mat;

/// A coefficient function f_i(p) of one affine part.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
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
        let (c, s) = (
            v.theta_deg.to_radians().cos(),
            v.theta_deg.to_radians().sin(),
        );
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

impl Coefficient {
    /// Partial derivatives of the coefficient with respect to each input (E, ν, ρ, Θ in
    /// degrees, h, lumped value), in a [`CoefficientValues`] of partials. The estimator and the
    /// pROM derivatives ∂K_r/∂p (thesis eq. 8.19–8.20) use them.
    pub fn gradient(self, v: &CoefficientValues) -> CoefficientValues {
        let (c, s) = (
            v.theta_deg.to_radians().cos(),
            v.theta_deg.to_radians().sin(),
        );
        let per_degree = std::f64::consts::PI / 180.0;
        let nu = v.nu;
        let mut g = CoefficientValues::default();
        match self {
            Coefficient::Constant => {}
            Coefficient::E => g.e = 1.0,
            Coefficient::Rho => g.rho = 1.0,
            Coefficient::Lambda => {
                let d = (1.0 + nu) * (1.0 - 2.0 * nu);
                g.e = nu / d;
                g.nu = v.e * (1.0 + 2.0 * nu * nu) / (d * d);
            }
            Coefficient::Mu => {
                g.e = 1.0 / (2.0 * (1.0 + nu));
                g.nu = -v.e / (2.0 * (1.0 + nu) * (1.0 + nu));
            }
            Coefficient::LambdaPlaneStress => {
                let d = 1.0 - nu * nu;
                g.e = nu / d;
                g.nu = v.e * (1.0 + nu * nu) / (d * d);
            }
            Coefficient::Cos4 => g.theta_deg = -4.0 * c.powi(3) * s * per_degree,
            Coefficient::Sin4 => g.theta_deg = 4.0 * s.powi(3) * c * per_degree,
            Coefficient::Cos2Sin2 => g.theta_deg = 2.0 * c * s * (c * c - s * s) * per_degree,
            Coefficient::CosSin3 => g.theta_deg = (3.0 * c * c * s * s - s.powi(4)) * per_degree,
            Coefficient::Cos3Sin => g.theta_deg = (c.powi(4) - 3.0 * c * c * s * s) * per_degree,
            Coefficient::H => g.h = 1.0,
            Coefficient::H2 => g.h = 2.0 * v.h,
            Coefficient::H3 => g.h = 3.0 * v.h * v.h,
            Coefficient::Lumped => g.lumped = 1.0,
        }
        g
    }

    /// Every coefficient, for exhaustive tests and name lookup.
    pub const ALL: [Coefficient; 15] = [
        Coefficient::Constant,
        Coefficient::E,
        Coefficient::Rho,
        Coefficient::Lambda,
        Coefficient::Mu,
        Coefficient::LambdaPlaneStress,
        Coefficient::Cos4,
        Coefficient::Sin4,
        Coefficient::Cos2Sin2,
        Coefficient::CosSin3,
        Coefficient::Cos3Sin,
        Coefficient::H,
        Coefficient::H2,
        Coefficient::H3,
        Coefficient::Lumped,
    ];
}

/// The parameter values the coefficients are evaluated at.
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize, serde::Deserialize)]
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

#[cfg(test)]
mod tests {
    use super::*;

    fn values() -> CoefficientValues {
        CoefficientValues {
            e: 7.0e10,
            nu: 0.31,
            rho: 2700.0,
            theta_deg: 27.0,
            h: 3.0e-4,
            lumped: 5.0e4,
        }
    }

    /// Central differences with a relative step; the truncation error O(δ²) of a smooth
    /// function at δ = 1e-6 relative is ~1e-12, round-off ~1e-16/1e-6 = 1e-10 relative, so 1e-7
    /// leaves three orders of margin and still catches any wrong sign or factor.
    #[test]
    fn gradient_matches_central_differences() {
        let v = values();
        type Field = fn(&mut CoefficientValues) -> &mut f64;
        let fields: [(&str, Field); 6] = [
            ("e", |v| &mut v.e),
            ("nu", |v| &mut v.nu),
            ("rho", |v| &mut v.rho),
            ("theta", |v| &mut v.theta_deg),
            ("h", |v| &mut v.h),
            ("lumped", |v| &mut v.lumped),
        ];
        for c in Coefficient::ALL {
            let mut g = c.gradient(&v);
            for (name, field) in fields {
                let x = *field(&mut v.clone());
                let step = 1e-6 * x.abs();
                let (mut up, mut down) = (v, v);
                *field(&mut up) = x + step;
                *field(&mut down) = x - step;
                let fd = (c.value(&up) - c.value(&down)) / (2.0 * step);
                let analytic = *field(&mut g);
                let scale = c.value(&v).abs() / x.abs();
                assert!(
                    (fd - analytic).abs() <= 1e-7 * scale.max(fd.abs()),
                    "{c:?} d/d{name}: analytic {analytic}, differences {fd}"
                );
            }
        }
    }
}
