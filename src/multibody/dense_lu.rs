//! A dense square matrix factored in place by LU with partial pivoting (faer's kernel, run
//! sequentially: the GGL iteration matrices of a few hundred rows are too small to gain from
//! threads, and their factorization is kept across many solves), with a solve that allocates
//! nothing: plain column-oriented triangular sweeps, which for the blocks of a few dozen rows
//! of [`super::block_kkt`] cost a fraction of a general kernel's set-up.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::lu::partial_pivoting::factor;
use faer::{Mat, MatMut, Par};

/// The matrix to assemble, then its LU factors in place (see module docs).
pub struct DenseLu {
    matrix: Mat<f64>,
    forward: Vec<usize>,
    inverse: Vec<usize>,
    factor_stack: MemBuffer,
    /// The permuted right-hand side.
    permuted: Vec<f64>,
}

impl DenseLu {
    /// An n × n matrix of zeros.
    pub fn new(n: usize) -> Self {
        Self {
            matrix: Mat::zeros(n, n),
            forward: vec![0; n],
            inverse: vec![0; n],
            factor_stack: MemBuffer::new(factor::lu_in_place_scratch::<usize, f64>(
                n,
                n,
                Par::Seq,
                Default::default(),
            )),
            permuted: vec![0.0; n],
        }
    }

    /// Number of rows n.
    pub fn size(&self) -> usize {
        self.matrix.nrows()
    }

    /// The matrix to assemble (its factors after [`DenseLu::factor`]).
    pub fn matrix_mut(&mut self) -> MatMut<'_, f64> {
        self.matrix.as_mut()
    }

    /// Factors the assembled matrix in place: P A = L U.
    pub fn factor(&mut self) {
        factor::lu_in_place(
            self.matrix.as_mut(),
            &mut self.forward,
            &mut self.inverse,
            Par::Seq,
            MemStack::new(&mut self.factor_stack),
            Default::default(),
        );
    }

    /// x ← A⁻¹ x with the factors (non-finite entries when A is singular): x ← P x, then
    /// L (unit lower) and U solved column by column.
    pub fn solve(&mut self, x: &mut [f64]) {
        let n = x.len();
        for (p, &i) in self.permuted.iter_mut().zip(&self.forward) {
            *p = x[i];
        }
        x.copy_from_slice(&self.permuted);
        let a = &self.matrix;
        for j in 0..n {
            let xj = x[j];
            if xj != 0.0 {
                let column = &a.col_as_slice(j)[j + 1..];
                for (xi, lij) in x[j + 1..].iter_mut().zip(column) {
                    *xi -= lij * xj;
                }
            }
        }
        for j in (0..n).rev() {
            x[j] /= a[(j, j)];
            let xj = x[j];
            if xj != 0.0 {
                let column = &a.col_as_slice(j)[..j];
                for (xi, uij) in x[..j].iter_mut().zip(column) {
                    *xi -= uij * xj;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn solves_a_system_that_needs_pivoting() {
        let a = [[0.0, 2.0, 1.0], [1.0, 1.0, 0.0], [3.0, 0.0, 1.0]];
        let mut lu = DenseLu::new(3);
        let mut m = lu.matrix_mut();
        for i in 0..3 {
            for j in 0..3 {
                m[(i, j)] = a[i][j];
            }
        }
        lu.factor();
        let expected = [1.0, -2.0, 0.5];
        let mut x: Vec<f64> = (0..3)
            .map(|i| (0..3).map(|j| a[i][j] * expected[j]).sum())
            .collect();
        lu.solve(&mut x);
        for (x, e) in x.iter().zip(expected) {
            assert!((x - e).abs() < 1e-14, "{x} vs {e}");
        }
    }
}
