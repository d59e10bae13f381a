//! The model's solution-control data by id: what case control selects (`METHOD`,
//! `FREQUENCY`, `TSTEP`, `IC`, `PROM`, `PVAL`, `ESTIM`, `MEAS`) and the model-wide ASET1 and
//! SENSOR lists, so that solution sequences never index the cards themselves.

use super::Model;
use crate::deck::cards::{
    Amanda, Aset1, Eigrl, Ekf, Ekfinp, Ekfpar, Freq, Meas, Measf, Pmor, Ptable, Pval, Randps,
    Randt1, Tabrnd, Tic, Tinteg, Tstep, Tstepvar,
};

impl Model {
    /// The EIGRL of `METHOD = sid`.
    pub fn eigrl(&self, sid: u32) -> Option<&Eigrl> {
        self.bulk.eigrl.iter().find(|e| e.sid == sid)
    }

    /// The TABDMP1 with id `id` (`SDAMPING = id`).
    pub fn tabdmp1(&self, id: u32) -> Option<&crate::deck::cards::Tabdmp1> {
        self.bulk.tabdmp1.iter().find(|t| t.id == id)
    }

    /// The frequency cards (FREQ, FREQ1–FREQ5) of `FREQUENCY = sid`, in card order.
    pub fn frequency_cards(&self, sid: u32) -> Vec<&Freq> {
        self.bulk.freq.iter().filter(|f| f.sid == sid).collect()
    }

    /// The RANDPS cards of `RANDOM = sid`, in card order.
    pub fn randps(&self, sid: u32) -> Vec<&Randps> {
        self.bulk.randps.iter().filter(|r| r.sid == sid).collect()
    }

    /// The RANDT1 of `RANDOM = sid` (the autocorrelation lags), if any.
    pub fn randt1(&self, sid: u32) -> Option<&Randt1> {
        self.bulk.randt1.iter().find(|r| r.sid == sid)
    }

    /// The TABRND1 or TABRNDG with id `id`.
    pub fn tabrnd(&self, id: u32) -> Option<&Tabrnd> {
        self.bulk.tabrnd.iter().find(|t| t.id == id)
    }

    /// The TSTEP of `TSTEP = sid`.
    pub fn tstep(&self, sid: u32) -> Option<&Tstep> {
        self.bulk.tstep.iter().find(|t| t.sid == sid)
    }

    /// The TINTEG with id `id` (the integrator of the TSTEP of the same id).
    pub fn tinteg(&self, id: u32) -> Option<&Tinteg> {
        self.bulk.tinteg.iter().find(|t| t.id == id)
    }

    /// The `TSTEPVAR` (step control) of TSTEP `id`, if any.
    pub fn tstepvar(&self, id: u32) -> Option<&Tstepvar> {
        self.bulk.tstepvar.iter().find(|t| t.id == id)
    }

    /// The TIC cards of `IC = sid`, in card order.
    pub fn tic(&self, sid: u32) -> Vec<&Tic> {
        self.bulk.tic.iter().filter(|t| t.sid == sid).collect()
    }

    /// The PMOR of `PROM = id`.
    pub fn pmor(&self, id: u32) -> Option<&Pmor> {
        self.bulk.pmor.iter().find(|p| p.id == id)
    }

    /// The PVAL of `PVAL = id`.
    pub fn pval(&self, id: u32) -> Option<&Pval> {
        self.bulk.pval.iter().find(|c| c.id == id)
    }

    /// The PTABLE cards of `PVAL = id`, in card order.
    pub fn ptables(&self, id: u32) -> Vec<&Ptable> {
        self.bulk.ptable.iter().filter(|c| c.id == id).collect()
    }

    /// Every ASET1 card (the a-set), in card order.
    pub fn aset1(&self) -> &[Aset1] {
        &self.bulk.aset1
    }

    /// The EKF of `ESTIM = id`.
    pub fn ekf(&self, id: u32) -> Option<&Ekf> {
        self.bulk.ekf.iter().find(|e| e.id == id)
    }

    /// The EKFPAR cards of EKF `id`, in card order.
    pub fn ekfpar(&self, id: u32) -> Vec<&Ekfpar> {
        self.bulk.ekfpar.iter().filter(|x| x.id == id).collect()
    }

    /// The EKFINP cards of EKF `id`, in card order.
    pub fn ekfinp(&self, id: u32) -> Vec<&Ekfinp> {
        self.bulk.ekfinp.iter().filter(|x| x.id == id).collect()
    }

    /// The AMANDA cards of EKF `id` (at most one is valid; the driver refuses more).
    pub fn amanda(&self, id: u32) -> Vec<&Amanda> {
        self.bulk.amanda.iter().filter(|a| a.id == id).collect()
    }

    /// The MEASF of `MEAS = id`.
    pub fn measf(&self, id: u32) -> Option<&Measf> {
        self.bulk.measf.iter().find(|m| m.id == id)
    }

    /// The MEAS channels of MEASF `id`, in card order.
    pub fn meas(&self, id: u32) -> Vec<&Meas> {
        self.bulk.meas.iter().filter(|m| m.id == id).collect()
    }
}
