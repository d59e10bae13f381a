//! Random response after the frequency-response subcases (`RANDOM = sid`): the output power
//! spectral densities, RMS values, zero-crossing rates N0 and (with a RANDT1) autocorrelations
//! of the grids the subcases ask DISPLACEMENT, VELOCITY or ACCELERATION of
//! ([`crate::dynamics::random`]).
//!
//! The RANDPS cards of the set combine the responses of the subcases they name (J, K): those
//! subcases must have run in this deck with the same frequency lines and the same grids. A
//! card naming a subcase the deck does not run is left out with a warning (MSC Nastran runs
//! such decks).
//! Written: `/random/<sid>/{frequency_hz (f), <quantity>_psd (f × k × 6), <quantity>_rms
//! (k × 6), <quantity>_n0 (k × 6), <quantity>_grid_ids (k)}` per requested quantity
//! (`displacement`, `velocity`, `acceleration`: S × (2πf)^(2p), p = 0, 1, 2, components in
//! basic), with a RANDT1 `lag_s (τ)` and `<quantity>_autocorrelation (τ × k × 6)`;
//! attribute `subcases`.

use super::report::sci;
use super::{RunContext, RunError};
use crate::deck::cards::{Randps, TabrndKind};
use crate::dynamics::random::{InputPsd, Moments, Spectrum, autocorrelation, output_psd};
use crate::io::{set_attr_f64s, write_f64, write_u32};
use crate::linalg::c64;

/// The quantities a random response reports, with the power p of (iω)^p that turns a
/// displacement response into them.
pub const QUANTITIES: [(&str, i32); 3] =
    [("DISPLACEMENT", 0), ("VELOCITY", 1), ("ACCELERATION", 2)];

/// What a frequency-response subcase keeps for the random analyses: its lines, the grids of
/// its DISPLACEMENT/VELOCITY/ACCELERATION requests (union, grid ids) and their complex
/// displacement response to the subcase's load.
pub struct GridResponse {
    pub subcase: u32,
    pub random: Option<u32>,
    pub hz: Vec<f64>,
    pub grid_ids: Vec<u32>,
    /// f × grids × 6.
    pub displacement: Vec<c64>,
    /// Per quantity of [`QUANTITIES`], the positions in `grid_ids` it asks for (None: no request).
    pub requests: [Option<Vec<usize>>; 3],
}

/// One random analysis done.
#[derive(Debug, Clone)]
pub struct RandomSummary {
    pub sid: u32,
    pub subcases: Vec<u32>,
    pub lines: usize,
    /// (quantity, grids) written.
    pub outputs: Vec<(&'static str, usize)>,
    /// Largest RMS of each quantity: (value, grid id, component 1–6).
    pub largest: Vec<(&'static str, f64, u32, usize)>,
    pub lags: usize,
    /// RANDPS cards left out because they name a subcase the deck does not run (their
    /// positions).
    pub ignored: Vec<String>,
}

impl RandomSummary {
    pub fn lines(&self) -> Vec<String> {
        let subcases: Vec<String> = self.subcases.iter().map(u32::to_string).collect();
        let mut out = vec![format!(
            "random {}: subcase(s) {}, {} line(s){}",
            self.sid,
            subcases.join(", "),
            self.lines,
            if self.lags > 0 {
                format!(", autocorrelation at {} lag(s)", self.lags)
            } else {
                String::new()
            }
        )];
        for (name, value, grid, component) in &self.largest {
            out.push(format!(
                "  largest {} RMS {} at GRID {grid} component {component}",
                name.to_lowercase(),
                sci(*value, 4)
            ));
        }
        out
    }
}

/// Runs every random analysis the subcases select, writing `/random/<sid>`.
pub fn run(ctx: &RunContext, responses: &[GridResponse]) -> Result<Vec<RandomSummary>, RunError> {
    let mut sids: Vec<u32> = responses.iter().filter_map(|r| r.random).collect();
    sids.sort_unstable();
    sids.dedup();
    sids.into_iter()
        .map(|sid| one(ctx, responses, sid))
        .collect()
}

fn one(ctx: &RunContext, responses: &[GridResponse], sid: u32) -> Result<RandomSummary, RunError> {
    let model = ctx.model;
    let first_user = responses.iter().find(|r| r.random == Some(sid));
    let case = |what: String| RunError::Case {
        subcase: first_user.map_or(0, |r| r.subcase),
        what,
    };
    // a card naming a subcase the deck does not run is left out, as MSC Nastran does
    let runs = |id: u32| responses.iter().any(|r| r.subcase == id);
    let (cards, ignored): (Vec<&Randps>, Vec<&Randps>) = model
        .randps(sid)
        .into_iter()
        .partition(|c| runs(c.j) && runs(c.k));
    if cards.is_empty() {
        let what = match ignored.first() {
            Some(c) => format!(
                "RANDOM = {sid}: every RANDPS of the set names a subcase this deck does not run (RANDPS at {} names subcases {} and {})",
                c.loc, c.j, c.k
            ),
            None => format!("RANDOM = {sid} selects no RANDPS card"),
        };
        return Err(case(what));
    }
    // the subcases the cards combine, in increasing id
    let mut subcases: Vec<u32> = cards.iter().flat_map(|c| [c.j, c.k]).collect();
    subcases.sort_unstable();
    subcases.dedup();
    let used: Vec<&GridResponse> = subcases
        .iter()
        .filter_map(|&id| responses.iter().find(|r| r.subcase == id))
        .collect();
    let base = used[0];
    if let Some(r) = used
        .iter()
        .find(|r| r.hz != base.hz || r.grid_ids != base.grid_ids)
    {
        return Err(case(format!(
            "RANDOM = {sid} combines subcases {} and {}, which differ in their frequency lines or in the grids of their DISPLACEMENT/VELOCITY/ACCELERATION requests; a random response needs the same of both",
            base.subcase, r.subcase
        )));
    }
    let hz = &base.hz;
    let index = |id: u32| subcases.iter().position(|&s| s == id).expect("listed");
    let mut inputs = Vec::new();
    for c in &cards {
        let spectrum = match c.tid {
            0 => Spectrum::Unit,
            tid => match model.tabrnd(tid).map(|t| &t.kind) {
                Some(TabrndKind::Table {
                    points,
                    log_x,
                    log_y,
                }) => Spectrum::Table {
                    points: points.clone(),
                    log_x: *log_x,
                    log_y: *log_y,
                },
                Some(TabrndKind::Gust { von_karman, lu, wg }) => {
                    Spectrum::gust(*von_karman, *lu, *wg)
                }
                None => {
                    return Err(case(format!(
                        "RANDPS {sid} at {}: TID = {tid} selects no TABRND1 or TABRNDG",
                        c.loc
                    )));
                }
            },
        };
        let g = hz
            .iter()
            .map(|&f| spectrum.value(f))
            .collect::<Option<Vec<f64>>>()
            .ok_or_else(|| {
                case(format!(
                    "RANDPS {sid} at {}: TABRND1 {} has a LOG frequency axis, which a 0 Hz line cannot enter",
                    c.loc, c.tid
                ))
            })?;
        inputs.push(InputPsd {
            a: index(c.j),
            b: index(c.k),
            x: c.x,
            y: c.y,
            g,
        });
    }
    let lags = model.randt1(sid).map(|t| t.lags()).unwrap_or_default();
    let group = ctx.output.group(&format!("random/{sid}"))?;
    let (n_f, n_g) = (hz.len(), base.grid_ids.len());
    write_f64(&group, "frequency_hz", hz, &[n_f])?;
    let ids: Vec<f64> = subcases.iter().map(|&s| f64::from(s)).collect();
    set_attr_f64s(&group, "subcases", &ids)?;
    if !lags.is_empty() {
        write_f64(&group, "lag_s", &lags, &[lags.len()])?;
    }
    let mut summary = RandomSummary {
        sid,
        subcases: subcases.clone(),
        lines: n_f,
        outputs: Vec::new(),
        largest: Vec::new(),
        lags: lags.len(),
        ignored: ignored.iter().map(|c| c.loc.to_string()).collect(),
    };
    for (q, (name, power)) in QUANTITIES.iter().enumerate() {
        let Some(rows) = &base.requests[q] else {
            continue;
        };
        let k = rows.len();
        let (mut psd, mut rms, mut n0) =
            (vec![0.0; n_f * k * 6], vec![0.0; k * 6], vec![0.0; k * 6]);
        let mut auto = vec![0.0; lags.len() * k * 6];
        let mut largest = (0.0, 0, 0);
        for (row, &g) in rows.iter().enumerate() {
            for comp in 0..6 {
                let h: Vec<Vec<c64>> = used
                    .iter()
                    .map(|r| {
                        (0..n_f)
                            .map(|l| r.displacement[(l * n_g + g) * 6 + comp])
                            .collect()
                    })
                    .collect();
                let refs: Vec<&[c64]> = h.iter().map(Vec::as_slice).collect();
                let mut s = output_psd(&refs, &inputs);
                for (v, &f) in s.iter_mut().zip(hz) {
                    *v *= (2.0 * std::f64::consts::PI * f).powi(2 * power);
                }
                let m = Moments::of(hz, &s);
                let at = row * 6 + comp;
                (rms[at], n0[at]) = (m.rms, m.n0);
                if m.rms > largest.0 {
                    largest = (m.rms, base.grid_ids[g], comp + 1);
                }
                for (l, v) in s.iter().enumerate() {
                    psd[(l * k + row) * 6 + comp] = *v;
                }
                for (t, &tau) in lags.iter().enumerate() {
                    auto[(t * k + row) * 6 + comp] = autocorrelation(hz, &s, tau);
                }
            }
        }
        let lower = name.to_lowercase();
        write_f64(&group, &format!("{lower}_psd"), &psd, &[n_f, k, 6])?;
        write_f64(&group, &format!("{lower}_rms"), &rms, &[k, 6])?;
        write_f64(&group, &format!("{lower}_n0"), &n0, &[k, 6])?;
        let grid_ids: Vec<u32> = rows.iter().map(|&g| base.grid_ids[g]).collect();
        write_u32(&group, &format!("{lower}_grid_ids"), &grid_ids, &[k])?;
        if !lags.is_empty() {
            write_f64(
                &group,
                &format!("{lower}_autocorrelation"),
                &auto,
                &[lags.len(), k, 6],
            )?;
        }
        summary.outputs.push((name, k));
        summary
            .largest
            .push((name, largest.0, largest.1, largest.2));
    }
    Ok(summary)
}
