//! Affine nodal masses of a pROM body for the multibody step (thesis §4.2, eq. 4.1–4.3); the
//! mass invariants built from them are in [`super::invariants`].
//!
//! The mass matrix of the pROM is affine, M(p) = Σ_k f_k(p) M^k (eq. 3.26), so the nodal masses
//! are affine with the same functions: m_j(p) = Σ_k f_k(p) m_j^k (eq. 4.1), and so are the total
//! mass m(p) = Σ_j m_j(p) (eq. 4.2) and every mass invariant Σ_j m_j h_j (eq. 4.8). The thesis
//! identifies m_j^k by least squares over the samples (eq. 4.3) because its matrices come from
//! a black box; here each component is lumped directly from the assembled part M^k, which is
//! what eq. 4.3 recovers from exact samples.
//!
//! Lumping: m_j^k = ⅓ Σ_d e_{j,d}ᵀ M^k r_d, with r_d the rigid translation along basic axis d
//! and e_{j,d} the translation of grid j along d (row-sum lumping of the translational block;
//! grid displacement frames rotated to basic). For isoparametric elements this is ∫ρ N_j dV,
//! which keeps the total mass and the centre of mass exact; a CONM2 contributes its m.

use crate::assembly::{AffineOperator, AssemblyError, GridFrames, ParamKey};

/// The affine nodal masses of a body.
#[derive(Debug, Clone, PartialEq)]
pub struct AffineMasses {
    /// Undeformed grid positions r_0,j in basic (one per grid of the model).
    pub positions: Vec<[f64; 3]>,
    /// m_j^k: one row per affine component k (the pROM's function order), one value per grid.
    pub nodal: Vec<Vec<f64>>,
}

impl AffineMasses {
    /// Lump the parts of the g-set mass operator `mass` listed in `keys` (a key the operator
    /// lacks gives zero masses) on grids at `positions` with displacement frames `frames`.
    pub fn lump(
        mass: &AffineOperator,
        keys: &[ParamKey],
        frames: &GridFrames,
        positions: Vec<[f64; 3]>,
    ) -> Result<Self, AssemblyError> {
        let n_grids = positions.len();
        let size = mass.ncols();
        let rigid: Vec<Vec<f64>> = (0..3)
            .map(|d| {
                let mut r = vec![0.0; size];
                let axis: [f64; 3] = std::array::from_fn(|i| f64::from(u8::from(i == d)));
                for grid in 0..n_grids {
                    r[6 * grid..6 * grid + 3].copy_from_slice(&frames.to_global(grid, axis));
                }
                r
            })
            .collect();
        let nodal = keys
            .iter()
            .map(|&key| -> Result<Vec<f64>, AssemblyError> {
                let Some(values) = mass.part(key) else {
                    return Ok(vec![0.0; n_grids]);
                };
                let mut m = vec![0.0; n_grids];
                for (d, r) in rigid.iter().enumerate() {
                    let force = mass.mul_values(values, r)?;
                    for (grid, mj) in m.iter_mut().enumerate() {
                        *mj += frames.to_basic(
                            grid,
                            [force[6 * grid], force[6 * grid + 1], force[6 * grid + 2]],
                        )[d] / 3.0;
                    }
                }
                Ok(m)
            })
            .collect::<Result<_, _>>()?;
        Ok(AffineMasses { positions, nodal })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rom::invariants::{MassInvariants, TranslationRows};
    use std::sync::Arc;

    /// Two grids, one part: a 12 × 12 diagonal mass with translational masses 2 (grid 0) and
    /// 5 (grid 1, its frame rotated 90° about z) and rotational inertias that must not count.
    #[test]
    fn lumps_translational_masses_in_basic_and_their_moments() {
        let n = 12;
        let pattern = nalgebra_sparse::pattern::SparsityPattern::try_from_offsets_and_indices(
            n,
            n,
            (0..=n).collect(),
            (0..n).collect(),
        )
        .unwrap();
        let values: Vec<f64> = (0..n)
            .map(|i| {
                if i % 6 < 3 {
                    if i < 6 { 2.0 } else { 5.0 }
                } else {
                    100.0
                }
            })
            .collect();
        let op = AffineOperator::from_parts(Arc::new(pattern), vec![(ParamKey::Constant, values)])
            .unwrap();
        let frames = GridFrames::from_rotations(vec![
            None,
            Some([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]),
        ]);
        let m = AffineMasses::lump(
            &op,
            &[ParamKey::Constant],
            &frames,
            vec![[0.0, 0.0, 0.0], [1.0, 2.0, 0.0]],
        )
        .unwrap();
        assert_eq!(m.nodal, vec![vec![2.0, 5.0]]);
        // the rigid invariants of these masses (no basis columns)
        let no_columns = TranslationRows {
            axes: std::array::from_fn(|_| faer::Mat::zeros(2, 0)),
        };
        let inv = MassInvariants::new(&m.nodal[0], &m.positions, &no_columns);
        assert_eq!((inv.mass, inv.m1), (7.0, [5.0, 10.0, 0.0]));
        // 5 · (r rᵀ − |r|² I) with r = (1, 2, 0), |r|² = 5
        assert_eq!(
            inv.m3,
            [[-20.0, 10.0, 0.0], [10.0, -5.0, 0.0], [0.0, 0.0, -25.0]]
        );
    }
}
