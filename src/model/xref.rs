//! Cross-references between bulk cards (grids and properties of elements are resolved in
//! [`build`](super::build)):
//!
//! | card | field | must exist |
//! |---|---|---|
//! | PSHELL | MID1 MID2 MID3 MID4 | MAT1 or MAT8; MID1 or MID2 given; MID3 blank unless MID2 is given; MID4 blank unless MID1 and MID2 are given, and different from both (Nastran) |
//! | PCOMP | MIDi | MAT8 or MAT1 |
//! | PSOLID | MID | MAT1 (a MAT8 is an error: it is a plane-stress shell material) |
//! | PROD, PTUBE, PBAR, PBARL, PBEAM, PBEAML, CONROD | MID | MAT1 |
//! | SPC, SPC1, ASET1, DAREA, FORCE/MOMENT | grids | GRID |
//! | FORCE/MOMENT, GRAV | CID | coordinate system |
//! | SPCADD | Si | SPC/SPC1 set |
//! | MPC | Gi | GRID |
//! | MPCADD | Si | MPC set |
//! | LOAD | Li | FORCE/MOMENT/FORCE1/FORCE2/MOMENT1/MOMENT2/SLOAD/GRAV/PLOAD4/PLOAD2/PLOAD/PLOAD1/SPCD set |
//! | TLOAD1/2, RLOAD1/2 | EXCITEID | DAREA set or static load set (FORCE/MOMENT/FORCE1/FORCE2/MOMENT1/MOMENT2/SLOAD/GRAV/PLOAD4/PLOAD2/PLOAD/PLOAD1/SPCD/LOAD) |
//! | TLOAD1 TID, RLOAD1 TC/TD, RLOAD2 TB/TP (≠ 0) | table | TABLED1–TABLED4 or TABLEF |
//! | DLOAD | Li | TLOAD1/2, RLOAD1/2 set |
//! | DESVAR | DDVAL | DDVAL |
//! | SENSOR | REF | GRID (DISP/VEL/ACCEL) or element (STRAIN); SURF only on shells |
//! | PVAL | NAMEi | PMPAR name |
//! | PMOR | BSET | at least one ASET1 card |
//! | TINTEG | ID | TSTEP |
//!
//! Problems of a property are reported on the property, with "required by" naming the elements
//! that use it.

use std::collections::{HashMap, HashSet};

use crate::card_values::{Dofs, ForceKind, SensorKind};
use crate::deck::cards::{BulkData, ExcitationKind, ParamValue, TloadFunction};
use crate::deck::{Deck, DeckError, Loc, Warning};

use super::MaterialRef;
use super::build::Refs;
use super::ids::{entry, index};

/// Run every check of the table above.
pub fn check(refs: &Refs, deck: &Deck, errors: &mut Vec<DeckError>, warnings: &mut Vec<Warning>) {
    let b = refs.bulk;
    let users = property_users(refs);
    let required_by = |pid: u32| -> String {
        match users.get(&pid) {
            Some(list) if !list.is_empty() => format!(" (required by {})", list.join(", ")),
            _ => String::new(),
        }
    };

    // property → material
    for p in &b.pshell {
        let card = format!("PSHELL {}", p.id);
        if p.mid1.is_none() && p.mid2.is_none() {
            errors.push(
                DeckError::at(
                    &p.loc,
                    format!(
                        "neither MID1 nor MID2 is given: the shell has no stiffness and no mass{}",
                        required_by(p.id)
                    ),
                )
                .on_card(&card),
            );
        }
        if p.mid3.is_some() && p.mid2.is_none() {
            errors.push(DeckError::at(&p.loc, format!("MID3 must be blank unless MID2 is given (a membrane-only shell has no transverse shear){}", required_by(p.id))).on_card(&card));
        }
        if let Some(m4) = p.mid4 {
            if p.mid1.is_none() || p.mid2.is_none() {
                errors.push(
                    DeckError::at(
                        &p.loc,
                        format!(
                            "MID4 must be blank unless MID1 and MID2 are given{}",
                            required_by(p.id)
                        ),
                    )
                    .on_card(&card),
                );
            }
            if p.mid1 == Some(m4) || p.mid2 == Some(m4) {
                errors.push(DeckError::at(&p.loc, format!("MID4 = {m4} may not equal MID1 or MID2 (use ZOFFS for an offset symmetric section){}", required_by(p.id))).on_card(&card));
            }
        }
        for (name, mid) in [
            ("MID1", p.mid1),
            ("MID2", p.mid2),
            ("MID3", p.mid3),
            ("MID4", p.mid4),
        ] {
            if let Some(mid) = mid {
                material(
                    refs,
                    mid,
                    name,
                    &["MAT1", "MAT8", "MAT2"],
                    &card,
                    &p.loc,
                    &required_by(p.id),
                    errors,
                );
            }
        }
    }
    for p in &b.pcomp {
        let card = format!("PCOMP {}", p.id);
        let mut seen = HashSet::new();
        for (k, ply) in p.plies.iter().enumerate() {
            if seen.insert(ply.mid) {
                material(
                    refs,
                    ply.mid,
                    &format!("MID{}", k + 1),
                    &["MAT8", "MAT1"],
                    &card,
                    &p.loc,
                    &required_by(p.id),
                    errors,
                );
            }
        }
    }
    for p in &b.psolid {
        let card = p.label();
        material(
            refs,
            p.mid,
            "MID",
            &["MAT1"],
            &card,
            &p.loc,
            &required_by(p.id),
            errors,
        );
    }

    let line_materials = (b.prod.iter().map(|p| ("PROD", p.id, p.mid, &p.loc)))
        .chain(b.ptube.iter().map(|p| ("PTUBE", p.id, p.mid, &p.loc)))
        .chain(b.pbar.iter().map(|p| ("PBAR", p.id, p.mid, &p.loc)))
        .chain(b.pbarl.iter().map(|p| ("PBARL", p.id, p.mid, &p.loc)))
        .chain(b.pbeam.iter().map(|p| ("PBEAM", p.id, p.mid, &p.loc)))
        .chain(b.pbeaml.iter().map(|p| ("PBEAML", p.id, p.mid, &p.loc)));
    for (name, pid, mid, loc) in line_materials {
        let card = format!("{name} {pid}");
        material(
            refs,
            mid,
            "MID",
            &["MAT1"],
            &card,
            loc,
            &required_by(pid),
            errors,
        );
    }
    for c in &b.conrod {
        let card = format!("CONROD {}", c.id);
        material(refs, c.mid, "MID", &["MAT1"], &card, &c.loc, "", errors);
    }

    // grids and systems of constraints and loads
    // a scalar point takes component 0 or blank (1 is accepted too), a grid components 1-6
    let spc_points = (b
        .spc
        .iter()
        .map(|s| ("SPC", s.sid, s.grid, s.components, &s.loc)))
    .chain((b.spcd.iter()).map(|s| ("SPCD", s.sid, s.grid, s.components, &s.loc)))
    .chain(b.spc1.iter().flat_map(|s| {
        s.grids
            .iter()
            .map(|&g| ("SPC1", s.sid, g, s.components, &s.loc))
    }));
    for (name, sid, id, components, loc) in spc_points {
        let card = format!("{name} {sid}");
        if !refs.point(id, "G", &card, loc, errors) {
            continue;
        }
        let scalar = refs.scalar_index.contains_key(&id);
        if scalar && !(components.is_empty() || components == Dofs(1)) {
            errors.push(DeckError::at(loc, format!("C = {components} on scalar point {id}: a scalar point has one DOF, give C = 0 or blank")).on_card(card));
        } else if !scalar && components.is_empty() && name == "SPC1" {
            errors.push(
                DeckError::at(
                    loc,
                    format!(
                        "C is blank or 0 on GRID {id}: give the constrained components, e.g. 123"
                    ),
                )
                .on_card(card),
            );
        }
    }
    for a in &b.aset1 {
        for g in &a.grids {
            refs.grid(*g, "G", "ASET1", &a.loc, errors);
        }
    }
    // the grid-point weight generator's reference grid
    for p in b.params.iter().filter(|p| p.name == "GRDPNT") {
        if let ParamValue::Int(id) = p.value
            && let Ok(id @ 1..) = u32::try_from(id)
        {
            refs.grid(id, "V1", "PARAM GRDPNT", &p.loc, errors);
        }
    }
    for m in &b.mpc {
        let card = format!("MPC {}", m.sid);
        for t in &m.terms {
            let (grid, scalar) = (
                refs.grid_index.contains_key(&t.grid),
                refs.scalar_index.contains_key(&t.grid),
            );
            let wrong = match (t.component, grid, scalar) {
                (0, true, _) => Some(format!(
                    "G = {} is a GRID: give its component 1-6 (0 or blank is for a scalar point)",
                    t.grid
                )),
                (1.., _, true) => Some(format!(
                    "G = {} is a scalar point: its component is 0 or blank, found {}",
                    t.grid, t.component
                )),
                _ => None,
            };
            if let Some(message) = wrong {
                errors.push(DeckError::at(&m.loc, message).on_card(card.clone()));
            } else if t.component == 0 {
                refs.point(t.grid, "G", &card, &m.loc, errors);
            } else {
                refs.grid(t.grid, "G", &card, &m.loc, errors);
            }
        }
    }
    // a deck that reads a pROM names the artifact's input DOFs: checked when it is read
    for d in b.darea.iter().filter(|_| !reads_rom(deck)) {
        refs.grid(d.grid, "P", &format!("DAREA {}", d.sid), &d.loc, errors);
    }
    for f in &b.forces {
        let card = format!("{} {}", force_name(f), f.sid);
        refs.grid(f.grid, "G", &card, &f.loc, errors);
        refs.coord(f.cid, "CID", &card, &f.loc, errors);
    }
    for f in &b.forces_by_grids {
        let card = format!("{} {}", f.card(), f.sid);
        refs.grid(f.grid, "G", &card, &f.loc, errors);
        for (k, &g) in f.grids.iter().enumerate() {
            refs.grid(g, &format!("G{}", k + 1), &card, &f.loc, errors);
        }
    }
    for g in &b.grav {
        refs.coord(g.cid, "CID", &format!("GRAV {}", g.sid), &g.loc, errors);
    }

    // sets
    let spc_sets: HashSet<u32> = b
        .spc
        .iter()
        .map(|s| s.sid)
        .chain(b.spc1.iter().map(|s| s.sid))
        .collect();
    for s in &b.spcadd {
        for id in &s.sets {
            if !spc_sets.contains(id) {
                errors.push(
                    DeckError::at(
                        &s.loc,
                        format!("S = {id} does not exist (no SPC or SPC1 set {id})"),
                    )
                    .on_card(format!("SPCADD {}", s.sid)),
                );
            }
        }
    }
    let mpc_sets: HashSet<u32> = b.mpc.iter().map(|s| s.sid).collect();
    for s in &b.mpcadd {
        for id in s.sets.iter().filter(|id| !mpc_sets.contains(id)) {
            errors.push(
                DeckError::at(&s.loc, format!("S = {id} does not exist (no MPC set {id})"))
                    .on_card(format!("MPCADD {}", s.sid)),
            );
        }
    }
    let static_sets: HashSet<u32> = b.static_load_sets().collect();
    for l in &b.load {
        for (_, id) in &l.terms {
            if static_sets.contains(id) {
                continue;
            }
            if b.load.iter().any(|other| other.sid == *id) {
                // MSC Nastran reads Li as simple load sets only: a LOAD of that id adds nothing
                // (its OP2 of pyNastran's unit/pload4/cquad4.bdf sums LOAD 8 without its LOAD 7)
                warnings.push(Warning {
                    loc: Some(l.loc.to_string()),
                    message: format!(
                        "LOAD {}: L = {id} is itself a LOAD and adds nothing: a LOAD combines simple load sets (FORCE, MOMENT, GRAV, PLOAD4, …), and Nastran, like paraflex, does not expand a LOAD named in another",
                        l.sid
                    ),
                });
            } else {
                errors.push(
                    DeckError::at(
                        &l.loc,
                        format!(
                            "L = {id} does not exist (no FORCE, MOMENT, FORCE1, FORCE2, MOMENT1, MOMENT2, SLOAD, GRAV, PLOAD4, PLOAD2, PLOAD, PLOAD1 or SPCD set {id})"
                        ),
                    )
                    .on_card(format!("LOAD {}", l.sid)),
                );
            }
        }
    }
    let excite: HashSet<u32> = b
        .darea
        .iter()
        .map(|d| d.sid)
        .chain(static_sets.iter().copied())
        .chain(b.load.iter().map(|l| l.sid))
        .chain(b.lseq.iter().map(|l| l.excite_id))
        .collect();
    let selected_lseqs: HashSet<u32> = deck
        .case
        .subcases()
        .iter()
        .filter_map(|sub| sub.loadset)
        .collect();
    for l in &b.lseq {
        let card = format!("LSEQ {}", l.sid);
        if !static_sets.contains(&l.lid) && !b.load.iter().any(|x| x.sid == l.lid) {
            errors.push(
                DeckError::at(
                    &l.loc,
                    format!(
                        "LID = {} does not exist (no static load set {})",
                        l.lid, l.lid
                    ),
                )
                .on_card(&card),
            );
        }
        // an LSEQ acts only where a subcase's LOADSET selects it (Nastran): one beside a DAREA
        // set of its EXCITEID that no LOADSET selects leaves the DAREA loads alone
        let selected = selected_lseqs.contains(&l.sid);
        if !selected {
            warnings.push(Warning {
                loc: Some(l.loc.to_string()),
                message: format!(
                    "LSEQ {}: no subcase selects it with LOADSET = {}: its load set {} is not applied to EXCITEID {}",
                    l.sid, l.sid, l.lid, l.excite_id
                ),
            });
        }
        if selected && b.darea.iter().any(|d| d.sid == l.excite_id) {
            errors.push(
                DeckError::at(&l.loc, format!("EXCITEID = {} is also a DAREA set: combining DAREA and LSEQ loads on one EXCITEID is not supported", l.excite_id))
                    .on_card(&card),
            );
        }
    }
    let tables = index(
        b.dynamic_tables()
            .map(|(id, card, loc)| entry(id, card, loc, ()))
            .collect(),
        "table",
        errors,
    );
    let table = |id: u32, field: &str, card: &str, loc: &Loc, errors: &mut Vec<DeckError>| {
        if !tables.contains_key(&id) {
            errors.push(
                DeckError::at(
                    loc,
                    format!("{field} = {id} does not exist (no TABLED1–TABLED4 or TABLEF {id})"),
                )
                .on_card(card),
            );
        }
    };
    for t in &b.tload {
        let card = format!("{} {}", t.function.card(), t.sid);
        if !excite.contains(&t.excite_id) {
            errors.push(
                DeckError::at(
                    &t.loc,
                    format!(
                        "EXCITEID = {} does not exist (no DAREA or static load set {})",
                        t.excite_id, t.excite_id
                    ),
                )
                .on_card(&card),
            );
        }
        excitation_kind(b, t.kind, t.excite_id, &card, &t.loc, errors);
        if let TloadFunction::Table(tid) = t.function {
            table(tid, "TID", &card, &t.loc, errors);
        }
    }
    for r in &b.rload {
        let card = format!("{} {}", r.tables.card(), r.sid);
        if !excite.contains(&r.excite_id) {
            errors.push(
                DeckError::at(
                    &r.loc,
                    format!(
                        "EXCITEID = {} does not exist (no DAREA or static load set {})",
                        r.excite_id, r.excite_id
                    ),
                )
                .on_card(&card),
            );
        }
        excitation_kind(b, r.kind, r.excite_id, &card, &r.loc, errors);
        for (name, id) in r.tables.named() {
            table(id, name, &card, &r.loc, errors);
        }
        if r.tables.is_zero() {
            errors.push(
                DeckError::at(
                    &r.loc,
                    "TC and TD are both 0: the load is zero at every frequency",
                )
                .on_card(&card),
            );
        }
    }
    let dynamic: HashSet<u32> = b
        .tload
        .iter()
        .map(|t| t.sid)
        .chain(b.rload.iter().map(|r| r.sid))
        .collect();
    for d in &b.dload {
        for (_, id) in &d.terms {
            if !dynamic.contains(id) {
                errors.push(
                    DeckError::at(
                        &d.loc,
                        format!(
                            "L = {id} does not exist (no TLOAD1/TLOAD2 or RLOAD1/RLOAD2 set {id})"
                        ),
                    )
                    .on_card(format!("DLOAD {}", d.sid)),
                );
            }
        }
    }

    // single-id spaces
    index(
        b.eigrl
            .iter()
            .map(|c| entry(c.sid, "EIGRL", &c.loc, ()))
            .collect(),
        "EIGRL",
        errors,
    );
    let tsteps = index(
        b.tstep
            .iter()
            .map(|c| entry(c.sid, "TSTEP", &c.loc, ()))
            .collect(),
        "TSTEP",
        errors,
    );
    index(
        b.tinteg
            .iter()
            .map(|c| entry(c.id, "TINTEG", &c.loc, ()))
            .collect(),
        "TINTEG",
        errors,
    );
    index(
        b.desvar
            .iter()
            .map(|c| entry(c.id, "DESVAR", &c.loc, ()))
            .collect(),
        "DESVAR",
        errors,
    );
    let ddvals = index(
        b.ddval
            .iter()
            .map(|c| entry(c.id, "DDVAL", &c.loc, ()))
            .collect(),
        "DDVAL",
        errors,
    );
    index(
        b.pmor
            .iter()
            .map(|c| entry(c.id, "PMOR", &c.loc, ()))
            .collect(),
        "PMOR",
        errors,
    );
    index(
        b.pval
            .iter()
            .map(|c| entry(c.id, "PVAL", &c.loc, ()))
            .collect(),
        "PVAL",
        errors,
    );
    index(
        b.sensors
            .iter()
            .map(|c| entry(c.id, "SENSOR", &c.loc, ()))
            .collect(),
        "SENSOR",
        errors,
    );
    index(
        b.sensors
            .iter()
            .map(|c| entry(c.name.to_ascii_uppercase(), "SENSOR", &c.loc, ()))
            .collect(),
        "SENSOR name",
        errors,
    );

    let tstep_settings = b
        .tinteg
        .iter()
        .map(|t| (t.id, &t.loc, "TINTEG"))
        .chain(b.tstepvar.iter().map(|t| (t.id, &t.loc, "TSTEPVAR")));
    for (id, loc, card) in tstep_settings {
        if !tsteps.contains_key(&id) {
            errors.push(
                DeckError::at(loc, format!("ID = {id} does not exist (no TSTEP {id})"))
                    .on_card(format!("{card} {id}")),
            );
        }
    }
    for d in &b.desvar {
        if let Some(id) = d.ddval
            && !ddvals.contains_key(&id)
        {
            errors.push(
                DeckError::at(
                    &d.loc,
                    format!("DDVAL = {id} does not exist (no DDVAL {id})"),
                )
                .on_card(format!("DESVAR {}", d.id)),
            );
        }
    }
    for p in &b.pmor {
        if p.bset.is_some() && b.aset1.is_empty() {
            errors.push(
                DeckError::at(
                    &p.loc,
                    "BSET is given but the deck has no ASET1 card (the a-set is empty)",
                )
                .on_card(format!("PMOR {}", p.id)),
            );
        }
    }
    // PVALs of a deck that reads a pROM or a pFMB name the artifact's parameters: checked when
    // it is read;
    // those of a multibody deck name BODY.PMPAR of its FLEXB artifacts (model::mechanism)
    let names: HashSet<String> = b
        .pmpar
        .iter()
        .map(|p| p.name.to_ascii_uppercase())
        .collect();
    let multibody = !b.flexb.is_empty() || !b.rigidb.is_empty();
    for p in b.pval.iter().filter(|_| !reads_rom(deck) && !multibody) {
        for (name, _) in &p.values {
            if !names.contains(&name.to_ascii_uppercase()) {
                errors.push(
                    DeckError::at(
                        &p.loc,
                        format!("NAME = {name} does not exist (no PMPAR named {name})"),
                    )
                    .on_card(format!("PVAL {}", p.id)),
                );
            }
        }
    }
    sensors(refs, errors);
}

/// True when some subcase reads a pROM artifact (`ROM =`) or a pFMB artifact (`FMB =`).
fn reads_rom(deck: &Deck) -> bool {
    let reads = |s: &crate::deck::case_control::Subcase| s.rom.is_some() || s.fmb.is_some();
    deck.case.explicit.iter().any(reads) || reads(&deck.case.global)
}

fn force_name(f: &crate::deck::cards::Force) -> &'static str {
    match f.kind {
        ForceKind::Force => "FORCE",
        ForceKind::Moment => "MOMENT",
    }
}

/// SENSOR REF by kind, and SURF only on shells.
fn sensors(refs: &Refs, errors: &mut Vec<DeckError>) {
    let b = refs.bulk;
    if b.sensors.is_empty() {
        // the map below is of every element: not built for nothing on large models
        return;
    }
    let mut element_kind: HashMap<u32, &'static str> = HashMap::new();
    for (name, ids) in [
        ("CQUAD4", b.cquad4.iter().map(|c| c.id).collect::<Vec<_>>()),
        ("CTRIA3", b.ctria3.iter().map(|c| c.id).collect()),
        ("CQUADR", b.cquadr.iter().map(|c| c.id).collect()),
        ("CTRIAR", b.ctriar.iter().map(|c| c.id).collect()),
        ("CQUAD8", b.cquad8.iter().map(|c| c.id).collect()),
        ("CTRIA6", b.ctria6.iter().map(|c| c.id).collect()),
        ("CHEXA", b.chexa.iter().map(|c| c.id).collect()),
        ("CPENTA", b.cpenta.iter().map(|c| c.id).collect()),
        ("CTETRA", b.ctetra.iter().map(|c| c.id).collect()),
        ("CELAS1", b.celas1.iter().map(|c| c.id).collect()),
        ("CELAS2", b.celas2.iter().map(|c| c.id).collect()),
        ("CONM2", b.conm2.iter().map(|c| c.id).collect()),
    ] {
        for id in ids {
            element_kind.entry(id).or_insert(name);
        }
    }
    for s in &b.sensors {
        let card = format!("SENSOR {}", s.id);
        match s.kind {
            SensorKind::Disp | SensorKind::Vel | SensorKind::Accel => {
                refs.grid(s.reference, "REF", &card, &s.loc, errors);
                if let Some(surf) = s.surface {
                    errors.push(DeckError::at(&s.loc, format!("SURF = {surf} is only meaningful for STRAIN sensors on shells; leave blank")).on_card(&card));
                }
            }
            SensorKind::Strain => match element_kind.get(&s.reference).copied() {
                None => errors.push(
                    DeckError::at(
                        &s.loc,
                        format!(
                            "REF = {} does not exist (no element {})",
                            s.reference, s.reference
                        ),
                    )
                    .on_card(&card),
                ),
                Some("CQUAD4" | "CTRIA3" | "CQUADR" | "CTRIAR" | "CQUAD8" | "CTRIA6") => {}
                Some(kind @ ("CHEXA" | "CPENTA" | "CTETRA")) => {
                    if let Some(surf) = s.surface {
                        errors.push(
                            DeckError::at(
                                &s.loc,
                                format!(
                                    "SURF = {surf} is only for shells; REF = {} is a {kind}",
                                    s.reference
                                ),
                            )
                            .on_card(&card),
                        );
                    }
                }
                Some(kind) => errors.push(
                    DeckError::at(
                        &s.loc,
                        format!(
                            "REF = {} is a {kind}; STRAIN sensors need a shell or solid element",
                            s.reference
                        ),
                    )
                    .on_card(&card),
                ),
            },
        }
        if !s.direction.iter().all(|v| v.is_finite()) || s.direction.iter().all(|v| *v == 0.0) {
            errors.push(
                DeckError::at(&s.loc, "direction X Y Z must be finite and not zero").on_card(&card),
            );
        }
    }
}

/// Check a material reference of a property.
#[allow(clippy::too_many_arguments)]
fn material(
    refs: &Refs,
    mid: u32,
    field: &str,
    allowed: &[&str],
    card: &str,
    loc: &Loc,
    required_by: &str,
    errors: &mut Vec<DeckError>,
) {
    let wanted = allowed.join(" or ");
    match refs.materials.get(&mid) {
        None => errors.push(
            DeckError::at(
                loc,
                format!("{field} = {mid} does not exist (no {wanted} {mid}){required_by}"),
            )
            .on_card(card),
        ),
        Some(m) if !allowed.contains(&m.card()) => {
            let why = match m {
                MaterialRef::Mat8(_) => ": MAT8 is a plane-stress (shell) material",
                MaterialRef::Mat2(_) => ": MAT2 is a plane-stress material, read by PSHELL only",
                MaterialRef::Mat1(_) => "",
            };
            errors.push(
                DeckError::at(
                    loc,
                    format!(
                        "{field} = {mid} is a {}; {} needs a {wanted}{why}{required_by}",
                        m.card(),
                        card.split(' ').next().unwrap_or(card)
                    ),
                )
                .on_card(card),
            );
        }
        Some(_) => {}
    }
}

/// Property id → up to three users ("CQUAD4 101") and a count of the rest.
fn property_users(refs: &Refs) -> HashMap<u32, Vec<String>> {
    let b = refs.bulk;
    let mut users: HashMap<u32, Vec<String>> = HashMap::new();
    let mut push = |pid: u32, name: &str, id: u32| {
        let list = users.entry(pid).or_default();
        if list.len() < 3 {
            list.push(format!("{name} {id}"));
        } else if list.len() == 3 {
            list.push("…".into());
        }
    };
    b.cquad4.iter().for_each(|c| push(c.pid, "CQUAD4", c.id));
    b.ctria3.iter().for_each(|c| push(c.pid, "CTRIA3", c.id));
    b.cquadr.iter().for_each(|c| push(c.pid, "CQUADR", c.id));
    b.ctriar.iter().for_each(|c| push(c.pid, "CTRIAR", c.id));
    b.cquad8.iter().for_each(|c| push(c.pid, "CQUAD8", c.id));
    b.ctria6.iter().for_each(|c| push(c.pid, "CTRIA6", c.id));
    b.cshear.iter().for_each(|c| push(c.pid, "CSHEAR", c.id));
    b.chexa.iter().for_each(|c| push(c.pid, "CHEXA", c.id));
    b.cpenta.iter().for_each(|c| push(c.pid, "CPENTA", c.id));
    b.ctetra.iter().for_each(|c| push(c.pid, "CTETRA", c.id));
    b.celas1.iter().for_each(|c| push(c.pid, "CELAS1", c.id));
    b.crod.iter().for_each(|c| push(c.pid, "CROD", c.id));
    b.ctube.iter().for_each(|c| push(c.pid, "CTUBE", c.id));
    b.cbar.iter().for_each(|c| push(c.pid, "CBAR", c.id));
    b.cbeam.iter().for_each(|c| push(c.pid, "CBEAM", c.id));
    b.cbend.iter().for_each(|c| push(c.pid, "CBEND", c.id));
    users
}

/// A dynamic load's TYPE against its EXCITEID: enforced motion (DISP, VELO, ACCE) moves the
/// DOFs of an SPCD set and nothing else; an applied load (LOAD) must not select SPCDs, whose
/// values it would ignore.
fn excitation_kind(
    b: &BulkData,
    kind: ExcitationKind,
    excite_id: u32,
    card: &str,
    loc: &Loc,
    errors: &mut Vec<DeckError>,
) {
    let spcd = b.spcd.iter().any(|c| c.sid == excite_id);
    let message = match kind {
        ExcitationKind::Load if spcd => format!(
            "EXCITEID = {excite_id} selects SPCD cards, which an applied load (TYPE = LOAD) ignores: give TYPE = DISP, VELO or ACCE for enforced motion"
        ),
        ExcitationKind::Load => return,
        _ if !spcd => format!(
            "TYPE = {} (enforced motion) needs EXCITEID = an SPCD set; there is no SPCD {excite_id}",
            kind.name()
        ),
        _ => return,
    };
    errors.push(DeckError::at(loc, message).on_card(card));
}
