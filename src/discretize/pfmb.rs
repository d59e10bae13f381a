//! The pFMB: a mechanism with everything it needs to be built at any parameter point
//! (DESIGN.md §11), independent of the deck it came from. [`Pfmb::of_model`] gathers it from a
//! model's mechanism bulk data (reading the bodies' pROM artifacts and the drives' and forces'
//! tables); [`crate::io::read_pfmb`] reads it back from the `/pfmb` group every `SOL FMB` run
//! writes, which is how a deck with `FMB = 'file.h5'` (and the optimizer and estimator, from
//! Rust) gets a mechanism without its bulk data. [`super::mechanism::build_system`] turns it
//! into a [`crate::multibody::System`] at given parameter values.

use std::collections::BTreeSet;

use super::loads::dynamic_table;
use super::mechanism::MechanismError;
use super::prom_body::{ParametricBody, read_parametric_body};
use crate::dynamics::table::Table;
use crate::model::Model;
use crate::model::mechanism::{BodyKind, Card, Mechanism};
use crate::multibody::{EomTerms, System};

/// A self-contained mechanism (module docs).
#[derive(Debug, Clone)]
pub struct Pfmb {
    /// Bodies, markers, joints, drives, forces and outputs; every position in basic.
    pub mechanism: Mechanism,
    /// Per body of the mechanism (same order): a flexible body's parametric data, `None` for a
    /// rigid body.
    pub bodies: Vec<Option<ParametricBody>>,
    /// The tables the drives and the point forces use, by id, in increasing id order.
    pub tables: Vec<(u32, Table)>,
    /// The gravity (basic) of the load sets the source deck's subcases select, by set id.
    pub gravity: Vec<(u32, [f64; 3])>,
}

impl Pfmb {
    /// The pFMB of `model`'s mechanism: its bodies' artifacts and its tables read, every
    /// error at its card (an artifact at its FLEXB, a table at the JDRIVE or MFORCE using it).
    pub fn of_model(model: &Model) -> Result<Pfmb, Vec<MechanismError>> {
        let mechanism = model.mechanism.clone();
        let mut errors = Vec::new();
        let error = |card: Card, message: String| MechanismError {
            card,
            field: None,
            message,
        };
        let bodies = mechanism
            .bodies
            .iter()
            .enumerate()
            .map(|(index, b)| match &b.kind {
                BodyKind::Flexible { artifact, .. } => read_parametric_body(artifact)
                    .map_err(|message| errors.push(error(Card::Body(index), message)))
                    .ok(),
                BodyKind::Rigid { .. } => None,
            })
            .collect();
        let mut tables = Vec::new();
        let users = (mechanism.drives.iter().enumerate())
            .map(|(i, d)| (d.table, Card::Drive(i)))
            .chain((mechanism.forces.iter().enumerate()).map(|(i, f)| (f.table, Card::Force(i))));
        for (tid, card) in users {
            match dynamic_table(model, tid) {
                Ok(table) if !tables.iter().any(|(id, _)| *id == tid) => tables.push((tid, table)),
                Ok(_) => {}
                Err(message) => errors.push(error(card, message)),
            }
        }
        tables.sort_by_key(|(id, _)| *id);
        let sets: BTreeSet<u32> = model.subcases.iter().filter_map(|s| s.load).collect();
        let gravity = sets
            .into_iter()
            .map(|sid| (sid, model.gravity(sid)))
            .collect();
        if !errors.is_empty() {
            return Err(errors);
        }
        Ok(Pfmb {
            mechanism,
            bodies,
            tables,
            gravity,
        })
    }

    /// Table `tid` (every table a drive or a force uses is here).
    pub fn table(&self, tid: u32) -> Option<&Table> {
        self.tables
            .iter()
            .find(|(id, _)| *id == tid)
            .map(|(_, t)| t)
    }

    /// The stored gravity of load set `sid`, if the source deck selected it.
    pub fn gravity_of(&self, sid: u32) -> Option<[f64; 3]> {
        self.gravity
            .iter()
            .find(|(id, _)| *id == sid)
            .map(|(_, g)| *g)
    }

    /// The flexible bodies' names with their parametric data.
    pub fn flexible(&self) -> impl Iterator<Item = (&str, &ParametricBody)> {
        self.mechanism
            .bodies
            .iter()
            .zip(&self.bodies)
            .filter_map(|(b, p)| p.as_ref().map(|p| (b.name.as_str(), p)))
    }

    /// Checks that every name of `pval` is `BODY.PMPAR` with BODY a flexible body and PMPAR
    /// one of its parameters; the message names the first that is not.
    pub fn check_parameter_names(&self, pval: &[(String, f64)]) -> Result<(), String> {
        for (name, _) in pval {
            let found = name.split_once('.').and_then(|(body, parameter)| {
                self.flexible()
                    .find(|(b, _)| b.eq_ignore_ascii_case(body))
                    .map(|(_, p)| {
                        p.prom
                            .parameters
                            .iter()
                            .any(|q| q.name.eq_ignore_ascii_case(parameter))
                    })
            });
            if found != Some(true) {
                return Err(format!(
                    "{name} is not BODY.PMPAR of this mechanism (parameters: {})",
                    self.parameter_names().join(", ")
                ));
            }
        }
        Ok(())
    }

    /// Every parameter as `BODY.PMPAR`, body by body.
    pub fn parameter_names(&self) -> Vec<String> {
        self.flexible()
            .flat_map(|(b, p)| {
                p.prom
                    .parameters
                    .iter()
                    .map(move |q| format!("{b}.{}", q.name))
            })
            .collect()
    }

    /// The derivatives of the data-carrying terms of the equations of motion
    /// ([`EomTerms`]: M(q), f_v, f_g, K q_f, C q̇_f) with respect to every parameter
    /// `BODY.PMPAR`, at (q, q̇) of `system` (built by
    /// [`super::mechanism::build_system`] from this pFMB at `pval`), in
    /// [`Pfmb::parameter_names`] order. Exact: the terms are linear in a body's data and the
    /// data affine in p ([`crate::multibody::derivatives`]).
    pub fn eom_parameter_derivatives(
        &self,
        system: &System,
        pval: &[(String, f64)],
        q: &[f64],
        v: &[f64],
    ) -> Result<Vec<(String, EomTerms)>, String> {
        let mut out = Vec::new();
        for (index, (b, parametric)) in self.mechanism.bodies.iter().zip(&self.bodies).enumerate() {
            let Some(p) = parametric else { continue };
            let values = super::mechanism::values_of(&b.name, pval);
            for (j, q_j) in p.prom.parameters.iter().enumerate() {
                let rate = p.derivative(&values, j, &b.name)?;
                out.push((
                    format!("{}.{}", b.name, q_j.name),
                    system.eom_terms_rate(index, &rate, q, v),
                ));
            }
        }
        Ok(out)
    }
}
