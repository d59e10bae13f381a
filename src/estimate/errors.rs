//! The accuracy of an estimate against a reference series (thesis §8.6, Table 8.2): percent
//! errors over the last 20 % of the window for parameters and inputs, and for sensors the
//! average absolute error with the largest |reference| to judge it by.

/// Percent errors 100 (x̂ − x)/x over the tail of a run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PercentErrors {
    pub min: f64,
    pub avg: f64,
    pub max: f64,
}

/// The first step of the last 20 % of `steps` (at least the last step).
pub fn tail_start(steps: usize) -> usize {
    steps - (steps / 5).max(1)
}

/// The percent errors of `estimate` against `truth` over the last 20 % of the run
/// ([`tail_start`]).
pub fn percent_errors(estimate: &[f64], truth: &[f64]) -> PercentErrors {
    let steps = estimate.len().min(truth.len());
    let errors: Vec<f64> = (tail_start(steps)..steps)
        .map(|k| 100.0 * (estimate[k] - truth[k]) / truth[k])
        .collect();
    PercentErrors {
        min: errors.iter().copied().fold(f64::INFINITY, f64::min),
        avg: errors.iter().sum::<f64>() / errors.len() as f64,
        max: errors.iter().copied().fold(f64::NEG_INFINITY, f64::max),
    }
}

/// (AAE, MRA): the average absolute error of `estimate` against `truth` over the whole run
/// and the maximum |truth|.
pub fn absolute_error(estimate: &[f64], truth: &[f64]) -> (f64, f64) {
    let aae = truth
        .iter()
        .zip(estimate)
        .map(|(a, b)| (a - b).abs())
        .sum::<f64>()
        / truth.len() as f64;
    let mra = truth.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    (aae, mra)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn percent_errors_read_only_the_last_fifth() {
        // ten steps: the tail is steps 8 and 9
        let truth = vec![2.0; 10];
        let mut estimate = vec![100.0; 10];
        estimate[8] = 2.2;
        estimate[9] = 1.9;
        let e = percent_errors(&estimate, &truth);
        assert!((e.max - 10.0).abs() < 1e-12);
        assert!((e.min + 5.0).abs() < 1e-12);
        assert!((e.avg - 2.5).abs() < 1e-12);
        assert_eq!(tail_start(3), 2);
    }

    #[test]
    fn absolute_error_averages_over_the_run() {
        let (aae, mra) = absolute_error(&[1.0, 2.0, 5.0, 0.0], &[1.0, 3.0, 4.0, -2.0]);
        assert!((aae - 1.0).abs() < 1e-15);
        assert_eq!(mra, 4.0);
    }
}
