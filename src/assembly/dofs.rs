//! The DOF map and the DOF sets g, m, s, n, f.
//!
//! Global (g-set) numbering is grid-major with six DOFs per grid, grids in the order of
//! [`Model::grids`](crate::model::Model::grids) (sorted by id), then one DOF per scalar point
//! in the order of [`Model::scalar_points`](crate::model::Model::scalar_points):
//!
//! ```text
//! g = 6 · grid_index + c,   c = 0..6  ↔  components 1..6 = T1 T2 T3 R1 R2 R3
//! g = 6 · grids + scalar_index       (scalar points)
//! ```
//!
//! Grids keep the 6·i numbering of a model without scalar points, so every grid-block loop
//! stays as it is; Nastran sorts grids and scalar points together by id, an internal ordering no
//! output depends on.
//!
//! A [`DofSet`] is a sorted subset of a parent numbering with the maps both ways; [`Sets`]
//! holds m, s, n = g − m and f = n − s, all as subsets of g.

use super::error::{AssemblyError, DofName};
use crate::model::scalar_points::PointDof;

/// DOFs per grid.
pub const DOFS_PER_GRID: usize = 6;

/// Map between g-set indices and (GRID id, component) or SPOINT id.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DofMap {
    /// GRID id of each grid index.
    grid_ids: Vec<u32>,
    /// SPOINT id of each scalar point index.
    scalar_ids: Vec<u32>,
}

impl DofMap {
    /// The map for grids with these ids, in grid-index order, without scalar points.
    pub fn new(grid_ids: Vec<u32>) -> Self {
        DofMap::with_scalar_points(grid_ids, Vec::new())
    }

    /// The map for grids and then scalar points with these ids, in index order.
    pub fn with_scalar_points(grid_ids: Vec<u32>, scalar_ids: Vec<u32>) -> Self {
        DofMap {
            grid_ids,
            scalar_ids,
        }
    }

    /// The map of a model.
    pub fn of_model(model: &crate::model::Model) -> Self {
        DofMap::with_scalar_points(
            model.grids.iter().map(|g| g.id).collect(),
            model.scalar_points.clone(),
        )
    }

    /// Number of grids.
    pub fn grids(&self) -> usize {
        self.grid_ids.len()
    }

    /// Number of scalar points.
    pub fn scalar_points(&self) -> usize {
        self.scalar_ids.len()
    }

    /// SPOINT ids, in scalar point order.
    pub fn scalar_ids(&self) -> &[u32] {
        &self.scalar_ids
    }

    /// Size of the g-set.
    pub fn size(&self) -> usize {
        DOFS_PER_GRID * self.grid_ids.len() + self.scalar_ids.len()
    }

    /// g index of the scalar point with index `k`.
    pub fn scalar_dof(&self, k: usize) -> usize {
        DOFS_PER_GRID * self.grid_ids.len() + k
    }

    /// The g indices of the scalar points, in scalar point order.
    pub fn scalar_dofs(&self) -> std::ops::Range<usize> {
        self.scalar_dof(0)..self.size()
    }

    /// g index of a grid component or scalar point.
    pub fn point_dof(&self, point: PointDof) -> usize {
        match point {
            PointDof::Grid { grid, component0 } => DofMap::dof(grid, component0),
            PointDof::Scalar(k) => self.scalar_dof(k),
        }
    }

    /// g index of component `component0` (0-based) of grid index `grid`.
    pub fn dof(grid: usize, component0: usize) -> usize {
        DOFS_PER_GRID * grid + component0
    }

    /// The six g indices of a grid.
    pub fn grid_dofs(grid: usize) -> std::ops::Range<usize> {
        DOFS_PER_GRID * grid..DOFS_PER_GRID * (grid + 1)
    }

    /// (GRID id, component 1–6) of a g index, or (SPOINT id, component 0), for messages;
    /// `None` past the end.
    pub fn dof_name(&self, index: usize) -> Option<DofName> {
        let grid_dofs = DOFS_PER_GRID * self.grid_ids.len();
        if index >= grid_dofs {
            return Some(DofName {
                grid: *self.scalar_ids.get(index - grid_dofs)?,
                component: 0,
            });
        }
        let grid = *self.grid_ids.get(index / DOFS_PER_GRID)?;
        Some(DofName {
            grid,
            component: (index % DOFS_PER_GRID + 1) as u8,
        })
    }

    /// Like [`DofMap::dof_name`] for an index known to be in range (falls back to grid 0).
    pub(crate) fn name(&self, index: usize) -> DofName {
        self.dof_name(index).unwrap_or(DofName {
            grid: 0,
            component: (index % DOFS_PER_GRID + 1) as u8,
        })
    }

    /// GRID id of a grid index.
    pub fn grid_id(&self, grid: usize) -> Option<u32> {
        self.grid_ids.get(grid).copied()
    }
}

/// A sorted subset of a parent numbering `0..parent_size`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DofSet {
    /// Members (parent indices), increasing.
    members: Vec<usize>,
    /// Parent index → position in `members`.
    position: Vec<Option<usize>>,
}

impl DofSet {
    /// The set of the parent indices where `keep` is true.
    pub fn from_mask(keep: &[bool]) -> Self {
        let members: Vec<usize> = keep
            .iter()
            .enumerate()
            .filter(|(_, k)| **k)
            .map(|(i, _)| i)
            .collect();
        let mut position = vec![None; keep.len()];
        for (k, &i) in members.iter().enumerate() {
            position[i] = Some(k);
        }
        DofSet { members, position }
    }

    /// The whole parent `0..size`.
    pub fn all(size: usize) -> Self {
        DofSet::from_mask(&vec![true; size])
    }

    /// Members in increasing order (parent indices).
    pub fn members(&self) -> &[usize] {
        &self.members
    }

    /// Number of members.
    pub fn len(&self) -> usize {
        self.members.len()
    }

    /// True when empty.
    pub fn is_empty(&self) -> bool {
        self.members.is_empty()
    }

    /// Size of the parent numbering.
    pub fn parent_size(&self) -> usize {
        self.position.len()
    }

    /// Position of a parent index in the set.
    pub fn position(&self, parent: usize) -> Option<usize> {
        self.position.get(parent).copied().flatten()
    }

    /// True when the parent index is a member.
    pub fn contains(&self, parent: usize) -> bool {
        self.position(parent).is_some()
    }

    /// Gather a parent vector into the set: out\[k\] = v\[members\[k\]\].
    pub fn gather(&self, v: &[f64]) -> Result<Vec<f64>, AssemblyError> {
        check_len("vector to gather", self.parent_size(), v.len())?;
        Ok(self.members.iter().map(|&i| v[i]).collect())
    }

    /// Scatter set values into a parent vector: v\[members\[k\]\] = x\[k\].
    pub fn scatter_into(&self, x: &[f64], v: &mut [f64]) -> Result<(), AssemblyError> {
        check_len("set vector", self.len(), x.len())?;
        check_len("parent vector", self.parent_size(), v.len())?;
        for (&i, &xi) in self.members.iter().zip(x) {
            v[i] = xi;
        }
        Ok(())
    }
}

pub(crate) fn check_len(
    what: &'static str,
    expected: usize,
    found: usize,
) -> Result<(), AssemblyError> {
    if expected == found {
        Ok(())
    } else {
        Err(AssemblyError::SizeMismatch {
            what,
            expected,
            found,
        })
    }
}

/// The sets of one constrained model, all as subsets of g.
///
/// Invariants: m ∩ s = ∅ (checked when the sets are built), n = g − m, f = n − s.
#[derive(Debug, Clone, PartialEq)]
pub struct Sets {
    /// Dependent DOFs (RBE2 / RBE3).
    pub m: DofSet,
    /// Constrained DOFs (SPC, PS, AUTOSPC).
    pub s: DofSet,
    /// Independent DOFs n = g − m.
    pub n: DofSet,
    /// Free DOFs f = n − s.
    pub f: DofSet,
    /// The s-set as a subset of n (positions in n), for K_fs and SPC forces.
    pub s_in_n: DofSet,
    /// The f-set as a subset of n (positions in n), for K_ff.
    pub f_in_n: DofSet,
}

impl Sets {
    /// Build the sets from the g-masks of m and s. Returns an error naming the first DOF that is
    /// in both (the caller usually checks earlier with better context).
    pub fn new(map: &DofMap, m_mask: &[bool], s_mask: &[bool]) -> Result<Self, AssemblyError> {
        let g = map.size();
        check_len("m-set mask", g, m_mask.len())?;
        check_len("s-set mask", g, s_mask.len())?;
        if let Some(i) = (0..g).find(|&i| m_mask[i] && s_mask[i]) {
            return Err(AssemblyError::DependentConstrained {
                dof: map.name(i),
                rigid: "a rigid element".into(),
                constraint: "the s-set".into(),
            });
        }
        let n_mask: Vec<bool> = m_mask.iter().map(|m| !m).collect();
        let f_mask: Vec<bool> = (0..g).map(|i| !m_mask[i] && !s_mask[i]).collect();
        let n = DofSet::from_mask(&n_mask);
        let s_in_n = DofSet::from_mask(&n.members().iter().map(|&i| s_mask[i]).collect::<Vec<_>>());
        let f_in_n = DofSet::from_mask(&n.members().iter().map(|&i| f_mask[i]).collect::<Vec<_>>());
        Ok(Sets {
            m: DofSet::from_mask(m_mask),
            s: DofSet::from_mask(s_mask),
            n,
            f: DofSet::from_mask(&f_mask),
            s_in_n,
            f_in_n,
        })
    }

    /// The s-set mask over g.
    pub fn s_mask(&self) -> Vec<bool> {
        (0..self.s.parent_size())
            .map(|i| self.s.contains(i))
            .collect()
    }

    /// The m-set mask over g.
    pub fn m_mask(&self) -> Vec<bool> {
        (0..self.m.parent_size())
            .map(|i| self.m.contains(i))
            .collect()
    }
}
