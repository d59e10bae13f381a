//! 3×3 matrices as row-major `[[f64; 3]; 3]`: `m[i][j]` is row i, column j. Passed by
//! reference, returned by value; the entries are summed in index order.

use super::vec3::dot;

/// A 3×3 matrix, row-major.
pub type Mat3 = [[f64; 3]; 3];

/// The identity matrix.
pub const IDENTITY: Mat3 = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];

/// Aᵀ
pub fn transpose(a: &Mat3) -> Mat3 {
    std::array::from_fn(|i| std::array::from_fn(|j| a[j][i]))
}

/// The matrix whose columns are c₀, c₁, c₂.
pub fn from_columns(c: [[f64; 3]; 3]) -> Mat3 {
    transpose(&c)
}

/// A v
pub fn mul_vec(a: &Mat3, v: [f64; 3]) -> [f64; 3] {
    [dot(a[0], v), dot(a[1], v), dot(a[2], v)]
}

/// Aᵀ v
pub fn transpose_mul_vec(a: &Mat3, v: [f64; 3]) -> [f64; 3] {
    mul_vec(&transpose(a), v)
}

/// A B
pub fn mul(a: &Mat3, b: &Mat3) -> Mat3 {
    let bt = transpose(b);
    std::array::from_fn(|i| std::array::from_fn(|j| dot(a[i], bt[j])))
}

/// det A, expanded along the first row.
pub fn det(a: &Mat3) -> f64 {
    a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1])
        - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0])
        + a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0])
}

/// The largest entry of |A − B|.
pub fn max_abs_difference(a: &Mat3, b: &Mat3) -> f64 {
    a.iter()
        .flatten()
        .zip(b.iter().flatten())
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::vec3::triple;

    const A: Mat3 = [[2.0, -1.0, 0.5], [0.3, 4.0, -2.0], [1.5, 0.0, 3.0]];
    const B: Mat3 = [[-1.0, 2.0, 0.0], [0.5, 0.25, 1.0], [3.0, -2.0, 1.0]];

    #[test]
    fn product_matches_the_index_sum() {
        let ab = mul(&A, &B);
        for i in 0..3 {
            for j in 0..3 {
                let s: f64 = (0..3).map(|k| A[i][k] * B[k][j]).sum();
                assert!((ab[i][j] - s).abs() < 1e-14);
            }
        }
        assert_eq!(mul(&A, &IDENTITY), A);
        assert_eq!(mul(&IDENTITY, &A), A);
    }

    #[test]
    fn transpose_and_vector_products_agree() {
        let v = [0.7, -0.2, 1.3];
        assert_eq!(transpose(&transpose(&A)), A);
        assert_eq!(transpose_mul_vec(&A, v), mul_vec(&transpose(&A), v));
        assert_eq!(from_columns(A), transpose(&A));
        // (A B)ᵀ = Bᵀ Aᵀ
        let lhs = transpose(&mul(&A, &B));
        let rhs = mul(&transpose(&B), &transpose(&A));
        assert!(max_abs_difference(&lhs, &rhs) < 1e-14);
    }

    #[test]
    fn determinant_is_the_triple_product_of_the_rows_and_multiplicative() {
        assert!((det(&A) - triple(A[0], A[1], A[2])).abs() < 1e-13);
        assert!((det(&mul(&A, &B)) - det(&A) * det(&B)).abs() < 1e-12);
        assert_eq!(det(&IDENTITY), 1.0);
    }
}
