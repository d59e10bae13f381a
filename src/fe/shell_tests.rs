//! Acceptance tests of the shell elements (DESIGN.md §4): rigid-body modes, patch tests,
//! symmetry, thin-plate locking, a shell cantilever, affine splits and degenerate geometry.
//! Global assembly belongs elsewhere; the tiny dense helper here is for these tests only.

use faer::linalg::solvers::Solve;
use faer::{Mat, Side};

use crate::geometry::mat3;

use super::affine::CoefficientValues;
use super::laminate::{
    Laminate, Ply, PshellSection, RoleMaterial, SectionData, SectionParameter, ShellSection,
    affine_sections, evaluate,
};
use super::shell::{
    Incompatible, ShellError, affine_mass, affine_stiffness, quad4_mass, quad4_stiffness,
    quad4_strains, tria3_mass, tria3_stiffness, tria3_strains,
};

type V3 = [f64; 3];

pub(super) fn steel(t: f64, nu: f64) -> ShellSection {
    ShellSection::pshell(&iso(210e9, nu, t)).unwrap()
}

pub(super) fn iso(e: f64, nu: f64, t: f64) -> PshellSection {
    PshellSection::homogeneous(RoleMaterial::mat1(1, e, nu, 7850.0), t)
}

/// Dense assembly of element matrices given by their grid lists.
pub(super) fn assemble(nnodes: usize, elements: &[(Vec<usize>, Mat<f64>)]) -> Mat<f64> {
    let mut k = Mat::<f64>::zeros(6 * nnodes, 6 * nnodes);
    for (grids, ke) in elements {
        for (a, &ga) in grids.iter().enumerate() {
            for (b, &gb) in grids.iter().enumerate() {
                for i in 0..6 {
                    for j in 0..6 {
                        k[(6 * ga + i, 6 * gb + j)] += ke[(6 * a + i, 6 * b + j)];
                    }
                }
            }
        }
    }
    k
}

fn quad_of(xyz: &[V3], g: &[usize]) -> [V3; 4] {
    [xyz[g[0]], xyz[g[1]], xyz[g[2]], xyz[g[3]]]
}

/// Stiffness of a quad mesh (grids per element), material x along basic x.
fn quad_mesh_stiffness(xyz: &[V3], quads: &[[usize; 4]], section: &ShellSection) -> Mat<f64> {
    let els: Vec<_> = quads
        .iter()
        .map(|q| {
            (
                q.to_vec(),
                quad4_stiffness(
                    &quad_of(xyz, q),
                    section,
                    Incompatible::Condensed(section),
                    Some([1.0, 0.0, 0.0]),
                )
                .unwrap(),
            )
        })
        .collect();
    assemble(xyz.len(), &els)
}

/// Number of eigenvalues with |λ| < 1e-8 · max λ.
pub(super) fn zero_modes(k: &Mat<f64>) -> usize {
    let ev = k.self_adjoint_eigenvalues(Side::Lower).unwrap();
    let max = ev.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    ev.iter().filter(|x| x.abs() < 1e-8 * max).count()
}

/// Structured nx × ny grid of nodes on [0, lx] × [0, ly] with z = height(x, y), and its quads.
fn grid_mesh(
    nx: usize,
    ny: usize,
    lx: f64,
    ly: f64,
    height: impl Fn(f64, f64) -> f64,
) -> (Vec<V3>, Vec<[usize; 4]>) {
    let mut xyz = Vec::new();
    for j in 0..=ny {
        for i in 0..=nx {
            let (x, y) = (lx * i as f64 / nx as f64, ly * j as f64 / ny as f64);
            xyz.push([x, y, height(x, y)]);
        }
    }
    let id = |i: usize, j: usize| j * (nx + 1) + i;
    let mut quads = Vec::new();
    for j in 0..ny {
        for i in 0..nx {
            quads.push([id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    (xyz, quads)
}

/// Solve K u = f for each load in `loads`, with the DOFs in `fixed` prescribed to `values`
/// (one dense LU on the free set).
pub(super) fn solve_with_prescribed(
    k: &Mat<f64>,
    loads: &[Vec<f64>],
    fixed: &[usize],
    values: &[f64],
) -> Vec<Vec<f64>> {
    let n = k.nrows();
    let mut is_fixed = vec![false; n];
    let mut u0 = vec![0.0; n];
    for (&d, &v) in fixed.iter().zip(values) {
        is_fixed[d] = true;
        u0[d] = v;
    }
    let free: Vec<usize> = (0..n).filter(|&d| !is_fixed[d]).collect();
    let kff = Mat::<f64>::from_fn(free.len(), free.len(), |i, j| k[(free[i], free[j])]);
    let lifted: Vec<f64> = free
        .iter()
        .map(|&r| fixed.iter().map(|&d| k[(r, d)] * u0[d]).sum())
        .collect();
    let rhs = Mat::<f64>::from_fn(free.len(), loads.len(), |i, c| {
        loads[c][free[i]] - lifted[i]
    });
    let x = kff.partial_piv_lu().solve(&rhs);
    (0..loads.len())
        .map(|c| {
            let mut u = u0.clone();
            for (i, &d) in free.iter().enumerate() {
                u[d] = x[(i, c)];
            }
            u
        })
        .collect()
}

// ---------------------------------------------------------------------------------------------
// (a) rigid-body modes

#[test]
fn single_flat_quad_has_six_zero_modes() {
    let xyz = [
        [0.0, 0.0, 0.0],
        [1.2, 0.1, 0.0],
        [1.0, 0.9, 0.0],
        [-0.1, 0.7, 0.0],
    ];
    let s = steel(0.05, 0.3);
    for modes in [Incompatible::Condensed(&s), Incompatible::Off] {
        let k = quad4_stiffness(&xyz, &s, modes, None).unwrap();
        assert_eq!(zero_modes(&k), 6, "{modes:?}");
    }
}

#[test]
fn single_warped_quad_has_six_zero_modes() {
    // Out-of-plane offsets ±0.025 alternating: 5 % warp over a unit-size element, rotated in 3-D.
    let flat = [
        [0.0, 0.0, 0.025],
        [1.1, 0.0, -0.025],
        [1.0, 1.0, 0.025],
        [0.05, 0.9, -0.025],
    ];
    let xyz = flat.map(rotate);
    let s = steel(0.05, 0.3);
    for modes in [Incompatible::Condensed(&s), Incompatible::Off] {
        let k = quad4_stiffness(&xyz, &s, modes, None).unwrap();
        assert_eq!(zero_modes(&k), 6, "{modes:?}");
    }
}

#[test]
fn single_tria_has_six_zero_modes() {
    let xyz = [[0.0, 0.0, 0.0], [1.0, 0.2, 0.3], [0.3, 0.8, -0.2]];
    let k = tria3_stiffness(&xyz, &steel(0.05, 0.3), None).unwrap();
    assert_eq!(zero_modes(&k), 6);
}

#[test]
fn free_warped_4x4_mesh_has_six_zero_modes() {
    // Spherical cap of radius 3 over a unit square: every element is warped.
    let (xyz, quads) = grid_mesh(4, 4, 1.0, 1.0, |x, y| {
        3.0 - (9.0 - (x - 0.3).powi(2) - (y - 0.4).powi(2)).sqrt()
    });
    let k = quad_mesh_stiffness(&xyz, &quads, &steel(0.02, 0.3));
    assert_eq!(zero_modes(&k), 6);
    // A free mesh of triangles (each quad split along a diagonal) likewise.
    let els: Vec<_> = quads
        .iter()
        .flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]])
        .map(|t| {
            (
                t.to_vec(),
                tria3_stiffness(&[xyz[t[0]], xyz[t[1]], xyz[t[2]]], &steel(0.02, 0.3), None)
                    .unwrap(),
            )
        })
        .collect();
    assert_eq!(zero_modes(&assemble(xyz.len(), &els)), 6);
}

// ---------------------------------------------------------------------------------------------
// (b) patch tests

/// A fixed, general rotation of basic space (the patch tests run off the coordinate planes).
fn rotation() -> [V3; 3] {
    let (a, b, c) = (0.4f64, -0.7f64, 1.1f64);
    let rz = [
        [c.cos(), -c.sin(), 0.0],
        [c.sin(), c.cos(), 0.0],
        [0.0, 0.0, 1.0],
    ];
    let ry = [
        [b.cos(), 0.0, b.sin()],
        [0.0, 1.0, 0.0],
        [-b.sin(), 0.0, b.cos()],
    ];
    let rx = [
        [1.0, 0.0, 0.0],
        [0.0, a.cos(), -a.sin()],
        [0.0, a.sin(), a.cos()],
    ];
    mat3::mul(&rz, &mat3::mul(&ry, &rx))
}

pub(super) fn rotate(v: V3) -> V3 {
    mat3::mul_vec(&rotation(), v)
}

/// MacNeal–Harder patch (1985): 0.24 × 0.12 rectangle, 4 interior grids, 5 distorted quads.
pub(super) fn macneal_harder_patch() -> (Vec<[f64; 2]>, Vec<[usize; 4]>) {
    let xy = vec![
        [0.0, 0.0],
        [0.24, 0.0],
        [0.24, 0.12],
        [0.0, 0.12],
        [0.04, 0.02],
        [0.18, 0.03],
        [0.16, 0.08],
        [0.08, 0.08],
    ];
    let quads = vec![
        [0, 1, 5, 4],
        [1, 2, 6, 5],
        [2, 3, 7, 6],
        [3, 0, 4, 7],
        [4, 5, 6, 7],
    ];
    (xy, quads)
}

/// Exact patch field in the patch plane: u = 1e-3(x + y/2), v = 1e-3(y + x/2),
/// w = 1e-3(x² + xy + y²)/2, θx = ∂w/∂y, θy = −∂w/∂x, θz = ½(∂v/∂x − ∂u/∂y) = 0.
pub(super) fn patch_field(x: f64, y: f64) -> [f64; 6] {
    let e = 1e-3;
    [
        e * (x + 0.5 * y),
        e * (y + 0.5 * x),
        0.5 * e * (x * x + x * y + y * y),
        e * (0.5 * x + y),
        -e * (x + 0.5 * y),
        0.0,
    ]
}

/// Membrane (constant strain) and bending (constant curvature) patch test of MacNeal & Harder,
/// "A proposed standard set of problems to test finite element accuracy", FEA&D 1 (1985),
/// run in a rotated plane: boundary grids get the exact field, interior grids are solved.
#[test]
fn macneal_harder_membrane_and_bending_patch_test() {
    let (xy, quads) = macneal_harder_patch();
    let xyz: Vec<V3> = xy.iter().map(|p| rotate([p[0], p[1], 0.0])).collect();
    let exact: Vec<f64> = xy
        .iter()
        .flat_map(|p| {
            let f = patch_field(p[0], p[1]);
            let (t, r) = (rotate([f[0], f[1], f[2]]), rotate([f[3], f[4], f[5]]));
            [t[0], t[1], t[2], r[0], r[1], r[2]]
        })
        .collect();
    let section = ShellSection::pshell(&PshellSection::homogeneous(
        RoleMaterial::mat1(1, 1e6, 0.25, 1.0),
        0.001,
    ))
    .unwrap();
    let mx = rotate([1.0, 0.0, 0.0]);
    let els: Vec<_> = quads
        .iter()
        .map(|q| {
            (
                q.to_vec(),
                quad4_stiffness(
                    &quad_of(&xyz, q),
                    &section,
                    Incompatible::Condensed(&section),
                    Some(mx),
                )
                .unwrap(),
            )
        })
        .collect();
    let k = assemble(xyz.len(), &els);
    let fixed: Vec<usize> = (0..24).collect();
    let u = solve_with_prescribed(&k, &[vec![0.0; 48]], &fixed, &exact[..24]).remove(0);
    for d in 24..48 {
        assert!(
            (u[d] - exact[d]).abs() < 1e-12,
            "DOF {d}: {} vs {}",
            u[d],
            exact[d]
        );
    }
    for q in &quads {
        let ue: [f64; 24] = std::array::from_fn(|i| u[6 * q[i / 6] + i % 6]);
        let s = quad4_strains(&quad_of(&xyz, q), Some(mx), (0.0005, -0.0005), &ue).unwrap();
        let want_m = [1e-3, 1e-3, 1e-3];
        let want_k = [-1e-3, -1e-3, -1e-3];
        for i in 0..3 {
            assert!((s.membrane[i] - want_m[i]).abs() < 1e-12, "{s:?}");
            assert!((s.curvature[i] - want_k[i]).abs() < 1e-11, "{s:?}");
            assert!((s.top[i] - (want_m[i] + 0.0005 * want_k[i])).abs() < 1e-12);
        }
        assert!(s.shear.iter().all(|g| g.abs() < 1e-12), "{s:?}");
    }
}

/// The same fields on a triangle patch (the MacNeal–Harder patch split into triangles).
#[test]
fn tria_membrane_and_bending_patch_test() {
    let (xy, quads) = macneal_harder_patch();
    let xyz: Vec<V3> = xy.iter().map(|p| rotate([p[0], p[1], 0.0])).collect();
    let exact: Vec<f64> = xy
        .iter()
        .flat_map(|p| {
            let f = patch_field(p[0], p[1]);
            let (t, r) = (rotate([f[0], f[1], f[2]]), rotate([f[3], f[4], f[5]]));
            [t[0], t[1], t[2], r[0], r[1], r[2]]
        })
        .collect();
    let section = steel(0.001, 0.25);
    let mx = rotate([1.0, 0.0, 0.0]);
    let trias: Vec<[usize; 3]> = quads
        .iter()
        .flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]])
        .collect();
    let els: Vec<_> = trias
        .iter()
        .map(|t| {
            (
                t.to_vec(),
                tria3_stiffness(&[xyz[t[0]], xyz[t[1]], xyz[t[2]]], &section, Some(mx)).unwrap(),
            )
        })
        .collect();
    let k = assemble(xyz.len(), &els);
    let fixed: Vec<usize> = (0..24).collect();
    let u = solve_with_prescribed(&k, &[vec![0.0; 48]], &fixed, &exact[..24]).remove(0);
    for d in 24..48 {
        assert!(
            (u[d] - exact[d]).abs() < 1e-12,
            "DOF {d}: {} vs {}",
            u[d],
            exact[d]
        );
    }
    for t in &trias {
        let ue: [f64; 18] = std::array::from_fn(|i| u[6 * t[i / 6] + i % 6]);
        let s = tria3_strains(
            &[xyz[t[0]], xyz[t[1]], xyz[t[2]]],
            Some(mx),
            (0.0, 0.0),
            &ue,
        )
        .unwrap();
        for i in 0..3 {
            assert!(
                (s.membrane[i] - 1e-3).abs() < 1e-12 && (s.curvature[i] + 1e-3).abs() < 1e-11,
                "{s:?}"
            );
        }
    }
}

// ---------------------------------------------------------------------------------------------
// (c) symmetry, positivity and mass

fn laminate_section() -> ShellSection {
    let ply = |theta_deg| Ply {
        e1: 140e9,
        e2: 10e9,
        nu12: 0.3,
        g12: 5e9,
        g1z: Some(5e9),
        g2z: Some(3.5e9),
        rho: 1600.0,
        t: 0.25e-3,
        theta_deg,
    };
    ShellSection::laminate(&Laminate {
        plies: vec![ply(30.0), ply(-30.0), ply(60.0)],
        z0: Some(-0.2e-3),
        nsm: 0.1,
        symmetric: false,
    })
    .unwrap()
}

#[test]
fn matrices_are_symmetric_and_positive() {
    let quad = [
        [0.0, 0.0, 0.01],
        [1.1, 0.0, -0.01],
        [1.0, 1.0, 0.01],
        [0.05, 0.9, -0.01],
    ]
    .map(rotate);
    let tria = [[0.0, 0.0, 0.0], [1.0, 0.2, 0.3], [0.3, 0.8, -0.2]];
    let s = laminate_section();
    for m in [
        quad4_stiffness(
            &quad,
            &s,
            Incompatible::Condensed(&s),
            Some([1.0, 1.0, 0.0]),
        )
        .unwrap(),
        tria3_stiffness(&tria, &s, None).unwrap(),
        quad4_mass(&quad, &s.mass, false).unwrap(),
        quad4_mass(&quad, &s.mass, true).unwrap(),
        tria3_mass(&tria, &s.mass, false).unwrap(),
        tria3_mass(&tria, &s.mass, true).unwrap(),
    ] {
        let max = (0..m.nrows()).map(|i| m[(i, i)].abs()).fold(0.0, f64::max);
        for i in 0..m.nrows() {
            for j in 0..m.ncols() {
                assert_eq!(m[(i, j)], m[(j, i)]);
            }
        }
        let ev = m.self_adjoint_eigenvalues(Side::Lower).unwrap();
        assert!(ev[0] > -1e-10 * max, "negative eigenvalue {}", ev[0]);
    }
}

/// An isotropic element does not depend on the choice of its material axes.
#[test]
fn isotropic_element_is_invariant_to_material_axes() {
    let quad = [
        [0.0, 0.0, 0.01],
        [1.1, 0.0, -0.01],
        [1.0, 1.0, 0.01],
        [0.05, 0.9, -0.01],
    ]
    .map(rotate);
    let tria = [[0.0, 0.0, 0.0], [1.0, 0.2, 0.3], [0.3, 0.8, -0.2]];
    let s = steel(0.02, 0.3);
    let (k1, k2) = (
        quad4_stiffness(&quad, &s, Incompatible::Condensed(&s), None).unwrap(),
        quad4_stiffness(
            &quad,
            &s,
            Incompatible::Condensed(&s),
            Some([0.3, -1.0, 0.2]),
        )
        .unwrap(),
    );
    assert!(rel_diff(&k1, &k2) < 1e-12, "quad: {}", rel_diff(&k1, &k2));
    let (k1, k2) = (
        tria3_stiffness(&tria, &s, None).unwrap(),
        tria3_stiffness(&tria, &s, Some([0.3, -1.0, 0.2])).unwrap(),
    );
    assert!(rel_diff(&k1, &k2) < 1e-12, "tria: {}", rel_diff(&k1, &k2));
}

/// Rigid translation and rotation: uᵀ M u = total mass, and the rotary inertia about the
/// normal of a flat unit square equals ρt·(1/6) for consistent and ρt·(1/2) for lumped mass.
#[test]
fn mass_reproduces_rigid_body_inertia() {
    let quad = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
    ];
    let s = steel(0.01, 0.3);
    let rho_t = s.mass.rho_t;
    for (lumped, jz) in [(false, 1.0 / 6.0), (true, 0.5)] {
        let m = quad4_mass(&quad, &s.mass, lumped).unwrap();
        let quad_form = |u: &[f64]| -> f64 {
            (0..24)
                .map(|i| (0..24).map(|j| u[i] * m[(i, j)] * u[j]).sum::<f64>())
                .sum()
        };
        let tx: Vec<f64> = (0..24)
            .map(|i| if i % 6 == 0 { 1.0 } else { 0.0 })
            .collect();
        assert!((quad_form(&tx) - rho_t).abs() < 1e-12 * rho_t);
        // Rotation about z through (0.5, 0.5): u = −(y − ½), v = x − ½, θz = 1.
        let rz: Vec<f64> = (0..24)
            .map(|i| {
                let p = quad[i / 6];
                match i % 6 {
                    0 => -(p[1] - 0.5),
                    1 => p[0] - 0.5,
                    5 => 1.0,
                    _ => 0.0,
                }
            })
            .collect();
        assert!(
            (quad_form(&rz) - rho_t * jz).abs() < 1e-12 * rho_t,
            "{lumped}: {}",
            quad_form(&rz)
        );
    }
}

// ---------------------------------------------------------------------------------------------
// (d) thin clamped plate: no shear locking

/// Central deflection of a clamped square plate (side L), 8 × 8 MITC4 (as a 4 × 4 quarter with
/// symmetry conditions, same result), against Kirchhoff
/// (Timoshenko & Woinowsky-Krieger, *Theory of Plates and Shells*, 1959, tables 35 and 59):
/// central point load P, w = 0.00560 P L²/D (series value 0.005612); uniform load q,
/// w = 0.00126 q L⁴/D (series value 0.00126532); D = Et³/(12(1−ν²)), t/L = 1e-2, 1e-3, 1e-4.
/// Shear locking would make the thin cases too stiff by orders of magnitude; here the ratios
/// are the mesh's discretization error (8 × 8: point 0.963, uniform 0.988; 16 × 16: 0.990,
/// 0.997) and do not depend on t/L.
#[test]
fn clamped_plate_does_not_lock() {
    let (e, nu, l) = (1.0e7, 0.3, 1.0);
    // The quarter [0, L/2]² with a 4 × 4 mesh and symmetry conditions is the full 8 × 8 mesh.
    let n = 4;
    let half = 0.5 * l;
    let (xyz, quads) = grid_mesh(n, n, half, half, |_, _| 0.0);
    let centre = n * (n + 1) + n;
    let fixed: Vec<usize> = (0..xyz.len())
        .flat_map(|a| {
            let [x, y, _] = xyz[a];
            let clamped = x.min(y) < 1e-12;
            // Symmetry planes: x = L/2 → T1, R2, R3 fixed; y = L/2 → T2, R1, R3 fixed.
            let (sx, sy) = ((x - half).abs() < 1e-12, (y - half).abs() < 1e-12);
            (0..6)
                .filter(move |&c| {
                    clamped || (sx && [0, 4, 5].contains(&c)) || (sy && [1, 3, 5].contains(&c))
                })
                .map(move |c| 6 * a + c)
        })
        .collect();
    let zero = vec![0.0; fixed.len()];
    let mut ratios = Vec::new();
    for tl in [1e-2, 1e-3, 1e-4] {
        let t = tl * l;
        let k = quad_mesh_stiffness(&xyz, &quads, &ShellSection::pshell(&iso(e, nu, t)).unwrap());
        let d = e * t.powi(3) / (12.0 * (1.0 - nu * nu));
        let mut point_load = vec![0.0; k.nrows()];
        point_load[6 * centre + 2] = 0.25; // a quarter of P = 1
        // Uniform q = 1: a quarter of each element's load on each of its grids.
        let mut uniform_load = vec![0.0; k.nrows()];
        let h = half / n as f64;
        for q in &quads {
            for &a in q {
                uniform_load[6 * a + 2] += 0.25 * h * h;
            }
        }
        let u = solve_with_prescribed(&k, &[point_load, uniform_load], &fixed, &zero);
        let point = u[0][6 * centre + 2] / (0.005612 * l * l / d);
        let uniform = u[1][6 * centre + 2] / (0.00126532 * l.powi(4) / d);
        println!(
            "clamped plate t/L = {tl:e}: w/w_Kirchhoff point {point:.4}, uniform {uniform:.4}"
        );
        assert!(
            (point - 1.0).abs() < 0.04,
            "t/L = {tl}: point-load ratio {point}"
        );
        assert!(
            (uniform - 1.0).abs() < 0.02,
            "t/L = {tl}: uniform-load ratio {uniform}"
        );
        ratios.push((point, uniform));
    }
    // Thin limit reached: t/L = 1e-3 and 1e-4 agree to 0.1 %.
    assert!((ratios[1].0 - ratios[2].0).abs() < 1e-3 && (ratios[1].1 - ratios[2].1).abs() < 1e-3);
}

// ---------------------------------------------------------------------------------------------
// (e) cantilever of shells

/// Cantilever strip L = 10, b = 1, t = 0.1 (ν = 0, so plate and beam bending agree), 20 × 2
/// MITC4, tip load P out of plane and in plane: δ = PL³/(3EI) + PL/(κGA), κ = 5/6.
#[test]
fn shell_cantilever_tip_deflection() {
    let (e, l, b, t, p) = (1.0e7, 10.0, 1.0, 0.1, 1.0);
    let (xyz, quads) = grid_mesh(20, 2, l, b, |_, _| 0.0);
    let sec = ShellSection::pshell(&iso(e, 0.0, t)).unwrap();
    let k = quad_mesh_stiffness(&xyz, &quads, &sec);
    let root: Vec<usize> = (0..xyz.len()).filter(|&a| xyz[a][0] < 1e-12).collect();
    let tip: Vec<usize> = (0..xyz.len()).filter(|&a| xyz[a][0] > l - 1e-12).collect();
    let fixed: Vec<usize> = root
        .iter()
        .flat_map(|&a| (0..6).map(move |c| 6 * a + c))
        .collect();
    let i = b * t.powi(3) / 12.0;
    let exact = p * l.powi(3) / (3.0 * e * i) + p * l / (5.0 / 6.0 * e / 2.0 * b * t);
    // Consistent tip load P on the 3 tip grids (P/4, P/2, P/4): out of plane (T3) and, on
    // the same strip seen edgewise with depth b, in plane (T2).
    let mut out_of_plane = vec![0.0; k.nrows()];
    let mut in_plane = vec![0.0; k.nrows()];
    for (&a, w) in tip.iter().zip([0.25, 0.5, 0.25]) {
        out_of_plane[6 * a + 2] = w * p;
        in_plane[6 * a + 1] = w * p;
    }
    let u = solve_with_prescribed(
        &k,
        &[out_of_plane, in_plane],
        &fixed,
        &vec![0.0; fixed.len()],
    );
    let w = tip.iter().map(|&a| u[0][6 * a + 2]).sum::<f64>() / 3.0;
    println!("cantilever out of plane: δ/δ_exact = {:.5}", w / exact);
    assert!((w / exact - 1.0).abs() < 0.02, "ratio {}", w / exact);
    // In plane: the assumed membrane shear removes the parasitic shear of in-plane bending.
    let v = tip.iter().map(|&a| u[1][6 * a + 1]).sum::<f64>() / 3.0;
    let i_in = t * b.powi(3) / 12.0;
    let exact_in = p * l.powi(3) / (3.0 * e * i_in) + p * l / (5.0 / 6.0 * e / 2.0 * b * t);
    println!("cantilever in plane: δ/δ_exact = {:.5}", v / exact_in);
    assert!(
        (v / exact_in - 1.0).abs() < 0.02,
        "in-plane ratio {}",
        v / exact_in
    );
}

// ---------------------------------------------------------------------------------------------
// (f) affine splits

fn max_abs(m: &Mat<f64>) -> f64 {
    let mut x = 0.0f64;
    for i in 0..m.nrows() {
        for j in 0..m.ncols() {
            x = x.max(m[(i, j)].abs());
        }
    }
    x
}

fn rel_diff(a: &Mat<f64>, b: &Mat<f64>) -> f64 {
    max_abs(&(a - b)) / max_abs(b)
}

/// The section of split data at its nominal parameter values (the deck's section).
fn nominal_section(data: &SectionData) -> ShellSection {
    match data {
        SectionData::Pshell { section, .. } => ShellSection::pshell(section),
        SectionData::Laminate(l) => ShellSection::laminate(l),
    }
    .unwrap()
}

/// Σ f_i(p) K_i against the matrix built at p with the incompatible modes condensed with the
/// nominal section (module doc, "frozen condensation"), for every split, at parameter values
/// away from the nominal ones (ν 0.21 against 0.3, Θ 37° against 20°, …).
#[test]
fn affine_stiffness_and_mass_match_direct_matrices() {
    let quad: Vec<V3> = [
        [0.0, 0.0, 0.02],
        [1.1, 0.0, -0.02],
        [1.0, 1.0, 0.02],
        [0.05, 0.9, -0.02],
    ]
    .map(rotate)
    .to_vec();
    let tria: Vec<V3> = vec![[0.0, 0.0, 0.0], [1.0, 0.2, 0.3], [0.3, 0.8, -0.2]];
    let mx = Some([1.0, 0.3, 0.0]);
    // Homogeneous PSHELL (material 1 in every role) and one with distinct MID1 = MID3 (1),
    // MID2 (2) and MID4 (4) materials, 12I/T³ = 0.55 and TS/T = 0.75.
    let iso_data = |e, nu, rho| PshellSection {
        nsm: 0.3,
        zoffs: 0.002,
        ..PshellSection::homogeneous(RoleMaterial::mat1(1, e, nu, rho), 0.01)
    };
    let mixed = |mid: u32, e, nu, rho| {
        let m = |id: u32, e0: f64, nu0: f64, rho0: f64| {
            if id == mid {
                RoleMaterial::mat1(id, e, nu, rho)
            } else {
                RoleMaterial::mat1(id, e0, nu0, rho0)
            }
        };
        let m1 = m(1, 70e9, 0.33, 2700.0);
        PshellSection {
            bending: Some(m(2, 190e9, 0.27, 7700.0)),
            bending_ratio: 0.55,
            shear_ratio: 0.75,
            coupling: Some(m(4, 4e9, 0.15, 90.0)),
            ..PshellSection {
                membrane: Some(m1),
                shear: Some(m1),
                ..iso_data(70e9, 0.33, 2700.0)
            }
        }
    };
    let pshell = |section, parametrized| SectionData::Pshell {
        section,
        parametrized,
    };
    let ply = |theta_deg: f64, t: f64| Ply {
        e1: 140e9,
        e2: 10e9,
        nu12: 0.3,
        g12: 5e9,
        g1z: Some(5e9),
        g2z: Some(3.5e9),
        rho: 1600.0,
        t,
        theta_deg,
    };
    let lam = |theta: f64, t: f64| Laminate {
        plies: vec![ply(theta, t), ply(-theta, t), ply(theta, t)],
        z0: None,
        nsm: 0.1,
        symmetric: true,
    };
    let v = CoefficientValues {
        e: 120e9,
        nu: 0.21,
        rho: 4321.0,
        theta_deg: 37.0,
        h: 0.4e-3,
        lumped: 0.0,
    };
    let mut cases = vec![
        (
            pshell(iso_data(70e9, 0.3, 2700.0), 1),
            SectionParameter::E,
            0.3,
            ShellSection::pshell(&iso_data(v.e, 0.3, 2700.0)),
        ),
        (
            pshell(iso_data(70e9, 0.3, 2700.0), 1),
            SectionParameter::Nu,
            0.3,
            ShellSection::pshell(&iso_data(v.e, v.nu, 2700.0)),
        ),
        (
            pshell(iso_data(70e9, 0.3, 2700.0), 1),
            SectionParameter::Rho,
            0.3,
            ShellSection::pshell(&iso_data(70e9, 0.3, v.rho)),
        ),
        (
            SectionData::Laminate(lam(20.0, 0.25e-3)),
            SectionParameter::Theta,
            0.3,
            ShellSection::laminate(&lam(v.theta_deg, 0.25e-3)),
        ),
        (
            SectionData::Laminate(lam(20.0, 0.25e-3)),
            SectionParameter::Tply,
            0.3,
            ShellSection::laminate(&lam(20.0, v.h)),
        ),
    ];
    // Distinct materials: the parameter on each of them (ν at E: that material's nominal).
    for (mid, e0, nu0, rho0) in [
        (1, 70e9, 0.33, 2700.0),
        (2, 190e9, 0.27, 7700.0),
        (4, 4e9, 0.15, 90.0),
    ] {
        let nominal = mixed(mid, e0, nu0, rho0);
        cases.push((
            pshell(nominal, mid),
            SectionParameter::E,
            nu0,
            ShellSection::pshell(&mixed(mid, v.e, nu0, rho0)),
        ));
        cases.push((
            pshell(nominal, mid),
            SectionParameter::Nu,
            nu0,
            ShellSection::pshell(&mixed(mid, v.e, v.nu, rho0)),
        ));
        cases.push((
            pshell(nominal, mid),
            SectionParameter::Rho,
            nu0,
            ShellSection::pshell(&mixed(mid, e0, nu0, v.rho)),
        ));
    }
    for (data, param, nu_at_e, direct) in cases {
        let direct = direct.unwrap();
        let parts = affine_sections(&data, param).unwrap();
        let v = if param == SectionParameter::E {
            CoefficientValues { nu: nu_at_e, ..v }
        } else {
            v
        };
        let nominal = nominal_section(&data);
        for xyz in [&quad, &tria] {
            let k = affine_stiffness(xyz, &parts, Incompatible::Condensed(&nominal), mx)
                .unwrap()
                .evaluate(&v);
            let m = affine_mass(xyz, &parts, false).unwrap().evaluate(&v);
            let (kd, md) = if xyz.len() == 4 {
                let q = [xyz[0], xyz[1], xyz[2], xyz[3]];
                (
                    quad4_stiffness(&q, &direct, Incompatible::Condensed(&nominal), mx).unwrap(),
                    quad4_mass(&q, &direct.mass, false).unwrap(),
                )
            } else {
                let t = [xyz[0], xyz[1], xyz[2]];
                (
                    tria3_stiffness(&t, &direct, mx).unwrap(),
                    tria3_mass(&t, &direct.mass, false).unwrap(),
                )
            };
            assert!(
                rel_diff(&k, &kd) < 1e-12,
                "{param:?} K: {}",
                rel_diff(&k, &kd)
            );
            assert!(
                rel_diff(&m, &md) < 1e-12,
                "{param:?} M: {}",
                rel_diff(&m, &md)
            );
        }
        // The section split itself is exact too.
        let s = evaluate(&parts, &v);
        assert!((s.d[0][0] - direct.d[0][0]).abs() < 1e-12 * direct.d[0][0].abs());
    }
}

// ---------------------------------------------------------------------------------------------
// degenerate geometry

#[test]
fn degenerate_geometry_is_an_error() {
    let s = steel(0.01, 0.3);
    let collinear = [[0.0, 0.0, 0.0], [1.0, 1.0, 1.0], [2.0, 2.0, 2.0]];
    assert_eq!(
        tria3_stiffness(&collinear, &s, None).unwrap_err(),
        ShellError::ZeroArea { shape: "CTRIA3" }
    );
    let coincident = [
        [0.0, 0.0, 0.0],
        [0.0, 0.0, 0.0],
        [0.0, 0.0, 0.0],
        [0.0, 0.0, 0.0],
    ];
    assert_eq!(
        quad4_stiffness(&coincident, &s, Incompatible::Condensed(&s), None).unwrap_err(),
        ShellError::ZeroArea { shape: "CQUAD4" }
    );
    let line = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [2.0, 0.0, 0.0],
        [3.0, 0.0, 0.0],
    ];
    assert_eq!(
        quad4_mass(&line, &s.mass, true).unwrap_err(),
        ShellError::ZeroArea { shape: "CQUAD4" }
    );
    // Re-entrant corner at grid 3; three collinear grids (degenerate corner at grid 2).
    let dart = [
        [0.0, 0.0, 0.0],
        [2.0, 0.0, 0.0],
        [0.5, 0.5, 0.0],
        [0.0, 2.0, 0.0],
    ];
    assert_eq!(
        quad4_stiffness(&dart, &s, Incompatible::Condensed(&s), None).unwrap_err(),
        ShellError::NotConvex { corner: 3 }
    );
    let flat_corner = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [2.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
    ];
    assert_eq!(
        quad4_stiffness(&flat_corner, &s, Incompatible::Condensed(&s), None).unwrap_err(),
        ShellError::NotConvex { corner: 2 }
    );
    let square = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
    ];
    assert!(matches!(
        quad4_stiffness(
            &square,
            &s,
            Incompatible::Condensed(&s),
            Some([0.0, 0.0, 1.0])
        ),
        Err(ShellError::MaterialAxisNormal { .. })
    ));
    assert_eq!(
        affine_stiffness(&square[..2], &[], Incompatible::Condensed(&s), None).unwrap_err(),
        ShellError::NodeCount(2)
    );
}
/// A rectangular CQUAD4 a × b whose thickness varies linearly in x (T1 = T4 = t0, T2 = T3 = t1)
/// under the constant-curvature field w = κx²/2, θy = −κx (no transverse shear; the patch test
/// shows the element reproduces it exactly): the strain energy is
/// ½ κ² E/(12(1−ν²)) b ∫₀ᵃ t(x)³ dx = ½ κ² E/(12(1−ν²)) b a (t1⁴ − t0⁴)/(4(t1 − t0)).
/// With the section taken at the integration points the 2-point Gauss rule integrates t³ (cubic
/// in x) exactly, so the energy matches to round-off; the mean thickness would give
/// a ((t0+t1)/2)³ in place of the integral (−10 % for t1 = 2 t0). Uniform corners reproduce the
/// single-section stiffness.
#[test]
fn tapered_quad_integrates_bending_thickness_cubed_exactly() {
    let (a, b, t0, t1, e, nu, kappa) = (0.4, 0.3, 0.01, 0.02, 70e9, 0.3, 1e-3);
    let xyz = [[0.0, 0.0, 0.0], [a, 0.0, 0.0], [a, b, 0.0], [0.0, b, 0.0]];
    let corners = [t0, t1, t1, t0];
    let nominal_at = |corners: &[f64]| -> Vec<ShellSection> {
        super::shell::integration_point_thickness(corners)
            .unwrap()
            .into_iter()
            .map(|t| ShellSection::pshell(&iso(e, nu, t)).unwrap())
            .collect()
    };
    let sections_at = |corners: &[f64]| -> Vec<Vec<(super::affine::Coefficient, ShellSection)>> {
        nominal_at(corners)
            .into_iter()
            .map(|s| vec![(super::affine::Coefficient::Constant, s)])
            .collect()
    };
    let at = |corners: &[f64]| {
        super::shell::affine_stiffness_at_points(
            &xyz,
            &sections_at(corners),
            Incompatible::Condensed(nominal_at(corners).as_slice()),
            None,
        )
    };
    let k = at(&corners).unwrap();
    assert_eq!(k.parts.len(), 1);
    let k = &k.parts[0].1;
    let u: Vec<f64> = xyz
        .iter()
        .flat_map(|p| [0.0, 0.0, 0.5 * kappa * p[0] * p[0], 0.0, -kappa * p[0], 0.0])
        .collect();
    let energy = 0.5
        * (0..24)
            .map(|i| (0..24).map(|j| u[i] * k[(i, j)] * u[j]).sum::<f64>())
            .sum::<f64>();
    let d = e / (12.0 * (1.0 - nu * nu));
    let exact = 0.5 * kappa * kappa * d * b * a * (t1.powi(4) - t0.powi(4)) / (4.0 * (t1 - t0));
    assert!(
        (energy - exact).abs() < 1e-10 * exact,
        "energy {energy} vs exact {exact}"
    );
    let mean = 0.5 * kappa * kappa * d * b * a * (0.5 * (t0 + t1)).powi(3);
    assert!(
        (exact - mean) / exact > 0.09,
        "the case must separate the two rules"
    );
    // uniform corners: the same matrix as one section everywhere
    let uniform = at(&[t0; 4]).unwrap();
    let s0 = ShellSection::pshell(&iso(e, nu, t0)).unwrap();
    let single = quad4_stiffness(&xyz, &s0, Incompatible::Condensed(&s0), None).unwrap();
    assert!(rel_diff(&uniform.parts[0].1, &single) < 1e-14);
    // one list per point, or an error
    assert!(matches!(
        super::shell::affine_stiffness_at_points(
            &xyz,
            &sections_at(&corners)[..3],
            Incompatible::Condensed(nominal_at(&corners).as_slice()),
            None
        ),
        Err(ShellError::PointCount {
            expected: 4,
            got: 3
        })
    ));
    assert!(matches!(
        super::shell::affine_stiffness_at_points(
            &xyz,
            &sections_at(&corners),
            Incompatible::Condensed(&nominal_at(&corners)[..2]),
            None
        ),
        Err(ShellError::PointCount {
            expected: 4,
            got: 2
        })
    ));
}

// ---------------------------------------------------------------------------------------------
// in-plane bending and the frozen condensation of the incompatible modes

/// Pure in-plane bending of a strip, x from 0 to 2a, y ∈ [−b/2, b/2], in a rotated plane:
/// u = −κxy, v = κx²/2 + νκy²/2, θz = κx (σx = −Eκy, σy = τ = 0). Element edges are the lines
/// y = ±b/2 and x = x₀ + s(y + b/2) (skew s; s = 0: rectangles). On a parallelogram the map is
/// affine, so the quadratic field lies in the element space (bilinear + the four incompatible
/// modes (1 − ξ²)x_i, (1 − η²)y_i, (1 − η²)x_i, (1 − ξ²)y_i), with zero shear (the assumed
/// element-mean shear is exact) and zero drilling residual (ω of the enhanced field is κx): with
/// ν = 0.3 a single element stores exactly ½EκI·κ·a (I = tb³/12), and on two elements with the
/// end grids prescribed the free mid-span grids come out exact. Without the incompatible modes
/// (`PARAM,QINCOMP,NO`, [`Incompatible::Off`]) on the rectangle, εy cannot vary across the
/// depth: the nodal values interpolate to u = −κxy, v = κax/2 + const, whose hourglass rotation
/// doubled, ω* = 2ω − ω̄ = κx, is again the exact θz, but εy = 0 where σy = 0 needs εy = νκy,
/// and the element stores exactly 1/(1 − ν²) of that energy.
#[test]
fn quad_in_plane_pure_bending_is_exact() {
    for skew in [0.0, 1.0, -0.7] {
        pure_bending_case(skew);
    }
}

fn pure_bending_case(skew: f64) {
    let (a, b, t, e, nu, kappa) = (0.3, 0.2, 0.01, 70e9, 0.3, 1e-3);
    let section = ShellSection::pshell(&iso(e, nu, t)).unwrap();
    let mx = rotate([1.0, 0.0, 0.0]);
    let (lo, hi) = (-0.5 * b, 0.5 * b);
    let (xy, quads) = (
        [
            [0.0, lo],
            [a, lo],
            [2.0 * a, lo],
            [skew * b, hi],
            [a + skew * b, hi],
            [2.0 * a + skew * b, hi],
        ],
        [[0, 1, 4, 3], [1, 2, 5, 4]],
    );
    let xyz: Vec<V3> = xy.iter().map(|p| rotate([p[0], p[1], 0.0])).collect();
    let exact: Vec<f64> = xy
        .iter()
        .flat_map(|&[x, y]| {
            let t = rotate([-kappa * x * y, 0.5 * kappa * (x * x + nu * y * y), 0.0]);
            let r = rotate([0.0, 0.0, kappa * x]);
            [t[0], t[1], t[2], r[0], r[1], r[2]]
        })
        .collect();
    let els: Vec<_> = quads
        .iter()
        .map(|q| {
            (
                q.to_vec(),
                quad4_stiffness(
                    &quad_of(&xyz, q),
                    &section,
                    Incompatible::Condensed(&section),
                    Some(mx),
                )
                .unwrap(),
            )
        })
        .collect();
    // One element: the strain energy of the exact field (its area is a·b whatever the skew).
    let ue: Vec<f64> = quads[0]
        .iter()
        .flat_map(|&g| exact[6 * g..6 * g + 6].to_vec())
        .collect();
    let energy_of = |k: &Mat<f64>| {
        0.5 * (0..24)
            .map(|i| (0..24).map(|j| ue[i] * k[(i, j)] * ue[j]).sum::<f64>())
            .sum::<f64>()
    };
    let energy = energy_of(&els[0].1);
    let want = 0.5 * e * kappa * kappa * t * b.powi(3) / 12.0 * a;
    assert!(
        (energy / want - 1.0).abs() < 1e-10,
        "skew {skew}: energy {energy} vs {want} (ratio {})",
        energy / want
    );
    if skew == 0.0 {
        let plain = quad4_stiffness(
            &quad_of(&xyz, &quads[0]),
            &section,
            Incompatible::Off,
            Some(mx),
        )
        .unwrap();
        let poisson = 1.0 / (1.0 - nu * nu);
        let ratio = energy_of(&plain) / want;
        assert!(
            (ratio / poisson - 1.0).abs() < 1e-10,
            "without the modes: ratio {ratio} vs 1/(1 − ν²) = {poisson}"
        );
    }
    // Two elements, end grids prescribed, mid-span grids 1 and 4 free and unloaded.
    let k = assemble(xyz.len(), &els);
    let fixed: Vec<usize> = [0, 2, 3, 5]
        .iter()
        .flat_map(|&g| (0..6).map(move |c| 6 * g + c))
        .collect();
    let values: Vec<f64> = fixed.iter().map(|&d| exact[d]).collect();
    let u = solve_with_prescribed(&k, &[vec![0.0; 36]], &fixed, &values).remove(0);
    let scale = exact.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    for g in [1, 4] {
        for c in 0..6 {
            let d = 6 * g + c;
            assert!(
                (u[d] - exact[d]).abs() < 1e-10 * scale,
                "skew {skew}, grid {g} DOF {c}: {} vs {}",
                u[d],
                exact[d]
            );
        }
    }
}

/// The condensation matrix T depends on the section only through the ratios of its entries:
/// built with a nominal section, K is exact for any multiple of it (a PMPAR on E). For another
/// ν the frozen T is not the optimal one: K_frozen − K_recondensed is positive semi-definite
/// (the condensed energy is the minimum over the modes) and of second order in Δν.
#[test]
fn frozen_condensation_is_exact_under_scaling_and_second_order_otherwise() {
    let quad = [
        [0.0, 0.0, 0.01],
        [1.1, 0.0, -0.01],
        [1.0, 0.7, 0.01],
        [0.05, 0.6, -0.01],
    ]
    .map(rotate);
    let (e, t) = (70e9, 0.02);
    let section = |e: f64, nu: f64| ShellSection::pshell(&iso(e, nu, t)).unwrap();
    let nominal = section(e, 0.3);
    let scaled = section(2.5 * e, 0.3);
    let (frozen, exact) = (
        quad4_stiffness(&quad, &scaled, Incompatible::Condensed(&nominal), None).unwrap(),
        quad4_stiffness(&quad, &scaled, Incompatible::Condensed(&scaled), None).unwrap(),
    );
    assert!(
        rel_diff(&frozen, &exact) < 1e-12,
        "E scaling: {}",
        rel_diff(&frozen, &exact)
    );
    let gap = |dnu: f64| {
        let s = section(e, 0.3 + dnu);
        let d = quad4_stiffness(&quad, &s, Incompatible::Condensed(&nominal), None).unwrap()
            - quad4_stiffness(&quad, &s, Incompatible::Condensed(&s), None).unwrap();
        let ev = d.self_adjoint_eigenvalues(Side::Lower).unwrap();
        let k = quad4_stiffness(&quad, &s, Incompatible::Condensed(&s), None).unwrap();
        assert!(
            ev[0] > -1e-12 * max_abs(&k),
            "Δν {dnu}: K_frozen − K is not PSD ({})",
            ev[0]
        );
        max_abs(&d) / max_abs(&k)
    };
    let (g1, g2) = (gap(-0.1), gap(-0.05));
    println!("frozen condensation, ν 0.3 → 0.2: max |ΔK|/max |K| {g1:.3e}; → 0.25: {g2:.3e}");
    assert!(
        g1 > 0.0 && (g1 / g2 - 4.0).abs() < 0.5,
        "not second order: {g1} / {g2}"
    );
}

// ---------------------------------------------------------------------------------------------
// membrane loaded and supported through the grid translations only

/// Uniform tension σ of a distorted 4 × 3 patch on [0, 1] × [0, 0.6] (straight outer edges, every
/// interior grid moved, the edge grids moved along their edges), held by u = 0 at the x = 0
/// grids and v = 0 at the origin, pulled by nodal forces at x = 1 (σt times each grid's half of
/// its adjacent edge segments, the consistent load of a linear edge), the drilling rotations
/// free everywhere (w, θx, θy held: a membrane problem). The exact field u = σx/E,
/// v = −νσy/E, θz = 0 lies in the element space with zero drilling residual and the element's
/// edges are linear in the corner translations, so the support holds the edge and the nodal
/// forces are the consistent load: every DOF is exact to round-off, with and without the
/// incompatible modes (they are orthogonal to constant stress, ∫B_i dA = 0).
#[test]
fn membrane_tension_patch_with_free_drilling_rotations_is_exact() {
    let (nx, ny, lx, ly) = (4, 3, 1.0, 0.6);
    let (e, nu, t, sigma) = (70e9, 0.3, 0.01, 7e7);
    let section = ShellSection::pshell(&iso(e, nu, t)).unwrap();
    let (mut xyz, quads) = grid_mesh(nx, ny, lx, ly, |_, _| 0.0);
    let wobble = |i: usize, j: usize, k: usize| ((3 * i + 5 * j + k) % 7) as f64 / 3.0 - 1.0;
    for j in 0..=ny {
        for i in 0..=nx {
            let p = &mut xyz[j * (nx + 1) + i];
            if i > 0 && i < nx {
                p[0] += 0.06 * wobble(i, j, 0);
            }
            if j > 0 && j < ny {
                p[1] += 0.05 * wobble(i, j, 2);
            }
        }
    }
    let n = 6 * xyz.len();
    let edge = |i: usize| (0..=ny).map(move |j| j * (nx + 1) + i);
    let mut f = vec![0.0; n];
    let right: Vec<usize> = edge(nx).collect();
    for w in right.windows(2) {
        let half = 0.5 * sigma * t * (xyz[w[1]][1] - xyz[w[0]][1]);
        f[6 * w[0]] += half;
        f[6 * w[1]] += half;
    }
    let mut fixed: Vec<usize> = edge(0).map(|g| 6 * g).collect();
    fixed.push(1);
    fixed.extend((0..xyz.len()).flat_map(|g| [6 * g + 2, 6 * g + 3, 6 * g + 4]));
    let exact: Vec<f64> = xyz
        .iter()
        .flat_map(|p| [sigma * p[0] / e, -nu * sigma * p[1] / e, 0.0, 0.0, 0.0, 0.0])
        .collect();
    let scale = sigma * lx / e;
    for modes in [Incompatible::Condensed(&section), Incompatible::Off] {
        let els: Vec<_> = quads
            .iter()
            .map(|q| {
                let k = quad4_stiffness(&quad_of(&xyz, q), &section, modes, None).unwrap();
                (q.to_vec(), k)
            })
            .collect();
        let k = assemble(xyz.len(), &els);
        let u = solve_with_prescribed(&k, &[f.clone()], &fixed, &vec![0.0; fixed.len()]).remove(0);
        let worst = (0..n).fold(0.0f64, |m, d| m.max((u[d] - exact[d]).abs()));
        // round-off of a dense LU on a 120-DOF stiffness with condition ~1e8: 1e-10
        assert!(
            worst < 1e-10 * scale,
            "{modes:?}: largest error {worst:e} of {scale:e}"
        );
    }
}
