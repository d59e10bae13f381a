//! Element forces and stresses of a static displacement field (SOL 101's FORCE and STRESS): the
//! model's sections and materials applied to the recovered centroid strains
//! ([`crate::fe::stress`], [`crate::fe::laminate::ply_states`], [`crate::fe::failure`]).
//!
//! | element | FORCE | STRESS |
//! |---|---|---|
//! | CQUAD4, CTRIA3 (PSHELL or PCOMP) | [Nx Ny Nxy Mx My Mxy Qx Qy] at the centroid, element material system | PSHELL: [σx σy τxy] and von Mises at the fibres Z2 (top) and Z1 (bottom), same system |
//! | CQUAD4, CTRIA3 (PCOMP) | as above | every ply at its mid-plane: [σ1 σ2 τ12 τ1z τ2z], [ε1 ε2 γ12 γ1z γ2z] in the ply axes, the FT failure index |
//! | CSHEAR | — | the panel's mean shear stress τ = G γ̄ (γ̄: [`crate::fe::shear_panel`]), shear flow q = τ t |
//! | CHEXA, CPENTA, CTETRA (4, 10) | — | [σxx σyy σzz τxy τyz τzx] and von Mises in basic at the centroid and at the corner grids (extrapolated from the integration points, [`solid::corner_strains`]) |
//!
//! A ply without a failure index (blank FT, an FT other than HILL, HOFF, TSAI, STRN, a MAT1
//! ply, or MAT8 allowables the theory lacks) has NaN; [`failure_warnings`] names each case once.

use std::collections::BTreeMap;

use super::statics::selected_shell_strains;
use crate::card_values::FailureTheory;
use crate::discretize::elements::{CentreSection, shear_panel, shell_centre_section};
use crate::discretize::thermal::ThermalStrains;
use crate::discretize::{DiscretizeError, Structure};
use crate::fe::laminate::{ShellSection, ply_states};
use crate::fe::stress::{
    ShellForces, pshell_fibre_stress, shell_forces, solid_stress, von_mises, von_mises_plane,
};
use crate::fe::{failure, solid};
use crate::model::materials::Material;
use crate::model::properties::{LaminateProperty, ShellProperty};
use crate::model::{Element, ElementKind, Model};

/// Element forces of one shell block, in element order.
#[derive(Debug, Default, Clone)]
pub struct ForceBlock {
    pub ids: Vec<u32>,
    /// [Nx, Ny, Nxy, Mx, My, Mxy, Qx, Qy] per element (m×8).
    pub forces: Vec<f64>,
}

/// Fibre stresses of the PSHELL elements of one shell block.
#[derive(Debug, Default, Clone)]
pub struct FibreBlock {
    pub ids: Vec<u32>,
    /// [σx, σy, τxy] at Z2 (m×3).
    pub top: Vec<f64>,
    /// [σx, σy, τxy] at Z1 (m×3).
    pub bottom: Vec<f64>,
    /// von Mises at [Z2, Z1] (m×2).
    pub von_mises: Vec<f64>,
}

/// Ply results of the PCOMP elements of one shell block, one row per (element, ply).
#[derive(Debug, Default, Clone)]
pub struct PlyBlock {
    /// Element id of each row.
    pub ids: Vec<u32>,
    /// Ply number (1 = bottom, the full stack).
    pub ply: Vec<u32>,
    /// Ply mid-plane z from the reference plane.
    pub z: Vec<f64>,
    /// [σ1, σ2, τ12, τ1z, τ2z] (r×5).
    pub stress: Vec<f64>,
    /// [ε1, ε2, γ12, γ1z, γ2z] (r×5).
    pub strain: Vec<f64>,
    /// Failure index (NaN without one).
    pub failure_index: Vec<f64>,
}

/// Stresses of one solid block.
#[derive(Debug, Default, Clone)]
pub struct SolidBlock {
    pub ids: Vec<u32>,
    /// Corner grids per element.
    pub corners: usize,
    /// [σxx, σyy, σzz, τxy, τyz, τzx] at the centroid (m×6).
    pub centroid: Vec<f64>,
    /// von Mises at the centroid (m).
    pub von_mises: Vec<f64>,
    /// Corner grid ids (m×corners).
    pub corner_grids: Vec<u32>,
    /// Stresses at the corners (m×corners×6).
    pub corner_stress: Vec<f64>,
    /// von Mises at the corners (m×corners).
    pub corner_von_mises: Vec<f64>,
}

/// Shear stresses of the CSHEAR panels.
#[derive(Debug, Default, Clone)]
pub struct ShearPanelBlock {
    pub ids: Vec<u32>,
    /// Mean shear stress τ = G γ̄ (m).
    pub shear: Vec<f64>,
    /// Shear flow q = τ t (m).
    pub shear_flow: Vec<f64>,
}

/// The element forces of a displacement field, by shell block name (CQUAD4, CTRIA3).
pub type ElementForces = BTreeMap<&'static str, ForceBlock>;

/// The element stresses of a displacement field, by block name.
#[derive(Debug, Default, Clone)]
pub struct ElementStresses {
    /// PSHELL fibre stresses (CQUAD4, CTRIA3).
    pub fibres: BTreeMap<&'static str, FibreBlock>,
    /// PCOMP ply results (CQUAD4, CTRIA3).
    pub plies: BTreeMap<&'static str, PlyBlock>,
    /// Solids (CHEXA, CPENTA, CTETRA, CTETRA10).
    pub solids: BTreeMap<&'static str, SolidBlock>,
    /// Shear panels (CSHEAR).
    pub shear_panels: ShearPanelBlock,
}

/// One shell's recovered state: its centre section, strains and forces.
struct ShellState {
    section: CentreSection,
    strains: crate::fe::shell::ShellStrains,
    forces: ShellForces,
    /// (z_top, z_bottom) of the fibres Z2, Z1 from the grid plane.
    fibres: (f64, f64),
}

fn element_error(e: &Element, reason: impl ToString) -> DiscretizeError {
    DiscretizeError::Element {
        card: e.kind.card(),
        id: e.id,
        reason: reason.to_string(),
    }
}

/// The shells `keep` selects with their recovered state, for the basic displacement rows `u`
/// and the thermal strains `thermal` (forces from the mechanical strains).
fn shell_states<'m>(
    model: &'m Model,
    st: &Structure,
    u: &[f64],
    thermal: &ThermalStrains,
    keep: impl Fn(u32) -> bool,
) -> Result<Vec<(&'m Element, ShellState)>, DiscretizeError> {
    let mut out = Vec::new();
    for shell in selected_shell_strains(model, st, u, &keep) {
        let (e, rec, strains) = shell?;
        let section = shell_centre_section(model, e)?;
        let full = match &section {
            CentreSection::Pshell(p) => ShellSection::pshell(p),
            CentreSection::Laminate(l) => ShellSection::laminate(l),
        }
        .map_err(|x| element_error(e, x))?;
        let forces = shell_forces(&full, &thermal.shell_mechanical(e.id, &strains));
        out.push((
            e,
            ShellState {
                section,
                strains,
                forces,
                fibres: rec.fibres,
            },
        ));
    }
    Ok(out)
}

/// The centroid element forces of the shells `keep` selects (module doc), less the thermal
/// resultants of `thermal`.
pub fn element_forces(
    model: &Model,
    st: &Structure,
    u: &[f64],
    thermal: &ThermalStrains,
    keep: impl Fn(u32) -> bool,
) -> Result<ElementForces, DiscretizeError> {
    let mut out = ElementForces::new();
    for (e, s) in shell_states(model, st, u, thermal, keep)? {
        let block = out.entry(e.kind.block_name()).or_default();
        block.ids.push(e.id);
        block.forces.extend(s.forces.row());
    }
    Ok(out)
}

/// The stresses of the elements `keep` selects (module doc): C (ε − ε_th) with the thermal
/// strains of `thermal`.
pub fn element_stresses(
    model: &Model,
    st: &Structure,
    u: &[f64],
    thermal: &ThermalStrains,
    keep: impl Fn(u32) -> bool,
) -> Result<ElementStresses, DiscretizeError> {
    let mut out = ElementStresses::default();
    let keep = &keep;
    for (e, s) in shell_states(model, st, u, thermal, keep)? {
        match &s.section {
            CentreSection::Pshell(p) => {
                let (z_top, z_bottom) = s.fibres;
                let top = pshell_fibre_stress(p, &s.forces, z_top);
                let bottom = pshell_fibre_stress(p, &s.forces, z_bottom);
                let block = out.fibres.entry(e.kind.block_name()).or_default();
                block.ids.push(e.id);
                block.top.extend(top);
                block.bottom.extend(bottom);
                block
                    .von_mises
                    .extend([von_mises_plane(top), von_mises_plane(bottom)]);
            }
            CentreSection::Laminate(l) => {
                let plies = ply_states(
                    l,
                    s.strains.membrane,
                    s.strains.curvature,
                    s.strains.shear,
                    thermal.plies(e.id),
                )
                .map_err(|x| element_error(e, x))?;
                let property = laminate_property(model, e);
                let block = out.plies.entry(e.kind.block_name()).or_default();
                for (k, p) in plies.iter().enumerate() {
                    block.ids.push(e.id);
                    block.ply.push(k as u32 + 1);
                    block.z.push(p.z);
                    block.stress.extend(p.stress);
                    block.strain.extend(p.strain);
                    block.failure_index.push(
                        property
                            .as_ref()
                            .and_then(|l| ply_failure_index(l, k, &p.stress, &p.strain))
                            .unwrap_or(f64::NAN),
                    );
                }
            }
        }
    }
    for e in model
        .elements
        .iter()
        .filter(|e| e.kind == ElementKind::Cshear)
    {
        if !keep(e.id) {
            continue;
        }
        let (panel, t, _, mid) = shear_panel::panel(model, e)?;
        let g = match model.material(mid) {
            Some(Material::Isotropic(m)) => m.g,
            _ => return Err(element_error(e, format!("MID = {mid} is not a MAT1"))),
        };
        let ut: [f64; 12] = std::array::from_fn(|i| u[6 * e.nodes[i / 3] + i % 3]);
        let tau = g * panel.mean_shear(&ut);
        let block = &mut out.shear_panels;
        block.ids.push(e.id);
        block.shear.push(tau);
        block.shear_flow.push(tau * t);
    }
    for e in &model.elements {
        let Some(midsides) = model.solid_midsides(e) else {
            continue;
        };
        if !keep(e.id) {
            continue;
        }
        let material = solid_material(model, e)?;
        let xyz = model.positions(e);
        let ut: Vec<f64> = e
            .nodes
            .iter()
            .flat_map(|&a| u[6 * a..6 * a + 3].iter().copied())
            .collect();
        let bad = |x: solid::SolidError| element_error(e, x);
        let centroid = solid_stress(
            material,
            &thermal.solid_mechanical(e.id, &midsides.strain_at_centroid(&xyz, &ut).map_err(bad)?),
        );
        let corners = midsides.corner_strains(&xyz, &ut, material).map_err(bad)?;
        let block = out.solids.entry(e.kind.block_name()).or_default();
        block.corners = corners.len();
        block.ids.push(e.id);
        block.centroid.extend(centroid);
        block.von_mises.push(von_mises(&centroid));
        for (&a, strain) in e.nodes.iter().zip(&corners) {
            let s = solid_stress(material, &thermal.solid_mechanical(e.id, strain));
            block.corner_grids.push(st.map.grid_id(a).unwrap_or(0));
            block.corner_stress.extend(s);
            block.corner_von_mises.push(von_mises(&s));
        }
    }
    Ok(out)
}

/// The PCOMP of a shell element, when it has one.
fn laminate_property(model: &Model, e: &Element) -> Option<LaminateProperty> {
    match model.shell_property(e.property?)? {
        ShellProperty::Laminate(l) => Some(l),
        ShellProperty::Plate(_) => None,
    }
}

/// The failure index of ply `k` (0-based, full stack) of `l`, `None` when it has none.
fn ply_failure_index(
    l: &LaminateProperty,
    k: usize,
    stress: &[f64; 5],
    strain: &[f64; 5],
) -> Option<f64> {
    let theory = FailureTheory::from_keyword(l.failure_theory.as_deref()?)?;
    let Some(Material::Orthotropic(m)) = l.plies.get(k)?.material.material else {
        return None;
    };
    failure::failure_index(theory, &m.allowables, stress, strain).ok()
}

/// MAT1 constants of a solid's PSOLID.
fn solid_material(model: &Model, e: &Element) -> Result<solid::Isotropic, DiscretizeError> {
    match e
        .property
        .and_then(|p| model.solid_material(p))
        .and_then(|(_, used)| used.material)
    {
        Some(Material::Isotropic(m)) => Ok(solid::Isotropic { e: m.e, nu: m.nu }),
        _ => Err(element_error(e, "a solid needs a PSOLID with a MAT1")),
    }
}

/// One line per PCOMP whose FT gives no failure index on some ply: an FT paraflex does not
/// evaluate, a MAT1 ply, or MAT8 allowables the theory lacks.
pub fn failure_warnings(model: &Model) -> Vec<String> {
    let mut out = Vec::new();
    let mut seen = std::collections::BTreeSet::new();
    for e in &model.elements {
        let Some(l) = laminate_property(model, e) else {
            continue;
        };
        let Some(ft) = l.failure_theory.as_deref() else {
            continue;
        };
        if !seen.insert(l.id) {
            continue;
        }
        let Some(theory) = FailureTheory::from_keyword(ft) else {
            out.push(format!(
                "PCOMP {}: FT = {ft} is not evaluated (paraflex has HILL, HOFF, TSAI, STRN); its plies have no failure index (NaN)",
                l.id
            ));
            continue;
        };
        let mut problems = BTreeMap::new();
        for p in &l.plies {
            let reason = match p.material.material {
                Some(Material::Orthotropic(m)) => failure::check(theory, &m.allowables)
                    .err()
                    .map(|x| x.to_string()),
                _ => Some("a failure index needs a MAT8 ply".to_string()),
            };
            if let Some(r) = reason {
                problems.entry(p.material.mid).or_insert(r);
            }
        }
        for (mid, reason) in problems {
            out.push(format!(
                "PCOMP {} FT = {ft}: the plies of material {mid} have no failure index (NaN): {reason}",
                l.id
            ));
        }
    }
    out
}
