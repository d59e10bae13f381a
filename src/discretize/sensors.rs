//! The SENSOR measurement operator on the f-set (DESIGN.md §3 `SENSOR`; thesis §2.3,
//! eq. 2.30–2.35): one sparse row per sensor, y = H u_f, shared by every sequence that
//! outputs sensors (full-model FRF, the pROM build's H_r = H Φ, transients, the estimator).
//!
//! - `DISP` / `VEL` / `ACCEL` (REF = grid): the translation of the grid along the normalized
//!   basic direction ϑ, y = ϑᵀ u_grid (eq. 2.34). VEL and ACCEL rows are the same row applied
//!   to u̇_f and ü_f (eq. 2.35). A dependent grid of an RBE2 / RBE3 is measured through the
//!   g → n recovery u_g = T u_n, so its row lands on the independent DOFs.
//! - `STRAIN` (REF = element): the strain at the element centroid projected on ϑ,
//!   ε_ϑ = ϑᵀ ε ϑ (tensor strain), i.e. [ϑ₁² ϑ₂² ϑ₃² ϑ₁ϑ₂ ϑ₂ϑ₃ ϑ₃ϑ₁] · [εxx εyy εzz γxy γyz γzx]
//!   with engineering shears (eq. 2.31–2.32). Solids use the centroid strain of
//!   [`crate::fe::solid::strain_at_centroid`] (basic system). Shells use the centroid strains
//!   of SOL 101's STRAIN output ([`super::elements::shell_strains`]) in the material system
//!   (x_m, y_m, n) at the fibre `SURF` selects: `TOP` = Z2 / the laminate's top surface,
//!   `BOT` = Z1 / its bottom surface, `MID` (or blank) = halfway between them; ϑ is expressed
//!   in (x_m, y_m) and its normal component is not measured (plane stress: a surface gauge
//!   reads in-plane strain only).
//!
//! Both recoveries are linear in the element displacements; a row is built by evaluating the
//! recovery on the unit displacements of the element's DOFs (no second copy of the strain
//! operators). Basic rows are rotated to the grids' CD frames (Λᵀ), mapped g → n by Tᵀ and
//! restricted to the f-set (constrained DOFs do not move in a response).
//!
//! Which sensors a run measures (a subcase's `SENSOR = ALL | NONE | set`) is the caller's
//! choice: [`sensor_operator`] takes the model's sensors ([`crate::model::sensors`]).

use std::collections::{BTreeMap, HashMap};

use faer::Mat;
use nalgebra_sparse::{CooMatrix, CscMatrix};

use super::elements::shell_strains;
use super::{Constrained, DiscretizeError, Structure};
use crate::assembly::DofSet;
use crate::card_values::SensorKind;
use crate::dynamics::measurement::Reads;
use crate::geometry::vec3::dot;
use crate::model::Model;
use crate::model::sensors::Sensor;

/// The measurement rows of a subcase's sensors on the f-set.
#[derive(Debug, Clone)]
pub struct SensorOperator {
    pub names: Vec<String>,
    pub kinds: Vec<SensorKind>,
    /// What each row reads ([`Reads::of_sensor`]).
    pub reads: Vec<Reads>,
    /// s × n_f: y = H u_f (DISP, STRAIN); VEL and ACCEL rows act on u̇_f and ü_f.
    pub rows: CscMatrix<f64>,
    /// The same rows on the constrained DOFs (sensors × n_s): what an enforced motion of the
    /// s-set adds to y.
    pub rows_s: CscMatrix<f64>,
}

impl SensorOperator {
    /// Number of sensors.
    pub fn len(&self) -> usize {
        self.names.len()
    }

    /// True when the subcase has no sensor.
    pub fn is_empty(&self) -> bool {
        self.names.is_empty()
    }

    /// H Φ (s × k) for an f-set basis Φ (n_f × k): the rows on reduced coordinates (eq. 2.32,
    /// 2.34).
    pub fn project(&self, basis: &Mat<f64>) -> Mat<f64> {
        project_rows(&self.rows, basis)
    }

    /// y = H (u_f, u̇_f or ü_f as each row reads), the measurement equations eq. 2.32–2.35
    /// ([`crate::dynamics::measurement`]); `y` has one entry per sensor, no allocation.
    pub fn evaluate(&self, u: &[f64], v: &[f64], a: &[f64], y: &mut [f64]) {
        y.fill(0.0);
        for (j, col) in self.rows.col_iter().enumerate() {
            for (&i, &h) in col.row_indices().iter().zip(col.values()) {
                y[i] += h * self.reads[i].select(u, v, a)[j];
            }
        }
    }

    /// y += H_s (u_s, u̇_s or ü_s as each row reads): what a prescribed motion of the
    /// constrained DOFs adds to [`Self::evaluate`].
    pub fn add_constrained(&self, u_s: &[f64], v_s: &[f64], a_s: &[f64], y: &mut [f64]) {
        for (j, col) in self.rows_s.col_iter().enumerate() {
            for (&i, &h) in col.row_indices().iter().zip(col.values()) {
                y[i] += h * self.reads[i].select(u_s, v_s, a_s)[j];
            }
        }
    }

    /// y = H u_f.
    pub fn apply(&self, u_f: &[f64]) -> Vec<f64> {
        let mut y = vec![0.0; self.rows.nrows()];
        for (j, col) in self.rows.col_iter().enumerate() {
            for (&i, &h) in col.row_indices().iter().zip(col.values()) {
                y[i] += h * u_f[j];
            }
        }
        y
    }
}

/// R Φ (r × k) of sparse f-set rows R (r × n_f) on an f-set basis Φ (n_f × k).
pub fn project_rows(rows: &CscMatrix<f64>, basis: &Mat<f64>) -> Mat<f64> {
    let mut out = Mat::<f64>::zeros(rows.nrows(), basis.ncols());
    for (j, col) in rows.col_iter().enumerate() {
        for (&i, &h) in col.row_indices().iter().zip(col.values()) {
            for k in 0..basis.ncols() {
                out[(i, k)] += h * basis[(j, k)];
            }
        }
    }
    out
}

/// The name written for a sensor kind (`/prom/sensors/kind`, FRF outputs).
pub fn sensor_kind_name(kind: SensorKind) -> &'static str {
    match kind {
        SensorKind::Disp => "DISP",
        SensorKind::Vel => "VEL",
        SensorKind::Accel => "ACCEL",
        SensorKind::Strain => "STRAIN",
    }
}

/// The f-set rows of `sensors` (see the module documentation). An error names the SENSOR:
/// `SENSOR <name>: <what>`.
pub fn sensor_operator(
    model: &Model,
    st: &Structure,
    c: &Constrained,
    sensors: &[Sensor],
) -> Result<SensorOperator, String> {
    let element_index: HashMap<u32, usize> = model
        .elements
        .iter()
        .enumerate()
        .map(|(i, e)| (e.id, i))
        .collect();
    let mut coo = CooMatrix::new(sensors.len(), c.sets.f.len());
    let mut coo_s = CooMatrix::new(sensors.len(), c.sets.s.len());
    let mut names = Vec::with_capacity(sensors.len());
    let mut kinds = Vec::with_capacity(sensors.len());
    for (r, s) in sensors.iter().enumerate() {
        let case = |what: String| format!("SENSOR {}: {what}", s.name);
        let norm = s.direction.iter().map(|x| x * x).sum::<f64>().sqrt();
        if !(norm > 0.0 && norm.is_finite()) {
            return Err(case("direction (X, Y, Z) is zero".into()));
        }
        let d = s.direction.map(|x| x / norm);
        let basic = match s.kind {
            SensorKind::Disp | SensorKind::Vel | SensorKind::Accel => {
                let grid = *model
                    .grid_index
                    .get(&s.reference)
                    .ok_or_else(|| case(format!("GRID {} does not exist", s.reference)))?;
                (0..3).map(|i| (6 * grid + i, d[i])).collect()
            }
            SensorKind::Strain => {
                let index = *element_index
                    .get(&s.reference)
                    .ok_or_else(|| case(format!("element {} does not exist", s.reference)))?;
                strain_row(model, st, index, s, d).map_err(|e| case(e.to_string()))?
            }
        };
        for (f, h) in set_row(st, &c.sets.f_in_n, &basic) {
            coo.push(r, f, h);
        }
        for (k, h) in set_row(st, &c.sets.s_in_n, &basic) {
            coo_s.push(r, k, h);
        }
        names.push(s.name.clone());
        kinds.push(s.kind);
    }
    let reads = kinds.iter().map(|k| Reads::of_sensor(*k)).collect();
    Ok(SensorOperator {
        names,
        kinds,
        reads,
        rows: CscMatrix::from(&coo),
        rows_s: CscMatrix::from(&coo_s),
    })
}

/// The strain row in basic g-set DOFs (6 per grid): ϑᵀ ε ϑ at the element centroid as a
/// linear function of the element's basic displacements, probed column by column.
fn strain_row(
    model: &Model,
    st: &Structure,
    index: usize,
    s: &Sensor,
    d: [f64; 3],
) -> Result<Vec<(usize, f64)>, DiscretizeError> {
    let e = &model.elements[index];
    let bad = |reason: String| DiscretizeError::Element {
        card: e.kind.card(),
        id: e.id,
        reason,
    };
    let xyz = model.positions(e);
    let mut row = Vec::new();
    if let Some((_, rec)) = st.shells.iter().find(|(i, _)| *i == index) {
        let surface = s.surface.unwrap_or("MID");
        let mut unit = vec![0.0; 6 * e.nodes.len()];
        for k in 0..unit.len() {
            unit[k] = 1.0;
            let strains = shell_strains(model, e, rec, &unit)?;
            unit[k] = 0.0;
            let eps: [f64; 3] = match surface {
                "TOP" => strains.top,
                "BOT" => strains.bottom,
                _ => std::array::from_fn(|i| 0.5 * (strains.top[i] + strains.bottom[i])),
            };
            let [x, y, _] = strains.axes;
            let (d1, d2) = (dot(d, x), dot(d, y));
            let h = d1 * d1 * eps[0] + d2 * d2 * eps[1] + d1 * d2 * eps[2];
            if h != 0.0 {
                row.push((6 * e.nodes[k / 6] + k % 6, h));
            }
        }
    } else if let Some(midsides) = model.solid_midsides(e) {
        if let Some(surf) = s.surface {
            return Err(bad(format!("SURF = {surf} applies to shells only")));
        }
        let weights = [
            d[0] * d[0],
            d[1] * d[1],
            d[2] * d[2],
            d[0] * d[1],
            d[1] * d[2],
            d[2] * d[0],
        ];
        let mut unit = vec![0.0; 3 * e.nodes.len()];
        for k in 0..unit.len() {
            unit[k] = 1.0;
            let eps = midsides
                .strain_at_centroid(&xyz, &unit)
                .map_err(|x| bad(x.to_string()))?;
            unit[k] = 0.0;
            let h: f64 = weights.iter().zip(&eps).map(|(w, e)| w * e).sum();
            if h != 0.0 {
                row.push((6 * e.nodes[k / 3] + k % 3, h));
            }
        }
    } else {
        return Err(bad(
            "STRAIN sensors need a shell (CQUAD4, CTRIA3, CQUADR, CTRIAR) or solid element".into(),
        ));
    }
    Ok(row)
}

/// The displacement rows of `grids` on the f-set (6 per grid, T1 T2 T3 R1 R2 R3 in basic, in
/// the order given): u_basic = R u_f, through the same CD-frame, g → n and f-set mapping as a
/// DISP sensor (a dependent RBE grid moves with its independent DOFs, a constrained one reads 0).
pub fn displacement_rows(st: &Structure, c: &Constrained, grids: &[usize]) -> CscMatrix<f64> {
    grid_rows(st, &c.sets.f_in_n, grids)
}

/// [`displacement_rows`] on the s-set (6·grids × n_s): what an enforced motion adds.
pub fn displacement_rows_s(st: &Structure, c: &Constrained, grids: &[usize]) -> CscMatrix<f64> {
    grid_rows(st, &c.sets.s_in_n, grids)
}

/// The basic displacement rows of `grids` restricted to `set` (positions in n).
fn grid_rows(st: &Structure, set: &DofSet, grids: &[usize]) -> CscMatrix<f64> {
    let mut coo = CooMatrix::new(6 * grids.len(), set.len());
    for (r, &grid) in grids.iter().enumerate() {
        for k in 0..6 {
            for (f, h) in set_row(st, set, &[(6 * grid + k, 1.0)]) {
                coo.push(6 * r + k, f, h);
            }
        }
    }
    CscMatrix::from(&coo)
}

/// A row over basic g-set DOFs → (index in `set`, value): Λᵀ per grid (CD frames), Tᵀ (g → n),
/// then the members of `set` (the f- or the s-set as positions in n).
fn set_row(st: &Structure, set: &DofSet, basic: &[(usize, f64)]) -> Vec<(usize, f64)> {
    let mut by_grid: BTreeMap<usize, [f64; 6]> = BTreeMap::new();
    for &(dof, h) in basic {
        by_grid.entry(dof / 6).or_default()[dof % 6] += h;
    }
    let mut n_row: BTreeMap<usize, f64> = BTreeMap::new();
    for (grid, v) in by_grid {
        let t = st.frames.to_global(grid, [v[0], v[1], v[2]]);
        let r = st.frames.to_global(grid, [v[3], v[4], v[5]]);
        for (k, h) in t.into_iter().chain(r).enumerate() {
            let row = st.rigid.t.row(6 * grid + k);
            for (&j, &tij) in row.col_indices().iter().zip(row.values()) {
                *n_row.entry(j).or_default() += h * tij;
            }
        }
    }
    n_row
        .into_iter()
        .filter(|(_, h)| *h != 0.0)
        .filter_map(|(j, h)| set.position(j).map(|f| (f, h)))
        .collect()
}
