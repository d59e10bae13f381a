//! Typed bulk-data cards: one struct per card, each with a `from_card` constructor that reads
//! its fields through a [`FieldReader`](super::reader::FieldReader) and reports every bad field.
//!
//! Field layouts, defaults and meanings follow the public Nastran Quick Reference for the
//! standard cards and `DESIGN.md` §3 for the extension cards; each struct's doc comment carries
//! its field table. Cards are dispatched by name through [`PARSERS`], the one table that says
//! which cards paraflex reads; a card not in it is reported as unsupported by name and line.

mod constraints;
mod design;
mod dynamic;
mod elements;
mod estimate;
mod extension;
mod geometry;
mod ignored;
mod line_elements;
mod line_properties;
mod loads;
mod materials;
mod multibody;
mod optimize;
mod param;
mod properties;
mod random;
mod rigid;
mod shear_panel;
mod superelement;
mod temperature;

pub use constraints::{Aset1, Mpc, MpcTerm, Mpcadd, SetUnion, Spc, Spc1, Spcadd, Suport};
pub use design::{Ddval, Desvar};
pub use dynamic::{
    Darea, Dload, EigenNorm, Eigrl, ExcitationKind, Freq, FreqKind, Lseq, ModalDampingUnits, Rload,
    RloadTables, RloadValue, Tabdmp1, Tabled, Tabled4, Tic, Tload, TloadFunction, Tstep,
    eigr_from_card,
};
pub use elements::{
    BushAxes, Cbush, Cdamp1, Cdamp2, Celas1, Celas2, Celas3, Celas4, Chexa, Cmass2, Conm2, Cpenta,
    Cpyram, Cquad4, Ctetra, Ctria3, Cvisc, OnCardLayout, QuadraticShell, Spoint,
};
pub use estimate::{Amanda, Ekf, Ekfinp, Ekfpar, Meas, Measf};
pub use extension::{
    Pmor, PmorRigid, PmorStatic, Pmpar, Ptable, Pval, Sensor, Tablef, Tinteg, TintegMethod,
    Tstepvar,
};
pub use geometry::{Cord2, CordKind, Grdset, Grid};
pub use ignored::ignored_card;
pub use line_elements::{BeamOrientation, Cbar, Cbend, Conrod, Crod, Offt};
pub use line_properties::{Pbar, Pbarl, Pbeam, Pbend, Prod, Ptube};
pub use loads::{
    Force, ForceByGrids, Grav, Load, Pload, Pload1, Pload1Scale, Pload2, Pload4, Pload4Target,
    Sload,
};
pub use materials::{Mat1, Mat2, Mat8};
pub use multibody::{Flexb, Fmbpose, Jdrive, Joint, Jsprd, Marker, Mforce, Msensor, Rigidb, Spdmp};
pub use optimize::{Dconstr, Dobj, Dvmap, Moopt, Promlib, ResponseSource, SearchMethod, Statistic};
pub use param::{Param, ParamValue};
pub use properties::{Pbush, Pcomp, Pdamp, Pelas, Ply, Pshell, Psolid, Pvisc};
pub use random::{Randps, Randt1, Tabrnd, TabrndKind};
pub use rigid::{Rbe2, Rbe3, Rbe3Group, Rsscon, RssconForm};
pub use shear_panel::{Cshear, Pshear};
pub use superelement::{DEFAULT_SE_TOL, Point, ReductionSet, SeMethod, Sebulk, Seconct, Seloc};
pub use temperature::{Matt1, Temp, Tempd};

use super::Loc;
use super::error::DeckError;
use super::fields::RawCard;
use crate::card_values::ForceKind;

/// Every bulk-data card of a deck, by kind, in input order.
#[derive(Debug, Default, Clone)]
pub struct BulkData {
    pub grids: Vec<Grid>,
    pub grdset: Vec<Grdset>,
    pub coords: Vec<Cord2>,
    pub cquad4: Vec<Cquad4>,
    pub ctria3: Vec<Ctria3>,
    /// CQUADR: the CQUAD4 layout and kernel (docs/departures.md).
    pub cquadr: Vec<Cquad4>,
    /// CTRIAR: the CTRIA3 layout and kernel (docs/departures.md).
    pub ctriar: Vec<Ctria3>,
    /// CQUAD8: eight-node curved shell.
    pub cquad8: Vec<QuadraticShell>,
    /// CTRIA6: six-node curved shell.
    pub ctria6: Vec<QuadraticShell>,
    pub cshear: Vec<Cshear>,
    pub chexa: Vec<Chexa>,
    pub cpenta: Vec<Cpenta>,
    pub ctetra: Vec<Ctetra>,
    pub cpyram: Vec<Cpyram>,
    pub celas1: Vec<Celas1>,
    pub celas2: Vec<Celas2>,
    pub celas3: Vec<Celas3>,
    pub celas4: Vec<Celas4>,
    pub cdamp1: Vec<Cdamp1>,
    pub cdamp2: Vec<Cdamp2>,
    pub cdamp3: Vec<Cdamp1>,
    pub cdamp4: Vec<Cdamp2>,
    pub cvisc: Vec<Cvisc>,
    pub cmass2: Vec<Cmass2>,
    pub cbush: Vec<Cbush>,
    pub spoints: Vec<Spoint>,
    pub conm2: Vec<Conm2>,
    pub crod: Vec<Crod>,
    pub ctube: Vec<Crod>,
    pub conrod: Vec<Conrod>,
    pub cbar: Vec<Cbar>,
    pub cbeam: Vec<Cbar>,
    pub cbend: Vec<Cbend>,
    pub rbe2: Vec<Rbe2>,
    pub rbe3: Vec<Rbe3>,
    pub rsscon: Vec<Rsscon>,
    pub mat1: Vec<Mat1>,
    pub mat8: Vec<Mat8>,
    pub mat2: Vec<Mat2>,
    pub matt1: Vec<Matt1>,
    pub temp: Vec<Temp>,
    pub tempd: Vec<Tempd>,
    /// TABLEM1, TABLEM2 and TABLEM3 (material tables, read by MATT1).
    pub tablem: Vec<Tabled>,
    /// TABLEM4.
    pub tablem4: Vec<Tabled4>,
    pub pshell: Vec<Pshell>,
    pub pcomp: Vec<Pcomp>,
    pub psolid: Vec<Psolid>,
    pub pshear: Vec<Pshear>,
    pub pelas: Vec<Pelas>,
    pub pdamp: Vec<Pdamp>,
    pub pvisc: Vec<Pvisc>,
    pub pbush: Vec<Pbush>,
    pub prod: Vec<Prod>,
    pub ptube: Vec<Ptube>,
    pub pbar: Vec<Pbar>,
    pub pbend: Vec<Pbend>,
    pub pbarl: Vec<Pbarl>,
    pub pbeam: Vec<Pbeam>,
    pub pbeaml: Vec<Pbarl>,
    pub spc: Vec<Spc>,
    /// SPCD cards (enforced displacements, a load set).
    pub spcd: Vec<Spc>,
    pub spc1: Vec<Spc1>,
    pub spcadd: Vec<Spcadd>,
    pub mpc: Vec<Mpc>,
    pub mpcadd: Vec<Mpcadd>,
    pub aset1: Vec<Aset1>,
    /// SUPORT and SUPORT1 cards.
    pub suport: Vec<Suport>,
    /// FORCE and MOMENT cards.
    pub forces: Vec<Force>,
    /// FORCE1, FORCE2, MOMENT1 and MOMENT2 cards.
    pub forces_by_grids: Vec<ForceByGrids>,
    pub sload: Vec<Sload>,
    pub grav: Vec<Grav>,
    pub pload4: Vec<Pload4>,
    pub pload2: Vec<Pload2>,
    pub pload: Vec<Pload>,
    pub pload1: Vec<Pload1>,
    pub load: Vec<Load>,
    pub eigrl: Vec<Eigrl>,
    /// FREQ and FREQ1–FREQ5 cards.
    pub freq: Vec<Freq>,
    pub tstep: Vec<Tstep>,
    /// TLOAD1 and TLOAD2.
    pub tload: Vec<Tload>,
    /// RLOAD1 and RLOAD2.
    pub rload: Vec<Rload>,
    pub darea: Vec<Darea>,
    pub lseq: Vec<Lseq>,
    pub tic: Vec<Tic>,
    pub ptable: Vec<Ptable>,
    /// TABLED1, TABLED2 and TABLED3.
    pub tabled: Vec<Tabled>,
    pub tabled4: Vec<Tabled4>,
    pub tabdmp1: Vec<Tabdmp1>,
    pub randps: Vec<Randps>,
    pub randt1: Vec<Randt1>,
    /// TABRND1 and TABRNDG cards.
    pub tabrnd: Vec<Tabrnd>,
    pub dload: Vec<Dload>,
    pub params: Vec<Param>,
    pub desvar: Vec<Desvar>,
    pub ddval: Vec<Ddval>,
    pub pmpar: Vec<Pmpar>,
    pub pmor: Vec<Pmor>,
    pub pval: Vec<Pval>,
    pub sensors: Vec<Sensor>,
    pub tablef: Vec<Tablef>,
    pub tinteg: Vec<Tinteg>,
    pub tstepvar: Vec<Tstepvar>,
    pub ekf: Vec<Ekf>,
    pub ekfpar: Vec<Ekfpar>,
    pub ekfinp: Vec<Ekfinp>,
    pub measf: Vec<Measf>,
    pub meas: Vec<Meas>,
    pub amanda: Vec<Amanda>,
    pub flexb: Vec<Flexb>,
    pub rigidb: Vec<Rigidb>,
    pub markers: Vec<Marker>,
    pub joints: Vec<Joint>,
    pub jdrive: Vec<Jdrive>,
    pub jsprd: Vec<Jsprd>,
    pub spdmp: Vec<Spdmp>,
    pub mforce: Vec<Mforce>,
    pub msensors: Vec<Msensor>,
    pub fmbpose: Vec<Fmbpose>,
    pub dvmap: Vec<Dvmap>,
    pub promlib: Vec<Promlib>,
    pub dobj: Vec<Dobj>,
    pub dconstr: Vec<Dconstr>,
    pub moopt: Vec<Moopt>,
    pub sebulk: Vec<Sebulk>,
    pub seconct: Vec<Seconct>,
    pub seloc: Vec<Seloc>,
    /// POINT cards (geometry for SELOC).
    pub points: Vec<Point>,
    /// ASET, QSET and QSET1 cards (read, not honoured: paraflex does not reduce).
    pub reduction_sets: Vec<ReductionSet>,
}

impl BulkData {
    /// The set ids of the static load cards a `LOAD` or `LOAD = sid` may select: FORCE, MOMENT,
    /// FORCE1, FORCE2, MOMENT1, MOMENT2, SLOAD, GRAV, PLOAD4, PLOAD2, PLOAD, PLOAD1, SPCD (with
    /// repeats).
    pub fn static_load_sets(&self) -> impl Iterator<Item = u32> + '_ {
        (self.forces.iter().map(|c| c.sid))
            .chain(self.forces_by_grids.iter().map(|c| c.sid))
            .chain(self.sload.iter().map(|c| c.sid))
            .chain(self.grav.iter().map(|c| c.sid))
            .chain(self.pload4.iter().map(|c| c.sid))
            .chain(self.pload2.iter().map(|c| c.sid))
            .chain(self.pload.iter().map(|c| c.sid))
            .chain(self.pload1.iter().map(|c| c.sid))
            .chain(self.spcd.iter().map(|c| c.sid))
    }

    /// (id, card name, where) of every table a dynamic load, a parameter or a mechanism's
    /// drive or force may name: TABLED1–TABLED4 and TABLEF.
    pub fn dynamic_tables(&self) -> impl Iterator<Item = (u32, &'static str, &Loc)> + '_ {
        (self.tabled.iter().map(|t| (t.id, t.card, &t.loc)))
            .chain(self.tabled4.iter().map(|t| (t.id, "TABLED4", &t.loc)))
            .chain(self.tablef.iter().map(|t| (t.id, "TABLEF", &t.loc)))
    }
}

/// A card constructor that stores its result in [`BulkData`].
pub type CardParser = fn(&RawCard, &mut BulkData) -> Result<(), Vec<DeckError>>;

/// Name → parser table of every supported bulk-data card.
#[allow(clippy::unit_arg)] // one line per card: `Ok(push(parsed?))` stores the card and returns Ok(())
pub static PARSERS: &[(&str, CardParser)] = &[
    ("GRID", |c, b| Ok(b.grids.push(Grid::from_card(c)?))),
    ("GRDSET", |c, b| Ok(b.grdset.push(Grdset::from_card(c)?))),
    ("CORD2R", |c, b| {
        Ok(b.coords.push(Cord2::from_card(c, CordKind::Rectangular)?))
    }),
    ("CORD2C", |c, b| {
        Ok(b.coords.push(Cord2::from_card(c, CordKind::Cylindrical)?))
    }),
    ("CORD2S", |c, b| {
        Ok(b.coords.push(Cord2::from_card(c, CordKind::Spherical)?))
    }),
    ("CQUAD4", |c, b| Ok(b.cquad4.push(Cquad4::from_card(c)?))),
    ("CTRIA3", |c, b| Ok(b.ctria3.push(Ctria3::from_card(c)?))),
    ("CQUADR", |c, b| Ok(b.cquadr.push(Cquad4::from_card(c)?))),
    ("CTRIAR", |c, b| Ok(b.ctriar.push(Ctria3::from_card(c)?))),
    ("CQUAD8", |c, b| {
        Ok(b.cquad8.push(QuadraticShell::cquad8(c)?))
    }),
    ("CTRIA6", |c, b| {
        Ok(b.ctria6.push(QuadraticShell::ctria6(c)?))
    }),
    ("CSHEAR", |c, b| Ok(b.cshear.push(Cshear::from_card(c)?))),
    ("CHEXA", |c, b| Ok(b.chexa.push(Chexa::from_card(c)?))),
    ("CPENTA", |c, b| Ok(b.cpenta.push(Cpenta::from_card(c)?))),
    ("CTETRA", |c, b| Ok(b.ctetra.push(Ctetra::from_card(c)?))),
    ("CPYRAM", |c, b| Ok(b.cpyram.push(Cpyram::from_card(c)?))),
    ("CELAS1", |c, b| Ok(b.celas1.push(Celas1::from_card(c)?))),
    ("CELAS2", |c, b| Ok(b.celas2.push(Celas2::from_card(c)?))),
    ("CELAS3", |c, b| {
        Ok(b.celas3.push(Celas3::from_scalar_card(c)?))
    }),
    ("CELAS4", |c, b| {
        Ok(b.celas4.push(Celas4::read(c, OnCardLayout::Celas4)?))
    }),
    ("CDAMP1", |c, b| Ok(b.cdamp1.push(Cdamp1::from_card(c)?))),
    ("CDAMP2", |c, b| {
        Ok(b.cdamp2.push(Cdamp2::read(c, OnCardLayout::Cdamp2)?))
    }),
    ("CDAMP3", |c, b| {
        Ok(b.cdamp3.push(Cdamp1::from_scalar_card(c)?))
    }),
    ("CDAMP4", |c, b| {
        Ok(b.cdamp4.push(Cdamp2::read(c, OnCardLayout::Cdamp4)?))
    }),
    ("CVISC", |c, b| Ok(b.cvisc.push(Cvisc::from_card(c)?))),
    ("CMASS2", |c, b| {
        Ok(b.cmass2.push(Cmass2::read(c, OnCardLayout::Cmass2)?))
    }),
    ("CBUSH", |c, b| Ok(b.cbush.push(Cbush::from_card(c)?))),
    ("SPOINT", |c, b| Ok(b.spoints.push(Spoint::from_card(c)?))),
    ("SELOC", |c, b| Ok(b.seloc.push(Seloc::from_card(c)?))),
    ("POINT", |c, b| Ok(b.points.push(Point::from_card(c)?))),
    ("SEBULK", |c, b| Ok(b.sebulk.push(Sebulk::from_card(c)?))),
    ("SECONCT", |c, b| Ok(b.seconct.push(Seconct::from_card(c)?))),
    ("ASET", |c, b| {
        Ok(b.reduction_sets.push(ReductionSet::pairs(c)?))
    }),
    ("QSET", |c, b| {
        Ok(b.reduction_sets.push(ReductionSet::pairs(c)?))
    }),
    ("QSET1", |c, b| {
        Ok(b.reduction_sets.push(ReductionSet::list(c)?))
    }),
    ("CONM2", |c, b| Ok(b.conm2.push(Conm2::from_card(c)?))),
    ("CROD", |c, b| Ok(b.crod.push(Crod::from_card(c)?))),
    ("CTUBE", |c, b| Ok(b.ctube.push(Crod::from_card(c)?))),
    ("CONROD", |c, b| Ok(b.conrod.push(Conrod::from_card(c)?))),
    ("CBAR", |c, b| Ok(b.cbar.push(Cbar::from_card(c, false)?))),
    ("CBEAM", |c, b| Ok(b.cbeam.push(Cbar::from_card(c, true)?))),
    ("CBEND", |c, b| Ok(b.cbend.push(Cbend::from_card(c)?))),
    ("RBE2", |c, b| Ok(b.rbe2.push(Rbe2::from_card(c)?))),
    ("RBE3", |c, b| Ok(b.rbe3.push(Rbe3::from_card(c)?))),
    ("RSSCON", |c, b| Ok(b.rsscon.push(Rsscon::from_card(c)?))),
    ("MAT1", |c, b| Ok(b.mat1.push(Mat1::from_card(c)?))),
    ("MAT8", |c, b| Ok(b.mat8.push(Mat8::from_card(c)?))),
    ("MAT2", |c, b| Ok(b.mat2.push(Mat2::from_card(c)?))),
    ("MATT1", |c, b| Ok(b.matt1.push(Matt1::from_card(c)?))),
    ("TEMP", |c, b| Ok(b.temp.push(Temp::from_card(c)?))),
    ("TEMPD", |c, b| Ok(b.tempd.extend(Tempd::from_card(c)?))),
    ("TABLEM1", |c, b| {
        Ok(b.tablem.push(Tabled::from_card(c, "TABLEM1")?))
    }),
    ("TABLEM2", |c, b| {
        Ok(b.tablem.push(Tabled::from_card(c, "TABLEM2")?))
    }),
    ("TABLEM3", |c, b| {
        Ok(b.tablem.push(Tabled::from_card(c, "TABLEM3")?))
    }),
    ("TABLEM4", |c, b| Ok(b.tablem4.push(Tabled4::from_card(c)?))),
    ("PSHELL", |c, b| Ok(b.pshell.push(Pshell::from_card(c)?))),
    ("PCOMP", |c, b| Ok(b.pcomp.push(Pcomp::from_card(c)?))),
    ("PCOMPG", |c, b| Ok(b.pcomp.push(Pcomp::from_pcompg(c)?))),
    ("PSOLID", |c, b| Ok(b.psolid.push(Psolid::from_card(c)?))),
    ("PCOMPS", |c, b| Ok(b.psolid.push(properties::pcomps(c)?))),
    ("PSHEAR", |c, b| Ok(b.pshear.push(Pshear::from_card(c)?))),
    ("PELAS", |c, b| Ok(b.pelas.extend(Pelas::from_card(c)?))),
    ("PDAMP", |c, b| Ok(b.pdamp.extend(Pdamp::from_card(c)?))),
    ("PVISC", |c, b| Ok(b.pvisc.extend(Pvisc::from_card(c)?))),
    ("PBUSH", |c, b| Ok(b.pbush.push(Pbush::from_card(c)?))),
    ("PROD", |c, b| Ok(b.prod.push(Prod::from_card(c)?))),
    ("PTUBE", |c, b| Ok(b.ptube.push(Ptube::from_card(c)?))),
    ("PBAR", |c, b| Ok(b.pbar.push(Pbar::from_card(c)?))),
    ("PBEND", |c, b| Ok(b.pbend.push(Pbend::from_card(c)?))),
    ("PBARL", |c, b| {
        Ok(b.pbarl.push(Pbarl::from_card(c, false)?))
    }),
    ("PBEAM", |c, b| Ok(b.pbeam.push(Pbeam::from_card(c)?))),
    ("PBEAML", |c, b| {
        Ok(b.pbeaml.push(Pbarl::from_card(c, true)?))
    }),
    ("SPC", |c, b| Ok(b.spc.extend(Spc::from_card(c)?))),
    ("SPCD", |c, b| Ok(b.spcd.extend(Spc::from_card(c)?))),
    ("SPC1", |c, b| Ok(b.spc1.push(Spc1::from_card(c)?))),
    ("SPCADD", |c, b| Ok(b.spcadd.push(Spcadd::from_card(c)?))),
    ("MPC", |c, b| Ok(b.mpc.push(Mpc::from_card(c)?))),
    ("MPCADD", |c, b| Ok(b.mpcadd.push(Mpcadd::from_card(c)?))),
    ("ASET1", |c, b| Ok(b.aset1.push(Aset1::from_card(c)?))),
    ("SUPORT", |c, b| {
        Ok(b.suport.push(Suport::from_card(c, false)?))
    }),
    ("SUPORT1", |c, b| {
        Ok(b.suport.push(Suport::from_card(c, true)?))
    }),
    ("FORCE", |c, b| {
        Ok(b.forces.push(Force::from_card(c, ForceKind::Force)?))
    }),
    ("MOMENT", |c, b| {
        Ok(b.forces.push(Force::from_card(c, ForceKind::Moment)?))
    }),
    ("FORCE1", |c, b| {
        let card = ForceByGrids::from_card(c, ForceKind::Force, false)?;
        Ok(b.forces_by_grids.push(card))
    }),
    ("FORCE2", |c, b| {
        let card = ForceByGrids::from_card(c, ForceKind::Force, true)?;
        Ok(b.forces_by_grids.push(card))
    }),
    ("MOMENT1", |c, b| {
        let card = ForceByGrids::from_card(c, ForceKind::Moment, false)?;
        Ok(b.forces_by_grids.push(card))
    }),
    ("MOMENT2", |c, b| {
        let card = ForceByGrids::from_card(c, ForceKind::Moment, true)?;
        Ok(b.forces_by_grids.push(card))
    }),
    ("SLOAD", |c, b| Ok(b.sload.push(Sload::from_card(c)?))),
    ("GRAV", |c, b| Ok(b.grav.push(Grav::from_card(c)?))),
    ("PLOAD4", |c, b| Ok(b.pload4.push(Pload4::from_card(c)?))),
    ("PLOAD2", |c, b| Ok(b.pload2.push(Pload2::from_card(c)?))),
    ("PLOAD", |c, b| Ok(b.pload.push(Pload::from_card(c)?))),
    ("PLOAD1", |c, b| Ok(b.pload1.push(Pload1::from_card(c)?))),
    ("LOAD", |c, b| Ok(b.load.push(Load::from_card(c)?))),
    ("EIGRL", |c, b| Ok(b.eigrl.push(Eigrl::from_card(c)?))),
    ("EIGR", |c, b| Ok(b.eigrl.push(eigr_from_card(c)?))),
    ("FREQ", |c, b| Ok(b.freq.push(Freq::from_card(c, "FREQ")?))),
    ("FREQ1", |c, b| {
        Ok(b.freq.push(Freq::from_card(c, "FREQ1")?))
    }),
    ("FREQ2", |c, b| {
        Ok(b.freq.push(Freq::from_card(c, "FREQ2")?))
    }),
    ("FREQ3", |c, b| {
        Ok(b.freq.push(Freq::from_card(c, "FREQ3")?))
    }),
    ("FREQ4", |c, b| {
        Ok(b.freq.push(Freq::from_card(c, "FREQ4")?))
    }),
    ("FREQ5", |c, b| {
        Ok(b.freq.push(Freq::from_card(c, "FREQ5")?))
    }),
    ("TSTEP", |c, b| Ok(b.tstep.push(Tstep::from_card(c)?))),
    ("TLOAD1", |c, b| Ok(b.tload.push(Tload::tload1(c)?))),
    ("TLOAD2", |c, b| Ok(b.tload.push(Tload::tload2(c)?))),
    ("RLOAD1", |c, b| Ok(b.rload.push(Rload::rload1(c)?))),
    ("RLOAD2", |c, b| Ok(b.rload.push(Rload::rload2(c)?))),
    ("DAREA", |c, b| Ok(b.darea.extend(Darea::from_card(c)?))),
    ("LSEQ", |c, b| Ok(b.lseq.push(Lseq::from_card(c)?))),
    ("TIC", |c, b| Ok(b.tic.push(Tic::from_card(c)?))),
    ("PTABLE", |c, b| Ok(b.ptable.push(Ptable::from_card(c)?))),
    ("TABDMP1", |c, b| Ok(b.tabdmp1.push(Tabdmp1::from_card(c)?))),
    ("RANDPS", |c, b| Ok(b.randps.push(Randps::from_card(c)?))),
    ("RANDT1", |c, b| Ok(b.randt1.push(Randt1::from_card(c)?))),
    ("TABRND1", |c, b| Ok(b.tabrnd.push(Tabrnd::tabrnd1(c)?))),
    ("TABRNDG", |c, b| Ok(b.tabrnd.push(Tabrnd::tabrndg(c)?))),
    ("TABLED1", |c, b| {
        Ok(b.tabled.push(Tabled::from_card(c, "TABLED1")?))
    }),
    ("TABLED2", |c, b| {
        Ok(b.tabled.push(Tabled::from_card(c, "TABLED2")?))
    }),
    ("TABLED3", |c, b| {
        Ok(b.tabled.push(Tabled::from_card(c, "TABLED3")?))
    }),
    ("TABLED4", |c, b| Ok(b.tabled4.push(Tabled4::from_card(c)?))),
    ("DLOAD", |c, b| Ok(b.dload.push(Dload::from_card(c)?))),
    ("PARAM", |c, b| Ok(b.params.push(Param::from_card(c)?))),
    ("DESVAR", |c, b| Ok(b.desvar.push(Desvar::from_card(c)?))),
    ("DDVAL", |c, b| Ok(b.ddval.push(Ddval::from_card(c)?))),
    ("PMPAR", |c, b| Ok(b.pmpar.push(Pmpar::from_card(c)?))),
    ("PMOR", |c, b| Ok(b.pmor.push(Pmor::from_card(c)?))),
    ("PVAL", |c, b| Ok(b.pval.push(Pval::from_card(c)?))),
    ("SENSOR", |c, b| Ok(b.sensors.push(Sensor::from_card(c)?))),
    ("TABLEF", |c, b| Ok(b.tablef.push(Tablef::from_card(c)?))),
    ("TINTEG", |c, b| Ok(b.tinteg.push(Tinteg::from_card(c)?))),
    ("TSTEPVAR", |c, b| {
        Ok(b.tstepvar.push(Tstepvar::from_card(c)?))
    }),
    ("EKF", |c, b| Ok(b.ekf.push(Ekf::from_card(c)?))),
    ("EKFPAR", |c, b| Ok(b.ekfpar.push(Ekfpar::from_card(c)?))),
    ("EKFINP", |c, b| Ok(b.ekfinp.push(Ekfinp::from_card(c)?))),
    ("MEASF", |c, b| Ok(b.measf.push(Measf::from_card(c)?))),
    ("MEAS", |c, b| Ok(b.meas.push(Meas::from_card(c)?))),
    ("AMANDA", |c, b| Ok(b.amanda.push(Amanda::from_card(c)?))),
    ("FLEXB", |c, b| Ok(b.flexb.push(Flexb::from_card(c)?))),
    ("RIGIDB", |c, b| Ok(b.rigidb.push(Rigidb::from_card(c)?))),
    ("MARKER", |c, b| Ok(b.markers.push(Marker::from_card(c)?))),
    ("JOINT", |c, b| Ok(b.joints.push(Joint::from_card(c)?))),
    ("JDRIVE", |c, b| Ok(b.jdrive.push(Jdrive::from_card(c)?))),
    ("FMBPOSE", |c, b| Ok(b.fmbpose.push(Fmbpose::from_card(c)?))),
    ("JSPRD", |c, b| Ok(b.jsprd.push(Jsprd::from_card(c)?))),
    ("SPDMP", |c, b| Ok(b.spdmp.push(Spdmp::from_card(c)?))),
    ("MFORCE", |c, b| {
        Ok(b.mforce.push(Mforce::from_card(c, ForceKind::Force)?))
    }),
    ("MMOMENT", |c, b| {
        Ok(b.mforce.push(Mforce::from_card(c, ForceKind::Moment)?))
    }),
    ("MSENSOR", |c, b| {
        Ok(b.msensors.push(Msensor::from_card(c)?))
    }),
    ("DVMAP", |c, b| Ok(b.dvmap.push(Dvmap::from_card(c)?))),
    ("PROMLIB", |c, b| Ok(b.promlib.push(Promlib::from_card(c)?))),
    ("DOBJ", |c, b| Ok(b.dobj.push(Dobj::from_card(c)?))),
    ("DCONSTR", |c, b| Ok(b.dconstr.push(Dconstr::from_card(c)?))),
    ("MOOPT", |c, b| Ok(b.moopt.push(Moopt::from_card(c)?))),
];

/// The parser for a card name (upper case), if paraflex supports the card.
pub fn parser_for(name: &str) -> Option<CardParser> {
    PARSERS.iter().find(|(n, _)| *n == name).map(|(_, p)| *p)
}

/// The error for a card paraflex does not read: its name, the supported card closest to it
/// when it looks like a misspelling (`did you mean CQUAD4?`) and, when `list_supported` (the
/// first such card of a deck), every card paraflex reads.
pub fn unsupported_card(card: &RawCard, list_supported: bool) -> DeckError {
    let names = PARSERS.iter().map(|(n, _)| *n);
    let mut message = format!("unsupported bulk data card '{}'", card.name);
    if let Some(near) = crate::deck::suggest::closest(&card.name, names.clone()) {
        message.push_str(&format!(" (did you mean {near}?)"));
    }
    if list_supported {
        message.push_str(&format!(
            ": paraflex reads {}",
            names.collect::<Vec<_>>().join(" ")
        ));
    }
    DeckError::at(&card.loc, message)
}
