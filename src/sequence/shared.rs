//! What several drivers share: the discretized mesh of the mesh drivers ([`structure`]), the
//! time steps of a `TSTEP` and the damping warning (full-model and pROM transients), the
//! frequency lines of `FREQUENCY` and the FRF output (full-model and pROM FRFs), the PTABLE
//! parameters of a `PVAL` selection (pROM transients and SOL FMB).

use super::report::weight_lines;
use super::{Clock, RunContext, RunError};
use crate::analysis::weight;
use crate::assembly::AssemblyError;
use crate::deck::Solution;
use crate::deck::cards::{Freq, TintegMethod, Tstep};
use crate::deck::case_control::Subcase;
use crate::discretize::Structure;
use crate::discretize::loads::table_of;
use crate::dynamics::integrators::Method;
use crate::dynamics::table::Table;
use crate::io::{IoError, set_attr_f64s, set_attr_str, write_c64, write_f64, write_strings};
use crate::linalg::c64;
use crate::model::Model;

/// The TSTEP of a subcase, its method and the method's name for output: the TINTEG with the
/// TSTEP's id; without one, for the Nastran sequences (SOL 109/112, SEDTRAN, SEMTRAN) the
/// trapezoidal rule (generalized-α with ρ∞ = 1: second order, no numerical damping, as the
/// Newmark-β integration of Nastran's transient solutions), for `SOL TRANSIENT` BDF1 (the
/// thesis's eq. 2.61).
pub fn method_of<'a>(
    model: &'a Model,
    sub: &Subcase,
) -> Result<(&'a Tstep, Method, String), RunError> {
    let case = |what: String| RunError::Case {
        subcase: sub.id,
        what,
    };
    let sid = sub
        .tstep
        .ok_or_else(|| case("SOL TRANSIENT needs TSTEP = <sid> in case control".into()))?;
    let tstep = model
        .tstep(sid)
        .ok_or_else(|| case(format!("TSTEP = {sid} selects no TSTEP card")))?;
    if model.tstepvar(sid).is_some() {
        return Err(case(format!(
            "TSTEPVAR {sid} asks for error-controlled steps, which only SOL FMB takes; SOL TRANSIENT runs the fixed steps of TSTEP {sid} (remove the TSTEPVAR card)"
        )));
    }
    let nastran = matches!(
        model.sol,
        Some(Solution::TransientDirect | Solution::TransientModal)
    );
    let (method, name) = match model.tinteg(sid).map(|t| (t.method, t.rho_inf)) {
        None if nastran => (
            Method::GeneralizedAlpha { rho_inf: 1.0 },
            "trapezoidal (GALPHA rho_inf = 1, the SOL 109/112 default without TINTEG)".to_string(),
        ),
        None | Some((TintegMethod::Bdf1, _)) => (Method::Bdf1, "BDF1".to_string()),
        Some((TintegMethod::Bdf2, _)) => (Method::Bdf2, "BDF2".to_string()),
        Some((TintegMethod::Galpha, rho_inf)) => (
            Method::GeneralizedAlpha { rho_inf },
            format!("GALPHA (rho_inf = {rho_inf})"),
        ),
    };
    Ok((tstep, method, name))
}

/// Number of output rows of a TSTEP: the initial state, then every NO-th step of each interval.
pub fn output_rows(intervals: &[(u32, f64, u32)]) -> usize {
    1 + intervals
        .iter()
        .map(|&(count, _, every)| count as usize / every.max(1) as usize)
        .sum::<usize>()
}

/// The frequency lines (Hz) of the subcase's `FREQUENCY = sid`: every FREQ, FREQ1–FREQ5 of
/// that SID, sorted, duplicates removed. FREQ3–FREQ5 place lines from `modes_hz`, the natural
/// frequencies of a modal solution; without them (`None`: a direct solution) those cards are
/// left out and returned as the second value, for the caller to warn or refuse.
pub fn frequency_lines<'m>(
    model: &'m Model,
    sub: &Subcase,
    modes_hz: Option<&[f64]>,
) -> Result<(Vec<f64>, Vec<&'m Freq>), RunError> {
    let case = |what: String| RunError::Case {
        subcase: sub.id,
        what,
    };
    let sid = sub
        .frequency
        .ok_or_else(|| case("SOL FRF needs FREQUENCY = <FREQ sid> in case control".into()))?;
    let cards = model.frequency_cards(sid);
    let (used, ignored): (Vec<&Freq>, Vec<&Freq>) = cards
        .iter()
        .partition(|f| modes_hz.is_some() || !f.needs_modes());
    let mut hz: Vec<f64> = used
        .iter()
        .flat_map(|f| f.frequencies(modes_hz.unwrap_or_default()))
        .collect();
    hz.sort_by(f64::total_cmp);
    hz.dedup();
    if hz.is_empty() {
        let what = match (cards.is_empty(), ignored.first()) {
            (true, _) => format!("FREQUENCY = {sid} selects no FREQ, FREQ1 … FREQ5 card"),
            (false, Some(f)) => format!(
                "FREQUENCY = {sid} selects only FREQ3/FREQ4/FREQ5 cards ({} at {}), which place lines from the natural frequencies of a modal frequency response (SOL 111); this solution has none",
                f.card_name(),
                f.loc
            ),
            (false, None) => format!(
                "FREQUENCY = {sid}: its cards place no line (FREQ3/FREQ4/FREQ5 found no natural frequency in their range)"
            ),
        };
        return Err(case(what));
    }
    Ok((hz, ignored))
}

/// Writes `frequency_hz`, `H` (f × o × i), `inputs` and `outputs` into `group`.
pub fn write_frf(
    group: &hdf5_metno::Group,
    hz: &[f64],
    flat: &[c64],
    inputs: &[String],
    outputs: &[String],
) -> Result<(), IoError> {
    write_f64(group, "frequency_hz", hz, &[hz.len()])?;
    write_c64(group, "H", flat, &[hz.len(), outputs.len(), inputs.len()])?;
    let refs: Vec<&str> = inputs.iter().map(String::as_str).collect();
    write_strings(group, "inputs", &refs)?;
    let refs: Vec<&str> = outputs.iter().map(String::as_str).collect();
    write_strings(group, "outputs", &refs)?;
    Ok(())
}

/// The mesh every mesh driver runs on: the [`Structure`] of the model, its build steps timed;
/// with `PARAM,GRDPNT` ≥ 0 also its grid-point weight table (console and `/model/gpwg`).
pub fn structure(ctx: &RunContext, clock: &mut Clock) -> Result<Structure, RunError> {
    let st = Structure::build_timed(ctx.model, &ctx.options, ctx.progress, &mut |name, d| {
        clock.record(name, d)
    })?;
    if ctx.model.params.grdpnt >= 0 {
        let start = std::time::Instant::now();
        let lines = grid_point_weight(ctx, &st)?;
        clock.record("grid-point weight", start.elapsed());
        clock.report_model(lines);
    }
    Ok(st)
}

/// The grid-point weight generator about `PARAM,GRDPNT` (0: the basic origin, > 0: a grid):
/// writes `/model/gpwg`, returns the console table.
fn grid_point_weight(ctx: &RunContext, st: &Structure) -> Result<Vec<String>, RunError> {
    let model = ctx.model;
    let id = u32::try_from(model.params.grdpnt).unwrap_or(0);
    let (reference, label) = if id == 0 {
        ([0.0; 3], "basic origin".to_string())
    } else {
        let grid = model.grid(id).ok_or(AssemblyError::MissingGrid {
            card: "PARAM GRDPNT".to_string(),
            grid: id,
        })?;
        (grid.xyz, format!("GRID {id}"))
    };
    let m_gg = st.mass_gg().evaluate(&st.weights(st.mass_gg()))?;
    let xyz: Vec<[f64; 3]> = model.grids.iter().map(|g| g.xyz).collect();
    let w = weight::grid_point_weight(
        &m_gg,
        &st.map,
        &st.frames,
        &xyz,
        reference,
        model.params.wtmass,
    )?;
    let group = ctx.output.group("model/gpwg")?;
    set_attr_str(&group, "reference", &label)?;
    set_attr_f64s(&group, "reference_xyz", &reference)?;
    let flat = |rows: &[[f64; 3]; 3]| rows.concat();
    write_f64(&group, "mo", &w.mo.concat(), &[6, 6])?;
    write_f64(&group, "s", &flat(&w.s), &[3, 3])?;
    write_f64(&group, "mass", &w.mass, &[3])?;
    write_f64(&group, "cg", &flat(&w.cg), &[3, 3])?;
    write_f64(&group, "inertia", &flat(&w.inertia), &[3, 3])?;
    write_f64(&group, "principal_inertia", &w.principal, &[3])?;
    write_f64(&group, "principal_axes", &flat(&w.q), &[3, 3])?;
    Ok(weight_lines(&w, &label))
}

/// The warning of a transient run whose structural damping `PARAM,G` is not applied: Nastran
/// turns G into viscous damping (G/W3)·K in transient response only with PARAM,W3, whose
/// default 0 leaves it out.
pub fn damping_warning(model: &Model) -> Option<String> {
    let p = &model.params;
    (p.g != 0.0 && p.w3 == 0.0).then(|| format!("PARAM,G = {} is not applied by SOL TRANSIENT without PARAM,W3 (as Nastran): set W3 (rad/s) for (G/W3)·K, or use Rayleigh damping (PARAM,ALPHA1 / BETA1)", p.g))
}

/// The warning of a full-model transient run whose elements' structural damping GE is not
/// applied: Nastran turns it into viscous damping (1/W4)·Σ GE_e K_e only with PARAM,W4.
pub fn w4_warning(model: &Model) -> Option<String> {
    if model.params.w4 > 0.0 {
        return None;
    }
    let some = model.structural_damping_elements(4);
    (!some.is_empty()).then(|| format!("the structural damping GE of {}{} is not applied by SOL TRANSIENT without PARAM,W4 (as Nastran): set W4 (rad/s) for (1/W4)·Σ GE·K_e", some.join(", "), if some.len() == 4 { ", …" } else { "" }))
}

/// The tables of the PTABLE cards of `PVAL = id`, each keyed by `resolve(NAME)` (an error text
/// when NAME is no parameter of the model run); a NAME that the PVAL cards set (`in_pval`) or an
/// earlier PTABLE already names (names compare without case) is refused. Errors name the card's
/// file:line and field.
pub fn parameter_tables<K>(
    model: &Model,
    id: u32,
    in_pval: impl Fn(&str) -> bool,
    resolve: impl Fn(&str) -> Result<K, String>,
) -> Result<Vec<(K, Table)>, String> {
    let mut out: Vec<(K, Table)> = Vec::new();
    let mut names: Vec<&str> = Vec::new();
    for card in model.ptables(id) {
        let at = |what: String| format!("{}: PTABLE {id}: {what}", card.loc);
        let key = resolve(&card.name).map_err(|e| at(format!("field 3 (NAME): {e}")))?;
        if in_pval(&card.name) || names.iter().any(|n| n.eq_ignore_ascii_case(&card.name)) {
            return Err(at(format!(
                "field 3 (NAME): {} is given twice (PVAL and PTABLE, or two PTABLEs)",
                card.name
            )));
        }
        let table = table_of(model, card.tid, "field 4 (TID)").map_err(at)?;
        names.push(&card.name);
        out.push((key, table));
    }
    Ok(out)
}
