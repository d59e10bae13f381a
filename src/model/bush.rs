//! The placement of a `CBUSH`: element axes, spring location and stiffnesses, from the card,
//! its PBUSH and the grids ([`Model::bush`]).
//!
//! - axes: CID ≥ 0 gives the axes of that system at GA; otherwise x runs from GA to GB and y
//!   lies in the plane of x and the orientation vector (GO − GA, or X1–X3 in GA's displacement
//!   system), z = x × v; with neither CID nor GO/X the axes are basic, which Nastran allows for
//!   coincident grids or a grounded bush; non-coincident grids then need an orientation;
//! - location P: OCID = −1 puts P on the segment GA–GB at S (0: GA, 1: GB; coincident grids and
//!   a grounded bush: at GA); OCID ≥ 0 puts P at GA + (S1, S2, S3) in system OCID.

use super::{Element, ElementKind, Model, PropertyRef};
use crate::deck::DeckError;
use crate::deck::cards::BushAxes;
use crate::fe::bush::Bush;
use crate::geometry::vec3::{add, cross, norm, normalize, scale, sub};

/// Relative distance below which GA and GB count as coincident.
const COINCIDENT: f64 = 1e-8;

/// A CBUSH ready for its kernel.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BushPlacement {
    pub pid: u32,
    pub bush: Bush,
    pub k: [f64; 6],
    /// Viscous damping B1–B6 along and about the same axes.
    pub b: [f64; 6],
    /// Structural damping GE1–GE6 ([`BushPlacement::structural`]).
    pub ge: [f64; 6],
}

impl Model {
    /// The placement of a CBUSH element (`None` for another element); `Err` names what is
    /// wrong with its geometry.
    pub fn bush(&self, e: &Element) -> Option<Result<BushPlacement, String>> {
        if e.kind != ElementKind::Cbush {
            return None;
        }
        let c = self.bulk.cbush.get(e.card)?;
        let Some(PropertyRef::Pbush(i)) = e.property else {
            return Some(Err(format!("PID {} is not a PBUSH", c.pid)));
        };
        let pbush = self.bulk.pbush.get(i)?;
        let (k, b, ge) = (pbush.k, pbush.b, pbush.ge);
        let xa = self.grids.get(*e.nodes.first()?)?.xyz;
        let xb = e
            .nodes
            .get(1)
            .and_then(|&j| self.grids.get(j))
            .map(|g| g.xyz);
        let span = xb.map(|b| sub(b, xa));
        let scale_of = norm(xa).max(xb.map_or(0.0, norm)).max(1.0);
        let line = span.filter(|d| norm(*d) > COINCIDENT * scale_of);
        let axes = match (c.axes, line) {
            (BushAxes::System(cid), _) => {
                let t = self.coords.get(&cid)?.axes_at(xa);
                std::array::from_fn(|r| std::array::from_fn(|col| t[col][r]))
            }
            (BushAxes::Blank, None) => [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
            (BushAxes::Blank, Some(_)) => {
                return Some(Err("GA and GB are apart and neither GO/X1-X3 nor CID is given: give an orientation or CID".into()));
            }
            (BushAxes::Grid(_) | BushAxes::Vector(_), None) => {
                return Some(Err("GA and GB coincide (or GB is blank): the orientation GO/X1-X3 needs GA ≠ GB; give CID".into()));
            }
            (BushAxes::Grid(go), Some(d)) => match self.grid(go) {
                Some(g) => match oriented_axes(d, sub(g.xyz, xa)) {
                    Some(a) => a,
                    None => return Some(Err(format!("GO = {go} lies on the line GA-GB"))),
                },
                None => return Some(Err(format!("GO = {go} does not exist"))),
            },
            (BushAxes::Vector(v), Some(d)) => {
                let cd = self.grids[e.nodes[0]].cd;
                let t = self.coords.get(&cd)?.axes_at(xa);
                let v_basic = std::array::from_fn(|r| (0..3).map(|j| t[r][j] * v[j]).sum());
                match oriented_axes(d, v_basic) {
                    Some(a) => a,
                    None => {
                        return Some(Err("X1-X3 is zero or parallel to GA-GB".into()));
                    }
                }
            }
        };
        let p = if c.ocid >= 0 {
            let t = self.coords.get(&(c.ocid as u32))?.axes_at(xa);
            let o: [f64; 3] = std::array::from_fn(|r| (0..3).map(|j| t[r][j] * c.offset[j]).sum());
            add(xa, o)
        } else {
            add(xa, scale(line.unwrap_or([0.0; 3]), c.s))
        };
        Some(Ok(BushPlacement {
            pid: c.pid,
            bush: Bush {
                axes,
                arm_a: sub(p, xa),
                arm_b: xb.map(|b| sub(p, b)),
            },
            k,
            b,
            ge,
        }))
    }
}

impl BushPlacement {
    /// The stiffnesses GEᵢ·kᵢ of the structural damping matrix (its imaginary stiffness): with
    /// GE1 alone (GE2–GE6 zero) Nastran's single element GE, GE1·K; otherwise one GE per
    /// direction, as OptiStruct's PBUSH.
    pub fn structural(&self) -> [f64; 6] {
        if self.ge[1..].iter().all(|&g| g == 0.0) {
            self.k.map(|k| self.ge[0] * k)
        } else {
            std::array::from_fn(|i| self.ge[i] * self.k[i])
        }
    }
}

/// Rows x, y, z: x along `d`, y in the plane of x and `v`, z = x × v.
fn oriented_axes(d: [f64; 3], v: [f64; 3]) -> Option<[[f64; 3]; 3]> {
    let x = normalize(d)?;
    let z = normalize(cross(x, v))?;
    Some([x, cross(z, x), z])
}

/// The geometry errors of every CBUSH, at its card.
pub(super) fn check(model: &Model) -> Vec<DeckError> {
    model
        .elements
        .iter()
        .filter_map(|e| match model.bush(e)? {
            Err(reason) => {
                let c = model.bulk.cbush.get(e.card)?;
                Some(DeckError::at(&c.loc, reason).on_card(format!("CBUSH {}", e.id)))
            }
            Ok(_) => None,
        })
        .collect()
}
