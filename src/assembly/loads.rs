//! Static load vectors P_g of a `LOAD = sid` selection, and their reduction to the f-set.
//!
//! - `FORCE` / `MOMENT`: F·(N1, N2, N3) with N in system CID *at the grid* (for a CORD2C the
//!   local (e_r, e_θ, e_z) there, `CoordSystem::axes_at`), rotated to the grid's global (CD)
//!   frame and added to its translations / rotations.
//! - `FORCE1` / `FORCE2` / `MOMENT1` / `MOMENT2`: as FORCE / MOMENT, the direction from the
//!   grids' basic positions ([`Model::direction_by_grids`]); `SLOAD`: F on a scalar point's DOF.
//! - `GRAV`: acceleration a = A·(N1, N2, N3) in CID's axes (its Cartesian axes i, j, k; the
//!   direction is uniform). The load is P = M_gg · a_g with a_g the rigid translational
//!   acceleration field (a in every grid's global frame, zero rotations), so the mass matrix
//!   must be assembled first ([`gravity_load`]).
//! - `PLOAD4` / `PLOAD2` / `PLOAD`: the consistent nodal forces of the pressure on each loaded
//!   face ([`crate::model::pressure`], [`crate::fe::pressure`]), added like FORCEs in basic.
//! - `LOAD sid S S1 L1 S2 L2 …`: P = S · Σ Si P(Li), with Li FORCE/MOMENT/FORCE1/FORCE2/MOMENT1/MOMENT2/SLOAD/GRAV/PLOAD4/PLOAD2/PLOAD/PLOAD1/SPCD sets; a LOAD that
//!   references a LOAD is an error, as in Nastran. The model resolves the set into scaled
//!   vectors in the basic system ([`Model::load_set`]).
//!
//! Reduction ([`reduce_load`]): P_n = Tᵀ P_g, then P_f = P_n\[f\] − K_fs u_s, which moves the
//! enforced displacements u_s to the right-hand side.

use super::assemble::AffineOperator;
use super::constraints::RigidElimination;
use super::dofs::{DofMap, Sets, check_len};
use super::error::AssemblyError;
use super::frames::GridFrames;
use crate::card_values::ForceKind;
use crate::model::Model;
use crate::model::sets::{LoadTerm, SetError};

/// The mass matrix M_gg as an operator and the values to use (M at the current parameters).
pub struct Mass<'a> {
    pub operator: &'a AffineOperator,
    pub values: &'a [f64],
}

/// P_g of the load selection `sid` ([`Model::load_set`]); `mass` is needed only when a GRAV is
/// involved.
pub fn load_vector(
    model: &Model,
    frames: &GridFrames,
    map: &DofMap,
    sid: u32,
    mass: Option<Mass<'_>>,
) -> Result<Vec<f64>, AssemblyError> {
    let terms = model.load_set(sid).map_err(|e| match e {
        SetError::Empty => AssemblyError::NoLoadSet { sid },
        SetError::Nested(li) => AssemblyError::BadLoad {
            sid,
            reason: format!("L = {li} is itself a LOAD (nested LOAD is not allowed)"),
        },
        SetError::Missing(li) => AssemblyError::BadLoad {
            sid,
            reason: format!(
                "L = {li} selects no FORCE/MOMENT/FORCE1/FORCE2/MOMENT1/MOMENT2/SLOAD/GRAV/PLOAD4/PLOAD2/PLOAD/PLOAD1/SPCD set"
            ),
        },
    })?;
    let mut p = vec![0.0; map.size()];
    for term in &terms {
        add_term(frames, term, &mass, sid, &mut p)?;
        for &(k, f) in &term.scalar_loads {
            p[map.scalar_dof(k)] += f;
        }
    }
    Ok(p)
}

/// Add one load term (its forces and moments rotated to the grids' global frames, its
/// accelerations as M · a) to P_g.
fn add_term(
    frames: &GridFrames,
    term: &LoadTerm,
    mass: &Option<Mass<'_>>,
    selected: u32,
    p: &mut [f64],
) -> Result<(), AssemblyError> {
    for f in &term.point_loads {
        let global = frames.to_global(f.grid, f.basic);
        let first = DofMap::dof(f.grid, if f.kind == ForceKind::Force { 0 } else { 3 });
        for (k, v) in global.iter().enumerate() {
            p[first + k] += v;
        }
    }
    for &a in &term.accelerations {
        let mass = mass
            .as_ref()
            .ok_or(AssemblyError::MassRequired { sid: selected })?;
        let pg = gravity_load(mass.operator, mass.values, frames, a)?;
        p.iter_mut().zip(pg).for_each(|(x, y)| *x += y);
    }
    Ok(())
}

/// P = M_gg · a_g for a uniform translational acceleration `accel` (basic components):
/// a_g holds `accel` in each grid's global frame for T1–T3 and zero for R1–R3.
pub fn gravity_load(
    m_gg: &AffineOperator,
    m_values: &[f64],
    frames: &GridFrames,
    accel: [f64; 3],
) -> Result<Vec<f64>, AssemblyError> {
    let g = m_gg.ncols();
    let mut a = vec![0.0; g];
    for grid in 0..g / 6 {
        let v = frames.to_global(grid, accel);
        a[6 * grid..6 * grid + 3].copy_from_slice(&v);
    }
    m_gg.mul_values(m_values, &a)
}

/// P_f = (Tᵀ P_g)\[f\] − K_fs u_s, with `k_fs` = K_nn\[f, s\] (an operator from
/// [`partition`](super::reduce::partition)) evaluated to `k_fs_values`, and `enforced` the
/// g-set enforced values ([`SpcSet::enforced`](super::spc::SpcSet::enforced)).
pub fn reduce_load(
    p_g: &[f64],
    rigid: &RigidElimination,
    sets: &Sets,
    k_fs: &AffineOperator,
    k_fs_values: &[f64],
    enforced: &[f64],
) -> Result<Vec<f64>, AssemblyError> {
    let p_n = rigid.reduce_vector(p_g)?;
    let mut p_f = sets.f_in_n.gather(&p_n)?;
    let u_s = sets.s.gather(enforced)?;
    if u_s.iter().any(|&u| u != 0.0) {
        check_len("rows of K_fs", p_f.len(), k_fs.nrows())?;
        let correction = k_fs.mul_values(k_fs_values, &u_s)?;
        p_f.iter_mut().zip(correction).for_each(|(p, c)| *p -= c);
    }
    Ok(p_f)
}
