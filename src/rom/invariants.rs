//! The nine mass invariants of a floating-frame body (thesis appendix A, eq. A.11–A.19) from
//! its nodal masses m_j, undeformed positions r_0,j and basis rows Ψ_j (the translations of grid
//! j in basic, 3 × n_r), and their affine components (eq. 4.8): every invariant is linear in the
//! m_j, so the invariants of component k use the nodal masses m_j^k of eq. 4.1 and the
//! invariants at p are Σ_k f_k(p) M̂^k ([`MassInvariants::combine`]).
//!
//! With ψ_k the k-th column of Ψ_j and ã the cross-product matrix of a (ã b = a × b):
//!
//! | | shape | definition |
//! |---|---|---|
//! | m | scalar | Σ m_j (eq. 4.2) |
//! | M̂₁ | 3 | Σ m_j r_0,j (A.11) |
//! | M̂₂ | 3 × n_r | Σ m_j Ψ_j (A.12) |
//! | M̂₃ | 3 × 3 | Σ m_j r̃_0,j r̃_0,j (A.13) |
//! | M̂₄ | n_r × 3 × 3 | \[l\] = Σ m_j r̃_0,j ψ̃_l (A.14), so M̂₄ q = Σ m_j r̃_0,j (Ψ_j q)~ |
//! | M̂₅ | n_r × n_r × 3 × 3 | \[k\]\[l\] = Σ m_j ψ̃_k ψ̃_l (A.15), so M̂₅ q q = Σ m_j (Ψ_j q)~ (Ψ_j q)~ |
//! | M̂₆ | 3 × n_r | column k = Σ m_j ψ̃_k r_0,j (A.16) = Σ m_j r̃_0,jᵀ ψ_k |
//! | M̂₇ | n_r × n_r × 3 | \[k\]\[l\] = Σ m_j ψ̃_k ψ_l (A.17), so D̂₃ = M̂₆ + M̂₇ q = Σ m_j r̃_jᵀ Ψ_j |
//! | M̂₈ | n_r | Σ m_j r_0,jᵀ Ψ_j (A.18) |
//! | M̂₉ | n_r × n_r | Σ m_j Ψ_jᵀ Ψ_j (A.19) |
//!
//! (r_j = r_0,j + Ψ_j q the deformed position.) The sums over grids are the nine products
//! W_ab = Σ_j m_j Ψ_j[a]ᵀ Ψ_j[b] (rows a, b of Ψ_j) and the three Z_ab = Σ_j m_j Ψ_j[a]ᵀ r_0,j[b],
//! from which ψ̃_k ψ̃_l = ψ_l ψ_kᵀ − (ψ_kᵀψ_l) I and r̃ ψ̃ = ψ rᵀ − (rᵀψ) I give M̂₄, M̂₅, M̂₇.

use faer::Mat;

/// The translation rows of a basis at every grid, in basic: `axes[a]` is n_g × n_r, row j the
/// basis row of grid j along basic axis a.
#[derive(Debug, Clone)]
pub struct TranslationRows {
    pub axes: [Mat<f64>; 3],
}

impl TranslationRows {
    /// From the basis columns expanded to every grid in basic (`columns[k]`: n_g × 6 values,
    /// T1 T2 T3 R1 R2 R3 of each grid).
    pub fn from_grid_columns(columns: &[Vec<f64>], n_grids: usize) -> Self {
        TranslationRows {
            axes: std::array::from_fn(|a| {
                Mat::from_fn(n_grids, columns.len(), |j, k| columns[k][6 * j + a])
            }),
        }
    }
}

/// The basis rows of a body's interface grids (the grids joints and forces attach to): grid
/// ids and, per grid, the 6 × n_r rows T1 T2 T3 R1 R2 R3 in basic, so a marker on the grid
/// moves by rows[0..3] q and turns by rows[3..6] q.
#[derive(Debug, Clone, PartialEq)]
pub struct InterfaceRows {
    pub grids: Vec<u32>,
    pub rows: Vec<Mat<f64>>,
}

impl InterfaceRows {
    /// The rows of the grids at `indices` (ids `grids`) from basis columns expanded to every
    /// grid in basic (as for [`TranslationRows::from_grid_columns`]).
    pub fn from_grid_columns(columns: &[Vec<f64>], grids: Vec<u32>, indices: &[usize]) -> Self {
        let rows = indices
            .iter()
            .map(|&g| Mat::from_fn(6, columns.len(), |c, k| columns[k][6 * g + c]))
            .collect();
        InterfaceRows { grids, rows }
    }
}

/// The mass invariants of one affine component (or of the body at one p); shapes in the
/// module doc, matrices row-major in `Vec`s of 3-arrays where the shape says 3.
#[derive(Debug, Clone, PartialEq)]
pub struct MassInvariants {
    pub mass: f64,
    pub m1: [f64; 3],
    /// 3 × n_r.
    pub m2: Mat<f64>,
    pub m3: [[f64; 3]; 3],
    /// n_r matrices 3 × 3.
    pub m4: Vec<[[f64; 3]; 3]>,
    /// n_r × n_r matrices 3 × 3, \[k\]\[l\] at k n_r + l.
    pub m5: Vec<[[f64; 3]; 3]>,
    /// 3 × n_r.
    pub m6: Mat<f64>,
    /// n_r × n_r vectors, \[k\]\[l\] at k n_r + l.
    pub m7: Vec<[f64; 3]>,
    /// n_r.
    pub m8: Vec<f64>,
    /// n_r × n_r.
    pub m9: Mat<f64>,
}

impl MassInvariants {
    /// The invariants of nodal masses `masses` (one per grid) at `positions` with basis rows
    /// `rows` (grids in the same order).
    pub fn new(masses: &[f64], positions: &[[f64; 3]], rows: &TranslationRows) -> Self {
        let n_r = rows.axes[0].ncols();
        let weighted: [Mat<f64>; 3] = std::array::from_fn(|a| {
            Mat::from_fn(n_r, masses.len(), |k, j| masses[j] * rows.axes[a][(j, k)])
        });
        // W_ab = Σ_j m_j Ψ_j[a]ᵀ Ψ_j[b] (n_r × n_r)
        let w: [[Mat<f64>; 3]; 3] =
            std::array::from_fn(|a| std::array::from_fn(|b| &weighted[a] * &rows.axes[b]));
        // Z_ab[k] = Σ_j m_j Ψ_j[a][k] r_0,j[b]
        let z: Vec<[[f64; 3]; 3]> = (0..n_r)
            .map(|k| {
                std::array::from_fn(|a| {
                    std::array::from_fn(|b| {
                        (0..masses.len())
                            .map(|j| weighted[a][(k, j)] * positions[j][b])
                            .sum()
                    })
                })
            })
            .collect();
        let mass: f64 = masses.iter().sum();
        let m1: [f64; 3] =
            std::array::from_fn(|b| masses.iter().zip(positions).map(|(m, r)| m * r[b]).sum());
        let m2 = Mat::from_fn(3, n_r, |a, k| {
            (0..masses.len()).map(|j| weighted[a][(k, j)]).sum()
        });
        let m3: [[f64; 3]; 3] = std::array::from_fn(|a| {
            std::array::from_fn(|b| {
                masses
                    .iter()
                    .zip(positions)
                    .map(|(m, r)| {
                        let rr: f64 = r.iter().map(|x| x * x).sum();
                        m * (r[a] * r[b] - if a == b { rr } else { 0.0 })
                    })
                    .sum()
            })
        });
        let m8: Vec<f64> = z.iter().map(|zk| (0..3).map(|a| zk[a][a]).sum()).collect();
        // r̃ ψ̃_l = ψ_l rᵀ − (rᵀψ_l) I
        let m4: Vec<[[f64; 3]; 3]> = z
            .iter()
            .zip(&m8)
            .map(|(zl, &trace)| {
                std::array::from_fn(|a| {
                    std::array::from_fn(|b| zl[a][b] - if a == b { trace } else { 0.0 })
                })
            })
            .collect();
        // column k = Σ m ψ_k × r
        let m6 = {
            let columns: Vec<[f64; 3]> = z
                .iter()
                .map(|zk| {
                    [
                        zk[1][2] - zk[2][1],
                        zk[2][0] - zk[0][2],
                        zk[0][1] - zk[1][0],
                    ]
                })
                .collect();
            Mat::from_fn(3, n_r, |a, k| columns[k][a])
        };
        let m9 = &w[0][0] + &w[1][1] + &w[2][2];
        let pairs = (0..n_r).flat_map(|k| (0..n_r).map(move |l| (k, l)));
        // ψ̃_k ψ̃_l = ψ_l ψ_kᵀ − (ψ_kᵀψ_l) I: entry (a, b) is Σ m ψ_l[a] ψ_k[b] = W_ba[k][l]
        let m5: Vec<[[f64; 3]; 3]> = pairs
            .clone()
            .map(|(k, l)| {
                std::array::from_fn(|a| {
                    std::array::from_fn(|b| w[b][a][(k, l)] - if a == b { m9[(k, l)] } else { 0.0 })
                })
            })
            .collect();
        // ψ_k × ψ_l
        let m7: Vec<[f64; 3]> = pairs
            .map(|(k, l)| {
                [
                    w[1][2][(k, l)] - w[2][1][(k, l)],
                    w[2][0][(k, l)] - w[0][2][(k, l)],
                    w[0][1][(k, l)] - w[1][0][(k, l)],
                ]
            })
            .collect();
        MassInvariants {
            mass,
            m1,
            m2,
            m3,
            m4,
            m5,
            m6,
            m7,
            m8,
            m9,
        }
    }

    /// The invariants as row-major arrays with their shapes (module doc), index 0 the mass and
    /// 1–9 M̂₁–M̂₉: the layout of an artifact's `/prom/invariants/<k>`.
    pub fn to_arrays(&self) -> Vec<(Vec<f64>, Vec<usize>)> {
        let n = self.size();
        let row_major = |m: &Mat<f64>| -> Vec<f64> {
            (0..m.nrows())
                .flat_map(|i| (0..m.ncols()).map(move |j| m[(i, j)]))
                .collect()
        };
        vec![
            (vec![self.mass], vec![1]),
            (self.m1.to_vec(), vec![3]),
            (row_major(&self.m2), vec![3, n]),
            (self.m3.concat(), vec![3, 3]),
            (
                self.m4.iter().flatten().flatten().copied().collect(),
                vec![n, 3, 3],
            ),
            (
                self.m5.iter().flatten().flatten().copied().collect(),
                vec![n, n, 3, 3],
            ),
            (row_major(&self.m6), vec![3, n]),
            (self.m7.concat(), vec![n, n, 3]),
            (self.m8.clone(), vec![n]),
            (row_major(&self.m9), vec![n, n]),
        ]
    }

    /// The inverse of [`MassInvariants::to_arrays`] for a basis of size `n`; `None` when an
    /// array count or length does not match.
    pub fn from_arrays(arrays: &[Vec<f64>], n: usize) -> Option<Self> {
        let lengths = [1, 3, 3 * n, 9, 9 * n, 9 * n * n, 3 * n, 3 * n * n, n, n * n];
        if arrays.len() != lengths.len() || arrays.iter().zip(lengths).any(|(a, l)| a.len() != l) {
            return None;
        }
        let matrix = |a: &[f64], rows: usize| Mat::from_fn(rows, n, |i, j| a[i * n + j]);
        let block = |a: &[f64]| -> [[f64; 3]; 3] {
            std::array::from_fn(|i| std::array::from_fn(|j| a[3 * i + j]))
        };
        Some(MassInvariants {
            mass: arrays[0][0],
            m1: [arrays[1][0], arrays[1][1], arrays[1][2]],
            m2: matrix(&arrays[2], 3),
            m3: block(&arrays[3]),
            m4: arrays[4].chunks(9).map(block).collect(),
            m5: arrays[5].chunks(9).map(block).collect(),
            m6: matrix(&arrays[6], 3),
            m7: arrays[7].chunks(3).map(|v| [v[0], v[1], v[2]]).collect(),
            m8: arrays[8].clone(),
            m9: matrix(&arrays[9], n),
        })
    }

    /// Size n_r of the basis.
    pub fn size(&self) -> usize {
        self.m8.len()
    }

    /// Σ_k w_k X^k of affine components (eq. 4.8 with w_k = f_k(p)); `None` without components.
    pub fn combine(components: &[MassInvariants], weights: &[f64]) -> Option<MassInvariants> {
        let (first, rest) = components.split_first()?;
        let w0 = weights[0];
        let mut out = first.scaled(w0);
        for (c, &w) in rest.iter().zip(&weights[1..]) {
            out.add_scaled(c, w);
        }
        Some(out)
    }

    fn scaled(&self, w: f64) -> MassInvariants {
        let mut out = self.clone();
        out.for_each_value(|x| *x *= w);
        out
    }

    /// self += w · other (same n_r).
    fn add_scaled(&mut self, other: &MassInvariants, w: f64) {
        let mut theirs = Vec::new();
        other.clone().for_each_value(|x| theirs.push(*x));
        let mut values = theirs.into_iter();
        self.for_each_value(|x| *x += w * values.next().expect("same shapes"));
    }

    /// Every stored number, in a fixed order.
    fn for_each_value(&mut self, mut f: impl FnMut(&mut f64)) {
        f(&mut self.mass);
        self.m1.iter_mut().for_each(&mut f);
        for m in [&mut self.m2, &mut self.m6, &mut self.m9] {
            for j in 0..m.ncols() {
                m.col_as_slice_mut(j).iter_mut().for_each(&mut f);
            }
        }
        self.m3.iter_mut().flatten().for_each(&mut f);
        self.m4.iter_mut().flatten().flatten().for_each(&mut f);
        self.m5.iter_mut().flatten().flatten().for_each(&mut f);
        self.m7.iter_mut().flatten().for_each(&mut f);
        self.m8.iter_mut().for_each(&mut f);
    }

    /// D̂₂(q) of eq. A.21 = −Σ m_j r̃_j r̃_j with r_j = r_0,j + Ψ_j q: the inertia tensor of the
    /// deformed body about the body origin, from the invariants.
    pub fn d2(&self, q: &[f64]) -> [[f64; 3]; 3] {
        let n = self.size();
        std::array::from_fn(|a| {
            std::array::from_fn(|b| {
                let m4q: f64 = (0..n).map(|l| self.m4[l][a][b] * q[l]).sum();
                let m4q_t: f64 = (0..n).map(|l| self.m4[l][b][a] * q[l]).sum();
                let m5qq: f64 = (0..n)
                    .flat_map(|k| (0..n).map(move |l| (k, l)))
                    .map(|(k, l)| self.m5[k * n + l][a][b] * q[k] * q[l])
                    .sum();
                -self.m3[a][b] - m4q - m4q_t - m5qq
            })
        })
    }

    /// D̂₃(q) of eq. A.22 = M̂₆ + M̂₇ q (3 × n_r).
    pub fn d3(&self, q: &[f64]) -> Mat<f64> {
        let n = self.size();
        Mat::from_fn(3, n, |a, k| {
            self.m6[(a, k)] + (0..n).map(|l| self.m7[k * n + l][a] * q[l]).sum::<f64>()
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::random::SplitMix64;

    /// ã b for a, b of length 3: the cross product.
    fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    }

    /// The deformed positions r_j = r_0,j + Ψ_j q of every grid (for checks of the invariants by
    /// direct sums over the grids).
    fn deformed(positions: &[[f64; 3]], rows: &TranslationRows, q: &[f64]) -> Vec<[f64; 3]> {
        positions
            .iter()
            .enumerate()
            .map(|(j, r)| {
                std::array::from_fn(|a| {
                    r[a] + (0..q.len())
                        .map(|k| rows.axes[a][(j, k)] * q[k])
                        .sum::<f64>()
                })
            })
            .collect()
    }

    fn random_body(
        n_g: usize,
        n_r: usize,
        seed: u64,
    ) -> (Vec<f64>, Vec<[f64; 3]>, TranslationRows) {
        let mut rng = SplitMix64::new(seed);
        let masses = (0..n_g).map(|_| 0.1 + rng.unit()).collect();
        let positions = (0..n_g)
            .map(|_| std::array::from_fn(|_| rng.unit() - 0.3))
            .collect();
        let axes = std::array::from_fn(|_| Mat::from_fn(n_g, n_r, |_, _| rng.unit() - 0.5));
        (masses, positions, TranslationRows { axes })
    }

    /// The defining sums of the module doc, by brute force over the grids with explicit cross
    /// products, at a random q: D̂₂(q) = −Σ m r̃_j r̃_j (A.21, so M̂₃, M̂₄, M̂₅ together),
    /// D̂₃(q) = Σ m r̃_jᵀ Ψ_j (A.22: M̂₆, M̂₇), M̂₁ + M̂₂ q = Σ m r_j (A.20), M̂₈ + qᵀM̂₉ =
    /// Σ m r_jᵀ Ψ_j (A.23). Bound 1e-12 of the largest term: sums of ~10³ products of O(1).
    #[test]
    fn invariants_reproduce_the_direct_sums_over_the_deformed_grids() {
        let (n_g, n_r) = (23, 4);
        let (masses, positions, rows) = random_body(n_g, n_r, 7);
        let inv = MassInvariants::new(&masses, &positions, &rows);
        let q = [0.3, -0.7, 0.45, 0.1];
        let r = deformed(&positions, &rows, &q);
        let psi =
            |j: usize, k: usize| -> [f64; 3] { std::array::from_fn(|a| rows.axes[a][(j, k)]) };
        let close = |a: f64, b: f64, what: &str| {
            assert!(
                (a - b).abs() <= 1e-12 * (1.0 + b.abs()),
                "{what}: {a} vs {b}"
            );
        };
        for a in 0..3 {
            for b in 0..3 {
                // −r̃ r̃ = (rᵀr) I − r rᵀ
                let direct: f64 = (0..n_g)
                    .map(|j| {
                        let rr: f64 = r[j].iter().map(|x| x * x).sum();
                        masses[j] * (if a == b { rr } else { 0.0 } - r[j][a] * r[j][b])
                    })
                    .sum();
                close(inv.d2(&q)[a][b], direct, "D2");
            }
            let first: f64 = (0..n_g).map(|j| masses[j] * r[j][a]).sum();
            let via: f64 = inv.m1[a] + (0..n_r).map(|k| inv.m2[(a, k)] * q[k]).sum::<f64>();
            close(via, first, "D1");
        }
        let d3 = inv.d3(&q);
        for k in 0..n_r {
            // r̃ᵀ ψ = ψ × r
            let direct: [f64; 3] = (0..n_g).fold([0.0; 3], |acc, j| {
                let c = cross(psi(j, k), r[j]);
                std::array::from_fn(|a| acc[a] + masses[j] * c[a])
            });
            for a in 0..3 {
                close(d3[(a, k)], direct[a], "D3");
            }
            let d4: f64 = (0..n_g)
                .map(|j| masses[j] * (0..3).map(|a| r[j][a] * psi(j, k)[a]).sum::<f64>())
                .sum();
            let via = inv.m8[k] + (0..n_r).map(|l| q[l] * inv.m9[(l, k)]).sum::<f64>();
            close(via, d4, "D4");
        }
        assert_eq!(inv.mass, masses.iter().sum::<f64>());
    }

    /// Every invariant is linear in the nodal masses: the invariants of Σ w_k m^k equal
    /// Σ w_k M̂(m^k) (eq. 4.8). Bound 1e-12 relative (a few additions per entry).
    #[test]
    fn combined_components_equal_the_invariants_of_the_combined_masses() {
        let (masses, positions, rows) = random_body(11, 3, 3);
        let other: Vec<f64> = masses.iter().map(|m| 0.5 - m * m).collect();
        let w = [1.7, -0.4];
        let parts = [
            MassInvariants::new(&masses, &positions, &rows),
            MassInvariants::new(&other, &positions, &rows),
        ];
        let combined_masses: Vec<f64> = masses
            .iter()
            .zip(&other)
            .map(|(a, b)| w[0] * a + w[1] * b)
            .collect();
        let mut direct = MassInvariants::new(&combined_masses, &positions, &rows);
        let mut via = MassInvariants::combine(&parts, &w).unwrap();
        let (mut a, mut b) = (Vec::new(), Vec::new());
        direct.for_each_value(|x| a.push(*x));
        via.for_each_value(|x| b.push(*x));
        assert_eq!(a.len(), b.len());
        for (x, y) in a.iter().zip(&b) {
            assert!((x - y).abs() <= 1e-12 * (1.0 + x.abs()), "{x} vs {y}");
        }
    }
}
