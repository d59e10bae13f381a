//! SOL 103 (MODAL): normal modes of K_ff φ = λ M_ff φ for every subcase
//! ([`crate::analysis::modal`]).
//!
//! Per subcase: `METHOD = sid` selects an `EIGRL` (V1, V2, ND, SHFSCL, NORM); `SPC = sid` and
//! AUTOSPC give the f-set ([`Constrained`]); one symbolic analysis of the K_ff/M_ff pattern is
//! shared by every subcase with the same f-set. The shift-invert Lanczos of
//! [`crate::linalg::eigen`] searches from the bottom of the spectrum when V1 is blank or ≤ 0:
//! σ = 0 when K_ff is safely positive definite, a negative shift otherwise (−(2π·SHFSCL)², or
//! −(2π·1 Hz)² without SHFSCL), so free-free structures return their rigid-body modes at
//! ≈ 0 Hz. A zero pivot of K − σM (a DOF with neither stiffness nor mass, e.g. with
//! PARAM,AUTOSPC,NO) is reported as a mechanism with its GRID and component.
//!
//! Normalization: NORM = MASS (default) gives φᵀMφ = 1; NORM = MAX scales each mode so that its
//! largest f-set component is 1, and the generalized mass is then φᵀMφ. The residual is
//! ‖Kφ − λMφ‖/‖Kφ‖ (see [`EigenResult::residuals`]). The Sturm check compares the number of
//! negative pivots of K − sM, s just above the highest mode returned, with the modes found.
//! When ND cuts through a multiple root, Lanczos finds the whole cluster and the count below s
//! exceeds ND: ND modes are stored, as Nastran returns ND, and the run notes the cut on the
//! console and in the attribute `sturm_note` ([`cut_note`]).
//!
//! A singular M_ff (grids with springs and no mass, rotations without rotary inertia that
//! AUTOSPC keeps because they have stiffness) has fewer finite eigenvalues than f-set DOFs; when
//! ND asks for more, only the finite modes are returned and the run warns (see
//! [`crate::linalg::eigen`], "Singular M").

use super::driver::{Basis, Driver, ElementDampingUse};
use super::report::{Report, lambda_to_hz, sci, sturm_line};
use super::shared::structure;
use super::{Clock, GridRows, RunContext, RunError, SubcaseSummary};
use crate::analysis::modal::{SymbolicCache, modes, normalize_to_unit_max, shapes_in_basic};
use crate::analysis::suport::{EPSILON_LIMIT, rigid_body_modes};
use crate::assembly::spc::suport_dofs;
use crate::deck::Solution;
use crate::deck::cards::EigenNorm;
use crate::deck::case_control::Subcase;
use crate::discretize::{Constrained, Structure};
use crate::io::{set_attr_f64, set_attr_i64, set_attr_str, write_f64};
use crate::linalg::{EigenRequest, EigenResult, SturmCheck};

/// What one modal subcase found.
#[derive(Debug, Clone)]
pub struct ModalSummary {
    /// λ = ω² (raw Rayleigh quotients; rigid-body modes may be slightly negative).
    pub eigenvalues: Vec<f64>,
    pub frequencies_hz: Vec<f64>,
    /// φᵀMφ in the chosen normalization.
    pub generalized_mass: Vec<f64>,
    /// ‖Kφ − λMφ‖/‖Kφ‖.
    pub residuals: Vec<f64>,
    pub sturm: SturmCheck,
    /// Lanczos shift σ (rad²/s²).
    pub shift: f64,
    pub norm: EigenNorm,
    /// Size of the eigenproblem (f-set).
    pub f_size: usize,
    /// Whether the mode shapes were written (DISPLACEMENT requested).
    pub shapes_written: bool,
    /// f-set DOFs without mass (zero rows of M_ff): the problem has at most f_size − massless
    /// finite eigenvalues.
    pub massless: usize,
    /// ND asked for more modes than M_ff has finite eigenvalues: all finite ones were returned.
    pub finite_exhausted: bool,
    /// ND of the EIGRL.
    pub nd: Option<usize>,
    /// The SUPORT r-set's check, when the deck has one.
    pub suport: Option<SuportCheck>,
    /// Lanczos thick restarts and steps (solves with K − σM).
    pub restarts: usize,
    pub solves: usize,
    /// Entries of the factor L of K − σM at the symbolic analysis's ordering (8 bytes each).
    pub factor_nnz: usize,
}

/// What the SUPORT r-set's rigid-body check found.
#[derive(Debug, Clone)]
pub struct SuportCheck {
    /// r-set size (the rigid-body modes reported at 0 Hz).
    pub dofs: usize,
    /// Rigid-body error ratio ε.
    pub epsilon: f64,
    /// Strain energy of each unit rigid-body motion.
    pub strain_energy: Vec<f64>,
}

/// The MODAL driver on the mesh.
pub struct Modal;

/// The output requests MODAL writes: mode shapes on request.
pub const HONOURED: &[&str] = &["DISPLACEMENT"];

impl Driver for Modal {
    fn name(&self) -> &'static str {
        "MODAL"
    }

    fn solutions(&self) -> &'static [Solution] {
        &[Solution::Modal]
    }

    fn basis(&self) -> Basis {
        Basis::Mesh
    }

    fn element_damping(&self) -> ElementDampingUse {
        ElementDampingUse::Ignored
    }

    fn honoured(&self) -> &'static [&'static str] {
        HONOURED
    }

    fn run(&self, ctx: &RunContext, clock: &mut Clock) -> Result<Vec<SubcaseSummary>, RunError> {
        let st = structure(ctx, clock)?;
        run(ctx, &st, clock)
    }
}

/// Runs every subcase.
fn run(
    ctx: &RunContext,
    st: &Structure,
    clock: &mut Clock,
) -> Result<Vec<SubcaseSummary>, RunError> {
    let mut symbolic_cache = SymbolicCache::default();
    let mut out = Vec::new();
    for sub in &ctx.model.subcases {
        let id = sub.id;
        let method = sub.method.ok_or_else(|| RunError::Case {
            subcase: id,
            what: "SOL 103 needs METHOD = <EIGRL or EIGR sid> in case control".into(),
        })?;
        let eigrl = ctx.model.eigrl(method).ok_or_else(|| RunError::Case {
            subcase: id,
            what: format!("METHOD = {method} selects no EIGRL or EIGR card"),
        })?;
        let norm = eigrl.norm;
        let c = clock.time(format!("subcase {id}: constraints"), || {
            Constrained::build(ctx.model, st, sub.spc)
        })?;
        if symbolic_cache.get(&c).is_none() {
            clock
                .time(format!("subcase {id}: symbolic analysis"), || {
                    symbolic_cache.analyze(&c)
                })
                .map_err(|e| RunError::Linalg {
                    subcase: id,
                    source: e,
                })?;
        }
        let symbolic = symbolic_cache.get(&c).ok_or(RunError::NoSolution)?;
        let request = EigenRequest {
            v1_hz: eigrl.v1,
            v2_hz: eigrl.v2,
            nd: eigrl.nd.map(|n| n as usize),
            shift_hz: eigrl.shfscl,
        };
        let result = clock
            .time_split(format!("subcase {id}: Lanczos"), ctx.progress, |progress| {
                modes(&c, &request, symbolic, ctx.options.par(), progress)
            })
            .map_err(|e| super::mechanism(&c, st, id, e))?;
        let (result, suport) = with_rigid_body_modes(ctx, st, &c, sub, result)?;
        let summary = clock.time(format!("subcase {id}: output"), || {
            write_subcase(ctx, st, &c, sub, norm, eigrl.nd.map(|n| n as usize), result)
        })?;
        let summary = ModalSummary {
            suport,
            factor_nnz: symbolic.factor_nnz(),
            ..summary
        };
        out.push(SubcaseSummary {
            id,
            autospc: c.autospc.names.clone(),
            result: Box::new(summary),
        });
    }
    Ok(out)
}

fn write_subcase(
    ctx: &RunContext,
    st: &Structure,
    c: &Constrained,
    sub: &Subcase,
    norm: EigenNorm,
    nd: Option<usize>,
    mut r: EigenResult,
) -> Result<ModalSummary, RunError> {
    let id = sub.id;
    let m = r.eigenvalues.len();
    let nf = r.vectors.nrows();
    let generalized_mass = match norm {
        EigenNorm::Max => normalize_to_unit_max(&mut r.vectors),
        EigenNorm::Mass => vec![1.0; m],
    };
    let group = ctx.output.group(&format!("results/{id}/modal"))?;
    write_f64(&group, "frequency_hz", &r.frequencies_hz, &[m])?;
    write_f64(&group, "eigenvalue", &r.eigenvalues, &[m])?;
    write_f64(&group, "generalized_mass", &generalized_mass, &[m])?;
    write_f64(&group, "residual", &r.residuals, &[m])?;
    set_attr_f64(&group, "sturm_shift", r.sturm.shift)?;
    set_attr_i64(&group, "sturm_count", r.sturm.negative_pivots as i64)?;
    set_attr_i64(
        &group,
        "sturm_found",
        (r.sturm.found + r.sturm.below_lower) as i64,
    )?;
    set_attr_i64(
        &group,
        "sturm_consistent",
        i64::from(r.sturm.is_consistent()),
    )?;
    if let Some(note) = cut_note(&r.sturm, m) {
        set_attr_str(&group, "sturm_note", &note)?;
    }
    set_attr_f64(&group, "shift", r.shift)?;
    set_attr_str(&group, "norm", norm.name())?;
    set_attr_i64(&group, "massless_count", r.massless as i64)?;
    set_attr_i64(&group, "finite_exhausted", i64::from(r.finite_exhausted))?;
    super::write_autospc(&group, &c.autospc)?;
    let rows = GridRows::of_subcase(ctx.deck, &st.map, sub, "DISPLACEMENT", None);
    let shapes_written = rows.is_some();
    if let Some(rows) = rows {
        let shapes = shapes_in_basic(st, c, &r.vectors)?;
        rows.write(&group, "shapes", &shapes, &[m], &st.map)?;
    }
    Ok(ModalSummary {
        eigenvalues: r.eigenvalues,
        frequencies_hz: r.frequencies_hz,
        generalized_mass,
        residuals: r.residuals,
        sturm: r.sturm,
        shift: r.shift,
        norm,
        f_size: nf,
        shapes_written,
        massless: r.massless,
        finite_exhausted: r.finite_exhausted,
        nd,
        suport: None,
        restarts: r.restarts,
        solves: r.solves,
        factor_nnz: 0,
    })
}

/// A subcase's eigensolution with its SUPORT r-set applied ([`rigid_body_modes`]): the r-set
/// checked (refused when K_ll is singular or ε exceeds [`EPSILON_LIMIT`]) and the lowest r
/// roots, which must be the rigid-body ones, replaced by the M-orthonormal rigid-body shapes at
/// 0 Hz. Without SUPORT cards the result is returned as it is.
fn with_rigid_body_modes(
    ctx: &RunContext,
    st: &Structure,
    c: &Constrained,
    sub: &Subcase,
    mut r: EigenResult,
) -> Result<(EigenResult, Option<SuportCheck>), RunError> {
    let case = |what: String| RunError::Case {
        subcase: sub.id,
        what,
    };
    let dofs = suport_dofs(ctx.model, &st.map, sub.suport1).map_err(|e| case(e.to_string()))?;
    if dofs.is_empty() {
        return Ok((r, None));
    }
    let positions = (dofs.iter())
        .map(|(g, source)| {
            c.sets.f.position(*g).ok_or_else(|| {
                case(format!(
                    "{source}: {} is constrained (SPC, AUTOSPC) or dependent: a SUPORT DOF must be free",
                    st.map.name(*g)
                ))
            })
        })
        .collect::<Result<Vec<_>, _>>()?;
    let rb = rigid_body_modes(c, &positions, ctx.model.params.maxratio).map_err(case)?;
    let n_r = positions.len();
    if !(rb.epsilon <= EPSILON_LIMIT) {
        let energies: Vec<String> = rb
            .strain_energy
            .iter()
            .map(|e| format!("{e:.3e}"))
            .collect();
        return Err(case(format!(
            "the SUPORT r-set ({n_r} DOFs) is not statically determinate: rigid-body error ratio ε = {:.3e} > {EPSILON_LIMIT:e}, strain energies [{}]; a redundant SUPORT or an SPC already holding the structure strains it — remove the redundant components",
            rb.epsilon,
            energies.join(", ")
        )));
    }
    // the lowest r roots must be the rigid-body ones: well below the first elastic root
    let m = r.eigenvalues.len();
    let first_elastic = r.eigenvalues.get(n_r).copied();
    let rigid_found = m >= n_r
        && (r.eigenvalues[..n_r].iter())
            .all(|l| first_elastic.is_none_or(|e| l.abs() <= 1e-6 * e.abs()));
    if !rigid_found {
        return Err(case(format!(
            "the eigensolution does not start with the {n_r} rigid-body modes of the SUPORT r-set (EIGRL V1 must be blank or ≤ 0 and ND at least {n_r})"
        )));
    }
    for k in 0..n_r {
        for i in 0..r.vectors.nrows() {
            r.vectors[(i, k)] = rb.shapes[(i, k)];
        }
        r.eigenvalues[k] = 0.0;
        r.frequencies_hz[k] = 0.0;
        r.residuals[k] = rb.residuals[k];
    }
    let check = SuportCheck {
        dofs: n_r,
        epsilon: rb.epsilon,
        strain_energy: rb.strain_energy,
    };
    Ok((r, Some(check)))
}

/// When the Sturm check counts more roots found between the lower end of the search and its
/// shift than the `stored` modes (ND cut through a multiple root and Lanczos found the whole
/// cluster), the note saying so. Roots below V1 are not stored and do not count.
pub fn cut_note(sturm: &SturmCheck, stored: usize) -> Option<String> {
    let found = sturm.found;
    (sturm.is_consistent() && found > stored).then(|| {
        format!(
            "a multiple root at the cut: {found} roots below {:.6e} Hz, {stored} stored as ND requests",
            lambda_to_hz(sturm.shift)
        )
    })
}

/// Modes with a larger residual are flagged in the run's warnings.
pub const RESIDUAL_WARNING: f64 = 1e-6;

impl Report for ModalSummary {
    fn render(&self, subcase: u32) -> Vec<String> {
        let m = self;
        let mut out = vec![format!(
            "subcase {}: {} mode(s), f-set {} DOFs, NORM = {:?}",
            subcase,
            m.frequencies_hz.len(),
            m.f_size,
            m.norm
        )];
        if m.frequencies_hz.is_empty() {
            out.push("  no mode in the requested range (EIGRL V1/V2)".to_string());
        } else {
            out.push(format!(
                "  {:>4}  {:>14}  {:>14}  {:>10}",
                "mode", "f [Hz]", "gen. mass", "residual"
            ));
        }
        for (k, f) in m.frequencies_hz.iter().enumerate() {
            out.push(format!(
                "  {:>4}  {:>14}  {:>14}  {:>10}",
                k + 1,
                sci(*f, 6),
                sci(m.generalized_mass[k], 6),
                sci(m.residuals[k], 1)
            ));
        }
        if let Some(SuportCheck {
            dofs: n_r,
            epsilon,
            strain_energy,
        }) = &m.suport
        {
            let worst = strain_energy.iter().fold(0.0_f64, |a, e| a.max(e.abs()));
            out.push(format!(
                "  SUPORT r-set of {n_r} DOF(s): rigid-body error ratio ε = {}, largest strain energy {}; the first {n_r} mode(s) are its rigid-body modes at 0 Hz",
                sci(*epsilon, 2),
                sci(worst, 2)
            ));
        }
        out.push(format!("  {}", sturm_line(&m.sturm)));
        out.push(format!(
            "  Lanczos: {} step(s) (solves with K − σM), {} restart(s); factor of K − σM: {} entries ({:.1} MB)",
            m.solves,
            m.restarts,
            m.factor_nnz,
            m.factor_nnz as f64 * 8.0 / 1e6
        ));
        if let Some(note) = cut_note(&m.sturm, m.eigenvalues.len()) {
            out.push(format!("  note: {note}"));
        }
        out
    }

    fn warnings(&self, subcase: u32) -> Vec<String> {
        let m = self;
        let mut warnings = Vec::new();
        let bad: Vec<String> = m
            .residuals
            .iter()
            .enumerate()
            .filter(|(_, r)| !(**r <= RESIDUAL_WARNING))
            .map(|(k, r)| format!("{} ({r:.1e})", k + 1))
            .collect();
        if !bad.is_empty() {
            warnings.push(format!(
                "subcase {}: mode(s) {} have residual ‖Kφ − λMφ‖/‖Kφ‖ above {RESIDUAL_WARNING:e}: not trustworthy (more modes requested than the mass matrix has finite ones, or masses many orders of magnitude apart, as in the large-mass method, where the frequencies stay accurate but the shapes lose digits)",
                subcase,
                bad.join(", ")
            ));
        }
        if m.finite_exhausted {
            let why = if m.massless > 0 {
                format!(
                    "M is singular on {} massless f-set DOF(s) (no mass on that row)",
                    m.massless
                )
            } else {
                "M is rank-deficient on DOFs that have mass (e.g. an offset CONM2 without inertia)"
                    .to_string()
            };
            warnings.push(format!(
                "subcase {}: only {} finite mode(s) exist above the lower bound, ND = {} asked for more: {why}; the other eigenvalues are infinite and are not returned",
                subcase,
                m.eigenvalues.len(),
                m.nd.map_or("(blank)".to_string(), |n| n.to_string()),
            ));
        }
        if !m.sturm.is_consistent() {
            warnings.push(format!(
                "subcase {}: Sturm check found {} eigenvalue(s) below {:.6e} Hz that Lanczos did not return",
                subcase,
                m.sturm.missing(),
                lambda_to_hz(m.sturm.shift)
            ));
        }
        warnings
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// ND = 12 through a double root: 13 roots below the Sturm shift, 12 stored, and a note.
    #[test]
    fn a_cut_through_a_multiple_root_is_noted() {
        let sturm = SturmCheck {
            shift: (2.0 * std::f64::consts::PI * 100.0_f64).powi(2),
            negative_pivots: 13,
            below_lower: 0,
            found: 13,
        };
        let note = cut_note(&sturm, 12).expect("a note");
        assert!(
            note.contains("13 roots below 1.000000e2 Hz, 12 stored"),
            "{note}"
        );
        assert_eq!(cut_note(&sturm, 13), None);
        let above_v1 = SturmCheck {
            below_lower: 1,
            found: 12,
            ..sturm
        };
        assert_eq!(cut_note(&above_v1, 12), None, "a root below V1 is no cut");
        let summary = ModalSummary {
            eigenvalues: vec![1.0; 12],
            frequencies_hz: vec![1.0; 12],
            generalized_mass: vec![1.0; 12],
            residuals: vec![0.0; 12],
            sturm,
            shift: 0.0,
            norm: EigenNorm::Mass,
            f_size: 60,
            shapes_written: false,
            massless: 0,
            finite_exhausted: false,
            nd: Some(12),
            suport: None,
            restarts: 0,
            solves: 0,
            factor_nnz: 0,
        };
        let lines = summary.render(1);
        assert!(
            lines
                .last()
                .is_some_and(|l| l.starts_with("  note: a multiple root at the cut")),
            "{lines:?}"
        );
    }
}
