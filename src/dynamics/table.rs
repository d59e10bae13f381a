//! Tabulated functions of time or frequency (TABLED1–TABLED4, TABLEF).
//!
//! - **Points** (TABLED1, and TABLED2/TABLED3 once their abscissae are mapped back to x):
//!   piecewise-linear interpolation between the points, the end values held outside the table
//!   (a load defined on [t₁, tₙ] stays at its last value; stated in docs/dynamics.md: Nastran
//!   extrapolates linearly from the two end points instead). Abscissae may be given in
//!   decreasing order, and two consecutive points may share an abscissa (a jump) except at
//!   either end: on the jump the value is the mean of the two ordinates, as Nastran's.
//! - **Power series** (TABLED4): y = Σᵢ aᵢ ((x − X1)/X2)ⁱ with x clamped to [X3, X4].

/// A tabulated function y(x).
#[derive(Debug, Clone, PartialEq)]
pub struct Table {
    form: Form,
}

#[derive(Debug, Clone, PartialEq)]
enum Form {
    Points { x: Vec<f64>, y: Vec<f64> },
    PowerSeries(PowerSeries),
}

/// TABLED4's y = Σᵢ aᵢ ((x − X1)/X2)ⁱ, x clamped to [X3, X4].
#[derive(Debug, Clone, PartialEq)]
pub struct PowerSeries {
    /// X1.
    pub shift: f64,
    /// X2 (≠ 0).
    pub scale: f64,
    /// X3 < X4: the range x is clamped to.
    pub range: (f64, f64),
    /// a₀, a₁, …
    pub coefficients: Vec<f64>,
}

impl PowerSeries {
    /// The derivative of order ≥ 1 at x inside [X3, X4] (Horner on the differentiated
    /// coefficients i!/(i − order)! aᵢ, over X2^order), zero outside, where y is clamped.
    fn derivative(&self, x: f64, order: usize) -> f64 {
        if x < self.range.0 || x > self.range.1 {
            return 0.0;
        }
        let u = (x - self.shift) / self.scale;
        let falling = |i: usize| ((i + 1 - order)..=i).product::<usize>() as f64;
        let sum = (self.coefficients.iter().enumerate().skip(order).rev())
            .fold(0.0, |acc, (i, a)| acc * u + falling(i) * a);
        sum / self.scale.powi(order as i32)
    }
}

/// Why a table is refused.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum TableError {
    #[error("the table has no point")]
    Empty,
    #[error(
        "abscissae must be monotonic (all increasing or all decreasing): x[{index}] = {value} follows {previous}"
    )]
    NotMonotonic {
        index: usize,
        value: f64,
        previous: f64,
    },
    #[error(
        "a jump (two points at x = {value}) is allowed between interior points only, not at the table's {end}"
    )]
    JumpAtEnd { value: f64, end: &'static str },
    #[error("three points share x = {value}: a jump has two")]
    ThreePointsAt { value: f64 },
    #[error("a point is not finite: ({x}, {y})")]
    NotFinite { x: f64, y: f64 },
    #[error("X2 must not be zero")]
    ZeroScale,
    #[error("X3 = {low} must be below X4 = {high}")]
    EmptyRange { low: f64, high: f64 },
    #[error("a power series needs at least one coefficient")]
    NoCoefficient,
}

impl Table {
    /// A piecewise-linear table through (x, y) points (see the module documentation).
    pub fn new(points: &[(f64, f64)]) -> Result<Self, TableError> {
        if points.is_empty() {
            return Err(TableError::Empty);
        }
        if let Some(&(x, y)) = points
            .iter()
            .find(|(x, y)| !x.is_finite() || !y.is_finite())
        {
            return Err(TableError::NotFinite { x, y });
        }
        let decreasing = points.last().unwrap().0 < points[0].0;
        for (k, w) in points.windows(2).enumerate() {
            let ordered = if decreasing {
                w[1].0 <= w[0].0
            } else {
                w[1].0 >= w[0].0
            };
            if !ordered {
                return Err(TableError::NotMonotonic {
                    index: k + 1,
                    value: w[1].0,
                    previous: w[0].0,
                });
            }
        }
        let mut sorted = points.to_vec();
        if decreasing {
            sorted.reverse();
        }
        let n = sorted.len();
        if n >= 2 {
            for (a, b, end) in [(0, 1, "start"), (n - 2, n - 1, "end")] {
                if sorted[a].0 == sorted[b].0 {
                    return Err(TableError::JumpAtEnd {
                        value: sorted[a].0,
                        end,
                    });
                }
            }
        }
        if let Some(w) = sorted.windows(3).find(|w| w[0].0 == w[2].0) {
            return Err(TableError::ThreePointsAt { value: w[0].0 });
        }
        Ok(Table {
            form: Form::Points {
                x: sorted.iter().map(|p| p.0).collect(),
                y: sorted.iter().map(|p| p.1).collect(),
            },
        })
    }

    /// A TABLED4 power series.
    pub fn power_series(series: PowerSeries) -> Result<Self, TableError> {
        if series.scale == 0.0 {
            return Err(TableError::ZeroScale);
        }
        let (low, high) = series.range;
        if !(low < high) {
            return Err(TableError::EmptyRange { low, high });
        }
        if series.coefficients.is_empty() {
            return Err(TableError::NoCoefficient);
        }
        Ok(Table {
            form: Form::PowerSeries(series),
        })
    }

    /// y(x).
    pub fn value(&self, x: f64) -> f64 {
        match &self.form {
            Form::Points { x: xs, y } => {
                let n = xs.len();
                if x <= xs[0] {
                    return y[0];
                }
                if x >= xs[n - 1] {
                    return y[n - 1];
                }
                let k = xs.partition_point(|&v| v <= x);
                if xs[k - 1] == x && k >= 2 && xs[k - 2] == x {
                    return 0.5 * (y[k - 2] + y[k - 1]);
                }
                let (x0, x1, y0, y1) = (xs[k - 1], xs[k], y[k - 1], y[k]);
                y0 + (y1 - y0) * (x - x0) / (x1 - x0)
            }
            Form::PowerSeries(s) => {
                let u = (x.clamp(s.range.0, s.range.1) - s.shift) / s.scale;
                s.coefficients.iter().rev().fold(0.0, |acc, a| acc * u + a)
            }
        }
    }

    /// dy/dx: for points, the slope of the segment holding x (of the segment starting at x on a
    /// point, the one after a jump on a jump), zero outside the table; for a power series, its
    /// derivative inside [X3, X4] and zero outside.
    pub fn slope(&self, x: f64) -> f64 {
        match &self.form {
            Form::Points { x: xs, y } => {
                let n = xs.len();
                if x < xs[0] || x >= xs[n - 1] {
                    return 0.0;
                }
                let k = xs.partition_point(|&v| v <= x);
                (y[k] - y[k - 1]) / (xs[k] - xs[k - 1])
            }
            Form::PowerSeries(s) => s.derivative(x, 1),
        }
    }

    /// d²y/dx²: zero for a table of points (between its points), the power series' second
    /// derivative inside [X3, X4] and zero outside.
    pub fn curvature(&self, x: f64) -> f64 {
        match &self.form {
            Form::Points { .. } => 0.0,
            Form::PowerSeries(s) => s.derivative(x, 2),
        }
    }

    /// The abscissae (increasing, a jump's twice) and ordinates of a table of points; `None`
    /// for a power series.
    pub fn points(&self) -> Option<(&[f64], &[f64])> {
        match &self.form {
            Form::Points { x, y } => Some((x, y)),
            Form::PowerSeries(_) => None,
        }
    }

    /// The power series of a TABLED4; `None` for a table of points.
    pub fn series(&self) -> Option<&PowerSeries> {
        match &self.form {
            Form::Points { .. } => None,
            Form::PowerSeries(s) => Some(s),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn interpolates_and_holds_the_ends() {
        let t = Table::new(&[(0.0, 0.0), (1.0, 2.0), (3.0, -2.0)]).unwrap();
        for (x, y) in [
            (-1.0, 0.0),
            (0.0, 0.0),
            (0.25, 0.5),
            (1.0, 2.0),
            (2.0, 0.0),
            (3.0, -2.0),
            (9.0, -2.0),
        ] {
            assert_eq!(t.value(x), y, "x = {x}");
        }
        assert_eq!(Table::new(&[]), Err(TableError::Empty));
        assert!(matches!(
            Table::new(&[(0.0, 1.0), (2.0, 2.0), (1.0, 0.0)]),
            Err(TableError::NotMonotonic { index: 2, .. })
        ));
        assert!(matches!(
            Table::new(&[(0.0, 1.0), (f64::NAN, 2.0)]),
            Err(TableError::NotFinite { .. })
        ));
    }

    #[test]
    fn a_decreasing_table_is_the_same_function() {
        let up = Table::new(&[(0.0, 0.0), (1.0, 2.0), (3.0, -2.0)]).unwrap();
        let down = Table::new(&[(3.0, -2.0), (1.0, 2.0), (0.0, 0.0)]).unwrap();
        assert_eq!(up, down);
    }

    #[test]
    fn a_jump_takes_the_mean_on_it_and_its_sides_elsewhere() {
        // A step of 1 at x = 1: Nastran's TABLED1 remark (mean value on the discontinuity).
        let t = Table::new(&[(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (2.0, 1.0)]).unwrap();
        assert_eq!(t.value(1.0 - 1e-12), 0.0);
        assert_eq!(t.value(1.0), 0.5);
        assert_eq!(t.value(1.0 + 1e-12), 1.0);
        assert_eq!(t.slope(1.0), 0.0);
        for bad in [
            vec![(0.0, 0.0), (0.0, 1.0), (1.0, 1.0)],
            vec![(0.0, 0.0), (1.0, 1.0), (1.0, 2.0)],
        ] {
            assert!(
                matches!(Table::new(&bad), Err(TableError::JumpAtEnd { .. })),
                "{bad:?}"
            );
        }
        assert_eq!(
            Table::new(&[(0.0, 0.0), (1.0, 1.0), (1.0, 2.0), (1.0, 3.0), (2.0, 0.0)]),
            Err(TableError::ThreePointsAt { value: 1.0 })
        );
    }

    #[test]
    fn slope_is_the_segment_slope_and_zero_outside() {
        let t = Table::new(&[(0.0, 0.0), (1.0, 2.0), (3.0, -2.0)]).unwrap();
        for (x, s) in [
            (-1.0, 0.0),
            (0.0, 2.0),
            (0.5, 2.0),
            (1.0, -2.0),
            (2.9, -2.0),
            (3.0, 0.0),
        ] {
            assert_eq!(t.slope(x), s, "x = {x}");
        }
    }

    #[test]
    fn a_power_series_is_clamped_to_its_range() {
        // y = 1 + 2u − u², u = (x − 1)/2, x in [0, 5].
        let t = Table::power_series(PowerSeries {
            shift: 1.0,
            scale: 2.0,
            range: (0.0, 5.0),
            coefficients: vec![1.0, 2.0, -1.0],
        })
        .unwrap();
        let exact = |x: f64| {
            let u = (x - 1.0) / 2.0;
            1.0 + 2.0 * u - u * u
        };
        for x in [0.0, 0.7, 3.0, 5.0] {
            assert!((t.value(x) - exact(x)).abs() < 1e-15, "x = {x}");
            let slope = (1.0 - (x - 1.0) / 2.0) * 2.0 / 2.0;
            assert!((t.slope(x) - slope).abs() < 1e-15, "x = {x}");
            assert_eq!(t.curvature(x), -0.5, "x = {x}: y'' = −2 / X2²");
        }
        assert_eq!(t.value(-3.0), exact(0.0));
        assert_eq!(t.value(9.0), exact(5.0));
        assert_eq!(t.slope(9.0), 0.0);
        assert_eq!(t.curvature(9.0), 0.0);
        let bad = |scale, range| {
            Table::power_series(PowerSeries {
                shift: 0.0,
                scale,
                range,
                coefficients: vec![1.0],
            })
        };
        assert_eq!(bad(0.0, (0.0, 1.0)), Err(TableError::ZeroScale));
        assert!(matches!(
            bad(1.0, (1.0, 1.0)),
            Err(TableError::EmptyRange { .. })
        ));
    }
}
