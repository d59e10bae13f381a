//! Helpers shared by the solution-sequence integration tests.

use std::io::Write;
use std::path::Path;

use paraflex::deck::Deck;
use paraflex::io::OutputFile;
use paraflex::model::Model;
use paraflex::sequence::{RunContext, RunError, RunOptions, RunSummary, run};

/// The parameters and the affine g-set operators K and M of a bulk-data section (elements,
/// assembly on one pattern; no constraints), as `SOL PROM` assembles them.
#[allow(dead_code)]
pub fn affine_operators(bulk: &str) -> (paraflex::sequence::parameters::Parameters, paraflex::assembly::AffineOperator, paraflex::assembly::AffineOperator) {
    use paraflex::assembly::{AffineOperator, DofMap, GridFrames};
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("deck.dat");
    let text = format!("SOL 103\nCEND\nBEGIN BULK\n{bulk}ENDDATA\n");
    std::fs::File::create(&path).and_then(|mut f| f.write_all(text.as_bytes())).unwrap();
    let deck = Deck::read(&path).unwrap_or_else(|e| panic!("{e}"));
    let model = Model::build(&deck).unwrap_or_else(|e| panic!("{:?}", e.iter().map(|x| x.to_string()).collect::<Vec<_>>()));
    let params = paraflex::sequence::parameters::Parameters::of_model(&model).unwrap();
    let frames = GridFrames::of_model(&model);
    let map = DofMap::of_model(&model);
    let quiet = |_: &str, _: usize, _: usize| {};
    let el = paraflex::sequence::elements::element_matrices(&model, &frames, &params, false, &quiet).unwrap_or_else(|e| panic!("{e}"));
    let pattern = std::sync::Arc::new(paraflex::assembly::pattern::grid_block_pattern(map.grids(), el.stiffness.iter().chain(&el.mass).map(|c| c.dofs.as_slice())).unwrap());
    let k = AffineOperator::assemble(pattern.clone(), &el.stiffness, false).unwrap();
    let m = AffineOperator::assemble(pattern, &el.mass, false).unwrap();
    (params, k, m)
}

/// Run a deck text through deck → model → sequence with an HDF5 file in a temp directory.
#[allow(dead_code)] // each test crate that includes this module uses one of the two runners
pub fn run_deck(text: &str) -> (Result<RunSummary, RunError>, tempfile::TempDir) {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("deck.dat");
    std::fs::File::create(&path).and_then(|mut f| f.write_all(text.as_bytes())).expect("write deck");
    let (result, _model, dir) = run_in(&path, dir);
    (result, dir)
}

/// Run the deck file at `path` (its INCLUDEs resolve relative to it) with the HDF5 file
/// `out.h5` in a new temp directory; also returns the model (mass properties, grids).
#[allow(dead_code)]
pub fn run_deck_file(path: &Path) -> (Result<RunSummary, RunError>, Model, tempfile::TempDir) {
    run_in(path, tempfile::tempdir().expect("temp dir"))
}

fn run_in(path: &Path, dir: tempfile::TempDir) -> (Result<RunSummary, RunError>, Model, tempfile::TempDir) {
    let deck = Deck::read(path).unwrap_or_else(|e| panic!("{}: deck: {e}", path.display()));
    let model = Model::build(&deck).unwrap_or_else(|e| panic!("{}: model: {:?}", path.display(), e.iter().map(|x| x.to_string()).collect::<Vec<_>>()));
    let file = OutputFile::create(dir.path().join("out.h5")).expect("output");
    let ctx = RunContext { deck: &deck, model: &model, output: &file, progress: &|_: &str, _: usize, _: usize| {}, options: RunOptions { parallel: false } };
    let result = run(&ctx);
    if result.is_ok() {
        file.commit().expect("commit");
    }
    (result, model, dir)
}
