//! Dynamic loads as the solver reads them:
//! - [`Model::dynamic_load_members`]: `DLOAD = sid` as (factor S · Sᵢ, load set Lᵢ) pairs, or
//!   the one set `sid` with factor 1 when no DLOAD combination has that id;
//! - [`Model::transient_loads`] / [`Model::harmonic_loads`]: the TLOAD1/TLOAD2 / RLOAD1/RLOAD2
//!   cards of a load set, each with the DAREA entries of its EXCITEID expanded per component
//!   ([`Excitation`]);
//! - [`Model::dynamic_table`]: a TABLED1–TABLED3's points, a TABLED4's power series, or a
//!   TABLEF's CSV file (path resolved relative to the file holding the card) and columns.

use std::path::PathBuf;

use crate::deck::Loc;
use crate::deck::cards::{ExcitationKind, RloadTables, TloadFunction};

use super::Model;
use crate::card_values::Column;
use crate::dynamics::table::PowerSeries;

/// One component of a DAREA entry: a unit load direction scaled by A.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Excitation {
    /// The DAREA set id.
    pub sid: u32,
    /// Grid id (a pROM input names it without a mesh).
    pub grid: u32,
    /// Component 1–6 in the grid's displacement frame.
    pub component: usize,
    /// A.
    pub scale: f64,
}

/// A TLOAD1 (excitation × table(t − τ)) or TLOAD2 (excitation × pulse(t − τ)).
#[derive(Debug, Clone, PartialEq)]
pub struct TransientLoad {
    pub sid: u32,
    pub excite_id: u32,
    /// The DAREA entries of EXCITEID (empty when EXCITEID names a static load set).
    pub excitation: Vec<Excitation>,
    /// τ (s).
    pub delay: f64,
    /// TYPE: an applied load or enforced motion.
    pub kind: ExcitationKind,
    /// The table (TLOAD1) or the pulse (TLOAD2).
    pub function: TloadFunction,
}

/// An RLOAD1 (excitation × (C(f) + iD(f)) · e^{i(θ − 2πfτ)}) or RLOAD2 (B(f) e^{iφ(f)} in
/// place of C + iD).
#[derive(Debug, Clone, PartialEq)]
pub struct HarmonicLoad {
    pub sid: u32,
    pub excite_id: u32,
    /// The DAREA entries of EXCITEID.
    pub excitation: Vec<Excitation>,
    /// τ (s).
    pub delay: f64,
    /// θ (degrees).
    pub phase_deg: f64,
    /// Table ids of P(f).
    pub tables: RloadTables,
    /// TYPE: an applied load, or the enforced motion of EXCITEID's SPCD DOFs.
    pub kind: ExcitationKind,
}

/// Where a table's (x, y) points come from.
#[derive(Debug, Clone, PartialEq)]
pub enum TableData {
    /// TABLED1–TABLED3: the points on the card, abscissae mapped to x.
    Points(Vec<(f64, f64)>),
    /// TABLED4.
    PowerSeries(PowerSeries),
    /// TABLEF: two columns of a CSV file.
    Csv { path: PathBuf, x: Column, y: Column },
}

/// A TABLED1–TABLED4 or TABLEF.
#[derive(Debug, Clone, PartialEq)]
pub struct DynamicTable {
    /// Card name.
    pub card: &'static str,
    pub data: TableData,
    pub loc: Loc,
}

impl Model {
    /// (factor, load set) of each member of `DLOAD = sid` (see the module documentation).
    pub fn dynamic_load_members(&self, sid: u32) -> Vec<(f64, u32)> {
        match self.bulk.dload.iter().find(|d| d.sid == sid) {
            Some(d) => d.terms.iter().map(|&(s, l)| (d.scale * s, l)).collect(),
            None => vec![(1.0, sid)],
        }
    }

    /// The TLOAD1 and TLOAD2 cards of load set `sid`, in card order.
    pub fn transient_loads(&self, sid: u32) -> Vec<TransientLoad> {
        self.bulk
            .tload
            .iter()
            .filter(|t| t.sid == sid)
            .map(|t| TransientLoad {
                sid: t.sid,
                excite_id: t.excite_id,
                excitation: self.excitation(t.excite_id),
                delay: t.delay,
                kind: t.kind,
                function: t.function.clone(),
            })
            .collect()
    }

    /// The RLOAD1 and RLOAD2 cards of load set `sid`, in card order.
    pub fn harmonic_loads(&self, sid: u32) -> Vec<HarmonicLoad> {
        self.bulk
            .rload
            .iter()
            .filter(|r| r.sid == sid)
            .map(|r| HarmonicLoad {
                sid: r.sid,
                excite_id: r.excite_id,
                excitation: self.excitation(r.excite_id),
                delay: r.delay,
                phase_deg: r.phase_deg,
                tables: r.tables,
                kind: r.kind,
            })
            .collect()
    }

    /// The static load set a dynamic load's EXCITEID selects: the LID of the LSEQ of set
    /// `loadset` (case control `LOADSET`) with that EXCITEID, or the EXCITEID itself.
    pub fn excited_static_set(&self, excite_id: u32, loadset: Option<u32>) -> u32 {
        (self.bulk.lseq.iter())
            .find(|l| Some(l.sid) == loadset && l.excite_id == excite_id)
            .map_or(excite_id, |l| l.lid)
    }

    /// The DAREA entries of set `sid`, one per component, in card order.
    fn excitation(&self, sid: u32) -> Vec<Excitation> {
        self.bulk
            .darea
            .iter()
            .filter(|d| d.sid == sid)
            .flat_map(|d| {
                d.components.components().map(move |component| Excitation {
                    sid: d.sid,
                    grid: d.grid,
                    component,
                    scale: d.scale,
                })
            })
            .collect()
    }

    /// The TABLED1–TABLED3, TABLED4 or TABLEF with id `tid`, first in that order.
    pub fn dynamic_table(&self, tid: u32) -> Option<DynamicTable> {
        let b = &self.bulk;
        if let Some(x) = b.tabled.iter().find(|x| x.id == tid) {
            return Some(DynamicTable {
                card: x.card,
                data: TableData::Points(x.points.clone()),
                loc: x.loc.clone(),
            });
        }
        if let Some(x) = b.tabled4.iter().find(|x| x.id == tid) {
            return Some(DynamicTable {
                card: "TABLED4",
                data: TableData::PowerSeries(PowerSeries {
                    shift: x.shift,
                    scale: x.scale,
                    range: x.range,
                    coefficients: x.coefficients.clone(),
                }),
                loc: x.loc.clone(),
            });
        }
        b.tablef.iter().find(|x| x.id == tid).map(|x| DynamicTable {
            card: "TABLEF",
            data: TableData::Csv {
                path: x
                    .loc
                    .file
                    .parent()
                    .map_or_else(|| PathBuf::from(&x.path), |dir| dir.join(&x.path)),
                x: x.tcol.clone(),
                y: x.ycol.clone(),
            },
            loc: x.loc.clone(),
        })
    }
}
