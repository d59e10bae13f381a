//! The metric of the GGL position correction. Eq. 2.60 corrects the positions along Φ_qᵀ μ,
//! q̇ − v = Φ_qᵀ μ; any symmetric positive definite W in its place, q̇ − v = W Φ_qᵀ μ, leaves
//! the solution unchanged (with Φ_q v + Φ_t = 0 and Φ = 0, Φ_q W Φ_qᵀ μ = 0, so μ = 0 while
//! Φ_q has full rank), but the discrete μ of a step is not zero: it takes up the drift of the
//! scheme, and W decides which coordinates move to take it up. The correction is the
//! projection onto Φ = 0 in the metric W⁻¹ (Bauchau & Laulusa, "Review of classical
//! approaches for constraint enforcement in multibody systems", J. Comput. Nonlinear Dynam. 3,
//! 2008: the projection is defined by the choice of a metric).
//!
//! With W = I (eq. 2.60 as written) the metric is that of the coordinates' numbers, and a
//! flexible body's reduced coordinates have no units of their own: rescaling a body's basis by
//! c weights its share of the correction by c², and a basis with stiff directions large at a
//! joint (a pROM's columns from samples far apart) turns the correction into strain that a
//! basis of the same span in other units does not. [`CorrectionMetric::StepInertia`] makes W
//! independent of those units: the identity on every frame coordinate (r and e, as eq. 2.60;
//! a rigid body is unchanged) and, for the flexible coordinates of a body of mass m,
//!
//! ```text
//! W_ff = m (M_ff + c_q c_v K_ff)⁻¹,
//! ```
//!
//! the inverse of the metric the step gives those coordinates — their mass, plus the strain
//! energy over c_q c_v ≈ h² as in the velocity block of the iteration matrix — per unit
//! of body mass, the normalization under which a frame translation's metric is |Δr|² (the mass
//! metric m |Δr|² over m). Under q_f = T q_f' the block transforms as T⁻¹ W_ff T⁻ᵀ, so the
//! physical correction Ψ W_ff Ψᵀ μ of the body's points does not depend on the basis's units
//! nor on how it spans its space. A mode of circular frequency ω takes a share of the
//! correction about 1/(1 + ω² c_q c_v) of a frame's: modes the step resolves move like the
//! frame, and modes far above 1/h take it up through their static compliance, which a
//! reduced basis with attachment modes reproduces exactly. Φ_q W Φ_qᵀ stays well conditioned:
//! where the frames alone cannot satisfy a constraint (out of plane in a planar loop of
//! flexible links), the soft modes that can have weights of order one.

use super::dense_lu::DenseLu;
use super::error::MultibodyError;
use super::system::System;
use faer::Mat;

/// Which metric the GGL position correction uses (module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CorrectionMetric {
    /// W = I: eq. 2.60 as written, the flexible coordinates in their own units.
    Coordinates,
    /// W = I on the frames, m (M_ff + c_q c_v K_ff)⁻¹ on each body's flexible coordinates.
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
            let mass = data.invariants.mass;
            let mut lu = DenseLu::new(n);
            let mut a = lu.matrix_mut();
            for j in 0..n {
                for i in 0..n {
                    a[(i, j)] = (data.mass[(i, j)] + c * data.stiffness[(i, j)]) / mass;
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
