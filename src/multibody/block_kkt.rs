//! The GGL iteration matrix (eq. 2.60 discretized by eq. 2.61 or its BDF2 / generalized-α
//! siblings, [`super::integrator`]) solved body by body: the bodies are independent blocks
//! coupled only through the constraint Jacobian G = Φ_q, so after eliminating Δq with the step
//! formula the velocity-level unknowns are solved per body and only the 2m multiplier rows
//! form a dense Schur complement.
//!
//! With P = c_v K̂ + Σ λ̂ᵢ∇²Φᵢ (the q-block of the momentum rows), A₀ = M + c_v Ĉ (their
//! v-block), V = ∂(Φ_q v + Φ_t)/∂q, W the weight of the position correction
//! ([`super::correction`]) and the μ-Hessian of the first rows left out (μ vanishes with the
//! step's error), J d = r for d = (Δq, Δv, Δλ̂, Δμ) reads
//!
//! ```text
//! Δq − c_q Δv − W Gᵀ Δμ = r₁     ⇒  Δq = r₁ + c_q Δv + W Gᵀ Δμ
//! P Δq + A₀ Δv + Gᵀ Δλ̂ = r₂      ⇒  A Δv + Gᵀ Δλ̂ + P W Gᵀ Δμ = r₂ − P r₁,   A = A₀ + c_q P
//! V Δq + G Δv = r₃               ⇒  (G + c_q V) Δv + V W Gᵀ Δμ = r₃ − V r₁
//! G Δq = r₄                      ⇒  c_q G Δv + G W Gᵀ Δμ = r₄ − G r₁
//! ```
//!
//! A is block diagonal when P and A₀ are. The blocks are runs of consecutive bodies: a body
//! alone, or the bodies a force couples (a spring-damper or compliant drive between two bodies
//! joins the run from the one to the other, [`BlockKkt::applies`]), whose K̂ and Ĉ blocks
//! between them are kept; the constraint Hessians' blocks between two runs are left out (a
//! modified Newton matrix, like the omitted ∂(M(v − v̂))/∂q). When one run would span the
//! whole system the caller uses the dense matrix instead. With E = [Gᵀ, P W Gᵀ], Y = A⁻¹ E
//! (one solve per run and column) and y = (Δλ̂, Δμ),
//!
//! ```text
//! S y = [r₃ − V w − G u;  r₄ − G w],   S = [0, V W Gᵀ; 0, G W Gᵀ] − [G + c_q V; c_q G] Y,
//! u = A⁻¹ (r₂ − P r₁),   w = r₁ + c_q u,   Δv = u − Y y
//! ```
//!
//! so a factorization is one LU per run (7 + n_f rows for a body alone) and one of S (2m rows)
//! instead of one LU of the whole matrix (2n + 2m rows), and a solve reads those factors
//! instead of the whole matrix's. W is block diagonal by body, so W Gᵀ has the bodies of Gᵀ.

use super::correction::CorrectionWeight;
use super::dense_lu::DenseLu;
use super::layout::Layout;
use faer::linalg::matmul::matmul;
use faer::{Accum, Mat, MatRef, Par};
use std::ops::Range;

/// The factored block form of the GGL iteration matrix (see module docs).
pub struct BlockKkt {
    /// Each body's coordinates.
    bodies: Vec<Range<usize>>,
    /// The coordinates of each run of bodies (module docs).
    runs: Vec<Range<usize>>,
    /// LU factors of each run's A.
    blocks: Vec<DenseLu>,
    /// Each run's block of P.
    p: Vec<Mat<f64>>,
    /// Gᵀ = Φ_qᵀ and Vᵀ = ∂(Φ_q v + Φ_t)/∂qᵀ (n × m: a row of G or V is a column here).
    gt: Mat<f64>,
    vt: Mat<f64>,
    /// W Gᵀ (n × m).
    wgt: Mat<f64>,
    /// Y = A⁻¹ [Gᵀ, P W Gᵀ] (n × 2m).
    y: Mat<f64>,
    /// G Y and V Y (m × 2m).
    gy: Mat<f64>,
    vy: Mat<f64>,
    schur: DenseLu,
    /// The runs each constraint row touches (nonzero in its row of G or V): a column of
    /// Y = A⁻¹ [Gᵀ, P W Gᵀ] is zero outside them, so products with G, V and Y skip the rest.
    touched: Vec<Vec<usize>>,
    c_q: f64,
    /// Scratch: u, w (n) and the Schur right-hand side (2m).
    u: Vec<f64>,
    w: Vec<f64>,
    z: Vec<f64>,
}

impl BlockKkt {
    /// Storage for the bodies of `layout` and m constraints.
    pub fn new(layout: &Layout, m: usize) -> Self {
        let n = layout.size();
        let bodies: Vec<Range<usize>> = layout
            .slices()
            .iter()
            .map(|s| s.offset..s.offset + s.len())
            .collect();
        let mut kkt = Self {
            blocks: Vec::new(),
            p: Vec::new(),
            runs: Vec::new(),
            bodies: bodies.clone(),
            gt: Mat::zeros(n, m),
            vt: Mat::zeros(n, m),
            wgt: Mat::zeros(n, m),
            y: Mat::zeros(n, 2 * m),
            gy: Mat::zeros(m, 2 * m),
            vy: Mat::zeros(m, 2 * m),
            schur: DenseLu::new(2 * m),
            touched: vec![Vec::new(); m],
            c_q: 0.0,
            u: vec![0.0; n],
            w: vec![0.0; n],
            z: vec![0.0; 2 * m],
        };
        kkt.set_runs(bodies);
        kkt
    }

    /// Sets the runs (coordinate ranges) and sizes the storage of their blocks.
    fn set_runs(&mut self, runs: Vec<Range<usize>>) {
        self.blocks = runs.iter().map(|r| DenseLu::new(r.len())).collect();
        self.p = runs.iter().map(|r| Mat::zeros(r.len(), r.len())).collect();
        self.runs = runs;
    }

    /// Groups the bodies into the runs of the module docs for the n × n matrices (the mass
    /// matrix, K̂, Ĉ): the fewest runs of consecutive bodies outside whose diagonal blocks the
    /// matrices are zero, so that the block form is the caller's matrix (up to the constraint
    /// Hessians between runs). Whether the block form applies: more than one run, or at most one
    /// body.
    pub fn applies(&mut self, matrices: &[MatRef<'_, f64>]) -> bool {
        let count = self.bodies.len();
        // the last body each body is coupled with
        let mut reach: Vec<usize> = (0..count).collect();
        for a in matrices {
            for (b, rows) in self.bodies.iter().enumerate() {
                for (c, columns) in self.bodies.iter().enumerate() {
                    let coupled = b != c
                        && columns
                            .clone()
                            .any(|j| rows.clone().any(|i| a[(i, j)] != 0.0));
                    if coupled {
                        let (low, high) = (b.min(c), b.max(c));
                        reach[low] = reach[low].max(high);
                    }
                }
            }
        }
        let mut runs = Vec::new();
        let mut first = 0;
        let mut last = 0;
        for (b, &far) in reach.iter().enumerate() {
            if b > last {
                runs.push(self.bodies[first].start..self.bodies[last].end);
                first = b;
            }
            last = last.max(far);
        }
        if count > 0 {
            runs.push(self.bodies[first].start..self.bodies[last].end);
        }
        if runs != self.runs {
            self.set_runs(runs);
        }
        self.runs.len() > 1 || count <= 1
    }

    /// Factors the matrix of the module docs from A₀ (n × n, read on the runs' blocks), P (n × n,
    /// read on the runs' blocks), G, V (m × n), c_q and the weight W.
    pub fn factor(
        &mut self,
        a0: MatRef<'_, f64>,
        p: MatRef<'_, f64>,
        g: MatRef<'_, f64>,
        v: MatRef<'_, f64>,
        c_q: f64,
        weight: &mut CorrectionWeight,
    ) {
        let m = g.nrows();
        self.c_q = c_q;
        self.gt.copy_from(g.transpose());
        self.vt.copy_from(v.transpose());
        self.wgt.copy_from(g.transpose());
        for k in 0..m {
            weight.apply(self.wgt.col_as_slice_mut(k));
        }
        for ((run, lu), pb) in self.runs.iter().zip(&mut self.blocks).zip(&mut self.p) {
            let (o, len) = (run.start, run.len());
            pb.copy_from(p.submatrix(o, o, len, len));
            let mut a = lu.matrix_mut();
            for j in 0..len {
                for i in 0..len {
                    a[(i, j)] = a0[(o + i, o + j)] + c_q * pb[(i, j)];
                }
            }
            lu.factor();
        }
        for (k, touched) in self.touched.iter_mut().enumerate() {
            let (g, v) = (self.gt.col_as_slice(k), self.vt.col_as_slice(k));
            touched.clear();
            for (b, range) in self.runs.iter().enumerate() {
                if g[range.clone()]
                    .iter()
                    .chain(&v[range.clone()])
                    .any(|&x| x != 0.0)
                {
                    touched.push(b);
                }
            }
        }
        // Y = A⁻¹ [Gᵀ, P W Gᵀ], column by column on the bodies the row touches
        self.y.fill(0.0);
        for (k, touched) in self.touched.iter().enumerate() {
            let (row, weighted) = (self.gt.col_as_slice(k), self.wgt.col_as_slice(k));
            for &b in touched {
                let (range, lu) = (self.runs[b].clone(), &mut self.blocks[b]);
                let column = &mut self.y.col_as_slice_mut(k)[range.clone()];
                column.copy_from_slice(&row[range.clone()]);
                lu.solve(column);
                let column = &mut self.y.col_as_slice_mut(m + k)[range.clone()];
                block_mul(self.p[b].as_ref(), range.start, |j| weighted[j], column);
                lu.solve(column);
            }
        }
        matmul(
            self.gy.as_mut(),
            Accum::Replace,
            self.gt.transpose(),
            self.y.as_ref(),
            1.0,
            Par::Seq,
        );
        matmul(
            self.vy.as_mut(),
            Accum::Replace,
            self.vt.transpose(),
            self.y.as_ref(),
            1.0,
            Par::Seq,
        );
        let mut s = self.schur.matrix_mut();
        for j in 0..2 * m {
            for i in 0..m {
                s[(i, j)] = -self.gy[(i, j)] - c_q * self.vy[(i, j)];
                s[(m + i, j)] = -c_q * self.gy[(i, j)];
            }
        }
        // [V W Gᵀ; G W Gᵀ] in the Δμ columns
        matmul(
            s.as_mut().submatrix_mut(0, m, m, m),
            Accum::Add,
            self.vt.transpose(),
            self.wgt.as_ref(),
            1.0,
            Par::Seq,
        );
        matmul(
            s.as_mut().submatrix_mut(m, m, m, m),
            Accum::Add,
            self.gt.transpose(),
            self.wgt.as_ref(),
            1.0,
            Par::Seq,
        );
        self.schur.factor();
    }

    /// r = (r₁, r₂, r₃, r₄) ← (Δq, Δv, Δλ̂, Δμ) (module docs).
    pub fn solve(&mut self, r: &mut [f64]) {
        let (n, m) = (self.gt.nrows(), self.gt.ncols());
        let c_q = self.c_q;
        let (r1, rest) = r.split_at_mut(n);
        let (r2, rest) = rest.split_at_mut(n);
        let (r34, _) = rest.split_at_mut(2 * m);
        // u = A⁻¹ (r₂ − P r₁)
        self.u.copy_from_slice(r2);
        for ((range, pb), lu) in self.runs.iter().zip(&self.p).zip(&mut self.blocks) {
            let block = &mut self.u[range.clone()];
            block_mul(pb.as_ref(), range.start, |j| -r1[j], block);
            lu.solve(block);
        }
        for ((w, r), u) in self.w.iter_mut().zip(r1.iter()).zip(&self.u) {
            *w = r + c_q * u;
        }
        // (the loops below run over the touched runs' slices, one run after the other)
        for (k, touched) in self.touched.iter().enumerate() {
            let (gk, vk) = (self.gt.col_as_slice(k), self.vt.col_as_slice(k));
            let (mut z3, mut z4) = (r34[k], r34[m + k]);
            for range in touched.iter().map(|&b| self.runs[b].clone()) {
                let (w, u) = (&self.w[range.clone()], &self.u[range.clone()]);
                for ((g, v), (w, u)) in gk[range.clone()]
                    .iter()
                    .zip(&vk[range])
                    .zip(w.iter().zip(u))
                {
                    z3 -= v * w + g * u;
                    z4 -= g * w;
                }
            }
            self.z[k] = z3;
            self.z[m + k] = z4;
        }
        self.schur.solve(&mut self.z);
        // Δv = u − Y y, Δq = r₁ + c_q Δv + W Gᵀ Δμ
        r2.copy_from_slice(&self.u);
        for (j, &yj) in self.z.iter().enumerate() {
            let column = self.y.col_as_slice(j);
            for range in self.touched[j % m].iter().map(|&b| self.runs[b].clone()) {
                for (r, y) in r2[range.clone()].iter_mut().zip(&column[range]) {
                    *r -= y * yj;
                }
            }
        }
        for (r, d) in r1.iter_mut().zip(r2.iter()) {
            *r += c_q * d;
        }
        for (k, touched) in self.touched.iter().enumerate() {
            let (mu, gk) = (self.z[m + k], self.wgt.col_as_slice(k));
            for range in touched.iter().map(|&b| self.runs[b].clone()) {
                for (r, g) in r1[range.clone()].iter_mut().zip(&gk[range]) {
                    *r += g * mu;
                }
            }
        }
        r34.copy_from_slice(&self.z);
    }
}

/// out += P_b x_b for one run's block P_b, its coordinates from `offset` on (x read through
/// `x(j)` with j the system index).
fn block_mul(pb: MatRef<'_, f64>, offset: usize, x: impl Fn(usize) -> f64, out: &mut [f64]) {
    for j in 0..pb.ncols() {
        let xj = x(offset + j);
        if xj != 0.0 {
            for (o, pij) in out.iter_mut().zip(pb.col(j).iter()) {
                *o += pij * xj;
            }
        }
    }
}
