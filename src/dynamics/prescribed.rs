//! Prescribed motion of constrained DOFs in time integration (enforced displacement, velocity
//! or acceleration: Nastran's TLOAD1/TLOAD2 with TYPE = DISP, VELO or ACCE on SPCD DOFs).
//!
//! The unknowns u obey M_uu ü + C_uu u̇ + K_uu u = f(t) − (M_us ü_s + C_us u̇_s + K_us u_s) with
//! the moved DOFs u_s = Σ_j e_j g_j(t): each term j is a fixed pattern e_j of the constrained
//! DOFs times a scalar motion g_j, and contributes the coupling columns M_us e_j, C_us e_j,
//! K_us e_j (absolute formulation: u is the absolute displacement, the stiffness coupling
//! carries the quasi-static part).
//!
//! The scalar kinematics (g, ġ, g̈) of each term follow the integration method's own update
//! from the driven quantity sampled at the step times: a DISP term fixes g_{n+1} and takes
//! ġ, g̈ from the method's difference formulas, a VELO term fixes ġ_{n+1}, an ACCE term g̈_{n+1},
//! and the method integrates the others. The moved DOFs are then exactly what the same method
//! would compute for them if they were unknowns whose motion is known, so a kink of a tabulated
//! displacement (an impulse in g̈) is resolved as any discrete motion is, without a Dirac
//! sampled at the step times. The balance of generalized-α reads the α-shifted kinematics
//! (g̈ at n+1−α_m, ġ and g at n+1−α_f) as it does for the unknowns.
//!
//! Start: each term's (g, ġ, g̈) at t₀ is given by the caller ([`PrescribedTerm::initial`]):
//! for a motion that starts at t₀ these are the right-hand limits, so a velocity or
//! acceleration that jumps at t₀ jumps there and is not spread over the first step.

/// Which kinematic quantity a term's function gives.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Drive {
    Displacement,
    Velocity,
    Acceleration,
}

/// One prescribed term: the driven quantity of g_j as a function of absolute time, and the
/// coupling columns (M_us e_j, C_us e_j, K_us e_j) on the unknowns.
pub struct PrescribedTerm<'a> {
    pub drive: Drive,
    pub function: Box<dyn Fn(f64) -> f64 + 'a>,
    /// (g, ġ, g̈) at the start time.
    pub initial: [f64; 3],
    pub mass: Vec<f64>,
    pub damping: Vec<f64>,
    pub stiffness: Vec<f64>,
}

/// The prescribed terms of a run and their scalar kinematics (g, ġ, g̈) as the integration
/// advances.
#[derive(Default)]
pub struct PrescribedMotion<'a> {
    terms: Vec<PrescribedTerm<'a>>,
    current: Vec<[f64; 3]>,
    previous: Vec<[f64; 3]>,
    /// The kinematics the balance of the current step reads (α-shifted for generalized-α).
    balance: Vec<[f64; 3]>,
}

/// The parameters of the generalized-α update.
#[derive(Debug, Clone, Copy)]
pub(crate) struct AlphaUpdate {
    pub dt: f64,
    pub beta: f64,
    pub gamma: f64,
    pub alpha_m: f64,
    pub alpha_f: f64,
}

impl<'a> PrescribedMotion<'a> {
    /// The terms, each of whose columns has the unknowns' length.
    pub fn new(terms: Vec<PrescribedTerm<'a>>) -> Self {
        let n = terms.len();
        PrescribedMotion {
            terms,
            current: vec![[0.0; 3]; n],
            previous: vec![[0.0; 3]; n],
            balance: vec![[0.0; 3]; n],
        }
    }

    /// Length of the coupling columns (`None` without terms).
    pub(crate) fn columns(&self) -> Option<usize> {
        self.terms.first().map(|t| t.mass.len())
    }

    /// (g, ġ, g̈) of every term at the last step.
    pub fn kinematics(&self) -> &[[f64; 3]] {
        &self.current
    }

    /// The start state (each term's [`PrescribedTerm::initial`]); the balance reads it.
    pub(crate) fn start(&mut self) {
        for (j, term) in self.terms.iter().enumerate() {
            self.current[j] = term.initial;
        }
        self.previous.clone_from(&self.current);
        self.balance.clone_from(&self.current);
    }

    /// One BDF step to `t` with the method's coefficient `c` (1: BDF1, 3/2: BDF2), whose
    /// history is r = x_n (BDF1) or 2x_n − x_{n−1}/2 (BDF2): ġ = (c g − r_g)/Δt and
    /// g̈ = (c ġ − r_ġ)/Δt, solved for the quantities the drive does not fix.
    pub(crate) fn advance_bdf(&mut self, t: f64, dt: f64, c: f64) {
        for (j, term) in self.terms.iter().enumerate() {
            let (now, before) = (self.current[j], self.previous[j]);
            let r = |k: usize| {
                if c == 1.0 {
                    now[k]
                } else {
                    2.0 * now[k] - 0.5 * before[k]
                }
            };
            let x = (term.function)(t);
            let next = match term.drive {
                Drive::Displacement => {
                    let v = (c * x - r(0)) / dt;
                    [x, v, (c * v - r(1)) / dt]
                }
                Drive::Velocity => [(r(0) + dt * x) / c, x, (c * x - r(1)) / dt],
                Drive::Acceleration => {
                    let v = (r(1) + dt * x) / c;
                    [(r(0) + dt * v) / c, v, x]
                }
            };
            self.previous[j] = now;
            self.current[j] = next;
            self.balance[j] = next;
        }
    }

    /// One generalized-α (Newmark) step to `t`: with g̃ = g + Δt ġ + (½−β)Δt² g̈ and
    /// ġ̃ = ġ + (1−γ)Δt g̈, g_{n+1} = g̃ + βΔt² g̈_{n+1} and ġ_{n+1} = ġ̃ + γΔt g̈_{n+1}, solved
    /// for the quantities the drive does not fix; the balance reads
    /// ((1−α_f) g_{n+1} + α_f g_n, (1−α_f) ġ_{n+1} + α_f ġ_n, (1−α_m) g̈_{n+1} + α_m g̈_n).
    pub(crate) fn advance_alpha(&mut self, t: f64, p: AlphaUpdate) {
        let AlphaUpdate {
            dt,
            beta,
            gamma,
            alpha_m,
            alpha_f,
        } = p;
        for (j, term) in self.terms.iter().enumerate() {
            let [g, v, a] = self.current[j];
            let g_pred = g + dt * v + (0.5 - beta) * dt * dt * a;
            let v_pred = v + (1.0 - gamma) * dt * a;
            let x = (term.function)(t);
            let a_next = match term.drive {
                Drive::Displacement => (x - g_pred) / (beta * dt * dt),
                Drive::Velocity => (x - v_pred) / (gamma * dt),
                Drive::Acceleration => x,
            };
            let next = [
                g_pred + beta * dt * dt * a_next,
                v_pred + gamma * dt * a_next,
                a_next,
            ];
            self.balance[j] = [
                (1.0 - alpha_f) * next[0] + alpha_f * g,
                (1.0 - alpha_f) * next[1] + alpha_f * v,
                (1.0 - alpha_m) * next[2] + alpha_m * a,
            ];
            self.previous[j] = self.current[j];
            self.current[j] = next;
        }
    }

    /// f −= Σ_j (M_us e_j g̈_j + C_us e_j ġ_j + K_us e_j g_j) at the balance's kinematics.
    pub(crate) fn subtract_coupling(&self, f: &mut [f64]) {
        for (term, &[g, v, a]) in self.terms.iter().zip(&self.balance) {
            for (i, fi) in f.iter_mut().enumerate() {
                *fi -= term.mass[i] * a + term.damping[i] * v + term.stiffness[i] * g;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn term(
        drive: Drive,
        function: impl Fn(f64) -> f64 + 'static,
        initial: [f64; 3],
    ) -> PrescribedTerm<'static> {
        PrescribedTerm {
            drive,
            function: Box::new(function),
            initial,
            mass: vec![1.0],
            damping: vec![0.0],
            stiffness: vec![0.0],
        }
    }

    /// g(t) = t² (ġ = 2t, g̈ = 2) given as each quantity, from the start state `initial`.
    fn quadratic_terms(initial: [f64; 3]) -> PrescribedMotion<'static> {
        PrescribedMotion::new(vec![
            term(Drive::Displacement, |t| t * t, initial),
            term(Drive::Velocity, |t| 2.0 * t, initial),
            term(Drive::Acceleration, |_| 2.0, initial),
        ])
    }

    #[test]
    fn newmark_kinematics_of_a_quadratic_motion_are_exact_for_every_drive() {
        // The trapezoidal Newmark rule (β = ¼, γ = ½) integrates a constant acceleration
        // exactly; started from the exact state (0, 0, 2), every drive must reproduce
        // (t², 2t, 2) to round-off.
        let mut m = quadratic_terms([0.0, 0.0, 2.0]);
        m.start();
        let p = AlphaUpdate {
            dt: 0.1,
            beta: 0.25,
            gamma: 0.5,
            alpha_m: 0.0,
            alpha_f: 0.0,
        };
        // a DISP drive differentiates g twice: its round-off ε·g reaches g̈ amplified by
        // 1/(βΔt²) = 400 per step, undamped by the trapezoidal rule, hence the looser bounds
        let bounds = [1e-12, 1e-11, 1e-9];
        for step in 1..=20 {
            let t = step as f64 * 0.1;
            m.advance_alpha(t, p);
            for (j, k) in m.kinematics().iter().enumerate() {
                let exact = [t * t, 2.0 * t, 2.0];
                for i in 0..3 {
                    assert!(
                        (k[i] - exact[i]).abs() < bounds[i],
                        "term {j} {i}: {k:?} at {t}"
                    );
                }
            }
        }
    }

    #[test]
    fn bdf_kinematics_follow_the_difference_formulas() {
        // BDF1 from rest: a displacement drive's velocity is the backward difference, an
        // acceleration drive's displacement the twice-summed backward Euler update.
        let dt = 0.25;
        let mut m = quadratic_terms([0.0; 3]);
        m.start();
        m.advance_bdf(dt, dt, 1.0);
        let k = m.kinematics();
        assert_eq!(k[0], [dt * dt, dt, 1.0]);
        assert_eq!(k[1], [dt * 2.0 * dt, 2.0 * dt, 2.0]);
        assert_eq!(k[2], [dt * dt * 2.0, dt * 2.0, 2.0]);
        // BDF2 differentiates a quadratic exactly: after a BDF1 start the DISP term's
        // velocity is 2t at every later step.
        let mut m = PrescribedMotion::new(vec![term(Drive::Displacement, |t| t * t, [0.0; 3])]);
        m.start();
        m.advance_bdf(dt, dt, 1.0);
        for step in 2..=8 {
            let t = step as f64 * dt;
            m.advance_bdf(t, dt, 1.5);
            let [g, v, _] = m.kinematics()[0];
            assert!((g - t * t).abs() < 1e-14);
            assert!((v - 2.0 * t).abs() < 1e-12, "step {step}: {v}");
        }
    }

    #[test]
    fn bdf2_kinematics_of_a_quadratic_motion_are_exact_for_every_drive() {
        // BDF2 differentiates and integrates polynomials of degree 2 exactly: with the two
        // previous states exact, every drive reproduces (t², 2t, 2) at every step
        let dt = 0.1;
        let exact = |t: f64| [t * t, 2.0 * t, 2.0];
        let mut m = quadratic_terms(exact(0.0));
        m.start();
        m.previous = vec![exact(-dt); 3];
        for step in 1..=20 {
            let t = step as f64 * dt;
            m.advance_bdf(t, dt, 1.5);
            for (j, k) in m.kinematics().iter().enumerate() {
                for i in 0..3 {
                    assert!(
                        (k[i] - exact(t)[i]).abs() < 1e-9,
                        "term {j} {i}: {k:?} at {t}"
                    );
                }
            }
        }
    }

    #[test]
    fn coupling_columns_of_another_length_are_refused() {
        use crate::dynamics::integrators::Dense;
        use crate::dynamics::integrators::{
            IntegrationError, LinearSystem, Run, integrate_prescribed,
        };
        let (m, c, k) = (
            faer::Mat::<f64>::identity(2, 2),
            faer::Mat::<f64>::zeros(2, 2),
            faer::Mat::<f64>::identity(2, 2),
        );
        let sys = LinearSystem {
            mass: m.as_ref(),
            damping: c.as_ref(),
            stiffness: k.as_ref(),
        };
        let mut motion = PrescribedMotion::new(vec![term(Drive::Displacement, |t| t, [0.0; 3])]);
        let run = Run {
            dt: 0.1,
            steps: 3,
            t0: 0.0,
        };
        let result = integrate_prescribed(
            &mut Dense::new(sys).unwrap(),
            crate::dynamics::integrators::Method::Bdf1,
            run,
            &[0.0, 0.0],
            &[0.0, 0.0],
            |_, f| f.fill(0.0),
            &mut motion,
            |_| {},
        );
        assert_eq!(
            result,
            Err(IntegrationError::Shape {
                what: "prescribed-motion coupling",
                expected: 2,
                got: 1
            })
        );
    }

    #[test]
    fn the_coupling_force_reads_the_alpha_shifted_kinematics() {
        // one Newmark step of a DISP drive g = t² from (g, ġ, g̈) = (0.3, 1.5, 0.5) (no unit value,
        // which would hide a · turned into a /), written out:
        // g̃ = g + Δt ġ + (½ − β)Δt² g̈, g̈' = (g(t) − g̃)/(βΔt²), ġ' = ġ + (1 − γ)Δt g̈ + γΔt g̈'
        let (g0, v0, a0) = (0.3, 1.5, 0.5);
        let mut m = PrescribedMotion::new(vec![PrescribedTerm {
            drive: Drive::Displacement,
            function: Box::new(|t| t * t),
            initial: [g0, v0, a0],
            mass: vec![1.0, 0.0],
            damping: vec![0.0, 10.0],
            stiffness: vec![100.0, 0.0],
        }]);
        m.start();
        let (dt, beta, gamma, alpha_m, alpha_f) = (0.5, 0.3, 0.6, 0.2, 0.4);
        let p = AlphaUpdate {
            dt,
            beta,
            gamma,
            alpha_m,
            alpha_f,
        };
        m.advance_alpha(0.5, p);
        let g_pred = g0 + dt * v0 + (0.5 - beta) * dt * dt * a0;
        let a1 = (0.25 - g_pred) / (beta * dt * dt);
        let v1 = v0 + (1.0 - gamma) * dt * a0 + gamma * dt * a1;
        let [g, v, a] = m.kinematics()[0];
        assert!((g - 0.25).abs() < 1e-15 && (v - v1).abs() < 1e-12 && (a - a1).abs() < 1e-12);
        let mut f = vec![0.0, 0.0];
        m.subtract_coupling(&mut f);
        let shifted = |new: f64, old: f64, alpha: f64| (1.0 - alpha) * new + alpha * old;
        let want = [
            -(shifted(a1, a0, alpha_m) + 100.0 * shifted(0.25, g0, alpha_f)),
            -10.0 * shifted(v1, v0, alpha_f),
        ];
        assert!(
            (f[0] - want[0]).abs() < 1e-12 && (f[1] - want[1]).abs() < 1e-12,
            "{f:?}"
        );
    }
}
