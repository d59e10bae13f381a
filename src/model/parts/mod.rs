//! Part superelements (`BEGIN SUPER = n` sections) assembled with the residual (the main bulk
//! data) into one model, which the solution sequences then solve as any other.
//!
//! Nastran reduces each part to its boundary and solves the residual; paraflex assembles the
//! parts' full matrices instead. For statics (SOL 101) the two are the same solution (static
//! condensation is exact); for modes and dynamics paraflex's answer is the unreduced model's,
//! which Nastran's Guyan reduction of each part only approximates — said by a warning.
//!
//! The steps, each its own module:
//! - [`motion`]: a `SELOC` moves its part rigidly (a generated `CORD2R` stands for the part's
//!   moved basic system, and the part's systems and grids are defined relative to it);
//! - [`renumber`]: each part's cards join the model in their own id namespace;
//! - [`connect`]: boundary grids become one point (shared id) or are tied (different ids).
//!
//! Every step reports what it did in warnings (renumbered ids, boundary points, ignored part
//! PARAMs and reduction sets).

mod connect;
mod motion;
mod renumber;

use std::collections::{HashMap, HashSet};

use crate::deck::cards::{BulkData, ParamValue};
use crate::deck::{Deck, DeckError, PartBulk, Solution, Warning};

use connect::{Join, Search};
use renumber::{PartMap, Space, UsedIds};

/// Superelement control cards, read in the main bulk data section only.
const CONTROL_CARDS: &[&str] = &["SEBULK", "SECONCT", "SELOC", "SEMPLN", "SEEXCLD", "SELABEL"];

/// At most this many boundary points are listed in a part's warning.
const LISTED_POINTS: usize = 12;

/// The bulk data of the whole structure: the residual with every part placed, moved and
/// connected. A deck without parts is its bulk data unchanged.
pub fn assemble(deck: &Deck, warnings: &mut Vec<Warning>) -> Result<BulkData, Vec<DeckError>> {
    let residual = &deck.bulk;
    let mut errors = check_controls(deck);
    for part in &deck.parts {
        check_cards(part, &mut errors);
    }
    if !errors.is_empty() {
        return Err(errors);
    }
    let mut out = BulkData::clone(residual);
    let mut used = UsedIds::of_residual(residual);
    let mut owner: Vec<u32> = vec![0; residual.grids.len()];
    let mut maps: Vec<PartMap> = Vec::new();
    for part in &deck.parts {
        let basic = match residual.seloc.iter().find(|s| s.seid == part.seid) {
            None => 0,
            Some(seloc) => {
                let id = used.fresh(Space::Coord);
                match motion::moved_basic(seloc, &part.bulk, residual, id, warnings) {
                    Ok(system) => {
                        out.coords.push(system);
                        id
                    }
                    Err(e) => {
                        errors.push(e);
                        0
                    }
                }
            }
        };
        let map = PartMap::new(part, &mut used, basic);
        let before = out.grids.len();
        let reduction = renumber::place(part, &map, &mut out, &mut errors);
        owner.extend(std::iter::repeat_n(part.seid, out.grids.len() - before));
        if let Some(first) = reduction.first() {
            warnings.push(Warning {
                loc: Some(first.to_string()),
                message: format!(
                    "ASET/ASET1/QSET/QSET1 of part superelement {} ({} cards) read and not honoured: paraflex solves the assembled model unreduced (for statics the same solution; for modes and dynamics the unreduced model's)",
                    part.seid,
                    reduction.len()
                ),
            });
        }
        part_params(part, residual, warnings);
        maps.push(map);
    }
    if !errors.is_empty() {
        return Err(errors);
    }
    let search: HashMap<u32, Search> = (residual.sebulk.iter())
        .map(|c| {
            let s = Search {
                method: c.method,
                tol: c.tol,
            };
            (c.seid, s)
        })
        .collect();
    let loc_of = deck.parts.iter().map(|p| (p.seid, p.loc.clone())).collect();
    let joins = connect::connect(
        &mut out,
        &owner,
        &search,
        &residual.seconct,
        &loc_of,
        &mut used,
        &mut errors,
    );
    if !errors.is_empty() {
        return Err(errors);
    }
    for (part, map) in deck.parts.iter().zip(&maps) {
        warnings.push(summary(part, map, &joins));
    }
    let sol = deck.executive.sol.as_ref().map(|(s, _)| *s);
    if !matches!(sol, Some(Solution::Statics) | None) {
        warnings.push(Warning {
            loc: deck.parts.first().map(|p| p.loc.to_string()),
            message: "the part superelements are assembled and solved unreduced: Nastran reduces each part to its boundary (Guyan reduction, or component modes where the part has generalized coordinates), so its modes and dynamic responses differ from paraflex's, which are the unreduced structure's".into(),
        });
    }
    Ok(out)
}

/// `ASET`, `QSET` and `QSET1` of the main bulk data: only Nastran's reduction of the residual.
/// In SOL 101 static condensation is exact, so they are read and not honoured, with a warning;
/// in the other solutions Guyan reduction would change the answer and they are refused.
pub fn main_reduction_sets(deck: &Deck, errors: &mut Vec<DeckError>, warnings: &mut Vec<Warning>) {
    let Some(first) = deck.bulk.reduction_sets.first() else {
        return;
    };
    let sol = deck.executive.sol.as_ref().map(|(s, _)| *s);
    if matches!(sol, Some(Solution::Statics) | None) {
        warnings.push(Warning {
            loc: Some(first.loc.to_string()),
            message: format!(
                "{} accepted and not honoured ({} ASET/QSET/QSET1 cards): paraflex solves the model unreduced, which for statics is the same solution as Nastran's static condensation",
                first.card,
                deck.bulk.reduction_sets.len()
            ),
        });
    } else {
        for set in &deck.bulk.reduction_sets {
            errors.push(
                DeckError::at(
                    &set.loc,
                    format!(
                        "{} reduces the model (Guyan reduction, or component modes with QSET) in Nastran, which changes modes and dynamic responses; paraflex does not reduce: remove it to solve the model unreduced",
                        set.card
                    ),
                )
                .on_card(set.card.clone()),
            );
        }
    }
}

/// SEBULK, SECONCT and SELOC name parts the deck defines, once each.
fn check_controls(deck: &Deck) -> Vec<DeckError> {
    let parts: HashSet<u32> = deck.parts.iter().map(|p| p.seid).collect();
    let b = &deck.bulk;
    let mut errors = Vec::new();
    let mut check = |card: &str, seid: u32, loc: &crate::deck::Loc, residual_ok: bool| {
        if !(parts.contains(&seid) || residual_ok && seid == 0) {
            errors.push(
                DeckError::at(
                    loc,
                    format!(
                        "{card} names part superelement {seid}, which the deck does not define (no BEGIN SUPER = {seid} section)"
                    ),
                )
                .on_card(format!("{card} {seid}")),
            );
        }
    };
    for c in &b.sebulk {
        check("SEBULK", c.seid, &c.loc, false);
    }
    for c in &b.seloc {
        check("SELOC", c.seid, &c.loc, false);
    }
    for c in &b.seconct {
        check("SECONCT", c.seid_a, &c.loc, true);
        check("SECONCT", c.seid_b, &c.loc, true);
    }
    let mut repeated = |card: &str, seids: Vec<(u32, &crate::deck::Loc)>| {
        let mut seen: HashMap<u32, &crate::deck::Loc> = HashMap::new();
        for (seid, loc) in seids {
            if let Some(first) = seen.insert(seid, loc) {
                errors.push(
                    DeckError::at(
                        loc,
                        format!(
                            "a second {card} for part superelement {seid} (the first is at {first})"
                        ),
                    )
                    .on_card(format!("{card} {seid}")),
                );
            }
        }
    };
    repeated(
        "SEBULK",
        b.sebulk.iter().map(|c| (c.seid, &c.loc)).collect(),
    );
    repeated("SELOC", b.seloc.iter().map(|c| (c.seid, &c.loc)).collect());
    errors
}

/// Each card of a part section is one [`renumber`] places, and no superelement control card;
/// a part has at most one GRDSET.
fn check_cards(part: &PartBulk, errors: &mut Vec<DeckError>) {
    for extra in part.bulk.grdset.iter().skip(1) {
        errors.push(
            DeckError::at(
                &extra.loc,
                format!(
                    "a second GRDSET in part superelement {} (the first is at {}); a section has at most one",
                    part.seid, part.bulk.grdset[0].loc
                ),
            )
            .on_card("GRDSET".to_string()),
        );
    }
    for (name, loc) in &part.cards {
        let why = if CONTROL_CARDS.contains(&name.as_str()) {
            format!(
                "{name} in part superelement {}: superelement control cards belong in the main bulk data section",
                part.seid
            )
        } else if !renumber::SUPPORTED.contains(&name.as_str())
            && crate::deck::cards::ignored_card(name).is_none()
        {
            format!(
                "{name} in part superelement {}: paraflex places only these cards of a part into the assembled model: {}",
                part.seid,
                renumber::SUPPORTED.join(" ")
            )
        } else {
            continue;
        };
        errors.push(DeckError::at(loc, why).on_card(name.clone()));
    }
}

/// A part's PARAMs: the assembled model takes the main bulk data's, so the part's PARAMs that
/// differ from (or are missing in) the main bulk data are reported as ignored, in one warning.
fn part_params(part: &PartBulk, residual: &BulkData, warnings: &mut Vec<Warning>) {
    let value = |v: &ParamValue| match v {
        ParamValue::Int(i) => i.to_string(),
        ParamValue::Real(r) => format!("{r:e}"),
        ParamValue::Text(t) => t.clone(),
        ParamValue::Complex(re, im) => format!("({re:e}, {im:e})"),
    };
    let ignored: Vec<String> = (part.bulk.params.iter())
        .filter_map(|p| {
            let main = residual.params.iter().find(|r| r.name == p.name);
            if main.is_some_and(|r| r.value == p.value) {
                return None;
            }
            let main = main.map_or("not set".to_string(), |r| value(&r.value));
            Some(format!("{} {} (main: {main})", p.name, value(&p.value)))
        })
        .collect();
    if let Some(first) = part.bulk.params.first().filter(|_| !ignored.is_empty()) {
        warnings.push(Warning {
            loc: Some(first.loc.to_string()),
            message: format!(
                "PARAMs of part superelement {} ignored: {}; the assembled model takes its PARAMs from the main bulk data",
                part.seid,
                ignored.join(", ")
            ),
        });
    }
}

/// The warning that says what became of a part: renumbered ids and boundary points.
fn summary(part: &PartBulk, map: &PartMap, joins: &[Join]) -> Warning {
    let name = |seid: u32| match seid {
        0 => "residual".to_string(),
        s => format!("part {s}"),
    };
    let points: Vec<String> = (joins.iter())
        .filter_map(|j| {
            let (mine, other) = if j.grid.0 == part.seid {
                (j.grid, j.to)
            } else if j.to.0 == part.seid {
                (j.to, j.grid)
            } else {
                return None;
            };
            Some(match j.rbe2 {
                Some(e) => format!("{} = {} {} (RBE2 {e})", mine.1, name(other.0), other.1),
                None => format!("{} (shared with {})", mine.1, name(other.0)),
            })
        })
        .collect();
    let mut text = format!("part superelement {} assembled", part.seid);
    if points.is_empty() {
        text.push_str(": no boundary point connects it to the residual or to another part");
    } else {
        let more = points.len().saturating_sub(LISTED_POINTS);
        text.push_str(&format!(
            " at {} boundary points: {}{}",
            points.len(),
            points[..points.len().min(LISTED_POINTS)].join(", "),
            if more > 0 {
                format!(" and {more} more")
            } else {
                String::new()
            }
        ));
    }
    let renumbered = map.renumbered_text();
    if !renumbered.is_empty() {
        text.push_str(&format!(
            "; ids used by an earlier section renumbered: {}",
            renumbered.join("; ")
        ));
    }
    Warning {
        loc: Some(part.loc.to_string()),
        message: text,
    }
}
