//! Step size against error against time for the GGL integrators (BDF1, BDF2, generalized-α
//! with ρ∞ = 0.8; [`paraflex::multibody::scheme`]) on a rigid four-bar swinging freely under
//! gravity: crank 0.3 m, coupler 0.8 m, rocker 0.6 m, ground 0.7 m (a Grashof crank-rocker),
//! three 1 kg bars released at rest with the crank at 1 rad, 1 s of motion.
//!
//!     cargo run --release --example multibody_bench
//!
//! Error: the largest distance over the run between the coupler–rocker pin and its position
//! in a reference run (generalized-α, Δt = 10 µs, whose own error is below 1e-8 m by the
//! second-order trend of the table), sampled every 10 ms. Time: wall clock of the step loop
//! alone, the best of three runs. Also printed: Newton iterations and factorizations per step
//! (the factorization is kept across steps while it contracts).

use std::time::Instant;

use paraflex::geometry::euler_parameters::from_axis_angle;
use paraflex::multibody::{Body, Ggl, JointKind, Marker, NewtonSettings, Scheme, System};

const END: f64 = 1.0;
const SAMPLE: f64 = 1e-2;

/// Adds a bar of length `length` along its body x axis centred at `centre`, turned by `angle`
/// about z; returns the markers at its −x and +x ends.
fn bar(sys: &mut System, length: f64, centre: [f64; 2], angle: f64) -> (usize, usize) {
    let j = length * length / 12.0;
    let body = sys.add_body(
        Body::rigid(1.0, [[1e-4, 0.0, 0.0], [0.0, j, 0.0], [0.0, 0.0, j]]),
        [centre[0], centre[1], 0.0],
        from_axis_angle([0.0, 0.0, 1.0], angle).expect("unit axis"),
    );
    (
        sys.add_marker(Marker::new(Some(body), [-0.5 * length, 0.0, 0.0])),
        sys.add_marker(Marker::new(Some(body), [0.5 * length, 0.0, 0.0])),
    )
}

/// The four-bar at crank angle θ₀ and the marker of the coupler–rocker pin.
fn four_bar() -> (System, usize) {
    let (a, b, c, d, theta0) = (0.3_f64, 0.8, 0.6, 0.7, 1.0_f64);
    let crank_tip = [a * theta0.cos(), a * theta0.sin()];
    // the pin: |P − B| = b and |P − D| = c, above the ground line
    let (dx, dy) = (d - crank_tip[0], -crank_tip[1]);
    let l = dx.hypot(dy);
    let along = (b * b - c * c + l * l) / (2.0 * l);
    let h = (b * b - along * along).sqrt();
    let (ux, uy) = (dx / l, dy / l);
    let pin = [
        crank_tip[0] + along * ux - h * uy,
        crank_tip[1] + along * uy + h * ux,
    ];
    let mut sys = System::new([0.0, -9.81, 0.0]);
    let (crank_start, crank_end) = bar(
        &mut sys,
        a,
        [0.5 * crank_tip[0], 0.5 * crank_tip[1]],
        theta0,
    );
    let (coupler_start, coupler_end) = bar(
        &mut sys,
        b,
        [0.5 * (crank_tip[0] + pin[0]), 0.5 * (crank_tip[1] + pin[1])],
        (pin[1] - crank_tip[1]).atan2(pin[0] - crank_tip[0]),
    );
    let (rocker_start, rocker_end) = bar(
        &mut sys,
        c,
        [0.5 * (d + pin[0]), 0.5 * pin[1]],
        pin[1].atan2(pin[0] - d),
    );
    let a_pivot = sys.add_marker(Marker::new(None, [0.0; 3]));
    let d_pivot = sys.add_marker(Marker::new(None, [d, 0.0, 0.0]));
    sys.add_joint(JointKind::Revolute, crank_start, a_pivot);
    sys.add_joint(JointKind::Revolute, coupler_start, crank_end);
    sys.add_joint(JointKind::Revolute, rocker_end, coupler_end);
    sys.add_joint(JointKind::Revolute, rocker_start, d_pivot);
    (sys, coupler_end)
}

struct Run {
    pins: Vec<[f64; 3]>,
    seconds: f64,
    iterations: usize,
    factorizations: usize,
}

/// Integrates 1 s with `scheme` and step `dt`, sampling the pin every 10 ms.
fn run(scheme: Scheme, dt: f64) -> Run {
    let (sys, pin) = four_bar();
    let mut ggl = Ggl::with_scheme(sys, dt, 0.0, NewtonSettings::default(), scheme)
        .expect("the four-bar assembles");
    let steps = (END / dt).round() as usize;
    let every = (SAMPLE / dt).round() as usize;
    let mut out = Run {
        pins: Vec::with_capacity(steps / every),
        seconds: 0.0,
        iterations: 0,
        factorizations: 0,
    };
    let start = Instant::now();
    for k in 1..=steps {
        let report = ggl.step().expect("the step converges");
        out.iterations += report.iterations;
        out.factorizations += report.factorizations;
        if k % every == 0 {
            out.pins.push(ggl.marker_position(pin));
        }
    }
    out.seconds = start.elapsed().as_secs_f64();
    out
}

fn main() {
    let alpha = Scheme::GeneralizedAlpha {
        spectral_radius: 0.8,
    };
    let reference = run(alpha, 1e-5).pins;
    println!(
        "| scheme | Δt (ms) | pin error (m) | wall (ms) | Newton it./step | factorizations/step |"
    );
    println!("|---|---|---|---|---|---|");
    for (name, scheme) in [
        ("BDF1", Scheme::Bdf1),
        ("BDF2", Scheme::Bdf2),
        ("gen-α 0.8", alpha),
    ] {
        // steps that divide the 10 ms sampling interval
        for dt in [5e-3, 2.5e-3, 1.25e-3, 6.25e-4, 3.125e-4] {
            let best = (0..3)
                .map(|_| run(scheme, dt))
                .min_by(|x, y| x.seconds.total_cmp(&y.seconds))
                .expect("three runs");
            let error = best
                .pins
                .iter()
                .zip(&reference)
                .map(|(p, r)| (0..3).map(|i| (p[i] - r[i]).powi(2)).sum::<f64>().sqrt())
                .fold(0.0, f64::max);
            let steps = (END / dt).round();
            println!(
                "| {name} | {} | {error:.2e} | {:.1} | {:.2} | {:.3} |",
                dt * 1e3,
                best.seconds * 1e3,
                best.iterations as f64 / steps,
                best.factorizations as f64 / steps
            );
        }
    }
}
