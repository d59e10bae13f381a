//! The unknown inputs of a pFMB (thesis eq. 9.1, 9.4: random walks in x*): point forces or
//! moments of the system (a deck's `MFORCE` / `MMOMENT`) whose amplitude is estimated instead
//! of read from their table. The state holds each amplitude u in physical units (N or N m)
//! along the element's fixed direction; the prediction applies it constant over the step
//! (u_k⁻ = u_{k−1}⁺, the random walk's mean), so the element's signal is set to u before each
//! step ([`Inputs::apply`]).
//!
//! The equations of motion are linear in u: f = f₀ + Σⱼ uⱼ Qⱼ(q) with Qⱼ the generalized force
//! of a unit amplitude ([`Inputs::unit_loads`], the element's own virtual-work form,
//! [`crate::multibody::forces`]), so the transition's input columns need no differences.

use crate::multibody::{Force, Signal, System};

/// One unknown input: element `force` of the system's forces, named `name` (its card id).
#[derive(Debug, Clone, PartialEq)]
pub struct Input {
    pub force: usize,
    pub name: String,
}

/// The unknown inputs of a system (module docs).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Inputs {
    pub list: Vec<Input>,
}

impl Inputs {
    /// Number of unknown inputs.
    pub fn len(&self) -> usize {
        self.list.len()
    }

    /// Whether there is none.
    pub fn is_empty(&self) -> bool {
        self.list.is_empty()
    }

    /// The names of the inputs.
    pub fn names(&self) -> Vec<String> {
        self.list.iter().map(|u| u.name.clone()).collect()
    }

    /// An error if an input is not a point force or moment of `system`.
    pub fn check(&self, system: &System) -> Result<(), String> {
        for u in &self.list {
            match system.forces.get(u.force) {
                Some(Force::Point { .. } | Force::Moment { .. }) => {}
                _ => {
                    return Err(format!(
                        "input {}: force element {} is not a point force or moment",
                        u.name, u.force
                    ));
                }
            }
        }
        Ok(())
    }

    /// Sets the amplitude of every input's element of `system` to the constant `u`.
    pub fn apply(&self, u: &[f64], system: &mut System) {
        for (input, value) in self.list.iter().zip(u) {
            if let Force::Point { signal, .. } | Force::Moment { signal, .. } =
                &mut system.forces[input.force]
            {
                *signal = Signal::constant(*value);
            }
        }
    }

    /// Qⱼ(q) at t of every input: the generalized force of a unit amplitude (n each).
    pub fn unit_loads(&self, system: &System, q: &[f64], t: f64) -> Vec<Vec<f64>> {
        self.list
            .iter()
            .map(|input| {
                let mut unit = system.forces[input.force].clone();
                if let Force::Point { signal, .. } | Force::Moment { signal, .. } = &mut unit {
                    *signal = Signal::constant(1.0);
                }
                let mut load = vec![0.0; q.len()];
                unit.add_load(&system.markers, &system.layout, q, t, &mut load);
                load
            })
            .collect()
    }
}
