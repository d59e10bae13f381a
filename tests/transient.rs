//! SOL TRANSIENT on the full model (direct integration of the f-set) against closed forms.

mod common;

use common::{TwoDofChain, read_dataset, run_deck};

/// Step response of the damped 2-DOF chain on the full model (no ROM): a step force on DOF 2
/// from rest, read through the D2 sensor (−u₂) and the DISPLACEMENT history. Second-order
/// integrators at ω_max Δt = 0.014 have a phase error ≈ (ωΔt)²/12 · ωT ≈ 1e-3 of the response
/// at T = 0.2 s: tolerance 2e-3 of the peak (as for the pROM run of the same chain); BDF1 is
/// first order, error ≈ ζ-like numerical damping ωΔt/2 · ωT ≈ 0.1: checked against 0.1. SOL 112
/// without TINTEG integrates by the trapezoidal rule (no numerical damping, as Nastran).
#[test]
fn full_model_step_response_equals_the_analytic_two_dof_chain() {
    let chain = TwoDofChain::reference();
    for (tinteg, what, tolerance) in [
        ("TINTEG,1,GALPHA,1.\n", "generalized-α ρ∞ = 1", 1e-4),
        ("TINTEG,1,GALPHA,0.6\n", "generalized-α ρ∞ = 0.6", 1e-4),
        ("TINTEG,1,BDF2\n", "BDF2", 1e-4),
        ("TINTEG,1,BDF1\n", "BDF1", 5e-2),
        ("", "SOL 112 without TINTEG (trapezoidal)", 1e-4),
    ] {
        let deck = format!(
            "SOL 112\nCEND\nTSTEP = 1\nDLOAD = 7\nSET 5 = 2\nDISPLACEMENT = 5\nBEGIN BULK\nTSTEP,1,4000,5.e-5,10\n{tinteg}TLOAD1,7,8,,,9\nDAREA,8,2,1,1.\nTABLED1,9\n,0.,1.,10.,1.,ENDT\n{}ENDDATA\n",
            chain.bulk()
        );
        let (r, out) = run_deck(&deck);
        r.unwrap_or_else(|e| panic!("{what}: {e}"));
        let file = hdf5_metno::File::open(out.path().join("out.h5")).expect("open");
        let g = file.group("results/1/transient").expect("transient group");
        let time = read_dataset::<f64>(&g, "time");
        assert_eq!(
            time.len(),
            401,
            "{what}: 4000 steps, output every 10, plus t = 0"
        );
        let d2 = read_dataset::<f64>(&g, "sensors/D2");
        let disp = read_dataset::<f64>(&g, "displacement");
        assert_eq!(
            disp.len(),
            time.len() * 6,
            "{what}: one grid (SET 5) × 6 components per row"
        );
        let exact = |t: f64| chain.response(t, [0.0; 2], [0.0; 2], 1.0)[1];
        let peak = time.iter().map(|&t| exact(t).abs()).fold(0.0, f64::max);
        let worst = time
            .iter()
            .enumerate()
            .map(|(i, &t)| (-d2[i] - exact(t)).abs())
            .fold(0.0, f64::max);
        println!("{what}: max |u₂ − exact| = {worst:.2e}, peak {peak:.3e}");
        assert!(
            worst <= tolerance * peak,
            "{what}: max error {worst:e} vs peak {peak:e}"
        );
        for i in 0..time.len() {
            assert_eq!(
                disp[6 * i],
                -d2[i],
                "{what}: DISPLACEMENT T1 of grid 2 and the D2 sensor differ at row {i}"
            );
        }
    }
}

/// PARAM,G with PARAM,W3 in a full-model transient is Nastran's equivalent viscous damping
/// (G/W3)·K: the chain with β₁ = 1e-4, G = 0.02 and W3 = 200 rad/s is the Rayleigh chain with
/// β = 2e-4, whose step response is analytic (modal solution of the damped chain). Tolerance as
/// the undamped-G test above for generalized-α at the same Δt (1e-4 of the peak). Without W3
/// the same deck leaves G out (a warning) and misses the analytic response by far more.
#[test]
fn full_model_structural_damping_g_over_w3_equals_the_analytic_two_dof_chain() {
    let chain = TwoDofChain::reference();
    assert_eq!(
        chain.beta, 2.0e-4,
        "the reference chain's β this test splits into β₁ + G/W3"
    );
    let split = TwoDofChain {
        beta: 1.0e-4,
        ..chain
    };
    let worst = |w3: &str| {
        let deck = format!(
            "SOL 112\nCEND\nTSTEP = 1\nDLOAD = 7\nBEGIN BULK\nTSTEP,1,4000,5.e-5,10\nTINTEG,1,GALPHA,1.\nTLOAD1,7,8,,,9\nDAREA,8,2,1,1.\nTABLED1,9\n,0.,1.,10.,1.,ENDT\nPARAM,G,0.02\n{w3}{}ENDDATA\n",
            split.bulk()
        );
        let (r, out) = run_deck(&deck);
        let summary = r.unwrap_or_else(|e| panic!("{e}"));
        let file = hdf5_metno::File::open(out.path().join("out.h5")).expect("open");
        let g = file.group("results/1/transient").expect("transient group");
        let (time, d2) = (
            read_dataset::<f64>(&g, "time"),
            read_dataset::<f64>(&g, "sensors/D2"),
        );
        let exact = |t: f64| chain.response(t, [0.0; 2], [0.0; 2], 1.0)[1];
        let peak = time.iter().map(|&t| exact(t).abs()).fold(0.0, f64::max);
        (
            time.iter()
                .enumerate()
                .map(|(i, &t)| (-d2[i] - exact(t)).abs())
                .fold(0.0, f64::max)
                / peak,
            summary.warnings,
        )
    };
    let (with_w3, warnings) = worst("PARAM,W3,200.\n");
    println!("G/W3: max |u₂ − exact| / peak = {with_w3:.2e}");
    assert!(
        with_w3 <= 1e-4,
        "G = 0.02, W3 = 200: error {with_w3:e} of the peak"
    );
    assert!(
        !warnings.iter().any(|w| w.contains("PARAM,G")),
        "{warnings:?}"
    );
    let (without, warnings) = worst("");
    assert!(
        without > 1e-2,
        "without W3, G must be left out (error {without:e} against the β = 2e-4 response)"
    );
    assert!(
        warnings
            .iter()
            .any(|w| w.contains("PARAM,G") && w.contains("W3")),
        "{warnings:?}"
    );
}

/// Full model and pROM of the same chain (both DOFs in the ASET: the pROM spans the whole
/// space) give the same sensor histories up to round-off of the reduced basis (1e-9 of the
/// peak: the basis is M-orthonormalized, so the reduced system equals the full one to ~1e-12).
#[test]
fn full_model_and_prom_transients_agree() {
    let chain = TwoDofChain::reference();
    let build = format!(
        "SOL PROM\nCEND\nPROM = 1\nBEGIN BULK\nPMPAR,1,K1,K,10,5.e3,5.e4\nPMOR,1,2,2,100.\n,1\n{}ENDDATA\n",
        chain.bulk()
    );
    let (r, prom_dir) = run_deck(&build);
    r.expect("SOL PROM");
    let cards = "TSTEP,1,2000,1.e-4,1\nTINTEG,1,GALPHA,0.8\nTLOAD1,7,8,,,9\nDAREA,8,2,1,1.\nTABLED1,9\n,0.,0.,0.01,1.,0.02,0.,ENDT\n";
    let full = format!(
        "SOL 112\nCEND\nTSTEP = 1\nDLOAD = 7\nBEGIN BULK\n{cards}{}ENDDATA\n",
        chain.bulk()
    );
    let reduced = format!(
        "SOL 112\nCEND\nROM = '{}'\nTSTEP = 1\nDLOAD = 7\nBEGIN BULK\n{cards}ENDDATA\n",
        prom_dir.path().join("out.h5").display()
    );
    let sensors = |deck: &str| -> (Vec<f64>, Vec<f64>) {
        let (r, out) = run_deck(deck);
        r.expect("transient");
        let file = hdf5_metno::File::open(out.path().join("out.h5")).expect("open");
        let g = file.group("results/1/transient").expect("group");
        (
            read_dataset::<f64>(&g, "sensors/D2"),
            read_dataset::<f64>(&g, "sensors/A2"),
        )
    };
    let ((d_full, a_full), (d_rom, a_rom)) = (sensors(&full), sensors(&reduced));
    for (what, x, y) in [("D2", d_full, d_rom), ("A2", a_full, a_rom)] {
        let peak = x.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        let worst = x
            .iter()
            .zip(&y)
            .fold(0.0_f64, |m, (a, b)| m.max((a - b).abs()));
        assert!(
            worst <= 1e-9 * peak,
            "{what}: full vs pROM differ by {worst:e} (peak {peak:e})"
        );
    }
}

/// A TSTEPVAR on the TSTEP of a SOL TRANSIENT asks for step control that only SOL FMB has: the
/// run stops and says so instead of running the fixed steps silently.
#[test]
fn tstepvar_is_refused_by_sol_transient() {
    let chain = TwoDofChain::reference();
    let deck = format!(
        "SOL 112\nCEND\nTSTEP = 1\nDLOAD = 7\nBEGIN BULK\nTSTEP,1,20,1.e-4,1\nTSTEPVAR,1,1.e-4\nTLOAD1,7,8,,,9\nDAREA,8,2,1,1.\nTABLED1,9\n,0.,1.,10.,1.,ENDT\n{}ENDDATA\n",
        chain.bulk()
    );
    let (r, _out) = run_deck(&deck);
    let message = r.expect_err("TSTEPVAR in SOL 112").to_string();
    assert!(
        message.contains("TSTEPVAR 1 asks for error-controlled steps, which only SOL FMB takes"),
        "{message}"
    );
}

/// Builds the 2-DOF chain's pROM (parameter K1 = k₁ over [5e3, 5e4]; both DOFs are inputs,
/// so the basis spans the whole space) and returns its directory.
fn chain_prom(chain: &TwoDofChain) -> tempfile::TempDir {
    let build = format!(
        "SOL PROM\nCEND\nPROM = 1\nBEGIN BULK\nPMPAR,1,K1,K,10,5.e3,5.e4\nPMOR,1,2,2,100.\n,1\n{}ENDDATA\n",
        chain.bulk()
    );
    let (r, dir) = run_deck(&build);
    r.expect("SOL PROM");
    dir
}

/// Enforced motion needs the full model's constrained DOFs: on a pROM (`ROM =`) a TLOAD of
/// TYPE = ACCE stops as "not available" (exit code 3), naming the TLOAD, instead of being
/// dropped from the loads.
#[test]
fn enforced_motion_on_a_prom_is_not_available() {
    let chain = TwoDofChain::reference();
    let prom = chain_prom(&chain);
    let deck = format!(
        "SOL 112\nCEND\nROM = '{}'\nTSTEP = 1\nDLOAD = 7\nPVAL = 4\nBEGIN BULK\nTSTEP,1,10,1.e-4\nPVAL,4,K1,1.e4\nTLOAD1,7,8,,ACCE,9\nGRID,2,,0.,0.,0.\nSPCD,8,2,1,9.81\nTABLED1,9\n,0.,1.,10.,1.,ENDT\nENDDATA\n",
        prom.path().join("out.h5").display()
    );
    let (r, _out) = run_deck(&deck);
    let e = r.expect_err("enforced motion on a pROM");
    assert!(
        matches!(e, paraflex::sequence::RunError::NotAvailable(_)),
        "{e}"
    );
    assert!(
        e.to_string().contains(
            "TLOAD1 7: TYPE = ACCE (enforced motion) is not available on a reduced model"
        ),
        "{e}"
    );
}

/// Runs a transient deck and returns (time, D2 sensor, the group's `evaluations` attribute or 0).
fn d2_history(deck: &str) -> (Vec<f64>, Vec<f64>, i64) {
    let (r, out) = run_deck(deck);
    r.unwrap_or_else(|e| panic!("{e}\n{deck}"));
    let file = hdf5_metno::File::open(out.path().join("out.h5")).expect("open");
    let g = file.group("results/1/transient").expect("group");
    let evaluations = g
        .attr("evaluations")
        .and_then(|a| a.read_scalar::<i64>())
        .unwrap_or(0);
    (
        read_dataset::<f64>(&g, "time"),
        read_dataset::<f64>(&g, "sensors/D2"),
        evaluations,
    )
}

/// Free vibration of the damped 2-DOF chain from TIC initial displacements and velocities
/// (IC = 3), on the full model and on its pROM (initial state defined on the input DOFs: with
/// both DOFs inputs, the static shape with the requested input displacements is exactly u0),
/// against the closed form. Generalized-α ρ∞ = 1 at Δt = 5e-5 s: phase error
/// (ω₂Δt)²/12 · ω₂T ≈ 1e-5 · 45 ≈ 5e-4 of the fast mode (here excited directly, unlike the step
/// response): tolerance 1e-3 of the peak.
#[test]
fn initial_conditions_give_the_analytic_free_vibration() {
    let chain = TwoDofChain::reference();
    let (u0, v0) = ([1.0e-3, -2.0e-3], [0.05, 0.1]);
    let cards = format!(
        "TSTEP,1,4000,5.e-5,10\nTINTEG,1,GALPHA,1.\nTIC,3,1,1,{:e},{:e}\nTIC,3,2,1,{:e},{:e}\n",
        u0[0], v0[0], u0[1], v0[1]
    );
    let prom = chain_prom(&chain);
    let full = format!(
        "SOL 109\nCEND\nTSTEP = 1\nIC = 3\nBEGIN BULK\n{cards}{}ENDDATA\n",
        chain.bulk()
    );
    let reduced = format!(
        "SOL 109\nCEND\nROM = '{}'\nTSTEP = 1\nIC = 3\nBEGIN BULK\n{cards}ENDDATA\n",
        prom.path().join("out.h5").display()
    );
    for (what, deck) in [("full model", full), ("pROM", reduced)] {
        let (time, d2, _) = d2_history(&deck);
        let exact = |t: f64| chain.response(t, u0, v0, 0.0)[1];
        assert!(
            (-d2[0] - u0[1]).abs() <= 1e-12 * u0[1].abs(),
            "{what}: initial displacement {} vs {}",
            -d2[0],
            u0[1]
        );
        let peak = time.iter().map(|&t| exact(t).abs()).fold(0.0, f64::max);
        let worst = time
            .iter()
            .zip(&d2)
            .map(|(&t, d)| (-d - exact(t)).abs())
            .fold(0.0, f64::max);
        println!("{what}: free vibration max error {worst:.2e}, peak {peak:.2e}");
        assert!(
            worst <= 1e-3 * peak,
            "{what}: max error {worst:e} vs peak {peak:e}"
        );
    }
}

/// PTABLE on a pROM: a constant table gives the frozen-parameter (PVAL) run to the last bit
/// and evaluates the pROM once; K1 rising linearly 2.5e4 → 4.5e4 over the 0.2 s run (slow
/// against the periods, 0.07 and 0.03 s) converges to a fine-step reference (Δt/16) at first
/// order or better in Δt (the matrices are taken at the end of each step), and its response
/// differs from the frozen one (the table matters).
#[test]
fn parameters_following_tables_on_a_prom() {
    let chain = TwoDofChain::reference();
    let prom = chain_prom(&chain);
    let deck = |steps: u32, dt: f64, params: &str| {
        format!(
            "SOL 112\nCEND\nROM = '{}'\nTSTEP = 1\nDLOAD = 7\nPVAL = 4\nBEGIN BULK\nTSTEP,1,{steps},{dt:e},{}\nTINTEG,1,GALPHA,0.9\nTLOAD1,7,8,,,9\nDAREA,8,2,1,1.\nTABLED1,9\n,0.,1.,10.,1.,ENDT\n{params}ENDDATA\n",
            prom.path().join("out.h5").display(),
            steps / 100
        )
    };
    let frozen = d2_history(&deck(2000, 1e-4, "PVAL,4,K1,2.5e4\n"));
    let constant = d2_history(&deck(
        2000,
        1e-4,
        "PTABLE,4,K1,20\nTABLED1,20\n,0.,2.5e4,1.,2.5e4,ENDT\n",
    ));
    assert_eq!(
        frozen.1, constant.1,
        "a constant PTABLE must equal the PVAL run"
    );
    assert_eq!(constant.2, 1, "a constant table evaluates the pROM once");
    let ramp = "PTABLE,4,K1,20\nTABLED1,20\n,0.,2.5e4,0.2,4.5e4,ENDT\n";
    let reference = d2_history(&deck(32000, 1e-4 / 16.0, ramp));
    let error = |steps: u32, dt: f64| {
        let (_, d, evaluations) = d2_history(&deck(steps, dt, ramp));
        assert_eq!(
            evaluations as u32,
            steps + 1,
            "a ramp changes K1 at every step"
        );
        d.iter()
            .zip(&reference.1)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max)
    };
    let peak = reference.1.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    let (e1, e2) = (error(2000, 1e-4), error(4000, 5e-5));
    println!(
        "PTABLE ramp: error {e1:.2e} at Δt = 1e-4, {e2:.2e} at 5e-5 (peak {peak:.2e}), observed order {:.2}",
        (e1 / e2).log2()
    );
    assert!((e1 / e2).log2() >= 0.9, "order below 1: {e1:e} → {e2:e}");
    let change = frozen
        .1
        .iter()
        .zip(&reference.1)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    assert!(
        change > 100.0 * e1,
        "the ramp must change the response well above the step error: {change:e} vs {e1:e}"
    );
    // a PTABLE naming no parameter of the pROM, or one the PVAL already sets, stops at its card
    for (params, expected) in [
        (
            "PTABLE,4,K9,20\nTABLED1,20\n,0.,2.5e4,1.,2.5e4,ENDT\n",
            "PTABLE 4: field 3 (NAME): K9 is not a parameter of the pROM (parameters: K1)",
        ),
        (
            "PVAL,4,K1,2.5e4\nPTABLE,4,k1,20\nTABLED1,20\n,0.,2.5e4,1.,2.5e4,ENDT\n",
            "PTABLE 4: field 3 (NAME): K1 is given twice (PVAL and PTABLE, or two PTABLEs)",
        ),
    ] {
        let (r, _out) = run_deck(&deck(100, 1e-4, params));
        let message = r.expect_err(expected).to_string();
        assert!(
            message.contains(expected) && message.contains("deck.dat:"),
            "{message}"
        );
    }
}

/// Hard cases on a pROM: a PTABLE leaving the parameter box during the run is warned about,
/// naming the parameter; a reduced mass matrix that is (numerically) singular is refused with
/// the conditioning check the dense eigen solver uses, not integrated.
#[test]
fn prom_hard_cases_are_reported() {
    let chain = TwoDofChain::reference();
    let prom = chain_prom(&chain);
    let rom = prom.path().join("out.h5");
    let deck = |params: &str| {
        format!(
            "SOL 112\nCEND\nROM = '{}'\nTSTEP = 1\nDLOAD = 7\nPVAL = 4\nBEGIN BULK\nTSTEP,1,100,1.e-4\nTLOAD1,7,8,,,9\nDAREA,8,2,1,1.\nTABLED1,9\n,0.,1.,10.,1.,ENDT\n{params}ENDDATA\n",
            rom.display()
        )
    };
    // K1's box is [5e3, 5e4]; the table leaves it at t = 5 ms
    let (r, _out) = run_deck(&deck(
        "PTABLE,4,K1,20\nTABLED1,20\n,0.,2.5e4,0.01,7.5e4,ENDT\n",
    ));
    let s = r.expect("out-of-box PTABLE runs (extrapolation is allowed)");
    assert!(
        s.warnings
            .iter()
            .any(|w| w.contains("K1") && w.contains("outside the box")),
        "{:?}",
        s.warnings
    );
    // PARAM,G: not applied in transient response (Nastran without PARAM,W3), with a warning; a
    // pROM FRF refuses it (its damping is the build's Rayleigh damping)
    let (r, _out) = run_deck(&deck("PVAL,4,K1,2.5e4\nPARAM,G,0.02\n"));
    let s = r.expect("PARAM,G in a transient runs");
    assert!(
        s.warnings
            .iter()
            .any(|w| w.contains("PARAM,G") && w.contains("W3")),
        "{:?}",
        s.warnings
    );
    let e = run_deck(&deck("PVAL,4,K1,2.5e4\nPARAM,G,0.02\nPARAM,W3,200.\n"))
        .0
        .expect_err("PARAM,G with W3 on a pROM transient");
    assert!(
        e.to_string().contains("PARAM,G") && e.to_string().contains("W3"),
        "{e}"
    );
    let frf = format!(
        "SOL 111\nCEND\nROM = '{}'\nFREQUENCY = 5\nPVAL = 4\nBEGIN BULK\nFREQ,5,10.\nPVAL,4,K1,2.5e4\nPARAM,G,0.02\nENDDATA\n",
        rom.display()
    );
    let e = run_deck(&frf).0.expect_err("PARAM,G on a pROM FRF");
    assert!(e.to_string().contains("PARAM,G"), "{e}");
    // every mass component replaced by a rank-one matrix: M_r(p) is singular
    {
        let file = hdf5_metno::File::open_rw(&rom).expect("open rw");
        let group = file.group("prom/M").expect("/prom/M");
        for name in group.member_names().unwrap() {
            group
                .dataset(&name)
                .unwrap()
                .write_raw(&[1.0, 1.0, 1.0, 1.0])
                .unwrap();
        }
    }
    let e = run_deck(&deck("PVAL,4,K1,2.5e4\n"))
        .0
        .expect_err("a singular reduced mass must be refused");
    assert!(
        e.to_string().contains("ill-conditioned") && e.to_string().contains("K1 = 2.5e4"),
        "{e}"
    );
}

/// Massless DOFs in a full-model transient: ground –k1– grid 1 (no mass) –k2– grid 2 (CONM2 m)
/// along T1, ramp force F(t) = F₁t at grid 2 from rest. Grid 1 is quasi-static, so grid 2 is an
/// SDOF with the series stiffness k = k1k2/(k1 + k2): u₂(t) = F₁/k (t − sin(ωt)/ω), ω² = k/m
/// (ramp response by the Duhamel integral, e.g. Inman, Engineering Vibration, 4th ed. 2014,
/// sec. 3.2), and u₁ = k2 u₂/(k1 + k2). The run starts at rest and unloaded, so a₀ = 0 is
/// consistent and no M⁻¹ is needed; each integrator then only factors the effective matrix,
/// definite through the springs. Tolerances as the two-DOF step response at the same ωΔt
/// (second-order methods 1e-4 of the peak, BDF1 with its numerical damping 5e-2; measured 2.2e-6
/// generalized-α, 8.4e-6 BDF2, 2.3e-3 BDF1). SOL 109 without TINTEG integrates like Nastran, with
/// no numerical damping (the trapezoidal rule), so it meets the second-order bound that BDF1
/// misses. A force that
/// jumps at t = 0 needs a₀ = M⁻¹(…), which does not exist: a clear error naming the DOF.
#[test]
fn massless_dofs_start_from_rest_and_a_loaded_start_is_refused() {
    let (k1, k2, m, f1): (f64, f64, f64, f64) = (3.0e4, 6.0e4, 2.0, 10.0);
    let k = k1 * k2 / (k1 + k2);
    let w = (k / m).sqrt();
    let deck = |tinteg: &str, table: &str| {
        format!(
            "SOL 109\nCEND\nSPC = 1\nTSTEP = 1\nDLOAD = 7\nBEGIN BULK\nGRID,1,,0.,0.,0.\nGRID,2,,1.,0.,0.\nSPC1,1,23456,1,2\nCONM2,1,2,,{m:?}\nCELAS2,11,{k1:?},1,1\nCELAS2,12,{k2:?},1,1,2,1\nSENSOR,1,D1,DISP,1,,1.,0.,0.\nSENSOR,2,D2,DISP,2,,1.,0.,0.\nTSTEP,1,4000,5.e-5,10\n{tinteg}TLOAD1,7,8,,,9\nDAREA,8,2,1,1.\nTABLED1,9\n{table}ENDDATA\n"
        )
    };
    let ramp = format!(",0.,0.,10.,{:?},ENDT\n", 10.0 * f1);
    for (tinteg, what, tolerance) in [
        ("TINTEG,1,GALPHA,0.8\n", "generalized-α ρ∞ = 0.8", 1e-4),
        ("TINTEG,1,BDF2\n", "BDF2", 1e-4),
        ("TINTEG,1,BDF1\n", "BDF1", 5e-2),
        ("", "SOL 109 without TINTEG (trapezoidal)", 1e-4),
    ] {
        let (r, out) = run_deck(&deck(tinteg, &ramp));
        r.unwrap_or_else(|e| panic!("{what}: {e}"));
        let file = hdf5_metno::File::open(out.path().join("out.h5")).expect("open");
        let g = file.group("results/1/transient").expect("transient group");
        let (time, d1, d2) = (
            read_dataset::<f64>(&g, "time"),
            read_dataset::<f64>(&g, "sensors/D1"),
            read_dataset::<f64>(&g, "sensors/D2"),
        );
        let exact = |t: f64| f1 / k * (t - (w * t).sin() / w);
        let peak = time.iter().map(|&t| exact(t).abs()).fold(0.0, f64::max);
        let worst2 = time
            .iter()
            .zip(&d2)
            .map(|(&t, y)| (y - exact(t)).abs())
            .fold(0.0, f64::max);
        let worst1 = time
            .iter()
            .zip(&d1)
            .map(|(&t, y)| (y - k2 / (k1 + k2) * exact(t)).abs())
            .fold(0.0, f64::max);
        println!(
            "{what}: max |u₂ − exact| = {worst2:.2e}, |u₁ − exact| = {worst1:.2e}, peak {peak:.3e}"
        );
        assert!(
            worst2 <= tolerance * peak && worst1 <= tolerance * peak,
            "{what}: errors {worst2:e}, {worst1:e} vs peak {peak:e}"
        );
    }
    let e = run_deck(&deck("", ",0.,1.,10.,1.,ENDT\n"))
        .0
        .expect_err("a loaded start with a massless DOF");
    assert!(
        e.to_string().contains("GRID 1 component 1 without mass"),
        "{e}"
    );
}

/// A TLOAD1 whose EXCITEID is a static load set with GRAV loads through the mass matrix:
/// spring k to ground, CONM2 m, GRAV g along T1 switched on at t = 0 (SOL 109, trapezoidal):
/// u(t) = (m g / k)(1 − cos ωt), ω² = k/m (undamped step response). At ωΔt = 0.011 the
/// trapezoidal rule's period error (ωΔt)²/12 · ωT ≈ 2e-4 of the amplitude over T = 0.2 s:
/// tolerance 1e-3 of the peak 2 m g / k.
#[test]
fn gravity_load_set_as_a_transient_excitation() {
    let (k, m, g): (f64, f64, f64) = (4.0e4, 2.0, 9.81);
    let w = (k / m).sqrt();
    let deck = format!(
        "SOL 109\nCEND\nSPC = 1\nTSTEP = 1\nDLOAD = 7\nBEGIN BULK\nGRID,2,,1.,0.,0.\nSPC1,1,23456,2\n\
         CONM2,1,2,,{m:?}\nCELAS2,11,{k:?},2,1\nSENSOR,2,D2,DISP,2,,1.,0.,0.\nTSTEP,1,2000,1.e-4,10\n\
         GRAV,5,,{g:?},1.,0.,0.\nTLOAD1,7,5,,,9\nTABLED1,9\n,0.,1.,10.,1.,ENDT\nENDDATA\n"
    );
    let (r, out) = run_deck(&deck);
    r.expect("run");
    let file = hdf5_metno::File::open(out.path().join("out.h5")).expect("open");
    let group = file.group("results/1/transient").expect("transient group");
    let (time, d2) = (
        read_dataset::<f64>(&group, "time"),
        read_dataset::<f64>(&group, "sensors/D2"),
    );
    let exact = |t: f64| m * g / k * (1.0 - (w * t).cos());
    let peak = 2.0 * m * g / k;
    let worst = time
        .iter()
        .zip(&d2)
        .map(|(&t, u)| (u - exact(t)).abs())
        .fold(0.0, f64::max);
    assert!(worst <= 1e-3 * peak, "max error {worst:e} vs peak {peak:e}");
}
