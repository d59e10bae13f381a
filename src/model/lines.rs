//! Line elements (CROD, CONROD, CTUBE, CBAR, CBEAM) as the element kernel reads them
//! ([`Model::line_element`]): the end grids, offsets and orientation vector in the basic
//! system, the pin flags, and the section with its material.
//!
//! Frames (Nastran QRG CBAR/CBEAM, OFFT = GGG default): the offsets WA, WB are components in
//! the displacement system (CD) of their grid; the orientation vector X1–X3 is in GA's
//! displacement system (OFFT first letter G) or the basic system (B); G0 gives v from GA to
//! G0. Every vector is rotated into basic at its grid (for a curvilinear CD, the local axes at
//! the grid).
//!
//! Sections: PROD (A, J, NSM), PTUBE (OD, T: the TUBE/ROD library shape), CONROD (on the card),
//! PBAR (A, I1, I2, I12, J, NSM, K1/K2 blank = rigid in shear), PBARL/PBEAML (library shapes,
//! [`crate::fe::beam_section`]; rigid in shear), PBEAM (end A's section; K1/K2 default 1.0,
//! 0.0 = rigid in shear).

use std::collections::HashMap;

use super::coords::CoordSystem;
use super::properties::MaterialUse;
use super::{Element, ElementKind, GridPoint, Model, PropertyRef};
use crate::card_values::Dofs;
use crate::deck::cards::{BeamOrientation, BulkData, Cbar};
use crate::fe::beam::{LineGeometry, element_axes};
use crate::fe::beam_section::{SectionError, SectionProperties, library_section};
use crate::geometry::mat3::mul_vec;
use crate::geometry::vec3::sub;

/// Section of a line element.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LineSectionValues {
    pub mid: u32,
    pub a: f64,
    pub i1: f64,
    pub i2: f64,
    pub i12: f64,
    pub j: f64,
    pub nsm: f64,
    /// Shear area factors (`None`: rigid in shear).
    pub k1: Option<f64>,
    pub k2: Option<f64>,
    /// PBEAM neutral axis (N1, N2) in the element's y, z (0 for the other properties).
    pub neutral_axis: [f64; 2],
}

/// A line element resolved into the basic system.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LineElement {
    /// Grid locations of ends A and B.
    pub grids: [[f64; 3]; 2],
    /// Offsets of ends A and B (basic).
    pub offsets: [[f64; 3]; 2],
    /// Orientation vector (basic) of a beam; `None` for rods.
    pub orientation: Option<[f64; 3]>,
    /// Pin flags of ends A and B.
    pub pins: [Dofs; 2],
    pub section: LineSectionValues,
}

/// What resolving a line element needs from the model or from the model being built.
pub(super) struct LineInputs<'a> {
    pub bulk: &'a BulkData,
    pub coords: &'a HashMap<u32, CoordSystem>,
    pub grids: &'a [GridPoint],
    pub grid_index: &'a super::ids::IdMap<usize>,
}

impl LineInputs<'_> {
    /// The orientation vector from end A to the orientation grid G0, in basic.
    pub(super) fn towards_g0(&self, g0: u32, a: &GridPoint) -> Result<[f64; 3], String> {
        let g = self
            .grid_index
            .get(&g0)
            .and_then(|&i| self.grids.get(i))
            .ok_or_else(|| format!("G0 = {g0} does not exist (no GRID {g0})"))?;
        Ok(sub(g.xyz, a.xyz))
    }

    /// A vector given in grid `g`'s displacement system, in basic.
    pub(super) fn in_basic(&self, g: &GridPoint, v: [f64; 3]) -> Result<[f64; 3], String> {
        if g.cd == 0 {
            return Ok(v);
        }
        let cs = self
            .coords
            .get(&g.cd)
            .ok_or_else(|| format!("CD = {} of GRID {} does not exist", g.cd, g.id))?;
        Ok(mul_vec(&cs.axes_at(g.xyz), v))
    }

    fn beam_placement(
        &self,
        c: &Cbar,
        ends: [&GridPoint; 2],
    ) -> Result<([[f64; 3]; 2], [f64; 3]), String> {
        let offsets = [
            self.in_basic(ends[0], c.offsets[0])?,
            self.in_basic(ends[1], c.offsets[1])?,
        ];
        let v = match c.orientation {
            BeamOrientation::Grid(g0) => self.towards_g0(g0, ends[0])?,
            BeamOrientation::Vector(v) if c.offt.vector_in_basic => v,
            BeamOrientation::Vector(v) => self.in_basic(ends[0], v)?,
        };
        Ok((offsets, v))
    }

    /// Resolve a line element (`Err` with the reason when its data is inconsistent).
    pub fn resolve(
        &self,
        e: &Element,
        property: Option<PropertyRef>,
    ) -> Result<LineElement, String> {
        let b = self.bulk;
        let ends: Vec<&GridPoint> = e.nodes.iter().filter_map(|&i| self.grids.get(i)).collect();
        let [ga, gb] = ends[..] else {
            return Err("a line element needs two grids".into());
        };
        let missing = || format!("{} {}: card missing", e.kind.card(), e.id);
        let (offsets, orientation, pins) = match e.kind {
            ElementKind::Cbar | ElementKind::Cbeam => {
                let list = if e.kind == ElementKind::Cbar {
                    &b.cbar
                } else {
                    &b.cbeam
                };
                let c = list.get(e.card).ok_or_else(missing)?;
                let (offsets, v) = self.beam_placement(c, [ga, gb])?;
                (offsets, Some(v), c.pins)
            }
            _ => ([[0.0; 3]; 2], None, [Dofs::NONE; 2]),
        };
        let section = match e.kind {
            ElementKind::Conrod => {
                let c = b.conrod.get(e.card).ok_or_else(missing)?;
                rod_section(c.mid, c.a, c.j, c.nsm)
            }
            _ => property_section(b, property.ok_or("property missing")?)
                .map_err(|x| x.to_string())?,
        };
        let line = LineElement {
            grids: [ga.xyz, gb.xyz],
            offsets,
            orientation,
            pins,
            section,
        };
        element_axes(&line.geometry()).map_err(|x| x.to_string())?;
        Ok(line)
    }
}

impl LineElement {
    /// The placement as the element kernel takes it.
    pub fn geometry(&self) -> LineGeometry {
        LineGeometry {
            grids: self.grids,
            offsets: self.offsets,
            orientation: self.orientation,
        }
    }
}

fn rod_section(mid: u32, a: f64, j: f64, nsm: f64) -> LineSectionValues {
    LineSectionValues {
        mid,
        a,
        i1: 0.0,
        i2: 0.0,
        i12: 0.0,
        j,
        nsm,
        k1: None,
        k2: None,
        neutral_axis: [0.0; 2],
    }
}

fn shaped(mid: u32, s: SectionProperties, nsm: f64) -> LineSectionValues {
    LineSectionValues {
        mid,
        a: s.a,
        i1: s.i1,
        i2: s.i2,
        i12: s.i12,
        j: s.j,
        nsm,
        k1: None,
        k2: None,
        neutral_axis: [0.0; 2],
    }
}

/// A PTUBE's section: a TUBE of radii OD/2 and OD/2 − T, a ROD when T = OD/2.
pub fn tube_section(od: f64, t: f64) -> Result<SectionProperties, SectionError> {
    let (ro, ri) = (od / 2.0, od / 2.0 - t);
    if ri > 0.0 {
        library_section("TUBE", &[ro, ri])
    } else {
        library_section("ROD", &[ro])
    }
}

/// The section of a line-element property (`Err` for a library shape paraflex does not
/// compute or inconsistent dimensions).
pub fn property_section(b: &BulkData, p: PropertyRef) -> Result<LineSectionValues, SectionError> {
    let gone = || SectionError::UnsupportedType(format!("{} (property missing)", p.card()));
    Ok(match p {
        PropertyRef::Prod(i) => {
            let c = b.prod.get(i).ok_or_else(gone)?;
            rod_section(c.mid, c.a, c.j, c.nsm)
        }
        PropertyRef::Ptube(i) => {
            let c = b.ptube.get(i).ok_or_else(gone)?;
            shaped(c.mid, tube_section(c.od, c.t)?, c.nsm)
        }
        PropertyRef::Pbar(i) => {
            let c = b.pbar.get(i).ok_or_else(gone)?;
            LineSectionValues {
                mid: c.mid,
                a: c.a,
                i1: c.i1,
                i2: c.i2,
                i12: c.i12,
                j: c.j,
                nsm: c.nsm,
                k1: c.k1,
                k2: c.k2,
                neutral_axis: [0.0; 2],
            }
        }
        PropertyRef::Pbarl(i) | PropertyRef::Pbeaml(i) => {
            let list = if matches!(p, PropertyRef::Pbarl(_)) {
                &b.pbarl
            } else {
                &b.pbeaml
            };
            let c = list.get(i).ok_or_else(gone)?;
            shaped(c.mid, library_section(&c.shape, &c.dims)?, c.nsm)
        }
        PropertyRef::Pbeam(i) => {
            let c = b.pbeam.get(i).ok_or_else(gone)?;
            let factor = |k: f64| (k > 0.0).then_some(k);
            LineSectionValues {
                mid: c.mid,
                a: c.a,
                i1: c.i1,
                i2: c.i2,
                i12: c.i12,
                j: c.j,
                nsm: c.nsm,
                k1: factor(c.k1),
                k2: factor(c.k2),
                neutral_axis: c.neutral_axis,
            }
        }
        _ => return Err(gone()),
    })
}

/// The location of a line-element property card.
pub fn property_loc(b: &BulkData, p: PropertyRef) -> Option<&crate::deck::Loc> {
    match p {
        PropertyRef::Prod(i) => b.prod.get(i).map(|c| &c.loc),
        PropertyRef::Ptube(i) => b.ptube.get(i).map(|c| &c.loc),
        PropertyRef::Pbar(i) => b.pbar.get(i).map(|c| &c.loc),
        PropertyRef::Pbarl(i) => b.pbarl.get(i).map(|c| &c.loc),
        PropertyRef::Pbeam(i) => b.pbeam.get(i).map(|c| &c.loc),
        PropertyRef::Pbeaml(i) => b.pbeaml.get(i).map(|c| &c.loc),
        _ => None,
    }
}

impl Model {
    /// What resolving a line or curved-beam element needs, from this model.
    pub(super) fn line_inputs(&self) -> LineInputs<'_> {
        LineInputs {
            bulk: &self.bulk,
            coords: &self.coords,
            grids: &self.grids,
            grid_index: &self.grid_index,
        }
    }

    /// The resolved data of a line element and its material (`None` for other elements).
    pub fn line_element(&self, e: &Element) -> Option<Result<(LineElement, MaterialUse), String>> {
        if !e.kind.is_line() {
            return None;
        }
        Some(self.line_inputs().resolve(e, e.property).map(|line| {
            let material = MaterialUse {
                mid: line.section.mid,
                material: self.material(line.section.mid),
            };
            (line, material)
        }))
    }
}
