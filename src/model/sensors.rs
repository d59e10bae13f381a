//! The SENSORs of a model as measurement points: what is measured, where, along which
//! direction ([`Model::sensors`]). Which of them a subcase measures is the caller's choice.

use super::Model;
use crate::card_values::SensorKind;

/// A sensor: one measured quantity along a direction at a grid (DISP, VEL, ACCEL) or at an
/// element's centroid (STRAIN).
#[derive(Debug, Clone, PartialEq)]
pub struct Sensor {
    pub id: u32,
    /// Name in outputs.
    pub name: String,
    pub kind: SensorKind,
    /// Grid id (DISP, VEL, ACCEL) or element id (STRAIN).
    pub reference: u32,
    /// Shell surface of a STRAIN sensor (`TOP`, `BOT`, `MID`), `None` for the mid-surface.
    pub surface: Option<&'static str>,
    /// Measuring direction in the basic system (not normalized).
    pub direction: [f64; 3],
}

impl Model {
    /// Every SENSOR, in card order.
    pub fn sensors(&self) -> Vec<Sensor> {
        self.bulk
            .sensors
            .iter()
            .map(|s| Sensor {
                id: s.id,
                name: s.name.clone(),
                kind: s.kind,
                reference: s.reference,
                surface: s.surface,
                direction: s.direction,
            })
            .collect()
    }
}
