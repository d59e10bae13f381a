//! Grid points and coordinate systems: `GRID`, `GRDSET`, `CORD2R`, `CORD2C`, `CORD2S`.

use crate::card_values::Dofs;
use crate::deck::error::{DeckError, Loc};
use crate::deck::fields::RawCard;
use crate::deck::reader::FieldReader;

/// `GRID` — grid point.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | ID | int > 0 | required | grid id |
/// | 3 | CP | int ≥ 0 | GRDSET CP, else 0 | coordinate system of X1–X3 |
/// | 4–6 | X1 X2 X3 | real | 0.0 | location in CP |
/// | 7 | CD | int ≥ 0 | GRDSET CD, else 0 | displacement (output) coordinate system |
/// | 8 | PS | components | GRDSET PS, else none | permanent single-point constraints |
/// | 9 | SEID | int ≥ 0 | 0 | superelement id (only 0 is supported) |
///
/// A blank CP, CD or PS takes the deck's `GRDSET` value (kept as `None` here).
#[derive(Debug, Clone, PartialEq)]
pub struct Grid {
    pub id: u32,
    pub cp: Option<u32>,
    pub x: [f64; 3],
    pub cd: Option<u32>,
    pub ps: Option<Dofs>,
    pub loc: Loc,
}

impl Grid {
    /// Read a `GRID` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let id = f.id(1, "ID");
        f.set_id(id);
        let cp = (!f.value(2).is_blank()).then(|| f.id0_or(2, "CP", 0));
        let x = [
            f.real_or(3, "X1", 0.0),
            f.real_or(4, "X2", 0.0),
            f.real_or(5, "X3", 0.0),
        ];
        let cd = (!f.value(6).is_blank()).then(|| f.id0_or(6, "CD", 0));
        let ps = (!f.value(7).is_blank()).then(|| f.dofs(7, "PS"));
        if f.id0_or(8, "SEID", 0) != 0 {
            f.error(
                8,
                "SEID",
                "superelements are not supported; SEID must be blank or 0",
            );
        }
        let loc = f.loc();
        f.finish(8)?;
        Ok(Grid {
            id,
            cp,
            x,
            cd,
            ps,
            loc,
        })
    }
}

/// `GRDSET` — defaults for the blank CP, CD and PS fields of every `GRID`.
///
/// At most one per deck. Fields 2 and 4–6 are blank.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 3 | CP | int ≥ 0 | 0 | coordinate system of a GRID's X1–X3 |
/// | 7 | CD | int ≥ 0 | 0 | displacement (output) coordinate system |
/// | 8 | PS | components | none | permanent single-point constraints |
/// | 9 | SEID | int ≥ 0 | 0 | superelement id (only 0 is supported) |
#[derive(Debug, Clone, PartialEq)]
pub struct Grdset {
    pub cp: u32,
    pub cd: u32,
    pub ps: Dofs,
    pub loc: Loc,
}

impl Grdset {
    /// Read a `GRDSET` card (fields 2 and 4–6 are unused and must be blank).
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        for (i, name) in [
            (1, "field 2"),
            (3, "field 4"),
            (4, "field 5"),
            (5, "field 6"),
        ] {
            if !f.value(i).is_blank() {
                f.error(i, name, "GRDSET leaves this field blank");
            }
        }
        let cp = f.id0_or(2, "CP", 0);
        let cd = f.id0_or(6, "CD", 0);
        let ps = f.dofs(7, "PS");
        if f.id0_or(8, "SEID", 0) != 0 {
            f.error(
                8,
                "SEID",
                "superelements are not supported; SEID must be blank or 0",
            );
        }
        let loc = f.loc();
        f.finish(8)?;
        Ok(Grdset { cp, cd, ps, loc })
    }
}

/// Kind of a `CORD2x` coordinate system.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub enum CordKind {
    /// `CORD2R`: rectangular (x, y, z).
    Rectangular,
    /// `CORD2C`: cylindrical (r, θ in degrees, z).
    Cylindrical,
    /// `CORD2S`: spherical (r, θ from the z axis in degrees, φ about z from the x axis in
    /// degrees).
    Spherical,
}

/// `CORD2R` / `CORD2C` / `CORD2S` — coordinate system defined by three points in system RID.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | CID | int > 0 | required | system id |
/// | 3 | RID | int ≥ 0 | 0 | system in which A, B, C are given |
/// | 4–6 | A1 A2 A3 | real | 0.0 | origin |
/// | 7–9 | B1 B2 B3 | real | 0.0 | a point on the z axis |
/// | cont. 2–4 | C1 C2 C3 | real | 0.0 | a point in the x–z plane |
///
/// A location in the system (GRID X1–X3 with CP = CID) is (x, y, z) in a CORD2R, (r, θ, z) in a
/// CORD2C and (r, θ, φ) in a CORD2S (θ from the z axis, φ about z from the x–z plane; angles in
/// degrees); as a CD, the components follow the local (e_r, e_θ, e_z) or (e_r, e_θ, e_φ) at the
/// grid.
#[derive(Debug, Clone, PartialEq)]
pub struct Cord2 {
    pub id: u32,
    pub kind: CordKind,
    pub rid: u32,
    pub a: [f64; 3],
    pub b: [f64; 3],
    pub c: [f64; 3],
    pub loc: Loc,
}

impl Cord2 {
    /// Read a `CORD2R` or `CORD2C` card.
    pub fn from_card(card: &RawCard, kind: CordKind) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let id = f.id(1, "CID");
        f.set_id(id);
        let rid = f.id0_or(2, "RID", 0);
        let point = |f: &mut FieldReader, first: usize, names: [&str; 3]| {
            [
                f.real_or(first, names[0], 0.0),
                f.real_or(first + 1, names[1], 0.0),
                f.real_or(first + 2, names[2], 0.0),
            ]
        };
        let a = point(&mut f, 3, ["A1", "A2", "A3"]);
        let b = point(&mut f, 6, ["B1", "B2", "B3"]);
        let c = point(&mut f, 9, ["C1", "C2", "C3"]);
        let loc = f.loc();
        f.finish(11)?;
        Ok(Cord2 {
            id,
            kind,
            rid,
            a,
            b,
            c,
            loc,
        })
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::deck::value::lex;
    use std::path::Path;
    use std::sync::Arc;

    pub(crate) fn raw(name: &str, fields: &[&str]) -> RawCard {
        RawCard {
            name: name.into(),
            loc: Loc::new(&Arc::from(Path::new("t.bdf")), 1),
            fields: fields.iter().map(|f| lex(f)).collect(),
            row_lines: vec![2, 3],
        }
    }

    #[test]
    fn grid_blanks_are_left_to_grdset_and_zeros_are_kept() {
        let g = Grid::from_card(&raw("GRID", &["7", "", "1.", "2.", ""])).unwrap();
        assert_eq!(
            (g.id, g.cp, g.x, g.cd, g.ps),
            (7, None, [1.0, 2.0, 0.0], None, None)
        );
        let g = Grid::from_card(&raw("GRID", &["7", "0", "1.", "2.", "", "0", "0"])).unwrap();
        assert_eq!((g.cp, g.cd, g.ps), (Some(0), Some(0), Some(Dofs::NONE)));
    }

    #[test]
    fn grdset_reads_cp_cd_ps_and_refuses_the_unused_fields() {
        let g = Grdset::from_card(&raw("GRDSET", &["", "2", "", "", "", "3", "456"])).unwrap();
        assert_eq!((g.cp, g.cd, g.ps), (2, 3, Dofs::parse(456).unwrap()));
        let e = Grdset::from_card(&raw("GRDSET", &["1", "2", "3."])).unwrap_err();
        assert_eq!(e.len(), 2, "{e:?}");
    }

    #[test]
    fn grid_collects_all_bad_fields() {
        let e = Grid::from_card(&raw("GRID", &["7", "1.", "1", "2.", "", "", "17"])).unwrap_err();
        assert_eq!(e.len(), 3, "{e:?}");
        assert!(
            e.iter()
                .all(|e| e.to_string().starts_with("t.bdf:1: GRID 7: field"))
        );
    }

    #[test]
    fn cord2r_reads_continuation() {
        let c = Cord2::from_card(
            &raw(
                "CORD2R",
                &[
                    "3", "", "0.", "0.", "0.", "0.", "0.", "1.", "1.", "0.", "0.",
                ],
            ),
            CordKind::Rectangular,
        )
        .unwrap();
        assert_eq!((c.id, c.b, c.c), (3, [0., 0., 1.], [1., 0., 0.]));
    }
}
