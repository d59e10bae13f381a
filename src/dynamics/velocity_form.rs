//! One-step methods in velocity form, one step at a time, for callers that own their operators
//! and step themselves: the augmented EKF's prediction ([`crate::estimate::filter`]), BDF1 as the
//! thesis (eq. 2.61, 8.22) or the trapezoidal rule.
//!
//! **BDF1** ([`bdf1_step`]): backward Euler on x = (q, q̇), q_k = q_{k−1} + Δt q̇_k and
//! M q̈_k + C q̇_k + K q_k = f_k with q̈_k = (q̇_k − q̇_{k−1})/Δt, solved for the velocity:
//!
//! ```text
//! S q̇_k = M q̇_{k−1} − Δt K q_{k−1} + Δt f_k,   S = M + Δt C + Δt² K,
//! q_k = q_{k−1} + Δt q̇_k,   q̈_k = (q̇_k − q̇_{k−1})/Δt.
//! ```
//!
//! The same method as [`super::integrators`]'s BDF1, which solves for q_k with S/Δt² (test
//! `velocity_form_equals_the_bdf1_integrator`); the velocity form suits the filter because its
//! transition Jacobian ∂q̇_k/∂x_{k−1} = S⁻¹ [−Δt K, M, …] (eq. 8.16) is a solve with the same
//! factored S. It damps a mode of frequency ω by ζ ≈ ω Δt / 2.
//!
//! **Trapezoidal rule** ([`trapezoidal_step`]; Newmark's average acceleration, γ = 1/2, β = 1/4,
//! no numerical damping): q_k = q_{k−1} + Δt/2 (q̇_{k−1} + q̇_k), q̇_k = q̇_{k−1} + Δt/2 (q̈_{k−1} +
//! q̈_k) with the equation of motion at k − 1 and at k. Substituting q_k and M q̈_k into the
//! second relation times M:
//!
//! ```text
//! S q̇_k = M (q̇_{k−1} + Δt/2 q̈_{k−1}) − Δt/2 K (q_{k−1} + Δt/2 q̇_{k−1}) + Δt/2 f_k,
//! S = M + Δt/2 C + Δt²/4 K,
//! q_k = q_{k−1} + Δt/2 (q̇_{k−1} + q̇_k),   q̈_k = 2 (q̇_k − q̇_{k−1})/Δt − q̈_{k−1}.
//! ```
//!
//! With M q̈_{k−1} = f_{k−1} − C q̇_{k−1} − K q_{k−1} the right-hand side is
//! (2M − S) q̇_{k−1} − Δt K q_{k−1} + Δt/2 (f_{k−1} + f_k): the transition Jacobian
//! ∂q̇_k/∂x_{k−1} = S⁻¹ [−Δt K, 2M − S, …] is again a solve with the factored S. q̈_{k−1} must
//! satisfy the equation of motion at k − 1 (the step keeps it so). For linear systems the rule
//! equals generalized-α with ρ∞ = 1 under a load linear in time (test
//! `velocity_form_equals_the_trapezoidal_integrator`).

/// Which matrix of M q̈ + C q̇ + K q = f a product uses.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Operator {
    Stiffness,
    Damping,
    Mass,
}

/// The operators of a step.
pub trait VelocityForm {
    /// out += scale · A x for A = M, C or K.
    fn add_product(&self, op: Operator, x: &[f64], out: &mut [f64], scale: f64);
    /// x ← S⁻¹ x with the effective matrix of the method stepped with, at the step's Δt:
    /// S = M + Δt C + Δt² K ([`bdf1_step`]) or M + Δt/2 C + Δt²/4 K ([`trapezoidal_step`]).
    fn solve_effective(&mut self, x: &mut [f64]);
}

/// One step from (q, q̇) = (q_{k−1}, q̇_{k−1}) under the force f_k: q, q̇ and q̈ ← step k;
/// `v_old` receives q̇_{k−1} and `rhs` is scratch (n each). Allocation-free.
#[allow(clippy::too_many_arguments)]
pub fn bdf1_step<O: VelocityForm>(
    ops: &mut O,
    dt: f64,
    force: &[f64],
    q: &mut [f64],
    v: &mut [f64],
    a: &mut [f64],
    v_old: &mut [f64],
    rhs: &mut [f64],
) {
    v_old.copy_from_slice(v);
    rhs.iter_mut().zip(force).for_each(|(r, f)| *r = dt * f);
    ops.add_product(Operator::Mass, v_old, rhs, 1.0);
    ops.add_product(Operator::Stiffness, q, rhs, -dt);
    ops.solve_effective(rhs);
    for (i, &vn) in rhs.iter().enumerate() {
        v[i] = vn;
        q[i] += dt * vn;
        a[i] = (vn - v_old[i]) / dt;
    }
}

/// One trapezoidal step from (q, q̇, q̈) = (q_{k−1}, q̇_{k−1}, q̈_{k−1}) (q̈ satisfying the
/// equation of motion) under the force f_k: q, q̇ and q̈ ← step k; `v_old` receives q̇_{k−1},
/// `rhs` and `work` are scratch (n each). Allocation-free.
#[allow(clippy::too_many_arguments)]
pub fn trapezoidal_step<O: VelocityForm>(
    ops: &mut O,
    dt: f64,
    force: &[f64],
    q: &mut [f64],
    v: &mut [f64],
    a: &mut [f64],
    v_old: &mut [f64],
    rhs: &mut [f64],
    work: &mut [f64],
) {
    let half = 0.5 * dt;
    v_old.copy_from_slice(v);
    rhs.iter_mut().zip(force).for_each(|(r, f)| *r = half * f);
    work.iter_mut()
        .zip(v_old.iter().zip(a.iter()))
        .for_each(|(w, (v, a))| *w = v + half * a);
    ops.add_product(Operator::Mass, work, rhs, 1.0);
    work.iter_mut()
        .zip(q.iter().zip(v_old.iter()))
        .for_each(|(w, (q, v))| *w = q + half * v);
    ops.add_product(Operator::Stiffness, work, rhs, -half);
    ops.solve_effective(rhs);
    for (i, &vn) in rhs.iter().enumerate() {
        v[i] = vn;
        q[i] += half * (v_old[i] + vn);
        a[i] = (vn - v_old[i]) / half - a[i];
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamics::integrators::{LinearSystem, Method, integrate};
    use faer::Mat;
    use faer::linalg::solvers::DenseSolveCore;

    struct Dense {
        m: Mat<f64>,
        c: Mat<f64>,
        k: Mat<f64>,
        s_inverse: Mat<f64>,
    }

    impl VelocityForm for Dense {
        fn add_product(&self, op: Operator, x: &[f64], out: &mut [f64], scale: f64) {
            let a = match op {
                Operator::Stiffness => &self.k,
                Operator::Damping => &self.c,
                Operator::Mass => &self.m,
            };
            for (i, o) in out.iter_mut().enumerate() {
                *o += scale * (0..x.len()).map(|j| a[(i, j)] * x[j]).sum::<f64>();
            }
        }
        fn solve_effective(&mut self, x: &mut [f64]) {
            let y: Vec<f64> = (0..x.len())
                .map(|i| (0..x.len()).map(|j| self.s_inverse[(i, j)] * x[j]).sum())
                .collect();
            x.copy_from_slice(&y);
        }
    }

    /// Velocity-form steps of `method` against [`integrate`] with `reference` on a damped 2-DOF
    /// system under `load`, 300 steps of 1 ms: q, q̇ and q̈ agree to round-off (1e-12 of the
    /// largest q, divided by Δt for q̇ and Δt² for q̈).
    fn equals_the_integrator(
        reference: Method,
        method: fn(&mut Dense, f64, &[f64], [&mut [f64]; 6]),
        effective: [f64; 2],
        load: fn(f64, &mut [f64]),
    ) {
        let m = Mat::from_fn(2, 2, |i, j| [[2.0, 0.1], [0.1, 1.0]][i][j]);
        let k = Mat::from_fn(2, 2, |i, j| [[3e4, -1e4], [-1e4, 1e4]][i][j]);
        let c = Mat::from_fn(2, 2, |i, j| 0.8 * m[(i, j)] + 2e-4 * k[(i, j)]);
        let dt = 1e-3;
        let [c_scale, k_scale] = effective.map(|e| e * dt);
        let s = Mat::from_fn(2, 2, |i, j| {
            m[(i, j)] + c_scale * c[(i, j)] + c_scale * k_scale * k[(i, j)]
        });
        let (q0, v0) = ([1e-3, -2e-3], [0.3, 0.1]);
        let sys = LinearSystem {
            mass: m.as_ref(),
            damping: c.as_ref(),
            stiffness: k.as_ref(),
        };
        let mut expected_states = Vec::new();
        integrate(sys, reference, dt, 300, &q0, &v0, load, |st| {
            expected_states.push([st.q.to_vec(), st.v.to_vec(), st.a.to_vec()])
        })
        .unwrap();
        let scale = expected_states
            .iter()
            .flat_map(|r| r[0].iter())
            .fold(0.0_f64, |m, q| m.max(q.abs()));
        let mut ops = Dense {
            s_inverse: s.partial_piv_lu().inverse(),
            m,
            c,
            k,
        };
        let (mut q, mut v) = (q0.to_vec(), v0.to_vec());
        let mut a = expected_states[0][2].clone();
        let (mut v_old, mut rhs, mut work, mut f) =
            (vec![0.0; 2], vec![0.0; 2], vec![0.0; 2], vec![0.0; 2]);
        for (step, expected) in expected_states.iter().enumerate().skip(1) {
            load(step as f64 * dt, &mut f);
            method(
                &mut ops,
                dt,
                &f,
                [&mut q, &mut v, &mut a, &mut v_old, &mut rhs, &mut work],
            );
            for (got, (want, bound)) in
                [&q, &v, &a]
                    .iter()
                    .zip(expected.iter().zip([scale, scale / dt, scale / (dt * dt)]))
            {
                for (x, y) in got.iter().zip(want) {
                    assert!(
                        (x - y).abs() <= 1e-12 * bound,
                        "{reference:?} step {step}: {got:?} vs {want:?}"
                    );
                }
            }
        }
    }

    /// BDF1 under a sine load.
    #[test]
    fn velocity_form_equals_the_bdf1_integrator() {
        equals_the_integrator(
            Method::Bdf1,
            |ops, dt, f, [q, v, a, v_old, rhs, _]| bdf1_step(ops, dt, f, q, v, a, v_old, rhs),
            [1.0, 1.0],
            |t, f| {
                f[0] = 3.0 * (40.0 * t).sin();
                f[1] = -(40.0 * t).sin();
            },
        );
    }

    /// The trapezoidal rule against generalized-α with ρ∞ = 1 (α_m = α_f = 1/2: the average of
    /// the equations of motion at k − 1 and k, the trapezoidal rule for a linear system) under a
    /// load linear in time, where generalized-α's load at t_k − Δt/2 is the average of the two.
    #[test]
    fn velocity_form_equals_the_trapezoidal_integrator() {
        equals_the_integrator(
            Method::GeneralizedAlpha { rho_inf: 1.0 },
            |ops, dt, f, [q, v, a, v_old, rhs, work]| {
                trapezoidal_step(ops, dt, f, q, v, a, v_old, rhs, work)
            },
            [0.5, 0.5],
            |t, f| {
                f[0] = 3.0 + 400.0 * t;
                f[1] = -1.0 - 150.0 * t;
            },
        );
    }
}
