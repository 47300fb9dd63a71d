//! Diagnostics: source files, locations and rendered error messages.

use std::fmt;
use std::path::{Path, PathBuf};

/// Index of a loaded source file in the [`SourceMap`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct FileId(pub u32);

/// One loaded source file.
#[derive(Debug)]
pub struct SourceFile {
    /// Path shown in diagnostics (as the user named it, or the prelude's absolute path).
    pub display: PathBuf,
    /// Full text.
    pub src: String,
}

/// All source files of a compilation.
#[derive(Debug, Default)]
pub struct SourceMap {
    files: Vec<SourceFile>,
}

impl SourceMap {
    /// Adds a file and returns its id.
    pub fn add(&mut self, display: PathBuf, src: String) -> FileId {
        self.files.push(SourceFile { display, src });
        FileId(self.files.len() as u32 - 1)
    }

    /// The file with this id.
    pub fn get(&self, id: FileId) -> &SourceFile {
        &self.files[id.0 as usize]
    }

    /// Number of files.
    pub fn len(&self) -> usize {
        self.files.len()
    }

    /// True when no file is loaded.
    pub fn is_empty(&self) -> bool {
        self.files.is_empty()
    }
}

/// A source position with 1-based line and column (columns count characters).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct Loc {
    /// 1-based line.
    pub line: u32,
    /// 1-based column.
    pub col: u32,
    /// 1-based line of the end of the span.
    pub end_line: u32,
    /// 1-based column just past the end of the span.
    pub end_col: u32,
}

impl Loc {
    /// Converts a proc-macro2 span (0-based columns) to a 1-based location.
    ///
    /// This is the only place where the column base is converted.
    ///
    /// A span without a location (line 0: synthesized tokens, or proc-macro2 without
    /// location tracking) has column 0 too, as DWARF requires (LLVM rejects a lexical block
    /// with a column but no line: fuzzing found this as an internal compiler error).
    pub fn of(span: proc_macro2::Span) -> Loc {
        let s = span.start();
        let e = span.end();
        let col = |line: usize, column: usize| if line == 0 { 0 } else { column as u32 + 1 };
        Loc {
            line: s.line as u32,
            col: col(s.line, s.column),
            end_line: e.line as u32,
            end_col: col(e.line, e.column),
        }
    }

    /// The location of the byte range `start..end` of `src` (columns count characters;
    /// offsets inside a character count as that character).
    pub fn of_bytes(src: &str, start: usize, end: usize) -> Loc {
        let (line, col) = line_col(src, start);
        let (end_line, end_col) = line_col(src, end.max(start));
        Loc {
            line,
            col,
            end_line,
            end_col,
        }
    }
}

/// 1-based line and column (in characters) of byte offset `off` of `src`.
fn line_col(src: &str, off: usize) -> (u32, u32) {
    let off = off.min(src.len());
    let mut b = off;
    while !src.is_char_boundary(b) {
        b -= 1;
    }
    let before = &src[..b];
    let line = before.matches('\n').count() as u32 + 1;
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    (line, src[line_start..b].chars().count() as u32 + 1)
}

/// A secondary span of a diagnostic, marked with `-` and a text.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Label {
    /// Location (same file as the diagnostic).
    pub loc: Loc,
    /// Text shown after the marks.
    pub text: String,
    /// The text of the source line at `loc.line`.
    pub source_line: String,
}

/// A compile error at a source location, fully rendered-ready.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Diagnostic {
    /// Stable kebab-case identifier, e.g. `unsupported-generics`.
    pub id: &'static str,
    /// Human message naming the construct.
    pub message: String,
    /// File path as displayed.
    pub file: PathBuf,
    /// Location.
    pub loc: Loc,
    /// The text of the source line at `loc.line`.
    pub source_line: String,
    /// Labels, secondary spans and notes (boxed: most diagnostics have none).
    pub extra: Box<Extra>,
}

/// The optional parts of a [`Diagnostic`].
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Extra {
    /// Text shown after the primary carets (empty: none).
    pub label: String,
    /// Other spans of the same file that explain the error.
    pub secondary: Vec<Label>,
    /// `= note:` lines after the source excerpt.
    pub notes: Vec<String>,
    /// `= help:` lines after the notes.
    pub helps: Vec<String>,
    /// rustc's error code (`E0382`) when rustc found the error; shown in place of the id.
    pub code: Option<String>,
    /// Unmarked source lines shown between two marked ones `(line, text)`.
    pub context: Vec<(u32, String)>,
}

impl Diagnostic {
    /// Builds a diagnostic for `span` in `file`.
    pub fn new(
        sources: &SourceMap,
        file: FileId,
        span: proc_macro2::Span,
        id: &'static str,
        message: impl Into<String>,
    ) -> Diagnostic {
        Diagnostic::at(sources, file, Loc::of(span), id, message)
    }

    /// Builds a diagnostic for location `loc` in `file`.
    pub fn at(
        sources: &SourceMap,
        file: FileId,
        loc: Loc,
        id: &'static str,
        message: impl Into<String>,
    ) -> Diagnostic {
        let f = sources.get(file);
        Diagnostic {
            id,
            message: message.into(),
            file: f.display.clone(),
            loc,
            source_line: source_line(&f.src, loc.line),
            extra: Box::default(),
        }
    }

    /// A diagnostic about a whole file (e.g. it cannot be read), pointing at line 1.
    pub fn file_level(file: &Path, id: &'static str, message: impl Into<String>) -> Diagnostic {
        Diagnostic {
            id,
            message: message.into(),
            file: file.to_path_buf(),
            loc: Loc {
                line: 1,
                col: 1,
                end_line: 1,
                end_col: 1,
            },
            source_line: String::new(),
            extra: Box::default(),
        }
    }

    /// Sets the text shown after the primary carets.
    pub fn with_label(mut self, text: impl Into<String>) -> Diagnostic {
        self.extra.label = text.into();
        self
    }

    /// Adds a secondary span at `loc` of `file` (the diagnostic's own file).
    pub fn with_secondary(
        mut self,
        sources: &SourceMap,
        file: FileId,
        loc: Loc,
        text: impl Into<String>,
    ) -> Diagnostic {
        let src = &sources.get(file).src;
        let x = &mut self.extra;
        x.secondary.push(Label {
            loc,
            text: text.into(),
            source_line: source_line(src, loc.line),
        });
        let mut lines: Vec<u32> = x.secondary.iter().map(|l| l.loc.line).collect();
        lines.push(self.loc.line);
        lines.sort_unstable();
        lines.dedup();
        x.context = lines
            .windows(2)
            .filter(|w| w[1] == w[0] + 2)
            .map(|w| (w[0] + 1, source_line(src, w[0] + 1)))
            .collect();
        self
    }

    /// Adds a `= note:` line.
    pub fn with_note(mut self, text: impl Into<String>) -> Diagnostic {
        self.extra.notes.push(text.into());
        self
    }

    /// Adds a `= help:` line.
    pub fn with_help(mut self, text: impl Into<String>) -> Diagnostic {
        self.extra.helps.push(text.into());
        self
    }

    /// Sets rustc's error code, shown as `error[CODE]` in place of the id.
    pub fn with_code(mut self, code: impl Into<String>) -> Diagnostic {
        self.extra.code = Some(code.into());
        self
    }

    /// What the heading shows in brackets: rustc's code, else the id.
    pub fn code_or_id(&self) -> &str {
        self.extra.code.as_deref().unwrap_or(self.id)
    }
}

/// Line `line` (1-based) of `src` without its line terminator.
fn source_line(src: &str, line: u32) -> String {
    src.lines()
        .nth(line.saturating_sub(1) as usize)
        .unwrap_or("")
        .to_string()
}

/// One span to draw under a source line.
struct Mark<'a> {
    loc: Loc,
    source_line: &'a str,
    text: &'a str,
    primary: bool,
}

impl Mark<'_> {
    /// The marker line (`   ^^^ text`) under the source line, without the gutter.
    fn render(&self) -> String {
        let chars = self.source_line.chars().count() as u32;
        let start = self.loc.col.saturating_sub(1);
        let end = if self.loc.end_line == self.loc.line {
            self.loc.end_col.saturating_sub(1)
        } else {
            chars
        };
        let width = end.saturating_sub(start).max(1) as usize;
        // Keep tabs so the marks line up under tab-indented code.
        let lead: String = self
            .source_line
            .chars()
            .chain(std::iter::repeat(' '))
            .take(start as usize)
            .map(|c| if c == '\t' { '\t' } else { ' ' })
            .collect();
        let mark = if self.primary { "^" } else { "-" };
        let mut s = format!("{lead}{}", mark.repeat(width));
        if !self.text.is_empty() {
            s.push(' ');
            s.push_str(self.text);
        }
        s
    }
}

impl fmt::Display for Diagnostic {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let mut marks = vec![Mark {
            loc: self.loc,
            source_line: &self.source_line,
            text: &self.extra.label,
            primary: true,
        }];
        marks.extend(self.extra.secondary.iter().map(|l| Mark {
            loc: l.loc,
            source_line: &l.source_line,
            text: &l.text,
            primary: false,
        }));
        // Stable: marks of one line keep primary-first order.
        marks.sort_by_key(|m| m.loc.line);
        let widest = marks.iter().map(|m| m.loc.line).max().unwrap_or(1);
        let pad = " ".repeat(widest.to_string().len());
        writeln!(f, "error[{}]: {}", self.code_or_id(), self.message)?;
        writeln!(
            f,
            "{pad}--> {}:{}:{}",
            self.file.display(),
            self.loc.line,
            self.loc.col
        )?;
        if self.source_line.is_empty() && self.extra.secondary.is_empty() {
            return self.write_notes(f, &pad);
        }
        writeln!(f, "{pad} |")?;
        let mut prev: Option<u32> = None;
        for m in &marks {
            let line = m.loc.line;
            if prev != Some(line) {
                match prev {
                    // One unmarked line between two marked ones is shown; more are elided.
                    Some(p) if line == p + 2 => {
                        if let Some((_, gap)) = self.extra.context.iter().find(|c| c.0 == p + 1) {
                            writeln!(f, "{:>w$} | {gap}", p + 1, w = pad.len())?;
                        }
                    }
                    Some(p) if line > p + 2 => writeln!(f, "...")?,
                    _ => {}
                }
                writeln!(f, "{line:>w$} | {}", m.source_line, w = pad.len())?;
            }
            writeln!(f, "{pad} | {}", m.render())?;
            prev = Some(line);
        }
        self.write_notes(f, &pad)
    }
}

impl Diagnostic {
    /// The `= note:` and `= help:` lines.
    fn write_notes(&self, f: &mut fmt::Formatter<'_>, pad: &str) -> fmt::Result {
        for n in &self.extra.notes {
            writeln!(f, "{pad} = note: {n}")?;
        }
        for h in &self.extra.helps {
            writeln!(f, "{pad} = help: {h}")?;
        }
        Ok(())
    }
}

/// Shorthand for stage results.
pub type DResult<T> = Result<T, Diagnostic>;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn renders_location_source_line_and_caret() {
        let d = Diagnostic {
            id: "unsupported-closure",
            message: "closures are not supported".into(),
            file: PathBuf::from("k.rs"),
            loc: Loc {
                line: 12,
                col: 13,
                end_line: 12,
                end_col: 17,
            },
            source_line: "    let f = |x| x;".into(),
            extra: Box::default(),
        };
        let s = d.to_string();
        let expected = "error[unsupported-closure]: closures are not supported\n  --> k.rs:12:13\n   |\n12 |     let f = |x| x;\n   |             ^^^^\n";
        assert_eq!(s, expected);
    }

    #[test]
    fn renders_secondary_spans_labels_gaps_and_notes() {
        let mut sm = SourceMap::default();
        let src = "fn f() {\n    let a = [1, 2;\n    let b = 3;\n}\n";
        let id = sm.add(PathBuf::from("k.rs"), src.to_string());
        let at = |line, col| Loc {
            line,
            col,
            end_line: line,
            end_col: col + 1,
        };
        let d = Diagnostic::at(&sm, id, at(2, 13), "x", "mismatched")
            .with_label("unclosed delimiter")
            .with_secondary(&sm, id, at(4, 1), "mismatched closing delimiter")
            .with_secondary(&sm, id, at(1, 8), "possibly meant for this")
            .with_note("a note");
        let expected = "error[x]: mismatched\n --> k.rs:2:13\n  |\n1 | fn f() {\n  |        - possibly meant for this\n2 |     let a = [1, 2;\n  |             ^ unclosed delimiter\n3 |     let b = 3;\n4 | }\n  | - mismatched closing delimiter\n  = note: a note\n";
        assert_eq!(d.to_string(), expected);
        // Byte offsets to locations: columns count characters.
        let l = Loc::of_bytes("ab\né x", 5, 6);
        assert_eq!((l.line, l.col, l.end_line, l.end_col), (2, 2, 2, 3));
    }

    #[test]
    fn spans_convert_to_one_based_columns() {
        let f: syn::File = syn::parse_str("fn a() {}\n  fn b() {}").unwrap();
        let syn::Item::Fn(b) = &f.items[1] else {
            panic!("fn")
        };
        let l = Loc::of(b.sig.ident.span());
        assert_eq!((l.line, l.col, l.end_col), (2, 6, 7));
    }

    /// A span without a line (proc-macro2's call site has line 0 or 1, depending on its
    /// build) must not get a column: LLVM rejects such debug locations.
    #[test]
    fn a_span_without_a_line_has_no_column() {
        let l = Loc::of(proc_macro2::Span::call_site());
        assert!(l.line > 0 || l.col == 0, "{l:?}");
        assert!(l.end_line > 0 || l.end_col == 0, "{l:?}");
    }
}
