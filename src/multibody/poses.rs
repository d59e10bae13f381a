//! Static equilibria over a grid of drive poses (thesis §4.5.4.1: the robot's workspace maps).
//!
//! A [`PoseGrid`] sets chosen drives to the values of a Cartesian product of axes: a rigid
//! drive holds its coordinate at initial value + v exactly (its reaction is the static holding
//! torque), a compliant drive aims at θ_d = initial value + v and the equilibrium includes its
//! spring's deflection (torque K(θ_d − θ), Fig. 4.15b), undriven joints with spring-dampers
//! find their own equilibrium. Every other drive and every force takes its value at t = 0.
//!
//! The grid is visited in boustrophedon order ([`PoseGrid::serpentine`]: consecutive poses
//! differ by one step of one axis), and with [`Start::Neighbour`] each pose's Newton solve
//! ([`super::statics::equilibrium_from`]) starts from the previous pose's equilibrium
//! (configuration and constraint forces) with the new drive targets, keeping the factored
//! matrix while the corrections contract ([`Refresh::WhenSlow`] at the Newton settings'
//! `slow_rate`). A pose whose warm start fails, and the first pose, start from the kinematic
//! assembly at their drive values (reached from the mechanism's initial configuration by
//! continuation in the drive targets, [`PoseSolver::assembled`]);
//! with [`Start::Assembly`] every pose does (the reference the warm start is measured
//! against). A pose that cannot be assembled or has no equilibrium (out of reach) is marked
//! not converged with NaN outputs, and the grid goes on.
//!
//! Outputs are those of a time run ([`Output`]) at the equilibrium with zero velocities and
//! accelerations: accelerations, drive power and actuation energy and the kinetic energy are
//! zero; a deviation compares with the rigid twin's equilibrium at the same drive values.

use super::error::MultibodyError;
use super::integrator::{Ggl, NewtonSettings};
use super::joints::drive_constraint;
use super::signal::Signal;
use super::simulation::{Output, value};
use super::statics::{KeptMatrix, Refresh, StaticSettings, equilibrium_from};
use super::system::{DriveSource, System};

/// Largest change of a drive target between two kinematic assemblies of a continuation
/// ([`PoseSolver::assembled`]): 0.5 rad keeps cos(θ − θ_d) ≥ 0.88 in a rigid drive's row.
const ASSEMBLY_STEP: f64 = 0.5;

/// Drives set over the Cartesian product of their axes.
#[derive(Debug, Clone, PartialEq)]
pub struct PoseGrid {
    /// The system's drives, one per axis.
    pub drives: Vec<usize>,
    /// The values of each drive's coordinate relative to its initial value (radians for a
    /// revolute joint, length for a prismatic one).
    pub axes: Vec<Vec<f64>>,
}

impl PoseGrid {
    /// Number of poses (the product of the axis lengths).
    pub fn len(&self) -> usize {
        self.axes.iter().map(Vec::len).product()
    }

    /// Whether the grid has no pose.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The axis indices of pose `k`, numbered row-major (the first axis varies slowest).
    fn indices(&self, mut k: usize) -> Vec<usize> {
        let mut out = vec![0; self.axes.len()];
        for (slot, axis) in out.iter_mut().zip(&self.axes).rev() {
            *slot = k % axis.len();
            k /= axis.len();
        }
        out
    }

    /// The drive values of pose `k` (row-major numbering).
    pub fn values(&self, k: usize) -> Vec<f64> {
        self.indices(k)
            .into_iter()
            .zip(&self.axes)
            .map(|(i, axis)| axis[i])
            .collect()
    }

    /// The poses (row-major numbers) in boustrophedon order: axis i runs backwards when the
    /// row-major rank of the slower axes' indices is odd, so consecutive poses differ by one
    /// step of one axis.
    pub fn serpentine(&self) -> Vec<usize> {
        (0..self.len())
            .map(|k| {
                let raw = self.indices(k);
                let mut rank = 0;
                let mut pose = 0;
                for (axis, (&i, values)) in raw.iter().zip(&self.axes).enumerate() {
                    let n = values.len();
                    let index = if axis > 0 && rank % 2 == 1 {
                        n - 1 - i
                    } else {
                        i
                    };
                    rank = rank * n + i;
                    pose = pose * n + index;
                }
                pose
            })
            .collect()
    }
}

/// Where each pose's Newton solve starts.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Start {
    /// From the previous pose's equilibrium (assembly for the first pose and after a failure).
    Neighbour,
    /// From the kinematic assembly at the pose's drive values, every pose.
    Assembly,
}

/// Equilibria over a grid, per pose in row-major numbering.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct PoseHistories {
    /// Whether the pose has an equilibrium (false: out of reach or no convergence).
    pub converged: Vec<bool>,
    /// Newton iterations of the equilibrium solve that converged (of the warm start and, when
    /// it failed, of the solve from the assembly).
    pub iterations: Vec<u32>,
    /// max |Φ_qᵀ λ − f| and max |Φ| at the equilibrium (NaN where none was found).
    pub force_residual: Vec<f64>,
    pub constraint_residual: Vec<f64>,
    /// One series per output, in the order given to [`solve_grid`].
    pub outputs: Vec<Vec<f64>>,
    /// Poses started from the assembly and factorizations of the iteration matrix, in all.
    pub assemblies: usize,
    pub factorizations: usize,
    /// Why each pose without an equilibrium has none: (pose, message).
    pub failures: Vec<(usize, String)>,
    /// Labels of the constraints removed as redundant (at the first assembled pose).
    pub redundant: Vec<String>,
    /// Size of the system: coordinates and constraints.
    pub coordinates: usize,
    pub constraints: usize,
}

/// One pose's solve.
struct Solved {
    iterations: usize,
    factorizations: usize,
    assembled: bool,
    residuals: [f64; 2],
}

/// The equilibria of one system over a grid, pose after pose (module docs).
struct PoseSolver<'a> {
    system: &'a System,
    drives: &'a [usize],
    /// Each drive's coordinate in the system's initial configuration (its targets are this +
    /// motion).
    origins: Vec<f64>,
    settings: NewtonSettings,
    start: Start,
    /// The last equilibrium's integrator state, its equations at that pose's targets.
    current: Option<Ggl>,
    /// The drive values of `current`, and the equilibrium before it (drive values, q, λ) when
    /// it was solved warm: the secant predictor's second point.
    current_values: Vec<f64>,
    previous: Option<(Vec<f64>, Vec<f64>, Vec<f64>)>,
    kept: KeptMatrix,
}

impl<'a> PoseSolver<'a> {
    fn new(
        system: &'a System,
        drives: &'a [usize],
        settings: NewtonSettings,
        start: Start,
    ) -> Self {
        Self {
            system,
            drives,
            origins: drive_origins(system),
            settings,
            start,
            current: None,
            current_values: Vec::new(),
            previous: None,
            kept: KeptMatrix::default(),
        }
    }

    fn static_settings(&self) -> StaticSettings {
        StaticSettings {
            tolerance: self.settings.tolerance,
            assembly_tolerance: self.settings.assembly_tolerance,
            refresh: Refresh::WhenSlow(self.settings.slow_rate),
        }
    }

    /// The system assembled at the drive values `values`, by continuation from the initial
    /// configuration: the targets move there in equal steps of at most [`ASSEMBLY_STEP`], each
    /// assembled from the last (a rigid drive's row sin(θ − θ_d) = 0 has a singular Jacobian a
    /// quarter turn from its target and a second root half a turn away, so one jump from the
    /// initial configuration to a far pose fails or lands on the wrong root).
    fn assembled(&self, values: &[f64]) -> Result<Ggl, MultibodyError> {
        let largest = values.iter().fold(0.0_f64, |a, v| a.max(v.abs()));
        let steps = (largest / ASSEMBLY_STEP).ceil().max(1.0) as usize;
        let (q0, _) = self.system.initial_state();
        let mut guess = q0.to_vec();
        let mut step = 1;
        loop {
            let fraction = step as f64 / steps as f64;
            let partial: Vec<f64> = values.iter().map(|v| v * fraction).collect();
            let system = self.targeted(&guess, &partial);
            let ggl = Ggl::new(system, 1.0, 0.0, self.settings)?;
            if step == steps {
                return Ok(ggl);
            }
            guess = ggl.q;
            step += 1;
        }
    }

    /// The system with its initial guess `guess` and every drive's target unchanged (its
    /// coordinate in the initial configuration + motion(t)), the grid's drives' motions set to
    /// `values`: [`System::equations`] takes a drive's initial value in the guess, so each
    /// motion is shifted by the difference.
    fn targeted(&self, guess: &[f64], values: &[f64]) -> System {
        let mut system = self.system.clone();
        let mut gradient = vec![0.0; guess.len()];
        for (d, origin) in self.origins.iter().enumerate() {
            let at_guess = system.joint_coordinate(system.drives[d].joint).evaluate(
                &system.layout,
                guess,
                &mut gradient,
            );
            let shift = origin - at_guess;
            let motion = match self.drives.iter().position(|&g| g == d) {
                Some(axis) => Signal::constant(values[axis] + shift),
                None => {
                    let motion = system.drives[d].motion.clone();
                    Signal::new(move |t| {
                        let [f, rate, acceleration] = motion.at(t);
                        [f + shift, rate, acceleration]
                    })
                }
            };
            system.drives[d].motion = motion;
        }
        system.set_initial_state(guess, &vec![0.0; guess.len()]);
        system
    }

    /// Solves the pose with drive values `values`: warm from the current state when there is
    /// one and the start asks for it, else (or when that fails) from the assembly. On success
    /// the state is the equilibrium, with zero velocities and accelerations.
    fn solve(&mut self, values: &[f64]) -> Result<Solved, MultibodyError> {
        let mut iterations = 0;
        let mut factorizations = 0;
        let settings = self.static_settings();
        if self.start == Start::Neighbour
            && let Some(ggl) = self.current.as_mut()
        {
            set_targets(ggl, self.drives, &self.origins, values)?;
            let (q0, lambda0) = secant_start(
                (&ggl.q, &ggl.lambda),
                &self.current_values,
                self.previous.as_ref(),
                values,
            );
            let attempt = equilibrium_from(
                &ggl.system,
                &ggl.equations,
                (&q0, &lambda0),
                0.0,
                settings,
                &mut self.kept,
            );
            match attempt {
                Ok(rest) => {
                    let before = std::mem::replace(&mut self.current_values, values.to_vec());
                    let q = std::mem::replace(&mut ggl.q, rest.q);
                    let lambda = std::mem::replace(&mut ggl.lambda, rest.lambda);
                    self.previous = Some((before, q, lambda));
                    return Ok(Solved {
                        iterations: rest.iterations,
                        factorizations: rest.factorizations,
                        assembled: false,
                        residuals: [rest.force_residual, rest.constraint_residual],
                    });
                }
                Err(MultibodyError::NoEquilibrium { iterations: n, .. }) => iterations += n,
                Err(MultibodyError::Singular { .. }) => {}
                Err(e) => return Err(e),
            }
        }
        self.kept.clear();
        let mut ggl = self.assembled(values)?;
        let lambda0 = vec![0.0; ggl.constraint_count()];
        let rest = equilibrium_from(
            &ggl.system,
            &ggl.equations,
            (&ggl.q, &lambda0),
            0.0,
            settings,
            &mut self.kept,
        )?;
        iterations += rest.iterations;
        factorizations += rest.factorizations;
        ggl.q = rest.q;
        ggl.lambda = rest.lambda;
        ggl.v.fill(0.0);
        ggl.acceleration.fill(0.0);
        self.current = Some(ggl);
        self.current_values = values.to_vec();
        self.previous = None;
        Ok(Solved {
            iterations,
            factorizations,
            assembled: true,
            residuals: [rest.force_residual, rest.constraint_residual],
        })
    }
}

/// The start of a warm solve at drive values `next`: the secant extrapolation 2x − x_prev of
/// the last two equilibria (q and λ) when `next` continues their step (the same increment of the
/// drive values, as along a row of the grid), an O(h²) guess instead of the neighbour's O(h);
/// else the last equilibrium itself.
fn secant_start(
    (q, lambda): (&[f64], &[f64]),
    current: &[f64],
    previous: Option<&(Vec<f64>, Vec<f64>, Vec<f64>)>,
    next: &[f64],
) -> (Vec<f64>, Vec<f64>) {
    let continues = |before: &[f64]| {
        (0..next.len()).all(|k| {
            let (step, last) = (next[k] - current[k], current[k] - before[k]);
            (step - last).abs() <= 1e-9 * (1.0 + step.abs())
        })
    };
    match previous {
        Some((before, q_prev, l_prev)) if continues(before) => (
            q.iter().zip(q_prev).map(|(a, b)| 2.0 * a - b).collect(),
            lambda
                .iter()
                .zip(l_prev)
                .map(|(a, b)| 2.0 * a - b)
                .collect(),
        ),
        _ => (q.to_vec(), lambda.to_vec()),
    }
}

/// Points the drives' constraint rows (rigid) or springs (compliant) of `ggl`'s equations at
/// their coordinates in the initial configuration (`origins`, per drive of the system) +
/// `values`.
fn set_targets(
    ggl: &mut Ggl,
    drives: &[usize],
    origins: &[f64],
    values: &[f64],
) -> Result<(), MultibodyError> {
    for (&d, &v) in drives.iter().zip(values) {
        let motion = Signal::constant(v);
        match ggl.equations.drive_sources[d] {
            DriveSource::Spring(i) => {
                let spring = &mut ggl.equations.springs[i];
                spring.rest = origins[d];
                spring.motion = Some(motion);
            }
            DriveSource::Row(row) => {
                let Some(k) = ggl.active_row[row] else {
                    return Err(MultibodyError::Input(format!(
                        "drive {d}: its constraint was removed as redundant, so a pose cannot set it"
                    )));
                };
                let system = &ggl.system;
                let joint = &system.joints[system.drives[d].joint];
                ggl.equations.constraints.constraints[k] = drive_constraint(
                    joint.kind,
                    &system.markers[joint.first],
                    &system.markers[joint.second],
                    origins[d],
                    &motion,
                );
            }
        }
    }
    Ok(())
}

/// Each drive's joint coordinate in the system's initial configuration.
fn drive_origins(system: &System) -> Vec<f64> {
    let (q0, _) = system.initial_state();
    let mut gradient = vec![0.0; q0.len()];
    system
        .drives
        .iter()
        .map(|d| {
            system
                .joint_coordinate(d.joint)
                .evaluate(&system.layout, q0, &mut gradient)
        })
        .collect()
}

/// Solves the equilibrium of `system` at every pose of `grid` in boustrophedon order from
/// `start` and records `outputs` there; `twin`, the rigid twin that [`Output::Deviation`]
/// compares with, is solved at the same poses. A pose without an equilibrium (of the system or
/// the twin) is recorded as not converged with NaN outputs.
pub fn solve_grid(
    system: &System,
    twin: Option<&System>,
    outputs: &[Output],
    grid: &PoseGrid,
    settings: NewtonSettings,
    start: Start,
) -> Result<PoseHistories, MultibodyError> {
    let solver = |system| PoseSolver::new(system, &grid.drives, settings, start);
    let mut main = solver(system);
    let mut rigid = twin.map(solver);
    let poses = grid.len();
    let mut h = PoseHistories {
        converged: vec![false; poses],
        iterations: vec![0; poses],
        force_residual: vec![f64::NAN; poses],
        constraint_residual: vec![f64::NAN; poses],
        outputs: vec![vec![f64::NAN; poses]; outputs.len()],
        ..PoseHistories::default()
    };
    let no_energy = vec![0.0; system.drives.len()];
    for pose in grid.serpentine() {
        let values = grid.values(pose);
        let solved = main.solve(&values).and_then(|s| {
            if let Some(twin) = rigid.as_mut() {
                twin.solve(&values)?;
            }
            Ok(s)
        });
        let s = match solved {
            Ok(s) => s,
            Err(e @ MultibodyError::Input(_)) => return Err(e),
            Err(e) => {
                h.failures.push((pose, e.to_string()));
                continue;
            }
        };
        let ggl = main.current.as_ref().expect("a solved pose has a state");
        if h.coordinates == 0 {
            h.redundant = ggl.redundant.clone();
            h.coordinates = ggl.system.size();
            h.constraints = ggl.constraint_count();
        }
        h.converged[pose] = true;
        h.iterations[pose] = s.iterations as u32;
        [h.force_residual[pose], h.constraint_residual[pose]] = s.residuals;
        h.assemblies += usize::from(s.assembled);
        h.factorizations += s.factorizations;
        let twin_state = rigid.as_ref().and_then(|t| t.current.as_ref());
        for (series, output) in h.outputs.iter_mut().zip(outputs) {
            series[pose] = value(ggl, twin_state, output, &no_energy);
        }
    }
    Ok(h)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Consecutive poses of the boustrophedon order differ by one step of one axis, and every
    /// pose is visited once.
    #[test]
    fn serpentine_visits_every_pose_once_in_single_steps() {
        for sizes in [vec![5], vec![3, 4], vec![2, 2, 2], vec![3, 1, 4, 2]] {
            let grid = PoseGrid {
                drives: (0..sizes.len()).collect(),
                axes: sizes
                    .iter()
                    .map(|&n| (0..n).map(f64::from).collect())
                    .collect(),
            };
            let order = grid.serpentine();
            let mut seen = order.clone();
            seen.sort_unstable();
            assert_eq!(seen, (0..grid.len()).collect::<Vec<_>>(), "{sizes:?}");
            for pair in order.windows(2) {
                let (a, b) = (grid.values(pair[0]), grid.values(pair[1]));
                let steps: f64 = a.iter().zip(&b).map(|(x, y)| (x - y).abs()).sum();
                assert_eq!(steps, 1.0, "{sizes:?}: {a:?} -> {b:?}");
            }
        }
    }

    #[test]
    fn values_are_numbered_row_major() {
        let grid = PoseGrid {
            drives: vec![0, 1],
            axes: vec![vec![0.0, 1.0], vec![10.0, 20.0, 30.0]],
        };
        assert_eq!(grid.len(), 6);
        assert_eq!(grid.values(0), vec![0.0, 10.0]);
        assert_eq!(grid.values(2), vec![0.0, 30.0]);
        assert_eq!(grid.values(4), vec![1.0, 20.0]);
    }

    /// The secant start extrapolates only when the next pose continues the last step.
    #[test]
    fn secant_start_extrapolates_along_a_row_only() {
        let previous = (vec![0.0, 0.1], vec![1.0, 2.0], vec![5.0]);
        let (q, lambda) = ([1.5, 2.5], [6.0]);
        let along = secant_start((&q, &lambda), &[0.0, 0.2], Some(&previous), &[0.0, 0.3]);
        assert_eq!(along, (vec![2.0, 3.0], vec![7.0]));
        let turn = secant_start((&q, &lambda), &[0.0, 0.2], Some(&previous), &[0.1, 0.2]);
        assert_eq!(turn, (q.to_vec(), lambda.to_vec()));
        let first = secant_start((&q, &lambda), &[0.0, 0.2], None, &[0.0, 0.3]);
        assert_eq!(first, (q.to_vec(), lambda.to_vec()));
    }
}
