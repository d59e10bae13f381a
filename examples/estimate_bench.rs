//! Speed of the augmented EKF on a pROM artifact with sensors, e.g. the blade
//! pROM of decks/estimate/blade_prom_sensors.dat: filter steps per second in the physical, the
//! modal and — where the modes do not diagonalize the pROM — the re-diagonalized modal
//! coordinates with τ = 1e-2 and 1e-3 ([`paraflex::estimate::filter`]), each with the BDF1 and the
//! trapezoidal prediction, and the estimation error for a few covariance settings (thesis §8.5.2,
//! eq. 8.30–8.31; BDF1 prediction).
//!
//!     cargo run --release --example estimate_bench -- blade_prom.h5 [REPEATS] [TRUTH.h5]
//!
//! Data: the prediction's own integrator — BDF1, or generalized-α with ρ∞ = 1 (the trapezoidal
//! rule; its load at t_k − Δt/2 instead of the average of t_{k−1} and t_k, a difference of order
//! Δt² ω²) — on the pROM (or on the pROM TRUTH.h5, e.g. a larger basis of the same model:
//! the filter then also meets its own truncation error; sensors and input matched by name) at
//! the nominal parameters under 5 N at 20 Hz on input 71:3 (thesis
//! Table 8.1), 1 s at 0.1 ms, every sensor plus seeded Gaussian noise (1e-7 on DISP/STRAIN,
//! 1e-3 m/s² on ACCEL, as §8.6) — the model of SOL ESTIMATE's data tools without the deck and
//! file round trip. Cases: E (+25 %), E and ρ (+25 %, −30 %), E and the tip force unknown.
//! Speed: the best of REPEATS (default 3) runs of the filter loop alone, in wall-clock time (what
//! real time is measured against: it includes any wait for a thread pool) and, beside it, in CPU
//! time of all the process's threads (Linux /proc/self/task/*/schedstat: the time they were on a
//! core, which other processes sharing the machine do not inflate). Error: average relative error of
//! each parameter over the last 20 % of the window (Table 8.2 format).

use std::time::Instant;

use faer::Mat;
use paraflex::dynamics::integrators::{LinearSystem, Method, integrate};
use paraflex::estimate::{Coordinates, Filter, FilterSetup, Prediction, SensorRows, covariance};
use paraflex::io::{read_prom, read_prom_inputs, read_prom_sensors};
use paraflex::linalg::random::SplitMix64;

const DT: f64 = 1e-4;
const STEPS: usize = 10_000;
const INPUT: &str = "71:3";

/// One estimation case: unknown parameters with (initial factor, δ in Hz, P0 factor of INIT²),
/// the unknown input (ω_u Hz, a_u N), measured sensors.
struct Case {
    name: &'static str,
    params: Vec<(&'static str, f64, f64, f64)>,
    input: Option<(f64, f64)>,
    sensors: Vec<&'static str>,
}

fn main() -> Result<(), String> {
    let args: Vec<String> = std::env::args().collect();
    let path = args
        .get(1)
        .ok_or("usage: estimate_bench PROM.h5 [REPEATS]")?;
    let repeats: usize = args
        .get(2)
        .map_or(Ok(3), |s| s.parse())
        .map_err(|e| format!("REPEATS: {e}"))?;
    let (prom, sensors, shape) = load_prom(path)?;
    let n = prom.size();
    let truth: Vec<f64> = prom.parameters.iter().map(|p| p.nominal).collect();
    let param = |name: &str| {
        prom.parameters
            .iter()
            .position(|p| p.name.eq_ignore_ascii_case(name))
            .ok_or(format!("{path}: no parameter {name}"))
    };
    let load = sine_load(&shape);
    let zeros = vec![0.0; n];

    // data: the prediction's integrator on the truth pROM at its nominal parameters, every
    // sensor, seeded noise
    let truth_path = args.get(3).unwrap_or(path);
    let data_of = |method: Method| -> Result<(Vec<String>, Vec<Vec<f64>>), String> {
        let (model, sensors, shape) = load_prom(truth_path)?;
        let nominal: Vec<f64> = model.parameters.iter().map(|p| p.nominal).collect();
        let mut at = model.workspace();
        model
            .evaluate(&nominal, &mut at)
            .map_err(|e| e.to_string())?;
        let sys = LinearSystem {
            mass: at.mass(),
            damping: at.damping(),
            stiffness: at.stiffness(),
        };
        let mut noise = SplitMix64::new(1);
        let mut data: Vec<Vec<f64>> = Vec::new();
        let zeros = vec![0.0; model.size()];
        integrate(
            sys,
            method,
            DT,
            STEPS,
            &zeros,
            &zeros,
            sine_load(&shape),
            |st| {
                let mut y = vec![0.0; sensors.len()];
                sensors.evaluate(st.q, st.v, st.a, &mut y);
                let sigma = |k: &str| if k == "ACCEL" { 1e-3 } else { 1e-7 };
                data.push(
                    y.iter()
                        .zip(&sensors.kinds)
                        .map(|(y, k)| y + sigma(k) * noise.normal())
                        .collect(),
                );
            },
        )
        .map_err(|e| e.to_string())?;
        Ok((sensors.names, data))
    };
    let data_bdf1 = data_of(Method::Bdf1)?;
    let data_trapezoidal = data_of(Method::GeneralizedAlpha { rho_inf: 1.0 })?;

    let run = |case: &Case,
               coordinates: Coordinates,
               prediction: Prediction|
     -> Result<(String, [f64; 2], Vec<f64>), String> {
        let (data_names, data) = match prediction {
            Prediction::Bdf1 => &data_bdf1,
            Prediction::Trapezoidal => &data_trapezoidal,
        };
        let rows: Vec<usize> = case
            .sensors
            .iter()
            .map(|s| {
                sensors
                    .names
                    .iter()
                    .position(|x| x == s)
                    .ok_or(format!("no sensor {s}"))
            })
            .collect::<Result<_, _>>()?;
        let columns: Vec<usize> = case
            .sensors
            .iter()
            .map(|s| {
                data_names
                    .iter()
                    .position(|x| x == s)
                    .ok_or(format!("{truth_path}: no sensor {s}"))
            })
            .collect::<Result<_, _>>()?;
        let measured = sensors.select(&rows);
        let mut p = truth.clone();
        let mut unknown = Vec::new();
        for (name, factor, ..) in &case.params {
            let j = param(name)?;
            p[j] = factor * truth[j];
            unknown.push(j);
        }
        let nu = usize::from(case.input.is_some());
        let setup = FilterSetup {
            prom: prom.clone(),
            p: p.clone(),
            unknown_params: unknown.clone(),
            s_un: Mat::from_fn(n, nu, |i, _| shape[i]),
            r: measured
                .kinds
                .iter()
                .map(|k| if k == "ACCEL" { 1e-6 } else { 1e-14 })
                .collect(),
            measured,
            dt: DT,
            q_state: f64::EPSILON,
            q_inputs: case
                .input
                .iter()
                .map(|&(w, a)| covariance::input(DT, w, a))
                .collect(),
            q_params: case
                .params
                .iter()
                .zip(&unknown)
                .map(|((_, _, delta, _), &j)| covariance::parameter(DT, *delta, p[j]))
                .collect(),
            q0: zeros.clone(),
            v0: zeros.clone(),
            u0: vec![0.0; nu],
            p0_state: 1e-20,
            p0_inputs: case.input.iter().map(|&(_, a)| a * a).collect(),
            p0_params: case
                .params
                .iter()
                .zip(&unknown)
                .map(|((_, _, _, p0), &j)| p0 * p[j] * p[j])
                .collect(),
            coordinates,
            prediction,
        };
        let mut best = [0.0_f64; 2];
        let mut errors = Vec::new();
        let mut label = String::new();
        for _ in 0..repeats {
            let mut filter = Filter::new(setup.clone()).map_err(|e| e.to_string())?;
            let (mut f, mut y) = (vec![0.0; n], vec![0.0; rows.len()]);
            let (mut sums, mut count) = (vec![0.0; unknown.len()], 0);
            let tail = STEPS - STEPS / 5;
            let started = (Instant::now(), cpu_seconds());
            for (k, sample) in data.iter().enumerate().skip(1) {
                if case.input.is_none() {
                    load(k as f64 * DT, &mut f);
                }
                y.iter_mut()
                    .zip(&columns)
                    .for_each(|(y, &c)| *y = sample[c]);
                filter
                    .step(&f, &y)
                    .map_err(|e| format!("{}: {e}", case.name))?;
                if k > tail {
                    count += 1;
                    for (s, &j) in sums.iter_mut().zip(&unknown) {
                        *s += filter.parameters()[j] / truth[j] - 1.0;
                    }
                }
            }
            let wall = started.0.elapsed().as_secs_f64();
            let cpu = match (started.1, cpu_seconds()) {
                (Some(a), Some(b)) => b - a,
                _ => wall,
            };
            best = [
                best[0].max(STEPS as f64 / wall),
                best[1].max(STEPS as f64 / cpu),
            ];
            errors = sums.iter().map(|s| 100.0 * s / f64::from(count)).collect();
            label = match (filter.modal(), filter.rediagonalizations(), coordinates) {
                (false, ..) => "physical".into(),
                (true, Some(count), Coordinates::Rediagonalized(tolerance)) => {
                    format!("τ {tolerance:.0e} ({count})")
                }
                (true, ..) => "modal".into(),
            };
        }
        Ok((label, best, errors))
    };

    let cases = [
        Case {
            name: "E",
            params: vec![("E", 1.25, 1e-3, 1.0)],
            input: None,
            sensors: vec!["D71", "D93"],
        },
        Case {
            name: "E, RHO",
            params: vec![("E", 1.25, 1.0, 1.0), ("RHO", 0.7, 1.0, 1.0)],
            input: None,
            sensors: vec!["D71", "D93", "A93"],
        },
        Case {
            name: "E, input",
            params: vec![("E", 1.25, 1e-3, 1e20 / (1.25f64 * 116.04e9).powi(2))],
            input: Some((80.0, 5.0)),
            sensors: vec!["D71", "D93"],
        },
    ];
    if truth_path != path {
        println!("data from {truth_path}");
    }
    println!(
        "n_r = {n}; {STEPS} steps of {DT} s (real time: {:.0} steps/s); best of {repeats}",
        1.0 / DT
    );
    println!(
        "(coordinates: τ = re-diagonalized modal coordinates with that tolerance, re-diagonalizations in parentheses)"
    );
    println!("(µs/step: wall clock; CPU: of all threads)");
    println!(
        "{:<10} {:>4} {:>16} {:>11} {:>12} {:>9} {:>9} {:>9}  avg error [%]",
        "case", "N", "coordinates", "prediction", "steps/s", "µs/step", "CPU µs", "× real"
    );
    for case in &cases {
        let mut modes_exact = false;
        for coordinates in [
            Coordinates::Physical,
            Coordinates::Auto,
            Coordinates::Rediagonalized(1e-2),
            Coordinates::Rediagonalized(1e-3),
        ] {
            if modes_exact && matches!(coordinates, Coordinates::Rediagonalized(_)) {
                continue; // the modes diagonalize the pROM: the same run as Auto's
            }
            for (prediction, name) in [
                (Prediction::Bdf1, "BDF1"),
                (Prediction::Trapezoidal, "TRAP"),
            ] {
                let (label, [speed, cpu], errors) = run(case, coordinates, prediction)?;
                modes_exact |= label == "modal";
                let big_n = 2 * n + case.params.len() + usize::from(case.input.is_some());
                let errors: Vec<String> = case
                    .params
                    .iter()
                    .zip(&errors)
                    .map(|((p, ..), e)| format!("{p} {e:+.4}"))
                    .collect();
                println!(
                    "{:<10} {big_n:>4} {label:>16} {name:>11} {speed:>12.0} {:>9.2} {:>9.2} {:>9.1}  {}",
                    case.name,
                    1e6 / speed,
                    1e6 / cpu,
                    speed * DT,
                    errors.join(", ")
                );
            }
        }
    }
    println!(
        "\ncovariance settings (modal path when it applies, BDF1): δ in Hz (eq. 8.31), P0 as a factor of INIT²"
    );
    println!(
        "{:<10} {:>10} {:>10} {:>12}  avg error [%]",
        "case", "δ", "P0", "steps/s"
    );
    for (name, delta, p0) in [
        ("E", 1e-3, 1.0),
        ("E", 1.0, 1.0),
        ("E", 1e-3, 1e-4),
        ("E, RHO", 1.0, 1.0),
        ("E, RHO", 10.0, 1.0),
        ("E, RHO", 1.0, 1e-2),
    ] {
        let base = cases.iter().find(|c| c.name == name).expect("case");
        let case = Case {
            params: base
                .params
                .iter()
                .map(|&(p, f, _, _)| (p, f, delta, p0))
                .collect(),
            sensors: base.sensors.clone(),
            input: None,
            name: base.name,
        };
        let (_, [speed, _], errors) = run(&case, Coordinates::Auto, Prediction::Bdf1)?;
        let errors: Vec<String> = case
            .params
            .iter()
            .zip(&errors)
            .map(|((p, ..), e)| format!("{p} {e:+.4}"))
            .collect();
        println!(
            "{name:<10} {delta:>10.0e} {p0:>10.0e} {speed:>12.0}  {}",
            errors.join(", ")
        );
    }
    Ok(())
}

/// The known load f(t) = 5 N sin(2π 20 Hz t) on the reduced input shape `shape` (thesis Table 8.1).
fn sine_load(shape: &[f64]) -> impl Fn(f64, &mut [f64]) + '_ {
    move |t, f| {
        let force = 5.0 * (2.0 * std::f64::consts::PI * 20.0 * t).sin();
        f.iter_mut().zip(shape).for_each(|(f, s)| *f = force * s);
    }
}

/// The pROM of `path`, its sensor rows and the reduced shape of input [`INPUT`].
fn load_prom(path: &str) -> Result<(paraflex::rom::prom::Prom, SensorRows, Vec<f64>), String> {
    let (prom, _) = read_prom(path).map_err(|e| e.to_string())?;
    let n = prom.size();
    let (inputs, s_r) = read_prom_inputs(path, n).map_err(|e| e.to_string())?;
    let (names, kinds, h) = read_prom_sensors(path, n).map_err(|e| e.to_string())?;
    let sensors = SensorRows::new(names, kinds, h)?;
    let input = inputs
        .iter()
        .position(|x| x == INPUT)
        .ok_or(format!("{path}: no input {INPUT}"))?;
    Ok((prom, sensors, (0..n).map(|i| s_r[(i, input)]).collect()))
}

/// Seconds the threads of this process have run on a core (Linux: the sum over
/// /proc/self/task/*/schedstat, so work that a library hands to a thread pool counts), None
/// elsewhere.
fn cpu_seconds() -> Option<f64> {
    let mut total = 0.0;
    for task in std::fs::read_dir("/proc/self/task").ok()? {
        let text = std::fs::read_to_string(task.ok()?.path().join("schedstat")).ok()?;
        total += text.split_whitespace().next()?.parse::<f64>().ok()? * 1e-9;
    }
    Some(total)
}
