//! `SOL FMB` decks against closed forms: a rigid compound pendulum (elliptic period, energy
//! with BDF1's first-order numerical dissipation) and the same rod driven at a constant rate
//! (drive torque, power and actuation energy against the statics of the rod).

mod common;

use std::path::Path;

use common::{root, run_deck};

fn read(g: &hdf5_metno::Group, name: &str) -> Vec<f64> {
    g.dataset(name)
        .unwrap_or_else(|e| panic!("{name}: {e}"))
        .read_raw()
        .unwrap()
}

/// Runs the deck text and returns its `/results/1/fmb` group's file.
fn run_text(text: &str) -> (hdf5_metno::File, tempfile::TempDir) {
    let (r, dir) = run_deck(text);
    r.unwrap_or_else(|e| panic!("{e}"));
    let file = hdf5_metno::File::open(dir.path().join("out.h5")).expect("open");
    (file, dir)
}

fn deck(name: &str) -> String {
    std::fs::read_to_string(root().join(Path::new("decks/fmb").join(name))).expect("deck")
}

/// Times where the series crosses zero (linear interpolation between rows).
fn zero_crossings(t: &[f64], x: &[f64]) -> Vec<f64> {
    (1..x.len())
        .filter(|&i| x[i - 1].signum() != x[i].signum() && x[i - 1] != 0.0)
        .map(|i| t[i - 1] - x[i - 1] * (t[i] - t[i - 1]) / (x[i] - x[i - 1]))
        .collect()
}

const G: f64 = 9.81;
/// Complete elliptic integral of the first kind K(k) at k = sin 45° (A&S table 17.1, m = 0.5).
const K_HALF: f64 = 1.854_074_677_301_372;

/// The rod released horizontal swings with T = 4 √(L/g) K(sin 45°), L = I_pivot/(m d) = 2/3 m.
/// The first quarter period (x of the centre of mass crosses zero) is met to 2e-4 (BDF1's
/// amplitude loss over a quarter swing is ~0.2 %, its effect on the crossing time second
/// order); the full period from two crossings to 1 % (the amplitude has then decayed by a few
/// per cent and a smaller swing is faster). The energy KE + m g y falls by BDF1's numerical
/// dissipation only: less than 10 % of m g d over 2.5 s at Δt = 1 ms, and halving Δt halves it
/// (first order, ratio within [1.8, 2.2]). The pivot's vertical force just after release is
/// m g − m α d = m g / 4 (α = m g d / I_pivot).
#[test]
fn rigid_pendulum_meets_the_elliptic_period_and_dissipates_at_first_order() {
    let text = deck("pendulum_rigid.dat");
    let energy_loss = |text: &str| {
        let (file, _dir) = run_text(text);
        let g = file.group("results/1/fmb").unwrap();
        let t = read(&g, "time");
        let ke = read(&g, "sensors/KE");
        let y = read(&g, "sensors/YCM");
        let x = read(&g, "sensors/XCM");
        let e: Vec<f64> = ke.iter().zip(&y).map(|(k, y)| k + G * y).collect();
        (
            t,
            x,
            e,
            read(&g, "sensors/PIVOTY"),
            read(&g, "constraint_residual"),
        )
    };
    let (t, x, e, pivot, residual) = energy_loss(&text);
    let l = 2.0 / 3.0;
    let period = 4.0 * (l / G).sqrt() * K_HALF;
    let crossings = zero_crossings(&t, &x);
    assert!(crossings.len() >= 2, "crossings {crossings:?}");
    let quarter = crossings[0];
    assert!(
        (quarter - period / 4.0).abs() < 2e-4 * period,
        "quarter period {quarter} vs {}",
        period / 4.0
    );
    let measured = 2.0 * (crossings[1] - crossings[0]);
    assert!(
        (measured - period).abs() < 1e-2 * period,
        "period {measured} vs {period}"
    );
    let mgd = G * 0.5;
    let loss = e[0] - e[e.len() - 1];
    assert!(loss > 0.0 && loss < 0.1 * mgd, "energy loss {loss}");
    assert!(residual.iter().all(|r| *r < 1e-10), "constraint residual");
    assert!(
        (pivot[1] - G / 4.0).abs() < 1e-2 * G,
        "pivot force {}",
        pivot[1]
    );
    let finer = text.replace("TSTEP,1,2500,1.e-3,5", "TSTEP,1,5000,5.e-4,10");
    assert_ne!(finer, text);
    let (_, _, e_fine, _, _) = energy_loss(&finer);
    let ratio = loss / (e_fine[0] - e_fine[e_fine.len() - 1]);
    assert!(
        (1.8..2.2).contains(&ratio),
        "loss ratio {ratio} for Δt halved"
    );
}

/// A rigid drive at ω = 1 rad/s from horizontal: no angular acceleration, so the drive torque
/// is the gravity moment m g d cos θ, the power T ω, and the actuation energy ∫ T ω dt =
/// m g d sin θ, the potential energy gained. Torque and power to 1e-4 of m g d (the BDF1
/// difference (v − v₀)/h of the Euler-parameter rates, which turn with the body even at a
/// constant ω, leaves an O(ω² Δt) inertia term: measured 3e-5 at ω Δt = 1e-3); energy to 1e-3
/// (the step-end rule of ∫ has error ω Δt / 2 relative).
#[test]
fn driven_rod_torque_power_and_energy_match_the_statics() {
    let (file, _dir) = run_text(&deck("pendulum_driven.dat"));
    let g = file.group("results/1/fmb").unwrap();
    let t = read(&g, "time");
    let torque = read(&g, "sensors/TORQUE");
    let power = read(&g, "sensors/POWER");
    let work = read(&g, "sensors/WORK");
    let angle = read(&g, "drives/1/angle");
    let rate = read(&g, "drives/1/rate");
    let drive_torque = read(&g, "drives/1/torque");
    let mgd = G * 0.5;
    for i in 1..t.len() {
        let theta = t[i];
        assert!((angle[i] - theta).abs() < 1e-9, "angle at {}", t[i]);
        assert!((rate[i] - 1.0).abs() < 1e-6, "rate at {}", t[i]);
        let expected = mgd * theta.cos();
        assert!(
            (torque[i] - expected).abs() < 1e-4 * mgd,
            "torque at {}: {} vs {expected}",
            t[i],
            torque[i]
        );
        assert_eq!(torque[i], drive_torque[i]);
        assert!(
            (power[i] - expected).abs() < 1e-4 * mgd,
            "power at {}",
            t[i]
        );
        assert!(
            (work[i] - mgd * theta.sin()).abs() < 1e-3 * mgd,
            "work at {}",
            t[i]
        );
    }
}
