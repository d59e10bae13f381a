//! P ← J P Jᵀ (thesis eq. 8.24) by blocks for the transition of the filter's prediction on the
//! augmented state x* = [q, q̇, w] (w: unknown inputs and parameters): J's q̇ block row J_v is
//! the only one computed (module documentation of [`super::filter`]).
//!
//! Both predictions have q rows e_q + a e_q̇ + b J_v ([`super::filter::Prediction`]: a = 0,
//! b = Δt for BDF1; a = b = Δt/2 for the trapezoidal rule). With the shear A: q ← q + a q̇ and
//! J̃_v = J_v A⁻¹ (J_v's q̇ columns minus a times its q columns), J = B A where B has the BDF1
//! shape (q rows e_q + b J̃_v, q̇ rows J̃_v): so P ← A P Aᵀ ([`shear`], (N + n) n adds) and then
//! the BDF1 blocks of [`propagate`] or [`super::modal_coordinates::Modal::propagate`] with J̃_v
//! and b. The models keep J̃_v.

use faer::Mat;

use super::kernels::{storage, storage_mut};

/// Columns j and n + j of P ← J P Jᵀ (eq. 8.24) from G = J_v P and H = G J_vᵀ: with
/// q' = q + b q̇', q̇' = J_v x, (u, p)' = (u, p) and w = (u, p),
///
/// ```text
/// P_q̇'q̇' = H,  P_q'q̇' = G_qᵀ + b H,  P_q'q' = P_qq + b (G_q + G_qᵀ) + b² H,
/// P_wq̇' = G_wᵀ,  P_wq' = P_wq + b G_wᵀ,  P_ww unchanged,
/// ```
///
/// (b of the module documentation; J_v is J̃_v there) so J P Jᵀ costs the two products only.
/// `gt_j` is column j of Gᵀ (N), `g_j` column j of G's q block (n: row j of Gᵀ) and `h_j` column j of H̄ = (H + Hᵀ)/2. Writes the q and q̇ rows of
/// columns j and n + j whole (contiguous) and their w rows; reads only P_qq's column j. Every
/// entry is computed from expressions symmetric in its two indices, so a symmetric P stays
/// exactly symmetric once [`mirror_w_rows`] has copied the w rows to the w columns.
/// `noise` = (column j of Φ⁻¹ Φ⁻ᵀ, q) adds the q and q̇ blocks of Q (modal coordinates) in
/// the same pass.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub(super) fn propagate_column(
    p: &mut [f64],
    ps: usize,
    (n, j): (usize, usize),
    gt_j: &[f64],
    g_j: &[f64],
    h_j: &[f64],
    noise: Option<(&[f64], f64)>,
    b: f64,
) {
    let (left, right) = p.split_at_mut((n + j) * ps);
    let (pq, pv) = left[j * ps..j * ps + 2 * n].split_at_mut(n);
    let (pqv, pvv) = right[..2 * n].split_at_mut(n);
    let blocks = pq
        .iter_mut()
        .zip(pv.iter_mut())
        .zip(pqv.iter_mut().zip(pvv.iter_mut()));
    let sources = gt_j[..n].iter().zip(&g_j[..n]).zip(&h_j[..n]);
    match noise {
        Some((gram, q)) => {
            for (((pq, pv), (pqv, pvv)), (((g_ij, g_ji), h_sym), gram)) in
                blocks.zip(sources.zip(gram))
            {
                *pq = (*pq + (b * (g_ij + g_ji) + b * b * h_sym)) + q * gram;
                *pv = g_ji + b * h_sym;
                *pqv = g_ij + b * h_sym;
                *pvv = h_sym + q * gram;
            }
        }
        None => {
            for (((pq, pv), (pqv, pvv)), ((g_ij, g_ji), h_sym)) in blocks.zip(sources) {
                *pq += b * (g_ij + g_ji) + b * b * h_sym;
                *pv = g_ji + b * h_sym;
                *pqv = g_ij + b * h_sym;
                *pvv = *h_sym;
            }
        }
    }
    for (k, &g_kj) in gt_j.iter().enumerate().skip(2 * n) {
        p[k + j * ps] += b * g_kj;
        p[k + (n + j) * ps] = g_kj;
    }
}

/// The q and q̇ rows of P's w columns from its w rows (after [`propagate_column`]).
#[inline(always)]
pub(super) fn mirror_w_rows(p: &mut [f64], ps: usize, n: usize, big_n: usize) {
    for k in 2 * n..big_n {
        for i in 0..2 * n {
            p[i + k * ps] = p[k + i * ps];
        }
    }
}

/// P ← J P Jᵀ (eq. 8.24 without Q; physical coordinates) by [`propagate_column`] from Gᵀ and H
/// ([`Physical::transition_products`]). `mirror` (n × 2n) receives the transposed q block of
/// Gᵀ and H̄ first, so that the main loop reads and writes whole columns only.
#[inline(always)]
pub(super) fn propagate(
    p: &mut Mat<f64>,
    gt: &Mat<f64>,
    h: &Mat<f64>,
    mirror: &mut Mat<f64>,
    b: f64,
) {
    let (n, big_n) = (h.nrows(), p.nrows());
    assert!(
        p.ncols() == big_n
            && gt.nrows() == big_n
            && gt.ncols() == n
            && h.ncols() == n
            && mirror.nrows() == n
            && mirror.ncols() == 2 * n,
        "propagate: shapes"
    );
    let ((g, gs), (h, hs)) = (storage(gt), storage(h));
    let (mirror, ms) = storage_mut(mirror);
    for j in 0..n {
        for i in 0..n {
            mirror[i + j * ms] = g[j + i * gs];
            mirror[i + (n + j) * ms] = 0.5 * (h[i + j * hs] + h[j + i * hs]);
        }
    }
    let (p, ps) = storage_mut(p);
    for j in 0..n {
        propagate_column(
            p,
            ps,
            (n, j),
            &g[j * gs..j * gs + big_n],
            &mirror[j * ms..j * ms + n],
            &mirror[(n + j) * ms..(n + j) * ms + n],
            None,
            b,
        );
    }
    mirror_w_rows(p, ps, n, big_n);
}

/// P ← A P Aᵀ for the shear A: q ← q + a q̇ (module documentation), in place:
///
/// ```text
/// P_qq ← P_qq + a (P_qq̇ + P_q̇q) + a² P_q̇q̇,  P_q̇q ← P_q̇q + a P_q̇q̇,  P_wq ← P_wq + a P_wq̇,
/// ```
///
/// column by column (column j reads its own old entries and column n + j's, which no earlier
/// column changed), then the q rows of the q̇ and w columns as copies of the new q columns. A
/// symmetric P stays exactly symmetric: entry (i, j) of P_qq is the same sum as (j, i).
pub(super) fn shear(p: &mut Mat<f64>, n: usize, a: f64) {
    let big_n = p.nrows();
    let (p, ps) = storage_mut(p);
    for j in 0..n {
        let (left, right) = p.split_at_mut((n + j) * ps);
        let column = &mut left[j * ps..j * ps + big_n];
        let velocity = &right[..big_n];
        let (q_rows, rest) = column.split_at_mut(n);
        for (i, pq) in q_rows.iter_mut().enumerate() {
            *pq += a * (velocity[i] + rest[i]) + a * a * velocity[n + i];
        }
        for (pr, pv) in rest.iter_mut().zip(&velocity[n..]) {
            *pr += a * pv;
        }
    }
    for k in n..big_n {
        for i in 0..n {
            p[i + k * ps] = p[k + i * ps];
        }
    }
}
