//! Dynamics cards: `EIGRL`, `FREQ`/`FREQ1`/`FREQ2`, `TSTEP`, `TLOAD1`/`TLOAD2`,
//! `RLOAD1`/`RLOAD2`, `DAREA`, `TABLED1`–`TABLED4`, `DLOAD`.

use super::loads::combination;
use crate::card_values::Dofs;
use crate::deck::error::{DeckError, Loc};
use crate::deck::fields::RawCard;
use crate::deck::reader::FieldReader;
use crate::deck::value::Value;
use crate::dynamics::pulse::Pulse;

/// `EIGRL` — real eigenvalue extraction (Lanczos).
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | SID | int > 0 | required | set id (selected by `METHOD`) |
/// | 3 | V1 | real | blank | lower frequency bound (Hz) |
/// | 4 | V2 | real | blank | upper frequency bound (Hz) |
/// | 5 | ND | int > 0 | blank | number of roots wanted |
/// | 6 | MSGLVL | int | 0 | diagnostics level (kept, unused) |
/// | 7 | MAXSET | int | blank | block size (kept, unused) |
/// | 8 | SHFSCL | real | blank | estimate of the first flexible mode (Hz) for free-free shifts |
/// | 9 | NORM | `MASS` / `MAX` | MASS | eigenvector normalization |
///
/// With neither V2 nor ND the lowest root (above V1 when given) is found, ND = 1, as the
/// MSC/NX and OptiStruct EIGRL tables of V1, V2, ND say. With massless DOFs (springs without
/// mass, rotations without rotary inertia) the mass matrix is singular and only rank(M) finite
/// modes exist: ND larger than that returns the finite modes with a warning (`only N finite
/// mode(s) exist …`), never modes at an "infinite" frequency.
#[derive(Debug, Clone, PartialEq)]
pub struct Eigrl {
    pub sid: u32,
    pub v1: Option<f64>,
    pub v2: Option<f64>,
    pub nd: Option<u32>,
    pub shfscl: Option<f64>,
    pub norm: EigenNorm,
    pub loc: Loc,
}

/// EIGRL NORM: how eigenvectors are normalized.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EigenNorm {
    /// φᵀMφ = 1.
    Mass,
    /// Largest component 1.
    Max,
}

impl EigenNorm {
    /// The keywords of NORM.
    pub const KEYWORDS: [(&'static str, EigenNorm); 2] =
        [("MASS", EigenNorm::Mass), ("MAX", EigenNorm::Max)];

    /// The keyword (`MASS`, `MAX`).
    pub fn name(self) -> &'static str {
        match self {
            EigenNorm::Mass => "MASS",
            EigenNorm::Max => "MAX",
        }
    }
}

impl Eigrl {
    /// Read an `EIGRL` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let sid = f.id(1, "SID");
        f.set_id(sid);
        let v1 = f.opt_real(2, "V1");
        let v2 = f.opt_real(3, "V2");
        let nd = f.opt_count(4, "ND");
        let nd = if v2.is_none() && nd.is_none() && f.value(4).is_blank() {
            Some(1)
        } else {
            nd
        };
        f.int_or(5, "MSGLVL", 0);
        f.opt_int(6, "MAXSET");
        let shfscl = f.opt_real(7, "SHFSCL");
        let norm = f.choice(8, "NORM", &EigenNorm::KEYWORDS, Some(EigenNorm::Mass));
        if let (Some(a), Some(b)) = (v1, v2)
            && b <= a
        {
            f.error(
                3,
                "V2",
                format!("V2 = {b:e} must be greater than V1 = {a:e}"),
            );
        }
        let loc = f.loc();
        f.finish(8)?;
        Ok(Eigrl {
            sid,
            v1,
            v2,
            nd,
            shfscl,
            norm,
            loc,
        })
    }
}

/// `EIGR` — real eigenvalue extraction by a named method, read as the equivalent `EIGRL`.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | SID | int > 0 | required | set id (selected by `METHOD`) |
/// | 3 | METHOD | `LAN`, `AHOU`, `HOU`, `MHOU`, `GIV`, `MGIV`, `INV`, `SINV` | required | extraction method |
/// | 4 | F1 | real | blank | lower frequency bound (Hz) |
/// | 5 | F2 | real | blank | upper frequency bound (Hz) |
/// | 6 | NE | int | blank | estimate of the roots in the range (kept, unused) |
/// | 7 | ND | int > 0 | blank | number of roots wanted |
/// | 10 | NORM | `MASS` / `MAX` | MASS | eigenvector normalization (`POINT` refused) |
/// | 11, 12 | G, C | int | blank | the grid and component of `NORM = POINT` |
///
/// The method names an algorithm, not a different answer: every method returns the roots in
/// [F1, F2] (the ND lowest of them when ND is given), which paraflex finds with the same
/// shift-invert Lanczos as EIGRL. With neither F2 nor ND the tridiagonal methods return every
/// root of the model, which only a dense method can: such a card is refused with a request for
/// F2 or ND.
pub fn eigr_from_card(card: &RawCard) -> Result<Eigrl, Vec<DeckError>> {
    const METHODS: [&str; 8] = ["LAN", "AHOU", "HOU", "MHOU", "GIV", "MGIV", "INV", "SINV"];
    let mut f = FieldReader::new(card);
    let sid = f.id(1, "SID");
    f.set_id(sid);
    f.keyword(2, "METHOD", &METHODS, None);
    let v1 = f.opt_real(3, "F1");
    let v2 = f.opt_real(4, "F2");
    f.opt_int(5, "NE");
    let nd = f.opt_count(6, "ND");
    if v2.is_none() && nd.is_none() {
        f.error(
            6,
            "ND",
            "give F2 or ND: with neither, EIGR asks for every root of the model, and paraflex extracts a subset of roots with Lanczos",
        );
    }
    if let (Some(a), Some(b)) = (v1, v2)
        && b <= a
    {
        f.error(
            4,
            "F2",
            format!("F2 = {b:e} must be greater than F1 = {a:e}"),
        );
    }
    let norm = f.choice(9, "NORM", &EigenNorm::KEYWORDS, Some(EigenNorm::Mass));
    f.opt_id(10, "G");
    f.opt_int(11, "C");
    let loc = f.loc();
    f.finish(11)?;
    Ok(Eigrl {
        sid,
        v1,
        v2,
        nd,
        shfscl: None,
        norm,
        loc,
    })
}

/// How a frequency card lists its frequencies.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub enum FreqKind {
    /// `FREQ SID F1 F2 …`: explicit list.
    List(Vec<f64>),
    /// `FREQ1 SID F1 DF NDF`: F1 + k·DF, k = 0 … NDF.
    Linear { f1: f64, df: f64, ndf: u32 },
    /// `FREQ2 SID F1 F2 NF`: NF logarithmic intervals from F1 to F2.
    Log { f1: f64, f2: f64, nf: u32 },
    /// `FREQ3 SID F1 F2 TYPE NEF CLUSTER`: NEF lines in each sub-range between F1, the
    /// natural frequencies inside (F1, F2) and F2, clustered towards the ends for CLUSTER > 1.
    Cluster {
        f1: f64,
        f2: f64,
        log: bool,
        nef: u32,
        cluster: f64,
    },
    /// `FREQ4 SID F1 F2 FSPD NFM`: NFM lines evenly spread over (1 ± FSPD)·f_n of each
    /// natural frequency f_n.
    Spread {
        f1: f64,
        f2: f64,
        fspd: f64,
        nfm: u32,
    },
    /// `FREQ5 SID F1 F2 FR1 FR2 …`: FRᵢ·f_n for each natural frequency f_n.
    Fractions { f1: f64, f2: f64, fr: Vec<f64> },
}

/// `FREQ`, `FREQ1` … `FREQ5` — excitation frequencies (Hz).
///
/// All cards with the same SID combine. FREQ3–FREQ5 place lines from the natural frequencies of a
/// modal frequency response (SOL 111): as in Nastran, a direct one (SOL 108) ignores them,
/// with a warning.
///
/// | card | fields 2 … | defaults |
/// |---|---|---|
/// | FREQ | SID F1 F2 F3 … | — |
/// | FREQ1 | SID F1 DF NDF | NDF = 1 |
/// | FREQ2 | SID F1 F2 NF | NF = 1; F1 > 0 |
/// | FREQ3 | SID F1 F2 TYPE NEF CLUSTER | F2 = F1, TYPE = LINEAR (or LOG, then F1 > 0), NEF = 10 (> 1), CLUSTER = 1.0 (> 0) |
/// | FREQ4 | SID F1 F2 FSPD NFM | F1 = 0, F2 = 1e20, FSPD = 0.1 (0 < FSPD < 1), NFM = 3 (an even NFM takes NFM + 1) |
/// | FREQ5 | SID F1 F2 FR1 FR2 … | F1 = 0, F2 = 1e20, FRᵢ > 0 (at least one) |
///
/// FREQ3: the break points are F1, the natural frequencies f_n with F1 < f_n < F2, and F2;
/// in each sub-range [a, b] the lines are f̂ = (â + b̂)/2 + (b̂ − â)/2 · |ξ|^(1/CLUSTER) sign ξ,
/// ξ = −1 + 2k/(NEF − 1), k = 0 … NEF − 1, with f̂ = f (LINEAR) or ln f (LOG).
/// FREQ4: f_n (1 − FSPD + 2 FSPD k/(NFM − 1)), k = 0 … NFM − 1 (f_n alone for NFM = 1).
/// FREQ4 and FREQ5 take every natural frequency and keep the lines within [F1, F2].
#[derive(Debug, Clone, PartialEq)]
pub struct Freq {
    pub sid: u32,
    pub kind: FreqKind,
    pub loc: Loc,
}

impl Freq {
    /// Read a `FREQ`, `FREQ1` or `FREQ2` card (`name` says which).
    pub fn from_card(card: &RawCard, name: &str) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let sid = f.id(1, "SID");
        f.set_id(sid);
        let len = f.len();
        let kind = match name {
            "FREQ1" => {
                let f1 = f.real_or(2, "F1", 0.0);
                let df = f.real(3, "DF");
                let ndf = f.opt_count(4, "NDF").unwrap_or(1);
                if df <= 0.0 && matches!(f.value(3), Value::Real(_)) {
                    f.error(3, "DF", format!("expected DF > 0, found {df:e}"));
                }
                FreqKind::Linear { f1, df, ndf }
            }
            "FREQ2" => {
                let f1 = f.real(2, "F1");
                let f2 = f.real(3, "F2");
                let nf = f.opt_count(4, "NF").unwrap_or(1);
                if !(f1 > 0.0 && f2 > f1)
                    && matches!((f.value(2), f.value(3)), (Value::Real(_), Value::Real(_)))
                {
                    f.card_error(format!(
                        "FREQ2 needs 0 < F1 < F2, found F1 = {f1:e}, F2 = {f2:e}"
                    ));
                }
                FreqKind::Log { f1, f2, nf }
            }
            "FREQ3" => freq3(&mut f),
            "FREQ4" => {
                let (f1, f2) = modal_range(&mut f);
                let fspd = f.real_or(4, "FSPD", 0.1);
                if !(fspd > 0.0 && fspd < 1.0) {
                    f.error(4, "FSPD", format!("expected 0 < FSPD < 1, found {fspd:e}"));
                }
                let nfm = f.opt_count(5, "NFM").unwrap_or(3);
                // an even count gets the natural frequency itself too
                let nfm = nfm + (1 - nfm % 2);
                FreqKind::Spread { f1, f2, fspd, nfm }
            }
            "FREQ5" => {
                let (f1, f2) = modal_range(&mut f);
                let fr = f.real_list(4, "FR");
                if fr.is_empty() {
                    f.card_error("no fraction FR1 … given");
                }
                if let Some(bad) = fr.iter().find(|&&r| r <= 0.0) {
                    f.card_error(format!("the fractions FRi must be > 0, found {bad:e}"));
                }
                FreqKind::Fractions { f1, f2, fr }
            }
            _ => {
                let list = f.real_list(2, "F");
                if list.is_empty() {
                    f.card_error("no frequency given");
                }
                FreqKind::List(list)
            }
        };
        let loc = f.loc();
        let last = match name {
            "FREQ" | "FREQ5" => len.max(1),
            "FREQ3" => 7,
            "FREQ4" => 5,
            _ => 4,
        };
        f.finish(last)?;
        Ok(Freq { sid, kind, loc })
    }

    /// Whether the card places its lines from natural frequencies (FREQ3, FREQ4, FREQ5).
    pub fn needs_modes(&self) -> bool {
        matches!(
            self.kind,
            FreqKind::Cluster { .. } | FreqKind::Spread { .. } | FreqKind::Fractions { .. }
        )
    }

    /// The card's name.
    pub fn card_name(&self) -> &'static str {
        match self.kind {
            FreqKind::List(_) => "FREQ",
            FreqKind::Linear { .. } => "FREQ1",
            FreqKind::Log { .. } => "FREQ2",
            FreqKind::Cluster { .. } => "FREQ3",
            FreqKind::Spread { .. } => "FREQ4",
            FreqKind::Fractions { .. } => "FREQ5",
        }
    }

    /// The frequencies this card lists (Hz); FREQ3–FREQ5 place them from `modes_hz`, the
    /// natural frequencies of the structure (ascending).
    pub fn frequencies(&self, modes_hz: &[f64]) -> Vec<f64> {
        let within = |f1: f64, f2: f64, lines: Vec<f64>| -> Vec<f64> {
            lines.into_iter().filter(|&x| x >= f1 && x <= f2).collect()
        };
        match &self.kind {
            FreqKind::Cluster {
                f1,
                f2,
                log,
                nef,
                cluster,
            } => cluster_lines(*f1, *f2, *log, *nef, *cluster, modes_hz),
            FreqKind::Spread { f1, f2, fspd, nfm } => {
                let steps = f64::from(nfm.saturating_sub(1).max(1));
                let lines = modes_hz.iter().flat_map(|&fnat| {
                    (0..*nfm).map(move |k| {
                        if *nfm == 1 {
                            fnat
                        } else {
                            fnat * (1.0 - fspd + 2.0 * fspd * f64::from(k) / steps)
                        }
                    })
                });
                within(*f1, *f2, lines.collect())
            }
            FreqKind::Fractions { f1, f2, fr } => {
                let lines = modes_hz
                    .iter()
                    .flat_map(|&fnat| fr.iter().map(move |r| r * fnat));
                within(*f1, *f2, lines.collect())
            }
            FreqKind::List(v) => v.clone(),
            FreqKind::Linear { f1, df, ndf } => {
                (0..=*ndf).map(|k| f1 + f64::from(k) * df).collect()
            }
            FreqKind::Log { f1, f2, nf } => {
                let d = (f2 / f1).ln() / f64::from(*nf);
                (0..=*nf).map(|k| f1 * (d * f64::from(k)).exp()).collect()
            }
        }
    }
}

/// FREQ4's and FREQ5's F1 (default 0) and F2 (default 1e20, > F1), fields 2 and 3.
fn modal_range(f: &mut FieldReader) -> (f64, f64) {
    let f1 = f.real_or(2, "F1", 0.0);
    let f2 = f.real_or(3, "F2", 1e20);
    if f1 < 0.0 {
        f.error(2, "F1", format!("expected F1 >= 0, found {f1:e}"));
    }
    if f2 <= f1 {
        f.card_error(format!("needs F2 > F1, found F1 = {f1:e}, F2 = {f2:e}"));
    }
    (f1, f2)
}

/// Reads FREQ3's fields 2–7.
fn freq3(f: &mut FieldReader) -> FreqKind {
    let f1 = f.real(2, "F1");
    let f2 = f.opt_real(3, "F2").unwrap_or(f1);
    let log = f.keyword(4, "TYPE", &["LINEAR", "LOG"], Some("LINEAR")) == "LOG";
    let nef = f.opt_count(5, "NEF").unwrap_or(10);
    let cluster = f.real_or(6, "CLUSTER", 1.0);
    if f1 < 0.0 || (log && f1 <= 0.0) {
        let bound = if log { "> 0 (TYPE = LOG)" } else { ">= 0" };
        f.error(2, "F1", format!("expected F1 {bound}, found {f1:e}"));
    }
    if f2 < f1 {
        f.card_error(format!("needs F2 >= F1, found F1 = {f1:e}, F2 = {f2:e}"));
    }
    if nef < 2 {
        f.error(5, "NEF", format!("expected NEF > 1, found {nef}"));
    }
    if cluster <= 0.0 {
        f.error(
            6,
            "CLUSTER",
            format!("expected CLUSTER > 0, found {cluster:e}"),
        );
    }
    FreqKind::Cluster {
        f1,
        f2,
        log,
        nef,
        cluster,
    }
}

/// FREQ3's lines: NEF per sub-range between F1, the natural frequencies strictly inside
/// (F1, F2) and F2, each sub-range spaced by the clustering rule of [`Freq`] (shared end
/// points appear once after the set's duplicates are removed).
fn cluster_lines(
    f1: f64,
    f2: f64,
    log: bool,
    nef: u32,
    cluster: f64,
    modes_hz: &[f64],
) -> Vec<f64> {
    let map = |x: f64| if log { x.ln() } else { x };
    let unmap = |x: f64| if log { x.exp() } else { x };
    let mut breaks = vec![f1];
    breaks.extend(modes_hz.iter().copied().filter(|&x| x > f1 && x < f2));
    breaks.push(f2);
    let steps = f64::from(nef.max(2) - 1);
    let mut lines = Vec::new();
    for pair in breaks.windows(2) {
        let (a, b) = (map(pair[0]), map(pair[1]));
        for k in 0..nef.max(2) {
            let xi = -1.0 + 2.0 * f64::from(k) / steps;
            let s = xi.abs().powf(1.0 / cluster) * xi.signum();
            lines.push(unmap(0.5 * (a + b) + 0.5 * (b - a) * s));
        }
    }
    // the end points exactly (no round-off through ln/exp)
    for (pair, chunk) in breaks.windows(2).zip(lines.chunks_mut(nef.max(2) as usize)) {
        chunk[0] = pair[0];
        *chunk.last_mut().expect("NEF >= 2") = pair[1];
    }
    lines
}

/// `TSTEP` — time step intervals.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | SID | int > 0 | required | set id |
/// | 3 | N1 | int > 0 | required | number of steps |
/// | 4 | DT1 | real > 0 | required | step size |
/// | 5 | NO1 | int > 0 | 1 | output every NO1 steps |
/// | cont. 3–5 | N2 DT2 NO2 … | | | further intervals |
#[derive(Debug, Clone, PartialEq)]
pub struct Tstep {
    pub sid: u32,
    /// (N, DT, NO) per interval.
    pub intervals: Vec<(u32, f64, u32)>,
    pub loc: Loc,
}

impl Tstep {
    /// Read a `TSTEP` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let sid = f.id(1, "SID");
        f.set_id(sid);
        let mut intervals = Vec::new();
        let len = f.len();
        let mut first = 2;
        while first <= len.max(2) {
            if first > 2 && (first..first + 3).all(|i| f.value(i).is_blank()) {
                first += 8;
                continue;
            }
            let n = f.count(first, "N");
            let dt = f.positive_real(first + 1, "DT");
            let no = f.opt_count(first + 2, "NO").unwrap_or(1);
            intervals.push((n, dt, no));
            first += 8;
        }
        let loc = f.loc();
        let mut last = 4;
        while last < len {
            last += 8;
        }
        f.finish(last)?;
        Ok(Tstep {
            sid,
            intervals,
            loc,
        })
    }
}

/// `TLOAD1`, `TLOAD2` — transient load: A · F(t − τ) with A from `DAREA` (or a static load set)
/// and F a table (TLOAD1) or a pulse (TLOAD2): with t̃ = t − T1 − τ,
/// F = t̃^B e^{C t̃} cos(2π F t̃ + P) for 0 ≤ t̃ ≤ T2 − T1 and 0 elsewhere.
///
/// TLOAD1:
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | SID | int > 0 | required | load set id |
/// | 3 | EXCITEID | int > 0 | required | DAREA, static load set (directly or through an LSEQ), or SPCD set (TYPE DISP/VELO/ACCE) |
/// | 4 | DELAY | real | 0.0 | time delay τ (a DELAY card id is not supported) |
/// | 5 | TYPE | `LOAD` / `DISP` / `VELO` / `ACCE` or 0–3 | LOAD | excitation type: an applied load, or the enforced displacement, velocity or acceleration of the DOFs of an SPCD set (EXCITEID; full-model SOL 109/112) |
/// | 6 | TID | int > 0 | required | TABLED1–TABLED4 or TABLEF id of F(t) |
/// | 7, 8 | US0 VS0 | real | 0.0 | enforced-motion initial values (kept, unused) |
///
/// TLOAD2 (fields 2–5 as TLOAD1):
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 6 | T1 | real ≥ 0 | 0.0 | start of the pulse |
/// | 7 | T2 | real > T1 | required | end of the pulse |
/// | 8 | F | real ≥ 0 | 0.0 | frequency (cycles per unit time) |
/// | 9 | P | real | 0.0 | phase (degrees) |
/// | cont. 2, 3 | C B | real; real ≥ 0 | 0.0 | exponential coefficient and growth exponent |
/// | cont. 4, 5 | US0 VS0 | real | 0.0 | enforced-motion initial values (kept, unused) |
#[derive(Debug, Clone, PartialEq)]
pub struct Tload {
    pub sid: u32,
    pub excite_id: u32,
    pub delay: f64,
    pub kind: ExcitationKind,
    pub function: TloadFunction,
    pub loc: Loc,
}

/// What multiplies a TLOAD's excitation.
#[derive(Debug, Clone, PartialEq)]
pub enum TloadFunction {
    /// TLOAD1: the table TID.
    Table(u32),
    /// TLOAD2.
    Pulse(Pulse),
}

impl TloadFunction {
    /// The card this function comes from.
    pub fn card(&self) -> &'static str {
        match self {
            TloadFunction::Table(_) => "TLOAD1",
            TloadFunction::Pulse(_) => "TLOAD2",
        }
    }
}

/// What a dynamic load's EXCITEID excites (its TYPE field).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ExcitationKind {
    /// `LOAD` / 0: an applied load (DAREA or a static load set).
    Load,
    /// `DISP` / 1: an enforced displacement (EXCITEID an SPCD set).
    Displacement,
    /// `VELO` / 2: an enforced velocity (EXCITEID an SPCD set).
    Velocity,
    /// `ACCE` / 3: an enforced acceleration (EXCITEID an SPCD set).
    Acceleration,
}

impl ExcitationKind {
    /// The TYPE keyword.
    pub fn name(self) -> &'static str {
        match self {
            ExcitationKind::Load => "LOAD",
            ExcitationKind::Displacement => "DISP",
            ExcitationKind::Velocity => "VELO",
            ExcitationKind::Acceleration => "ACCE",
        }
    }
}

/// Read an excitation TYPE field: an integer 0–3 or a keyword, which Nastran matches by its
/// first letters (`L`, `LO`, `LOA`, `LOAD`; `D` … `DISP`; `V` … `VELO`; `A` … `ACCE`).
fn excitation_type(f: &mut FieldReader, i: usize) -> ExcitationKind {
    let by_prefix = |t: &str| {
        let t = t.to_ascii_uppercase();
        [
            ("LOAD", ExcitationKind::Load),
            ("DISP", ExcitationKind::Displacement),
            ("VELO", ExcitationKind::Velocity),
            ("ACCE", ExcitationKind::Acceleration),
        ]
        .into_iter()
        .find(|(name, _)| !t.is_empty() && name.starts_with(t.as_str()))
        .map(|(_, kind)| kind)
    };
    let kind = match f.value(i) {
        Value::Blank | Value::Int(0) => Some(ExcitationKind::Load),
        Value::Int(1) => Some(ExcitationKind::Displacement),
        Value::Int(2) => Some(ExcitationKind::Velocity),
        Value::Int(3) => Some(ExcitationKind::Acceleration),
        Value::Text(t) => by_prefix(t),
        _ => None,
    };
    kind.unwrap_or_else(|| {
        let found = f.value(i).describe();
        f.error(
            i,
            "TYPE",
            format!("expected LOAD, DISP, VELO, ACCE or 0-3, found {found}"),
        );
        ExcitationKind::Load
    })
}

/// Read a DELAY field: a real delay, or an error for a DELAY card reference.
fn delay(f: &mut FieldReader, i: usize) -> f64 {
    match f.value(i) {
        Value::Int(_) => {
            f.error(
                i,
                "DELAY",
                "DELAY card references are not supported; give the delay as a real",
            );
            0.0
        }
        _ => f.real_or(i, "DELAY", 0.0),
    }
}

impl Tload {
    /// Read a `TLOAD1` card.
    pub fn tload1(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let (sid, excite_id, delay, kind) = tload_head(&mut f);
        let tid = f.id(5, "TID");
        f.opt_real(6, "US0");
        f.opt_real(7, "VS0");
        let loc = f.loc();
        f.finish(7)?;
        Ok(Tload {
            sid,
            excite_id,
            delay,
            kind,
            function: TloadFunction::Table(tid),
            loc,
        })
    }

    /// Read a `TLOAD2` card.
    pub fn tload2(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let (sid, excite_id, delay, kind) = tload_head(&mut f);
        let start = f.real_or(5, "T1", 0.0);
        let end = f.real(6, "T2");
        if start < 0.0 {
            f.error(5, "T1", format!("T1 must be ≥ 0, found {start:e}"));
        }
        if !(end > start) {
            f.error(6, "T2", format!("T2 = {end:e} must exceed T1 = {start:e}"));
        }
        let frequency = f.real_or(7, "F", 0.0);
        if frequency < 0.0 {
            f.error(7, "F", format!("F must be ≥ 0, found {frequency:e}"));
        }
        let phase_deg = f.real_or(8, "P", 0.0);
        let exponential = f.real_or(9, "C", 0.0);
        let power = f.real_or(10, "B", 0.0);
        if power < 0.0 {
            f.error(10, "B", format!("B must be ≥ 0, found {power:e}"));
        }
        f.opt_real(11, "US0");
        f.opt_real(12, "VS0");
        let loc = f.loc();
        f.finish(12)?;
        Ok(Tload {
            sid,
            excite_id,
            delay,
            kind,
            function: TloadFunction::Pulse(Pulse {
                start,
                end,
                frequency,
                phase_deg,
                exponential,
                power,
            }),
            loc,
        })
    }
}

/// SID, EXCITEID, DELAY and TYPE of a TLOAD1 or TLOAD2.
fn tload_head(f: &mut FieldReader) -> (u32, u32, f64, ExcitationKind) {
    let sid = f.id(1, "SID");
    f.set_id(sid);
    let excite_id = f.id(2, "EXCITEID");
    let delay = delay(f, 3);
    let kind = excitation_type(f, 4);
    (sid, excite_id, delay, kind)
}

/// `RLOAD1`, `RLOAD2` — frequency-dependent load A · P(f) · e^{i(θ − 2πfτ)}, A from `DAREA`:
/// P = C(f) + i D(f) (RLOAD1) or P = B(f) e^{i φ(f)} with φ in degrees (RLOAD2).
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | SID | int > 0 | required | load set id |
/// | 3 | EXCITEID | int > 0 | required | DAREA, static load set (directly or through an LSEQ), or SPCD set (TYPE DISP/VELO/ACCE) |
/// | 4 | DELAY | real | 0.0 | time delay τ |
/// | 5 | DPHASE | real | 0.0 | phase θ in degrees (a DPHASE card id is not supported) |
/// | 6 | TC (RLOAD1) / TB (RLOAD2) | int ≥ 0 or real / int > 0 or real | 0 / required | table id of C(f) (0 = none) / of B(f); a real is a constant value (newer MSC Nastran) |
/// | 7 | TD (RLOAD1) / TP (RLOAD2) | int ≥ 0 or real | 0 | table id of D(f) / of φ(f) in degrees; 0 = none; a real is a constant value |
/// | 8 | TYPE | `LOAD` / `DISP` / `VELO` / `ACCE` or 0–3 | LOAD | excitation type: an applied load, or the enforced displacement, velocity or acceleration of the DOFs of an SPCD set (EXCITEID) |
///
/// Tables are TABLED1–TABLED4 or TABLEF.
#[derive(Debug, Clone, PartialEq)]
pub struct Rload {
    pub sid: u32,
    pub excite_id: u32,
    pub delay: f64,
    pub phase_deg: f64,
    pub tables: RloadTables,
    pub kind: ExcitationKind,
    pub loc: Loc,
}

/// One function of an RLOAD's P(f): a table id (0: none, the function is zero) or a constant.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum RloadValue {
    Table(u32),
    Constant(f64),
}

impl RloadValue {
    /// True when the function is zero at every frequency (table id 0 or the constant 0).
    pub fn is_zero(self) -> bool {
        matches!(self, RloadValue::Table(0)) || self == RloadValue::Constant(0.0)
    }
}

/// The functions of an RLOAD's P(f).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum RloadTables {
    /// RLOAD1: C(f) + i D(f).
    Rectangular { tc: RloadValue, td: RloadValue },
    /// RLOAD2: B(f) e^{i φ(f)}, φ in degrees.
    Polar { tb: RloadValue, tp: RloadValue },
}

impl RloadTables {
    /// The card these tables come from.
    pub fn card(&self) -> &'static str {
        match self {
            RloadTables::Rectangular { .. } => "RLOAD1",
            RloadTables::Polar { .. } => "RLOAD2",
        }
    }

    /// (field name, value) of the two functions.
    fn pairs(&self) -> [(&'static str, RloadValue); 2] {
        match *self {
            RloadTables::Rectangular { tc, td } => [("TC", tc), ("TD", td)],
            RloadTables::Polar { tb, tp } => [("TB", tb), ("TP", tp)],
        }
    }

    /// (field name, table id) of each table given (id ≠ 0).
    pub fn named(&self) -> Vec<(&'static str, u32)> {
        self.pairs()
            .into_iter()
            .filter_map(|(name, v)| match v {
                RloadValue::Table(id) if id != 0 => Some((name, id)),
                _ => None,
            })
            .collect()
    }

    /// True when RLOAD1's C and D are both zero (no table, or constants 0).
    pub fn is_zero(&self) -> bool {
        matches!(self, RloadTables::Rectangular { .. })
            && self.pairs().iter().all(|(_, v)| v.is_zero())
    }
}

/// An RLOAD table field: a table id (int ≥ 0, blank = 0) or a real constant.
fn rload_value(f: &mut FieldReader, i: usize, name: &str) -> RloadValue {
    match f.value(i) {
        Value::Real(_) => RloadValue::Constant(f.real(i, name)),
        _ => RloadValue::Table(f.id0_or(i, name, 0)),
    }
}

impl Rload {
    /// Read an `RLOAD1` card.
    pub fn rload1(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        Self::read(card, |f| {
            let tc = rload_value(f, 5, "TC");
            let td = rload_value(f, 6, "TD");
            if tc == RloadValue::Table(0) && td == RloadValue::Table(0) {
                f.card_error("give TC or TD (a table of the load's frequency dependence)");
            }
            RloadTables::Rectangular { tc, td }
        })
    }

    /// Read an `RLOAD2` card.
    pub fn rload2(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        Self::read(card, |f| RloadTables::Polar {
            tb: match f.value(5) {
                Value::Real(_) => RloadValue::Constant(f.real(5, "TB")),
                _ => RloadValue::Table(f.id(5, "TB")),
            },
            tp: rload_value(f, 6, "TP"),
        })
    }

    fn read(
        card: &RawCard,
        tables: impl FnOnce(&mut FieldReader) -> RloadTables,
    ) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let sid = f.id(1, "SID");
        f.set_id(sid);
        let excite_id = f.id(2, "EXCITEID");
        let delay = delay(&mut f, 3);
        let phase_deg = match f.value(4) {
            Value::Int(_) => {
                f.error(
                    4,
                    "DPHASE",
                    "DPHASE card references are not supported; give the phase as a real",
                );
                0.0
            }
            _ => f.real_or(4, "DPHASE", 0.0),
        };
        let tables = tables(&mut f);
        let kind = excitation_type(&mut f, 7);
        let loc = f.loc();
        f.finish(7)?;
        Ok(Rload {
            sid,
            excite_id,
            delay,
            phase_deg,
            tables,
            kind,
            loc,
        })
    }
}

/// `LSEQ` — a static load set as the excitation of dynamic loads: with case control
/// `LOADSET = SID`, a TLOAD1/TLOAD2/RLOAD1/RLOAD2 whose EXCITEID is this card's EXCITEID takes
/// the load vector of static load set LID (FORCE, MOMENT, LOAD, PLOAD4, GRAV, …).
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | SID | int > 0 | required | the set LOADSET selects |
/// | 3 | EXCITEID | int > 0 | required | the id dynamic loads reference |
/// | 4 | LID | int > 0 | required | static load set |
/// | 5 | TID | int ≥ 0 | blank | thermal load set (refused: thermal loads are static, SOL 101 only) |
#[derive(Debug, Clone, PartialEq)]
pub struct Lseq {
    pub sid: u32,
    pub excite_id: u32,
    pub lid: u32,
    pub loc: Loc,
}

impl Lseq {
    /// Read an `LSEQ` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let sid = f.id(1, "SID");
        f.set_id(sid);
        let excite_id = f.id(2, "EXCITEID");
        let lid = f.id(3, "LID");
        if f.id0_or(4, "TID", 0) != 0 {
            f.error(
                4,
                "TID",
                "thermal load sets as dynamic excitations are not supported (paraflex applies thermal loads in SOL 101 only)",
            );
        }
        let loc = f.loc();
        f.finish(4)?;
        Ok(Lseq {
            sid,
            excite_id,
            lid,
            loc,
        })
    }
}

/// `DAREA` — load scale factor at a grid component (one entry per grid on the card).
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | SID | int > 0 | required | set id |
/// | 3, 4, 5 | P1 C1 A1 | int, component, real | required | grid, component, scale |
/// | 6, 7, 8 | P2 C2 A2 | | blank | optional second entry |
#[derive(Debug, Clone, PartialEq)]
pub struct Darea {
    pub sid: u32,
    pub grid: u32,
    pub components: Dofs,
    pub scale: f64,
    pub loc: Loc,
}

impl Darea {
    /// Read a `DAREA` card (one or two entries).
    pub fn from_card(card: &RawCard) -> Result<Vec<Self>, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let sid = f.id(1, "SID");
        f.set_id(sid);
        let loc = f.loc();
        let out = f
            .grid_component_values(["P", "C", "A"], None)
            .into_iter()
            .map(|(grid, components, scale)| Darea {
                sid,
                grid,
                components,
                scale,
                loc: loc.clone(),
            })
            .collect();
        f.finish(7)?;
        Ok(out)
    }
}

/// `TIC` — transient initial condition of one grid component, selected by case control
/// `IC = SID`. On a pROM (`ROM =`) the grid component must be an input DOF of the pROM; the
/// reduced initial state is then the static shape with these input displacements (see
/// "Initial conditions" in docs/dynamics.md).
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | SID | int > 0 | required | set id |
/// | 3 | G | int > 0 | required | grid |
/// | 4 | C | one component 1–6 | required | component (grid's displacement frame) |
/// | 5 | U0 | real | 0.0 | initial displacement |
/// | 6 | V0 | real | 0.0 | initial velocity |
#[derive(Debug, Clone, PartialEq)]
pub struct Tic {
    pub sid: u32,
    pub grid: u32,
    /// Component 1–6.
    pub component: usize,
    pub u0: f64,
    pub v0: f64,
    pub loc: Loc,
}

impl Tic {
    /// Read a `TIC` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let sid = f.id(1, "SID");
        f.set_id(sid);
        let grid = f.id(2, "G");
        let c = f.int(3, "C");
        if !(1..=6).contains(&c) {
            f.error(3, "C", format!("expected one component 1-6, found {c}"));
        }
        let u0 = f.real_or(4, "U0", 0.0);
        let v0 = f.real_or(5, "V0", 0.0);
        let loc = f.loc();
        f.finish(5)?;
        Ok(Tic {
            sid,
            grid,
            component: c.clamp(1, 6) as usize,
            u0,
            v0,
            loc,
        })
    }
}

/// `TABLED1`, `TABLED2`, `TABLED3`, `TABLEM1`, `TABLEM2`, `TABLEM3` — tabular function y(x) with linear interpolation (the end
/// values held outside the table; a jump is two points at one x, where y is their mean).
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | TID | int > 0 | required | table id |
/// | 3 | XAXIS (TABLED1, TABLEM1) / X1 (TABLED2, TABLED3, TABLEM2, TABLEM3) | `LINEAR` / real | LINEAR / 0.0 | TABLED1: only LINEAR supported; TABLED2: y = T(x − X1); TABLED3: y = T((x − X1)/X2) |
/// | 4 | YAXIS (TABLED1, TABLEM1) / X2 (TABLED3, TABLEM3) | `LINEAR` / real ≠ 0 | LINEAR / required | TABLED1: only LINEAR supported |
/// | 5 | EXTRAP (TABLEM1, Simcenter) | int | blank | kept, not used (material tables are not evaluated, see MATT1) |
/// | cont. | x1 y1 x2 y2 … `ENDT` | real pairs | ≥ 2 points | x all increasing or all decreasing; `SKIP SKIP` drops a pair |
#[derive(Debug, Clone, PartialEq)]
pub struct Tabled {
    pub id: u32,
    /// TABLED1, TABLED2, TABLED3, TABLEM1, TABLEM2 or TABLEM3.
    pub card: &'static str,
    /// The points with their abscissae mapped to x (X1 + X2 · xᵢ; X1 = 0, X2 = 1 for TABLED1).
    pub points: Vec<(f64, f64)>,
    pub loc: Loc,
}

impl Tabled {
    /// Read a `TABLED1`, `TABLED2`, `TABLED3` or a `TABLEM1`–`TABLEM3` card (`name` says which;
    /// a TABLEMi has the layout of the TABLEDi).
    pub fn from_card(card: &RawCard, name: &'static str) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let id = f.id(1, "TID");
        f.set_id(id);
        let (shift, scale) = match name {
            "TABLED1" | "TABLEM1" => {
                for (i, field) in [(2, "XAXIS"), (3, "YAXIS")] {
                    f.keyword(i, field, &["LINEAR"], Some("LINEAR"));
                }
                if name == "TABLEM1" {
                    f.opt_int(4, "EXTRAP");
                }
                (0.0, 1.0)
            }
            "TABLED2" | "TABLEM2" => (f.real_or(2, "X1", 0.0), 1.0),
            _ => {
                let shift = f.real_or(2, "X1", 0.0);
                let scale = f.real(3, "X2");
                if scale == 0.0 {
                    f.error(3, "X2", "X2 must not be zero");
                }
                (shift, scale)
            }
        };
        let mut points: Vec<(f64, f64)> = Vec::new();
        let len = f.len();
        let ended = table_entries(&mut f, |f, i| {
            let x = f.real(i, "x");
            let y = f.real(i + 1, "y");
            points.push((shift + scale * x, y));
            2
        });
        if !ended {
            f.card_error("the table does not end with ENDT");
        }
        if points.len() < 2 {
            f.card_error("a table needs at least two points");
        }
        if let Err(e) = crate::dynamics::table::Table::new(&points) {
            f.card_error(e.to_string());
        }
        let loc = f.loc();
        f.finish(len)?;
        Ok(Tabled {
            id,
            card: name,
            points,
            loc,
        })
    }
}

/// `TABDMP1` — modal damping as a function of the natural frequency, selected by `SDAMPING`:
/// linear between the points, extrapolated linearly from the two end points (as Nastran), a
/// jump's mean at the jump.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | TID | int > 0 | required | table id |
/// | 3 | TYPE | `G`, `CRIT`, `Q` | G | units: structural damping g (ζ = g/2), fraction of critical ζ, or quality factor Q (ζ = 1/(2Q)) |
/// | cont. | f1 g1 f2 g2 … `ENDT` | real pairs | ≥ 2 points | natural frequency (Hz) and damping; f all increasing or all decreasing; `SKIP SKIP` drops a pair |
#[derive(Debug, Clone, PartialEq)]
pub struct Tabdmp1 {
    pub id: u32,
    pub units: ModalDampingUnits,
    /// (f Hz, damping in `units`).
    pub points: Vec<(f64, f64)>,
    pub loc: Loc,
}

/// The units of a TABDMP1's damping values.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ModalDampingUnits {
    /// Structural damping g = 2ζ.
    G,
    /// Fraction of critical damping ζ.
    Crit,
    /// Quality factor Q = 1/(2ζ).
    Q,
}

impl ModalDampingUnits {
    /// The fraction of critical damping of `value` in these units.
    pub fn critical_ratio(self, value: f64) -> f64 {
        match self {
            ModalDampingUnits::G => 0.5 * value,
            ModalDampingUnits::Crit => value,
            ModalDampingUnits::Q => 0.5 / value,
        }
    }
}

impl Tabdmp1 {
    /// Read a `TABDMP1` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let id = f.id(1, "TID");
        f.set_id(id);
        let units = match f.keyword(2, "TYPE", &["G", "CRIT", "Q"], Some("G")) {
            "CRIT" => ModalDampingUnits::Crit,
            "Q" => ModalDampingUnits::Q,
            _ => ModalDampingUnits::G,
        };
        let mut points: Vec<(f64, f64)> = Vec::new();
        let len = f.len();
        let ended = table_entries(&mut f, |f, i| {
            let x = f.real(i, "f");
            let y = f.real(i + 1, "g");
            points.push((x, y));
            2
        });
        if !ended {
            f.card_error("the table does not end with ENDT");
        }
        if points.len() < 2 {
            f.card_error("a table needs at least two points");
        }
        if points.iter().any(|&(x, _)| x < 0.0) {
            f.card_error("the frequencies of a TABDMP1 must be >= 0");
        }
        if units == ModalDampingUnits::Q && points.iter().any(|&(_, q)| q <= 0.0) {
            f.card_error("TYPE = Q needs quality factors > 0");
        }
        if let Err(e) = crate::dynamics::table::Table::new(&points) {
            f.card_error(e.to_string());
        }
        let loc = f.loc();
        f.finish(len)?;
        Ok(Tabdmp1 {
            id,
            units,
            points,
            loc,
        })
    }
}

/// `TABLED4`, `TABLEM4` — power series y = Σᵢ aᵢ ((x − X1)/X2)ⁱ, x clamped to [X3, X4].
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | TID | int > 0 | required | table id (shares the id space of TABLED1) |
/// | 3 | X1 | real | 0.0 | shift |
/// | 4 | X2 | real ≠ 0 | required | scale |
/// | 5, 6 | X3 X4 | real, X3 < X4 | required | the range x is clamped to |
/// | cont. | A0 A1 … `ENDT` | real | ≥ 1 | coefficients |
#[derive(Debug, Clone, PartialEq)]
pub struct Tabled4 {
    pub id: u32,
    pub shift: f64,
    pub scale: f64,
    pub range: (f64, f64),
    pub coefficients: Vec<f64>,
    pub loc: Loc,
}

impl Tabled4 {
    /// Read a `TABLED4` or `TABLEM4` card (same layout).
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let id = f.id(1, "TID");
        f.set_id(id);
        let shift = f.real_or(2, "X1", 0.0);
        let scale = f.real(3, "X2");
        if scale == 0.0 {
            f.error(3, "X2", "X2 must not be zero");
        }
        let (low, high) = (f.real(4, "X3"), f.real(5, "X4"));
        if !(low < high) {
            f.error(5, "X4", format!("X4 = {high:e} must exceed X3 = {low:e}"));
        }
        let mut coefficients = Vec::new();
        let len = f.len();
        let ended = table_entries(&mut f, |f, i| {
            coefficients.push(f.real(i, "A"));
            1
        });
        if !ended {
            f.card_error("the table does not end with ENDT");
        }
        if coefficients.is_empty() {
            f.card_error("a power series needs at least one coefficient");
        }
        let loc = f.loc();
        f.finish(len)?;
        Ok(Tabled4 {
            id,
            shift,
            scale,
            range: (low, high),
            coefficients,
            loc,
        })
    }
}

/// Walk a table's entries from field 9 (the first continuation) to `ENDT`, skipping `SKIP`
/// pairs; `read(f, i)` reads the entry at field i and returns how many fields it took. Returns
/// whether `ENDT` was found.
pub(super) fn table_entries(
    f: &mut FieldReader,
    mut read: impl FnMut(&mut FieldReader, usize) -> usize,
) -> bool {
    let len = f.len();
    let mut i = 9;
    while i <= len {
        if matches!(f.value(i), Value::Text(t) if t.eq_ignore_ascii_case("ENDT")) {
            return true;
        }
        if matches!(f.value(i), Value::Text(t) if t.eq_ignore_ascii_case("SKIP")) {
            i += 2;
            continue;
        }
        i += read(f, i);
    }
    false
}

/// `DLOAD` — linear combination of dynamic load sets (TLOAD1 or RLOAD1): S · Σ Si · (set Li).
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | SID | int > 0 | required | new set id |
/// | 3 | S | real | required | overall scale |
/// | 4, 5, … | S1 L1 S2 L2 … | real, int > 0 | ≥ 1 pair | scale and TLOAD1/RLOAD1 set id |
#[derive(Debug, Clone, PartialEq)]
pub struct Dload {
    pub sid: u32,
    pub scale: f64,
    pub terms: Vec<(f64, u32)>,
    pub loc: Loc,
}

impl Dload {
    /// Read a `DLOAD` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let (sid, scale, terms, loc) = combination(card)?;
        Ok(Dload {
            sid,
            scale,
            terms,
            loc,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::deck::cards::geometry::tests::raw;
    use crate::deck::fields::card_from_line;

    /// With neither V2 nor ND, EIGRL asks for the lowest root (above V1), as Nastran does.
    #[test]
    fn eigrl_without_v2_and_nd_finds_the_lowest_root() {
        let e = Eigrl::from_card(&raw("EIGRL", &["1", "0."])).expect("valid");
        assert_eq!((e.v1, e.v2, e.nd), (Some(0.0), None, Some(1)));
        let e = Eigrl::from_card(&raw("EIGRL", &["1", "", "100."])).expect("valid");
        assert_eq!((e.v2, e.nd), (Some(100.0), None));
    }

    /// EIGR reads as the EIGRL of the same range and count whatever its method; asking for
    /// every root (neither F2 nor ND) and NORM = POINT are refused at their fields.
    #[test]
    fn eigr_reads_as_the_eigrl_of_its_range() {
        let e = eigr_from_card(&card_from_line("EIGR,2,MGIV,0.,200.")).expect("valid");
        assert_eq!((e.sid, e.v1, e.v2, e.nd), (2, Some(0.0), Some(200.0), None));
        let e = eigr_from_card(&card_from_line("EIGR,301,LAN,,,,3,,,MAX")).expect("valid");
        assert_eq!((e.v2, e.nd, e.norm), (None, Some(3), EigenNorm::Max));
        let m = messages(eigr_from_card(&card_from_line("EIGR,3,AHOU,0.")));
        assert!(m.contains("field 7 (ND): give F2 or ND"), "{m}");
        let m = messages(eigr_from_card(&card_from_line(
            "EIGR,4,LAN,,,,3,,,POINT,7,1",
        )));
        assert!(
            m.contains("(NORM): expected one of MASS, MAX, found 'POINT'"),
            "{m}"
        );
        let m = messages(eigr_from_card(&card_from_line("EIGR,5,QR,,,,3")));
        assert!(m.contains("field 3 (METHOD)"), "{m}");
    }

    fn messages(r: Result<impl std::fmt::Debug, Vec<DeckError>>) -> String {
        let errors = r.expect_err("the card is refused");
        errors
            .iter()
            .map(|e| e.to_string())
            .collect::<Vec<_>>()
            .join("\n")
    }

    /// TABLED2 shifts and TABLED3 shifts and scales the abscissae (a negative X2 reverses
    /// them); the points are stored in x.
    #[test]
    fn tabled2_and_tabled3_map_their_abscissae_to_x() {
        let t = Tabled::from_card(
            &card_from_line("TABLED2,5,1.,,,,,,,0.,1.,2.,3.,ENDT"),
            "TABLED2",
        )
        .unwrap();
        assert_eq!(t.points, vec![(1.0, 1.0), (3.0, 3.0)]);
        let t = Tabled::from_card(
            &card_from_line("TABLED3,6,10.,-2.,,,,,,0.,1.,1.,3.,ENDT"),
            "TABLED3",
        )
        .unwrap();
        assert_eq!(t.points, vec![(10.0, 1.0), (8.0, 3.0)]);
        let table = crate::dynamics::table::Table::new(&t.points).unwrap();
        assert_eq!(table.value(9.0), 2.0);
        let m = messages(Tabled::from_card(
            &card_from_line("TABLED3,6,10.,0.,,,,,,0.,1.,1.,3.,ENDT"),
            "TABLED3",
        ));
        assert!(m.contains("X2 must not be zero"), "{m}");
        let m = messages(Tabled::from_card(
            &card_from_line("TABLED1,7,,,,,,,,0.,1.,2.,3.,1.,0.,ENDT"),
            "TABLED1",
        ));
        assert!(m.contains("monotonic"), "{m}");
    }

    #[test]
    fn tabled4_reads_its_power_series_and_refuses_an_empty_range() {
        let t =
            Tabled4::from_card(&card_from_line("TABLED4,8,1.,2.,0.,5.,,,,1.,2.,-1.,ENDT")).unwrap();
        assert_eq!(
            (t.shift, t.scale, t.range, t.coefficients),
            (1.0, 2.0, (0.0, 5.0), vec![1.0, 2.0, -1.0])
        );
        let m = messages(Tabled4::from_card(&card_from_line(
            "TABLED4,8,1.,0.,5.,5.,,,,1.,ENDT",
        )));
        assert!(
            m.contains("X2 must not be zero") && m.contains("must exceed X3"),
            "{m}"
        );
        let m = messages(Tabled4::from_card(&card_from_line(
            "TABLED4,8,1.,2.,0.,5.,,,,1.",
        )));
        assert!(m.contains("ENDT"), "{m}");
    }

    #[test]
    fn tload2_reads_its_pulse_and_refuses_an_empty_one() {
        let t = Tload::tload2(&card_from_line("TLOAD2,7,8,0.5,,0.1,0.3,50.,90.,-10.,1.5")).unwrap();
        assert_eq!((t.sid, t.excite_id, t.delay), (7, 8, 0.5));
        assert_eq!(
            t.function,
            TloadFunction::Pulse(Pulse {
                start: 0.1,
                end: 0.3,
                frequency: 50.0,
                phase_deg: 90.0,
                exponential: -10.0,
                power: 1.5,
            })
        );
        let m = messages(Tload::tload2(&card_from_line(
            "TLOAD2,7,8,,,0.3,0.3,,,,-1.",
        )));
        assert!(
            m.contains("must exceed T1") && m.contains("B must be"),
            "{m}"
        );
    }

    #[test]
    fn rload2_needs_its_amplitude_table() {
        let r = Rload::rload2(&card_from_line("RLOAD2,7,8,,30.,20,21")).unwrap();
        assert_eq!(
            r.tables,
            RloadTables::Polar {
                tb: RloadValue::Table(20),
                tp: RloadValue::Table(21)
            }
        );
        assert_eq!(r.tables.card(), "RLOAD2");
        let m = messages(Rload::rload2(&card_from_line("RLOAD2,7,8,,30.,,21")));
        assert!(m.contains("TB"), "{m}");
    }
}
