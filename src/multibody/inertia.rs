//! Inertia terms of one body from its mass moments ([`MassInvariants`]): the mass matrix
//! (eq. 2.49–2.50, A.5–A.9 with A.24–A.27), the quadratic velocity vector (eq. 2.47, 4.9) and
//! the generalized gravity force, all exact for the kinematics
//!
//! ```text
//! xⱼ(q) = r + A(e) ūⱼ,   ūⱼ = r₀ⱼ + Ψⱼ q_f,   Lⱼ = ∂xⱼ/∂q = [I, (A,ₐ ūⱼ)ₐ, A Ψⱼ]
//! ```
//!
//! with A(e) = E Gᵀ the homogeneous quadratic of eq. A.4 and A,ₐ = ∂A/∂eₐ (linear in e). The
//! mass matrix is M = Σⱼ mⱼ Lⱼᵀ Lⱼ and the quadratic velocity vector f_v = −Σⱼ mⱼ Lⱼᵀ γⱼ with
//! γⱼ = L̇ⱼ q̇ = 2 A(ė) ūⱼ + 2 Ȧ Ψⱼ q̇_f (since Ä = Σₐ ëₐ A,ₐ + 2 A(ė)); Lagrange's equations
//! of T = ½ q̇ᵀ M q̇ then read M q̈ = f_v + Q. Both sums reduce to the moments
//!
//! ```text
//! S = Σ m ū,   Π = Σ m ū ūᵀ,   Tₖ = Σ m ψₖ ūᵀ,
//! M_RΘ[:, a] = A,ₐ S,   M_Rf = A M̂₂,   M_ΘΘ[a, b] = tr(A,ₐᵀ A,_b Π),   M_Θf[a, k] = tr(A,ₐᵀ A Tₖ)
//! ```
//!
//! This is A.24–A.27 with the exact derivative of A(e) ū with respect to e: M_ΘΘ carries, in
//! addition to 4 Gᵀ D̂₂ G of A.26, the term 4 (Σ m ūᵀū) e eᵀ along the normalization
//! gradient (A.27 carries its Θf counterpart 2 e D̂₄). That term only changes the multiplier of
//! eᵀe = 1 and makes M positive definite. For a rigid body (no modes, frame at the centre of
//! mass) M_ΘΘ = 4 Gᵀ J G + 2 tr(J) e eᵀ (test `rigid_rotation_block_is_four_gt_j_g`). The flexible
//! block M_ff is the reduced model's; the velocity terms use the lumped moments.

use super::flexible::MassInvariants;
use crate::geometry::euler_parameters::{rotated_vector_jacobian, rotation_matrix};
use crate::geometry::mat3::{self, Mat3};
use faer::{MatMut, MatRef};

/// ∂A/∂eₐ at x for a = 0..3 (each linear in x); column i of the a-th matrix is
/// ∂(A e⁽ⁱ⁾)/∂eₐ with e⁽ⁱ⁾ the i-th unit vector.
pub fn rotation_partials(x: &[f64; 4]) -> [Mat3; 4] {
    let columns = [0, 1, 2].map(|i| {
        let mut unit = [0.0; 3];
        unit[i] = 1.0;
        rotated_vector_jacobian(x, unit)
    });
    std::array::from_fn(|a| std::array::from_fn(|r| std::array::from_fn(|c| columns[c][r][a])))
}

/// Σᵢⱼ Pᵢⱼ Qᵢⱼ = tr(Pᵀ Q).
fn frobenius(p: &Mat3, q: &Mat3) -> f64 {
    (0..3)
        .map(|i| (0..3).map(|j| p[i][j] * q[i][j]).sum::<f64>())
        .sum()
}

fn add_scaled(target: &mut Mat3, s: f64, m: &Mat3) {
    for i in 0..3 {
        for j in 0..3 {
            target[i][j] += s * m[i][j];
        }
    }
}

fn scaled_sum(terms: impl Iterator<Item = (f64, Mat3)>) -> Mat3 {
    let mut out = [[0.0; 3]; 3];
    for (s, m) in terms {
        add_scaled(&mut out, s, &m);
    }
    out
}

/// The configuration-dependent moments of one body at (e, q_f).
struct Configuration {
    a: Mat3,
    partials: [Mat3; 4],
    /// S = Σ m ū
    first: [f64; 3],
    /// Π = Σ m ū ūᵀ
    second: Mat3,
    /// Tₖ = Σ m ψₖ ūᵀ
    mixed: Vec<Mat3>,
}

impl Configuration {
    fn new(inv: &MassInvariants, e: &[f64; 4], qf: &[f64]) -> Self {
        let n = inv.modes();
        let mut first = inv.first;
        for (k, psi) in inv.first_modal.iter().enumerate() {
            for i in 0..3 {
                first[i] += qf[k] * psi[i];
            }
        }
        let mixed: Vec<Mat3> = (0..n)
            .map(|k| {
                let mut t = mat3::transpose(&inv.second_mixed[k]);
                for (l, &ql) in qf.iter().enumerate() {
                    add_scaled(&mut t, ql, &inv.second_modal[k * n + l]);
                }
                t
            })
            .collect();
        // Π = Σ m r₀r₀ᵀ + Σₖ qₖ (Σ m r₀ψₖᵀ + Tₖ), since Σₖ qₖ Tₖ holds Σₖ qₖ Σ m ψₖr₀ᵀ and
        // the quadratic part Σₖₗ qₖ qₗ Σ m ψₖψₗᵀ.
        let mut second = inv.second;
        for (k, &qk) in qf.iter().enumerate() {
            add_scaled(&mut second, qk, &inv.second_mixed[k]);
            add_scaled(&mut second, qk, &mixed[k]);
        }
        Self {
            a: rotation_matrix(e),
            partials: rotation_partials(e),
            first,
            second,
            mixed,
        }
    }
}

/// The body mass matrix (7 + n square) at (e, q_f) into `out`; `modal_mass` is M_ff.
pub fn mass_matrix(
    inv: &MassInvariants,
    modal_mass: MatRef<'_, f64>,
    e: &[f64; 4],
    qf: &[f64],
    mut out: MatMut<'_, f64>,
) {
    let n = inv.modes();
    let c = Configuration::new(inv, e, qf);
    out.fill(0.0);
    for i in 0..3 {
        out[(i, i)] = inv.mass;
    }
    let mut set = |i: usize, j: usize, x: f64| {
        out[(i, j)] = x;
        out[(j, i)] = x;
    };
    for a in 0..4 {
        let column = mat3::mul_vec(&c.partials[a], c.first);
        for (i, x) in column.into_iter().enumerate() {
            set(i, 3 + a, x);
        }
        for b in a..4 {
            let ab = mat3::mul(&c.partials[b], &c.second);
            set(3 + a, 3 + b, frobenius(&c.partials[a], &ab));
        }
        for k in 0..n {
            let at = mat3::mul(&c.a, &c.mixed[k]);
            set(3 + a, 7 + k, frobenius(&c.partials[a], &at));
        }
    }
    for k in 0..n {
        let column = mat3::mul_vec(&c.a, inv.first_modal[k]);
        for (i, x) in column.into_iter().enumerate() {
            set(i, 7 + k, x);
        }
        for l in 0..n {
            set(7 + k, 7 + l, modal_mass[(k, l)]);
        }
    }
}

/// The quadratic velocity vector f_v (eq. 2.47) at (e, q_f, ė, q̇_f) into `out` (7 + n).
pub fn quadratic_velocity(
    inv: &MassInvariants,
    e: &[f64; 4],
    qf: &[f64],
    e_dot: &[f64; 4],
    qf_dot: &[f64],
    out: &mut [f64],
) {
    let c = Configuration::new(inv, e, qf);
    quadratic_velocity_at(inv, &c, e_dot, qf_dot, out);
}

fn quadratic_velocity_at(
    inv: &MassInvariants,
    c: &Configuration,
    e_dot: &[f64; 4],
    qf_dot: &[f64],
    out: &mut [f64],
) {
    let n = inv.modes();
    let a_of_rate = rotation_matrix(e_dot);
    let a_dot = scaled_sum((0..4).map(|a| (e_dot[a], c.partials[a])));
    // Σ m γ = 2 A(ė) S + 2 Ȧ M̂₂ q̇_f
    let mut modal_rate = [0.0; 3];
    for (k, psi) in inv.first_modal.iter().enumerate() {
        for i in 0..3 {
            modal_rate[i] += qf_dot[k] * psi[i];
        }
    }
    let g1 = mat3::mul_vec(&a_of_rate, c.first);
    let g2 = mat3::mul_vec(&a_dot, modal_rate);
    for i in 0..3 {
        out[i] = -2.0 * (g1[i] + g2[i]);
    }
    // Σ m γ ūᵀ = 2 A(ė) Π + 2 Ȧ W,  W = Σ m (Ψ q̇_f) ūᵀ = Σₖ q̇ₖ Tₖ
    let w = scaled_sum((0..n).map(|k| (qf_dot[k], c.mixed[k])));
    let mut gu = mat3::mul(&a_of_rate, &c.second);
    add_scaled(&mut gu, 1.0, &mat3::mul(&a_dot, &w));
    for a in 0..4 {
        out[3 + a] = -2.0 * frobenius(&c.partials[a], &gu);
    }
    // Σ m γ ψₖᵀ = 2 A(ė) Tₖᵀ + 2 Ȧ Σₗ q̇ₗ Σ m ψₗ ψₖᵀ
    for k in 0..n {
        let modal = scaled_sum((0..n).map(|l| (qf_dot[l], inv.second_modal[l * n + k])));
        let mut gk = mat3::mul(&a_of_rate, &mat3::transpose(&c.mixed[k]));
        add_scaled(&mut gk, 1.0, &mat3::mul(&a_dot, &modal));
        out[7 + k] = -2.0 * frobenius(&c.a, &gk);
    }
}

/// ∂f_v/∂(ė, q̇_f) into the columns 3.. of `out` ((7 + n) square; column 0..3 stays zero, f_v
/// does not depend on ṙ). f_v is a quadratic form Q(v, v) of the rates, so column j is exactly
/// 2 Q(v, uⱼ) = (f_v(v + uⱼ) − f_v(v − uⱼ)) / 2 (polarization, no truncation error).
pub fn quadratic_velocity_rate_jacobian(
    inv: &MassInvariants,
    e: &[f64; 4],
    qf: &[f64],
    e_dot: &[f64; 4],
    qf_dot: &[f64],
    mut out: MatMut<'_, f64>,
) {
    let n = inv.modes();
    let c = Configuration::new(inv, e, qf);
    let mut plus = vec![0.0; 7 + n];
    let mut minus = vec![0.0; 7 + n];
    let mut rates: Vec<f64> = e_dot.iter().chain(qf_dot).copied().collect();
    out.fill(0.0);
    for j in 0..4 + n {
        let base = rates[j];
        for (sign, target) in [(1.0, &mut plus), (-1.0, &mut minus)] {
            rates[j] = base + sign;
            let ed = [rates[0], rates[1], rates[2], rates[3]];
            quadratic_velocity_at(inv, &c, &ed, &rates[4..], target);
        }
        rates[j] = base;
        for i in 0..7 + n {
            out[(i, 3 + j)] = 0.5 * (plus[i] - minus[i]);
        }
    }
}

/// The generalized gravity force Σⱼ mⱼ Lⱼᵀ g at (e, q_f) into `out` (7 + n).
pub fn gravity_force(
    inv: &MassInvariants,
    e: &[f64; 4],
    qf: &[f64],
    gravity: [f64; 3],
    out: &mut [f64],
) {
    let c = Configuration::new(inv, e, qf);
    for i in 0..3 {
        out[i] = inv.mass * gravity[i];
    }
    for a in 0..4 {
        out[3 + a] = crate::geometry::vec3::dot(gravity, mat3::mul_vec(&c.partials[a], c.first));
    }
    for (k, psi) in inv.first_modal.iter().enumerate() {
        out[7 + k] = crate::geometry::vec3::dot(gravity, mat3::mul_vec(&c.a, *psi));
    }
}
