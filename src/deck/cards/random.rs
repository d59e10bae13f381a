//! Random response cards: `RANDPS`, `RANDT1`, `TABRND1`, `TABRNDG`.

use super::dynamic::table_entries;
use crate::deck::error::{DeckError, Loc};
use crate::deck::fields::RawCard;
use crate::deck::reader::FieldReader;

/// `RANDPS` — the input spectral density S_JK(f) = (X + iY)·G(f) between the loads of
/// subcases J and K (RANDOM = SID selects it).
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | SID | int > 0 | required | random set id |
/// | 3 | J | int > 0 | required | subcase of the excited load |
/// | 4 | K | int ≥ J | required | subcase of the applied load (K = J: an auto-spectrum) |
/// | 5 | X | real | required | real part of the scale |
/// | 6 | Y | real | 0.0 | imaginary part (0 when J = K) |
/// | 7 | TID | int ≥ 0 | 0 | TABRND1 or TABRNDG of G(f); 0: G = 1 |
#[derive(Debug, Clone, PartialEq)]
pub struct Randps {
    pub sid: u32,
    pub j: u32,
    pub k: u32,
    pub x: f64,
    pub y: f64,
    pub tid: u32,
    pub loc: Loc,
}

impl Randps {
    /// Read a `RANDPS` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let sid = f.id(1, "SID");
        f.set_id(sid);
        let j = f.id(2, "J");
        let k = f.id(3, "K");
        let x = f.real(4, "X");
        let y = f.real_or(5, "Y", 0.0);
        let tid = f.id0_or(6, "TID", 0);
        if k < j {
            f.error(3, "K", format!("expected K >= J = {j}, found {k}"));
        }
        if j == k && y != 0.0 {
            f.error(
                5,
                "Y",
                format!("an auto-spectrum (J = K) is real: expected Y = 0, found {y:e}"),
            );
        }
        let loc = f.loc();
        f.finish(6)?;
        Ok(Randps {
            sid,
            j,
            k,
            x,
            y,
            tid,
            loc,
        })
    }
}

/// `RANDT1` — time lags of the autocorrelation functions of a random set.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | SID | int > 0 | required | random set id (RANDOM = SID) |
/// | 3 | N | int > 0 | required | number of lag intervals |
/// | 4 | T0 | real ≥ 0 | required | first lag |
/// | 5 | TMAX | real > T0 | required | last lag |
///
/// The lags are T0 + i (TMAX − T0)/N, i = 0 … N.
#[derive(Debug, Clone, PartialEq)]
pub struct Randt1 {
    pub sid: u32,
    pub n: u32,
    pub t0: f64,
    pub tmax: f64,
    pub loc: Loc,
}

impl Randt1 {
    /// Read a `RANDT1` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let sid = f.id(1, "SID");
        f.set_id(sid);
        let n = f.count(2, "N");
        let t0 = f.real(3, "T0");
        let tmax = f.real(4, "TMAX");
        if t0 < 0.0 {
            f.error(3, "T0", format!("expected T0 >= 0, found {t0:e}"));
        }
        if tmax <= t0 {
            f.error(
                4,
                "TMAX",
                format!("expected TMAX > T0 = {t0:e}, found {tmax:e}"),
            );
        }
        let loc = f.loc();
        f.finish(4)?;
        Ok(Randt1 {
            sid,
            n,
            t0,
            tmax,
            loc,
        })
    }

    /// The time lags T0 + i (TMAX − T0)/N, i = 0 … N.
    pub fn lags(&self) -> Vec<f64> {
        let step = (self.tmax - self.t0) / f64::from(self.n);
        (0..=self.n)
            .map(|i| self.t0 + f64::from(i) * step)
            .collect()
    }
}

/// `TABRND1` and `TABRNDG` — the spectral density G(f) of a RANDPS.
#[derive(Debug, Clone, PartialEq)]
pub struct Tabrnd {
    pub id: u32,
    pub kind: TabrndKind,
    pub loc: Loc,
}

/// What a [`Tabrnd`] holds.
#[derive(Debug, Clone, PartialEq)]
pub enum TabrndKind {
    /// `TABRND1 ID XAXIS YAXIS` + (f, g) pairs to `ENDT`: interpolated linearly in the
    /// axes' scales (LINEAR or LOG), extrapolated from the end segments, the mean (in the
    /// y scale) at a jump.
    Table {
        points: Vec<(f64, f64)>,
        log_x: bool,
        log_y: bool,
    },
    /// `TABRNDG ID TYPE LU WG`: the gust spectrum
    /// G(f) = 2 WG² LU (1 + 2(p + 1) k² LU² ω²)/(1 + k² LU² ω²)^(p + 3/2), ω = 2πf, with
    /// TYPE 1 (von Kármán) p = 1/3, k = 1.339 and TYPE 2 (Dryden) p = 1/2, k = 1;
    /// LU = scale of turbulence / velocity (time), WG = RMS gust velocity.
    Gust { von_karman: bool, lu: f64, wg: f64 },
}

impl Tabrnd {
    /// Read a `TABRND1` card.
    pub fn tabrnd1(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let id = f.id(1, "ID");
        f.set_id(id);
        let log_x = f.keyword(2, "XAXIS", &["LINEAR", "LOG"], Some("LINEAR")) == "LOG";
        let log_y = f.keyword(3, "YAXIS", &["LINEAR", "LOG"], Some("LINEAR")) == "LOG";
        let mut points = Vec::new();
        let len = f.len();
        let ended = table_entries(&mut f, |f, i| {
            points.push((f.real(i, "f"), f.real(i + 1, "g")));
            2
        });
        if !ended {
            f.card_error("the table does not end with ENDT");
        }
        if points.len() < 2 {
            f.card_error("a table needs at least two points");
        }
        if points.iter().any(|&(x, _)| x < 0.0 || (log_x && x <= 0.0)) {
            f.card_error(if log_x {
                "XAXIS = LOG needs frequencies > 0"
            } else {
                "the frequencies of a TABRND1 must be >= 0"
            });
        }
        if log_y && points.iter().any(|&(_, y)| y <= 0.0) {
            f.card_error("YAXIS = LOG needs spectral densities > 0");
        }
        if let Err(e) = crate::dynamics::table::Table::new(&points) {
            f.card_error(e.to_string());
        }
        let loc = f.loc();
        f.finish(len)?;
        Ok(Tabrnd {
            id,
            kind: TabrndKind::Table {
                points,
                log_x,
                log_y,
            },
            loc,
        })
    }

    /// Read a `TABRNDG` card.
    pub fn tabrndg(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let id = f.id(1, "ID");
        f.set_id(id);
        let kind = f.int(2, "TYPE");
        if !matches!(kind, 1 | 2) {
            f.error(
                2,
                "TYPE",
                format!("expected 1 (von Kármán) or 2 (Dryden), found {kind}"),
            );
        }
        let lu = f.positive_real(3, "LU");
        let wg = f.real(4, "WG");
        let loc = f.loc();
        f.finish(4)?;
        Ok(Tabrnd {
            id,
            kind: TabrndKind::Gust {
                von_karman: kind == 1,
                lu,
                wg,
            },
            loc,
        })
    }
}
