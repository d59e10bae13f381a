//! Progress reporting. The library never prints; long operations call [`Progress::step`] and
//! the binary renders it (indicatif). Any `Fn(&str, usize, usize) + Sync` closure is a
//! `Progress`, so `&|_, _, _| {}` silences it.

/// Receives progress events: `what` names the phase, `done` of `total` units are complete.
pub trait Progress: Sync {
    /// Reports that `done` of `total` units of phase `what` are complete.
    fn step(&self, what: &str, done: usize, total: usize);
}

impl<F: Fn(&str, usize, usize) + Sync> Progress for F {
    fn step(&self, what: &str, done: usize, total: usize) {
        self(what, done, total)
    }
}
