//! Ply failure indices of the PCOMP failure theories (field FT) from a ply's stresses or strains
//! in its own axes ([`crate::fe::laminate::PlyState`]) and the MAT8 allowables (positive
//! magnitudes; Xc = Xt and Yc = Yt when blank). In-plane terms only, as the theories are stated
//! (Jones, *Mechanics of Composite Materials*, 2nd ed., 1999, §2.9; Hoffman, J. Compos. Mater.
//! 1 (1967) 200–206; Tsai & Wu, J. Compos. Mater. 5 (1971) 58–80). An index ≥ 1 means failure.
//!
//! ```text
//! HILL  σ1²/X² − σ1σ2/X² + σ2²/Y² + τ12²/S²       X = Xt if σ1 ≥ 0 else Xc, Y likewise by σ2
//! HOFF  (1/Xt − 1/Xc)σ1 + (1/Yt − 1/Yc)σ2 + σ1²/(XtXc) + σ2²/(YtYc) − σ1σ2/(XtXc) + τ12²/S²
//! TSAI  (1/Xt − 1/Xc)σ1 + (1/Yt − 1/Yc)σ2 + σ1²/(XtXc) + σ2²/(YtYc) + τ12²/S² + 2F12σ1σ2
//! STRN  max(ε1/Xt or −ε1/Xc, ε2/Yt or −ε2/Yc, |γ12|/S)   (allowables are strains: MAT8 STRN = 1)
//! ```

use crate::card_values::{FailureTheory, PlyAllowables};

/// Why a ply has no failure index under a theory.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FailureError {
    /// An allowable the theory needs is blank.
    #[error("{theory} needs MAT8 {field}")]
    Missing {
        theory: &'static str,
        field: &'static str,
    },
    /// An allowable is not positive.
    #[error("MAT8 {field} = {value} must be positive")]
    NonPositive { field: &'static str, value: f64 },
    /// STRN with stress allowables.
    #[error("STRN needs strain allowables (MAT8 STRN = 1.0)")]
    StressAllowables,
}

/// The allowables a theory reads, checked: (Xt, Xc, Yt, Yc, S).
fn strengths(
    theory: FailureTheory,
    a: &PlyAllowables,
) -> Result<(f64, f64, f64, f64, f64), FailureError> {
    let get = |field: &'static str, v: Option<f64>| {
        let v = v.ok_or(FailureError::Missing {
            theory: theory.keyword(),
            field,
        })?;
        if v > 0.0 && v.is_finite() {
            Ok(v)
        } else {
            Err(FailureError::NonPositive { field, value: v })
        }
    };
    Ok((
        get("Xt", a.xt)?,
        get("Xc", a.xc)?,
        get("Yt", a.yt)?,
        get("Yc", a.yc)?,
        get("S", a.s)?,
    ))
}

/// Checks that `theory` can be evaluated with the allowables `a` (module doc).
pub fn check(theory: FailureTheory, a: &PlyAllowables) -> Result<(), FailureError> {
    strengths(theory, a)?;
    match theory {
        FailureTheory::TsaiWu if a.f12.is_none() => Err(FailureError::Missing {
            theory: "TSAI",
            field: "F12",
        }),
        FailureTheory::MaxStrain if !a.strain_allowables => Err(FailureError::StressAllowables),
        FailureTheory::Hill | FailureTheory::Hoffman if a.strain_allowables => {
            Err(FailureError::Missing {
                theory: theory.keyword(),
                field: "stress allowables (STRN blank)",
            })
        }
        _ => Ok(()),
    }
}

/// The failure index of a ply with stresses `stress` = [σ1, σ2, τ12, …] and strains
/// `strain` = [ε1, ε2, γ12, …] in its axes (module doc).
pub fn failure_index(
    theory: FailureTheory,
    a: &PlyAllowables,
    stress: &[f64; 5],
    strain: &[f64; 5],
) -> Result<f64, FailureError> {
    check(theory, a)?;
    let (xt, xc, yt, yc, s) = strengths(theory, a)?;
    let [s1, s2, t12, ..] = *stress;
    let linear = (1.0 / xt - 1.0 / xc) * s1 + (1.0 / yt - 1.0 / yc) * s2;
    let quadratic = s1 * s1 / (xt * xc) + s2 * s2 / (yt * yc) + t12 * t12 / (s * s);
    Ok(match theory {
        FailureTheory::Hill => {
            let x = if s1 >= 0.0 { xt } else { xc };
            let y = if s2 >= 0.0 { yt } else { yc };
            (s1 * s1 - s1 * s2) / (x * x) + s2 * s2 / (y * y) + t12 * t12 / (s * s)
        }
        FailureTheory::Hoffman => linear + quadratic - s1 * s2 / (xt * xc),
        FailureTheory::TsaiWu => linear + quadratic + 2.0 * a.f12.unwrap_or(0.0) * s1 * s2,
        FailureTheory::MaxStrain => {
            let ratio = |e: f64, t: f64, c: f64| if e >= 0.0 { e / t } else { -e / c };
            ratio(strain[0], xt, xc)
                .max(ratio(strain[1], yt, yc))
                .max(strain[2].abs() / s)
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn allowables() -> PlyAllowables {
        PlyAllowables {
            xt: Some(1500e6),
            xc: Some(1200e6),
            yt: Some(50e6),
            yc: Some(250e6),
            s: Some(70e6),
            f12: Some(-1.0e-18),
            strain_allowables: false,
        }
    }

    /// Each theory gives 1 at each uniaxial strength (Hill, Hoffman, Tsai–Wu are built so).
    #[test]
    fn uniaxial_strengths_give_an_index_of_one() {
        let a = allowables();
        for theory in [
            FailureTheory::Hill,
            FailureTheory::Hoffman,
            FailureTheory::TsaiWu,
        ] {
            for stress in [
                [1500e6, 0.0, 0.0, 0.0, 0.0],
                [-1200e6, 0.0, 0.0, 0.0, 0.0],
                [0.0, 50e6, 0.0, 0.0, 0.0],
                [0.0, -250e6, 0.0, 0.0, 0.0],
                [0.0, 0.0, -70e6, 0.0, 0.0],
            ] {
                let fi = failure_index(theory, &a, &stress, &[0.0; 5]).unwrap();
                assert!((fi - 1.0).abs() < 1e-12, "{theory:?} {stress:?}: {fi}");
            }
        }
    }

    #[test]
    fn max_strain_needs_strain_allowables_and_tsai_wu_needs_f12() {
        let a = allowables();
        assert_eq!(
            check(FailureTheory::MaxStrain, &a),
            Err(FailureError::StressAllowables)
        );
        let strain = PlyAllowables {
            xt: Some(0.01),
            xc: Some(0.008),
            yt: Some(0.005),
            yc: Some(0.02),
            s: Some(0.015),
            f12: None,
            strain_allowables: true,
        };
        let fi = failure_index(
            FailureTheory::MaxStrain,
            &strain,
            &[0.0; 5],
            &[-0.004, 0.004, 0.0, 0.0, 0.0],
        )
        .unwrap();
        assert!((fi - 0.8).abs() < 1e-12);
        let no_f12 = PlyAllowables { f12: None, ..a };
        assert!(check(FailureTheory::TsaiWu, &no_f12).is_err());
        let no_s = PlyAllowables { s: None, ..a };
        assert_eq!(
            check(FailureTheory::Hill, &no_s).unwrap_err().to_string(),
            "HILL needs MAT8 S"
        );
    }
}
