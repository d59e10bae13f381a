//! Tests of assembly, set reduction, loads and recovery on small decks with hand-made element
//! matrices (springs), checked against hand solutions.

use std::sync::Arc;

use faer::Mat;
use faer::linalg::solvers::Solve;
use nalgebra_sparse::CscMatrix;

use super::assemble::{AffineOperator, Contribution, ParamKey, ParamTarget};
use super::constraints::RigidElimination;
use super::dofs::{DofMap, Sets};
use super::error::{AssemblyError, DofName};
use super::frames::GridFrames;
use super::loads::{Mass, load_vector, reduce_load};
use super::pattern::grid_block_pattern;
use super::recover::{expand_f_to_n, recover_g, spc_forces};
use super::reduce::{GToN, Partition, partition, reduce_g_to_n, reduce_n_to_f};
use super::spc::{AutoSpcReport, SpcSet, autospc};
use crate::fe::affine::Coefficient;
use crate::model::Model;
use crate::model::testing::model_of_text;

fn model(bulk: &str, case: &str) -> Model {
    model_of_text(&format!("SOL 101\nCEND\n{case}BEGIN BULK\n{bulk}ENDDATA\n"))
}

/// A spring k between g DOFs a and b.
fn spring(k: f64, a: usize, b: usize) -> Contribution {
    Contribution::constant(
        vec![a, b],
        Mat::from_fn(2, 2, |i, j| if i == j { k } else { -k }),
    )
}

/// T1 of a grid index.
fn t1(grid: usize) -> usize {
    DofMap::dof(grid, 0)
}

fn dense(m: &CscMatrix<f64>) -> Mat<f64> {
    let mut d = Mat::zeros(m.nrows(), m.ncols());
    for (i, j, v) in m.triplet_iter() {
        d[(i, j)] += *v;
    }
    d
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-10 * (1.0 + a.abs().max(b.abs()))
}

/// A linear static solve with every piece of the module (dense solve of the tiny K_ff).
struct Solved {
    u_g: Vec<f64>,
    q_s: Vec<f64>,
    sets: Sets,
    report: AutoSpcReport,
    k_ff: Mat<f64>,
}

fn solve(model: &Model, contributions: &[Contribution]) -> Result<Solved, AssemblyError> {
    let map = DofMap::of_model(model);
    let frames = GridFrames::of_model(model);
    let pattern = Arc::new(grid_block_pattern(
        map.grids(),
        map.scalar_points(),
        contributions.iter().map(|c| c.dofs.as_slice()),
    )?);
    let k_gg = AffineOperator::assemble(pattern, contributions, true)?;
    let rigid = RigidElimination::of_model(model, &frames, &map)?;
    let sub = &model.subcases[0];
    let mut spc = SpcSet::of_model(model, &map, sub.spc)?;
    spc.check_against_rigids(&rigid, &map)?;
    let k_nn = reduce_g_to_n(&k_gg, &rigid.t)?;
    let k_nn_values = {
        let mut v = vec![0.0; k_nn.pattern().nnz()];
        k_nn.evaluate_into(&k_nn.weights(|_| 1.0), &mut v)?;
        v
    };
    let report = if model.params.autospc {
        autospc(&k_nn, &k_nn_values, &rigid.n, &spc.mask, &map)?
    } else {
        AutoSpcReport::default()
    };
    spc.add_autospc(&report);
    let sets = Sets::new(&map, &rigid.m_mask, &spc.mask)?;
    let k_ff = dense(&reduce_n_to_f(&k_nn, &sets.f_in_n)?.evaluate(&k_nn.weights(|_| 1.0))?);
    let k_fs = partition(&k_nn, &sets.f_in_n, &sets.s_in_n)?;
    let k_fs_values = k_fs.evaluate(&k_fs.weights(|_| 1.0))?.values().to_vec();
    let p_g = match sub.load {
        Some(sid) => load_vector(model, &frames, &map, sid, None)?,
        None => vec![0.0; map.size()],
    };
    let p_f = reduce_load(&p_g, &rigid, &sets, &k_fs, &k_fs_values, &spc.enforced)?;
    let mut x = Mat::from_fn(p_f.len(), 1, |i, _| p_f[i]);
    k_ff.partial_piv_lu().solve_in_place(&mut x);
    let u_f: Vec<f64> = (0..p_f.len()).map(|i| x[(i, 0)]).collect();
    let u_g = recover_g(&u_f, &sets, &spc.enforced, &rigid)?;
    let u_n = expand_f_to_n(&u_f, &sets, &spc.enforced)?;
    let p_n = rigid.reduce_vector(&p_g)?;
    let q_s = spc_forces(&k_nn, &k_nn_values, &u_n, &p_n, &sets)?;
    Ok(Solved {
        u_g,
        q_s,
        sets,
        report,
        k_ff,
    })
}

const CHAIN: &str = "GRID,1,,0.,0.,0.\nGRID,2,,1.,0.,0.\nGRID,3,,2.,0.,0.\nGRID,4,,3.,0.,0.\n";

/// Three springs 100, 200, 300 in series along x, grid 1 clamped, F = 10 at grid 4:
/// u2 = 10/100, u3 = u2 + 10/200, u4 = u3 + 10/300; reaction −10.
#[test]
fn three_spring_chain_with_spc() {
    let m = model(
        &format!("{CHAIN}SPC1,1,123456,1\nFORCE,2,4,,10.,1.,0.,0.\n"),
        "SPC = 1\nLOAD = 2\n",
    );
    let springs = [
        spring(100., t1(0), t1(1)),
        spring(200., t1(1), t1(2)),
        spring(300., t1(2), t1(3)),
    ];
    let s = solve(&m, &springs).expect("solve");
    // AUTOSPC removed everything but T1 of grids 2–4
    assert_eq!(s.sets.f.members(), &[t1(1), t1(2), t1(3)]);
    let expected = [[300., -200., 0.], [-200., 500., -300.], [0., -300., 300.]];
    for (i, row) in expected.iter().enumerate() {
        for (j, &v) in row.iter().enumerate() {
            assert!(
                close(s.k_ff[(i, j)], v),
                "K_ff[{i},{j}] = {}",
                s.k_ff[(i, j)]
            );
        }
    }
    let u2 = 0.1;
    let u3 = u2 + 10. / 200.;
    let u4 = u3 + 10. / 300.;
    assert!(
        close(s.u_g[t1(1)], u2) && close(s.u_g[t1(2)], u3) && close(s.u_g[t1(3)], u4),
        "{:?}",
        &s.u_g
    );
    // SPC force at grid 1 T1 (first s DOF)
    assert_eq!(s.sets.s.members()[0], t1(0));
    assert!(close(s.q_s[0], -10.), "reaction {}", s.q_s[0]);
    // total of reactions balances the load
    assert!(close(s.q_s.iter().sum::<f64>(), -10.));
}

/// AUTOSPC lists every DOF without stiffness of a 3-D spring model, as (GRID, component).
#[test]
fn autospc_lists_zero_rows_of_spring_model() {
    let m = model(
        &format!("{CHAIN}SPC1,1,1,1\nFORCE,2,4,,10.,1.,0.,0.\n"),
        "SPC = 1\nLOAD = 2\n",
    );
    let springs = [
        spring(100., t1(0), t1(1)),
        spring(200., t1(1), t1(2)),
        spring(300., t1(2), t1(3)),
    ];
    let s = solve(&m, &springs).expect("solve");
    // grid 1: components 2–6 (T1 is SPC'd); grids 2–4: components 2–6
    let mut expected = Vec::new();
    for grid in 1..=4 {
        for c in 2..=6 {
            expected.push(DofName { grid, component: c });
        }
    }
    assert_eq!(s.report.names, expected);
    assert!(s.report.to_string().contains("4/6"), "{}", s.report);
    // PARAM,AUTOSPC,NO leaves them free: the singular K_ff has zero rows
    let off = model(
        &format!("{CHAIN}SPC1,1,1,1\nPARAM,AUTOSPC,NO\n"),
        "SPC = 1\n",
    );
    assert!(!off.params.autospc);
}

/// RBE2 joining two springs: the dependent grid follows its independent grid rigidly.
#[test]
fn rbe2_joins_two_springs() {
    let bulk = "GRID,1,,0.,0.,0.\nGRID,2,,1.,0.,0.\nGRID,3,,1.,0.,0.\nGRID,4,,2.,0.,0.\nRBE2,9,2,123456,3\nSPC1,1,123456,1\nFORCE,2,4,,10.,1.,0.,0.\n";
    let m = model(bulk, "SPC = 1\nLOAD = 2\n");
    let s = solve(
        &m,
        &[spring(100., t1(0), t1(1)), spring(100., t1(2), t1(3))],
    )
    .expect("solve");
    assert!(
        close(s.u_g[t1(1)], 0.1) && close(s.u_g[t1(2)], 0.1) && close(s.u_g[t1(3)], 0.2),
        "{:?}",
        s.u_g
    );
    assert_eq!(s.sets.m.len(), 6);
}

/// An MPC 2 u2 − u3 − 3 u4 = 0 (T1 of each), u2 dependent: u2 = u3/2 + 3 u4/2. Springs
/// k3 = 100 and k4 = 150 hold grids 3 and 4 to the clamped grid 1 and F = 10 pulls grid 2: by
/// virtual work k3 u3 = F/2, k4 u4 = 3F/2, so u3 = 0.05, u4 = 0.1 and u2 = 0.175.
#[test]
fn mpc_equation_ties_its_first_term_to_the_others() {
    let bulk = format!(
        "{CHAIN}MPC,5,2,1,2.,3,1,-1.\n,,4,1,-3.\nSPC1,1,123456,1\nSPC1,1,23456,2,3,4\n\
         FORCE,2,2,,10.,1.,0.,0.\n"
    );
    let m = model(&bulk, "SPC = 1\nMPC = 5\nLOAD = 2\n");
    let s = solve(
        &m,
        &[spring(100., t1(0), t1(2)), spring(150., t1(0), t1(3))],
    )
    .expect("solve");
    assert!(
        close(s.u_g[t1(1)], 0.175) && close(s.u_g[t1(2)], 0.05) && close(s.u_g[t1(3)], 0.1),
        "{:?}",
        s.u_g
    );
}

/// RBE2 kinematics with a lever arm: a rotation θz = 1 of GN moves a dependent grid at
/// r = (0, 1, 0) by θ × r = (−1, 0, 0); chains (GM of one RBE2 is GN of the next) resolve.
#[test]
fn rbe2_lever_arm_and_chain() {
    let bulk = "GRID,1,,0.,0.,0.\nGRID,2,,0.,1.,0.\nGRID,3,,0.,2.,0.\nRBE2,8,2,123456,3\nRBE2,7,1,123456,2\n";
    let m = model(bulk, "");
    let map = DofMap::of_model(&m);
    let rigid = RigidElimination::of_model(&m, &GridFrames::of_model(&m), &map).expect("rigid");
    assert_eq!(rigid.n.members(), &[0, 1, 2, 3, 4, 5]);
    let u_g = rigid.expand(&[0., 0., 0., 0., 0., 1.]).expect("expand");
    assert!(
        close(u_g[6], -1.) && close(u_g[12], -2.) && close(u_g[11], 1.) && close(u_g[17], 1.),
        "{u_g:?}"
    );
}

/// RBE2 onto a grid whose displacement system (CD) is turned 90° about z (x' = y, y' = −x):
/// the dependent grid's DOFs are the rigid motion resolved in that system. A translation
/// (1, 0, 0) of the independent grid reads (0, −1, 0); a rotation θz = 1 moves the grid at
/// r = (0, 1, 0) by θ × r = (−1, 0, 0), i.e. (0, 1, 0) in CD, and turns it by (0, 0, 1).
#[test]
fn rbe2_resolves_the_rigid_motion_in_the_dependent_grid_cd_system() {
    let bulk = "CORD2R,5,,0.,0.,0.,0.,0.,1.\n,0.,1.,0.\nGRID,1,,0.,0.,0.\nGRID,2,,0.,1.,0.,5\n\
                RBE2,8,1,123456,2\n";
    let m = model(bulk, "");
    let map = DofMap::of_model(&m);
    let rigid = RigidElimination::of_model(&m, &GridFrames::of_model(&m), &map).expect("rigid");
    let u = rigid.expand(&[1., 0., 0., 0., 0., 0.]).expect("expand");
    let expected = [0., -1., 0., 0., 0., 0.];
    assert!(
        (0..6).all(|k| close(u[6 + k], expected[k])),
        "{:?}",
        &u[6..]
    );
    let u = rigid.expand(&[0., 0., 0., 0., 0., 1.]).expect("expand");
    let expected = [0., 1., 0., 0., 0., 1.];
    assert!(
        (0..6).all(|k| close(u[6 + k], expected[k])),
        "{:?}",
        &u[6..]
    );
    let u = rigid.expand(&[0., 0., 0., 1., 0., 0.]).expect("expand");
    // θx = 1: θ × r = (0, 0, 1); the rotation (1, 0, 0) reads (0, −1, 0) in CD
    let expected = [0., 0., 1., 0., -1., 0.];
    assert!(
        (0..6).all(|k| close(u[6 + k], expected[k])),
        "{:?}",
        &u[6..]
    );
}

/// A chain of RBE2s with levers other than 1 and out of plane: GN 1 → GM 2 at r = (0, 2, 0),
/// GN 2 → GM 3 at r = (0, 1, 1). θz₁ = 1 moves grid 2 by (−2, 0, 0) and grid 3 by
/// (−2, 0, 0) + (0, 0, 1) × (0, 1, 1) = (−3, 0, 0); θx₁ = 1 moves grid 2 by (0, 0, 2) and grid 3
/// by (0, 0, 2) + (1, 0, 0) × (0, 1, 1) = (0, −1, 3).
#[test]
fn rbe2_chain_composes_levers_in_three_dimensions() {
    let bulk = "GRID,1,,0.,0.,0.\nGRID,2,,0.,2.,0.\nGRID,3,,0.,3.,1.\nRBE2,7,1,123456,2\nRBE2,8,2,123456,3\n";
    let m = model(bulk, "");
    let map = DofMap::of_model(&m);
    let rigid = RigidElimination::of_model(&m, &GridFrames::of_model(&m), &map).expect("rigid");
    for (u1, grid2, grid3) in [
        ([0., 0., 0., 0., 0., 1.], [-2., 0., 0.], [-3., 0., 0.]),
        ([0., 0., 0., 1., 0., 0.], [0., 0., 2.], [0., -1., 3.]),
    ] {
        let u = rigid.expand(&u1).expect("expand");
        for c in 0..3 {
            assert!(
                close(u[6 + c], grid2[c]) && close(u[12 + c], grid3[c]),
                "{u1:?}: {u:?}"
            );
        }
    }
}

const SQUARE: &str = "GRID,1,,1.,1.,0.\nGRID,2,,-1.,1.,0.\nGRID,3,,-1.,-1.,0.\nGRID,4,,1.,-1.,0.\nGRID,5,,0.,0.,0.\n";

/// RBE3 with unequal weights (1 on grids 1, 2; 3 on grids 3, 4): the reference's six DOFs are
/// the weighted least-squares rigid motion of the legs, u_ref = (Σ Gᵢᵀ Wᵢ Gᵢ)⁻¹ Σ Gᵢᵀ Wᵢ uᵢ with
/// Gᵢ = [I −[rᵢ]×; 0 I] restricted to each group's components and Wᵢ the group weight, times L_c²
/// on rotations (L_c = √2, the corners' mean distance: the MSC definition of the module doc). The
/// weighted centre is off the reference point, so translations and rotations couple. Computed
/// here with faer's dense LU rather than the module's 6 × 6 inverse, for translations only and
/// with the first group's rotations observed too.
#[test]
fn rbe3_unequal_weights_give_the_weighted_least_squares_motion() {
    let legs: [[f64; 6]; 4] = [
        [1., 2., 3., 0.1, -0.2, 0.3],
        [-1., 0., 5., 0.4, 0.0, -0.1],
        [4., 2., -1., 0.2, 0.3, 0.0],
        [0., 0., 1., -0.3, 0.1, 0.2],
    ];
    let weights = [1.0, 1.0, 3.0, 3.0];
    let r: [[f64; 3]; 4] = [[1., 1., 0.], [-1., 1., 0.], [-1., -1., 0.], [1., -1., 0.]];
    let lc2 = 2.0;
    for (first, observed) in [("123", 3), ("123456", 6)] {
        let m = model(
            &format!("{SQUARE}RBE3,9,,5,123456,1.,{first},1,2,\n+,3.,123,3,4\n"),
            "",
        );
        let map = DofMap::of_model(&m);
        let rigid = RigidElimination::of_model(&m, &GridFrames::of_model(&m), &map).expect("rigid");
        let mut u_n = vec![0.0; rigid.n.len()];
        for (g, leg) in legs.iter().enumerate() {
            u_n[6 * g..6 * g + 6].copy_from_slice(leg);
        }
        let u = rigid.expand(&u_n).expect("expand");
        let mut normal = Mat::<f64>::zeros(6, 6);
        let mut rhs = Mat::<f64>::zeros(6, 1);
        for g in 0..4 {
            let [x, y, z] = r[g];
            // u_leg = u_ref + θ × r = u_ref − [r]× θ; θ_leg = θ
            let gi = Mat::from_fn(6, 6, |i, j| match (i, j) {
                (i, j) if i == j => 1.0,
                (0, 4) => z,
                (0, 5) => -y,
                (1, 3) => -z,
                (1, 5) => x,
                (2, 3) => y,
                (2, 4) => -x,
                _ => 0.0,
            });
            let rows = if g < 2 { observed } else { 3 };
            for (c, &value) in legs[g].iter().enumerate().take(rows) {
                let w = weights[g] * if c < 3 { 1.0 } else { lc2 };
                let row = gi.as_ref().subrows(c, 1);
                normal += row.transpose() * row * w;
                rhs += row.transpose() * Mat::from_fn(1, 1, |_, _| value) * w;
            }
        }
        let expected = normal.partial_piv_lu().solve(&rhs);
        for k in 0..6 {
            assert!(
                close(u[24 + k], expected[(k, 0)]),
                "C = {first}, reference DOF {}: {} vs {}",
                k + 1,
                u[24 + k],
                expected[(k, 0)]
            );
        }
    }
}

/// RBE3 whose legs all sit on the reference point (L_c = 0, taken as 1): with all six
/// components observed, the reference motion is the weighted average of the legs' motions,
/// rotations included (weights 1 and 3).
#[test]
fn rbe3_with_legs_on_the_reference_point_averages_their_motions() {
    let bulk = "GRID,1,,0.,0.,0.\nGRID,2,,0.,0.,0.\nGRID,5,,0.,0.,0.\n\
                RBE3,9,,5,123456,1.,123456,1,\n+,3.,123456,2\n";
    let m = model(bulk, "");
    let map = DofMap::of_model(&m);
    let rigid = RigidElimination::of_model(&m, &GridFrames::of_model(&m), &map).expect("rigid");
    let legs = [[1., 2., 3., 0.4, -0.8, 1.2], [5., -2., 7., 0.0, 0.4, -0.4]];
    let u_n: Vec<f64> = legs.iter().flatten().copied().collect();
    let u = rigid.expand(&u_n).expect("expand");
    for k in 0..6 {
        let expected = (legs[0][k] + 3.0 * legs[1][k]) / 4.0;
        assert!(
            close(u[12 + k], expected),
            "DOF {}: {} vs {expected}",
            k + 1,
            u[12 + k]
        );
    }
}

/// RBE3 with equal weights on the four corners of a square: the reference translation is the
/// average; a rigid rotation of the corners gives the reference that rotation.
#[test]
fn rbe3_average_and_rigid_rotation() {
    let m = model(
        &format!("{SQUARE}RBE3,9,,5,123456,1.,123,1,2,\n+,3,4\n"),
        "",
    );
    let map = DofMap::of_model(&m);
    let rigid = RigidElimination::of_model(&m, &GridFrames::of_model(&m), &map).expect("rigid");
    assert_eq!(rigid.m_mask.iter().filter(|m| **m).count(), 6);
    let n = rigid.n.len();
    // independent corner translations
    let corners: [[f64; 3]; 4] = [[1., 2., 3.], [-1., 0., 5.], [4., 2., -1.], [0., 0., 1.]];
    let mut u_n = vec![0.0; n];
    for (g, t) in corners.iter().enumerate() {
        u_n[6 * g..6 * g + 3].copy_from_slice(t);
    }
    let u = rigid.expand(&u_n).expect("expand");
    let avg: [f64; 3] = std::array::from_fn(|c| corners.iter().map(|t| t[c]).sum::<f64>() / 4.);
    for c in 0..3 {
        assert!(
            close(u[24 + c], avg[c]),
            "T{}: {} vs {}",
            c + 1,
            u[24 + c],
            avg[c]
        );
    }
    // rigid rotation θ about the reference point: u_i = θ × r_i
    let theta = [0.1, -0.2, 0.3];
    let mut u_n = vec![0.0; n];
    for g in 0..4 {
        let r = m.grids[g].xyz;
        let v = crate::geometry::vec3::cross(theta, r);
        u_n[6 * g..6 * g + 3].copy_from_slice(&v);
    }
    let u = rigid.expand(&u_n).expect("expand");
    for c in 0..3 {
        assert!(u[24 + c].abs() < 1e-12, "translation {c} = {}", u[24 + c]);
        assert!(
            close(u[27 + c], theta[c]),
            "R{}: {} vs {}",
            c + 1,
            u[27 + c],
            theta[c]
        );
    }
}

/// The RBE3's motion is unchanged when every weight is multiplied by one factor, and so must be
/// whether it is refused as singular: the pivot test is relative to the largest diagonal entry
/// of A = Σ w sᵀs. Three legs observing translations, at (±1, 0, 0) and (0, δ, 0): only the
/// third leg sees a rotation about x, and after eliminating T3 its pivot is (2/3)·w·δ² against
/// the largest diagonal 3w, i.e. (2/9)·δ² relative to it. δ = 1e-6 (2.2e-13, below
/// RBE3_PIVOT_TOL = 1e-10) is refused and δ = 1e-3 (2.2e-7) accepted, at weights 1e-4 … 1e4;
/// an absolute or inversely scaled threshold flips one of them at one end of that range. The
/// accepted ones reproduce a rigid motion of the legs (conditioning ~1e7 at δ = 1e-3, so a
/// relative 1e-6 bound).
#[test]
fn rbe3_singularity_is_judged_relative_to_the_weight_scale() {
    let theta = [0.1, -0.2, 0.3];
    let t = [1.0, 2.0, -0.5];
    for (delta, accepted) in [("1.-6", false), ("1.-3", true)] {
        for w in ["1.-4", "1.", "1.+4"] {
            let bulk = format!(
                "GRID,1,,1.,0.,0.\nGRID,2,,-1.,0.,0.\nGRID,3,,0.,{delta},0.\n\
                 GRID,5,,0.,0.,0.\nRBE3,9,,5,123456,{w},123,1,2,\n+,3\n"
            );
            let m = model(&bulk, "");
            let map = DofMap::of_model(&m);
            let rigid = RigidElimination::of_model(&m, &GridFrames::of_model(&m), &map);
            let Ok(rigid) = rigid else {
                assert!(!accepted, "δ = {delta}, w = {w}: refused");
                continue;
            };
            assert!(accepted, "δ = {delta}, w = {w}: accepted");
            let mut u_n = vec![0.0; rigid.n.len()];
            for g in 0..3 {
                let arm = crate::geometry::vec3::cross(theta, m.grids[g].xyz);
                for c in 0..3 {
                    u_n[6 * g + c] = t[c] + arm[c];
                }
            }
            let u = rigid.expand(&u_n).expect("expand");
            for (k, expected) in t.iter().chain(&theta).enumerate() {
                assert!(
                    (u[18 + k] - expected).abs() < 1e-6,
                    "δ = {delta}, w = {w}, DOF {}: {} vs {expected}",
                    k + 1,
                    u[18 + k]
                );
            }
        }
    }
}

/// SPCADD is the union of its sets; a set without cards is an error. (Nested SPCADD and
/// members without cards, which the model check rejects, are errors of the set resolution
/// itself: `model::sets` tests them.)
#[test]
fn spcadd_union_and_errors() {
    let bulk = format!("{CHAIN}SPC1,1,123,1\nSPC1,2,456,2\nSPC,2,3,1,0.\nSPCADD,3,1,2\n");
    let m = model(&bulk, "");
    let map = DofMap::of_model(&m);
    let s = SpcSet::of_model(&m, &map, Some(3)).expect("union");
    let on: Vec<usize> = (0..map.size()).filter(|&i| s.mask[i]).collect();
    assert_eq!(on, vec![0, 1, 2, 9, 10, 11, 12]);
    assert!(
        s.source[12]
            .as_deref()
            .is_some_and(|x| x.starts_with("SPC 2 at ") && x.ends_with(".bdf:10")),
        "{:?}",
        s.source[12]
    );
    assert_eq!(
        SpcSet::of_model(&m, &map, Some(99)).unwrap_err(),
        AssemblyError::NoConstraintSet {
            selection: "SPC",
            cards: "SPC/SPC1/SPCADD".to_string(),
            sid: 99
        }
    );
}

/// Enforced displacement: two equal springs, grid 1 moved by 0.01, grid 3 fixed: u2 = 0.005,
/// reactions ±k · 0.005. Conflicting values in one set are an error.
#[test]
fn enforced_displacement() {
    let bulk = "GRID,1,,0.,0.,0.\nGRID,2,,1.,0.,0.\nGRID,3,,2.,0.,0.\nSPC,1,1,1,0.01,3,1,0.\n";
    let m = model(bulk, "SPC = 1\n");
    let s = solve(
        &m,
        &[spring(100., t1(0), t1(1)), spring(100., t1(1), t1(2))],
    )
    .expect("solve");
    assert!(close(s.u_g[t1(0)], 0.01) && close(s.u_g[t1(1)], 0.005) && close(s.u_g[t1(2)], 0.0));
    let s_dofs = s.sets.s.members();
    let r1 = s.q_s[s_dofs
        .iter()
        .position(|&d| d == t1(0))
        .expect("T1 of grid 1 in s")];
    let r3 = s.q_s[s_dofs
        .iter()
        .position(|&d| d == t1(2))
        .expect("T1 of grid 3 in s")];
    assert!(close(r1, 0.5) && close(r3, -0.5), "{r1} {r3}");
    let bad = model("GRID,1,,0.,0.,0.\nSPC,1,1,1,0.01\nSPC1,1,1,1\n", "");
    let e = SpcSet::of_model(&bad, &DofMap::of_model(&bad), Some(1)).unwrap_err();
    assert!(
        matches!(
            e,
            AssemblyError::ConflictingEnforced {
                dof: DofName {
                    grid: 1,
                    component: 1
                },
                ..
            }
        ),
        "{e}"
    );
}

/// LOAD 2 = 2.0 · (1.5 · FORCE 10 − 1.0 · MOMENT 11); GRAV without mass is an error, with
/// mass it is M · a. (A LOAD named in a LOAD adds nothing, as in Nastran: `model::sets` tests
/// it.)
#[test]
fn load_combination_and_gravity() {
    let bulk = format!(
        "{CHAIN}FORCE,10,2,,3.,0.,1.,0.\nMOMENT,11,3,,4.,0.,0.,1.\nLOAD,2,2.,1.5,10,-1.,11\nGRAV,20,,9.81,0.,0.,-1.\n"
    );
    let m = model(&bulk, "");
    let map = DofMap::of_model(&m);
    let frames = GridFrames::of_model(&m);
    let p = load_vector(&m, &frames, &map, 2, None).expect("load");
    assert!(close(p[DofMap::dof(1, 1)], 2. * 1.5 * 3.) && close(p[DofMap::dof(2, 5)], -2. * 4.));
    assert_eq!(p.iter().filter(|v| **v != 0.0).count(), 2);
    assert_eq!(
        load_vector(&m, &frames, &map, 20, None).unwrap_err(),
        AssemblyError::MassRequired { sid: 20 }
    );
    assert_eq!(
        load_vector(&m, &frames, &map, 77, None).unwrap_err(),
        AssemblyError::NoLoadSet { sid: 77 }
    );
    // lumped masses 2 at grid 1 translations (a 3 × 3 diagonal block)
    let mass = Contribution::constant(
        vec![0, 1, 2],
        Mat::from_fn(3, 3, |i, j| if i == j { 2.0 } else { 0.0 }),
    );
    let pattern =
        Arc::new(grid_block_pattern(map.grids(), 0, [mass.dofs.as_slice()]).expect("pattern"));
    let m_gg = AffineOperator::assemble(pattern, &[mass], false).expect("mass");
    let values = m_gg.parts()[0].1.clone();
    let p = load_vector(
        &m,
        &frames,
        &map,
        20,
        Some(Mass {
            operator: &m_gg,
            values: &values,
        }),
    )
    .expect("grav");
    assert!(close(p[2], -2. * 9.81) && close(p[0], 0.) && close(p[8], 0.));
}

/// FORCE in a CORD2R rotated 90° about z (local x = basic y) at a grid whose CD is that system:
/// basic (0, 2, 0), global (2, 0, 0).
#[test]
fn force_in_rotated_cord2r() {
    let bulk = "CORD2R,5,,0.,0.,0.,0.,0.,1.,\n+,0.,1.,0.\nGRID,1,,0.,0.,0.\nGRID,2,,1.,0.,0.,5\nFORCE,1,1,5,2.,1.,0.,0.\nFORCE,1,2,5,2.,1.,0.,0.\n";
    let m = model(bulk, "");
    let map = DofMap::of_model(&m);
    let p = load_vector(&m, &GridFrames::of_model(&m), &map, 1, None).expect("load");
    assert!(
        close(p[0], 0.) && close(p[1], 2.) && close(p[2], 0.),
        "grid 1 (basic): {:?}",
        &p[0..3]
    );
    assert!(
        close(p[6], 2.) && close(p[7], 0.),
        "grid 2 (CD = 5): {:?}",
        &p[6..9]
    );
}

/// A spring along basic x at a grid with CD rotated 90° about z acts on that grid's T2.
#[test]
fn element_rotated_to_cd_frame() {
    let bulk = "CORD2R,5,,0.,0.,0.,0.,0.,1.,\n+,0.,1.,0.\nGRID,1,,0.,0.,0.,5\nGRID,2,,1.,0.,0.\n";
    let m = model(bulk, "");
    let frames = GridFrames::of_model(&m);
    let mut k = Mat::<f64>::zeros(12, 12);
    for (i, j, v) in [(0, 0, 1.), (6, 6, 1.), (0, 6, -1.), (6, 0, -1.)] {
        k[(i, j)] = v;
    }
    let c = Contribution::element(&frames, &[0, 1], vec![(ParamKey::Constant, k)]);
    let m0 = &c.parts[0].1;
    // basic x at grid 1 = −(local y) of system 5 (local x = basic y, local y = −basic x)
    assert!(
        close(m0[(1, 1)], 1.) && close(m0[(0, 0)], 0.) && close(m0[(1, 6)], 1.),
        "{m0:?}"
    );
}

/// Every affine part shares one pattern (same index arrays), through g → n and n → f, and
/// Σ f_i K_i equals the matrix assembled directly at p.
#[test]
fn affine_parts_share_one_pattern() {
    let e = ParamKey::Param {
        target: ParamTarget::Material(1),
        function: Coefficient::E,
    };
    let rho = ParamKey::Param {
        target: ParamTarget::Material(2),
        function: Coefficient::Rho,
    };
    let unit = |a: usize, b: usize| {
        Mat::from_fn(2, 2, |i, j| if i == j { 1.0 } else { -1.0 }) * faer::Scale((a + b) as f64)
    };
    let parts = vec![
        Contribution {
            dofs: vec![t1(0), t1(1)],
            parts: vec![(ParamKey::Constant, unit(1, 0)), (e, unit(2, 0))],
        },
        Contribution {
            dofs: vec![t1(1), DofMap::dof(2, 1)],
            parts: vec![(e, unit(3, 0)), (rho, unit(1, 1))],
        },
    ];
    let (fe, frho) = (7.0, 0.25);
    let direct: Vec<Contribution> = parts
        .iter()
        .map(|c| {
            let mut sum = Mat::<f64>::zeros(2, 2);
            for (k, m) in &c.parts {
                let f = if *k == e {
                    fe
                } else if *k == rho {
                    frho
                } else {
                    1.0
                };
                sum += m * faer::Scale(f);
            }
            Contribution::constant(c.dofs.clone(), sum)
        })
        .collect();
    let map = DofMap::new(vec![1, 2, 3]);
    let pattern = Arc::new(
        grid_block_pattern(3, 0, parts.iter().map(|c| c.dofs.as_slice())).expect("pattern"),
    );
    let k = AffineOperator::assemble(pattern.clone(), &parts, true).expect("assemble");
    let k_direct = AffineOperator::assemble(pattern.clone(), &direct, false).expect("assemble");
    assert_eq!(k.keys(), vec![ParamKey::Constant, e, rho]);
    assert!(k.parts().iter().all(|(_, v)| v.len() == pattern.nnz()));
    let w = k.weights(|key| {
        if key == e {
            fe
        } else if key == rho {
            frho
        } else {
            1.0
        }
    });
    let at_p = k.evaluate(&w).expect("evaluate");
    let reference = k_direct.evaluate(&[1.0]).expect("evaluate");
    assert_eq!(at_p.col_offsets(), reference.col_offsets());
    assert_eq!(at_p.row_indices(), reference.row_indices());
    assert!(
        at_p.values()
            .iter()
            .zip(reference.values())
            .all(|(a, b)| close(*a, *b))
    );
    // g → n (no rigid) and n → f keep one pattern for all parts, and commute with evaluation
    let rigid = RigidElimination::identity(&map);
    let plan = GToN::new(pattern, &rigid.t).expect("plan");
    let k_nn = plan.apply(&k).expect("reduce");
    let sets = Sets::new(
        &map,
        &rigid.m_mask,
        &(0..18).map(|i| i < 6).collect::<Vec<_>>(),
    )
    .expect("sets");
    let ff = Partition::new(k_nn.pattern().clone(), &sets.f_in_n, &sets.f_in_n).expect("plan");
    let k_ff = ff.apply(&k_nn).expect("k_ff");
    let k_ff_direct = ff
        .apply(&plan.apply(&k_direct).expect("reduce"))
        .expect("k_ff");
    assert!(Arc::ptr_eq(k_ff.pattern(), k_ff_direct.pattern()));
    let a = k_ff.evaluate(&w).expect("evaluate");
    let b = k_ff_direct.evaluate(&[1.0]).expect("evaluate");
    assert!(
        a.values()
            .iter()
            .zip(b.values())
            .all(|(x, y)| close(*x, *y))
    );
    assert_eq!(a.nrows(), 12);
    // allocation-free evaluation into a caller buffer
    let mut buf = vec![0.0; k_ff.pattern().nnz()];
    k_ff.evaluate_into(&w, &mut buf).expect("into");
    assert_eq!(buf, a.values());
    // the partition evaluated directly from the n-set parts: the same values, bit for bit
    let direct = ff.evaluate(&k_nn, &w).expect("direct");
    assert_eq!(direct.values(), a.values());
    assert_eq!(direct.pattern(), a.pattern());
}

/// Errors name the grid and component (or the rigid elements) instead of panicking.
#[test]
fn rigid_errors_are_typed() {
    let two = model(
        "GRID,1,,0.,0.,0.\nGRID,2,,1.,0.,0.\nGRID,3,,2.,0.,0.\nRBE2,7,1,1,2\nRBE2,8,3,12,2\n",
        "",
    );
    let e = RigidElimination::of_model(&two, &GridFrames::of_model(&two), &DofMap::of_model(&two))
        .unwrap_err();
    // each card named with its file:line (deck lines: SOL, CEND, BEGIN BULK, 3 GRIDs, RBE2 7, RBE2 8)
    assert!(
        matches!(
            &e,
            AssemblyError::DependentTwice {
                dof: DofName {
                    grid: 2,
                    component: 1
                },
                ..
            }
        ),
        "{e:?}"
    );
    let text = e.to_string();
    assert!(
        text.starts_with("GRID 2 component 1 is dependent in both RBE2 7 at ")
            && text.contains(".bdf:7 and RBE2 8 at ")
            && text.ends_with(".bdf:8"),
        "{text}"
    );

    let cyc = model(
        "GRID,1,,0.,0.,0.\nGRID,2,,1.,0.,0.\nRBE2,7,1,1,2\nRBE2,8,2,2,1\nRBE2,9,2,3,1\nRBE2,10,1,3,2\n",
        "",
    );
    let e = RigidElimination::of_model(&cyc, &GridFrames::of_model(&cyc), &DofMap::of_model(&cyc))
        .unwrap_err();
    assert!(matches!(e, AssemblyError::RigidCycle { .. }), "{e}");
    // the cycle is T3 of grids 1 and 2 (RBE2 9 and 10); RBE2 7 and 8 are not part of it
    assert!(
        e.to_string().contains("RBE2 9")
            && e.to_string().contains("RBE2 10")
            && !e.to_string().contains("RBE2 7")
            && !e.to_string().contains("RBE2 8"),
        "{e}"
    );

    let spc = model(
        "GRID,1,,0.,0.,0.\nGRID,2,,1.,0.,0.\nRBE2,7,1,123,2\nSPC1,1,3,2\n",
        "SPC = 1\n",
    );
    let err = solve(&spc, &[]).map(|_| ()).unwrap_err();
    let text = err.to_string();
    assert!(
        text.starts_with("GRID 2 component 3 is dependent in RBE2 7 at ")
            && text.contains(".bdf:7 and also constrained by SPC1 1 at ")
            && text.ends_with(".bdf:8"),
        "{text}"
    );

    let one = model(
        "GRID,1,,0.,0.,0.\nGRID,2,,1.,0.,0.\nRBE3,9,,2,123456,1.,123,1\n",
        "",
    );
    let e = RigidElimination::of_model(&one, &GridFrames::of_model(&one), &DofMap::of_model(&one))
        .unwrap_err();
    assert!(
        matches!(&e, AssemblyError::Rbe3Singular { owner } if owner.starts_with("RBE3 9 at ") && owner.ends_with(".bdf:6")),
        "{e:?}"
    );

    let map = DofMap::new(vec![4]);
    assert_eq!(
        map.dof_name(5),
        Some(DofName {
            grid: 4,
            component: 6
        })
    );
    assert_eq!(map.dof_name(6), None);
    let bad = AffineOperator::assemble(
        Arc::new(grid_block_pattern(1, 0, [&[0usize][..]]).expect("p")),
        &[spring(1., 0, 40)],
        false,
    );
    assert_eq!(
        bad.unwrap_err(),
        AssemblyError::DofOutOfRange { index: 40, size: 6 }
    );
}

/// A solid element (translations of grids 0 and 1) and a spring between T3 of grid 1 and R1 of
/// grid 2: grids 0–1 couple in 3 × 3 translation blocks, their rotations keep only a diagonal
/// entry, grid 2's R1 (its only active component) meets grid 1's translations and nothing else.
#[test]
fn pattern_blocks_hold_only_active_components() {
    let solid: Vec<usize> = (0..3).chain(6..9).collect();
    let spring = [8usize, 15];
    let p = grid_block_pattern(3, 0, [solid.as_slice(), &spring[..]]).expect("pattern");
    let has = |r: usize, c: usize| super::pattern::entry_position(&p, r, c).is_some();
    assert!(has(0, 8) && has(8, 0) && has(7, 2));
    for d in 0..18 {
        assert!(has(d, d), "diagonal {d}");
    }
    assert!(
        !has(3, 0) && !has(0, 3) && !has(3, 4) && !has(9, 6),
        "rotations of solid grids are not coupled"
    );
    assert!(has(8, 15) && has(15, 8) && has(15, 6) && !has(15, 0) && !has(15, 12) && !has(14, 15));
    // grids 0–1: 6 × 6 translations; grid 2 R1 × grid 1's 3 translations both ways and its
    // diagonal; the 11 other diagonals (rotations of grids 0, 1; grid 2 but R1)
    assert_eq!(p.nnz(), 36 + 2 * 3 + 1 + 11);
}

/// A translational (3·n) element matrix on grids with CD frames is rotated like the
/// translational block of the same matrix in the 6·n layout, and contributes only T1–T3.
#[test]
fn translational_contributions_rotate_like_the_six_dof_layout() {
    let (c, s) = (0.6_f64, 0.8_f64);
    let frames = GridFrames::from_rotations(vec![
        None,
        Some([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]),
        Some([[1.0, 0.0, 0.0], [0.0, c, s], [0.0, -s, c]]),
    ]);
    let nodes = [2usize, 0, 1];
    let k3 = Mat::<f64>::from_fn(9, 9, |i, j| {
        1.0 + (i * 9 + j).min(j * 9 + i) as f64 + if i == j { 50.0 } else { 0.0 }
    });
    let six = |i: usize| 6 * (i / 3) + i % 3;
    let k6 = Mat::<f64>::from_fn(18, 18, |i, j| {
        if i % 6 < 3 && j % 6 < 3 {
            k3[(3 * (i / 6) + i % 6, 3 * (j / 6) + j % 6)]
        } else {
            0.0
        }
    });
    let t = Contribution::element(&frames, &nodes, vec![(ParamKey::Constant, k3)]);
    let f = Contribution::element(&frames, &nodes, vec![(ParamKey::Constant, k6)]);
    assert_eq!(t.dofs, vec![12, 13, 14, 0, 1, 2, 6, 7, 8]);
    for i in 0..9 {
        assert_eq!(t.dofs[i], f.dofs[six(i)]);
        for j in 0..9 {
            assert!((t.parts[0].1[(i, j)] - f.parts[0].1[(six(i), six(j))]).abs() < 1e-12);
        }
    }
}
