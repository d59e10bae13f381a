//! A dense square matrix factored in place by LU with partial pivoting (faer's kernel, run
//! sequentially: the GGL iteration matrices of a few hundred rows are too small to gain from
//! threads, and their factorization is kept across many solves), with a solve that allocates
//! nothing.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::lu::partial_pivoting::{factor, solve};
use faer::perm::PermRef;
use faer::{Conj, Mat, MatMut, Par};

/// The matrix to assemble, then its LU factors in place (see module docs).
pub struct DenseLu {
    matrix: Mat<f64>,
    forward: Vec<usize>,
    inverse: Vec<usize>,
    factor_stack: MemBuffer,
    solve_stack: MemBuffer,
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
            solve_stack: MemBuffer::new(solve::solve_in_place_scratch::<usize, f64>(
                n,
                1,
                Par::Seq,
            )),
        }
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

    /// x ← A⁻¹ x with the factors (non-finite entries when A is singular).
    pub fn solve(&mut self, x: &mut [f64]) {
        let n = x.len();
        // SAFETY: `forward` and `inverse` are the inverse permutations written by the
        // factorization
        let perm = unsafe { PermRef::new_unchecked(&self.forward, &self.inverse, n) };
        solve::solve_in_place_with_conj(
            self.matrix.as_ref(),
            self.matrix.as_ref(),
            perm,
            Conj::No,
            MatMut::from_column_major_slice_mut(x, n, 1),
            Par::Seq,
            MemStack::new(&mut self.solve_stack),
        );
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
