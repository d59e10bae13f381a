//! Acceptance tests of the solid elements (DESIGN.md §4): zero-energy modes, patch tests,
//! cantilever bending, symmetry/definiteness, total mass, affine parts, geometry errors.

use super::affine::CoefficientValues;
use super::solid::*;
use super::solid_midside::Midsides;
use super::solid_shape as shape;
use crate::geometry::vec3::triple;
use faer::linalg::solvers::Solve;
use faer::{Mat, Side};
use std::collections::HashMap;

const STEEL: Isotropic = Isotropic { e: 210.0, nu: 0.3 };

// ---------------------------------------------------------------- geometry samples

fn unit_hexa() -> Vec<[f64; 3]> {
    vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
        [1.0, 0.0, 1.0],
        [1.0, 1.0, 1.0],
        [0.0, 1.0, 1.0],
    ]
}

fn distorted_hexa() -> Vec<[f64; 3]> {
    vec![
        [0.0, 0.0, 0.0],
        [1.3, 0.1, -0.1],
        [1.1, 0.9, 0.2],
        [-0.1, 1.2, 0.05],
        [0.1, -0.2, 1.0],
        [1.0, 0.05, 1.3],
        [1.2, 1.1, 0.9],
        [0.0, 0.8, 1.1],
    ]
}

fn unit_penta() -> Vec<[f64; 3]> {
    vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
        [1.0, 0.0, 1.0],
        [0.0, 1.0, 1.0],
    ]
}

fn distorted_penta() -> Vec<[f64; 3]> {
    vec![
        [0.0, 0.0, 0.0],
        [1.4, 0.2, 0.1],
        [-0.2, 0.9, -0.1],
        [0.1, 0.1, 1.2],
        [1.1, -0.1, 0.8],
        [0.2, 1.3, 1.1],
    ]
}

fn unit_tet() -> Vec<[f64; 3]> {
    vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
    ]
}

fn distorted_tet() -> Vec<[f64; 3]> {
    vec![
        [0.1, -0.2, 0.0],
        [1.5, 0.3, 0.2],
        [0.4, 1.1, -0.3],
        [0.2, 0.5, 0.9],
    ]
}

/// The quadratic element `kind` on the corners `c`: each mid-side grid at the middle of its
/// edge moved by `bend` times a fixed offset (curved edges when `bend` ≠ 0).
fn quadratic(kind: SolidKind, c: &[[f64; 3]], bend: f64) -> Vec<[f64; 3]> {
    let mut x = c.to_vec();
    for (edge, [a, b]) in shape::midside_edges(kind).iter().enumerate() {
        let e = edge % 6;
        let off = [
            0.7 - 0.2 * e as f64,
            0.3 * e as f64 - 0.5,
            0.1 * (e % 3) as f64 - 0.2,
        ];
        x.push(std::array::from_fn(|k| {
            0.5 * (c[*a][k] + c[*b][k]) + bend * off[k]
        }));
    }
    x
}

/// CTETRA 10 on the corners `c` with mid-edge grids at the edge midpoints plus `bend` · an
/// edge-specific offset (bend = 0: straight edges).
fn tet10(c: &[[f64; 3]], bend: f64) -> Vec<[f64; 3]> {
    quadratic(SolidKind::Tetra10, c, bend)
}

/// Every element kind, regular and distorted (and the quadratic ones with curved edges).
fn samples() -> Vec<(SolidKind, &'static str, Vec<[f64; 3]>)> {
    let (h20, p15) = (SolidKind::Hexa20, SolidKind::Penta15);
    vec![
        (h20, "regular", quadratic(h20, &unit_hexa(), 0.0)),
        (h20, "distorted", quadratic(h20, &distorted_hexa(), 0.0)),
        (h20, "curved", quadratic(h20, &distorted_hexa(), 0.06)),
        (p15, "regular", quadratic(p15, &unit_penta(), 0.0)),
        (p15, "distorted", quadratic(p15, &distorted_penta(), 0.0)),
        (p15, "curved", quadratic(p15, &distorted_penta(), 0.06)),
        (SolidKind::Hexa8, "regular", unit_hexa()),
        (SolidKind::Hexa8, "distorted", distorted_hexa()),
        (SolidKind::Penta6, "regular", unit_penta()),
        (SolidKind::Penta6, "distorted", distorted_penta()),
        (SolidKind::Tetra4, "regular", unit_tet()),
        (SolidKind::Tetra4, "distorted", distorted_tet()),
        (SolidKind::Tetra10, "regular", tet10(&unit_tet(), 0.0)),
        (
            SolidKind::Tetra10,
            "distorted",
            tet10(&distorted_tet(), 0.0),
        ),
        (SolidKind::Tetra10, "curved", tet10(&distorted_tet(), 0.04)),
        (SolidKind::Pyram5, "regular", unit_pyram()),
        (SolidKind::Pyram5, "distorted", distorted_pyram()),
    ]
}

/// Unit-square base, apex over its centre at height 1 (volume 1/3).
fn unit_pyram() -> Vec<[f64; 3]> {
    vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.5, 0.5, 1.0],
    ]
}

/// A warped base and a leaning apex.
fn distorted_pyram() -> Vec<[f64; 3]> {
    vec![
        [0.05, -0.02, 0.0],
        [1.1, 0.03, 0.04],
        [0.95, 1.05, -0.03],
        [-0.04, 0.9, 0.02],
        [0.6, 0.45, 1.1],
    ]
}

// ---------------------------------------------------------------- helpers

fn max_abs(m: &Mat<f64>) -> f64 {
    let mut v = 0.0_f64;
    for j in 0..m.ncols() {
        for i in 0..m.nrows() {
            v = v.max(m[(i, j)].abs());
        }
    }
    v
}

fn eigenvalues(m: &Mat<f64>) -> Vec<f64> {
    m.self_adjoint_eigenvalues(Side::Lower)
        .expect("symmetric eigenvalues")
}

/// Number of eigenvalues below 1e-8 · the largest.
fn zero_modes(k: &Mat<f64>) -> usize {
    let ev = eigenvalues(k);
    let top = ev.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    ev.iter().filter(|v| v.abs() < 1e-8 * top).count()
}

/// Grids and elements (topology with its blank mid-sides, given grids).
type Mesh = (Vec<[f64; 3]>, Vec<(Midsides, Vec<usize>)>);

fn whole(kind: SolidKind, nodes: Vec<usize>) -> (Midsides, Vec<usize>) {
    (Midsides::complete(kind), nodes)
}

fn element_stiffness(mids: &Midsides, x: &[[f64; 3]], mat: Isotropic) -> Mat<f64> {
    let mut k = mids
        .affine_stiffness(x, StiffnessParametrization::Fixed(mat))
        .expect("element stiffness");
    k.parts.remove(0).1
}

fn assemble(mesh: &Mesh, mat: Isotropic) -> Mat<f64> {
    let (xyz, elements) = mesh;
    let mut k = Mat::<f64>::zeros(3 * xyz.len(), 3 * xyz.len());
    for (mids, nodes) in elements {
        let x: Vec<[f64; 3]> = nodes.iter().map(|&n| xyz[n]).collect();
        let ke = element_stiffness(mids, &x, mat);
        let dof = |i: usize| 3 * nodes[i / 3] + i % 3;
        for j in 0..ke.ncols() {
            for i in 0..ke.nrows() {
                k[(dof(i), dof(j))] += ke[(i, j)];
            }
        }
    }
    k
}

/// A deterministic pseudo-random number in [−1, 1].
fn jitter(seed: usize) -> f64 {
    let x = (seed as f64 * 12.9898 + 78.233).sin() * 43758.5453;
    2.0 * (x - x.floor()) - 1.0
}

/// Lattice of (n+1)³ grids on the unit cube (spacing 1/n), interior grids moved by up to
/// `amp`/n in each direction; returns the coordinates and the grid index function.
fn lattice(n: usize, amp: f64) -> (Vec<[f64; 3]>, impl Fn(usize, usize, usize) -> usize) {
    let id = move |i: usize, j: usize, k: usize| i + (n + 1) * (j + (n + 1) * k);
    let h = 1.0 / n as f64;
    let mut xyz = vec![[0.0; 3]; (n + 1).pow(3)];
    for k in 0..=n {
        for j in 0..=n {
            for i in 0..=n {
                let interior = [i, j, k].iter().all(|&c| c > 0 && c < n);
                let p = id(i, j, k);
                xyz[p] = std::array::from_fn(|d| {
                    let base = [i, j, k][d] as f64 * h;
                    if interior {
                        base + amp * h * jitter(3 * p + d)
                    } else {
                        base
                    }
                });
            }
        }
    }
    (xyz, id)
}

/// The 8 lattice grids of cell (i, j, k) in CHEXA order.
fn cell(id: &impl Fn(usize, usize, usize) -> usize, i: usize, j: usize, k: usize) -> [usize; 8] {
    [
        id(i, j, k),
        id(i + 1, j, k),
        id(i + 1, j + 1, k),
        id(i, j + 1, k),
        id(i, j, k + 1),
        id(i + 1, j, k + 1),
        id(i + 1, j + 1, k + 1),
        id(i, j + 1, k + 1),
    ]
}

/// Meshes the n³ cells of a lattice with CHEXA, CPENTA (2 per cell), CTETRA (6 Kuhn
/// tetrahedra per cell, conforming), linear or quadratic.
fn lattice_mesh(kind: SolidKind, n: usize, amp: f64) -> Mesh {
    quadratic_lattice(kind, n, amp, 0.0, &|_| false)
}

/// [`lattice_mesh`] whose interior mid-side grids (quadratic kinds) are moved off their edge's
/// middle by up to `bend`/n in each direction (curved edges), and whose k-th mid-side edge (in
/// creation order) has no grid when `blank(k)`: every element on that edge takes it blank.
fn quadratic_lattice(
    kind: SolidKind,
    n: usize,
    amp: f64,
    bend: f64,
    blank: &dyn Fn(usize) -> bool,
) -> Mesh {
    let (mut xyz, id) = lattice(n, amp);
    let mut corner_lists: Vec<Vec<usize>> = Vec::new();
    for k in 0..n {
        for j in 0..n {
            for i in 0..n {
                let c = cell(&id, i, j, k);
                match kind {
                    SolidKind::Hexa8 | SolidKind::Hexa20 => corner_lists.push(c.to_vec()),
                    SolidKind::Penta6 | SolidKind::Penta15 => {
                        corner_lists.push(vec![c[0], c[1], c[2], c[4], c[5], c[6]]);
                        corner_lists.push(vec![c[0], c[2], c[3], c[4], c[6], c[7]]);
                    }
                    SolidKind::Tetra4 | SolidKind::Tetra10 => {
                        // Kuhn: paths 000 → e_p → e_p + e_q → 111 along every axis order;
                        // cell corner by bits (x, y, z) → CHEXA index.
                        let corner =
                            |b: [usize; 3]| c[[0, 1, 3, 2, 4, 5, 7, 6][b[0] + 2 * b[1] + 4 * b[2]]];
                        for (p, q, odd) in [
                            (0, 1, false),
                            (1, 2, false),
                            (2, 0, false),
                            (1, 0, true),
                            (2, 1, true),
                            (0, 2, true),
                        ] {
                            let mut b1 = [0; 3];
                            b1[p] = 1;
                            let mut b2 = b1;
                            b2[q] = 1;
                            let mut t = vec![c[0], corner(b1), corner(b2), c[6]];
                            if odd {
                                t.swap(1, 2);
                            }
                            corner_lists.push(t);
                        }
                    }
                    SolidKind::Pyram5 => unreachable!("no pyramid lattice"),
                }
            }
        }
    }
    let on_boundary = |x: [f64; 3]| {
        x.iter()
            .any(|&c| c.abs() < 1e-12 || (c - 1.0).abs() < 1e-12)
    };
    let mut midside: HashMap<(usize, usize), Option<usize>> = HashMap::new();
    let mut elements = Vec::new();
    for t in corner_lists {
        let mut nodes = t.clone();
        let mut present = vec![true; t.len()];
        for &[a, b] in shape::midside_edges(kind) {
            let key = (t[a].min(t[b]), t[a].max(t[b]));
            let count = midside.len();
            let m = *midside.entry(key).or_insert_with(|| {
                if blank(count) {
                    return None;
                }
                let mid: [f64; 3] = std::array::from_fn(|d| 0.5 * (xyz[t[a]][d] + xyz[t[b]][d]));
                let p = xyz.len();
                xyz.push(if on_boundary(mid) {
                    mid
                } else {
                    std::array::from_fn(|d| mid[d] + bend / n as f64 * jitter(7 * p + d))
                });
                Some(p)
            });
            present.push(m.is_some());
            nodes.extend(m);
        }
        elements.push((Midsides::new(kind, &present), nodes));
    }
    (xyz, elements)
}

/// MacNeal & Harder (1985) solid patch: unit cube, 7 CHEXA around an irregular inner hexahedron.
fn macneal_harder_patch() -> Mesh {
    let mut xyz = unit_hexa();
    xyz.extend([
        [0.249, 0.342, 0.192],
        [0.826, 0.288, 0.288],
        [0.850, 0.649, 0.263],
        [0.273, 0.750, 0.230],
        [0.320, 0.186, 0.643],
        [0.677, 0.305, 0.683],
        [0.788, 0.693, 0.644],
        [0.165, 0.745, 0.702],
    ]);
    let outward_faces = [
        [0, 3, 2, 1],
        [4, 5, 6, 7],
        [0, 1, 5, 4],
        [1, 2, 6, 5],
        [2, 3, 7, 6],
        [3, 0, 4, 7],
    ];
    let mut elements = vec![whole(SolidKind::Hexa8, (8..16).collect::<Vec<_>>())];
    for f in outward_faces {
        // outer face (outward normal) reversed as the bottom, the inner face on top
        let nodes = vec![
            f[0],
            f[3],
            f[2],
            f[1],
            f[0] + 8,
            f[3] + 8,
            f[2] + 8,
            f[1] + 8,
        ];
        elements.push(whole(SolidKind::Hexa8, nodes));
    }
    (xyz, elements)
}

/// Linear field u = A x + c; the exact strain is [A11, A22, A33, A12 + A21, A23 + A32, A31 + A13].
const A: [[f64; 3]; 3] = [
    [1.0e-3, 2.0e-3, -1.5e-3],
    [0.5e-3, -1.0e-3, 0.7e-3],
    [-0.4e-3, 0.9e-3, 1.5e-3],
];
const C: [f64; 3] = [1e-3, -2e-3, 0.5e-3];

fn linear_field(x: [f64; 3]) -> [f64; 3] {
    std::array::from_fn(|i| C[i] + A[i][0] * x[0] + A[i][1] * x[1] + A[i][2] * x[2])
}

/// Patch test: prescribe the linear field on the boundary grids of the unit cube, solve for the
/// interior grids; returns (max interior displacement error, max centroid strain error), both
/// relative to the field's magnitude 1e-3.
fn patch_test(mesh: &Mesh) -> (f64, f64) {
    let (xyz, elements) = mesh;
    let k = assemble(mesh, Isotropic { e: 1.0, nu: 0.25 });
    let on_boundary = |x: &[f64; 3]| {
        x.iter()
            .any(|&c| c.abs() < 1e-12 || (c - 1.0).abs() < 1e-12)
    };
    let free: Vec<usize> = (0..xyz.len())
        .filter(|&n| !on_boundary(&xyz[n]))
        .flat_map(|n| 3 * n..3 * n + 3)
        .collect();
    let fixed: Vec<usize> = (0..xyz.len())
        .filter(|&n| on_boundary(&xyz[n]))
        .flat_map(|n| 3 * n..3 * n + 3)
        .collect();
    assert!(!free.is_empty());
    let exact: Vec<f64> = xyz.iter().flat_map(|&x| linear_field(x)).collect();
    let kff = Mat::from_fn(free.len(), free.len(), |i, j| k[(free[i], free[j])]);
    let mut rhs = Mat::from_fn(free.len(), 1, |i, _| {
        -fixed
            .iter()
            .map(|&j| k[(free[i], j)] * exact[j])
            .sum::<f64>()
    });
    kff.llt(Side::Lower)
        .expect("K_ff positive definite")
        .solve_in_place(rhs.as_mut());
    let mut u = exact.clone();
    let mut du = 0.0_f64;
    for (i, &d) in free.iter().enumerate() {
        du = du.max((rhs[(i, 0)] - exact[d]).abs());
        u[d] = rhs[(i, 0)];
    }
    let eps = [
        A[0][0],
        A[1][1],
        A[2][2],
        A[0][1] + A[1][0],
        A[1][2] + A[2][1],
        A[2][0] + A[0][2],
    ];
    let mut de = 0.0_f64;
    for (mids, nodes) in elements {
        let x: Vec<[f64; 3]> = nodes.iter().map(|&n| xyz[n]).collect();
        let ue: Vec<f64> = nodes
            .iter()
            .flat_map(|&n| u[3 * n..3 * n + 3].to_vec())
            .collect();
        let s = mids.strain_at_centroid(&x, &ue).expect("strain");
        for (a, b) in s.iter().zip(eps) {
            de = de.max((a - b).abs());
        }
    }
    (du / 1e-3, de / 1e-3)
}

// ---------------------------------------------------------------- (a) zero-energy modes

#[test]
fn every_free_element_has_exactly_six_zero_energy_modes() {
    for (kind, label, xyz) in samples() {
        let k = stiffness(kind, &xyz, STEEL).unwrap();
        assert_eq!(zero_modes(&k), 6, "{kind} {label}");
    }
}

#[test]
fn free_meshes_have_exactly_six_zero_energy_modes() {
    // CTETRA 10 on one cell (6 tetrahedra, 27 grids) keeps the dense eigenproblem small
    for (kind, n) in [
        (SolidKind::Hexa8, 2),
        (SolidKind::Tetra4, 2),
        (SolidKind::Tetra10, 1),
        (SolidKind::Penta6, 2),
    ] {
        let mesh = lattice_mesh(kind, n, 0.2);
        assert_eq!(
            zero_modes(&assemble(&mesh, STEEL)),
            6,
            "free {n}×{n}×{n} {kind} mesh"
        );
    }
}

// ---------------------------------------------------------------- (b) patch tests

/// The unit cube as six CPYRAM, one on each face with the apex at a shifted interior grid: the
/// patch test (a linear field on the cube's corners gives it exactly at the apex and constant
/// strain in every pyramid).
#[test]
fn pyramids_pass_the_patch_test() {
    let mut xyz: Vec<[f64; 3]> = (0..8)
        .map(|a| super::solid_shape::node_xi(SolidKind::Hexa8, a).map(|s| 0.5 * (1.0 + s)))
        .collect();
    xyz.push([0.45, 0.56, 0.47]);
    // the cube's faces, outward; a pyramid's base runs the other way (its normal to the apex)
    let faces = [
        [0, 3, 2, 1],
        [4, 5, 6, 7],
        [0, 1, 5, 4],
        [1, 2, 6, 5],
        [2, 3, 7, 6],
        [3, 0, 4, 7],
    ];
    let elements = faces
        .iter()
        .map(|f| whole(SolidKind::Pyram5, vec![f[3], f[2], f[1], f[0], 8]))
        .collect();
    let (du, de) = patch_test(&(xyz, elements));
    assert!(
        du < 1e-10 && de < 1e-10,
        "CPYRAM patch: displacement {du:.2e}, strain {de:.2e}"
    );
}

#[test]
fn hexa_passes_the_macneal_harder_patch_test() {
    let (du, de) = patch_test(&macneal_harder_patch());
    assert!(
        du < 1e-10 && de < 1e-10,
        "CHEXA MacNeal–Harder patch: displacement {du:.2e}, strain {de:.2e}"
    );
}

#[test]
fn every_element_passes_the_patch_test_on_a_distorted_lattice() {
    for kind in [
        SolidKind::Hexa8,
        SolidKind::Penta6,
        SolidKind::Tetra4,
        SolidKind::Tetra10,
    ] {
        let (du, de) = patch_test(&lattice_mesh(kind, 3, 0.25));
        assert!(
            du < 1e-10 && de < 1e-10,
            "{kind} distorted patch: displacement {du:.2e}, strain {de:.2e}"
        );
    }
}

// ---------------------------------------------------------------- (c) bending

/// Cantilever 10 × 1 × 1 of 10 CHEXA, clamped at x = 0, tip shear P in z spread over the four tip
/// grids. Reference: Euler–Bernoulli PL³/(3EI) plus Timoshenko shear PL/(κGA) with Cowper's
/// κ = 10(1+ν)/(12+11ν) for a rectangle.
#[test]
fn hexa_cantilever_tip_deflection_within_three_percent() {
    let (e, nu, p, l): (f64, f64, f64, f64) = (1000.0, 0.3, 1.0, 10.0);
    let id = |i: usize, j: usize, k: usize| 4 * i + j + 2 * k;
    let mut xyz = vec![[0.0; 3]; 44];
    for i in 0..=10 {
        for k in 0..2 {
            for j in 0..2 {
                xyz[id(i, j, k)] = [i as f64, j as f64, k as f64];
            }
        }
    }
    let elements = (0..10)
        .map(|i| whole(SolidKind::Hexa8, cell(&id, i, 0, 0).to_vec()))
        .collect();
    let k = assemble(&(xyz, elements), Isotropic { e, nu });
    let free: Vec<usize> = (12..3 * 44).collect();
    let kff = Mat::from_fn(free.len(), free.len(), |i, j| k[(free[i], free[j])]);
    let mut f = Mat::<f64>::zeros(free.len(), 1);
    for n in 40..44 {
        f[(3 * n + 2 - 12, 0)] = p / 4.0;
    }
    kff.llt(Side::Lower).unwrap().solve_in_place(f.as_mut());
    let tip = (40..44).map(|n| f[(3 * n + 2 - 12, 0)]).sum::<f64>() / 4.0;
    let (inertia, g) = (1.0 / 12.0, e / (2.0 * (1.0 + nu)));
    let kappa = 10.0 * (1.0 + nu) / (12.0 + 11.0 * nu);
    let reference = p * l.powi(3) / (3.0 * e * inertia) + p * l / (kappa * g);
    let err = (tip - reference) / reference;
    assert!(
        err.abs() < 0.03,
        "tip {tip:.5} vs {reference:.5}: {:.2} %",
        100.0 * err
    );
}

// ---------------------------------------------------------------- (d) symmetry, definiteness

#[test]
fn matrices_are_symmetric_and_semi_definite() {
    for (kind, label, xyz) in samples() {
        let k = stiffness(kind, &xyz, STEEL).unwrap();
        let m = mass(kind, &xyz, 7.8, MassLumping::Consistent).unwrap();
        let l = mass(kind, &xyz, 7.8, MassLumping::Lumped).unwrap();
        for (name, a, definite) in [("K", &k, false), ("M", &m, true), ("M lumped", &l, true)] {
            let asym = max_abs(&(a - a.transpose()));
            assert!(
                asym <= 1e-14 * max_abs(a),
                "{kind} {label} {name}: asymmetry {asym:.2e}"
            );
            let ev = eigenvalues(a);
            let top = ev[ev.len() - 1];
            let floor = if definite { 1e-12 * top } else { -1e-12 * top };
            assert!(
                ev[0] > floor,
                "{kind} {label} {name}: smallest eigenvalue {:.3e} (largest {top:.3e})",
                ev[0]
            );
        }
    }
}

// ---------------------------------------------------------------- (e) mass

/// Volume by the divergence theorem, V = ⅓ ∮ x · n dA over the element faces (independent of the
/// element's volume quadrature): quadrilateral faces bilinear, triangular faces 6-node quadratic
/// (corner, corner, corner, mid 0–1, mid 1–2, mid 2–0), each oriented outward.
/// A straight-edged CHEXA 20 / CPENTA 15 has the volume of its corners' linear element.
fn surface_volume(kind: SolidKind, x: &[[f64; 3]]) -> f64 {
    match kind {
        SolidKind::Hexa20 => return surface_volume(SolidKind::Hexa8, &x[..8]),
        SolidKind::Penta15 => return surface_volume(SolidKind::Penta6, &x[..6]),
        _ => {}
    }
    let mid =
        |a: usize, b: usize| -> [f64; 3] { std::array::from_fn(|k| 0.5 * (x[a][k] + x[b][k])) };
    let (quads, tris): (Vec<[usize; 4]>, Vec<[[f64; 3]; 6]>) = match kind {
        SolidKind::Hexa8 => (
            vec![
                [0, 3, 2, 1],
                [4, 5, 6, 7],
                [0, 1, 5, 4],
                [1, 2, 6, 5],
                [2, 3, 7, 6],
                [3, 0, 4, 7],
            ],
            vec![],
        ),
        SolidKind::Penta6 => (
            vec![[0, 1, 4, 3], [1, 2, 5, 4], [2, 0, 3, 5]],
            vec![
                [x[0], x[2], x[1], mid(0, 2), mid(2, 1), mid(1, 0)],
                [x[3], x[4], x[5], mid(3, 4), mid(4, 5), mid(5, 3)],
            ],
        ),
        SolidKind::Pyram5 => (
            vec![[0, 3, 2, 1]],
            [[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]]
                .iter()
                .map(|&[a, b, c]| [x[a], x[b], x[c], mid(a, b), mid(b, c), mid(c, a)])
                .collect(),
        ),
        SolidKind::Tetra4 => (
            vec![],
            [[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]]
                .iter()
                .map(|&[a, b, c]| [x[a], x[b], x[c], mid(a, b), mid(b, c), mid(c, a)])
                .collect(),
        ),
        SolidKind::Tetra10 => (
            vec![],
            [
                [0, 2, 1, 6, 5, 4],
                [0, 1, 3, 4, 8, 7],
                [1, 2, 3, 5, 9, 8],
                [0, 3, 2, 7, 9, 6],
            ]
            .iter()
            .map(|f| f.map(|i| x[i]))
            .collect(),
        ),
        SolidKind::Hexa20 | SolidKind::Penta15 => unreachable!("reduced to the corners above"),
    };
    let gauss = [
        (0.5 - 0.5 * 0.6_f64.sqrt(), 5.0 / 18.0),
        (0.5, 8.0 / 18.0),
        (0.5 + 0.5 * 0.6_f64.sqrt(), 5.0 / 18.0),
    ];
    let comb = |w: &[f64], pts: &[[f64; 3]]| -> [f64; 3] {
        std::array::from_fn(|k| w.iter().zip(pts).map(|(w, p)| w * p[k]).sum())
    };
    let mut v = 0.0;
    for &(s, ws) in &gauss {
        for &(t, wt) in &gauss {
            for q in &quads {
                let p: Vec<[f64; 3]> = q.iter().map(|&i| x[i]).collect();
                let pos = comb(
                    &[(1.0 - s) * (1.0 - t), s * (1.0 - t), s * t, (1.0 - s) * t],
                    &p,
                );
                let ds = comb(&[-(1.0 - t), 1.0 - t, t, -t], &p);
                let dt = comb(&[-(1.0 - s), -s, s, 1.0 - s], &p);
                v += ws * wt * triple(pos, ds, dt) / 3.0;
            }
            // collapsed triangle: (r, q) = (s, (1 − s) t), Jacobian (1 − s)
            let (r, q) = (s, (1.0 - s) * t);
            let l = [1.0 - r - q, r, q];
            let n = [
                l[0] * (2.0 * l[0] - 1.0),
                l[1] * (2.0 * l[1] - 1.0),
                l[2] * (2.0 * l[2] - 1.0),
                4.0 * l[0] * l[1],
                4.0 * l[1] * l[2],
                4.0 * l[2] * l[0],
            ];
            let dr = [
                1.0 - 4.0 * l[0],
                4.0 * l[1] - 1.0,
                0.0,
                4.0 * (l[0] - l[1]),
                4.0 * l[2],
                -4.0 * l[2],
            ];
            let dq = [
                1.0 - 4.0 * l[0],
                0.0,
                4.0 * l[2] - 1.0,
                -4.0 * l[1],
                4.0 * l[1],
                4.0 * (l[0] - l[2]),
            ];
            for tri in &tris {
                v += ws * wt * (1.0 - s) * triple(comb(&n, tri), comb(&dr, tri), comb(&dq, tri))
                    / 3.0;
            }
        }
    }
    v
}

#[test]
fn total_mass_is_rho_v_consistent_and_lumped() {
    let rho = 2.7;
    for (kind, label, xyz) in samples() {
        // curved quadratic elements: the element's own volume (the total mass check remains)
        let v = if label == "curved" && kind != SolidKind::Tetra10 {
            volume_and_centroid(kind, &xyz).unwrap().0
        } else {
            surface_volume(kind, &xyz)
        };
        if label == "regular" {
            let exact = match kind {
                SolidKind::Hexa8 | SolidKind::Hexa20 => 1.0,
                SolidKind::Penta6 | SolidKind::Penta15 => 0.5,
                SolidKind::Pyram5 => 1.0 / 3.0,
                _ => 1.0 / 6.0,
            };
            assert!((v - exact).abs() < 1e-14, "{kind}: surface volume {v}");
        }
        for lumping in [MassLumping::Consistent, MassLumping::Lumped] {
            let m = mass(kind, &xyz, rho, lumping).unwrap();
            for c in 0..3 {
                let total: f64 = (0..kind.nodes())
                    .flat_map(|a| (0..kind.nodes()).map(move |b| (a, b)))
                    .map(|(a, b)| m[(3 * a + c, 3 * b + c)])
                    .sum();
                assert!(
                    (total - rho * v).abs() < 1e-13 * rho * v,
                    "{kind} {label} {lumping:?}: {total} vs ρV = {}",
                    rho * v
                );
            }
            if lumping == MassLumping::Lumped {
                assert!(
                    max_abs(
                        &(&m - Mat::from_fn(m.nrows(), m.ncols(), |i, j| if i == j {
                            m[(i, i)]
                        } else {
                            0.0
                        }))
                    ) == 0.0
                );
            }
        }
    }
}

#[test]
fn tet10_hrz_lumping_gives_the_textbook_fractions() {
    let m = mass(
        SolidKind::Tetra10,
        &tet10(&unit_tet(), 0.0),
        6.0,
        MassLumping::Lumped,
    )
    .unwrap();
    // ρV = 1: corners 1/36, mid-edge grids 4/27
    for a in 0..10 {
        let expected = if a < 4 { 1.0 / 36.0 } else { 4.0 / 27.0 };
        assert!((m[(3 * a, 3 * a)] - expected).abs() < 1e-14);
    }
}

// ---------------------------------------------------------------- (f) affine parts

fn relative_difference(a: &Mat<f64>, b: &Mat<f64>) -> f64 {
    max_abs(&(a - b)) / max_abs(b)
}

#[test]
fn affine_parts_reproduce_the_matrices() {
    let at = |e: f64, nu: f64, rho: f64| CoefficientValues {
        e,
        nu,
        rho,
        ..Default::default()
    };
    for (kind, label, xyz) in samples() {
        let k = stiffness(kind, &xyz, STEEL).unwrap();
        let parts = affine_stiffness(
            kind,
            &xyz,
            StiffnessParametrization::YoungsModulus { nu: 0.3 },
        )
        .unwrap();
        assert!(
            relative_difference(&parts.evaluate(&at(210.0, 0.3, 0.0)), &k) < 1e-12,
            "{kind} {label} E"
        );
        let fixed = affine_stiffness(kind, &xyz, StiffnessParametrization::Fixed(STEEL)).unwrap();
        assert!(
            relative_difference(&fixed.evaluate(&at(1.0, 0.1, 0.0)), &k) < 1e-15,
            "{kind} {label} fixed"
        );
        match affine_stiffness(kind, &xyz, StiffnessParametrization::Lame) {
            Ok(parts) => {
                assert_ne!(kind, SolidKind::Hexa8);
                for (e, nu) in [(210.0, 0.3), (70.0, 0.33), (1.0, 0.49), (5.0, -0.2)] {
                    let k = stiffness(kind, &xyz, Isotropic { e, nu }).unwrap();
                    assert!(
                        relative_difference(&parts.evaluate(&at(e, nu, 0.0)), &k) < 1e-12,
                        "{kind} {label} λ, μ"
                    );
                }
            }
            Err(err) => {
                assert_eq!(kind, SolidKind::Hexa8);
                assert_eq!(err, SolidError::NuNotAffineForIncompatibleHexa);
                assert!(
                    err.to_string()
                        .starts_with("ν cannot be a parameter of CHEXA with incompatible modes")
                );
            }
        }
        for lumping in [MassLumping::Consistent, MassLumping::Lumped] {
            let m = mass(kind, &xyz, 7.8, lumping).unwrap();
            let parts = affine_mass(kind, &xyz, lumping, MassParametrization::Density).unwrap();
            assert!(
                relative_difference(&parts.evaluate(&at(0.0, 0.0, 7.8)), &m) < 1e-14,
                "{kind} {label} ρ"
            );
            let fixed =
                affine_mass(kind, &xyz, lumping, MassParametrization::Fixed { rho: 7.8 }).unwrap();
            assert!(relative_difference(&fixed.evaluate(&at(0.0, 0.0, 1.0)), &m) < 1e-15);
        }
    }
}

// ---------------------------------------------------------------- geometry and input errors

#[test]
fn inverted_and_degenerate_elements_are_errors_naming_the_point() {
    // mirrored CHEXA: top and bottom faces swapped
    let mut inverted = unit_hexa();
    inverted.rotate_left(4);
    let err = stiffness(SolidKind::Hexa8, &inverted, STEEL).unwrap_err();
    assert!(
        matches!(
            err,
            SolidError::NonPositiveJacobian {
                at: EvalPoint::Integration { index: 0, of: 8 },
                ..
            }
        ),
        "{err:?}"
    );
    assert!(
        err.to_string().contains("integration point 1 of 8"),
        "{err}"
    );
    // flat CTETRA: all grids in z = 0
    let flat = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [1.0, 1.0, 0.0],
    ];
    for result in [
        stiffness(SolidKind::Tetra4, &flat, STEEL).map(|_| ()),
        mass(SolidKind::Tetra4, &flat, 1.0, MassLumping::Consistent).map(|_| ()),
        strain_at_centroid(SolidKind::Tetra4, &flat, &[0.0; 12]).map(|_| ()),
    ] {
        assert!(matches!(
            result,
            Err(SolidError::NonPositiveJacobian { .. })
        ));
    }
    // CHEXA whose corner folds through: valid centre, negative det J at one Gauss point
    let mut folded = unit_hexa();
    folded[6] = [0.2, 0.2, 0.2];
    let err = stiffness(SolidKind::Hexa8, &folded, STEEL).unwrap_err();
    assert!(
        matches!(
            err,
            SolidError::NonPositiveJacobian {
                at: EvalPoint::Integration { .. },
                ..
            }
        ),
        "{err:?}"
    );
    // NaN coordinates are errors, not panics
    let mut nan = unit_penta();
    nan[3][2] = f64::NAN;
    assert!(stiffness(SolidKind::Penta6, &nan, STEEL).is_err());
    // wrong counts
    assert_eq!(
        stiffness(SolidKind::Tetra10, &unit_tet(), STEEL).unwrap_err(),
        SolidError::NodeCount {
            kind: SolidKind::Tetra10,
            expected: 10,
            got: 4
        }
    );
    assert!(matches!(
        strain_at_centroid(SolidKind::Tetra4, &unit_tet(), &[0.0; 24]),
        Err(SolidError::DisplacementLength {
            expected: 12,
            got: 24,
            ..
        })
    ));
    // a material the incompatible-mode condensation cannot handle
    assert!(matches!(
        stiffness(
            SolidKind::Hexa8,
            &unit_hexa(),
            Isotropic { e: -1.0, nu: 0.3 }
        ),
        Err(SolidError::CondensationFailed { .. })
    ));
}

// ---------------------------------------------------------------- quadratic solids

#[test]
fn quadratic_meshes_have_six_zero_energy_modes_and_pass_the_curved_patch_test() {
    // curved interior edges and some blank mid-sides (every third edge, shared by all its
    // elements): an isoparametric element represents a linear field whatever its edges, and
    // the transition elements stay conforming
    for kind in [SolidKind::Hexa20, SolidKind::Penta15] {
        for (label, blank) in [
            ("all mid-sides", &(|_| false) as &dyn Fn(usize) -> bool),
            ("every third mid-side blank", &|k| k % 3 == 0),
        ] {
            let mesh = quadratic_lattice(kind, 2, 0.2, 0.15, blank);
            let (du, de) = patch_test(&mesh);
            assert!(
                du < 1e-10 && de < 1e-10,
                "{kind} {label}: displacement {du:.2e}, strain {de:.2e}"
            );
            assert_eq!(zero_modes(&assemble(&mesh, STEEL)), 6, "{kind} {label}");
        }
    }
}

/// The trilinear (8-node, no incompatible modes) hexahedron under 3×3×3 Gauss, written out here.
fn trilinear_hexa(xyz: &[[f64; 3]], mat: Isotropic) -> Mat<f64> {
    let Lame { lambda, mu } = mat.lame();
    let mut k = Mat::<f64>::zeros(24, 24);
    for q in shape::hexa_rule(shape::Gauss::Three) {
        let s = shape::shape(SolidKind::Hexa8, q.xi);
        let j = Mat::from_fn(3, 3, |r, c| {
            (0..8).map(|a| xyz[a][r] * s.dn[a][c]).sum::<f64>()
        });
        let det = j.determinant();
        let mut jinv = Mat::<f64>::identity(3, 3);
        j.partial_piv_lu().solve_in_place(jinv.as_mut());
        // ∇N_a = J⁻ᵀ ∇_ξ N_a
        let g: Vec<[f64; 3]> = (0..8)
            .map(|a| std::array::from_fn(|i| (0..3).map(|c| jinv[(c, i)] * s.dn[a][c]).sum()))
            .collect();
        for a in 0..8 {
            for b in 0..8 {
                let dot: f64 = (0..3).map(|i| g[a][i] * g[b][i]).sum();
                for i in 0..3 {
                    for jj in 0..3 {
                        let diag = if i == jj { dot } else { 0.0 };
                        k[(3 * a + i, 3 * b + jj)] += q.w
                            * det
                            * (lambda * g[a][i] * g[b][jj] + mu * (g[a][jj] * g[b][i] + diag));
                    }
                }
            }
        }
    }
    k
}

#[test]
fn quadratic_solids_with_every_midside_blank_are_the_linear_elements() {
    // CHEXA 20 without mid-sides: the trilinear element (same 3×3×3 rule)
    let corners = distorted_hexa();
    let hexa = Midsides::new(SolidKind::Hexa20, &[false; 20]);
    let k = element_stiffness(&hexa, &corners, STEEL);
    let reference = trilinear_hexa(&corners, STEEL);
    assert!(relative_difference(&k, &reference) < 1e-13);
    // … and stiffer than nothing: the CHEXA 8 with incompatible modes is softer
    let wilson = stiffness(SolidKind::Hexa8, &corners, STEEL).unwrap();
    assert!(relative_difference(&k, &wilson) > 1e-3);
    // CTETRA 10 without mid-sides: the constant-strain CTETRA 4; with one mid-side blank on a
    // curved element, still exactly six zero-energy modes
    let tetra = Midsides::new(SolidKind::Tetra10, &[false; 10]);
    let k = element_stiffness(&tetra, &distorted_tet(), STEEL);
    let reference = stiffness(SolidKind::Tetra4, &distorted_tet(), STEEL).unwrap();
    assert!(relative_difference(&k, &reference) < 1e-13);
    let mut present = [true; 10];
    present[5] = false;
    let curved: Vec<[f64; 3]> = (tet10(&distorted_tet(), 0.05).into_iter().enumerate())
        .filter(|&(a, _)| present[a])
        .map(|(_, x)| x)
        .collect();
    let one_blank = Midsides::new(SolidKind::Tetra10, &present);
    assert_eq!(
        zero_modes(&element_stiffness(&one_blank, &curved, STEEL)),
        6
    );
    // CPENTA 15 without mid-sides on a right prism: the CPENTA 6 (both rules exact there)
    let penta = Midsides::new(SolidKind::Penta15, &[false; 15]);
    let k = element_stiffness(&penta, &unit_penta(), STEEL);
    let reference = stiffness(SolidKind::Penta6, &unit_penta(), STEEL).unwrap();
    assert!(relative_difference(&k, &reference) < 1e-13);
    let m = penta
        .affine_mass(
            &unit_penta(),
            MassLumping::Consistent,
            MassParametrization::Fixed { rho: 2.0 },
        )
        .unwrap()
        .evaluate(&CoefficientValues::default());
    let reference = mass(
        SolidKind::Penta6,
        &unit_penta(),
        2.0,
        MassLumping::Consistent,
    )
    .unwrap();
    assert!(relative_difference(&m, &reference) < 1e-13);
}

/// A cantilever 4 × 1 × 1 clamped at x = 0 (ν = 0, so the clamp does not restrain a Poisson
/// contraction) under a tip moment M (σxx = M z / I on the tip face): the exact solution
/// u = κ x z, w = −κ x²/2 (κ = M/EI) is quadratic, so the quadratic elements reproduce it to
/// round-off on a coarse mesh (one element through the depth); the linear CPENTA 6 does not
/// (checked as the contrast, so the test can fail).
#[test]
fn quadratic_cantilever_under_a_tip_moment_is_exact() {
    let (e, moment, l) = (1000.0, 2.0, 4.0);
    let inertia = 1.0 / 12.0;
    let kappa = moment / (e * inertia);
    let mat = Isotropic { e, nu: 0.0 };
    let tip_error = |kind: SolidKind| {
        let (mut xyz, mut elements) = (Vec::new(), Vec::new());
        // four copies of a one-cell lattice along x
        let (lx, lattice_elements) = quadratic_lattice(kind, 1, 0.0, 0.0, &|_| false);
        for i in 0..4 {
            let offset = xyz.len();
            xyz.extend(lx.iter().map(|p| [p[0] + i as f64, p[1], p[2] - 0.5]));
            elements.extend(
                lattice_elements
                    .iter()
                    .map(|(m, n)| (m.clone(), n.iter().map(|&a| a + offset).collect::<Vec<_>>())),
            );
        }
        // merge the coincident grids of neighbouring cells
        let mut canonical: Vec<usize> = (0..xyz.len()).collect();
        for a in 0..xyz.len() {
            if let Some(b) = (0..a).find(|&b| (0..3).all(|k| (xyz[a][k] - xyz[b][k]).abs() < 1e-12))
            {
                canonical[a] = canonical[b];
            }
        }
        for (_, nodes) in elements.iter_mut() {
            nodes.iter_mut().for_each(|a| *a = canonical[*a]);
        }
        let k = assemble(&(xyz.clone(), elements), mat);
        let fixed = |a: usize| xyz[a][0].abs() < 1e-12 || canonical[a] != a;
        let free: Vec<usize> = (0..xyz.len())
            .filter(|&a| !fixed(a))
            .flat_map(|a| 3 * a..3 * a + 3)
            .collect();
        // tip loads: the x-components of K u_exact at the tip grids, which are the consistent
        // loads ∫ N_a σxx dA of σxx = E κ z when the element space holds u_exact; every other
        // residual of K u_exact is dropped, so the solve returns u_exact only if it does
        let exact: Vec<f64> = xyz
            .iter()
            .flat_map(|p| [kappa * p[0] * p[2], 0.0, -0.5 * kappa * p[0] * p[0]])
            .collect();
        let tip = |a: usize| (xyz[a][0] - l).abs() < 1e-12 && canonical[a] == a;
        let mut f = Mat::<f64>::zeros(free.len(), 1);
        for (r, &d) in free.iter().enumerate() {
            if tip(d / 3) && d % 3 == 0 {
                f[(r, 0)] = (0..exact.len()).map(|c| k[(d, c)] * exact[c]).sum::<f64>();
            }
        }
        let kff = Mat::from_fn(free.len(), free.len(), |i, j| k[(free[i], free[j])]);
        kff.llt(Side::Lower).unwrap().solve_in_place(f.as_mut());
        let mut err = 0.0_f64;
        for (r, &d) in free.iter().enumerate() {
            err = err.max((f[(r, 0)] - exact[d]).abs());
        }
        err / (0.5 * kappa * l * l)
    };
    for kind in [SolidKind::Hexa20, SolidKind::Penta15] {
        let err = tip_error(kind);
        assert!(err < 1e-10, "{kind}: max |u − u_exact| / w_tip = {err:.2e}");
    }
    let err = tip_error(SolidKind::Penta6);
    assert!(err > 1e-2, "CPENTA 6 would lock: {err:.2e}");
}
