//! Virtual-sensing cards of `SOL ESTIMATE` (augmented EKF, thesis ch. 8): `EKF`, `EKFPAR`,
//! `EKFINP`, `MEASF`, `MEAS`, and `AMANDA` (the AMANDA-EKF on a mechanism, thesis ch. 9). Same
//! field rules as the other extension cards; every bad field is reported, not only the first.

use crate::card_values::Column;
use crate::card_values::{
    MAX_REDIAGONALIZATION_TOLERANCE, Prediction, valid_rediagonalization_tolerance,
};
use crate::deck::error::{DeckError, Loc};
use crate::deck::fields::RawCard;
use crate::deck::reader::FieldReader;
use crate::deck::value::Value;

/// `EKF` — filter settings, selected by case control `ESTIM = id`.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | ID | int > 0 | required | id |
/// | 3 | QSTATE | real > 0 | machine ε | diagonal of Q for q and q̇ (thesis §8.5.2: Q_q = Q_q̇ = εI); on a mechanism for q only, q̇'s on `AMANDA` |
/// | 4 | P0STATE | real > 0 | 1.0E-20 | initial variance of q and q̇; on a mechanism of q only, q̇'s on `AMANDA` |
/// | 5 | FORCE | `YES` `NO` | NO | run even when the observability check fails |
/// | 6 | REDIAG | real in (0, 0.1] | blank | re-diagonalized modal coordinates with this drift tolerance when the estimated parameters change a pROM part that no modes diagonalize (blank: exact coordinates, the pROM's own when modal ones do not apply; paraflex-specific) |
/// | 7 | PREDICT | `TRAP` `BDF1` | TRAP | the prediction's time discretization: the trapezoidal rule (no numerical damping) or BDF1 (the thesis's eq. 8.22, exact on data made by BDF1); paraflex-specific |
#[derive(Debug, Clone, PartialEq)]
pub struct Ekf {
    pub id: u32,
    pub q_state: f64,
    pub p0_state: f64,
    pub force: bool,
    pub rediagonalize: Option<f64>,
    pub prediction: Prediction,
    pub loc: Loc,
}

impl Ekf {
    /// Read an `EKF` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let id = f.id(1, "ID");
        f.set_id(id);
        let q_state = optional_positive(&mut f, 2, "QSTATE", f64::EPSILON);
        let p0_state = optional_positive(&mut f, 3, "P0STATE", 1.0e-20);
        let force = f.keyword(4, "FORCE", &["YES", "NO"], Some("NO")) == "YES";
        let rediagonalize = f.opt_real(5, "REDIAG");
        if let Some(t) = rediagonalize.filter(|t| !valid_rediagonalization_tolerance(*t)) {
            f.error(
                5,
                "REDIAG",
                format!("expected a real in (0, {MAX_REDIAGONALIZATION_TOLERANCE}], found {t:e}"),
            );
        }
        let prediction = f.choice(
            6,
            "PREDICT",
            &[Prediction::Trapezoidal, Prediction::Bdf1].map(|p| (p.card_name(), p)),
            Some(Prediction::Trapezoidal),
        );
        let loc = f.loc();
        f.finish(6)?;
        Ok(Ekf {
            id,
            q_state,
            p0_state,
            force,
            rediagonalize,
            prediction,
            loc,
        })
    }
}

/// `EKFPAR` — an unknown pROM parameter of the `EKF` with the same id.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | ID | int > 0 | required | the EKF id |
/// | 3 | NAME | name | required | PMPAR name in the pROM; on a mechanism `BODY.PMPAR` of a flexible body |
/// | 4 | INIT | real ≠ 0 | required | initial guess p₀ |
/// | 5 | DELTA | real > 0 | required | δ_p in Hz: Q_p = (Δt δ_p INIT)² (eq. 8.31) |
/// | 6 | P0 | real > 0 | INIT² | initial variance |
#[derive(Debug, Clone, PartialEq)]
pub struct Ekfpar {
    pub id: u32,
    pub name: String,
    pub init: f64,
    pub delta: f64,
    pub p0: f64,
    pub loc: Loc,
}

impl Ekfpar {
    /// Read an `EKFPAR` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let id = f.id(1, "ID");
        f.set_id(id);
        let name = f.text(2, "NAME");
        let init = f.real(3, "INIT");
        if init == 0.0 && matches!(f.value(3), Value::Real(_)) {
            f.error(3, "INIT", "the initial guess must not be zero (a zero parameter has no physical meaning, thesis §8.3)");
        }
        let delta = f.positive_real(4, "DELTA");
        let p0 = optional_positive(&mut f, 5, "P0", init * init);
        let loc = f.loc();
        f.finish(5)?;
        Ok(Ekfpar {
            id,
            name,
            init,
            delta,
            p0,
            loc,
        })
    }
}

/// `EKFINP` — an unknown input of the `EKF` with the same id: a pROM input DOF (GRID, COMP),
/// or on a mechanism the amplitude of an `MFORCE` / `MMOMENT` (GRID its id, COMP blank; the
/// element's table is not used).
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | ID | int > 0 | required | the EKF id |
/// | 3 | GRID | int > 0 | required | grid of the input DOF; on a mechanism the MFORCE or MMOMENT id |
/// | 4 | COMP | int 1–6 | blank | component (required for a pROM input DOF, blank on a mechanism) |
/// | 5 | OMEGA | real > 0 | required | ω_u in Hz: Q_u = (Δt ω_u a_u)² (eq. 8.30) |
/// | 6 | AMPL | real > 0 | required | expected amplitude a_u (also the input's P₀ = a_u²) |
#[derive(Debug, Clone, PartialEq)]
pub struct Ekfinp {
    pub id: u32,
    pub grid: u32,
    pub component: Option<u8>,
    pub omega: f64,
    pub amplitude: f64,
    pub loc: Loc,
}

impl Ekfinp {
    /// Read an `EKFINP` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let id = f.id(1, "ID");
        f.set_id(id);
        let grid = f.id(2, "GRID");
        let component = f.opt_int(3, "COMP");
        if let Some(c) = component.filter(|c| !(1..=6).contains(c)) {
            f.error(3, "COMP", format!("expected one component 1–6, found {c}"));
        }
        let omega = f.positive_real(4, "OMEGA");
        let amplitude = f.positive_real(5, "AMPL");
        let loc = f.loc();
        f.finish(5)?;
        Ok(Ekfinp {
            id,
            grid,
            component: component.map(|c| c.clamp(1, 6) as u8),
            omega,
            amplitude,
            loc,
        })
    }
}

/// `MEASF` — a CSV file of measurements, selected by case control `MEAS = id`.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | ID | int > 0 | required | id |
/// | 3 | PATH | quoted string | required | CSV file, relative to the file holding the card |
/// | 4 | TCOL | int ≥ 1 or name | 1 | time column |
#[derive(Debug, Clone, PartialEq)]
pub struct Measf {
    pub id: u32,
    pub path: String,
    pub tcol: Column,
    pub loc: Loc,
}

impl Measf {
    /// Read a `MEASF` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let id = f.id(1, "ID");
        f.set_id(id);
        let path = f.path(2, "PATH");
        let tcol = if f.value(3).is_blank() {
            Column::Index(1)
        } else {
            f.column(3, "TCOL")
        };
        let loc = f.loc();
        f.finish(3)?;
        Ok(Measf {
            id,
            path,
            tcol,
            loc,
        })
    }
}

/// `MEAS` — one measured channel of the `MEASF` with the same id.
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | ID | int > 0 | required | the MEASF id |
/// | 3 | SENSOR | name | required | SENSOR name in the pROM; on a mechanism an MSENSOR name (kind STRAIN, POS or ACCEL) |
/// | 4 | COLUMN | int ≥ 1 or name | required | CSV column |
/// | 5 | SIGMA | real > 0 | required | noise standard deviation (R = σ²) |
#[derive(Debug, Clone, PartialEq)]
pub struct Meas {
    pub id: u32,
    pub sensor: String,
    pub column: Column,
    pub sigma: f64,
    pub loc: Loc,
}

impl Meas {
    /// Read a `MEAS` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let id = f.id(1, "ID");
        f.set_id(id);
        let sensor = f.text(2, "SENSOR");
        let column = if f.value(3).is_blank() {
            f.error(
                3,
                "COLUMN",
                "expected a 1-based column index or a column name, found a blank field",
            );
            Column::Index(1)
        } else {
            f.column(3, "COLUMN")
        };
        let sigma = f.positive_real(4, "SIGMA");
        let loc = f.loc();
        f.finish(4)?;
        Ok(Meas {
            id,
            sensor,
            column,
            sigma,
            loc,
        })
    }
}

/// `AMANDA` — settings of the AMANDA-EKF (thesis ch. 9) on a mechanism.
///
/// Read with the `EKF` of the same id when `SOL ESTIMATE` runs on a mechanism (bodies in the
/// deck or `FMB = 'file.h5'`).
///
/// | field | name | type | default | meaning |
/// |---|---|---|---|---|
/// | 2 | ID | int > 0 | required | the EKF id |
/// | 3 | TOL | real > 0 | 1.0E-10 | the AMANDA step (eq. 9.9–9.14) ends when max \|Φ\| and max \|Φ_q v + Φ_t\| are below TOL |
/// | 4 | MAXIT | int > 0 | 10 | Gauss–Newton iterations of the AMANDA step before the kinematic-assembly fallback |
/// | 5 | FREEZE | real > 0 | blank | a parameter's update is frozen at a step where its largest reading sensitivity max_i \|∂h_i/∂θ\| / σ_i (θ = p / INIT, along the prior trajectory: noise σ per 100 % change) is below FREEZE (§9.3.2); blank: never frozen |
/// | 6 | QVEL | real > 0 | EKF QSTATE | Q of the velocity coordinates (the EKF's QSTATE is the positions'); paraflex-specific |
/// | 7 | P0VEL | real > 0 | EKF P0STATE | initial variance of the velocities (the EKF's P0STATE is the positions'); paraflex-specific |
/// | 8 | OBSEVERY | int > 0 | blank | the numerical observability of the linearized filter (§9.3.1) over a window starting every OBSEVERY steps along the run, written and summarized; blank: at the start only; paraflex-specific |
/// | 9 | RANK | int > 0 | blank | before the run, rank the subcase's STRAIN MSENSORs as candidate gauges by the information they add about the unknowns over the first RANK steps of the prior trajectory (greedy, log det of the unknowns' predicted covariance; each with the largest σ of the MEAS on strain gauges), written and printed with the prediction for the measured set; blank: no ranking; paraflex-specific |
#[derive(Debug, Clone, PartialEq)]
pub struct Amanda {
    pub id: u32,
    pub tolerance: f64,
    pub max_iterations: u32,
    pub freeze: Option<f64>,
    pub q_velocities: Option<f64>,
    pub p0_velocities: Option<f64>,
    pub observe_every: Option<u32>,
    pub rank: Option<u32>,
    pub loc: Loc,
}

impl Amanda {
    /// Read an `AMANDA` card.
    pub fn from_card(card: &RawCard) -> Result<Self, Vec<DeckError>> {
        let mut f = FieldReader::new(card);
        let id = f.id(1, "ID");
        f.set_id(id);
        let tolerance = optional_positive(&mut f, 2, "TOL", 1e-10);
        let max_iterations = f.opt_count(3, "MAXIT").unwrap_or(10);
        let freeze = blank_or_positive(&mut f, 4, "FREEZE");
        let q_velocities = blank_or_positive(&mut f, 5, "QVEL");
        let p0_velocities = blank_or_positive(&mut f, 6, "P0VEL");
        let observe_every = f.opt_count(7, "OBSEVERY");
        let rank = f.opt_count(8, "RANK");
        let loc = f.loc();
        f.finish(8)?;
        Ok(Amanda {
            id,
            tolerance,
            max_iterations,
            freeze,
            q_velocities,
            p0_velocities,
            observe_every,
            rank,
            loc,
        })
    }
}

/// A real that must be > 0 when given; `None` when blank.
fn blank_or_positive(f: &mut FieldReader, i: usize, name: &str) -> Option<f64> {
    let v = f.opt_real(i, name)?;
    if v <= 0.0 {
        f.error(i, name, format!("expected a real > 0, found {v:e}"));
    }
    Some(v)
}

/// A real that must be > 0 when given; `default` when blank.
fn optional_positive(f: &mut FieldReader, i: usize, name: &str, default: f64) -> f64 {
    match f.opt_real(i, name) {
        Some(v) if v <= 0.0 => {
            f.error(i, name, format!("expected a real > 0, found {v:e}"));
            default
        }
        Some(v) => v,
        None => default,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::card_values::Column;

    use crate::deck::fields::card_from_line as card;

    #[test]
    fn cards_read_with_defaults() {
        let e = Ekf::from_card(&card("EKF,3")).unwrap();
        assert_eq!(
            (e.id, e.q_state, e.p0_state, e.force, e.rediagonalize),
            (3, f64::EPSILON, 1e-20, false, None)
        );
        assert_eq!(e.prediction, Prediction::Trapezoidal);
        let e = Ekf::from_card(&card("EKF,3,1.e-12,1.e-10,YES,1.e-2,bdf1")).unwrap();
        assert_eq!(
            (
                e.q_state,
                e.p0_state,
                e.force,
                e.rediagonalize,
                e.prediction
            ),
            (1e-12, 1e-10, true, Some(1e-2), Prediction::Bdf1)
        );
        let e = Ekf::from_card(&card("EKF,3,,,,,TRAP")).unwrap();
        assert_eq!(e.prediction, Prediction::Trapezoidal);
        let p = Ekfpar::from_card(&card("EKFPAR,3,e,2.5e11,1.e-3")).unwrap();
        assert_eq!(
            (p.name.as_str(), p.init, p.delta, p.p0),
            ("E", 2.5e11, 1e-3, 2.5e11 * 2.5e11)
        );
        let u = Ekfinp::from_card(&card("EKFINP,3,12,3,80.,5.")).unwrap();
        assert_eq!(
            (u.grid, u.component, u.omega, u.amplitude),
            (12, Some(3), 80.0, 5.0)
        );
        let u = Ekfinp::from_card(&card("EKFINP,3,7,,150.,10.")).unwrap();
        assert_eq!((u.grid, u.component), (7, None));
        let m = Measf::from_card(&card("MEASF,4,'meas.csv',time")).unwrap();
        assert_eq!(
            (m.path.as_str(), m.tcol.clone()),
            ("meas.csv", Column::Name("time".into()))
        );
        let a = Amanda::from_card(&card("AMANDA,3")).unwrap();
        assert_eq!(
            (a.tolerance, a.max_iterations, a.freeze, a.q_velocities),
            (1e-10, 10, None, None)
        );
        let a = Amanda::from_card(&card("AMANDA,3,1.e-9,4,0.5,1.e-14,1.e-10")).unwrap();
        assert_eq!(
            (a.tolerance, a.max_iterations, a.freeze),
            (1e-9, 4, Some(0.5))
        );
        assert_eq!(
            (a.q_velocities, a.p0_velocities),
            (Some(1e-14), Some(1e-10))
        );
        let m = Meas::from_card(&card("MEAS,4,S1,3,1.e-7")).unwrap();
        assert_eq!(
            (m.sensor.as_str(), m.column.clone(), m.sigma),
            ("S1", Column::Index(3), 1e-7)
        );
    }

    /// Every bad field is reported, each naming its field.
    #[test]
    fn every_bad_field_is_reported() {
        let errors = Ekf::from_card(&card("EKF,3,-1.,0.,MAYBE,0.5,BDF2")).unwrap_err();
        assert_eq!(errors.len(), 5, "{errors:?}");
        assert!(
            errors.iter().any(|e| e.to_string().contains("PREDICT")),
            "{errors:?}"
        );
        assert!(
            errors.iter().any(|e| e.to_string().contains("REDIAG")),
            "{errors:?}"
        );
        let errors = Ekfpar::from_card(&card("EKFPAR,3,E,0.,-1.,-2.")).unwrap_err();
        let text: Vec<String> = errors.iter().map(|e| e.to_string()).collect();
        assert_eq!(errors.len(), 3, "{text:?}");
        assert!(
            text.iter()
                .any(|t| t.contains("INIT") && t.contains("zero")),
            "{text:?}"
        );
        assert_eq!(
            Ekfinp::from_card(&card("EKFINP,3,12,7,-80.,"))
                .unwrap_err()
                .len(),
            3
        );
        assert_eq!(
            Amanda::from_card(&card("AMANDA,3,0.,-2,-1.,0.,x"))
                .unwrap_err()
                .len(),
            5
        );
        assert_eq!(
            Meas::from_card(&card("MEAS,4,S1,,0.")).unwrap_err().len(),
            2
        );
        assert_eq!(
            Measf::from_card(&card("MEASF,4,,,extra"))
                .unwrap_err()
                .len(),
            2
        );
    }
}
