//! Element geometry: exact areas, volumes and centroids, and the shape checks.
//!
//! # Integrals
//! Every element is treated as its isoparametric map x(ξ) = Σ Nᵢ(ξ) pᵢ:
//! - `CTRIA3`: flat triangle, area ½|(p2−p1)×(p3−p1)|, centroid = node mean (both exact);
//!   with a linearly varying density (corner thicknesses) the closed-form moments are used.
//! - `CQUAD4`: bilinear surface, A = ∫|x_ξ × x_η| dξ dη and centroid ∫x dA / A with an 8×8
//!   Gauss–Legendre rule. For a planar quad |x_ξ × x_η| is linear in (ξ, η), so the rule is exact
//!   to round-off; for a warped quad the integrand is smooth and the rule converges exponentially.
//! - `CHEXA` (trilinear), `CPENTA` (linear triangle × linear), `CTETRA` 4 and 10 (quadratic,
//!   mid-side grids where they are): V = ∫det J and centroid ∫x det J / V with rules exact for
//!   these polynomial integrands (3×3×3 Gauss for the hexa, degree-5 collapsed rules for wedge
//!   and tetra). A sheared hexa therefore has volume base × height, not pyNastran's face formula.
//!
//! # Checks and thresholds
//! Solids (`check_solid`): det J is sampled at the corners and at the quadrature points.
//! - any det J ≤ 0 → **error** "inverted or degenerate element"; when det J < 0 everywhere the
//!   message says the node order is reversed (mirror image numbering);
//! - Jacobian ratio min det J / max det J < [`JACOBIAN_RATIO_WARN`] → warning (very distorted).
//!
//! Shells (`check_quad`, `check_tria`), following Nastran's GEOMCHECK defaults for warnings:
//! - area ≤ [`ZERO_AREA_REL`] · (longest edge)² → **error** (zero area);
//! - a corner whose two edges are collinear or coincident, or a reflex/crossed corner (bow-tie,
//!   concave quad: the bilinear map folds) → **error**;
//! - interior angle outside [[`QUAD_ANGLE_MIN`], [`QUAD_ANGLE_MAX`]] (quad) or below
//!   [`TRIA_ANGLE_MIN`] (tria) → warning;
//! - warp = h / (½ · mean diagonal length) > [`WARP_WARN`] → warning, with h the distance of the
//!   corners from the mean plane (the plane through the corner mean spanned by the diagonals; all
//!   four corners are ±h from it);
//! - taper = max |Aᵢ − Ā| / Ā > [`TAPER_WARN`] → warning, Aᵢ the corner triangles' areas;
//! - skew: the smaller angle between the lines joining opposite edge midpoints < [`SKEW_MIN`] →
//!   warning.

use crate::geometry::vec3::{self, add, cross, dot, norm, scale, sub, triple};
use std::sync::OnceLock;

/// Solids: Jacobian ratio (min/max det J) below which a warning is issued.
pub const JACOBIAN_RATIO_WARN: f64 = 0.05;
/// Shells: area relative to the longest edge squared at or below which the element is degenerate.
pub const ZERO_AREA_REL: f64 = 1e-10;
/// Shells: |sin| of a corner angle at or below which the corner's edges count as collinear.
pub const COLLINEAR_SIN: f64 = 1e-8;
/// CQUAD4 interior angle warning limits (degrees), Nastran GEOMCHECK Q4_IAMIN / Q4_IAMAX.
pub const QUAD_ANGLE_MIN: f64 = 30.0;
/// See [`QUAD_ANGLE_MIN`].
pub const QUAD_ANGLE_MAX: f64 = 150.0;
/// CTRIA3 smallest interior angle warning limit (degrees), Nastran GEOMCHECK T3_SKEW.
pub const TRIA_ANGLE_MIN: f64 = 10.0;
/// CQUAD4 warp warning limit, Nastran GEOMCHECK Q4_WARP.
pub const WARP_WARN: f64 = 0.05;
/// CQUAD4 taper warning limit, Nastran GEOMCHECK Q4_TAPER.
pub const TAPER_WARN: f64 = 0.5;
/// CQUAD4 skew warning limit (degrees), Nastran GEOMCHECK Q4_SKEW.
pub const SKEW_MIN: f64 = 30.0;

/// Solid element shapes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SolidShape {
    Hexa8,
    Penta6,
    Tetra4,
    Tetra10,
}

impl SolidShape {
    /// Number of grids.
    pub fn nodes(self) -> usize {
        match self {
            SolidShape::Hexa8 => 8,
            SolidShape::Penta6 => 6,
            SolidShape::Tetra4 => 4,
            SolidShape::Tetra10 => 10,
        }
    }

    /// Natural coordinates of the corner grids.
    fn corners(self) -> Vec<[f64; 3]> {
        match self {
            SolidShape::Hexa8 => HEXA_CORNERS.to_vec(),
            SolidShape::Penta6 => {
                vec![
                    [0., 0., -1.],
                    [1., 0., -1.],
                    [0., 1., -1.],
                    [0., 0., 1.],
                    [1., 0., 1.],
                    [0., 1., 1.],
                ]
            }
            SolidShape::Tetra4 | SolidShape::Tetra10 => {
                vec![[0., 0., 0.], [1., 0., 0.], [0., 1., 0.], [0., 0., 1.]]
            }
        }
    }

    /// Quadrature rule (natural point, weight), exact for the volume and first-moment integrands.
    fn rule(self) -> &'static [([f64; 3], f64)] {
        static RULES: OnceLock<[Vec<([f64; 3], f64)>; 3]> = OnceLock::new();
        let rules = RULES.get_or_init(|| {
            [
                SolidShape::Hexa8.compute_rule(),
                SolidShape::Penta6.compute_rule(),
                SolidShape::Tetra4.compute_rule(),
            ]
        });
        match self {
            SolidShape::Hexa8 => &rules[0],
            SolidShape::Penta6 => &rules[1],
            SolidShape::Tetra4 | SolidShape::Tetra10 => &rules[2],
        }
    }

    fn compute_rule(self) -> Vec<([f64; 3], f64)> {
        match self {
            SolidShape::Hexa8 => {
                let g = gauss_legendre(3);
                let mut out = Vec::with_capacity(27);
                for &(a, wa) in g {
                    for &(b, wb) in g {
                        for &(c, wc) in g {
                            out.push(([a, b, c], wa * wb * wc));
                        }
                    }
                }
                out
            }
            SolidShape::Penta6 => {
                let g = gauss_legendre(3);
                let mut out = Vec::new();
                for (rs, w) in triangle_rule(4) {
                    for &(z, wz) in g {
                        out.push(([rs[0], rs[1], z], w * wz));
                    }
                }
                out
            }
            SolidShape::Tetra4 | SolidShape::Tetra10 => tetra_rule(4),
        }
    }

    /// Shape functions and their derivatives with respect to the natural coordinates.
    fn shape(self, q: [f64; 3]) -> (Vec<f64>, Vec<[f64; 3]>) {
        match self {
            SolidShape::Hexa8 => {
                let mut n = Vec::with_capacity(8);
                let mut d = Vec::with_capacity(8);
                for c in HEXA_CORNERS {
                    let (a, b, e) = (1.0 + c[0] * q[0], 1.0 + c[1] * q[1], 1.0 + c[2] * q[2]);
                    n.push(a * b * e / 8.0);
                    d.push([c[0] * b * e / 8.0, a * c[1] * e / 8.0, a * b * c[2] / 8.0]);
                }
                (n, d)
            }
            SolidShape::Penta6 => {
                let l = [1.0 - q[0] - q[1], q[0], q[1]];
                let dl = [[-1.0, -1.0], [1.0, 0.0], [0.0, 1.0]];
                let mut n = Vec::with_capacity(6);
                let mut d = Vec::with_capacity(6);
                for (sign, half) in [(-1.0, 0.5 * (1.0 - q[2])), (1.0, 0.5 * (1.0 + q[2]))] {
                    for k in 0..3 {
                        n.push(l[k] * half);
                        d.push([dl[k][0] * half, dl[k][1] * half, 0.5 * sign * l[k]]);
                    }
                }
                (n, d)
            }
            SolidShape::Tetra4 => {
                let n = vec![1.0 - q[0] - q[1] - q[2], q[0], q[1], q[2]];
                let d = vec![[-1., -1., -1.], [1., 0., 0.], [0., 1., 0.], [0., 0., 1.]];
                (n, d)
            }
            SolidShape::Tetra10 => {
                let l = [1.0 - q[0] - q[1] - q[2], q[0], q[1], q[2]];
                let dl: [[f64; 3]; 4] = [[-1., -1., -1.], [1., 0., 0.], [0., 1., 0.], [0., 0., 1.]];
                let mut n = Vec::with_capacity(10);
                let mut d = Vec::with_capacity(10);
                for k in 0..4 {
                    n.push(l[k] * (2.0 * l[k] - 1.0));
                    d.push(scale(dl[k], 4.0 * l[k] - 1.0));
                }
                for (a, b) in TETRA10_EDGES {
                    n.push(4.0 * l[a] * l[b]);
                    d.push(scale(add(scale(dl[a], l[b]), scale(dl[b], l[a])), 4.0));
                }
                (n, d)
            }
        }
    }

    /// Volume, centroid and det J extremes of an element with grids `p` (basic).
    pub fn integrate(self, p: &[[f64; 3]]) -> SolidIntegrals {
        let mut volume = 0.0;
        let mut moment = [0.0; 3];
        let mut min_det = f64::INFINITY;
        let mut max_det = f64::NEG_INFINITY;
        for &(q, w) in self.rule() {
            let (n, d) = self.shape(q);
            let det = jacobian_det(&d, p);
            let x = p
                .iter()
                .zip(&n)
                .fold([0.0; 3], |acc, (pi, ni)| add(acc, scale(*pi, *ni)));
            volume += w * det;
            moment = add(moment, scale(x, w * det));
            min_det = min_det.min(det);
            max_det = max_det.max(det);
        }
        for q in self.corners() {
            let (_, d) = self.shape(q);
            let det = jacobian_det(&d, p);
            min_det = min_det.min(det);
            max_det = max_det.max(det);
        }
        let centroid = if volume != 0.0 {
            scale(moment, 1.0 / volume)
        } else {
            vec3::mean(p)
        };
        SolidIntegrals {
            volume,
            centroid,
            min_det,
            max_det,
        }
    }
}

/// Corner natural coordinates of the 8-node hexa in Nastran order.
const HEXA_CORNERS: [[f64; 3]; 8] = [
    [-1., -1., -1.],
    [1., -1., -1.],
    [1., 1., -1.],
    [-1., 1., -1.],
    [-1., -1., 1.],
    [1., -1., 1.],
    [1., 1., 1.],
    [-1., 1., 1.],
];

/// CTETRA G5…G10 edges (0-based corner pairs): G1G2, G2G3, G3G1, G1G4, G2G4, G3G4.
const TETRA10_EDGES: [(usize, usize); 6] = [(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)];

/// Result of [`SolidShape::integrate`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SolidIntegrals {
    /// ∫ det J (signed).
    pub volume: f64,
    /// ∫ x det J / V.
    pub centroid: [f64; 3],
    /// Smallest det J at the corners and quadrature points.
    pub min_det: f64,
    /// Largest det J at the corners and quadrature points.
    pub max_det: f64,
}

fn jacobian_det(d: &[[f64; 3]], p: &[[f64; 3]]) -> f64 {
    let mut j = [[0.0; 3]; 3];
    for (di, pi) in d.iter().zip(p) {
        for a in 0..3 {
            for b in 0..3 {
                j[a][b] += di[a] * pi[b];
            }
        }
    }
    triple(j[0], j[1], j[2])
}

/// Gauss–Legendre points and weights on [−1, 1] (Newton iteration on Pₙ, to round-off).
/// Gauss–Legendre rule with `n` points on [−1, 1] (1 ≤ n ≤ 8; other values are clamped),
/// computed once and shared.
pub fn gauss_legendre(n: usize) -> &'static [(f64, f64)] {
    static RULES: OnceLock<Vec<Vec<(f64, f64)>>> = OnceLock::new();
    let rules = RULES.get_or_init(|| (0..=8).map(compute_gauss_legendre).collect());
    &rules[n.clamp(1, 8)]
}

fn compute_gauss_legendre(n: usize) -> Vec<(f64, f64)> {
    let mut out = Vec::with_capacity(n);
    for i in 0..n {
        let mut x = (std::f64::consts::PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
        let mut dp = 1.0;
        for _ in 0..100 {
            let (mut p0, mut p1) = (1.0, x);
            for k in 2..=n {
                let p2 = ((2 * k - 1) as f64 * x * p1 - (k - 1) as f64 * p0) / k as f64;
                p0 = p1;
                p1 = p2;
            }
            dp = n as f64 * (x * p1 - p0) / (x * x - 1.0);
            let dx = p1 / dp;
            x -= dx;
            if dx.abs() < 1e-16 {
                break;
            }
        }
        out.push((x, 2.0 / ((1.0 - x * x) * dp * dp)));
    }
    out
}

/// Collapsed (Duffy) rule on the unit triangle {r, s ≥ 0, r + s ≤ 1}: exact for polynomials of
/// degree ≤ 2n − 2.
fn triangle_rule(n: usize) -> Vec<([f64; 2], f64)> {
    let g: Vec<(f64, f64)> = gauss_legendre(n)
        .iter()
        .map(|&(x, w)| (0.5 * (x + 1.0), 0.5 * w))
        .collect();
    let mut out = Vec::with_capacity(n * n);
    for &(u, wu) in &g {
        for &(v, wv) in &g {
            out.push(([u * (1.0 - v), v], wu * wv * (1.0 - v)));
        }
    }
    out
}

/// Collapsed rule on the unit tetrahedron: exact for polynomials of degree ≤ 2n − 3.
fn tetra_rule(n: usize) -> Vec<([f64; 3], f64)> {
    let g: Vec<(f64, f64)> = gauss_legendre(n)
        .iter()
        .map(|&(x, w)| (0.5 * (x + 1.0), 0.5 * w))
        .collect();
    let mut out = Vec::with_capacity(n * n * n);
    for &(u, wu) in &g {
        for &(v, wv) in &g {
            for &(w, ww) in &g {
                let q = [u * (1.0 - v) * (1.0 - w), v * (1.0 - w), w];
                out.push((q, wu * wv * ww * (1.0 - v) * (1.0 - w) * (1.0 - w)));
            }
        }
    }
    out
}

/// Exact area and centroid of a CTRIA3.
pub fn tria_area_centroid(p: &[[f64; 3]; 3]) -> (f64, [f64; 3]) {
    (
        0.5 * norm(cross(sub(p[1], p[0]), sub(p[2], p[0]))),
        vec3::mean(p),
    )
}

/// ∫w dA and ∫x w dA / ∫w dA over a flat triangle for a density w linear between the corner
/// values (exact: ∫Nᵢ dA = A/3, ∫Nᵢ Nⱼ dA = A(1 + δᵢⱼ)/12).
pub fn tria_weighted(p: &[[f64; 3]; 3], w: [f64; 3]) -> (f64, [f64; 3]) {
    let (area, mean) = tria_area_centroid(p);
    let total = area * (w[0] + w[1] + w[2]) / 3.0;
    let sum_p = add(add(p[0], p[1]), p[2]);
    let mut moment = [0.0; 3];
    for k in 0..3 {
        moment = add(moment, scale(add(sum_p, p[k]), w[k] * area / 12.0));
    }
    let c = if total != 0.0 {
        scale(moment, 1.0 / total)
    } else {
        mean
    };
    (total, c)
}

/// Area ∫|x_ξ × x_η| and centroid of the bilinear CQUAD4 surface (8×8 Gauss–Legendre).
pub fn quad_area_centroid(p: &[[f64; 3]; 4]) -> (f64, [f64; 3]) {
    quad_weighted(p, [1.0; 4])
}

/// ∫w dA and ∫x w dA / ∫w dA over the bilinear CQUAD4 surface for a density w interpolated
/// bilinearly between the corner values (8×8 Gauss–Legendre, exact for planar quads).
pub fn quad_weighted(p: &[[f64; 3]; 4], w: [f64; 4]) -> (f64, [f64; 3]) {
    let g = gauss_legendre(8);
    let mut total = 0.0;
    let mut moment = [0.0; 3];
    for &(xi, wx) in g {
        for &(eta, we) in g {
            let n = [
                (1. - xi) * (1. - eta),
                (1. + xi) * (1. - eta),
                (1. + xi) * (1. + eta),
                (1. - xi) * (1. + eta),
            ];
            let dxi = [-(1. - eta), 1. - eta, 1. + eta, -(1. + eta)];
            let deta = [-(1. - xi), -(1. + xi), 1. + xi, 1. - xi];
            let mut x = [0.0; 3];
            let mut a = [0.0; 3];
            let mut b = [0.0; 3];
            let mut density = 0.0;
            for k in 0..4 {
                x = add(x, scale(p[k], n[k] / 4.0));
                a = add(a, scale(p[k], dxi[k] / 4.0));
                b = add(b, scale(p[k], deta[k] / 4.0));
                density += w[k] * n[k] / 4.0;
            }
            let dm = norm(cross(a, b)) * wx * we * density;
            total += dm;
            moment = add(moment, scale(x, dm));
        }
    }
    let c = if total != 0.0 {
        scale(moment, 1.0 / total)
    } else {
        vec3::mean(p)
    };
    (total, c)
}

/// Outcome of a shape check: errors make the element unusable, warnings are reported.
#[derive(Debug, Default, Clone, PartialEq)]
pub struct ShapeReport {
    /// Fatal problems (message without the element name).
    pub errors: Vec<String>,
    /// Quality warnings as (check name, measured value text).
    pub warnings: Vec<(&'static str, String)>,
}

/// Check a solid; `nodes` are the grid ids (for messages).
pub fn check_solid(
    shape: SolidShape,
    p: &[[f64; 3]],
    nodes: &[u32],
) -> (SolidIntegrals, ShapeReport) {
    let integrals = shape.integrate(p);
    let mut report = ShapeReport::default();
    let grids = nodes
        .iter()
        .map(|g| g.to_string())
        .collect::<Vec<_>>()
        .join(" ");
    let finite = integrals.volume.is_finite() && integrals.min_det.is_finite();
    if !finite {
        report
            .errors
            .push(format!("non-finite geometry (grids {grids})"));
    } else if integrals.max_det < 0.0 {
        report.errors.push(format!(
            "inverted or degenerate element: det J < 0 everywhere (volume {:.6e}); the node order is reversed (mirror-image numbering of grids {grids})",
            integrals.volume
        ));
    } else if integrals.min_det <= 0.0 {
        report.errors.push(format!(
            "inverted or degenerate element: det J = {:.3e} ≤ 0 at a corner or integration point (zero volume or folded; grids {grids})",
            integrals.min_det
        ));
    } else {
        let ratio = integrals.min_det / integrals.max_det;
        if ratio < JACOBIAN_RATIO_WARN {
            report
                .warnings
                .push(("Jacobian ratio", format!("{ratio:.3}")));
        }
    }
    (integrals, report)
}

fn angle_deg(a: [f64; 3], b: [f64; 3], n: [f64; 3]) -> f64 {
    dot(cross(a, b), n).atan2(dot(a, b)).to_degrees()
}

/// Check a CQUAD4 with corners `p` and grid ids `nodes`.
pub fn check_quad(p: &[[f64; 3]; 4], nodes: &[u32; 4]) -> ShapeReport {
    let mut report = ShapeReport::default();
    if !p.iter().flatten().all(|v| v.is_finite()) {
        report.errors.push("non-finite grid coordinates".into());
        return report;
    }
    let d13 = sub(p[2], p[0]);
    let d24 = sub(p[3], p[1]);
    let longest = (0..4)
        .map(|k| norm(sub(p[(k + 1) % 4], p[k])))
        .fold(0.0, f64::max);
    let nv = cross(d13, d24);
    let projected = 0.5 * norm(nv);
    if longest == 0.0 || projected <= ZERO_AREA_REL * longest * longest {
        report.errors.push(format!(
            "zero area (grids {} {} {} {} are coincident or collinear)",
            nodes[0], nodes[1], nodes[2], nodes[3]
        ));
        return report;
    }
    let n = scale(nv, 1.0 / norm(nv));
    let mut corner_areas = [0.0; 4];
    for k in 0..4 {
        let e1 = sub(p[(k + 1) % 4], p[k]);
        let e2 = sub(p[(k + 3) % 4], p[k]);
        let (l1, l2) = (norm(e1), norm(e2));
        let c = cross(e1, e2);
        corner_areas[k] = 0.5 * dot(c, n);
        if l1 == 0.0 || l2 == 0.0 {
            report.errors.push(format!(
                "grid {} coincides with a neighbour (zero-length edge)",
                nodes[k]
            ));
            continue;
        }
        let sin = dot(c, n) / (l1 * l2);
        if sin.abs() <= COLLINEAR_SIN {
            report.errors.push(format!(
                "the edges at grid {} are collinear (degenerate corner)",
                nodes[k]
            ));
        } else if sin < 0.0 {
            report.errors.push(format!(
                "reflex or crossed corner at grid {} (concave or bow-tie quad: the element folds)",
                nodes[k]
            ));
        } else {
            let ang = angle_deg(e1, e2, n);
            if !(QUAD_ANGLE_MIN..=QUAD_ANGLE_MAX).contains(&ang) {
                report
                    .warnings
                    .push(("interior angle", format!("{ang:.1}° at grid {}", nodes[k])));
            }
        }
    }
    if !report.errors.is_empty() {
        return report;
    }
    let mean = vec3::mean(p);
    let h = dot(sub(p[0], mean), n).abs();
    let warp = h / (0.25 * (norm(d13) + norm(d24)));
    if warp > WARP_WARN {
        report.warnings.push(("warp", format!("{warp:.3}")));
    }
    let abar = corner_areas.iter().sum::<f64>() / 4.0;
    let taper = corner_areas
        .iter()
        .map(|a| (a - abar).abs())
        .fold(0.0, f64::max)
        / abar;
    if taper > TAPER_WARN {
        report.warnings.push(("taper", format!("{taper:.3}")));
    }
    let m = |a: usize, b: usize| scale(add(p[a], p[b]), 0.5);
    let l1 = sub(m(1, 2), m(3, 0));
    let l2 = sub(m(2, 3), m(0, 1));
    let cosang = (dot(l1, l2) / (norm(l1) * norm(l2))).clamp(-1.0, 1.0);
    let between = cosang.abs().acos().to_degrees();
    if between < SKEW_MIN {
        report.warnings.push(("skew", format!("{between:.1}°")));
    }
    report
}

/// Check a CTRIA3.
pub fn check_tria(p: &[[f64; 3]; 3], nodes: &[u32; 3]) -> ShapeReport {
    let mut report = ShapeReport::default();
    if !p.iter().flatten().all(|v| v.is_finite()) {
        report.errors.push("non-finite grid coordinates".into());
        return report;
    }
    let longest = (0..3)
        .map(|k| norm(sub(p[(k + 1) % 3], p[k])))
        .fold(0.0, f64::max);
    let (area, _) = tria_area_centroid(p);
    if longest == 0.0 || area <= ZERO_AREA_REL * longest * longest {
        report.errors.push(format!(
            "zero area (grids {} {} {} are coincident or collinear)",
            nodes[0], nodes[1], nodes[2]
        ));
        return report;
    }
    let n = cross(sub(p[1], p[0]), sub(p[2], p[0]));
    let n = scale(n, 1.0 / norm(n));
    for k in 0..3 {
        let ang = angle_deg(sub(p[(k + 1) % 3], p[k]), sub(p[(k + 2) % 3], p[k]), n);
        if ang < TRIA_ANGLE_MIN {
            report
                .warnings
                .push(("interior angle", format!("{ang:.1}° at grid {}", nodes[k])));
        }
    }
    report
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() <= 1e-13 * a.abs().max(b.abs()).max(1.0)
    }

    #[test]
    fn unit_cube_volume_and_centroid() {
        let p: Vec<[f64; 3]> = HEXA_CORNERS
            .iter()
            .map(|c| scale(add(*c, [1., 1., 1.]), 0.5))
            .collect();
        let s = SolidShape::Hexa8.integrate(&p);
        assert!(close(s.volume, 1.0));
        assert!(s.centroid.iter().all(|c| close(*c, 0.5)));
    }

    #[test]
    fn sheared_hexa_volume_is_base_times_height() {
        // unit square base, height 2, top shifted by (0.7, 0.3): V = 2 exactly
        let mut p: Vec<[f64; 3]> = HEXA_CORNERS
            .iter()
            .map(|c| scale(add(*c, [1., 1., 1.]), 0.5))
            .collect();
        for q in p.iter_mut().skip(4) {
            *q = [q[0] + 0.7, q[1] + 0.3, 2.0];
        }
        let s = SolidShape::Hexa8.integrate(&p);
        assert!(close(s.volume, 2.0), "{}", s.volume);
        assert!(close(s.centroid[0], 0.5 + 0.35) && close(s.centroid[2], 1.0));
    }

    #[test]
    fn wedge_and_tets() {
        let w = [
            [0., 0., 0.],
            [2., 0., 0.],
            [0., 1., 0.],
            [0., 0., 3.],
            [2., 0., 3.],
            [0., 1., 3.],
        ];
        let s = SolidShape::Penta6.integrate(&w);
        assert!(close(s.volume, 3.0));
        assert!(
            close(s.centroid[0], 2.0 / 3.0)
                && close(s.centroid[1], 1.0 / 3.0)
                && close(s.centroid[2], 1.5)
        );
        let t = [[0., 0., 0.], [1., 0., 0.], [0., 1., 0.], [0., 0., 1.]];
        let s = SolidShape::Tetra4.integrate(&t);
        assert!(close(s.volume, 1.0 / 6.0) && s.centroid.iter().all(|c| close(*c, 0.25)));
        let mut t10 = t.to_vec();
        for (a, b) in TETRA10_EDGES {
            t10.push(scale(add(t[a], t[b]), 0.5));
        }
        let s = SolidShape::Tetra10.integrate(&t10);
        assert!(close(s.volume, 1.0 / 6.0) && s.centroid.iter().all(|c| close(*c, 0.25)));
    }

    #[test]
    fn reversed_tetra_is_an_error_naming_the_order() {
        let t = [[0., 0., 0.], [0., 1., 0.], [1., 0., 0.], [0., 0., 1.]];
        let (_, r) = check_solid(SolidShape::Tetra4, &t, &[1, 2, 3, 4]);
        assert!(r.errors[0].contains("node order is reversed"), "{r:?}");
    }

    #[test]
    fn trapezoid_quad_centroid() {
        // trapezoid with parallel sides 4 (y=0) and 2 (y=1): area 3, ȳ = h(a+2b)/(3(a+b)) = 4/9
        let p = [[0., 0., 0.], [4., 0., 0.], [3., 1., 0.], [1., 1., 0.]];
        let (a, c) = quad_area_centroid(&p);
        assert!(
            close(a, 3.0) && close(c[0], 2.0) && close(c[1], 4.0 / 9.0),
            "{a} {c:?}"
        );
        assert!(check_quad(&p, &[1, 2, 3, 4]).errors.is_empty());
    }

    #[test]
    fn bow_tie_and_collinear_quads_are_errors() {
        let bow = [[0., 0., 0.], [1., 0., 0.], [0., 1., 0.], [1., 1., 0.]];
        assert!(!check_quad(&bow, &[1, 2, 3, 4]).errors.is_empty());
        let line = [[0., 0., 0.], [1., 0., 0.], [2., 0., 0.], [3., 0., 0.]];
        assert!(check_quad(&line, &[1, 2, 3, 4]).errors[0].contains("zero area"));
    }
}
