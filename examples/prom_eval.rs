//! Online cost of a pROM: time `Prom::evaluate` (M_r, C_r, K_r and the
//! parameter derivatives, eq. 3.32) at random points of the box of an artifact.
//!
//!     cargo run --release --example prom_eval -- FILE.h5 [EVALUATIONS]
//!
//! Prints `n_red`, the number of affine components and the mean seconds per evaluation.

use std::time::Instant;

fn main() -> std::process::ExitCode {
    let args: Vec<String> = std::env::args().collect();
    let Some(path) = args.get(1) else {
        eprintln!("usage: prom_eval FILE.h5 [EVALUATIONS]");
        return std::process::ExitCode::from(2);
    };
    let count: usize = match args.get(2).map(|s| s.parse()) {
        None => 1000,
        Some(Ok(n)) if n > 0 => n,
        Some(_) => {
            eprintln!("EVALUATIONS must be a positive integer");
            return std::process::ExitCode::from(2);
        }
    };
    let prom = match paraflex::io::read_prom(path) {
        Ok((prom, _)) => prom,
        Err(e) => {
            eprintln!("error: {e}");
            return std::process::ExitCode::from(2);
        }
    };
    let mut at = prom.workspace();
    // a fixed linear congruential sequence: reproducible points in the box
    let mut state: u64 = 0x2545_f491_4f6c_dd1d;
    let mut uniform = || {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let points: Vec<Vec<f64>> = (0..count)
        .map(|_| {
            prom.parameters
                .iter()
                .map(|q| q.low + uniform() * (q.high - q.low))
                .collect()
        })
        .collect();
    let start = Instant::now();
    for p in &points {
        if let Err(e) = prom.evaluate(p, &mut at) {
            eprintln!("error: {e}");
            return std::process::ExitCode::from(4);
        }
    }
    let seconds = start.elapsed().as_secs_f64() / count as f64;
    println!(
        "n_red {} components {} evaluations {count} seconds_per_evaluation {seconds:.3e}",
        prom.size(),
        prom.functions.len()
    );
    std::process::ExitCode::SUCCESS
}
