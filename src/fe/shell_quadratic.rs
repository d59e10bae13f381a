//! Eight- and six-node curved Mindlin–Reissner shells (CQUAD8, CTRIA6): isoparametric
//! geometry, resultant (A, B, D, S) constitutive law of [`crate::fe::laminate`], assumed
//! covariant strains (MITC) against shear and membrane locking, and the Hughes–Brezzi drilling
//! penalty of the CQUAD4.
//!
//! # Formulation
//!
//! **Geometry.** The reference surface is x(ξ, η) = Σ N_a x_a with the serendipity (8 nodes:
//! corners G1–G4 counter-clockwise, G5 on G1–G2, G6 on G2–G3, G7 on G3–G4, G8 on G4–G1) or
//! quadratic triangle (G4 on G1–G2, G5 on G2–G3, G6 on G3–G1) functions, so the element is
//! curved. Each node carries the unit normal of that surface at the node, n_a, and the
//! director field is d = Σ N_a n_a (degenerated continuum, Ahmad–Irons–Zienkiewicz 1970; Bathe,
//! *Finite Element Procedures*, 2014, §5.4). The six DOFs per grid are the basic translations
//! u_a and rotations θ_a, and the displacement through the thickness is
//! u(ξ, η, z) = Σ N_a (u_a + z θ_a × n_a).
//!
//! **Strains.** With X = x + z d, the covariant Green strains ε_ij = ½(X,i·u,j + X,j·u,i)
//! are split into the reference-surface part ε⁰_αβ = ½(x,α·u⁰,β + x,β·u⁰,α), its first moment
//! ε¹_αβ = ½(x,α·w,β + d,α·u⁰,β + (α↔β)) with w = Σ N_a θ_a × n_a, and the transverse shear
//! 2ε_α3 = x,α·w + d·u⁰,α (terms in z² dropped; the metric through the thickness is taken as
//! the reference surface's, the usual thin-shell resultant approximation). Every term of a
//! rigid motion u_a = c + ω × x_a, θ_a = ω vanishes identically, so a free element has exactly
//! six zero-energy modes whatever its curvature. At each point they are turned into the local
//! Cartesian frame (x_m, y_m, n): n the surface normal, x_m the material direction
//! (`material_x`, default G1→G2) projected on the tangent plane, y_m = n × x_m; with the
//! contravariant base vectors gᵅ (gᵅ·x,β = δ), c_αi = gᵅ·e_i and
//! ε_ij = Σ c_αi c_βj ε_αβ. This gives the generalized strains of the CQUAD4,
//! ε̂ = [εx εy γxy | κx κy κxy | γxz γyz | d] (ε(z) = ε⁰ + zκ), so
//! K = Σ_gauss w·dA · Bᵀ C B with the same C = diag([[A, B], [B, D]], S, γ): K is linear in
//! the section, and the affine split per PMPAR kind is exactly the CQUAD4's (without its
//! frozen condensation: these elements condense nothing).
//!
//! **Drilling.** d = θ·n − ½(∂v/∂x − ∂u/∂y) in the local frame, Hughes–Brezzi penalty
//! ½∫γ d² dA with the CQUAD4's modulus γ = `section.drill` (= A66). On a flat element θ·n and
//! the in-plane rotation of the quadratic membrane lie in the same polynomial space, so the
//! penalty constrains no membrane motion (no locking) and leaves no spurious drilling mode.
//!
//! **Blank mid-side grids** ([`Layout`]): the 4-to-8 (3-to-6) node transition element
//! (Bathe, *Finite Element Procedures*, 2014, §5.3.1): the missing node is put at its edge's
//! middle and tied to the edge's corners inside the element, so its matrices are those of the
//! full element reduced by T (K' = Tᵀ K T), exactly affine in the section. A blank edge is
//! straight with linear displacements, as a CQUAD4 edge, so it conforms with a CQUAD4
//! neighbour (membrane patch exact on a mixed patch). Measured: six rigid modes
//! for every subset of blanks; the bending patch (w quadratic) is not in the space of an element
//! with a blank edge and is not passed; a cantilever strip of transition elements (edges across
//! the strip blank) is within 0.3 % of beam theory.
//!
//! **Assumed strains, CQUAD8** (the MITC9 tying of Bucalem & Bathe, "Higher-order MITC general
//! shell elements", IJNME 36 (1993) 3729–3754, on the 8-node serendipity field): with
//! a = 1/√3, b = √(3/5), ε⁰_ξξ and 2ε_ξ3 are tied at ξ = ±a, η ∈ {−b, 0, b} and interpolated
//! linearly in ξ, quadratically in η; ε⁰_ηη and 2ε_η3 the same with ξ ↔ η; ε⁰_ξη is tied at
//! (±a, ±a) and interpolated bilinearly. The curvature part ε¹ is taken at the integration
//! point. 3 × 3 Gauss points. Measured (`fe::shell_quadratic_tests`):
//! - a free element, flat or doubly curved, has exactly six zero-energy modes;
//! - constant membrane strain and constant curvature are exact on parallelograms; on a
//!   distorted patch they are not (MacNeal–Harder patch: 4 % membrane strain error, and the
//!   curvature state is not in the serendipity space of a non-affine map);
//! - no membrane locking: a thin quarter ring (t/R = 1e-3, 8 elements) bends as the curved
//!   beam to 2e-5;
//! - shear locking is not removed on coarse thin flat meshes: a simply supported plate with
//!   t/a = 0.01 is +62 % (2 × 2), +2.9 % (4 × 4) in frequency, −0.08 % (8 × 8, converged to
//!   the Mindlin value). Tying the shear at the 2 × 2 points instead removes that locking but
//!   converges to a wrong limit (−0.5 % at 16 × 16), so it is not used.
//!
//! **Assumed strains, CTRIA6** (MITC6 of Lee & Bathe, "Development of MITC isotropic
//! triangular shell finite elements", Comput. Struct. 82 (2004) 945–962): the covariant
//! transverse shears are ẽ_r = a₁ + b₁r + c₁s + s(dr + es), ẽ_s = a₂ + b₂r + c₂s − r(dr + es),
//! tied to e_r at (r₁, 0), (r₂, 0), e_s at (0, r₁), (0, r₂), e_s − e_r (the edge tangent of
//! G2–G3) at (r₂, r₁), (r₁, r₂), r₁,₂ = ½ ∓ 1/(2√3), and both at (⅓, ⅓). 6-point Gauss rule of
//! degree 4 (Dunavant 1985). Patch tests exact (straight-sided triangles are affine). The
//! membrane is displacement-based (not tied) and **locks on curved thin shells**: the quarter
//! ring above is 0.57 of the beam value at t/R = 1e-2 and 0.016 at 1e-3 — use CQUAD8 (or
//! CTRIA3) for curved thin shells. On flat plates it converges from below (simply supported
//! plate: −1.8 % on 4 × 4 × 2, −0.64 % on 8 × 8 × 2).
//!
//! **Mass.** Per unit area as the CQUAD4's, in basic components at each point with the normal
//! n there: ρt on the translations, ρi(I − nnᵀ) on the rotations, ρs on u·(θ × n).
//! Consistent: Σ w dA N_a N_b; lumped: the HRZ diagonal scaling (Hinton, Rock & Zienkiewicz,
//! Earthquake Eng. Struct. Dyn. 4 (1976) 245–249), node a taking the share ∫N_a² / Σ_b ∫N_b²
//! of the area with its own normal, so that no grid gets a negative or zero mass.
//!
//! **Strains reported** at the centroid (ξ = η = 0; r = s = ⅓), assumed field, in the material
//! system there.

use faer::Mat;
use faer::linalg::solvers::Solve;

use crate::geometry::vec3::{cross, dot, norm, scale, sub};

use super::affine::{AffineMatrix, Coefficient};
use super::laminate::{ShellMass, ShellSection};
use super::shell::{ShellError, ShellStrains, constitutive};

type V3 = [f64; 3];

/// The quadratic shell shapes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Quadratic {
    /// CQUAD8: 8-node serendipity quad.
    Quad8,
    /// CTRIA6: 6-node triangle.
    Tria6,
}

impl Quadratic {
    /// The shape with `nodes` grids, `None` for another count.
    pub fn with_nodes(nodes: usize) -> Option<Self> {
        match nodes {
            8 => Some(Quadratic::Quad8),
            6 => Some(Quadratic::Tria6),
            _ => None,
        }
    }

    fn card(self) -> &'static str {
        match self {
            Quadratic::Quad8 => "CQUAD8",
            Quadratic::Tria6 => "CTRIA6",
        }
    }

    fn nodes(self) -> usize {
        match self {
            Quadratic::Quad8 => 8,
            Quadratic::Tria6 => 6,
        }
    }

    /// Natural coordinates of the grids.
    fn node_coordinates(self) -> &'static [[f64; 2]] {
        match self {
            Quadratic::Quad8 => &QUAD8_NODES,
            Quadratic::Tria6 => &TRIA6_NODES,
        }
    }

    /// Centroid in natural coordinates.
    fn centre(self) -> [f64; 2] {
        match self {
            Quadratic::Quad8 => [0.0, 0.0],
            Quadratic::Tria6 => [1.0 / 3.0, 1.0 / 3.0],
        }
    }

    /// Integration points (natural coordinates) and weights.
    fn rule(self) -> Vec<([f64; 2], f64)> {
        match self {
            Quadratic::Quad8 => {
                let mut out = Vec::with_capacity(9);
                for (eta, we) in GAUSS_3 {
                    for (xi, wx) in GAUSS_3 {
                        out.push(([xi, eta], wx * we));
                    }
                }
                out
            }
            Quadratic::Tria6 => {
                let mut out = Vec::with_capacity(6);
                for (a, w) in [(TRI6_A1, TRI6_W1), (TRI6_A2, TRI6_W2)] {
                    let b = 1.0 - 2.0 * a;
                    for p in [[a, a], [b, a], [a, b]] {
                        out.push((p, 0.5 * w));
                    }
                }
                out
            }
        }
    }

    /// Shape values and natural derivatives (∂/∂ξ, ∂/∂η) at `p` (ξ, η on [−1, 1]² for the
    /// quad, area coordinates r = L2, s = L3 for the triangle).
    pub(crate) fn shape(self, [xi, eta]: [f64; 2]) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
        match self {
            Quadratic::Quad8 => {
                let mut n = vec![0.0; 8];
                let mut dx = vec![0.0; 8];
                let mut de = vec![0.0; 8];
                for (a, &[xa, ea]) in QUAD8_NODES.iter().enumerate() {
                    if a < 4 {
                        let (p, q) = (1.0 + xa * xi, 1.0 + ea * eta);
                        let s = xa * xi + ea * eta - 1.0;
                        n[a] = 0.25 * p * q * s;
                        dx[a] = 0.25 * xa * q * (s + p);
                        de[a] = 0.25 * ea * p * (s + q);
                    } else if xa == 0.0 {
                        n[a] = 0.5 * (1.0 - xi * xi) * (1.0 + ea * eta);
                        dx[a] = -xi * (1.0 + ea * eta);
                        de[a] = 0.5 * ea * (1.0 - xi * xi);
                    } else {
                        n[a] = 0.5 * (1.0 + xa * xi) * (1.0 - eta * eta);
                        dx[a] = 0.5 * xa * (1.0 - eta * eta);
                        de[a] = -eta * (1.0 + xa * xi);
                    }
                }
                (n, dx, de)
            }
            Quadratic::Tria6 => {
                let l = [1.0 - xi - eta, xi, eta];
                // ∂L/∂r, ∂L/∂s
                let dl = [[-1.0, -1.0], [1.0, 0.0], [0.0, 1.0]];
                let mut n = vec![0.0; 6];
                let mut dr = vec![0.0; 6];
                let mut ds = vec![0.0; 6];
                for i in 0..3 {
                    n[i] = l[i] * (2.0 * l[i] - 1.0);
                    dr[i] = (4.0 * l[i] - 1.0) * dl[i][0];
                    ds[i] = (4.0 * l[i] - 1.0) * dl[i][1];
                }
                for (k, (i, j)) in [(0, 1), (1, 2), (2, 0)].into_iter().enumerate() {
                    n[3 + k] = 4.0 * l[i] * l[j];
                    dr[3 + k] = 4.0 * (dl[i][0] * l[j] + l[i] * dl[j][0]);
                    ds[3 + k] = 4.0 * (dl[i][1] * l[j] + l[i] * dl[j][1]);
                }
                (n, dr, ds)
            }
        }
    }

    /// Corner (bilinear / linear) functions at `p`, for corner thicknesses.
    fn corner_shape(self, [xi, eta]: [f64; 2]) -> Vec<f64> {
        match self {
            Quadratic::Quad8 => QUAD8_NODES[..4]
                .iter()
                .map(|[xa, ea]| 0.25 * (1.0 + xa * xi) * (1.0 + ea * eta))
                .collect(),
            Quadratic::Tria6 => vec![1.0 - xi - eta, xi, eta],
        }
    }
}

/// Which mid-side grids of a CQUAD8 / CTRIA6 are given. A blank mid-side grid leaves its
/// edge straight and the displacement along it linear: the transition element to a CQUAD4 /
/// CTRIA3 neighbour (the MSC Nastran QRG, CQUAD8 remark 3, allows any subset blank, "the
/// element equations are modified" for the reduced connections). The element is built as
/// the full 8- / 6-node element with that mid-side node at the middle of its edge, tied by
/// u_m = ½(u_a + u_b) on all six DOFs (a, b the edge's corners): with T the map from the
/// given grids' DOFs to the full element's, its strain operator is B T, its shape functions
/// Tᵀ N, so K' = Tᵀ K T, M' = Tᵀ M T and loads Tᵀ f. No grid and no constraint is added to the
/// model, and K' stays linear in the section (the affine split is the full element's).
/// Along a tied edge the serendipity / quadratic functions with the middle value the mean of
/// the ends are linear, so the edge conforms with a CQUAD4 / CTRIA3 edge; a rigid motion is
/// linear in x and satisfies the tie on a straight edge, so the six rigid-body modes stay in
/// the element's space.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Layout {
    pub shape: Quadratic,
    /// `blank[k]`: the mid-side grid of edge k (from corner k to corner k + 1) is blank; only
    /// the first three are used by a CTRIA6.
    pub blank: [bool; 4],
}

impl Layout {
    /// Every mid-side grid given.
    pub fn full(shape: Quadratic) -> Self {
        Layout {
            shape,
            blank: [false; 4],
        }
    }

    /// The layout of a card's grid list (corners, then mid-sides, 0 for a blank one), `None`
    /// for a list of another length than 8 or 6.
    pub fn of_card(nodes: &[u32]) -> Option<Self> {
        let shape = Quadratic::with_nodes(nodes.len())?;
        let corners = shape.nodes() / 2;
        let mut blank = [false; 4];
        for (b, &g) in blank.iter_mut().zip(&nodes[corners..]) {
            *b = g == 0;
        }
        Some(Layout { shape, blank })
    }

    /// True when a mid-side grid is blank.
    pub fn has_blank(self) -> bool {
        self.blank[..self.shape.nodes() / 2].contains(&true)
    }

    /// Number of grids given (corners and mid-sides).
    pub fn grids(self) -> usize {
        let corners = self.shape.nodes() / 2;
        corners + self.blank[..corners].iter().filter(|&&b| !b).count()
    }

    /// For each node of the full element, the given grids (positions in the given list:
    /// corners first, then the given mid-sides in order) and weights it is tied to.
    fn ties(self) -> Vec<Vec<(usize, f64)>> {
        let corners = self.shape.nodes() / 2;
        let mut out: Vec<Vec<(usize, f64)>> = (0..corners).map(|a| vec![(a, 1.0)]).collect();
        let mut next = corners;
        for k in 0..corners {
            if self.blank[k] {
                out.push(vec![(k, 0.5), ((k + 1) % corners, 0.5)]);
            } else {
                out.push(vec![(next, 1.0)]);
                next += 1;
            }
        }
        out
    }

    /// The full element's grid positions from the given grids' (a blank mid-side grid at the
    /// middle of its edge).
    pub fn complete(self, xyz: &[V3]) -> Result<Vec<V3>, ShellError> {
        if xyz.len() != self.grids() {
            return Err(ShellError::NodeCount(xyz.len()));
        }
        Ok(self
            .ties()
            .iter()
            .map(|tie| {
                tie.iter().fold([0.0; 3], |s, &(a, w)| {
                    std::array::from_fn(|k| s[k] + w * xyz[a][k])
                })
            })
            .collect())
    }

    /// Tᵀ v: `v` of the full element's nodes (grid-major, `per` values each) summed onto the
    /// given grids.
    pub fn condense(self, v: &[f64], per: usize) -> Vec<f64> {
        let mut out = vec![0.0; per * self.grids()];
        for (f, tie) in self.ties().iter().enumerate() {
            for &(a, w) in tie {
                for i in 0..per {
                    out[per * a + i] += w * v[per * f + i];
                }
            }
        }
        out
    }

    /// B T: the columns (6 per full node) of `b` onto the given grids'.
    fn condense_columns(self, b: &Mat<f64>) -> Mat<f64> {
        let mut out = Mat::<f64>::zeros(b.nrows(), 6 * self.grids());
        for (f, tie) in self.ties().iter().enumerate() {
            for &(a, w) in tie {
                for r in 0..b.nrows() {
                    for i in 0..6 {
                        out[(r, 6 * a + i)] += w * b[(r, 6 * f + i)];
                    }
                }
            }
        }
        out
    }
}

const QUAD8_NODES: [[f64; 2]; 8] = [
    [-1.0, -1.0],
    [1.0, -1.0],
    [1.0, 1.0],
    [-1.0, 1.0],
    [0.0, -1.0],
    [1.0, 0.0],
    [0.0, 1.0],
    [-1.0, 0.0],
];

const TRIA6_NODES: [[f64; 2]; 6] = [
    [0.0, 0.0],
    [1.0, 0.0],
    [0.0, 1.0],
    [0.5, 0.0],
    [0.5, 0.5],
    [0.0, 0.5],
];

/// √(3/5), the outer 3-point Gauss abscissa.
const GAUSS_3_X: f64 = 0.774_596_669_241_483_4;

/// 3-point Gauss rule on [−1, 1].
const GAUSS_3: [(f64, f64); 3] = [
    (-GAUSS_3_X, 5.0 / 9.0),
    (0.0, 8.0 / 9.0),
    (GAUSS_3_X, 5.0 / 9.0),
];

/// 1/√3, the 2-point Gauss abscissa (tying points).
const GAUSS_2_X: f64 = 0.577_350_269_189_625_8;

/// Dunavant's 6-point rule of degree 4 on the triangle: points (a, a), (1 − 2a, a),
/// (a, 1 − 2a) with weights w (fractions of the area).
const TRI6_A1: f64 = 0.445_948_490_915_965;
const TRI6_W1: f64 = 0.223_381_589_678_011;
const TRI6_A2: f64 = 0.091_576_213_509_771;
const TRI6_W2: f64 = 0.109_951_743_655_322;

/// Number of generalized strains (as the CQUAD4's).
const NSTRAIN: usize = 9;

/// Covariant strain rows at one point, each over the 6n basic DOFs: membrane ε⁰_ξξ, ε⁰_ηη,
/// ε⁰_ξη (tensor), their first moments ε¹, transverse 2ε_ξ3, 2ε_η3, and the drilling residual
/// (already Cartesian).
struct Covariant {
    membrane: [Vec<f64>; 3],
    bending: [Vec<f64>; 3],
    shear: [Vec<f64>; 2],
    drill: Vec<f64>,
    /// c[α][i] = gᵅ·e_i, Cartesian derivative ∂/∂x_i = Σ_α c[α][i] ∂/∂ξ_α.
    c: [[f64; 2]; 2],
    /// Area element |x,ξ × x,η|.
    da: f64,
    /// Local axes e1 (x_m), e2, e3 (normal).
    axes: [V3; 3],
}

/// Assumed covariant rows: membrane ε⁰_ξξ, ε⁰_ηη, ε⁰_ξη and transverse 2ε_ξ3, 2ε_η3.
type Assumed = ([Vec<f64>; 3], [Vec<f64>; 2]);

/// The element's geometry, ready for strain rows at any point.
struct Geometry {
    shape: Quadratic,
    xyz: Vec<V3>,
    normals: Vec<V3>,
    material_x: V3,
}

fn lin(row: &mut [f64], col: usize, v: V3, f: f64) {
    for k in 0..3 {
        row[col + k] += f * v[k];
    }
}

fn combine(rows: &[(&[f64], f64)], len: usize) -> Vec<f64> {
    let mut out = vec![0.0; len];
    for (r, f) in rows {
        for (o, x) in out.iter_mut().zip(r.iter()) {
            *o += f * x;
        }
    }
    out
}

/// The tangent normals g = x_ξ × x_η of a quadratic surface at its nodes, checked at the nodes
/// and the integration points against the centre's (the surface must not fold over: every
/// g · g_centre > 10⁻⁸ |g_centre|²), and the Jacobian ratio min / max of g · g_centre over
/// those points.
fn surface_jacobians(shape: Quadratic, xyz: &[V3]) -> Result<(Vec<V3>, f64), ShellError> {
    if xyz.len() != shape.nodes() {
        return Err(ShellError::NodeCount(xyz.len()));
    }
    let tangents = |p: [f64; 2]| {
        let (_, dx, de) = shape.shape(p);
        let t = |d: &[f64]| {
            (0..xyz.len()).fold([0.0; 3], |s, a| {
                [
                    s[0] + d[a] * xyz[a][0],
                    s[1] + d[a] * xyz[a][1],
                    s[2] + d[a] * xyz[a][2],
                ]
            })
        };
        cross(t(&dx), t(&de))
    };
    let size = xyz
        .iter()
        .flat_map(|p| xyz.iter().map(move |q| norm(sub(*p, *q))))
        .fold(0.0, f64::max);
    let centre = tangents(shape.centre());
    if !(norm(centre) > 1e-10 * size * size) {
        return Err(ShellError::ZeroArea {
            shape: shape.card(),
        });
    }
    let mut normals = Vec::with_capacity(xyz.len());
    let (mut min, mut max) = (f64::INFINITY, f64::NEG_INFINITY);
    let check = shape
        .node_coordinates()
        .iter()
        .map(|&p| (p, true))
        .chain(shape.rule().into_iter().map(|(p, _)| (p, false)));
    for (k, (p, at_node)) in check.enumerate() {
        let g = tangents(p);
        let along = dot(g, centre);
        if !(along > 1e-8 * dot(centre, centre)) {
            return Err(ShellError::Distorted {
                shape: shape.card(),
                grid: at_node.then_some(k + 1),
            });
        }
        (min, max) = (min.min(along), max.max(along));
        if at_node {
            normals.push(scale(g, 1.0 / norm(g)));
        }
    }
    Ok((normals, min / max))
}

/// The Jacobian ratio (min / max of the surface Jacobian over the nodes and integration points)
/// of a CQUAD8 / CTRIA6 with the given grids' positions `xyz`, or the kernel's error for a
/// degenerate or folded surface: the geometry check of `paraflex check`.
pub fn jacobian_ratio(layout: Layout, xyz: &[V3]) -> Result<f64, ShellError> {
    surface_jacobians(layout.shape, &layout.complete(xyz)?).map(|(_, ratio)| ratio)
}

impl Geometry {
    fn new(shape: Quadratic, xyz: &[V3], material_x: Option<V3>) -> Result<Self, ShellError> {
        let (normals, _) = surface_jacobians(shape, xyz)?;
        Ok(Geometry {
            shape,
            xyz: xyz.to_vec(),
            normals,
            material_x: material_x.unwrap_or_else(|| sub(xyz[1], xyz[0])),
        })
    }

    fn dofs(&self) -> usize {
        6 * self.xyz.len()
    }

    /// The direct covariant strain rows at `p`.
    fn covariant(&self, p: [f64; 2]) -> Result<Covariant, ShellError> {
        let (n, dx, de) = self.shape.shape(p);
        let nn = self.xyz.len();
        let sum = |w: &[f64], v: &[V3]| {
            (0..nn).fold([0.0; 3], |s, a| {
                [
                    s[0] + w[a] * v[a][0],
                    s[1] + w[a] * v[a][1],
                    s[2] + w[a] * v[a][2],
                ]
            })
        };
        let g = [sum(&dx, &self.xyz), sum(&de, &self.xyz)];
        let d = sum(&n, &self.normals);
        let dd = [sum(&dx, &self.normals), sum(&de, &self.normals)];
        let normal = cross(g[0], g[1]);
        let da = norm(normal);
        let e3 = scale(normal, 1.0 / da);
        let mx = self.material_x;
        let proj = sub(mx, scale(e3, dot(mx, e3)));
        if norm(proj) <= 1e-8 * norm(mx) {
            return Err(ShellError::MaterialAxisNormal { direction: mx });
        }
        let e1 = scale(proj, 1.0 / norm(proj));
        let e2 = cross(e3, e1);
        // contravariant base: gᵅ = g^{αβ} g_β
        let m = [
            [dot(g[0], g[0]), dot(g[0], g[1])],
            [dot(g[1], g[0]), dot(g[1], g[1])],
        ];
        let det = m[0][0] * m[1][1] - m[0][1] * m[1][0];
        let inv = [
            [m[1][1] / det, -m[0][1] / det],
            [-m[1][0] / det, m[0][0] / det],
        ];
        let contra: [V3; 2] = std::array::from_fn(|a| {
            std::array::from_fn(|k| inv[a][0] * g[0][k] + inv[a][1] * g[1][k])
        });
        let c = [
            [dot(contra[0], e1), dot(contra[0], e2)],
            [dot(contra[1], e1), dot(contra[1], e2)],
        ];
        let len = self.dofs();
        let dn = [&dx, &de];
        let pairs = [(0, 0), (1, 1), (0, 1)];
        let mut membrane: [Vec<f64>; 3] = std::array::from_fn(|_| vec![0.0; len]);
        let mut bending: [Vec<f64>; 3] = std::array::from_fn(|_| vec![0.0; len]);
        let mut shear: [Vec<f64>; 2] = std::array::from_fn(|_| vec![0.0; len]);
        let mut drill = vec![0.0; len];
        for a in 0..nn {
            let (u, t) = (6 * a, 6 * a + 3);
            let na = self.normals[a];
            for (r, &(al, be)) in pairs.iter().enumerate() {
                let (fa, fb) = (dn[al][a], dn[be][a]);
                lin(&mut membrane[r], u, g[al], 0.5 * fb);
                lin(&mut membrane[r], u, g[be], 0.5 * fa);
                // x,α·(θ × n) = θ·(n × x,α)
                lin(&mut bending[r], t, cross(na, g[al]), 0.5 * fb);
                lin(&mut bending[r], t, cross(na, g[be]), 0.5 * fa);
                lin(&mut bending[r], u, dd[al], 0.5 * fb);
                lin(&mut bending[r], u, dd[be], 0.5 * fa);
            }
            for (al, row) in shear.iter_mut().enumerate() {
                lin(row, t, cross(na, g[al]), n[a]);
                lin(row, u, d, dn[al][a]);
            }
            // d = θ·e3 − ½(e2·u,x − e1·u,y)
            let (nx, ny) = (
                c[0][0] * dx[a] + c[1][0] * de[a],
                c[0][1] * dx[a] + c[1][1] * de[a],
            );
            lin(&mut drill, t, e3, n[a]);
            lin(&mut drill, u, e2, -0.5 * nx);
            lin(&mut drill, u, e1, 0.5 * ny);
        }
        Ok(Covariant {
            membrane,
            bending,
            shear,
            drill,
            c,
            da,
            axes: [e1, e2, e3],
        })
    }

    /// The assumed covariant membrane and shear rows at `p` (module doc, "Assumed strains").
    fn assumed(&self, p: [f64; 2], direct: &Covariant) -> Result<Assumed, ShellError> {
        let len = self.dofs();
        match self.shape {
            Quadratic::Quad8 => {
                let (a, b) = (GAUSS_2_X, GAUSS_3_X);
                let linear = |x: f64| [0.5 * (1.0 - x / a), 0.5 * (1.0 + x / a)];
                let quadratic = |x: f64| {
                    [
                        0.5 * x * (x - b) / (b * b),
                        1.0 - x * x / (b * b),
                        0.5 * x * (x + b) / (b * b),
                    ]
                };
                let (two, three) = ([-a, a], [-b, 0.0, b]);
                // along ξ: linear in ξ, quadratic in η; along η the same with ξ ↔ η
                let mut membrane: [Vec<f64>; 3] = std::array::from_fn(|_| vec![0.0; len]);
                let mut shear: [Vec<f64>; 2] = std::array::from_fn(|_| vec![0.0; len]);
                for dir in 0..2 {
                    let (along, across) = if dir == 0 { (p[0], p[1]) } else { (p[1], p[0]) };
                    let (la, qa) = (linear(along), quadratic(across));
                    for (i, &s) in two.iter().enumerate() {
                        for (j, &t) in three.iter().enumerate() {
                            let at = if dir == 0 { [s, t] } else { [t, s] };
                            let cov = self.covariant(at)?;
                            let w = la[i] * qa[j];
                            for k in 0..len {
                                membrane[dir][k] += w * cov.membrane[dir][k];
                                shear[dir][k] += w * cov.shear[dir][k];
                            }
                        }
                    }
                }
                let (lx, le) = (linear(p[0]), linear(p[1]));
                for (i, &s) in two.iter().enumerate() {
                    for (j, &t) in two.iter().enumerate() {
                        let cov = self.covariant([s, t])?;
                        let w = lx[i] * le[j];
                        for (o, x) in membrane[2].iter_mut().zip(&cov.membrane[2]) {
                            *o += w * x;
                        }
                    }
                }
                Ok((membrane, shear))
            }
            Quadratic::Tria6 => {
                let weights = mitc6_weights(p);
                let (r1, r2) = (0.5 - 0.5 * GAUSS_2_X, 0.5 + 0.5 * GAUSS_2_X);
                let third = 1.0 / 3.0;
                // tied data: (point, coefficient of e_r, coefficient of e_s)
                let data: [([f64; 2], f64, f64); 8] = [
                    ([r1, 0.0], 1.0, 0.0),
                    ([r2, 0.0], 1.0, 0.0),
                    ([0.0, r1], 0.0, 1.0),
                    ([0.0, r2], 0.0, 1.0),
                    ([r2, r1], -1.0, 1.0),
                    ([r1, r2], -1.0, 1.0),
                    ([third, third], 1.0, 0.0),
                    ([third, third], 0.0, 1.0),
                ];
                let mut shear: [Vec<f64>; 2] = std::array::from_fn(|_| vec![0.0; len]);
                for (k, (at, cr, cs)) in data.into_iter().enumerate() {
                    let cov = self.covariant(at)?;
                    let tied = combine(&[(&cov.shear[0], cr), (&cov.shear[1], cs)], len);
                    for dir in 0..2 {
                        for (o, x) in shear[dir].iter_mut().zip(&tied) {
                            *o += weights[dir][k] * x;
                        }
                    }
                }
                Ok((direct.membrane.clone(), shear))
            }
        }
    }

    /// The Cartesian strain operator B (9 × 6n) at `p` with the assumed strains, its area
    /// element and the local axes.
    fn operator(&self, p: [f64; 2]) -> Result<(Mat<f64>, f64, [V3; 3]), ShellError> {
        let direct = self.covariant(p)?;
        let (membrane, shear) = self.assumed(p, &direct)?;
        let c = direct.c;
        let len = self.dofs();
        let mut b = Mat::<f64>::zeros(NSTRAIN, len);
        // ε_ij = Σ c_αi c_βj ε_αβ; engineering γxy = 2ε_12
        let cart = |rows: &[Vec<f64>; 3], b: &mut Mat<f64>, offset: usize| {
            for k in 0..len {
                let (e11, e22, e12) = (rows[0][k], rows[1][k], rows[2][k]);
                let t = |i: usize, j: usize| {
                    c[0][i] * c[0][j] * e11
                        + c[1][i] * c[1][j] * e22
                        + (c[0][i] * c[1][j] + c[1][i] * c[0][j]) * e12
                };
                b[(offset, k)] = t(0, 0);
                b[(offset + 1, k)] = t(1, 1);
                b[(offset + 2, k)] = 2.0 * t(0, 1);
            }
        };
        cart(&membrane, &mut b, 0);
        cart(&direct.bending, &mut b, 3);
        for k in 0..len {
            for i in 0..2 {
                b[(6 + i, k)] = c[0][i] * shear[0][k] + c[1][i] * shear[1][k];
            }
            b[(8, k)] = direct.drill[k];
        }
        Ok((b, direct.da, direct.axes))
    }
}

/// MITC6 interpolation weights at (r, s): ẽ_r = Σ_k weights[0][k] t_k, ẽ_s = Σ_k
/// weights[1][k] t_k over the eight tied values t_k of [`Geometry::assumed`], i.e. the rows
/// of the assumed basis at (r, s) times M⁻¹, M the basis at the tying data.
fn mitc6_weights([r, s]: [f64; 2]) -> [[f64; 8]; 2] {
    let basis_r = |r: f64, s: f64| [1.0, r, s, 0.0, 0.0, 0.0, s * r, s * s];
    let basis_s = |r: f64, s: f64| [0.0, 0.0, 0.0, 1.0, r, s, -r * r, -r * s];
    let (r1, r2) = (0.5 - 0.5 * GAUSS_2_X, 0.5 + 0.5 * GAUSS_2_X);
    let third = 1.0 / 3.0;
    let diff = |r: f64, s: f64| -> [f64; 8] {
        let (a, b) = (basis_r(r, s), basis_s(r, s));
        std::array::from_fn(|i| b[i] - a[i])
    };
    let rows = [
        basis_r(r1, 0.0),
        basis_r(r2, 0.0),
        basis_s(0.0, r1),
        basis_s(0.0, r2),
        diff(r2, r1),
        diff(r1, r2),
        basis_r(third, third),
        basis_s(third, third),
    ];
    let m = Mat::<f64>::from_fn(8, 8, |i, j| rows[i][j]);
    let inv = m.partial_piv_lu().solve(Mat::<f64>::identity(8, 8));
    let (br, bs) = (basis_r(r, s), basis_s(r, s));
    let at = |basis: [f64; 8]| -> [f64; 8] {
        std::array::from_fn(|k| (0..8).map(|i| basis[i] * inv[(i, k)]).sum())
    };
    [at(br), at(bs)]
}

/// One integration point of a built element.
struct Point {
    /// Weight × area element.
    wda: f64,
    shape: Vec<f64>,
    b: Mat<f64>,
    normal: V3,
}

/// A quadratic shell element, ready for any section: strain operators and shape functions
/// on the given grids (blank mid-side nodes tied, [`Layout`]).
struct Curved {
    /// Nodal normals of the given grids.
    normals: Vec<V3>,
    points: Vec<Point>,
}

impl Curved {
    fn new(layout: Layout, xyz: &[V3], material_x: Option<V3>) -> Result<Self, ShellError> {
        let shape = layout.shape;
        let geometry = Geometry::new(shape, &layout.complete(xyz)?, material_x)?;
        let mut normals = vec![[0.0; 3]; layout.grids()];
        for (f, tie) in layout.ties().iter().enumerate() {
            if let [(a, _)] = tie[..] {
                normals[a] = geometry.normals[f];
            }
        }
        let points = shape
            .rule()
            .into_iter()
            .map(|(p, w)| {
                let (b, da, axes) = geometry.operator(p)?;
                Ok(Point {
                    wda: w * da,
                    shape: layout.condense(&shape.shape(p).0, 1),
                    b: layout.condense_columns(&b),
                    normal: axes[2],
                })
            })
            .collect::<Result<Vec<_>, ShellError>>()?;
        Ok(Curved { normals, points })
    }

    fn dofs(&self) -> usize {
        6 * self.normals.len()
    }

    fn stiffness_at_points(&self, sections: &[&ShellSection]) -> Mat<f64> {
        let n = self.dofs();
        let mut k = Mat::<f64>::zeros(n, n);
        for (p, s) in self.points.iter().zip(sections) {
            let cb = constitutive(s) * &p.b;
            k += p.b.transpose() * &cb * faer::Scale(p.wda);
        }
        symmetrize(&mut k);
        k
    }

    fn stiffness(&self, section: &ShellSection) -> Mat<f64> {
        self.stiffness_at_points(&vec![section; self.points.len()])
    }

    fn mass(&self, m: &ShellMass, lumped: bool) -> Mat<f64> {
        let nn = self.normals.len();
        let mut out = Mat::<f64>::zeros(6 * nn, 6 * nn);
        let mut add = |a: usize, b: usize, f: f64, normal: V3| {
            let rho = mass_density(m, normal);
            for i in 0..6 {
                for j in 0..6 {
                    out[(6 * a + i, 6 * b + j)] += f * rho[i][j];
                }
            }
        };
        if lumped {
            let diag: Vec<f64> = (0..nn)
                .map(|a| self.points.iter().map(|p| p.wda * p.shape[a].powi(2)).sum())
                .collect();
            let area: f64 = self.points.iter().map(|p| p.wda).sum();
            let total: f64 = diag.iter().sum();
            for (a, d) in diag.iter().enumerate() {
                add(a, a, area * d / total, self.normals[a]);
            }
        } else {
            for p in &self.points {
                for a in 0..nn {
                    for b in 0..nn {
                        add(a, b, p.wda * p.shape[a] * p.shape[b], p.normal);
                    }
                }
            }
        }
        symmetrize(&mut out);
        out
    }
}

fn symmetrize(k: &mut Mat<f64>) {
    for i in 0..k.nrows() {
        for j in 0..i {
            let v = 0.5 * (k[(i, j)] + k[(j, i)]);
            k[(i, j)] = v;
            k[(j, i)] = v;
        }
    }
}

/// Mass density per area over basic u (3), θ (3) at a point with normal n (module doc).
fn mass_density(m: &ShellMass, n: V3) -> [[f64; 6]; 6] {
    let mut r = [[0.0; 6]; 6];
    for i in 0..3 {
        r[i][i] = m.rho_t;
        for j in 0..3 {
            let delta = if i == j { 1.0 } else { 0.0 };
            r[3 + i][3 + j] = m.rho_i * (delta - n[i] * n[j]);
        }
    }
    // u·(θ × n) = uᵀ S θ with S = −[n]×
    let s = [[0.0, n[2], -n[1]], [-n[2], 0.0, n[0]], [n[1], -n[0], 0.0]];
    for i in 0..3 {
        for j in 0..3 {
            r[i][3 + j] = m.rho_s * s[i][j];
            r[3 + j][i] = m.rho_s * s[i][j];
        }
    }
    r
}

/// Thickness at the stiffness integration points of a CQUAD8 (4 corner values, bilinear) or
/// CTRIA6 (3 corner values, linear), in the order [`affine_stiffness_at_points`] takes its
/// sections.
pub fn integration_point_thickness(
    shape: Quadratic,
    corner_t: &[f64],
) -> Result<Vec<f64>, ShellError> {
    let corners = shape.nodes() / 2;
    if corner_t.len() != corners {
        return Err(ShellError::NodeCount(corner_t.len()));
    }
    Ok(shape
        .rule()
        .into_iter()
        .map(|(p, _)| {
            shape
                .corner_shape(p)
                .iter()
                .zip(corner_t)
                .map(|(n, t)| n * t)
                .sum()
        })
        .collect())
}

/// Affine stiffness Σ f_i K_i of a CQUAD8 or CTRIA6 of `layout` (`xyz`: its given grids,
/// corners first), basic system:
/// K_i = K(section_i) by linearity; parts without stiffness are skipped.
pub fn affine_stiffness(
    layout: Layout,
    xyz: &[V3],
    sections: &[(Coefficient, ShellSection)],
    material_x: Option<V3>,
) -> Result<AffineMatrix, ShellError> {
    let el = Curved::new(layout, xyz, material_x)?;
    let parts = sections
        .iter()
        .filter(|(_, s)| !s.stiffness_is_zero())
        .map(|(c, s)| (*c, el.stiffness(s)))
        .collect();
    Ok(AffineMatrix { parts })
}

/// [`affine_stiffness`] with one list of affine section parts per integration point (see
/// [`integration_point_thickness`]); every point must give the same coefficients in the same
/// order.
pub fn affine_stiffness_at_points(
    layout: Layout,
    xyz: &[V3],
    sections: &[Vec<(Coefficient, ShellSection)>],
    material_x: Option<V3>,
) -> Result<AffineMatrix, ShellError> {
    let el = Curved::new(layout, xyz, material_x)?;
    let expected = el.points.len();
    let first = sections
        .first()
        .ok_or(ShellError::PointCount { expected, got: 0 })?;
    let same = |p: &Vec<(Coefficient, ShellSection)>| {
        p.len() == first.len() && p.iter().zip(first).all(|((a, _), (b, _))| a == b)
    };
    if sections.len() != expected || !sections.iter().all(same) {
        return Err(ShellError::PointCount {
            expected,
            got: sections.len(),
        });
    }
    let parts = (0..first.len())
        .filter(|&i| sections.iter().any(|p| !p[i].1.stiffness_is_zero()))
        .map(|i| {
            let at: Vec<&ShellSection> = sections.iter().map(|p| &p[i].1).collect();
            (first[i].0, el.stiffness_at_points(&at))
        })
        .collect();
    Ok(AffineMatrix { parts })
}

/// Affine mass Σ f_i M_i of a CQUAD8 or CTRIA6 (consistent or HRZ-lumped); parts without mass
/// are skipped.
pub fn affine_mass(
    layout: Layout,
    xyz: &[V3],
    sections: &[(Coefficient, ShellSection)],
    lumped: bool,
) -> Result<AffineMatrix, ShellError> {
    let el = Curved::new(layout, xyz, None)?;
    let parts = sections
        .iter()
        .filter(|(_, s)| !s.mass.is_zero())
        .map(|(c, s)| (*c, el.mass(&s.mass, lumped)))
        .collect();
    Ok(AffineMatrix { parts })
}

/// Centroid strains of a CQUAD8 or CTRIA6 in the material system there, from basic
/// displacements `u` (grid-major, 6 per grid); `section_z` = (z_top, z_bot) of the fibres.
pub fn strains(
    layout: Layout,
    xyz: &[V3],
    material_x: Option<V3>,
    section_z: (f64, f64),
    u: &[f64],
) -> Result<ShellStrains, ShellError> {
    let shape = layout.shape;
    let geometry = Geometry::new(shape, &layout.complete(xyz)?, material_x)?;
    if u.len() != 6 * layout.grids() {
        return Err(ShellError::NodeCount(u.len() / 6));
    }
    let (b, _, axes) = geometry.operator(shape.centre())?;
    let b = layout.condense_columns(&b);
    let e: Vec<f64> = (0..NSTRAIN)
        .map(|r| (0..u.len()).map(|c| b[(r, c)] * u[c]).sum())
        .collect();
    let membrane = [e[0], e[1], e[2]];
    let curvature = [e[3], e[4], e[5]];
    let at = |z: f64| std::array::from_fn(|i| membrane[i] + z * curvature[i]);
    Ok(ShellStrains {
        membrane,
        curvature,
        top: at(section_z.0),
        bottom: at(section_z.1),
        shear: [e[6], e[7]],
        axes,
    })
}

/// ∫w dA and ∫x w dA / ∫w dA over a CQUAD8 / CTRIA6 surface, for a density w interpolated
/// from its corner values (bilinear / linear), with the element's integration rule (the one
/// of its mass matrix, so the two agree).
pub fn weighted(layout: Layout, xyz: &[V3], corner_w: &[f64]) -> Result<(f64, V3), ShellError> {
    let shape = layout.shape;
    let xyz = &layout.complete(xyz)?;
    // validates the element (a folded surface has no meaningful area)
    Geometry::new(shape, xyz, None)?;
    let w_at = integration_point_thickness(shape, corner_w)?;
    let mut total = 0.0;
    let mut moment = [0.0; 3];
    for ((p, w), density) in shape.rule().into_iter().zip(w_at) {
        let (n, dx, de) = shape.shape(p);
        let at = |f: &[f64]| {
            (0..xyz.len()).fold([0.0; 3], |s, a| {
                std::array::from_fn(|k| s[k] + f[a] * xyz[a][k])
            })
        };
        let da = norm(cross(at(&dx), at(&de)));
        let dm = w * da * density;
        total += dm;
        let x = at(&n);
        moment = std::array::from_fn(|k| moment[k] + dm * x[k]);
    }
    let c = if total != 0.0 {
        scale(moment, 1.0 / total)
    } else {
        xyz.iter().fold([0.0; 3], |s, p| {
            std::array::from_fn(|k| s[k] + p[k] / xyz.len() as f64)
        })
    };
    Ok((total, c))
}
