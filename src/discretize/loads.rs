//! Loads and initial conditions of a model on the f-set of a [`Constrained`] system.
//!
//! - Placement: a DAREA entry (component in the grid's CD frame, as Nastran's DAREA) is a
//!   g-set unit load reduced to n through the rigid elimination (Tᵀ: a dependent RBE DOF
//!   spreads to its independent DOFs) and restricted to f ([`place_darea`],
//!   [`unit_load_columns`]); a static load set (FORCE, MOMENT, LOAD) used as a TLOAD's or an
//!   RLOAD's EXCITEID the same way ([`static_shape`]). A load on a constrained DOF is an error: it would be lost.
//!   On a pROM, a DAREA entry names one of its input DOFs and loads that column of S_r
//!   ([`place_input`]).
//! - Time domain ([`load_terms`]): `DLOAD = sid` as a DLOAD combination S·Σ Sᵢ·Lᵢ or one load
//!   set, each TLOAD1/TLOAD2 a shape × F(t − delay), F a table or a pulse ([`LoadTerm`], summed
//!   by [`load_into`]).
//! - Frequency domain ([`frequency_inputs`]): the DAREA DOFs of the RLOAD1/RLOAD2s of
//!   `DLOAD = sid` are the inputs, and so is each static load set an EXCITEID selects; each term is scale · P(f) · e^{i(θ − 2πfτ)} with
//!   P = C(f) + iD(f) (RLOAD1) or B(f) e^{iφ(f)} (RLOAD2) ([`FrequencyLoad`]).
//! - Tables ([`dynamic_table`]): a TABLED1–TABLED4 or a TABLEF (CSV read through
//!   [`crate::io::csv_table`]).
//! - Initial conditions ([`initial_state`]): the TIC cards of `IC = sid` on the f-set.

use faer::{Mat, c64};

use super::enforced::enforced_dofs;
use super::{Constrained, Structure};
use crate::assembly::AssemblyError;
use crate::assembly::DofMap;
use crate::assembly::loads::{Mass, load_vector};
use crate::deck::cards::{ExcitationKind, RloadTables, RloadValue, TloadFunction};
use crate::dynamics::pulse::Pulse;
use crate::dynamics::table::Table;
use crate::io::csv_table::read_columns;
use crate::model::Model;
use crate::model::dynamic_loads::{DynamicTable, Excitation, TableData};
use crate::model::sets::EnforcedEntry;

/// A TABLED1–TABLED4 or TABLEF (CSV, path relative to the file holding the card) by id.
pub fn dynamic_table(model: &Model, tid: u32) -> Result<Table, String> {
    let Some(DynamicTable { card, data, loc }) = model.dynamic_table(tid) else {
        return Err(format!("table {tid} is no TABLED1–TABLED4 or TABLEF"));
    };
    match data {
        TableData::Points(points) => {
            Table::new(&points).map_err(|e| format!("{loc}: {card} {tid}: {e}"))
        }
        TableData::PowerSeries(series) => {
            Table::power_series(series).map_err(|e| format!("{loc}: {card} {tid}: {e}"))
        }
        TableData::Csv { path, x, y } => {
            let points =
                read_columns(&path, &x, &y).map_err(|e| format!("{loc}: {card} {tid}: {e}"))?;
            Table::new(&points)
                .map_err(|e| format!("{loc}: {card} {tid} ({}): {e}", path.display()))
        }
    }
}

/// A TLOAD1's (or PTABLE's) table, [`dynamic_table`], with `user` naming the card in errors.
pub fn table_of(model: &Model, tid: u32, user: &str) -> Result<Table, String> {
    dynamic_table(model, tid).map_err(|e| format!("{user}: {e}"))
}

/// One time-domain load term: shape × F(t − delay).
pub struct LoadTerm {
    pub shape: Vec<f64>,
    pub function: TimeFunction,
    pub delay: f64,
}

/// A TLOAD's F: a table (TLOAD1) or a pulse (TLOAD2).
pub enum TimeFunction {
    Table(Table),
    Pulse(Pulse),
}

impl TimeFunction {
    /// F(x).
    pub fn value(&self, x: f64) -> f64 {
        match self {
            TimeFunction::Table(table) => table.value(x),
            TimeFunction::Pulse(pulse) => pulse.value(x),
        }
    }

    /// (F, F', F'') at x, right-hand limits where F has a corner ([`Table::slope`],
    /// [`Table::curvature`], [`Pulse::derivatives`]).
    pub fn derivatives(&self, x: f64) -> [f64; 3] {
        match self {
            TimeFunction::Table(table) => [table.value(x), table.slope(x), table.curvature(x)],
            TimeFunction::Pulse(pulse) => pulse.derivatives(x),
        }
    }
}

impl LoadTerm {
    /// F(t − delay).
    pub fn factor(&self, t: f64) -> f64 {
        self.function.value(t - self.delay)
    }
}

/// f(t) = Σ shape · F(t − delay) into `f`.
pub fn load_into(terms: &[LoadTerm], t: f64, f: &mut [f64]) {
    load_into_where(terms, t, f, &|_| true);
}

/// f(t) = Σ shape · F(t − delay) over the terms `which` keeps.
pub fn load_into_where(
    terms: &[LoadTerm],
    t: f64,
    f: &mut [f64],
    which: &dyn Fn(&LoadTerm) -> bool,
) {
    f.fill(0.0);
    for term in terms.iter().filter(|term| which(term)) {
        let a = term.factor(t);
        if a != 0.0 {
            f.iter_mut()
                .zip(&term.shape)
                .for_each(|(fi, s)| *fi += a * s);
        }
    }
}

/// A TLOAD1/TLOAD2 of TYPE = DISP, VELO or ACCE: the SPCD entries its EXCITEID selects (values
/// scaled by the DLOAD factors) move by value · F(t − delay), F the displacement, velocity or
/// acceleration `kind` says.
pub struct EnforcedLoad {
    pub kind: ExcitationKind,
    pub entries: Vec<EnforcedEntry>,
    pub function: TimeFunction,
    pub delay: f64,
    /// The card and its SID, for messages ("TLOAD1 7").
    pub name: String,
}

/// The time-domain loads of `DLOAD = sid`: applied loads and enforced motions.
pub struct TimeLoads {
    pub applied: Vec<LoadTerm>,
    pub enforced: Vec<EnforcedLoad>,
}

impl TimeLoads {
    /// The applied loads, for a model on which enforced motion is not available (`model`
    /// names it); an error naming the first enforced-motion TLOAD otherwise.
    pub fn applied_only(self, model: &str) -> Result<Vec<LoadTerm>, String> {
        match self.enforced.first() {
            None => Ok(self.applied),
            Some(e) => Err(format!(
                "{}: TYPE = {} (enforced motion) is not available on {model} in this version; the full model takes it (SOL 109/112 without ROM)",
                e.name,
                e.kind.name()
            )),
        }
    }
}

/// The load terms of `DLOAD = sid`: a DLOAD combination S·Σ Sᵢ·(TLOAD Lᵢ), or one TLOAD set.
/// `place(excitation, scale, shape)` adds one DAREA entry (scale including the DLOAD factors) to a shape vector of length `len`; when a TLOAD1's EXCITEID selects no
/// DAREA, `static_set(excite_id)` may supply the shape of a static load set (FORCE, LOAD) as the
/// full model does, or `None` (pROMs: loads act on input DOFs only). A TLOAD of TYPE = DISP,
/// VELO or ACCE is an enforced motion of the SPCD set its EXCITEID names ([`EnforcedLoad`]).
pub fn load_terms(
    model: &Model,
    sid: u32,
    len: usize,
    mut place: impl FnMut(&Excitation, f64, &mut [f64]) -> Result<(), String>,
    mut static_set: impl FnMut(u32) -> Result<Option<Vec<f64>>, String>,
) -> Result<TimeLoads, String> {
    let mut out = TimeLoads {
        applied: Vec::new(),
        enforced: Vec::new(),
    };
    for (scale, set) in model.dynamic_load_members(sid) {
        let tloads = model.transient_loads(set);
        if tloads.is_empty() {
            return Err(format!(
                "DLOAD {sid}: load set {set} has no TLOAD1 or TLOAD2"
            ));
        }
        for t in tloads {
            let card = t.function.card();
            let function = match &t.function {
                TloadFunction::Table(tid) => {
                    TimeFunction::Table(table_of(model, *tid, &format!("{card} {}", t.sid))?)
                }
                TloadFunction::Pulse(pulse) => TimeFunction::Pulse(pulse.clone()),
            };
            if t.kind != ExcitationKind::Load {
                let entries = model.enforced_members(&[(scale, t.excite_id)]);
                if entries.is_empty() {
                    return Err(format!(
                        "{card} {}: TYPE = {} needs EXCITEID = an SPCD set; there is no SPCD {}",
                        t.sid,
                        t.kind.name(),
                        t.excite_id
                    ));
                }
                out.enforced.push(EnforcedLoad {
                    kind: t.kind,
                    entries,
                    function,
                    delay: t.delay,
                    name: format!("{card} {}", t.sid),
                });
                continue;
            }
            let mut shape = vec![0.0; len];
            for x in &t.excitation {
                place(x, scale * x.scale, &mut shape)?;
            }
            if t.excitation.is_empty() {
                let p = static_set(t.excite_id)
                    .map_err(|e| format!("{card} {}: {e}", t.sid))?
                    .ok_or_else(|| {
                        format!(
                            "{card} {}: EXCITEID {} selects no DAREA",
                            t.sid, t.excite_id
                        )
                    })?;
                shape.iter_mut().zip(&p).for_each(|(s, p)| *s += scale * p);
            }
            out.applied.push(LoadTerm {
                shape,
                function,
                delay: t.delay,
            });
        }
    }
    Ok(out)
}

/// The f-set shape of a static load set (FORCE, MOMENT, LOAD combinations) used as a TLOAD's or
/// an RLOAD's EXCITEID: the LID of an LSEQ of the subcase's `loadset` with that EXCITEID, or
/// the set of that id itself (as MSC Nastran accepts without LSEQ).
pub fn static_shape(
    model: &Model,
    st: &Structure,
    c: &Constrained,
    excite_id: u32,
    loadset: Option<u32>,
) -> Result<Option<Vec<f64>>, String> {
    let sid = model.excited_static_set(excite_id, loadset);
    let with_mass = |values: &[f64]| {
        load_vector(
            model,
            &st.frames,
            &st.map,
            sid,
            Some(Mass {
                operator: st.mass_gg(),
                values,
            }),
        )
    };
    // M_gg is evaluated only for a set with GRAV
    let p_g = match load_vector(model, &st.frames, &st.map, sid, None) {
        Err(AssemblyError::MassRequired { .. }) => {
            st.mass_gg_values().and_then(|values| with_mass(&values))
        }
        other => other,
    }
    .map_err(|e| format!("EXCITEID {sid}: no DAREA and {e}"))?;
    let p_n = st.rigid.reduce_vector(&p_g).map_err(|e| e.to_string())?;
    c.sets
        .f_in_n
        .gather(&p_n)
        .map(Some)
        .map_err(|e| e.to_string())
}

/// Adds a DAREA entry to an f-set load shape: the g-set entry (grid's displacement frame, as
/// DAREA components are) reduced to n through the rigid elimination (Tᵀ) and restricted to f;
/// an entry on a constrained DOF is an error (it would be lost).
pub fn place_darea(
    model: &Model,
    st: &Structure,
    c: &Constrained,
    d: &Excitation,
    scale: f64,
    shape: &mut [f64],
) -> Result<(), String> {
    let comp = d.component;
    let grid = model
        .grid_index
        .get(&d.grid)
        .copied()
        .ok_or_else(|| format!("DAREA {}: GRID {} does not exist", d.sid, d.grid))?;
    let mut p_g = vec![0.0; st.map.size()];
    p_g[DofMap::dof(grid, comp - 1)] = scale;
    let p_n = st.rigid.reduce_vector(&p_g).map_err(|e| e.to_string())?;
    let p_f = c.sets.f_in_n.gather(&p_n).map_err(|e| e.to_string())?;
    if p_f.iter().all(|x| *x == 0.0) {
        return Err(format!(
            "DAREA {}: GRID {} component {comp} is constrained (SPC or AUTOSPC): the load would not act",
            d.sid, d.grid
        ));
    }
    shape.iter_mut().zip(&p_f).for_each(|(s, p)| *s += p);
    Ok(())
}

/// The f-set state of `IC = sid` (none: at rest): each TIC sets u and u̇ of one free grid
/// component (its displacement frame); components without a TIC start at zero. A TIC on a
/// constrained (SPC, AUTOSPC) or dependent (RBE) DOF is an error: its value would be ignored.
pub fn initial_state(
    model: &Model,
    c: &Constrained,
    sid: Option<u32>,
) -> Result<(Vec<f64>, Vec<f64>), String> {
    let n_f = c.sets.f.len();
    let (mut u, mut v) = (vec![0.0; n_f], vec![0.0; n_f]);
    let Some(sid) = sid else { return Ok((u, v)) };
    let cards = model.tic(sid);
    if cards.is_empty() {
        return Err(format!("IC = {sid} selects no TIC card"));
    }
    for t in cards {
        let grid = model
            .grid_index
            .get(&t.grid)
            .copied()
            .ok_or_else(|| format!("TIC {sid}: GRID {} does not exist", t.grid))?;
        let i = c.sets.f.position(DofMap::dof(grid, t.component - 1)).ok_or_else(|| format!("TIC {sid}: GRID {} component {} is not a free DOF (constrained by SPC/AUTOSPC or dependent in an RBE)", t.grid, t.component))?;
        u[i] += t.u0;
        v[i] += t.v0;
    }
    Ok((u, v))
}

/// One RLOAD1/RLOAD2 term on one input: scale · P(f) · e^{i(θ − 2πfτ)}, for enforced motion
/// the displacement of that value (a velocity divided by iω, an acceleration by −ω²).
pub struct FrequencyLoad {
    /// Index of the input DOF the term loads.
    pub input: usize,
    pub scale: f64,
    pub p: FrequencyFunction,
    /// θ (rad).
    pub phase: f64,
    /// τ (s).
    pub delay: f64,
    /// TYPE of the RLOAD.
    pub kind: ExcitationKind,
}

impl FrequencyLoad {
    /// The complex load (or enforced displacement) at `hz`; a VELO or ACCE term at 0 Hz is
    /// infinite (the caller refuses that line).
    pub fn at(&self, hz: f64) -> c64 {
        let w = 2.0 * std::f64::consts::PI * hz;
        let integrate = match self.kind {
            ExcitationKind::Load | ExcitationKind::Displacement => c64::new(1.0, 0.0),
            ExcitationKind::Velocity => c64::new(0.0, -1.0 / w),
            ExcitationKind::Acceleration => c64::new(-1.0 / (w * w), 0.0),
        };
        let value = |t: &Option<Table>| t.as_ref().map_or(0.0, |t| t.value(hz));
        let p = match &self.p {
            FrequencyFunction::Rectangular { c, d } => c64::new(value(c), value(d)),
            FrequencyFunction::Polar { b, phi } => {
                let phi = value(phi).to_radians();
                c64::new(phi.cos(), phi.sin()) * b.value(hz)
            }
        };
        let angle = self.phase - w * self.delay;
        p * c64::new(angle.cos(), angle.sin()) * self.scale * integrate
    }
}

/// An RLOAD's P(f) (a table `None`: zero).
#[derive(Clone)]
pub enum FrequencyFunction {
    /// RLOAD1: C(f) + i D(f).
    Rectangular { c: Option<Table>, d: Option<Table> },
    /// RLOAD2: B(f) e^{i φ(f)}, φ in degrees.
    Polar { b: Table, phi: Option<Table> },
}

/// The inputs of a frequency response: names `GRID:component` (DAREA DOFs, unit-load columns)
/// then `LOAD sid` (static load sets selected by an EXCITEID, their load vector as the column),
/// then `GRID:component` of the enforced DOFs (SPCD DOFs of RLOADs with TYPE = DISP, VELO or
/// ACCE: a zero column here, their response is composed by the caller from
/// [`crate::discretize::enforced::EnforcedColumns`]); the f-set columns (n_f × k) and the RLOAD
/// terms on them.
pub struct FrequencyInputs {
    pub names: Vec<String>,
    pub columns: Mat<f64>,
    pub terms: Vec<FrequencyLoad>,
    /// g index of each enforced DOF: the last `enforced.len()` inputs.
    pub enforced: Vec<usize>,
}

impl FrequencyInputs {
    /// The response to the RLOAD1 terms at each line, Σ H(f)[o, input] · P(f) over the terms,
    /// line-major (lines × `outputs`); `h(line, output, input)` reads H.
    pub fn response(
        &self,
        hz: &[f64],
        outputs: usize,
        h: impl Fn(usize, usize, usize) -> c64,
    ) -> Vec<c64> {
        let mut out = vec![c64::new(0.0, 0.0); hz.len() * outputs];
        for (l, f) in hz.iter().enumerate() {
            for term in &self.terms {
                let p = term.at(*f);
                for o in 0..outputs {
                    out[l * outputs + o] += h(l, o, term.input) * p;
                }
            }
        }
        out
    }
}

/// The inputs of `DLOAD = sid` (a DLOAD combination S·Σ Sᵢ·Lᵢ or one RLOAD set): every DAREA
/// entry of its RLOADs' EXCITEIDs is an input DOF, loaded by a unit force through Tᵀ; an
/// EXCITEID with no DAREA selects a static load set, one input whose column is its load vector
/// (its output row is the load's work-conjugate displacement pᵀu).
pub fn frequency_inputs(
    model: &Model,
    st: &Structure,
    c: &Constrained,
    sid: u32,
    loadset: Option<u32>,
) -> Result<FrequencyInputs, String> {
    let mut dofs: Vec<(u32, usize)> = Vec::new();
    let mut static_sets: Vec<(u32, Vec<f64>)> = Vec::new();
    // terms on a static set: (index in `terms`, index in `static_sets`), numbered after the DOFs
    let mut on_static_sets: Vec<(usize, usize)> = Vec::new();
    // enforced DOFs (g indices) and the terms on them, numbered after the static sets
    let mut enforced: Vec<usize> = Vec::new();
    let mut on_enforced: Vec<(usize, usize)> = Vec::new();
    let mut terms = Vec::new();
    for (scale, set) in model.dynamic_load_members(sid) {
        let rloads = model.harmonic_loads(set);
        if rloads.is_empty() {
            return Err(format!(
                "DLOAD {sid}: load set {set} has no RLOAD1 or RLOAD2"
            ));
        }
        for r in rloads {
            let card = r.tables.card();
            let table = |value: RloadValue| match value {
                RloadValue::Table(0) => Ok(None),
                RloadValue::Table(tid) => dynamic_table(model, tid)
                    .map(Some)
                    .map_err(|e| format!("{card} {}: {e}", r.sid)),
                // a one-point table is that value at every frequency
                RloadValue::Constant(c) => Table::new(&[(0.0, c)])
                    .map(Some)
                    .map_err(|e| format!("{card} {}: {e}", r.sid)),
            };
            let p = match r.tables {
                RloadTables::Rectangular { tc, td } => FrequencyFunction::Rectangular {
                    c: table(tc)?,
                    d: table(td)?,
                },
                RloadTables::Polar { tb, tp } => FrequencyFunction::Polar {
                    b: table(tb)?.ok_or_else(|| format!("{card} {}: TB is required", r.sid))?,
                    phi: table(tp)?,
                },
            };
            for x in &r.excitation {
                let dof = (x.grid, x.component);
                let input = match dofs.iter().position(|&d| d == dof) {
                    Some(i) => i,
                    None => {
                        dofs.push(dof);
                        dofs.len() - 1
                    }
                };
                terms.push(FrequencyLoad {
                    input,
                    scale: scale * x.scale,
                    p: p.clone(),
                    phase: r.phase_deg.to_radians(),
                    delay: r.delay,
                    kind: r.kind,
                });
            }
            if r.kind != ExcitationKind::Load {
                let entries = model.enforced_members(&[(1.0, r.excite_id)]);
                let moved = enforced_dofs(model, st, c, &entries)
                    .map_err(|e| format!("{card} {}: {e}", r.sid))?;
                for (g, value) in moved {
                    let index = match enforced.iter().position(|&x| x == g) {
                        Some(i) => i,
                        None => {
                            enforced.push(g);
                            enforced.len() - 1
                        }
                    };
                    on_enforced.push((terms.len(), index));
                    terms.push(FrequencyLoad {
                        input: index,
                        scale: scale * value,
                        p: p.clone(),
                        phase: r.phase_deg.to_radians(),
                        delay: r.delay,
                        kind: r.kind,
                    });
                }
            } else if r.excitation.is_empty() {
                let known = static_sets.iter().position(|(id, _)| *id == r.excite_id);
                let index = match known {
                    Some(i) => i,
                    None => {
                        let shape = static_shape(model, st, c, r.excite_id, loadset)
                            .map_err(|e| format!("{card} {}: {e}", r.sid))?
                            .ok_or_else(|| {
                                format!(
                                    "{card} {}: EXCITEID {} selects no DAREA",
                                    r.sid, r.excite_id
                                )
                            })?;
                        static_sets.push((r.excite_id, shape));
                        static_sets.len() - 1
                    }
                };
                on_static_sets.push((terms.len(), index));
                terms.push(FrequencyLoad {
                    input: index,
                    scale,
                    p: p.clone(),
                    phase: r.phase_deg.to_radians(),
                    delay: r.delay,
                    kind: r.kind,
                });
            }
        }
    }
    for (term, index) in on_static_sets {
        terms[term].input = dofs.len() + index;
    }
    for (term, index) in on_enforced {
        terms[term].input = dofs.len() + static_sets.len() + index;
    }
    let unit = unit_load_columns(model, st, c, &dofs)?;
    let loads = dofs.len() + static_sets.len();
    let columns = Mat::from_fn(unit.nrows(), loads + enforced.len(), |i, j| {
        match j.checked_sub(dofs.len()) {
            None => unit[(i, j)],
            Some(k) if k < static_sets.len() => static_sets[k].1[i],
            Some(_) => 0.0,
        }
    });
    let names = dofs
        .iter()
        .map(|(g, c)| format!("{g}:{c}"))
        .chain(static_sets.iter().map(|(id, _)| format!("LOAD {id}")))
        .chain(enforced.iter().map(|&g| {
            let n = st.map.name(g);
            format!("{}:{}", n.grid, n.component)
        }))
        .collect();
    Ok(FrequencyInputs {
        names,
        columns,
        terms,
        enforced,
    })
}

/// The f-set columns (n_f × k) of unit loads on `dofs` (GRID id, component 1–6 in its CD
/// frame) through Tᵀ; a DOF whose load moves nothing (constrained) is an error.
pub fn unit_load_columns(
    model: &Model,
    st: &Structure,
    c: &Constrained,
    dofs: &[(u32, usize)],
) -> Result<Mat<f64>, String> {
    let mut columns = Mat::<f64>::zeros(c.sets.f.len(), dofs.len());
    for (j, &(grid, comp)) in dofs.iter().enumerate() {
        let index = *model
            .grid_index
            .get(&grid)
            .ok_or_else(|| format!("DAREA: GRID {grid} does not exist"))?;
        let g = DofMap::dof(index, comp - 1);
        let row = st.rigid.t.row(g);
        let mut any = false;
        for (&n, &t) in row.col_indices().iter().zip(row.values()) {
            if let Some(f) = c.sets.f_in_n.position(n) {
                columns[(f, j)] += t;
                any |= t != 0.0;
            }
        }
        if !any {
            return Err(format!(
                "DAREA: GRID {grid} component {comp} is constrained (SPC, AUTOSPC): a load there moves nothing"
            ));
        }
    }
    Ok(columns)
}

/// The load shapes of the pROM inputs `which` (columns of S_r, n × k), in that order.
pub fn input_columns(s_r: &Mat<f64>, which: &[usize]) -> Mat<f64> {
    Mat::from_fn(s_r.nrows(), which.len(), |i, k| s_r[(i, which[k])])
}

/// Adds a DAREA entry, which must name a pROM input DOF (`GRID:component`), to a reduced load
/// shape: scale × column of S_r.
pub fn place_input(
    names: &[String],
    s_r: &Mat<f64>,
    d: &Excitation,
    scale: f64,
    shape: &mut [f64],
) -> Result<(), String> {
    let comp = d.component;
    let name = format!("{}:{comp}", d.grid);
    let j = names.iter().position(|x| *x == name).ok_or_else(|| {
        format!(
            "DAREA {}: GRID {} component {comp} is not an input DOF of the pROM (inputs: {})",
            d.sid,
            d.grid,
            names.join(", ")
        )
    })?;
    shape
        .iter_mut()
        .enumerate()
        .for_each(|(i, s)| *s += scale * s_r[(i, j)]);
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An enforced velocity is integrated to a displacement as v/(iω) and an acceleration as
    /// a/(−ω²) (Nastran's frequency-domain enforced motion); a displacement or a load is taken
    /// as it is. P(f) = 2 (a constant table), scale 3, no phase or delay.
    #[test]
    fn enforced_velocity_and_acceleration_are_integrated() {
        let table = Table::new(&[(0.0, 2.0), (100.0, 2.0)]).expect("table");
        let term = |kind| FrequencyLoad {
            input: 0,
            scale: 3.0,
            p: FrequencyFunction::Rectangular {
                c: Some(table.clone()),
                d: None,
            },
            phase: 0.0,
            delay: 0.0,
            kind,
        };
        let (hz, w) = (10.0, 2.0 * std::f64::consts::PI * 10.0);
        let close = |a: c64, b: c64| (a - b).norm() <= 1e-15 * b.norm();
        assert!(close(term(ExcitationKind::Load).at(hz), c64::new(6.0, 0.0)));
        assert!(close(
            term(ExcitationKind::Displacement).at(hz),
            c64::new(6.0, 0.0)
        ));
        assert!(close(
            term(ExcitationKind::Velocity).at(hz),
            c64::new(0.0, -6.0 / w)
        ));
        assert!(close(
            term(ExcitationKind::Acceleration).at(hz),
            c64::new(-6.0 / (w * w), 0.0)
        ));
    }
}
