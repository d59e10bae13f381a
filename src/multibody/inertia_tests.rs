//! The inertia kernel against direct nodal sums of a small synthetic flexible body (random
//! nodes, masses and basis rows): M(q) = Σⱼ mⱼ Lⱼᵀ Lⱼ with Lⱼ = ∂xⱼ/∂q, the quadratic
//! velocity vector against finite differences of the nodal kinetic energy (Lagrange:
//! f_v = ½ ∂(q̇ᵀ M q̇)/∂q − Ṁ q̇ with M = Σⱼ mⱼ Lⱼᵀ Lⱼ), the gravity force against Σⱼ mⱼ Lⱼᵀ g.

use super::flexible::{MassInvariants, NodalMass};
use super::inertia::*;
use crate::geometry::euler_parameters::{
    g_matrix, normalize, rotated_vector_jacobian, rotation_matrix,
};
use crate::geometry::mat3;
use crate::linalg::random::SplitMix64;
use faer::Mat;

const MODES: usize = 3;

fn synthetic_nodes(rng: &mut SplitMix64) -> Vec<NodalMass> {
    (0..6)
        .map(|_| NodalMass {
            mass: 0.5 + rng.unit(),
            position: [0.0; 3].map(|_| rng.symmetric()),
            modes: (0..MODES)
                .map(|_| [0.0; 3].map(|_| 0.3 * rng.symmetric()))
                .collect(),
        })
        .collect()
}

fn lumped_modal_mass(nodes: &[NodalMass]) -> Mat<f64> {
    Mat::from_fn(MODES, MODES, |k, l| {
        nodes
            .iter()
            .map(|n| n.mass * (0..3).map(|i| n.modes[k][i] * n.modes[l][i]).sum::<f64>())
            .sum()
    })
}

/// Lⱼ = ∂xⱼ/∂q (3 × (7 + n)) of node j at (e, q_f).
fn node_jacobian(node: &NodalMass, e: &[f64; 4], qf: &[f64]) -> Mat<f64> {
    let mut u = node.position;
    for (k, psi) in node.modes.iter().enumerate() {
        for i in 0..3 {
            u[i] += qf[k] * psi[i];
        }
    }
    let de = rotated_vector_jacobian(e, u);
    let a = rotation_matrix(e);
    Mat::from_fn(3, 7 + MODES, |i, j| match j {
        0..3 => f64::from(u8::from(i == j)),
        3..7 => de[i][j - 3],
        _ => mat3::mul_vec(&a, node.modes[j - 7])[i],
    })
}

fn state(rng: &mut SplitMix64) -> ([f64; 4], Vec<f64>, [f64; 4], Vec<f64>) {
    let e = normalize(&[0.0; 4].map(|_| rng.symmetric())).unwrap();
    let qf: Vec<f64> = (0..MODES).map(|_| 0.2 * rng.symmetric()).collect();
    let e_dot = [0.0; 4].map(|_| rng.symmetric());
    let qf_dot: Vec<f64> = (0..MODES).map(|_| rng.symmetric()).collect();
    (e, qf, e_dot, qf_dot)
}

/// Σⱼ mⱼ Lⱼᵀ Lⱼ at q = (r, e, q_f) for any e (off the unit sphere too, where the reduced
/// M_ff of the kernel would miss the factor |e|⁴ of Aᵀ A).
fn nodal_mass(nodes: &[NodalMass], q: &[f64]) -> Mat<f64> {
    let e = [q[3], q[4], q[5], q[6]];
    let mut m = Mat::<f64>::zeros(7 + MODES, 7 + MODES);
    for node in nodes {
        let l = node_jacobian(node, &e, &q[7..]);
        m += node.mass * (l.transpose() * &l);
    }
    m
}

#[test]
fn mass_matrix_from_the_invariants_equals_the_nodal_sum() {
    let mut rng = SplitMix64::new(7);
    let nodes = synthetic_nodes(&mut rng);
    let inv = MassInvariants::from_nodes(&nodes);
    let m_ff = lumped_modal_mass(&nodes);
    let (e, qf, _, _) = state(&mut rng);
    let mut m = Mat::zeros(7 + MODES, 7 + MODES);
    mass_matrix(&inv, m_ff.as_ref(), &e, &qf, m.as_mut());
    let q: Vec<f64> = [0.0; 3].iter().chain(&e).chain(&qf).copied().collect();
    let direct = nodal_mass(&nodes, &q);
    let err = (&m - &direct).norm_max();
    assert!(
        err < 1e-13 * direct.norm_max(),
        "max |M − Σ m Lᵀ L| = {err:e}"
    );
}

#[test]
fn mass_product_equals_the_mass_matrix_times_the_vector() {
    let mut rng = SplitMix64::new(5);
    let nodes = synthetic_nodes(&mut rng);
    let inv = MassInvariants::from_nodes(&nodes);
    let m_ff = lumped_modal_mass(&nodes);
    let (e, qf, _, _) = state(&mut rng);
    let w: Vec<f64> = (0..7 + MODES).map(|_| rng.symmetric()).collect();
    let configuration = Configuration::new(&inv, &e, &qf);
    let mut m = Mat::zeros(7 + MODES, 7 + MODES);
    configuration.mass_matrix(&inv, m_ff.as_ref(), m.as_mut());
    let mut product = vec![0.0; 7 + MODES];
    configuration.mass_product(&inv, m_ff.as_ref(), &w, &mut product);
    for (i, p) in product.iter().enumerate() {
        let expected: f64 = (0..7 + MODES).map(|j| m[(i, j)] * w[j]).sum();
        assert!(
            (p - expected).abs() < 1e-13 * m.norm_max(),
            "row {i}: {p} vs {expected}"
        );
    }
}

#[test]
fn quadratic_velocity_vector_matches_lagrange_by_finite_differences() {
    let mut rng = SplitMix64::new(11);
    let nodes = synthetic_nodes(&mut rng);
    let inv = MassInvariants::from_nodes(&nodes);
    let (e, qf, e_dot, qf_dot) = state(&mut rng);
    let q: Vec<f64> = [0.1, -0.2, 0.3]
        .iter()
        .chain(&e)
        .chain(&qf)
        .copied()
        .collect();
    let v: Vec<f64> = [0.4, 0.5, -0.6]
        .iter()
        .chain(&e_dot)
        .chain(&qf_dot)
        .copied()
        .collect();
    let nq = q.len();
    let kinetic = |q: &[f64]| {
        let m = nodal_mass(&nodes, q);
        (0..nq)
            .map(|i| (0..nq).map(|j| v[i] * m[(i, j)] * v[j]).sum::<f64>())
            .sum::<f64>()
    };
    let h = 1e-6;
    let shifted = |q: &[f64], dir: &[f64], s: f64| -> Vec<f64> {
        q.iter().zip(dir).map(|(a, b)| a + s * b).collect()
    };
    // Ṁ q̇ = d/dε M(q + ε q̇) q̇
    let (mp, mm) = (
        nodal_mass(&nodes, &shifted(&q, &v, h)),
        nodal_mass(&nodes, &shifted(&q, &v, -h)),
    );
    let mut expected = vec![0.0; nq];
    for i in 0..nq {
        let mut unit = vec![0.0; nq];
        unit[i] = 1.0;
        let dt = (kinetic(&shifted(&q, &unit, h)) - kinetic(&shifted(&q, &unit, -h))) / (2.0 * h);
        let mdot_v: f64 = (0..nq)
            .map(|j| (mp[(i, j)] - mm[(i, j)]) / (2.0 * h) * v[j])
            .sum();
        expected[i] = 0.5 * dt - mdot_v;
    }
    let mut fv = vec![0.0; nq];
    quadratic_velocity(&inv, &e, &qf, &e_dot, &qf_dot, &mut fv);
    let scale = expected.iter().fold(0.0_f64, |a, b| a.max(b.abs()));
    for i in 0..nq {
        assert!(
            (fv[i] - expected[i]).abs() < 1e-7 * scale,
            "f_v[{i}] = {} vs {}",
            fv[i],
            expected[i]
        );
    }
    // its rate Jacobian (closed form) against a finite difference
    let mut jac = Mat::zeros(nq, nq);
    quadratic_velocity_rate_jacobian(&inv, &e, &qf, &e_dot, &qf_dot, jac.as_mut());
    for j in 3..nq {
        let mut ed = e_dot;
        let mut fd = qf_dot.clone();
        if j < 7 {
            ed[j - 3] += h
        } else {
            fd[j - 7] += h
        }
        let mut plus = vec![0.0; nq];
        quadratic_velocity(&inv, &e, &qf, &ed, &fd, &mut plus);
        for i in 0..nq {
            let numeric = (plus[i] - fv[i]) / h;
            assert!(
                (jac[(i, j)] - numeric).abs() < 1e-4 * (1.0 + scale),
                "∂f_v/∂v [{i},{j}]"
            );
        }
    }
}

#[test]
fn gravity_force_is_the_sum_of_nodal_weights() {
    let mut rng = SplitMix64::new(3);
    let nodes = synthetic_nodes(&mut rng);
    let inv = MassInvariants::from_nodes(&nodes);
    let (e, qf, _, _) = state(&mut rng);
    let g = [0.3, -9.81, 1.2];
    let mut f = vec![0.0; 7 + MODES];
    gravity_force(&inv, &e, &qf, g, &mut f);
    for (i, fi) in f.iter().enumerate() {
        let direct: f64 = nodes
            .iter()
            .map(|n| {
                let l = node_jacobian(n, &e, &qf);
                n.mass * (0..3).map(|k| l[(k, i)] * g[k]).sum::<f64>()
            })
            .sum();
        assert!((fi - direct).abs() < 1e-12, "Q_g[{i}]");
    }
}

#[test]
fn rigid_rotation_block_is_four_gt_j_g() {
    let j = [[2.0, 0.1, -0.2], [0.1, 3.0, 0.3], [-0.2, 0.3, 4.0]];
    let inv = MassInvariants::rigid(5.0, j);
    let e = normalize(&[0.9, 0.2, -0.3, 0.4]).unwrap();
    let mut m = Mat::zeros(7, 7);
    mass_matrix(&inv, Mat::zeros(0, 0).as_ref(), &e, &[], m.as_mut());
    let g = g_matrix(&e);
    let trace = 9.0;
    for a in 0..4 {
        for b in 0..4 {
            let gjg: f64 = (0..3)
                .map(|k| (0..3).map(|l| g[k][a] * j[k][l] * g[l][b]).sum::<f64>())
                .sum();
            let expected = 4.0 * gjg + 2.0 * trace * e[a] * e[b];
            assert!(
                (m[(3 + a, 3 + b)] - expected).abs() < 1e-13,
                "M_ΘΘ[{a},{b}]"
            );
        }
        for i in 0..3 {
            assert_eq!(m[(i, 3 + a)], 0.0);
        }
    }
}

#[test]
fn rotation_partials_are_the_derivatives_of_the_rotation_matrix() {
    let x = [0.7, -0.3, 0.5, 0.2];
    let p = rotation_partials(&x);
    let h = 1e-6;
    for a in 0..4 {
        let (mut xp, mut xm) = (x, x);
        xp[a] += h;
        xm[a] -= h;
        let (ap, am) = (rotation_matrix(&xp), rotation_matrix(&xm));
        for i in 0..3 {
            for j in 0..3 {
                let fd = (ap[i][j] - am[i][j]) / (2.0 * h);
                assert!(
                    (p[a][i][j] - fd).abs() < 1e-8,
                    "∂A/∂e{a} [{i}][{j}]: {} vs {fd}",
                    p[a][i][j]
                );
            }
        }
    }
}
