//! A run of a [`System`] over a time grid with the output histories a user asked for: the
//! [`Output`]s (marker kinematics, joint reactions, drive efforts, power, actuation energy,
//! kinetic energy, strain gauges of flexible bodies), every drive's coordinate, rate, effort and power, the constraint residual
//! and the Newton iterations of each recorded step.

use super::error::MultibodyError;
use super::integrator::{Ggl, NewtonSettings};
use super::scheme::Scheme;
use super::statics;
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
    /// A drive's actuation energy ∫ ω T dt so far (eq. 6.1 f₂).
    DriveEnergy(usize),
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

/// Output histories of a run: one row at t₀ and after every `every`-th step.
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
fn value(ggl: &Ggl, twin: Option<&Ggl>, output: &Output, energy: &[f64]) -> f64 {
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
/// from it.
fn started(
    system: &System,
    dt: f64,
    settings: NewtonSettings,
    scheme: Scheme,
    start: Start,
) -> Result<Ggl, MultibodyError> {
    let mut system = system.clone();
    if start == Start::Equilibrium {
        let assembled = Ggl::new(system.clone(), dt, 0.0, settings)?;
        let rest = statics::equilibrium(
            &assembled.system,
            &assembled.equations,
            &assembled.q,
            0.0,
            settings.tolerance,
            settings.assembly_tolerance,
        )?;
        system.set_initial_state(&rest.q, &vec![0.0; rest.q.len()]);
    }
    Ggl::with_scheme(system, dt, 0.0, settings, scheme)
}

/// Runs `system` from `start` at t = 0 with GGL and `scheme` over the TSTEP intervals
/// `(steps, Δt, every)` (none: only the start is recorded), recording `outputs` and every
/// drive. The actuation energy ∫ ω T dt (eq. 6.1 f₂) is summed over every step with the power
/// at the step's end (the rectangle rule of BDF1). `twin`, the rigid twin that
/// [`Output::Deviation`] compares with (same markers, drives and forces), runs in lockstep
/// with the same start, scheme and steps.
pub fn simulate(
    system: &System,
    twin: Option<&System>,
    outputs: &[Output],
    intervals: &[(u32, f64, u32)],
    settings: NewtonSettings,
    scheme: Scheme,
    start: Start,
) -> Result<Histories, MultibodyError> {
    let dt0 = intervals.first().map_or(1.0, |i| i.1);
    let mut ggl = started(system, dt0, settings, scheme, start)?;
    let mut twin = twin
        .map(|t| started(t, dt0, settings, scheme, start))
        .transpose()?;
    let drives = system.drives.len();
    let mut h = Histories {
        outputs: vec![Vec::new(); outputs.len()],
        drives: vec![Default::default(); drives],
        redundant: ggl.redundant.clone(),
        coordinates: ggl.system.size(),
        constraints: ggl.constraint_count(),
        ..Histories::default()
    };
    let mut energy = vec![0.0; drives];
    let mut phi = vec![0.0; ggl.equations.constraints.len()];
    ggl.equations
        .constraints
        .values(&ggl.system.layout, &ggl.q, 0.0, &mut phi);
    let residual0 = phi.iter().fold(0.0_f64, |a, x| a.max(x.abs()));
    let record = |ggl: &Ggl,
                  twin: Option<&Ggl>,
                  h: &mut Histories,
                  energy: &[f64],
                  residual: f64,
                  its: usize| {
        h.time.push(ggl.time);
        for (series, output) in h.outputs.iter_mut().zip(outputs) {
            series.push(value(ggl, twin, output, energy));
        }
        for (d, series) in h.drives.iter_mut().enumerate() {
            for (x, v) in series.iter_mut().zip(drive_row(ggl, d)) {
                x.push(v);
            }
        }
        h.constraint_residual.push(residual);
        h.newton_iterations.push(its as u32);
    };
    record(&ggl, twin.as_ref(), &mut h, &energy, residual0, 0);
    for &(count, dt, every) in intervals {
        ggl.step_size = dt;
        if let Some(twin) = twin.as_mut() {
            twin.step_size = dt;
        }
        let every = every.max(1) as usize;
        for step in 1..=count as usize {
            let report = ggl.step()?;
            if let Some(twin) = twin.as_mut() {
                twin.step()?;
            }
            h.steps += 1;
            h.max_iterations = h.max_iterations.max(report.iterations);
            for (d, e) in energy.iter_mut().enumerate() {
                *e += drive_row(&ggl, d)[3] * dt;
            }
            if step % every == 0 {
                record(
                    &ggl,
                    twin.as_ref(),
                    &mut h,
                    &energy,
                    report.constraint_residual,
                    report.iterations,
                );
            }
        }
    }
    Ok(h)
}
