//! The local basis Ψ_i = [Ψ_nm,i Ψ_sm,i] of one parameter sample (thesis §2.3.2, eq. 2.28;
//! §3.4.1 "Local bases and matrices generation"; DESIGN.md §7 step 2).
//!
//! - Normal modes: the shift-invert Lanczos of [`crate::linalg::eigen`] (NMODES modes, or those
//!   below FMAX), sharing the caller's symbolic factorization.
//! - Static modes, `STATIC = ATTACH`: attachment (unit-load) modes K ψ_b = e_b for every boundary
//!   DOF b. When the structure is free (rigid-body modes Φ_r at ≈ 0 Hz) K is singular and the
//!   modes are the inertia-relief ones: the load is made self-equilibrated, f̃ = e_b − M Φ_r Φ_rᵀ e_b,
//!   and ψ_b is the solution of K ψ = f̃ that is M-orthogonal to Φ_r. It is computed with the
//!   regular K − σM (σ = −λ₁/100 < 0) by the fixed-point iteration
//!   ψ ← (K − σM)⁻¹ (f̃ − σ M ψ), projected on the elastic subspace, which converges with the
//!   ratio |σ|/(λ₁ − σ) per step (λ₁ the first elastic eigenvalue).
//! - Static modes, `STATIC = CONSTR`: Craig–Bampton (thesis §2.3.2). The normal modes are those
//!   of the fixed interface (boundary DOFs b held, pencil (K_ii, M_ii) of the interior DOFs i)
//!   and the static modes the constraint modes: unit displacement at one boundary DOF, the
//!   other boundary DOFs held, interior in static equilibrium, ψ_b = [−K_ii⁻¹ K_ib e_b; e_b],
//!   all from one factorization of K_ii per sample. The interior pattern and its symbolic
//!   analysis are computed once ([`LocalBasisSetup`]) and shared by every sample. The
//!   constraint modes carry the rigid-body motion, so `RIGID = REMOVE` is refused with them.
//! - `RIGID = REMOVE` drops the rigid-body modes from the basis (floating-frame bodies: the
//!   multibody frame carries the rigid motion); `KEEP` keeps them. The modes found are
//!   returned either way, for [`remove_rigid_content`]: a pROM build makes the columns of all
//!   samples M-orthogonal to one set of them (each sample's own, computed to the eigen
//!   solver's tolerance, differ from sample to sample by more than round-off).
//!
//! Rigid-body modes are recognised as λ ≤ [`RIGID_REL`] · λ_max of the modes computed.

use faer::{Mat, Par};
use nalgebra_sparse::CscMatrix;

use crate::linalg::{
    EigenProblem, EigenRequest, LanczosOptions, LinalgError, Progress, SymbolicFactor, solve_modes,
    sym_matvec,
};

/// λ below this fraction of the largest computed eigenvalue counts as a rigid-body mode. The
/// eigen solver returns rigid-body λ at round-off (≈ 1e-12 of ‖K‖/‖M‖ or less); an elastic
/// mode 1e4 times below the highest requested one in frequency (1e-8 in λ) does not occur in a
/// local basis of a few tens of modes.
pub const RIGID_REL: f64 = 1e-8;

/// The inertia-relief shift σ = −RELIEF_SHIFT·λ₁ (λ₁ the first elastic eigenvalue): the
/// iteration then contracts by |σ|/(λ₁ − σ) ≈ 0.01 per step (≈ 7 steps to 1e-13), while
/// K − σM stays as well conditioned on the elastic subspace as K itself.
const RELIEF_SHIFT: f64 = 0.01;

/// Relative change of the inertia-relief iteration at which it has converged
/// (‖Δψ‖ ≤ tol·‖ψ‖).
const RELIEF_TOL: f64 = 1e-13;
/// Below this relative change, a change that no longer decreases is round-off: the iteration
/// has converged as far as the factorization allows (an ill-conditioned K − σM, e.g. a stiff
/// composite ply direction, leaves its round-off above [`RELIEF_TOL`]).
const RELIEF_STAGNATION: f64 = 1e-10;
const RELIEF_MAX_ITERATIONS: usize = 60;

/// Whether the inertia-relief iteration stops after a step whose relative change is `change`
/// (`previous`: the step before's): at [`RELIEF_TOL`], or when the change has stopped
/// decreasing below [`RELIEF_STAGNATION`]. A contracting iteration (factor ≈ 0.01) reaches
/// [`RELIEF_TOL`] with every change smaller than the one before, so it stops as at a fixed
/// tolerance.
fn relief_converged(change: f64, previous: f64) -> bool {
    change <= RELIEF_TOL || (change <= RELIEF_STAGNATION && change >= previous)
}

/// Which static modes to add (PMOR STATIC).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StaticModes {
    /// Unit-load (attachment) modes at the boundary DOFs.
    Attach,
    /// Craig–Bampton: fixed-interface normal modes and constraint modes at the boundary DOFs.
    Constr,
    /// No static modes.
    None,
}

/// Rigid-body modes in the basis (PMOR RIGID).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RigidModes {
    Keep,
    Remove,
}

/// What one local basis holds.
#[derive(Debug, Clone)]
pub struct LocalBasisRequest {
    /// Elastic normal modes wanted (NMODES).
    pub n_modes: usize,
    /// Upper frequency of the band (FMAX, Hz): modes above it are not wanted even if fewer
    /// than `n_modes`.
    pub fmax_hz: Option<f64>,
    /// Boundary DOFs (f-set indices) for static modes.
    pub boundary: Vec<usize>,
    pub statics: StaticModes,
    pub rigid: RigidModes,
}

/// Ψ_i with what it is made of.
#[derive(Debug, Clone)]
pub struct LocalBasis {
    /// n × (rigid kept + elastic + static) columns, in that order.
    pub vectors: Mat<f64>,
    /// Frequencies (Hz) of the normal-mode columns (rigid kept, then elastic).
    pub frequencies_hz: Vec<f64>,
    /// The rigid-body modes found (n × n_rigid, M-normalized; whether kept or not).
    pub rigid: Mat<f64>,
    /// Static-mode columns (last).
    pub n_static: usize,
}

/// Errors of a local basis.
#[derive(Debug, thiserror::Error)]
pub enum LocalBasisError {
    #[error(transparent)]
    Linalg(#[from] LinalgError),
    #[error("boundary DOF index {index} is outside the f-set of size {size}")]
    BoundaryOutOfRange { index: usize, size: usize },
    #[error("STATIC = CONSTR needs boundary DOFs (BSET)")]
    ConstrWithoutBoundary,
    #[error(
        "RIGID = REMOVE cannot be combined with STATIC = CONSTR: the constraint modes carry the rigid-body motion"
    )]
    ConstrRemovesRigid,
    #[error(
        "STATIC = CONSTR: the stiffness of the interior DOFs with the boundary DOFs held is singular (the boundary does not restrain the rigid-body motion): {0}"
    )]
    ConstrSingular(LinalgError),
    #[error(
        "the inertia-relief static mode of boundary DOF {dof} did not converge (relative change {change:.1e} after {RELIEF_MAX_ITERATIONS} iterations): the first elastic mode is too close to the shift"
    )]
    ReliefNotConverged { dof: usize, change: f64 },
}

/// A validated [`LocalBasisRequest`] with what every sample shares: for `STATIC = CONSTR`
/// the interior DOFs and the symbolic analysis of their pattern.
pub struct LocalBasisSetup {
    request: LocalBasisRequest,
    fixed: Option<FixedInterface>,
}

/// The interior (non-boundary) DOFs of a Craig–Bampton basis.
struct FixedInterface {
    /// Interior index of each f-set DOF (`None` on the boundary).
    interior_of: Vec<Option<usize>>,
    interior: Vec<usize>,
    symbolic: SymbolicFactor,
}

impl LocalBasisSetup {
    /// Checks the request against the size of K (`pattern_of`: any matrix with K's pattern).
    pub fn new(
        pattern_of: &CscMatrix<f64>,
        request: LocalBasisRequest,
    ) -> Result<Self, LocalBasisError> {
        let n = pattern_of.nrows();
        if let Some(&index) = request.boundary.iter().find(|&&b| b >= n) {
            return Err(LocalBasisError::BoundaryOutOfRange { index, size: n });
        }
        let fixed = match request.statics {
            StaticModes::Constr => {
                if request.boundary.is_empty() {
                    return Err(LocalBasisError::ConstrWithoutBoundary);
                }
                if request.rigid == RigidModes::Remove {
                    return Err(LocalBasisError::ConstrRemovesRigid);
                }
                let mut interior_of = vec![Some(0); n];
                request.boundary.iter().for_each(|&b| interior_of[b] = None);
                let interior: Vec<usize> = (0..n).filter(|&i| interior_of[i].is_some()).collect();
                interior
                    .iter()
                    .enumerate()
                    .for_each(|(new, &old)| interior_of[old] = Some(new));
                let symbolic = SymbolicFactor::analyze(
                    principal(pattern_of, &interior_of, interior.len()).pattern(),
                )?;
                Some(FixedInterface {
                    interior_of,
                    interior,
                    symbolic,
                })
            }
            StaticModes::Attach | StaticModes::None => None,
        };
        Ok(Self { request, fixed })
    }
}

/// The principal submatrix of `a` on the DOFs with an index in `new_of` (structural entries
/// kept, so K and M on one pattern give submatrices on one pattern).
fn principal(a: &CscMatrix<f64>, new_of: &[Option<usize>], size: usize) -> CscMatrix<f64> {
    let (offsets, rows, values) = (a.col_offsets(), a.row_indices(), a.values());
    let (mut col_offsets, mut row_indices, mut kept) = (vec![0], Vec::new(), Vec::new());
    for (j, new_j) in new_of.iter().enumerate() {
        if new_j.is_none() {
            continue;
        }
        for k in offsets[j]..offsets[j + 1] {
            if let Some(new_i) = new_of[rows[k]] {
                row_indices.push(new_i);
                kept.push(values[k]);
            }
        }
        col_offsets.push(row_indices.len());
    }
    CscMatrix::try_from_csc_data(size, size, col_offsets, row_indices, kept)
        .expect("a principal submatrix of a valid CSC matrix is valid")
}

/// Build the local basis of the pencil (K, M).
pub fn local_basis(
    problem: &EigenProblem<'_>,
    setup: &LocalBasisSetup,
    par: Par,
    progress: &dyn Progress,
) -> Result<LocalBasis, LocalBasisError> {
    let request = &setup.request;
    if let Some(fixed) = &setup.fixed {
        return craig_bampton(problem, request, fixed, par, progress);
    }
    let n = problem.k.nrows();
    // Ask for 6 more than wanted so the rigid-body modes of a free body do not eat the elastic
    // ones (a free 3-D body has at most 6; mechanisms are refused upstream).
    let wanted = request.n_modes + 6;
    let eigen = solve_modes(
        problem,
        &EigenRequest {
            v1_hz: None,
            v2_hz: request.fmax_hz,
            nd: Some(wanted.min(n)),
            shift_hz: None,
        },
        &LanczosOptions::default(),
        par,
        progress,
    )?;
    let lambda_max = eigen.eigenvalues.iter().copied().fold(0.0, f64::max);
    let is_rigid: Vec<bool> = eigen
        .eigenvalues
        .iter()
        .map(|&l| l <= RIGID_REL * lambda_max)
        .collect();
    let rigid_cols: Vec<usize> = (0..is_rigid.len()).filter(|&j| is_rigid[j]).collect();
    let elastic_cols: Vec<usize> = (0..is_rigid.len())
        .filter(|&j| !is_rigid[j])
        .take(request.n_modes)
        .collect();
    let kept_normal: Vec<usize> = match request.rigid {
        RigidModes::Keep => rigid_cols.iter().chain(&elastic_cols).copied().collect(),
        RigidModes::Remove => elastic_cols.clone(),
    };
    let statics = match request.statics {
        StaticModes::None | StaticModes::Constr => Mat::zeros(n, 0),
        StaticModes::Attach => {
            let lambda_1 = elastic_cols
                .first()
                .map(|&j| eigen.eigenvalues[j])
                .unwrap_or(lambda_max);
            attachment_modes(
                problem,
                &eigen.vectors,
                &rigid_cols,
                -RELIEF_SHIFT * lambda_1,
                &request.boundary,
                par,
            )?
        }
    };
    let n_static = statics.ncols();
    let vectors = Mat::from_fn(n, kept_normal.len() + n_static, |i, c| {
        if c < kept_normal.len() {
            eigen.vectors[(i, kept_normal[c])]
        } else {
            statics[(i, c - kept_normal.len())]
        }
    });
    Ok(LocalBasis {
        vectors,
        frequencies_hz: kept_normal
            .iter()
            .map(|&j| eigen.frequencies_hz[j])
            .collect(),
        rigid: Mat::from_fn(n, rigid_cols.len(), |i, c| {
            eigen.vectors[(i, rigid_cols[c])]
        }),
        n_static,
    })
}

/// Fixed-interface modes and constraint modes (module doc).
fn craig_bampton(
    problem: &EigenProblem<'_>,
    request: &LocalBasisRequest,
    fixed: &FixedInterface,
    par: Par,
    progress: &dyn Progress,
) -> Result<LocalBasis, LocalBasisError> {
    let n = problem.k.nrows();
    let ni = fixed.interior.len();
    let (k_ii, m_ii) = (
        principal(problem.k, &fixed.interior_of, ni),
        principal(problem.m, &fixed.interior_of, ni),
    );
    let factor = fixed
        .symbolic
        .factor_llt(&k_ii, par)
        .map_err(LocalBasisError::ConstrSingular)?;
    let interior = EigenProblem {
        k: &k_ii,
        m: &m_ii,
        symbolic: &fixed.symbolic,
    };
    let eigen = solve_modes(
        &interior,
        &EigenRequest {
            v1_hz: None,
            v2_hz: request.fmax_hz,
            nd: Some(request.n_modes.min(ni)),
            shift_hz: None,
        },
        &LanczosOptions::default(),
        par,
        progress,
    )?;
    let n_modes = eigen.vectors.ncols();
    let nb = request.boundary.len();
    let mut vectors = Mat::<f64>::zeros(n, n_modes + nb);
    for j in 0..n_modes {
        fixed
            .interior
            .iter()
            .enumerate()
            .for_each(|(r, &i)| vectors[(i, j)] = eigen.vectors[(r, j)]);
    }
    let mut scratch = factor.solve_scratch(1)?;
    let (offsets, rows, values) = (
        problem.k.col_offsets(),
        problem.k.row_indices(),
        problem.k.values(),
    );
    let mut x = vec![0.0; ni];
    for (c, &b) in request.boundary.iter().enumerate() {
        // −K_ib e_b: column b of K on the interior rows (K symmetric, full pattern)
        x.fill(0.0);
        for k in offsets[b]..offsets[b + 1] {
            if let Some(r) = fixed.interior_of[rows[k]] {
                x[r] = -values[k];
            }
        }
        factor.solve_in_place_with_scratch(
            faer::MatMut::from_column_major_slice_mut(&mut x, ni, 1),
            &mut scratch,
        )?;
        let col = n_modes + c;
        fixed
            .interior
            .iter()
            .enumerate()
            .for_each(|(r, &i)| vectors[(i, col)] = x[r]);
        vectors[(b, col)] = 1.0;
    }
    Ok(LocalBasis {
        vectors,
        frequencies_hz: eigen.frequencies_hz,
        rigid: Mat::zeros(n, 0),
        n_static: nb,
    })
}

/// Attachment modes (module doc): plain K ψ = e_b for a supported structure, inertia relief for
/// a free one.
fn attachment_modes(
    problem: &EigenProblem<'_>,
    modes: &Mat<f64>,
    rigid: &[usize],
    relief_shift: f64,
    boundary: &[usize],
    par: Par,
) -> Result<Mat<f64>, LocalBasisError> {
    let n = problem.k.nrows();
    let mut out = Mat::<f64>::zeros(n, boundary.len());
    if boundary.is_empty() {
        return Ok(out);
    }
    let free = !rigid.is_empty();
    let sigma = if free { relief_shift.min(0.0) } else { 0.0 };
    let shifted = shifted(problem, sigma);
    let factor = if sigma == 0.0 {
        problem.symbolic.factor_llt(problem.k, par)
    } else {
        problem.symbolic.factor_ldlt(&shifted, par)
    }?;
    let mut scratch = factor.solve_scratch(1)?;
    let mut m_x = vec![0.0; n];
    // M-orthogonal projection on the elastic subspace: x ← x − Φ_r Φ_rᵀ M x.
    let project = |x: &mut [f64], m_x: &mut [f64]| -> Result<(), LinalgError> {
        sym_matvec(problem.m, x, m_x)?;
        for &r in rigid {
            let phi = modes.col_as_slice(r);
            let c: f64 = phi.iter().zip(m_x.iter()).map(|(p, q)| p * q).sum();
            x.iter_mut().zip(phi).for_each(|(xi, p)| *xi -= c * p);
        }
        Ok(())
    };
    for (col, &b) in boundary.iter().enumerate() {
        // self-equilibrated load f̃ = e_b − M Φ_r Φ_rᵀ e_b
        let mut load = vec![0.0; n];
        load[b] = 1.0;
        if free {
            let mut m_phi = vec![0.0; n];
            for &r in rigid {
                let phi = modes.col_as_slice(r);
                sym_matvec(problem.m, phi, &mut m_phi)?;
                let c = phi[b];
                load.iter_mut().zip(&m_phi).for_each(|(l, mp)| *l -= c * mp);
            }
        }
        let mut x = load.clone();
        factor.solve_in_place_with_scratch(
            faer::MatMut::from_column_major_slice_mut(&mut x, n, 1),
            &mut scratch,
        )?;
        if free {
            project(&mut x, &mut m_x)?;
            let (mut change, mut previous) = (f64::INFINITY, f64::INFINITY);
            let mut iterations = 0;
            while !relief_converged(change, previous) {
                if iterations == RELIEF_MAX_ITERATIONS {
                    return Err(LocalBasisError::ReliefNotConverged { dof: b, change });
                }
                sym_matvec(problem.m, &x, &mut m_x)?;
                let mut next: Vec<f64> = load
                    .iter()
                    .zip(&m_x)
                    .map(|(l, mx)| l - sigma * mx)
                    .collect();
                factor.solve_in_place_with_scratch(
                    faer::MatMut::from_column_major_slice_mut(&mut next, n, 1),
                    &mut scratch,
                )?;
                project(&mut next, &mut m_x)?;
                let norm = next.iter().map(|v| v * v).sum::<f64>().sqrt();
                previous = change;
                change = next
                    .iter()
                    .zip(&x)
                    .map(|(a, b)| (a - b).powi(2))
                    .sum::<f64>()
                    .sqrt()
                    / norm.max(f64::MIN_POSITIVE);
                x = next;
                iterations += 1;
            }
        }
        out.col_as_slice_mut(col).copy_from_slice(&x);
    }
    Ok(out)
}

/// Removes the rigid-body content of every column x of `vectors` in the mass metric of `mass`:
/// x ← x − Φ (ΦᵀMΦ)⁻¹ ΦᵀM x, so that Φᵀ M x = 0 to round-off (the mean-axis conditions of a
/// floating frame, thesis §2.4). Φ = `rigid` need not be M-normalized. A column's span with
/// the rigid-body modes is unchanged, which is all a floating-frame body sees of it.
pub fn remove_rigid_content(
    vectors: &mut Mat<f64>,
    rigid: faer::MatRef<'_, f64>,
    mass: &CscMatrix<f64>,
) -> Result<(), LinalgError> {
    use faer::prelude::Solve;
    let (n, r) = (rigid.nrows(), rigid.ncols());
    if r == 0 || vectors.ncols() == 0 {
        return Ok(());
    }
    let mut m_phi = Mat::<f64>::zeros(n, r);
    let mut column = vec![0.0; n];
    for j in 0..r {
        column
            .iter_mut()
            .enumerate()
            .for_each(|(i, c)| *c = rigid[(i, j)]);
        sym_matvec(mass, &column, m_phi.col_as_slice_mut(j))?;
    }
    let gram = rigid.transpose() * &m_phi;
    let content = gram
        .partial_piv_lu()
        .solve(m_phi.transpose() * vectors.as_ref());
    *vectors -= rigid * &content;
    Ok(())
}

/// K − σM on K's pattern (M shares it).
fn shifted(problem: &EigenProblem<'_>, sigma: f64) -> CscMatrix<f64> {
    let mut a = problem.k.clone();
    if sigma != 0.0 {
        a.values_mut()
            .iter_mut()
            .zip(problem.m.values())
            .for_each(|(k, m)| *k -= sigma * m);
    }
    a
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::prelude::Solve;
    use nalgebra_sparse::CooMatrix;

    /// Spring chain of n unit masses and unit springs; `grounded` adds a spring to ground at
    /// the first mass. Full pattern, M on K's pattern.
    fn chain(n: usize, grounded: bool) -> (CscMatrix<f64>, CscMatrix<f64>) {
        let (mut k, mut m) = (CooMatrix::new(n, n), CooMatrix::new(n, n));
        for i in 0..n - 1 {
            for (a, b, v) in [
                (i, i, 1.0),
                (i + 1, i + 1, 1.0),
                (i, i + 1, -1.0),
                (i + 1, i, -1.0),
            ] {
                k.push(a, b, v);
                m.push(a, b, 0.0);
            }
        }
        for i in 0..n {
            m.push(i, i, 1.0);
        }
        if grounded {
            k.push(0, 0, 1.0);
        }
        (CscMatrix::from(&k), CscMatrix::from(&m))
    }

    fn quiet() -> impl Progress {
        |_: &str, _: usize, _: usize| {}
    }

    fn basis_with(
        k: &CscMatrix<f64>,
        m: &CscMatrix<f64>,
        statics: StaticModes,
        rigid: RigidModes,
        boundary: Vec<usize>,
    ) -> Result<LocalBasis, LocalBasisError> {
        let symbolic = SymbolicFactor::analyze(k.pattern()).unwrap();
        let problem = EigenProblem {
            k,
            m,
            symbolic: &symbolic,
        };
        let setup = LocalBasisSetup::new(
            k,
            LocalBasisRequest {
                n_modes: 3,
                fmax_hz: None,
                boundary,
                statics,
                rigid,
            },
        )?;
        local_basis(&problem, &setup, Par::Seq, &quiet())
    }

    fn basis(
        k: &CscMatrix<f64>,
        m: &CscMatrix<f64>,
        rigid: RigidModes,
        boundary: Vec<usize>,
    ) -> LocalBasis {
        basis_with(k, m, StaticModes::Attach, rigid, boundary).unwrap()
    }

    fn dense(a: &CscMatrix<f64>) -> Mat<f64> {
        let mut d = Mat::<f64>::zeros(a.nrows(), a.ncols());
        a.triplet_iter().for_each(|(i, j, v)| d[(i, j)] += *v);
        d
    }

    /// Free chain (K singular), boundary at both ends and inside: the constraint modes are the
    /// interior's static response to each unit boundary displacement, so Ψ_c u_b equals the
    /// full static response to prescribed boundary displacements u_b (interior unloaded),
    /// solved here independently by a dense LU of K_ii (bound 1e-12 relative: K_ii of the
    /// chain has condition ~n² = 400). The fixed-interface modes vanish on the boundary and are
    /// eigenvectors of (K_ii, M_ii) (residual bound 1e-9 relative: Lanczos Ritz tolerance).
    #[test]
    fn constraint_modes_reproduce_static_boundary_displacements() {
        let (k, m) = chain(20, false);
        let boundary = vec![19, 0, 7];
        let b = basis_with(
            &k,
            &m,
            StaticModes::Constr,
            RigidModes::Keep,
            boundary.clone(),
        )
        .unwrap();
        assert_eq!((b.rigid.ncols(), b.n_static, b.vectors.ncols()), (0, 3, 6));
        let u_b = [0.3, -1.1, 0.45];
        let interior: Vec<usize> = (0..20).filter(|i| !boundary.contains(i)).collect();
        let kd = dense(&k);
        let k_ii = Mat::<f64>::from_fn(interior.len(), interior.len(), |r, c| {
            kd[(interior[r], interior[c])]
        });
        let rhs = Mat::<f64>::from_fn(interior.len(), 1, |r, _| {
            -boundary
                .iter()
                .zip(&u_b)
                .map(|(&bd, u)| kd[(interior[r], bd)] * u)
                .sum::<f64>()
        });
        let u_i = k_ii.partial_piv_lu().solve(&rhs);
        let reduced: Vec<f64> = (0..20)
            .map(|i| (0..3).map(|c| b.vectors[(i, 3 + c)] * u_b[c]).sum())
            .collect();
        for (r, &i) in interior.iter().enumerate() {
            assert!(
                (reduced[i] - u_i[(r, 0)]).abs() < 1e-12 * u_i.norm_max(),
                "dof {i}: {} vs {}",
                reduced[i],
                u_i[(r, 0)]
            );
        }
        for (c, &bd) in boundary.iter().enumerate() {
            assert!((reduced[bd] - u_b[c]).abs() < 1e-15, "boundary {bd}");
        }
        for j in 0..3 {
            let phi = b.vectors.col_as_slice(j);
            assert!(boundary.iter().all(|&bd| phi[bd] == 0.0));
            let lambda = (2.0 * std::f64::consts::PI * b.frequencies_hz[j]).powi(2);
            let (kp, mp) = (apply(&k, phi), apply(&m, phi));
            for &i in &interior {
                assert!(
                    (kp[i] - lambda * mp[i]).abs()
                        < 1e-9 * kp.iter().map(|x| x.abs()).fold(0.0, f64::max),
                    "mode {j}, dof {i}"
                );
            }
        }
    }

    /// Grounded chain loaded only at boundary DOFs: the full static solution has an unloaded
    /// interior, so it lies in the span of the constraint modes and the Galerkin solution on
    /// the Craig–Bampton basis reproduces it to round-off (bound 1e-10 relative: condition of
    /// the chain ~1.6e3 times that of the reduced system).
    #[test]
    fn craig_bampton_basis_reproduces_static_response_to_boundary_loads() {
        let (k, m) = chain(20, true);
        let boundary = vec![5, 19];
        let b = basis_with(
            &k,
            &m,
            StaticModes::Constr,
            RigidModes::Keep,
            boundary.clone(),
        )
        .unwrap();
        let mut f = Mat::<f64>::zeros(20, 1);
        f[(5, 0)] = 2.0;
        f[(19, 0)] = -0.7;
        let kd = dense(&k);
        let full = kd.partial_piv_lu().solve(&f);
        let psi = &b.vectors;
        let reduced = psi
            * (psi.transpose() * &kd * psi)
                .partial_piv_lu()
                .solve(&(psi.transpose() * &f));
        assert!(
            (&reduced - &full).norm_max() < 1e-10 * full.norm_max(),
            "{:?} vs {:?}",
            reduced,
            full
        );
    }

    #[test]
    fn constr_needs_a_boundary_and_keeps_rigid_modes() {
        let (k, m) = chain(6, false);
        assert!(matches!(
            basis_with(&k, &m, StaticModes::Constr, RigidModes::Keep, vec![]),
            Err(LocalBasisError::ConstrWithoutBoundary)
        ));
        assert!(matches!(
            basis_with(&k, &m, StaticModes::Constr, RigidModes::Remove, vec![0]),
            Err(LocalBasisError::ConstrRemovesRigid)
        ));
    }

    /// Two disconnected free chains with the boundary on the first only: the second floats
    /// when the boundary is held, and K_ii is singular — a clear error, not a panic.
    #[test]
    fn constr_with_a_floating_interior_is_an_error() {
        let (k1, m1) = chain(4, false);
        let block = |a: &CscMatrix<f64>| {
            let mut coo = CooMatrix::new(8, 8);
            for (i, j, v) in a.triplet_iter() {
                coo.push(i, j, *v);
                coo.push(i + 4, j + 4, *v);
            }
            CscMatrix::from(&coo)
        };
        let (k, m) = (block(&k1), block(&m1));
        assert!(
            matches!(
                basis_with(&k, &m, StaticModes::Constr, RigidModes::Keep, vec![0]),
                Err(LocalBasisError::ConstrSingular(_))
            ),
            "{:?}",
            basis_with(&k, &m, StaticModes::Constr, RigidModes::Keep, vec![0])
                .map(|b| b.frequencies_hz)
        );
    }

    fn apply(a: &CscMatrix<f64>, x: &[f64]) -> Vec<f64> {
        let mut y = vec![0.0; x.len()];
        sym_matvec(a, x, &mut y).unwrap();
        y
    }

    /// Grounded chain: attachment modes solve K ψ = e_b to round-off (bound 1e-12 relative to
    /// the load; the chain's condition number is ~4n² = 1.6e3).
    #[test]
    fn supported_attachment_modes_solve_k() {
        let (k, m) = chain(20, true);
        let b = basis(&k, &m, RigidModes::Keep, vec![19, 7]);
        assert_eq!((b.rigid.ncols(), b.n_static, b.vectors.ncols()), (0, 2, 5));
        for (c, &dof) in [19usize, 7].iter().enumerate() {
            let r = apply(&k, b.vectors.col_as_slice(3 + c));
            for (i, v) in r.iter().enumerate() {
                let want = if i == dof { 1.0 } else { 0.0 };
                assert!((v - want).abs() < 1e-12, "dof {dof}, row {i}: {v}");
            }
        }
    }

    /// Free chain: one rigid mode, removed on request; the static mode satisfies the
    /// inertia-relief equations K ψ = e_b − M φ_r φ_rᵀ e_b and φ_rᵀ M ψ = 0 (bounds as above).
    #[test]
    fn free_attachment_modes_are_inertia_relief() {
        let (k, m) = chain(20, false);
        let b = basis(&k, &m, RigidModes::Remove, vec![19]);
        assert_eq!((b.rigid.ncols(), b.n_static, b.vectors.ncols()), (1, 1, 4));
        assert!(
            b.frequencies_hz.iter().all(|&f| f > 1e-3),
            "{:?}",
            b.frequencies_hz
        );
        let psi = b.vectors.col_as_slice(3);
        let phi_r = 1.0 / (20f64).sqrt(); // M-normalized rigid mode of unit masses
        let r = apply(&k, psi);
        for (i, v) in r.iter().enumerate() {
            let want = if i == 19 { 1.0 } else { 0.0 } - phi_r * phi_r;
            assert!((v - want).abs() < 1e-11, "row {i}: {v} vs {want}");
        }
        // relative to ‖Mψ‖·‖φ_r‖ (ψ grows like n² on a free chain); the projection uses the
        // Lanczos rigid mode, accurate to the solver's Ritz tolerance 1e-10, not the exact one
        let m_psi = apply(&m, psi);
        let mass_weighted: f64 = m_psi.iter().map(|x| x * phi_r).sum();
        let scale = m_psi.iter().map(|x| x * x).sum::<f64>().sqrt();
        assert!(
            mass_weighted.abs() < 1e-10 * scale,
            "{mass_weighted} vs scale {scale}"
        );
    }

    /// The inertia-relief iteration's stop: a contraction by 0.01 per step stops where the
    /// fixed tolerance stopped it (the first change ≤ 1e-13); a change that reaches a
    /// round-off floor above 1e-13 (3e-12, then no longer decreasing) stops at the first change
    /// that does not decrease, where `change ≤ 1e-13` alone would run into the iteration
    /// limit; a change that stops decreasing far from round-off (1e-6) does not stop.
    #[test]
    fn relief_iteration_stops_at_its_round_off_floor() {
        let first_stop = |changes: &[f64]| {
            (0..changes.len()).find(|&i| {
                relief_converged(
                    changes[i],
                    if i == 0 {
                        f64::INFINITY
                    } else {
                        changes[i - 1]
                    },
                )
            })
        };
        let contracting: Vec<f64> = (1..=8).map(|k| 0.01f64.powi(k)).collect();
        assert_eq!(first_stop(&contracting), Some(6));
        let floor = [1e-2, 1e-4, 1e-6, 1e-8, 1e-10, 3e-12, 5e-12, 4e-12, 6e-12];
        assert_eq!(first_stop(&floor), Some(6));
        assert!(floor.iter().all(|&c| c > RELIEF_TOL));
        let stalled = [1e-2, 1e-4, 1e-6, 2e-6, 1e-6, 3e-6];
        assert_eq!(first_stop(&stalled), None);
    }

    #[test]
    fn boundary_outside_the_f_set_is_an_error() {
        let (k, m) = chain(5, true);
        assert!(matches!(
            basis_with(&k, &m, StaticModes::Attach, RigidModes::Keep, vec![5]),
            Err(LocalBasisError::BoundaryOutOfRange { index: 5, size: 5 })
        ));
    }
}
