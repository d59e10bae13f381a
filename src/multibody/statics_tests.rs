//! The static iteration matrix against finite differences of the static residual
//! [Φ_qᵀ λ − f; Φ] in q: a closed loop (crank, flexible coupler, rocker; revolute, spherical
//! and revolute joints back to the ground) under gravity off every axis, with a compliant
//! drive and a joint spring on revolutes (ℓ an angle), a spring on a prismatic joint (a slide),
//! a point-to-point spring (a distance), a point force and moments on the rigid and the
//! flexible body, at a configuration off the assembly (random q with e off the unit sphere,
//! random λ): the derivative identities hold at any (q, λ).

use super::body::Body;
use super::flexible::{FlexibleBodyData, MassInvariants, NodalMass};
use super::forces::Force;
use super::joints::{DriveKind, JointKind};
use super::marker::Marker;
use super::signal::Signal;
use super::statics::{iteration_matrix, residual};
use super::system::System;
use crate::geometry::euler_parameters::from_axis_angle;
use crate::linalg::random::SplitMix64;
use faer::Mat;

const MODES: usize = 3;

fn flexible_coupler(rng: &mut SplitMix64) -> FlexibleBodyData {
    let nodes: Vec<NodalMass> = (0..6)
        .map(|_| NodalMass {
            mass: 0.5 + rng.unit(),
            position: [0.0; 3].map(|_| rng.symmetric()),
            modes: (0..MODES)
                .map(|_| [0.0; 3].map(|_| 0.3 * rng.symmetric()))
                .collect(),
        })
        .collect();
    let b = Mat::from_fn(MODES, MODES, |_, _| rng.symmetric());
    FlexibleBodyData {
        invariants: MassInvariants::from_nodes(&nodes),
        mass: Mat::identity(MODES, MODES),
        stiffness: &b * b.transpose() + Mat::<f64>::identity(MODES, MODES) * 50.0,
        damping: Mat::identity(MODES, MODES),
        interfaces: Vec::new(),
    }
}

/// The loop of the module docs and a random (q, λ) off its assembly.
fn loaded_loop(rng: &mut SplitMix64) -> (System, Vec<f64>, Vec<f64>, super::system::Equations) {
    let mut sys = System::new([0.3, -9.81, 0.5]);
    let inertia = [[0.02, 0.0, 0.0], [0.0, 0.03, 0.0], [0.0, 0.0, 0.04]];
    let crank = sys.add_body(
        Body::rigid(1.2, inertia),
        [0.0, 0.1, 0.0],
        from_axis_angle([0.0, 0.0, 1.0], 0.4).unwrap(),
    );
    let coupler = sys.add_body(
        Body::flexible(flexible_coupler(rng)),
        [0.3, 0.2, 0.0],
        from_axis_angle([1.0, 2.0, 3.0], 0.3).unwrap(),
    );
    let rocker = sys.add_body(
        Body::rigid(0.8, inertia),
        [0.6, 0.1, 0.0],
        from_axis_angle([0.0, 0.0, 1.0], -0.5).unwrap(),
    );
    let mut random3 = || [0.0; 3].map(|_| rng.symmetric());
    let on_coupler = |rng3: &mut dyn FnMut() -> [f64; 3]| {
        let mut m = Marker::new(Some(coupler), rng3()).with_z_axis(rng3());
        m.translation = (0..MODES).map(|_| rng3()).collect();
        m.rotation = (0..MODES).map(|_| rng3()).collect();
        m
    };
    let coupler_a = on_coupler(&mut random3);
    let coupler_b = on_coupler(&mut random3);
    let markers = [
        Marker::new(None, [0.0, 0.0, 0.0]),
        Marker::new(Some(crank), [-0.1, 0.0, 0.0]),
        Marker::new(Some(crank), [0.1, 0.0, 0.0]),
        coupler_a,
        coupler_b,
        Marker::new(Some(rocker), [-0.1, 0.05, 0.0]).with_z_axis(random3()),
        Marker::new(Some(rocker), [0.1, 0.0, 0.0]),
        Marker::new(None, [0.7, 0.0, 0.0]),
    ]
    .map(|m| sys.add_marker(m));
    let drive_joint = sys.add_joint(JointKind::Revolute, markers[0], markers[1]);
    sys.add_joint(JointKind::Revolute, markers[2], markers[3]);
    sys.add_joint(JointKind::Spherical, markers[4], markers[5]);
    let hinge = sys.add_joint(JointKind::Revolute, markers[6], markers[7]);
    let slide = sys.add_joint(JointKind::Prismatic, markers[4], markers[5]);
    sys.add_drive(
        drive_joint,
        Signal::sine(0.4, 1.5),
        DriveKind::Compliant {
            stiffness: 300.0,
            damping: 2.0,
        },
    )
    .unwrap();
    for (joint, stiffness, rest) in [(hinge, 40.0, 0.2), (slide, 900.0, 0.05)] {
        sys.add_force(Force::JointSpringDamper {
            joint,
            stiffness,
            damping: 1.0,
            rest,
        });
    }
    sys.add_force(Force::PointSpringDamper {
        first: markers[1],
        second: markers[4],
        stiffness: 500.0,
        damping: 1.0,
        length: 0.2,
    });
    sys.add_force(Force::Point {
        marker: markers[3],
        direction: [0.6, 0.0, 0.8],
        signal: Signal::constant(7.0),
    });
    for marker in [markers[4], markers[5]] {
        sys.add_force(Force::Moment {
            marker,
            direction: [0.0, 0.6, 0.8],
            signal: Signal::constant(3.0),
        });
    }
    let mut q = sys.initial_state().0.to_vec();
    let equations = sys.equations(&q).unwrap();
    for x in q.iter_mut() {
        *x += 0.1 * rng.symmetric();
    }
    let lambda: Vec<f64> = (0..equations.constraints.len())
        .map(|_| 10.0 * rng.symmetric())
        .collect();
    (sys, q, lambda, equations)
}

/// Central differences with h = 1e-6 (1 + |qⱼ|) err by h² R‴/6 (about 1e-12 of the entries
/// here: R is a low-order polynomial in q except for the springs' atan2 and square root) plus
/// the rounding ε |R| / h ≈ 1e-10 of the largest residual entry (measured: 9e-11 of the largest
/// matrix entry); 1e-6 leaves room for both and catches a missing term: the terms the
/// integrator's matrix leaves out (gravity's Hessian, the springs' curvature, the loads'
/// derivatives) reach 0.34 of the largest entry here.
#[test]
fn static_iteration_matrix_is_the_derivative_of_the_static_residual() {
    let mut rng = SplitMix64::new(11);
    let (sys, q, lambda, equations) = loaded_loop(&mut rng);
    let (n, m) = (q.len(), lambda.len());
    let t = 0.3;
    let mut phi_q = Mat::zeros(m, n);
    residual(&sys, &equations, &q, &lambda, t, &mut phi_q);
    let mut analytic = Mat::zeros(n + m, n + m);
    iteration_matrix(
        &sys,
        &equations,
        (&q, &lambda),
        t,
        &phi_q,
        analytic.as_mut(),
    );
    let largest = (0..n + m)
        .flat_map(|i| (0..n).map(move |j| (i, j)))
        .fold(0.0_f64, |a, (i, j)| a.max(analytic[(i, j)].abs()));
    let mut worst = 0.0_f64;
    for j in 0..n {
        let h = 1e-6 * (1.0 + q[j].abs());
        let at = |x: f64| {
            let mut shifted = q.clone();
            shifted[j] = x;
            residual(
                &sys,
                &equations,
                &shifted,
                &lambda,
                t,
                &mut Mat::zeros(m, n),
            )
        };
        let (plus, minus) = (at(q[j] + h), at(q[j] - h));
        for i in 0..n + m {
            let fd = (plus[i] - minus[i]) / (2.0 * h);
            worst = worst.max((analytic[(i, j)] - fd).abs());
        }
    }
    assert!(
        worst <= 1e-6 * largest,
        "largest difference {worst:e} of the largest entry {largest:e}"
    );
    // the Φ_qᵀ columns of the λ unknowns: R is linear in λ
    for i in 0..m {
        for j in 0..n {
            assert_eq!(analytic[(j, n + i)], phi_q[(i, j)]);
        }
    }
}
