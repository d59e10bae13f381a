//! Measurement equations of pROM sensors, y = h(x*) (thesis eq. 8.7–8.9, 8.36): one module for
//! every sequence that reads sensors off reduced states — the estimator here, and the transient
//! and FRF drivers can share [`SensorRows::evaluate`] instead of repeating the kind dispatch.
//!
//! A sensor row h (1 × n_r) of `/prom/sensors/H_r` reads y = h q for `DISP` and `STRAIN`
//! (strain and displacement carry the same information, thesis §8.4.1: eq. 8.38 holds for
//! both), y = h q̇ for `VEL` and y = h q̈ for `ACCEL` (eq. 8.9, q̈ from the equation of motion).

use faer::Mat;

/// What a sensor row reads.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Reads {
    /// q: DISP and STRAIN rows.
    Displacement,
    /// q̇: VEL rows.
    Velocity,
    /// q̈: ACCEL rows.
    Acceleration,
}

impl Reads {
    /// The kind of a `/prom/sensors/kind` entry, or `None` for an unknown kind.
    pub fn of_kind(kind: &str) -> Option<Reads> {
        match kind {
            "DISP" | "STRAIN" => Some(Reads::Displacement),
            "VEL" => Some(Reads::Velocity),
            "ACCEL" => Some(Reads::Acceleration),
            _ => None,
        }
    }
}

/// Sensor rows of a pROM: names, what each reads, H_r (s × n_r).
#[derive(Debug, Clone)]
pub struct SensorRows {
    pub names: Vec<String>,
    pub kinds: Vec<String>,
    pub reads: Vec<Reads>,
    pub h: Mat<f64>,
}

impl SensorRows {
    /// Rows from the pROM's names, kinds and H_r; an unknown kind is an error naming the sensor.
    pub fn new(names: Vec<String>, kinds: Vec<String>, h: Mat<f64>) -> Result<Self, String> {
        let reads = names
            .iter()
            .zip(&kinds)
            .map(|(n, k)| Reads::of_kind(k).ok_or_else(|| format!("sensor {n}: kind {k} is not DISP, STRAIN, VEL or ACCEL")))
            .collect::<Result<Vec<_>, _>>()?;
        Ok(SensorRows { names, kinds, reads, h })
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

    pub fn len(&self) -> usize {
        self.names.len()
    }

    pub fn is_empty(&self) -> bool {
        self.names.is_empty()
    }

    /// y_r = h_r · (q, q̇ or q̈ as the row reads), eq. 8.36 with H* of eq. 8.7–8.9.
    pub fn evaluate(&self, q: &[f64], v: &[f64], a: &[f64], y: &mut [f64]) {
        for (r, out) in y.iter_mut().enumerate() {
            let x = match self.reads[r] {
                Reads::Displacement => q,
                Reads::Velocity => v,
                Reads::Acceleration => a,
            };
            *out = x.iter().enumerate().map(|(i, xi)| self.h[(r, i)] * xi).sum();
        }
    }
}
