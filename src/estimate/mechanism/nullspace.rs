//! The nullspace of the constraint Jacobian Φ_q (m × n, full row rank) by coordinate
//! partitioning (Yen and Petzold; thesis eq. 9.2): m dependent coordinates d, chosen as the
//! pivot columns of a completely pivoted elimination of Φ_q, and the n − m independent ones i.
//! With Φ_q = [Φ_d Φ_i] (columns regrouped),
//!
//! ```text
//! V = [V_d; V_i] = [−Φ_d⁻¹ Φ_i; I],   Φ_q V = 0,   N = Vᵀ (N Φ_qᵀ = 0, eq. 9.2)
//! ```
//!
//! The derivative of the projection N(q) r(q) the Jacobian needs comes from the same blocks:
//! V_i is constant and Φ_d dV_d = −dΦ_q V, so dVᵀ r = −Vᵀ dΦ_qᵀ λ̂ with λ̂ = Φ_d⁻ᵀ r_d, and
//!
//! ```text
//! ∂(Vᵀ r)/∂q = Vᵀ (∂r/∂q − Σₖ λ̂ₖ ∇²Φₖ)
//! ```
//!
//! exact for any r ([`Nullspace::multiplier`] gives λ̂; at a GGL solution it is the scaled
//! constraint force of the row block r belongs to). The partition is kept while Φ_d stays
//! well conditioned and chosen again when the smallest pivot of its elimination falls below
//! [`DEGRADED`] times its value at the choice.

use faer::{Mat, MatRef};

/// Pivot ratio (smallest over largest |pivot| of Φ_d), relative to the one at the choice,
/// below which the dependent coordinates are chosen again.
pub const DEGRADED: f64 = 0.1;

/// The dependent coordinates (module docs) and the pivot ratio they were chosen with.
#[derive(Debug, Clone)]
pub struct Partition {
    pub dependent: Vec<usize>,
    pub independent: Vec<usize>,
    chosen_ratio: f64,
    /// Times the coordinates were chosen (the first included).
    pub choices: usize,
}

/// V = [−Φ_d⁻¹ Φ_i; I] at one configuration, with Φ_d⁻¹ for the multipliers.
#[derive(Debug, Clone)]
pub struct Nullspace {
    /// V (n × (n − m)): column j is independent coordinate j's direction.
    pub basis: Mat<f64>,
    dependent: Vec<usize>,
    inverse_dependent: Mat<f64>,
}

/// A problem of Φ_q: a row-rank deficit (a dependent constraint or a singular configuration).
#[derive(Debug, Clone, PartialEq)]
pub struct RankDeficient {
    pub rank: usize,
    pub rows: usize,
}

impl std::fmt::Display for RankDeficient {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "the constraint Jacobian has rank {} < {} rows: no coordinate partitioning",
            self.rank, self.rows
        )
    }
}

/// The pivot columns of a completely pivoted elimination of `a` (m × n, m ≤ n), in pivot order,
/// and the ratio smallest over largest |pivot|.
fn pivot_columns(a: MatRef<'_, f64>) -> Result<(Vec<usize>, f64), RankDeficient> {
    let (m, n) = (a.nrows(), a.ncols());
    let mut w = a.to_owned();
    let mut rows: Vec<usize> = (0..m).collect();
    let mut free: Vec<usize> = (0..n).collect();
    let mut chosen = Vec::with_capacity(m);
    let (mut smallest, mut largest) = (f64::INFINITY, 0.0_f64);
    for k in 0..m {
        let (mut bi, mut bj, mut best) = (0, 0, 0.0);
        for (ii, &i) in rows.iter().enumerate() {
            for (jj, &j) in free.iter().enumerate() {
                if w[(i, j)].abs() > best {
                    (bi, bj, best) = (ii, jj, w[(i, j)].abs());
                }
            }
        }
        if best == 0.0 || best <= 1e-13 * largest {
            return Err(RankDeficient { rank: k, rows: m });
        }
        let (pi, pj) = (rows.swap_remove(bi), free.swap_remove(bj));
        for &i in &rows {
            let f = w[(i, pj)] / w[(pi, pj)];
            if f != 0.0 {
                for &j in &free {
                    let x = w[(pi, j)];
                    w[(i, j)] -= f * x;
                }
            }
        }
        chosen.push(pj);
        (smallest, largest) = (smallest.min(best), largest.max(best));
    }
    Ok((chosen, if m == 0 { 1.0 } else { smallest / largest }))
}

/// The inverse of the square `a` by Gauss–Jordan elimination with partial pivoting, and the
/// ratio smallest over largest |pivot|.
fn inverse(mut a: Mat<f64>) -> (Mat<f64>, f64) {
    let m = a.nrows();
    let mut inv = Mat::<f64>::identity(m, m);
    let (mut smallest, mut largest) = (f64::INFINITY, 0.0_f64);
    for k in 0..m {
        let p = (k..m)
            .max_by(|&x, &y| a[(x, k)].abs().total_cmp(&a[(y, k)].abs()))
            .expect("k < m");
        let pivot = a[(p, k)];
        (smallest, largest) = (smallest.min(pivot.abs()), largest.max(pivot.abs()));
        if pivot == 0.0 {
            return (inv, 0.0);
        }
        if p != k {
            for j in 0..m {
                let (x, y) = (a[(k, j)], inv[(k, j)]);
                (a[(k, j)], inv[(k, j)]) = (a[(p, j)], inv[(p, j)]);
                (a[(p, j)], inv[(p, j)]) = (x, y);
            }
        }
        for j in 0..m {
            a[(k, j)] /= pivot;
            inv[(k, j)] /= pivot;
        }
        for i in (0..m).filter(|&i| i != k) {
            let f = a[(i, k)];
            if f != 0.0 {
                for j in 0..m {
                    let (x, y) = (a[(k, j)], inv[(k, j)]);
                    a[(i, j)] -= f * x;
                    inv[(i, j)] -= f * y;
                }
            }
        }
    }
    (inv, if m == 0 { 1.0 } else { smallest / largest })
}

impl Partition {
    /// Chooses the dependent coordinates of `phi_q` (module docs).
    pub fn choose(phi_q: MatRef<'_, f64>) -> Result<Self, RankDeficient> {
        let (dependent, chosen_ratio) = pivot_columns(phi_q)?;
        let independent = (0..phi_q.ncols())
            .filter(|j| !dependent.contains(j))
            .collect();
        Ok(Self {
            dependent,
            independent,
            chosen_ratio,
            choices: 1,
        })
    }

    /// The nullspace at `phi_q`, with the coordinates chosen again first if Φ_d's pivots
    /// degraded (module docs).
    pub fn nullspace(&mut self, phi_q: MatRef<'_, f64>) -> Result<Nullspace, RankDeficient> {
        let columns = |d: &[usize]| Mat::from_fn(d.len(), d.len(), |i, j| phi_q[(i, d[j])]);
        let (mut inverse_dependent, ratio) = inverse(columns(&self.dependent));
        if !(ratio >= DEGRADED * self.chosen_ratio) {
            let choices = self.choices;
            *self = Self::choose(phi_q)?;
            self.choices += choices;
            inverse_dependent = inverse(columns(&self.dependent)).0;
        }
        let (n, m) = (phi_q.ncols(), phi_q.nrows());
        let mut basis = Mat::zeros(n, n - m);
        for (c, &j) in self.independent.iter().enumerate() {
            basis[(j, c)] = 1.0;
            // V_d[:, c] = −Φ_d⁻¹ Φ_q[:, j]
            for (r, &d) in self.dependent.iter().enumerate() {
                basis[(d, c)] = -(0..m)
                    .map(|k| inverse_dependent[(r, k)] * phi_q[(k, j)])
                    .sum::<f64>();
            }
        }
        Ok(Nullspace {
            basis,
            dependent: self.dependent.clone(),
            inverse_dependent,
        })
    }
}

impl Nullspace {
    /// λ̂ = Φ_d⁻ᵀ r_d (module docs): the multipliers with Φ_qᵀ λ̂ = r when r lies in the range
    /// of Φ_qᵀ.
    pub fn multiplier(&self, r: &[f64]) -> Vec<f64> {
        let m = self.dependent.len();
        (0..m)
            .map(|k| {
                self.dependent
                    .iter()
                    .enumerate()
                    .map(|(i, &d)| self.inverse_dependent[(i, k)] * r[d])
                    .sum()
            })
            .collect()
    }

    /// Vᵀ X for X with n rows.
    pub fn project(&self, x: MatRef<'_, f64>) -> Mat<f64> {
        self.basis.transpose() * x
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 2 × 4 Jacobian with an obvious partition.
    fn jacobian() -> Mat<f64> {
        let rows = [[1.0, 0.5, -2.0, 0.1], [0.3, 4.0, 1.0, -1.0]];
        Mat::from_fn(2, 4, |i, j| rows[i][j])
    }

    #[test]
    fn the_basis_spans_the_nullspace_and_the_multiplier_inverts_the_transpose() {
        let a = jacobian();
        let mut partition = Partition::choose(a.as_ref()).expect("full rank");
        assert_eq!(partition.dependent, vec![1, 2]);
        let ns = partition.nullspace(a.as_ref()).expect("full rank");
        let product = &a * &ns.basis;
        assert!(product.norm_max() < 1e-14, "Φ_q V = {product:?}");
        // r = Φ_qᵀ λ: λ̂ recovers λ and Vᵀ r vanishes
        let lambda = [0.7, -1.3];
        let r: Vec<f64> = (0..4)
            .map(|j| a[(0, j)] * lambda[0] + a[(1, j)] * lambda[1])
            .collect();
        let found = ns.multiplier(&r);
        assert!((found[0] - lambda[0]).abs() < 1e-14 && (found[1] - lambda[1]).abs() < 1e-14);
        let projected = ns.project(Mat::from_fn(4, 1, |i, _| r[i]).as_ref());
        assert!(projected.norm_max() < 1e-14);
    }

    #[test]
    fn degraded_pivots_choose_the_coordinates_again() {
        let a = jacobian();
        let mut partition = Partition::choose(a.as_ref()).expect("full rank");
        // column 1 of the first choice nearly vanishes: its Φ_d turns nearly singular
        let mut b = a.clone();
        b[(1, 1)] = 1e-9;
        b[(0, 1)] = 1e-9;
        let ns = partition.nullspace(b.as_ref()).expect("full rank");
        assert_eq!(partition.choices, 2);
        assert!(!partition.dependent.contains(&1));
        assert!((&b * &ns.basis).norm_max() < 1e-12);
    }

    #[test]
    fn dependent_rows_are_refused() {
        let a = Mat::from_fn(2, 3, |_, j| j as f64 + 1.0);
        assert_eq!(
            Partition::choose(a.as_ref()).unwrap_err(),
            RankDeficient { rank: 1, rows: 2 }
        );
    }
}
