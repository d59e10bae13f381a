//! Consistent nodal forces of a pressure on an element face (`PLOAD4`, `PLOAD2`, `PLOAD`):
//! F_a = ∫ N_a(ξ) p(ξ) d(ξ) dA over the face, with p interpolated from its corner values by the
//! face's corner (linear or bilinear) shape functions and d either the face's unit normal
//! (n dA = x_ξ × x_η dξ dη, oriented by the node order) or a fixed unit direction.
//!
//! Faces: 3-node triangles and 4-node quadrilaterals (the shells, the faces of CHEXA, CPENTA,
//! CTETRA 4), the 6-node triangles of CTETRA 10 and CTRIA6 (corners then mid-sides 1–2, 2–3,
//! 3–1) and the 8-node CQUAD8 (corners, then mid-sides 1–2, 2–3, 3–4, 4–1; shape functions of
//! [`crate::fe::shell_quadratic`]); the pressure is interpolated from the corners. The rules
//! integrate the pressure products exactly for flat faces (straight-sided for the quadratic
//! ones) and the bilinear warp of a quadrilateral: 3 × 3 Gauss points (degree 5 per direction, beyond the 3 a pressure needs, for
//! the non-polynomial |x_ξ × x_η| of a fixed direction on a warped face), the 3-point (degree 2)
//! and 7-point (degree 5) triangle rules.

use crate::geometry::vec3::{cross, norm, scale};

/// How the load is directed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Direction {
    /// Along the face normal of the node order (x_ξ × x_η): a pressure.
    Normal,
    /// Along this unit vector, |p| per area with the sign of p.
    Fixed([f64; 3]),
}

/// The consistent nodal forces of corner pressures `p` (one per corner) on the face through
/// `x` (3, 4 or 6 points), in the order of `x`.
pub fn face_forces(x: &[[f64; 3]], p: &[f64], direction: Direction) -> Vec<[f64; 3]> {
    let mut f = vec![[0.0; 3]; x.len()];
    for (xi, eta, w) in rule(x.len()) {
        let (n, dn_dxi, dn_deta) = shape(x.len(), xi, eta);
        let corners = if x.len() == 4 || x.len() == 8 { 4 } else { 3 };
        let (c, _, _) = shape(corners, xi, eta);
        let pressure: f64 = c.iter().zip(p).map(|(ci, pi)| ci * pi).sum();
        let tangent = |d: &[f64]| -> [f64; 3] {
            std::array::from_fn(|k| d.iter().zip(x).map(|(di, xi)| di * xi[k]).sum())
        };
        let area_vector = cross(tangent(&dn_dxi), tangent(&dn_deta));
        let load = match direction {
            Direction::Normal => scale(area_vector, pressure * w),
            Direction::Fixed(d) => scale(d, pressure * norm(area_vector) * w),
        };
        for (fa, na) in f.iter_mut().zip(&n) {
            for k in 0..3 {
                fa[k] += na * load[k];
            }
        }
    }
    f
}

/// Shape functions and their ξ, η derivatives of a 3-, 4- or 6-node face at (ξ, η): triangles
/// in area coordinates (L1 = 1 − ξ − η, L2 = ξ, L3 = η), the quadrilateral on [−1, 1]².
fn shape(nodes: usize, xi: f64, eta: f64) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    match nodes {
        3 => (
            vec![1.0 - xi - eta, xi, eta],
            vec![-1.0, 1.0, 0.0],
            vec![-1.0, 0.0, 1.0],
        ),
        4 => {
            let s = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)];
            (
                s.iter()
                    .map(|(a, b)| 0.25 * (1.0 + a * xi) * (1.0 + b * eta))
                    .collect(),
                s.iter().map(|(a, b)| 0.25 * a * (1.0 + b * eta)).collect(),
                s.iter().map(|(a, b)| 0.25 * b * (1.0 + a * xi)).collect(),
            )
        }
        6 => crate::fe::shell_quadratic::Quadratic::Tria6.shape([xi, eta]),
        8 => crate::fe::shell_quadratic::Quadratic::Quad8.shape([xi, eta]),
        _ => unreachable!("faces have 3, 4, 6 or 8 nodes"),
    }
}

/// Integration points (ξ, η, weight): 3 × 3 Gauss on the quadrilateral; on the triangle (weights
/// including its reference area ½) the 3-point rule exact to degree 2 for linear faces and the
/// 7-point rule exact to degree 5 (Dunavant) for the 6-node face.
fn rule(nodes: usize) -> Vec<(f64, f64, f64)> {
    match nodes {
        4 | 8 => {
            let (g, w) = ((0.6f64).sqrt(), [5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0]);
            let points = [-g, 0.0, g];
            (0..9)
                .map(|k| (points[k % 3], points[k / 3], w[k % 3] * w[k / 3]))
                .collect()
        }
        3 => [
            (1.0 / 6.0, 1.0 / 6.0),
            (2.0 / 3.0, 1.0 / 6.0),
            (1.0 / 6.0, 2.0 / 3.0),
        ]
        .map(|(a, b)| (a, b, 1.0 / 6.0))
        .to_vec(),
        6 => super::solid_shape::triangle_seven(),
        _ => unreachable!("faces have 3, 4 or 6 nodes"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn total(f: &[[f64; 3]]) -> [f64; 3] {
        f.iter()
            .fold([0.0; 3], |s, v| std::array::from_fn(|k| s[k] + v[k]))
    }

    fn close(a: [f64; 3], b: [f64; 3], tol: f64) -> bool {
        (0..3).all(|k| (a[k] - b[k]).abs() <= tol)
    }

    /// A uniform pressure on a flat face: the resultant is p·A·n̂ and, for the linear faces,
    /// the nodal shares are the textbook ones (p·A/3 on a triangle, p·A/4 on a parallelogram;
    /// the 6-node triangle's corners carry 0 and its mid-sides p·A/3).
    #[test]
    fn uniform_pressure_shares() {
        let tri = [[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        let f = face_forces(&tri, &[3.0; 3], Direction::Normal);
        assert!(f.iter().all(|v| close(*v, [0.0, 0.0, 1.0], 1e-15)), "{f:?}");
        let quad = [
            [0.0, 0.0, 0.0],
            [2.0, 0.0, 0.0],
            [3.0, 1.0, 0.0],
            [1.0, 1.0, 0.0],
        ];
        let f = face_forces(&quad, &[4.0; 4], Direction::Normal);
        assert!(f.iter().all(|v| close(*v, [0.0, 0.0, 2.0], 1e-14)), "{f:?}");
        let mid = |a: [f64; 3], b: [f64; 3]| std::array::from_fn(|k| 0.5 * (a[k] + b[k]));
        let tri6 = [
            tri[0],
            tri[1],
            tri[2],
            mid(tri[0], tri[1]),
            mid(tri[1], tri[2]),
            mid(tri[2], tri[0]),
        ];
        let f = face_forces(&tri6, &[3.0; 3], Direction::Normal);
        assert!(f[..3].iter().all(|v| close(*v, [0.0; 3], 1e-15)), "{f:?}");
        assert!(
            f[3..].iter().all(|v| close(*v, [0.0, 0.0, 1.0], 1e-14)),
            "{f:?}"
        );
    }

    /// A linearly varying pressure on a warped quadrilateral and on a 6-node triangle with a
    /// curved edge: the resultant equals a fine midpoint-rule integral of p·(x_ξ × x_η) and the
    /// moment about the origin that of p·x × n (computed here on a 400 × 400 grid, error
    /// O(1/400²) ~ 1e-6 relative, hence 1e-5); a fixed direction gives ∫|p| dA along it.
    #[test]
    fn linear_pressure_on_curved_faces_matches_a_fine_quadrature() {
        let quad = [
            [0.0, 0.0, 0.0],
            [2.0, 0.1, 0.3],
            [2.2, 1.5, -0.2],
            [-0.1, 1.2, 0.4],
        ];
        let p = [1.0, 2.0, 4.0, 3.0];
        let f = face_forces(&quad, &p, Direction::Normal);
        let steps = 400;
        let (mut force, mut moment, mut area_load) = ([0.0; 3], [0.0; 3], 0.0);
        for i in 0..steps {
            for j in 0..steps {
                let (xi, eta) = (
                    -1.0 + (2 * i + 1) as f64 / steps as f64,
                    -1.0 + (2 * j + 1) as f64 / steps as f64,
                );
                let (n, dxi, deta) = shape(4, xi, eta);
                let at = |w: &[f64]| -> [f64; 3] {
                    std::array::from_fn(|k| w.iter().zip(&quad).map(|(a, x)| a * x[k]).sum())
                };
                let pressure: f64 = n.iter().zip(&p).map(|(a, b)| a * b).sum();
                let da = cross(at(&dxi), at(&deta));
                let w = (2.0 / steps as f64).powi(2);
                let load = scale(da, pressure * w);
                let arm = cross(at(&n), load);
                for k in 0..3 {
                    force[k] += load[k];
                    moment[k] += arm[k];
                }
                area_load += pressure * norm(da) * w;
            }
        }
        let m = f.iter().zip(&quad).fold([0.0; 3], |s, (fa, xa)| {
            let c = cross(*xa, *fa);
            std::array::from_fn(|k| s[k] + c[k])
        });
        assert!(
            close(total(&f), force, 1e-5 * norm(force)),
            "{:?} vs {force:?}",
            total(&f)
        );
        assert!(close(m, moment, 1e-5 * norm(moment)), "{m:?} vs {moment:?}");
        let d = [0.6, 0.0, 0.8];
        let fixed = face_forces(&quad, &p, Direction::Fixed(d));
        let err = norm(std::array::from_fn(|k| total(&fixed)[k] - d[k] * area_load));
        // |x_ξ × x_η| of the warped face is not a polynomial: 3 × 3 Gauss leaves 2e-6 here
        assert!(err <= 1e-5 * area_load);
    }
}
