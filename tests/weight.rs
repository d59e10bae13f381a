//! The grid-point weight generator (`PARAM,GRDPNT`) against closed forms: a flat plate with
//! coupled mass (whose bilinear shape functions carry the rigid-body motions exactly, so the
//! continuum values come out), the same plate with lumped mass (the nodal sums of its quarter
//! / half / full tributary masses), and CONM2s with offsets, a rotated CID and their own inertia
//! on grids with rotated displacement systems, against the model summary's mass properties
//! (written independently from the cards and compared with pyNastran in `conformance_mass`).

mod common;
use common::{read_dataset, run_to_file};

use paraflex::deck::Deck;
use paraflex::model::Model;

const RHO: f64 = 2700.0;
const T: f64 = 0.01;
const A: f64 = 2.0;
const B: f64 = 1.0;
const NX: usize = 8;
const NY: usize = 4;
const ORIGIN: [f64; 3] = [0.5, -0.25, 0.3];

fn plate(extra: &str) -> String {
    let mut s = format!(
        "SOL 103\nCEND\nMETHOD = 1\nBEGIN BULK\n{extra}EIGRL,1,,,3\nMAT1,1,7.e10,,0.3,{RHO:?}\nPSHELL,1,1,{T:?},1,,1\n"
    );
    for j in 0..=NY {
        for i in 0..=NX {
            let x = ORIGIN[0] + A * i as f64 / NX as f64;
            let y = ORIGIN[1] + B * j as f64 / NY as f64;
            s += &format!(
                "GRID,{},,{x:?},{y:?},{:?}\n",
                j * (NX + 1) + i + 1,
                ORIGIN[2]
            );
        }
    }
    for j in 0..NY {
        for i in 0..NX {
            let n = j * (NX + 1) + i + 1;
            s += &format!(
                "CQUAD4,{},1,{n},{},{},{}\n",
                j * NX + i + 1,
                n + 1,
                n + NX + 2,
                n + NX + 1
            );
        }
    }
    s + "ENDDATA\n"
}

struct Gpwg {
    mass: Vec<f64>,
    cg: Vec<f64>,
    inertia: Vec<f64>,
    principal: Vec<f64>,
}

fn gpwg(deck: &str) -> Gpwg {
    let (file, _dir) = run_to_file(deck);
    let g = file.group("model/gpwg").expect("/model/gpwg");
    Gpwg {
        mass: read_dataset(&g, "mass"),
        cg: read_dataset(&g, "cg"),
        inertia: read_dataset(&g, "inertia"),
        principal: read_dataset(&g, "principal_inertia"),
    }
}

fn close(what: &str, got: f64, want: f64, tol: f64) {
    let scale = want.abs().max(1.0);
    assert!(
        (got - want).abs() <= tol * scale,
        "{what}: {got} vs {want} (tolerance {tol:e} × {scale})"
    );
}

/// Mass, C.G. and inertia about it of the plate: m = ρ a b t; I = diag(m(b² + t²)/12,
/// m(a² + t²)/12, m(a² + b²)/12), the t² terms being the shell's rotary inertia ρt³/12.
/// Coupled mass reproduces them exactly; lumped mass gives the tributary-area sums, whose
/// second moment over n equal intervals of length L is m L² (1 + 2/n²)/12.
#[test]
fn plate_mass_properties_match_the_closed_forms() {
    let m = RHO * A * B * T;
    let cg = [ORIGIN[0] + A / 2.0, ORIGIN[1] + B / 2.0, ORIGIN[2]];
    let lumped = |l: f64, n: usize| l * l * (1.0 + 2.0 / (n * n) as f64);
    for (mass_param, ix2, iy2) in [
        ("PARAM,COUPMASS,1\n", B * B, A * A),
        ("", lumped(B, NY), lumped(A, NX)),
    ] {
        let w = gpwg(&plate(&format!("PARAM,GRDPNT,0\n{mass_param}")));
        // round-off of sums over 45 grids: 1e-12 relative
        let tol = 1e-12;
        for k in 0..3 {
            close("mass", w.mass[k], m, tol);
            for c in (0..3).filter(|&c| c != k) {
                close("cg", w.cg[3 * k + c], cg[c], tol);
            }
        }
        let want = [
            m * (ix2 + T * T) / 12.0,
            m * (iy2 + T * T) / 12.0,
            m * (ix2 + iy2) / 12.0,
        ];
        for (r, &diagonal) in want.iter().enumerate() {
            for c in 0..3 {
                let v = if r == c { diagonal } else { 0.0 };
                close(
                    &format!("I({r},{c}) {mass_param}"),
                    w.inertia[3 * r + c],
                    v,
                    tol,
                );
            }
            close("principal", w.principal[r], diagonal, tol);
        }
    }
}

/// CONM2s with offsets, a rotated CID and their own inertia, on grids whose displacement
/// systems are rotated, one mass hanging on an RBE2: the same mass, C.G. and inertia as the
/// model summary computes from the cards, about a reference grid (the C.G. relative to it);
/// WTMASS is divided out.
#[test]
fn conm2_masses_agree_with_the_model_summary() {
    let deck = "SOL 103\nCEND\nMETHOD = 1\nBEGIN BULK\nPARAM,GRDPNT,3\nPARAM,WTMASS,0.5\n\
        EIGRL,1,,,2\n\
        CORD2R,5,0,0.,0.,0.,0.3,0.2,1.\n,1.,0.4,0.1\n\
        CORD2R,6,0,1.,2.,3.,1.,2.5,4.\n,2.,2.,3.\n\
        GRID,1,,0.,0.,0.,5\nGRID,2,,1.5,0.2,-0.4\nGRID,3,,-0.7,1.1,0.6,6\nGRID,4,,0.4,-0.9,1.3\n\
        CONM2,11,1,5,3.0,0.1,-0.2,0.3\n,0.5,0.01,0.4,0.02,-0.03,0.6\n\
        CONM2,12,2,0,1.5,-0.3,0.2,0.1\n,0.2,0.,0.3,0.,0.,0.25\n\
        CONM2,13,3,6,2.0\n\
        CONM2,14,4,0,0.8,0.,0.,0.2\n\
        RBE2,20,2,123456,4\n\
        SPC1,1,123456,1\n\
        ENDDATA\n";
    // springs to ground on every free DOF, so that the modal run has a stiffness to solve with
    let springs: String = (0..12)
        .map(|k| format!("CELAS2,{},1.e4,{},{}\n", 100 + k, 2 + k / 6, 1 + k % 6))
        .collect();
    let deck = deck.replace("ENDDATA", &format!("{springs}ENDDATA"));
    let deck = deck.as_str();
    let mut file = tempfile::Builder::new().suffix(".dat").tempfile().unwrap();
    std::io::Write::write_all(&mut file, deck.as_bytes()).unwrap();
    let model = Model::build(&Deck::read(file.path()).unwrap()).unwrap();
    let summary = model.mass_properties();
    let w = gpwg(deck);
    // the summary is × WTMASS, the GPWG in input units
    let wtmass = 0.5;
    // GRDPNT = 3: the centres of gravity are relative to grid 3, as Nastran prints them
    let reference = [-0.7, 1.1, 0.6];
    let tol = 1e-12;
    for k in 0..3 {
        close("mass", w.mass[k] * wtmass, summary.mass, tol);
        for c in (0..3).filter(|&c| c != k) {
            close("cg", w.cg[3 * k + c], summary.cg[c] - reference[c], tol);
        }
    }
    for r in 0..3 {
        for c in 0..3 {
            close(
                &format!("I({r},{c})"),
                w.inertia[3 * r + c] * wtmass,
                summary.inertia_cg[r][c],
                tol,
            );
        }
    }
}

/// No PARAM,GRDPNT: no table; a GRDPNT naming no grid is a located error.
#[test]
fn grdpnt_is_off_by_default_and_checked() {
    let (file, _dir) = run_to_file(&plate(""));
    assert!(file.group("model/gpwg").is_err());
    let mut f = tempfile::Builder::new().suffix(".dat").tempfile().unwrap();
    std::io::Write::write_all(&mut f, plate("PARAM,GRDPNT,999\n").as_bytes()).unwrap();
    let errors: Vec<String> = Model::build(&Deck::read(f.path()).unwrap())
        .expect_err("an error")
        .iter()
        .map(|e| e.to_string())
        .collect();
    assert!(
        errors
            .iter()
            .any(|e| e.contains("PARAM GRDPNT") && e.contains("V1 = 999 does not exist")),
        "{errors:?}"
    );
}
