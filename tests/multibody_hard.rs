//! Hard cases for the GGL integrators, each with BDF1, BDF2 and generalized-α: a step far
//! above the period of a flexible body's mode, a very stiff joint spring and a drive whose
//! acceleration jumps at t₀; a driven four-bar passing near its dead centre and one stopping on
//! it; a rigid body tumbling through every orientation (angular momentum, Euler parameters).
//! Each must run stably (the stiff parts damped, the slow motion kept) or stop with a clear
//! error.

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
const PI_2: f64 = std::f64::consts::FRAC_PI_2;

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

/// Adds a planar rigid link (mass 1, inertia of a slender rod) of length `length` from `start`
/// at `angle` about z; returns (marker at the start, marker at the end).
fn link(sys: &mut System, length: f64, start: [f64; 2], angle: f64) -> (usize, usize) {
    let j = length * length / 12.0;
    let (c, s) = (angle.cos(), angle.sin());
    let body = sys.add_body(
        Body::rigid(1.0, [[1e-4, 0.0, 0.0], [0.0, j, 0.0], [0.0, 0.0, j]]),
        [
            start[0] + 0.5 * length * c,
            start[1] + 0.5 * length * s,
            0.0,
        ],
        from_axis_angle([0.0, 0.0, 1.0], angle).unwrap(),
    );
    let first = sys.add_marker(Marker::new(Some(body), [-0.5 * length, 0.0, 0.0]));
    let second = sys.add_marker(Marker::new(Some(body), [0.5 * length, 0.0, 0.0]));
    (first, second)
}

/// The joint C of a four-bar with crank a at angle θ about the ground pivot A = 0, coupler b,
/// rocker c about D = (d, 0): the intersection of |C − B| = b and |C − D| = c left of the
/// direction B → D (the branch the run starts on), with the transmission angle at C (rad).
fn four_bar_joint(a: f64, b: f64, c: f64, d: f64, theta: f64) -> ([f64; 2], f64) {
    let bp = [a * theta.cos(), a * theta.sin()];
    let (dx, dy) = (d - bp[0], -bp[1]);
    let l = dx.hypot(dy);
    let along = (b * b - c * c + l * l) / (2.0 * l);
    let h = (b * b - along * along).sqrt();
    let (ux, uy) = (dx / l, dy / l);
    let transmission = ((b * b + c * c - l * l) / (2.0 * b * c)).acos();
    (
        [bp[0] + along * ux - h * uy, bp[1] + along * uy + h * ux],
        transmission,
    )
}

/// What a turn of a driven four-bar measured: the largest distance of joint C from the loop
/// equations' solution, the narrowest transmission angle passed (rad) and the largest |drive
/// torque|.
struct Turn {
    worst: f64,
    narrowest: f64,
    torque: f64,
}

/// One turn of the crank (0.3) of a four-bar with coupler 0.8, rocker 0.6 and ground `d` at
/// 1 rev/s under gravity with `scheme` at Δt = 1 ms, from θ = 90° with C above the ground.
fn four_bar_turn(d: f64, scheme: Scheme) -> Result<Turn, MultibodyError> {
    let (a, b, c) = (0.3, 0.8, 0.6);
    let (omega, theta0, h) = (2.0 * std::f64::consts::PI, PI_2, 1e-3);
    let bp = [0.0, a];
    let (cp, _) = four_bar_joint(a, b, c, d, theta0);
    let mut sys = System::new([0.0, -G, 0.0]);
    let (crank_start, crank_end) = link(&mut sys, a, [0.0, 0.0], theta0);
    let coupler_angle = (cp[1] - bp[1]).atan2(cp[0] - bp[0]);
    let (coupler_start, coupler_end) = link(&mut sys, b, bp, coupler_angle);
    let (rocker_start, rocker_end) = link(&mut sys, c, [d, 0.0], cp[1].atan2(cp[0] - d));
    let a_pivot = sys.add_marker(Marker::new(None, [0.0; 3]));
    let d_pivot = sys.add_marker(Marker::new(None, [d, 0.0, 0.0]));
    let crank = sys.add_joint(JointKind::Revolute, crank_start, a_pivot);
    sys.add_joint(JointKind::Revolute, coupler_start, crank_end);
    sys.add_joint(JointKind::Revolute, rocker_end, coupler_end);
    sys.add_joint(JointKind::Revolute, rocker_start, d_pivot);
    sys.add_drive(crank, Signal::ramp(omega), DriveKind::Rigid)?;
    let mut ggl = Ggl::with_scheme(sys, h, 0.0, NewtonSettings::default(), scheme)?;
    let mut turn = Turn {
        worst: 0.0,
        narrowest: PI_2,
        torque: 0.0,
    };
    ggl.run((1.0 / h).round() as usize, |g, report| {
        let (expected, transmission) = four_bar_joint(a, b, c, d, theta0 + omega * report.time);
        let p = g.marker_position(coupler_end);
        turn.worst = turn
            .worst
            .max((p[0] - expected[0]).hypot(p[1] - expected[1]));
        turn.narrowest = turn
            .narrowest
            .min(transmission.min(std::f64::consts::PI - transmission));
        turn.torque = turn.torque.max(g.drive_effort(0).abs());
    })?;
    Ok(turn)
}

/// A driven four-bar one millimetre off a change point (crank 0.3 + coupler 0.8 = rocker 0.6 +
/// ground 0.501 − 1e-3) turns its crank once. At θ = 0 coupler and rocker come within 1.7° of a
/// line (the transmission angle), where Φ_q is close to losing rank and the rocker turns ≈ 35×
/// faster than the crank. Every scheme passes it on the branch it started on: joint C within
/// 1e-9 of the loop equations' solution over the whole turn (measured 1.3e-13) and a finite
/// drive torque (≈ 700 N m at the dead centre for these unit-mass links).
#[test]
fn a_four_bar_passes_near_its_dead_centre_on_its_branch() {
    for scheme in SCHEMES {
        let turn = four_bar_turn(0.501, scheme).unwrap_or_else(|e| panic!("{scheme:?}: {e}"));
        eprintln!(
            "{scheme:?}: joint C error {:e}, narrowest transmission angle {:.2}°, |torque| ≤ {:.3}",
            turn.worst,
            turn.narrowest.to_degrees(),
            turn.torque
        );
        assert!(
            turn.narrowest.to_degrees() < 2.0,
            "the turn must pass the dead centre"
        );
        assert!(
            turn.worst < 1e-9,
            "{scheme:?}: joint C error {:e}",
            turn.worst
        );
        assert!(turn.torque.is_finite());
    }
}

/// On the change point itself (ground 0.5: all four links on one line at θ = 0) the loop
/// bifurcates and Φ_q loses rank: each scheme stops at the dead centre (t = 0.75 s, θ = 360°)
/// with the step's time, its Newton residual, the worst constraint and the joints whose rows
/// became dependent (all four: σ_min/σ_max of Φ_q measured 1e-11 to 1e-8), never a silent
/// jump to the other branch.
#[test]
fn a_four_bar_on_its_change_point_stops_at_the_dead_centre() {
    for scheme in SCHEMES {
        match four_bar_turn(0.5, scheme) {
            Err(MultibodyError::NotConverged {
                time,
                worst,
                dependent,
                ..
            }) => {
                eprintln!(
                    "{scheme:?}: stopped at t = {time}, worst constraint {worst}; {dependent}"
                );
                assert!((time - 0.75).abs() <= 2e-3, "{scheme:?}: stopped at {time}");
                // The worst constraint of the last iterate is named (a joint of the loop, or
                // a body's Euler-parameter normalization when the block solve's Newton steps
                // leave it worst); which one depends on the iterate, not on the cause.
                assert!(!worst.is_empty(), "the stop names a constraint");
                // Φ_q lost a rank there: its weakest combination of rows is near zero and
                // holds the rows of all four joints of the loop
                assert!(dependent.ratio < 1e-6, "{scheme:?}: {dependent}");
                for joint in 0..4 {
                    let name = format!("joint {joint} (Revolute)");
                    assert!(
                        dependent.constraints.contains(&name),
                        "{scheme:?}: {name} missing from {dependent}"
                    );
                }
            }
            other => panic!(
                "{scheme:?}: expected a stop at the dead centre, got {:?}",
                other.map(|t| t.worst)
            ),
        }
    }
}

/// A rigid body spun about its intermediate axis (J = diag(1, 2, 3), 2 rad/s about body y with a
/// 1 % perturbation about x: the Dzhanibekov flip) turns over repeatedly over 10 s, through the
/// x-y-z Euler angles' gimbal lock (|A₁₃| = 1), which Euler parameters do not have: the
/// normalization residual |e|² − 1 stays at round-off and the global angular momentum
/// H = A J ω̄ (ω̄ = 2 G ė, eq. A.3) stays constant up to each scheme's error: the drift of
/// |H − H₀|/|H₀| at Δt = 2 ms, bounded at about twice its measured value per scheme.
#[test]
fn a_body_tumbling_through_every_orientation_keeps_its_angular_momentum() {
    use paraflex::geometry::euler_parameters::{body_angular_velocity, rotation_matrix};
    use paraflex::geometry::mat3;
    let j = [[1.0, 0.0, 0.0], [0.0, 2.0, 0.0], [0.0, 0.0, 3.0]];
    for scheme in SCHEMES {
        let mut sys = System::new([0.0; 3]);
        let body = sys.add_body(Body::rigid(1.0, j), [0.0; 3], IDENTITY);
        sys.set_initial_velocity(body, [0.0; 3], [0.02, 2.0, 0.0]);
        let mut ggl = Ggl::with_scheme(sys, 2e-3, 0.0, NewtonSettings::default(), scheme).unwrap();
        let momentum = |q: &[f64], v: &[f64]| {
            let (e, e_dot) = ([q[3], q[4], q[5], q[6]], [v[3], v[4], v[5], v[6]]);
            let omega = body_angular_velocity(&e, &e_dot);
            mat3::mul_vec(&rotation_matrix(&e), mat3::mul_vec(&j, omega))
        };
        let h0 = momentum(&ggl.q, &ggl.v);
        let (mut drift, mut norm, mut gimbal) = (0.0_f64, 0.0_f64, 0.0_f64);
        ggl.run(5000, |g, _| {
            let e = [g.q[3], g.q[4], g.q[5], g.q[6]];
            let h = momentum(&g.q, &g.v);
            drift = drift.max(vec3::norm(vec3::sub(h, h0)) / vec3::norm(h0));
            norm = norm.max((e.iter().map(|x| x * x).sum::<f64>() - 1.0).abs());
            gimbal = gimbal.max(rotation_matrix(&e)[0][2].abs());
        })
        .unwrap();
        eprintln!("{scheme:?}: |H − H₀|/|H₀| ≤ {drift:e}, |e|² − 1 ≤ {norm:e}, |A13| ≤ {gimbal}");
        assert!(gimbal > 0.99, "{scheme:?}: no pass near gimbal lock");
        assert!(norm < 1e-10, "{scheme:?}: |e|² − 1 = {norm:e}");
        // measured 8.2e-3 (BDF1, first order), 5.6e-6 (BDF2), 1.3e-6 (generalized-α)
        let bound = match scheme {
            Scheme::Bdf1 => 2e-2,
            Scheme::Bdf2 => 1.2e-5,
            Scheme::GeneralizedAlpha { .. } => 3e-6,
        };
        assert!(
            drift < bound,
            "{scheme:?}: angular momentum drift {drift:e}"
        );
    }
}
