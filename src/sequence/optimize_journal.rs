//! The journal of a study's evaluations: every evaluation appended, as it completes, to a
//! JSON-lines file beside the output (`<output>.designs-<subcase>.jsonl`), so that an
//! interrupted study loses nothing it evaluated and `MOOPT … START = RESUME` reruns it
//! evaluating only the designs the journal does not hold.
//!
//! The first line names the study (`{"variables": [...], "responses": [...]}`); each further
//! line is one evaluation: `{"design": [...], "responses": [...] | null, "error": "..." |
//! null, "seconds": s}`. The search is deterministic (a seeded NSGA-II, or the grid), so a
//! rerun proposes the same designs in the same order; a design is looked up by the exact
//! values of its variables (f64 written in their shortest round-trip form). A non-finite
//! response is written as `null` and read back as NaN. A last line cut short (the process
//! killed while writing it) is ignored; an evaluation that panicked is not journaled and runs
//! again on resume.

use std::fs::{File, OpenOptions};
use std::io::{BufRead, BufReader, Write};
use std::path::{Path, PathBuf};
use std::sync::Mutex;

use serde::{Deserialize, Serialize};

use crate::optimize::{Design, EvalError, Evaluated};

/// What the journal's first line records of the study.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Header {
    pub variables: Vec<String>,
    pub responses: Vec<String>,
}

/// One journaled evaluation.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
struct Entry {
    design: Vec<f64>,
    responses: Option<Vec<Option<f64>>>,
    error: Option<String>,
    seconds: f64,
}

impl Entry {
    fn of(design: &[f64], evaluated: &Evaluated) -> Entry {
        let (responses, error) = match &evaluated.result {
            Ok(r) => (
                Some(r.iter().map(|v| v.is_finite().then_some(*v)).collect()),
                None,
            ),
            Err(e) => (None, Some(e.0.clone())),
        };
        Entry {
            design: design.to_vec(),
            responses,
            error,
            seconds: evaluated.seconds,
        }
    }

    fn evaluated(&self) -> Evaluated {
        let result = match (&self.responses, &self.error) {
            (Some(r), _) => Ok(r.iter().map(|v| v.unwrap_or(f64::NAN)).collect()),
            (None, e) => Err(EvalError(e.clone().unwrap_or_default())),
        };
        Evaluated {
            result,
            seconds: self.seconds,
        }
    }
}

/// The journal line (JSON, without its newline) of the evaluation of `design`; also what
/// `paraflex evaluate` prints per design.
pub fn entry_line(design: &[f64], evaluated: &Evaluated) -> Result<String, String> {
    serde_json::to_string(&Entry::of(design, evaluated)).map_err(|e| e.to_string())
}

/// The design and evaluation of a journal line (what `paraflex evaluate` prints per design).
pub fn parse_entry_line(line: &str) -> Result<(Design, Evaluated), String> {
    let entry: Entry = serde_json::from_str(line).map_err(|e| e.to_string())?;
    let evaluated = entry.evaluated();
    Ok((entry.design, evaluated))
}

/// An open journal: the evaluations read from it (on resume) and the file appended to.
pub struct Journal {
    path: PathBuf,
    file: Mutex<File>,
    known: Vec<Entry>,
}

/// The journal's path for the output `output` and subcase `subcase`.
pub fn journal_path(output: &Path, subcase: u32) -> PathBuf {
    let mut name = output.as_os_str().to_os_string();
    name.push(format!(".designs-{subcase}.jsonl"));
    PathBuf::from(name)
}

impl Journal {
    /// Opens the journal at `path` for the study `header`: a new one (any old file replaced),
    /// or with `resume` the existing one, its evaluations kept (no file: a new one). A journal
    /// of another study (variables or responses differ) is an error.
    pub fn open(path: &Path, header: &Header, resume: bool) -> Result<Journal, String> {
        let shown = path.display();
        let mut known = Vec::new();
        if resume && path.exists() {
            let file = File::open(path).map_err(|e| format!("cannot read {shown}: {e}"))?;
            let mut lines = BufReader::new(file).lines();
            let first = lines
                .next()
                .transpose()
                .map_err(|e| format!("cannot read {shown}: {e}"))?
                .unwrap_or_default();
            let theirs: Header = serde_json::from_str(&first)
                .map_err(|e| format!("{shown}: line 1 is no study header: {e}"))?;
            if &theirs != header {
                return Err(format!(
                    "{shown} is the journal of another study (variables {:?}, responses {:?}; this one: {:?}, {:?}): remove it or drop START = RESUME",
                    theirs.variables, theirs.responses, header.variables, header.responses
                ));
            }
            let lines: Vec<String> = lines
                .collect::<Result<_, _>>()
                .map_err(|e| format!("cannot read {shown}: {e}"))?;
            for (i, line) in lines.iter().enumerate() {
                match serde_json::from_str::<Entry>(line) {
                    Ok(entry) => known.push(entry),
                    // the process was killed while writing the last line
                    Err(_) if i + 1 == lines.len() => {}
                    Err(e) => return Err(format!("{shown}: line {}: {e}", i + 2)),
                }
            }
        }
        // (re)written: the header and the evaluations kept (a cut-short last line dropped),
        // then appended to
        let mut text = serde_json::to_string(header).map_err(|e| e.to_string())? + "\n";
        for entry in &known {
            text += &(serde_json::to_string(entry).map_err(|e| e.to_string())? + "\n");
        }
        std::fs::write(path, text).map_err(|e| format!("cannot write {shown}: {e}"))?;
        let file = OpenOptions::new()
            .append(true)
            .open(path)
            .map_err(|e| format!("cannot write {shown}: {e}"))?;
        Ok(Journal {
            path: path.to_path_buf(),
            file: Mutex::new(file),
            known,
        })
    }

    /// The journaled evaluation of `design`, if the journal holds one (the first).
    pub fn known(&self, design: &Design) -> Option<Evaluated> {
        let same = |e: &&Entry| {
            e.design.len() == design.len()
                && e.design
                    .iter()
                    .zip(design)
                    .all(|(a, b)| a.to_bits() == b.to_bits())
        };
        self.known.iter().find(same).map(Entry::evaluated)
    }

    /// Appends the evaluation of `design` (one line, flushed).
    pub fn record(&self, design: &[f64], evaluated: &Evaluated) -> Result<(), String> {
        let line = entry_line(design, evaluated)? + "\n";
        let mut file = self.file.lock().unwrap_or_else(|p| p.into_inner());
        file.write_all(line.as_bytes())
            .and_then(|()| file.flush())
            .map_err(|e| format!("cannot write {}: {e}", self.path.display()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_resumed_journal_returns_what_was_recorded_and_skips_a_cut_line() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("j.jsonl");
        let header = Header {
            variables: vec!["X".into()],
            responses: vec!["F".into(), "G".into()],
        };
        let a = Evaluated {
            result: Ok(vec![0.1 + 0.2, f64::INFINITY]),
            seconds: 1.5,
        };
        let b = Evaluated {
            result: Err(EvalError("Newton failed".into())),
            seconds: 0.25,
        };
        let j = Journal::open(&path, &header, false).unwrap();
        j.record(&[1.0 / 3.0], &a).unwrap();
        j.record(&[2.0], &b).unwrap();
        drop(j);
        // a line cut short by a kill
        let mut f = OpenOptions::new().append(true).open(&path).unwrap();
        write!(f, "{{\"design\":[3.0],\"resp").unwrap();
        drop(f);
        let j = Journal::open(&path, &header, true).unwrap();
        let got = j.known(&vec![1.0 / 3.0]).unwrap();
        let r = got.result.unwrap();
        assert_eq!(r[0].to_bits(), (0.1_f64 + 0.2).to_bits());
        assert!(r[1].is_nan(), "a non-finite response comes back as NaN");
        assert_eq!(j.known(&vec![2.0]), Some(b));
        assert_eq!(j.known(&vec![3.0]), None);
        assert_eq!(j.known(&vec![1.0 / 3.0 + 1e-16]), None);
        let other = Header {
            variables: vec!["Y".into()],
            responses: header.responses.clone(),
        };
        let e = Journal::open(&path, &other, true).err().unwrap();
        assert!(e.contains("journal of another study"), "{e}");
        // without resume the journal starts over
        let j = Journal::open(&path, &header, false).unwrap();
        assert_eq!(j.known(&vec![2.0]), None);
        drop(j);
        assert_eq!(std::fs::read_to_string(&path).unwrap().lines().count(), 1);
    }
}
