//! [`Model::build`]: grids, elements and rigid elements with their references, then the other
//! checks ([`xref`](super::xref), [`values`](super::values), [`pmpar`](super::pmpar),
//! [`params`](super::params), [`case`](super::case)). Every error of every check is collected;
//! a model that passes them all is last checked for mass when its solution needs it
//! ([`mass_check`](super::mass_check)).

use std::collections::{BTreeMap, HashMap};
use std::sync::Arc;

use crate::deck::cards::BulkData;
use crate::deck::fields::RawCard;
use crate::deck::{Deck, DeckError, Loc, Warning};
use crate::fe::beam_section::SectionError;
use crate::fe::solid_midside::Midsides;

use super::coords::{self, CoordSystem};
use super::geometry::{self, ShapeReport};
use super::ids::{IdMap, entry, index};
use super::{
    Element, ElementKind, GridPoint, MaterialRef, Model, PropertyRef, Rigid, RigidKind,
    WeightedGroup,
};

/// At most this many element ids are listed in one grouped geometry warning.
const LISTED_IDS: usize = 10;

impl Model {
    /// Build and validate the model of a deck. On error, returns every error found, sorted by
    /// file and line.
    pub fn build(deck: &Deck) -> Result<Model, Vec<DeckError>> {
        let mut warnings: Vec<Warning> = deck.warnings.clone();
        if !deck.parts.is_empty() {
            // the parts placed into one bulk data section, then built as any deck
            let bulk = super::parts::assemble(deck, &mut warnings)?;
            let assembled = Deck {
                bulk: Arc::new(bulk),
                parts: Vec::new(),
                warnings,
                ..deck.clone()
            };
            return Model::build(&assembled);
        }
        let bulk = &deck.bulk;
        let mut errors: Vec<DeckError> = Vec::new();
        super::parts::main_reduction_sets(deck, &mut errors, &mut warnings);

        index(
            bulk.coords
                .iter()
                .map(|c| entry(c.id, coords::kind_name(c.kind), &c.loc, ()))
                .collect(),
            "coordinate system",
            &mut errors,
        );
        let coords = coords::resolve(&bulk.coords, &mut errors);
        let (grids, grid_index) = build_grids(bulk, &coords, &mut errors, &mut warnings);
        let (scalar_points, scalar_index) =
            super::scalar_points::build(bulk, &grid_index, &mut errors);
        let (properties, solid_properties) = index_properties(bulk, &mut errors);
        let materials = index_materials(bulk, &mut errors);
        let refs = Refs {
            bulk,
            coords: &coords,
            grid_index: &grid_index,
            scalar_index: &scalar_index,
            properties: &properties,
            solid_properties: &solid_properties,
            materials: &materials,
        };
        let mut quality = Quality::default();
        let mut elements = build_elements(&refs, &grids, &mut errors, &mut quality);
        elements.sort_by_key(|e| e.id);
        let mut rigids = build_rigids(&refs, &mut errors);
        rigids.extend(super::rsscon::build(&refs, &grids, &elements, &mut errors));
        rigids.sort_by_key(|r| r.id);
        let declared_elements = element_id_space(bulk, &mut errors, &mut warnings);
        let element_index: IdMap<usize> = {
            // map ids to positions in the sorted element list (rigid ids are not in it); an id
            // shared by a CONM2 and another element is the other element's
            let mut by_id = IdMap::with_capacity_and_hasher(elements.len(), Default::default());
            for (i, e) in elements.iter().enumerate() {
                if e.kind != ElementKind::Conm2 {
                    by_id.insert(e.id, i);
                }
            }
            for (i, e) in elements.iter().enumerate() {
                by_id.entry(e.id).or_insert(i);
            }
            // in place: a second map of every element was the largest block of a large deck
            by_id.retain(|id, _| declared_elements.contains_key(id));
            by_id
        };

        super::xref::check(&refs, deck, &mut errors, &mut warnings);
        super::values::check(&refs, &mut errors, &mut warnings);
        super::temperature::check(deck, &refs, &mut errors, &mut warnings);
        super::pmpar::check(&refs, &mut errors);
        let mechanism = super::mechanism::build(bulk, &coords, &mut errors);
        let params = super::params::read(&bulk.params, &deck.case, &mut errors, &mut warnings);
        super::case::check(deck, &refs, &mut errors);
        super::case::unselected_sets(deck, &mut warnings);
        warnings.extend(quality.into_warnings());

        let model = Model {
            sol: deck.executive.sol.as_ref().map(|(s, _)| *s),
            grids,
            grid_index,
            scalar_points,
            scalar_index,
            coords,
            elements,
            element_index,
            rigids,
            properties: solid_properties.into_iter().chain(properties).collect(),
            materials,
            bulk: Arc::clone(&deck.bulk),
            subcases: deck.case.subcases(),
            params,
            mechanism,
            warnings,
        };
        // the pressure cards' faces need the built elements and grids
        errors.extend(super::pressure::check(&model, &declared_elements));
        errors.extend(super::line_loads::check(&model, &declared_elements));
        errors.extend(super::grid_loads::check(&model));
        errors.extend(super::bush::check(&model));
        if !errors.is_empty() {
            errors.sort_by(|a, b| (&*a.loc.file, a.loc.line).cmp(&(&*b.loc.file, b.loc.line)));
            return Err(errors);
        }
        let massless = super::mass_check::check(deck, &model);
        if !massless.is_empty() {
            return Err(massless);
        }
        Ok(model)
    }
}

/// The id maps every cross-reference check looks things up in.
pub struct Refs<'a> {
    pub bulk: &'a BulkData,
    pub coords: &'a HashMap<u32, CoordSystem>,
    pub grid_index: &'a IdMap<usize>,
    /// Scalar point id → index into [`Model::scalar_points`].
    pub scalar_index: &'a HashMap<u32, usize>,
    /// Property id → property, PSOLID excepted.
    pub properties: &'a HashMap<u32, PropertyRef>,
    /// PSOLID id → property (an id space of its own, see `index_properties`).
    pub solid_properties: &'a HashMap<u32, PropertyRef>,
    pub materials: &'a HashMap<u32, MaterialRef>,
}

impl Refs<'_> {
    /// The grid index of `id`, or an error "`FIELD = id` does not exist" on `card` at `loc`.
    pub fn grid(
        &self,
        id: u32,
        field: &str,
        card: &str,
        loc: &Loc,
        errors: &mut Vec<DeckError>,
    ) -> Option<usize> {
        let found = self.grid_index.get(&id).copied();
        if found.is_none() {
            errors.push(
                DeckError::at(loc, format!("{field} = {id} does not exist (no GRID {id})"))
                    .on_card(card),
            );
        }
        found
    }

    /// True when `id` is a grid or a scalar point; otherwise an error "`FIELD = id` does not
    /// exist" on `card` at `loc`.
    pub fn point(
        &self,
        id: u32,
        field: &str,
        card: &str,
        loc: &Loc,
        errors: &mut Vec<DeckError>,
    ) -> bool {
        let found = self.grid_index.contains_key(&id) || self.scalar_index.contains_key(&id);
        if !found {
            errors.push(
                DeckError::at(
                    loc,
                    format!("{field} = {id} does not exist (no GRID or SPOINT {id})"),
                )
                .on_card(card),
            );
        }
        found
    }

    /// Check a coordinate system reference (0 = basic always exists).
    pub fn coord(
        &self,
        id: u32,
        field: &str,
        card: &str,
        loc: &Loc,
        errors: &mut Vec<DeckError>,
    ) -> Option<&CoordSystem> {
        let found = self.coords.get(&id);
        if found.is_none() {
            errors.push(
                DeckError::at(loc, format!("{field} = {id} does not exist or is in error (no usable CORD2R/CORD2C/CORD2S {id})"))
                    .on_card(card),
            );
        }
        found
    }
}

fn build_grids(
    bulk: &BulkData,
    coords: &HashMap<u32, CoordSystem>,
    errors: &mut Vec<DeckError>,
    warnings: &mut Vec<Warning>,
) -> (Vec<GridPoint>, IdMap<usize>) {
    let unique = index(
        bulk.grids
            .iter()
            .enumerate()
            .map(|(i, g)| entry(g.id, "GRID", &g.loc, i))
            .collect(),
        "grid",
        errors,
    );
    let mut order: Vec<usize> = unique.into_values().collect();
    order.sort_by_key(|&i| bulk.grids[i].id);
    let defaults = grid_defaults(&bulk.grdset, errors);
    let mut grids = Vec::with_capacity(order.len());
    for i in order {
        let g = &bulk.grids[i];
        let card = format!("GRID {}", g.id);
        let (cp, cd, ps) = (
            g.cp.unwrap_or(defaults.cp),
            g.cd.unwrap_or(defaults.cd),
            g.ps.unwrap_or(defaults.ps),
        );
        if !g.x.iter().all(|v| v.is_finite()) {
            errors
                .push(DeckError::at(&g.loc, "X1-X3 must be finite numbers").on_card(card.clone()));
        }
        let xyz = match coords.get(&cp) {
            Some(sys) => sys.point_to_basic(g.x),
            None => {
                errors.push(
                    DeckError::at(
                        &g.loc,
                        format!(
                            "CP = {} does not exist or is in error (no usable CORD2R/CORD2C/CORD2S {})",
                            cp, cp
                        ),
                    )
                    .on_card(card.clone()),
                );
                g.x
            }
        };
        match coords.get(&cd) {
            None => errors.push(
                DeckError::at(&g.loc, format!("CD = {} does not exist or is in error (no usable CORD2R/CORD2C/CORD2S {})", cd, cd))
                    .on_card(card),
            ),
            Some(sys) if sys.on_polar_axis(xyz) => warnings.push(Warning {
                loc: Some(g.loc.to_string()),
                message: format!(
                    "{card} lies on the polar axis of its CD = {cd}, where the azimuth is undefined: its displacement directions are taken at azimuth 0 (e_r along the system's x axis); other codes may choose other directions there"
                ),
            }),
            Some(_) => {}
        }
        grids.push(GridPoint {
            id: g.id,
            xyz,
            cp,
            cd,
            ps,
            loc: g.loc.clone(),
        });
    }
    let grid_index = grids.iter().enumerate().map(|(i, g)| (g.id, i)).collect();
    (grids, grid_index)
}

/// The `GRDSET` defaults for blank GRID CP, CD and PS (all zero / none without one); a second
/// `GRDSET` is an error (Nastran allows one).
fn grid_defaults(
    cards: &[crate::deck::cards::Grdset],
    errors: &mut Vec<DeckError>,
) -> GridDefaults {
    for extra in cards.iter().skip(1) {
        errors.push(
            DeckError::at(
                &extra.loc,
                format!(
                    "a second GRDSET (the first is at {}); a deck has at most one",
                    cards[0].loc
                ),
            )
            .on_card("GRDSET".to_string()),
        );
    }
    cards.first().map_or(
        GridDefaults {
            cp: 0,
            cd: 0,
            ps: crate::card_values::Dofs::NONE,
        },
        |g| GridDefaults {
            cp: g.cp,
            cd: g.cd,
            ps: g.ps,
        },
    )
}

/// CP, CD and PS of a GRID whose field is blank.
struct GridDefaults {
    cp: u32,
    cd: u32,
    ps: crate::card_values::Dofs,
}

/// The property id spaces: every property but PSOLID, and PSOLID apart. A PSOLID may share
/// the id of a shell or line property, as MSC Nastran accepts (its test deck `rs321h` has a
/// PSHELL 1 and a PSOLID 1): a solid element's PID names a PSOLID, any other element's PID one
/// of the others.
fn index_properties(
    bulk: &BulkData,
    errors: &mut Vec<DeckError>,
) -> (HashMap<u32, PropertyRef>, HashMap<u32, PropertyRef>) {
    let solids = bulk
        .psolid
        .iter()
        .enumerate()
        .map(|(i, p)| entry(p.id, "PSOLID", &p.loc, PropertyRef::Psolid(i)))
        .collect();
    let solids = index(solids, "property", errors);
    let mut entries = Vec::new();
    entries.extend(
        bulk.pshell
            .iter()
            .enumerate()
            .map(|(i, p)| entry(p.id, "PSHELL", &p.loc, PropertyRef::Pshell(i))),
    );
    entries.extend(
        bulk.pcomp
            .iter()
            .enumerate()
            .map(|(i, p)| entry(p.id, "PCOMP", &p.loc, PropertyRef::Pcomp(i))),
    );
    entries.extend(
        bulk.pshear
            .iter()
            .enumerate()
            .map(|(i, p)| entry(p.id, "PSHEAR", &p.loc, PropertyRef::Pshear(i))),
    );
    entries.extend(
        bulk.pelas
            .iter()
            .enumerate()
            .map(|(i, p)| entry(p.id, "PELAS", &p.loc, PropertyRef::Pelas(i))),
    );
    entries.extend(
        bulk.pdamp
            .iter()
            .enumerate()
            .map(|(i, p)| entry(p.id, "PDAMP", &p.loc, PropertyRef::Pdamp(i))),
    );
    entries.extend(
        bulk.pvisc
            .iter()
            .enumerate()
            .map(|(i, p)| entry(p.id, "PVISC", &p.loc, PropertyRef::Pvisc(i))),
    );
    entries.extend(
        bulk.pbush
            .iter()
            .enumerate()
            .map(|(i, p)| entry(p.id, "PBUSH", &p.loc, PropertyRef::Pbush(i))),
    );
    entries.extend(
        bulk.prod
            .iter()
            .enumerate()
            .map(|(i, p)| entry(p.id, "PROD", &p.loc, PropertyRef::Prod(i))),
    );
    entries.extend(
        bulk.ptube
            .iter()
            .enumerate()
            .map(|(i, p)| entry(p.id, "PTUBE", &p.loc, PropertyRef::Ptube(i))),
    );
    entries.extend(
        bulk.pbar
            .iter()
            .enumerate()
            .map(|(i, p)| entry(p.id, "PBAR", &p.loc, PropertyRef::Pbar(i))),
    );
    entries.extend(
        bulk.pbend
            .iter()
            .enumerate()
            .map(|(i, p)| entry(p.id, "PBEND", &p.loc, PropertyRef::Pbend(i))),
    );
    entries.extend(
        bulk.pbarl
            .iter()
            .enumerate()
            .map(|(i, p)| entry(p.id, "PBARL", &p.loc, PropertyRef::Pbarl(i))),
    );
    entries.extend(
        bulk.pbeam
            .iter()
            .enumerate()
            .map(|(i, p)| entry(p.id, "PBEAM", &p.loc, PropertyRef::Pbeam(i))),
    );
    entries.extend(
        bulk.pbeaml
            .iter()
            .enumerate()
            .map(|(i, p)| entry(p.id, "PBEAML", &p.loc, PropertyRef::Pbeaml(i))),
    );
    (index(entries, "property", errors), solids)
}

fn index_materials(bulk: &BulkData, errors: &mut Vec<DeckError>) -> HashMap<u32, MaterialRef> {
    let mut entries = Vec::new();
    entries.extend(
        bulk.mat1
            .iter()
            .enumerate()
            .map(|(i, m)| entry(m.id, "MAT1", &m.loc, MaterialRef::Mat1(i))),
    );
    entries.extend(
        bulk.mat8
            .iter()
            .enumerate()
            .map(|(i, m)| entry(m.id, "MAT8", &m.loc, MaterialRef::Mat8(i))),
    );
    entries.extend(
        bulk.mat2
            .iter()
            .enumerate()
            .map(|(i, m)| entry(m.id, "MAT2", &m.loc, MaterialRef::Mat2(i))),
    );
    index(entries, "material", errors)
}

/// The element id space (elements, CELAS, RBE2, RBE3) and the mass element id space (CONM2),
/// each without duplicates; a mass element may share an id with another element (MSC Nastran
/// stores mass elements apart and runs such decks), with a warning. Returns id → () for the ids.
fn element_id_space(
    bulk: &BulkData,
    errors: &mut Vec<DeckError>,
    warnings: &mut Vec<Warning>,
) -> HashMap<u32, ()> {
    let mut e = Vec::new();
    e.extend(
        bulk.cquad4
            .iter()
            .map(|c| entry(c.id, "CQUAD4", &c.loc, ())),
    );
    e.extend(
        bulk.ctria3
            .iter()
            .map(|c| entry(c.id, "CTRIA3", &c.loc, ())),
    );
    for c in bulk.cquad8.iter().chain(&bulk.ctria6) {
        let card = if c.nodes.len() == 8 {
            "CQUAD8"
        } else {
            "CTRIA6"
        };
        e.push(entry(c.id, card, &c.loc, ()));
    }
    e.extend(
        bulk.cshear
            .iter()
            .map(|c| entry(c.id, "CSHEAR", &c.loc, ())),
    );
    e.extend(
        bulk.cquadr
            .iter()
            .map(|c| entry(c.id, "CQUADR", &c.loc, ())),
    );
    e.extend(
        bulk.ctriar
            .iter()
            .map(|c| entry(c.id, "CTRIAR", &c.loc, ())),
    );
    e.extend(bulk.chexa.iter().map(|c| entry(c.id, "CHEXA", &c.loc, ())));
    e.extend(
        bulk.cpenta
            .iter()
            .map(|c| entry(c.id, "CPENTA", &c.loc, ())),
    );
    e.extend(
        bulk.ctetra
            .iter()
            .map(|c| entry(c.id, "CTETRA", &c.loc, ())),
    );
    e.extend(
        bulk.cpyram
            .iter()
            .map(|c| entry(c.id, "CPYRAM", &c.loc, ())),
    );
    e.extend(
        bulk.celas1
            .iter()
            .map(|c| entry(c.id, "CELAS1", &c.loc, ())),
    );
    e.extend(
        bulk.celas2
            .iter()
            .map(|c| entry(c.id, "CELAS2", &c.loc, ())),
    );
    for (name, id, _, loc) in super::scalar_points::scalar_element_ends(bulk) {
        if !matches!(name, "CELAS1" | "CELAS2") {
            e.push(entry(id, name, loc, ()));
        }
    }
    e.extend(bulk.cvisc.iter().map(|c| entry(c.id, "CVISC", &c.loc, ())));
    e.extend(bulk.cbush.iter().map(|c| entry(c.id, "CBUSH", &c.loc, ())));
    e.extend(bulk.crod.iter().map(|c| entry(c.id, "CROD", &c.loc, ())));
    e.extend(bulk.ctube.iter().map(|c| entry(c.id, "CTUBE", &c.loc, ())));
    e.extend(
        bulk.conrod
            .iter()
            .map(|c| entry(c.id, "CONROD", &c.loc, ())),
    );
    e.extend(bulk.cbar.iter().map(|c| entry(c.id, "CBAR", &c.loc, ())));
    e.extend(bulk.cbeam.iter().map(|c| entry(c.id, "CBEAM", &c.loc, ())));
    e.extend(bulk.cbend.iter().map(|c| entry(c.id, "CBEND", &c.loc, ())));
    e.extend(bulk.rbe2.iter().map(|c| entry(c.id, "RBE2", &c.loc, ())));
    e.extend(bulk.rbe3.iter().map(|c| entry(c.id, "RBE3", &c.loc, ())));
    e.extend(
        bulk.rsscon
            .iter()
            .map(|c| entry(c.id, "RSSCON", &c.loc, ())),
    );
    // no two cards share a line, so an unstable sort (no scratch copy of `e`) keeps file order
    e.sort_unstable_by(|a, b| (&*a.loc.file, a.loc.line).cmp(&(&*b.loc.file, b.loc.line)));
    let mut declared = index(e, "element", errors);
    let masses = bulk
        .conm2
        .iter()
        .map(|c| entry(c.id, "CONM2", &c.loc, ()))
        .collect();
    let masses = index(masses, "mass element", errors);
    // in card order; a repeated CONM2 id was reported above
    let mut seen = std::collections::HashSet::new();
    for c in bulk.conm2.iter().filter(|c| masses.contains_key(&c.id)) {
        let id = c.id;
        if !seen.insert(id) {
            continue;
        }
        if declared.insert(id, ()).is_some() {
            warnings.push(Warning {
                loc: Some(c.loc.to_string()),
                message: format!(
                    "CONM2 {id} has the id of another element: the QRG asks for unique element ids, MSC Nastran keeps mass elements apart and accepts it, and so does paraflex (element {id} in loads and output is the other element)"
                ),
            });
        }
    }
    declared
}

/// Geometry warnings grouped by (card, check): one warning per group.
#[derive(Default)]
struct Quality {
    groups: BTreeMap<(&'static str, &'static str), Vec<String>>,
}

impl Quality {
    fn add(&mut self, card: &'static str, id: u32, report: &ShapeReport) {
        for (check, value) in &report.warnings {
            self.groups
                .entry((card, check))
                .or_default()
                .push(format!("{id} ({value})"));
        }
    }

    fn into_warnings(self) -> Vec<Warning> {
        self.groups
            .into_iter()
            .map(|((card, check), items)| {
                let more = items.len().saturating_sub(LISTED_IDS);
                let mut list = items.iter().take(LISTED_IDS).cloned().collect::<Vec<_>>().join(", ");
                if more > 0 {
                    list.push_str(&format!(" and {more} more"));
                }
                Warning {
                    loc: None,
                    message: format!("{} {card} element(s) fail the {check} check (see model::geometry for the limits): {list}", items.len()),
                }
            })
            .collect()
    }
}

/// Resolve the grids of an element; errors name each missing or repeated grid.
fn resolve_nodes(
    refs: &Refs,
    ids: &[u32],
    names: &[&str],
    card: &str,
    loc: &Loc,
    errors: &mut Vec<DeckError>,
) -> Option<Vec<usize>> {
    let mut out = Vec::with_capacity(ids.len());
    let mut ok = true;
    for (k, &id) in ids.iter().enumerate() {
        let name = names.get(k).copied().unwrap_or("G");
        if let Some(j) = ids[..k].iter().position(|&x| x == id) {
            let first = names.get(j).copied().unwrap_or("G");
            errors.push(
                DeckError::at(
                    loc,
                    format!("{first} and {name} are both grid {id} (repeated grid)"),
                )
                .on_card(card),
            );
            ok = false;
            continue;
        }
        match refs.grid(id, name, card, loc, errors) {
            Some(i) => out.push(i),
            None => ok = false,
        }
    }
    ok.then_some(out)
}

/// Resolve a property and check its kind.
fn resolve_property(
    refs: &Refs,
    pid: u32,
    allowed: &[&str],
    card: &str,
    loc: &Loc,
    errors: &mut Vec<DeckError>,
) -> Option<PropertyRef> {
    let wanted = allowed.join(" or ");
    let (own, other) = if allowed.contains(&"PSOLID") {
        (refs.solid_properties, refs.properties)
    } else {
        (refs.properties, refs.solid_properties)
    };
    match own.get(&pid).or_else(|| other.get(&pid)) {
        None => {
            errors.push(
                DeckError::at(
                    loc,
                    format!("PID = {pid} does not exist (no {wanted} {pid})"),
                )
                .on_card(card),
            );
            None
        }
        Some(p) if !allowed.contains(&p.card()) => {
            errors.push(
                DeckError::at(
                    loc,
                    format!(
                        "PID = {pid} is a {}; a {} needs a {wanted}",
                        p.card(),
                        card.split(' ').next().unwrap_or(card)
                    ),
                )
                .on_card(card),
            );
            None
        }
        Some(p) => Some(*p),
    }
}

/// (id, pid, grids, kind, position in its card vector, card name, location) of a solid card.
type SolidCard<'a> = (
    u32,
    u32,
    &'a [u32],
    ElementKind,
    usize,
    &'static str,
    &'a Loc,
);

/// A shell or shear panel card: kind, index in its card list, id, PID, grids, position.
type SurfaceCard<'a> = (ElementKind, usize, u32, u32, &'a [u32], &'a Loc);

const G: [&str; 10] = ["G1", "G2", "G3", "G4", "G5", "G6", "G7", "G8", "G9", "G10"];

fn build_elements(
    refs: &Refs,
    grids: &[GridPoint],
    errors: &mut Vec<DeckError>,
    quality: &mut Quality,
) -> Vec<Element> {
    let b = refs.bulk;
    let mut out = Vec::new();
    let pos = |nodes: &[usize]| -> Vec<[f64; 3]> {
        nodes
            .iter()
            .filter_map(|&i| grids.get(i))
            .map(|g| g.xyz)
            .collect()
    };
    let shell = ["PSHELL", "PCOMP"];
    let solid = ["PSOLID"];

    let mut surfaces: Vec<SurfaceCard> = Vec::new();
    // the surface card lists are of different card types with the same fields
    macro_rules! surfaces_of {
        ($($cards:expr => $kind:expr),* $(,)?) => {$(
            surfaces.extend(
                $cards
                    .iter()
                    .enumerate()
                    .map(|(i, c)| ($kind, i, c.id, c.pid, &c.nodes[..], &c.loc)),
            );
        )*};
    }
    surfaces_of!(
        b.cquad4 => ElementKind::Quad4,
        b.cquadr => ElementKind::QuadR,
        b.ctria3 => ElementKind::Tria3,
        b.ctriar => ElementKind::TriaR,
        b.cquad8 => ElementKind::Quad8,
        b.ctria6 => ElementKind::Tria6,
        b.cshear => ElementKind::Cshear,
    );
    for (kind, i, id, pid, ids, loc) in surfaces {
        let card = format!("{} {id}", kind.card());
        let allowed: &[&str] = if kind == ElementKind::Cshear {
            &["PSHEAR"]
        } else {
            &shell
        };
        // a blank (0) mid-side grid of a CQUAD8 / CTRIA6 is no grid of the element
        let (given, names): (Vec<u32>, Vec<&str>) =
            ids.iter().zip(G).filter(|(id, _)| **id != 0).unzip();
        let nodes = resolve_nodes(refs, &given, &names, &card, loc, errors);
        let prop = resolve_property(refs, pid, allowed, &card, loc, errors);
        let Some(nodes) = nodes else {
            continue;
        };
        // the shape checks of the corner grids (4 of a CQUAD8, 3 of a CTRIA6: the kernel of a
        // quadratic shell refuses a surface that folds over)
        let corners = if matches!(
            kind,
            ElementKind::Tria3 | ElementKind::TriaR | ElementKind::Tria6
        ) {
            3
        } else {
            4
        };
        let xyz = pos(&nodes[..corners.min(nodes.len())]);
        let report = match corners {
            3 => <[[f64; 3]; 3]>::try_from(xyz)
                .ok()
                .zip(<[u32; 3]>::try_from(&ids[..3]).ok())
                .map(|(t, g)| geometry::check_tria(&t, &g)),
            _ => <[[f64; 3]; 4]>::try_from(xyz)
                .ok()
                .zip(<[u32; 4]>::try_from(&ids[..4]).ok())
                .map(|(q, g)| geometry::check_quad(&q, &g)),
        };
        let report = match report {
            // a quadratic shell whose corners pass: its curved surface
            Some(r)
                if r.errors.is_empty()
                    && matches!(kind, ElementKind::Quad8 | ElementKind::Tria6) =>
            {
                let curved = geometry::check_quadratic_shell(ids, &pos(&nodes));
                Some(ShapeReport {
                    errors: curved.errors,
                    warnings: r.warnings.into_iter().chain(curved.warnings).collect(),
                })
            }
            r => r,
        };
        if let Some(report) = report {
            shape_errors(&report, &card, loc, errors);
            quality.add(kind.card(), id, &report);
        }
        out.push(Element {
            id,
            kind,
            card: i,
            property: prop,
            nodes,
        });
    }
    let mut solids: Vec<SolidCard> = Vec::new();
    solids.extend(b.chexa.iter().enumerate().map(|(i, c)| {
        let kind = if c.nodes.len() > 8 {
            ElementKind::Hexa20
        } else {
            ElementKind::Hexa8
        };
        (c.id, c.pid, &c.nodes[..], kind, i, "CHEXA", &c.loc)
    }));
    solids.extend(b.cpenta.iter().enumerate().map(|(i, c)| {
        let kind = if c.nodes.len() > 6 {
            ElementKind::Penta15
        } else {
            ElementKind::Penta6
        };
        (c.id, c.pid, &c.nodes[..], kind, i, "CPENTA", &c.loc)
    }));
    for (i, c) in b.ctetra.iter().enumerate() {
        let kind = if c.nodes.len() == 10 {
            ElementKind::Tetra10
        } else {
            ElementKind::Tetra4
        };
        solids.push((c.id, c.pid, &c.nodes[..], kind, i, "CTETRA", &c.loc));
    }
    solids.extend(b.cpyram.iter().enumerate().map(|(i, c)| {
        (
            c.id,
            c.pid,
            &c.nodes[..],
            ElementKind::Pyram5,
            i,
            "CPYRAM",
            &c.loc,
        )
    }));
    for (id, pid, card_ids, kind, i, name, loc) in solids {
        let card = format!("{name} {id}");
        // a quadratic CHEXA / CPENTA lists 0 for a blank mid-side grid: its element keeps the
        // given grids (Model::solid_midsides recovers the blank ones from the card)
        let (ids, names): (Vec<u32>, Vec<String>) = card_ids
            .iter()
            .enumerate()
            .filter(|&(_, &g)| g != 0)
            .map(|(k, &g)| (g, format!("G{}", k + 1)))
            .unzip();
        let names: Vec<&str> = names.iter().map(String::as_str).collect();
        let nodes = resolve_nodes(refs, &ids, &names, &card, loc, errors);
        let prop = resolve_property(refs, pid, &solid, &card, loc, errors);
        let Some(nodes) = nodes else { continue };
        if let Some(solid_kind) = kind.solid_kind() {
            // the complete element (a blank mid-side grid at its edge's middle), sampled where
            // the kernels evaluate it
            let present: Vec<bool> = card_ids.iter().map(|&g| g != 0).collect();
            let range = Midsides::new(solid_kind, &present).jacobian_range(&pos(&nodes));
            if let Ok(range) = range {
                let report = geometry::check_solid(&range, &ids);
                shape_errors(&report, &card, loc, errors);
                quality.add(name, id, &report);
            }
        }
        out.push(Element {
            id,
            kind,
            card: i,
            property: prop,
            nodes,
        });
    }
    let scalar_cards = [
        (ElementKind::Celas1, &b.celas1, Some("PELAS")),
        (ElementKind::Celas3, &b.celas3, Some("PELAS")),
        (ElementKind::Cdamp1, &b.cdamp1, Some("PDAMP")),
        (ElementKind::Cdamp3, &b.cdamp3, Some("PDAMP")),
    ]
    .into_iter()
    .flat_map(|(kind, cards, property)| {
        cards
            .iter()
            .enumerate()
            .map(move |(i, c)| (kind, i, c.id, Some(c.pid), property, c.ends, &c.loc))
    });
    let on_card = [
        (ElementKind::Celas2, &b.celas2),
        (ElementKind::Celas4, &b.celas4),
        (ElementKind::Cdamp2, &b.cdamp2),
        (ElementKind::Cdamp4, &b.cdamp4),
        (ElementKind::Cmass2, &b.cmass2),
    ]
    .into_iter()
    .flat_map(|(kind, cards)| {
        cards
            .iter()
            .enumerate()
            .map(move |(i, c)| (kind, i, c.id, None, None, c.ends, &c.loc))
    });
    for (kind, i, id, pid, property, ends, loc) in scalar_cards.chain(on_card) {
        let card = format!("{} {id}", kind.card());
        let nodes = scalar_element_grids(refs, &ends, &card, loc, errors);
        let prop = match (pid, property) {
            (Some(pid), Some(name)) => resolve_property(refs, pid, &[name], &card, loc, errors),
            _ => None,
        };
        if let Some(nodes) = nodes {
            out.push(Element {
                id,
                kind,
                card: i,
                property: prop,
                nodes,
            });
        }
    }
    for (i, c) in b.cvisc.iter().enumerate() {
        let card = format!("CVISC {}", c.id);
        let nodes = resolve_nodes(refs, &c.grids, &G, &card, &c.loc, errors);
        let prop = resolve_property(refs, c.pid, &["PVISC"], &card, &c.loc, errors);
        if let Some(nodes) = nodes {
            out.push(Element {
                id: c.id,
                kind: ElementKind::Cvisc,
                card: i,
                property: prop,
                nodes,
            });
        }
    }
    for (i, c) in b.cbush.iter().enumerate() {
        let card = format!("CBUSH {}", c.id);
        let ids: Vec<u32> = std::iter::once(c.ga).chain(c.gb).collect();
        let nodes = resolve_nodes(refs, &ids, &["GA", "GB"], &card, &c.loc, errors);
        let prop = resolve_property(refs, c.pid, &["PBUSH"], &card, &c.loc, errors);
        match c.axes {
            crate::deck::cards::BushAxes::System(cid) => {
                refs.coord(cid, "CID", &card, &c.loc, errors);
            }
            crate::deck::cards::BushAxes::Grid(go) => {
                refs.grid(go, "GO", &card, &c.loc, errors);
            }
            _ => {}
        }
        if let Ok(ocid @ 0..) = u32::try_from(c.ocid) {
            refs.coord(ocid, "OCID", &card, &c.loc, errors);
        }
        if let Some(nodes) = nodes {
            out.push(Element {
                id: c.id,
                kind: ElementKind::Cbush,
                card: i,
                property: prop,
                nodes,
            });
        }
    }
    build_lines(refs, grids, errors, &mut out);
    build_bends(refs, grids, errors, &mut out);
    for (i, c) in b.conm2.iter().enumerate() {
        let card = format!("CONM2 {}", c.id);
        let node = refs.grid(c.grid, "G", &card, &c.loc, errors);
        if let Ok(cid) = u32::try_from(c.cid) {
            refs.coord(cid, "CID", &card, &c.loc, errors);
        }
        if let Some(n) = node {
            out.push(Element {
                id: c.id,
                kind: ElementKind::Conm2,
                card: i,
                property: None,
                nodes: vec![n],
            });
        }
    }
    out
}

/// The curved beams: grids, property, and the check of their arc.
fn build_bends(
    refs: &Refs,
    grids: &[GridPoint],
    errors: &mut Vec<DeckError>,
    out: &mut Vec<Element>,
) {
    let inputs = super::lines::LineInputs {
        bulk: refs.bulk,
        coords: refs.coords,
        grids,
        grid_index: refs.grid_index,
    };
    for (i, c) in refs.bulk.cbend.iter().enumerate() {
        let card = format!("CBEND {}", c.id);
        let nodes = resolve_nodes(refs, &c.nodes, &["GA", "GB"], &card, &c.loc, errors);
        let prop = resolve_property(refs, c.pid, &["PBEND"], &card, &c.loc, errors);
        let Some(nodes) = nodes else { continue };
        let element = Element {
            id: c.id,
            kind: ElementKind::Cbend,
            card: i,
            property: prop,
            nodes,
        };
        if prop.is_some()
            && let Err(reason) = inputs.resolve_bend(&element, prop)
        {
            let field = if reason.contains("PBEND") || reason.contains("RB") {
                format!("{} (GEOM)", RawCard::field_label(8))
            } else {
                format!("{} (X1/G0)", RawCard::field_label(5))
            };
            let mut e = DeckError::at(&c.loc, reason).on_card(card);
            e.field = Some(field);
            errors.push(e);
        }
        out.push(element);
    }
}

/// A rod or beam card as [`build_lines`] reads it.
struct LineCard<'a> {
    kind: ElementKind,
    /// Position in its card vector.
    card: usize,
    id: u32,
    /// `None` for CONROD (properties on the card).
    pid: Option<u32>,
    grids: [u32; 2],
    loc: &'a Loc,
}

/// The rods and beams: grids, property, and the checks of their placement (length,
/// orientation) and of the sections they use (library shapes), each property reported once.
fn build_lines(
    refs: &Refs,
    grids: &[GridPoint],
    errors: &mut Vec<DeckError>,
    out: &mut Vec<Element>,
) {
    let b = refs.bulk;
    let line = |kind, card, id, pid, grids, loc| LineCard {
        kind,
        card,
        id,
        pid,
        grids,
        loc,
    };
    let mut cards: Vec<LineCard> = Vec::new();
    for (i, c) in b.crod.iter().enumerate() {
        cards.push(line(
            ElementKind::Crod,
            i,
            c.id,
            Some(c.pid),
            c.nodes,
            &c.loc,
        ));
    }
    for (i, c) in b.ctube.iter().enumerate() {
        cards.push(line(
            ElementKind::Ctube,
            i,
            c.id,
            Some(c.pid),
            c.nodes,
            &c.loc,
        ));
    }
    for (i, c) in b.conrod.iter().enumerate() {
        cards.push(line(ElementKind::Conrod, i, c.id, None, c.nodes, &c.loc));
    }
    for (i, c) in b.cbar.iter().enumerate() {
        cards.push(line(
            ElementKind::Cbar,
            i,
            c.id,
            Some(c.pid),
            c.nodes,
            &c.loc,
        ));
    }
    for (i, c) in b.cbeam.iter().enumerate() {
        cards.push(line(
            ElementKind::Cbeam,
            i,
            c.id,
            Some(c.pid),
            c.nodes,
            &c.loc,
        ));
    }
    let inputs = super::lines::LineInputs {
        bulk: b,
        coords: refs.coords,
        grids,
        grid_index: refs.grid_index,
    };
    let mut section_ok: HashMap<u32, bool> = HashMap::new();
    for c in cards {
        let (names, allowed): ([&str; 2], &[&str]) = match c.kind {
            ElementKind::Crod => (["G1", "G2"], &["PROD"]),
            ElementKind::Ctube => (["G1", "G2"], &["PTUBE"]),
            ElementKind::Cbar => (["GA", "GB"], &["PBAR", "PBARL"]),
            ElementKind::Cbeam => (["GA", "GB"], &["PBEAM", "PBEAML"]),
            _ => (["G1", "G2"], &[]),
        };
        let card = format!("{} {}", c.kind.card(), c.id);
        let nodes = resolve_nodes(refs, &c.grids, &names, &card, c.loc, errors);
        let prop = c
            .pid
            .and_then(|pid| resolve_property(refs, pid, allowed, &card, c.loc, errors));
        let Some(nodes) = nodes else { continue };
        let element = Element {
            id: c.id,
            kind: c.kind,
            card: c.card,
            property: prop,
            nodes,
        };
        let usable = match (c.pid, prop) {
            (None, _) => true,
            (Some(_), None) => false,
            (Some(pid), Some(p)) => *section_ok.entry(pid).or_insert_with(|| {
                let result = super::lines::property_section(b, p);
                if let Err(e) = &result {
                    let at = super::lines::property_loc(b, p).unwrap_or(c.loc);
                    let mut error =
                        DeckError::at(at, e.to_string()).on_card(format!("{} {pid}", p.card()));
                    if matches!(e, SectionError::UnsupportedType(_)) {
                        error.field = Some(format!("{} (TYPE)", RawCard::field_label(4)));
                    }
                    errors.push(error);
                }
                result.is_ok()
            }),
        };
        if usable && let Err(reason) = inputs.resolve(&element, prop) {
            let mut e = DeckError::at(c.loc, reason.clone()).on_card(card);
            if reason.contains("orientation vector") {
                e.field = Some(format!("{} (X1/G0)", RawCard::field_label(5)));
            } else if reason.contains("zero length") {
                e.field = Some(format!("{} ({})", RawCard::field_label(4), names[1]));
            }
            errors.push(e);
        }
        out.push(element);
    }
}

/// The grid indices of a scalar element's ends that are grids (component 1–6); a scalar point
/// end (component 0) must name a scalar point, not a GRID.
fn scalar_element_grids(
    refs: &Refs,
    ends: &[crate::card_values::SpringEnd; 2],
    card: &str,
    loc: &Loc,
    errors: &mut Vec<DeckError>,
) -> Option<Vec<usize>> {
    let mut ok = true;
    let mut out = Vec::new();
    for (k, end) in ends.iter().enumerate() {
        let Some(id) = end.grid else { continue };
        let field = ["G1", "G2"][k];
        if end.component == 0 {
            if refs.grid_index.contains_key(&id) {
                errors.push(
                    DeckError::at(
                        loc,
                        format!("{field} = {id} is a GRID: give its component 1-6 (component 0 or blank names a scalar point)"),
                    )
                    .on_card(card),
                );
                ok = false;
            }
        } else {
            match refs.grid(id, field, card, loc, errors) {
                Some(i) => out.push(i),
                None => ok = false,
            }
        }
    }
    ok.then_some(out)
}

fn shape_errors(report: &ShapeReport, card: &str, loc: &Loc, errors: &mut Vec<DeckError>) {
    for e in &report.errors {
        errors.push(DeckError::at(loc, e.clone()).on_card(card));
    }
}

fn build_rigids(refs: &Refs, errors: &mut Vec<DeckError>) -> Vec<Rigid> {
    let b = refs.bulk;
    let mut out = Vec::new();
    for r in &b.rbe2 {
        let card = format!("RBE2 {}", r.id);
        let hub = refs.grid(r.gn, "GN", &card, &r.loc, errors);
        let mut legs = Vec::with_capacity(r.gm.len());
        let mut ok = hub.is_some();
        for &g in &r.gm {
            if g == r.gn {
                errors.push(
                    DeckError::at(&r.loc, format!("GM = {g} is also the independent grid GN"))
                        .on_card(card.clone()),
                );
                ok = false;
            } else if let Some(j) = refs.grid(g, "GM", &card, &r.loc, errors) {
                legs.push(j);
            } else {
                ok = false;
            }
        }
        if let (true, Some(hub)) = (ok, hub) {
            out.push(Rigid {
                id: r.id,
                kind: RigidKind::Rbe2 { cm: r.cm },
                hub,
                legs,
                loc: r.loc.clone(),
            });
        }
    }
    for r in &b.rbe3 {
        let card = format!("RBE3 {}", r.id);
        let hub = refs.grid(r.refgrid, "REFGRID", &card, &r.loc, errors);
        let mut legs = Vec::new();
        let mut groups = Vec::with_capacity(r.groups.len());
        let mut ok = hub.is_some();
        for grp in &r.groups {
            let mut grids = Vec::with_capacity(grp.grids.len());
            for g in &grp.grids {
                match refs.grid(*g, "Gi,j", &card, &r.loc, errors) {
                    Some(j) => grids.push(j),
                    None => ok = false,
                }
            }
            legs.extend(&grids);
            groups.push(WeightedGroup {
                weight: grp.weight,
                components: grp.components,
                grids,
            });
        }
        if let (true, Some(hub)) = (ok, hub) {
            out.push(Rigid {
                id: r.id,
                kind: RigidKind::Rbe3 {
                    refc: r.refc,
                    groups,
                },
                hub,
                legs,
                loc: r.loc.clone(),
            });
        }
    }
    out
}
