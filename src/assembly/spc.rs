//! The s-set: SPC / SPC1 / SPCADD (case control `SPC = sid`), GRID PS and AUTOSPC.
//!
//! Components are in the global (CD) frame of the grid, as in Nastran. An `SPC` may enforce a
//! non-zero value D; the values are kept in the g-set vector [`SpcSet::enforced`] and enter the
//! reduced load as −K_fs u_s ([`loads::reduce_load`](super::loads::reduce_load)).
//!
//! An SPCD set of the load selection ([`SpcSet::with_spcd`]) replaces the enforced values of its
//! DOFs, which must be in the s-set by SPC, SPC1 or GRID PS (Nastran's rule; a DOF AUTOSPC alone
//! constrained is refused too: it has no stiffness to be moved against).
//!
//! `SPCADD sid S1 S2 …` is the union of the SPC/SPC1 sets Si; an SPCADD of an SPCADD is an
//! error, as in Nastran. One DOF given two different values in one set is an error.
//!
//! AUTOSPC ([`autospc`]): after the g → n reduction, every n-set DOF not already in s whose
//! stiffness diagonal is ≤ [`AUTOSPC_RATIO`] × the largest diagonal of the same grid's
//! translations (T1–T3) or rotations (R1–R3) — Nastran's grid-point singularity test, on the
//! diagonal; a triple with no stiffness at all (largest diagonal 0) is constrained whole — is
//! constrained to zero and listed (GRID, component) in an [`AutoSpcReport`] for the solver to
//! print. The test is per grid only, so that stiffness elsewhere (a stiff RBE hub, 1e20
//! grounded springs standing for a clamp) does not make a shell's bending or drilling stiffness
//! look like none: a model-wide floor (1e-14 × the largest diagonal of K_nn, dropped) constrained
//! every plate rotation of a plate held by 1e20 springs and made it 2.5e4 times too stiff. Typical
//! finds: rotations of grids attached only to solids, drilling rotations of flat shells without
//! drilling stiffness, components of spring-only grids. `PARAM,AUTOSPC,NO` disables it (the
//! caller checks `model.params.autospc`). A mechanism with non-zero diagonals is not detected
//! here; the factorization reports its failing index, named with
//! [`DofMap::dof_name`](super::dofs::DofMap::dof_name).

use super::assemble::AffineOperator;
use super::constraints::RigidElimination;
use super::dofs::{DofMap, DofSet};
use super::error::{AssemblyError, DofName};
use crate::card_values::Dofs;
use crate::model::Model;
use crate::model::sets::EnforcedEntry;

/// AUTOSPC threshold: a diagonal ≤ ratio × the largest diagonal of its grid's translation or
/// rotation triple counts as "no stiffness" (Nastran's EPZERO default).
pub const AUTOSPC_RATIO: f64 = 1e-8;

/// Constrained g DOFs with their enforced values and where each constraint came from.
#[derive(Debug, Clone, PartialEq)]
pub struct SpcSet {
    /// s-set mask over g.
    pub mask: Vec<bool>,
    /// Enforced values over g (0 outside s).
    pub enforced: Vec<f64>,
    /// The card that constrained each DOF with its file:line ("SPC1 1 at deck.dat:12", "GRID 7 PS at deck.dat:3") or "AUTOSPC".
    pub source: Vec<Option<String>>,
}

impl SpcSet {
    /// No constraint.
    pub fn empty(map: &DofMap) -> Self {
        SpcSet {
            mask: vec![false; map.size()],
            enforced: vec![0.0; map.size()],
            source: vec![None; map.size()],
        }
    }

    /// GRID PS of every grid plus the SPC set `sid` (if any).
    pub fn of_model(model: &Model, map: &DofMap, sid: Option<u32>) -> Result<Self, AssemblyError> {
        let mut out = SpcSet::empty(map);
        for (i, g) in model.grids.iter().enumerate() {
            for c in g.ps.components() {
                out.set(
                    map,
                    DofMap::dof(i, c - 1),
                    0.0,
                    format!("GRID {} PS at {}", g.id, g.loc),
                    None,
                )?;
            }
        }
        let Some(sid) = sid else { return Ok(out) };
        let entries = model
            .spc_set(sid)
            .map_err(|e| AssemblyError::unresolved_set(e, "SPC", "SPC/SPC1", "SPCADD", sid))?;
        for entry in &entries {
            let card = format!("{} {}", entry.card.name(), entry.set);
            for &g in &entry.grids {
                if let Some(&k) = model.scalar_index.get(&g) {
                    out.set(
                        map,
                        map.scalar_dof(k),
                        entry.value,
                        format!("{card} at {}", entry.loc),
                        Some(sid),
                    )?;
                    continue;
                }
                let grid = grid_of(model, g, &card)?;
                out.add_components(
                    map,
                    grid,
                    entry.components,
                    entry.value,
                    &format!("{card} at {}", entry.loc),
                    sid,
                )?;
            }
        }
        Ok(out)
    }

    fn add_components(
        &mut self,
        map: &DofMap,
        grid: usize,
        comps: Dofs,
        value: f64,
        source: &str,
        sid: u32,
    ) -> Result<(), AssemblyError> {
        for c in comps.components() {
            self.set(
                map,
                DofMap::dof(grid, c - 1),
                value,
                source.to_string(),
                Some(sid),
            )?;
        }
        Ok(())
    }

    /// Constrain one g DOF to `value`; a different value already set is an error.
    pub fn set(
        &mut self,
        map: &DofMap,
        dof: usize,
        value: f64,
        source: String,
        sid: Option<u32>,
    ) -> Result<(), AssemblyError> {
        let size = self.mask.len();
        if dof >= size {
            return Err(AssemblyError::DofOutOfRange { index: dof, size });
        }
        if self.mask[dof] && self.enforced[dof] != value {
            return Err(AssemblyError::ConflictingEnforced {
                dof: map.name(dof),
                sid: sid.unwrap_or(0),
                a: self.enforced[dof],
                b: value,
            });
        }
        if !self.mask[dof] {
            self.source[dof] = Some(source);
        }
        self.mask[dof] = true;
        self.enforced[dof] = value;
        Ok(())
    }

    /// The g-set enforced values with the SPCD entries `spcd` applied: each DOF an SPCD names
    /// takes the sum of its SPCD values in place of its SPC value. A DOF outside the s-set, or
    /// constrained by AUTOSPC only, is an error naming the SPCD card and its file:line.
    pub fn with_spcd(
        &self,
        model: &Model,
        map: &DofMap,
        spcd: &[EnforcedEntry],
    ) -> Result<Vec<f64>, AssemblyError> {
        let mut out = self.enforced.clone();
        let mut touched = vec![false; out.len()];
        for entry in spcd {
            let card = format!("SPCD {} at {}", entry.set, entry.loc);
            let dofs = point_dofs(model, map, entry.grid, entry.components, &card)?;
            for dof in dofs {
                let by_autospc = self.source[dof].as_deref() == Some("AUTOSPC");
                if !self.mask[dof] || by_autospc {
                    return Err(AssemblyError::SpcdNotConstrained {
                        dof: map.name(dof),
                        card,
                        autospc: by_autospc,
                    });
                }
                if !touched[dof] {
                    (touched[dof], out[dof]) = (true, 0.0);
                }
                out[dof] += entry.value;
            }
        }
        Ok(out)
    }

    /// Error if a constrained DOF is dependent in a rigid element.
    pub fn check_against_rigids(
        &self,
        rigid: &RigidElimination,
        map: &DofMap,
    ) -> Result<(), AssemblyError> {
        for (i, (&s, &m)) in self.mask.iter().zip(&rigid.m_mask).enumerate() {
            if s && m {
                return Err(AssemblyError::DependentConstrained {
                    dof: map.name(i),
                    rigid: rigid.owner(i).unwrap_or("a rigid element").to_string(),
                    constraint: self.source[i].clone().unwrap_or_else(|| "an SPC".into()),
                });
            }
        }
        Ok(())
    }

    /// Hold the r-set DOFs `suport` ([`suport_dofs`]) like SPCs at zero (SOL 101 without
    /// inertia relief, as MSC Nastran); a DOF already constrained keeps its constraint.
    pub fn add_suport(&mut self, suport: &[(usize, String)]) {
        for (d, source) in suport {
            if *d < self.mask.len() && !self.mask[*d] {
                self.mask[*d] = true;
                self.source[*d] = Some(source.clone());
            }
        }
    }

    /// Add the DOFs AUTOSPC found (enforced value 0).
    pub fn add_autospc(&mut self, report: &AutoSpcReport) {
        for &d in &report.dofs {
            if d < self.mask.len() && !self.mask[d] {
                self.mask[d] = true;
                self.enforced[d] = 0.0;
                self.source[d] = Some("AUTOSPC".into());
            }
        }
    }
}

/// The g indices of a grid's components, or of a scalar point's one DOF (`card` names the
/// referencing card in the error for a missing grid).
pub fn point_dofs(
    model: &Model,
    map: &DofMap,
    id: u32,
    components: Dofs,
    card: &str,
) -> Result<Vec<usize>, AssemblyError> {
    if let Some(&k) = model.scalar_index.get(&id) {
        return Ok(vec![map.scalar_dof(k)]);
    }
    let grid = grid_of(model, id, card)?;
    Ok((components.components())
        .map(|c| DofMap::dof(grid, c - 1))
        .collect())
}

/// The g indices of the r-set of a subcase (SUPORT cards and its `SUPORT1` set), each with
/// the card that put it there.
pub fn suport_dofs(
    model: &Model,
    map: &DofMap,
    suport1: Option<u32>,
) -> Result<Vec<(usize, String)>, AssemblyError> {
    let entries = (model.suport_entries(suport1)).map_err(|_| AssemblyError::NoConstraintSet {
        selection: "SUPORT1",
        cards: "SUPORT1".into(),
        sid: suport1.unwrap_or(0),
    })?;
    let mut out: Vec<(usize, String)> = Vec::new();
    for (id, dofs, source) in entries {
        for d in point_dofs(model, map, id, dofs, &source)? {
            if !out.iter().any(|(x, _)| *x == d) {
                out.push((d, source.clone()));
            }
        }
    }
    Ok(out)
}

fn grid_of(model: &Model, id: u32, card: &str) -> Result<usize, AssemblyError> {
    model
        .grid_index
        .get(&id)
        .copied()
        .ok_or(AssemblyError::MissingGrid {
            card: card.to_string(),
            grid: id,
        })
}

/// The DOFs AUTOSPC constrained, for the solver to print.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct AutoSpcReport {
    /// g indices, increasing.
    pub dofs: Vec<usize>,
    /// (GRID, component) of each.
    pub names: Vec<DofName>,
    /// Largest diagonal of K_nn (the reference of the ratio).
    pub max_diagonal: f64,
}

impl std::fmt::Display for AutoSpcReport {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "AUTOSPC constrained {} DOF(s) with stiffness ≤ {AUTOSPC_RATIO:e} × {:e}:",
            self.names.len(),
            self.max_diagonal
        )?;
        for n in &self.names {
            write!(f, " {}/{}", n.grid, n.component)?;
        }
        Ok(())
    }
}

/// Find n-set DOFs outside s with no stiffness in K_nn (values `k_nn` on `op`'s pattern,
/// typically K at the nominal parameters).
pub fn autospc(
    op: &AffineOperator,
    k_nn: &[f64],
    n: &DofSet,
    s_mask: &[bool],
    map: &DofMap,
) -> Result<AutoSpcReport, AssemblyError> {
    super::dofs::check_len("K_nn size (n-set)", n.len(), op.ncols())?;
    super::dofs::check_len("K_nn values", op.pattern().nnz(), k_nn.len())?;
    let diag = op.diagonal(k_nn);
    let max = diag.iter().fold(0.0_f64, |m, d| m.max(d.abs()));
    // Largest diagonal of each (grid, translations | rotations) triple among the n-set DOFs; a
    // scalar point is a group of its own (keys g / 3 < 2·grids never meet scalar g ≥ 6·grids).
    let grid_dofs = map.size() - map.scalar_points();
    let group = |g: usize| if g < grid_dofs { g / 3 } else { g };
    let mut triple_max: std::collections::HashMap<usize, f64> = std::collections::HashMap::new();
    for (k, &g) in n.members().iter().enumerate() {
        let entry = triple_max.entry(group(g)).or_insert(0.0);
        *entry = entry.max(diag[k].abs());
    }
    let mut report = AutoSpcReport {
        max_diagonal: max,
        ..Default::default()
    };
    for (k, &g) in n.members().iter().enumerate() {
        if s_mask.get(g).copied().unwrap_or(false) {
            continue;
        }
        let local = triple_max.get(&group(g)).copied().unwrap_or(0.0);
        let d = diag[k].abs();
        if d <= AUTOSPC_RATIO * local {
            report.dofs.push(g);
            report.names.push(map.name(g));
        }
    }
    Ok(report)
}

/// The n-set DOFs outside s whose diagonal is exactly zero in every matrix of `diagonals` (the
/// solution's matrices over the n-set: K in statics, K and M in the eigenproblems, and the
/// damping matrices in direct response): with `PARAM,AUTOSPC,NO` these DOFs (e.g. the rotations
/// of a grid only rods reach) carry no equation of the solution, and MSC Nastran still removes
/// them (its static displacements and mode shapes of such decks are exactly zero there). The matrices are positive semi-definite, so a zero diagonal is a null row and column.
pub fn null_dofs(
    diagonals: &[Vec<f64>],
    n: &DofSet,
    s_mask: &[bool],
    map: &DofMap,
) -> AutoSpcReport {
    let mut report = AutoSpcReport::default();
    for (k, &g) in n.members().iter().enumerate() {
        let free = !s_mask.get(g).copied().unwrap_or(false);
        if free
            && diagonals
                .iter()
                .all(|d| d.get(k).copied().unwrap_or(0.0) == 0.0)
        {
            report.dofs.push(g);
            report.names.push(map.name(g));
        }
    }
    report
}
