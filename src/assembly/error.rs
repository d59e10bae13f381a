//! Typed errors of assembly and set reduction. Each names the grid and component (1–6) or the
//! card involved; none is a panic.

use thiserror::Error;

use crate::model::sets::SetError;

/// A DOF as the user knows it: GRID id and component 1–6.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct DofName {
    /// GRID id, or SPOINT id when `component` is 0.
    pub grid: u32,
    /// Component 1–6 (T1 T2 T3 R1 R2 R3), 0 for a scalar point.
    pub component: u8,
}

impl std::fmt::Display for DofName {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.component {
            0 => write!(f, "SPOINT {}", self.grid),
            c => write!(f, "GRID {} component {c}", self.grid),
        }
    }
}

/// Errors of assembly, constraint elimination and loads.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum AssemblyError {
    /// A DOF is dependent in two rigid elements.
    #[error("{dof} is dependent in both {first} and {second}")]
    DependentTwice {
        dof: DofName,
        first: String,
        second: String,
    },
    /// A dependent DOF is also constrained by an SPC or GRID PS.
    #[error("{dof} is dependent in {rigid} and also constrained by {constraint}")]
    DependentConstrained {
        dof: DofName,
        rigid: String,
        constraint: String,
    },
    /// A cycle of rigid elements (each depends on the next).
    #[error("rigid elements form a dependency cycle: {}", rigids.join(" → "))]
    RigidCycle { rigids: Vec<String> },
    /// The weighted least-squares fit of an RBE3 is singular (e.g. collinear independent grids
    /// with rotational REFC, or only one independent grid).
    #[error(
        "{owner}: the independent grids do not determine the reference motion (weighted fit matrix is singular); add non-collinear grids or rotational components"
    )]
    Rbe3Singular { owner: String },
    /// A grid is referenced but does not exist.
    #[error("{card}: grid {grid} is referenced but does not exist")]
    MissingGrid { card: String, grid: u32 },
    /// The selected SPC or MPC set does not exist.
    #[error("{selection} = {sid} selects no {cards} set {sid}")]
    NoConstraintSet {
        selection: &'static str,
        cards: String,
        sid: u32,
    },
    /// SPCADD / MPCADD references another union (not allowed, as in Nastran) or a missing set.
    #[error("{card} {sid}: {reason}")]
    BadUnion {
        card: &'static str,
        sid: u32,
        reason: String,
    },
    /// Two different enforced values for one DOF in one SPC set.
    #[error("{dof} has two enforced values in SPC set {sid}: {a} and {b}")]
    ConflictingEnforced {
        dof: DofName,
        sid: u32,
        a: f64,
        b: f64,
    },
    /// An SPCD names a DOF that the subcase's SPC set does not constrain.
    #[error("{card}: {dof} is {}: an enforced displacement (SPCD) must act on a DOF of the subcase's SPC set (SPC, SPC1 or GRID PS), as in Nastran; add it to the SPC set selected by SPC =", if *autospc { "constrained by AUTOSPC only" } else { "not constrained" })]
    SpcdNotConstrained {
        dof: DofName,
        card: String,
        autospc: bool,
    },
    /// The LOAD set does not exist.
    #[error(
        "LOAD = {sid} selects no LOAD/FORCE/MOMENT/FORCE1/FORCE2/MOMENT1/MOMENT2/SLOAD/GRAV/PLOAD4/PLOAD2/PLOAD/PLOAD1/SPCD set {sid}"
    )]
    NoLoadSet { sid: u32 },
    /// A LOAD card references another LOAD (not allowed, as in Nastran) or a missing set.
    #[error("LOAD {sid}: {reason}")]
    BadLoad { sid: u32, reason: String },
    /// GRAV needs the assembled mass matrix.
    #[error("load set {sid} contains GRAV, which needs the assembled mass matrix M_gg")]
    MassRequired { sid: u32 },
    /// A DOF index outside the g-set (an element contribution from a caller).
    #[error("DOF index {index} is outside the g-set of {size} DOFs")]
    DofOutOfRange { index: usize, size: usize },
    /// Sizes that must agree do not.
    #[error("{what}: expected {expected}, found {found}")]
    SizeMismatch {
        what: &'static str,
        expected: usize,
        found: usize,
    },
    /// Affine parts of one operator that do not share its pattern.
    #[error("matrix pattern differs from the operator's pattern ({what})")]
    PatternMismatch { what: &'static str },
}

impl AssemblyError {
    /// The error of a selected constraint set `selection = sid` that cannot be resolved:
    /// `members` are the cards of a plain set (`SPC/SPC1`), `union` the card that unites sets.
    pub fn unresolved_set(
        e: SetError,
        selection: &'static str,
        members: &str,
        union: &'static str,
        sid: u32,
    ) -> Self {
        match e {
            SetError::Empty => AssemblyError::NoConstraintSet {
                selection,
                cards: format!("{members}/{union}"),
                sid,
            },
            SetError::Nested(s) => AssemblyError::BadUnion {
                card: union,
                sid,
                reason: format!("S = {s} is itself an {union} (nested {union} is not allowed)"),
            },
            SetError::Missing(s) => AssemblyError::BadUnion {
                card: union,
                sid,
                reason: format!("S = {s} selects no {members} set"),
            },
        }
    }
}
