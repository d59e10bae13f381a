//! Bad input never panics and every problem is reported where it is (DESIGN.md §3).
//!
//! Every deck in `decks/bad/` (`*.dat`, `*.bdf`; the helpers in `decks/bad/include/` are only
//! reached through INCLUDE) holds one problem. Its first line says what `paraflex check` must
//! report:
//!
//! ```text
//! $ EXPECT <file>:<line> <substring of the message>
//! ```
//!
//! The test runs `paraflex check` on each deck and requires: a non-zero exit code that is not
//! 101 (a panic), one stderr line that carries both `<file>:<line>: ` and the substring, and no
//! "panicked" anywhere in the output. `<file>` is the file the error is in (an include helper
//! for errors inside included files).
//!
//! Decks listed in [`MODEL_LAYER`] are syntactically valid: their problems (dangling and
//! duplicate ids, non-physical materials, degenerate elements) are found by the model
//! validation layer ([`model_layer_rejects_its_bad_decks`]).

use std::path::{Path, PathBuf};

use assert_cmd::cargo::cargo_bin_cmd;

/// Decks whose problem is found by model validation (cross references and physics), not by
/// the deck reader.
const MODEL_LAYER: &[&str] = &[
    "chexa20_midside_folded.dat",
    "cord_cycle.dat",
    "cquad8_midside_folded.dat",
    "ctetra10_midside_folded.dat",
    "dangling_grid.dat",
    "dangling_material.dat",
    "dangling_property.dat",
    "duplicate_element.dat",
    "duplicate_grid.dat",
    "fmb_drive_on_spherical.dat",
    "fmb_jforce_on_inline.dat",
    "fmb_marker_grid_on_rigid.dat",
    "fmb_marker_unknown_body.dat",
    "fmb_pose_unknown_drive.dat",
    "fmb_poses_missing.dat",
    "fmb_poses_transient.dat",
    "fmb_pval_not_body_parameter.dat",
    "inverted_hexa.dat",
    "mat1_e_nonpositive.dat",
    "mat1_nu_half.dat",
    "mat1_rho_negative.dat",
    "method_missing_eigrl.dat",
    "pmpar_nominal_outside.dat",
    "pmpar_range_outside_card.dat",
    "pshell_mid3_without_mid2.dat",
    "pshell_mid4.dat",
    "spc_missing_grid.dat",
    "zero_area_quad.dat",
];

/// Decks that cannot carry an `EXPECT` comment: (name, location, substring).
const NO_HEADER: &[(&str, &str, &str)] = &[("empty.dat", "empty.dat:1", "the deck is empty")];

/// Fewer bad decks than this means the directory was damaged or the glob is wrong.
const MIN_BAD_DECKS: usize = 40;

/// What one bad deck must produce.
#[derive(Debug)]
struct Expectation {
    path: PathBuf,
    name: String,
    /// `file:line` of the expected error.
    loc: String,
    /// A substring of the expected message.
    message: String,
}

fn bad_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("decks/bad")
}

fn expectation(path: &Path) -> Expectation {
    let name = path.file_name().unwrap().to_string_lossy().to_string();
    if let Some((_, loc, message)) = NO_HEADER.iter().find(|(n, _, _)| *n == name) {
        return Expectation {
            path: path.to_path_buf(),
            name,
            loc: loc.to_string(),
            message: message.to_string(),
        };
    }
    let bytes =
        std::fs::read(path).unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()));
    let text = String::from_utf8_lossy(&bytes);
    let first = text.lines().next().unwrap_or("");
    let rest = first.strip_prefix("$ EXPECT ").unwrap_or_else(|| {
        panic!("{name}: first line must be '$ EXPECT file:line message', found '{first}'")
    });
    let (loc, message) = rest
        .split_once(' ')
        .unwrap_or_else(|| panic!("{name}: EXPECT needs 'file:line message'"));
    assert!(
        loc.rsplit_once(':')
            .is_some_and(|(_, line)| line.parse::<u32>().is_ok()),
        "{name}: EXPECT location '{loc}' is not file:line"
    );
    Expectation {
        path: path.to_path_buf(),
        name,
        loc: loc.to_string(),
        message: message.trim().to_string(),
    }
}

/// Every bad deck, sorted by name.
fn bad_decks() -> Vec<Expectation> {
    let mut paths: Vec<PathBuf> = std::fs::read_dir(bad_dir())
        .expect("decks/bad exists")
        .map(|e| e.unwrap().path())
        .filter(|p| p.is_file() && p.extension().is_some_and(|x| x == "dat" || x == "bdf"))
        .collect();
    paths.sort();
    paths.iter().map(|p| expectation(p)).collect()
}

struct Outcome {
    code: Option<i32>,
    stdout: String,
    stderr: String,
}

fn check_deck(path: &Path) -> Outcome {
    let out = cargo_bin_cmd!("paraflex")
        .arg("check")
        .arg(path)
        .output()
        .expect("paraflex runs");
    Outcome {
        code: out.status.code(),
        stdout: String::from_utf8_lossy(&out.stdout).into_owned(),
        stderr: String::from_utf8_lossy(&out.stderr).into_owned(),
    }
}

/// Problems with a run that are failures whatever the deck: a panic or a signal.
fn panic_problem(e: &Expectation, o: &Outcome) -> Option<String> {
    match o.code {
        None => Some(format!("{}: killed by a signal\n{}", e.name, o.stderr)),
        Some(101) => Some(format!("{}: panicked (exit 101)\n{}", e.name, o.stderr)),
        _ if o.stdout.contains("panicked") || o.stderr.contains("panicked") => Some(format!(
            "{}: output mentions a panic\n{}{}",
            e.name, o.stdout, o.stderr
        )),
        _ => None,
    }
}

/// The full expectation: rejected, at the expected place, with the expected message.
fn problem(e: &Expectation, o: &Outcome) -> Option<String> {
    if let Some(p) = panic_problem(e, o) {
        return Some(p);
    }
    if o.code == Some(0) {
        return Some(format!(
            "{}: accepted (exit 0); expected '{} {}'",
            e.name, e.loc, e.message
        ));
    }
    let at = format!("{}: ", e.loc);
    // The file name may be printed with a directory in front: match on the line's text.
    let found = o
        .stderr
        .lines()
        .any(|l| l.contains(&at) && l.contains(&e.message));
    if !found {
        return Some(format!(
            "{}: expected an error at '{}' containing '{}'; stderr:\n{}",
            e.name, e.loc, e.message, o.stderr
        ));
    }
    None
}

fn run_all(decks: &[Expectation], judge: fn(&Expectation, &Outcome) -> Option<String>) {
    let failures: Vec<String> = decks
        .iter()
        .filter_map(|e| judge(e, &check_deck(&e.path)))
        .collect();
    assert!(
        failures.is_empty(),
        "{} of {} bad decks failed:\n\n{}",
        failures.len(),
        decks.len(),
        failures.join("\n\n")
    );
}

#[test]
fn there_are_enough_bad_decks_and_the_lists_name_real_files() {
    let decks = bad_decks();
    assert!(
        decks.len() >= MIN_BAD_DECKS,
        "only {} bad decks in decks/bad",
        decks.len()
    );
    for name in MODEL_LAYER
        .iter()
        .chain(NO_HEADER.iter().map(|(n, _, _)| n))
    {
        assert!(
            decks.iter().any(|d| d.name == *name),
            "{name} is listed but not in decks/bad"
        );
    }
}

#[test]
fn reader_rejects_every_bad_deck_at_its_location() {
    let decks: Vec<Expectation> = bad_decks()
        .into_iter()
        .filter(|d| !MODEL_LAYER.contains(&d.name.as_str()))
        .collect();
    run_all(&decks, problem);
}

#[test]
fn model_layer_rejects_its_bad_decks() {
    let decks: Vec<Expectation> = bad_decks()
        .into_iter()
        .filter(|d| MODEL_LAYER.contains(&d.name.as_str()))
        .collect();
    assert_eq!(decks.len(), MODEL_LAYER.len());
    run_all(&decks, problem);
}
