//! Typed values of card fields that the model keeps and the solver reads: force or moment,
//! sensor quantity, what a PMPAR scales, shell material orientation and corner thicknesses,
//! scalar-spring ends, CSV columns, multibody joint types, MSENSOR kinds and FMBSTART.
//! The deck reader builds them while parsing the cards; the model and the solver read them. A
//! leaf module: it uses no other paraflex module, so `deck` and every later module share one
//! vocabulary without a backwards edge. The range of the `EKF` card's REDIAG tolerance
//! ([`valid_rediagonalization_tolerance`]) is here too: checked where the card is read and where
//! the estimator is set up, both against this one rule; so is its PREDICT choice ([`Prediction`],
//! whose numbers the estimator adds).

mod dofs;

pub use dofs::Dofs;

/// The time discretization of the augmented EKF's prediction (thesis eq. 8.22; `EKF` field
/// PREDICT). Both are one solve with an effective matrix S = M + h C + h² K per step
/// (`dynamics::velocity_form`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Prediction {
    /// BDF1, as the thesis (eq. 8.10–8.13, 8.22; h = Δt): exact on data made by BDF1 on the
    /// same pROM, but it damps a mode of frequency ω by ζ ≈ ω Δt / 2, an error the default
    /// process noise of q and q̇ (ε) does not cover on data from elsewhere.
    Bdf1,
    /// The trapezoidal rule (Newmark's average acceleration; h = Δt/2): no numerical damping,
    /// second order. The default: it estimates from data the filter did not make (the exact
    /// response of the pROM) within the thesis's bounds with the default process noise.
    #[default]
    Trapezoidal,
}

impl Prediction {
    /// The name the `EKF` card's PREDICT field gives it.
    pub fn card_name(self) -> &'static str {
        match self {
            Prediction::Bdf1 => "BDF1",
            Prediction::Trapezoidal => "TRAP",
        }
    }
}

/// Whether a `FORCE` / `MOMENT` card is a force or a moment.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub enum ForceKind {
    /// `FORCE`.
    Force,
    /// `MOMENT`.
    Moment,
}

/// What a `SENSOR` measures.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub enum SensorKind {
    Disp,
    Vel,
    Accel,
    Strain,
}

/// Material orientation of a shell: angle from the G1–G2 side, or a coordinate system.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub enum ShellOrientation {
    /// THETA in degrees (real field).
    Theta(f64),
    /// MCID: the projection of this system's x axis gives the material x axis (integer field).
    Mcid(u32),
}

/// Corner thicknesses of a shell (continuation: TFLAG, T1 … Tn).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct CornerThickness {
    /// TFLAG = 1: the Ti are ratios of the property thickness; 0: actual thicknesses.
    pub relative: bool,
    /// Ti per corner; `None` = the property thickness (or ratio 1.0).
    pub t: [Option<f64>; 4],
}

/// One end of a scalar spring: a grid and a component, or ground.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub struct SpringEnd {
    /// Grid id, or `None` for ground.
    pub grid: Option<u32>,
    /// Component 1–6 (0 for ground).
    pub component: u8,
}

/// A CSV column selected by index or header name.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub enum Column {
    /// 1-based index.
    Index(usize),
    /// Header name.
    Name(String),
}

/// What a `PMPAR` parameter scales.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub enum PmparKind {
    /// Young's modulus of a MAT1.
    E,
    /// Density of a MAT1.
    Rho,
    /// Poisson's ratio of a MAT1.
    Nu,
    /// Angle-ply angle of a PCOMP (degrees).
    Theta,
    /// Ply thickness of a PCOMP.
    Tply,
    /// Stiffness of a PELAS.
    K,
    /// Mass of a CONM2.
    Mass,
}

impl PmparKind {
    /// Every kind with its keyword as written in decks.
    pub const ALL: [(&'static str, PmparKind); 7] = [
        ("E", PmparKind::E),
        ("RHO", PmparKind::Rho),
        ("NU", PmparKind::Nu),
        ("THETA", PmparKind::Theta),
        ("TPLY", PmparKind::Tply),
        ("K", PmparKind::K),
        ("MASS", PmparKind::Mass),
    ];

    /// The card REFID points at.
    pub fn target_card(self) -> &'static str {
        match self {
            PmparKind::E | PmparKind::Rho | PmparKind::Nu => "MAT1",
            PmparKind::Theta | PmparKind::Tply => "PCOMP",
            PmparKind::K => "PELAS",
            PmparKind::Mass => "CONM2",
        }
    }

    /// The keyword as written in decks.
    pub fn name(self) -> &'static str {
        Self::ALL
            .iter()
            .find(|(_, k)| *k == self)
            .map_or("?", |(n, _)| n)
    }
}

/// A `JOINT` type (DESIGN.md §11).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub enum JointType {
    /// `REV`: revolute about N.
    Revolute,
    /// `FIX`: bracket.
    Fixed,
    /// `SPH`: spherical.
    Spherical,
    /// `PRIS`: prismatic along N.
    Prismatic,
    /// `CYL`: cylindrical along N.
    Cylindrical,
    /// `UNIV`: universal.
    Universal,
    /// `INLINE`: a point on a line.
    Inline,
    /// `INPLANE`: a point in a plane.
    Inplane,
}

impl JointType {
    /// Keywords as written in decks.
    pub const KEYWORDS: [(&'static str, JointType); 8] = [
        ("REV", JointType::Revolute),
        ("FIX", JointType::Fixed),
        ("SPH", JointType::Spherical),
        ("PRIS", JointType::Prismatic),
        ("CYL", JointType::Cylindrical),
        ("UNIV", JointType::Universal),
        ("INLINE", JointType::Inline),
        ("INPLANE", JointType::Inplane),
    ];

    /// The keyword of this type.
    pub fn keyword(self) -> &'static str {
        Self::KEYWORDS
            .iter()
            .find(|(_, k)| *k == self)
            .map_or("?", |(n, _)| n)
    }

    /// Whether its first three equations make the two markers' points coincide, so that their
    /// multipliers are the joint's reaction force (what an `MSENSOR JFORCE` reads).
    pub fn makes_points_coincide(self) -> bool {
        matches!(
            self,
            JointType::Revolute | JointType::Fixed | JointType::Spherical | JointType::Universal
        )
    }

    /// Whether a drive or a joint spring-damper can act on its relative coordinate.
    pub fn has_coordinate(self) -> bool {
        matches!(self, JointType::Revolute | JointType::Prismatic)
    }
}

/// What an `MSENSOR` measures (DESIGN.md §11).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub enum MsensorKind {
    Pos,
    Accel,
    Jforce,
    Jtorq,
    Power,
    Energy,
    Ke,
    Strain,
    Dev,
}

impl MsensorKind {
    /// Keywords as written in decks.
    pub const KEYWORDS: [(&'static str, MsensorKind); 9] = [
        ("POS", MsensorKind::Pos),
        ("ACCEL", MsensorKind::Accel),
        ("JFORCE", MsensorKind::Jforce),
        ("JTORQ", MsensorKind::Jtorq),
        ("POWER", MsensorKind::Power),
        ("ENERGY", MsensorKind::Energy),
        ("KE", MsensorKind::Ke),
        ("STRAIN", MsensorKind::Strain),
        ("DEV", MsensorKind::Dev),
    ];

    /// The keyword of this kind.
    pub fn keyword(self) -> &'static str {
        Self::KEYWORDS
            .iter()
            .find(|(_, k)| *k == self)
            .map_or("?", |(n, _)| n)
    }
}

/// Case control `FMBSTART`: how a `SOL FMB` run finds its initial state.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub enum FmbStart {
    /// Kinematic assembly at t₀ with the drives, velocities from the drive rates.
    Assemble,
    /// Static equilibrium under the subcase's gravity.
    Static,
}

/// Largest re-diagonalization tolerance τ the estimator accepts: its coupled solves contract by
/// about τ per iteration (the estimator's re-diagonalized modal coordinates).
pub const MAX_REDIAGONALIZATION_TOLERANCE: f64 = 0.1;

/// Whether τ is an accepted re-diagonalization tolerance, 0 < τ ≤
/// [`MAX_REDIAGONALIZATION_TOLERANCE`] (false for NaN).
pub fn valid_rediagonalization_tolerance(tolerance: f64) -> bool {
    tolerance > 0.0 && tolerance <= MAX_REDIAGONALIZATION_TOLERANCE
}

/// MAT8 strength allowables (fields Xt Xc Yt Yc S F12 STRN), positive magnitudes as on the card;
/// blank fields `None`. With `strain_allowables` (STRN = 1.0) Xt … S are strains.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct PlyAllowables {
    /// Tension and compression along the fibres.
    pub xt: Option<f64>,
    pub xc: Option<f64>,
    /// Tension and compression across the fibres.
    pub yt: Option<f64>,
    pub yc: Option<f64>,
    /// In-plane shear.
    pub s: Option<f64>,
    /// Tsai–Wu interaction coefficient F12.
    pub f12: Option<f64>,
    /// STRN = 1.0: the allowables are strains.
    pub strain_allowables: bool,
}

/// The ply failure theory of a PCOMP (field FT).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FailureTheory {
    /// HILL: Tsai–Hill.
    Hill,
    /// HOFF: Hoffman.
    Hoffman,
    /// TSAI: Tsai–Wu.
    TsaiWu,
    /// STRN: maximum strain.
    MaxStrain,
}

impl FailureTheory {
    /// The theory of an FT keyword (HILL, HOFF, TSAI, STRN); `None` for any other.
    pub fn from_keyword(ft: &str) -> Option<Self> {
        Some(match ft {
            "HILL" => FailureTheory::Hill,
            "HOFF" => FailureTheory::Hoffman,
            "TSAI" => FailureTheory::TsaiWu,
            "STRN" => FailureTheory::MaxStrain,
            _ => return None,
        })
    }

    /// The FT keyword.
    pub fn keyword(self) -> &'static str {
        match self {
            FailureTheory::Hill => "HILL",
            FailureTheory::Hoffman => "HOFF",
            FailureTheory::TsaiWu => "TSAI",
            FailureTheory::MaxStrain => "STRN",
        }
    }
}
