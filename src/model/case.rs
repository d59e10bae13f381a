//! Case-control checks, per subcase (global defaults applied):
//!
//! | selection | must exist |
//! |---|---|
//! | SPC | SPC / SPC1 / SPCADD set |
//! | MPC | MPC / MPCADD set, the same in every subcase that selects one |
//! | LOAD | LOAD / FORCE / MOMENT / GRAV set |
//! | METHOD | EIGRL |
//! | FREQUENCY | FREQ / FREQ1 / FREQ2 set |
//! | DLOAD | DLOAD / TLOAD1–2 / RLOAD1–2 set |
//! | TSTEP | TSTEP |
//! | PROM | PMOR |
//! | PVAL | PVAL |
//! | POSES | FMBPOSE, in a subcase without TSTEP (a static one) |
//! | TEMPERATURE(LOAD), TEMPERATURE(MATERIAL / INITIAL / BOTH) | TEMP / TEMPD set |
//! | SENSOR = n | case-control SET n, whose ids are SENSOR ids |
//! | output request = n | case-control SET n |
//!
//! Errors point at the statement (`Subcase::loc_of`). Which output requests the solution
//! sequence writes is the sequence's business (`crate::sequence::request_warnings`).
//!
//! The other way round, an SPC set (SPC / SPC1 / SPCADD), an MPC set (MPC / MPCADD) or a LOAD
//! set (LOAD / FORCE / MOMENT / GRAV) that bulk data defines but nothing selects (no subcase's
//! `SPC =`, `MPC =` or `LOAD =`, no SPCADD, MPCADD or LOAD combination, no TLOAD / RLOAD EXCITEID) is a warning at its first card
//! ([`unselected_sets`]): a forgotten `SPC = 1` otherwise leaves a structure free without a word.

use std::collections::{BTreeMap, HashSet};

use crate::card_values::ForceKind;
use crate::deck::case_control::{StrainReference, Subcase, Target};
use crate::deck::{Deck, DeckError, Loc, Warning};

use super::build::Refs;

/// Run the checks for every subcase.
pub fn check(deck: &Deck, refs: &Refs, errors: &mut Vec<DeckError>) {
    let b = refs.bulk;
    let set_of = |ids: Vec<u32>| -> HashSet<u32> { ids.into_iter().collect() };
    let spc = set_of(
        b.spc
            .iter()
            .map(|s| s.sid)
            .chain(b.spc1.iter().map(|s| s.sid))
            .chain(b.spcadd.iter().map(|s| s.sid))
            .collect(),
    );
    let load = set_of(
        b.load
            .iter()
            .map(|s| s.sid)
            .chain(b.static_load_sets())
            .collect(),
    );
    let method = set_of(b.eigrl.iter().map(|s| s.sid).collect());
    let freq = set_of(b.freq.iter().map(|s| s.sid).collect());
    let tabdmp1 = set_of(b.tabdmp1.iter().map(|t| t.id).collect());
    let randps = set_of(b.randps.iter().map(|r| r.sid).collect());
    let dload = set_of(
        b.dload
            .iter()
            .map(|s| s.sid)
            .chain(b.tload.iter().map(|s| s.sid))
            .chain(b.rload.iter().map(|s| s.sid))
            .collect(),
    );
    let tstep = set_of(b.tstep.iter().map(|s| s.sid).collect());
    let prom = set_of(b.pmor.iter().map(|s| s.id).collect());
    let pval = set_of(
        b.pval
            .iter()
            .map(|s| s.id)
            .chain(b.ptable.iter().map(|s| s.id))
            .collect(),
    );
    let tic = set_of(b.tic.iter().map(|s| s.sid).collect());
    let sensors = set_of(b.sensors.iter().map(|s| s.id).collect());
    let poses = set_of(b.fmbpose.iter().map(|s| s.id).collect());
    let temperatures = set_of(
        b.temp
            .iter()
            .map(|t| t.sid)
            .chain(b.tempd.iter().map(|t| t.sid))
            .collect(),
    );

    let fallback = deck.executive.sol_loc.clone().unwrap_or_else(|| Loc {
        file: std::sync::Arc::from(deck.path.as_path()),
        line: 1,
    });
    let mut reported: HashSet<(String, Loc)> = HashSet::new();

    let subcases = deck.case.subcases();
    for (index, sub) in subcases.iter().cloned().enumerate() {
        let loc = |name: &str| {
            sub.loc_of(name)
                .cloned()
                .unwrap_or_else(|| fallback.clone())
        };
        let mut need = |name: &str, id: Option<u32>, have: &HashSet<u32>, cards: &str| {
            if let Some(id) = id
                && !have.contains(&id)
            {
                let at = loc(name);
                if reported.insert((format!("{name} {id}"), at.clone())) {
                    errors.push(
                        DeckError::at(
                            &at,
                            format!(
                                "{name} = {id} selects no {cards} set {id}{}",
                                subcase_text(&sub)
                            ),
                        )
                        .on_card(name.to_string()),
                    );
                }
            }
        };
        need("SPC", sub.spc, &spc, "SPC/SPC1/SPCADD");
        // an MPC selection without any MPC/MPCADD card is a warning (`unselected_sets`)
        // a deck loading a mechanism (FMB =) may select a gravity set stored with it
        if sub.fmb.is_none() {
            need(
                "LOAD",
                sub.load,
                &load,
                "LOAD/FORCE/MOMENT/FORCE1/FORCE2/MOMENT1/MOMENT2/SLOAD/GRAV/PLOAD4/PLOAD2/PLOAD/PLOAD1/SPCD",
            );
        }
        need("METHOD", sub.method, &method, "EIGRL/EIGR");
        need("FREQUENCY", sub.frequency, &freq, "FREQ/FREQ1 … FREQ5");
        need("RANDOM", sub.random, &randps, "RANDPS");
        // direct transient, statics and modes do not read SDAMPING (Nastran ignores it there,
        // whatever it selects; the sequence warns that it is not applied)
        let reads_sdamping = !matches!(
            deck.executive.sol,
            Some((
                crate::deck::Solution::TransientDirect
                    | crate::deck::Solution::Statics
                    | crate::deck::Solution::Modal,
                _
            ))
        );
        if reads_sdamping {
            need("SDAMPING", sub.sdamping, &tabdmp1, "TABDMP1");
        }
        need(
            "DLOAD",
            sub.dload,
            &dload,
            "DLOAD/TLOAD1/TLOAD2/RLOAD1/RLOAD2",
        );
        need("TSTEP", sub.tstep, &tstep, "TSTEP");
        need("PROM", sub.prom, &prom, "PMOR");
        need("PVAL", sub.pval, &pval, "PVAL/PTABLE");
        need("IC", sub.ic, &tic, "TIC");
        need("POSES", sub.poses, &poses, "FMBPOSE");
        need(
            "TEMPERATURE(LOAD)",
            sub.temperature_load,
            &temperatures,
            "TEMP/TEMPD",
        );
        need(
            "TEMPERATURE(MATERIAL)",
            sub.temperature_material,
            &temperatures,
            "TEMP/TEMPD",
        );
        if let (Some(id), Some(sid)) = (sub.poses, sub.tstep) {
            errors.push(
                DeckError::at(
                    &loc("POSES"),
                    format!(
                        "POSES = {id} in a transient subcase (TSTEP = {sid}){}: a pose grid is solved by statics; give it a subcase without TSTEP",
                        subcase_text(&sub)
                    ),
                )
                .on_card("POSES"),
            );
        }
        if let Some(coefficients) = &sub.combination {
            let preceding = subcases[..index]
                .iter()
                .filter(|s| s.combination.is_none())
                .count();
            let statics = matches!(
                deck.executive.sol,
                Some((crate::deck::Solution::Statics, _))
            );
            let problem = if !statics {
                Some("SUBCOM combines the results of static subcases; this deck's SOL is not SOL 101".to_string())
            } else if coefficients.is_empty() {
                Some("SUBCOM without SUBSEQ: give SUBSEQ = c1, c2, … (one coefficient per preceding SUBCASE)".to_string())
            } else if coefficients.len() > preceding {
                Some(format!(
                    "SUBSEQ lists {} coefficients, but {preceding} SUBCASE(s) precede this SUBCOM (one coefficient per preceding SUBCASE, in deck order)",
                    coefficients.len()
                ))
            } else {
                None
            };
            if let Some(problem) = problem {
                let at = sub.loc_of("SUBSEQ").unwrap_or(&loc("SUBCOM")).clone();
                errors.push(DeckError::at(&at, problem).on_card(format!("SUBCOM {}", sub.id)));
            }
        }
        if let Some(StrainReference::Subcase(id)) = sub.strref
            && !subcases[..index].iter().any(|s| s.id == id)
        {
            errors.push(
                DeckError::at(
                    &loc("STRREF"),
                    format!(
                        "STRREF = {id}: no subcase {id} before this one{} (the reference is the last state of an earlier subcase)",
                        subcase_text(&sub)
                    ),
                )
                .on_card("STRREF"),
            );
        }
        if let Some(Target::Set(id)) = sub.sensor {
            let at = loc("SENSOR");
            match deck.case.set(id) {
                None => {
                    if reported.insert((format!("SENSOR {id}"), at.clone())) {
                        errors.push(
                            DeckError::at(&at, format!("SENSOR = {id}: no case-control SET {id}"))
                                .on_card("SENSOR"),
                        );
                    }
                }
                Some(set) => {
                    for s in set.ids.iter().filter(|s| !sensors.contains(s)) {
                        if reported.insert((format!("SENSOR {id} {s}"), set.loc.clone())) {
                            errors.push(DeckError::at(&set.loc, format!("SET {id} lists {s}, but there is no SENSOR {s} (required by SENSOR = {id})")).on_card(format!("SET {id}")));
                        }
                    }
                }
            }
        }
        for out in &sub.outputs {
            if let Target::Set(id) = out.target
                && deck.case.set(id).is_none()
                && reported.insert((format!("{} {id}", out.name), out.loc.clone()))
            {
                errors.push(
                    DeckError::at(
                        &out.loc,
                        format!("{} = {id}: no case-control SET {id}", out.name),
                    )
                    .on_card(out.name.to_string()),
                );
            }
        }
    }
    one_mpc_set(&subcases, errors);
}

/// The MPC elimination is part of the structure every subcase shares: subcases that select
/// different MPC sets, or a subcase without `MPC =` beside one with it, are refused at the
/// statement (Nastran would eliminate per subcase).
fn one_mpc_set(subcases: &[Subcase], errors: &mut Vec<DeckError>) {
    let Some(first) = subcases.iter().find(|s| s.mpc.is_some()) else {
        return;
    };
    for sub in subcases.iter().filter(|s| s.mpc != first.mpc) {
        let (at, what) = match sub.mpc {
            Some(id) => (sub.loc_of("MPC"), format!("MPC = {id}")),
            None => (sub.loc_of("SUBCASE"), "no MPC =".to_string()),
        };
        let Some(at) = at.or_else(|| first.loc_of("MPC")) else {
            continue;
        };
        errors.push(
            DeckError::at(
                at,
                format!(
                    "{what}{} while subcase {} selects MPC = {}: paraflex eliminates one MPC set for the whole run; select the same set in every subcase (MPC = above the first SUBCASE)",
                    subcase_text(sub),
                    first.id,
                    first.mpc.unwrap_or_default()
                ),
            )
            .on_card("MPC"),
        );
    }
}
fn subcase_text(sub: &Subcase) -> String {
    format!(" (subcase {})", sub.id)
}

/// Warn about the SPC and LOAD sets nothing selects (see the module documentation), one
/// warning per set id at its first card, naming the subcases without a selection.
pub fn unselected_sets(deck: &Deck, warnings: &mut Vec<Warning>) {
    if !deck.has_control_sections {
        return;
    }
    let b = &deck.bulk;
    let subcases = deck.case.subcases();
    let spc_cards = b
        .spc
        .iter()
        .map(|c| (c.sid, "SPC", &c.loc))
        .chain(b.spc1.iter().map(|c| (c.sid, "SPC1", &c.loc)))
        .chain(b.spcadd.iter().map(|c| (c.sid, "SPCADD", &c.loc)));
    let spc_selected = subcases
        .iter()
        .filter_map(|s| s.spc)
        .chain(b.spcadd.iter().flat_map(|c| c.sets.iter().copied()));
    warn_unselected(
        "SPC",
        "its constraints are not applied",
        spc_cards,
        spc_selected,
        &subcases,
        |s| s.spc,
        warnings,
    );
    let mpc_cards = b
        .mpc
        .iter()
        .map(|c| (c.sid, "MPC", &c.loc))
        .chain(b.mpcadd.iter().map(|c| (c.sid, "MPCADD", &c.loc)));
    let mpc_selected = subcases
        .iter()
        .filter_map(|s| s.mpc)
        .chain(b.mpcadd.iter().flat_map(|c| c.sets.iter().copied()));
    warn_unselected(
        "MPC",
        "its equations are not applied",
        mpc_cards,
        mpc_selected,
        &subcases,
        |s| s.mpc,
        warnings,
    );
    // MPC = sid with no MPC/MPCADD card of that id applies nothing: MSC Nastran runs such
    // decks (pyNastran's random/random_test_bar_plus_tri.bdf and its OP2), so a warning
    let mut warned = HashSet::new();
    for sub in &subcases {
        let Some(sid) = sub.mpc else { continue };
        let defined = b.mpc.iter().any(|c| c.sid == sid) || b.mpcadd.iter().any(|c| c.sid == sid);
        if !defined && warned.insert(sid) {
            warnings.push(Warning {
                loc: sub.loc_of("MPC").map(ToString::to_string),
                message: format!(
                    "MPC = {sid} selects no MPC/MPCADD set {sid}: no multipoint constraint is applied (MSC Nastran runs such a deck too)"
                ),
            });
        }
    }
    let force_name = |kind: ForceKind| match kind {
        ForceKind::Force => "FORCE",
        ForceKind::Moment => "MOMENT",
    };
    let load_cards = b
        .load
        .iter()
        .map(|c| (c.sid, "LOAD", &c.loc))
        .chain(b.forces.iter().map(|c| (c.sid, force_name(c.kind), &c.loc)))
        .chain(b.grav.iter().map(|c| (c.sid, "GRAV", &c.loc)))
        .chain(b.pload4.iter().map(|c| (c.sid, "PLOAD4", &c.loc)))
        .chain(b.pload2.iter().map(|c| (c.sid, "PLOAD2", &c.loc)))
        .chain(b.pload.iter().map(|c| (c.sid, "PLOAD", &c.loc)))
        .chain(b.pload1.iter().map(|c| (c.sid, "PLOAD1", &c.loc)))
        .chain(b.spcd.iter().map(|c| (c.sid, "SPCD", &c.loc)))
        .chain((b.forces_by_grids.iter()).map(|c| (c.sid, c.card(), &c.loc)))
        .chain(b.sload.iter().map(|c| (c.sid, "SLOAD", &c.loc)));
    let load_selected = subcases
        .iter()
        .filter_map(|s| s.load)
        .chain(
            b.load
                .iter()
                .flat_map(|c| c.terms.iter().map(|(_, sid)| *sid)),
        )
        .chain(b.tload.iter().map(|t| t.excite_id))
        .chain(b.rload.iter().map(|r| r.excite_id))
        .chain(b.lseq.iter().map(|l| l.lid));
    warn_unselected(
        "LOAD",
        "it is not applied",
        load_cards,
        load_selected,
        &subcases,
        |s| s.load,
        warnings,
    );
}

/// One warning per set id of `cards` (id, card name, position) that `selected` does not hold.
fn warn_unselected<'a>(
    selection: &str,
    effect: &str,
    cards: impl Iterator<Item = (u32, &'static str, &'a Loc)>,
    selected: impl Iterator<Item = u32>,
    subcases: &[Subcase],
    selects: impl Fn(&Subcase) -> Option<u32>,
    warnings: &mut Vec<Warning>,
) {
    let selected: HashSet<u32> = selected.collect();
    let mut first: BTreeMap<u32, (&str, &Loc)> = BTreeMap::new();
    for (sid, card, loc) in cards {
        first.entry(sid).or_insert((card, loc));
    }
    let without: Vec<String> = subcases
        .iter()
        .filter(|s| selects(s).is_none())
        .map(|s| s.id.to_string())
        .collect();
    let subcases_text = if without.is_empty() {
        format!("every subcase selects another {selection} set")
    } else {
        format!("subcase(s) without {selection} =: {}", without.join(", "))
    };
    for (sid, (card, loc)) in first.into_iter().filter(|(sid, _)| !selected.contains(sid)) {
        warnings.push(Warning {
            loc: Some(loc.to_string()),
            message: format!(
                "{card} set {sid} is selected by no subcase ({subcases_text}): {effect}; add {selection} = {sid} to case control"
            ),
        });
    }
}
