//! Redundant constraints: the rows of Φ_q that are linear combinations of others (a planar
//! loop of revolute joints between rigid bodies has three). A column-pivoted QR of Φ_qᵀ,
//! Φ_qᵀ P = Q R, orders the constraints by how much each adds to the span of those before it;
//! |R_kk| ≤ tol · |R_00| marks the k-th pivoted constraint (and all after it) as dependent.

use faer::MatRef;

/// The split of a constraint set into independent rows and redundant ones.
#[derive(Debug, Clone, PartialEq)]
pub struct RankSplit {
    /// Rows kept, in increasing order.
    pub independent: Vec<usize>,
    /// Rows found dependent on the others, in increasing order.
    pub redundant: Vec<usize>,
}

/// Splits the rows of `jacobian` (m × n) by a column-pivoted QR of its transpose with the
/// relative tolerance `tol` on the diagonal of R.
pub fn split_rows(jacobian: MatRef<'_, f64>, tol: f64) -> RankSplit {
    let m = jacobian.nrows();
    if m == 0 {
        return RankSplit {
            independent: Vec::new(),
            redundant: Vec::new(),
        };
    }
    let transposed = jacobian.transpose().to_owned();
    let qr = transposed.col_piv_qr();
    let r = qr.R();
    let steps = r.nrows().min(r.ncols());
    let largest = if steps > 0 { r[(0, 0)].abs() } else { 0.0 };
    let rank = (0..steps)
        .take_while(|&k| largest > 0.0 && r[(k, k)].abs() > tol * largest)
        .count();
    let (forward, _) = qr.P().arrays();
    let mut independent: Vec<usize> = forward[..rank].to_vec();
    let mut redundant: Vec<usize> = forward[rank..].to_vec();
    independent.sort_unstable();
    redundant.sort_unstable();
    RankSplit {
        independent,
        redundant,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::mat;

    #[test]
    fn a_repeated_row_and_a_sum_of_rows_are_redundant() {
        let j = mat![
            [1.0, 0.0, 0.0, 2.0],
            [0.0, 1.0, 0.0, 0.0],
            [1.0, 0.0, 0.0, 2.0],
            [1.0, 1.0, 0.0, 2.0],
            [0.0, 0.0, 1.0, 0.0],
        ];
        let split = split_rows(j.as_ref(), 1e-10);
        assert_eq!(split.independent.len(), 3);
        assert_eq!(split.redundant.len(), 2);
        assert!(split.independent.contains(&4));
    }
}
