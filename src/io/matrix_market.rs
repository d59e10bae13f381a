//! Matrix Market coordinate files (the exchange format of sampled FE matrices for the
//! least-squares route, `paraflex prom-lsq`): `%%MatrixMarket matrix coordinate real|integer
//! general|symmetric`, 1-based indices, duplicates summed. A symmetric file stores one triangle
//! and is expanded to the full pattern `linalg` works on; an entry above the diagonal of a
//! symmetric file is taken as its mirror (some writers store the upper triangle). Every
//! unreadable line is an error naming the file and the line.

use std::path::Path;

use nalgebra_sparse::{CooMatrix, CscMatrix};

use super::hdf5_file::IoError;

/// The square matrix of a Matrix Market coordinate file, full pattern (explicit zeros kept).
pub fn read_matrix_market(path: &Path) -> Result<CscMatrix<f64>, IoError> {
    let text = std::fs::read_to_string(path).map_err(|cause| IoError::Fs {
        path: path.into(),
        what: "read the Matrix Market file".into(),
        cause,
    })?;
    let bad = |line: usize, reason: String| IoError::Parse {
        path: path.into(),
        line,
        reason,
    };
    let mut lines = text.lines().enumerate().map(|(k, l)| (k + 1, l.trim()));
    let (_, banner) = lines.next().ok_or_else(|| bad(0, "empty file".into()))?;
    let words: Vec<String> = banner
        .split_whitespace()
        .map(str::to_ascii_lowercase)
        .collect();
    let symmetric = match words
        .iter()
        .map(String::as_str)
        .collect::<Vec<_>>()
        .as_slice()
    {
        [
            "%%matrixmarket",
            "matrix",
            "coordinate",
            "real" | "integer",
            sym,
        ] => match *sym {
            "general" => false,
            "symmetric" => true,
            other => {
                return Err(bad(
                    1,
                    format!("symmetry '{other}' is not supported (general or symmetric)"),
                ));
            }
        },
        _ => {
            return Err(bad(
                1,
                format!(
                    "expected '%%MatrixMarket matrix coordinate real general|symmetric', found '{banner}'"
                ),
            ));
        }
    };
    let mut data = lines.filter(|(_, l)| !l.is_empty() && !l.starts_with('%'));
    let (size_line, size) = data.next().ok_or_else(|| bad(0, "no size line".into()))?;
    let dims: Vec<usize> = size
        .split_whitespace()
        .map(str::parse)
        .collect::<Result<_, _>>()
        .map_err(|_| {
            bad(
                size_line,
                format!("size line '{size}' is not three integers"),
            )
        })?;
    let [rows, cols, nnz] = dims[..] else {
        return Err(bad(
            size_line,
            format!("size line '{size}' is not three integers"),
        ));
    };
    if rows != cols {
        return Err(bad(
            size_line,
            format!("{rows} × {cols}: a stiffness or mass matrix is square"),
        ));
    }
    let mut coo = CooMatrix::new(rows, cols);
    let mut count = 0;
    for (line, entry) in data {
        let fields: Vec<&str> = entry.split_whitespace().collect();
        let [i, j, v] = fields[..] else {
            return Err(bad(
                line,
                format!("expected 'row column value', found '{entry}'"),
            ));
        };
        let index = |s: &str| {
            s.parse::<usize>()
                .ok()
                .filter(|&x| (1..=rows).contains(&x))
                .ok_or_else(|| bad(line, format!("index '{s}' is not in 1..={rows}")))
        };
        let (i, j) = (index(i)? - 1, index(j)? - 1);
        let v: f64 = v
            .parse()
            .ok()
            .filter(|x: &f64| x.is_finite())
            .ok_or_else(|| bad(line, format!("value '{v}' is not a finite number")))?;
        coo.push(i, j, v);
        if symmetric && i != j {
            coo.push(j, i, v);
        }
        count += 1;
    }
    if count != nnz {
        return Err(bad(
            0,
            format!("the size line announces {nnz} entries, the file has {count}"),
        ));
    }
    Ok(CscMatrix::from(&coo))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn file(text: &str) -> (tempfile::TempDir, std::path::PathBuf) {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("a.mtx");
        std::fs::write(&path, text).unwrap();
        (dir, path)
    }

    #[test]
    fn reads_symmetric_and_general_files() {
        let (_d, p) = file(
            "%%MatrixMarket matrix coordinate real symmetric\n% comment\n3 3 4\n1 1 2.0\n2 1 -1\n2 2 2\n3 3 0\n",
        );
        let a = read_matrix_market(&p).unwrap();
        let dense: Vec<(usize, usize, f64)> =
            a.triplet_iter().map(|(i, j, v)| (i, j, *v)).collect();
        assert_eq!(
            dense,
            vec![
                (0, 0, 2.0),
                (1, 0, -1.0),
                (0, 1, -1.0),
                (1, 1, 2.0),
                (2, 2, 0.0)
            ]
        );
        let (_d, p) =
            file("%%MatrixMarket matrix coordinate real general\n2 2 2\n1 2 3.5\n2 1 3.5\n");
        assert_eq!(read_matrix_market(&p).unwrap().nnz(), 2);
    }

    #[test]
    fn bad_files_name_the_line() {
        for (text, needle) in [
            ("%%MatrixMarket matrix array real general\n", ":1: expected"),
            (
                "%%MatrixMarket matrix coordinate real general\n2 3 1\n1 1 1\n",
                ":2: 2 × 3",
            ),
            (
                "%%MatrixMarket matrix coordinate real general\n2 2 1\n3 1 1\n",
                ":3: index '3'",
            ),
            (
                "%%MatrixMarket matrix coordinate real general\n2 2 1\n1 1 x\n",
                ":3: value 'x'",
            ),
            (
                "%%MatrixMarket matrix coordinate real general\n2 2 2\n1 1 1\n",
                ":0: the size line announces 2",
            ),
        ] {
            let (_d, p) = file(text);
            let message = read_matrix_market(&p).unwrap_err().to_string();
            assert!(message.contains(needle), "{message}");
        }
    }
}
