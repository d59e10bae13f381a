//! Fuzz target: `Deck::read` must never panic, whatever the bytes (DESIGN.md §3).
//!
//! The reader's public entry point takes a path, so each input is written to a file in a
//! private temporary directory and read from there. INCLUDE statements in the input resolve
//! relative to that directory (an input that includes its own file name exercises the cycle
//! check). Inputs that name device or process files (`/dev/`, `/proc/`) are skipped: an
//! `INCLUDE '/dev/zero'` would read forever, which is not a reader bug.

#![no_main]

use std::path::PathBuf;
use std::sync::OnceLock;

use libfuzzer_sys::fuzz_target;
use paraflex::deck::Deck;

/// One directory per fuzzing process; removed by the OS's tmp cleaning, not by us.
fn deck_path() -> &'static PathBuf {
    static PATH: OnceLock<PathBuf> = OnceLock::new();
    PATH.get_or_init(|| {
        let dir = std::env::temp_dir().join(format!("paraflex-fuzz-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("create the fuzz directory");
        dir.join("deck.bdf")
    })
}

fn names_special_files(data: &[u8]) -> bool {
    let lower = data.to_ascii_lowercase();
    lower.windows(5).any(|w| w == b"/dev/" || w == b"/proc")
}

fuzz_target!(|data: &[u8]| {
    if names_special_files(data) {
        return;
    }
    let path = deck_path();
    std::fs::write(path, data).expect("write the fuzz input");
    // Ok or Err are both fine; only a panic (or a hang / OOM) is a finding.
    let _ = Deck::read(path);
});
