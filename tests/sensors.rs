//! The SENSOR measurement operator (`discretize::sensors`, thesis eq. 2.31–2.35) against the
//! analytic cantilever strip of `reference/analytic/cantilever_strain_sensor.json`: y = H u_f
//! with u_f from SOL 101.

mod common;

use std::path::PathBuf;

use paraflex::deck::Deck;
use paraflex::discretize::sensors::sensor_operator;
use paraflex::discretize::{BuildOptions, Constrained, Structure};
use paraflex::io::OutputFile;
use paraflex::model::Model;
use paraflex::sequence::{RunContext, run, selected_sensors};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// SOL 101 of the strip, then H u_f for every SENSOR: each against the beam formula with the
/// reference's tolerance (justified there: the 1D analogue of MITC4 in cylindrical bending has
/// centroid curvatures within 1e-10 of M/EI, so the bound is round-off plus element variants),
/// and each shell STRAIN row against SOL 101's own STRAIN output at the same fibre (the same
/// recovery, so 1e-12 relative: only the summation order differs).
#[test]
fn strain_and_displacement_sensors_match_the_beam_formula() {
    let reference: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(root().join("reference/analytic/cantilever_strain_sensor.json"))
            .unwrap(),
    )
    .unwrap();
    let deck_path = root().join(reference["meshes"][0]["deck"].as_str().unwrap());
    let deck = Deck::read(&deck_path).expect("deck");
    let model = Model::build(&deck).expect("model");
    let dir = tempfile::tempdir().unwrap();
    let file = OutputFile::create(dir.path().join("out.h5")).unwrap();
    let ctx = RunContext {
        deck: &deck,
        model: &model,
        output: &file,
        progress: &|_: &str, _: usize, _: usize| {},
        options: BuildOptions { parallel: false },
        engine: None,
    };
    run(&ctx).expect("SOL 101");
    let st = Structure::build(&model, &ctx.options, ctx.progress).expect("structure");
    let sub = &model.subcases[0];
    let c = Constrained::build(&model, &st, sub.spc).expect("constraints");
    let sensors = selected_sensors(&deck, &model, sub);
    let h = sensor_operator(&model, &st, &c, &sensors).expect("sensor operator");
    file.commit().unwrap();

    let out = hdf5_metno::File::open(dir.path().join("out.h5")).unwrap();
    let g = out.group("results/1/statics").unwrap();
    // no CD frames and no RBE: the basic n × 6 rows are u_g, and u_f its f-set members
    let u_g: Vec<f64> = g.dataset("displacement").unwrap().read_raw().unwrap();
    let u_f: Vec<f64> = c.sets.f.members().iter().map(|&i| u_g[i]).collect();
    let y = h.apply(&u_f);

    let labels: Vec<&str> = reference["value_labels"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_str().unwrap())
        .collect();
    assert_eq!(h.names, labels);
    let values: Vec<f64> = reference["values"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    let tol: Vec<f64> = reference["tolerance_finest"]["relative"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    let scale = reference["absolute_scale"].as_f64().unwrap();
    for (((name, got), want), tol) in labels.iter().zip(&y).zip(&values).zip(&tol) {
        let err = (got - want).abs() / if *want == 0.0 { scale } else { want.abs() };
        println!("{name}: {got:.10e} vs {want:.10e} (rel {err:.1e}, tol {tol:.1e})");
        assert!(err <= *tol, "{name}: {got:e} vs {want:e}");
    }

    // the same numbers from SOL 101's STRAIN output: εx of elements 1 and 11 (material x = G1→G2 =
    // basic x; ε_ϑ is quadratic in ϑ, so the −x gauge of ROOT_BOT reads εx as well)
    let s = g.group("strain/CQUAD4").unwrap();
    let ids: Vec<u32> = s.dataset("ids").unwrap().read_raw().unwrap();
    let top: Vec<f64> = s.dataset("top").unwrap().read_raw().unwrap();
    let bottom: Vec<f64> = s.dataset("bottom").unwrap().read_raw().unwrap();
    let at = |surface: &[f64], eid: u32| -> [f64; 3] {
        std::array::from_fn(|i| surface[3 * ids.iter().position(|&e| e == eid).unwrap() + i])
    };
    // the 45° gauge: ϑ = (1, 1)/√2 → (εx + εy + γxy)/2 (eq. 2.31)
    let e45 = at(&top, 1).iter().sum::<f64>() / 2.0;
    for (k, want) in [
        (0, at(&top, 1)[0]),
        (1, at(&bottom, 1)[0]),
        (3, e45),
        (4, at(&top, 11)[0]),
    ] {
        assert!(
            (y[k] - want).abs() <= 1e-12 * want.abs(),
            "{}: {} vs STRAIN output {want}",
            labels[k],
            y[k]
        );
    }
}
