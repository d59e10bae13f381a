//! The evaluation interface: a batch of designs in, one result per design out, each a vector
//! of responses or an [`EvalError`], with its wall time. A failed evaluation is a result like
//! any other (the search marks the design infeasible and goes on), never the end of a study.
//!
//! Searches take the batch as `&mut dyn FnMut(&[Design]) -> Vec<Evaluated>`, so that the same
//! search runs on [`Threaded`] (a rayon pool of NPAR threads over a per-design function) or on
//! any other engine that maps designs to results.

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::time::Instant;

use rayon::prelude::*;

use super::space::Design;

/// The responses of one design, in the study's response order.
pub type Responses = Vec<f64>;

/// Why one design could not be evaluated.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{0}")]
pub struct EvalError(pub String);

/// One design's result and how long its evaluation took.
#[derive(Debug, Clone, PartialEq)]
pub struct Evaluated {
    pub result: Result<Responses, EvalError>,
    pub seconds: f64,
}

/// A batch evaluator: one result per design, in order.
pub type Batch<'a> = dyn FnMut(&[Design]) -> Vec<Evaluated> + 'a;

/// A batch evaluator that runs `evaluate` on each design in turn, in the calling thread (cheap
/// responses such as the reference problems, or one evaluation at a time).
pub fn serial<F>(evaluate: F) -> impl FnMut(&[Design]) -> Vec<Evaluated>
where
    F: Fn(&[f64]) -> Result<Responses, EvalError>,
{
    move |designs: &[Design]| {
        designs
            .iter()
            .map(|d| {
                let start = Instant::now();
                let result = evaluate(d);
                Evaluated {
                    result,
                    seconds: start.elapsed().as_secs_f64(),
                }
            })
            .collect()
    }
}

/// Evaluates batches with a per-design function on a pool of its own threads.
pub struct Threaded<F> {
    pool: rayon::ThreadPool,
    evaluate: F,
}

impl<F> Threaded<F>
where
    F: Fn(&[f64]) -> Result<Responses, EvalError> + Sync,
{
    /// A pool of `threads` threads (0: one per core) running `evaluate`.
    pub fn new(threads: usize, evaluate: F) -> Result<Self, EvalError> {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .map_err(|e| EvalError(format!("cannot start {threads} evaluation thread(s): {e}")))?;
        Ok(Threaded { pool, evaluate })
    }

    /// Every design of `designs` evaluated, in order. A panicking evaluation is recorded as
    /// failed with the panic's message.
    pub fn batch(&self, designs: &[Design]) -> Vec<Evaluated> {
        self.pool.install(|| {
            designs
                .par_iter()
                .map(|d| {
                    let start = Instant::now();
                    let result = catch_unwind(AssertUnwindSafe(|| (self.evaluate)(d)))
                        .unwrap_or_else(|panic| Err(EvalError(panic_message(&panic))));
                    Evaluated {
                        result,
                        seconds: start.elapsed().as_secs_f64(),
                    }
                })
                .collect()
        })
    }
}

/// The text of a caught panic.
fn panic_message(panic: &Box<dyn std::any::Any + Send>) -> String {
    let text = panic
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| panic.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "unknown cause".into());
    format!("the evaluation panicked: {text}")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_batch_keeps_the_order_and_records_failures() {
        let threaded = Threaded::new(2, |d: &[f64]| {
            if d[0] < 0.0 {
                Err(EvalError("negative".into()))
            } else if d[0] > 10.0 {
                panic!("too large")
            } else {
                Ok(vec![d[0] * 2.0])
            }
        })
        .unwrap();
        let out = threaded.batch(&[vec![1.0], vec![-1.0], vec![3.0], vec![11.0]]);
        assert_eq!(out[0].result, Ok(vec![2.0]));
        assert_eq!(out[1].result, Err(EvalError("negative".into())));
        assert_eq!(out[2].result, Ok(vec![6.0]));
        assert_eq!(
            out[3].result,
            Err(EvalError("the evaluation panicked: too large".into()))
        );
    }
}
