//! Element geometry: exact areas, volumes and centroids, and the shape checks.
//!
//! # Integrals
//! Every element is treated as its isoparametric map x(ξ) = Σ Nᵢ(ξ) pᵢ:
//! - `CTRIA3`: flat triangle, area ½|(p2−p1)×(p3−p1)|, centroid = node mean (both exact);
//!   with a linearly varying density (corner thicknesses) the closed-form moments are used.
//! - `CQUAD4`: bilinear surface, A = ∫|x_ξ × x_η| dξ dη and centroid ∫x dA / A with an 8×8
//!   Gauss–Legendre rule. For a planar quad |x_ξ × x_η| is linear in (ξ, η), so the rule is exact
//!   to round-off; for a warped quad the integrand is smooth and the rule converges exponentially.
//! - the solids' volumes and centroids are those of their kernels
//!   (`fe::solid::volume_and_centroid`, exact for the isoparametric maps, curved edges too).
//!
//! # Checks and thresholds
//! Solids (`check_solid`): det J of the complete element (blank mid-side grids at their edges'
//! middles) is sampled by `fe::solid::jacobian_range` at every node, the centre and the points of
//! the stiffness and mass rules, so a quadratic element with a misplaced mid-side grid is caught.
//! - a scaled Jacobian det J / (|J₁||J₂||J₃|) ≤ 10⁻¹⁰ anywhere (det J ≤ 0 included; the kernels'
//!   own limit) → **error** "inverted or degenerate element" naming the point; when det J < 0
//!   everywhere the message says the node order is reversed (mirror image numbering);
//! - Jacobian ratio min det J / max det J < [`JACOBIAN_RATIO_WARN`] → warning (very distorted).
//!
//! CQUAD8 / CTRIA6 (`check_quadratic_shell`, besides the checks of their corners below): the
//! kernel's surface Jacobian x_ξ × x_η, projected on the centre's, must stay positive at every
//! node and integration point → **error** otherwise (a misplaced mid-side grid folds the
//! surface); its min / max ratio below [`JACOBIAN_RATIO_WARN`] → warning.
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

use crate::fe::shell::ShellError;
use crate::fe::shell_quadratic::{self, Layout};
use crate::fe::solid::JacobianRange;
use crate::geometry::quadrature::gauss_legendre;
use crate::geometry::vec3::{self, add, cross, dot, norm, scale, sub};

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
/// bilinearly between the corner values. On a planar convex quad |x_ξ × x_η| is the positive
/// linear function n·(x_ξ × x_η), so the integrands are of degree ≤ 3 in each direction and
/// 2×2 Gauss–Legendre is exact; a warped or non-convex quad takes 8×8 (|x_ξ × x_η| is then not
/// polynomial). The 2×2 rule is what makes reading a mesh of 10⁶ quads cheap.
pub fn quad_weighted(p: &[[f64; 3]; 4], w: [f64; 4]) -> (f64, [f64; 3]) {
    let points = if planar_and_convex(p) { 2 } else { 8 };
    quad_weighted_with(p, w, gauss_legendre(points))
}

/// Whether the quad's corners lie in one plane (to 1e-12 of its size) and every corner turns
/// the same way about the plane's normal.
fn planar_and_convex(p: &[[f64; 3]; 4]) -> bool {
    let (d1, d2) = (sub(p[2], p[0]), sub(p[3], p[1]));
    let n = cross(d1, d2);
    let size = dot(d1, d1).max(dot(d2, d2));
    let warp = dot(sub(p[1], p[0]), cross(d1, sub(p[3], p[0])));
    warp.abs() <= 1e-12 * size * size.sqrt()
        && (0..4).all(|k| {
            let corner = cross(sub(p[(k + 1) % 4], p[k]), sub(p[(k + 3) % 4], p[k]));
            dot(corner, n) > 0.0
        })
}

/// [`quad_weighted`] with the tensor rule of `rule` in each direction.
fn quad_weighted_with(p: &[[f64; 3]; 4], w: [f64; 4], g: &[(f64, f64)]) -> (f64, [f64; 3]) {
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

/// Check a solid from its Jacobian range (`fe::solid::jacobian_range`); `nodes` are the grid
/// ids (for messages).
pub fn check_solid(range: &JacobianRange, nodes: &[u32]) -> ShapeReport {
    let mut report = ShapeReport::default();
    let grids = nodes
        .iter()
        .map(|g| g.to_string())
        .collect::<Vec<_>>()
        .join(" ");
    let [xi, eta, zeta] = range.min_xi;
    if !(range.volume.is_finite() && range.min.is_finite()) {
        report
            .errors
            .push(format!("non-finite geometry (grids {grids})"));
    } else if range.max < 0.0 {
        report.errors.push(format!(
            "inverted or degenerate element: det J < 0 everywhere (volume {:.6e}); the node order is reversed (mirror-image numbering of grids {grids})",
            range.volume
        ));
    } else if !range.is_valid() {
        report.errors.push(format!(
            "inverted or degenerate element: det J = {:.3e} at {}, (ξ, η, ζ) = ({xi:.3}, {eta:.3}, {zeta:.3}) (zero volume or folded: a corner or mid-side grid misplaced; grids {grids})",
            range.min, range.min_at
        ));
    } else {
        let ratio = range.min / range.max;
        if ratio < JACOBIAN_RATIO_WARN {
            report
                .warnings
                .push(("Jacobian ratio", format!("{ratio:.3}")));
        }
    }
    report
}

/// Check the curved surface of a CQUAD8 / CTRIA6 from its card's grid list `card_grids`
/// (corners, then mid-sides, 0 for a blank one) and the given grids' positions `xyz`: the
/// surface Jacobian must keep its sign at every node and integration point (error otherwise),
/// and a Jacobian ratio below [`JACOBIAN_RATIO_WARN`] is a warning.
pub fn check_quadratic_shell(card_grids: &[u32], xyz: &[[f64; 3]]) -> ShapeReport {
    let mut report = ShapeReport::default();
    let Some(layout) = Layout::of_card(card_grids) else {
        return report;
    };
    match shell_quadratic::jacobian_ratio(layout, xyz) {
        Ok(ratio) if ratio < JACOBIAN_RATIO_WARN => report
            .warnings
            .push(("Jacobian ratio", format!("{ratio:.3}"))),
        Ok(_) => {}
        Err(ShellError::Distorted { grid, .. }) => {
            let at = match grid.map(|k| (k, card_grids.get(k - 1).copied().unwrap_or(0))) {
                Some((k, 0)) => format!(" at the blank mid-side G{k}"),
                Some((k, g)) => format!(" at G{k} (grid {g})"),
                None => " between the grids".to_string(),
            };
            report.errors.push(format!(
                "inverted or degenerate element: the curved surface folds over{at} (det J ≤ 0: a mid-side grid too far from its edge's middle, or corners out of order)"
            ));
        }
        Err(e) => report.errors.push(e.to_string()),
    }
    report
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
    use crate::fe::solid::SolidKind;

    /// The 2×2 rule of planar convex quads equals 8×8 (itself exact there) to round-off, on a
    /// tilted, skewed trapezoid with a density varying by corner; a warped quad keeps 8×8.
    #[test]
    fn planar_quads_integrate_exactly_with_two_by_two_points() {
        let tilt = |[x, y]: [f64; 2]| [x, 0.6 * y, 0.8 * y + 0.3];
        let planar = [[0.0, 0.0], [2.0, 0.1], [1.6, 1.3], [0.3, 0.9]].map(tilt);
        let w = [1.0, 2.5, 0.7, 1.9];
        assert!(planar_and_convex(&planar));
        let (m2, c2) = quad_weighted(&planar, w);
        let (m8, c8) = quad_weighted_with(&planar, w, gauss_legendre(8));
        assert!((m2 - m8).abs() < 1e-14 * m8, "{m2} vs {m8}");
        for k in 0..3 {
            assert!((c2[k] - c8[k]).abs() < 1e-14, "{c2:?} vs {c8:?}");
        }
        let mut warped = planar;
        warped[2][2] += 0.2;
        assert!(!planar_and_convex(&warped));
        assert_eq!(
            quad_weighted(&warped, w),
            quad_weighted_with(&warped, w, gauss_legendre(8))
        );
        // a planar quad whose corner 2 is pulled inside (re-entrant) is not convex
        let dart = [[0.0, 0.0], [2.0, 0.0], [0.5, 0.5], [0.0, 2.0]].map(tilt);
        assert!(!planar_and_convex(&dart));
    }

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() <= 1e-13 * a.abs().max(b.abs()).max(1.0)
    }

    #[test]
    fn reversed_tetra_is_an_error_naming_the_order() {
        let t = [[0., 0., 0.], [0., 1., 0.], [1., 0., 0.], [0., 0., 1.]];
        let range = crate::fe::solid::jacobian_range(SolidKind::Tetra4, &t).unwrap();
        let r = check_solid(&range, &[1, 2, 3, 4]);
        assert!(r.errors[0].contains("node order is reversed"), "{r:?}");
    }

    /// A unit cube CHEXA 20 whose mid-side G9 (edge G1–G2, along x) sits at x = `m`: along that
    /// edge x'(ξ) runs from 4m − 1 at G1 to 3 − 4m at G2 (per unit ξ/2), so det J stays positive
    /// up to the quarter point m = ¾, with min/max ratio (3 − 4m)/(4m − 1) at the edge.
    fn hexa20_with_g9_at(m: f64) -> ShapeReport {
        let corners = [
            [0., 0., 0.],
            [1., 0., 0.],
            [1., 1., 0.],
            [0., 1., 0.],
            [0., 0., 1.],
            [1., 0., 1.],
            [1., 1., 1.],
            [0., 1., 1.],
        ];
        // G9–G20 on 1–2, 2–3, 3–4, 4–1, 1–5, 2–6, 3–7, 4–8, 5–6, 6–7, 7–8, 8–5
        let edges = [
            (0, 1),
            (1, 2),
            (2, 3),
            (3, 0),
            (0, 4),
            (1, 5),
            (2, 6),
            (3, 7),
        ]
        .into_iter()
        .chain([(4, 5), (5, 6), (6, 7), (7, 4)]);
        let mut p = corners.to_vec();
        p.extend(edges.map(|(a, b)| scale(add(corners[a], corners[b]), 0.5)));
        p[8][0] = m;
        let range = crate::fe::solid::jacobian_range(SolidKind::Hexa20, &p).unwrap();
        check_solid(&range, &(1..=20).collect::<Vec<u32>>())
    }

    #[test]
    fn quadratic_solid_midside_folds_or_warns() {
        let regular = hexa20_with_g9_at(0.5);
        assert!(
            regular.errors.is_empty() && regular.warnings.is_empty(),
            "{regular:?}"
        );
        // (3 − 4m)/(4m − 1) = 0.08/1.92 ≈ 0.04 at the edge: below 0.05, a warning
        let poor = hexa20_with_g9_at(0.73);
        assert!(poor.errors.is_empty(), "{poor:?}");
        assert_eq!(poor.warnings[0].0, "Jacobian ratio", "{poor:?}");
        let folded = hexa20_with_g9_at(0.9);
        assert!(folded.errors[0].contains("at corner G2"), "{folded:?}");
    }

    #[test]
    fn quadratic_shell_midside_folds_or_warns() {
        let square = |m: f64| {
            let p = [
                [0., 0., 0.],
                [1., 0., 0.],
                [1., 1., 0.],
                [0., 1., 0.],
                [0.5, 0., 0.],
                [1., m, 0.],
                [0.5, 1., 0.],
                [0., 0.5, 0.],
            ];
            check_quadratic_shell(&[1, 2, 3, 4, 5, 6, 7, 8], &p)
        };
        assert_eq!(square(0.5), ShapeReport::default());
        assert_eq!(square(0.73).warnings[0].0, "Jacobian ratio");
        assert!(square(0.9).errors[0].contains("folds over at G3 (grid 3)"));
        // a blank mid-side is at its edge's middle: the straight-edged square passes
        let blank = [
            [0., 0., 0.],
            [1., 0., 0.],
            [1., 1., 0.],
            [0., 1., 0.],
            [0.5, 0., 0.],
        ];
        let r = check_quadratic_shell(&[1, 2, 3, 4, 5, 0, 0, 0], &blank);
        assert_eq!(r, ShapeReport::default());
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
