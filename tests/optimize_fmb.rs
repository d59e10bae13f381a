//! `SOL OPTIMIZE` on the four-bar with the composite coupler (decks/fourbar/fmb/
//! optimize_composite.dat): the coupler's fibre angle (continuous) and the cranks' density
//! (discrete, one variable setting two parameters) against the mean deviation from the rigid
//! twin and the actuation energy, the peak drive torque bounded. The links' artifacts are built
//! once into a temp directory by the paraflex binary, as a user builds them.
//!
//! - A GRID study equals its designs run one by one as separate `SOL FMB` decks (responses
//!   reduced here from the written histories): the evaluation is the FMB run.
//! - A seeded NSGA-II study: feasibility as the constraint says, the Pareto set non-dominated
//!   and complete, the hypervolume history non-decreasing and equal to the engine's own
//!   recomputation from the written designs and responses; the same seed gives the same study.
//! - Bad input (a DVMAP onto an unknown parameter, bounds outside the pROM's box, an objective
//!   on an unknown MSENSOR, a discrete variable with a DELXV, a GRID larger than its budget)
//!   stops with its error at the card before any evaluation and writes no file.

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;

use common::{read_dataset, root};
use paraflex::optimize::{Archive, EvalError, Evaluated, Scoring, summarize};

const DECKS: &str = "decks/fourbar/fmb";
const STUDY: &str = "optimize_composite.dat";
/// The peak drive torque the study deck allows.
const TORQUE_LIMIT: f64 = 0.1;

fn deck(name: &str) -> String {
    std::fs::read_to_string(root().join(DECKS).join(name)).expect("deck")
}

/// `text` with `from` replaced by `to`; `from` must occur.
fn edit(text: &str, from: &str, to: &str) -> String {
    assert!(text.contains(from), "'{from}' not in the deck");
    text.replace(from, to)
}

/// Runs `paraflex run <deck> -o <out>`.
fn paraflex(deck: &Path, out: &Path) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_paraflex"))
        .arg("run")
        .arg(deck)
        .arg("-o")
        .arg(out)
        .output()
        .expect("run paraflex")
}

/// The directory holding the three links' artifacts and the drive table, built once.
fn artifacts() -> &'static Path {
    static DIR: OnceLock<tempfile::TempDir> = OnceLock::new();
    DIR.get_or_init(|| {
        let dir = tempfile::tempdir().expect("temp dir");
        let meshes = format!("'{}/", root().join("meshes").display());
        for (source, artifact) in [
            ("crank_prom.dat", "crank.h5"),
            ("coupler_composite_prom.dat", "coupler_composite.h5"),
            ("output_crank_prom.dat", "output_crank.h5"),
        ] {
            let path = dir.path().join(source);
            std::fs::write(&path, deck(source).replace("'../../../meshes/", &meshes))
                .expect("write deck");
            let run = paraflex(&path, &dir.path().join(artifact));
            assert!(
                run.status.success(),
                "{artifact}: {}",
                String::from_utf8_lossy(&run.stderr)
            );
        }
        std::fs::copy(
            root().join(DECKS).join("drive.csv"),
            dir.path().join("drive.csv"),
        )
        .expect("csv");
        dir
    })
    .path()
}

/// Runs deck `text` as `name` beside the artifacts, writing `out` (a path in a fresh temp
/// directory); returns the run and the directory.
fn run(name: &str, text: &str) -> (std::process::Output, tempfile::TempDir, PathBuf) {
    let path = artifacts().join(name);
    std::fs::write(&path, text).expect("write deck");
    let out_dir = tempfile::tempdir().expect("temp dir");
    let out = out_dir.path().join("out.h5");
    (paraflex(&path, &out), out_dir, out)
}

/// Runs a study deck that must succeed and opens its optimize group.
fn study(name: &str, text: &str) -> (hdf5_metno::Group, tempfile::TempDir) {
    let (r, dir, out) = run(name, text);
    assert!(
        r.status.success(),
        "{name}: {}",
        String::from_utf8_lossy(&r.stderr)
    );
    let file = hdf5_metno::File::open(&out).expect("open");
    (file.group("results/1/optimize").expect("optimize"), dir)
}

/// Rows of a row-major `rows × cols` dataset.
fn rows(values: Vec<f64>, cols: usize) -> Vec<Vec<f64>> {
    values.chunks(cols).map(<[f64]>::to_vec).collect()
}

/// The trapezoidal time average.
fn mean(t: &[f64], v: &[f64]) -> f64 {
    let area: f64 = (1..t.len())
        .map(|i| 0.5 * (t[i] - t[i - 1]) * (v[i] + v[i - 1]))
        .sum();
    area / (t[t.len() - 1] - t[0])
}

#[test]
fn a_grid_study_equals_its_designs_run_as_separate_fmb_decks() {
    // THETA at 0 and 90 deg by the three densities: six designs
    let text = edit(&deck(STUDY), "MOOPT,1,NSGA2,24,8,1,2", "MOOPT,1,GRID,6,2");
    let (g, _dir) = study("grid.dat", &text);
    let designs = rows(read_dataset::<f64>(&g, "designs"), 2);
    let responses = rows(read_dataset::<f64>(&g, "responses"), 3);
    assert_eq!(designs.len(), 6);
    let mut expected_designs = Vec::new();
    for theta in [0.0, 90.0] {
        for rho in [6000.0, 7990.0, 10000.0] {
            expected_designs.push(vec![theta, rho]);
        }
    }
    assert_eq!(designs, expected_designs);
    let fmb = edit(&deck(STUDY), "SOL OPTIMIZE", "SOL FMB");
    for (design, response) in designs.iter().zip(&responses) {
        let [theta, rho] = [design[0], design[1]];
        let text = edit(
            &fmb,
            "PVAL,1,C.THETA,45.",
            &format!("PVAL,1,C.THETA,{theta:?},IC.RHO,{rho:?},OC.RHO,{rho:?}"),
        );
        let (r, _out_dir, out) = run(&format!("fmb_{theta}_{rho}.dat"), &text);
        assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
        let file = hdf5_metno::File::open(&out).expect("open");
        let h = file.group("results/1/fmb").expect("fmb");
        let t = read_dataset::<f64>(&h, "time");
        let dev = read_dataset::<f64>(&h, "sensors/CDEV");
        let work = read_dataset::<f64>(&h, "sensors/WORK");
        let torque = read_dataset::<f64>(&h, "sensors/TORQUE");
        let reference = [
            mean(&t, &dev),
            work[work.len() - 1],
            torque.iter().fold(0.0_f64, |m, x| m.max(x.abs())),
        ];
        for (k, (got, want)) in response.iter().zip(reference).enumerate() {
            assert!(
                (got - want).abs() <= 1e-12 * want.abs().max(1e-30),
                "design {design:?} response {k}: study {got:e}, SOL FMB {want:e}"
            );
        }
    }
}

/// The archive of a written study, evaluations in order.
fn archive_of(designs: &[Vec<f64>], responses: &[Vec<f64>], errors: &[bool]) -> Archive {
    Archive {
        designs: designs.to_vec(),
        evaluated: responses
            .iter()
            .zip(errors)
            .map(|(r, &failed)| Evaluated {
                result: if failed {
                    Err(EvalError("failed".into()))
                } else {
                    Ok(r.clone())
                },
                seconds: 0.0,
            })
            .collect(),
    }
}

#[test]
fn a_seeded_nsga2_study_marks_feasibility_keeps_its_front_and_repeats() {
    let text = edit(
        &deck(STUDY),
        "MOOPT,1,NSGA2,24,8,1,2",
        "MOOPT,1,NSGA2,16,8,3,2",
    );
    let (g, _dir) = study("nsga2.dat", &text);
    let designs = rows(read_dataset::<f64>(&g, "designs"), 2);
    let responses = rows(read_dataset::<f64>(&g, "responses"), 3);
    let feasible = read_dataset::<u32>(&g, "feasible");
    let pareto: Vec<usize> = read_dataset::<u32>(&g, "pareto")
        .into_iter()
        .map(|i| i as usize)
        .collect();
    let hypervolume = read_dataset::<f64>(&g, "hypervolume");
    assert_eq!(designs.len(), 16);
    for (d, r) in designs.iter().zip(&responses) {
        assert!((0.0..=90.0).contains(&d[0]), "{d:?}");
        assert!([6000.0, 7990.0, 10000.0].contains(&d[1]), "{d:?}");
        assert!(r.iter().all(|v| v.is_finite()), "{r:?}");
    }
    for (i, r) in responses.iter().enumerate() {
        assert_eq!(feasible[i] == 1, r[2] <= TORQUE_LIMIT, "design {i}: {r:?}");
    }
    // the front: feasible, non-dominated, and dominating every other feasible design
    let dominates = |a: &[f64], b: &[f64]| {
        a[..2].iter().zip(&b[..2]).all(|(x, y)| x <= y)
            && a[..2].iter().zip(&b[..2]).any(|(x, y)| x < y)
    };
    assert!(!pareto.is_empty());
    for &i in &pareto {
        assert_eq!(feasible[i], 1);
        assert!(
            (0..designs.len())
                .all(|j| feasible[j] == 0 || !dominates(&responses[j], &responses[i]))
        );
    }
    for j in (0..designs.len()).filter(|j| feasible[*j] == 1 && !pareto.contains(j)) {
        assert!(
            pareto
                .iter()
                .any(|&i| dominates(&responses[i], &responses[j])
                    || responses[i][..2] == responses[j][..2]),
            "design {j} is feasible, off the front and dominated by none of it"
        );
    }
    assert!(
        hypervolume.windows(2).all(|w| w[1] >= w[0]),
        "{hypervolume:?}"
    );
    let errors = vec![false; designs.len()];
    let mut scoring = Scoring::minimize_all(2);
    scoring.constraints.push(paraflex::optimize::Constraint {
        response: 2,
        low: None,
        high: Some(TORQUE_LIMIT),
    });
    let again = summarize(&archive_of(&designs, &responses, &errors), &scoring, None);
    assert_eq!(again.pareto, pareto);
    assert_eq!(again.hypervolume, hypervolume);
    assert_eq!(
        again.feasible,
        feasible.iter().map(|&f| f == 1).collect::<Vec<_>>()
    );

    let (repeat, _dir) = study("nsga2_repeat.dat", &text);
    assert_eq!(read_dataset::<f64>(&repeat, "designs"), designs.concat());
    assert_eq!(
        read_dataset::<f64>(&repeat, "responses"),
        responses.concat()
    );
    for label in ["best_DEV", "best_ENERGY", "knee"] {
        let time = read_dataset::<f64>(&g, &format!("representative/{label}/time"));
        assert_eq!(time.len(), 101, "{label}");
    }
}

#[test]
fn bad_input_stops_before_any_evaluation_and_writes_nothing() {
    let study_deck = deck(STUDY);
    for (name, from, to, expected) in [
        (
            "unknown_target.dat",
            "DVMAP,1,1,C.THETA",
            "DVMAP,1,1,C.PHI",
            "DVMAP 1: field 4 (TARGET1): C.PHI is not BODY.PMPAR of this mechanism",
        ),
        (
            "outside_box.dat",
            "DESVAR,1,THETA,45.,0.,90.",
            "DESVAR,1,THETA,45.,-10.,90.",
            "DESVAR 1: field 5 (XLB): XLB = -1e1 is outside the box [0e0, 9e1] of C.THETA",
        ),
        (
            "unknown_sensor.dat",
            "DOBJ,1,DEV,MIN,CDEV,MEAN",
            "DOBJ,1,DEV,MIN,CDEVX,MEAN",
            "DOBJ 1: field 5 (SOURCE): CDEVX is no MSENSOR of this mechanism",
        ),
        (
            "discrete_delxv.dat",
            "DESVAR,2,RHO,7990.,,,,2",
            "DESVAR,2,RHO,7990.,,,1.,2",
            "a move limit DELXV for a discrete variable",
        ),
        (
            "grid_too_large.dat",
            "MOOPT,1,NSGA2,24,8,1,2",
            "MOOPT,1,GRID,4,3",
            "MOOPT 1: field 4 (NEVAL): the full-factorial grid of 3 level(s) per continuous variable has 9 designs, more than NEVAL = 4",
        ),
    ] {
        let (r, dir, out) = run(name, &edit(&study_deck, from, to));
        let stderr = String::from_utf8_lossy(&r.stderr);
        assert!(!r.status.success(), "{name} ran");
        assert!(stderr.contains(expected), "{name}: {stderr}");
        assert!(
            stderr.contains(&format!("{name}:")),
            "{name}: no file:line in {stderr}"
        );
        assert!(!out.exists(), "{name} wrote {}", out.display());
        assert_eq!(
            std::fs::read_dir(dir.path()).expect("dir").count(),
            0,
            "{name} left a file"
        );
    }
}
