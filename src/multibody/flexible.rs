//! The reduced data a flexible body is built from, evaluated at the parameters p (the pROM
//! artifact's affine sums m(p) = m⁰ + Σₖ mᵏ fᵏ(p), eq. 4.1–4.3 and 4.8, are formed by its
//! loader): mass moments, reduced M_ff, K_ff, C_ff and the basis rows of the interface grids.
//!
//! The nine mass invariants of eq. A.11–A.19 are linear images of five nodal sums (with
//! r₀ⱼ the undeformed node position, ψⱼₖ the translation row of node j for mode k, and
//! r̃ s̃ = s rᵀ − (rᵀs) I):
//!
//! | stored | sum | invariants it gives |
//! |---|---|---|
//! | `first` | Σ mⱼ r₀ⱼ | M̂₁ (A.11) |
//! | `first_modal[k]` | Σ mⱼ ψⱼₖ | M̂₂ (A.12), column k |
//! | `second` | Σ mⱼ r₀ⱼ r₀ⱼᵀ | M̂₃ = `second` − tr(`second`) I (A.13) |
//! | `second_mixed[k]` | Σ mⱼ r₀ⱼ ψⱼₖᵀ | M̂₄ (A.14), M̂₆ (A.16), M̂₈ₖ = tr (A.18) |
//! | `second_modal[k n + l]` | Σ mⱼ ψⱼₖ ψⱼₗᵀ | M̂₅ (A.15), M̂₇ (A.17), M̂₉ₖₗ = tr (A.19) |
//!
//! The outer-product form is what the mass matrix and the quadratic velocity vector of
//! [`super::inertia`] contract with, without the skew matrices of the appendix.

use crate::geometry::mat3::Mat3;
use faer::Mat;

/// Mass moments of a body about its frame origin, in body components (see module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct MassInvariants {
    /// Total mass m (eq. 4.2).
    pub mass: f64,
    /// Σ mⱼ r₀ⱼ (M̂₁, eq. A.11).
    pub first: [f64; 3],
    /// Σ mⱼ ψⱼₖ for each mode k (the columns of M̂₂, eq. A.12).
    pub first_modal: Vec<[f64; 3]>,
    /// Σ mⱼ r₀ⱼ r₀ⱼᵀ.
    pub second: Mat3,
    /// Σ mⱼ r₀ⱼ ψⱼₖᵀ for each mode k.
    pub second_mixed: Vec<Mat3>,
    /// Σ mⱼ ψⱼₖ ψⱼₗᵀ at index k·n + l.
    pub second_modal: Vec<Mat3>,
}

/// One node of a body for [`MassInvariants::from_nodes`]: its mass, undeformed position in the
/// body frame and translation basis row per mode (ψⱼₖ, a 3-vector for each mode k).
#[derive(Debug, Clone, PartialEq)]
pub struct NodalMass {
    pub mass: f64,
    pub position: [f64; 3],
    pub modes: Vec<[f64; 3]>,
}

impl MassInvariants {
    /// Number of flexible coordinates n.
    pub fn modes(&self) -> usize {
        self.first_modal.len()
    }

    /// A rigid body with its frame at the centre of mass: mass m and inertia tensor J about the
    /// centre of mass in body components, whose second moment is Σ m r rᵀ = ½ tr(J) I − J.
    pub fn rigid(mass: f64, inertia: Mat3) -> Self {
        let half_trace = 0.5 * (inertia[0][0] + inertia[1][1] + inertia[2][2]);
        let second = std::array::from_fn(|i| {
            std::array::from_fn(|j| if i == j { half_trace } else { 0.0 } - inertia[i][j])
        });
        Self {
            mass,
            first: [0.0; 3],
            first_modal: Vec::new(),
            second,
            second_mixed: Vec::new(),
            second_modal: Vec::new(),
        }
    }

    /// The sums of eq. 2.51 over lumped nodal masses (all nodes must have the same number of
    /// modes), through the appendix-A invariants of [`crate::rom::invariants`], the one
    /// implementation of the nodal sums.
    pub fn from_nodes(nodes: &[NodalMass]) -> Self {
        use crate::rom::invariants::{MassInvariants as AppendixInvariants, TranslationRows};
        let n = nodes.first().map_or(0, |node| node.modes.len());
        let rows = TranslationRows {
            axes: std::array::from_fn(|a| {
                Mat::from_fn(nodes.len(), n, |j, k| nodes[j].modes[k][a])
            }),
        };
        let masses: Vec<f64> = nodes.iter().map(|node| node.mass).collect();
        let positions: Vec<[f64; 3]> = nodes.iter().map(|node| node.position).collect();
        Self::from(&AppendixInvariants::new(&masses, &positions, &rows))
    }
}

/// The basis rows of one interface grid: undeformed position in the body frame, and per mode
/// the translation ψₖ and the small rotation θₖ of the grid (3-vectors in body components).
#[derive(Debug, Clone, PartialEq)]
pub struct InterfaceRows {
    pub grid: u32,
    pub position: [f64; 3],
    pub translation: Vec<[f64; 3]>,
    pub rotation: Vec<[f64; 3]>,
}

/// A flexible body's reduced data at one parameter point (what a pROM loader fills).
#[derive(Debug, Clone)]
pub struct FlexibleBodyData {
    pub invariants: MassInvariants,
    /// Reduced mass matrix M_ff (n × n).
    pub mass: Mat<f64>,
    /// Reduced stiffness K_ff (eq. 2.54).
    pub stiffness: Mat<f64>,
    /// Reduced damping C_ff (eq. 2.55).
    pub damping: Mat<f64>,
    /// Basis rows of the grids markers may be placed on.
    pub interfaces: Vec<InterfaceRows>,
}

impl From<&crate::rom::invariants::MassInvariants> for MassInvariants {
    /// The outer-product sums from the invariants M̂₁ … M̂₉ of appendix A as a pROM artifact
    /// stores them: with r̃ s̃ = s rᵀ − (rᵀs) I, Σ m r rᵀ = M̂₃ − ½ tr(M̂₃) I,
    /// Σ m r ψₖᵀ = (M̂₄ₖ + M̂₈ₖ I)ᵀ and Σ m ψₖ ψₗᵀ = (M̂₅ₖₗ + M̂₉ₖₗ I)ᵀ.
    fn from(inv: &crate::rom::invariants::MassInvariants) -> Self {
        let n = inv.size();
        let plus_diagonal_transposed = |a: &Mat3, d: f64| -> Mat3 {
            std::array::from_fn(|i| std::array::from_fn(|j| a[j][i] + if i == j { d } else { 0.0 }))
        };
        let half_trace = 0.5 * (inv.m3[0][0] + inv.m3[1][1] + inv.m3[2][2]);
        Self {
            mass: inv.mass,
            first: inv.m1,
            first_modal: (0..n)
                .map(|k| std::array::from_fn(|a| inv.m2[(a, k)]))
                .collect(),
            second: plus_diagonal_transposed(&inv.m3, -half_trace),
            second_mixed: (0..n)
                .map(|k| plus_diagonal_transposed(&inv.m4[k], inv.m8[k]))
                .collect(),
            second_modal: (0..n * n)
                .map(|kl| plus_diagonal_transposed(&inv.m5[kl], inv.m9[(kl / n, kl % n)]))
                .collect(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::random::SplitMix64;

    /// The outer-product sums of random nodes through the appendix invariants equal the sums
    /// taken directly over the nodes: the conversion is exact (bound 1e-12 relative, a few
    /// additions per entry).
    #[test]
    fn appendix_invariants_convert_to_the_outer_product_sums() {
        let (n_g, n) = (9, 3);
        let mut rng = SplitMix64::new(5);
        let nodes: Vec<NodalMass> = (0..n_g)
            .map(|_| NodalMass {
                mass: 0.2 + rng.unit(),
                position: [0.0; 3].map(|_| rng.symmetric()),
                modes: (0..n).map(|_| [0.0; 3].map(|_| rng.symmetric())).collect(),
            })
            .collect();
        let via = MassInvariants::from_nodes(&nodes);
        let outer = |a: [f64; 3], b: [f64; 3], m: f64| -> Mat3 {
            std::array::from_fn(|i| std::array::from_fn(|j| m * a[i] * b[j]))
        };
        let sum = |terms: Vec<Mat3>| -> Mat3 {
            terms.iter().fold([[0.0; 3]; 3], |acc, t| {
                std::array::from_fn(|i| std::array::from_fn(|j| acc[i][j] + t[i][j]))
            })
        };
        let direct = MassInvariants {
            mass: nodes.iter().map(|x| x.mass).sum(),
            first: std::array::from_fn(|a| nodes.iter().map(|x| x.mass * x.position[a]).sum()),
            first_modal: (0..n)
                .map(|k| {
                    std::array::from_fn(|a| nodes.iter().map(|x| x.mass * x.modes[k][a]).sum())
                })
                .collect(),
            second: sum(nodes
                .iter()
                .map(|x| outer(x.position, x.position, x.mass))
                .collect()),
            second_mixed: (0..n)
                .map(|k| {
                    sum(nodes
                        .iter()
                        .map(|x| outer(x.position, x.modes[k], x.mass))
                        .collect())
                })
                .collect(),
            second_modal: (0..n * n)
                .map(|kl| {
                    sum(nodes
                        .iter()
                        .map(|x| outer(x.modes[kl / n], x.modes[kl % n], x.mass))
                        .collect())
                })
                .collect(),
        };
        let close =
            |a: f64, b: f64| assert!((a - b).abs() <= 1e-12 * (1.0 + b.abs()), "{a} vs {b}");
        close(via.mass, direct.mass);
        let flat = |m: &MassInvariants| -> Vec<f64> {
            let mut v = m.first.to_vec();
            v.extend(m.first_modal.iter().flatten());
            v.extend(m.second.iter().flatten());
            v.extend(m.second_mixed.iter().flatten().flatten());
            v.extend(m.second_modal.iter().flatten().flatten());
            v
        };
        let (a, b) = (flat(&via), flat(&direct));
        assert_eq!(a.len(), b.len());
        a.iter().zip(&b).for_each(|(x, y)| close(*x, *y));
    }
}
