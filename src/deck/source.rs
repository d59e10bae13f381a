//! Reading deck files line by line, with `$` comments removed, tabs expanded and `INCLUDE`
//! statements followed (nested, cycles reported).
//!
//! Where an INCLUDE file is looked for: an absolute name is taken as it is. A relative name is
//! tried in the including file's directory, then in the main deck's directory, the first file
//! that exists being read. MSC Nastran resolves relative names from the input file's directory,
//! so decks written for it nest INCLUDEs written relative to the main deck; paraflex's own decks
//! (and pyNastran's writer) write them relative to the including file. When neither exists, the
//! error lists every path tried.
//!
//! A name of the form `SYMBOL:rest` (a symbol of two or more letters, digits or underscores,
//! so that a Windows drive letter is not one) uses MSC's logical symbols: `SYMBOL` is read from
//! the environment (MSC also defines symbols with `SYMBOL=` in its RC files, which paraflex
//! does not read) and `rest` is taken relative to its value. An undefined symbol is an error
//! naming it.
//!
//! The walk is streaming: each line is handed to a visitor as soon as it is read, so a
//! million-grid deck is never held as a list of lines.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use super::error::{DeckError, Diagnostics, Loc};

/// One preprocessed input line.
#[derive(Debug)]
pub struct Line<'a> {
    /// File and line number.
    pub loc: &'a Loc,
    /// The text with the comment removed, tabs expanded to 8-column stops, and trailing blanks
    /// and line ends removed.
    pub text: &'a str,
}

/// Receives the lines of a deck in reading order.
pub trait LineVisitor {
    /// Called once per non-empty line (comment-only lines are skipped).
    fn line(&mut self, line: Line<'_>, diag: &mut Diagnostics);
}

/// Maximum include nesting depth; deeper nesting is reported (it is almost certainly a cycle
/// through differently spelled paths).
const MAX_INCLUDE_DEPTH: usize = 64;

/// Looks up the value of an INCLUDE logical symbol.
pub type SymbolLookup = Box<dyn Fn(&str) -> Option<PathBuf>>;

/// Walks a deck file and everything it includes.
pub struct SourceWalker {
    stack: Vec<PathBuf>,
    /// Every file read, in order (the main deck first).
    pub files: Vec<PathBuf>,
    /// Logical symbols of INCLUDE names (`SYMBOL:file`).
    symbols: SymbolLookup,
}

impl SourceWalker {
    /// A walker with nothing read yet, taking INCLUDE logical symbols from the environment.
    pub fn new() -> Self {
        Self::with_symbols(Box::new(|name| std::env::var_os(name).map(PathBuf::from)))
    }

    /// A walker with nothing read yet, taking INCLUDE logical symbols from `symbols`.
    pub fn with_symbols(symbols: SymbolLookup) -> Self {
        SourceWalker {
            stack: Vec::new(),
            files: Vec::new(),
            symbols,
        }
    }

    /// Read `path` (and its includes) and feed every line to `visitor`. A file that cannot be
    /// read is reported at `included_from` (or without position for the main file).
    pub fn walk(
        &mut self,
        path: &Path,
        included_from: Option<&Loc>,
        visitor: &mut dyn LineVisitor,
        diag: &mut Diagnostics,
    ) {
        let canonical = std::fs::canonicalize(path).unwrap_or_else(|_| path.to_path_buf());
        let here = included_from
            .cloned()
            .unwrap_or_else(|| Loc::new(&Arc::from(path), 0));
        if let Some(pos) = self.stack.iter().position(|p| *p == canonical) {
            let cycle: Vec<String> = self.stack[pos..]
                .iter()
                .chain(std::iter::once(&canonical))
                .map(|p| p.display().to_string())
                .collect();
            diag.error(
                DeckError::at(&here, format!("INCLUDE cycle: {}", cycle.join(" -> ")))
                    .on_card("INCLUDE"),
            );
            return;
        }
        if self.stack.len() >= MAX_INCLUDE_DEPTH {
            diag.error(
                DeckError::at(
                    &here,
                    format!("INCLUDE nested deeper than {MAX_INCLUDE_DEPTH} levels"),
                )
                .on_card("INCLUDE"),
            );
            return;
        }
        let bytes = match std::fs::read(path) {
            Ok(b) => b,
            Err(e) => {
                let msg = format!("cannot read '{}': {e}", path.display());
                let err = DeckError::at(&here, msg);
                diag.error(if included_from.is_some() {
                    err.on_card("INCLUDE")
                } else {
                    err
                });
                return;
            }
        };
        self.stack.push(canonical);
        self.files.push(path.to_path_buf());
        let file: Arc<Path> = Arc::from(path);
        let text = String::from_utf8_lossy(&bytes);
        self.walk_text(&file, &text, visitor, diag);
        self.stack.pop();
    }

    /// Feed the lines of `text`, read as the file `path` (its INCLUDEs resolve relative to
    /// `path`), to `visitor`.
    pub fn walk_str(
        &mut self,
        path: &Path,
        text: &str,
        visitor: &mut dyn LineVisitor,
        diag: &mut Diagnostics,
    ) {
        self.files.push(path.to_path_buf());
        self.walk_text(&Arc::from(path), text, visitor, diag);
    }

    fn walk_text(
        &mut self,
        file: &Arc<Path>,
        text: &str,
        visitor: &mut dyn LineVisitor,
        diag: &mut Diagnostics,
    ) {
        let mut lines = text.lines().enumerate();
        let mut expanded = String::new();
        let mut loc = Loc::new(file, 0);
        while let Some((index, raw)) = lines.next() {
            loc.line = index as u32 + 1;
            let Some(content) = preprocess(raw, &mut expanded, &loc, diag) else {
                continue;
            };
            if let Some(rest) = include_argument(content) {
                let mut argument = rest.trim().to_string();
                // A quoted file name may continue on following lines until the closing quote.
                while argument.starts_with('\'') && argument.matches('\'').count() < 2 {
                    match lines.next() {
                        Some((_, next)) => argument.push_str(strip_comment(next).trim()),
                        None => break,
                    }
                }
                self.follow_include(&loc, &argument, visitor, diag);
                continue;
            }
            visitor.line(
                Line {
                    loc: &loc,
                    text: content,
                },
                diag,
            );
        }
    }

    fn follow_include(
        &mut self,
        loc: &Loc,
        argument: &str,
        visitor: &mut dyn LineVisitor,
        diag: &mut Diagnostics,
    ) {
        let name = match argument.strip_prefix('\'') {
            Some(quoted) => match quoted.find('\'') {
                Some(end) => quoted[..end].to_string(),
                None => {
                    diag.error(
                        DeckError::at(loc, "INCLUDE file name has no closing quote")
                            .on_card("INCLUDE"),
                    );
                    return;
                }
            },
            None => argument.to_string(),
        };
        if name.is_empty() {
            diag.error(
                DeckError::at(loc, "INCLUDE needs a file name, e.g. INCLUDE 'mesh.bdf'")
                    .on_card("INCLUDE"),
            );
            return;
        }
        let candidates = match self.include_candidates(loc, &name) {
            Ok(candidates) => candidates,
            Err(message) => {
                diag.error(DeckError::at(loc, message).on_card("INCLUDE"));
                return;
            }
        };
        // A single candidate is read directly, so that the error is the system's reason.
        let found = match candidates.as_slice() {
            [only] => Some(only),
            _ => candidates.iter().find(|c| c.is_file()),
        };
        match found {
            Some(target) => self.walk(&target.clone(), Some(loc), visitor, diag),
            None => {
                let tried: Vec<String> = candidates
                    .iter()
                    .map(|c| format!("'{}'", c.display()))
                    .collect();
                diag.error(
                    DeckError::at(
                        loc,
                        format!(
                            "cannot find '{name}': tried {} (a relative name is looked for \
                             beside the including file, then beside the main deck)",
                            tried.join(", ")
                        ),
                    )
                    .on_card("INCLUDE"),
                );
            }
        }
    }

    /// The paths an INCLUDE name may mean, in search order (see the module documentation), or
    /// the error for an undefined logical symbol.
    fn include_candidates(&self, loc: &Loc, name: &str) -> Result<Vec<PathBuf>, String> {
        let (name, symbol_dir) = match logical_symbol(name) {
            Some((symbol, rest)) => match (self.symbols)(symbol) {
                Some(dir) => (rest, Some(dir)),
                None => {
                    return Err(format!(
                        "logical symbol '{symbol}' in '{name}' is not defined (set the \
                         environment variable {symbol} to its directory)"
                    ));
                }
            },
            None => (name, None),
        };
        let relative = match symbol_dir {
            Some(dir) => dir.join(name),
            None => PathBuf::from(name),
        };
        if relative.is_absolute() {
            return Ok(vec![relative]);
        }
        let mut candidates = vec![loc.file.parent().unwrap_or(Path::new("")).join(&relative)];
        if let Some(main) = self.files.first() {
            let beside_main = main.parent().unwrap_or(Path::new("")).join(&relative);
            if beside_main != candidates[0] {
                candidates.push(beside_main);
            }
        }
        Ok(candidates)
    }
}

/// Splits `SYMBOL:rest` into the logical symbol and the rest, if the name starts with one (two
/// or more ASCII letters, digits or underscores, the first not a digit: a one-letter prefix is
/// a Windows drive).
fn logical_symbol(name: &str) -> Option<(&str, &str)> {
    let (symbol, rest) = name.split_once(':')?;
    let valid = symbol.len() >= 2
        && symbol.starts_with(|c: char| c.is_ascii_alphabetic() || c == '_')
        && symbol
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_');
    valid.then_some((symbol, rest))
}

impl Default for SourceWalker {
    fn default() -> Self {
        Self::new()
    }
}

/// If `line` is an `INCLUDE` statement, the rest of the line after the keyword.
fn include_argument(line: &str) -> Option<&str> {
    let head = line.get(..7)?;
    if !head.eq_ignore_ascii_case("INCLUDE") {
        return None;
    }
    let rest = &line[7..];
    (rest.is_empty() || rest.starts_with([' ', '\'', '\t'])).then_some(rest)
}

/// Remove a `$` comment (outside quotes).
fn strip_comment(line: &str) -> &str {
    let mut in_quote = false;
    for (i, c) in line.char_indices() {
        match c {
            '\'' => in_quote = !in_quote,
            '$' if !in_quote => return &line[..i],
            _ => {}
        }
    }
    line
}

/// Comment removal, control-character check and tab expansion. Returns `None` for lines that
/// are empty after comment removal or that were reported as errors.
fn preprocess<'a>(
    raw: &'a str,
    expanded: &'a mut String,
    loc: &Loc,
    diag: &mut Diagnostics,
) -> Option<&'a str> {
    let content = strip_comment(raw.strip_suffix('\r').unwrap_or(raw));
    if content.trim().is_empty() {
        return None;
    }
    if let Some(bad) = content
        .chars()
        .find(|&c| (c.is_control() && c != '\t') || c == '\u{FFFD}')
    {
        diag.error(DeckError::at(
            loc,
            format!(
                "line contains a non-text character (U+{:04X}); is this a binary file?",
                bad as u32
            ),
        ));
        return None;
    }
    let content = content.trim_end();
    if !content.contains('\t') {
        return Some(content);
    }
    expanded.clear();
    for c in content.chars() {
        if c == '\t' {
            let pad = 8 - expanded.chars().count() % 8;
            expanded.extend(std::iter::repeat_n(' ', pad));
        } else {
            expanded.push(c);
        }
    }
    Some(expanded.as_str())
}

#[cfg(test)]
mod tests {
    use super::*;

    struct Collect(Vec<(u32, String, String)>);
    impl LineVisitor for Collect {
        fn line(&mut self, line: Line<'_>, _: &mut Diagnostics) {
            let name = line
                .loc
                .file
                .file_name()
                .unwrap()
                .to_string_lossy()
                .to_string();
            self.0.push((line.loc.line, name, line.text.to_string()));
        }
    }

    fn walk(path: &Path) -> (Collect, Diagnostics) {
        let mut c = Collect(Vec::new());
        let mut d = Diagnostics::default();
        SourceWalker::new().walk(path, None, &mut c, &mut d);
        (c, d)
    }

    #[test]
    fn comments_tabs_and_includes() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::create_dir(dir.path().join("sub")).unwrap();
        std::fs::write(
            dir.path().join("main.dat"),
            "$ header\nGRID\t1\t\t0.\nINCLUDE 'sub/a.bdf'\nENDDATA $ end\n",
        )
        .unwrap();
        std::fs::write(dir.path().join("sub/a.bdf"), "include 'b.bdf'\nCARD A\n").unwrap();
        std::fs::write(dir.path().join("sub/b.bdf"), "CARD B\r\n").unwrap();
        let (c, d) = walk(&dir.path().join("main.dat"));
        assert!(d.is_ok(), "{:?}", d.errors);
        let texts: Vec<_> = c.0.iter().map(|(l, f, t)| format!("{f}:{l}:{t}")).collect();
        assert_eq!(
            texts,
            [
                "main.dat:2:GRID    1               0.",
                "b.bdf:1:CARD B",
                "a.bdf:2:CARD A",
                "main.dat:4:ENDDATA"
            ]
        );
    }

    /// The layout of decks written for MSC Nastran: a file under INCLUDE/ includes
    /// '../../BULK/x.blk', which exists only relative to the main deck in JOBS/QS/.
    fn msc_layout() -> tempfile::TempDir {
        let dir = tempfile::tempdir().unwrap();
        for sub in ["JOBS/QS", "INCLUDE", "BULK"] {
            std::fs::create_dir_all(dir.path().join(sub)).unwrap();
        }
        std::fs::write(
            dir.path().join("INCLUDE/group.dat"),
            "CARD G\nINCLUDE '../../BULK/x.blk'\n",
        )
        .unwrap();
        std::fs::write(dir.path().join("BULK/x.blk"), "CARD X\n").unwrap();
        dir
    }

    #[test]
    fn nested_include_falls_back_to_the_main_deck_directory() {
        let dir = msc_layout();
        let main = dir.path().join("JOBS/QS/main.dat");
        std::fs::write(&main, "INCLUDE '../../INCLUDE/group.dat'\nCARD M\n").unwrap();
        let (c, d) = walk(&main);
        assert!(d.is_ok(), "{:?}", d.errors);
        let texts: Vec<_> = c.0.iter().map(|(_, f, t)| format!("{f}:{t}")).collect();
        assert_eq!(
            texts,
            ["group.dat:CARD G", "x.blk:CARD X", "main.dat:CARD M"]
        );
    }

    #[test]
    fn include_found_nowhere_lists_every_path_tried() {
        let dir = msc_layout();
        std::fs::remove_file(dir.path().join("BULK/x.blk")).unwrap();
        let main = dir.path().join("JOBS/QS/main.dat");
        std::fs::write(&main, "INCLUDE '../../INCLUDE/group.dat'\n").unwrap();
        let (_, d) = walk(&main);
        assert_eq!(d.errors.len(), 1);
        let msg = d.errors[0].to_string();
        let beside_group = dir.path().join("JOBS/QS/../../INCLUDE/../../BULK/x.blk");
        let beside_main = dir.path().join("JOBS/QS/../../BULK/x.blk");
        assert!(
            msg.contains("group.dat:2: INCLUDE: cannot find '../../BULK/x.blk'")
                && msg.contains(&format!("'{}'", beside_group.display()))
                && msg.contains(&format!("'{}'", beside_main.display())),
            "{msg}"
        );
    }

    fn walk_with_symbols(path: &Path, symbols: &[(&str, PathBuf)]) -> (Collect, Diagnostics) {
        let table: Vec<(String, PathBuf)> = symbols
            .iter()
            .map(|(k, v)| (k.to_string(), v.clone()))
            .collect();
        let lookup = move |name: &str| {
            table
                .iter()
                .find(|(k, _)| k == name)
                .map(|(_, v)| v.clone())
        };
        let mut c = Collect(Vec::new());
        let mut d = Diagnostics::default();
        SourceWalker::with_symbols(Box::new(lookup)).walk(path, None, &mut c, &mut d);
        (c, d)
    }

    #[test]
    fn logical_symbols_name_directories() {
        let dir = msc_layout();
        let main = dir.path().join("JOBS/QS/main.dat");
        std::fs::write(
            &main,
            "INCLUDE 'MY_INC:group.dat'\nINCLUDE 'MY_BULK:x.blk'\n",
        )
        .unwrap();
        let symbols = [
            ("MY_INC", dir.path().join("INCLUDE")),
            ("MY_BULK", dir.path().join("BULK")),
        ];
        let (c, d) = walk_with_symbols(&main, &symbols);
        assert!(d.is_ok(), "{:?}", d.errors);
        let texts: Vec<_> = c.0.iter().map(|(_, f, t)| format!("{f}:{t}")).collect();
        assert_eq!(texts, ["group.dat:CARD G", "x.blk:CARD X", "x.blk:CARD X"]);
    }

    #[test]
    fn undefined_logical_symbol_is_named() {
        let dir = msc_layout();
        let main = dir.path().join("JOBS/QS/main.dat");
        std::fs::write(&main, "CARD M\nINCLUDE 'NO_SUCH_SYM:x.blk'\n").unwrap();
        let (_, d) = walk_with_symbols(&main, &[]);
        assert_eq!(d.errors.len(), 1);
        let msg = d.errors[0].to_string();
        assert!(
            msg.contains("main.dat:2: INCLUDE: logical symbol 'NO_SUCH_SYM'"),
            "{msg}"
        );
    }

    #[test]
    fn a_drive_letter_is_not_a_logical_symbol() {
        assert_eq!(logical_symbol("C:/x.bdf"), None);
        assert_eq!(logical_symbol("9AB:x.bdf"), None);
        assert_eq!(logical_symbol("A-B:x.bdf"), None);
        assert_eq!(logical_symbol("AB:x.bdf"), Some(("AB", "x.bdf")));
    }

    #[test]
    fn include_cycle_is_reported_with_the_chain() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("a.bdf"), "INCLUDE 'b.bdf'\n").unwrap();
        std::fs::write(dir.path().join("b.bdf"), "GRID,1\nINCLUDE 'a.bdf'\n").unwrap();
        let (_, d) = walk(&dir.path().join("a.bdf"));
        assert_eq!(d.errors.len(), 1);
        let msg = d.errors[0].to_string();
        assert!(
            msg.contains("b.bdf:2") && msg.contains("INCLUDE cycle"),
            "{msg}"
        );
    }

    #[test]
    fn missing_include_names_the_including_line() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("a.bdf"), "GRID,1\n\nINCLUDE 'nope.bdf'\n").unwrap();
        let (_, d) = walk(&dir.path().join("a.bdf"));
        assert!(
            d.errors[0]
                .to_string()
                .contains("a.bdf:3: INCLUDE: cannot read"),
            "{}",
            d.errors[0]
        );
    }

    #[test]
    fn multi_line_quoted_include() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::create_dir(dir.path().join("long")).unwrap();
        std::fs::write(dir.path().join("long/name.bdf"), "X\n").unwrap();
        std::fs::write(dir.path().join("a.bdf"), "INCLUDE 'long/\n name.bdf'\n").unwrap();
        let (c, d) = walk(&dir.path().join("a.bdf"));
        assert!(d.is_ok(), "{:?}", d.errors);
        assert_eq!(c.0.len(), 1);
    }

    #[test]
    fn binary_garbage_is_an_error_with_line() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("a.bdf"), b"GRID,1\n\x00\x01\xff\xfe\n").unwrap();
        let (_, d) = walk(&dir.path().join("a.bdf"));
        assert!(
            d.errors[0].to_string().contains("a.bdf:2"),
            "{}",
            d.errors[0]
        );
    }
}
