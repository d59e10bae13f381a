//! Rigid elements `RBE2` and `RBE3`, imposed by elimination of dependent DOFs (DESIGN.md §4).

use crate::card_values::Dofs;
use crate::deck::error::{DeckError, Loc};
use crate::deck::fields::RawCard;
use crate::deck::reader::FieldReader;
use crate::deck::value::Value;

/// `RBE2` — rigid body: the CM components of every dependent grid follow the independent grid.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | EID | int > 0 | required | element id |
/// | 3 | GN | int > 0 | required | independent grid |
/// | 4 | CM | components | required | dependent components |
/// | 5 … | GM1 GM2 … | int > 0 | ≥ 1 required | dependent grids (`THRU` allowed) |
/// | after the grids | ALPHA | real | 0.0 | thermal expansion (kept; paraflex's rigid elements take no thermal expansion) |
#[derive(Debug, Clone, PartialEq)]
pub struct Rbe2 {
    pub id: u32,
    pub gn: u32,
    pub cm: Dofs,
    pub gm: Vec<u32>,
    pub alpha: f64,
    pub loc: Loc,
}

impl Rbe2 {
    /// Read an `RBE2` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let id = f.id(1, "EID");
        f.set_id(id);
        let gn = f.id(2, "GN");
        let cm = f.dofs(3, "CM");
        if cm.is_empty() {
            f.error(3, "CM", "expected the dependent components, e.g. 123456");
        }
        let len = f.len();
        let alpha_at = (4..=len).find(|&i| matches!(f.value(i), Value::Real(_)));
        let grids_end = alpha_at.map_or(len, |a| a - 1);
        let gm = f.id_list_until(4, grids_end, "GM");
        if gm.is_empty() {
            f.card_error("no dependent grid (GM1 …) given");
        }
        let alpha = alpha_at.map_or(0.0, |a| f.real(a, "ALPHA"));
        let loc = f.loc();
        f.finish(alpha_at.unwrap_or(len).max(4))?;
        Ok(Rbe2 {
            id,
            gn,
            cm,
            gm,
            alpha,
            loc,
        })
    }
}

/// One weighted group of independent grids of an `RBE3`.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Rbe3Group {
    pub weight: f64,
    pub components: Dofs,
    pub grids: Vec<u32>,
}

/// `RBE3` — interpolation element: the reference grid moves with the weighted average of the
/// independent grids.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | EID | int > 0 | required | element id |
/// | 3 | — | blank | | |
/// | 4 | REFGRID | int > 0 | required | dependent (reference) grid |
/// | 5 | REFC | components | required | dependent components |
/// | 6 … | WT1 C1 G1,1 G1,2 … WT2 C2 G2,1 … | real, components, ids | ≥ 1 group | weighted independent groups |
/// | then | `UM` GM1 CM1 GM2 CM2 … | | blank | extra dependent DOFs (not supported: error) |
/// | then | `ALPHA` value | real | 0.0 | thermal expansion (kept, unused) |
#[derive(Debug, Clone, PartialEq)]
pub struct Rbe3 {
    pub id: u32,
    pub refgrid: u32,
    pub refc: Dofs,
    pub groups: Vec<Rbe3Group>,
    pub alpha: f64,
    pub loc: Loc,
}

impl Rbe3 {
    /// Read an `RBE3` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let id = f.id(1, "EID");
        f.set_id(id);
        let refgrid = f.id(3, "REFGRID");
        let refc = f.dofs(4, "REFC");
        if refc.is_empty() {
            f.error(4, "REFC", "expected the dependent components, e.g. 123456");
        }
        let len = f.len();
        let mut groups: Vec<Rbe3Group> = Vec::new();
        let mut alpha = 0.0;
        let mut i = 5;
        while i <= len {
            match f.value(i) {
                Value::Blank => i += 1,
                Value::Real(w) => {
                    let components = f.dofs(i + 1, "C");
                    if components.is_empty() {
                        f.error(i + 1, "C", "expected the components of this weight group");
                    }
                    let mut group = Rbe3Group {
                        weight: *w,
                        components,
                        grids: Vec::new(),
                    };
                    i += 2;
                    while i <= len && matches!(f.value(i), Value::Int(_) | Value::Blank) {
                        if let Some(g) = f.opt_id(i, "G") {
                            group.grids.push(g);
                        }
                        i += 1;
                    }
                    if group.grids.is_empty() {
                        f.error(i.min(len), "G", "weight group has no grid");
                    }
                    if *w <= 0.0 {
                        f.error(i, "WT", format!("weights must be > 0, found {w:e}"));
                    }
                    groups.push(group);
                }
                Value::Text(t) if t.eq_ignore_ascii_case("ALPHA") => {
                    alpha = f.real(i + 1, "ALPHA");
                    i += 2;
                    if f.opt_real(i, "TREF").is_some() {
                        i += 1;
                    }
                }
                Value::Text(t) if t.eq_ignore_ascii_case("UM") => {
                    f.error(i, "UM", "UM (extra dependent DOFs) is not supported");
                    i = len + 1;
                }
                _ => {
                    let found = f.value(i).describe();
                    f.error(
                        i,
                        "WT",
                        format!("expected a weight (real), UM or ALPHA, found {found}"),
                    );
                    i += 1;
                }
            }
        }
        if groups.is_empty() {
            f.card_error("no weighted group of independent grids (WT1 C1 G1,1 …) given");
        }
        let loc = f.loc();
        f.finish(len.max(5))?;
        Ok(Rbe3 {
            id,
            refgrid,
            refc,
            groups,
            alpha,
            loc,
        })
    }
}

/// How an `RSSCON` names what it connects.
#[derive(Debug, Clone, PartialEq)]
pub enum RssconForm {
    /// `ELEM`: a shell element and the solid element its edge meets; the links are found from
    /// the geometry (every shell grid on a line between two grids of the solid's face).
    Elem { shell: u32, solid: u32 },
    /// `GRID`: one or two links, each a shell grid and the bottom and top solid grids of the
    /// solid edge it lies on.
    Grid { links: Vec<[u32; 3]> },
}

/// `RSSCON` — shell-to-solid connector, a multipoint constraint.
///
/// The shell grids on a solid face become dependent on the solid grids of the edge through
/// them (equations in `assembly::rsscon`).
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | RBID | int > 0 | required | element id |
/// | 3 | TYPE | `ELEM` or `GRID` | `ELEM` | how the connection is given |
/// | 4 | ES1 | int > 0 | required | shell element (`ELEM`) or shell grid (`GRID`) |
/// | 5 | EA1 | int > 0 | required | solid element (`ELEM`) or bottom solid grid (`GRID`) |
/// | 6 | EB1 | int > 0 | `GRID`: required | top solid grid (`GRID` only) |
/// | 7–9 | ES2 EA2 EB2 | int > 0 | blank | a second shell grid and its solid grids (`GRID` only) |
#[derive(Debug, Clone, PartialEq)]
pub struct Rsscon {
    pub id: u32,
    pub form: RssconForm,
    pub loc: Loc,
}

impl Rsscon {
    /// Read an `RSSCON` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let id = f.id(1, "RBID");
        f.set_id(id);
        let grid_form = f.choice(2, "TYPE", &[("ELEM", false), ("GRID", true)], Some(false));
        let form = if grid_form {
            let mut links = vec![[f.id(3, "ES1"), f.id(4, "EA1"), f.id(5, "EB1")]];
            if (6..=8).any(|i| !f.value(i).is_blank()) {
                links.push([f.id(6, "ES2"), f.id(7, "EA2"), f.id(8, "EB2")]);
            }
            RssconForm::Grid { links }
        } else {
            for (i, name) in [(5, "EB1"), (6, "ES2"), (7, "EA2"), (8, "EB2")] {
                if !f.value(i).is_blank() {
                    f.error(
                        i,
                        name,
                        "the ELEM form takes a shell and a solid element only",
                    );
                }
            }
            RssconForm::Elem {
                shell: f.id(3, "ES1"),
                solid: f.id(4, "EA1"),
            }
        };
        let loc = f.loc();
        f.finish(8)?;
        Ok(Rsscon { id, form, loc })
    }
}
