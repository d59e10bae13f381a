//! Helpers shared by the solution-sequence integration tests.

use std::io::Write;

use paraflex::deck::Deck;
use paraflex::io::OutputFile;
use paraflex::model::Model;
use paraflex::sequence::{RunContext, RunError, RunOptions, RunSummary, run};

/// Run a deck text through deck → model → sequence with an HDF5 file in a temp directory.
pub fn run_deck(text: &str) -> (Result<RunSummary, RunError>, tempfile::TempDir) {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("deck.dat");
    std::fs::File::create(&path).and_then(|mut f| f.write_all(text.as_bytes())).expect("write deck");
    let deck = Deck::read(&path).unwrap_or_else(|e| panic!("deck: {e}"));
    let model = Model::build(&deck).unwrap_or_else(|e| panic!("model: {:?}", e.iter().map(|x| x.to_string()).collect::<Vec<_>>()));
    let file = OutputFile::create(dir.path().join("out.h5")).expect("output");
    let ctx = RunContext { deck: &deck, model: &model, output: &file, progress: &|_: &str, _: usize, _: usize| {}, options: RunOptions { parallel: false } };
    let result = run(&ctx);
    if result.is_ok() {
        file.commit().expect("commit");
    }
    (result, dir)
}
