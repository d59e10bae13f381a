//! Curved beams (CBEND with PBEND) as the element kernel [`crate::fe::bend`] reads them: the
//! arc in the basic system and the section.
//!
//! Frames (MSC QRG CBEND): the orientation vector X1–X3 is in GA's displacement system (for a
//! curvilinear CD, the local axes at GA); G0 gives v from GA to G0. GEOM 3 takes the radius RB
//! and GEOM 4 the arc angle THETAB (degrees) of the PBEND.

use super::lines::LineInputs;
use super::properties::MaterialUse;
use super::{Element, Model, PropertyRef};
use crate::deck::cards::{BeamOrientation, Cbend, Pbend};
use crate::fe::bend::{Arc, ArcRule, BendSection};

/// A CBEND resolved into the basic system.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BendElement {
    pub arc: Arc,
    pub section: BendSection,
    pub mid: u32,
}

impl LineInputs<'_> {
    /// The arc and section of a CBEND (`Err` with the reason when they are inconsistent).
    pub fn resolve_bend(
        &self,
        e: &Element,
        property: Option<PropertyRef>,
    ) -> Result<BendElement, String> {
        let c = self
            .bulk
            .cbend
            .get(e.card)
            .ok_or_else(|| format!("CBEND {}: card missing", e.id))?;
        let Some(PropertyRef::Pbend(i)) = property else {
            return Err("property missing".into());
        };
        let p = self.bulk.pbend.get(i).ok_or("PBEND missing")?;
        let ends: Vec<_> = e.nodes.iter().filter_map(|&i| self.grids.get(i)).collect();
        let [ga, gb] = ends[..] else {
            return Err("a CBEND needs two grids".into());
        };
        let v = match c.orientation {
            BeamOrientation::Grid(g0) => self.towards_g0(g0, ga)?,
            BeamOrientation::Vector(v) => self.in_basic(ga, v)?,
        };
        let arc = Arc::new(ga.xyz, gb.xyz, v, arc_rule(c, p)?).map_err(|x| x.to_string())?;
        Ok(BendElement {
            arc,
            section: BendSection {
                a: p.a,
                i1: p.i1,
                i2: p.i2,
                j: p.j,
                k1: p.k1,
                k2: p.k2,
                nsm: p.nsm,
            },
            mid: p.mid,
        })
    }
}

/// The arc rule of a CBEND's GEOM with its PBEND's RB / THETAB.
fn arc_rule(c: &Cbend, p: &Pbend) -> Result<ArcRule, String> {
    let needs = |name: &str| {
        format!(
            "GEOM = {} needs {name} on PBEND {} (blank there)",
            c.geom, p.id
        )
    };
    Ok(match c.geom {
        1 => ArcRule::CentreAlongV,
        2 => ArcRule::TangentAlongV,
        3 => ArcRule::Radius(p.rb.ok_or_else(|| needs("RB"))?),
        _ => ArcRule::Angle(p.thetab.ok_or_else(|| needs("THETAB"))?.to_radians()),
    })
}

impl Model {
    /// The resolved data of a CBEND and its material (`None` for other elements).
    pub fn bend_element(&self, e: &Element) -> Option<Result<(BendElement, MaterialUse), String>> {
        if e.kind != super::ElementKind::Cbend {
            return None;
        }
        Some(self.line_inputs().resolve_bend(e, e.property).map(|bend| {
            let material = MaterialUse {
                mid: bend.mid,
                material: self.material(bend.mid),
            };
            (bend, material)
        }))
    }
}
