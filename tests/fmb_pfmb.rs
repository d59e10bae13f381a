//! The pFMB artifact: every `SOL FMB` run writes its mechanism as `/pfmb`, and a deck with
//! `FMB = 'file.h5'` and no mechanism bulk data runs it (DESIGN.md §11).

mod common;

use std::path::Path;

use common::{root, run_deck};

fn deck(name: &str) -> String {
    std::fs::read_to_string(root().join("decks/fmb").join(name)).expect("deck")
}

/// Builds the strip body's pROM (decks/fmb/strip_body_prom.dat with an axial STRAIN gauge at
/// the root) into a temp directory as `strip_body.h5`.
fn strip_artifact() -> tempfile::TempDir {
    let text = deck("strip_body_prom.dat")
        .replace("ASET1,", "SENSOR,1,ROOTX,STRAIN,1,TOP,1.,0.,0.\nASET1,");
    let (r, dir) = run_deck(&text);
    r.unwrap_or_else(|e| panic!("strip pROM: {e}"));
    std::fs::rename(dir.path().join("out.h5"), dir.path().join("strip_body.h5")).expect("rename");
    dir
}

/// Runs `text` as `name` in `dir`; the output is `dir/<name>.h5`.
fn run_in(dir: &Path, name: &str, text: &str) -> Result<hdf5_metno::File, String> {
    let path = dir.join(name);
    std::fs::write(&path, text).expect("write deck");
    let (r, _model, out) = common::run_deck_file(&path);
    r.map_err(|e| e.to_string())?;
    let h5 = dir.join(format!("{name}.h5"));
    std::fs::rename(out.path().join("out.h5"), &h5).expect("move output");
    Ok(hdf5_metno::File::open(&h5).expect("open"))
}

/// A flexible mechanism using every kind of card the artifact stores: the strip body on a
/// driven revolute at its root, a rigid tip mass fixed to its tip, a point force on the mass
/// from a table, a point spring-damper from the mass to the ground, a joint spring on a second
/// (undriven) revolute of a rigid pendulum and a moment about that revolute from the same
/// table, and one output of each kind.
const MECHANISM: &str = "\
FLEXB,1,STRIP,'strip_body.h5'
RIGIDB,2,TIP,0.01,,0.3,0.015,0.
,1.e-6,0.,1.e-6,0.,0.,1.e-6
RIGIDB,3,ROD,0.1,,0.,0.5,0.25
,1.e-3,0.,1.e-3,0.,0.,1.e-5
MARKER,10,1,14
MARKER,11,1,26
MARKER,20,2,,0.3,0.015,0.
MARKER,21,2,,0.3,0.025,0.
MARKER,30,0,,0.3,0.2,0.
MARKER,40,3,,0.,0.5,0.5
JOINT,1,REV,10,0,0.,1.,0.
JOINT,2,FIX,20,11,0.,0.,1.
JOINT,3,REV,40,0,1.,0.,0.
JDRIVE,1,1,5,0.5
TABLED1,5
,0.,0.,1.,1.,ENDT
MFORCE,1,20,6,0.2,0.,0.,1.
MMOMENT,2,40,6,1.e-3,1.,0.,0.
TABLED1,6
,0.,0.,0.05,1.,ENDT
SPDMP,1,21,30,50.,0.05
JSPRD,1,3,2.,0.01,0.1
MSENSOR,1,TIPZ,POS,,11,0.,0.,1.
MSENSOR,2,TIPAZ,ACCEL,,11,0.,0.,1.
MSENSOR,3,ROOTEPS,STRAIN,1,ROOTX
MSENSOR,4,TIPDEV,DEV,,11
MSENSOR,5,TORQUE,JTORQ,,1
MSENSOR,6,POWER,POWER,,1
MSENSOR,7,WORK,ENERGY,,1
MSENSOR,8,REACT,JFORCE,,3,0.,1.,0.
MSENSOR,9,KE,KE
";

/// The case control both runs share, with PVAL `pval`, and the bulk cards that stay in a deck
/// loading the mechanism.
fn case(pval: u32) -> String {
    format!("TSTEP = 1\nLOAD = 1\nPVAL = {pval}\nSTRREF = INITIAL\n")
}
const KEPT_BULK: &str = "TSTEP,1,60,1.e-3,2\nPVAL,1,STRIP.RHO,2700.\nPVAL,2,STRIP.RHO,2150.\n";

fn full_deck(pval: u32) -> String {
    format!(
        "SOL FMB\nCEND\n{}BEGIN BULK\n{KEPT_BULK}GRAV,1,,9.81,0.,0.,-1.\n{MECHANISM}ENDDATA\n",
        case(pval)
    )
}

fn loading_deck(file: &str, pval: u32, bulk: &str) -> String {
    format!(
        "SOL FMB\nCEND\nFMB = '{file}'\n{}BEGIN BULK\n{KEPT_BULK}{bulk}ENDDATA\n",
        case(pval)
    )
}

/// Every dataset under `group`, recursively, by path.
fn datasets(group: &hdf5_metno::Group, prefix: &str, out: &mut Vec<(String, Vec<f64>)>) {
    for name in group.member_names().unwrap() {
        let path = format!("{prefix}/{name}");
        if let Ok(g) = group.group(&name) {
            datasets(&g, &path, out);
        } else {
            let d = group.dataset(&name).unwrap();
            // numbers as f64 (u32 exactly), strings by their bytes
            let values = d
                .read_raw::<f64>()
                .or_else(|_| {
                    d.read_raw::<u32>()
                        .map(|v| v.into_iter().map(f64::from).collect())
                })
                .or_else(|_| {
                    d.read_raw::<hdf5_metno::types::VarLenUnicode>().map(|v| {
                        v.iter()
                            .flat_map(|s| s.as_bytes().iter().map(|&b| f64::from(b)).chain([-1.0]))
                            .collect()
                    })
                })
                .unwrap();
            out.push((path, values));
        }
    }
}

fn histories(file: &hdf5_metno::File) -> Vec<(String, Vec<f64>)> {
    let mut out = Vec::new();
    datasets(&file.group("results/1/fmb").unwrap(), "", &mut out);
    out
}

/// The mechanism run from its bulk data and from the `/pfmb` of that run gives the same
/// histories bit for bit (the artifact stores every f64 exactly, and the loaded system is
/// built by the same code from the same numbers), at the nominal density and at another PVAL;
/// the loaded run writes the same `/pfmb` again.
#[test]
fn a_mechanism_loaded_from_its_pfmb_reproduces_the_bulk_data_run_exactly() {
    let dir = strip_artifact();
    let source = run_in(dir.path(), "source.dat", &full_deck(1)).expect("bulk-data run");
    let pfmb = source.group("pfmb").unwrap();
    let params: Vec<String> = pfmb
        .attr("params")
        .unwrap()
        .read_raw::<hdf5_metno::types::VarLenUnicode>()
        .unwrap()
        .iter()
        .map(|s| s.to_string())
        .collect();
    assert_eq!(params, vec!["STRIP.RHO".to_string()]);
    let low: Vec<f64> = pfmb.attr("low").unwrap().read_raw().unwrap();
    assert_eq!(low, vec![2000.0]);
    for pval in [1, 2] {
        let bulk = if pval == 1 {
            source.clone()
        } else {
            run_in(dir.path(), "source2.dat", &full_deck(2)).expect("bulk-data run at PVAL 2")
        };
        let loaded = run_in(
            dir.path(),
            &format!("loaded{pval}.dat"),
            &loading_deck("source.dat.h5", pval, ""),
        )
        .expect("run from /pfmb");
        let (want, got) = (histories(&bulk), histories(&loaded));
        assert_eq!(
            want.iter().map(|(n, _)| n).collect::<Vec<_>>(),
            got.iter().map(|(n, _)| n).collect::<Vec<_>>()
        );
        assert!(
            want.iter()
                .any(|(n, v)| n == "/sensors/ROOTEPS" && v.iter().any(|x| *x != 0.0))
        );
        for ((name, a), (_, b)) in want.iter().zip(&got) {
            let same =
                a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits());
            assert!(same, "PVAL {pval}: {name} differs");
        }
        let mut again = Vec::new();
        datasets(&loaded.group("pfmb").unwrap(), "", &mut again);
        let mut first = Vec::new();
        datasets(&pfmb, "", &mut first);
        // the same numbers; only the bodies' source paths name the pFMB file instead
        assert_eq!(again.len(), first.len());
        for ((name, a), (other, b)) in again.iter().zip(&first) {
            assert_eq!(name, other);
            let same = a
                .iter()
                .map(|x| x.to_bits())
                .eq(b.iter().map(|x| x.to_bits()));
            assert!(
                same || name == "/bodies/source",
                "the loaded run's /pfmb{name} differs"
            );
        }
    }
}

/// Bad input of `FMB =`: a missing file, a file without `/pfmb`, another layout version, a
/// deck that also has mechanism bulk data, and a PVAL name that is no BODY.PMPAR of the
/// loaded mechanism: each an error naming the FMB statement's line (or the PVAL card's).
#[test]
fn fmb_statement_errors_name_the_line_and_the_cause() {
    let dir = strip_artifact();
    run_in(dir.path(), "source.dat", &full_deck(1)).expect("bulk-data run");
    let line = 3; // FMB = is the third line of loading_deck
    let e = run_in(dir.path(), "a.dat", &loading_deck("nowhere.h5", 1, "")).unwrap_err();
    assert!(
        e.contains(&format!("a.dat:{line}: FMB = 'nowhere.h5'")),
        "{e}"
    );
    assert!(e.contains("nowhere.h5"), "{e}");
    let e = run_in(dir.path(), "b.dat", &loading_deck("strip_body.h5", 1, "")).unwrap_err();
    assert!(
        e.contains(&format!("b.dat:{line}: FMB = 'strip_body.h5'"))
            && e.contains("no /pfmb group (was it written by a SOL FMB run?)"),
        "{e}"
    );
    let old = dir.path().join("old.h5");
    std::fs::copy(dir.path().join("source.dat.h5"), &old).unwrap();
    {
        let f = hdf5_metno::File::open_rw(&old).unwrap();
        let g = f.group("pfmb").unwrap();
        g.delete_attr("layout_version").unwrap();
        g.new_attr::<i64>()
            .create("layout_version")
            .unwrap()
            .write_scalar(&99i64)
            .unwrap();
    }
    let e = run_in(dir.path(), "c.dat", &loading_deck("old.h5", 1, "")).unwrap_err();
    assert!(
        e.contains(&format!(
            "pFMB layout is version 99, this paraflex reads version {}",
            paraflex::io::PFMB_VERSION
        )),
        "{e}"
    );
    let both = full_deck(1).replace("CEND\n", "CEND\nFMB = 'source.dat.h5'\n");
    let e = run_in(dir.path(), "d.dat", &both).unwrap_err();
    assert!(
        e.contains(&format!(
            "d.dat:{line}: FMB = 'source.dat.h5' loads a mechanism, and the deck has its own"
        )),
        "{e}"
    );
    let unknown = loading_deck("source.dat.h5", 3, "PVAL,3,STRIP.E,7.e10\n");
    let e = run_in(dir.path(), "e.dat", &unknown).unwrap_err();
    assert!(
        e.contains("PVAL 3: STRIP.E is not BODY.PMPAR of this mechanism (parameters: STRIP.RHO)"),
        "{e}"
    );
    let pval_line = 1 + unknown
        .lines()
        .position(|l| l.starts_with("PVAL,3"))
        .unwrap();
    assert!(e.contains(&format!("e.dat:{pval_line}: PVAL 3")), "{e}");
}
