//! Resource use per phase of a run, for the console report: wall time, the process's CPU
//! time (user + system of all its threads, `getrusage(RUSAGE_SELF)`; on a machine shared with
//! other work wall ≫ CPU, and with rayon threads CPU > wall), and the resident memory at the
//! end of the phase and its peak since the process started (`VmRSS` and `VmHWM` of
//! `/proc/self/status`). The memory figures are Linux only: elsewhere they are `None` and the
//! report leaves them blank; CPU time needs a Unix `getrusage`.
//!
//! `VmHWM` is monotone, so a phase that raised it is the one that set the peak so far: the
//! report marks it. (Resetting the high-water mark per phase through `/proc/self/clear_refs`
//! would also reset what `/usr/bin/time` reports for the whole run, so it is not done.)

use std::sync::Mutex;
use std::time::{Duration, Instant};

use crate::linalg::Progress;

/// A reading of the process's resources at one instant.
#[derive(Clone, Copy, Debug)]
pub struct Usage {
    wall: Instant,
    cpu: Duration,
}

impl Usage {
    /// The process's wall clock and CPU time now.
    pub fn now() -> Self {
        Usage {
            wall: Instant::now(),
            cpu: process_cpu_time(),
        }
    }

    /// The phase `name` from this reading to now, with the memory read now.
    pub fn phase(&self, name: impl Into<String>) -> Phase {
        let memory = Memory::read();
        Phase {
            name: name.into(),
            wall: self.wall.elapsed(),
            cpu: process_cpu_time().saturating_sub(self.cpu),
            rss: memory.map(|m| m.rss),
            peak: memory.map(|m| m.peak),
        }
    }
}

/// One phase's resources (memory in bytes).
#[derive(Clone, Debug, PartialEq)]
pub struct Phase {
    pub name: String,
    pub wall: Duration,
    /// CPU time of the whole process (all threads) during the phase.
    pub cpu: Duration,
    /// Resident memory at the end of the phase (`VmRSS`), Linux only.
    pub rss: Option<u64>,
    /// Peak resident memory of the process up to the end of the phase (`VmHWM`), Linux only.
    pub peak: Option<u64>,
}

/// The phases as console lines: a header, then one line per phase (wall s, CPU s, resident MB at
/// the end, peak MB so far, `*` where the phase raised the peak by a printed MB or more).
pub fn render(phases: &[Phase]) -> Vec<String> {
    let megabytes = |b: u64| (b as f64 / 1e6).round() as u64;
    let mb = |b: Option<u64>| b.map_or("-".to_string(), |b| megabytes(b).to_string());
    let mut out = vec![
        "resources per phase (CPU: all threads, getrusage; memory: VmRSS / VmHWM of /proc/self/status, Linux only; * = the phase raised the peak):"
            .to_string(),
    ];
    out.push(format!(
        "  {:<42} {:>9} {:>9} {:>9} {:>9}",
        "phase", "wall s", "CPU s", "RSS MB", "peak MB"
    ));
    let mut peak_before = 0;
    for p in phases {
        let peak = p.peak.map_or(0, megabytes);
        let raised = peak > peak_before;
        peak_before = peak_before.max(peak);
        out.push(format!(
            "  {:<42} {:>9.3} {:>9.3} {:>9} {:>9}{}",
            p.name,
            p.wall.as_secs_f64(),
            p.cpu.as_secs_f64(),
            mb(p.rss),
            mb(p.peak),
            if raised { " *" } else { "" }
        ));
    }
    out
}

/// A [`Progress`] that forwards every event to `inner` and splits the work it watches into
/// sub-phases, one per run of events with the same name (the eigensolver's "factor K − σM",
/// "Lanczos", "Sturm check", …), each with its resources.
pub struct PhaseSplitter<'a> {
    inner: &'a dyn Progress,
    state: Mutex<Split>,
}

#[derive(Default)]
struct Split {
    current: Option<(String, Usage)>,
    done: Vec<Phase>,
}

impl<'a> PhaseSplitter<'a> {
    /// A splitter forwarding to `inner`.
    pub fn new(inner: &'a dyn Progress) -> Self {
        PhaseSplitter {
            inner,
            state: Mutex::new(Split::default()),
        }
    }

    /// The sub-phases seen, the last one ending now.
    pub fn finish(self) -> Vec<Phase> {
        let mut split = self.state.into_inner().unwrap_or_else(|e| e.into_inner());
        if let Some((name, start)) = split.current.take() {
            split.done.push(start.phase(name));
        }
        split.done
    }
}

impl Progress for PhaseSplitter<'_> {
    fn step(&self, what: &str, done: usize, total: usize) {
        self.inner.step(what, done, total);
        let mut split = self.state.lock().unwrap_or_else(|e| e.into_inner());
        if split.current.as_ref().is_some_and(|(name, _)| name == what) {
            return;
        }
        if let Some((name, start)) = split.current.take() {
            split.done.push(start.phase(name));
        }
        split.current = Some((what.to_string(), Usage::now()));
    }
}

/// Resident memory now and at its peak (bytes).
#[derive(Clone, Copy, Debug)]
struct Memory {
    rss: u64,
    peak: u64,
}

impl Memory {
    /// `VmRSS` and `VmHWM` of `/proc/self/status` (kB there); `None` where that file does not
    /// exist or lacks them.
    fn read() -> Option<Self> {
        let status = std::fs::read_to_string("/proc/self/status").ok()?;
        let field = |key: &str| {
            status
                .lines()
                .find_map(|l| l.strip_prefix(key))
                .and_then(|rest| {
                    rest.trim()
                        .trim_end_matches("kB")
                        .trim()
                        .parse::<u64>()
                        .ok()
                })
                .map(|kb| kb * 1024)
        };
        Some(Memory {
            rss: field("VmRSS:")?,
            peak: field("VmHWM:")?,
        })
    }
}

/// User + system CPU time of the process (all threads) so far; zero where `getrusage` is not
/// available.
fn process_cpu_time() -> Duration {
    #[cfg(unix)]
    {
        let mut usage = std::mem::MaybeUninit::<libc::rusage>::zeroed();
        // SAFETY: getrusage writes a `rusage` into the pointer it is given, which points to
        // a zero-initialized value of that type.
        let ok = unsafe { libc::getrusage(libc::RUSAGE_SELF, usage.as_mut_ptr()) } == 0;
        if ok {
            // SAFETY: getrusage succeeded and filled the value (it was zeroed before).
            let u = unsafe { usage.assume_init() };
            let t = |tv: libc::timeval| {
                Duration::from_secs(tv.tv_sec.max(0) as u64)
                    + Duration::from_micros(tv.tv_usec.max(0) as u64)
            };
            return t(u.ru_utime) + t(u.ru_stime);
        }
        Duration::ZERO
    }
    #[cfg(not(unix))]
    {
        Duration::ZERO
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A phase that allocates and touches 64 MB: CPU time advances with the work, and on Linux
    /// the peak covers the block while it is alive.
    #[test]
    fn a_phase_sees_its_cpu_time_and_memory() {
        let start = Usage::now();
        let block: Vec<u8> = (0..64 << 20).map(|i| (i % 251) as u8).collect();
        let sum: u64 = block.iter().map(|&b| u64::from(b)).sum();
        let phase = start.phase("allocate");
        assert!(sum > 0);
        if cfg!(unix) {
            assert!(phase.cpu > Duration::ZERO, "{phase:?}");
        }
        assert!(phase.wall > Duration::ZERO);
        if cfg!(target_os = "linux") {
            let (rss, peak) = (phase.rss.expect("VmRSS"), phase.peak.expect("VmHWM"));
            assert!(rss >= 64 << 20, "{phase:?}");
            assert!(peak >= rss, "{phase:?}");
        }
        drop(block);
        let lines = render(std::slice::from_ref(&phase));
        assert_eq!(lines.len(), 3);
        assert!(
            lines[2].contains("allocate") && lines[2].ends_with(" *"),
            "{lines:?}"
        );
    }

    /// The splitter opens a sub-phase at each new event name and closes the last at `finish`.
    #[test]
    fn the_splitter_cuts_at_each_new_event_name() {
        let events = Mutex::new(Vec::new());
        let inner = |what: &str, done: usize, _: usize| {
            events.lock().unwrap().push(format!("{what} {done}"));
        };
        let split = PhaseSplitter::new(&inner);
        for (what, done) in [("factor", 0), ("factor", 1), ("lanczos", 0), ("lanczos", 3)] {
            split.step(what, done, 3);
        }
        split.step("sturm", 0, 1);
        let names: Vec<String> = split.finish().into_iter().map(|p| p.name).collect();
        assert_eq!(names, ["factor", "lanczos", "sturm"]);
        assert_eq!(events.lock().unwrap().len(), 5, "every event forwarded");
    }
}
