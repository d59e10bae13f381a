//! The `paraflex` command: check a deck, run it, describe an output file.
//!
//! This binary owns the command line (clap), the rendering of errors for humans and the exit
//! codes; all work is done by the library.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::{Parser, Subcommand};
use paraflex::deck::{Deck, DeckErrors, Warning};
use paraflex::model::{CheckSummary, Model};

#[derive(Parser)]
#[command(name = "paraflex", version, about = "Parametric structural and flexible-multibody dynamics from Nastran decks")]
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

fn print_warnings(warnings: &[Warning]) {
    for w in warnings {
        eprintln!("warning: {w}");
    }
}

/// Read and validate a deck; on failure print every error (exit code 2).
fn load_model(path: &Path) -> Result<(Deck, Model), Failure> {
    let report = |errors: DeckErrors| {
        eprintln!("{errors}");
        Failure(2)
    };
    let deck = Deck::read(path).map_err(report)?;
    let model = Model::build(&deck).map_err(|errors| report(DeckErrors { errors }))?;
    Ok((deck, model))
}

/// The human-readable form of `paraflex check`.
fn print_summary(path: &Path, s: &CheckSummary) {
    println!("{}", path.display());
    println!("  solution     {}", s.sol.unwrap_or("(none)"));
    println!("  grids        {} ({} DOFs)", s.grids, s.dofs);
    let list = |m: &std::collections::BTreeMap<&str, usize>| {
        m.iter().filter(|(_, n)| **n > 0).map(|(k, n)| format!("{k} {n}")).collect::<Vec<_>>().join(", ")
    };
    println!("  elements     {}", list(&s.elements));
    println!("  rigid        {}", list(&s.rigid));
    println!("  properties   {}", list(&s.properties));
    println!("  materials    {}", list(&s.materials));
    println!("  mass         {:.6e} (WTMASS {})", s.mass, s.wtmass);
    println!("  cg           [{:.6e}, {:.6e}, {:.6e}]", s.cg[0], s.cg[1], s.cg[2]);
    println!("  inertia (cg) [{:.6e}, {:.6e}, {:.6e}]", s.inertia_cg[0][0], s.inertia_cg[0][1], s.inertia_cg[0][2]);
    println!("               [{:.6e}, {:.6e}, {:.6e}]", s.inertia_cg[1][0], s.inertia_cg[1][1], s.inertia_cg[1][2]);
    println!("               [{:.6e}, {:.6e}, {:.6e}]", s.inertia_cg[2][0], s.inertia_cg[2][1], s.inertia_cg[2][2]);
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Check { deck, json } => commands::check(&deck, json),
        Command::Run { deck, output } => commands::run(&deck, output.as_deref()),
        Command::Info { file, json } => commands::info(&file, json),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(Failure(code)) => ExitCode::from(code),
    }
}

mod commands {
    use super::*;

    pub fn check(path: &Path, json: bool) -> Result<(), Failure> {
        let (_, model) = load_model(path)?;
        let summary = model.summary();
        if json {
            println!("{}", serde_json::to_string(&summary).unwrap_or_default());
        } else {
            print_warnings(&model.warnings);
            print_summary(path, &summary);
        }
        Ok(())
    }

    /// Write `/model` (and the XDMF file next to it) for a validated model.
    fn write_model_file(deck: &Deck, model: &Model, out: &Path) -> Result<PathBuf, paraflex::io::IoError> {
        let mesh = model.mesh_arrays();
        let info = paraflex::io::ModelInfo {
            title: deck.case.subcases().first().and_then(|s| s.title.clone()),
            deck: Some(deck.path.display().to_string()),
            sol: deck.executive.sol.as_ref().map(|(sol, _)| sol.name().to_string()),
        };
        let file = paraflex::io::OutputFile::create(out)?;
        paraflex::io::write_model(&file, &mesh, &info)?;
        let written = file.commit()?;
        let xdmf = paraflex::io::write_xdmf(&written, &mesh)?;
        for skipped in &xdmf.skipped {
            eprintln!("warning: not drawn in the XDMF file: {skipped}");
        }
        Ok(written)
    }

    pub fn run(path: &Path, output: Option<&Path>) -> Result<(), Failure> {
        let (deck, model) = load_model(path)?;
        print_warnings(&model.warnings);
        let out = output.map(Path::to_path_buf).unwrap_or_else(|| path.with_extension("h5"));
        match write_model_file(&deck, &model, &out) {
            Ok(written) => eprintln!("wrote the model to {}", written.display()),
            Err(e) => {
                eprintln!("error: {e}");
                return Err(Failure(2));
            }
        }
        match &deck.executive.sol {
            Some((sol, text)) => {
                eprintln!("error: SOL {text} ({}) is not available in this version of paraflex", sol.name());
            }
            None => eprintln!("error: the deck has no SOL statement; nothing to run"),
        }
        Err(Failure(3))
    }

    pub fn info(file: &Path, json: bool) -> Result<(), Failure> {
        let summary = paraflex::io::describe(file).map_err(|e| {
            eprintln!("error: {e}");
            Failure(2)
        })?;
        if json {
            println!("{}", serde_json::to_string_pretty(&summary).unwrap_or_default());
        } else {
            print!("{summary}");
        }
        Ok(())
    }
}
