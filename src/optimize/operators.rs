//! The variation operators of NSGA-II with pymoo's defaults (pymoo 0.6: `SBX`, `PM`,
//! `TournamentSelection(binary_tournament)`), on genomes whose coordinate `i` lies in
//! `bounds[i]`.
//!
//! - Simulated binary crossover (Deb & Agrawal 1995) in the bounded form of Deb's NSGA-II code:
//!   a mating crosses with probability 0.9, each variable with probability 0.5, distribution
//!   index η_c = 15, and the two children's values are exchanged with probability 0.5.
//! - Polynomial mutation (Deb & Goyal 1996), bounded form: a child mutates with probability
//!   0.9, each of its variables with probability min(0.5, 1/n), distribution index η_m = 20.
//! - Binary tournament: an infeasible candidate loses to a less violating one, a feasible pair
//!   is decided by dominance and then by the larger crowding distance, ties at random.

use super::dominance::dominates;
use crate::linalg::random::SplitMix64;

/// Simulated binary crossover settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sbx {
    /// Probability that a mating crosses at all (else the children are copies of the parents).
    pub probability: f64,
    /// Probability that a variable of a crossing mating is crossed.
    pub variable_probability: f64,
    /// Distribution index η_c.
    pub eta: f64,
}

impl Default for Sbx {
    /// pymoo's `SBX()`: prob 0.9, prob_var 0.5, η = 15.
    fn default() -> Self {
        Sbx {
            probability: 0.9,
            variable_probability: 0.5,
            eta: 15.0,
        }
    }
}

/// Polynomial mutation settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pm {
    /// Probability that a child is mutated at all.
    pub probability: f64,
    /// Probability of mutating a variable; `None`: min(0.5, 1/n) for n variables.
    pub variable_probability: Option<f64>,
    /// Distribution index η_m.
    pub eta: f64,
}

impl Default for Pm {
    /// pymoo's `PM()`: prob 0.9, prob_var min(0.5, 1/n), η = 20.
    fn default() -> Self {
        Pm {
            probability: 0.9,
            variable_probability: None,
            eta: 20.0,
        }
    }
}

/// Two parents values closer than this are not crossed (pymoo's `eps`).
const TOO_CLOSE: f64 = 1e-14;

impl Sbx {
    /// The two children of parents `a` and `b`.
    pub fn cross(
        &self,
        a: &[f64],
        b: &[f64],
        bounds: &[(f64, f64)],
        rng: &mut SplitMix64,
    ) -> (Vec<f64>, Vec<f64>) {
        let (mut c1, mut c2) = (a.to_vec(), b.to_vec());
        if rng.unit() >= self.probability {
            return (c1, c2);
        }
        for (i, &(low, high)) in bounds.iter().enumerate() {
            let crossed = rng.unit() < self.variable_probability;
            if !crossed || (a[i] - b[i]).abs() <= TOO_CLOSE || low == high {
                continue;
            }
            let (y1, y2) = (a[i].min(b[i]), a[i].max(b[i]));
            let delta = y2 - y1;
            let u = rng.unit();
            let spread = |beta: f64| {
                let alpha = 2.0 - beta.powf(-(self.eta + 1.0));
                if u <= 1.0 / alpha {
                    (u * alpha).powf(1.0 / (self.eta + 1.0))
                } else {
                    (1.0 / (2.0 - u * alpha)).powf(1.0 / (self.eta + 1.0))
                }
            };
            let beta_low = spread(1.0 + 2.0 * (y1 - low) / delta);
            let beta_high = spread(1.0 + 2.0 * (high - y2) / delta);
            let mut x1 = 0.5 * ((y1 + y2) - beta_low * delta);
            let mut x2 = 0.5 * ((y1 + y2) + beta_high * delta);
            if rng.unit() < 0.5 {
                std::mem::swap(&mut x1, &mut x2);
            }
            c1[i] = x1.clamp(low, high);
            c2[i] = x2.clamp(low, high);
        }
        (c1, c2)
    }
}

impl Pm {
    /// Mutates `x` in place.
    pub fn mutate(&self, x: &mut [f64], bounds: &[(f64, f64)], rng: &mut SplitMix64) {
        let p = self
            .variable_probability
            .unwrap_or_else(|| (1.0 / bounds.len() as f64).min(0.5));
        let power = 1.0 / (self.eta + 1.0);
        if rng.unit() > self.probability {
            return;
        }
        for (xi, &(low, high)) in x.iter_mut().zip(bounds) {
            if rng.unit() >= p || low == high {
                continue;
            }
            let range = high - low;
            let (d1, d2) = ((*xi - low) / range, (high - *xi) / range);
            let u = rng.unit();
            let dq = if u <= 0.5 {
                let v = 2.0 * u + (1.0 - 2.0 * u) * (1.0 - d1).powf(self.eta + 1.0);
                v.powf(power) - 1.0
            } else {
                let v = 2.0 * (1.0 - u) + 2.0 * (u - 0.5) * (1.0 - d2).powf(self.eta + 1.0);
                1.0 - v.powf(power)
            };
            *xi = (*xi + dq * range).clamp(low, high);
        }
    }
}

/// What a tournament knows of a population member.
#[derive(Debug, Clone, PartialEq)]
pub struct Standing {
    /// Minimized objectives.
    pub objectives: Vec<f64>,
    /// Total constraint violation (0: feasible; +∞: the evaluation failed).
    pub violation: f64,
    /// Crowding distance in its front (0 for infeasible members).
    pub crowding: f64,
}

/// The winner of a binary tournament between members `a` and `b` of `pop`.
pub fn binary_tournament(pop: &[Standing], a: usize, b: usize, rng: &mut SplitMix64) -> usize {
    let (x, y) = (&pop[a], &pop[b]);
    let pick = |better_a: bool, better_b: bool, rng: &mut SplitMix64| match (better_a, better_b) {
        (true, false) => a,
        (false, true) => b,
        _ if rng.unit() < 0.5 => a,
        _ => b,
    };
    if x.violation > 0.0 || y.violation > 0.0 {
        return pick(x.violation < y.violation, y.violation < x.violation, rng);
    }
    if dominates(&x.objectives, &y.objectives) {
        return a;
    }
    if dominates(&y.objectives, &x.objectives) {
        return b;
    }
    pick(x.crowding > y.crowding, y.crowding > x.crowding, rng)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sbx_children_stay_in_bounds_and_keep_the_parents_mean_without_clipping() {
        let mut rng = SplitMix64::new(3);
        let sbx = Sbx {
            probability: 1.0,
            variable_probability: 1.0,
            eta: 15.0,
        };
        let bounds = vec![(0.0, 1.0); 4];
        let (a, b) = (vec![0.2, 0.5, 0.9, 0.4], vec![0.3, 0.45, 0.1, 0.4]);
        for _ in 0..200 {
            let (c1, c2) = sbx.cross(&a, &b, &bounds, &mut rng);
            for i in 0..4 {
                assert!((0.0..=1.0).contains(&c1[i]) && (0.0..=1.0).contains(&c2[i]));
            }
            // equal parents' values are copied
            assert_eq!((c1[3], c2[3]), (0.4, 0.4));
        }
    }

    #[test]
    fn pm_moves_some_variables_within_bounds() {
        let mut rng = SplitMix64::new(5);
        let pm = Pm::default();
        let bounds = vec![(-1.0, 2.0); 10];
        let mut moved = 0;
        for _ in 0..100 {
            let mut x = vec![0.5; 10];
            pm.mutate(&mut x, &bounds, &mut rng);
            assert!(x.iter().all(|v| (-1.0..=2.0).contains(v)));
            moved += x.iter().filter(|v| **v != 0.5).count();
        }
        // 1000 variables at probability 1/10: 100 expected, σ ≈ 9.5
        assert!((60..140).contains(&moved), "{moved}");
    }

    #[test]
    fn tournament_prefers_feasible_then_dominating_then_less_crowded() {
        let mut rng = SplitMix64::new(1);
        let m = |f: [f64; 2], v: f64, c: f64| Standing {
            objectives: f.to_vec(),
            violation: v,
            crowding: c,
        };
        let pop = vec![
            m([0.0, 0.0], 1.0, 0.0),
            m([5.0, 5.0], 0.0, 0.1),
            m([4.0, 4.0], 0.0, 0.0),
            m([1.0, 6.0], 0.0, 2.0),
            m([6.0, 1.0], 0.0, f64::INFINITY),
            m([0.0, 0.0], f64::INFINITY, 0.0),
        ];
        assert_eq!(binary_tournament(&pop, 0, 1, &mut rng), 1);
        assert_eq!(binary_tournament(&pop, 1, 2, &mut rng), 2);
        assert_eq!(binary_tournament(&pop, 3, 4, &mut rng), 4);
        assert_eq!(binary_tournament(&pop, 5, 0, &mut rng), 0);
    }
}
