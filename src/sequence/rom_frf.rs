//! `SOL FRF` (108/111) on a pROM artifact (`ROM = 'file.h5'`): the receptance matrix between
//! the pROM's load inputs (its BSET DOFs, `/prom/inputs`) at the subcase's `PVAL` values,
//! H(ω) = S_rᵀ (K_r − ω²M_r + iωC_r)⁻¹ S_r with C_r = αM_r + βK_r (thesis eq. 3.31), at the
//! frequencies of `FREQUENCY = sid` (FREQ, FREQ1, FREQ2 cards of that SID, combined and
//! sorted). A line where the reduced dynamic stiffness is singular (undamped resonance) is an
//! error naming the frequency.
//!
//! Outputs: the input DOFs (receptance) and then the pROM's SENSORs (DISP: displacement, STRAIN:
//! strain, VEL: iω × displacement, ACCEL: −ω² × displacement, per unit force).
//!
//! Written: `/results/<id>/frf/{frequency_hz (f), H (f × o × i, complex as h5py), inputs (i),
//! outputs (o)}` with attributes `rom`, `params`, `values`.

use faer::{Mat, c64};

use super::rom_case::RomAtPoint;
use super::{Clock, RunContext, RunError, SubcaseResult, SubcaseSummary};
use crate::deck::case_control::Subcase;
use crate::dynamics::frf::{DenseModel, receptance};
use crate::io::{read_prom_inputs, read_prom_sensors, set_attr_f64s, set_attr_str, set_attr_strings, write_c64, write_f64, write_strings};

/// What one pROM FRF subcase computed.
#[derive(Debug, Clone)]
pub struct RomFrfSummary {
    pub rom: std::path::PathBuf,
    pub lines: usize,
    pub inputs: Vec<String>,
    pub extrapolated: Vec<String>,
    /// Largest |H| over lines and pairs, with its frequency (Hz), for the console.
    pub peak: (f64, f64),
}

/// Runs every subcase on its pROM.
pub fn run(ctx: &RunContext, clock: &mut Clock) -> Result<Vec<SubcaseSummary>, RunError> {
    ctx.model.subcases.iter().map(|sub| clock.time(format!("subcase {}: pROM FRF", sub.id), || subcase(ctx, sub))).collect()
}

fn subcase(ctx: &RunContext, sub: &Subcase) -> Result<SubcaseSummary, RunError> {
    let id = sub.id;
    let case = |what: String| RunError::Case { subcase: id, what };
    let RomAtPoint { path, prom, p, at, extrapolated } = RomAtPoint::load(ctx, sub)?;
    let (names, s_r) = read_prom_inputs(&path, prom.size())?;
    if names.is_empty() {
        return Err(case(format!("{} has no load inputs (build it with PMOR BSET and ASET1)", path.display())));
    }
    let sid = sub.frequency.ok_or_else(|| case("SOL FRF needs FREQUENCY = <FREQ sid> in case control".into()))?;
    let mut hz: Vec<f64> = ctx.model.bulk.freq.iter().filter(|f| f.sid == sid).flat_map(|f| f.frequencies()).collect();
    if hz.is_empty() {
        return Err(case(format!("FREQUENCY = {sid} selects no FREQ, FREQ1 or FREQ2 card")));
    }
    hz.sort_by(f64::total_cmp);
    hz.dedup();
    let omegas: Vec<f64> = hz.iter().map(|f| 2.0 * std::f64::consts::PI * f).collect();
    let (sensor_names, sensor_kinds, h_r) = read_prom_sensors(&path, prom.size())?;
    // outputs: the input DOFs (receptance), then the sensors (DISP ×1, VEL ×iω, ACCEL ×−ω²)
    let k = names.len();
    let outputs = Mat::<f64>::from_fn(k + sensor_names.len(), prom.size(), |o, j| if o < k { s_r[(j, o)] } else { h_r[(o - k, j)] });
    let model = DenseModel { stiffness: at.stiffness.as_ref(), mass: at.mass.as_ref(), damping: at.damping.as_ref() };
    let h = receptance(&model, s_r.as_ref(), outputs.as_ref(), &omegas).map_err(|e| case(format!("{}: {e}", path.display())))?;
    let factor = |o: usize, w: f64| -> c64 {
        match o.checked_sub(k).map(|s| sensor_kinds[s].as_str()) {
            Some("VEL") => c64::new(0.0, w),
            Some("ACCEL") => c64::new(-w * w, 0.0),
            _ => c64::new(1.0, 0.0),
        }
    };
    let n_out = outputs.nrows();
    let mut flat = Vec::with_capacity(hz.len() * n_out * k);
    let mut peak = (0.0_f64, 0.0);
    for ((hw, f), w) in h.iter().zip(&hz).zip(&omegas) {
        for o in 0..n_out {
            for i in 0..k {
                let z: c64 = hw[(o, i)] * factor(o, *w);
                if z.norm() > peak.0 {
                    peak = (z.norm(), *f);
                }
                flat.push(z);
            }
        }
    }
    let group = ctx.output.group(&format!("results/{id}/frf"))?;
    write_f64(&group, "frequency_hz", &hz, &[hz.len()])?;
    write_c64(&group, "H", &flat, &[hz.len(), n_out, k])?;
    let name_refs: Vec<&str> = names.iter().map(String::as_str).collect();
    write_strings(&group, "inputs", &name_refs)?;
    let output_refs: Vec<&str> = names.iter().chain(&sensor_names).map(String::as_str).collect();
    write_strings(&group, "outputs", &output_refs)?;
    set_attr_str(&group, "rom", &path.display().to_string())?;
    let params: Vec<&str> = prom.parameters.iter().map(|q| q.name.as_str()).collect();
    set_attr_strings(&group, "params", &params)?;
    set_attr_f64s(&group, "values", &p)?;
    let summary = RomFrfSummary { rom: path, lines: hz.len(), inputs: names, extrapolated, peak };
    Ok(SubcaseSummary { id, autospc: Vec::new(), result: SubcaseResult::RomFrf(summary) })
}
