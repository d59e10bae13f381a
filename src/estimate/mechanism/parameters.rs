//! The estimated parameters of a pFMB (thesis eq. 9.1, 9.4: random walks in x*): pROM
//! parameters `BODY.PMPAR` of its flexible bodies. The state holds each one scaled by its
//! initial guess a_p (θ = p / a_p), so that the rule of thumb of eq. 8.31 reads
//! Q_θ = (Δt δ_p)² and the covariance entries are relative.
//!
//! At θ the bodies' data are the pROMs' affine sums ([`ParametricBody::at`]), and the rates of
//! the equations' data-carrying terms are exact ([`ParametricBody::derivative`] with
//! [`System::eom_terms_rate`]): nothing in the constraints depends on p (constant bases), so
//! only the equations of motion carry parameter columns (§9.2.1).

use crate::discretize::prom_body::ParametricBody;
use crate::multibody::{BodyId, EomTerms, System};

/// A flexible body some of whose pROM parameters are estimated.
#[derive(Debug, Clone)]
pub struct EstimatedBody {
    /// The body in the system.
    pub body: BodyId,
    /// Its name (the `BODY` of `BODY.PMPAR`).
    pub name: String,
    pub model: ParametricBody,
    /// Values of the parameters that are not estimated (PMPAR, value); the pROM's nominal
    /// values for those not listed.
    pub fixed: Vec<(String, f64)>,
}

/// One estimated parameter: PMPAR `pmpar` of `bodies[body]`, initial guess `initial`.
#[derive(Debug, Clone)]
pub struct Parameter {
    pub body: usize,
    pub pmpar: String,
    pub initial: f64,
}

/// The estimated parameters of a system (module docs).
#[derive(Debug, Clone)]
pub struct Parameters {
    pub bodies: Vec<EstimatedBody>,
    pub list: Vec<Parameter>,
}

impl Parameters {
    /// Number of estimated parameters.
    pub fn len(&self) -> usize {
        self.list.len()
    }

    /// Whether none is estimated.
    pub fn is_empty(&self) -> bool {
        self.list.is_empty()
    }

    /// `BODY.PMPAR` of each parameter.
    pub fn names(&self) -> Vec<String> {
        self.list
            .iter()
            .map(|p| format!("{}.{}", self.bodies[p.body].name, p.pmpar))
            .collect()
    }

    /// The physical values p = a_p θ.
    pub fn values(&self, theta: &[f64]) -> Vec<f64> {
        self.list
            .iter()
            .zip(theta)
            .map(|(p, t)| p.initial * t)
            .collect()
    }

    /// The pROM parameter values of body `b` at θ: the fixed ones, then the estimated ones.
    fn body_values(&self, b: usize, theta: &[f64]) -> Vec<(String, f64)> {
        let mut values = self.bodies[b].fixed.clone();
        for (p, t) in self.list.iter().zip(theta).filter(|(p, _)| p.body == b) {
            values.push((p.pmpar.clone(), p.initial * t));
        }
        values
    }

    /// Sets the data of every estimated body of `system` to its pROM at θ.
    pub fn apply(&self, theta: &[f64], system: &mut System) -> Result<(), String> {
        for (b, body) in self.bodies.iter().enumerate() {
            let at = body.model.at(&self.body_values(b, theta), &body.name)?;
            system.bodies[body.body].data = at.data;
        }
        Ok(())
    }

    /// ∂(terms)/∂θ_j at (q, q̇) for every parameter j (a_p ∂/∂p: [`EomTerms`] scaled).
    pub fn rates(
        &self,
        theta: &[f64],
        system: &System,
        q: &[f64],
        v: &[f64],
    ) -> Result<Vec<EomTerms>, String> {
        self.list
            .iter()
            .map(|p| {
                let body = &self.bodies[p.body];
                let values = self.body_values(p.body, theta);
                let j = body
                    .model
                    .prom
                    .parameters
                    .iter()
                    .position(|x| x.name.eq_ignore_ascii_case(&p.pmpar))
                    .ok_or_else(|| format!("{} has no parameter {}", body.name, p.pmpar))?;
                let rate = body.model.derivative(&values, j, &body.name)?;
                let mut terms = system.eom_terms_rate(body.body, &rate, q, v);
                let a = p.initial;
                terms.mass *= faer::Scale(a);
                for x in [
                    &mut terms.quadratic_velocity,
                    &mut terms.gravity,
                    &mut terms.elastic,
                    &mut terms.damping,
                ] {
                    x.iter_mut().for_each(|y| *y *= a);
                }
                Ok(terms)
            })
            .collect()
    }
}
