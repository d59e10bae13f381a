//! PMPAR bindings on assembled models (DESIGN.md §5): for every parameter kind, the operators
//! assembled with the PMPAR and evaluated at p, Σ f_i(p) K^i, equal the operators assembled
//! directly from a deck whose card values are p — to round-off (for NU, THETA and TPLY of an
//! unsymmetric laminate, which change the CQUAD4's frozen condensation: at the nominal values, on
//! triangles, and at p with `PARAM,QINCOMP,NO`: [`check_frozen`]).
//!
//! Tolerance: 1e-12 relative to the largest entry. Both sides sum the same element integrals;
//! they differ only by the order of floating-point operations (unit-parameter parts scaled
//! afterwards vs. parameters inside the kernels), i.e. a few ulps per entry times the number of
//! elements meeting at a DOF.

mod common;

use paraflex::assembly::GridFrames;
use paraflex::deck::Deck;
use paraflex::discretize::elements::element_matrices;
use paraflex::discretize::parameters::Parameters;
use paraflex::model::Model;

/// (K values, M values, number of parametrized parts) of a deck evaluated at `p` (card order
/// of its PMPARs; empty = nominal).
fn assembled(bulk: &str, p: &[f64]) -> (Vec<f64>, Vec<f64>, usize) {
    let (params, k, m) = common::affine_operators(bulk);
    let at = if p.is_empty() {
        params.nominal()
    } else {
        p.to_vec()
    };
    let parts = k.parts().len() + m.parts().len() - 2;
    (
        k.evaluate(&params.weights(&k, &at))
            .unwrap()
            .values()
            .to_vec(),
        m.evaluate(&params.weights(&m, &at))
            .unwrap()
            .values()
            .to_vec(),
        parts,
    )
}

fn assert_same(a: &[f64], b: &[f64], what: &str) {
    assert_eq!(a.len(), b.len(), "{what}: pattern");
    let scale = b.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    let worst = a
        .iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max);
    assert!(
        worst <= 1e-12 * scale,
        "{what}: max difference {worst:e} vs max entry {scale:e}"
    );
}

/// `template` has `{name}` placeholders; `pmpars` are the PMPAR cards; `nominal` and `p` give
/// the placeholder values (nominal must match the PMPAR nominal values, i.e. the card values).
fn check(what: &str, template: &str, pmpars: &str, names: &[&str], nominal: &[f64], p: &[f64]) {
    let fill = |values: &[f64]| {
        names
            .iter()
            .zip(values)
            .fold(template.to_string(), |t, (n, v)| {
                t.replace(&format!("{{{n}}}"), &format!("{v:e}"))
            })
    };
    let (k_param, m_param, parts) = assembled(&format!("{}{pmpars}", fill(nominal)), p);
    assert!(parts > 0, "{what}: no parametrized part was assembled");
    let (k_direct, m_direct, none) = assembled(&fill(p), &[]);
    assert_eq!(none, 0, "{what}: the direct deck has parts");
    assert_same(&k_param, &k_direct, &format!("{what}: K"));
    assert_same(&m_param, &m_direct, &format!("{what}: M"));
}

const PLATE: &str = "GRID,1,,0.,0.,0.\nGRID,2,,1.,0.,0.\nGRID,3,,1.,.8,0.1\nGRID,4,,-.1,.9,0.\nGRID,5,,2.,0.,0.\nGRID,6,,2.1,1.,0.\n\
CQUAD4,1,1,1,2,3,4,30.\nCTRIA3,2,1,2,5,6\nCTRIA3,3,1,2,6,3\n";

/// The quad of [`PLATE`], whose incompatible modes are condensed with the nominal section.
const PLATE_QUAD: &str = "CQUAD4,1,1,1,2,3,4,30.\n";

/// [`check`] for a parameter that changes the CQUAD4's condensation (NU, THETA, TPLY with
/// membrane–bending coupling): the parts
/// condense the quad's incompatible modes with the nominal section (src/fe/shell.rs, "frozen
/// condensation"), a deck whose card values are p with the section at p, so at p ≠ nominal the
/// two differ by design (second order in the change; that difference, and the exact identity
/// Σ f_i(p) K^i = K(p) with the nominal condensation, are tested in `fe::shell_tests`). Checked
/// here to round-off: at the nominal values with the quad, at p with the quad split into
/// two triangles (no incompatible modes), and at p with the quad and `PARAM,QINCOMP,NO` (the
/// modes left out, so nothing is frozen).
fn check_frozen(
    what: &str,
    template: &str,
    pmpars: &str,
    names: &[&str],
    nominal: &[f64],
    p: &[f64],
) {
    assert!(
        template.contains(PLATE_QUAD),
        "{what}: the template has no quad"
    );
    check(
        &format!("{what} at nominal"),
        template,
        pmpars,
        names,
        nominal,
        nominal,
    );
    let trias = template.replace(PLATE_QUAD, "CTRIA3,1,1,1,2,3,30.\nCTRIA3,4,1,1,3,4,30.\n");
    check(
        &format!("{what} on triangles"),
        &trias,
        pmpars,
        names,
        nominal,
        p,
    );
    check(
        &format!("{what} with QINCOMP NO"),
        &format!("{template}PARAM,QINCOMP,NO\n"),
        pmpars,
        names,
        nominal,
        p,
    );
}

#[test]
fn pshell_e_nu_rho() {
    let tpl = format!("{PLATE}PSHELL,1,1,0.02,1,,1\nMAT1,1,{{E}},,{{NU}},{{RHO}}\n");
    let pm = "PMPAR,1,E,E,1,1.e10,5.e11\nPMPAR,2,NU,NU,1,0.1,0.45\nPMPAR,3,RHO,RHO,1,1000.,9000.\n";
    check_frozen(
        "PSHELL E, NU, RHO",
        &tpl,
        pm,
        &["E", "NU", "RHO"],
        &[2.1e11, 0.3, 7850.0],
        &[1.3e11, 0.41, 2700.0],
    );
    let pm_e = "PMPAR,1,E,E,1,1.e10,5.e11\n";
    check(
        "PSHELL E only",
        &tpl.replace("{NU}", "0.3").replace("{RHO}", "7850."),
        pm_e,
        &["E"],
        &[2.1e11],
        &[0.7e11],
    );
}

/// E on the bending material only (MID2 ≠ MID1, 12I/T³ ≠ 1, MID3 = a third material).
#[test]
fn pshell_e_on_the_bending_material() {
    let tpl = format!(
        "{PLATE}PSHELL,1,1,0.02,2,1.7,3,0.8\nMAT1,1,7.e10,,0.33,2700.\nMAT1,2,{{E}},,0.3,7850.\nMAT1,3,5.e10,,0.25,1.\n"
    );
    check(
        "PSHELL MID2 E",
        &tpl,
        "PMPAR,1,E2,E,2,1.e10,5.e11\n",
        &["E"],
        &[2.1e11],
        &[3.2e11],
    );
}

#[test]
fn pcomp_theta_tply_rho() {
    let plies = "MAT8,7,1.4e11,1.e10,.3,5.e9,5.e9,3.e9,{RHO}\nPCOMP,1\n,7,{T},{TH},,7,{T},-{TH}\n,7,{T},-{TH},,7,{T},{TH}\n";
    let tpl = format!("{PLATE}{plies}");
    // THETA
    let t_fixed = tpl.replace("{T}", "3.e-4").replace("{RHO}", "1600.");
    check_frozen(
        "PCOMP THETA",
        &t_fixed,
        "PMPAR,1,TH,THETA,1,0.,90.\n",
        &["TH"],
        &[20.0],
        &[63.0],
    );
    // TPLY
    let th_fixed = tpl.replace("{TH}", "20.").replace("{RHO}", "1600.");
    check(
        "PCOMP TPLY",
        &th_fixed,
        "PMPAR,1,H,TPLY,1,1.e-4,1.e-3\n",
        &["T"],
        &[3.0e-4],
        &[4.5e-4],
    );
    // TPLY of an unsymmetric laminate: A ∝ h but B ∝ h², so the condensation is frozen (a
    // symmetric one has B = 0 and stays exact with the quad, above)
    let unsymmetric = format!(
        "{PLATE}MAT8,7,1.4e11,1.e10,.3,5.e9,5.e9,3.e9,1600.\nPCOMP,1\n,7,{{T}},20.,,7,{{T}},-20.\n"
    );
    check_frozen(
        "PCOMP TPLY unsymmetric",
        &unsymmetric,
        "PMPAR,1,H,TPLY,1,1.e-4,1.e-3\n",
        &["T"],
        &[3.0e-4],
        &[4.5e-4],
    );
}

#[test]
fn solids_e_nu_rho() {
    let grids = "GRID,1,,0.,0.,0.\nGRID,2,,1.,0.,0.\nGRID,3,,0.,1.,0.\nGRID,4,,0.,0.,1.\n\
GRID,11,,2.,0.,0.\nGRID,12,,3.,0.,0.\nGRID,13,,2.,1.,0.\nGRID,14,,2.,0.,1.\nGRID,15,,3.1,0.,1.1\nGRID,16,,2.,1.,1.\n";
    let tets = "CTETRA,1,1,1,2,3,4\nCPENTA,2,1,11,12,13,14,15,16\n";
    let tpl = format!("{grids}{tets}PSOLID,1,1\nMAT1,1,{{E}},,{{NU}},{{RHO}}\n");
    let pm = "PMPAR,1,E,E,1,1.e10,5.e11\nPMPAR,2,NU,NU,1,0.1,0.45\nPMPAR,3,RHO,RHO,1,1000.,9000.\n";
    check(
        "tetra/penta E, NU, RHO",
        &tpl,
        pm,
        &["E", "NU", "RHO"],
        &[2.1e11, 0.3, 7850.0],
        &[1.1e11, 0.37, 4500.0],
    );
    let hexa = "GRID,1,,0.,0.,0.\nGRID,2,,1.,0.,0.\nGRID,3,,1.,1.,0.\nGRID,4,,0.,1.1,0.\nGRID,5,,0.,0.,1.\nGRID,6,,1.,0.,1.\nGRID,7,,1.2,1.,1.\nGRID,8,,0.,1.,1.\nCHEXA,1,1,1,2,3,4,5,6\n,7,8\n";
    let tpl_h = format!("{hexa}PSOLID,1,1\nMAT1,1,{{E}},,0.3,{{RHO}}\n");
    check(
        "hexa E, RHO",
        &tpl_h,
        "PMPAR,1,E,E,1,1.e10,5.e11\nPMPAR,3,RHO,RHO,1,1000.,9000.\n",
        &["E", "RHO"],
        &[2.1e11, 7850.0],
        &[0.9e11, 3000.0],
    );
}

#[test]
fn spring_and_mass() {
    let tpl = "GRID,1,,0.,0.,0.\nGRID,2,,1.,0.,0.\nCELAS1,1,4,1,1,2,1\nPELAS,4,{K}\nCELAS2,2,5.e3,2,2\nCONM2,9,2,,{M}\n";
    check(
        "PELAS K, CONM2 MASS",
        tpl,
        "PMPAR,1,K,K,4,1.e3,1.e6\nPMPAR,2,M,MASS,9,0.1,10.\n",
        &["K", "M"],
        &[2.0e4, 1.5],
        &[7.5e4, 4.2],
    );
}

/// Combinations without an affine form are refused with the reason, naming the element.
#[test]
fn non_affine_combinations_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("deck.dat");
    let bulk = format!(
        "{PLATE}MAT8,7,1.4e11,1.e10,.3,5.e9,5.e9,3.e9,1600.\nPCOMP,1\n,7,3.e-4,20.,,7,3.e-4,-20.\nPMPAR,1,TH,THETA,1,0.,90.\nPMPAR,2,H,TPLY,1,1.e-4,1.e-3\n"
    );
    std::fs::write(&path, format!("SOL 103\nCEND\nBEGIN BULK\n{bulk}ENDDATA\n")).unwrap();
    let deck = Deck::read(&path).unwrap();
    let model = Model::build(&deck).unwrap();
    let params = Parameters::of_model(&model).unwrap();
    let quiet = |_: &str, _: usize, _: usize| {};
    let message = element_matrices(
        &model,
        &GridFrames::of_model(&model),
        &params,
        false,
        &quiet,
    )
    .unwrap_err()
    .to_string();
    assert!(
        message.contains("THETA and TPLY") && message.contains("CQUAD4 1"),
        "{message}"
    );
}
