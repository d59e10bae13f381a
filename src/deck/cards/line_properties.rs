//! Line-element properties: `PROD`, `PTUBE`, `PBAR`, `PBARL`, `PBEAM`, `PBEAML`, `PBEND`.

use crate::deck::error::{DeckError, Loc};
use crate::deck::fields::RawCard;
use crate::deck::reader::FieldReader;
use crate::deck::value::Value;

/// `PROD` — rod property.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | PID | int > 0 | required | property id |
/// | 3 | MID | int > 0 | required | MAT1 id |
/// | 4 | A | real | 0.0 | area |
/// | 5 | J | real | 0.0 | torsion constant |
/// | 6 | C | real | 0.0 | torsional stress coefficient (kept, unused) |
/// | 7 | NSM | real | 0.0 | non-structural mass per length |
#[derive(Debug, Clone, PartialEq)]
pub struct Prod {
    pub id: u32,
    pub mid: u32,
    pub a: f64,
    pub j: f64,
    pub c: f64,
    pub nsm: f64,
    pub loc: Loc,
}

impl Prod {
    /// Read a `PROD` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let id = f.id(1, "PID");
        f.set_id(id);
        let mid = f.id(2, "MID");
        let a = f.real_or(3, "A", 0.0);
        let j = f.real_or(4, "J", 0.0);
        let c = f.real_or(5, "C", 0.0);
        let nsm = f.real_or(6, "NSM", 0.0);
        let loc = f.loc();
        f.finish(6)?;
        Ok(Prod {
            id,
            mid,
            a,
            j,
            c,
            nsm,
            loc,
        })
    }
}

/// `PTUBE` — circular tube property (constant diameter).
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | PID | int > 0 | required | property id |
/// | 3 | MID | int > 0 | required | MAT1 id |
/// | 4 | OD | real > 0 | required | outer diameter |
/// | 5 | T | real | OD/2 (solid) | wall thickness, 0 < T ≤ OD/2 |
/// | 6 | NSM | real | 0.0 | non-structural mass per length |
/// | 7 | OD2 | real | OD | diameter at end B: a different value (tapered tube) is refused |
#[derive(Debug, Clone, PartialEq)]
pub struct Ptube {
    pub id: u32,
    pub mid: u32,
    pub od: f64,
    pub t: f64,
    pub nsm: f64,
    pub loc: Loc,
}

impl Ptube {
    /// Read a `PTUBE` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let id = f.id(1, "PID");
        f.set_id(id);
        let mid = f.id(2, "MID");
        let od = f.positive_real(3, "OD");
        let t = f.real_or(4, "T", od / 2.0);
        if !(t > 0.0 && t <= od / 2.0) {
            f.error(
                4,
                "T",
                format!("expected 0 < T <= OD/2 = {:e}, found {t:e}", od / 2.0),
            );
        }
        let nsm = f.real_or(5, "NSM", 0.0);
        if let Some(od2) = f.opt_real(6, "OD2")
            && od2 != od
        {
            f.error(
                6,
                "OD2",
                format!("a tapered tube (OD2 = {od2:e} differs from OD = {od:e}) is not supported"),
            );
        }
        let loc = f.loc();
        f.finish(6)?;
        Ok(Ptube {
            id,
            mid,
            od,
            t,
            nsm,
            loc,
        })
    }
}

/// `PBAR` — simple beam property.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | PID | int > 0 | required | property id |
/// | 3 | MID | int > 0 | required | MAT1 id |
/// | 4 | A | real | 0.0 | area |
/// | 5, 6 | I1 I2 | real | 0.0 | area moments of inertia (plane 1: about the element z axis) |
/// | 7 | J | real | 0.0 | torsion constant |
/// | 8 | NSM | real | 0.0 | non-structural mass per length |
/// | cont. 2–9 | C1 … F2 | real | 0.0 | stress recovery points (kept, unused) |
/// | cont. 2, 3 | K1 K2 | real | blank | shear area factors; blank: rigid in shear (Euler–Bernoulli) |
/// | cont. 4 | I12 | real | 0.0 | product of inertia ∫yz dA |
#[derive(Debug, Clone, PartialEq)]
pub struct Pbar {
    pub id: u32,
    pub mid: u32,
    pub a: f64,
    pub i1: f64,
    pub i2: f64,
    pub i12: f64,
    pub j: f64,
    pub nsm: f64,
    pub k1: Option<f64>,
    pub k2: Option<f64>,
    pub loc: Loc,
}

impl Pbar {
    /// Read a `PBAR` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let id = f.id(1, "PID");
        f.set_id(id);
        let mid = f.id(2, "MID");
        let a = f.real_or(3, "A", 0.0);
        let i1 = f.real_or(4, "I1", 0.0);
        let i2 = f.real_or(5, "I2", 0.0);
        let j = f.real_or(6, "J", 0.0);
        let nsm = f.real_or(7, "NSM", 0.0);
        for (k, name) in ["C1", "C2", "D1", "D2", "E1", "E2", "F1", "F2"]
            .iter()
            .enumerate()
        {
            f.opt_real(9 + k, name);
        }
        let k1 = f.opt_real(17, "K1");
        let k2 = f.opt_real(18, "K2");
        let i12 = f.real_or(19, "I12", 0.0);
        for (i, name, v) in [(4, "I1", i1), (5, "I2", i2)] {
            if v < 0.0 {
                f.error(i, name, format!("expected a real >= 0, found {v:e}"));
            }
        }
        let loc = f.loc();
        f.finish(19)?;
        Ok(Pbar {
            id,
            mid,
            a,
            i1,
            i2,
            i12,
            j,
            nsm,
            k1,
            k2,
            loc,
        })
    }
}

/// `PBARL` / `PBEAML` — beam property by a library cross-section.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | PID | int > 0 | required | property id |
/// | 3 | MID | int > 0 | required | MAT1 id |
/// | 4 | GROUP | name | MSCBML0 | only the standard library MSCBML0 |
/// | 5 | TYPE | name | required | a shape of the MSCBML0 library; paraflex computes ROD TUBE BAR BOX I CHAN T L and refuses the others by name when the property is used |
/// | cont. | DIM1 … DIMn, NSM | real | NSM 0.0 | dimensions of the shape (`fe::beam_section`), then the non-structural mass per length |
///
/// `PBEAML` may continue with stations `SO X/XB DIM1 … DIMn NSM`; only a constant section
/// (every station's dimensions equal to end A's) is supported.
#[derive(Debug, Clone, PartialEq)]
pub struct Pbarl {
    pub id: u32,
    pub mid: u32,
    pub shape: String,
    pub dims: Vec<f64>,
    pub nsm: f64,
    pub loc: Loc,
}

impl Pbarl {
    /// Read a `PBARL` (`beam` false) or `PBEAML` (`beam` true) card.
    pub fn from_card(card: &RawCard, beam: bool) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let id = f.id(1, "PID");
        f.set_id(id);
        let mid = f.id(2, "MID");
        let group = f.opt_text(3, "GROUP").unwrap_or_else(|| "MSCBML0".into());
        if group != "MSCBML0" {
            f.error(
                3,
                "GROUP",
                format!("GROUP = {group} is not supported; only the standard library MSCBML0"),
            );
        }
        let shape = f.text(4, "TYPE");
        let len = f.len();
        let numeric: Vec<usize> = (9..=len)
            .filter(|&i| !matches!(f.value(i), Value::Text(_)))
            .collect();
        let values: Vec<f64> = numeric.iter().map(|&i| f.real_or(i, "DIM", 0.0)).collect();
        let Some(n) = LIBRARY_DIMENSIONS
            .iter()
            .find(|(name, _)| *name == shape)
            .map(|(_, n)| *n)
        else {
            f.error(
                4,
                "TYPE",
                format!("TYPE = {shape} is not a shape of the MSCBML0 library"),
            );
            return Err(f.into_errors());
        };
        let dims: Vec<f64> = values.iter().take(n).copied().collect();
        let nsm = values.get(n).copied().unwrap_or(0.0);
        if beam {
            // stations: SO X/XB DIM1…DIMn NSM after end A's dimensions and NSM
            let mut i = 9 + n + 1;
            while i <= len {
                let station_dims: Vec<f64> = (i + 2..i + 2 + n)
                    .map(|k| f.real_or(k, "DIM", 0.0))
                    .collect();
                let station_nsm = f.real_or(i + 2 + n, "NSM", nsm);
                let blank_dims = (i + 2..i + 2 + n).all(|k| f.value(k).is_blank());
                if !(blank_dims || station_dims == dims) || station_nsm != nsm {
                    f.error(
                        i + 1,
                        "X/XB",
                        "a tapered PBEAML (a station with other dimensions or NSM) is not supported",
                    );
                }
                i += n + 3;
            }
        } else if values.len() > n + 1 {
            f.card_error(format!(
                "TYPE = {shape} takes {n} dimensions and NSM; {} values given",
                values.len()
            ));
        }
        let loc = f.loc();
        f.finish(len)?;
        Ok(Pbarl {
            id,
            mid,
            shape,
            dims,
            nsm,
            loc,
        })
    }
}

/// The number of dimensions DIM1…DIMn of each shape of the standard library (MSCBML0).
const LIBRARY_DIMENSIONS: [(&str, usize); 21] = [
    ("ROD", 1),
    ("TUBE", 2),
    ("TUBE2", 2),
    ("I", 6),
    ("CHAN", 4),
    ("T", 4),
    ("BOX", 4),
    ("BAR", 2),
    ("CROSS", 4),
    ("H", 4),
    ("T1", 4),
    ("I1", 4),
    ("CHAN1", 4),
    ("Z", 4),
    ("CHAN2", 4),
    ("T2", 4),
    ("BOX1", 6),
    ("HEXA", 3),
    ("HAT", 4),
    ("HAT1", 5),
    ("DBOX", 10),
];

/// `PBEAM` — beam property, constant section.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | PID | int > 0 | required | property id |
/// | 3 | MID | int > 0 | required | MAT1 id |
/// | 4–8 | A I1 I2 I12 J | real | 0.0 | section at end A (I12 = ∫yz dA) |
/// | 9 | NSM | real | 0.0 | non-structural mass per length |
/// | cont. | C1 … F2 | real | blank | stress recovery points at end A (kept, unused) |
/// | cont. | SO X/XB A I1 I2 I12 J NSM (+ C1 … F2 when SO = YES) | | blank = end A's value | stations; a station that differs from end A by more than 1e-4 relative (a taper, not the rounding of an 8-character field) is refused; end A's section is used |
/// | cont. | K1 K2 S1 S2 NSI(A) NSI(B) CW(A) CW(B) | real | 1.0 1.0 0 … | shear factors (0.0: rigid in shear); S1 S2 and CW kept (no effect on a constant section without warping DOF); NSI ≠ 0 refused |
/// | cont. | M1(A) M2(A) M1(B) M2(B) | real | 0.0 | centre-of-mass offsets: ≠ 0 refused |
/// | cont. | N1(A) N2(A) N1(B) N2(B) | real | 0.0 (B: A's) | neutral axis (y, z) from the shear centre (the element axis): axial force acts on it, coupling stretch and bending; end B as end A only |
#[derive(Debug, Clone, PartialEq)]
pub struct Pbeam {
    pub id: u32,
    pub mid: u32,
    pub a: f64,
    pub i1: f64,
    pub i2: f64,
    pub i12: f64,
    pub j: f64,
    pub nsm: f64,
    pub k1: f64,
    pub k2: f64,
    /// Neutral axis (N1, N2) from the shear centre in the element's y, z.
    pub neutral_axis: [f64; 2],
    pub loc: Loc,
}

/// Relative difference up to which a station's value is end A's value: the rounding of a value
/// printed in an 8-character field (5 significant digits, e.g. 5.2083-3 and 5.208-3).
const SAME_SECTION: f64 = 1e-4;

/// The station fields A I1 I2 I12 J NSM, by offset from X/XB.
const STATION: [&str; 6] = ["A", "I1", "I2", "I12", "J", "NSM"];

impl Pbeam {
    /// Read a `PBEAM` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let id = f.id(1, "PID");
        f.set_id(id);
        let mid = f.id(2, "MID");
        let end_a: Vec<f64> = (0..6).map(|k| f.real_or(3 + k, STATION[k], 0.0)).collect();
        let so = |f: &FieldReader, i: usize| matches!(f.value(i), Value::Text(t) if ["YES", "YESA", "NO"].iter().any(|k| k.eq_ignore_ascii_case(t)));
        let len = f.len();
        // line 2: end A's stress points unless it is already a station
        let mut i = if so(&f, 9) { 9 } else { 17 };
        while i <= len && so(&f, i) {
            let yes = matches!(f.value(i), Value::Text(t) if t.eq_ignore_ascii_case("YES"));
            let x = f.real_or(i + 1, "X/XB", 1.0);
            for (k, name) in STATION.iter().enumerate() {
                let v = f.real_or(i + 2 + k, name, end_a[k]);
                if (v - end_a[k]).abs() > SAME_SECTION * v.abs().max(end_a[k].abs()) {
                    f.error(
                        i + 2 + k,
                        name,
                        format!(
                            "the station at X/XB = {x} has {name} = {v:e}, end A {:e}: a tapered PBEAM is not supported",
                            end_a[k]
                        ),
                    );
                }
            }
            i += 8;
            if yes && !so(&f, i) && i <= len {
                // C1 … F2 of this station, unless the line holds the shear factors: stress
                // points only follow SO = YES
                i += 8;
            }
        }
        let k1 = f.real_or(i, "K1", 1.0);
        let k2 = f.real_or(i + 1, "K2", 1.0);
        for (k, name) in [(2, "S1"), (3, "S2"), (6, "CW(A)"), (7, "CW(B)")] {
            f.opt_real(i + k, name);
        }
        for (k, name) in [(4, "NSI(A)"), (5, "NSI(B)")] {
            if f.real_or(i + k, name, 0.0) != 0.0 {
                f.error(
                    i + k,
                    name,
                    "non-structural mass moment of inertia is not supported",
                );
            }
        }
        for (k, name) in ["M1(A)", "M2(A)", "M1(B)", "M2(B)"].iter().enumerate() {
            if f.real_or(i + 8 + k, name, 0.0) != 0.0 {
                f.error(i + 8 + k, name, "centre-of-mass offsets are not supported");
            }
        }
        // the neutral axis of end A, end B's by default; a varying one would be a taper
        let na_a = [
            f.real_or(i + 12, "N1(A)", 0.0),
            f.real_or(i + 13, "N2(A)", 0.0),
        ];
        for (k, name) in [(14, "N1(B)"), (15, "N2(B)")] {
            let b = f.real_or(i + k, name, na_a[k - 14]);
            if (b - na_a[k - 14]).abs() > SAME_SECTION * b.abs().max(na_a[k - 14].abs()) {
                f.error(
                    i + k,
                    name,
                    format!("{name} = {b:e} differs from end A's {:e}: a neutral axis that varies along the beam is not supported", na_a[k - 14]),
                );
            }
        }
        let loc = f.loc();
        f.finish(i + 15)?;
        Ok(Pbeam {
            id,
            mid,
            a: end_a[0],
            i1: end_a[1],
            i2: end_a[2],
            i12: end_a[3],
            j: end_a[4],
            nsm: end_a[5],
            k1,
            k2,
            neutral_axis: na_a,
            loc,
        })
    }
}

/// `PBEND` — curved beam property (MSC's first form: the section given by its constants).
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | PID | int > 0 | required | property id |
/// | 3 | MID | int > 0 | required | MAT1 id |
/// | 4 | A | real > 0 | required | area (an integer here is MSC's pipe form, FSI RM T P: refused) |
/// | 5, 6 | I1 I2 | real > 0 | required | area moments of inertia: I1 in the plane of the arc, I2 out of it |
/// | 7 | J | real ≥ 0 | 0.0 | torsion constant |
/// | 8 | RB | real > 0 | blank | bend radius (needed by CBEND GEOM = 3; 0.0 is blank) |
/// | 9 | THETAB | real | blank | arc angle in degrees, 0 < THETAB < 360 (needed by GEOM = 4; 0.0 is blank) |
/// | cont. 2–9 | C1 … F2 | real | 0.0 | stress recovery points (kept, unused) |
/// | cont. 2, 3 | K1 K2 | real | blank | shear area factors in and out of the plane of the arc; blank or 0: rigid in shear |
/// | cont. 4 | NSM | real | 0.0 | non-structural mass per length |
/// | cont. 5, 6, 7 | RC ZC DELTAN | real | 0.0 | offsets of the centroid from the grids' arc and of the neutral axis from the centroid: only 0 is supported |
#[derive(Debug, Clone, PartialEq)]
pub struct Pbend {
    pub id: u32,
    pub mid: u32,
    pub a: f64,
    pub i1: f64,
    pub i2: f64,
    pub j: f64,
    pub rb: Option<f64>,
    pub thetab: Option<f64>,
    pub k1: Option<f64>,
    pub k2: Option<f64>,
    pub nsm: f64,
    pub loc: Loc,
}

impl Pbend {
    /// Read a `PBEND` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let id = f.id(1, "PID");
        f.set_id(id);
        let mid = f.id(2, "MID");
        let a = if let Value::Int(_) = f.value(3) {
            f.error(
                3,
                "FSI",
                "the pipe form of PBEND (FSI RM T P) is not supported; give A I1 I2 J",
            );
            0.0
        } else {
            f.positive_real(3, "A")
        };
        let i1 = f.positive_real(4, "I1");
        let i2 = f.positive_real(5, "I2");
        let j = f.real_or(6, "J", 0.0);
        // 0.0 is taken as not given, as a blank
        let rb = f.opt_real(7, "RB").filter(|&r| r != 0.0);
        let thetab = f.opt_real(8, "THETAB").filter(|&t| t != 0.0);
        for (k, name) in ["C1", "C2", "D1", "D2", "E1", "E2", "F1", "F2"]
            .iter()
            .enumerate()
        {
            f.opt_real(9 + k, name);
        }
        let factor = |k: Option<f64>| k.filter(|&k| k > 0.0);
        let k1 = factor(f.opt_real(17, "K1"));
        let k2 = factor(f.opt_real(18, "K2"));
        let nsm = f.real_or(19, "NSM", 0.0);
        for (i, name) in [(20, "RC"), (21, "ZC"), (22, "DELTAN")] {
            if f.real_or(i, name, 0.0) != 0.0 {
                f.error(
                    i,
                    name,
                    "offsets of the centroid or neutral axis are not supported; give 0 or blank",
                );
            }
        }
        if j < 0.0 {
            f.error(6, "J", format!("expected a real >= 0, found {j:e}"));
        }
        if let Some(rb) = rb.filter(|&r| !(r > 0.0)) {
            f.error(7, "RB", format!("expected a real > 0, found {rb:e}"));
        }
        if let Some(t) = thetab.filter(|&t| !(t > 0.0 && t < 360.0)) {
            f.error(
                8,
                "THETAB",
                format!("expected 0 < THETAB < 360 degrees, found {t:e}"),
            );
        }
        let loc = f.loc();
        f.finish(22)?;
        Ok(Pbend {
            id,
            mid,
            a,
            i1,
            i2,
            j,
            rb,
            thetab,
            k1,
            k2,
            nsm,
            loc,
        })
    }
}
