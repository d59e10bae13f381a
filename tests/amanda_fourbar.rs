//! The AMANDA-EKF (thesis ch. 9) on the flexible four-bar of decks/fourbar/fmb: the transition
//! Jacobian against central differences of the GGL–BDF1 step, the AMANDA step back onto the
//! constraints, and Table 9.1's estimation of the coupler's Young's modulus from sensor set 1.
//!
//! The filter runs the pFMB (the links' parametric artifacts, built here into a temp directory
//! from the pROM decks, as tests/fourbar.rs does). The measurements are
//! reference/amanda_fourbar_set1.csv (tools/amanda/fourbar_measurements.py): a forward run of
//! the same mechanism with its links as NON-parametric ROMs reduced at the true E, plus 1e-7
//! white noise: the data do not come from the model the filter predicts with.
//!
//! The same case runs from the deck decks/fourbar/fmb/fourbar_estimate_ec.dat (`SOL ESTIMATE`
//! on the mechanism): its Table 9.1 bound is asserted on the deck route's output, and the Rust
//! filter is checked to be what the deck runs, step by step. Table 9.1's "E_C, input" case
//! runs from decks/fourbar/fmb/fourbar_estimate_ec_input.dat on
//! reference/amanda_fourbar_input_set1.csv (the same forward run with a 15 Hz, 10 N force on
//! OC).

mod common;

use std::path::Path;
use std::sync::OnceLock;

use common::{read_dataset, root, run_deck_file};
use faer::Mat;
use paraflex::deck::Deck;
use paraflex::discretize::mechanism::{Bodies, MechanismSystem, build_system};
use paraflex::discretize::pfmb::Pfmb;
use paraflex::estimate::errors::{PercentErrors, percent_errors, tail_start};
use paraflex::estimate::mechanism::inputs::{Input, Inputs};
use paraflex::estimate::mechanism::manifold::{Manifold, ManifoldSettings};
use paraflex::estimate::mechanism::nullspace::Partition;
use paraflex::estimate::mechanism::parameters::{EstimatedBody, Parameter, Parameters};
use paraflex::estimate::mechanism::reference::{Reference, StrainReference};
use paraflex::estimate::mechanism::sensors::{Sensor, measure};
use paraflex::estimate::mechanism::transition::transition;
use paraflex::estimate::mechanism::{Amanda, AmandaSetup};
use paraflex::model::Model;
use paraflex::multibody::{Force, Ggl, NewtonSettings, Output, Signal};

const DECKS: &str = "decks/fourbar/fmb";
const E_TRUE: f64 = 201.99e9;
/// Table 9.1's initial guess: 25 % above the true value.
const E_GUESS: f64 = 1.25 * E_TRUE;
const GAUGES: [&str; 3] = ["ICEPS", "CEPS", "OCEPS"];

/// The three parametric link artifacts and the FMB deck beside them, built once.
fn artifacts() -> &'static Path {
    static DIR: OnceLock<tempfile::TempDir> = OnceLock::new();
    DIR.get_or_init(|| {
        let dir = tempfile::tempdir().expect("temp dir");
        let meshes = format!("'{}/", root().join("meshes").display());
        for (deck, artifact) in [
            ("crank_prom.dat", "crank.h5"),
            ("coupler_prom.dat", "coupler.h5"),
            ("output_crank_prom.dat", "output_crank.h5"),
        ] {
            let text = std::fs::read_to_string(root().join(DECKS).join(deck)).expect("deck");
            let path = dir.path().join(deck);
            std::fs::write(&path, text.replace("'../../../meshes/", &meshes)).expect("write");
            let run = std::process::Command::new(env!("CARGO_BIN_EXE_paraflex"))
                .arg("run")
                .arg(&path)
                .arg("-o")
                .arg(dir.path().join(artifact))
                .output()
                .expect("run paraflex");
            assert!(
                run.status.success(),
                "{deck}: {}",
                String::from_utf8_lossy(&run.stderr)
            );
        }
        for file in ["fourbar_steel.dat", "drive.csv"] {
            std::fs::copy(root().join(DECKS).join(file), dir.path().join(file)).expect("copy");
        }
        dir
    })
    .path()
}

/// The estimation deck fourbar_estimate_ec.dat beside the artifacts as `name`, its window cut
/// to `steps` steps, its measurement file read from reference/, and `edit` applied to its text.
fn estimation_deck(
    name: &str,
    steps: usize,
    edit: impl Fn(String) -> String,
) -> std::path::PathBuf {
    deck_beside_artifacts("fourbar_estimate_ec.dat", name, steps, edit)
}

/// The estimation deck `deck` of decks/fourbar/fmb beside the artifacts as `name`
/// ([`estimation_deck`]).
fn deck_beside_artifacts(
    deck: &str,
    name: &str,
    steps: usize,
    edit: impl Fn(String) -> String,
) -> std::path::PathBuf {
    let text = std::fs::read_to_string(root().join(DECKS).join(deck))
        .expect("deck")
        .replace("TSTEP,1,1000,", &format!("TSTEP,1,{steps},"))
        .replace(
            "'../../../reference/",
            &format!("'{}/", root().join("reference").display()),
        );
    let path = artifacts().join(name);
    std::fs::write(&path, edit(text)).expect("write");
    path
}

/// What the deck route wrote over the Rust test's 400 steps.
struct DeckRun {
    /// C.E per step.
    e: Vec<f64>,
    /// The largest constraint residuals of the estimates (position, velocity).
    position: f64,
    velocity: f64,
    /// Whether CEPS is marked measured.
    measured: i64,
    /// The sensitivity per step.
    sensitivity: Vec<f64>,
}

/// The deck route ([`DeckRun`]), run once for the tests that read it.
fn deck_estimate() -> &'static DeckRun {
    static RUN: OnceLock<DeckRun> = OnceLock::new();
    RUN.get_or_init(|| {
        let path = estimation_deck("estimate_ec.dat", 400, |t| t);
        let (result, _, dir) = run_deck_file(&path);
        let summary = result.unwrap_or_else(|e| panic!("{e}"));
        println!("{summary:?}");
        let file = hdf5_metno::File::open(dir.path().join("out.h5")).expect("open");
        let g = file.group("results/1/estimate").expect("estimate group");
        let e = read_dataset::<f64>(&g.group("params").expect("params"), "C.E");
        let largest = |name: &str| {
            read_dataset::<f64>(&g, name)
                .into_iter()
                .fold(0.0, f64::max)
        };
        let measured = (g.dataset("sensors/CEPS").expect("CEPS"))
            .attr("measured")
            .and_then(|a| a.read_scalar::<i64>())
            .expect("measured");
        DeckRun {
            e,
            position: largest("constraint_residual"),
            velocity: largest("velocity_residual"),
            measured,
            sensitivity: read_dataset::<f64>(&g, "sensitivity"),
        }
    })
}

/// The pFMB of fourbar_steel.dat, its system with C.E at `e` and the model's MSENSORs.
fn four_bar(e: f64) -> (Pfmb, MechanismSystem, Model) {
    let deck = Deck::read(&artifacts().join("fourbar_steel.dat")).expect("deck");
    let model = Model::build(&deck).expect("model");
    let pfmb = Pfmb::of_model(&model).expect("pFMB");
    let pval = vec![("C.E".to_string(), e)];
    let system = build_system(&pfmb, model.gravity(1), &pval, Bodies::Flexible).expect("system");
    (pfmb, system, model)
}

/// C.E estimated, C.RHO at its true value.
fn coupler_modulus(pfmb: &Pfmb, system: &MechanismSystem) -> Parameters {
    let c = (pfmb.mechanism.bodies.iter())
        .position(|b| b.name == "C")
        .expect("body C");
    let model = pfmb.bodies[c].clone().expect("C is flexible");
    assert!(system.flexible_of[c].is_some());
    Parameters {
        bodies: vec![EstimatedBody {
            body: c,
            name: "C".into(),
            model,
            fixed: vec![("RHO".into(), 7990.0)],
        }],
        list: vec![Parameter {
            body: 0,
            pmpar: "E".into(),
            initial: E_GUESS,
        }],
    }
}

fn integrator(system: &MechanismSystem, tolerance: f64) -> Ggl {
    let settings = NewtonSettings {
        tolerance,
        ..NewtonSettings::default()
    };
    Ggl::new(system.system.clone(), 1e-3, 0.0, settings).expect("assembly")
}

/// The largest |entry| of `a − b` over the largest |entry| of `b`, on a block.
fn relative_error(
    a: &Mat<f64>,
    b: &Mat<f64>,
    rows: std::ops::Range<usize>,
    cols: std::ops::Range<usize>,
) -> f64 {
    let (mut diff, mut size) = (0.0_f64, 0.0_f64);
    for i in rows {
        for j in cols.clone() {
            diff = diff.max((a[(i, j)] - b[(i, j)]).abs());
            size = size.max(b[(i, j)].abs());
        }
    }
    diff / size
}

/// The transition Jacobian (eq. 9.8) at a moving state of the four-bar (30 steps into the run,
/// the drive turning, the links deforming under gravity) against central differences of the
/// GGL–BDF1 step itself, column by column in (q_{k−1}, v_{k−1}), the amplitude u of an unknown
/// input (a point force at OC's coupler end along x, at u = 3 N so that its q-dependence is in
/// the state columns too) and θ = E_C / E_guess. The
/// Newton iteration stops at 1e-13 here, so the differences' own error is about
/// 1e-13 (1 + |z|) / ε ≈ 1e-7 of ε = 1e-6 relative steps, with O(ε²) truncation: a bound of
/// 1e-4 on each block's largest entry leaves room for both and still fails on any wrong term
/// (a dropped nullspace derivative, parameter rate or input load changes its block at O(1)).
#[test]
fn transition_jacobian_matches_central_differences_of_the_step() {
    let (pfmb, system, _) = four_bar(E_GUESS);
    let parameters = coupler_modulus(&pfmb, &system);
    let mut ggl = integrator(&system, 1e-13);
    let marker = (pfmb.mechanism.markers.iter())
        .position(|m| m.id == 32)
        .expect("marker 32");
    ggl.system.add_force(Force::Point {
        marker: system.markers[marker],
        direction: [1.0, 0.0, 0.0],
        signal: Signal::constant(0.0),
    });
    let inputs = Inputs {
        list: vec![Input {
            force: ggl.system.forces.len() - 1,
            name: "MFORCE7".into(),
        }],
    };
    let u0 = 3.0;
    inputs.apply(&[u0], &mut ggl.system);
    ggl.run(30, |_, _| {}).expect("run");
    let n = ggl.system.size();
    let m = ggl.constraint_count();
    let start = ggl.checkpoint();
    let z0: Vec<f64> = ggl.q.iter().chain(&ggl.v).copied().collect();
    // the step from z0 at θ = 1, and its analytic Jacobian
    let step = |ggl: &mut Ggl, z: &[f64], u: f64, theta: f64| -> Vec<f64> {
        ggl.restore(&start);
        parameters.apply(&[theta], &mut ggl.system).expect("apply");
        inputs.apply(&[u], &mut ggl.system);
        ggl.q.copy_from_slice(&z[..n]);
        ggl.v.copy_from_slice(&z[n..]);
        ggl.step().expect("step");
        ggl.q.iter().chain(&ggl.v).copied().collect()
    };
    step(&mut ggl, &z0, u0, 1.0);
    let mut phi_q = Mat::zeros(m, n);
    ggl.equations
        .constraints
        .jacobian(&ggl.system.layout, &ggl.q, ggl.time, phi_q.as_mut());
    let nullspace = Partition::choose(phi_q.as_ref())
        .expect("partition")
        .nullspace(phi_q.as_ref())
        .expect("nullspace");
    let rates = parameters
        .rates(&[1.0], &ggl.system, &ggl.q, &ggl.v)
        .expect("rates");
    let loads = inputs.unit_loads(&ggl.system, &ggl.q, ggl.time);
    let j = transition(&ggl, (&z0[..n], &z0[n..]), &nullspace, &loads, &rates).expect("Jacobian");
    let analytic = Mat::from_fn(2 * n, 2 * n + 2, |i, c| match c {
        c if c < 2 * n => j.states[(i, c)],
        c if c == 2 * n => j.inputs[(i, 0)],
        _ => j.parameters[(i, 0)],
    });
    let mut numeric = Mat::zeros(2 * n, 2 * n + 2);
    for c in 0..2 * n + 2 {
        let (plus, minus, eps) = if c < 2 * n {
            let eps = 1e-6 * (1.0 + z0[c].abs());
            let mut z = z0.clone();
            z[c] = z0[c] + eps;
            let plus = step(&mut ggl, &z, u0, 1.0);
            z[c] = z0[c] - eps;
            (plus, step(&mut ggl, &z, u0, 1.0), eps)
        } else if c == 2 * n {
            let eps = 1e-6 * (1.0 + u0);
            (
                step(&mut ggl, &z0, u0 + eps, 1.0),
                step(&mut ggl, &z0, u0 - eps, 1.0),
                eps,
            )
        } else {
            let eps = 1e-6;
            (
                step(&mut ggl, &z0, u0, 1.0 + eps),
                step(&mut ggl, &z0, u0, 1.0 - eps),
                eps,
            )
        };
        for i in 0..2 * n {
            numeric[(i, c)] = (plus[i] - minus[i]) / (2.0 * eps);
        }
    }
    let blocks = [
        ("∂q/∂q", 0..n, 0..n),
        ("∂q/∂v", 0..n, n..2 * n),
        ("∂v/∂q", n..2 * n, 0..n),
        ("∂v/∂v", n..2 * n, n..2 * n),
        ("∂q/∂u", 0..n, 2 * n..2 * n + 1),
        ("∂v/∂u", n..2 * n, 2 * n..2 * n + 1),
        ("∂q/∂θ", 0..n, 2 * n + 1..2 * n + 2),
        ("∂v/∂θ", n..2 * n, 2 * n + 1..2 * n + 2),
    ];
    for (name, rows, cols) in blocks {
        let e = relative_error(&analytic, &numeric, rows, cols);
        println!("{name}: relative error {e:.2e}");
        assert!(e < 1e-4, "{name}: {e:e}");
    }
}

/// Rows (time, ICEPS, CEPS, OCEPS noisy) of reference/amanda_fourbar_set1.csv.
fn measurements() -> Vec<[f64; 4]> {
    let text = std::fs::read_to_string(root().join("reference/amanda_fourbar_set1.csv"))
        .expect("measurements");
    text.lines()
        .filter(|l| !l.starts_with('#'))
        .map(|l| {
            let v: Vec<f64> = l.split(',').map(|x| x.parse().expect("number")).collect();
            [v[0], v[1], v[2], v[3]]
        })
        .collect()
}

/// Sensor set 1: the mid-span gauge of each link, absolute strain, R = (1e-7)².
fn set_1(system: &MechanismSystem, model: &Model) -> Vec<Sensor> {
    GAUGES
        .iter()
        .map(|name| {
            let s = (model.mechanism.sensors.iter())
                .find(|s| s.name == *name)
                .expect("gauge");
            let output = system.outputs(std::slice::from_ref(s)).remove(0);
            assert!(matches!(output, Output::Strain { .. }));
            Sensor {
                output,
                reference: 0.0,
                variance: 1e-14,
            }
        })
        .collect()
}

/// The covariances of the four-bar case: δ_E = 1e-3 Hz (Table 9.1's parameter estimation,
/// eq. 8.31), P₀ of θ = E/E_guess the square of the initial guess's relative error (0.2 in
/// θ), the start (assembled at rest, as the forward run's) known to P₀ = 1e-14 on q and 1e-10
/// on v, and a model uncertainty Q of 1e-18 and 1e-14.
fn setup() -> AmandaSetup {
    AmandaSetup {
        q_positions: 1e-18,
        q_velocities: 1e-14,
        inputs: Vec::new(),
        parameter_rates: vec![1e-3],
        p0_positions: 1e-14,
        p0_velocities: 1e-10,
        p0_parameters: vec![0.04],
        manifold: ManifoldSettings::default(),
        freeze: None,
        observe_every: None,
        strain_reference: StrainReference::Absolute,
    }
}

/// Runs the filter over the first `steps` measurement rows; returns E_C per step, and the
/// largest constraint residuals of the estimates (position, velocity).
fn estimate_coupler_modulus(steps: usize) -> (Vec<f64>, f64, f64) {
    let (pfmb, system, model) = four_bar(E_GUESS);
    let parameters = coupler_modulus(&pfmb, &system);
    let sensors = set_1(&system, &model);
    let ggl = integrator(&system, 1e-10);
    let mut filter =
        Amanda::new(ggl, Inputs::default(), parameters, sensors, &setup()).expect("filter");
    let rows = measurements();
    let (mut e, mut position, mut velocity) = (Vec::new(), 0.0_f64, 0.0_f64);
    let clock = std::time::Instant::now();
    for row in &rows[1..=steps] {
        let report = filter.step(&row[1..]).expect("step");
        assert!((report.time - row[0]).abs() < 1e-9);
        position = position.max(report.manifold.position_residual);
        velocity = velocity.max(report.manifold.velocity_residual);
        e.push(filter.parameters().0[0]);
    }
    println!(
        "{steps} steps in {:.2} s ({:.2} ms per step); E_C / E_true at steps 10, 25, 50, 100, last: {:?}",
        clock.elapsed().as_secs_f64(),
        1e3 * clock.elapsed().as_secs_f64() / steps as f64,
        [10, 25, 50, 100, steps].map(|k| e.get(k - 1).map(|x| x / E_TRUE))
    );
    (e, position, velocity)
}

/// Table 9.1, the coupler's E from sensor set 1 (one mid-span gauge per link), from the deck
/// (`SOL ESTIMATE` on the mechanism): from 25 % above the truth, on measurements of the
/// non-parametric ROMs' forward run with 1e-7 noise. Over the last 20 % of the 400-step window
/// the error stays within the thesis's worst error of its E_C rows with set 1 (|−0.07| %,
/// "E_C, input"), and every estimate lies on the constraints. (The window is the Rust filter's
/// earlier 400 steps, about 7 s in the debug profile on a loaded machine: the bound needs the
/// estimate settled, reached after some 300 steps; the Rust filter's own run is cut to the
/// 50 steps of [`the_deck_runs_the_rust_filter`], so the file's time grows by the deck's
/// overhead only.)
#[test]
fn coupler_modulus_from_sensor_set_1() {
    let DeckRun {
        e,
        position,
        velocity,
        measured,
        ..
    } = deck_estimate();
    let truth = vec![E_TRUE; e.len()];
    let err = percent_errors(e, &truth);
    println!(
        "E_C error over the last 20 %: min {:.3} %, avg {:.3} %, max {:.3} %; max |Φ| {position:.1e}, max |Φ_q v + Φ_t| {velocity:.1e}",
        err.min, err.avg, err.max
    );
    assert!(err.min.abs().max(err.max.abs()) < 0.07, "{err:?}");
    let tol = ManifoldSettings::default().tolerance;
    assert!(
        *position <= tol && *velocity <= tol,
        "{position:e} {velocity:e}"
    );
    assert_eq!(*measured, 1, "CEPS is a measured sensor");
}

/// The deck's cards (EKF QSTATE, P0STATE; AMANDA QVEL, P0VEL; EKFPAR INIT, DELTA, P0; MEAS σ)
/// set the filter the Rust API sets in [`setup`]: over the first 50 steps (the estimate still
/// moving by per cents) both give E_C within 1e-9 relative — the same arithmetic up to the
/// order of a few operations, far below the step-to-step change of about 1e-4.
#[test]
fn the_deck_runs_the_rust_filter() {
    let steps = 50;
    let (e, _, _) = estimate_coupler_modulus(steps);
    let deck = &deck_estimate().e;
    for (k, (a, b)) in e.iter().zip(deck).enumerate() {
        assert!((a - b).abs() <= 1e-9 * b, "step {}: {a} vs {b}", k + 1);
    }
}

/// Bad estimation input is refused before any computation, each error at its card and field:
/// an EKFPAR that is not BODY.PMPAR of the mechanism, a MEAS naming no MSENSOR, a MEAS on an
/// MSENSOR kind without a measurement equation (JTORQ), a second AMANDA card, an unknown input
/// with a COMP (a mechanism's input is an MFORCE's amplitude) or naming no MFORCE; and a
/// STRREF the filter does not support.
#[test]
fn bad_estimation_input_is_refused_at_its_card() {
    type Case = (&'static str, fn(String) -> String, &'static [&'static str]);
    let cases: [Case; 7] = [
        (
            "bad_parameter.dat",
            |t| t.replace("EKFPAR,1,C.E,", "EKFPAR,1,C.G,"),
            &[
                "bad_parameter.dat:30: EKFPAR 1: field 3 (NAME): C.G is not BODY.PMPAR",
                "C.E, C.RHO",
            ],
        ),
        (
            "bad_sensor.dat",
            |t| t.replace("MEAS,2,CEPS,", "MEAS,2,CSTRAIN,"),
            &["bad_sensor.dat:33: MEAS 2: field 3 (SENSOR): CSTRAIN is not an MSENSOR"],
        ),
        (
            "bad_kind.dat",
            |t| {
                t.replace("MEAS,2,OCEPS,", "MEAS,2,TORQUE,")
                    .replace("ENDDATA", "MSENSOR,5,TORQUE,JTORQ,,1\nENDDATA")
            },
            &["bad_kind.dat:34: MEAS 2: field 3 (SENSOR): TORQUE is a JTORQ MSENSOR"],
        ),
        (
            "two_amanda.dat",
            |t| t.replace("AMANDA,1,,,,", "AMANDA,1\nAMANDA,1,,,,"),
            &["two_amanda.dat:30: AMANDA 1: a second AMANDA card for EKF 1"],
        ),
        (
            "input_component.dat",
            |t| t.replace("EKFPAR,1,", "EKFINP,1,12,3,80.,5.\nEKFPAR,1,"),
            &["input_component.dat:30: EKFINP 1: field 4 (COMP): found 3"],
        ),
        (
            "input_not_a_force.dat",
            |t| t.replace("EKFPAR,1,", "EKFINP,1,12,,80.,5.\nEKFPAR,1,"),
            &[
                "input_not_a_force.dat:30: EKFINP 1: field 3 (GRID): 12 is not an MFORCE or MMOMENT id",
            ],
        ),
        (
            "strref.dat",
            |t| t.replace("ESTIM = 1", "ESTIM = 1\nSTRREF = INITIAL"),
            &[
                "strref.dat:",
                "STRREF: the filter's gauges read absolute strains (NONE)",
            ],
        ),
    ];
    for (name, edit, expected) in cases {
        let path = estimation_deck(name, 400, edit);
        let (result, _, dir) = run_deck_file(&path);
        let message = result.expect_err(name).to_string();
        for text in expected {
            assert!(message.contains(text), "{name}: {message}");
        }
        assert!(
            !dir.path().join("out.h5").exists(),
            "{name}: nothing written"
        );
    }
}

/// The setups thesis §9.3.1 says cannot work are refused before the filter runs, at the EKF
/// card: accelerations only (here AX and AY), and strains only on the undriven four-bar (its
/// JDRIVE removed: one rigid degree of freedom that no measurement fixes). With FORCE = YES
/// on the EKF card the acceleration-only setup runs (5 steps; the data are the strain columns
/// of the reference file, the run only shows that the refusal was overridden) and the output
/// records it.
#[test]
fn setups_without_static_or_absolute_information_are_refused_unless_forced() {
    let accelerations = |t: String| {
        t.replace("MEAS,2,ICEPS,2,1.e-7", "MEAS,2,AX,2,1.e-3")
            .replace("MEAS,2,CEPS,3,1.e-7", "MEAS,2,AY,3,1.e-3")
            .replace("MEAS,2,OCEPS,4,1.e-7\n", "")
    };
    let undriven = |t: String| t.replace("JDRIVE,1,1,7,1.\n", "");
    for (name, edit, expected) in [
        (
            "accelerations_only.dat",
            &accelerations as &dyn Fn(String) -> String,
            "accelerations_only.dat:28: EKF 1: every measurement is an acceleration",
        ),
        (
            "undriven.dat",
            &undriven,
            "undriven.dat:28: EKF 1: the joints, drives and springs leave 1 rigid degree(s) of freedom free and no POS is measured",
        ),
    ] {
        let path = estimation_deck(name, 400, edit);
        let message = run_deck_file(&path).0.expect_err(name).to_string();
        assert!(message.contains(expected), "{name}: {message}");
        assert!(message.contains("FORCE = YES"), "{message}");
    }
    let path = estimation_deck("forced.dat", 5, |t| {
        accelerations(t).replace("EKF,1,1.e-18,1.e-14", "EKF,1,1.e-18,1.e-14,YES")
    });
    let (result, _, dir) = run_deck_file(&path);
    let summary = result.unwrap_or_else(|e| panic!("{e}"));
    assert!(
        summary.warnings.iter().any(|w| w.contains("FORCE = YES")),
        "{:?}",
        summary.warnings
    );
    let file = hdf5_metno::File::open(dir.path().join("out.h5")).expect("open");
    let g = file.group("results/1/estimate").expect("estimate group");
    let forced = g.attr("forced").and_then(|a| a.read_scalar::<i64>());
    assert_eq!(forced.expect("forced"), 1);
}

/// FREEZE on the AMANDA card (§9.3.2): a parameter's update is frozen at the steps whose
/// sensitivity (the largest change of a reading, in noise σ, per 100 % change of the
/// parameter, along the prior trajectory) is below the threshold. With the threshold at the
/// unfrozen run's sensitivity at step 15, over 30 steps: the frozen steps are exactly those
/// whose own sensitivity is below it, C.E does not move at them and moves at the others, and
/// both kinds occur.
#[test]
fn parameter_updates_freeze_below_the_sensitivity_threshold() {
    let threshold = deck_estimate().sensitivity[14];
    let path = estimation_deck("freeze.dat", 30, |t| {
        t.replace("AMANDA,1,,,,", &format!("AMANDA,1,,,{threshold:e},"))
    });
    let (result, _, dir) = run_deck_file(&path);
    result.unwrap_or_else(|e| panic!("{e}"));
    let file = hdf5_metno::File::open(dir.path().join("out.h5")).expect("open");
    let g = file.group("results/1/estimate").expect("estimate group");
    let e = read_dataset::<f64>(&g.group("params").expect("params"), "C.E");
    let sensitivity = read_dataset::<f64>(&g, "sensitivity");
    let frozen: Vec<bool> = sensitivity.iter().map(|s| *s < threshold).collect();
    println!("threshold {threshold:e}; sensitivity {sensitivity:?}");
    let count = frozen.iter().filter(|f| **f).count();
    assert!(
        count > 0 && count < frozen.len(),
        "{count} of {} frozen",
        frozen.len()
    );
    let attr = g.attr("frozen_steps").and_then(|a| a.read_scalar::<i64>());
    assert_eq!(attr.expect("frozen_steps"), count as i64);
    let before = std::iter::once(E_GUESS).chain(e.iter().copied());
    for (k, ((now, before), frozen)) in e.iter().zip(before).zip(&frozen).enumerate() {
        assert_eq!(*now == before, *frozen, "step {}: {before} → {now}", k + 1);
    }
}

/// The AMANDA step from a configuration pushed off the constraints (every coordinate moved by
/// 1e-4 relative, every velocity by 1e-3) comes back to |Φ| ≤ tol and |Φ_q v + Φ_t| ≤ tol,
/// and moves q no farther than the push (it is the closest point on the manifold, and the
/// prior it starts from lies there).
#[test]
fn manifold_step_returns_to_the_constraints() {
    let (_, system, _) = four_bar(E_TRUE);
    let mut ggl = integrator(&system, 1e-10);
    ggl.run(20, |_, _| {}).expect("run");
    let settings = ManifoldSettings::default();
    let manifold = Manifold {
        layout: &ggl.system.layout,
        constraints: &ggl.equations.constraints,
        time: ggl.time,
        settings,
    };
    let prior = ggl.q.clone();
    let mut q: Vec<f64> = (prior.iter().enumerate())
        .map(|(i, x)| x + 1e-4 * (1.0 + x.abs()) * if i % 3 == 0 { 1.0 } else { -0.5 })
        .collect();
    let push = q
        .iter()
        .zip(&prior)
        .map(|(a, b)| (a - b) * (a - b))
        .sum::<f64>()
        .sqrt();
    let mut v: Vec<f64> = (ggl.v.iter().enumerate())
        .map(|(i, x)| x + 1e-3 * if i % 2 == 0 { 1.0 } else { -1.0 })
        .collect();
    let report = manifold.step(&prior, &mut q, &mut v).expect("AMANDA step");
    println!("{report:?}");
    assert!(report.position_residual <= settings.tolerance);
    assert!(report.velocity_residual <= settings.tolerance);
    assert!(report.distance <= push, "{} > {push}", report.distance);
}

/// The rows of J_m (eq. 9.19) of the deck's position (CX, CY), acceleration (AX, AY) and
/// strain gauges at a moving state of the four-bar against central differences of h over q
/// and v (steps 1e-6 (1 + |x|)): the position rows are the marker's exact Jacobian, the strain
/// rows C_ε, the acceleration rows differences themselves (here of a 10 times larger step). A
/// bound of 1e-5 on the largest entry's relative error leaves the differences' O(ε²) and
/// round-off room and fails on a row on the wrong coordinates or with the wrong sign.
#[test]
fn measurement_rows_match_central_differences() {
    let (_, system, model) = four_bar(E_TRUE);
    let mut ggl = integrator(&system, 1e-10);
    ggl.run(30, |_, _| {}).expect("run");
    let previous = ggl.v.clone();
    ggl.run(1, |_, _| {}).expect("run");
    let n = ggl.system.size();
    let names = ["CX", "CY", "AX", "AY", "ICEPS", "CEPS", "OCEPS"];
    let sensors: Vec<Sensor> = names
        .iter()
        .map(|name| {
            let s = (model.mechanism.sensors.iter())
                .find(|s| s.name == *name)
                .expect("sensor");
            Sensor {
                output: system.outputs(std::slice::from_ref(s)).remove(0),
                reference: 0.0,
                variance: 1.0,
            }
        })
        .collect();
    let k = sensors.len();
    let mut x: Vec<f64> = ggl.q.iter().chain(&ggl.v).copied().collect();
    x.push(1.0);
    let (mut y, mut jm) = (vec![0.0; k], Mat::zeros(k, 2 * n + 1));
    measure(&sensors, &ggl, &x, &previous, &mut y, &mut jm);
    let mut numeric = Mat::zeros(k, 2 * n + 1);
    let (mut plus, mut minus, mut scratch) = (vec![0.0; k], vec![0.0; k], Mat::zeros(k, 2 * n + 1));
    for c in 0..2 * n {
        let eps = 1e-6 * (1.0 + x[c].abs());
        let mut xs = x.clone();
        xs[c] = x[c] + eps;
        measure(&sensors, &ggl, &xs, &previous, &mut plus, &mut scratch);
        xs[c] = x[c] - eps;
        measure(&sensors, &ggl, &xs, &previous, &mut minus, &mut scratch);
        for i in 0..k {
            numeric[(i, c)] = (plus[i] - minus[i]) / (2.0 * eps);
        }
    }
    for (i, name) in names.iter().enumerate() {
        let e = relative_error(&jm, &numeric, i..i + 1, 0..2 * n + 1);
        println!("{name}: relative error {e:.2e}");
        assert!(e < 1e-5, "{name}: {e:e}");
    }
}

/// The input case's columns (time, the three noisy gauges, …, the true force) of
/// reference/amanda_fourbar_input_set1.csv: (time, force) per row.
fn true_input() -> Vec<(f64, f64)> {
    let text = std::fs::read_to_string(root().join("reference/amanda_fourbar_input_set1.csv"))
        .expect("measurements");
    text.lines()
        .filter(|l| !l.starts_with('#'))
        .map(|l| {
            let v: Vec<f64> = l.split(',').map(|x| x.parse().expect("number")).collect();
            (v[0], v[7])
        })
        .collect()
}

/// What the deck fourbar_estimate_ec_input.dat wrote over `steps` steps: C.E, its σ, the
/// input MFORCE7, and the run's steps per second.
fn input_estimate(steps: usize) -> (Vec<f64>, Vec<f64>, Vec<f64>, f64) {
    let path = deck_beside_artifacts(
        "fourbar_estimate_ec_input.dat",
        &format!("estimate_input_{steps}.dat"),
        steps,
        |t| t.replace("AMANDA,1,,,,1.e-14,1.e-10", "AMANDA,1,,,,1.e-14,1.e-10,30"),
    );
    let (result, _, dir) = run_deck_file(&path);
    let summary = result.unwrap_or_else(|e| panic!("{e}"));
    println!("{summary:?}");
    let file = hdf5_metno::File::open(dir.path().join("out.h5")).expect("open");
    let g = file.group("results/1/estimate").expect("estimate group");
    let read = |group: &str, name: &str| read_dataset::<f64>(&g.group(group).expect(group), name);
    let speed = g
        .attr("steps_per_second")
        .and_then(|a| a.read_scalar::<f64>());
    // OBSEVERY = 30: the first window (45 steps) along the run sees both unknowns
    let along = g.group("observability").expect("observability");
    for name in ["C.E", "MFORCE7"] {
        let identifiability = read_dataset::<f64>(&along, name);
        assert!(
            !identifiability.is_empty() && identifiability.iter().all(|d| *d > 0.1),
            "{name}: {identifiability:?}"
        );
    }
    (
        read("params", "C.E"),
        read("params_sigma", "C.E"),
        read("inputs", "MFORCE7"),
        speed.expect("steps_per_second"),
    )
}

/// The errors of the input case over the last 20 % of its window: E_C's (per cent) and the
/// input's RMS error over the true input's RMS.
fn input_case_errors(e: &[f64], u: &[f64]) -> (PercentErrors, f64) {
    let truth = true_input();
    let from = tail_start(u.len());
    let (mut error, mut size) = (0.0, 0.0);
    for (k, estimate) in u.iter().enumerate().skip(from) {
        let (time, force) = truth[k + 1];
        assert!((time - (k + 1) as f64 * 1e-3).abs() < 1e-12);
        error += (estimate - force).powi(2);
        size += force * force;
    }
    (
        percent_errors(e, &vec![E_TRUE; e.len()]),
        (error / size).sqrt(),
    )
}

/// Table 9.1's "E_C, input" case with sensor set 1, from the deck: C.E from 25 % above the
/// truth and the amplitude of MFORCE 7 (15 Hz, 10 N on OC; tools/amanda/fourbar_measurements.py
/// --input) from zero, over the first 80 steps (1.6–2.3 s in the debug profile on the shared
/// machine; the whole second is [`coupler_modulus_and_input_benchmark`], which holds Table
/// 9.1's bound). Checked over the last 20 % of the window:
/// - the input's RMS error is below 2π f Δt = 9.4 % of its RMS, the error of the random
///   walk's own prediction u_k⁻ = u_{k−1}⁺ of a 15 Hz sine at Δt = 1 ms: an estimate no
///   better than that has learnt nothing from the correction (a missing or wrong input column
///   of the Jacobian fails it);
/// - E_C lies within 3σ of the truth at every step (a consistent filter's error; the
///   parameter still converging, the thesis's settled bound applies later).
#[test]
fn coupler_modulus_and_input_from_sensor_set_1() {
    let (e, sigma, u, _) = input_estimate(80);
    let (e_error, u_error) = input_case_errors(&e, &u);
    println!(
        "E_C error over the last 20 %: {e_error:?}; input RMS error / input RMS {u_error:.4}; E_C/E_true at the end {}",
        e[e.len() - 1] / E_TRUE
    );
    let lag = 2.0 * std::f64::consts::PI * 15.0 * 1e-3;
    assert!(u_error < lag, "{u_error} ≥ {lag}");
    let from = tail_start(e.len());
    for (k, (value, s)) in e.iter().zip(&sigma).enumerate().skip(from) {
        assert!(
            (value - E_TRUE).abs() < 3.0 * s,
            "step {}: {value} ± {s}",
            k + 1
        );
    }
}

/// The observability along the run (AMANDA OBSEVERY, §9.3.1) shows an unknown the readings
/// cannot see: the input case with MFORCE 7 moved to marker 31, OC's grounded joint master,
/// whose revolute joint takes any force there (its unit generalized force lies in the range of
/// Φ_qᵀ, so the projected equations never feel it). Over 50 steps with a window every 20
/// steps (one window of 45 steps finishes), the input's identifiability is zero at the start
/// and in the window along the run, where C.E's is not, and the console says so; the input's
/// estimate stays at its initial zero. (The data carry the force at marker 32, which this
/// filter cannot explain, so its C.E goes astray: not checked. With the force at marker 32
/// the same windows see both unknowns, [`input_estimate`].)
#[test]
fn observability_along_the_run_shows_an_unobservable_input() {
    let path = deck_beside_artifacts(
        "fourbar_estimate_ec_input.dat",
        "unobservable_input.dat",
        50,
        |t| {
            t.replace("MFORCE,7,32,", "MFORCE,7,31,")
                .replace("AMANDA,1,,,,1.e-14,1.e-10", "AMANDA,1,,,,1.e-14,1.e-10,20")
        },
    );
    let (result, _, dir) = run_deck_file(&path);
    let summary = result.unwrap_or_else(|e| panic!("{e}"));
    let file = hdf5_metno::File::open(dir.path().join("out.h5")).expect("open");
    let g = file.group("results/1/estimate").expect("estimate group");
    let start = g
        .attr("input_identifiability")
        .and_then(|a| a.read_raw::<f64>());
    assert_eq!(start.expect("input_identifiability"), vec![0.0]);
    let along = g.group("observability").expect("observability");
    let time = read_dataset::<f64>(&along, "time");
    let input = read_dataset::<f64>(&along, "MFORCE7");
    let modulus = read_dataset::<f64>(&along, "C.E");
    println!("windows from {time:?}: MFORCE7 {input:?}, C.E {modulus:?}");
    assert_eq!(time, vec![1e-3]);
    assert_eq!(input, vec![0.0]);
    assert!(modulus[0] > 0.1, "{modulus:?}");
    let u = read_dataset::<f64>(&g.group("inputs").expect("inputs"), "MFORCE7");
    assert!(u.iter().all(|x| x.abs() < 1e-6), "{u:?}");
    let console = summary.subcases[0].result.render(1).join("\n");
    println!("{console}");
    assert!(
        console.contains("least identifiability: C.E") && console.contains("MFORCE7 0.00E+00"),
        "{console}"
    );
}

/// The adaptive strain reference's rows (eq. 9.25): −C_ε ∂q_f,ref/∂θ from the equilibrium's
/// tangent against central differences of the reference strains themselves (the static
/// equilibrium at t = 0 solved at θ = 1 ± 1e-6, Newton to 1e-12 relative), for the three
/// gauges at C.E = E_guess. The differences' error is about 1e-12 / 1e-6 = 1e-6 of the
/// reference (round-off of the solves) plus O(ε²): a bound of 1e-4 on the largest entry's
/// relative error fails on a missing force rate (gravity's through the mass invariants or
/// K's) at O(1).
#[test]
fn adaptive_reference_rows_match_central_differences() {
    let (pfmb, system, model) = four_bar(E_GUESS);
    let parameters = coupler_modulus(&pfmb, &system);
    let mut ggl = integrator(&system, 1e-10);
    let n = ggl.system.size();
    let mut sensors = set_1(&system, &model);
    let inputs = Inputs::default();
    let reference_at = |ggl: &mut Ggl, theta: f64, sensors: &mut [Sensor]| {
        parameters.apply(&[theta], &mut ggl.system).expect("apply");
        let r = Reference::new(
            StrainReference::Adaptive,
            ggl,
            &inputs,
            &[],
            &parameters,
            &[theta],
        )
        .expect("equilibrium")
        .expect("a reference");
        r.apply(sensors, ggl);
        r
    };
    let eps = 1e-6;
    let (mut plus, mut minus) = (sensors.clone(), sensors.clone());
    reference_at(&mut ggl, 1.0 + eps, &mut plus);
    reference_at(&mut ggl, 1.0 - eps, &mut minus);
    let r = reference_at(&mut ggl, 1.0, &mut sensors);
    let mut jm = Mat::zeros(sensors.len(), 2 * n + 1);
    r.add_rows(&sensors, &ggl, &mut jm, 2 * n);
    let analytic = Mat::from_fn(sensors.len(), 1, |k, _| jm[(k, 2 * n)]);
    let numeric = Mat::from_fn(sensors.len(), 1, |k, _| {
        -(plus[k].reference - minus[k].reference) / (2.0 * eps)
    });
    let e = relative_error(&analytic, &numeric, 0..sensors.len(), 0..1);
    println!(
        "references {:?}; rows {:?}; relative error {e:.2e}",
        sensors.iter().map(|s| s.reference).collect::<Vec<_>>(),
        (0..sensors.len())
            .map(|k| analytic[(k, 0)])
            .collect::<Vec<_>>()
    );
    assert!(e < 1e-4, "{e:e}");
}

/// Strains read from the reference configuration (reference/amanda_fourbar_set1_relative.csv:
/// the forward run's gauges minus their values at its static equilibrium at t = 0, eq. 9.24)
/// over the first 40 steps of the E_C case. With STRREF = ADAPTIVE (eq. 9.25: the reference
/// solved at the current estimate) C.E lies within 3σ of the truth over the last 20 %, as a
/// consistent filter's; with STRREF = STATIC (the reference at the initial guess, 25 % too
/// stiff) the offset is wrong by about a fifth of the gauges' static strains — several noise σ
/// on CEPS — and C.E is pulled away from the truth by more than 3σ, the bias the thesis's
/// adaptive reference removes (the whole second: docs/estimation.md).
#[test]
fn adaptive_strain_reference_removes_the_fixed_reference_bias() {
    let run = |reference: &str| {
        let path = estimation_deck(&format!("strref_{reference}.dat"), 40, |t| {
            t.replace(
                "amanda_fourbar_set1.csv",
                "amanda_fourbar_set1_relative.csv",
            )
            .replace("ESTIM = 1", &format!("ESTIM = 1\nSTRREF = {reference}"))
        });
        let (result, _, dir) = run_deck_file(&path);
        result.unwrap_or_else(|e| panic!("{e}"));
        let file = hdf5_metno::File::open(dir.path().join("out.h5")).expect("open");
        let g = file.group("results/1/estimate").expect("estimate group");
        let read = |group: &str| read_dataset::<f64>(&g.group(group).expect(group), "C.E");
        (read("params"), read("params_sigma"))
    };
    let outside = |(e, sigma): &(Vec<f64>, Vec<f64>)| {
        (tail_start(e.len())..e.len())
            .map(|k| (e[k] - E_TRUE).abs() / sigma[k])
            .fold(0.0, f64::max)
    };
    let (adaptive, fixed) = (run("ADAPTIVE"), run("STATIC"));
    let (a, f) = (outside(&adaptive), outside(&fixed));
    println!(
        "E_C/E_true at step 40: adaptive {}, fixed {}; largest |error|/σ over the last 20 %: {a:.2}, {f:.2}",
        adaptive.0[39] / E_TRUE,
        fixed.0[39] / E_TRUE
    );
    assert!(a < 3.0, "adaptive: {a}");
    assert!(f > 3.0, "fixed: {f}");
}

/// The input case over the whole measured second (1000 steps), on demand with the
/// benchmarks: Table 9.1's bound of its "E_C, input" row with set 1 (the row's largest
/// |error| over the last 20 %, 0.07 % as printed; measured 0.071 %, so this check fails by
/// 0.001 %: docs/estimation.md reports the distance), the input's error as in
/// [`coupler_modulus_and_input_from_sensor_set_1`], and the time per step.
#[test]
#[ignore]
fn coupler_modulus_and_input_benchmark() {
    let (e, _, u, speed) = input_estimate(1000);
    let (e_error, u_error) = input_case_errors(&e, &u);
    println!(
        "1000 steps, {:.2} ms per step: E_C error over the last 20 %: min {:.3} %, avg {:.3} %, max {:.3} %; input RMS error / input RMS {u_error:.4}",
        1e3 / speed,
        e_error.min,
        e_error.avg,
        e_error.max
    );
    assert!(
        e_error.min.abs().max(e_error.max.abs()) <= 0.07,
        "{e_error:?}"
    );
    assert!(u_error < 2.0 * std::f64::consts::PI * 15.0 * 1e-3);
}

/// The benchmark of the four-bar case over the whole measured second (1000 steps at
/// Δt = 1 ms), on demand: `cargo test --release --test amanda_fourbar -- --ignored
/// --nocapture`. Prints the time per step against the error of E_C over the last 20 %
/// (docs/estimation.md, "Mechanisms (AMANDA-EKF)").
#[test]
#[ignore]
fn coupler_modulus_benchmark() {
    let (e, _, _) = estimate_coupler_modulus(1000);
    let err = percent_errors(&e, &vec![E_TRUE; e.len()]);
    println!(
        "1000 steps: E_C error over the last 20 %: min {:.3} %, avg {:.3} %, max {:.3} %",
        err.min, err.avg, err.max
    );
}

/// fourbar_steel.dat beside the artifacts as `name`, cut to `steps` steps and, unless `cards`
/// is empty, with C.E taken out of its PVAL and `cards` added (the PTABLE of C.E and its
/// table), run by SOL FMB: CEPS per row (t = 0 included).
fn forward_with_coupler_table(name: &str, steps: usize, cards: &str) -> Vec<f64> {
    let mut text = std::fs::read_to_string(artifacts().join("fourbar_steel.dat"))
        .expect("deck")
        .replace("TSTEP,1,1000,", &format!("TSTEP,1,{steps},"));
    if !cards.is_empty() {
        text = text.replace(
            "PVAL,1,IC.E,201.99E9,IC.RHO,7990.,C.E,201.99E9,C.RHO\n,7990.,OC.E,201.99E9,OC.RHO,7990.",
            "PVAL,1,IC.E,201.99E9,IC.RHO,7990.,C.RHO,7990.,OC.E\n,201.99E9,OC.RHO,7990.",
        )
        .replace("ENDDATA", &format!("{cards}ENDDATA"));
    }
    let path = artifacts().join(name);
    std::fs::write(&path, text).expect("write");
    let (result, _, dir) = run_deck_file(&path);
    result.unwrap_or_else(|e| panic!("{e}"));
    let file = hdf5_metno::File::open(dir.path().join("out.h5")).expect("open");
    read_dataset::<f64>(&file.group("results/1/fmb").expect("fmb"), "sensors/CEPS")
}

/// A `BODY.PMPAR` that follows a table of time in SOL FMB (PTABLE, the degrading-E_C case's
/// forward model): over 60 steps of the four-bar,
/// - a table constant at E gives the run of PVAL C.E = E to round-off (1e-12 of the largest
///   strain: the schedule's data are the build's, re-evaluated each step);
/// - a table jumping from E to 0.8 E at t = 30.5 ms gives the constant run's gauge readings
///   exactly up to step 30 (the step's data are taken at its end time) and differs after it by
///   more than 1 % of the largest strain (the coupler gauge reads about 1/E: a 20 % softer
///   link reads 25 % more);
/// - a PTABLE naming no body's parameter is refused at its card.
#[test]
fn coupler_modulus_follows_a_table_of_time() {
    let steps = 60;
    let e = "201.99E9";
    let constant = forward_with_coupler_table("pval_ce.dat", steps, "");
    let tabulated = forward_with_coupler_table(
        "ptable_ce.dat",
        steps,
        &format!("PTABLE,1,C.E,9\nTABLED1,9\n,0.,{e},1.,{e},ENDT\n"),
    );
    let largest = constant.iter().fold(0.0_f64, |a, x| a.max(x.abs()));
    let worst = (constant.iter().zip(&tabulated)).fold(0.0_f64, |a, (x, y)| a.max((x - y).abs()));
    assert!(worst <= 1e-12 * largest, "{worst:e} of {largest:e}");
    let jump = forward_with_coupler_table(
        "ptable_jump.dat",
        steps,
        &format!(
            "PTABLE,1,C.E,9\nTABLED1,9\n,0.,{e},0.0305,{e},0.0305,161.592E9,1.,161.592E9\n,ENDT\n"
        ),
    );
    let k = 30;
    assert!(
        (0..=k).all(|i| (jump[i] - constant[i]).abs() <= 1e-12 * largest),
        "before the jump"
    );
    let after = (k + 1..=steps).fold(0.0_f64, |a, i| a.max((jump[i] - constant[i]).abs()));
    println!("after the jump: largest change of CEPS {after:.3e} (largest reading {largest:.3e})");
    assert!(after > 0.01 * largest);
    let path = artifacts().join("ptable_bad.dat");
    let text = std::fs::read_to_string(artifacts().join("ptable_ce.dat"))
        .expect("deck")
        .replace("PTABLE,1,C.E,9", "PTABLE,1,C.G,9");
    std::fs::write(&path, text).expect("write");
    let message = run_deck_file(&path).0.expect_err("refused").to_string();
    assert!(
        message.contains("ptable_bad.dat")
            && message.contains("PTABLE 1")
            && message.contains("C.G"),
        "{message}"
    );
}

/// The degrading case's truth per row of reference/amanda_fourbar_degrading.csv: (time, force,
/// E_C(t)).
fn degrading_truth() -> Vec<(f64, f64, f64)> {
    let text = std::fs::read_to_string(root().join("reference/amanda_fourbar_degrading.csv"))
        .expect("measurements");
    text.lines()
        .filter(|l| !l.starts_with('#'))
        .map(|l| {
            let v: Vec<f64> = l.split(',').map(|x| x.parse().expect("number")).collect();
            (v[0], v[11], v[12])
        })
        .collect()
}

/// What an estimation deck wrote: the estimate group's parameters and inputs (name, series),
/// its steps per second, and the output file's directory (kept alive) for the other datasets.
struct EstimateRun {
    params: Vec<(String, Vec<f64>)>,
    inputs: Vec<(String, Vec<f64>)>,
    speed: f64,
    dir: tempfile::TempDir,
}

/// What the deck `deck` (an estimation deck of decks/fourbar/fmb) wrote over `steps` steps.
fn run_estimation_deck(deck: &str, steps: usize) -> EstimateRun {
    estimation_run(&deck_beside_artifacts(
        deck,
        &format!("run_{steps}_{deck}"),
        steps,
        |t| t,
    ))
}

/// What the estimation deck at `path` wrote ([`EstimateRun`]).
fn estimation_run(path: &Path) -> EstimateRun {
    let (result, _, dir) = run_deck_file(path);
    let summary = result.unwrap_or_else(|e| panic!("{e}"));
    println!("{summary:?}");
    let file = hdf5_metno::File::open(dir.path().join("out.h5")).expect("open");
    let g = file.group("results/1/estimate").expect("estimate group");
    let series = |group: &str| -> Vec<(String, Vec<f64>)> {
        let Ok(g) = g.group(group) else {
            return Vec::new();
        };
        let mut names = g.member_names().expect("names");
        names.sort();
        names
            .into_iter()
            .map(|n| {
                let values = read_dataset::<f64>(&g, &n);
                (n, values)
            })
            .collect()
    };
    let speed = g
        .attr("steps_per_second")
        .and_then(|a| a.read_scalar::<f64>())
        .expect("steps_per_second");
    EstimateRun {
        params: series("params"),
        inputs: series("inputs"),
        speed,
        dir,
    }
}

/// E_C's error (per cent of the truth E_C(t)) per step and the input's RMS error over its RMS
/// over the last 20 % of a degrading-case run.
fn degrading_errors(run: &EstimateRun) -> (Vec<f64>, f64) {
    let truth = degrading_truth();
    let e = &run.params[0].1;
    let u = &run.inputs[0].1;
    let errors: Vec<f64> = (e.iter().enumerate())
        .map(|(k, value)| {
            let (time, _, modulus) = truth[k + 1];
            assert!((time - (k + 1) as f64 * 1e-3).abs() < 1e-12);
            100.0 * (value - modulus) / modulus
        })
        .collect();
    let from = tail_start(u.len());
    let (mut error, mut size) = (0.0, 0.0);
    for (k, estimate) in u.iter().enumerate().skip(from) {
        let force = truth[k + 1].1;
        error += (estimate - force).powi(2);
        size += force * force;
    }
    (errors, (error / size).sqrt())
}

/// Table 9.1's "degrading E_C, input" case with sensor set 1 (thesis §9.4.1.4, Fig. 9.7), from
/// decks/fourbar/fmb/fourbar_estimate_degrading_set1.dat: the data's E_C falls by 10 %/s
/// (tools/amanda/fourbar_measurements.py --degrading, a PTABLE in the forward run), the filter
/// starts at the true initial E_C with δ_E = 1 Hz and learns the 15 Hz, 10 N input on OC from
/// zero. Over the first 80 steps (the 2 s budget of the debug profile):
/// - E_C's error stays below 2 % from step 10 on: the thesis's "errors always below 2 %" for
///   set 1 (Fig. 9.7, text of §9.4.1.4). The first steps are left out: there the input's
///   random walk still starts from zero and C.E (P₀ = (0.2 E)²) absorbs the unexplained force
///   (4.7 % at step 3), a transient the figure's one-second scale does not resolve;
/// - the input's RMS error over the last 20 % is below 2π f Δt (as in
///   [`coupler_modulus_and_input_from_sensor_set_1`]): the input is learnt.
///
/// The window is too short to show the tracking itself (the truth falls by 0.8 % in 80 ms,
/// inside the bound, so an estimate that stayed at E(0) would pass the first check); the
/// tracking over the whole second, against Table 9.1's errors, is the ignored
/// [`table_9_1_benchmark`] (docs/estimation.md).
#[test]
fn degrading_coupler_modulus_and_input_from_sensor_set_1() {
    let run = run_estimation_deck("fourbar_estimate_degrading_set1.dat", 80);
    let (errors, u_error) = degrading_errors(&run);
    let worst = errors[9..].iter().fold(0.0_f64, |a, e| a.max(e.abs()));
    println!("E_C error from step 10: largest {worst:.3} %; input RMS error / RMS {u_error:.4}");
    assert!(worst < 2.0, "{worst} %");
    assert!(
        u_error < 2.0 * std::f64::consts::PI * 15.0 * 1e-3,
        "{u_error}"
    );
}

/// Table 9.1's first case (the three moduli, each from 25 % above the truth) from sensor set
/// `set` (deck fourbar_estimate_e3_set<set>.dat) over 30 steps, with its AMANDA RANK cut to
/// the same 30 steps (the five gauges of both sets are candidates in both decks), run once:
/// the run and its ranking (unknowns, the measured set's log det and predicted σ).
fn three_moduli(set: usize) -> &'static ThreeModuli {
    static RUNS: [OnceLock<ThreeModuli>; 2] = [OnceLock::new(), OnceLock::new()];
    RUNS[set - 1].get_or_init(|| {
        let steps = 30;
        let deck = format!("fourbar_estimate_e3_set{set}.dat");
        let path = deck_beside_artifacts(&deck, &format!("three_moduli_{set}.dat"), steps, |t| {
            t.replace(
                "AMANDA,1,,,,1.e-14,1.e-10,,45",
                "AMANDA,1,,,,1.e-14,1.e-10,,30",
            )
        });
        let run = estimation_run(&path);
        let file = hdf5_metno::File::open(run.dir.path().join("out.h5")).expect("open");
        let g = file.group("results/1/estimate/ranking").expect("ranking");
        let attr = |name: &str| g.attr(name).expect(name);
        let unknowns: Vec<String> = attr("unknowns")
            .read_raw::<hdf5_metno::types::VarLenUnicode>()
            .expect("unknowns")
            .iter()
            .map(|s| s.to_string())
            .collect();
        let log_det = attr("measured_log_det")
            .read_scalar::<f64>()
            .expect("log det");
        let sigma = attr("measured_sigma").read_raw::<f64>().expect("sigma");
        ThreeModuli {
            run,
            unknowns,
            log_det,
            sigma,
        }
    })
}

/// A [`three_moduli`] run and its ranking's prediction for the measured set.
struct ThreeModuli {
    run: EstimateRun,
    /// The unknowns, log det of their predicted covariance and their predicted σ.
    unknowns: Vec<String>,
    log_det: f64,
    sigma: Vec<f64>,
}

/// |estimate − truth| / truth of `name` at the end of `run`.
fn final_error(run: &EstimateRun, name: &str) -> f64 {
    let (_, series) = (run.params.iter())
        .find(|(n, _)| n == name)
        .expect("parameter");
    (series[series.len() - 1] - E_TRUE).abs() / E_TRUE
}

/// The three moduli from sensor sets 1 and 2 ([`three_moduli`]): every estimate at the end of
/// the 30 steps lies within 3 σ of the truth, σ the ranking's prediction for the measured set
/// (the covariance of the linearized problem over the same window, the filter's own P₀ as
/// prior): the prediction is a consistent account of what each set achieves. Table 9.1's
/// settled errors need the whole second: [`table_9_1_benchmark`].
#[test]
fn three_moduli_from_sensor_sets_1_and_2() {
    for set in [1, 2] {
        let ThreeModuli {
            run,
            unknowns,
            sigma,
            ..
        } = three_moduli(set);
        for (name, s) in unknowns.iter().zip(sigma) {
            let e = final_error(run, name);
            println!(
                "set {set}: {name} error {:.3} %, predicted σ {:.3} %",
                100.0 * e,
                100.0 * s
            );
            assert!(e < 3.0 * s, "set {set}: {name}: {e} vs σ {s}");
        }
    }
}

/// The sensor ranking (AMANDA RANK, beyond the thesis) predicts which of the four-bar's two
/// sensor sets estimates the moduli better ([`three_moduli`]):
/// - set 1 (a gauge on each link) has the smaller log det of the unknowns' predicted
///   covariance (the ranking's criterion) than set 2 (three gauges on IC);
/// - for every modulus whose predicted σ differs between the sets by more than a factor of
///   two (C.E and OC.E: set 2 sees C and OC only through IC's deformation; measured: about
///   ten times), the set with the smaller predicted σ has the smaller error at the end of the
///   window — a factor that one noisy estimate cannot swap.
#[test]
fn sensor_ranking_predicts_the_better_sensor_set() {
    let (one, two) = (three_moduli(1), three_moduli(2));
    let (unknowns, det1, det2) = (&one.unknowns, one.log_det, two.log_det);
    let (run1, run2, sigma1, sigma2) = (&one.run, &two.run, &one.sigma, &two.sigma);
    println!("log det: set 1 {det1:.3}, set 2 {det2:.3}");
    assert!(det1 < det2);
    let mut compared = 0;
    for (j, name) in unknowns.iter().enumerate() {
        let (e1, e2) = (final_error(run1, name), final_error(run2, name));
        println!(
            "{name}: predicted σ {:.3} % / {:.3} %, error {:.3} % / {:.3} % (sets 1 / 2)",
            100.0 * sigma1[j],
            100.0 * sigma2[j],
            100.0 * e1,
            100.0 * e2
        );
        if sigma2[j] > 2.0 * sigma1[j] {
            assert!(e1 < e2, "{name}");
            compared += 1;
        } else if sigma1[j] > 2.0 * sigma2[j] {
            assert!(e2 < e1, "{name}");
            compared += 1;
        }
    }
    assert!(compared >= 2, "the sets differ on C.E and OC.E");
}

/// Table 9.1's rows the decks fourbar_estimate_e3_set{1,2}.dat and
/// fourbar_estimate_degrading_set{1,2}.dat reproduce, over the whole measured second, on
/// demand (`cargo test --release --test amanda_fourbar table_9_1 -- --ignored --nocapture`):
/// per parameter its error over the last 20 % (min / avg / max, per cent, against E_true or
/// E_C(t)), the input's RMS error over its RMS, and the time per step; docs/estimation.md
/// compares them with the thesis's.
#[test]
#[ignore]
fn table_9_1_benchmark() {
    for deck in [
        "fourbar_estimate_e3_set1.dat",
        "fourbar_estimate_e3_set2.dat",
        "fourbar_estimate_degrading_set1.dat",
        "fourbar_estimate_degrading_set2.dat",
    ] {
        let run = run_estimation_deck(deck, 1000);
        let ms = 1e3 / run.speed;
        if run.inputs.is_empty() {
            for (name, e) in &run.params {
                let err = percent_errors(e, &vec![E_TRUE; e.len()]);
                println!(
                    "{deck}: {name} error over the last 20 %: min {:.3} %, avg {:.3} %, max {:.3} %; {ms:.2} ms per step",
                    err.min, err.avg, err.max
                );
            }
        } else {
            let (errors, u_error) = degrading_errors(&run);
            let tail = &errors[tail_start(errors.len())..];
            let (min, max) = tail
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), e| {
                    (a.min(*e), b.max(*e))
                });
            let avg = tail.iter().sum::<f64>() / tail.len() as f64;
            println!(
                "{deck}: E_C error over the last 20 %: min {min:.3} %, avg {avg:.3} %, max {max:.3} %; largest from step 10 {:.3} %; input RMS error / RMS {u_error:.4}; {ms:.2} ms per step",
                errors[9..].iter().fold(0.0_f64, |a, e| a.max(e.abs()))
            );
        }
    }
}
