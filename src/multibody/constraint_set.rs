//! The system's constraint equations as one set: Φ(q, t), Φ_q, Φ_t, the weighted Hessian
//! Σᵢ wᵢ ∇²Φᵢ and the q-derivative of the velocity equation Φ_q v + Φ_t, each evaluated into
//! dense caller-owned storage (Φ, Φ_t and Φ_q also in one pass, [`ConstraintSet::evaluate`]);
//! rows found redundant are dropped ([`super::redundancy`]).

use super::constraint::Constraint;
use super::layout::Layout;
use super::redundancy::{RankSplit, split_rows};
use super::rotations::Rotations;
use faer::{Mat, MatMut, MatRef};
use std::ops::Range;

/// Constraints with a name each (for reports).
#[derive(Debug, Clone, Default)]
pub struct ConstraintSet {
    pub constraints: Vec<Constraint>,
    pub labels: Vec<String>,
}

impl ConstraintSet {
    /// Appends one constraint.
    pub fn push(&mut self, constraint: Constraint, label: String) {
        self.constraints.push(constraint);
        self.labels.push(label);
    }

    /// Number of rows m.
    pub fn len(&self) -> usize {
        self.constraints.len()
    }

    /// Whether there are no rows.
    pub fn is_empty(&self) -> bool {
        self.constraints.is_empty()
    }

    /// Φ(q, t) into `out` (m).
    pub fn values(&self, layout: &Layout, q: &[f64], t: f64, out: &mut [f64]) {
        for (o, c) in out.iter_mut().zip(&self.constraints) {
            *o = c.value(layout, q, t);
        }
    }

    /// Φ_t(q, t) into `out` (m).
    pub fn time_rates(&self, layout: &Layout, q: &[f64], t: f64, out: &mut [f64]) {
        for (o, c) in out.iter_mut().zip(&self.constraints) {
            *o = c.time_rate(layout, q, t);
        }
    }

    /// Φ_q into `out` (m × n, overwritten).
    pub fn jacobian(&self, layout: &Layout, q: &[f64], t: f64, mut out: MatMut<'_, f64>) {
        out.fill(0.0);
        let rotations = Rotations::at(layout, q);
        for (i, c) in self.constraints.iter().enumerate() {
            c.gradient(layout, q, t, &rotations, 0, |j, x| out[(i, j)] += x);
        }
    }

    /// Φ into `phi`, Φ_t into `phi_t` (m each) and Φ_q into `jacobian` (m × n, overwritten) in
    /// one pass over the rows, with the bodies' rotations updated to q once.
    #[allow(clippy::too_many_arguments)]
    pub fn evaluate(
        &self,
        layout: &Layout,
        q: &[f64],
        t: f64,
        rotations: &mut Rotations,
        phi: &mut [f64],
        phi_t: &mut [f64],
        mut jacobian: MatMut<'_, f64>,
    ) {
        rotations.update(layout, q);
        jacobian.fill(0.0);
        for (i, c) in self.constraints.iter().enumerate() {
            [phi[i], phi_t[i]] = c.evaluate(layout, q, t, rotations, |j, x| jacobian[(i, j)] += x);
        }
    }

    /// Adds scale · Σᵢ wᵢ ∇²Φᵢ to `out` (n × n).
    pub fn add_weighted_hessian(
        &self,
        layout: &Layout,
        q: &[f64],
        t: f64,
        weights: &[f64],
        scale: f64,
        mut out: MatMut<'_, f64>,
    ) {
        for (c, &w) in self.constraints.iter().zip(weights) {
            if w != 0.0 {
                c.hessian(layout, q, t, scale * w, |i, j, x| out[(i, j)] += x);
            }
        }
    }

    /// ∂(Φ_q v + Φ_t)/∂q into `velocity_q` (m × n, overwritten): row i is
    /// (∇²Φᵢ v)ᵀ + ∂Φ_t,i/∂q; and adds scale · Σᵢ wᵢ ∇²Φᵢ to `hessian` (n × n), from one
    /// evaluation of each row's Hessian.
    #[allow(clippy::too_many_arguments)]
    pub fn velocity_jacobian_and_weighted_hessian(
        &self,
        layout: &Layout,
        q: &[f64],
        v: &[f64],
        t: f64,
        weights: &[f64],
        scale: f64,
        mut velocity_q: MatMut<'_, f64>,
        mut hessian: MatMut<'_, f64>,
    ) {
        velocity_q.fill(0.0);
        let rotations = Rotations::at(layout, q);
        for (i, (c, &w)) in self.constraints.iter().zip(weights).enumerate() {
            let sw = scale * w;
            c.hessian(layout, q, t, 1.0, |a, b, x| {
                velocity_q[(i, b)] += v[a] * x;
                hessian[(a, b)] += sw * x;
            });
            c.gradient(layout, q, t, &rotations, 1, |j, x| velocity_q[(i, j)] += x);
        }
    }

    /// The right-hand side of the acceleration equation Φ_q q̈ = γ into `out` (m):
    /// γᵢ = −(vᵀ ∇²Φᵢ v + 2 ∂Φ_t,ᵢ/∂q · v + ∂²Φᵢ/∂t²), the second time derivative of Φᵢ = 0
    /// without its Φ_q q̈ part.
    pub fn acceleration_rhs(&self, layout: &Layout, q: &[f64], v: &[f64], t: f64, out: &mut [f64]) {
        let rotations = Rotations::at(layout, q);
        for (o, c) in out.iter_mut().zip(&self.constraints) {
            let mut sum = c.time_derivative(layout, q, t, 2);
            c.hessian(layout, q, t, 1.0, |a, b, x| sum += v[a] * x * v[b]);
            c.gradient(layout, q, t, &rotations, 1, |j, x| sum += 2.0 * x * v[j]);
            *o = -sum;
        }
    }

    /// Where each row of Φ_q (and of ∂(Φ_q v + Φ_t)/∂q) can be nonzero ([`RowSupport`]).
    pub fn support(&self, layout: &Layout) -> RowSupport {
        RowSupport {
            rows: self
                .constraints
                .iter()
                .map(|c| {
                    c.bodies()
                        .into_iter()
                        .map(|b| {
                            let s = layout.slice(b);
                            s.offset..s.offset + s.len()
                        })
                        .collect()
                })
                .collect(),
        }
    }

    /// Removes the rows that are linear combinations of the others at q (tolerance `tol` on
    /// the pivots of the QR of Φ_qᵀ); returns the split (indices into the set before removal).
    pub fn remove_redundant(&mut self, layout: &Layout, q: &[f64], t: f64, tol: f64) -> RankSplit {
        let mut jac = Mat::zeros(self.len(), layout.size());
        self.jacobian(layout, q, t, jac.as_mut());
        let split = split_rows(jac.as_ref(), tol);
        self.constraints = split
            .independent
            .iter()
            .map(|&i| self.constraints[i].clone())
            .collect();
        self.labels = split
            .independent
            .iter()
            .map(|&i| self.labels[i].clone())
            .collect();
        split
    }
}

/// The coordinates each constraint row depends on: the slices of its bodies, ascending. A row
/// touches one or two bodies, so products with Φ_q over these ranges skip the zeros of the
/// dense m × n storage; they add the same nonzero terms in the same order as the dense
/// products, so the results are the same numbers.
#[derive(Debug, Clone, Default)]
pub struct RowSupport {
    rows: Vec<Vec<Range<usize>>>,
}

impl RowSupport {
    /// The coordinate ranges of row i.
    pub fn row(&self, i: usize) -> &[Range<usize>] {
        &self.rows[i]
    }

    /// y = Aᵀ x for A (m × n) zero outside the support (y overwritten).
    pub fn transpose_mul(&self, a: MatRef<'_, f64>, x: &[f64], y: &mut [f64]) {
        y.fill(0.0);
        for (i, (ranges, &xi)) in self.rows.iter().zip(x).enumerate() {
            let row = a.row(i);
            for range in ranges {
                for j in range.clone() {
                    y[j] += row[j] * xi;
                }
            }
        }
    }

    /// y += A x for A (m × n) zero outside the support.
    pub fn mul_add(&self, a: MatRef<'_, f64>, x: &[f64], y: &mut [f64]) {
        for (i, (ranges, yi)) in self.rows.iter().zip(y.iter_mut()).enumerate() {
            let row = a.row(i);
            for range in ranges {
                for j in range.clone() {
                    *yi += row[j] * x[j];
                }
            }
        }
    }
}
