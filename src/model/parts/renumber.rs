//! A part superelement's cards placed into the assembled bulk data: each part is its own id
//! namespace, so its element, property, material and coordinate-system ids are mapped into the
//! assembled model's, and every reference of its cards must name an id the part defines.
//!
//! Policy: the residual (main bulk data) keeps all its ids; a part keeps an id when no earlier
//! namespace (residual, then parts by increasing SEID) uses it in that space, and otherwise gets
//! the next id above every id used in the space (listed in a warning). Grid ids are never
//! changed (results are reported by grid id): a part grid whose id another namespace uses is
//! resolved by [`super::connect`]. Set ids (SPC, LOAD, FORCE … SIDs) are shared by all parts, as
//! case control selects one set id for the whole model.

use std::collections::{BTreeMap, HashMap, HashSet};

use crate::card_values::{ShellOrientation, SpringEnd};
use crate::deck::cards::{BulkData, Grdset, Pload4Target};
use crate::deck::{DeckError, Loc, PartBulk};

/// The cards a part section may hold; any other card is refused at its first occurrence.
pub const SUPPORTED: &[&str] = &[
    "GRID", "GRDSET", "CORD2R", "CORD2C", "CORD2S", "CQUAD4", "CTRIA3", "CQUADR", "CTRIAR",
    "CQUAD8", "CTRIA6", "CHEXA", "CPENTA", "CTETRA", "CELAS1", "CELAS2", "CONM2", "RBE2", "MAT1",
    "MAT8", "PSHELL", "PCOMP", "PSOLID", "PELAS", "SPC", "SPC1", "SPCADD", "FORCE", "MOMENT",
    "PLOAD2", "PLOAD4", "GRAV", "LOAD", "PARAM", "ASET", "ASET1", "QSET", "QSET1", "POINT",
];

/// Id spaces renumbered per part.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Space {
    Element,
    Property,
    Material,
    Coord,
}

impl Space {
    fn name(self) -> &'static str {
        match self {
            Space::Element => "element",
            Space::Property => "property",
            Space::Material => "material",
            Space::Coord => "coordinate system",
        }
    }
}

/// The ids used so far in each renumbered space of the assembled model.
#[derive(Default)]
pub struct UsedIds(HashMap<Space, HashSet<u32>>);

impl UsedIds {
    /// The ids the residual's cards define.
    pub fn of_residual(b: &BulkData) -> Self {
        let mut used = UsedIds::default();
        for (space, id) in defined_ids(b) {
            used.0.entry(space).or_default().insert(id);
        }
        used
    }

    /// A fresh id in `space`, above every id used there; marked used.
    pub fn fresh(&mut self, space: Space) -> u32 {
        let set = self.0.entry(space).or_default();
        let id = set.iter().max().map_or(1, |m| m + 1);
        set.insert(id);
        id
    }

    fn take(&mut self, space: Space, id: u32) -> u32 {
        let set = self.0.entry(space).or_default();
        if set.insert(id) {
            id
        } else {
            let id = set.iter().max().map_or(1, |m| m + 1);
            set.insert(id);
            id
        }
    }
}

/// Every (space, id) a bulk data section defines.
fn defined_ids(b: &BulkData) -> Vec<(Space, u32)> {
    let el = |id: u32| (Space::Element, id);
    let mut out: Vec<(Space, u32)> = Vec::new();
    out.extend(b.cquad4.iter().chain(&b.cquadr).map(|c| el(c.id)));
    out.extend(b.ctria3.iter().chain(&b.ctriar).map(|c| el(c.id)));
    out.extend(b.cquad8.iter().chain(&b.ctria6).map(|c| el(c.id)));
    out.extend(b.chexa.iter().map(|c| el(c.id)));
    out.extend(b.cpenta.iter().map(|c| el(c.id)));
    out.extend(b.ctetra.iter().map(|c| el(c.id)));
    out.extend(b.cpyram.iter().map(|c| el(c.id)));
    out.extend(b.cshear.iter().map(|c| el(c.id)));
    out.extend(b.celas1.iter().map(|c| el(c.id)));
    out.extend(b.celas2.iter().map(|c| el(c.id)));
    out.extend(b.celas3.iter().map(|c| el(c.id)));
    out.extend(b.celas4.iter().map(|c| el(c.id)));
    out.extend(b.cdamp1.iter().chain(&b.cdamp3).map(|c| el(c.id)));
    out.extend(b.cdamp2.iter().chain(&b.cdamp4).map(|c| el(c.id)));
    out.extend(b.cvisc.iter().map(|c| el(c.id)));
    out.extend(b.cmass2.iter().map(|c| el(c.id)));
    out.extend(b.cbush.iter().map(|c| el(c.id)));
    out.extend(b.conm2.iter().map(|c| el(c.id)));
    out.extend(b.crod.iter().chain(&b.ctube).map(|c| el(c.id)));
    out.extend(b.conrod.iter().map(|c| el(c.id)));
    out.extend(b.cbar.iter().chain(&b.cbeam).map(|c| el(c.id)));
    out.extend(b.rbe2.iter().map(|c| el(c.id)));
    out.extend(b.rbe3.iter().map(|c| el(c.id)));
    out.extend(b.rsscon.iter().map(|c| el(c.id)));
    let pr = |id: u32| (Space::Property, id);
    out.extend(b.pshell.iter().map(|c| pr(c.id)));
    out.extend(b.pcomp.iter().map(|c| pr(c.id)));
    out.extend(b.psolid.iter().map(|c| pr(c.id)));
    out.extend(b.pshear.iter().map(|c| pr(c.id)));
    out.extend(b.pelas.iter().map(|c| pr(c.id)));
    out.extend(b.pdamp.iter().map(|c| pr(c.id)));
    out.extend(b.pvisc.iter().map(|c| pr(c.id)));
    out.extend(b.pbush.iter().map(|c| pr(c.id)));
    out.extend(b.prod.iter().map(|c| pr(c.id)));
    out.extend(b.ptube.iter().map(|c| pr(c.id)));
    out.extend(b.pbar.iter().map(|c| pr(c.id)));
    out.extend(b.pbarl.iter().chain(&b.pbeaml).map(|c| pr(c.id)));
    out.extend(b.pbeam.iter().map(|c| pr(c.id)));
    let ma = |id: u32| (Space::Material, id);
    out.extend(b.mat1.iter().map(|c| ma(c.id)));
    out.extend(b.mat2.iter().map(|c| ma(c.id)));
    out.extend(b.mat8.iter().map(|c| ma(c.id)));
    out.extend(b.coords.iter().map(|c| (Space::Coord, c.id)));
    out
}

/// How one part's ids map into the assembled model.
pub struct PartMap {
    pub seid: u32,
    ids: HashMap<(Space, u32), u32>,
    grids: HashSet<u32>,
    /// The system the part's basic system becomes (0 when the part is not moved).
    basic: u32,
    defaults: Grdset,
}

impl PartMap {
    /// Map the part's ids: kept when free, else fresh (see the module documentation).
    /// `basic` is the system that stands for the part's basic system.
    pub fn new(part: &PartBulk, used: &mut UsedIds, basic: u32) -> Self {
        let mut ids = HashMap::new();
        let mut defined: Vec<(Space, u32)> = defined_ids(&part.bulk);
        defined.sort();
        defined.dedup();
        for (space, id) in defined {
            ids.insert((space, id), used.take(space, id));
        }
        let defaults = part.bulk.grdset.first().cloned().unwrap_or(Grdset {
            cp: 0,
            cd: 0,
            ps: crate::card_values::Dofs::NONE,
            loc: part.loc.clone(),
        });
        PartMap {
            seid: part.seid,
            ids,
            grids: part.bulk.grids.iter().map(|g| g.id).collect(),
            basic,
            defaults,
        }
    }

    /// The ids that changed, by space: (old, new).
    pub fn renumbered(&self) -> BTreeMap<Space, Vec<(u32, u32)>> {
        let mut out: BTreeMap<Space, Vec<(u32, u32)>> = BTreeMap::new();
        for (&(space, old), &new) in &self.ids {
            if old != new {
                out.entry(space).or_default().push((old, new));
            }
        }
        out.values_mut().for_each(|v| v.sort());
        out
    }

    /// One line per space with changed ids, for the part's warning.
    pub fn renumbered_text(&self) -> Vec<String> {
        self.renumbered()
            .into_iter()
            .map(|(space, pairs)| {
                let listed: Vec<String> = pairs.iter().map(|(o, n)| format!("{o}→{n}")).collect();
                format!("{} ids {}", space.name(), listed.join(" "))
            })
            .collect()
    }
}

/// Maps the references of one card of a part, collecting errors for ids the part lacks.
struct Mapper<'a> {
    map: &'a PartMap,
    errors: &'a mut Vec<DeckError>,
    card: &'static str,
    loc: &'a Loc,
}

impl Mapper<'_> {
    fn missing(&mut self, what: &str, id: impl std::fmt::Display) {
        self.errors.push(
            DeckError::at(
                self.loc,
                format!(
                    "{} of part superelement {} refers to {what} {id}, which part {} does not define (a part's cards refer only to its own BEGIN SUPER section)",
                    self.card, self.map.seid, self.map.seid
                ),
            )
            .on_card(self.card.to_string()),
        );
    }

    fn id(&mut self, space: Space, id: u32) -> u32 {
        match self.map.ids.get(&(space, id)) {
            Some(&new) => new,
            None => {
                self.missing(space.name(), id);
                id
            }
        }
    }

    fn coord(&mut self, id: u32) -> u32 {
        if id == 0 {
            self.map.basic
        } else {
            self.id(Space::Coord, id)
        }
    }

    fn grid(&mut self, id: u32) -> u32 {
        if id != 0 && !self.map.grids.contains(&id) {
            self.missing("grid", id);
        }
        id
    }

    fn grids(&mut self, ids: &[u32]) {
        for &g in ids {
            self.grid(g);
        }
    }

    /// A shell element's id, property, grids and material orientation system.
    fn shell(&mut self, id: &mut u32, pid: &mut u32, nodes: &[u32], o: &mut ShellOrientation) {
        *id = self.id(Space::Element, *id);
        *pid = self.id(Space::Property, *pid);
        self.grids(nodes);
        if let ShellOrientation::Mcid(c) = o {
            *c = self.coord(*c);
        }
    }

    /// A use of a card that a part may not make, with the reason.
    fn refuse(&mut self, why: &str) {
        self.errors.push(
            DeckError::at(
                self.loc,
                format!(
                    "{} in part superelement {}: {why}",
                    self.card, self.map.seid
                ),
            )
            .on_card(self.card.to_string()),
        );
    }

    fn end(&mut self, e: &SpringEnd) {
        if let Some(g) = e.grid {
            self.grid(g);
        }
    }
}

/// Append the part's cards, mapped, to `out`. Reduction sets (ASET, ASET1, QSET, QSET1) are
/// checked and returned (they are not honoured); GRDSET fills the part's blank GRID fields.
pub fn place(
    part: &PartBulk,
    map: &PartMap,
    out: &mut BulkData,
    errors: &mut Vec<DeckError>,
) -> Vec<Loc> {
    let b = &part.bulk;
    macro_rules! each {
        ($field:ident, $card:expr, |$m:ident, $c:ident| $body:block) => {
            for original in &b.$field {
                // some cards are only checked, not changed
                #[allow(unused_mut)]
                let mut $c = original.clone();
                let mut $m = Mapper {
                    map,
                    errors,
                    card: $card,
                    loc: &original.loc,
                };
                $body
                out.$field.push($c);
            }
        };
    }
    each!(grids, "GRID", |m, c| {
        let d = &m.map.defaults;
        c.cp = Some(m.coord(c.cp.unwrap_or(d.cp)));
        c.cd = Some(m.coord(c.cd.unwrap_or(d.cd)));
        c.ps = Some(c.ps.unwrap_or(d.ps));
    });
    each!(coords, "CORD2x", |m, c| {
        c.id = m.id(Space::Coord, c.id);
        c.rid = m.coord(c.rid);
    });
    each!(cquad4, "CQUAD4", |m, c| {
        m.shell(&mut c.id, &mut c.pid, &c.nodes, &mut c.orientation);
    });
    each!(cquadr, "CQUADR", |m, c| {
        m.shell(&mut c.id, &mut c.pid, &c.nodes, &mut c.orientation);
    });
    each!(ctria3, "CTRIA3", |m, c| {
        m.shell(&mut c.id, &mut c.pid, &c.nodes, &mut c.orientation);
    });
    each!(ctriar, "CTRIAR", |m, c| {
        m.shell(&mut c.id, &mut c.pid, &c.nodes, &mut c.orientation);
    });
    each!(cquad8, "CQUAD8", |m, c| {
        m.shell(&mut c.id, &mut c.pid, &c.nodes, &mut c.orientation);
    });
    each!(ctria6, "CTRIA6", |m, c| {
        m.shell(&mut c.id, &mut c.pid, &c.nodes, &mut c.orientation);
    });
    each!(chexa, "CHEXA", |m, c| {
        c.id = m.id(Space::Element, c.id);
        c.pid = m.id(Space::Property, c.pid);
        m.grids(&c.nodes);
    });
    each!(cpenta, "CPENTA", |m, c| {
        c.id = m.id(Space::Element, c.id);
        c.pid = m.id(Space::Property, c.pid);
        m.grids(&c.nodes);
    });
    each!(ctetra, "CTETRA", |m, c| {
        c.id = m.id(Space::Element, c.id);
        c.pid = m.id(Space::Property, c.pid);
        m.grids(&c.nodes);
    });
    each!(celas1, "CELAS1", |m, c| {
        c.id = m.id(Space::Element, c.id);
        c.pid = m.id(Space::Property, c.pid);
        c.ends.iter().for_each(|e| m.end(e));
    });
    each!(celas2, "CELAS2", |m, c| {
        c.id = m.id(Space::Element, c.id);
        c.ends.iter().for_each(|e| m.end(e));
    });
    each!(conm2, "CONM2", |m, c| {
        c.id = m.id(Space::Element, c.id);
        m.grid(c.grid);
        if c.cid >= 0 {
            c.cid = m.coord(c.cid as u32) as i32;
        } else if m.map.basic != 0 {
            // CID = -1 gives the offset in the part's basic system, which the part's move
            // turns into the moved system's coordinates; refuse rather than misplace it
            m.refuse("CID = -1 (an offset in the basic system) is not supported in a part moved by SELOC");
        }
    });
    each!(rbe2, "RBE2", |m, c| {
        c.id = m.id(Space::Element, c.id);
        m.grid(c.gn);
        m.grids(&c.gm);
    });
    each!(mat1, "MAT1", |m, c| {
        c.id = m.id(Space::Material, c.id);
    });
    each!(mat8, "MAT8", |m, c| {
        c.id = m.id(Space::Material, c.id);
    });
    each!(pshell, "PSHELL", |m, c| {
        c.id = m.id(Space::Property, c.id);
        for id in [&mut c.mid1, &mut c.mid2, &mut c.mid3, &mut c.mid4]
            .into_iter()
            .flatten()
        {
            *id = m.id(Space::Material, *id);
        }
    });
    each!(pcomp, "PCOMP", |m, c| {
        c.id = m.id(Space::Property, c.id);
        for ply in &mut c.plies {
            ply.mid = m.id(Space::Material, ply.mid);
        }
    });
    each!(psolid, "PSOLID", |m, c| {
        c.id = m.id(Space::Property, c.id);
        c.mid = m.id(Space::Material, c.mid);
        if c.cordm >= 0 {
            c.cordm = i64::from(m.coord(c.cordm as u32));
        }
    });
    each!(pelas, "PELAS", |m, c| {
        c.id = m.id(Space::Property, c.id);
    });
    each!(spc, "SPC", |m, c| {
        m.grid(c.grid);
    });
    each!(spc1, "SPC1", |m, c| {
        m.grids(&c.grids);
    });
    each!(spcadd, "SPCADD", |_m, _c| {});
    each!(forces, "FORCE", |m, c| {
        m.grid(c.grid);
        c.cid = m.coord(c.cid);
    });
    each!(pload2, "PLOAD2", |m, c| {
        if let Some((first, last)) = c.range.take() {
            // THRU covers the part's elements in the range; map each of them
            let mut ids: Vec<u32> = (m.map.ids.keys())
                .filter(|(s, id)| *s == Space::Element && (first..=last).contains(id))
                .map(|(_, id)| *id)
                .collect();
            ids.sort_unstable();
            c.elements.extend(ids);
        }
        c.elements = c
            .elements
            .iter()
            .map(|&e| m.id(Space::Element, e))
            .collect();
    });
    each!(pload4, "PLOAD4", |m, c| {
        match &mut c.target {
            Pload4Target::Element { eid, g1, g34 } => {
                *eid = m.id(Space::Element, *eid);
                g1.iter().chain(g34.iter()).for_each(|&g| {
                    m.grid(g);
                });
            }
            _ => m.refuse("a THRU range of elements is not supported in a part (write one PLOAD4 per element)"),
        }
        if let Some((cid, _)) = &mut c.direction {
            *cid = m.coord(*cid);
        }
    });
    each!(grav, "GRAV", |m, c| {
        c.cid = m.coord(c.cid);
    });
    each!(load, "LOAD", |_m, _c| {});
    let mut reduction = Vec::new();
    for set in &b.reduction_sets {
        let mut m = Mapper {
            map,
            errors,
            card: "ASET/QSET",
            loc: &set.loc,
        };
        set.points.iter().for_each(|(g, _)| {
            m.grid(*g);
        });
        reduction.push(set.loc.clone());
    }
    for set in &b.aset1 {
        let mut m = Mapper {
            map,
            errors,
            card: "ASET1",
            loc: &set.loc,
        };
        m.grids(&set.grids);
        reduction.push(set.loc.clone());
    }
    reduction
}
