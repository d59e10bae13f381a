//! Isotropic 3-D solid elements: CHEXA 8 (incompatible modes), CPENTA 6, CTETRA 4, CTETRA 10,
//! CHEXA 20, CPENTA 15 (DESIGN.md §4–§5; thesis §2.1 and eq. 3.13–3.16).
//!
//! # Translational matrices (3 DOFs per grid)
//! Solids have no rotational stiffness or mass. Unlike the rest of [`crate::fe`], every function
//! here returns **3·n × 3·n** matrices over the translations only, grid-major: row `3·a + c` is
//! component T(c+1) of the element's grid `a`, in the basic system. They are assembled as they
//! are ([`crate::assembly::Contribution::element`] takes 3·n matrices as translations only), so a
//! solid mesh's K and M hold 3 × 3 grid blocks (the assembly AUTOSPCs rotations that nothing else
//! touches). The 3·n form quarters the storage of solid meshes and keeps the kernels and their
//! tests free of structurally zero rows.
//!
//! # Constitutive law and affine parts
//! Strains are engineering strains ε = [εxx, εyy, εzz, γxy, γyz, γzx]. The isotropic
//! constitutive matrix is split into the Lamé parts of eq. 3.13,
//!
//! D = λ D_λ + μ D_μ,  `D_λ = [[𝟏, 0], [0, 0]]` (𝟏 the 3×3 matrix of ones),
//! D_μ = diag(2, 2, 2, 1, 1, 1),
//!
//! λ = Eν/((1+ν)(1−2ν)), μ = E/(2(1+ν)). With Cartesian shape-function gradients g_a = ∇N_a the
//! 3×3 block (a, b) of K = ∫ Bᵀ D B dV is therefore, componentwise (i, j),
//!
//! K_ab,ij = ∫ λ g_a,i g_b,j + μ (g_a,j g_b,i + δ_ij g_a · g_b) dV,
//!
//! which is how the kernels evaluate it. K is linear in (λ, μ) for every element but CHEXA 8
//! (the isoparametric CPENTA 6/15, CTETRA 4/10 and CHEXA 20 condense nothing), so the
//! Lamé parts K_λ, K_μ of eq. 3.14 are exact; K ∝ E at fixed ν (eq. 3.15) for every element,
//! CHEXA included (static condensation commutes with scaling D). Mass M ∝ ρ (eq. 3.16).
//! For CHEXA with incompatible modes the condensed matrix K_uu − K_ua K_aa⁻¹ K_au is *not*
//! affine in (λ, μ): [`affine_stiffness`] refuses [`StiffnessParametrization::Lame`] for it
//! (DESIGN.md §5: refuse rather than approximate).
//!
//! # Elements and quadrature
//! | element | stiffness | consistent mass (exact) | lumped mass |
//! |---|---|---|---|
//! | CHEXA 8 | 2×2×2 Gauss + 9 incompatible modes, condensed | 3×3×3 Gauss | row sum |
//! | CPENTA 6 | 3-point triangle × 2-point Gauss | collapsed 3×3 triangle × 3 Gauss | row sum |
//! | CTETRA 4 | 1 point (constant strain) | 4-point, degree 2 | row sum (ρV/4 each) |
//! | CTETRA 10 | 4-point, degree 2 | collapsed 5×5×5, degree 7 (curved edges too) | HRZ |
//! | CHEXA 20 | 3×3×3 Gauss (full) | 5×5×5 Gauss, degree 9 per direction (curved edges too) | HRZ |
//! | CPENTA 15 | 7-point triangle × 3 Gauss (21 points, full) | collapsed 5×5 triangle × 5 Gauss | HRZ |
//!
//! Node orders and shape functions are documented in `solid_shape.rs`. The consistent mass is
//! M_ab = ρ ∫ N_a N_b dV · I₃. Lumping by row sum is positive for the linear elements
//! (N_a ≥ 0); for the quadratic elements the row sums of the corner nodes are negative
//! (CTETRA 10) or small and of either sign, so the HRZ scheme
//! (Hinton, Rock & Zienkiewicz 1976) is used instead: m_a = M_aa · ρV / Σ_b M_bb, i.e. the
//! diagonal of the consistent mass scaled to the total mass (CTETRA 10 with straight edges:
//! corners ρV/36, mid-edge nodes 4ρV/27).
//!
//! Blank mid-side grids of CHEXA 20 and CPENTA 15 are handled in `solid_midside.rs` on top of
//! these full-node kernels.
//!
//! ## CHEXA 8 with incompatible modes
//! Wilson's incompatible modes P₁ = 1 − ξ², P₂ = 1 − η², P₃ = 1 − ζ², one per displacement
//! component (9 internal DOFs α), in the form of Taylor, Beresford & Wilson, "A non-conforming
//! element for stress analysis", IJNME 10 (1976) 1211–1219 (QM6): their Cartesian gradients use
//! the Jacobian J₀ at the element centre and are scaled by det J₀ / det J,
//!
//! ∇P_k(ξ) = (det J₀ / det J(ξ)) · J₀⁻ᵀ ∇_ξ P_k(ξ),
//!
//! so that ∫ ∇P_k dV = det J₀ J₀⁻ᵀ ∫ ∇_ξ P_k dξ = 0 exactly under 2×2×2 Gauss: a constant stress
//! does no work on the modes, α = 0 for a linear field, and the element passes the patch test on
//! distorted meshes. The 33×33 matrix `[[K_uu, K_uα], [K_αu, K_αα]]` is condensed statically,
//! K = K_uu − K_uα K_αα⁻¹ K_αu (Cholesky of K_αα), and symmetrized to round-off. At the centroid
//! ∇_ξ P_k = 0, so the centroid strain of [`strain_at_centroid`] needs no α and no material.
//!
//! # Geometry errors
//! Every evaluation point (integration points, and the centre for CHEXA) checks the Jacobian:
//! det J ≤ 10⁻¹⁰ · |J₁||J₂||J₃| (columns J_k = ∂x/∂ξ_k; i.e. a scaled Jacobian at or below 10⁻¹⁰,
//! which includes det J ≤ 0 and NaN) returns [`SolidError::NonPositiveJacobian`] naming the
//! point. Grids must be ordered so that the natural axes are right-handed (for CHEXA: G1–G4
//! counter-clockwise seen from G5–G8); mirrored orderings are reported, not silently reordered.

use super::affine::{AffineMatrix, Coefficient};
use super::solid_shape::{self as shape, Gauss, MAX_NODES, QuadPoint};
use crate::geometry::{mat3, vec3};
use faer::linalg::solvers::{Llt, Solve};
use faer::{Mat, Side};
use std::fmt;

/// The solid element topologies.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum SolidKind {
    /// CHEXA with 8 grids (trilinear + incompatible modes).
    Hexa8,
    /// CPENTA with 6 grids (linear wedge).
    Penta6,
    /// CTETRA with 4 grids (constant strain).
    Tetra4,
    /// CTETRA with 10 grids (quadratic).
    Tetra10,
    /// CHEXA with 20 grids (quadratic serendipity).
    Hexa20,
    /// CPENTA with 15 grids (quadratic).
    Penta15,
    /// CPYRAM with 5 grids (rational pyramid, [`shape`] module doc).
    Pyram5,
}

impl SolidKind {
    /// Number of grids.
    pub fn nodes(self) -> usize {
        match self {
            SolidKind::Hexa8 => 8,
            SolidKind::Penta6 => 6,
            SolidKind::Tetra4 => 4,
            SolidKind::Tetra10 => 10,
            SolidKind::Hexa20 => 20,
            SolidKind::Penta15 => 15,
            SolidKind::Pyram5 => 5,
        }
    }

    /// Number of (translational) DOFs of the matrices returned here: 3 · nodes.
    pub fn dofs(self) -> usize {
        3 * self.nodes()
    }
}

impl fmt::Display for SolidKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            SolidKind::Hexa8 => "CHEXA",
            SolidKind::Penta6 => "CPENTA",
            SolidKind::Tetra4 => "CTETRA (4 grids)",
            SolidKind::Tetra10 => "CTETRA (10 grids)",
            SolidKind::Hexa20 => "CHEXA (20 grids)",
            SolidKind::Penta15 => "CPENTA (15 grids)",
            SolidKind::Pyram5 => "CPYRAM",
        })
    }
}

/// Isotropic elastic constants (MAT1 E and ν).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Isotropic {
    pub e: f64,
    pub nu: f64,
}

impl Isotropic {
    /// Lamé constants (λ, μ) of eq. 3.13.
    pub fn lame(self) -> Lame {
        Lame {
            lambda: self.e * self.nu / ((1.0 + self.nu) * (1.0 - 2.0 * self.nu)),
            mu: self.e / (2.0 * (1.0 + self.nu)),
        }
    }
}

/// Lamé constants: D = λ D_λ + μ D_μ (eq. 3.13).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Lame {
    pub lambda: f64,
    pub mu: f64,
}

/// Where a Jacobian was evaluated.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum EvalPoint {
    /// Integration point `index` (0-based) of a rule of `of` points.
    Integration { index: usize, of: usize },
    /// The element centre (CHEXA incompatible modes) or centroid (strain recovery).
    Centre,
    /// Corner `0-based index` (strain recovery of the quadratic elements).
    Corner(usize),
    /// Mid-side node `0-based index` (its natural position; the grid may be blank).
    MidSide(usize),
}

impl fmt::Display for EvalPoint {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            EvalPoint::Integration { index, of } => {
                write!(f, "integration point {} of {}", index + 1, of)
            }
            EvalPoint::Centre => f.write_str("the element centre"),
            EvalPoint::Corner(a) => write!(f, "corner G{}", a + 1),
            EvalPoint::MidSide(a) => write!(f, "mid-side node G{}", a + 1),
        }
    }
}

/// Errors of the solid kernels.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SolidError {
    #[error("{kind}: {got} grid coordinates given, {expected} expected")]
    NodeCount {
        kind: SolidKind,
        expected: usize,
        got: usize,
    },
    #[error(
        "{kind}: det J = {det:.4e} at {at}, (ξ, η, ζ) = ({:.4}, {:.4}, {:.4}), scaled Jacobian {scaled:.3e}: the element is inverted or degenerate (check the grid order and coincident grids)",
        xi[0], xi[1], xi[2]
    )]
    NonPositiveJacobian {
        kind: SolidKind,
        at: EvalPoint,
        xi: [f64; 3],
        det: f64,
        scaled: f64,
    },
    #[error(
        "{kind}: {got} displacement values given, {expected} expected (3 translations per grid)"
    )]
    DisplacementLength {
        kind: SolidKind,
        expected: usize,
        got: usize,
    },
    #[error(
        "ν cannot be a parameter of CHEXA with incompatible modes (static condensation is not affine in λ, μ); parametrize E with ν fixed (K ∝ E is exact), or mesh the parametrized region with CPENTA/CTETRA"
    )]
    NuNotAffineForIncompatibleHexa,
    #[error(
        "CHEXA: the incompatible-mode block K_αα is not positive definite (λ = {lambda:.4e}, μ = {mu:.4e}); static condensation needs μ > 0 and 3λ + 2μ > 0 (E > 0, −1 < ν < ½)"
    )]
    CondensationFailed { lambda: f64, mu: f64 },
}

/// Scaled-Jacobian threshold: det J ≤ this · |J₁||J₂||J₃| counts as inverted or degenerate.
const MIN_SCALED_JACOBIAN: f64 = 1e-10;

/// Shape values, Cartesian gradients and det J at one point.
struct PointEval {
    n: [f64; MAX_NODES],
    g: [[f64; 3]; MAX_NODES],
    det: f64,
}

/// J_ij = ∂x_i/∂ξ_j = Σ_a x_a,i ∂N_a/∂ξ_j.
fn jacobian(xyz: &[[f64; 3]], dn: &[[f64; 3]]) -> [[f64; 3]; 3] {
    let mut j = [[0.0; 3]; 3];
    for (x, d) in xyz.iter().zip(dn) {
        for r in 0..3 {
            for c in 0..3 {
                j[r][c] += x[r] * d[c];
            }
        }
    }
    j
}

/// J⁻ᵀ = cofactor(J) / det J.
fn inverse_transpose(j: &[[f64; 3]; 3], det: f64) -> [[f64; 3]; 3] {
    let c =
        |r0: usize, r1: usize, c0: usize, c1: usize| j[r0][c0] * j[r1][c1] - j[r0][c1] * j[r1][c0];
    [
        [
            c(1, 2, 1, 2) / det,
            -c(1, 2, 0, 2) / det,
            c(1, 2, 0, 1) / det,
        ],
        [
            -c(0, 2, 1, 2) / det,
            c(0, 2, 0, 2) / det,
            -c(0, 2, 0, 1) / det,
        ],
        [
            c(0, 1, 1, 2) / det,
            -c(0, 1, 0, 2) / det,
            c(0, 1, 0, 1) / det,
        ],
    ]
}

fn mat_vec(a: &[[f64; 3]; 3], v: [f64; 3]) -> [f64; 3] {
    std::array::from_fn(|r| a[r][0] * v[0] + a[r][1] * v[1] + a[r][2] * v[2])
}

/// Jacobian, its determinant and J⁻ᵀ at `xi`, with the degeneracy check.
fn checked_jacobian(
    kind: SolidKind,
    xyz: &[[f64; 3]],
    dn: &[[f64; 3]],
    xi: [f64; 3],
    at: EvalPoint,
) -> Result<(f64, [[f64; 3]; 3]), SolidError> {
    let j = jacobian(xyz, dn);
    let det = mat3::det(&j);
    let norms: f64 = (0..3)
        .map(|c| vec3::norm([j[0][c], j[1][c], j[2][c]]))
        .product();
    let scaled = det / norms;
    if scaled.is_nan() || scaled <= MIN_SCALED_JACOBIAN {
        return Err(SolidError::NonPositiveJacobian {
            kind,
            at,
            xi,
            det,
            scaled,
        });
    }
    Ok((det, inverse_transpose(&j, det)))
}

fn evaluate(
    kind: SolidKind,
    xyz: &[[f64; 3]],
    xi: [f64; 3],
    at: EvalPoint,
) -> Result<PointEval, SolidError> {
    let n = kind.nodes();
    let s = shape::shape(kind, xi);
    let (det, jit) = checked_jacobian(kind, xyz, &s.dn[..n], xi, at)?;
    let mut g = [[0.0; 3]; MAX_NODES];
    for (ga, &da) in g.iter_mut().zip(&s.dn[..n]) {
        *ga = mat_vec(&jit, da);
    }
    Ok(PointEval { n: s.n, g, det })
}

fn check_nodes(kind: SolidKind, xyz: &[[f64; 3]]) -> Result<(), SolidError> {
    if xyz.len() == kind.nodes() {
        Ok(())
    } else {
        Err(SolidError::NodeCount {
            kind,
            expected: kind.nodes(),
            got: xyz.len(),
        })
    }
}

/// Evaluates every point of `rule`, naming the failing one.
fn evaluate_rule(
    kind: SolidKind,
    xyz: &[[f64; 3]],
    rule: &[QuadPoint],
) -> Result<Vec<(f64, PointEval)>, SolidError> {
    let of = rule.len();
    rule.iter()
        .enumerate()
        .map(|(index, p)| {
            Ok((
                p.w,
                evaluate(kind, xyz, p.xi, EvalPoint::Integration { index, of })?,
            ))
        })
        .collect()
}

/// Adds w · K_ab,ij = w (λ g_a,i g_b,j + μ (g_a,j g_b,i + δ_ij g_a·g_b)) for all pseudo-nodes of
/// `g` into the row-major `ndof × ndof` buffer `k` (ndof = 3 · g.len()).
fn add_lame_blocks(k: &mut [f64], g: &[[f64; 3]], lame: Lame, w: f64) {
    let ndof = 3 * g.len();
    for (a, ga) in g.iter().enumerate() {
        for (b, gb) in g.iter().enumerate() {
            let dot = vec3::dot(*ga, *gb);
            for i in 0..3 {
                let row = &mut k[(3 * a + i) * ndof + 3 * b..][..3];
                for (j, kij) in row.iter_mut().enumerate() {
                    let diag = if i == j { dot } else { 0.0 };
                    *kij += w * (lame.lambda * ga[i] * gb[j] + lame.mu * (ga[j] * gb[i] + diag));
                }
            }
        }
    }
}

fn stiffness_rule(kind: SolidKind) -> Vec<QuadPoint> {
    match kind {
        SolidKind::Hexa8 => shape::hexa_rule(Gauss::Two),
        SolidKind::Penta6 => shape::wedge_stiffness_rule(),
        SolidKind::Tetra4 => shape::tet_centroid_rule(),
        SolidKind::Tetra10 => shape::tet_four_rule(),
        SolidKind::Hexa20 => shape::hexa_rule(Gauss::Three),
        SolidKind::Penta15 => shape::wedge15_stiffness_rule(),
        SolidKind::Pyram5 => shape::pyramid_rule(Gauss::Two),
    }
}

/// Stiffness for Lamé constants `lame` (3·n × 3·n), the kernel behind [`stiffness`] and
/// [`affine_stiffness`].
fn stiffness_lame(kind: SolidKind, xyz: &[[f64; 3]], lame: Lame) -> Result<Mat<f64>, SolidError> {
    check_nodes(kind, xyz)?;
    let n = kind.nodes();
    let points = evaluate_rule(kind, xyz, &stiffness_rule(kind))?;
    if kind == SolidKind::Hexa8 {
        return hexa_incompatible(xyz, lame, &points);
    }
    let nd = 3 * n;
    let mut k = vec![0.0; nd * nd];
    for (w, p) in &points {
        add_lame_blocks(&mut k, &p.g[..n], lame, w * p.det);
    }
    Ok(Mat::from_fn(nd, nd, |i, j| k[i * nd + j]))
}

/// CHEXA 8 DOFs: 24 grid translations and 9 incompatible-mode amplitudes α.
const HEXA_NU: usize = 24;
const HEXA_NA: usize = 9;
const HEXA_ND: usize = HEXA_NU + HEXA_NA;

/// Cartesian gradients of the 8 grids' shape functions and of the 3 incompatible modes (Taylor's
/// form, module doc) at each evaluated 2×2×2 Gauss point of `points`.
fn hexa_gradients(
    xyz: &[[f64; 3]],
    points: &[(f64, PointEval)],
) -> Result<Vec<[[f64; 3]; 11]>, SolidError> {
    let kind = SolidKind::Hexa8;
    let centre = shape::shape(kind, [0.0; 3]);
    let (det0, j0it) = checked_jacobian(kind, xyz, &centre.dn[..8], [0.0; 3], EvalPoint::Centre)?;
    let rule = shape::hexa_rule(Gauss::Two);
    Ok(rule
        .iter()
        .zip(points)
        .map(|(q, (_, p))| {
            let mut g = [[0.0; 3]; 11];
            g[..8].copy_from_slice(&p.g[..8]);
            for m in 0..3 {
                let mut dp = [0.0; 3];
                dp[m] = -2.0 * q.xi[m];
                g[8 + m] = mat_vec(&j0it, dp).map(|v| v * det0 / p.det);
            }
            g
        })
        .collect())
}

/// The 33 × 33 stiffness of grids and modes (row-major, grids first) at the Gauss points
/// `points` with the gradients `grads`, and the Cholesky factor of its mode block K_αα.
fn hexa_extended(
    lame: Lame,
    points: &[(f64, PointEval)],
    grads: &[[[f64; 3]; 11]],
) -> Result<(Vec<f64>, Llt<f64>), SolidError> {
    let mut k = vec![0.0; HEXA_ND * HEXA_ND];
    for ((w, p), g) in points.iter().zip(grads) {
        add_lame_blocks(&mut k, g, lame, w * p.det);
    }
    let kaa = Mat::from_fn(HEXA_NA, HEXA_NA, |i, j| {
        k[(HEXA_NU + i) * HEXA_ND + HEXA_NU + j]
    });
    let llt = kaa
        .llt(Side::Lower)
        .map_err(|_| SolidError::CondensationFailed {
            lambda: lame.lambda,
            mu: lame.mu,
        })?;
    Ok((k, llt))
}

/// CHEXA 8 with the Taylor–Beresford–Wilson incompatible modes, statically condensed (module
/// doc). `points` are the evaluated 2×2×2 Gauss points.
fn hexa_incompatible(
    xyz: &[[f64; 3]],
    lame: Lame,
    points: &[(f64, PointEval)],
) -> Result<Mat<f64>, SolidError> {
    const NU: usize = HEXA_NU;
    const NA: usize = HEXA_NA;
    const ND: usize = HEXA_ND;
    let (k, llt) = hexa_extended(lame, points, &hexa_gradients(xyz, points)?)?;
    let mut x = Mat::from_fn(NA, NU, |i, j| k[(NU + i) * ND + j]);
    llt.solve_in_place(x.as_mut());
    let condensed = |i: usize, j: usize| {
        k[i * ND + j] - (0..NA).map(|m| k[i * ND + NU + m] * x[(m, j)]).sum::<f64>()
    };
    let kc = Mat::from_fn(NU, NU, condensed);
    Ok(Mat::from_fn(NU, NU, |i, j| 0.5 * (kc[(i, j)] + kc[(j, i)])))
}

/// Element stiffness K (3·n × 3·n, translations only; see the module doc) of an isotropic solid
/// with grids at `xyz` (basic coordinates, Nastran order).
pub fn stiffness(
    kind: SolidKind,
    xyz: &[[f64; 3]],
    material: Isotropic,
) -> Result<Mat<f64>, SolidError> {
    stiffness_lame(kind, xyz, material.lame())
}

/// Which material constants of a solid's stiffness are parameters (DESIGN.md §5).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum StiffnessParametrization {
    /// Nothing parametrized: one [`Coefficient::Constant`] part, K at the given material.
    Fixed(Isotropic),
    /// E varies at fixed ν (eq. 3.15): one [`Coefficient::E`] part, K at E = 1. Exact for every
    /// element, CHEXA with incompatible modes included.
    YoungsModulus { nu: f64 },
    /// ν (and possibly E) varies: parts [`Coefficient::Lambda`] (K at λ = 1, μ = 0) and
    /// [`Coefficient::Mu`] (K at λ = 0, μ = 1), eq. 3.14. Refused for CHEXA.
    Lame,
}

/// Affine parts of the element stiffness (3·n × 3·n), K(p) = Σ f_i(p) K_i exactly.
///
/// Errors: [`SolidError::NuNotAffineForIncompatibleHexa`] for CHEXA with
/// [`StiffnessParametrization::Lame`]; geometry errors as [`stiffness`].
pub fn affine_stiffness(
    kind: SolidKind,
    xyz: &[[f64; 3]],
    parametrization: StiffnessParametrization,
) -> Result<AffineMatrix, SolidError> {
    let parts = match parametrization {
        StiffnessParametrization::Fixed(m) => {
            vec![(Coefficient::Constant, stiffness(kind, xyz, m)?)]
        }
        StiffnessParametrization::YoungsModulus { nu } => {
            vec![(
                Coefficient::E,
                stiffness(kind, xyz, Isotropic { e: 1.0, nu })?,
            )]
        }
        StiffnessParametrization::Lame if kind == SolidKind::Hexa8 => {
            return Err(SolidError::NuNotAffineForIncompatibleHexa);
        }
        StiffnessParametrization::Lame => vec![
            (
                Coefficient::Lambda,
                stiffness_lame(
                    kind,
                    xyz,
                    Lame {
                        lambda: 1.0,
                        mu: 0.0,
                    },
                )?,
            ),
            (
                Coefficient::Mu,
                stiffness_lame(
                    kind,
                    xyz,
                    Lame {
                        lambda: 0.0,
                        mu: 1.0,
                    },
                )?,
            ),
        ],
    };
    Ok(AffineMatrix { parts })
}

/// Consistent or lumped mass.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MassLumping {
    /// M_ab = ρ ∫ N_a N_b dV · I₃, integrated exactly.
    Consistent,
    /// Diagonal: row sums (CHEXA 8, CPENTA 6, CTETRA 4) or HRZ (CTETRA 10, CHEXA 20,
    /// CPENTA 15); module doc.
    Lumped,
}

fn mass_rule(kind: SolidKind) -> Vec<QuadPoint> {
    match kind {
        SolidKind::Hexa8 => shape::hexa_rule(Gauss::Three),
        SolidKind::Penta6 => shape::wedge_mass_rule(),
        SolidKind::Tetra4 => shape::tet_four_rule(),
        SolidKind::Tetra10 => shape::tet_collapsed_rule(Gauss::Five),
        SolidKind::Hexa20 => shape::hexa_rule(Gauss::Five),
        SolidKind::Penta15 => shape::wedge15_mass_rule(),
        SolidKind::Pyram5 => shape::pyramid_rule(Gauss::Three),
    }
}

/// Element mass (3·n × 3·n, translations only) for density `rho`.
pub fn mass(
    kind: SolidKind,
    xyz: &[[f64; 3]],
    rho: f64,
    lumping: MassLumping,
) -> Result<Mat<f64>, SolidError> {
    let mut m = scalar_mass(kind, xyz, rho)?;
    if lumping == MassLumping::Lumped {
        lump(kind, &mut m);
    }
    Ok(translational(&m))
}

/// The consistent scalar mass ρ ∫ N_a N_b dV (n × n, one block of I₃ ⊗ m).
pub(crate) fn scalar_mass(
    kind: SolidKind,
    xyz: &[[f64; 3]],
    rho: f64,
) -> Result<Mat<f64>, SolidError> {
    check_nodes(kind, xyz)?;
    let n = kind.nodes();
    let mut m = Mat::<f64>::zeros(n, n);
    for (w, p) in evaluate_rule(kind, xyz, &mass_rule(kind))? {
        for b in 0..n {
            for a in 0..n {
                m[(a, b)] += rho * w * p.det * p.n[a] * p.n[b];
            }
        }
    }
    Ok(m)
}

/// Lumps a scalar mass in place: row sums (linear elements) or HRZ (quadratic; module doc).
pub(crate) fn lump(kind: SolidKind, m: &mut Mat<f64>) {
    let n = m.nrows();
    let row = |a: usize| (0..n).map(|b| m[(a, b)]).sum::<f64>();
    let diag: Vec<f64> = match kind {
        SolidKind::Tetra10 | SolidKind::Hexa20 | SolidKind::Penta15 => {
            let total: f64 = (0..n).map(row).sum();
            let trace: f64 = (0..n).map(|a| m[(a, a)]).sum();
            (0..n).map(|a| m[(a, a)] * total / trace).collect()
        }
        SolidKind::Hexa8 | SolidKind::Penta6 | SolidKind::Tetra4 | SolidKind::Pyram5 => {
            (0..n).map(row).collect()
        }
    };
    *m = Mat::from_fn(n, n, |a, b| if a == b { diag[a] } else { 0.0 });
}

/// I₃ ⊗ m: the 3·n × 3·n translational matrix of a scalar n × n mass, grid-major.
pub(crate) fn translational(m: &Mat<f64>) -> Mat<f64> {
    let n = 3 * m.nrows();
    Mat::from_fn(n, n, |i, j| {
        if i % 3 == j % 3 {
            m[(i / 3, j / 3)]
        } else {
            0.0
        }
    })
}

/// Volume ∫ dV and centroid (1/V) ∫ x dV of the element, by its mass rule.
pub fn volume_and_centroid(
    kind: SolidKind,
    xyz: &[[f64; 3]],
) -> Result<(f64, [f64; 3]), SolidError> {
    check_nodes(kind, xyz)?;
    let n = kind.nodes();
    let mut volume = 0.0;
    let mut moment = [0.0; 3];
    for (w, p) in evaluate_rule(kind, xyz, &mass_rule(kind))? {
        let dv = w * p.det;
        volume += dv;
        for (na, x) in p.n[..n].iter().zip(xyz) {
            for k in 0..3 {
                moment[k] += dv * na * x[k];
            }
        }
    }
    Ok((volume, moment.map(|m| m / volume)))
}

/// The Jacobian determinant of an element sampled where the kernels evaluate it and at its
/// nodes: [`jacobian_range`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JacobianRange {
    /// Smallest det J.
    pub min: f64,
    /// Largest det J.
    pub max: f64,
    /// Where det J is smallest.
    pub min_at: EvalPoint,
    /// Natural coordinates of `min_at`.
    pub min_xi: [f64; 3],
    /// Smallest scaled Jacobian det J / (|J₁||J₂||J₃|) (the kernels refuse ≤ 10⁻¹⁰, module doc).
    pub min_scaled: f64,
    /// ∫ det J by the mass rule: the signed volume.
    pub volume: f64,
}

impl JacobianRange {
    /// Whether the kernels accept the element: every sampled scaled Jacobian above 10⁻¹⁰.
    pub fn is_valid(&self) -> bool {
        self.min_scaled > MIN_SCALED_JACOBIAN
    }
}

/// det J of the element with grids `xyz` at its nodes (corners and mid-side nodes), its centre
/// and every point of its stiffness and mass rules, without refusing any: the geometry check
/// of `paraflex check` (an element that [`JacobianRange::is_valid`] accepts passes the
/// kernels' own check at every point they evaluate). NaN coordinates give a NaN range.
pub fn jacobian_range(kind: SolidKind, xyz: &[[f64; 3]]) -> Result<JacobianRange, SolidError> {
    check_nodes(kind, xyz)?;
    let n = kind.nodes();
    let corners = corners(kind);
    let nodes = (0..n).map(|a| {
        let at = if a < corners {
            EvalPoint::Corner(a)
        } else {
            EvalPoint::MidSide(a)
        };
        (at, shape::node_xi(kind, a))
    });
    let rule_points = |rule: Vec<QuadPoint>| {
        let of = rule.len();
        rule.into_iter()
            .enumerate()
            .map(move |(index, p)| (EvalPoint::Integration { index, of }, p.xi))
    };
    let mut range = JacobianRange {
        min: f64::INFINITY,
        max: f64::NEG_INFINITY,
        min_at: EvalPoint::Centre,
        min_xi: shape::centroid(kind),
        min_scaled: f64::INFINITY,
        volume: 0.0,
    };
    let points = nodes
        .chain([(EvalPoint::Centre, shape::centroid(kind))])
        .chain(rule_points(stiffness_rule(kind)))
        .chain(rule_points(mass_rule(kind)));
    for (at, xi) in points {
        let j = jacobian(xyz, &shape::shape(kind, xi).dn[..n]);
        let det = mat3::det(&j);
        let norms: f64 = (0..3)
            .map(|c| vec3::norm([j[0][c], j[1][c], j[2][c]]))
            .product();
        if det.is_nan() || det < range.min {
            range.min = det;
            range.min_at = at;
            range.min_xi = xi;
        }
        range.max = range.max.max(det);
        let scaled = det / norms;
        if scaled.is_nan() || scaled < range.min_scaled {
            range.min_scaled = scaled;
        }
    }
    for p in mass_rule(kind) {
        let j = jacobian(xyz, &shape::shape(kind, p.xi).dn[..n]);
        range.volume += p.w * mat3::det(&j);
    }
    Ok(range)
}

/// Whether the density is a parameter.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum MassParametrization {
    /// One [`Coefficient::Constant`] part, M at density `rho`.
    Fixed { rho: f64 },
    /// One [`Coefficient::Rho`] part, M at ρ = 1 (eq. 3.16).
    Density,
}

/// Affine parts of the element mass (3·n × 3·n).
pub fn affine_mass(
    kind: SolidKind,
    xyz: &[[f64; 3]],
    lumping: MassLumping,
    parametrization: MassParametrization,
) -> Result<AffineMatrix, SolidError> {
    super::solid_midside::Midsides::complete(kind).affine_mass(xyz, lumping, parametrization)
}

/// Strain [εxx, εyy, εzz, γxy, γyz, γzx] (engineering shear) at the element centroid from the
/// element's translations `u` (3·n values, grid-major), ε = Σ_a B_a(centroid) u_a. For CHEXA
/// the incompatible modes have zero gradient at the centre, so this is the full element strain.
pub fn strain_at_centroid(
    kind: SolidKind,
    xyz: &[[f64; 3]],
    u: &[f64],
) -> Result<[f64; 6], SolidError> {
    check_nodes(kind, xyz)?;
    let n = kind.nodes();
    if u.len() != 3 * n {
        return Err(SolidError::DisplacementLength {
            kind,
            expected: 3 * n,
            got: u.len(),
        });
    }
    let p = evaluate(kind, xyz, shape::centroid(kind), EvalPoint::Centre)?;
    Ok(strain_of(&p.g[..n], u))
}

/// Engineering strain of the field Σ_a u_a N_a for the gradients g_a = ∇N_a and the
/// (pseudo-)node vectors u_a (3 per gradient).
fn strain_of(g: &[[f64; 3]], u: &[f64]) -> [f64; 6] {
    // displacement gradient H_ij = ∂u_i/∂x_j
    let mut h = [[0.0; 3]; 3];
    for (ga, ua) in g.iter().zip(u.chunks_exact(3)) {
        for i in 0..3 {
            for j in 0..3 {
                h[i][j] += ua[i] * ga[j];
            }
        }
    }
    [
        h[0][0],
        h[1][1],
        h[2][2],
        h[0][1] + h[1][0],
        h[1][2] + h[2][1],
        h[2][0] + h[0][2],
    ]
}

/// The element's corner grids: all of them for the linear elements, the first 4 (CTETRA 10),
/// 8 (CHEXA 20) or 6 (CPENTA 15) of the quadratic ones.
pub fn corners(kind: SolidKind) -> usize {
    kind.nodes() - shape::midside_edges(kind).len()
}

/// Strains at the corner grids ([`corners`] of them, in grid order), extrapolated from the
/// stiffness integration points as CalculiX and Nastran's CORNER output do: the strains of
/// the element's own field at its stiffness points (CHEXA 8 with its incompatible modes
/// recovered, α = −K_αα⁻¹ K_αu u for the material `material`) are interpolated by the linear
/// element on the corners that passes through them (2×2×2 points → trilinear on the 8 corners,
/// CPENTA's 3 × 2 points → the linear wedge, CTETRA 10's 4 points → the linear tetrahedron);
/// CTETRA 4 has one point, a constant strain. Exact for strain fields the element's points
/// represent linearly (e.g. pure bending of a brick). CHEXA 20 and CPENTA 15 evaluate their
/// own strain field at the corners instead (their 27 and 21 points are more than the corners,
/// and the quadratic field holds a linear strain exactly), and so does CPYRAM (8 points, 5
/// corners).
pub fn corner_strains(
    kind: SolidKind,
    xyz: &[[f64; 3]],
    u: &[f64],
    material: Isotropic,
) -> Result<Vec<[f64; 6]>, SolidError> {
    check_nodes(kind, xyz)?;
    let n = kind.nodes();
    if u.len() != 3 * n {
        return Err(SolidError::DisplacementLength {
            kind,
            expected: 3 * n,
            got: u.len(),
        });
    }
    if matches!(
        kind,
        SolidKind::Hexa20 | SolidKind::Penta15 | SolidKind::Pyram5
    ) {
        return (0..corners(kind))
            .map(|a| {
                let xi = shape::node_xi(kind, a);
                let p = evaluate(kind, xyz, xi, EvalPoint::Corner(a))?;
                Ok(strain_of(&p.g[..n], u))
            })
            .collect();
    }
    let rule = stiffness_rule(kind);
    let points = evaluate_rule(kind, xyz, &rule)?;
    let at_points: Vec<[f64; 6]> = if kind == SolidKind::Hexa8 {
        let grads = hexa_gradients(xyz, &points)?;
        let (k, llt) = hexa_extended(material.lame(), &points, &grads)?;
        let mut alpha = Mat::from_fn(HEXA_NA, 1, |i, _| {
            -(0..HEXA_NU)
                .map(|j| k[(HEXA_NU + i) * HEXA_ND + j] * u[j])
                .sum::<f64>()
        });
        llt.solve_in_place(alpha.as_mut());
        let extended: Vec<f64> = u
            .iter()
            .copied()
            .chain((0..HEXA_NA).map(|i| alpha[(i, 0)]))
            .collect();
        grads.iter().map(|g| strain_of(g, &extended)).collect()
    } else {
        points
            .iter()
            .map(|(_, p)| strain_of(&p.g[..n], u))
            .collect()
    };
    let c = corners(kind);
    if at_points.len() == 1 {
        return Ok(vec![at_points[0]; c]);
    }
    // corner values s_c from the point values: N_lin(ξ_q) s_c = s_q
    let linear = if kind == SolidKind::Tetra10 {
        SolidKind::Tetra4
    } else {
        kind
    };
    let interpolation = Mat::from_fn(c, c, |q, a| shape::shape(linear, rule[q].xi).n[a]);
    let mut values = Mat::from_fn(c, 6, |q, i| at_points[q][i]);
    interpolation
        .partial_piv_lu()
        .solve_in_place(values.as_mut());
    Ok((0..c)
        .map(|a| std::array::from_fn(|i| values[(a, i)]))
        .collect())
}
