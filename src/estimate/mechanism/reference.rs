//! Strain references of the AMANDA-EKF (thesis §9.3.2): a gauge zeroed in a reference
//! configuration reads h = C_ε (q_f − q_f,ref) (eq. 9.24). The reference is the static
//! equilibrium at t = 0 (drives at their t = 0 values, gravity and the known loads; the unknown
//! inputs off, as when a gauge is zeroed under gravity alone) of the system at given
//! parameters:
//!
//! - [`StrainReference::Fixed`] (eq. 9.24): at the initial guesses, once — the offset is wrong
//!   by as much as the guesses are;
//! - [`StrainReference::Adaptive`] (eq. 9.25): at the current estimate θ⁻ before each
//!   correction, warm-started from the previous reference, and the measurement rows gain the
//!   reference's dependence on θ, −C_ε ∂q_f,ref/∂θⱼ, with ∂q_ref/∂θ from the equilibrium's
//!   tangent ([`equilibrium_rates`]; the force rates ∂f/∂θ are the exact affine rates of
//!   [`super::parameters`] at v = 0).

use super::inputs::Inputs;
use super::parameters::Parameters;
use super::sensors::Sensor;
use crate::multibody::statics::{
    Equilibrium, KeptMatrix, Refresh, StaticSettings, equilibrium_from, equilibrium_rates,
};
use crate::multibody::{Ggl, Output};
use faer::Mat;

/// Which configuration the strain gauges read from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum StrainReference {
    /// The undeformed body (eq. 2.57).
    #[default]
    Absolute,
    /// The static equilibrium at the initial guesses (eq. 9.24).
    Fixed,
    /// The static equilibrium at the current estimate (eq. 9.25).
    Adaptive,
}

/// Newton tolerance of the reference equilibrium (relative correction of q).
const TOLERANCE: f64 = 1e-12;

/// The reference configuration of the gauges (module docs).
pub struct Reference {
    pub kind: StrainReference,
    equilibrium: Equilibrium,
    /// ∂q_ref/∂θⱼ of the adaptive reference (n each).
    rates: Vec<Vec<f64>>,
}

impl Reference {
    /// The reference of `kind` for `ggl`'s system at θ (`None` for absolute strains).
    pub fn new(
        kind: StrainReference,
        ggl: &mut Ggl,
        inputs: &Inputs,
        u: &[f64],
        parameters: &Parameters,
        theta: &[f64],
    ) -> Result<Option<Self>, String> {
        if kind == StrainReference::Absolute {
            return Ok(None);
        }
        let start = Equilibrium {
            q: ggl.q.clone(),
            lambda: vec![0.0; ggl.constraint_count()],
            iterations: 0,
            factorizations: 0,
            force_residual: 0.0,
            constraint_residual: 0.0,
        };
        let mut reference = Self {
            kind,
            equilibrium: start,
            rates: Vec::new(),
        };
        reference.solve(ggl, inputs, u, parameters, theta)?;
        Ok(Some(reference))
    }

    /// Solves the equilibrium again at θ (the system's data already at θ), warm-started, with
    /// the unknown inputs off (restored to `u` after), and its rates for the adaptive kind.
    fn solve(
        &mut self,
        ggl: &mut Ggl,
        inputs: &Inputs,
        u: &[f64],
        parameters: &Parameters,
        theta: &[f64],
    ) -> Result<(), String> {
        let settings = StaticSettings {
            tolerance: TOLERANCE,
            assembly_tolerance: ggl.settings.tolerance,
            refresh: Refresh::Every,
        };
        inputs.apply(&vec![0.0; inputs.len()], &mut ggl.system);
        let solved = equilibrium_from(
            &ggl.system,
            &ggl.equations,
            (&self.equilibrium.q, &self.equilibrium.lambda),
            0.0,
            settings,
            &mut KeptMatrix::default(),
        );
        let result = solved.map_err(|e| format!("the strain reference's equilibrium: {e}"));
        let rates = result.as_ref().ok().map(|eq| {
            let zero = vec![0.0; eq.q.len()];
            let terms = parameters.rates(theta, &ggl.system, &eq.q, &zero)?;
            let forces: Vec<Vec<f64>> = (terms.iter())
                .map(|t| {
                    (0..eq.q.len())
                        .map(|i| {
                            t.quadratic_velocity[i] + t.gravity[i] - t.elastic[i] - t.damping[i]
                        })
                        .collect()
                })
                .collect();
            equilibrium_rates(&ggl.system, &ggl.equations, eq, 0.0, &forces)
                .map_err(|e| format!("the strain reference's rates: {e}"))
        });
        inputs.apply(u, &mut ggl.system);
        self.equilibrium = result?;
        if self.kind == StrainReference::Adaptive {
            self.rates = rates.expect("solved")?;
        }
        Ok(())
    }

    /// The adaptive reference at the estimate θ (the system's data at θ); the fixed one stays.
    pub fn update(
        &mut self,
        ggl: &mut Ggl,
        inputs: &Inputs,
        u: &[f64],
        parameters: &Parameters,
        theta: &[f64],
    ) -> Result<(), String> {
        match self.kind {
            StrainReference::Adaptive => self.solve(ggl, inputs, u, parameters, theta),
            _ => Ok(()),
        }
    }

    /// Sets every strain sensor's ε_ref = C_ε q_f,ref.
    pub fn apply(&self, sensors: &mut [Sensor], ggl: &Ggl) {
        let layout = &ggl.system.layout;
        for s in sensors {
            if let Output::Strain { body, rows } = &s.output {
                let f = layout.slice(*body).flexible();
                s.reference = (rows.iter().enumerate())
                    .map(|(i, c)| c * self.equilibrium.q[f + i])
                    .sum();
            }
        }
    }

    /// Adds −C_ε ∂q_f,ref/∂θⱼ to the strain rows of `jm`, θⱼ in column `first + j`.
    pub fn add_rows(&self, sensors: &[Sensor], ggl: &Ggl, jm: &mut Mat<f64>, first: usize) {
        let layout = &ggl.system.layout;
        for (k, s) in sensors.iter().enumerate() {
            if let Output::Strain { body, rows } = &s.output {
                let f = layout.slice(*body).flexible();
                for (j, rate) in self.rates.iter().enumerate() {
                    let d: f64 = (rows.iter().enumerate())
                        .map(|(i, c)| c * rate[f + i])
                        .sum();
                    jm[(k, first + j)] -= d;
                }
            }
        }
    }
}
