//! 3-vectors as `[f64; 3]`, passed by value (no allocation). Every function spells its
//! arithmetic out once, in a fixed order, so a result does not depend on which caller asks.

use super::mat3::Mat3;

/// a + b
pub fn add(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

/// a − b
pub fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// s a
pub fn scale(a: [f64; 3], s: f64) -> [f64; 3] {
    [a[0] * s, a[1] * s, a[2] * s]
}

/// a · b
pub fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// a × b
pub fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// |a| = √(a · a)
pub fn norm(a: [f64; 3]) -> f64 {
    dot(a, a).sqrt()
}

/// a / |a| (each component divided by the length); `None` when the length is zero or not
/// finite, where no direction is defined.
pub fn normalize(a: [f64; 3]) -> Option<[f64; 3]> {
    let n = norm(a);
    (n > 0.0 && n.is_finite()).then(|| a.map(|x| x / n))
}

/// a · (b × c): the signed volume of the parallelepiped on a, b, c.
pub fn triple(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> f64 {
    dot(a, cross(b, c))
}

/// Mean of points (the origin for none).
pub fn mean(points: &[[f64; 3]]) -> [f64; 3] {
    let n = points.len().max(1) as f64;
    let s = points.iter().fold([0.0; 3], |acc, p| add(acc, *p));
    scale(s, 1.0 / n)
}

/// The skew-symmetric cross-product matrix ã of a (thesis's tilde operator, as in eq. A.10 and
/// A.13): ã u = a × u, ãᵀ = −ã, and ã ã = a aᵀ − |a|² I.
///
/// ```text
///      ⎡  0   −a₃   a₂ ⎤
/// ã =  ⎢  a₃   0   −a₁ ⎥
///      ⎣ −a₂   a₁   0  ⎦
/// ```
pub fn skew(a: [f64; 3]) -> Mat3 {
    [[0.0, -a[2], a[1]], [a[2], 0.0, -a[0]], [-a[1], a[0], 0.0]]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::mat3;

    const A: [f64; 3] = [0.3, -1.7, 2.2];
    const B: [f64; 3] = [-4.1, 0.6, 1.9];

    #[test]
    fn cross_is_orthogonal_to_both_factors_and_anticommutes() {
        let c = cross(A, B);
        assert!(dot(c, A).abs() < 1e-14 && dot(c, B).abs() < 1e-14);
        assert_eq!(cross(B, A), scale(c, -1.0));
        assert_eq!(cross([1.0, 0.0, 0.0], [0.0, 1.0, 0.0]), [0.0, 0.0, 1.0]);
        // |a × b|² + (a · b)² = |a|² |b|² (Lagrange)
        let lagrange = dot(c, c) + dot(A, B).powi(2) - dot(A, A) * dot(B, B);
        assert!(lagrange.abs() < 1e-12);
    }

    #[test]
    fn skew_matrix_applies_the_cross_product() {
        let s = skew(A);
        assert_eq!(mat3::mul_vec(&s, B), cross(A, B));
        assert_eq!(mat3::transpose(&s), skew(scale(A, -1.0)));
        // ã ã = a aᵀ − |a|² I
        let ss = mat3::mul(&s, &s);
        for (i, row) in ss.iter().enumerate() {
            for (j, v) in row.iter().enumerate() {
                let expected = A[i] * A[j] - if i == j { dot(A, A) } else { 0.0 };
                assert!(
                    (v - expected).abs() < 1e-14,
                    "({i}, {j}): {v} vs {expected}"
                );
            }
        }
    }

    #[test]
    fn normalize_gives_a_unit_vector_and_refuses_zero_or_infinite_length() {
        let u = normalize(A).unwrap();
        assert!((norm(u) - 1.0).abs() < 1e-15);
        assert!(norm(cross(u, A)) < 1e-14 && dot(u, A) > 0.0);
        assert_eq!(normalize([0.0; 3]), None);
        assert_eq!(normalize([f64::INFINITY, 0.0, 0.0]), None);
        assert_eq!(normalize([f64::NAN, 1.0, 0.0]), None);
    }

    #[test]
    fn triple_product_is_the_signed_volume() {
        let e = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        assert_eq!(triple(e[0], e[1], e[2]), 1.0);
        assert_eq!(triple(e[1], e[0], e[2]), -1.0);
        assert!((triple(A, B, cross(A, B)) - dot(cross(A, B), cross(A, B))).abs() < 1e-12);
    }

    #[test]
    fn mean_of_points_and_of_none() {
        assert_eq!(mean(&[A, B]), scale(add(A, B), 0.5));
        assert_eq!(mean(&[]), [0.0; 3]);
        assert_eq!(sub(A, A), [0.0; 3]);
    }
}
