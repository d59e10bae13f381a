//! The transition Jacobian of the AMANDA-EKF's prediction (thesis eq. 9.5–9.8, 9.17): the
//! derivative of one GGL–BDF1 step's result z_k = (q_k, v_k) with respect to the previous
//! estimate z_{k−1} and the (scaled) parameters θ, from the projected equations of motion
//! (eq. 9.3) discretized with BDF1 (eq. 9.6), with V from [`super::nullspace`]:
//!
//! ```text
//! G₁ = Vᵀ W⁻¹ (q_k − q_{k−1} − h v_k)                          = 0   (n − m)
//! G₂ = Vᵀ (M(q_k, θ) (v_k − v_{k−1}) − h f(q_k, v_k, t_k, θ))  = 0   (n − m)
//! G₃ = Φ_q v_k + Φ_t                                          = 0   (m)
//! G₄ = Φ(q_k, t_k)                                             = 0   (m)
//! ```
//!
//! W is the metric of the step's position correction q_k − q_{k−1} − h v_k = W Φ_qᵀ μ
//! ([`crate::multibody::correction`]; constant in q). The GGL step's solution satisfies them
//! (Vᵀ Φ_qᵀ = 0 removes the multipliers), and they are
//! 2n equations in z_k, so the step's derivatives follow by implicit differentiation:
//! J = −(∂G/∂z_k)⁻¹ [∂G/∂z_{k−1}  ∂G/∂θ] (eq. 9.8, which writes ∂G/∂z_k through g_d's two
//! arguments). The rows of ∂G/∂z_k:
//!
//! ```text
//! Vᵀ [W⁻¹ − Σ μ̂ₖ∇²Φₖ,  −h W⁻¹]            μ̂ = Φ_d⁻ᵀ (W⁻¹ (q_k − q_{k−1} − h v_k))_d
//! Vᵀ [∂r₂/∂q − Σ λ̂ₖ∇²Φₖ,  M − h ∂f/∂v]     λ̂ = Φ_d⁻ᵀ (r₂)_d, r₂ the bracket of G₂
//! [∂(Φ_q v + Φ_t)/∂q,  Φ_q]
//! [Φ_q,  0]
//! ```
//!
//! (the λ̂ and μ̂ terms are the nullspace's derivative, [`super::nullspace`]); ∂G/∂z_{k−1} has
//! −Vᵀ W⁻¹ and −Vᵀ M(q_k) in G₁'s q and G₂'s v columns; ∂G₂/∂θⱼ = Vᵀ(∂M/∂θⱼ w − h ∂f/∂θⱼ),
//! w = v_k − v_{k−1}, from the exact rates of [`super::parameters`]; an unknown input's
//! ∂G₂/∂uⱼ = −h Vᵀ Qⱼ(q_k), Qⱼ its unit generalized force ([`super::inputs`]). W depends on θ through
//! the bodies' M_ff and K_ff, but G₁'s θ-derivative Vᵀ (∂W⁻¹/∂θ) W Φ_qᵀ μ is of the size of the
//! step's multiplier μ (the scheme's drift, zero for the exact solution) and is left out.
//!
//! ∂f/∂v is the system's exact rate Jacobian (C, ∂f_v/∂q̇, the dampers'); ∂r₂/∂q — the
//! q-derivatives of M(q) w, f_v, gravity, K q, springs and loads, for which the multibody
//! module has no exact form — is taken by central differences of
//! [`crate::multibody::System::forces_and_momentum`] with steps 10⁻⁶ (1 + |qⱼ|), one coordinate of every body
//! at a time when no spring couples bodies: those terms are polynomials of low degree in q, so
//! the differences are exact to round-off and O(10⁻¹²) truncation.

use faer::linalg::solvers::Solve;
use faer::{Mat, MatRef};

use super::nullspace::Nullspace;
use crate::multibody::{EomTerms, Ggl, correction};

/// Relative step of the central differences of ∂r₂/∂q.
const STEP: f64 = 1e-6;

/// J of one step (module docs): the state block ∂z_k/∂z_{k−1} (2n × 2n), the input block
/// ∂z_k/∂u (2n × n_u) and the parameter block ∂z_k/∂θ (2n × n_θ).
#[derive(Debug, Clone)]
pub struct Transition {
    pub states: Mat<f64>,
    pub inputs: Mat<f64>,
    pub parameters: Mat<f64>,
}

/// r₂ = M(q) w − h f(q, v, t) into `out`.
fn momentum_residual(ggl: &Ggl, q: &[f64], v: &[f64], w: &[f64], out: &mut [f64]) {
    let n = q.len();
    let (mut force, mut momentum) = (vec![0.0; n], vec![0.0; n]);
    ggl.system.forces_and_momentum(
        &ggl.equations,
        q,
        v,
        ggl.time,
        &mut force,
        Some((w, &mut momentum)),
        None,
    );
    for i in 0..n {
        out[i] = momentum[i] - ggl.step_size * force[i];
    }
}

/// The columns of ∂r₂/∂q differenced together, each with the rows it can change. Without
/// spring-dampers every term of r₂ is a body's own (inertia, gravity, K q_f, C q̇_f, and point
/// loads at its markers), so the j-th coordinate of every body shares one evaluation (the
/// largest body's size pairs of evaluations instead of n); a spring couples two bodies and
/// then each column is differenced alone over all rows.
fn column_groups(ggl: &Ggl) -> Vec<Vec<(usize, std::ops::Range<usize>)>> {
    let slices = ggl.system.layout.slices();
    let n = ggl.system.size();
    if !ggl.equations.springs.is_empty() {
        return (0..n).map(|j| vec![(j, 0..n)]).collect();
    }
    let largest = slices.iter().map(|s| s.len()).max().unwrap_or(0);
    (0..largest)
        .map(|k| {
            (slices.iter().filter(|s| s.len() > k))
                .map(|s| (s.offset + k, s.offset..s.offset + s.len()))
                .collect()
        })
        .collect()
}

/// J of the step that took `ggl` from `previous` = (q_{k−1}, v_{k−1}) to its current state
/// (time t_k, step h), with the nullspace at q_k, the unknown inputs' unit generalized forces
/// Qⱼ(q_k) (`loads`) and the rates ∂terms/∂θⱼ at (q_k, v_k). `None` if ∂G/∂z_k is singular.
pub fn transition(
    ggl: &Ggl,
    previous: (&[f64], &[f64]),
    nullspace: &Nullspace,
    loads: &[Vec<f64>],
    rates: &[EomTerms],
) -> Option<Transition> {
    let (q, v, t, h) = (&ggl.q[..], &ggl.v[..], ggl.time, ggl.step_size);
    let (layout, c) = (&ggl.system.layout, &ggl.equations.constraints);
    let (n, m) = (q.len(), c.len());
    let r = n - m;
    let w: Vec<f64> = v.iter().zip(previous.1).map(|(a, b)| a - b).collect();
    let r1: Vec<f64> = (0..n).map(|i| q[i] - previous.0[i] - h * v[i]).collect();
    let mut r2 = vec![0.0; n];
    momentum_residual(ggl, q, v, &w, &mut r2);
    let inverse_weight = correction::inverse_weight(&ggl.system, ggl.settings.correction, h, h);
    let weighted_r1: Vec<f64> = (0..n)
        .map(|i| (0..n).map(|j| inverse_weight[(i, j)] * r1[j]).sum())
        .collect();
    let (mu, lambda) = (
        nullspace.multiplier(&weighted_r1),
        nullspace.multiplier(&r2),
    );
    // full-space blocks before projection: G₁'s q block and G₂'s q and v blocks
    let mut g1q = inverse_weight.clone();
    c.add_weighted_hessian(layout, q, t, &mu, -1.0, g1q.as_mut());
    let mut g2q = Mat::<f64>::zeros(n, n);
    let (mut plus, mut minus, mut shifted) = (vec![0.0; n], vec![0.0; n], q.to_vec());
    for group in column_groups(ggl) {
        let steps: Vec<f64> = group
            .iter()
            .map(|(j, _)| STEP * (1.0 + q[*j].abs()))
            .collect();
        for sign in [1.0, -1.0] {
            for ((j, _), step) in group.iter().zip(&steps) {
                shifted[*j] = q[*j] + sign * step;
            }
            let out = if sign > 0.0 { &mut plus } else { &mut minus };
            momentum_residual(ggl, &shifted, v, &w, out);
        }
        for ((j, rows), step) in group.iter().zip(&steps) {
            shifted[*j] = q[*j];
            for i in rows.clone() {
                g2q[(i, *j)] = (plus[i] - minus[i]) / (2.0 * step);
            }
        }
    }
    let mut velocity_q = Mat::<f64>::zeros(m, n);
    c.velocity_jacobian_and_weighted_hessian(
        layout,
        q,
        v,
        t,
        &lambda,
        -1.0,
        velocity_q.as_mut(),
        g2q.as_mut(),
    );
    let (mut dq, mut g2v) = (Mat::<f64>::zeros(n, n), Mat::<f64>::zeros(n, n));
    let mut force = vec![0.0; n];
    ggl.system.applied_forces(
        &ggl.equations,
        q,
        v,
        t,
        &mut force,
        Some((dq.as_mut(), g2v.as_mut(), h)),
    );
    let mut mass = Mat::<f64>::zeros(n, n);
    ggl.system.mass_matrix(q, mass.as_mut());
    g2v += &mass;
    let mut phi_q = Mat::<f64>::zeros(m, n);
    c.jacobian(layout, q, t, phi_q.as_mut());
    let vt = nullspace.basis.transpose();
    let mut a = Mat::<f64>::zeros(2 * n, 2 * n);
    let mut put = |row: usize, col: usize, block: MatRef<'_, f64>| {
        a.as_mut()
            .submatrix_mut(row, col, block.nrows(), block.ncols())
            .copy_from(block);
    };
    put(0, 0, (vt * &g1q).as_ref());
    let vt_inverse_weight = vt * &inverse_weight;
    put(0, n, (&vt_inverse_weight * faer::Scale(-h)).as_ref());
    put(r, 0, (vt * &g2q).as_ref());
    put(r, n, (vt * &g2v).as_ref());
    put(2 * r, 0, velocity_q.as_ref());
    put(2 * r, n, phi_q.as_ref());
    put(2 * r + m, 0, phi_q.as_ref());
    // −[∂G/∂z_{k−1}  ∂G/∂u  ∂G/∂θ]
    let (nu, np) = (loads.len(), rates.len());
    let mut rhs = Mat::<f64>::zeros(2 * n, 2 * n + nu + np);
    rhs.as_mut()
        .submatrix_mut(0, 0, r, n)
        .copy_from(&vt_inverse_weight);
    rhs.as_mut().submatrix_mut(r, n, r, n).copy_from(vt * &mass);
    for (j, load) in loads.iter().enumerate() {
        let column = Mat::from_fn(n, 1, |i, _| h * load[i]);
        rhs.as_mut()
            .submatrix_mut(r, 2 * n + j, r, 1)
            .copy_from(vt * &column);
    }
    for (j, terms) in rates.iter().enumerate() {
        let dr2 = Mat::from_fn(n, 1, |i, _| {
            let dm_w: f64 = (0..n).map(|k| terms.mass[(i, k)] * w[k]).sum();
            let df = terms.quadratic_velocity[i] + terms.gravity[i]
                - terms.elastic[i]
                - terms.damping[i];
            -(dm_w - h * df)
        });
        rhs.as_mut()
            .submatrix_mut(r, 2 * n + nu + j, r, 1)
            .copy_from(vt * &dr2);
    }
    a.partial_piv_lu().solve_in_place(rhs.as_mut());
    if (0..rhs.ncols()).any(|j| rhs.col(j).iter().any(|x| !x.is_finite())) {
        return None;
    }
    Some(Transition {
        states: rhs.as_ref().submatrix(0, 0, 2 * n, 2 * n).to_owned(),
        inputs: rhs.as_ref().submatrix(0, 2 * n, 2 * n, nu).to_owned(),
        parameters: rhs.as_ref().submatrix(0, 2 * n + nu, 2 * n, np).to_owned(),
    })
}
