//! The r-set (SUPORT / SUPORT1) of a normal-modes run, as Nastran treats it.
//!
//! With l = f − r, the rigid-body shapes are the static response to unit motions of the r-set,
//! Ψ = [D; I] with D = −K_ll⁻¹ K_lr, and their strain energy is
//! X = Ψᵀ K Ψ = K_rr + K_rl D. A statically determinate r-set has X = 0 up to round-off;
//! Nastran prints ε = ‖X‖/‖K_rr‖ (its rigid-body error ratio) and the diagonal of X (the
//! strain energy of each unit rigid-body motion). Here ‖·‖ is the Frobenius norm:
//! - K_ll singular: the r-set leaves a rigid-body motion (or a mechanism) free — refused;
//! - ε > [`EPSILON_LIMIT`]: the r-set is over-determined (or the model is held elsewhere) —
//!   refused, with ε and the strain energies;
//! - otherwise Ψ, M-orthonormalized, are the rigid-body modes, reported at 0 Hz in place of the
//!   lowest r roots of the eigensolution ([`RigidBodyModes`]).

use faer::Par;
use nalgebra_sparse::{CooMatrix, CscMatrix};

use crate::discretize::Constrained;
use crate::linalg::{Mat, SymbolicFactor, sym_matvec};

/// Largest ε accepted: a determinate r-set gives round-off (≈ 1e-12 on shell and solid models),
/// one redundant support gives ε of order one.
pub const EPSILON_LIMIT: f64 = 1e-6;

/// The rigid-body check and modes of an r-set.
pub struct RigidBodyModes {
    /// ε = ‖K_rr + K_rl D‖ / ‖K_rr‖.
    pub epsilon: f64,
    /// diag(K_rr + K_rl D), one per r DOF.
    pub strain_energy: Vec<f64>,
    /// Ψ on the f-set, M-orthonormalized (n_f × r).
    pub shapes: Mat<f64>,
    /// ‖Kψ‖₂ / (‖K‖₁ ‖ψ‖₂) of each shape (the eigensolver's residual of a rigid-body mode).
    pub residuals: Vec<f64>,
}

/// The rigid-body shapes of the r-set at f-set positions `r` and their check (see the module
/// documentation); `max_ratio` is PARAM,MAXRATIO for the factor of K_ll. Errors are sentences
/// for the user.
pub fn rigid_body_modes(
    c: &Constrained,
    r: &[usize],
    max_ratio: f64,
) -> Result<RigidBodyModes, String> {
    let n_f = c.k_ff.nrows();
    let n_r = r.len();
    // f position → l position (None on the r-set)
    let mut l_of = vec![Some(0); n_f];
    for &i in r {
        l_of[i] = None;
    }
    let mut n_l = 0;
    for slot in l_of.iter_mut().filter(|s| s.is_some()) {
        *slot = Some(n_l);
        n_l += 1;
    }
    let r_of = |i: usize| r.iter().position(|&x| x == i);
    let mut k_ll = CooMatrix::new(n_l, n_l);
    let mut k_lr = Mat::<f64>::zeros(n_l, n_r);
    let mut k_rr = Mat::<f64>::zeros(n_r, n_r);
    for (j, column) in c.k_ff.col_iter().enumerate() {
        for (&i, &v) in column.row_indices().iter().zip(column.values()) {
            match (l_of[i], l_of[j]) {
                (Some(a), Some(b)) => k_ll.push(a, b, v),
                (Some(a), None) => k_lr[(a, r_of(j).unwrap_or(0))] += v,
                (None, None) => k_rr[(r_of(i).unwrap_or(0), r_of(j).unwrap_or(0))] += v,
                (None, Some(_)) => {}
            }
        }
    }
    let k_ll = CscMatrix::from(&k_ll);
    let factor = SymbolicFactor::analyze(k_ll.pattern())
        .and_then(|s| s.with_max_ratio(max_ratio).factor_llt(&k_ll, Par::Seq))
        .map_err(|e| {
            format!("the SUPORT DOFs do not hold every rigid-body motion: the stiffness with them held (K_ll) is singular ({e}); add SUPORT components until the structure is statically determinate")
        })?;
    let mut d = Mat::<f64>::zeros(n_l, n_r);
    for k in 0..n_r {
        let mut x: Vec<f64> = (0..n_l).map(|i| -k_lr[(i, k)]).collect();
        factor
            .solve_in_place(&mut x)
            .map_err(|e| format!("SUPORT rigid-body shapes: {e}"))?;
        (0..n_l).for_each(|i| d[(i, k)] = x[i]);
    }
    // X = K_rr + K_rl D
    let x = Mat::<f64>::from_fn(n_r, n_r, |a, b| {
        k_rr[(a, b)] + (0..n_l).map(|i| k_lr[(i, a)] * d[(i, b)]).sum::<f64>()
    });
    let frobenius = |m: &Mat<f64>| {
        let mut s = 0.0;
        for j in 0..m.ncols() {
            for i in 0..m.nrows() {
                s += m[(i, j)] * m[(i, j)];
            }
        }
        s.sqrt()
    };
    let (x_norm, k_norm) = (frobenius(&x), frobenius(&k_rr));
    let epsilon = if k_norm > 0.0 {
        x_norm / k_norm
    } else {
        x_norm
    };
    let strain_energy = (0..n_r).map(|k| x[(k, k)]).collect();
    let mut shapes = Mat::<f64>::from_fn(n_f, n_r, |i, k| match l_of[i] {
        Some(l) => d[(l, k)],
        None => f64::from(u8::from(r[k] == i)),
    });
    m_orthonormalize(&c.m_ff, &mut shapes)?;
    let k_norm1 = (c.k_ff.col_iter())
        .map(|col| col.values().iter().map(|v| v.abs()).sum::<f64>())
        .fold(0.0, f64::max);
    let mut kx = vec![0.0; n_f];
    let mut residuals = Vec::with_capacity(n_r);
    for k in 0..n_r {
        let x: Vec<f64> = (0..n_f).map(|i| shapes[(i, k)]).collect();
        sym_matvec(&c.k_ff, &x, &mut kx).map_err(|e| e.to_string())?;
        let norm = |v: &[f64]| v.iter().map(|a| a * a).sum::<f64>().sqrt();
        residuals.push(norm(&kx) / (k_norm1 * norm(&x)).max(f64::MIN_POSITIVE));
    }
    Ok(RigidBodyModes {
        epsilon,
        strain_energy,
        shapes,
        residuals,
    })
}

/// Modified Gram–Schmidt in the M inner product, twice (the rigid shapes of a long structure
/// are far from M-orthogonal); a shape with no mass left is an error.
fn m_orthonormalize(m: &CscMatrix<f64>, v: &mut Mat<f64>) -> Result<(), String> {
    let (n, k) = (v.nrows(), v.ncols());
    let mut mx = vec![0.0; n];
    for j in 0..k {
        let mut x: Vec<f64> = (0..n).map(|i| v[(i, j)]).collect();
        for _ in 0..2 {
            sym_matvec(m, &x, &mut mx).map_err(|e| e.to_string())?;
            for p in 0..j {
                let a: f64 = (0..n).map(|i| v[(i, p)] * mx[i]).sum();
                (0..n).for_each(|i| x[i] -= a * v[(i, p)]);
            }
        }
        sym_matvec(m, &x, &mut mx).map_err(|e| e.to_string())?;
        let norm = x.iter().zip(&mx).map(|(a, b)| a * b).sum::<f64>();
        if !(norm > 0.0) {
            return Err(format!(
                "SUPORT rigid-body shape {} has no mass: the structure's mass does not move with it",
                j + 1
            ));
        }
        let norm = norm.sqrt();
        (0..n).for_each(|i| v[(i, j)] = x[i] / norm);
    }
    Ok(())
}
