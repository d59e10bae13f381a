//! The deck reader against committed decks and small hand-written ones (DESIGN.md §3).
//!
//! - Conformance: `decks/conformance/<model>_{small,large,free}.bdf` are one model written by
//!   pyNastran in the three field formats; read, they must give the same typed cards, field by
//!   field (positions aside).
//! - Conventions: INCLUDE relative to the including file, Nastran real shorthand, tabs, large
//!   fields with `*` continuations, free-field continuations, case-insensitive names, comments
//!   anywhere, and what executive and case control record.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use paraflex::card_values::ShellOrientation;
use paraflex::deck::cards::BulkData;
use paraflex::deck::{Deck, Loc, Solution};

// ---------------------------------------------------------------------------------------------
// helpers

fn conformance(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("decks/conformance")
        .join(name)
}

fn read(path: &Path) -> Deck {
    Deck::read(path).unwrap_or_else(|e| panic!("{} should read cleanly:\n{e}", path.display()))
}

/// Write `files` (relative path, text) into a fresh directory and read the first one.
fn read_files(
    files: &[(&str, &str)],
) -> (tempfile::TempDir, Result<Deck, paraflex::deck::DeckErrors>) {
    let dir = tempfile::tempdir().unwrap();
    for (name, text) in files {
        let path = dir.path().join(name);
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(path, text).unwrap();
    }
    let deck = Deck::read(&dir.path().join(files[0].0));
    (dir, deck)
}

/// Read a one-file deck that must be clean.
fn read_text(text: &str) -> Deck {
    let (_dir, deck) = read_files(&[("deck.dat", text)]);
    deck.unwrap_or_else(|e| panic!("deck should read cleanly:\n{e}\n--- deck ---\n{text}"))
}

/// Every position in `bulk` replaced by one dummy position, so that the same cards read from
/// differently formatted files compare equal.
fn without_locs(bulk: &BulkData) -> BulkData {
    let dummy = Loc {
        file: Arc::from(Path::new("-")),
        line: 0,
    };
    let mut b = bulk.clone();
    macro_rules! clear {
        ($($field:ident),* $(,)?) => { $( for card in &mut b.$field { card.loc = dummy.clone(); } )* };
    }
    clear!(
        grids, coords, cquad4, ctria3, chexa, cpenta, ctetra, celas1, celas2, conm2, rbe2, rbe3,
        mat1, mat8, pshell, pcomp, psolid, pelas, spc, spc1, spcadd, aset1, forces, grav, load,
        eigrl, freq, tstep, tload, rload, darea, tabled, tabled4, dload, params, desvar, ddval,
        pmpar, pmor, pval, sensors, tablef, tinteg,
    );
    b
}

/// Compare two bulk sections card kind by card kind, with a readable message on the first
/// difference of each kind.
fn assert_same_bulk(a: &BulkData, b: &BulkData, what: &str) {
    let (a, b) = (without_locs(a), without_locs(b));
    let mut diffs = Vec::new();
    macro_rules! compare {
        ($($field:ident),* $(,)?) => { $(
            if a.$field.len() != b.$field.len() {
                diffs.push(format!("{}: {} vs {} cards", stringify!($field), a.$field.len(), b.$field.len()));
            } else if let Some((x, y)) = a.$field.iter().zip(&b.$field).find(|(x, y)| x != y) {
                diffs.push(format!("{}: first difference\n  {x:?}\n  {y:?}", stringify!($field)));
            }
        )* };
    }
    compare!(
        grids, coords, cquad4, ctria3, chexa, cpenta, ctetra, celas1, celas2, conm2, rbe2, rbe3,
        mat1, mat8, pshell, pcomp, psolid, pelas, spc, spc1, spcadd, aset1, forces, grav, load,
        eigrl, freq, tstep, tload, rload, darea, tabled, tabled4, dload, params, desvar, ddval,
        pmpar, pmor, pval, sensors, tablef, tinteg,
    );
    assert!(diffs.is_empty(), "{what}:\n{}", diffs.join("\n"));
}

fn card_count(b: &BulkData) -> usize {
    b.grids.len()
        + b.coords.len()
        + b.cquad4.len()
        + b.ctria3.len()
        + b.chexa.len()
        + b.cpenta.len()
        + b.ctetra.len()
}

// ---------------------------------------------------------------------------------------------
// conformance decks: small, large and free field give the same cards

/// Models whose three files carry exactly the same values.
const EXACT_MODELS: &[&str] = &[
    "mixed",
    "pcomp_plate",
    "plate_pshell",
    "solid_hexa",
    "solid_tetra",
];

#[test]
fn small_large_and_free_field_decks_give_identical_bulk_data() {
    for model in EXACT_MODELS {
        let small = read(&conformance(&format!("{model}_small.bdf")));
        assert!(card_count(&small.bulk) > 0, "{model}: no cards read");
        for format in ["large", "free"] {
            let other = read(&conformance(&format!("{model}_{format}.bdf")));
            assert_same_bulk(
                &small.bulk,
                &other.bulk,
                &format!("{model}: small vs {format}"),
            );
            assert_eq!(
                small.executive.sol, other.executive.sol,
                "{model} {format}: SOL"
            );
            assert_eq!(
                small.case.global.method, other.case.global.method,
                "{model} {format}: METHOD"
            );
            assert_eq!(
                small.case.global.spc, other.case.global.spc,
                "{model} {format}: SPC"
            );
        }
    }
}

/// Points equal within `1e-6` of their magnitude (at least 1): what survives rounding a
/// coordinate to an 8-column small field (about 7 significant digits).
fn assert_points_close(p: [f64; 3], q: [f64; 3], what: &str) {
    let scale = p.iter().map(|v| v.abs()).fold(1.0, f64::max);
    for (x, y) in p.iter().zip(&q) {
        assert!((x - y).abs() <= 1e-6 * scale, "{what}: {p:?} vs {q:?}");
    }
}

/// meshio writes grid coordinates rounded to the field width: 8 columns in its small- and
/// free-field files (`0.285714`), 16 in its large-field (`default`) files (`0.285714285714`).
/// So grids are compared within the small-field rounding, and everything else exactly.
fn assert_same_mesh(a: &BulkData, b: &BulkData, what: &str) {
    assert_eq!(a.grids.len(), b.grids.len(), "{what}: grids");
    for (g, h) in a.grids.iter().zip(&b.grids) {
        assert_eq!((g.id, g.cp, g.cd, g.ps), (h.id, h.cp, h.cd, h.ps), "{what}");
        assert_points_close(g.x, h.x, &format!("{what}: GRID {}", g.id));
    }
    let (mut a, mut b) = (a.clone(), b.clone());
    a.grids.clear();
    b.grids.clear();
    assert_same_bulk(&a, &b, what);
}

#[test]
fn meshio_decks_agree_across_formats() {
    let tet = read(&conformance("meshio_box_tet_small.bdf"));
    assert!(!tet.bulk.ctetra.is_empty());
    for other in ["meshio_box_tet_free.bdf", "meshio_box_tet_default.bdf"] {
        assert_same_mesh(
            &tet.bulk,
            &read(&conformance(other)).bulk,
            &format!("meshio_box_tet_small vs {other}"),
        );
    }
    let hex = read(&conformance("meshio_box_hex_default.bdf"));
    assert!(!hex.bulk.chexa.is_empty());
    assert_same_mesh(
        &hex.bulk,
        &read(&conformance("meshio_box_hex_large.bdf")).bulk,
        "meshio_box_hex default vs large",
    );
}

/// `conm2_coords`: everything is identical except the CORD2R points. pyNastran writes the
/// CORD2R A/B/C points with full precision in the large-field file (16 columns,
/// `-.0211395339889`) but has to round them to 8 columns in the small- and free-field files
/// (`-.02114`), so the three files genuinely carry different numbers. The rounding is ~7
/// significant digits of the largest coordinate of the point, so the points are compared with
/// a tolerance of 1e-6 relative to the point's magnitude (not to each component, which for a
/// small component like -0.0211 differs by ~2e-5 relatively).
#[test]
fn conm2_coords_decks_agree_up_to_cord2r_rounding() {
    let small = read(&conformance("conm2_coords_small.bdf"));
    assert!(!small.bulk.conm2.is_empty() && !small.bulk.coords.is_empty());
    for format in ["large", "free"] {
        let other = read(&conformance(&format!("conm2_coords_{format}.bdf")));
        let what = format!("conm2_coords: small vs {format}");
        assert_eq!(
            small.bulk.coords.len(),
            other.bulk.coords.len(),
            "{what}: coordinate systems"
        );
        for (a, b) in small.bulk.coords.iter().zip(&other.bulk.coords) {
            assert_eq!((a.id, a.kind, a.rid), (b.id, b.kind, b.rid), "{what}");
            for (p, q) in [(a.a, b.a), (a.b, b.b), (a.c, b.c)] {
                assert_points_close(p, q, &format!("{what}: CORD {}", a.id));
            }
        }
        // The rest must be identical: compare with the coordinate systems taken out.
        let (mut s, mut o) = ((*small.bulk).clone(), (*other.bulk).clone());
        s.coords.clear();
        o.coords.clear();
        assert_same_bulk(&s, &o, &what);
    }
}

// ---------------------------------------------------------------------------------------------
// field formats and conventions

const HEAD: &str = "SOL 103\nCEND\nBEGIN BULK\n";

#[test]
fn include_paths_are_relative_to_the_including_file_and_nest() {
    let (dir, deck) = read_files(&[
        (
            "main.dat",
            "SOL 101\nCEND\nBEGIN BULK\nINCLUDE 'mesh/part.bdf'\nGRID    9               9.      0.      0.\nENDDATA\n",
        ),
        // part.bdf is in mesh/: 'sub/grids.bdf' is mesh/sub/grids.bdf, '../props.bdf' is next to main.dat.
        (
            "mesh/part.bdf",
            "$ part\nINCLUDE 'sub/grids.bdf'\ninclude '../props.bdf'\n",
        ),
        (
            "mesh/sub/grids.bdf",
            "GRID    1               0.      0.      0.\n$\nGRID    2               1.      0.      0.\n",
        ),
        (
            "props.bdf",
            "MAT1    1       7.+10           .3      2700.\n",
        ),
    ]);
    let deck = deck.unwrap_or_else(|e| panic!("{e}"));
    let ids: Vec<u32> = deck.bulk.grids.iter().map(|g| g.id).collect();
    assert_eq!(ids, [1, 2, 9], "grids in reading order");
    assert_eq!(deck.bulk.mat1.len(), 1);
    let names: Vec<String> = deck
        .files
        .iter()
        .map(|p| {
            p.strip_prefix(dir.path())
                .unwrap()
                .to_string_lossy()
                .replace('\\', "/")
        })
        .collect();
    assert_eq!(
        names,
        [
            "main.dat",
            "mesh/part.bdf",
            "mesh/sub/grids.bdf",
            "mesh/../props.bdf"
        ]
    );
    // Positions point into the included file.
    let g2 = &deck.bulk.grids[1];
    assert!(
        g2.loc.file.ends_with("grids.bdf") && g2.loc.line == 3,
        "{}",
        g2.loc
    );
}

#[test]
fn nastran_real_shorthand() {
    let deck = read_text(&format!(
        "{HEAD}GRID    1               1.-3    7.+1    -1.D-3\nGRID    2               .5      -2.5E-1 1.5d+2\nMAT1    1       7.+10           .33     2.7+3\n"
    ));
    assert_eq!(deck.bulk.grids[0].x, [1e-3, 70.0, -1e-3]);
    assert_eq!(deck.bulk.grids[1].x, [0.5, -0.25, 150.0]);
    let m = &deck.bulk.mat1[0];
    assert_eq!((m.e, m.nu, m.rho), (7e10, 0.33, 2700.0));
}

#[test]
fn tab_separated_small_fields_read_like_spaces() {
    let tabs = read_text(&format!(
        "{HEAD}GRID\t1\t\t1.5\t2.5\t3.5\nCQUAD4\t10\t1\t1\t2\t3\t4\n"
    ));
    let spaces = read_text(&format!(
        "{HEAD}GRID    1               1.5     2.5     3.5\nCQUAD4  10      1       1       2       3       4\n"
    ));
    assert_eq!(tabs.bulk.grids[0].x, [1.5, 2.5, 3.5]);
    assert_same_bulk(&tabs.bulk, &spaces.bulk, "tabs vs spaces");
}

#[test]
fn large_field_with_star_continuations() {
    let large = read_text(&format!(
        "{HEAD}\
GRID*                  1                             1.5             2.5\n\
*                    3.5\n\
CHEXA*                 1               1               1               2\n\
*                      3               4               5               6\n\
*                      7               8\n"
    ));
    let small = read_text(&format!(
        "{HEAD}GRID    1               1.5     2.5     3.5\nCHEXA   1       1       1       2       3       4       5       6\n        7       8\n"
    ));
    assert_eq!(large.bulk.chexa[0].nodes, [1, 2, 3, 4, 5, 6, 7, 8]);
    assert_same_bulk(&large.bulk, &small.bulk, "large vs small");
    assert_eq!(
        large.bulk.chexa[0].loc.line, 6,
        "a card's position is its first line"
    );
}

#[test]
fn free_field_continuations() {
    let plus = read_text(&format!("{HEAD}CHEXA,1,1,1,2,3,4,5,6,+C1\n+C1,7,8\n"));
    let blank = read_text(&format!("{HEAD}CHEXA,1,1,1,2,3,4,5,6\n,7,8\n"));
    let small = read_text(&format!(
        "{HEAD}CHEXA   1       1       1       2       3       4       5       6\n+       7       8\n"
    ));
    assert_eq!(plus.bulk.chexa[0].nodes, [1, 2, 3, 4, 5, 6, 7, 8]);
    assert_same_bulk(
        &plus.bulk,
        &blank.bulk,
        "'+' vs blank free-field continuation",
    );
    assert_same_bulk(&plus.bulk, &small.bulk, "free vs small");
}

#[test]
fn names_are_case_insensitive() {
    let lower = read_text(
        "sol semodes\ncend\nmethod = 7\nspc = 1\nbegin bulk\ngrid,1,,0.,0.,0.\ngrid    2               1.      0.      0.\nspc1,1,123456,1\neigrl,7,,,4\nenddata\n",
    );
    let upper = read_text(
        "SOL SEMODES\nCEND\nMETHOD = 7\nSPC = 1\nBEGIN BULK\nGRID,1,,0.,0.,0.\nGRID    2               1.      0.      0.\nSPC1,1,123456,1\nEIGRL,7,,,4\nENDDATA\n",
    );
    assert_same_bulk(&lower.bulk, &upper.bulk, "lower vs upper case");
    assert_eq!(lower.bulk.grids.len(), 2);
    assert_eq!(
        lower.executive.sol.as_ref().map(|s| s.0),
        Some(Solution::Modal)
    );
    assert_eq!(lower.case.global.method, Some(7));
}

#[test]
fn comments_everywhere() {
    let deck = read_text(
        "$ header comment\n\
         SOL 103 $ modes\n\
         $ between statements\n\
         CEND$ no space before the comment\n\
         $\n\
         METHOD = 1 $ selects EIGRL 1\n\
         BEGIN BULK $ bulk starts\n\
         $ a card with a comment between its lines\n\
         CHEXA   1       1       1       2       3       4       5       6       +C1\n\
         $ inside the card\n\
         +C1     7       8 $ trailing\n\
         GRID,1,,0.,0.,0. $ free-field trailing comment\n\
         EIGRL   1                       6\n\
         ENDDATA $ end\n\
         text after ENDDATA is ignored\n",
    );
    assert_eq!(deck.bulk.chexa[0].nodes, [1, 2, 3, 4, 5, 6, 7, 8]);
    assert_eq!(deck.bulk.grids.len(), 1);
    assert_eq!(deck.bulk.eigrl.len(), 1);
    assert_eq!(deck.case.global.method, Some(1));
    assert_eq!(
        deck.executive.sol.as_ref().map(|s| s.0),
        Some(Solution::Modal)
    );
}

#[test]
fn executive_and_case_control_are_recorded() {
    let deck = read_text(
        "ID PARAFLEX, TEST\nTIME 10\nSOL 101\nCEND\nTITLE = a title, with = signs\nSPC = 1\nSET 5 = 1, 3 THRU 6,\n  10\n\
         DISP(PRINT) = 5\nSUBCASE 1\n  LOAD = 2\nSUBCASE 2\n  LOAD = 3\n  SPC = 4\nBEGIN BULK\nGRID,1,,0.,0.,0.\nENDDATA\n",
    );
    assert!(deck.has_control_sections);
    assert_eq!(
        deck.executive.sol.as_ref().map(|s| s.0),
        Some(Solution::Statics)
    );
    assert_eq!(deck.executive.recorded.len(), 2);
    assert_eq!(
        deck.case.global.title.as_deref(),
        Some("a title, with = signs")
    );
    assert_eq!(deck.case.sets.len(), 1);
    assert_eq!(deck.case.sets[0].ids, [1, 3, 4, 5, 6, 10]);
    let subcases = deck.case.subcases();
    let summary: Vec<(u32, Option<u32>, Option<u32>)> =
        subcases.iter().map(|s| (s.id, s.spc, s.load)).collect();
    assert_eq!(
        summary,
        [(1, Some(1), Some(2)), (2, Some(4), Some(3))],
        "SPC inherited from above the first SUBCASE"
    );
    assert!(
        subcases
            .iter()
            .all(|s| s.outputs.iter().any(|o| o.name == "DISPLACEMENT"))
    );
}

#[test]
fn bulk_only_file_reads_with_a_warning() {
    let deck = read_text("GRID,1,,0.,0.,0.\nGRID,2,,1.,0.,0.\n");
    assert!(!deck.has_control_sections);
    assert_eq!(deck.bulk.grids.len(), 2);
    assert!(
        deck.warnings
            .iter()
            .any(|w| w.message.contains("bulk data only"))
    );
}

#[test]
fn every_error_is_collected_with_its_position() {
    let (_dir, deck) = read_files(&[(
        "deck.dat",
        "SOL 103\nCEND\nBEGIN BULK\nGRID    1               1       0.      0.\nCQUAD4  10      1.      1       2       3       4\nCGAP    1\n",
    )]);
    let errors = deck.expect_err("three errors").errors;
    let lines: Vec<u32> = errors.iter().map(|e| e.loc.line).collect();
    assert_eq!(lines, [4, 5, 6], "{errors:?}");
    assert_eq!(errors[1].card.as_deref(), Some("CQUAD4 10"));
    assert_eq!(errors[1].field.as_deref(), Some("field 3 (PID)"));
}

/// A part superelement section may follow case control directly (`BEGIN SUPER = 1` before
/// `BEGIN BULK`, as pyNastran writes them): its cards are read as that part's bulk data (a bad
/// field is reported at its line, not as an unknown case control command), and `BEGIN BULK`
/// returns to the main bulk data.
#[test]
fn begin_super_after_case_control_opens_a_part_section() {
    let (_dir, deck) = read_files(&[(
        "deck.dat",
        "SOL 101\nCEND\nSUBCASE 1\n  LOAD = 2\nBEGIN SUPER=1\nGRID,1,,0.,0.,0.\nGRID,2,,1.,0.,0.,-7\nENDDATA\n",
    )]);
    let errors = deck.expect_err("bad CD").to_string();
    assert!(
        errors.contains("deck.dat:7: GRID 2: field 7 (CD)"),
        "the GRID cards are read as bulk data: {errors}"
    );
    assert!(!errors.contains("case control command"), "{errors}");
    let deck = read_text(
        "SOL 101\nCEND\nBEGIN SUPER=1\nGRID,1,,0.,0.,0.\nBEGIN BULK\nGRID,2,,1.,0.,0.\nENDDATA\n",
    );
    assert_eq!(deck.parts.len(), 1);
    assert_eq!((deck.parts[0].seid, deck.parts[0].bulk.grids.len()), (1, 1));
    assert_eq!(
        deck.bulk.grids.len(),
        1,
        "BEGIN BULK returns to the main section"
    );
}

/// `BEGIN BULK SUPER = n` (the older spelling of `BEGIN SUPER = n`) opens part n's section;
/// a second section of one part, another kind of BEGIN section and a malformed one are errors
/// at their line; SEBULK, SECONCT and SELOC are read with their fields checked; a POINT that
/// no SELOC can use is set aside with a warning, its fields checked.
#[test]
fn part_sections_and_superelement_cards_are_read() {
    let deck = read_text(
        "SOL 101\nCEND\nBEGIN BULK\nGRID,40,,-5.,15.,0.\nSELOC,1,16,13,12,40,50,60\n\
         SEBULK,1,PRIMARY,,MANUAL,2.e-5\nSECONCT,1,0,3.e-5,NO\n,16,40,1,THRU,3,41,THRU,43\n\
         BEGIN BULK SUPER = 1\nGRID,11,,0.,0.,0.\nBEGIN SUPER 2\nGRID,12,,0.,0.,0.\nENDDATA\n",
    );
    let seids: Vec<u32> = deck.parts.iter().map(|p| p.seid).collect();
    assert_eq!(seids, [1, 2]);
    assert_eq!(deck.bulk.seloc[0].pa, [16, 13, 12]);
    let sebulk = &deck.bulk.sebulk[0];
    assert_eq!(
        (sebulk.method, sebulk.tol),
        (paraflex::deck::cards::SeMethod::Manual, 2.0e-5)
    );
    let seconct = &deck.bulk.seconct[0];
    assert_eq!(seconct.pairs, [(16, 40), (1, 41), (2, 42), (3, 43)]);
    assert!(!seconct.check_location);
    let (_dir, bad) = read_files(&[(
        "deck.dat",
        "SOL 101\nCEND\nBEGIN BULK\nPOINT,8,,x\nSECONCT,1,1\n,5,6\nBEGIN SUPER = 1\n\
         BEGIN SUPER = 1\nBEGIN AUXMODEL = 3\nBEGIN SUPER = x\nENDDATA\n",
    )]);
    let errors = bad.expect_err("refused").to_string();
    for text in [
        "deck.dat:4: POINT 8: field 4 (X1)",
        "deck.dat:5: SECONCT 1: field 3 (SEIDB): SEIDB equals SEIDA (1)",
        "deck.dat:8: a second BEGIN SUPER = 1 section",
        "deck.dat:9: 'BEGIN AUXMODEL = 3': paraflex reads the main bulk data section",
        "deck.dat:10: 'BEGIN SUPER = x': expected a part superelement id > 0",
    ] {
        assert!(errors.contains(text), "'{text}' not in:\n{errors}");
    }
    let deck =
        read_text("SOL 101\nCEND\nBEGIN BULK\nGRID,1,,0.,0.,0.\nPOINT,7,,1.,2.,3.\nENDDATA\n");
    assert!(
        deck.warnings.iter().any(|w| w
            .message
            .contains("POINT accepted and ignored (1 card): a POINT is a geometric point")),
        "{:?}",
        deck.warnings
    );
}

/// Cards that cannot change results are read and set aside with one warning per card name that
/// says why; where only some uses are harmless (USET set names, MDLPRM options: OFFDEF = LROFF
/// changes only nonlinear analyses, NOMASS changes the mass; PELAST: TKNID is nonlinear only, TKID
/// changes frequency responses) the others are refused at their field.
#[test]
fn harmless_cards_are_set_aside_with_a_reason_and_the_others_refused() {
    let deck = read_text(
        "SOL 101\nCEND\nLINES = 9999\nBEGIN BULK\nECHOON\nGRID,1,,0.,0.,0.\nGRID,2,,1.,0.,0.\n\
         USET,U2,1,123,2,456\nUSET1,U1,123,1,2\nUSET,U2,2,1\nCBARAO,1,2,FR,0.2,0.4\n\
         PLOTEL,7,1,2\nMAT4,14,8.6\nMDLPRM,HDF5,1,H5MDL,0,OFFDEF,LROFF\nECHOOFF\n\
         DTI,MATALL,1,YIELD,2.417e5,ULTIMATE,2.7595e5\nDVPREL1,10,PSHELL,4,T\n,1,1.\n\
         PBUSH1D,71,3000.,200.,300.\nPELAST,11,,,42\n\
         EPOINT,103,THRU,107\nENDDATA\n",
    );
    let warned = |text: &str| deck.warnings.iter().any(|w| w.message.contains(text));
    for text in [
        "USET accepted and ignored (2 cards): user DOF sets U1–U6",
        "USET1 accepted and ignored (1 card)",
        "CBARAO accepted and ignored",
        "PLOTEL accepted and ignored",
        "MAT4 accepted and ignored",
        "MDLPRM accepted and ignored",
        "ECHOON accepted and ignored",
        "DTI accepted and ignored (1 card): a direct table is data for DMAP modules",
        "case control 'LINES' is accepted and ignored",
        "DVPREL1 accepted and ignored (1 card): Nastran's design model is read by SOL 200 only",
        "PBUSH1D accepted and ignored",
        "PELAST accepted and ignored (1 card): its nonlinear force-deflection table",
        "EPOINT accepted and ignored (1 card): extra points carry no stiffness or mass",
    ] {
        assert!(warned(text), "no warning '{text}' in {:?}", deck.warnings);
    }
    let (_dir, refused) = read_files(&[(
        "deck.dat",
        "SOL 101\nCEND\nBEGIN BULK\nUSET,A,1,123\nMDLPRM,HDF5,1,OFFDEF,NOMASS\nPELAST,12,7\nENDDATA\n",
    )]);
    let message = refused.expect_err("refused").to_string();
    for text in [
        "deck.dat:4: USET: field 2 (SNAME): set A is not supported",
        "deck.dat:5: MDLPRM: field 4 (PARAMi): model parameter OFFDEF is not supported",
        "deck.dat:6: PELAST 12: field 3 (TKID): frequency-dependent stiffness of a PELAS is not supported",
    ] {
        assert!(message.contains(text), "'{text}' not in:\n{message}");
    }
}

/// PCOMPG is a PCOMP with a global ply id per line: the same plies (the second ply's MID
/// defaults to the first's), the ids kept; CQUAD8 and CTRIA6 read their grids, THETA/MCID,
/// ZOFFS and corner thicknesses from their own field positions.
#[test]
fn pcompg_and_quadratic_shell_cards_read_their_fields() {
    let deck = read_text(
        "SOL 103
CEND
BEGIN BULK
PCOMPG  1               .1                                      SYM
        11      1       .001    30.
        12              .002    -45.    YES
PCOMP   2               .1                                      SYM
        1       .001    30.             1       .002    -45.    YES
CQUAD8  5       1       1       2       3       4       5       6
        7       8       .1      .2      .3      .4      7       .05
        1
CTRIA6  6       2       1       2       3       4       5       6
        15.     -.02    1.      2.      3.      1
ENDDATA
",
    );
    let b = &deck.bulk;
    assert_eq!(b.pcomp[0].plies, b.pcomp[1].plies);
    assert_eq!(b.pcomp[0].global_ply_ids, vec![11, 12]);
    assert!(b.pcomp[1].global_ply_ids.is_empty());
    let q = &b.cquad8[0];
    assert_eq!(q.nodes, vec![1, 2, 3, 4, 5, 6, 7, 8]);
    assert_eq!(q.orientation, ShellOrientation::Mcid(7));
    assert_eq!(q.zoffs, 0.05);
    let c = q.corner_thickness.unwrap();
    assert!(c.relative);
    assert_eq!(c.t, [Some(0.1), Some(0.2), Some(0.3), Some(0.4)]);
    let t = &b.ctria6[0];
    assert_eq!((t.id, t.pid), (6, 2));
    assert_eq!(t.nodes, vec![1, 2, 3, 4, 5, 6]);
    assert_eq!(t.orientation, ShellOrientation::Theta(15.0));
    assert_eq!(t.zoffs, -0.02);
    let c = t.corner_thickness.unwrap();
    assert!(c.relative);
    assert_eq!(c.t, [Some(1.0), Some(2.0), Some(3.0), None]);
}

/// CHEXA and CPENTA take their mid-side grids (G9–G20, G7–G15) on continuations, each one
/// blank or not: no mid-side grid is the linear element, any is the quadratic one with 0 for
/// a blank; so does CTETRA.
#[test]
fn quadratic_solids_read_mid_side_grids_blank_or_not() {
    let deck = read_text(&format!(
        "{HEAD}CHEXA,1,1,1,2,3,4,5,6\n,7,8,9,,11,12,13,14\n,15,16,17,18,,20\n\
         CHEXA,2,1,1,2,3,4,5,6\n,7,8\n\
         CPENTA,3,1,1,2,3,4,5,6\n,7,8,9,10,11,12,13,14\n,15\n\
         CPENTA,4,1,1,2,3,4,5,6\n,,,,,,,,14\n"
    ));
    let b = &deck.bulk;
    assert_eq!(
        b.chexa[0].nodes,
        [
            1, 2, 3, 4, 5, 6, 7, 8, 9, 0, 11, 12, 13, 14, 15, 16, 17, 18, 0, 20
        ]
    );
    assert_eq!(b.chexa[1].nodes, [1, 2, 3, 4, 5, 6, 7, 8]);
    assert_eq!(b.cpenta[0].nodes, (1..=15).collect::<Vec<u32>>());
    assert_eq!(
        b.cpenta[1].nodes,
        [1, 2, 3, 4, 5, 6, 0, 0, 0, 0, 0, 0, 0, 14, 0]
    );
    let tetra = read_text(&format!("{HEAD}CTETRA,5,1,1,2,3,4,5,6\n,,8,9,10\n"));
    assert_eq!(tetra.bulk.ctetra[0].nodes, [1, 2, 3, 4, 5, 6, 0, 8, 9, 10]);
}
