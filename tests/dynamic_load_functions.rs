//! Dynamic loads beyond TLOAD1/RLOAD1 with tables: TLOAD2 pulses, RLOAD2 (amplitude and phase
//! tables) and the TABLED2–TABLED4 table forms, against the analytic and independently
//! integrated references of `reference/analytic/{frf_sdof_rload2,tload2_sdof,
//! tload2_sdof_damped,tload_base_excitation}.json` (`tools/analytic/make_cases.py`). Tolerances come from the JSONs, with their reasons.

mod common;

use common::{f64s, json, read_dataset, root, run_deck, run_deck_file};
use faer::c64;

/// An SDOF under a DLOAD of an RLOAD2 (B(f) a TABLED4 power series clamped to its range, φ(f) a
/// TABLED3) and an RLOAD1 whose C(f) is a TABLED2: the forced response at every line equals
/// H (s₁ P₂ + s₂ P₁) evaluated independently in Python, including a line (150 Hz) beyond the
/// power series' range X4 where B is clamped.
#[test]
fn rload2_and_parametric_tables_equal_the_analytic_sdof_response() {
    let r = json("reference/analytic/frf_sdof_rload2.json");
    let deck = root().join(r["meshes"][0]["deck"].as_str().unwrap());
    let (result, _, out) = run_deck_file(&deck);
    result.unwrap_or_else(|e| panic!("{}: {e}", deck.display()));
    let file = hdf5_metno::File::open(out.path().join("out.h5")).expect("open");
    let g = file.group("results/1/frf").expect("frf group");
    let response: Vec<c64> = read_dataset(&g, "response");
    response_matches(&r, &read_dataset::<f64>(&g, "frequency_hz"), &response);
}

/// The SDOF response of `r` (its lines, values and per-line tolerances relative to the peak)
/// against `response` at lines `hz`.
fn response_matches(r: &serde_json::Value, hz: &[f64], response: &[c64]) {
    assert_eq!(hz, f64s(&r["frequency_hz"]));
    let (re, im) = (f64s(&r["response_re"]), f64s(&r["response_im"]));
    let tolerance = f64s(&r["tolerance_finest"]["relative"]);
    let peak = re
        .iter()
        .zip(&im)
        .map(|(a, b)| a.hypot(*b))
        .fold(0.0, f64::max);
    for (l, f) in hz.iter().enumerate() {
        let error = (response[l] - c64::new(re[l], im[l])).norm() / peak;
        println!("{f} Hz: |response − reference| / peak = {error:.1e}");
        assert!(error <= tolerance[l], "{f} Hz: {error:e}");
    }
}

/// The same SDOF with its DAREA replaced by a static FORCE set of the same id (MSC Nastran's
/// EXCITEID may select a static load set): the input is the load vector p = 2.5 e_x, named
/// `LOAD 8`, and its output row is the work-conjugate displacement pᵀu = 2.5 u, so the response
/// divided by 2.5 equals the analytic SDOF response to the same tolerance.
#[test]
fn rload_excitation_by_a_static_force_set_equals_the_analytic_sdof_response() {
    let r = json("reference/analytic/frf_sdof_rload2.json");
    let deck = root().join(r["meshes"][0]["deck"].as_str().unwrap());
    let text = std::fs::read_to_string(&deck).expect("deck");
    assert!(text.contains("DAREA,8,1,1,2.5\n"));
    let (result, dir) = run_deck(&text.replace("DAREA,8,1,1,2.5\n", "FORCE,8,1,,2.5,1.,0.,0.\n"));
    result.expect("run");
    let file = hdf5_metno::File::open(dir.path().join("out.h5")).expect("open");
    let g = file.group("results/1/frf").expect("frf group");
    let response: Vec<c64> = read_dataset(&g, "response");
    let names: Vec<hdf5_metno::types::VarLenUnicode> = g
        .dataset("inputs")
        .and_then(|d| d.read_raw())
        .expect("inputs");
    assert_eq!(names.len(), 1);
    assert_eq!(names[0].as_str(), "LOAD 8");
    let per_unit: Vec<c64> = response.iter().map(|x| x / 2.5).collect();
    response_matches(&r, &read_dataset::<f64>(&g, "frequency_hz"), &per_unit);
}

/// An undamped SDOF under a TLOAD2 pulse with delay, T1, growth exponent, exponential and
/// phase: the displacement history against scipy's DOP853 integration of the same load.
#[test]
fn tload2_pulse_response_equals_the_independent_integration() {
    pulse_response_matches("tload2_sdof");
}

/// The same pulse on the SDOF with a CDAMP2 and GE on its CELAS2 with PARAM,W4: the damping
/// c + GE·k/W4 of Nastran's transient response (tolerance from the JSON, as above). Without
/// W4, GE is left out with a warning naming the spring.
#[test]
fn damped_pulse_response_applies_the_damper_and_ge_over_w4() {
    pulse_response_matches("tload2_sdof_damped");
    let r = json("reference/analytic/tload2_sdof_damped.json");
    let text = std::fs::read_to_string(root().join(r["meshes"][0]["deck"].as_str().unwrap()))
        .unwrap()
        .replace("PARAM,W4,150.0\n", "")
        .replace("TSTEP,1,10000,", "TSTEP,1,10,");
    let (result, _dir) = run_deck(&text);
    let warnings = result.expect("without W4").warnings.join("\n");
    assert!(
        warnings.contains("GE of CELAS2 11 is not applied by SOL TRANSIENT without PARAM,W4"),
        "{warnings}"
    );
}

fn pulse_response_matches(case: &str) {
    let r = json(&format!("reference/analytic/{case}.json"));
    let deck = root().join(r["meshes"][0]["deck"].as_str().unwrap());
    let (result, _, out) = run_deck_file(&deck);
    result.unwrap_or_else(|e| panic!("{}: {e}", deck.display()));
    let file = hdf5_metno::File::open(out.path().join("out.h5")).expect("open");
    let g = file.group("results/1/transient").expect("transient group");
    let time: Vec<f64> = read_dataset(&g, "time");
    let displacement: Vec<f64> = read_dataset(&g, "displacement");
    let (want_time, want) = (f64s(&r["time"]), f64s(&r["u"]));
    assert_eq!(time.len(), want_time.len(), "output times");
    let peak = want.iter().fold(0.0_f64, |a, b| a.max(b.abs()));
    let worst = (0..time.len())
        .map(|i| {
            assert!((time[i] - want_time[i]).abs() < 1e-12, "time row {i}");
            (displacement[6 * i] - want[i]).abs()
        })
        .fold(0.0, f64::max);
    let tolerance = f64s(&r["tolerance_finest"]["relative"])[0];
    println!(
        "{case}: max |u − reference| = {worst:.2e}, peak {peak:.3e} ({:.1e} of it)",
        worst / peak
    );
    assert!(
        peak > 0.0 && worst <= tolerance * peak,
        "{worst:e} vs {peak:e}"
    );
}

/// Enforced motion in the time domain: a base grid held by SPC1 and moved by an SPCD through
/// TLOADs of TYPE = DISP (a DLOAD of a constant and a cosine TLOAD2), VELO (SOL 112), ACCE, and
/// a TABLED1 ramp-hold-ramp of TYPE = DISP (BDF2), with a consistent-mass rod coupling the base's
/// acceleration into the mass. The mass's absolute displacement against scipy's integration of
/// the same equation, within the integrators' a-priori error bounds of the JSON; the base grid
/// moves as prescribed (exactly for DISP; VELO and ACCE integrate g by the method's own rule,
/// within the same bound relative to Y); the ACCEL sensor on the base reads the prescribed
/// acceleration exactly for TYPE = ACCE.
#[test]
fn base_excitation_by_tload_matches_the_independent_integration() {
    let r = json("reference/analytic/tload_base_excitation.json");
    let inputs = &r["inputs"];
    let y = inputs["Y"].as_f64().unwrap();
    let w = 2.0 * std::f64::consts::PI * inputs["f_hz"].as_f64().unwrap();
    let want_time = f64s(&r["time"]);
    let tolerance = f64s(&r["tolerance_finest"]["relative"]);
    let ramp: Vec<(f64, f64)> = r["inputs"]["ramp"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| (p[0].as_f64().unwrap(), p[1].as_f64().unwrap()))
        .collect();
    let ramp_at = |t: f64| {
        let k = ramp
            .iter()
            .rposition(|p| p.0 <= t)
            .unwrap()
            .min(ramp.len() - 2);
        let ((x0, y0), (x1, y1)) = (ramp[k], ramp[k + 1]);
        y * (y0 + (y1 - y0) * (t - x0) / (x1 - x0))
    };
    for (mesh, key) in ["disp", "velo", "acce", "ramp"].iter().enumerate() {
        let deck = root().join(r["meshes"][mesh]["deck"].as_str().unwrap());
        assert!(deck.to_string_lossy().ends_with(&format!("_{key}.dat")));
        let (result, _, out) = run_deck_file(&deck);
        result.unwrap_or_else(|e| panic!("{key}: {e}"));
        let file = hdf5_metno::File::open(out.path().join("out.h5")).expect("open");
        let g = file.group("results/1/transient").expect("transient group");
        let time: Vec<f64> = read_dataset(&g, "time");
        let d: Vec<f64> = read_dataset(&g, "displacement");
        let base_acceleration: Vec<f64> = read_dataset(&g, "sensors/BASEA");
        assert_eq!(time.len(), want_time.len(), "{key}: output times");
        let (want, tol) = if *key == "ramp" {
            (f64s(&r["u_ramp"]), tolerance[1])
        } else {
            (f64s(&r["u_smooth"]), tolerance[0])
        };
        let peak = want.iter().fold(0.0_f64, |a, b| a.max(b.abs()));
        let (mut mass_error, mut base_error) = (0.0_f64, 0.0_f64);
        for (i, t) in time.iter().enumerate() {
            // rows: grid 1 (base) then grid 2 (mass), six components each
            let base = d[12 * i];
            let motion = if *key == "ramp" {
                ramp_at(*t)
            } else {
                y * (1.0 - (w * t).cos())
            };
            mass_error = mass_error.max((d[12 * i + 6] - want[i]).abs());
            base_error = base_error.max((base - motion).abs());
            if *key == "acce" {
                let a = y * w * w * (w * t).cos();
                assert!(
                    (base_acceleration[i] - a).abs() <= 1e-12 * y * w * w,
                    "{key}: base acceleration {} vs {a} at {t}",
                    base_acceleration[i]
                );
            }
        }
        println!(
            "{key}: mass {:.1e} of the peak (bound {tol:.1e}), base {:.1e} of Y",
            mass_error / peak,
            base_error / y
        );
        assert!(mass_error <= tol * peak, "{key}: mass {mass_error:e}");
        let base_bound = if matches!(*key, "disp" | "ramp") {
            1e-12
        } else {
            tol
        };
        assert!(base_error <= base_bound * y, "{key}: base {base_error:e}");
    }
}
