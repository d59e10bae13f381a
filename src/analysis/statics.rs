//! Linear statics of a discretized structure: K_ff u_f = P_f by sparse Cholesky, as the
//! library call behind SOL 101.
//!
//! 1. K_ff = LLᵀ: one symbolic analysis and one numeric factor per distinct f-set, shared by
//!    every load case with that f-set (K does not depend on the load) — [`StaticFactors`];
//! 2. P_g of a load selection (FORCE, MOMENT, GRAV with M_gg; plus a thermal load), u_s the SPC values with the
//!    selection's SPCD values in their place ([`SpcSet::with_spcd`]), P_f = (Tᵀ P_g)_f − K_fs u_s;
//! 3. u_f by the factor plus one step of iterative refinement
//!    ([`Constrained::solve_static`]: shell models mix membrane and bending stiffness,
//!    condition numbers 1e8–1e10);
//! 4. u_g = T [u_f; u_s]; SPC forces q_s = (K_nn u_n − P_n)_s — [`StaticSolution`];
//! 5. centroid strains of the elements a caller keeps — [`element_strains`].

use std::collections::BTreeMap;

use faer::Par;

use super::AnalysisError;
use crate::assembly::AssemblyError;
use crate::assembly::loads::{Mass, load_vector, reduce_load};
use crate::assembly::recover::{expand_f_to_n, spc_forces};
#[cfg(doc)]
use crate::assembly::spc::SpcSet;
use crate::discretize::elements::{ShellRecovery, element_displacements, shell_strains};
use crate::discretize::{Constrained, DiscretizeError, Structure};
use crate::fe::shell::ShellStrains;
use crate::linalg::{Factor, LinalgError, SymbolicFactor};
use crate::model::{Element, Model};

/// The Cholesky factors of K_ff, one per distinct f-set.
pub struct StaticFactors {
    max_ratio: f64,
    par: Par,
    factors: Vec<(Vec<usize>, Factor)>,
}

impl StaticFactors {
    /// No factor yet; `max_ratio` is the pivot-ratio bound of PARAM,MAXRATIO.
    pub fn new(max_ratio: f64, par: Par) -> Self {
        StaticFactors {
            max_ratio,
            par,
            factors: Vec::new(),
        }
    }

    /// The factor of `c`'s f-set, if it has been computed.
    pub fn get(&self, c: &Constrained) -> Option<&Factor> {
        let f = c.sets.f.members();
        self.factors
            .iter()
            .find(|(key, _)| key.as_slice() == f)
            .map(|(_, factor)| factor)
    }

    /// The symbolic analysis (ordering, elimination tree) of `c`'s K_ff pattern.
    pub fn analyze(c: &Constrained) -> Result<SymbolicFactor, LinalgError> {
        SymbolicFactor::analyze(c.k_ff.pattern())
    }

    /// Factors `c`'s K_ff with its symbolic analysis and keeps the factor for its f-set. A
    /// failing pivot is a mechanism ([`Constrained::mechanism_dof`] names it).
    pub fn factor(&mut self, c: &Constrained, symbolic: SymbolicFactor) -> Result<(), LinalgError> {
        let factor = symbolic
            .with_max_ratio(self.max_ratio)
            .factor_llt(&c.k_ff, self.par)?;
        self.factors.push((c.sets.f.members().to_vec(), factor));
        Ok(())
    }
}

/// The static response to one load selection, g-set (the structure's DOF map, output frames).
#[derive(Debug, Clone)]
pub struct StaticSolution {
    /// Displacements u_g.
    pub u_g: Vec<f64>,
    /// SPC forces q_g (zero off the s-set).
    pub q_g: Vec<f64>,
    /// Applied loads P_g.
    pub p_g: Vec<f64>,
}

impl StaticSolution {
    /// Σ cᵢ solutionᵢ (a `SUBCOM`): the last coefficient applies to the last solution, the one
    /// before it to the one before, and so on (Nastran's SUBSEQ: Rn to the most recent
    /// subcase), so a short list combines the most recent subcases. Statics is linear, so
    /// displacements, loads and SPC forces combine with the same coefficients.
    pub fn combine(solutions: &[StaticSolution], coefficients: &[f64]) -> StaticSolution {
        let n = solutions.first().map_or(0, |s| s.u_g.len());
        let mut sum = StaticSolution {
            u_g: vec![0.0; n],
            q_g: vec![0.0; n],
            p_g: vec![0.0; n],
        };
        let recent = &solutions[solutions.len().saturating_sub(coefficients.len())..];
        let first = coefficients.len().saturating_sub(recent.len());
        for (s, &c) in recent.iter().zip(&coefficients[first..]) {
            for (total, part) in [
                (&mut sum.u_g, &s.u_g),
                (&mut sum.q_g, &s.q_g),
                (&mut sum.p_g, &s.p_g),
            ] {
                total.iter_mut().zip(part).for_each(|(t, x)| *t += c * x);
            }
        }
        sum
    }

    /// Solves K_ff u_f = P_f for the load set `load` (`None`: no load, enforced displacements
    /// only) plus the thermal load `thermal` (P_g, [`crate::discretize::thermal::thermal_load`])
    /// with `factor` of `c`'s K_ff; `mass_values` are M_gg's ([`Structure::mass_gg_values`]).
    pub fn solve(
        model: &Model,
        st: &Structure,
        c: &Constrained,
        (load, thermal): (Option<u32>, Option<&[f64]>),
        factor: &Factor,
        mass_values: &[f64],
    ) -> Result<StaticSolution, AnalysisError> {
        let mut p_g = match load {
            Some(sid) => load_vector(
                model,
                &st.frames,
                &st.map,
                sid,
                Some(Mass {
                    operator: st.mass_gg(),
                    values: mass_values,
                }),
            )?,
            None => vec![0.0; st.map.size()],
        };
        if let Some(thermal) = thermal {
            p_g.iter_mut().zip(thermal).for_each(|(p, t)| *p += t);
        }
        let enforced = match load {
            Some(sid) => {
                let spcd = model
                    .enforced_displacements(sid)
                    .map_err(|_| AssemblyError::NoLoadSet { sid })?;
                c.spc.with_spcd(model, &st.map, &spcd)?
            }
            None => c.spc.enforced.clone(),
        };
        let k_fs_values = c.k_fs.evaluate(&st.weights(&c.k_fs))?.values().to_vec();
        let p_f = reduce_load(&p_g, &st.rigid, &c.sets, &c.k_fs, &k_fs_values, &enforced)?;
        let u_f = c.solve_static(factor, &p_f)?;
        let u_n = expand_f_to_n(&u_f, &c.sets, &enforced)?;
        let u_g = st.rigid.expand(&u_n)?;
        let p_n = st.rigid.reduce_vector(&p_g)?;
        let q_s = spc_forces(&st.k_nn, &c.k_nn_values(st)?, &u_n, &p_n, &c.sets)?;
        let mut q_g = vec![0.0; st.map.size()];
        c.sets.s.scatter_into(&q_s, &mut q_g)?;
        Ok(StaticSolution { u_g, q_g, p_g })
    }
}

/// Σ forces and Σ (moments + x × F) about the basic origin of n×6 basic rows.
pub fn resultant(model: &Model, rows: &[f64]) -> [f64; 6] {
    let mut out = [0.0; 6];
    for (g, grid) in model.grids.iter().enumerate() {
        let r = &rows[6 * g..6 * g + 6];
        let f = [r[0], r[1], r[2]];
        let m = crate::geometry::vec3::cross(grid.xyz, f);
        for k in 0..3 {
            out[k] += f[k];
            out[3 + k] += r[3 + k] + m[k];
        }
    }
    out
}

/// Centroid strains of one element block, in element order.
#[derive(Debug, Default, Clone)]
pub struct StrainBlock {
    pub ids: Vec<u32>,
    /// Shells: [εx, εy, γxy] at the top fibre (m×3); solids: [εxx, εyy, εzz, γxy, γyz, γzx]
    /// in basic (m×6).
    pub first: Vec<f64>,
    /// Shells: the bottom fibre (m×3); solids: empty.
    pub second: Vec<f64>,
}

/// The centroid strains of a displacement field, by element block name.
#[derive(Debug, Default, Clone)]
pub struct ElementStrains {
    /// CQUAD4, CTRIA3: top and bottom fibres (Z2, Z1 of the PSHELL; the laminate's surfaces
    /// for PCOMP) in the element material system.
    pub shells: BTreeMap<&'static str, StrainBlock>,
    /// CHEXA, CPENTA, CTETRA, CTETRA10: engineering strains in basic at the centroid.
    pub solids: BTreeMap<&'static str, StrainBlock>,
}

/// The shells `keep` selects, each with its recovery data and its centroid strains for the
/// basic-system displacement rows `u`.
pub(crate) fn selected_shell_strains<'m, 'i, F: Fn(u32) -> bool>(
    model: &'m Model,
    st: &'i Structure,
    u: &'i [f64],
    keep: &'i F,
) -> impl Iterator<Item = Result<(&'m Element, &'i ShellRecovery, ShellStrains), DiscretizeError>> + 'i
where
    'm: 'i,
{
    st.shells
        .iter()
        .map(|(idx, rec)| (&model.elements[*idx], rec))
        .filter(|(e, _)| keep(e.id))
        .map(|(e, rec)| {
            shell_strains(model, e, rec, &element_displacements(u, &e.nodes))
                .map(|strains| (e, rec, strains))
        })
}

/// The centroid strains of the elements `keep` selects, for the basic-system displacement
/// rows `u` (n×6).
pub fn element_strains(
    model: &Model,
    st: &Structure,
    u: &[f64],
    keep: impl Fn(u32) -> bool,
) -> Result<ElementStrains, DiscretizeError> {
    let mut out = ElementStrains::default();
    for shell in selected_shell_strains(model, st, u, &keep) {
        let (e, _, strains) = shell?;
        let block = out.shells.entry(e.kind.block_name()).or_default();
        block.ids.push(e.id);
        block.first.extend(strains.top);
        block.second.extend(strains.bottom);
    }
    for e in &model.elements {
        let Some(midsides) = model.solid_midsides(e) else {
            continue;
        };
        if !keep(e.id) {
            continue;
        }
        let xyz = model.positions(e);
        let ut: Vec<f64> = e
            .nodes
            .iter()
            .flat_map(|&a| u[6 * a..6 * a + 3].iter().copied())
            .collect();
        let eps = midsides
            .strain_at_centroid(&xyz, &ut)
            .map_err(|x| DiscretizeError::Element {
                card: e.kind.card(),
                id: e.id,
                reason: x.to_string(),
            })?;
        let block = out.solids.entry(e.kind.block_name()).or_default();
        block.ids.push(e.id);
        block.first.extend(eps);
    }
    Ok(out)
}
