//! Discretization of a [`Model`](crate::model::Model): from the cross-referenced model to the
//! assembled parametric operators every solution works on (DESIGN.md §1, the `fe` and
//! `assemble` arrows), usable from Rust without a deck file or an output file.
//!
//! - [`elements`]: which `fe` kernel each element/property/material combination calls, with
//!   its affine parts bound to the entities the PMPARs act on;
//! - [`parameters`]: the PMPARs as parameters with nominal values and bounds, and the affine
//!   function f_i(p) of every parametrized part (thesis §3.3);
//! - [`Structure`]: K(p) and M(p) assembled on one grid-block pattern and reduced g → n by the
//!   rigid elimination (RBE2/RBE3), built once per model;
//! - [`Constrained`]: per SPC set, the f-set with AUTOSPC and K_ff, M_ff evaluated at p, or
//!   with every affine part as the FOM of a pROM build ([`affine_fom`]);
//! - [`sensors`] and [`loads`]: the f-set rows of SENSORs (thesis eq. 2.30–2.35) and the f-set
//!   placement of loads (DAREA entries, static load sets, initial conditions);
//! - [`mechanism`], [`pfmb`] and [`prom_body`]: the multibody system of a model's mechanism
//!   (gathered with its artifacts and tables as a self-contained [`pfmb::Pfmb`]), its flexible
//!   bodies evaluated from their pROM data at p.
//!
//! A model in memory becomes a modal solution in four calls:
//!
//! ```no_run
//! use paraflex::discretize::{BuildOptions, Constrained, Structure};
//! use paraflex::linalg::{EigenProblem, EigenRequest, LanczosOptions, SymbolicFactor, solve_modes};
//! # fn modes(model: &paraflex::model::Model) -> Result<(), Box<dyn std::error::Error>> {
//! let quiet = |_: &str, _: usize, _: usize| {};
//! let options = BuildOptions { parallel: false };
//! let structure = Structure::build(model, &options, &quiet)?;
//! // K_ff, M_ff of SPC set 1 at the PMPARs' nominal values
//! let p = structure.params.nominal();
//! let c = Constrained::at(model, &structure, Some(1), &p)?;
//! let symbolic = SymbolicFactor::analyze(c.k_ff.pattern())?;
//! let problem = EigenProblem { k: &c.k_ff, m: &c.m_ff, symbolic: &symbolic };
//! let request = EigenRequest { v1_hz: None, v2_hz: None, nd: Some(6), shift_hz: None };
//! let modes = solve_modes(&problem, &request, &LanczosOptions::default(), options.par(), &quiet)?;
//! println!("{:?}", modes.frequencies_hz);
//! # Ok(())
//! # }
//! ```

pub mod body;
pub mod elements;
pub mod enforced;
pub mod loads;
pub mod mechanism;
pub mod parameters;
pub mod pfmb;
pub mod prom_body;
pub mod sensors;
mod structure;
pub mod thermal;

use faer::Par;

use crate::assembly::AssemblyError;

pub use body::{basic_columns, flexible_body};
pub use structure::{Constrained, Structure, affine_fom, affine_keys};

/// How the discretization (and the solutions after it) run.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct BuildOptions {
    /// Use rayon / faer parallelism (element matrices, assembly, factorization).
    pub parallel: bool,
}

impl Default for BuildOptions {
    fn default() -> Self {
        BuildOptions { parallel: true }
    }
}

impl BuildOptions {
    /// The faer parallelism these options ask for.
    pub fn par(&self) -> Par {
        if self.parallel {
            Par::rayon(0)
        } else {
            Par::Seq
        }
    }
}

/// Errors of the discretization. Each names the element or parameter at fault.
#[derive(Debug, thiserror::Error)]
pub enum DiscretizeError {
    /// An element whose property or material combination is not supported, or whose
    /// geometry the element kernel rejects.
    #[error("{card} {id}: {reason}")]
    Element {
        card: &'static str,
        id: u32,
        reason: String,
    },
    /// A PMPAR that cannot be applied (e.g. its nominal value cannot be read).
    #[error("PMPAR {name}: {reason}")]
    Parameter { name: String, reason: String },
    #[error(transparent)]
    Assembly(#[from] AssemblyError),
}
