//! Materials: isotropic `MAT1`, orthotropic plane-stress `MAT8` and anisotropic plane-stress
//! `MAT2`.

use crate::card_values::PlyAllowables;
use crate::deck::error::{DeckError, Loc};
use crate::deck::fields::RawCard;
use crate::deck::reader::FieldReader;

/// `MAT1` — isotropic material.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | MID | int > 0 | required | material id |
/// | 3 | E | real | see below | Young's modulus |
/// | 4 | G | real | see below | shear modulus |
/// | 5 | NU | real | see below | Poisson's ratio |
/// | 6 | RHO | real | 0.0 | mass density |
/// | 7 | A | real | 0.0 | thermal expansion coefficient (thermal loads, `TEMPERATURE(LOAD)`) |
/// | 8 | TREF | real | 0.0 | reference (stress-free) temperature |
/// | 9 | GE | real | 0.0 | structural damping coefficient |
/// | cont. 2–5 | ST SC SS MCSID | | blank | stress limits (kept, unused) |
///
/// As in Nastran, two of E, G, NU give the third (G = E / (2(1+NU))); E alone gives NU = 0 and
/// G = E/2; at least one of E and G must be given.
#[derive(Debug, Clone, PartialEq)]
pub struct Mat1 {
    pub id: u32,
    pub e: f64,
    pub g: f64,
    pub nu: f64,
    pub rho: f64,
    pub a: f64,
    pub tref: f64,
    pub ge: f64,
    /// Which of E, G, NU were given on the card (the rest are derived).
    pub given: [bool; 3],
    pub loc: Loc,
}

impl Mat1 {
    /// Read a `MAT1` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let id = f.id(1, "MID");
        f.set_id(id);
        let (e, g, nu) = (f.opt_real(2, "E"), f.opt_real(3, "G"), f.opt_real(4, "NU"));
        let given = [e.is_some(), g.is_some(), nu.is_some()];
        let (e, g, nu) = match (e, g, nu) {
            (Some(e), Some(g), Some(nu)) => (e, g, nu),
            (Some(e), None, Some(nu)) => (e, e / (2.0 * (1.0 + nu)), nu),
            (Some(e), Some(g), None) => (e, g, e / (2.0 * g) - 1.0),
            (None, Some(g), Some(nu)) => (2.0 * (1.0 + nu) * g, g, nu),
            (Some(e), None, None) => (e, e / 2.0, 0.0),
            (None, Some(g), None) => (0.0, g, 0.0),
            (None, None, _) => {
                f.error(2, "E", "at least one of E and G must be given");
                (0.0, 0.0, 0.0)
            }
        };
        let rho = f.real_or(5, "RHO", 0.0);
        let a = f.real_or(6, "A", 0.0);
        let tref = f.real_or(7, "TREF", 0.0);
        let ge = f.real_or(8, "GE", 0.0);
        for (i, name) in [(9, "ST"), (10, "SC"), (11, "SS")] {
            f.opt_real(i, name);
        }
        f.id0_or(12, "MCSID", 0);
        let loc = f.loc();
        f.finish(12)?;
        Ok(Mat1 {
            id,
            e,
            g,
            nu,
            rho,
            a,
            tref,
            ge,
            given,
            loc,
        })
    }
}

/// `MAT8` — orthotropic material for shells (plane stress).
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | MID | int > 0 | required | material id |
/// | 3 | E1 | real | required | modulus along the fibres |
/// | 4 | E2 | real | required | transverse modulus |
/// | 5 | NU12 | real | required | Poisson's ratio (strain in 2 from stress in 1) |
/// | 6 | G12 | real | 0.0 | in-plane shear modulus |
/// | 7 | G1Z | real | blank | transverse shear modulus 1–Z; blank = rigid in transverse shear |
/// | 8 | G2Z | real | blank | transverse shear modulus 2–Z; blank = rigid in transverse shear |
/// | 9 | RHO | real | 0.0 | mass density |
/// | cont. 2–3 | A1 A2 | real | 0.0 | thermal expansion coefficients along material axes 1, 2 |
/// | cont. 4 | TREF | real | 0.0 | reference (stress-free) temperature |
/// | cont. 5–9 | Xt Xc Yt Yc S | real > 0 | blank; Xc = Xt, Yc = Yt | allowables along and across the fibres (tension, compression as magnitudes) and in-plane shear, for PCOMP failure indices |
/// | cont. 2 | GE | real | 0.0 | structural damping coefficient |
/// | cont. 3 | F12 | real | blank | Tsai–Wu interaction coefficient (FT = TSAI needs it) |
/// | cont. 4 | STRN | real | blank | 1.0: Xt … S are strain allowables (FT = STRN needs it; HILL, HOFF need stress allowables) |
#[derive(Debug, Clone, PartialEq)]
pub struct Mat8 {
    pub id: u32,
    pub e1: f64,
    pub e2: f64,
    pub nu12: f64,
    pub g12: f64,
    pub g1z: Option<f64>,
    pub g2z: Option<f64>,
    pub rho: f64,
    /// Thermal expansion coefficients A1, A2 along the material axes 1, 2.
    pub a: [f64; 2],
    /// Reference (stress-free) temperature.
    pub tref: f64,
    pub ge: f64,
    /// Strength allowables (ply failure indices).
    pub allowables: PlyAllowables,
    pub loc: Loc,
}

impl Mat8 {
    /// Read a `MAT8` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let id = f.id(1, "MID");
        f.set_id(id);
        let e1 = f.real(2, "E1");
        let e2 = f.real(3, "E2");
        let nu12 = f.real(4, "NU12");
        let g12 = f.real_or(5, "G12", 0.0);
        let g1z = f.opt_real(6, "G1Z");
        let g2z = f.opt_real(7, "G2Z");
        let rho = f.real_or(8, "RHO", 0.0);
        let a = [f.real_or(9, "A1", 0.0), f.real_or(10, "A2", 0.0)];
        let tref = f.real_or(11, "TREF", 0.0);
        let xt = f.opt_real(12, "Xt");
        let yt = f.opt_real(14, "Yt");
        let allowables = PlyAllowables {
            xt,
            xc: f.opt_real(13, "Xc").or(xt),
            yt,
            yc: f.opt_real(15, "Yc").or(yt),
            s: f.opt_real(16, "S"),
            f12: None,
            strain_allowables: false,
        };
        let ge = f.real_or(17, "GE", 0.0);
        let allowables = PlyAllowables {
            f12: f.opt_real(18, "F12"),
            strain_allowables: f.opt_real(19, "STRN") == Some(1.0),
            ..allowables
        };
        let loc = f.loc();
        f.finish(19)?;
        Ok(Mat8 {
            id,
            e1,
            e2,
            nu12,
            g12,
            g1z,
            g2z,
            rho,
            a,
            tref,
            ge,
            allowables,
            loc,
        })
    }
}

/// `MAT2` — anisotropic plane-stress material for shells, its stiffness matrix given directly.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | MID | int > 0 | required | material id |
/// | 3–8 | G11 G12 G13 G22 G23 G33 | real | 0.0 | symmetric stiffness {σ1 σ2 τ12} = G {ε1 ε2 γ12} in the element material axes |
/// | 9 | RHO | real | 0.0 | mass density |
/// | cont. 2–4 | A1 A2 A3 | real | 0.0 | thermal expansion coefficients of {ε1 ε2 γ12} |
/// | cont. 5 | TREF | real | 0.0 | reference temperature |
/// | cont. 6 | GE | real | 0.0 | structural damping coefficient |
/// | cont. 7–9 | ST SC SS | real | blank | stress limits (kept, unused) |
/// | cont. 2 | MCSID | int ≥ 0 | blank | material system for PARAM,CURV output (kept, unused) |
///
/// A PSHELL MID1, MID2 or MID4 takes G as its plane-stress matrix; a MID3 takes
/// [[G11, G12], [G12, G22]] as the transverse-shear matrix of {τxz τyz} (G13, G23, G33 must
/// then be 0, as Nastran requires). PCOMP plies, solids, rods and beams refuse a MAT2.
#[derive(Debug, Clone, PartialEq)]
pub struct Mat2 {
    pub id: u32,
    /// G11, G12, G13, G22, G23, G33.
    pub g: [f64; 6],
    pub rho: f64,
    /// Thermal expansion coefficients A1, A2, A3 ({ε1 ε2 γ12} per degree, material axes).
    pub a: [f64; 3],
    /// Reference (stress-free) temperature.
    pub tref: f64,
    pub ge: f64,
    pub loc: Loc,
}

impl Mat2 {
    /// Read a `MAT2` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let id = f.id(1, "MID");
        f.set_id(id);
        let names = ["G11", "G12", "G13", "G22", "G23", "G33"];
        let g: [f64; 6] = std::array::from_fn(|k| f.real_or(2 + k, names[k], 0.0));
        let rho = f.real_or(8, "RHO", 0.0);
        let a = [
            f.real_or(9, "A1", 0.0),
            f.real_or(10, "A2", 0.0),
            f.real_or(11, "A3", 0.0),
        ];
        let tref = f.real_or(12, "TREF", 0.0);
        let ge = f.real_or(13, "GE", 0.0);
        for (i, name) in [(14, "ST"), (15, "SC"), (16, "SS")] {
            f.opt_real(i, name);
        }
        f.id0_or(17, "MCSID", 0);
        let loc = f.loc();
        f.finish(17)?;
        Ok(Mat2 {
            id,
            g,
            rho,
            a,
            tref,
            ge,
            loc,
        })
    }

    /// The 3 × 3 in-plane matrix G (order 1, 2, 12).
    pub fn in_plane(&self) -> [[f64; 3]; 3] {
        let [g11, g12, g13, g22, g23, g33] = self.g;
        [[g11, g12, g13], [g12, g22, g23], [g13, g23, g33]]
    }
}
