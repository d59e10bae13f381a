//! SOL 103 (MODAL) through `paraflex::sequence::run`, against analytic references.
//! Decks are written here (small, generated meshes); tolerances are stated with their reasons.

mod common;
use common::run_deck;

use paraflex::sequence::RunSummary;
use paraflex::sequence::modal::ModalSummary;

const TWO_PI: f64 = 2.0 * std::f64::consts::PI;

fn modal(s: &RunSummary) -> &ModalSummary {
    match s.subcases[0].result::<ModalSummary>() {
        Some(m) => m,
        None => panic!("not modal: {:?}", s.subcases[0].result),
    }
}

/// Two masses on two springs in series, grounded (CELAS2 + CONM2):
/// K = [[k1+k2, −k2], [−k2, k2]], M = diag(m1, m2), m1 m2 λ² − (m1 k2 + m2(k1+k2)) λ + k1 k2 = 0.
/// The 2-DOF eigenproblem is solved exactly, so the tolerance is round-off (1e-10).
#[test]
fn two_dof_spring_mass_matches_the_analytic_2x2_eigenproblem() {
    let (k1, k2, m1, m2): (f64, f64, f64, f64) = (1.0e4, 2.5e3, 2.0, 0.5);
    let deck = format!(
        "SOL 103\nCEND\nMETHOD = 1\nBEGIN BULK\nGRID,1,,0.,0.,0.\nGRID,2,,1.,0.,0.\nCELAS2,1,{k1:?},1,1\nCELAS2,2,{k2:?},1,1,2,1\nCONM2,3,1,,{m1:?}\nCONM2,4,2,,{m2:?}\nEIGRL,1,,,2\nENDDATA\n"
    );
    let (r, _dir) = run_deck(&deck);
    let s = r.expect("run");
    let m = modal(&s);
    let (a, b, c) = (m1 * m2, -(m1 * k2 + m2 * (k1 + k2)), k1 * k2);
    let disc = (b * b - 4.0 * a * c).sqrt();
    let lambdas = [(-b - disc) / (2.0 * a), (-b + disc) / (2.0 * a)];
    assert_eq!(m.frequencies_hz.len(), 2);
    for (got, l) in m.frequencies_hz.iter().zip(lambdas) {
        let f = l.sqrt() / TWO_PI;
        assert!((got - f).abs() <= 1e-10 * f, "{got} vs {f}");
    }
    assert!(m.generalized_mass.iter().all(|g| (g - 1.0).abs() < 1e-12));
    assert!(m.residuals.iter().all(|r| *r < 1e-10), "{:?}", m.residuals);
    assert!(m.sturm.is_consistent());
    // every other DOF has no stiffness: AUTOSPC lists them (2 grids × 5 components)
    assert_eq!(s.subcases[0].autospc.len(), 10);
}

/// The same two-DOF system with CMASS2 scalar masses instead of CONM2s: m1 grounded at grid 1
/// T1, and m2 split as a grounded CMASS2 at grid 2 T1 plus a CMASS2 *between* grid 1 T1 and
/// grid 2 T1 of mass mc. A scalar mass between two DOFs has the matrix of a spring,
/// mc [[1, −1], [−1, 1]] (Nastran's CMASS2), so M = [[m1 + mc, −mc], [−mc, m2 + mc]] and the
/// frequencies are the roots of det(K − λM) = 0 (the 2 × 2 quadratic, round-off: 1e-10). The
/// deck warns that CMASS2 masses are not in the mass properties.
#[test]
fn cmass2_scalar_masses_give_the_analytic_2x2_eigenproblem() {
    let (k1, k2, m1, m2, mc): (f64, f64, f64, f64, f64) = (1.0e4, 2.5e3, 2.0, 0.5, 0.3);
    let deck = format!(
        "SOL 103\nCEND\nMETHOD = 1\nBEGIN BULK\nGRID,1,,0.,0.,0.,,23456\nGRID,2,,1.,0.,0.,,23456\n\
         CELAS2,1,{k1:?},1,1\nCELAS2,2,{k2:?},1,1,2,1\nCMASS2,3,{m1:?},1,1\nCMASS2,4,{m2:?},2,1\n\
         CMASS2,5,{mc:?},1,1,2,1\nEIGRL,1,,,2\nENDDATA\n"
    );
    let model = common::build_model(&deck).expect("model");
    assert!(
        model.warnings.iter().any(|w| w
            .message
            .contains("CMASS2 masses are in the mass matrix but not in the mass properties")),
        "{:?}",
        model.warnings
    );
    let (r, _dir) = run_deck(&deck);
    let s = r.expect("run");
    let m = modal(&s);
    // det([[k1 + k2 − λ(m1 + mc), −k2 + λ mc], [−k2 + λ mc, k2 − λ(m2 + mc)]]) = a λ² + b λ + c
    let (ma, mb) = (m1 + mc, m2 + mc);
    let a = ma * mb - mc * mc;
    let b = -((k1 + k2) * mb + k2 * ma) + 2.0 * k2 * mc;
    let c = k1 * k2;
    let disc = (b * b - 4.0 * a * c).sqrt();
    let lambdas = [(-b - disc) / (2.0 * a), (-b + disc) / (2.0 * a)];
    assert_eq!(m.frequencies_hz.len(), 2);
    for (got, l) in m.frequencies_hz.iter().zip(lambdas) {
        let f = l.sqrt() / TWO_PI;
        assert!((got - f).abs() <= 1e-10 * f, "{got} vs {f}");
    }
}

/// RBE2 + CONM2: grid 1 on grounded springs (kt in T1–T3, k4, k5, k6 in R1–R3), a mass m
/// with inertia I (I11 = I22 = I33) at grid 2, at distance d along y, tied to grid 1 by an
/// RBE2. About grid 1 the pairs (T1, R3) and (T3, R1) are coupled by m d, with
/// K = diag(kt, kr), M = [[m, ∓m d], [∓m d, m d² + I]]:
/// m I λ² − (kt (m d² + I) + kr m) λ + kt kr = 0; T2 alone gives kt/m and R2 gives k5/I.
/// (With I = 0 the mass is rank one per pair; see the report about singular M.)
#[test]
fn rbe2_with_offset_conm2_matches_the_rigid_link_eigenproblem() {
    let (kt, k4, k5, k6, m, d, i): (f64, f64, f64, f64, f64, f64, f64) =
        (1.0e4, 2.0e3, 1.0e3, 3.0e3, 2.0, 0.5, 1.0e-3);
    let deck = format!(
        "SOL 103\nCEND\nMETHOD = 1\nBEGIN BULK\nGRID,1,,0.,0.,0.\nGRID,2,,0.,{d:?},0.\nRBE2,9,1,123456,2\nCONM2,10,2,,{m:?},,,,,\n,{i:?},,{i:?},,,{i:?}\n\
         CELAS2,1,{kt:?},1,1\nCELAS2,2,{kt:?},1,2\nCELAS2,3,{kt:?},1,3\nCELAS2,4,{k4:?},1,4\nCELAS2,5,{k5:?},1,5\nCELAS2,6,{k6:?},1,6\nEIGRL,1,,,6\nENDDATA\n"
    );
    let (r, _dir) = run_deck(&deck);
    let s = r.expect("run");
    let got = &modal(&s).frequencies_hz;
    let pair = |kr: f64| {
        let (a, b, c) = (m * i, -(kt * (m * d * d + i) + kr * m), kt * kr);
        let disc = (b * b - 4.0 * a * c).sqrt();
        [(-b - disc) / (2.0 * a), (-b + disc) / (2.0 * a)]
    };
    let mut expected: Vec<f64> = [vec![kt / m, k5 / i], pair(k4).to_vec(), pair(k6).to_vec()]
        .concat()
        .iter()
        .map(|l| l.sqrt() / TWO_PI)
        .collect();
    expected.sort_by(f64::total_cmp);
    assert_eq!(got.len(), 6, "{got:?}");
    for (g, e) in got.iter().zip(&expected) {
        assert!((g - e).abs() <= 1e-9 * e, "{got:?} vs {expected:?}");
    }
}

/// A CHEXA box mesh nx × ny × nz of size lx × ly × lz (grid ids from 1, x fastest).
fn hexa_mesh(n: [usize; 3], l: [f64; 3]) -> String {
    let mut s = String::new();
    let id = |i: usize, j: usize, k: usize| 1 + i + (n[0] + 1) * (j + (n[1] + 1) * k);
    for k in 0..=n[2] {
        for j in 0..=n[1] {
            for i in 0..=n[0] {
                let x = [
                    i as f64 * l[0] / n[0] as f64,
                    j as f64 * l[1] / n[1] as f64,
                    k as f64 * l[2] / n[2] as f64,
                ];
                s += &format!(
                    "GRID,{},,{:.12e},{:.12e},{:.12e}\n",
                    id(i, j, k),
                    x[0],
                    x[1],
                    x[2]
                );
            }
        }
    }
    let mut e = 1;
    for k in 0..n[2] {
        for j in 0..n[1] {
            for i in 0..n[0] {
                let g = [
                    id(i, j, k),
                    id(i + 1, j, k),
                    id(i + 1, j + 1, k),
                    id(i, j + 1, k),
                    id(i, j, k + 1),
                    id(i + 1, j, k + 1),
                    id(i + 1, j + 1, k + 1),
                    id(i, j + 1, k + 1),
                ];
                s += &format!(
                    "CHEXA,{e},1,{},{},{},{},{},{},\n+,{},{}\n",
                    g[0], g[1], g[2], g[3], g[4], g[5], g[6], g[7]
                );
                e += 1;
            }
        }
    }
    s + "PSOLID,1,1\nMAT1,1,2.1e11,,0.3,7850.\n"
}

/// A free-free solid block has exactly six rigid-body modes (≈ 0 Hz; rotational DOFs of the
/// solid-only grids are removed by AUTOSPC), then elastic ones. "≈ 0": below 1e-4 of the first
/// elastic frequency (round-off of a K with entries ~1e11 gives |λ| ~ 1e-5 ‖K‖).
#[test]
fn free_free_solid_block_has_exactly_six_rigid_modes() {
    let deck = format!(
        "SOL 103\nCEND\nMETHOD = 1\nBEGIN BULK\nEIGRL,1,,,9\n{}ENDDATA\n",
        hexa_mesh([3, 2, 2], [0.3, 0.2, 0.2])
    );
    let (r, _dir) = run_deck(&deck);
    let s = r.expect("run");
    let m = modal(&s);
    let f = &m.frequencies_hz;
    assert_eq!(f.len(), 9);
    let elastic = f[6];
    assert!(elastic > 1000.0, "{f:?}");
    assert!(f[..6].iter().all(|x| *x < 1e-4 * elastic), "{f:?}");
    assert!(f[7] >= f[6] && f[8] >= f[7]);
    assert!(m.sturm.is_consistent(), "{:?}", m.sturm);
    assert!(
        m.shift < 0.0,
        "free-free needs a negative shift, got {}",
        m.shift
    );
}

/// A free-free steel plate (Kirchhoff PSHELL: MID3 blank, whose stiff shear penalty makes the
/// rigid-body pivots smaller still) asked for fewer modes than its six rigid-body ones (EIGRL ND = 4)
/// returns four ≈ 0 Hz modes, ascending, with a consistent Sturm check: just above λ ≈ 0
/// K − sM is numerically singular, so the check counts at λ_top + |σ| (was: "matrix is
/// singular at DOF 116"; and the round-off λ of rigid modes came out unsorted). "≈ 0": below
/// 1e-4 of the first elastic frequency (of the ND = 7 run), as for the solid block. Likewise a
/// range V2 = 0.01 Hz, which holds the six rigid-body modes only.
#[test]
fn free_free_plate_with_fewer_modes_than_rigid_ones() {
    let plate = format!(
        "MAT1,1,2.0e11,,0.3,7800.\nPSHELL,1,1,0.003,1\n{}",
        quad_plate([6, 2], [0.3, 0.1], [0.0, 1.0, 0.0], false)
    );
    let run = |nd: usize| {
        run_deck(&format!(
            "SOL 103\nCEND\nMETHOD = 1\nBEGIN BULK\nEIGRL,1,,,{nd}\n{plate}ENDDATA\n"
        ))
    };
    let (all, _dir) = run(7);
    let all = all.expect("ND = 7");
    let elastic = modal(&all).frequencies_hz[6];
    let (few, _dir) = run(4);
    let few = few.expect("ND = 4");
    let m = modal(&few);
    let f = &m.frequencies_hz;
    assert_eq!(f.len(), 4);
    assert!(m.sturm.is_consistent(), "{:?}", m.sturm);
    assert!(
        f.iter().all(|x| *x < 1e-4 * elastic),
        "{f:?} vs elastic {elastic}"
    );
    assert!(f.windows(2).all(|w| w[0] <= w[1]), "{f:?}");
    // a range that holds only the rigid-body modes (V2 = 0.01 Hz): all six, counted at V2 + |σ|
    let (range, _dir) = run_deck(&format!(
        "SOL 103\nCEND\nMETHOD = 1\nBEGIN BULK\nEIGRL,1,,0.01\n{plate}ENDDATA\n"
    ));
    let range = range.expect("V2 = 0.01 Hz");
    let m = modal(&range);
    assert_eq!(m.frequencies_hz.len(), 6, "{:?}", m.frequencies_hz);
    assert!(m.sturm.is_consistent(), "{:?}", m.sturm);
}

/// CHEXA cantilever L = 1, square section h = 0.05 (L/h = 20), 20 × 2 × 2 incompatible-mode
/// hexahedra, clamped face at x = 0. Euler–Bernoulli: f₁ = (1.8751²/2π) √(EI/(ρA L⁴)).
/// Tolerance 3 %: shear deformation and rotary inertia lower f₁ by ≈ 0.3 % at L/h = 20
/// (Timoshenko), the fully clamped face (Poisson contraction prevented) stiffens slightly, and
/// 20 elements along the span leave a discretization error of a few tenths of a percent.
#[test]
fn chexa_cantilever_first_bending_frequency_vs_euler_bernoulli() {
    let (l, h, e, rho) = (1.0, 0.05, 2.1e11, 7850.0);
    let n = [20, 2, 2];
    let mut spc = String::new();
    for k in 0..=n[2] {
        for j in 0..=n[1] {
            spc += &format!("SPC1,1,123,{}\n", 1 + (n[0] + 1) * (j + (n[1] + 1) * k));
        }
    }
    let deck = format!(
        "SOL 103\nCEND\nSPC = 1\nMETHOD = 1\nDISPLACEMENT = ALL\nBEGIN BULK\nEIGRL,1,,,2\n{spc}{}ENDDATA\n",
        hexa_mesh(n, [l, h, h])
    );
    let (r, dir) = run_deck(&deck);
    let s = r.expect("run");
    let m = modal(&s);
    let inertia = h.powi(4) / 12.0;
    let f_eb = 1.8751_f64.powi(2) / TWO_PI * (e * inertia / (rho * h * h * l.powi(4))).sqrt();
    // the section is square: two equal bending modes (y and z)
    for f in &m.frequencies_hz {
        assert!(
            (f - f_eb).abs() < 0.03 * f_eb,
            "{f} vs Euler–Bernoulli {f_eb}"
        );
    }
    assert!(m.shapes_written);
    let file = hdf5_metno::File::open(dir.path().join("out.h5")).expect("open");
    let shapes = file.dataset("results/1/modal/shapes").expect("shapes");
    assert_eq!(shapes.shape(), vec![2, 21 * 3 * 3, 6]);
}

/// PARAM,AUTOSPC,NO on a solid model leaves the rotational DOFs with neither stiffness nor mass
/// (null rows and columns of K and M): as MSC Nastran does (its SOL 103 mode shapes of
/// pyNastran's `elements/modes_elements` deck, run with AUTOSPC NO, are exactly zero at the
/// rotations only rods reach), they are removed still, and the free cube has the modes it has
/// with AUTOSPC: six rigid ones (≈ 0, as in `free_free_solid_block_has_exactly_six_rigid_modes`)
/// and the same first elastic one (to 1e-9: the same f-set and matrices, so round-off).
#[test]
fn null_dofs_are_removed_without_autospc() {
    let run = |param: &str| {
        let deck = format!(
            "SOL 103\nCEND\nMETHOD = 1\nBEGIN BULK\n{param}EIGRL,1,,,7\n{}ENDDATA\n",
            hexa_mesh([1, 1, 1], [1.0, 1.0, 1.0])
        );
        let (r, _dir) = run_deck(&deck);
        let s = r.expect("run");
        (
            modal(&s).frequencies_hz.clone(),
            s.subcases[0].autospc.len(),
        )
    };
    let (with, n_with) = run("");
    let (without, n_without) = run("PARAM,AUTOSPC,NO\n");
    // 8 grids × 3 rotations
    assert_eq!((n_with, n_without), (24, 24));
    assert!(
        without[..6].iter().all(|f| *f < 1e-4 * without[6]),
        "{without:?}"
    );
    assert!(
        (without[6] - with[6]).abs() <= 1e-9 * with[6],
        "{without:?} vs {with:?}"
    );
}

/// PARAM,AUTOSPC,NO with a genuine mechanism in statics: two grids joined by a CELAS2 along T1
/// and held by nothing, so K's T1 rows are not null but singular; the other components are
/// null rows (no element reaches them) and are removed as MSC removes them. The run fails
/// naming a GRID and component 1 and suggesting SPC / AUTOSPC.
#[test]
fn mechanism_without_autospc_names_grid_and_component() {
    let deck = "SOL 101\nCEND\nLOAD = 1\nBEGIN BULK\nPARAM,AUTOSPC,NO\nGRID,1,,0.,0.,0.\nGRID,2,,1.,0.,0.\nCELAS2,1,1000.,1,1,2,1\nFORCE,1,1,,1.,1.,0.,0.\nENDDATA\n";
    let (r, _dir) = run_deck(deck);
    let e = r.expect_err("mechanism").to_string();
    assert!(
        e.contains("component 1")
            && e.contains("GRID ")
            && e.contains("AUTOSPC")
            && e.contains("SPC"),
        "{e}"
    );
}

/// A CQUAD4 plate mesh nx × ny of size lx × ly in the plane spanned by the basic x axis and
/// `y_dir` (a unit vector), grid ids from 1 (x fastest), all elements PID 1; `clamp` adds
/// SPC1 123456 on the grids at x = 0 (set 1).
fn quad_plate(n: [usize; 2], l: [f64; 2], y_dir: [f64; 3], clamp: bool) -> String {
    let mut s = String::new();
    let id = |i: usize, j: usize| 1 + i + (n[0] + 1) * j;
    for j in 0..=n[1] {
        for i in 0..=n[0] {
            let (x, y) = (i as f64 * l[0] / n[0] as f64, j as f64 * l[1] / n[1] as f64);
            s += &format!(
                "GRID,{},,{:.15e},{:.15e},{:.15e}\n",
                id(i, j),
                x + y * y_dir[0],
                y * y_dir[1],
                y * y_dir[2]
            );
            if clamp && i == 0 {
                s += &format!("SPC1,1,123456,{}\n", id(i, j));
            }
        }
    }
    let mut e = 1;
    for j in 0..n[1] {
        for i in 0..n[0] {
            s += &format!(
                "CQUAD4,{e},1,{},{},{},{}\n",
                id(i, j),
                id(i + 1, j),
                id(i + 1, j + 1),
                id(i, j + 1)
            );
            e += 1;
        }
    }
    s
}

/// Modal run of a clamped 8 × 3 aluminium-membrane plate with the given PSHELL and extra
/// material cards (consistent mass).
fn clamped_plate_modes(pshell: &str, modes: usize) -> RunSummary {
    let deck = format!(
        "SOL 103\nCEND\nSPC = 1\nMETHOD = 1\nBEGIN BULK\nPARAM,COUPMASS,1\nEIGRL,1,,,{modes}\nMAT1,1,7.0e10,,0.33,2700.\nMAT1,2,2.0e11,,0.28,7800.\nMAT1,3,{:?},,0.28,7800.\n{pshell}\n{}ENDDATA\n",
        2.0e11 * 0.43,
        quad_plate([8, 3], [0.4, 0.15], [0.0, 1.0, 0.0], true)
    );
    let (r, _dir) = run_deck(&deck);
    r.expect("run")
}

/// Nastran PSHELL: D = (12I/T³)·T³/12·Q2, so 12I/T³ = k with MID2 E gives the same bending
/// stiffness as 12I/T³ = 1 with a MID2 of modulus k·E (same ν); MID1 (membrane, mass, and
/// here MID3 shear) is untouched. The two models have the same K and M to round-off (k·E·T³/12
/// evaluated in two orders: 1 ulp), so every frequency agrees to the eigensolver's round-off:
/// tolerance 1e-10 (residuals are below 1e-10 and the spectrum is well separated).
#[test]
fn pshell_bending_ratio_equals_scaled_bending_modulus() {
    let a = clamped_plate_modes("PSHELL,1,1,0.004,2,0.43,1,0.8,0.5", 6);
    let b = clamped_plate_modes("PSHELL,1,1,0.004,3,1.0,1,0.8,0.5", 6);
    let (fa, fb) = (&modal(&a).frequencies_hz, &modal(&b).frequencies_hz);
    assert_eq!(fa.len(), 6);
    for (x, y) in fa.iter().zip(fb) {
        assert!((x - y).abs() <= 1e-10 * y, "{fa:?}\n{fb:?}");
    }
    // 12I/T³ = 1 with MID2 = 2: the first mode (bending of a thin plate, L/T = 100) scales
    // with √D, i.e. by 1/√0.43, up to the transverse-shear share of its energy (~(T/L)² ≈ 1e-4
    // times a mode factor) — 0.5 % covers that with margin.
    let c = clamped_plate_modes("PSHELL,1,1,0.004,2,1.0,1,0.8,0.5", 6);
    let ratio = modal(&c).frequencies_hz[0] / fa[0];
    assert!((ratio * 0.43_f64.sqrt() - 1.0).abs() < 5e-3, "{ratio}");
}

/// MID2 blank: membrane only. In a flat plate the membrane (T1, T2, R3) and bending (T3, R1,
/// R2) problems decouple exactly, so the membrane-only plate's frequencies are the in-plane
/// frequencies of the full shell: each must appear among the full shell's 30 lowest modes
/// (to 1e-9, the eigensolver's round-off on well-separated modes). AUTOSPC removes T3, R1 and
/// R2 of every free grid (no stiffness there: Nastran's membrane has none either).
#[test]
fn membrane_only_pshell_is_the_in_plane_part_of_the_shell() {
    let membrane = clamped_plate_modes("PSHELL,1,1,0.004,,,,,0.5", 4);
    let full = clamped_plate_modes("PSHELL,1,1,0.004,1,1.0,1,0.8,0.5", 30);
    let free_grids = 9 * 4 - 4;
    let auto = &membrane.subcases[0].autospc;
    assert_eq!(auto.len(), 3 * free_grids, "{auto:?}");
    assert!(
        auto.iter().all(|d| [3, 4, 5].contains(&d.component)),
        "{auto:?}"
    );
    let fm = &modal(&membrane).frequencies_hz;
    let ff = &modal(&full).frequencies_hz;
    assert!(
        fm[0] > ff[0] * 5.0,
        "the in-plane modes lie far above the first bending mode"
    );
    for f in fm {
        let nearest = ff
            .iter()
            .map(|x| (x - f).abs())
            .fold(f64::INFINITY, f64::min);
        assert!(
            nearest <= 1e-9 * f,
            "membrane mode {f} Hz is not among the shell's {ff:?}"
        );
    }
}

/// Nastran: an element offset (ZOFFS) needs MID1 and MID2; a membrane-only PSHELL with ZOFFS
/// is an error naming the rule.
#[test]
fn zoffs_on_a_membrane_only_pshell_is_an_error() {
    let mesh = quad_plate([1, 1], [1.0, 1.0], [0.0, 1.0, 0.0], true)
        .replace("CQUAD4,1,1,1,2,4,3", "CQUAD4,1,1,1,2,4,3,,0.001");
    let deck = format!(
        "SOL 103\nCEND\nSPC = 1\nMETHOD = 1\nBEGIN BULK\nEIGRL,1,,,2\nMAT1,1,7.0e10,,0.33,2700.\nPSHELL,1,1,0.004\n{mesh}ENDDATA\n"
    );
    let (r, _dir) = run_deck(&deck);
    let e = r.expect_err("ZOFFS without MID2").to_string();
    assert!(e.contains("ZOFFS") && e.contains("MID2"), "{e}");
}

/// The rigid-link model above with I = 0: M on grid 1's six DOFs has rank 3 (T2, and one
/// combination per coupled pair) with only R2 massless, so only the exhaustion of the Krylov
/// space can tell that 3 finite modes exist. ND = 6 returns those 3 and the warning, never a
/// mode at an "infinite" frequency. With I = 0 each pair's quadratic degenerates to
/// λ = kt kr / (m (kt d² + kr)) (a massless combination carries no inertia); T2 gives kt/m.
#[test]
fn offset_conm2_without_inertia_returns_only_the_finite_modes() {
    let (kt, k4, k5, k6, m, d): (f64, f64, f64, f64, f64, f64) =
        (1.0e4, 2.0e3, 1.0e3, 3.0e3, 2.0, 0.5);
    let deck = format!(
        "SOL 103\nCEND\nMETHOD = 1\nBEGIN BULK\nGRID,1,,0.,0.,0.\nGRID,2,,0.,{d:?},0.\nRBE2,9,1,123456,2\nCONM2,10,2,,{m:?}\n\
         CELAS2,1,{kt:?},1,1\nCELAS2,2,{kt:?},1,2\nCELAS2,3,{kt:?},1,3\nCELAS2,4,{k4:?},1,4\nCELAS2,5,{k5:?},1,5\nCELAS2,6,{k6:?},1,6\nEIGRL,1,,,6\nENDDATA\n"
    );
    let (r, _dir) = run_deck(&deck);
    let s = r.expect("run");
    let mm = modal(&s);
    let pair = |kr: f64| kt * kr / (m * (kt * d * d + kr));
    let mut expected: Vec<f64> = [kt / m, pair(k4), pair(k6)]
        .iter()
        .map(|l| l.sqrt() / TWO_PI)
        .collect();
    expected.sort_by(f64::total_cmp);
    assert_eq!(mm.frequencies_hz.len(), 3, "{:?}", mm.frequencies_hz);
    for (g, e) in mm.frequencies_hz.iter().zip(&expected) {
        assert!(
            (g - e).abs() <= 1e-9 * e,
            "{:?} vs {expected:?}",
            mm.frequencies_hz
        );
    }
    assert!(mm.sturm.is_consistent(), "{:?}", mm.sturm);
    assert_eq!((mm.massless, mm.finite_exhausted), (1, true));
    assert!(
        s.warnings
            .iter()
            .any(|w| w.contains("only 3 finite mode(s)") && w.contains("ND = 6")),
        "{:?}",
        s.warnings
    );
}

/// `DISPLACEMENT = SET` writes the mode shapes of the SET's grids only (m × k × 6, ids in
/// `shapes_grid_ids`), equal to those rows of the `ALL` run; `NONE` writes no shapes.
#[test]
fn mode_shapes_follow_the_displacement_set() {
    let bulk = "BEGIN BULK\nGRID,1,,0.,0.,0.\nGRID,2,,1.,0.,0.\nGRID,3,,2.,0.,0.\nCELAS2,1,1.0e4,1,1\nCELAS2,2,2.5e3,1,1,2,1\nCELAS2,3,4.0e3,2,1,3,1\nCONM2,4,1,,2.0\nCONM2,5,2,,0.5\nCONM2,6,3,,1.0\nEIGRL,1,,,3\nENDDATA\n";
    let shapes = |case: &str| {
        let (r, dir) = run_deck(&format!("SOL 103\nCEND\n{case}METHOD = 1\n{bulk}"));
        r.expect("run");
        let file = hdf5_metno::File::open(dir.path().join("out.h5")).expect("open");
        let d = file.dataset("results/1/modal/shapes").ok();
        let ids: Option<Vec<u32>> = file
            .dataset("results/1/modal/shapes_grid_ids")
            .ok()
            .map(|d| d.read_raw().expect("ids"));
        d.map(|d| (d.shape(), d.read_raw::<f64>().expect("shapes"), ids))
    };
    let (shape, all, ids) = shapes("DISPLACEMENT = ALL\n").expect("shapes");
    assert_eq!((shape, ids), (vec![3, 3, 6], None));
    let (shape, set, ids) = shapes("SET 7 = 3, 1\nDISPLACEMENT = 7\n").expect("shapes");
    assert_eq!((shape, ids), (vec![3, 2, 6], Some(vec![1, 3])));
    for mode in 0..3 {
        for (k, g) in [0, 2].into_iter().enumerate() {
            assert_eq!(
                set[(mode * 2 + k) * 6..][..6],
                all[(mode * 3 + g) * 6..][..6],
                "mode {mode}, grid row {g}"
            );
        }
    }
    assert!(shapes("DISPLACEMENT = NONE\n").is_none());
}

/// SUPORT on the free-free solid block of the test above, 3-2-1 (grid 1: T1 T2 T3; grid 4, on
/// the x edge: T2 T3; grid 9, on the y edge: T3), a statically determinate r-set: the first six
/// modes are its rigid-body modes at exactly 0 Hz, the elastic ones are those of the run without
/// SUPORT (the same eigenproblem, so to round-off), and the rigid-body error ratio is round-off.
/// The same r-set as a SUPORT1 set selected in case control gives the same modes. An
/// over-determined r-set (grid 9 T1 added) and an under-determined one (grid 1 alone) are refused
/// with the reason. SOL 101 holds the SUPORT DOFs like SPCs: a self-balanced load leaves
/// reactions of round-off there.
#[test]
fn suport_gives_rigid_modes_at_zero_and_the_free_elastic_frequencies() {
    let mesh = hexa_mesh([3, 2, 2], [0.3, 0.2, 0.2]);
    let run = |case: &str, bulk: &str| {
        let deck = format!(
            "SOL 103\nCEND\nMETHOD = 1\n{case}BEGIN BULK\nEIGRL,1,,,9\n{bulk}{mesh}ENDDATA\n"
        );
        run_deck(&deck).0
    };
    let free = run("", "").expect("free");
    let free = modal(&free).frequencies_hz.clone();
    let supported = run("", "SUPORT,1,123,4,23,9,3\n").expect("SUPORT");
    let m = modal(&supported);
    let check = m.suport.clone().expect("r-set reported");
    assert_eq!(check.dofs, 6);
    assert!(check.epsilon <= 1e-9, "ε = {:e}", check.epsilon);
    assert!(
        m.frequencies_hz[..6].iter().all(|f| *f == 0.0),
        "{:?}",
        m.frequencies_hz
    );
    for (k, (a, b)) in m.frequencies_hz.iter().zip(&free).enumerate().skip(6) {
        assert!((a - b).abs() <= 1e-9 * b, "mode {}: {a} vs {b}", k + 1);
    }
    let set = run("SUPORT1 = 5\n", "SUPORT1,5,1,123,4,23,9,3\n").expect("SUPORT1");
    assert_eq!(modal(&set).frequencies_hz, m.frequencies_hz);
    let over = run("", "SUPORT,1,123,4,23,9,13\n").expect_err("over-determined");
    assert!(
        over.to_string().contains("not statically determinate"),
        "{over}"
    );
    let under = run("", "SUPORT,1,123\n").expect_err("under-determined");
    assert!(
        under
            .to_string()
            .contains("do not hold every rigid-body motion"),
        "{under}"
    );
    let statics = format!(
        "SOL 101\nCEND\nLOAD = 2\nSPCFORCES = ALL\nBEGIN BULK\nSUPORT,1,123,4,23,9,3\nFORCE,2,1,,-1.e4,1.,0.,0.\nFORCE,2,4,,1.e4,1.,0.,0.\n{mesh}ENDDATA\n"
    );
    let (file, _dir) = common::run_to_file(&statics);
    let q: Vec<f64> = common::read_dataset(&file.group("results/1/statics").unwrap(), "spc_force");
    let worst = q.iter().fold(0.0_f64, |a, v| a.max(v.abs()));
    assert!(worst <= 1e-6 * 1.0e4, "largest SUPORT reaction {worst:e}");
}
