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
//!
//! **Low-rank couplings** ([`OffDiagonal::LowRank`]). When one changing part is the only one
//! that couples in its matrix, that same cancellation gives its off-diagonal as −1/f_i(p₀) times
//! the constant part's, and the constant part is often of low rank: a few springs, bushings or
//! point masses beside the material that is estimated (the blade's bolts: rank 6 in n = 36).
//! Φᵀ A_c Φ = V Θ Vᵀ then keeps its r eigenpairs above round-off, and a product with the
//! coupling costs 2 n r + n multiply-adds instead of n²; it is used when that is fewer.
use faer::Mat;

use super::kernels::{add_product, axpy, dot};
use crate::linalg::dense::{generalized_eigen, product, symmetric_eigen_vectors};
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
    /// Φᵀ K_i Φ and Φᵀ M_i Φ without their diagonals (`None`: that one is diagonal).
    pub stiffness: Option<OffDiagonal>,
    pub mass: Option<OffDiagonal>,
}

/// The off-diagonal part Ã − diag(Ã) of a coupled pROM part in the modes.
#[derive(Debug, Clone)]
pub enum OffDiagonal {
    /// Stored whole (n × n, zero diagonal).
    Dense(Mat<f64>),
    /// V diag(θ) Vᵀ − diag(V diag(θ) Vᵀ) with V n × r (module documentation): `diagonal` holds
    /// diag(V diag(θ) Vᵀ).
    LowRank {
        vectors: Mat<f64>,
        values: Vec<f64>,
        diagonal: Vec<f64>,
    },
}

impl OffDiagonal {
    /// out += scale · (Ã − diag Ã) x.
    pub fn add_product(&self, x: &[f64], out: &mut [f64], scale: f64) {
        match self {
            OffDiagonal::Dense(a) => add_product(a, x, out, scale),
            OffDiagonal::LowRank {
                vectors,
                values,
                diagonal,
            } => {
                for (k, value) in values.iter().enumerate() {
                    let v = vectors.col_as_slice(k);
                    axpy(out, scale * value * dot(v, x), v);
                }
                out.iter_mut()
                    .zip(diagonal.iter().zip(x))
                    .for_each(|(o, (d, x))| *o -= scale * d * x);
            }
        }
    }

    /// −`factor` times the off-diagonal of the symmetric `a` as [`OffDiagonal::LowRank`] when
    /// its eigenvalues above the round-off n ε max |θ| are few enough that 2 n r + n < n².
    fn low_rank(a: &Mat<f64>, factor: f64) -> Option<OffDiagonal> {
        let n = a.nrows();
        let (theta, v) = symmetric_eigen_vectors(a.as_ref()).ok()?;
        let largest = theta.iter().fold(0.0_f64, |m, t| m.max(t.abs()));
        let keep: Vec<usize> = (0..n)
            .filter(|&k| theta[k].abs() > n as f64 * f64::EPSILON * largest)
            .collect();
        if 2 * keep.len() + 1 >= n {
            return None;
        }
        let vectors = Mat::from_fn(n, keep.len(), |i, c| v[(i, keep[c])]);
        Some(OffDiagonal::from_factor(
            vectors,
            keep.iter().map(|&k| -factor * theta[k]).collect(),
        ))
    }

    /// V diag(θ) Vᵀ − diag(V diag(θ) Vᵀ) as [`OffDiagonal::LowRank`].
    fn from_factor(vectors: Mat<f64>, values: Vec<f64>) -> OffDiagonal {
        let diagonal = (0..vectors.nrows())
            .map(|i| {
                values
                    .iter()
                    .enumerate()
                    .map(|(c, t)| t * vectors[(i, c)] * vectors[(i, c)])
                    .sum()
            })
            .collect();
        OffDiagonal::LowRank {
            vectors,
            values,
            diagonal,
        }
    }
}

impl Coupling {
    /// Its off-diagonal part in M̃ (`mass`) or K̃.
    fn part(&self, mass: bool) -> &Option<OffDiagonal> {
        if mass { &self.mass } else { &self.stiffness }
    }

    /// [`Coupling::part`], mutable.
    fn part_mut(&mut self, mass: bool) -> &mut Option<OffDiagonal> {
        if mass {
            &mut self.mass
        } else {
            &mut self.stiffness
        }
    }

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
    form(prom, p, unknown, coupled, None)
}

/// [`modal_form`] with couplings at new parameters `p` after the form `previous` (a
/// re-diagonalization): a low-rank coupling's factor is carried over to the new modes,
/// V₂ = Φ₂ᵀ Φ₁⁻ᵀ V₁ (the constant part, Φ₁⁻ᵀ V₁ Θ V₁ᵀ Φ₁⁻¹, does not change with the estimate),
/// n² r multiply-adds instead of an eigendecomposition; a dense coupling stays dense.
pub fn modal_form_after(
    prom: &Prom,
    p: &[f64],
    unknown: &[usize],
    previous: &ModalForm,
) -> Option<ModalForm> {
    form(prom, p, unknown, true, Some(previous))
}

fn form(
    prom: &Prom,
    p: &[f64],
    unknown: &[usize],
    coupled: bool,
    previous: Option<&ModalForm>,
) -> Option<ModalForm> {
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
    // Φᵀ A Φ, its diagonal and its largest coupling ratio
    let transform = |a: &Mat<f64>| -> (Vec<f64>, f64, Mat<f64>) {
        let t = product(
            product(basis.transpose(), a.as_ref()).as_ref(),
            basis.as_ref(),
        );
        let roundoff = n as f64 * f64::EPSILON * t.norm_max();
        let mut coupling = 0.0_f64;
        for j in 0..n {
            for i in 0..n {
                let (off, scale) = (t[(i, j)].abs(), (t[(i, i)] * t[(j, j)]).abs().sqrt());
                if i != j && off > roundoff {
                    coupling = coupling.max(if scale > 0.0 {
                        off / scale
                    } else {
                        f64::INFINITY
                    });
                }
            }
        }
        let diagonal = (0..n).map(|i| t[(i, i)]).collect();
        (diagonal, coupling, t)
    };
    let off_diagonal = |c: f64, mut t: Mat<f64>| {
        (0..n).for_each(|i| t[(i, i)] = 0.0);
        (c > DIAGONAL_TOLERANCE).then_some(OffDiagonal::Dense(t))
    };
    let mut coupling = 0.0_f64;
    let mut parts = Vec::new();
    let mut couplings = Vec::new();
    let mut constant = None;
    for (function, k, m) in std::iter::once((None, &k_fixed, &m_fixed)).chain(
        varying
            .iter()
            .map(|&i| (Some(i), &prom.stiffness[i], &prom.mass[i])),
    ) {
        let ((k_diag, k_coupling, k_t), (m_diag, m_coupling, m_t)) = (transform(k), transform(m));
        coupling = coupling.max(k_coupling).max(m_coupling);
        let couples = k_coupling.max(m_coupling) > DIAGONAL_TOLERANCE;
        if couples && !coupled {
            return None;
        }
        parts.push((function, k_diag, m_diag));
        let Some(i) = function else {
            // the constant part's off-diagonal is dropped (module documentation); kept whole for
            // the low-rank couplings below
            constant = Some((k_t, m_t));
            continue;
        };
        if couples {
            couplings.push(Coupling {
                function: i,
                reference: prom.functions[i].value(p),
                stiffness: off_diagonal(k_coupling, k_t),
                mass: off_diagonal(m_coupling, m_t),
            });
        }
    }
    // a matrix's only coupled part: its off-diagonal from the constant part's, if of low rank
    let (k_c, m_c) = constant.expect("the constant part is transformed first");
    for (c, mass) in [(&k_c, false), (&m_c, true)] {
        let mut coupled_parts = couplings.iter_mut().filter(|k| k.part(mass).is_some());
        let Some(only) = coupled_parts
            .next()
            .filter(|_| coupled_parts.next().is_none())
        else {
            continue;
        };
        let carried = previous.and_then(|form| {
            form.couplings
                .iter()
                .find(|k| k.function == only.function)
                .map(|k| (form, k.reference, k.part(mass)))
        });
        // the constant part's rank does not change with the estimate: a coupling found dense
        // stays dense
        let low = match carried {
            Some((
                form,
                reference,
                Some(OffDiagonal::LowRank {
                    vectors, values, ..
                }),
            )) => {
                let moved = product(
                    basis.transpose(),
                    product(form.inverse.transpose(), vectors.as_ref()).as_ref(),
                );
                Some(OffDiagonal::from_factor(
                    moved,
                    values
                        .iter()
                        .map(|v| v * reference / only.reference)
                        .collect(),
                ))
            }
            Some((_, _, Some(OffDiagonal::Dense(_)))) => None,
            _ => OffDiagonal::low_rank(c, 1.0 / only.reference),
        };
        if let Some(low) = low {
            *only.part_mut(mass) = Some(low);
        }
    }
    Some(ModalForm {
        basis,
        inverse,
        parts,
        coupling,
        couplings,
    })
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
        assert!(
            modal_form(&two, &[1.2, 0.9], &[1], false).is_some(),
            "ρ alone scales all of M"
        );
        assert!(modal_form(&two, &[1.2, 0.9], &[], false).is_some());
        let mut one = chain();
        one.stiffness[0].fill(0.0);
        let form = modal_form(&one, &[1.2, 0.9], &[0, 1], false).unwrap();
        assert!(
            form.coupling <= 1e-13 && form.couplings.is_empty(),
            "{}",
            form.coupling
        );
        // Φ⁻¹ Φ = I
        let eye = &form.inverse * &form.basis;
        assert!((0..2).all(|i| {
            (0..2).all(|j| (eye[(i, j)] - if i == j { 1.0 } else { 0.0 }).abs() <= 1e-13)
        }));
    }

    /// An n-DOF version of the filter tests' chain: springs E K¹ (fixed–free, 1e4 each), the
    /// grounded spring K⁰ at DOF 0 (5e3, rank 1), M = ρ M¹ (diagonal 2, 1, … with 0.1 between
    /// neighbours).
    fn chain_of(n: usize) -> Prom {
        let mut prom = chain();
        prom.stiffness[1] = Mat::from_fn(n, n, |i, j| match (i, j) {
            (i, j) if i == j => {
                if i + 1 < n {
                    2e4
                } else {
                    1e4
                }
            }
            (i, j) if i.abs_diff(j) == 1 => -1e4,
            _ => 0.0,
        });
        prom.stiffness[0] = Mat::from_fn(n, n, |i, j| if i == 0 && j == 0 { 5e3 } else { 0.0 });
        prom.stiffness[2] = Mat::zeros(n, n);
        prom.mass = vec![
            Mat::zeros(n, n),
            Mat::zeros(n, n),
            Mat::from_fn(n, n, |i, j| {
                if i == j {
                    2.0 - (i % 2) as f64
                } else if i.abs_diff(j) == 1 {
                    0.1
                } else {
                    0.0
                }
            }),
        ];
        prom
    }

    /// With `coupled`, the bolted-chain E part (beside its constant grounded spring) is kept as
    /// a coupling, ρ's part (all of M) stays diagonal, and the form reproduces Φᵀ K(p) Φ and
    /// Φᵀ M(p) Φ away from p₀ as diagonal parts + Σ (f_i(p) − f_i(p₀)) off-diagonals, applied by
    /// [`OffDiagonal::add_product`]: exact up to the round-off of the modes (the dropped constant
    /// off-diagonal), bound 1e-12 of max |Ã|. On 2 DOFs the coupling is stored whole; on 6 the
    /// rank-1 spring makes it [`OffDiagonal::LowRank`] (2 · 6 · 1 + 6 < 36). The same holds for
    /// the form re-diagonalized at (1.35, 0.8) after the one at p₀ ([`modal_form_after`]: the
    /// low-rank factor carried over, not recomputed).
    #[test]
    fn coupled_parts_reproduce_the_transformed_matrices_away_from_the_modes_parameters() {
        for (prom, low_rank, after) in [
            (chain(), false, false),
            (chain_of(6), true, false),
            (chain(), false, true),
            (chain_of(6), true, true),
        ] {
            let n = prom.size();
            let p0 = [1.2, 0.9];
            let form = modal_form(&prom, &p0, &[0, 1], true).expect("coupled form");
            let (form, p0) = if after {
                (
                    modal_form_after(&prom, &[1.35, 0.8], &[0, 1], &form).expect("re-diagonalized"),
                    [1.35, 0.8],
                )
            } else {
                (form, p0)
            };
            assert!(
                (form.couplings[0].reference
                    - prom.functions[form.couplings[0].function].value(&p0))
                .abs()
                    <= 1e-15
            );
            assert_eq!(form.couplings.len(), 1);
            let c = &form.couplings[0];
            assert!(c.mass.is_none() && prom.functions[c.function].driven_by[0].1 == 0);
            assert!(
                matches!(c.stiffness, Some(OffDiagonal::LowRank { ref values, .. }) if values.len() == 1)
                    == low_rank,
                "n = {n}: {:?}",
                c.stiffness
            );
            let p = [1.5, 0.7];
            let mut at = prom.workspace();
            prom.evaluate(&p, &mut at).unwrap();
            for (which, exact) in [("K", at.stiffness()), ("M", at.mass())] {
                let exact = form.basis.transpose() * exact * &form.basis;
                let mut model = Mat::<f64>::zeros(n, n);
                for (function, k, m) in &form.parts {
                    let w = function.map_or(1.0, |i| prom.functions[i].value(&p));
                    (0..n)
                        .for_each(|i| model[(i, i)] += w * if which == "K" { k[i] } else { m[i] });
                }
                for c in &form.couplings {
                    if let Some(off) = if which == "K" { &c.stiffness } else { &c.mass } {
                        let mut unit = vec![0.0; n];
                        for j in 0..n {
                            unit[j] = 1.0;
                            off.add_product(
                                &unit,
                                model.col_as_slice_mut(j),
                                prom.functions[c.function].value(&p) - c.reference,
                            );
                            unit[j] = 0.0;
                        }
                    }
                }
                let scale = exact.norm_max();
                assert!(
                    (&exact - &model).norm_max() <= 1e-12 * scale,
                    "n = {n}, after {after}, {which}: {:e}",
                    (&exact - &model).norm_max()
                );
            }
        }
    }

    /// [`OffDiagonal::low_rank`] of A = B Bᵀ − C Cᵀ (8 × 8, rank 3, indefinite) applies
    /// −f (A − diag A) to round-off (bound 1e-14 of max |A| |x|), and a full-rank matrix is left
    /// dense (None).
    #[test]
    fn low_rank_off_diagonal_applies_the_scaled_off_diagonal() {
        let n = 8;
        let b = Mat::from_fn(n, 2, |i, j| {
            ((i * 7 + j * 3) % 5) as f64 - 2.0 + 0.1 * i as f64
        });
        let c = Mat::from_fn(n, 1, |i, _| (i as f64 * 0.7).sin());
        let a = &b * b.transpose() - &c * c.transpose();
        let f = 2.5;
        let off = OffDiagonal::low_rank(&a, f).expect("rank 3 of 8 is low");
        assert!(
            matches!(&off, OffDiagonal::LowRank { values, .. } if values.len() == 3),
            "{off:?}"
        );
        let x: Vec<f64> = (0..n).map(|i| 1.0 + 0.3 * i as f64).collect();
        let mut out = vec![1.0; n];
        off.add_product(&x, &mut out, 0.5);
        let scale = a.norm_max() * x.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        for i in 0..n {
            let exact = 1.0
                - 0.5
                    * f
                    * (0..n)
                        .filter(|&j| j != i)
                        .map(|j| a[(i, j)] * x[j])
                        .sum::<f64>();
            assert!(
                (out[i] - exact).abs() <= 1e-14 * scale * n as f64,
                "{i}: {} vs {exact}",
                out[i]
            );
        }
        assert!(
            OffDiagonal::low_rank(&(&a + Mat::<f64>::identity(n, n) * faer::Scale(3.0)), f)
                .is_none()
        );
    }
}
