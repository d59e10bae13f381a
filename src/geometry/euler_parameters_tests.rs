//! Tests of [`super::euler_parameters`]: every identity of the module doc checked on random
//! parameters, the conversions against Rodrigues' formula, the rates against finite
//! differences of A(e(t)).

use super::euler_parameters::*;
use super::mat3::{self, IDENTITY as I3, Mat3};
use super::rotation::{self, is_rotation};
use super::vec3::{self, skew};
use crate::linalg::random::SplitMix64;
use std::f64::consts::PI;

/// Random parameters with normal components (not normalized).
fn random_parameters(rng: &mut SplitMix64) -> EulerParameters {
    [rng.normal(), rng.normal(), rng.normal(), rng.normal()]
}

fn random_unit_parameters(rng: &mut SplitMix64) -> EulerParameters {
    normalize(&random_parameters(rng)).unwrap()
}

fn random_vector(rng: &mut SplitMix64) -> [f64; 3] {
    [rng.normal(), rng.normal(), rng.normal()]
}

fn max_abs_3x4(a: &Mat3x4, b: &Mat3x4) -> f64 {
    a.iter()
        .flatten()
        .zip(b.iter().flatten())
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

/// M N for a 3×4 matrix M and a 4×4 matrix N.
fn mul_3x4_4x4(m: &Mat3x4, n: &[[f64; 4]; 4]) -> Mat3x4 {
    std::array::from_fn(|i| std::array::from_fn(|j| (0..4).map(|k| m[i][k] * n[k][j]).sum()))
}

/// M Nᵀ for two 3×4 matrices.
fn mul_transpose(m: &Mat3x4, n: &Mat3x4) -> Mat3 {
    std::array::from_fn(|i| std::array::from_fn(|j| (0..4).map(|k| m[i][k] * n[j][k]).sum()))
}

fn scaled_identity(s: f64) -> Mat3 {
    I3.map(|row| row.map(|x| s * x))
}

#[test]
fn rotation_matrix_is_orthonormal_with_determinant_one_for_random_parameters() {
    let mut rng = SplitMix64::new(11);
    assert_eq!(rotation_matrix(&IDENTITY), I3);
    for _ in 0..200 {
        let e = random_unit_parameters(&mut rng);
        let a = rotation_matrix(&e);
        assert!(is_rotation(&a, 1e-14), "A({e:?}) = {a:?}");
        // e and −e are the same rotation
        assert_eq!(rotation_matrix(&e.map(|x| -x)), a);
        // the written-out form (e₀² − ēᵀē) I + 2 ē ēᵀ + 2 e₀ ẽ
        let v = [e[1], e[2], e[3]];
        let s = skew(v);
        let closed: Mat3 = std::array::from_fn(|i| {
            std::array::from_fn(|j| {
                (e[0] * e[0] - vec3::dot(v, v)) * I3[i][j]
                    + 2.0 * v[i] * v[j]
                    + 2.0 * e[0] * s[i][j]
            })
        });
        assert!(mat3::max_abs_difference(&a, &closed) < 1e-15);
    }
}

#[test]
fn e_and_g_matrices_satisfy_the_identities_of_appendix_a() {
    let mut rng = SplitMix64::new(12);
    for unit in [true, false] {
        for _ in 0..50 {
            let e = if unit {
                random_unit_parameters(&mut rng)
            } else {
                random_parameters(&mut rng)
            };
            let (em, gm) = (e_matrix(&e), g_matrix(&e));
            let ete = e.iter().map(|x| x * x).sum::<f64>();
            let tol = 1e-14 * ete.max(1.0);
            // E Eᵀ = G Gᵀ = (eᵀe) I₃
            let eet = mul_transpose(&em, &em);
            let ggt = mul_transpose(&gm, &gm);
            assert!(mat3::max_abs_difference(&eet, &scaled_identity(ete)) < tol);
            assert!(mat3::max_abs_difference(&ggt, &scaled_identity(ete)) < tol);
            // E e = G e = 0
            for row in em.iter().chain(gm.iter()) {
                assert!(row.iter().zip(&e).map(|(r, x)| r * x).sum::<f64>().abs() < tol);
            }
            // A = E Gᵀ (eq. A.4) and A G = (eᵀe) E
            let a = rotation_matrix(&e);
            assert!(mat3::max_abs_difference(&a, &mul_transpose(&em, &gm)) < tol);
            let ag: Mat3x4 = std::array::from_fn(|i| {
                std::array::from_fn(|k| (0..3).map(|j| a[i][j] * gm[j][k]).sum())
            });
            assert!(max_abs_3x4(&ag, &em.map(|r| r.map(|x| ete * x))) < 4.0 * tol * ete.max(1.0));
        }
    }
}

#[test]
fn axis_angle_parameters_give_the_rodrigues_matrix() {
    let mut rng = SplitMix64::new(13);
    for _ in 0..200 {
        let axis = random_vector(&mut rng);
        let angle = 2.0 * PI * rng.symmetric();
        let e = from_axis_angle(axis, angle).unwrap();
        assert!(normalization_residual(&e).abs() < 4.0 * f64::EPSILON);
        let rodrigues = rotation::from_axis_angle(axis, angle).unwrap();
        let a = rotation_matrix(&e);
        assert!(
            mat3::max_abs_difference(&a, &rodrigues) < 1e-15,
            "{axis:?} {angle}"
        );
    }
    assert_eq!(from_axis_angle([0.0; 3], 1.0), None);
}

#[test]
fn rotation_matrix_round_trips_through_shepperd_including_half_turns() {
    let mut rng = SplitMix64::new(14);
    let mut cases: Vec<([f64; 3], f64)> = (0..300)
        .map(|_| (random_vector(&mut rng), PI * rng.symmetric()))
        .collect();
    // half turns about random and coordinate axes, just below and above them, no rotation
    for k in 0..40 {
        let axis = match k {
            0..3 => std::array::from_fn(|i| if i == k { 1.0 } else { 0.0 }),
            3..6 => std::array::from_fn(|i| if i == k - 3 { -1.0 } else { 0.0 }),
            _ => random_vector(&mut rng),
        };
        for angle in [PI, -PI, PI - 1e-9, PI + 1e-9, PI - 1e-3, 1e-12, 0.0] {
            cases.push((axis, angle));
        }
    }
    for (axis, angle) in cases {
        let r = rotation::from_axis_angle(axis, angle).unwrap();
        let e = from_rotation_matrix(&r);
        assert!(e[0] >= 0.0);
        assert!(normalization_residual(&e).abs() < 4.0 * f64::EPSILON);
        let back = rotation_matrix(&e);
        assert!(
            mat3::max_abs_difference(&back, &r) < 1e-15,
            "{axis:?} {angle}: {e:?}"
        );
        // the same parameters as the axis–angle ones, up to the sign of the pair ±e
        let direct = from_axis_angle(axis, angle).unwrap();
        let same = e
            .iter()
            .zip(&direct)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        let opposite = e
            .iter()
            .zip(&direct)
            .map(|(a, b)| (a + b).abs())
            .fold(0.0, f64::max);
        assert!(
            same.min(opposite) < 1e-15 * 8.0,
            "{axis:?} {angle}: {e:?} vs {direct:?}"
        );
    }
}

/// A smooth curve of unit parameters, e(t) = p(t) / |p(t)| with p quadratic in t, and its
/// exact rate ė = (I − e eᵀ) ṗ / |p|.
struct Curve {
    p: [[f64; 4]; 3],
}

impl Curve {
    fn p(&self, t: f64) -> [f64; 4] {
        std::array::from_fn(|k| self.p[0][k] + self.p[1][k] * t + self.p[2][k] * t * t)
    }

    fn e(&self, t: f64) -> EulerParameters {
        normalize(&self.p(t)).unwrap()
    }

    fn e_dot(&self, t: f64) -> EulerParameters {
        let p = self.p(t);
        let n = p.iter().map(|x| x * x).sum::<f64>().sqrt();
        let e = p.map(|x| x / n);
        let p_dot: [f64; 4] = std::array::from_fn(|k| self.p[1][k] + 2.0 * self.p[2][k] * t);
        let radial: f64 = e.iter().zip(&p_dot).map(|(a, b)| a * b).sum();
        std::array::from_fn(|k| (p_dot[k] - radial * e[k]) / n)
    }
}

#[test]
fn angular_velocities_match_finite_differences_of_the_rotation_matrix() {
    let mut rng = SplitMix64::new(15);
    for _ in 0..20 {
        let curve = Curve {
            p: std::array::from_fn(|_| random_parameters(&mut rng)),
        };
        let t = 0.3;
        let (e, e_dot) = (curve.e(t), curve.e_dot(t));
        assert!(e.iter().zip(&e_dot).map(|(a, b)| a * b).sum::<f64>().abs() < 1e-14);
        let h = 1e-5;
        let (ap, am) = (
            rotation_matrix(&curve.e(t + h)),
            rotation_matrix(&curve.e(t - h)),
        );
        let a_dot: Mat3 =
            std::array::from_fn(|i| std::array::from_fn(|j| (ap[i][j] - am[i][j]) / (2.0 * h)));
        let a = rotation_matrix(&e);
        let scale = e_dot.iter().map(|x| x.abs()).fold(1.0, f64::max);
        let tol = 1e-8 * scale.powi(3);
        // Ȧ Aᵀ = ω̃ with ω = 2 E ė (global), Aᵀ Ȧ = ω̄̃ with ω̄ = 2 G ė (body)
        let omega = global_angular_velocity(&e, &e_dot);
        let omega_body = body_angular_velocity(&e, &e_dot);
        let global = mat3::mul(&a_dot, &mat3::transpose(&a));
        let body = mat3::mul(&mat3::transpose(&a), &a_dot);
        assert!(
            mat3::max_abs_difference(&global, &skew(omega)) < tol,
            "{global:?} {omega:?}"
        );
        assert!(mat3::max_abs_difference(&body, &skew(omega_body)) < tol);
        // ω = A ω̄
        let rotated = mat3::mul_vec(&a, omega_body);
        assert!(vec3::norm(vec3::sub(rotated, omega)) < 1e-13 * scale);
    }
}

#[test]
fn rates_from_angular_velocity_invert_it_and_keep_the_normalization() {
    let mut rng = SplitMix64::new(16);
    for _ in 0..100 {
        let e = random_unit_parameters(&mut rng);
        let omega = random_vector(&mut rng);
        let e_dot = rates_from_global_angular_velocity(&e, omega);
        assert!(e.iter().zip(&e_dot).map(|(a, b)| a * b).sum::<f64>().abs() < 1e-15);
        let back = global_angular_velocity(&e, &e_dot);
        assert!(vec3::norm(vec3::sub(back, omega)) < 1e-14 * vec3::norm(omega).max(1.0));
        let e_dot = rates_from_body_angular_velocity(&e, omega);
        assert!(e.iter().zip(&e_dot).map(|(a, b)| a * b).sum::<f64>().abs() < 1e-15);
        let back = body_angular_velocity(&e, &e_dot);
        assert!(vec3::norm(vec3::sub(back, omega)) < 1e-14 * vec3::norm(omega).max(1.0));
    }
}

#[test]
fn rotated_vector_jacobian_matches_finite_differences() {
    let mut rng = SplitMix64::new(17);
    for unit in [true, false] {
        for _ in 0..50 {
            let e = if unit {
                random_unit_parameters(&mut rng)
            } else {
                random_parameters(&mut rng)
            };
            let s = random_vector(&mut rng);
            let jac = rotated_vector_jacobian(&e, s);
            // A(e) s̄ is quadratic in e: the central difference is exact up to round-off
            let h = 1e-4;
            let fd: Mat3x4 = std::array::from_fn(|i| {
                std::array::from_fn(|k| {
                    let (mut ep, mut em) = (e, e);
                    ep[k] += h;
                    em[k] -= h;
                    let (ap, am) = (rotation_matrix(&ep), rotation_matrix(&em));
                    (mat3::mul_vec(&ap, s)[i] - mat3::mul_vec(&am, s)[i]) / (2.0 * h)
                })
            });
            let size = vec3::norm(s) * e.iter().map(|x| x.abs()).fold(1.0, f64::max);
            assert!(max_abs_3x4(&jac, &fd) < 1e-10 * size, "{jac:?} vs {fd:?}");
            // −2 E s̄⁺ is the product of eq. A.6 / A.24
            let product = mul_3x4_4x4(&e_matrix(&e), &plus_matrix(s)).map(|r| r.map(|x| -2.0 * x));
            assert!(max_abs_3x4(&jac, &product) < 1e-14 * size);
        }
    }
}

#[test]
fn rate_of_a_body_fixed_vector_is_omega_cross_it() {
    let mut rng = SplitMix64::new(18);
    for _ in 0..50 {
        let e = random_unit_parameters(&mut rng);
        let e_dot = rates_from_global_angular_velocity(&e, random_vector(&mut rng));
        let s = random_vector(&mut rng);
        let jac = rotated_vector_jacobian(&e, s);
        let rate: [f64; 3] = jac.map(|row| row.iter().zip(&e_dot).map(|(j, d)| j * d).sum());
        let a_s = mat3::mul_vec(&rotation_matrix(&e), s);
        let expected = vec3::cross(global_angular_velocity(&e, &e_dot), a_s);
        assert!(vec3::norm(vec3::sub(rate, expected)) < 1e-13 * (1.0 + vec3::norm(s)));
    }
}

#[test]
fn plus_matrix_is_skew_symmetric_with_the_skew_matrix_inside() {
    let s = [0.4, -1.1, 2.5];
    let p = plus_matrix(s);
    let t = skew(s);
    for (i, row) in p.iter().enumerate() {
        for (j, v) in row.iter().enumerate() {
            assert_eq!(*v, -p[j][i]);
        }
    }
    for i in 0..3 {
        assert_eq!(p[0][i + 1], s[i]);
        assert_eq!(p[i + 1][0], -s[i]);
        for j in 0..3 {
            assert_eq!(p[i + 1][j + 1], t[i][j]);
        }
    }
}

#[test]
fn normalization_constraint_and_its_jacobian() {
    let mut rng = SplitMix64::new(19);
    let e = random_unit_parameters(&mut rng);
    assert!(normalization_residual(&e).abs() < 4.0 * f64::EPSILON);
    let p = random_parameters(&mut rng);
    let jac = normalization_jacobian(&p);
    let h = 1e-6;
    for (k, jk) in jac.iter().enumerate() {
        let (mut pp, mut pm) = (p, p);
        pp[k] += h;
        pm[k] -= h;
        let fd = (normalization_residual(&pp) - normalization_residual(&pm)) / (2.0 * h);
        assert!((fd - jk).abs() < 1e-8, "{k}: {fd} vs {jk}");
    }
    assert_eq!(normalize(&[0.0; 4]), None);
    assert_eq!(normalize(&[f64::NAN, 0.0, 0.0, 0.0]), None);
    let n = normalize(&[0.0, 0.0, 3.0, 0.0]).unwrap();
    assert_eq!(n, [0.0, 0.0, 1.0, 0.0]);
}
