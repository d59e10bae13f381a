//! Nastran's grid-point weight generator (GPWG, `PARAM,GRDPNT`): the rigid-body mass
//! properties of the assembled mass matrix, as the F06 prints them.
//!
//! With D (g × 6) the rigid-body motions about the reference point x₀ in basic — at grid i with
//! r = xᵢ − x₀, translations t − [r×]θ and rotations θ, taken into the grid's displacement
//! frame (Lᵢᵀ, see [`frames`](crate::assembly::frames)) — the rigid-body mass matrix is
//!
//! ```text
//! MO = Dᵀ M_gg D / WTMASS        (6 × 6, basic, about x₀)
//! ```
//!
//! M_gg is the mass the analysis uses (lumped or coupled, CONM2 offsets and inertia, RBE
//! dependent grids included); dividing by WTMASS gives the deck's input mass units, as
//! Nastran's GPWG does. From MO:
//!
//! - S: the principal axes of the translational block MO_tt (the identity when the mass is
//!   the same in every direction, as for elements and CONM2); the mass of direction k is
//!   (Sᵀ MO_tt S)_kk;
//! - the centre of gravity of each direction from the translation–rotation block
//!   M_tr = Sᵀ MO_tθ S: direction X gives y = −M_tr[0][2]/m_x, z = M_tr[0][1]/m_x; Y gives
//!   x = M_tr[1][2]/m_y, z = −M_tr[1][0]/m_y; Z gives x = −M_tr[2][1]/m_z,
//!   y = M_tr[2][0]/m_z, relative to the reference point as the F06 prints them (the
//!   coordinate along the direction itself is not defined: 0);
//! - I(S): the inertia tensor about those centres of gravity, Sᵀ MO_θθ S less the parallel-axis
//!   terms of each direction's mass (I₁₁ = M_θθ,11 − m_y z_y² − m_z y_z², I₁₂ = M_θθ,12 +
//!   m_z x_z y_z, …); off-diagonal entries are the tensor's, −∫xy dm (the F06 prints them with
//!   the opposite sign, as products of inertia ∫xy dm);
//! - I(Q) and Q: the principal inertias (ascending) and their axes (columns, in S).
//!
//! Reference: MSC Nastran Reference Manual, "Grid Point Weight Generator"; the formulas are
//! checked on point masses and a plate in this module's tests and `tests/weight.rs`.

use nalgebra_sparse::CscMatrix;

use crate::assembly::constraints::{frame6, rigid_arm};
use crate::assembly::frames::GridFrames;
use crate::assembly::{AssemblyError, DofMap};
use crate::linalg::dense::{DenseEigenError, symmetric_eigen_vectors};
use crate::linalg::sym_matvec;

/// The GPWG of a mass matrix (see the module documentation).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct WeightSummary {
    /// The reference point x₀ in basic.
    pub reference: [f64; 3],
    /// MO, the 6 × 6 rigid-body mass matrix about x₀ (basic, input mass units).
    pub mo: [[f64; 6]; 6],
    /// S: the mass axes (columns) in basic.
    pub s: [[f64; 3]; 3],
    /// Mass of each direction of S.
    pub mass: [f64; 3],
    /// Centre of gravity of each direction relative to the reference point (rows X, Y, Z of S;
    /// columns x, y, z in S).
    pub cg: [[f64; 3]; 3],
    /// I(S): inertia tensor about the centres of gravity, in S.
    pub inertia: [[f64; 3]; 3],
    /// I(Q): principal inertias, ascending.
    pub principal: [f64; 3],
    /// Q: principal axes (columns) in S.
    pub q: [[f64; 3]; 3],
}

/// Why the GPWG cannot be formed.
#[derive(Debug, thiserror::Error)]
pub enum WeightError {
    #[error(transparent)]
    Assembly(#[from] AssemblyError),
    #[error("grid-point weight generator: {0}")]
    Eigen(#[from] DenseEigenError),
    #[error("grid-point weight generator: {0}")]
    Linalg(#[from] crate::linalg::LinalgError),
}

/// Relative size below which MO_tt's off-diagonal terms and direction differences count as
/// round-off (S = I).
const ISOTROPIC_TOL: f64 = 1e-12;

/// The GPWG of `m_gg` (g × g, the analysis's mass, global frames) about `reference` (basic);
/// `xyz` are the grids' basic positions, `wtmass` the deck's PARAM,WTMASS.
pub fn grid_point_weight(
    m_gg: &CscMatrix<f64>,
    map: &DofMap,
    frames: &GridFrames,
    xyz: &[[f64; 3]],
    reference: [f64; 3],
    wtmass: f64,
) -> Result<WeightSummary, WeightError> {
    let g = map.size();
    crate::assembly::dofs::check_len("GPWG grid positions", map.grids(), xyz.len())?;
    // D column by column: the rigid motion k of every grid in its displacement frame
    let mut d = vec![vec![0.0; g]; 6];
    for (i, x) in xyz.iter().enumerate() {
        let arm = rigid_arm(std::array::from_fn(|c| x[c] - reference[c]));
        let l = frame6(frames, i);
        for (k, column) in d.iter_mut().enumerate() {
            for (r, value) in column[DofMap::grid_dofs(i)].iter_mut().enumerate() {
                // (Lᵀ R)[r][k]
                *value = (0..6).map(|j| l[j][r] * arm[j][k]).sum();
            }
        }
    }
    let mut md = vec![0.0; g];
    let mut mo = [[0.0; 6]; 6];
    for k in 0..6 {
        sym_matvec(m_gg, &d[k], &mut md)?;
        for (j, dj) in d.iter().enumerate() {
            mo[j][k] = dj.iter().zip(&md).map(|(a, b)| a * b).sum::<f64>() / wtmass;
        }
    }
    from_rigid_body_mass(mo, reference)
}

/// The GPWG quantities of a rigid-body mass matrix MO about `reference`.
pub fn from_rigid_body_mass(
    mo: [[f64; 6]; 6],
    reference: [f64; 3],
) -> Result<WeightSummary, WeightError> {
    let block = |r0: usize, c0: usize| -> [[f64; 3]; 3] {
        std::array::from_fn(|i| std::array::from_fn(|j| mo[r0 + i][c0 + j]))
    };
    let (tt, tr, rr) = (block(0, 0), block(0, 3), block(3, 3));
    let s = mass_axes(&tt)?;
    let in_s = |a: &[[f64; 3]; 3]| -> [[f64; 3]; 3] {
        std::array::from_fn(|i| {
            std::array::from_fn(|j| {
                (0..3)
                    .map(|k| (0..3).map(|l| s[k][i] * a[k][l] * s[l][j]).sum::<f64>())
                    .sum()
            })
        })
    };
    let (tt, tr, rr) = (in_s(&tt), in_s(&tr), in_s(&rr));
    let mass = [tt[0][0], tt[1][1], tt[2][2]];
    let over = |x: f64, m: f64| if m == 0.0 { 0.0 } else { x / m };
    let cg = [
        [0.0, over(-tr[0][2], mass[0]), over(tr[0][1], mass[0])],
        [over(tr[1][2], mass[1]), 0.0, over(-tr[1][0], mass[1])],
        [over(-tr[2][1], mass[2]), over(tr[2][0], mass[2]), 0.0],
    ];
    let (mx, my, mz) = (mass[0], mass[1], mass[2]);
    let (yx, zx) = (cg[0][1], cg[0][2]);
    let (xy, zy) = (cg[1][0], cg[1][2]);
    let (xz, yz) = (cg[2][0], cg[2][1]);
    let i11 = rr[0][0] - my * zy * zy - mz * yz * yz;
    let i22 = rr[1][1] - mz * xz * xz - mx * zx * zx;
    let i33 = rr[2][2] - mx * yx * yx - my * xy * xy;
    let i12 = rr[0][1] + mz * xz * yz;
    let i13 = rr[0][2] + my * xy * zy;
    let i23 = rr[1][2] + mx * yx * zx;
    let inertia = [[i11, i12, i13], [i12, i22, i23], [i13, i23, i33]];
    let (principal, q) = symmetric3(&inertia)?;
    Ok(WeightSummary {
        reference,
        mo,
        s,
        mass,
        cg,
        inertia,
        principal,
        q,
    })
}

/// S: the identity when MO_tt is a multiple of it to round-off, its eigenvectors otherwise.
fn mass_axes(tt: &[[f64; 3]; 3]) -> Result<[[f64; 3]; 3], WeightError> {
    let scale = tt.iter().flatten().fold(0.0_f64, |a, x| a.max(x.abs()));
    let off = [tt[0][1], tt[0][2], tt[1][2]];
    let spread = [
        tt[0][0] - tt[1][1],
        tt[1][1] - tt[2][2],
        tt[0][0] - tt[2][2],
    ];
    let isotropic = off
        .iter()
        .chain(&spread)
        .all(|x| x.abs() <= ISOTROPIC_TOL * scale);
    if isotropic {
        return Ok([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]);
    }
    Ok(symmetric3(tt)?.1)
}

/// Ascending eigenvalues and eigenvectors (columns) of a symmetric 3 × 3 matrix.
fn symmetric3(a: &[[f64; 3]; 3]) -> Result<([f64; 3], [[f64; 3]; 3]), DenseEigenError> {
    let m = faer::Mat::from_fn(3, 3, |i, j| a[i][j]);
    let (values, vectors) = symmetric_eigen_vectors(m.as_ref())?;
    Ok((
        std::array::from_fn(|i| values[i]),
        std::array::from_fn(|i| std::array::from_fn(|j| vectors[(i, j)])),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// MO of point masses (m, x) about the origin, written out from the rigid motion:
    /// MO_tt = Σm I, MO_tθ = −Σ m [x×], MO_θθ = Σ m (|x|² I − x xᵀ).
    fn point_masses(points: &[(f64, [f64; 3])]) -> [[f64; 6]; 6] {
        let mut mo = [[0.0; 6]; 6];
        for &(m, x) in points {
            let cross = [[0.0, -x[2], x[1]], [x[2], 0.0, -x[0]], [-x[1], x[0], 0.0]];
            let r2: f64 = x.iter().map(|c| c * c).sum();
            for i in 0..3 {
                mo[i][i] += m;
                for j in 0..3 {
                    mo[i][3 + j] -= m * cross[i][j];
                    mo[3 + j][i] -= m * cross[i][j];
                    let delta = if i == j { 1.0 } else { 0.0 };
                    mo[3 + i][3 + j] += m * (r2 * delta - x[i] * x[j]);
                }
            }
        }
        mo
    }

    #[test]
    fn one_point_mass_has_its_position_as_every_cg_and_no_inertia() {
        let x = [0.3, -1.2, 2.5];
        let w = from_rigid_body_mass(point_masses(&[(4.0, x)]), [0.0; 3]).unwrap();
        assert_eq!(w.mass, [4.0; 3]);
        let cg = [[0.0, x[1], x[2]], [x[0], 0.0, x[2]], [x[0], x[1], 0.0]];
        for (a, b) in w.cg.iter().flatten().zip(cg.iter().flatten()) {
            assert!((a - b).abs() < 1e-14, "{:?}", w.cg);
        }
        assert!(
            w.inertia.iter().flatten().all(|v| v.abs() < 1e-13),
            "{:?}",
            w.inertia
        );
    }

    /// Two masses on a line along x at ±a: about their CG, I = diag(0, 2ma², 2ma²) whatever
    /// the line's offset from the reference point.
    #[test]
    fn dumbbell_inertia_about_its_cg() {
        let (m, a, c) = (1.5, 0.4, [2.0, 1.0, -3.0]);
        let at = |s: f64| [c[0] + s * a, c[1], c[2]];
        let w =
            from_rigid_body_mass(point_masses(&[(m, at(1.0)), (m, at(-1.0))]), [0.0; 3]).unwrap();
        let want = [
            [0.0, 0.0, 0.0],
            [0.0, 2.0 * m * a * a, 0.0],
            [0.0, 0.0, 2.0 * m * a * a],
        ];
        for (r, row) in w.inertia.iter().enumerate() {
            for (k, v) in row.iter().enumerate() {
                assert!((v - want[r][k]).abs() < 1e-13, "{:?}", w.inertia);
            }
        }
        assert!((w.principal[0]).abs() < 1e-13 && (w.principal[2] - 2.0 * m * a * a).abs() < 1e-13);
        assert!((w.cg[1][0] - c[0]).abs() < 1e-14 && (w.cg[0][2] - c[2]).abs() < 1e-14);
    }

    /// A product of inertia: masses at (a, b, 0) and (−a, −b, 0) give I₁₂ = −2mab about the CG.
    #[test]
    fn product_of_inertia_has_the_tensor_sign() {
        let (m, a, b) = (2.0, 0.5, 0.25);
        let w = from_rigid_body_mass(
            point_masses(&[(m, [a, b, 0.0]), (m, [-a, -b, 0.0])]),
            [0.0; 3],
        )
        .unwrap();
        assert!(
            (w.inertia[0][1] + 2.0 * m * a * b).abs() < 1e-14,
            "{:?}",
            w.inertia
        );
        assert!((w.inertia[2][2] - 2.0 * m * (a * a + b * b)).abs() < 1e-14);
    }

    /// Mass that differs by direction (a scalar mass on one axis) turns S away from I.
    #[test]
    fn anisotropic_translational_mass_gets_its_own_axes() {
        let mut mo = point_masses(&[(1.0, [0.0; 3])]);
        mo[0][0] += 1.0;
        mo[0][1] += 1.0;
        mo[1][0] += 1.0;
        mo[1][1] += 1.0;
        let w = from_rigid_body_mass(mo, [0.0; 3]).unwrap();
        let mut masses = w.mass;
        masses.sort_by(f64::total_cmp);
        assert!((masses[0] - 1.0).abs() < 1e-14 && (masses[2] - 3.0).abs() < 1e-14);
        // the heavy axis is (1, 1, 0)/√2
        let heavy = (0..3)
            .max_by(|&i, &j| w.mass[i].total_cmp(&w.mass[j]))
            .unwrap();
        assert!((w.s[0][heavy].abs() - 0.5_f64.sqrt()).abs() < 1e-12);
    }
}
