//! Time functions with their first two derivatives: drive motions and force histories.

use std::fmt;
use std::sync::Arc;

/// f(t) with ḟ(t) and f̈(t), as `[f, ḟ, f̈]`.
#[derive(Clone)]
pub struct Signal(Arc<dyn Fn(f64) -> [f64; 3] + Send + Sync>);

impl fmt::Debug for Signal {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("Signal")
    }
}

impl Signal {
    /// A function returning `[f, ḟ, f̈]` at t.
    pub fn new(f: impl Fn(f64) -> [f64; 3] + Send + Sync + 'static) -> Self {
        Self(Arc::new(f))
    }
    /// f = c.
    pub fn constant(c: f64) -> Self {
        Self::new(move |_| [c, 0.0, 0.0])
    }
    /// f = ω t (a constant rate).
    pub fn ramp(rate: f64) -> Self {
        Self::new(move |t| [rate * t, rate, 0.0])
    }
    /// f = a sin(2π f t).
    pub fn sine(amplitude: f64, frequency: f64) -> Self {
        let w = 2.0 * std::f64::consts::PI * frequency;
        Self::new(move |t| {
            let (s, c) = (w * t).sin_cos();
            [amplitude * s, amplitude * w * c, -amplitude * w * w * s]
        })
    }
    /// `[f, ḟ, f̈]` at t.
    pub fn at(&self, t: f64) -> [f64; 3] {
        (self.0)(t)
    }
}
