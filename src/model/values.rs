//! Value ranges of materials, properties and masses, and the kept-but-unused fields.
//!
//! | card | rule (error unless stated) |
//! |---|---|
//! | MAT1 | E > 0 when given; G > 0 (given or derived); −1 < ν < 0.5 (given, or derived for a material of a plate, solid or shear panel; a warning when only line elements, which take E and G as given, use it); ρ ≥ 0; all finite |
//! | MAT8 | E1, E2, G12 > 0; ρ ≥ 0; G1Z, G2Z > 0 when given; ν12² < E1/E2 (positive-definite compliance) |
//! | PSHELL | T > 0; 12I/T³ > 0, TS/T > 0; NSM, Z1, Z2 finite |
//! | PCOMP | every ply T > 0; NSM finite |
//! | PELAS, CELAS2 | K finite |
//! | CONM2 | M ≥ 0; I11, I22, I33 ≥ 0; all finite |
//!
//! Kept-but-unused fields are noted with one warning per card type (e.g. PSOLID IN/STRESS/ISOP).

use crate::deck::{DeckError, Loc, Warning};

use super::build::Refs;

fn bad(errors: &mut Vec<DeckError>, loc: &Loc, card: String, message: String) {
    errors.push(DeckError::at(loc, message).on_card(card));
}

/// Run the checks of the table above and note the kept-but-unused fields.
pub fn check(refs: &Refs, errors: &mut Vec<DeckError>, warnings: &mut Vec<Warning>) {
    let b = refs.bulk;
    // materials whose Poisson ratio enters an element (plates, solids, shear panels)
    let continuum: std::collections::HashSet<u32> = b
        .pshell
        .iter()
        .flat_map(|p| [p.mid1, p.mid2, p.mid3, p.mid4])
        .flatten()
        .chain(
            b.pcomp
                .iter()
                .flat_map(|p| p.plies.iter().map(|ply| ply.mid)),
        )
        .chain(b.psolid.iter().map(|p| p.mid))
        .chain(b.pshear.iter().map(|p| p.mid))
        .collect();
    for m in &b.mat1 {
        let card = format!("MAT1 {}", m.id);
        let [e_given, g_given, nu_given] = m.given;
        if ![m.e, m.g, m.nu, m.rho, m.a, m.tref, m.ge]
            .iter()
            .all(|v| v.is_finite())
        {
            bad(
                errors,
                &m.loc,
                card.clone(),
                "every value must be finite".into(),
            );
            continue;
        }
        if e_given && m.e <= 0.0 {
            bad(
                errors,
                &m.loc,
                card.clone(),
                format!("E = {:e} must be > 0", m.e),
            );
        }
        if m.g <= 0.0 {
            let how = if g_given {
                ""
            } else {
                " (derived from E and NU)"
            };
            bad(
                errors,
                &m.loc,
                card.clone(),
                format!("G = {:e}{how} must be > 0", m.g),
            );
        }
        let nu_in_range = m.nu > -1.0 && m.nu < 0.5;
        if !nu_in_range && !nu_given && !continuum.contains(&m.id) {
            // Nastran's line elements take E and G as given; only plates and solids use ν
            warnings.push(Warning {
                loc: Some(m.loc.to_string()),
                message: format!(
                    "MAT1 {}: NU = {} (derived as E/(2G) − 1) lies outside (−1, 0.5); no shell, solid or shear panel uses this material, and bars, beams and rods take E and G as given: accepted",
                    m.id, m.nu
                ),
            });
        } else if !nu_in_range {
            let how = if nu_given {
                ""
            } else {
                " (derived as E/(2G) − 1)"
            };
            bad(
                errors,
                &m.loc,
                card.clone(),
                format!("NU = {}{how} must lie in (−1, 0.5)", m.nu),
            );
        }
        if m.rho < 0.0 {
            bad(
                errors,
                &m.loc,
                card,
                format!("RHO = {:e} must be ≥ 0", m.rho),
            );
        }
    }
    for m in &b.mat8 {
        let card = format!("MAT8 {}", m.id);
        let opt = [m.g1z.unwrap_or(1.0), m.g2z.unwrap_or(1.0)];
        if ![m.e1, m.e2, m.nu12, m.g12, m.rho, m.ge]
            .iter()
            .chain(opt.iter())
            .all(|v| v.is_finite())
        {
            bad(
                errors,
                &m.loc,
                card.clone(),
                "every value must be finite".into(),
            );
            continue;
        }
        for (name, v) in [("E1", m.e1), ("E2", m.e2), ("G12", m.g12)] {
            if v <= 0.0 {
                bad(
                    errors,
                    &m.loc,
                    card.clone(),
                    format!("{name} = {v:e} must be > 0"),
                );
            }
        }
        for (name, v) in [("G1Z", m.g1z), ("G2Z", m.g2z)] {
            if let Some(v) = v.filter(|v| *v <= 0.0) {
                bad(
                    errors,
                    &m.loc,
                    card.clone(),
                    format!("{name} = {v:e} must be > 0 (or blank for rigid transverse shear)"),
                );
            }
        }
        if m.e1 > 0.0 && m.e2 > 0.0 && m.nu12 * m.nu12 >= m.e1 / m.e2 {
            bad(
                errors,
                &m.loc,
                card.clone(),
                format!(
                    "NU12 = {} violates NU12² < E1/E2: the compliance is not positive definite",
                    m.nu12
                ),
            );
        }
        if m.rho < 0.0 {
            bad(
                errors,
                &m.loc,
                card,
                format!("RHO = {:e} must be ≥ 0", m.rho),
            );
        }
    }
    for m in &b.mat2 {
        let card = format!("MAT2 {}", m.id);
        if !m.g.iter().chain([&m.rho, &m.ge]).all(|v| v.is_finite()) {
            bad(errors, &m.loc, card, "every value must be finite".into());
        } else if m.rho < 0.0 {
            bad(
                errors,
                &m.loc,
                card,
                format!("RHO = {:e} must be ≥ 0", m.rho),
            );
        }
    }
    for p in &b.pshell {
        let card = format!("PSHELL {}", p.id);
        if !(p.t > 0.0 && p.t.is_finite()) {
            bad(
                errors,
                &p.loc,
                card.clone(),
                format!("T = {:e} must be > 0", p.t),
            );
        }
        if ![p.nsm, p.bending_ratio, p.ts_t, p.z1, p.z2]
            .iter()
            .all(|v| v.is_finite())
        {
            bad(
                errors,
                &p.loc,
                card.clone(),
                "every value must be finite".into(),
            );
        }
        for (name, v) in [("12I/T**3", p.bending_ratio), ("TS/T", p.ts_t)] {
            if v <= 0.0 {
                bad(
                    errors,
                    &p.loc,
                    card.clone(),
                    format!("{name} = {v:e} must be > 0"),
                );
            }
        }
    }
    for p in &b.pcomp {
        let card = format!("PCOMP {}", p.id);
        for (k, ply) in p.plies.iter().enumerate() {
            if !(ply.t > 0.0 && ply.t.is_finite()) {
                bad(
                    errors,
                    &p.loc,
                    card.clone(),
                    format!("T{} = {:e} (ply {}) must be > 0", k + 1, ply.t, k + 1),
                );
            }
            if !ply.theta.is_finite() {
                bad(
                    errors,
                    &p.loc,
                    card.clone(),
                    format!("THETA{} must be finite", k + 1),
                );
            }
        }
        if !p.nsm.is_finite() || !p.z0.unwrap_or(0.0).is_finite() {
            bad(errors, &p.loc, card, "NSM and Z0 must be finite".into());
        }
    }
    for p in &b.pelas {
        if !p.k.is_finite() || !p.ge.is_finite() {
            bad(
                errors,
                &p.loc,
                format!("PELAS {}", p.id),
                "K and GE must be finite".into(),
            );
        }
    }
    for c in &b.celas2 {
        if !c.k.is_finite() || !c.ge.is_finite() {
            bad(
                errors,
                &c.loc,
                format!("CELAS2 {}", c.id),
                "K and GE must be finite".into(),
            );
        }
    }
    for c in &b.conm2 {
        let card = format!("CONM2 {}", c.id);
        if !c.mass.is_finite()
            || !c
                .offset
                .iter()
                .chain(c.inertia.iter())
                .all(|v| v.is_finite())
        {
            bad(errors, &c.loc, card, "every value must be finite".into());
            continue;
        }
        if c.mass < 0.0 {
            bad(
                errors,
                &c.loc,
                card.clone(),
                format!("M = {:e} must be ≥ 0", c.mass),
            );
        }
        for (name, v) in [
            ("I11", c.inertia[0]),
            ("I22", c.inertia[2]),
            ("I33", c.inertia[5]),
        ] {
            if v < 0.0 {
                bad(
                    errors,
                    &c.loc,
                    card.clone(),
                    format!("{name} = {v:e} must be ≥ 0"),
                );
            }
        }
    }
    kept_fields(refs, warnings);
}

/// One warning per card type whose cards carry fields paraflex keeps but does not use.
fn kept_fields(refs: &Refs, warnings: &mut Vec<Warning>) {
    let b = refs.bulk;
    let mut note = |any: bool, text: &str| {
        if any {
            warnings.push(Warning {
                loc: None,
                message: text.to_string(),
            });
        }
    };
    note(
        b.psolid.iter().any(|p| !p.kept.is_empty()),
        "PSOLID IN/STRESS/ISOP are kept and have no effect (paraflex chooses its own integration)",
    );
    note(
        b.pcomp.iter().any(|p| p.sb != 0.0),
        "PCOMP SB is kept and has no effect (no interlaminar bonding index)",
    );
    note(
        !b.cmass2.is_empty(),
        "CMASS2 masses are in the mass matrix but not in the mass properties (each acts along one component, not as a point mass)",
    );
    note(
        b.pelas.iter().any(|p| p.s != 0.0),
        "PELAS S is kept and has no effect (no spring stress output)",
    );
    note(
        b.celas2.iter().any(|c| c.s != 0.0),
        "CELAS2 S is kept and has no effect (no spring stress output)",
    );
    note(
        b.rbe2.iter().any(|r| r.alpha != 0.0),
        "RBE2 ALPHA is kept and has no effect (rigid elements take no thermal expansion)",
    );
    note(
        b.rbe3.iter().any(|r| r.alpha != 0.0),
        "RBE3 ALPHA is kept and has no effect (rigid elements take no thermal expansion)",
    );
}
