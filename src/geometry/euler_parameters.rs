//! Euler parameters: the rotation coordinates of a floating frame (thesis eq. A.1,
//! DESIGN.md §11), e = (e₀, e₁, e₂, e₃) with e₀ = cos(θ/2) and (e₁, e₂, e₃) = sin(θ/2) u for a
//! rotation by θ about the unit axis u. They have no singular orientation; the price is one
//! redundant coordinate and the normalization constraint eᵀe = 1 per body. e and −e are the
//! same rotation.
//!
//! With ẽ the skew matrix of (e₁, e₂, e₃) and e the 4-vector, the two 3×4 matrices of
//! eq. A.2–A.3 are (Nikravesh's E and G; Shabana writes them G and Ḡ)
//!
//! ```text
//! E(e) = [−ē, ẽ + e₀ I],   G(e) = [−ē, −ẽ + e₀ I],   ē = (e₁, e₂, e₃)
//! ```
//!
//! Both are linear in e (so Ė = E(ė), Ġ = G(ė)) and satisfy E e = G e = 0,
//! E Eᵀ = G Gᵀ = (eᵀe) I₃. The rotation matrix is their product A = E Gᵀ (eq. A.4), a
//! homogeneous quadratic in e that maps body components to global ones (x = A x̄) and is
//! orthonormal for eᵀe = 1. On the constraint (eᵀe = 1, eᵀė = 0) the angular velocity is
//! ω = 2 E ė in the global frame and ω̄ = 2 G ė in the body frame (ω = A ω̄), inverted by
//! ė = ½ Eᵀ ω = ½ Gᵀ ω̄. The mass matrix of eq. A.24–A.27 is written with E, G and the 4×4
//! matrix s⁺ of eq. A.10 ([`plus_matrix`]).

use super::mat3::Mat3;
use super::vec3::normalize as normalize_axis;

/// Euler parameters (e₀, e₁, e₂, e₃), eq. A.1.
pub type EulerParameters = [f64; 4];

/// A 3×4 matrix, row-major (E, G and the Jacobians of this module).
pub type Mat3x4 = [[f64; 4]; 3];

/// The parameters of no rotation.
pub const IDENTITY: EulerParameters = [1.0, 0.0, 0.0, 0.0];

/// E(e) of eq. A.2: ω = 2 E ė is the angular velocity in the global frame.
///
/// ```text
///        ⎡ −e₁   e₀  −e₃   e₂ ⎤
/// E  =   ⎢ −e₂   e₃   e₀  −e₁ ⎥
///        ⎣ −e₃  −e₂   e₁   e₀ ⎦
/// ```
pub fn e_matrix(e: &EulerParameters) -> Mat3x4 {
    let [e0, e1, e2, e3] = *e;
    [[-e1, e0, -e3, e2], [-e2, e3, e0, -e1], [-e3, -e2, e1, e0]]
}

/// G(e) of eq. A.3: ω̄ = 2 G ė is the angular velocity in the body frame.
///
/// ```text
///        ⎡ −e₁   e₀   e₃  −e₂ ⎤
/// G  =   ⎢ −e₂  −e₃   e₀   e₁ ⎥
///        ⎣ −e₃   e₂  −e₁   e₀ ⎦
/// ```
pub fn g_matrix(e: &EulerParameters) -> Mat3x4 {
    let [e0, e1, e2, e3] = *e;
    [[-e1, e0, e3, -e2], [-e2, -e3, e0, e1], [-e3, e2, -e1, e0]]
}

/// The rotation matrix A(e) = E(e) G(e)ᵀ of eq. A.4 (body → global components). Written
/// out: A = (e₀² − ēᵀē) I + 2 ē ēᵀ + 2 e₀ ẽ; orthonormal with det +1 when eᵀe = 1.
pub fn rotation_matrix(e: &EulerParameters) -> Mat3 {
    let (em, gm) = (e_matrix(e), g_matrix(e));
    std::array::from_fn(|i| std::array::from_fn(|j| dot4(&em[i], &gm[j])))
}

/// The 4×4 matrix s⁺ of a 3-vector s (eq. A.10), with s̃ its skew matrix:
///
/// ```text
///        ⎡  0   sᵀ ⎤
/// s⁺ =   ⎣ −s   s̃  ⎦
/// ```
pub fn plus_matrix(s: [f64; 3]) -> [[f64; 4]; 4] {
    let [x, y, z] = s;
    [
        [0.0, x, y, z],
        [-x, 0.0, -z, y],
        [-y, z, 0.0, -x],
        [-z, -y, x, 0.0],
    ]
}

/// ∂(A(e) s̄)/∂e = −2 E(e) s̄⁺ (3×4): the derivative of a body-fixed vector s̄ in global
/// components with respect to the Euler parameters, the block of eq. A.6 / A.24 (summed over
/// the nodes with their masses it is M_RΘ) and of every constraint Jacobian row that involves
/// a point or a direction fixed in a body. Exact for every e (A(e) s̄ is quadratic in e), and
/// d(A s̄)/dt = (∂(A s̄)/∂e) ė.
pub fn rotated_vector_jacobian(e: &EulerParameters, s: [f64; 3]) -> Mat3x4 {
    let em = e_matrix(e);
    let plus = plus_matrix(s);
    std::array::from_fn(|i| {
        std::array::from_fn(|j| -2.0 * (0..4).map(|k| em[i][k] * plus[k][j]).sum::<f64>())
    })
}

/// ω = 2 E(e) ė: the angular velocity in global components (for eᵀe = 1, eᵀė = 0).
pub fn global_angular_velocity(e: &EulerParameters, e_dot: &EulerParameters) -> [f64; 3] {
    e_matrix(e).map(|row| 2.0 * dot4(&row, e_dot))
}

/// ω̄ = 2 G(e) ė: the angular velocity in body components (for eᵀe = 1, eᵀė = 0).
pub fn body_angular_velocity(e: &EulerParameters, e_dot: &EulerParameters) -> [f64; 3] {
    g_matrix(e).map(|row| 2.0 * dot4(&row, e_dot))
}

/// ė = ½ E(e)ᵀ ω: the parameter rates of a global angular velocity (for eᵀe = 1; the result
/// satisfies eᵀė = 0, the derivative of the normalization constraint).
pub fn rates_from_global_angular_velocity(e: &EulerParameters, omega: [f64; 3]) -> EulerParameters {
    half_transpose_mul(&e_matrix(e), omega)
}

/// ė = ½ G(e)ᵀ ω̄: the parameter rates of a body-frame angular velocity (for eᵀe = 1; the
/// result satisfies eᵀė = 0).
pub fn rates_from_body_angular_velocity(
    e: &EulerParameters,
    omega_body: [f64; 3],
) -> EulerParameters {
    half_transpose_mul(&g_matrix(e), omega_body)
}

/// The normalization constraint Φ(e) = eᵀe − 1 (zero on valid parameters).
pub fn normalization_residual(e: &EulerParameters) -> f64 {
    dot4(e, e) - 1.0
}

/// ∂Φ/∂e = 2 eᵀ, the Jacobian row of [`normalization_residual`].
pub fn normalization_jacobian(e: &EulerParameters) -> [f64; 4] {
    e.map(|x| 2.0 * x)
}

/// e / |e|, the nearest valid parameters; `None` for a zero or non-finite length.
pub fn normalize(e: &EulerParameters) -> Option<EulerParameters> {
    let n = dot4(e, e).sqrt();
    (n > 0.0 && n.is_finite()).then(|| e.map(|x| x / n))
}

/// The parameters of the rotation by `angle` radians about `axis` (normalized here):
/// e₀ = cos(θ/2), (e₁, e₂, e₃) = sin(θ/2) u. `None` when the axis has no direction.
pub fn from_axis_angle(axis: [f64; 3], angle: f64) -> Option<EulerParameters> {
    let u = normalize_axis(axis)?;
    let (s, c) = (0.5 * angle).sin_cos();
    Some([c, s * u[0], s * u[1], s * u[2]])
}

/// The parameters of a rotation matrix by Shepperd's method (J. Guidance and Control 1(3),
/// 1978): of 4e₀² = 1 + tr A and 4eₖ² = 1 + 2A_kk − tr A the largest is taken with a square
/// root (it is at least 1, so no cancellation and no singular rotation, 180° included) and the
/// other three parameters follow from sums and differences of off-diagonal entries divided by
/// it. Returned normalized, with e₀ ≥ 0 (of the pair ±e). `a` must be a rotation
/// ([`super::rotation::is_rotation`]) up to round-off.
pub fn from_rotation_matrix(a: &Mat3) -> EulerParameters {
    let trace = a[0][0] + a[1][1] + a[2][2];
    let pivot = |four_e_squared: f64| {
        let ek = 0.5 * four_e_squared.sqrt();
        (ek, 0.25 / ek)
    };
    let e = if trace >= a[0][0] && trace >= a[1][1] && trace >= a[2][2] {
        let (e0, f) = pivot(1.0 + trace);
        [
            e0,
            (a[2][1] - a[1][2]) * f,
            (a[0][2] - a[2][0]) * f,
            (a[1][0] - a[0][1]) * f,
        ]
    } else if a[0][0] >= a[1][1] && a[0][0] >= a[2][2] {
        let (e1, f) = pivot(1.0 + 2.0 * a[0][0] - trace);
        [
            (a[2][1] - a[1][2]) * f,
            e1,
            (a[0][1] + a[1][0]) * f,
            (a[0][2] + a[2][0]) * f,
        ]
    } else if a[1][1] >= a[2][2] {
        let (e2, f) = pivot(1.0 + 2.0 * a[1][1] - trace);
        [
            (a[0][2] - a[2][0]) * f,
            (a[0][1] + a[1][0]) * f,
            e2,
            (a[1][2] + a[2][1]) * f,
        ]
    } else {
        let (e3, f) = pivot(1.0 + 2.0 * a[2][2] - trace);
        [
            (a[1][0] - a[0][1]) * f,
            (a[0][2] + a[2][0]) * f,
            (a[1][2] + a[2][1]) * f,
            e3,
        ]
    };
    let sign = if e[0] < 0.0 { -1.0 } else { 1.0 };
    let n = sign * dot4(&e, &e).sqrt();
    e.map(|x| x / n)
}

fn dot4(a: &[f64; 4], b: &[f64; 4]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3]
}

/// ½ Mᵀ v for a 3×4 matrix M.
fn half_transpose_mul(m: &Mat3x4, v: [f64; 3]) -> [f64; 4] {
    std::array::from_fn(|k| 0.5 * (m[0][k] * v[0] + m[1][k] * v[1] + m[2][k] * v[2]))
}
