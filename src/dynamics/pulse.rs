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

    /// (F, F', F'') at t (measured from the load's delay), the right-hand limits at T1 and
    /// T2 (zero from T2 on): with h = t̃^B e^{C t̃} and c = cos(2πF t̃ + P),
    /// F' = h'c + hc', F'' = h''c + 2h'c' + hc''. A growth exponent 0 < B < 2 has an infinite
    /// derivative at T1 (t̃^{B−1} or t̃^{B−2}); it is returned as such.
    pub fn derivatives(&self, t: f64) -> [f64; 3] {
        let local = t - self.start;
        if local < 0.0 || local >= self.end - self.start {
            return [0.0; 3];
        }
        let (b, c) = (self.power, self.exponential);
        // t̃^e, with 0^0 = 1; a term whose coefficient is zero is dropped (no 0 · ∞)
        let power = |coefficient: f64, e: f64| {
            if coefficient == 0.0 {
                0.0
            } else if e == 0.0 {
                coefficient
            } else {
                coefficient * local.powf(e)
            }
        };
        let exp = (c * local).exp();
        let h = [
            power(1.0, b) * exp,
            (power(b, b - 1.0) + power(c, b)) * exp,
            (power(b * (b - 1.0), b - 2.0) + power(2.0 * b * c, b - 1.0) + power(c * c, b)) * exp,
        ];
        let w = 2.0 * std::f64::consts::PI * self.frequency;
        let angle = w * local + self.phase_deg.to_radians();
        let (sin, cos) = angle.sin_cos();
        let k = [cos, -w * sin, -w * w * cos];
        [
            h[0] * k[0],
            h[1] * k[0] + h[0] * k[1],
            h[2] * k[0] + 2.0 * h[1] * k[1] + h[0] * k[2],
        ]
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
        assert_eq!(step.derivatives(0.0), [1.0, 0.0, 0.0]);
        assert_eq!(step.derivatives(1.0), [0.0; 3], "zero from T2 on");
    }

    #[test]
    fn pulse_derivatives_match_central_differences() {
        // h = 1e-4 on a pulse whose second derivative is O(1e3): the central differences'
        // truncation (h²/6 F''' ~ 1e-4 relative) dominates their round-off (ε F / h² ~ 1e-8).
        for power in [0.0, 1.0, 2.0, 2.5] {
            let p = Pulse {
                start: 0.1,
                end: 2.0,
                frequency: 1.5,
                phase_deg: 40.0,
                exponential: -0.7,
                power,
            };
            let h = 1e-4;
            for t in [0.4, 1.1, 1.7] {
                let [f, d1, d2] = p.derivatives(t);
                assert!((f - p.value(t)).abs() < 1e-14);
                let fd1 = (p.value(t + h) - p.value(t - h)) / (2.0 * h);
                let fd2 = (p.value(t + h) - 2.0 * f + p.value(t - h)) / (h * h);
                let scale = 1.0 + d1.abs() + d2.abs();
                assert!(
                    (d1 - fd1).abs() < 1e-5 * scale,
                    "B {power} t {t}: {d1} {fd1}"
                );
                assert!(
                    (d2 - fd2).abs() < 1e-4 * scale,
                    "B {power} t {t}: {d2} {fd2}"
                );
            }
            // at T1: the right-hand limits (B = 0: C and C² times the cosine terms)
            let [f, d1, _] = p.derivatives(0.1);
            if power == 0.0 {
                let w = 3.0 * std::f64::consts::PI;
                let (s, c) = 40f64.to_radians().sin_cos();
                assert!((f - c).abs() < 1e-15 && (d1 - (-0.7 * c - w * s)).abs() < 1e-12);
            }
        }
    }
}
