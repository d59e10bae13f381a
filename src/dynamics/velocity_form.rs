//! BDF1 (thesis eq. 2.61) in velocity form, one step at a time, for callers that own their
//! operators and step themselves: the augmented EKF's prediction (thesis eq. 8.22,
//! [`crate::estimate::filter`]).
//!
//! Backward Euler on x = (q, q̇), q_k = q_{k−1} + Δt q̇_k and M q̈_k + C q̇_k + K q_k = f_k with
//! q̈_k = (q̇_k − q̇_{k−1})/Δt, solved for the velocity:
//!
//! ```text
//! S q̇_k = M q̇_{k−1} − Δt K q_{k−1} + Δt f_k,   S = M + Δt C + Δt² K,
//! q_k = q_{k−1} + Δt q̇_k,   q̈_k = (q̇_k − q̇_{k−1})/Δt.
//! ```
//!
//! The same method as [`super::integrators`]'s BDF1, which solves for q_k with S/Δt² (test
//! `velocity_form_equals_the_bdf1_integrator`); the velocity form suits the filter because its
//! transition Jacobian ∂q̇_k/∂x_{k−1} = S⁻¹ [−Δt K, M, …] (eq. 8.16) is a solve with the same
//! factored S.

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
    /// x ← S⁻¹ x, S = M + Δt C + Δt² K at the step's Δt.
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

    /// A damped, loaded 2-DOF system: q, q̇ and q̈ of 300 velocity-form steps equal the BDF1
    /// integrator's to round-off (1e-12 of the largest q, divided by Δt for q̇ and Δt² for q̈).
    #[test]
    fn velocity_form_equals_the_bdf1_integrator() {
        let m = Mat::from_fn(2, 2, |i, j| [[2.0, 0.1], [0.1, 1.0]][i][j]);
        let k = Mat::from_fn(2, 2, |i, j| [[3e4, -1e4], [-1e4, 1e4]][i][j]);
        let c = Mat::from_fn(2, 2, |i, j| 0.8 * m[(i, j)] + 2e-4 * k[(i, j)]);
        let dt = 1e-3;
        let s = Mat::from_fn(2, 2, |i, j| {
            m[(i, j)] + dt * c[(i, j)] + dt * dt * k[(i, j)]
        });
        let load = |t: f64, f: &mut [f64]| {
            f[0] = 3.0 * (40.0 * t).sin();
            f[1] = -(40.0 * t).sin();
        };
        let (q0, v0) = ([1e-3, -2e-3], [0.3, 0.1]);
        let sys = LinearSystem {
            mass: m.as_ref(),
            damping: c.as_ref(),
            stiffness: k.as_ref(),
        };
        let mut reference = Vec::new();
        integrate(sys, Method::Bdf1, dt, 300, &q0, &v0, load, |st| {
            reference.push([st.q.to_vec(), st.v.to_vec(), st.a.to_vec()])
        })
        .unwrap();
        let scale = reference
            .iter()
            .flat_map(|r| r[0].iter())
            .fold(0.0_f64, |m, q| m.max(q.abs()));
        let mut ops = Dense {
            s_inverse: s.partial_piv_lu().inverse(),
            m,
            c,
            k,
        };
        let (mut q, mut v, mut a) = (q0.to_vec(), v0.to_vec(), vec![0.0; 2]);
        let (mut v_old, mut rhs, mut f) = (vec![0.0; 2], vec![0.0; 2], vec![0.0; 2]);
        for (step, expected) in reference.iter().enumerate().skip(1) {
            load(step as f64 * dt, &mut f);
            bdf1_step(
                &mut ops, dt, &f, &mut q, &mut v, &mut a, &mut v_old, &mut rhs,
            );
            for (got, (want, bound)) in
                [&q, &v, &a]
                    .iter()
                    .zip(expected.iter().zip([scale, scale / dt, scale / (dt * dt)]))
            {
                for (x, y) in got.iter().zip(want) {
                    assert!(
                        (x - y).abs() <= 1e-12 * bound,
                        "step {step}: {got:?} vs {want:?}"
                    );
                }
            }
        }
    }
}
