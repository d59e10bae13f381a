//! The thesis's case-study scenes: every deck under `decks/<scene>/` runs in-process, and its
//! frequencies (read back from the HDF5 output, `/results/1/modal/frequency_hz`) and mass (the
//! model's mass properties) are compared with `reference/scenes/<deck stem>.json` when that
//! exists. The tolerances are the JSON's `rel_tol`, written there with their source (thesis
//! tables: 5 % on mass, 10 % on frequencies; analytic decks: justified by the mesh
//! size, meshes/plates.py); nothing here sets or widens one. A scene directory that does not
//! exist yet is reported and skipped, and so is a deck that includes `meshes/full/` (a
//! full-size variant: those meshes are made on demand by `make meshes-full`, not committed). `cargo test --test scenes -- --nocapture` prints the
//! table of achieved against target values.
//!
//! `committed_includes_are_current` regenerates the "test" mesh includes with
//! `meshes/build.py --check` and fails when a committed include is stale, missing or extra.

mod common;

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use paraflex::sequence::modal::ModalSummary;
use serde_json::Value;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The decks of a scene, sorted; None when the scene directory does not exist (yet).
fn scene_decks(scene: &str) -> Option<Vec<PathBuf>> {
    let dir = root().join("decks").join(scene);
    let entries = std::fs::read_dir(&dir).ok()?;
    let mut decks: Vec<PathBuf> = entries
        .map(|e| e.expect("dir entry").path())
        .filter(|p| p.extension().is_some_and(|x| x == "dat"))
        .collect();
    decks.sort();
    Some(decks)
}

fn reference(deck: &Path) -> Option<Value> {
    let stem = deck.file_stem().expect("stem").to_string_lossy();
    let path = root().join("reference/scenes").join(format!("{stem}.json"));
    let text = std::fs::read_to_string(&path).ok()?;
    Some(serde_json::from_str(&text).unwrap_or_else(|e| panic!("{}: {e}", path.display())))
}

fn number(v: &Value, what: &str, json: &str) -> f64 {
    v.as_f64()
        .unwrap_or_else(|| panic!("{json}: {what} is not a number: {v}"))
}

/// One row of the printed table; `Err` rows are collected as failures.
fn row(
    out: &mut String,
    deck: &str,
    quantity: &str,
    achieved: f64,
    target: Option<(f64, f64)>,
) -> Result<(), String> {
    match target {
        None => {
            let _ = writeln!(
                out,
                "{deck:<28} {quantity:<10} {achieved:>12.6} {:>12} {:>9} {:>7}",
                "-", "-", "-"
            );
            Ok(())
        }
        Some((t, tol)) => {
            let err = (achieved - t) / t.abs();
            let ok = err.abs() <= tol;
            let _ = writeln!(
                out,
                "{deck:<28} {quantity:<10} {achieved:>12.6} {t:>12.6} {:>+8.3}% {:>6.2}% {}",
                100.0 * err,
                100.0 * tol,
                if ok { "" } else { "  FAIL" }
            );
            if ok {
                Ok(())
            } else {
                Err(format!(
                    "{deck}: {quantity} = {achieved} vs {t} (error {:+.3} %, tolerance {} %)",
                    100.0 * err,
                    100.0 * tol
                ))
            }
        }
    }
}

/// Run every deck of `decks/<scene>/`, print the table, fail on any mismatch.
fn check_scene(scene: &str) {
    let Some(decks) = scene_decks(scene) else {
        println!("decks/{scene}/ does not exist (yet): nothing to run");
        return;
    };
    let mut table = format!(
        "{:<28} {:<10} {:>12} {:>12} {:>9} {:>7}\n",
        "deck", "quantity", "achieved", "target", "error", "tol"
    );
    let mut failures = Vec::new();
    for path in &decks {
        let name = path
            .file_name()
            .expect("name")
            .to_string_lossy()
            .into_owned();
        let text =
            std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        if text.contains("meshes/full/") {
            let _ = writeln!(
                table,
                "{name:<28} skipped: a full-size variant (includes meshes/full/, made by `make meshes-full`, not committed)"
            );
            continue;
        }
        let t0 = std::time::Instant::now();
        let (result, model, dir) = common::run_deck_file(path);
        let summary = match result {
            Ok(s) => s,
            Err(e) => {
                failures.push(format!("{name}: run failed: {e}"));
                continue;
            }
        };
        if let Some(m) = summary
            .subcases
            .first()
            .and_then(|s| s.result::<ModalSummary>())
            && !m.sturm.is_consistent()
        {
            failures.push(format!("{name}: Sturm check inconsistent: {:?}", m.sturm));
        }
        let file = hdf5_metno::File::open(dir.path().join("out.h5")).expect("open out.h5");
        let freqs: Vec<f64> = file
            .dataset("results/1/modal/frequency_hz")
            .and_then(|d| d.read_raw())
            .unwrap_or_default();
        let mass = model.mass_properties().mass;
        let reference = reference(path);
        let json = format!(
            "reference/scenes/{}.json",
            path.file_stem().expect("stem").to_string_lossy()
        );
        let mass_target = reference.as_ref().and_then(|r| r.get("mass")).map(|m| {
            (
                number(&m["target"], "mass.target", &json),
                number(&m["rel_tol"], "mass.rel_tol", &json),
            )
        });
        failures.extend(row(&mut table, &name, "mass", mass, mass_target).err());
        match reference.as_ref().and_then(|r| r.get("frequencies")) {
            Some(fr) => {
                let targets: Vec<f64> = fr["target"]
                    .as_array()
                    .unwrap_or_else(|| panic!("{json}: frequencies.target"))
                    .iter()
                    .map(|t| number(t, "frequencies.target[]", &json))
                    .collect();
                let tol = number(&fr["rel_tol"], "frequencies.rel_tol", &json);
                let first = fr.get("first_mode").and_then(Value::as_u64).unwrap_or(1) as usize;
                assert!(first >= 1, "{json}: frequencies.first_mode is 1-based");
                if freqs.len() < first - 1 + targets.len() {
                    failures.push(format!(
                        "{name}: {} modes computed, {json} compares modes {first}..{}",
                        freqs.len(),
                        first - 1 + targets.len()
                    ));
                    continue;
                }
                for (k, t) in targets.iter().enumerate() {
                    failures.extend(
                        row(
                            &mut table,
                            &name,
                            &format!("f{} Hz", first + k),
                            freqs[first - 1 + k],
                            Some((*t, tol)),
                        )
                        .err(),
                    );
                }
            }
            None => {
                // no target: print the elastic modes (above 1 Hz; rigid-body modes are ~0)
                for (k, f) in freqs.iter().enumerate().filter(|(_, f)| **f > 1.0) {
                    row(&mut table, &name, &format!("f{} Hz", k + 1), *f, None).expect("no target");
                }
            }
        }
        let _ = writeln!(
            table,
            "{:<28} ran in {:.2} s, {} grids, {} modes",
            "",
            t0.elapsed().as_secs_f64(),
            model.grids.len(),
            freqs.len()
        );
    }
    println!("scene {scene}:\n{table}");
    assert!(
        failures.is_empty(),
        "scene {scene}:\n{}",
        failures.join("\n")
    );
}

#[test]
fn plates() {
    check_scene("plates");
}

#[test]
fn fourbar() {
    check_scene("fourbar");
}

#[test]
fn robot() {
    check_scene("robot");
}

#[test]
fn blade() {
    check_scene("blade");
}

/// `meshes/build.py --check`: the committed "test" includes are byte-identical to what the
/// generators write now. `make test` creates `.venv` first; without it the check fails.
#[test]
fn committed_includes_are_current() {
    check_generator("meshes/build.py");
}

/// `script --check` with the venv's Python must succeed: the committed files it writes are
/// byte-identical to what it writes now. `make test` creates `.venv` first; without it the
/// check fails.
fn check_generator(script: &str) {
    let python = root().join(".venv/bin/python");
    assert!(
        python.exists(),
        "{} is missing: run `make test` (it creates the venv) to check {script}'s files",
        python.display()
    );
    let out = std::process::Command::new(&python)
        .args([script, "--check"])
        .current_dir(root())
        .output()
        .unwrap_or_else(|e| panic!("run {script} --check: {e}"));
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    println!("{text}");
    assert!(out.status.success(), "{script} --check failed:\n{text}");
}

/// The composite link libraries of thesis §6.3.1 (`tools/robot/composite_library.py`): the
/// committed decks are what the generator writes now, and every side's laminate mass, as
/// `paraflex check` computes it, times two (the tables give both sides) is within 5 % of thesis
/// Tables 6.1–6.2 (the tolerance the robot issue sets for these masses; the outline was sized
/// once for the 8-ply mass, so the other counts test the laminate's thickness scaling).
#[test]
fn composite_link_libraries_are_current_and_weigh_what_tables_6_1_and_6_2_say() {
    check_generator("tools/robot/composite_library.py");
    let table: [(&str, [f64; 4]); 2] = [
        ("l2", [0.2652, 0.3536, 0.4420, 0.5304]),
        ("l3", [0.1680, 0.2240, 0.2800, 0.3360]),
    ];
    let dir = root().join("decks/robot/fmb/composite");
    for (link, masses) in table {
        for (plies, both_sides) in [6, 8, 10, 12].into_iter().zip(masses) {
            let deck = dir.join(format!("{link}_{plies}ply_prom.dat"));
            let out = std::process::Command::new(env!("CARGO_BIN_EXE_paraflex"))
                .arg("check")
                .arg(&deck)
                .arg("--json")
                .output()
                .expect("run paraflex check");
            assert!(
                out.status.success(),
                "{}",
                String::from_utf8_lossy(&out.stderr)
            );
            let json: Value = serde_json::from_slice(&out.stdout).expect("check --json");
            let mass = 2.0 * json["mass"].as_f64().expect("mass");
            let error = mass / both_sides - 1.0;
            println!("{link} {plies} plies: {mass:.4} kg against {both_sides} kg ({error:+.3})");
            assert!(error.abs() < 0.05, "{}: {error:+.3}", deck.display());
        }
    }
}
