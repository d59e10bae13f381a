//! Boundary points: which grids of different namespaces (the residual, 0, and each part) are
//! one point of the assembled structure, and how they are joined.
//!
//! Two grids connect when (MSC `SEBULK` METHOD) their namespaces both search automatically
//! (`AUTO`, the default; the residual always does) and they are coincident within the later
//! part's TOL after the `SELOC` moves, or when a `SECONCT` lists them as a pair. Connected grids
//! with the same id are one GRID (their PS combined; their displacement systems must agree at
//! the point). Connected grids with different ids keep their ids and are tied by a generated
//! `RBE2` (all six components of each later grid follow the first grid of the group, residual
//! first, then parts by SEID): the elimination is exact, so the results equal one shared grid,
//! and each grid keeps its own CD, SPCs and loads. Grids that share an id without being
//! connected are an error naming both: results are reported by grid id.

use std::collections::HashMap;

use crate::card_values::Dofs;
use crate::deck::cards::{BulkData, Grid, Rbe2, SeMethod, Seconct};
use crate::deck::{DeckError, Loc};
use crate::model::coords::{self, CoordSystem};

use super::renumber::{Space, UsedIds};

/// How one namespace connects.
#[derive(Clone, Copy)]
pub struct Search {
    pub method: SeMethod,
    pub tol: f64,
}

/// One connection: a grid (namespace, id) joined to the first grid of its group (namespace,
/// id), by a generated RBE2 (its id) or as one GRID (`None`: the same id).
#[derive(Debug, Clone, Copy)]
pub struct Join {
    pub grid: (u32, u32),
    pub to: (u32, u32),
    pub rbe2: Option<u32>,
}

struct UnionFind(Vec<usize>);

impl UnionFind {
    fn find(&mut self, i: usize) -> usize {
        let mut r = i;
        while self.0[r] != r {
            r = self.0[r];
        }
        let mut j = i;
        while self.0[j] != r {
            let next = self.0[j];
            self.0[j] = r;
            j = next;
        }
        r
    }

    /// Join the classes of `a` and `b`; the smaller index (earlier namespace) is the root.
    fn union(&mut self, a: usize, b: usize) {
        let (ra, rb) = (self.find(a), self.find(b));
        let (lo, hi) = (ra.min(rb), ra.max(rb));
        self.0[hi] = lo;
    }
}

fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    (0..3).map(|k| (a[k] - b[k]).powi(2)).sum::<f64>().sqrt()
}

fn cell(p: [f64; 3], size: f64) -> [i64; 3] {
    p.map(|x| (x / size).floor() as i64)
}

/// Whether grid cards `a` and `b` have the same displacement axes at their locations (a
/// missing CD system counts as the same: the model build reports it).
fn same_frame(
    systems: &HashMap<u32, CoordSystem>,
    grids: &[Grid],
    at: &[[f64; 3]],
    a: usize,
    b: usize,
) -> bool {
    let frame = |k: usize| {
        let cd = grids[k].cd.unwrap_or(0);
        systems.get(&cd).map(|s| s.axes_at(at[k]))
    };
    match (frame(a), frame(b)) {
        (Some(x), Some(y)) => (0..3).all(|r| dist(x[r], y[r]) <= 1e-9),
        _ => true,
    }
}

/// Add `ps` to the PS of `grid` (`default_ps`, GRDSET's, when its field is blank).
fn add_ps(grid: &mut Grid, ps: Dofs, default_ps: Dofs) {
    let own = grid.ps.unwrap_or(default_ps);
    grid.ps = Some(Dofs(own.0 | ps.0));
}

/// Whether grid card `k` has a PS or is named by an SPC or SPC1.
fn is_constrained(out: &BulkData, k: usize, default_ps: Dofs) -> bool {
    let id = out.grids[k].id;
    !out.grids[k].ps.unwrap_or(default_ps).is_empty()
        || out.spc.iter().any(|c| c.grid == id)
        || out.spc1.iter().any(|c| c.grids.contains(&id))
}

/// The PS, SPC and SPC1 constraints of the tied grid card `from` moved to the grid card `to`
/// it follows (same displacement axes): a dependent DOF of the tie cannot be constrained, and
/// the constraint means the same on the grid it follows.
fn move_constraints(out: &mut BulkData, from: usize, to: usize, default_ps: Dofs) {
    let (id, head) = (out.grids[from].id, out.grids[to].id);
    let ps = out.grids[from].ps.unwrap_or(default_ps);
    out.grids[from].ps = Some(Dofs::NONE);
    add_ps(&mut out.grids[to], ps, default_ps);
    for c in out.spc.iter_mut().filter(|c| c.grid == id) {
        c.grid = head;
    }
    for c in &mut out.spc1 {
        c.grids
            .iter_mut()
            .filter(|g| **g == id)
            .for_each(|g| *g = head);
    }
}

/// Connect the namespaces of `out` (grid card `i` belongs to namespace `owner[i]`, residual
/// grids first): add the tying RBE2s and drop repeated GRID cards. `loc_of` gives each part's
/// `BEGIN SUPER` line (the generated RBE2s' position).
pub fn connect(
    out: &mut BulkData,
    owner: &[u32],
    search: &HashMap<u32, Search>,
    seconct: &[Seconct],
    loc_of: &HashMap<u32, Loc>,
    used: &mut UsedIds,
    errors: &mut Vec<DeckError>,
) -> Vec<Join> {
    let mut ignored = Vec::new();
    let systems = coords::resolve(&out.coords, &mut ignored);
    let basic = CoordSystem::basic();
    let default_cp = out.grdset.first().map_or(0, |d| d.cp);
    let default_ps = out.grdset.first().map_or(Dofs::NONE, |d| d.ps);
    let at: Vec<[f64; 3]> = (out.grids.iter())
        .map(|g| {
            systems
                .get(&g.cp.unwrap_or(default_cp))
                .unwrap_or(&basic)
                .point_to_basic(g.x)
        })
        .collect();
    let mut uf = UnionFind((0..out.grids.len()).collect());
    coincident(&at, owner, search, &mut uf);
    seconct_pairs(&at, owner, &out.grids, seconct, &mut uf, errors);
    let points = Points {
        systems: &systems,
        at: &at,
        owner,
        default_ps,
    };
    let (drop, first_of_id) = same_ids(out, &points, &mut uf, errors);
    let joins = tie(
        out,
        &points,
        &mut uf,
        (&drop, &first_of_id),
        loc_of,
        used,
        errors,
    );
    let mut k = 0;
    out.grids.retain(|_| {
        k += 1;
        !drop[k - 1]
    });
    joins
}

/// What the connection steps know of the grid cards: displacement systems, basic locations,
/// namespaces, GRDSET's PS.
struct Points<'a> {
    systems: &'a HashMap<u32, CoordSystem>,
    at: &'a [[f64; 3]],
    owner: &'a [u32],
    default_ps: Dofs,
}

/// Join each grid of an `AUTO` part to the nearest grid within its TOL of the `AUTO`
/// namespaces before it (residual first), found through a grid of cells of the largest TOL.
fn coincident(at: &[[f64; 3]], owner: &[u32], search: &HashMap<u32, Search>, uf: &mut UnionFind) {
    let search_of = |seid: u32| {
        search.get(&seid).copied().unwrap_or(Search {
            method: SeMethod::Auto,
            tol: crate::deck::cards::DEFAULT_SE_TOL,
        })
    };
    let n = at.len();
    let mut order: Vec<u32> = owner.to_vec();
    order.dedup();
    let max_tol = order.iter().map(|&s| search_of(s).tol).fold(0.0, f64::max);
    let size = max_tol.max(1e-300);
    let mut cells: HashMap<[i64; 3], Vec<usize>> = HashMap::new();
    for &seid in &order {
        let s = search_of(seid);
        let members: Vec<usize> = (0..n).filter(|&i| owner[i] == seid).collect();
        if s.method == SeMethod::Auto {
            if seid != 0 {
                for &i in &members {
                    let c = cell(at[i], size);
                    let mut best: Option<(f64, usize)> = None;
                    for dx in -1..=1 {
                        for dy in -1..=1 {
                            for dz in -1..=1 {
                                let key = [c[0] + dx, c[1] + dy, c[2] + dz];
                                for &j in cells.get(&key).into_iter().flatten() {
                                    let d = dist(at[i], at[j]);
                                    if d <= s.tol && best.is_none_or(|(bd, bj)| (d, j) < (bd, bj)) {
                                        best = Some((d, j));
                                    }
                                }
                            }
                        }
                    }
                    if let Some((_, j)) = best {
                        uf.union(i, j);
                    }
                }
            }
            for &i in &members {
                cells.entry(cell(at[i], size)).or_default().push(i);
            }
        }
    }
}

/// Join the `SECONCT` pairs (an error for a grid the section lacks or a pair too far apart).
fn seconct_pairs(
    at: &[[f64; 3]],
    owner: &[u32],
    grids: &[Grid],
    seconct: &[Seconct],
    uf: &mut UnionFind,
    errors: &mut Vec<DeckError>,
) {
    let n = at.len();
    let index: HashMap<(u32, u32), usize> = (0..n).map(|i| ((owner[i], grids[i].id), i)).collect();
    for card in seconct {
        for &(a, b) in &card.pairs {
            let find = |seid: u32, gid: u32| {
                index.get(&(seid, gid)).copied().ok_or_else(|| {
                    let whose = match seid {
                        0 => "the main bulk data".to_string(),
                        s => format!("part superelement {s}"),
                    };
                    DeckError::at(
                        &card.loc,
                        format!(
                            "SECONCT {} {}: GRID {gid} is not a grid of {whose}",
                            card.seid_a, card.seid_b
                        ),
                    )
                    .on_card(format!("SECONCT {}", card.seid_a))
                })
            };
            match (find(card.seid_a, a), find(card.seid_b, b)) {
                (Ok(i), Ok(j)) => {
                    let d = dist(at[i], at[j]);
                    if card.check_location && d > card.tol {
                        errors.push(
                            DeckError::at(
                                &card.loc,
                                format!(
                                    "SECONCT {} {}: GRID {a} and GRID {b} are {d:.4e} apart (TOL {:.1e}, LOC = YES): a pair must be coincident",
                                    card.seid_a, card.seid_b, card.tol
                                ),
                            )
                            .on_card(format!("SECONCT {}", card.seid_a)),
                        );
                    } else {
                        uf.union(i, j);
                    }
                }
                (a, b) => errors.extend(a.err().into_iter().chain(b.err())),
            }
        }
    }
}

/// Grid cards with one id: one GRID when they are connected (PS combined; the later cards are
/// dropped), else an error. Returns the dropped cards and each id's kept card.
fn same_ids(
    out: &mut BulkData,
    p: &Points,
    uf: &mut UnionFind,
    errors: &mut Vec<DeckError>,
) -> (Vec<bool>, HashMap<u32, usize>) {
    let (at, owner, default_ps) = (p.at, p.owner, p.default_ps);
    let n = at.len();
    let mut first_of_id: HashMap<u32, usize> = HashMap::new();
    let mut drop = vec![false; n];
    for i in 0..n {
        let id = out.grids[i].id;
        let Some(&f) = first_of_id.get(&id) else {
            first_of_id.insert(id, i);
            continue;
        };
        let name = |k: usize| match owner[k] {
            0 => "the main bulk data".to_string(),
            s => format!("part superelement {s}"),
        };
        if uf.find(i) != uf.find(f) {
            errors.push(
                DeckError::at(
                    &out.grids[i].loc,
                    format!(
                        "GRID {id} of {} at {:?} and GRID {id} of {} ({}) at {:?} have the same id but are not connected (not coincident within TOL, nor a SECONCT pair): paraflex reports results by grid id, so give one of them another id",
                        name(i), at[i], name(f), out.grids[f].loc, at[f]
                    ),
                )
                .on_card(format!("GRID {id}")),
            );
            continue;
        }
        let same = same_frame(p.systems, &out.grids, at, i, f);
        if !same {
            errors.push(
                DeckError::at(
                    &out.grids[i].loc,
                    format!(
                        "GRID {id} of {} and GRID {id} of {} ({}) are one point with different displacement systems (CD); give them the same CD or different ids",
                        name(i), name(f), out.grids[f].loc
                    ),
                )
                .on_card(format!("GRID {id}")),
            );
        }
        let ps = out.grids[i].ps.unwrap_or(Dofs::NONE);
        add_ps(&mut out.grids[f], ps, default_ps);
        drop[i] = true;
    }

    (drop, first_of_id)
}

/// The grids of each connected group with different ids: one generated RBE2 makes them follow
/// one grid (the first constrained one, else the first), their constraints moved to it.
fn tie(
    out: &mut BulkData,
    p: &Points,
    uf: &mut UnionFind,
    (drop, first_of_id): (&[bool], &HashMap<u32, usize>),
    loc_of: &HashMap<u32, Loc>,
    used: &mut UsedIds,
    errors: &mut Vec<DeckError>,
) -> Vec<Join> {
    let (at, owner, default_ps) = (p.at, p.owner, p.default_ps);
    let n = at.len();
    let mut classes: HashMap<usize, Vec<usize>> = HashMap::new();
    for i in 0..n {
        classes.entry(uf.find(i)).or_default().push(i);
    }
    let mut roots: Vec<usize> = classes.keys().copied().collect();
    roots.sort_unstable();
    let mut joins: Vec<Join> = Vec::new();
    for root in roots {
        let members = &classes[&root];
        for &m in members.iter().filter(|&&m| drop[m]) {
            let kept = first_of_id[&out.grids[m].id];
            joins.push(Join {
                grid: (owner[m], out.grids[m].id),
                to: (owner[kept], out.grids[kept].id),
                rbe2: None,
            });
        }
        let kept: Vec<usize> = members.iter().copied().filter(|&m| !drop[m]).collect();
        if kept.len() < 2 {
            continue;
        }
        // the grid the others follow: the first constrained one (a dependent DOF cannot be
        // constrained), else the first (residual first, then parts by SEID)
        let head = (kept.iter().copied())
            .find(|&k| is_constrained(out, k, default_ps))
            .unwrap_or(kept[0]);
        let eid = used.fresh(Space::Element);
        let head_id = out.grids[head].id;
        let mut tied = Vec::new();
        for &k in kept.iter().filter(|&&k| k != head) {
            let id = out.grids[k].id;
            if same_frame(p.systems, &out.grids, at, k, head) {
                move_constraints(out, k, head, default_ps);
            } else if is_constrained(out, k, default_ps) {
                errors.push(
                    DeckError::at(
                        &out.grids[k].loc,
                        format!(
                            "GRID {id} is tied to GRID {head_id} (one boundary point) and both are constrained by a PS or an SPC, but their displacement systems (CD) differ there, so the two constraints cannot act on one grid: give them the same CD, or constrain only one"
                        ),
                    )
                    .on_card(format!("GRID {id}")),
                );
            }
            tied.push(id);
            joins.push(Join {
                grid: (owner[k], id),
                to: (owner[head], head_id),
                rbe2: Some(eid),
            });
        }
        let seid = kept.iter().map(|&k| owner[k]).max().unwrap_or(0);
        out.rbe2.push(Rbe2 {
            id: eid,
            gn: head_id,
            cm: Dofs::ALL,
            gm: tied,
            alpha: 0.0,
            loc: (loc_of.get(&seid).cloned()).unwrap_or_else(|| out.grids[head].loc.clone()),
        });
    }
    joins
}
