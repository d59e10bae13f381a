//! SOL PROM and SOL 103 on a pROM artifact (`ROM =`, `PVAL`): the pROM against the full model
//! at the same parameter values (thesis §3.4).

mod common;

use common::run_deck;
use paraflex::sequence::RunSummary;
use paraflex::sequence::modal::ModalSummary;
use paraflex::sequence::prom::PromSummary;
use paraflex::sequence::rom_modal::RomModalSummary;

/// Cantilever plate 0.3 × 0.1 m, CQUAD4 12 × 4, clamped at x = 0; `property` holds the
/// PSHELL/PCOMP and material cards (PID 1); ASET1 on three tip grids (T3).
fn plate(property: &str) -> String {
    // tip grids (12, 0), (12, 2), (12, 4) of the 13 × 5 grid numbering
    common::clamped_plate_mesh(12, 4, 0.3, 0.1) + "ASET1,3,13,39,65\n" + property
}

fn frequencies(s: &RunSummary) -> Vec<f64> {
    let sub = &s.subcases[0];
    match (
        sub.result::<ModalSummary>(),
        sub.result::<RomModalSummary>(),
    ) {
        (Some(m), _) => m.frequencies_hz.clone(),
        (_, Some(r)) => r.frequencies_hz.clone(),
        _ => panic!("not modal: {:?}", sub.result),
    }
}

/// Full SOL 103 of the plate with these cards.
fn full_modes(property: &str, modes: usize) -> Vec<f64> {
    let deck = format!(
        "SOL 103\nCEND\nSPC = 1\nMETHOD = 1\nBEGIN BULK\nPARAM,COUPMASS,1\nEIGRL,1,,,{modes}\n{}ENDDATA\n",
        plate(property)
    );
    let (r, _dir) = run_deck(&deck);
    frequencies(&r.expect("full run"))
}

/// Build the plate's pROM; returns the directory holding its out.h5.
fn build_plate_prom(property: &str, pmpar: &str, pmor: &str) -> tempfile::TempDir {
    let build = format!(
        "SOL PROM\nCEND\nSPC = 1\nPROM = 1\nBEGIN BULK\nPARAM,COUPMASS,1\n{pmpar}{pmor}{}ENDDATA\n",
        plate(property)
    );
    let (r, dir) = run_deck(&build);
    r.expect("SOL PROM");
    dir
}

/// The modes of the pROM in `built` (from [`build_plate_prom`]) at `pval`.
fn prom_modes(built: &tempfile::TempDir, pval: &str, modes: usize) -> (Vec<f64>, RunSummary) {
    let artifact = built.path().join("out.h5");
    let deck = format!(
        "SOL 103\nCEND\nROM = '{}'\nPVAL = 1\nMETHOD = 1\nBEGIN BULK\nEIGRL,1,,,{modes}\n{pval}ENDDATA\n",
        artifact.display()
    );
    let (r, _dir) = run_deck(&deck);
    let summary = r.expect("pROM modal run");
    (frequencies(&summary), summary)
}

const STEEL: &str = "PSHELL,1,1,0.002,1,,1\nMAT1,1,{E},,0.3,{RHO}\n";

/// Thesis §3.4.2: with E and ρ of the only material as parameters, the normal modes do not
/// depend on (E, ρ), one sample spans them, and the pROM reproduces the full model's
/// frequencies at any (E, ρ) — inside the box and far outside it. Tolerance 1e-8 relative:
/// both sides are eigenvalues accurate to the Lanczos Ritz tolerance (1e-10 on θ) and the
/// pROM's dense eigen solve (round-off).
#[test]
fn single_material_e_rho_prom_equals_the_full_model_everywhere() {
    let nominal = STEEL.replace("{E}", "2.1e11").replace("{RHO}", "7850.");
    let pmpar = "PMPAR,1,E,E,1,1.26e11,2.94e11\nPMPAR,2,RHO,RHO,1,4710.,10990.\n";
    let pmor = "PMOR,1,4,6,2000.,1.e-3,3\n,1\n";
    let built = build_plate_prom(&nominal, pmpar, pmor);
    for (e, rho, outside) in [(1.5e11, 9000.0, false), (4.0e11, 2000.0, true)] {
        let pval = format!("PVAL,1,E,{e:e},RHO,{rho:?}\n");
        let (reduced, summary) = prom_modes(&built, &pval, 6);
        let full = full_modes(
            &STEEL
                .replace("{E}", &format!("{e:e}"))
                .replace("{RHO}", &format!("{rho:?}")),
            6,
        );
        assert_eq!(reduced.len(), 6);
        for (r, f) in reduced.iter().zip(&full) {
            assert!(
                (r - f).abs() <= 1e-8 * f,
                "E = {e}, ρ = {rho}: pROM {reduced:?} vs full {full:?}"
            );
        }
        let warned = summary
            .warnings
            .iter()
            .any(|w| w.contains("outside the box") && w.contains('E') && w.contains("RHO"));
        assert_eq!(warned, outside, "{:?}", summary.warnings);
        assert!(
            !summary.warnings.iter().any(|w| w.contains("EIGRL ND")),
            "{:?}",
            summary.warnings
        );
    }
    // ND beyond the pROM's size returns every mode and says so
    let (all, summary) = prom_modes(&built, "PVAL,1,E,2.1e11\n", 500);
    let size = match summary.subcases[0].result::<RomModalSummary>() {
        Some(r) => r.n_red,
        None => panic!("not a pROM modal run: {:?}", summary.subcases[0].result),
    };
    assert_eq!(all.len(), size);
    assert!(
        summary
            .warnings
            .iter()
            .any(|w| w.contains("EIGRL ND = 500") && w.contains(&format!("all {size} returned"))),
        "{:?}",
        summary.warnings
    );
}

/// Fibre angle of an angle-ply laminate (thesis §3.6, Table 3.4 style: THETA over [0°, 90°]):
/// the affine functions of eq. 3.18 make the pROM exact in its matrices, but the basis is
/// only as rich as the samples. Inside the box the first four frequencies must agree with the
/// full model within 0.5 %: ERRTOL = 1e-3 bounds the mean relative FRF change of the last basis
/// step over the band, and a frequency error δ moves an FRF line by ~δ/ζ_eff near a peak, so
/// converged bases keep frequency errors well below 1e-2; 0.5 % leaves margin without
/// accepting a wrong basis (a missing mode shape is off by several percent). Measured: ≤ 1.2e-7
/// at Θ = 33°, ≤ 1.4e-6 at 71°. One build serves both angles (8 s of CPU in debug).
#[test]
fn angle_ply_theta_prom_tracks_the_full_model_inside_the_box() {
    angle_ply_theta_prom_with("ATTACH", &[33.0, 71.0]);
}

/// The same with Craig–Bampton static modes (`STATIC = CONSTR`): fixed-interface modes with the
/// three tip grids' T3 held, and their constraint modes; same bound and argument. Measured:
/// ≤ 2.7e-6 at Θ = 71° (one angle: each further angle costs a full SOL 103 of the plate, ~5 s
/// in debug on a loaded machine; 33° gave ≤ 2.6e-6 when tried). 8.7 s of CPU in debug (16 s
/// with the former 60 lines and steps of 4).
#[test]
fn angle_ply_theta_craig_bampton_prom_tracks_the_full_model_inside_the_box() {
    angle_ply_theta_prom_with("CONSTR", &[71.0]);
}

fn angle_ply_theta_prom_with(statics: &str, thetas: &[f64]) {
    let pmpar = "PMPAR,1,TH,THETA,1,0.,90.\n";
    // 30 FRF lines instead of the default 200 and steps of 8 keep the debug-mode size selection
    // short (it was most of the time: 60 lines and steps of 4 took twice as long, with the same
    // frequencies to the digits printed)
    let pmor = format!("PMOR,1,8,10,3000.,1.e-3,8\n,1,{statics},KEEP,30\n");
    let built = build_plate_prom(&laminate("20."), pmpar, &pmor);
    for &theta in thetas {
        let (reduced, _) = prom_modes(&built, &format!("PVAL,1,TH,{theta:?}\n"), 4);
        let full = full_modes(&laminate(&format!("{theta:?}")), 4);
        let errors: Vec<String> = reduced
            .iter()
            .zip(&full)
            .map(|(r, f)| format!("{:+.2e}", (r - f) / f))
            .collect();
        println!("STATIC = {statics}, Θ = {theta}: pROM − full (relative) {errors:?}");
        for (r, f) in reduced.iter().zip(&full) {
            assert!(
                (r - f).abs() <= 5e-3 * f,
                "Θ = {theta}: pROM {reduced:?} vs full {full:?}"
            );
        }
    }
}

/// The [±Θ]s laminate of the angle-ply tests.
fn laminate(theta: &str) -> String {
    format!(
        "MAT8,7,1.4e11,1.e10,.3,5.e9,5.e9,3.e9,1600.\nPCOMP,1\n,7,2.5e-4,{theta},,7,2.5e-4,-{theta}\n,7,2.5e-4,-{theta},,7,2.5e-4,{theta}\n"
    )
}

/// SOL PROM warns once when a parameter freezes the CQUAD4's condensation of its incompatible
/// modes (docs/elements.md "Frozen condensation"): a THETA PMPAR on the quads' PCOMP, TPLY of an
/// unsymmetric one (B ∝ h², A ∝ h), or NU (with E) of the PSHELL's MAT1, with the default
/// `PARAM,QINCOMP,YES`; not for E alone or
/// TPLY of a symmetric laminate (T does not change when (A, B) is scaled; both exact in
/// `tests/affine_assembly.rs`), and not with `PARAM,QINCOMP,NO` (no modes to condense). A
/// 4 × 2 plate keeps the six builds short.
#[test]
fn frozen_quad_condensation_is_warned_about_once() {
    let warnings = |property: &str, pmpar: &str, param: &str| -> Vec<String> {
        let mesh = common::clamped_plate_mesh(4, 2, 0.3, 0.1);
        let deck = format!(
            "SOL PROM\nCEND\nSPC = 1\nPROM = 1\nBEGIN BULK\n{param}{pmpar}PMOR,1,2,4,2000.\n{mesh}{property}ENDDATA\n"
        );
        let (r, _dir) = run_deck(&deck);
        r.expect("SOL PROM")
            .warnings
            .into_iter()
            .filter(|w| w.contains("QINCOMP"))
            .collect()
    };
    let theta = "PMPAR,1,TH,THETA,1,0.,90.\n";
    let warned = warnings(&laminate("20."), theta, "");
    assert_eq!(warned.len(), 1, "{warned:?}");
    assert!(
        warned[0].contains("PMPAR TH ") && warned[0].contains("PARAM,QINCOMP,NO"),
        "{}",
        warned[0]
    );
    assert!(warnings(&laminate("20."), theta, "PARAM,QINCOMP,NO\n").is_empty());
    let steel = STEEL.replace("{E}", "2.1e11").replace("{RHO}", "7850.");
    assert!(warnings(&steel, "PMPAR,1,E,E,1,1.e11,3.e11\n", "").is_empty());
    let warned = warnings(
        &steel,
        "PMPAR,1,E,E,1,1.e11,3.e11\nPMPAR,2,NU,NU,1,0.2,0.4\n",
        "",
    );
    assert!(
        warned.len() == 1 && warned[0].contains("PMPAR E, NU "),
        "{warned:?}"
    );
    let tply = "PMPAR,1,H,TPLY,1,1.e-4,1.e-3\n";
    assert!(warnings(&laminate("20."), tply, "").is_empty());
    let unsymmetric =
        "MAT8,7,1.4e11,1.e10,.3,5.e9,5.e9,3.e9,1600.\nPCOMP,1\n,7,2.5e-4,20.,,7,2.5e-4,-20.\n";
    let warned = warnings(unsymmetric, tply, "");
    assert!(
        warned.len() == 1 && warned[0].contains("PMPAR H "),
        "{warned:?}"
    );
}

/// A PVAL naming a parameter the artifact does not have is an error that lists the ones it has;
/// a PVAL whose K is indefinite is an error naming the point.
#[test]
fn pval_with_an_unknown_name_lists_the_parameters() {
    let nominal = STEEL.replace("{E}", "2.1e11").replace("{RHO}", "7850.");
    let build = format!(
        "SOL PROM\nCEND\nSPC = 1\nPROM = 1\nBEGIN BULK\nPMPAR,1,E,E,1,1.e11,3.e11\nPMOR,1,2,4,2000.\n{}ENDDATA\n",
        plate(&nominal)
    );
    let (r, dir) = run_deck(&build);
    r.expect("SOL PROM");
    let deck = format!(
        "SOL 103\nCEND\nROM = '{}'\nPVAL = 1\nBEGIN BULK\nPVAL,1,EE,2.e11\nENDDATA\n",
        dir.path().join("out.h5").display()
    );
    let (r, _d) = run_deck(&deck);
    let message = r.expect_err("unknown parameter").to_string();
    assert!(
        message.contains("EE") && message.contains("parameters: E"),
        "{message}"
    );
    // a negative modulus (an extrapolation past E = 0) makes K indefinite: refused, naming the
    // point, instead of reporting modes with negative λ as 0 Hz (the same check in SOL 111 and
    // SOL 112 on a pROM: they share this evaluation)
    let deck = format!(
        "SOL 103\nCEND\nROM = '{}'\nPVAL = 1\nMETHOD = 1\nBEGIN BULK\nEIGRL,1,,,3\nPVAL,1,E,-1.e11\nENDDATA\n",
        dir.path().join("out.h5").display()
    );
    let (r, _d) = run_deck(&deck);
    let message = r.expect_err("negative E").to_string();
    assert!(
        message.contains("E = -1e11") && message.contains("stiffness matrix is indefinite"),
        "{message}"
    );
}

/// `paraflex info` (io::describe) lists an artifact's parameters with their boxes and nominal
/// values, and its input DOFs.
#[test]
fn artifact_is_described_with_parameters_and_inputs() {
    let nominal = STEEL.replace("{E}", "2.1e11").replace("{RHO}", "7850.");
    let build = format!(
        "SOL PROM\nCEND\nSPC = 1\nPROM = 1\nBEGIN BULK\nPMPAR,1,E,E,1,1.e11,3.e11\nPMOR,1,2,4,2000.\n,1\n{}ENDDATA\n",
        plate(&nominal)
    );
    let (r, dir) = run_deck(&build);
    r.expect("SOL PROM");
    let summary = paraflex::io::describe(dir.path().join("out.h5")).expect("describe");
    let prom = summary.prom.clone().expect("/prom");
    assert_eq!(prom.params, vec!["E"]);
    assert_eq!(prom.ranges, vec![(1.0e11, 3.0e11)]);
    assert_eq!(prom.nominal, vec![2.1e11]);
    assert_eq!(prom.inputs, vec!["13:3", "39:3", "65:3"]);
    // RIGID = KEEP (default): no multibody body, no /prom/nodal_mass
    assert!(
        paraflex::io::read_prom_body(dir.path().join("out.h5"), 1, 1)
            .expect("read")
            .is_none()
    );
    let text = summary.to_string();
    assert!(
        text.contains("param     E in [1e11, 3e11], nominal 2.1e11")
            && text.contains("inputs    3"),
        "{text}"
    );
}

/// The blade scene's pROM (decks/blade/blade_prom_e_rho.dat: E and ρ ± 40 %, thesis Table 3.1
/// settings) against the full model at two points of the box. The bolt springs are not
/// parametrized, so the modes do change with (E, ρ) and the basis is not exact; the bound is
/// 1e-3 relative on the frequencies in 0–500 Hz, the accuracy the FRF-change tolerance of the
/// build (1e-3) is meant to deliver.
#[test]
fn blade_e_rho_prom_matches_the_full_model_inside_the_box() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let (r, _model, dir) = common::run_deck_file(&root.join("decks/blade/blade_prom_e_rho.dat"));
    r.expect("blade SOL PROM");
    let artifact = dir.path().join("out.h5");
    let bolts =
        std::fs::read_to_string(root.join("decks/blade/blade_ti_bolts.bdf")).expect("bolts");
    for (e, rho) in [(1.0e11, 5500.0), (1.5e11, 3500.0)] {
        let rom = format!(
            "SOL 103\nCEND\nROM = '{}'\nPVAL = 1\nMETHOD = 1\nBEGIN BULK\nPVAL,1,E,{e:e},RHO,{rho:?}\nEIGRL,1,0.,500.\nENDDATA\n",
            artifact.display()
        );
        let (r, _d) = run_deck(&rom);
        let reduced = frequencies(&r.expect("pROM modes"));
        let material = bolts.replace(
            "MAT1,1,116.04E9,,0.34,4873.",
            &format!("MAT1,1,{e:e},,0.34,{rho:?}"),
        );
        assert_ne!(material, bolts, "MAT1 line not found");
        let mesh = root.join("meshes/blade");
        let full = format!(
            "SOL 103\nCEND\nMETHOD = 1\nBEGIN BULK\nEIGRL,1,0.,500.\n{material}\nINCLUDE '{}'\nINCLUDE '{}'\nENDDATA\n",
            mesh.join("blade.bdf").display(),
            mesh.join("blade_rbe.bdf").display()
        );
        let (r, _d) = run_deck(&full);
        let full = frequencies(&r.expect("full modes"));
        assert_eq!(
            reduced.len(),
            full.len(),
            "E = {e}, ρ = {rho}: {reduced:?} vs {full:?}"
        );
        let worst = reduced
            .iter()
            .zip(&full)
            .map(|(a, b)| ((a - b) / b).abs())
            .fold(0.0, f64::max);
        println!(
            "blade pROM at E = {e:e}, ρ = {rho}: max relative frequency error {worst:.1e} over {} modes",
            full.len()
        );
        assert!(worst <= 1e-3, "{reduced:?} vs {full:?}");
    }
}

/// Frequency response of a pROM (`SOL 111` with `ROM =`) against the analytic receptance of a
/// 2-DOF spring–mass chain: ground–k₁–m₁–k₂–m₂ with C = αM + βK. With both DOFs in the BSET the
/// pROM spans the whole (2-DOF) space, so H(ω) = (K − ω²M + iωC)⁻¹ exactly at any k₁ — here
/// outside the box as well; tolerance 1e-10 relative to max |H| (2 × 2 complex solves).
#[test]
fn prom_frf_equals_the_analytic_two_dof_receptance() {
    let (k2, m1, m2, alpha, beta) = (3.0e4, 2.0, 1.0, 0.8, 2.0e-4);
    let bulk = format!(
        "GRID,1,,0.,0.,0.,,23456\nGRID,2,,1.,0.,0.,,23456\nCELAS1,1,10,1,1\nPELAS,10,1.e4\nCELAS1,2,20,1,1,2,1\nPELAS,20,{k2:e}\n\
         CONM2,11,1,,{m1:?}\nCONM2,12,2,,{m2:?}\nASET1,1,1,2\nPARAM,ALPHA1,{alpha:?}\nPARAM,BETA1,{beta:e}\n\
         SENSOR,1,A2,ACCEL,2,,2.,0.,0.\nSENSOR,2,D2,DISP,2,,-1.,0.,0.\n"
    );
    let build = format!(
        "SOL PROM\nCEND\nPROM = 1\nBEGIN BULK\nPMPAR,1,K1,K,10,5.e3,2.e4\nPMOR,1,2,2,100.\n,1\n{bulk}ENDDATA\n"
    );
    let (r, dir) = run_deck(&build);
    r.expect("SOL PROM");
    let k1 = 2.5e4;
    let frf = format!(
        "SOL 111\nCEND\nROM = '{}'\nPVAL = 1\nFREQUENCY = 1\nBEGIN BULK\nPVAL,1,K1,{k1:e}\nFREQ1,1,0.5,0.5,60\nENDDATA\n",
        dir.path().join("out.h5").display()
    );
    let (r, out) = run_deck(&frf);
    let s = r.expect("pROM FRF");
    assert!(
        s.warnings
            .iter()
            .any(|w| w.contains("K1") && w.contains("outside the box")),
        "{:?}",
        s.warnings
    );
    let file = hdf5_metno::File::open(out.path().join("out.h5")).expect("open");
    let g = file.group("results/1/frf").expect("frf group");
    let hz: Vec<f64> = g.dataset("frequency_hz").unwrap().read_raw().unwrap();
    let h: Vec<faer::c64> = g.dataset("H").unwrap().read_raw().unwrap();
    // outputs: 1:1, 2:1 (the inputs), then A2 (acceleration along +x), D2 (displacement along −x)
    let outputs: Vec<String> = g
        .dataset("outputs")
        .unwrap()
        .read_raw::<hdf5_metno::types::VarLenUnicode>()
        .unwrap()
        .iter()
        .map(|s| s.to_string())
        .collect();
    assert_eq!(outputs, ["1:1", "2:1", "A2", "D2"]);
    assert_eq!(h.len(), hz.len() * 8);
    let c = |re: f64, im: f64| faer::c64::new(re, im);
    let mut max_h = 0.0_f64;
    let mut worst = 0.0_f64;
    for (l, f) in hz.iter().enumerate() {
        let w = 2.0 * std::f64::consts::PI * f;
        let (k11, k12, k22) = (k1 + k2, -k2, k2);
        let z = |k: f64, m: f64| c(k - w * w * m, w * (alpha * m + beta * k));
        let (a, b, d) = (z(k11, m1), z(k12, 0.0), z(k22, m2));
        let det = a * d - b * b;
        // H[o][i] for o = 1:1, 2:1, A2 = −ω² · 2:1, D2 = −2:1
        let (h11, h12, h21, h22) = (d / det, -b / det, -b / det, a / det);
        let acc = c(-w * w, 0.0);
        let exact = [h11, h12, h21, h22, acc * h21, acc * h22, -h21, -h22];
        for (got, want) in h[8 * l..8 * l + 8].iter().zip(exact) {
            max_h = max_h.max(want.norm());
            worst = worst.max((got - want).norm());
        }
    }
    assert!(
        worst <= 1e-10 * max_h,
        "max |H − exact| = {worst:e}, max |H| = {max_h:e}"
    );
}

/// Transient response of a pROM (`SOL 112` with `ROM =`) against the analytic step response
/// of the damped 2-DOF chain above (modal superposition with Rayleigh damping ζ_j = α/2ω_j +
/// βω_j/2): a step force on DOF 2 from rest. Second-order integrators at ω_max Δt = 0.014 have a
/// phase error ≈ (ωΔt)²/12 · ωT ≈ 1e-3 of the response at T = 0.2 s: tolerance 2e-3 of the
/// peak displacement, for generalized-α (ρ∞ = 1, the trapezoidal rule) and BDF2.
#[test]
fn prom_transient_equals_the_analytic_two_dof_step_response() {
    let chain = common::TwoDofChain::reference();
    let build = format!(
        "SOL PROM\nCEND\nPROM = 1\nBEGIN BULK\nPMPAR,1,K1,K,10,5.e3,5.e4\nPMOR,1,2,2,100.\n,1\n{}ENDDATA\n",
        chain.bulk()
    );
    let (r, dir) = run_deck(&build);
    r.expect("SOL PROM");
    let exact = |t: f64| chain.response(t, [0.0; 2], [0.0; 2], 1.0);
    // the same step as a CSV table (TABLEF) must give the same numbers as the TABLED1
    let csv_dir = tempfile::tempdir().unwrap();
    let csv = csv_dir.path().join("step.csv");
    std::fs::write(&csv, "time,force\n0.,1.\n10.,1.\n").unwrap();
    let tablef = format!("TABLEF,9,'{}',time,force\n", csv.display());
    let mut galpha_u: Option<Vec<f64>> = None;
    for (tinteg, table, what) in [
        (
            "TINTEG,1,GALPHA,1.\n",
            "TABLED1,9\n,0.,1.,10.,1.,ENDT\n".to_string(),
            "generalized-α ρ∞ = 1",
        ),
        (
            "TINTEG,1,BDF2\n",
            "TABLED1,9\n,0.,1.,10.,1.,ENDT\n".to_string(),
            "BDF2",
        ),
        (
            "TINTEG,1,GALPHA,1.\n",
            tablef,
            "generalized-α ρ∞ = 1, TABLEF",
        ),
    ] {
        let deck = format!(
            "SOL 112\nCEND\nROM = '{}'\nTSTEP = 1\nDLOAD = 7\nBEGIN BULK\nTSTEP,1,4000,5.e-5,10\n{tinteg}TLOAD1,7,8,,,9\nDAREA,8,2,1,1.\n{table}ENDDATA\n",
            dir.path().join("out.h5").display()
        );
        let (r, out) = run_deck(&deck);
        r.unwrap_or_else(|e| panic!("{what}: {e}"));
        let file = hdf5_metno::File::open(out.path().join("out.h5")).expect("open");
        let g = file.group("results/1/transient").expect("transient group");
        let time: Vec<f64> = g.dataset("time").unwrap().read_raw().unwrap();
        let u: Vec<f64> = g.dataset("displacement").unwrap().read_raw().unwrap();
        assert_eq!(
            time.len(),
            401,
            "{what}: 4000 steps, output every 10, plus t = 0"
        );
        let peak = time.iter().map(|&t| exact(t)[1].abs()).fold(0.0, f64::max);
        let worst = time
            .iter()
            .enumerate()
            .map(|(i, &t)| {
                (0..2)
                    .map(|d| (u[2 * i + d] - exact(t)[d]).abs())
                    .fold(0.0, f64::max)
            })
            .fold(0.0, f64::max);
        println!("{what}: max |u − exact| = {worst:.2e}, peak {peak:.3e}");
        match (&galpha_u, tinteg.contains("GALPHA")) {
            (None, true) => galpha_u = Some(u.clone()),
            (Some(first), true) => assert_eq!(first, &u, "{what}: TABLEF differs from TABLED1"),
            _ => {}
        }
        // SENSOR D2 (DISP along −x at grid 2) is −u of DOF 2:1; A2 (ACCEL along +x) is the
        // acceleration output of 2:1 — the same numbers, to the last bit
        let sensor = |name: &str| -> Vec<f64> {
            g.dataset(&format!("sensors/{name}"))
                .unwrap()
                .read_raw()
                .unwrap()
        };
        let a: Vec<f64> = g.dataset("acceleration").unwrap().read_raw().unwrap();
        let (d2, a2) = (sensor("D2"), sensor("A2"));
        for i in 0..time.len() {
            assert!(
                (d2[i] + u[2 * i + 1]).abs() <= 1e-15 * peak
                    && (a2[i] - a[2 * i + 1]).abs() <= 1e-12 * a[2 * i + 1].abs().max(1.0),
                "{what}: sensor rows at step {i}"
            );
        }
        assert!(
            worst <= 2e-3 * peak,
            "{what}: max error {worst:e} vs peak {peak:e}"
        );
    }
}

/// The aluminium / steel [`two_material_plate`] with the PMPAR cards `pmpar`: its parameters,
/// affine K and M, and `count` Latin-hypercube samples of the parameter box (`seed`).
fn two_material_samples(
    pmpar: &str,
    count: usize,
    seed: u64,
) -> (
    paraflex::discretize::parameters::Parameters,
    paraflex::assembly::AffineOperator,
    paraflex::assembly::AffineOperator,
    Vec<Vec<f64>>,
) {
    let property =
        "PSHELL,1,1,0.002\nPSHELL,2,2,0.002\nMAT1,1,7.e10,,0.33,2700.\nMAT1,2,2.1e11,,0.3,7850.\n";
    let (params, k, m) =
        common::affine_operators(&format!("{}{pmpar}", two_material_plate(property)));
    let low: Vec<f64> = params.list.iter().map(|p| p.low).collect();
    let high: Vec<f64> = params.list.iter().map(|p| p.high).collect();
    let samples = paraflex::rom::basis::latin_hypercube(count, &low, &high, seed);
    (params, k, m, samples)
}

/// [`plate`] with the elements of its right half (x > 0.15) on PID 2 instead of 1.
fn two_material_plate(property: &str) -> String {
    let nx = 12;
    plate(property)
        .lines()
        .map(|line| match line.strip_prefix("CQUAD4,") {
            Some(rest) => {
                let (eid, tail) = rest.split_once(",1,").expect("CQUAD4,eid,1,...");
                let right = (eid.parse::<usize>().expect("eid") - 1) % nx >= nx / 2;
                format!("CQUAD4,{eid},{},{tail}\n", if right { 2 } else { 1 })
            }
            None => format!("{line}\n"),
        })
        .collect()
}

/// Affine nodal masses for the multibody step (thesis eq. 4.1–4.2, A.11; `RIGID = REMOVE`):
/// the free plate of [`plate`] with its left half on MAT1 1 (ρ₁ a parameter), its right half on
/// MAT1 2 (ρ₂ = 2700 fixed) and a CONM2 at the tip (m_c a parameter). At random (ρ₁, m_c)
/// the sums Σ_k f_k(p) m_j^k of `/prom/nodal_mass` must equal the lumped masses assembled by hand:
/// a CQUAD4 of area A gives ρtA/4 to each of its grids (∫ρ N_j dA of a bilinear square), the
/// CONM2 its m. Total mass and centre of mass follow. Bound 1e-12 relative: sums of ≤ 65
/// round-off-exact terms.
#[test]
fn affine_nodal_masses_equal_the_lumped_masses_at_any_parameters() {
    let (nx, ny, h, t) = (12usize, 4usize, 0.025, 0.002);
    let tip = 1 + nx + (nx + 1) * 2;
    let property = format!(
        "PSHELL,1,1,{t:?}\nPSHELL,2,2,{t:?}\nMAT1,1,7.e10,,0.33,2000.\nMAT1,2,7.e10,,0.33,2700.\nCONM2,100,{tip},,0.05\n"
    );
    let mesh = two_material_plate(&property);
    let pmpar = "PMPAR,1,RHO1,RHO,1,1500.,2500.\nPMPAR,2,MC,MASS,100,0.02,0.08\n";
    let build = format!(
        "SOL PROM\nCEND\nPROM = 1\nBEGIN BULK\n{pmpar}PMOR,1,2,4,500.,1.e-3,2\n,,,REMOVE,20\n{mesh}ENDDATA\n"
    );
    let (r, dir) = run_deck(&build);
    r.expect("SOL PROM");
    let artifact = dir.path().join("out.h5");
    let (prom, _) = paraflex::io::read_prom(&artifact).expect("pROM");
    let body = paraflex::io::read_prom_body(&artifact, prom.size(), prom.functions.len())
        .expect("read")
        .expect("/prom/nodal_mass with RIGID = REMOVE");
    let (grids, masses) = (&body.grids, &body.masses);
    for (rho1, mc) in [(1733.0, 0.031), (2461.5, 0.077), (3100.0, 0.01)] {
        let f: Vec<f64> = prom
            .functions
            .iter()
            .map(|g| g.value(&[rho1, mc]))
            .collect();
        let at = |values: &[f64]| -> f64 { values.iter().zip(&f).map(|(v, w)| v * w).sum() };
        // by hand
        let mut want = vec![0.0; grids.len()];
        let index = |i: usize, j: usize| i + (nx + 1) * j;
        for j in 0..ny {
            for i in 0..nx {
                let rho = if i >= nx / 2 { 2700.0 } else { rho1 };
                for g in [
                    index(i, j),
                    index(i + 1, j),
                    index(i + 1, j + 1),
                    index(i, j + 1),
                ] {
                    want[g] += rho * t * h * h / 4.0;
                }
            }
        }
        want[tip - 1] += mc;
        assert_eq!(*grids, (1..=want.len() as u32).collect::<Vec<_>>());
        let got: Vec<f64> = (0..grids.len())
            .map(|g| at(&masses.nodal.iter().map(|m| m[g]).collect::<Vec<_>>()))
            .collect();
        let scale = want.iter().copied().fold(0.0, f64::max);
        for (g, (a, b)) in got.iter().zip(&want).enumerate() {
            assert!(
                (a - b).abs() <= 1e-12 * scale,
                "ρ₁ = {rho1}, m_c = {mc}, grid {}: {a} vs {b}",
                g + 1
            );
        }
        let inv = paraflex::rom::invariants::MassInvariants::combine(&body.invariants, &f).unwrap();
        let total = (rho1 + 2700.0) * t * (nx as f64 * h / 2.0) * (ny as f64 * h) + mc;
        assert!((inv.mass - total).abs() <= 1e-12 * total);
        let half = nx as f64 * h / 2.0;
        let cx =
            (rho1 * t * half * 0.1 * half / 2.0 + 2700.0 * t * half * 0.1 * 1.5 * half + mc * 0.3)
                / total;
        let cy = 0.05;
        let centre: Vec<f64> = inv.m1.iter().map(|m| m / inv.mass).collect();
        for (c, w) in centre.iter().zip([cx, cy, 0.0]) {
            assert!(
                (c - w).abs() <= 1e-12 * 0.3,
                "centre {centre:?} vs ({cx}, {cy}, 0)"
            );
        }
    }
}

/// Matrix Market (general coordinate, every stored entry, shortest round-trip values).
fn write_matrix_market(path: &std::path::Path, a: &nalgebra_sparse::CscMatrix<f64>) {
    let mut text = format!(
        "%%MatrixMarket matrix coordinate real general\n{} {} {}\n",
        a.nrows(),
        a.ncols(),
        a.nnz()
    );
    for (i, j, v) in a.triplet_iter() {
        text += &format!("{} {} {v:e}\n", i + 1, j + 1);
    }
    std::fs::write(path, text).expect("write .mtx");
}

/// The black-box route (thesis eq. 3.29): K and M of the two-material plate
/// sampled at 7 LHS points of (E₁, ρ₁, E₂), exported as Matrix Market files with a manifest,
/// read back by `paraflex prom-lsq`; the least-squares components must equal the components
/// assembled directly (X⁰ = X(0), X^j = (X(h_j e_j) − X(0)) / h_j with h_j the upper bound,
/// exact since X is affine in p; h_j rather than 1 keeps the subtraction's cancellation at the
/// round-off of the sampled magnitudes).
/// Metric: max_h |f_i(p_h)| · max |X^i_lsq − X^i| relative to the largest sampled entry, bound
/// 1e-13: the (column-scaled) function matrix has a condition number ~10 for these boxes and the
/// samples are exact to the ~1e-16 of their decimal round trip, so round-off is a few 1e-15
/// (measured ≤ 1.4e-15); a wrong component is off by O(1).
/// Too few samples and dependent functions are refused with the reason, by the library and by
/// the CLI (exit code 2).
#[test]
fn least_squares_components_of_exported_samples_equal_the_assembled_ones() {
    let (params, k, m, samples) = two_material_samples(
        "PMPAR,1,E1,E,1,5.e10,9.e10\nPMPAR,2,RHO1,RHO,1,2000.,3400.\nPMPAR,3,E2,E,2,1.5e11,2.7e11\n",
        7,
        3,
    );
    let high: Vec<f64> = params.list.iter().map(|p| p.high).collect();
    let dir = tempfile::tempdir().expect("temp dir");
    let mut manifest = String::from("# two-material plate, E1 RHO1 E2\nK, M, 1, E1, RHO1, E2\n");
    let at = |op: &paraflex::assembly::AffineOperator, p: &[f64]| {
        op.evaluate(&params.weights(op, p)).expect("evaluate")
    };
    for (h, p) in samples.iter().enumerate() {
        write_matrix_market(&dir.path().join(format!("k{h}.mtx")), &at(&k, p));
        write_matrix_market(&dir.path().join(format!("m{h}.mtx")), &at(&m, p));
        manifest += &format!(
            "k{h}.mtx, m{h}.mtx, 1, {:e}, {:e}, {:e}\n",
            p[0], p[1], p[2]
        );
    }
    let path = dir.path().join("samples.csv");
    std::fs::write(&path, &manifest).expect("manifest");
    let (read, fit) = paraflex::io::prom_lsq::fit_samples(&path).expect("fit");
    assert_eq!(read.functions, vec!["1", "E1", "RHO1", "E2"]);
    assert!(
        fit.residual_stiffness < 1e-14 && fit.residual_mass < 1e-14,
        "{} {}",
        fit.residual_stiffness,
        fit.residual_mass
    );
    for (what, op, parts) in [("K", &k, &fit.stiffness), ("M", &m, &fit.mass)] {
        let zero = at(op, &[0.0; 3]);
        let largest = samples
            .iter()
            .map(|p| {
                at(op, p)
                    .values()
                    .iter()
                    .fold(0.0_f64, |a, v| a.max(v.abs()))
            })
            .fold(0.0, f64::max);
        for (i, part) in parts.iter().enumerate() {
            assert_eq!(
                part.pattern(),
                zero.pattern(),
                "{what}: the union of the sample patterns is the assembled pattern"
            );
            let direct: Vec<f64> = if i == 0 {
                zero.values().to_vec()
            } else {
                let corner: Vec<f64> = (0..3)
                    .map(|j| if j == i - 1 { high[j] } else { 0.0 })
                    .collect();
                at(op, &corner)
                    .values()
                    .iter()
                    .zip(zero.values())
                    .map(|(a, b)| (a - b) / high[i - 1])
                    .collect()
            };
            let f_max = if i == 0 { 1.0 } else { high[i - 1] };
            let worst = part
                .values()
                .iter()
                .zip(&direct)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max)
                * f_max;
            println!(
                "{what}^{}: max |lsq − direct| · f = {:.1e} of the largest entry",
                read.functions[i],
                worst / largest
            );
            assert!(
                worst <= 1e-13 * largest,
                "{what}^{}: {worst:e} vs {largest:e}",
                read.functions[i]
            );
        }
    }
    // too few samples (3 for 4 functions) and a dependent function column (2·E1)
    let rows: Vec<&str> = manifest.lines().collect();
    let too_few = dir.path().join("too_few.csv");
    std::fs::write(&too_few, rows[..5].join("\n")).expect("write");
    let message = paraflex::io::prom_lsq::fit_samples(&too_few)
        .expect_err("3 samples")
        .to_string();
    assert!(
        message.contains("3 sampled matrices for 4 affine functions"),
        "{message}"
    );
    let dependent = dir.path().join("dependent.csv");
    let doubled: Vec<String> = samples
        .iter()
        .enumerate()
        .map(|(h, p)| {
            format!(
                "k{h}.mtx, m{h}.mtx, 1, {:e}, {:e}, {:e}, {:e}",
                p[0],
                p[1],
                p[2],
                2.0 * p[0]
            )
        })
        .collect();
    std::fs::write(
        &dependent,
        format!("K, M, 1, E1, RHO1, E2, TWICE_E1\n{}\n", doubled.join("\n")),
    )
    .expect("write");
    let message = paraflex::io::prom_lsq::fit_samples(&dependent)
        .expect_err("dependent")
        .to_string();
    assert!(
        message.contains("linearly dependent")
            && message.contains("E1")
            && message.contains("TWICE_E1"),
        "{message}"
    );
    // the CLI
    let cli = |manifest: &std::path::Path| {
        std::process::Command::new(env!("CARGO_BIN_EXE_paraflex"))
            .arg("prom-lsq")
            .arg(manifest)
            .arg("-o")
            .arg(dir.path().join("parts.h5"))
            .output()
            .expect("run paraflex")
    };
    let ok = cli(&path);
    assert!(
        ok.status.success(),
        "{}",
        String::from_utf8_lossy(&ok.stderr)
    );
    assert!(String::from_utf8_lossy(&ok.stdout).contains("functions 1, E1, RHO1, E2"));
    let refused = cli(&dependent);
    assert_eq!(refused.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&refused.stderr).contains("linearly dependent"));
}

/// STRAIN sensors of the strain-sensor pROMs below: element 1 (root corner) TOP along x,
/// element 30 (column 6 of the middle row) BOT along (1, 0.5), and its MID along y.
const STRAIN_SENSORS: &str = "SENSOR,1,R_TOP,STRAIN,1,TOP,1.,0.,0.\nSENSOR,2,M_BOT,STRAIN,30,BOT,1.,0.5,0.\nSENSOR,3,M_MID,STRAIN,30,MID,0.,1.,0.\n";

/// SOL PROM of the steel plate with E as parameter and [`STRAIN_SENSORS`] (plus `extra` bulk
/// cards). MACTOL = 1 turns the MAC filter off (it was needed while the filter also compared
/// columns of one local basis: the tip attachment modes have MAC > 0.99 with the first bending
/// mode) and ERRTOL = 1e-12 keeps the whole rank; K ∝ E, so every sample has the same
/// attachment modes and the basis holds K⁻¹S exactly at any E.
fn strain_prom(extra: &str) -> tempfile::TempDir {
    let nominal = STEEL.replace("{E}", "2.1e11").replace("{RHO}", "7850.");
    let build = format!(
        "SOL PROM\nCEND\nSPC = 1\nPROM = 1\nBEGIN BULK\nPMPAR,1,E,E,1,1.e11,3.e11\nPMOR,1,2,4,2000.,1.e-12,,1.\n,1\n{STRAIN_SENSORS}{extra}{}ENDDATA\n",
        plate(&nominal)
    );
    let (r, dir) = run_deck(&build);
    r.expect("SOL PROM");
    dir
}

/// What the [`STRAIN_SENSORS`] read in the full SOL 101 of the plate under a unit force on
/// grid 39 T3, from the STRAIN output projected on the gauge directions (ε_ϑ = ϑ₁²εx + ϑ₂²εy +
/// ϑ₁ϑ₂γxy in the material axes, here basic x, y; MID = the mean of the two fibres).
fn full_static_gauges() -> [f64; 3] {
    let nominal = STEEL.replace("{E}", "2.1e11").replace("{RHO}", "7850.");
    let full = format!(
        "SOL 101\nCEND\nSPC = 1\nLOAD = 2\nSTRAIN = ALL\nBEGIN BULK\nFORCE,2,39,0,1.,0.,0.,1.\n{}ENDDATA\n",
        plate(&nominal)
    );
    let (r, out) = run_deck(&full);
    r.expect("SOL 101");
    let file = hdf5_metno::File::open(out.path().join("out.h5")).expect("open");
    let s = file
        .group("results/1/statics/strain/CQUAD4")
        .expect("strain");
    let ids: Vec<u32> = s.dataset("ids").unwrap().read_raw().unwrap();
    let top: Vec<f64> = s.dataset("top").unwrap().read_raw().unwrap();
    let bottom: Vec<f64> = s.dataset("bottom").unwrap().read_raw().unwrap();
    let at = |surface: &[f64], eid: u32| -> [f64; 3] {
        std::array::from_fn(|i| surface[3 * ids.iter().position(|&e| e == eid).unwrap() + i])
    };
    let gauge = |e: [f64; 3], d: [f64; 2]| {
        let n = (d[0] * d[0] + d[1] * d[1]).sqrt();
        let (a, b) = (d[0] / n, d[1] / n);
        a * a * e[0] + b * b * e[1] + a * b * e[2]
    };
    let mid: [f64; 3] = std::array::from_fn(|i| 0.5 * (at(&top, 30)[i] + at(&bottom, 30)[i]));
    [
        gauge(at(&top, 1), [1.0, 0.0]),
        gauge(at(&bottom, 30), [1.0, 0.5]),
        gauge(mid, [0.0, 1.0]),
    ]
}

/// `got` against `want` within `rel` of the largest |want|.
fn assert_gauges(what: &str, got: &[f64], want: &[f64; 3], rel: f64) {
    let scale = want.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
    for ((name, g), w) in ["R_TOP", "M_BOT", "M_MID"].iter().zip(got).zip(want) {
        println!("{what} {name}: pROM {g:.10e}, full {w:.10e}");
        assert!(
            (g - w).abs() <= rel * scale,
            "{what} {name}: pROM {g:e} vs full {w:e}"
        );
    }
}

/// STRAIN rows of a pROM (H_r = H Φ, eq. 2.32) against the full model at the nominal point:
/// the basis holds the static attachment modes of the tip grids ([`strain_prom`]), so the
/// pROM's FRF at 0 Hz is the full static response to a unit tip force and each strain sensor
/// must read what SOL 101's STRAIN output gives. Tolerance 1e-7 relative to the largest strain:
/// the two paths are exact up to the conditioning of the shell K_ff (~1e9 × 1e-16 through the
/// Cholesky solve and the SVD of the basis).
#[test]
fn prom_strain_sensors_equal_the_full_model_at_the_nominal_point() {
    let dir = strain_prom("");
    let frf = format!(
        "SOL 111\nCEND\nROM = '{}'\nPVAL = 1\nFREQUENCY = 1\nBEGIN BULK\nPVAL,1,E,2.1e11\nFREQ,1,0.\nENDDATA\n",
        dir.path().join("out.h5").display()
    );
    let (r, out) = run_deck(&frf);
    r.expect("pROM FRF");
    let file = hdf5_metno::File::open(out.path().join("out.h5")).expect("open");
    let g = file.group("results/1/frf").expect("frf group");
    let outputs: Vec<String> = g
        .dataset("outputs")
        .unwrap()
        .read_raw::<hdf5_metno::types::VarLenUnicode>()
        .unwrap()
        .iter()
        .map(|s| s.to_string())
        .collect();
    assert_eq!(outputs, ["13:3", "39:3", "65:3", "R_TOP", "M_BOT", "M_MID"]);
    let h: Vec<faer::c64> = g.dataset("H").unwrap().read_raw().unwrap();
    // column of input 39:3 (index 1 of 3), sensor rows 3..6
    let reduced: Vec<f64> = (3..6).map(|o| h[3 * o + 1].re).collect();
    assert_gauges("FRF at 0 Hz", &reduced, &full_static_gauges(), 1e-7);
}

/// A pROM transient outputs STRAIN sensors as y = H_r q (like DISP): a unit step force on
/// grid 39 T3 with Rayleigh damping α = 200 /s, β = 2e-3 s decays every transient at least as
/// e^(−αt/2) (ζ_j ω_j = α/2 + βω_j²/2), e^(−50) after 0.5 s, and BDF1's fixed point is K_r q = S_r:
/// the last sample is the static strain of SOL 101 (tolerance 1e-7, as the FRF test above).
#[test]
fn prom_transient_strain_sensors_settle_on_the_static_strain() {
    let dir = strain_prom("PARAM,ALPHA1,200.\nPARAM,BETA1,2.e-3\n");
    let deck = format!(
        "SOL 112\nCEND\nROM = '{}'\nTSTEP = 1\nDLOAD = 7\nBEGIN BULK\nTSTEP,1,5000,1.e-4,5000\nTLOAD1,7,8,,,9\nDAREA,8,39,3,1.\nTABLED1,9\n,0.,1.,10.,1.,ENDT\nENDDATA\n",
        dir.path().join("out.h5").display()
    );
    let (r, out) = run_deck(&deck);
    r.expect("pROM transient");
    let file = hdf5_metno::File::open(out.path().join("out.h5")).expect("open");
    let g = file.group("results/1/transient").expect("transient group");
    let last: Vec<f64> = ["R_TOP", "M_BOT", "M_MID"]
        .iter()
        .map(|name| {
            *g.dataset(&format!("sensors/{name}"))
                .unwrap()
                .read_raw::<f64>()
                .unwrap()
                .last()
                .unwrap()
        })
        .collect();
    assert_gauges("transient at 0.5 s", &last, &full_static_gauges(), 1e-7);
}

/// The HDF5 input of `paraflex prom-lsq` (layout in `src/io/prom_lsq.rs`): the samples of the
/// two-material plate of the test above written as one HDF5 file — K of each sample in
/// coordinate form (0-based `row`, `col`, `data`, attribute `shape`), M as a dense n × n
/// dataset, the function values as `/values` — must give the components of the Matrix Market
/// route. Both readers hand the same numbers (stored exactly: f64 in HDF5, shortest round-trip
/// decimals in .mtx) to the same fit, so the bound is 1e-14 of the largest component entry
/// (summation order only); a transposed or shifted reader is off by O(1). A missing `/values`
/// and an index out of range are errors naming the object.
#[test]
fn least_squares_components_from_hdf5_samples_equal_the_matrix_market_ones() {
    use hdf5_metno::types::VarLenUnicode;
    let (params, k, m, samples) = two_material_samples(
        "PMPAR,1,E1,E,1,5.e10,9.e10\nPMPAR,2,RHO1,RHO,1,2000.,3400.\n",
        4,
        5,
    );
    let dir = tempfile::tempdir().expect("temp dir");
    let at = |op: &paraflex::assembly::AffineOperator, p: &[f64]| {
        op.evaluate(&params.weights(op, p)).expect("evaluate")
    };
    let mut manifest = String::from("K, M, 1, E1, RHO1\n");
    let h5 = dir.path().join("samples.h5");
    {
        let file = hdf5_metno::File::create(&h5).expect("create");
        let names: Vec<VarLenUnicode> = ["1", "E1", "RHO1"]
            .iter()
            .map(|s| s.parse().unwrap())
            .collect();
        file.new_dataset_builder()
            .with_data(&names)
            .create("functions")
            .expect("functions");
        let values: Vec<f64> = samples.iter().flat_map(|p| [1.0, p[0], p[1]]).collect();
        file.new_dataset::<f64>()
            .shape([samples.len(), 3])
            .create("values")
            .expect("values")
            .write_raw(&values)
            .expect("write values");
        let (k_group, m_group) = (
            file.create_group("K").unwrap(),
            file.create_group("M").unwrap(),
        );
        for (h, p) in samples.iter().enumerate() {
            let (kh, mh) = (at(&k, p), at(&m, p));
            write_matrix_market(&dir.path().join(format!("k{h}.mtx")), &kh);
            write_matrix_market(&dir.path().join(format!("m{h}.mtx")), &mh);
            manifest += &format!("k{h}.mtx, m{h}.mtx, 1, {:e}, {:e}\n", p[0], p[1]);
            let g = k_group.create_group(&h.to_string()).unwrap();
            let (rows, cols, data): (Vec<i64>, Vec<i64>, Vec<f64>) = kh.triplet_iter().fold(
                (vec![], vec![], vec![]),
                |(mut r, mut c, mut d), (i, j, v)| {
                    r.push(i as i64);
                    c.push(j as i64);
                    d.push(*v);
                    (r, c, d)
                },
            );
            g.new_dataset_builder()
                .with_data(&rows)
                .create("row")
                .unwrap();
            g.new_dataset_builder()
                .with_data(&cols)
                .create("col")
                .unwrap();
            g.new_dataset_builder()
                .with_data(&data)
                .create("data")
                .unwrap();
            g.new_attr_builder()
                .with_data(&[kh.nrows() as i64, kh.ncols() as i64])
                .create("shape")
                .unwrap();
            let n = mh.nrows();
            let mut dense = vec![0.0; n * n];
            mh.triplet_iter()
                .for_each(|(i, j, v)| dense[i * n + j] += v);
            m_group
                .new_dataset::<f64>()
                .shape([n, n])
                .create(h.to_string().as_str())
                .unwrap()
                .write_raw(&dense)
                .unwrap();
        }
    }
    let csv = dir.path().join("samples.csv");
    std::fs::write(&csv, &manifest).expect("manifest");
    let (_, from_mtx) = paraflex::io::prom_lsq::fit_samples(&csv).expect("Matrix Market");
    let (read, from_h5) = paraflex::io::prom_lsq::fit_samples(&h5).expect("HDF5");
    assert_eq!(read.functions, ["1", "E1", "RHO1"]);
    for (what, a, b) in [
        ("K", &from_mtx.stiffness, &from_h5.stiffness),
        ("M", &from_mtx.mass, &from_h5.mass),
    ] {
        for (i, (x, y)) in a.iter().zip(b.iter()).enumerate() {
            let largest = x.values().iter().fold(0.0_f64, |s, v| s.max(v.abs()));
            let diff = (x - y).values().iter().fold(0.0_f64, |s, v| s.max(v.abs()));
            println!(
                "{what}^{}: max |HDF5 − Matrix Market| = {:.1e} of the largest entry",
                read.functions[i],
                diff / largest
            );
            assert!(
                diff <= 1e-14 * largest,
                "{what}^{}: {diff:e} vs {largest:e}",
                read.functions[i]
            );
        }
    }
    // the CLI reads it too, and writes next to it without overwriting it
    let ok = std::process::Command::new(env!("CARGO_BIN_EXE_paraflex"))
        .arg("prom-lsq")
        .arg(&h5)
        .output()
        .expect("run paraflex");
    assert!(
        ok.status.success(),
        "{}",
        String::from_utf8_lossy(&ok.stderr)
    );
    assert!(
        dir.path().join("samples_lsq.h5").exists()
            && paraflex::io::prom_lsq::read_samples(&h5).is_ok()
    );
    // errors name the object
    let broken = dir.path().join("broken.h5");
    {
        let file = hdf5_metno::File::create(&broken).expect("create");
        let names: Vec<VarLenUnicode> = ["1"].iter().map(|s| s.parse().unwrap()).collect();
        file.new_dataset_builder()
            .with_data(&names)
            .create("functions")
            .unwrap();
    }
    let message = paraflex::io::prom_lsq::fit_samples(&broken)
        .expect_err("no values")
        .to_string();
    assert!(message.contains("/values"), "{message}");
    {
        let file = hdf5_metno::File::open_rw(&broken).expect("open");
        file.new_dataset::<f64>()
            .shape([1, 1])
            .create("values")
            .unwrap()
            .write_raw(&[1.0])
            .unwrap();
        let g = file.create_group("K").unwrap().create_group("0").unwrap();
        g.new_dataset_builder()
            .with_data(&[0_i64, 2])
            .create("row")
            .unwrap();
        g.new_dataset_builder()
            .with_data(&[0_i64, 0])
            .create("col")
            .unwrap();
        g.new_dataset_builder()
            .with_data(&[1.0, 1.0])
            .create("data")
            .unwrap();
        g.new_attr_builder()
            .with_data(&[2_i64, 2])
            .create("shape")
            .unwrap();
    }
    let message = paraflex::io::prom_lsq::fit_samples(&broken)
        .expect_err("index 2 of 2")
        .to_string();
    assert!(
        message.contains("/K/0") && message.contains("row index 2 is not in 0..2"),
        "{message}"
    );
}

/// [±Θ]s angle-ply cantilever strip 0.3 × 0.03 m (the laminate of [`laminate`], 1 mm), CQUAD4
/// 24 × 4 clamped at x = 0, `PARAM,QINCOMP,NO`, the pROM's input T3 at the middle tip grid
/// (24, 2). The symmetric laminate uncouples membrane and bending, so the input never excites
/// the strip's in-plane bending and the FRF change of eq. 3.35 cannot see whether the basis
/// holds those modes.
fn strip(property: &str) -> String {
    common::clamped_plate_mesh(24, 4, 0.3, 0.03) + "ASET1,3,75\nPARAM,QINCOMP,NO\n" + property
}

/// Band of [`strip`]'s checks (FMAX of its pROM deck).
const STRIP_FMAX: f64 = 600.0;

/// Full SOL 103 of the strip: every frequency below [`STRIP_FMAX`].
fn strip_full_modes(theta: f64) -> Vec<f64> {
    let deck = format!(
        "SOL 103\nCEND\nSPC = 1\nMETHOD = 1\nBEGIN BULK\nEIGRL,1,,{STRIP_FMAX:?}\n{}ENDDATA\n",
        strip(&laminate(&format!("{theta:?}")))
    );
    let (r, _dir) = run_deck(&deck);
    frequencies(&r.expect("full run"))
}

/// Every full-model mode below FMAX against the pROM's modes at Θ: `(relative errors, pROM
/// frequencies, full frequencies)`, the pROM asked for two modes more than the full model has.
fn strip_errors(built: &tempfile::TempDir, theta: f64) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let full = strip_full_modes(theta);
    let (reduced, _) = prom_modes(built, &format!("PVAL,1,TH,{theta:?}\n"), full.len() + 2);
    let errors = full
        .iter()
        .zip(&reduced)
        .map(|(f, r)| (r - f) / f)
        .collect();
    (errors, reduced, full)
}

/// The pROM of `decks/prom/strip_angle_ply_prom_theta.dat` with `nsamp` samples: [`strip`] at
/// Θ = 45° with Θ over [0°, 90°], NMODES 12 (the 12th mode lies above FMAX = 600 Hz at every
/// angle, so each local basis holds all of its sample's modes in the band), the attachment mode
/// of the input; ERRTOL 1e-12 lets the size selection grow to the whole numerical rank, so what
/// the basis lacks is what the MAC filter removed. Returns the artifact's directory and the
/// sampled angles.
fn build_strip_prom(nsamp: usize) -> (tempfile::TempDir, Vec<f64>) {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("decks/prom/strip_angle_ply_prom_theta.dat");
    let deck = std::fs::read_to_string(&path)
        .expect("strip deck")
        .replace("PMOR,1,2,", &format!("PMOR,1,{nsamp},"));
    let (r, dir) = run_deck(&deck);
    let summary = r.expect("SOL PROM");
    let Some(prom) = summary.subcases[0].result::<PromSummary>() else {
        panic!("not a pROM build")
    };
    println!("strip pROM: {:?}", prom.log);
    (dir, prom.log.samples.iter().map(|p| p[0]).collect())
}

/// A pROM must reproduce every FOM mode below FMAX, not only those its FRF-error inputs see:
/// the in-plane bending of a link carries a mechanism's deviation. [`strip`]:
/// - two samples (the deck): at a sampled angle the basis holds that sample's modes, so every
///   mode below FMAX must come back to the accuracy of the Lanczos vectors and the SVD (bound
///   1e-7 relative; measured ≤ 2e-9). The displacement MAC of eq. 3.39 drops columns of the
///   second sample whose shapes match the first sample's although their strain energies
///   differ, and that sample's frequencies are then off by percents; the energy MAC of
///   `rom::basis::mac_filter` keeps them;
/// - six samples, at angles between them: every mode below FMAX within 1e-4 relative (measured
///   ≤ 4.7e-6: the six local bases span the modes' change over Θ; a mode missing from the
///   basis moves to a combination of the others, percents away).
#[test]
fn every_strip_mode_below_fmax_is_kept_at_sampled_and_unsampled_angles() {
    let (built, samples) = build_strip_prom(2);
    for theta in samples {
        let (errors, reduced, full) = strip_errors(&built, theta);
        println!("Θ = {theta}: full {full:?}\n  pROM {reduced:?}\n  errors {errors:?}");
        assert!(
            errors.iter().all(|e| e.abs() <= 1e-7),
            "Θ = {theta} (sampled): pROM {reduced:?} vs full {full:?}"
        );
    }
    let (built, samples) = build_strip_prom(6);
    println!("six samples at {samples:?}");
    for theta in [10.0, 45.0, 80.0] {
        let (errors, reduced, full) = strip_errors(&built, theta);
        println!("Θ = {theta} (unsampled): full {full:?}\n  pROM {reduced:?}\n  errors {errors:?}");
        assert!(
            errors.iter().all(|e| e.abs() <= 1e-4),
            "Θ = {theta} (unsampled): pROM {reduced:?} vs full {full:?}"
        );
    }
}

/// The multibody data of a `RIGID = REMOVE` artifact (thesis eq. 4.1–4.3, 4.8, A.11–A.19)
/// against independent values. The free plate of [`common::plate_mesh`], 12 × 4 CQUAD4 of
/// 25 mm, massless (MAT1 without ρ) with a CONM2 of mass m₀ at every grid except the corner
/// grid 13, whose CONM2 (m_t) is the parameter, so every mass is a translational point mass:
/// M = Σ_j m_j (e_jx e_jxᵀ + e_jy e_jyᵀ + e_jz e_jzᵀ).
/// - rigid invariants at p: m, M̂₁ = Σ m_j r_j and M̂₃ = Σ m_j (r_j r_jᵀ − |r_j|² I) summed by
///   hand over the lattice (the affine components combined with f_k(p), eq. 4.8);
/// - M̂₉(p) = Σ_j m_j Ψ_jᵀΨ_j equals the pROM's reduced mass Φᵀ M(p) Φ: with point masses the
///   two are the same sum, reached through different code (invariants from the g-set rows in
///   basic, the pROM by sparse projection of the f-set parts);
/// - the interface rows (ASET1 grids 1 and 65, six components) come back one 6 × n_r block per
///   grid, and the T3 row of grid 65 equals the pROM's input shape of 65:3.
///
/// Bounds: 1e-12 relative for the hand sums (~10² exact products), 1e-10 of the largest entry
/// for M̂₉ (two summation orders of the same products).
#[test]
fn body_invariants_equal_point_mass_sums_and_the_reduced_mass() {
    let (nx, ny, h) = (12usize, 4usize, 0.025);
    let (mesh, _) = common::plate_mesh(nx, ny, 0.3, 0.1);
    let (m0, tip) = (0.01, nx + 1);
    let conm2: String = (1..=(nx + 1) * (ny + 1))
        .map(|g| {
            format!(
                "CONM2,{},{g},,{}\n",
                100 + g,
                if g == tip { 0.02 } else { m0 }
            )
        })
        .collect();
    let build = format!(
        "SOL PROM\nCEND\nPROM = 1\nBEGIN BULK\nPMPAR,1,MT,MASS,{},0.01,0.05\nPMOR,1,2,6,2000.,1.e-3,2\n,1,ATTACH,REMOVE,20\nASET1,123456,1,65\nPSHELL,1,1,0.002,1,,1\nMAT1,1,7.e10,,0.33\n{conm2}{mesh}ENDDATA\n",
        100 + tip
    );
    let (r, dir) = run_deck(&build);
    r.expect("SOL PROM");
    let artifact = dir.path().join("out.h5");
    let (prom, _) = paraflex::io::read_prom(&artifact).expect("pROM");
    let n = prom.size();
    let body = paraflex::io::read_prom_body(&artifact, n, prom.functions.len())
        .expect("read")
        .expect("body data with RIGID = REMOVE");
    let (_, inputs) = paraflex::io::read_prom_inputs(&artifact, n).expect("inputs");
    for mt in [0.013, 0.047] {
        let f: Vec<f64> = prom.functions.iter().map(|g| g.value(&[mt])).collect();
        let inv = paraflex::rom::invariants::MassInvariants::combine(&body.invariants, &f).unwrap();
        let grids: Vec<(f64, [f64; 3])> = (0..=ny)
            .flat_map(|j| (0..=nx).map(move |i| (i, j)))
            .map(|(i, j)| {
                let m = if i == nx && j == 0 { mt } else { m0 };
                (m, [i as f64 * h, j as f64 * h, 0.0])
            })
            .collect();
        let mass: f64 = grids.iter().map(|(m, _)| m).sum();
        assert!(
            (inv.mass - mass).abs() <= 1e-12 * mass,
            "{} vs {mass}",
            inv.mass
        );
        for a in 0..3 {
            let first: f64 = grids.iter().map(|(m, r)| m * r[a]).sum();
            assert!((inv.m1[a] - first).abs() <= 1e-12 * mass, "M1 {a}: {inv:?}");
            for b in 0..3 {
                let second: f64 = grids
                    .iter()
                    .map(|(m, r)| {
                        let rr: f64 = r.iter().map(|x| x * x).sum();
                        m * (r[a] * r[b] - if a == b { rr } else { 0.0 })
                    })
                    .sum();
                assert!((inv.m3[a][b] - second).abs() <= 1e-12 * mass, "M3 {a}{b}");
            }
        }
        let mut at = prom.workspace();
        prom.evaluate(&[mt], &mut at).unwrap();
        let scale = (0..n).map(|k| at.mass()[(k, k)].abs()).fold(0.0, f64::max);
        for k in 0..n {
            for l in 0..n {
                let (a, b) = (inv.m9[(k, l)], at.mass()[(k, l)]);
                assert!((a - b).abs() <= 1e-10 * scale, "M9 ({k}, {l}): {a} vs {b}");
            }
        }
    }
    assert_eq!(body.interface.grids, vec![1, 65]);
    // input 8 is 65:3, after the six DOFs of grid 1 and 65:1, 65:2
    for k in 0..n {
        let (row, input) = (body.interface.rows[1][(2, k)], inputs[(k, 8)]);
        assert!(
            (row - input).abs() <= 1e-12 * (1.0 + input.abs()),
            "row {k}: {row} vs {input}"
        );
    }
}
