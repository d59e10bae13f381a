//! Four- and three-node Mindlin–Reissner shells (CQUAD4, CTRIA3): MITC4 and MITC3 with a
//! Hughes–Brezzi drilling rotation, the quad with straight edges and the four incompatible
//! membrane modes of QM6 condensed with the nominal section (DESIGN.md §4).
//!
//! # Formulation
//!
//! **Geometry.** Each element is flat. A quad is projected onto its mean plane: normal
//! n = (x₃ − x₁) × (x₄ − x₂)/|…|, centre c = mean of the nodes, warp heights h_a = (x_a − c)·n
//! (±h alternately), projected nodes p_a = x_a − h_a n. The projected element is connected to
//! the grids by rigid links (MacNeal, *Finite Elements: Their Design and Performance*, 1994,
//! §9): u(p_a) = u_a + θ_a × (p_a − x_a). The links are exact rigid-body kinematics, so a
//! warped element keeps exactly six zero-energy modes; a twisted element is somewhat too soft
//! for large warp (Nastran warns above 5 %).
//!
//! **Local system.** x_m = the material direction (`material_x`, default G1→G2) projected onto
//! the element plane, y_m = n × x_m, z = n. The element is computed, and its strains reported,
//! in this material system: the isoparametric and MITC interpolations are invariant to the
//! in-plane orientation of the local axes, so the section matrices (given in material axes)
//! are used as they are. Local DOFs per node are u v w θx θy θz; the basic-system matrices
//! are Tᵀ K T with T = (rigid links)·(rotation to the material system).
//!
//! **Kinematics.** u(z) = u⁰ + z β with β = (θy, −θx); generalized strains
//! ε̂ = [εx εy γxy | κx κy κxy | γxz γyz | d] with κx = ∂θy/∂x, κy = −∂θx/∂y,
//! κxy = ∂θy/∂y − ∂θx/∂x, γxz = ∂w/∂x + θy, γyz = ∂w/∂y − θx, and the drilling residual
//! d = θz − ½(∂v/∂x − ∂u/∂y). With the section resultants of [`crate::fe::laminate`],
//!
//! ```text
//! K = Σ_gauss w·detJ · Bᵀ C B,   C = diag([[A, B], [B, D]], S, γ)      (9 × 9)
//! ```
//!
//! so K is linear in the section (for the quad B is the enhanced B̄ of "Frozen condensation"
//! below, fixed by the nominal section); the reference-plane offset (ZOFFS, Z0) is carried by the
//! section's B and D. Quads use 2 × 2 Gauss points, triangles the 3-point rule of degree 2.
//!
//! **Transverse shear (MITC).** Quads: Bathe & Dvorkin, "A formulation of general shell
//! elements — the use of mixed interpolation of tensorial components", IJNME 22 (1986)
//! 697–722. Covariant strains e_ξ = ∂w/∂ξ + β·∂x/∂ξ tied at the edge midpoints
//! A (0, 1), C (0, −1) and e_η at B (1, 0), D (−1, 0):
//! ẽ_ξ = ½(1+η)e_ξᴬ + ½(1−η)e_ξᶜ, ẽ_η = ½(1+ξ)e_ηᴮ + ½(1−ξ)e_ηᴰ, γ = J⁻¹ ẽ.
//! Triangles: MITC3 of Lee & Bathe, "Development of MITC isotropic triangular shell finite
//! elements", Comput. Struct. 82 (2004) 945–962: e_r tied at (½, 0), e_s at (0, ½), both at
//! (½, ½); ẽ_r = e_rᵗ¹ + c·s, ẽ_s = e_sᵗ² − c·r, c = e_sᵗ² − e_rᵗ¹ + e_rᵗ³ − e_sᵗ³ (constant
//! tangential shear along each edge).
//!
//! **Membrane and drilling (CQUAD4).** Every edge of the quad membrane is straight and its
//! displacement linear in the corner translations, as in Nastran's QUAD4: a support that holds
//! the translations of an edge's grids holds the edge, and edge loads applied as nodal FORCEs
//! are the consistent load, whatever the drilling rotations do (a uniform-tension patch with θz
//! free is exact, `membrane_tension_patch_with_free_drilling_rotations_is_exact`). The
//! membrane is the bilinear u, v with Taylor's incompatible modes below (QM6), strains at 2 × 2
//! Gauss points, and the drilling rotation θz enters only through the Hughes–Brezzi penalty
//! ½∫γ (θz − ω)² dA (Hughes & Brezzi, "On drilling degrees of freedom", CMAME 72 (1989)
//! 105–121), ω = ½(∂v/∂x − ∂u/∂y) the rotation of the enhanced field (bilinear + modes),
//! integrated at the same 2 × 2 points: no spurious zero-energy mode (six rigid-body modes,
//! tested flat and warped). γ = `section.drill` = A66 = G·t (`DRILL_FRACTION` = 1, see
//! [`crate::fe::laminate`]): θz is then the rotation of the membrane, which ties the rotations
//! of non-coplanar neighbours. Measured on the MacNeal–Harder beams (tests/references.rs) for
//! γ/A66 = 1, 10⁻¹, 10⁻², 10⁻³: the straight beam's in-plane shear 0.993 (rectangles) at every
//! γ, 0.952, 0.988, 0.993, 0.993 (parallelograms), 0.049–0.052 (trapezoids); the thick twisted
//! beam 0.997/1.001, 0.999/1.004, 1.028/1.028, 1.306/1.266 (loads z/y): a weak tie lets the
//! twisted facets' normal rotations go soft, so the full strength is kept. The element with
//! the modes has no assumed strains: with the modes the parasitic shear of in-plane bending is
//! gone (QM6), and the element-mean shear used without them (`PARAM,QINCOMP`) would, with the
//! modes (1 − ξ²) y_i and (1 − η²) x_i, leave zero-energy hourglass modes. The reported
//! membrane strains are the element means of the compatible field.
//!
//! Edges linear in the corner translations cost accuracy on tapered shapes: by MacNeal's
//! theorem ("A theorem regarding the locking of tapered four-noded membrane elements", IJNME 24
//! (1987) 1793–1799) such an element that passes the patch test locks in in-plane bending of
//! trapezoids (MacNeal–Harder trapezoidal beam: 0.049; MSC's QUAD4 0.173, CalculiX C3D8I
//! 0.051). Allman's edge modes, which this element used before (Ibrahimbegovic, Taylor & Wilson,
//! IJNME 30 (1990) 445–457) escape the theorem (trapezoids 0.954) only because their edges
//! bulge with the corner θz, which made a free-θz support or nodal-force edge load wrong by a
//! boundary layer of first order in h (43 % of u_x on a 3 × 2 tension patch).
//!
//! **Incompatible modes (CQUAD4).** The bilinear field cannot bend in its plane without
//! parasitic shear, nor give εy the linear variation across the depth that pure in-plane
//! bending needs. The four modes of QM6 (Taylor, Beresford & Wilson, "A non-conforming element
//! for stress analysis", IJNME 10 (1976) 1211–1219) are added: (u, v) += α₁ (1 − ξ²) x_i +
//! α₂ (1 − η²) y_i + α₃ (1 − η²) x_i + α₄ (1 − ξ²) y_i along the intrinsic axes x_i, y_i
//! (x_i along ∂x/∂ξ at the centre), with Cartesian derivatives taken from the centre Jacobian
//! J₀ and scaled by detJ₀/detJ, so that ∫B_i dA = 0 exactly (2 × 2 Gauss) on any convex quad:
//! the patch test holds, the modes are orthogonal to any constant stress (the nodal-force patch
//! above is exact with and without them), and the element means of the strains (what is
//! reported) are those of the compatible field. Their rotation enters the drilling residual, so
//! θz follows the rotation of in-plane bending. On a parallelogram the map is affine and every
//! quadratic field lies in the element space, so pure in-plane bending (u = −κxy,
//! v = κ(x² + νy²)/2, θz = κx) is exact, rectangles and parallelograms alike
//! (`fe::shell_tests::quad_in_plane_pure_bending_is_exact`). The modes carry no mass.
//!
//! **Frozen condensation.** The modes are condensed per element, α = T q with
//! T = −K_ii⁺ K_ic, K_ii = ∫B_iᵀ C B_i dA, K_ic = ∫B_iᵀ C B dA (K_ii⁺: pseudo-inverse, zero for a
//! section without membrane stiffness). K_cc − K_ci K_ii⁻¹ K_ic is not linear in the section,
//! and every element must give affine parts K = Σ f_i(p) K_i (DESIGN.md §5). So T is computed
//! once, from the element's *nominal* section (the deck's, i.e. the parts at the nominal
//! parameter values; an explicit argument of [`quad4_stiffness`], [`affine_stiffness`] and
//! [`affine_stiffness_at_points`]), and every part uses the enhanced operator B̄ = B + B_i T:
//! K_i = ∫B̄ᵀ C_i B̄ dA. K is then exactly affine; at the nominal section it is the exactly
//! condensed element; T does not change when the section is scaled, so E parameters stay
//! exact at any E; for ν, Θ and ply thickness away from the nominal values only the
//! condensation is frozen, and since the condensed energy is the minimum over α,
//! K_frozen − K_condensed is positive semi-definite and of second order in the change of the
//! section (`frozen_condensation_is_exact_under_scaling_and_second_order_otherwise`: ν 0.3 →
//! 0.2 changes K by 2.3e-3 of its largest entry, 0.3 → 0.25 by 5.7e-4). C is the full section:
//! the modes only strain the reference plane and rotate it, so K_ii involves A and the drilling
//! modulus (a fixed multiple of A66) only, while K_ic also takes the coupling B (offsets,
//! unsymmetric laminates) — the condensation of the element's own energy, in which a curvature
//! of an offset shell strains the reference plane, rather than of its membrane part alone.
//!
//! **`PARAM,QINCOMP`.** The modes are a user choice ([`Incompatible`]): `YES` (default)
//! condenses them as above; `NO` leaves them out, so K(section) depends on the section alone
//! and a pROM with ν, Θ or ply-thickness parameters agrees to round-off with a deck rebuilt at
//! any parameter value. The bilinear membrane then takes two B̄-type corrections in place of
//! the modes: the in-plane shear is an assumed strain — in the intrinsic axes εxx and εyy are
//! taken at the Gauss points and γxy is the element mean (1/A)∫γxy dA, which removes the
//! parasitic shear of in-plane bending and keeps ∫Bᵀσ dA exact for constant σ — and the
//! drilling residual is θz − ω* with ω* = ω + (ω − ω̄) (ω̄ the element mean): the hourglass
//! rotation of the bilinear field is half the rotation of the bending it stands for (on a
//! rectangle u = −κxy has ω = κx/2 about the centre, the bending rotation is κx), and with ω
//! itself the penalty locks in-plane bending (MacNeal–Harder rectangular beam 0.285 against
//! 0.904). Constant strains and rigid rotations are unchanged. The element is then exact for
//! the rectangle's pure bending but for the Poisson term (εy cannot vary across the depth: too
//! stiff by 1/(1 − ν²), rectangular beam 0.904) and locks on parallelograms (0.033) and
//! trapezoids (0.065).
//!
//! **Membrane and drilling (CTRIA3).** Linear u, v (constant strain) with the same penalty at
//! γ = `TRIA_DRILL_SCALE`·`section.drill` = 10⁻³·A66, integrated at the 3 points. The Allman
//! triangle (edge modes 4 L_i L_j on the same construction) was tried and left out: with any
//! γ from 10⁻³·A66 to A66 it locks in the thin MacNeal–Harder twisted beam (0.02 of the
//! reference against 0.72 for this element), and the constant-strain triangle with γ = A66
//! locks there too (0.01).
//!
//! **Mass.** Per unit area, from ∫ρ|u⁰ + zβ|² dz: ρt on u, v, w; ρi on θx, θy; ρs coupling
//! u–θy (+) and v–θx (−); nothing on θz. Consistent: ∫ N_a N_b dA; lumped: area/nodes at each
//! node (translation, rotary inertia and offset coupling). Both go through the same T.

use faer::Mat;

use crate::geometry::vec3::{cross, dot, norm, scale, sub};

use super::affine::{AffineMatrix, Coefficient};
use super::laminate::{ShellMass, ShellSection};

/// The CQUAD4's incompatible membrane modes (module doc, "Incompatible modes", "Frozen
/// condensation"; `PARAM,QINCOMP`). Triangles have none and ignore it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Incompatible<S> {
    /// Condensed with the nominal section(s) `S`, the deck's (`PARAM,QINCOMP,YES`, the default):
    /// in-plane bending exact on rectangles; K is affine in the section, but for a section away
    /// from the nominal one only the condensation is frozen.
    Condensed(S),
    /// Left out (`PARAM,QINCOMP,NO`): the plain membrane, too stiff in in-plane bending by
    /// ≈ 1/(1 − ν²), and K(section) independent of any nominal section.
    Off,
}

impl<S> Incompatible<S> {
    /// The nominal section(s), `None` when the modes are off.
    fn nominal(self) -> Option<S> {
        match self {
            Incompatible::Condensed(s) => Some(s),
            Incompatible::Off => None,
        }
    }
}

/// True when the condensation of the CQUAD4's incompatible modes, computed once with `nominal`,
/// is frozen, i.e. differs from the one of Σ f_i(p) section_i at some p (module doc, "Frozen
/// condensation"). T depends on the section only through its reference-plane blocks (A, B) and
/// is the same for any non-zero multiple of them, so it is exact at every p when every part's
/// (A, B) is a multiple of the nominal (A, B) (an E parameter; TPLY on a laminate without
/// membrane–bending coupling, whose B parts are zero; a density), to round-off: the residual of
/// the projection on the nominal blocks at most 10⁻¹⁰ of the part's largest entry.
pub fn condensation_is_frozen(
    parts: &[(Coefficient, ShellSection)],
    nominal: &ShellSection,
) -> bool {
    let blocks =
        |s: &ShellSection| -> Vec<f64> { s.a.iter().chain(&s.b).flatten().copied().collect() };
    let n = blocks(nominal);
    let nn: f64 = n.iter().map(|x| x * x).sum();
    parts.iter().any(|(_, part)| {
        let v = blocks(part);
        let c = if nn > 0.0 {
            v.iter().zip(&n).map(|(x, y)| x * y).sum::<f64>() / nn
        } else {
            0.0
        };
        let largest = v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        v.iter()
            .zip(&n)
            .any(|(x, y)| (x - c * y).abs() > 1e-10 * largest)
    })
}

/// Errors of shell element geometry.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ShellError {
    /// The element has no area (coincident or collinear grids).
    #[error("{shape} has zero area (coincident or collinear grids)")]
    ZeroArea {
        /// "CQUAD4" or "CTRIA3".
        shape: &'static str,
    },
    /// The projected quad is not convex at a corner (or three grids are collinear there).
    #[error("CQUAD4 is not convex at its grid {corner} (1-based; interior angle ≥ 180°)")]
    NotConvex {
        /// 1-based position of the grid in the element connectivity.
        corner: usize,
    },
    /// The material x direction is (nearly) normal to the element.
    #[error("material x direction {direction:?} is normal to the element plane")]
    MaterialAxisNormal {
        /// The direction given.
        direction: [f64; 3],
    },
    /// A matrix was asked for a node count other than 3, 4, 6 or 8.
    #[error("a shell element has 3, 4, 6 or 8 grids, got {0}")]
    NodeCount(usize),
    /// The curved surface of a quadratic element folds over (its Jacobian changes sign), at a
    /// grid or between them: a mid-side grid too far from its edge's middle.
    #[error("{shape} is too distorted: its surface folds over{}", .grid.map_or(" inside the element".to_string(), |g| format!(" at its grid {g} (1-based)")))]
    Distorted {
        /// "CQUAD8" or "CTRIA6".
        shape: &'static str,
        /// 1-based position of the grid in the connectivity, `None` inside the element.
        grid: Option<usize>,
    },
    /// Per-point sections do not match the element's integration points.
    #[error(
        "expected one section and one nominal section per integration point ({expected}), with the same affine coefficients at each; got {got}"
    )]
    PointCount { expected: usize, got: usize },
}

/// Centroid strains of a shell element in its material system (x_m, y_m, n).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShellStrains {
    /// Reference-plane membrane strains [εx, εy, γxy].
    pub membrane: [f64; 3],
    /// Curvatures [κx, κy, κxy] (ε(z) = ε⁰ + z κ).
    pub curvature: [f64; 3],
    /// Strains at z_top: [εx, εy, γxy].
    pub top: [f64; 3],
    /// Strains at z_bot.
    pub bottom: [f64; 3],
    /// Transverse shear [γxz, γyz] (assumed MITC field at the centroid).
    pub shear: [f64; 2],
    /// The material system the strains are in: unit vectors x_m, y_m, n (basic).
    pub axes: [V3; 3],
}

type V3 = [f64; 3];

/// CTRIA3 drilling modulus as a fraction of `section.drill` (= A66): the triangle keeps the
/// linear (CST) membrane with a weak Hughes–Brezzi tie, γ = 10⁻³·A66 (module doc, "Membrane
/// and drilling (CTRIA3)").
const TRIA_DRILL_SCALE: f64 = 1.0e-3;

/// Number of generalized strains: 3 membrane, 3 curvature, 2 shear, 1 drilling.
const NSTRAIN: usize = 9;

/// One integration point: weight × detJ, shape-function values, strain operator B (9 × 6n),
/// the incompatible-mode operator B_i (9 × 4 on quads, membrane and drilling rows; 9 × 0 on
/// triangles) and, on quads, the hourglass rotation ω − ω̄ of the compatible field (a row over
/// the 24 local DOFs; empty on triangles).
struct GaussPoint {
    wdet: f64,
    shape: [f64; 4],
    b: Mat<f64>,
    bi: Mat<f64>,
    hourglass_rotation: Vec<f64>,
}

/// A flat element on its projected geometry, ready for any section.
struct Flat {
    nodes: usize,
    /// Basic DOFs → local DOFs of the projected element (6n × 6n).
    t: Mat<f64>,
    area: f64,
    points: Vec<GaussPoint>,
    /// Strain operator at the centroid.
    centroid: Mat<f64>,
    /// Material axes x_m, y_m, n (basic).
    axes: [V3; 3],
}

/// Local frame: rows e1 = x_m, e2 = y_m, e3 = n; and the in-plane coordinates and warp heights.
struct Frame {
    axes: [V3; 3],
    xy: Vec<[f64; 2]>,
    warp: Vec<f64>,
}

fn frame(xyz: &[V3], normal: V3, material_x: Option<V3>) -> Result<Frame, ShellError> {
    let n = scale(normal, 1.0 / norm(normal));
    let k = xyz.len() as f64;
    let c = xyz.iter().fold([0.0; 3], |s, p| {
        [s[0] + p[0] / k, s[1] + p[1] / k, s[2] + p[2] / k]
    });
    let mx = material_x.unwrap_or_else(|| sub(xyz[1], xyz[0]));
    let proj = sub(mx, scale(n, dot(mx, n)));
    if norm(proj) <= 1e-8 * norm(mx) {
        return Err(ShellError::MaterialAxisNormal { direction: mx });
    }
    let e1 = scale(proj, 1.0 / norm(proj));
    let e2 = cross(n, e1);
    let warp: Vec<f64> = xyz.iter().map(|p| dot(sub(*p, c), n)).collect();
    let xy = xyz
        .iter()
        .map(|p| [dot(sub(*p, c), e1), dot(sub(*p, c), e2)])
        .collect();
    Ok(Frame {
        axes: [e1, e2, n],
        xy,
        warp,
    })
}

/// T = (rigid links) · blockdiag(R, R) per node; R has rows e1, e2, n. The link from grid a
/// to its projection p_a = x_a − h_a n gives u_p = u − h θy, v_p = v + h θx (local axes).
fn transformation(f: &Frame) -> Mat<f64> {
    let nn = f.xy.len();
    let mut t = Mat::<f64>::zeros(6 * nn, 6 * nn);
    for a in 0..nn {
        for blk in 0..2 {
            for i in 0..3 {
                for j in 0..3 {
                    t[(6 * a + 3 * blk + i, 6 * a + 3 * blk + j)] = f.axes[i][j];
                }
            }
        }
        let h = f.warp[a];
        for j in 0..3 {
            // row u += −h · (θy row), row v += +h · (θx row)
            t[(6 * a, 6 * a + 3 + j)] -= h * f.axes[1][j];
            t[(6 * a + 1, 6 * a + 3 + j)] += h * f.axes[0][j];
        }
    }
    t
}

/// Quad natural coordinates of the nodes.
const QUAD_NODES: [[f64; 2]; 4] = [[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]];

/// 1/√3, the 2-point Gauss abscissa.
const GAUSS_2: f64 = 0.577_350_269_189_625_8;

/// 2 × 2 Gauss points (ξ, η) of the quad.
const QUAD_GAUSS: [[f64; 2]; 4] = [
    [-GAUSS_2, -GAUSS_2],
    [GAUSS_2, -GAUSS_2],
    [GAUSS_2, GAUSS_2],
    [-GAUSS_2, GAUSS_2],
];

/// The triangle's 3-point rule of degree 2 (r, s), weights 1/6.
const TRIA_POINTS: [[f64; 2]; 3] = [
    [1.0 / 6.0, 1.0 / 6.0],
    [2.0 / 3.0, 1.0 / 6.0],
    [1.0 / 6.0, 2.0 / 3.0],
];

/// Bilinear shape functions and their natural derivatives at (ξ, η).
fn quad_shape(xi: f64, eta: f64) -> ([f64; 4], [f64; 4], [f64; 4]) {
    let mut n = [0.0; 4];
    let mut dxi = [0.0; 4];
    let mut deta = [0.0; 4];
    for (a, [xa, ea]) in QUAD_NODES.iter().enumerate() {
        n[a] = 0.25 * (1.0 + xa * xi) * (1.0 + ea * eta);
        dxi[a] = 0.25 * xa * (1.0 + ea * eta);
        deta[a] = 0.25 * ea * (1.0 + xa * xi);
    }
    (n, dxi, deta)
}

/// J = [[x_ξ, y_ξ], [x_η, y_η]].
fn jacobian(xy: &[[f64; 2]], dr: &[f64], ds: &[f64]) -> [[f64; 2]; 2] {
    let mut j = [[0.0; 2]; 2];
    for a in 0..xy.len() {
        for k in 0..2 {
            j[0][k] += dr[a] * xy[a][k];
            j[1][k] += ds[a] * xy[a][k];
        }
    }
    j
}

fn inverse(j: &[[f64; 2]; 2]) -> ([[f64; 2]; 2], f64) {
    let det = j[0][0] * j[1][1] - j[0][1] * j[1][0];
    (
        [
            [j[1][1] / det, -j[0][1] / det],
            [-j[1][0] / det, j[0][0] / det],
        ],
        det,
    )
}

/// Covariant transverse shear e = ∂w/∂r + β·∂x/∂r along the natural direction whose shape
/// derivatives are `dr` and tangent (x_r, y_r) = `tangent`, at a point with shape values `n`;
/// β = (θy, −θx). Returned as a row over the 6n local DOFs.
fn covariant_shear(n: &[f64], dr: &[f64], tangent: [f64; 2]) -> Vec<f64> {
    let mut row = vec![0.0; 6 * n.len()];
    for a in 0..n.len() {
        row[6 * a + 2] = dr[a];
        row[6 * a + 4] = n[a] * tangent[0];
        row[6 * a + 3] = -n[a] * tangent[1];
    }
    row
}

/// Membrane, bending and drilling rows (0–5, 8) of B from shape values and Cartesian
/// derivatives.
fn fill_standard_rows(b: &mut Mat<f64>, n: &[f64], nx: &[f64], ny: &[f64]) {
    for a in 0..n.len() {
        let (u, v, tx, ty, tz) = (6 * a, 6 * a + 1, 6 * a + 3, 6 * a + 4, 6 * a + 5);
        b[(0, u)] = nx[a];
        b[(1, v)] = ny[a];
        b[(2, u)] = ny[a];
        b[(2, v)] = nx[a];
        b[(3, ty)] = nx[a];
        b[(4, tx)] = -ny[a];
        b[(5, ty)] = ny[a];
        b[(5, tx)] = -nx[a];
        b[(8, tz)] = n[a];
        b[(8, v)] = -0.5 * nx[a];
        b[(8, u)] = 0.5 * ny[a];
    }
}

/// Cartesian derivatives (∂/∂x, ∂/∂y) of functions with natural derivatives `dr`, `ds`.
fn cartesian(jinv: &[[f64; 2]; 2], dr: &[f64], ds: &[f64]) -> (Vec<f64>, Vec<f64>) {
    let nx = (0..dr.len())
        .map(|a| jinv[0][0] * dr[a] + jinv[0][1] * ds[a])
        .collect();
    let ny = (0..dr.len())
        .map(|a| jinv[1][0] * dr[a] + jinv[1][1] * ds[a])
        .collect();
    (nx, ny)
}

/// Shear rows 6, 7 of B: γ = J⁻¹ [ẽ_r, ẽ_s].
fn fill_shear_rows(b: &mut Mat<f64>, jinv: &[[f64; 2]; 2], er: &[f64], es: &[f64]) {
    for c in 0..er.len() {
        b[(6, c)] = jinv[0][0] * er[c] + jinv[0][1] * es[c];
        b[(7, c)] = jinv[1][0] * er[c] + jinv[1][1] * es[c];
    }
}

/// MITC4 strain operator (9 × 24) and detJ at (ξ, η) (Bathe–Dvorkin 1986 tying, module doc).
fn mitc4_operator(xy: &[[f64; 2]], xi: f64, eta: f64) -> (Mat<f64>, f64) {
    let (n, dxi, deta) = quad_shape(xi, eta);
    let (jinv, det) = inverse(&jacobian(xy, &dxi, &deta));
    let (nx, ny) = cartesian(&jinv, &dxi, &deta);
    let mut b = Mat::<f64>::zeros(NSTRAIN, 24);
    fill_standard_rows(&mut b, &n, &nx, &ny);
    let tied = |txi: f64, teta: f64, along_xi: bool| {
        let (tn, txd, ted) = quad_shape(txi, teta);
        let j = jacobian(xy, &txd, &ted);
        if along_xi {
            covariant_shear(&tn, &txd, j[0])
        } else {
            covariant_shear(&tn, &ted, j[1])
        }
    };
    let (ea, ec) = (tied(0.0, 1.0, true), tied(0.0, -1.0, true));
    let (eb, ed) = (tied(1.0, 0.0, false), tied(-1.0, 0.0, false));
    let exi: Vec<f64> = (0..24)
        .map(|c| 0.5 * (1.0 + eta) * ea[c] + 0.5 * (1.0 - eta) * ec[c])
        .collect();
    let eeta: Vec<f64> = (0..24)
        .map(|c| 0.5 * (1.0 + xi) * eb[c] + 0.5 * (1.0 - xi) * ed[c])
        .collect();
    fill_shear_rows(&mut b, &jinv, &exi, &eeta);
    (b, det)
}

/// Number of incompatible membrane modes of the quad (module doc, "Incompatible modes").
const INCOMPATIBLE: usize = 4;

/// Operator (9 × 4: membrane rows 0–2 and drilling row 8) at (ξ, η) of the four incompatible
/// modes (1 − ξ²)·x_i, (1 − η²)·y_i, (1 − η²)·x_i, (1 − ξ²)·y_i, x_i = (cos φ, sin φ) and
/// y_i = (−sin φ, cos φ) the intrinsic axes, with Taylor's correction: Cartesian derivatives
/// from the centre Jacobian J₀, scaled by detJ₀/detJ, so that
/// ∫B_i dA = detJ₀ J₀⁻¹ Σ_gauss w ∂N/∂(ξ, η) = 0 (module doc). Row 8 is −ω of the mode,
/// ω = ½(∂v/∂x − ∂u/∂y): the modes' rotation enters the drilling residual.
fn incompatible_operator(xy: &[[f64; 2]], xi: f64, eta: f64, phi: f64) -> Mat<f64> {
    let (_, dxi, deta) = quad_shape(xi, eta);
    let det = inverse(&jacobian(xy, &dxi, &deta)).1;
    let (_, dxi0, deta0) = quad_shape(0.0, 0.0);
    let (j0inv, det0) = inverse(&jacobian(xy, &dxi0, &deta0));
    // Cartesian gradients of the bubbles 1 − ξ² (index 0) and 1 − η² (index 1)
    let (mx, my) = cartesian(&j0inv, &[-2.0 * xi, 0.0], &[0.0, -2.0 * eta]);
    let (s, c) = phi.sin_cos();
    let directions = [[c, s], [-s, c]];
    let taylor = det0 / det;
    // (bubble, direction) of each mode
    let modes = [(0, 0), (1, 1), (1, 0), (0, 1)];
    let mut b = Mat::<f64>::zeros(NSTRAIN, INCOMPATIBLE);
    for (k, (bubble, direction)) in modes.into_iter().enumerate() {
        let [ux, uy] = directions[direction];
        let (gx, gy) = (taylor * mx[bubble], taylor * my[bubble]);
        b[(0, k)] = gx * ux;
        b[(1, k)] = gy * uy;
        b[(2, k)] = gy * ux + gx * uy;
        b[(8, k)] = -0.5 * (gx * uy - gy * ux);
    }
    b
}

/// Moore–Penrose inverse of a symmetric positive semi-definite matrix (eigenvalues below
/// 10⁻¹² of the largest count as zero).
fn pseudo_inverse(k: &Mat<f64>) -> Mat<f64> {
    let n = k.nrows();
    let mut inv = Mat::<f64>::zeros(n, n);
    if n == 0 {
        return inv;
    }
    let Ok(evd) = k.self_adjoint_eigen(faer::Side::Lower) else {
        return inv;
    };
    let (u, values) = (evd.U(), evd.S().column_vector());
    let largest = (0..n).fold(0.0f64, |m, i| m.max(values[i].abs()));
    for l in 0..n {
        if largest > 0.0 && values[l] > 1e-12 * largest {
            for i in 0..n {
                for j in 0..n {
                    inv[(i, j)] += u[(i, l)] * u[(j, l)] / values[l];
                }
            }
        }
    }
    inv
}

/// MITC3 strain operator (9 × 18) at (r, s) (Lee–Bathe 2004 tying, module doc); detJ is
/// constant (twice the area).
fn mitc3_operator(xy: &[[f64; 2]], r: f64, s: f64) -> (Mat<f64>, f64) {
    let n = [1.0 - r - s, r, s];
    let (dr, ds) = ([-1.0, 1.0, 0.0], [-1.0, 0.0, 1.0]);
    let j = jacobian(xy, &dr, &ds);
    let (jinv, det) = inverse(&j);
    let (nx, ny) = cartesian(&jinv, &dr, &ds);
    let mut b = Mat::<f64>::zeros(NSTRAIN, 18);
    fill_standard_rows(&mut b, &n, &nx, &ny);
    let at = |r: f64, s: f64| [1.0 - r - s, r, s];
    let er1 = covariant_shear(&at(0.5, 0.0), &dr, j[0]);
    let es2 = covariant_shear(&at(0.0, 0.5), &ds, j[1]);
    let er3 = covariant_shear(&at(0.5, 0.5), &dr, j[0]);
    let es3 = covariant_shear(&at(0.5, 0.5), &ds, j[1]);
    let c: Vec<f64> = (0..18).map(|k| es2[k] - er1[k] + er3[k] - es3[k]).collect();
    let er: Vec<f64> = (0..18).map(|k| er1[k] + c[k] * s).collect();
    let es: Vec<f64> = (0..18).map(|k| es2[k] - c[k] * r).collect();
    fill_shear_rows(&mut b, &jinv, &er, &es);
    (b, det)
}

/// Engineering-strain rotation T_ε(φ): strains [εx, εy, γxy] of a frame → those of the frame
/// rotated by φ about the normal.
pub(crate) fn strain_rotation(phi: f64) -> [[f64; 3]; 3] {
    let (s, c) = phi.sin_cos();
    [
        [c * c, s * s, c * s],
        [s * s, c * c, -c * s],
        [-2.0 * c * s, 2.0 * c * s, c * c - s * s],
    ]
}

/// The membrane of the quad without incompatible modes (module doc, `PARAM,QINCOMP`), applied
/// to the compatible operators B of the points: (1) assumed shear: in the element's intrinsic
/// axes (x_i along ∂x/∂ξ at the centre, at angle φ from the local x), εxx and εyy are taken at
/// the point and γxy is the element mean,
/// B̃_m = T_ε(−φ) [diag(1,1,0) T_ε(φ) B_m + diag(0,0,1) T_ε(φ) B̄_m], B̄_m = (1/A)∫B_m dA;
/// (2) the drilling residual θz − ω* with ω* = ω + (ω − ω̄), ω the rotation of the bilinear
/// field (row 8 = θz − ω), ω̄ its element mean. Constant strain states and rigid rotations are
/// unchanged, ∫B̃ᵀσ dA = ∫Bᵀσ dA for constant σ (patch test), the parasitic shear of in-plane
/// bending is removed and ω* is the rotation of pure bending on a rectangle (module doc).
fn assume_membrane_shear_and_rotation(
    points: &mut [GaussPoint],
    mean: &Mat<f64>,
    area: f64,
    phi: f64,
) {
    let rotation = |p: &GaussPoint| -> Vec<f64> {
        (0..24)
            .map(|c| if c % 6 == 5 { p.shape[c / 6] } else { 0.0 } - p.b[(8, c)])
            .collect()
    };
    let mut mean_rotation = [0.0; 24];
    for p in points.iter() {
        for (m, w) in mean_rotation.iter_mut().zip(rotation(p)) {
            *m += w * p.wdet / area;
        }
    }
    let (t, back) = (strain_rotation(phi), strain_rotation(-phi));
    for p in points.iter_mut() {
        let omega = rotation(p);
        let b = &mut p.b;
        for c in 0..24 {
            b[(8, c)] -= omega[c] - mean_rotation[c];
            let m: [f64; 3] = std::array::from_fn(|i| (0..3).map(|k| t[i][k] * b[(k, c)]).sum());
            let mc: f64 = (0..3).map(|k| t[2][k] * mean[(k, c)]).sum();
            let assumed = [m[0], m[1], mc];
            for i in 0..3 {
                b[(i, c)] = (0..3).map(|k| back[i][k] * assumed[k]).sum();
            }
        }
    }
}

/// Characteristic squared size (largest squared edge) for relative tolerances.
fn size2(xyz: &[V3]) -> f64 {
    (0..xyz.len())
        .map(|a| {
            dot(
                sub(xyz[(a + 1) % xyz.len()], xyz[a]),
                sub(xyz[(a + 1) % xyz.len()], xyz[a]),
            )
        })
        .fold(0.0, f64::max)
}

impl Flat {
    /// The projected quad; `modes`: whether its stiffness will condense the incompatible modes,
    /// which selects the membrane (module doc, "Membrane and drilling (CQUAD4)").
    fn quad(xyz: &[V3; 4], material_x: Option<V3>, modes: bool) -> Result<Self, ShellError> {
        let normal = cross(sub(xyz[2], xyz[0]), sub(xyz[3], xyz[1]));
        let area = 0.5 * norm(normal);
        if area.is_nan() || area <= 1e-10 * size2(xyz) {
            return Err(ShellError::ZeroArea { shape: "CQUAD4" });
        }
        let f = frame(xyz, normal, material_x)?;
        for (a, [xa, ea]) in QUAD_NODES.iter().enumerate() {
            let (_, dxi, deta) = quad_shape(*xa, *ea);
            let det = inverse(&jacobian(&f.xy, &dxi, &deta)).1;
            if det.is_nan() || det <= 1e-8 * area {
                return Err(ShellError::NotConvex { corner: a + 1 });
            }
        }
        let centroid = mitc4_operator(&f.xy, 0.0, 0.0).0;
        let (_, dxi, _) = quad_shape(0.0, 0.0);
        let tangent = (0..4).fold([0.0; 2], |t, a| {
            [t[0] + dxi[a] * f.xy[a][0], t[1] + dxi[a] * f.xy[a][1]]
        });
        let phi = tangent[1].atan2(tangent[0]);
        let mut points: Vec<GaussPoint> = QUAD_GAUSS
            .iter()
            .map(|&[xi, eta]| {
                let (b, det) = mitc4_operator(&f.xy, xi, eta);
                GaussPoint {
                    wdet: det,
                    shape: quad_shape(xi, eta).0,
                    b,
                    bi: incompatible_operator(&f.xy, xi, eta, phi),
                    hourglass_rotation: Vec::new(),
                }
            })
            .collect();
        let mut mean = Mat::<f64>::zeros(NSTRAIN, 24);
        for p in &points {
            mean += &p.b * faer::Scale(p.wdet / area);
        }
        if !modes {
            assume_membrane_shear_and_rotation(&mut points, &mean, area, phi);
        }
        // Reported membrane strains: the element mean, which the assumed field shares.
        let mut centroid = centroid;
        for r in 0..3 {
            for c in 0..24 {
                centroid[(r, c)] = mean[(r, c)];
            }
        }
        Ok(Flat {
            nodes: 4,
            t: transformation(&f),
            area,
            points,
            centroid,
            axes: f.axes,
        })
    }

    fn tria(xyz: &[V3; 3], material_x: Option<V3>) -> Result<Self, ShellError> {
        let normal = cross(sub(xyz[1], xyz[0]), sub(xyz[2], xyz[0]));
        let area = 0.5 * norm(normal);
        if area.is_nan() || area <= 1e-10 * size2(xyz) {
            return Err(ShellError::ZeroArea { shape: "CTRIA3" });
        }
        let f = frame(xyz, normal, material_x)?;
        let points = TRIA_POINTS
            .iter()
            .map(|&[r, s]| {
                let (b, det) = mitc3_operator(&f.xy, r, s);
                GaussPoint {
                    wdet: det / 6.0,
                    shape: [1.0 - r - s, r, s, 0.0],
                    b,
                    bi: Mat::zeros(NSTRAIN, 0),
                    hourglass_rotation: Vec::new(),
                }
            })
            .collect();
        let centroid = mitc3_operator(&f.xy, 1.0 / 3.0, 1.0 / 3.0).0;
        Ok(Flat {
            nodes: 3,
            t: transformation(&f),
            area,
            points,
            centroid,
            axes: f.axes,
        })
    }

    /// A quad ([`Flat::quad`], `modes` as there) or a triangle (`modes` ignored).
    fn new(xyz: &[V3], material_x: Option<V3>, modes: bool) -> Result<Self, ShellError> {
        match xyz.len() {
            4 => Self::quad(&[xyz[0], xyz[1], xyz[2], xyz[3]], material_x, modes),
            3 => Self::tria(&[xyz[0], xyz[1], xyz[2]], material_x),
            n => Err(ShellError::NodeCount(n)),
        }
    }

    /// Tᵀ (Σ w detJ B̄ᵀ C B̄) T in the basic system, the incompatible modes condensed with the
    /// section `nominal`, or left out when `None` ([`Flat::stiffness_at_points`]).
    fn stiffness(&self, section: &ShellSection, nominal: Option<&ShellSection>) -> Mat<f64> {
        let n = self.points.len();
        let nominal = nominal.map(|s| vec![s; n]);
        self.stiffness_at_points(&vec![section; n], nominal.as_deref())
    }

    /// C of a section at this element's points: [`constitutive`], with the triangle's weak
    /// drilling modulus.
    fn constitutive(&self, section: &ShellSection) -> Mat<f64> {
        let mut c = constitutive(section);
        if self.nodes == 3 {
            c[(8, 8)] *= TRIA_DRILL_SCALE;
        }
        c
    }

    /// Frozen condensation of the incompatible modes (module doc): T = −K_ii⁺ K_ic with
    /// K_ii = Σₚ wₚ B_iᵀ C B_i and K_ic = Σₚ wₚ B_iᵀ C B from the sections `nominal` (one per
    /// point), so that α = T q. Empty (0 × 6n) for triangles; zero when the modes are off
    /// (`nominal` = `None`: α = 0, B̄ = B exactly).
    fn condensation(&self, nominal: Option<&[&ShellSection]>) -> Mat<f64> {
        let n = 6 * self.nodes;
        let modes = self.points.first().map_or(0, |p| p.bi.ncols());
        let Some(nominal) = nominal.filter(|_| modes > 0) else {
            return Mat::zeros(modes, n);
        };
        let mut kii = Mat::<f64>::zeros(modes, modes);
        let mut kic = Mat::<f64>::zeros(modes, n);
        for (p, section) in self.points.iter().zip(nominal) {
            let cbi = self.constitutive(section) * &p.bi;
            kii += cbi.transpose() * &p.bi * faer::Scale(p.wdet);
            kic += cbi.transpose() * &p.b * faer::Scale(p.wdet);
        }
        -(pseudo_inverse(&kii) * &kic)
    }

    /// Tᵀ (Σₚ wₚ detJₚ B̄ₚᵀ C(sectionₚ) B̄ₚ) T: one section per integration point, B̄ = B + B_i T
    /// with the condensation T of the sections `nominal` (one per point; `None`: T = 0), so the
    /// matrix is linear in `sections`.
    fn stiffness_at_points(
        &self,
        sections: &[&ShellSection],
        nominal: Option<&[&ShellSection]>,
    ) -> Mat<f64> {
        let n = 6 * self.nodes;
        let t = self.condensation(nominal);
        let mut k = Mat::<f64>::zeros(n, n);
        for (p, section) in self.points.iter().zip(sections) {
            let mut b = &p.b + &p.bi * &t;
            if nominal.is_none() {
                // without the modes, the drilling residual takes ω* = ω + (ω − ω̄) (module doc)
                for (c, w) in p.hourglass_rotation.iter().enumerate() {
                    b[(8, c)] -= w;
                }
            }
            let cb = self.constitutive(section) * &b;
            k += b.transpose() * &cb * faer::Scale(p.wdet);
        }
        self.to_basic(&k)
    }

    fn mass(&self, m: &ShellMass, lumped: bool) -> Mat<f64> {
        let rho = mass_density(m);
        let n = 6 * self.nodes;
        let mut out = Mat::<f64>::zeros(n, n);
        let mut add = |a: usize, b: usize, f: f64| {
            for i in 0..6 {
                for j in 0..6 {
                    out[(6 * a + i, 6 * b + j)] += f * rho[i][j];
                }
            }
        };
        if lumped {
            for a in 0..self.nodes {
                add(a, a, self.area / self.nodes as f64);
            }
        } else {
            for p in &self.points {
                for a in 0..self.nodes {
                    for b in 0..self.nodes {
                        add(a, b, p.wdet * p.shape[a] * p.shape[b]);
                    }
                }
            }
        }
        self.to_basic(&out)
    }

    fn to_basic(&self, local: &Mat<f64>) -> Mat<f64> {
        let kt = local * &self.t;
        let mut k = self.t.transpose() * &kt;
        // Exact symmetry (the products above are symmetric only to round-off).
        for i in 0..k.nrows() {
            for j in 0..i {
                let v = 0.5 * (k[(i, j)] + k[(j, i)]);
                k[(i, j)] = v;
                k[(j, i)] = v;
            }
        }
        k
    }

    fn strains(&self, z: (f64, f64), u: &[f64]) -> ShellStrains {
        let n = 6 * self.nodes;
        let ul: Vec<f64> = (0..n)
            .map(|i| (0..n).map(|j| self.t[(i, j)] * u[j]).sum())
            .collect();
        let e: Vec<f64> = (0..NSTRAIN)
            .map(|r| (0..n).map(|c| self.centroid[(r, c)] * ul[c]).sum())
            .collect();
        let membrane = [e[0], e[1], e[2]];
        let curvature = [e[3], e[4], e[5]];
        let at = |z: f64| std::array::from_fn(|i| membrane[i] + z * curvature[i]);
        ShellStrains {
            membrane,
            curvature,
            top: at(z.0),
            bottom: at(z.1),
            shear: [e[6], e[7]],
            axes: self.axes,
        }
    }
}

/// C = diag([[A, B], [B, D]], S, γ) (9 × 9), the generalized-strain constitutive matrix.
pub(crate) fn constitutive(s: &ShellSection) -> Mat<f64> {
    let mut c = Mat::<f64>::zeros(NSTRAIN, NSTRAIN);
    for i in 0..3 {
        for j in 0..3 {
            c[(i, j)] = s.a[i][j];
            c[(i, 3 + j)] = s.b[i][j];
            c[(3 + i, j)] = s.b[j][i];
            c[(3 + i, 3 + j)] = s.d[i][j];
        }
    }
    for i in 0..2 {
        for j in 0..2 {
            c[(6 + i, 6 + j)] = s.s[i][j];
        }
    }
    c[(8, 8)] = s.drill;
    c
}

/// Mass density per area over local DOFs u v w θx θy θz (module doc).
fn mass_density(m: &ShellMass) -> [[f64; 6]; 6] {
    let mut r = [[0.0; 6]; 6];
    for (i, row) in r.iter_mut().enumerate().take(3) {
        row[i] = m.rho_t;
    }
    r[3][3] = m.rho_i;
    r[4][4] = m.rho_i;
    r[0][4] = m.rho_s;
    r[4][0] = m.rho_s;
    r[1][3] = -m.rho_s;
    r[3][1] = -m.rho_s;
    r
}

/// CQUAD4 stiffness (24 × 24, basic system), MITC4 with the straight-edged drilling membrane and,
/// with [`Incompatible::Condensed`], incompatible membrane modes condensed with that nominal
/// section (module doc, "frozen condensation"); linear in `section`. `Condensed(section)`
/// gives the element with its modes condensed exactly; the affine parts of a parametrized
/// section pass the deck's section. `material_x`: direction of the material x axis (projected
/// onto the element), default G1→G2.
pub fn quad4_stiffness(
    xyz: &[V3; 4],
    section: &ShellSection,
    modes: Incompatible<&ShellSection>,
    material_x: Option<V3>,
) -> Result<Mat<f64>, ShellError> {
    let nominal = modes.nominal();
    Ok(Flat::quad(xyz, material_x, nominal.is_some())?.stiffness(section, nominal))
}

/// CTRIA3 stiffness (18 × 18, basic system), MITC3 with drilling; linear in `section`.
pub fn tria3_stiffness(
    xyz: &[V3; 3],
    section: &ShellSection,
    material_x: Option<V3>,
) -> Result<Mat<f64>, ShellError> {
    Ok(Flat::tria(xyz, material_x)?.stiffness(section, None))
}

/// CQUAD4 mass (24 × 24, basic): consistent (bilinear, 2 × 2 Gauss, exact) or lumped.
pub fn quad4_mass(xyz: &[V3; 4], mass: &ShellMass, lumped: bool) -> Result<Mat<f64>, ShellError> {
    Ok(Flat::quad(xyz, None, true)?.mass(mass, lumped))
}

/// CTRIA3 mass (18 × 18, basic): consistent (linear, exact 3-point rule) or lumped.
pub fn tria3_mass(xyz: &[V3; 3], mass: &ShellMass, lumped: bool) -> Result<Mat<f64>, ShellError> {
    Ok(Flat::tria(xyz, None)?.mass(mass, lumped))
}

/// CQUAD4 centroid strains in the material system from basic displacements `u` (grid-major,
/// 6 per grid); `section_z` = (z_top, z_bot) of the fibres reported, from the reference plane.
pub fn quad4_strains(
    xyz: &[V3; 4],
    material_x: Option<V3>,
    section_z: (f64, f64),
    u: &[f64; 24],
) -> Result<ShellStrains, ShellError> {
    Ok(Flat::quad(xyz, material_x, true)?.strains(section_z, u))
}

/// CTRIA3 centroid strains, as [`quad4_strains`].
pub fn tria3_strains(
    xyz: &[V3; 3],
    material_x: Option<V3>,
    section_z: (f64, f64),
    u: &[f64; 18],
) -> Result<ShellStrains, ShellError> {
    Ok(Flat::tria(xyz, material_x)?.strains(section_z, u))
}

/// Affine stiffness Σ f_i K_i of a CQUAD4 (4 grids) or CTRIA3 (3 grids) from affine section
/// parts ([`crate::fe::laminate::affine_sections`]): K_i = K(section_i) by linearity, the
/// quad's incompatible modes condensed once with the section of [`Incompatible::Condensed`],
/// the one at the nominal parameter values (the deck's; module doc, "frozen condensation"), or
/// left out ([`Incompatible::Off`]; triangles have no such modes and ignore `modes`). Parts
/// without stiffness are skipped.
pub fn affine_stiffness(
    xyz: &[V3],
    sections: &[(Coefficient, ShellSection)],
    modes: Incompatible<&ShellSection>,
    material_x: Option<V3>,
) -> Result<AffineMatrix, ShellError> {
    let nominal = modes.nominal();
    let el = Flat::new(xyz, material_x, nominal.is_some())?;
    let parts = sections
        .iter()
        .filter(|(_, s)| !s.stiffness_is_zero())
        .map(|(c, s)| (*c, el.stiffness(s, nominal)))
        .collect();
    Ok(AffineMatrix { parts })
}

/// Thickness at the stiffness integration points of a CQUAD4 (4 corner values: 2 × 2 Gauss,
/// bilinear interpolation) or CTRIA3 (3 values: the 3-point rule, linear), in the order
/// [`affine_stiffness_at_points`] takes its sections. Tapered elements (PSHELL with T1…T4)
/// integrate the section there: D ∝ t³ is cubic along an edge with linear thickness, which the
/// 2-point Gauss rule integrates exactly.
pub fn integration_point_thickness(corner_t: &[f64]) -> Result<Vec<f64>, ShellError> {
    let shapes: Vec<[f64; 4]> = match corner_t.len() {
        4 => QUAD_GAUSS
            .iter()
            .map(|&[xi, eta]| quad_shape(xi, eta).0)
            .collect(),
        3 => TRIA_POINTS
            .iter()
            .map(|&[r, s]| [1.0 - r - s, r, s, 0.0])
            .collect(),
        n => return Err(ShellError::NodeCount(n)),
    };
    Ok(shapes
        .iter()
        .map(|n| n.iter().zip(corner_t).map(|(n, t)| n * t).sum())
        .collect())
}

/// [`affine_stiffness`] with one list of affine section parts per integration point (see
/// [`integration_point_thickness`]): K_i = Σₚ wₚ B̄ₚᵀ C(section_{p,i}) B̄ₚ, and, with
/// [`Incompatible::Condensed`], one nominal section per point for the condensation. Every point
/// must give the same coefficients in the same order (the section's dependence on the
/// parameters is the same everywhere; only its value varies).
pub fn affine_stiffness_at_points(
    xyz: &[V3],
    sections: &[Vec<(Coefficient, ShellSection)>],
    modes: Incompatible<&[ShellSection]>,
    material_x: Option<V3>,
) -> Result<AffineMatrix, ShellError> {
    let el = Flat::new(xyz, material_x, modes.nominal().is_some())?;
    let points = el.points.len();
    let Some(first) = sections.first() else {
        return Err(ShellError::PointCount {
            expected: points,
            got: 0,
        });
    };
    let same_coefficients = |p: &Vec<(Coefficient, ShellSection)>| {
        p.len() == first.len() && p.iter().zip(first).all(|((a, _), (b, _))| a == b)
    };
    let nominal: Option<Vec<&ShellSection>> = modes.nominal().map(|n| n.iter().collect());
    for got in std::iter::once(sections.len()).chain(nominal.as_ref().map(Vec::len)) {
        if got != points {
            return Err(ShellError::PointCount {
                expected: points,
                got,
            });
        }
    }
    if !sections.iter().all(same_coefficients) {
        return Err(ShellError::PointCount {
            expected: points,
            got: sections.len(),
        });
    }
    let parts = (0..first.len())
        .filter(|&i| sections.iter().any(|p| !p[i].1.stiffness_is_zero()))
        .map(|i| {
            let at: Vec<&ShellSection> = sections.iter().map(|p| &p[i].1).collect();
            (first[i].0, el.stiffness_at_points(&at, nominal.as_deref()))
        })
        .collect();
    Ok(AffineMatrix { parts })
}

/// Affine mass Σ f_i M_i of a CQUAD4 or CTRIA3 from the masses of the affine section parts;
/// parts without mass are skipped.
pub fn affine_mass(
    xyz: &[V3],
    sections: &[(Coefficient, ShellSection)],
    lumped: bool,
) -> Result<AffineMatrix, ShellError> {
    let el = Flat::new(xyz, None, true)?;
    let parts = sections
        .iter()
        .filter(|(_, s)| !s.mass.is_zero())
        .map(|(c, s)| (*c, el.mass(&s.mass, lumped)))
        .collect();
    Ok(AffineMatrix { parts })
}
