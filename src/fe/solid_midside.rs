//! Quadratic solids with blank mid-side grids (CHEXA 20, CPENTA 15, CTETRA 10).
//!
//! Nastran lets any mid-side grid of a CHEXA 20, CPENTA 15 or CTETRA 10 be blank: that edge is then
//! straight and the displacement varies linearly along it. Here the element keeps its full node
//! set: a blank mid-side node m of the edge (a, b) sits at the middle of the edge,
//! x_m = (x_a + x_b)/2, and moves with it, u_m = (u_a + u_b)/2. With T the map from the given
//! grids' displacements to all nodes' (identity rows for the given grids, ½ ½ for a blank
//! node's corners), u_full = T u, the element matrices are Tᵀ K T and Tᵀ M T. On the shape
//! functions this is the variable-number-of-nodes (transition) element of Bathe, *Finite
//! Element Procedures* (1996) §5.3.1, whose corner functions are N_a + ½ Σ N_m over the blank
//! mid-sides m of the corner's edges: still isoparametric, conforming with a linear neighbour
//! along that edge, and with all 12 (9) mid-sides blank it is the trilinear (linear) element.
//! K stays exactly affine in (λ, μ) since T is constant. Lumped mass lumps the reduced
//! consistent mass (HRZ, as the complete element).

use super::affine::{AffineMatrix, Coefficient};
use super::solid::{
    self, Isotropic, MassLumping, MassParametrization, SolidError, SolidKind,
    StiffnessParametrization,
};
use super::solid_shape::midside_edges;
use faer::Mat;

/// Which nodes of a solid element have a grid.
#[derive(Debug, Clone, PartialEq)]
pub struct Midsides {
    kind: SolidKind,
    /// One flag per node of the complete element, corners first.
    present: Vec<bool>,
}

impl Midsides {
    /// Every node given.
    pub fn complete(kind: SolidKind) -> Self {
        Midsides {
            kind,
            present: vec![true; kind.nodes()],
        }
    }

    /// `present[i]` for each node of the complete element; corners are always present (a false
    /// corner flag is ignored).
    pub fn new(kind: SolidKind, present: &[bool]) -> Self {
        let corners = solid::corners(kind);
        Midsides {
            kind,
            present: (0..kind.nodes())
                .map(|i| i < corners || present.get(i).copied().unwrap_or(true))
                .collect(),
        }
    }

    /// The element topology.
    pub fn kind(&self) -> SolidKind {
        self.kind
    }

    fn is_complete(&self) -> bool {
        self.present.iter().all(|&p| p)
    }

    /// Number of given grids.
    pub fn given(&self) -> usize {
        self.present.iter().filter(|&&p| p).count()
    }

    /// Rows of T: for each node of the complete element, (given grid, weight) pairs.
    fn rows(&self) -> Vec<Vec<(usize, f64)>> {
        let corners = solid::corners(self.kind);
        let edges = midside_edges(self.kind);
        let mut next = 0;
        (0..self.kind.nodes())
            .map(|i| {
                if self.present[i] {
                    next += 1;
                    vec![(next - 1, 1.0)]
                } else {
                    // corners come first and are always given: corner a is given grid a
                    let [a, b] = edges[i - corners];
                    vec![(a, 0.5), (b, 0.5)]
                }
            })
            .collect()
    }

    /// The given grid (its index among the given grids) at the middle of the edge between
    /// corners `a` and `b` (0-based, either order); `None` when that mid-side grid is blank or
    /// the element has none there.
    pub fn edge_midside(&self, a: usize, b: usize) -> Option<usize> {
        let corners = solid::corners(self.kind);
        let m = midside_edges(self.kind)
            .iter()
            .position(|&[p, q]| (p, q) == (a, b) || (p, q) == (b, a))?;
        let node = corners + m;
        self.present[node].then(|| self.present[..node].iter().filter(|&&p| p).count())
    }

    /// Positions of all nodes from the given grids' `xyz` (a blank mid-side at its edge's middle).
    pub fn full_xyz(&self, xyz: &[[f64; 3]]) -> Result<Vec<[f64; 3]>, SolidError> {
        self.check_given(xyz.len())?;
        Ok(self
            .rows()
            .iter()
            .map(|row| {
                std::array::from_fn(|k| row.iter().map(|&(g, w)| w * xyz[g][k]).sum::<f64>())
            })
            .collect())
    }

    /// Translations of all nodes, u_full = T u, from the given grids' `u` (3 per grid).
    pub fn full_u(&self, u: &[f64]) -> Result<Vec<f64>, SolidError> {
        if u.len() != 3 * self.given() {
            return Err(SolidError::DisplacementLength {
                kind: self.kind,
                expected: 3 * self.given(),
                got: u.len(),
            });
        }
        Ok(self
            .rows()
            .iter()
            .flat_map(|row| {
                std::array::from_fn::<f64, 3, _>(|k| {
                    row.iter().map(|&(g, w)| w * u[3 * g + k]).sum()
                })
            })
            .collect())
    }

    fn check_given(&self, got: usize) -> Result<(), SolidError> {
        if got == self.given() {
            Ok(())
        } else {
            Err(SolidError::NodeCount {
                kind: self.kind,
                expected: self.given(),
                got,
            })
        }
    }

    /// Tᵀ M T for a matrix with `block` DOFs per node (3: translations, 1: a scalar mass).
    fn reduce(&self, m: &Mat<f64>, block: usize) -> Mat<f64> {
        if self.is_complete() {
            return m.clone();
        }
        let mut t = Mat::<f64>::zeros(block * self.kind.nodes(), block * self.given());
        for (i, row) in self.rows().iter().enumerate() {
            for &(g, w) in row {
                for c in 0..block {
                    t[(block * i + c, block * g + c)] = w;
                }
            }
        }
        t.transpose() * m * &t
    }

    /// Affine parts of the stiffness over the given grids (3·given × 3·given), as
    /// [`solid::affine_stiffness`] of the complete element reduced by T.
    pub fn affine_stiffness(
        &self,
        xyz: &[[f64; 3]],
        parametrization: StiffnessParametrization,
    ) -> Result<AffineMatrix, SolidError> {
        let full = solid::affine_stiffness(self.kind, &self.full_xyz(xyz)?, parametrization)?;
        Ok(AffineMatrix {
            parts: full
                .parts
                .into_iter()
                .map(|(c, k)| (c, self.reduce(&k, 3)))
                .collect(),
        })
    }

    /// Affine parts of the mass over the given grids: the consistent mass reduced by T, lumped
    /// after the reduction when `lumping` asks for it.
    pub fn affine_mass(
        &self,
        xyz: &[[f64; 3]],
        lumping: MassLumping,
        parametrization: MassParametrization,
    ) -> Result<AffineMatrix, SolidError> {
        let (coefficient, rho) = match parametrization {
            MassParametrization::Fixed { rho } => (Coefficient::Constant, rho),
            MassParametrization::Density => (Coefficient::Rho, 1.0),
        };
        let full = solid::scalar_mass(self.kind, &self.full_xyz(xyz)?, rho)?;
        let mut m = self.reduce(&full, 1);
        if lumping == MassLumping::Lumped {
            solid::lump(self.kind, &mut m);
        }
        Ok(AffineMatrix {
            parts: vec![(coefficient, solid::translational(&m))],
        })
    }

    /// [`solid::strain_at_centroid`] from the given grids' positions and translations.
    pub fn strain_at_centroid(&self, xyz: &[[f64; 3]], u: &[f64]) -> Result<[f64; 6], SolidError> {
        solid::strain_at_centroid(self.kind, &self.full_xyz(xyz)?, &self.full_u(u)?)
    }

    /// [`solid::corner_strains`] from the given grids' positions and translations.
    pub fn corner_strains(
        &self,
        xyz: &[[f64; 3]],
        u: &[f64],
        material: Isotropic,
    ) -> Result<Vec<[f64; 6]>, SolidError> {
        solid::corner_strains(self.kind, &self.full_xyz(xyz)?, &self.full_u(u)?, material)
    }

    /// [`solid::volume_and_centroid`] from the given grids' positions.
    pub fn volume_and_centroid(&self, xyz: &[[f64; 3]]) -> Result<(f64, [f64; 3]), SolidError> {
        solid::volume_and_centroid(self.kind, &self.full_xyz(xyz)?)
    }

    /// [`solid::jacobian_range`] of the complete element from the given grids' positions.
    pub fn jacobian_range(&self, xyz: &[[f64; 3]]) -> Result<solid::JacobianRange, SolidError> {
        solid::jacobian_range(self.kind, &self.full_xyz(xyz)?)
    }
}
