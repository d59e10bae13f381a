//! The generalized spring CBUSH: six uncoupled springs along and about the element axes, acting
//! at one point P (the spring location) rigidly attached to both grids.
//!
//! With e₁, e₂, e₃ the element axes (unit, in basic), r_a = P − x_a and r_b = P − x_b, the
//! motion of P as carried by a grid with translation u and rotation θ is u + θ × r = u − [r]× θ.
//! The relative translation and rotation at P in element axes are
//!
//! ```text
//! d = E ((u_b − [r_b]× θ_b) − (u_a − [r_a]× θ_a)),   φ = E (θ_b − θ_a),   E = [e₁ e₂ e₃]ᵀ,
//! ```
//!
//! i.e. (d, φ) = T q with q = (u_a, θ_a, u_b, θ_b) and the 6 × 12 matrix
//!
//! ```text
//! T = [[−E, E [r_a]×, E, −E [r_b]×], [0, −E, 0, E]].
//! ```
//!
//! The strain energy ½ Σ kᵢ (T q)ᵢ² gives K = Tᵀ diag(k₁ … k₆) T (12 × 12, basic). A grounded
//! CBUSH (no GB) keeps the columns of grid A only (6 × 6). Nastran's element forces are the
//! products kᵢ (T q)ᵢ; K is symmetric, positive semi-definite, and leaves rigid motions of both
//! grids together free: for u_b = u_a + θ × (x_b − x_a), θ_b = θ_a, T q = 0.

use faer::Mat;

use crate::geometry::vec3::skew;

/// A CBUSH in the basic system.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bush {
    /// Rows: the element axes e₁, e₂, e₃ in basic (orthonormal).
    pub axes: [[f64; 3]; 3],
    /// P − x_a.
    pub arm_a: [f64; 3],
    /// P − x_b, `None` for a grounded bush.
    pub arm_b: Option<[f64; 3]>,
}

impl Bush {
    /// The 6 × 12 (6 × 6 grounded) map T from the grid DOFs (basic) to the relative motion at
    /// P in element axes (module doc).
    pub fn relative_motion(&self) -> Mat<f64> {
        let n = if self.arm_b.is_some() { 12 } else { 6 };
        let e = Mat::from_fn(3, 3, |i, j| self.axes[i][j]);
        let block = |arm: [f64; 3]| {
            let s = skew(arm);
            &e * Mat::from_fn(3, 3, |i, j| s[i][j])
        };
        let mut t = Mat::zeros(6, n);
        let mut put = |row: usize, col: usize, m: &Mat<f64>, sign: f64| {
            for i in 0..3 {
                for j in 0..3 {
                    t[(row + i, col + j)] = sign * m[(i, j)];
                }
            }
        };
        put(0, 0, &e, -1.0);
        put(0, 3, &block(self.arm_a), 1.0);
        put(3, 3, &e, -1.0);
        if let Some(arm_b) = self.arm_b {
            put(0, 6, &e, 1.0);
            put(0, 9, &block(arm_b), -1.0);
            put(3, 9, &e, 1.0);
        }
        t
    }

    /// K = Tᵀ diag(k) T in basic, over (u_a, θ_a[, u_b, θ_b]).
    pub fn stiffness(&self, k: [f64; 6]) -> Mat<f64> {
        let t = self.relative_motion();
        let kt = Mat::from_fn(6, t.ncols(), |i, j| k[i] * t[(i, j)]);
        t.transpose() * kt
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A rigid motion of both grids together strains nothing; a unit relative translation
    /// along e₁ at P costs k₁.
    #[test]
    fn rigid_motion_is_free_and_axes_pick_the_spring() {
        let (xa, xb) = ([0.0, 0.0, 0.0], [2.0, 1.0, -0.5]);
        let p = [0.6, 0.3, -0.15];
        let c = std::f64::consts::FRAC_1_SQRT_2;
        let bush = Bush {
            axes: [[c, c, 0.0], [-c, c, 0.0], [0.0, 0.0, 1.0]],
            arm_a: std::array::from_fn(|i| p[i] - xa[i]),
            arm_b: Some(std::array::from_fn(|i| p[i] - xb[i])),
        };
        let k = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0];
        let kk = bush.stiffness(k);
        let (u, w) = ([0.3, -0.2, 0.7], [0.1, 0.4, -0.3]);
        let d = crate::geometry::vec3::cross(w, [xb[0] - xa[0], xb[1] - xa[1], xb[2] - xa[2]]);
        let q: Vec<f64> = u
            .iter()
            .chain(&w)
            .copied()
            .chain((0..3).map(|i| u[i] + d[i]))
            .chain(w)
            .collect();
        let f = &kk * Mat::from_fn(12, 1, |i, _| q[i]);
        assert!((0..12).all(|i| f[(i, 0)].abs() < 1e-12), "{f:?}");
        // u_b = e₁ (unit), everything else 0: energy ½ k₁
        let mut q = [0.0; 12];
        q[6..9].copy_from_slice(&[c, c, 0.0]);
        let e: f64 = (0..12)
            .flat_map(|i| (0..12).map(move |j| (i, j)))
            .map(|(i, j)| q[i] * kk[(i, j)] * q[j])
            .sum();
        assert!((e - k[0]).abs() < 1e-12, "{e}");
    }
}
