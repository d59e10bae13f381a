//! The `paraflex` command: check a deck, run it, describe an output file.
//!
//! This binary owns the command line (clap), the rendering of errors for humans and the exit
//! codes; all work is done by the library.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::{Parser, Subcommand};
use paraflex::deck::{Deck, Warning};

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

fn read_deck(path: &Path) -> Result<Deck, Failure> {
    Deck::read(path).map_err(|errors| {
        eprintln!("{errors}");
        Failure(2)
    })
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
        let deck = read_deck(path)?;
        print_warnings(&deck.warnings);
        if json {
            let summary = serde_json::json!({ "cards": deck.bulk.grids.len() });
            println!("{summary}");
        } else {
            println!("{}: read {} grids", path.display(), deck.bulk.grids.len());
        }
        Ok(())
    }

    pub fn run(path: &Path, _output: Option<&Path>) -> Result<(), Failure> {
        let deck = read_deck(path)?;
        print_warnings(&deck.warnings);
        match &deck.executive.sol {
            Some((sol, text)) => {
                eprintln!("error: SOL {text} ({}) is not available in this version of paraflex", sol.name());
            }
            None => eprintln!("error: the deck has no SOL statement; nothing to run"),
        }
        Err(Failure(3))
    }

    pub fn info(file: &Path, _json: bool) -> Result<(), Failure> {
        eprintln!("error: cannot describe '{}': HDF5 support is not built yet", file.display());
        Err(Failure(2))
    }
}
