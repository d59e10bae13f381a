//! Constraint derivatives against finite differences (the test oracle): Φ_q of Φ, the
//! Hessian ∇²Φ of Φ_q, Φ_t of Φ in t and the acceleration right-hand side γ of the second
//! difference of Φ along a straight path, for every joint type and both drives, between a
//! rigid body and a flexible body whose marker moves and turns with random basis rows.

use super::body::Body;
use super::flexible::{FlexibleBodyData, MassInvariants, NodalMass};
use super::joints::{JointKind, drive_constraint};
use super::marker::Marker;
use super::signal::Signal;
use super::system::System;
use crate::geometry::euler_parameters::from_axis_angle;
use crate::linalg::random::SplitMix64;
use faer::Mat;

const KINDS: [JointKind; 8] = [
    JointKind::Revolute,
    JointKind::Fixed,
    JointKind::Spherical,
    JointKind::Prismatic,
    JointKind::Cylindrical,
    JointKind::Universal,
    JointKind::Inline,
    JointKind::Inplane,
];

fn two_bodies(rng: &mut SplitMix64) -> (System, Marker, Marker, Vec<f64>) {
    let mut sys = System::new([0.0; 3]);
    let rigid = sys.add_body(
        Body::rigid(1.0, [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]),
        [0.1, 0.2, 0.3],
        from_axis_angle([1.0, 2.0, 3.0], 0.7).unwrap(),
    );
    let modes = 2;
    let node = NodalMass {
        mass: 1.0,
        position: [0.5, 0.0, 0.0],
        modes: vec![[0.1, 0.0, 0.0]; modes],
    };
    let flexible = sys.add_body(
        Body::flexible(FlexibleBodyData {
            invariants: MassInvariants::from_nodes(&[node]),
            mass: Mat::identity(modes, modes),
            stiffness: Mat::identity(modes, modes),
            damping: Mat::zeros(modes, modes),
            interfaces: Vec::new(),
        }),
        [-0.2, 0.4, 0.1],
        from_axis_angle([-1.0, 0.5, 2.0], 1.1).unwrap(),
    );
    let mut random3 = || [0.0; 3].map(|_| rng.symmetric());
    let m1 = Marker::new(Some(rigid), random3()).with_z_axis(random3());
    let mut m2 = Marker::new(Some(flexible), random3()).with_z_axis(random3());
    m2.translation = (0..modes).map(|_| random3()).collect();
    m2.rotation = (0..modes).map(|_| random3()).collect();
    let mut q = sys.initial_state().0.to_vec();
    for x in q.iter_mut() {
        *x += 0.1 * rng.symmetric();
    }
    (sys, m1, m2, q)
}

#[test]
fn joint_and_drive_derivatives_match_finite_differences() {
    let mut rng = SplitMix64::new(5);
    let (sys, m1, m2, q) = two_bodies(&mut rng);
    let layout = &sys.layout;
    let n = q.len();
    let t = 0.3;
    let motion = Signal::sine(0.4, 1.5);
    let mut constraints: Vec<_> = KINDS.iter().flat_map(|k| k.constraints(&m1, &m2)).collect();
    constraints.push(drive_constraint(
        JointKind::Revolute,
        &m1,
        &m2,
        0.2,
        &motion,
    ));
    constraints.push(drive_constraint(
        JointKind::Prismatic,
        &m1,
        &m2,
        0.1,
        &motion,
    ));
    let h = 1e-6;
    for (row, c) in constraints.iter().enumerate() {
        let mut jac = vec![0.0; n];
        c.jacobian(layout, &q, t, 0, |j, x| jac[j] += x);
        let mut hess = Mat::<f64>::zeros(n, n);
        c.hessian(layout, &q, t, 1.0, |i, j, x| hess[(i, j)] += x);
        for j in 0..n {
            let (mut qp, mut qm) = (q.clone(), q.clone());
            qp[j] += h;
            qm[j] -= h;
            let fd = (c.value(layout, &qp, t) - c.value(layout, &qm, t)) / (2.0 * h);
            assert!(
                (jac[j] - fd).abs() < 1e-7,
                "row {row}: ∂Φ/∂q{j} {} vs {fd}",
                jac[j]
            );
            let (mut jp, mut jm) = (vec![0.0; n], vec![0.0; n]);
            c.jacobian(layout, &qp, t, 0, |i, x| jp[i] += x);
            c.jacobian(layout, &qm, t, 0, |i, x| jm[i] += x);
            for i in 0..n {
                let fd = (jp[i] - jm[i]) / (2.0 * h);
                assert!((hess[(i, j)] - fd).abs() < 1e-6, "row {row}: ∇²Φ[{i},{j}]");
            }
        }
        let fd = (c.value(layout, &q, t + h) - c.value(layout, &q, t - h)) / (2.0 * h);
        assert!(
            (c.time_rate(layout, &q, t) - fd).abs() < 1e-7,
            "row {row}: Φ_t"
        );
    }
}

#[test]
fn acceleration_rhs_is_minus_the_second_time_difference_along_a_straight_path() {
    // along q(t) = q + (t − t₀) v, q̈ = 0, so d²Φ/dt² = −γ; the central second difference has
    // error h² Φ⁗/12 (≈ 1e-8 · 10 here) plus roundoff 4ε|Φ|/h² ≈ 1e-8
    let mut rng = SplitMix64::new(8);
    let (sys, m1, m2, q) = two_bodies(&mut rng);
    let layout = &sys.layout;
    let v: Vec<f64> = q.iter().map(|_| rng.symmetric()).collect();
    let t = 0.3;
    let motion = Signal::sine(0.4, 1.5);
    let mut set = super::constraint_set::ConstraintSet::default();
    for c in KINDS.iter().flat_map(|k| k.constraints(&m1, &m2)) {
        set.push(c, String::new());
    }
    for kind in [JointKind::Revolute, JointKind::Prismatic] {
        set.push(
            drive_constraint(kind, &m1, &m2, 0.2, &motion),
            String::new(),
        );
    }
    set.push(
        super::constraint::Constraint::Normalization { body: 1 },
        String::new(),
    );
    let mut gamma = vec![0.0; set.len()];
    set.acceleration_rhs(layout, &q, &v, t, &mut gamma);
    let h = 1e-4;
    let at = |s: f64| {
        let qs: Vec<f64> = q.iter().zip(&v).map(|(a, b)| a + s * b).collect();
        let mut phi = vec![0.0; set.len()];
        set.values(layout, &qs, t + s, &mut phi);
        phi
    };
    let (plus, centre, minus) = (at(h), at(0.0), at(-h));
    for (row, g) in gamma.iter().enumerate() {
        let fd = (plus[row] - 2.0 * centre[row] + minus[row]) / (h * h);
        assert!((g + fd).abs() < 1e-5, "row {row}: γ {g} vs −Φ̈ {}", -fd);
    }
}
