//! Conformance of the model summary with pyNastran 1.4.1 (`reference/conformance/*.json`,
//! written by `tools/conformance/make_references.py`; pyNastran's formulas are specified in
//! `tools/conformance/PYNASTRAN_MASS.md`).
//!
//! - every deck: grid, element and rigid-element counts equal;
//! - `*_regular_*` decks (geometry on which pyNastran's formulas are exact: flat parallelogram
//!   quads, triangles, box hexas, right-prism wedges, tetras, CONM2 with CID 0/−1 and diagonal
//!   inertia or CID > 0 without inertia): mass, cg and inertia_cg within 1e-10 relative to the
//!   norm of each quantity;
//! - distorted decks (warped shells, corner thicknesses, sheared hexas): counts only — pyNastran
//!   lumps at node averages and uses a face formula for hexa/penta volumes, so its own mass is
//!   approximate there; the measured differences are printed, and the exact values are checked
//!   against an independent integration in tests/conformance_exact_mass.rs.
//!
//! Run with `--nocapture` to see the per-deck table.

use std::path::{Path, PathBuf};

use paraflex::deck::Deck;
use paraflex::model::Model;
use serde_json::Value;

/// Relative tolerance for quantities pyNastran computes exactly: round-off only.
const TOL: f64 = 1e-10;

/// Distorted decks whose total MASS pyNastran computes exactly (tetra volumes are exact for
/// straight edges; the meshio hexa box is rectangular). Their cg/inertia are exact too, since
/// the corner average is the tetra centroid and the box centroid.
const EXACT_ALL: &[&str] = &[
    "solid_tetra_",
    "meshio_box_tet_",
    "meshio_box_hex_",
    "conm2_coords_",
];

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn decks() -> Vec<PathBuf> {
    let mut out: Vec<PathBuf> = std::fs::read_dir(root().join("decks/conformance"))
        .expect("decks/conformance exists")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "bdf"))
        .collect();
    out.sort();
    out
}

fn reference(deck: &Path) -> Value {
    let stem = deck
        .file_stem()
        .and_then(|s| s.to_str())
        .unwrap_or_default();
    let text = std::fs::read_to_string(
        root()
            .join("reference/conformance")
            .join(format!("{stem}.json")),
    )
    .expect("reference json");
    serde_json::from_str(&text).expect("valid json")
}

fn norm(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

/// max over mass, cg, inertia of |a − b| / |b| (norm of the quantity).
fn diffs(deck: &Deck, model: &Model, r: &Value) -> [f64; 3] {
    let mp = model.mass_properties();
    let rm = r["mass"].as_f64().unwrap_or(f64::NAN);
    let rcg: Vec<f64> = r["cg"]
        .as_array()
        .map(|a| a.iter().filter_map(Value::as_f64).collect())
        .unwrap_or_default();
    let ri: Vec<f64> = r["inertia_cg"]
        .as_array()
        .map(|rows| {
            rows.iter()
                .flat_map(|row| {
                    row.as_array()
                        .into_iter()
                        .flatten()
                        .filter_map(Value::as_f64)
                })
                .collect()
        })
        .unwrap_or_default();
    let dm = (mp.mass - rm).abs() / rm.abs();
    let dcg: Vec<f64> = mp.cg.iter().zip(&rcg).map(|(a, b)| a - b).collect();
    let correction = conm2_cid_inertia(deck, model);
    let ri: Vec<f64> = ri
        .iter()
        .zip(correction.iter().flatten())
        .map(|(r, c)| r + mp.wtmass * c)
        .collect();
    let di: Vec<f64> = mp
        .inertia_cg
        .iter()
        .flatten()
        .zip(&ri)
        .map(|(a, b)| a - b)
        .collect();
    [
        dm,
        norm(&dcg) / norm(&rcg).max(1e-300),
        norm(&di) / norm(&ri).max(1e-300),
    ]
}

/// The inertia pyNastran drops: Σ T J Tᵀ of every CONM2 with CID > 0 (PYNASTRAN_MASS.md §5,
/// quirk 2), T the CID axes as columns, J the card's tensor [[I11, −I21, −I31], …]. Only
/// diagonal J occurs in the decks, so the product-of-inertia sign question does not arise.
fn conm2_cid_inertia(deck: &Deck, model: &Model) -> [[f64; 3]; 3] {
    let mut out = [[0.0; 3]; 3];
    for c in deck.bulk.conm2.iter().filter(|c| c.cid > 0) {
        let (Some(sys), Some(grid)) = (model.coords.get(&(c.cid as u32)), model.grid(c.grid))
        else {
            continue;
        };
        let t = sys.axes_at(grid.xyz);
        let [i11, i21, i22, i31, i32, i33] = c.inertia;
        let j = [[i11, -i21, -i31], [-i21, i22, -i32], [-i31, -i32, i33]];
        for a in 0..3 {
            for b in 0..3 {
                for k in 0..3 {
                    for l in 0..3 {
                        out[a][b] += t[a][k] * j[k][l] * t[b][l];
                    }
                }
            }
        }
    }
    out
}

fn counts_match(model: &Model, r: &Value) -> Result<(), String> {
    let s = model.summary();
    let elements: serde_json::Map<String, Value> = s
        .elements
        .iter()
        .map(|(k, v)| (k.to_string(), Value::from(*v)))
        .collect();
    let rigid: serde_json::Map<String, Value> = s
        .rigid
        .iter()
        .map(|(k, v)| (k.to_string(), Value::from(*v)))
        .collect();
    let checks = [
        ("grids", Value::from(s.grids), r["grids"].clone()),
        ("elements", Value::Object(elements), r["elements"].clone()),
        ("rigid", Value::Object(rigid), r["rigid"].clone()),
        ("dofs", Value::from(s.dofs), r["dofs"].clone()),
    ];
    for (name, ours, theirs) in checks {
        if ours != theirs {
            return Err(format!("{name}: paraflex {ours} vs pyNastran {theirs}"));
        }
    }
    Ok(())
}

#[test]
fn conformance_decks_match_pynastran() {
    let mut failures = Vec::new();
    println!(
        "{:<34} {:>10} {:>10} {:>10}  compared",
        "deck", "mass", "cg", "inertia"
    );
    for deck_path in decks() {
        let name = deck_path
            .file_name()
            .and_then(|s| s.to_str())
            .unwrap_or_default()
            .to_string();
        let deck = match Deck::read(&deck_path) {
            Ok(d) => d,
            Err(e) => {
                failures.push(format!("{name}: deck not read:\n{e}"));
                continue;
            }
        };
        let model = match Model::build(&deck) {
            Ok(m) => m,
            Err(errors) => {
                let text: Vec<String> = errors.iter().map(|e| e.to_string()).collect();
                failures.push(format!("{name}: model not built:\n{}", text.join("\n")));
                continue;
            }
        };
        let r = reference(&deck_path);
        if let Err(e) = counts_match(&model, &r) {
            failures.push(format!("{name}: {e}"));
        }
        let d = diffs(&deck, &model, &r);
        let regular = name.contains("_regular_");
        let all = regular || EXACT_ALL.iter().any(|p| name.starts_with(p));
        let compared = if all {
            "mass cg inertia"
        } else {
            "counts (approximate in pyNastran)"
        };
        println!(
            "{name:<34} {:>10.2e} {:>10.2e} {:>10.2e}  {compared}",
            d[0], d[1], d[2]
        );
        let limit = if all { 3 } else { 0 };
        for (k, label) in ["mass", "cg", "inertia_cg"].iter().enumerate().take(limit) {
            if d[k].is_nan() || d[k] > TOL {
                failures.push(format!(
                    "{name}: {label} differs from pyNastran by {:.3e} relative (tolerance {TOL:e})",
                    d[k]
                ));
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
