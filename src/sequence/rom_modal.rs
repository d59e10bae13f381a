//! `SOL MODAL` on a pROM artifact (`ROM = 'file.h5'`): the pROM is evaluated at the subcase's
//! `PVAL` values (parameters not listed keep their nominal values) and its frequencies come
//! from the dense generalized eigenproblem of (K_r(p), M_r(p)) — no full-model work.
//!
//! `METHOD = sid` (EIGRL) applies as on the full model: ND keeps the lowest ND modes, V1/V2
//! the band. The path is relative to the deck's directory. A parameter outside the pROM's box
//! is evaluated (the affine form holds everywhere) with a warning naming it; an ill-conditioned
//! reduced mass matrix is an error ([`crate::linalg::dense`]).
//!
//! Written: `/results/<id>/modal/{frequency_hz, eigenvalue, generalized_mass, residual}` with
//! attributes `rom` (the artifact path), `params` and `values`.

use super::driver::{Basis, Driver, ElementDampingUse};
use crate::deck::Solution;
use std::path::PathBuf;

use super::report::{Report, lambda_to_hz, sci};
use super::rom_case::RomAtPoint;
use super::rom_case::extrapolation_warning;
use super::{Clock, RunContext, RunError, SubcaseSummary};
use crate::deck::case_control::Subcase;
use crate::io::{set_attr_f64s, set_attr_str, set_attr_strings, write_f64};
use crate::rom::modes::ReducedModes;

/// What one ROM modal subcase found.
#[derive(Debug, Clone)]
pub struct RomModalSummary {
    pub rom: PathBuf,
    pub n_red: usize,
    pub frequencies_hz: Vec<f64>,
    /// (name, value) the pROM was evaluated at.
    pub values: Vec<(String, f64)>,
    /// Parameters outside the pROM's box.
    pub extrapolated: Vec<String>,
    /// EIGRL ND when it asked for more modes than the pROM's band holds (all were returned).
    pub nd_short: Option<usize>,
}

/// The MODAL driver on pROM artifacts.
pub struct RomModal;

impl Driver for RomModal {
    fn name(&self) -> &'static str {
        "MODAL"
    }

    fn solutions(&self) -> &'static [Solution] {
        &[Solution::Modal]
    }

    fn basis(&self) -> Basis {
        Basis::Rom
    }

    fn element_damping(&self) -> ElementDampingUse {
        ElementDampingUse::Ignored
    }

    /// Runs every subcase on its pROM.
    fn run(&self, ctx: &RunContext, clock: &mut Clock) -> Result<Vec<SubcaseSummary>, RunError> {
        ctx.model
            .subcases
            .iter()
            .map(|sub| {
                clock.time(format!("subcase {}: pROM modes", sub.id), || {
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
    let modes = ReducedModes::of(&at).map_err(|e| case(format!("{}: {e}", path.display())))?;
    let (keep, nd_short) = selection(ctx, sub, &modes.eigenvalues)?;
    let (lambda, residuals) = modes.kept(&at, &keep);
    let frequencies_hz: Vec<f64> = lambda.iter().map(|&l| lambda_to_hz(l)).collect();
    let group = ctx.output.group(&format!("results/{id}/modal"))?;
    let m = lambda.len();
    write_f64(&group, "frequency_hz", &frequencies_hz, &[m])?;
    write_f64(&group, "eigenvalue", &lambda, &[m])?;
    write_f64(&group, "generalized_mass", &vec![1.0; m], &[m])?;
    write_f64(&group, "residual", &residuals, &[m])?;
    set_attr_str(&group, "rom", &path.display().to_string())?;
    let names: Vec<&str> = prom.parameters.iter().map(|q| q.name.as_str()).collect();
    set_attr_strings(&group, "params", &names)?;
    set_attr_f64s(&group, "values", &p)?;
    let summary = RomModalSummary {
        rom: path.clone(),
        n_red: prom.size(),
        frequencies_hz,
        values: names
            .iter()
            .map(|n| n.to_string())
            .zip(p.iter().copied())
            .collect(),
        extrapolated,
        nd_short,
    };
    Ok(SubcaseSummary {
        id,
        autospc: Vec::new(),
        result: Box::new(summary),
    })
}

/// Indices of the modes EIGRL asks for (all when no METHOD), and ND when fewer exist in the band.
fn selection(
    ctx: &RunContext,
    sub: &Subcase,
    lambda: &[f64],
) -> Result<(Vec<usize>, Option<usize>), RunError> {
    let Some(method) = sub.method else {
        return Ok(((0..lambda.len()).collect(), None));
    };
    let eigrl = ctx.model.eigrl(method).ok_or_else(|| RunError::Case {
        subcase: sub.id,
        what: format!("METHOD = {method} selects no EIGRL or EIGR card"),
    })?;
    let (v1, v2) = (
        eigrl.v1.unwrap_or(f64::NEG_INFINITY),
        eigrl.v2.unwrap_or(f64::INFINITY),
    );
    let mut keep: Vec<usize> = (0..lambda.len())
        .filter(|&j| (v1..=v2).contains(&lambda_to_hz(lambda[j])))
        .collect();
    let nd = eigrl.nd.map(|nd| nd as usize);
    if let Some(nd) = nd {
        keep.truncate(nd);
    }
    let short = nd.filter(|&nd| nd > keep.len());
    Ok((keep, short))
}

impl Report for RomModalSummary {
    fn render(&self, subcase: u32) -> Vec<String> {
        let r = self;
        let values: Vec<String> = r
            .values
            .iter()
            .map(|(n, v)| format!("{n} = {}", sci(*v, 4)))
            .collect();
        let mut out = vec![format!(
            "subcase {}: {} mode(s) of the pROM {} (size {}) at {}",
            subcase,
            r.frequencies_hz.len(),
            r.rom.display(),
            r.n_red,
            values.join(", ")
        )];
        for (k, f) in r.frequencies_hz.iter().enumerate() {
            out.push(format!("  {:>4}  {:>14}", k + 1, sci(*f, 6)));
        }
        out
    }

    fn warnings(&self, subcase: u32) -> Vec<String> {
        let r = self;
        let mut warnings: Vec<String> = extrapolation_warning(subcase, &r.extrapolated, &r.rom)
            .into_iter()
            .collect();
        if let Some(nd) = r.nd_short {
            warnings.push(format!("subcase {}: EIGRL ND = {nd} asks for more modes than the pROM {} has in the band (size {}): all {} returned", subcase, r.rom.display(), r.n_red, r.frequencies_hz.len()));
        }
        warnings
    }
}
