//! The filter's modal coordinates z (q = Φ z): the pROM's matrices as diagonals in the modes of
//! the initial estimate, plus — re-diagonalized coordinates — the couplings of [`super::drift`]
//! ([`super::filter`]'s module documentation).

use std::cell::OnceCell;

use faer::Mat;
use faer::dyn_stack::MemBuffer;

use super::coordinates::{PromCoordinates, Refused};
use super::drift::{Drift, add_coupled, solve_modal};
use super::filter::Prediction;
use super::kernels::{axpy, storage_mut};
use super::modal::ModalForm;
use super::propagation::{mirror_w_rows, propagate_column};
use crate::dynamics::velocity_form::Operator;
use crate::rom::prom::{Prom, PromError};

/// Diagonal matrices in modal coordinates z (q = Φ z).
pub(super) struct Modal {
    pub(super) form: ModalForm,
    /// Φ⁻¹ Φ⁻ᵀ: the q and q̇ blocks of Q and P₀ for a unit physical diagonal.
    pub(super) gram: Mat<f64>,
    /// diag of K, M, C, S.
    pub(super) k: Vec<f64>,
    pub(super) m: Vec<f64>,
    pub(super) c: Vec<f64>,
    pub(super) s: Vec<f64>,
    /// diag of ∂K/∂p_j, ∂M/∂p_j per estimated parameter (n × n_p).
    pub(super) dk: Mat<f64>,
    pub(super) dm: Mat<f64>,
    /// J̃_v = [diag(jk), diag(jm), jw] (jw: n × (n_un + n_p)).
    pub(super) jk: Vec<f64>,
    pub(super) jm: Vec<f64>,
    pub(super) jw: Mat<f64>,
    /// x* and q̈ in the physical coordinates, mapped on the first request after a step
    /// ([`super::filter::Filter::state`], [`super::filter::Filter::acceleration`]): a step itself never needs them.
    pub(super) physical: OnceCell<(Vec<f64>, Vec<f64>)>,
    /// h of S = M + h C + h² K and the Rayleigh α, β (for the off-diagonal parts of C and S).
    pub(super) h: f64,
    pub(super) alpha: f64,
    pub(super) beta: f64,
    /// The off-diagonal couplings (re-diagonalized coordinates only).
    pub(super) drift: Option<Drift>,
}

impl Modal {
    /// The factors (f_M, f_K) with which the off-diagonal parts of M̃ and K̃ enter `op`
    /// (C = α M + β K).
    fn off_factors(&self, op: Operator) -> (f64, f64) {
        match op {
            Operator::Stiffness => (0.0, 1.0),
            Operator::Damping => (self.alpha, self.beta),
            Operator::Mass => (1.0, 0.0),
        }
    }

    /// [`Modal::off_factors`] of S = M + h C + h² K.
    fn effective_factors(&self) -> (f64, f64) {
        (1.0 + self.h * self.alpha, self.h * (self.beta + self.h))
    }
}

impl PromCoordinates for Modal {
    /// Evaluate at `params` and factor S = M + h C + h² K and M (`first`: M was never factored).
    fn evaluate(
        &mut self,
        prom: &Prom,
        params: &[f64],
        unknown: &[usize],
        h: f64,
        _: bool,
        _: &mut MemBuffer,
    ) -> Result<(), Refused> {
        if let Some((q, &value)) = prom
            .parameters
            .iter()
            .zip(params)
            .find(|(_, v)| !v.is_finite())
        {
            return Err(Refused::Prom(
                PromError::NotFinite {
                    name: q.name.clone(),
                    value,
                }
                .to_string(),
            ));
        }
        self.k.fill(0.0);
        self.m.fill(0.0);
        self.dk.fill(0.0);
        self.dm.fill(0.0);
        for (function, kd, mdiag) in &self.form.parts {
            let f = function.map(|i| &prom.functions[i]);
            let w = f.map_or(1.0, |f| f.value(params));
            axpy(&mut self.k, w, kd);
            axpy(&mut self.m, w, mdiag);
            for (c, &j) in unknown.iter().enumerate() {
                let d = f.map_or(0.0, |f| f.derivative(params, j));
                if d != 0.0 {
                    axpy(self.dk.col_as_slice_mut(c), d, kd);
                    axpy(self.dm.col_as_slice_mut(c), d, mdiag);
                }
            }
        }
        let (alpha, beta) = (prom.alpha, prom.beta);
        for i in 0..self.k.len() {
            self.c[i] = alpha * self.m[i] + beta * self.k[i];
            self.s[i] = self.m[i] + h * self.c[i] + h * h * self.k[i];
        }
        if let Some(dr) = &mut self.drift {
            dr.current = 0.0;
            for (c, coupling) in self.form.couplings.iter().enumerate() {
                let f = &prom.functions[coupling.function];
                let w = f.value(params);
                dr.current = dr.current.max(coupling.drift(w));
                dr.weights[c] = w - coupling.reference;
                for (k, &j) in unknown.iter().enumerate() {
                    dr.derivatives[(c, k)] = f.derivative(params, j);
                }
            }
        }
        if !self.s.iter().all(|&s| s > 0.0) {
            return Err(Refused::NotDefinite(
                "the step matrix S = M + h C + h² K (h = Δt for BDF1, Δt/2 for TRAP)",
            ));
        }
        if !self.m.iter().all(|&m| m > 0.0) {
            return Err(Refused::NotDefinite("M"));
        }
        Ok(())
    }

    /// out += scale · A x (A symmetric: entries as dot products with its columns).
    fn mul(&self, op: Operator, x: &[f64], out: &mut [f64], scale: f64) {
        let d = match op {
            Operator::Stiffness => &self.k,
            Operator::Damping => &self.c,
            Operator::Mass => &self.m,
        };
        out.iter_mut()
            .zip(d.iter().zip(x))
            .for_each(|(o, (d, x))| *o += scale * d * x);
        if let Some(dr) = &self.drift {
            add_coupled(
                &self.form.couplings,
                &dr.weights,
                self.off_factors(op),
                x,
                out,
                scale,
            );
        }
    }

    /// x ← S⁻¹ x (`effective`) or M⁻¹ x.
    fn solve(&mut self, effective: bool, x: &mut [f64]) {
        let factors = if effective {
            self.effective_factors()
        } else {
            self.off_factors(Operator::Mass)
        };
        solve_modal(
            if effective { &self.s } else { &self.m },
            &self.form.couplings,
            self.drift.as_mut(),
            factors,
            x,
        );
    }

    /// D (n × n_p) from w_k = q + β q̇ and w_m = q̈ + α q̇ (see [`parameter_columns`]).
    fn parameter_columns(&self, params: &[usize], w_k: &[f64], w_m: &[f64], d: &mut Mat<f64>) {
        for c in 0..params.len() {
            let (dk, dm) = (self.dk.col_as_slice(c), self.dm.col_as_slice(c));
            let out = d.col_as_slice_mut(c);
            for i in 0..out.len() {
                out[i] = dk[i] * w_k[i] + dm[i] * w_m[i];
            }
            if let Some(dr) = &self.drift {
                for (k, coupling) in self.form.couplings.iter().enumerate() {
                    let f = dr.derivatives[(k, c)];
                    for (part, w) in [(&coupling.stiffness, w_k), (&coupling.mass, w_m)] {
                        if let (true, Some(part)) = (f != 0.0, part) {
                            part.add_product(w, out, f);
                        }
                    }
                }
            }
        }
    }

    /// J̃_v = S⁻¹ [−Δt K, V, Δt S_un, −Δt D] (eq. 8.16–8.20, 8.33; V of
    /// [`PromCoordinates::set_transition`]; its q and q̇ blocks from the diagonals).
    fn set_transition(&mut self, dt: f64, prediction: Prediction, s_un: &Mat<f64>, d: &Mat<f64>) {
        let nu = s_un.ncols();
        let h = self.h;
        for i in 0..self.s.len() {
            self.jk[i] = -dt * self.k[i] / self.s[i];
            self.jm[i] = match prediction {
                Prediction::Bdf1 => self.m[i],
                Prediction::Trapezoidal => self.m[i] - h * self.c[i] + h * h * self.k[i],
            } / self.s[i];
        }
        for j in 0..self.jw.ncols() {
            let (src, scale) = if j < nu {
                (s_un.col_as_slice(j), dt)
            } else {
                (d.col_as_slice(j - nu), -dt)
            };
            self.jw
                .col_as_slice_mut(j)
                .iter_mut()
                .zip(src.iter().zip(&self.s))
                .for_each(|(o, (v, s))| *o = scale * v / s);
        }
    }

    /// J̃_v as a dense n × N matrix.
    fn transition_rows(&self, n: usize, big_n: usize) -> Mat<f64> {
        Mat::from_fn(n, big_n, |i, j| match j {
            j if j < n => {
                if i == j {
                    self.jk[i]
                } else {
                    0.0
                }
            }
            j if j < 2 * n => {
                if i == j - n {
                    self.jm[i]
                } else {
                    0.0
                }
            }
            j => self.jw[(i, j - 2 * n)],
        })
    }
}

/// Buffers of [`Modal::propagate`]: column j of Gᵀ (N), columns j and n + j of G and column j
/// of H and of Hᵀ (n each), and G's w columns (n × (n_un + n_p)).
pub(super) struct ModalColumns {
    pub(super) gt: Vec<f64>,
    pub(super) g_q: Vec<f64>,
    pub(super) g_v: Vec<f64>,
    pub(super) h: Vec<f64>,
    pub(super) h_t: Vec<f64>,
    pub(super) g_w: Mat<f64>,
}

impl ModalColumns {
    pub(super) fn new(n: usize, big_n: usize) -> Self {
        ModalColumns {
            gt: vec![0.0; big_n],
            g_q: vec![0.0; n],
            g_v: vec![0.0; n],
            h: vec![0.0; n],
            h_t: vec![0.0; n],
            g_w: Mat::zeros(n, big_n - 2 * n),
        }
    }
}

impl Modal {
    /// P ← J P Jᵀ + the q and q̇ blocks of Q (eq. 8.24) in modal coordinates (J_v is J̃_v and b
    /// the weight of q̇_k in q_k, [`super::propagation`]), one column pair at a time without
    /// forming G or H: J_v = [diag(jk), diag(jm), jw] is diagonal in its q and q̇ blocks, so column j of Gᵀ = P J_vᵀ combines columns j, n + j and the w columns of
    /// P, and — P being exactly symmetric — column j of G = J_v P (row j of Gᵀ) combines
    /// three rows of P's column j, as does column n + j of G from P's column n + j; column j of
    /// H = J_v Gᵀ and of Hᵀ (row j of H) follow from those. Every sum is the one a transposed
    /// copy of Gᵀ and H would give (bit for bit, P symmetric), with whole-column reads only:
    /// (N + 4 n)(2 + n_un + n_p) multiply-adds per column pair (instead of
    /// (N + n)(2 + n_un + n_p) and two n × n transpositions with strided reads, which cost more
    /// on the blade). P's q and q̇ columns are rewritten in place in order: column j's old values are read before they are written,
    /// and the w columns only change at the end ([`mirror_w_rows`]).
    #[inline(always)]
    pub(super) fn propagate(
        &self,
        p: &mut Mat<f64>,
        cols: &mut ModalColumns,
        q_state: f64,
        b: f64,
    ) {
        let (n, big_n, nw) = (self.jk.len(), p.nrows(), self.jw.ncols());
        let (jk, jm, jw) = (&self.jk[..n], &self.jm[..n], &self.jw);
        for k in 0..nw {
            g_of_column(
                jk,
                jm,
                jw,
                p.col_as_slice(2 * n + k),
                cols.g_w.col_as_slice_mut(k),
            );
        }
        let (p, ps) = storage_mut(p);
        for j in 0..n {
            let (pj, pv) = (
                &p[j * ps..j * ps + big_n],
                &p[(n + j) * ps..(n + j) * ps + big_n],
            );
            let gt = &mut cols.gt[..];
            gt.iter_mut()
                .zip(pj.iter().zip(pv))
                .for_each(|(o, (z, v))| *o = jk[j] * z + jm[j] * v);
            for k in 0..nw {
                let c = jw[(j, k)];
                if c != 0.0 {
                    axpy(gt, c, &p[(2 * n + k) * ps..(2 * n + k) * ps + big_n]);
                }
            }
            g_of_column(jk, jm, jw, pj, &mut cols.g_q);
            g_of_column(jk, jm, jw, pv, &mut cols.g_v);
            let (h, h_t) = (&mut cols.h[..n], &mut cols.h_t[..n]);
            h.iter_mut()
                .zip(jk.iter().zip(jm).zip(gt[..n].iter().zip(&gt[n..2 * n])))
                .for_each(|(o, ((a, b), (z, v)))| *o = a * z + b * v);
            h_t.iter_mut()
                .zip(cols.g_q.iter().zip(&cols.g_v))
                .for_each(|(o, (z, v))| *o = jk[j] * z + jm[j] * v);
            for k in 0..nw {
                let x = gt[2 * n + k];
                if x != 0.0 {
                    axpy(h, x, jw.col_as_slice(k));
                }
                let c = jw[(j, k)];
                h_t.iter_mut()
                    .zip(cols.g_w.col_as_slice(k))
                    .for_each(|(o, g)| *o += g * c);
            }
            h.iter_mut()
                .zip(h_t.iter())
                .for_each(|(h, h_t)| *h = 0.5 * (*h + h_t));
            propagate_column(
                p,
                ps,
                (n, j),
                &cols.gt,
                &cols.g_q,
                &cols.h,
                Some((self.gram.col_as_slice(j), q_state)),
                b,
            );
        }
        mirror_w_rows(p, ps, n, big_n);
    }
}

/// J_v x (n) for a column x of P (N): jk ∘ x_q + jm ∘ x_q̇ + Σ_k jw_k x_{2n+k}, entry i summed
/// as entry (row of x, i) of Gᵀ = P J_vᵀ ([`Modal::propagate`]).
#[inline(always)]
fn g_of_column(jk: &[f64], jm: &[f64], jw: &Mat<f64>, x: &[f64], out: &mut [f64]) {
    let n = jk.len();
    out.iter_mut()
        .zip(jk.iter().zip(jm).zip(x[..n].iter().zip(&x[n..2 * n])))
        .for_each(|(o, ((a, b), (z, v)))| *o = a * z + b * v);
    for (k, &s) in x[2 * n..].iter().enumerate() {
        out.iter_mut()
            .zip(jw.col_as_slice(k))
            .for_each(|(o, c)| *o += c * s);
    }
}
