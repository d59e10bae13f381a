//! The gradient-based search (`MOOPT GRAD`): for each combination of the discrete variables'
//! values, a weighted-sum scalarization sweep over the objectives, each scalarized problem
//! minimized over the continuous variables' box by projected steepest descent with the
//! responses' exact gradients (forward sensitivities of the transient).
//!
//! **Scalarization: weighted sum.** F_w(x) = Σₖ wₖ fₖ(x)/sₖ + ρ Σⱼ (vⱼ(x)/cⱼ)², with fₖ the
//! objectives as minimizations, sₖ = |fₖ| at the combination's first design (1 where zero) so
//! that the weights compare objectives of different units, vⱼ the amount constraint j is
//! violated by (pymoo's CV, [`super::scoring`]), cⱼ = |its bound| (1 where zero) and ρ =
//! [`PENALTY`] (an exterior penalty: the designs it visits are journaled and marked
//! infeasible like any other). The weights are the Das–Dennis lattice on the simplex with the
//! most points not above POP (2 objectives: POP weights (i/(POP−1), 1 − i/(POP−1))). Why a
//! weighted sum and not the ε-constraint method: it needs no bounds on the objectives before
//! the first evaluation, and the search's gradients serve it directly; its known limit is
//! that it reaches only the convex hull of the front (a non-convex stretch is skipped).
//!
//! **Descent.** In the box scaled to [0, 1]ⁿ: d = −∇F/|∇F|∞, the trial x' = P(x + α d) (P the
//! projection onto the box), accepted when F(x') ≤ F(x) + 10⁻⁴ ∇F·(x' − x) (Armijo), after
//! which α doubles (at most [`MAX_STEP`]); else α halves and the trial is made again from x.
//! A scalarized problem ends when α falls below [`MIN_STEP`], when the projected gradient
//! vanishes, or when its share of the budget is spent; the next weight starts from where the
//! last one ended (its value and gradient re-weighted from the stored responses: no new
//! evaluation), so the sweep walks along the front. A failed evaluation counts as F = +∞
//! (the step halves). A design the search meets again (a line search back to a point it
//! has) is taken from the points it has, not evaluated again.
//!
//! **Budget.** NEVAL evaluations, shared equally by the combinations and, within one, by
//! its weights (each at least one evaluation). An evaluation runs one transient with the
//! sensitivities, which costs more than a plain one (docs/optimize.md).
//!
//! **No crate.** The bounded gradient optimizers on crates.io either bind a C or Fortran
//! library (nlopt, L-BFGS-B) that the build would have to compile, or, like argmin, have no
//! bound constraints; a projected descent with a backtracking line search is ~100 lines.

use super::evaluate::{Evaluated, Responses};
use super::nsga2::Archive;
use super::scoring::{Scoring, Sense};
use super::space::{Design, DesignSpace, Domain};

/// ρ of the penalty on the scaled constraint violations.
pub const PENALTY: f64 = 100.0;
/// The largest step, in units of the scaled box.
pub const MAX_STEP: f64 = 0.5;
/// The first step of a scalarized problem.
pub const FIRST_STEP: f64 = 0.1;
/// The step below which a scalarized problem has converged.
pub const MIN_STEP: f64 = 1e-3;

/// One evaluation with gradients: the design's [`Evaluated`] and, when it succeeded, the
/// responses' gradients (`gradient[k][i]` = ∂ response k / ∂ variable i).
pub type WithGradient = (Evaluated, Option<Vec<Vec<f64>>>);

/// The gradient-based search (module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GradientSearch {
    /// POP: the most weights of the sweep per combination.
    pub weights: usize,
    /// NEVAL.
    pub budget: usize,
}

/// An evaluated point of the search: design, responses and gradients.
#[derive(Clone)]
struct Point {
    design: Design,
    responses: Responses,
    gradient: Vec<Vec<f64>>,
}

/// The Das–Dennis lattice: every w with wₖ = iₖ/h, Σ iₖ = h, for m objectives.
pub fn lattice(m: usize, h: usize) -> Vec<Vec<f64>> {
    fn fill(m: usize, left: usize, h: usize, prefix: &mut Vec<f64>, out: &mut Vec<Vec<f64>>) {
        if prefix.len() + 1 == m {
            prefix.push(left as f64 / h as f64);
            out.push(prefix.clone());
            prefix.pop();
            return;
        }
        for i in (0..=left).rev() {
            prefix.push(i as f64 / h as f64);
            fill(m, left - i, h, prefix, out);
            prefix.pop();
        }
    }
    if m <= 1 || h == 0 {
        return vec![vec![1.0 / m.max(1) as f64; m.max(1)]];
    }
    let mut out = Vec::new();
    fill(m, h, h, &mut Vec::new(), &mut out);
    out
}

/// The weights of the sweep: the finest lattice with at most `count` points.
pub fn weights(m: usize, count: usize) -> Vec<Vec<f64>> {
    let mut h = 0;
    while lattice(m, h + 1).len() <= count.max(1) && h < count {
        h += 1;
    }
    lattice(m, h)
}

/// Every combination of the discrete variables' values (one empty one without any).
fn combinations(space: &DesignSpace) -> Vec<Vec<(usize, f64)>> {
    let mut out = vec![Vec::new()];
    for (i, v) in space.variables.iter().enumerate() {
        if let Domain::Discrete { values } = &v.domain {
            out = (out.iter())
                .flat_map(|c| {
                    values.iter().map(move |x| {
                        let mut c = c.clone();
                        c.push((i, *x));
                        c
                    })
                })
                .collect();
        }
    }
    out
}

/// The scalarized objective of one weight and its gradient in the scaled box.
struct Scalarized<'a> {
    scoring: &'a Scoring,
    weights: &'a [f64],
    scales: &'a [f64],
    /// (index, low, high) of each continuous variable.
    box_: &'a [(usize, f64, f64)],
}

impl Scalarized<'_> {
    /// F and ∇F (per continuous variable, in the scaled box) at a point.
    fn at(&self, p: &Point) -> (f64, Vec<f64>) {
        let n = self.box_.len();
        let mut value = 0.0;
        let mut gradient = vec![0.0; n];
        let sign = |s: Sense| if s == Sense::Min { 1.0 } else { -1.0 };
        for ((o, w), s) in (self.scoring.objectives.iter())
            .zip(self.weights)
            .zip(self.scales)
        {
            let c = sign(o.sense) * w / s;
            value += c * p.responses[o.response];
            for (g, (i, low, high)) in gradient.iter_mut().zip(self.box_) {
                *g += c * p.gradient[o.response][*i] * (high - low);
            }
        }
        for c in &self.scoring.constraints {
            let y = p.responses[c.response];
            // the amount outside the bounds, signed as the response moves it out
            let (excess, bound) = match (c.low, c.high) {
                (Some(l), _) if y < l => (y - l, l),
                (_, Some(h)) if y > h => (y - h, h),
                _ => continue,
            };
            let scale = if bound == 0.0 { 1.0 } else { bound.abs() };
            value += PENALTY * (excess / scale).powi(2);
            for (g, (i, low, high)) in gradient.iter_mut().zip(self.box_) {
                *g += 2.0 * PENALTY * excess / (scale * scale)
                    * p.gradient[c.response][*i]
                    * (high - low);
            }
        }
        (value, gradient)
    }
}

impl GradientSearch {
    /// Runs the search from `start` (a design of the space whose continuous values start
    /// every combination), each evaluation by `evaluate`; every evaluated design is in the
    /// returned archive, in order.
    pub fn run(
        &self,
        space: &DesignSpace,
        scoring: &Scoring,
        start: &[f64],
        evaluate: &mut dyn FnMut(&[f64]) -> WithGradient,
    ) -> Archive {
        let mut archive = Archive::default();
        let box_: Vec<(usize, f64, f64)> = (space.variables.iter().enumerate())
            .filter_map(|(i, v)| match v.domain {
                Domain::Continuous { low, high } => Some((i, low, high)),
                Domain::Discrete { .. } => None,
            })
            .collect();
        let combinations = combinations(space);
        let sweep = weights(scoring.objectives.len(), self.weights);
        let per_combination = (self.budget / combinations.len()).max(1);
        // a design met again (a line search returning to it) is not evaluated again
        let mut seen: Vec<Point> = Vec::new();
        let mut call = |design: &[f64], archive: &mut Archive| -> Option<Point> {
            if let Some(p) = seen.iter().find(|p| p.design == design) {
                return Some(p.clone());
            }
            let (evaluated, gradient) = evaluate(design);
            archive.designs.push(design.to_vec());
            let responses = evaluated.result.clone().ok();
            archive.evaluated.push(evaluated);
            let point = Point {
                design: design.to_vec(),
                responses: responses?,
                gradient: gradient?,
            };
            seen.push(point.clone());
            Some(point)
        };
        for combination in combinations {
            if archive.len() >= self.budget {
                break;
            }
            let mut x = start.to_vec();
            for &(i, v) in &combination {
                x[i] = v;
            }
            for &(i, low, high) in &box_ {
                x[i] = x[i].clamp(low, high);
            }
            let spent_before = archive.len();
            let Some(mut point) = call(&x, &mut archive) else {
                continue;
            };
            let scales: Vec<f64> = (scoring.objectives.iter())
                .map(|o| match point.responses[o.response].abs() {
                    s if s > 0.0 && s.is_finite() => s,
                    _ => 1.0,
                })
                .collect();
            if box_.is_empty() {
                continue;
            }
            let per_weight = (per_combination.saturating_sub(1) / sweep.len()).max(1);
            for w in &sweep {
                let f = Scalarized {
                    scoring,
                    weights: w,
                    scales: &scales,
                    box_: &box_,
                };
                let end = (archive.len() + per_weight).min(spent_before + per_combination);
                point = descend(&f, point, end, self.budget, &mut archive, &mut call);
            }
        }
        archive
    }
}

/// Projected steepest descent of `f` from `point` until the archive holds `end` designs (or
/// `budget`), or the step or projected gradient vanishes (module docs); the last accepted
/// point.
fn descend(
    f: &Scalarized,
    mut point: Point,
    end: usize,
    budget: usize,
    archive: &mut Archive,
    call: &mut dyn FnMut(&[f64], &mut Archive) -> Option<Point>,
) -> Point {
    let (mut value, mut gradient) = f.at(&point);
    let mut step = FIRST_STEP;
    while archive.len() < end.min(budget) && step >= MIN_STEP {
        let size = gradient.iter().fold(0.0_f64, |m, g| m.max(g.abs()));
        if !(size > 0.0 && size.is_finite()) {
            break;
        }
        let mut trial = point.design.clone();
        let mut moved = 0.0;
        for (g, &(i, low, high)) in gradient.iter().zip(f.box_) {
            let u = (point.design[i] - low) / (high - low);
            let next = (u - step * g / size).clamp(0.0, 1.0);
            moved += g * (next - u);
            trial[i] = low + next * (high - low);
        }
        if moved == 0.0 {
            // every descent direction leaves the box: a projected stationary point
            break;
        }
        let accepted = call(&trial, archive).and_then(|p| {
            let (v, g) = f.at(&p);
            (v <= value + 1e-4 * moved).then_some((p, v, g))
        });
        match accepted {
            Some((p, v, g)) => {
                (point, value, gradient) = (p, v, g);
                step = (2.0 * step).min(MAX_STEP);
            }
            None => step *= 0.5,
        }
    }
    point
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::optimize::evaluate::Evaluated;
    use crate::optimize::scoring::{Constraint, Objective};
    use crate::optimize::space::Variable;

    #[test]
    fn the_lattice_spans_the_simplex() {
        assert_eq!(
            lattice(2, 2),
            vec![vec![1.0, 0.0], vec![0.5, 0.5], vec![0.0, 1.0]]
        );
        assert_eq!(lattice(3, 2).len(), 6);
        assert_eq!(weights(2, 5).len(), 5);
        assert_eq!(weights(3, 7).len(), 6);
        assert_eq!(weights(1, 4), vec![vec![1.0]]);
    }

    /// f₁ = x², f₂ = (x − 1)² + (k − 1)², x ∈ [−1, 2], k ∈ {0, 1}: the front is x ∈ [0, 1]
    /// at k = 1. From x = 1.5 the scales at k = 1 are s = (2.25, 0.25), and the minimizer of
    /// w₁ f₁/s₁ + w₂ f₂/s₂ is x = (w₂/s₂)/(w₁/s₁ + w₂/s₂) (convex front: every weight's
    /// minimizer is on it).
    #[test]
    fn a_convex_front_is_traced_by_the_sweep() {
        let space = DesignSpace {
            variables: vec![
                Variable::continuous("x", -1.0, 2.0),
                Variable::discrete("k", &[0.0, 1.0]),
            ],
        };
        let scoring = Scoring {
            objectives: (0..2)
                .map(|response| Objective {
                    response,
                    sense: Sense::Min,
                })
                .collect(),
            constraints: vec![Constraint {
                response: 0,
                low: None,
                high: Some(3.0),
            }],
        };
        let mut evaluate = |d: &[f64]| -> WithGradient {
            let (x, k) = (d[0], d[1]);
            let responses = vec![x * x, (x - 1.0).powi(2) + (k - 1.0).powi(2)];
            let gradient = vec![vec![2.0 * x, f64::NAN], vec![2.0 * (x - 1.0), f64::NAN]];
            (
                Evaluated {
                    result: Ok(responses),
                    seconds: 0.0,
                },
                Some(gradient),
            )
        };
        let search = GradientSearch {
            weights: 5,
            budget: 120,
        };
        let archive = search.run(&space, &scoring, &[1.5, 0.0], &mut evaluate);
        assert!(archive.len() <= 120);
        // on k = 1, each weight's minimizer (w₂ = 0, ¼, ½, ¾, 1) is visited within 1e-2
        // (the descent stops at steps of 1e-3 of the box, 3e-3 in x)
        for w2 in [0.0, 0.25, 0.5, 0.75, 1.0] {
            let target = (w2 / 0.25) / ((1.0 - w2) / 2.25 + w2 / 0.25);
            let best = (archive.designs.iter())
                .filter(|d| d[1] == 1.0)
                .map(|d| (d[0] - target).abs())
                .fold(f64::INFINITY, f64::min);
            assert!(best < 1e-2, "x = {target}: closest {best}");
        }
        // every design in its domain
        assert!(
            archive
                .designs
                .iter()
                .all(|d| { (space.variables.iter().zip(d)).all(|(v, x)| v.contains(*x)) })
        );
    }
}
