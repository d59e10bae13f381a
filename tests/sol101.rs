//! SOL 101 (STATICS) through `paraflex::sequence::run`, against analytic references.

mod common;
use common::run_deck;

use paraflex::sequence::RunSummary;
use paraflex::sequence::statics::StaticsSummary;

fn statics(s: &RunSummary, k: usize) -> &StaticsSummary {
    match s.subcases[k].result::<StaticsSummary>() {
        Some(m) => m,
        None => panic!("not statics: {:?}", s.subcases[k].result),
    }
}

const E: f64 = 2.0e11;
const L: f64 = 1.0;
const B: f64 = 0.1;
const T: f64 = 0.01;
const NX: usize = 20;

/// CQUAD4 strip L × B (NX × 1 elements), thickness T, ν = 0 (so plate and beam bending agree),
/// clamped at x = 0 (123456), tip grids tied by an RBE2 to grid 1000 at the tip centre.
fn strip(case: &str, extra: &str) -> String {
    strip_tapered(case, extra, None)
}

/// [`strip`] whose thickness varies linearly from `taper.0` at x = 0 to `taper.1` at x = L,
/// given as CQUAD4 corner thicknesses (TFLAG = 0).
fn strip_tapered(case: &str, extra: &str, taper: Option<(f64, f64)>) -> String {
    let mut s = format!(
        "SOL 101\nCEND\n{case}BEGIN BULK\nPSHELL,1,1,{T:?},1,,1\nMAT1,1,{E:?},,0.,7850.\n{extra}"
    );
    for i in 0..=NX {
        let x = i as f64 * L / NX as f64;
        s += &format!(
            "GRID,{},,{x:.12e},0.,0.\nGRID,{},,{x:.12e},{B:?},0.\n",
            1 + i,
            101 + i
        );
    }
    for i in 0..NX {
        s += &format!(
            "CQUAD4,{},1,{},{},{},{}\n",
            1 + i,
            1 + i,
            2 + i,
            102 + i,
            101 + i
        );
        if let Some((t0, t1)) = taper {
            let t = |k: usize| t0 + (t1 - t0) * k as f64 / NX as f64;
            s += &format!("+,,0,{:?},{:?},{:?},{:?}\n", t(i), t(i + 1), t(i + 1), t(i));
        }
    }
    s += &format!(
        "SPC1,1,123456,1,101\nGRID,1000,,{L:?},{:?},0.\nRBE2,2000,1000,123456,{},{}\nENDDATA\n",
        B / 2.0,
        1 + NX,
        101 + NX
    );
    s
}

/// Tip load P (z) on the RBE2 hub: w = P L³ / (3 E I), I = B T³ / 12. Tolerance 0.5 %: transverse
/// shear adds ≈ 3EI/(κGA L²) ~ 1e-4 at L/T = 100, and MITC4 with 20 elements along the span
/// reproduces the cubic deflection to well below that; ν = 0 removes the plate/beam difference.
/// The sum of SPC forces balances the applied load (forces and moments) to 1e-8 · P L: the
/// imbalance is Σ(K u) over a rigid translation, i.e. the round-off of the shell matrices' rigid
/// modes (entries ~E·T = 2e9 against results ~P = 10), not a solver error (see the spring test
/// below for the 1e-10 balance of exactly rigid-free matrices).
#[test]
fn cquad4_cantilever_tip_deflection_and_reaction_balance() {
    let p = 10.0;
    let deck = strip(
        "SPC = 1\nLOAD = 5\nSPCFORCES = ALL\nDISPLACEMENT = ALL\n",
        &format!("FORCE,5,1000,,{p:?},0.,0.,1.\n"),
    );
    let (r, dir) = run_deck(&deck);
    let s = r.expect("run");
    let st = statics(&s, 0);
    let w = p * L.powi(3) / (3.0 * E * B * T.powi(3) / 12.0);
    let file = hdf5_metno::File::open(dir.path().join("out.h5")).expect("open");
    let u: Vec<f64> = file
        .dataset("results/1/statics/displacement")
        .expect("u")
        .read_raw()
        .expect("read");
    // grid 1000 (the RBE2 hub) is the last grid in id order
    let hub = &u[u.len() - 6..];
    assert!(
        (hub[2] - w).abs() < 5e-3 * w,
        "tip {} vs PL³/3EI {w}",
        hub[2]
    );
    let slope = p * L * L / (2.0 * E * B * T.powi(3) / 12.0);
    assert!(
        (hub[4] + slope).abs() < 5e-3 * slope,
        "tip rotation {} vs −PL²/2EI {}",
        hub[4],
        -slope
    );
    // the tip grids move with the hub (RBE2): any of them may hold the maximum
    assert!(
        (st.max_translation.1 - hub[2]).abs() < 1e-12 * w,
        "{:?}",
        st.max_translation
    );
    let scale = p * L;
    for k in 0..6 {
        assert!(
            (st.reaction[k] + st.applied[k]).abs() <= 1e-8 * scale,
            "component {k}: reaction {:?} vs applied {:?}",
            st.reaction,
            st.applied
        );
    }
    assert!((st.applied[2] - p).abs() < 1e-12);
    // the file holds n×6 displacements and SPC forces, in /model/grid_ids order
    let n = 2 * (NX + 1) + 1;
    for name in ["displacement", "spc_force"] {
        assert_eq!(
            file.dataset(&format!("results/1/statics/{name}"))
                .expect(name)
                .shape(),
            vec![n, 6]
        );
    }
    assert!(
        file.dataset("results/1/statics/strain").is_err(),
        "strain written without STRAIN"
    );
}

/// The strip clamped by 1e20 grounded CELAS2 springs on all six components of its root grids
/// (the usual stand-in for a clamp) deflects as the SPC-clamped strip: the springs' compliance
/// (1e-20) is far below round-off of the tip deflection, so the bound is 1e-9 relative. AUTOSPC
/// used to apply a model-wide floor (1e-14 × the largest diagonal = 1e6 here) that constrained
/// every plate rotation and made the strip 2.5e4 times too stiff.
#[test]
fn stiff_spring_clamp_equals_the_spc_clamp() {
    let p = 10.0;
    let clamped = strip(
        "SPC = 1\nLOAD = 5\n",
        &format!("FORCE,5,1000,,{p:?},0.,0.,1.\n"),
    );
    let springs: String = [1, 101]
        .iter()
        .enumerate()
        .flat_map(|(i, g)| {
            (1..=6).map(move |c| format!("CELAS2,{},1.e20,{g},{c}\n", 9000 + 6 * i + c))
        })
        .collect();
    let sprung = strip(
        "LOAD = 5\n",
        &format!("FORCE,5,1000,,{p:?},0.,0.,1.\n{springs}"),
    )
    .replace("SPC1,1,123456,1,101\n", "");
    let tip = |deck: &str| {
        let (r, _dir) = run_deck(deck);
        let s = r.expect("run");
        let st = statics(&s, 0);
        assert!(
            s.subcases[0].autospc.is_empty(),
            "AUTOSPC: {:?}",
            s.subcases[0].autospc
        );
        st.max_translation.1
    };
    let (a, b) = (tip(&clamped), tip(&sprung));
    assert!(
        (a - b).abs() <= 1e-9 * a,
        "SPC clamp {a:e} vs 1e20 springs {b:e}"
    );
}

/// Two subcases with the same SPC share one factorization; a load scaled by 2 doubles u, and
/// STRAIN writes top/bottom membrane strains: at the root, ε_x(top) = −ε_x(bottom) ≈ M c / (E I).
#[test]
fn two_subcases_share_the_factor_and_strains_follow_beam_theory() {
    let p = 10.0;
    let case = "SPC = 1\nSTRAIN = ALL\nSUBCASE 1\n  LOAD = 5\nSUBCASE 2\n  LOAD = 6\n";
    let deck = strip(
        case,
        &format!("FORCE,5,1000,,{p:?},0.,0.,1.\nLOAD,6,2.,1.,5\n"),
    );
    let (r, dir) = run_deck(&deck);
    let s = r.expect("run");
    let (a, b) = (statics(&s, 0), statics(&s, 1));
    assert!((b.max_component.2 - 2.0 * a.max_component.2).abs() < 1e-12 * a.max_component.2.abs());
    let choleskys = s
        .timings
        .iter()
        .filter(|(n, _)| n.contains("Cholesky"))
        .count();
    assert_eq!(choleskys, 1, "{:?}", s.timings);
    let file = hdf5_metno::File::open(dir.path().join("out.h5")).expect("open");
    let top: Vec<f64> = file
        .dataset("results/1/statics/strain/CQUAD4/top")
        .expect("top")
        .read_raw()
        .expect("read");
    let bottom: Vec<f64> = file
        .dataset("results/1/statics/strain/CQUAD4/bottom")
        .expect("bottom")
        .read_raw()
        .expect("read");
    let ids: Vec<u32> = file
        .dataset("results/1/statics/strain/CQUAD4/ids")
        .expect("ids")
        .read_raw()
        .expect("read");
    assert_eq!(ids.len(), NX);
    // element 1 centroid at x = L/(2 NX): M = P (L − x), ε = M (T/2) / (E I); w > 0 bends the
    // top fibre (z = +T/2) into compression at the root
    let x = 0.5 * L / NX as f64;
    let eps = p * (L - x) * (T / 2.0) / (E * B * T.powi(3) / 12.0);
    assert!(
        (top[0] + eps).abs() < 0.02 * eps && (bottom[0] - eps).abs() < 0.02 * eps,
        "top {} bottom {} vs ±{eps}",
        top[0],
        bottom[0]
    );
}

/// A SUBCOM combines the preceding SUBCASEs with its SUBSEQ coefficients: tip force P and tip
/// moment M as subcases 1 and 2, SUBCOM 3 = 2·(1) + 1·(2) gives w = 2 P L³/(3EI) + M L²/(2EI)
/// (0.5 % as the single-load test above), the displacements are 2 u₁ + u₂ to round-off, the
/// strains (recovered from the combined displacements) follow, and the applied load and SPC
/// reaction of the summary are the combined ones. SUBSEQ with more coefficients than preceding
/// SUBCASEs, and a SUBCOM in SOL 103, are refused at the SUBSEQ.
#[test]
fn subcom_combines_the_preceding_subcases() {
    let (p, m) = (10.0, 3.0);
    let case = "SPC = 1\nSTRAIN = ALL\nSUBCASE 1\n  LOAD = 5\nSUBCASE 2\n  LOAD = 7\n\
                SUBCOM 3\n  SUBSEQ = 2.0, 1.0\nSUBCOM 4\n  SUBSEQ = 3.0\n";
    let deck = strip(
        case,
        &format!("FORCE,5,1000,,{p:?},0.,0.,1.\nMOMENT,7,1000,,{m:?},0.,-1.,0.\n"),
    );
    let (r, dir) = run_deck(&deck);
    let s = r.expect("run");
    let i = B * T.powi(3) / 12.0;
    let w = 2.0 * p * L.powi(3) / (3.0 * E * i) + m * L.powi(2) / (2.0 * E * i);
    let combined = statics(&s, 2);
    assert!(
        (combined.max_translation.1 - w).abs() < 5e-3 * w,
        "{} vs {w}",
        combined.max_translation.1
    );
    assert!((combined.applied[2] - 2.0 * p).abs() < 1e-12 * p);
    assert!((combined.reaction[2] + 2.0 * p).abs() < 1e-8 * p);
    let file = hdf5_metno::File::open(dir.path().join("out.h5")).expect("open");
    let read = |path: &str| -> Vec<f64> { file.dataset(path).expect(path).read_raw().expect(path) };
    for name in ["displacement", "strain/CQUAD4/top"] {
        let (u1, u2, u3) = (
            read(&format!("results/1/statics/{name}")),
            read(&format!("results/2/statics/{name}")),
            read(&format!("results/3/statics/{name}")),
        );
        let scale = u3.iter().fold(0.0f64, |a, x| a.max(x.abs()));
        for k in 0..u3.len() {
            assert!(
                (u3[k] - 2.0 * u1[k] - u2[k]).abs() < 1e-12 * scale,
                "{name}[{k}]"
            );
        }
        // one coefficient applies to the most recent SUBCASE (Nastran's SUBSEQ: Rn to the
        // latest), as MSC's OP2 of pyNastran's other/v10112.bdf shows (its SUBCOM 40)
        let u4 = read(&format!("results/4/statics/{name}"));
        for k in 0..u4.len() {
            assert!((u4[k] - 3.0 * u2[k]).abs() < 1e-12 * scale, "{name}[{k}]");
        }
    }

    let refused = |case: &str, sol: &str| {
        let deck = strip(
            case,
            &format!("FORCE,5,1000,,{p:?},0.,0.,1.\nEIGRL,9,,,2\n"),
        )
        .replacen("SOL 101", sol, 1);
        common::build_model(&deck).expect_err("refused").join("\n")
    };
    let e = refused(
        "SPC = 1\nSUBCASE 1\n  LOAD = 5\nSUBCOM 2\n  SUBSEQ = 1.0, 1.0\n",
        "SOL 101",
    );
    assert!(
        e.contains("SUBCOM 2: SUBSEQ lists 2 coefficients, but 1 SUBCASE(s) precede this SUBCOM"),
        "{e}"
    );
    let e = refused(
        "SPC = 1\nMETHOD = 9\nSUBCASE 1\nSUBCOM 2\n  SUBSEQ = 1.0\n",
        "SOL 103",
    );
    assert!(
        e.contains("SUBCOM 2: SUBCOM combines the results of static subcases"),
        "{e}"
    );
}

/// A LOAD named as a member of another LOAD adds nothing, as in MSC Nastran, which reads the
/// members as simple load sets only: its OP2 of pyNastran's `unit/pload4/cquad4.bdf` (LOAD 8 =
/// 13 (11 L1 + 17 L5 + 1.1 L7), L7 a LOAD) has SPC forces summing to 13 (11 P1 + 17 P5) =
/// 537.485, not to the sum with L7 (1037.985). Here FORCE 1 = 1 N and FORCE 5 = 2 N along z at
/// the tip: the applied load of LOAD 8 is 13 (11 + 34) = 585 N (exact sums), with a warning
/// naming the LOAD.
#[test]
fn a_load_named_in_a_load_adds_nothing() {
    let case = "SPC = 1\nLOAD = 8\n";
    let deck = strip(
        case,
        "FORCE,1,1000,,1.,0.,0.,1.\nFORCE,5,1000,,2.,0.,0.,1.\nLOAD,7,5.,7.,1\n\
         LOAD,8,13.,11.,1,17.,5,1.1,7\n",
    );
    let model = common::build_model(&deck).expect("valid deck");
    assert!(
        model.warnings.iter().any(|w| w
            .message
            .contains("LOAD 8: L = 7 is itself a LOAD and adds nothing")),
        "{:#?}",
        model.warnings
    );
    let (r, _dir) = run_deck(&deck);
    let s = r.expect("run");
    let applied = statics(&s, 0).applied[2];
    assert!((applied - 585.0).abs() < 1e-12 * 585.0, "{applied}");
}

/// A CHEXA cube with PARAM,AUTOSPC,NO: the rotations of solid-only grids are null rows of K
/// (no element reaches them), which MSC Nastran removes even without AUTOSPC (its static
/// displacements are exactly zero there); they are listed like AUTOSPC's, and the translations
/// equal those of the run with AUTOSPC, in the parameter and in the case-control form
/// (`AUTOSPC(NOPRINT) = NO`). A singular K whose rows are not null is still a mechanism
/// (`mechanism_without_autospc_names_grid_and_component`).
#[test]
fn autospc_no_still_removes_the_null_rows_of_solid_grids() {
    let mut deck = String::from(
        "SOL 101\nCEND\nSPC = 1\nLOAD = 2\nDISPLACEMENT = ALL\nBEGIN BULK\nPARAM,AUTOSPC,NO\nPSOLID,1,1\nMAT1,1,2.1e11,,0.3,7850.\nFORCE,2,8,,1.,0.,0.,1.\n",
    );
    let c = [
        [0., 0., 0.],
        [1., 0., 0.],
        [1., 1., 0.],
        [0., 1., 0.],
        [0., 0., 1.],
        [1., 0., 1.],
        [1., 1., 1.],
        [0., 1., 1.],
    ];
    for (k, x) in c.iter().enumerate() {
        deck += &format!("GRID,{},,{:?},{:?},{:?}\n", k + 1, x[0], x[1], x[2]);
    }
    deck += "CHEXA,1,1,1,2,3,4,5,6,\n+,7,8\nSPC1,1,123,1,2,3,4\nENDDATA\n";
    let solve = |deck: &str| {
        let (r, dir) = run_deck(deck);
        let s = r.unwrap_or_else(|e| panic!("{e}"));
        let autospc_on = !deck.contains("AUTOSPC,NO") && !deck.contains("AUTOSPC(NOPRINT) = NO");
        let wording = if autospc_on {
            "AUTOSPC constrained 24 DOF(s)"
        } else {
            "24 DOF(s) that no element reaches (null rows of the solution's matrices) removed although AUTOSPC is off"
        };
        assert!(
            s.warnings.iter().any(|w| w.contains(wording)),
            "{:?}",
            s.warnings
        );
        let u: Vec<f64> = hdf5_metno::File::open(dir.path().join("out.h5"))
            .expect("open")
            .dataset("results/1/statics/displacement")
            .expect("u")
            .read_raw()
            .expect("read");
        (u, s.subcases[0].autospc.len())
    };
    let (with, n_with) = solve(&deck.replace("PARAM,AUTOSPC,NO\n", ""));
    let case_form = deck
        .replace("PARAM,AUTOSPC,NO\n", "")
        .replace("LOAD = 2\n", "LOAD = 2\nAUTOSPC(NOPRINT) = NO\n");
    for deck in [deck.clone(), case_form] {
        let (without, n_without) = solve(&deck);
        assert_eq!((n_with, n_without), (8 * 3, 8 * 3));
        let peak = with.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
        assert!(peak > 0.0);
        for (a, b) in with.iter().zip(&without) {
            assert!((a - b).abs() <= 1e-12 * peak, "{a} vs {b}");
        }
    }
}

/// Springs (rigid-mode free to the last bit) from a loaded grid to three clamped grids along
/// x, y, z: the SPC forces at the clamped grids sum to −F to 1e-10, and the displacement of
/// the loaded grid is F_i / k_i.
#[test]
fn spring_reactions_balance_the_load_to_round_off() {
    let (k, f) = ([1.0e3, 2.0e3, 4.0e3], [3.0, -2.0, 5.0]);
    let deck = format!(
        "SOL 101\nCEND\nSPC = 1\nLOAD = 2\nSPCFORCES = ALL\nBEGIN BULK\nGRID,1,,0.,0.,0.\nGRID,2,,1.,0.,0.\nGRID,3,,0.,1.,0.\nGRID,4,,0.,0.,1.\n\
         CELAS2,1,{:?},1,1,2,1\nCELAS2,2,{:?},1,2,3,2\nCELAS2,3,{:?},1,3,4,3\nSPC1,1,123456,2,3,4\nFORCE,2,1,,1.,{:?},{:?},{:?}\nENDDATA\n",
        k[0], k[1], k[2], f[0], f[1], f[2]
    );
    let (r, dir) = run_deck(&deck);
    let s = r.expect("run");
    let st = statics(&s, 0);
    for (c, fc) in f.iter().enumerate() {
        assert!(
            (st.reaction[c] + fc).abs() <= 1e-10 * 5.0,
            "{:?}",
            st.reaction
        );
    }
    let file = hdf5_metno::File::open(dir.path().join("out.h5")).expect("open");
    let u: Vec<f64> = file
        .dataset("results/1/statics/displacement")
        .expect("u")
        .read_raw()
        .expect("read");
    for c in 0..3 {
        assert!((u[c] - f[c] / k[c]).abs() <= 1e-12, "{:?}", &u[..3]);
    }
}

/// Output requests select what is stored, with one writer for every grid-point output
/// (`GridRows`, shared with SOL 103 shapes): `DISPLACEMENT = SET` and `SPCFORCES = SET` keep the
/// rows of the SET's grids (ids not naming a grid are ignored) with a `<name>_grid_ids` dataset,
/// equal to the same rows of the `ALL` run; `= NONE` and an absent `SPCFORCES`/`STRAIN` store
/// nothing; without any DISPLACEMENT request every grid is written (the documented default);
/// `STRAIN = SET` keeps the SET's elements.
#[test]
fn output_requests_store_only_the_requested_sets() {
    let load = "FORCE,5,1000,,10.,0.,0.,1.\n";
    let read = |dir: &tempfile::TempDir, name: &str| -> Option<(Vec<usize>, Vec<f64>)> {
        let file = hdf5_metno::File::open(dir.path().join("out.h5")).expect("open");
        let d = file.dataset(&format!("results/1/statics/{name}")).ok()?;
        Some((d.shape(), d.read_raw().expect("read")))
    };
    let read_ids = |dir: &tempfile::TempDir, name: &str| -> Vec<u32> {
        let file = hdf5_metno::File::open(dir.path().join("out.h5")).expect("open");
        file.dataset(&format!("results/1/statics/{name}"))
            .expect(name)
            .read_raw()
            .expect("read")
    };
    // reference run: everything for every grid; grid rows in increasing id order
    let (all, all_dir) = run_deck(&strip(
        "SPC = 1\nLOAD = 5\nDISPLACEMENT = ALL\nSPCFORCES = ALL\n",
        load,
    ));
    all.expect("run");
    let ids: Vec<u32> = (1..=NX as u32 + 1)
        .chain(101..=101 + NX as u32)
        .chain([1000])
        .collect::<std::collections::BTreeSet<_>>()
        .into_iter()
        .collect();
    let (shape, u_all) = read(&all_dir, "displacement").expect("displacement");
    assert_eq!(shape, vec![ids.len(), 6]);
    let (_, q_all) = read(&all_dir, "spc_force").expect("spc_force");
    let row = |v: &[f64], id: u32| -> Vec<f64> {
        let g = ids.iter().position(|&x| x == id).expect("grid");
        v[6 * g..6 * g + 6].to_vec()
    };

    // SETs: 99999 is no grid; SET 2 lists the clamped grids and one free grid
    let case = "SET 1 = 1000, 3, 99999, 2\nSET 2 = 1, 101, 5\nSET 3 = 2, 4\nSPC = 1\nLOAD = 5\nDISPLACEMENT = 1\nSPCFORCES(PLOT) = 2\nSTRAIN = 3\n";
    let (r, dir) = run_deck(&strip(case, load));
    r.expect("run");
    let (shape, u) = read(&dir, "displacement").expect("displacement");
    assert_eq!(shape, vec![3, 6]);
    assert_eq!(read_ids(&dir, "displacement_grid_ids"), vec![2, 3, 1000]);
    let (shape, q) = read(&dir, "spc_force").expect("spc_force");
    assert_eq!(shape, vec![3, 6]);
    assert_eq!(read_ids(&dir, "spc_force_grid_ids"), vec![1, 5, 101]);
    for (k, id) in [2, 3, 1000].into_iter().enumerate() {
        assert_eq!(
            u[6 * k..6 * k + 6],
            row(&u_all, id)[..],
            "displacement of GRID {id}"
        );
    }
    for (k, id) in [1, 5, 101].into_iter().enumerate() {
        assert_eq!(
            q[6 * k..6 * k + 6],
            row(&q_all, id)[..],
            "SPC force of GRID {id}"
        );
    }
    assert!(
        q[..6].iter().any(|x| x.abs() > 1.0),
        "the clamped grid 1 carries a reaction: {:?}",
        &q[..6]
    );
    assert_eq!(read_ids(&dir, "strain/CQUAD4/ids"), vec![2, 4]);
    assert!(
        read(&all_dir, "displacement_grid_ids").is_none(),
        "ALL writes no id list (rows are /model/grid_ids)"
    );

    // NONE stores nothing; absent SPCFORCES / STRAIN store nothing
    let (r, dir) = run_deck(&strip("SPC = 1\nLOAD = 5\nDISPLACEMENT = NONE\n", load));
    r.expect("run");
    for name in ["displacement", "spc_force", "strain"] {
        assert!(
            read(&dir, name).is_none()
                && hdf5_metno::File::open(dir.path().join("out.h5"))
                    .unwrap()
                    .group(&format!("results/1/statics/{name}"))
                    .is_err(),
            "{name} written"
        );
    }

    // no DISPLACEMENT request at all: the default writes every grid
    let (r, dir) = run_deck(&strip("SPC = 1\nLOAD = 5\n", load));
    r.expect("run");
    assert_eq!(
        read(&dir, "displacement").expect("default displacement"),
        (vec![ids.len(), 6], u_all)
    );
}

/// PARAM,MAXRATIO sets the diagonal/pivot ratio SOL 101 accepts: the MacNeal–Harder thin twisted
/// beam (t = 0.0032, largest pivot ratio 9.8e6 with the full-strength drilling membrane; 1.3e7,
/// above Nastran's default 1e7, before it) is refused at PARAM,MAXRATIO,1e6 with the grid and
/// component named, and solved with the deck's PARAM,MAXRATIO,1e10.
#[test]
fn maxratio_param_admits_an_ill_conditioned_thin_shell() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/decks/verify/hard/mh_twisted_thin_cquad4.dat"
    );
    let text = std::fs::read_to_string(path).expect("deck");
    assert!(text.contains("PARAM,MAXRATIO,"));
    let (ok, _dir) = run_deck(&text);
    ok.expect("solved with PARAM,MAXRATIO,1e10");
    let low: String = text
        .lines()
        .map(|l| {
            if l.starts_with("PARAM,MAXRATIO") {
                "PARAM,MAXRATIO,1e6\n".to_string()
            } else {
                format!("{l}\n")
            }
        })
        .collect();
    let (err, _dir) = run_deck(&low);
    let msg = err.expect_err("refused at MAXRATIO 1e6").to_string();
    assert!(msg.contains("GRID") && msg.contains("pivot ratio"), "{msg}");
}
/// Springs in series ground –k– grid 1 –K– grid 2, F on grid 2, K/k = 1e9: the pivot ratio
/// of the factor is about K/k (whatever the ordering), above MAXRATIO's default 1e7. Nastran's
/// default BAILOUT = 0 stops (UFM 9050) and so does paraflex, naming the DOF and BAILOUT;
/// PARAM,BAILOUT,-1 goes on with a warning and the exact answer u₁ = F/k, u₂ = F/k + F/K.
/// Without the ground spring K is exactly singular: an error even with BAILOUT = -1.
#[test]
fn bailout_lets_a_pivot_ratio_above_maxratio_through_but_not_a_singularity() {
    let deck = |bailout: &str, ground: &str| {
        format!(
            "SOL 101\nCEND\nLOAD = 1\nBEGIN BULK\n{bailout}GRID,1,,0.,0.,0.,,23456\n\
             GRID,2,,1.,0.,0.,,23456\n{ground}CELAS2,12,1.e9,1,1,2,1\nFORCE,1,2,,3.,1.,0.,0.\nENDDATA\n"
        )
    };
    let soft = "CELAS2,11,1.,1,1\n";
    let (err, _dir) = run_deck(&deck("", soft));
    let msg = err.expect_err("stops at the default BAILOUT").to_string();
    assert!(
        msg.contains("GRID") && msg.contains("pivot ratio") && msg.contains("PARAM,BAILOUT,-1"),
        "{msg}"
    );
    let (ok, dir) = run_deck(&deck("PARAM,BAILOUT,-1\n", soft));
    let summary = ok.expect("runs with BAILOUT = -1");
    let warned = summary.warnings.iter().any(|w| {
        w.contains("exceeds PARAM,MAXRATIO") && w.contains("BAILOUT") && w.contains("GRID")
    });
    assert!(warned, "{:?}", summary.warnings);
    let file = hdf5_metno::File::open(dir.path().join("out.h5")).expect("open");
    let u: Vec<f64> = file
        .dataset("results/1/statics/displacement")
        .unwrap()
        .read_raw()
        .unwrap();
    // an ill-conditioned but regular 2 × 2 system: relative error ~ ε · K/k
    let (u1, u2) = (3.0, 3.0 + 3.0e-9);
    assert!((u[0] - u1).abs() < 1e-6 * u1, "u1 = {}", u[0]);
    assert!((u[6] - u2).abs() < 1e-6 * u2, "u2 = {}", u[6]);
    let (err, _dir) = run_deck(&deck("PARAM,BAILOUT,-1\n", ""));
    let msg = err.expect_err("a singular K stops").to_string();
    assert!(
        msg.contains("singular") && !msg.contains("BAILOUT"),
        "{msg}"
    );
}

/// Linearly tapered cantilever strip (t = T at the root to T/2 at the tip, CQUAD4 corner
/// thicknesses), tip load P: unit-load integral of Euler–Bernoulli bending plus shear,
/// δ = ∫₀ᴸ P(L−x)²/(E I(x)) dx + ∫₀ᴸ P/(κ G B t(x)) dx, I = B t³/12, t(x) = t0 + s x, in closed
/// form δ = 12P/(E B s³) [ln(t1/t0) + 2 t1 (1/t1 − 1/t0) − t1²/2 (1/t1² − 1/t0²)] + P ln(t1/t0)/(κ G B s)
/// (G = E/2 at ν = 0, κ = 5/6). Measured error −3.32e-4 with NX = 20 and −8.35e-5 with NX = 40
/// (ratio 3.98: the O(h²) discretization error of the displacement-based element, converging to
/// the formula), hence the tolerance 1e-3 (3× the measured error). With the section taken at the
/// Gauss points each element integrates EI ∝ t³ exactly (kernel test
/// `tapered_quad_integrates_bending_thickness_cubed_exactly`); the former mean corner thickness
/// gave −9.4e-5 and −2.4e-5 here, closer only because its too-soft section (mean³ < mean of t³)
/// partly cancels the too-stiff discretization. This test covers the deck path (TFLAG = 0
/// corners → per-point sections).
#[test]
fn tapered_cantilever_tip_deflection() {
    let (p, t0, t1) = (10.0, T, T / 2.0);
    let deck = strip_tapered(
        "SPC = 1\nLOAD = 5\n",
        &format!("FORCE,5,1000,,{p:?},0.,0.,1.\n"),
        Some((t0, t1)),
    );
    let (r, dir) = run_deck(&deck);
    r.expect("run");
    let file = hdf5_metno::File::open(dir.path().join("out.h5")).expect("open");
    let u: Vec<f64> = file
        .dataset("results/1/statics/displacement")
        .expect("u")
        .read_raw()
        .expect("read");
    let tip = u[u.len() - 6 + 2];
    let s = (t1 - t0) / L;
    let bending = 12.0 * p / (E * B * s.powi(3))
        * ((t1 / t0).ln() + 2.0 * t1 * (1.0 / t1 - 1.0 / t0)
            - 0.5 * t1 * t1 * (1.0 / (t1 * t1) - 1.0 / (t0 * t0)));
    let shear = p * (t1 / t0).ln() / (5.0 / 6.0 * E / 2.0 * B * s);
    let exact = bending + shear;
    assert!(
        (tip - exact).abs() < 1e-3 * exact,
        "tip {tip} vs {exact} ({:+.3e})",
        tip / exact - 1.0
    );
}

/// `GRDSET` and `CORD2S`: the cantilever strip (no hub; a tip load on one tip corner, which
/// twists it) with every GRID's location written in a tilted spherical system (r, θ, φ, computed
/// here from the basic coordinates with the textbook formulas) whose id comes from a GRDSET CP,
/// and PS = 4 (no twist) from the GRDSET, gives the displacements of the strip with explicit basic
/// GRIDs and PS = 4 on each;
/// grid 1 keeps an explicit CP = 0 (a given field overrides the GRDSET). Locations round-trip
/// through the spherical system to ~1e-16 relative, so the displacements agree to 1e-9 of their
/// largest value (errors amplify by at most cond(K) ε ~ 1e-10 here). A wrong spherical
/// conversion moves grids by O(L) and the results by O(1); a GRDSET PS not applied lets the strip
/// twist (O(1) change).
#[test]
fn grdset_defaults_and_cord2s_locations_give_the_basic_strip() {
    let case = "SPC = 1\nLOAD = 3\nDISPLACEMENT = ALL\n";
    let load = format!("FORCE,3,{},,10.,0.,0.,1.\n", 1 + NX);
    let lines: Vec<String> = strip(case, &load)
        .lines()
        .filter(|l| !l.starts_with("GRID,1000") && !l.starts_with("RBE2"))
        .map(str::to_string)
        .collect();
    let basic: String = lines
        .iter()
        .map(|l| match l.starts_with("GRID") {
            true => format!("{l},,4\n"),
            false => format!("{l}\n"),
        })
        .collect();
    let (origin, axis_b, plane_c) = ([0.3, -0.2, 0.5], [0.5, 0.1, 1.4], [1.2, -0.3, 0.6]);
    let sub = |a: [f64; 3], b: [f64; 3]| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let cross = |a: [f64; 3], b: [f64; 3]| {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    };
    let unit = |a: [f64; 3]| {
        let n = dot(a, a).sqrt();
        [a[0] / n, a[1] / n, a[2] / n]
    };
    let k = unit(sub(axis_b, origin));
    let j = unit(cross(k, sub(plane_c, origin)));
    let i = cross(j, k);
    let spherical = |p: [f64; 3]| {
        let d = sub(p, origin);
        let (x, y, z) = (dot(d, i), dot(d, j), dot(d, k));
        let r = (x * x + y * y + z * z).sqrt();
        (r, (z / r).acos().to_degrees(), y.atan2(x).to_degrees())
    };
    let system = format!(
        "CORD2S,9,,{:?},{:?},{:?},{:?},{:?},{:?},\n,{:?},{:?},{:?}\nGRDSET,,9,,,,,4\n",
        origin[0],
        origin[1],
        origin[2],
        axis_b[0],
        axis_b[1],
        axis_b[2],
        plane_c[0],
        plane_c[1],
        plane_c[2]
    );
    let mut tilted = String::new();
    for line in &lines {
        let f: Vec<&str> = line.split(',').collect();
        if line.starts_with("BEGIN BULK") {
            tilted += &format!("{line}\n{system}");
        } else if f[0] == "GRID" && f[1] != "1" {
            let p = [f[3], f[4], f[5]].map(|v| v.parse::<f64>().expect("coordinate"));
            let (r, t, ph) = spherical(p);
            tilted += &format!("GRID,{},,{r:.17e},{t:.17e},{ph:.17e}\n", f[1]);
        } else if f[0] == "GRID" {
            tilted += &format!("GRID,1,0,{},{},{}\n", f[3], f[4], f[5]);
        } else {
            tilted += line;
            tilted += "\n";
        }
    }
    let (u_basic, u_tilted) = (displacements(&basic), displacements(&tilted));
    let scale = u_basic.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    assert!(scale > 1e-6, "the strip deflects: {scale:e}");
    let diff = u_basic
        .iter()
        .zip(&u_tilted)
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    assert!(
        diff <= 1e-9 * scale,
        "GRDSET/CORD2S strip differs by {diff:e} of {scale:e}"
    );
}

/// A rod along basic x whose tip grid lies on the polar axis (at the origin) of a cylindrical
/// CD: there its directions are those of azimuth 0, e_r = the system's i (basic y here) and
/// e_θ = k × i (basic −x). With the tip held in e_r, z and the rotations and loaded along x,
/// the only free direction is e_θ, so the rod stretches by the closed form F L/(E A). Were e_r
/// taken along x the tip could not move (u = 0). The CORD2C is written as one free-field line
/// of 12 fields, which runs on into its second row (C = (1, 1, 0)).
#[test]
fn grid_on_the_polar_axis_of_its_cd_uses_azimuth_zero() {
    let (length, e, area, force) = (2.0, 7.0e10, 1.0e-4, 1.0e3);
    let deck = format!(
        "SOL 101\nCEND\nSPC = 1\nLOAD = 2\nDISPLACEMENT = ALL\nBEGIN BULK\n\
         CORD2C,5,0, {length:?},0.,0., {length:?},0.,1., {length:?},1.,0.\n\
         GRID,1,,0.,0.,0.\nGRID,2,,{length:?},0.,0.,5\n\
         CROD,10,11,1,2\nPROD,11,12,{area:?}\nMAT1,12,{e:?},,0.3\n\
         SPC1,1,123456,1\nSPC1,1,13456,2\nFORCE,2,2,,{force:?},1.,0.,0.\nENDDATA\n"
    );
    let (r, dir) = run_deck(&deck);
    r.expect("run");
    let u: Vec<f64> = hdf5_metno::File::open(dir.path().join("out.h5"))
        .expect("open")
        .dataset("results/1/statics/displacement")
        .expect("u")
        .read_raw()
        .expect("read");
    let expected = force * length / (e * area);
    // One rod element is exact for an axial end load: round-off of the 2×2 solve only.
    assert!(
        (u[6] - expected).abs() <= 1e-12 * expected,
        "tip u_x = {:e}, F L/(E A) = {expected:e}",
        u[6]
    );
    assert!(u[7].abs() <= 1e-15 && u[8].abs() <= 1e-15, "{:?}", &u[6..9]);
}

/// A rod of four CROD elements (E A / element length k = E·A·4/L) held at x = 0 and pulled to
/// d at x = L by an SPCD on a DOF of the SPC set. Nodal values of a linear rod are exact, so the
/// analytic answers hold to round-off:
/// - subcase 1, `LOAD = 7` (the SPCD set): u(x) = d·x/L, SPC forces ∓E A d/L at the ends; the
///   SPC card's own D (5e-3 on that DOF) is replaced by the SPCD value, as in Nastran;
/// - subcase 2, `LOAD = 10` = 0.5·(2·SPCD 7 + 1·FORCE 8): the same d plus a force F/2 at mid
///   span: u(L/2) = d/2 + (F/2)·L/(4 E A) (two halves, each of stiffness 2 E A/L, in parallel),
///   SPC force at x = L: E A d/L − F/4, at x = 0: −E A d/L − F/4;
/// - subcase 3, `LOAD = 8` (the FORCE alone): the SPC's D = 5e-3 holds again.
#[test]
fn spcd_enforces_the_rod_end_directly_and_through_a_load_combination() {
    let (e, a, l, d, f) = (7.0e10, 1.0e-4, 2.0, 1.0e-3, 3.0e4);
    let mut deck = format!(
        "SOL 101\nCEND\nSPC = 1\nSPCFORCES = ALL\nSUBCASE 1\nLOAD = 7\nSUBCASE 2\nLOAD = 10\nSUBCASE 3\nLOAD = 8\nBEGIN BULK\n\
         MAT1,1,{e:?},,0.3\nPROD,1,1,{a:?}\nSPC1,1,123456,1\nSPC,1,5,1,5.e-3\nSPCD,7,5,1,{d:?}\n\
         FORCE,8,3,,{f:?},1.,0.,0.\nLOAD,10,0.5,2.,7,1.,8\n"
    );
    for i in 0..5 {
        deck += &format!("GRID,{},,{:?},0.,0.,,23456\n", i + 1, l * i as f64 / 4.0);
    }
    for i in 0..4 {
        deck += &format!("CROD,{},1,{},{}\n", i + 1, i + 1, i + 2);
    }
    deck += "ENDDATA\n";
    let (r, dir) = run_deck(&deck);
    r.unwrap_or_else(|e| panic!("{e}"));
    let file = hdf5_metno::File::open(dir.path().join("out.h5")).expect("open");
    let read = |sub: u32, name: &str| -> Vec<f64> {
        file.dataset(&format!("results/{sub}/statics/{name}"))
            .expect(name)
            .read_raw()
            .expect("read")
    };
    let ea_l = e * a / l;
    let tol = 1e-12 * d;
    let (u, q) = (read(1, "displacement"), read(1, "spc_force"));
    for i in 0..5 {
        assert!(
            (u[6 * i] - d * i as f64 / 4.0).abs() <= tol,
            "{i}: {}",
            u[6 * i]
        );
    }
    assert!((q[24] - ea_l * d).abs() <= 1e-9 * ea_l * d, "{}", q[24]);
    assert!((q[0] + ea_l * d).abs() <= 1e-9 * ea_l * d, "{}", q[0]);
    let (u, q) = (read(2, "displacement"), read(2, "spc_force"));
    let mid = d / 2.0 + (f / 2.0) / (4.0 * ea_l);
    assert!((u[12] - mid).abs() <= tol, "{} vs {mid}", u[12]);
    assert!((u[24] - d).abs() <= tol, "{}", u[24]);
    assert!(
        (q[24] - (ea_l * d - f / 4.0)).abs() <= 1e-9 * f,
        "{}",
        q[24]
    );
    assert!((q[0] - (-ea_l * d - f / 4.0)).abs() <= 1e-9 * f, "{}", q[0]);
    let u = read(3, "displacement");
    assert!((u[24] - 5.0e-3).abs() <= tol, "{}", u[24]);
}

/// An SPCD on a DOF that no SPC of the subcase constrains is refused, naming the SPCD card, its
/// file:line and the DOF (Nastran's rule), instead of being dropped or applied as a load.
#[test]
fn spcd_on_an_unconstrained_dof_is_refused_with_its_card_and_line() {
    let deck = "SOL 101\nCEND\nSPC = 1\nLOAD = 7\nBEGIN BULK\nMAT1,1,7.e10,,0.3\nPROD,1,1,1.e-4\n\
                GRID,1,,0.,0.,0.,,23456\nGRID,2,,1.,0.,0.,,23456\nCROD,1,1,1,2\nSPC1,1,1,1\n\
                SPCD,7,2,1,1.e-3\nENDDATA\n";
    let (r, _dir) = run_deck(deck);
    let message = r
        .expect_err("an SPCD on a free DOF must be refused")
        .to_string();
    assert!(
        message.contains("SPCD 7 at")
            && message.contains("deck.dat:12")
            && message.contains("GRID 2 component 1 is not constrained"),
        "{message}"
    );
}

/// FORCE1, FORCE2, MOMENT1, MOMENT2 on grid 1, held by six grounded CELAS2 springs kᵢ (one per
/// component), so uᵢ = Pᵢ/kᵢ exactly. Directions from the grids' positions: FORCE1/MOMENT1
/// along G1 → G2 = (0, 2, 2)/√8; FORCE2/MOMENT2 along (G2 − G1) × (G4 − G3) = (0, 2, 2) ×
/// (3, 0, 0) = (0, 6, −6), normalized. Grids 2–5 carry nothing (AUTOSPC holds them).
/// Coincident direction grids are refused at the card.
#[test]
fn force1_force2_moment1_moment2_follow_their_grids() {
    let k = [1.0e3, 2.0e3, 4.0e3, 5.0e2, 2.5e2, 8.0e2];
    let (f1, f2, m1, m2) = (30.0, -12.0, 7.0, 5.0);
    let mut deck = String::from("SOL 101\nCEND\nLOAD = 1\nBEGIN BULK\nGRID,1,,0.,0.,0.\n");
    deck += "GRID,2,,1.,0.,0.\nGRID,3,,1.,2.,2.\nGRID,4,,0.,0.,1.\nGRID,5,,3.,0.,1.\n";
    for (c, kc) in k.iter().enumerate() {
        deck += &format!("CELAS2,{},{kc:?},1,{}\n", 10 + c, c + 1);
    }
    deck += &format!(
        "FORCE1,1,1,{f1:?},2,3\nFORCE2,1,1,{f2:?},2,3,4,5\nMOMENT1,1,1,{m1:?},2,3\nMOMENT2,1,1,{m2:?},2,3,4,5\nENDDATA\n"
    );
    let (file, _dir) = common::run_to_file(&deck);
    let u: Vec<f64> = common::read_dataset(
        &file.group("results/1/statics").expect("statics"),
        "displacement",
    );
    let s = std::f64::consts::FRAC_1_SQRT_2;
    let p = [
        0.0,
        (f1 + f2) * s,
        (f1 - f2) * s,
        0.0,
        (m1 + m2) * s,
        (m1 - m2) * s,
    ];
    for c in 0..6 {
        let want = p[c] / k[c];
        assert!(
            (u[c] - want).abs() <= 1e-13,
            "component {}: {} vs {want}",
            c + 1,
            u[c]
        );
    }
    let bad = deck.replace("FORCE1,1,1,30.0,2,3", "FORCE1,1,1,30.0,2,2");
    let e = common::build_model(&bad).unwrap_err().join("\n");
    assert!(
        e.contains("FORCE1 1") && e.contains("G1 and G2 are the same grid"),
        "{e}"
    );
    let parallel = deck.replace("GRID,5,,3.,0.,1.", "GRID,5,,0.,2.,3.");
    let e = common::build_model(&parallel).unwrap_err().join("\n");
    assert!(e.contains("FORCE2 1") && e.contains("has no length"), "{e}");
}

/// Static displacements (n × 6, grid id order) of a deck.
fn displacements(deck: &str) -> Vec<f64> {
    let (r, dir) = run_deck(deck);
    r.expect("run");
    hdf5_metno::File::open(dir.path().join("out.h5"))
        .expect("open")
        .dataset("results/1/statics/displacement")
        .expect("u")
        .read_raw()
        .expect("read")
}

/// A 4 × 3 CQUAD4 plate 1.2 × 0.9 (grid 10·i + j + 1 at column i, row j; interior grids moved
/// off the regular lattice so the elements are general quadrilaterals), every element with
/// material angle THETA = 30°, PSHELL 1 (`pshell`, with the material cards `materials`),
/// clamped along x = 0, loaded at the x = 1.2 corners in z and along the edge in x and y.
fn skew_plate(pshell: &str, materials: &str) -> String {
    let mut s = format!(
        "SOL 101\nCEND\nSPC = 1\nLOAD = 5\nDISPLACEMENT = ALL\nBEGIN BULK\n{pshell}\n{materials}"
    );
    for i in 0..=4 {
        for j in 0..=3 {
            let (x, y) = skew_xy(i, j);
            s += &format!("GRID,{},,{x:?},{y:?},0.\n", 10 * i + j + 1);
        }
    }
    for i in 0..4 {
        for j in 0..3 {
            let g = 10 * i + j + 1;
            s += &format!(
                "CQUAD4,{},1,{},{},{},{},30.\n",
                10 * i + j + 1,
                g,
                g + 10,
                g + 11,
                g + 1
            );
        }
    }
    s += "SPC1,1,123456,1,2,3,4\nFORCE,5,41,,1.,0.3,0.2,1.\nFORCE,5,44,,1.,-0.1,0.4,-0.5\n\
          MOMENT,5,42,,0.2,1.,0.,0.\nENDDATA\n";
    s
}

/// Location of grid (column `i`, row `j`) of [`skew_plate`]: interior grids off the lattice.
fn skew_xy(i: usize, j: usize) -> (f64, f64) {
    let interior = i > 0 && i < 4 && j > 0 && j < 3;
    let (dx, dy) = if interior {
        (0.04 * ((i + j) % 2) as f64, -0.03 * (j % 2) as f64)
    } else {
        (0.0, 0.0)
    };
    (0.3 * i as f64 + dx, 0.3 * j as f64 + dy)
}

/// Largest difference between two displacement sets, relative to the largest displacement.
fn relative_difference(a: &[f64], b: &[f64]) -> f64 {
    let scale = a.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    assert!(scale > 0.0, "the plate moves");
    let diff = a
        .iter()
        .zip(b)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
    diff / scale
}

/// MAT2 in all three PSHELL roles against the cards whose matrices it spells out: a MAT2 equal
/// to a MAT1's plane-stress matrix E/(1−ν²)[[1, ν, 0], [ν, 1, 0], [0, 0, (1−ν)/2]] (MID3: a MAT2
/// with G11 = G22 = E/(2(1+ν))), and one equal to a MAT8's Q (Q11 = E1/(1−ν12ν21), Q12 =
/// ν12 E2/(1−ν12ν21), Q22 = E2/(1−ν12ν21), Q66 = G12; MID3: diag(G1Z, G2Z)), on a distorted
/// plate with material angle 30° loaded in bending, torsion and in-plane. The element
/// matrices are the same numbers reached by another route, so the displacements agree to
/// round-off (bound 1e-10 of the largest: cond(K) · ε ~ 1e-11 here); a transverse-shear matrix
/// taken from the wrong Gij, a G13/G23 coupling dropped or the material angle ignored for MAT2
/// changes them by O(1e-3) or more. The first four natural frequencies of the MAT8 and MAT2
/// plates agree to 1e-10 too (the mass is MID1's RHO in both).
#[test]
fn mat2_equals_the_mat1_and_mat8_it_spells_out() {
    let (e, nu) = (7.0e10, 0.3);
    let c = e / (1.0 - nu * nu);
    let g = e / (2.0 * (1.0 + nu));
    let pshell = "PSHELL,1,1,0.02,2,,3";
    let mat1 = format!("MAT1,1,{e:?},,{nu:?},2700.\nMAT1,2,{e:?},,{nu:?}\nMAT1,3,{e:?},,{nu:?}\n");
    let iso = format!(
        "MAT2,1,{:?},{:?},0.,{c:?},0.,{:?},2700.\nMAT2,2,{:?},{:?},0.,{c:?},0.,{:?}\nMAT2,3,{g:?},0.,,{g:?}\n",
        c,
        c * nu,
        c * (1.0 - nu) / 2.0,
        c,
        c * nu,
        c * (1.0 - nu) / 2.0
    );
    let d = relative_difference(
        &displacements(&skew_plate(pshell, &mat1)),
        &displacements(&skew_plate(pshell, &iso)),
    );
    assert!(d < 1e-10, "MAT2 (isotropic) vs MAT1: {d:e}");

    let (e1, e2, nu12, g12, g1z, g2z) = (1.4e11, 1.0e10, 0.3, 5.0e9, 4.0e9, 3.0e9);
    let nu21 = nu12 * e2 / e1;
    let den = 1.0 - nu12 * nu21;
    let mat8 = format!(
        "MAT8,1,{e1:?},{e2:?},{nu12:?},{g12:?},{g1z:?},{g2z:?},1600.\n\
         MAT8,2,{e1:?},{e2:?},{nu12:?},{g12:?},{g1z:?},{g2z:?}\n\
         MAT8,3,{e1:?},{e2:?},{nu12:?},{g12:?},{g1z:?},{g2z:?}\n"
    );
    let q = format!(
        "{:?},{:?},0.,{:?},0.,{g12:?}",
        e1 / den,
        nu12 * e2 / den,
        e2 / den
    );
    let ortho = format!("MAT2,1,{q},1600.\nMAT2,2,{q}\nMAT2,3,{g1z:?},0.,,{g2z:?}\n");
    let d = relative_difference(
        &displacements(&skew_plate(pshell, &mat8)),
        &displacements(&skew_plate(pshell, &ortho)),
    );
    assert!(d < 1e-10, "MAT2 (orthotropic) vs MAT8: {d:e}");

    // the mass comes from MID1's RHO: the modes of the MAT8 and MAT2 plates agree as closely
    let frequencies = |materials: &str| -> Vec<f64> {
        let deck = skew_plate(pshell, materials)
            .replace("SOL 101", "SOL 103")
            .replace("LOAD = 5", "METHOD = 9")
            .replace("ENDDATA", "EIGRL,9,,,4\nENDDATA");
        let (r, dir) = run_deck(&deck);
        r.expect("run");
        hdf5_metno::File::open(dir.path().join("out.h5"))
            .expect("open")
            .dataset("results/1/modal/frequency_hz")
            .expect("frequencies")
            .read_raw()
            .expect("read")
    };
    let (f8, f2) = (frequencies(&mat8), frequencies(&ortho));
    assert_eq!(f8.len(), 4);
    for (a, b) in f8.iter().zip(&f2) {
        assert!((a - b).abs() < 1e-10 * a, "MAT8 {a} Hz vs MAT2 {b} Hz");
    }
}

/// A fully anisotropic MAT2 (G13, G23 ≠ 0) in a free membrane patch pulled by a uniform
/// tension N along x at both ends (self-equilibrated nodal forces): every CQUAD4 passes the
/// patch test, so the strain is uniform and exact, ε = G⁻¹ (N/t, 0, 0). The drilling
/// rotations are held at 0 on every grid, which leaves the in-plane rotation ω = 0 (the
/// drilling penalty ties it to them) and, with the origin held, the displacements are
/// u = εx x + γxy y/2, v = εy y + γxy x/2. Bound 1e-9 of the largest displacement
/// (round-off; a coupling term G13 or G23 left out changes v by O(1)).
#[test]
fn anisotropic_mat2_membrane_patch_follows_its_compliance() {
    let (t, n, lx, ly) = (0.01, 1.0e5, 1.0, 0.6);
    let gm = [
        [2.0e11, 5.0e10, 2.0e10],
        [5.0e10, 1.0e11, -1.5e10],
        [2.0e10, -1.5e10, 4.0e10],
    ];
    let mut s = format!(
        "SOL 101\nCEND\nSPC = 1\nLOAD = 5\nDISPLACEMENT = ALL\nBEGIN BULK\nPSHELL,1,7,{t:?}\n\
         MAT2,7,{:?},{:?},{:?},{:?},{:?},{:?}\n",
        gm[0][0], gm[0][1], gm[0][2], gm[1][1], gm[1][2], gm[2][2]
    );
    let (nx, ny) = (3, 2);
    for i in 0..=nx {
        for j in 0..=ny {
            let (x, y) = (lx * i as f64 / nx as f64, ly * j as f64 / ny as f64);
            s += &format!("GRID,{},,{x:?},{y:?},0.,,3456\n", 10 * i + j + 1);
        }
    }
    for i in 0..nx {
        for j in 0..ny {
            let g = 10 * i + j + 1;
            s += &format!("CQUAD4,{g},1,{g},{},{},{}\n", g + 10, g + 11, g + 1);
        }
    }
    // edges x = 0 and x = lx: the consistent nodal forces of the traction ∓N (per length)
    let h = ly / ny as f64;
    for j in 0..=ny {
        let share = if j == 0 || j == ny { 0.5 } else { 1.0 };
        for (i, sign) in [(0, -1.0), (nx, 1.0)] {
            let f = sign * n * h * share;
            s += &format!("FORCE,5,{},,{f:?},1.,0.,0.\n", 10 * i + j + 1);
        }
    }
    s += "SPC1,1,12,1\nENDDATA\n";
    let u = displacements(&s);
    // ε = G⁻¹ σ by Cramer's rule for σ = (N/t, 0, 0): the first column of G⁻¹ times σx
    let det = gm[0][0] * (gm[1][1] * gm[2][2] - gm[1][2] * gm[2][1])
        - gm[0][1] * (gm[1][0] * gm[2][2] - gm[1][2] * gm[2][0])
        + gm[0][2] * (gm[1][0] * gm[2][1] - gm[1][1] * gm[2][0]);
    let sx = n / t;
    let ex = sx * (gm[1][1] * gm[2][2] - gm[1][2] * gm[2][1]) / det;
    let ey = -sx * (gm[1][0] * gm[2][2] - gm[1][2] * gm[2][0]) / det;
    let gxy = sx * (gm[1][0] * gm[2][1] - gm[1][1] * gm[2][0]) / det;
    let mut k = 0;
    for i in 0..=nx {
        for j in 0..=ny {
            let (x, y) = (lx * i as f64 / nx as f64, ly * j as f64 / ny as f64);
            let (ue, ve) = (ex * x + gxy * y / 2.0, ey * y + gxy * x / 2.0);
            let tol = 1e-9 * (ex * lx).abs();
            assert!(
                (u[6 * k] - ue).abs() < tol && (u[6 * k + 1] - ve).abs() < tol,
                "grid ({x}, {y}): ({}, {}) vs ({ue:e}, {ve:e})",
                u[6 * k],
                u[6 * k + 1]
            );
            k += 1;
        }
    }
    assert!(
        gxy.abs() > 0.1 * ex.abs(),
        "the patch shears: {gxy:e} vs {ex:e}"
    );
}

/// MAT2 where its matrix cannot serve is refused with the card and the reason: as MID3 with
/// G33 ≠ 0 (Nastran requires G13, G23, G33 blank there), with negative stiffness as MID1, as a
/// PCOMP ply or a PSOLID material, and as the REFID of a PMPAR E (no E to scale).
#[test]
fn mat2_misuse_is_refused_with_its_card() {
    let mats = "MAT2,1,2.e11,5.e10,0.,1.e11,0.,4.e10,1600.\nMAT2,2,2.e11,5.e10,0.,1.e11,0.,4.e10\n";
    let cases = [
        (
            skew_plate("PSHELL,1,1,0.02,1,,2", mats),
            "MID3 = 2 (MAT2): as MID3 (transverse shear from G11, G12, G22) G13, G23 and G33 must be blank",
        ),
        (
            skew_plate(
                "PSHELL,1,3,0.02",
                "MAT2,3,2.e11,3.e11,0.,1.e11,0.,4.e10,1600.\n",
            ),
            "MID1 = 3 (MAT2): G11 … G33 must form a positive semi-definite matrix",
        ),
        (
            skew_plate("PCOMP,1\n,1,0.01,0.", mats),
            "MID1 = 1 is a MAT2; PCOMP needs a MAT8 or MAT1: MAT2 is a plane-stress material, read by PSHELL only",
        ),
        (
            skew_plate("PSHELL,1,1,0.02,1\nPMPAR,1,EM,E,1,1.,2.", mats),
            "REFID = 1 is a MAT2; KIND = E acts on a MAT1",
        ),
        (
            skew_plate("PSHELL,1,2,0.02,2", mats)
                .replace("SOL 101", "SOL 103")
                .replace("LOAD = 5", "METHOD = 9")
                .replace("ENDDATA", "EIGRL,9,,,3\nENDDATA"),
            "MAT2 2: field 9 (RHO): RHO is zero or blank: SOL 103",
        ),
    ];
    for (k, (deck, expected)) in cases.iter().enumerate() {
        // the section errors surface when the elements are built, the others with the model
        let message = if k < 2 {
            run_deck(deck).0.expect_err("refused").to_string()
        } else {
            common::build_model(deck).expect_err("refused").join("\n")
        };
        assert!(
            message.contains(expected),
            "'{expected}' not in:\n{message}"
        );
    }
}

/// A 4 × 1 × 1 CHEXA cantilever 2 × 0.5 × 0.5, clamped at x = 0, loaded at the tip in y and
/// z, its elements of property 1 (`property`: the PSOLID or PCOMPS card, with its MAT1s).
fn hex_cantilever(property: &str) -> String {
    let mut s =
        format!("SOL 101\nCEND\nSPC = 1\nLOAD = 5\nDISPLACEMENT = ALL\nBEGIN BULK\n{property}\n");
    for i in 0..=4 {
        for (k, (y, z)) in [(0.0, 0.0), (0.5, 0.0), (0.5, 0.5), (0.0, 0.5)]
            .iter()
            .enumerate()
        {
            s += &format!(
                "GRID,{},,{:?},{y:?},{z:?}\n",
                10 * i + k + 1,
                0.5 * i as f64
            );
        }
    }
    for i in 0..4 {
        let g = |k: usize| 10 * i + k;
        s += &format!(
            "CHEXA,{},1,{},{},{},{},{},{}\n,{},{}\n",
            i + 1,
            g(1),
            g(2),
            g(3),
            g(4),
            g(11),
            g(12),
            g(13),
            g(14)
        );
    }
    s += "SPC1,1,123,1,2,3,4\nFORCE,5,43,,100.,0.,1.,-2.\nENDDATA\n";
    s
}

/// A PCOMPS whose plies all use one MAT1 is that homogeneous solid: with plies of unequal
/// thickness and different angles it gives the PSOLID's displacements to round-off (the same
/// element matrices; bound 1e-12 of the largest). Plies of different materials (a laminate
/// paraflex would have to integrate ply by ply) and a GE are refused at their field.
#[test]
fn pcomps_of_one_mat1_is_that_psolid() {
    let mat = "MAT1,7,2.e11,,0.3,7850.";
    let psolid = displacements(&hex_cantilever(&format!("PSOLID,1,7\n{mat}")));
    let pcomps = displacements(&hex_cantilever(&format!(
        "PCOMPS,1,0,13,,,20.,0.\n,11,7,2.,0.,,,YES,ABS\n,12,7,3.,45.\n{mat}"
    )));
    let d = relative_difference(&psolid, &pcomps);
    assert!(d < 1e-12, "PCOMPS vs PSOLID: {d:e}");
    let (_dir, deck) = {
        let dir = tempfile::tempdir().expect("dir");
        let path = dir.path().join("deck.dat");
        let text = hex_cantilever(&format!(
            "PCOMPS,1,,,,,,0.02\n,11,7,2.,0.\n,12,8,3.,45.\n{mat}\nMAT1,8,1.e11,,0.3"
        ));
        std::fs::write(&path, text).expect("write");
        let deck = paraflex::deck::Deck::read(&path);
        (dir, deck)
    };
    let message = deck.expect_err("refused").to_string();
    for text in [
        "PCOMPS 1: field 8 (GE): a PCOMPS GE is not supported",
        "PCOMPS 1: field 3 of continuation 2 (MID2): ply 2 has MID 8 and ply 1 MID 7",
    ] {
        assert!(message.contains(text), "'{text}' not in:\n{message}");
    }
}

/// Static displacements by grid id (basic T1 T2 T3 R1 R2 R3) of a deck: the rows of the
/// displacement dataset follow the model's grids, sorted by id.
fn displacements_by_grid(deck: &str) -> std::collections::HashMap<u32, Vec<f64>> {
    let model = common::build_model(deck).expect("builds");
    let u = displacements(deck);
    (model.grids.iter().map(|g| g.id))
        .zip(u.chunks(6).map(|c| c.to_vec()))
        .collect()
}

/// How the part of [`skew_plate_in_parts`] is written and connected.
#[derive(Clone, Copy, PartialEq)]
enum PartStyle {
    /// Boundary grids repeated in the part with the residual's ids (one point each).
    SharedIds,
    /// Part grids numbered +100: the boundary connects by coincident location (AUTO).
    Coincident,
    /// Part grids numbered +100, `SEBULK … MANUAL` and the boundary pairs on `SECONCT`.
    Seconct,
    /// Part grids numbered +100 and drawn rotated 90° about z and shifted; `SELOC` moves
    /// the part onto the residual's boundary (AUTO after the move).
    Moved,
}

/// [`skew_plate`] split at column 2: the residual holds columns 0–2 (elements of columns 0–1,
/// the clamp), part superelement 7 the elements of columns 2–3 with their own PSHELL 1, MAT1 1
/// and element ids 1… (the residual's ids: renumbered) and the loads.
fn skew_plate_in_parts(style: PartStyle) -> String {
    let (pshell, mat) = ("PSHELL,1,1,0.01,1,,1", "MAT1,1,7.e10,,0.3,2700.");
    let offset = if style == PartStyle::SharedIds {
        0
    } else {
        100
    };
    // the part is drawn at R^T (x − t): rotated −90° about z, x' = y, y' = −x, then shifted
    let drawn = |x: f64, y: f64| match style {
        PartStyle::Moved => (y + 5.0, -x - 2.0),
        _ => (x, y),
    };
    let direction = |d: [f64; 3]| match style {
        PartStyle::Moved => [d[1], -d[0], d[2]],
        _ => d,
    };
    let mut s = format!(
        "SOL 101\nCEND\nSPC = 1\nLOAD = 5\nDISPLACEMENT = ALL\nBEGIN BULK\n{pshell}\n{mat}\n"
    );
    for i in 0..=2 {
        for j in 0..=3 {
            let (x, y) = skew_xy(i, j);
            s += &format!("GRID,{},,{x:?},{y:?},0.\n", 10 * i + j + 1);
        }
    }
    let quad = |s: &mut String, eid: usize, g: usize, off: usize| {
        *s += &format!(
            "CQUAD4,{eid},1,{},{},{},{},30.\n",
            g + off,
            g + 10 + off,
            g + 11 + off,
            g + 1 + off
        );
    };
    for i in 0..2 {
        for j in 0..3 {
            quad(&mut s, 3 * i + j + 1, 10 * i + j + 1, 0);
        }
    }
    s += "SPC1,1,123456,1,2,3,4\n";
    match style {
        PartStyle::Seconct => {
            s += "SEBULK,7,PRIMARY,,MANUAL\nSECONCT,7,0\n,121,21,122,22,123,23,124,24\n";
        }
        PartStyle::Moved => {
            // PA: part grids 121, 124, 141 (drawn rotated); PB: where they belong
            let (x, y) = skew_xy(4, 0);
            s += &format!("GRID,901,,{x:?},{y:?},0.\nSELOC,7,121,124,141,21,24,901\n");
        }
        _ => {}
    }
    s += &format!("BEGIN SUPER = 7\n{pshell}\n{mat}\n");
    for i in 2..=4 {
        for j in 0..=3 {
            let (x, y) = skew_xy(i, j);
            let (x, y) = drawn(x, y);
            s += &format!("GRID,{},,{x:?},{y:?},0.\n", 10 * i + j + 1 + offset);
        }
    }
    for i in 2..4 {
        for j in 0..3 {
            quad(&mut s, 3 * (i - 2) + j + 1, 10 * i + j + 1, offset);
        }
    }
    let [a, b, c] = direction([0.3, 0.2, 1.0]);
    let [d, e, f] = direction([-0.1, 0.4, -0.5]);
    let [m, n, o] = direction([1.0, 0.0, 0.0]);
    s += &format!(
        "FORCE,5,{},,1.,{a:?},{b:?},{c:?}\nFORCE,5,{},,1.,{d:?},{e:?},{f:?}\n\
         MOMENT,5,{},,0.2,{m:?},{n:?},{o:?}\nENDDATA\n",
        41 + offset,
        44 + offset,
        42 + offset
    );
    s
}

/// A plate split into the residual and a part superelement (its own PSHELL, MAT1 and element
/// ids, the residual's reused) gives the displacements of the same plate in one bulk data
/// section, whether the part repeats the boundary grids' ids, connects by coincidence, by
/// SECONCT pairs, or is drawn elsewhere and moved by SELOC. The part's elements are the same
/// element matrices (for the moved part, from coordinates rotated and shifted: a change of
/// 1e-16 relative) and the ties (RBE2 of all six components) are eliminated exactly, so the
/// displacements agree to round-off: bound 1e-10 of the largest (cond(K) · ε ~ 1e-11, as in
/// `mat2_equals_the_mat1_and_mat8_it_spells_out`); a boundary left unconnected, an element of
/// the part on the wrong property or a load in the wrong direction changes them by O(1).
#[test]
fn part_superelements_give_the_one_section_plate() {
    let pshell = "PSHELL,1,1,0.01,1,,1";
    let one = displacements(&skew_plate(pshell, "MAT1,1,7.e10,,0.3,2700.\n"));
    for style in [
        PartStyle::SharedIds,
        PartStyle::Coincident,
        PartStyle::Seconct,
        PartStyle::Moved,
    ] {
        let parts = displacements_by_grid(&skew_plate_in_parts(style));
        let offset = if style == PartStyle::SharedIds {
            0
        } else {
            100
        };
        let mut ours = Vec::new();
        for i in 0..=4 {
            for j in 0..=3 {
                let id = 10 * i + j + 1;
                let id = if i > 2 { id + offset } else { id };
                ours.extend_from_slice(&parts[&(id as u32)]);
            }
        }
        let d = relative_difference(&one, &ours);
        assert!(d < 1e-10, "style {}: {d:e}", style as u8);
        if offset > 0 {
            // the part's boundary grids keep their ids and follow the residual's
            for j in 1..=4u32 {
                let (a, b) = (&parts[&(20 + j)], &parts[&(120 + j)]);
                assert!(relative_difference(a, b) < 1e-12, "grid {j}: {a:?} {b:?}");
            }
        }
    }
}

/// The assembled model says what it did (renumbered ids, boundary points and their RBE2s, or
/// that none connects a part);
/// a SOL 103 deck with parts warns that Nastran's reduced parts give other modes; ASET/QSET
/// of the main bulk data are read with a warning in SOL 101 and refused in SOL 103; bad part
/// input is refused with its card: a SELOC of a part the deck does not define, SECONCT pairs
/// too far apart or naming a grid the section lacks, two grids with one id at different
/// points, a part card referring to a property only the residual defines, a part's second
/// GRDSET, an SEBULK of another type than PRIMARY.
#[test]
fn part_superelement_reports_and_errors() {
    let deck = skew_plate_in_parts(PartStyle::Coincident);
    let model = common::build_model(&deck).expect("builds");
    let warned = |model: &paraflex::model::Model, text: &str| {
        model.warnings.iter().any(|w| w.message.contains(text))
    };
    for text in [
        "part superelement 7 assembled at 4 boundary points: 121 = residual 21 (RBE2 ",
        "ids used by an earlier section renumbered: element ids 1→7 2→8 3→9 4→10 5→11 6→12; property ids 1→2; material ids 1→2",
    ] {
        assert!(warned(&model, text), "'{text}' not in {:?}", model.warnings);
    }
    let modal = deck
        .replace("SOL 101", "SOL 103")
        .replace("LOAD = 5", "METHOD = 1")
        .replace("SPC1,1,", "EIGRL,1,,,2\nSPC1,1,");
    let model = common::build_model(&modal).expect("builds");
    assert!(
        warned(
            &model,
            "assembled and solved unreduced: Nastran reduces each part"
        ),
        "{:?}",
        model.warnings
    );
    // a MANUAL part without SECONCT pairs has no partner for its boundary grids
    let alone = deck.replace(
        "BEGIN SUPER = 7",
        "SEBULK,7,PRIMARY,,MANUAL\nBEGIN SUPER = 7",
    );
    let model = common::build_model(&alone).expect("builds");
    assert!(
        warned(
            &model,
            "part superelement 7 assembled: no boundary point connects it"
        ),
        "{:?}",
        model.warnings
    );
    // ASET/QSET of the main bulk data: SOL 101 solves unreduced (the same solution), with a
    // warning; SOL 103 would differ from Nastran's Guyan reduction, so it is refused
    let aset = deck.replace("SPC1,1,", "ASET,21,123456\nQSET1,0,22\nSPC1,1,");
    let model = common::build_model(&aset).expect("builds");
    assert!(
        warned(
            &model,
            "ASET accepted and not honoured (2 ASET/QSET/QSET1 cards)"
        ),
        "{:?}",
        model.warnings
    );
    let e = common::build_model(&aset.replace("SOL 101", "SOL 103")).expect_err("refused");
    assert!(
        e.iter()
            .any(|m| m.contains("ASET: ASET reduces the model (Guyan reduction")),
        "{e:?}"
    );
    let refused = |from: &str, to: &str, text: &str| {
        let bad = deck.replacen(from, to, 1);
        assert_ne!(bad, deck, "'{from}' not in the deck");
        let e = common::build_model(&bad).expect_err(text).join("\n");
        assert!(e.contains(text), "'{text}' not in:\n{e}");
    };
    let line = deck
        .lines()
        .position(|l| l == "BEGIN SUPER = 7")
        .expect("part")
        + 1;
    refused(
        "BEGIN SUPER = 7",
        "SELOC,8,121,124,141,21,24,1\nBEGIN SUPER = 7",
        &format!(
            ".bdf:{line}: SELOC 8: SELOC names part superelement 8, which the deck does not define (no BEGIN SUPER = 8 section)"
        ),
    );
    refused(
        "BEGIN SUPER = 7",
        "SEBULK,7,PRIMARY,,MANUAL\nSECONCT,7,0\n,121,21,122,22,124,23\nBEGIN SUPER = 7",
        "SECONCT 7 0: GRID 124 and GRID 23 are",
    );
    refused(
        "BEGIN SUPER = 7",
        "SEBULK,7,PRIMARY,,MANUAL\nSECONCT,7,0\n,121,21,122,22,123,23,124,29\nBEGIN SUPER = 7",
        "SECONCT 7 0: GRID 29 is not a grid of the main bulk data",
    );
    refused(
        "BEGIN SUPER = 7\n",
        "BEGIN SUPER = 7\nGRID,11,,9.,9.,0.\n",
        "GRID 11 of part superelement 7 at [9.0, 9.0, 0.0] and GRID 11 of the main bulk data",
    );
    refused(
        "CQUAD4,1,1,121",
        "CQUAD4,1,3,121",
        "CQUAD4 of part superelement 7 refers to property 3, which part 7 does not define",
    );
    refused(
        "BEGIN SUPER = 7\n",
        "BEGIN SUPER = 7\nGRDSET,,,,,,,6\nGRDSET,,,,,,,6\n",
        "a second GRDSET in part superelement 7",
    );
    refused(
        "BEGIN SUPER = 7",
        "SEBULK,7,MIRROR,3\nBEGIN SUPER = 7",
        "a MIRROR superelement is not supported",
    );
}
