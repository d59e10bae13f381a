//! The XDMF files of real runs, read as users read them: `tools/xdmf/check_xdmf.py` opens
//! them with meshio (the mesh file whole, the time series' mesh and step count) and compares
//! points, element ids, step counts, time values and displacements with the HDF5 arrays
//! exactly. SOL 101 (with strains), SOL 103 (a mixed quad/RBE2/CONM2 mesh), SOL 109 and
//! SOL 111 with `DISPLACEMENT = ALL`.

use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// Runs `deck_text` as `<dir>/<name>.dat`; returns the HDF5 path and paraflex's stderr.
fn run(dir: &Path, name: &str, deck_text: &str) -> (PathBuf, String) {
    let deck = dir.join(format!("{name}.dat"));
    std::fs::write(&deck, deck_text).expect("write deck");
    let h5 = dir.join(format!("{name}.h5"));
    let out = Command::new(env!("CARGO_BIN_EXE_paraflex"))
        .arg("run")
        .arg(&deck)
        .arg("-o")
        .arg(&h5)
        .output()
        .expect("run paraflex");
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(out.status.success(), "{name}: {stderr}");
    (h5, stderr)
}

/// The checker's report on `h5` (panics when it finds a mismatch).
fn check(h5: &Path) -> String {
    let python = root().join(".venv/bin/python");
    assert!(
        python.exists(),
        "{} is missing: run `make test` (it creates the venv with meshio and h5py)",
        python.display()
    );
    let out = Command::new(python)
        .arg(root().join("tools/xdmf/check_xdmf.py"))
        .arg(h5)
        .output()
        .expect("run check_xdmf.py");
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(
        out.status.success(),
        "{}: {stdout}{}",
        h5.display(),
        String::from_utf8_lossy(&out.stderr)
    );
    stdout
}

fn deck(rel: &str) -> String {
    std::fs::read_to_string(root().join(rel)).expect("read deck")
}

/// The thin CQUAD4 strip (21 × 3 grids, 40 elements), clamped, tip load 2.
const STRIP: &str = "decks/verify/hard/thin/cquad4_regular_static_t0.01.dat";

#[test]
fn static_modal_transient_and_frf_runs_open_in_meshio_with_the_hdf5_values() {
    let dir = tempfile::tempdir().expect("tempdir");

    let statics = deck(STRIP).replace("DISPLACEMENT = ALL", "DISPLACEMENT = ALL\n  STRAIN = ALL");
    let (h5, _) = run(dir.path(), "strip", &statics);
    let report = check(&h5);
    assert!(
        report.contains("strip.xdmf: meshio: 63 points, 40 cells, 1 static displacement(s)"),
        "{report}"
    );
    assert!(
        report.contains("strip_1_statics.xdmf: meshio: 63 points, 1 steps"),
        "{report}"
    );
    let model = std::fs::read_to_string(dir.path().join("strip.xdmf")).unwrap();
    assert!(model.contains("strip.h5:/results/1/statics/strain/CQUAD4/top"));

    let (h5, _) = run(dir.path(), "bracket", &deck("decks/demo/bracket_plate.dat"));
    let report = check(&h5);
    assert!(
        report.contains("bracket.xdmf: meshio: 190 points, 170 cells"),
        "{report}"
    );
    assert!(
        report.contains("bracket_1_modes.xdmf: meshio: 190 points, 10 steps"),
        "{report}"
    );

    // A load ramped from 0 (the drilling rotations have no mass), 40 steps, output every 4.
    let transient = deck(STRIP)
        .replace("SOL 101", "SOL 109")
        .replace("  LOAD = 2\n", "  DLOAD = 7\n  TSTEP = 1\n")
        .replace(
            "BEGIN BULK\n",
            "BEGIN BULK\nTSTEP,1,40,1.e-4,4\nTLOAD1,7,2,,,9\nTABLED1,9\n,0.,0.,1.e-3,1.,10.,1.,ENDT\n",
        );
    let (h5, _) = run(dir.path(), "ramp", &transient);
    let report = check(&h5);
    assert!(
        report.contains("ramp_1_transient.xdmf: meshio: 63 points, 11 steps"),
        "{report}"
    );

    let frf = deck("decks/verify/analytic/frf_two_dof_modal.dat")
        .replace("  DLOAD = 7\n", "  DLOAD = 7\n  DISPLACEMENT = ALL\n");
    let (h5, stderr) = run(dir.path(), "frf", &frf);
    let report = check(&h5);
    assert!(
        report.contains("frf.xdmf: meshio: 2 points, 4 cells"),
        "{report}"
    );
    assert!(
        stderr.contains(
            "warning: not drawn in the XDMF file: /results/1/frf/displacement: complex values"
        ),
        "{stderr}"
    );
}
