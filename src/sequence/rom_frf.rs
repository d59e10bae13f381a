//! `SOL FRF` (108/111) on a pROM artifact (`ROM = 'file.h5'`): the receptance matrix between
//! the pROM's load inputs (its BSET DOFs, `/prom/inputs`) at the subcase's `PVAL` values,
//! H(ω) = S_rᵀ (K_r − ω²M_r + iωC_r)⁻¹ S_r with C_r = αM_r + βK_r (thesis eq. 3.31), at the
//! frequencies of `FREQUENCY = sid` (FREQ, FREQ1, FREQ2 cards of that SID, combined and
//! sorted; FREQ3–FREQ5, which place lines from natural frequencies, are refused), by modal superposition over all the pROM's modes at p (one n_r × n_r eigenproblem,
//! exact since C_r is Rayleigh; [`rayleigh_receptance`]). A line where the reduced dynamic
//! stiffness is singular (undamped resonance) is an error naming the frequency.
//!
//! Outputs: the input DOFs (receptance) and then the pROM's SENSORs (DISP: displacement, STRAIN:
//! strain, VEL: iω × displacement, ACCEL: −ω² × displacement, per unit force).
//!
//! Written: `/results/<id>/frf/{frequency_hz (f), H (f × o × i, complex as h5py), inputs (i),
//! outputs (o)}` with attributes `rom`, `params`, `values`.

use super::driver::{Basis, Driver};
use super::report::{Report, sci};
use super::rom_case::RomAtPoint;
use super::rom_case::extrapolation_warning;
use super::shared::{frequency_lines, write_frf};
use super::{Clock, RunContext, RunError, SubcaseSummary};
use crate::deck::Solution;
use crate::deck::case_control::Subcase;
use crate::dynamics::frf::scaled_flat;
use crate::dynamics::frf::{DenseModel, FrfError, rayleigh_receptance, receptance};
use crate::dynamics::measurement::{Reads, SensorRows};
use crate::io::{
    read_prom_inputs, read_prom_sensors, set_attr_f64s, set_attr_str, set_attr_strings,
};

/// What one pROM FRF subcase computed.
#[derive(Debug, Clone)]
pub struct RomFrfSummary {
    pub rom: std::path::PathBuf,
    pub lines: usize,
    pub inputs: Vec<String>,
    /// The input DOFs, then the pROM's sensors.
    pub outputs: Vec<String>,
    pub extrapolated: Vec<String>,
    /// Largest |H| over lines and pairs, with its frequency (Hz), for the console.
    pub peak: (f64, f64),
}

/// The FRF driver on pROM artifacts.
pub struct RomFrf;

impl Driver for RomFrf {
    fn name(&self) -> &'static str {
        "FRF"
    }

    fn solutions(&self) -> &'static [Solution] {
        &[Solution::FrfDirect, Solution::FrfModal, Solution::Frf]
    }

    fn basis(&self) -> Basis {
        Basis::Rom
    }

    /// Runs every subcase on its pROM.
    fn run(&self, ctx: &RunContext, clock: &mut Clock) -> Result<Vec<SubcaseSummary>, RunError> {
        ctx.model
            .subcases
            .iter()
            .map(|sub| {
                clock.time(format!("subcase {}: pROM FRF", sub.id), || {
                    subcase(ctx, sub)
                })
            })
            .collect()
    }
}

fn subcase(ctx: &RunContext, sub: &Subcase) -> Result<SubcaseSummary, RunError> {
    let id = sub.id;
    let case = |what: String| RunError::Case { subcase: id, what };
    let RomAtPoint {
        path,
        prom,
        p,
        at,
        extrapolated,
    } = RomAtPoint::load(ctx, sub)?;
    let (names, s_r) = read_prom_inputs(&path, prom.size())?;
    if names.is_empty() {
        return Err(case(format!(
            "{} has no load inputs (build it with PMOR BSET and ASET1)",
            path.display()
        )));
    }
    if let Some(sid) = sub.random {
        return Err(case(format!(
            "RANDOM = {sid}: a random response is computed from the grid responses of the full-model SOL 108/111; a pROM FRF has no grids"
        )));
    }
    if ctx.model.params.g != 0.0 {
        return Err(case(format!(
            "PARAM,G = {}: structural damping is applied by the full-model SOL 108/111 only; a pROM carries the Rayleigh damping of its build (PARAM,ALPHA1 / BETA1)",
            ctx.model.params.g
        )));
    }
    let (hz, ignored) = frequency_lines(ctx.model, sub, None)?;
    if let Some(f) = ignored.first() {
        return Err(case(format!(
            "{} at {} places lines from natural frequencies, which a pROM FRF does not compute; list the lines with FREQ, FREQ1 or FREQ2",
            f.card_name(),
            f.loc
        )));
    }
    let omegas: Vec<f64> = hz.iter().map(|f| 2.0 * std::f64::consts::PI * f).collect();
    let (sensor_names, sensor_kinds, h_r) = read_prom_sensors(&path, prom.size())?;
    let sensors = SensorRows::new(sensor_names, sensor_kinds, h_r)
        .map_err(|e| case(format!("{}: {e}", path.display())))?;
    // outputs: the input DOFs (receptance), then the sensors (DISP ×1, VEL ×iω, ACCEL ×−ω²)
    let k = names.len();
    let outputs = sensors.below_inputs(s_r.as_ref());
    // all the pROM's modes at p, then O(n) per line and pair; the dense LU per line only when
    // the reduced eigenproblem cannot be solved (an ill-conditioned M_r)
    let h = match rayleigh_receptance(
        at.stiffness(),
        at.mass(),
        (prom.alpha, prom.beta),
        s_r.as_ref(),
        outputs.as_ref(),
        &omegas,
    ) {
        Err(FrfError::Eigen(_)) => receptance(
            &DenseModel {
                stiffness: at.stiffness(),
                mass: at.mass(),
                damping: at.damping(),
                structural: None,
            },
            s_r.as_ref(),
            outputs.as_ref(),
            &omegas,
        ),
        modal => modal,
    }
    .map_err(|e| case(format!("{}: {e}", path.display())))?;
    let reads: Vec<Reads> = (0..k)
        .map(|_| Reads::Displacement)
        .chain(sensors.reads.iter().copied())
        .collect();
    let (flat, peak) = scaled_flat(&h, &hz, &reads);
    let group = ctx.output.group(&format!("results/{id}/frf"))?;
    let outputs: Vec<String> = names.iter().chain(&sensors.names).cloned().collect();
    write_frf(&group, &hz, &flat, &names, &outputs)?;
    set_attr_str(&group, "rom", &path.display().to_string())?;
    let params: Vec<&str> = prom.parameters.iter().map(|q| q.name.as_str()).collect();
    set_attr_strings(&group, "params", &params)?;
    set_attr_f64s(&group, "values", &p)?;
    let summary = RomFrfSummary {
        rom: path,
        lines: hz.len(),
        inputs: names,
        outputs,
        extrapolated,
        peak,
    };
    Ok(SubcaseSummary {
        id,
        autospc: Vec::new(),
        result: Box::new(summary),
    })
}

impl Report for RomFrfSummary {
    fn render(&self, subcase: u32) -> Vec<String> {
        let r = self;
        vec![
            format!(
                "subcase {}: FRF of the pROM {} at {} line(s), {} input(s) × {} output(s) ({})",
                subcase,
                r.rom.display(),
                r.lines,
                r.inputs.len(),
                r.outputs.len(),
                r.inputs.join(", ")
            ),
            format!(
                "  largest |H| {} at {} Hz",
                sci(r.peak.0, 4),
                sci(r.peak.1, 4)
            ),
        ]
    }

    fn warnings(&self, subcase: u32) -> Vec<String> {
        extrapolation_warning(subcase, &self.extrapolated, &self.rom)
            .into_iter()
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The console line counts the outputs (input DOFs and sensors), not the inputs twice.
    #[test]
    fn report_counts_inputs_and_outputs() {
        let summary = RomFrfSummary {
            rom: "blade.h5".into(),
            lines: 10,
            inputs: vec!["1:3".into()],
            outputs: vec!["1:3".into(), "S1".into(), "S2".into()],
            extrapolated: Vec::new(),
            peak: (1.0, 2.0),
        };
        let lines = summary.render(7);
        assert!(
            lines[0].starts_with(
                "subcase 7: FRF of the pROM blade.h5 at 10 line(s), 1 input(s) × 3 output(s) (1:3)"
            ),
            "{lines:?}"
        );
        assert!(summary.warnings(7).is_empty());
    }
}
