//! A dynamic solution needs mass: on a model whose mass matrix would be zero (no density on any
//! material, no CONM2, no CMASS2), `SOL 103`, frequency and transient response and `SOL PROM` have no
//! finite eigenvalue or response, so the model check refuses them, naming the materials
//! without density. The classic slip, the density typed one column too far (in MAT1's A, the
//! thermal expansion coefficient, with RHO blank), gets a "did you mean RHO" hint. Statics
//! and pROM-artifact runs (`ROM =`) do not need the mesh's mass and are not checked.

use crate::deck::{Deck, DeckError, Loc, Solution};

use super::Model;

/// The solutions that need the mesh's mass matrix.
const NEED_MASS: &[Solution] = &[
    Solution::Modal,
    Solution::FrfDirect,
    Solution::FrfModal,
    Solution::Frf,
    Solution::TransientDirect,
    Solution::TransientModal,
    Solution::Transient,
    Solution::Prom,
];

/// The errors of a model without mass under a solution that needs it (none otherwise).
pub fn check(deck: &Deck, model: &Model) -> Vec<DeckError> {
    let Some((sol, text)) = &deck.executive.sol else {
        return Vec::new();
    };
    let on_mesh = model.subcases.iter().all(|s| s.rom.is_none());
    if !NEED_MASS.contains(sol) || !on_mesh || model.elements.is_empty() {
        return Vec::new();
    }
    let mp = model.mass_properties();
    // CMASS2 scalar masses are not in the mass properties (they act along one component)
    let scalar_masses = deck.bulk.cmass2.iter().any(|c| c.k != 0.0);
    if scalar_masses || mp.mass != 0.0 || mp.inertia_cg.iter().flatten().any(|v| *v != 0.0) {
        return Vec::new();
    }
    let why = format!(
        "SOL {text} ({}) needs a mass matrix, and this model has no mass (no material density, no CONM2)",
        sol.name()
    );
    let b = &deck.bulk;
    let mut errors: Vec<DeckError> = b
        .mat1
        .iter()
        .filter(|m| m.rho == 0.0)
        .map(|m| {
            let hint = if m.a != 0.0 {
                format!(
                    "; did you mean RHO (field 6) = {:e}? A (field 7) is the thermal expansion coefficient",
                    m.a
                )
            } else {
                String::new()
            };
            zero_rho(&m.loc, format!("MAT1 {}", m.id), 6, &why, &hint)
        })
        .chain(
            b.mat8
                .iter()
                .filter(|m| m.rho == 0.0)
                .map(|m| zero_rho(&m.loc, format!("MAT8 {}", m.id), 9, &why, "")),
        )
        .chain(
            b.mat2
                .iter()
                .filter(|m| m.rho == 0.0)
                .map(|m| zero_rho(&m.loc, format!("MAT2 {}", m.id), 9, &why, "")),
        )
        .collect();
    if errors.is_empty() {
        let at = deck.executive.sol_loc.clone().unwrap_or_else(|| Loc {
            file: std::sync::Arc::from(deck.path.as_path()),
            line: 1,
        });
        errors.push(
            DeckError::at(
                &at,
                format!("{why}: give the materials a density (RHO) or add CONM2 masses"),
            )
            .on_card("SOL"),
        );
    }
    errors
}

/// The error on one material card with zero density.
/// The error at a material's RHO field (`field`: 6 on a MAT1, 9 on a MAT8 or MAT2).
fn zero_rho(loc: &Loc, card: String, field: u32, why: &str, hint: &str) -> DeckError {
    let mut e = DeckError::at(loc, format!("RHO is zero or blank: {why}{hint}")).on_card(card);
    e.field = Some(format!("field {field} (RHO)"));
    e
}
