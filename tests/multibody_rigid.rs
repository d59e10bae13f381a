//! Rigid mechanisms against closed forms: pendulum periods (small-amplitude formula and the
//! elliptic-integral period, e.g. Landau & Lifshitz, Mechanics §11), the first-order energy
//! and position errors of BDF1, the observed orders 1, 2, 2 of BDF1, BDF2 and generalized-α
//! against the linearized pendulum θ₀ cos ωt, each scheme's energy behaviour, slider-crank and
//! four-bar kinematics against their loop equations solved here, a free tumbling rigid body
//! (angular momentum, Euler-parameter norm, a spin through every orientation), the redundancy
//! report of a planar loop of revolute joints and the reports of a loop that cannot close and
//! of one guessed at a dead centre.

use paraflex::geometry::euler_parameters::{IDENTITY, from_axis_angle};
use paraflex::multibody::{
    Body, DriveKind, Ggl, JointKind, Marker, NewtonSettings, Scheme, Signal, System,
};
use std::f64::consts::PI;

const G: f64 = 9.81;

/// The three schemes; generalized-α with ρ∞ = 0.8, a common choice that damps the modes
/// above the step's Nyquist frequency while its low-frequency dissipation stays O((ωh)³).
const SCHEMES: [Scheme; 3] = [
    Scheme::Bdf1,
    Scheme::Bdf2,
    Scheme::GeneralizedAlpha {
        spectral_radius: 0.8,
    },
];

/// A pendulum: body of mass m, inertia J_zz about its centre, hanging a distance d below a
/// revolute joint to the ground at the origin (axis z), released at rest at angle θ₀.
fn pendulum(theta0: f64, dt: f64) -> (Ggl, f64) {
    pendulum_with(theta0, dt, Scheme::Bdf1)
}

/// [`pendulum`] integrated with `scheme`; also returns I_O/(m g d) = 1/ω².
fn pendulum_with(theta0: f64, dt: f64, scheme: Scheme) -> (Ggl, f64) {
    let (m, d, jzz) = (2.0, 0.8, 0.05);
    let mut sys = System::new([0.0, -G, 0.0]);
    let e = from_axis_angle([0.0, 0.0, 1.0], theta0).unwrap();
    let body = sys.add_body(
        Body::rigid(m, [[0.03, 0.0, 0.0], [0.0, 0.04, 0.0], [0.0, 0.0, jzz]]),
        [d * theta0.sin(), -d * theta0.cos(), 0.0],
        e,
    );
    let on_body = sys.add_marker(Marker::new(Some(body), [0.0, d, 0.0]));
    let on_ground = sys.add_marker(Marker::new(None, [0.0, 0.0, 0.0]));
    sys.add_joint(JointKind::Revolute, on_body, on_ground);
    let ggl = Ggl::with_scheme(sys, dt, 0.0, NewtonSettings::default(), scheme).unwrap();
    let i_o = jzz + m * d * d;
    (ggl, i_o / (m * G * d))
}

/// The angle of the pendulum (from the hanging position) from its centre.
fn angle(ggl: &Ggl) -> f64 {
    ggl.q[0].atan2(-ggl.q[1])
}

/// θ̇ from the centre's position (x, y) = d (sin θ, −cos θ) and velocity.
fn angle_rate(ggl: &Ggl) -> f64 {
    let (x, y) = (ggl.q[0], ggl.q[1]);
    (x * ggl.v[1] - y * ggl.v[0]) / (x * x + y * y)
}

#[test]
fn observed_orders_are_one_two_two_against_the_linearized_pendulum() {
    // θ₀ = 1e-3 rad: the linear solution θ₀ cos ωt is exact up to the frequency shift θ₀²/16
    // (a phase error ωt θ₀²/16 ≈ 2e-7 θ₀ at t = 1 s), far below the smallest discretization
    // error here (≈ 1e-5 θ₀ for the second-order schemes at h = 2.5 ms)
    let (theta0, end) = (1e-3, 1.0);
    let error = |scheme: Scheme, dt: f64| {
        let (mut ggl, ratio) = pendulum_with(theta0, dt, scheme);
        let omega = 1.0 / ratio.sqrt();
        ggl.run((end / dt).round() as usize, |_, _| {}).unwrap();
        let (theta, rate) = (
            theta0 * (omega * end).cos(),
            -theta0 * omega * (omega * end).sin(),
        );
        // phase-space distance, smooth in h (unlike the error at a zero crossing)
        ((angle(&ggl) - theta).powi(2) + ((angle_rate(&ggl) - rate) / omega).powi(2)).sqrt()
            / theta0
    };
    for (scheme, order) in SCHEMES.iter().zip([1.0, 2.0, 2.0]) {
        let errors = [1e-2, 5e-3, 2.5e-3].map(|dt| error(*scheme, dt));
        eprintln!("{scheme:?}: {errors:?}");
        for pair in errors.windows(2) {
            let observed = (pair[0] / pair[1]).log2();
            // e(h) = C h^p (1 + O(ωh)) with ωh ≤ 0.035: the next term moves log₂ of the
            // ratio by ≲ 0.05, so ±0.1 bounds the observed order
            assert!(
                (observed - order).abs() < 0.1,
                "{scheme:?}: observed order {observed} ({errors:?})"
            );
        }
    }
}

#[test]
fn energy_without_damping_bdf1_dissipates_bdf2_and_generalized_alpha_keep_it_to_second_order() {
    // linear-oscillator estimates at ω₀² = m g d / I_O: BDF1 loses energy at the rate ω²h
    // per second, BDF2 at ω⁴h³/2 and generalized-α (ρ∞ = 0.8) at O(ω⁴h³) (1e-7 and 1e-10
    // per second here); at 1 rad the pendulum's nonlinearity and the GGL projection change
    // BDF1's constant by O(1), hence a factor-2 band around ω₀²hT E₀; a second-order scheme
    // keeps a bounded O((ωh)²) energy error on the nonlinear pendulum, so (ω₀h)² = 1.2e-5
    // (relative to m g d) bounds their deviation
    // (measured: BDF1 −1.24e-2, BDF2 ≤ 1.1e-5 of which 5e-6 is its BDF1 start step's loss
    // ω₀²h²E₀, generalized-α ≤ 1.4e-6; relative to m g d, E₀ = 0.46 m g d); the second-order
    // schemes' largest deviation must fall by 4 when h halves (the O(h³) terms move the ratio
    // by ~ωh < 1 %, the sampling of an oscillating maximum by a few %: band 3–5)
    let (theta0, end) = (1.0, 2.0);
    let run = |scheme: Scheme, dt: f64| {
        let (mut ggl, ratio) = pendulum_with(theta0, dt, scheme);
        let scale = 2.0 * G * 0.8;
        let energy = |g: &Ggl| (g.kinetic_energy() + 2.0 * G * g.q[1]) / scale;
        let e0 = energy(&ggl);
        let mut largest: f64 = 0.0;
        ggl.run((end / dt).round() as usize, |g, _| {
            largest = largest.max((energy(g) - e0).abs());
        })
        .unwrap();
        (energy(&ggl) - e0, largest, 1.0 / ratio)
    };
    for scheme in SCHEMES {
        let (change, largest, omega2) = run(scheme, 1e-3);
        eprintln!("{scheme:?}: final ΔE/(mgd) {change:e}, largest {largest:e}");
        match scheme {
            Scheme::Bdf1 => {
                let estimate = omega2 * 1e-3 * end * (1.0 - theta0.cos());
                assert!(
                    change < 0.0 && -change < 2.0 * estimate && -change > 0.5 * estimate,
                    "BDF1 energy change {change:e} vs −{estimate:e}"
                );
            }
            _ => {
                assert!(largest < omega2 * 1e-6, "{scheme:?}: deviation {largest:e}");
                let ratio = run(scheme, 2e-3).1 / largest;
                assert!((3.0..5.0).contains(&ratio), "{scheme:?}: ratio {ratio}");
            }
        }
    }
}

/// Time of the first full period: between the first and third zero crossings of θ.
fn measured_period(ggl: &mut Ggl) -> f64 {
    let mut crossings = Vec::new();
    let mut previous = (ggl.time, angle(ggl));
    while crossings.len() < 3 {
        ggl.step().unwrap();
        let now = (ggl.time, angle(ggl));
        if previous.1 * now.1 < 0.0 {
            let s = previous.1 / (previous.1 - now.1);
            crossings.push(previous.0 + s * (now.0 - previous.0));
        }
        previous = now;
    }
    crossings[2] - crossings[0]
}

/// K(k) = π / (2 AGM(1, √(1 − k²))), the complete elliptic integral of the first kind.
fn elliptic_k(k: f64) -> f64 {
    let (mut a, mut b) = (1.0_f64, (1.0 - k * k).sqrt());
    for _ in 0..30 {
        (a, b) = (0.5 * (a + b), (a * b).sqrt());
    }
    PI / (2.0 * a)
}

#[test]
fn pendulum_small_amplitude_period_is_two_pi_sqrt_i_over_mgd() {
    let theta0 = 0.05;
    let (mut ggl, ratio) = pendulum(theta0, 1e-3);
    let expected = 2.0 * PI * ratio.sqrt();
    let period = measured_period(&mut ggl);
    // finite amplitude adds θ₀²/16 = 1.6e-4; BDF1's phase error is (ωΔt)²/3 ≈ 4e-6
    let err = (period / expected - 1.0).abs();
    assert!(err < 4e-4, "period {period} vs {expected}: {err:e}");
}

#[test]
fn pendulum_large_amplitude_period_matches_the_elliptic_integral() {
    let theta0 = 0.5 * PI;
    let (mut ggl, ratio) = pendulum(theta0, 2e-4);
    let expected = 4.0 * ratio.sqrt() * elliptic_k((0.5 * theta0).sin());
    let period = measured_period(&mut ggl);
    // BDF1 loses amplitude at the rate ω²Δt/2 = 1.2e-3 per second here (0.25 % of θ₀ over the
    // period); at 90° (dT/dθ₀)(θ₀/T) ≈ 0.5, so the measured period is ≈ 1e-3 short
    let err = (period / expected - 1.0).abs();
    assert!(err < 2e-3, "period {period} vs {expected}: {err:e}");
}

#[test]
fn pendulum_energy_and_position_errors_are_first_order_in_the_step() {
    let theta0 = 1.0;
    let end = 1.0;
    let run = |dt: f64| {
        let (mut ggl, _) = pendulum(theta0, dt);
        let energy = |g: &Ggl| g.kinetic_energy() + 2.0 * G * g.q[1];
        let e0 = energy(&ggl);
        let steps = (end / dt).round() as usize;
        ggl.run(steps, |_, _| {}).unwrap();
        (energy(&ggl) - e0, angle(&ggl))
    };
    let (reference_angle, base) = (run(1e-5).1, 4e-3);
    let results: Vec<(f64, f64)> = [base, base / 2.0, base / 4.0].map(run).to_vec();
    for pair in results.windows(2) {
        let energy_ratio = pair[0].0 / pair[1].0;
        let position_ratio = (pair[0].1 - reference_angle) / (pair[1].1 - reference_angle);
        assert!(pair[0].0 < 0.0, "BDF1 dissipates");
        assert!(
            (1.7..2.3).contains(&energy_ratio),
            "energy error ratio {energy_ratio}"
        );
        assert!(
            (1.7..2.3).contains(&position_ratio),
            "position error ratio {position_ratio} {results:?}"
        );
    }
}

/// Adds a planar link of length `length` along its body x axis, centred at `centre` with
/// angle `angle` about z; returns (body, marker at −x end, marker at +x end).
fn link(sys: &mut System, length: f64, centre: [f64; 2], angle: f64) -> (usize, usize, usize) {
    let m = 1.0;
    let j = m * length * length / 12.0;
    let body = sys.add_body(
        Body::rigid(m, [[1e-4, 0.0, 0.0], [0.0, j, 0.0], [0.0, 0.0, j]]),
        [centre[0], centre[1], 0.0],
        from_axis_angle([0.0, 0.0, 1.0], angle).unwrap(),
    );
    let start = sys.add_marker(Marker::new(Some(body), [-0.5 * length, 0.0, 0.0]));
    let end = sys.add_marker(Marker::new(Some(body), [0.5 * length, 0.0, 0.0]));
    (body, start, end)
}

fn polar(length: f64, angle: f64) -> [f64; 2] {
    [length * angle.cos(), length * angle.sin()]
}

#[test]
fn driven_slider_crank_follows_its_closed_form_kinematics() {
    let (a, b, omega) = (0.2, 0.6, 2.0 * PI);
    let theta0: f64 = 0.3;
    let beta0 = (-(a * theta0.sin()) / b).asin();
    let mut sys = System::new([0.0, -G, 0.0]);
    let (_, crank_start, crank_end) = link(&mut sys, a, polar(0.5 * a, theta0), theta0);
    let tip = polar(a, theta0);
    let rod_centre = [
        tip[0] + 0.5 * b * beta0.cos(),
        tip[1] + 0.5 * b * beta0.sin(),
    ];
    let (_, rod_start, rod_end) = link(&mut sys, b, rod_centre, beta0);
    let x0 = tip[0] + b * beta0.cos();
    let slider = sys.add_body(
        Body::rigid(0.5, [[1e-3, 0.0, 0.0], [0.0, 1e-3, 0.0], [0.0, 0.0, 1e-3]]),
        [x0, 0.0, 0.0],
        IDENTITY,
    );
    let slider_pin = sys.add_marker(Marker::new(Some(slider), [0.0; 3]));
    let slider_axis =
        sys.add_marker(Marker::new(Some(slider), [0.0; 3]).with_z_axis([1.0, 0.0, 0.0]));
    let ground_pivot = sys.add_marker(Marker::new(None, [0.0; 3]));
    let ground_axis = sys.add_marker(Marker::new(None, [0.0; 3]).with_z_axis([1.0, 0.0, 0.0]));
    let crank_joint = sys.add_joint(JointKind::Revolute, crank_start, ground_pivot);
    sys.add_joint(JointKind::Revolute, rod_start, crank_end);
    sys.add_joint(JointKind::Revolute, slider_pin, rod_end);
    sys.add_joint(JointKind::Prismatic, slider_axis, ground_axis);
    sys.add_drive(crank_joint, Signal::ramp(omega), DriveKind::Rigid)
        .unwrap();
    let mut ggl = Ggl::new(sys, 1e-3, 0.0, NewtonSettings::default()).unwrap();
    assert!(
        !ggl.redundant.is_empty(),
        "a planar loop in 3-D has redundant rows"
    );
    let mut worst: f64 = 0.0;
    ggl.run(1000, |g, report| {
        let theta = theta0 + omega * report.time;
        let x = a * theta.cos() + (b * b - (a * theta.sin()).powi(2)).sqrt();
        worst = worst.max((g.marker_position(slider_pin)[0] - x).abs());
        assert!(report.constraint_residual < 1e-9);
    })
    .unwrap();
    assert!(worst < 1e-8, "slider position error {worst:e}");
}

#[test]
fn driven_four_bar_follows_its_loop_equations_and_reports_redundancy() {
    let (a, b, c, d) = (0.3, 0.8, 0.6, 0.7);
    let omega = 3.0;
    let theta0: f64 = 1.0;
    // rocker tip C: the intersection of |C − B| = b and |C − D| = c above the ground line
    let coupler_point = |theta: f64| {
        let bp = polar(a, theta);
        let (dx, dy) = (d - bp[0], -bp[1]);
        let l = (dx * dx + dy * dy).sqrt();
        let along = (b * b - c * c + l * l) / (2.0 * l);
        let h = (b * b - along * along).sqrt();
        let (ux, uy) = (dx / l, dy / l);
        [bp[0] + along * ux - h * uy, bp[1] + along * uy + h * ux]
    };
    let bp = polar(a, theta0);
    let cp = coupler_point(theta0);
    let mut sys = System::new([0.0, -G, 0.0]);
    let (_, crank_start, crank_end) = link(&mut sys, a, polar(0.5 * a, theta0), theta0);
    let coupler_angle = (cp[1] - bp[1]).atan2(cp[0] - bp[0]);
    let (_, coupler_start, coupler_end) = link(
        &mut sys,
        b,
        [0.5 * (bp[0] + cp[0]), 0.5 * (bp[1] + cp[1])],
        coupler_angle,
    );
    let rocker_angle = (cp[1]).atan2(cp[0] - d);
    let (_, rocker_start, rocker_end) =
        link(&mut sys, c, [0.5 * (d + cp[0]), 0.5 * cp[1]], rocker_angle);
    let a_pivot = sys.add_marker(Marker::new(None, [0.0; 3]));
    let d_pivot = sys.add_marker(Marker::new(None, [d, 0.0, 0.0]));
    let crank_joint = sys.add_joint(JointKind::Revolute, crank_start, a_pivot);
    sys.add_joint(JointKind::Revolute, coupler_start, crank_end);
    sys.add_joint(JointKind::Revolute, rocker_end, coupler_end);
    sys.add_joint(JointKind::Revolute, rocker_start, d_pivot);
    sys.add_drive(crank_joint, Signal::ramp(omega), DriveKind::Rigid)
        .unwrap();
    let mut ggl = Ggl::new(sys, 1e-3, 0.0, NewtonSettings::default()).unwrap();
    // 3 links × 6 − 4 revolutes × 5 − 1 drive = −3: three rows are redundant
    assert_eq!(ggl.redundant.len(), 3, "{:?}", ggl.redundant);
    let mut worst: f64 = 0.0;
    ggl.run(500, |g, report| {
        let expected = coupler_point(theta0 + omega * report.time);
        let p = g.marker_position(coupler_end);
        worst = worst
            .max((p[0] - expected[0]).abs())
            .max((p[1] - expected[1]).abs());
    })
    .unwrap();
    assert!(worst < 1e-8, "coupler point error {worst:e}");
    assert!(ggl.drive_effort(0).is_finite());
}

#[test]
fn free_tumbling_body_keeps_its_angular_momentum_and_unit_euler_parameters() {
    let j = [[1.0, 0.0, 0.0], [0.0, 2.0, 0.0], [0.0, 0.0, 3.0]];
    let omega0 = [0.3, 0.1, 2.0];
    let run = |dt: f64| {
        let mut sys = System::new([0.0; 3]);
        let e0 = from_axis_angle([1.0, 1.0, 0.0], 0.4).unwrap();
        let body = sys.add_body(Body::rigid(1.0, j), [0.0; 3], e0);
        sys.set_initial_velocity(body, [0.0; 3], omega0);
        let mut ggl = Ggl::new(sys, dt, 0.0, NewtonSettings::default()).unwrap();
        let momentum = |g: &Ggl| {
            let e = [g.q[3], g.q[4], g.q[5], g.q[6]];
            let e_dot = [g.v[3], g.v[4], g.v[5], g.v[6]];
            let w = paraflex::geometry::euler_parameters::body_angular_velocity(&e, &e_dot);
            let a = paraflex::geometry::euler_parameters::rotation_matrix(&e);
            let hb = [j[0][0] * w[0], j[1][1] * w[1], j[2][2] * w[2]];
            paraflex::geometry::mat3::mul_vec(&a, hb)
        };
        let h0 = momentum(&ggl);
        let mut norm_error: f64 = 0.0;
        ggl.run((1.0 / dt).round() as usize, |g, _| {
            let n: f64 = g.q[3..7].iter().map(|x| x * x).sum();
            norm_error = norm_error.max((n - 1.0).abs());
        })
        .unwrap();
        let h1 = momentum(&ggl);
        let drift = (0..3).map(|i| (h1[i] - h0[i]).powi(2)).sum::<f64>().sqrt();
        let size = (0..3).map(|i| h0[i] * h0[i]).sum::<f64>().sqrt();
        (drift / size, norm_error)
    };
    let (coarse, norm_coarse) = run(2e-3);
    let (fine, _) = run(1e-3);
    assert!(norm_coarse < 1e-10, "|e|² − 1 = {norm_coarse:e}");
    // BDF1 does not conserve momentum exactly: the drift is first order in Δt
    assert!(coarse < 0.05, "relative momentum drift {coarse:e}");
    let ratio = coarse / fine;
    assert!(
        (1.6..2.4).contains(&ratio),
        "drift ratio {ratio} ({coarse:e}, {fine:e})"
    );
}

#[test]
fn a_step_that_does_not_converge_names_time_residual_and_constraint() {
    let (ggl, _) = pendulum(1.0, 1e-2);
    let settings = NewtonSettings {
        max_iterations: 1,
        tolerance: 1e-15,
        ..NewtonSettings::default()
    };
    let mut ggl = Ggl::new(ggl.system, 1e-2, 0.0, settings).unwrap();
    let message = ggl.step().unwrap_err().to_string();
    assert!(
        message.starts_with("step to t = 0.01 did not converge in 1 Newton iterations"),
        "{message}"
    );
    assert!(message.contains("worst constraint"), "{message}");
}

#[test]
fn a_drive_on_a_spherical_joint_is_refused() {
    let mut sys = System::new([0.0; 3]);
    let body = sys.add_body(
        Body::rigid(1.0, [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]),
        [0.0; 3],
        IDENTITY,
    );
    let a = sys.add_marker(Marker::new(Some(body), [0.0; 3]));
    let b = sys.add_marker(Marker::new(None, [0.0; 3]));
    let joint = sys.add_joint(JointKind::Spherical, a, b);
    let err = sys
        .add_drive(joint, Signal::constant(0.0), DriveKind::Rigid)
        .unwrap_err();
    assert!(
        err.to_string()
            .contains("Spherical joint has no coordinate to drive"),
        "{err}"
    );
}

#[test]
fn a_four_bar_that_cannot_close_names_its_violated_joints() {
    // crank 0.3 + coupler 0.2 + rocker 0.2 < ground 1.5: no configuration closes the loop
    // (the guess is not collinear, so the redundancy test sees the planar loop's rank)
    let mut sys = System::new([0.0; 3]);
    let (_, crank_start, crank_end) = link(&mut sys, 0.3, [0.1, 0.1], 0.5);
    let (_, coupler_start, coupler_end) = link(&mut sys, 0.2, [0.4, 0.2], -0.3);
    let (_, rocker_start, rocker_end) = link(&mut sys, 0.2, [1.4, 0.1], 1.0);
    let a_pivot = sys.add_marker(Marker::new(None, [0.0; 3]));
    let d_pivot = sys.add_marker(Marker::new(None, [1.5, 0.0, 0.0]));
    sys.add_joint(JointKind::Revolute, crank_start, a_pivot);
    sys.add_joint(JointKind::Revolute, coupler_start, crank_end);
    sys.add_joint(JointKind::Revolute, rocker_start, coupler_end);
    sys.add_joint(JointKind::Revolute, rocker_end, d_pivot);
    let message = match Ggl::new(sys, 1e-3, 0.0, NewtonSettings::default()) {
        Err(e) => e.to_string(),
        Ok(_) => panic!("the loop cannot close"),
    };
    assert!(
        message.starts_with("kinematic assembly at t = 0 did not converge"),
        "{message}"
    );
    for joint in 0..4 {
        assert!(
            message.contains(&format!("joint {joint} (Revolute) row 0 (|Φ| = ")),
            "{message}"
        );
    }
}

#[test]
fn a_body_spun_about_its_intermediate_axis_flips_through_every_orientation() {
    // the intermediate axis is unstable (Dzhanibekov): a spin 2 rad/s about body y with a
    // 1 % perturbation turns the body over repeatedly, so its orientation passes through the
    // Euler-angle singularities (|A₁₃| = 1 for x-y-z angles) that Euler parameters do not have
    let j = [[1.0, 0.0, 0.0], [0.0, 2.0, 0.0], [0.0, 0.0, 3.0]];
    for scheme in SCHEMES {
        let mut sys = System::new([0.0; 3]);
        let body = sys.add_body(Body::rigid(1.0, j), [0.0; 3], IDENTITY);
        sys.set_initial_velocity(body, [0.0; 3], [0.02, 2.0, 0.0]);
        let mut ggl = Ggl::with_scheme(sys, 2e-3, 0.0, NewtonSettings::default(), scheme).unwrap();
        let e0 = ggl.kinetic_energy();
        let (mut lowest_yy, mut largest_13, mut norm_error) = (1.0_f64, 0.0_f64, 0.0_f64);
        ggl.run(5000, |g, _| {
            let e = [g.q[3], g.q[4], g.q[5], g.q[6]];
            let a = paraflex::geometry::euler_parameters::rotation_matrix(&e);
            lowest_yy = lowest_yy.min(a[1][1]);
            largest_13 = largest_13.max(a[0][2].abs());
            norm_error = norm_error.max((e.iter().map(|x| x * x).sum::<f64>() - 1.0).abs());
        })
        .unwrap();
        let energy = ggl.kinetic_energy() / e0 - 1.0;
        eprintln!("{scheme:?}: A_yy min {lowest_yy}, |A13| max {largest_13}, ΔT/T {energy:e}");
        assert!(
            lowest_yy < -0.99,
            "{scheme:?}: the y axis did not turn over"
        );
        assert!(largest_13 > 0.99, "{scheme:?}: no pass near gimbal lock");
        assert!(norm_error < 1e-10, "{scheme:?}: |e|² − 1 = {norm_error:e}");
        assert!(energy.is_finite());
    }
}

#[test]
fn a_four_bar_guessed_straight_is_refused_naming_the_rows_lost_at_the_dead_centre() {
    // all three links drawn along the x axis: there Φ_q loses in-plane rank, so the rank
    // test removes an in-plane row besides the three out-of-plane ones; the assembly cannot
    // leave the line (no first-order method picks elbow up or down) and the removed row
    // stays violated by the loop's length mismatch 0.3 + 0.8 − 0.6 − 0.7 = −0.2
    let (a, b, c, d) = (0.3, 0.8, 0.6, 0.7);
    let mut sys = System::new([0.0, -G, 0.0]);
    let (_, crank_start, crank_end) = link(&mut sys, a, [0.5 * a, 0.0], 0.0);
    let (_, coupler_start, coupler_end) = link(&mut sys, b, [a + 0.5 * b, 0.0], 0.0);
    let (_, rocker_start, rocker_end) = link(&mut sys, c, [d + 0.5 * c, 0.0], 0.0);
    let a_pivot = sys.add_marker(Marker::new(None, [0.0; 3]));
    let d_pivot = sys.add_marker(Marker::new(None, [d, 0.0, 0.0]));
    sys.add_joint(JointKind::Revolute, crank_start, a_pivot);
    sys.add_joint(JointKind::Revolute, coupler_start, crank_end);
    sys.add_joint(JointKind::Revolute, rocker_end, coupler_end);
    sys.add_joint(JointKind::Revolute, rocker_start, d_pivot);
    let message = match Ggl::new(sys, 1e-3, 0.0, NewtonSettings::default()) {
        Err(e) => e.to_string(),
        Ok(_) => panic!("a straight guess of a closing loop must not run"),
    };
    assert!(
        message.starts_with("kinematic assembly at t = 0 did not converge"),
        "{message}"
    );
    assert!(
        message.contains("joint 3 (Revolute) row 0 (|Φ| = "),
        "{message}"
    );
}
