//! NSGA-II (Deb, Pratap, Agarwal & Meyarivan 2002) for mixed continuous/discrete variables,
//! in the canonical form pymoo 0.6 runs by default: random initial population, binary crowded
//! tournaments, SBX crossover and polynomial mutation ([`super::operators`], pymoo's default
//! probabilities and distribution indices), and elitist survival of the merged parents and
//! children by non-dominated rank and crowding distance (the last admitted front cut by
//! decreasing crowding distance, ties at random). Constraints follow Deb's feasibility rules as
//! pymoo does: feasible designs survive first, ranked by dominance; infeasible ones after them,
//! by increasing violation.
//!
//! Discrete variables are integer genes (indices into their value sets, [`super::space`]),
//! crossed and mutated as reals and rounded after each operator: pymoo's mixed-variable route
//! for `Integer` variables (`SBX`/`PM` with `RoundingRepair`).
//!
//! One departure from pymoo, for costly evaluations: a child equal to any design evaluated
//! before in the study (pymoo compares with the current population only) is bred again, up to
//! 100 times per generation as pymoo does; a generation that cannot breed a new design ends the
//! search (a small discrete space exhausted).
//!
//! The budget counts evaluations: the initial population, then generations of `population`
//! children, the last one cut to the evaluations left.

use std::collections::HashSet;

use super::dominance::{crowding_distance, non_dominated_fronts};
use super::evaluate::{Batch, Evaluated};
use super::operators::{Pm, Sbx, Standing, binary_tournament};
use super::scoring::{Score, Scoring};
use super::space::{Design, DesignSpace};
use crate::linalg::random::SplitMix64;

/// NSGA-II settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Nsga2 {
    /// Population size (and children per generation).
    pub population: usize,
    /// Evaluation budget, the initial population included.
    pub evaluations: usize,
    pub seed: u64,
    pub crossover: Sbx,
    pub mutation: Pm,
}

impl Nsga2 {
    /// pymoo's operators with the given population, budget and seed.
    pub fn new(population: usize, evaluations: usize, seed: u64) -> Self {
        Nsga2 {
            population,
            evaluations,
            seed,
            crossover: Sbx::default(),
            mutation: Pm::default(),
        }
    }
}

/// Every design a search evaluated, in evaluation order, with its result.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Archive {
    pub designs: Vec<Design>,
    pub evaluated: Vec<Evaluated>,
}

impl Archive {
    /// Evaluates `designs` with `batch` and appends them.
    pub fn evaluate(&mut self, designs: Vec<Design>, batch: &mut Batch) {
        let results = batch(&designs);
        self.designs.extend(designs);
        self.evaluated.extend(results);
    }

    pub fn len(&self) -> usize {
        self.designs.len()
    }

    pub fn is_empty(&self) -> bool {
        self.designs.is_empty()
    }
}

/// A population member: its genome and its place in the archive.
#[derive(Debug, Clone)]
struct Member {
    genome: Vec<f64>,
    archived: usize,
}

/// Breeding attempts per generation before giving up on new designs (pymoo's
/// `n_max_iterations` of its duplicate-free mating).
const MAX_BREEDING_ATTEMPTS: usize = 100;

impl Nsga2 {
    /// Runs the search on `space`, evaluating with `batch`.
    pub fn run(&self, space: &DesignSpace, scoring: &Scoring, batch: &mut Batch) -> Archive {
        let mut rng = SplitMix64::new(self.seed);
        let bounds: Vec<(f64, f64)> = space.variables.iter().map(|v| v.gene_bounds()).collect();
        let mut archive = Archive::default();
        let first = self.population.min(self.evaluations);
        let genomes = self.fresh(first, space, &archive, &mut rng, |rng| {
            let mut g: Vec<f64> = bounds
                .iter()
                .map(|(lo, hi)| lo + rng.unit() * (hi - lo))
                .collect();
            space.repair(&mut g);
            vec![g]
        });
        let mut population = self.admit(genomes, space, &mut archive, batch);
        let mut standings = survive(
            &mut population,
            &archive,
            scoring,
            self.population,
            &mut rng,
        );
        while archive.len() < self.evaluations {
            let wanted = self.population.min(self.evaluations - archive.len());
            let mut candidates = Permutations::new(standings.len());
            let children = self.fresh(wanted, space, &archive, &mut rng, |rng| {
                let mut parent = |rng: &mut SplitMix64| {
                    let (x, y) = (candidates.next(rng), candidates.next(rng));
                    binary_tournament(&standings, x, y, rng)
                };
                let (a, b) = (parent(rng), parent(rng));
                let (mut c1, mut c2) = self.crossover.cross(
                    &population[a].genome,
                    &population[b].genome,
                    &bounds,
                    rng,
                );
                for c in [&mut c1, &mut c2] {
                    space.repair(c);
                    self.mutation.mutate(c, &bounds, rng);
                    space.repair(c);
                }
                vec![c1, c2]
            });
            if children.is_empty() {
                break;
            }
            population.extend(self.admit(children, space, &mut archive, batch));
            standings = survive(
                &mut population,
                &archive,
                scoring,
                self.population,
                &mut rng,
            );
        }
        archive
    }

    /// Up to `wanted` genomes from `breed`, none encoding a design of the archive or of an
    /// earlier genome of the batch.
    fn fresh(
        &self,
        wanted: usize,
        space: &DesignSpace,
        archive: &Archive,
        rng: &mut SplitMix64,
        mut breed: impl FnMut(&mut SplitMix64) -> Vec<Vec<f64>>,
    ) -> Vec<Vec<f64>> {
        let key = |d: &[f64]| d.iter().map(|x| x.to_bits()).collect::<Vec<u64>>();
        let mut seen: HashSet<Vec<u64>> = archive.designs.iter().map(|d| key(d)).collect();
        let mut out: Vec<Vec<f64>> = Vec::new();
        'attempts: for _ in 0..MAX_BREEDING_ATTEMPTS {
            while out.len() < wanted {
                let before = out.len();
                for g in breed(rng) {
                    if out.len() < wanted && seen.insert(key(&space.design(&g))) {
                        out.push(g);
                    }
                }
                if out.len() == before {
                    continue 'attempts;
                }
            }
            break;
        }
        out
    }

    /// Evaluates `genomes`, archives them and returns them as population members.
    fn admit(
        &self,
        genomes: Vec<Vec<f64>>,
        space: &DesignSpace,
        archive: &mut Archive,
        batch: &mut Batch,
    ) -> Vec<Member> {
        let start = archive.len();
        archive.evaluate(genomes.iter().map(|g| space.design(g)).collect(), batch);
        genomes
            .into_iter()
            .enumerate()
            .map(|(i, genome)| Member {
                genome,
                archived: start + i,
            })
            .collect()
    }
}

/// Keeps the best `size` members of `population` (elitist survival) and returns their
/// standings for the next tournaments, in the kept order.
fn survive(
    population: &mut Vec<Member>,
    archive: &Archive,
    scoring: &Scoring,
    size: usize,
    rng: &mut SplitMix64,
) -> Vec<Standing> {
    let scores: Vec<Score> = population
        .iter()
        .map(|m| scoring.score(&archive.evaluated[m.archived]))
        .collect();
    let feasible: Vec<usize> = (0..scores.len())
        .filter(|&i| scores[i].is_feasible())
        .collect();
    let mut infeasible: Vec<usize> = (0..scores.len())
        .filter(|&i| !scores[i].is_feasible())
        .collect();
    infeasible.sort_by(|&a, &b| scores[a].violation.total_cmp(&scores[b].violation));
    let points: Vec<Vec<f64>> = feasible
        .iter()
        .map(|&i| scores[i].objectives.clone())
        .collect();
    let mut kept: Vec<(usize, f64)> = Vec::new();
    for front in non_dominated_fronts(&points) {
        if kept.len() >= size {
            break;
        }
        let members: Vec<usize> = front.iter().map(|&j| feasible[j]).collect();
        let crowding =
            crowding_distance(&front.iter().map(|&j| points[j].clone()).collect::<Vec<_>>());
        let mut order: Vec<usize> = (0..members.len()).collect();
        if kept.len() + members.len() > size {
            shuffle(&mut order, rng);
            order.sort_by(|&a, &b| crowding[b].total_cmp(&crowding[a]));
            order.truncate(size - kept.len());
        }
        kept.extend(order.into_iter().map(|k| (members[k], crowding[k])));
    }
    let room = size.saturating_sub(kept.len());
    kept.extend(infeasible.into_iter().take(room).map(|i| (i, 0.0)));
    let standings = kept
        .iter()
        .map(|&(i, crowding)| Standing {
            objectives: scores[i].objectives.clone(),
            violation: scores[i].violation,
            crowding,
        })
        .collect();
    let old = std::mem::take(population);
    *population = kept.iter().map(|&(i, _)| old[i].clone()).collect();
    standings
}

/// The tournament candidates: the entries of successive random permutations of the
/// population, as pymoo draws them (every member competes before any competes twice).
struct Permutations {
    order: Vec<usize>,
    next: usize,
}

impl Permutations {
    fn new(n: usize) -> Self {
        Permutations {
            order: (0..n).collect(),
            next: n,
        }
    }

    fn next(&mut self, rng: &mut SplitMix64) -> usize {
        if self.next == self.order.len() {
            shuffle(&mut self.order, rng);
            self.next = 0;
        }
        self.next += 1;
        self.order[self.next - 1]
    }
}

/// Fisher–Yates shuffle.
fn shuffle(v: &mut [usize], rng: &mut SplitMix64) {
    for i in (1..v.len()).rev() {
        v.swap(i, rng.below(i + 1));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::optimize::evaluate::Responses;
    use crate::optimize::hypervolume::hypervolume;
    use crate::optimize::space::Variable;

    /// [`serial`](crate::optimize::serial) over an infallible `f`.
    fn serial(f: impl Fn(&[f64]) -> Responses) -> impl FnMut(&[Design]) -> Vec<Evaluated> {
        crate::optimize::serial(move |d| Ok(f(d)))
    }

    /// Schaffer's problem (f₁ = x², f₂ = (x − 2)²): its front is x ∈ [0, 2]. 20 × 30
    /// evaluations spend exactly the budget and cover the front.
    #[test]
    fn schaffer_front_is_found_within_the_budget() {
        let space = DesignSpace::new(vec![Variable::continuous("x", -10.0, 10.0)]);
        let mut batch = serial(|d| vec![d[0] * d[0], (d[0] - 2.0).powi(2)]);
        let archive = Nsga2::new(20, 600, 7).run(&space, &Scoring::minimize_all(2), &mut batch);
        assert_eq!(archive.len(), 600);
        let points: Vec<Vec<f64>> = archive
            .evaluated
            .iter()
            .map(|e| e.result.clone().unwrap())
            .collect();
        let front = crate::optimize::dominance::pareto_indices(&points);
        assert!(front.len() >= 20, "{}", front.len());
        // a design just outside [0, 2] is non-dominated until its mirror image is evaluated
        let off: Vec<f64> = front
            .iter()
            .map(|&i| archive.designs[i][0])
            .filter(|x| !(-0.05..=2.05).contains(x))
            .collect();
        assert!(off.is_empty(), "{off:?}");
        // the exact front's hypervolume to (4, 4): ∫₀² (4 − (x − 2)²) 2x dx = 40/3
        let hv = hypervolume(&points, &[4.0, 4.0]);
        assert!(hv > 13.2 && hv < 40.0 / 3.0, "{hv}");
    }

    /// A discrete space smaller than the budget: every design once, then the search stops.
    #[test]
    fn a_small_discrete_space_is_exhausted_without_repeats() {
        let space = DesignSpace::new(vec![
            Variable::discrete("a", &[1.0, 2.0, 3.0]),
            Variable::discrete("b", &[10.0, 20.0]),
        ]);
        let mut batch = serial(|d| vec![d[0] + d[1], -d[0] * d[1]]);
        let archive = Nsga2::new(4, 100, 1).run(&space, &Scoring::minimize_all(2), &mut batch);
        let mut seen = archive.designs.clone();
        seen.sort_by(|a, b| a.partial_cmp(b).unwrap());
        seen.dedup();
        assert_eq!(seen.len(), archive.len());
        assert!(archive.len() <= 6);
    }

    /// The same seed gives the same archive.
    #[test]
    fn seeded_runs_repeat() {
        let space = DesignSpace::new(vec![
            Variable::continuous("x", 0.0, 1.0),
            Variable::discrete("n", &[2.0, 4.0, 8.0]),
        ]);
        let f = |d: &[f64]| vec![d[0] * d[1], (1.0 - d[0]) / d[1]];
        let a = Nsga2::new(8, 40, 11).run(&space, &Scoring::minimize_all(2), &mut serial(f));
        let b = Nsga2::new(8, 40, 11).run(&space, &Scoring::minimize_all(2), &mut serial(f));
        // the same designs and responses (the seconds differ from run to run)
        assert_eq!(a.designs, b.designs);
        let results = |x: &Archive| {
            x.evaluated
                .iter()
                .map(|e| e.result.clone())
                .collect::<Vec<_>>()
        };
        assert_eq!(results(&a), results(&b));
    }
}
