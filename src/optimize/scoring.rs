//! From responses to what a search compares: the objectives, all turned into minimizations,
//! and the total constraint violation (pymoo's CV: the sum of the amounts by which each
//! constrained response leaves its bounds; 0 for a feasible design). A failed evaluation, or a
//! response that is not a finite number, is infeasible with an infinite violation.

use super::evaluate::Evaluated;

/// Whether an objective is minimized or maximized.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Sense {
    Min,
    Max,
}

/// An objective: one response and its sense.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Objective {
    pub response: usize,
    pub sense: Sense,
}

/// A constraint: one response kept within `[low, high]` (an absent bound is open).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Constraint {
    pub response: usize,
    pub low: Option<f64>,
    pub high: Option<f64>,
}

/// The objectives and constraints of a study over its responses.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Scoring {
    pub objectives: Vec<Objective>,
    pub constraints: Vec<Constraint>,
}

/// What a search compares of one evaluated design.
#[derive(Debug, Clone, PartialEq)]
pub struct Score {
    /// The objectives as minimizations (a maximized response negated); +∞ when infeasible
    /// with an infinite violation.
    pub objectives: Vec<f64>,
    /// The total constraint violation: 0 when feasible.
    pub violation: f64,
}

impl Score {
    pub fn is_feasible(&self) -> bool {
        self.violation == 0.0
    }
}

impl Scoring {
    /// Every response minimized, no constraints: test problems whose responses are their
    /// objectives.
    pub fn minimize_all(responses: usize) -> Self {
        Scoring {
            objectives: (0..responses)
                .map(|response| Objective {
                    response,
                    sense: Sense::Min,
                })
                .collect(),
            constraints: Vec::new(),
        }
    }

    /// The score of one evaluated design.
    pub fn score(&self, evaluated: &Evaluated) -> Score {
        let failed = Score {
            objectives: vec![f64::INFINITY; self.objectives.len()],
            violation: f64::INFINITY,
        };
        let Ok(r) = &evaluated.result else {
            return failed;
        };
        let used = (self.objectives.iter().map(|o| o.response))
            .chain(self.constraints.iter().map(|c| c.response));
        if used
            .into_iter()
            .any(|i| !r.get(i).is_some_and(|v| v.is_finite()))
        {
            return failed;
        }
        let objectives = self
            .objectives
            .iter()
            .map(|o| match o.sense {
                Sense::Min => r[o.response],
                Sense::Max => -r[o.response],
            })
            .collect();
        let violation = self
            .constraints
            .iter()
            .map(|c| {
                let v = r[c.response];
                c.low.map_or(0.0, |l| (l - v).max(0.0)) + c.high.map_or(0.0, |h| (v - h).max(0.0))
            })
            .sum();
        Score {
            objectives,
            violation,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::optimize::evaluate::EvalError;

    fn ok(r: &[f64]) -> Evaluated {
        Evaluated {
            result: Ok(r.to_vec()),
            seconds: 0.0,
        }
    }

    #[test]
    fn senses_bounds_and_failures() {
        let scoring = Scoring {
            objectives: vec![
                Objective {
                    response: 0,
                    sense: Sense::Min,
                },
                Objective {
                    response: 2,
                    sense: Sense::Max,
                },
            ],
            constraints: vec![Constraint {
                response: 1,
                low: Some(1.0),
                high: Some(2.0),
            }],
        };
        let s = scoring.score(&ok(&[3.0, 1.5, 4.0]));
        assert_eq!((s.objectives.clone(), s.violation), (vec![3.0, -4.0], 0.0));
        assert!(s.is_feasible());
        assert_eq!(scoring.score(&ok(&[3.0, 2.5, 4.0])).violation, 0.5);
        assert_eq!(scoring.score(&ok(&[3.0, 0.25, 4.0])).violation, 0.75);
        assert_eq!(
            scoring.score(&ok(&[f64::NAN, 1.5, 4.0])).violation,
            f64::INFINITY
        );
        let failed = Evaluated {
            result: Err(EvalError("diverged".into())),
            seconds: 1.0,
        };
        assert_eq!(scoring.score(&failed).violation, f64::INFINITY);
    }
}
