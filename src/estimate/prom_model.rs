//! The pROM's augmented process model (thesis §8.2–8.3): the [`ProcessModel`] of
//! [`super::filter::Filter`], in the coordinates of [`super::coordinates`]. Prediction by BDF1
//! or the trapezoidal rule in velocity form ([`crate::dynamics::velocity_form`], eq. 8.22), its
//! Jacobian's q̇ block row J_v (eq. 8.16–8.20, 8.33), P ← J P Jᵀ + Q by blocks
//! ([`super::propagation`], eq. 8.24), the
//! measurement rows (eq. 8.37–8.39), and after each correction the pROM at p⁺ (eq. 3.32) with
//! S and M factored, re-diagonalized modes when the estimate has drifted ([`super::drift`]).

use std::cell::OnceCell;

use faer::dyn_stack::MemBuffer;
use faer::linalg::cholesky::llt::factor::cholesky_in_place_scratch;
use faer::linalg::matmul::matmul;
use faer::{Accum, Mat, MatRef, Par};

use super::coordinates::{Model, PromCoordinates, Refused};
use super::drift::{Drift, gram};
use super::ekf::ProcessModel;
use super::filter::{Coordinates, FilterError, FilterSetup, Prediction, check_initial_stiffness};
use super::kernels::{axpy, column, dot, vectorized};
use super::measurement::Reads;
use super::modal::{modal_form, modal_form_after};
use super::modal_coordinates::{Modal, ModalColumns};
use super::physical::Physical;
use super::propagation::{propagate, shear};
use crate::card_values::valid_rediagonalization_tolerance;
use crate::dynamics::velocity_form::{Operator, bdf1_step, trapezoidal_step};
use crate::linalg::dense::product;

/// The pROM, its evaluation at the current estimate and the buffers of a step.
pub(super) struct PromModel {
    /// The setup with S_un and the sensor rows in the filter's coordinates.
    pub(super) setup: FilterSetup,
    pub(super) n: usize,
    nu: usize,
    np: usize,
    /// q̈ at x* (prior after the prediction, posterior after the correction).
    pub(super) a: Vec<f64>,
    /// Values of every pROM parameter at the current estimate.
    pub(super) params: Vec<f64>,
    pub(super) model: Model,
    /// J_v is up to date (kept between steps when no parameter is estimated).
    jv_valid: bool,
    /// Gᵀ = P J_vᵀ (N × n) and H = J_v P J_vᵀ (n × n) of the covariance prediction.
    gt: Mat<f64>,
    h: Mat<f64>,
    scratch: Scratch,
}

/// Buffers of one step (sizes fixed by n, N, n_p).
struct Scratch {
    /// Known load in the filter's coordinates, reduced force, q̇ before the step, q + β q̇ and
    /// q̈ + α q̇, right-hand side and scratch of the step, M⁻¹ h of an ACCEL row and a product
    /// with it (n each).
    load: Vec<f64>,
    /// The modes (re-diagonalization count) and the physical load that `load` was made from
    /// (modal coordinates: the correction reuses the prediction's Φᵀ f; NaN: none yet).
    load_of: (usize, Vec<f64>),
    force: Vec<f64>,
    v_old: Vec<f64>,
    w_k: Vec<f64>,
    w_m: Vec<f64>,
    rhs: Vec<f64>,
    work: Vec<f64>,
    g: Vec<f64>,
    t: Vec<f64>,
    /// D (n × n_p).
    d: Mat<f64>,
    /// The transposed q block of Gᵀ and H̄ (n × 2n) for [`propagate`].
    mirror: Mat<f64>,
    /// The columns of [`Modal::propagate`].
    columns: ModalColumns,
    /// Workspace of the in-place Cholesky factorizations.
    mem: MemBuffer,
}

impl PromModel {
    /// Check the setup and prepare step 0: the model, x*₀ and P₀ in its coordinates.
    pub(super) fn new(mut setup: FilterSetup) -> Result<(Self, Vec<f64>, Mat<f64>), FilterError> {
        let n = setup.prom.size();
        let (nu, np, m) = (
            setup.s_un.ncols(),
            setup.unknown_params.len(),
            setup.measured.len(),
        );
        for (what, expected, got) in [
            ("S_un rows", n, setup.s_un.nrows()),
            (
                "parameter values",
                setup.prom.parameters.len(),
                setup.p.len(),
            ),
            ("noise variances", m, setup.r.len()),
            ("sensor row length", n, setup.measured.h.ncols()),
            ("input noise variances", nu, setup.q_inputs.len()),
            ("parameter noise variances", np, setup.q_params.len()),
            ("initial q", n, setup.q0.len()),
            ("initial q̇", n, setup.v0.len()),
            ("initial inputs", nu, setup.u0.len()),
            ("initial input variances", nu, setup.p0_inputs.len()),
            ("initial parameter variances", np, setup.p0_params.len()),
        ] {
            if expected != got {
                return Err(FilterError::Shape {
                    what,
                    expected,
                    got,
                });
            }
        }
        let mut at = setup.prom.workspace();
        setup
            .prom
            .evaluate(&setup.p, &mut at)
            .map_err(|e| FilterError::Prom(e.to_string()))?;
        check_initial_stiffness(at.stiffness(), &setup.p)?;
        let big_n = 2 * n + nu + np;
        let mut x = vec![0.0; big_n];
        x[..n].copy_from_slice(&setup.q0);
        x[n..2 * n].copy_from_slice(&setup.v0);
        x[2 * n..2 * n + nu].copy_from_slice(&setup.u0);
        for (k, &j) in setup.unknown_params.iter().enumerate() {
            x[2 * n + nu + k] = setup.p[j];
        }
        let diag: Vec<f64> = std::iter::repeat_n(setup.p0_state, 2 * n)
            .chain(setup.p0_inputs.iter().copied())
            .chain(setup.p0_params.iter().copied())
            .collect();
        let mut p = Mat::from_fn(big_n, big_n, |i, j| if i == j { diag[i] } else { 0.0 });
        let form = match setup.coordinates {
            Coordinates::Auto => modal_form(&setup.prom, &setup.p, &setup.unknown_params, false),
            Coordinates::Rediagonalized(tolerance)
                if !valid_rediagonalization_tolerance(tolerance) =>
            {
                return Err(FilterError::Tolerance(tolerance));
            }
            Coordinates::Rediagonalized(_) => {
                modal_form(&setup.prom, &setup.p, &setup.unknown_params, true)
            }
            Coordinates::Physical => None,
        };
        let model = match form {
            None => Model::Physical(Physical {
                at: setup.prom.workspace(),
                s_factor: Mat::zeros(n, n),
                m_factor: Mat::zeros(n, n),
                factored_mass: Mat::zeros(n, n),
                jv: Mat::zeros(n, big_n),
            }),
            Some(form) => {
                let drift = match setup.coordinates {
                    Coordinates::Rediagonalized(tolerance) if !form.couplings.is_empty() => Some(
                        Drift::new(&form, tolerance, np, &setup.s_un, &setup.measured.h),
                    ),
                    _ => None,
                };
                // z₀ = Φ⁻¹ q₀, P₀ and (per step) Q: the q and q̇ blocks times Φ⁻¹ Φ⁻ᵀ
                setup.s_un = form.basis.transpose() * &setup.s_un;
                setup.measured.h = &setup.measured.h * &form.basis;
                for block in [0..n, n..2 * n] {
                    let z =
                        &form.inverse * MatRef::from_column_major_slice(&x[block.clone()], n, 1);
                    x[block]
                        .iter_mut()
                        .enumerate()
                        .for_each(|(i, x)| *x = z[(i, 0)]);
                }
                let gram = gram(&form.inverse);
                for b in [0, n] {
                    p.as_mut()
                        .submatrix_mut(b, b, n, n)
                        .copy_from(&gram * faer::Scale(setup.p0_state));
                }
                Model::Modal(Box::new(Modal {
                    form,
                    gram,
                    k: vec![0.0; n],
                    m: vec![0.0; n],
                    c: vec![0.0; n],
                    s: vec![0.0; n],
                    dk: Mat::zeros(n, np),
                    dm: Mat::zeros(n, np),
                    jk: vec![0.0; n],
                    jm: vec![0.0; n],
                    jw: Mat::zeros(n, nu + np),
                    physical: OnceCell::new(),
                    h: setup.prediction.effective_step(setup.dt),
                    alpha: setup.prom.alpha,
                    beta: setup.prom.beta,
                    drift,
                }))
            }
        };
        let params = setup.p.clone();
        let scratch = Scratch {
            load: vec![0.0; n],
            load_of: (0, vec![f64::NAN; n]),
            force: vec![0.0; n],
            v_old: vec![0.0; n],
            w_k: vec![0.0; n],
            w_m: vec![0.0; n],
            rhs: vec![0.0; n],
            work: vec![0.0; n],
            g: vec![0.0; n],
            t: vec![0.0; n],
            d: Mat::zeros(n, np),
            mirror: Mat::zeros(n, 2 * n),
            columns: ModalColumns::new(n, big_n),
            mem: MemBuffer::new(cholesky_in_place_scratch::<f64>(
                n,
                Par::Seq,
                Default::default(),
            )),
        };
        let mut model = PromModel {
            n,
            nu,
            np,
            a: vec![0.0; n],
            params,
            model,
            jv_valid: false,
            gt: Mat::zeros(big_n, n),
            h: Mat::zeros(n, n),
            scratch,
            setup,
        };
        model.refresh(0, &mut x, &mut p)?;
        model.set_acceleration(&x);
        Ok((model, x, p))
    }

    /// Evaluate the pROM at the estimated parameters and factor S and M (the callers set q̈ from
    /// the equation of motion; with zero known load before the first step).
    pub(super) fn refresh(
        &mut self,
        step: usize,
        x: &mut [f64],
        p: &mut Mat<f64>,
    ) -> Result<(), FilterError> {
        let (n, nu) = (self.n, self.nu);
        for (k, &j) in self.setup.unknown_params.iter().enumerate() {
            self.params[j] = x[2 * n + nu + k];
        }
        if step > 0 && self.np == 0 {
            return Ok(());
        }
        self.evaluate(step)?;
        let drifted = match &self.model {
            Model::Modal(md) => md
                .drift
                .as_ref()
                .is_some_and(|dr| dr.stalled || dr.current > dr.tolerance),
            Model::Physical(_) => false,
        };
        if drifted {
            self.rediagonalize(step, x, p)?;
            self.evaluate(step)?;
        }
        Ok(())
    }

    /// [`PromCoordinates::evaluate`] at the current parameters.
    fn evaluate(&mut self, step: usize) -> Result<(), FilterError> {
        let s = &self.setup;
        match self.model.evaluate(
            &s.prom,
            &self.params,
            &s.unknown_params,
            s.prediction.effective_step(s.dt),
            step == 0,
            &mut self.scratch.mem,
        ) {
            Ok(()) => {
                self.jv_valid = false;
                Ok(())
            }
            Err(Refused::Prom(e)) => Err(FilterError::Prom(e)),
            Err(Refused::NotDefinite(what)) => Err(FilterError::NotDefinite {
                step,
                what,
                params: self.params.clone(),
            }),
        }
    }

    /// Move re-diagonalized coordinates to the modes Φ₂ at the current parameters: z₂ = R z₁
    /// with R = Φ₂⁻¹ Φ₁ on the q and q̇ blocks of x* and P (P ↦ T P Tᵀ, T = diag(R, R, I, I)),
    /// S_un, the sensor rows and Q's blocks transformed from the physical ones. N³, rare: only
    /// when the estimate has drifted by the tolerance (module documentation).
    fn rediagonalize(
        &mut self,
        step: usize,
        x: &mut [f64],
        p: &mut Mat<f64>,
    ) -> Result<(), FilterError> {
        let (n, big_n) = (self.n, x.len());
        let Model::Modal(md) = &mut self.model else {
            return Ok(());
        };
        let Some(dr) = md.drift.as_mut() else {
            return Ok(());
        };
        let s = &mut self.setup;
        let form = modal_form_after(&s.prom, &self.params, &s.unknown_params, &md.form)
            .ok_or_else(|| {
                FilterError::Prom(format!(
                    "at step {}: no modes of the pROM at parameters {:?} (re-diagonalization)",
                    step, self.params
                ))
            })?;
        let r = product(form.inverse.as_ref(), md.form.basis.as_ref());
        for start in [0, n] {
            let z = product(
                r.as_ref(),
                MatRef::from_column_major_slice(&x[start..start + n], n, 1),
            );
            x[start..start + n].copy_from_slice(z.col_as_slice(0));
        }
        // T P Tᵀ by blocks: the q and q̇ rows of P times R, then those columns times Rᵀ
        let mut rows = p.clone();
        for start in [0, n] {
            matmul(
                rows.as_mut().subrows_mut(start, n),
                Accum::Replace,
                r.as_ref(),
                p.as_ref().subrows(start, n),
                1.0,
                Par::Seq,
            );
        }
        p.copy_from(&rows);
        for start in [0, n] {
            matmul(
                p.as_mut().subcols_mut(start, n),
                Accum::Replace,
                rows.as_ref().subcols(start, n),
                r.transpose(),
                1.0,
                Par::Seq,
            );
        }
        for j in 0..big_n {
            for i in 0..j {
                let mean = 0.5 * (p[(i, j)] + p[(j, i)]);
                (p[(i, j)], p[(j, i)]) = (mean, mean);
            }
        }
        s.s_un = product(form.basis.transpose(), dr.s_un.as_ref());
        s.measured.h = product(dr.h.as_ref(), form.basis.as_ref());
        md.gram = gram(&form.inverse);
        *dr = Drift {
            count: dr.count + 1,
            ..Drift::new(&form, dr.tolerance, self.np, &dr.s_un, &dr.h)
        };
        md.form = form;
        Ok(())
    }

    /// The known load in the filter's coordinates (Φᵀ f in modal ones) into `scratch.load`.
    pub(super) fn set_load(&mut self, f_kn: &[f64]) {
        let (load, load_of) = (&mut self.scratch.load, &mut self.scratch.load_of);
        match &self.model {
            Model::Physical(_) => load.copy_from_slice(f_kn),
            Model::Modal(md) => {
                let modes = md.drift.as_ref().map_or(0, |dr| dr.count);
                if load_of.0 == modes && load_of.1 == f_kn {
                    return;
                }
                load.iter_mut()
                    .enumerate()
                    .for_each(|(c, l)| *l = dot(column(md.form.basis.as_ref(), c), f_kn));
                load_of.0 = modes;
                load_of.1.copy_from_slice(f_kn);
            }
        }
    }

    /// Reduced force S_un u + f_kn at the current estimate, into `scratch.force`.
    fn set_force(&mut self, x: &[f64]) {
        let (n, nu) = (self.n, self.nu);
        let f = &mut self.scratch.force;
        f.copy_from_slice(&self.scratch.load);
        for j in 0..nu {
            axpy(f, x[2 * n + j], self.setup.s_un.col_as_slice(j));
        }
    }

    /// q̈ = M⁻¹(f − K q − C q̇) at x with the load of `scratch.load`, into `a`.
    pub(super) fn set_acceleration(&mut self, x: &[f64]) {
        let n = self.n;
        self.set_force(x);
        let rhs = &mut self.scratch.rhs;
        rhs.copy_from_slice(&self.scratch.force);
        self.model.mul(Operator::Stiffness, &x[..n], rhs, -1.0);
        self.model.mul(Operator::Damping, &x[n..2 * n], rhs, -1.0);
        self.model.solve(false, rhs);
        self.a.copy_from_slice(rhs);
    }

    /// The physical x* and q̈ of the modal path: q = Φ z, q̇ = Φ ż, q̈ = Φ z̈.
    pub(super) fn physical(&self, md: &Modal, x: &[f64]) -> (Vec<f64>, Vec<f64>) {
        let n = self.n;
        let phi = md.form.basis.as_ref();
        let map = |z: &[f64], out: &mut [f64]| (0..n).for_each(|c| axpy(out, z[c], column(phi, c)));
        let (mut physical, mut a) = (vec![0.0; x.len()], vec![0.0; n]);
        physical[2 * n..].copy_from_slice(&x[2 * n..]);
        map(&x[..n], &mut physical[..n]);
        map(&x[n..2 * n], &mut physical[n..2 * n]);
        map(&self.a, &mut a);
        (physical, a)
    }

    /// Forget the physical x* and q̈ of the previous step (modal coordinates).
    fn unpublish(&mut self) {
        if let Model::Modal(md) = &mut self.model {
            md.physical.take();
        }
    }

    /// P += Q (eq. 8.29) but for the modal q and q̇ blocks of T⁻¹ Q T⁻ᵀ, which [`Modal::propagate`]
    /// adds.
    fn add_noise(&self, p: &mut Mat<f64>) {
        let n = self.n;
        let s = &self.setup;
        if let Model::Physical(_) = &self.model {
            (0..2 * n).for_each(|i| p[(i, i)] += s.q_state);
        }
        for (i, q) in s.q_inputs.iter().chain(&s.q_params).enumerate() {
            p[(2 * n + i, 2 * n + i)] += q;
        }
    }

    /// Diagonal of Q at augmented index i (eq. 8.29), in physical coordinates.
    #[cfg(test)]
    pub(super) fn noise(&self, i: usize) -> f64 {
        let (n, nu) = (self.n, self.nu);
        if i < 2 * n {
            self.setup.q_state
        } else if i < 2 * n + nu {
            self.setup.q_inputs[i - 2 * n]
        } else {
            self.setup.q_params[i - 2 * n - nu]
        }
    }

    /// D into `scratch.d` (see [`super::physical::parameter_columns`]) at x and q̈, or — with
    /// `midpoint`, after a trapezoidal step from q̇_{k−1} = `scratch.v_old` — at the step's
    /// mid-point (x_{k−1} + x_k)/2, (q̈_{k−1} + q̈_k)/2: q̇ = (q̇_{k−1} + q̇_k)/2,
    /// q = q_k − Δt/2 q̇ and q̈ = (q̇_k − q̇_{k−1})/Δt by the trapezoidal relations.
    fn parameter_columns(&mut self, x: &[f64], midpoint: bool) {
        let (n, dt) = (self.n, self.setup.dt);
        let (alpha, beta) = (self.setup.prom.alpha, self.setup.prom.beta);
        let sc = &mut self.scratch;
        let (q, v) = (&x[..n], &x[n..2 * n]);
        for c in 0..n {
            let (q, v, a) = if midpoint {
                let v_mid = 0.5 * (sc.v_old[c] + v[c]);
                (q[c] - 0.5 * dt * v_mid, v_mid, (v[c] - sc.v_old[c]) / dt)
            } else {
                (q[c], v[c], self.a[c])
            };
            sc.w_k[c] = q + beta * v;
            sc.w_m[c] = a + alpha * v;
        }
        self.model
            .parameter_columns(&self.setup.unknown_params, &sc.w_k, &sc.w_m, &mut sc.d);
    }

    /// Rows of J_m (eq. 8.38 for DISP/STRAIN, q̇ rows for VEL, eq. 8.39 for ACCEL with
    /// g = M⁻¹ hᵀ: [−gᵀ K, −gᵀ C, gᵀ S_un, −gᵀ D]).
    pub(super) fn measurement_rows(&mut self, x: &[f64], jm: &mut Mat<f64>) {
        let (n, nu) = (self.n, self.nu);
        jm.fill(0.0);
        let any_accel = self.setup.measured.reads.contains(&Reads::Acceleration);
        if any_accel && self.np > 0 {
            self.parameter_columns(x, false);
        }
        let rows = &self.setup.measured;
        for r in 0..rows.len() {
            match rows.reads[r] {
                Reads::Displacement => (0..n).for_each(|i| jm[(r, i)] = rows.h[(r, i)]),
                Reads::Velocity => (0..n).for_each(|i| jm[(r, n + i)] = rows.h[(r, i)]),
                Reads::Acceleration => {
                    let (g, t) = (&mut self.scratch.g, &mut self.scratch.t);
                    (0..n).for_each(|i| g[i] = rows.h[(r, i)]);
                    self.model.solve(false, g);
                    for (op, offset) in [(Operator::Stiffness, 0), (Operator::Damping, n)] {
                        t.fill(0.0);
                        self.model.mul(op, g, t, -1.0);
                        (0..n).for_each(|c| jm[(r, offset + c)] = t[c]);
                    }
                    for c in 0..nu {
                        jm[(r, 2 * n + c)] = dot(g, self.setup.s_un.col_as_slice(c));
                    }
                    for c in 0..self.np {
                        jm[(r, 2 * n + nu + c)] = -dot(g, self.scratch.d.col_as_slice(c));
                    }
                }
            }
        }
    }
}

impl ProcessModel for PromModel {
    /// The known reduced load f_kn = S_kn u_kn(t_k) of the step.
    type Input = [f64];

    fn size(&self) -> usize {
        2 * self.n + self.nu + self.np
    }

    fn measurement_noise(&self) -> &[f64] {
        &self.setup.r
    }

    fn check_input(&self, f_kn: &[f64]) -> Result<(), FilterError> {
        if f_kn.len() == self.n {
            Ok(())
        } else {
            Err(FilterError::Shape {
                what: "known load",
                expected: self.n,
                got: f_kn.len(),
            })
        }
    }

    /// The prediction (eq. 8.22–8.24): x⁻, q̈⁻, J and P⁻.
    fn predict(
        &mut self,
        _: usize,
        f_kn: &[f64],
        x: &mut [f64],
        p: &mut Mat<f64>,
    ) -> Result<(), FilterError> {
        let n = self.n;
        self.unpublish();
        let dt = self.setup.dt;
        // prediction (eq. 8.22)
        self.set_load(f_kn);
        self.set_force(x);
        let (q, w) = x.split_at_mut(n);
        let sc = &mut self.scratch;
        let prediction = self.setup.prediction;
        match prediction {
            Prediction::Bdf1 => bdf1_step(
                &mut self.model,
                dt,
                &sc.force,
                q,
                &mut w[..n],
                &mut self.a,
                &mut sc.v_old,
                &mut sc.rhs,
            ),
            Prediction::Trapezoidal => trapezoidal_step(
                &mut self.model,
                dt,
                &sc.force,
                q,
                &mut w[..n],
                &mut self.a,
                &mut sc.v_old,
                &mut sc.rhs,
                &mut sc.work,
            ),
        }
        // Jacobian block row J_v (eq. 8.16–8.20, 8.33): D of BDF1 at the predicted x_k, q̈_k
        // (g_d's q_k terms), of the trapezoidal rule at the step's mid-point
        if !self.jv_valid || self.np > 0 {
            self.parameter_columns(x, prediction == Prediction::Trapezoidal);
            self.model
                .set_transition(dt, prediction, &self.setup.s_un, &self.scratch.d);
            self.jv_valid = true;
        }
        // P⁻ = J P Jᵀ + Q (eq. 8.24): P ← A P Aᵀ, then the BDF1-shaped blocks with J̃_v and b
        let (a, b) = prediction.displacement_weights(dt);
        if a != 0.0 {
            shear(p, n, a);
        }
        let sc = &mut self.scratch;
        match &self.model {
            Model::Physical(ph) => vectorized(
                #[inline(always)]
                || {
                    ph.transition_products(p, &mut self.gt, &mut self.h);
                    propagate(p, &self.gt, &self.h, &mut sc.mirror, b);
                },
            ),
            Model::Modal(md) => vectorized(
                #[inline(always)]
                || md.propagate(p, &mut sc.columns, self.setup.q_state, b),
            ),
        }
        self.add_noise(p);
        Ok(())
    }

    fn measure(&mut self, x: &[f64], predicted: &mut [f64], jm: &mut Mat<f64>) {
        let n = self.n;
        self.unpublish();
        self.measurement_rows(x, jm);
        self.setup
            .measured
            .evaluate(&x[..n], &x[n..2 * n], &self.a, predicted);
    }

    /// The pROM at p⁺ and q̈⁺ with the same known load as the prediction.
    fn corrected(
        &mut self,
        step: usize,
        f_kn: &[f64],
        x: &mut [f64],
        p: &mut Mat<f64>,
    ) -> Result<(), FilterError> {
        self.refresh(step, x, p)?;
        self.set_load(f_kn);
        self.set_acceleration(x);
        Ok(())
    }
}
