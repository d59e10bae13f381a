//! Consistent grid loads of a load along a beam (`PLOAD1`): a force or moment, concentrated at a
//! point of the element's axis or distributed linearly over a stretch of it.
//!
//! The load acts on the axis between the element's ends (grids plus offsets), at positions
//! measured from end A as fractions ξ of the length L. Its work on the element's displacement
//! field gives the end loads: linear interpolation for axial force and torsion, the cubic Hermite
//! functions N₁ … N₄ of the Euler–Bernoulli element for transverse forces, and their slopes for
//! bending moments (θ_z = v′, θ_y = −w′). A distributed load is integrated by three-point Gauss,
//! exact for a cubic times a linear intensity. The end loads move to the grids through the rigid
//! offsets (M_grid = M_end + w × F). With shear flexibility (K1/K2) these are still the
//! Euler–Bernoulli loads: exact for loads over the whole length, within O(Φ) of the Timoshenko
//! element's for a concentrated load between the ends.

use super::beam::{BeamError, LineGeometry, element_axes, length};
use crate::geometry::vec3::{add, cross, dot, norm, scale};

/// Force or moment.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LineLoadKind {
    Force,
    Moment,
}

/// The system the load's direction is given in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LoadAxes {
    Basic,
    /// The element's axes (x from A to B, y in the plane of the orientation vector).
    Element,
}

/// A load along a line element.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LineLoad {
    pub kind: LineLoadKind,
    /// Unit direction, in `axes`.
    pub direction: [f64; 3],
    pub axes: LoadAxes,
    /// Positions from end A as fractions of the length, `at[0] ≤ at[1]`; equal: concentrated.
    pub at: [f64; 2],
    /// Intensities per unit length at the two positions; a concentrated load is `values[0]`.
    pub values: [f64; 2],
    /// Intensities per unit of the length projected on a plane normal to the direction: the
    /// load per unit length is P·√(1 − (x·d)²), x the element axis (for an element direction
    /// x·d is its x component: 0 for y and z, so P unchanged; 1 for x, so no load).
    pub projected: bool,
}

/// Forces and moments on grids A and B, in the basic system.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct GridLoads {
    pub force: [[f64; 3]; 2],
    pub moment: [[f64; 3]; 2],
}

/// Three-point Gauss–Legendre on [−1, 1].
const GAUSS: [(f64, f64); 3] = [
    (-0.774_596_669_241_483_4, 5.0 / 9.0),
    (0.0, 8.0 / 9.0),
    (0.774_596_669_241_483_4, 5.0 / 9.0),
];

/// Local DOFs (u v w θx θy θz at A, then B) and the work of a unit load along element axis `k`
/// at ξ on each.
fn work_weights(kind: LineLoadKind, k: usize, xi: f64, l: f64) -> Vec<(usize, f64)> {
    let (x2, x3) = (xi * xi, xi * xi * xi);
    let n = [
        1.0 - 3.0 * x2 + 2.0 * x3,
        l * (xi - 2.0 * x2 + x3),
        3.0 * x2 - 2.0 * x3,
        l * (x3 - x2),
    ];
    let dn = [
        (6.0 * x2 - 6.0 * xi) / l,
        1.0 - 4.0 * xi + 3.0 * x2,
        (6.0 * xi - 6.0 * x2) / l,
        3.0 * x2 - 2.0 * xi,
    ];
    match (kind, k) {
        (LineLoadKind::Force, 0) => vec![(0, 1.0 - xi), (6, xi)],
        (LineLoadKind::Force, 1) => vec![(1, n[0]), (5, n[1]), (7, n[2]), (11, n[3])],
        (LineLoadKind::Force, _) => vec![(2, n[0]), (4, -n[1]), (8, n[2]), (10, -n[3])],
        (LineLoadKind::Moment, 0) => vec![(3, 1.0 - xi), (9, xi)],
        (LineLoadKind::Moment, 1) => vec![(2, -dn[0]), (4, dn[1]), (8, -dn[2]), (10, dn[3])],
        (LineLoadKind::Moment, _) => vec![(1, dn[0]), (5, dn[1]), (7, dn[2]), (11, dn[3])],
    }
}

/// The consistent grid loads of `load` on the element placed by `g`.
pub fn grid_loads(g: &LineGeometry, load: &LineLoad) -> Result<GridLoads, BeamError> {
    let axes = element_axes(g)?;
    let l = length(g)?;
    let local = match load.axes {
        LoadAxes::Element => load.direction,
        LoadAxes::Basic => axes.map(|a| dot(a, load.direction)),
    };
    // the cosine between the element axis and the load direction, in either frame
    let projection = if load.projected {
        let c = local[0] / norm(local);
        (1.0 - c * c).max(0.0).sqrt()
    } else {
        1.0
    };
    // (ξ, amount) points: the concentrated load, or Gauss points weighted by the stretch's length
    let [x1, x2] = load.at;
    let points: Vec<(f64, f64)> = if x2 > x1 {
        let half = 0.5 * (x2 - x1);
        GAUSS
            .iter()
            .map(|&(s, w)| {
                let t = 0.5 * (1.0 + s);
                let value = load.values[0] + t * (load.values[1] - load.values[0]);
                (x1 + half * (1.0 + s), w * half * l * value * projection)
            })
            .collect()
    } else {
        vec![(x1, load.values[0])]
    };
    let mut f = [0.0; 12];
    for (xi, amount) in points {
        for (k, &c) in local.iter().enumerate() {
            for (dof, w) in work_weights(load.kind, k, xi, l) {
                f[dof] += w * c * amount;
            }
        }
    }
    let to_basic =
        |v: &[f64]| -> [f64; 3] { (0..3).fold([0.0; 3], |acc, k| add(acc, scale(axes[k], v[k]))) };
    let mut out = GridLoads::default();
    for end in 0..2 {
        let force = to_basic(&f[6 * end..6 * end + 3]);
        let moment = to_basic(&f[6 * end + 3..6 * end + 6]);
        out.force[end] = force;
        out.moment[end] = add(moment, cross(g.offsets[end], force));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::vec3::sub;

    fn close(a: f64, b: f64, tol: f64) {
        assert!((a - b).abs() <= tol, "{a:e} vs {b:e}");
    }

    fn geometry() -> LineGeometry {
        LineGeometry {
            grids: [[0.1, -0.2, 0.3], [1.3, 0.7, -0.1]],
            offsets: [[0.02, 0.0, -0.01], [0.0, 0.03, 0.01]],
            orientation: Some([0.2, -0.4, 1.0]),
        }
    }

    fn load(kind: LineLoadKind, axes: LoadAxes, at: [f64; 2], values: [f64; 2]) -> LineLoad {
        LineLoad {
            kind,
            direction: [0.48, 0.6, 0.64],
            axes,
            at,
            values,
            projected: false,
        }
    }

    /// Uniform transverse force q over the whole length along element y: q L/2 at each end and
    /// the fixed-end moments ±q L²/12 about z.
    #[test]
    fn uniform_transverse_force_gives_the_fixed_end_loads() {
        let g = LineGeometry {
            grids: [[0.0; 3], [2.0, 0.0, 0.0]],
            offsets: [[0.0; 3]; 2],
            orientation: Some([0.0, 1.0, 0.0]),
        };
        let mut q = load(
            LineLoadKind::Force,
            LoadAxes::Element,
            [0.0, 1.0],
            [3.0, 3.0],
        );
        q.direction = [0.0, 1.0, 0.0];
        let r = grid_loads(&g, &q).unwrap();
        close(r.force[0][1], 3.0, 1e-12);
        close(r.force[1][1], 3.0, 1e-12);
        close(r.moment[0][2], 1.0, 1e-12);
        close(r.moment[1][2], -1.0, 1e-12);
        // along z the moments are about −y (θ_y = −w′)
        q.direction = [0.0, 0.0, 1.0];
        let r = grid_loads(&g, &q).unwrap();
        close(r.moment[0][1], -1.0, 1e-12);
        close(r.moment[1][1], 1.0, 1e-12);
    }

    /// Whatever the load, the grid loads are statically equivalent to it: the same resultant and
    /// the same moment about grid A (forces at their points of the axis between the offset ends).
    #[test]
    fn grid_loads_are_statically_equivalent_to_the_load() {
        let g = geometry();
        let ends = [add(g.grids[0], g.offsets[0]), add(g.grids[1], g.offsets[1])];
        let axis = sub(ends[1], ends[0]);
        let at = |xi: f64| add(ends[0], scale(axis, xi));
        for kind in [LineLoadKind::Force, LineLoadKind::Moment] {
            for axes in [LoadAxes::Basic, LoadAxes::Element] {
                for (span, values) in [([0.3, 0.3], [5.0, 0.0]), ([0.2, 0.9], [2.0, -7.0])] {
                    let q = load(kind, axes, span, values);
                    let r = grid_loads(&g, &q).unwrap();
                    let d = match axes {
                        LoadAxes::Basic => q.direction,
                        LoadAxes::Element => {
                            let e = element_axes(&g).unwrap();
                            (0..3).fold([0.0; 3], |acc, k| add(acc, scale(e[k], q.direction[k])))
                        }
                    };
                    // resultant and moment about grid A of the applied load, by a fine midpoint rule
                    let (mut total, mut about_a) = ([0.0; 3], [0.0; 3]);
                    let mut add_point = |xi: f64, amount: f64| {
                        let v = scale(d, amount);
                        match kind {
                            LineLoadKind::Force => {
                                total = add(total, v);
                                about_a = add(about_a, cross(sub(at(xi), g.grids[0]), v));
                            }
                            LineLoadKind::Moment => about_a = add(about_a, v),
                        }
                    };
                    if span[1] > span[0] {
                        let n = 20_000;
                        let len = norm(axis) * (span[1] - span[0]);
                        for i in 0..n {
                            let t = (i as f64 + 0.5) / n as f64;
                            let value = values[0] + t * (values[1] - values[0]);
                            add_point(span[0] + t * (span[1] - span[0]), value * len / n as f64);
                        }
                    } else {
                        add_point(span[0], values[0]);
                    }
                    let mut got = add(r.moment[0], r.moment[1]);
                    got = add(got, cross(sub(g.grids[1], g.grids[0]), r.force[1]));
                    let resultant = add(r.force[0], r.force[1]);
                    for c in 0..3 {
                        // midpoint rule: error O(1/n²) of loads of order 10
                        close(resultant[c], total[c], 1e-7);
                        close(got[c], about_a[c], 1e-7);
                    }
                }
            }
        }
    }

    /// A projected load on an element at 30° to the load direction carries P·sin 30° per length.
    #[test]
    fn projected_intensity_scales_with_the_sine_of_the_angle() {
        let g = LineGeometry {
            grids: [[0.0; 3], [0.5, 0.75f64.sqrt(), 0.0]],
            offsets: [[0.0; 3]; 2],
            orientation: Some([0.0, 0.0, 1.0]),
        };
        let mut q = load(LineLoadKind::Force, LoadAxes::Basic, [0.0, 1.0], [4.0, 4.0]);
        q.direction = [0.0, 1.0, 0.0];
        q.projected = true;
        let r = grid_loads(&g, &q).unwrap();
        close(r.force[0][1] + r.force[1][1], 4.0 * 0.5, 1e-12);
    }

    /// Projected loads in the element frame: the length projected on the plane normal to the
    /// element's own y (or z) axis is the whole length, so FYE is unchanged; on the plane normal
    /// to its x axis it is zero, so FXE carries nothing.
    #[test]
    fn projected_element_loads_keep_transverse_and_drop_axial_intensities() {
        let g = geometry();
        for (axis, expected) in [(1, 1.0), (2, 1.0), (0, 0.0)] {
            let mut q = load(
                LineLoadKind::Force,
                LoadAxes::Element,
                [0.1, 0.8],
                [2.0, 3.0],
            );
            q.direction = [0.0; 3];
            q.direction[axis] = 1.0;
            let plain = grid_loads(&g, &q).unwrap();
            q.projected = true;
            let projected = grid_loads(&g, &q).unwrap();
            for end in 0..2 {
                for k in 0..3 {
                    close(
                        projected.force[end][k],
                        expected * plain.force[end][k],
                        1e-12,
                    );
                    close(
                        projected.moment[end][k],
                        expected * plain.moment[end][k],
                        1e-12,
                    );
                }
            }
        }
    }
}
