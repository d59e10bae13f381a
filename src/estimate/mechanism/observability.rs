//! Observability of a mechanism estimation (thesis §9.3.1) before the filter runs: the two
//! setups the thesis names as unable to work, and the numerical observability of the
//! linearized system along the first steps of the prior trajectory.
//!
//! - [`structural`]: accelerations only carry no static information (the estimates drift);
//!   strains read flexible coordinates only, so without a position measurement the rigid
//!   coordinates that the joints and drives leave free (an undriven mechanism) have no
//!   absolute information. The free rigid coordinates are counted as n_rigid − rank Φ_q[:,
//!   rigid] at the assembled start (the flexible coordinates held), the gradients of the
//!   coordinates of springs with stiffness (compliant drives, joint and point springs: each
//!   ties its coordinate to a known table or rest value) counted as rows of Φ_q.
//! - [`numerical`]: the observability matrix of the linearized system over the first K steps
//!   from the initial estimate (the filter's prediction without corrections),
//!
//!   ```text
//!   O = [ R^{-1/2} J_m,1 Φ_1 ; … ; R^{-1/2} J_m,K Φ_K ] T,   Φ_k = J_k Φ_{k−1},  Φ_0 = I,
//!   ```
//!
//!   J_k the augmented transition Jacobian (eq. 9.8, 9.17), J_m,k the measurement rows (eq.
//!   9.19), T = diag(N₀, N₀, I) restricting the initial perturbation to the independent
//!   coordinates (N₀ the nullspace of Φ_q at the start: perturbations off the constraints are
//!   not states), its columns scaled to unit norm (the coordinates, velocities, inputs and
//!   scaled parameters have different units; a column below [`RANK_TOLERANCE`] × the largest
//!   column's norm is round-off of an exact zero, an unknown no reading sees, and stays zero).
//!   Its rank (singular values above
//!   [`RANK_TOLERANCE`] × the largest) and its smallest singular value over the largest are
//!   reported, and per parameter and input the distance of its (unit) column from the span of all the
//!   other columns: 0 when the data cannot tell a parameter change from a change of the
//!   states or the other parameters, 1 when its effect is orthogonal to theirs.

use faer::Mat;
use faer::linalg::matmul::matmul;
use faer::{Accum, Par};

use super::inputs::Inputs;
use super::nullspace::Partition;
use super::parameters::Parameters;
use super::sensors::{Sensor, measure};
use super::transition::transition;
use crate::multibody::{Ggl, Output};

/// Singular values below this fraction of the largest count as zero.
pub const RANK_TOLERANCE: f64 = 1e-9;

/// Why a setup cannot work (module docs).
#[derive(Debug, Clone, PartialEq)]
pub enum Refusal {
    /// Every measurement is an acceleration.
    AccelerationsOnly,
    /// `free` rigid coordinates are not fixed by joints, drives and springs and no position is
    /// measured.
    NoAbsoluteInformation { free: usize },
}

impl std::fmt::Display for Refusal {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Refusal::AccelerationsOnly => write!(
                f,
                "every measurement is an acceleration: accelerations carry no static information, the estimates would drift (thesis §9.3.1); add a position or strain measurement"
            ),
            Refusal::NoAbsoluteInformation { free } => write!(
                f,
                "the joints, drives and springs leave {free} rigid degree(s) of freedom free and no POS is measured: strains read the flexible coordinates only, so nothing fixes the rigid ones absolutely (thesis §9.3.1); measure a marker position or drive the mechanism"
            ),
        }
    }
}

/// The rank of `a` (singular values above [`RANK_TOLERANCE`] × the largest), its smallest
/// and largest singular values (of its thin SVD; zero for an empty matrix).
fn rank(a: &Mat<f64>) -> (usize, f64, f64) {
    if a.nrows() == 0 || a.ncols() == 0 {
        return (0, 0.0, 0.0);
    }
    let Ok(values) = a.singular_values() else {
        return (0, 0.0, 0.0);
    };
    let largest = values.iter().copied().fold(0.0, f64::max);
    let count = values
        .iter()
        .filter(|s| **s > RANK_TOLERANCE * largest)
        .count();
    let smallest = if a.nrows() >= a.ncols() {
        values.iter().copied().fold(f64::INFINITY, f64::min)
    } else {
        0.0
    };
    (count, smallest, largest)
}

/// The setup's refusal, if any (module docs), at `ggl`'s assembled start.
pub fn structural(ggl: &Ggl, sensors: &[Sensor]) -> Option<Refusal> {
    let kinds = |f: fn(&Output) -> bool| sensors.iter().filter(|s| f(&s.output)).count();
    if kinds(|o| matches!(o, Output::Acceleration { .. })) == sensors.len() {
        return Some(Refusal::AccelerationsOnly);
    }
    if kinds(|o| matches!(o, Output::Position { .. })) > 0 {
        return None;
    }
    let layout = &ggl.system.layout;
    let (n, m) = (ggl.system.size(), ggl.constraint_count());
    let mut phi_q = Mat::zeros(m, n);
    ggl.equations
        .constraints
        .jacobian(layout, &ggl.q, ggl.time, phi_q.as_mut());
    let rigid: Vec<usize> = (layout.slices().iter())
        .flat_map(|s| s.offset..s.offset + 7)
        .collect();
    // A spring with stiffness (a compliant drive toward its table, a joint or point spring
    // toward its rest value) ties its coordinate to a known value: its gradient is a row of
    // absolute information like a constraint's.
    let springs = &ggl.equations.springs;
    let mut gradients = Vec::new();
    for spring in springs.iter().filter(|s| s.stiffness > 0.0) {
        let mut gradient = vec![0.0; n];
        spring.coordinate.evaluate(layout, &ggl.q, &mut gradient);
        gradients.push(gradient);
    }
    let columns = Mat::from_fn(m + gradients.len(), rigid.len(), |i, j| {
        if i < m {
            phi_q[(i, rigid[j])]
        } else {
            gradients[i - m][rigid[j]]
        }
    });
    let free = rigid.len() - rank(&columns).0;
    (free > 0).then_some(Refusal::NoAbsoluteInformation { free })
}

/// The numerical observability (module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct Observability {
    /// Steps of the window.
    pub steps: usize,
    /// Rank and number of columns (independent coordinates, velocities, inputs and
    /// parameters).
    pub rank: usize,
    pub columns: usize,
    /// Smallest over largest singular value of the column-scaled matrix.
    pub ratio: f64,
    /// Per input, the distance of its unit column from the span of the others.
    pub inputs: Vec<f64>,
    /// Per parameter, the distance of its unit column from the span of the others.
    pub parameters: Vec<f64>,
}

impl Observability {
    /// Whether the matrix has full column rank.
    pub fn full(&self) -> bool {
        self.rank == self.columns
    }
}

/// The observability matrix of a window being accumulated (module docs): Φ_k and the rows
/// of the steps so far. The augmented state is x* = (q, v, u, θ) with `nu` inputs and `np`
/// parameters.
#[derive(Debug, Clone)]
pub struct Window {
    /// Φ_k T (N × columns).
    phi: Mat<f64>,
    o: Mat<f64>,
    /// Columns of the independent coordinates (and velocities), and of the unknowns.
    free: usize,
    unknowns: (usize, usize),
    /// Steps of the window and steps added.
    pub steps: usize,
    added: usize,
}

impl Window {
    /// A window from the configuration whose constraint Jacobian is `phi_q` (partitioned by
    /// `partition`), with `sensors` rows per step: the shortest whose rows outnumber its
    /// columns (two steps more), at most `limit` steps.
    pub fn start(
        phi_q: &Mat<f64>,
        partition: &mut Partition,
        unknowns: (usize, usize),
        sensors: usize,
        limit: usize,
    ) -> Result<Self, String> {
        let columns = 2 * Self::independent(phi_q, partition)? + unknowns.0 + unknowns.1;
        let steps = (columns.div_ceil(sensors.max(1)) + 2).min(limit).max(1);
        Self::of_length(phi_q, partition, unknowns, sensors, steps)
    }

    /// The number of independent coordinates of the partition at `phi_q`.
    fn independent(phi_q: &Mat<f64>, partition: &mut Partition) -> Result<usize, String> {
        partition
            .nullspace(phi_q.as_ref())
            .map(|n| n.basis.ncols())
            .map_err(|e| format!("{e:?}"))
    }

    /// A window as [`Window::start`] of `steps` steps.
    pub fn of_length(
        phi_q: &Mat<f64>,
        partition: &mut Partition,
        unknowns: (usize, usize),
        sensors: usize,
        steps: usize,
    ) -> Result<Self, String> {
        let n = phi_q.ncols();
        let (nu, np) = unknowns;
        let big_n = 2 * n + nu + np;
        let n0 = partition
            .nullspace(phi_q.as_ref())
            .map_err(|e| format!("{e:?}"))?
            .basis;
        let free = n0.ncols();
        let columns = 2 * free + nu + np;
        // T = diag(N₀, N₀, I)
        let phi = Mat::from_fn(big_n, columns, |i, j| {
            match (i < n, i < 2 * n, j < free, j < 2 * free) {
                (true, _, true, _) => n0[(i, j)],
                (false, true, false, true) => n0[(i - n, j - free)],
                (false, false, false, false) => f64::from(u8::from(i - 2 * n == j - 2 * free)),
                _ => 0.0,
            }
        });
        let steps = steps.max(1);
        Ok(Self {
            phi,
            o: Mat::zeros(steps * sensors, columns),
            free,
            unknowns,
            steps,
            added: 0,
        })
    }

    /// Adds a step: Φ_k = J_k Φ_{k−1} with the augmented transition Jacobian `jacobian`,
    /// and the rows R^{-1/2} J_m,k Φ_k of the measurement rows `jm` (noise `variances`).
    /// Whether the window is complete.
    pub fn add(&mut self, jacobian: &Mat<f64>, jm: &Mat<f64>, variances: &[f64]) -> bool {
        if self.added == self.steps {
            return true;
        }
        let mut next = Mat::zeros(self.phi.nrows(), self.phi.ncols());
        matmul(
            next.as_mut(),
            Accum::Replace,
            jacobian.as_ref(),
            self.phi.as_ref(),
            1.0,
            Par::Seq,
        );
        self.phi = next;
        let k = variances.len();
        let rows = self
            .o
            .as_mut()
            .submatrix_mut(self.added * k, 0, k, self.phi.ncols());
        matmul(
            rows,
            Accum::Replace,
            jm.as_ref(),
            self.phi.as_ref(),
            1.0,
            Par::Seq,
        );
        for (r, variance) in variances.iter().enumerate() {
            let weight = 1.0 / variance.sqrt();
            for c in 0..self.o.ncols() {
                self.o[(self.added * k + r, c)] *= weight;
            }
        }
        self.added += 1;
        self.added == self.steps
    }

    /// The Fisher information of sensor `r`'s readings over the steps added so far about the
    /// window's columns: Σ_k o_k,rᵀ o_k,r with o_k,r = σ_r⁻¹ J_m,k,r Φ_k T, unscaled.
    pub fn information(&self, r: usize) -> Mat<f64> {
        let k = self.o.nrows() / self.steps;
        let rows = Mat::from_fn(self.added, self.o.ncols(), |i, c| self.o[(i * k + r, c)]);
        let mut f = Mat::zeros(self.o.ncols(), self.o.ncols());
        matmul(
            f.as_mut(),
            Accum::Replace,
            rows.transpose(),
            rows.as_ref(),
            1.0,
            Par::Seq,
        );
        f
    }

    /// Columns of the independent coordinates (the velocities' as many after them) and the
    /// unknowns (inputs, parameters).
    pub fn layout(&self) -> (usize, (usize, usize)) {
        (self.free, self.unknowns)
    }

    /// The observability of the rows added so far (module docs).
    pub fn finish(&self) -> Observability {
        let k = self.o.nrows() / self.steps;
        let mut o = self
            .o
            .as_ref()
            .submatrix(0, 0, self.added * k, self.o.ncols())
            .to_owned();
        let columns = o.ncols();
        let norms: Vec<f64> = (0..columns)
            .map(|c| {
                (0..o.nrows())
                    .map(|r| o[(r, c)] * o[(r, c)])
                    .sum::<f64>()
                    .sqrt()
            })
            .collect();
        // a column this much smaller than the largest is round-off of an exact zero (an
        // unknown the readings do not see): left zero rather than scaled up to unit norm
        let floor = RANK_TOLERANCE * norms.iter().copied().fold(0.0, f64::max);
        for (c, norm) in norms.iter().enumerate() {
            let scale = if *norm > floor { 1.0 / norm } else { 0.0 };
            (0..o.nrows()).for_each(|r| o[(r, c)] *= scale);
        }
        let (rank, smallest, largest) = rank(&o);
        let first = 2 * self.free;
        let (nu, np) = self.unknowns;
        let distances =
            |range: std::ops::Range<usize>| range.map(|c| distance_from_others(&o, c)).collect();
        Observability {
            steps: self.added,
            rank,
            columns,
            ratio: if largest > 0.0 {
                smallest / largest
            } else {
                0.0
            },
            inputs: distances(first..first + nu),
            parameters: distances(first + nu..first + nu + np),
        }
    }
}

/// The observability matrix of `ggl` (assembled at the start, its system at the initial
/// guesses θ = 1 of `parameters` and u = 0 of `inputs`) with `sensors` (module docs), over the
/// shortest window whose rows outnumber its columns (two steps more), at most `limit` steps.
pub fn numerical(
    ggl: Ggl,
    inputs: &Inputs,
    parameters: &Parameters,
    sensors: &[Sensor],
    limit: usize,
) -> Result<Observability, String> {
    let k = sensors.len();
    let (nu, np) = (inputs.len(), parameters.len());
    let window = along_prior(ggl, inputs, parameters, sensors, |phi_q, partition| {
        Window::start(phi_q, partition, (nu, np), k, limit)
    })?;
    Ok(window.finish())
}

/// The window that `start` makes from the constraint Jacobian at the start of `ggl` (as
/// [`numerical`]), filled with `sensors`' rows along the prior trajectory: the prediction
/// from the initial guesses, uncorrected.
pub fn along_prior(
    mut ggl: Ggl,
    inputs: &Inputs,
    parameters: &Parameters,
    sensors: &[Sensor],
    start: impl FnOnce(&Mat<f64>, &mut Partition) -> Result<Window, String>,
) -> Result<Window, String> {
    let (n, m) = (ggl.system.size(), ggl.constraint_count());
    let (nu, np) = (inputs.len(), parameters.len());
    let big_n = 2 * n + nu + np;
    let theta = vec![1.0; np];
    parameters.apply(&theta, &mut ggl.system)?;
    inputs.apply(&vec![0.0; nu], &mut ggl.system);
    let jacobian_at = |ggl: &Ggl| {
        let mut phi_q = Mat::zeros(m, n);
        ggl.equations
            .constraints
            .jacobian(&ggl.system.layout, &ggl.q, ggl.time, phi_q.as_mut());
        phi_q
    };
    let first = jacobian_at(&ggl);
    let mut partition = Partition::choose(first.as_ref()).map_err(|e| format!("{e:?}"))?;
    let k = sensors.len();
    let mut window = start(&first, &mut partition)?;
    let variances: Vec<f64> = sensors.iter().map(|s| s.variance).collect();
    let mut augmented = Mat::identity(big_n, big_n);
    let (mut y, mut jm) = (vec![0.0; k], Mat::zeros(k, big_n));
    loop {
        let previous: Vec<f64> = ggl.q.iter().chain(&ggl.v).copied().collect();
        ggl.step().map_err(|e| e.to_string())?;
        let rates = parameters.rates(&theta, &ggl.system, &ggl.q, &ggl.v)?;
        let loads = inputs.unit_loads(&ggl.system, &ggl.q, ggl.time);
        let phi_q = jacobian_at(&ggl);
        let nullspace = partition
            .nullspace(phi_q.as_ref())
            .map_err(|e| format!("{e:?}"))?;
        let j = transition(
            &ggl,
            (&previous[..n], &previous[n..]),
            &nullspace,
            &loads,
            &rates,
        )
        .ok_or_else(|| {
            format!(
                "at t = {}: the projected step equations are singular",
                ggl.time
            )
        })?;
        let z = 2 * n;
        augmented
            .as_mut()
            .submatrix_mut(0, 0, z, z)
            .copy_from(&j.states);
        augmented
            .as_mut()
            .submatrix_mut(0, z, z, nu)
            .copy_from(&j.inputs);
        augmented
            .as_mut()
            .submatrix_mut(0, z + nu, z, np)
            .copy_from(&j.parameters);
        let x: Vec<f64> = (ggl.q.iter().chain(&ggl.v).copied())
            .chain(std::iter::repeat_n(0.0, nu))
            .chain(theta.iter().copied())
            .collect();
        measure(sensors, &ggl, &x, &previous[n..], &mut y, &mut jm);
        if window.add(&augmented, &jm, &variances) {
            return Ok(window);
        }
    }
}

/// ‖o_c − U Uᵀ o_c‖ for a unit column o_c of `o` and U the range of the other columns (left
/// singular vectors of singular values above [`RANK_TOLERANCE`] × the largest).
fn distance_from_others(o: &Mat<f64>, c: usize) -> f64 {
    let others = Mat::from_fn(o.nrows(), o.ncols() - 1, |i, j| {
        o[(i, j + usize::from(j >= c))]
    });
    let column: Vec<f64> = (0..o.nrows()).map(|i| o[(i, c)]).collect();
    let Ok(svd) = others.thin_svd() else {
        return 0.0;
    };
    let sigma = svd.S().column_vector();
    let largest = (0..sigma.nrows()).map(|i| sigma[i]).fold(0.0, f64::max);
    let mut residual = column.clone();
    for k in (0..sigma.nrows()).filter(|&k| sigma[k] > RANK_TOLERANCE * largest) {
        let u = svd.U().col(k);
        let along: f64 = (0..o.nrows()).map(|i| u[i] * column[i]).sum();
        for (i, r) in residual.iter_mut().enumerate() {
            *r -= along * u[i];
        }
    }
    residual.iter().map(|r| r * r).sum::<f64>().sqrt()
}
