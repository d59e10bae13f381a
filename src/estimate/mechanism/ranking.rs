//! Ranking candidate sensors of a mechanism by what they tell about its unknowns (beyond the
//! thesis: its §9.5 names the choice of sensor setups as future work).
//!
//! Along the prior trajectory (the filter's prediction from the initial guesses, the window of
//! [`super::observability::along_prior`]) each candidate r gives the Fisher information of its
//! readings about the initial perturbation of the independent coordinates, velocities,
//! inputs and scaled parameters,
//!
//! ```text
//! F_r = Σ_k o_k,rᵀ o_k,r,   o_k,r = σ_r⁻¹ J_m,k,r Φ_k T     (the observability rows of r),
//! ```
//!
//! and a set S of sensors, with the filter's own P₀ as the prior (in the same columns),
//! the information F(S) = P₀⁻¹ + Σ_{r∈S} F_r. Its inverse is the covariance that a linear,
//! Gaussian estimate of the window's data would reach (the Cramér–Rao bound of the
//! linearized problem without process noise); its block on the unknowns, C_u(S), holds the
//! states as nuisance: an unknown whose effect a change of the states can mimic keeps its
//! prior variance. The criterion is log det C_u(S) (D-optimality on the unknowns: the volume
//! of their confidence ellipsoid), and the ranking is greedy: at each stage the candidate
//! whose addition lowers it most. Each stage reports the predicted standard deviations of the
//! unknowns (√diag C_u; the parameters' relative to their initial guesses).

use faer::Mat;
use faer::linalg::solvers::Solve;

use super::observability::Window;

/// The information each candidate adds over a window, and the prior.
#[derive(Debug, Clone)]
pub struct Information {
    /// F_r per candidate (columns × columns).
    pub candidates: Vec<Mat<f64>>,
    /// The prior variances of the columns (P₀ of the independent coordinates, velocities,
    /// inputs and scaled parameters).
    pub prior: Vec<f64>,
    /// The unknowns' columns: the last `unknowns` of the window's.
    pub unknowns: usize,
}

/// One stage of a ranking: the candidate added, log det C_u and the predicted standard
/// deviation of each unknown with the sensors chosen so far.
#[derive(Debug, Clone, PartialEq)]
pub struct Stage {
    pub candidate: usize,
    pub log_det: f64,
    pub sigma: Vec<f64>,
}

/// What a sensor set predicts: log det C_u and the unknowns' standard deviations.
#[derive(Debug, Clone, PartialEq)]
pub struct Prediction {
    pub log_det: f64,
    pub sigma: Vec<f64>,
}

impl Information {
    /// The information of the `candidates` sensors of `window` (filled with their rows, one
    /// per candidate in order) with the prior variances of the states (`positions`,
    /// `velocities`: per coordinate) and of the unknowns (`unknowns`: inputs, then scaled
    /// parameters).
    pub fn of_window(
        window: &Window,
        candidates: usize,
        positions: f64,
        velocities: f64,
        unknowns: &[f64],
    ) -> Self {
        let (free, (nu, np)) = window.layout();
        debug_assert_eq!(unknowns.len(), nu + np);
        let mut prior = vec![positions; free];
        prior.extend(std::iter::repeat_n(velocities, free));
        prior.extend(unknowns);
        Self {
            candidates: (0..candidates).map(|r| window.information(r)).collect(),
            prior,
            unknowns: nu + np,
        }
    }

    /// What the set `chosen` (candidate indices) predicts (module docs); `None` when the
    /// information matrix cannot be factored (a prior variance not positive).
    pub fn predict(&self, chosen: &[usize]) -> Option<Prediction> {
        let size = self.prior.len();
        let mut f = Mat::from_fn(
            size,
            size,
            |i, j| {
                if i == j { 1.0 / self.prior[i] } else { 0.0 }
            },
        );
        for &r in chosen {
            f += &self.candidates[r];
        }
        // symmetric (Jacobi) scaling: the columns' units differ by many orders
        let d: Vec<f64> = (0..size).map(|i| f[(i, i)].sqrt()).collect();
        if d.iter().any(|x| !(x.is_finite() && *x > 0.0)) {
            return None;
        }
        let scaled = Mat::from_fn(size, size, |i, j| f[(i, j)] / (d[i] * d[j]));
        let first = size - self.unknowns;
        let rhs = Mat::from_fn(size, self.unknowns, |i, j| {
            f64::from(u8::from(i == first + j))
        });
        let x = scaled.llt(faer::Side::Lower).ok()?.solve(&rhs);
        // C_u of the unscaled F: D⁻¹ (scaled F)⁻¹ D⁻¹ on the unknowns' block
        let block = Mat::from_fn(self.unknowns, self.unknowns, |i, j| {
            x[(first + i, j)] / (d[first + i] * d[first + j])
        });
        let log_det = block
            .llt(faer::Side::Lower)
            .ok()
            .map(|l| (0..self.unknowns).map(|i| 2.0 * l.L()[(i, i)].ln()).sum())?;
        Some(Prediction {
            log_det,
            sigma: (0..self.unknowns).map(|i| block[(i, i)].sqrt()).collect(),
        })
    }

    /// The greedy ranking of every candidate (module docs); stops early if a set's
    /// information cannot be factored.
    pub fn rank(&self) -> Vec<Stage> {
        let mut chosen: Vec<usize> = Vec::new();
        let mut stages = Vec::new();
        while chosen.len() < self.candidates.len() {
            let best = (0..self.candidates.len())
                .filter(|r| !chosen.contains(r))
                .filter_map(|r| {
                    let mut set = chosen.clone();
                    set.push(r);
                    self.predict(&set).map(|p| (r, p))
                })
                .min_by(|a, b| a.1.log_det.total_cmp(&b.1.log_det));
            let Some((candidate, prediction)) = best else {
                break;
            };
            chosen.push(candidate);
            stages.push(Stage {
                candidate,
                log_det: prediction.log_det,
                sigma: prediction.sigma,
            });
        }
        stages
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One state s and one unknown u; candidate 0 reads s + u (it cannot tell them apart
    /// without the prior), candidate 1 reads u alone at half the weight: each F_r = a aᵀ. The
    /// predicted variance of u is the (u, u) entry of the inverse of P₀⁻¹ + Σ F_r, in closed
    /// form for 2 × 2; with the prior on s (p_s = 0.5, p_u = 2) the greedy ranking takes
    /// candidate 0 first (variance of u 6/7 against 4/3 from candidate 1).
    #[test]
    fn prediction_is_the_unknowns_block_of_the_inverse_information() {
        let outer = |a: [f64; 2]| Mat::from_fn(2, 2, |i, j| a[i] * a[j]);
        let (ps, pu) = (0.5, 2.0);
        let information = Information {
            candidates: vec![outer([1.0, 1.0]), outer([0.0, 0.5])],
            prior: vec![ps, pu],
            unknowns: 1,
        };
        let variance = |f: [[f64; 2]; 2]| {
            let det = f[0][0] * f[1][1] - f[0][1] * f[1][0];
            f[0][0] / det
        };
        let expected = [
            variance([[1.0 / ps + 1.0, 1.0], [1.0, 1.0 / pu + 1.0]]),
            variance([[1.0 / ps, 0.0], [0.0, 1.0 / pu + 0.25]]),
            variance([[1.0 / ps + 1.0, 1.0], [1.0, 1.0 / pu + 1.25]]),
        ];
        for (set, v) in [vec![0], vec![1], vec![0, 1]].iter().zip(expected) {
            let p = information.predict(set).expect("factored");
            assert!((p.sigma[0] * p.sigma[0] - v).abs() < 1e-14 * v, "{set:?}");
            assert!((p.log_det - v.ln()).abs() < 1e-13, "{set:?}");
        }
        let stages = information.rank();
        assert_eq!(
            stages.iter().map(|s| s.candidate).collect::<Vec<_>>(),
            [0, 1]
        );
    }
}
