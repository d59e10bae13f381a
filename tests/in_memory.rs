//! The library without files: a model built from deck text held in memory, discretized
//! ([`paraflex::discretize::Structure`]), evaluated at parameter values p and solved for its
//! modes — no deck file, no output file, no solution sequence.
//!
//! The model is a single-DOF oscillator: grid 2 free in T1 only (GRID PS 23456), a CONM2 of
//! mass m = 4 and a grounded CELAS1 whose PELAS stiffness k is the parameter KS (nominal 1000):
//! λ = k/m, so f = √(k/m)/2π at every p.

use std::path::Path;

use paraflex::deck::Deck;
use paraflex::discretize::{BuildOptions, Constrained, Structure};
use paraflex::linalg::{EigenProblem, EigenRequest, LanczosOptions, SymbolicFactor, solve_modes};
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
