//! The extended Kalman filter's algebra (thesis §8.2–8.3, eq. 8.22–8.28), written once over a
//! [`ProcessModel`]: the model predicts the mean and the covariance (eq. 8.22–8.24: the
//! structure of its transition Jacobian is its own, e.g. the block-sparse BDF1 transition of a
//! pROM) and gives the predicted measurements and their Jacobian J_m (eq. 8.36–8.39); [`Ekf`]
//! owns x* and P and does the correction:
//!
//! - innovation e = y − h(x⁻), U = P J_mᵀ (columns of P combined by the nonzero entries of
//!   J_m's rows), S_y = J_m U + R, gain 𝒦 = U S_y⁻¹ (eq. 8.26) by a Cholesky factor of S_y;
//! - x⁺ = x⁻ + 𝒦 e (eq. 8.27);
//! - the Joseph form (eq. 8.28) L P Lᵀ + 𝒦 R 𝒦ᵀ, L = I − 𝒦 J_m, expanded into
//!   P − 𝒦 Uᵀ − U 𝒦ᵀ + 𝒦 S_y 𝒦ᵀ (no term dropped: first-order insensitive to errors of 𝒦, as
//!   the Joseph form is), a symmetric rank-2m update: 2 N² m multiply-adds, exactly symmetric.
//!
//! after which the model linearizes again at x⁺ ([`ProcessModel::corrected`]). A step allocates
//! nothing: the buffers are sized at construction.
//!
//! The observability tests before a run read a model's continuous-time [`Linearization`].

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::cholesky_in_place_scratch;
use faer::linalg::matmul::matmul;
use faer::{Accum, Mat, Par};

use super::filter::FilterError;
use super::kernels::{axpy, factor_in_place, solve_seq, storage, storage_mut, vectorized};
use super::measurement::Reads;
use super::observability::{OperatingPoint, Unknown};

/// An augmented process model x*_k = f(x*_{k−1}, input_k) + noise with measurements
/// y = h(x*) + noise, linearized by the model itself.
pub trait ProcessModel {
    /// The known input of a step (a pROM's reduced load).
    type Input: ?Sized;
    /// Size N of the augmented state.
    fn size(&self) -> usize;
    /// Noise variances R of the measurements (diagonal; one per measurement).
    fn measurement_noise(&self) -> &[f64];
    /// Whether `input` fits the model.
    fn check_input(&self, input: &Self::Input) -> Result<(), FilterError>;
    /// Prediction to step `step` (≥ 1): x ← f(x, input), P ← J P Jᵀ + Q (eq. 8.22–8.24).
    fn predict(
        &mut self,
        step: usize,
        input: &Self::Input,
        x: &mut [f64],
        p: &mut Mat<f64>,
    ) -> Result<(), FilterError>;
    /// The predicted measurements h(x) and the rows of J_m (m × N) at the prior x.
    fn measure(&mut self, x: &[f64], predicted: &mut [f64], jm: &mut Mat<f64>);
    /// Entries of x that this step's correction leaves unchanged (their rows of the gain are
    /// zero; the Joseph form keeps P consistent with any gain), decided by [`Self::measure`];
    /// none by default.
    fn frozen(&self) -> &[usize] {
        &[]
    }
    /// Linearize again at the posterior of step `step` (which may change the coordinates of x
    /// and P), for the correction's and the next prediction's input `input`.
    fn corrected(
        &mut self,
        step: usize,
        input: &Self::Input,
        x: &mut [f64],
        p: &mut Mat<f64>,
    ) -> Result<(), FilterError>;
}

/// The continuous-time linearization of an augmented process model, what the observability
/// tests ([`super::observability`], thesis eq. 7.28, 8.40–8.41) read: the state x* holds the
/// model's states, then the unknowns (inputs and parameters, random walks).
pub trait Linearization {
    /// Size N of the augmented state.
    fn size(&self) -> usize;
    /// The unknowns, in the order of their (last) entries of x*.
    fn unknowns(&self) -> &[Unknown];
    /// What each measurement row reads.
    fn reads(&self) -> &[Reads];
    /// PBH(0) = [−J_c; J_m] at `point` (N columns): the rows of −J_c that are not identically
    /// zero, a block row possibly multiplied by an invertible matrix (e.g. M for the equation
    /// of motion; the rank is kept), over the measurement Jacobian J_m.
    fn pbh_zero(&self, point: &OperatingPoint) -> Mat<f64>;
    /// The modes (1-based, with frequency in Hz) at whose eigenvalue s = λ_i ≠ 0 of J_c the
    /// PBH matrix loses rank: modes no measured row sees.
    fn hidden_modes(&self) -> Vec<(usize, f64)>;
}

/// The filter: a process model, the estimate x* and its covariance P.
pub struct Ekf<M: ProcessModel> {
    pub(super) model: M,
    pub(super) x: Vec<f64>,
    pub(super) p: Mat<f64>,
    /// J_m and y − h(x⁻) of the last correction.
    pub(super) jm: Mat<f64>,
    pub(super) innovation: Vec<f64>,
    /// Steps predicted so far.
    pub(super) step: usize,
    update: Update,
}

/// Buffers of the correction: h(x⁻) (m); U = P J_mᵀ, 𝒦, W = 𝒦 S_y / 2 − U (N × m);
/// S_y = J_m U + R and its factor (m × m); the Cholesky workspace.
struct Update {
    predicted: Vec<f64>,
    pht: Mat<f64>,
    gain: Mat<f64>,
    w: Mat<f64>,
    sy: Mat<f64>,
    sy_factor: Mat<f64>,
    mem: MemBuffer,
}

impl<M: ProcessModel> Ekf<M> {
    /// A filter at step 0 with the estimate `x` and covariance `p` of `model`'s state.
    pub fn new(model: M, x: Vec<f64>, p: Mat<f64>) -> Self {
        let (big_n, m) = (model.size(), model.measurement_noise().len());
        Ekf {
            update: Update {
                predicted: vec![0.0; m],
                pht: Mat::zeros(big_n, m),
                gain: Mat::zeros(big_n, m),
                w: Mat::zeros(big_n, m),
                sy: Mat::zeros(m, m),
                sy_factor: Mat::zeros(m, m),
                mem: MemBuffer::new(cholesky_in_place_scratch::<f64>(
                    m,
                    Par::Seq,
                    Default::default(),
                )),
            },
            model,
            x,
            p,
            jm: Mat::zeros(m, big_n),
            innovation: vec![0.0; m],
            step: 0,
        }
    }

    /// The prediction half of a step (eq. 8.22–8.24).
    #[inline(always)]
    pub fn predict(&mut self, input: &M::Input) -> Result<(), FilterError> {
        self.model.check_input(input)?;
        self.step += 1;
        self.model
            .predict(self.step, input, &mut self.x, &mut self.p)
    }

    /// The correction half of a step (eq. 8.25–8.28) with the measurements `y`, then the
    /// model's linearization at x⁺ with `input`.
    pub fn correct(&mut self, input: &M::Input, y: &[f64]) -> Result<(), FilterError> {
        let m = self.innovation.len();
        if y.len() != m {
            return Err(FilterError::Shape {
                what: "measurements",
                expected: m,
                got: y.len(),
            });
        }
        self.model.check_input(input)?;
        let sc = &mut self.update;
        self.model.measure(&self.x, &mut sc.predicted, &mut self.jm);
        self.innovation
            .iter_mut()
            .zip(y.iter().zip(&sc.predicted))
            .for_each(|(e, (y, h))| *e = y - h);
        // U = P J_mᵀ: columns of P combined by the nonzero entries of J_m's rows
        let ((p, ps), (jm, js)) = (storage(&self.p), storage(&self.jm));
        let big_n = self.p.nrows();
        vectorized(
            #[inline(always)]
            || {
                let (u, us) = storage_mut(&mut sc.pht);
                u.fill(0.0);
                for c in 0..big_n {
                    let column = &p[c * ps..c * ps + big_n];
                    for k in 0..m {
                        let a = jm[k + c * js];
                        if a != 0.0 {
                            axpy(&mut u[k * us..k * us + big_n], a, column);
                        }
                    }
                }
            },
        );
        matmul(
            sc.sy.as_mut(),
            Accum::Replace,
            self.jm.as_ref(),
            sc.pht.as_ref(),
            1.0,
            Par::Seq,
        );
        for (i, r) in self.model.measurement_noise().iter().enumerate() {
            sc.sy[(i, i)] += r;
        }
        sc.sy_factor.copy_from(&sc.sy);
        if !factor_in_place(sc.sy_factor.as_mut(), MemStack::new(&mut sc.mem)) {
            return Err(FilterError::Innovation { step: self.step });
        }
        // 𝒦ᵀ = S_y⁻¹ Uᵀ, solved on the transposed view of 𝒦 (N × m)
        sc.gain.copy_from(&sc.pht);
        solve_seq(sc.sy_factor.as_ref(), sc.gain.as_mut().transpose_mut());
        for &i in self.model.frozen() {
            for j in 0..m {
                sc.gain[(i, j)] = 0.0;
            }
        }
        for (j, e) in self.innovation.iter().enumerate() {
            axpy(&mut self.x, *e, sc.gain.col_as_slice(j));
        }
        // Joseph form (eq. 8.28) L P Lᵀ + 𝒦 R 𝒦ᵀ = P − 𝒦 Uᵀ − U 𝒦ᵀ + 𝒦 S_y 𝒦ᵀ = P + 𝒦 Wᵀ + W 𝒦ᵀ
        // with W = 𝒦 S_y / 2 − U, column by column; entry (i, j) adds 𝒦_ik W_jk + W_ik 𝒦_jk per k,
        // the same two products as entry (j, i): P stays exactly symmetric.
        matmul(
            sc.w.as_mut(),
            Accum::Replace,
            sc.gain.as_ref(),
            sc.sy.as_ref(),
            0.5,
            Par::Seq,
        );
        sc.w -= &sc.pht;
        let big_n = self.p.nrows();
        let ((gain, gs), (w, ws)) = (storage(&sc.gain), storage(&sc.w));
        let (p, ps) = storage_mut(&mut self.p);
        vectorized(
            #[inline(always)]
            || {
                // up to three sensors per pass over the column (one load and store of P per group):
                // the same sums in the same order as one pass per sensor
                let (gain_of, w_of) = (
                    |k: usize| &gain[k * gs..k * gs + big_n],
                    |k: usize| &w[k * ws..k * ws + big_n],
                );
                for j in 0..big_n {
                    let col = &mut p[j * ps..j * ps + big_n];
                    let mut k = 0;
                    while m - k >= 3 {
                        joseph_pass(
                            col,
                            j,
                            [0, 1, 2].map(|s| gain_of(k + s)),
                            [0, 1, 2].map(|s| w_of(k + s)),
                        );
                        k += 3;
                    }
                    match m - k {
                        2 => joseph_pass(
                            col,
                            j,
                            [gain_of(k), gain_of(k + 1)],
                            [w_of(k), w_of(k + 1)],
                        ),
                        1 => joseph_pass(col, j, [gain_of(k)], [w_of(k)]),
                        _ => {}
                    }
                }
            },
        );
        if !self.x.iter().all(|v| v.is_finite()) {
            return Err(FilterError::NonFinite { step: self.step });
        }
        self.model
            .corrected(self.step, input, &mut self.x, &mut self.p)
    }
}

/// Column j of the Joseph update (eq. 8.28) for K sensors: col += Σ_s 𝒦_s W_s[j] + W_s 𝒦_s[j],
/// added sensor by sensor (`gain` = 𝒦 and `w` = W columns, each as long as `col`).
#[inline(always)]
fn joseph_pass<const K: usize>(col: &mut [f64], j: usize, gain: [&[f64]; K], w: [&[f64]; K]) {
    let len = col.len();
    let (gain, w) = (gain.map(|g| &g[..len]), w.map(|w| &w[..len]));
    let (a, b): ([f64; K], [f64; K]) = (w.map(|w| w[j]), gain.map(|g| g[j]));
    for i in 0..len {
        let mut v = col[i];
        for s in 0..K {
            v += gain[s][i] * a[s] + w[s][i] * b[s];
        }
        col[i] = v;
    }
}

#[cfg(test)]
mod tests {
    //! The correction against the textbook Kalman update written out here with plain loops
    //! (gain 𝒦 = P Hᵀ (H P Hᵀ + R)⁻¹ by Gauss–Jordan, Joseph form (I − 𝒦H) P (I − 𝒦H)ᵀ + 𝒦 R 𝒦ᵀ),
    //! on a linear model whose prediction is x ← F x + b, P ← F P Fᵀ + Q.
    use super::*;

    type Dense = Vec<Vec<f64>>;

    fn product(a: &Dense, b: &Dense) -> Dense {
        let (n, k, m) = (a.len(), b.len(), b[0].len());
        (0..n)
            .map(|i| {
                (0..m)
                    .map(|j| (0..k).map(|l| a[i][l] * b[l][j]).sum())
                    .collect()
            })
            .collect()
    }

    fn transpose(a: &Dense) -> Dense {
        (0..a[0].len())
            .map(|j| a.iter().map(|row| row[j]).collect())
            .collect()
    }

    fn inverse(a: &Dense) -> Dense {
        let n = a.len();
        let mut aug: Dense = a
            .iter()
            .enumerate()
            .map(|(i, row)| {
                let mut r = row.clone();
                r.extend((0..n).map(|j| if i == j { 1.0 } else { 0.0 }));
                r
            })
            .collect();
        for c in 0..n {
            let pivot = (c..n)
                .max_by(|&i, &j| aug[i][c].abs().total_cmp(&aug[j][c].abs()))
                .unwrap();
            aug.swap(c, pivot);
            let d = aug[c][c];
            aug[c].iter_mut().for_each(|v| *v /= d);
            for i in (0..n).filter(|&i| i != c) {
                let f = aug[i][c];
                let row_c = aug[c].clone();
                aug[i].iter_mut().zip(&row_c).for_each(|(v, r)| *v -= f * r);
            }
        }
        aug.into_iter().map(|r| r[n..].to_vec()).collect()
    }

    /// x ← F x + b, P ← F P Fᵀ + diag(q); y = H x + noise of variances r.
    #[derive(Clone)]
    struct Linear {
        f: Dense,
        b: Vec<f64>,
        q: Vec<f64>,
        h: Dense,
        r: Vec<f64>,
        frozen: Vec<usize>,
        /// ('p' | 'c', step) of every call, in order.
        calls: Vec<(char, usize)>,
    }

    impl Linear {
        fn new(m: usize) -> Self {
            let n = 4;
            let f = (0..n)
                .map(|i| {
                    (0..n)
                        .map(|j| match (i, j) {
                            _ if i == j => 0.97 - 0.01 * i as f64,
                            _ if j == i + 1 => 0.1,
                            _ if i == j + 2 => -0.05,
                            _ => 0.0,
                        })
                        .collect()
                })
                .collect();
            let h = (0..m)
                .map(|k| {
                    (0..n)
                        .map(|j| (((k + 1) * (j + 2)) % 5) as f64 - 1.5)
                        .collect()
                })
                .collect();
            Linear {
                f,
                b: vec![0.01, -0.02, 0.03, 0.0],
                q: vec![1e-3, 2e-3, 5e-4, 1e-4],
                h,
                r: (0..m).map(|k| 1e-2 * (1.0 + k as f64)).collect(),
                frozen: vec![],
                calls: vec![],
            }
        }

        fn dense(p: &Mat<f64>) -> Dense {
            (0..p.nrows())
                .map(|i| (0..p.ncols()).map(|j| p[(i, j)]).collect())
                .collect()
        }

        /// The textbook step: prediction, then the correction with the gain's frozen rows zeroed.
        fn reference(&self, x: &mut Vec<f64>, p: &mut Dense, y: &[f64]) {
            let xp: Vec<f64> = (0..x.len())
                .map(|i| (0..x.len()).map(|j| self.f[i][j] * x[j]).sum::<f64>() + self.b[i])
                .collect();
            let mut pp = product(&product(&self.f, p), &transpose(&self.f));
            (0..x.len()).for_each(|i| pp[i][i] += self.q[i]);
            let pp: Dense = (0..x.len())
                .map(|i| (0..x.len()).map(|j| 0.5 * (pp[i][j] + pp[j][i])).collect())
                .collect();
            let ht = transpose(&self.h);
            let mut s = product(&product(&self.h, &pp), &ht);
            (0..y.len()).for_each(|k| s[k][k] += self.r[k]);
            let mut gain = product(&product(&pp, &ht), &inverse(&s));
            for &i in &self.frozen {
                gain[i].iter_mut().for_each(|g| *g = 0.0);
            }
            let hx: Vec<f64> = self
                .h
                .iter()
                .map(|row| row.iter().zip(&xp).map(|(a, b)| a * b).sum())
                .collect();
            *x = (0..x.len())
                .map(|i| {
                    xp[i]
                        + (0..y.len())
                            .map(|k| gain[i][k] * (y[k] - hx[k]))
                            .sum::<f64>()
                })
                .collect();
            let n = x.len();
            let l: Dense = (0..n)
                .map(|i| {
                    (0..n)
                        .map(|j| {
                            let kh: f64 = (0..y.len()).map(|k| gain[i][k] * self.h[k][j]).sum();
                            if i == j { 1.0 - kh } else { -kh }
                        })
                        .collect()
                })
                .collect();
            let r: Dense = (0..y.len())
                .map(|i| {
                    (0..y.len())
                        .map(|j| if i == j { self.r[i] } else { 0.0 })
                        .collect()
                })
                .collect();
            let lpl = product(&product(&l, &pp), &transpose(&l));
            let krk = product(&product(&gain, &r), &transpose(&gain));
            *p = (0..n)
                .map(|i| (0..n).map(|j| lpl[i][j] + krk[i][j]).collect())
                .collect();
        }
    }

    impl ProcessModel for Linear {
        type Input = ();
        fn size(&self) -> usize {
            self.f.len()
        }
        fn measurement_noise(&self) -> &[f64] {
            &self.r
        }
        fn check_input(&self, _: &()) -> Result<(), FilterError> {
            Ok(())
        }
        fn predict(
            &mut self,
            step: usize,
            _: &(),
            x: &mut [f64],
            p: &mut Mat<f64>,
        ) -> Result<(), FilterError> {
            self.calls.push(('p', step));
            let n = x.len();
            let xp: Vec<f64> = (0..n)
                .map(|i| (0..n).map(|j| self.f[i][j] * x[j]).sum::<f64>() + self.b[i])
                .collect();
            x.copy_from_slice(&xp);
            let mut pp = product(&product(&self.f, &Self::dense(p)), &transpose(&self.f));
            (0..n).for_each(|i| pp[i][i] += self.q[i]);
            // symmetrized, so that the correction's exact symmetry can be asserted
            *p = Mat::from_fn(n, n, |i, j| 0.5 * (pp[i][j] + pp[j][i]));
            Ok(())
        }
        fn measure(&mut self, x: &[f64], predicted: &mut [f64], jm: &mut Mat<f64>) {
            for (k, row) in self.h.iter().enumerate() {
                predicted[k] = row.iter().zip(x).map(|(a, b)| a * b).sum();
                row.iter().enumerate().for_each(|(j, v)| jm[(k, j)] = *v);
            }
        }
        fn frozen(&self) -> &[usize] {
            &self.frozen
        }
        fn corrected(
            &mut self,
            step: usize,
            _: &(),
            _: &mut [f64],
            _: &mut Mat<f64>,
        ) -> Result<(), FilterError> {
            self.calls.push(('c', step));
            Ok(())
        }
    }

    fn measurements(m: usize, step: usize) -> Vec<f64> {
        (0..m).map(|k| (0.3 * (k + step) as f64).sin()).collect()
    }

    fn start() -> (Vec<f64>, Dense) {
        let x = vec![0.5, -0.2, 0.1, 0.3];
        let p = (0..4)
            .map(|i| {
                (0..4)
                    .map(|j| if i == j { 0.2 + 0.1 * i as f64 } else { 0.02 })
                    .collect()
            })
            .collect();
        (x, p)
    }

    /// Runs three steps of the filter and of the reference; the largest difference of x and P.
    fn compare(model: Linear) -> f64 {
        let m = model.r.len();
        let (mut x_ref, mut p_ref) = start();
        let p0 = Mat::from_fn(4, 4, |i, j| p_ref[i][j]);
        let reference = model.clone();
        let mut ekf = Ekf::new(model, x_ref.clone(), p0);
        let mut worst = 0.0f64;
        for step in 1..=3 {
            let y = measurements(m, step);
            ekf.predict(&()).unwrap();
            ekf.correct(&(), &y).unwrap();
            reference.reference(&mut x_ref, &mut p_ref, &y);
            for (i, row) in p_ref.iter().enumerate() {
                worst = worst.max((ekf.x[i] - x_ref[i]).abs());
                for (j, reference) in row.iter().enumerate() {
                    worst = worst.max((ekf.p[(i, j)] - reference).abs());
                    assert_eq!(ekf.p[(i, j)], ekf.p[(j, i)], "P stays exactly symmetric");
                }
            }
        }
        worst
    }

    #[test]
    fn correction_matches_the_textbook_joseph_update_for_every_sensor_grouping() {
        // one to seven sensors: the Joseph pass groups them by three (3, 3 + 1, 3 + 2, 3 + 3 + 1);
        // x and P are O(1): round-off of a few dozen operations is ~1e-15
        for m in 1..=7 {
            let worst = compare(Linear::new(m));
            assert!(worst < 1e-12, "{m} sensors: largest difference {worst:e}");
        }
    }

    #[test]
    fn frozen_entries_take_no_correction_and_p_follows_that_gain() {
        let mut model = Linear::new(3);
        model.frozen = vec![1, 3];
        let worst = compare(model);
        assert!(worst < 1e-12, "largest difference {worst:e}");
        // and the frozen entries keep their predicted values
        let mut model = Linear::new(3);
        model.frozen = vec![2];
        let (x, p) = start();
        let mut ekf = Ekf::new(model, x, Mat::from_fn(4, 4, |i, j| p[i][j]));
        ekf.predict(&()).unwrap();
        let predicted = ekf.x[2];
        ekf.correct(&(), &measurements(3, 1)).unwrap();
        assert_eq!(ekf.x[2], predicted);
    }

    #[test]
    fn the_model_sees_the_step_number_of_each_prediction_and_correction() {
        let (x, p) = start();
        let mut ekf = Ekf::new(Linear::new(2), x, Mat::from_fn(4, 4, |i, j| p[i][j]));
        for step in 1..=3 {
            ekf.predict(&()).unwrap();
            ekf.correct(&(), &measurements(2, step)).unwrap();
        }
        let expected: Vec<(char, usize)> = (1..=3).flat_map(|s| [('p', s), ('c', s)]).collect();
        assert_eq!(ekf.model.calls, expected);
    }

    #[test]
    fn bad_measurements_and_an_indefinite_innovation_are_refused_with_their_step() {
        let (x, p) = start();
        let p0 = Mat::from_fn(4, 4, |i, j| p[i][j]);
        let mut ekf = Ekf::new(Linear::new(2), x.clone(), p0.clone());
        ekf.predict(&()).unwrap();
        assert!(matches!(
            ekf.correct(&(), &[0.0; 3]),
            Err(FilterError::Shape {
                expected: 2,
                got: 3,
                ..
            })
        ));
        ekf.predict(&()).unwrap();
        assert!(matches!(
            ekf.correct(&(), &[f64::NAN, 0.0]),
            Err(FilterError::NonFinite { step: 2 })
        ));
        // a negative noise variance larger than H P Hᵀ: S_y is not positive definite
        let mut model = Linear::new(2);
        model.r = vec![-1e6, 1e-2];
        let mut ekf = Ekf::new(model, x, p0);
        ekf.predict(&()).unwrap();
        assert!(matches!(
            ekf.correct(&(), &[0.0, 0.0]),
            Err(FilterError::Innovation { step: 1 })
        ));
    }
}
