//! RBE2, RBE3, RSSCON and MPC equations by elimination of the dependent DOFs: u_m = G_mn u_n,
//! u_g = T u_n.
//!
//! # RBE2 (rigid body)
//! The CM components of each dependent grid d follow the independent grid i rigidly. In basic,
//! with r = x_d − x_i,
//!
//! ```text
//! u_d = u_i + θ_i × r = u_i − [r×] θ_i,    θ_d = θ_i,      R(r) = [ I  −[r×] ]
//!                                                                  [ 0    I   ]
//! ```
//!
//! and in the global frames (L = diag(Λ, Λ), see [`frames`](super::frames))
//! u_d = L_dᵀ R(r) L_i u_i; the rows CM of that 6 × 6 matrix are the relations.
//!
//! # RBE3 (weighted average, MSC / MYSTRAN formulation)
//! The reference motion q = (t, θ) (basic, at the reference point x_ref) is the weighted
//! least-squares rigid fit of the independent motions. For an independent grid i with
//! r_i = x_i − x_ref, the rigid motion at i is S_i q, S_i = R(r_i); only the components C of
//! its group (in the grid's global frame, rows c of L_iᵀ S_i, written s_c) are observed:
//!
//! ```text
//! min_q Σ_i Σ_{c∈C_i} w_c (u_{i,c} − s_c q)²   ⇒   q = A⁻¹ Σ_i Σ_c w_c s_cᵀ u_{i,c},
//! A = Σ_i Σ_c w_c s_cᵀ s_c   (6 × 6)
//! ```
//!
//! w_c is the group weight WT for translations; for rotational components (C ∋ 4–6) it is
//! WT · L_c², with L_c the mean distance of the independent grids from the reference point
//! (1 if they all coincide with it), which makes the two kinds of residual commensurate (as
//! MSC Nastran does). The reference DOFs in REFC are then u_ref = L_refᵀ q restricted to REFC.
//! For equal weights and translations only, with the reference at the centroid, t is the plain
//! average of the independent translations and a rigid rotation of the independent grids is
//! recovered exactly. A singular A (fewer than three non-collinear translational grids and
//! no rotations, …) is [`AssemblyError::Rbe3Singular`].
//!
//! # MPC
//! An equation Σⱼ Aⱼ u_j = 0 (components in the grids' displacement frames, which are the
//! g-set's frames, or scalar points) makes its first DOF dependent: u₁ = −Σ_{j>1} (Aⱼ / A₁) u_j. The set is the
//! one case control selects ([`Model::selected_mpc`]), the same for every subcase.
//!
//! # RSSCON
//! Each link of a shell-to-solid connector gives up to five relations of its shell grid
//! ([`rsscon`](super::rsscon)); a link repeated by two RSSCONs is imposed once.
//!
//! # Chains and checks
//! A relation may refer to a DOF that is itself dependent (an RBE2 whose GN is a dependent grid
//! of another RBE2): relations are substituted depth-first (iteratively, no recursion), so any
//! acyclic order of definition works; a cycle is [`AssemblyError::RigidCycle`]. A DOF dependent
//! in two rigid elements is [`AssemblyError::DependentTwice`].

use std::collections::HashMap;

use nalgebra_sparse::CsrMatrix;

use super::dofs::{DofMap, DofSet};
use super::error::AssemblyError;
use super::frames::GridFrames;
use crate::card_values::Dofs;
use crate::deck::cards::MpcTerm;
use crate::model::{Model, RigidKind, WeightedGroup};

/// Relative pivot tolerance of the 6 × 6 RBE3 fit.
pub const RBE3_PIVOT_TOL: f64 = 1e-10;

/// One dependent DOF: u_dependent = Σ coef · u_term (g indices; terms may be dependent).
#[derive(Debug, Clone, PartialEq)]
pub struct Relation {
    pub dependent: usize,
    pub terms: Vec<(usize, f64)>,
    /// The rigid element, e.g. "RBE2 7" (for messages).
    pub owner: String,
}

/// The eliminated rigid constraints: m-set, owners and the transformation T (g × n).
#[derive(Debug, Clone)]
pub struct RigidElimination {
    /// u_g = T u_n (g rows, n columns).
    pub t: CsrMatrix<f64>,
    /// The m-set mask over g.
    pub m_mask: Vec<bool>,
    /// The n-set (g − m).
    pub n: DofSet,
    owners: HashMap<usize, String>,
}

impl RigidElimination {
    /// The RBE2 / RBE3 relations and the selected MPC equations of a model, eliminated.
    pub fn of_model(
        model: &Model,
        frames: &GridFrames,
        map: &DofMap,
    ) -> Result<Self, AssemblyError> {
        let mut relations = Vec::new();
        // a shell grid shared by two shell elements meeting one solid edge is linked by the
        // RSSCON of each: the same equations, imposed once
        let mut linked = std::collections::HashSet::new();
        for r in &model.rigids {
            let owner = format!("{} {} at {}", r.kind.card(), r.id, r.loc);
            match &r.kind {
                RigidKind::Rbe2 { cm } => {
                    relations.extend(rbe2_relations(model, frames, &owner, r.hub, &r.legs, *cm));
                }
                RigidKind::Rbe3 { refc, groups } => {
                    let xyz: Vec<[f64; 3]> = model.grids.iter().map(|g| g.xyz).collect();
                    relations.extend(rbe3_relations(&xyz, frames, &owner, r.hub, *refc, groups)?);
                }
                RigidKind::Rsscon { links } => {
                    let xyz: Vec<[f64; 3]> = model.grids.iter().map(|g| g.xyz).collect();
                    for &link in links.iter().filter(|&&l| linked.insert(l)) {
                        relations.extend(super::rsscon::link_relations(&xyz, frames, &owner, link));
                    }
                }
            }
        }
        if let Some(sid) = model.selected_mpc() {
            relations.extend(mpc_relations(model, map, sid)?);
        }
        RigidElimination::from_relations(map, relations)
    }

    /// Eliminate explicit relations (resolving chains) and build T.
    pub fn from_relations(map: &DofMap, relations: Vec<Relation>) -> Result<Self, AssemblyError> {
        let g = map.size();
        let mut slot: HashMap<usize, usize> = HashMap::with_capacity(relations.len());
        for (k, r) in relations.iter().enumerate() {
            if r.dependent >= g {
                return Err(AssemblyError::DofOutOfRange {
                    index: r.dependent,
                    size: g,
                });
            }
            if let Some(&(t, _)) = r.terms.iter().find(|(t, _)| *t >= g) {
                return Err(AssemblyError::DofOutOfRange { index: t, size: g });
            }
            if let Some(&first) = slot.get(&r.dependent) {
                return Err(AssemblyError::DependentTwice {
                    dof: map.name(r.dependent),
                    first: relations[first].owner.clone(),
                    second: r.owner.clone(),
                });
            }
            slot.insert(r.dependent, k);
        }
        let resolved = resolve_chains(&relations, &slot)?;
        let mut m_mask = vec![false; g];
        for r in &relations {
            m_mask[r.dependent] = true;
        }
        let n = DofSet::from_mask(&m_mask.iter().map(|m| !m).collect::<Vec<_>>());
        let mut offsets = Vec::with_capacity(g + 1);
        let mut cols = Vec::new();
        let mut vals = Vec::new();
        offsets.push(0);
        for i in 0..g {
            match slot.get(&i) {
                None => {
                    cols.push(n.position(i).unwrap_or(0));
                    vals.push(1.0);
                }
                Some(&k) => {
                    for &(t, c) in &resolved[k] {
                        if let Some(p) = n.position(t) {
                            cols.push(p);
                            vals.push(c);
                        }
                    }
                }
            }
            offsets.push(cols.len());
        }
        let t = CsrMatrix::try_from_csr_data(g, n.len(), offsets, cols, vals).map_err(|_| {
            AssemblyError::PatternMismatch {
                what: "internal: T is not a valid CSR matrix",
            }
        })?;
        let owners = relations
            .into_iter()
            .map(|r| (r.dependent, r.owner))
            .collect();
        Ok(RigidElimination {
            t,
            m_mask,
            n,
            owners,
        })
    }

    /// No rigid elements: T = I.
    pub fn identity(map: &DofMap) -> Self {
        // from_relations with no relations cannot fail
        RigidElimination::from_relations(map, Vec::new()).unwrap_or_else(|_| RigidElimination {
            t: CsrMatrix::identity(map.size()),
            m_mask: vec![false; map.size()],
            n: DofSet::all(map.size()),
            owners: HashMap::new(),
        })
    }

    /// The rigid element that makes a g DOF dependent.
    pub fn owner(&self, dof: usize) -> Option<&str> {
        self.owners.get(&dof).map(String::as_str)
    }

    /// u_g = T u_n.
    pub fn expand(&self, u_n: &[f64]) -> Result<Vec<f64>, AssemblyError> {
        super::dofs::check_len("n-set vector", self.t.ncols(), u_n.len())?;
        Ok(self
            .t
            .row_iter()
            .map(|row| {
                row.col_indices()
                    .iter()
                    .zip(row.values())
                    .map(|(&j, &c)| c * u_n[j])
                    .sum()
            })
            .collect())
    }

    /// P_n = Tᵀ P_g.
    pub fn reduce_vector(&self, p_g: &[f64]) -> Result<Vec<f64>, AssemblyError> {
        super::dofs::check_len("g-set vector", self.t.nrows(), p_g.len())?;
        let mut p_n = vec![0.0; self.t.ncols()];
        for (i, row) in self.t.row_iter().enumerate() {
            for (&j, &c) in row.col_indices().iter().zip(row.values()) {
                p_n[j] += c * p_g[i];
            }
        }
        Ok(p_n)
    }
}

/// One relation per MPC card of `MPC = sid`.
fn mpc_relations(model: &Model, map: &DofMap, sid: u32) -> Result<Vec<Relation>, AssemblyError> {
    let cards = model
        .mpc_set(sid)
        .map_err(|e| AssemblyError::unresolved_set(e, "MPC", "MPC", "MPCADD", sid))?;
    cards
        .into_iter()
        .map(|card| {
            let owner = format!("MPC {} at {}", card.sid, card.loc);
            let dof = |t: &MpcTerm| {
                let found = match t.component {
                    0 => model.scalar_index.get(&t.grid).map(|&k| map.scalar_dof(k)),
                    c => model
                        .grid_index
                        .get(&t.grid)
                        .map(|&g| DofMap::dof(g, usize::from(c) - 1)),
                };
                found.ok_or_else(|| AssemblyError::MissingGrid {
                    card: owner.clone(),
                    grid: t.grid,
                })
            };
            let (first, rest) = card.terms.split_first().ok_or(AssemblyError::BadUnion {
                card: "MPC",
                sid,
                reason: "an equation without terms".to_string(),
            })?;
            let terms = rest
                .iter()
                .map(|t| Ok((dof(t)?, -t.coefficient / first.coefficient)))
                .collect::<Result<_, AssemblyError>>()?;
            Ok(Relation {
                dependent: dof(first)?,
                terms,
                owner: owner.clone(),
            })
        })
        .collect()
}

/// Substitute dependent terms depth-first; returns each relation's terms over independent DOFs.
fn resolve_chains(
    relations: &[Relation],
    slot: &HashMap<usize, usize>,
) -> Result<Vec<Vec<(usize, f64)>>, AssemblyError> {
    const NEW: u8 = 0;
    const OPEN: u8 = 1;
    const DONE: u8 = 2;
    let mut state = vec![NEW; relations.len()];
    let mut resolved: Vec<Vec<(usize, f64)>> = vec![Vec::new(); relations.len()];
    for root in 0..relations.len() {
        if state[root] != NEW {
            continue;
        }
        let mut stack: Vec<(usize, bool)> = vec![(root, false)];
        while let Some((k, exit)) = stack.pop() {
            if exit {
                let mut acc: HashMap<usize, f64> = HashMap::new();
                for &(t, c) in &relations[k].terms {
                    match slot.get(&t) {
                        None => *acc.entry(t).or_insert(0.0) += c,
                        Some(&j) => {
                            for &(u, d) in &resolved[j] {
                                *acc.entry(u).or_insert(0.0) += c * d;
                            }
                        }
                    }
                }
                let mut terms: Vec<(usize, f64)> =
                    acc.into_iter().filter(|(_, c)| *c != 0.0).collect();
                terms.sort_by_key(|(t, _)| *t);
                resolved[k] = terms;
                state[k] = DONE;
                continue;
            }
            if state[k] == DONE {
                continue;
            }
            state[k] = OPEN;
            stack.push((k, true));
            for &(t, _) in &relations[k].terms {
                if let Some(&j) = slot.get(&t) {
                    match state[j] {
                        OPEN => {
                            let mut rigids: Vec<String> = Vec::new();
                            for (i, s) in state.iter().enumerate() {
                                if *s == OPEN && !rigids.contains(&relations[i].owner) {
                                    rigids.push(relations[i].owner.clone());
                                }
                            }
                            return Err(AssemblyError::RigidCycle { rigids });
                        }
                        NEW => stack.push((j, false)),
                        _ => {}
                    }
                }
            }
        }
    }
    Ok(resolved)
}

/// 6 × 6 matrix, row-major.
type M6 = [[f64; 6]; 6];

/// R(r) = [I −[r×]; 0 I]: rigid motion at offset r from the motion (t, θ) at the origin.
pub(crate) fn rigid_arm(r: [f64; 3]) -> M6 {
    let mut m = [[0.0; 6]; 6];
    for (i, row) in m.iter_mut().enumerate() {
        row[i] = 1.0;
    }
    // −[r×] = [[0, rz, −ry], [−rz, 0, rx], [ry, −rx, 0]]
    m[0][4] = r[2];
    m[0][5] = -r[1];
    m[1][3] = -r[2];
    m[1][5] = r[0];
    m[2][3] = r[1];
    m[2][4] = -r[0];
    m
}

/// L = diag(Λ, Λ) of a grid (identity in basic).
pub(crate) fn frame6(frames: &GridFrames, grid: usize) -> M6 {
    let mut l = [[0.0; 6]; 6];
    match frames.rotation(grid) {
        None => (0..6).for_each(|i| l[i][i] = 1.0),
        Some(r) => {
            for i in 0..3 {
                for j in 0..3 {
                    l[i][j] = r[i][j];
                    l[i + 3][j + 3] = r[i][j];
                }
            }
        }
    }
    l
}

fn mul(a: &M6, b: &M6) -> M6 {
    std::array::from_fn(|i| std::array::from_fn(|j| (0..6).map(|k| a[i][k] * b[k][j]).sum()))
}

fn transpose(a: &M6) -> M6 {
    std::array::from_fn(|i| std::array::from_fn(|j| a[j][i]))
}

/// Relations of one RBE2: CM components of each dependent grid; `owner` names the card in
/// errors (e.g. "RBE2 7 at deck.dat:12").
pub fn rbe2_relations(
    model: &Model,
    frames: &GridFrames,
    owner: &str,
    independent: usize,
    dependents: &[usize],
    cm: Dofs,
) -> Vec<Relation> {
    let xyz = |g: usize| model.grids.get(g).map_or([0.0; 3], |p| p.xyz);
    let li = frame6(frames, independent);
    let mut out = Vec::new();
    for &d in dependents {
        let r = crate::geometry::vec3::sub(xyz(d), xyz(independent));
        let g = mul(&transpose(&frame6(frames, d)), &mul(&rigid_arm(r), &li));
        for c in cm.components() {
            let terms = (0..6)
                .filter(|&k| g[c - 1][k] != 0.0)
                .map(|k| (DofMap::dof(independent, k), g[c - 1][k]))
                .collect();
            out.push(Relation {
                dependent: DofMap::dof(d, c - 1),
                terms,
                owner: owner.to_string(),
            });
        }
    }
    out
}

/// Relations of one RBE3 (see the module doc) with its weight groups; `owner` names the card in errors (e.g. "RBE3 9 at deck.dat:14").
pub fn rbe3_relations(
    xyz: &[[f64; 3]],
    frames: &GridFrames,
    owner: &str,
    reference: usize,
    refc: Dofs,
    groups: &[WeightedGroup],
) -> Result<Vec<Relation>, AssemblyError> {
    use crate::geometry::vec3::{norm, sub};
    let at = |g: usize| xyz.get(g).copied().unwrap_or([0.0; 3]);
    let x_ref = at(reference);
    let legs: Vec<usize> = groups
        .iter()
        .flat_map(|g| g.grids.iter().copied())
        .collect();
    let lc = legs.iter().map(|&g| norm(sub(at(g), x_ref))).sum::<f64>() / legs.len().max(1) as f64;
    let lc = if lc > 0.0 { lc } else { 1.0 };
    // observed rows: (grid, component 0..6, weight, s_c)
    let mut rows: Vec<(usize, usize, f64, [f64; 6])> = Vec::new();
    for group in groups {
        let (w, comps) = (&group.weight, group.components);
        for &g in &group.grids {
            let s = mul(
                &transpose(&frame6(frames, g)),
                &rigid_arm(sub(at(g), x_ref)),
            );
            for c in comps.components() {
                let wc = if c <= 3 { *w } else { *w * lc * lc };
                rows.push((g, c - 1, wc, s[c - 1]));
            }
        }
    }
    let mut a = [[0.0; 6]; 6];
    for (_, _, w, s) in &rows {
        for i in 0..6 {
            for j in 0..6 {
                a[i][j] += w * s[i] * s[j];
            }
        }
    }
    let a_inv = invert6(&a).ok_or_else(|| AssemblyError::Rbe3Singular {
        owner: owner.to_string(),
    })?;
    let l_ref_t = transpose(&frame6(frames, reference));
    // u_ref = L_refᵀ A⁻¹ Σ w s_cᵀ u_{i,c}: H = L_refᵀ A⁻¹ (6 × 6), coefficient = w · (H s_cᵀ)[r]
    let h = mul(&l_ref_t, &a_inv);
    let mut out = Vec::new();
    for r in refc.components() {
        let mut terms = Vec::with_capacity(rows.len());
        for (g, c, w, s) in &rows {
            let coef: f64 = w * (0..6).map(|k| h[r - 1][k] * s[k]).sum::<f64>();
            if coef != 0.0 {
                terms.push((DofMap::dof(*g, *c), coef));
            }
        }
        out.push(Relation {
            dependent: DofMap::dof(reference, r - 1),
            terms,
            owner: owner.to_string(),
        });
    }
    Ok(out)
}

/// Inverse of a symmetric positive semi-definite 6 × 6 matrix by Gauss–Jordan with partial
/// pivoting; `None` when a pivot is below [`RBE3_PIVOT_TOL`] × the largest diagonal entry.
fn invert6(a: &M6) -> Option<M6> {
    let scale = (0..6).map(|i| a[i][i].abs()).fold(0.0, f64::max);
    if scale == 0.0 || !scale.is_finite() {
        return None;
    }
    let mut m = *a;
    let mut inv: M6 =
        std::array::from_fn(|i| std::array::from_fn(|j| if i == j { 1.0 } else { 0.0 }));
    for col in 0..6 {
        let p = (col..6).max_by(|&i, &j| m[i][col].abs().total_cmp(&m[j][col].abs()))?;
        if m[p][col].abs() <= RBE3_PIVOT_TOL * scale {
            return None;
        }
        m.swap(col, p);
        inv.swap(col, p);
        let d = m[col][col];
        for j in 0..6 {
            m[col][j] /= d;
            inv[col][j] /= d;
        }
        for i in 0..6 {
            if i != col {
                let f = m[i][col];
                if f != 0.0 {
                    for j in 0..6 {
                        m[i][j] -= f * m[col][j];
                        inv[i][j] -= f * inv[col][j];
                    }
                }
            }
        }
    }
    Some(inv)
}
