use super::*;
use faer::linalg::solvers::Solve;
use std::f64::consts::{FRAC_PI_2, FRAC_PI_4, PI};

/// A quarter circle in the x–y plane: centre at the origin, A = (R, 0, 0), B = (0, R, 0).
fn quarter(r: f64, rule: ArcRule, v: [f64; 3]) -> Arc {
    Arc::new([r, 0.0, 0.0], [0.0, r, 0.0], v, rule).unwrap()
}

/// An arc of 2 rad in a general position, off every basic plane.
fn skew_arc() -> Arc {
    Arc::new(
        [0.3, -0.2, 1.0],
        [1.1, 0.4, 0.2],
        [0.2, 1.0, 0.5],
        ArcRule::Angle(2.0),
    )
    .unwrap()
}

const SECTION: BendSection = BendSection {
    a: 0.5,
    i1: 0.08,
    i2: 0.05,
    j: 0.03,
    k1: Some(0.8),
    k2: Some(0.7),
    nsm: 0.0,
};

/// Tip displacement (basic) of the arc clamped at A under a unit load `load` at B, from the
/// 12×12 stiffness (the A rows and columns removed).
fn tip_response(arc: &Arc, s: &BendSection, e: f64, g: f64, load: [f64; 6]) -> [f64; 6] {
    let k = stiffness(arc, s, e, g).unwrap();
    let kbb = Mat::from_fn(6, 6, |i, j| k[(6 + i, 6 + j)]);
    let rhs = Mat::from_fn(6, 1, |i, _| load[i]);
    let x = kbb.partial_piv_lu().solve(&rhs);
    std::array::from_fn(|i| x[(i, 0)])
}

#[test]
fn every_geom_rule_finds_the_same_quarter_circle() {
    let r = 2.0;
    // GEOM 1: v from A towards the centre; 2: v along the tangent at A (+y);
    // 3, 4: v on the bulge side of the chord (away from the centre)
    let bulge = [1.0, 1.0, 0.0];
    let arcs = [
        quarter(r, ArcRule::CentreAlongV, [-1.0, 0.0, 0.0]),
        quarter(r, ArcRule::TangentAlongV, [0.0, 1.0, 0.0]),
        quarter(r, ArcRule::Radius(r), bulge),
        quarter(r, ArcRule::Angle(FRAC_PI_2), bulge),
    ];
    for arc in arcs {
        assert!(norm(arc.centre) < 1e-14, "{arc:?}");
        assert!((arc.radius - r).abs() < 1e-14, "{arc:?}");
        assert!((arc.angle - FRAC_PI_2).abs() < 1e-14, "{arc:?}");
        assert!((arc.normal[2] - 1.0).abs() < 1e-14, "{arc:?}");
        let mid = arc.point(FRAC_PI_4);
        assert!((mid[0] - r / 2f64.sqrt()).abs() < 1e-14, "{mid:?}");
        let end = arc.point(arc.angle);
        assert!(norm(sub(end, [0.0, r, 0.0])) < 1e-14, "{end:?}");
    }
}

#[test]
fn major_arcs_of_geom_2_and_4() {
    // the tangent at A = (R, 0) along −y: the arc leaves A away from B = (0, R) and comes
    // back, three quarters of the circle centred at the origin
    let r = 1.0;
    let a = [r, 0.0, 0.0];
    let b = [0.0, r, 0.0];
    let by_tangent = Arc::new(a, b, [0.0, -1.0, 0.0], ArcRule::TangentAlongV).unwrap();
    let by_angle = Arc::new(a, b, [-1.0, -1.0, 0.0], ArcRule::Angle(1.5 * PI)).unwrap();
    for arc in [by_tangent, by_angle] {
        assert!((arc.angle - 1.5 * PI).abs() < 1e-13, "{arc:?}");
        assert!(norm(arc.centre) < 1e-13, "{arc:?}");
        // the arc passes through (−R, 0) and (0, −R)
        let p = arc.point(PI);
        assert!(norm(sub(p, [-r, 0.0, 0.0])) < 1e-13, "{p:?}");
    }
}

#[test]
fn bad_placements_are_errors() {
    let (a, b) = ([0.0; 3], [1.0, 0.0, 0.0]);
    assert_eq!(
        Arc::new(a, b, [2.0, 0.0, 0.0], ArcRule::TangentAlongV),
        Err(BendError::OrientationAlongChord)
    );
    assert_eq!(
        Arc::new(a, b, [0.0, 1.0, 0.0], ArcRule::CentreAlongV),
        Err(BendError::CentreAtInfinity)
    );
    assert_eq!(
        Arc::new(a, b, [0.0, 1.0, 0.0], ArcRule::Radius(0.4)),
        Err(BendError::RadiusTooSmall {
            radius: 0.4,
            half_chord: 0.5
        })
    );
    assert_eq!(
        Arc::new(a, a, [0.0, 1.0, 0.0], ArcRule::Radius(1.0)),
        Err(BendError::ZeroLength)
    );
}

/// Reference: Castigliano's theorem for a quarter-circle cantilever (Roark, *Formulas for
/// Stress and Strain*, curved beams; every term integrated in closed form here). Clamped at
/// A = (R, 0), a load P along y at B = (0, R) gives at the section φ: M_n = −P R cos φ,
/// N = P cos φ, V_r = P sin φ, so δ_y = (π/4) P (R³/(E I1) + R/(E A) + R/(K1 G A)).
/// A load P along z gives M_r = P R cos φ, T = P R (1 − sin φ), V_n = P, so
/// δ_z = P (π R³/(4 E I2) + (3π/4 − 2) R³/(G J) + π R/(2 K2 G A)).
/// The element is exact for this model: the tolerance is round-off of the quadrature and the
/// 6×6 inversions (1e-12 relative).
#[test]
fn quarter_circle_cantilever_matches_castigliano() {
    let (r, e, g) = (3.0, 200.0, 80.0);
    let s = SECTION;
    let arc = quarter(r, ArcRule::CentreAlongV, [-1.0, 0.0, 0.0]);
    let in_plane = tip_response(&arc, &s, e, g, [0.0, 1.0, 0.0, 0.0, 0.0, 0.0]);
    let dy = FRAC_PI_4 * (r.powi(3) / (e * s.i1) + r / (e * s.a) + r / (s.k1.unwrap() * g * s.a));
    assert!(
        (in_plane[1] - dy).abs() < 1e-12 * dy,
        "{} vs {dy}",
        in_plane[1]
    );
    // in-plane: no out-of-plane motion
    for i in [2, 3, 4] {
        assert!(in_plane[i].abs() < 1e-12 * dy, "{in_plane:?}");
    }
    let out_of_plane = tip_response(&arc, &s, e, g, [0.0, 0.0, 1.0, 0.0, 0.0, 0.0]);
    let dz = PI * r.powi(3) / (4.0 * e * s.i2)
        + (0.75 * PI - 2.0) * r.powi(3) / (g * s.j)
        + PI * r / (2.0 * s.k2.unwrap() * g * s.a);
    assert!(
        (out_of_plane[2] - dz).abs() < 1e-12 * dz,
        "{} vs {dz}",
        out_of_plane[2]
    );
}

/// Reference: a moment about the arc's normal at the tip bends a circular arc uniformly (M_n
/// constant, no other resultant), so each element ds turns by κ ds, κ = M/(E I1), and moves the
/// tip by κ ds n × (p_B − p). For the half circle from (R, 0) through (0, R) to (−R, 0) the
/// tip turns by κ R π and moves by κ R² (2, −π).
#[test]
fn end_moment_on_a_half_circle() {
    let (r, e, g) = (1.5, 70.0, 26.0);
    let s = SECTION;
    let arc = Arc::new(
        [r, 0.0, 0.0],
        [-r, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        ArcRule::TangentAlongV,
    )
    .unwrap();
    assert!((arc.angle - PI).abs() < 1e-14);
    let x = tip_response(&arc, &s, e, g, [0.0, 0.0, 0.0, 0.0, 0.0, 1.0]);
    let curvature = 1.0 / (e * s.i1);
    assert!(
        (x[5] - curvature * r * PI).abs() < 1e-12 * curvature * r * PI,
        "{x:?}"
    );
    // p_B − p = (−R − R cos φ, −R sin φ) and z × (a, b) = (−b, a)
    let (ux, uy) = (2.0 * curvature * r * r, -PI * curvature * r * r);
    assert!((x[0] - ux).abs() < 1e-12 * ux.abs(), "{x:?} vs {ux}");
    assert!((x[1] - uy).abs() < 1e-12 * uy.abs(), "{x:?} vs {uy}");
}

#[test]
fn stiffness_is_symmetric_with_six_rigid_modes() {
    let arc = skew_arc();
    let k = stiffness(&arc, &SECTION, 100.0, 40.0).unwrap();
    let scale = (0..12).map(|i| k[(i, i)].abs()).fold(0.0, f64::max);
    for i in 0..12 {
        for j in 0..12 {
            assert!((k[(i, j)] - k[(j, i)]).abs() < 1e-12 * scale);
        }
    }
    let (a, b) = (arc.point(0.0), arc.point(arc.angle));
    // rigid translation along each axis and rotation about each axis through the origin
    for mode in 0..6 {
        let u: Vec<f64> = [a, b]
            .iter()
            .flat_map(|p| {
                let mut d = [0.0; 6];
                if mode < 3 {
                    d[mode] = 1.0;
                } else {
                    let mut w = [0.0; 3];
                    w[mode - 3] = 1.0;
                    let t = cross(w, *p);
                    d[..3].copy_from_slice(&t);
                    d[mode] = 1.0;
                }
                d
            })
            .collect();
        for i in 0..12 {
            let f: f64 = (0..12).map(|j| k[(i, j)] * u[j]).sum();
            assert!(f.abs() < 1e-10 * scale, "mode {mode} row {i}: {f}");
        }
    }
}

#[test]
fn affine_parts_and_lumped_mass() {
    let arc = quarter(2.0, ArcRule::Radius(2.0), [1.0, 1.0, 0.0]);
    let fixed = stiffness(&arc, &SECTION, 210.0, 84.0).unwrap();
    let parts = affine_stiffness(&arc, &SECTION, Elasticity::YoungsModulus { g_per_e: 0.4 })
        .unwrap()
        .parts;
    assert_eq!(parts.len(), 1);
    assert_eq!(parts[0].0, Coefficient::E);
    for i in 0..12 {
        for j in 0..12 {
            assert!(
                (210.0 * parts[0].1[(i, j)] - fixed[(i, j)]).abs() < 1e-9 * fixed[(0, 0)].abs()
            );
        }
    }
    assert_eq!(
        affine_stiffness(&arc, &SECTION, Elasticity::Separate).unwrap_err(),
        BendError::SeparateModuli
    );
    let s = BendSection {
        nsm: 0.25,
        ..SECTION
    };
    let m = affine_mass(&arc, &s, Density::Fixed { rho: 3.0 });
    let total = (3.0 * s.a + s.nsm) * 2.0 * FRAC_PI_2;
    assert!((m.parts[0].1[(0, 0)] - total / 2.0).abs() < 1e-14);
    assert!((m.parts[0].1[(8, 8)] - total / 2.0).abs() < 1e-14);
    assert_eq!(m.parts[0].1[(3, 3)], 0.0);
    let split = affine_mass(&arc, &s, Density::Parameter);
    assert_eq!(split.parts.len(), 2);
}

/// The equivalent loads of a load along the arc balance it (force, and moment about the
/// origin), and a force at an end goes to that end alone.
#[test]
fn arc_loads_balance_and_end_loads_stay_at_their_end() {
    let arc = skew_arc();
    let (e, g) = (100.0, 40.0);
    let direction = [0.6, 0.0, 0.8];
    let distributed = ArcLoad {
        moment: false,
        direction,
        at: [0.2, 0.9],
        values: [3.0, -1.0],
    };
    let loads = grid_loads(&arc, &SECTION, e, g, &distributed).unwrap();
    // total force: ∫ (3 + t (−1 − 3)) ds over 0.7 of the arc, t from 0 to 1
    let total = 0.7 * arc.length() * (3.0 - 2.0);
    // its moment about the origin: ∫ p(φ) × d q(φ) ds
    let mut moment = [0.0; 3];
    for (phi, w) in arc.quadrature(0.2 * arc.angle, 0.9 * arc.angle) {
        let t = (phi / arc.angle - 0.2) / 0.7;
        let m = cross(arc.point(phi), scale(direction, w * (3.0 - 4.0 * t)));
        moment = add(moment, m);
    }
    let (pa, pb) = (arc.point(0.0), arc.point(arc.angle));
    for k in 0..3 {
        let f = loads[k] + loads[6 + k];
        assert!((f - total * direction[k]).abs() < 1e-12, "{loads:?}");
    }
    let fa = [loads[0], loads[1], loads[2]];
    let fb = [loads[6], loads[7], loads[8]];
    let m_sum = add(
        add([loads[3], loads[4], loads[5]], cross(pa, fa)),
        add([loads[9], loads[10], loads[11]], cross(pb, fb)),
    );
    for k in 0..3 {
        assert!(
            (m_sum[k] - moment[k]).abs() < 1e-12,
            "{m_sum:?} vs {moment:?}"
        );
    }
    for (end, at) in [(0, 0.0), (1, 1.0)] {
        let point = ArcLoad {
            moment: false,
            direction,
            at: [at, at],
            values: [5.0, 0.0],
        };
        let loads = grid_loads(&arc, &SECTION, e, g, &point).unwrap();
        for (i, v) in loads.iter().enumerate() {
            let want = if i / 6 == end && i % 6 < 3 {
                5.0 * direction[i % 3]
            } else {
                0.0
            };
            assert!((v - want).abs() < 1e-10, "end {end}: {loads:?}");
        }
    }
}
