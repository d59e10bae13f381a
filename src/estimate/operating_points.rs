//! Operating points for the observability test before a run ([`super::observability`]): the
//! static equilibrium of the initial estimate under the loads whose table is constant over the
//! window, plus 16 states of a BDF1 simulation ([`crate::dynamics::integrators`]) of the
//! time-varying loads. Unknown inputs count as static when every measured channel is at its
//! noise level ([`at_noise_level`]), and as a sine of their expected frequency and amplitude
//! (EKFINP) otherwise.

use faer::Mat;
use faer::linalg::solvers::Solve;

use super::observability::OperatingPoint;
use crate::dynamics::integrators::{LinearSystem, Method, integrate};
use crate::rom::prom::PromEvaluation;

/// Whether every measured series is noise around a constant: its RMS deviation from its mean
/// over the second half of the window is at most 2σ (σ: the channel's noise standard deviation).
/// Noise alone gives σ (within 3 % for a window of 1000 steps); ≥ √3 σ means a dynamic part at
/// least as large as the noise: threshold 2σ. (A bound on every sample, e.g. 3σ, is exceeded by
/// pure Gaussian noise over a long window: the largest of 2500 samples is ≈ 3.5σ.)
pub fn at_noise_level(series: &[Vec<f64>], sigma: &[f64]) -> bool {
    series.iter().zip(sigma).all(|(y, s)| {
        let tail = &y[y.len() / 2..];
        let count = tail.len().max(1) as f64;
        let mean = tail.iter().sum::<f64>() / count;
        (tail.iter().map(|v| (v - mean) * (v - mean)).sum::<f64>() / count).sqrt() <= 2.0 * s
    })
}

/// Operating points of the initial estimate (see the module documentation). `load(t, f,
/// static_part)` fills the known reduced load: its constant terms or its time-varying ones;
/// `inputs` are the unknown inputs' (frequency in Hz, amplitude), `static_inputs` whether they
/// count as static ([`at_noise_level`]).
pub fn of_initial_estimate(
    at: &PromEvaluation,
    s_un: &Mat<f64>,
    inputs: &[(f64, f64)],
    static_inputs: bool,
    dt: f64,
    steps: usize,
    load: &dyn Fn(f64, &mut [f64], bool),
) -> Result<Vec<OperatingPoint>, String> {
    let n = at.mass().nrows();
    let mut f_static = vec![0.0; n];
    load(dt, &mut f_static, true);
    if static_inputs {
        for (c, (_, amplitude)) in inputs.iter().enumerate() {
            (0..n).for_each(|i| f_static[i] += amplitude * s_un[(i, c)]);
        }
    }
    let q_static = match at.stiffness().llt(faer::Side::Lower) {
        Ok(llt) => {
            let x = llt.solve(Mat::from_fn(n, 1, |i, _| f_static[i]));
            (0..n).map(|i| x[(i, 0)]).collect()
        }
        Err(_) if f_static.iter().all(|v| *v == 0.0) => vec![0.0; n],
        Err(_) => return Err("K is not positive definite at the initial estimate: no static equilibrium under the constant loads".into()),
    };
    let mut probe = vec![0.0; n];
    let dynamic_known = (1..=steps).step_by((steps / 50).max(1)).any(|k| {
        load(k as f64 * dt, &mut probe, false);
        probe.iter().any(|v| *v != 0.0)
    });
    let dynamic_inputs = !inputs.is_empty() && !static_inputs;
    if !dynamic_known && !dynamic_inputs {
        return Ok(vec![OperatingPoint {
            q: q_static,
            v: vec![0.0; n],
            a: vec![0.0; n],
            dynamic: false,
        }]);
    }
    let sys = LinearSystem {
        mass: at.mass(),
        damping: at.damping(),
        stiffness: at.stiffness(),
    };
    // 16 sampling instants offset by the golden-ratio fraction of a spacing, so that they do
    // not fall on the zeros of a periodic load (where the state is a free response)
    let samples: Vec<usize> = (0..16)
        .map(|i| ((steps as f64) * (i as f64 + 0.618_034) / 16.0).round() as usize)
        .filter(|&k| k > 0)
        .collect();
    let mut points = Vec::new();
    let forcing = |t: f64, f: &mut [f64]| {
        load(t, f, false);
        if dynamic_inputs {
            for (c, (omega, amplitude)) in inputs.iter().enumerate() {
                let u = amplitude * (2.0 * std::f64::consts::PI * omega * t).sin();
                (0..n).for_each(|i| f[i] += u * s_un[(i, c)]);
            }
        }
    };
    integrate(
        sys,
        Method::Bdf1,
        dt,
        steps,
        &vec![0.0; n],
        &vec![0.0; n],
        forcing,
        |s| {
            if samples.contains(&s.step) {
                points.push(OperatingPoint {
                    q: s.q.iter().zip(&q_static).map(|(a, b)| a + b).collect(),
                    v: s.v.to_vec(),
                    a: s.a.to_vec(),
                    dynamic: true,
                });
            }
        },
    )
    .map_err(|e| e.to_string())?;
    Ok(points)
}
