//! Frequency response of dense models (reduced models, pROMs evaluated at a point).
//!
//! H(ω) = S_out (K − ω²M + iωC)⁻¹ S_in (thesis eq. 2.24 in the frequency domain), receptance
//! (displacement per force). One complex LU per frequency; frequencies run in parallel.

use faer::linalg::solvers::Solve;
use faer::{Mat, MatRef, c64};
use rayon::prelude::*;

/// Why a frequency response cannot be computed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FrfError {
    #[error("{what}: expected {expected}, got {got}")]
    Shape { what: &'static str, expected: usize, got: usize },
    #[error("the dynamic stiffness K − ω²M + iωC is singular at {hz} Hz (an undamped resonance or a rigid-body mode at 0 Hz): add damping or move the frequency line")]
    Singular { hz: f64 },
}

/// The dense model of one frequency-response evaluation.
pub struct DenseModel<'a> {
    pub stiffness: MatRef<'a, f64>,
    pub mass: MatRef<'a, f64>,
    pub damping: MatRef<'a, f64>,
}

/// H(ω_l) (outputs × inputs) at every angular frequency in `omegas` (rad/s).
/// `inputs` is n × n_in (load shapes), `outputs` n_out × n (output rows).
pub fn receptance(model: &DenseModel<'_>, inputs: MatRef<'_, f64>, outputs: MatRef<'_, f64>, omegas: &[f64]) -> Result<Vec<Mat<c64>>, FrfError> {
    let n = model.stiffness.nrows();
    for (what, got) in [
        ("stiffness columns", model.stiffness.ncols()),
        ("mass size", model.mass.nrows()),
        ("mass columns", model.mass.ncols()),
        ("damping size", model.damping.nrows()),
        ("damping columns", model.damping.ncols()),
        ("input shape rows", inputs.nrows()),
        ("output row length", outputs.ncols()),
    ] {
        if got != n {
            return Err(FrfError::Shape { what, expected: n, got });
        }
    }
    let rhs = Mat::<c64>::from_fn(n, inputs.ncols(), |i, j| c64::new(inputs[(i, j)], 0.0));
    let out = Mat::<c64>::from_fn(outputs.nrows(), n, |i, j| c64::new(outputs[(i, j)], 0.0));
    omegas
        .par_iter()
        .map(|&w| {
            let a = Mat::<c64>::from_fn(n, n, |i, j| c64::new(model.stiffness[(i, j)] - w * w * model.mass[(i, j)], w * model.damping[(i, j)]));
            let x = a.partial_piv_lu().solve(&rhs);
            if (0..x.ncols()).any(|j| x.col(j).iter().any(|z| !(z.re.is_finite() && z.im.is_finite()))) {
                return Err(FrfError::Singular { hz: w / (2.0 * std::f64::consts::PI) });
            }
            Ok(&out * &x)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// SDOF: H = 1/(k − ω²m + iωc) exactly (one complex division; bound 1e-14 relative).
    #[test]
    fn single_dof_matches_the_closed_form() {
        let (k, m, c) = (4.0e4, 2.0, 8.0);
        let one = |v: f64| Mat::<f64>::from_fn(1, 1, |_, _| v);
        let (km, mm, cm, unit) = (one(k), one(m), one(c), one(1.0));
        let model = DenseModel { stiffness: km.as_ref(), mass: mm.as_ref(), damping: cm.as_ref() };
        let omegas = [0.0, 50.0, (k / m).sqrt(), 400.0];
        let h = receptance(&model, unit.as_ref(), unit.as_ref(), &omegas).unwrap();
        for (w, hw) in omegas.iter().zip(&h) {
            let exact = c64::new(1.0, 0.0) / c64::new(k - w * w * m, w * c);
            assert!((hw[(0, 0)] - exact).norm() <= 1e-14 * exact.norm(), "ω = {w}");
        }
    }

    #[test]
    fn undamped_resonance_is_reported() {
        let one = |v: f64| Mat::<f64>::from_fn(1, 1, |_, _| v);
        let (km, mm, cm, unit) = (one(1.0), one(1.0), one(0.0), one(1.0));
        let model = DenseModel { stiffness: km.as_ref(), mass: mm.as_ref(), damping: cm.as_ref() };
        match receptance(&model, unit.as_ref(), unit.as_ref(), &[1.0]) {
            Err(FrfError::Singular { hz }) => assert!((hz - 1.0 / (2.0 * std::f64::consts::PI)).abs() < 1e-15),
            other => panic!("{other:?}"),
        }
    }
}
