//! Rotation matrices: orthonormal 3×3 matrices with determinant +1 ([`Mat3`], row-major).
//!
//! R maps components in the rotated frame to the fixed frame (x = R x̄); the rotation "first
//! R₂, then R₁" is R₁ R₂ ([`mat3::mul`]) and R⁻¹ = Rᵀ ([`mat3::transpose`]). Euler parameters
//! of the same rotations are in [`super::euler_parameters`].

use super::mat3::{self, IDENTITY, Mat3};
use super::vec3::normalize;

/// Rodrigues' formula: the rotation by `angle` radians about `axis` (right-hand rule; the axis
/// is normalized here), R = cos θ I + sin θ ũ + (1 − cos θ) u uᵀ with u = axis / |axis|.
/// `None` when the axis has no direction (zero or non-finite length).
pub fn from_axis_angle(axis: [f64; 3], angle: f64) -> Option<Mat3> {
    let [x, y, z] = normalize(axis)?;
    let (s, c) = angle.sin_cos();
    let t = 1.0 - c;
    Some([
        [c + x * x * t, x * y * t - z * s, x * z * t + y * s],
        [y * x * t + z * s, c + y * y * t, y * z * t - x * s],
        [z * x * t - y * s, z * y * t + x * s, c + z * z * t],
    ])
}

/// Whether `r` is a rotation to within `tol`: every entry of Rᵀ R − I and det R − 1 at most
/// `tol` in magnitude (a reflection, det −1, is not a rotation).
pub fn is_rotation(r: &Mat3, tol: f64) -> bool {
    let rtr = mat3::mul(&mat3::transpose(r), r);
    mat3::max_abs_difference(&rtr, &IDENTITY) <= tol && (mat3::det(r) - 1.0).abs() <= tol
}

/// R J Rᵀ: a second-order tensor J (an inertia tensor, say) given in the rotated frame,
/// expressed in the fixed frame. Summed term by term, Σₖ Σₗ R_ak J_kl R_bl.
pub fn rotate_tensor(r: &Mat3, j: &Mat3) -> Mat3 {
    let mut out = [[0.0; 3]; 3];
    for a in 0..3 {
        for b in 0..3 {
            for k in 0..3 {
                for l in 0..3 {
                    out[a][b] += r[a][k] * j[k][l] * r[b][l];
                }
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::vec3::{cross, dot, norm, scale, skew, sub};
    use std::f64::consts::{FRAC_PI_2, PI};

    #[test]
    fn quarter_turn_about_z_takes_x_to_y() {
        let r = from_axis_angle([0.0, 0.0, 2.0], FRAC_PI_2).unwrap();
        let y = mat3::mul_vec(&r, [1.0, 0.0, 0.0]);
        assert!(norm(sub(y, [0.0, 1.0, 0.0])) < 1e-15);
        assert!(is_rotation(&r, 1e-15));
        assert_eq!(from_axis_angle([0.0; 3], 1.0), None);
    }

    #[test]
    fn rodrigues_keeps_the_axis_and_turns_the_rest_by_the_angle() {
        let axis = [0.36, -0.48, 0.8]; // unit
        let angle = 2.3;
        let r = from_axis_angle(axis, angle).unwrap();
        assert!(is_rotation(&r, 1e-14));
        assert!(norm(sub(mat3::mul_vec(&r, axis), axis)) < 1e-15);
        // v ⟂ axis: R v = cos θ v + sin θ (axis × v)
        let v = cross(axis, [1.0, 0.0, 0.0]);
        let expected = [0, 1, 2].map(|i| angle.cos() * v[i] + angle.sin() * cross(axis, v)[i]);
        assert!(norm(sub(mat3::mul_vec(&r, v), expected)) < 1e-15);
        // the series form I + sin θ ũ + (1 − cos θ) ũ²
        let u = skew(axis);
        let uu = mat3::mul(&u, &u);
        let series: Mat3 = std::array::from_fn(|i| {
            std::array::from_fn(|j| {
                IDENTITY[i][j] + angle.sin() * u[i][j] + (1.0 - angle.cos()) * uu[i][j]
            })
        });
        assert!(mat3::max_abs_difference(&r, &series) < 1e-15);
    }

    #[test]
    fn composition_adds_angles_about_one_axis_and_the_transpose_undoes() {
        let axis = [1.0, 2.0, -2.0];
        let (a, b) = (0.7, -2.9);
        let ra = from_axis_angle(axis, a).unwrap();
        let rb = from_axis_angle(axis, b).unwrap();
        let rab = from_axis_angle(axis, a + b).unwrap();
        assert!(mat3::max_abs_difference(&mat3::mul(&ra, &rb), &rab) < 1e-15);
        let back = mat3::mul(&mat3::transpose(&ra), &ra);
        assert!(mat3::max_abs_difference(&back, &IDENTITY) < 1e-15);
    }

    #[test]
    fn orthonormality_check_refuses_reflections_and_stretches() {
        let r = from_axis_angle([0.2, 0.1, -1.0], PI).unwrap();
        assert!(is_rotation(&r, 1e-14));
        let mut mirror = r;
        mirror[2] = scale(r[2], -1.0);
        assert!(!is_rotation(&mirror, 1e-6));
        let stretched = [r[0], r[1], scale(r[2], 1.0 + 1e-6)];
        assert!(!is_rotation(&stretched, 1e-8));
        assert!(is_rotation(&stretched, 1e-5));
    }

    #[test]
    fn tensor_in_the_fixed_frame_keeps_its_quadratic_form() {
        let j = [[3.0, 0.2, -0.1], [0.2, 2.0, 0.4], [-0.1, 0.4, 1.5]];
        let r = from_axis_angle([-0.3, 0.9, 0.5], 1.1).unwrap();
        let jr = rotate_tensor(&r, &j);
        let v = [0.4, -1.2, 0.9];
        let rv = mat3::mul_vec(&r, v);
        // (R v)ᵀ (R J Rᵀ) (R v) = vᵀ J v
        let lhs = dot(rv, mat3::mul_vec(&jr, rv));
        let rhs = dot(v, mat3::mul_vec(&j, v));
        assert!((lhs - rhs).abs() < 1e-13);
    }
}
