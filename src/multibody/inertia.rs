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
use crate::geometry::vec3;
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

/// target += s m, entry by entry over the nine entries in a row (vectorizable).
fn add_scaled(target: &mut Mat3, s: f64, m: &Mat3) {
    for (t, x) in target.as_flattened_mut().iter_mut().zip(m.as_flattened()) {
        *t += s * x;
    }
}

fn scaled_sum(terms: impl Iterator<Item = (f64, Mat3)>) -> Mat3 {
    let mut out = [[0.0; 3]; 3];
    for (s, m) in terms {
        add_scaled(&mut out, s, &m);
    }
    out
}

/// The configuration-dependent moments of one body at (e, q_f) (module docs), built once per
/// evaluation and shared by the mass matrix, the quadratic velocity vector, its rate Jacobian
/// and the gravity force.
pub struct Configuration {
    a: Mat3,
    partials: [Mat3; 4],
    /// S = Σ m ū
    first: [f64; 3],
    /// Π = Σ m ū ūᵀ
    second: Mat3,
    /// Tₖ = Σ m ψₖ ūᵀ
    mixed: Vec<Mat3>,
    /// Rₖ = Σₗ q̇ₗ Σ m ψₖ ψₗᵀ at the rates given to [`Configuration::moving`] (empty from
    /// [`Configuration::new`]).
    rate_moments: Vec<Mat3>,
}

impl Configuration {
    /// The moments at (e, q_f).
    pub fn new(inv: &MassInvariants, e: &[f64; 4], qf: &[f64]) -> Self {
        Self::build(inv, e, qf, None)
    }

    /// The moments at (e, q_f) and the rate moments Rₖ at q̇_f that
    /// [`Configuration::quadratic_velocity`] needs, both from one pass over the n² modal
    /// moments Σ m ψₖ ψₗᵀ (the largest data of a flexible body: 9 n² numbers).
    pub fn moving(inv: &MassInvariants, e: &[f64; 4], qf: &[f64], qf_dot: &[f64]) -> Self {
        Self::build(inv, e, qf, Some(qf_dot))
    }

    fn build(inv: &MassInvariants, e: &[f64; 4], qf: &[f64], qf_dot: Option<&[f64]>) -> Self {
        let n = inv.modes();
        let mut first = inv.first;
        for (k, psi) in inv.first_modal.iter().enumerate() {
            for i in 0..3 {
                first[i] += qf[k] * psi[i];
            }
        }
        let mut mixed = Vec::with_capacity(n);
        let mut rate_moments = Vec::with_capacity(if qf_dot.is_some() { n } else { 0 });
        for k in 0..n {
            let row = inv.second_modal[k * n..(k + 1) * n]
                .as_flattened()
                .as_flattened();
            let mut t = mat3::transpose(&inv.second_mixed[k]);
            let t_flat = t.as_flattened_mut();
            match qf_dot {
                Some(rates) => {
                    let mut r = [[0.0; 3]; 3];
                    contract_two(row, qf, rates, t_flat, r.as_flattened_mut());
                    rate_moments.push(r);
                }
                None => contract_two(row, qf, &[], t_flat, &mut []),
            }
            mixed.push(t);
        }
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
            rate_moments,
        }
    }

    /// The body mass matrix (7 + n square) into `out`; `modal_mass` is M_ff.
    pub fn mass_matrix(
        &self,
        inv: &MassInvariants,
        modal_mass: MatRef<'_, f64>,
        mut out: MatMut<'_, f64>,
    ) {
        let n = inv.modes();
        out.fill(0.0);
        for i in 0..3 {
            out[(i, i)] = inv.mass;
        }
        let mut set = |i: usize, j: usize, x: f64| {
            out[(i, j)] = x;
            out[(j, i)] = x;
        };
        for a in 0..4 {
            let column = mat3::mul_vec(&self.partials[a], self.first);
            for (i, x) in column.into_iter().enumerate() {
                set(i, 3 + a, x);
            }
            for b in a..4 {
                let ab = mat3::mul(&self.partials[b], &self.second);
                set(3 + a, 3 + b, frobenius(&self.partials[a], &ab));
            }
            // tr(A,ₐᵀ A Tₖ) = tr((Aᵀ A,ₐ)ᵀ Tₖ)
            let at_partial = mat3::mul(&mat3::transpose(&self.a), &self.partials[a]);
            for k in 0..n {
                set(3 + a, 7 + k, frobenius(&at_partial, &self.mixed[k]));
            }
        }
        for k in 0..n {
            let column = mat3::mul_vec(&self.a, inv.first_modal[k]);
            for (i, x) in column.into_iter().enumerate() {
                set(i, 7 + k, x);
            }
            for l in 0..n {
                set(7 + k, 7 + l, modal_mass[(k, l)]);
            }
        }
    }

    /// The product M w of the body mass matrix ([`Configuration::mass_matrix`]) with a vector
    /// w = (w_r, w_e, w_f) of 7 + n entries into `out`, block by block from the moments
    /// without forming M: O(n²) for M_ff w_f and O(n) for the rest.
    pub fn mass_product(
        &self,
        inv: &MassInvariants,
        modal_mass: MatRef<'_, f64>,
        w: &[f64],
        out: &mut [f64],
    ) {
        let n = inv.modes();
        let (w_r, w_e, w_f) = (&w[..3], &w[3..7], &w[7..]);
        // M_Rf w_f = A M̂₂ w_f and M_RΘ w_e = Σₐ wₐ A,ₐ S
        let translation = mat3::mul_vec(&self.a, modal_rate(inv, w_f));
        let mut first_columns = [[0.0; 3]; 4];
        for (a, column) in first_columns.iter_mut().enumerate() {
            *column = mat3::mul_vec(&self.partials[a], self.first);
        }
        for i in 0..3 {
            out[i] = inv.mass * w_r[i]
                + translation[i]
                + (0..4).map(|a| first_columns[a][i] * w_e[a]).sum::<f64>();
        }
        // rows Θ: M_ΘR w_r + M_ΘΘ w_e + M_Θf w_f, with M_Θf[a, k] = tr((Aᵀ A,ₐ)ᵀ Tₖ) and
        // Σₖ tr(Xᵀ Tₖ) w_fk = tr(Xᵀ Σₖ w_fk Tₖ)
        let mixed_sum = scaled_sum((0..n).map(|k| (w_f[k], self.mixed[k])));
        let at = mat3::transpose(&self.a);
        // M_ΘΘ w_e = (tr(A,ₐᵀ Σ_b w_b A,_b Π))ₐ
        let rotation_rate = mat3::mul(
            &scaled_sum((0..4).map(|b| (w_e[b], self.partials[b]))),
            &self.second,
        );
        let mut at_partials = [[[0.0; 3]; 3]; 4];
        for a in 0..4 {
            at_partials[a] = mat3::mul(&at, &self.partials[a]);
            let rotation = frobenius(&self.partials[a], &rotation_rate);
            out[3 + a] = vec3::dot(first_columns[a], [w_r[0], w_r[1], w_r[2]])
                + rotation
                + frobenius(&at_partials[a], &mixed_sum);
        }
        // rows f: M_fR w_r + M_fΘ w_e + M_ff w_f, with (A ψₖ)ᵀ w_r = ψₖ · (Aᵀ w_r)
        let body_w_r = mat3::mul_vec(&at, [w_r[0], w_r[1], w_r[2]]);
        let rotation_weight = scaled_sum((0..4).map(|a| (w_e[a], at_partials[a])));
        for k in 0..n {
            out[7 + k] = vec3::dot(inv.first_modal[k], body_w_r)
                + frobenius(&rotation_weight, &self.mixed[k]);
        }
        for (l, &wl) in w_f.iter().enumerate() {
            for (o, mkl) in out[7..7 + n].iter_mut().zip(modal_mass.col(l).iter()) {
                *o += mkl * wl;
            }
        }
    }

    /// The quadratic velocity vector f_v (eq. 2.47, 4.9) at the rates (ė, q̇_f) into `out`
    /// (7 + n); q̇_f must be the rates given to [`Configuration::moving`] when the moments
    /// were built by it.
    pub fn quadratic_velocity(
        &self,
        inv: &MassInvariants,
        e_dot: &[f64; 4],
        qf_dot: &[f64],
        out: &mut [f64],
    ) {
        let n = inv.modes();
        let a_of_rate = rotation_matrix(e_dot);
        let a_dot = scaled_sum((0..4).map(|a| (e_dot[a], self.partials[a])));
        // Σ m γ = 2 A(ė) S + 2 Ȧ M̂₂ q̇_f
        let g1 = mat3::mul_vec(&a_of_rate, self.first);
        let g2 = mat3::mul_vec(&a_dot, modal_rate(inv, qf_dot));
        for i in 0..3 {
            out[i] = -2.0 * (g1[i] + g2[i]);
        }
        // Σ m γ ūᵀ = 2 A(ė) Π + 2 Ȧ W,  W = Σ m (Ψ q̇_f) ūᵀ = Σₖ q̇ₖ Tₖ
        let w = scaled_sum((0..n).map(|k| (qf_dot[k], self.mixed[k])));
        let mut gu = mat3::mul(&a_of_rate, &self.second);
        add_scaled(&mut gu, 1.0, &mat3::mul(&a_dot, &w));
        for a in 0..4 {
            out[3 + a] = -2.0 * frobenius(&self.partials[a], &gu);
        }
        // Σ m γ ψₖᵀ = 2 A(ė) Tₖᵀ + 2 Ȧ Rₖᵀ,  Rₖ = Σₗ q̇ₗ Σ m ψₖ ψₗᵀ, and its product with A:
        // tr(Aᵀ (A(ė) Tₖᵀ + Ȧ Rₖᵀ)) = tr((Aᵀ A(ė)) Tₖᵀ) + tr((Aᵀ Ȧ) Rₖᵀ)
        let at = mat3::transpose(&self.a);
        let (at_rate, at_dot) = (mat3::mul(&at, &a_of_rate), mat3::mul(&at, &a_dot));
        let computed;
        let rate_moments = if self.rate_moments.len() == n {
            &self.rate_moments
        } else {
            computed = (0..n)
                .map(|k| {
                    scaled_sum(
                        qf_dot
                            .iter()
                            .zip(&inv.second_modal[k * n..(k + 1) * n])
                            .map(|(&r, s)| (r, *s)),
                    )
                })
                .collect::<Vec<Mat3>>();
            &computed
        };
        for (k, r) in rate_moments.iter().enumerate() {
            out[7 + k] = -2.0 * (frobenius(&at_rate, &self.mixed[k]) + frobenius(&at_dot, r));
        }
    }

    /// ∂f_v/∂(ė, q̇_f) into the columns 3.. of `out` ((7 + n) square; columns 0..3 are zero,
    /// f_v does not depend on ṙ), in closed form from the terms of
    /// [`Configuration::quadratic_velocity`]: with A(ė) homogeneous quadratic,
    /// ∂A(ė)/∂ė_b = A,_b(ė), and Ȧ = Σₐ ėₐ A,ₐ linear, ∂Ȧ/∂ė_b = A,_b, so
    ///
    /// ```text
    /// ∂/∂ė_b:  −2 (A,_b(ė) S + A,_b M̂₂ q̇_f),  −2 tr(A,ₐᵀ (A,_b(ė) Π + A,_b W)),  −2 tr(Aᵀ (A,_b(ė) Tₖᵀ + A,_b Nₖ))
    /// ∂/∂q̇ₗ:   −2 Ȧ ψₗ,                       −2 tr(A,ₐᵀ Ȧ Tₗ),                  −2 tr(Aᵀ Ȧ Σ m ψₗ ψₖᵀ)
    /// ```
    ///
    /// (rows r, e, q_f); O(n²) per body.
    pub fn quadratic_velocity_rate_jacobian(
        &self,
        inv: &MassInvariants,
        e_dot: &[f64; 4],
        qf_dot: &[f64],
        mut out: MatMut<'_, f64>,
    ) {
        let n = inv.modes();
        out.fill(0.0);
        let rate_partials = rotation_partials(e_dot);
        let a_dot = scaled_sum((0..4).map(|a| (e_dot[a], self.partials[a])));
        let rate = modal_rate(inv, qf_dot);
        let w = scaled_sum((0..n).map(|k| (qf_dot[k], self.mixed[k])));
        let moments: Vec<Mat3> = (0..n).map(|k| modal_rate_moment(inv, qf_dot, k)).collect();
        for (b, rate_partial) in rate_partials.iter().enumerate() {
            let column = 3 + b;
            let t1 = mat3::mul_vec(rate_partial, self.first);
            let t2 = mat3::mul_vec(&self.partials[b], rate);
            for i in 0..3 {
                out[(i, column)] = -2.0 * (t1[i] + t2[i]);
            }
            let mut x = mat3::mul(rate_partial, &self.second);
            add_scaled(&mut x, 1.0, &mat3::mul(&self.partials[b], &w));
            for a in 0..4 {
                out[(3 + a, column)] = -2.0 * frobenius(&self.partials[a], &x);
            }
            for k in 0..n {
                let mut x = mat3::mul(rate_partial, &mat3::transpose(&self.mixed[k]));
                add_scaled(&mut x, 1.0, &mat3::mul(&self.partials[b], &moments[k]));
                out[(7 + k, column)] = -2.0 * frobenius(&self.a, &x);
            }
        }
        // tr(Aᵀ Ȧ N) = tr((Ȧᵀ A)ᵀ N)
        let a_dot_t_a = mat3::mul(&mat3::transpose(&a_dot), &self.a);
        for l in 0..n {
            let column = 7 + l;
            let t = mat3::mul_vec(&a_dot, inv.first_modal[l]);
            for i in 0..3 {
                out[(i, column)] = -2.0 * t[i];
            }
            let x = mat3::mul(&a_dot, &self.mixed[l]);
            for a in 0..4 {
                out[(3 + a, column)] = -2.0 * frobenius(&self.partials[a], &x);
            }
            for k in 0..n {
                out[(7 + k, column)] = -2.0 * frobenius(&a_dot_t_a, &inv.second_modal[l * n + k]);
            }
        }
    }

    /// The generalized gravity force Σⱼ mⱼ Lⱼᵀ g into `out` (7 + n).
    pub fn gravity_force(&self, inv: &MassInvariants, gravity: [f64; 3], out: &mut [f64]) {
        for i in 0..3 {
            out[i] = inv.mass * gravity[i];
        }
        for a in 0..4 {
            out[3 + a] = vec3::dot(gravity, mat3::mul_vec(&self.partials[a], self.first));
        }
        for (k, psi) in inv.first_modal.iter().enumerate() {
            out[7 + k] = vec3::dot(gravity, mat3::mul_vec(&self.a, *psi));
        }
    }
}

/// t += Σₗ xₗ sₗ and r += Σₗ yₗ sₗ over the 3 × 3 blocks sₗ (9 numbers each, one after the
/// other in `blocks`); `y` and `r` may be empty. Each entry is summed over l in order; the
/// second sum reads the blocks again while they are in the cache.
fn contract_two(blocks: &[f64], x: &[f64], y: &[f64], t: &mut [f64], r: &mut [f64]) {
    for (out, weights) in [(t, x), (r, y)] {
        let mut acc = [0.0; 9];
        for (s, &wl) in blocks.chunks_exact(9).zip(weights) {
            for c in 0..9 {
                acc[c] += wl * s[c];
            }
        }
        for (o, a) in out.iter_mut().zip(acc) {
            *o += a;
        }
    }
}

/// M̂₂ q̇_f = Σₖ q̇ₖ Σ m ψₖ.
fn modal_rate(inv: &MassInvariants, qf_dot: &[f64]) -> [f64; 3] {
    let mut rate = [0.0; 3];
    for (k, psi) in inv.first_modal.iter().enumerate() {
        for i in 0..3 {
            rate[i] += qf_dot[k] * psi[i];
        }
    }
    rate
}

/// Nₖ = Σₗ q̇ₗ Σ m ψₗ ψₖᵀ.
fn modal_rate_moment(inv: &MassInvariants, qf_dot: &[f64], k: usize) -> Mat3 {
    let n = inv.modes();
    let mut moment = [[0.0; 3]; 3];
    for (l, &rate) in qf_dot.iter().enumerate() {
        add_scaled(&mut moment, rate, &inv.second_modal[l * n + k]);
    }
    moment
}

/// The body mass matrix (7 + n square) at (e, q_f) into `out`; `modal_mass` is M_ff.
pub fn mass_matrix(
    inv: &MassInvariants,
    modal_mass: MatRef<'_, f64>,
    e: &[f64; 4],
    qf: &[f64],
    out: MatMut<'_, f64>,
) {
    Configuration::new(inv, e, qf).mass_matrix(inv, modal_mass, out);
}

/// The quadratic velocity vector f_v (eq. 2.47, 4.9) at (e, q_f, ė, q̇_f) into `out` (7 + n).
pub fn quadratic_velocity(
    inv: &MassInvariants,
    e: &[f64; 4],
    qf: &[f64],
    e_dot: &[f64; 4],
    qf_dot: &[f64],
    out: &mut [f64],
) {
    Configuration::new(inv, e, qf).quadratic_velocity(inv, e_dot, qf_dot, out);
}

/// ∂f_v/∂(ė, q̇_f) at (e, q_f, ė, q̇_f) ([`Configuration::quadratic_velocity_rate_jacobian`]).
pub fn quadratic_velocity_rate_jacobian(
    inv: &MassInvariants,
    e: &[f64; 4],
    qf: &[f64],
    e_dot: &[f64; 4],
    qf_dot: &[f64],
    out: MatMut<'_, f64>,
) {
    Configuration::new(inv, e, qf).quadratic_velocity_rate_jacobian(inv, e_dot, qf_dot, out);
}

/// The generalized gravity force Σⱼ mⱼ Lⱼᵀ g at (e, q_f) into `out` (7 + n).
pub fn gravity_force(
    inv: &MassInvariants,
    e: &[f64; 4],
    qf: &[f64],
    gravity: [f64; 3],
    out: &mut [f64],
) {
    Configuration::new(inv, e, qf).gravity_force(inv, gravity, out);
}
