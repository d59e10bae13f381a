//! The data of a floating-frame body built from a `RIGID = REMOVE` pROM (thesis §4.2, appendix
//! A): the reduced basis expanded to every grid in basic, the mass invariants of each affine mass
//! component (eq. 4.8, A.11–A.19) and the basis rows of the interface grids, which joints and
//! forces on the body move and turn with.

use super::{Constrained, DiscretizeError, Structure};
use crate::assembly::recover::recover_g;
use crate::io::PromBody;
use crate::linalg::Mat;
use crate::model::Model;
use crate::rom::invariants::{InterfaceRows, MassInvariants, TranslationRows};
use crate::rom::mass::AffineMasses;

/// The columns of the f-set basis `basis` expanded to every grid in basic (dependent DOFs
/// recovered, constrained ones zero): `columns[k]` holds T1 T2 T3 R1 R2 R3 of each grid in
/// `/model/grid_ids` order.
pub fn basic_columns(
    st: &Structure,
    c: &Constrained,
    basis: &Mat<f64>,
) -> Result<Vec<Vec<f64>>, DiscretizeError> {
    let zero = vec![0.0; st.map.size()];
    (0..basis.ncols())
        .map(|k| {
            Ok(st.to_basic_rows(&recover_g(
                basis.col_as_slice(k),
                &c.sets,
                &zero,
                &st.rigid,
            )?))
        })
        .collect()
}

/// The multibody data of a body whose basis columns expanded to every grid in basic are
/// `columns` ([`basic_columns`]): the invariants of each affine mass component in `masses` and
/// the rows of the interface grids (every ASET1 grid, in the order the cards list them).
pub fn flexible_body(
    model: &Model,
    st: &Structure,
    columns: &[Vec<f64>],
    masses: AffineMasses,
) -> PromBody {
    let rows = TranslationRows::from_grid_columns(columns, st.map.grids());
    let invariants = masses
        .nodal
        .iter()
        .map(|m| MassInvariants::new(m, &masses.positions, &rows))
        .collect();
    let (mut ids, mut indices) = (Vec::new(), Vec::new());
    for &grid in model.aset1().iter().flat_map(|card| &card.grids) {
        if let (false, Some(&index)) = (ids.contains(&grid), model.grid_index.get(&grid)) {
            ids.push(grid);
            indices.push(index);
        }
    }
    PromBody {
        grids: model.grids.iter().map(|g| g.id).collect(),
        masses,
        invariants,
        interface: InterfaceRows::from_grid_columns(columns, ids, &indices),
    }
}
