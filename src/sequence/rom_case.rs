//! What every sequence on a pROM artifact (`ROM = 'file.h5'`) shares: reading the artifact
//! (path relative to the deck's directory), the parameter values of the subcase's `PVAL`
//! (parameters it does not list keep their nominal values), and the pROM evaluated there,
//! refused when its reduced mass matrix is ill-conditioned ([`crate::rom::modes::check_evaluation`]). A
//! `PVAL = id` may select PTABLE cards (parameters following tables of time) instead of or
//! besides a PVAL card; only the transient reads those ([`super::rom_transient`]).

use std::path::{Path, PathBuf};

use super::{RunContext, RunError};
use crate::deck::Solution;
use crate::deck::case_control::Subcase;
use crate::io::read_prom;
use crate::model::Model;
use crate::rom::modes::check_evaluation;
use crate::rom::prom::{Prom, PromEvaluation};

/// True when every subcase reads a pROM (no full model is needed).
pub fn applies(model: &Model) -> bool {
    !model.subcases.is_empty() && model.subcases.iter().all(|s| s.rom.is_some())
}

/// A pROM evaluated at a subcase's parameter values.
pub struct RomAtPoint {
    pub path: PathBuf,
    pub prom: Prom,
    /// Parameter values, in the pROM's parameter order.
    pub p: Vec<f64>,
    pub at: PromEvaluation,
    /// Names of the parameters outside the pROM's box.
    pub extrapolated: Vec<String>,
}

impl RomAtPoint {
    /// Read the subcase's artifact and evaluate it at its PVAL.
    pub fn load(ctx: &RunContext, sub: &Subcase) -> Result<Self, RunError> {
        let case = |what: String| RunError::Case {
            subcase: sub.id,
            what,
        };
        let rom = sub
            .rom
            .as_deref()
            .ok_or_else(|| case("ROM = 'file.h5' missing".into()))?;
        let path = ctx
            .deck
            .path
            .parent()
            .map_or_else(|| PathBuf::from(rom), |dir| dir.join(rom));
        let (prom, _) = read_prom(&path)?;
        let mut p: Vec<f64> = prom.parameters.iter().map(|q| q.nominal).collect();
        if let Some(pval_id) = sub.pval {
            let tabulated = !ctx.model.ptables(pval_id).is_empty();
            let transient = ctx.deck.executive.sol.as_ref().is_some_and(|(sol, _)| {
                matches!(
                    sol,
                    Solution::Transient | Solution::TransientDirect | Solution::TransientModal
                )
            });
            if tabulated && !transient {
                return Err(case(format!(
                    "PTABLE {pval_id}: parameters varying in time apply to SOL TRANSIENT only (and to SOL FMB on a mechanism)"
                )));
            }
            let card = ctx.model.pval(pval_id);
            if card.is_none() && !tabulated {
                return Err(case(format!("PVAL {pval_id} missing")));
            }
            for (name, value) in card.iter().flat_map(|c| &c.values) {
                let j = prom.parameters.iter().position(|q| q.name.eq_ignore_ascii_case(name)).ok_or_else(|| {
                    case(format!(
                        "PVAL {pval_id} names {name}, which is not a parameter of {} (parameters: {})",
                        path.display(),
                        prom.parameters.iter().map(|q| q.name.as_str()).collect::<Vec<_>>().join(", ")
                    ))
                })?;
                p[j] = *value;
            }
        }
        let mut at = prom.workspace();
        prom.evaluate(&p, &mut at)
            .map_err(|e| case(format!("{}: {e}", path.display())))?;
        check_evaluation(&at)
            .map_err(|e| case(format!("{} at {}: {e}", path.display(), point(&prom, &p))))?;
        let extrapolated = prom.outside_box(&p).into_iter().map(String::from).collect();
        Ok(RomAtPoint {
            path,
            prom,
            p,
            at,
            extrapolated,
        })
    }
}

/// "E = 1.1e11, RHO = 4500" for messages.
fn point(prom: &Prom, p: &[f64]) -> String {
    prom.parameters
        .iter()
        .zip(p)
        .map(|(q, v)| format!("{} = {v:e}", q.name))
        .collect::<Vec<_>>()
        .join(", ")
}

/// The warning of a subcase whose parameters `names` lie outside the box the pROM `rom` was
/// built for (none when all are inside).
pub fn extrapolation_warning(subcase: u32, names: &[String], rom: &Path) -> Option<String> {
    (!names.is_empty()).then(|| format!("subcase {}: parameter(s) {} lie outside the box the pROM {} was built for: extrapolated", subcase, names.join(", "), rom.display()))
}
