//! The `paraflex` command as a user runs it: exit codes, JSON summary, output files.

use std::path::PathBuf;

use assert_cmd::Command;
use paraflex::deck::Deck;
use paraflex::model::Model;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn paraflex() -> Command {
    let mut cmd = Command::cargo_bin("paraflex").expect("binary built");
    cmd.env("HDF5_USE_FILE_LOCKING", "FALSE");
    cmd
}

/// `paraflex check --json` prints exactly the library's summary (the numbers the pyNastran
/// conformance test in tests/conformance_mass.rs compares), for every conformance deck.
#[test]
fn check_json_is_the_model_summary_for_every_conformance_deck() {
    let mut decks: Vec<PathBuf> = std::fs::read_dir(root().join("decks/conformance"))
        .expect("decks/conformance")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "bdf"))
        .collect();
    decks.sort();
    assert!(
        decks.len() >= 30,
        "expected the conformance decks, found {}",
        decks.len()
    );
    for deck in decks {
        let out = paraflex()
            .arg("check")
            .arg("--json")
            .arg(&deck)
            .output()
            .expect("runs");
        assert!(
            out.status.success(),
            "{}: {}",
            deck.display(),
            String::from_utf8_lossy(&out.stderr)
        );
        let printed: serde_json::Value =
            serde_json::from_slice(&out.stdout).expect("one JSON object");
        let model = Model::build(&Deck::read(&deck).expect("reads")).expect("builds");
        let expected = serde_json::to_value(model.summary()).expect("serializes");
        assert_eq!(printed, expected, "{}", deck.display());
        for key in [
            "grids",
            "elements",
            "rigid",
            "dofs",
            "mass",
            "cg",
            "inertia_cg",
            "warnings",
        ] {
            assert!(
                printed.get(key).is_some(),
                "{}: key {key} missing",
                deck.display()
            );
        }
    }
}

#[test]
fn run_demo_writes_model_results_and_xdmf_and_prints_the_frequency_table() {
    let dir = tempfile::tempdir().expect("tempdir");
    let out = dir.path().join("demo.h5");
    let deck = root().join("decks/demo/bracket_plate.dat");
    let result = paraflex()
        .arg("run")
        .arg(&deck)
        .arg("-o")
        .arg(&out)
        .output()
        .expect("runs");
    assert_eq!(
        result.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&result.stderr)
    );
    let stdout = String::from_utf8_lossy(&result.stdout);
    for line in [
        "MODAL",
        "f [Hz]",
        "gen. mass",
        "residual",
        "Sturm check",
        "consistent",
        "AUTOSPC",
        "timings",
    ] {
        assert!(stdout.contains(line), "{line} missing in\n{stdout}");
    }
    assert!(out.exists() && dir.path().join("demo.xdmf").exists());
    let leftovers: Vec<_> = std::fs::read_dir(dir.path())
        .expect("dir")
        .filter_map(|e| e.ok())
        .filter(|e| e.file_name().to_string_lossy().contains(".tmp"))
        .collect();
    assert!(leftovers.is_empty(), "temporary files left: {leftovers:?}");

    let info = paraflex()
        .arg("info")
        .arg("--json")
        .arg(&out)
        .output()
        .expect("runs");
    assert!(
        info.status.success(),
        "{}",
        String::from_utf8_lossy(&info.stderr)
    );
    let summary: serde_json::Value = serde_json::from_slice(&info.stdout).expect("json");
    assert_eq!(summary["model"]["n_grids"], 190, "{summary}");
    assert_eq!(summary["model"]["elements"]["RBE2"], 1, "{summary}");
    assert!(
        summary["results"].to_string().contains("frequency_hz"),
        "{summary}"
    );
}

/// A deck asking for a solution this version does not run (Nastran sequences such as 200, 106,
/// 144) exits 3 naming it and writes nothing: no XDMF, and an earlier output file stays as it
/// was.
#[test]
fn an_unavailable_solution_exits_3_and_writes_nothing() {
    let dir = tempfile::tempdir().expect("tempdir");
    let text =
        std::fs::read_to_string(root().join("decks/demo/bracket_plate.dat")).expect("demo deck");
    for (sol, named) in [
        ("200", "SOL 200 (design optimization)"),
        ("106", "SOL 106 (nonlinear statics)"),
        ("144", "SOL 144 (static aeroelastic response)"),
    ] {
        let deck = dir.path().join("unavailable.dat");
        std::fs::write(&deck, text.replacen("SOL 103", &format!("SOL {sol}"), 1)).expect("write");
        let out = dir.path().join("unavailable.h5");
        std::fs::write(&out, "earlier results").expect("write");
        let result = paraflex()
            .arg("run")
            .arg(&deck)
            .arg("-o")
            .arg(&out)
            .output()
            .expect("runs");
        let stderr = String::from_utf8_lossy(&result.stderr);
        assert_eq!(result.status.code(), Some(3), "SOL {sol}: {stderr}");
        assert!(
            stderr.contains(named) && stderr.contains("is not available in this version"),
            "{stderr}"
        );
        assert_eq!(
            std::fs::read_to_string(&out).expect("kept"),
            "earlier results"
        );
        let mut left: Vec<String> = std::fs::read_dir(dir.path())
            .expect("dir")
            .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
            .collect();
        left.sort();
        assert_eq!(left, ["unavailable.dat", "unavailable.h5"], "SOL {sol}");
    }
}

/// A deck whose subcases mix `ROM =` (a pROM artifact) with full-model subcases is refused
/// before anything runs, naming both groups (one run is on pROMs or on the mesh, not both).
#[test]
fn subcases_mixing_rom_and_full_model_are_refused() {
    let dir = tempfile::tempdir().expect("tempdir");
    let text =
        std::fs::read_to_string(root().join("decks/demo/bracket_plate.dat")).expect("demo deck");
    let deck = dir.path().join("mixed.dat");
    std::fs::write(
        &deck,
        text.replacen("BEGIN BULK", "SUBCASE 2\n  ROM = 'blade.h5'\nBEGIN BULK", 1),
    )
    .expect("write");
    let result = paraflex()
        .arg("run")
        .arg(&deck)
        .arg("-o")
        .arg(dir.path().join("mixed.h5"))
        .output()
        .expect("runs");
    assert_eq!(
        result.status.code(),
        Some(3),
        "{}",
        String::from_utf8_lossy(&result.stderr)
    );
    let stderr = String::from_utf8_lossy(&result.stderr);
    assert!(
        stderr.contains("ROM = in subcase(s) [2] but not in subcase(s) 1"),
        "{stderr}"
    );
}

#[test]
fn invalid_deck_writes_nothing_and_exits_2() {
    let dir = tempfile::tempdir().expect("tempdir");
    let deck = dir.path().join("bad.dat");
    std::fs::write(
        &deck,
        "SOL 103\nCEND\nBEGIN BULK\nGRID,1,,0.,0.,0.\nCQUAD4,1,1,1,2,3,4\nENDDATA\n",
    )
    .expect("write");
    let out = dir.path().join("bad.h5");
    let result = paraflex()
        .arg("run")
        .arg(&deck)
        .arg("-o")
        .arg(&out)
        .output()
        .expect("runs");
    assert_eq!(result.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&result.stderr);
    assert!(stderr.contains("bad.dat:5"), "{stderr}");
    assert_eq!(
        std::fs::read_dir(dir.path()).expect("dir").count(),
        1,
        "only the deck remains"
    );
}

#[test]
fn check_text_names_the_deck_and_counts() {
    let deck = root().join("decks/demo/bracket_plate.dat");
    let out = paraflex().arg("check").arg(&deck).output().expect("runs");
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("CQUAD4 160") && text.contains("190 (1140 DOFs)"),
        "{text}"
    );
}
