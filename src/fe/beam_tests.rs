//! Unit tests of the line-element kernel ([`super::beam`]).

use faer::linalg::solvers::Solve;
use faer::{Mat, Side};

use super::affine::{AffineMatrix, Coefficient, CoefficientValues};
use super::beam::{
    BeamError, Density, Elasticity, LineGeometry, LineSection, MassForm, Releases, affine_mass,
    affine_stiffness,
};
use crate::geometry::vec3::{cross, sub};

const E: f64 = 2.0e11;
const G: f64 = 7.7e10;
const FREE: Releases = [[false; 6]; 2];

fn oblique() -> LineGeometry {
    LineGeometry {
        grids: [[0.1, -0.2, 0.3], [0.9, 0.4, 0.8]],
        offsets: [[0.0, 0.05, -0.02], [0.03, 0.0, 0.04]],
        orientation: Some([0.2, 0.1, 1.0]),
    }
}

fn section() -> LineSection {
    LineSection {
        a: 3.0e-3,
        i1: 2.0e-6,
        i2: 5.0e-6,
        i12: 0.0,
        j: 4.0e-6,
        k1: None,
        k2: None,
        nsm: 0.7,
        neutral_axis: [0.0; 2],
    }
}

fn fixed(g: &LineGeometry, s: &LineSection, releases: &Releases) -> Mat<f64> {
    let k = affine_stiffness(g, s, Elasticity::Fixed { e: E, g: G }, releases, (E, G)).unwrap();
    evaluate(&k)
}

fn evaluate(m: &AffineMatrix) -> Mat<f64> {
    m.evaluate(&CoefficientValues {
        e: E,
        nu: E / (2.0 * G) - 1.0,
        rho: 7800.0,
        ..Default::default()
    })
}

fn max_abs(m: &Mat<f64>) -> f64 {
    let mut out = 0.0f64;
    for i in 0..m.nrows() {
        for j in 0..m.ncols() {
            out = out.max(m[(i, j)].abs());
        }
    }
    out
}

/// Basic grid displacements of a rigid motion (translation t, small rotation w) at `points`.
fn rigid(points: &[[f64; 3]; 2], t: [f64; 3], w: [f64; 3]) -> Mat<f64> {
    let mut u = Mat::<f64>::zeros(12, 1);
    for (a, p) in points.iter().enumerate() {
        let d = cross(w, *p);
        for c in 0..3 {
            u[(6 * a + c, 0)] = t[c] + d[c];
            u[(6 * a + 3 + c, 0)] = w[c];
        }
    }
    u
}

#[test]
fn rigid_motions_are_stress_free_and_the_matrices_symmetric() {
    let g = oblique();
    let s = LineSection {
        k1: Some(0.85),
        k2: Some(0.6),
        ..section()
    };
    let k = fixed(&g, &s, &FREE);
    let scale = max_abs(&k);
    for (t, w) in [
        ([1.0, 0.0, 0.0], [0.0; 3]),
        ([0.0, 1.0, 0.0], [0.0; 3]),
        ([0.0, 0.0, 1.0], [0.0; 3]),
        ([0.0; 3], [1.0, 0.0, 0.0]),
        ([0.0; 3], [0.0, 1.0, 0.0]),
        ([0.0; 3], [0.0, 0.0, 1.0]),
    ] {
        let f = &k * rigid(&g.grids, t, w);
        assert!(
            max_abs(&f) < 1e-9 * scale,
            "rigid motion {t:?} {w:?}: {f:?}"
        );
    }
    let m =
        evaluate(&affine_mass(&g, &s, Density::Fixed { rho: 7800.0 }, MassForm::Coupled).unwrap());
    for mat in [&k, &m] {
        let asym = max_abs(&(mat - mat.transpose()));
        assert!(asym <= 1e-12 * max_abs(mat));
    }
    // exactly six zero eigenvalues: the rest are positive and far from zero
    let eig = k.self_adjoint_eigenvalues(Side::Lower).unwrap();
    let nonzero = eig.iter().filter(|v| v.abs() > 1e-9 * scale).count();
    assert_eq!(nonzero, 6, "{eig:?}");
}

#[test]
fn timoshenko_tip_deflection_adds_the_shear_term() {
    // cantilever along x, load P in y at the tip: δ = PL³/(3EI1) + PL/(K1 G A)
    let l = 0.4;
    let g = LineGeometry {
        grids: [[0.0; 3], [l, 0.0, 0.0]],
        offsets: [[0.0; 3]; 2],
        orientation: Some([0.0, 1.0, 0.0]),
    };
    for k1 in [None, Some(0.8)] {
        let s = LineSection { k1, ..section() };
        let k = fixed(&g, &s, &FREE);
        // tip DOFs v (7) and θz (11): solve the 2×2 system for a unit load on v
        let (a, b, c) = (k[(7, 7)], k[(7, 11)], k[(11, 11)]);
        let v = c / (a * c - b * b);
        let shear = k1.map_or(0.0, |k1| l / (k1 * G * s.a));
        let expected = l.powi(3) / (3.0 * E * s.i1) + shear;
        assert!((v - expected).abs() < 1e-12 * expected, "{v} vs {expected}");
    }
}

#[test]
fn product_of_inertia_equals_a_rotated_principal_section() {
    // a section with I1, I2, I12 in (y, z) is the principal section (P1, P2) in the frame
    // rotated by α about x: I1 = P1 c² + P2 s², I2 = P1 s² + P2 c², I12 = (P1 − P2) s c
    let g = oblique();
    let (p1, p2, alpha) = (2.0e-6, 7.0e-6, 0.4f64);
    let (s, c) = alpha.sin_cos();
    let coupled = LineSection {
        i1: p1 * c * c + p2 * s * s,
        i2: p1 * s * s + p2 * c * c,
        i12: (p1 - p2) * s * c,
        ..section()
    };
    let principal = LineSection {
        i1: p1,
        i2: p2,
        ..section()
    };
    // element axes of the oblique geometry, then y' = c y + s z
    let a = [
        crate::geometry::vec3::add(g.grids[0], g.offsets[0]),
        crate::geometry::vec3::add(g.grids[1], g.offsets[1]),
    ];
    let x = crate::geometry::vec3::normalize(sub(a[1], a[0])).unwrap();
    let z = crate::geometry::vec3::normalize(cross(x, g.orientation.unwrap())).unwrap();
    let y = cross(z, x);
    let rotated = LineGeometry {
        orientation: Some(std::array::from_fn(|i| c * y[i] + s * z[i])),
        ..g
    };
    let k1 = fixed(&g, &coupled, &FREE);
    let k2 = fixed(&rotated, &principal, &FREE);
    assert!(max_abs(&(&k1 - &k2)) < 1e-9 * max_abs(&k1));
}

#[test]
fn pins_release_moments_and_refuse_mechanisms() {
    let g = LineGeometry {
        grids: [[0.0; 3], [2.0, 0.0, 0.0]],
        offsets: [[0.0; 3]; 2],
        orientation: Some([0.0, 0.0, 1.0]),
    };
    // all rotations but torsion released at both ends: a truss member with torsion
    let mut pins = FREE;
    for end in &mut pins {
        end[4] = true;
        end[5] = true;
    }
    let k = fixed(&g, &section(), &pins);
    let axial = E * section().a / 2.0;
    assert!((k[(0, 0)] - axial).abs() < 1e-9 * axial);
    for i in [1, 2, 4, 5, 7, 8, 10, 11] {
        for j in 0..12 {
            assert!(k[(i, j)].abs() < 1e-6 * axial, "K[{i},{j}] = {}", k[(i, j)]);
        }
    }
    assert!(k[(3, 3)] > 0.0);
    // torsion released at both ends leaves a free twist
    let mut twist = FREE;
    twist[0][3] = true;
    twist[1][3] = true;
    let e = affine_stiffness(
        &g,
        &section(),
        Elasticity::Fixed { e: E, g: G },
        &twist,
        (E, G),
    );
    assert_eq!(e.unwrap_err(), BeamError::PinMechanism);
}

#[test]
fn mass_of_a_rigid_translation_is_the_element_mass() {
    let g = oblique();
    let s = section();
    let a = [
        crate::geometry::vec3::add(g.grids[0], g.offsets[0]),
        crate::geometry::vec3::add(g.grids[1], g.offsets[1]),
    ];
    let l = crate::geometry::vec3::norm(sub(a[1], a[0]));
    let total = (7800.0 * s.a + s.nsm) * l;
    let forms = [
        MassForm::Lumped { torsion: false },
        MassForm::Lumped { torsion: true },
        MassForm::Coupled,
    ];
    for form in forms {
        for rod in [true, false] {
            let g = LineGeometry {
                orientation: if rod { None } else { g.orientation },
                ..g
            };
            let m = evaluate(&affine_mass(&g, &s, Density::Fixed { rho: 7800.0 }, form).unwrap());
            for t in [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]] {
                let u = rigid(&g.grids, t, [0.0; 3]);
                let mass = (u.transpose() * &m * &u)[(0, 0)];
                assert!(
                    (mass - total).abs() < 1e-12 * total,
                    "{form:?} {rod}: {mass}"
                );
            }
        }
    }
}

#[test]
fn affine_parts_sum_to_the_fixed_matrices() {
    let g = oblique();
    let s = section();
    let full = fixed(&g, &s, &FREE);
    let by_e = affine_stiffness(
        &g,
        &s,
        Elasticity::YoungsModulus { g_per_e: G / E },
        &FREE,
        (E, G),
    )
    .unwrap();
    let separate = affine_stiffness(&g, &s, Elasticity::Separate, &FREE, (E, G)).unwrap();
    assert_eq!(separate.parts[1].0, Coefficient::Mu);
    for k in [by_e, separate] {
        assert!(max_abs(&(evaluate(&k) - &full)) < 1e-12 * max_abs(&full));
    }
    let m_fixed =
        evaluate(&affine_mass(&g, &s, Density::Fixed { rho: 7800.0 }, MassForm::Coupled).unwrap());
    let m_split = evaluate(&affine_mass(&g, &s, Density::Parameter, MassForm::Coupled).unwrap());
    assert!(max_abs(&(&m_fixed - &m_split)) < 1e-12 * max_abs(&m_split));
    // E and G separately are not affine with shear flexibility
    let sheared = LineSection { k1: Some(0.8), ..s };
    let refused = affine_stiffness(&g, &sheared, Elasticity::Separate, &FREE, (E, G));
    assert_eq!(refused.unwrap_err(), BeamError::SeparateModuliWithShear);
}

#[test]
fn degenerate_geometry_is_refused() {
    let mut g = oblique();
    g.orientation = Some(sub(
        crate::geometry::vec3::add(g.grids[1], g.offsets[1]),
        crate::geometry::vec3::add(g.grids[0], g.offsets[0]),
    ));
    let e = affine_stiffness(
        &g,
        &section(),
        Elasticity::Fixed { e: E, g: G },
        &FREE,
        (E, G),
    );
    assert_eq!(e.unwrap_err(), BeamError::OrientationAlongAxis);
    let g = LineGeometry {
        grids: [[1.0, 2.0, 3.0]; 2],
        offsets: [[0.0; 3]; 2],
        orientation: None,
    };
    let e = affine_mass(
        &g,
        &section(),
        Density::Parameter,
        MassForm::Lumped { torsion: false },
    );
    assert_eq!(e.unwrap_err(), BeamError::ZeroLength);
}

/// A cantilever along x whose neutral axis sits at (y_n, z_n) from its axis, pulled by P along
/// the axis at the free end: on the neutral axis that is P and the moment (0, −z_n P, y_n P),
/// so θy = −z_n P L/(E I2), θz = y_n P L/(E I1), v = θz L/2, w = −θy L/2 and the axis stretches
/// by P L/(E A) + P L (z_n²/(E I2) + y_n²/(E I1)) (one element is exact: constant moment).
#[test]
fn a_neutral_axis_offset_couples_stretch_and_bending() {
    let l = 2.0;
    let g = LineGeometry {
        grids: [[0.0; 3], [l, 0.0, 0.0]],
        offsets: [[0.0; 3]; 2],
        orientation: Some([0.0, 1.0, 0.0]),
    };
    let (yn, zn, p) = (0.01, 0.03, 1.0e4);
    let s = LineSection {
        neutral_axis: [yn, zn],
        ..section()
    };
    let k = fixed(&g, &s, &FREE);
    let kbb = Mat::from_fn(6, 6, |i, j| k[(6 + i, 6 + j)]);
    let mut u = Mat::<f64>::zeros(6, 1);
    u[(0, 0)] = p;
    kbb.llt(Side::Lower)
        .expect("clamped at A")
        .solve_in_place(u.as_mut());
    let (ty, tz) = (-zn * p * l / (E * s.i2), yn * p * l / (E * s.i1));
    let stretch = p * l / (E * s.a) + p * l * (zn * zn / (E * s.i2) + yn * yn / (E * s.i1));
    let want = [stretch, tz * l / 2.0, -ty * l / 2.0, 0.0, ty, tz];
    for (c, w) in want.iter().enumerate() {
        let scale = want.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        assert!(
            (u[(c, 0)] - w).abs() < 1e-9 * scale,
            "component {c}: {} vs {w}",
            u[(c, 0)]
        );
    }
}
