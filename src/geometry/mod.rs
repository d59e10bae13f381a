//! Geometry of points, directions and orientations in 3-D: the vector algebra the element
//! kernels and the model checks use, and the rotation coordinates of the floating-frame bodies
//! (DESIGN.md §11; thesis ch. 2.4 and appendix A).
//!
//! - [`vec3`]: 3-vectors as `[f64; 3]` (sum, difference, products, length, unit vector) and the
//!   skew-symmetric cross-product matrix ṽ (ṽ u = v × u);
//! - [`mat3`]: 3×3 matrices as row-major `[[f64; 3]; 3]` (`m[i][j]` = row i, column j):
//!   products, transpose, determinant;
//! - [`quadrature`]: Gauss–Legendre rules;
//! - [`rotation`]: rotation matrices (orthonormal, det +1): axis–angle (Rodrigues), the
//!   orthonormality check, tensors in a rotated frame;
//! - [`euler_parameters`]: the Euler parameters e = (e₀, e₁, e₂, e₃) of eq. A.1, their
//!   rotation matrix A(e) = E Gᵀ (eq. A.2–A.4), angular velocities, the normalization
//!   constraint, the conversion from a rotation matrix and the derivative ∂(A s̄)/∂e.
//!
//! Conventions: a rotation matrix R maps components in the rotated (body) frame to the fixed
//! (global) frame, x = R x̄; composing "first R₂, then R₁" is R₁ R₂ ([`mat3::mul`]) and the
//! inverse is the transpose ([`mat3::transpose`]).
//!
//! ```
//! use paraflex::geometry::{euler_parameters as ep, mat3, vec3};
//!
//! // a body turned a quarter turn about the global z axis
//! let e = ep::from_axis_angle([0.0, 0.0, 1.0], std::f64::consts::FRAC_PI_2).unwrap();
//! let a = ep::rotation_matrix(&e);
//! // its x axis points along global y
//! let x = mat3::mul_vec(&a, [1.0, 0.0, 0.0]);
//! assert!(vec3::norm(vec3::sub(x, [0.0, 1.0, 0.0])) < 1e-15);
//! // the same parameters back from the matrix (Shepperd's method)
//! let back = ep::from_rotation_matrix(&a);
//! assert!((0..4).all(|k| (back[k] - e[k]).abs() < 1e-15));
//! ```

pub mod euler_parameters;
#[cfg(test)]
mod euler_parameters_tests;
pub mod mat3;
pub mod quadrature;
pub mod rotation;
pub mod vec3;
