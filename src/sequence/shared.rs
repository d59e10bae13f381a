//! What several drivers share: the discretized mesh of the mesh drivers ([`structure`]), the
//! time steps of a `TSTEP` and the damping warning (full-model and pROM transients), the
//! frequency lines of `FREQUENCY` and the FRF output (full-model and pROM FRFs), and the
//! placement of a DAREA on a pROM's inputs (pROM transient and estimation).

use super::{Clock, RunContext, RunError};
use crate::deck::cards::Eigrl;
use crate::deck::cards::{TintegMethod, Tstep};
use crate::deck::case_control::Subcase;
use crate::discretize::{Constrained, Structure};
use crate::dynamics::integrators::Method;
use crate::dynamics::measurement::Reads;
use crate::io::{IoError, write_c64, write_f64, write_strings};
use crate::linalg::{
    EigenProblem, EigenRequest, EigenResult, LanczosOptions, SymbolicFactor, solve_modes,
};
use crate::linalg::{Mat, c64};
use crate::model::Model;
use crate::model::dynamic_loads::Excitation;

/// The TSTEP of a subcase, its method (TINTEG with the TSTEP's id; BDF1 without one) and the
/// method's name for output.
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
    let (method, name) = match model.tinteg(sid).map(|t| (t.method, t.rho_inf)) {
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

/// The frequency lines (Hz) of the subcase's `FREQUENCY = sid`: every FREQ, FREQ1, FREQ2 of
/// that SID, sorted, duplicates removed.
pub fn frequency_lines(model: &Model, sub: &Subcase) -> Result<Vec<f64>, RunError> {
    let case = |what: String| RunError::Case {
        subcase: sub.id,
        what,
    };
    let sid = sub
        .frequency
        .ok_or_else(|| case("SOL FRF needs FREQUENCY = <FREQ sid> in case control".into()))?;
    let hz = model.frequencies_hz(sid);
    if hz.is_empty() {
        return Err(case(format!(
            "FREQUENCY = {sid} selects no FREQ, FREQ1 or FREQ2 card"
        )));
    }
    Ok(hz)
}

/// Scales H by each output row's (iω)^k ([`Reads::frequency_factor`]: the input DOFs, DISP and
/// STRAIN read displacement, VEL iω, ACCEL −ω²) and flattens it line-major (f × o × i); also
/// returns the largest |H| and its frequency.
pub fn scaled_flat(h: &[Mat<c64>], hz: &[f64], reads: &[Reads]) -> (Vec<c64>, (f64, f64)) {
    let mut flat = Vec::with_capacity(h.iter().map(|m| m.nrows() * m.ncols()).sum());
    let mut peak = (0.0_f64, 0.0);
    for (hw, f) in h.iter().zip(hz) {
        let w = 2.0 * std::f64::consts::PI * f;
        for (o, row) in reads.iter().enumerate() {
            let factor = row.frequency_factor(w);
            for i in 0..hw.ncols() {
                let z = hw[(o, i)] * factor;
                if z.norm() > peak.0 {
                    peak = (z.norm(), *f);
                }
                flat.push(z);
            }
        }
    }
    (flat, peak)
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

/// Adds a DAREA entry, which must name a pROM input DOF (`GRID:component`), to a reduced load
/// shape: scale × column of S_r.
pub fn place_input(
    names: &[String],
    s_r: &Mat<f64>,
    d: &Excitation,
    scale: f64,
    shape: &mut [f64],
) -> Result<(), String> {
    let comp = d.component;
    let name = format!("{}:{comp}", d.grid);
    let j = names.iter().position(|x| *x == name).ok_or_else(|| {
        format!(
            "DAREA {}: GRID {} component {comp} is not an input DOF of the pROM (inputs: {})",
            d.sid,
            d.grid,
            names.join(", ")
        )
    })?;
    shape
        .iter_mut()
        .enumerate()
        .for_each(|(i, s)| *s += scale * s_r[(i, j)]);
    Ok(())
}

/// The modes an EIGRL card asks for, of the constrained model `c` (shift-invert Lanczos on the
/// f-set with the symbolic analysis of K_ff), timed as the subcase's "Lanczos" step; a singular
/// factor is reported as the mechanism DOF it comes from.
pub fn lanczos_modes(
    ctx: &RunContext,
    st: &Structure,
    c: &Constrained,
    id: u32,
    eigrl: &Eigrl,
    symbolic: &SymbolicFactor,
    clock: &mut Clock,
) -> Result<EigenResult, RunError> {
    let request = EigenRequest {
        v1_hz: eigrl.v1,
        v2_hz: eigrl.v2,
        nd: eigrl.nd.map(|n| n as usize),
        shift_hz: eigrl.shfscl,
    };
    let problem = EigenProblem {
        k: &c.k_ff,
        m: &c.m_ff,
        symbolic,
    };
    clock
        .time(format!("subcase {id}: Lanczos"), || {
            solve_modes(
                &problem,
                &request,
                &LanczosOptions::default(),
                ctx.options.par(),
                ctx.progress,
            )
        })
        .map_err(|e| super::mechanism(c, st, id, e))
}

/// The mesh every mesh driver runs on: the [`Structure`] of the model, its build steps timed.
pub fn structure(ctx: &RunContext, clock: &mut Clock) -> Result<Structure, RunError> {
    Ok(Structure::build_timed(
        ctx.model,
        &ctx.options,
        ctx.progress,
        &mut |name, d| clock.record(name, d),
    )?)
}

/// The warning of a transient run whose structural damping `PARAM,G` is not applied: Nastran
/// turns G into viscous damping (G/W3)·K in transient response only with PARAM,W3, whose
/// default 0 leaves it out.
pub fn damping_warning(model: &Model) -> Option<String> {
    let p = &model.params;
    (p.g != 0.0 && p.w3 == 0.0).then(|| format!("PARAM,G = {} is not applied by SOL TRANSIENT without PARAM,W3 (as Nastran): set W3 (rad/s) for (G/W3)·K, or use Rayleigh damping (PARAM,ALPHA1 / BETA1)", p.g))
}
