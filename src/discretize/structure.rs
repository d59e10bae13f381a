//! The assembled parametric structure of a model ([`Structure`]: K(p), M(p) on the n-set) and
//! its constrained system for one SPC set at one parameter point ([`Constrained`]: K_ff, M_ff).

use std::sync::Arc;
use std::time::{Duration, Instant};

use nalgebra_sparse::CscMatrix;

use super::elements::{self, ShellRecovery};
use super::parameters::Parameters;
use super::{BuildOptions, DiscretizeError};
use crate::assembly::error::DofName;
use crate::assembly::reduce::{GToN, Partition};
use crate::assembly::spc::{AutoSpcReport, SpcSet, autospc, null_dofs};
use crate::assembly::{AffineOperator, DofMap, GridFrames, ParamKey, RigidElimination, Sets};
use crate::deck::Solution;
use crate::linalg::{Factor, LinalgError, Progress, sym_matvec};
use crate::model::Model;
use crate::rom::build::AffineFom;

/// The assembled structure shared by every subcase: K and M on one g pattern, reduced to n.
pub struct Structure {
    pub map: DofMap,
    pub frames: GridFrames,
    pub rigid: RigidElimination,
    /// K_nn and M_nn as affine operators on one shared pattern.
    pub k_nn: AffineOperator,
    pub m_nn: AffineOperator,
    /// The viscous damping B_nn and the structural damping Σ GE_e K_e on the same pattern,
    /// when some element has them ([`elements::ElementMatrices::damping`], `structural`).
    pub damping: ElementDamping<AffineOperator>,
    /// M_gg when rigid elements make n ≠ g (GRAV loads need it; see [`Structure::mass_gg`]).
    m_gg: Option<AffineOperator>,
    /// Recovery data of each shell (strains), by index into `model.elements`.
    pub shells: Vec<(usize, ShellRecovery)>,
    /// The PMPARs the affine parts are functions of.
    pub params: Parameters,
    /// The PMPARs that freeze the condensation of a CQUAD4's incompatible modes at the deck's
    /// section ([`elements::ElementMatrices::frozen_condensation`]).
    pub frozen_condensation: Vec<String>,
}

impl Structure {
    /// Element matrices, assembly on one pattern, rigid elimination.
    pub fn build(
        model: &Model,
        options: &BuildOptions,
        progress: &dyn Progress,
    ) -> Result<Self, DiscretizeError> {
        Self::build_timed(model, options, progress, &mut |_, _| {})
    }

    /// [`Structure::build`], reporting the wall-clock time of each of its three steps
    /// (`element matrices`, `assembly`, `rigid elimination g → n`, the last with the release
    /// of the element matrices) to `record`.
    pub fn build_timed(
        model: &Model,
        options: &BuildOptions,
        progress: &dyn Progress,
        record: &mut dyn FnMut(&'static str, Duration),
    ) -> Result<Self, DiscretizeError> {
        let mut time = |name: &'static str, start: Instant| record(name, start.elapsed());
        let map = DofMap::of_model(model);
        let frames = GridFrames::of_model(model);
        let params = Parameters::of_model(model)?;
        let start = Instant::now();
        let elements =
            elements::element_matrices(model, &frames, &params, options.parallel, progress);
        time("element matrices", start);
        let elements = elements?;
        let start = Instant::now();
        let assembled = (|| -> Result<_, DiscretizeError> {
            progress.step("assembly", 0, 2);
            let lists = elements
                .stiffness
                .iter()
                .chain(&elements.mass)
                .chain(&elements.damping)
                .chain(&elements.structural)
                .map(|c| c.dofs.as_slice());
            let pattern = Arc::new(crate::assembly::pattern::grid_block_pattern(
                map.grids(),
                map.scalar_points(),
                lists,
            )?);
            let k =
                AffineOperator::assemble(pattern.clone(), &elements.stiffness, options.parallel)?;
            progress.step("assembly", 1, 2);
            let m = AffineOperator::assemble(pattern.clone(), &elements.mass, options.parallel)?;
            let optional = |list: &[crate::assembly::Contribution]| {
                (!list.is_empty())
                    .then(|| AffineOperator::assemble(pattern.clone(), list, options.parallel))
                    .transpose()
            };
            let damping = ElementDamping {
                viscous: optional(&elements.damping)?,
                structural: optional(&elements.structural)?,
            };
            progress.step("assembly", 2, 2);
            Ok((k, m, damping))
        })();
        time("assembly", start);
        let (k_gg, m_gg, damping_gg) = assembled?;
        // the element matrices are assembled: only the shells' recovery data stay (their
        // release is timed with the next step)
        let start = Instant::now();
        let frozen_condensation =
            params.names_on(&elements.frozen_condensation, &elements::SECTION_STIFFNESS);
        let shells = elements.shells;
        drop((
            elements.stiffness,
            elements.mass,
            elements.damping,
            elements.structural,
        ));
        return_freed_memory();
        let reduced = (|| -> Result<_, DiscretizeError> {
            let rigid = RigidElimination::of_model(model, &frames, &map)?;
            if rigid.m_mask.iter().any(|&m| m) {
                let plan = GToN::new(k_gg.pattern().clone(), &rigid.t)?;
                let (k_nn, m_nn) = (plan.apply(&k_gg)?, plan.apply(&m_gg)?);
                let damping = damping_gg.try_map(|op| plan.apply(op))?;
                Ok((rigid, k_nn, m_nn, damping, Some(m_gg)))
            } else {
                // no dependent DOFs: n = g in the same order and T = I, so K_nn = K_gg (no copy)
                Ok((rigid, k_gg, m_gg, damping_gg, None))
            }
        })();
        time("rigid elimination g → n", start);
        let (rigid, k_nn, m_nn, damping, m_gg) = reduced?;
        Ok(Structure {
            map,
            frames,
            rigid,
            k_nn,
            m_nn,
            damping,
            m_gg,
            shells,
            params,
            frozen_condensation,
        })
    }

    /// M_gg (GRAV loads): M_nn itself when the model has no dependent DOFs (n = g).
    pub fn mass_gg(&self) -> &AffineOperator {
        self.m_gg.as_ref().unwrap_or(&self.m_nn)
    }

    /// The values of M_gg at the PMPAR nominal values (on [`Self::mass_gg`]'s pattern), for the
    /// GRAV loads of a load set.
    pub fn mass_gg_values(&self) -> Result<Vec<f64>, crate::assembly::AssemblyError> {
        let m_gg = self.mass_gg();
        let mut values = vec![0.0; m_gg.pattern().nnz()];
        m_gg.evaluate_into(&self.weights(m_gg), &mut values)?;
        Ok(values)
    }

    /// Weights of an operator's affine parts at the PMPAR nominal values (all weights are 1
    /// for the constant part).
    pub fn weights(&self, op: &AffineOperator) -> Vec<f64> {
        self.params.weights(op, &self.params.nominal())
    }

    /// u_g (global frames) → n × 6 grid rows in basic, followed by the scalar point values
    /// (which have no frame) in [`DofMap::scalar_ids`](crate::assembly::DofMap::scalar_ids) order.
    pub fn to_basic_rows(&self, u_g: &[f64]) -> Vec<f64> {
        let mut out = u_g.to_vec();
        for grid in 0..self.map.grids() {
            let b = 6 * grid;
            let t = self.frames.to_basic(grid, [u_g[b], u_g[b + 1], u_g[b + 2]]);
            let r = self
                .frames
                .to_basic(grid, [u_g[b + 3], u_g[b + 4], u_g[b + 5]]);
            out[b..b + 3].copy_from_slice(&t);
            out[b + 3..b + 6].copy_from_slice(&r);
        }
        out
    }
}

/// Hands the heap memory freed so far back to the operating system. The element matrices are
/// many small allocations (a 24 × 24 CHEXA matrix is 4.6 kB), which glibc's allocator keeps in
/// its heaps after they are freed: without this the resident memory of a large solid model
/// stays higher by about their total size (~0.6 GB at 200k DOFs) for the rest of the run.
/// A no-op on other allocators.
fn return_freed_memory() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    // SAFETY: malloc_trim only releases free pages of the allocator's own heaps.
    unsafe {
        libc::malloc_trim(0);
    }
}

/// The constrained system of one SPC set at one parameter point: sets, AUTOSPC, K_ff / M_ff
/// on one pattern.
pub struct Constrained {
    pub spc: SpcSet,
    pub sets: Sets,
    pub autospc: AutoSpcReport,
    /// The parameter values (one per PMPAR, card order) the matrices are evaluated at.
    pub p: Vec<f64>,
    pub k_ff: CscMatrix<f64>,
    pub m_ff: CscMatrix<f64>,
    /// B_ff and Σ GE_e K_e,ff at `p`, on K_ff's pattern, when the structure has them.
    pub damping_ff: ElementDamping<CscMatrix<f64>>,
    /// K_fs for enforced displacements.
    pub k_fs: AffineOperator,
}

impl Constrained {
    /// [`Constrained::at`] the PMPAR nominal values.
    pub fn build(model: &Model, st: &Structure, sid: Option<u32>) -> Result<Self, DiscretizeError> {
        Self::at(model, st, sid, &st.params.nominal())
    }

    /// The s-set of `SPC = sid` (plus GRID PS and AUTOSPC when enabled, AUTOSPC judged on
    /// K(p)) and the f-set matrices K_ff(p), M_ff(p); `p` has one value per PMPAR, in card
    /// order ([`Parameters::list`]).
    pub fn at(
        model: &Model,
        st: &Structure,
        sid: Option<u32>,
        p: &[f64],
    ) -> Result<Self, DiscretizeError> {
        Self::held(model, st, sid, p, &[])
    }

    /// [`Constrained::build`] with the DOFs `also` (g index, source card) held as well: the
    /// SUPORT DOFs of SOL 101 without inertia relief.
    pub fn build_holding(
        model: &Model,
        st: &Structure,
        sid: Option<u32>,
        also: &[(usize, String)],
    ) -> Result<Self, DiscretizeError> {
        Self::held(model, st, sid, &st.params.nominal(), also)
    }

    fn held(
        model: &Model,
        st: &Structure,
        sid: Option<u32>,
        p: &[f64],
        also: &[(usize, String)],
    ) -> Result<Self, DiscretizeError> {
        let weights = |op: &AffineOperator| st.params.weights(op, p);
        let mut spc = SpcSet::of_model(model, &st.map, sid)?;
        spc.add_suport(also);
        spc.check_against_rigids(&st.rigid, &st.map)?;
        let autospc = if model.params.autospc {
            let k_nn_values = Self::k_nn_at(st, p)?;
            autospc(&st.k_nn, &k_nn_values, &st.rigid.n, &spc.mask, &st.map)?
        } else {
            // without AUTOSPC the DOFs no matrix of the solution reaches are still removed
            // (null_dofs): K in statics, K and M in the eigenproblems, and the damping matrices
            // where they enter the solution directly
            let mut diagonals = vec![Self::diagonal_at(st, &st.k_nn, p)?];
            if !matches!(model.sol, None | Some(Solution::Statics)) {
                diagonals.push(Self::diagonal_at(st, &st.m_nn, p)?);
            }
            let direct = matches!(
                model.sol,
                Some(
                    Solution::FrfDirect
                        | Solution::Frf
                        | Solution::TransientDirect
                        | Solution::Transient
                )
            );
            let damping = [&st.damping.viscous, &st.damping.structural];
            for op in damping.into_iter().flatten().filter(|_| direct) {
                diagonals.push(Self::diagonal_at(st, op, p)?);
            }
            null_dofs(&diagonals, &st.rigid.n, &spc.mask, &st.map)
        };
        spc.add_autospc(&autospc);
        let sets = Sets::new(&st.map, &st.rigid.m_mask, &spc.mask)?;
        let ff = Partition::new(st.k_nn.pattern().clone(), &sets.f_in_n, &sets.f_in_n)?;
        let k_ff = ff.evaluate(&st.k_nn, &weights(&st.k_nn))?;
        let m_ff = ff.evaluate(&st.m_nn, &weights(&st.m_nn))?;
        let damping_ff = st.damping.try_map(|op| ff.evaluate(op, &weights(op)))?;
        drop(ff);
        let k_fs = crate::assembly::reduce::partition(&st.k_nn, &sets.f_in_n, &sets.s_in_n)?;
        Ok(Constrained {
            spc,
            sets,
            autospc,
            p: p.to_vec(),
            k_ff,
            m_ff,
            damping_ff,
            k_fs,
        })
    }

    /// K_nn at this system's parameter values (on `st.k_nn`'s pattern), for SPC forces;
    /// computed on request rather than kept, as it is the size of K_gg.
    pub fn k_nn_values(&self, st: &Structure) -> Result<Vec<f64>, DiscretizeError> {
        Self::k_nn_at(st, &self.p)
    }

    /// The diagonal of the n-set operator `op` at `p`.
    fn diagonal_at(
        st: &Structure,
        op: &AffineOperator,
        p: &[f64],
    ) -> Result<Vec<f64>, DiscretizeError> {
        let mut values = vec![0.0; op.pattern().nnz()];
        op.evaluate_into(&st.params.weights(op, p), &mut values)?;
        Ok(op.diagonal(&values))
    }

    fn k_nn_at(st: &Structure, p: &[f64]) -> Result<Vec<f64>, DiscretizeError> {
        let mut values = vec![0.0; st.k_nn.pattern().nnz()];
        st.k_nn
            .evaluate_into(&st.params.weights(&st.k_nn, p), &mut values)?;
        Ok(values)
    }

    /// Weights of an operator's affine parts at this system's parameter values.
    pub fn weights(&self, st: &Structure, op: &AffineOperator) -> Vec<f64> {
        st.params.weights(op, &self.p)
    }

    /// K_ff and M_ff with every affine part (for a pROM build), on one pattern.
    pub fn affine_ff(
        &self,
        st: &Structure,
    ) -> Result<(AffineOperator, AffineOperator), DiscretizeError> {
        let ff = Partition::new(
            st.k_nn.pattern().clone(),
            &self.sets.f_in_n,
            &self.sets.f_in_n,
        )?;
        Ok((ff.apply(&st.k_nn)?, ff.apply(&st.m_nn)?))
    }

    /// u_f of K_ff u_f = p_f with `factor` (a factorization of K_ff) and one step of iterative
    /// refinement, u ← u + K_ff⁻¹ (p_f − K_ff u): K_ff of shells mixes membrane and bending
    /// stiffness (condition numbers ~1e8–1e10), the plain solve leaves ε·κ residuals.
    pub fn solve_static(&self, factor: &Factor, p_f: &[f64]) -> Result<Vec<f64>, LinalgError> {
        let mut u_f = p_f.to_vec();
        factor.solve_in_place(&mut u_f)?;
        let mut r = vec![0.0; u_f.len()];
        sym_matvec(&self.k_ff, &u_f, &mut r)?;
        r.iter_mut().zip(p_f).for_each(|(a, b)| *a = b - *a);
        factor.solve_in_place(&mut r)?;
        u_f.iter_mut().zip(&r).for_each(|(u, d)| *u += d);
        Ok(u_f)
    }

    /// Whether K_ff has (relatively) no stiffness on the diagonal at f index `i`.
    fn no_stiffness(&self, i: usize) -> bool {
        let diag = |j: usize| {
            self.k_ff
                .get_entry(j, j)
                .map_or(0.0, |v| v.into_value().abs())
        };
        let max = (0..self.k_ff.nrows()).map(diag).fold(0.0_f64, f64::max);
        diag(i) <= crate::assembly::spc::AUTOSPC_RATIO * max
    }

    /// The (GRID, component) of a factorization failure of K_ff (or K − σM) when it is a
    /// mechanism: LLᵀ of K_ff failing is one; a zero pivot of K − σM (eigen) is one only when
    /// K_ff itself has no stiffness there (otherwise σ hit an eigenvalue). `None` otherwise.
    pub fn mechanism_dof(&self, st: &Structure, e: &LinalgError) -> Option<DofName> {
        let index = match *e {
            LinalgError::NotPositiveDefinite { index, .. } => Some(index),
            LinalgError::Singular { index } if self.no_stiffness(index) => Some(index),
            _ => None,
        }?;
        self.sets
            .f
            .members()
            .get(index)
            .and_then(|&g| st.map.dof_name(g))
    }
}

/// The element damping matrices of a structure (operators) or of a constrained system (f-set
/// matrices): each `None` when no element has it.
#[derive(Debug, Clone, Default)]
pub struct ElementDamping<T> {
    /// The viscous damping matrix B (CDAMP, CVISC, PBUSH B).
    pub viscous: Option<T>,
    /// The structural damping matrix Σ GE_e K_e (the imaginary stiffness).
    pub structural: Option<T>,
}

impl<T> ElementDamping<T> {
    /// Both matrices through `f`.
    pub fn try_map<U, E>(&self, f: impl Fn(&T) -> Result<U, E>) -> Result<ElementDamping<U>, E> {
        Ok(ElementDamping {
            viscous: self.viscous.as_ref().map(&f).transpose()?,
            structural: self.structural.as_ref().map(&f).transpose()?,
        })
    }

    /// True when neither matrix is present.
    pub fn is_empty(&self) -> bool {
        self.viscous.is_none() && self.structural.is_none()
    }
}

/// The part keys of K and M, K's first: the pROM's component order.
pub fn affine_keys(k: &AffineOperator, m: &AffineOperator) -> Vec<ParamKey> {
    let mut keys: Vec<ParamKey> = k.keys();
    for key in m.keys() {
        if !keys.contains(&key) {
            keys.push(key);
        }
    }
    keys
}

/// The affine FOM of f-set operators `k`, `m` (from [`Constrained::affine_ff`]) for a pROM
/// build ([`crate::rom::build::build_prom`]): one function per key of `keys` (a zero matrix where an operator lacks
/// that key).
pub fn affine_fom(
    st: &Structure,
    keys: &[ParamKey],
    k: &AffineOperator,
    m: &AffineOperator,
) -> Result<AffineFom, DiscretizeError> {
    let matrices = |op: &AffineOperator| -> Result<Vec<CscMatrix<f64>>, DiscretizeError> {
        keys.iter()
            .map(|&key| {
                Ok(op.matrix(
                    op.part(key)
                        .map_or_else(|| vec![0.0; op.pattern().nnz()], <[f64]>::to_vec),
                )?)
            })
            .collect()
    };
    Ok(AffineFom {
        parameters: st.params.list.clone(),
        functions: keys.iter().map(|&key| st.params.function(key)).collect(),
        stiffness: matrices(k)?,
        mass: matrices(m)?,
    })
}
