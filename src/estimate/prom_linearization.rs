//! The pROM's linearization for the observability tests ([`super::observability`], thesis
//! eq. 8.33, 8.40–8.41), in the physical reduced coordinates q at the initial parameters:
//!
//! - PBH(0) with the q̇ block row of −J_c multiplied by M: [0 −I 0 0; K C −S_un D; J_m],
//!   D_j = ∂K/∂p_j q + ∂C/∂p_j q̇ + ∂M/∂p_j q̈ at the operating point (eq. 8.33); DISP (and
//!   STRAIN) rows read q, VEL rows q̇, ACCEL rows g [−K, −C, S_un, −D] with g = h M⁻¹.
//! - Hidden modes: with Rayleigh damping the state eigenvectors are [φ_i; λ_i φ_i] for the
//!   undamped modes φ_i, and DISP, VEL and ACCEL rows read h φ_i times 1, λ_i, λ_i²: mode i is
//!   unobservable when H φ_i = 0.

use faer::Mat;

use super::ekf::Linearization;
use super::measurement::{Reads, SensorRows};
use super::observability::{OperatingPoint, Unknown};
use super::physical::parameter_columns;
use crate::rom::prom::PromEvaluation;

/// The pROM's augmented system at the initial parameters.
pub struct PromLinearization<'a> {
    /// pROM at the initial parameters and its Rayleigh α, β.
    pub at: &'a PromEvaluation,
    pub alpha_beta: (f64, f64),
    /// Unknown-input shapes S_un.
    pub s_un: &'a Mat<f64>,
    /// Indices of the unknown parameters.
    pub params: &'a [usize],
    /// Descriptions of the unknowns, inputs first.
    pub unknowns: &'a [Unknown],
    pub measured: &'a SensorRows,
    /// (ω² ascending, M-orthonormal shapes) of K, M at the initial parameters.
    pub modes: (&'a [f64], &'a Mat<f64>),
}

impl Linearization for PromLinearization<'_> {
    fn size(&self) -> usize {
        2 * self.at.mass().nrows() + self.s_un.ncols() + self.params.len()
    }

    fn unknowns(&self) -> &[Unknown] {
        self.unknowns
    }

    fn reads(&self) -> &[Reads] {
        &self.measured.reads
    }

    fn pbh_zero(&self, op: &OperatingPoint) -> Mat<f64> {
        let (at, s_un, measured) = (self.at, self.s_un, self.measured);
        let n = at.mass().nrows();
        let (nu, np, m) = (s_un.ncols(), self.params.len(), measured.len());
        let big_n = self.size();
        let d = parameter_columns(at, self.alpha_beta, self.params, &op.q, &op.v, &op.a);
        let mut pbh = Mat::zeros(2 * n + m, big_n);
        for i in 0..n {
            pbh[(i, n + i)] = -1.0;
            for c in 0..n {
                pbh[(n + i, c)] = at.stiffness()[(i, c)];
                pbh[(n + i, n + c)] = at.damping()[(i, c)];
            }
            for c in 0..nu {
                pbh[(n + i, 2 * n + c)] = -s_un[(i, c)];
            }
            for k in 0..np {
                pbh[(n + i, 2 * n + nu + k)] = d[(i, k)];
            }
        }
        // accelerometer rows g [−K, −C, S_un, −D] with g = h M⁻¹; VEL rows read q̇
        let m_llt = at.mass().llt(faer::Side::Lower).ok();
        for r in 0..m {
            match measured.reads[r] {
                Reads::Displacement => {
                    (0..n).for_each(|c| pbh[(2 * n + r, c)] = measured.h[(r, c)])
                }
                Reads::Velocity => {
                    (0..n).for_each(|c| pbh[(2 * n + r, n + c)] = measured.h[(r, c)])
                }
                Reads::Acceleration => {
                    let Some(llt) = m_llt.as_ref() else { continue };
                    let g = faer::linalg::solvers::Solve::solve(
                        llt,
                        Mat::from_fn(n, 1, |i, _| measured.h[(r, i)]),
                    );
                    for c in 0..big_n {
                        pbh[(2 * n + r, c)] =
                            -(0..n).map(|i| g[(i, 0)] * pbh[(n + i, c)]).sum::<f64>();
                    }
                }
            }
        }
        pbh
    }

    fn hidden_modes(&self) -> Vec<(usize, f64)> {
        let (lambda, phi) = self.modes;
        let (n, measured) = (self.at.mass().nrows(), self.measured);
        (0..lambda.len())
            .filter(|&j| {
                let col_norm = (0..n)
                    .map(|i| phi[(i, j)] * phi[(i, j)])
                    .sum::<f64>()
                    .sqrt();
                let seen = (0..measured.len())
                    .map(|r| {
                        (0..n)
                            .map(|i| measured.h[(r, i)] * phi[(i, j)])
                            .sum::<f64>()
                            .abs()
                            / (row_norm(&measured.h, r) * col_norm).max(f64::MIN_POSITIVE)
                    })
                    .fold(0.0, f64::max);
                seen <= 1e-8
            })
            .map(|j| {
                (
                    j + 1,
                    lambda[j].max(0.0).sqrt() / (2.0 * std::f64::consts::PI),
                )
            })
            .collect()
    }
}

fn row_norm(m: &Mat<f64>, r: usize) -> f64 {
    (0..m.ncols())
        .map(|c| m[(r, c)] * m[(r, c)])
        .sum::<f64>()
        .sqrt()
}
