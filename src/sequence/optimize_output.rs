//! What a `SOL OPTIMIZE` study writes and prints.
//!
//! Written: `/results/<id>/optimize/{designs (n×d), responses (n×k; NaN for a failed
//! evaluation), feasible (n: 1/0), errors (n: why an evaluation failed, empty when it did
//! not), pareto (archive indices of the feasible non-dominated designs), hypervolume (n: after
//! each evaluation), correlation (d×k: eq. 6.2), eval_seconds (n), extremes (per objective:
//! the front's best design), knee (0 or 1 index)}` with attributes `method`, `variables`,
//! `targets` (per variable, the `BODY.PMPAR` it sets and the bodies whose artifact it
//! chooses, space-separated), `responses`, `sensors` (each response's SOURCE: the MSENSOR,
//! `MASS` or `FREQ <body>`), `statistics` (empty for MASS, the mode number for FREQ),
//! `objectives` (response names), `senses`, `constraints`,
//! `constraint_low`, `constraint_high` (NaN: open), `reference` (the hypervolume's reference
//! point in minimized objectives), `seed`, `population` (NSGA2: the population; GRID: the
//! levels; GRAD: the most weights per combination); and each representative design's histories under
//! `representative/<label>/{time, sensors/<name>}` (`best_<objective>` per objective and
//! `knee`), attributes `design` (its archive index) and `values`.

use super::optimize_study::{Quantity, Study};
use super::report::{Report, sci};
use super::{RunContext, RunError};
use crate::deck::cards::{SearchMethod, Statistic};
use crate::io::{
    set_attr_f64s, set_attr_i64, set_attr_str, set_attr_strings, write_f64, write_strings,
    write_u32,
};
use crate::multibody::Histories;
use crate::optimize::{Archive, Sense, Summary};

/// A representative design of the front: its label and archive index.
#[derive(Debug, Clone, PartialEq)]
pub struct Representative {
    pub label: String,
    pub design: usize,
}

impl Representative {
    /// The front's best design of each objective (`best_<objective>`) and its knee.
    pub fn of(summary: &Summary, study: &Study) -> Vec<Representative> {
        let best = summary
            .extremes
            .iter()
            .zip(&study.responses)
            .map(|(&design, r)| Representative {
                label: format!("best_{}", r.name),
                design,
            });
        let knee = summary.knee.map(|design| Representative {
            label: "knee".into(),
            design,
        });
        best.chain(knee).collect()
    }
}

fn method_name(m: SearchMethod) -> &'static str {
    match m {
        SearchMethod::Nsga2 => "NSGA2",
        SearchMethod::Grid => "GRID",
        SearchMethod::Grad => "GRAD",
    }
}

fn statistic_name(s: Statistic) -> &'static str {
    match s {
        Statistic::Mean => "MEAN",
        Statistic::Final => "FINAL",
        Statistic::Max => "MAX",
        Statistic::Rms => "RMS",
    }
}

fn indices(values: &[usize]) -> Vec<u32> {
    values.iter().map(|&i| i as u32).collect()
}

/// Writes the study's group of subcase `id` (module docs).
pub fn write_study(
    ctx: &RunContext,
    id: u32,
    study: &Study,
    archive: &Archive,
    summary: &Summary,
    representatives: &[(Representative, Histories)],
    sensors: &[String],
) -> Result<(), RunError> {
    let group = ctx.output.group(&format!("results/{id}/optimize"))?;
    let (n, d, k) = (archive.len(), study.space.len(), study.responses.len());
    write_f64(&group, "designs", &archive.designs.concat(), &[n, d])?;
    let responses: Vec<f64> = (archive.evaluated.iter())
        .flat_map(|e| e.result.clone().unwrap_or_else(|_| vec![f64::NAN; k]))
        .collect();
    write_f64(&group, "responses", &responses, &[n, k])?;
    let feasible: Vec<u32> = summary.feasible.iter().map(|&f| u32::from(f)).collect();
    write_u32(&group, "feasible", &feasible, &[n])?;
    let errors: Vec<String> = (archive.evaluated.iter())
        .map(|e| {
            e.result
                .as_ref()
                .err()
                .map_or(String::new(), |e| e.0.clone())
        })
        .collect();
    write_strings(
        &group,
        "errors",
        &errors.iter().map(String::as_str).collect::<Vec<_>>(),
    )?;
    write_u32(
        &group,
        "pareto",
        &indices(&summary.pareto),
        &[summary.pareto.len()],
    )?;
    write_f64(&group, "hypervolume", &summary.hypervolume, &[n])?;
    let correlation = if summary.correlation.is_empty() {
        vec![f64::NAN; d * k]
    } else {
        summary.correlation.concat()
    };
    write_f64(&group, "correlation", &correlation, &[d, k])?;
    let seconds: Vec<f64> = archive.evaluated.iter().map(|e| e.seconds).collect();
    write_f64(&group, "eval_seconds", &seconds, &[n])?;
    write_u32(
        &group,
        "extremes",
        &indices(&summary.extremes),
        &[summary.extremes.len()],
    )?;
    let knee: Vec<u32> = summary.knee.iter().map(|&i| i as u32).collect();
    write_u32(&group, "knee", &knee, &[knee.len()])?;

    let names: Vec<String> = study
        .space
        .variables
        .iter()
        .map(|v| v.name.clone())
        .collect();
    let targets: Vec<String> = study.targets.iter().map(|t| t.join(" ")).collect();
    let response_names: Vec<String> = study.responses.iter().map(|r| r.name.clone()).collect();
    let response_sources: Vec<String> = study.responses.iter().map(|r| r.source.clone()).collect();
    let statistics: Vec<String> = (study.responses.iter())
        .map(|r| match r.quantity {
            Quantity::Sensor { statistic, .. } => statistic_name(statistic).to_string(),
            Quantity::Mass => String::new(),
            Quantity::Frequency { mode, .. } => mode.to_string(),
        })
        .collect();
    let objectives: Vec<String> = (study.scoring.objectives.iter())
        .map(|o| study.responses[o.response].name.clone())
        .collect();
    let senses: Vec<String> = (study.scoring.objectives.iter())
        .map(|o| if o.sense == Sense::Max { "MAX" } else { "MIN" }.to_string())
        .collect();
    let constraints: Vec<String> = (study.scoring.constraints.iter())
        .map(|c| study.responses[c.response].name.clone())
        .collect();
    for (name, values) in [
        ("variables", &names),
        ("targets", &targets),
        ("responses", &response_names),
        ("sensors", &response_sources),
        ("statistics", &statistics),
        ("objectives", &objectives),
        ("senses", &senses),
        ("constraints", &constraints),
    ] {
        set_attr_strings(
            &group,
            name,
            &values.iter().map(String::as_str).collect::<Vec<_>>(),
        )?;
    }
    let bound = |b: Option<f64>| b.unwrap_or(f64::NAN);
    let low: Vec<f64> = study
        .scoring
        .constraints
        .iter()
        .map(|c| bound(c.low))
        .collect();
    let high: Vec<f64> = study
        .scoring
        .constraints
        .iter()
        .map(|c| bound(c.high))
        .collect();
    set_attr_f64s(&group, "constraint_low", &low)?;
    set_attr_f64s(&group, "constraint_high", &high)?;
    set_attr_f64s(&group, "reference", &summary.reference)?;
    set_attr_str(&group, "method", method_name(study.search.method))?;
    set_attr_i64(&group, "seed", study.search.seed as i64)?;
    set_attr_i64(&group, "population", i64::from(study.search.pop))?;

    for (r, h) in representatives {
        let path = format!("results/{id}/optimize/representative/{}", r.label);
        let g = ctx.output.group(&path)?;
        let rows = h.time.len();
        write_f64(&g, "time", &h.time, &[rows])?;
        let sg = ctx.output.group(&format!("{path}/sensors"))?;
        for (name, series) in sensors.iter().zip(&h.outputs) {
            write_f64(&sg, name, series, &[rows])?;
        }
        set_attr_i64(&g, "design", r.design as i64)?;
        set_attr_f64s(&g, "values", &archive.designs[r.design])?;
    }
    Ok(())
}

/// The console summary of a study.
#[derive(Debug, Clone)]
pub struct OptimizeSummary {
    pub method: &'static str,
    pub variables: Vec<String>,
    pub responses: Vec<String>,
    pub objectives: usize,
    pub constraints: usize,
    pub evaluations: usize,
    pub feasible: usize,
    /// The evaluations that failed, with the first one's message.
    pub failed: usize,
    pub first_failure: Option<String>,
    pub front: usize,
    pub hypervolume: f64,
    pub mean_seconds: f64,
    pub wall_seconds: f64,
    /// Where the designs were evaluated (NPAR threads, or an engine's command).
    pub engine: String,
    /// The journal's path and how many evaluations were taken from it (START = RESUME).
    pub journal: String,
    pub resumed: usize,
    /// The knee's archive index, design and responses.
    pub knee: Option<(usize, Vec<f64>, Vec<f64>)>,
}

impl OptimizeSummary {
    pub fn new(
        study: &Study,
        archive: &Archive,
        summary: &Summary,
        wall_seconds: f64,
        engine: String,
        (journal, resumed): (String, usize),
    ) -> Self {
        let n = archive.len();
        let failures: Vec<&str> = (archive.evaluated.iter())
            .filter_map(|e| e.result.as_ref().err().map(|e| e.0.as_str()))
            .collect();
        OptimizeSummary {
            method: method_name(study.search.method),
            variables: study
                .space
                .variables
                .iter()
                .map(|v| v.name.clone())
                .collect(),
            responses: study.responses.iter().map(|r| r.name.clone()).collect(),
            objectives: study.scoring.objectives.len(),
            constraints: study.scoring.constraints.len(),
            evaluations: n,
            feasible: summary.feasible.iter().filter(|&&f| f).count(),
            failed: failures.len(),
            first_failure: failures.first().map(|s| s.to_string()),
            front: summary.pareto.len(),
            hypervolume: summary.hypervolume.last().copied().unwrap_or(0.0),
            mean_seconds: archive.evaluated.iter().map(|e| e.seconds).sum::<f64>()
                / n.max(1) as f64,
            wall_seconds,
            engine,
            journal,
            resumed,
            knee: summary.knee.map(|i| {
                (
                    i,
                    archive.designs[i].clone(),
                    archive.evaluated[i].result.clone().unwrap_or_default(),
                )
            }),
        }
    }
}

/// `name = value` pairs.
fn pairs(names: &[String], values: &[f64]) -> String {
    names
        .iter()
        .zip(values)
        .map(|(n, v)| format!("{n} = {}", sci(*v, 5)))
        .collect::<Vec<_>>()
        .join(", ")
}

impl Report for OptimizeSummary {
    fn render(&self, subcase: u32) -> Vec<String> {
        let mut out = vec![
            format!(
                "subcase {subcase}: optimize ({}), {} evaluation(s) of {} variable(s) ({}), {} objective(s), {} constraint(s)",
                self.method,
                self.evaluations,
                self.variables.len(),
                self.variables.join(", "),
                self.objectives,
                self.constraints
            ),
            format!(
                "  {} feasible, {} failed; Pareto front of {} design(s); hypervolume {}",
                self.feasible,
                self.failed,
                self.front,
                sci(self.hypervolume, 5)
            ),
            format!(
                "  {:.3} s per evaluation; {:.3} s wall on {}",
                self.mean_seconds, self.wall_seconds, self.engine
            ),
            format!(
                "  journal {}: {} evaluation(s) taken from it, {} run",
                self.journal,
                self.resumed,
                self.evaluations - self.resumed
            ),
        ];
        if let Some((i, design, responses)) = &self.knee {
            out.push(format!(
                "  knee: design {i}: {}; {}",
                pairs(&self.variables, design),
                pairs(&self.responses, responses)
            ));
        }
        out
    }

    fn warnings(&self, subcase: u32) -> Vec<String> {
        match &self.first_failure {
            None => Vec::new(),
            Some(first) => vec![format!(
                "subcase {subcase}: {} evaluation(s) failed and are kept as infeasible designs (why: the `errors` dataset); the first: {first}",
                self.failed
            )],
        }
    }
}
