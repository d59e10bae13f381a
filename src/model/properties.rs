//! Element data as the element kernels read them, with properties and materials attached:
//! a shell's placement on its element card ([`Model::shell_placement`]), its PSHELL or PCOMP
//! section ([`Model::shell_property`], the PCOMP as its full ply stack), a solid's PSOLID
//! material ([`Model::solid_material`]) and a scalar spring's stiffness and ends
//! ([`Model::spring`]).

use super::materials::Material;
use super::scalar_points::PointDof;
use super::{Element, ElementKind, Model, PropertyRef};
use crate::card_values::{CornerThickness, ShellOrientation, SpringEnd};

/// The shell fields of a CQUAD4 / CTRIA3 card.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShellPlacement {
    pub pid: u32,
    pub orientation: ShellOrientation,
    /// ZOFFS: offset of the reference plane from the grids.
    pub zoffs: f64,
    pub corners: Option<CornerThickness>,
}

/// A material id with its material (`None`: the id names no material).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MaterialUse {
    pub mid: u32,
    pub material: Option<Material>,
}

/// A PSHELL: thickness, the material of each role, ratios and fibre distances.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlateProperty {
    pub id: u32,
    pub t: f64,
    /// MID1 … MID4: membrane, bending, transverse shear, membrane–bending coupling.
    pub membrane: Option<MaterialUse>,
    pub bending: Option<MaterialUse>,
    pub shear: Option<MaterialUse>,
    pub coupling: Option<MaterialUse>,
    /// 12I/T³.
    pub bending_ratio: f64,
    /// TS/T.
    pub shear_ratio: f64,
    pub nsm: f64,
    /// Fibre distances Z1 (bottom), Z2 (top).
    pub z1: f64,
    pub z2: f64,
}

/// One ply of a laminate stack.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Lamina {
    pub material: MaterialUse,
    pub t: f64,
    /// Fibre angle in degrees from the element material x axis.
    pub theta_deg: f64,
}

/// A PCOMP as its full stack (mirror image appended for `SYM`), bottom to top.
#[derive(Debug, Clone, PartialEq)]
pub struct LaminateProperty {
    pub id: u32,
    pub plies: Vec<Lamina>,
    /// Z0 with its default (−thickness/2) applied.
    pub z0: f64,
    /// True when Z0 is on the card.
    pub z0_given: bool,
    pub nsm: f64,
    /// Total thickness.
    pub thickness: f64,
    /// The ply failure theory (FT) as written, `None` when blank.
    pub failure_theory: Option<String>,
    /// TREF: the reference (stress-free) temperature of every ply.
    pub tref: f64,
}

/// A shell section property.
#[derive(Debug, Clone, PartialEq)]
pub enum ShellProperty {
    /// PSHELL (boxed: its role materials make it large).
    Plate(Box<PlateProperty>),
    Laminate(LaminateProperty),
}

/// How stiff a scalar spring is.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum SpringStiffness {
    /// CELAS1 / CELAS3: K of its PELAS (`None`: PID names no PELAS).
    Property { pid: u32, k: Option<f64> },
    /// CELAS2 / CELAS4: K on the card.
    OnCard(f64),
}

/// A scalar spring (CELAS1–CELAS4); an end is a grid component, a scalar point or ground.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Spring {
    pub stiffness: SpringStiffness,
    pub ends: [SpringEnd; 2],
}

impl Model {
    fn material_use(&self, mid: u32) -> MaterialUse {
        MaterialUse {
            mid,
            material: self.material(mid),
        }
    }

    /// Which mid-side grids of a CQUAD8 / CTRIA6 are given (`None` for other elements); the
    /// element's grids are the given ones, corners first.
    pub fn quadratic_layout(&self, e: &Element) -> Option<crate::fe::shell_quadratic::Layout> {
        let cards = match e.kind {
            ElementKind::Quad8 => &self.bulk.cquad8,
            ElementKind::Tria6 => &self.bulk.ctria6,
            _ => return None,
        };
        cards
            .get(e.card)
            .and_then(|c| crate::fe::shell_quadratic::Layout::of_card(&c.nodes))
    }

    /// The shell fields of a CQUAD4 / CTRIA3 / CQUADR / CTRIAR / CQUAD8 / CTRIA6 element.
    pub fn shell_placement(&self, e: &Element) -> Option<ShellPlacement> {
        let b = &self.bulk;
        let quads = match e.kind {
            ElementKind::Quad4 => &b.cquad4,
            ElementKind::QuadR => &b.cquadr,
            _ => &b.cquad4,
        };
        let trias = match e.kind {
            ElementKind::TriaR => &b.ctriar,
            _ => &b.ctria3,
        };
        match e.kind {
            ElementKind::Quad4 | ElementKind::QuadR => quads.get(e.card).map(|c| ShellPlacement {
                pid: c.pid,
                orientation: c.orientation,
                zoffs: c.zoffs,
                corners: c.corner_thickness,
            }),
            ElementKind::Tria3 | ElementKind::TriaR => trias.get(e.card).map(|c| ShellPlacement {
                pid: c.pid,
                orientation: c.orientation,
                zoffs: c.zoffs,
                corners: c.corner_thickness,
            }),
            ElementKind::Quad8 | ElementKind::Tria6 => {
                let cards = if e.kind == ElementKind::Quad8 {
                    &b.cquad8
                } else {
                    &b.ctria6
                };
                cards.get(e.card).map(|c| ShellPlacement {
                    pid: c.pid,
                    orientation: c.orientation,
                    zoffs: c.zoffs,
                    corners: c.corner_thickness,
                })
            }
            _ => None,
        }
    }

    /// The PSHELL or PCOMP a property reference points at (`None` for other properties).
    pub fn shell_property(&self, property: PropertyRef) -> Option<ShellProperty> {
        let b = &self.bulk;
        match property {
            PropertyRef::Pshell(i) => b.pshell.get(i).map(|p| {
                let role = |mid: Option<u32>| mid.map(|m| self.material_use(m));
                ShellProperty::Plate(Box::new(PlateProperty {
                    id: p.id,
                    t: p.t,
                    membrane: role(p.mid1),
                    bending: role(p.mid2),
                    shear: role(p.mid3),
                    coupling: role(p.mid4),
                    bending_ratio: p.bending_ratio,
                    shear_ratio: p.ts_t,
                    nsm: p.nsm,
                    z1: p.z1,
                    z2: p.z2,
                }))
            }),
            PropertyRef::Pcomp(i) => b.pcomp.get(i).map(|p| {
                ShellProperty::Laminate(LaminateProperty {
                    id: p.id,
                    plies: p
                        .full_stack()
                        .iter()
                        .map(|ply| Lamina {
                            material: self.material_use(ply.mid),
                            t: ply.t,
                            theta_deg: ply.theta,
                        })
                        .collect(),
                    z0: p.z0_resolved(),
                    z0_given: p.z0.is_some(),
                    nsm: p.nsm,
                    thickness: p.thickness(),
                    failure_theory: p.ft.clone(),
                    tref: p.tref,
                })
            }),
            _ => None,
        }
    }

    /// The card and id (`PSOLID 3`, `PCOMPS 2`) and the material of a solid property
    /// reference.
    pub fn solid_material(&self, property: PropertyRef) -> Option<(String, MaterialUse)> {
        let PropertyRef::Psolid(i) = property else {
            return None;
        };
        let p = self.bulk.psolid.get(i)?;
        Some((p.label(), self.material_use(p.mid)))
    }

    /// The PSHEAR of a CSHEAR element.
    pub fn pshear(&self, e: &Element) -> Option<&crate::deck::cards::Pshear> {
        let PropertyRef::Pshear(i) = e.property? else {
            return None;
        };
        self.bulk.pshear.get(i)
    }

    /// The stiffness and ends of a CELAS1–CELAS4 element.
    pub fn spring(&self, e: &Element) -> Option<Spring> {
        let b = &self.bulk;
        let on_card = |c: &crate::deck::cards::Celas2| Spring {
            stiffness: SpringStiffness::OnCard(c.k),
            ends: c.ends,
        };
        match e.kind {
            ElementKind::Celas1 | ElementKind::Celas3 => {
                let cards = if e.kind == ElementKind::Celas1 {
                    &b.celas1
                } else {
                    &b.celas3
                };
                cards.get(e.card).map(|c| Spring {
                    stiffness: SpringStiffness::Property {
                        pid: c.pid,
                        k: match e.property {
                            Some(PropertyRef::Pelas(i)) => b.pelas.get(i).map(|p| p.k),
                            _ => None,
                        },
                    },
                    ends: c.ends,
                })
            }
            ElementKind::Celas2 => b.celas2.get(e.card).map(on_card),
            ElementKind::Celas4 => b.celas4.get(e.card).map(on_card),
            _ => None,
        }
    }

    /// The mass M and ends of a CMASS2 element.
    pub fn scalar_mass(&self, e: &Element) -> Option<(f64, [SpringEnd; 2])> {
        match e.kind {
            ElementKind::Cmass2 => self.bulk.cmass2.get(e.card).map(|c| (c.k, c.ends)),
            _ => None,
        }
    }

    /// The DOF of a scalar element end: a grid component, a scalar point, or `None` for ground
    /// (or an id the model check has already reported).
    pub fn point_dof(&self, end: SpringEnd) -> Option<PointDof> {
        let id = end.grid?;
        match end.component {
            0 => self.scalar_index.get(&id).map(|&k| PointDof::Scalar(k)),
            c => self.grid_index.get(&id).map(|&grid| PointDof::Grid {
                grid,
                component0: usize::from(c) - 1,
            }),
        }
    }
}
