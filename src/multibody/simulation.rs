//! A run of a [`System`] over a time grid with the output histories a user asked for: the
//! [`Output`]s (marker kinematics, joint reactions, drive efforts, power, actuation energy,
//! kinetic energy, strain gauges of flexible bodies), every drive's coordinate, rate, effort and power, the constraint residual
//! and the Newton iterations of each recorded step.
//!
//! The steps are the TSTEP intervals' Δt, or chosen by [`StepControl`] to meet a tolerance
//! on the local error of q ([`super::step_control`]). Controlled steps end exactly on every
//! output time of the intervals (a step that would pass one is shortened to it, one that
//! would leave less than a step before it is halved), so the recorded rows are the same
//! times with every output computed from the solver's state there, not interpolated: no
//! interpolation error adds to the controlled one, at the price of steps no longer than the
//! output spacing.

use super::error::MultibodyError;
use super::integrator::{Ggl, NewtonSettings};
use super::scheme::Scheme;
use super::sensitivity::{ParameterRate, Sensitivities, kinetic_energy_rate};
use super::signal::Signal;
use super::statics;
use super::step_control::{NOT_CONVERGED_RATIO, StepControl};
use super::system::System;
use crate::geometry::vec3::{dot, norm, sub};

/// One scalar output of a run, on the system's markers, joints, drives and bodies (their
/// indices).
#[derive(Debug, Clone, PartialEq)]
pub enum Output {
    /// Global position of a marker along a unit direction (eq. 2.58).
    Position { marker: usize, direction: [f64; 3] },
    /// Global acceleration of a marker along a unit direction (eq. 2.59).
    Acceleration { marker: usize, direction: [f64; 3] },
    /// The reaction force a joint applies to its first marker's body, along a unit direction
    /// (NaN for a joint whose rows do not make its points coincide).
    JointForce { joint: usize, direction: [f64; 3] },
    /// A drive's torque (force).
    DriveEffort(usize),
    /// A drive's power ω T.
    DrivePower(usize),
    /// A drive's actuation energy ∫ ω T dt so far.
    DriveEnergy(usize),
    /// The power Σ ω T of every drive.
    DrivesPower,
    /// The actuation energy of every drive, Σ ∫ ω T dt so far (eq. 6.1 f₂).
    DrivesEnergy,
    /// Kinetic energy of the system.
    KineticEnergy,
    /// The distance ‖x − x_R‖ of a marker from the same marker of the rigid twin (eq. 4.10),
    /// the system whose flexible bodies are rigid with their undeformed mass properties.
    Deviation(usize),
    /// A strain gauge of a flexible body, ε = C_ε q_f (eq. 2.57): `rows` holds C_ε, one value
    /// per flexible coordinate of `body`.
    Strain { body: usize, rows: Vec<f64> },
}

/// Where a run starts at t = 0.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Start {
    /// The kinematically assembled initial configuration.
    Assembled,
    /// The static equilibrium under gravity reached from the assembly with the drives held
    /// ([`statics`]).
    Equilibrium,
}

/// The time grid of a run: TSTEP intervals `(steps, Δt, every)` (rows at t₀ and after every
/// `every`-th step), stepped at their Δt or, with `control`, by the error controller from a
/// first step Δt of the first interval onto the same output times.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct TimeGrid {
    pub intervals: Vec<(u32, f64, u32)>,
    pub control: Option<StepControl>,
}

impl TimeGrid {
    /// The end time of every interval's output rows and of the interval, with whether it is
    /// an output row: t₀ + j·every·Δt, and t₀ + steps·Δt when it is not one of them.
    fn targets(&self) -> Vec<(f64, bool)> {
        let mut targets = Vec::new();
        let mut start = 0.0;
        for &(count, dt, every) in &self.intervals {
            let every = every.max(1);
            for step in (every..=count).step_by(every as usize) {
                targets.push((start + f64::from(step) * dt, true));
            }
            let end = start + f64::from(count) * dt;
            if count % every != 0 {
                targets.push((end, false));
            }
            start = end;
        }
        targets
    }
}

/// Output histories of a run: one row at t₀ and at every output time of the grid.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Histories {
    pub time: Vec<f64>,
    /// One series per output, in the order given to [`simulate`].
    pub outputs: Vec<Vec<f64>>,
    /// Per drive of the system: coordinate (angle or slide), rate, effort (torque or force),
    /// power.
    pub drives: Vec<[Vec<f64>; 4]>,
    /// max |Φᵢ| at each row.
    pub constraint_residual: Vec<f64>,
    /// Newton iterations of the step ending at each row (0 at t₀).
    pub newton_iterations: Vec<u32>,
    /// Steps taken, largest iteration count of a step, labels of removed redundant constraints.
    pub steps: usize,
    /// Under step control: the steps rejected (and retried smaller), the largest local error
    /// estimate of an accepted step in units of the tolerance (≤ 1), the smallest and the
    /// largest step taken.
    pub rejected: usize,
    pub max_error: f64,
    pub step_range: [f64; 2],
    pub max_iterations: usize,
    pub redundant: Vec<String>,
    /// Size of the system: coordinates and constraints.
    pub coordinates: usize,
    pub constraints: usize,
}

/// A drive's coordinate, rate, effort and power at the integrator's state.
fn drive_row(ggl: &Ggl, drive: usize) -> [f64; 4] {
    let [coordinate, rate] = ggl.drive_coordinate(drive);
    let effort = ggl.drive_effort(drive);
    [coordinate, rate, effort, effort * rate]
}

/// The value of `output` at the integrator's state; `energy` holds the actuation energy
/// integrated so far of each drive, `twin` the rigid twin's integrator.
pub(super) fn value(ggl: &Ggl, twin: Option<&Ggl>, output: &Output, energy: &[f64]) -> f64 {
    match output {
        &Output::Position { marker, direction } => dot(direction, ggl.marker_position(marker)),
        &Output::Acceleration { marker, direction } => {
            dot(direction, ggl.marker_acceleration(marker))
        }
        &Output::JointForce { joint, direction } => ggl
            .joint_force(joint)
            .map_or(f64::NAN, |f| dot(direction, f)),
        &Output::DriveEffort(d) => ggl.drive_effort(d),
        &Output::DrivePower(d) => drive_row(ggl, d)[3],
        &Output::DriveEnergy(d) => energy[d],
        Output::DrivesPower => (0..energy.len()).map(|d| drive_row(ggl, d)[3]).sum(),
        Output::DrivesEnergy => energy.iter().sum(),
        Output::KineticEnergy => ggl.kinetic_energy(),
        &Output::Deviation(marker) => twin.map_or(f64::NAN, |twin| {
            norm(sub(
                ggl.marker_position(marker),
                twin.marker_position(marker),
            ))
        }),
        Output::Strain { body, rows } => {
            let modal = ggl.system.layout.slice(*body).modal(&ggl.q);
            rows.iter().zip(modal).map(|(c, q)| c * q).sum()
        }
    }
}

/// The integrator of `system` at its start: the assembly, or the static equilibrium reached
/// from it. From the equilibrium the drives keep their targets (initial value + motion(t),
/// the initial value taken in the first configuration, not in the equilibrium), and the
/// constraint forces and accelerations are the consistent ones there (the static holding
/// torques of rigid drives).
fn started(
    system: &System,
    dt: f64,
    settings: NewtonSettings,
    scheme: Scheme,
    start: Start,
) -> Result<Ggl, MultibodyError> {
    let mut system = system.clone();
    if start == Start::Assembled {
        return Ggl::with_scheme(system, dt, 0.0, settings, scheme);
    }
    let assembled = Ggl::new(system.clone(), dt, 0.0, settings)?;
    let rest = statics::equilibrium(
        &assembled.system,
        &assembled.equations,
        &assembled.q,
        0.0,
        settings.tolerance,
        settings.assembly_tolerance,
    )?;
    let mut gradient = vec![0.0; rest.q.len()];
    for (d, initial) in assembled.equations.drive_initial.iter().enumerate() {
        let at_rest = system.joint_coordinate(system.drives[d].joint).evaluate(
            &system.layout,
            &rest.q,
            &mut gradient,
        );
        let (motion, shift) = (system.drives[d].motion.clone(), initial - at_rest);
        system.drives[d].motion = Signal::new(move |t| {
            let [f, rate, acceleration] = motion.at(t);
            [f + shift, rate, acceleration]
        });
    }
    system.set_initial_state(&rest.q, &vec![0.0; rest.q.len()]);
    let mut ggl = Ggl::with_scheme(system, dt, 0.0, settings, scheme)?;
    if !scheme.needs_initial_accelerations() {
        ggl.solve_accelerations()?;
    }
    Ok(ggl)
}

/// The derivatives of a run's outputs with respect to parameters ([`simulate_sensitivities`]).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct OutputSensitivities {
    /// Per parameter, per output, per recorded row: ∂y/∂p.
    pub outputs: Vec<Vec<Vec<f64>>>,
    /// Sensitivity iterations over every step and parameter.
    pub iterations: usize,
}

/// The forward sensitivities of a run and what they have recorded.
struct Tracker {
    sensitivities: Sensitivities,
    /// Per parameter, per drive: ∂(actuation energy so far)/∂p.
    energy: Vec<Vec<f64>>,
    recorded: OutputSensitivities,
}

/// Records output rows: the histories, the drives' actuation energy so far and the outputs
/// asked for, and with `tracker` their derivatives with respect to parameters.
struct Recorder<'a> {
    histories: Histories,
    energy: Vec<f64>,
    outputs: &'a [Output],
    tracker: Option<Tracker>,
}

impl Recorder<'_> {
    /// Adds the power of every drive over a step of size `dt` to its energy (the rectangle
    /// rule with the power at the step's end, that of BDF1); with sensitivities, advances
    /// them over the step and adds the power's derivatives likewise.
    fn integrate(&mut self, ggl: &mut Ggl, dt: f64) -> Result<(), MultibodyError> {
        for (d, e) in self.energy.iter_mut().enumerate() {
            *e += drive_row(ggl, d)[3] * dt;
        }
        let Some(tracker) = self.tracker.as_mut() else {
            return Ok(());
        };
        tracker.sensitivities.advance(ggl)?;
        tracker.recorded.iterations = tracker.sensitivities.iterations;
        for (s, energy) in (tracker.sensitivities.states.iter()).zip(&mut tracker.energy) {
            for (d, e) in energy.iter_mut().enumerate() {
                *e += s.along(ggl, |g| drive_row(g, d)[3]) * dt;
            }
        }
        Ok(())
    }

    /// The outputs' derivatives at the integrator's state, with a recorded row.
    fn record_rates(&mut self, ggl: &mut Ggl, twin: Option<&Ggl>) {
        let Some(tracker) = self.tracker.as_mut() else {
            return;
        };
        let parameters = (tracker.sensitivities.states.iter())
            .zip(&tracker.sensitivities.rates)
            .zip(&tracker.energy);
        for (((s, rate), energy), series) in parameters.zip(&mut tracker.recorded.outputs) {
            for (output, series) in self.outputs.iter().zip(series.iter_mut()) {
                let rate = match output {
                    &Output::DriveEnergy(d) => energy[d],
                    Output::DrivesEnergy => energy.iter().sum(),
                    Output::KineticEnergy => {
                        kinetic_energy_rate(ggl, rate) + s.along(ggl, |g| g.kinetic_energy())
                    }
                    &Output::Deviation(marker) => match twin {
                        // ‖d‖ with d = x − x_R is not smooth where d = 0 (at the start): the
                        // chain rule on the smooth x, ∂‖d‖ = d·∂x/‖d‖ (the twin has no p)
                        Some(twin) => {
                            let d = sub(ggl.marker_position(marker), twin.marker_position(marker));
                            let size = norm(d);
                            if size > 0.0 {
                                (0..3)
                                    .map(|c| {
                                        d[c] / size * s.along(ggl, |g| g.marker_position(marker)[c])
                                    })
                                    .sum()
                            } else {
                                0.0
                            }
                        }
                        None => f64::NAN,
                    },
                    other => s.along(ggl, |g| value(g, twin, other, &self.energy)),
                };
                series.push(rate);
            }
        }
    }

    /// A row at the integrator's time.
    fn record(&mut self, ggl: &Ggl, twin: Option<&Ggl>, residual: f64, iterations: usize) {
        let h = &mut self.histories;
        h.time.push(ggl.time);
        for (series, output) in h.outputs.iter_mut().zip(self.outputs) {
            series.push(value(ggl, twin, output, &self.energy));
        }
        for (d, series) in h.drives.iter_mut().enumerate() {
            for (x, v) in series.iter_mut().zip(drive_row(ggl, d)) {
                x.push(v);
            }
        }
        h.constraint_residual.push(residual);
        h.newton_iterations.push(iterations as u32);
    }
}

/// The contraction rate of the Newton corrections above which the rigid twin refactors its
/// iteration matrix (the flexible system keeps `NewtonSettings::slow_rate`, 0.3 by default,
/// or a lower one it is given). The twin's rigid bodies make 7-row blocks, so its
/// factorization costs about four of its iterations, against about ten for 29-row flexible
/// bodies: refreshing a matrix that contracts by 0.05–0.3 per iteration pays for the twin and
/// not for the links. On the flexible four-bar (docs/fourbar.md, "Speed") the twin's Newton
/// iterations per step fall from 7.5 to 5.4 and its factorizations rise from 7 to 87 per
/// 1000 steps: 3 % fewer instructions for the run.
pub const TWIN_SLOW_RATE: f64 = 0.05;

/// Runs `system` from `start` at t = 0 with GGL and `scheme` over `grid` (no intervals: only
/// the start is recorded), recording `outputs` and every drive. The actuation energy ∫ ω T dt
/// (eq. 6.1 f₂) is summed over every step with the power at the step's end (the rectangle
/// rule of BDF1). `twin`, the rigid twin that [`Output::Deviation`] compares with (same
/// markers, drives and forces), runs in lockstep with the same start, scheme and steps, and
/// refactors its iteration matrix sooner ([`TWIN_SLOW_RATE`]).
pub fn simulate(
    system: &System,
    twin: Option<&System>,
    outputs: &[Output],
    grid: &TimeGrid,
    settings: NewtonSettings,
    scheme: Scheme,
    start: Start,
) -> Result<Histories, MultibodyError> {
    let run = Run {
        system,
        twin,
        outputs,
        grid,
        settings,
        scheme,
        start,
    };
    Ok(run.go(None)?.0)
}

/// [`simulate`] with the derivatives of the outputs with respect to the parameters whose
/// data rates are `rates`, by forward sensitivities ([`super::sensitivity`]): at every
/// recorded row, the derivative of each output along the state's sensitivity (a central
/// difference of the output, whose dependence on the state is smooth and cheap to evaluate),
/// plus ½ q̇ᵀ ∂M/∂p q̇ for the kinetic energy (the other outputs do not read the bodies' data);
/// the actuation energy's by the same rectangle rule. From an assembled start on fixed steps
/// of BDF1 or BDF2 (else an error: the start or the steps would depend on p).
#[allow(clippy::too_many_arguments)]
pub fn simulate_sensitivities(
    system: &System,
    twin: Option<&System>,
    outputs: &[Output],
    grid: &TimeGrid,
    settings: NewtonSettings,
    scheme: Scheme,
    start: Start,
    rates: Vec<ParameterRate>,
) -> Result<(Histories, OutputSensitivities), MultibodyError> {
    if start != Start::Assembled || grid.control.is_some() {
        return Err(MultibodyError::Input(
            "forward sensitivities need an assembled start and fixed steps (the static equilibrium and the controlled steps depend on the parameters)".into(),
        ));
    }
    let run = Run {
        system,
        twin,
        outputs,
        grid,
        settings,
        scheme,
        start,
    };
    let (histories, rates) = run.go(Some(rates))?;
    Ok((histories, rates.unwrap_or_default()))
}

/// What a run is given.
struct Run<'a> {
    system: &'a System,
    twin: Option<&'a System>,
    outputs: &'a [Output],
    grid: &'a TimeGrid,
    settings: NewtonSettings,
    scheme: Scheme,
    start: Start,
}

impl Run<'_> {
    /// The run, with sensitivities when `rates` are given.
    fn go(
        &self,
        rates: Option<Vec<ParameterRate>>,
    ) -> Result<(Histories, Option<OutputSensitivities>), MultibodyError> {
        let Run {
            system,
            twin,
            outputs,
            grid,
            settings,
            scheme,
            start,
        } = *self;
        let dt0 = grid.intervals.first().map_or(1.0, |i| i.1);
        let mut ggl = started(system, dt0, settings, scheme, start)?;
        let mut twin = twin
            .map(|t| {
                let slow_rate = settings.slow_rate.min(TWIN_SLOW_RATE);
                let settings = NewtonSettings {
                    slow_rate,
                    ..settings
                };
                started(t, dt0, settings, scheme, start)
            })
            .transpose()?;
        let drives = system.drives.len();
        let mut recorder = Recorder {
            histories: Histories {
                outputs: vec![Vec::new(); outputs.len()],
                drives: vec![Default::default(); drives],
                redundant: ggl.redundant.clone(),
                coordinates: ggl.system.size(),
                constraints: ggl.constraint_count(),
                ..Histories::default()
            },
            energy: vec![0.0; drives],
            outputs,
            tracker: None,
        };
        if let Some(rates) = rates {
            let count = rates.len();
            recorder.tracker = Some(Tracker {
                sensitivities: Sensitivities::start(&ggl, rates)?,
                energy: vec![vec![0.0; drives]; count],
                recorded: OutputSensitivities {
                    outputs: vec![vec![Vec::new(); outputs.len()]; count],
                    iterations: 0,
                },
            });
        }
        let mut phi = vec![0.0; ggl.equations.constraints.len()];
        ggl.equations
            .constraints
            .values(&ggl.system.layout, &ggl.q, 0.0, &mut phi);
        let residual0 = phi.iter().fold(0.0_f64, |a, x| a.max(x.abs()));
        recorder.record(&ggl, twin.as_ref(), residual0, 0);
        recorder.record_rates(&mut ggl, twin.as_ref());
        match grid.control {
            None => fixed_steps(&mut ggl, twin.as_mut(), &grid.intervals, &mut recorder)?,
            Some(control) => {
                control.check()?;
                controlled_steps(&mut ggl, twin.as_mut(), grid, control, &mut recorder)?
            }
        }
        Ok((recorder.histories, recorder.tracker.map(|t| t.recorded)))
    }
}

/// The TSTEP intervals at their Δt.
fn fixed_steps(
    ggl: &mut Ggl,
    mut twin: Option<&mut Ggl>,
    intervals: &[(u32, f64, u32)],
    recorder: &mut Recorder,
) -> Result<(), MultibodyError> {
    for &(count, dt, every) in intervals {
        ggl.step_size = dt;
        if let Some(twin) = twin.as_deref_mut() {
            twin.step_size = dt;
        }
        let every = every.max(1) as usize;
        for step in 1..=count as usize {
            let report = ggl.step()?;
            if let Some(twin) = twin.as_deref_mut() {
                twin.step()?;
            }
            let h = &mut recorder.histories;
            h.steps += 1;
            h.max_iterations = h.max_iterations.max(report.iterations);
            recorder.integrate(ggl, dt)?;
            if step % every == 0 {
                recorder.record(
                    ggl,
                    twin.as_deref(),
                    report.constraint_residual,
                    report.iterations,
                );
                recorder.record_rates(ggl, twin.as_deref());
            }
        }
    }
    Ok(())
}

/// Error-controlled steps onto the grid's output times (module docs and
/// [`super::step_control`]).
fn controlled_steps(
    ggl: &mut Ggl,
    mut twin: Option<&mut Ggl>,
    grid: &TimeGrid,
    control: StepControl,
    recorder: &mut Recorder,
) -> Result<(), MultibodyError> {
    ggl.vary_steps()?;
    if let Some(twin) = twin.as_deref_mut() {
        twin.vary_steps()?;
    }
    let order = ggl.scheme().order();
    let mut h = control.bounded(ggl.step_size, ggl.time, 0.0)?;
    let [mut smallest, mut largest] = [f64::INFINITY, 0.0_f64];
    let targets = grid.targets();
    let span = targets.last().map_or(0.0, |t| t.0) - ggl.time;
    for (target, output) in targets {
        loop {
            let remaining = target - ggl.time;
            if remaining <= 1e-12 * target.abs().max(h) {
                break;
            }
            // land on the target, or halve what is left rather than leave a sliver
            let (step, lands) = if remaining <= h * (1.0 + 1e-9) {
                (remaining, true)
            } else if remaining < 2.0 * h {
                (0.5 * remaining, false)
            } else {
                (h, false)
            };
            let before = ggl.checkpoint();
            let twin_before = twin.as_deref().map(Ggl::checkpoint);
            let (q0, v0, a0) = (ggl.q.clone(), ggl.v.clone(), ggl.acceleration.clone());
            ggl.step_size = step;
            let mut attempt = ggl.step();
            if let (Ok(_), Some(twin)) = (&attempt, twin.as_deref_mut()) {
                twin.step_size = step;
                if let Err(e) = twin.step() {
                    attempt = Err(e);
                }
            }
            let (ratio, error, report) = match attempt {
                Ok(report) => {
                    let error =
                        control.error(step, span, [&q0, &v0, &a0], [&ggl.q, &ggl.acceleration]);
                    (control.ratio(error, order), error, Some(report))
                }
                Err(MultibodyError::NotConverged { .. }) => (NOT_CONVERGED_RATIO, f64::NAN, None),
                Err(e) => return Err(e),
            };
            let stats = &mut recorder.histories;
            match report {
                Some(report) if error <= 1.0 => {
                    if lands {
                        ggl.time = target;
                        if let Some(twin) = twin.as_deref_mut() {
                            twin.time = target;
                        }
                    }
                    stats.steps += 1;
                    stats.max_iterations = stats.max_iterations.max(report.iterations);
                    stats.max_error = stats.max_error.max(error);
                    (smallest, largest) = (smallest.min(step), largest.max(step));
                    recorder.integrate(ggl, step)?;
                    // a step shortened before a target keeps the size reached before it
                    let next = if step < h && ratio >= 1.0 {
                        h.max(step * ratio)
                    } else {
                        step * ratio
                    };
                    h = control.bounded(next, ggl.time, error)?;
                    if lands && output {
                        recorder.record(
                            ggl,
                            twin.as_deref(),
                            report.constraint_residual,
                            report.iterations,
                        );
                    }
                    if lands {
                        break;
                    }
                }
                _ => {
                    ggl.restore(&before);
                    if let (Some(twin), Some(c)) = (twin.as_deref_mut(), &twin_before) {
                        twin.restore(c);
                    }
                    stats.rejected += 1;
                    h = control.bounded(step * ratio.min(1.0), ggl.time, error)?;
                }
            }
        }
    }
    recorder.histories.step_range = [smallest, largest];
    Ok(())
}
