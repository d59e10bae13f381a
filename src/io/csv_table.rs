//! Two columns of a CSV file as (x, y) points (TABLEF; measurement files later).
//!
//! Comma-separated numbers, one row per line; blank lines and lines starting with `#` are
//! skipped; a first row that is not all numbers is the header, whose names (trimmed,
//! case-insensitive) select columns as well as 1-based indices do. Every unreadable or
//! non-finite field (NaN, inf: a missing sample is not a value) is an error naming the file, the
//! line and the column.

use std::path::Path;

use super::hdf5_file::IoError;
use crate::card_values::Column;

fn read(path: &Path) -> Result<String, IoError> {
    std::fs::read_to_string(path).map_err(|cause| IoError::Fs {
        path: path.into(),
        what: "read the CSV file".into(),
        cause,
    })
}

/// The header names of a first significant row (upper case), `None` when it is all numbers.
fn header_of(first: &str) -> Option<Vec<String>> {
    first
        .split(',')
        .any(|f| f.trim().parse::<f64>().is_err())
        .then(|| {
            first
                .split(',')
                .map(|f| f.trim().to_ascii_uppercase())
                .collect()
        })
}

/// The header names (upper case) of the CSV file at `path`, empty when its first row is all
/// numbers.
pub fn header(path: &Path) -> Result<Vec<String>, IoError> {
    let text = read(path)?;
    let first = text
        .lines()
        .map(str::trim)
        .find(|l| !l.is_empty() && !l.starts_with('#'))
        .unwrap_or("");
    Ok(header_of(first).unwrap_or_default())
}

/// The (x, y) points of columns `x` and `y` of the CSV file at `path`.
pub fn read_columns(path: &Path, x: &Column, y: &Column) -> Result<Vec<(f64, f64)>, IoError> {
    let text = read(path)?;
    let bad = |line: usize, reason: String| IoError::Parse {
        path: path.into(),
        line,
        reason,
    };
    let mut rows = text
        .lines()
        .enumerate()
        .map(|(k, l)| (k + 1, l.trim()))
        .filter(|(_, l)| !l.is_empty() && !l.starts_with('#'))
        .peekable();
    let Some(&(first_line, _)) = rows.peek() else {
        return Err(IoError::malformed(
            path,
            "CSV file",
            "no header and no data rows",
        ));
    };
    let header = rows.peek().and_then(|(_, first)| header_of(first));
    if header.is_some() {
        rows.next();
    }
    let index = |c: &Column| -> Result<usize, IoError> {
        match c {
            Column::Index(i) if *i >= 1 => Ok(i - 1),
            Column::Index(i) => Err(bad(
                first_line,
                format!("column index {i}: columns count from 1"),
            )),
            Column::Name(n) => header
                .as_ref()
                .and_then(|h| h.iter().position(|x| x.eq_ignore_ascii_case(n)))
                .ok_or_else(|| {
                    bad(
                        first_line,
                        format!(
                            "no column named {n} (header: {})",
                            header.as_ref().map_or("none".into(), |h| h.join(", "))
                        ),
                    )
                }),
        }
    };
    let (ix, iy) = (index(x)?, index(y)?);
    let mut out = Vec::new();
    for (line, row) in rows {
        let fields: Vec<&str> = row.split(',').map(str::trim).collect();
        let value = |i: usize| -> Result<f64, IoError> {
            let field = fields.get(i).ok_or_else(|| {
                bad(
                    line,
                    format!("{} field(s), column {} wanted", fields.len(), i + 1),
                )
            })?;
            match field.parse::<f64>() {
                Ok(v) if v.is_finite() => Ok(v),
                Ok(_) => Err(bad(
                    line,
                    format!("column {}: '{field}' is not a finite number", i + 1),
                )),
                Err(_) => Err(bad(
                    line,
                    format!("column {}: '{field}' is not a number", i + 1),
                )),
            }
        };
        out.push((value(ix)?, value(iy)?));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_by_index_and_by_header_name_and_names_bad_fields() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("t.csv");
        std::fs::write(
            &path,
            "# load history\ntime, force ,other\n0.0,1.5,9\n\n0.1,2.5e3,9\n",
        )
        .unwrap();
        let by_name = read_columns(
            &path,
            &Column::Name("TIME".into()),
            &Column::Name("force".into()),
        )
        .unwrap();
        assert_eq!(by_name, vec![(0.0, 1.5), (0.1, 2.5e3)]);
        assert_eq!(
            read_columns(&path, &Column::Index(1), &Column::Index(3)).unwrap(),
            vec![(0.0, 9.0), (0.1, 9.0)]
        );
        std::fs::write(&path, "0,1\n0.2,x\n").unwrap();
        let message = read_columns(&path, &Column::Index(1), &Column::Index(2))
            .unwrap_err()
            .to_string();
        assert!(
            message.contains("t.csv:2: column 2: 'x' is not a number"),
            "{message}"
        );
        let missing = read_columns(&path, &Column::Name("F".into()), &Column::Index(2))
            .unwrap_err()
            .to_string();
        assert!(missing.contains("no column named F"), "{missing}");
        // a missing sample written as NaN or an overflow is refused where it is
        std::fs::write(&path, "0,1\n0.1,2\n0.2,NaN\n0.3,inf\n").unwrap();
        let message = read_columns(&path, &Column::Index(1), &Column::Index(2))
            .unwrap_err()
            .to_string();
        assert!(
            message.contains("t.csv:3: column 2: 'NaN' is not a finite number"),
            "{message}"
        );
        std::fs::write(&path, "# only a comment\n\n").unwrap();
        let message = read_columns(&path, &Column::Index(1), &Column::Index(2))
            .unwrap_err()
            .to_string();
        assert!(
            message.contains("t.csv") && message.contains("no header and no data rows"),
            "{message}"
        );
    }
}
