//! Rigid-body null space of assembled models with RBE2 / RBE3: a free structure must have exactly
//! the six rigid motions as zero-energy modes, whatever the plate's orientation and the grids'
//! displacement (CD) frames. Checked on the assembled, reduced operator (K_nn r = 0 and
//! T r_n = r_g for the six rigid motions r) and through SOL 103 (six zero frequencies, the
//! seventh elastic, no AUTOSPC).
//!
//! This guards the pieces a rigid motion passes through: the MITC4/MITC3 kernels with the
//! Hughes–Brezzi drilling term (zero energy when R3 equals the rigid rotation about the normal),
//! the element frame → basic → CD transformations, the RBE2 relation u_d = u_i + θ_i × r and the
//! RBE3 rigid fit, and AUTOSPC (which must not remove a DOF that a rigid motion moves).

mod common;
use common::run_deck;

use std::io::Write;

use paraflex::deck::Deck;
use paraflex::discretize::{BuildOptions, Structure};
use paraflex::model::Model;
use paraflex::sequence::modal::ModalSummary;

/// Plate 0.2 × 0.2 × 0.002 m, steel.
const SIDE: f64 = 0.2;
const N: usize = 6;
const HUB: u32 = 1000;
const REF: u32 = 2000;

/// How the test plate is placed and constrained.
struct Variant {
    name: &'static str,
    /// Rotation (basic ← plate) applied to the plate built in the XY plane, and an offset.
    rotation: [[f64; 3]; 3],
    offset: [f64; 3],
    /// A coordinate-system card used as CD of every grid (`None`: basic).
    cd: Option<&'static str>,
    /// An RBE3 from the reference grid to the four plate corners (T1–T3) besides the RBE2.
    rbe3: bool,
}

fn place(v: &Variant, p: [f64; 3]) -> [f64; 3] {
    std::array::from_fn(|i| v.offset[i] + (0..3).map(|j| v.rotation[i][j] * p[j]).sum::<f64>())
}

/// The deck: N × N plate (the first row split into CTRIA3 pairs so MITC3 is covered too), an RBE2
/// from a hub 50 mm above the centre to the 3 × 3 central grids (CM 123456) with a CONM2 on the
/// hub, optionally an RBE3 to the corners with a CONM2 on its reference grid. Free: no SPC.
fn deck(v: &Variant, modes: usize) -> String {
    let id = |i: usize, j: usize| 1 + i + j * (N + 1);
    let cd = if v.cd.is_some() { "9" } else { "" };
    let mut s = format!(
        "SOL 103\nCEND\nMETHOD = 1\nBEGIN BULK\nEIGRL,1,,,{modes}\nPSHELL,1,1,.002,1,,1\nMAT1,1,2.1+11,,.3,7850.\n"
    );
    if let Some(card) = v.cd {
        s += card;
    }
    let h = SIDE / N as f64;
    for j in 0..=N {
        for i in 0..=N {
            let [x, y, z] = place(
                v,
                [i as f64 * h - SIDE / 2.0, j as f64 * h - SIDE / 2.0, 0.0],
            );
            s += &format!("GRID,{},,{x:?},{y:?},{z:?},{cd}\n", id(i, j));
        }
    }
    let [x, y, z] = place(v, [0.0, 0.0, 0.05]);
    s += &format!(
        "GRID,{HUB},,{x:?},{y:?},{z:?},{cd}\nCONM2,9000,{HUB},,.5,,,,,\n,1.-4,,1.-4,,,2.-4\n"
    );
    let mut eid = 0;
    for j in 0..N {
        for i in 0..N {
            let q = [id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)];
            if j == 0 {
                eid += 2;
                s += &format!(
                    "CTRIA3,{},1,{},{},{}\nCTRIA3,{},1,{},{},{}\n",
                    eid - 1,
                    q[0],
                    q[1],
                    q[2],
                    eid,
                    q[0],
                    q[2],
                    q[3]
                );
            } else {
                eid += 1;
                s += &format!("CQUAD4,{eid},1,{},{},{},{}\n", q[0], q[1], q[2], q[3]);
            }
        }
    }
    let c = N / 2;
    let central: Vec<String> = (c - 1..=c + 1)
        .flat_map(|j| (c - 1..=c + 1).map(move |i| id(i, j).to_string()))
        .collect();
    s += &format!(
        "RBE2,9001,{HUB},123456,{},\n,{}\n",
        central[..5].join(","),
        central[5..].join(",")
    );
    if v.rbe3 {
        let [x, y, z] = place(v, [0.03, -0.02, -0.04]);
        s += &format!("GRID,{REF},,{x:?},{y:?},{z:?},{cd}\nCONM2,9002,{REF},,.2\n");
        s += &format!(
            "RBE3,9003,,{REF},123456,1.,123,{},{},\n,{},{}\n",
            id(0, 0),
            id(N, 0),
            id(N, N),
            id(0, N)
        );
    }
    s + "ENDDATA\n"
}

fn variants() -> Vec<Variant> {
    // CORD2R / CORD2C with axes in no particular alignment; the CORD2C axis misses every grid.
    const CORD2R: &str = "CORD2R,9,,.1,-.2,.3,.4,.3,1.1,\n,1.1,-.1,.5\n";
    const CORD2C: &str = "CORD2C,9,,.5,.4,-.3,.7,.9,.6,\n,1.4,.2,-.1\n";
    let tilt = paraflex::geometry::rotation::from_axis_angle([1.0, 2.0, 3.0], 0.7).unwrap();
    vec![
        Variant {
            name: "XY plane, basic",
            rotation: paraflex::geometry::mat3::IDENTITY,
            offset: [0.0; 3],
            cd: None,
            rbe3: false,
        },
        Variant {
            name: "XY plane, CORD2R CD, RBE3",
            rotation: paraflex::geometry::mat3::IDENTITY,
            offset: [0.0; 3],
            cd: Some(CORD2R),
            rbe3: true,
        },
        Variant {
            name: "tilted, basic, RBE3",
            rotation: tilt,
            offset: [0.3, -0.1, 0.2],
            cd: None,
            rbe3: true,
        },
        Variant {
            name: "tilted, CORD2C CD, RBE3",
            rotation: tilt,
            offset: [0.3, -0.1, 0.2],
            cd: Some(CORD2C),
            rbe3: true,
        },
    ]
}

/// Build the assembled structure of a deck text (the same path as `paraflex run`).
fn structure(text: &str, check: impl FnOnce(&Model, &Structure)) {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("deck.dat");
    std::fs::File::create(&path)
        .and_then(|mut f| f.write_all(text.as_bytes()))
        .expect("write deck");
    let deck = Deck::read(&path).unwrap_or_else(|e| panic!("deck: {e}"));
    let model = Model::build(&deck).unwrap_or_else(|e| {
        panic!(
            "model: {:?}",
            e.iter().map(|x| x.to_string()).collect::<Vec<_>>()
        )
    });
    let quiet = |_: &str, _: usize, _: usize| {};
    let st = Structure::build(&model, &BuildOptions { parallel: false }, &quiet)
        .unwrap_or_else(|e| panic!("structure: {e}"));
    check(&model, &st);
}

/// Rigid motion k (0–2 translation along basic x, y, z; 3–5 rotation about them through the
/// origin) of every grid, in the grids' global (CD) frames.
fn rigid_g(model: &Model, st: &Structure, k: usize) -> Vec<f64> {
    let mut e = [0.0; 3];
    e[k % 3] = 1.0;
    let mut u = vec![0.0; 6 * model.grids.len()];
    for (g, p) in model.grids.iter().enumerate() {
        let (t, r) = if k < 3 {
            (e, [0.0; 3])
        } else {
            // θ × x
            (paraflex::geometry::vec3::cross(e, p.xyz), e)
        };
        u[6 * g..6 * g + 3].copy_from_slice(&st.frames.to_global(g, t));
        u[6 * g + 3..6 * g + 6].copy_from_slice(&st.frames.to_global(g, r));
    }
    u
}

fn max_abs(v: &[f64]) -> f64 {
    v.iter().fold(0.0, |m, x| m.max(x.abs()))
}

/// T r_n = r_g (the RBE2/RBE3 relations hold for rigid motions) and K_nn r_n = 0 relative to
/// max|K_nn| · max|r_n|. Both are round-off: measured ≤ 1.7e-15 and ≤ 1e-15. The drilling
/// penalty is small against the membrane and bending terms, so a wrong drilling row shows only as
/// ~1e-6 (measured 8e-7 with the sign of ∂u/∂y flipped); wrong RBE kinematics or frames give
/// O(0.1–1). Hence 1e-12 for T and 1e-11 for K.
#[test]
fn rigid_motions_are_in_the_null_space_of_k_nn() {
    for v in variants() {
        structure(&deck(&v, 8), |model, st| {
            let w = st.weights(&st.k_nn);
            let mut k = vec![0.0; st.k_nn.pattern().nnz()];
            st.k_nn.evaluate_into(&w, &mut k).expect("K_nn");
            let k_max = max_abs(&k);
            for mode in 0..6 {
                let r_g = rigid_g(model, st, mode);
                let r_n = st.rigid.n.gather(&r_g).expect("gather");
                let back = st.rigid.expand(&r_n).expect("expand");
                let kin = back
                    .iter()
                    .zip(&r_g)
                    .map(|(a, b)| (a - b).abs())
                    .fold(0.0, f64::max);
                assert!(
                    kin <= 1e-12 * max_abs(&r_g),
                    "{}: rigid motion {mode}: T r_n differs from r_g by {kin:e}",
                    v.name
                );
                let kr = st.k_nn.mul_values(&k, &r_n).expect("K r");
                let ratio = max_abs(&kr) / (k_max * max_abs(&r_n));
                assert!(
                    ratio <= 1e-11,
                    "{}: rigid motion {mode}: |K_nn r| / (|K| |r|) = {ratio:e}",
                    v.name
                );
            }
        });
    }
}

/// SOL 103 of the free models: exactly six zero modes. Rigid-body eigenvalues come out of the
/// shifted Lanczos at round-off level (measured f ≤ 1.5e-6 f_7, i.e. λ ≤ 3e-12 λ_7); the first
/// elastic mode is 172 Hz (RBE3 variants) or 285 Hz. A rigid motion with energy puts the sixth
/// frequency at a finite fraction of f_7 (80.7 Hz with the drilling row's sign flipped), an extra
/// mechanism the seventh near zero. Hence f_1…f_6 ≤ 1e-4 f_7 and f_7 > 100 Hz.
#[test]
fn free_plate_with_rbe2_and_rbe3_has_exactly_six_zero_modes() {
    for v in variants() {
        let (r, _dir) = run_deck(&deck(&v, 8));
        let s = r.unwrap_or_else(|e| panic!("{}: {e}", v.name));
        assert!(
            s.subcases[0].autospc.is_empty(),
            "{}: AUTOSPC removed {:?}",
            v.name,
            s.subcases[0].autospc
        );
        let Some(m) = s.subcases[0].result::<ModalSummary>() else {
            panic!("not modal")
        };
        let f = &m.frequencies_hz;
        assert_eq!(f.len(), 8, "{}: {f:?}", v.name);
        assert!(
            f[6] > 100.0,
            "{}: seventh mode is not elastic: {f:?}",
            v.name
        );
        assert!(
            f[..6].iter().all(|x| *x <= 1e-4 * f[6]),
            "{}: not six zero modes: {f:?}",
            v.name
        );
    }
}
