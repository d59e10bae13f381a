//! The `paraflex` command: check a deck, run it, describe an output file.
//!
//! This binary owns the command line (clap), the rendering of errors for humans and the exit
//! codes; all work is done by the library.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::{Parser, Subcommand};
use paraflex::deck::{Deck, DeckErrors, Warning};
use paraflex::discretize::BuildOptions;
use paraflex::model::{CheckSummary, Model};
use paraflex::sequence::{self, RunContext};
use std::time::Instant;

#[derive(Parser)]
#[command(
    name = "paraflex",
    version,
    about = "Parametric structural and flexible-multibody dynamics from Nastran decks"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Read and validate a deck and print a model summary (grids, elements, mass properties).
    Check {
        /// The input deck.
        deck: PathBuf,
        /// Print one JSON object instead of text.
        #[arg(long)]
        json: bool,
    },
    /// Validate a deck, run its solution sequence and write the results to HDF5 (+ XDMF).
    Run {
        /// The input deck.
        deck: PathBuf,
        /// Output file (default: the deck name with .h5).
        #[arg(short, long)]
        output: Option<PathBuf>,
        /// SOL OPTIMIZE: evaluate the study's designs with this command (run by `sh -c`)
        /// instead of NPAR threads here, e.g. the Dask driver
        /// `.venv/bin/python -m paraflex_tools.dask_engine --scheduler tcp://host:8786`
        /// (docs/optimize.md, "Evaluation engines").
        #[arg(long, value_name = "COMMAND")]
        engine: Option<String>,
    },
    /// Affine components of stiffness and mass matrices sampled by another FE code (Matrix
    /// Market files listed in a CSV manifest with the affine function values, or one HDF5 file
    /// with /functions, /values, /K/<h>, /M/<h>), by least squares.
    PromLsq {
        /// The samples: a CSV manifest (header `K, M, <function names>`, one row per sample) or
        /// an HDF5 file.
        manifest: PathBuf,
        /// Output file (default: the input's name with .h5, or with _lsq.h5 for an HDF5 input).
        #[arg(short, long)]
        output: Option<PathBuf>,
    },
    /// Evaluate designs of a SOL OPTIMIZE deck's study, nothing written: one JSON line per
    /// design on stdout (design, responses or error, seconds), as the study's journal holds
    /// them. The design evaluation as a pure function, for an engine outside this process.
    Evaluate {
        /// The SOL OPTIMIZE deck.
        deck: PathBuf,
        /// A JSON file holding the designs: an array of arrays of the variables' values.
        #[arg(long)]
        designs: PathBuf,
        /// The subcase whose study evaluates them.
        #[arg(long, default_value_t = 1)]
        subcase: u32,
        /// Also the gradients of the responses with respect to the continuous variables
        /// (forward sensitivities): each line gets `gradient`, one row per response, one
        /// column per variable (null for a discrete one), and `sensitivity_iterations` (over
        /// every step and variable); the designs run one after the other.
        #[arg(long)]
        gradient: bool,
    },
    /// Describe a paraflex HDF5 file.
    Info {
        /// The HDF5 file.
        file: PathBuf,
        /// Print JSON instead of text.
        #[arg(long)]
        json: bool,
    },
}

/// A failure already explained to the user; the exit code says what kind.
struct Failure(u8);

/// `println!` for a command-line tool: when stdout is closed early (piped into `head`), stop
/// quietly with success instead of panicking. Reports are printed after the output file is
/// committed, so nothing is left half-written.
macro_rules! println {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        if let Err(e) = writeln!(std::io::stdout(), $($arg)*) {
            if e.kind() == std::io::ErrorKind::BrokenPipe {
                std::process::exit(0);
            }
        }
    }};
}

fn print_warnings(warnings: &[Warning]) {
    for w in warnings {
        eprintln!("warning: {w}");
    }
}

/// Read and validate a deck: every error of the first stage that has any.
fn read_model(path: &Path) -> Result<(Deck, Model), DeckErrors> {
    let deck = Deck::read(path)?;
    let model = Model::build(&deck).map_err(|errors| DeckErrors { errors })?;
    Ok((deck, model))
}

/// Read and validate a deck; on failure print every error (exit code 2).
fn load_model(path: &Path) -> Result<(Deck, Model), Failure> {
    read_model(path).map_err(|errors| {
        eprintln!("{errors}");
        Failure(2)
    })
}

/// The errors of an invalid deck as `paraflex check --json` prints them: `{"errors": [{"file",
/// "line", "card", "field", "message", "text"}, …]}`, `text` being the line printed on stderr.
fn errors_json(errors: &DeckErrors) -> serde_json::Value {
    let list: Vec<serde_json::Value> = errors
        .errors
        .iter()
        .map(|e| {
            serde_json::json!({
                "file": e.loc.file.display().to_string(),
                "line": e.loc.line,
                "card": e.card,
                "field": e.field,
                "message": e.message,
                "text": e.to_string(),
            })
        })
        .collect();
    serde_json::json!({ "errors": list })
}

/// The human-readable form of `paraflex check`.
fn print_summary(path: &Path, s: &CheckSummary) {
    println!("{}", path.display());
    println!("  solution     {}", s.sol.unwrap_or("(none)"));
    println!("  grids        {} ({} DOFs)", s.grids, s.dofs);
    let list = |m: &std::collections::BTreeMap<&str, usize>| {
        m.iter()
            .filter(|(_, n)| **n > 0)
            .map(|(k, n)| format!("{k} {n}"))
            .collect::<Vec<_>>()
            .join(", ")
    };
    println!("  elements     {}", list(&s.elements));
    println!("  rigid        {}", list(&s.rigid));
    println!("  properties   {}", list(&s.properties));
    println!("  materials    {}", list(&s.materials));
    println!("  mass         {:.6e} (WTMASS {})", s.mass, s.wtmass);
    println!(
        "  cg           [{:.6e}, {:.6e}, {:.6e}]",
        s.cg[0], s.cg[1], s.cg[2]
    );
    println!(
        "  inertia (cg) [{:.6e}, {:.6e}, {:.6e}]",
        s.inertia_cg[0][0], s.inertia_cg[0][1], s.inertia_cg[0][2]
    );
    println!(
        "               [{:.6e}, {:.6e}, {:.6e}]",
        s.inertia_cg[1][0], s.inertia_cg[1][1], s.inertia_cg[1][2]
    );
    println!(
        "               [{:.6e}, {:.6e}, {:.6e}]",
        s.inertia_cg[2][0], s.inertia_cg[2][1], s.inertia_cg[2][2]
    );
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    allocator::tune();
    interrupt::install();
    let result = match cli.command {
        Command::Check { deck, json } => commands::check(&deck, json),
        Command::Run {
            deck,
            output,
            engine,
        } => commands::run(&deck, output.as_deref(), engine.as_deref()),
        Command::Info { file, json } => commands::info(&file, json),
        Command::Evaluate {
            deck,
            designs,
            subcase,
            gradient,
        } => commands::evaluate(&deck, &designs, subcase, gradient),
        Command::PromLsq { manifest, output } => commands::prom_lsq(&manifest, output.as_deref()),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(Failure(code)) => ExitCode::from(code),
    }
}

mod commands {
    use super::*;

    pub fn check(path: &Path, json: bool) -> Result<(), Failure> {
        let (deck, model) = if json {
            read_model(path).map_err(|errors| {
                eprintln!("{errors}");
                println!("{}", errors_json(&errors));
                Failure(2)
            })?
        } else {
            load_model(path)?
        };
        let summary = model.summary();
        if json {
            println!("{}", serde_json::to_string(&summary).unwrap_or_default());
        } else {
            print_warnings(&model.warnings);
            print_warnings(&sequence::request_warnings(&deck, &model));
            print_summary(path, &summary);
        }
        Ok(())
    }

    pub fn run(path: &Path, output: Option<&Path>, engine: Option<&str>) -> Result<(), Failure> {
        let read_start = paraflex::sequence::usage::Usage::now();
        let (deck, model) = load_model(path)?;
        let read = read_start.phase("read and validate the deck");
        print_warnings(&model.warnings);
        print_warnings(&sequence::request_warnings(&deck, &model));
        let optimize = deck.executive.sol.as_ref().map(|(s, _)| *s)
            == Some(paraflex::deck::Solution::Optimize);
        if engine.is_some() && !optimize {
            eprintln!("warning: --engine is ignored: only SOL OPTIMIZE evaluates designs");
        }
        let out = output
            .map(Path::to_path_buf)
            .unwrap_or_else(|| path.with_extension("h5"));
        if let Err(reason) = sequence::runnable(&deck, &model) {
            eprintln!("error: {reason}");
            return Err(Failure(run_failure_code(&reason)));
        }
        let io_failure = |e: paraflex::io::IoError| {
            eprintln!("error: {e}");
            Failure(2)
        };
        let start = Instant::now();
        let mesh = model.mesh_arrays();
        interrupt::remove_on_signal(&out);
        interrupt::remove_on_signal(&paraflex::io::xdmf_path_for(&out));
        let file = paraflex::io::OutputFile::create(&out).map_err(io_failure)?;
        paraflex::io::write_model(&file, &mesh, &model_info(&deck)).map_err(io_failure)?;
        let bars = progress::Bars::new();
        let ctx = RunContext {
            deck: &deck,
            model: &model,
            output: &file,
            progress: &bars,
            options: BuildOptions::default(),
            engine,
        };
        let result = sequence::run(&ctx);
        bars.finish();
        let mut summary = result.map_err(|e| {
            eprintln!("error: {e}");
            Failure(run_failure_code(&e))
        })?;
        summary.phases.insert(0, read);
        let written = file.commit().map_err(io_failure)?;
        let xdmf = paraflex::io::write_xdmf(&written, &mesh).map_err(io_failure)?;
        for skipped in &xdmf.skipped {
            eprintln!("warning: not drawn in the XDMF file: {skipped}");
        }
        for w in &summary.warnings {
            eprintln!("warning: {w}");
        }
        for line in summary.render(path, start.elapsed()) {
            println!("{line}");
        }
        eprintln!("wrote {}", written.display());
        Ok(())
    }

    pub fn evaluate(
        path: &Path,
        designs: &Path,
        subcase: u32,
        gradient: bool,
    ) -> Result<(), Failure> {
        let (deck, model) = load_model(path)?;
        let fail = |message: String| {
            eprintln!("error: {message}");
            Failure(2)
        };
        if deck.executive.sol.as_ref().map(|(s, _)| *s) != Some(paraflex::deck::Solution::Optimize)
        {
            return Err(fail(format!(
                "{}: paraflex evaluate takes a SOL OPTIMIZE deck",
                path.display()
            )));
        }
        let text = std::fs::read_to_string(designs)
            .map_err(|e| fail(format!("cannot read {}: {e}", designs.display())))?;
        let designs: Vec<Vec<f64>> = serde_json::from_str(&text).map_err(|e| {
            fail(format!(
                "{}: expected an array of designs (arrays of numbers): {e}",
                designs.display()
            ))
        })?;
        // the preparation reads the deck's model only: the output it is given is a scratch
        // file, removed unwritten
        let scratch =
            std::env::temp_dir().join(format!("paraflex-evaluate-{}.h5", std::process::id()));
        let file = paraflex::io::OutputFile::create(&scratch).map_err(|e| fail(e.to_string()))?;
        let bars = progress::Bars::new();
        let ctx = RunContext {
            deck: &deck,
            model: &model,
            output: &file,
            progress: &bars,
            options: BuildOptions::default(),
            engine: None,
        };
        let stopped = |e: sequence::RunError| {
            eprintln!("error: {e}");
            Failure(run_failure_code(&e))
        };
        if gradient {
            let gradients = sequence::optimize::gradients_of_designs(&ctx, subcase, &designs)
                .map_err(stopped)?;
            for (design, g) in designs.iter().zip(gradients) {
                let line = match g {
                    Ok(g) => serde_json::json!({
                        "design": design,
                        "responses": g.responses,
                        "gradient": g.gradient,
                        "sensitivity_iterations": g.iterations,
                    }),
                    Err(e) => serde_json::json!({ "design": design, "error": e }),
                };
                println!("{line}");
            }
            return Ok(());
        }
        let evaluated =
            sequence::optimize::evaluate_designs(&ctx, subcase, &designs).map_err(stopped)?;
        for (design, e) in designs.iter().zip(&evaluated) {
            let line = sequence::optimize_journal::entry_line(design, e).map_err(fail)?;
            println!("{line}");
        }
        Ok(())
    }

    /// The exit code of a run that stopped: 3 for a deck asking for what this version cannot
    /// do (no SOL, a SOL without a driver), 4 for a solution that failed.
    fn run_failure_code(e: &sequence::RunError) -> u8 {
        match e {
            sequence::RunError::NotAvailable(_) | sequence::RunError::NoSolution => 3,
            _ => 4,
        }
    }

    fn model_info(deck: &Deck) -> paraflex::io::ModelInfo {
        paraflex::io::ModelInfo {
            title: deck.case.subcases().first().and_then(|s| s.title.clone()),
            deck: Some(deck.path.display().to_string()),
            sol: deck
                .executive
                .sol
                .as_ref()
                .map(|(sol, _)| sol.name().to_string()),
        }
    }

    pub fn prom_lsq(manifest: &Path, output: Option<&Path>) -> Result<(), Failure> {
        let fail = |e: &dyn std::fmt::Display| {
            eprintln!("error: {e}");
            Failure(2)
        };
        let (m, fit) = paraflex::io::prom_lsq::fit_samples(manifest).map_err(|e| fail(&e))?;
        let built =
            paraflex::io::prom_lsq::build_samples(manifest, &m, &fit).map_err(|e| fail(&e))?;
        let default = match manifest.with_extension("h5") {
            same if same == manifest => manifest.with_file_name(format!(
                "{}_lsq.h5",
                manifest.file_stem().unwrap_or_default().to_string_lossy()
            )),
            other => other,
        };
        let out = output.map(Path::to_path_buf).unwrap_or(default);
        interrupt::remove_on_signal(&out);
        let written = (|| -> Result<PathBuf, paraflex::io::IoError> {
            let file = paraflex::io::OutputFile::create(&out)?;
            paraflex::io::prom_lsq::write_lsq(&file.group("lsq")?, &m.functions, &fit)?;
            if let Some(built) = &built {
                paraflex::io::prom_lsq::write_black_box(&file, &m, built)?;
            }
            file.commit()
        })()
        .map_err(|e| fail(&e))?;
        println!(
            "{}: {} samples, functions {}",
            manifest.display(),
            m.values.len(),
            m.functions.join(", ")
        );
        println!(
            "  n {}, nnz {}",
            fit.stiffness[0].nrows(),
            fit.stiffness[0].nnz()
        );
        println!(
            "  max relative residual  K {:.1e}  M {:.1e}",
            fit.residual_stiffness, fit.residual_mass
        );
        if let Some(b) = &built {
            println!(
                "  pROM: {} local columns, {} after the MAC filter, n_red {}, {} inputs, {} strain sensors",
                b.concatenated,
                b.kept,
                b.prom.size(),
                b.inputs.ncols(),
                b.strains.nrows()
            );
        }
        eprintln!("wrote {}", written.display());
        Ok(())
    }

    pub fn info(file: &Path, json: bool) -> Result<(), Failure> {
        let summary = paraflex::io::describe(file).map_err(|e| {
            eprintln!("error: {e}");
            Failure(2)
        })?;
        if json {
            println!(
                "{}",
                serde_json::to_string_pretty(&summary).unwrap_or_default()
            );
        } else {
            print!("{summary}");
        }
        Ok(())
    }
}

/// glibc's allocator settings for a solver's allocation pattern.
///
/// By default glibc serves a block above its mmap threshold (128 KiB at start, raised to the size
/// of each freed mapped block up to 32 MiB) with a fresh mapping and trims the heap's free top
/// above twice that threshold, so the dense blocks a time-stepping solver allocates and frees at
/// every step (a 175 × 350 right-hand side is 490 KiB) are mapped, zero-filled page by page and
/// unmapped again, often in the worker threads' arenas whose thresholds never adapt. Fixed
/// settings keep blocks up to 4 MiB on the heap and return a free top above 64 MiB to the
/// system: the four-bar AMANDA-EKF's system time fell from 0.46–1.03 s to 0.15–0.37 s of
/// ≈ 3 s (docs/performance.md, "Allocator"), while blocks above 4 MiB — the large models'
/// matrices and factors — are still mapped and released at once, so the peak memory of large
/// runs is unchanged. Only where the C library is glibc.
mod allocator {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    pub fn tune() {
        // SAFETY: mallopt only changes allocator parameters; it is called before any other
        // thread exists, and a refused setting (return 0) leaves glibc's default in place.
        unsafe {
            libc::mallopt(libc::M_MMAP_THRESHOLD, 4 << 20);
            libc::mallopt(libc::M_TRIM_THRESHOLD, 64 << 20);
        }
    }

    #[cfg(not(all(target_os = "linux", target_env = "gnu")))]
    pub fn tune() {}
}

/// An interrupted run (Ctrl-C, SIGTERM) leaves no temporary output file: a thread waits for
/// SIGINT and SIGTERM, removes the `<out>.tmp-<pid>` files of the outputs being written and
/// exits with 128 + the signal number (130, 143), the status a shell reports for a process the
/// signal ended.
mod interrupt {
    use std::path::{Path, PathBuf};
    use std::sync::Mutex;

    use signal_hook::consts::{SIGINT, SIGTERM};
    use signal_hook::iterator::Signals;

    /// The final paths this run writes (each under its temporary name until committed).
    static OUTPUTS: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

    /// Start the waiting thread. Should the handler not install, an interrupt only keeps its
    /// default effect (the temporary files stay), which is no reason to refuse the command.
    pub fn install() {
        let Ok(mut signals) = Signals::new([SIGINT, SIGTERM]) else {
            return;
        };
        std::thread::spawn(move || {
            if let Some(signal) = signals.forever().next() {
                if let Ok(outputs) = OUTPUTS.lock() {
                    for out in outputs.iter() {
                        let _ = std::fs::remove_file(paraflex::io::temp_path_for(out));
                    }
                }
                std::process::exit(128 + signal);
            }
        });
    }

    /// Remove the temporary file of `out` if the run is interrupted.
    pub fn remove_on_signal(out: &Path) {
        if let Ok(mut outputs) = OUTPUTS.lock() {
            outputs.push(out.to_path_buf());
        }
    }
}

/// indicatif progress bars behind the library's `Progress` trait (only on a terminal).
mod progress {
    use std::io::IsTerminal;
    use std::sync::Mutex;

    use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
    use paraflex::linalg::Progress;

    pub struct Bars {
        enabled: bool,
        current: Mutex<Option<(String, ProgressBar)>>,
    }

    impl Bars {
        pub fn new() -> Self {
            Bars {
                enabled: std::io::stderr().is_terminal(),
                current: Mutex::new(None),
            }
        }

        pub fn finish(&self) {
            if let Ok(mut cur) = self.current.lock()
                && let Some((_, bar)) = cur.take()
            {
                bar.finish_and_clear();
            }
        }
    }

    impl Progress for Bars {
        fn step(&self, what: &str, done: usize, total: usize) {
            if !self.enabled {
                return;
            }
            let Ok(mut cur) = self.current.lock() else {
                return;
            };
            let same = cur.as_ref().is_some_and(|(name, _)| name == what);
            if !same {
                if let Some((_, bar)) = cur.take() {
                    bar.finish_and_clear();
                }
                let bar =
                    ProgressBar::with_draw_target(Some(total as u64), ProgressDrawTarget::stderr());
                let style =
                    ProgressStyle::with_template("{msg:32} [{bar:30}] {pos}/{len} {elapsed}")
                        .unwrap_or_else(|_| ProgressStyle::default_bar());
                bar.set_style(style.progress_chars("=> "));
                bar.set_message(what.to_string());
                *cur = Some((what.to_string(), bar));
            }
            if let Some((_, bar)) = cur.as_ref() {
                bar.set_length(total as u64);
                bar.set_position(done as u64);
            }
        }
    }
}
