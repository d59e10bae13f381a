//! Rods and beams (CROD, CONROD, CTUBE, CBAR, CBEAM) against closed forms; references and
//! tolerances in reference/analytic/line_elements.json.

mod common;
use common::{read_dataset, run_deck, run_to_file};

use std::io::Write;

use assert_cmd::cargo::cargo_bin_cmd;
use paraflex::deck::Deck;
use paraflex::model::Model;
use paraflex::sequence::modal::ModalSummary;

const E: f64 = 2.1e11;
const NU: f64 = 0.3;
const RHO: f64 = 7800.0;

fn reference() -> serde_json::Value {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/reference/analytic/line_elements.json"
    );
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

fn beta_l(ends: &str) -> Vec<f64> {
    reference()["beta_l"][ends]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect()
}

/// Grids 1…n+1 from `start` along `dir` (unit) over length `l`, with a CD and a PS code.
fn grids_in(n: usize, start: [f64; 3], dir: [f64; 3], l: f64, cd: &str, ps: &str) -> String {
    (0..=n)
        .map(|i| {
            let t = l * i as f64 / n as f64;
            let p: Vec<f64> = (0..3).map(|c| start[c] + t * dir[c]).collect();
            format!(
                "GRID,{},,{:?},{:?},{:?},{cd},{ps}\n",
                i + 1,
                p[0],
                p[1],
                p[2]
            )
        })
        .collect()
}

/// [`grids_in`] the basic system.
fn grids(n: usize, start: [f64; 3], dir: [f64; 3], l: f64, ps: &str) -> String {
    grids_in(n, start, dir, l, "", ps)
}

fn statics(bulk: &str) -> Vec<f64> {
    let deck = format!(
        "SOL 101\nCEND\nSUBCASE 1\n  SPC = 1\n  LOAD = 2\n  DISPLACEMENT = ALL\nBEGIN BULK\n{bulk}MAT1,1,{E:e},,{NU:?},{RHO:?}\nSPC1,1,123456,1\nENDDATA\n"
    );
    let (file, _dir) = run_to_file(&deck);
    read_dataset::<f64>(&file.group("results/1/statics").unwrap(), "displacement")
}

fn close(got: f64, want: f64, tol: f64) {
    assert!(
        (got - want).abs() <= tol * want.abs(),
        "{got:e} vs {want:e} (tolerance {tol:e} relative)"
    );
}

/// Axial force P and torsion moment T at the tip of a 4-element rod along an oblique axis:
/// u = P L/(E A), φ = T L/(G J), for CROD/PROD, CONROD and CTUBE/PTUBE. The grids' displacement
/// system (CD 5) has its x axis along the rod, so PS = 2356 removes the DOFs a rod leaves free.
#[test]
fn rods_stretch_and_twist_like_pl_over_ea_and_tl_over_gj() {
    let d = [1.0 / 3.0, 2.0 / 3.0, 2.0 / 3.0];
    let (l, p, t) = (1.5, 2.0e3, 40.0);
    let g = E / (2.0 * (1.0 + NU));
    let (od, wall): (f64, f64) = (0.03, 0.004);
    let ri = od / 2.0 - wall;
    let tube_a = std::f64::consts::PI * ((od / 2.0).powi(2) - ri * ri);
    let tube_j = std::f64::consts::PI * ((od / 2.0).powi(4) - ri.powi(4)) / 2.0;
    let cases = [
        ("PROD,10,1,4.e-4,3.e-8\n", "CROD", 4.0e-4, 3.0e-8),
        ("", "CONROD", 4.0e-4, 3.0e-8),
        ("PTUBE,10,1,0.03,0.004\n", "CTUBE", tube_a, tube_j),
    ];
    for (property, card, a, j) in cases {
        let elements: String = (1..=4)
            .map(|i| match card {
                "CONROD" => format!("CONROD,{i},{i},{},1,4.e-4,3.e-8\n", i + 1),
                _ => format!("{card},{i},10,{i},{}\n", i + 1),
            })
            .collect();
        let load = format!(
            "FORCE,2,5,,{p:?},{:?},{:?},{:?}\nMOMENT,2,5,,{t:?},{:?},{:?},{:?}\n",
            d[0], d[1], d[2], d[0], d[1], d[2]
        );
        let frame = "CORD2R,5,,0.,0.,0.,2.,-1.,0.\n,1.,2.,2.\n";
        let u = statics(&format!(
            "{frame}{}{elements}{property}{load}",
            grids_in(4, [0.2, 0.1, -0.3], d, l, "5", "2356")
        ));
        let tip = &u[4 * 6..5 * 6];
        let along = |o: usize| (0..3).map(|c| tip[o + c] * d[c]).sum::<f64>();
        close(along(0), p * l / (E * a), 1e-9);
        close(along(3), t * l / (g * j), 1e-9);
    }
}

/// A cantilever along an oblique axis with an oblique orientation vector: tip loads along the
/// element y and z axes bend it by P L³/(3 E I1) and P L³/(3 E I2) (CBAR/PBAR, CBEAM/PBEAM
/// with K1 = K2 = 0: no shear flexibility); CBEAM with its default K = 1 adds P L/(G A).
#[test]
fn oblique_cantilever_bends_like_pl3_over_3ei_in_both_planes() {
    let x = [2.0 / 3.0, -1.0 / 3.0, 2.0 / 3.0];
    let v = [0.3, 1.0, 0.2];
    // element axes: z = x × v / |x × v|, y = z × x
    let cross = |a: [f64; 3], b: [f64; 3]| {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    };
    let z0 = cross(x, v);
    let n = z0.iter().map(|c| c * c).sum::<f64>().sqrt();
    let z = z0.map(|c| c / n);
    let y = cross(z, x);
    let (l, p, a, i1, i2) = (2.0, 150.0, 6.0e-4, 2.0e-8, 4.5e-8);
    let g = E / (2.0 * (1.0 + NU));
    let properties = [
        (
            "CBAR",
            format!("PBAR,10,1,{a:e},{i1:e},{i2:e},1.e-8\n"),
            0.0,
        ),
        (
            "CBEAM",
            format!(
                "PBEAM,10,1,{a:e},{i1:e},{i2:e},,1.e-8\n,0.,0.,0.,0.,0.,0.,0.,0.\n,NO,1.\n,0.,0.\n"
            ),
            0.0,
        ),
        (
            "CBEAM",
            format!("PBEAM,10,1,{a:e},{i1:e},{i2:e},,1.e-8\n"),
            1.0,
        ),
    ];
    for (card, property, shear_k) in properties {
        let elements: String = (1..=10)
            .map(|i| {
                format!(
                    "{card},{i},10,{i},{},{:?},{:?},{:?}\n",
                    i + 1,
                    v[0],
                    v[1],
                    v[2]
                )
            })
            .collect();
        for (dir, inertia) in [(y, i1), (z, i2)] {
            let load = format!("FORCE,2,11,,{p:?},{:?},{:?},{:?}\n", dir[0], dir[1], dir[2]);
            let u = statics(&format!(
                "{}{elements}{property}{load}",
                grids(10, [0.0; 3], x, l, "")
            ));
            let tip: f64 = (0..3).map(|c| u[10 * 6 + c] * dir[c]).sum();
            let shear = if shear_k > 0.0 {
                p * l / (shear_k * g * a)
            } else {
                0.0
            };
            close(tip, p * l.powi(3) / (3.0 * E * inertia) + shear, 1e-9);
        }
    }
}

/// Offsets: grids on y = 0, the bar axis on y = 0.1 (WA = WB = (0, 0.1, 0)), clamped at grid 1.
/// An axial force P at grid 2 acts 0.1 below the axis point B: the rigid link carries P and the
/// moment M_z = 0.1 P to B, so θ_z = M_z L/(E I) and B moves by P L/(E A) along x; the grid, 0.1
/// below B, moves by that plus θ_z · 0.1 along x.
#[test]
fn offsets_carry_the_load_through_rigid_links() {
    let (l, p, a, i) = (1.0, 500.0, 1.0e-4, 1.0e-8);
    let bulk = format!(
        "{}CBAR,1,10,1,2,0.,0.,1.\n,,,0.,0.1,0.,0.,0.1,0.\nPBAR,10,1,{a:e},{i:e},{i:e},1.e-8\nFORCE,2,2,,{p:?},1.,0.,0.\n",
        grids(1, [0.0; 3], [1.0, 0.0, 0.0], l, "")
    );
    let u = statics(&bulk);
    let rz = 0.1 * p * l / (E * i);
    // the bar is a mesh block of the output (a 2-node Polyline cell in the XDMF file)
    let deck = format!(
        "SOL 101\nCEND\nSUBCASE 1\n  SPC = 1\n  LOAD = 2\nBEGIN BULK\n{bulk}MAT1,1,{E:e},,{NU:?},{RHO:?}\nSPC1,1,123456,1\nENDDATA\n"
    );
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("deck.dat"), deck).unwrap();
    let out = cargo_bin_cmd!("paraflex")
        .current_dir(dir.path())
        .args(["run", "deck.dat", "-o", "out.h5"])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let file = hdf5_metno::File::open(dir.path().join("out.h5")).unwrap();
    let ids: Vec<u32> = read_dataset(&file.group("model/elements/CBAR").unwrap(), "ids");
    assert_eq!(ids, [1]);
    let xdmf = std::fs::read_to_string(dir.path().join("out.xdmf")).unwrap();
    assert!(xdmf.contains("Polyline"), "{xdmf}");
    close(u[6 + 5], rz, 1e-9);
    close(u[6], p * l / (E * a) + 0.1 * rz, 1e-9);
    close(u[6 + 1], 0.1 * p * l * l / (2.0 * E * i), 1e-9);
}

fn modes(bulk: &str, nd: usize, coupled: bool) -> Vec<f64> {
    let coupmass = if coupled { "PARAM,COUPMASS,1\n" } else { "" };
    let spc = if bulk.contains("SPC1") {
        "SPC = 1\n"
    } else {
        ""
    };
    let deck = format!(
        "SOL 103\nCEND\nMETHOD = 1\n{spc}BEGIN BULK\n{coupmass}{bulk}MAT1,1,{E:e},,{NU:?},{RHO:?}\nEIGRL,1,,,{nd}\nENDDATA\n"
    );
    let (r, _dir) = run_deck(&deck);
    let s = r.unwrap_or_else(|e| panic!("{e}"));
    let m = s.subcases[0].result::<ModalSummary>().expect("modal");
    m.frequencies_hz.clone()
}

/// Euler–Bernoulli frequencies of a 40-element beam in the x–y plane (plane 1; T3 R1 R2
/// fixed on every grid) clamped-free and free-free, lumped and consistent mass:
/// f_n = (β_n L)²/(2π L²) √(E I/(ρ A)).
#[test]
fn beam_frequencies_match_euler_bernoulli_for_both_mass_forms() {
    let (l, b, h): (f64, f64, f64) = (1.0, 0.01, 0.012);
    let (a, i1) = (b * h, b * h.powi(3) / 12.0);
    let scale = (E * i1 / (RHO * a)).sqrt() / (2.0 * std::f64::consts::PI * l * l);
    let n = 40;
    let elements: String = (1..=n)
        .map(|i| format!("CBAR,{i},10,{i},{},0.,1.,0.\n", i + 1))
        .collect();
    // PBARL BAR: DIM1 along the element z, DIM2 along y (plane 1): I1 = DIM1·DIM2³/12
    let property = format!("PBARL,10,1,,BAR\n,{b:?},{h:?}\n");
    let mesh = grids(n, [0.0; 3], [1.0, 0.0, 0.0], l, "345");
    for (coupled, tol) in [(true, 2e-4), (false, 5e-3)] {
        let clamped = modes(
            &format!("{mesh}{elements}{property}SPC1,1,126,1\n"),
            3,
            coupled,
        );
        for (f, bl) in clamped.iter().zip(beta_l("clamped_free")) {
            close(*f, bl * bl * scale, tol);
        }
        // free-free: three rigid modes (T1, T2, R3) first
        let free = modes(&format!("{mesh}{elements}{property}"), 6, coupled);
        for (f, bl) in free[3..].iter().zip(beta_l("free_free")) {
            close(*f, bl * bl * scale, tol);
        }
    }
}

/// Mass properties: (ρ A + NSM) L of every line element, A of PTUBE and PBARL from the shape.
#[test]
fn mass_properties_include_rods_and_beams() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("deck.dat");
    let bulk = "GRID,1,,0.,0.,0.\nGRID,2,,2.,0.,0.\nGRID,3,,2.,1.,0.\n\
        CTUBE,1,10,1,2\nPTUBE,10,1,0.05,0.005,0.2\n\
        CBAR,2,11,2,3,0.,0.,1.\nPBARL,11,1,,I\n,0.1,0.05,0.06,0.004,0.006,0.008,0.1\n\
        CONROD,3,1,3,1,2.e-4,,,0.05\nMAT1,1,2.1e11,,0.3,7800.\n";
    std::fs::File::create(&path)
        .and_then(|mut f| {
            f.write_all(format!("SOL 101\nCEND\nBEGIN BULK\n{bulk}ENDDATA\n").as_bytes())
        })
        .unwrap();
    let model = Model::build(&Deck::read(&path).unwrap()).unwrap();
    let pi = std::f64::consts::PI;
    let tube = pi * (0.025f64.powi(2) - 0.02f64.powi(2));
    let i_area = 0.05 * 0.006 + 0.06 * 0.008 + 0.004 * (0.1 - 0.014);
    let diagonal = 5.0f64.sqrt();
    let masses = [
        (RHO * tube + 0.2) * 2.0,
        (RHO * i_area + 0.1) * 1.0,
        (RHO * 2.0e-4 + 0.05) * diagonal,
    ];
    let points = [[1.0, 0.0, 0.0], [2.0, 0.5, 0.0], [1.0, 0.5, 0.0]];
    let total: f64 = masses.iter().sum();
    let mp = model.mass_properties();
    close(mp.mass, total, 1e-12);
    for c in 0..3 {
        let cg: f64 = masses
            .iter()
            .zip(points)
            .map(|(m, p)| m * p[c])
            .sum::<f64>()
            / total;
        assert!((mp.cg[c] - cg).abs() < 1e-12, "{:?}", mp.cg);
    }
}

/// Bad line-element input: `paraflex check` names file:line, card and field.
#[test]
fn bad_line_elements_are_reported_with_card_and_field() {
    let cases = [
        (
            "GRID,1,,0.,0.,0.\nGRID,2,,0.,0.,0.\nCBAR,1,10,1,2,0.,1.,0.\nPBAR,10,1,1.e-4,1.e-8,1.e-8\n",
            "deck.dat:6: CBAR 1: field 5 (GB): zero length",
        ),
        (
            "GRID,1,,0.,0.,0.\nGRID,2,,1.,1.,0.\nCBAR,1,10,1,2,2.,2.,0.\nPBAR,10,1,1.e-4,1.e-8,1.e-8\n",
            "deck.dat:6: CBAR 1: field 6 (X1/G0): the orientation vector is parallel",
        ),
        (
            "GRID,1,,0.,0.,0.\nGRID,2,,1.,0.,0.\nCBEAM,1,10,1,2,0.,1.,0.\n",
            "deck.dat:6: CBEAM 1: PID = 10 does not exist (no PBEAM or PBEAML 10)",
        ),
        (
            "GRID,1,,0.,0.,0.\nGRID,2,,1.,0.,0.\nCBAR,1,10,1,2,0.,1.,0.\nPBARL,10,1,,ZED\n,1.,2.\n",
            "deck.dat:7: PBARL 10: field 5 (TYPE): TYPE = ZED is not a shape",
        ),
        (
            "GRID,1,,0.,0.,0.\nGRID,2,,1.,0.,0.\nCBAR,1,10,1,2,0.,1.,0.\nPBARL,10,1,,HAT\n,1.,2.,0.1,0.1\n",
            "deck.dat:7: PBARL 10: field 5 (TYPE): TYPE = HAT is not supported",
        ),
        (
            "GRID,1,,0.,0.,0.\nGRID,2,,1.,0.,0.\nCTUBE,1,10,1,2\nPTUBE,10,1,0.1,0.01,,0.2\n",
            "deck.dat:7: PTUBE 10: field 7 (OD2): a tapered tube",
        ),
        (
            "GRID,1,,0.,0.,0.\nGRID,2,,1.,0.,0.\nCBAR,1,10,1,2\nPBAR,10,1,1.e-4,1.e-8,1.e-8\n",
            "deck.dat:6: CBAR 1: field 6 (X1/G0): give the orientation vector",
        ),
    ];
    for (bulk, expected) in cases {
        check_reports(
            &format!("SOL 101\nCEND\nBEGIN BULK\n{bulk}MAT1,1,2.1e11,,0.3\nENDDATA\n"),
            expected,
        );
    }
}

/// `paraflex check` on `text` (as deck.dat) fails with exit 2 and a line containing `expected`.
fn check_reports(text: &str, expected: &str) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("deck.dat");
    std::fs::write(&path, text).unwrap();
    let out = cargo_bin_cmd!("paraflex")
        .arg("check")
        .arg(&path)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.lines().any(|l| l.contains(expected)),
        "expected '{expected}' in:\n{stderr}"
    );
}

/// A frame of a CBAR, a CROD, a CBEAM (no shear flexibility) and a warped CSHEAR on one MAT1
/// with PMPARs E, NU and RHO: the assembled affine K(p), M(p) equal the operators of the deck
/// with the MAT1 at p, to round-off (axial and bending ∝ E, torsion and panel shear ∝ μ(E, ν),
/// mass ∝ ρ plus NSM).
#[test]
fn beam_parameters_act_exactly_through_the_affine_parts() {
    let frame = "GRID,1,,0.,0.,0.\nGRID,2,,0.,1.,0.\nGRID,3,,1.,1.,0.2\nGRID,4,,1.,0.,0.\n\
        CBAR,1,10,1,2,1.,0.,0.\nPBAR,10,1,1.e-3,2.e-7,3.e-7,1.e-7,0.4\n\
        CBEAM,2,11,2,3,0.,0.,1.\nPBEAM,11,1,2.e-3,4.e-7,5.e-7,,2.e-7,0.3\n,0.,0.,0.,0.,0.,0.,0.,0.\n,NO,1.\n,0.,0.\n\
        CROD,3,12,3,4\nPROD,12,1,5.e-4,1.e-8,,0.1\n\
        CSHEAR,4,13,1,2,3,4\nPSHEAR,13,1,2.e-3,0.5\n";
    let operators = |bulk: &str, p: &[f64]| {
        let (params, k, m) = common::affine_operators(bulk);
        let at = if p.is_empty() {
            params.nominal()
        } else {
            p.to_vec()
        };
        (
            k.evaluate(&params.weights(&k, &at))
                .unwrap()
                .values()
                .to_vec(),
            m.evaluate(&params.weights(&m, &at))
                .unwrap()
                .values()
                .to_vec(),
            k.parts().len(),
        )
    };
    let pmpar =
        "PMPAR,1,E,E,1,1.e11,3.e11\nPMPAR,2,NU,NU,1,0.2,0.4\nPMPAR,3,RHO,RHO,1,2000.,9000.\n";
    let p = [1.3e11, 0.37, 2700.0];
    let (k, m, parts) = operators(&format!("{frame}MAT1,1,2.1e11,,0.3,7800.\n{pmpar}"), &p);
    assert_eq!(parts, 3, "constant, E and μ parts");
    let (k_ref, m_ref, _) = operators(&format!("{frame}MAT1,1,1.3e11,,0.37,2700.\n"), &[]);
    for (got, want, what) in [(&k, &k_ref, "K"), (&m, &m_ref, "M")] {
        let scale = want.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        let worst = got
            .iter()
            .zip(want.iter())
            .fold(0.0f64, |a, (x, y)| a.max((x - y).abs()));
        assert!(worst <= 1e-12 * scale, "{what}: {worst:e} of {scale:e}");
    }
}

/// A cantilever of shear panels (CSHEAR, bays a × h) between CROD flanges (area A_f) with CROD
/// posts at every station, tip load P shared by the two tip grids: the assembly is statically
/// determinate (constant shear flow q = P/h in every panel, posts unloaded, flange force
/// q·a·(n − i + ½) in bay i, the panel's corner forces being q·a/2 along and q·h/2 across), so
/// the unit-load method gives the exact tip deflection of the discrete model,
/// δ = 2 P a³ Σ_{m=1..n} (m − ½)² / (h² E A_f) + P L/(G t h)
/// (reference/analytic/shear_panel.json): 1e-9 is round-off. Every panel's STRESS is
/// τ = −P/(h t) (element axes x along the span, y up: the downward tip load gives negative
/// shear), its shear flow −P/h. The mass properties are (ρt + NSM)·a·h per panel, plus the rods'.
#[test]
fn shear_panel_beam_deflects_like_the_unit_load_closed_form() {
    let reference = common::json("reference/analytic/shear_panel.json");
    let v = |k: &str| reference["parameters"][k].as_f64().unwrap();
    let (a, h, af, t, nsm, p) = (v("a"), v("h"), v("A_f"), v("t"), v("nsm"), v("P"));
    let n = reference["parameters"]["n"].as_u64().unwrap() as usize;
    let g = E / (2.0 * (1.0 + NU));
    let mut bulk = String::from("SPC1,1,123456,101\nPROD,20,1,1.e-4\nPSHEAR,30,1,");
    bulk += &format!(
        "{t:e},{nsm:e}\nFORCE,2,{},,{:e},0.,-1.,0.\n",
        n + 1,
        p / 2.0
    );
    bulk += &format!("FORCE,2,{},,{:e},0.,-1.,0.\n", 101 + n, p / 2.0);
    bulk += &format!("PROD,10,1,{af:e}\n");
    for k in 0..=n {
        let x = a * k as f64;
        bulk += &format!(
            "GRID,{},,{x:?},0.,0.,,3456\nGRID,{},,{x:?},{h:?},0.,,3456\n",
            k + 1,
            101 + k
        );
        bulk += &format!("CROD,{},20,{},{}\n", 300 + k, k + 1, 101 + k);
        if k > 0 {
            bulk += &format!(
                "CROD,{},10,{k},{}\nCROD,{},10,{},{}\n",
                100 + k,
                k + 1,
                200 + k,
                100 + k,
                101 + k
            );
            bulk += &format!("CSHEAR,{k},30,{k},{},{},{}\n", k + 1, 101 + k, 100 + k);
        }
    }
    let deck = format!(
        "SOL 101\nCEND\nSUBCASE 1\n  SPC = 1\n  LOAD = 2\n  STRESS = ALL\nBEGIN BULK\n{bulk}MAT1,1,{E:e},,{NU:?},{RHO:?}\nSPC1,1,123456,1\nENDDATA\n"
    );
    let (file, _dir) = run_to_file(&deck);
    let statics = file.group("results/1/statics").unwrap();
    let u = read_dataset::<f64>(&statics, "displacement");
    let stress = statics.group("stress/CSHEAR").unwrap();
    assert_eq!(
        read_dataset::<u32>(&stress, "ids"),
        (1..=n as u32).collect::<Vec<_>>()
    );
    for tau in read_dataset::<f64>(&stress, "shear") {
        close(tau, -p / (h * t), 1e-9);
    }
    for q in read_dataset::<f64>(&stress, "shear_flow") {
        close(q, -p / h, 1e-9);
    }
    let sum: f64 = (1..=n).map(|m| (m as f64 - 0.5).powi(2)).sum();
    let l = a * n as f64;
    let delta = 2.0 * p * a.powi(3) * sum / (h * h * E * af) + p * l / (g * t * h);
    close(delta, reference["tip_deflection"].as_f64().unwrap(), 1e-12);
    // rows: grids 1..=n+1, then 101..=101+n
    for row in [n, 2 * n + 1] {
        close(-u[6 * row + 1], delta, 1e-9);
    }
    // the grid-point weight: panels and rods
    let model = common::build_model(&deck).unwrap();
    let panels = n as f64 * (RHO * t + nsm) * a * h;
    let rods = RHO * (2.0 * l * af + (n + 1) as f64 * h * 1.0e-4);
    close(model.mass_properties().mass, panels + rods, 1e-12);
}

/// Bad shear-panel input is named with file:line, card and field.
#[test]
fn bad_shear_panels_are_reported_with_card_and_field() {
    let grids = "GRID,1,,0.,0.,0.\nGRID,2,,1.,0.,0.\nGRID,3,,1.,1.,0.\nGRID,4,,0.,1.,0.\n";
    let cases = [
        (
            "CSHEAR,1,10,1,2,3,4\nPSHEAR,10,1,0.01,,0.5\n",
            "deck.dat:9: PSHEAR 10: field 6 (F1): extensional effectiveness F1",
        ),
        (
            "CSHEAR,1,10,1,2,3,4\nPSHEAR,10,1,-0.01\n",
            "deck.dat:9: PSHEAR 10: field 4 (T): expected a real > 0",
        ),
        (
            "CSHEAR,1,10,1,2,3,4\nPSHELL,10,1,0.01\n",
            "deck.dat:8: CSHEAR 1: PID = 10 is a PSHELL",
        ),
        (
            "CSHEAR,1,10,1,3,2,4\nPSHEAR,10,1,0.01\n",
            "deck.dat:8: CSHEAR 1: ",
        ),
    ];
    for (bulk, expected) in cases {
        check_reports(
            &format!("SOL 101\nCEND\nBEGIN BULK\n{grids}{bulk}MAT1,1,2.1e11,,0.3\nENDDATA\n"),
            expected,
        );
    }
}

/// NU as a parameter of a beam with shear flexibility (PBEAM's default K = 1) has no affine
/// form: the run stops and says why.
#[test]
fn nu_parameter_on_a_shear_flexible_beam_is_refused() {
    let deck = "SOL 103\nCEND\nMETHOD = 1\nBEGIN BULK\nGRID,1,,0.,0.,0.\nGRID,2,,1.,0.,0.\n\
        CBEAM,1,11,1,2,0.,0.,1.\nPBEAM,11,1,2.e-3,4.e-7,5.e-7,,2.e-7\nMAT1,1,2.1e11,,0.3,7800.\n\
        PMPAR,1,NU,NU,1,0.2,0.4\nEIGRL,1,,,2\nENDDATA\n";
    let (r, _dir) = run_deck(deck);
    let message = r.err().map(|e| e.to_string()).unwrap_or_default();
    assert!(message.contains("CBEAM 1"), "{message}");
    assert!(message.contains("not affine in E and G"), "{message}");
}

/// PLOAD1 on a cantilever of four CBARs in the x-y plane at 30° to x (clamped at grid 1,
/// orientation vector n = (−sin α, cos α, 0), so element y = n and element z = basic z): the
/// tip displacement under each load against the closed form of Euler–Bernoulli beam theory
/// (Roark, Table 8.1 cases 1a, 2a, 2b and 3a; distributed moment by integrating M(x) = m (L − x)).
/// Consistent loads make the cubic element exact at its nodes, so 1e-9 is round-off.
#[test]
fn pload1_loads_bend_the_cantilever_like_closed_forms() {
    let alpha = std::f64::consts::PI / 6.0;
    let (x, n) = (
        [alpha.cos(), alpha.sin(), 0.0],
        [-alpha.sin(), alpha.cos(), 0.0],
    );
    let z = [0.0, 0.0, 1.0];
    let (l, a, i1, i2) = (2.0, 6.0e-4, 2.0e-8, 4.5e-8);
    let h = l / 4.0;
    let elements: String = (1..=4)
        .map(|i| format!("CBAR,{i},10,{i},{},{:?},{:?},0.\n", i + 1, n[0], n[1]))
        .collect();
    let mesh = format!(
        "{}{elements}PBAR,10,1,{a:e},{i1:e},{i2:e},1.e-8\n",
        grids(4, [0.0; 3], x, l, "")
    );
    let tip = |loads: &str, dir: [f64; 3]| -> f64 {
        let u = statics(&format!("{mesh}{loads}"));
        (0..3).map(|c| u[4 * 6 + c] * dir[c]).sum()
    };
    let each = |f: &dyn Fn(usize) -> String| (1..=4).map(f).collect::<String>();
    let (q, p, m) = (30.0, 150.0, 8.0);
    // uniform force along element y, in fractions: q L⁴ / (8 E I1)
    let uniform = each(&|i| format!("PLOAD1,2,{i},FYE,FR,0.,{q:?},1.,{q:?}\n"));
    close(tip(&uniform, n), q * l.powi(4) / (8.0 * E * i1), 1e-9);
    // triangular force, q at the root and 0 at the tip, in lengths: q L⁴ / (30 E I1)
    let triangle = each(&|i| {
        let (qa, qb) = (q * (1.0 - (i - 1) as f64 / 4.0), q * (1.0 - i as f64 / 4.0));
        // the last element's P2 = 0 is left blank: blank P2 is 0, as MSC Nastran computes it
        match i {
            4 => format!("PLOAD1,2,{i},FYE,LE,0.,{qa:?},{h:?}\n"),
            _ => format!("PLOAD1,2,{i},FYE,LE,0.,{qa:?},{h:?},{qb:?}\n"),
        }
    });
    close(tip(&triangle, n), q * l.powi(4) / (30.0 * E * i1), 1e-9);
    // a concentrated basic FZ at 0.3 of element 2 (a = 1.3 h): P a² (3 L − a) / (6 E I2)
    let at = 1.3 * h;
    let point = format!("PLOAD1,2,2,FZ,FR,0.3,{p:?}\n");
    close(
        tip(&point, z),
        p * at * at * (3.0 * l - at) / (6.0 * E * i2),
        1e-9,
    );
    // a uniform moment about element z: M(x) = m (L − x), tip m L³ / (3 E I1)
    let moment = each(&|i| format!("PLOAD1,2,{i},MZE,FR,0.,{m:?},1.,{m:?}\n"));
    close(tip(&moment, n), m * l.powi(3) / (3.0 * E * i1), 1e-9);
    // a moment about element y at the tip: θ_y = −w′, so the tip moves by −M L² / (2 E I2) along z
    let end_moment = format!("PLOAD1,2,4,MYE,LE,{h:?},{m:?}\n");
    close(tip(&end_moment, z), -m * l * l / (2.0 * E * i2), 1e-9);
    // basic FY per unit projected length: q cos α per unit length, q cos² α across the axis and
    // q cos α sin α along it, so u_y = q cos³α L⁴/(8 E I1) + q cos α sin² α L²/(2 E A)
    let projected = each(&|i| format!("PLOAD1,2,{i},FY,FRPR,0.,{q:?},1.,{q:?}\n"));
    let (c, s) = (alpha.cos(), alpha.sin());
    close(
        tip(&projected, [0.0, 1.0, 0.0]),
        q * c.powi(3) * l.powi(4) / (8.0 * E * i1) + q * c * s * s * l * l / (2.0 * E * a),
        1e-9,
    );
}

/// PLOAD1 that cannot act: `paraflex check` names file:line, card and what is wrong.
#[test]
fn bad_pload1_cards_are_reported() {
    let bar =
        "GRID,1,,0.,0.,0.\nGRID,2,,1.,0.,0.\nCBAR,1,10,1,2,0.,1.,0.\nPBAR,10,1,1.e-4,1.e-8,1.e-8\n";
    let cases = [
        (
            "CROD,2,11,1,2\nPROD,11,1,1.e-4\nPLOAD1,3,2,FY,FR,0.5,1.\n",
            "deck.dat:11: PLOAD1 3: EID = 2 is not a CBAR, CBEAM or CBEND",
        ),
        (
            "PLOAD1,3,1,FY,FR,0.5,1.,1.2,1.\n",
            "deck.dat:9: PLOAD1 3: field 8 (X2): X2 = 1.2 exceeds 1",
        ),
        (
            "PLOAD1,3,1,FY,LE,0.,1.,1.5,1.\n",
            "deck.dat:9: PLOAD1 3: X2 = 1.5 is beyond the element's length",
        ),
        (
            "PLOAD1,3,1,FW,LE,0.,1.\n",
            "deck.dat:9: PLOAD1 3: field 4 (TYPE)",
        ),
        (
            "CBAR,2,10,1,2,0.,1.,0.\n,1\nPLOAD1,3,2,FY,FR,0.5,1.\n",
            "deck.dat:11: PLOAD1 3: CBAR 2 has pin flags",
        ),
    ];
    for (extra, expected) in cases {
        check_reports(
            &format!(
                "SOL 101\nCEND\nLOAD = 3\nBEGIN BULK\n{bar}{extra}MAT1,1,2.1e11,,0.3\nENDDATA\n"
            ),
            expected,
        );
    }
}

/// PLOAD1 against MSC Nastran: decks/verify/pload1_cbar.dat is the model of pyNastran's
/// models/unit/pload4/pload1.bdf, whose OP2 holds MSC Nastran's displacements
/// (reference/nastran/pload1_cbar.json): concentrated forces and moments in each basic direction
/// and distributed moments with a blank P2. The OP2 stores single precision, so 1e-6 of each
/// subcase's largest component.
#[test]
fn pload1_matches_msc_nastran() {
    let reference = common::json("reference/nastran/pload1_cbar.json");
    let deck =
        std::fs::read_to_string(common::root().join("decks/verify/pload1_cbar.dat")).unwrap();
    let (file, _dir) = run_to_file(&deck);
    // the deck's grids are 1 and 2: displacement rows 0 and 1
    let ids = [1, 2];
    for (subcase, grids) in reference["displacement"].as_object().unwrap() {
        let u = read_dataset::<f64>(
            &file.group(&format!("results/{subcase}/statics")).unwrap(),
            "displacement",
        );
        let want: Vec<(usize, Vec<f64>)> = grids
            .as_object()
            .unwrap()
            .iter()
            .map(|(g, v)| {
                let row = ids.iter().position(|&i| i.to_string() == *g).unwrap();
                (row, common::f64s(v))
            })
            .collect();
        let scale = want
            .iter()
            .flat_map(|(_, v)| v.iter().map(|x| x.abs()))
            .fold(0.0, f64::max);
        for (row, v) in want {
            for c in 0..6 {
                let got = u[6 * row + c];
                assert!(
                    (got - v[c]).abs() <= 1e-6 * scale,
                    "subcase {subcase} row {row} component {c}: {got:e} vs MSC {:e}",
                    v[c]
                );
            }
        }
    }
}

/// Modes against Simcenter Nastran: decks/verify/beam_modes.dat (a thick CBAR/CBEAM cantilever
/// with Timoshenko shear, lumped mass and a tip CONM2) against the ten frequencies of
/// reference/nastran/beam_modes.json. The torsion mode checks Nastran's lumped CBEAM torsional
/// inertia ρ(I1 + I2)L/2 (the CBARs have none); 1e-6: single-precision reference.
#[test]
fn beam_modes_match_simcenter_nastran() {
    let reference = common::json("reference/nastran/beam_modes.json");
    let want = common::f64s(&reference["frequency_hz"]);
    let deck = std::fs::read_to_string(common::root().join("decks/verify/beam_modes.dat")).unwrap();
    let (file, _dir) = run_to_file(&deck);
    let got = read_dataset::<f64>(&file.group("results/1/modal").unwrap(), "frequency_hz");
    assert_eq!(got.len(), want.len());
    for (g, w) in got.iter().zip(&want) {
        close(*g, *w, 1e-6);
    }
}

/// Thermal loads on rods and beams (αΔT = 1e-3, TEMPD; MAT1 A and TREF): a CROD held at one
/// end grows by αΔT·L; held at both ends it carries N = −EAαΔT, the SPC forces ±EAαΔT along the
/// axis. A CBAR whose axis is offset by w = 0.05 in y at both ends (WA = WB) and is held at both
/// grids: the same axial force, now acting on the offset axis, so each grid's support also
/// carries the moment w × F (Mz = ∓0.05·EAαΔT); free at one grid, the far grid moves by αΔT·L
/// along x without rotation (the rigid offsets do not expand). A uniform axial strain is exact
/// for these elements: 1e-9 of the values (round-off).
#[test]
fn heated_rods_and_offset_bars_expand_or_push_by_e_a_alpha_dt() {
    let (l, a, alpha, tref, dt) = (2.0, 1.0e-4, 1.0e-5, 20.0, 100.0);
    let f = E * a * alpha * dt;
    let deck = |element: &str, spc: &str| {
        format!(
            "SOL 101\nCEND\nSPC = 1\nTEMPERATURE(LOAD) = 3\nSPCFORCES = ALL\nBEGIN BULK\n\
             GRID,1,,0.,0.,0.\nGRID,2,,{l:?},0.,0.\n{element}\
             PROD,10,1,{a:?}\nPBAR,20,1,{a:?},1.e-8,1.e-8,1.e-8\n\
             MAT1,1,{E:?},,{NU:?},{RHO:?},{alpha:?},{tref:?}\nTEMPD,3,{:?}\n{spc}ENDDATA\n",
            tref + dt
        )
    };
    let rod = "CROD,1,10,1,2\n";
    let bar = "CBAR,1,20,1,2,0.,0.,1.\n+,,,0.,0.05,0.,0.,0.05,0.\n";
    for element in [rod, bar] {
        let (file, _dir) = run_to_file(&deck(element, "SPC1,1,123456,1\nSPC1,1,2345,2\n"));
        let u: Vec<f64> = read_dataset(&file.group("results/1/statics").unwrap(), "displacement");
        let want = [alpha * dt * l, 0.0, 0.0, 0.0, 0.0, 0.0];
        for (got, w) in u[6..12].iter().zip(want) {
            assert!(
                (got - w).abs() < 1e-9 * alpha * dt * l,
                "{element}: {:?}",
                &u[6..]
            );
        }
        let (file, _dir) = run_to_file(&deck(element, "SPC1,1,123456,1,2\n"));
        let q: Vec<f64> = read_dataset(&file.group("results/1/statics").unwrap(), "spc_force");
        let arm = if element == bar { 0.05 } else { 0.0 };
        let want = [
            f,
            0.0,
            0.0,
            0.0,
            0.0,
            -arm * f,
            -f,
            0.0,
            0.0,
            0.0,
            0.0,
            arm * f,
        ];
        for (got, w) in q.iter().zip(want) {
            assert!((got - w).abs() < 1e-9 * f, "{element}: {q:?}");
        }
    }
}

/// Quarter-circle cantilevers of radius R, one per CBEND GEOM rule (1: v from A to the centre;
/// 2: v along the tangent at A, here given by a grid G0; 3: PBEND RB; 4: PBEND THETAB = 90),
/// each clamped at A = (R, 0) and loaded at B = (0, R) by P along y (in the plane of the arc)
/// and, in a second subcase, along z. Reference: Castigliano's theorem with bending,
/// extension, shear and torsion energies (Roark, curved beams; integrated in closed form):
/// δ_y = (π/4) P (R³/(E I1) + R/(E A) + R/(K1 G A)),
/// δ_z = P (π R³/(4 E I2) + (3π/4 − 2) R³/(G J) + π R/(2 K2 G A)).
/// One CBEND is exact for this model; the tolerance is the round-off of the solve (1e-9).
#[test]
fn cbend_quarter_circles_deflect_like_castigliano() {
    use std::f64::consts::PI;
    let (r, p, a, i1, i2, j, k1, k2): (f64, f64, f64, f64, f64, f64, f64, f64) =
        (0.8, 500.0, 2.0e-4, 3.0e-9, 2.0e-9, 4.0e-9, 0.85, 0.7);
    let g = E / (2.0 * (1.0 + NU));
    let pbend = |pid: u32, rb: &str, thetab: &str| {
        format!("PBEND,{pid},1,{a:e},{i1:e},{i2:e},{j:e},{rb},{thetab}\n,,,,,,,,\n,{k1},{k2}\n")
    };
    let mut bulk = String::new();
    let mut tips = Vec::new();
    let mut ids = Vec::new();
    // (GEOM, orientation fields, property)
    let arcs = [
        (1, "-1.,0.,0.".to_string(), pbend(11, "", "")),
        (2, "G0".to_string(), pbend(12, "", "")),
        (3, "1.,1.,0.".to_string(), pbend(13, &format!("{r:?}"), "")),
        (4, "1.,1.,0.".to_string(), pbend(14, "", "90.")),
    ];
    for (k, (geom, orientation, property)) in arcs.iter().enumerate() {
        let (ga, gb, g0) = (10 * k + 1, 10 * k + 2, 10 * k + 3);
        let z = k as f64;
        bulk += &format!("GRID,{ga},,{r:?},0.,{z:?},,123456\nGRID,{gb},,0.,{r:?},{z:?}\n");
        ids.extend([ga, gb]);
        let orientation = if orientation == "G0" {
            ids.push(g0);
            bulk += &format!("GRID,{g0},,{r:?},1.,{z:?}\n");
            format!("{g0},,")
        } else {
            orientation.clone()
        };
        bulk += &format!(
            "CBEND,{},{},{ga},{gb},{orientation},{geom}\n{property}",
            k + 1,
            11 + k
        );
        bulk += &format!("FORCE,2,{gb},,{p:?},0.,1.,0.\nFORCE,3,{gb},,{p:?},0.,0.,1.\n");
        tips.push(gb);
    }
    let deck = format!(
        "SOL 101\nCEND\nDISPLACEMENT = ALL\nSUBCASE 1\n  LOAD = 2\nSUBCASE 2\n  LOAD = 3\nBEGIN BULK\n{bulk}MAT1,1,{E:e},,{NU:?},{RHO:?}\nENDDATA\n"
    );
    let (file, _dir) = run_to_file(&deck);
    // displacement rows follow the grid ids, increasing
    ids.sort_unstable();
    let row = |id: usize| ids.iter().position(|&g| g == id).unwrap();
    let in_plane = read_dataset::<f64>(&file.group("results/1/statics").unwrap(), "displacement");
    let out_of_plane =
        read_dataset::<f64>(&file.group("results/2/statics").unwrap(), "displacement");
    let dy = PI / 4.0 * p * (r.powi(3) / (E * i1) + r / (E * a) + r / (k1 * g * a));
    let dz = p
        * (PI * r.powi(3) / (4.0 * E * i2)
            + (0.75 * PI - 2.0) * r.powi(3) / (g * j)
            + PI * r / (2.0 * k2 * g * a));
    for tip in tips {
        close(in_plane[6 * row(tip) + 1], dy, 1e-9);
        close(out_of_plane[6 * row(tip) + 2], dz, 1e-9);
    }
}

/// Bad CBEND / PBEND input: `paraflex check` names file:line, card and field.
#[test]
fn bad_cbends_are_reported_with_card_and_field() {
    let grids = "GRID,1,,0.,0.,0.\nGRID,2,,1.,0.,0.\n";
    let cases = [
        (
            "CBEND,1,10,1,2,0.,1.,0.,3\nPBEND,10,1,1.e-4,1.e-8,1.e-8,1.e-8\n",
            "deck.dat:6: CBEND 1: field 9 (GEOM): GEOM = 3 needs RB on PBEND 10",
        ),
        (
            "CBEND,1,10,1,2,0.,1.,0.,1\nPBEND,10,1,1.e-4,1.e-8,1.e-8,1.e-8\n",
            "deck.dat:6: CBEND 1: field 6 (X1/G0): GEOM = 1 with the orientation vector perpendicular",
        ),
        (
            "CBEND,1,10,1,2,1.,0.,0.,2\nPBEND,10,1,1.e-4,1.e-8,1.e-8,1.e-8\n",
            "deck.dat:6: CBEND 1: field 6 (X1/G0): the orientation vector is parallel to the chord",
        ),
        (
            "CBEND,1,10,1,2,0.,1.,0.,3\nPBEND,10,1,1.e-4,1.e-8,1.e-8,1.e-8,0.4\n",
            "deck.dat:6: CBEND 1: field 9 (GEOM): the bend radius RB = 4e-1 is less than half the chord",
        ),
        (
            "CBEND,1,10,1,2,0.,1.,0.,5\nPBEND,10,1,1.e-4,1.e-8,1.e-8,1.e-8\n",
            "deck.dat:6: CBEND 1: field 9 (GEOM): expected 1, 2, 3 or 4, found 5",
        ),
        (
            "CBEND,1,10,1,2,0.,1.,0.,3\nPBEND,10,1,2,1.,0.1,,1.\n",
            "deck.dat:7: PBEND 10: field 4 (FSI): the pipe form of PBEND",
        ),
        (
            "CBEND,1,10,1,2,0.,1.,0.,3\nPBEND,10,1,1.e-4,1.e-8,1.e-8,1.e-8,1.\n,,,,,,,,\n,,,,0.1\n",
            "deck.dat:9: PBEND 10: field 5 of continuation 2 (RC): offsets of the centroid",
        ),
    ];
    for (bulk, expected) in cases {
        check_reports(
            &format!("SOL 101\nCEND\nBEGIN BULK\n{grids}{bulk}MAT1,1,2.1e11,,0.3\nENDDATA\n"),
            expected,
        );
    }
}

/// PLOAD1 on a CBEND: a quarter circle of radius R clamped at A = (R, 0) under a uniform load
/// q per unit arc length along z over the whole arc (FZ, FR 0 → 1). Reference: the unit-load
/// method with Castigliano's energies, integrated in closed form (at the section φ the load
/// beyond it gives V = q R (π/2 − φ), M_r = q R² (1 − sin φ), T = q R² (π/2 − φ − cos φ); a
/// unit tip load gives 1, R cos φ, R (1 − sin φ)):
/// w_B = q R⁴/(2 E I2) + q R⁴ (π²/8 − π/2 + 1/2)/(G J) + q R² π²/(8 K2 G A).
/// The element's loads are exact for this model; the tolerance is round-off (1e-9).
#[test]
fn pload1_on_a_cbend_bends_it_like_the_unit_load_method() {
    use std::f64::consts::PI;
    let (r, q, a, i2, j, k2): (f64, f64, f64, f64, f64, f64) =
        (0.6, 900.0, 2.0e-4, 2.0e-9, 4.0e-9, 0.7);
    let g = E / (2.0 * (1.0 + NU));
    let deck = format!(
        "SOL 101\nCEND\nDISPLACEMENT = ALL\nSPCFORCES = ALL\nSUBCASE 1\n  LOAD = 2\nBEGIN BULK\n\
         GRID,1,,{r:?},0.,0.,,123456\nGRID,2,,0.,{r:?},0.\n\
         CBEND,1,11,1,2,-1.,0.,0.,1\nPBEND,11,1,{a:e},3.e-9,{i2:e},{j:e}\n,,,,,,,,\n,0.9,{k2}\n\
         PLOAD1,2,1,FZ,FR,0.,{q:?},1.,{q:?}\n\
         MAT1,1,{E:e},,{NU:?},{RHO:?}\nENDDATA\n"
    );
    let (file, _dir) = run_to_file(&deck);
    let u = read_dataset::<f64>(&file.group("results/1/statics").unwrap(), "displacement");
    let w = q * r.powi(4) / (2.0 * E * i2)
        + q * r.powi(4) * (PI * PI / 8.0 - PI / 2.0 + 0.5) / (g * j)
        + q * r * r * PI * PI / (8.0 * k2 * g * a);
    close(u[6 + 2], w, 1e-9);
}
