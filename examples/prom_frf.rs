//! Online cost of a pROM FRF: the receptance between the pROM's inputs at the middle of its
//! parameter box over LINES frequency lines from 0 to FMAX Hz, by modal superposition over the
//! pROM's modes at p (`rayleigh_receptance`, what `SOL 111` with `ROM =` runs) and by one dense
//! complex LU per line (`receptance`), with the largest difference between the two.
//!
//!     cargo run --release --example prom_frf -- FILE.h5 [LINES] [FMAX] [REPEATS]
//!
//! Prints n_red, the inputs, and the mean seconds of each way (evaluation at p included).

use std::time::Instant;

use paraflex::dynamics::frf::{DenseModel, rayleigh_receptance, receptance};

fn main() -> std::process::ExitCode {
    let args: Vec<String> = std::env::args().collect();
    let Some(path) = args.get(1) else {
        eprintln!("usage: prom_frf FILE.h5 [LINES] [FMAX] [REPEATS]");
        return std::process::ExitCode::from(2);
    };
    let number = |i: usize, default: f64| args.get(i).map_or(Some(default), |s| s.parse().ok());
    let (Some(lines), Some(fmax), Some(repeats)) =
        (number(2, 200.0), number(3, 500.0), number(4, 50.0))
    else {
        eprintln!("LINES, FMAX and REPEATS must be numbers");
        return std::process::ExitCode::from(2);
    };
    let (lines, repeats) = (lines.max(1.0) as usize, repeats.max(1.0) as usize);
    let prom = match paraflex::io::read_prom(path) {
        Ok((prom, _)) => prom,
        Err(e) => {
            eprintln!("error: {e}");
            return std::process::ExitCode::from(2);
        }
    };
    let (names, s_r) = match paraflex::io::read_prom_inputs(path, prom.size()) {
        Ok(inputs) => inputs,
        Err(e) => {
            eprintln!("error: {e}");
            return std::process::ExitCode::from(2);
        }
    };
    let outputs = s_r.transpose().to_owned();
    let p: Vec<f64> = prom
        .parameters
        .iter()
        .map(|q| 0.5 * (q.low + q.high))
        .collect();
    let omegas: Vec<f64> = (1..=lines)
        .map(|l| 2.0 * std::f64::consts::PI * fmax * l as f64 / lines as f64)
        .collect();
    let mut at = prom.workspace();
    let modal = || {
        prom.evaluate(&p, &mut at).expect("evaluation");
        rayleigh_receptance(
            at.stiffness(),
            at.mass(),
            (prom.alpha, prom.beta),
            s_r.as_ref(),
            outputs.as_ref(),
            &omegas,
        )
        .expect("modal receptance")
    };
    let mut at = prom.workspace();
    let direct = || {
        prom.evaluate(&p, &mut at).expect("evaluation");
        let model = DenseModel {
            stiffness: at.stiffness(),
            mass: at.mass(),
            damping: at.damping(),
            structural: None,
        };
        receptance(&model, s_r.as_ref(), outputs.as_ref(), &omegas).expect("receptance")
    };
    let time = |mut f: Box<dyn FnMut() -> Vec<faer::Mat<faer::c64>> + '_>| {
        let first = f();
        let start = Instant::now();
        for _ in 0..repeats {
            f();
        }
        (first, start.elapsed().as_secs_f64() / repeats as f64)
    };
    let (h_modal, t_modal) = time(Box::new(modal));
    let (h_direct, t_direct) = time(Box::new(direct));
    let peak = h_direct
        .iter()
        .flat_map(|h| h.col_iter().flat_map(|c| c.iter().map(|z| z.norm())))
        .fold(0.0, f64::max);
    let difference = h_modal
        .iter()
        .zip(&h_direct)
        .flat_map(|(a, b)| {
            (0..a.nrows())
                .flat_map(move |i| (0..a.ncols()).map(move |j| (a[(i, j)] - b[(i, j)]).norm()))
        })
        .fold(0.0, f64::max);
    println!(
        "n_red {} inputs {} lines {lines} modal_seconds {t_modal:.3e} dense_lu_seconds {t_direct:.3e} max_difference_over_max_h {:.1e}",
        prom.size(),
        names.len(),
        difference / peak
    );
    std::process::ExitCode::SUCCESS
}
