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
    let mut text = text
        .replace("INCLUDE '", &format!("INCLUDE '{}/", base.display()))
        .replace("TABLEF,9,'", &format!("TABLEF,9,'{}/", base.display()));
    for (start, line) in edits {
        let old = text
            .lines()
            .find(|l| l.starts_with(start))
            .unwrap_or_else(|| panic!("{deck}: no line starts with {start}"))
            .to_string();
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
        let mesh = ["INCLUDE", "PSOLID", "MAT1", "MAT8", "PCOMP"]
            .iter()
            .any(|c| l.starts_with(c));
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
    let path = deck.with_file_name(format!(
        "rom_{}",
        deck.file_name().unwrap().to_str().unwrap()
    ));
    std::fs::write(&path, lines.join("\n") + "\n").unwrap();
    path
}

/// (outputs, inputs, H as f × o × i) of `results/1/frf`.
fn frf(out: &tempfile::TempDir) -> (Vec<String>, Vec<String>, Vec<c64>) {
    let file = hdf5_metno::File::open(out.path().join("out.h5")).unwrap();
    let g = file.group("results/1/frf").unwrap();
    let names = |n: &str| {
        g.dataset(n)
            .unwrap()
            .read_raw::<VarLenUnicode>()
            .unwrap()
            .iter()
            .map(|s| s.to_string())
            .collect::<Vec<_>>()
    };
    (
        names("outputs"),
        names("inputs"),
        g.dataset("H").unwrap().read_raw().unwrap(),
    )
}

/// H(output, input) over the lines.
fn column(h: &(Vec<String>, Vec<String>, Vec<c64>), output: &str, input: &str) -> Vec<c64> {
    let (o, i) = (
        h.0.iter()
            .position(|x| x == output)
            .unwrap_or_else(|| panic!("output {output}")),
        h.1.iter().position(|x| x == input).unwrap(),
    );
    let (n_o, n_i) = (h.0.len(), h.1.len());
    (0..h.2.len() / (n_o * n_i))
        .map(|l| h.2[(l * n_o + o) * n_i + i])
        .collect()
}

fn sensor(out: &tempfile::TempDir, name: &str) -> Vec<f64> {
    let file = hdf5_metno::File::open(out.path().join("out.h5")).unwrap();
    file.dataset(&format!("results/1/transient/sensors/{name}"))
        .unwrap()
        .read_raw()
        .unwrap()
}

/// max |a − b| / max |a|.
fn relative<T: Copy>(a: &[T], b: &[T], norm: impl Fn(T) -> f64, minus: impl Fn(T, T) -> T) -> f64 {
    assert_eq!(a.len(), b.len());
    let scale = a.iter().map(|&x| norm(x)).fold(0.0, f64::max);
    a.iter()
        .zip(b)
        .map(|(&x, &y)| norm(minus(x, y)))
        .fold(0.0, f64::max)
        / scale
}

/// One scene's cross-model comparison: the pROM deck (with the `prom` edits), its ROM at the point (the `rom` edits of
/// the pROM deck: a zero-width box and one sample), the full model at the point (the `point`
/// edits of the FRF and transient decks), `lines` and `steps` edits of the FRF and transient
/// decks, and `scene` edits applied to every deck (e.g. another mesh).
struct Scene {
    name: &'static str,
    prefix: &'static str,
    scene: Vec<(&'static str, String)>,
    prom: Vec<(&'static str, String)>,
    rom: Vec<(&'static str, String)>,
    point: Vec<(&'static str, String)>,
    pval: String,
    lines: (&'static str, String),
    steps: (&'static str, String),
    drive: &'static str,
    /// FRF outputs (drive point, accelerometer, strain gauge) and transient sensors.
    outputs: [&'static str; 3],
    bound: f64,
}

/// Runs the pROM, the ROM, the full model, and both reduced models in frequency and time, and
/// checks max |full − reduced| / max |full| of every output against the scene's bound.
fn full_rom_and_prom_agree(s: &Scene) {
    let tmp = tempfile::tempdir().unwrap();
    let deck = |name: &str| format!("{}_{name}.dat", s.prefix);
    let with = |extra: &[(&'static str, String)]| {
        s.scene
            .iter()
            .cloned()
            .chain(extra.iter().cloned())
            .collect::<Vec<_>>()
    };
    let prom = run(&variant(&deck("prom"), &with(&s.prom), tmp.path()));
    let rom_deck = variant(&deck("prom"), &with(&s.rom), tmp.path());
    let rom_dir = tempfile::tempdir().unwrap();
    std::fs::rename(&rom_deck, rom_dir.path().join("rom.dat")).unwrap();
    let rom = run(&rom_dir.path().join("rom.dat"));
    let reduced = [
        ("ROM", rom.path().join("out.h5")),
        ("pROM", prom.path().join("out.h5")),
    ];
    // frequency
    let full = frf(&run(&variant(
        &deck("frf"),
        &with(&[std::slice::from_ref(&s.lines), &s.point[..]].concat()),
        tmp.path(),
    )));
    let frf_deck = variant(
        &deck("frf"),
        &with(std::slice::from_ref(&s.lines)),
        tmp.path(),
    );
    for (what, artifact) in &reduced {
        let h = frf(&run(&on_rom(&frf_deck, artifact, &s.pval)));
        for output in s.outputs {
            let err = relative(
                &column(&full, output, s.drive),
                &column(&h, output, s.drive),
                |z: c64| z.norm(),
                |x, y| x - y,
            );
            println!("{} FRF, {what} vs full, {output}: {err:.1e}", s.name);
            assert!(
                err <= s.bound,
                "{} FRF {what} vs full, {output}: {err:e}",
                s.name
            );
        }
    }
    // time
    let full = run(&variant(
        &deck("transient"),
        &with(&[std::slice::from_ref(&s.steps), &s.point[..]].concat()),
        tmp.path(),
    ));
    let transient_deck = variant(
        &deck("transient"),
        &with(std::slice::from_ref(&s.steps)),
        tmp.path(),
    );
    for (what, artifact) in &reduced {
        let r = run(&on_rom(&transient_deck, artifact, &s.pval));
        for name in &s.outputs[1..] {
            let err = relative(&sensor(&full, name), &sensor(&r, name), f64::abs, |x, y| {
                x - y
            });
            println!("{} transient, {what} vs full, {name}: {err:.1e}", s.name);
            assert!(
                err <= s.bound,
                "{} transient {what} vs full, {name}: {err:e}",
                s.name
            );
        }
    }
}

/// Blade on its bolts (thesis §3.5, Fig. 3.10 and 3.14) at (E, ρ) = (1.5e11 Pa, 3500 kg/m³),
/// "high E, low ρ", inside the ±40 % box and no sample of the pROM: full model (SOL 108 direct,
/// SOL 109), ROM of the point (24 vectors) and pROM (31 vectors) at the drive point 71 T3, the
/// drive-point accelerance A71 and the spanwise top-face strain S237. Measured (release, the
/// decks as committed), relative to each output's max |H| over the 49 lines in 5–485 Hz: ROM
/// 8.2e-8 / 7.1e-7 / 1.5e-5, pROM 2.3e-6 / 1.7e-6 / 2.0e-5 (71:3 / A71 / S237); on the 0.1 s
/// random-force histories, relative to the peak: ROM 5.4e-7 / 8.6e-5, pROM 1.0e-6 / 2.9e-5
/// (A71 / S237). This test runs 5 lines and 0.02 s (debug build, CPU: pROM build 29 s, ROM build
/// 7 s, ~1.7 s per direct line, 50 ms per full-model step; 59 s in all, against ~85 s with the 9
/// lines, 0.04 s and COLAMD LU it ran with before) and measured at most 9.7e-5 (ROM, S237, transient). Bound 1e-3
/// for all: ten times the largest truncation error.
#[test]
fn blade_full_rom_and_prom_agree_in_frequency_and_time() {
    let (e, rho) = ("1.5E11", "3500.");
    let material = format!("MAT1,1,{e},,0.34,{rho}");
    full_rom_and_prom_agree(&Scene {
        name: "blade",
        prefix: "blade",
        scene: Vec::new(),
        prom: Vec::new(),
        rom: vec![
            ("PMPAR,1,", format!("PMPAR,1,E,E,1,{e},{e}")),
            ("PMPAR,2,", format!("PMPAR,2,RHO,RHO,1,{rho},{rho}")),
            ("PMOR,1,", "PMOR,1,1,15,500.,1.E-3,8".into()),
            ("MAT1,", material.clone()),
        ],
        point: vec![("MAT1,", material)],
        pval: format!("E,{e},RHO,{rho}"),
        // 5 of the deck's 49 lines (5, 125, …, 485 Hz): a direct line costs ~1.7 s of CPU in a
        // debug build; the reduced models' errors grow with frequency, so the top line stays
        lines: ("FREQ1,5,", "FREQ1,5,5.,120.,4".into()),
        // the first 0.02 s of the deck's 0.1 s (200 steps, ~50 ms of CPU each in a debug build;
        // the fade-in ends at 0.01 s)
        steps: ("TSTEP,1,", "TSTEP,1,200,1.E-4,1".into()),
        drive: "71:3",
        outputs: ["71:3", "A71", "S237"],
        bound: 1e-3,
    });
}

/// Composite link L2r (thesis §3.6.4–3.6.5, Fig. 3.21 and 3.26), free-free, on the coarse mesh
/// (`decks/crossmodel/l2r_coarse.bdf`: 499 grids, 1062 f-set DOFs against 6402 on the test
/// mesh, whose direct lines cost minutes in a debug build) at Θ = 30°, inside the [0°, 45°] box
/// and no sample of the 4-sample pROM: full model (SOL 108 direct, SOL 109), ROM of the point
/// (29 vectors) and pROM (92 vectors) at the distal motor axis 1000002 T3, the accelerance
/// A1000002 and the axial top-face strain S123; 5 lines (5, 125, …, 485 Hz) and the first 0.02 s
/// of the random force (200 steps; the fade-in ends at 0.01 s).
///
/// Both builds grow their basis to the numerical rank of the local bases (92 and 29), so the
/// basis does not depend on how often the growth is checked: the FRF-change check runs every 30
/// vectors on 50 lines (PMOR DSIZE, NFREQ) instead of every 5 on 200, which halves the debug
/// build (58 → 27 s of CPU) and leaves the pROM as the deck builds it.
///
/// Measured (debug build), relative to each output's max over the lines / the history:
/// FRF ROM 3.1e-7 / 1.3e-3 / 6.9e-4, pROM 4.0e-8 / 1.6e-4 / 5.2e-4 (1000002:3 / A1000002 /
/// S123); transient ROM 6.3e-4 / 9.3e-4, pROM 7.9e-5 / 4.7e-4 (A1000002 / S123). The largest,
/// the ROM's accelerance at 365 Hz, is the truncation its build accepted (ERRTOL 1e-3 on the FRF
/// change, eq. 3.35); a pROM of 2 samples instead of 4 (54 vectors) measured 5.6e-2 / 6.2e-2 on
/// the same outputs, so the check tells a converged pROM from a short one. Bound 1e-2: ten times
/// the largest truncation error, as for the blade. The pROM (nominal Θ = 20°) evaluated at 30°
/// also carries the CQUAD4's frozen condensation (docs/elements.md "Frozen condensation"; the
/// ROM and the full model condense at 30°): adding the incompatible modes moved the pROM's errors from
/// 6.8e-8 / 1.4e-5 / 3.1e-4 to 2.4e-7 / 5.2e-4 / 4.4e-4 (FRF) and from 2.1e-6 / 2.3e-4 to
/// 8.2e-5 / 3.6e-4 (transient), within the bound.
#[test]
fn composite_link_full_rom_and_prom_agree_in_frequency_and_time() {
    let plies = ",2,0.3E-3,30.,,2,0.3E-3,-30.".to_string();
    let checks = [
        ("PMOR,1,", "PMOR,1,4,16,500.,1.E-3,30".to_string()),
        (",1,ATTACH,KEEP", ",1,ATTACH,KEEP,50".to_string()),
    ];
    full_rom_and_prom_agree(&Scene {
        name: "L2r",
        prefix: "l2r",
        scene: vec![(
            "INCLUDE '",
            format!("INCLUDE '{}/l2r_coarse.bdf'", dir().display()),
        )],
        prom: checks.to_vec(),
        rom: vec![
            ("PMPAR,1,", "PMPAR,1,THETA,THETA,1,30.,30.".into()),
            ("PMOR,1,", "PMOR,1,1,16,500.,1.E-3,30".into()),
            checks[1].clone(),
            (",2,0.3E-3,20.", plies.clone()),
        ],
        point: vec![(",2,0.3E-3,20.", plies)],
        pval: "THETA,30.".into(),
        lines: ("FREQ1,5,", "FREQ1,5,5.,120.,4".into()),
        steps: ("TSTEP,1,", "TSTEP,1,200,1.E-4,1".into()),
        drive: "1000002:3",
        outputs: ["1000002:3", "A1000002", "S123"],
        bound: 1e-2,
    });
}
