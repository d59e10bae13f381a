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
        "MPCADD,20,10\nMPC,30,2,7,1.0\nMPC,31,2,1,0.0,1,1,1.0\nMPC,32,2,1,1.0,1,1,1.0,7\n",
    );
    let e = error_text(&fields);
    for want in [
        "MPC 30: field 4 (C1): expected a single component 1-6 (0 or blank for a scalar point), found 7",
        "MPC 31: field 5 (A1): the first coefficient must be nonzero",
        "MPC 32: field 9 (blank)",
    ] {
        assert!(e.contains(want), "missing '{want}' in:\n{e}");
    }
    let references = with_case(
        &lever_static_deck(),
        "MPCADD,20,10\n",
        "MPCADD,20,10\nMPC,32,99,1,1.0\nMPCADD,33,20\nSPOINT,50\nMPC,34,2,0,1.0\nMPC,35,50,1,1.0\nMPC,36,98,0,1.0\n",
    );
    let e = error_text(&references);
    for want in [
        "G = 99 does not exist",
        "MPC 34: G = 2 is a GRID: give its component 1-6",
        "MPC 35: G = 50 is a scalar point: its component is 0 or blank, found 1",
        "MPC 36: G = 98 does not exist (no GRID or SPOINT 98)",
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

/// A cantilever of width `b` and thickness `t` along x: a solid block (one 20-node CHEXA
/// through the thickness and across the width, `nx` along x, length `ls`) clamped at x = 0,
/// continued by CQUAD8 shells at mid-thickness (length `lsh`, `ns` along x) that an RSSCON
/// (ELEM form, one per shell element on the solid face) connects to the last solid element,
/// with a tip moment `m` about y spread over the tip edge as a quadratic edge takes it
/// (1/6, 2/3, 1/6). ν = 0, so beam, plate and solid bending coincide. The PSHELL and the
/// PSOLID share id 1, as in MSC's rs321h (each element kind names its own).
fn shell_on_solid_deck(rsscon: &str) -> String {
    let (nx, ls, ns, lsh, b, t) = (2, 1.0, 4, 3.0, 0.5, 0.2);
    let mut bulk = String::new();
    let sid = |i: usize, j: usize, k: usize| 10_000 + 100 * i + 10 * j + k;
    for i in 0..=2 * nx {
        for j in 0..=2 {
            for k in 0..=2 {
                if (i % 2) + (j % 2) + (k % 2) <= 1 {
                    let (x, y, z) = (
                        i as f64 * ls / (2 * nx) as f64,
                        j as f64 * b / 2.0,
                        k as f64 * t / 2.0,
                    );
                    bulk += &format!("GRID,{},,{x:?},{y:?},{z:?}\n", sid(i, j, k));
                    if i == 0 {
                        bulk += &format!("SPC1,1,123,{}\n", sid(i, j, k));
                    }
                }
            }
        }
    }
    for e in 0..nx {
        let i = 2 * e;
        let c = |di: usize, j: usize, k: usize| sid(i + di, j, k);
        let nodes = [
            c(0, 0, 0),
            c(2, 0, 0),
            c(2, 2, 0),
            c(0, 2, 0),
            c(0, 0, 2),
            c(2, 0, 2),
            c(2, 2, 2),
            c(0, 2, 2),
            c(1, 0, 0),
            c(2, 1, 0),
            c(1, 2, 0),
            c(0, 1, 0),
            c(0, 0, 1),
            c(2, 0, 1),
            c(2, 2, 1),
            c(0, 2, 1),
            c(1, 0, 2),
            c(2, 1, 2),
            c(1, 2, 2),
            c(0, 1, 2),
        ];
        let list: Vec<String> = nodes.iter().map(|n| n.to_string()).collect();
        bulk += &format!("CHEXA,{},1,{}\n", 100 + e, list.join(","));
    }
    let hid = |i: usize, j: usize| 20_000 + 10 * i + j;
    for i in 0..=2 * ns {
        for j in 0..=2 {
            if (i % 2) + (j % 2) <= 1 {
                let x = ls + i as f64 * lsh / (2 * ns) as f64;
                bulk += &format!(
                    "GRID,{},,{x:?},{:?},{:?}\n",
                    hid(i, j),
                    j as f64 * b / 2.0,
                    t / 2.0
                );
            }
        }
    }
    for e in 0..ns {
        let i = 2 * e;
        let nodes = [
            hid(i, 0),
            hid(i + 2, 0),
            hid(i + 2, 2),
            hid(i, 2),
            hid(i + 1, 0),
            hid(i + 2, 1),
            hid(i + 1, 2),
            hid(i, 1),
        ];
        let list: Vec<String> = nodes.iter().map(|n| n.to_string()).collect();
        bulk += &format!("CQUAD8,{},1,{}\n", 200 + e, list.join(","));
    }
    bulk += rsscon;
    let m = 10.0;
    for (j, share) in [(0, 1.0 / 6.0), (1, 2.0 / 3.0), (2, 1.0 / 6.0)] {
        bulk += &format!("MOMENT,1,{},,{:?},0.,1.,0.\n", hid(2 * ns, j), m * share);
    }
    format!(
        "SOL 101\nCEND\nSPC = 1\nLOAD = 1\nDISPLACEMENT = ALL\nBEGIN BULK\n\
         PSHELL,1,1,{t},1,,1\nPSOLID,1,1\nMAT1,1,2.e7,,0.\n{bulk}ENDDATA\n"
    )
}

/// Displacements of the shell-on-solid cantilever (grid id → 6 components).
fn shell_on_solid_displacements(rsscon: &str) -> std::collections::HashMap<u32, Vec<f64>> {
    let deck = shell_on_solid_deck(rsscon);
    let (file, _dir) = run_to_file(&deck);
    let u: Vec<f64> = read_dataset(&file.group("results/1/statics").unwrap(), "displacement");
    // the rows are in grid id order
    let mut ids: Vec<u32> = deck
        .lines()
        .filter_map(|l| l.strip_prefix("GRID,"))
        .map(|l| l.split(',').next().unwrap().parse().unwrap())
        .collect();
    ids.sort();
    ids.iter()
        .enumerate()
        .map(|(i, &g)| (g, u[6 * i..6 * i + 6].to_vec()))
        .collect()
}

/// RSSCON ties a shell to the solid it ends on: under a tip moment the cantilever bends as
/// one beam, tip rotation M L / (E I) and deflection −M L² / (2 E I) over the whole length
/// L = 4 (solid 1, shell 3). At the junction the shell grid moves with the bottom solid grid
/// of the edge and turns with the edge, (u_top − u_bottom)·x / t, the QRG's equations (MSC's
/// own rs321h results satisfy them to 4 digits). The ELEM form and the GRID form naming the
/// same links give the same answer.
#[test]
fn rsscon_ties_a_shell_cantilever_to_its_solid_root() {
    let elem = shell_on_solid_displacements("RSSCON,1,ELEM,200,101\n");
    let (m, l, t, ei) = (10.0, 4.0, 0.2, 2.0e7 * 0.5 * 0.2f64.powi(3) / 12.0);
    // the pure-bending field (quadratic displacements) lies in the CHEXA20 and CQUAD8 spaces
    // and satisfies the RSSCON equations, so the solution is exact up to rounding
    let tol = 1e-9;
    let tip = &elem[&20_081];
    let (theta, w) = (m * l / ei, -m * l * l / (2.0 * ei));
    assert!(
        (tip[4] - theta).abs() < tol * theta,
        "tip θy {} vs {theta}",
        tip[4]
    );
    assert!(
        (tip[2] - w).abs() < tol * w.abs(),
        "tip w {} vs {w}",
        tip[2]
    );
    // junction: shell grid (x = 1, y = 0, z = t/2) halfway up the solid edge 10400 – 10402
    let (s, a, b) = (&elem[&20_000], &elem[&10_400], &elem[&10_402]);
    for c in 0..3 {
        let mean = 0.5 * (a[c] + b[c]);
        assert!(
            (s[c] - mean).abs() < tol * w.abs(),
            "u{c}: {} vs {mean}",
            s[c]
        );
    }
    let turn = (b[0] - a[0]) / t;
    assert!((s[4] - turn).abs() < tol * theta, "θy {} vs {turn}", s[4]);
    // the GRID form with the ELEM form's three links
    let grid = shell_on_solid_displacements(
        "RSSCON,1,GRID,20000,10400,10402,20001,10410,10412\nRSSCON,2,GRID,20002,10420,10422\n",
    );
    for (g, u) in &elem {
        for c in 0..6 {
            assert!(
                (grid[g][c] - u[c]).abs() < tol * theta.max(w.abs()),
                "grid {g} component {c}"
            );
        }
    }
}

/// RSSCON cards that cannot connect: the error names the card and what is wrong.
#[test]
fn rsscon_errors_name_the_card() {
    let deck = shell_on_solid_deck("RSSCON,1,ELEM,200,100\nRSSCON,2,ELEM,101,200\n");
    let text = error_text(&deck);
    for want in [
        "RSSCON 1: no grid of shell element 200 lies on an edge of solid element 100",
        "RSSCON 2: ES1 = 101 is not a shell element",
    ] {
        assert!(text.contains(want), "{want} not in\n{text}");
    }
    let deck = shell_on_solid_deck("RSSCON,1,GRID,20002,10400,10402\n");
    let text = error_text(&deck);
    let want =
        "RSSCON 1: shell grid ES1 = 20002 is not on the solid edge EA1 = 10400 – EB1 = 10402";
    assert!(text.contains(want), "{want} not in\n{text}");
    let deck = shell_on_solid_deck("RSSCON,1,ELEM,200,101,5\n");
    let text = error_text(&deck);
    let want = "EB1";
    assert!(text.contains(want), "{want} not in\n{text}");
}
