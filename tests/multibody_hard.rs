//! Hard cases for the GGL integrators, each with BDF1, BDF2 and generalized-α: a step far
//! above the period of a flexible body's mode, a very stiff joint spring and a drive whose
//! acceleration jumps at t₀. Each must run stably (the stiff parts damped, the slow motion
//! kept) or stop with a clear error.

use faer::Mat;
use paraflex::geometry::euler_parameters::{IDENTITY, from_axis_angle};
use paraflex::geometry::vec3;
use paraflex::linalg::random::SplitMix64;
use paraflex::multibody::flexible::NodalMass;
use paraflex::multibody::{
    Body, DriveKind, FlexibleBodyData, Force, Ggl, JointKind, Marker, MassInvariants,
    MultibodyError, NewtonSettings, Scheme, Signal, System,
};

const G: f64 = 9.81;

const SCHEMES: [Scheme; 3] = [
    Scheme::Bdf1,
    Scheme::Bdf2,
    Scheme::GeneralizedAlpha {
        spectral_radius: 0.8,
    },
];

/// A rigid pendulum (m = 2, d = 0.8, J_zz = 0.05, I_O = 1.33) on a revolute joint to the
/// ground at the origin, at angle θ₀; returns the system and the joint.
fn pendulum(theta0: f64) -> (System, usize) {
    let (m, d) = (2.0, 0.8);
    let mut sys = System::new([0.0, -G, 0.0]);
    let body = sys.add_body(
        Body::rigid(m, [[0.03, 0.0, 0.0], [0.0, 0.04, 0.0], [0.0, 0.0, 0.05]]),
        [d * theta0.sin(), -d * theta0.cos(), 0.0],
        from_axis_angle([0.0, 0.0, 1.0], theta0).unwrap(),
    );
    let on_body = sys.add_marker(Marker::new(Some(body), [0.0, d, 0.0]));
    let on_ground = sys.add_marker(Marker::new(None, [0.0; 3]));
    let joint = sys.add_joint(JointKind::Revolute, on_body, on_ground);
    (sys, joint)
}

#[test]
fn a_step_far_above_a_flexible_mode_period_damps_the_mode_and_keeps_the_swing() {
    // a synthetic flexible body (random nodal masses, two modes at 500 Hz: period 2 ms)
    // swinging on a revolute joint 2 m above its origin, with h = 20 ms = 10 periods
    let modes = 2;
    let mut rng = SplitMix64::new(4);
    let nodes: Vec<NodalMass> = (0..8)
        .map(|_| NodalMass {
            mass: 0.5 + rng.unit(),
            position: [0.0; 3].map(|_| rng.symmetric()),
            modes: (0..modes)
                .map(|_| [0.0; 3].map(|_| 0.2 * rng.symmetric()))
                .collect(),
        })
        .collect();
    let m_ff = Mat::from_fn(modes, modes, |k, l| {
        nodes
            .iter()
            .map(|n| n.mass * vec3::dot(n.modes[k], n.modes[l]))
            .sum::<f64>()
    });
    let omega = 2.0 * std::f64::consts::PI * 500.0;
    let stiffness = Mat::from_fn(modes, modes, |k, l| {
        if k == l {
            omega * omega * m_ff[(k, k)]
        } else {
            0.0
        }
    });
    let (h, end, q_f0) = (2e-2, 2.0, 0.01);
    for scheme in SCHEMES {
        let mut sys = System::new([0.0, -G, 0.0]);
        let body = sys.add_body(
            Body::flexible(FlexibleBodyData {
                invariants: MassInvariants::from_nodes(&nodes),
                mass: m_ff.clone(),
                stiffness: stiffness.clone(),
                damping: Mat::zeros(modes, modes),
                interfaces: Vec::new(),
            }),
            [0.5, -2.0, 0.0],
            IDENTITY,
        );
        sys.set_initial_modal(body, &[q_f0, -q_f0]);
        let mut pivot = Marker::new(Some(body), [0.0, 2.0, 0.0]);
        pivot.translation = vec![[0.0; 3]; modes];
        pivot.rotation = vec![[0.0; 3]; modes];
        let on_body = sys.add_marker(pivot);
        let on_ground = sys.add_marker(Marker::new(None, [0.5, 0.0, 0.0]));
        sys.add_joint(JointKind::Revolute, on_body, on_ground);
        let mut ggl = Ggl::with_scheme(sys, h, 0.0, NewtonSettings::default(), scheme).unwrap();
        let mut swing: f64 = 0.0;
        ggl.run((end / h).round() as usize, |g, _| {
            swing = swing.max(g.q[0] - 0.5);
        })
        .unwrap();
        let q_f = ggl.q[7].abs().max(ggl.q[8].abs());
        eprintln!("{scheme:?}: |q_f| {q_f:e}, largest swing {swing}");
        // the 500 Hz mode decays per step by 1/(ωh) = 0.016 (BDF1), by the BDF2 roots
        // (≈ 0.8/√(ωh)), by ρ∞ = 0.8 (generalized-α): after 100 steps ≤ 0.8¹⁰⁰ q_f0 = 2e-12;
        // what remains is the quasi-static deflection under gravity and the swing's inertial
        // loads, (g + ω_p² L) Σ mⱼ|Ψⱼ| / (ω² m_ff) ≈ 1e-6; 1e-5 bounds it
        assert!(q_f < 1e-5, "{scheme:?}: modal amplitude {q_f:e}");
        // the swing is kept and bounded: the random nodes put the centre of mass off the
        // vertical through the pivot, so the body swings (≈ 3 s period, 2 m pendulum) with
        // its origin moving by decimetres, never beyond the 1 m an escape would need
        assert!(swing > 0.0 && swing < 1.0, "{scheme:?}: swing {swing}");
    }
}

#[test]
fn a_very_stiff_joint_spring_is_damped_by_the_step_and_holds_the_pendulum() {
    // k = 1e8 N m/rad on the pendulum's revolute joint (ω = √(k/I_O) ≈ 8.7e3 rad/s, period
    // 0.7 ms) released 0.3 rad from the spring's rest angle 0, h = 10 ms (ωh ≈ 87)
    let (k, theta0, h) = (1e8, 0.3, 1e-2);
    // the Newton matrix keeps K ∇θ∇θᵀ but not K (θ − θ₀) ∇²θ, a third of it at 0.3 rad: the
    // iteration contracts by ≈ 0.3 per step, so 40 iterations instead of 12
    let settings = NewtonSettings {
        max_iterations: 40,
        ..NewtonSettings::default()
    };
    for scheme in SCHEMES {
        let (mut sys, joint) = pendulum(theta0);
        sys.add_force(Force::JointSpringDamper {
            joint,
            stiffness: k,
            damping: 0.0,
            rest: 0.0,
        });
        let mut ggl = Ggl::with_scheme(sys, h, 0.0, settings, scheme).unwrap();
        if let Err(e) = ggl.run(100, |_, _| {}) {
            // generalized-α starts from the consistent q̈₀ = −k θ₀/I_O ≈ −2e7 rad/s², whose
            // O(h²) share of the first steps' prediction turns the body by radians: Newton
            // diverges and the guard stops both attempts before their 40 iterations, naming
            // the step
            if let MultibodyError::NotConverged { iterations, .. } = e {
                assert!(
                    iterations < settings.max_iterations,
                    "{iterations} iterations"
                );
            }
            let message = e.to_string();
            eprintln!("{scheme:?}: {message}");
            assert!(
                matches!(scheme, Scheme::GeneralizedAlpha { .. })
                    && message.starts_with("step to t = 0.0")
                    && message.contains("did not converge"),
                "{scheme:?}: {message}"
            );
            continue;
        }
        let theta = ggl.q[0].atan2(-ggl.q[1]);
        eprintln!("{scheme:?}: θ(1 s) = {theta:e}");
        // per step the stiff oscillation shrinks by ≤ 1/(ωh) (BDF1), the BDF2 roots
        // (≈ 0.8/√(ωh)), ρ∞ = 0.8 (generalized-α): after 100 steps ≤ 0.8¹⁰⁰ θ₀ ≈ 6e-11;
        // the static sag m g d θ / k is below 1e-8
        assert!(theta.abs() < 1e-8, "{scheme:?}: θ = {theta:e}");
    }
}

#[test]
fn a_drive_whose_acceleration_jumps_at_the_start_gives_the_closed_form_torque() {
    // θ(t) = θ₀ + ½ α t² from rest: θ̈ jumps from 0 to α at t₀. The drive torque is
    // τ = I_O α + m g d sin θ (the pendulum's equation of motion with θ prescribed)
    let (theta0, alpha, h, end) = (0.2_f64, 4.0, 1e-3, 0.5);
    let (i_o, mgd) = (0.05 + 2.0 * 0.8 * 0.8, 2.0 * G * 0.8);
    for scheme in SCHEMES {
        let (mut sys, joint) = pendulum(theta0);
        let motion = Signal::new(move |t| [0.5 * alpha * t * t, alpha * t, alpha]);
        sys.add_drive(joint, motion, DriveKind::Rigid).unwrap();
        let mut ggl = Ggl::with_scheme(sys, h, 0.0, NewtonSettings::default(), scheme).unwrap();
        let mut worst: f64 = 0.0;
        ggl.run((end / h).round() as usize, |g, report| {
            let theta = theta0 + 0.5 * alpha * report.time * report.time;
            let exact = i_o * alpha + mgd * theta.sin();
            worst = worst.max((g.drive_effort(0) - exact).abs());
        })
        .unwrap();
        eprintln!("{scheme:?}: torque error {worst:e}");
        // a multiplier one step off in time is off by τ̇ h ≤ m g d θ̇_max h = 3e-2; the
        // schemes' multipliers are O(h) (BDF1) or O(h²) accurate, never worse than that
        assert!(
            worst < mgd * alpha * end * h,
            "{scheme:?}: torque error {worst:e}"
        );
    }
}
