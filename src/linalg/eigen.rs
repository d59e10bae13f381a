//! Lowest modes of K φ = λ M φ by shift-invert Lanczos with a Sturm-sequence check.
//!
//! # Algorithm
//! With a shift σ, the operator OP = (K − σM)⁻¹ M is self-adjoint in the M-inner product
//! ⟨x, y⟩ = xᵀ M y, and OP φ = θ φ with θ = 1 / (λ − σ): the eigenvalues just above σ become the
//! largest θ, which a Krylov method finds first (Ericsson & Ruhe 1980; Grimes, Lewis & Simon,
//! "A shifted block Lanczos algorithm for solving sparse symmetric generalized eigenproblems",
//! SIAM J. Matrix Anal. Appl. 15, 1994 — the scheme of MSC/NX Nastran's Lanczos; here with
//! block size 1). K − σM is factored once by LDLᵀ with the shared [`SymbolicFactor`]; every
//! Lanczos step is one M product and one pair of triangular solves.
//!
//! - **Lanczos with full reorthogonalization** in the M-inner product (classical Gram–Schmidt
//!   repeated while the norm drops by more than 1/0.7, the DGKS criterion), so the projected
//!   matrix H = Vᵀ M OP V is formed explicitly and symmetric. On breakdown (an invariant
//!   subspace) a fresh random vector, mapped through OP, continues the basis. The M products
//!   are column gathers over the symmetric M (parallel, independent of the thread count), and
//!   M vⱼ₊₁ = (M w)/β comes from the orthogonalization's last product.
//! - **Thick restart** (Wu & Simon 2000, the symmetric Krylov–Schur of Stewart 2001): after m
//!   steps the wanted Ritz vectors Y = V S are kept, H becomes diag(θ) bordered by the
//!   residual couplings β sₘ, and the iteration continues from the residual vector. The basis
//!   grows when the wanted set does not fit. A Ritz pair is converged when its residual
//!   |β sₘᵢ| ≤ tol·θᵢ.
//! - **Purification and normalization**: each returned vector is φ = OP(Vs)/θ, applied
//!   explicitly with one block solve for all returned modes (in exact arithmetic
//!   Vs + (β sₘ/θ) vₘ₊₁; explicitly it also removes the round-off that the Lanczos vectors
//!   accumulate in the null space of a singular M), M-normalized (φᵀMφ = 1) with its largest
//!   component positive; λ is its Rayleigh quotient φᵀKφ. The modes are returned by ascending λ
//!   (rigid-body λ are round-off and need not follow the Ritz order).
//! - **Sturm check** (Parlett, *The Symmetric Eigenvalue Problem*, §3.3; Sylvester's law of
//!   inertia): the number of negative pivots of the LDLᵀ of K − sM equals the number of
//!   eigenvalues below s. With s just above the highest mode returned (or s = V2 for a range
//!   request; when only rigid-body modes are returned, K − sM is numerically singular just above
//!   λ ≈ 0 and s = λ_top + |σ| (or V2 + |σ|) instead), neg(s) − neg(σ) must equal the number of converged
//!   eigenvalues in [σ, s). A
//!   deficit means modes were skipped — single-vector Lanczos cannot see a second copy of a
//!   repeated eigenvalue in exact arithmetic — and the run is extended: converged vectors are
//!   locked, a random vector orthogonal to them restarts the Krylov space, and iteration goes on
//!   until the count is met (at most `max_recoveries` times; the final [`SturmCheck`] is
//!   returned either way). The modes are purified before the count and the factor of K − σM
//!   is released, so that the count's factorization takes its memory (one factor alive at a
//!   time); an extended run factors K − σM again at the same σ.
//!
//! # EIGRL semantics ([`EigenRequest`], frequencies in Hz, λ = (2πf)²)
//! - V1, V2 and ND: the lowest ND modes in [V1, V2] (fewer if the range holds fewer);
//! - V1, V2: all modes in [V1, V2] (their number is known beforehand from two Sturm counts);
//! - ND (and V1): the lowest ND modes above V1.
//!
//! A blank or non-positive V1 means "from the bottom of the spectrum", including rigid-body
//! modes. The shift is then σ = −(2π·`shift_hz`)² (the role of Nastran's SHFSCL: about the
//! first flexible frequency); without `shift_hz`, σ = 0 is used if K is safely positive definite
//! (no zero or negative pivot, pivot ratio ≤ 10⁷) and σ = −(2π·1 Hz)² otherwise (free-free
//! structures; give `shift_hz` when the model's units make 1 Hz a poor scale). With V1 > 0 the
//! shift is σ = (2πV1)², moved slightly down if K − σM is singular there.
//!
//! # Singular M (massless DOFs)
//! M may be positive semi-definite: grids with springs and no mass, rotations without rotary
//! inertia. The pencil then has only rank(M) finite eigenvalues; the others are infinite and are
//! the θ = 0 eigenvalues of OP (OP x = 0 for x in null(M)), which a Krylov space built from
//! OP-images never contains: its dimension is at most rank(M) (range(OP) = (K − σM)⁻¹ range(M)).
//! Two bounds keep the search on the finite part:
//! - **massless DOFs** ([`massless_dofs`]): a zero diagonal of the semi-definite M means a zero
//!   row, so rank(M) ≤ n − #massless. The Krylov size and the number of modes sought are capped
//!   by it (exact when M is non-singular on the DOFs that have mass, e.g. lumped masses);
//! - **exhaustion**: when the basis spans an invariant subspace and no random vector mapped
//!   through OP adds an M-norm above 10⁻⁸ of its own (the M-range is spanned), the search stops
//!   there: the Ritz values are then exact and are all the finite eigenvalues above σ (this
//!   covers a rank-deficient M on DOFs that do have mass, e.g. an offset CONM2 without inertia).
//!
//! When ND asks for more modes than the finite ones above the lower end, all finite modes are
//! returned and [`EigenResult::finite_exhausted`] is set (the caller warns). The Sturm counts
//! count finite eigenvalues only (K − sM at finite s), so the check stays exact; purification
//! keeps the vectors M-consistent.

use super::random::SplitMix64;
use faer::linalg::matmul::matmul;
use faer::reborrow::{Reborrow, ReborrowMut};
use faer::{Accum, Mat, MatMut, MatRef, Par};
use nalgebra_sparse::CscMatrix;

use super::cholesky::DEFAULT_MAX_RATIO;
use super::sparse::{norm_1, sym_matvec_gather};
use super::{Factor, Inertia, LinalgError, Progress, SolveScratch, SymbolicFactor};

const TWO_PI: f64 = 2.0 * std::f64::consts::PI;

/// Which modes to compute, with the field meanings of Nastran's EIGRL card (see module doc).
#[derive(Copy, Clone, Debug, Default, PartialEq)]
pub struct EigenRequest {
    /// Lower frequency bound V1 in Hz; `None` or ≤ 0: from the bottom of the spectrum.
    pub v1_hz: Option<f64>,
    /// Upper frequency bound V2 in Hz.
    pub v2_hz: Option<f64>,
    /// Number of modes ND.
    pub nd: Option<usize>,
    /// Magnitude (Hz) of the negative shift used when searching from the bottom (SHFSCL).
    pub shift_hz: Option<f64>,
}

/// Tuning of the Lanczos iteration.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct LanczosOptions {
    /// Ritz pair accepted when its OP residual |β sₘᵢ| ≤ `tol`·θᵢ.
    pub tol: f64,
    /// Maximum number of thick restarts.
    pub max_restarts: usize,
    /// Maximum number of Sturm-triggered extensions of the run.
    pub max_recoveries: usize,
    /// Seed of the random start vectors (results are reproducible for a given seed).
    pub seed: u64,
}

impl Default for LanczosOptions {
    fn default() -> Self {
        Self {
            tol: 1e-10,
            max_restarts: 200,
            max_recoveries: 4,
            seed: 0x5eed_1a2c,
        }
    }
}

/// The pencil (K, M): full-pattern CSC matrices with identical patterns, and the symbolic
/// analysis of that pattern.
#[derive(Copy, Clone, Debug)]
pub struct EigenProblem<'a> {
    pub k: &'a CscMatrix<f64>,
    pub m: &'a CscMatrix<f64>,
    pub symbolic: &'a SymbolicFactor,
}

/// Result of the Sturm-sequence check at `shift`: consistent when
/// `negative_pivots == below_lower + found`.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct SturmCheck {
    /// Shift s of the check, just above the highest mode (or V2).
    pub shift: f64,
    /// Negative pivots of LDLᵀ(K − sM) = number of eigenvalues below s.
    pub negative_pivots: usize,
    /// Eigenvalues below the lower end of the search (negative pivots at the Lanczos shift).
    pub below_lower: usize,
    /// Eigenvalues found between the lower end and s.
    pub found: usize,
}

impl SturmCheck {
    /// Number of eigenvalues below `shift` that the search did not find.
    pub fn missing(&self) -> usize {
        self.negative_pivots
            .saturating_sub(self.below_lower + self.found)
    }

    /// True when the count of found modes matches the inertia.
    pub fn is_consistent(&self) -> bool {
        self.negative_pivots == self.below_lower + self.found
    }
}

/// Modes in ascending order of λ.
#[derive(Clone, Debug)]
pub struct EigenResult {
    /// λ = φᵀKφ (raw, may be slightly negative for rigid-body modes).
    pub eigenvalues: Vec<f64>,
    /// f = √max(λ, 0) / 2π.
    pub frequencies_hz: Vec<f64>,
    /// n × m, M-normalized columns (φᵀMφ = 1), largest component positive.
    pub vectors: Mat<f64>,
    /// ‖Kφ − λMφ‖₂ / ‖Kφ‖₂, or / (‖K‖₁‖φ‖₂) for rigid-body-like modes where
    /// ‖Kφ‖₂ < 10⁻⁶‖K‖₁‖φ‖₂ (there ‖Kφ‖ is itself round-off).
    pub residuals: Vec<f64>,
    /// Modes whose negative round-off λ was clamped to 0 Hz.
    pub clamped: Vec<usize>,
    /// Lanczos shift σ.
    pub shift: f64,
    /// Missed-mode check.
    pub sturm: SturmCheck,
    /// Thick restarts performed.
    pub restarts: usize,
    /// Runs extended after a Sturm deficit.
    pub recoveries: usize,
    /// Lanczos steps: applications of OP, one solve with the factor of K − σM each (the
    /// purification's block solve not counted).
    pub solves: usize,
    /// Massless DOFs ([`massless_dofs`]): the pencil has at most n − `massless` finite
    /// eigenvalues.
    pub massless: usize,
    /// The request asked for more modes than the pencil has finite eigenvalues above its lower
    /// end (ND too large for a singular M): every finite one was returned.
    pub finite_exhausted: bool,
}

/// A diagonal entry of the positive semi-definite M at or below this fraction of the largest
/// entry of its own row counts as massless (zero up to the round-off of that row's sums).
pub const MASSLESS_RATIO: f64 = 1e-13;

/// Indices of the massless DOFs of M: diagonal ≤ [`MASSLESS_RATIO`] × the largest |entry| of
/// the same row (a zero row included). For a positive semi-definite M a zero diagonal entry
/// means a zero row and column, so rank(M) ≤ n − (their number). The scale is the row's own,
/// not the matrix's: a 1e12 kg CONM2 (the large-mass method) made every plate DOF of ~1e-2 kg
/// count as massless when the test compared with the largest diagonal of M.
pub fn massless_dofs(m: &CscMatrix<f64>) -> Vec<usize> {
    // M is symmetric: column j holds row j
    m.col_iter()
        .enumerate()
        .filter(|(j, col)| {
            let (mut diagonal, mut largest) = (0.0_f64, 0.0_f64);
            for (&i, &v) in col.row_indices().iter().zip(col.values()) {
                largest = largest.max(v.abs());
                if i == *j {
                    diagonal = v;
                }
            }
            diagonal <= MASSLESS_RATIO * largest
        })
        .map(|(j, _)| j)
        .collect()
}

/// Inertia of K − sM: `negative` is the number of eigenvalues below s (Sturm count).
pub fn sturm_count(problem: &EigenProblem, shift: f64, par: Par) -> Result<Inertia, LinalgError> {
    let values = shifted_values(problem, shift);
    Ok(problem.symbolic.factor_ldlt_values(&values, par)?.inertia())
}

/// Sturm check of a set of computed eigenvalues: `below_lower` eigenvalues are known to lie
/// below the searched interval, `eigenvalues` are those found in it; the check counts those
/// below `shift` and compares with the inertia of K − shift·M.
pub fn sturm_check(
    problem: &EigenProblem,
    shift: f64,
    below_lower: usize,
    eigenvalues: &[f64],
    par: Par,
) -> Result<SturmCheck, LinalgError> {
    validate(problem)?;
    let negative_pivots = sturm_count(problem, shift, par)?.negative;
    let found = eigenvalues.iter().filter(|&&l| l < shift).count();
    Ok(SturmCheck {
        shift,
        negative_pivots,
        below_lower,
        found,
    })
}

/// Computes the modes requested by `request` (EIGRL semantics, see module doc).
pub fn solve_modes(
    problem: &EigenProblem,
    request: &EigenRequest,
    options: &LanczosOptions,
    par: Par,
    progress: &dyn Progress,
) -> Result<EigenResult, LinalgError> {
    solve_modes_from(problem, request, options, par, progress, None)
}

/// [`solve_modes`] with an optional start vector (random when `None`).
fn solve_modes_from(
    problem: &EigenProblem,
    request: &EigenRequest,
    options: &LanczosOptions,
    par: Par,
    progress: &dyn Progress,
    start: Option<&[f64]>,
) -> Result<EigenResult, LinalgError> {
    validate(problem)?;
    let n = problem.k.nrows();
    if start.is_some_and(|x| x.len() != n) {
        return Err(LinalgError::DimensionMismatch {
            expected: n,
            got: start.map_or(0, <[f64]>::len),
        });
    }
    let mut bounds = Bounds::from_request(request)?;
    progress.step("eigen: factor K - sigma M", 0, 1);
    let (sigma, op_factor) = choose_shift(problem, &bounds, request.shift_hz, par)?;
    let below_sigma = op_factor.inertia().negative;
    if bounds.lower.is_none() && below_sigma > 0 {
        return Err(LinalgError::NegativeEigenvalues {
            count: below_sigma,
            shift: sigma,
        });
    }
    let upper = match bounds.upper {
        Some(u) => Some(count_above(problem, u, sigma, par)?),
        None => None,
    };
    // A V2 on an eigenvalue was moved up: the returned modes follow the counted interval.
    bounds.upper = upper.map(|(shift, _)| shift);
    progress.step("eigen: factor K - sigma M", 1, 1);
    let massless = massless_dofs(problem.m).len();
    let rank_bound = n - massless;
    let mut target = Target {
        lower: bounds.lower,
        nd: request.nd,
        cap: upper.map(|(_, inertia)| inertia.negative.saturating_sub(below_sigma)),
        available: rank_bound.saturating_sub(below_sigma),
    };
    if rank_bound == 0 {
        return Err(LinalgError::InvalidRequest {
            what: "the mass matrix is zero, so there is no finite eigenvalue (give the materials a density or add masses)",
        });
    }
    let mut lanczos = Lanczos::new(problem, op_factor, sigma, rank_bound, options, par, start)?;
    let mut recoveries = 0;
    loop {
        let ritz = lanczos.run(&target, options, progress)?;
        if lanczos.exhausted {
            // An invariant subspace holding the whole M-range: its Ritz values are all the
            // finite eigenvalues above σ.
            target.available = target.available.min(ritz.lambdas.len());
        }
        let want = target.wanted(&ritz.lambdas).min(ritz.lambdas.len());
        let (top, modes) = match (upper, target.cap) {
            (Some((shift, inertia)), Some(cap)) if want == cap => ((shift, inertia), None),
            _ => {
                let lambda_top = if want == 0 {
                    sigma
                } else {
                    ritz.lambdas[want - 1].max(sigma)
                };
                let margin = 1e-6 * lambda_top.abs().max(sigma.abs()).max(f64::MIN_POSITIVE);
                // The modes are purified first and the operator's factor released, so that
                // the Sturm count's factorization of K − sM takes its place in memory: one
                // factor alive at a time (it is recomputed only if the run must go on).
                let modes = purified(&mut lanczos, &ritz, want, &bounds, progress)?;
                lanczos.release_factor();
                progress.step("eigen: Sturm check", 0, 1);
                (
                    count_above(problem, lambda_top + margin, sigma, par)?,
                    Some(modes),
                )
            }
        };
        let sturm = SturmCheck {
            shift: top.0,
            negative_pivots: top.1.negative,
            below_lower: below_sigma,
            found: ritz.converged_below(top.0),
        };
        progress.step("eigen: Sturm check", 1, 1);
        if sturm.is_consistent() || recoveries == options.max_recoveries {
            let finite_exhausted = target.demand(&ritz.lambdas) > want;
            let mut result = match modes {
                Some(modes) => modes,
                None => purified(&mut lanczos, &ritz, want, &bounds, progress)?,
            };
            result.sturm = sturm;
            result.recoveries = recoveries;
            result.massless = massless;
            result.finite_exhausted = finite_exhausted;
            return Ok(result);
        }
        recoveries += 1;
        lanczos.recover(&ritz, top.0, sturm.negative_pivots - below_sigma)?;
    }
}

/// [`Lanczos::modes`] of the wanted Ritz pairs, reported as a phase of its own.
fn purified(
    lanczos: &mut Lanczos,
    ritz: &Ritz,
    want: usize,
    bounds: &Bounds,
    progress: &dyn Progress,
) -> Result<EigenResult, LinalgError> {
    progress.step("eigen: purify and normalize the modes", 0, 1);
    let modes = lanczos.modes(ritz, want, bounds)?;
    progress.step("eigen: purify and normalize the modes", 1, 1);
    Ok(modes)
}

/// λ bounds of the request; `lower`/`upper` are (2πV1)², (2πV2)².
struct Bounds {
    lower: Option<f64>,
    upper: Option<f64>,
}

impl Bounds {
    fn from_request(request: &EigenRequest) -> Result<Self, LinalgError> {
        let finite = |f: Option<f64>| f.is_none_or(f64::is_finite);
        if !finite(request.v1_hz) || !finite(request.v2_hz) || !finite(request.shift_hz) {
            return Err(LinalgError::InvalidRequest {
                what: "V1, V2 and the shift must be finite",
            });
        }
        if request.shift_hz.is_some_and(|f| f <= 0.0) {
            return Err(LinalgError::InvalidRequest {
                what: "shift frequency must be positive",
            });
        }
        if request.nd == Some(0) {
            return Err(LinalgError::InvalidRequest {
                what: "ND must be positive",
            });
        }
        if request.nd.is_none() && request.v2_hz.is_none() {
            return Err(LinalgError::InvalidRequest {
                what: "give ND or V2",
            });
        }
        let lower = request
            .v1_hz
            .filter(|&f| f > 0.0)
            .map(|f| (TWO_PI * f).powi(2));
        let upper = match request.v2_hz {
            Some(f) if f <= request.v1_hz.unwrap_or(0.0).max(0.0) => {
                return Err(LinalgError::InvalidRequest {
                    what: "V2 must exceed V1 and 0",
                });
            }
            Some(f) => Some((TWO_PI * f).powi(2)),
            None => None,
        };
        Ok(Self { lower, upper })
    }
}

/// How many of the Ritz values (ascending λ above σ) are wanted.
struct Target {
    lower: Option<f64>,
    nd: Option<usize>,
    /// Eigenvalues in [σ, V2) from the Sturm counts, if V2 was given.
    cap: Option<usize>,
    /// Finite eigenvalues above σ (an upper bound until the Krylov space is exhausted).
    available: usize,
}

impl Target {
    /// Length of the wanted prefix of `lambdas` (ascending): the ones between σ and V1
    /// (locked, not returned) plus ND, capped by the count in [σ, V2) and by the finite
    /// eigenvalues available.
    fn wanted(&self, lambdas: &[f64]) -> usize {
        self.demand(lambdas).min(self.available)
    }

    /// [`Self::wanted`] without the cap by the available finite eigenvalues.
    fn demand(&self, lambdas: &[f64]) -> usize {
        match self.nd {
            Some(nd) => {
                let below_v1 = self
                    .lower
                    .map_or(0, |l| lambdas.iter().take_while(|&&x| x < l).count());
                let want = below_v1 + nd;
                self.cap.map_or(want, |cap| want.min(cap))
            }
            None => self.cap.unwrap_or(0),
        }
    }
}

fn validate(problem: &EigenProblem) -> Result<(), LinalgError> {
    let (k, m) = (problem.k, problem.m);
    if k.nrows() != k.ncols() {
        return Err(LinalgError::NotSquare {
            nrows: k.nrows(),
            ncols: k.ncols(),
        });
    }
    problem.symbolic.values_of(k)?;
    problem.symbolic.values_of(m)?;
    Ok(())
}

/// Values of K − sM on the shared pattern.
fn shifted_values(problem: &EigenProblem, shift: f64) -> Vec<f64> {
    problem
        .k
        .values()
        .iter()
        .zip(problem.m.values())
        .map(|(k, m)| k - shift * m)
        .collect()
}

/// LDLᵀ of K − sM at `shift`, moved by growing relative steps in `direction` (±1) while the
/// factorization is singular or has numerically zero pivots (the shift sits on an eigenvalue).
fn factor_near(
    problem: &EigenProblem,
    shift: f64,
    direction: f64,
    par: Par,
) -> Result<(f64, Factor), LinalgError> {
    let scale = shift.abs().max(f64::MIN_POSITIVE);
    let mut last = None;
    for attempt in 0..5 {
        let s = if attempt == 0 {
            shift
        } else {
            shift + direction * scale * 1e-4 * 4f64.powi(attempt - 1)
        };
        match problem
            .symbolic
            .factor_ldlt_values(&shifted_values(problem, s), par)
        {
            Ok(f) if f.inertia().zero == 0 => return Ok((s, f)),
            Ok(f) => {
                last = Some(LinalgError::Singular {
                    index: f.max_pivot_ratio().index,
                })
            }
            Err(e @ LinalgError::Singular { .. }) => last = Some(e),
            Err(e) => return Err(e),
        }
    }
    Err(last.unwrap_or(LinalgError::Singular { index: 0 }))
}

fn inertia_near(
    problem: &EigenProblem,
    shift: f64,
    direction: f64,
    par: Par,
) -> Result<(f64, Inertia), LinalgError> {
    factor_near(problem, shift, direction, par).map(|(s, f)| (s, f.inertia()))
}

/// The inertia of K − sM for a Sturm count at `shift` (moved up off an eigenvalue by
/// [`inertia_near`]). Among rigid-body modes (λ ≈ 0, free–free with σ < 0) K − sM is
/// numerically singular near `shift`: the count is then taken at `shift` + |σ|, the mirror
/// image of the shift whose factorization already succeeded (modes in between are counted and
/// must have been found, as any below the shift).
fn count_above(
    problem: &EigenProblem,
    shift: f64,
    sigma: f64,
    par: Par,
) -> Result<(f64, Inertia), LinalgError> {
    inertia_near(problem, shift, 1.0, par).or_else(|e| match e {
        LinalgError::Singular { .. } if sigma < 0.0 => {
            inertia_near(problem, shift - sigma, 1.0, par)
        }
        e => Err(e),
    })
}

/// Chooses σ (module doc) and returns it with the LDLᵀ of K − σM.
fn choose_shift(
    problem: &EigenProblem,
    bounds: &Bounds,
    shift_hz: Option<f64>,
    par: Par,
) -> Result<(f64, Factor), LinalgError> {
    if let Some(lower) = bounds.lower {
        return factor_near(problem, lower, -1.0, par);
    }
    if let Some(f) = shift_hz {
        return factor_near(problem, -(TWO_PI * f).powi(2), -1.0, par);
    }
    if let Ok(f) = problem.symbolic.factor_ldlt_values(problem.k.values(), par) {
        let inertia = f.inertia();
        if inertia.negative == 0
            && inertia.zero == 0
            && f.max_pivot_ratio().ratio <= DEFAULT_MAX_RATIO
        {
            return Ok((0.0, f));
        }
    }
    factor_near(problem, -TWO_PI * TWO_PI, -1.0, par)
}

/// The factor of K − σM in `slot`, computed (again, after [`Lanczos::release_factor`]) when
/// the slot is empty.
fn factor_at<'f>(
    slot: &'f mut Option<Factor>,
    problem: &EigenProblem,
    sigma: f64,
    par: Par,
) -> Result<&'f Factor, LinalgError> {
    match slot {
        Some(factor) => Ok(factor),
        None => {
            let values = shifted_values(problem, sigma);
            Ok(slot.insert(problem.symbolic.factor_ldlt_values(&values, par)?))
        }
    }
}

/// The Sturm check of a result not yet checked ([`Lanczos::modes`]; the caller sets it).
const UNCHECKED: SturmCheck = SturmCheck {
    shift: f64::NAN,
    negative_pivots: 0,
    below_lower: 0,
    found: 0,
};

/// Rayleigh–Ritz data of one Lanczos cycle, positive θ only, sorted by descending θ
/// (= ascending λ).
struct Ritz {
    /// Column of S (eigenvectors of H) for each entry.
    columns: Vec<usize>,
    theta: Vec<f64>,
    lambdas: Vec<f64>,
    converged: Vec<bool>,
    /// Eigenvectors of H (m × m), H's size m and the residual norm βₘ.
    s: Mat<f64>,
    m: usize,
    beta: f64,
}

impl Ritz {
    fn converged_below(&self, shift: f64) -> usize {
        self.lambdas
            .iter()
            .zip(&self.converged)
            .filter(|&(&l, &c)| c && l < shift)
            .count()
    }
}

/// State of the thick-restart Lanczos iteration (module doc).
struct Lanczos<'a> {
    problem: &'a EigenProblem<'a>,
    /// LDLᵀ of K − σM; `None` while released for the Sturm count ([`Self::release_factor`]).
    factor: Option<Factor>,
    scratch: SolveScratch,
    sigma: f64,
    par: Par,
    n: usize,
    /// Upper bound of the Krylov dimension: n − massless DOFs ≥ rank(M) = dim range(OP).
    limit: usize,
    /// The basis spans an invariant subspace and OP adds no new M-direction: every finite
    /// eigenvalue above σ is among the Ritz values.
    exhausted: bool,
    /// Basis V (n × (m+1), M-orthonormal columns) and projected matrix H ((m+1) × (m+1)).
    v: Mat<f64>,
    h: Mat<f64>,
    /// Kept (restart) vectors at the start of the next cycle, and Krylov size m.
    k: usize,
    m: usize,
    /// Convergence also requires this many converged values below the shift (after a
    /// Sturm deficit).
    floor: Option<(f64, usize)>,
    restarts: usize,
    /// Applications of OP so far.
    solves: usize,
    rng: SplitMix64,
    /// 1 / diag(M) (0 on massless DOFs): random start vectors are scaled by it so that M x is
    /// a balanced random load ([`Self::start`]).
    start_scale: Vec<f64>,
    /// Per-step buffers (no allocation inside a cycle).
    w: Vec<f64>,
    p: Vec<f64>,
    /// The column j of V such that `p` holds M vⱼ (set when vⱼ is made from w, whose M w is in
    /// p, so that the next step need not multiply by M again).
    p_is_mv: Option<usize>,
    c: Vec<f64>,
    c_pass: Vec<f64>,
}

impl<'a> Lanczos<'a> {
    fn new(
        problem: &'a EigenProblem<'a>,
        factor: Factor,
        sigma: f64,
        limit: usize,
        options: &LanczosOptions,
        par: Par,
        start: Option<&[f64]>,
    ) -> Result<Self, LinalgError> {
        let n = problem.k.nrows();
        let scratch = factor.solve_scratch(1)?;
        let mut this = Self {
            problem,
            factor: Some(factor),
            scratch,
            sigma,
            par,
            n,
            limit,
            exhausted: false,
            v: Mat::zeros(n, 1),
            h: Mat::zeros(1, 1),
            k: 0,
            m: 0,
            floor: None,
            restarts: 0,
            solves: 0,
            rng: SplitMix64::new(options.seed),
            start_scale: (0..n)
                .map(|i| problem.m.get_entry(i, i).map_or(0.0, |v| v.into_value()))
                .map(|d| if d > 0.0 { 1.0 / d } else { 0.0 })
                .collect(),
            w: vec![0.0; n],
            p: vec![0.0; n],
            p_is_mv: None,
            c: Vec::new(),
            c_pass: Vec::new(),
        };
        if !this.start(0, start)? {
            return Err(LinalgError::InvalidRequest {
                what: "the mass matrix has no positive part (no mass) to search",
            });
        }
        Ok(this)
    }

    /// Makes room for a Krylov size of `m` (keeps existing columns).
    fn ensure_size(&mut self, m: usize) {
        let m = m.min(self.limit);
        if m <= self.m {
            return;
        }
        self.v.resize_with(self.n, m + 1, |_, _| 0.0);
        self.h.resize_with(m + 1, m + 1, |_, _| 0.0);
        self.c.resize(m + 1, 0.0);
        self.c_pass.resize(m + 1, 0.0);
        self.m = m;
    }

    /// w ← OP x = (K − σM)⁻¹ M x, x = column `x_col` of V or w itself.
    fn apply_op(&mut self, x_col: Option<usize>) -> Result<(), LinalgError> {
        let (m, par) = (self.problem.m, self.par);
        match x_col {
            Some(j) if self.p_is_mv == Some(j) => {}
            Some(j) => sym_matvec_gather(m, self.v.col_as_slice(j), &mut self.p, par),
            None => sym_matvec_gather(m, &self.w, &mut self.p, par),
        }
        self.p_is_mv = None;
        self.w.copy_from_slice(&self.p);
        let n = self.n;
        self.solves += 1;
        let factor = factor_at(&mut self.factor, self.problem, self.sigma, par)?;
        factor.solve_in_place_with_scratch(
            MatMut::from_column_major_slice_mut(&mut self.w, n, 1),
            &mut self.scratch,
        )
    }

    /// Frees the factor of K − σM (for the Sturm count's); [`Self::apply_op`] computes it
    /// again, at the same σ, should the iteration continue.
    fn release_factor(&mut self) {
        self.factor = None;
    }

    /// ‖w‖_M, leaving M w in p.
    fn m_norm_w(&mut self) -> f64 {
        sym_matvec_gather(self.problem.m, &self.w, &mut self.p, self.par);
        self.p_is_mv = None;
        self.w
            .iter()
            .zip(&self.p)
            .map(|(a, b)| a * b)
            .sum::<f64>()
            .max(0.0)
            .sqrt()
    }

    /// M-orthogonalizes w against columns 0..ncols of V (CGS with DGKS repetition); the
    /// coefficients go to c[..ncols]. Returns (‖w‖_M before, ‖w‖_M after); p holds M w.
    fn orthogonalize(&mut self, ncols: usize) -> (f64, f64) {
        let n = self.n;
        let norm0 = self.m_norm_w();
        let mut norm = norm0;
        self.c[..ncols].fill(0.0);
        for _ in 0..3 {
            if ncols == 0 {
                break;
            }
            let basis = self.v.as_ref().subcols(0, ncols);
            let mut cp = MatMut::from_column_major_slice_mut(&mut self.c_pass[..ncols], ncols, 1);
            matmul(
                cp.rb_mut(),
                Accum::Replace,
                basis.transpose(),
                MatRef::from_column_major_slice(&self.p, n, 1),
                1.0,
                self.par,
            );
            matmul(
                MatMut::from_column_major_slice_mut(&mut self.w, n, 1),
                Accum::Add,
                basis,
                cp.rb(),
                -1.0,
                self.par,
            );
            for (c, d) in self.c[..ncols].iter_mut().zip(&self.c_pass[..ncols]) {
                *c += d;
            }
            let previous = norm;
            norm = self.m_norm_w();
            if norm > 0.7 * previous {
                break;
            }
        }
        (norm0, norm)
    }

    /// Column `j` of V ← OP(random), M-orthogonal to columns 0..j and M-normalized; false
    /// when no such vector exists (see [`Self::start`]).
    fn random_start(&mut self, j: usize) -> Result<bool, LinalgError> {
        self.start(j, None)
    }

    /// Column `j` of V ← OP(x) for the given x (first attempt) or random x, M-orthogonal to
    /// columns 0..j and M-normalized. Returns false when three attempts keep less than 10⁻⁸ of
    /// their M-norm: columns 0..j already span range(OP) (the M-range). A random x is r / diag(M)
    /// (r uniform): M x is then a load of the same size on every DOF with mass, so a few heavy
    /// DOFs (a 1e12 kg CONM2 of the large-mass method) do not fill OP x and its M-norm, which
    /// would leave nothing after orthogonalization and read as an exhausted space.
    fn start(&mut self, j: usize, x: Option<&[f64]>) -> Result<bool, LinalgError> {
        for attempt in 0..3 {
            match x {
                Some(x) if attempt == 0 => self.w.copy_from_slice(x),
                _ => {
                    for (w, scale) in self.w.iter_mut().zip(&self.start_scale) {
                        *w = self.rng.symmetric() * scale;
                    }
                }
            }
            self.apply_op(None)?;
            self.ensure_size(j + 1);
            let (norm0, norm) = self.orthogonalize(j);
            if norm > 1e-8 * norm0 {
                for (dst, &x) in self.v.col_as_slice_mut(j).iter_mut().zip(&self.w) {
                    *dst = x / norm;
                }
                return Ok(true);
            }
        }
        Ok(false)
    }

    /// Extends the basis from column k to m, filling H. Returns the size reached (m, or less
    /// if the whole space was exhausted, then with β = 0 and `exhausted` set) and βₘ.
    fn expand(&mut self) -> Result<(usize, f64), LinalgError> {
        for j in self.k..self.m {
            self.apply_op(Some(j))?;
            let (norm0, beta) = self.orthogonalize(j + 1);
            for i in 0..=j {
                self.h[(i, j)] = self.c[i];
                self.h[(j, i)] = self.c[i];
            }
            if beta <= 1e-12 * norm0 {
                self.h[(j + 1, j)] = 0.0;
                self.h[(j, j + 1)] = 0.0;
                if j + 1 == self.n || !self.random_start(j + 1)? {
                    self.exhausted = true;
                    return Ok((j + 1, 0.0));
                }
            } else {
                self.h[(j + 1, j)] = beta;
                self.h[(j, j + 1)] = beta;
                for (dst, &x) in self.v.col_as_slice_mut(j + 1).iter_mut().zip(&self.w) {
                    *dst = x / beta;
                }
                // p = M w, so M v_{j+1} = p / β for the next step
                self.p.iter_mut().for_each(|x| *x /= beta);
                self.p_is_mv = Some(j + 1);
            }
        }
        Ok((self.m, self.h[(self.m, self.m - 1)]))
    }

    fn rayleigh_ritz(&self, m: usize, beta: f64, tol: f64) -> Result<Ritz, LinalgError> {
        let hm = self.h.as_ref().submatrix(0, 0, m, m).to_owned();
        let (theta_all, s) =
            crate::linalg::dense::symmetric_eigen_vectors(hm.as_ref()).map_err(|_| {
                LinalgError::NotConverged {
                    converged: 0,
                    wanted: m,
                    restarts: self.restarts,
                }
            })?;
        let mut columns: Vec<usize> = (0..m).filter(|&i| theta_all[i] > 0.0).collect();
        columns.sort_by(|&a, &b| theta_all[b].total_cmp(&theta_all[a]));
        let theta: Vec<f64> = columns.iter().map(|&i| theta_all[i]).collect();
        let lambdas = theta.iter().map(|t| self.sigma + 1.0 / t).collect();
        let converged = columns
            .iter()
            .zip(&theta)
            .map(|(&i, &t)| (beta * s[(m - 1, i)]).abs() <= tol * t)
            .collect();
        Ok(Ritz {
            columns,
            theta,
            lambdas,
            converged,
            s,
            m,
            beta,
        })
    }

    /// Runs cycles until the wanted prefix (and the Sturm floor, if any) is converged.
    fn run(
        &mut self,
        target: &Target,
        options: &LanczosOptions,
        progress: &dyn Progress,
    ) -> Result<Ritz, LinalgError> {
        let initial = target.nd.unwrap_or(0).max(target.cap.unwrap_or(0)).max(1);
        progress.step("eigen: Lanczos", 0, initial);
        self.ensure_size((2 * initial + 10).max(initial + 20));
        loop {
            let (m, beta) = self.expand()?;
            let ritz = self.rayleigh_ritz(m, beta, options.tol)?;
            let want = target.wanted(&ritz.lambdas);
            let done = ritz.converged.iter().take(want).filter(|&&c| c).count();
            progress.step("eigen: Lanczos", done, want);
            let floor_met = self
                .floor
                .is_none_or(|(shift, count)| ritz.converged_below(shift) >= count);
            if (done == want && ritz.lambdas.len() >= want && floor_met)
                || m == self.limit
                || self.exhausted
            {
                return Ok(ritz);
            }
            if self.restarts == options.max_restarts {
                return Err(LinalgError::NotConverged {
                    converged: done,
                    wanted: want,
                    restarts: self.restarts,
                });
            }
            let floor = self.floor.map_or(0, |(_, count)| count);
            let keep_n = (want.max(floor) + (want / 2).max(4))
                .min(ritz.columns.len())
                .min(m - 1);
            self.restart(&ritz, &(0..keep_n).collect::<Vec<_>>(), false)?;
        }
    }

    /// Thick restart: V[:, ..k] ← V S[:, keep], H ← diag(θ) bordered by βₘ sₘ (or, with
    /// `inject`, by zero and a fresh random vector).
    fn restart(&mut self, ritz: &Ritz, keep: &[usize], inject: bool) -> Result<(), LinalgError> {
        let (n, m, k) = (self.n, ritz.m, keep.len());
        let mut sk = Mat::<f64>::zeros(m, k);
        for (dst, &e) in keep.iter().enumerate() {
            for i in 0..m {
                sk[(i, dst)] = ritz.s[(i, ritz.columns[e])];
            }
        }
        let mut y = Mat::<f64>::zeros(n, k);
        matmul(
            y.as_mut(),
            Accum::Replace,
            self.v.as_ref().subcols(0, m),
            sk.as_ref(),
            1.0,
            self.par,
        );
        self.v.as_mut().subcols_mut(0, k).copy_from(y.as_ref());
        self.p_is_mv = None;
        self.h.fill(0.0);
        for (dst, &e) in keep.iter().enumerate() {
            self.h[(dst, dst)] = ritz.theta[e];
        }
        self.k = k;
        self.restarts += 1;
        // Grow the Krylov space when the kept set leaves too little room.
        let room = (k / 2).max(10);
        if k + room > self.m {
            self.ensure_size(k + room);
        }
        if inject {
            return match self.random_start(k)? {
                true => Ok(()),
                false => Err(LinalgError::InvalidRequest {
                    what: "the Sturm count exceeds the finite eigenvalues the mass matrix allows",
                }),
            };
        }
        let (residual, rest) = self.v.as_mut().split_at_col_mut(m);
        residual.col_mut(k).copy_from(rest.col(0));
        for (dst, &e) in keep.iter().enumerate() {
            let b = ritz.beta * ritz.s[(m - 1, ritz.columns[e])];
            self.h[(k, dst)] = b;
            self.h[(dst, k)] = b;
        }
        Ok(())
    }

    /// After a Sturm deficit: lock the converged vectors, continue from a fresh random vector
    /// and require `count` converged values below `shift`.
    fn recover(&mut self, ritz: &Ritz, shift: f64, count: usize) -> Result<(), LinalgError> {
        let keep: Vec<usize> = (0..ritz.columns.len())
            .filter(|&e| ritz.converged[e])
            .collect();
        self.floor = Some((shift, count));
        self.restart(ritz, &keep, true)
    }

    /// Purified, M-normalized vectors, Rayleigh quotients and residuals of the first `want`
    /// Ritz pairs, filtered to the requested interval; the caller sets the Sturm check, the
    /// recoveries and the counts of the result.
    fn modes(
        &mut self,
        ritz: &Ritz,
        want: usize,
        bounds: &Bounds,
    ) -> Result<EigenResult, LinalgError> {
        let (n, m) = (self.n, ritz.m);
        let selected: Vec<usize> = (0..want.min(ritz.lambdas.len()))
            .filter(|&e| bounds.lower.is_none_or(|l| ritz.lambdas[e] >= l))
            .filter(|&e| bounds.upper.is_none_or(|u| ritz.lambdas[e] <= u))
            .collect();
        let mut coeffs = Mat::<f64>::zeros(m, selected.len());
        for (dst, &e) in selected.iter().enumerate() {
            for i in 0..m {
                coeffs[(i, dst)] = ritz.s[(i, ritz.columns[e])];
            }
        }
        let mut ritz_vectors = Mat::<f64>::zeros(n, selected.len());
        matmul(
            ritz_vectors.as_mut(),
            Accum::Replace,
            self.v.as_ref().subcols(0, m),
            coeffs.as_ref(),
            1.0,
            self.par,
        );
        // Purification φ = OP(Vs)/θ, explicitly (one block solve): with a singular M the
        // Lanczos vectors pick up round-off in null(M) that the M-products never see and that
        // grows from step to step (each new vector is a residual divided by its small M-norm);
        // OP removes it, since M annihilates it. Exact arithmetic would give Vs + (β sₘ/θ) vₘ.
        let mut vectors = Mat::<f64>::zeros(n, selected.len());
        for (dst, &e) in selected.iter().enumerate() {
            sym_matvec_gather(
                self.problem.m,
                ritz_vectors.col_as_slice(dst),
                vectors.col_as_slice_mut(dst),
                self.par,
            );
            vectors
                .col_as_slice_mut(dst)
                .iter_mut()
                .for_each(|x| *x /= ritz.theta[e]);
        }
        drop(ritz_vectors);
        let factor = factor_at(&mut self.factor, self.problem, self.sigma, self.par)?;
        let mut block_scratch = factor.solve_scratch(selected.len())?;
        factor.solve_in_place_with_scratch(vectors.as_mut(), &mut block_scratch)?;
        let k_norm = norm_1(self.problem.k);
        let (mut kx, mut mx) = (vec![0.0; n], vec![0.0; n]);
        let mut result = EigenResult {
            eigenvalues: Vec::with_capacity(selected.len()),
            frequencies_hz: Vec::with_capacity(selected.len()),
            vectors,
            residuals: Vec::with_capacity(selected.len()),
            clamped: Vec::new(),
            shift: self.sigma,
            sturm: UNCHECKED,
            restarts: self.restarts,
            recoveries: 0,
            solves: self.solves,
            massless: 0,
            finite_exhausted: false,
        };
        for dst in 0..selected.len() {
            let phi = result.vectors.col_as_slice_mut(dst);
            sym_matvec_gather(self.problem.m, phi, &mut mx, self.par);
            let mass = dot(phi, &mx).sqrt();
            let sign = if phi
                .iter()
                .fold(0.0f64, |a, &x| if x.abs() > a.abs() { x } else { a })
                < 0.0
            {
                -1.0
            } else {
                1.0
            };
            for x in phi.iter_mut() {
                *x *= sign / mass;
            }
            sym_matvec_gather(self.problem.m, phi, &mut mx, self.par);
            sym_matvec_gather(self.problem.k, phi, &mut kx, self.par);
            let lambda = dot(phi, &kx) / dot(phi, &mx);
            let r = kx
                .iter()
                .zip(&mx)
                .map(|(k, m)| (k - lambda * m).powi(2))
                .sum::<f64>()
                .sqrt();
            let (kphi, phi_norm) = (dot(&kx, &kx).sqrt(), dot(phi, phi).sqrt());
            let denom = if kphi < 1e-6 * k_norm * phi_norm {
                k_norm * phi_norm
            } else {
                kphi
            };
            if lambda < 0.0 {
                result.clamped.push(dst);
            }
            result.eigenvalues.push(lambda);
            result.frequencies_hz.push(lambda.max(0.0).sqrt() / TWO_PI);
            result
                .residuals
                .push(if denom > 0.0 { r / denom } else { r });
        }
        result.sort_ascending();
        Ok(result)
    }
}

impl EigenResult {
    /// Modes by ascending λ (Rayleigh quotient). The Ritz order already is for separated
    /// modes, but the λ of rigid-body modes are round-off and need not follow it.
    fn sort_ascending(&mut self) {
        let mut order: Vec<usize> = (0..self.eigenvalues.len()).collect();
        order.sort_by(|&a, &b| self.eigenvalues[a].total_cmp(&self.eigenvalues[b]));
        if order.iter().enumerate().all(|(i, &o)| i == o) {
            return;
        }
        let permute = |v: &[f64]| order.iter().map(|&o| v[o]).collect::<Vec<f64>>();
        (self.eigenvalues, self.frequencies_hz, self.residuals) = (
            permute(&self.eigenvalues),
            permute(&self.frequencies_hz),
            permute(&self.residuals),
        );
        self.vectors = Mat::from_fn(self.vectors.nrows(), order.len(), |i, c| {
            self.vectors[(i, order[c])]
        });
        self.clamped = (0..order.len())
            .filter(|&i| self.eigenvalues[i] < 0.0)
            .collect();
    }
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::linalg::cholesky::tests::chain;
    use nalgebra_sparse::CooMatrix;
    use std::f64::consts::PI;

    fn quiet() -> impl Progress {
        |_: &str, _: usize, _: usize| {}
    }

    /// Lumped mass `mass`·I on the pattern of `k` (explicit zeros off the diagonal).
    fn lumped(k: &CscMatrix<f64>, mass: f64) -> CscMatrix<f64> {
        let mut m = k.clone();
        for (i, j, v) in m.triplet_iter_mut() {
            *v = if i == j { mass } else { 0.0 };
        }
        m
    }

    fn hz(lambda: f64) -> f64 {
        lambda.sqrt() / TWO_PI
    }

    fn solve(k: &CscMatrix<f64>, m: &CscMatrix<f64>, request: EigenRequest) -> EigenResult {
        let symbolic = SymbolicFactor::analyze(k.pattern()).unwrap();
        let problem = EigenProblem {
            k,
            m,
            symbolic: &symbolic,
        };
        solve_modes(
            &problem,
            &request,
            &LanczosOptions::default(),
            Par::Seq,
            &quiet(),
        )
        .unwrap()
    }

    fn assert_modes(result: &EigenResult, m: &CscMatrix<f64>, expected: &[f64], tol: f64) {
        assert_eq!(
            result.eigenvalues.len(),
            expected.len(),
            "{:?}",
            result.eigenvalues
        );
        for (j, (&got, &want)) in result.eigenvalues.iter().zip(expected).enumerate() {
            assert!(
                (got - want).abs() <= tol * want.abs().max(1e-300),
                "mode {j}: {got} vs {want}"
            );
            let phi = result.vectors.col_as_slice(j);
            let mut mphi = vec![0.0; phi.len()];
            sym_matvec_checked(m, phi, &mut mphi);
            assert!((dot(phi, &mphi) - 1.0).abs() < 1e-12);
            assert!(
                result.residuals[j] < 1e-8,
                "mode {j}: residual {}",
                result.residuals[j]
            );
        }
        assert!(result.sturm.is_consistent(), "{:?}", result.sturm);
    }

    fn sym_matvec_checked(a: &CscMatrix<f64>, x: &[f64], y: &mut [f64]) {
        crate::linalg::sym_matvec(a, x, y).unwrap();
    }

    /// Fixed–fixed chain of n masses m with unit springs (Rao, *Mechanical Vibrations*, the
    /// discrete string): λ_j = (4k/m) sin²(jπ / (2(n+1))).
    #[test]
    fn fixed_fixed_chain_matches_analytic() {
        let (n, mass) = (50, 2.5);
        let k = chain(n, true, true, None);
        let m = lumped(&k, mass);
        let exact: Vec<f64> = (1..=n)
            .map(|j| 4.0 / mass * (j as f64 * PI / (2.0 * (n + 1) as f64)).sin().powi(2))
            .collect();
        for nd in [10, 50] {
            let result = solve(
                &k,
                &m,
                EigenRequest {
                    nd: Some(nd),
                    ..Default::default()
                },
            );
            assert_eq!(result.shift, 0.0);
            assert_modes(&result, &m, &exact[..nd], 1e-10);
            let f = &result.frequencies_hz;
            assert!((f[0] - hz(exact[0])).abs() < 1e-10 * f[0]);
        }
    }

    /// A stiff, light free–free chain asked for its rigid mode only: just above λ ≈ 0,
    /// K − sM is numerically singular (pivots below 1e-12 of the diagonal), so the Sturm check
    /// counts at λ_top + |σ| (was: "matrix is singular" on a free plate with EIGRL ND = 4, fewer
    /// modes than its 6 rigid ones).
    #[test]
    fn free_free_rigid_mode_only_passes_the_sturm_check() {
        let n = 50;
        let mut k = chain(n, false, false, None);
        k.values_mut().iter_mut().for_each(|v| *v *= 1e10);
        let m = lumped(&k, 1e-3);
        let first_flexible = 1e13 * 4.0 * (PI / (2.0 * n as f64)).sin().powi(2);
        let result = solve(
            &k,
            &m,
            EigenRequest {
                nd: Some(1),
                ..Default::default()
            },
        );
        assert!(result.sturm.is_consistent(), "{:?}", result.sturm);
        assert_eq!(result.eigenvalues.len(), 1);
        assert!(
            result.eigenvalues[0].abs() < 1e-8 * first_flexible,
            "{}",
            result.eigenvalues[0]
        );
    }

    /// V1 above every finite eigenvalue (here with massless DOFs beside them): an empty but
    /// verified range, as between two modes, not a "no mass" error (the shift's Sturm count
    /// already holds every finite eigenvalue, so nothing is left to search).
    #[test]
    fn range_above_the_spectrum_has_no_modes() {
        let n = 20;
        let k = chain(n, true, false, None);
        let mut m = lumped(&k, 1.0);
        m.triplet_iter_mut()
            .filter(|(i, j, _)| *i == 0 && *j == 0)
            .for_each(|(_, _, v)| *v = 0.0); // one massless DOF: an infinite eigenvalue
        let top = 4.0_f64.sqrt() / (2.0 * PI); // λ_max < 4
        let result = solve(
            &k,
            &m,
            EigenRequest {
                v1_hz: Some(2.0 * top),
                v2_hz: Some(3.0 * top),
                ..Default::default()
            },
        );
        assert!(result.eigenvalues.is_empty(), "{:?}", result.eigenvalues);
        assert!(result.sturm.is_consistent(), "{:?}", result.sturm);
        assert_eq!(result.sturm.negative_pivots, n - 1, "{:?}", result.sturm);
    }

    /// The large-mass method: a grounded chain with 1e14 on its last DOF (the others 1). Every
    /// DOF has mass (1e-14 of the largest diagonal: massless by a matrix-wide ratio, not by
    /// the row's own), so ND = 6 finds six modes: one ~1e-16 (the heavy mass on the chain's
    /// flexibility), then the chain with that DOF held: n − 1 unit masses between two fixed
    /// ends, λ_j = 4 sin²(jπ / (2n)) (to 1e-8: the heavy DOF moves by ~λ/1e14). Before, random
    /// start vectors were all heavy-DOF (M x ≈ 1e14 x_n) and the run stopped after 1 mode.
    #[test]
    fn large_mass_method_finds_every_requested_mode() {
        let n = 40;
        let k = chain(n, true, false, None);
        let mut m = lumped(&k, 1.0);
        m.triplet_iter_mut()
            .filter(|(i, j, _)| *i == n - 1 && *j == n - 1)
            .for_each(|(_, _, v)| *v = 1e14);
        assert!(massless_dofs(&m).is_empty());
        let result = solve(
            &k,
            &m,
            EigenRequest {
                nd: Some(6),
                ..Default::default()
            },
        );
        assert_eq!(result.eigenvalues.len(), 6, "{:?}", result.eigenvalues);
        assert!(
            !result.finite_exhausted && result.sturm.is_consistent(),
            "{:?}",
            result.sturm
        );
        assert!(result.eigenvalues[0] < 1e-10, "{}", result.eigenvalues[0]);
        for (j, lambda) in result.eigenvalues[1..].iter().enumerate() {
            let held = 4.0 * ((j + 1) as f64 * PI / (2.0 * n as f64)).sin().powi(2);
            assert!(
                (lambda - held).abs() <= 1e-8 * held,
                "mode {}: {lambda} vs {held}",
                j + 2
            );
        }
    }

    /// Free–free chain: one rigid-body mode (λ = 0) found through the negative shift, then
    /// λ_j = 4 sin²(jπ / (2n)).
    #[test]
    fn free_free_chain_finds_rigid_mode() {
        let n = 50;
        let k = chain(n, false, false, None);
        let m = lumped(&k, 1.0);
        let exact: Vec<f64> = (1..5)
            .map(|j| 4.0 * (j as f64 * PI / (2.0 * n as f64)).sin().powi(2))
            .collect();
        for shift_hz in [Some(0.01), None] {
            let result = solve(
                &k,
                &m,
                EigenRequest {
                    nd: Some(5),
                    shift_hz,
                    ..Default::default()
                },
            );
            assert!(result.shift < 0.0);
            assert!(
                result.eigenvalues[0].abs() < 1e-12,
                "{}",
                result.eigenvalues[0]
            );
            assert!(
                result.residuals[0] < 1e-8,
                "rigid residual {}",
                result.residuals[0]
            );
            let rigid = result.vectors.col_as_slice(0);
            assert!(
                rigid
                    .iter()
                    .all(|&x| (x - 1.0 / (n as f64).sqrt()).abs() < 1e-8)
            );
            assert_eq!(
                result.frequencies_hz[0],
                result.eigenvalues[0].max(0.0).sqrt() / TWO_PI
            );
            assert_eq!(
                result.clamped,
                if result.eigenvalues[0] < 0.0 {
                    vec![0]
                } else {
                    vec![]
                }
            );
            let elastic = EigenResult {
                eigenvalues: result.eigenvalues[1..].to_vec(),
                ..result.clone()
            };
            for (got, want) in elastic.eigenvalues.iter().zip(&exact) {
                assert!((got - want).abs() < 1e-10 * want);
            }
            assert!(result.sturm.is_consistent());
        }
    }

    /// EIGRL: range only, ND only above V1, and ND within a range.
    #[test]
    fn eigrl_semantics() {
        let n = 50;
        let k = chain(n, true, true, None);
        let m = lumped(&k, 1.0);
        let exact: Vec<f64> = (1..=n)
            .map(|j| 4.0 * (j as f64 * PI / (2.0 * (n + 1) as f64)).sin().powi(2))
            .collect();
        let between = |a: usize| 0.5 * (hz(exact[a]) + hz(exact[a + 1]));
        // modes with 0-based index 4..=11 lie in [V1, V2]
        let (v1, v2) = (Some(between(3)), Some(between(11)));
        let cases = [
            (
                EigenRequest {
                    v1_hz: v1,
                    v2_hz: v2,
                    ..Default::default()
                },
                4..12,
            ),
            (
                EigenRequest {
                    v1_hz: v1,
                    nd: Some(4),
                    ..Default::default()
                },
                4..8,
            ),
            (
                EigenRequest {
                    v1_hz: v1,
                    v2_hz: v2,
                    nd: Some(3),
                    ..Default::default()
                },
                4..7,
            ),
            (
                EigenRequest {
                    v1_hz: v1,
                    v2_hz: v2,
                    nd: Some(20),
                    ..Default::default()
                },
                4..12,
            ),
            (
                EigenRequest {
                    v2_hz: v2,
                    ..Default::default()
                },
                0..12,
            ),
        ];
        for (request, range) in cases {
            let result = solve(&k, &m, request);
            assert_modes(&result, &m, &exact[range], 1e-10);
        }
        let symbolic = SymbolicFactor::analyze(k.pattern()).unwrap();
        let problem = EigenProblem {
            k: &k,
            m: &m,
            symbolic: &symbolic,
        };
        let bad = EigenRequest {
            v1_hz: Some(2.0),
            v2_hz: Some(1.0),
            ..Default::default()
        };
        assert!(matches!(
            solve_modes(
                &problem,
                &bad,
                &LanczosOptions::default(),
                Par::Seq,
                &quiet()
            ),
            Err(LinalgError::InvalidRequest { .. })
        ));
    }

    /// Sturm check against known inertia: dropping one of the first 10 eigenvalues is reported
    /// as one missing mode.
    #[test]
    fn sturm_check_flags_a_skipped_mode() {
        let n = 30;
        let k = chain(n, true, true, None);
        let m = lumped(&k, 1.0);
        let symbolic = SymbolicFactor::analyze(k.pattern()).unwrap();
        let problem = EigenProblem {
            k: &k,
            m: &m,
            symbolic: &symbolic,
        };
        let exact: Vec<f64> = (1..=n)
            .map(|j| 4.0 * (j as f64 * PI / (2.0 * (n + 1) as f64)).sin().powi(2))
            .collect();
        let shift = 0.5 * (exact[9] + exact[10]);
        let all = sturm_check(&problem, shift, 0, &exact[..10], Par::Seq).unwrap();
        assert!(all.is_consistent());
        assert_eq!((all.negative_pivots, all.found, all.missing()), (10, 10, 0));
        let skipped: Vec<f64> = exact[..10]
            .iter()
            .enumerate()
            .filter(|&(j, _)| j != 6)
            .map(|(_, &l)| l)
            .collect();
        let check = sturm_check(&problem, shift, 0, &skipped, Par::Seq).unwrap();
        assert!(!check.is_consistent());
        assert_eq!(check.missing(), 1);
    }

    /// Two mirror-image chains (grounded at the outer ends, no spring between them): every
    /// eigenvalue is double, λ_j = 4 sin²((2j−1)π / (2(2n+1))) for each fixed–free half of n
    /// DOFs. Single-vector Lanczos sees one copy per pair; the Sturm check must detect the
    /// deficit and the extended run must find the second copies.
    #[test]
    fn repeated_eigenvalues_are_recovered_by_sturm_check() {
        let half = 60;
        let k = chain(2 * half, true, true, Some(half));
        let m = lumped(&k, 1.0);
        let single: Vec<f64> = (1..=3)
            .map(|j| {
                4.0 * ((2 * j - 1) as f64 * PI / (2.0 * (2 * half + 1) as f64))
                    .sin()
                    .powi(2)
            })
            .collect();
        let exact: Vec<f64> = single.iter().flat_map(|&l| [l, l]).collect();
        let request = EigenRequest {
            nd: Some(6),
            ..Default::default()
        };
        let result = solve(&k, &m, request);
        assert_modes(&result, &m, &exact, 1e-10);
        // A start vector that vanishes on the second chain keeps the Krylov space exactly inside
        // the first one (the factor has no coupling between the blocks), so the first pass
        // returns λ1..λ6 of one chain; the Sturm count sees 12 eigenvalues below the top and
        // the extended run must find the second copies.
        let symbolic = SymbolicFactor::analyze(k.pattern()).unwrap();
        let problem = EigenProblem {
            k: &k,
            m: &m,
            symbolic: &symbolic,
        };
        let start: Vec<f64> = (0..2 * half)
            .map(|i| if i < half { 1.0 + i as f64 } else { 0.0 })
            .collect();
        let options = LanczosOptions::default();
        let result = solve_modes_from(
            &problem,
            &request,
            &options,
            Par::Seq,
            &quiet(),
            Some(&start),
        )
        .unwrap();
        assert_modes(&result, &m, &exact, 1e-10);
        assert!(
            result.recoveries > 0,
            "the pairs were found without the Sturm check"
        );
    }

    /// Fixed–fixed unit-spring chain of 2p + 1 DOFs with mass `mass` on the odd DOFs only
    /// (the even ones, ends included, are massless). Static condensation of each massless DOF
    /// joins its two unit springs in series (1/2), so the p finite eigenvalues are those of a
    /// fixed–fixed chain of p masses on springs 1/2: λ_j = (2/m) sin²(jπ / (2(p+1))); the other
    /// p + 1 are infinite.
    fn half_massless_chain(p: usize, mass: f64) -> (CscMatrix<f64>, CscMatrix<f64>, Vec<f64>) {
        let k = chain(2 * p + 1, true, true, None);
        let mut m = k.clone();
        for (i, j, v) in m.triplet_iter_mut() {
            *v = if i == j && i % 2 == 1 { mass } else { 0.0 };
        }
        let exact = (1..=p)
            .map(|j| 2.0 / mass * (j as f64 * PI / (2.0 * (p + 1) as f64)).sin().powi(2))
            .collect();
        (k, m, exact)
    }

    /// Singular M: ND below, at and above the number of finite eigenvalues, and V1..V2 ranges.
    /// Only finite modes come back (never the θ = 0 ones at "infinite" frequency), and
    /// `finite_exhausted` says when ND asked for more than exist.
    #[test]
    fn massless_dofs_give_only_finite_modes() {
        for p in [10, 150] {
            let (k, m, exact) = half_massless_chain(p, 1.5);
            let nd = |nd: usize| EigenRequest {
                nd: Some(nd),
                ..Default::default()
            };
            for (request, range, exhausted) in [
                (nd(5), 0..5, false),
                (nd(p), 0..p, false),
                (nd(p + 1), 0..p, true),
                (nd(2 * p + 1), 0..p, true),
                (
                    EigenRequest {
                        v1_hz: Some(0.5 * (hz(exact[2]) + hz(exact[3]))),
                        nd: Some(2 * p),
                        ..Default::default()
                    },
                    3..p,
                    true,
                ),
                (
                    EigenRequest {
                        v1_hz: Some(0.5 * (hz(exact[1]) + hz(exact[2]))),
                        v2_hz: Some(0.5 * (hz(exact[5]) + hz(exact[6]))),
                        ..Default::default()
                    },
                    2..6,
                    false,
                ),
                (
                    EigenRequest {
                        v2_hz: Some(100.0 * hz(exact[p - 1])),
                        ..Default::default()
                    },
                    0..p,
                    false,
                ),
            ] {
                let result = solve(&k, &m, request);
                assert_modes(&result, &m, &exact[range], 1e-10);
                assert_eq!(result.massless, p + 1);
                assert_eq!(result.finite_exhausted, exhausted, "{request:?}");
            }
        }
    }

    /// M singular on DOFs that do have mass (rank-1 2×2 blocks, as an offset CONM2 without
    /// inertia): no zero diagonal, so only the exhaustion of the Krylov space can tell that
    /// rank(M) = n/2 finite eigenvalues exist. Checked without a closed form: exactly n/2 modes,
    /// small residuals, and the Sturm count just above the highest equals n/2.
    #[test]
    fn rank_deficient_mass_blocks_stop_at_rank() {
        let n = 24;
        let k = chain(n, true, true, None);
        let mut m = k.clone();
        for (i, j, v) in m.triplet_iter_mut() {
            *v = if i / 2 == j / 2 { 1.0 } else { 0.0 };
        }
        let result = solve(
            &k,
            &m,
            EigenRequest {
                nd: Some(n),
                ..Default::default()
            },
        );
        assert_eq!(result.massless, 0);
        assert_eq!(result.eigenvalues.len(), n / 2, "{:?}", result.eigenvalues);
        assert!(result.finite_exhausted);
        assert!(
            result.residuals.iter().all(|&r| r < 1e-8),
            "{:?}",
            result.residuals
        );
        assert!(result.sturm.is_consistent(), "{:?}", result.sturm);
        assert_eq!(result.sturm.negative_pivots, n / 2);
    }

    /// Every property of a run against a closed-form spectrum: `spectrum` is the whole finite
    /// spectrum, ascending, and `expected` the positions in it the request should return.
    /// - eigenvalues: |λ − λ_exact| ≤ 1e-10 · max(|λ_exact|, `scale`) (`scale`: the first
    ///   flexible eigenvalue, the size that makes a rigid-body λ ≈ 0 round-off);
    /// - multiplicity: each distinct exact value (equal to 1e-12) is returned as many times as
    ///   it occurs in `expected`;
    /// - M-orthonormality: max |ΦᵀMΦ − I| ≤ 1e-10, across and within repeated eigenspaces;
    /// - residuals ‖Kφ − λMφ‖ / ‖Kφ‖ ≤ 1e-8, the bound of [`assert_modes`] for the default
    ///   `tol` = 1e-10 (measured on these problems: ≤ 1.9e-9, the free–free flexible modes;
    ///   pairs accepted at a 1e4 × looser `tol` reach 1e-4 there);
    /// - Sturm: the negative pivots of K − sM at the check's shift s equal the number of exact
    ///   eigenvalues below s, and the check is consistent.
    fn assert_against_spectrum(
        result: &EigenResult,
        m: &CscMatrix<f64>,
        spectrum: &[f64],
        expected: std::ops::Range<usize>,
        scale: f64,
    ) {
        let want = &spectrum[expected.clone()];
        assert_eq!(
            result.eigenvalues.len(),
            want.len(),
            "count: {:?} vs {want:?}",
            result.eigenvalues
        );
        for (j, (&got, &exact)) in result.eigenvalues.iter().zip(want).enumerate() {
            assert!(
                (got - exact).abs() <= 1e-10 * exact.abs().max(scale),
                "mode {j}: {got} vs {exact}"
            );
        }
        let mut start = 0;
        while start < want.len() {
            let value = want[start];
            let same = |l: &f64| (l - value).abs() <= 1e-12 * value.abs().max(scale);
            let multiplicity = want.iter().filter(|l| same(l)).count();
            let found = result
                .eigenvalues
                .iter()
                .filter(|l| (*l - value).abs() <= 1e-8 * value.abs().max(scale))
                .count();
            assert_eq!(
                found, multiplicity,
                "λ = {value}: found {found} copies, multiplicity {multiplicity}"
            );
            start += multiplicity;
        }
        let count = result.eigenvalues.len();
        let mut mphi = vec![0.0; m.nrows()];
        for i in 0..count {
            sym_matvec_checked(m, result.vectors.col_as_slice(i), &mut mphi);
            for j in 0..count {
                let g = dot(result.vectors.col_as_slice(j), &mphi);
                let identity = if i == j { 1.0 } else { 0.0 };
                assert!(
                    (g - identity).abs() <= 1e-10,
                    "φ{i}ᵀMφ{j} = {g:e} (λ {} and {})",
                    result.eigenvalues[i],
                    result.eigenvalues[j]
                );
            }
        }
        let worst = result.residuals.iter().copied().fold(0.0, f64::max);
        assert!(worst <= 1e-8, "residuals {:?}", result.residuals);
        let below = spectrum.iter().filter(|&&l| l < result.sturm.shift).count();
        assert_eq!(
            result.sturm.negative_pivots, below,
            "negative pivots at s = {} against the exact count: {:?}",
            result.sturm.shift, result.sturm
        );
        assert!(result.sturm.is_consistent(), "{:?}", result.sturm);
    }

    /// Sturm counts against the closed-form spectrum of a problem with repeated eigenvalues
    /// (the 6×6×6 7-point Laplacian: multiplicities 1, 3, 3, 6, …): at a shift between two
    /// distinct eigenvalues the negative pivots are the exact count below it, and a set of
    /// eigenvalues with one copy of a repeated eigenvalue dropped is short by exactly one.
    #[test]
    fn sturm_counts_follow_the_exact_multiplicities() {
        let dims = [6, 6, 6];
        let k = laplacian(&dims);
        let m = lumped(&k, 1.0);
        let spectrum = laplacian_eigenvalues(&dims, 216);
        let symbolic = SymbolicFactor::analyze(k.pattern()).unwrap();
        let problem = EigenProblem {
            k: &k,
            m: &m,
            symbolic: &symbolic,
        };
        let mut distinct: Vec<f64> = spectrum.clone();
        distinct.dedup_by(|a, b| (*a - *b).abs() <= 1e-12 * b.abs());
        let mut triple_seen = false;
        for pair in distinct.windows(2).take(12) {
            let shift = 0.5 * (pair[0] + pair[1]);
            let below: Vec<f64> = spectrum.iter().copied().filter(|&l| l < shift).collect();
            let exact = sturm_check(&problem, shift, 0, &below, Par::Seq).unwrap();
            assert_eq!(exact.negative_pivots, below.len(), "{exact:?}");
            assert!(exact.is_consistent());
            let copies = below
                .iter()
                .filter(|&&l| (l - pair[0]).abs() <= 1e-12)
                .count();
            triple_seen |= copies == 3;
            let short = sturm_check(&problem, shift, 0, &below[1..], Par::Seq).unwrap();
            assert!(!short.is_consistent(), "{short:?}");
            assert_eq!(short.missing(), 1, "{short:?}");
        }
        assert!(triple_seen, "the test must cross a triple eigenvalue");
    }

    /// Exact multiplicities 3 and 6 (the 5×5×5 Laplacian, a cube's symmetry): single-vector
    /// Lanczos from one start vector sees one direction per eigenspace; every copy must come
    /// back, M-orthonormal, with the Sturm count exact.
    #[test]
    fn repeated_eigenvalues_of_a_cube_come_back_with_their_multiplicity() {
        let dims = [5, 5, 5];
        let k = laplacian(&dims);
        let m = lumped(&k, 2.0);
        let spectrum: Vec<f64> = laplacian_eigenvalues(&dims, 125)
            .iter()
            .map(|l| l / 2.0)
            .collect();
        // λ1 (simple), λ2 (×3), λ3 (×3), λ4 (×3): 10 modes, the request ends after a full group
        let result = solve(
            &k,
            &m,
            EigenRequest {
                nd: Some(10),
                ..Default::default()
            },
        );
        assert_against_spectrum(&result, &m, &spectrum, 0..10, spectrum[0]);
    }

    /// Clustered eigenvalues: two fixed–fixed chains of 40 unit masses, the second's springs
    /// stiffer by a factor 1 + δ, side by side: λ_j = 4 sin²(jπ/82) and (1 + δ) λ_j, pairs a
    /// relative δ = 1e-4 or 1e-6 apart. Each pair's two vectors must come out separate
    /// (eigenvalues to 1e-10, orthogonal, small residuals), which a loose convergence test
    /// does not give: a Ritz vector accepted early is a mixture of the pair.
    #[test]
    fn clustered_eigenvalues_converge_to_separate_vectors() {
        let n = 40;
        let single: Vec<f64> = (1..=n)
            .map(|j| 4.0 * (j as f64 * PI / (2.0 * (n + 1) as f64)).sin().powi(2))
            .collect();
        for delta in [1e-4, 1e-6] {
            let half = chain(n, true, true, None);
            let mut coo = CooMatrix::new(2 * n, 2 * n);
            for (i, j, v) in half.triplet_iter() {
                coo.push(i, j, *v);
                coo.push(n + i, n + j, (1.0 + delta) * v);
            }
            let k = CscMatrix::from(&coo);
            let m = lumped(&k, 1.0);
            let mut spectrum: Vec<f64> = single
                .iter()
                .flat_map(|&l| [l, (1.0 + delta) * l])
                .collect();
            spectrum.sort_by(f64::total_cmp);
            let result = solve(
                &k,
                &m,
                EigenRequest {
                    nd: Some(12),
                    ..Default::default()
                },
            );
            assert_against_spectrum(&result, &m, &spectrum, 0..12, spectrum[0]);
        }
    }

    /// Free–free: two disconnected free chains of 30 and 45 unit masses on unit springs, so
    /// λ = 0 twice (a rigid mode each) and λ_j = 4 sin²(jπ/(2n)) of each. The rigid vectors
    /// must be constant on each chain, the run must find both zeros and the flexible modes
    /// above them.
    #[test]
    fn free_free_pieces_give_each_rigid_mode() {
        let (n1, n2) = (30, 45);
        let k = chain(n1 + n2, false, false, Some(n1));
        let m = lumped(&k, 1.0);
        let mut spectrum: Vec<f64> = [n1, n2]
            .iter()
            .flat_map(|&n| {
                (0..n).map(move |j| 4.0 * (j as f64 * PI / (2.0 * n as f64)).sin().powi(2))
            })
            .collect();
        spectrum.sort_by(f64::total_cmp);
        let first_flexible = spectrum[2];
        for shift_hz in [None, Some(0.02)] {
            let result = solve(
                &k,
                &m,
                EigenRequest {
                    nd: Some(8),
                    shift_hz,
                    ..Default::default()
                },
            );
            assert!(result.shift < 0.0, "{}", result.shift);
            assert_against_spectrum(&result, &m, &spectrum, 0..8, first_flexible);
            for rigid in 0..2 {
                let phi = result.vectors.col_as_slice(rigid);
                for piece in [&phi[..n1], &phi[n1..]] {
                    let spread = piece
                        .iter()
                        .map(|x| (x - piece[0]).abs())
                        .fold(0.0, f64::max);
                    assert!(
                        spread <= 1e-8,
                        "rigid mode {rigid} is not rigid: {spread:e}"
                    );
                }
            }
        }
    }

    /// Massless DOFs and repeated eigenvalues together: two identical half-massless chains
    /// side by side (every finite eigenvalue double, p + 1 massless DOFs each). All finite
    /// modes (ND above their number), each with its multiplicity, none infinite.
    #[test]
    fn massless_pieces_give_every_finite_copy() {
        let p = 12;
        let (k1, m1, exact) = half_massless_chain(p, 1.5);
        let size = k1.nrows();
        let block = |a: &CscMatrix<f64>| {
            let mut coo = CooMatrix::new(2 * size, 2 * size);
            for (i, j, v) in a.triplet_iter() {
                coo.push(i, j, *v);
                coo.push(size + i, size + j, *v);
            }
            CscMatrix::from(&coo)
        };
        let (k, m) = (block(&k1), block(&m1));
        let spectrum: Vec<f64> = exact.iter().flat_map(|&l| [l, l]).collect();
        let result = solve(
            &k,
            &m,
            EigenRequest {
                nd: Some(3 * p),
                ..Default::default()
            },
        );
        assert_eq!(result.massless, 2 * (p + 1));
        assert!(result.finite_exhausted);
        assert_against_spectrum(&result, &m, &spectrum, 0..2 * p, spectrum[0]);
    }

    /// Finite-difference Laplacian (5-point stencil in 2-D, 7-point in 3-D) on a grid of
    /// `dims` points with unit spacing and Dirichlet boundaries; its eigenvalues are
    /// Σ_d 4 sin²(i_d π / (2(n_d+1))), i_d = 1..n_d.
    pub(crate) fn laplacian(dims: &[usize]) -> CscMatrix<f64> {
        let n: usize = dims.iter().product();
        let strides: Vec<usize> = (0..dims.len())
            .map(|d| dims[..d].iter().product())
            .collect();
        let mut coo = CooMatrix::new(n, n);
        for i in 0..n {
            coo.push(i, i, 2.0 * dims.len() as f64);
            for (d, &stride) in strides.iter().enumerate() {
                if (i / stride) % dims[d] + 1 < dims[d] {
                    coo.push(i, i + stride, -1.0);
                    coo.push(i + stride, i, -1.0);
                }
            }
        }
        CscMatrix::from(&coo)
    }

    /// The `count` smallest analytic eigenvalues of [`laplacian`].
    fn laplacian_eigenvalues(dims: &[usize], count: usize) -> Vec<f64> {
        let mut all = vec![0.0];
        for &nd in dims {
            let axis = (1..=nd.min(count))
                .map(|i| 4.0 * (i as f64 * PI / (2.0 * (nd + 1) as f64)).sin().powi(2));
            let axis: Vec<f64> = axis.collect();
            all = all
                .iter()
                .flat_map(|s| axis.iter().map(move |a| s + a))
                .collect();
        }
        all.sort_by(f64::total_cmp);
        all.truncate(count);
        all
    }

    /// 2-D 5-point Laplacian on 120×84 = 10 080 points: first 10 eigenvalues against the
    /// analytic ones (2-D rather than 3-D keeps the debug-build test fast; the 3-D stencil is
    /// exercised by the benchmark below).
    #[test]
    fn laplacian_10k_first_modes() {
        let dims = [120, 84];
        let k = laplacian(&dims);
        let m = lumped(&k, 1.0);
        let result = solve(
            &k,
            &m,
            EigenRequest {
                nd: Some(10),
                ..Default::default()
            },
        );
        assert_modes(&result, &m, &laplacian_eigenvalues(&dims, 10), 1e-10);
    }

    /// The 7-point stencil against its analytic spectrum on a small box (the 300k benchmark
    /// relies on the same builder).
    #[test]
    fn laplacian_3d_small_first_modes() {
        let dims = [9, 8, 7];
        let k = laplacian(&dims);
        let m = lumped(&k, 1.0);
        let result = solve(
            &k,
            &m,
            EigenRequest {
                nd: Some(6),
                ..Default::default()
            },
        );
        assert_modes(&result, &m, &laplacian_eigenvalues(&dims, 6), 1e-10);
    }

    /// Benchmark (run on demand, release), AMD against METIS nested dissection on the 7-point
    /// Laplacian of 70×66×65 = 300 300 points (nnz(A) = 2.1·10⁶), 2 cores shared with other
    /// jobs (load average ≈ 6 during the run, so times are upper bounds):
    ///
    /// | ordering | nnz(L) | analyse | one LDLᵀ, `Par::rayon(2)` | `Par::Seq` | 24 modes |
    /// |---|---|---|---|---|---|
    /// | AMD (faer) | 3.36·10⁸ (2.7 GB) | 1.7 s | 41 s (88 s in an earlier run) | — | 363 s (earlier run) |
    /// | METIS ND   | 1.70·10⁸ (1.4 GB) | 5.9 s | 46 s | 44 s | 152 s |
    ///
    /// Both supernodal. ND halves the factor, hence the memory and every solve of the Lanczos
    /// run (two LDLᵀ — shift and Sturm check — plus about 120 solves, 2 restarts): max relative
    /// eigenvalue error 9.8·10⁻¹⁴, max residual 1.6·10⁻¹². Analysis is slower (METIS on the
    /// uncompressible 300k-vertex graph; a 6-DOF FE pattern hands METIS a 36× smaller graph).
    /// `Par::rayon(2)` gave no speedup over `Par::Seq` on the loaded machine.
    /// `cargo test --release --lib linalg::eigen::tests::bench_laplacian_300k -- --ignored --nocapture`
    #[test]
    #[ignore]
    fn bench_laplacian_300k() {
        use crate::linalg::{FactorVariant, Ordering};
        use std::time::Instant;
        let dims = [70, 66, 65];
        let k = laplacian(&dims);
        let m = lumped(&k, 1.0);
        let par = Par::rayon(2);
        for ordering in [Ordering::NestedDissection, Ordering::Amd] {
            let t0 = Instant::now();
            let symbolic =
                SymbolicFactor::analyze_with(k.pattern(), FactorVariant::Auto, ordering).unwrap();
            let t_analyze = t0.elapsed();
            let t1 = Instant::now();
            let factor = symbolic.factor_ldlt(&k, par).unwrap();
            let t_par = t1.elapsed();
            drop(factor);
            println!(
                "{ordering:?}: n = {}, nnz(A) = {}, nnz(L) = {} ({:?}), analyze {:.2?}, \
                 one LDLᵀ {:.2?} (Par::rayon(2))",
                k.nrows(),
                k.nnz(),
                symbolic.factor_nnz(),
                symbolic.variant(),
                t_analyze,
                t_par,
            );
            if ordering == Ordering::Amd {
                // The full AMD eigen run takes 6 min; its numbers are in the doc comment.
                continue;
            }
            let t1 = Instant::now();
            drop(symbolic.factor_ldlt(&k, Par::Seq).unwrap());
            println!("{ordering:?}: one LDLᵀ {:.2?} (Par::Seq)", t1.elapsed());
            let problem = EigenProblem {
                k: &k,
                m: &m,
                symbolic: &symbolic,
            };
            let t2 = Instant::now();
            let request = EigenRequest {
                nd: Some(24),
                ..Default::default()
            };
            let result = solve_modes(
                &problem,
                &request,
                &LanczosOptions::default(),
                par,
                &quiet(),
            )
            .unwrap();
            let t_eigen = t2.elapsed();
            let exact = laplacian_eigenvalues(&dims, 24);
            let err = result
                .eigenvalues
                .iter()
                .zip(&exact)
                .map(|(a, b)| ((a - b) / b).abs())
                .fold(0.0, f64::max);
            let res = result.residuals.iter().copied().fold(0.0, f64::max);
            println!(
                "{ordering:?}: eigen total {:.2?} ({} modes, {} restarts), max rel. eigenvalue \
                 error {:.1e}, max residual {:.1e}, Sturm {:?}",
                t_eigen,
                result.eigenvalues.len(),
                result.restarts,
                err,
                res,
                result.sturm
            );
            assert!(err < 1e-10 && result.sturm.is_consistent());
        }
    }
}
