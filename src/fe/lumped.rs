//! Lumped elements: scalar springs CELAS1/CELAS2 and the concentrated mass CONM2
//! (DESIGN.md §4; thesis eq. 3.23 and 3.25).
//!
//! A spring acts on single DOFs, so instead of a 6·n block it returns a small matrix together
//! with the list of DOFs its rows and columns refer to: the caller's DOF indices (a grid
//! component or a scalar point; the kernel never interprets them).
//!
//! # Scalar spring (CELAS1–CELAS4)
//! Between DOFs a and b: `K = k [[1, −1], [−1, 1]]` over (a, b); grounded (one grid blank):
//! `K = [k]` on the remaining DOF. Affine in k (eq. 3.23): one [`Coefficient::Lumped`] part with
//! the k = 1 matrix. The CELAS2 damping GE and stress coefficient S are not part of K.
//!
//! # Concentrated mass (CONM2)
//! Mass m whose centre of gravity sits at offset X from the grid (X in the basic system),
//! inertia tensor J about the CG (3×3 in the basic system, the caller has already turned
//! Nastran's Iij = −∫xixj dm products of inertia into a tensor). A rigid offset gives the CG
//! velocity `v_cg = v + ω × X = v − [X]× ω`, where `[X]×` is the cross-product matrix
//! (`[X]× y = X × y`). The kinetic energy ½ m v_cgᵀ v_cg + ½ ωᵀ J ω = ½ qᵀ M q with
//! q = (v, ω) then gives
//!
//! `M = [[m I, −m [X]×], [m [X]×, J − m [X]×[X]×]]`,
//!
//! where `−[X]×[X]× = |X|² I − X Xᵀ` (the parallel-axis term). The CONM2 mass parameter
//! (eq. 3.25) scales the whole element — m and J together, as a denser material would — so
//! M(p) = (p / m) M with one [`Coefficient::Lumped`] part M / m, i.e. the matrix at unit mass
//! with J/m. A CONM2 with m = 0 (pure inertia) cannot be parametrized that way and is refused.

use super::affine::{AffineMatrix, Coefficient};
use crate::geometry::vec3::{dot, skew};
use faer::Mat;

/// Errors of the lumped elements.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum LumpedError {
    #[error("scalar spring: both ends are grounded; at least one grid or scalar point is required")]
    BothEndsGrounded,
    #[error("scalar spring: both ends are the same DOF ({dof}); the spring would do nothing")]
    SameDof { dof: usize },
    #[error("CONM2: {what} is not finite")]
    NotFinite { what: &'static str },
    #[error("CONM2: inertia tensor is not symmetric (J[{i}][{j}] = {a:e}, J[{j}][{i}] = {b:e})")]
    InertiaNotSymmetric { i: usize, j: usize, a: f64, b: f64 },
    #[error(
        "CONM2 with zero mass cannot be mass-parametrized (the MASS parameter scales m and the inertia together)"
    )]
    ZeroMassParameter,
}

/// A CELAS1–CELAS4 spring: DOFs and the stiffness at k = 1.
#[derive(Debug, Clone)]
pub struct ScalarSpring {
    /// The DOFs of the rows and columns of [`ScalarSpring::stiffness`]: one (grounded) or two.
    pub dofs: Vec<usize>,
    unit: Mat<f64>,
}

impl ScalarSpring {
    /// Spring between DOFs `a` and `b`; `None` is a grounded end.
    pub fn new(a: Option<usize>, b: Option<usize>) -> Result<Self, LumpedError> {
        let (dofs, unit) = match (a, b) {
            (None, None) => return Err(LumpedError::BothEndsGrounded),
            (Some(a), Some(b)) if a == b => return Err(LumpedError::SameDof { dof: a }),
            (Some(a), Some(b)) => (
                vec![a, b],
                Mat::from_fn(2, 2, |i, j| if i == j { 1.0 } else { -1.0 }),
            ),
            (Some(g), None) | (None, Some(g)) => (vec![g], Mat::from_fn(1, 1, |_, _| 1.0)),
        };
        Ok(ScalarSpring { dofs, unit })
    }

    /// K for spring constant `k`, over [`ScalarSpring::dofs`].
    pub fn stiffness(&self, k: f64) -> Mat<f64> {
        &self.unit * faer::Scale(k)
    }

    /// Affine stiffness K = k · K₁ (eq. 3.23): one [`Coefficient::Lumped`] part.
    pub fn affine_stiffness(&self) -> AffineMatrix {
        AffineMatrix {
            parts: vec![(Coefficient::Lumped, self.unit.clone())],
        }
    }
}

/// A CONM2 in the basic system (module doc).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Conm2 {
    mass: f64,
    offset: [f64; 3],
    inertia: [[f64; 3]; 3],
}

impl Conm2 {
    /// Mass `mass`, CG offset `offset` from the grid, inertia tensor `inertia` about the CG
    /// (symmetric to 1e-12 relative), all in the basic system.
    pub fn new(mass: f64, offset: [f64; 3], inertia: [[f64; 3]; 3]) -> Result<Self, LumpedError> {
        if !mass.is_finite() {
            return Err(LumpedError::NotFinite { what: "mass" });
        }
        if !offset.iter().all(|v| v.is_finite()) {
            return Err(LumpedError::NotFinite { what: "offset" });
        }
        if !inertia.iter().flatten().all(|v| v.is_finite()) {
            return Err(LumpedError::NotFinite { what: "inertia" });
        }
        let scale = inertia
            .iter()
            .flatten()
            .fold(0.0_f64, |m, v| m.max(v.abs()));
        for (i, j) in [(0, 1), (0, 2), (1, 2)] {
            let (a, b) = (inertia[i][j], inertia[j][i]);
            if (a - b).abs() > 1e-12 * scale {
                return Err(LumpedError::InertiaNotSymmetric { i, j, a, b });
            }
        }
        Ok(Conm2 {
            mass,
            offset,
            inertia,
        })
    }

    /// 6×6 mass matrix at the grid (T1 T2 T3 R1 R2 R3):
    /// `M = [[m I, −m [X]×], [m [X]×, J − m [X]×[X]×]]`.
    pub fn mass_matrix(&self) -> Mat<f64> {
        let (m, x) = (self.mass, self.offset);
        let cross = skew(x);
        let x2 = dot(x, x);
        Mat::from_fn(6, 6, |i, j| match (i < 3, j < 3) {
            (true, true) => {
                if i == j {
                    m
                } else {
                    0.0
                }
            }
            (true, false) => -m * cross[i][j - 3],
            (false, true) => m * cross[i - 3][j],
            (false, false) => {
                let (r, c) = (i - 3, j - 3);
                let parallel_axis = if r == c { x2 } else { 0.0 } - x[r] * x[c];
                0.5 * (self.inertia[r][c] + self.inertia[c][r]) + m * parallel_axis
            }
        })
    }

    /// Affine mass with the CONM2 mass as parameter (eq. 3.25): one [`Coefficient::Lumped`]
    /// part M / m (m and J scale together). Refused for m = 0.
    pub fn affine_mass(&self) -> Result<AffineMatrix, LumpedError> {
        if self.mass == 0.0 {
            return Err(LumpedError::ZeroMassParameter);
        }
        Ok(AffineMatrix {
            parts: vec![(
                Coefficient::Lumped,
                self.mass_matrix() * faer::Scale(1.0 / self.mass),
            )],
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fe::affine::CoefficientValues;
    use crate::geometry::vec3::cross;

    fn quad_form(m: &Mat<f64>, q: &[f64; 6]) -> f64 {
        (0..6)
            .flat_map(|i| (0..6).map(move |j| (i, j)))
            .map(|(i, j)| q[i] * m[(i, j)] * q[j])
            .sum()
    }

    #[test]
    fn spring_between_two_dofs_and_grounded() {
        let (a, b) = (44, 58);
        let s = ScalarSpring::new(Some(a), Some(b)).unwrap();
        assert_eq!(s.dofs, vec![a, b]);
        let k = s.stiffness(3.5);
        assert_eq!(
            [k[(0, 0)], k[(0, 1)], k[(1, 0)], k[(1, 1)]],
            [3.5, -3.5, -3.5, 3.5]
        );
        let at = CoefficientValues {
            lumped: 3.5,
            ..Default::default()
        };
        assert_eq!(s.affine_stiffness().evaluate(&at), k);
        let g = ScalarSpring::new(None, Some(b)).unwrap();
        assert_eq!(g.dofs, vec![b]);
        assert_eq!(g.stiffness(2.0)[(0, 0)], 2.0);
        assert_eq!(
            ScalarSpring::new(None, None).unwrap_err(),
            LumpedError::BothEndsGrounded
        );
        assert!(matches!(
            ScalarSpring::new(Some(a), Some(a)),
            Err(LumpedError::SameDof { dof: 44 })
        ));
    }

    /// A rigid motion about an axis through the grid, ω = (ω₁, ω₂, ω₃) and grid velocity 0:
    /// the CG moves with v_cg = ω × X, so T = ½ m |ω × X|² + ½ ωᵀ J ω. Also a general rigid
    /// motion with grid velocity v, and a point mass on the x axis (textbook I = m d²).
    #[test]
    fn conm2_kinetic_energy_of_rigid_motions() {
        let (m, x) = (2.5, [0.3, -1.2, 0.8]);
        let j = [[1.1, 0.2, -0.1], [0.2, 0.9, 0.05], [-0.1, 0.05, 1.4]];
        let c = Conm2::new(m, x, j).unwrap();
        let mm = c.mass_matrix();
        for (v, w) in [
            ([0.0; 3], [0.4, -0.7, 1.3]),
            ([0.5, 0.1, -0.2], [0.0, 2.0, -1.0]),
        ] {
            let vcg: [f64; 3] = std::array::from_fn(|k| v[k] + cross(w, x)[k]);
            let jw: f64 = (0..3)
                .flat_map(|r| (0..3).map(move |s| (r, s)))
                .map(|(r, s)| w[r] * j[r][s] * w[s])
                .sum();
            let expected = 0.5 * m * vcg.iter().map(|a| a * a).sum::<f64>() + 0.5 * jw;
            let q = [v[0], v[1], v[2], w[0], w[1], w[2]];
            let got = 0.5 * quad_form(&mm, &q);
            assert!(
                (got - expected).abs() < 1e-13 * expected,
                "{got} vs {expected}"
            );
        }
        // point mass 2 at distance 3 on x: rotation about z through the grid → I = m d² = 18;
        // force on the grid from a unit acceleration in y is m, and the moment about z is m d.
        let p = Conm2::new(2.0, [3.0, 0.0, 0.0], [[0.0; 3]; 3])
            .unwrap()
            .mass_matrix();
        assert_eq!(p[(5, 5)], 18.0);
        assert_eq!(p[(3, 3)], 0.0);
        assert_eq!(p[(1, 5)], 6.0);
        assert_eq!(p[(5, 1)], 6.0);
        assert_eq!(p[(2, 4)], -6.0);
        // symmetric
        for r in 0..6 {
            for s in 0..6 {
                assert_eq!(mm[(r, s)], mm[(s, r)]);
            }
        }
    }

    #[test]
    fn conm2_affine_mass_scales_m_and_inertia_together() {
        let j = [[1.0, 0.1, 0.0], [0.1, 2.0, 0.0], [0.0, 0.0, 3.0]];
        let c = Conm2::new(4.0, [1.0, 2.0, -1.0], j).unwrap();
        let parts = c.affine_mass().unwrap();
        let at = |lumped: f64| CoefficientValues {
            lumped,
            ..Default::default()
        };
        let same = parts.evaluate(&at(4.0)) - c.mass_matrix();
        assert!((0..36).all(|k| same[(k / 6, k % 6)].abs() < 1e-14));
        let doubled = Conm2::new(8.0, [1.0, 2.0, -1.0], j.map(|r| r.map(|v| 2.0 * v)))
            .unwrap()
            .mass_matrix();
        let diff = parts.evaluate(&at(8.0)) - doubled;
        assert!((0..36).all(|k| diff[(k / 6, k % 6)].abs() < 1e-13));
        let pure = Conm2::new(0.0, [0.0; 3], j).unwrap();
        assert_eq!(
            pure.affine_mass().unwrap_err(),
            LumpedError::ZeroMassParameter
        );
        assert!(matches!(
            Conm2::new(
                1.0,
                [0.0; 3],
                [[1.0, 0.5, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
            ),
            Err(LumpedError::InertiaNotSymmetric { i: 0, j: 1, .. })
        ));
        assert!(matches!(
            Conm2::new(f64::NAN, [0.0; 3], j),
            Err(LumpedError::NotFinite { what: "mass" })
        ));
    }
}
