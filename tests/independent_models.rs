//! paraflex against independent computations of the same model: CalculiX on the same mesh and
//! separately written numpy models (`tools/calculix/`, `tools/analytic/`), with the references
//! and their provenance in `reference/`. Each comparison is at the precision the two
//! computations share (round-off, or the digits CalculiX prints), with the bound and its reason
//! stored in the reference JSON next to the values, so that an error in an element, a
//! constraint or a mass coupling shows as a failure by orders of magnitude.

mod common;

use paraflex::model::Model;
use paraflex::sequence::RunSummary;
use paraflex::sequence::modal::ModalSummary;
use serde_json::Value;

use common::{f64s, json, root};

/// `error ≤ bound`, false for a NaN error (a failed comparison must not pass).
fn within(error: f64, bound: f64) -> bool {
    error <= bound
}

/// Checks `f` against `reference` index by index (relative error ≤ `bound`), printing each
/// pair and adding a line to `failures` for each outside the bound; `label` names the case.
fn check_frequencies(
    label: &str,
    f: &[f64],
    reference: &[f64],
    bound: f64,
    failures: &mut Vec<String>,
) {
    assert_eq!(f.len(), reference.len(), "{label}: frequencies {f:?}");
    for (k, (g, w)) in f.iter().zip(reference).enumerate() {
        let e = g / w - 1.0;
        println!(
            "{label}: f{} = {g:.6} Hz, reference {w:.6} Hz, error {e:.1e}",
            k + 1
        );
        if !within(e.abs(), bound) {
            failures.push(format!(
                "{label} f{}: {g} Hz vs {w} Hz, |error| {:.2e} > {bound:.0e}",
                k + 1,
                e.abs()
            ));
        }
    }
}

fn num(v: &Value, key: &str) -> f64 {
    v[key]
        .as_f64()
        .unwrap_or_else(|| panic!("{key}: not a number in {v}"))
}

/// A finished run of a deck file of the repository.
struct Run {
    summary: RunSummary,
    model: Model,
    dir: tempfile::TempDir,
}

fn run(rel: &str) -> Run {
    let (result, model, dir) = common::run_deck_file(&root().join(rel));
    let summary = result.unwrap_or_else(|e| panic!("{rel}: {e}"));
    Run {
        summary,
        model,
        dir,
    }
}

impl Run {
    /// Grid id → (T1 T2 T3 R1 R2 R3) in basic of `/results/<subcase>/statics/displacement`.
    fn displacements(&self, subcase: usize) -> std::collections::BTreeMap<u32, [f64; 6]> {
        let file = hdf5_metno::File::open(self.dir.path().join("out.h5")).expect("open h5");
        let mut ids: Vec<u32> = self.model.grids.iter().map(|g| g.id).collect();
        ids.sort_unstable(); // rows in increasing grid id
        let u: Vec<f64> = file
            .dataset(&format!("results/{subcase}/statics/displacement"))
            .expect("displacement")
            .read_raw()
            .expect("read u");
        assert_eq!(u.len(), 6 * ids.len());
        ids.iter()
            .enumerate()
            .map(|(i, id)| (*id, std::array::from_fn(|k| u[6 * i + k])))
            .collect()
    }

    /// Frequencies (Hz) of the modal subcase `subcase` (1-based), ascending.
    fn frequencies(&self, subcase: usize) -> Vec<f64> {
        match self.summary.subcases[subcase - 1].result::<ModalSummary>() {
            Some(m) => {
                assert!(m.sturm.is_consistent(), "Sturm check: {:?}", m.sturm);
                m.frequencies_hz.clone()
            }
            None => panic!(
                "subcase {subcase} is not modal: {:?}",
                self.summary.subcases[subcase - 1].result
            ),
        }
    }
}

/// The first three components T1 T2 T3, all six T1 … R3, or the in-plane T1 T3 R2 (0-based).
const TRANSLATIONS: &[usize] = &[0, 1, 2];
const ALL: &[usize] = &[0, 1, 2, 3, 4, 5];
const XZ_PLANE: &[usize] = &[0, 2, 4];

/// ‖a − b‖₂ / ‖b‖₂ over the listed grids' `components` (`want` holds them in that order), and
/// max |a − b| / max |b|.
fn differences(
    got: &std::collections::BTreeMap<u32, [f64; 6]>,
    want: &[(u32, Vec<f64>)],
    components: &[usize],
) -> (f64, f64) {
    let (mut d2, mut r2, mut dmax, mut rmax) = (0.0, 0.0, 0.0f64, 0.0f64);
    for (id, w) in want {
        let g = got.get(id).unwrap_or_else(|| panic!("grid {id} missing"));
        assert_eq!(w.len(), components.len(), "grid {id}: {w:?}");
        for (k, &c) in components.iter().enumerate() {
            let d = g[c] - w[k];
            d2 += d * d;
            r2 += w[k] * w[k];
            dmax = dmax.max(d.abs());
            rmax = rmax.max(w[k].abs());
        }
    }
    ((d2 / r2).sqrt(), dmax / rmax)
}

/// `{"<grid id>": [ux, uy, uz, …], …}` of a reference JSON.
fn grid_vectors(v: &Value) -> Vec<(u32, Vec<f64>)> {
    v.as_object()
        .expect("object of grid id → vector")
        .iter()
        .map(|(id, u)| (id.parse().expect("grid id"), f64s(u)))
        .collect()
}

// ---------------------------------------------------------------------------------------------
// Tetrahedra and pentahedra: the same cantilever mesh as CalculiX (tools/calculix/solid_same_mesh.py)

/// Statics (every grid's displacement) and the six lowest frequencies of one cantilever case of
/// `reference/calculix/solid/`, against the numpy model with the element's exact quadrature
/// (checked there against CalculiX with CalculiX's quadrature), and, where CalculiX integrates
/// the stiffness as paraflex does, against CalculiX's printed displacements.
fn solid_cantilever(case: &str) {
    let r = json(&format!("reference/calculix/solid/{case}.json"));
    let tol = &r["tolerance"];
    let bound = num(tol, "reference_rel");
    let statics = run(r["decks"]["static"].as_str().unwrap());
    let u = statics.displacements(1);
    let (rel2, _) = differences(
        &u,
        &grid_vectors(&r["reference"]["displacements"]),
        TRANSLATIONS,
    );
    println!(
        "{case}: displacements against the exact-quadrature model: {rel2:.1e} (bound {bound:.0e})"
    );
    let mut failures = Vec::new();
    if !within(rel2, bound) {
        failures.push(format!(
            "displacements: ‖u − u_ref‖/‖u_ref‖ = {rel2:.2e} > {bound:.0e} ({})",
            tol["reference_justification"]
        ));
    }
    if let Some(ccx_bound) = tol["calculix_displacement_over_max_u"].as_f64() {
        let (_, relmax) = differences(
            &u,
            &grid_vectors(&r["calculix"]["displacements"]),
            TRANSLATIONS,
        );
        println!("{case}: displacements against CalculiX: {relmax:.1e} (bound {ccx_bound:.0e})");
        if !within(relmax, ccx_bound) {
            failures.push(format!(
                "displacements: max |u − u_ccx| / max |u_ccx| = {relmax:.2e} > {ccx_bound:.0e} ({})",
                tol["calculix_justification"]
            ));
        }
    }
    let f = run(r["decks"]["modal"].as_str().unwrap()).frequencies(1);
    let reference = f64s(&r["reference"]["frequencies_hz"]);
    check_frequencies(case, &f, &reference, bound, &mut failures);
    assert!(failures.is_empty(), "{case}:\n  {}", failures.join("\n  "));
}

#[test]
fn ctetra4_cantilever_matches_the_same_mesh() {
    solid_cantilever("cantilever_ctetra4");
}

#[test]
fn ctetra10_cantilever_matches_the_same_mesh() {
    solid_cantilever("cantilever_ctetra10");
}

#[test]
fn cpenta6_cantilever_matches_the_same_mesh() {
    solid_cantilever("cantilever_cpenta6");
}

#[test]
fn chexa20_cantilever_matches_the_same_mesh() {
    solid_cantilever("cantilever_chexa20");
}

#[test]
fn cpenta15_cantilever_matches_the_same_mesh() {
    solid_cantilever("cantilever_cpenta15");
}

/// CHEXA 20 with curved edges: the cantilever bent into a quarter ring.
#[test]
fn chexa20_quarter_ring_matches_the_same_mesh() {
    solid_cantilever("ring_chexa20");
}

// ---------------------------------------------------------------------------------------------
// RBE3: unequal weights, partial components, reference point off the centroid

/// Grounded springs under an RBE3 whose weight groups differ (1, 3.5, 2, 0.4 with components
/// 123, 123, 13, 123456) and whose reference grid carries a force and a moment: every component
/// of every grid against the numpy model of the RBE3 equations (tools/analytic/rbe3_weighted.py).
#[test]
fn rbe3_unequal_weights_match_the_interpolation_equations() {
    let r = json("reference/analytic/rbe3_weighted.json");
    let bound = num(&r["tolerance"], "relative");
    let u = run(r["deck"].as_str().unwrap()).displacements(1);
    let want = grid_vectors(&r["displacements"]);
    let (rel2, _) = differences(&u, &want, ALL);
    for (id, w) in &want {
        println!("grid {id}: paraflex {:?}\n        reference {w:?}", u[id]);
    }
    println!("rbe3_weighted: ‖u − u_ref‖/‖u_ref‖ = {rel2:.1e} (bound {bound:.0e})");
    assert!(
        within(rel2, bound),
        "rbe3_weighted: ‖u − u_ref‖/‖u_ref‖ = {rel2:.2e} > {bound:.0e} ({})",
        r["tolerance"]["justification"]
    );
}

// ---------------------------------------------------------------------------------------------
// Offset shell (ZOFFS): membrane–bending coupling of the stiffness and of the mass

/// A CQUAD4 strip with ZOFFS = t/2 moving in the x-z plane, against the numpy beam-and-bar
/// model of the same discretization written in the grid-plane variables
/// (tools/analytic/zoffs_strip.py): the displacements under an axial tip force in the grid plane
/// (eccentric: it bends the strip, closed form in the JSON) and a transverse one, and the eight
/// lowest frequencies, which the offset's membrane–rotation mass coupling ρ t z₀ shifts by up
/// to 9 % when its sign is wrong.
#[test]
fn zoffs_strip_matches_the_offset_beam_model() {
    let r = json("reference/analytic/zoffs_strip.json");
    let bound = num(&r["tolerance"], "relative");
    let statics = run(r["decks"]["static"].as_str().unwrap());
    let mut failures = Vec::new();
    for subcase in [1, 2] {
        let u = statics.displacements(subcase);
        let want = grid_vectors(&r["static_displacements"][subcase.to_string()]);
        let (rel2, _) = differences(&u, &want, XZ_PLANE);
        println!(
            "zoffs_strip subcase {subcase}: ‖u − u_ref‖/‖u_ref‖ = {rel2:.1e} (bound {bound:.0e})"
        );
        if !within(rel2, bound) {
            failures.push(format!(
                "subcase {subcase}: ‖u − u_ref‖/‖u_ref‖ = {rel2:.2e} > {bound:.0e}"
            ));
        }
    }
    let f = run(r["decks"]["modal"].as_str().unwrap()).frequencies(1);
    let reference = f64s(&r["frequencies_hz"]);
    check_frequencies("zoffs_strip", &f, &reference, bound, &mut failures);
    assert!(
        failures.is_empty(),
        "zoffs_strip ({}):\n  {}",
        r["tolerance"]["justification"],
        failures.join("\n  ")
    );
}

// ---------------------------------------------------------------------------------------------
// MITC4 transverse shear on thick plates

/// Clamped square plates with t/L = 0.1 and 0.2 on a distorted 8 × 8 CQUAD4 mesh, where the
/// transverse shear carries much of the energy and the MITC4 tying (e_ξ at the edge midpoints
/// (0, ±1), e_η at (±1, 0)) sets the answer: T3 of every grid under three point forces and the
/// eight lowest frequencies against the independent numpy MITC4 plate of the same mesh
/// (tools/analytic/mitc_thick_plate.py).
#[test]
fn thick_plates_match_the_independent_mitc4_plate() {
    let r = json("reference/analytic/mitc_thick_plate.json");
    let mut failures = Vec::new();
    for (key, c) in r["cases"].as_object().expect("cases") {
        let bound = num(c, "tolerance");
        let u = run(c["decks"]["static"].as_str().unwrap()).displacements(1);
        let want: Vec<(u32, Vec<f64>)> = c["w"]
            .as_object()
            .unwrap()
            .iter()
            .map(|(id, w)| (id.parse().unwrap(), vec![w.as_f64().unwrap()]))
            .collect();
        let (rel2, _) = differences(&u, &want, &[2]);
        println!("mitc_thick {key}: ‖w − w_ref‖/‖w_ref‖ = {rel2:.1e} (bound {bound:.0e})");
        if !within(rel2, bound) {
            failures.push(format!(
                "{key}: ‖w − w_ref‖/‖w_ref‖ = {rel2:.2e} > {bound:.0e}"
            ));
        }
        let f = run(c["decks"]["modal"].as_str().unwrap()).frequencies(1);
        let reference = f64s(&c["frequencies_hz"]);
        let label = format!("mitc_thick {key}");
        check_frequencies(&label, &f, &reference, bound, &mut failures);
    }
    assert!(
        failures.is_empty(),
        "mitc_thick_plate ({}):\n  {}",
        r["tolerance_justification"],
        failures.join("\n  ")
    );
}
