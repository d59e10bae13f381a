//! `RSSCON` shell-to-solid connectors resolved to links: a shell grid and the two solid grids
//! (bottom, top) of the solid edge through it. The equations a link imposes are in
//! [`assembly::rsscon`](crate::assembly::rsscon).
//!
//! The `GRID` form gives the links. The `ELEM` form gives a shell element and a solid
//! element: each grid of the shell that lies on a line between two grids of the solid, that
//! line being along the shell normal (the solid edge spans the shell's thickness direction), is
//! linked to the longest such pair (a 20-node solid's corner edge, not its half through the
//! mid-side grid). A shell grid counts as on the line within Nastran's default `TOLRSC`: at most
//! 5 % of the edge length from it and between its ends (5 % beyond them at most). Shell grids
//! off the solid are not linked (the free edges of the shell element); a `GRID` link out of
//! tolerance is an error, as in Nastran.

use std::collections::HashMap;

use super::build::Refs;
use super::{Element, ElementKind, GridPoint, Rigid, RigidKind};
use crate::deck::DeckError;
use crate::deck::cards::RssconForm;
use crate::geometry::vec3::{cross, dot, norm, sub};

/// Nastran's `PARAM,TOLRSC` default: the distance a shell grid may be from the solid edge, as
/// a fraction of the edge length.
pub const TOLRSC: f64 = 0.05;

/// Smallest |cos| between a candidate solid edge and the shell normal for the `ELEM` search.
const ALONG_NORMAL: f64 = 0.9;

/// One shell grid tied to a solid edge (grid indices into [`Model::grids`](super::Model::grids)).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct RssconLink {
    pub shell: usize,
    pub bottom: usize,
    pub top: usize,
}

/// Where `p` is on the line a → b: (ξ, distance from the line / |b − a|), ξ = 0 at a and 1 at
/// b; `None` when a and b coincide.
pub fn on_line(p: [f64; 3], a: [f64; 3], b: [f64; 3]) -> Option<(f64, f64)> {
    let ab = sub(b, a);
    let h2 = dot(ab, ab);
    if !(h2 > 0.0) {
        return None;
    }
    let ap = sub(p, a);
    let xi = dot(ap, ab) / h2;
    let off = norm(cross(ab, ap)) / h2;
    Some((xi, off))
}

/// True when (ξ, offset) of [`on_line`] is within [`TOLRSC`] of the segment.
fn within_tolerance((xi, off): (f64, f64)) -> bool {
    off <= TOLRSC && (-TOLRSC..=1.0 + TOLRSC).contains(&xi)
}

/// The RSSCON cards of a deck as rigid elements (links resolved); errors name card and field.
pub(super) fn build(
    refs: &Refs,
    grids: &[GridPoint],
    elements: &[Element],
    errors: &mut Vec<DeckError>,
) -> Vec<Rigid> {
    let by_id: HashMap<u32, &Element> = elements
        .iter()
        .filter(|e| e.kind.is_shell() || e.kind.solid_kind().is_some())
        .map(|e| (e.id, e))
        .collect();
    let mut out = Vec::new();
    for r in &refs.bulk.rsscon {
        let card = format!("RSSCON {}", r.id);
        let mut fail = |message: String| {
            errors.push(DeckError::at(&r.loc, message).on_card(card.clone()));
        };
        let links = match &r.form {
            RssconForm::Grid { links } => {
                let mut out = Vec::new();
                for (k, [s, a, b]) in links.iter().enumerate() {
                    let n = k + 1;
                    let ids = [
                        refs.grid(*s, &format!("ES{n}"), &card, &r.loc, errors),
                        refs.grid(*a, &format!("EA{n}"), &card, &r.loc, errors),
                        refs.grid(*b, &format!("EB{n}"), &card, &r.loc, errors),
                    ];
                    let [Some(shell), Some(bottom), Some(top)] = ids else {
                        continue;
                    };
                    let at = |g: usize| grids[g].xyz;
                    match on_line(at(shell), at(bottom), at(top)) {
                        None => errors.push(
                            DeckError::at(
                                &r.loc,
                                format!("EA{n} = {a} and EB{n} = {b} are at the same location: they do not make a solid edge"),
                            )
                            .on_card(card.clone()),
                        ),
                        Some(place) if !within_tolerance(place) => errors.push(
                            DeckError::at(
                                &r.loc,
                                format!(
                                    "shell grid ES{n} = {s} is not on the solid edge EA{n} = {a} – EB{n} = {b} (at ξ = {:.3} along it, {:.3} edge lengths off it; Nastran's TOLRSC allows {TOLRSC})",
                                    place.0, place.1
                                ),
                            )
                            .on_card(card.clone()),
                        ),
                        Some(_) => out.push(RssconLink { shell, bottom, top }),
                    }
                }
                out
            }
            RssconForm::Elem { shell, solid } => {
                let es = by_id.get(shell).filter(|e| e.kind.is_shell());
                let ea = by_id.get(solid).filter(|e| e.kind.solid_kind().is_some());
                match (es, ea) {
                    (None, _) => {
                        fail(format!(
                            "ES1 = {shell} is not a shell element (CQUAD4, CTRIA3, CQUADR, CTRIAR, CQUAD8, CTRIA6)"
                        ));
                        continue;
                    }
                    (_, None) => {
                        fail(format!(
                            "EA1 = {solid} is not a solid element (CHEXA, CPENTA, CTETRA)"
                        ));
                        continue;
                    }
                    (Some(es), Some(ea)) => {
                        let links = element_links(grids, es, ea);
                        if links.is_empty() {
                            fail(format!(
                                "no grid of shell element {shell} lies on an edge of solid element {solid} along the shell normal (within TOLRSC = {TOLRSC} of the edge length)"
                            ));
                        }
                        links
                    }
                }
            }
        };
        if links.is_empty() {
            continue;
        }
        let hub = links[0].shell;
        let mut legs: Vec<usize> = Vec::new();
        for l in &links {
            for g in [l.shell, l.bottom, l.top] {
                if g != hub && !legs.contains(&g) {
                    legs.push(g);
                }
            }
        }
        out.push(Rigid {
            id: r.id,
            kind: RigidKind::Rsscon { links },
            hub,
            legs,
            loc: r.loc.clone(),
        });
    }
    out
}

/// The `ELEM` form's links: each shell grid on a solid edge along the shell normal, linked to
/// the longest such pair of solid grids.
fn element_links(grids: &[GridPoint], shell: &Element, solid: &Element) -> Vec<RssconLink> {
    let at = |g: usize| grids[g].xyz;
    let corners = match shell.kind {
        ElementKind::Tria3 | ElementKind::TriaR | ElementKind::Tria6 => 3,
        _ => 4,
    };
    let c: Vec<[f64; 3]> = shell.nodes.iter().take(corners).map(|&g| at(g)).collect();
    let normal = if corners == 3 {
        cross(sub(c[1], c[0]), sub(c[2], c[0]))
    } else {
        cross(sub(c[2], c[0]), sub(c[3], c[1]))
    };
    let nn = norm(normal);
    if !(nn > 0.0) {
        return Vec::new();
    }
    let mut links = Vec::new();
    for &s in &shell.nodes {
        let mut best: Option<(f64, RssconLink)> = None;
        for (i, &a) in solid.nodes.iter().enumerate() {
            for &b in &solid.nodes[i + 1..] {
                let ab = sub(at(b), at(a));
                let h = norm(ab);
                if !(h > 0.0) || dot(ab, normal).abs() < ALONG_NORMAL * h * nn {
                    continue;
                }
                let fits = on_line(at(s), at(a), at(b)).is_some_and(within_tolerance);
                if fits && best.is_none_or(|(longest, _)| h > longest) {
                    let link = RssconLink {
                        shell: s,
                        bottom: a,
                        top: b,
                    };
                    best = Some((h, link));
                }
            }
        }
        if let Some((_, link)) = best {
            links.push(link);
        }
    }
    links
}
