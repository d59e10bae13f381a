//! Superelement cards that paraflex reads only to refuse them with their reason.
//!
//! paraflex reads one bulk data section and no part superelements (`BEGIN SUPER = n`, or
//! `BEGIN BULK SUPER = n`, is an error at its line), so a card that acts on a part superelement
//! names a superelement no model paraflex builds contains.

use crate::deck::error::DeckError;
use crate::deck::fields::RawCard;
use crate::deck::reader::FieldReader;

/// `SELOC` — relocation of a part superelement: read, then refused.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | SEID | int > 0 | required | part superelement to move |
/// | 3–5 | PA1–PA3 | int > 0 | required | three non-collinear GRID/POINT ids of superelement SEID |
/// | 6–8 | PB1–PB3 | int > 0 | required | three GRID/POINT ids of the main bulk data that PA1–PA3 are moved onto |
///
/// Nastran requires PA1–PA3 in part superelement SEID and stops with a fatal message when that
/// superelement is not defined. paraflex reads no part superelement, so every `SELOC` is refused
/// at its SEID field (after its fields are checked), with that reason: the deck is not run
/// with its superelements left out or left where they were drawn.
pub fn seloc(card: &RawCard) -> Result<(), Vec<DeckError>> {
    let mut f = FieldReader::new(card);
    let seid = f.id(1, "SEID");
    f.set_id(seid);
    for (i, name) in [
        (2, "PA1"),
        (3, "PA2"),
        (4, "PA3"),
        (5, "PB1"),
        (6, "PB2"),
        (7, "PB3"),
    ] {
        f.id(i, name);
    }
    f.error(
        1,
        "SEID",
        format!(
            "SELOC moves part superelement {seid}, which paraflex does not read (it reads no part superelements); Nastran stops on a SELOC whose superelement is not defined"
        ),
    );
    f.finish(7)
}
