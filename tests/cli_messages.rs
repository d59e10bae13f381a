//! The `paraflex` command's messages for a Nastran user's usual slips: a misspelled or
//! unsupported card, the density typed in MAT1's A column, an SPC set no subcase selects, an
//! invalid deck under `check --json`, the modal summary of `info`, and an interrupted run.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use assert_cmd::Command;

fn paraflex() -> Command {
    let mut cmd = Command::cargo_bin("paraflex").expect("binary built");
    cmd.env("HDF5_USE_FILE_LOCKING", "FALSE");
    cmd
}

/// The README's tour plate: 200 × 50 × 2 mm steel, clamped at x = 0, four modes.
const PLATE: &str = "SOL 103
CEND
SPC = 1
METHOD = 1
DISPLACEMENT = ALL
BEGIN BULK
GRID,1,,0.,0.,0.
GRID,2,,0.05,0.,0.
GRID,3,,0.1,0.,0.
GRID,4,,0.15,0.,0.
GRID,5,,0.2,0.,0.
GRID,6,,0.,0.05,0.
GRID,7,,0.05,0.05,0.
GRID,8,,0.1,0.05,0.
GRID,9,,0.15,0.05,0.
GRID,10,,0.2,0.05,0.
CQUAD4,1,1,1,2,7,6
CQUAD4,2,1,2,3,8,7
CQUAD4,3,1,3,4,9,8
CQUAD4,4,1,4,5,10,9
PSHELL,1,1,0.002,1,,1
MAT1,1,2.1e11,,0.3,7850.
SPC1,1,123456,1,6
EIGRL,1,,,4
ENDDATA
";

/// The plate with `from` replaced by `to`, written as `name` in `dir`.
fn plate_variant(dir: &Path, name: &str, from: &str, to: &str) -> PathBuf {
    assert!(PLATE.contains(from), "{from}");
    let path = dir.join(name);
    std::fs::write(&path, PLATE.replacen(from, to, 1)).expect("write deck");
    path
}

fn error_lines(stderr: &str) -> Vec<&str> {
    stderr.lines().filter(|l| l.starts_with("error:")).collect()
}

/// An unsupported card names itself at every occurrence, suggests the supported card a
/// misspelling is close to, and lists the supported cards only once.
#[test]
fn unsupported_cards_suggest_a_spelling_and_list_the_cards_once() {
    let dir = tempfile::tempdir().expect("tempdir");
    let text = PLATE
        .replacen("CQUAD4,1,", "CQAUD4,1,", 1)
        .replacen("CQUAD4,2,", "CGAP,2,", 1)
        .replacen("CQUAD4,3,", "CQAUD4,3,", 1);
    let deck = dir.path().join("typo.dat");
    std::fs::write(&deck, text).expect("write");
    let out = paraflex().arg("check").arg(&deck).output().expect("runs");
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    let errors = error_lines(&stderr);
    assert_eq!(errors.len(), 3, "{stderr}");
    assert!(
        errors[0].contains("typo.dat:17: unsupported bulk data card 'CQAUD4' (did you mean CQUAD4?): paraflex reads GRID"),
        "{stderr}"
    );
    assert!(
        errors[1].ends_with("unsupported bulk data card 'CGAP'"),
        "{stderr}"
    );
    assert!(
        errors[2].ends_with("unsupported bulk data card 'CQAUD4' (did you mean CQUAD4?)"),
        "{stderr}"
    );
    assert_eq!(stderr.matches("paraflex reads").count(), 1, "{stderr}");
}

/// An integer where MAT1 wants a real E is one error, without the knock-on "at least one of
/// E and G must be given".
#[test]
fn an_integer_modulus_is_one_error() {
    let dir = tempfile::tempdir().expect("tempdir");
    let deck = plate_variant(dir.path(), "int_e.dat", "2.1e11", "210000");
    let out = paraflex().arg("check").arg(&deck).output().expect("runs");
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(error_lines(&stderr).len(), 1, "{stderr}");
    assert!(stderr.contains("field 3 (E): expected a real"), "{stderr}");
}

/// The density typed in MAT1's A column of a modal deck: `check` and `run` both stop at the
/// MAT1 card and suggest RHO; the same massless material is fine in statics.
#[test]
fn density_in_the_a_column_of_a_modal_deck_is_found_by_check_and_run() {
    let dir = tempfile::tempdir().expect("tempdir");
    let deck = plate_variant(
        dir.path(),
        "rho_in_a.dat",
        "MAT1,1,2.1e11,,0.3,7850.",
        "MAT1,1,2.1e11,,0.3,,7850.",
    );
    let out_h5 = dir.path().join("rho_in_a.h5");
    let check = paraflex().arg("check").arg(&deck).output().expect("runs");
    let run = paraflex()
        .arg("run")
        .arg(&deck)
        .arg("-o")
        .arg(&out_h5)
        .output()
        .expect("runs");
    for (command, out) in [("check", check), ("run", run)] {
        assert_eq!(out.status.code(), Some(2), "{command}");
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(
            stderr.contains("rho_in_a.dat:22: MAT1 1: field 6 (RHO)")
                && stderr.contains(
                    "did you mean RHO (field 6) = 7.85e3? A (field 7) is the thermal expansion coefficient"
                ),
            "{command}: {stderr}"
        );
        assert!(!stderr.contains("mass matrix is zero"), "{stderr}");
    }
    assert!(!out_h5.exists());

    let text = PLATE.replacen("SOL 103", "SOL 101", 1).replacen(
        "MAT1,1,2.1e11,,0.3,7850.",
        "MAT1,1,2.1e11,,0.3",
        1,
    );
    let statics = dir.path().join("massless_statics.dat");
    std::fs::write(&statics, text).expect("write");
    let out = paraflex()
        .arg("check")
        .arg(&statics)
        .output()
        .expect("runs");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// An SPC set that no subcase selects is a warning at the card, naming the subcases without
/// SPC; a selected set gives none.
#[test]
fn an_spc_set_no_subcase_selects_is_warned_about() {
    let dir = tempfile::tempdir().expect("tempdir");
    let deck = plate_variant(dir.path(), "free.dat", "SPC = 1\n", "");
    let out = paraflex().arg("check").arg(&deck).output().expect("runs");
    assert!(out.status.success());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains(
            "free.dat:22: SPC1 set 1 is selected by no subcase (subcase(s) without SPC =: 1)"
        ),
        "{stderr}"
    );
    let selected = plate_variant(dir.path(), "clamped.dat", "", "");
    let out = paraflex()
        .arg("check")
        .arg(&selected)
        .output()
        .expect("runs");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!stderr.contains("selected by no subcase"), "{stderr}");
}

/// `check --json` on an invalid deck prints the errors as JSON on stdout and exits 2.
#[test]
fn check_json_prints_the_errors_of_an_invalid_deck() {
    let dir = tempfile::tempdir().expect("tempdir");
    let deck = plate_variant(
        dir.path(),
        "dangling.dat",
        "CQUAD4,4,1,4,5,10,9",
        "CQUAD4,4,1,4,5,10,99",
    );
    let out = paraflex()
        .arg("check")
        .arg("--json")
        .arg(&deck)
        .output()
        .expect("runs");
    assert_eq!(out.status.code(), Some(2));
    let printed: serde_json::Value = serde_json::from_slice(&out.stdout).expect("one JSON object");
    let errors = printed["errors"].as_array().expect("errors");
    assert_eq!(errors.len(), 1, "{printed}");
    assert_eq!(errors[0]["line"], 20);
    assert!(
        errors[0]["message"]
            .as_str()
            .is_some_and(|m| m.contains("99")),
        "{printed}"
    );
}

/// `info` on a modal result shows the frequencies and the Sturm check, besides the shapes.
#[test]
fn info_shows_frequencies_and_the_sturm_check() {
    let dir = tempfile::tempdir().expect("tempdir");
    let deck = plate_variant(dir.path(), "plate.dat", "", "");
    let out_h5 = dir.path().join("plate.h5");
    let run = paraflex()
        .arg("run")
        .arg(&deck)
        .arg("-o")
        .arg(&out_h5)
        .output()
        .expect("runs");
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let info = paraflex().arg("info").arg(&out_h5).output().expect("runs");
    let text = String::from_utf8_lossy(&info.stdout);
    assert!(
        text.contains("frequencies [Hz]  4.164700e1  1.991203e2  2.638745e2  6.007068e2"),
        "{text}"
    );
    assert!(
        text.contains("Sturm check       4 eigenvalue(s) below")
            && text.contains("4 found: consistent"),
        "{text}"
    );
}

/// SIGTERM during a run: exit status 143 and no `<out>.tmp-<pid>` left behind.
#[test]
fn an_interrupted_run_leaves_no_temporary_file() {
    let dir = tempfile::tempdir().expect("tempdir");
    // A 120 × 120 CQUAD4 plate and 60 modes: long enough to be interrupted after the output
    // file is opened.
    let n = 120;
    let mut text =
        String::from("SOL 103\nCEND\nSPC = 1\nMETHOD = 1\nDISPLACEMENT = ALL\nBEGIN BULK\n");
    for j in 0..=n {
        for i in 0..=n {
            text += &format!("GRID,{},,{}.,{}.,0.\n", j * (n + 1) + i + 1, i, j);
        }
    }
    for j in 0..n {
        for i in 0..n {
            let a = j * (n + 1) + i + 1;
            text += &format!(
                "CQUAD4,{},1,{a},{},{},{}\n",
                j * n + i + 1,
                a + 1,
                a + n + 2,
                a + n + 1
            );
        }
    }
    text += &format!(
        "PSHELL,1,1,0.01,1,,1\nMAT1,1,2.1e11,,0.3,7850.\nSPC1,1,123456,1,THRU,{}\nEIGRL,1,,,60\nENDDATA\n",
        n + 1
    );
    let deck = dir.path().join("big.dat");
    std::fs::write(&deck, text).expect("write");
    let bin = assert_cmd::cargo::cargo_bin("paraflex");
    let mut child = std::process::Command::new(bin)
        .arg("run")
        .arg(&deck)
        .arg("-o")
        .arg(dir.path().join("big.h5"))
        .env("HDF5_USE_FILE_LOCKING", "FALSE")
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .expect("spawns");
    let tmp = dir.path().join(format!("big.h5.tmp-{}", child.id()));
    let start = Instant::now();
    while !tmp.exists() {
        assert!(
            start.elapsed() < Duration::from_secs(120),
            "no temporary file appeared"
        );
        assert!(
            child.try_wait().expect("wait").is_none(),
            "the run ended early"
        );
        std::thread::sleep(Duration::from_millis(5));
    }
    let killed = std::process::Command::new("kill")
        .arg("-TERM")
        .arg(child.id().to_string())
        .status()
        .expect("kill");
    assert!(killed.success());
    let status = child.wait().expect("waits");
    assert_eq!(status.code(), Some(143));
    let left: Vec<String> = std::fs::read_dir(dir.path())
        .expect("dir")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(left, ["big.dat"]);
}
