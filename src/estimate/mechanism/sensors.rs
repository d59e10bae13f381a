//! The measurement equations y = h(x*) of the AMANDA-EKF (thesis eq. 9.16, 9.19) for the
//! multibody outputs a sensor reads ([`Output`]): strain gauges of flexible bodies (eq. 2.57,
//! absolute, or relative to a fixed reference configuration, eq. 9.24), marker positions
//! (eq. 2.58) and marker accelerations (eq. 2.59), with their rows of J_m.
//!
//! - strain: ε = C_ε q_f − ε_ref, linear: its row is C_ε on the body's flexible coordinates;
//! - position: nᵀ x(q), row nᵀ ∂x/∂q (the marker point's exact Jacobian);
//! - acceleration: nᵀ (∂x/∂q q̈ + q̇ᵀ ∂²x/∂q² q̇) with q̈ = (v_k − v_{k−1})/h, the BDF1
//!   difference the forward run reports (v_{k−1} the previous posterior, held fixed); its row by
//!   central differences in (q, v) of that expression (a few evaluations of one point).

use faer::Mat;

use crate::geometry::vec3::dot;
use crate::multibody::{Ggl, Output};

/// One measured quantity.
#[derive(Debug, Clone, PartialEq)]
pub struct Sensor {
    /// What it reads (only [`Output::Strain`], [`Output::Position`] and
    /// [`Output::Acceleration`] are measurement equations here).
    pub output: Output,
    /// Subtracted from the reading: ε_ref of a strain relative to a reference configuration
    /// (eq. 9.24), zero otherwise.
    pub reference: f64,
    /// Noise variance R.
    pub variance: f64,
}

impl Sensor {
    /// A strain gauge relative to the configuration with flexible coordinates `reference` of
    /// its body (eq. 9.24).
    pub fn relative_strain(body: usize, rows: Vec<f64>, reference: &[f64], variance: f64) -> Self {
        let reference = rows.iter().zip(reference).map(|(c, q)| c * q).sum();
        Self {
            output: Output::Strain { body, rows },
            reference,
            variance,
        }
    }

    /// Whether the output has a measurement equation here.
    pub fn is_supported(&self) -> bool {
        matches!(
            self.output,
            Output::Strain { .. } | Output::Position { .. } | Output::Acceleration { .. }
        )
    }
}

/// Relative step of the central differences of the acceleration rows.
const STEP: f64 = 1e-7;

/// nᵀ of a marker's acceleration at (q, v) with q̈ = (v − v_previous)/h.
fn acceleration(
    ggl: &Ggl,
    marker: usize,
    direction: [f64; 3],
    q: &[f64],
    v: &[f64],
    previous: &[f64],
) -> f64 {
    let p = ggl.system.markers[marker].point();
    let layout = &ggl.system.layout;
    let h = ggl.step_size;
    let qdd: Vec<f64> = v.iter().zip(previous).map(|(a, b)| (a - b) / h).collect();
    let mut a = p.rate(layout, q, &qdd);
    let convective = p.convective_acceleration(layout, q, v);
    for i in 0..3 {
        a[i] += convective[i];
    }
    dot(direction, a)
}

/// h(x) of every sensor at (q, v) = x's first 2n entries into `y` (no rows: the estimated
/// sensors' values); `previous` is v_{k−1} and `ggl` the system (its state is not read).
pub fn values(sensors: &[Sensor], ggl: &Ggl, x: &[f64], previous: &[f64], y: &mut [f64]) {
    let n = ggl.system.size();
    let (q, v) = (&x[..n], &x[n..2 * n]);
    let layout = &ggl.system.layout;
    for (k, s) in sensors.iter().enumerate() {
        y[k] = match &s.output {
            Output::Strain { body, rows } => {
                let f = layout.slice(*body).flexible();
                rows.iter().zip(&q[f..]).map(|(c, x)| c * x).sum::<f64>() - s.reference
            }
            &Output::Position { marker, direction } => {
                let p = ggl.system.markers[marker].point();
                dot(direction, p.value(layout, q))
            }
            &Output::Acceleration { marker, direction } => {
                acceleration(ggl, marker, direction, q, v, previous)
            }
            other => unreachable!("{other:?} is checked to have a measurement equation"),
        };
    }
}

/// h(x) of every sensor at (q, v) = x's first 2n entries into `y` ([`values`]), and their rows
/// (over all of x) into `jm` (overwritten); `previous` is v_{k−1} and `ggl` the system (its
/// state is not read).
pub fn measure(
    sensors: &[Sensor],
    ggl: &Ggl,
    x: &[f64],
    previous: &[f64],
    y: &mut [f64],
    jm: &mut Mat<f64>,
) {
    values(sensors, ggl, x, previous, y);
    let n = ggl.system.size();
    let (q, v) = (&x[..n], &x[n..2 * n]);
    let layout = &ggl.system.layout;
    jm.fill(0.0);
    for (k, s) in sensors.iter().enumerate() {
        match &s.output {
            Output::Strain { body, rows } => {
                let f = layout.slice(*body).flexible();
                for (i, c) in rows.iter().enumerate() {
                    jm[(k, f + i)] = *c;
                }
            }
            &Output::Position { marker, direction } => {
                let p = ggl.system.markers[marker].point();
                p.jacobian(layout, q, |i, j, d| jm[(k, j)] += direction[i] * d);
            }
            &Output::Acceleration { marker, direction } => {
                let (mut qs, mut vs) = (q.to_vec(), v.to_vec());
                for j in 0..n {
                    let step = STEP * (1.0 + q[j].abs());
                    qs[j] = q[j] + step;
                    let plus = acceleration(ggl, marker, direction, &qs, v, previous);
                    qs[j] = q[j] - step;
                    let minus = acceleration(ggl, marker, direction, &qs, v, previous);
                    qs[j] = q[j];
                    jm[(k, j)] = (plus - minus) / (2.0 * step);
                    let step = STEP * (1.0 + v[j].abs());
                    vs[j] = v[j] + step;
                    let plus = acceleration(ggl, marker, direction, q, &vs, previous);
                    vs[j] = v[j] - step;
                    let minus = acceleration(ggl, marker, direction, q, &vs, previous);
                    vs[j] = v[j];
                    jm[(k, n + j)] = (plus - minus) / (2.0 * step);
                }
            }
            other => unreachable!("{other:?} is checked to have a measurement equation"),
        }
    }
}
