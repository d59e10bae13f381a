//! Pressure loads (`PLOAD4`, `PLOAD2`, `PLOAD`) through SOL 101, against exact and analytic
//! solutions.

mod common;
use common::run_deck;

fn displacement(deck: &str) -> Vec<f64> {
    let (r, dir) = run_deck(deck);
    r.unwrap_or_else(|e| panic!("run: {e}"));
    hdf5_metno::File::open(dir.path().join("out.h5"))
        .expect("open")
        .dataset("results/1/statics/displacement")
        .expect("u")
        .read_raw()
        .expect("read")
}

const E: f64 = 1000.0;
const NU: f64 = 0.3;
const P: f64 = 7.0;
const H: f64 = 2.0;

/// A unit-square column of height H in two layers of cells, grid (i, j, k) at (i, j, k·H/2).
fn column_grids() -> (String, impl Fn(usize, usize, usize) -> u32) {
    let id = |i: usize, j: usize, k: usize| (1 + i + 2 * j + 4 * k) as u32;
    let mut s = String::new();
    for k in 0..3 {
        for j in 0..2 {
            for i in 0..2 {
                s += &format!("GRID,{},,{i}.,{j}.,{:?}\n", id(i, j, k), k as f64 * H / 2.0);
            }
        }
    }
    // the base slides freely on z = 0; three components fix the rigid in-plane motion
    s += &format!(
        "SPC1,1,3,{},{},{},{}\nSPC1,1,12,{}\nSPC1,1,2,{}\n",
        id(0, 0, 0),
        id(1, 0, 0),
        id(1, 1, 0),
        id(0, 1, 0),
        id(0, 0, 0),
        id(1, 0, 0)
    );
    (s, id)
}

fn column_deck(elements: &str, mid_grids: &str) -> String {
    let (grids, _) = column_grids();
    format!(
        "SOL 101\nCEND\nSPC = 1\nLOAD = 5\nDISPLACEMENT = ALL\nBEGIN BULK\nMAT1,1,{E:?},,{NU:?}\nPSOLID,1,1\n{grids}{mid_grids}{elements}ENDDATA\n"
    )
}

/// Uniform compression: a pressure P on the top of a free-sliding column gives the uniform stress
/// σ_zz = −P, so the top moves by −P H / E and sideways by ν P x / E — a state every linear and
/// quadratic solid element reproduces exactly (patch test), so any error in the face's forces
/// (share, sign, orientation, mid-side grids) shows at O(1). Bound 1e-10 of P H / E: round-off.
fn assert_uniform_compression(u: &[f64], top: &[usize], label: &str) {
    let w = -P * H / E;
    let scale = P * H / E;
    for &g in top {
        let err = (u[6 * g + 2] - w).abs();
        assert!(
            err <= 1e-10 * scale,
            "{label}: top grid {g}: w = {:e}, expected {w:e}",
            u[6 * g + 2]
        );
    }
}

#[test]
fn pload4_on_solid_faces_compresses_the_column_exactly() {
    let (_, id) = column_grids();
    let corner = |c: usize, k: usize| -> u32 {
        let (i, j) = [(0, 0), (1, 0), (1, 1), (0, 1)][c];
        id(i, j, k)
    };
    // grid indices (sorted by id) of the top layer: ids 9..12
    let top: Vec<usize> = (8..12).collect();

    // CHEXA: two cells, the top face picked by G1 and its diagonal G3
    let mut hexa = String::new();
    for k in 0..2 {
        let g: Vec<u32> = (0..4)
            .map(|c| corner(c, k))
            .chain((0..4).map(|c| corner(c, k + 1)))
            .collect();
        hexa += &format!(
            "CHEXA,{},1,{},{},{},{},{},{},\n,{},{}\n",
            1 + k,
            g[0],
            g[1],
            g[2],
            g[3],
            g[4],
            g[5],
            g[6],
            g[7]
        );
    }
    hexa += &format!("PLOAD4,5,2,{P:?},,,,{},{}\n", corner(1, 2), corner(3, 2));
    assert_uniform_compression(&displacement(&column_deck(&hexa, "")), &top, "CHEXA");

    // CPENTA: each cell split into two prisms; the top triangles picked by G1 alone
    let mut penta = String::new();
    for k in 0..2 {
        for (n, tri) in [[0, 1, 2], [0, 2, 3]].iter().enumerate() {
            let eid = 1 + 2 * k + n;
            let g: Vec<u32> = tri
                .iter()
                .map(|&c| corner(c, k))
                .chain(tri.iter().map(|&c| corner(c, k + 1)))
                .collect();
            penta += &format!(
                "CPENTA,{eid},1,{},{},{},{},{},{}\n",
                g[0], g[1], g[2], g[3], g[4], g[5]
            );
            if k == 1 {
                penta += &format!("PLOAD4,5,{eid},{P:?},,,,{}\n", g[4]);
            }
        }
    }
    assert_uniform_compression(&displacement(&column_deck(&penta, "")), &top, "CPENTA");

    // CTETRA 4 and 10: each cell in six tetrahedra around its main diagonal (conforming
    // between cells); a face on the top picked by G1 on it and G4 off it
    let kuhn = [
        [0, 1, 2, 6],
        [0, 2, 3, 6],
        [0, 3, 7, 6],
        [0, 7, 4, 6],
        [0, 4, 5, 6],
        [0, 5, 1, 6],
    ];
    let cell = |k: usize, v: usize| {
        if v < 4 {
            corner(v, k)
        } else {
            corner(v - 4, k + 1)
        }
    };
    let xyz = |g: u32| {
        let n = (g - 1) as usize;
        [
            (n % 2) as f64,
            ((n / 2) % 2) as f64,
            (n / 4) as f64 * H / 2.0,
        ]
    };
    for quadratic in [false, true] {
        let (mut tets, mut mids, mut next_mid) = (String::new(), String::new(), 1000u32);
        let mut mid_of = std::collections::HashMap::new();
        for k in 0..2 {
            for (n, t) in kuhn.iter().enumerate() {
                let eid = 1 + 6 * k + n;
                let mut g: Vec<u32> = t.iter().map(|&v| cell(k, v)).collect();
                let d =
                    |a: u32, b: u32| -> [f64; 3] { std::array::from_fn(|i| xyz(b)[i] - xyz(a)[i]) };
                let (a, b, c) = (d(g[0], g[1]), d(g[0], g[2]), d(g[0], g[3]));
                let volume = a[0] * (b[1] * c[2] - b[2] * c[1])
                    - a[1] * (b[0] * c[2] - b[2] * c[0])
                    + a[2] * (b[0] * c[1] - b[1] * c[0]);
                if volume < 0.0 {
                    g.swap(1, 2);
                }
                let mut line = format!("CTETRA,{eid},1,{},{},{},{}", g[0], g[1], g[2], g[3]);
                if quadratic {
                    let mut extra = Vec::new();
                    for (p, q) in [(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)] {
                        let key = (g[p].min(g[q]), g[p].max(g[q]));
                        let m = *mid_of.entry(key).or_insert_with(|| {
                            next_mid += 1;
                            let (x, y) = (xyz(key.0), xyz(key.1));
                            mids += &format!(
                                "GRID,{next_mid},,{:?},{:?},{:?}\n",
                                0.5 * (x[0] + y[0]),
                                0.5 * (x[1] + y[1]),
                                0.5 * (x[2] + y[2])
                            );
                            if x[2] + y[2] == 0.0 {
                                mids += &format!("SPC1,1,3,{next_mid}\n");
                            }
                            next_mid
                        });
                        extra.push(m);
                    }
                    line += &format!(
                        ",{},{},\n,{},{},{},{}",
                        extra[0], extra[1], extra[2], extra[3], extra[4], extra[5]
                    );
                }
                tets += &line;
                tets += "\n";
                let on_top: Vec<u32> = g.iter().copied().filter(|&x| xyz(x)[2] == H).collect();
                if on_top.len() == 3 {
                    let off = g
                        .iter()
                        .copied()
                        .find(|x| !on_top.contains(x))
                        .expect("fourth corner");
                    tets += &format!("PLOAD4,5,{eid},{P:?},,,,{},{off}\n", on_top[0]);
                }
            }
        }
        let label = if quadratic { "CTETRA 10" } else { "CTETRA 4" };
        assert_uniform_compression(&displacement(&column_deck(&tets, &mids)), &top, label);
    }

    // CHEXA 20 and CPENTA 15: the same cells with mid-side grids (shared, base ones sliding on
    // z = 0); the PLOAD4 then loads the 8-node quadrilateral and 6-node triangular top faces
    type Mids = (std::collections::HashMap<(u32, u32), u32>, String);
    let quadratic_card =
        |state: &mut Mids, card: &str, eid: usize, g: &[u32], edges: &[(usize, usize)]| {
            let (mid_of, mids) = state;
            let mut all: Vec<u32> = g.to_vec();
            for &(p, q) in edges {
                let key = (g[p].min(g[q]), g[p].max(g[q]));
                let next = 2000 + mid_of.len() as u32;
                let m = *mid_of.entry(key).or_insert_with(|| {
                    let (x, y) = (xyz(key.0), xyz(key.1));
                    *mids += &format!(
                        "GRID,{next},,{:?},{:?},{:?}\n",
                        0.5 * (x[0] + y[0]),
                        0.5 * (x[1] + y[1]),
                        0.5 * (x[2] + y[2])
                    );
                    if x[2] + y[2] == 0.0 {
                        *mids += &format!("SPC1,1,3,{next}\n");
                    }
                    next
                });
                all.push(m);
            }
            let ids: Vec<String> = all.iter().map(u32::to_string).collect();
            let mut line = format!("{card},{eid},1,{}", ids[..6].join(","));
            for chunk in ids[6..].chunks(8) {
                line += &format!("\n,{}", chunk.join(","));
            }
            line + "\n"
        };
    let hexa_edges = [
        (0, 1),
        (1, 2),
        (2, 3),
        (3, 0),
        (0, 4),
        (1, 5),
        (2, 6),
        (3, 7),
        (4, 5),
        (5, 6),
        (6, 7),
        (7, 4),
    ];
    let mut state = Mids::default();
    let mut hexa20 = String::new();
    for k in 0..2 {
        let g: Vec<u32> = (0..4)
            .map(|c| corner(c, k))
            .chain((0..4).map(|c| corner(c, k + 1)))
            .collect();
        hexa20 += &quadratic_card(&mut state, "CHEXA", 1 + k, &g, &hexa_edges);
    }
    hexa20 += &format!("PLOAD4,5,2,{P:?},,,,{},{}\n", corner(1, 2), corner(3, 2));
    let deck = column_deck(&hexa20, &state.1);
    assert_uniform_compression(&displacement(&deck), &top, "CHEXA 20");
    let penta_edges = [
        (0, 1),
        (1, 2),
        (2, 0),
        (0, 3),
        (1, 4),
        (2, 5),
        (3, 4),
        (4, 5),
        (5, 3),
    ];
    let mut state = Mids::default();
    let mut penta15 = String::new();
    for k in 0..2 {
        for (n, tri) in [[0, 1, 2], [0, 2, 3]].iter().enumerate() {
            let eid = 1 + 2 * k + n;
            let g: Vec<u32> = tri
                .iter()
                .map(|&c| corner(c, k))
                .chain(tri.iter().map(|&c| corner(c, k + 1)))
                .collect();
            penta15 += &quadratic_card(&mut state, "CPENTA", eid, &g, &penta_edges);
            if k == 1 {
                penta15 += &format!("PLOAD4,5,{eid},{P:?},,,,{}\n", g[4]);
            }
        }
    }
    let deck = column_deck(&penta15, &state.1);
    assert_uniform_compression(&displacement(&deck), &top, "CPENTA 15");
}

/// Navier's series for the centre deflection of a simply supported a × a Kirchhoff plate under
/// a uniform pressure q (Timoshenko & Woinowsky-Krieger §30): w = 16 q / (π⁶ D) Σ_{m,n odd}
/// (−1)^((m+n)/2 − 1) / (m n (m² + n²)² / a⁴); 200 terms per index leave < 1e-9 relative.
fn navier_centre(q: f64, a: f64, d: f64) -> f64 {
    let mut sum = 0.0;
    for m in (1..400).step_by(2) {
        for n in (1..400).step_by(2) {
            let sign = if ((m + n) / 2 - 1) % 2 == 0 {
                1.0
            } else {
                -1.0
            };
            let (m, n) = (m as f64, n as f64);
            sum += sign / (m * n * ((m * m + n * n) / (a * a)).powi(2));
        }
    }
    16.0 * q / (std::f64::consts::PI.powi(6) * d) * sum
}

/// A hard simply supported square plate (w and the rotation about the edge normal held) of
/// CQUAD4 under a uniform pressure given four ways — one PLOAD4 per element, a PLOAD4 THRU
/// range, a PLOAD2 list and PLOAD by grids — gives the same displacements (1e-12 of the largest:
/// the same nodal forces summed in another order), and the centre deflection converges to
/// Navier's: thin plate (a/t = 100, Reissner–Mindlin shear adds ~(t/a)² ~ 1e-4), error below
/// 1.5 % at 8 × 8 and shrinking at least 3× to 16 × 16 (MITC4 converges at O(h²) in deflection).
#[test]
fn pressure_on_a_simply_supported_plate_converges_to_navier() {
    let (a, t, e, nu, q): (f64, f64, f64, f64, f64) = (1.0, 0.01, 2.0e11, 0.3, 1000.0);
    let d = e * t.powi(3) / (12.0 * (1.0 - nu * nu));
    let reference = navier_centre(q, a, d);
    let mut errors = Vec::new();
    for nx in [8usize, 16] {
        let (mesh, _) = common::plate_mesh(nx, nx, a, a);
        let id = |i: usize, j: usize| 1 + i + (nx + 1) * j;
        let mut edges = String::new();
        for k in 0..=nx {
            for (g, c) in [
                (id(0, k), "34"),
                (id(nx, k), "34"),
                (id(k, 0), "35"),
                (id(k, nx), "35"),
            ] {
                edges += &format!("SPC1,1,{c},{g}\n");
            }
        }
        edges += &format!("SPC1,1,12,{}\nSPC1,1,2,{}\n", id(0, 0), id(nx, 0));
        let n_el = nx * nx;
        let loads = [
            (1..=n_el)
                .map(|e| format!("PLOAD4,5,{e},{q:?}\n"))
                .collect::<String>(),
            format!("PLOAD4,5,1,{q:?},,,,THRU,{n_el}\n"),
            (1..=n_el)
                .collect::<Vec<_>>()
                .chunks(6)
                .map(|c| {
                    format!(
                        "PLOAD2,5,{q:?},{}\n",
                        c.iter()
                            .map(|e| e.to_string())
                            .collect::<Vec<_>>()
                            .join(",")
                    )
                })
                .collect(),
            (0..nx)
                .flat_map(|j| (0..nx).map(move |i| (i, j)))
                .map(|(i, j)| {
                    format!(
                        "PLOAD,5,{q:?},{},{},{},{}\n",
                        id(i, j),
                        id(i + 1, j),
                        id(i + 1, j + 1),
                        id(i, j + 1)
                    )
                })
                .collect(),
        ];
        let runs: Vec<Vec<f64>> = loads
            .iter()
            .map(|load| {
                displacement(&format!(
                    "SOL 101\nCEND\nSPC = 1\nLOAD = 5\nDISPLACEMENT = ALL\nBEGIN BULK\nMAT1,1,{e:?},,{nu:?}\nPSHELL,1,1,{t:?},1,,1\n{mesh}{edges}{load}ENDDATA\n"
                ))
            })
            .collect();
        let largest = runs[0].iter().fold(0.0f64, |m, v| m.max(v.abs()));
        for (k, u) in runs.iter().enumerate().skip(1) {
            let diff = u
                .iter()
                .zip(&runs[0])
                .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
            assert!(
                diff <= 1e-12 * largest,
                "{nx}×{nx}: load form {k} differs by {diff:e}"
            );
        }
        let centre = (id(nx / 2, nx / 2) - 1) * 6 + 2;
        errors.push((runs[0][centre] - reference) / reference);
    }
    assert!(
        errors[0].abs() < 0.015,
        "8×8 centre deflection error {:.3e}",
        errors[0]
    );
    assert!(
        errors[1].abs() * 3.0 < errors[0].abs(),
        "no convergence to Navier: errors {errors:?}"
    );
}
