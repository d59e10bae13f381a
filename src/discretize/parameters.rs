//! The model's PMPAR parameters (DESIGN.md §3, §5): the entity each one acts on, the nominal
//! values, and the affine function f_i(p) of every parametrized part of the assembled operators.
//!
//! A part is keyed by (entity, coefficient) ([`ParamKey::Param`]); its function is the
//! coefficient evaluated with the entity's card values, except the inputs that PMPARs on that
//! entity drive: e.g. λ* of a MAT1 with `PMPAR E` and `PMPAR NU` is λ*(p_E, p_NU), with only
//! `PMPAR NU` it is λ*(E of the MAT1, p_NU).

use std::collections::BTreeMap;

use super::DiscretizeError;
use crate::assembly::{AffineOperator, ParamKey, ParamTarget};
use crate::card_values::PmparKind;
use crate::fe::affine::CoefficientValues;
use crate::model::Model;
use crate::model::materials::Material;
use crate::model::pmpar::Parameter;
use crate::rom::prom::{AffineFunction, CoefficientInput, PromParameter};

/// The PMPARs of a model, in card order.
#[derive(Debug, Clone, Default)]
pub struct Parameters {
    pub list: Vec<PromParameter>,
    kinds: Vec<PmparKind>,
    targets: Vec<ParamTarget>,
    /// Card values of every parametrized entity (the fixed inputs of its functions).
    fixed: BTreeMap<ParamTarget, CoefficientValues>,
}

/// The entity a PMPAR acts on.
fn target_of(p: &Parameter) -> ParamTarget {
    match p.kind {
        PmparKind::E | PmparKind::Rho | PmparKind::Nu => ParamTarget::Material(p.entity),
        PmparKind::Theta | PmparKind::Tply => ParamTarget::Pcomp(p.entity),
        PmparKind::K => ParamTarget::Pelas(p.entity),
        PmparKind::Mass => ParamTarget::Conm2(p.entity),
    }
}

fn input_of(kind: PmparKind) -> CoefficientInput {
    match kind {
        PmparKind::E => CoefficientInput::E,
        PmparKind::Rho => CoefficientInput::Rho,
        PmparKind::Nu => CoefficientInput::Nu,
        PmparKind::Theta => CoefficientInput::ThetaDeg,
        PmparKind::Tply => CoefficientInput::H,
        PmparKind::K | PmparKind::Mass => CoefficientInput::Lumped,
    }
}

impl Parameters {
    /// Collect the PMPARs (already validated by [`Model::build`]).
    pub fn of_model(model: &Model) -> Result<Self, DiscretizeError> {
        let mut out = Parameters::default();
        let parameters = model.parameters().map_err(|e| DiscretizeError::Parameter {
            name: e.name,
            reason: e.reason,
        })?;
        for p in &parameters {
            let value = p.nominal;
            let target = target_of(p);
            out.list.push(PromParameter {
                name: p.name.to_ascii_uppercase(),
                low: p.low,
                high: p.high,
                nominal: value,
            });
            out.kinds.push(p.kind);
            out.targets.push(target);
            let fixed = out.fixed.entry(target).or_default();
            *input_of(p.kind).slot(fixed) = value;
        }
        // the other card values of each entity (e.g. ν of a MAT1 whose E is the parameter)
        for (&target, fixed) in out.fixed.iter_mut() {
            if let ParamTarget::Material(mid) = target
                && let Some(Material::Isotropic(m)) = model.material(mid)
            {
                *fixed = CoefficientValues {
                    e: m.e,
                    nu: m.nu,
                    rho: m.rho,
                    ..*fixed
                };
            }
        }
        Ok(out)
    }

    /// True when no PMPAR exists.
    pub fn is_empty(&self) -> bool {
        self.list.is_empty()
    }

    /// The kinds of the PMPARs acting on `target`.
    pub fn kinds_on(&self, target: ParamTarget) -> Vec<PmparKind> {
        self.targets
            .iter()
            .zip(&self.kinds)
            .filter(|(t, _)| **t == target)
            .map(|(_, k)| *k)
            .collect()
    }

    /// The names of the PMPARs of one of `kinds` acting on one of `targets`, in card order.
    pub fn names_on(&self, targets: &[ParamTarget], kinds: &[PmparKind]) -> Vec<String> {
        self.list
            .iter()
            .zip(self.targets.iter().zip(&self.kinds))
            .filter(|(_, (t, k))| targets.contains(t) && kinds.contains(k))
            .map(|(p, _)| p.name.clone())
            .collect()
    }

    /// True when some PMPAR acts on `target`.
    pub fn acts_on(&self, target: ParamTarget) -> bool {
        self.targets.contains(&target)
    }

    /// Nominal parameter values.
    pub fn nominal(&self) -> Vec<f64> {
        self.list.iter().map(|p| p.nominal).collect()
    }

    /// The affine function of a part.
    pub fn function(&self, key: ParamKey) -> AffineFunction {
        match key {
            ParamKey::Constant => AffineFunction::constant(),
            ParamKey::Param { target, function } => AffineFunction {
                coefficient: function,
                fixed: self.fixed.get(&target).copied().unwrap_or_default(),
                driven_by: self
                    .targets
                    .iter()
                    .zip(&self.kinds)
                    .enumerate()
                    .filter(|(_, (t, _))| **t == target)
                    .map(|(j, (_, k))| (input_of(*k), j))
                    .collect(),
            },
        }
    }

    /// Weights of an operator's parts at parameter values `p` (one per PMPAR, card order).
    pub fn weights(&self, op: &AffineOperator, p: &[f64]) -> Vec<f64> {
        op.weights(|key| self.function(key).value(p))
    }
}
