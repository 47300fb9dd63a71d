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
        let f = sources.get(file);
        let loc = Loc::of(span);
        let source_line = f
            .src
            .lines()
            .nth(loc.line.saturating_sub(1) as usize)
            .unwrap_or("")
            .to_string();
        Diagnostic {
            id,
            message: message.into(),
            file: f.display.clone(),
            loc,
            source_line,
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
        }
    }
}

impl fmt::Display for Diagnostic {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let line_no = self.loc.line.to_string();
        let pad = " ".repeat(line_no.len());
        writeln!(f, "error[{}]: {}", self.id, self.message)?;
        writeln!(
            f,
            "{pad}--> {}:{}:{}",
            self.file.display(),
            self.loc.line,
            self.loc.col
        )?;
        if self.source_line.is_empty() {
            return Ok(());
        }
        writeln!(f, "{pad} |")?;
        writeln!(f, "{line_no} | {}", self.source_line)?;
        let chars = self.source_line.chars().count() as u32;
        let start = self.loc.col.saturating_sub(1);
        let end = if self.loc.end_line == self.loc.line {
            self.loc.end_col.saturating_sub(1)
        } else {
            chars
        };
        let width = end.saturating_sub(start).max(1) as usize;
        // Keep tabs so the caret lines up under tab-indented code.
        let lead: String = self
            .source_line
            .chars()
            .take(start as usize)
            .map(|c| if c == '\t' { '\t' } else { ' ' })
            .collect();
        writeln!(f, "{pad} | {lead}{}", "^".repeat(width))
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
        };
        let s = d.to_string();
        let expected = "error[unsupported-closure]: closures are not supported\n  --> k.rs:12:13\n   |\n12 |     let f = |x| x;\n   |             ^^^^\n";
        assert_eq!(s, expected);
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
