//! Exact mass properties of the distorted conformance decks against an independent
//! implementation (`reference/conformance/<stem>.exact.json`).
//!
//! Provenance: `tools/conformance/exact_mass.py` (run with `.venv/bin/python`). It implements
//! paraflex's exact convention (see `src/model/mass.rs`) without using pyNastran's
//! `mass_properties` (which is approximate on these decks) and without sharing any algorithm with
//! the Rust code: pyNastran only reads the cards, the grid positions in basic and the CORD2x
//! axes; every element is a map from the unit square/cube (CTRIA3 as a collapsed quad, CPENTA
//! and CTETRA4 as collapsed hexas, CTETRA10 through a Duffy map) integrated with a composite
//! tensor Gauss–Legendre rule (shells 8×8 panels × 20×20 points, solids 3³ panels × 7³ points),
//! totals summed with `math.fsum`. Its convergence check (against shells 4×4 × 12×12, solids
//! 1 × 5³) changes mass, cg and inertia_cg by at most 3.3e-16 relative on these decks, and its
//! self-check reproduces closed forms (tetra, parallelepiped, triangle with linear density) and
//! an adaptive scipy integral of a warped quad's area to ≤ 1e-14.
//!
//! Tolerance 1e-10 relative (norm of each quantity): both sides are exact up to round-off
//! (~1e-15 here: the Python integration accuracy above plus the Rust Gauss rules, which are exact
//! for the polynomial integrands and converge exponentially for warped quads), so 1e-10 leaves
//! five orders of magnitude of margin. Convention errors are far larger: measured with the Python
//! script on these decks, mean instead of bilinear corner thickness changes mixed by 3.7e-7 and
//! plate_pshell by 2.2e-4, node-average lumping of quads 1.2e-6 to 7.1e-4, PCOMP SYM NSM doubled
//! 3.1e-5 to 1.1e-2, TFLAG = 1 read as absolute 9.6e-2 to 11.
//!
//! Not exercised by these decks (all CONM2 inertias are diagonal and none has CID > 0, the one
//! CORD2C CONM2 sits at θ = 0 where e_r, e_θ = i, j, and every PSHELL has MID1): the sign of
//! CONM2 products of inertia, the rotation of CONM2 inertia into basic, the cylindrical e_θ and
//! the MID2 fallback.
//!
//! Run with `--nocapture` to see the per-deck table.

use std::path::PathBuf;

use paraflex::deck::Deck;
use paraflex::model::Model;
use serde_json::Value;

/// Relative tolerance (norm-wise) for mass, cg and inertia_cg.
const TOL: f64 = 1e-10;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// Every `reference/conformance/*.exact.json`, sorted.
fn exact_references() -> Vec<PathBuf> {
    let mut out: Vec<PathBuf> = std::fs::read_dir(root().join("reference/conformance"))
        .expect("reference/conformance exists")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| {
            p.file_name()
                .and_then(|s| s.to_str())
                .is_some_and(|s| s.ends_with(".exact.json"))
        })
        .collect();
    out.sort();
    out
}

fn norm(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

fn floats(v: &Value) -> Vec<f64> {
    match v {
        Value::Array(items) => items.iter().flat_map(floats).collect(),
        other => other.as_f64().into_iter().collect(),
    }
}

#[test]
fn distorted_decks_match_independent_exact_mass() {
    let refs = exact_references();
    assert!(
        refs.len() >= 12,
        "expected the 12 *.exact.json references, found {}",
        refs.len()
    );
    let mut failures = Vec::new();
    println!(
        "{:<26} {:>10} {:>10} {:>10}",
        "deck", "mass", "cg", "inertia"
    );
    for path in refs {
        let file = path
            .file_name()
            .and_then(|s| s.to_str())
            .unwrap_or_default()
            .to_string();
        let stem = file.trim_end_matches(".exact.json");
        let r: Value =
            serde_json::from_str(&std::fs::read_to_string(&path).expect("read reference"))
                .expect("valid json");
        assert!(
            r["provenance"]
                .as_str()
                .is_some_and(|s| s.contains("exact_mass.py")),
            "{file}: provenance"
        );
        let deck_path = root().join("decks/conformance").join(format!("{stem}.bdf"));
        let deck = match Deck::read(&deck_path) {
            Ok(d) => d,
            Err(e) => {
                failures.push(format!("{stem}: deck not read:\n{e}"));
                continue;
            }
        };
        let model = match Model::build(&deck) {
            Ok(m) => m,
            Err(errors) => {
                let text: Vec<String> = errors.iter().map(|e| e.to_string()).collect();
                failures.push(format!("{stem}: model not built:\n{}", text.join("\n")));
                continue;
            }
        };
        let mp = model.mass_properties();
        let rm = r["mass"].as_f64().unwrap_or(f64::NAN);
        let rcg = floats(&r["cg"]);
        let ri = floats(&r["inertia_cg"]);
        assert_eq!(
            (rcg.len(), ri.len()),
            (3, 9),
            "{file}: cg and inertia_cg shapes"
        );
        let dm = (mp.mass - rm).abs() / rm.abs();
        let dcg: Vec<f64> = mp.cg.iter().zip(&rcg).map(|(a, b)| a - b).collect();
        let di: Vec<f64> = mp
            .inertia_cg
            .iter()
            .flatten()
            .zip(&ri)
            .map(|(a, b)| a - b)
            .collect();
        let d = [dm, norm(&dcg) / norm(&rcg), norm(&di) / norm(&ri)];
        println!("{stem:<26} {:>10.2e} {:>10.2e} {:>10.2e}", d[0], d[1], d[2]);
        for (k, label) in ["mass", "cg", "inertia_cg"].iter().enumerate() {
            if d[k].is_nan() || d[k] > TOL {
                failures.push(format!("{stem}: {label} differs from the independent exact value by {:.3e} relative (tolerance {TOL:e})", d[k]));
            }
        }
        if failures.iter().any(|f| f.starts_with(&format!("{stem}:"))) {
            failures.push(format!(
                "{stem}: paraflex mass {:?} cg {:?} inertia_cg {:?}\n  expected mass {rm:?} cg {rcg:?} inertia_cg {ri:?}",
                mp.mass, mp.cg, mp.inertia_cg
            ));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
