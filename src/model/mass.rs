//! Mass properties, like the summary of Nastran's grid-point weight generator.
//!
//! Convention (the same as pyNastran's `mass_properties`, with exact geometry):
//! - every element's mass is a point mass at the element's exact centroid (∫x dA / A for shells,
//!   ∫x dV / V for solids, see [`geometry`](super::geometry)); element rotary inertia is not added;
//! - shells: m = ∫(ρ t + NSM) dA for `PSHELL`, t bilinear/linear between the corner thicknesses
//!   when the element gives them (pyNastran uses the mean corner thickness × A), (ρ of MID1, or of MID2 when MID1 is blank) and
//!   m = A · (Σ over the full stack ρᵢ tᵢ + NSM) for `PCOMP` (LAM = SYM doubles the plies, not
//!   NSM); ZOFFS and the PCOMP Z0 do not move the mass point (as in pyNastran);
//! - solids: m = ρ V with ρ of the PSOLID's MAT1;
//! - rods and beams: m = (ρ A + NSM) L at the middle of the element axis, L and the ends
//!   between the offset points (A of PTUBE and PBARL/PBEAML from the shape's dimensions);
//! - `CONM2`: mass M at the grid + offset: CID = 0 offset in basic; CID = −1: X is the CG in
//!   basic; CID > 0: X are components along the local Cartesian axes of CID at the grid (for a
//!   CORD2C: e_r, e_θ, e_z, Nastran QRG CONM2 remark; pyNastran instead reads X as (R, θ, z)
//!   point coordinates, which agrees only when X2 = 0 at a grid with θ = 0 or X1 = X2 = 0). Its own
//!   inertia is added about its CG, rotated from the CID axes into basic (J_basic = T J Tᵀ, T the
//!   CID axes as columns; pyNastran drops it when CID > 0).
//!
//! CONM2 inertia signs, Nastran QRG: I11 = ∫(x2² + x3²) dm, I21 = ∫x1 x2 dm, …, and the
//! inertia matrix is [[I11, −I21, −I31], [−I21, I22, −I32], [−I31, −I32, I33]]: "the negative
//! signs for the off-diagonal terms are supplied automatically". So I21 is the *positive*
//! product of inertia and the tensor entry is −I21. (pyNastran adds −I21 to its positive
//! product Ixy, i.e. the opposite sign, see tools/conformance/PYNASTRAN_MASS.md §5; the decks
//! compared with pyNastran use diagonal CONM2 inertia only.)
//!
//! Totals: M = WTMASS · Σ m; cg = Σ m x / Σ m (not scaled); the inertia **tensor** about the
//! CG, I = WTMASS · (Σ m (|d|² 1 − d dᵀ) + Σ J_CONM2), d = x − cg, so the off-diagonal entries
//! are −Σ m dx dy (negative products). WTMASS multiplies mass and inertia because that is the
//! mass that enters the mass matrix (Nastran's GPWG prints weight units, i.e. without WTMASS).

use crate::card_values::CornerThickness;
use crate::deck::cards::Conm2;
use crate::geometry::mat3::{IDENTITY, mul_vec};
use crate::geometry::rotation::rotate_tensor;
use crate::geometry::vec3::{add, dot, scale, sub};

use super::geometry;
use super::{Element, ElementKind, Model, PropertyRef};

/// Total mass, centre of gravity and inertia tensor about the CG (basic system).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct MassProperties {
    /// WTMASS × Σ element masses.
    pub mass: f64,
    /// Centre of gravity in basic (the origin when the mass is zero).
    pub cg: [f64; 3],
    /// Inertia tensor about the CG with negative products off the diagonal, × WTMASS.
    pub inertia_cg: [[f64; 3]; 3],
    /// The PARAM,WTMASS applied.
    pub wtmass: f64,
}

/// The mass contribution of one element: point mass, its location, and its own inertia tensor
/// about that point (basic axes; only CONM2 has one).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MassPoint {
    pub mass: f64,
    pub point: [f64; 3],
    pub inertia: Option<[[f64; 3]; 3]>,
}

impl Model {
    /// Mass properties of the whole model (see the module documentation for the convention).
    pub fn mass_properties(&self) -> MassProperties {
        // two passes over the elements (the CG, then the inertia about it) rather than a list of
        // every mass point: a million-element model would hold ~100 MB for it
        let points = || self.elements.iter().filter_map(|e| self.element_mass(e));
        let (total, moment) = points().fold((0.0, [0.0; 3]), |(m, s), p| {
            (m + p.mass, add(s, scale(p.point, p.mass)))
        });
        let cg = if total != 0.0 {
            scale(moment, 1.0 / total)
        } else {
            [0.0; 3]
        };
        let mut inertia = [[0.0; 3]; 3];
        for p in points() {
            let d = sub(p.point, cg);
            let d2 = dot(d, d);
            for a in 0..3 {
                for b in 0..3 {
                    let delta = if a == b { d2 } else { 0.0 };
                    inertia[a][b] += p.mass * (delta - d[a] * d[b]);
                    if let Some(j) = p.inertia {
                        inertia[a][b] += j[a][b];
                    }
                }
            }
        }
        let w = self.params.wtmass;
        MassProperties {
            mass: w * total,
            cg,
            inertia_cg: inertia.map(|row| row.map(|v| w * v)),
            wtmass: w,
        }
    }

    /// The mass point of one element (`None` for massless elements and springs).
    pub fn element_mass(&self, e: &Element) -> Option<MassPoint> {
        let p = self.positions(e);
        match e.kind {
            ElementKind::Quad4 | ElementKind::QuadR => {
                let q = <[[f64; 3]; 4]>::try_from(p).ok()?;
                let w = self.corner_densities::<4>(
                    e.property?,
                    self.shell_placement(e)?.corners.as_ref(),
                )?;
                let (mass, point) = geometry::quad_weighted(&q, w);
                Some(MassPoint {
                    mass,
                    point,
                    inertia: None,
                })
            }
            ElementKind::Tria3 | ElementKind::TriaR => {
                let t = <[[f64; 3]; 3]>::try_from(p).ok()?;
                let w = self.corner_densities::<3>(
                    e.property?,
                    self.shell_placement(e)?.corners.as_ref(),
                )?;
                let (mass, point) = geometry::tria_weighted(&t, w);
                Some(MassPoint {
                    mass,
                    point,
                    inertia: None,
                })
            }
            ElementKind::Quad8 | ElementKind::Tria6 => {
                let corners = self.shell_placement(e)?.corners;
                let w: Vec<f64> = if e.kind == ElementKind::Quad8 {
                    self.corner_densities::<4>(e.property?, corners.as_ref())?
                        .to_vec()
                } else {
                    self.corner_densities::<3>(e.property?, corners.as_ref())?
                        .to_vec()
                };
                let layout = self.quadratic_layout(e)?;
                let (mass, point) = crate::fe::shell_quadratic::weighted(layout, &p, &w).ok()?;
                Some(MassPoint {
                    mass,
                    point,
                    inertia: None,
                })
            }
            ElementKind::Cshear => {
                let q = <[[f64; 3]; 4]>::try_from(p).ok()?;
                let ps = self.pshear(e)?;
                let mu = ps.nsm + self.rho(ps.mid).unwrap_or(0.0) * ps.t;
                let (mass, point) = geometry::quad_weighted(&q, [mu; 4]);
                Some(MassPoint {
                    mass,
                    point,
                    inertia: None,
                })
            }
            ElementKind::Hexa8
            | ElementKind::Penta6
            | ElementKind::Tetra4
            | ElementKind::Tetra10
            | ElementKind::Hexa20
            | ElementKind::Penta15
            | ElementKind::Pyram5 => {
                let PropertyRef::Psolid(i) = e.property? else {
                    return None;
                };
                let rho = self.rho(self.bulk.psolid.get(i)?.mid)?;
                let (volume, centroid) = self.solid_midsides(e)?.volume_and_centroid(&p).ok()?;
                Some(MassPoint {
                    mass: rho * volume,
                    point: centroid,
                    inertia: None,
                })
            }
            ElementKind::Celas1
            | ElementKind::Celas2
            | ElementKind::Celas3
            | ElementKind::Celas4
            | ElementKind::Cdamp1
            | ElementKind::Cdamp2
            | ElementKind::Cdamp3
            | ElementKind::Cdamp4
            | ElementKind::Cvisc
            | ElementKind::Cbush
            // a scalar mass acts along one component: no point mass (values.rs warns)
            | ElementKind::Cmass2 => None,
            ElementKind::Conm2 => self.conm2_mass(self.bulk.conm2.get(e.card)?, *p.first()?),
            ElementKind::Crod
            | ElementKind::Conrod
            | ElementKind::Ctube
            | ElementKind::Cbar
            | ElementKind::Cbeam => {
                let (line, material) = self.line_element(e)?.ok()?;
                let rho = material.material.map_or(0.0, |m| m.rho());
                let geometry = line.geometry();
                let ends = [
                    add(geometry.grids[0], geometry.offsets[0]),
                    add(geometry.grids[1], geometry.offsets[1]),
                ];
                let length = crate::geometry::vec3::norm(sub(ends[1], ends[0]));
                Some(MassPoint {
                    mass: (rho * line.section.a + line.section.nsm) * length,
                    point: scale(add(ends[0], ends[1]), 0.5),
                    inertia: None,
                })
            }
            ElementKind::Cbend => {
                let (bend, material) = self.bend_element(e)?.ok()?;
                let rho = material.material.map_or(0.0, |m| m.rho());
                let arc = bend.arc;
                // the centroid of a circular arc: on its bisector at R sin(Θ/2)/(Θ/2)
                let half = 0.5 * arc.angle;
                let bisector = sub(arc.point(half), arc.centre);
                Some(MassPoint {
                    mass: (rho * bend.section.a + bend.section.nsm) * arc.length(),
                    point: add(arc.centre, scale(bisector, half.sin() / half)),
                    inertia: None,
                })
            }
        }
    }

    /// Shell mass per unit area at each corner: ρ tᵢ + NSM for a PSHELL (tᵢ from the element's
    /// corner thicknesses: TFLAG = 1 ratios of T, TFLAG = 0 actual values, blank = T), and
    /// Σ ρᵢ tᵢ + NSM over the full stack for a PCOMP (corner thicknesses do not apply to PCOMP).
    fn corner_densities<const N: usize>(
        &self,
        prop: PropertyRef,
        corners: Option<&CornerThickness>,
    ) -> Option<[f64; N]> {
        match prop {
            PropertyRef::Pshell(i) => {
                let ps = self.bulk.pshell.get(i)?;
                let rho = ps.mid1.or(ps.mid2).and_then(|m| self.rho(m)).unwrap_or(0.0);
                let mut out = [ps.nsm + rho * ps.t; N];
                if let Some(c) = corners {
                    for (k, slot) in out.iter_mut().enumerate() {
                        let t = match c.t.get(k).copied().flatten() {
                            Some(ti) if c.relative => ti * ps.t,
                            Some(ti) => ti,
                            None => ps.t,
                        };
                        *slot = ps.nsm + rho * t;
                    }
                }
                Some(out)
            }
            PropertyRef::Pcomp(i) => {
                let pc = self.bulk.pcomp.get(i)?;
                let plies: f64 = pc
                    .full_stack()
                    .iter()
                    .map(|ply| self.rho(ply.mid).unwrap_or(0.0) * ply.t)
                    .sum();
                Some([plies + pc.nsm; N])
            }
            _ => None,
        }
    }

    fn conm2_mass(&self, c: &Conm2, grid: [f64; 3]) -> Option<MassPoint> {
        let [i11, i21, i22, i31, i32, i33] = c.inertia;
        let local = [[i11, -i21, -i31], [-i21, i22, -i32], [-i31, -i32, i33]];
        let (point, t) = match c.cid {
            -1 => (c.offset, IDENTITY),
            0 => (add(grid, c.offset), IDENTITY),
            cid => {
                let sys = self.coords.get(&u32::try_from(cid).ok()?)?;
                let t = sys.axes_at(grid);
                (add(grid, mul_vec(&t, c.offset)), t)
            }
        };
        let inertia = if c.inertia.iter().all(|v| *v == 0.0) {
            None
        } else {
            Some(rotate_tensor(&t, &local))
        };
        Some(MassPoint {
            mass: c.mass,
            point,
            inertia,
        })
    }
}
