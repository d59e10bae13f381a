//! MPC / MPCADD equations: statics against the hand elimination of
//! `reference/analytic/mpc_lever.json` (the modes are in `tests/references.rs`), and the
//! errors of sets, subcases and DOFs an equation cannot use.

use std::io::Write;

use paraflex::deck::Deck;
use paraflex::model::Model;

mod common;
use common::{json, read_dataset, root, run_deck, run_to_file};

fn lever_static_deck() -> String {
    let r = json("reference/analytic/mpc_lever.json");
    let deck = r["static"]["deck"].as_str().expect("deck");
    std::fs::read_to_string(root().join(deck)).expect("read deck")
}

/// The dependent DOF (T2 of grid 2 in its rotated system, reported in basic as −x) and the two
/// independent ones match the eliminated 2 × 2 solve.
#[test]
fn three_term_mpc_statics_match_the_hand_elimination() {
    let r = json("reference/analytic/mpc_lever.json");
    let v = &r["static"]["values"];
    let tol = r["static"]["tolerance_relative"].as_f64().expect("tol");
    let (file, _dir) = run_to_file(&lever_static_deck());
    let u: Vec<f64> = read_dataset(&file.group("results/1/statics").unwrap(), "displacement");
    let expected = [
        (0, v["u1_T1"].as_f64().unwrap()),
        (6, v["u2_basic_x"].as_f64().unwrap()),
        (12, v["u3_T1"].as_f64().unwrap()),
    ];
    for (i, want) in expected {
        let err = (u[i] - want).abs() / want.abs();
        assert!(err < tol, "u[{i}] = {} vs {want}: {err:e}", u[i]);
    }
    // every other component is constrained or zero by the equation's geometry
    for (i, x) in u
        .iter()
        .enumerate()
        .filter(|(i, _)| ![0, 6, 12].contains(i))
    {
        assert!(x.abs() < 1e-14, "u[{i}] = {x}");
    }
}

/// The errors of reading, checking or running `deck`, one per line.
fn error_text(deck: &str) -> String {
    let mut file = tempfile::Builder::new()
        .suffix(".dat")
        .tempfile()
        .expect("temp file");
    file.write_all(deck.as_bytes()).expect("write deck");
    let read =
        Deck::read(file.path()).map_err(|e| e.errors.iter().map(|x| x.to_string()).collect());
    let built = read.and_then(|d| {
        Model::build(&d).map_err(|e| e.iter().map(|x| x.to_string()).collect::<Vec<_>>())
    });
    let errors = match built {
        Err(errors) => errors,
        Ok(_) => match run_deck(deck).0 {
            Ok(_) => panic!("expected an error for:\n{deck}"),
            Err(e) => vec![e.to_string()],
        },
    };
    errors.join("\n")
}

fn with_case(deck: &str, from: &str, to: &str) -> String {
    assert!(deck.contains(from), "{from}");
    deck.replacen(from, to, 1)
}

#[test]
fn subcases_must_share_one_mpc_set() {
    let deck = with_case(
        &lever_static_deck(),
        "MPC = 20\nSUBCASE 1\n  SPC = 1\n  LOAD = 2\n  DISPLACEMENT = ALL\n",
        "SUBCASE 1\n  MPC = 20\n  SPC = 1\n  LOAD = 2\nSUBCASE 2\n  MPC = 10\n  SPC = 1\n  LOAD = 2\n",
    );
    let e = error_text(&deck);
    assert!(
        e.contains("MPC = 10 (subcase 2) while subcase 1 selects MPC = 20"),
        "{e}"
    );
}

/// `MPC = sid` with no MPC/MPCADD card of that id applies nothing, with a warning at the
/// command (MSC Nastran runs such decks): the lever without its MPC cards runs.
#[test]
fn an_mpc_selection_without_cards_is_a_warning() {
    let deck = with_case(&lever_static_deck(), "MPC = 20\n", "MPC = 99\n");
    let model = common::build_model(&deck).expect("reads");
    assert!(
        model
            .warnings
            .iter()
            .any(|w| w.message.contains("MPC = 99 selects no MPC/MPCADD set 99")),
        "{:?}",
        model.warnings
    );
    run_deck(&deck).0.expect("runs without the MPC");
}

#[test]
fn bad_mpc_cards_are_reported_in_one_pass() {
    let fields = with_case(
        &lever_static_deck(),
        "MPCADD,20,10\n",
        "MPCADD,20,10\nMPC,30,2,0,1.0\nMPC,31,2,1,0.0,1,1,1.0\nMPC,32,2,1,1.0,1,1,1.0,7\n",
    );
    let e = error_text(&fields);
    for want in [
        "MPC 30: field 4 (C1): component 0 (a scalar point) is not supported",
        "MPC 31: field 5 (A1): the first coefficient must be nonzero",
        "MPC 32: field 9 (blank)",
    ] {
        assert!(e.contains(want), "missing '{want}' in:\n{e}");
    }
    let references = with_case(
        &lever_static_deck(),
        "MPCADD,20,10\n",
        "MPCADD,20,10\nMPC,32,99,1,1.0\nMPCADD,33,20\n",
    );
    let e = error_text(&references);
    for want in [
        "G = 99 does not exist",
        "S = 20 does not exist (no MPC set 20)",
    ] {
        assert!(e.contains(want), "missing '{want}' in:\n{e}");
    }
}

/// A dependent DOF may be neither constrained by an SPC nor dependent in a rigid element.
#[test]
fn dependent_dof_conflicts_name_both_owners() {
    let spc = with_case(
        &lever_static_deck(),
        "SPC1,1,13456,2\n",
        "SPC1,1,123456,2\n",
    );
    let e = error_text(&spc);
    assert!(e.contains("MPC 10"), "{e}");
    let rbe2 = with_case(
        &lever_static_deck(),
        "MPCADD,20,10\n",
        "MPCADD,20,10\nGRID,4,,1.,1.,0.\nRBE2,40,4,123456,2\n",
    );
    let e = error_text(&rbe2);
    assert!(e.contains("MPC 10") && e.contains("RBE2 40"), "{e}");
}
