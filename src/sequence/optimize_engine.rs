//! An evaluation engine outside this process: `paraflex run DECK --engine CMD` hands a
//! `SOL OPTIMIZE` study's batches of designs to a command (a Dask driver fanning them out to a
//! cluster, `tools/paraflex_tools/dask_engine.py`, or any other), which evaluates each design
//! as `paraflex evaluate` does and answers with its journal line.
//!
//! The protocol, JSON lines over the command's standard input and output (its standard error
//! is the console's):
//! 1. paraflex writes one line naming the study: `{"deck": <absolute path>, "subcase": n,
//!    "paraflex": <absolute path of this executable>}`;
//! 2. for each batch, paraflex writes `{"designs": [[x, …], …]}`; the engine answers one
//!    journal line per design (`{"design": …, "responses": … | null, "error": … | null,
//!    "seconds": s}`, what `paraflex evaluate` prints), in any order, each as soon as it has
//!    it, so that the study journals every evaluation as it completes;
//! 3. paraflex closes the engine's input at the end of the study; the engine exits.
//!
//! An answer is matched to its design by the exact bits of the design's values (f64 written
//! in their shortest round-trip form, as the journal writes them). An answer for no design of
//! the batch, a line that is no journal line, or an engine that exits before answering the
//! whole batch ends the study with an error (the journal keeps what was evaluated; `MOOPT …
//! START = RESUME` goes on from it).

use std::io::{BufRead, BufReader, Write};
use std::path::Path;
use std::process::{Child, ChildStdin, ChildStdout, Command, Stdio};

use serde::Serialize;

use super::optimize_journal::parse_entry_line;
use crate::optimize::{Design, Evaluated};

/// The first line paraflex writes to the engine.
#[derive(Serialize)]
struct Hello<'a> {
    deck: &'a Path,
    subcase: u32,
    paraflex: &'a Path,
}

/// A batch of designs, as paraflex writes it to the engine.
#[derive(Serialize)]
struct BatchLine<'a> {
    designs: &'a [Design],
}

/// A running engine process.
pub struct Engine {
    command: String,
    child: Child,
    input: Option<ChildStdin>,
    output: BufReader<ChildStdout>,
}

impl Engine {
    /// Starts `command` (run by `sh -c`) for the study of subcase `subcase` of `deck`.
    pub fn start(command: &str, deck: &Path, subcase: u32) -> Result<Engine, String> {
        let deck = std::path::absolute(deck)
            .map_err(|e| format!("cannot resolve {}: {e}", deck.display()))?;
        let paraflex = std::env::current_exe()
            .map_err(|e| format!("cannot find this executable's path: {e}"))?;
        let mut child = Command::new("sh")
            .arg("-c")
            .arg(command)
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::inherit())
            .spawn()
            .map_err(|e| format!("cannot start the engine `{command}`: {e}"))?;
        let input = child.stdin.take();
        let output = BufReader::new(child.stdout.take().expect("stdout was piped"));
        let mut engine = Engine {
            command: command.to_string(),
            child,
            input,
            output,
        };
        let hello = Hello {
            deck: &deck,
            subcase,
            paraflex: &paraflex,
        };
        engine.send(&serde_json::to_string(&hello).map_err(|e| e.to_string())?)?;
        Ok(engine)
    }

    /// The command the engine runs.
    pub fn command(&self) -> &str {
        &self.command
    }

    fn send(&mut self, line: &str) -> Result<(), String> {
        let sent = match self.input.as_mut() {
            Some(input) => writeln!(input, "{line}").and_then(|()| input.flush()),
            None => return Err(self.failure("its input is closed")),
        };
        sent.map_err(|e| self.failure(&format!("cannot write to it: {e}")))
    }

    fn failure(&self, what: &str) -> String {
        format!("the evaluation engine `{}`: {what}", self.command)
    }

    /// Every design of `designs` evaluated by the engine, in the order of `designs`;
    /// `completed` is called with each design's result as its answer arrives.
    pub fn batch(
        &mut self,
        designs: &[Design],
        mut completed: impl FnMut(&Design, &Evaluated),
    ) -> Result<Vec<Evaluated>, String> {
        let mut results: Vec<Option<Evaluated>> = vec![None; designs.len()];
        if designs.is_empty() {
            return Ok(Vec::new());
        }
        self.send(&serde_json::to_string(&BatchLine { designs }).map_err(|e| e.to_string())?)?;
        let mut waiting = designs.len();
        let mut line = String::new();
        while waiting > 0 {
            line.clear();
            let read = (self.output.read_line(&mut line))
                .map_err(|e| self.failure(&format!("cannot read its answer: {e}")))?;
            if read == 0 {
                return Err(self.failure(&format!(
                    "it ended with {waiting} of the batch's {} design(s) unanswered",
                    designs.len()
                )));
            }
            let (design, evaluated) = parse_entry_line(line.trim_end())
                .map_err(|e| self.failure(&format!("its answer is no journal line: {e}")))?;
            let slot = (designs.iter().zip(&results))
                .position(|(d, r)| r.is_none() && same_bits(d, &design))
                .ok_or_else(|| {
                    self.failure(&format!(
                        "it answered for {design:?}, no design of the batch waiting for an answer"
                    ))
                })?;
            completed(&designs[slot], &evaluated);
            results[slot] = Some(evaluated);
            waiting -= 1;
        }
        Ok(results.into_iter().flatten().collect())
    }

    /// Closes the engine's input and waits for it to exit.
    pub fn finish(mut self) -> Result<(), String> {
        drop(self.input.take());
        let status = (self.child.wait()).map_err(|e| self.failure(&e.to_string()))?;
        if status.success() {
            Ok(())
        } else {
            Err(self.failure(&format!("it exited with {status}")))
        }
    }
}

impl Drop for Engine {
    /// An engine left behind by a failed study is stopped.
    fn drop(&mut self) {
        if self.input.is_some() {
            let _ = self.child.kill();
            let _ = self.child.wait();
        }
    }
}

/// Whether two designs have the same values, bit for bit.
fn same_bits(a: &[f64], b: &[f64]) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::optimize::EvalError;

    /// An engine in `sh`: reads the hello line, then answers each batch line with `answers`.
    fn engine(answers: &str) -> Engine {
        let script = format!("read hello; while read batch; do printf '%s' '{answers}'; done");
        Engine::start(&script, Path::new("study.dat"), 1).unwrap()
    }

    /// An engine that answers its first batch with `answers` and exits.
    fn one_batch_engine(answers: &str) -> Engine {
        let script = format!("read hello; read batch; printf '%s' '{answers}'");
        Engine::start(&script, Path::new("study.dat"), 1).unwrap()
    }

    #[test]
    fn answers_in_any_order_come_back_in_the_designs_order() {
        let mut e = engine(concat!(
            r#"{"design":[2.0],"responses":null,"error":"Newton failed","seconds":0.5}"#,
            "\n",
            r#"{"design":[0.30000000000000004],"responses":[1.5,null],"error":null,"seconds":1.0}"#,
            "\n"
        ));
        let designs = vec![vec![0.1 + 0.2], vec![2.0]];
        let mut seen = Vec::new();
        let out = e
            .batch(&designs, |d, _| seen.push(d[0]))
            .expect("a full answer");
        assert_eq!(seen, vec![2.0, 0.1 + 0.2], "reported as they arrive");
        let r = out[0].result.as_ref().unwrap();
        assert_eq!(r[0], 1.5);
        assert!(r[1].is_nan());
        assert_eq!(out[1].result, Err(EvalError("Newton failed".into())));
        e.finish().unwrap();
    }

    #[test]
    fn a_wrong_or_missing_answer_is_an_error_naming_the_engine() {
        let one = r#"{"design":[1.0],"responses":[1.0],"error":null,"seconds":0.1}"#;
        let e = one_batch_engine(&format!("{one}\n"))
            .batch(&[vec![1.0], vec![2.0]], |_, _| {})
            .err()
            .unwrap();
        assert!(e.contains("1 of the batch's 2 design(s) unanswered"), "{e}");
        let e = engine(&format!("{one}\n"))
            .batch(&[vec![3.0]], |_, _| {})
            .err()
            .unwrap();
        assert!(
            e.contains("answered for [1.0], no design of the batch"),
            "{e}"
        );
        let e = engine("garbage\n")
            .batch(&[vec![3.0]], |_, _| {})
            .err()
            .unwrap();
        assert!(
            e.contains("`read hello") && e.contains("no journal line"),
            "{e}"
        );
        // an engine that exits at once
        let e = Engine::start("exit 3", Path::new("study.dat"), 1)
            .and_then(|mut e| e.batch(&[vec![3.0]], |_, _| {}))
            .err()
            .unwrap();
        assert!(e.contains("`exit 3`"), "{e}");
    }
}
