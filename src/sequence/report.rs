//! The console report of a run: each driver's per-subcase result implements [`Report`] (its
//! lines and its warnings), and [`RunSummary::render`] puts them together with the AUTOSPC
//! lists and the timings. The library renders lines; the binary prints them.

use std::time::Duration;

use super::RunSummary;
use crate::analysis::weight::WeightSummary;
use crate::linalg::SturmCheck;

/// What one subcase's result tells the user (the summary type of a driver; `Any` so that
/// callers get their driver's type back with [`super::SubcaseSummary::result`]).
pub trait Report: std::any::Any + std::fmt::Debug + Send + Sync {
    /// The console lines of subcase `subcase` (the first names it).
    fn render(&self, subcase: u32) -> Vec<String>;

    /// The warnings of subcase `subcase` ("subcase N: …"), in the order they matter.
    fn warnings(&self, _subcase: u32) -> Vec<String> {
        Vec::new()
    }
}

impl RunSummary {
    /// The console report of the run of deck `deck` that took `total`: a header line, each
    /// subcase's lines with its AUTOSPC list, and the step timings.
    pub fn render(&self, deck: &std::path::Path, total: Duration) -> Vec<String> {
        let mut out = vec![format!("{} — {}", deck.display(), self.sequence)];
        out.extend(self.model_lines.iter().cloned());
        for sub in &self.subcases {
            out.extend(sub.result.render(sub.id));
            if sub.autospc.is_empty() {
                out.push("  AUTOSPC: none".to_string());
            } else {
                let list: Vec<String> = sub
                    .autospc
                    .iter()
                    .map(|d| format!("{}/{}", d.grid, d.component))
                    .collect();
                out.push(format!(
                    "  AUTOSPC: {} DOF(s) (GRID/component): {}",
                    list.len(),
                    abbreviate(&list, 12)
                ));
            }
        }
        let steps: Vec<String> = self
            .timings
            .iter()
            .map(|(name, d)| format!("{name} {:.3} s", d.as_secs_f64()))
            .collect();
        out.push(format!(
            "timings: {}; total {:.3} s",
            steps.join(", "),
            total.as_secs_f64()
        ));
        if !self.phases.is_empty() {
            out.extend(super::usage::render(&self.phases));
        }
        out
    }
}

/// 1.234568E+01 style (fixed-width exponent).
pub fn sci(x: f64, digits: usize) -> String {
    let s = format!("{x:.digits$e}");
    match s.split_once('e') {
        Some((mantissa, exp)) => format!("{mantissa}E{:+03}", exp.parse::<i32>().unwrap_or(0)),
        None => s,
    }
}

/// The first `max` entries of a list, then how many more.
fn abbreviate(list: &[String], max: usize) -> String {
    if list.len() <= max {
        list.join(" ")
    } else {
        format!(
            "{} … (+{} more; full list: the `autospc` dataset of the results group)",
            list[..max].join(" "),
            list.len() - max
        )
    }
}

/// The grid-point weight table, laid out like Nastran's F06 (`reference` names the point).
pub fn weight_lines(w: &WeightSummary, reference: &str) -> Vec<String> {
    let row = |v: &[f64]| v.iter().map(|x| sci(*x, 6)).collect::<Vec<_>>().join(" ");
    let mut out = vec![format!(
        "  grid-point weight generator (PARAM,GRDPNT), reference point {reference}, input mass units (M / WTMASS):"
    )];
    out.push("    MO, rigid-body mass matrix about the reference point (basic):".to_string());
    out.extend(w.mo.iter().map(|r| format!("      {}", row(r))));
    out.push("    S, mass axes (columns):".to_string());
    out.extend(w.s.iter().map(|r| format!("      {}", row(r))));
    out.push("    direction  mass           X-C.G.         Y-C.G.         Z-C.G.".to_string());
    for (k, name) in ["X", "Y", "Z"].iter().enumerate() {
        out.push(format!(
            "    {name:<10} {} {}",
            sci(w.mass[k], 6),
            row(&w.cg[k])
        ));
    }
    out.push("    I(S), inertia about the C.G. (tensor, off-diagonal −∫xy dm):".to_string());
    out.extend(w.inertia.iter().map(|r| format!("      {}", row(r))));
    out.push(format!(
        "    I(Q), principal inertias: {}",
        row(&w.principal)
    ));
    out.push("    Q, principal axes (columns, in S):".to_string());
    out.extend(w.q.iter().map(|r| format!("      {}", row(r))));
    out
}

/// f = √max(λ, 0)/2π.
pub fn lambda_to_hz(lambda: f64) -> f64 {
    lambda.max(0.0).sqrt() / (2.0 * std::f64::consts::PI)
}

/// Sturm check as stored in the output and printed.
pub fn sturm_line(s: &SturmCheck) -> String {
    format!(
        "Sturm check at {:.6e} Hz: {} eigenvalue(s) below, {} found + {} below the shift — {}",
        lambda_to_hz(s.shift),
        s.negative_pivots,
        s.found,
        s.below_lower,
        if s.is_consistent() {
            "consistent".to_string()
        } else {
            format!("{} MISSING", s.missing())
        }
    )
}
