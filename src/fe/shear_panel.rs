//! Four-node shear panel (CSHEAR): a quadrilateral that carries only a uniform in-plane shear
//! flow and connects only the grids' translations.
//!
//! # Formulation
//!
//! The panel is projected onto its mean plane as the shells are ([`crate::fe::shell`]):
//! normal n = (x₃ − x₁) × (x₄ − x₂)/|…|, centre c = mean of the grids, in-plane axes
//! e₁ = (x₂ − x₁) projected on the plane, e₂ = n × e₁, local coordinates
//! (x_a, y_a) = ((x_a − c)·e₁, (x_a − c)·e₂) and projected area A = ½|(x₃ − x₁) × (x₄ − x₂)|.
//! The in-plane displacement is bilinear; the panel's only strain is its mean shear
//!
//! ```text
//! γ̄ = (1/A) ∫(∂u/∂y + ∂v/∂x) dA = (1/A) Σ_edges ½(u_a + u_b) m_y + ½(v_a + v_b) m_x
//! ```
//!
//! (divergence theorem, exact for the bilinear field; m = (y_b − y_a, −(x_b − x_a)) is the
//! outward edge normal times the edge length of edge a → b), with u_a = U_a·e₁, v_a = U_a·e₂ the
//! in-plane components of grid a's basic translation U_a. The strain energy ½ G t A γ̄² gives
//!
//! ```text
//! K = G t A b bᵀ   (12 × 12, translations),   γ̄ = b·U
//! ```
//!
//! a rank-one matrix: the single constant shear flow q = G t γ̄ of the classical shear panel
//! (on a parallelogram the shear flow of equilibrium is uniform, and this is the exact panel;
//! Nastran's CSHEAR, after Garvey, lets the edge shear flows differ on a non-parallelogram).
//! The operator is invariant to rigid motion even for a warped panel: a translation gives
//! Σ_a b_a = 0 (the edge normals of a closed polygon sum to zero), a rotation about n gives
//! ∂u/∂y + ∂v/∂x = 0, and a rotation about an in-plane axis moves grid a in the plane by
//! h_a (ω × n), whose edge sums ½(h_a + h_b) vanish because the warp heights alternate ±h.
//!
//! Mass (per unit mass per area μ = ρt + NSM): lumped μA/4 on each grid's translations, or
//! consistent μ ∫N_a N_b dA (bilinear, 2 × 2 Gauss, exact) on each translation component.
//! Rotations carry neither stiffness nor mass.

use faer::Mat;

use crate::geometry::vec3::{cross, dot, norm, scale, sub};

type V3 = [f64; 3];

/// Errors of the panel's geometry.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ShearPanelError {
    /// The projected panel has no area or G1→G2 is normal to its plane.
    #[error("CSHEAR has zero area (coincident or collinear grids)")]
    ZeroArea,
}

/// A panel's geometry, ready for any material.
#[derive(Debug, Clone)]
pub struct ShearPanel {
    /// γ̄ = Σ_a b[a]·U_a with U_a the basic translation of grid a.
    b: [V3; 4],
    /// Projected area.
    area: f64,
    /// Projected in-plane coordinates of the grids.
    xy: [[f64; 2]; 4],
    /// Element axes e₁, e₂, n (basic).
    axes: [V3; 3],
}

impl ShearPanel {
    /// The panel with grids at `xyz` (basic), in card order.
    pub fn new(xyz: &[V3; 4]) -> Result<Self, ShearPanelError> {
        let normal = cross(sub(xyz[2], xyz[0]), sub(xyz[3], xyz[1]));
        let twice_area = norm(normal);
        let size = (0..4)
            .map(|a| norm(sub(xyz[(a + 1) % 4], xyz[a])))
            .fold(0.0, f64::max);
        if !(twice_area > 1e-12 * size * size) {
            return Err(ShearPanelError::ZeroArea);
        }
        let n = scale(normal, 1.0 / twice_area);
        let g12 = sub(xyz[1], xyz[0]);
        let x_dir = sub(g12, scale(n, dot(g12, n)));
        let lx = norm(x_dir);
        if !(lx > 1e-12 * size) {
            return Err(ShearPanelError::ZeroArea);
        }
        let e1 = scale(x_dir, 1.0 / lx);
        let e2 = cross(n, e1);
        let centre: V3 = std::array::from_fn(|i| xyz.iter().map(|p| p[i]).sum::<f64>() / 4.0);
        let xy: [[f64; 2]; 4] = std::array::from_fn(|a| {
            let d = sub(xyz[a], centre);
            [dot(d, e1), dot(d, e2)]
        });
        let area = 0.5 * twice_area;
        // local (u, v) coefficients of γ̄ per grid: ½ Σ over the two edges at the grid
        let mut local = [[0.0; 2]; 4];
        for a in 0..4 {
            let b = (a + 1) % 4;
            let m = [xy[b][1] - xy[a][1], -(xy[b][0] - xy[a][0])];
            for g in [a, b] {
                local[g][0] += 0.5 * m[1] / area;
                local[g][1] += 0.5 * m[0] / area;
            }
        }
        let b = std::array::from_fn(|a| {
            std::array::from_fn(|i| local[a][0] * e1[i] + local[a][1] * e2[i])
        });
        Ok(ShearPanel {
            b,
            area,
            xy,
            axes: [e1, e2, n],
        })
    }

    /// The projected area.
    pub fn area(&self) -> f64 {
        self.area
    }

    /// The element axes e₁ (along G1→G2), e₂, n (basic).
    pub fn axes(&self) -> [V3; 3] {
        self.axes
    }

    /// Stiffness per unit G·t (12 × 12, basic translations): A b bᵀ.
    pub fn unit_stiffness(&self) -> Mat<f64> {
        let flat: Vec<f64> = self.b.iter().flatten().copied().collect();
        Mat::from_fn(12, 12, |i, j| self.area * flat[i] * flat[j])
    }

    /// Mass per unit mass per area (12 × 12, basic translations), lumped or consistent.
    pub fn unit_mass(&self, lumped: bool) -> Mat<f64> {
        let mut n = [[0.0; 4]; 4];
        if lumped {
            for (a, row) in n.iter_mut().enumerate() {
                row[a] = self.area / 4.0;
            }
        } else {
            let g = 1.0 / 3f64.sqrt();
            for (xi, eta) in [(-g, -g), (g, -g), (g, g), (-g, g)] {
                let corners = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)];
                let shape: [f64; 4] = std::array::from_fn(|a| {
                    0.25 * (1.0 + corners[a].0 * xi) * (1.0 + corners[a].1 * eta)
                });
                let d_xi: [f64; 4] =
                    std::array::from_fn(|a| 0.25 * corners[a].0 * (1.0 + corners[a].1 * eta));
                let d_eta: [f64; 4] =
                    std::array::from_fn(|a| 0.25 * corners[a].1 * (1.0 + corners[a].0 * xi));
                let j = |d: &[f64; 4], k: usize| (0..4).map(|a| d[a] * self.xy[a][k]).sum::<f64>();
                let det = j(&d_xi, 0) * j(&d_eta, 1) - j(&d_xi, 1) * j(&d_eta, 0);
                for a in 0..4 {
                    for b in 0..4 {
                        n[a][b] += det * shape[a] * shape[b];
                    }
                }
            }
        }
        Mat::from_fn(
            12,
            12,
            |i, j| {
                if i % 3 == j % 3 { n[i / 3][j / 3] } else { 0.0 }
            },
        )
    }

    /// The mean shear strain γ̄ of basic grid translations `u` (12 values, grid-major).
    pub fn mean_shear(&self, u: &[f64; 12]) -> f64 {
        (0..4)
            .map(|a| dot(self.b[a], [u[3 * a], u[3 * a + 1], u[3 * a + 2]]))
            .sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A rectangle a × h in pure shear (u = γ y): γ̄ = γ, energy ½ G t A γ² — the closed form of
    /// the panel, to round-off.
    #[test]
    fn rectangle_in_pure_shear_is_exact() {
        let (a, h) = (3.0, 2.0);
        let xyz = [[0.0, 0.0, 0.0], [a, 0.0, 0.0], [a, h, 0.0], [0.0, h, 0.0]];
        let p = ShearPanel::new(&xyz).unwrap();
        let gamma = 1e-3;
        let u: [f64; 12] = std::array::from_fn(|i| {
            if i % 3 == 0 {
                gamma * xyz[i / 3][1]
            } else {
                0.0
            }
        });
        assert!((p.mean_shear(&u) - gamma).abs() < 1e-15);
        let k = p.unit_stiffness();
        let energy: f64 = (0..12)
            .map(|i| (0..12).map(|j| u[i] * k[(i, j)] * u[j]).sum::<f64>())
            .sum::<f64>()
            / 2.0;
        assert!((energy - 0.5 * a * h * gamma * gamma).abs() < 1e-15 * a * h);
    }

    /// Rigid translations and rotations strain a warped, skewed panel by nothing (module doc).
    #[test]
    fn rigid_motion_of_a_warped_panel_is_strain_free() {
        let xyz = [
            [0.0, 0.0, 0.1],
            [2.0, 0.3, -0.1],
            [2.5, 1.7, 0.1],
            [0.2, 1.5, -0.1],
        ];
        let p = ShearPanel::new(&xyz).unwrap();
        for motion in 0..6 {
            let u: [f64; 12] = std::array::from_fn(|i| {
                let (a, c) = (i / 3, i % 3);
                if motion < 3 {
                    f64::from(u8::from(c == motion))
                } else {
                    let mut w = [0.0; 3];
                    w[motion - 3] = 1.0;
                    cross(w, xyz[a])[c]
                }
            });
            assert!(p.mean_shear(&u).abs() < 1e-14, "motion {motion}");
        }
    }

    /// The consistent and lumped masses both sum to μA on each translation.
    #[test]
    fn masses_total_the_panel_mass() {
        let xyz = [
            [0.0, 0.0, 0.0],
            [2.0, 0.3, 0.0],
            [2.5, 1.7, 0.0],
            [0.2, 1.5, 0.0],
        ];
        let p = ShearPanel::new(&xyz).unwrap();
        for lumped in [true, false] {
            let m = p.unit_mass(lumped);
            let total: f64 = (0..12)
                .filter(|i| i % 3 == 0)
                .flat_map(|i| (0..12).filter(|j| j % 3 == 0).map(move |j| (i, j)))
                .map(|(i, j)| m[(i, j)])
                .sum();
            assert!((total - p.area()).abs() < 1e-12, "lumped {lumped}: {total}");
        }
    }
}
