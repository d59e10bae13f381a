//! SOL TRANSIENT on the full model (direct integration of the f-set) against closed forms.

mod common;

use common::{TwoDofChain, run_deck};

fn read(g: &hdf5_metno::Group, name: &str) -> Vec<f64> {
    g.dataset(name).unwrap_or_else(|e| panic!("{name}: {e}")).read_raw().unwrap()
}

/// Step response of the damped 2-DOF chain on the full model (no ROM): a step force on DOF 2
/// from rest, read through the D2 sensor (−u₂) and the DISPLACEMENT history. Second-order
/// integrators at ω_max Δt = 0.014 have a phase error ≈ (ωΔt)²/12 · ωT ≈ 1e-3 of the response
/// at T = 0.2 s: tolerance 2e-3 of the peak (as for the pROM run of the same chain); BDF1 is
/// first order, error ≈ ζ-like numerical damping ωΔt/2 · ωT ≈ 0.1: checked against 0.1.
#[test]
fn full_model_step_response_equals_the_analytic_two_dof_chain() {
    let chain = TwoDofChain::reference();
    for (tinteg, what, tolerance) in [("TINTEG,1,GALPHA,1.\n", "generalized-α ρ∞ = 1", 1e-4), ("TINTEG,1,GALPHA,0.6\n", "generalized-α ρ∞ = 0.6", 1e-4), ("TINTEG,1,BDF2\n", "BDF2", 1e-4), ("", "BDF1", 5e-2)] {
        let deck = format!(
            "SOL 112\nCEND\nTSTEP = 1\nDLOAD = 7\nSET 5 = 2\nDISPLACEMENT = 5\nBEGIN BULK\nTSTEP,1,4000,5.e-5,10\n{tinteg}TLOAD1,7,8,,,9\nDAREA,8,2,1,1.\nTABLED1,9\n,0.,1.,10.,1.,ENDT\n{}ENDDATA\n",
            chain.bulk()
        );
        let (r, out) = run_deck(&deck);
        r.unwrap_or_else(|e| panic!("{what}: {e}"));
        let file = hdf5_metno::File::open(out.path().join("out.h5")).expect("open");
        let g = file.group("results/1/transient").expect("transient group");
        let time = read(&g, "time");
        assert_eq!(time.len(), 401, "{what}: 4000 steps, output every 10, plus t = 0");
        let d2 = read(&g, "sensors/D2");
        let disp = read(&g, "displacement");
        assert_eq!(disp.len(), time.len() * 6, "{what}: one grid (SET 5) × 6 components per row");
        let exact = |t: f64| chain.response(t, [0.0; 2], [0.0; 2], 1.0)[1];
        let peak = time.iter().map(|&t| exact(t).abs()).fold(0.0, f64::max);
        let worst = time.iter().enumerate().map(|(i, &t)| (-d2[i] - exact(t)).abs()).fold(0.0, f64::max);
        println!("{what}: max |u₂ − exact| = {worst:.2e}, peak {peak:.3e}");
        assert!(worst <= tolerance * peak, "{what}: max error {worst:e} vs peak {peak:e}");
        for i in 0..time.len() {
            assert_eq!(disp[6 * i], -d2[i], "{what}: DISPLACEMENT T1 of grid 2 and the D2 sensor differ at row {i}");
        }
    }
}

/// Full model and pROM of the same chain (both DOFs in the ASET: the pROM spans the whole
/// space) give the same sensor histories up to round-off of the reduced basis (1e-9 of the
/// peak: the basis is M-orthonormalized, so the reduced system equals the full one to ~1e-12).
#[test]
fn full_model_and_prom_transients_agree() {
    let chain = TwoDofChain::reference();
    let build = format!("SOL PROM\nCEND\nPROM = 1\nBEGIN BULK\nPMPAR,1,K1,K,10,5.e3,5.e4\nPMOR,1,2,2,100.\n,1\n{}ENDDATA\n", chain.bulk());
    let (r, prom_dir) = run_deck(&build);
    r.expect("SOL PROM");
    let cards = "TSTEP,1,2000,1.e-4,1\nTINTEG,1,GALPHA,0.8\nTLOAD1,7,8,,,9\nDAREA,8,2,1,1.\nTABLED1,9\n,0.,0.,0.01,1.,0.02,0.,ENDT\n";
    let full = format!("SOL 112\nCEND\nTSTEP = 1\nDLOAD = 7\nBEGIN BULK\n{cards}{}ENDDATA\n", chain.bulk());
    let reduced = format!("SOL 112\nCEND\nROM = '{}'\nTSTEP = 1\nDLOAD = 7\nBEGIN BULK\n{cards}ENDDATA\n", prom_dir.path().join("out.h5").display());
    let sensors = |deck: &str| -> (Vec<f64>, Vec<f64>) {
        let (r, out) = run_deck(deck);
        r.expect("transient");
        let file = hdf5_metno::File::open(out.path().join("out.h5")).expect("open");
        let g = file.group("results/1/transient").expect("group");
        (read(&g, "sensors/D2"), read(&g, "sensors/A2"))
    };
    let ((d_full, a_full), (d_rom, a_rom)) = (sensors(&full), sensors(&reduced));
    for (what, x, y) in [("D2", d_full, d_rom), ("A2", a_full, a_rom)] {
        let peak = x.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        let worst = x.iter().zip(&y).fold(0.0_f64, |m, (a, b)| m.max((a - b).abs()));
        assert!(worst <= 1e-9 * peak, "{what}: full vs pROM differ by {worst:e} (peak {peak:e})");
    }
}
