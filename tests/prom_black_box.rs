//! The black-box pROM route (thesis §3.3.5, §3.4.1.1; `src/rom/black_box.rs`): matrices,
//! local bases and strain bases sampled by "another FE code" — here a two-material spring chain
//! written in the test — in the HDF5 samples layout of `paraflex prom-lsq`.

use faer::Mat;
use faer::linalg::solvers::Solve;
use hdf5_metno::types::VarLenUnicode;

mod common;

/// Chain of `N` masses, spring j between DOF j − 1 and j (DOF −1 the ground), springs 0..6 of
/// stiffness E1, 6..12 of stiffness E2, a constant grounding spring 0.5 at the tip (so the
/// constant component is not zero), masses RHO · (1 + j/N).
const N: usize = 12;

fn stiffness(p: &[f64; 3]) -> Mat<f64> {
    let mut k = Mat::<f64>::zeros(N, N);
    for j in 0..N {
        let s = if j < 6 { p[0] } else { p[1] };
        k[(j, j)] += s;
        if j > 0 {
            k[(j - 1, j - 1)] += s;
            k[(j - 1, j)] -= s;
            k[(j, j - 1)] -= s;
        }
    }
    k[(N - 1, N - 1)] += 0.5;
    k
}

fn mass(p: &[f64; 3]) -> Mat<f64> {
    Mat::from_fn(N, N, |i, j| {
        if i == j {
            p[2] * (1.0 + i as f64 / N as f64)
        } else {
            0.0
        }
    })
}

/// Strains of springs 2, 7 and 11: u_j − u_{j−1}.
fn strain_rows() -> Mat<f64> {
    let springs = [2, 7, 11];
    Mat::from_fn(3, N, |s, i| {
        if i == springs[s] {
            1.0
        } else if i + 1 == springs[s] {
            -1.0
        } else {
            0.0
        }
    })
}

const SAMPLES: [[f64; 3]; 5] = [
    [1.0, 2.0, 1.0],
    [1.5, 1.2, 2.0],
    [2.2, 2.6, 1.4],
    [0.8, 1.7, 2.6],
    [1.9, 0.9, 0.7],
];
const INPUTS: [usize; 2] = [N - 1, 5];

/// Local basis of sample h: static shapes K(p_h)⁻¹ of a unit load at DOF 2h + 1 and of a load
/// pair +1 at DOF 2h, −1 at the tip (the external code's "static modes"; different per sample:
/// the largest MAC across samples is 0.981, numpy, so the 0.99 filter keeps all 10 columns,
/// and the smallest singular value of the scaled concatenation is 1.3e-2 of the largest).
fn local_basis(h: usize) -> Mat<f64> {
    let loads = Mat::<f64>::from_fn(N, 2, |i, j| match j {
        0 if i == 2 * h + 1 => 1.0,
        1 if i == 2 * h => 1.0,
        1 if i == N - 1 => -1.0,
        _ => 0.0,
    });
    stiffness(&SAMPLES[h]).partial_piv_lu().solve(&loads)
}

fn write_dense(parent: &hdf5_metno::Group, name: &str, m: &Mat<f64>) {
    let data: Vec<f64> = (0..m.nrows())
        .flat_map(|i| (0..m.ncols()).map(move |j| m[(i, j)]))
        .collect();
    parent
        .new_dataset::<f64>()
        .shape([m.nrows(), m.ncols()])
        .create(name)
        .unwrap()
        .write_raw(&data)
        .unwrap();
}

fn strings(parent: &hdf5_metno::Group, name: &str, values: &[&str]) {
    let v: Vec<VarLenUnicode> = values.iter().map(|s| s.parse().unwrap()).collect();
    parent
        .new_dataset_builder()
        .with_data(&v)
        .create(name)
        .unwrap();
}

/// The samples file; `basis_of(h)` and `strain_of(h)` give what sample h carries.
fn write_samples(
    path: &std::path::Path,
    basis_of: &dyn Fn(usize) -> Mat<f64>,
    strain_of: &dyn Fn(usize) -> Mat<f64>,
) {
    let file = hdf5_metno::File::create(path).unwrap();
    strings(&file, "functions", &["1", "E1", "E2", "RHO"]);
    let values: Vec<f64> = SAMPLES
        .iter()
        .flat_map(|p| [1.0, p[0], p[1], p[2]])
        .collect();
    file.new_dataset::<f64>()
        .shape([SAMPLES.len(), 4])
        .create("values")
        .unwrap()
        .write_raw(&values)
        .unwrap();
    let groups: Vec<hdf5_metno::Group> = ["K", "M", "basis", "strain"]
        .iter()
        .map(|g| file.create_group(g).unwrap())
        .collect();
    for (h, p) in SAMPLES.iter().enumerate() {
        write_dense(&groups[0], &h.to_string(), &stiffness(p));
        write_dense(&groups[1], &h.to_string(), &mass(p));
        write_dense(&groups[2], &h.to_string(), &basis_of(h));
        write_dense(&groups[3], &h.to_string(), &strain_of(h));
    }
    strings(&file, "sensors", &["S2", "S7", "S11"]);
    let inputs = file.create_group("inputs").unwrap();
    strings(&inputs, "names", &["12:1", "6:1"]);
    inputs
        .new_dataset_builder()
        .with_data(&INPUTS.map(|i| i as i64))
        .create("dofs")
        .unwrap();
}

fn run_cli(args: &[&std::path::Path]) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_paraflex"))
        .args(args)
        .output()
        .expect("run paraflex")
}

/// [G_S | G_H](ω) = [H; Sᵀ] (K − ω²M)⁻¹ [S | Hᵀ] for one model: with V Vᵀ-invariant quantities
/// like this one, a pROM on any orthonormal basis of the same span gives the same numbers.
fn transfer(
    k: &Mat<f64>,
    m: &Mat<f64>,
    inputs: &Mat<f64>,
    sensors: &Mat<f64>,
    omega: f64,
) -> Mat<f64> {
    let right = Mat::<f64>::from_fn(k.nrows(), inputs.ncols() + sensors.nrows(), |i, j| {
        if j < inputs.ncols() {
            inputs[(i, j)]
        } else {
            sensors[(j - inputs.ncols(), i)]
        }
    });
    let dynamic = Mat::<f64>::from_fn(k.nrows(), k.ncols(), |i, j| {
        k[(i, j)] - omega * omega * m[(i, j)]
    });
    right.transpose() * dynamic.partial_piv_lu().solve(&right)
}

/// `paraflex prom-lsq samples.h5` with local bases Ψ_h and strain bases N_s,h = L Ψ_h (L the
/// spring strain rows) must give the Galerkin pROM on span{Ψ_h}: least-squares components
/// (eq. 3.29) projected on the SVD basis of the scaled, MAC-filtered concatenation, S_r from
/// the input DOFs, H_r by eq. 3.36–3.38. Reference: the exact K(p), M(p) of the chain projected
/// on Q, an orthonormal basis of all 10 local columns (QR; the MAC filter keeps all 10, checked
/// through the CLI report, and the SVD rank is 10), and L Q. The bases differ by a rotation,
/// so the test compares [Sᵀ; H] (K_r − ω²M_r)⁻¹ [S | Hᵀ] at three parameter points (two
/// outside the sampled box) and ω = 0, 0.3, 0.7 rad/s (static and between resonances: the
/// first two are 0.12–0.38 rad/s at these points, numpy). Bound 1e-10 relative to the largest
/// entry: the components are exact to ~1e-15 (LSQ residual 8e-16 on exact samples), the SVD
/// and QR bases span the same space to round-off, and the dynamic stiffness has a condition
/// number ≤ 2.2e2 at these points (numpy), so errors are ~1e-13; a wrong projection, input row
/// or strain transformation is off by O(1). The artifact loads with `paraflex info`, and a
/// `SOL 111` deck with `ROM =` on it gives the same FRF (inputs and strain sensors as outputs)
/// at 3 lines, same bound.
#[test]
fn black_box_prom_equals_the_galerkin_projection_on_the_local_bases() {
    let dir = tempfile::tempdir().unwrap();
    let (samples, out) = (dir.path().join("samples.h5"), dir.path().join("out.h5"));
    let l = strain_rows();
    write_samples(&samples, &local_basis, &|h| &l * local_basis(h));
    let run = run_cli(&[
        std::path::Path::new("prom-lsq"),
        &samples,
        std::path::Path::new("-o"),
        &out,
    ]);
    let stdout = String::from_utf8_lossy(&run.stdout);
    assert!(
        run.status.success(),
        "{stdout}{}",
        String::from_utf8_lossy(&run.stderr)
    );
    assert!(
        stdout.contains(
            "pROM: 10 local columns, 10 after the MAC filter, n_red 10, 2 inputs, 3 strain sensors"
        ),
        "{stdout}"
    );
    let (prom, n_full) = paraflex::io::read_prom(&out).unwrap();
    assert_eq!(
        (
            n_full,
            prom.parameters
                .iter()
                .map(|p| p.name.as_str())
                .collect::<Vec<_>>()
        ),
        (N, vec!["E1", "E2", "RHO"])
    );
    let (input_names, s_r) = paraflex::io::read_prom_inputs(&out, prom.size()).unwrap();
    let (sensor_names, kinds, h_r) = paraflex::io::read_prom_sensors(&out, prom.size()).unwrap();
    assert_eq!(
        (input_names, sensor_names, kinds),
        (
            vec!["12:1".to_string(), "6:1".into()],
            vec!["S2".to_string(), "S7".into(), "S11".into()],
            vec!["STRAIN".to_string(); 3]
        )
    );

    let concatenated = Mat::<f64>::from_fn(N, 10, |i, c| local_basis(c / 2)[(i, c % 2)]);
    let q = concatenated.qr().compute_thin_Q();
    let s = Mat::<f64>::from_fn(
        N,
        INPUTS.len(),
        |i, j| if i == INPUTS[j] { 1.0 } else { 0.0 },
    );
    let mut worst: f64 = 0.0;
    for p in [[1.3, 1.6, 1.5], [0.6, 3.0, 1.0], [2.5, 0.7, 3.1]] {
        let sum = |parts: &[Mat<f64>]| -> Mat<f64> {
            let mut total = Mat::<f64>::zeros(prom.size(), prom.size());
            for (f, x) in prom.functions.iter().zip(parts) {
                total += faer::Scale(f.value(&p)) * x;
            }
            total
        };
        let (k_r, m_r) = (sum(&prom.stiffness), sum(&prom.mass));
        let (k_q, m_q) = (
            q.transpose() * stiffness(&p) * &q,
            q.transpose() * mass(&p) * &q,
        );
        for omega in [0.0, 0.3, 0.7] {
            let got = transfer(&k_r, &m_r, &s_r, &h_r, omega);
            let want = transfer(&k_q, &m_q, &(q.transpose() * &s), &(&l * &q), omega);
            let scale = (0..want.nrows())
                .flat_map(|i| (0..want.ncols()).map(move |j| (i, j)))
                .fold(0.0_f64, |a, (i, j)| a.max(want[(i, j)].abs()));
            for i in 0..want.nrows() {
                for j in 0..want.ncols() {
                    worst = worst.max((got[(i, j)] - want[(i, j)]).abs() / scale);
                }
            }
        }
    }
    eprintln!("max relative difference {worst:e}");
    assert!(worst < 1e-10, "max relative difference {worst:e}");
    let info = run_cli(&[std::path::Path::new("info"), &out]);
    assert!(
        info.status.success(),
        "{}",
        String::from_utf8_lossy(&info.stderr)
    );

    // a SOL 111 deck on the artifact: outputs = the inputs, then the strain sensors
    let p = [1.3, 1.6, 1.5];
    let deck = format!(
        "SOL 111\nCEND\nROM = '{}'\nPVAL = 1\nFREQUENCY = 1\nBEGIN BULK\nPVAL,1,E1,{},E2,{},RHO,{}\nFREQ1,1,0.01,0.04,2\nENDDATA\n",
        out.display(),
        p[0],
        p[1],
        p[2]
    );
    let (r, frf_dir) = common::run_deck(&deck);
    r.expect("pROM FRF");
    let file = hdf5_metno::File::open(frf_dir.path().join("out.h5")).unwrap();
    let g = file.group("results/1/frf").unwrap();
    let hz: Vec<f64> = g.dataset("frequency_hz").unwrap().read_raw().unwrap();
    let h: Vec<faer::c64> = g.dataset("H").unwrap().read_raw().unwrap();
    let (k_q, m_q) = (
        q.transpose() * stiffness(&p) * &q,
        q.transpose() * mass(&p) * &q,
    );
    let mut worst: f64 = 0.0;
    for (line, f) in hz.iter().enumerate() {
        let want = transfer(
            &k_q,
            &m_q,
            &(q.transpose() * &s),
            &(&l * &q),
            2.0 * std::f64::consts::PI * f,
        );
        let scale = (0..5)
            .flat_map(|o| (0..2).map(move |i| (o, i)))
            .fold(0.0_f64, |a, (o, i)| a.max(want[(o, i)].abs()));
        for o in 0..5 {
            for i in 0..2 {
                worst = worst.max(
                    (h[10 * line + 2 * o + i] - faer::c64::new(want[(o, i)], 0.0)).norm() / scale,
                );
            }
        }
    }
    eprintln!(
        "SOL 111 on the artifact: max relative difference {worst:e} over {} lines",
        hz.len()
    );
    assert!(
        hz.len() == 3 && worst < 1e-10,
        "max relative difference {worst:e} over {hz:?}"
    );
}

/// Mismatched sizes are refused with the object named and exit code 2: a local basis with a
/// row too many, and a strain basis with fewer columns than its local basis.
#[test]
fn black_box_samples_with_mismatched_sizes_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let samples = dir.path().join("samples.h5");
    let l = strain_rows();
    type PerSample<'a> = &'a dyn Fn(usize) -> Mat<f64>;
    let cases: [(PerSample, PerSample, &str); 2] = [
        (
            &|h| {
                if h == 1 {
                    Mat::zeros(N + 1, 2)
                } else {
                    local_basis(h)
                }
            },
            &|h| &l * local_basis(h),
            "/basis/1: 13 rows, the matrices are 12 × 12",
        ),
        (
            &local_basis,
            &|h| {
                if h == 3 {
                    Mat::zeros(3, 1)
                } else {
                    &l * local_basis(h)
                }
            },
            "companion of local basis 4: 1 columns, the local basis has 2",
        ),
    ];
    for (basis, strain, needle) in cases {
        write_samples(&samples, basis, strain);
        let run = run_cli(&[std::path::Path::new("prom-lsq"), &samples]);
        let stderr = String::from_utf8_lossy(&run.stderr);
        assert_eq!(run.status.code(), Some(2), "{stderr}");
        assert!(stderr.contains(needle), "{stderr}");
    }
}
