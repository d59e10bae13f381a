//! Damping data of the elements: the viscous dampers (CDAMP1–CDAMP4 with PDAMP or B on the
//! card, CVISC with PVISC; a CBUSH's PBUSH B is read with its placement, [`Model::bush`]) and
//! each element's structural damping coefficient GE (PELAS, CELAS2, MAT1 / MAT8, PCOMP; a
//! CBUSH's GE1–GE6 are per direction, [`super::bush::BushPlacement::structural`]).
//!
//! No PMPAR acts on PDAMP, PVISC or PBUSH: the viscous damping matrix is constant. GE scales an
//! element's stiffness, so its structural damping matrix GE·K_e has K_e's affine parts.

use super::{Element, ElementKind, Model, PropertyRef};
use crate::card_values::SpringEnd;

/// A viscous damper element's data.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Damper {
    /// CDAMP1–CDAMP4: damping `b` between two scalar ends (grid components, scalar points or
    /// ground), as a CELAS spring.
    Scalar { b: f64, ends: [SpringEnd; 2] },
    /// CVISC: axial damping `ce` and torsional damping `cr` along the line of its two grids.
    Rod { ce: f64, cr: f64 },
}

impl Model {
    /// The damper data of a CDAMP1–CDAMP4 or CVISC element (`None` for another element);
    /// `Err` when its PID names no PDAMP / PVISC.
    pub fn damper(&self, e: &Element) -> Option<Result<Damper, String>> {
        let b = &self.bulk;
        let missing = |pid: u32, card: &str| Err(format!("PID {pid} is not a {card}"));
        Some(match e.kind {
            ElementKind::Cdamp1 | ElementKind::Cdamp3 => {
                let cards = if e.kind == ElementKind::Cdamp1 {
                    &b.cdamp1
                } else {
                    &b.cdamp3
                };
                let c = cards.get(e.card)?;
                match e.property {
                    Some(PropertyRef::Pdamp(i)) => b.pdamp.get(i).map_or_else(
                        || missing(c.pid, "PDAMP"),
                        |p| {
                            Ok(Damper::Scalar {
                                b: p.b,
                                ends: c.ends,
                            })
                        },
                    ),
                    _ => missing(c.pid, "PDAMP"),
                }
            }
            ElementKind::Cdamp2 => b.cdamp2.get(e.card).map(|c| {
                Ok(Damper::Scalar {
                    b: c.k,
                    ends: c.ends,
                })
            })?,
            ElementKind::Cdamp4 => b.cdamp4.get(e.card).map(|c| {
                Ok(Damper::Scalar {
                    b: c.k,
                    ends: c.ends,
                })
            })?,
            ElementKind::Cvisc => {
                let c = b.cvisc.get(e.card)?;
                match e.property {
                    Some(PropertyRef::Pvisc(i)) => b.pvisc.get(i).map_or_else(
                        || missing(c.pid, "PVISC"),
                        |p| Ok(Damper::Rod { ce: p.ce, cr: p.cr }),
                    ),
                    _ => missing(c.pid, "PVISC"),
                }
            }
            _ => return None,
        })
    }

    /// The structural damping coefficient GE of an element's stiffness: PELAS GE (CELAS1,
    /// CELAS3), GE on a CELAS2, the GE of the material of a rod, beam or solid, of a PSHELL's
    /// MID1 (MID2 without a membrane material) and PCOMP's GE. 0 for every other element
    /// (a CBUSH's GE is per direction: [`super::bush::BushPlacement::structural`]).
    pub fn element_ge(&self, e: &Element) -> f64 {
        let b = &self.bulk;
        let material = |mid: u32| {
            self.materials
                .get(&mid)
                .and_then(|m| match *m {
                    super::MaterialRef::Mat1(i) => b.mat1.get(i).map(|m| m.ge),
                    super::MaterialRef::Mat8(i) => b.mat8.get(i).map(|m| m.ge),
                    super::MaterialRef::Mat2(i) => b.mat2.get(i).map(|m| m.ge),
                })
                .unwrap_or(0.0)
        };
        match (e.kind, e.property) {
            (ElementKind::Celas1 | ElementKind::Celas3, Some(PropertyRef::Pelas(i))) => {
                b.pelas.get(i).map_or(0.0, |p| p.ge)
            }
            (ElementKind::Celas2, _) => b.celas2.get(e.card).map_or(0.0, |c| c.ge),
            (_, Some(PropertyRef::Pshell(i))) => b
                .pshell
                .get(i)
                .and_then(|p| p.mid1.or(p.mid2))
                .map_or(0.0, material),
            (_, Some(PropertyRef::Pcomp(i))) => b.pcomp.get(i).map_or(0.0, |p| p.ge),
            (_, Some(p @ PropertyRef::Psolid(_))) => {
                self.solid_material(p).map_or(0.0, |(_, u)| material(u.mid))
            }
            (k, _) if k.is_line() => match self.line_element(e) {
                Some(Ok((_, used))) => material(used.mid),
                _ => 0.0,
            },
            _ => 0.0,
        }
    }

    /// The elements with viscous damping ("CDAMP2 7", "CBUSH 3" when its PBUSH has a B), at
    /// most `limit` of them.
    pub fn viscous_damping_elements(&self, limit: usize) -> Vec<String> {
        self.elements
            .iter()
            .filter(|e| {
                e.kind.is_damper()
                    || (e.kind == ElementKind::Cbush
                        && matches!(e.property, Some(PropertyRef::Pbush(i))
                            if self.bulk.pbush.get(i).is_some_and(|p| p.b.iter().any(|&b| b != 0.0))))
            })
            .take(limit)
            .map(|e| format!("{} {}", e.kind.card(), e.id))
            .collect()
    }

    /// The elements with structural damping GE ≠ 0 ("CQUAD4 12", "CBUSH 3"), at most `limit`.
    pub fn structural_damping_elements(&self, limit: usize) -> Vec<String> {
        self.elements
            .iter()
            .filter(|e| {
                self.element_ge(e) != 0.0
                    || (e.kind == ElementKind::Cbush
                        && matches!(e.property, Some(PropertyRef::Pbush(i))
                            if self.bulk.pbush.get(i).is_some_and(|p| p.ge.iter().any(|&g| g != 0.0))))
            })
            .take(limit)
            .map(|e| format!("{} {}", e.kind.card(), e.id))
            .collect()
    }
}
