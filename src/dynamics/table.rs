//! Tabulated functions of time (TABLED1): piecewise-linear interpolation between the points,
//! the end values held outside the table (a load defined on [t₁, tₙ] stays at its last value;
//! stated in docs/dynamics.md, Nastran's TABLED1 extrapolates linearly unless told otherwise).

/// A piecewise-linear table y(x) with increasing abscissae.
#[derive(Debug, Clone, PartialEq)]
pub struct Table {
    x: Vec<f64>,
    y: Vec<f64>,
}

/// Why a table is refused.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum TableError {
    #[error("the table has no point")]
    Empty,
    #[error("abscissae must increase: x[{index}] = {value} follows {previous}")]
    NotIncreasing {
        index: usize,
        value: f64,
        previous: f64,
    },
}

impl Table {
    /// A table from (x, y) points.
    pub fn new(points: &[(f64, f64)]) -> Result<Self, TableError> {
        if points.is_empty() {
            return Err(TableError::Empty);
        }
        for (k, w) in points.windows(2).enumerate() {
            if !(w[1].0 > w[0].0) {
                return Err(TableError::NotIncreasing {
                    index: k + 1,
                    value: w[1].0,
                    previous: w[0].0,
                });
            }
        }
        Ok(Table {
            x: points.iter().map(|p| p.0).collect(),
            y: points.iter().map(|p| p.1).collect(),
        })
    }

    /// y(x).
    pub fn value(&self, x: f64) -> f64 {
        let n = self.x.len();
        if x <= self.x[0] {
            return self.y[0];
        }
        if x >= self.x[n - 1] {
            return self.y[n - 1];
        }
        let k = self.x.partition_point(|&v| v <= x);
        let (x0, x1, y0, y1) = (self.x[k - 1], self.x[k], self.y[k - 1], self.y[k]);
        y0 + (y1 - y0) * (x - x0) / (x1 - x0)
    }

    /// The abscissae x₁ < … < xₙ.
    pub fn abscissae(&self) -> &[f64] {
        &self.x
    }

    /// The ordinates y₁ … yₙ.
    pub fn ordinates(&self) -> &[f64] {
        &self.y
    }

    /// dy/dx: the slope of the segment holding x (of the segment starting at x on a point), zero
    /// outside the table.
    pub fn slope(&self, x: f64) -> f64 {
        let n = self.x.len();
        if x < self.x[0] || x >= self.x[n - 1] {
            return 0.0;
        }
        let k = self.x.partition_point(|&v| v <= x);
        (self.y[k] - self.y[k - 1]) / (self.x[k] - self.x[k - 1])
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
            Table::new(&[(0.0, 1.0), (0.0, 2.0)]),
            Err(TableError::NotIncreasing { index: 1, .. })
        ));
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
}
