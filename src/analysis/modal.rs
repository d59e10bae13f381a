//! Normal modes of a constrained structure, K_ff φ = λ M_ff φ, as the library call behind
//! SOL 103: the shift-invert Lanczos of [`crate::linalg::eigen`] on the f-set with one
//! symbolic analysis per f-set ([`SymbolicCache`]), the NORM = MAX scaling, and the mode shapes
//! recovered on every grid.

use faer::Par;

use crate::assembly::AssemblyError;
use crate::assembly::recover::recover_g;
use crate::discretize::{Constrained, Structure};
use crate::linalg::{
    EigenProblem, EigenRequest, EigenResult, LanczosOptions, LinalgError, Mat, Progress,
    SymbolicFactor, solve_modes,
};

/// The symbolic analyses of K_ff's pattern, one per distinct f-set (K_ff and M_ff share it).
#[derive(Default)]
pub struct SymbolicCache {
    analyses: Vec<(Vec<usize>, SymbolicFactor)>,
}

impl SymbolicCache {
    /// The analysis of `c`'s f-set, if it has been made.
    pub fn get(&self, c: &Constrained) -> Option<&SymbolicFactor> {
        let f = c.sets.f.members();
        self.analyses
            .iter()
            .find(|(key, _)| key.as_slice() == f)
            .map(|(_, s)| s)
    }

    /// Analyzes `c`'s K_ff pattern (ordering, elimination tree) and keeps it for its f-set.
    pub fn analyze(&mut self, c: &Constrained) -> Result<(), LinalgError> {
        let symbolic = SymbolicFactor::analyze(c.k_ff.pattern())?;
        self.analyses.push((c.sets.f.members().to_vec(), symbolic));
        Ok(())
    }
}

/// The modes `request` asks for of `c` (shift-invert Lanczos with the symbolic analysis
/// `symbolic` of its K_ff), M-normalized. A zero pivot of K − σM is a
/// [`LinalgError`] that [`Constrained::mechanism_dof`] may name.
pub fn modes(
    c: &Constrained,
    request: &EigenRequest,
    symbolic: &SymbolicFactor,
    par: Par,
    progress: &dyn Progress,
) -> Result<EigenResult, LinalgError> {
    let problem = EigenProblem {
        k: &c.k_ff,
        m: &c.m_ff,
        symbolic,
    };
    solve_modes(&problem, request, &LanczosOptions::default(), par, progress)
}

/// Scales each mode so that its largest |component| is 1 (Nastran's NORM = MAX) and returns
/// the generalized masses φᵀMφ of the scaled modes (1/s² for a mass-normalized mode scaled by
/// 1/s; a zero mode is left as it is, with generalized mass 1).
pub fn normalize_to_unit_max(vectors: &mut Mat<f64>) -> Vec<f64> {
    let (nf, m) = (vectors.nrows(), vectors.ncols());
    let mut generalized_mass = vec![1.0; m];
    for (j, gm) in generalized_mass.iter_mut().enumerate() {
        let s = (0..nf).fold(0.0_f64, |acc, i| acc.max(vectors[(i, j)].abs()));
        if s > 0.0 {
            for i in 0..nf {
                vectors[(i, j)] /= s;
            }
            *gm = 1.0 / (s * s);
        }
    }
    generalized_mass
}

/// The f-set mode shapes `vectors` (n_f × m) on every grid, in basic: m blocks of n × 6 rows
/// (dependent RBE DOFs recovered, constrained DOFs zero).
pub fn shapes_in_basic(
    st: &Structure,
    c: &Constrained,
    vectors: &Mat<f64>,
) -> Result<Vec<f64>, AssemblyError> {
    let (nf, m) = (vectors.nrows(), vectors.ncols());
    let zero = vec![0.0; st.map.size()];
    let mut shapes = Vec::with_capacity(m * 6 * st.map.grids());
    let mut u_f = vec![0.0; nf];
    for j in 0..m {
        for (i, u) in u_f.iter_mut().enumerate() {
            *u = vectors[(i, j)];
        }
        let u_g = recover_g(&u_f, &c.sets, &zero, &st.rigid)?;
        shapes.extend(st.to_basic_rows(&u_g));
    }
    Ok(shapes)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unit_max_scaling_returns_the_scaled_generalized_mass() {
        // two mass-normalized modes of M = diag(1, 4): φ₁ = (1, 0), φ₂ = (0, ½); a zero column
        let mut v = Mat::<f64>::from_fn(2, 3, |i, j| match (i, j) {
            (0, 0) => -1.0,
            (1, 1) => 0.5,
            _ => 0.0,
        });
        let gm = normalize_to_unit_max(&mut v);
        assert_eq!(gm, vec![1.0, 4.0, 1.0]);
        assert_eq!((v[(0, 0)], v[(1, 1)]), (-1.0, 1.0));
    }
}
