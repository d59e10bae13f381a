//! Global (displacement) frames of the grids: the CD system of each grid.
//!
//! Element matrices are computed in the basic system; the g-set is in the global system of
//! each grid, as in Nastran. With Λ_a the 3×3 matrix whose columns are the CD axes at grid a in
//! basic (`CoordSystem::axes_at`), u_basic = Λ_a u_global for the translations and likewise for
//! the rotations, so an element matrix transforms as
//!
//! ```text
//! K_global = Λᵀ K_basic Λ,   Λ = diag(Λ_a, Λ_a, Λ_b, Λ_b, …)
//! ```
//!
//! and a force vector as P_global = Λᵀ P_basic. Grids with CD = 0 have Λ = I and are skipped.

use faer::Mat;

use crate::model::Model;

/// 3×3 rotation: columns are the global axes in basic.
pub type Rotation = [[f64; 3]; 3];

/// The global frame of every grid (`None` = basic).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct GridFrames {
    rotations: Vec<Option<Rotation>>,
}

impl GridFrames {
    /// All grids in basic.
    pub fn basic(grids: usize) -> Self {
        GridFrames {
            rotations: vec![None; grids],
        }
    }

    /// The CD frames of a model's grids. A CD missing from `model.coords` cannot happen in a
    /// validated model; it is treated as basic.
    pub fn of_model(model: &Model) -> Self {
        let rotations = model
            .grids
            .iter()
            .map(|g| {
                if g.cd == 0 {
                    None
                } else {
                    model.coords.get(&g.cd).map(|c| c.axes_at(g.xyz))
                }
            })
            .collect();
        GridFrames { rotations }
    }

    /// From explicit rotations (tests, or callers with their own frames).
    pub fn from_rotations(rotations: Vec<Option<Rotation>>) -> Self {
        GridFrames { rotations }
    }

    /// The rotation of a grid (`None` = basic or out of range).
    pub fn rotation(&self, grid: usize) -> Option<&Rotation> {
        self.rotations.get(grid).and_then(|r| r.as_ref())
    }

    /// Basic vector → global components at a grid: Λᵀ v.
    pub fn to_global(&self, grid: usize, v: [f64; 3]) -> [f64; 3] {
        match self.rotation(grid) {
            None => v,
            Some(l) => std::array::from_fn(|j| (0..3).map(|i| l[i][j] * v[i]).sum()),
        }
    }

    /// Global components at a grid → basic vector: Λ v.
    pub fn to_basic(&self, grid: usize, v: [f64; 3]) -> [f64; 3] {
        match self.rotation(grid) {
            None => v,
            Some(l) => std::array::from_fn(|i| (0..3).map(|j| l[i][j] * v[j]).sum()),
        }
    }

    /// Rotate an element matrix from basic to global in place: K ← Λᵀ K Λ (only the 3×3
    /// blocks of grids with CD ≠ 0 are touched). `per_node` = 6 (T1–T3, R1–R3 of each grid) or
    /// 3 (translations only, solids).
    pub fn rotate_element(&self, nodes: &[usize], per_node: usize, k: &mut Mat<f64>) {
        let n = k.nrows().min(k.ncols()).min(per_node * nodes.len());
        for (a, &grid) in nodes.iter().enumerate() {
            let Some(l) = self.rotation(grid) else {
                continue;
            };
            for b in (0..per_node).step_by(3).map(|c| per_node * a + c) {
                if b + 3 > n {
                    continue;
                }
                // rows: K[b..b+3, :] ← Λᵀ K[b..b+3, :]
                for c in 0..k.ncols() {
                    let v = [k[(b, c)], k[(b + 1, c)], k[(b + 2, c)]];
                    for j in 0..3 {
                        k[(b + j, c)] = (0..3).map(|i| l[i][j] * v[i]).sum();
                    }
                }
                // columns: K[:, b..b+3] ← K[:, b..b+3] Λ
                for r in 0..k.nrows() {
                    let v = [k[(r, b)], k[(r, b + 1)], k[(r, b + 2)]];
                    for j in 0..3 {
                        k[(r, b + j)] = (0..3).map(|i| v[i] * l[i][j]).sum();
                    }
                }
            }
        }
    }
}
