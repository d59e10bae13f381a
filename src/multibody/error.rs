//! Errors of model building, assembly and integration.

/// The constraints of a failed step's last iterate that came closest to depending on each
/// other ([`super::redundancy::weakest_combination`] of Φ_q there): a loop at a dead centre
/// names its joints.
#[derive(Debug, Clone, PartialEq)]
pub struct Dependence {
    /// σ_min / σ_max of Φ_q.
    pub ratio: f64,
    /// The joints, drives or normalizations whose rows form the weakest combination, largest
    /// weight first.
    pub constraints: Vec<String>,
}

impl std::fmt::Display for Dependence {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "rows closest to dependent (σ_min/σ_max of Φ_q = {:.1e}): {}",
            self.ratio,
            self.constraints.join(", ")
        )
    }
}

/// Why a multibody computation stopped.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MultibodyError {
    #[error("{0}")]
    Input(String),
    #[error(
        "kinematic assembly at t = {time} did not converge: |Φ| = {residual:.3e}, worst constraint {worst}; still violated: {}",
        violated.join(", ")
    )]
    Assembly {
        time: f64,
        residual: f64,
        worst: String,
        /// Every constraint left above the assembly tolerance, largest first, with its |Φ|.
        violated: Vec<String>,
    },
    #[error(
        "step to t = {time} did not converge in {iterations} Newton iterations: residual {residual:.3e}, worst constraint {worst} (|Φ| = {constraint:.3e}); {dependent}"
    )]
    NotConverged {
        time: f64,
        iterations: usize,
        residual: f64,
        worst: String,
        constraint: f64,
        dependent: Dependence,
    },
    #[error(
        "step to t = {time}: singular GGL iteration matrix at residual {residual:.3e}, worst constraint {worst} (|Φ| = {constraint:.3e}); {dependent}"
    )]
    SingularStep {
        time: f64,
        residual: f64,
        worst: String,
        constraint: f64,
        dependent: Dependence,
    },
    #[error(
        "static equilibrium at t = {time} not found in {iterations} Newton iterations: force residual {residual:.3e}, worst constraint {worst} (|Φ| = {constraint:.3e})"
    )]
    NoEquilibrium {
        time: f64,
        iterations: usize,
        residual: f64,
        worst: String,
        constraint: f64,
    },
    #[error(
        "error-controlled step at t = {time}: the step {step:.3e} fell below HMIN = {min_step:.3e} (estimated local error {error:.3e} times the tolerance); loosen RTOL/ATOL or lower HMIN"
    )]
    StepTooSmall {
        time: f64,
        step: f64,
        min_step: f64,
        /// The last step's estimate in units of the tolerance (NaN: Newton did not converge).
        error: f64,
    },
    #[error("singular {what} at t = {time}")]
    Singular { what: &'static str, time: f64 },
}
