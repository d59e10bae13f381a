//! Offline building blocks of the global reduction basis (thesis §3.4.1–3.4.2):
//! seeded Latin hypercube samples of the parameter box, the MAC filter of eq. 3.39, the SVD of
//! the concatenated local bases (eq. 3.33–3.34) truncated to the leading left singular vectors,
//! the matching transformation of a companion basis (strains, eq. 3.36–3.38), and the FRF change
//! between consecutive basis sizes (eq. 3.35) that decides when the basis is large enough.

use faer::{Mat, MatRef, c64};
use nalgebra_sparse::CscMatrix;
use rayon::prelude::*;

use super::local_basis::RIGID_REL;
use crate::linalg::random::SplitMix64;
use crate::linalg::sym_matvec;

/// A seeded Latin hypercube of `n` points in the box `[low_j, high_j]` (thesis §3.4.1, [104]):
/// every parameter's range is cut into `n` equal strata, each stratum is used exactly once,
/// strata are paired across parameters by independent random permutations, and each point sits
/// at a random position inside its stratum. Same seed → same points on every machine.
///
/// The generator is [`SplitMix64`].
pub fn latin_hypercube(n: usize, low: &[f64], high: &[f64], seed: u64) -> Vec<Vec<f64>> {
    let mut rng = SplitMix64::new(seed);
    let mut points = vec![vec![0.0; low.len()]; n];
    for (j, (&lo, &hi)) in low.iter().zip(high).enumerate() {
        let mut strata: Vec<usize> = (0..n).collect();
        for i in (1..n).rev() {
            strata.swap(i, rng.below(i + 1));
        }
        for (point, &stratum) in points.iter_mut().zip(&strata) {
            let u = (stratum as f64 + rng.unit()) / n as f64;
            point[j] = lo + u * (hi - lo);
        }
    }
    points
}

/// Modal Assurance Criterion of eq. 3.39 from the three inner products of two vectors in some
/// inner product ⟨·,·⟩: ⟨a, b⟩² / (⟨a, a⟩⟨b, b⟩) (the standard form; the thesis prints the
/// denominator with the indices crossed). A vector of zero norm has MAC 0 with everything.
pub fn mac(ab: f64, aa: f64, bb: f64) -> f64 {
    if aa <= 0.0 || bb <= 0.0 {
        0.0
    } else {
        ab * ab / (aa * bb)
    }
}

/// The stiffness and mass of the samples the local bases come from, K_s = Σ_i f_i(p_s) K^i and
/// M_s likewise (eq. 3.26; full-pattern parts): the inner products [`mac_filter`] compares in.
pub struct SampledPencil<'a> {
    pub stiffness: &'a [CscMatrix<f64>],
    pub mass: &'a [CscMatrix<f64>],
    /// f_i(p_s): one row per sample (local basis), one value per part.
    pub weights: &'a [Vec<f64>],
}

/// A pencil that does not fit the columns it should weigh.
#[derive(Debug, thiserror::Error)]
pub enum PencilError {
    #[error("{stiffness} stiffness and {mass} mass parts")]
    Parts { stiffness: usize, mass: usize },
    #[error("sample {sample}: {got} function values for {expected} parts")]
    Weights {
        sample: usize,
        expected: usize,
        got: usize,
    },
    #[error("{got} rows of function values for {expected} local bases")]
    Samples { expected: usize, got: usize },
    #[error("the local bases have {rows} rows, the matrices are {size} × {size}")]
    Size { rows: usize, size: usize },
}

impl SampledPencil<'_> {
    fn check(&self, rows: usize, samples: usize) -> Result<(), PencilError> {
        let parts = self.stiffness.len();
        if self.mass.len() != parts {
            return Err(PencilError::Parts {
                stiffness: parts,
                mass: self.mass.len(),
            });
        }
        if self.weights.len() < samples {
            return Err(PencilError::Samples {
                expected: samples,
                got: self.weights.len(),
            });
        }
        if let Some((s, w)) = self
            .weights
            .iter()
            .enumerate()
            .find(|(_, w)| w.len() != parts)
        {
            return Err(PencilError::Weights {
                sample: s + 1,
                expected: parts,
                got: w.len(),
            });
        }
        if let Some(x) = self
            .stiffness
            .iter()
            .chain(self.mass)
            .find(|x| x.nrows() != rows || x.ncols() != rows)
        {
            return Err(PencilError::Size {
                rows,
                size: x.nrows(),
            });
        }
        Ok(())
    }
}

/// A column ψ of sample s seen through the pencil: its images K_s ψ and M_s ψ, and the quadratic
/// forms ψᵀK^iψ and ψᵀM^iψ of every part, so that ψᵀK_tψ at any sample t is a short sum.
struct Weighed {
    k_image: Vec<f64>,
    m_image: Vec<f64>,
    k_forms: Vec<f64>,
    m_forms: Vec<f64>,
}

impl Weighed {
    fn new(psi: &[f64], weights: &[f64], pencil: &SampledPencil<'_>) -> Self {
        let through = |parts: &[CscMatrix<f64>]| -> (Vec<f64>, Vec<f64>) {
            let mut image = vec![0.0; psi.len()];
            let mut part_image = vec![0.0; psi.len()];
            let forms = parts
                .iter()
                .zip(weights)
                .map(|(x, &w)| {
                    sym_matvec(x, psi, &mut part_image).expect("sizes checked");
                    image
                        .iter_mut()
                        .zip(&part_image)
                        .for_each(|(o, v)| *o += w * v);
                    dot(psi, &part_image)
                })
                .collect();
            (image, forms)
        };
        let (k_image, k_forms) = through(pencil.stiffness);
        let (m_image, m_forms) = through(pencil.mass);
        Weighed {
            k_image,
            m_image,
            k_forms,
            m_forms,
        }
    }
}

/// The MAC filter of §3.4.2 in the energy inner products of the samples: walk the columns in
/// order and drop column b of sample s when an already kept column a *of another local basis*
/// has a MAC above `threshold` (0.99 in the thesis) with it in both the mass and the stiffness
/// inner product of sample s, ⟨a, b⟩ = aᵀM_s b and aᵀK_s b. Returns the indices of the kept
/// columns; `sample[j]` is the local basis column j comes from.
///
/// Why both energies, not the thesis's displacement MAC (aᵀb): two vectors can be near-parallel
/// as displacements while their strain energies differ. For an eigenvector b of sample s,
/// MAC_K = MAC_M · λ_b / R_s(a) with R_s(a) = aᵀK_s a / aᵀM_s a, so passing both bounds the
/// frequency a gives at sample s to within a factor 1/√threshold of b's (0.5 % at 0.99): a
/// dropped mode is one the kept column reproduces. With the displacement MAC instead, the
/// [±Θ]s angle-ply cantilever strip of `decks/prom/strip_angle_ply_prom_theta.dat` (samples at
/// 33.6° and 88.7°) keeps 24 of 26 columns: shapes of the second sample that match the first
/// sample's although their stiffness differs are dropped, and the pROM misses that sample's
/// modes above the third by 2–66 %; in both energies all 26 stay and every mode below FMAX
/// comes back within 2.3e-9 (`tests/prom.rs`,
/// `every_strip_mode_below_fmax_is_kept_at_sampled_and_unsampled_angles`). Exact duplicates
/// (one material with E and ρ as parameters, §3.4.2's example) pass both tests and are still
/// removed. A rigid-body mode (Rayleigh quotient below [`RIGID_REL`] of the stiffest column's)
/// has no strain energy to compare and is judged by its mass MAC alone. MACTOL = 1 turns the
/// filter off but for exact duplicates (the SVD's numerical rank then removes redundancy). To
/// return to the thesis's displacement MAC, compare `mac` of the raw columns' dot products
/// instead of the energies in `energy_redundant`.
///
/// The thesis compares every couple; here columns of one local basis are never compared: they
/// are independent by construction (M-orthogonal modes, and static modes K⁻¹e_b of distinct unit
/// loads), and the filter's purpose is the redundancy *between* samples. Compared within one
/// basis, a tip attachment mode has MAC > 0.99 with the first bending mode of a cantilever
/// (their difference, the static flexibility of all the modes above, is ≲ 10 % of the vector),
/// and dropping it removes exactly that residual flexibility: on the small composite plate of
/// `tests/prom_maps.rs` the one-sample ROMs at Θ = 40° and 60° lost two of their three
/// attachment modes and their FRFs moved by 6.5e-2 and 9.6e-2 (thesis metric of Fig. 3.22).
pub fn mac_filter(
    vectors: MatRef<'_, f64>,
    sample: &[usize],
    pencil: &SampledPencil<'_>,
    threshold: f64,
) -> Result<Vec<usize>, PencilError> {
    let samples = sample.iter().max().map_or(0, |s| s + 1);
    pencil.check(vectors.nrows(), samples)?;
    let column = |j: usize| -> Vec<f64> { (0..vectors.nrows()).map(|i| vectors[(i, j)]).collect() };
    let weighed: Vec<Option<(Vec<f64>, Weighed)>> = (0..vectors.ncols())
        .into_par_iter()
        .map(|j| {
            let v = column(j);
            if v.iter().all(|x| *x == 0.0) {
                return None;
            }
            let w = Weighed::new(&v, &pencil.weights[sample[j]], pencil);
            Some((v, w))
        })
        .collect();
    let rayleigh = |(v, w): &(Vec<f64>, Weighed)| dot(v, &w.k_image) / dot(v, &w.m_image);
    let stiffest = weighed
        .iter()
        .flatten()
        .map(rayleigh)
        .filter(|r| r.is_finite())
        .fold(0.0, f64::max);
    let mut kept: Vec<usize> = Vec::new();
    for (j, candidate) in weighed.iter().enumerate() {
        let Some(b) = candidate else { continue };
        let weights = &pencil.weights[sample[j]];
        // a rigid-body mode has no strain energy to compare: its mass MAC decides alone
        let elastic = rayleigh(b) > RIGID_REL * stiffest;
        let redundant = kept.iter().any(|&i| {
            let a = weighed[i].as_ref().expect("kept columns are non-zero");
            sample[i] != sample[j] && energy_redundant(a, b, weights, threshold, elastic)
        });
        if !redundant {
            kept.push(j);
        }
    }
    Ok(kept)
}

fn dot(x: &[f64], y: &[f64]) -> f64 {
    x.iter().zip(y).map(|(p, q)| p * q).sum()
}

/// Column a (of any sample) makes column b of sample s redundant: MAC above `threshold` in
/// aᵀM_s b and, when `compare_stiffness`, in aᵀK_s b (`weights` = f_i(p_s)).
fn energy_redundant(
    (a, a_weighed): &(Vec<f64>, Weighed),
    (b, b_weighed): &(Vec<f64>, Weighed),
    weights: &[f64],
    threshold: f64,
    compare_stiffness: bool,
) -> bool {
    let at_s = |forms: &[f64]| forms.iter().zip(weights).map(|(f, w)| f * w).sum::<f64>();
    let m = mac(
        dot(a, &b_weighed.m_image),
        at_s(&a_weighed.m_forms),
        dot(b, &b_weighed.m_image),
    );
    m > threshold
        && (!compare_stiffness || {
            let k = mac(
                dot(a, &b_weighed.k_image),
                at_s(&a_weighed.k_forms),
                dot(b, &b_weighed.k_image),
            );
            k > threshold
        })
}

/// The thin SVD Ψ_global = U Σ Vᵀ of concatenated local bases (eq. 3.34), kept whole so the
/// basis can be grown in steps without recomputing it.
pub struct GlobalBasis {
    u: Mat<f64>,
    sigma: Vec<f64>,
    v: Mat<f64>,
}

impl GlobalBasis {
    /// Decompose the concatenated local bases (columns).
    pub fn new(concatenated: MatRef<'_, f64>) -> Result<Self, faer::linalg::svd::SvdError> {
        let svd = concatenated.thin_svd()?;
        let sigma = (0..svd.S().dim())
            .map(|i| svd.S().column_vector()[i])
            .collect();
        Ok(GlobalBasis {
            u: svd.U().to_owned(),
            sigma,
            v: svd.V().to_owned(),
        })
    }

    /// Singular values, descending.
    pub fn singular_values(&self) -> &[f64] {
        &self.sigma
    }

    /// Number of singular values above `rel_tol · σ₁`: the rank beyond which further left
    /// singular vectors carry no information ("spatial noise", §3.4.2).
    pub fn numerical_rank(&self, rel_tol: f64) -> usize {
        let top = self.sigma.first().copied().unwrap_or(0.0);
        self.sigma
            .iter()
            .take_while(|&&s| s > rel_tol * top)
            .count()
    }

    /// The truncated basis Ψ = U_n (first `n` left singular vectors).
    pub fn truncated(&self, n: usize) -> MatRef<'_, f64> {
        self.u.as_ref().subcols(0, n)
    }

    /// Eq. 3.38: a companion basis built column by column with the filtered concatenation (e.g.
    /// the strains N_s,global of each local mode from a black-box code) made consistent with the
    /// truncation: N_s = N_s,global V_n Σ_n⁻¹.
    pub fn transform_companion(&self, companion: MatRef<'_, f64>, n: usize) -> Mat<f64> {
        let scaled = Mat::<f64>::from_fn(self.v.nrows(), n, |i, k| self.v[(i, k)] / self.sigma[k]);
        companion * scaled
    }
}

/// A companion that does not match the local bases it should follow.
#[derive(Debug, thiserror::Error)]
pub enum CompanionError {
    #[error("{got} companion bases for {expected} local bases")]
    Count { expected: usize, got: usize },
    #[error("companion of local basis {sample}: {got} columns, the local basis has {expected}")]
    Columns {
        sample: usize,
        expected: usize,
        got: usize,
    },
    #[error("companion of local basis {sample}: {got} rows, the first companion has {expected}")]
    Rows {
        sample: usize,
        expected: usize,
        got: usize,
    },
}

/// Why the concatenation could not be filtered or decomposed.
#[derive(Debug, thiserror::Error)]
pub enum ConcatenationError {
    #[error("MAC filter: {0}")]
    Pencil(#[from] PencilError),
    #[error("SVD of the concatenated bases failed: {0:?}")]
    Svd(faer::linalg::svd::SvdError),
}

/// The global basis of eq. 3.33–3.34 from local bases: the columns scaled to unit length (M-
/// normalized modes and unit-load modes differ in scale by orders of magnitude, which would let
/// the SVD rank columns by their units instead of their shape), MAC-filtered across samples
/// ([`mac_filter`]) and decomposed. It remembers which columns it kept and their scales, so a
/// companion basis given per local basis (the strain bases N_s,i = ϑᵀε_i of the black-box route,
/// §3.4.1.1) follows the same scaling, filtering and truncation ([`Concatenation::companion`],
/// eq. 3.36–3.38).
pub struct Concatenation {
    pub global: GlobalBasis,
    sizes: Vec<usize>,
    /// (column of the concatenation, 1/‖ψ‖) of each kept column, in order.
    kept: Vec<(usize, f64)>,
}

impl Concatenation {
    /// Concatenate, filter (threshold `mac_tol` in the energies of `pencil`, one row of
    /// weights per local basis) and decompose `locals` (n × k_i each).
    pub fn new(
        locals: &[MatRef<'_, f64>],
        pencil: &SampledPencil<'_>,
        mac_tol: f64,
    ) -> Result<Self, ConcatenationError> {
        let n = locals.first().map_or(0, |b| b.nrows());
        let sizes: Vec<usize> = locals.iter().map(|b| b.ncols()).collect();
        let columns: Vec<(&MatRef<'_, f64>, usize)> = locals
            .iter()
            .flat_map(|b| (0..b.ncols()).map(move |j| (b, j)))
            .collect();
        let scale: Vec<f64> = columns
            .iter()
            .map(|(b, j)| {
                let norm = b.col(*j).iter().map(|x| x * x).sum::<f64>().sqrt();
                if norm > 0.0 { 1.0 / norm } else { 1.0 }
            })
            .collect();
        let concatenated = Mat::<f64>::from_fn(n, columns.len(), |i, c| {
            columns[c].0[(i, columns[c].1)] * scale[c]
        });
        let sample_of: Vec<usize> = sizes
            .iter()
            .enumerate()
            .flat_map(|(s, &k)| std::iter::repeat_n(s, k))
            .collect();
        let kept: Vec<(usize, f64)> =
            mac_filter(concatenated.as_ref(), &sample_of, pencil, mac_tol)?
                .into_iter()
                .map(|c| (c, scale[c]))
                .collect();
        let filtered = Mat::<f64>::from_fn(n, kept.len(), |i, k| concatenated[(i, kept[k].0)]);
        drop(concatenated);
        Ok(Concatenation {
            global: GlobalBasis::new(filtered.as_ref()).map_err(ConcatenationError::Svd)?,
            sizes,
            kept,
        })
    }

    /// Columns of the concatenation (eq. 3.33).
    pub fn concatenated(&self) -> usize {
        self.sizes.iter().sum()
    }

    /// Columns the MAC filter kept.
    pub fn kept(&self) -> usize {
        self.kept.len()
    }

    /// Eq. 3.36–3.38: the companion of the truncated basis U_n from companions given per local
    /// basis (s × k_i each, column j the image of local column j — e.g. its strains at the
    /// sensors): concatenated, scaled and filtered as the local bases were, then
    /// N_s = N_s,global,n V_n Σ_n⁻¹. For a companion L Ψ_i (L linear) this is L U_n.
    pub fn companion(
        &self,
        companions: &[MatRef<'_, f64>],
        n: usize,
    ) -> Result<Mat<f64>, CompanionError> {
        if companions.len() != self.sizes.len() {
            return Err(CompanionError::Count {
                expected: self.sizes.len(),
                got: companions.len(),
            });
        }
        let rows = companions.first().map_or(0, |c| c.nrows());
        for (sample, (c, &k)) in companions.iter().zip(&self.sizes).enumerate() {
            if c.ncols() != k {
                return Err(CompanionError::Columns {
                    sample: sample + 1,
                    expected: k,
                    got: c.ncols(),
                });
            }
            if c.nrows() != rows {
                return Err(CompanionError::Rows {
                    sample: sample + 1,
                    expected: rows,
                    got: c.nrows(),
                });
            }
        }
        let columns: Vec<(&MatRef<'_, f64>, usize)> = companions
            .iter()
            .flat_map(|c| (0..c.ncols()).map(move |j| (c, j)))
            .collect();
        let filtered = Mat::<f64>::from_fn(rows, self.kept.len(), |i, k| {
            let (c, scale) = self.kept[k];
            columns[c].0[(i, columns[c].1)] * scale
        });
        Ok(self.global.transform_companion(filtered.as_ref(), n))
    }
}

/// The FRF change of eq. 3.35 between the pROM with basis Ψ_{k−1} (`previous`) and Ψ_k
/// (`current`), both evaluated at the same parameters and frequency lines:
/// e_k = Σ_i Σ_j (1/n_ω) Σ_l | |H_ij(ω_l, Ψ_{k−1})| − |H_ij(ω_l, Ψ_k)| | / |H_ij(ω_l, Ψ_{k−1})|.
/// Lines where the previous FRF is exactly zero (an input that does not reach an output) are
/// skipped rather than divided by.
pub fn frf_change(previous: &[Mat<c64>], current: &[Mat<c64>]) -> f64 {
    let Some(first) = previous.first() else {
        return 0.0;
    };
    let n_omega = previous.len() as f64;
    let mut total = 0.0;
    for i in 0..first.ncols() {
        for j in 0..first.nrows() {
            let sum: f64 = previous
                .iter()
                .zip(current)
                .map(|(p, c)| (p[(j, i)].norm(), c[(j, i)].norm()))
                .filter(|(p, _)| *p > 0.0)
                .map(|(p, c)| (p - c).abs() / p)
                .sum();
            total += sum / n_omega;
        }
    }
    total
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn latin_hypercube_uses_every_stratum_once_and_is_reproducible() {
        let (low, high) = ([0.6, 10.0], [1.4, 20.0]);
        let pts = latin_hypercube(7, &low, &high, 42);
        for j in 0..2 {
            let mut strata: Vec<usize> = pts
                .iter()
                .map(|p| ((p[j] - low[j]) / (high[j] - low[j]) * 7.0).floor() as usize)
                .collect();
            strata.sort_unstable();
            assert_eq!(strata, (0..7).collect::<Vec<_>>());
        }
        assert_eq!(pts, latin_hypercube(7, &low, &high, 42));
        assert_ne!(pts, latin_hypercube(7, &low, &high, 43));
    }

    /// Eq. 3.35 on hand-made data: 2 lines, 1 × 2 FRFs; magnitudes 2 → 1 and 4 → 4 on input 0,
    /// 1 → 1.5 and 0 (skipped) on input 1: e = (0.5 + 0)/2 + (0.5 + 0)/2 = 0.5, phase ignored.
    #[test]
    fn frf_change_follows_eq_3_35() {
        let h = |a: c64, b: c64| Mat::<c64>::from_fn(1, 2, |_, j| if j == 0 { a } else { b });
        let prev = [
            h(c64::new(2.0, 0.0), c64::new(0.0, 1.0)),
            h(c64::new(0.0, 4.0), c64::new(0.0, 0.0)),
        ];
        let cur = [
            h(c64::new(0.0, -1.0), c64::new(1.5, 0.0)),
            h(c64::new(4.0, 0.0), c64::new(7.0, 0.0)),
        ];
        assert!((frf_change(&prev, &cur) - 0.5).abs() < 1e-15);
        assert_eq!(frf_change(&prev, &prev), 0.0);
    }

    #[test]
    fn mac_is_scale_invariant_and_detects_orthogonality() {
        let (a, b) = ([1.0, 2.0, 3.0], [-2.0, -4.0, -6.0]);
        assert!((mac(dot(&a, &b), dot(&a, &a), dot(&b, &b)) - 1.0).abs() < 1e-15);
        assert_eq!(mac(0.0, 1.0, 25.0), 0.0);
        assert_eq!(mac(0.0, 0.0, 2.0), 0.0);
    }

    /// Diagonal n × n matrix with these entries (full pattern, as `sym_matvec` wants).
    fn diagonal(entries: &[f64]) -> CscMatrix<f64> {
        let mut coo = nalgebra_sparse::CooMatrix::new(entries.len(), entries.len());
        entries
            .iter()
            .enumerate()
            .for_each(|(i, &v)| coo.push(i, i, v));
        CscMatrix::from(&coo)
    }

    /// K = M = I at every sample: the energy MAC is the displacement MAC.
    fn identity_pencil(n: usize, samples: usize) -> (Vec<CscMatrix<f64>>, Vec<Vec<f64>>) {
        (vec![diagonal(&vec![1.0; n])], vec![vec![1.0]; samples])
    }

    /// Thesis §3.4.2 example: bases of a one-material model at different (E, ρ) are the same
    /// modes scaled; the filter keeps one copy of each. Columns of one local basis are never
    /// compared: a near-duplicate inside sample 0 (column 1 ≈ column 0, MAC 0.995) stays, its
    /// copies in sample 1 go.
    #[test]
    fn mac_filter_removes_scaled_duplicates_across_samples() {
        let a = [1.0, 2.0, 0.5, -1.0];
        let b = [0.0, 1.0, -1.0, 2.0];
        let near_a = [1.0, 2.0, 0.5, -0.8];
        assert!(mac(dot(&a, &near_a), dot(&a, &a), dot(&near_a, &near_a)) > 0.99);
        let cols = [
            a.to_vec(),
            near_a.to_vec(),
            b.to_vec(),
            a.iter().map(|x| 3.0 * x).collect(),
            b.iter().map(|x| -0.2 * x).collect(),
            vec![1.0, 0.0, 0.0, 0.0],
        ];
        let m = Mat::<f64>::from_fn(4, cols.len(), |i, j| cols[j][i]);
        let (parts, weights) = identity_pencil(4, 2);
        let pencil = SampledPencil {
            stiffness: &parts,
            mass: &parts,
            weights: &weights,
        };
        assert_eq!(
            mac_filter(m.as_ref(), &[0, 0, 0, 1, 1, 1], &pencil, 0.99).unwrap(),
            vec![0, 1, 2, 5]
        );
        // one sample: nothing is compared, nothing removed
        assert_eq!(
            mac_filter(m.as_ref(), &[0; 6], &pencil, 0.99).unwrap(),
            (0..6).collect::<Vec<_>>()
        );
    }

    /// Two vectors with displacement MAC 0.9924 whose difference lies in a DOF that is stiff at
    /// sample 1 only (K_1 = diag(1, 1, 1, 1000) from two affine parts, K_0 = I): compared in
    /// sample 1's stiffness (MAC_K = 5.25 / 45.25 = 0.116) the sample-1 vector carries energy
    /// the other lacks and stays; the same vector in sample 0 (K_0 = I, MAC_K = 0.9924) goes.
    #[test]
    fn mac_filter_keeps_a_shape_whose_strain_energy_differs_at_its_sample() {
        let a = [1.0, 2.0, 0.5, 0.0];
        let b = [1.0, 2.0, 0.5, 0.2];
        let stiffness = [
            diagonal(&[1.0, 1.0, 1.0, 0.0]),
            diagonal(&[0.0, 0.0, 0.0, 1.0]),
        ];
        let mass = [diagonal(&[1.0; 4]), diagonal(&[0.0; 4])];
        let weights = [vec![1.0, 1.0], vec![1.0, 1000.0]];
        let pencil = SampledPencil {
            stiffness: &stiffness,
            mass: &mass,
            weights: &weights,
        };
        let m = Mat::<f64>::from_fn(4, 2, |i, j| if j == 0 { a[i] } else { b[i] });
        assert_eq!(
            mac_filter(m.as_ref(), &[0, 1], &pencil, 0.99).unwrap(),
            vec![0, 1]
        );
        let swapped = Mat::<f64>::from_fn(4, 2, |i, j| if j == 0 { b[i] } else { a[i] });
        assert_eq!(
            mac_filter(swapped.as_ref(), &[1, 0], &pencil, 0.99).unwrap(),
            vec![0]
        );
        let short = [vec![1.0]];
        let refused = SampledPencil {
            weights: &short,
            ..pencil
        };
        assert_eq!(
            mac_filter(m.as_ref(), &[0, 1], &refused, 0.99)
                .unwrap_err()
                .to_string(),
            "1 rows of function values for 2 local bases"
        );
    }

    /// Eq. 3.36–3.38 through [`Concatenation`]: local bases of very different column scales, one
    /// column of sample 1 a scaled copy of a column of sample 0 (filtered out), companions
    /// L Ψ_i: the companion of U_n must be L U_n (bound 1e-10 relative: a few SVD round-offs
    /// divided by σ_n ~ 1); a companion with a wrong column count is refused.
    #[test]
    fn concatenation_companion_follows_scaling_filter_and_truncation() {
        let n = 9;
        let local0 = Mat::<f64>::from_fn(n, 3, |i, j| {
            ((i * (j + 2)) as f64 * 0.7).sin() * 10f64.powi(3 * j as i32)
        });
        let local1 = Mat::<f64>::from_fn(n, 3, |i, j| {
            if j == 0 {
                -5.0 * local0[(i, 1)]
            } else {
                ((i + 3 * j) as f64 * 1.3).cos() * 1e-4
            }
        });
        let (parts, weights) = identity_pencil(n, 2);
        let pencil = SampledPencil {
            stiffness: &parts,
            mass: &parts,
            weights: &weights,
        };
        let c = Concatenation::new(&[local0.as_ref(), local1.as_ref()], &pencil, 0.99).unwrap();
        assert_eq!((c.concatenated(), c.kept()), (6, 5));
        let l = Mat::<f64>::from_fn(2, n, |i, j| (i as f64 + 1.0) * (j as f64 * 0.4).sin() - 0.3);
        let (s0, s1) = (&l * &local0, &l * &local1);
        let rank = c.global.numerical_rank(1e-12);
        assert_eq!(rank, 5);
        let via = c.companion(&[s0.as_ref(), s1.as_ref()], rank).unwrap();
        let direct = &l * c.global.truncated(rank);
        for i in 0..2 {
            for k in 0..rank {
                assert!(
                    (via[(i, k)] - direct[(i, k)]).abs() <= 1e-10 * (1.0 + direct[(i, k)].abs()),
                    "{i},{k}: {} vs {}",
                    via[(i, k)],
                    direct[(i, k)]
                );
            }
        }
        let short = s1.as_ref().subcols(0, 2);
        let message = c
            .companion(&[s0.as_ref(), short], rank)
            .unwrap_err()
            .to_string();
        assert_eq!(
            message,
            "companion of local basis 2: 2 columns, the local basis has 3"
        );
    }

    /// Σ and U reproduce the concatenation; the numerical rank sees duplicated information;
    /// the companion transform of eq. 3.38 applied to a linear image L Ψ_global equals L U_n.
    #[test]
    fn global_basis_truncation_and_companion() {
        let n = 6;
        let base = Mat::<f64>::from_fn(n, 3, |i, j| ((i + 1) as f64).powi(j as i32 + 1).sin());
        // concatenation with a scaled copy of the first two vectors: rank 3
        let concat = Mat::<f64>::from_fn(n, 5, |i, j| {
            if j < 3 {
                base[(i, j)]
            } else {
                2.0 * base[(i, j - 3)]
            }
        });
        let g = GlobalBasis::new(concat.as_ref()).unwrap();
        assert_eq!(g.numerical_rank(1e-12), 3);
        let l = Mat::<f64>::from_fn(2, n, |i, j| (i as f64 + 1.0) * (j as f64) - 1.0);
        let companion = &l * &concat;
        let via_companion = g.transform_companion(companion.as_ref(), 3);
        let direct = &l * g.truncated(3);
        for i in 0..2 {
            for k in 0..3 {
                assert!(
                    (via_companion[(i, k)] - direct[(i, k)]).abs()
                        < 1e-10 * (1.0 + direct[(i, k)].abs()),
                    "{i},{k}"
                );
            }
        }
    }
}
