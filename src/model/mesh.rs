//! Plain mesh arrays for output: what the `/model` group of the HDF5 file and the XDMF file
//! need, with no reference to cards or element formulations.

/// Grids and element connectivity as flat arrays.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct MeshArrays {
    /// Grid ids, sorted increasing. Row `i` of every per-grid array refers to `grid_ids[i]`.
    pub grid_ids: Vec<u32>,
    /// Grid locations in the basic system.
    pub xyz: Vec<[f64; 3]>,
    /// One block per element type present in the model.
    pub blocks: Vec<ElementBlock>,
}

/// All elements of one type.
#[derive(Debug, Clone, PartialEq)]
pub struct ElementBlock {
    /// Card name: `CQUAD4`, `CTRIA3`, `CQUAD8`, `CTRIA6` (and `CQUAD8_CORNERS`,
    /// `CTRIA6_CORNERS`: those with a blank mid-side grid, by their corner grids), `CHEXA`, `CPENTA`, `CTETRA` (4 nodes), `CTETRA10` (`CTETRA10_CORNERS`: with a blank mid-edge grid, by its corners),
    /// `CELAS1`, `CELAS2`, `CONM2`, and `RBE2`/`RBE3` as one two-node line per leg
    /// (independent/reference grid to each dependent/independent grid), for drawing spiders.
    pub card: &'static str,
    /// Element id of each row (repeated for the legs of one rigid element).
    pub ids: Vec<u32>,
    /// Property id of each row (0 when the element has none: CELAS2, CONM2, CONROD, RBE2, RBE3).
    pub pids: Vec<u32>,
    /// Grids per element.
    pub nodes_per_element: usize,
    /// Row-major `ids.len() × nodes_per_element` 0-based indices into `grid_ids`. A grounded
    /// spring end repeats the spring's grid.
    pub connectivity: Vec<u32>,
}
