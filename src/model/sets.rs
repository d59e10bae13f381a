//! The static sets case control selects, resolved for the solver:
//! - [`Model::spc_set`]: `SPC = sid` with its `SPCADD` expanded into the SPC / SPC1 entries of
//!   every member set (members in increasing id, SPC before SPC1, card order within);
//! - [`Model::mpc_set`]: `MPC = sid` with its `MPCADD` expanded into the MPC cards of every
//!   member set (members in increasing id, card order within);
//! - [`Model::load_set`]: `LOAD = sid` with its `LOAD` combination expanded into terms of
//!   FORCE / MOMENT vectors and GRAV accelerations in the basic system, the combination factor
//!   S · Si applied;
//! - [`Model::enforced_displacements`]: the SPCD entries of `LOAD = sid` (a member set of a LOAD
//!   combination, or the set itself), their values scaled by the combination factor S · Si.
//!
//! An SPCADD of an SPCADD, an MPCADD of an MPCADD, a LOAD of a LOAD, and a member that selects nothing are errors, as in
//! Nastran ([`SetError`]); the model check rejects them already, and the resolution does not
//! rely on it.

use std::collections::BTreeSet;

use crate::deck::Loc;
use crate::deck::cards::{BulkData, Mpc, SetUnion};

use super::{Dofs, Model};
use crate::card_values::ForceKind;

/// Why a selected set cannot be resolved.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SetError {
    /// No card belongs to the selected set.
    Empty,
    /// The member is itself a combination (SPCADD in SPCADD, LOAD in LOAD).
    Nested(u32),
    /// The member selects no card.
    Missing(u32),
}

/// The card an SPC entry comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SpcCard {
    /// `SPC`: one grid, an enforced value.
    Spc,
    /// `SPC1`: grids held at zero.
    Spc1,
}

impl SpcCard {
    /// Card name.
    pub fn name(self) -> &'static str {
        match self {
            SpcCard::Spc => "SPC",
            SpcCard::Spc1 => "SPC1",
        }
    }
}

/// Components of grids held at a value, from one SPC or SPC1 card.
#[derive(Debug, Clone, PartialEq)]
pub struct SpcEntry {
    pub card: SpcCard,
    /// The set the card belongs to (an SPCADD member, or the selected set itself).
    pub set: u32,
    /// Grid ids.
    pub grids: Vec<u32>,
    pub components: Dofs,
    /// Enforced value (0 for SPC1).
    pub value: f64,
    pub loc: Loc,
}

/// Components of a grid (or a scalar point) moved by an enforced displacement, from one SPCD.
#[derive(Debug, Clone, PartialEq)]
pub struct EnforcedEntry {
    /// The SPCD set (a LOAD member, or the selected set itself).
    pub set: u32,
    /// Grid or scalar point id.
    pub grid: u32,
    pub components: Dofs,
    /// S · Si · D.
    pub value: f64,
    pub loc: Loc,
}

/// A force or moment of a load set at one grid.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PointLoad {
    pub kind: ForceKind,
    /// Grid index into [`Model::grids`].
    pub grid: usize,
    /// The vector in the basic system: S · Si · F · (N1, N2, N3), with N in system CID at the
    /// grid (for a CORD2C the local (e_r, e_θ, e_z) there, [`super::CoordSystem::axes_at`]).
    pub basic: [f64; 3],
}

/// One member of a load set: its FORCE / MOMENT / FORCE1 / FORCE2 / MOMENT1 / MOMENT2 cards,
/// its SLOAD scalar-point loads, and the consistent nodal forces of its
/// PLOAD4 / PLOAD2 / PLOAD pressures ([`crate::fe::pressure`]), the grid loads of its PLOAD1
/// beam loads ([`crate::fe::beam_load`]), and its GRAV accelerations.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct LoadTerm {
    pub point_loads: Vec<PointLoad>,
    /// Uniform translational accelerations S · Si · A · (N1, N2, N3) in the basic system, N in
    /// CID's Cartesian axes.
    pub accelerations: Vec<[f64; 3]>,
    /// SLOAD loads: (scalar point index into the model's scalar points, S · Si · F).
    pub scalar_loads: Vec<(usize, f64)>,
}

impl Model {
    /// The SPC / SPC1 entries of `SPC = sid` (see the module documentation).
    pub fn spc_set(&self, sid: u32) -> Result<Vec<SpcEntry>, SetError> {
        spc_entries(&self.bulk, sid)
    }

    /// The MPC cards of `MPC = sid` (see the module documentation).
    pub fn mpc_set(&self, sid: u32) -> Result<Vec<&Mpc>, SetError> {
        let b = &self.bulk;
        let sets = union_members(&b.mpcadd, sid, |s| b.mpc.iter().any(|x| x.sid == s))?;
        let out: Vec<&Mpc> = sets
            .iter()
            .flat_map(|&s| b.mpc.iter().filter(move |x| x.sid == s))
            .collect();
        if out.is_empty() {
            Err(SetError::Empty)
        } else {
            Ok(out)
        }
    }

    /// The MPC set the subcases select (the model check makes it one for all of them);
    /// `None` also when no MPC/MPCADD card has that id (a warning of the model check).
    pub fn selected_mpc(&self) -> Option<u32> {
        let b = &self.bulk;
        self.subcases.iter().find_map(|s| s.mpc).filter(|&sid| {
            b.mpc.iter().any(|c| c.sid == sid) || b.mpcadd.iter().any(|c| c.sid == sid)
        })
    }

    /// The terms of `LOAD = sid`: one term of factor 1 for a FORCE / MOMENT / GRAV set, one
    /// term per member of a LOAD combination otherwise (see the module documentation).
    pub fn load_set(&self, sid: u32) -> Result<Vec<LoadTerm>, SetError> {
        let members = load_members(&self.bulk, sid)?;
        Ok(members
            .into_iter()
            .map(|(scale, set)| self.load_term(set, scale))
            .collect())
    }

    /// The SPCD entries of `LOAD = sid`, scaled by their combination factor (see the module
    /// documentation); empty when the selection holds no SPCD.
    pub fn enforced_displacements(&self, sid: u32) -> Result<Vec<EnforcedEntry>, SetError> {
        Ok(self.enforced_members(&load_members(&self.bulk, sid)?))
    }

    /// The SPCD entries of the (factor, set) pairs `members`.
    pub fn enforced_members(&self, members: &[(f64, u32)]) -> Vec<EnforcedEntry> {
        members
            .iter()
            .flat_map(|&(scale, set)| {
                (self.bulk.spcd.iter().filter(move |c| c.sid == set)).map(move |c| EnforcedEntry {
                    set,
                    grid: c.grid,
                    components: c.components,
                    value: scale * c.value,
                    loc: c.loc.clone(),
                })
            })
            .collect()
    }

    /// Whether the deck has SUPORT or SUPORT1 cards.
    pub fn has_suport(&self) -> bool {
        !self.bulk.suport.is_empty()
    }

    /// The r-set of a subcase: every SUPORT card's (point, components) and those of the SUPORT1
    /// set `suport1`, each with its card and file:line; an error when `suport1` selects no card.
    pub fn suport_entries(
        &self,
        suport1: Option<u32>,
    ) -> Result<Vec<(u32, Dofs, String)>, SetError> {
        if let Some(sid) = suport1
            && !self.bulk.suport.iter().any(|c| c.sid == Some(sid))
        {
            return Err(SetError::Empty);
        }
        Ok((self.bulk.suport.iter())
            .filter(|c| c.sid.is_none() || c.sid == suport1)
            .flat_map(|c| {
                let source = match c.sid {
                    Some(sid) => format!("SUPORT1 {sid} at {}", c.loc),
                    None => format!("SUPORT at {}", c.loc),
                };
                c.points
                    .iter()
                    .map(move |&(id, dofs)| (id, dofs, source.clone()))
            })
            .collect())
    }

    fn load_term(&self, set: u32, scale: f64) -> LoadTerm {
        let b = &self.bulk;
        let mut term = LoadTerm::default();
        for f in b.forces.iter().filter(|f| f.sid == set) {
            // grids and systems exist in a built model
            let (Some(&grid), Some(cs)) = (self.grid_index.get(&f.grid), self.coords.get(&f.cid))
            else {
                continue;
            };
            let axes = cs.axes_at(self.grids[grid].xyz);
            let n = f.direction;
            let basic = std::array::from_fn(|i| {
                scale * f.scale * (0..3).map(|j| axes[i][j] * n[j]).sum::<f64>()
            });
            term.point_loads.push(PointLoad {
                kind: f.kind,
                grid,
                basic,
            });
        }
        for c in b.forces_by_grids.iter().filter(|c| c.sid == set) {
            // grids and directions are checked when the model is built
            let (Some(&grid), Ok(n)) = (self.grid_index.get(&c.grid), self.direction_by_grids(c))
            else {
                continue;
            };
            term.point_loads.push(PointLoad {
                kind: c.kind,
                grid,
                basic: n.map(|v| scale * c.magnitude * v),
            });
        }
        for c in b.sload.iter().filter(|c| c.sid == set) {
            for &(point, f) in &c.loads {
                if let Some(&k) = self.scalar_index.get(&point) {
                    term.scalar_loads.push((k, scale * f));
                } else if let Some(&grid) = self.grid_index.get(&point) {
                    // on a grid: component T1 of its displacement system (CD)
                    let Some(cs) = self.coords.get(&self.grids[grid].cd) else {
                        continue;
                    };
                    let axes = cs.axes_at(self.grids[grid].xyz);
                    term.point_loads.push(PointLoad {
                        kind: ForceKind::Force,
                        grid,
                        basic: std::array::from_fn(|i| scale * f * axes[i][0]),
                    });
                }
            }
        }
        let faces = (b.pload4.iter().filter(|c| c.sid == set))
            .flat_map(|c| self.pload4_faces(c).unwrap_or_default())
            .chain(
                (b.pload2.iter().filter(|c| c.sid == set))
                    .flat_map(|c| self.pload2_faces(c).unwrap_or_default()),
            )
            .chain(
                (b.pload.iter().filter(|c| c.sid == set)).filter_map(|c| self.pload_face(c).ok()),
            );
        for face in faces {
            let xyz: Vec<[f64; 3]> = face.grids.iter().map(|&g| self.grids[g].xyz).collect();
            let forces = face.forces(&xyz);
            for (&grid, f) in face.grids.iter().zip(forces) {
                term.point_loads.push(PointLoad {
                    kind: ForceKind::Force,
                    grid,
                    basic: f.map(|v| scale * v),
                });
            }
        }
        for c in b.pload1.iter().filter(|c| c.sid == set) {
            term.point_loads
                .extend(self.pload1_loads(c, scale).unwrap_or_default());
        }
        for g in b.grav.iter().filter(|g| g.sid == set) {
            if let Some(cs) = self.coords.get(&g.cid) {
                term.accelerations
                    .push(cs.vector_to_basic(g.direction.map(|x| x * g.a * scale)));
            }
        }
        term
    }
}

fn simple_set_exists(b: &BulkData, sid: u32) -> bool {
    b.static_load_sets().any(|s| s == sid)
}

/// (factor, FORCE/MOMENT/FORCE1/FORCE2/MOMENT1/MOMENT2/SLOAD/GRAV/PLOAD4/PLOAD2/PLOAD/PLOAD1/SPCD set) of each member of `LOAD = sid`.
fn load_members(b: &BulkData, sid: u32) -> Result<Vec<(f64, u32)>, SetError> {
    let combos: Vec<_> = b.load.iter().filter(|l| l.sid == sid).collect();
    if combos.is_empty() {
        return if simple_set_exists(b, sid) {
            Ok(vec![(1.0, sid)])
        } else {
            Err(SetError::Empty)
        };
    }
    let mut members = Vec::new();
    for combo in combos {
        for &(si, li) in &combo.terms {
            // a LOAD named in a LOAD adds nothing (Nastran reads Li as simple sets only)
            if !simple_set_exists(b, li) && b.load.iter().any(|l| l.sid == li) {
                continue;
            }
            if !simple_set_exists(b, li) {
                return Err(SetError::Missing(li));
            }
            members.push((combo.scale * si, li));
        }
    }
    Ok(members)
}

/// The member set ids of `sid`: those of its union cards (`SPCADD` / `MPCADD`), in increasing
/// id, or `sid` itself when no union card has that id. `exists` tells whether a plain set exists.
fn union_members(
    unions: &[SetUnion],
    sid: u32,
    exists: impl Fn(u32) -> bool,
) -> Result<Vec<u32>, SetError> {
    let adds: Vec<_> = unions.iter().filter(|a| a.sid == sid).collect();
    if adds.is_empty() {
        return Ok(vec![sid]);
    }
    let mut sets = BTreeSet::new();
    for a in &adds {
        for &s in &a.sets {
            if unions.iter().any(|x| x.sid == s) {
                return Err(SetError::Nested(s));
            }
            if !exists(s) {
                return Err(SetError::Missing(s));
            }
            sets.insert(s);
        }
    }
    Ok(sets.into_iter().collect())
}

/// The entries of `SPC = sid` in a deck's bulk data.
fn spc_entries(b: &BulkData, sid: u32) -> Result<Vec<SpcEntry>, SetError> {
    let sets = union_members(&b.spcadd, sid, |s| {
        b.spc.iter().any(|x| x.sid == s) || b.spc1.iter().any(|x| x.sid == s)
    })?;
    let mut out = Vec::new();
    for &s in &sets {
        out.extend(b.spc.iter().filter(|x| x.sid == s).map(|x| SpcEntry {
            card: SpcCard::Spc,
            set: s,
            grids: vec![x.grid],
            components: x.components,
            value: x.value,
            loc: x.loc.clone(),
        }));
        out.extend(b.spc1.iter().filter(|x| x.sid == s).map(|x| SpcEntry {
            card: SpcCard::Spc1,
            set: s,
            grids: x.grids.clone(),
            components: x.components,
            value: 0.0,
            loc: x.loc.clone(),
        }));
    }
    if out.is_empty() {
        Err(SetError::Empty)
    } else {
        Ok(out)
    }
}

#[cfg(test)]
mod tests {
    use std::io::Write;

    use super::*;
    use crate::deck::Deck;

    fn deck(bulk: &str) -> Deck {
        let text = format!("SOL 101\nCEND\nBEGIN BULK\n{bulk}ENDDATA\n");
        let mut file = tempfile::Builder::new()
            .suffix(".bdf")
            .tempfile()
            .expect("temp file");
        file.write_all(text.as_bytes()).expect("write deck");
        Deck::read(file.path()).unwrap_or_else(|e| panic!("deck: {e}"))
    }

    /// A flat 2 × 2 CQUAD8 whose mid-side grid G6 (edge G2–G3) is blank, next to a CQUAD4 on
    /// that edge: the element has seven grids, the mesh draws it by its corners, and a uniform
    /// PLOAD4 p on it gives the full element's consistent loads (−pA/12 at the corners, pA/3
    /// at the mid-sides; Zienkiewicz & Taylor vol. 1 §8.8) with the blank mid-side's share
    /// split to G2 and G3 (T^T f): pA/12 each there, total pA. Exact to round-off.
    #[test]
    fn pload4_on_a_cquad8_with_a_blank_midside_grid() {
        let text = "SOL 101\nCEND\nBEGIN BULK\n\
            GRID,1,,0.,0.,0.\nGRID,2,,2.,0.,0.\nGRID,3,,2.,2.,0.\nGRID,4,,0.,2.,0.\n\
            GRID,5,,1.,0.,0.\nGRID,7,,1.,2.,0.\nGRID,8,,0.,1.,0.\n\
            GRID,9,,4.,0.,0.\nGRID,10,,4.,2.,0.\n\
            MAT1,1,70000.,,.3\nPSHELL,1,1,.1,1,,1\n\
            CQUAD8,10,1,1,2,3,4,5,,\n,7,8\nCQUAD4,11,1,2,9,10,3\n\
            PLOAD4,5,10,3.\nENDDATA\n";
        let model = crate::model::testing::model_of_text(text);
        let e = &model.elements[model.element_index[&10]];
        assert_eq!(e.nodes.len(), 7);
        let mesh = model.mesh_arrays();
        let cards: Vec<&str> = mesh.blocks.iter().map(|b| b.card).collect();
        assert_eq!(cards, ["CQUAD4", "CQUAD8_CORNERS"]);
        let loads = model.load_set(5).unwrap();
        let (p, area) = (3.0, 4.0);
        let mut total = 0.0;
        for l in &loads[0].point_loads {
            let id = model.grids[l.grid].id;
            let want = match id {
                1 | 4 => -p * area / 12.0,
                2 | 3 => p * area / 12.0,
                5 | 7 | 8 => p * area / 3.0,
                _ => panic!("load on grid {id}"),
            };
            assert!(
                (l.basic[2] - want).abs() < 1e-12 && l.basic[0].abs() + l.basic[1].abs() < 1e-12,
                "grid {id}: {:?}",
                l.basic
            );
            total += l.basic[2];
        }
        assert!((total - p * area).abs() < 1e-12);
    }

    /// Nested SPCADD and members without cards are errors of the resolution itself, whatever
    /// the model check would say.
    #[test]
    fn spcadd_errors_without_the_model_check() {
        let mut d =
            deck("GRID,1,,0.,0.,0.\nGRID,2,,1.,0.,0.\nSPC1,1,123,1\nSPC,2,2,3,0.\nSPCADD,3,1,2\n");
        let mut nested = d.bulk.spcadd[0].clone();
        (nested.sid, nested.sets) = (4, vec![3]);
        let mut missing = d.bulk.spcadd[0].clone();
        (missing.sid, missing.sets) = (5, vec![1, 77]);
        std::sync::Arc::make_mut(&mut d.bulk)
            .spcadd
            .extend([nested, missing]);
        let union = spc_entries(&d.bulk, 3).expect("union");
        let sets: Vec<_> = union.iter().map(|e| (e.card, e.set)).collect();
        assert_eq!(sets, [(SpcCard::Spc1, 1), (SpcCard::Spc, 2)]);
        assert_eq!(spc_entries(&d.bulk, 4), Err(SetError::Nested(3)));
        assert_eq!(spc_entries(&d.bulk, 5), Err(SetError::Missing(77)));
        assert_eq!(spc_entries(&d.bulk, 99), Err(SetError::Empty));
    }

    /// A LOAD of a LOAD and a LOAD member without FORCE / MOMENT / GRAV are errors of the
    /// resolution itself.
    #[test]
    fn nested_load_without_the_model_check() {
        let mut d = deck("GRID,1,,0.,0.,0.\nFORCE,10,1,,3.,0.,1.,0.\nLOAD,2,2.,1.5,10\n");
        let mut nested = d.bulk.load[0].clone();
        (nested.sid, nested.terms) = (5, vec![(1.0, 2)]);
        let mut missing = d.bulk.load[0].clone();
        (missing.sid, missing.terms) = (6, vec![(1.0, 10), (1.0, 77)]);
        std::sync::Arc::make_mut(&mut d.bulk)
            .load
            .extend([nested, missing]);
        assert_eq!(load_members(&d.bulk, 2), Ok(vec![(3.0, 10)]));
        assert_eq!(load_members(&d.bulk, 10), Ok(vec![(1.0, 10)]));
        assert_eq!(load_members(&d.bulk, 5), Ok(vec![]));
        assert_eq!(load_members(&d.bulk, 6), Err(SetError::Missing(77)));
        assert_eq!(load_members(&d.bulk, 77), Err(SetError::Empty));
    }
}
