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

use super::{Constrained, Structure};
use crate::assembly::AffineOperator;
use crate::assembly::reduce::partition;
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
        let fs = |op: &AffineOperator| -> Result<(AffineOperator, Vec<f64>), String> {
            let op = partition(op, &c.sets.f_in_n, &c.sets.s_in_n).map_err(|e| e.to_string())?;
            let values = op
                .evaluate(&c.weights(st, &op))
                .map_err(|e| e.to_string())?;
            let values = values.values().to_vec();
            Ok((op, values))
        };
        let (m_fs, m_fs_values) = fs(&st.m_nn)?;
        let damping_fs = st.damping.try_map(fs)?;
        let k_fs_values = c
            .k_fs
            .evaluate(&c.weights(st, &c.k_fs))
            .map_err(|e| e.to_string())?
            .values()
            .to_vec();
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
                "SPCD {} at {}: enforced motion of a scalar point in frequency response is not supported; use a grid",
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
