//! Bad input: every problem is reported in one pass, located at the card, never a panic.

mod common;

use std::io::Write;

use common::build_model;

use paraflex::deck::Deck;
use paraflex::model::Model;
use paraflex::sequence::request_warnings;

/// The warnings `paraflex check` prints for a valid deck: the model's, then the output
/// requests its solution sequence does not write.
fn warnings(text: &str) -> Vec<String> {
    let mut file = tempfile::Builder::new()
        .suffix(".bdf")
        .tempfile()
        .expect("temp file");
    file.write_all(text.as_bytes()).expect("write deck");
    let deck = Deck::read(file.path()).expect("valid deck");
    let model = Model::build(&deck).expect("valid deck");
    model
        .warnings
        .iter()
        .chain(&request_warnings(&deck, &model))
        .map(|w| w.to_string())
        .collect()
}

const BAD: &str = "SOL 103
CEND
METHOD = 7
SPC = 1
DISP = 5
BEGIN BULK
GRID,1,,0.,0.,0.
GRID,2,,1.,0.,0.
GRID,3,,1.,1.,0.
GRID,3,,1.,1.,0.
GRID,4,,0.,1.,0.,9
CQUAD4,101,1,1,2,77,4
CQUAD4,101,1,1,2,3,4
CTRIA3,102,2,1,2,3
CHEXA,103,1,1,2,3,4,5,6,
+,7,8
PSHELL,1,8,0.
PSOLID,2,8
MAT8,8,1.e10,1.e9,0.3,0.
MAT1,9,-1.,,0.7,-2.
PSHELL,3,10,0.01
MAT1,10,2.e7,5.e6
CONM2,104,66,,-1.
CORD2R,5,6,0.,0.,0.,0.,0.,1.
+,1.,0.,0.
CORD2R,6,5,0.,0.,0.,0.,0.,1.
+,1.,0.,0.
CORD2R,7,,0.,0.,0.,0.,0.,0.
+,1.,0.,0.
PMPAR,1,EMOD,E,9,1.,2.
PARAM,WTMASS,-1.
PARAM,POST,-1
PARAM,PRTMAXIM,YES
ENDDATA
";

#[test]
fn every_error_is_collected_with_its_card() {
    let errors = build_model(BAD).expect_err("the deck is invalid");
    let expect = [
        "CQUAD4 101: G3 = 77 does not exist",
        "duplicate grid id 3",
        "duplicate element id 101",
        "CTRIA3 102: PID = 2 is a PSOLID; a CTRIA3 needs a PSHELL or PCOMP",
        "CHEXA 103: PID = 1 is a PSHELL; a CHEXA needs a PSOLID",
        "CHEXA 103: G5 = 5 does not exist",
        "PSHELL 1: T = 0e0 must be > 0",
        "PSOLID 2: MID = 8 is a MAT8",
        "required by CTRIA3 102",
        "MAT8 8: G12 = 0e0 must be > 0",
        "MAT1 9: E = -1e0 must be > 0",
        "MAT1 9: NU = 0.7 must lie in (−1, 0.5)",
        "MAT1 9: RHO = -2e0 must be ≥ 0",
        "MAT1 10: NU = 1 (derived as E/(2G) − 1) must lie in (−1, 0.5)",
        "CONM2 104: G = 66 does not exist",
        "CONM2 104: M = -1e0 must be ≥ 0",
        "RID cycle",
        "CORD2R 7: degenerate system: A and B coincide",
        "GRID 4: CD = 9 does not exist",
        "PMPAR 1: nominal E = -1 (from MAT1 9) lies outside [LOW, HIGH] = [1, 2]",
        "PARAM WTMASS: WTMASS must be a real > 0",
        "METHOD = 7 selects no EIGRL/EIGR set 7",
        "SPC = 1 selects no SPC/SPC1/SPCADD set 1",
        "DISPLACEMENT = 5: no case-control SET 5",
    ];
    let missing: Vec<&str> = expect
        .iter()
        .copied()
        .filter(|e| !errors.iter().any(|x| x.contains(e)))
        .collect();
    assert!(missing.is_empty(), "missing {missing:#?}\nin {errors:#?}");
    // every error is located file:line
    assert!(errors.iter().all(|e| e.contains(".bdf:")), "{errors:#?}");
}

#[test]
fn good_deck_warns_once_about_unknown_params_and_output_requests() {
    let deck = "SOL 103
CEND
METHOD = 1
DISP = ALL
STRESS = ALL
BEGIN BULK
PARAM,POST,-1
PARAM,PRTMAXIM,YES
PARAM,WTMASS,0.5
EIGRL,1,,,4
GRID,1,,0.,0.,0.
GRID,2,,2.,0.,0.
GRID,3,,3.,1.,0.
GRID,4,,1.,1.,0.
CQUAD4,1,1,1,2,3,4
PSHELL,1,1,0.1
MAT1,1,1.e7,,0.3,2.
PSOLID,5,1,,2
ENDDATA
";
    let w = warnings(deck);
    let model = build_model(deck).expect("valid deck");
    assert_eq!(
        w.iter()
            .filter(|x| x.contains("accepted and ignored: POST, PRTMAXIM"))
            .count(),
        1,
        "{w:#?}"
    );
    // SOL 103 writes mode shapes for DISPLACEMENT (sequence::modal), but no stresses
    assert!(
        w.iter()
            .any(|x| x.contains("STRESS is not honoured by SOL 103")),
        "{w:#?}"
    );
    assert!(
        !w.iter().any(|x| x.contains("DISPLACEMENT is not honoured")),
        "{w:#?}"
    );
    assert!(
        w.iter()
            .any(|x| x.contains("PSOLID IN/STRESS/ISOP are kept")),
        "{w:#?}"
    );
    // parallelogram 2 × 1, t = 0.1, rho = 2: m = 0.4, × WTMASS 0.5
    let mp = model.mass_properties();
    assert!(
        (mp.mass - 0.2).abs() < 1e-14 && (mp.cg[0] - 1.5).abs() < 1e-14,
        "{mp:?}"
    );
    let s = model.summary();
    assert_eq!(s.elements.get("CQUAD4"), Some(&1));
    assert_eq!(s.rigid.get("RBE2"), Some(&0));
    let mesh = model.mesh_arrays();
    assert_eq!(mesh.grid_ids, vec![1, 2, 3, 4]);
    assert_eq!(mesh.blocks[0].connectivity, vec![0, 1, 2, 3]);
}

#[test]
fn conm2_inertia_is_rotated_from_its_cid() {
    // CID 10: local x = basic y, local y = −basic x, z = z. I11 = 1 (about local x = basic y).
    let deck = "BEGIN BULK
CORD2R,10,,0.,0.,0.,0.,0.,1.
+,0.,1.,0.
GRID,1,,0.,0.,0.
CONM2,1,1,10,2.,1.,0.,0.
,1.,0.,2.,0.,0.,3.
ENDDATA
";
    let model = build_model(deck).expect("valid deck");
    let mp = model.mass_properties();
    // offset (1,0,0) local → (0,1,0) basic; tensor diag(1,2,3) local → diag(2,1,3) basic
    assert!(
        (mp.cg[1] - 1.0).abs() < 1e-14 && mp.cg[0].abs() < 1e-14,
        "{mp:?}"
    );
    let i = mp.inertia_cg;
    assert!(
        (i[0][0] - 2.0).abs() < 1e-14
            && (i[1][1] - 1.0).abs() < 1e-14
            && (i[2][2] - 3.0).abs() < 1e-14,
        "{i:?}"
    );
}

/// SOL 109/112 write displacement histories for DISPLACEMENT on the mesh (sequence::transient),
/// so no "not honoured" warning there; a subcase on a pROM artifact has no grids and is warned.
#[test]
fn transient_displacement_requests_are_honoured_on_the_mesh_only() {
    let deck = |sol: &str, rom: &str| {
        format!(
            "SOL {sol}
CEND
{rom}TSTEP = 9
DISP = ALL
BEGIN BULK
TSTEP,9,10,1.e-3,1
GRID,1,,0.,0.,0.
CELAS2,1,1.e3,1,1
CONM2,2,1,,1.
ENDDATA
"
        )
    };
    for sol in ["109", "112", "TRANSIENT"] {
        let w = warnings(&deck(sol, ""));
        assert!(
            !w.iter().any(|x| x.contains("DISPLACEMENT is not honoured")),
            "SOL {sol}: {w:#?}"
        );
        let w = warnings(&deck(sol, "ROM = 'blade.h5'\n"));
        assert!(
            w.iter().any(|x| x.contains("DISPLACEMENT is not honoured")),
            "SOL {sol} on a pROM: {w:#?}"
        );
    }
}

/// A second GRDSET is an error naming both cards; a GRDSET CP that does not exist is reported on
/// every GRID that takes it (the GRID's line, where the location is read).
#[test]
fn a_second_grdset_and_a_missing_grdset_system_are_errors() {
    let deck =
        "BEGIN BULK\nGRDSET,,7\nGRDSET,,,,,,,6\nGRID,1,,0.,0.,0.\nGRID,2,0,1.,0.,0.\nENDDATA\n";
    let errors = build_model(deck).expect_err("two GRDSETs");
    assert!(
        errors
            .iter()
            .any(|e| e.contains(":3: GRDSET") && e.contains("a second GRDSET")),
        "{errors:#?}"
    );
    assert!(
        errors
            .iter()
            .any(|e| e.contains(":4: GRID 1") && e.contains("CP = 7 does not exist")),
        "{errors:#?}"
    );
    assert!(!errors.iter().any(|e| e.contains("GRID 2")), "{errors:#?}");
}

/// PLOAD4 on a missing element, on a CHEXA with G1 and G3 not diagonal on one face, and on a
/// CTETRA without G4: one error each, at the card's line, all in one pass; a LOAD naming a
/// PLOAD4 set is valid; a LOAD naming a LOAD is not an error (it adds nothing, with a warning:
/// `a_load_named_in_a_load_adds_nothing` in tests/sol101.rs).
#[test]
fn pressure_cards_that_pick_no_face_are_errors() {
    let mut deck =
        String::from("SOL 101\nCEND\nLOAD = 9\nBEGIN BULK\nMAT1,1,1000.,,.3\nPSOLID,1,1\n");
    for (k, (x, y, z)) in [
        (0, 0, 0),
        (1, 0, 0),
        (1, 1, 0),
        (0, 1, 0),
        (0, 0, 1),
        (1, 0, 1),
        (1, 1, 1),
        (0, 1, 1),
    ]
    .iter()
    .enumerate()
    {
        deck += &format!("GRID,{},,{x}.,{y}.,{z}.\n", k + 1);
    }
    deck += "CHEXA,1,1,1,2,3,4,5,6,\n,7,8\nCTETRA,2,1,1,2,4,5\nSPC1,1,123,1,2,3,4\n";
    deck += "PLOAD4,5,1,1.,,,,5,6\nPLOAD4,5,2,1.\nPLOAD4,5,77,1.\nLOAD,9,1.,1.,5\nLOAD,10,1.,1.,9\nENDDATA\n";
    let errors = build_model(&deck).expect_err("bad PLOAD4s");
    assert_eq!(errors.len(), 3, "{errors:#?}");
    assert!(
        errors[0].contains("PLOAD4 5") && errors[0].contains("diagonally opposite"),
        "{errors:#?}"
    );
    assert!(
        errors[1].contains("CTETRA 2") && errors[1].contains("G1 is required"),
        "{errors:#?}"
    );
    assert!(errors[2].contains("EID = 77"), "{errors:#?}");
}

/// MATT1 with TABLEM1–TABLEM4: the tables apply only at a material temperature set, which
/// paraflex does not evaluate, so the MAT1's values apply (Nastran without TEMPERATURE(MATERIAL)):
/// a rod whose MATT1 E table says 1e11 everywhere stretches by P L/(E A) with the MAT1's
/// E = 2e11 (1e-12: round-off of a one-element solve), and one warning says why. A MATT1
/// naming a missing table or a MAT8 is an error at its field.
#[test]
fn matt1_leaves_the_mat1_values_without_a_temperature_set() {
    let bulk = "GRID,1,,0.,0.,0.,,123456\nGRID,2,,2.,0.,0.,,23456\nCROD,1,10,1,2\n\
        PROD,10,1,1.e-4\nMAT1,1,2.e11,,0.3,7800.\nFORCE,3,2,,1.e4,1.,0.,0.\n\
        MATT1,1,5,,6,,7,,8\nTABLEM1,5,,,1\n,0.,1.e11,100.,1.e11,ENDT\n\
        TABLEM2,6,20.\n,0.,0.3,100.,0.3,ENDT\nTABLEM3,7,20.,10.\n,0.,1.e-5,10.,2.e-5,ENDT\n\
        TABLEM4,8,0.,1.,0.,100.\n,0.01,1.e-4,ENDT\n";
    let deck = format!("SOL 101\nCEND\nLOAD = 3\nBEGIN BULK\n{bulk}ENDDATA\n");
    let warned = warnings(&deck);
    assert!(
        warned
            .iter()
            .any(|w| w.contains("MATT1 (1 card)") && w.contains("each MAT1 keeps its own values")),
        "{warned:#?}"
    );
    let (file, _dir) = common::run_to_file(&deck);
    let u = common::read_dataset::<f64>(&file.group("results/1/statics").unwrap(), "displacement");
    let want = 1.0e4 * 2.0 / (2.0e11 * 1.0e-4);
    assert!((u[6] - want).abs() <= 1e-12 * want, "{} vs {want}", u[6]);

    let bad = deck.replace("MATT1,1,5,,6", "MATT1,1,9,,6").replace(
        "MAT1,1,2.e11,,0.3,7800.\n",
        "MAT1,1,2.e11,,0.3,7800.\nMAT8,2,1.e11,1.e10,0.3\nMATT1,2,5\n",
    );
    let errors = build_model(&bad).expect_err("bad MATT1");
    for text in [
        "MATT1 1: field 3 (T(E)): T(E) = 9 does not exist (no TABLEM1",
        "MATT1 2: field 2 (MID): MID = 2 is a MAT8; a MATT1 applies to a MAT1",
    ] {
        assert!(
            errors.iter().any(|e| e.contains(text)),
            "'{text}' not in {errors:#?}"
        );
    }
    // a material temperature set would evaluate the tables: refused, at the statement
    let with_set = deck
        .replace("LOAD = 3\n", "LOAD = 3\nTEMPERATURE(INITIAL) = 4\n")
        .replace("ENDDATA", "TEMPD,4,100.\nENDDATA");
    let errors = build_model(&with_set).expect_err("material set with MATT1");
    assert!(
        errors.iter().any(|e| e.contains(":4: TEMPERATURE: TEMPERATURE(MATERIAL | INITIAL | BOTH) = 4 with MATT1 cards: temperature-dependent material properties are not available")),
        "{errors:#?}"
    );
}

/// Temperature sets: `TEMPERATURE(LOAD)` must select a TEMP or TEMPD set, a TEMP must name
/// existing grids, and a thermal load needs a temperature at every grid of an element that
/// expands (no TEMP for it and no TEMPD: an error naming the grid and the set). Describers
/// other than LOAD, MATERIAL, INITIAL, BOTH are refused at their line.
#[test]
fn temperature_sets_are_checked() {
    let base = "SOL 101\nCEND\nSPC = 1\nTEMP(LOAD) = 7\nBEGIN BULK\n\
        GRID,1,,0.,0.,0.,,123456\nGRID,2,,2.,0.,0.,,23456\nCROD,1,10,1,2\n\
        PROD,10,1,1.e-4\nMAT1,1,2.e11,,0.3,7800.,1.e-5\nSPC1,1,1,2\n";
    let e = build_model(&format!("{base}TEMP,8,1,10.\nENDDATA\n")).expect_err("no set 7");
    assert!(
        e.iter()
            .any(|e| e.contains("TEMPERATURE(LOAD) = 7 selects no TEMP/TEMPD set 7")),
        "{e:#?}"
    );
    let e = build_model(&format!("{base}TEMP,7,1,10.,3,20.\nENDDATA\n")).expect_err("grid 3");
    assert!(
        e.iter()
            .any(|e| e.contains("TEMP 7") && e.contains("G2 = 3 does not exist")),
        "{e:#?}"
    );
    let e = build_model(&base.replace("TEMP(LOAD)", "TEMP(HEAT)")).expect_err("describer");
    assert!(
        e.iter().any(|e| e.contains(
            ":4: TEMPERATURE: TEMPERATURE(HEAT): expected LOAD, MATERIAL, INITIAL or BOTH"
        )),
        "{e:#?}"
    );
    let (r, _dir) = common::run_deck(&format!("{base}TEMP,7,1,10.\nENDDATA\n"));
    let e = r.expect_err("grid 2 has no temperature").to_string();
    assert!(
        e.contains("CROD 1") && e.contains("GRID 2 has no temperature in temperature set 7"),
        "{e}"
    );
    // an element that does not expand (A = 0) needs no temperatures
    let cold = base.replace("7800.,1.e-5", "7800.");
    let (r, _dir) = common::run_deck(&format!("{cold}TEMP,7,1,10.\nENDDATA\n"));
    r.expect("no expansion, no temperature needed");
}

/// A MAT1 whose derived ν = E/(2G) − 1 lies outside (−1, 0.5) is accepted with a warning when
/// only line elements use it (they take E and G as given, as in Nastran; the shell use is an
/// error, above).
#[test]
fn derived_poisson_ratio_out_of_range_is_accepted_for_line_elements() {
    let w = warnings(
        "SOL 101\nCEND\nBEGIN BULK\nGRID,1,,0.,0.,0.\nGRID,2,,1.,0.,0.\nCROD,1,1,1,2\n\
         PROD,1,1,0.1,0.001\nMAT1,1,2.e7,5.e6\nENDDATA\n",
    );
    assert!(
        w.iter().any(|w| w.contains(
            "MAT1 1: NU = 1 (derived as E/(2G) − 1) lies outside (−1, 0.5); no shell, solid or shear panel uses this material"
        )),
        "{w:#?}"
    );
}

/// Enforced motion needs an SPCD set and an SPCD set needs enforced motion: an RLOAD1 or TLOAD1
/// of TYPE = DISP/VELO/ACCE whose EXCITEID has no SPCD, and one of TYPE = LOAD whose EXCITEID
/// selects SPCDs (whose values it would ignore), are errors at the card; a bad TYPE names the
/// field.
#[test]
fn enforced_motion_type_and_exciteid_must_agree() {
    let deck = "SOL 108\nCEND\nSPC = 1\nFREQUENCY = 5\nDLOAD = 7\nBEGIN BULK\n\
                GRID,1,,0.,0.,0.\nGRID,2,,1.,0.,0.\nCONM2,1,2,,1.\nCELAS2,3,1.e3,1,1,2,1\n\
                SPC1,1,123456,1\nSPC1,1,23456,2\nFREQ,5,10.\nTABLED1,20\n+,0.,1.,100.,1.,ENDT\n\
                SPCD,8,1,1,1.e-3\nDAREA,9,2,1,1.\n\
                RLOAD1,7,9,,,20,,DISP\nRLOAD1,7,8,,,20\nTLOAD1,6,8,,LOAD,20\nENDDATA\n";
    let mut errors = build_model(deck).expect_err("the deck is invalid");
    // a TYPE that is no excitation type is a field error of the reader
    let bad_type = deck.replace("ENDDATA", "RLOAD1,4,8,,,20,,SHAKE\nENDDATA");
    errors.extend(build_model(&bad_type).expect_err("bad TYPE"));
    let expect = [
        "RLOAD1 7: TYPE = DISP (enforced motion) needs EXCITEID = an SPCD set; there is no SPCD 9",
        "RLOAD1 7: EXCITEID = 8 selects SPCD cards, which an applied load (TYPE = LOAD) ignores",
        "TLOAD1 6: EXCITEID = 8 selects SPCD cards",
        "RLOAD1 4: field 8 (TYPE): expected LOAD, DISP, VELO, ACCE or 0-3, found 'SHAKE'",
    ];
    let missing: Vec<&str> = expect
        .iter()
        .copied()
        .filter(|e| !errors.iter().any(|x| x.contains(e)))
        .collect();
    assert!(missing.is_empty(), "missing {missing:#?}\nin {errors:#?}");
}

/// A CONM2 may share its id with another element (MSC Nastran keeps mass elements apart: four
/// decks of pyNastran's collection, with MSC results, have CONM2 50 beside CVISC 50), with a
/// warning; two CONM2 with one id and two other elements with one id stay errors.
#[test]
fn a_conm2_may_share_its_id_with_another_element_only() {
    let base = "SOL 103\nCEND\nMETHOD = 1\nBEGIN BULK\nEIGRL,1,,,1\nGRID,1,,0.,0.,0.\nGRID,2,,1.,0.,0.\nCELAS2,5,1000.,1,1\nCONM2,5,1,,1.\n";
    let shared = warnings(&format!("{base}ENDDATA\n"));
    assert!(
        shared
            .iter()
            .any(|w| w.contains(":9:") && w.contains("CONM2 5 has the id of another element")),
        "{shared:#?}"
    );
    let errors = build_model(&format!(
        "{base}CONM2,5,2,,1.\nCELAS2,5,1000.,2,1\nENDDATA\n"
    ))
    .expect_err("repeated ids");
    assert!(
        errors
            .iter()
            .any(|e| e.contains(":10: CONM2 5") && e.contains("duplicate mass element id 5")),
        "{errors:#?}"
    );
    assert!(
        errors
            .iter()
            .any(|e| e.contains(":11: CELAS2 5") && e.contains("duplicate element id 5")),
        "{errors:#?}"
    );
}

/// An LSEQ acts only where a subcase's LOADSET selects it (Nastran): beside a DAREA set of its
/// EXCITEID and selected by no LOADSET (pyNastran's `other/trncomp12.bdf`) it is a warning and
/// the DAREA loads stand alone; selected, the combination is refused at the LSEQ.
#[test]
fn an_lseq_no_loadset_selects_leaves_the_darea_set_alone() {
    let deck = |loadset: &str| {
        format!(
            "SOL 109\nCEND\nTSTEP = 5\nDLOAD = 10\n{loadset}BEGIN BULK\nGRID,1,,0.,0.,0.,,23456\nCELAS2,1,1000.,1,1\nCONM2,2,1,,1.\nTSTEP,5,10,.01\nTLOAD1,10,10,,,7\nTABLED1,7\n,0.,1.,1.,1.,ENDT\nDAREA,10,1,1,1.\nFORCE,12,1,,2.,1.,0.,0.\nLSEQ,10,10,12\nENDDATA\n"
        )
    };
    let w = warnings(&deck(""));
    assert!(
        w.iter()
            .any(|w| w.contains(":15:") && w.contains("LSEQ 10: no subcase selects it")),
        "{w:#?}"
    );
    let errors = build_model(&deck("LOADSET = 10\n")).expect_err("DAREA and LSEQ combined");
    assert!(
        errors
            .iter()
            .any(|e| e.contains(":16: LSEQ 10") && e.contains("is also a DAREA set")),
        "{errors:#?}"
    );
}
