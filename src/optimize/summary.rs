//! What a study reports about its archive (DESIGN.md §12): feasibility of each design, the
//! Pareto set of the feasible designs, the hypervolume after every evaluation, the Pearson
//! correlations of eq. 6.2 between variables and responses, and the representative designs
//! (the front's extremes and its knee).
//!
//! The hypervolume history is measured against one reference point for the whole study, in
//! the minimized objectives: the one given, or the worst feasible value of each objective plus
//! a tenth of its range (plus 1 when the range is 0) so that every feasible design, the
//! extremes of the front included, adds volume.

use super::correlation::pearson;
use super::dominance::{dominates, pareto_indices};
use super::hypervolume::hypervolume;
use super::knee::{extremes, knee};
use super::nsga2::Archive;
use super::scoring::{Score, Scoring};

/// The report of a study.
#[derive(Debug, Clone, PartialEq)]
pub struct Summary {
    /// Per design: evaluated and within every constraint.
    pub feasible: Vec<bool>,
    /// Per design: evaluated without error.
    pub succeeded: Vec<bool>,
    /// Archive indices of the non-dominated feasible designs, ascending.
    pub pareto: Vec<usize>,
    /// The hypervolume reference point (minimized objectives).
    pub reference: Vec<f64>,
    /// The hypervolume of the feasible front after each evaluation.
    pub hypervolume: Vec<f64>,
    /// ρ (eq. 6.2) of variable i with response j at `[i][j]`, over the designs evaluated
    /// without error.
    pub correlation: Vec<Vec<f64>>,
    /// Archive indices of the front's best design per objective.
    pub extremes: Vec<usize>,
    /// Archive index of the front's knee.
    pub knee: Option<usize>,
}

/// The summary of `archive` under `scoring`, the hypervolume up to `reference` if given.
pub fn summarize(archive: &Archive, scoring: &Scoring, reference: Option<&[f64]>) -> Summary {
    let scores: Vec<Score> = archive.evaluated.iter().map(|e| scoring.score(e)).collect();
    let feasible: Vec<bool> = scores.iter().map(Score::is_feasible).collect();
    let succeeded: Vec<bool> = archive.evaluated.iter().map(|e| e.result.is_ok()).collect();
    let ids: Vec<usize> = (0..scores.len()).filter(|&i| feasible[i]).collect();
    let points: Vec<Vec<f64>> = ids.iter().map(|&i| scores[i].objectives.clone()).collect();
    let pareto: Vec<usize> = pareto_indices(&points)
        .into_iter()
        .map(|j| ids[j])
        .collect();
    let reference = reference.map_or_else(|| default_reference(&points, scoring), <[f64]>::to_vec);
    let hypervolume = history(&scores, &reference);
    let front: Vec<Vec<f64>> = pareto
        .iter()
        .map(|&i| scores[i].objectives.clone())
        .collect();
    Summary {
        correlation: correlations(archive),
        extremes: extremes(&front).into_iter().map(|j| pareto[j]).collect(),
        knee: knee(&front).map(|j| pareto[j]),
        feasible,
        succeeded,
        pareto,
        reference,
        hypervolume,
    }
}

/// The worst feasible value of each objective plus a tenth of its range (1 for a zero range;
/// 1 for every objective without a feasible design).
fn default_reference(points: &[Vec<f64>], scoring: &Scoring) -> Vec<f64> {
    (0..scoring.objectives.len())
        .map(|m| {
            let (lo, hi) = points
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
                    (lo.min(p[m]), hi.max(p[m]))
                });
            match hi - lo {
                r if !r.is_finite() => 1.0,
                r if r > 0.0 => hi + 0.1 * r,
                _ => hi + 1.0,
            }
        })
        .collect()
}

/// The hypervolume of the feasible non-dominated set after each evaluation in order.
fn history(scores: &[Score], reference: &[f64]) -> Vec<f64> {
    let mut front: Vec<Vec<f64>> = Vec::new();
    let mut volume = 0.0;
    scores
        .iter()
        .map(|s| {
            let p = &s.objectives;
            if s.is_feasible() && !front.iter().any(|q| dominates(q, p) || q == p) {
                front.retain(|q| !dominates(p, q));
                front.push(p.clone());
                volume = hypervolume(&front, reference);
            }
            volume
        })
        .collect()
}

/// ρ of every variable with every response over the designs evaluated without error.
fn correlations(archive: &Archive) -> Vec<Vec<f64>> {
    let ok: Vec<(&Vec<f64>, &Vec<f64>)> = archive
        .designs
        .iter()
        .zip(&archive.evaluated)
        .filter_map(|(d, e)| e.result.as_ref().ok().map(|r| (d, r)))
        .collect();
    let (Some(d), Some(r)) = (archive.designs.first(), ok.first().map(|(_, r)| r.len())) else {
        return Vec::new();
    };
    (0..d.len())
        .map(|i| {
            let x: Vec<f64> = ok.iter().map(|(d, _)| d[i]).collect();
            (0..r)
                .map(|j| pearson(&x, &ok.iter().map(|(_, r)| r[j]).collect::<Vec<_>>()))
                .collect()
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::optimize::evaluate::{EvalError, Evaluated};

    #[test]
    fn summary_of_a_hand_archive() {
        let ok = |r: [f64; 2]| Evaluated {
            result: Ok(r.to_vec()),
            seconds: 0.0,
        };
        let archive = Archive {
            designs: vec![vec![0.0], vec![1.0], vec![2.0], vec![3.0], vec![4.0]],
            evaluated: vec![
                ok([4.0, 1.0]),
                ok([1.0, 4.0]),
                Evaluated {
                    result: Err(EvalError("diverged".into())),
                    seconds: 0.0,
                },
                ok([2.0, 2.0]),
                ok([3.0, 3.0]),
            ],
        };
        let s = summarize(&archive, &Scoring::minimize_all(2), Some(&[5.0, 5.0]));
        assert_eq!(s.feasible, vec![true, true, false, true, true]);
        assert_eq!(s.pareto, vec![0, 1, 3]);
        // 4; 4 + 3 = 7 (two disjoint boxes: (1·4) + (4·1) − (1·1) = 7); then + (2,2) adds 4
        assert_eq!(s.hypervolume, vec![4.0, 7.0, 7.0, 11.0, 11.0]);
        assert_eq!(s.extremes, vec![1, 0]);
        assert_eq!(s.knee, Some(3));
        assert_eq!(s.correlation.len(), 1);
        assert_eq!(s.correlation[0].len(), 2);
        let auto = summarize(&archive, &Scoring::minimize_all(2), None);
        assert_eq!(auto.reference, vec![4.3, 4.3]);
    }
}
