//! `SOL FMB` statics over pose grids (`POSES = id`, FMBPOSE): a rigid two-link arm against the
//! closed form of its holding torques, the same arm with a compliant shoulder drive against an
//! independent scalar Newton solve, the compliant drive in a single-pose static subcase, and
//! the warm-started grid of a flexible arm against independent single-pose static subcases.

mod common;

use std::path::Path;

use common::{read_dataset, root, run_deck, run_to_file};

const G: f64 = 9.81;
/// The arm of decks/fmb/two_link_arm_poses.dat: masses, lengths and centre-of-mass distances.
const M1: f64 = 2.0;
const M2: f64 = 1.0;
const L1: f64 = 0.6;
const L1C: f64 = 0.3;
const L2C: f64 = 0.25;

/// The closed-form static holding torques [T1, T2] of the arm at (θ1, θ2) (gravity along −y,
/// angles from the straight horizontal arm).
fn holding_torques(t1: f64, t2: f64) -> [f64; 2] {
    let elbow = G * M2 * L2C * (t1 + t2).cos();
    [G * (M1 * L1C + M2 * L1) * t1.cos() + elbow, elbow]
}

/// The largest holding torque's scale g (m1 l1c + m2 (l1 + l2c)).
fn torque_scale() -> f64 {
    G * (M1 * L1C + M2 * (L1 + L2C))
}

fn deck(name: &str) -> String {
    std::fs::read_to_string(root().join(Path::new("decks/fmb").join(name))).expect("deck")
}

/// The rigid arm's holding torques over the 5 × 4 grid meet the closed form to 1e-9 of the
/// torque scale: the drives hold the pose exactly (|Φ| ≤ 1e-12), the constraint forces come
/// out of a Newton solve stopped at a correction below 1e-10 (1 + |q|), and the force balance
/// is linear in them. The grid's values are the Cartesian product, first drive slowest, every
/// pose converged, and the elbow sits at l1 (cos θ1, sin θ1).
#[test]
fn rigid_arm_holding_torques_match_the_closed_form_over_the_grid() {
    let (file, _dir) = run_to_file(&deck("two_link_arm_poses.dat"));
    let g = file.group("results/1/fmb/poses").unwrap();
    let values = read_dataset::<f64>(&g, "values");
    assert_eq!(values.len(), 40);
    assert_eq!(read_dataset::<u32>(&g, "shape"), vec![5, 4]);
    assert_eq!(read_dataset::<u32>(&g, "converged"), vec![1; 20]);
    let (t1, t2) = (
        read_dataset::<f64>(&g, "sensors/T1"),
        read_dataset::<f64>(&g, "sensors/T2"),
    );
    let (ex, ey) = (
        read_dataset::<f64>(&g, "sensors/ELBX"),
        read_dataset::<f64>(&g, "sensors/ELBY"),
    );
    for k in 0..20 {
        let (a, b) = (values[2 * k], values[2 * k + 1]);
        assert!(
            (a - (-0.5 + 0.5 * (k / 4) as f64)).abs() < 1e-15,
            "pose {k}"
        );
        assert!((b - 0.4 * (k % 4) as f64).abs() < 1e-15, "pose {k}");
        let [r1, r2] = holding_torques(a, b);
        assert!(
            (t1[k] - r1).abs() < 1e-9 * torque_scale()
                && (t2[k] - r2).abs() < 1e-9 * torque_scale(),
            "pose {k} ({a}, {b}): T = ({}, {}) vs ({r1}, {r2})",
            t1[k],
            t2[k]
        );
        assert!((ex[k] - L1 * a.cos()).abs() < 1e-12 && (ey[k] - L1 * a.sin()).abs() < 1e-12);
    }
    let iterations = read_dataset::<u32>(&g, "iterations");
    assert!(
        iterations.iter().all(|&n| (1..=20).contains(&n)),
        "{iterations:?}"
    );
    assert!(
        read_dataset::<f64>(&g, "constraint_residual")
            .iter()
            .all(|r| *r <= 1e-12)
    );
}

/// θ1 solving K (θ1d − θ1) = T1(θ1, θ2) by scalar Newton (T1 of [`holding_torques`]).
fn compliant_shoulder(k: f64, target: f64, t2: f64) -> f64 {
    let mut t1 = target;
    for _ in 0..50 {
        let r = k * (target - t1) - holding_torques(t1, t2)[0];
        let slope = -k + G * ((M1 * L1C + M2 * L1) * t1.sin() + M2 * L2C * (t1 + t2).sin());
        t1 -= r / slope;
    }
    t1
}

/// With a compliant shoulder drive (K = 200 N m/rad) the arm sags below each target by the
/// torque over K: the shoulder angle (from the elbow's position) meets the scalar Newton
/// solution of K (θ1d − θ1) = T1(θ1, θ2) to 1e-9 rad, and the drive's torque K (θ1d − θ1)
/// equals the holding torque there.
#[test]
fn compliant_shoulder_drive_sags_by_the_torque_over_its_stiffness() {
    let k = 200.0;
    let text =
        deck("two_link_arm_poses.dat").replace("JDRIVE,1,1,5,1.\n", "JDRIVE,1,1,5,1.,200.\n");
    let (file, _dir) = run_to_file(&text);
    let g = file.group("results/1/fmb/poses").unwrap();
    let values = read_dataset::<f64>(&g, "values");
    let (t1, ex, ey) = (
        read_dataset::<f64>(&g, "sensors/T1"),
        read_dataset::<f64>(&g, "sensors/ELBX"),
        read_dataset::<f64>(&g, "sensors/ELBY"),
    );
    for pose in 0..20 {
        let (target, elbow) = (values[2 * pose], values[2 * pose + 1]);
        let expected = compliant_shoulder(k, target, elbow);
        let shoulder = ey[pose].atan2(ex[pose]);
        assert!(
            (shoulder - expected).abs() < 1e-9,
            "pose {pose}: θ1 = {shoulder} vs {expected}"
        );
        assert!(expected < target - 1e-3 || target.cos() < 0.2);
        let torque = holding_torques(shoulder, elbow)[0];
        assert!((t1[pose] - torque).abs() < 1e-7 * torque_scale());
        assert!((t1[pose] - k * (target - shoulder)).abs() < 1e-7 * torque_scale());
    }
}

/// A single-pose static subcase (FMBSTART = STATIC, no TSTEP, no POSES) with the compliant
/// shoulder drive aimed at its table's value at t = 0 finds the same sagged angle, the rigid
/// elbow drive holds its table's value, and both torques are the static holding torques.
#[test]
fn single_pose_static_subcase_includes_the_compliant_drive_deflection() {
    let (k, target, elbow) = (200.0, 0.7, 0.4);
    let text = deck("two_link_arm_poses.dat")
        .replace("POSES = 1\n", "FMBSTART = STATIC\n")
        .replace("JDRIVE,1,1,5,1.\n", "JDRIVE,1,1,6,1.,200.\n")
        .replace("JDRIVE,2,2,5,1.\n", "JDRIVE,2,2,7,1.\n")
        .replace(
            "ENDDATA",
            "TABLED1,6\n,0.,0.7,10.,0.7,ENDT\nTABLED1,7\n,0.,0.4,10.,0.4,ENDT\nENDDATA",
        );
    let (file, _dir) = run_to_file(&text);
    let g = file.group("results/1/fmb").unwrap();
    let (ex, ey) = (
        read_dataset::<f64>(&g, "sensors/ELBX")[0],
        read_dataset::<f64>(&g, "sensors/ELBY")[0],
    );
    let expected = compliant_shoulder(k, target, elbow);
    assert!((ey.atan2(ex) - expected).abs() < 1e-9);
    let [shoulder, rigid_elbow] = holding_torques(expected, elbow);
    let (t1, t2) = (
        read_dataset::<f64>(&g, "sensors/T1")[0],
        read_dataset::<f64>(&g, "sensors/T2")[0],
    );
    assert!(
        (t1 - shoulder).abs() < 1e-7 * torque_scale(),
        "T1 {t1} vs {shoulder}"
    );
    assert!(
        (t2 - rigid_elbow).abs() < 1e-7 * torque_scale(),
        "T2 {t2} vs {rigid_elbow}"
    );
}

/// Builds the strip body's pROM artifact (decks/fmb/strip_body_prom.dat) as `strip_body.h5`
/// in a temp directory.
fn strip_artifact() -> tempfile::TempDir {
    let (r, dir) = run_deck(&deck("strip_body_prom.dat"));
    r.unwrap_or_else(|e| panic!("strip pROM: {e}"));
    std::fs::rename(dir.path().join("out.h5"), dir.path().join("strip_body.h5")).expect("rename");
    dir
}

/// Runs `text` as a deck beside the artifact in `dir`.
fn run_beside(dir: &tempfile::TempDir, text: &str) -> (hdf5_metno::File, tempfile::TempDir) {
    let path = dir.path().join("deck.dat");
    std::fs::write(&path, text).expect("write deck");
    let (r, _model, out) = common::run_deck_file(&path);
    r.unwrap_or_else(|e| panic!("{e}"));
    let file = hdf5_metno::File::open(out.path().join("out.h5")).expect("open");
    (file, out)
}

/// The flexible two-strip arm over a shoulder grid (elbow at 0.6 rad), each pose started from
/// its neighbour's equilibrium, equals the same poses run as independent single-pose static
/// subcases (full Newton from the kinematic assembly, the drives' tables at the pose): tip
/// height to 1e-9 m (the Newton tolerance 1e-10 (1 + |q|) on coordinates of order 1), holding
/// torques and the tip's deviation from the rigid twin to 1e-7 of their scale.
#[test]
fn warm_started_flexible_grid_equals_independent_single_pose_subcases() {
    let dir = strip_artifact();
    let grid = deck("two_strip_arm_poses.dat").replace(
        "FMBPOSE,1,1,0.,1.5707963267948966,19,2,0.,1.5707963267948966\n,19\n",
        "FMBPOSE,1,1,0.,1.2,5,2,0.6,0.6\n,1\n",
    );
    let (file, _out) = run_beside(&dir, &grid);
    let g = file.group("results/1/fmb/poses").unwrap();
    assert_eq!(read_dataset::<u32>(&g, "converged"), vec![1; 5]);
    let names = ["TIPZ", "T1", "T2", "TIPDEV"];
    let warm: Vec<Vec<f64>> = names
        .iter()
        .map(|n| read_dataset::<f64>(&g, &format!("sensors/{n}")))
        .collect();
    assert!(warm[3].iter().skip(1).all(|d| *d > 1e-4), "{:?}", warm[3]);
    for pose in 0..5 {
        let shoulder = 0.3 * pose as f64;
        let single = deck("two_strip_arm_poses.dat")
            .replace("POSES = 1\n", "FMBSTART = STATIC\n")
            .replace("JDRIVE,1,1,5,1.\n", "JDRIVE,1,1,6,1.\n")
            .replace("JDRIVE,2,2,5,1.\n", "JDRIVE,2,2,7,1.\n")
            .replace(
                "ENDDATA",
                &format!(
                    "TABLED1,6\n,0.,{shoulder:?},10.,{shoulder:?},ENDT\nTABLED1,7\n,0.,0.6,10.,0.6,ENDT\nENDDATA"
                ),
            );
        let (file, _out) = run_beside(&dir, &single);
        let s = file.group("results/1/fmb/sensors").unwrap();
        for (name, series) in names.iter().zip(&warm) {
            let reference = read_dataset::<f64>(&s, name)[0];
            let tolerance = if *name == "TIPZ" {
                1e-9
            } else {
                1e-7 * series.iter().fold(0.0_f64, |a, x| a.max(x.abs()))
            };
            assert!(
                (series[pose] - reference).abs() <= tolerance,
                "pose {pose} {name}: grid {} vs single {reference}",
                series[pose]
            );
        }
    }
}

/// Every problem of the pose-grid input is reported in one pass with its file and line: an
/// axis on a JDRIVE that does not exist, POSES naming no FMBPOSE in one subcase and POSES in a
/// transient subcase in another.
#[test]
fn pose_grid_input_errors_are_reported_together() {
    let text = deck("two_link_arm_poses.dat")
        .replace(
            "POSES = 1\n",
            "SUBCASE 1\n  POSES = 3\nSUBCASE 2\n  POSES = 1\n  TSTEP = 1\n",
        )
        .replace("FMBPOSE,1,1,", "TSTEP,1,10,1.e-3\nFMBPOSE,1,9,");
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("deck.dat");
    std::fs::write(&path, &text).expect("write deck");
    let deck = paraflex::deck::Deck::read(&path).expect("the deck reads");
    let Err(errors) = paraflex::model::Model::build(&deck) else {
        panic!("accepted");
    };
    let message = errors
        .iter()
        .map(ToString::to_string)
        .collect::<Vec<_>>()
        .join("\n");
    for part in [
        "POSES = 3 selects no FMBPOSE",
        "POSES = 1 in a transient subcase",
        "JDRIVE = 9 does not exist (drives: 1 2)",
    ] {
        assert!(message.contains(part), "missing '{part}' in:\n{message}");
    }
}
