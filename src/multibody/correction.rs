//! The metric of the GGL position correction. Eq. 2.60 corrects the positions along Φ_qᵀ μ,
//! q̇ − v = Φ_qᵀ μ; any symmetric positive definite W in its place, q̇ − v = W Φ_qᵀ μ, leaves
//! the solution unchanged (with Φ_q v + Φ_t = 0 and Φ = 0, Φ_q W Φ_qᵀ μ = 0, so μ = 0 while
//! Φ_q has full rank), but the discrete μ of a step is not zero: it takes up the drift of the
//! scheme, and W decides which coordinates move to take it up. The correction is the
//! projection onto Φ = 0 in the metric W⁻¹ (Bauchau & Laulusa, "Review of classical
//! approaches for constraint enforcement in multibody systems", J. Comput. Nonlinear Dynam. 3,
//! 2008: a projection is defined by the choice of its metric).
//!
//! With W = I (eq. 2.60 as written) the metric is that of the coordinates' numbers, and a
//! flexible body's reduced coordinates have no units of their own: rescaling a body's basis by
//! c weights its share of the correction by c². Whatever share the flexible coordinates take
//! costs twice: as strain (a pROM basis with stiff directions large at a joint turns it into
//! far more strain at a gauge than a ROM basis of other columns does) and as velocity (in
//! steady motion q_f − q̂_f − c_q v_f = δ_f leaves v_f off the coordinates' rate by δ_f / c_q,
//! which the damping and the quadratic velocity vector then act on). The frames take the
//! correction without either wherever they can satisfy the constraints, so
//! [`CorrectionMetric::StepInertia`] keeps eq. 2.60's identity on every frame coordinate (r
//! and e; a rigid body is unchanged) and gives the flexible coordinates of a body of mass m
//!
//! ```text
//! W_ff = ε m (M_ff + c_q c_v K_ff)⁻¹,    ε = FLEXIBLE_SHARE,
//! ```
//!
//! the inverse of the metric the step gives them — their mass plus the strain energy over
//! c_q c_v ≈ h², as in the velocity block of the iteration matrix — per unit of body mass (the
//! normalization under which a frame translation's metric is |Δr|², the mass metric m |Δr|²
//! over m), times ε. Under q_f = T q_f' the block transforms as T⁻¹ W_ff T⁻ᵀ, so the physical
//! correction Ψ W_ff Ψᵀ μ of the body's points depends neither on the basis's units nor on
//! how it spans its space, and ε is a dimensionless share: a mode of circular frequency ω
//! takes about ε / (1 + ω² c_q c_v) of what a frame would. The flexible coordinates still take
//! what the frames cannot (out of plane in a planar loop of flexible links, whose frames alone
//! do not satisfy every row): in the step's metric, soft modes first, stiff ones through their
//! static compliance, which a basis with attachment modes reproduces. Φ_q W Φ_qᵀ then has
//! rows of size ε next to rows of size one: a scaling, which the LU's pivoting absorbs.
//!
//! The same metric gives the minimum-norm projections of the start (assembly and initial
//! velocities, [`super::integrator`]). Measured (docs/fourbar.md): the composite four-bar's
//! coupler gauge at Θ = 0° against the FMB of ROMs, 1.9e-2 with W = I, 5.6e-4 (the pROM's own
//! error) for every ε ≤ 1e-2; the spun strip of tests/fmb_strip.rs against SOL 101 at the
//! ramp's peak, −2.1e-2 with ε = 1, −2.0e-3 with 1e-2, 8e-6 with 1e-4 and 3e-5 below (W = I:
//! −3.9e-3). ε = 1e-4 lies two decades below where the share shows and keeps the scaling of
//! Φ_q W Φ_qᵀ to four decades.

use super::dense_lu::DenseLu;
use super::error::MultibodyError;
use super::flexible::FlexibleBodyData;
use super::system::System;
use faer::Mat;

/// ε: the flexible coordinates' share of the correction relative to a frame's (module docs).
pub const FLEXIBLE_SHARE: f64 = 1e-4;

/// Entry (i, j) of a flexible body's W_ff⁻¹ = (M_ff + c_q c_v K_ff) / (ε m), `c` = c_q c_v.
fn inverse_block_entry(data: &FlexibleBodyData, c: f64, i: usize, j: usize) -> f64 {
    (data.mass[(i, j)] + c * data.stiffness[(i, j)]) / (FLEXIBLE_SHARE * data.invariants.mass)
}

/// W⁻¹ of `metric` for a step with factors c_q, c_v, dense and of the system's size: the
/// identity on the frames, W_ff⁻¹ on each body's flexible coordinates. Vᵀ W⁻¹ with
/// Vᵀ Φ_qᵀ = 0 removes the multipliers W Φ_qᵀ μ from a step's position equation.
pub fn inverse_weight(system: &System, metric: CorrectionMetric, c_q: f64, c_v: f64) -> Mat<f64> {
    let n = system.size();
    let mut out = Mat::identity(n, n);
    if metric == CorrectionMetric::Coordinates {
        return out;
    }
    for (body, slice) in system.bodies.iter().zip(system.layout.slices()) {
        let first = slice.flexible();
        for j in 0..slice.modes {
            for i in 0..slice.modes {
                out[(first + i, first + j)] = inverse_block_entry(&body.data, c_q * c_v, i, j);
            }
        }
    }
    out
}

/// Which metric the GGL position correction uses (module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CorrectionMetric {
    /// W = I: eq. 2.60 as written, the flexible coordinates in their own units.
    Coordinates,
    /// W = I on the frames, ε m (M_ff + c_q c_v K_ff)⁻¹ on each body's flexible coordinates.
    StepInertia,
}

/// The weight W of the correction for one step form, block diagonal by body (module docs).
#[derive(Debug, Clone)]
pub struct CorrectionWeight {
    metric: CorrectionMetric,
    /// Each flexible body's first flexible coordinate and its block W_ff.
    blocks: Vec<(usize, Mat<f64>)>,
    /// The c_q c_v the blocks were formed for.
    formed_for: Option<f64>,
    /// Scratch of a block's length.
    scratch: Vec<f64>,
}

impl CorrectionWeight {
    /// No blocks yet: [`CorrectionWeight::form`] sets them for a step form.
    pub fn new(metric: CorrectionMetric) -> Self {
        Self {
            metric,
            blocks: Vec::new(),
            formed_for: None,
            scratch: Vec::new(),
        }
    }

    /// Forms the flexible blocks for the factors c_q, c_v of a step (kept while c_q c_v is
    /// unchanged). An error when M_ff + c_q c_v K_ff of a body is singular.
    pub fn form(&mut self, system: &System, c_q: f64, c_v: f64) -> Result<(), MultibodyError> {
        let c = c_q * c_v;
        if self.metric == CorrectionMetric::Coordinates || self.formed_for == Some(c) {
            return Ok(());
        }
        self.blocks.clear();
        for (body, (data, slice)) in system
            .bodies
            .iter()
            .map(|b| &b.data)
            .zip(system.layout.slices())
            .enumerate()
        {
            let n = slice.modes;
            if n == 0 {
                continue;
            }
            let mut lu = DenseLu::new(n);
            let mut a = lu.matrix_mut();
            for j in 0..n {
                for i in 0..n {
                    a[(i, j)] = inverse_block_entry(data, c, i, j);
                }
            }
            lu.factor();
            let mut w = Mat::identity(n, n);
            for j in 0..n {
                lu.solve(w.col_as_slice_mut(j));
            }
            if (0..n).any(|j| w.col_as_slice(j).iter().any(|x| !x.is_finite())) {
                return Err(MultibodyError::Input(format!(
                    "body {body}: M_ff + c_q c_v K_ff (the metric of the position correction) \
                     is singular"
                )));
            }
            self.blocks.push((slice.flexible(), w));
            self.scratch.resize(self.scratch.len().max(n), 0.0);
        }
        self.formed_for = Some(c);
        Ok(())
    }

    /// x ← W x (x of the system's size).
    pub fn apply(&mut self, x: &mut [f64]) {
        self.apply_to_column(None, x);
    }

    /// ∂W/∂p x for the rate `rate` = ∂D/∂p of the data of the flexible body whose flexible
    /// coordinates start at `first` (`modes` of them), with `data` its data: zero outside
    /// the body's block, and there, with A = W_ff⁻¹ = (M_ff + c K_ff)/(ε m) and
    /// ∂W = −W ∂A W, ∂A = (∂M_ff + c ∂K_ff)/(ε m) − A ∂m/m,
    /// ∂W x = −W (∂M_ff + c ∂K_ff) W x/(ε m) + (∂m/m) W x. Needs the blocks formed for the
    /// step ([`CorrectionWeight::form`]), c = c_q c_v.
    pub fn rate_product(
        &mut self,
        (first, modes): (usize, usize),
        data: &FlexibleBodyData,
        rate: &FlexibleBodyData,
        x: &[f64],
    ) -> Vec<f64> {
        let mut out = vec![0.0; x.len()];
        let (CorrectionMetric::StepInertia, Some(c)) = (self.metric, self.formed_for) else {
            return out;
        };
        if modes == 0 {
            return out;
        }
        let range = first..first + modes;
        let mut wx = vec![0.0; x.len()];
        wx[range.clone()].copy_from_slice(&x[range.clone()]);
        self.apply(&mut wx);
        let m = data.invariants.mass;
        let mut z = vec![0.0; x.len()];
        for (i, zi) in z[range.clone()].iter_mut().enumerate() {
            *zi = -(0..modes)
                .map(|j| (rate.mass[(i, j)] + c * rate.stiffness[(i, j)]) * wx[first + j])
                .sum::<f64>()
                / (FLEXIBLE_SHARE * m);
        }
        self.apply(&mut z);
        let share = rate.invariants.mass / m;
        for i in range {
            out[i] = z[i] + share * wx[i];
        }
        out
    }

    /// x ← W (x − e_j) + e_j for column j of a matrix I + X (system size): W applied to X,
    /// the identity left in place.
    pub fn apply_beside_identity(&mut self, j: usize, x: &mut [f64]) {
        self.apply_to_column(Some(j), x);
    }

    /// [`CorrectionWeight::apply`], or with the identity's column j kept.
    fn apply_to_column(&mut self, identity: Option<usize>, x: &mut [f64]) {
        for (first, w) in &self.blocks {
            let n = w.nrows();
            let range = *first..*first + n;
            let unit = identity.filter(|j| range.contains(j)).map(|j| j - first);
            let (block, out) = (&mut x[range], &mut self.scratch[..n]);
            if let Some(k) = unit {
                block[k] -= 1.0;
            }
            out.fill(0.0);
            for (j, &xj) in block.iter().enumerate() {
                if xj != 0.0 {
                    for (o, wij) in out.iter_mut().zip(w.col_as_slice(j)) {
                        *o += wij * xj;
                    }
                }
            }
            block.copy_from_slice(out);
            if let Some(k) = unit {
                block[k] += 1.0;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::multibody::flexible::{FlexibleBodyData, MassInvariants, NodalMass};
    use crate::multibody::{Body, System};

    /// A rigid body, then a free flexible body of two nodes and two modes whose flexible
    /// coordinates are in units 1/c of the c = 1 body's (basis × c, M_ff and K_ff × c²).
    fn system(c: f64) -> System {
        let basis = [
            [[1.0, 0.2, 0.0], [0.0, 1.0, 0.1]],
            [[-1.0, 0.3, 0.0], [0.5, -1.0, 0.0]],
        ];
        let nodes: Vec<NodalMass> = (0..2)
            .map(|j| NodalMass {
                mass: 0.5,
                position: [j as f64, 0.0, 0.0],
                modes: basis[j].iter().map(|row| row.map(|x| c * x)).collect(),
            })
            .collect();
        let mass = Mat::from_fn(2, 2, |i, k| c * c * [[1.0, 0.1], [0.1, 0.8]][i][k]);
        let stiffness = Mat::from_fn(2, 2, |i, k| c * c * [[4e6, 1e5], [1e5, 9e4]][i][k]);
        let mut sys = System::new([0.0; 3]);
        let inertia = [[0.1, 0.0, 0.0], [0.0, 0.2, 0.0], [0.0, 0.0, 0.3]];
        sys.add_body(Body::rigid(2.0, inertia), [0.0; 3], [1.0, 0.0, 0.0, 0.0]);
        sys.add_body(
            Body::flexible(FlexibleBodyData {
                invariants: MassInvariants::from_nodes(&nodes),
                damping: Mat::zeros(2, 2),
                mass,
                stiffness,
                interfaces: Vec::new(),
            }),
            [0.0; 3],
            [1.0, 0.0, 0.0, 0.0],
        );
        sys
    }

    #[test]
    fn frames_keep_the_identity_and_the_correction_ignores_the_flexible_units() {
        let (c_q, c_v) = (1e-3, 1e-3);
        // a generalized force: unit weight on the frames, Ψᵀ f on the flexible coordinates
        let frames = [0.3, -0.2, 0.1, 0.7, 0.05, -0.4, 0.2];
        let displaced = |c: f64| {
            let sys = system(c);
            let mut weight = CorrectionWeight::new(CorrectionMetric::StepInertia);
            weight.form(&sys, c_q, c_v).unwrap();
            let mut x: Vec<f64> = frames.iter().chain(&frames).copied().collect();
            x.extend([0.4 * c, -1.1 * c]);
            weight.apply(&mut x);
            // the frames as given, the flexible coordinates back in the c = 1 units
            assert_eq!(
                &x[..14],
                frames.iter().chain(&frames).copied().collect::<Vec<_>>()
            );
            [x[14] * c, x[15] * c]
        };
        let (one, small) = (displaced(1.0), displaced(1e-2));
        for (a, b) in one.iter().zip(&small) {
            assert!((a - b).abs() < 1e-12 * a.abs(), "{a} vs {b}");
        }
        // (M_ff + c_q c_v K_ff)/(ε m) times the result is the input (m = 1)
        let metric = [[1.0 + 4.0, 0.1 + 0.1], [0.1 + 0.1, 0.8 + 0.09]];
        for (row, input) in metric.iter().zip([0.4, -1.1]) {
            let back = (row[0] * one[0] + row[1] * one[1]) / FLEXIBLE_SHARE;
            assert!((back - input).abs() < 1e-10, "{back} vs {input}");
        }
    }

    #[test]
    fn the_coordinates_metric_is_the_identity() {
        let sys = system(1.0);
        let mut weight = CorrectionWeight::new(CorrectionMetric::Coordinates);
        weight.form(&sys, 1e-3, 1e-3).unwrap();
        let mut x: Vec<f64> = (0..16).map(|i| i as f64 - 3.5).collect();
        let before = x.clone();
        weight.apply(&mut x);
        weight.apply_beside_identity(15, &mut x);
        assert_eq!(x, before);
    }
}
