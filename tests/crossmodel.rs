//! Cross-model references (thesis Fig. 3.10, 3.14, 3.21, 3.26): the full model, the
//! non-parametric ROM of a parameter point and the pROM evaluated at that point, in frequency
//! (FRF at the sensors) and in time (sensor histories under a random force), on the case-study
//! scenes (`decks/crossmodel/`, test-size meshes).
//!
//! The ROM of a point is the pROM deck with a zero-width box at the point and one sample
//! (its local basis: the build's normal and static modes at that point), as
//! `tools/prom/error_map.py` builds it. Tolerances: the reduced models' truncation error
//! measured on these decks (stated per test), times ~10 for platform differences in the
//! eigen solutions and factorizations.

mod common;

use std::path::{Path, PathBuf};

use common::run_deck_file;
use faer::c64;
use hdf5_metno::types::VarLenUnicode;

fn dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("decks/crossmodel")
}

/// Writes `deck` (a file of decks/crossmodel) into `out` with its INCLUDE and TABLEF paths made
/// absolute and each (line start, replacement) edit applied to the lines starting so, and returns
/// the path. A missing line is a test error (an edit that changes nothing proves nothing).
fn variant(deck: &str, edits: &[(&str, String)], out: &Path) -> PathBuf {
    let base = dir();
    let text = std::fs::read_to_string(base.join(deck)).unwrap();
    let mut text = text.replace("INCLUDE '", &format!("INCLUDE '{}/", base.display())).replace("TABLEF,9,'", &format!("TABLEF,9,'{}/", base.display()));
    for (start, line) in edits {
        let old = text.lines().find(|l| l.starts_with(start)).unwrap_or_else(|| panic!("{deck}: no line starts with {start}")).to_string();
        text = text.replace(&old, line);
    }
    let path = out.join(deck);
    std::fs::write(&path, text).unwrap();
    path
}

fn run(path: &Path) -> tempfile::TempDir {
    let (r, _model, out) = run_deck_file(path);
    r.unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    out
}

/// The full-model deck at `deck` (a [`variant`]) run on a ROM artifact: `ROM =` and `PVAL = 1`
/// (the card holding `pval`) added, the mesh cards (INCLUDE, PSOLID, MAT1, MAT8, PCOMP and its
/// continuations) dropped.
fn on_rom(deck: &Path, rom: &Path, pval: &str) -> PathBuf {
    let text = std::fs::read_to_string(deck).unwrap();
    let mut lines = Vec::new();
    let mut skipping = false;
    for l in text.lines() {
        let mesh = ["INCLUDE", "PSOLID", "MAT1", "MAT8", "PCOMP"].iter().any(|c| l.starts_with(c));
        skipping = mesh || (skipping && l.starts_with(','));
        if !skipping {
            lines.push(l.to_string());
        }
        if l == "CEND" {
            lines.push(format!("ROM = '{}'\nPVAL = 1", rom.display()));
        }
        if l == "BEGIN BULK" {
            lines.push(format!("PVAL,1,{pval}"));
        }
    }
    let path = deck.with_file_name(format!("rom_{}", deck.file_name().unwrap().to_str().unwrap()));
    std::fs::write(&path, lines.join("\n") + "\n").unwrap();
    path
}

/// (outputs, inputs, H as f × o × i) of `results/1/frf`.
fn frf(out: &tempfile::TempDir) -> (Vec<String>, Vec<String>, Vec<c64>) {
    let file = hdf5_metno::File::open(out.path().join("out.h5")).unwrap();
    let g = file.group("results/1/frf").unwrap();
    let names = |n: &str| g.dataset(n).unwrap().read_raw::<VarLenUnicode>().unwrap().iter().map(|s| s.to_string()).collect::<Vec<_>>();
    (names("outputs"), names("inputs"), g.dataset("H").unwrap().read_raw().unwrap())
}

/// H(output, input) over the lines.
fn column(h: &(Vec<String>, Vec<String>, Vec<c64>), output: &str, input: &str) -> Vec<c64> {
    let (o, i) = (h.0.iter().position(|x| x == output).unwrap_or_else(|| panic!("output {output}")), h.1.iter().position(|x| x == input).unwrap());
    let (n_o, n_i) = (h.0.len(), h.1.len());
    (0..h.2.len() / (n_o * n_i)).map(|l| h.2[(l * n_o + o) * n_i + i]).collect()
}

fn sensor(out: &tempfile::TempDir, name: &str) -> Vec<f64> {
    let file = hdf5_metno::File::open(out.path().join("out.h5")).unwrap();
    file.dataset(&format!("results/1/transient/sensors/{name}")).unwrap().read_raw().unwrap()
}

/// max |a − b| / max |a|.
fn relative<T: Copy>(a: &[T], b: &[T], norm: impl Fn(T) -> f64, minus: impl Fn(T, T) -> T) -> f64 {
    assert_eq!(a.len(), b.len());
    let scale = a.iter().map(|&x| norm(x)).fold(0.0, f64::max);
    a.iter().zip(b).map(|(&x, &y)| norm(minus(x, y))).fold(0.0, f64::max) / scale
}

/// Blade on its bolts (thesis §3.5, Fig. 3.10 and 3.14) at (E, ρ) = (1.5e11 Pa, 3500 kg/m³),
/// "high E, low ρ", inside the ±40 % box and no sample of the pROM: full model (SOL 108 direct,
/// SOL 109), ROM of the point (24 vectors) and pROM (31 vectors) at the drive point 71 T3, the
/// drive-point accelerance A71 and the spanwise top-face strain S237. Measured (release, the
/// decks as committed), relative to each output's max |H| over the 49 lines in 5–485 Hz: ROM
/// 8.2e-8 / 7.1e-7 / 1.5e-5, pROM 2.3e-6 / 1.7e-6 / 2.0e-5 (71:3 / A71 / S237); on the 0.1 s
/// random-force histories, relative to the peak: ROM 5.4e-7 / 8.6e-5, pROM 1.0e-6 / 2.9e-5
/// (A71 / S237). This test runs 9 lines and 0.04 s (a debug build costs ~4 s of CPU per direct
/// line) and measured at most 6.8e-5. Bound 1e-3 for all: ten times the largest truncation error.
#[test]
fn blade_full_rom_and_prom_agree_in_frequency_and_time() {
    let tmp = tempfile::tempdir().unwrap();
    let (e, rho) = ("1.5E11", "3500.");
    let material = || format!("MAT1,1,{e},,0.34,{rho}");
    let prom = run(&variant("blade_prom.dat", &[], tmp.path()));
    let rom_deck = variant(
        "blade_prom.dat",
        &[("PMPAR,1,", format!("PMPAR,1,E,E,1,{e},{e}")), ("PMPAR,2,", format!("PMPAR,2,RHO,RHO,1,{rho},{rho}")), ("PMOR,1,", "PMOR,1,1,15,500.,1.E-3,8".into()), ("MAT1,", material())],
        tmp.path(),
    );
    let rom_dir = tempfile::tempdir().unwrap();
    std::fs::rename(&rom_deck, rom_dir.path().join("rom.dat")).unwrap();
    let rom = run(&rom_dir.path().join("rom.dat"));
    let pval = format!("E,{e},RHO,{rho}");
    let reduced = [("ROM", rom.path().join("out.h5")), ("pROM", prom.path().join("out.h5"))];
    // frequency
    // 9 of the deck's 49 lines (5, 65, …, 485 Hz): a direct line costs ~4 s in a debug build
    let lines = ("FREQ1,5,", "FREQ1,5,5.,60.,8".to_string());
    let full = frf(&run(&variant("blade_frf.dat", &[lines.clone(), ("MAT1,", material())], tmp.path())));
    let frf_deck = variant("blade_frf.dat", &[lines], tmp.path());
    for (what, artifact) in &reduced {
        let h = frf(&run(&on_rom(&frf_deck, artifact, &pval)));
        for output in ["71:3", "A71", "S237"] {
            let err = relative(&column(&full, output, "71:3"), &column(&h, output, "71:3"), |z: c64| z.norm(), |x, y| x - y);
            println!("blade FRF, {what} vs full, {output}: {err:.1e}");
            assert!(err <= 1e-3, "blade FRF {what} vs full, {output}: {err:e}");
        }
    }
    // time
    // the first 0.04 s of the deck's 0.1 s (400 steps; the fade-in ends at 0.01 s)
    let steps = ("TSTEP,1,", "TSTEP,1,400,1.E-4,1".to_string());
    let full = run(&variant("blade_transient.dat", &[steps.clone(), ("MAT1,", material())], tmp.path()));
    let transient_deck = variant("blade_transient.dat", &[steps], tmp.path());
    for (what, artifact) in &reduced {
        let r = run(&on_rom(&transient_deck, artifact, &pval));
        for s in ["A71", "S237"] {
            let err = relative(&sensor(&full, s), &sensor(&r, s), f64::abs, |x, y| x - y);
            println!("blade transient, {what} vs full, {s}: {err:.1e}");
            assert!(err <= 1e-3, "blade transient {what} vs full, {s}: {err:e}");
        }
    }
}
