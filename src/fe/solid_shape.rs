//! Shape functions, natural coordinates and quadrature rules of the solid elements
//! (used by `solid.rs`).
//!
//! Reference cells and node orders (Nastran):
//!
//! | element | natural cell | nodes |
//! |---|---|---|
//! | CHEXA 8 | (ξ, η, ζ) ∈ [−1, 1]³ | G1 (−,−,−) G2 (+,−,−) G3 (+,+,−) G4 (−,+,−), G5–G8 the same at ζ = +1 |
//! | CPENTA 6 | triangle ξ, η ≥ 0, ξ + η ≤ 1, times ζ ∈ [−1, 1] | G1 (0,0) G2 (1,0) G3 (0,1) at ζ = −1; G4–G6 above them at ζ = +1 |
//! | CTETRA 4 | ξ, η, ζ ≥ 0, ξ + η + ζ ≤ 1 | G1 origin, G2 ξ = 1, G3 η = 1, G4 ζ = 1 |
//! | CTETRA 10 | as CTETRA 4 | G1–G4 corners; G5 on 1–2, G6 2–3, G7 3–1, G8 1–4, G9 2–4, G10 3–4 |
//! | CHEXA 20 | as CHEXA 8 | G1–G8 corners; G9–G12 on 1–2, 2–3, 3–4, 4–1; G13–G16 on 1–5, 2–6, 3–7, 4–8; G17–G20 on 5–6, 6–7, 7–8, 8–5 |
//! | CPENTA 15 | as CPENTA 6 | G1–G6 corners; G7–G9 on 1–2, 2–3, 3–1; G10–G12 on 1–4, 2–5, 3–6; G13–G15 on 4–5, 5–6, 6–4 |
//!
//! Shape functions, with volume coordinates L1 = 1 − ξ − η − ζ, L2 = ξ, L3 = η, L4 = ζ
//! (triangle: L1 = 1 − ξ − η, L2 = ξ, L3 = η):
//! - CHEXA 8: N_a = ⅛ (1 + ξ_a ξ)(1 + η_a η)(1 + ζ_a ζ);
//! - CPENTA 6: N_a = L_a (1 − ζ)/2, N_{a+3} = L_a (1 + ζ)/2 (a = 1..3);
//! - CTETRA 4: N_a = L_a;
//! - CTETRA 10: corners N_a = L_a (2 L_a − 1), mid-edge N_ab = 4 L_a L_b;
//! - CHEXA 20 (serendipity; Zienkiewicz & Taylor, *The Finite Element Method* vol. 1, §8.7):
//!   corners N_a = ⅛ (1 + ξ_a ξ)(1 + η_a η)(1 + ζ_a ζ)(ξ_a ξ + η_a η + ζ_a ζ − 2), mid-sides
//!   N_m = ¼ Π_k g_k with g_k = 1 − ξ_k² along the edge's direction (ξ_m,k = 0) and
//!   1 + ξ_m,k ξ_k across it;
//! - CPENTA 15 (with s_a = ∓1 the ζ of the corner's triangle): corners
//!   N_a = ½ L_a [(2 L_a − 1)(1 + s_a ζ) − (1 − ζ²)], triangle mid-sides
//!   N_ab = 2 L_a L_b (1 + s ζ), vertical mid-sides N_a = L_a (1 − ζ²).

use super::solid::SolidKind;

/// Largest number of nodes of a solid element (CHEXA 20).
pub(crate) const MAX_NODES: usize = 20;

/// Shape-function values and natural derivatives ∂N_a/∂(ξ, η, ζ) at one natural point; only
/// the first `kind.nodes()` entries are meaningful.
pub(crate) struct Shape {
    pub n: [f64; MAX_NODES],
    pub dn: [[f64; 3]; MAX_NODES],
}

const HEXA_SIGNS: [[f64; 3]; 8] = [
    [-1.0, -1.0, -1.0],
    [1.0, -1.0, -1.0],
    [1.0, 1.0, -1.0],
    [-1.0, 1.0, -1.0],
    [-1.0, -1.0, 1.0],
    [1.0, -1.0, 1.0],
    [1.0, 1.0, 1.0],
    [-1.0, 1.0, 1.0],
];

/// CTETRA 10 mid-edge nodes G5–G10: the (0-based) corners of each edge.
const TET10_EDGES: [[usize; 2]; 6] = [[0, 1], [1, 2], [2, 0], [0, 3], [1, 3], [2, 3]];

/// CHEXA 20 mid-side nodes G9–G20: the (0-based) corners of each edge.
const HEXA20_EDGES: [[usize; 2]; 12] = [
    [0, 1],
    [1, 2],
    [2, 3],
    [3, 0],
    [0, 4],
    [1, 5],
    [2, 6],
    [3, 7],
    [4, 5],
    [5, 6],
    [6, 7],
    [7, 4],
];

/// CPENTA 15 mid-side nodes G7–G15: the (0-based) corners of each edge.
const PENTA15_EDGES: [[usize; 2]; 9] = [
    [0, 1],
    [1, 2],
    [2, 0],
    [0, 3],
    [1, 4],
    [2, 5],
    [3, 4],
    [4, 5],
    [5, 3],
];

/// The corner pairs of the mid-side nodes of `kind`, in node order after the corners (empty for
/// the linear elements).
pub(crate) fn midside_edges(kind: SolidKind) -> &'static [[usize; 2]] {
    match kind {
        SolidKind::Tetra10 => &TET10_EDGES,
        SolidKind::Hexa20 => &HEXA20_EDGES,
        SolidKind::Penta15 => &PENTA15_EDGES,
        SolidKind::Hexa8 | SolidKind::Penta6 | SolidKind::Tetra4 | SolidKind::Pyram5 => &[],
    }
}

/// Natural coordinates of node `a` of `kind` (a mid-side node at the middle of its edge).
pub(crate) fn node_xi(kind: SolidKind, a: usize) -> [f64; 3] {
    let corners = kind.nodes() - midside_edges(kind).len();
    if a >= corners {
        let [p, q] = midside_edges(kind)[a - corners];
        let (xp, xq) = (node_xi(kind, p), node_xi(kind, q));
        return std::array::from_fn(|k| 0.5 * (xp[k] + xq[k]));
    }
    match kind {
        SolidKind::Hexa8 | SolidKind::Hexa20 => HEXA_SIGNS[a],
        SolidKind::Penta6 | SolidKind::Penta15 => {
            let tri = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]][a % 3];
            [tri[0], tri[1], if a < 3 { -1.0 } else { 1.0 }]
        }
        SolidKind::Tetra4 | SolidKind::Tetra10 => {
            let mut x = [0.0; 3];
            if a > 0 {
                x[a - 1] = 1.0;
            }
            x
        }
        SolidKind::Pyram5 => match a {
            0..4 => [HEXA_SIGNS[a][0], HEXA_SIGNS[a][1], 0.0],
            _ => [0.0, 0.0, 1.0],
        },
    }
}

/// Shape functions of `kind` at natural point `xi`.
pub(crate) fn shape(kind: SolidKind, xi: [f64; 3]) -> Shape {
    let mut s = Shape {
        n: [0.0; MAX_NODES],
        dn: [[0.0; 3]; MAX_NODES],
    };
    let [x, y, z] = xi;
    match kind {
        SolidKind::Hexa8 => {
            for (a, sg) in HEXA_SIGNS.iter().enumerate() {
                let (fx, fy, fz) = (1.0 + sg[0] * x, 1.0 + sg[1] * y, 1.0 + sg[2] * z);
                s.n[a] = 0.125 * fx * fy * fz;
                s.dn[a] = [
                    0.125 * sg[0] * fy * fz,
                    0.125 * sg[1] * fx * fz,
                    0.125 * sg[2] * fx * fy,
                ];
            }
        }
        SolidKind::Hexa20 => hexa20(&mut s, xi),
        SolidKind::Pyram5 => pyram5(&mut s, xi),
        SolidKind::Penta15 => penta15(&mut s, xi),
        SolidKind::Penta6 => {
            let l = [1.0 - x - y, x, y];
            let dl = [[-1.0, -1.0], [1.0, 0.0], [0.0, 1.0]];
            for a in 0..3 {
                for (b, sz) in [(a, -1.0), (a + 3, 1.0)] {
                    let h = 0.5 * (1.0 + sz * z);
                    s.n[b] = l[a] * h;
                    s.dn[b] = [dl[a][0] * h, dl[a][1] * h, 0.5 * sz * l[a]];
                }
            }
        }
        SolidKind::Tetra4 | SolidKind::Tetra10 => {
            let l = [1.0 - x - y - z, x, y, z];
            let dl = [
                [-1.0, -1.0, -1.0],
                [1.0, 0.0, 0.0],
                [0.0, 1.0, 0.0],
                [0.0, 0.0, 1.0],
            ];
            if kind == SolidKind::Tetra4 {
                s.n[..4].copy_from_slice(&l);
                s.dn[..4].copy_from_slice(&dl);
            } else {
                for a in 0..4 {
                    s.n[a] = l[a] * (2.0 * l[a] - 1.0);
                    s.dn[a] = dl[a].map(|d| (4.0 * l[a] - 1.0) * d);
                }
                for (e, &[a, b]) in TET10_EDGES.iter().enumerate() {
                    s.n[4 + e] = 4.0 * l[a] * l[b];
                    s.dn[4 + e] =
                        std::array::from_fn(|k| 4.0 * (dl[a][k] * l[b] + l[a] * dl[b][k]));
                }
            }
        }
    }
    s
}

/// CPYRAM 5 rational functions on the pyramid |ξ|, |η| ≤ 1 − ζ, 0 ≤ ζ ≤ 1 (base G1–G4 at
/// (∓1, ∓1, 0) in CHEXA order, apex G5 at ζ = 1), with a = 1 − ζ:
/// N_i = (a + ξ_i ξ)(a + η_i η) / (4a) = ¼ (a + ξ_i ξ + η_i η + ξ_i η_i ξη / a), N_5 = ζ
/// (Bedrosian's pyramid, also Zienkiewicz–Taylor's): bilinear on the base, linear on the
/// triangular faces (so it conforms to CTETRA 4 and CHEXA 8 neighbours), complete to degree
/// one. At the apex ξ = η = 0, where the rational terms vanish: a is kept positive there (and
/// a² too, so that 0/a² is 0).
fn pyram5(s: &mut Shape, [x, y, z]: [f64; 3]) {
    let a = (1.0 - z).max(1e-100);
    for (i, sg) in HEXA_SIGNS.iter().take(4).enumerate() {
        let (si, ti) = (sg[0], sg[1]);
        s.n[i] = 0.25 * (a + si * x + ti * y + si * ti * x * y / a);
        s.dn[i] = [
            0.25 * (si + si * ti * y / a),
            0.25 * (ti + si * ti * x / a),
            0.25 * (-1.0 + si * ti * x * y / (a * a)),
        ];
    }
    s.n[4] = z;
    s.dn[4] = [0.0, 0.0, 1.0];
}

/// CHEXA 20 serendipity functions (module doc).
fn hexa20(s: &mut Shape, xi: [f64; 3]) {
    for (a, sg) in HEXA_SIGNS.iter().enumerate() {
        let f = [0, 1, 2].map(|k| 1.0 + sg[k] * xi[k]);
        let t = sg[0] * xi[0] + sg[1] * xi[1] + sg[2] * xi[2];
        s.n[a] = 0.125 * f[0] * f[1] * f[2] * (t - 2.0);
        // ∂/∂ξ_k: ⅛ s_k Π_{j≠k} f_j (2 s_k ξ_k + Σ_{j≠k} s_j ξ_j − 1)
        s.dn[a] = std::array::from_fn(|k| {
            let others = f[(k + 1) % 3] * f[(k + 2) % 3];
            0.125 * sg[k] * others * (t + sg[k] * xi[k] - 1.0)
        });
    }
    for (m, &[p, q]) in HEXA20_EDGES.iter().enumerate() {
        let c: [f64; 3] = std::array::from_fn(|k| 0.5 * (HEXA_SIGNS[p][k] + HEXA_SIGNS[q][k]));
        let g = [0, 1, 2].map(|k| {
            if c[k] == 0.0 {
                1.0 - xi[k] * xi[k]
            } else {
                1.0 + c[k] * xi[k]
            }
        });
        let dg = [0, 1, 2].map(|k| if c[k] == 0.0 { -2.0 * xi[k] } else { c[k] });
        s.n[8 + m] = 0.25 * g[0] * g[1] * g[2];
        s.dn[8 + m] = std::array::from_fn(|k| 0.25 * dg[k] * g[(k + 1) % 3] * g[(k + 2) % 3]);
    }
}

/// CPENTA 15 functions (module doc).
fn penta15(s: &mut Shape, xi: [f64; 3]) {
    let [x, y, z] = xi;
    let l = [1.0 - x - y, x, y];
    let dl = [[-1.0, -1.0], [1.0, 0.0], [0.0, 1.0]];
    let bubble = 1.0 - z * z;
    for a in 0..3 {
        for (node, sz) in [(a, -1.0), (a + 3, 1.0)] {
            let h = 1.0 + sz * z;
            let r = (2.0 * l[a] - 1.0) * h - bubble;
            s.n[node] = 0.5 * l[a] * r;
            let dr_dl = 2.0 * h;
            let d = 0.5 * (r + l[a] * dr_dl);
            s.dn[node] = [
                d * dl[a][0],
                d * dl[a][1],
                0.5 * l[a] * ((2.0 * l[a] - 1.0) * sz + 2.0 * z),
            ];
        }
    }
    for (m, &[p, q]) in PENTA15_EDGES.iter().enumerate() {
        let node = 6 + m;
        let (i, j) = (p % 3, q % 3);
        if i == j {
            // vertical edge: L_i (1 − ζ²)
            s.n[node] = l[i] * bubble;
            s.dn[node] = [dl[i][0] * bubble, dl[i][1] * bubble, -2.0 * z * l[i]];
        } else {
            let sz = if p < 3 { -1.0 } else { 1.0 };
            let h = 1.0 + sz * z;
            s.n[node] = 2.0 * l[i] * l[j] * h;
            s.dn[node] = [
                2.0 * (dl[i][0] * l[j] + l[i] * dl[j][0]) * h,
                2.0 * (dl[i][1] * l[j] + l[i] * dl[j][1]) * h,
                2.0 * l[i] * l[j] * sz,
            ];
        }
    }
}

/// Natural coordinates of the element centroid (where strains are recovered).
pub(crate) fn centroid(kind: SolidKind) -> [f64; 3] {
    match kind {
        SolidKind::Hexa8 | SolidKind::Hexa20 => [0.0; 3],
        SolidKind::Penta6 | SolidKind::Penta15 => [1.0 / 3.0, 1.0 / 3.0, 0.0],
        SolidKind::Tetra4 | SolidKind::Tetra10 => [0.25; 3],
        SolidKind::Pyram5 => [0.0, 0.0, 0.25],
    }
}

/// One quadrature point in natural coordinates with its weight (natural-cell measure).
#[derive(Debug, Clone, Copy)]
pub(crate) struct QuadPoint {
    pub xi: [f64; 3],
    pub w: f64,
}

/// Gauss–Legendre rules on [−1, 1]; n points integrate degree 2n − 1 exactly.
#[derive(Debug, Clone, Copy)]
pub(crate) enum Gauss {
    Two,
    Three,
    Five,
}

fn gauss(g: Gauss) -> Vec<(f64, f64)> {
    match g {
        Gauss::Two => {
            let a = 1.0 / 3.0_f64.sqrt();
            vec![(-a, 1.0), (a, 1.0)]
        }
        Gauss::Three => {
            let a = 0.6_f64.sqrt();
            vec![(-a, 5.0 / 9.0), (0.0, 8.0 / 9.0), (a, 5.0 / 9.0)]
        }
        Gauss::Five => {
            let r = 2.0 * (10.0_f64 / 7.0).sqrt();
            let (a, b) = ((5.0 - r).sqrt() / 3.0, (5.0 + r).sqrt() / 3.0);
            let s70 = 70.0_f64.sqrt();
            let (wa, wb) = ((322.0 + 13.0 * s70) / 900.0, (322.0 - 13.0 * s70) / 900.0);
            vec![(-b, wb), (-a, wa), (0.0, 128.0 / 225.0), (a, wa), (b, wb)]
        }
    }
}

/// Tensor-product Gauss rule on the hexahedron [−1, 1]³.
pub(crate) fn hexa_rule(g: Gauss) -> Vec<QuadPoint> {
    let line = gauss(g);
    let mut out = Vec::with_capacity(line.len().pow(3));
    for &(z, wz) in &line {
        for &(y, wy) in &line {
            for &(x, wx) in &line {
                out.push(QuadPoint {
                    xi: [x, y, z],
                    w: wx * wy * wz,
                });
            }
        }
    }
    out
}

/// Collapsed (Duffy) Gauss rule on the pyramid |ξ|, |η| ≤ 1 − ζ, 0 ≤ ζ ≤ 1: ξ = u (1 − ζ),
/// η = v (1 − ζ), ζ = (1 + w)/2 with (u, v, w) a tensor Gauss rule on [−1, 1]³, weight ×
/// (1 − ζ)²/2. The pyramid's functions become polynomials of (u, v, w) under this map (N_i =
/// ¼ a (1 + ξ_i u)(1 + η_i v)), so n points per direction integrate a straight-sided pyramid's
/// stiffness (n = 2: degree ≤ 2 in u, v and w) and mass (n = 3) exactly; no point is at the apex.
pub(crate) fn pyramid_rule(g: Gauss) -> Vec<QuadPoint> {
    hexa_rule(g)
        .into_iter()
        .map(|p| {
            let [u, v, w] = p.xi;
            let z = 0.5 * (1.0 + w);
            let a = 1.0 - z;
            QuadPoint {
                xi: [u * a, v * a, z],
                w: p.w * a * a * 0.5,
            }
        })
        .collect()
}

/// Collapsed (Duffy) Gauss rule on the unit triangle: ξ = u, η = (1 − u) v with u, v Gauss
/// points on [0, 1], weight × (1 − u). With n points per direction it integrates total degree
/// 2n − 2 exactly, with positive weights.
fn triangle_collapsed(g: Gauss) -> Vec<(f64, f64, f64)> {
    let line: Vec<(f64, f64)> = gauss(g)
        .into_iter()
        .map(|(x, w)| (0.5 * (1.0 + x), 0.5 * w))
        .collect();
    let mut out = Vec::with_capacity(line.len().pow(2));
    for &(u, wu) in &line {
        for &(v, wv) in &line {
            out.push((u, (1.0 - u) * v, wu * wv * (1.0 - u)));
        }
    }
    out
}

/// The 3-point (degree 2) triangle rule at (1/6, 1/6), (2/3, 1/6), (1/6, 2/3), weights 1/6.
fn triangle_three() -> Vec<(f64, f64, f64)> {
    let (a, b, w) = (1.0 / 6.0, 2.0 / 3.0, 1.0 / 6.0);
    vec![(a, a, w), (b, a, w), (a, b, w)]
}

/// Dunavant's 7-point rule of degree 5 on the unit triangle (weights include the area ½):
/// the centroid (weight 9/80) and the orbits of (a, a) for a = (6 ∓ √15)/21 with weights
/// (155 ∓ √15)/2400.
pub(crate) fn triangle_seven() -> Vec<(f64, f64, f64)> {
    let r = 15.0_f64.sqrt();
    let mut out = vec![(1.0 / 3.0, 1.0 / 3.0, 9.0 / 80.0)];
    for (a, w) in [
        ((6.0 - r) / 21.0, (155.0 - r) / 2400.0),
        ((6.0 + r) / 21.0, (155.0 + r) / 2400.0),
    ] {
        let b = 1.0 - 2.0 * a;
        out.extend([(a, a, w), (b, a, w), (a, b, w)]);
    }
    out
}

/// CPENTA stiffness rule: 3-point triangle × 2-point Gauss (6 points).
pub(crate) fn wedge_stiffness_rule() -> Vec<QuadPoint> {
    wedge_product(&triangle_three(), Gauss::Two)
}

/// CPENTA 15 stiffness rule: 7-point triangle (degree 5) × 3-point Gauss (degree 5), 21 points,
/// exact for Bᵀ D B det J of a wedge with straight edges and parallel triangles (degree 4 in
/// ξ, η and in ζ).
pub(crate) fn wedge15_stiffness_rule() -> Vec<QuadPoint> {
    wedge_product(&triangle_seven(), Gauss::Three)
}

/// CPENTA 15 mass rule: collapsed 5 × 5 triangle (degree 8) × 5-point Gauss (degree 9), exact
/// for N_a N_b det J (degree 4 in ξ, η and in ζ) with a det J up to degree 4 in ξ, η and 5 in ζ
/// (curved edges).
pub(crate) fn wedge15_mass_rule() -> Vec<QuadPoint> {
    wedge_product(&triangle_collapsed(Gauss::Five), Gauss::Five)
}

/// CPENTA mass rule: collapsed 3 × 3 triangle (degree 4) × 3-point Gauss (degree 5), exact
/// for N_a N_b det J on any wedge (degree 3 in ξ, η and 4 in ζ).
pub(crate) fn wedge_mass_rule() -> Vec<QuadPoint> {
    wedge_product(&triangle_collapsed(Gauss::Three), Gauss::Three)
}

fn wedge_product(tri: &[(f64, f64, f64)], g: Gauss) -> Vec<QuadPoint> {
    let line = gauss(g);
    let mut out = Vec::with_capacity(tri.len() * line.len());
    for &(z, wz) in &line {
        for &(x, y, w) in tri {
            out.push(QuadPoint {
                xi: [x, y, z],
                w: w * wz,
            });
        }
    }
    out
}

/// One-point tetrahedron rule at the centroid (weight 1/6): exact for constant strain.
pub(crate) fn tet_centroid_rule() -> Vec<QuadPoint> {
    vec![QuadPoint {
        xi: [0.25; 3],
        w: 1.0 / 6.0,
    }]
}

/// Four-point (degree 2) tetrahedron rule: points at the permutations of (a, b, b, b) in volume
/// coordinates, a = (5 + 3√5)/20, b = (5 − √5)/20, weights 1/24.
pub(crate) fn tet_four_rule() -> Vec<QuadPoint> {
    let s5 = 5.0_f64.sqrt();
    let (a, b) = ((5.0 + 3.0 * s5) / 20.0, (5.0 - s5) / 20.0);
    [[b, b, b], [a, b, b], [b, a, b], [b, b, a]]
        .into_iter()
        .map(|xi| QuadPoint { xi, w: 1.0 / 24.0 })
        .collect()
}

/// Collapsed (Duffy) Gauss rule on the unit tetrahedron: ξ = u, η = (1 − u) v,
/// ζ = (1 − u)(1 − v) w, weight × (1 − u)²(1 − v). With n points per direction it integrates
/// total degree 2n − 3 exactly (n = 5: degree 7, enough for N_a N_b det J of a curved-edge
/// CTETRA 10), with positive weights.
pub(crate) fn tet_collapsed_rule(g: Gauss) -> Vec<QuadPoint> {
    let line: Vec<(f64, f64)> = gauss(g)
        .into_iter()
        .map(|(x, w)| (0.5 * (1.0 + x), 0.5 * w))
        .collect();
    let mut out = Vec::with_capacity(line.len().pow(3));
    for &(u, wu) in &line {
        for &(v, wv) in &line {
            for &(t, wt) in &line {
                let xi = [u, (1.0 - u) * v, (1.0 - u) * (1.0 - v) * t];
                out.push(QuadPoint {
                    xi,
                    w: wu * wv * wt * (1.0 - u).powi(2) * (1.0 - v),
                });
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// ∫ ξ^a η^b ζ^c over the unit tetrahedron = a! b! c! / (a + b + c + 3)!.
    fn tet_monomial(a: u32, b: u32, c: u32) -> f64 {
        let f = |n: u32| (1..=n).map(f64::from).product::<f64>();
        f(a) * f(b) * f(c) / f(a + b + c + 3)
    }

    #[test]
    fn rules_integrate_their_stated_degree() {
        let check = |rule: &[QuadPoint], deg: u32, exact: &dyn Fn(u32, u32, u32) -> f64| {
            for a in 0..=deg {
                for b in 0..=deg - a {
                    for c in 0..=deg - a - b {
                        let q: f64 = rule
                            .iter()
                            .map(|p| {
                                p.w * p.xi[0].powi(a as i32)
                                    * p.xi[1].powi(b as i32)
                                    * p.xi[2].powi(c as i32)
                            })
                            .sum();
                        let e = exact(a, b, c);
                        assert!((q - e).abs() < 1e-14, "degree ({a},{b},{c}): {q} vs {e}");
                    }
                }
            }
        };
        check(&tet_collapsed_rule(Gauss::Five), 7, &tet_monomial);
        check(&tet_four_rule(), 2, &tet_monomial);
        check(&tet_centroid_rule(), 1, &tet_monomial);
        // wedge: triangle monomial ∫ ξ^a η^b = a! b! / (a + b + 2)!, times ∫ ζ^c over [−1, 1].
        let f = |n: u32| (1..=n).map(f64::from).product::<f64>();
        let line = |c: u32| {
            if c % 2 == 1 {
                0.0
            } else {
                2.0 / f64::from(c + 1)
            }
        };
        let wedge = |a: u32, b: u32, c: u32| f(a) * f(b) / f(a + b + 2) * line(c);
        let cube = |a: u32, b: u32, c: u32| line(a) * line(b) * line(c);
        check(&wedge_mass_rule(), 4, &wedge);
        check(&wedge_stiffness_rule(), 2, &wedge);
        check(&wedge15_stiffness_rule(), 5, &wedge);
        check(&wedge15_mass_rule(), 8, &wedge);
        check(&hexa_rule(Gauss::Five), 9, &cube);
        check(&hexa_rule(Gauss::Three), 5, &cube);
        // pyramid: ∫ ξ^a η^b ζ^c = line(a) line(b) c! (a + b + 2)! / (a + b + c + 3)!; the
        // collapsed rule with n points is exact while a + b + c + 2 ≤ 2n − 1
        let pyramid =
            |a: u32, b: u32, c: u32| line(a) * line(b) * f(c) * f(a + b + 2) / f(a + b + c + 3);
        check(&pyramid_rule(Gauss::Two), 1, &pyramid);
        check(&pyramid_rule(Gauss::Three), 3, &pyramid);
    }

    #[test]
    fn shape_functions_are_a_partition_of_unity_and_interpolate_nodes() {
        for kind in [
            SolidKind::Hexa8,
            SolidKind::Penta6,
            SolidKind::Tetra4,
            SolidKind::Tetra10,
            SolidKind::Hexa20,
            SolidKind::Penta15,
            SolidKind::Pyram5,
        ] {
            let n = kind.nodes();
            for a in 0..n {
                let at = shape(kind, node_xi(kind, a));
                for b in 0..n {
                    let delta = if a == b { 1.0 } else { 0.0 };
                    assert!((at.n[b] - delta).abs() < 1e-14, "{kind}: N{b} at node {a}");
                }
            }
            let s = shape(kind, [0.21, 0.17, 0.33]);
            assert!((s.n[..n].iter().sum::<f64>() - 1.0).abs() < 1e-14);
            for k in 0..3 {
                assert!(s.dn[..n].iter().map(|d| d[k]).sum::<f64>().abs() < 1e-14);
            }
            // central differences of N reproduce dN
            let h = 1e-6;
            for k in 0..3 {
                let mut xp = [0.21, 0.17, 0.33];
                let mut xm = xp;
                xp[k] += h;
                xm[k] -= h;
                let (sp, sm) = (shape(kind, xp), shape(kind, xm));
                for a in 0..n {
                    assert!(((sp.n[a] - sm.n[a]) / (2.0 * h) - s.dn[a][k]).abs() < 1e-8);
                }
            }
        }
    }
}
