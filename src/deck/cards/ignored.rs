//! Bulk data cards that paraflex reads and sets aside because they cannot change its results,
//! each with the reason given to the user once per deck, and a check where only some of a
//! card's uses are harmless (the others are refused at their field).
//!
//! | card | why it has no effect | refused |
//! |---|---|---|
//! | `ECHOON`, `ECHOOFF` | echo control; paraflex prints no echo | – |
//! | `PLOTEL` | a plot element: no stiffness, mass or load | – |
//! | `CBARAO` | output points along a CBAR; paraflex writes no bar forces or stresses | – |
//! | `USET`, `USET1` | user DOF sets U1–U6 partition matrices for DMAP alters and OUTPUT2/4; paraflex runs no DMAP | any set name other than U1–U6 or ZERO |
//! | `MAT4`, `MAT5` | thermal materials, read by heat-transfer solutions only | – |
//! | `DTI` | a direct table is data for DMAP modules (and `SETREE` for the processing tree of reduced superelements; paraflex assembles parts unreduced); paraflex runs no DMAP | – |
//! | `DVPREL1`, `DVPREL2`, `DVMREL1`, `DVMREL2`, `DVCREL1`, `DVCREL2`, `DLINK`, `DRESP1`, `DRESP2`, `DOPTPRM` | Nastran's design model, read by SOL 200 only (paraflex's own studies use `DVMAP`, `DOBJ`, `DCONSTR`) | – |
//! | `PBUSH1D` | property of CBUSH1D, which paraflex refuses: no element of a deck it runs can use it | – |
//! | `PELAST` | frequency-dependent (TKID) and structural-damping (TGEID) tables of a PELAS, or its nonlinear force–deflection table (TKNID, read by nonlinear solutions only) | a TKID or TGEID table |
//! | `EPOINT` | extra points carry no stiffness or mass; only transfer functions, DMIG and loads act on them, and paraflex refuses a load or constraint on a point it does not know | – |
//! | `SELABEL` | a superelement's label titles printed output only | – |
//! | `MDLPRM` | HDF5 output options (`HDF5`, `H5…`): paraflex writes its own HDF5 file; `OFFDEF = LROFF`: offsets that do not follow large rotations, a nonlinear option | every other model parameter (they change the model, e.g. `OFFDEF = NOMASS`) |

use crate::deck::error::DeckError;
use crate::deck::fields::RawCard;
use crate::deck::reader::FieldReader;
use crate::deck::value::Value;

/// A check of a card that is harmless only in some uses.
type Check = fn(&RawCard) -> Result<(), Vec<DeckError>>;

/// Card name, reason, check.
static IGNORED: &[(&str, &str, Option<Check>)] = &[
    (
        "ECHOON",
        "echo control: paraflex prints no echo of the deck",
        None,
    ),
    (
        "ECHOOFF",
        "echo control: paraflex prints no echo of the deck",
        None,
    ),
    (
        "PLOTEL",
        "a plot element has no stiffness, mass or load",
        None,
    ),
    (
        "CBARAO",
        "output points along a CBAR: paraflex writes no bar forces or stresses",
        None,
    ),
    (
        "USET",
        "user DOF sets U1–U6 only partition matrices for DMAP alters and OUTPUT2/4, and paraflex runs no DMAP",
        Some(user_set_name),
    ),
    (
        "USET1",
        "user DOF sets U1–U6 only partition matrices for DMAP alters and OUTPUT2/4, and paraflex runs no DMAP",
        Some(user_set_name),
    ),
    (
        "MAT4",
        "a thermal material is read by heat-transfer solutions only",
        None,
    ),
    (
        "MAT5",
        "a thermal material is read by heat-transfer solutions only",
        None,
    ),
    (
        "DTI",
        "a direct table is data for DMAP modules (SETREE: the processing tree of reduced superelements), and paraflex runs no DMAP and assembles parts unreduced",
        None,
    ),
    (
        "DVPREL1",
        "Nastran's design model is read by SOL 200 only (paraflex's own studies use DVMAP, DOBJ and DCONSTR)",
        None,
    ),
    (
        "DVPREL2",
        "Nastran's design model is read by SOL 200 only (paraflex's own studies use DVMAP, DOBJ and DCONSTR)",
        None,
    ),
    (
        "DVMREL1",
        "Nastran's design model is read by SOL 200 only (paraflex's own studies use DVMAP, DOBJ and DCONSTR)",
        None,
    ),
    (
        "DVMREL2",
        "Nastran's design model is read by SOL 200 only (paraflex's own studies use DVMAP, DOBJ and DCONSTR)",
        None,
    ),
    (
        "DVCREL1",
        "Nastran's design model is read by SOL 200 only (paraflex's own studies use DVMAP, DOBJ and DCONSTR)",
        None,
    ),
    (
        "DVCREL2",
        "Nastran's design model is read by SOL 200 only (paraflex's own studies use DVMAP, DOBJ and DCONSTR)",
        None,
    ),
    (
        "DLINK",
        "Nastran's design model is read by SOL 200 only (paraflex's own studies use DVMAP, DOBJ and DCONSTR)",
        None,
    ),
    (
        "DRESP1",
        "Nastran's design model is read by SOL 200 only (paraflex's own studies use DVMAP, DOBJ and DCONSTR)",
        None,
    ),
    (
        "DRESP2",
        "Nastran's design model is read by SOL 200 only (paraflex's own studies use DVMAP, DOBJ and DCONSTR)",
        None,
    ),
    (
        "DOPTPRM",
        "Nastran's design model is read by SOL 200 only (paraflex's own studies use DVMAP, DOBJ and DCONSTR)",
        None,
    ),
    (
        "PBUSH1D",
        "a property of CBUSH1D, which paraflex does not support: no element of this deck can use it",
        None,
    ),
    (
        "PELAST",
        "its nonlinear force-deflection table (TKNID) is read by nonlinear solutions only",
        Some(linear_spring_tables),
    ),
    (
        "SELABEL",
        "a superelement's label only titles Nastran's printed output",
        None,
    ),
    (
        "EPOINT",
        "extra points carry no stiffness or mass (only transfer functions, DMIG and loads act on them, and a load or constraint on a point paraflex does not know is refused)",
        None,
    ),
    (
        "MDLPRM",
        "its HDF5 output options do not apply: paraflex writes its own HDF5 file",
        Some(harmless_model_parameters),
    ),
];

/// Why `name` is read and set aside, and its check, when it is such a card.
pub fn ignored_card(name: &str) -> Option<(&'static str, Option<Check>)> {
    IGNORED
        .iter()
        .find(|(n, _, _)| *n == name)
        .map(|(_, why, check)| (*why, *check))
}

/// `USET`/`USET1` SNAME must be a user set: another set name would change the solution's sets.
fn user_set_name(card: &RawCard) -> Result<(), Vec<DeckError>> {
    let mut f = FieldReader::new(card);
    let name = f.text(1, "SNAME").to_ascii_uppercase();
    let user = ["U1", "U2", "U3", "U4", "U5", "U6", "ZERO"];
    if !name.is_empty() && !user.contains(&name.as_str()) {
        f.error(
            1,
            "SNAME",
            format!("set {name} is not supported: paraflex reads the user sets U1–U6 (and ZERO) only, which do not change its results"),
        );
    }
    f.finish(card.fields.len())
}

/// `PELAST` TKID (stiffness against frequency) and TGEID (damping against frequency) change
/// frequency responses; only TKNID (nonlinear force–deflection) is harmless in linear solutions.
fn linear_spring_tables(card: &RawCard) -> Result<(), Vec<DeckError>> {
    let mut f = FieldReader::new(card);
    let pid = f.id(1, "PID");
    f.set_id(pid);
    for (i, name, what) in [
        (2, "TKID", "frequency-dependent stiffness"),
        (3, "TGEID", "frequency-dependent structural damping"),
    ] {
        if f.opt_id(i, name).is_some() {
            f.error(
                i,
                name,
                format!("{what} of a PELAS is not supported: leave {name} blank"),
            );
        }
    }
    f.opt_id(4, "TKNID");
    f.finish(4)
}

/// `MDLPRM` pairs: only the HDF5 output options (`HDF5`, `H5…`) and `OFFDEF = LROFF` (offsets
/// that do not follow large rotations: a nonlinear-analysis option, no effect on the linear
/// solutions paraflex runs) are harmless.
fn harmless_model_parameters(card: &RawCard) -> Result<(), Vec<DeckError>> {
    let mut f = FieldReader::new(card);
    for i in (1..=card.fields.len()).step_by(2) {
        let Value::Text(name) = f.value(i) else {
            continue;
        };
        let name = name.to_ascii_uppercase();
        let value = match f.value(i + 1) {
            Value::Text(v) => v.to_ascii_uppercase(),
            _ => String::new(),
        };
        let harmless =
            name == "HDF5" || name.starts_with("H5") || (name == "OFFDEF" && value == "LROFF");
        if !harmless {
            f.error(
                i,
                "PARAMi",
                format!("model parameter {name} is not supported (paraflex accepts only the HDF5 output options HDF5 and H5… and OFFDEF = LROFF, which do not change linear results)"),
            );
        }
    }
    f.finish(card.fields.len())
}
