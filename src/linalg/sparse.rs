//! Sparse helpers for full-pattern symmetric CSC matrices (see the module doc of `linalg`).

use nalgebra_sparse::{CooMatrix, CscMatrix};

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
