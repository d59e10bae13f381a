//! Static load vectors P_g of a `LOAD = sid` selection, and their reduction to the f-set.
//!
//! - `FORCE` / `MOMENT`: F·(N1, N2, N3) with N in system CID *at the grid* (for a CORD2C the
//!   local (e_r, e_θ, e_z) there, `CoordSystem::axes_at`), rotated to the grid's global (CD)
//!   frame and added to its translations / rotations.
//! - `GRAV`: acceleration a = A·(N1, N2, N3) in CID's axes (its Cartesian axes i, j, k; the
//!   direction is uniform). The load is P = M_gg · a_g with a_g the rigid translational
//!   acceleration field (a in every grid's global frame, zero rotations), so the mass matrix
//!   must be assembled first ([`gravity_load`]).
//! - `LOAD sid S S1 L1 S2 L2 …`: P = S · Σ Si P(Li), with Li FORCE/MOMENT/GRAV sets; a LOAD that
//!   references a LOAD is an error, as in Nastran.
//!
//! Reduction ([`reduce_load`]): P_n = Tᵀ P_g, then P_f = P_n\[f\] − K_fs u_s, which moves the
//! enforced displacements u_s to the right-hand side.

use super::assemble::AffineOperator;
use super::constraints::RigidElimination;
use super::dofs::{DofMap, Sets, check_len};
use super::error::AssemblyError;
use super::frames::GridFrames;
use crate::model::Model;
use crate::model::card_fields::ForceKind;

/// The mass matrix M_gg as an operator and the values to use (M at the current parameters).
pub struct Mass<'a> {
    pub operator: &'a AffineOperator,
    pub values: &'a [f64],
}

/// P_g of the load selection `sid`; `mass` is needed only when a GRAV is involved.
pub fn load_vector(
    model: &Model,
    frames: &GridFrames,
    map: &DofMap,
    sid: u32,
    mass: Option<Mass<'_>>,
) -> Result<Vec<f64>, AssemblyError> {
    let b = &model.bulk;
    let mut p = vec![0.0; map.size()];
    let combos: Vec<_> = b.load.iter().filter(|l| l.sid == sid).collect();
    if combos.is_empty() {
        if !simple_set_exists(model, sid) {
            return Err(AssemblyError::NoLoadSet { sid });
        }
        add_simple(model, frames, sid, 1.0, &mass, sid, &mut p)?;
        return Ok(p);
    }
    for combo in combos {
        for &(si, li) in &combo.terms {
            if b.load.iter().any(|l| l.sid == li) {
                return Err(AssemblyError::BadLoad {
                    sid,
                    reason: format!("L = {li} is itself a LOAD (nested LOAD is not allowed)"),
                });
            }
            if !simple_set_exists(model, li) {
                return Err(AssemblyError::BadLoad {
                    sid,
                    reason: format!("L = {li} selects no FORCE/MOMENT/GRAV set"),
                });
            }
            add_simple(model, frames, li, combo.scale * si, &mass, sid, &mut p)?;
        }
    }
    Ok(p)
}

fn simple_set_exists(model: &Model, sid: u32) -> bool {
    model.bulk.forces.iter().any(|f| f.sid == sid) || model.bulk.grav.iter().any(|g| g.sid == sid)
}

/// Add `scale` × the FORCE/MOMENT/GRAV cards of set `set` to P_g.
fn add_simple(
    model: &Model,
    frames: &GridFrames,
    set: u32,
    scale: f64,
    mass: &Option<Mass<'_>>,
    selected: u32,
    p: &mut [f64],
) -> Result<(), AssemblyError> {
    for f in model.bulk.forces.iter().filter(|f| f.sid == set) {
        let card = format!(
            "{} {}",
            if f.kind == ForceKind::Force {
                "FORCE"
            } else {
                "MOMENT"
            },
            f.sid
        );
        let grid = *model
            .grid_index
            .get(&f.grid)
            .ok_or(AssemblyError::MissingGrid {
                card: card.clone(),
                grid: f.grid,
            })?;
        let cs = model
            .coords
            .get(&f.cid)
            .ok_or(AssemblyError::MissingCoord { card, cid: f.cid })?;
        let xyz = model.grids.get(grid).map_or([0.0; 3], |g| g.xyz);
        let axes = cs.axes_at(xyz);
        let n = f.direction;
        let basic: [f64; 3] = std::array::from_fn(|i| {
            scale * f.scale * (0..3).map(|j| axes[i][j] * n[j]).sum::<f64>()
        });
        let global = frames.to_global(grid, basic);
        let first = DofMap::dof(grid, if f.kind == ForceKind::Force { 0 } else { 3 });
        for (k, v) in global.iter().enumerate() {
            p[first + k] += v;
        }
    }
    for g in model.bulk.grav.iter().filter(|g| g.sid == set) {
        let mass = mass
            .as_ref()
            .ok_or(AssemblyError::MassRequired { sid: selected })?;
        let cs = model
            .coords
            .get(&g.cid)
            .ok_or(AssemblyError::MissingCoord {
                card: format!("GRAV {}", g.sid),
                cid: g.cid,
            })?;
        let a = cs.vector_to_basic(g.direction.map(|x| x * g.a * scale));
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
