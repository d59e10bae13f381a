//! Redundant constraints: the rows of Φ_q that are linear combinations of others (a planar
//! loop of revolute joints between rigid bodies has three). A column-pivoted QR of Φ_qᵀ,
//! Φ_qᵀ P = Q R, orders the constraints by how much each adds to the span of those before it;
//! |R_kk| ≤ tol · |R_00| marks the k-th pivoted constraint (and all after it) as dependent.
//!
//! Where a step fails (a loop at a dead centre, where Φ_q loses a rank the assembly did not see
//! lost), the singular value decomposition Φ_q = U Σ Vᵀ names the rows that became dependent:
//! the left singular vector of the smallest σ holds the weights y of the combination
//! Φ_qᵀ y = σ_min v closest to zero, and the rows with a large weight are the ones that lost
//! their independence ([`weakest_combination`]).

use faer::MatRef;

/// Relative weight above which a row takes part in the weakest combination of rows.
const PARTICIPATION: f64 = 0.1;

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

/// The combination of rows of a Jacobian closest to linear dependence.
#[derive(Debug, Clone, PartialEq)]
pub struct WeakestCombination {
    /// σ_min / σ_max of the Jacobian (0 when it has a zero row space or the decomposition fails).
    pub ratio: f64,
    /// Rows whose weight in the combination is at least a tenth of the largest, largest first.
    pub rows: Vec<usize>,
}

/// The rows of `jacobian` (m × n, m ≤ n) that come closest to depending on each other: the
/// left singular vector of its smallest singular value (module docs).
pub fn weakest_combination(jacobian: MatRef<'_, f64>) -> WeakestCombination {
    let m = jacobian.nrows();
    let none = WeakestCombination {
        ratio: 0.0,
        rows: Vec::new(),
    };
    if m == 0 || m > jacobian.ncols() {
        return none;
    }
    let Ok(svd) = jacobian.thin_svd() else {
        return none;
    };
    let sigma = svd.S().column_vector();
    // faer orders the singular values from the largest down
    let (largest, smallest) = (sigma[0], sigma[m - 1]);
    let weights = svd.U().col(m - 1);
    let top = weights.iter().fold(0.0_f64, |a, w| a.max(w.abs()));
    let mut rows: Vec<usize> = (0..m)
        .filter(|&i| weights[i].abs() >= PARTICIPATION * top)
        .collect();
    rows.sort_by(|&a, &b| weights[b].abs().total_cmp(&weights[a].abs()));
    WeakestCombination {
        ratio: if largest > 0.0 {
            smallest / largest
        } else {
            0.0
        },
        rows,
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

    #[test]
    fn the_weakest_combination_names_the_nearly_dependent_rows() {
        // rows 0 and 2 differ by 1e-8 in one entry; row 1 is independent of both
        let j = mat![
            [1.0, 0.0, 0.0, 2.0],
            [0.0, 1.0, 0.0, 0.0],
            [1.0, 0.0, 1e-8, 2.0],
        ];
        let weakest = weakest_combination(j.as_ref());
        assert!(weakest.ratio < 1e-8, "{}", weakest.ratio);
        let mut rows = weakest.rows.clone();
        rows.sort_unstable();
        assert_eq!(rows, vec![0, 2]);
    }
}
