//! Constraints and DOF sets: `SPC`, `SPCD`, `SPC1`, `SPCADD`, `MPC`, `MPCADD`, `ASET1`,
//! `SUPORT`, `SUPORT1`.

use crate::card_values::Dofs;
use crate::deck::error::{DeckError, Loc};
use crate::deck::fields::RawCard;
use crate::deck::reader::FieldReader;

/// `SPC` / `SPCD` — single-point constraint with an enforced value / enforced displacement
/// (one entry per grid on the card).
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | SID | int > 0 | required | constraint set id (SPC) / load set id (SPCD) |
/// | 3, 4, 5 | G1 C1 D1 | int, components, real | G1 C1 required; D1 0.0 | grid, components, enforced value |
/// | 6, 7, 8 | G2 C2 D2 | | blank | an optional second grid |
///
/// An `SPCD` set is a load set: `LOAD = sid` selects it in statics (directly or as a member of
/// a `LOAD` combination, whose factors scale D), an RLOAD1/RLOAD2/TLOAD1/TLOAD2 EXCITEID in
/// dynamics. Its DOFs must be constrained by the subcase's SPC set (SPC, SPC1 or GRID PS), as
/// in Nastran; its values replace the D of the SPC there.
#[derive(Debug, Clone, PartialEq)]
pub struct Spc {
    pub sid: u32,
    pub grid: u32,
    pub components: Dofs,
    pub value: f64,
    pub loc: Loc,
}

impl Spc {
    /// Read an `SPC` card (one or two constraints).
    pub fn from_card(card: &RawCard) -> Result<Vec<Self>, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let sid = f.id(1, "SID");
        f.set_id(sid);
        let loc = f.loc();
        let out = f
            .grid_component_values(["G", "C", "D"], Some(0.0))
            .into_iter()
            .map(|(grid, components, value)| Spc {
                sid,
                grid,
                components,
                value,
                loc: loc.clone(),
            })
            .collect();
        f.finish(7)?;
        Ok(out)
    }
}

/// `SPC1` — the same components constrained to zero at a list of grids.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | SID | int > 0 | required | constraint set id |
/// | 3 | C | components | required on grids | components; 0 or blank for scalar points |
/// | 4 … | G1 G2 … | int > 0 (`THRU` allowed) | ≥ 1 required | grids or scalar points |
#[derive(Debug, Clone, PartialEq)]
pub struct Spc1 {
    pub sid: u32,
    pub components: Dofs,
    pub grids: Vec<u32>,
    pub loc: Loc,
}

impl Spc1 {
    /// Read an `SPC1` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let sid = f.id(1, "SID");
        f.set_id(sid);
        // blank or 0 constrains scalar points; the model check refuses it on a grid
        let components = f.dofs(2, "C");
        let grids = f.id_list(3, "G");
        if grids.is_empty() {
            f.card_error("no grid given");
        }
        let loc = f.loc();
        let len = f.len();
        f.finish(len)?;
        Ok(Spc1 {
            sid,
            components,
            grids,
            loc,
        })
    }
}

/// `SPCADD` / `MPCADD` — union of constraint sets (SPC/SPC1 sets, or MPC sets).
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | SID | int > 0 | required | new set id |
/// | 3 … | S1 S2 … | int > 0 | ≥ 1 required | the united set ids |
#[derive(Debug, Clone, PartialEq)]
pub struct SetUnion {
    pub sid: u32,
    pub sets: Vec<u32>,
    pub loc: Loc,
}

/// `SPCADD`: a union of SPC / SPC1 sets.
pub type Spcadd = SetUnion;
/// `MPCADD`: a union of MPC sets.
pub type Mpcadd = SetUnion;

impl SetUnion {
    /// Read an `SPCADD` or `MPCADD` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let sid = f.id(1, "SID");
        f.set_id(sid);
        let sets = f.id_list(2, "S");
        if sets.is_empty() {
            f.card_error("no set id given");
        }
        let loc = f.loc();
        let len = f.len();
        f.finish(len)?;
        Ok(SetUnion { sid, sets, loc })
    }
}

/// One term of an `MPC` equation: a grid's component and its coefficient.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MpcTerm {
    /// Grid or scalar point id.
    pub grid: u32,
    /// Component 1-6 in the grid's displacement frame; 0 for a scalar point.
    pub component: u8,
    pub coefficient: f64,
}

/// `MPC` — multipoint constraint Σ Aⱼ u_j = 0; the first term's DOF is the dependent one.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | SID | int > 0 | required | constraint set id |
/// | 3, 4, 5 | G1 C1 A1 | int > 0, component 1-6 (0 or blank: a scalar point), real ≠ 0 | required | the dependent DOF and its coefficient |
/// | 6, 7, 8 | G2 C2 A2 | | blank | a second term |
/// | continuation 3-5, 6-8 | G3 C3 A3, G4 C4 A4 … | | blank | two more terms per continuation (its fields 2 and 9 blank) |
#[derive(Debug, Clone, PartialEq)]
pub struct Mpc {
    pub sid: u32,
    pub terms: Vec<MpcTerm>,
    pub loc: Loc,
}

impl Mpc {
    /// Read an `MPC` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let sid = f.id(1, "SID");
        f.set_id(sid);
        let len = f.len();
        let mut terms = Vec::new();
        for line in 0..len.div_ceil(8).max(1) {
            let base = 8 * line;
            if line > 0 && !f.value(base + 1).is_blank() {
                f.error(
                    base + 1,
                    "blank",
                    "expected a blank field before G on a continuation",
                );
            }
            for first in [base + 2, base + 5] {
                if (first..first + 3).all(|i| f.value(i).is_blank()) {
                    continue;
                }
                let (gname, cname, aname) = match terms.len() {
                    0 => ("G1", "C1", "A1"),
                    _ => ("Gi", "Ci", "Ai"),
                };
                let grid = f.id(first, gname);
                // blank or 0: a scalar point (the model check refuses it on a grid)
                let code = f.int_or(first + 1, cname, 0);
                let component = match code {
                    0..=6 => code as u8,
                    _ => {
                        f.error(
                            first + 1,
                            cname,
                            format!("expected a single component 1-6 (0 or blank for a scalar point), found {code}"),
                        );
                        1
                    }
                };
                let coefficient = f.real(first + 2, aname);
                if terms.is_empty() && coefficient == 0.0 {
                    f.error(
                        first + 2,
                        aname,
                        "the first coefficient must be nonzero: it divides the equation for the dependent DOF",
                    );
                }
                terms.push(MpcTerm {
                    grid,
                    component,
                    coefficient,
                });
            }
            if !f.value(base + 8).is_blank() {
                f.error(base + 8, "blank", "expected a blank last field");
            }
        }
        if terms.is_empty() {
            f.card_error("no term given: expected G1 C1 A1");
        }
        let loc = f.loc();
        f.finish(len)?;
        Ok(Mpc { sid, terms, loc })
    }
}

/// `ASET1` — DOFs of the analysis (boundary) set, in Nastran's layout. All `ASET1` cards of a
/// deck together form its a-set; paraflex uses it as the boundary DOFs of a `PMOR` (static modes,
/// pROM inputs).
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | C | components | required | components |
/// | 3 … | G1 G2 … | int > 0 (`THRU` allowed) | ≥ 1 required | grids |
#[derive(Debug, Clone, PartialEq)]
pub struct Aset1 {
    pub components: Dofs,
    pub grids: Vec<u32>,
    pub loc: Loc,
}

impl Aset1 {
    /// Read an `ASET1` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let components = f.dofs(1, "C");
        if components.is_empty() {
            f.error(1, "C", "expected components, e.g. 123456");
        }
        let grids = f.id_list(2, "G");
        if grids.is_empty() {
            f.card_error("no grid given");
        }
        let loc = f.loc();
        let len = f.len();
        f.finish(len)?;
        Ok(Aset1 {
            components,
            grids,
            loc,
        })
    }
}

/// `SUPORT` / `SUPORT1` — the DOFs of the r-set (free-body supports): SUPORT cards always
/// apply, a SUPORT1 set when case control selects it (`SUPORT1 = sid`).
///
/// SUPORT:
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2, 3 | ID1 C1 | int > 0, components | required | grid and components |
/// | 4 … | ID2 C2 … | | blank | more pairs (continuations as well) |
///
/// SUPORT1: field 2 SID (int > 0, the set), then the pairs from field 3.
///
/// SOL 103: the r-set must hold the structure statically determinate (the rigid-body check
/// below); the rigid-body modes are then reported at 0 Hz (the mass-orthonormalized static
/// rigid-body shapes). SOL 101 (no PARAM,INREL): the SUPORT DOFs are held like SPCs, their
/// reactions reported as SPC forces, as MSC Nastran does.
#[derive(Debug, Clone, PartialEq)]
pub struct Suport {
    /// `None` for SUPORT, the set id for SUPORT1.
    pub sid: Option<u32>,
    /// (grid or scalar point, components).
    pub points: Vec<(u32, Dofs)>,
    pub loc: Loc,
}

impl Suport {
    /// Read a SUPORT (`set` false) or SUPORT1 (`set` true) card.
    pub fn from_card(card: &RawCard, set: bool) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let sid = set.then(|| {
            let sid = f.id(1, "SID");
            f.set_id(sid);
            sid
        });
        let first = if set { 2 } else { 1 };
        let len = f.len();
        let mut points = Vec::new();
        let mut i = first;
        while i < len.max(first + 1) {
            // SUPORT1's pairs leave the first line's field 9 (index 8) blank: continuation pairs
            // start in field 2 as SUPORT's do
            if set && i % 8 == 0 {
                i += 1;
                continue;
            }
            if f.value(i).is_blank() && f.value(i + 1).is_blank() {
                i += 2;
                continue;
            }
            let k = points.len() + 1;
            let id = f.id(i, &format!("ID{k}"));
            let c = f.dofs(i + 1, &format!("C{k}"));
            points.push((id, c));
            i += 2;
        }
        if points.is_empty() {
            f.card_error("no (ID, C) pair given");
        }
        let loc = f.loc();
        f.finish(len.max(first))?;
        Ok(Suport { sid, points, loc })
    }

    /// The card name.
    pub fn card(&self) -> &'static str {
        if self.sid.is_some() {
            "SUPORT1"
        } else {
            "SUPORT"
        }
    }
}
