//! Measurement equations y = h(state) of SENSORs (thesis §2.3, eq. 2.32–2.36 and 2.41–2.43;
//! on pROMs eq. 8.7–8.9, 8.36), in one place for every sequence that reads sensors: the
//! full-model FRF and transient (sparse f-set rows, [`crate::discretize::sensors`]), the pROM FRF
//! and transient and the estimator (dense reduced rows, [`SensorRows`]).
//!
//! A sensor row h is linear in the displacements: strain ε_ϑ = N_s q (eq. 2.32) and
//! displacement d = N_d q (eq. 2.34) read the displacement state, a velocity sensor reads q̇
//! with the displacement row, and an accelerometer reads q̈ = N_d q̈ (eq. 2.35) — which the
//! equation of motion turns into a function of (q, q̇, u), eq. 2.36 / 2.43; the time integrators
//! provide q̈ at every step, and the estimator differentiates eq. 2.36 itself
//! (`estimate::filter`). Strain and displacement carry the same information (eq. 2.41–2.42,
//! thesis §8.4.1), so both are [`Reads::Displacement`].
//!
//! In the frequency domain the state derivatives become factors: with q(t) = Q e^{iωt},
//! q̇ = iω Q and q̈ = (iω)² Q = −ω² Q, so a row reading the k-th derivative multiplies the
//! receptance by (iω)^k ([`Reads::frequency_factor`]).

use faer::{Mat, MatRef, c64};

use super::integrators::{StepState, matvec_add};

use crate::card_values::SensorKind;

/// What a sensor row reads: the displacement state or one of its time derivatives.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Reads {
    /// q: DISP and STRAIN rows (eq. 2.32, 2.34).
    Displacement,
    /// q̇: VEL rows.
    Velocity,
    /// q̈: ACCEL rows (eq. 2.35).
    Acceleration,
}

impl Reads {
    /// The kind of a SENSOR (`DISP`, `STRAIN`, `VEL`, `ACCEL`, as `/prom/sensors/kind` stores
    /// it), or `None` for an unknown kind.
    pub fn of_kind(kind: &str) -> Option<Reads> {
        match kind {
            "DISP" | "STRAIN" => Some(Reads::Displacement),
            "VEL" => Some(Reads::Velocity),
            "ACCEL" => Some(Reads::Acceleration),
            _ => None,
        }
    }

    /// What a SENSOR card of `kind` reads.
    pub fn of_sensor(kind: SensorKind) -> Reads {
        match kind {
            SensorKind::Disp | SensorKind::Strain => Reads::Displacement,
            SensorKind::Vel => Reads::Velocity,
            SensorKind::Accel => Reads::Acceleration,
        }
    }

    /// The state this row reads among (q, q̇, q̈).
    pub fn select<T>(self, q: T, v: T, a: T) -> T {
        match self {
            Reads::Displacement => q,
            Reads::Velocity => v,
            Reads::Acceleration => a,
        }
    }

    /// (iω)^k for the k-th time derivative this row reads: 1, iω, −ω² — the factor that turns
    /// a displacement-per-force receptance into this row's quantity at ω (rad/s).
    pub fn frequency_factor(self, w: f64) -> c64 {
        self.select(c64::new(1.0, 0.0), c64::new(0.0, w), c64::new(-w * w, 0.0))
    }
}

/// Dense sensor rows on reduced coordinates (a pROM's `/prom/sensors`): names, kinds, what each
/// reads and H_r (s × n_r).
#[derive(Debug, Clone)]
pub struct SensorRows {
    pub names: Vec<String>,
    pub kinds: Vec<String>,
    pub reads: Vec<Reads>,
    pub h: Mat<f64>,
}

impl SensorRows {
    /// Rows from names, kinds and H_r; an unknown kind is an error naming the sensor.
    pub fn new(names: Vec<String>, kinds: Vec<String>, h: Mat<f64>) -> Result<Self, String> {
        let reads = names
            .iter()
            .zip(&kinds)
            .map(|(n, k)| {
                Reads::of_kind(k).ok_or_else(|| {
                    format!("sensor {n}: kind {k} is not DISP, STRAIN, VEL or ACCEL")
                })
            })
            .collect::<Result<Vec<_>, _>>()?;
        Ok(SensorRows {
            names,
            kinds,
            reads,
            h,
        })
    }

    /// The rows `which` (indices) only.
    pub fn select(&self, which: &[usize]) -> SensorRows {
        SensorRows {
            names: which.iter().map(|&i| self.names[i].clone()).collect(),
            kinds: which.iter().map(|&i| self.kinds[i].clone()).collect(),
            reads: which.iter().map(|&i| self.reads[i]).collect(),
            h: Mat::from_fn(which.len(), self.h.ncols(), |r, c| self.h[(which[r], c)]),
        }
    }

    /// The output rows of a receptance on the reduced coordinates: first the input DOFs (the
    /// rows of S_rᵀ, for the input shapes `s_r`, n × k: their displacement), then these
    /// sensors.
    pub fn below_inputs(&self, s_r: MatRef<'_, f64>) -> Mat<f64> {
        let k = s_r.ncols();
        Mat::<f64>::from_fn(k + self.len(), s_r.nrows(), |o, j| {
            if o < k {
                s_r[(j, o)]
            } else {
                self.h[(o - k, j)]
            }
        })
    }

    pub fn len(&self) -> usize {
        self.names.len()
    }

    pub fn is_empty(&self) -> bool {
        self.names.is_empty()
    }

    /// y_r = h_r · (q, q̇ or q̈ as the row reads), eq. 2.32–2.35 (8.36 with H* of eq. 8.7–8.9).
    /// Column-oriented (H_r is column-major), no allocation.
    pub fn evaluate(&self, q: &[f64], v: &[f64], a: &[f64], y: &mut [f64]) {
        debug_assert!(y.len() == self.len() && q.len() == self.h.ncols());
        y.fill(0.0);
        for j in 0..self.h.ncols() {
            let column = self.h.col_as_slice(j);
            for ((out, h), reads) in y.iter_mut().zip(column).zip(&self.reads) {
                *out += h * reads.select(q, v, a)[j];
            }
        }
    }
}

/// The outputs of a reduced time integration, in buffers sized before the run and filled by
/// matrix–vector products (no allocation in the time loop): input-DOF series `rows` × k
/// (row-major, column r of a k × rows column-major buffer), and per sensor a series of `rows`
/// values (sensor-major).
pub struct Recorder<'a> {
    /// S_rᵀ (k × n).
    s_t: Mat<f64>,
    /// The pROM's sensor rows (DISP and STRAIN from q, VEL from q̇, ACCEL from q̈).
    sensors: &'a SensorRows,
    scratch: Vec<f64>,
    rows: usize,
    pub time: Vec<f64>,
    pub disp: Vec<f64>,
    pub vel: Vec<f64>,
    pub acc: Vec<f64>,
    pub series: Vec<f64>,
}

impl<'a> Recorder<'a> {
    pub fn new(s_r: &Mat<f64>, sensors: &'a SensorRows, rows: usize) -> Self {
        let k = s_r.ncols();
        Recorder {
            s_t: s_r.transpose().to_owned(),
            sensors,
            scratch: vec![0.0; sensors.len()],
            rows,
            time: Vec::with_capacity(rows),
            disp: Vec::with_capacity(rows * k),
            vel: Vec::with_capacity(rows * k),
            acc: Vec::with_capacity(rows * k),
            series: vec![0.0; sensors.len() * rows],
        }
    }

    pub fn record(&mut self, s: &StepState<'_>) {
        let r = self.time.len();
        if r == self.rows {
            return;
        }
        self.time.push(s.time);
        let k = self.s_t.nrows();
        for (out, x) in [
            (&mut self.disp, s.q),
            (&mut self.vel, s.v),
            (&mut self.acc, s.a),
        ] {
            out.resize(out.len() + k, 0.0);
            let end = out.len();
            matvec_add(&self.s_t, x, &mut out[end - k..]);
        }
        self.sensors.evaluate(s.q, s.v, s.a, &mut self.scratch);
        for (j, value) in self.scratch.iter().enumerate() {
            self.series[j * self.rows + r] = *value;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each kind reads its state, and the frequency factors are (iω)^k computed as powers.
    #[test]
    fn rows_read_their_state_and_derivative_factors_are_powers_of_i_omega() {
        let rows = SensorRows::new(
            vec!["D".into(), "S".into(), "V".into(), "A".into()],
            ["DISP", "STRAIN", "VEL", "ACCEL"]
                .map(String::from)
                .to_vec(),
            Mat::from_fn(4, 2, |r, c| (1 + r + 4 * c) as f64),
        )
        .unwrap();
        let (q, v, a) = ([1.0, 2.0], [10.0, 20.0], [100.0, 200.0]);
        let mut y = [0.0; 4];
        rows.evaluate(&q, &v, &a, &mut y);
        assert_eq!(
            y,
            [
                1.0 + 10.0,
                2.0 + 12.0,
                10.0 * 3.0 + 20.0 * 7.0,
                100.0 * 4.0 + 200.0 * 8.0
            ]
        );
        let w = 37.5;
        for (reads, k) in [
            (Reads::Displacement, 0),
            (Reads::Velocity, 1),
            (Reads::Acceleration, 2),
        ] {
            assert_eq!(
                reads.frequency_factor(w),
                c64::new(0.0, w).powi(k),
                "{reads:?}"
            );
        }
    }

    #[test]
    fn an_unknown_kind_is_an_error_naming_the_sensor() {
        let err =
            SensorRows::new(vec!["X1".into()], vec!["FORCE".into()], Mat::zeros(1, 3)).unwrap_err();
        assert!(err.contains("X1") && err.contains("FORCE"), "{err}");
    }
}
