//! Helpers shared by the solution-sequence integration tests.

use std::io::Write;
use std::path::Path;

use paraflex::deck::Deck;
use paraflex::discretize::BuildOptions;
use paraflex::io::OutputFile;
use paraflex::model::Model;
use paraflex::sequence::{RunContext, RunError, RunSummary, run};

/// The parameters and the affine g-set operators K and M of a bulk-data section (elements,
/// assembly on one pattern; no constraints), as `SOL PROM` assembles them.
#[allow(dead_code)]
pub fn affine_operators(
    bulk: &str,
) -> (
    paraflex::discretize::parameters::Parameters,
    paraflex::assembly::AffineOperator,
    paraflex::assembly::AffineOperator,
) {
    use paraflex::assembly::{AffineOperator, DofMap, GridFrames};
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("deck.dat");
    let text = format!("SOL 103\nCEND\nBEGIN BULK\n{bulk}ENDDATA\n");
    std::fs::File::create(&path)
        .and_then(|mut f| f.write_all(text.as_bytes()))
        .unwrap();
    let deck = Deck::read(&path).unwrap_or_else(|e| panic!("{e}"));
    let model = Model::build(&deck)
        .unwrap_or_else(|e| panic!("{:?}", e.iter().map(|x| x.to_string()).collect::<Vec<_>>()));
    let params = paraflex::discretize::parameters::Parameters::of_model(&model).unwrap();
    let frames = GridFrames::of_model(&model);
    let map = DofMap::of_model(&model);
    let quiet = |_: &str, _: usize, _: usize| {};
    let el =
        paraflex::discretize::elements::element_matrices(&model, &frames, &params, false, &quiet)
            .unwrap_or_else(|e| panic!("{e}"));
    let pattern = std::sync::Arc::new(
        paraflex::assembly::pattern::grid_block_pattern(
            map.grids(),
            map.scalar_points(),
            el.stiffness
                .iter()
                .chain(&el.mass)
                .map(|c| c.dofs.as_slice()),
        )
        .unwrap(),
    );
    let k = AffineOperator::assemble(pattern.clone(), &el.stiffness, false).unwrap();
    let m = AffineOperator::assemble(pattern, &el.mass, false).unwrap();
    (params, k, m)
}

/// Run a deck text through deck → model → sequence with an HDF5 file in a temp directory.
#[allow(dead_code)] // each test crate that includes this module uses one of the two runners
pub fn run_deck(text: &str) -> (Result<RunSummary, RunError>, tempfile::TempDir) {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("deck.dat");
    std::fs::File::create(&path)
        .and_then(|mut f| f.write_all(text.as_bytes()))
        .expect("write deck");
    let (result, _model, dir) = run_in(&path, dir);
    (result, dir)
}

/// Run the deck file at `path` (its INCLUDEs resolve relative to it) with the HDF5 file
/// `out.h5` in a new temp directory; also returns the model (mass properties, grids).
#[allow(dead_code)]
pub fn run_deck_file(path: &Path) -> (Result<RunSummary, RunError>, Model, tempfile::TempDir) {
    run_in(path, tempfile::tempdir().expect("temp dir"))
}

fn run_in(
    path: &Path,
    dir: tempfile::TempDir,
) -> (Result<RunSummary, RunError>, Model, tempfile::TempDir) {
    let deck = Deck::read(path).unwrap_or_else(|e| panic!("{}: deck: {e}", path.display()));
    let model = Model::build(&deck).unwrap_or_else(|e| {
        panic!(
            "{}: model: {:?}",
            path.display(),
            e.iter().map(|x| x.to_string()).collect::<Vec<_>>()
        )
    });
    let file = OutputFile::create(dir.path().join("out.h5")).expect("output");
    let ctx = RunContext {
        deck: &deck,
        model: &model,
        output: &file,
        progress: &|_: &str, _: usize, _: usize| {},
        options: BuildOptions { parallel: false },
        engine: None,
    };
    let result = run(&ctx);
    if result.is_ok() {
        file.commit().expect("commit");
    }
    (result, model, dir)
}

/// The 2-DOF spring–mass chain ground–k₁–m₁–k₂–m₂ along x (grids 1, 2, both in the ASET) with
/// Rayleigh damping C = αM + βK, and its closed-form time response by modal superposition
/// (ζ_j = α/2ω_j + βω_j/2): shared by the pROM and full-model transient references.
#[allow(dead_code)]
pub struct TwoDofChain {
    pub k1: f64,
    pub k2: f64,
    pub m1: f64,
    pub m2: f64,
    pub alpha: f64,
    pub beta: f64,
}

#[allow(dead_code)]
impl TwoDofChain {
    /// The chain of the pROM FRF / transient tests.
    pub fn reference() -> Self {
        TwoDofChain {
            k1: 2.5e4,
            k2: 3.0e4,
            m1: 2.0,
            m2: 1.0,
            alpha: 0.8,
            beta: 2.0e-4,
        }
    }

    /// Bulk cards (grids, springs with PELAS 10 = k₁ and 20 = k₂, masses, ASET, damping) and
    /// two sensors on grid 2: A2 (ACCEL along +x) and D2 (DISP along −x).
    pub fn bulk(&self) -> String {
        let TwoDofChain {
            k1,
            k2,
            m1,
            m2,
            alpha,
            beta,
        } = self;
        format!(
            "GRID,1,,0.,0.,0.,,23456\nGRID,2,,1.,0.,0.,,23456\nCELAS1,1,10,1,1\nPELAS,10,{k1:e}\nCELAS1,2,20,1,1,2,1\nPELAS,20,{k2:e}\n\
             CONM2,11,1,,{m1:?}\nCONM2,12,2,,{m2:?}\nASET1,1,1,2\nPARAM,ALPHA1,{alpha:?}\nPARAM,BETA1,{beta:e}\n\
             SENSOR,1,A2,ACCEL,2,,2.,0.,0.\nSENSOR,2,D2,DISP,2,,-1.,0.,0.\n"
        )
    }

    /// u(t) of both DOFs from (u0, v0) under a unit step force on DOF 2 times `force`.
    pub fn response(&self, t: f64, u0: [f64; 2], v0: [f64; 2], force: f64) -> [f64; 2] {
        let km = faer::Mat::<f64>::from_fn(2, 2, |i, j| {
            [[self.k1 + self.k2, -self.k2], [-self.k2, self.k2]][i][j]
        });
        let mm = faer::Mat::<f64>::from_fn(2, 2, |i, j| [[self.m1, 0.0], [0.0, self.m2]][i][j]);
        let (lambda, phi) =
            paraflex::linalg::dense::generalized_eigen(km.as_ref(), mm.as_ref()).unwrap();
        let mut x = [0.0; 2];
        for j in 0..2 {
            let w = lambda[j].sqrt();
            let zeta = self.alpha / (2.0 * w) + self.beta * w / 2.0;
            let wd = w * (1.0 - zeta * zeta).sqrt();
            let (c, s, e) = ((wd * t).cos(), (wd * t).sin(), (-zeta * w * t).exp());
            // modal initial conditions η = φᵀ M u
            let eta0 = phi[(0, j)] * self.m1 * u0[0] + phi[(1, j)] * self.m2 * u0[1];
            let deta0 = phi[(0, j)] * self.m1 * v0[0] + phi[(1, j)] * self.m2 * v0[1];
            let free = e * (eta0 * c + (deta0 + zeta * w * eta0) / wd * s);
            let step = force * phi[(1, j)] / lambda[j] * (1.0 - e * (c + zeta * w / wd * s));
            x[0] += phi[(0, j)] * (free + step);
            x[1] += phi[(1, j)] * (free + step);
        }
        x
    }
}

/// A flat lx × ly plate of nx × ny CQUAD4 on PID 1 in the z = 0 plane: grid (i, j) has id
/// 1 + i + (nx + 1) j and element (i, j) id 1 + i + nx j. Returns the GRID and CQUAD4 cards and
/// the ids of the root edge x = 0 (for SPC1 or springs).
#[allow(dead_code)]
pub fn plate_mesh(nx: usize, ny: usize, lx: f64, ly: f64) -> (String, Vec<usize>) {
    let id = |i: usize, j: usize| 1 + i + (nx + 1) * j;
    let mut s = String::new();
    for j in 0..=ny {
        for i in 0..=nx {
            s += &format!(
                "GRID,{},,{:?},{:?},0.\n",
                id(i, j),
                i as f64 * lx / nx as f64,
                j as f64 * ly / ny as f64
            );
        }
    }
    for j in 0..ny {
        for i in 0..nx {
            s += &format!(
                "CQUAD4,{},1,{},{},{},{}\n",
                1 + i + nx * j,
                id(i, j),
                id(i + 1, j),
                id(i + 1, j + 1),
                id(i, j + 1)
            );
        }
    }
    (s, (0..=ny).map(|j| id(0, j)).collect())
}

/// [`plate_mesh`] clamped at x = 0 (SPC1 set 1, all six components of the root grids).
#[allow(dead_code)]
pub fn clamped_plate_mesh(nx: usize, ny: usize, lx: f64, ly: f64) -> String {
    let (mesh, root) = plate_mesh(nx, ny, lx, ly);
    mesh + &root
        .iter()
        .map(|g| format!("SPC1,1,123456,{g}\n"))
        .collect::<String>()
}

/// The repository's root (reference JSONs, decks and meshes are read relative to it).
#[allow(dead_code)]
pub fn root() -> std::path::PathBuf {
    std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The model of a deck text, or every deck and model error as text.
#[allow(dead_code)]
pub fn build_model(text: &str) -> Result<Model, Vec<String>> {
    let mut file = tempfile::Builder::new()
        .suffix(".bdf")
        .tempfile()
        .expect("temp file");
    file.write_all(text.as_bytes()).expect("write deck");
    let deck = Deck::read(file.path())
        .map_err(|e| e.errors.iter().map(|x| x.to_string()).collect::<Vec<_>>())?;
    Model::build(&deck).map_err(|e| e.iter().map(|x| x.to_string()).collect())
}

/// A JSON file of the repository, e.g. a reference in `reference/`.
#[allow(dead_code)]
pub fn json(rel: &str) -> serde_json::Value {
    let p = root().join(rel);
    serde_json::from_str(
        &std::fs::read_to_string(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display())),
    )
    .expect("json")
}

/// A JSON array of numbers.
#[allow(dead_code)]
pub fn f64s(v: &serde_json::Value) -> Vec<f64> {
    v.as_array()
        .unwrap_or_else(|| panic!("not an array: {v}"))
        .iter()
        .map(|x| x.as_f64().expect("number"))
        .collect()
}

/// Run a deck text ([`run_deck`], which must succeed) and open its output file; the directory
/// that holds it comes along so that the file outlives the call.
#[allow(dead_code)]
pub fn run_to_file(text: &str) -> (hdf5_metno::File, tempfile::TempDir) {
    let (r, dir) = run_deck(text);
    r.unwrap_or_else(|e| panic!("{e}"));
    let file = hdf5_metno::File::open(dir.path().join("out.h5")).expect("open");
    (file, dir)
}

/// A dataset of group `g` read whole, panicking with its name when it is missing.
#[allow(dead_code)]
pub fn read_dataset<T: hdf5_metno::H5Type>(g: &hdf5_metno::Group, name: &str) -> Vec<T> {
    g.dataset(name)
        .unwrap_or_else(|e| panic!("{name}: {e}"))
        .read_raw()
        .unwrap()
}
