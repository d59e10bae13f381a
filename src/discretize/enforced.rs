//! Enforced motion in frequency response: an RLOAD1/RLOAD2 with TYPE = DISP, VELO or ACCE
//! moves the DOFs of an SPCD set (its EXCITEID) by u_s(ω) (the load's P(ω) taken as a
//! displacement, a velocity divided by iω, or an acceleration divided by −ω², as Nastran
//! integrates them).
//!
//! The partitioned equations Z_ff u_f = −Z_fs u_s, Z = K(1 + iG) + iω(αM + βK + B) + iK₄ − ω²M,
//! are split per enforced DOF e (a unit motion): u_f = u_qs + w with the static shape
//! u_qs = −K_ff⁻¹ K_fs e. Since K_fs e + K_ff u_qs = 0, the stiffness-proportional terms (K, βK,
//! G·K) drop out and
//!
//! Z_ff w = ω² m_r − iω c_r − i k_r,
//! m_r = M_fs e + M_ff u_qs, c_r = α m_r + B_fs e + B_ff u_qs, k_r = K₄,fs e + K₄,ff u_qs,
//!
//! three constant load columns ([`EnforcedColumns`]): w is the receptance to them, computed by
//! the direct solution (exact, the partition method of SOL 108) or by mode superposition (SOL
//! 111: absolute response = quasi-static u_qs, exact, + the modal response w, which alone is
//! truncated; modal damping tables act on w only).

use faer::{Mat, c64};
use nalgebra_sparse::CscMatrix;

use super::loads::EnforcedLoad;
use super::{Constrained, Structure};
use crate::assembly::AffineOperator;
use crate::assembly::reduce::partition;
use crate::deck::cards::ExcitationKind;
use crate::dynamics::prescribed::{Drive, PrescribedMotion, PrescribedTerm};
use crate::linalg::{SymbolicFactor, sym_matvec};
use crate::model::Model;
use crate::model::sets::EnforcedEntry;

/// The load columns of the dynamic part of enforced unit motions, one column per enforced DOF
/// (f-set rows, n_f × e).
pub struct EnforcedColumns {
    /// The s-set position of each enforced DOF.
    pub s_positions: Vec<usize>,
    /// u_qs = −K_ff⁻¹ K_fs e.
    pub quasi_static: Mat<f64>,
    /// m_r (multiplies ω²).
    pub mass: Mat<f64>,
    /// c_r (multiplies −iω); `None` when zero (no α, no viscous elements).
    pub damping: Option<Mat<f64>>,
    /// k_r (multiplies −i); `None` without structural element damping.
    pub structural: Option<Mat<f64>>,
}

impl EnforcedColumns {
    /// The columns of the enforced DOFs `dofs` (g indices, each in `c`'s s-set) with Rayleigh
    /// mass factor `alpha`; `max_ratio` is PARAM,MAXRATIO for the factor of K_ff.
    pub fn new(
        st: &Structure,
        c: &Constrained,
        dofs: &[usize],
        alpha: f64,
        max_ratio: f64,
    ) -> Result<Self, String> {
        let n_f = c.sets.f.len();
        let n_s = c.sets.s.len();
        let s_positions = dofs
            .iter()
            .map(|&g| {
                c.sets.s.position(g).ok_or_else(|| {
                    format!("{} is not constrained: it cannot be moved", st.map.name(g))
                })
            })
            .collect::<Result<Vec<_>, _>>()?;
        let fs = |op: &AffineOperator| free_by_constrained(st, c, op);
        let (m_fs, m_fs_values) = fs(&st.m_nn)?;
        let damping_fs = st.damping.try_map(fs)?;
        let k_fs_values = stiffness_fs_values(st, c)?;
        let factor = SymbolicFactor::analyze(c.k_ff.pattern())
            .and_then(|s| {
                s.with_max_ratio(max_ratio)
                    .factor_llt(&c.k_ff, faer::Par::Seq)
            })
            .map_err(|e| format!("K_ff of the enforced-motion static shapes: {e}"))?;
        let e_cols = dofs.len();
        let mut out = EnforcedColumns {
            s_positions: s_positions.clone(),
            quasi_static: Mat::zeros(n_f, e_cols),
            mass: Mat::zeros(n_f, e_cols),
            damping: (alpha != 0.0 || damping_fs.viscous.is_some())
                .then(|| Mat::zeros(n_f, e_cols)),
            structural: damping_fs
                .structural
                .as_ref()
                .map(|_| Mat::zeros(n_f, e_cols)),
        };
        let mut scratch = vec![0.0; n_f];
        for (j, &s) in s_positions.iter().enumerate() {
            let mut unit = vec![0.0; n_s];
            unit[s] = 1.0;
            // u_qs = −K_ff⁻¹ K_fs e, with one refinement step as the static solution
            let k_col = c
                .k_fs
                .mul_values(&k_fs_values, &unit)
                .map_err(|e| e.to_string())?;
            let rhs: Vec<f64> = k_col.iter().map(|v| -v).collect();
            let u_qs = c
                .solve_static(&factor, &rhs)
                .map_err(|e| format!("enforced-motion static shape: {e}"))?;
            // r = A_fs e + A_ff u_qs for A = M, B, K₄
            let coupled = |a_fs: (&AffineOperator, &[f64]),
                           a_ff: &CscMatrix<f64>,
                           scratch: &mut [f64]|
             -> Result<Vec<f64>, String> {
                let mut r = a_fs
                    .0
                    .mul_values(a_fs.1, &unit)
                    .map_err(|e| e.to_string())?;
                sym_matvec(a_ff, &u_qs, scratch).map_err(|e| e.to_string())?;
                r.iter_mut().zip(scratch.iter()).for_each(|(x, y)| *x += y);
                Ok(r)
            };
            let m_r = coupled((&m_fs, &m_fs_values), &c.m_ff, &mut scratch)?;
            let b_r = match (&damping_fs.viscous, &c.damping_ff.viscous) {
                (Some((op, values)), Some(b_ff)) => {
                    Some(coupled((op, values), b_ff, &mut scratch)?)
                }
                _ => None,
            };
            let k4_r = match (&damping_fs.structural, &c.damping_ff.structural) {
                (Some((op, values)), Some(k4_ff)) => {
                    Some(coupled((op, values), k4_ff, &mut scratch)?)
                }
                _ => None,
            };
            for i in 0..n_f {
                out.quasi_static[(i, j)] = u_qs[i];
                out.mass[(i, j)] = m_r[i];
                if let Some(d) = out.damping.as_mut() {
                    d[(i, j)] = alpha * m_r[i] + b_r.as_ref().map_or(0.0, |b| b[i]);
                }
                if let (Some(k), Some(k4)) = (out.structural.as_mut(), &k4_r) {
                    k[(i, j)] = k4[i];
                }
            }
        }
        Ok(out)
    }

    /// The load columns of the dynamic part, side by side: mass, then damping and structural
    /// when present (n_f × e·(1 to 3)).
    pub fn load_columns(&self) -> Vec<&Mat<f64>> {
        std::iter::once(&self.mass)
            .chain(self.damping.as_ref())
            .chain(self.structural.as_ref())
            .collect()
    }
}

/// The f × s block of an n-set operator and its values at the subcase's weights.
fn free_by_constrained(
    st: &Structure,
    c: &Constrained,
    op: &AffineOperator,
) -> Result<(AffineOperator, Vec<f64>), String> {
    let op = partition(op, &c.sets.f_in_n, &c.sets.s_in_n).map_err(|e| e.to_string())?;
    let values = op
        .evaluate(&c.weights(st, &op))
        .map_err(|e| e.to_string())?;
    let values = values.values().to_vec();
    Ok((op, values))
}

/// The values of K_fs at the subcase's weights.
fn stiffness_fs_values(st: &Structure, c: &Constrained) -> Result<Vec<f64>, String> {
    Ok(c.k_fs
        .evaluate(&c.weights(st, &c.k_fs))
        .map_err(|e| e.to_string())?
        .values()
        .to_vec())
}

/// The coupling of enforced motions with the free DOFs in the time domain (absolute
/// formulation, [`crate::dynamics::prescribed`]): per moved pattern e_j of the s-set, the
/// columns M_fs e_j, C_fs e_j and K_fs e_j, with C = αM + βK + B + w₄·K₄ the transient damping
/// of the full model (Rayleigh α, β; the elements' viscous B; their structural damping K₄
/// weighted by w₄ = 1/W4, or 0).
pub struct EnforcedCoupling {
    pub mass: Vec<f64>,
    pub damping: Vec<f64>,
    pub stiffness: Vec<f64>,
}

/// Rayleigh and structural weights of the transient damping C = αM + βK + B + w₄·K₄.
#[derive(Debug, Clone, Copy)]
pub struct TransientDamping {
    pub alpha: f64,
    pub beta: f64,
    pub structural: f64,
}

impl EnforcedCoupling {
    /// The columns of each s-set pattern of `patterns` (n_s each).
    pub fn of_patterns(
        st: &Structure,
        c: &Constrained,
        patterns: &[Vec<f64>],
        damping: TransientDamping,
    ) -> Result<Vec<Self>, String> {
        let (m_fs, m_values) = free_by_constrained(st, c, &st.m_nn)?;
        let damping_fs = st.damping.try_map(|op| free_by_constrained(st, c, op))?;
        let k_values = stiffness_fs_values(st, c)?;
        let product = |op: &AffineOperator, values: &[f64], e: &[f64]| {
            op.mul_values(values, e).map_err(|e| e.to_string())
        };
        patterns
            .iter()
            .map(|e| {
                let mass = product(&m_fs, &m_values, e)?;
                let stiffness = product(&c.k_fs, &k_values, e)?;
                let mut damping_col: Vec<f64> = mass
                    .iter()
                    .zip(&stiffness)
                    .map(|(m, k)| damping.alpha * m + damping.beta * k)
                    .collect();
                let weighted = [
                    (1.0, damping_fs.viscous.as_ref()),
                    (damping.structural, damping_fs.structural.as_ref()),
                ];
                for (w, block) in weighted {
                    if let (Some((op, values)), true) = (block, w != 0.0) {
                        let col = product(op, values, e)?;
                        damping_col
                            .iter_mut()
                            .zip(&col)
                            .for_each(|(d, x)| *d += w * x);
                    }
                }
                Ok(EnforcedCoupling {
                    mass,
                    damping: damping_col,
                    stiffness,
                })
            })
            .collect()
    }
}

/// The enforced motions of a time-domain subcase: each [`EnforcedLoad`]'s s-set pattern e_j
/// (its SPCD values) and coupling columns; g_j(t) = F_j(t − delay_j).
pub struct EnforcedMotion {
    pub patterns: Vec<Vec<f64>>,
    pub couplings: Vec<EnforcedCoupling>,
}

impl EnforcedMotion {
    /// The patterns and couplings of `loads` with the model's transient damping (PARAM,ALPHA1,
    /// BETA1 with G/W3, W4).
    pub fn new(
        model: &Model,
        st: &Structure,
        c: &Constrained,
        loads: &[EnforcedLoad],
    ) -> Result<Self, String> {
        let patterns = loads
            .iter()
            .map(|l| {
                enforced_pattern(model, st, c, &l.entries).map_err(|e| format!("{}: {e}", l.name))
            })
            .collect::<Result<Vec<_>, _>>()?;
        let p = &model.params;
        let damping = TransientDamping {
            alpha: p.alpha1,
            beta: p.transient_beta(),
            structural: if p.w4 > 0.0 { 1.0 / p.w4 } else { 0.0 },
        };
        let couplings = if loads.is_empty() {
            Vec::new()
        } else {
            EnforcedCoupling::of_patterns(st, c, &patterns, damping)?
        };
        Ok(EnforcedMotion {
            patterns,
            couplings,
        })
    }

    /// The integrator's prescribed terms from time `t0`: each load's F as the displacement,
    /// velocity or acceleration of its pattern, started at F's right-hand derivatives at t0.
    pub fn prescribed<'a>(&self, loads: &'a [EnforcedLoad], t0: f64) -> PrescribedMotion<'a> {
        PrescribedMotion::new(
            loads
                .iter()
                .zip(&self.couplings)
                .map(|(load, coupling)| {
                    let [f, d1, d2] = load.function.derivatives(t0 - load.delay);
                    let (drive, initial) = match load.kind {
                        ExcitationKind::Velocity => (Drive::Velocity, [0.0, f, d1]),
                        ExcitationKind::Acceleration => (Drive::Acceleration, [0.0, 0.0, f]),
                        _ => (Drive::Displacement, [f, d1, d2]),
                    };
                    PrescribedTerm {
                        drive,
                        function: Box::new(move |t| load.function.value(t - load.delay)),
                        initial,
                        mass: coupling.mass.clone(),
                        damping: coupling.damping.clone(),
                        stiffness: coupling.stiffness.clone(),
                    }
                })
                .collect(),
        )
    }
}

/// The s-set displacement, velocity and acceleration Σ_j e_j (g_j, ġ_j, g̈_j) of the moved DOFs.
pub struct MovedState {
    pub u: Vec<f64>,
    pub v: Vec<f64>,
    pub a: Vec<f64>,
}

impl MovedState {
    /// At rest, for an s-set of `n_s` DOFs.
    pub fn new(n_s: usize) -> Self {
        MovedState {
            u: vec![0.0; n_s],
            v: vec![0.0; n_s],
            a: vec![0.0; n_s],
        }
    }

    /// The displacements written over a g-set vector at the s-set's g indices `s_members`.
    pub fn scatter_displacement(&self, s_members: &[usize], u_g: &mut [f64]) {
        for (&g, &u) in s_members.iter().zip(&self.u) {
            u_g[g] = u;
        }
    }

    /// Σ_j e_j (g_j, ġ_j, g̈_j) for the patterns e_j and the terms' kinematics.
    pub fn set(&mut self, patterns: &[Vec<f64>], kinematics: &[[f64; 3]]) {
        for x in [&mut self.u, &mut self.v, &mut self.a] {
            x.fill(0.0);
        }
        for (e, k) in patterns.iter().zip(kinematics) {
            for (i, ei) in e.iter().enumerate().filter(|(_, x)| **x != 0.0) {
                self.u[i] += ei * k[0];
                self.v[i] += ei * k[1];
                self.a[i] += ei * k[2];
            }
        }
    }
}

/// The s-set pattern (n_s) of enforced-motion SPCD entries: each moved DOF's value at its
/// s-set position ([`enforced_dofs`]'s checks).
pub fn enforced_pattern(
    model: &Model,
    st: &Structure,
    c: &Constrained,
    entries: &[EnforcedEntry],
) -> Result<Vec<f64>, String> {
    let mut e = vec![0.0; c.sets.s.len()];
    for (g, value) in enforced_dofs(model, st, c, entries)? {
        let s =
            c.sets.s.position(g).ok_or_else(|| {
                format!("{} is not constrained: it cannot be moved", st.map.name(g))
            })?;
        e[s] += value;
    }
    Ok(e)
}

/// The g indices of the DOFs an enforced-motion load's SPCD entries name, checked against the
/// subcase's s-set ([`crate::assembly::spc::SpcSet::with_spcd`]'s rule), each with its value.
pub fn enforced_dofs(
    model: &Model,
    st: &Structure,
    c: &Constrained,
    entries: &[EnforcedEntry],
) -> Result<Vec<(usize, f64)>, String> {
    c.spc
        .with_spcd(model, &st.map, entries)
        .map_err(|e| e.to_string())?;
    let mut out = Vec::new();
    for entry in entries {
        let grid = *model.grid_index.get(&entry.grid).ok_or_else(|| {
            format!(
                "SPCD {} at {}: enforced motion of a scalar point is not supported; use a grid",
                entry.set, entry.loc
            )
        })?;
        for comp in entry.components.components() {
            out.push((crate::assembly::DofMap::dof(grid, comp - 1), entry.value));
        }
    }
    Ok(out)
}

impl EnforcedColumns {
    /// The receptance with the enforced inputs composed: `h_solve` holds, per line, the
    /// outputs' response to the `loads` applied-load columns followed by [`Self::load_columns`];
    /// the result keeps the load columns and appends, per enforced DOF, the response to its unit
    /// motion O_f (u_qs + w) + O_s e with w = ω² H m_r − iω H c_r − i H k_r. `outputs` (o × n_f)
    /// and `outputs_s` (o × n_s) are the output rows on the free and the constrained DOFs.
    pub fn compose(
        &self,
        h_solve: &[Mat<c64>],
        loads: usize,
        omegas: &[f64],
        outputs: &CscMatrix<f64>,
        outputs_s: &CscMatrix<f64>,
    ) -> Vec<Mat<c64>> {
        let e = self.s_positions.len();
        let o = outputs.nrows();
        // the frequency-independent part O_f u_qs + O_s e
        let mut fixed = Mat::<f64>::zeros(o, e);
        for (col, column) in outputs.col_iter().enumerate() {
            for (&row, &v) in column.row_indices().iter().zip(column.values()) {
                for j in 0..e {
                    fixed[(row, j)] += v * self.quasi_static[(col, j)];
                }
            }
        }
        for (j, &s) in self.s_positions.iter().enumerate() {
            let column = outputs_s.col(s);
            for (&row, &v) in column.row_indices().iter().zip(column.values()) {
                fixed[(row, j)] += v;
            }
        }
        // first solve column of each block: mass at `loads`, then damping, then structural
        let damping = self.damping.is_some().then_some(loads + e);
        let structural = (self.structural.is_some())
            .then(|| loads + e * (1 + usize::from(self.damping.is_some())));
        h_solve
            .iter()
            .zip(omegas)
            .map(|(hs, &w)| {
                Mat::from_fn(o, loads + e, |r, col| {
                    let Some(j) = col.checked_sub(loads) else {
                        return hs[(r, col)];
                    };
                    let mut v = c64::new(fixed[(r, j)], 0.0) + hs[(r, loads + j)] * (w * w);
                    if let Some(first) = damping {
                        v -= hs[(r, first + j)] * c64::new(0.0, w);
                    }
                    if let Some(first) = structural {
                        v -= hs[(r, first + j)] * c64::new(0.0, 1.0);
                    }
                    v
                })
            })
            .collect()
    }

    /// The solve's load columns: `loads` (n_f × k, its first `applied` columns the applied
    /// loads) followed by [`Self::load_columns`].
    pub fn solve_columns(&self, loads: &Mat<f64>, applied: usize) -> Mat<f64> {
        let extra = self.load_columns();
        let e = self.s_positions.len();
        Mat::from_fn(loads.nrows(), applied + e * extra.len(), |i, j| {
            match j.checked_sub(applied) {
                None => loads[(i, j)],
                Some(k) => extra[k / e][(i, k % e)],
            }
        })
    }
}
