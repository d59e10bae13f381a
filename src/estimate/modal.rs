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
//!
//! **Coupled parts** ([`modal_form`] with `coupled`): a changing part that is not diagonal (E of
//! the bolted blade besides its constant bolt springs) keeps its off-diagonal Ã − diag(Ã).
//! At p₀ the parts sum to the diagonal Λ, so the off-diagonal of Ã(p) = Σ f_i(p) Ã_i is
//! Σ (f_i(p) − f_i(p₀)) (Ã_i − diag Ã_i), small while the estimate stays near p₀ (the constant
//! part's off-diagonal cancels the changing parts' at p₀ up to the eigensolver's round-off and is
//! dropped). The filter then re-computes the modes when the weights have drifted.
use faer::Mat;

use crate::linalg::dense::{generalized_eigen, product};
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
    /// Largest coupling ratio found above round-off (≤ [`DIAGONAL_TOLERANCE`] unless
    /// `couplings` holds the parts above it).
    pub coupling: f64,
    /// Changing parts that are not diagonal: their off-diagonal parts.
    pub couplings: Vec<Coupling>,
}

/// A changing pROM part that is not diagonal in the modes (see the module documentation).
#[derive(Debug, Clone)]
pub struct Coupling {
    /// The pROM component (index of its affine function).
    pub function: usize,
    /// Its weight f_i(p₀) at the parameters of the modes.
    pub reference: f64,
    /// Φᵀ K_i Φ and Φᵀ M_i Φ without their diagonals (n × n; `None`: that one is diagonal).
    pub stiffness: Option<Mat<f64>>,
    pub mass: Option<Mat<f64>>,
}

impl Coupling {
    /// |f_i(p) − f_i(p₀)| / |f_i(p₀)|: how far the part's weight has moved from the modes'.
    pub fn drift(&self, weight: f64) -> f64 {
        (weight - self.reference).abs() / self.reference.abs().max(f64::MIN_POSITIVE)
    }
}

/// The modal form of `prom` for the estimated parameters `unknown` from `p`, or `None` when a
/// part that changes is not diagonal in the modes and `coupled` is false (or the modes cannot be
/// computed: the physical path then reports the problem). With `coupled`, such parts are kept
/// as [`Coupling`]s.
pub fn modal_form(prom: &Prom, p: &[f64], unknown: &[usize], coupled: bool) -> Option<ModalForm> {
    let mut at = prom.workspace();
    prom.evaluate(p, &mut at).ok()?;
    let (_, basis) = generalized_eigen(at.stiffness(), at.mass()).ok()?;
    let inverse = product(basis.transpose(), at.mass());
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
    // Φᵀ A Φ, its diagonal and, when it couples, itself with the diagonal zeroed
    let transform = |a: &Mat<f64>| -> (Vec<f64>, f64, Mat<f64>) {
        let mut t = product(product(basis.transpose(), a.as_ref()).as_ref(), basis.as_ref());
        let roundoff = n as f64 * f64::EPSILON * t.norm_max();
        let mut coupling = 0.0_f64;
        for j in 0..n {
            for i in 0..n {
                let (off, scale) = (t[(i, j)].abs(), (t[(i, i)] * t[(j, j)]).abs().sqrt());
                if i != j && off > roundoff {
                    coupling = coupling.max(if scale > 0.0 { off / scale } else { f64::INFINITY });
                }
            }
        }
        let diagonal = (0..n).map(|i| t[(i, i)]).collect();
        (0..n).for_each(|i| t[(i, i)] = 0.0);
        (diagonal, coupling, t)
    };
    let mut coupling = 0.0_f64;
    let mut parts = Vec::new();
    let mut couplings = Vec::new();
    for (function, k, m) in std::iter::once((None, &k_fixed, &m_fixed)).chain(varying.iter().map(|&i| (Some(i), &prom.stiffness[i], &prom.mass[i]))) {
        let ((k_diag, k_coupling, k_off), (m_diag, m_coupling, m_off)) = (transform(k), transform(m));
        coupling = coupling.max(k_coupling).max(m_coupling);
        let off = |c: f64, t: Mat<f64>| (c > DIAGONAL_TOLERANCE).then_some(t);
        let (stiffness, mass) = (off(k_coupling, k_off), off(m_coupling, m_off));
        let couples = stiffness.is_some() || mass.is_some();
        if couples && !coupled {
            return None;
        }
        // the constant part's off-diagonal is dropped (module documentation)
        if let (Some(i), true) = (function, couples) {
            couplings.push(Coupling { function: i, reference: prom.functions[i].value(p), stiffness, mass });
        }
        parts.push((function, k_diag, m_diag));
    }
    Some(ModalForm { basis, inverse, parts, coupling, couplings })
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
        assert!(modal_form(&two, &[1.2, 0.9], &[0, 1], false).is_none());
        assert!(modal_form(&two, &[1.2, 0.9], &[1], false).is_some(), "ρ alone scales all of M");
        assert!(modal_form(&two, &[1.2, 0.9], &[], false).is_some());
        let mut one = chain();
        one.stiffness[0].fill(0.0);
        let form = modal_form(&one, &[1.2, 0.9], &[0, 1], false).unwrap();
        assert!(form.coupling <= 1e-13 && form.couplings.is_empty(), "{}", form.coupling);
        // Φ⁻¹ Φ = I
        let eye = &form.inverse * &form.basis;
        assert!((0..2).all(|i| (0..2).all(|j| (eye[(i, j)] - if i == j { 1.0 } else { 0.0 }).abs() <= 1e-13)));
    }

    /// With `coupled`, the bolted-chain E part (beside its constant grounded spring) is kept as
    /// a coupling, ρ's part (all of M) stays diagonal, and the form reproduces Φᵀ K(p) Φ and
    /// Φᵀ M(p) Φ away from p₀ as diagonal parts + Σ (f_i(p) − f_i(p₀)) off-diagonals: exact up to
    /// the round-off of the modes (the dropped constant off-diagonal), bound 1e-12 of max |Ã|.
    #[test]
    fn coupled_parts_reproduce_the_transformed_matrices_away_from_the_modes_parameters() {
        let prom = chain();
        let p0 = [1.2, 0.9];
        let form = modal_form(&prom, &p0, &[0, 1], true).expect("coupled form");
        assert_eq!(form.couplings.len(), 1);
        let c = &form.couplings[0];
        assert!(c.stiffness.is_some() && c.mass.is_none() && prom.functions[c.function].driven_by[0].1 == 0);
        let p = [1.5, 0.7];
        let mut at = prom.workspace();
        prom.evaluate(&p, &mut at).unwrap();
        for (which, exact) in [("K", at.stiffness()), ("M", at.mass())] {
            let exact = form.basis.transpose() * exact * &form.basis;
            let mut model = Mat::<f64>::zeros(2, 2);
            for (function, k, m) in &form.parts {
                let w = function.map_or(1.0, |i| prom.functions[i].value(&p));
                (0..2).for_each(|i| model[(i, i)] += w * if which == "K" { k[i] } else { m[i] });
            }
            for c in &form.couplings {
                if let Some(off) = if which == "K" { &c.stiffness } else { &c.mass } {
                    model += off * faer::Scale(prom.functions[c.function].value(&p) - c.reference);
                }
            }
            let scale = exact.norm_max();
            assert!((&exact - &model).norm_max() <= 1e-12 * scale, "{which}: {:e}", (&exact - &model).norm_max());
        }
    }
}
