//! Stationary random response from frequency responses (Nastran's RANDPS/RANDOM analysis).
//!
//! An output with complex responses H_a(f) to the loads of subcases a (per unit of the load,
//! as the frequency response computed them) under input spectral densities
//! S_ab(f) = (X + iY)·G(f) has the power spectral density
//! S_y(f) = |Σ_(a ≤ b) c_ab G(f) Re(H_a (X + iY) conj(H_b))|, c_aa = 1, c_ab = 2 for a < b
//! ([`output_psd`]): each RANDPS with J < K stands for both S_JK and S_KJ = conj(S_JK).
//! The mean square, the expected zero-crossing rate N0 and the autocorrelation R(τ) integrate
//! S_y assuming it linear between the frequency lines ([`Moments`], [`autocorrelation`]):
//! the rule of NASTRAN-95's RAND3/RAND4 (public COSMIC source, `mis/rand3.f90`), which MSC
//! Nastran keeps as its default (`PARAM,RMSINT,LINEAR`).

use std::f64::consts::PI;

/// The spectral density G(f) of a RANDPS.
#[derive(Debug, Clone, PartialEq)]
pub enum Spectrum {
    /// TID = 0: G = 1.
    Unit,
    /// TABRND1: (f, g) points interpolated linearly in the axes' scales (ln for a LOG axis),
    /// extrapolated from the end segments, the mean (in the y scale) at a jump.
    Table {
        points: Vec<(f64, f64)>,
        log_x: bool,
        log_y: bool,
    },
    /// TABRNDG: 2 WG² LU (1 + 2(p + 1) k² LU² ω²)/(1 + k² LU² ω²)^(p + 3/2), ω = 2πf.
    Gust { p: f64, k: f64, lu: f64, wg: f64 },
}

impl Spectrum {
    /// The von Kármán (p = 1/3, k = 1.339) or Dryden (p = 1/2, k = 1) gust spectrum of
    /// TABRNDG, as NASTRAN-95's PRETAB evaluates it.
    pub fn gust(von_karman: bool, lu: f64, wg: f64) -> Self {
        let (p, k) = if von_karman {
            (1.0 / 3.0, 1.339)
        } else {
            (0.5, 1.0)
        };
        Spectrum::Gust { p, k, lu, wg }
    }

    /// G(f); `None` where a LOG x axis meets f ≤ 0.
    pub fn value(&self, f: f64) -> Option<f64> {
        match self {
            Spectrum::Unit => Some(1.0),
            Spectrum::Gust { p, k, lu, wg } => {
                let t = (k * lu * 2.0 * PI * f).powi(2);
                Some(2.0 * wg * wg * lu * (1.0 + 2.0 * (p + 1.0) * t) / (1.0 + t).powf(p + 1.5))
            }
            Spectrum::Table {
                points,
                log_x,
                log_y,
            } => {
                if *log_x && f <= 0.0 {
                    return None;
                }
                let sx = |x: f64| if *log_x { x.ln() } else { x };
                let sy = |y: f64| if *log_y { y.ln() } else { y };
                let mut pts: Vec<(f64, f64)> =
                    points.iter().map(|&(x, y)| (sx(x), sy(y))).collect();
                if pts[0].0 > pts[pts.len() - 1].0 {
                    pts.reverse();
                }
                let u = sx(f);
                let n = pts.len();
                // a jump: the mean of its two ordinates
                if let Some(w) = pts.windows(2).find(|w| w[0].0 == u && w[1].0 == u) {
                    let v = 0.5 * (w[0].1 + w[1].1);
                    return Some(if *log_y { v.exp() } else { v });
                }
                let i = pts[1..n - 1].iter().take_while(|p| p.0 <= u).count();
                let ((x0, y0), (x1, y1)) = (pts[i], pts[i + 1]);
                let v = y0 + (u - x0) * (y1 - y0) / (x1 - x0);
                Some(if *log_y { v.exp() } else { v })
            }
        }
    }
}

/// One input spectral density of a random analysis: S_ab = (X + iY)·G(f) between the loads
/// `a` and `b` (indices into the responses), a ≤ b.
#[derive(Debug, Clone, PartialEq)]
pub struct InputPsd {
    pub a: usize,
    pub b: usize,
    pub x: f64,
    pub y: f64,
    /// G at each frequency line.
    pub g: Vec<f64>,
}

/// S_y at each line of one output, from its responses `h[a][line]` to each load.
pub fn output_psd(h: &[&[faer::c64]], inputs: &[InputPsd]) -> Vec<f64> {
    let lines = h.first().map_or(0, |r| r.len());
    (0..lines)
        .map(|l| {
            let s: f64 = inputs
                .iter()
                .map(|p| {
                    let two = if p.a == p.b { 1.0 } else { 2.0 };
                    let z = h[p.a][l] * faer::c64::new(p.x, p.y) * h[p.b][l].conj();
                    two * p.g[l] * z.re
                })
                .sum();
            s.abs()
        })
        .collect()
}

/// The RMS value and the expected rate of zero crossings with positive slope N0 of a PSD
/// given at frequency lines `f` (ascending), S linear between lines:
/// RMS² = Σ (S_i + S_(i+1)) Δf/2 (trapezoid) and N0 = √(∫ f² S df / RMS²), the numerator
/// integrated exactly: Δf/12 [(3f_i² + 2f_i f_(i+1) + f_(i+1)²) S_i + (f_i² + 2f_i f_(i+1) + 3f_(i+1)²) S_(i+1)].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Moments {
    pub rms: f64,
    pub n0: f64,
}

impl Moments {
    pub fn of(f: &[f64], s: &[f64]) -> Self {
        let (mut m0, mut m2) = (0.0, 0.0);
        for i in 0..f.len().saturating_sub(1) {
            let (a, b) = (f[i], f[i + 1]);
            let df = b - a;
            m0 += 0.5 * (s[i] + s[i + 1]) * df;
            m2 += df / 12.0
                * ((3.0 * a * a + 2.0 * a * b + b * b) * s[i]
                    + (a * a + 2.0 * a * b + 3.0 * b * b) * s[i + 1]);
        }
        let rms = m0.sqrt();
        let n0 = if m0 > 0.0 { (m2 / m0).sqrt() } else { 0.0 };
        Moments { rms, n0 }
    }
}

/// R(τ) = ∫ S(f) cos(2πfτ) df over the lines, S linear between them, integrated exactly
/// (R(0) = RMS²).
pub fn autocorrelation(f: &[f64], s: &[f64], tau: f64) -> f64 {
    if tau == 0.0 {
        return Moments::of(f, s).rms.powi(2);
    }
    let a = 2.0 * PI * tau;
    let sum: f64 = (0..f.len().saturating_sub(1))
        .map(|i| {
            let slope = (s[i + 1] - s[i]) / (f[i + 1] - f[i]);
            slope / a * ((a * f[i + 1]).cos() - (a * f[i]).cos()) + s[i + 1] * (a * f[i + 1]).sin()
                - s[i] * (a * f[i]).sin()
        })
        .sum();
    sum / a
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A flat PSD S0 on [f1, f2]: RMS² = S0 (f2 − f1), N0² = (f2³ − f1³)/(3 (f2 − f1)), and
    /// R(τ) = S0 (sin 2πf2τ − sin 2πf1τ)/(2πτ) — exact for any line spacing.
    #[test]
    fn flat_spectrum_moments_and_autocorrelation_are_exact() {
        let f = [10.0, 13.0, 50.0, 100.0];
        let s = [2.0; 4];
        let m = Moments::of(&f, &s);
        assert!((m.rms - (2.0f64 * 90.0).sqrt()).abs() < 1e-12);
        let n0 = ((100f64.powi(3) - 10f64.powi(3)) / (3.0 * 90.0)).sqrt();
        assert!((m.n0 - n0).abs() < 1e-12 * n0);
        let tau = 0.0123;
        let w = 2.0 * PI * tau;
        let exact = 2.0 * ((w * 100.0).sin() - (w * 10.0).sin()) / w;
        assert!((autocorrelation(&f, &s, tau) - exact).abs() < 1e-12);
        assert!((autocorrelation(&f, &s, 0.0) - 180.0).abs() < 1e-12);
    }

    /// A ramp S = f on [0, 2]: ∫ S = 2, ∫ f² S = 4, so N0 = √2 (the trapezoid is exact on a
    /// linear S); R(τ) against ∫₀² f cos(2πfτ) df = [cos ωf + ωf sin ωf]/ω² from 0 to 2.
    #[test]
    fn ramp_spectrum_matches_its_closed_form() {
        let f = [0.0, 0.5, 2.0];
        let s = [0.0, 0.5, 2.0];
        let m = Moments::of(&f, &s);
        assert!((m.rms - 2f64.sqrt()).abs() < 1e-12);
        assert!((m.n0 - 2f64.sqrt()).abs() < 1e-12);
        let tau = 0.3;
        let w = 2.0 * PI * tau;
        let exact = ((w * 2.0).cos() + w * 2.0 * (w * 2.0).sin() - 1.0) / (w * w);
        assert!((autocorrelation(&f, &s, tau) - exact).abs() < 1e-12);
    }

    /// TABRND1 LOG/LOG through (10, 1) and (1000, 100): g = f/10 inside and on the
    /// extrapolated line, and the geometric mean at a jump; the Dryden spectrum at f = 0 is
    /// 2 WG² LU and falls as 1/ω² (factor 3/(k² LU² ω²) · 2 WG² LU / 1) far out.
    #[test]
    fn tables_and_gust_spectra_evaluate_as_nastran() {
        let t = Spectrum::Table {
            points: vec![(10.0, 1.0), (1000.0, 100.0)],
            log_x: true,
            log_y: true,
        };
        for f in [10.0, 31.6, 1000.0, 5000.0, 2.0] {
            assert!((t.value(f).unwrap() - f / 10.0).abs() < 1e-12 * f);
        }
        assert_eq!(t.value(0.0), None);
        let jump = Spectrum::Table {
            points: vec![(0.0, 1.0), (5.0, 1.0), (5.0, 4.0), (9.0, 4.0)],
            log_x: false,
            log_y: true,
        };
        assert!((jump.value(5.0).unwrap() - 2.0).abs() < 1e-12);
        assert!((jump.value(7.0).unwrap() - 4.0).abs() < 1e-12);
        let d = Spectrum::gust(false, 0.2, 6.0);
        assert!((d.value(0.0).unwrap() - 2.0 * 36.0 * 0.2).abs() < 1e-12);
        let f = 1e4;
        let w = 2.0 * PI * f * 0.2;
        let far = 2.0 * 36.0 * 0.2 * 3.0 / (w * w);
        assert!((d.value(f).unwrap() / far - 1.0).abs() < 1e-6);
    }
}
