//! Scalar points (`SPOINT`, implicit scalar points of scalar elements) and the scalar springs
//! CELAS1–CELAS4 on them: statics against a closed form, SPC on scalar points with an enforced
//! value, their results in HDF5, and the errors that name them.

mod common;

use std::io::Write;

use common::{build_model, read_dataset, run_deck, run_to_file};
use paraflex::deck::Deck;

/// A chain ground –k₁– s1 –k₁₂– s2 –k₂₃– s3 on scalar points, s3 enforced to 1 by SPC, and
/// GRID 10 (only T1 free) tied to s1 by a CELAS2 of k = 4 and pulled by F = 5. With
/// k₁ = 1 (CELAS4), k₁₂ = 2 (CELAS4), k₂₃ = 3 (CELAS3 with PELAS), equilibrium is
///
/// ```text
/// grid 10:  4 (u₁₀ − u₁) = 5
/// s1:       1 u₁ + 2 (u₁ − u₂) + 4 (u₁ − u₁₀) = 0   →  3 u₁ − 2 u₂ = 5
/// s2:       2 (u₂ − u₁) + 3 (u₂ − 1) = 0            → −2 u₁ + 5 u₂ = 3
/// ```
///
/// so u₁ = 31/11, u₂ = 19/11, u₁₀ = u₁ + 5/4 = 179/44, and the SPC force at s3 is
/// 3 (1 − u₂) = −24/11.
const CHAIN: &str = "SOL 101
CEND
SPC = 1
LOAD = 2
SPCFORCES = ALL
BEGIN BULK
SPOINT,1,THRU,3
GRID,10,,0.,0.,0.,,23456
CELAS4,101,1.0,1
CELAS4,102,2.0,1,2
CELAS3,103,7,2,3
PELAS,7,3.0
CELAS2,104,4.0,10,1,1,0
SPC,1,3,0,1.0
FORCE,2,10,,5.0,1.,0.,0.
ENDDATA
";

#[test]
fn spring_chain_on_scalar_points_matches_the_closed_form() {
    let (file, _dir) = run_to_file(CHAIN);
    let g = file.group("results/1/statics").expect("statics");
    let ids: Vec<u32> = read_dataset(&g, "scalar_point_ids");
    assert_eq!(ids, vec![1, 2, 3]);
    let u: Vec<f64> = read_dataset(&g, "displacement_scalar");
    let expected = [31.0 / 11.0, 19.0 / 11.0, 1.0];
    for (a, b) in u.iter().zip(expected) {
        assert!((a - b).abs() <= 1e-12, "{u:?} vs {expected:?}");
    }
    let grid: Vec<f64> = read_dataset(&g, "displacement");
    assert_eq!(grid.len(), 6, "one grid row");
    assert!((grid[0] - 179.0 / 44.0).abs() <= 1e-12, "{grid:?}");
    let q: Vec<f64> = read_dataset(&g, "spc_force_scalar");
    assert!((q[2] + 24.0 / 11.0).abs() <= 1e-12, "{q:?}");
    assert!(q[0].abs() <= 1e-12 && q[1].abs() <= 1e-12, "{q:?}");
}

/// Ground may be written as a 0 id as well as a blank (QRG: G, S integer ≥ 0), as in MSC's
/// `sdbush10` (`CELAS1 … 777 1 0 0`): the chain with CELAS4 101's ground end written as S2 = 0,
/// plus a zero-stiffness CELAS1 from GRID 10 to a ground written G2 C2 = 0 0, gives the same
/// closed form.
#[test]
fn ground_may_be_written_as_a_zero_id() {
    let deck = CHAIN
        .replace("CELAS4,101,1.0,1\n", "CELAS4,101,1.0,1,0\n")
        .replace(
            "PELAS,7,3.0\n",
            "PELAS,7,3.0\nPELAS,8,0.0\nCELAS1,105,8,10,1,0,0\n",
        );
    let (file, _dir) = run_to_file(&deck);
    let g = file.group("results/1/statics").expect("statics");
    let u: Vec<f64> = read_dataset(&g, "displacement_scalar");
    let expected = [31.0 / 11.0, 19.0 / 11.0, 1.0];
    for (a, b) in u.iter().zip(expected) {
        assert!((a - b).abs() <= 1e-12, "{u:?} vs {expected:?}");
    }
}

/// Scalar points need not be declared: a CELAS end with component 0 or blank whose id is no
/// GRID is a scalar point (as in Nastran); same numbers as the declared chain.
/// An MPC whose dependent DOF is a scalar point (as Femap writes relative motions): s = u₁ − u₂
/// of grids 1 and 2 (T1 free only), a CELAS2 of k_s = 3 on s to ground and one of k = 1 from
/// grid 2 to ground, grid 1 pulled by F = 2 and tied to grid 2 by nothing else: the relative
/// spring makes u₁ − u₂ = F / k_s and the ground spring u₂ = F / k, so u₁ = 2 + 2/3, u₂ = 2,
/// s = 2/3.
#[test]
fn an_mpc_may_make_a_scalar_point_dependent() {
    let deck = "SOL 101\nCEND\nMPC = 5\nLOAD = 2\nBEGIN BULK\n\
                SPOINT,9\nGRID,1,,0.,0.,0.,,23456\nGRID,2,,1.,0.,0.,,23456\n\
                MPC,5,9,0,-1.,1,1,1.\n,,2,1,-1.\n\
                CELAS2,101,3.0,9,0\nCELAS2,102,1.0,2,1\nFORCE,2,1,,2.0,1.,0.,0.\nENDDATA\n";
    let (file, _dir) = run_to_file(deck);
    let g = file.group("results/1/statics").expect("statics");
    let s: Vec<f64> = read_dataset(&g, "displacement_scalar");
    let u: Vec<f64> = read_dataset(&g, "displacement");
    let (u1, u2) = (u[0], u[6]);
    assert!((u2 - 2.0).abs() <= 1e-12, "u2 = {u2}");
    assert!((u1 - 8.0 / 3.0).abs() <= 1e-12, "u1 = {u1}");
    assert!((s[0] - 2.0 / 3.0).abs() <= 1e-12, "s = {s:?}");
}

#[test]
fn implicit_scalar_points_are_the_declared_ones() {
    let (file, _dir) = run_to_file(&CHAIN.replace("SPOINT,1,THRU,3\n", ""));
    let g = file.group("results/1/statics").expect("statics");
    let u: Vec<f64> = read_dataset(&g, "displacement_scalar");
    assert!((u[0] - 31.0 / 11.0).abs() <= 1e-12, "{u:?}");
}

#[test]
fn errors_name_scalar_points() {
    let bad = |from: &str, to: &str| {
        build_model(&CHAIN.replace(from, to))
            .unwrap_err()
            .join("\n")
    };
    let e = bad("SPC,1,3,0,1.0", "SPC,1,3,123,1.0");
    assert!(
        e.contains("scalar point 3") && e.contains("C = 0 or blank"),
        "{e}"
    );
    let e = bad("CELAS2,104,4.0,10,1,1,0", "CELAS2,104,4.0,10,0,1,0");
    assert!(e.contains("G1 = 10 is a GRID"), "{e}");
    let e = bad("SPOINT,1,THRU,3", "SPOINT,1,THRU,3,10");
    assert!(e.contains("scalar point 10 is also a GRID"), "{e}");
    let e = bad("SPC,1,3,0,1.0", "SPC1,1,,10");
    assert!(e.contains("C is blank or 0 on GRID 10"), "{e}");
    let e = bad("SPC,1,3,0,1.0", "SPC,1,33,0,1.0");
    assert!(e.contains("no GRID or SPOINT 33"), "{e}");
}

/// A scalar point with no stiffness is a singular DOF, named as a scalar point.
#[test]
fn a_loose_scalar_point_is_named() {
    let deck = CHAIN.replace("SPOINT,1,THRU,3", "SPOINT,1,THRU,3,77");
    let (r, _dir) = run_deck(&deck);
    let text = match r {
        Ok(s) => s.subcases[0]
            .autospc
            .iter()
            .map(|d| d.to_string())
            .collect::<Vec<_>>()
            .join(", "),
        Err(e) => e.to_string(),
    };
    assert!(text.contains("SPOINT 77"), "{text}");
}

/// Viscous dampers are read and ignored by statics (as Nastran), applied by SOL 108, and
/// refused where the damping matrix cannot be carried (a pROM build).
#[test]
fn dampers_run_in_statics_and_frf_and_are_refused_by_a_prom() {
    let dampers = "CDAMP1,201,8,1,0,2,0\nPDAMP,8,0.5\nCDAMP2,202,0.1,10,1\nCDAMP3,203,8,1,2\nCDAMP4,204,0.2,3\nGRID,11,,1.,0.,0.,,23456\nCVISC,205,9,10,11\nPVISC,9,0.3,0.1\nCELAS2,206,1.0,11,1\n";
    let deck = CHAIN.replace("ENDDATA", &format!("{dampers}ENDDATA"));
    let (file, _dir) = run_to_file(&deck);
    let g = file.group("results/1/statics").expect("statics");
    let u: Vec<f64> = read_dataset(&g, "displacement_scalar");
    assert!((u[1] - 19.0 / 11.0).abs() <= 1e-12, "{u:?}");
    let frf = deck
        .replace("SOL 101", "SOL 108")
        .replace("ENDDATA", "CONM2,301,10,,1.0\nENDDATA");
    let model = build_model(&frf).expect("model");
    let deck_read = |text: &str| {
        let mut file = tempfile::Builder::new().suffix(".bdf").tempfile().unwrap();
        file.write_all(text.as_bytes()).unwrap();
        Deck::read(file.path()).unwrap()
    };
    assert!(paraflex::sequence::driver::runnable(&deck_read(&frf), &model).is_ok());
    let prom = frf.replace("SOL 108", "SOL PROM");
    let model = build_model(&prom).expect("model");
    let deck_read = deck_read(&prom);
    let e = paraflex::sequence::driver::runnable(&deck_read, &model)
        .err()
        .expect("refused")
        .to_string();
    assert!(e.contains("viscous damping elements (CDAMP1 201"), "{e}");
}

/// SLOAD: the chain of [`CHAIN`] with a load of 3 on s2 besides the FORCE: the s2 equation
/// becomes −2 u₁ + 5 u₂ = 3 + 3, so u₂ = 28/11, u₁ = 37/11, and the SPC force at s3 is
/// 3 (1 − u₂) = −51/11. An SLOAD of 3 on GRID 10 instead loads its T1 (Nastran QRG: component
/// T1 of the grid's CD system), as the FORCE does: 4 (u₁₀ − u₁) = 8, 3 u₁ − 2 u₂ = 8, so
/// u₁ = 46/11, u₂ = 25/11, u₁₀ = u₁ + 2 = 68/11. An SLOAD on no point is refused at its card.
#[test]
fn sload_loads_a_scalar_point_or_a_grid_t1() {
    let deck = CHAIN.replace("ENDDATA", "SLOAD,2,2,3.0\nENDDATA");
    let (file, _dir) = run_to_file(&deck);
    let g = file.group("results/1/statics").expect("statics");
    let u: Vec<f64> = read_dataset(&g, "displacement_scalar");
    let expected = [37.0 / 11.0, 28.0 / 11.0, 1.0];
    for (a, b) in u.iter().zip(expected) {
        assert!((a - b).abs() <= 1e-12, "{u:?} vs {expected:?}");
    }
    let q: Vec<f64> = read_dataset(&g, "spc_force_scalar");
    assert!((q[2] + 51.0 / 11.0).abs() <= 1e-12, "{q:?}");
    let (file, _dir) = run_to_file(&CHAIN.replace("ENDDATA", "SLOAD,2,10,3.0\nENDDATA"));
    let g = file.group("results/1/statics").expect("statics");
    let u: Vec<f64> = read_dataset(&g, "displacement_scalar");
    let expected = [46.0 / 11.0, 25.0 / 11.0, 1.0];
    for (a, b) in u.iter().zip(expected) {
        assert!((a - b).abs() <= 1e-12, "{u:?} vs {expected:?}");
    }
    let grid: Vec<f64> = read_dataset(&g, "displacement");
    assert!((grid[0] - 68.0 / 11.0).abs() <= 1e-12, "{grid:?}");
    let e = build_model(&CHAIN.replace("ENDDATA", "SLOAD,2,33,3.0\nENDDATA"))
        .unwrap_err()
        .join("\n");
    assert!(
        e.contains("SLOAD 2") && e.contains("S1 = 33 does not exist"),
        "{e}"
    );
}
