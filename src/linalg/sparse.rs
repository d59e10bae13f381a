//! Sparse helpers for full-pattern symmetric CSC matrices (see the module doc of `linalg`).

use faer::Par;
use nalgebra_sparse::{CooMatrix, CscMatrix};
use rayon::prelude::*;

use super::LinalgError;

/// Expands a matrix that stores only the upper triangle (row ≤ col) into the full symmetric
/// pattern used throughout `linalg`. Fails with [`LinalgError::NotUpperTriangular`] on the first
/// entry below the diagonal, and [`LinalgError::NotSquare`] for a rectangular input.
pub fn full_from_upper(upper: &CscMatrix<f64>) -> Result<CscMatrix<f64>, LinalgError> {
    let n = upper.nrows();
    if upper.ncols() != n {
        return Err(LinalgError::NotSquare {
            nrows: n,
            ncols: upper.ncols(),
        });
    }
    let mut coo = CooMatrix::new(n, n);
    for (row, col, &v) in upper.triplet_iter() {
        if row > col {
            return Err(LinalgError::NotUpperTriangular { row, col });
        }
        coo.push(row, col, v);
        if row != col {
            coo.push(col, row, v);
        }
    }
    Ok(CscMatrix::from(&coo))
}

/// y = A x for a full-pattern CSC matrix, writing into the caller's buffer (no allocation).
/// For a symmetric A this is also Aᵀx. Fails on mismatched lengths.
pub fn sym_matvec(a: &CscMatrix<f64>, x: &[f64], y: &mut [f64]) -> Result<(), LinalgError> {
    for len in [x.len(), y.len()] {
        if len != a.ncols() || a.nrows() != a.ncols() {
            return Err(LinalgError::DimensionMismatch {
                expected: a.ncols(),
                got: len,
            });
        }
    }
    matvec_unchecked(a, x, y);
    Ok(())
}

/// Columns per rayon task of [`sym_matvec_gather`].
const GATHER_CHUNK: usize = 4096;

/// y = A x for a symmetric full-pattern CSC matrix as column dot products, yⱼ = Σᵢ A_ij xᵢ
/// (= (Aᵀx)ⱼ = (Ax)ⱼ for symmetric A). Each yⱼ is one sequential sum over its column, so the
/// result is the same for any number of threads; with a parallel `par` the columns are split
/// over rayon tasks. Unlike the scatter of [`matvec_unchecked`] it stores each yⱼ once, which
/// is also faster on one thread. The caller guarantees `x.len() == y.len() == a.ncols() ==
/// a.nrows()` and the symmetry of A (values, not only the pattern).
pub(crate) fn sym_matvec_gather(a: &CscMatrix<f64>, x: &[f64], y: &mut [f64], par: Par) {
    let (offsets, rows, vals) = (a.col_offsets(), a.row_indices(), a.values());
    let columns = |first: usize, out: &mut [f64]| {
        for (c, yj) in out.iter_mut().enumerate() {
            let range = offsets[first + c]..offsets[first + c + 1];
            *yj = rows[range.clone()]
                .iter()
                .zip(&vals[range])
                .map(|(&i, &v)| v * x[i])
                .sum();
        }
    };
    match par {
        Par::Rayon(threads) if threads.get() > 1 && y.len() > GATHER_CHUNK => {
            y.par_chunks_mut(GATHER_CHUNK)
                .enumerate()
                .for_each(|(k, out)| columns(k * GATHER_CHUNK, out));
        }
        _ => columns(0, y),
    }
}

/// y = A x; the caller guarantees `x.len() == y.len() == a.ncols() == a.nrows()`.
pub(crate) fn matvec_unchecked(a: &CscMatrix<f64>, x: &[f64], y: &mut [f64]) {
    y.fill(0.0);
    let (offsets, rows, vals) = (a.col_offsets(), a.row_indices(), a.values());
    for (j, &xj) in x.iter().enumerate() {
        let range = offsets[j]..offsets[j + 1];
        for (&i, &v) in rows[range.clone()].iter().zip(&vals[range]) {
            y[i] += v * xj;
        }
    }
}

/// Largest absolute column sum ‖A‖₁ (= ‖A‖∞ for symmetric A).
pub(crate) fn norm_1(a: &CscMatrix<f64>) -> f64 {
    let offsets = a.col_offsets();
    (0..a.ncols())
        .map(|j| {
            a.values()[offsets[j]..offsets[j + 1]]
                .iter()
                .map(|v| v.abs())
                .sum::<f64>()
        })
        .fold(0.0, f64::max)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The gather product equals the scatter product of a symmetric matrix to round-off (sums
    /// in another order), on one thread and split over rayon tasks (more columns than one
    /// task takes), and the split does not change a bit.
    #[test]
    fn gather_product_matches_the_scatter_product() {
        let n = 3 * GATHER_CHUNK + 17;
        let mut rng = crate::linalg::random::SplitMix64::new(7);
        let mut coo = CooMatrix::new(n, n);
        for j in 0..n {
            coo.push(j, j, 4.0 + rng.symmetric());
            for off in [1, 5, 400] {
                if j + off < n {
                    let v = rng.symmetric();
                    coo.push(j, j + off, v);
                    coo.push(j + off, j, v);
                }
            }
        }
        let a = CscMatrix::from(&coo);
        let x: Vec<f64> = (0..n).map(|_| rng.symmetric()).collect();
        let mut scatter = vec![0.0; n];
        matvec_unchecked(&a, &x, &mut scatter);
        let (mut seq, mut par) = (vec![0.0; n], vec![0.0; n]);
        sym_matvec_gather(&a, &x, &mut seq, Par::Seq);
        sym_matvec_gather(&a, &x, &mut par, Par::rayon(2));
        assert_eq!(seq, par);
        let worst = (0..n).fold(0.0_f64, |w, i| w.max((seq[i] - scatter[i]).abs()));
        // four products of magnitude ≤ 5 per row: a few ulps of 20
        assert!(worst <= 1e-13, "{worst:e}");
    }

    #[test]
    fn upper_to_full_mirrors_off_diagonal_entries() {
        let mut coo = CooMatrix::new(3, 3);
        coo.push(0, 0, 2.0);
        coo.push(0, 1, -1.0);
        coo.push(1, 1, 2.0);
        coo.push(1, 2, -1.0);
        coo.push(2, 2, 2.0);
        let full = full_from_upper(&CscMatrix::from(&coo)).unwrap();
        assert_eq!(full.nnz(), 7);
        let mut y = [0.0; 3];
        sym_matvec(&full, &[1.0, 1.0, 1.0], &mut y).unwrap();
        assert_eq!(y, [1.0, 0.0, 1.0]);
        let mut bad = CooMatrix::new(2, 2);
        bad.push(1, 0, 1.0);
        assert_eq!(
            full_from_upper(&CscMatrix::from(&bad)).unwrap_err(),
            LinalgError::NotUpperTriangular { row: 1, col: 0 }
        );
    }
}
