//! The library without files: a model built from deck text held in memory, discretized
//! ([`paraflex::discretize::Structure`]), evaluated at parameter values p and solved for its
//! modes, its static response and its receptance ([`paraflex::analysis`]) — no deck file, no
//! output file, no solution sequence.
//!
//! The model is a single-DOF oscillator: grid 2 free in T1 only (GRID PS 23456), a CONM2 of
//! mass m = 4 and a grounded CELAS1 whose PELAS stiffness k is the parameter KS (nominal 1000):
//! λ = k/m, so f = √(k/m)/2π at every p; FORCE 10 pulls it with 5 N along x, so u = 5/k; its
//! undamped receptance is H(ω) = 1/(k − ω²m).

use std::path::Path;

use paraflex::analysis::frf::{self, Damping, FrfRun, output_rows};
use paraflex::analysis::statics::{StaticFactors, StaticSolution};
use paraflex::assembly::reduce::Partition;
use paraflex::deck::Deck;
use paraflex::discretize::{BuildOptions, Constrained, Structure};
use paraflex::linalg::{
    EigenProblem, EigenRequest, LanczosOptions, Mat, SymbolicFactor, solve_modes,
};
use paraflex::model::Model;

const OSCILLATOR: &str = "\
SOL 103
CEND
BEGIN BULK
GRID,2,,1.,0.,0.,,23456
CONM2,1,2,,4.
CELAS1,2,7,2,1
PELAS,7,1000.
PMPAR,1,KS,K,7,500.,2000.
FORCE,10,2,,5.,1.,0.,0.
ENDDATA
";

/// The first eigenvalue of the oscillator at parameter values `p`.
fn eigenvalue_at(model: &Model, structure: &Structure, p: &[f64]) -> f64 {
    let quiet = |_: &str, _: usize, _: usize| {};
    let c = Constrained::at(model, structure, None, p).expect("constraints");
    assert_eq!(c.sets.f.len(), 1, "one free DOF");
    let symbolic = SymbolicFactor::analyze(c.k_ff.pattern()).expect("symbolic");
    let problem = EigenProblem {
        k: &c.k_ff,
        m: &c.m_ff,
        symbolic: &symbolic,
    };
    let request = EigenRequest {
        v1_hz: None,
        v2_hz: None,
        nd: Some(1),
        shift_hz: None,
    };
    let options = BuildOptions { parallel: false };
    let modes = solve_modes(
        &problem,
        &request,
        &LanczosOptions::default(),
        options.par(),
        &quiet,
    )
    .expect("modes");
    assert_eq!(modes.eigenvalues.len(), 1);
    modes.eigenvalues[0]
}

#[test]
fn a_model_in_memory_is_discretized_evaluated_at_p_and_solved_for_its_modes() {
    let (model, structure) = oscillator();
    assert_eq!(structure.params.list.len(), 1);
    assert_eq!(structure.params.nominal(), vec![1000.0]);
    for k in [1000.0, 500.0, 2000.0] {
        let lambda = eigenvalue_at(&model, &structure, &[k]);
        let exact = k / 4.0;
        assert!(
            (lambda - exact).abs() <= 1e-10 * exact,
            "k = {k}: λ = {lambda}, k/m = {exact}"
        );
    }
}

/// The oscillator's model and structure, built from the text in memory.
fn oscillator() -> (Model, Structure) {
    let deck = Deck::parse(Path::new("oscillator.dat"), OSCILLATOR)
        .unwrap_or_else(|e| panic!("deck: {e}"));
    let model = Model::build(&deck).unwrap_or_else(|e| {
        panic!(
            "model: {:?}",
            e.iter().map(|x| x.to_string()).collect::<Vec<_>>()
        )
    });
    let quiet = |_: &str, _: usize, _: usize| {};
    let structure = Structure::build(&model, &BuildOptions { parallel: false }, &quiet)
        .unwrap_or_else(|e| panic!("structure: {e}"));
    (model, structure)
}

#[test]
fn statics_and_receptance_of_a_model_in_memory_at_p() {
    let (model, structure) = oscillator();
    let quiet = |_: &str, _: usize, _: usize| {};
    let par = BuildOptions { parallel: false }.par();
    let masses = structure.mass_gg_values().expect("M_gg");
    for k in [1000.0, 500.0, 2000.0] {
        let c = Constrained::at(&model, &structure, None, &[k]).expect("constraints");
        // statics: u = F/k (one DOF: exact to round-off)
        let mut factors = StaticFactors::new(model.params.maxratio, par);
        let symbolic = StaticFactors::analyze(&c).expect("symbolic");
        factors.factor(&c, symbolic).expect("Cholesky");
        let factor = factors.get(&c).expect("the factor of this f-set");
        let solution =
            StaticSolution::solve(&model, &structure, &c, (Some(10), None), factor, &masses)
                .unwrap_or_else(|e| panic!("statics: {e}"));
        let u = structure.to_basic_rows(&solution.u_g)[0];
        assert!((u - 5.0 / k).abs() <= 1e-12 * 5.0 / k, "k = {k}: u = {u}");

        // receptance at the input DOF, direct and modal, against 1/(k − ω²m)
        let inputs = Mat::<f64>::from_fn(1, 1, |_, _| 1.0);
        let outputs = output_rows(inputs.as_ref(), &[]);
        let omegas = [3.0, 0.5 * (k / 4.0_f64).sqrt(), 2.0 * (k / 4.0_f64).sqrt()];
        let run = FrfRun {
            inputs: inputs.as_ref(),
            outputs: &outputs,
            omegas: &omegas,
            damping: Damping {
                alpha: 0.0,
                beta: 0.0,
                structural: 0.0,
                modal_table: None,
            },
            par,
            progress: &quiet,
        };
        let modal = frf::Method::Modal {
            request: EigenRequest {
                v1_hz: None,
                v2_hz: None,
                nd: Some(1),
                shift_hz: None,
            },
            residual_vectors: true,
        };
        for method in [frf::Method::Direct, modal] {
            let h = frf::receptance(&c, method, &run, &mut |_, _| {})
                .unwrap_or_else(|e| panic!("FRF: {e}"));
            for (line, w) in omegas.iter().enumerate() {
                let exact = 1.0 / (k - w * w * 4.0);
                let got = h.h[line][(0, 0)];
                // one DOF: the LU (direct) or the one mode (modal) is exact to round-off
                assert!(
                    (got.re - exact).abs() <= 1e-10 * exact.abs() && got.im.abs() <= 1e-12,
                    "{method:?}, k = {k}, ω = {w}: H = {got:?}, exact {exact}"
                );
            }
        }
    }
}

/// A mixed mesh: a CHEXA, a CQUAD4 on its top face, an RBE2 tying two of the plate's grids to
/// a CBAR, a grounded CELAS2 and a CONM2 at the bar's tip, with a PMPAR on the shared MAT1's E
/// (so K has a constant and a parametrized part).
const MIXED: &str = "\
SOL 103
CEND
SPC = 1
BEGIN BULK
PARAM,COUPMASS,1
GRID,1,,0.,0.,0.
GRID,2,,1.,0.,0.
GRID,3,,1.,1.,0.
GRID,4,,0.,1.,0.
GRID,5,,0.,0.,1.
GRID,6,,1.,0.,1.
GRID,7,,1.,1.,1.
GRID,8,,0.,1.,1.
GRID,9,,2.,0.,1.
GRID,10,,2.,1.,1.
GRID,11,,3.,0.5,1.
GRID,12,,4.,0.5,1.
MAT1,1,2.1+11,,0.3,7850.
PSOLID,1,1
CHEXA,1,1,1,2,3,4,5,6,+
+,7,8
PSHELL,2,1,0.01,1
CQUAD4,2,2,6,9,10,7
RBE2,3,11,123456,9,10
PBAR,4,1,1.-4,1.-9,1.-9,2.-9
CBAR,4,4,11,12,0.,0.,1.
CELAS2,5,1.+6,12,3
CONM2,6,12,,2.
PMPAR,1,E1,E,1,1.+11,3.+11
SPC1,1,123,1,2,3,4
ENDDATA
";

/// K_ff and M_ff of [`Constrained::at`], evaluated straight from the n-set parts
/// ([`Partition::evaluate`]), equal the f-set sub-operators of every part summed afterwards
/// (the former path) bit for bit, at the nominal E and away from it, on a mesh with solids,
/// shells, a bar, a spring, a mass and a rigid element.
#[test]
fn the_f_set_matrices_of_a_mixed_mesh_equal_the_summed_sub_operators() {
    let deck = Deck::parse(Path::new("mixed.dat"), MIXED).unwrap_or_else(|e| panic!("deck: {e}"));
    let model = Model::build(&deck).unwrap_or_else(|e| {
        panic!(
            "model: {:?}",
            e.iter().map(|x| x.to_string()).collect::<Vec<_>>()
        )
    });
    let quiet = |_: &str, _: usize, _: usize| {};
    let st = Structure::build(&model, &BuildOptions { parallel: true }, &quiet)
        .unwrap_or_else(|e| panic!("structure: {e}"));
    assert!(st.k_nn.parts().len() > 1, "a parametrized part of K");
    assert!(st.rigid.m_mask.iter().any(|&m| m), "the RBE2 makes n ≠ g");
    for p in [st.params.nominal(), vec![2.7e11]] {
        let c = Constrained::at(&model, &st, Some(1), &p).expect("constraints");
        let ff = Partition::new(st.k_nn.pattern().clone(), &c.sets.f_in_n, &c.sets.f_in_n)
            .expect("plan");
        for (op, direct) in [(&st.k_nn, &c.k_ff), (&st.m_nn, &c.m_ff)] {
            let sub = ff.apply(op).expect("sub-operator");
            let summed = sub.evaluate(&c.weights(&st, &sub)).expect("evaluate");
            assert_eq!(direct.pattern(), summed.pattern());
            assert_eq!(direct.values(), summed.values(), "p = {p:?}");
        }
    }
}
