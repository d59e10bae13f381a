//! Observability of an augmented system before a run: the PBH test (thesis eq. 7.28,
//! 8.40–8.41) on the linearization of a process model around operating points of the initial
//! estimate, for any model that gives its linearization ([`Linearization`]; the pROM's is
//! [`super::prom_linearization::PromLinearization`]).
//!
//! - **s = 0** (the critical value: the random-walk states add zero eigenvalues, §7.5.1):
//!   PBH(0) = [−J_c; J_m] (block rows of −J_c may be multiplied by invertible matrices, which
//!   keeps the rank; the random walks' rows are zero and left out). Rows and columns are scaled
//!   to unit norm (rank-invariant; parameters and states differ by 20 orders of magnitude) and
//!   the numerical rank counts the singular values above [`RANK_TOLERANCE`] × σ_max. The
//!   parameter columns depend on the operating point (zero at rest), so the test runs at each
//!   operating point the caller supplies (the response of the initial estimate to the loads)
//!   and passes when one has full rank.
//! - **s = λ_i ≠ 0**, the eigenvalues of J_c: the rows of u and p are s·I there, so PBH(λ_i)
//!   loses rank exactly when a mode of the model is invisible to the measured rows
//!   ([`Linearization::hidden_modes`]). These modes stay stable (detectable, §7.5.1), so they
//!   are reported, not refused.
//!
//! When PBH(0) is deficient everywhere, the null vector names the unknowns that cannot be told
//! apart, and the cause is named as in thesis §8.4.3–8.4.4.

use faer::Mat;

use super::ekf::Linearization;
use super::measurement::Reads;

/// Relative singular-value threshold of the numerical rank of the equilibrated PBH matrix:
/// exact dependencies (a zero column, proportional columns) land at round-off (≲ 1e-13), while
/// genuinely independent unknowns of the validation cases stay above 1e-6.
pub const RANK_TOLERANCE: f64 = 1e-9;

/// A state to linearize around: q, q̇, q̈ and whether it is a static equilibrium.
#[derive(Debug, Clone)]
pub struct OperatingPoint {
    pub q: Vec<f64>,
    pub v: Vec<f64>,
    pub a: Vec<f64>,
    pub dynamic: bool,
}

/// What an unknown is, for naming causes.
#[derive(Debug, Clone, PartialEq)]
pub enum Unknown {
    Input(String),
    /// A parameter: name, whether it enters K, whether it enters M.
    Parameter {
        name: String,
        stiffness: bool,
        mass: bool,
    },
}

impl Unknown {
    fn name(&self) -> &str {
        match self {
            Unknown::Input(n) | Unknown::Parameter { name: n, .. } => n,
        }
    }
}

/// The outcome of the check.
#[derive(Debug, Clone)]
pub struct Observability {
    /// Numerical rank and size of PBH(0) at the best operating point.
    pub rank: usize,
    pub columns: usize,
    /// Smallest / largest singular value there.
    pub ratio: f64,
    /// Why the system is unobservable at s = 0 (None when observable).
    pub cause: Option<String>,
    /// Modes (1-based, with frequency in Hz) that no measured row sees.
    pub hidden_modes: Vec<(usize, f64)>,
}

impl Observability {
    pub fn observable(&self) -> bool {
        self.cause.is_none()
    }
}

/// Run the PBH test of `model` at `points` (see the module documentation).
pub fn check<L: Linearization>(model: &L, points: &[OperatingPoint]) -> Observability {
    let big_n = model.size();
    let unknowns = model.unknowns();
    let mut best: Option<(usize, f64, Vec<f64>, bool)> = None;
    for point in points {
        let (rank, ratio, null) = numerical_rank(&model.pbh_zero(point));
        if best.as_ref().is_none_or(|b| (rank, ratio) > (b.0, b.1)) {
            best = Some((rank, ratio, null, point.dynamic));
        }
    }
    let (rank, ratio, null, dynamic) = best.unwrap_or((0, 0.0, vec![1.0; big_n], false));
    let cause = (rank < big_n).then(|| {
        name_cause(
            &null[big_n - unknowns.len()..],
            unknowns,
            model.reads(),
            dynamic,
        )
    });
    Observability {
        rank,
        columns: big_n,
        ratio,
        cause,
        hidden_modes: model.hidden_modes(),
    }
}

/// Numerical rank of `a` after unit-norm row and column scaling, σ_min/σ_max, and the right
/// singular vector of the smallest singular value (in scaled columns).
fn numerical_rank(a: &Mat<f64>) -> (usize, f64, Vec<f64>) {
    let (rows, cols) = (a.nrows(), a.ncols());
    let norm = |v: &mut dyn Iterator<Item = f64>| v.map(|x| x * x).sum::<f64>().sqrt();
    let rn: Vec<f64> = (0..rows)
        .map(|r| norm(&mut (0..cols).map(|c| a[(r, c)])))
        .collect();
    let scaled_rows = Mat::from_fn(rows, cols, |r, c| {
        if rn[r] > 0.0 { a[(r, c)] / rn[r] } else { 0.0 }
    });
    let cn: Vec<f64> = (0..cols)
        .map(|c| norm(&mut (0..rows).map(|r| scaled_rows[(r, c)])))
        .collect();
    let b = Mat::from_fn(rows, cols, |r, c| {
        if cn[c] > 0.0 {
            scaled_rows[(r, c)] / cn[c]
        } else {
            0.0
        }
    });
    let Ok(svd) = b.svd() else {
        return (0, 0.0, vec![1.0; cols]);
    };
    let s: Vec<f64> = (0..rows.min(cols))
        .map(|i| svd.S().column_vector()[i])
        .collect();
    let max = s.iter().copied().fold(0.0, f64::max);
    let rank = s.iter().filter(|&&x| x > RANK_TOLERANCE * max).count();
    let min = if rows >= cols {
        s.iter().copied().fold(f64::INFINITY, f64::min)
    } else {
        0.0
    };
    // the null direction: the last right singular vector (singular values descend)
    let v = svd.V();
    let null = (0..cols).map(|i| v[(i, cols - 1)]).collect();
    (rank, if max > 0.0 { min / max } else { 0.0 }, null)
}

/// Name the reason PBH(0) is deficient (thesis §8.4.3–8.4.4). `null`: the null vector's
/// entries on the unknowns (inputs first, then parameters).
fn name_cause(null: &[f64], unknowns: &[Unknown], reads: &[Reads], dynamic: bool) -> String {
    let displacement_rows = reads.iter().filter(|r| **r == Reads::Displacement).count();
    let count = unknowns.len();
    if displacement_rows == 0 && count > 0 {
        return format!(
            "only accelerometers (or velocity sensors) are measured: their rows are combinations of the equation of motion and add no information at s = 0, so the {count} unknown(s) need at least {count} STRAIN or DISP sensor(s) (thesis §8.4.3)"
        );
    }
    if displacement_rows < count {
        return format!(
            "fewer strain/displacement sensors ({displacement_rows}) than unknown inputs and parameters ({count}): at least one per unknown is needed (thesis §8.4.3)"
        );
    }
    let involved: Vec<&Unknown> = unknowns
        .iter()
        .zip(null)
        .filter(|(_, v)| v.abs() > 0.1)
        .map(|(u, _)| u)
        .collect();
    let names = |list: &[&Unknown]| {
        list.iter()
            .map(|u| u.name().to_string())
            .collect::<Vec<_>>()
            .join(", ")
    };
    let stiffness = involved.iter().any(|u| {
        matches!(
            u,
            Unknown::Parameter {
                stiffness: true,
                ..
            }
        )
    });
    let mass = involved.iter().any(|u| {
        matches!(
            u,
            Unknown::Parameter {
                mass: true,
                stiffness: false,
                ..
            }
        )
    });
    let input = involved.iter().any(|u| matches!(u, Unknown::Input(_)));
    let load = if dynamic {
        "without a known dynamic input"
    } else {
        "under a static load"
    };
    match (stiffness, mass, input) {
        (false, true, false) if !dynamic => format!(
            "{} (mass parameter) cannot be observed under a static load: the inertia is not excited (thesis §8.4.3)",
            names(&involved)
        ),
        (true, true, _) => format!(
            "stiffness and mass parameters {} cannot be estimated together {load}: their effects on the response are proportional (E and ρ, thesis §8.4.4)",
            names(&involved)
        ),
        (true, false, true) if !dynamic => format!(
            "{} cannot be estimated together: a stiffness parameter and a static unknown input are indistinguishable (E with a static input, thesis §8.4.4)",
            names(&involved)
        ),
        _ => format!(
            "the unknowns {} cannot be told apart by the measured sensors at s = 0 ({})",
            names(&involved),
            if dynamic {
                "dynamic operating point"
            } else {
                "static operating point"
            }
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::estimate::filter::tests::chain;
    use crate::estimate::measurement::SensorRows;
    use crate::estimate::prom_linearization::PromLinearization;
    use faer::linalg::solvers::Solve;

    struct Case {
        params: Vec<usize>,
        inputs: usize,
        kinds: Vec<&'static str>,
    }

    /// The chain; `single`: without its constant spring (one material, thesis §8.4.4).
    fn prom(single: bool) -> crate::rom::prom::Prom {
        let mut p = chain();
        if single {
            p.stiffness[0].fill(0.0);
        }
        p
    }

    /// Check the chain with `case` at `point` (p = nominal).
    fn run(case: &Case, point: OperatingPoint, single: bool) -> Observability {
        let prom = prom(single);
        let mut at = prom.workspace();
        prom.evaluate(&[1.0, 1.0], &mut at).unwrap();
        let s_un = Mat::from_fn(2, case.inputs, |i, _| i as f64);
        let names = ["E", "RHO"];
        let mut unknowns: Vec<Unknown> = (0..case.inputs)
            .map(|k| Unknown::Input(format!("U{k}")))
            .collect();
        unknowns.extend(case.params.iter().map(|&j| Unknown::Parameter {
            name: names[j].into(),
            stiffness: j == 0,
            mass: j == 1,
        }));
        let k = case.kinds.len();
        let sensors = SensorRows::new(
            (0..k).map(|r| format!("S{r}")).collect(),
            case.kinds.iter().map(|s| s.to_string()).collect(),
            Mat::from_fn(k, 2, |r, c| if r % 2 == c { 1.0 } else { 0.3 }),
        )
        .unwrap();
        let (lambda, phi) =
            crate::linalg::dense::generalized_eigen(at.stiffness(), at.mass()).unwrap();
        let linearization = PromLinearization {
            at: &at,
            alpha_beta: (prom.alpha, prom.beta),
            s_un: &s_un,
            params: &case.params,
            unknowns: &unknowns,
            measured: &sensors,
            modes: (&lambda, &phi),
        };
        check(&linearization, &[point])
    }

    /// Static equilibrium under a load on DOF 2, and a dynamic point with that load (q̈ from
    /// the equation of motion) or without load (free response).
    fn points(single: bool) -> (OperatingPoint, OperatingPoint, OperatingPoint) {
        let prom = prom(single);
        let mut at = prom.workspace();
        prom.evaluate(&[1.0, 1.0], &mut at).unwrap();
        let f = Mat::from_fn(2, 1, |i, _| i as f64 * 3.0);
        let q = at.stiffness().llt(faer::Side::Lower).unwrap().solve(&f);
        let col = |m: &Mat<f64>| vec![m[(0, 0)], m[(1, 0)]];
        let statics = OperatingPoint {
            q: col(&q),
            v: vec![0.0; 2],
            a: vec![0.0; 2],
            dynamic: false,
        };
        let (qd, vd) = (
            Mat::from_fn(2, 1, |i, _| [1e-3, -4e-4][i]),
            Mat::from_fn(2, 1, |i, _| [0.2, 0.5][i]),
        );
        let accel = |load: f64| {
            col(&at
                .mass()
                .llt(faer::Side::Lower)
                .unwrap()
                .solve(&(&f * faer::Scale(load) - at.stiffness() * &qd - at.damping() * &vd)))
        };
        let forced = OperatingPoint {
            q: col(&qd),
            v: col(&vd),
            a: accel(1.0),
            dynamic: true,
        };
        let free = OperatingPoint {
            q: col(&qd),
            v: col(&vd),
            a: accel(0.0),
            dynamic: true,
        };
        (statics, forced, free)
    }

    /// The generic and particular results of thesis §8.4.3–8.4.4 on a 2-DOF chain with one
    /// stiffness and one mass parameter; the particular ones (E and ρ in free response, E with a
    /// static input) need one material for everything (no constant spring), as in §8.4.4.
    #[test]
    fn thesis_observability_results_are_reproduced() {
        let (statics, forced, _) = points(false);
        let (single_statics, _, free) = points(true);
        let two_disp = vec!["DISP", "STRAIN"];
        let e = Case {
            params: vec![0],
            inputs: 0,
            kinds: two_disp.clone(),
        };
        assert!(
            run(&e, statics.clone(), false).observable(),
            "E under a static load is observable"
        );
        let e_rho = Case {
            params: vec![0, 1],
            inputs: 0,
            kinds: two_disp.clone(),
        };
        assert!(
            run(&e_rho, forced.clone(), false).observable(),
            "E and ρ under a known dynamic load are observable"
        );
        let cause = run(&e_rho, statics.clone(), false).cause.unwrap();
        assert!(
            cause.contains("RHO") && cause.contains("static load"),
            "{cause}"
        );
        let cause = run(&e_rho, free, true).cause.unwrap();
        assert!(
            cause.contains("E, RHO") && cause.contains("without a known dynamic input"),
            "{cause}"
        );
        let rho = Case {
            params: vec![1],
            inputs: 0,
            kinds: two_disp.clone(),
        };
        assert!(
            run(&rho, statics.clone(), false)
                .cause
                .unwrap()
                .contains("mass parameter")
        );
        let e_input = Case {
            params: vec![0],
            inputs: 1,
            kinds: two_disp.clone(),
        };
        assert!(
            run(&e_input, forced.clone(), false).observable(),
            "E and a dynamic input are observable"
        );
        let cause = run(&e_input, single_statics, true).cause.unwrap();
        assert!(cause.contains("static input"), "{cause}");
        let cause = run(
            &Case {
                params: vec![0],
                inputs: 0,
                kinds: vec!["ACCEL", "ACCEL"],
            },
            forced.clone(),
            false,
        )
        .cause
        .unwrap();
        assert!(cause.contains("only accelerometers"), "{cause}");
        let cause = run(
            &Case {
                params: vec![0, 1],
                inputs: 0,
                kinds: vec!["DISP", "ACCEL"],
            },
            forced,
            false,
        )
        .cause
        .unwrap();
        assert!(
            cause.contains(
                "fewer strain/displacement sensors (1) than unknown inputs and parameters (2)"
            ),
            "{cause}"
        );
        assert!(run(&e, statics, false).hidden_modes.is_empty());
    }
}
