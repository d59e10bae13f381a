//! The sparsity pattern of K_gg / M_gg, built once from the connectivity.
//!
//! The pattern is the symmetric *full* (both triangles) CSC pattern that `linalg` takes, in
//! **grid blocks restricted to active components**: a component of a grid is active when some
//! element contribution has it among its DOFs (a solid's grid: T1–T3; a shell's: all six). If two
//! grids share an element, every pair of their active components is in the pattern; every DOF
//! has its diagonal entry, active or not (AUTOSPC and the factorization rely on it). The pattern
//! A scalar point is a block of one DOF after the grids' blocks. The pattern
//! is a superset of the exact DOF pattern (a spring couples one component); the extra entries are
//! stored zeros. Restricting the blocks to active components keeps solid meshes at 3 × 3 blocks
//! (a quarter of the 6 × 6 entries: K, M and every operator derived from them). It is computed
//! from grid adjacency, so its cost is Σ_e nodes_e² rather than Σ_e (6·nodes_e)².
//!
//! Every affine part of K and M is assembled on this one pattern
//! ([`AffineOperator`](super::assemble::AffineOperator)), so K(p), K − σM, … are sums of value
//! arrays and one symbolic factorization serves every parameter sample.

use nalgebra_sparse::pattern::SparsityPattern;

use super::dofs::DOFS_PER_GRID;
use super::error::AssemblyError;

/// Grid-block pattern (module doc) of a g-set of `grids` grids followed by `scalars` scalar
/// points (one DOF each, a block of one) from the DOF lists of the element contributions
/// (g indices). Errors on a DOF past the g-set.
pub fn grid_block_pattern<'a>(
    grids: usize,
    scalars: usize,
    dof_lists: impl IntoIterator<Item = &'a [usize]>,
) -> Result<SparsityPattern, AssemblyError> {
    let grid_dofs = DOFS_PER_GRID * grids;
    let size = grid_dofs + scalars;
    let blocks = grids + scalars;
    // block of a g index and its component in the block
    let block_of = |d: usize| {
        if d < grid_dofs {
            (d / DOFS_PER_GRID, d % DOFS_PER_GRID)
        } else {
            (grids + d - grid_dofs, 0)
        }
    };
    let start = |a: usize| {
        if a < grids {
            DOFS_PER_GRID * a
        } else {
            grid_dofs + a - grids
        }
    };
    let width = |a: usize| if a < grids { DOFS_PER_GRID } else { 1 };
    let mut adjacent: Vec<Vec<usize>> = (0..blocks).map(|a| vec![a]).collect();
    // bit c of active[a]: component c of block a is a DOF of some contribution
    let mut active = vec![0u8; blocks];
    let mut element_blocks: Vec<usize> = Vec::new();
    for dofs in dof_lists {
        element_blocks.clear();
        for &d in dofs {
            if d >= size {
                return Err(AssemblyError::DofOutOfRange { index: d, size });
            }
            let (a, c) = block_of(d);
            element_blocks.push(a);
            active[a] |= 1 << c;
        }
        element_blocks.sort_unstable();
        element_blocks.dedup();
        for &a in &element_blocks {
            adjacent[a].extend(element_blocks.iter().copied().filter(|&b| b != a));
        }
    }
    for list in &mut adjacent {
        list.sort_unstable();
        list.dedup();
    }
    let is_active = |a: usize, c: usize| active[a] & (1 << c) != 0;
    let mut offsets = Vec::with_capacity(size + 1);
    let mut rows = Vec::new();
    offsets.push(0);
    for (a, list) in adjacent.iter().enumerate() {
        for c in 0..width(a) {
            if is_active(a, c) {
                for &b in list {
                    rows.extend(
                        (0..width(b))
                            .filter(|&r| is_active(b, r) || (b == a && r == c))
                            .map(|r| start(b) + r),
                    );
                }
            } else {
                rows.push(start(a) + c);
            }
            offsets.push(rows.len());
        }
    }
    SparsityPattern::try_from_offsets_and_indices(size, size, offsets, rows).map_err(|_| {
        AssemblyError::PatternMismatch {
            what: "internal: grid-block pattern is not a valid CSC pattern",
        }
    })
}

/// Position of entry (row, col) in a CSC pattern (binary search in the column).
pub fn entry_position(pattern: &SparsityPattern, row: usize, col: usize) -> Option<usize> {
    let offsets = pattern.major_offsets();
    let start = *offsets.get(col)?;
    let end = *offsets.get(col + 1)?;
    pattern.minor_indices()[start..end]
        .binary_search(&row)
        .ok()
        .map(|k| start + k)
}

/// A CSC pattern from per-column sorted, deduplicated row lists.
pub(crate) fn from_columns(
    nrows: usize,
    columns: &[Vec<usize>],
) -> Result<SparsityPattern, AssemblyError> {
    let mut offsets = Vec::with_capacity(columns.len() + 1);
    let mut rows = Vec::with_capacity(columns.iter().map(Vec::len).sum());
    offsets.push(0);
    for c in columns {
        rows.extend_from_slice(c);
        offsets.push(rows.len());
    }
    SparsityPattern::try_from_offsets_and_indices(columns.len(), nrows, offsets, rows).map_err(
        |_| AssemblyError::PatternMismatch {
            what: "internal: column lists are not a valid CSC pattern",
        },
    )
}
