//! Model → element [`Contribution`]s of K and M: which `fe` kernel each card/property/material
//! combination calls, and with what data.
//!
//! | element | property / material | kernel |
//! |---|---|---|
//! | CQUAD4, CTRIA3 | PSHELL, each of MID1…MID4 MAT1 or MAT8 | [`ShellSection::pshell`]: MID1 membrane, MID2 bending with 12I/T³, MID3 transverse shear with TS/T (MAT1 G, MAT8 G1Z/G2Z), MID4 membrane–bending coupling; MID1 blank = no membrane, MID2 blank = membrane only, MID3 blank = Kirchhoff penalty (see [`PshellSection`]) |
//! | CQUAD4, CTRIA3 | PCOMP (plies MAT8 or MAT1) | [`ShellSection::laminate`] of the full ply stack ([`crate::model::properties::LaminateProperty`]), bottom at Z0 + ZOFFS, NSM |
//! | CSHEAR | PSHEAR + MAT1 | [`crate::fe::shear_panel`]: shear only, translations only (K = G·t·A·b·bᵀ) |
//! | CHEXA, CPENTA, CTETRA | PSOLID + MAT1 | [`solid`] (translations, expanded to 6 DOFs per grid) |
//! | CELAS1–CELAS4 | PELAS k (CELAS1, CELAS3) / k on the card (CELAS2, CELAS4) | [`ScalarSpring`] between g DOFs: grid components in the grid's CD frame (as in Nastran) or scalar points |
//! | CBUSH | PBUSH K1–K6, B1–B6 | [`bush`]: six springs (and dampers) along and about the element axes at the spring location |
//! | CDAMP1–CDAMP4 | PDAMP / B on the card | damping only: [`ScalarSpring`] with b ([`damper_element`]) |
//! | CMASS2 | M on the card | mass only: [`ScalarSpring`]'s matrix with M ([`scalar_mass_element`]) |
//! | CVISC | PVISC CE, CR | damping only: axial CE and torsional CR along G1→G2 ([`rod_damping`]) |
//! | CONM2 | — | [`Conm2`] with the CG offset and inertia tensor from [`Model::element_mass`] |
//! | CROD, CTUBE, CONROD | PROD, PTUBE / on the card + MAT1 | [`beam`] without bending (axial, torsion) |
//! | CBAR, CBEAM | PBAR, PBARL / PBEAM, PBEAML + MAT1 | [`beam`]: offsets, orientation vector, pin flags ([`Model::line_element`]) |
//! | CBEND | PBEND + MAT1 | [`bend`]: the arc of GEOM 1–4, force-method stiffness, lumped mass ([`Model::bend_element`]) |
//!
//! Shell details:
//! - material x axis: THETA rotates the projected G1→G2 direction by θ about the element normal
//!   (n = (x₃−x₁)×(x₄−x₂) for quads, (x₂−x₁)×(x₃−x₁) for triangles); MCID takes the x axis of that
//!   system at the element centroid, projected on the element plane by the kernel;
//! - ZOFFS moves the reference plane: PSHELL mid-surface at ZOFFS, PCOMP bottom at Z0 + ZOFFS;
//! - corner thicknesses (T1…T4, TFLAG): the stiffness takes the PSHELL section at each
//!   integration point with the thickness interpolated there from the corners (bilinear on quads,
//!   linear on triangles; [`shell::integration_point_thickness`]), so D ∝ t³ of a linearly
//!   tapered edge is integrated exactly by the 2-point Gauss rule; the mass and the strain fibres
//!   use the mean corner thickness (= the interpolated thickness at the centroid; exact for the
//!   mass of a parallelogram with bilinear thickness); refused for PCOMP, whose thickness is the
//!   ply stack;
//! - PSHELL: ZOFFS needs MID1 and MID2 (Nastran); a role combination Nastran forbids (MID3
//!   without MID2, MID4 without MID1 and MID2) is an error of the section.
//!
//! Damping: the viscous dampers and PBUSH B give the viscous damping matrix B
//! ([`ElementMatrices::damping`], constant: no PMPAR acts on PDAMP, PVISC or PBUSH); an element
//! with structural damping GE ([`Model::element_ge`]; CBUSH per direction) gives GE·K_e, K_e's
//! affine parts scaled ([`ElementMatrices::structural`]).
//!
//! Mass: `PARAM,COUPMASS` = 1 gives consistent shell, solid, rod and beam masses, anything else
//! (default −1) lumped, as in Nastran; `PARAM,WTMASS` multiplies every mass matrix, CONM2 included.
//!
//! CQUAD4 membrane: `PARAM,QINCOMP,YES` (default) condenses its incompatible modes with the
//! deck's section, `NO` leaves them out ([`shell::Incompatible`]). With YES, a quad whose
//! stiffness parts change its section by more than a scale (NU, THETA, TPLY of a laminate with
//! membrane–bending coupling; [`shell::condensation_is_frozen`]) has its condensation frozen at
//! the deck's values; [`ElementMatrices::frozen_condensation`] lists those parameters' entities.
//!
//! Affine parts (DESIGN.md §5, thesis eq. 3.12–3.28): every kernel is called through its affine
//! entry point. When PMPARs act on the element's material, PCOMP, PELAS or CONM2, the kernel
//! splits by them (sections: [`shell_parts`]; solids: E, Lamé, ρ parts) and [`bind`] ties each
//! non-constant coefficient to that entity ([`ParamTarget`]); otherwise everything is frozen at
//! the card values into the constant part. [`Parameters`] turns each (entity, coefficient) part
//! into its function f_i(p).

pub(crate) mod shear_panel;

use std::sync::atomic::{AtomicUsize, Ordering};

use rayon::prelude::*;

use super::DiscretizeError;
use super::parameters::Parameters;
use crate::assembly::assemble::Binding;
use crate::assembly::{Contribution, DofMap, GridFrames, ParamKey, ParamTarget};
use crate::card_values::{CornerThickness, PmparKind, ShellOrientation};
use crate::fe::affine::{AffineMatrix, Coefficient, CoefficientValues};
use crate::fe::laminate::{
    Laminate, Ply, PshellSection, RoleMaterial, SectionData, SectionError, SectionParameter,
    ShellMaterial, ShellSection, affine_sections,
};
use crate::fe::lumped::{Conm2, ScalarSpring};
use crate::fe::{beam, bend, shell, shell_quadratic, solid};
use crate::geometry::vec3::{normalize, sub};
use crate::linalg::Progress;
use crate::model::damping::Damper;
use crate::model::materials::{IsotropicMaterial, Material};
use crate::model::properties::{
    MaterialUse, ShellPlacement, ShellProperty, Spring, SpringStiffness,
};
use crate::model::{Element, ElementKind, Model, PropertyRef};

/// Element matrices of a model, ready for assembly, plus what strain recovery needs.
#[derive(Debug, Clone, Default)]
pub struct ElementMatrices {
    /// Stiffness contributions (global frames).
    pub stiffness: Vec<Contribution>,
    /// Mass contributions (global frames, WTMASS applied).
    pub mass: Vec<Contribution>,
    /// Viscous damping contributions B (global frames): dampers and PBUSH B.
    pub damping: Vec<Contribution>,
    /// Structural damping contributions GE·K_e (global frames): the imaginary stiffness.
    pub structural: Vec<Contribution>,
    /// Recovery data of each shell, by index into `model.elements`.
    pub shells: Vec<(usize, ShellRecovery)>,
    /// The entities whose parameters change the section of a CQUAD4 whose incompatible modes are
    /// condensed with the deck's section (PARAM,QINCOMP,YES) by more than a scale, so that the
    /// condensation is frozen ([`shell::condensation_is_frozen`]), sorted, without repeats.
    pub frozen_condensation: Vec<ParamTarget>,
}

/// What a shell's strain recovery needs besides geometry and displacements.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShellRecovery {
    /// Material x direction (basic), `None` = G1→G2.
    pub material_x: Option<[f64; 3]>,
    /// (z_top, z_bottom) of the reported fibres, from the grid plane.
    pub fibres: (f64, f64),
}

/// What one element contributes.
#[derive(Default)]
struct Built {
    k: Option<Contribution>,
    m: Option<Contribution>,
    /// Viscous damping.
    b: Option<Contribution>,
    /// Structural damping GE·K (set by the element only when GE is not one scale of K).
    k4: Option<Contribution>,
    shell: Option<ShellRecovery>,
    /// The entity of a frozen condensation ([`ElementMatrices::frozen_condensation`]).
    frozen: Option<ParamTarget>,
}

/// What every element's wiring needs.
struct ElementContext<'a> {
    model: &'a Model,
    /// The g-set numbering (scalar elements place their DOFs directly).
    map: DofMap,
    frames: &'a GridFrames,
    params: &'a Parameters,
    /// Lumped mass (PARAM,COUPMASS ≠ 1).
    lumped: bool,
    /// CQUAD4 incompatible modes (PARAM,QINCOMP).
    incompatible: bool,
}

impl<'a> ElementContext<'a> {
    /// The context of `model`'s elements: its numbering and its mass and membrane options.
    fn new(model: &'a Model, frames: &'a GridFrames, params: &'a Parameters) -> Self {
        ElementContext {
            model,
            map: DofMap::of_model(model),
            frames,
            params,
            lumped: model.params.coupmass != 1,
            incompatible: model.params.qincomp,
        }
    }
}

/// Element matrices of every element of `model` (in parallel when `parallel`), with their
/// coefficients bound to the entities `params` act on.
pub fn element_matrices(
    model: &Model,
    frames: &GridFrames,
    params: &Parameters,
    parallel: bool,
    progress: &dyn Progress,
) -> Result<ElementMatrices, DiscretizeError> {
    let total = model.elements.len();
    let done = AtomicUsize::new(0);
    let step = (total / 100).max(1);
    let ctx = ElementContext::new(model, frames, params);
    let one = |e: &Element| {
        let r = element(&ctx, e);
        let d = done.fetch_add(1, Ordering::Relaxed) + 1;
        if d.is_multiple_of(step) || d == total {
            progress.step("element matrices", d, total);
        }
        r
    };
    let built: Vec<Built> = if parallel {
        model
            .elements
            .par_iter()
            .map(one)
            .collect::<Result<_, _>>()?
    } else {
        model.elements.iter().map(one).collect::<Result<_, _>>()?
    };
    let mut out = ElementMatrices::default();
    for (i, b) in built.into_iter().enumerate() {
        out.stiffness.extend(b.k);
        out.mass.extend(b.m);
        out.damping.extend(b.b);
        out.structural.extend(b.k4);
        if let Some(s) = b.shell {
            out.shells.push((i, s));
        }
        out.frozen_condensation.extend(b.frozen);
    }
    out.frozen_condensation.sort_unstable();
    out.frozen_condensation.dedup();
    Ok(out)
}

/// The stiffness contribution (global frames, coefficients bound as in [`element_matrices`])
/// of every element `keep` selects that has one, with its element: what each adds to K(p).
pub(crate) fn element_stiffnesses<'m>(
    model: &'m Model,
    frames: &GridFrames,
    params: &Parameters,
    keep: impl Fn(&Element) -> bool,
) -> Result<Vec<(&'m Element, Contribution)>, DiscretizeError> {
    let ctx = ElementContext::new(model, frames, params);
    let mut out = Vec::new();
    for e in model.elements.iter().filter(|e| keep(e)) {
        if let Some(k) = element(&ctx, e)?.k {
            out.push((e, k));
        }
    }
    Ok(out)
}

/// The binding of an element's coefficients: to `target` when PMPARs act on it, otherwise
/// frozen at `nominal` (the element's card values) and folded into the constant part.
fn bind(
    target: Option<ParamTarget>,
    nominal: CoefficientValues,
) -> impl Fn(Coefficient) -> Binding {
    move |c| match target {
        Some(t) => Binding::Param(t),
        None => Binding::Fixed(c.value(&nominal)),
    }
}

/// `target` if PMPARs act on it.
fn acted_on(params: &Parameters, target: ParamTarget) -> Option<ParamTarget> {
    params.acts_on(target).then_some(target)
}

fn err(e: &Element, reason: impl ToString) -> DiscretizeError {
    DiscretizeError::Element {
        card: e.kind.card(),
        id: e.id,
        reason: reason.to_string(),
    }
}

fn element(ctx: &ElementContext, e: &Element) -> Result<Built, DiscretizeError> {
    let wtmass = ctx.model.params.wtmass;
    let xyz = ctx.model.positions(e);
    let mut built = match e.kind {
        ElementKind::Quad4
        | ElementKind::Tria3
        | ElementKind::QuadR
        | ElementKind::TriaR
        | ElementKind::Quad8
        | ElementKind::Tria6 => shell_element(ctx, e, &xyz)?,
        ElementKind::Cshear => shear_panel::shear_panel_element(ctx, e)?,
        ElementKind::Hexa8
        | ElementKind::Penta6
        | ElementKind::Tetra4
        | ElementKind::Tetra10
        | ElementKind::Hexa20
        | ElementKind::Penta15
        | ElementKind::Pyram5 => solid_element(ctx, e, &xyz)?,
        ElementKind::Celas1 | ElementKind::Celas2 | ElementKind::Celas3 | ElementKind::Celas4 => {
            spring_element(ctx, e)?
        }
        ElementKind::Cdamp1
        | ElementKind::Cdamp2
        | ElementKind::Cdamp3
        | ElementKind::Cdamp4
        | ElementKind::Cvisc => damper_element(ctx, e)?,
        ElementKind::Cbush => bush_element(ctx, e)?,
        ElementKind::Cmass2 => scalar_mass_element(ctx, e)?,
        ElementKind::Conm2 => conm2_element(ctx, e)?,
        ElementKind::Crod
        | ElementKind::Conrod
        | ElementKind::Ctube
        | ElementKind::Cbar
        | ElementKind::Cbeam => line_element(ctx, e)?,
        ElementKind::Cbend => bend_element(ctx, e)?,
    };
    if let Some(m) = built.m.as_mut()
        && wtmass != 1.0
    {
        for (_, part) in m.parts.iter_mut() {
            *part = &*part * faer::Scale(wtmass);
        }
    }
    let ge = ctx.model.element_ge(e);
    if built.k4.is_none()
        && ge != 0.0
        && let Some(k) = &built.k
    {
        let mut k4 = k.clone();
        for (_, part) in k4.parts.iter_mut() {
            *part = &*part * faer::Scale(ge);
        }
        built.k4 = Some(k4);
    }
    Ok(built)
}

/// Corner thicknesses of a PSHELL element with T1…T4 (TFLAG = 1: ratios of T, 0: values,
/// blank corner: T), `None` without them.
fn corner_thicknesses(t: f64, corners: Option<&CornerThickness>, n: usize) -> Option<Vec<f64>> {
    corners.map(|c| {
        c.t.iter()
            .take(n)
            .map(|ti| match (ti, c.relative) {
                (Some(r), true) => r * t,
                (Some(v), false) => *v,
                (None, _) => t,
            })
            .collect()
    })
}

/// A ply of a material (a MAT1 is a ply with E1 = E2 = E, G12 = G1Z = G2Z = G); a MAT2
/// has no ply constants (Nastran's PCOMP reads MAT2 plies, paraflex does not).
fn ply_of(material: Material, t: f64, theta_deg: f64) -> Result<Ply, String> {
    Ok(match material {
        Material::Anisotropic(_) => {
            return Err("a PCOMP ply needs a MAT8 or MAT1; MAT2 plies are not supported".into());
        }
        Material::Orthotropic(m) => Ply {
            e1: m.e1,
            e2: m.e2,
            nu12: m.nu12,
            g12: m.g12,
            g1z: m.g1z,
            g2z: m.g2z,
            rho: m.rho,
            t,
            theta_deg,
        },
        Material::Isotropic(m) => Ply {
            e1: m.e,
            e2: m.e,
            nu12: m.nu,
            g12: m.g,
            g1z: Some(m.g),
            g2z: Some(m.g),
            rho: m.rho,
            t,
            theta_deg,
        },
    })
}

/// A MAT1 / MAT8 / MAT2 as the material of a PSHELL role.
fn shell_material(mid: u32, material: Material) -> RoleMaterial {
    match material {
        Material::Isotropic(m) => RoleMaterial {
            mid,
            material: ShellMaterial::Isotropic { e: m.e, nu: m.nu },
            rho: m.rho,
        },
        Material::Orthotropic(m) => RoleMaterial {
            mid,
            material: ShellMaterial::Orthotropic {
                e1: m.e1,
                e2: m.e2,
                nu12: m.nu12,
                g12: m.g12,
                g1z: m.g1z,
                g2z: m.g2z,
            },
            rho: m.rho,
        },
        Material::Anisotropic(m) => RoleMaterial {
            mid,
            material: ShellMaterial::Anisotropic { g: m.g },
            rho: m.rho,
        },
    }
}

/// The data of a shell section, before any affine split. One value per property while the
/// sections are built, so the size difference between the variants costs nothing.
#[allow(clippy::large_enum_variant)]
enum SectionInput {
    Pshell {
        pid: u32,
        section: PshellSection,
    },
    Laminate {
        pid: u32,
        laminate: Laminate,
        plies: Vec<u32>,
        explicit_offset: bool,
    },
}

impl SectionInput {
    fn full(&self) -> Result<ShellSection, SectionError> {
        match self {
            SectionInput::Pshell { section, .. } => ShellSection::pshell(section),
            SectionInput::Laminate { laminate, .. } => ShellSection::laminate(laminate),
        }
    }
}

/// The sections of a shell: at the centroid (mass, strain fibres), and per stiffness
/// integration point when the thickness varies over the element (corner thicknesses).
struct ShellSections {
    centre: SectionInput,
    points: Option<Vec<SectionInput>>,
    /// Strain fibres (top, bottom) from the reference plane.
    fibres: (f64, f64),
}

/// The sections of a shell and the fibres its strains are reported at.
fn shell_section(
    model: &Model,
    e: &Element,
    card: &ShellPlacement,
) -> Result<ShellSections, DiscretizeError> {
    // corner grids: the quadratic shells' corner thicknesses are those of their corners
    let quadratic = model.quadratic_layout(e).map(|l| l.shape);
    let n = match quadratic {
        Some(shell_quadratic::Quadratic::Quad8) => 4,
        Some(shell_quadratic::Quadratic::Tria6) => 3,
        None => e.nodes.len(),
    };
    let zoffs = card.zoffs;
    match e.property {
        Some(property @ PropertyRef::Pshell(_)) => {
            let Some(ShellProperty::Plate(p)) = model.shell_property(property) else {
                return Err(err(e, format!("PSHELL {} missing", card.pid)));
            };
            let role = |used: Option<MaterialUse>| {
                used.map(|u| {
                    u.material.map(|m| shell_material(u.mid, m)).ok_or_else(|| {
                        err(e, format!("PSHELL {}: material {} missing", p.id, u.mid))
                    })
                })
                .transpose()
            };
            let corners = corner_thicknesses(p.t, card.corners.as_ref(), n);
            let t = corners
                .as_ref()
                .map_or(p.t, |c| c.iter().sum::<f64>() / n as f64);
            let scale = t / p.t;
            let fibres = (zoffs + p.z2 * scale, zoffs + p.z1 * scale);
            let section = PshellSection {
                t,
                membrane: role(p.membrane)?,
                bending: role(p.bending)?,
                bending_ratio: p.bending_ratio,
                shear: role(p.shear)?,
                shear_ratio: p.shear_ratio,
                coupling: role(p.coupling)?,
                nsm: p.nsm,
                zoffs,
            };
            let points = match corners {
                None => None,
                Some(c) => {
                    let at = match quadratic {
                        Some(q) => shell_quadratic::integration_point_thickness(q, &c),
                        None => shell::integration_point_thickness(&c),
                    }
                    .map_err(|x| err(e, x))?;
                    Some(
                        at.into_iter()
                            .map(|t| SectionInput::Pshell {
                                pid: p.id,
                                section: PshellSection { t, ..section },
                            })
                            .collect(),
                    )
                }
            };
            Ok(ShellSections {
                centre: SectionInput::Pshell { pid: p.id, section },
                points,
                fibres,
            })
        }
        Some(property @ PropertyRef::Pcomp(_)) => {
            let Some(ShellProperty::Laminate(p)) = model.shell_property(property) else {
                return Err(err(e, format!("PCOMP {} missing", card.pid)));
            };
            if card.corners.is_some() {
                return Err(err(
                    e,
                    format!(
                        "corner thicknesses with PCOMP {} are not supported (the thickness is the ply stack); remove T1–T4",
                        p.id
                    ),
                ));
            }
            let plies = p
                .plies
                .iter()
                .map(|ply| {
                    let m = ply.material.material.ok_or_else(|| {
                        err(
                            e,
                            format!("PCOMP {}: material {} missing", p.id, ply.material.mid),
                        )
                    })?;
                    ply_of(m, ply.t, ply.theta_deg).map_err(|x| {
                        err(e, format!("PCOMP {}: MID {}: {x}", p.id, ply.material.mid))
                    })
                })
                .collect::<Result<Vec<_>, _>>()?;
            let bottom = p.z0 + zoffs;
            let laminate = Laminate {
                plies,
                z0: Some(bottom),
                nsm: p.nsm,
                symmetric: false,
            };
            let explicit_offset = p.z0_given || zoffs != 0.0;
            let centre = SectionInput::Laminate {
                pid: p.id,
                laminate,
                plies: p.plies.iter().map(|ply| ply.material.mid).collect(),
                explicit_offset,
            };
            Ok(ShellSections {
                centre,
                points: None,
                fibres: (bottom + p.thickness, bottom),
            })
        }
        other => Err(err(
            e,
            format!(
                "property {} is not a shell property",
                other.map_or("(none)", |p| p.card())
            ),
        )),
    }
}

/// Affine section parts of a shell for stiffness and for mass, and the entity their
/// non-constant coefficients bind to (DESIGN.md §5, [`affine_sections`]).
///
/// | section | PMPARs | stiffness split | mass split |
/// |---|---|---|---|
/// | PSHELL | E / NU (± E) on one MAT1 of its roles | `E` / `Nu` on that material | — |
/// | PSHELL | RHO on the mass material | — | `Rho` |
/// | PCOMP | THETA | `Theta` | `Theta` (mass constant) |
/// | PCOMP | TPLY | `Tply` | `Tply` |
/// | PCOMP | RHO on the MAT1 of every ply | — | `Rho` |
///
/// Refused, with the reason: PMPARs on two materials of one PSHELL; THETA with TPLY (no
/// affine form, thesis §3.3); RHO with TPLY (ρ·h); TPLY with an explicit Z0 or ZOFFS (the split
/// scales every length with h); E or NU on ply materials.
fn shell_parts(input: &SectionInput, params: &Parameters) -> Result<ShellParts, String> {
    let constant = |s: &SectionInput| -> Result<Vec<(Coefficient, ShellSection)>, String> {
        Ok(vec![(
            Coefficient::Constant,
            s.full().map_err(|x| x.to_string())?,
        )])
    };
    let split =
        |data: &SectionData, parameter| affine_sections(data, parameter).map_err(|x| x.to_string());
    match input {
        SectionInput::Pshell { pid, section } => {
            let roles = [
                section.membrane,
                section.bending,
                section.shear,
                section.coupling,
            ];
            let mut mids: Vec<u32> = roles
                .iter()
                .flatten()
                .map(|r| r.mid)
                .filter(|&m| params.acts_on(ParamTarget::Material(m)))
                .collect();
            mids.sort_unstable();
            mids.dedup();
            match mids.as_slice() {
                [] => Ok(ShellParts {
                    stiffness: constant(input)?,
                    mass: constant(input)?,
                    stiffness_target: None,
                    mass_target: None,
                }),
                [mid] => {
                    let target = ParamTarget::Material(*mid);
                    let kinds = params.kinds_on(target);
                    let data = SectionData::Pshell {
                        section: *section,
                        parametrized: *mid,
                    };
                    let stiffness = if kinds.contains(&PmparKind::Nu) {
                        split(&data, SectionParameter::Nu)?
                    } else if kinds.contains(&PmparKind::E) {
                        split(&data, SectionParameter::E)?
                    } else {
                        constant(input)?
                    };
                    let mass = if kinds.contains(&PmparKind::Rho) {
                        split(&data, SectionParameter::Rho)?
                    } else {
                        constant(input)?
                    };
                    Ok(ShellParts {
                        stiffness,
                        mass,
                        stiffness_target: Some(target),
                        mass_target: Some(target),
                    })
                }
                several => Err(format!(
                    "PMPARs act on materials {several:?} of PSHELL {pid}; one parametrized material per PSHELL is supported"
                )),
            }
        }
        SectionInput::Laminate {
            pid,
            laminate,
            plies,
            explicit_offset,
        } => {
            let own = ParamTarget::Pcomp(*pid);
            let kinds = params.kinds_on(own);
            let (theta, tply) = (
                kinds.contains(&PmparKind::Theta),
                kinds.contains(&PmparKind::Tply),
            );
            let mut ply_mids: Vec<u32> = plies
                .iter()
                .copied()
                .filter(|&m| params.acts_on(ParamTarget::Material(m)))
                .collect();
            ply_mids.sort_unstable();
            ply_mids.dedup();
            let rho_on_plies = match ply_mids.as_slice() {
                [] => None,
                [mid] => {
                    let ply_kinds = params.kinds_on(ParamTarget::Material(*mid));
                    if ply_kinds
                        .iter()
                        .any(|k| matches!(k, PmparKind::E | PmparKind::Nu))
                    {
                        return Err(format!(
                            "PMPAR E / NU on MAT1 {mid}, a ply material of PCOMP {pid}: laminates take THETA, TPLY and RHO only"
                        ));
                    }
                    if plies.iter().any(|m| m != mid) {
                        return Err(format!(
                            "PMPAR RHO on MAT1 {mid}: every ply of PCOMP {pid} must use that material"
                        ));
                    }
                    Some(*mid)
                }
                several => {
                    return Err(format!(
                        "PMPARs act on ply materials {several:?} of PCOMP {pid}; at most one"
                    ));
                }
            };
            if theta && tply {
                return Err(format!(
                    "PCOMP {pid} has both THETA and TPLY parameters: their product has no affine form (thesis §3.3.5); use one"
                ));
            }
            if tply && rho_on_plies.is_some() {
                return Err(format!(
                    "PCOMP {pid}: TPLY with RHO on its plies makes the mass ∝ ρ·h, which is not affine; use one"
                ));
            }
            if tply && *explicit_offset {
                return Err(format!(
                    "PCOMP {pid}: TPLY needs the default Z0 (−total/2) and no ZOFFS, because the split scales every length with the ply thickness"
                ));
            }
            let data = SectionData::Laminate(laminate.clone());
            let stiffness_target = (theta || tply).then_some(own);
            let stiffness = match (theta, tply) {
                (true, _) => split(&data, SectionParameter::Theta)?,
                (_, true) => split(&data, SectionParameter::Tply)?,
                _ => constant(input)?,
            };
            let (mass, mass_target) = match (rho_on_plies, tply) {
                (Some(mid), _) => (
                    split(&data, SectionParameter::Rho)?,
                    Some(ParamTarget::Material(mid)),
                ),
                (None, true) => (split(&data, SectionParameter::Tply)?, Some(own)),
                // THETA leaves the mass constant
                (None, false) => (constant(input)?, None),
            };
            Ok(ShellParts {
                stiffness,
                mass,
                stiffness_target,
                mass_target,
            })
        }
    }
}

/// The PMPAR kinds that act on a shell's stiffness section (the others act on its mass).
pub const SECTION_STIFFNESS: [PmparKind; 4] = [
    PmparKind::E,
    PmparKind::Nu,
    PmparKind::Theta,
    PmparKind::Tply,
];

/// The split parts of one shell section and the entities their coefficients bind to.
struct ShellParts {
    stiffness: Vec<(Coefficient, ShellSection)>,
    mass: Vec<(Coefficient, ShellSection)>,
    stiffness_target: Option<ParamTarget>,
    mass_target: Option<ParamTarget>,
}

/// Material x axis of a shell (module doc); `None` = the kernel's default G1→G2.
fn material_axis(
    model: &Model,
    e: &Element,
    xyz: &[[f64; 3]],
    orientation: ShellOrientation,
) -> Result<Option<[f64; 3]>, DiscretizeError> {
    use crate::geometry::vec3::{cross, dot, normalize, scale, sub};
    match orientation {
        ShellOrientation::Theta(0.0) => Ok(None),
        ShellOrientation::Theta(theta) => {
            let n = if matches!(
                e.kind,
                ElementKind::Quad4 | ElementKind::QuadR | ElementKind::Quad8
            ) {
                cross(sub(xyz[2], xyz[0]), sub(xyz[3], xyz[1]))
            } else {
                cross(sub(xyz[1], xyz[0]), sub(xyz[2], xyz[0]))
            };
            let n = normalize(n).ok_or_else(|| err(e, "zero area"))?;
            let g12 = sub(xyz[1], xyz[0]);
            let d = dot(g12, n);
            let x = normalize(sub(g12, scale(n, d)))
                .ok_or_else(|| err(e, "G1→G2 is normal to the element"))?;
            let y = cross(n, x);
            let (s, c) = theta.to_radians().sin_cos();
            Ok(Some(std::array::from_fn(|i| c * x[i] + s * y[i])))
        }
        ShellOrientation::Mcid(cid) => {
            let cs = model
                .coords
                .get(&cid)
                .ok_or_else(|| err(e, format!("MCID = {cid} does not exist")))?;
            let k = xyz.len() as f64;
            let centroid: [f64; 3] =
                std::array::from_fn(|i| xyz.iter().map(|p| p[i]).sum::<f64>() / k);
            let axes = cs.axes_at(centroid);
            Ok(Some([axes[0][0], axes[1][0], axes[2][0]]))
        }
    }
}

fn shell_element(
    ctx: &ElementContext,
    e: &Element,
    xyz: &[[f64; 3]],
) -> Result<Built, DiscretizeError> {
    let model = ctx.model;
    let card = model
        .shell_placement(e)
        .ok_or_else(|| err(e, "card missing"))?;
    let ShellSections {
        centre,
        points,
        fibres,
    } = shell_section(model, e, &card)?;
    let material_x = material_axis(model, e, xyz, card.orientation)?;
    let parts = shell_parts(&centre, ctx.params).map_err(|x| err(e, x))?;
    if let Some(layout) = model.quadratic_layout(e) {
        return quadratic_shell(
            ctx,
            e,
            (layout, xyz),
            parts,
            points,
            ShellRecovery { material_x, fibres },
        );
    }
    // The deck's section(s), i.e. the parts at the nominal parameter values: the CQUAD4
    // condenses its incompatible modes with them (shell module doc, "frozen condensation"),
    // unless PARAM,QINCOMP,NO leaves the modes out.
    let incompatible = ctx.incompatible && e.nodes.len() == 4;
    let (k, condensation_frozen) = match points {
        None => {
            let nominal = if incompatible {
                Some(centre.full().map_err(|x| err(e, x))?)
            } else {
                None
            };
            let frozen = nominal
                .as_ref()
                .is_some_and(|n| shell::condensation_is_frozen(&parts.stiffness, n));
            (
                shell::affine_stiffness(
                    xyz,
                    &parts.stiffness,
                    nominal
                        .as_ref()
                        .map_or(shell::Incompatible::Off, shell::Incompatible::Condensed),
                    material_x,
                ),
                frozen,
            )
        }
        Some(points) => {
            let at = points
                .iter()
                .map(|s| shell_parts(s, ctx.params).map(|p| p.stiffness))
                .collect::<Result<Vec<_>, _>>()
                .map_err(|x| err(e, x))?;
            let nominal = if incompatible {
                Some(
                    points
                        .iter()
                        .map(SectionInput::full)
                        .collect::<Result<Vec<_>, _>>()
                        .map_err(|x| err(e, x))?,
                )
            } else {
                None
            };
            let frozen = nominal.as_ref().is_some_and(|n| {
                at.iter()
                    .zip(n)
                    .any(|(parts, n)| shell::condensation_is_frozen(parts, n))
            });
            (
                shell::affine_stiffness_at_points(
                    xyz,
                    &at,
                    nominal
                        .as_deref()
                        .map_or(shell::Incompatible::Off, shell::Incompatible::Condensed),
                    material_x,
                ),
                frozen,
            )
        }
    };
    let k = k.map_err(|x| err(e, x))?;
    let m = shell::affine_mass(xyz, &parts.mass, ctx.lumped).map_err(|x| err(e, x))?;
    Ok(Built {
        frozen: parts.stiffness_target.filter(|_| condensation_frozen),
        ..shell_built(
            ctx,
            e,
            (&k, &m),
            &parts,
            ShellRecovery { material_x, fibres },
        )
    })
}

/// A shell's [`Built`] from its affine stiffness and mass parts. Split sections carry
/// unit-parameter parts: only bound coefficients appear besides the constant one, so frozen
/// values are never needed here.
fn shell_built(
    ctx: &ElementContext,
    e: &Element,
    (k, m): (&AffineMatrix, &AffineMatrix),
    parts: &ShellParts,
    recovery: ShellRecovery,
) -> Built {
    let frozen = CoefficientValues::default();
    Built {
        k: nonempty(k).then(|| {
            Contribution::from_affine(
                ctx.frames,
                &e.nodes,
                k,
                bind(parts.stiffness_target, frozen),
            )
        }),
        m: nonempty(m).then(|| {
            Contribution::from_affine(ctx.frames, &e.nodes, m, bind(parts.mass_target, frozen))
        }),
        shell: Some(recovery),
        ..Built::default()
    }
}

/// A CQUAD8 / CTRIA6 ([`shell_quadratic`]): the section parts as for the CQUAD4, nothing
/// condensed, so nothing is frozen.
fn quadratic_shell(
    ctx: &ElementContext,
    e: &Element,
    (layout, xyz): (shell_quadratic::Layout, &[[f64; 3]]),
    parts: ShellParts,
    points: Option<Vec<SectionInput>>,
    recovery: ShellRecovery,
) -> Result<Built, DiscretizeError> {
    let k = match points {
        None => {
            shell_quadratic::affine_stiffness(layout, xyz, &parts.stiffness, recovery.material_x)
        }
        Some(points) => {
            let at = points
                .iter()
                .map(|s| shell_parts(s, ctx.params).map(|p| p.stiffness))
                .collect::<Result<Vec<_>, _>>()
                .map_err(|x| err(e, x))?;
            shell_quadratic::affine_stiffness_at_points(layout, xyz, &at, recovery.material_x)
        }
    }
    .map_err(|x| err(e, x))?;
    let m = shell_quadratic::affine_mass(layout, xyz, &parts.mass, ctx.lumped)
        .map_err(|x| err(e, x))?;
    Ok(shell_built(ctx, e, (&k, &m), &parts, recovery))
}

fn nonempty(a: &AffineMatrix) -> bool {
    !a.parts.is_empty()
}

/// A solid's stiffness and mass, split by the PMPARs on its MAT1: E → one E part at fixed ν;
/// NU (± E) → Lamé parts (refused for CHEXA by the kernel: its condensed incompatible modes
/// are not affine in ν); RHO → one ρ part.
fn solid_element(
    ctx: &ElementContext,
    e: &Element,
    xyz: &[[f64; 3]],
) -> Result<Built, DiscretizeError> {
    let model = ctx.model;
    let midsides = model
        .solid_midsides(e)
        .ok_or_else(|| err(e, "not a solid"))?;
    let Some((property, used)) = e.property.and_then(|p| model.solid_material(p)) else {
        return Err(err(e, "a solid needs a PSOLID"));
    };
    let m = match used.material {
        Some(Material::Isotropic(m)) => m,
        Some(other) => {
            return Err(err(
                e,
                format!(
                    "{property}: {} {} is a shell material; solids need MAT1",
                    other.card(),
                    used.mid
                ),
            ));
        }
        None => {
            return Err(err(e, format!("{property}: material {} missing", used.mid)));
        }
    };
    let target = ParamTarget::Material(used.mid);
    let kinds = ctx.params.kinds_on(target);
    let stiffness_split = if kinds.contains(&PmparKind::Nu) {
        solid::StiffnessParametrization::Lame
    } else if kinds.contains(&PmparKind::E) {
        solid::StiffnessParametrization::YoungsModulus { nu: m.nu }
    } else {
        solid::StiffnessParametrization::Fixed(solid::Isotropic { e: m.e, nu: m.nu })
    };
    let mass_split = if kinds.contains(&PmparKind::Rho) {
        solid::MassParametrization::Density
    } else {
        solid::MassParametrization::Fixed { rho: m.rho }
    };
    let k = midsides
        .affine_stiffness(xyz, stiffness_split)
        .map_err(|x| err(e, x))?;
    let lumping = if ctx.lumped {
        solid::MassLumping::Lumped
    } else {
        solid::MassLumping::Consistent
    };
    let mass = midsides
        .affine_mass(xyz, lumping, mass_split)
        .map_err(|x| err(e, x))?;
    // 3·n translational matrices: the contributions carry T1–T3 of each grid only
    Ok(isotropic_built(
        ctx,
        e,
        target,
        &m,
        (&k, &mass),
        m.rho != 0.0,
    ))
}

/// A rod or beam ([`beam`]): its stiffness and mass, split by the PMPARs on its MAT1 (E: one
/// part ∝ E at the card's G/E; NU (± E): axial and bending ∝ E, torsion ∝ μ = E/(2(1+ν)), which
/// needs the card's G to be E/(2(1+ν)) and no shear flexibility; RHO: ρ part plus a constant
/// NSM part). Pin flags are released by static condensation.
fn line_element(ctx: &ElementContext, e: &Element) -> Result<Built, DiscretizeError> {
    let (line, used) = ctx
        .model
        .line_element(e)
        .ok_or_else(|| err(e, "not a line element"))?
        .map_err(|x| err(e, x))?;
    let (m, target, elasticity, density) = line_material(ctx, e, &used)?;
    let s = line.section;
    let section = beam::LineSection {
        a: s.a,
        i1: s.i1,
        i2: s.i2,
        i12: s.i12,
        j: s.j,
        k1: s.k1,
        k2: s.k2,
        nsm: s.nsm,
        neutral_axis: s.neutral_axis,
    };
    let releases = line
        .pins
        .map(|p| std::array::from_fn(|c| p.contains(c + 1)));
    let geometry = line.geometry();
    let k = beam::affine_stiffness(&geometry, &section, elasticity, &releases, (m.e, m.g))
        .map_err(|x| err(e, x))?;
    let form = if ctx.lumped {
        beam::MassForm::Lumped {
            torsion: e.kind == ElementKind::Cbeam,
        }
    } else {
        beam::MassForm::Coupled
    };
    let mass = beam::affine_mass(&geometry, &section, density, form).map_err(|x| err(e, x))?;
    let has_mass = m.rho * s.a + s.nsm != 0.0;
    Ok(isotropic_built(ctx, e, target, &m, (&k, &mass), has_mass))
}

/// The MAT1 of a rod, beam or curved beam and how its matrices split by the PMPARs on it (see
/// [`line_element`]).
fn line_material(
    ctx: &ElementContext,
    e: &Element,
    used: &MaterialUse,
) -> Result<
    (
        IsotropicMaterial,
        ParamTarget,
        beam::Elasticity,
        beam::Density,
    ),
    DiscretizeError,
> {
    let m = match used.material {
        Some(Material::Isotropic(m)) => m,
        Some(other) => {
            return Err(err(
                e,
                format!(
                    "MID = {} is a {}, a shell material; rods and beams need a MAT1",
                    used.mid,
                    other.card()
                ),
            ));
        }
        None => return Err(err(e, format!("material {} missing", used.mid))),
    };
    let target = ParamTarget::Material(used.mid);
    let kinds = ctx.params.kinds_on(target);
    let elasticity = if kinds.contains(&PmparKind::Nu) {
        let derived = m.e / (2.0 * (1.0 + m.nu));
        if (m.g - derived).abs() > 1e-9 * derived.abs() {
            return Err(err(
                e,
                format!(
                    "PMPAR NU on MAT1 {}: its G = {:e} is not E/(2(1+NU)) = {derived:e}, so the torsion stiffness would not follow NU; leave G blank on the MAT1",
                    used.mid, m.g
                ),
            ));
        }
        beam::Elasticity::Separate
    } else if kinds.contains(&PmparKind::E) {
        beam::Elasticity::YoungsModulus { g_per_e: m.g / m.e }
    } else {
        beam::Elasticity::Fixed { e: m.e, g: m.g }
    };
    let density = if kinds.contains(&PmparKind::Rho) {
        beam::Density::Parameter
    } else {
        beam::Density::Fixed { rho: m.rho }
    };
    Ok((m, target, elasticity, density))
}

/// A curved beam ([`bend`]): its force-method stiffness (one part ∝ E under a PMPAR E; NU is
/// refused) and lumped mass (ρ part plus a constant NSM part under a PMPAR RHO).
fn bend_element(ctx: &ElementContext, e: &Element) -> Result<Built, DiscretizeError> {
    let (element, used) = ctx
        .model
        .bend_element(e)
        .ok_or_else(|| err(e, "not a CBEND"))?
        .map_err(|x| err(e, x))?;
    let (m, target, elasticity, density) = line_material(ctx, e, &used)?;
    let k = bend::affine_stiffness(&element.arc, &element.section, elasticity)
        .map_err(|x| err(e, x))?;
    let mass = bend::affine_mass(&element.arc, &element.section, density);
    let has_mass = m.rho * element.section.a + element.section.nsm != 0.0;
    Ok(isotropic_built(ctx, e, target, &m, (&k, &mass), has_mass))
}

/// The stiffness and mass of an element of one MAT1 `m`, their affine parts bound to the PMPAR
/// acting on `target` or fixed at the card's E, NU and RHO; the mass only when the element has
/// some (`has_mass`) or a PMPAR may give it some.
fn isotropic_built(
    ctx: &ElementContext,
    e: &Element,
    target: ParamTarget,
    m: &IsotropicMaterial,
    (k, mass): (&AffineMatrix, &AffineMatrix),
    has_mass: bool,
) -> Built {
    let nominal = CoefficientValues {
        e: m.e,
        nu: m.nu,
        rho: m.rho,
        ..Default::default()
    };
    let binding = acted_on(ctx.params, target);
    let contribution = |a: &AffineMatrix| {
        Contribution::from_affine(ctx.frames, &e.nodes, a, bind(binding, nominal))
    };
    Built {
        k: Some(contribution(k)),
        m: (has_mass || binding.is_some()).then(|| contribution(mass)),
        ..Built::default()
    }
}

/// A contribution whose rows are g DOFs given directly (no frame rotation).
fn on_dofs(
    dofs: Vec<usize>,
    matrix: &AffineMatrix,
    binding: impl Fn(Coefficient) -> Binding,
) -> Contribution {
    let mut c = Contribution::from_affine(&GridFrames::default(), &[], matrix, binding);
    c.dofs = dofs;
    c
}

/// A spring; `PMPAR K` on its PELAS makes k a parameter (eq. 3.23). CELAS2 / CELAS4 carry k on
/// the card, which no PMPAR can reach.
fn spring_element(ctx: &ElementContext, e: &Element) -> Result<Built, DiscretizeError> {
    let model = ctx.model;
    let Spring { stiffness, ends } = model.spring(e).ok_or_else(|| err(e, "card missing"))?;
    let (k, target) = match stiffness {
        SpringStiffness::Property { pid, k: Some(k) } => {
            (k, acted_on(ctx.params, ParamTarget::Pelas(pid)))
        }
        SpringStiffness::Property { pid, k: None } => {
            return Err(err(e, format!("PID {pid} is not a PELAS")));
        }
        SpringStiffness::OnCard(k) => (k, None),
    };
    let [a, b] = ends.map(|end| model.point_dof(end).map(|p| ctx.map.point_dof(p)));
    let spring = ScalarSpring::new(a, b).map_err(|x| err(e, x))?;
    let dofs = spring.dofs.clone();
    let nominal = CoefficientValues {
        lumped: k,
        ..Default::default()
    };
    Ok(Built {
        k: Some(on_dofs(
            dofs,
            &spring.affine_stiffness(),
            bind(target, nominal),
        )),
        ..Built::default()
    })
}

/// A CMASS2: the mass M between its two DOFs, M·[[1, −1], [−1, 1]] (a [`ScalarSpring`]'s
/// matrix with M; one end grounded: M on the other DOF), as Nastran's scalar masses.
fn scalar_mass_element(ctx: &ElementContext, e: &Element) -> Result<Built, DiscretizeError> {
    let model = ctx.model;
    let (m, ends) = model.scalar_mass(e).ok_or_else(|| err(e, "card missing"))?;
    let [a, b] = ends.map(|end| model.point_dof(end).map(|p| ctx.map.point_dof(p)));
    let mass = ScalarSpring::new(a, b).map_err(|x| err(e, x))?;
    Ok(Built {
        m: Some(Contribution::constant(mass.dofs.clone(), mass.stiffness(m))),
        ..Built::default()
    })
}

/// A CDAMP1–CDAMP4 (a [`ScalarSpring`] with b) or a CVISC ([`rod_damping`]): damping only.
fn damper_element(ctx: &ElementContext, e: &Element) -> Result<Built, DiscretizeError> {
    let model = ctx.model;
    let damper = model
        .damper(e)
        .ok_or_else(|| err(e, "card missing"))?
        .map_err(|x| err(e, x))?;
    let b = match damper {
        Damper::Scalar { b, ends } => {
            let [a, z] = ends.map(|end| model.point_dof(end).map(|p| ctx.map.point_dof(p)));
            let spring = ScalarSpring::new(a, z).map_err(|x| err(e, x))?;
            Contribution::constant(spring.dofs.clone(), spring.stiffness(b))
        }
        Damper::Rod { ce, cr } => {
            let xyz = model.positions(e);
            let matrix = rod_damping(&xyz, ce, cr).map_err(|x| err(e, x))?;
            Contribution::element(ctx.frames, &e.nodes, vec![(ParamKey::Constant, matrix)])
        }
    };
    Ok(Built {
        b: Some(b),
        ..Built::default()
    })
}

/// The 12 × 12 damping matrix (basic, (u_a, θ_a, u_b, θ_b)) of a CVISC between `xyz[0]` and
/// `xyz[1]`: axial `ce` on the translations and torsional `cr` on the rotations along the unit
/// axis e, each ±c·eeᵀ (a rod's axial and torsion terms).
fn rod_damping(xyz: &[[f64; 3]], ce: f64, cr: f64) -> Result<faer::Mat<f64>, String> {
    let [a, b] = [xyz.first(), xyz.get(1)].map(|p| p.copied().unwrap_or_default());
    let axis = normalize(sub(b, a)).ok_or("G1 and G2 coincide: the damper has no axis")?;
    Ok(faer::Mat::from_fn(12, 12, |i, j| {
        let (node_i, node_j) = (i / 6, j / 6);
        let (ri, rj) = (i % 6, j % 6);
        if ri / 3 != rj / 3 {
            return 0.0;
        }
        let c = if ri < 3 { ce } else { cr };
        let sign = if node_i == node_j { 1.0 } else { -1.0 };
        sign * c * axis[ri % 3] * axis[rj % 3]
    }))
}

/// A CBUSH: K1–K6, B1–B6 and GE of its PBUSH at the spring location (constant: no PMPAR
/// reaches a PBUSH).
fn bush_element(ctx: &ElementContext, e: &Element) -> Result<Built, DiscretizeError> {
    let placement = ctx
        .model
        .bush(e)
        .ok_or_else(|| err(e, "card missing"))?
        .map_err(|reason| err(e, reason))?;
    let on_axes = |values: [f64; 6]| {
        values.iter().any(|&v| v != 0.0).then(|| {
            Contribution::element(
                ctx.frames,
                &e.nodes,
                vec![(ParamKey::Constant, placement.bush.stiffness(values))],
            )
        })
    };
    Ok(Built {
        k: Some(Contribution::element(
            ctx.frames,
            &e.nodes,
            vec![(ParamKey::Constant, placement.bush.stiffness(placement.k))],
        )),
        b: on_axes(placement.b),
        k4: on_axes(placement.structural()),
        ..Built::default()
    })
}

/// A CONM2; `PMPAR MASS` on it scales its whole mass matrix (eq. 3.25).
fn conm2_element(ctx: &ElementContext, e: &Element) -> Result<Built, DiscretizeError> {
    let (model, frames) = (ctx.model, ctx.frames);
    // The CG location and the inertia tensor (basic, negative products) come from the model's
    // mass-property code, so the CONM2 CID / sign conventions live in one place (model::mass).
    let point = model
        .element_mass(e)
        .ok_or_else(|| err(e, "cannot resolve the CONM2 location (grid or CID missing)"))?;
    let node = *e.nodes.first().ok_or_else(|| err(e, "no grid"))?;
    let grid = model.grids[node].xyz;
    let offset = std::array::from_fn(|i| point.point[i] - grid[i]);
    let conm2 = Conm2::new(point.mass, offset, point.inertia.unwrap_or([[0.0; 3]; 3]))
        .map_err(|x| err(e, x))?;
    let matrix = if point.mass != 0.0 {
        conm2.affine_mass().map_err(|x| err(e, x))?
    } else {
        AffineMatrix {
            parts: vec![(Coefficient::Constant, conm2.mass_matrix())],
        }
    };
    let nominal = CoefficientValues {
        lumped: point.mass,
        ..Default::default()
    };
    let target = acted_on(ctx.params, ParamTarget::Conm2(e.id));
    Ok(Built {
        k: None,
        m: Some(Contribution::from_affine(
            frames,
            &[node],
            &matrix,
            bind(target, nominal),
        )),
        ..Built::default()
    })
}

/// The centroid section of a shell as its stress recovery reads it, at the deck's values.
#[derive(Debug, Clone, PartialEq)]
pub enum CentreSection {
    /// PSHELL: the roles, thickness (mean of the corners) and ZOFFS (boxed: its role materials
    /// make it large).
    Pshell(Box<PshellSection>),
    /// PCOMP: the full ply stack, its bottom at Z0 + ZOFFS.
    Laminate(Laminate),
}

/// The [`CentreSection`] of a CQUAD4 / CTRIA3: the section its mass and strain fibres use.
pub fn shell_centre_section(model: &Model, e: &Element) -> Result<CentreSection, DiscretizeError> {
    let card = model
        .shell_placement(e)
        .ok_or_else(|| err(e, "card missing"))?;
    Ok(match shell_section(model, e, &card)?.centre {
        SectionInput::Pshell { section, .. } => CentreSection::Pshell(Box::new(section)),
        SectionInput::Laminate { laminate, .. } => CentreSection::Laminate(laminate),
    })
}

/// Element displacements (basic, 6 per grid, grid-major) from basic n×6 rows.
pub fn element_displacements(rows: &[f64], nodes: &[usize]) -> Vec<f64> {
    nodes
        .iter()
        .flat_map(|&a| rows[6 * a..6 * a + 6].iter().copied())
        .collect()
}

/// Centroid strains of a shell (CQUAD4, CTRIA3) in its material system from its basic element
/// displacements `ue` (6 per grid, [`element_displacements`]): the recovery of SOL 101's STRAIN
/// output and of STRAIN sensors.
pub fn shell_strains(
    model: &Model,
    e: &Element,
    rec: &ShellRecovery,
    ue: &[f64],
) -> Result<shell::ShellStrains, DiscretizeError> {
    let xyz = model.positions(e);
    let bad = |reason: String| DiscretizeError::Element {
        card: e.kind.card(),
        id: e.id,
        reason,
    };
    if let Some(layout) = model.quadratic_layout(e) {
        return shell_quadratic::strains(layout, &xyz, rec.material_x, rec.fibres, ue)
            .map_err(|x| bad(x.to_string()));
    }
    match (xyz.len(), ue.len()) {
        (4, 24) => shell::quad4_strains(
            &[xyz[0], xyz[1], xyz[2], xyz[3]],
            rec.material_x,
            rec.fibres,
            &std::array::from_fn(|i| ue[i]),
        ),
        (3, 18) => shell::tria3_strains(
            &[xyz[0], xyz[1], xyz[2]],
            rec.material_x,
            rec.fibres,
            &std::array::from_fn(|i| ue[i]),
        ),
        (k, _) => return Err(bad(format!("a shell with {k} grids"))),
    }
    .map_err(|x| bad(x.to_string()))
}
