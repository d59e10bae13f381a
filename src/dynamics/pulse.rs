//! The TLOAD2 pulse: with t̃ = t − T1 (the load's delay τ already taken off t),
//! F(t̃) = t̃^B e^{C t̃} cos(2π F t̃ + P) on 0 ≤ t̃ ≤ T2 − T1 and 0 elsewhere (Nastran's TLOAD2).

/// A TLOAD2 pulse.
#[derive(Debug, Clone, PartialEq)]
pub struct Pulse {
    /// T1: where the pulse starts.
    pub start: f64,
    /// T2 > T1: where it ends.
    pub end: f64,
    /// F (cycles per unit time).
    pub frequency: f64,
    /// P (degrees).
    pub phase_deg: f64,
    /// C (1 / unit time).
    pub exponential: f64,
    /// B ≥ 0 (t̃⁰ = 1, also at t̃ = 0).
    pub power: f64,
}

impl Pulse {
    /// F(t) for t measured from the load's delay.
    pub fn value(&self, t: f64) -> f64 {
        let local = t - self.start;
        if local < 0.0 || local > self.end - self.start {
            return 0.0;
        }
        let growth = if self.power == 0.0 {
            1.0
        } else {
            local.powf(self.power)
        };
        let angle =
            2.0 * std::f64::consts::PI * self.frequency * local + self.phase_deg.to_radians();
        growth * (self.exponential * local).exp() * angle.cos()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_pulse_is_its_formula_inside_and_zero_outside() {
        let p = Pulse {
            start: 0.5,
            end: 2.5,
            frequency: 3.0,
            phase_deg: 30.0,
            exponential: -0.4,
            power: 1.5,
        };
        for t in [0.5, 0.7, 1.9, 2.5] {
            let s: f64 = t - 0.5;
            let exact = s.powf(1.5)
                * (-0.4 * s).exp()
                * (2.0 * std::f64::consts::PI * 3.0 * s + std::f64::consts::PI / 6.0).cos();
            assert!((p.value(t) - exact).abs() < 1e-15, "t = {t}");
        }
        for t in [0.0, 0.4999, 2.5001, 9.0] {
            assert_eq!(p.value(t), 0.0, "t = {t}");
        }
        let step = Pulse {
            start: 0.0,
            end: 1.0,
            frequency: 0.0,
            phase_deg: 0.0,
            exponential: 0.0,
            power: 0.0,
        };
        assert_eq!(step.value(0.0), 1.0, "t̃⁰ = 1 at the start");
    }
}
