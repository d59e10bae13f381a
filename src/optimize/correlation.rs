//! The Pearson correlation coefficient of eq. 6.2, ρ(x, y) = cov(x, y) / (σ_x σ_y) =
//! Σ (x_i − μ_x)(y_i − μ_y) / √(Σ (x_i − μ_x)² Σ (y_i − μ_y)²): the linear correlation between
//! a design variable and a response over the designs of a study (the thesis's eq. 6.2 writes
//! the sum over the pairs in front of the normalized product; the normalization by σ_x σ_y
//! belongs to the sum, so that ρ ∈ [−1, 1]).

/// ρ(x, y) of eq. 6.2; NaN when either series is constant or the series are shorter than 2.
pub fn pearson(x: &[f64], y: &[f64]) -> f64 {
    let n = x.len().min(y.len());
    if n < 2 {
        return f64::NAN;
    }
    let mean = |v: &[f64]| v[..n].iter().sum::<f64>() / n as f64;
    let (mx, my) = (mean(x), mean(y));
    let (mut sxy, mut sxx, mut syy) = (0.0, 0.0, 0.0);
    for (a, b) in x[..n].iter().zip(&y[..n]) {
        sxy += (a - mx) * (b - my);
        sxx += (a - mx) * (a - mx);
        syy += (b - my) * (b - my);
    }
    if sxx == 0.0 || syy == 0.0 {
        return f64::NAN;
    }
    sxy / (sxx * syy).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn linear_anti_linear_and_constant_series() {
        let x = [1.0, 2.0, 3.0, 4.0];
        assert!((pearson(&x, &[3.0, 5.0, 7.0, 9.0]) - 1.0).abs() < 1e-15);
        assert!((pearson(&x, &[4.0, 3.0, 2.0, 1.0]) + 1.0).abs() < 1e-15);
        assert!(pearson(&x, &[2.0; 4]).is_nan());
        // hand value: x = (1,2,3), y = (1,3,2): Σxy' = 1, Σx'² = 2, Σy'² = 2 → 0.5
        assert!((pearson(&[1.0, 2.0, 3.0], &[1.0, 3.0, 2.0]) - 0.5).abs() < 1e-15);
    }
}
