//! Modal coordinates for the filter: when every part of the pROM that the estimated parameters
//! change is diagonal in the modes of the initial estimate, the filter runs on z (q = Φ z) with
//! diagonal matrices (see [`super::filter`]).
//!
//! Φ are the M-orthonormal modes of K_r, M_r at the initial parameters p₀ (Φᵀ M₀ Φ = I,
//! Φᵀ K₀ Φ = Λ). The pROM's components are split into those whose function depends on an
//! estimated parameter (each kept on its own: its weight changes with the estimate) and the
//! others, summed at p₀ into one constant part. Each is transformed (Φᵀ A Φ) and accepted when
//! its coupling ratios |Ã_ab| / √(|Ã_aa| |Ã_bb|) (≤ 1 for a semi-definite Ã, Cauchy–Schwarz)
//! stay below [`DIAGONAL_TOLERANCE`]; entries below the round-off of the transform,
//! n ε max|Ã|, are no coupling (between two soft modes of a stiff pROM the ratio of pure
//! round-off reaches ε λ_max/λ_min: 9e-10 on the clamped blade). This is the case of E and ρ of one material (K ∝ E,
//! M ∝ ρ: thesis §3.4.2) and of any pROM without estimated parameters; it is not the case of
//! two materials or of E entering through separate Lamé parts λ, μ (each part on its own is not
//! diagonal), where the filter keeps the physical coordinates.

use faer::Mat;

use crate::linalg::dense::generalized_eigen;
use crate::rom::prom::Prom;

/// Largest coupling ratio |Ã_ab| / √(|Ã_aa| |Ã_bb|) of a transformed component accepted as
/// diagonal (entries above the transform's round-off). A component proportional to M₀ or K₀
/// has none left, a genuinely coupling one (the bolt springs of the blade pROM, another
/// material, a Lamé part) ratios ≳ 1e-3 (0.93 on the blade); dropping couplings below 1e-9 changes the model by
/// less than 1e-9 relative in the energy norm, far below any measurement noise.
pub const DIAGONAL_TOLERANCE: f64 = 1e-9;

/// The pROM in modal coordinates.
#[derive(Debug, Clone)]
pub struct ModalForm {
    /// Φ (n × n) and Φ⁻¹ = Φᵀ M₀.
    pub basis: Mat<f64>,
    pub inverse: Mat<f64>,
    /// Diagonal parts: the affine function (None: the constant sum of the parts no estimated
    /// parameter changes), diag(Φᵀ K_i Φ), diag(Φᵀ M_i Φ).
    pub parts: Vec<(Option<usize>, Vec<f64>, Vec<f64>)>,
    /// Largest coupling ratio found above round-off (≤ [`DIAGONAL_TOLERANCE`]).
    pub coupling: f64,
}

/// The modal form of `prom` for the estimated parameters `unknown` from `p`, or `None` when a
/// part that changes is not diagonal in the modes (or the modes cannot be computed: the
/// physical path then reports the problem).
pub fn modal_form(prom: &Prom, p: &[f64], unknown: &[usize]) -> Option<ModalForm> {
    let mut at = prom.workspace();
    prom.evaluate(p, &mut at).ok()?;
    let (_, basis) = generalized_eigen(at.stiffness(), at.mass()).ok()?;
    let inverse = basis.transpose() * at.mass();
    let n = prom.size();
    let (mut k_fixed, mut m_fixed) = (Mat::<f64>::zeros(n, n), Mat::<f64>::zeros(n, n));
    let mut varying = Vec::new();
    for (i, f) in prom.functions.iter().enumerate() {
        if f.driven_by.iter().any(|(_, j)| unknown.contains(j)) {
            varying.push(i);
        } else {
            let w = faer::Scale(f.value(p));
            k_fixed += &prom.stiffness[i] * w;
            m_fixed += &prom.mass[i] * w;
        }
    }
    let mut coupling = 0.0_f64;
    let mut diagonal = |a: &Mat<f64>| -> Option<Vec<f64>> {
        let t = basis.transpose() * a * &basis;
        let roundoff = n as f64 * f64::EPSILON * t.norm_max();
        for j in 0..n {
            for i in 0..n {
                let (off, scale) = (t[(i, j)].abs(), (t[(i, i)] * t[(j, j)]).abs().sqrt());
                if i != j && off > roundoff {
                    let ratio = if scale > 0.0 { off / scale } else { f64::INFINITY };
                    coupling = coupling.max(ratio);
                }
            }
        }
        (coupling <= DIAGONAL_TOLERANCE).then(|| (0..n).map(|i| t[(i, i)]).collect())
    };
    let mut parts = vec![(None, diagonal(&k_fixed)?, diagonal(&m_fixed)?)];
    for i in varying {
        parts.push((Some(i), diagonal(&prom.stiffness[i])?, diagonal(&prom.mass[i])?));
    }
    Some(ModalForm { basis, inverse, parts, coupling })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::estimate::filter::tests::chain;

    /// The chain of the filter tests: with its grounded spring (a part E does not scale) E is
    /// not diagonal in the modes; without it (one material) E and ρ are; with nothing estimated
    /// every pROM is.
    #[test]
    fn one_material_is_diagonal_and_a_second_spring_is_not() {
        let two = chain();
        assert!(modal_form(&two, &[1.2, 0.9], &[0, 1]).is_none());
        assert!(modal_form(&two, &[1.2, 0.9], &[1]).is_some(), "ρ alone scales all of M");
        assert!(modal_form(&two, &[1.2, 0.9], &[]).is_some());
        let mut one = chain();
        one.stiffness[0].fill(0.0);
        let form = modal_form(&one, &[1.2, 0.9], &[0, 1]).unwrap();
        assert!(form.coupling <= 1e-13, "{}", form.coupling);
        // Φ⁻¹ Φ = I
        let eye = &form.inverse * &form.basis;
        assert!((0..2).all(|i| (0..2).all(|j| (eye[(i, j)] - if i == j { 1.0 } else { 0.0 }).abs() <= 1e-13)));
    }
}
