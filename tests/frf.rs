//! SOL FRF on the full model (`sequence::frf`): SOL 108 (direct) and SOL 111 (modal) against the
//! analytic single- and two-DOF responses of `reference/analytic/frf_*.json`, and direct vs
//! modal vs pROM on the cantilever plate.

mod common;

use std::path::PathBuf;

use common::{run_deck, run_deck_file};
use faer::c64;
use hdf5_metno::types::VarLenUnicode;
use paraflex::sequence::frf::FrfSummary;
use serde_json::Value;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn reference(case: &str) -> Value {
    serde_json::from_str(
        &std::fs::read_to_string(root().join(format!("reference/analytic/{case}.json"))).unwrap(),
    )
    .unwrap()
}

fn f64s(v: &Value) -> Vec<f64> {
    v.as_array()
        .unwrap()
        .iter()
        .flat_map(|x| {
            if x.is_array() {
                f64s(x)
            } else {
                vec![x.as_f64().unwrap()]
            }
        })
        .collect()
}

/// The `/results/1/frf` group of a run: (frequency_hz, H, outputs, response).
struct Frf {
    hz: Vec<f64>,
    h: Vec<c64>,
    outputs: Vec<String>,
    response: Vec<c64>,
}

fn read_frf(path: &std::path::Path) -> Frf {
    let file = hdf5_metno::File::open(path).expect("open");
    let g = file.group("results/1/frf").expect("frf group");
    let outputs = g
        .dataset("outputs")
        .unwrap()
        .read_raw::<VarLenUnicode>()
        .unwrap()
        .iter()
        .map(|s| s.to_string())
        .collect();
    let response = if g.link_exists("response") {
        g.dataset("response").unwrap().read_raw().unwrap()
    } else {
        Vec::new()
    };
    Frf {
        hz: g.dataset("frequency_hz").unwrap().read_raw().unwrap(),
        h: g.dataset("H").unwrap().read_raw().unwrap(),
        outputs,
        response,
    }
}

/// Largest |got − want| relative to max |want|.
fn worst(got: &[c64], re: &[f64], im: &[f64]) -> f64 {
    assert_eq!(got.len(), re.len());
    let scale = re
        .iter()
        .zip(im)
        .map(|(a, b)| a.hypot(*b))
        .fold(0.0, f64::max);
    got.iter()
        .zip(re.iter().zip(im))
        .map(|(g, (a, b))| (g - c64::new(*a, *b)).norm())
        .fold(0.0, f64::max)
        / scale
}

/// SDOF with Rayleigh damping: H and the RLOAD1 response (amplitude, phase, delay, C and D
/// tables) against the closed form; tolerance from the reference (1e-10 of max |H|: a 1 × 1
/// complex solve, no discretization).
#[test]
fn sdof_direct_matches_the_closed_form() {
    let r = reference("frf_sdof");
    let (run, _model, dir) = run_deck_file(&root().join(r["meshes"][0]["deck"].as_str().unwrap()));
    run.expect("SOL 108");
    let out = read_frf(&dir.path().join("out.h5"));
    assert_eq!(out.hz, f64s(&r["frequency_hz"]));
    assert_eq!(out.outputs, ["1:1"]);
    let tol = f64s(&r["tolerance_finest"]["relative"])[0];
    let (h, resp) = (
        worst(&out.h, &f64s(&r["H_re"]), &f64s(&r["H_im"])),
        worst(
            &out.response,
            &f64s(&r["response_re"]),
            &f64s(&r["response_im"]),
        ),
    );
    println!("SDOF: H error {h:.1e}, response error {resp:.1e} (tol {tol:.0e})");
    assert!(h <= tol && resp <= tol, "H {h:e}, response {resp:e}");
}

/// `DISPLACEMENT = ALL` in SOL 108: `frf/displacement` (f × grids × 6, basic) is the grid's
/// complex response to the deck's load: T1 equals the closed-form SDOF response (same reference
/// and tolerance as above) and the SPC'd components read exactly zero; H keeps only its named
/// outputs.
#[test]
fn sdof_displacement_output_is_the_closed_form_response() {
    let r = reference("frf_sdof");
    let text = std::fs::read_to_string(root().join(r["meshes"][0]["deck"].as_str().unwrap()))
        .unwrap()
        .replace("  DLOAD = 7\n", "  DLOAD = 7\n  DISPLACEMENT = ALL\n");
    assert!(text.contains("DISPLACEMENT = ALL"));
    let (run, dir) = run_deck(&text);
    run.expect("SOL 108 with DISPLACEMENT");
    let path = dir.path().join("out.h5");
    let out = read_frf(&path);
    assert_eq!(out.outputs, ["1:1"]);
    assert_eq!(out.h.len(), out.hz.len());
    let file = hdf5_metno::File::open(&path).unwrap();
    let d = file.dataset("results/1/frf/displacement").unwrap();
    assert_eq!(d.shape(), [out.hz.len(), 1, 6]);
    let d: Vec<c64> = d.read_raw().unwrap();
    let t1: Vec<c64> = d.chunks_exact(6).map(|g| g[0]).collect();
    let tol = f64s(&r["tolerance_finest"]["relative"])[0];
    let err = worst(&t1, &f64s(&r["response_re"]), &f64s(&r["response_im"]));
    assert!(err <= tol, "T1 response {err:e}");
    assert!(
        d.chunks_exact(6)
            .all(|g| g[1..].iter().all(|z| z.norm() == 0.0)),
        "constrained components"
    );
}

/// The 2-DOF chain by SOL 108 and SOL 111 with `DISPLACEMENT = 3` (SET 3 = 2): the grid's T1
/// response equals the `response` of output "2:1" (the same load on the same solve) to
/// round-off, and the set's grid ids are written.
#[test]
fn two_dof_displacement_set_equals_the_response() {
    for deck in ["frf_two_dof_modal.dat", "frf_two_dof_direct.dat"] {
        let text = std::fs::read_to_string(root().join("decks/verify/analytic").join(deck))
            .unwrap()
            .replace(
                "  DLOAD = 7\n",
                "  DLOAD = 7\n  SET 3 = 2\n  DISPLACEMENT = 3\n",
            );
        assert!(text.contains("DISPLACEMENT = 3"), "{deck}");
        let (run, dir) = run_deck(&text);
        run.unwrap_or_else(|e| panic!("{deck}: {e}"));
        let path = dir.path().join("out.h5");
        let out = read_frf(&path);
        let o = out.outputs.iter().position(|x| x == "2:1").unwrap();
        let file = hdf5_metno::File::open(&path).unwrap();
        let g = file.group("results/1/frf").unwrap();
        let ids: Vec<u32> = g
            .dataset("displacement_grid_ids")
            .unwrap()
            .read_raw()
            .unwrap();
        assert_eq!(ids, [2], "{deck}");
        let d: Vec<c64> = g.dataset("displacement").unwrap().read_raw().unwrap();
        assert_eq!(d.len(), 6 * out.hz.len(), "{deck}");
        for (l, grid) in d.chunks_exact(6).enumerate() {
            let want = out.response[l * out.outputs.len() + o];
            assert!(
                (grid[0] - want).norm() <= 1e-12 * want.norm(),
                "{deck} line {l}: {:?} vs {want:?}",
                grid[0]
            );
        }
    }
}

/// 2-DOF chain: receptance at both masses and DISP / VEL / ACCEL sensors, by SOL 108 and by
/// SOL 111 over both modes (and each as `SOL FRF`), against Z(ω)⁻¹; tolerance from the reference, relative to the
/// largest |H| of each output row (rows differ by ω² in scale).
#[test]
fn two_dof_direct_and_modal_match_the_analytic_receptance() {
    two_dof_matches("frf_two_dof");
}

/// The same chain with PARAM,G = 0.05 on top of Rayleigh damping: Z = K(1 + iG) − ω²M + iωC
/// (SOL 108) and ω_j²(1 + iG) on the modal stiffness (SOL 111), both exact for this G K; same
/// tolerance (`reference/analytic/frf_two_dof_g.json`).
#[test]
fn two_dof_structural_damping_matches_the_complex_stiffness() {
    two_dof_matches("frf_two_dof_g");
}

/// The same chain with viscous dampers (CDAMP2 to ground, CDAMP1 + PDAMP between the masses)
/// and GE on the coupling spring: Z = K − ω²M + iω(αM + βK + B) + i·GE·K_e in SOL 108, and in
/// SOL 111 the coupled modal equations (ΦᵀBΦ and Φᵀ GE K_e Φ are not diagonal), exact with both
/// modes; same tolerance (`reference/analytic/frf_two_dof_dampers.json`).
#[test]
fn two_dof_dampers_and_element_ge_match_the_analytic_receptance() {
    two_dof_matches("frf_two_dof_dampers");
}

/// Rods (one with MAT1 GE), a CVISC and a grounded CBUSH with K, B and per-direction GE on a
/// line inclined in x-y, the grids' displacement system along the line: the receptance at a
/// force along the line and a moment about it against a separately written 4-DOF numpy model,
/// direct and coupled modal (`reference/analytic/frf_damped_rods.json`, tolerance 1e-9 of
/// each output's largest |H|: round-off only, all modes superposed).
#[test]
fn rods_cvisc_and_bush_damping_match_the_independent_model() {
    two_dof_matches("frf_damped_rods");
}

/// The chain's modal FRF with a TABDMP1 (TYPE CRIT) selected by SDAMPING: ζ interpolated at
/// the first mode and extrapolated from the table's end points at the second, viscous 2ζ_jω_j
/// per mode (`reference/analytic/frf_two_dof_tabdmp.json`, same tolerance). SOL 108 leaves
/// SDAMPING out with a warning, as a direct solution has no modes.
#[test]
fn two_dof_tabdmp1_modal_damping_matches_the_analytic_receptance() {
    two_dof_matches("frf_two_dof_tabdmp");
    let text =
        std::fs::read_to_string(root().join("decks/verify/analytic/frf_two_dof_tabdmp_modal.dat"))
            .unwrap()
            .replace("SOL 111", "SOL 108");
    let (run, _dir) = run_deck(&text);
    let warnings = run.expect("SOL 108").warnings.join("\n");
    assert!(
        warnings.contains("SDAMPING = 30 is not applied by SOL FRF"),
        "{warnings}"
    );
}

/// The 2-DOF chain without its ground spring is free along x: a 0 Hz line (the static
/// response) is refused by SOL 108 and SOL 111 alike, naming the reason, instead of being
/// solved from round-off pivots or the round-off λ of the rigid-body mode; from 2 Hz up both
/// run.
#[test]
fn free_chain_static_line_is_refused_by_both_methods() {
    let text = std::fs::read_to_string(root().join("decks/verify/analytic/frf_two_dof_modal.dat"))
        .unwrap()
        .replace("CELAS2,11,25000.0,1,1\n", "");
    for deck in [text.clone(), text.replace("SOL 111", "SOL 108")] {
        let at_zero = deck.replace("FREQ,5,2.0,", "FREQ,5,0.0,2.0,");
        let (run, _dir) = run_deck(&at_zero);
        let message = run.expect_err("0 Hz on a free chain").to_string();
        assert!(
            message.contains("at 0 Hz the dynamic stiffness is K (1 + iG), and K is singular"),
            "{message}"
        );
        let (run, _dir) = run_deck(&deck);
        run.expect("2 Hz and up");
    }
}

fn two_dof_matches(case: &str) {
    let r = reference(case);
    let tol = f64s(&r["tolerance_finest"]["relative"])[0];
    let (re, im) = (f64s(&r["H_re"]), f64s(&r["H_im"]));
    let outputs: Vec<String> = r["outputs"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_str().unwrap().to_string())
        .collect();
    // each deck as written (SOL 108, SOL 111) and as `SOL FRF`, which is modal with METHOD
    let runs = r["meshes"].as_array().unwrap().iter().flat_map(|mesh| {
        let path = mesh["deck"].as_str().unwrap().to_string();
        let text = std::fs::read_to_string(root().join(&path)).unwrap();
        let generic = text
            .replace("SOL 108", "SOL FRF")
            .replace("SOL 111", "SOL FRF");
        [
            (path.clone(), text),
            (format!("{path} as SOL FRF"), generic),
        ]
    });
    for (deck, text) in runs {
        let (run, dir) = run_deck(&text);
        let summary = run.unwrap_or_else(|e| panic!("{deck}: {e}"));
        let Some(s) = summary.subcases[0].result::<FrfSummary>() else {
            panic!("{deck}: not a full-model FRF")
        };
        let modes = r["modes"].as_u64().unwrap_or(2) as usize;
        assert_eq!(
            s.modes,
            if deck.contains("modal") { modes } else { 0 },
            "{deck}"
        );
        let out = read_frf(&dir.path().join("out.h5"));
        assert_eq!(out.outputs, outputs, "{deck}");
        let (n_o, n_i) = (outputs.len(), r["inputs_dofs"].as_array().unwrap().len());
        for (o, name) in outputs.iter().enumerate() {
            let idx: Vec<usize> = (0..out.hz.len())
                .flat_map(|l| (0..n_i).map(move |i| (l * n_o + o) * n_i + i))
                .collect();
            let got: Vec<c64> = idx.iter().map(|&k| out.h[k]).collect();
            let err = worst(
                &got,
                &idx.iter().map(|&k| re[k]).collect::<Vec<_>>(),
                &idx.iter().map(|&k| im[k]).collect::<Vec<_>>(),
            );
            println!("{deck} {name}: error {err:.1e}");
            assert!(err <= tol, "{deck} output {name}: {err:e}");
        }
    }
}

/// Cantilever plate 0.3 × 0.1 m, CQUAD4 12 × 4, clamped at x = 0, with the tip grids 13, 39, 65
/// as ASET1 (pROM inputs) and a STRAIN sensor at the root.
/// Case control of the plate FRF runs: SPC, the frequency set 5 and the DLOAD 7 of [`plate_loads`].
const PLATE_CASE: &str = "SPC = 1\nFREQUENCY = 5\nDLOAD = 7\n";

/// The frequency card `freq` (set 5) and a unit RLOAD1 (7) on T3 of the three tip grids.
fn plate_loads(freq: &str) -> String {
    format!(
        "{freq}RLOAD1,7,8,,,20\nDAREA,8,13,3,1.,39,3,1.\nDAREA,8,65,3,1.\nTABLED1,20\n,0.,1.,1000.,1.,ENDT\n"
    )
}

/// The plate's SOL 108 FRF with `loads`: the reference of the modal and pROM runs.
fn plate_direct(loads: &str) -> Frf {
    let (r, dir) = run_deck(&format!(
        "SOL 108\nCEND\n{PLATE_CASE}BEGIN BULK\n{loads}{}ENDDATA\n",
        plate()
    ));
    r.expect("SOL 108");
    read_frf(&dir.path().join("out.h5"))
}

fn plate() -> String {
    let header = "PSHELL,1,1,0.002,1,,1\nMAT1,1,2.1e11,,0.3,7850.\nPARAM,COUPMASS,1\nPARAM,ALPHA1,2.\nPARAM,BETA1,2.e-5\n";
    header.to_string()
        + &common::clamped_plate_mesh(12, 4, 0.3, 0.1)
        + "ASET1,3,13,39,65\nSENSOR,1,ROOT,STRAIN,1,TOP,1.,0.,0.\nSENSOR,2,TIPACC,ACCEL,39,,0.,0.,1.\n"
}

/// The plate's FRF three ways over 5–395 Hz (first bending ≈ 18 Hz, first torsion ≈ 110 Hz,
/// second bending ≈ 115 Hz): inputs and outputs the tip grids' T3 and the two sensors.
/// - direct (SOL 108) is the reference;
/// - modal (SOL 111) with every mode below 5 kHz: the truncation leaves the static
///   flexibility of the modes above, ≲ (400/5000)² ≈ 0.6 % of a typical line near the band
///   top and far less near resonances; bound 2e-2 of max |H| per output row;
/// - the pROM (E as parameter, evaluated at its nominal value, ERRTOL 1e-6): its basis holds
///   the modes below FMAX = 2 kHz and the tip attachment modes, so it is exact at 0 Hz and
///   within the same truncation bound (2e-2) in the band.
#[test]
fn plate_direct_modal_and_prom_agree() {
    let (case, loads) = (PLATE_CASE, plate_loads("FREQ1,5,5.,10.,39\n"));
    let direct = plate_direct(&loads);
    let (r, dir) = run_deck(&format!(
        "SOL 111\nCEND\n{case}METHOD = 10\nBEGIN BULK\nEIGRL,10,,5000.\n{loads}{}ENDDATA\n",
        plate()
    ));
    r.expect("SOL 111");
    let modal = read_frf(&dir.path().join("out.h5"));
    let (r, dir) = run_deck(&format!(
        "SOL PROM\nCEND\nSPC = 1\nPROM = 1\nBEGIN BULK\nPMPAR,1,E,E,1,1.e11,3.e11\nPMOR,1,2,20,2000.,1.e-6\n,1\n{}ENDDATA\n",
        plate()
    ));
    r.expect("SOL PROM");
    let (r, rom_dir) = run_deck(&format!(
        "SOL 111\nCEND\nROM = '{}'\nFREQUENCY = 5\nBEGIN BULK\nFREQ1,5,5.,10.,39\nENDDATA\n",
        dir.path().join("out.h5").display()
    ));
    r.expect("pROM FRF");
    let prom = read_frf(&rom_dir.path().join("out.h5"));
    let outputs = ["13:3", "39:3", "65:3", "ROOT", "TIPACC"];
    for (name, other) in [("modal", &modal), ("pROM", &prom)] {
        assert_eq!(other.outputs, outputs, "{name}");
        assert_eq!(other.hz, direct.hz, "{name}");
        for (o, output) in outputs.iter().enumerate() {
            let idx: Vec<usize> = (0..direct.hz.len())
                .flat_map(|l| (0..3).map(move |i| (l * 5 + o) * 3 + i))
                .collect();
            let scale = idx.iter().map(|&k| direct.h[k].norm()).fold(0.0, f64::max);
            let err = idx
                .iter()
                .map(|&k| (other.h[k] - direct.h[k]).norm())
                .fold(0.0, f64::max)
                / scale;
            println!("{name} vs direct, {output}: {err:.1e}");
            assert!(err <= 2e-2, "{name} vs direct, output {output}: {err:e}");
        }
    }
}

/// Residual vectors (PARAM,RESVEC, default YES): the plate by SOL 111 with only its first 2
/// modes, inputs at the three tip grids, lines 0–50 Hz. With the residual vectors the basis
/// holds K⁻¹ S_in, so at 0 Hz H equals the direct solution to the round-off of the two solves
/// (κ(K_ff)·ε ~ 1e-8 on this plate, see the strain test below: bound 1e-7 of the line's max |H|),
/// and below the first resonance (18.9 Hz) the missing modes' static part is there (1 Hz
/// also within 1e-7). With PARAM,RESVEC,NO the 2 modes miss it: > 1e-3 at 0 Hz, which shows the
/// test can fail. A free chain (K singular) skips them with a warning.
#[test]
fn residual_vectors_make_truncated_modal_frf_exact_at_zero_hz() {
    let (case, loads) = (PLATE_CASE, plate_loads("FREQ,5,0.,1.,5.,10.\n"));
    let direct = plate_direct(&loads);
    // per line: largest |H_modal − H_direct| over the pairs / largest |H_direct| of that line
    let worst_line = |modal: &Frf| -> Vec<f64> {
        let per_line = modal.h.len() / modal.hz.len();
        (0..modal.hz.len())
            .map(|l| {
                let line = l * per_line..(l + 1) * per_line;
                let scale = line.clone().map(|k| direct.h[k].norm()).fold(0.0, f64::max);
                line.map(|k| (modal.h[k] - direct.h[k]).norm())
                    .fold(0.0, f64::max)
                    / scale
            })
            .collect()
    };
    for (param, resvec) in [("", true), ("PARAM,RESVEC,NO\n", false)] {
        let (r, dir) = run_deck(&format!(
            "SOL 111\nCEND\n{case}METHOD = 10\nBEGIN BULK\nEIGRL,10,,,2\n{param}{loads}{}ENDDATA\n",
            plate()
        ));
        let summary = r.expect("SOL 111");
        let Some(s) = summary.subcases[0].result::<FrfSummary>() else {
            panic!("not a full-model FRF")
        };
        assert_eq!((s.modes, s.residual_vectors.is_some()), (2, resvec));
        let err = worst_line(&read_frf(&dir.path().join("out.h5")));
        println!("RESVEC {resvec}: error per line {err:?}");
        if resvec {
            assert_eq!(s.residual_vectors, Some(3), "one per input");
            assert!(err[0] <= 1e-7 && err[1] <= 1e-7, "{err:?}");
        } else {
            assert!(err[0] > 1e-3, "{err:?}");
        }
    }
    let free = std::fs::read_to_string(root().join("decks/verify/analytic/frf_two_dof_modal.dat"))
        .unwrap()
        .replace("CELAS2,11,25000.0,1,1\n", "")
        .replace("EIGRL,10,,,2", "EIGRL,10,,,1");
    let (r, _dir) = run_deck(&free);
    let summary = r.expect("free chain from 2 Hz");
    assert!(
        summary
            .warnings
            .iter()
            .any(|w| w.contains("no residual vectors") && w.contains("K is singular")),
        "{:?}",
        summary.warnings
    );
}

/// STRAIN sensors on solids (CHEXA, centroid strain in basic, eq. 2.31 with all six
/// components) through the full-model FRF at 0 Hz: the RLOAD1 response to the DAREA copy of the
/// static tip load must read what SOL 101's STRAIN output gives, projected on the gauge
/// directions. Both paths solve K u = P on the same f-set (Cholesky vs complex LU, each with one
/// refinement step); a backward-stable solve is accurate to ~κ(K_ff)·ε ≈ 1e-8 for the slender
/// strip's κ ~ 1e8 (the two differ by ~2e-9 here, and further refinement steps move the LU result
/// by as much): bound 1e-7 relative to the largest gauge.
#[test]
fn solid_strain_sensors_read_the_static_strain_at_zero_hz() {
    let text = std::fs::read_to_string(
        root().join("decks/verify/analytic/cantilever_static_solid_n2.dat"),
    )
    .unwrap();
    // element 41: root, top layer (centroid at z = 3t/4, where bending strain is not zero)
    let gauges: [(&str, [f64; 3]); 3] = [
        ("XX", [1.0, 0.0, 0.0]),
        ("XZ", [1.0, 0.0, 1.0]),
        ("XYZ", [1.0, 1.0, 1.0]),
    ];
    let sensors: String = gauges
        .iter()
        .enumerate()
        .map(|(k, (name, d))| {
            format!(
                "SENSOR,{},{name},STRAIN,41,,{:?},{:?},{:?}\n",
                k + 1,
                d[0],
                d[1],
                d[2]
            )
        })
        .collect();
    let statics = text.replace("  DISPLACEMENT = ALL", "  STRAIN = ALL");
    let (r, dir) = run_deck(&statics);
    r.expect("SOL 101");
    let file = hdf5_metno::File::open(dir.path().join("out.h5")).unwrap();
    let s = file.group("results/1/statics/strain/CHEXA").unwrap();
    let ids: Vec<u32> = s.dataset("ids").unwrap().read_raw().unwrap();
    let eps: Vec<f64> = s.dataset("centroid").unwrap().read_raw().unwrap();
    let e = &eps[6 * ids.iter().position(|&i| i == 41).unwrap()..][..6];
    let expected: Vec<f64> = gauges
        .iter()
        .map(|(_, d)| {
            let t = paraflex::geometry::vec3::normalize(*d).unwrap();
            t[0] * t[0] * e[0]
                + t[1] * t[1] * e[1]
                + t[2] * t[2] * e[2]
                + t[0] * t[1] * e[3]
                + t[1] * t[2] * e[4]
                + t[2] * t[0] * e[5]
        })
        .collect();
    let darea: String = text
        .lines()
        .filter(|l| l.starts_with("FORCE,2,"))
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            format!("DAREA,8,{},3,{}\n", f[2], f[4])
        })
        .collect();
    let frf = text
        .replace("SOL 101", "SOL 108")
        .replace("  LOAD = 2", "  FREQUENCY = 5\n  DLOAD = 7")
        .lines()
        .filter(|l| !l.starts_with("FORCE,2,"))
        .collect::<Vec<_>>()
        .join("\n")
        .replace(
            "ENDDATA",
            &format!(
                "FREQ,5,0.\nRLOAD1,7,8,,,20\nTABLED1,20\n,0.,1.,1.,1.,ENDT\n{darea}{sensors}ENDDATA"
            ),
        );
    let (r, dir) = run_deck(&frf);
    r.expect("SOL 108");
    let out = read_frf(&dir.path().join("out.h5"));
    let n_o = out.outputs.len();
    assert_eq!(&out.outputs[n_o - 3..], ["XX", "XZ", "XYZ"]);
    let scale = expected.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
    for (k, want) in expected.iter().enumerate() {
        let got = out.response[n_o - 3 + k];
        println!(
            "{}: FRF at 0 Hz {:.10e} (imag {:.1e}), SOL 101 {want:.10e}",
            gauges[k].0, got.re, got.im
        );
        assert!(
            (got - c64::new(*want, 0.0)).norm() <= 1e-7 * scale,
            "{}: {got:?} vs {want:e}",
            gauges[k].0
        );
    }
}

/// Bad FRF requests are clear errors naming what is missing: no DLOAD, and a DAREA on a
/// constrained DOF (a load there moves nothing).
#[test]
fn missing_dload_and_constrained_inputs_are_reported() {
    let text = std::fs::read_to_string(root().join("decks/verify/analytic/frf_two_dof_direct.dat"))
        .unwrap();
    let (r, _dir) = run_deck(&text.replace("  DLOAD = 7\n", ""));
    let e = r.expect_err("no DLOAD").to_string();
    assert!(e.contains("DLOAD"), "{e}");
    let (r, _dir) = run_deck(&text.replace("DAREA,8,1,1,1.0,2,1,1.0", "DAREA,8,1,1,1.0,2,2,1.0"));
    let e = r
        .expect_err("DAREA on T2, which SPC 23456 holds")
        .to_string();
    assert!(e.contains("GRID 2 component 2 is constrained"), "{e}");
}

/// Enforced motion: a mass on a spring and a damper to a base moved by an SPCD
/// (`reference/analytic/frf_base_excitation.json`). TYPE = DISP by the direct partition method
/// (SOL 108) and TYPE = ACCE (u = a/(−ω²)) by the modal route (SOL 111, quasi-static + modal):
/// the mass's absolute displacement against the transmissibility closed form, the base grid
/// reading its enforced displacement, and the base input's own H entry 1 (the DOF reads its
/// unit motion). Tolerance from the reference (1e-9 of max |X|, no discretization).
#[test]
fn base_excitation_by_spcd_matches_the_transmissibility() {
    let r = reference("frf_base_excitation");
    let tol = f64s(&r["tolerance_finest"]["relative"])[0];
    let hz = f64s(&r["frequency_hz"]);
    for (mesh, key, base) in [(0, "disp", true), (1, "acce", false)] {
        let deck = root().join(r["meshes"][mesh]["deck"].as_str().unwrap());
        let (run, _model, dir) = run_deck_file(&deck);
        run.unwrap_or_else(|e| panic!("{key}: {e}"));
        let path = dir.path().join("out.h5");
        let out = read_frf(&path);
        assert_eq!(out.outputs, ["1:1"], "{key}");
        let file = hdf5_metno::File::open(&path).unwrap();
        let d: Vec<c64> = file
            .dataset("results/1/frf/displacement")
            .unwrap()
            .read_raw()
            .unwrap();
        // lines × 2 grids × 6: grid 2's T1 is the mass, grid 1's T1 the base
        let mass: Vec<c64> = d.chunks_exact(12).map(|l| l[6]).collect();
        let err = worst(
            &mass,
            &f64s(&r[format!("{key}_re")]),
            &f64s(&r[format!("{key}_im")]),
        );
        println!("base excitation {key}: error {err:.1e} (tol {tol:.0e})");
        assert!(err <= tol, "{key}: {err:e}");
        let y = r["inputs"]["Y"].as_f64().unwrap();
        let a = r["inputs"]["A"].as_f64().unwrap();
        for (l, f) in hz.iter().enumerate() {
            let w = 2.0 * std::f64::consts::PI * f;
            let want = if base { y } else { -a / (w * w) };
            let got = d[12 * l];
            assert!(
                (got - c64::new(want, 0.0)).norm() <= 1e-12 * want.abs(),
                "{key}: base {got}"
            );
            assert!(
                (out.h[l] - c64::new(1.0, 0.0)).norm() <= 1e-12,
                "{key}: H {}",
                out.h[l]
            );
        }
    }
}

/// LSEQ with case control LOADSET: the RLOAD1's EXCITEID 8 maps to the static FORCE set 30
/// (2.5 N along T1, the DAREA scale of the reference deck), so the grid's displacement is the
/// closed-form SDOF response of `frf_sdof.json` (same tolerance); the input is named after the
/// EXCITEID. Without LOADSET the EXCITEID selects nothing and the run stops naming it.
#[test]
fn lseq_maps_an_exciteid_to_a_static_load_set() {
    let r = reference("frf_sdof");
    let text = std::fs::read_to_string(root().join(r["meshes"][0]["deck"].as_str().unwrap()))
        .unwrap()
        .replace(
            "  DLOAD = 7\n",
            "  DLOAD = 7\n  LOADSET = 5\n  DISPLACEMENT = ALL\n",
        )
        .replace(
            "DAREA,8,1,1,2.5\n",
            "FORCE,30,1,,2.5,1.,0.,0.\nLSEQ,5,8,30\n",
        );
    assert!(text.contains("LSEQ,5,8,30") && text.contains("LOADSET = 5"));
    let (run, dir) = run_deck(&text);
    run.unwrap_or_else(|e| panic!("{e}"));
    let file = hdf5_metno::File::open(dir.path().join("out.h5")).unwrap();
    let d: Vec<c64> = file
        .dataset("results/1/frf/displacement")
        .unwrap()
        .read_raw()
        .unwrap();
    let t1: Vec<c64> = d.chunks_exact(6).map(|g| g[0]).collect();
    let tol = f64s(&r["tolerance_finest"]["relative"])[0];
    let err = worst(&t1, &f64s(&r["response_re"]), &f64s(&r["response_im"]));
    assert!(err <= tol, "T1 response {err:e}");
    assert_eq!(read_frf(&dir.path().join("out.h5")).outputs, ["LOAD 8"]);
    let (run, _dir) = run_deck(&text.replace("  LOADSET = 5\n", ""));
    let e = run.expect_err("EXCITEID 8 without LOADSET").to_string();
    assert!(e.contains("EXCITEID 8"), "{e}");
}

/// FREQ3, FREQ4 and FREQ5 place the lines of SOL 111 from the natural frequencies of the 2-DOF
/// chain, f₁ = √7500/2π and f₂ = √50000/2π (roots of 2λ² − 115000λ + 7.5e8 = 0), against the
/// lists written out by hand from the card rules (docs/dynamics.md). Tolerance 1e-9 relative:
/// the Lanczos roots of a 2-DOF problem are exact to round-off.
#[test]
fn freq3_freq4_freq5_place_lines_from_the_natural_frequencies() {
    let text = std::fs::read_to_string(root().join("decks/verify/analytic/frf_two_dof_modal.dat"))
        .unwrap();
    let tau = 2.0 * std::f64::consts::PI;
    let (f1, f2) = (7500f64.sqrt() / tau, 50000f64.sqrt() / tau);
    // FREQ3 LINEAR, NEF 5, CLUSTER 2: per sub-range a + (b − a)(1 + s)/2 with
    // s = −1, −√½, 0, √½, 1 (|ξ|^½ sign ξ of ξ = −1, −½, 0, ½, 1)
    let r = 0.5f64.sqrt();
    let cluster = |a: f64, b: f64| -> Vec<f64> {
        [-1.0, -r, 0.0, r, 1.0]
            .iter()
            .map(|s| 0.5 * (a + b) + 0.5 * (b - a) * s)
            .collect()
    };
    let mut freq3: Vec<f64> = [cluster(5.0, f1), cluster(f1, f2), cluster(f2, 45.0)].concat();
    freq3.sort_by(f64::total_cmp);
    freq3.dedup();
    // FREQ3 LOG, NEF 3: the geometric means of each sub-range between 5, f1, f2, 45
    let freq3_log = vec![
        5.0,
        (5.0 * f1).sqrt(),
        f1,
        (f1 * f2).sqrt(),
        f2,
        (f2 * 45.0).sqrt(),
        45.0,
    ];
    // FREQ4 FSPD 0.1, NFM 2 (→ 3): 0.9, 1, 1.1 × f_n kept in [0, 38] (1.1 f₂ = 39.1 dropped)
    let freq4 = vec![0.9 * f1, f1, 1.1 * f1, 0.9 * f2, f2];
    // FREQ5 FR 0.5 1 2 within [10, 40]: 0.5 f₁ = 6.9 and 2 f₂ = 71.2 dropped
    let freq5 = vec![f1, 0.5 * f2, 2.0 * f1, f2];
    let cases = [
        ("FREQ3,6,5.0,45.0,LINEAR,5,2.0", freq3),
        ("FREQ3,6,5.0,45.0,LOG,3", freq3_log),
        ("FREQ4,6,,38.0,,2", freq4),
        ("FREQ5,6,10.0,40.0,0.5,1.0,2.0", freq5),
    ];
    for (card, want) in cases {
        let deck = text
            .replace("FREQUENCY = 5", "FREQUENCY = 6")
            .replace("EIGRL,10,", &format!("{card}\nEIGRL,10,"));
        let (run, dir) = run_deck(&deck);
        run.unwrap_or_else(|e| panic!("{card}: {e}"));
        let got = read_frf(&dir.path().join("out.h5")).hz;
        assert_eq!(got.len(), want.len(), "{card}: {got:?} vs {want:?}");
        for (g, w) in got.iter().zip(&want) {
            assert!((g - w).abs() <= 1e-9 * w, "{card}: {got:?} vs {want:?}");
        }
    }
    // the direct solution ignores FREQ4 with a warning; alone, it leaves no line: an error
    let direct =
        std::fs::read_to_string(root().join("decks/verify/analytic/frf_two_dof_direct.dat"))
            .unwrap()
            .replace("FREQ,5,", "FREQ4,5\nFREQ,5,");
    let (run, _dir) = run_deck(&direct);
    let summary = run.expect("SOL 108 with FREQ and FREQ4");
    let f = summary.subcases[0].result::<FrfSummary>().unwrap();
    assert_eq!(f.lines, 5);
    assert!(
        summary
            .warnings
            .iter()
            .any(|w| w.contains("FREQ4 at") && w.contains("ignored")),
        "{:?}",
        summary.warnings
    );
    let only = direct.replace("FREQ,5,", "FREQ,55,");
    let e = run_deck(&only)
        .0
        .expect_err("FREQ4 alone in SOL 108")
        .to_string();
    assert!(e.contains("selects only FREQ3/FREQ4/FREQ5"), "{e}");
}

/// Random response (RANDOM, RANDPS with a cross-spectrum, TABRND1 LOG/LOG, RANDT1) of the 2-DOF
/// chain loaded on each mass by its own subcase, against `reference/analytic/random_two_dof.json`
/// (numpy: h (G S) hᴴ with the full Hermitian input matrix, trapezoid RMS, Simpson second
/// moment, quad autocorrelation): T1 PSD, RMS, N0 and R(τ) of displacement and acceleration
/// at both grids. Tolerance 1e-8 relative to each quantity's largest value: the direct FRF of a
/// 2-DOF model is exact to round-off (1e-12 in `two_dof_direct…`), the integrals are exact for
/// the piecewise-linear PSD, and quad is asked for 1e-13.
#[test]
fn random_two_dof_matches_the_hermitian_form_reference() {
    let r = reference("random_two_dof");
    let (run, _model, dir) = run_deck_file(&root().join(r["deck"].as_str().unwrap()));
    let summary = run.expect("SOL 108 random");
    let f = summary.subcases[0].result::<FrfSummary>().unwrap();
    assert_eq!(
        f.random.len(),
        1,
        "the random analysis reports with subcase 1"
    );
    assert_eq!(f.random[0].subcases, [1, 2]);
    let file = hdf5_metno::File::open(dir.path().join("out.h5")).unwrap();
    let g = file.group("random/50").unwrap();
    let read = |name: &str| -> Vec<f64> { g.dataset(name).unwrap().read_raw().unwrap() };
    assert_eq!(read("frequency_hz"), f64s(&r["frequency_hz"]));
    assert_eq!(read("lag_s"), f64s(&r["lags_s"]));
    let close = |what: &str, got: Vec<f64>, want: Vec<f64>| {
        assert_eq!(got.len(), want.len(), "{what}");
        let scale = want.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let err = got
            .iter()
            .zip(&want)
            .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()))
            / scale;
        println!("{what}: {err:.1e}");
        assert!(err <= 1e-8, "{what}: {err:e}");
    };
    for q in ["displacement", "acceleration"] {
        let ids: Vec<u32> = g
            .dataset(&format!("{q}_grid_ids"))
            .unwrap()
            .read_raw()
            .unwrap();
        assert_eq!(ids, [1, 2]);
        // T1 (component 0) of each grid; the other components carry no response
        let t1 = |v: Vec<f64>| -> Vec<f64> { v.chunks_exact(6).map(|c| c[0]).collect() };
        let psd = read(&format!("{q}_psd"));
        assert!(
            psd.chunks_exact(6)
                .all(|c| c[1..].iter().all(|&x| x == 0.0))
        );
        close(&format!("{q} PSD"), t1(psd), f64s(&r[q]["psd"]));
        close(
            &format!("{q} RMS"),
            t1(read(&format!("{q}_rms"))),
            f64s(&r[q]["rms"]),
        );
        close(
            &format!("{q} N0"),
            t1(read(&format!("{q}_n0"))),
            f64s(&r[q]["n0"]),
        );
        close(
            &format!("{q} autocorrelation"),
            t1(read(&format!("{q}_autocorrelation"))),
            f64s(&r[q]["autocorrelation"]),
        );
    }
}

/// Bad random input is a clear error naming the card: a set whose RANDPS all name a subcase
/// the deck does not run (one such card among others is left out with a warning, as MSC
/// Nastran runs such decks), a TID with no TABRND1/TABRNDG, an auto-spectrum with an
/// imaginary part (at read).
#[test]
fn random_input_errors_name_the_card() {
    let text =
        std::fs::read_to_string(root().join("decks/verify/analytic/random_two_dof.dat")).unwrap();
    let cases = [
        (
            "RANDPS,50,1,1,1.0,,10\nRANDPS,50,2,2,2.0,,10\nRANDPS,50,1,2,0.5,0.3,10",
            "RANDPS,50,3,3,1.0,,10",
            "names subcases 3 and 3",
        ),
        (
            "RANDPS,50,2,2,2.0,,10",
            "RANDPS,50,2,2,2.0,,11",
            "TID = 11 selects no TABRND1",
        ),
    ];
    for (from, to, want) in cases {
        assert!(text.contains(from));
        let (r, _dir) = run_deck(&text.replace(from, to));
        let e = r.expect_err(to).to_string();
        assert!(e.contains(want), "{to}: {e}");
    }
    let e = common::build_model(&text.replace("RANDPS,50,2,2,2.0,,10", "RANDPS,50,2,2,2.0,0.1,10"))
        .expect_err("Y on an auto-spectrum")
        .join("\n");
    assert!(
        e.contains("RANDPS 50: field 6 (Y)") && e.contains("expected Y = 0"),
        "{e}"
    );
    let extra = text.replace("RANDT1,", "RANDPS,50,3,3,1.0,,10\nRANDT1,");
    let summary = run_deck(&extra)
        .0
        .expect("a RANDPS of subcase 3 is left out");
    assert!(
        summary.warnings.iter().any(|w| w.contains("left out")),
        "{:?}",
        summary.warnings
    );
}

/// RLOAD1 TD given as a real (newer MSC Nastran: a constant D(f)): the SDOF deck's D table is
/// the constant 0.5, so `TD = 0.5` must give the same closed-form response (same reference and
/// tolerance as `sdof_direct_matches_the_closed_form`); `TD = 0.0` is no D term.
#[test]
fn rload1_constant_td_equals_its_constant_table() {
    let r = reference("frf_sdof");
    let text = std::fs::read_to_string(root().join(r["meshes"][0]["deck"].as_str().unwrap()))
        .unwrap()
        .replace(
            "RLOAD1,7,8,0.01,30.0,20,21\n",
            "RLOAD1,7,8,0.01,30.0,20,0.5\n",
        );
    assert!(text.contains(",20,0.5\n"));
    let (run, dir) = run_deck(&text);
    run.unwrap_or_else(|e| panic!("{e}"));
    let out = read_frf(&dir.path().join("out.h5"));
    let tol = f64s(&r["tolerance_finest"]["relative"])[0];
    let err = worst(
        &out.response,
        &f64s(&r["response_re"]),
        &f64s(&r["response_im"]),
    );
    assert!(err <= tol, "response {err:e}");
    // D = 0: the response of C alone differs from the reference
    let (run, dir) = run_deck(&text.replace(",20,0.5\n", ",20,0.0\n"));
    run.unwrap_or_else(|e| panic!("{e}"));
    let out = read_frf(&dir.path().join("out.h5"));
    let err = worst(
        &out.response,
        &f64s(&r["response_re"]),
        &f64s(&r["response_im"]),
    );
    assert!(err > 0.1, "D = 0 should change the response: {err:e}");
}
