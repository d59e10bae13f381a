//! Speed of the static pose grid ([`paraflex::multibody::poses`]) on the flexible two-strip arm
//! of decks/fmb/two_strip_arm_poses.dat: 19 × 19 poses of the shoulder and elbow drives over
//! [0, π/2] (the robot's workspace-map setting), each pose warm-started from its neighbour's
//! equilibrium, against the same grid with every pose solved from the kinematic assembly.
//!
//!     cargo run --release --example poses_bench [-- N]
//!
//! Builds the strip's pROM artifact (decks/fmb/strip_body_prom.dat) in a temp directory, reads
//! the arm deck beside it and builds its system as `SOL FMB` does. Prints the wall time of the
//! grid solve alone (best of three), the Newton iterations (total and per pose), the
//! factorizations and the poses started from the assembly, for both starts, and the largest
//! difference between the two on the tip height (m) and the holding torques (N m).

use std::path::Path;
use std::time::Instant;

use paraflex::deck::Deck;
use paraflex::discretize::BuildOptions;
use paraflex::discretize::mechanism::{Bodies, build_system};
use paraflex::discretize::pfmb::Pfmb;
use paraflex::io::OutputFile;
use paraflex::model::Model;
use paraflex::multibody::NewtonSettings;
use paraflex::multibody::poses::{PoseGrid, PoseHistories, Start, solve_grid};
use paraflex::sequence::{RunContext, run};

/// Reads and builds the deck at `path` (panics with its errors).
fn model(path: &Path) -> (Deck, Model) {
    let deck = Deck::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let model = Model::build(&deck).unwrap_or_else(|e| panic!("{}: {e:?}", path.display()));
    (deck, model)
}

/// Runs the strip body's `SOL PROM` deck into `dir/strip_body.h5`.
fn build_strip(root: &Path, dir: &Path) {
    let text = std::fs::read_to_string(root.join("decks/fmb/strip_body_prom.dat")).expect("deck");
    let path = dir.join("strip_body_prom.dat");
    std::fs::write(&path, text).expect("write deck");
    let (deck, model) = model(&path);
    let file = OutputFile::create(dir.join("strip_body.h5")).expect("output");
    let ctx = RunContext {
        deck: &deck,
        model: &model,
        output: &file,
        progress: &|_: &str, _: usize, _: usize| {},
        options: BuildOptions { parallel: false },
        engine: None,
    };
    run(&ctx).unwrap_or_else(|e| panic!("strip pROM: {e}"));
    file.commit().expect("commit");
}

fn main() {
    let n: usize = std::env::args()
        .nth(1)
        .map_or(19, |a| a.parse().expect("N: the grid's points per axis"));
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let dir = tempfile::tempdir().expect("temp dir");
    build_strip(root, dir.path());
    let arm = dir.path().join("arm.dat");
    std::fs::copy(root.join("decks/fmb/two_strip_arm_poses.dat"), &arm).expect("copy deck");
    let (_deck, model) = model(&arm);
    let pfmb = Pfmb::of_model(&model).expect("the arm's mechanism");
    let ms = build_system(&pfmb, model.gravity(1), &[], Bodies::Flexible).expect("system");
    let quarter = std::f64::consts::FRAC_PI_2;
    let axis: Vec<f64> = (0..n)
        .map(|i| quarter * i as f64 / (n - 1).max(1) as f64)
        .collect();
    let grid = PoseGrid {
        drives: ms.drives.clone(),
        axes: vec![axis.clone(), axis],
    };
    let sensors = &pfmb.mechanism.sensors;
    let outputs = ms.outputs(
        &sensors[..1]
            .iter()
            .chain(&sensors[2..])
            .cloned()
            .collect::<Vec<_>>(),
    );
    let timed = |start: Start| -> (f64, PoseHistories) {
        let mut best = (f64::INFINITY, PoseHistories::default());
        for _ in 0..3 {
            let clock = Instant::now();
            let h = solve_grid(
                &ms.system,
                None,
                &outputs,
                &grid,
                NewtonSettings::default(),
                start,
            )
            .expect("grid");
            let seconds = clock.elapsed().as_secs_f64();
            if seconds < best.0 {
                best = (seconds, h);
            }
        }
        best
    };
    println!("flexible two-strip arm, {n} x {n} poses");
    println!(
        "| start | wall (ms) | converged | Newton it. | it./pose | factorizations | from assembly |"
    );
    println!("|---|---|---|---|---|---|---|");
    let mut runs = Vec::new();
    for (name, start) in [
        ("neighbour", Start::Neighbour),
        ("assembly", Start::Assembly),
    ] {
        let (seconds, h) = timed(start);
        let total: u32 = h.iterations.iter().sum();
        let poses = h.iterations.len();
        println!(
            "| {name} | {:.1} | {}/{poses} | {total} | {:.2} | {} | {} |",
            seconds * 1e3,
            h.converged.iter().filter(|c| **c).count(),
            f64::from(total) / poses as f64,
            h.factorizations,
            h.assemblies
        );
        runs.push(h);
    }
    println!(
        "{} coordinates, {} constraints",
        runs[0].coordinates, runs[0].constraints
    );
    let names = ["TIPZ (m)", "T1 (N m)", "T2 (N m)"];
    for (k, name) in names.iter().enumerate() {
        let difference = runs[0].outputs[k]
            .iter()
            .zip(&runs[1].outputs[k])
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        println!("largest |neighbour − assembly| of {name}: {difference:.2e}");
    }
}
