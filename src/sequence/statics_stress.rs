//! SOL 101's element FORCE and STRESS output ([`crate::analysis::stress`]), only for the
//! elements of the request's SET (or ALL), under `/results/<subcase>/statics`:
//!
//! ```text
//! force/<CQUAD4|CTRIA3>/{ids (m), forces (m×8)}      Nx Ny Nxy Mx My Mxy Qx Qy, material system
//! stress/<CQUAD4|CTRIA3>/{ids (m), top (m×3), bottom (m×3), von_mises (m×2)}   PSHELL elements
//! ply_stress/<CQUAD4|CTRIA3>/{ids (r), ply (r), z (r), stress (r×5), strain (r×5),
//!                             failure_index (r)}                             PCOMP elements
//! stress/CSHEAR/{ids (m), shear (m), shear_flow (m)}   mean shear stress τ = G γ̄, q = τ t
//! stress/<CHEXA|CPENTA|CTETRA|CTETRA10>/{ids (m), centroid (m×6), von_mises (m),
//!     corner_grid_ids (m×c), corners (m×c×6), corner_von_mises (m×c)}    basic system
//! ```

use hdf5_metno::Group;

use super::{RunContext, RunError};
use crate::analysis::stress::{ElementForces, ElementStresses};
use crate::io::{write_f64, write_u32};

/// The group `<parent>/<kind>/<block>`.
fn block_group(
    ctx: &RunContext,
    parent: &Group,
    kind: &str,
    block: &str,
) -> Result<Group, RunError> {
    Ok(ctx
        .output
        .group(&format!("{}/{kind}/{block}", parent.name()))?)
}

/// Writes `force/<block>/{ids, forces}` under `group`.
pub fn write_forces(
    ctx: &RunContext,
    group: &Group,
    forces: &ElementForces,
) -> Result<(), RunError> {
    for (name, b) in forces {
        let g = block_group(ctx, group, "force", name)?;
        let m = b.ids.len();
        write_u32(&g, "ids", &b.ids, &[m])?;
        write_f64(&g, "forces", &b.forces, &[m, 8])?;
    }
    Ok(())
}

/// Writes the `stress` and `ply_stress` groups (module doc) under `group`.
pub fn write_stresses(
    ctx: &RunContext,
    group: &Group,
    stresses: &ElementStresses,
) -> Result<(), RunError> {
    for (name, b) in &stresses.fibres {
        let g = block_group(ctx, group, "stress", name)?;
        let m = b.ids.len();
        write_u32(&g, "ids", &b.ids, &[m])?;
        write_f64(&g, "top", &b.top, &[m, 3])?;
        write_f64(&g, "bottom", &b.bottom, &[m, 3])?;
        write_f64(&g, "von_mises", &b.von_mises, &[m, 2])?;
    }
    for (name, b) in &stresses.plies {
        let g = block_group(ctx, group, "ply_stress", name)?;
        let r = b.ids.len();
        write_u32(&g, "ids", &b.ids, &[r])?;
        write_u32(&g, "ply", &b.ply, &[r])?;
        write_f64(&g, "z", &b.z, &[r])?;
        write_f64(&g, "stress", &b.stress, &[r, 5])?;
        write_f64(&g, "strain", &b.strain, &[r, 5])?;
        write_f64(&g, "failure_index", &b.failure_index, &[r])?;
    }
    for (name, b) in &stresses.solids {
        let g = block_group(ctx, group, "stress", name)?;
        let (m, c) = (b.ids.len(), b.corners);
        write_u32(&g, "ids", &b.ids, &[m])?;
        write_f64(&g, "centroid", &b.centroid, &[m, 6])?;
        write_f64(&g, "von_mises", &b.von_mises, &[m])?;
        write_u32(&g, "corner_grid_ids", &b.corner_grids, &[m, c])?;
        write_f64(&g, "corners", &b.corner_stress, &[m, c, 6])?;
        write_f64(&g, "corner_von_mises", &b.corner_von_mises, &[m, c])?;
    }
    let b = &stresses.shear_panels;
    if !b.ids.is_empty() {
        let g = block_group(ctx, group, "stress", "CSHEAR")?;
        let m = b.ids.len();
        write_u32(&g, "ids", &b.ids, &[m])?;
        write_f64(&g, "shear", &b.shear, &[m])?;
        write_f64(&g, "shear_flow", &b.shear_flow, &[m])?;
    }
    Ok(())
}
