//! CBUSH / PBUSH: statics against the numpy bush model of `tools/analytic/cbush_static.py`
//! (orientation grid, spring location S, grounded bush with CID and OCID offset), a bush
//! between coincident grids against the equivalent CELAS2 springs, and placement errors.

mod common;

use std::io::Write;

use common::{f64s, json, read_dataset, root, run_to_file};
use paraflex::deck::Deck;
use paraflex::model::Model;

/// The static displacement rows (grids in increasing id).
fn displacement_rows(text: &str) -> Vec<f64> {
    let (file, _dir) = run_to_file(text);
    let g = file.group("results/1/statics").expect("statics");
    read_dataset(&g, "displacement")
}

#[test]
fn bush_statics_match_the_numpy_model() {
    let reference = json("reference/analytic/cbush_static.json");
    let deck = std::fs::read_to_string(root().join("decks/verify/independent/cbush_static.dat"))
        .expect("deck");
    let u = displacement_rows(&deck);
    let ids = [1u32, 2, 3, 5];
    for grid in [2u32, 5] {
        let expected = f64s(&reference["displacement"][grid.to_string()]);
        let row = ids.iter().position(|&i| i == grid).expect("grid row");
        let got = &u[6 * row..6 * row + 6];
        let scale = expected.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        for (a, b) in got.iter().zip(&expected) {
            assert!(
                (a - b).abs() <= 1e-10 * scale,
                "grid {grid}: {got:?} vs {expected:?}"
            );
        }
    }
}

/// Coincident grids with blank axes: the bush is six springs along the basic axes, the same
/// as six CELAS2 between the grids' components.
#[test]
fn coincident_bush_equals_six_scalar_springs() {
    let k = [11.0, 23.0, 37.0, 41.0, 53.0, 67.0];
    let head = "SOL 101\nCEND\nSPC = 1\nLOAD = 2\nBEGIN BULK\nGRID,1,,1.,2.,3.\nGRID,2,,1.,2.,3.\nSPC1,1,123456,1\nFORCE,2,2,,1.,3.,-2.,5.\nMOMENT,2,2,,1.,-1.,4.,2.\n";
    let bush = format!(
        "{head}CBUSH,9,4,1,2\nPBUSH,4,K,{}\nENDDATA\n",
        k.map(|v| format!("{v:?}")).join(",")
    );
    let springs: String = (0..6)
        .map(|c| format!("CELAS2,{},{:?},1,{},2,{}\n", 10 + c, k[c], c + 1, c + 1))
        .collect();
    let celas = format!("{head}{springs}ENDDATA\n");
    let a = displacement_rows(&bush);
    let b = displacement_rows(&celas);
    let load = [3.0, -2.0, 5.0, -1.0, 4.0, 2.0];
    for c in 0..6 {
        assert!((a[6 + c] - load[c] / k[c]).abs() <= 1e-14, "{a:?}");
        assert!((a[6 + c] - b[6 + c]).abs() <= 1e-14, "{a:?} vs {b:?}");
    }
}

#[test]
fn bush_without_axes_between_distinct_grids_is_refused() {
    let text = "SOL 101\nCEND\nBEGIN BULK\nGRID,1,,0.,0.,0.\nGRID,2,,1.,0.,0.\nCBUSH,9,4,1,2\nPBUSH,4,K,1.\nENDDATA\n";
    let mut file = tempfile::Builder::new().suffix(".bdf").tempfile().unwrap();
    file.write_all(text.as_bytes()).unwrap();
    let deck = Deck::read(file.path()).expect("deck");
    let e: Vec<String> = Model::build(&deck)
        .unwrap_err()
        .iter()
        .map(|x| x.to_string())
        .collect();
    assert!(
        e.iter()
            .any(|m| m.contains("CBUSH 9") && m.contains("neither GO/X1-X3 nor CID")),
        "{e:?}"
    );
}
