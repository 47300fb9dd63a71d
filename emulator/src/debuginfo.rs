//! PC -> source frames (file:line:col, function, inline chain) from the executable's DWARF,
//! built once and shared by crash reports, the disassembler, the profiler and the debugger.

use std::borrow::Cow;
use std::collections::HashMap;
use std::path::Path;
use std::sync::{Arc, Mutex};

use object::{Object, ObjectSection};

type Reader = gimli::EndianArcSlice<gimli::RunTimeEndian>;

/// One source frame: innermost (possibly inlined) function first.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SourceFrame {
    /// Function name (demangled), if known.
    pub function: Option<String>,
    /// Source file path, if known.
    pub file: Option<String>,
    /// Line (1-based), 0 if unknown.
    pub line: u32,
    /// Column (1-based), 0 if unknown.
    pub column: u32,
    /// True if this frame is a function inlined into the next one.
    pub inlined: bool,
}

impl SourceFrame {
    /// `file:line:col` (parts that are unknown are left out).
    pub fn location(&self) -> String {
        let mut s = self.file.clone().unwrap_or_else(|| "??".into());
        if self.line != 0 {
            s += &format!(":{}", self.line);
            if self.column != 0 {
                s += &format!(":{}", self.column);
            }
        }
        s
    }
}

/// Errors reading debug information.
#[derive(Debug, thiserror::Error)]
pub enum DebugInfoError {
    /// The ELF could not be parsed.
    #[error("{path}: {msg}")]
    Elf { path: String, msg: String },
    /// The DWARF is malformed.
    #[error("{path}: bad DWARF: {msg}")]
    Dwarf { path: String, msg: String },
}

/// The PC -> frames index of one executable.
pub struct DebugInfo {
    ctx: Option<addr2line::Context<Reader>>,
    cache: Mutex<HashMap<u32, Arc<[SourceFrame]>>>,
    sources: Mutex<HashMap<String, Option<Arc<Vec<String>>>>>,
}

impl std::fmt::Debug for DebugInfo {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("DebugInfo")
            .field("has_dwarf", &self.ctx.is_some())
            .finish()
    }
}

/// The text of source file `file` as DWARF names it: a prelude file's from the prelude
/// embedded in this trax, any other file's from disk.
fn source_text(file: &str) -> Option<String> {
    let embedded = Path::new(file)
        .strip_prefix(trax_runtime::prelude::DIR)
        .ok()
        .and_then(|rel| trax_runtime::prelude::file(rel.to_str()?));
    match embedded {
        Some(s) => Some(s.to_string()),
        None => std::fs::read_to_string(file).ok(),
    }
}

impl DebugInfo {
    /// Reads the DWARF of an ELF file (an ELF without DWARF gives an empty index).
    pub fn parse(path: &str, data: &[u8]) -> Result<DebugInfo, DebugInfoError> {
        let file = object::File::parse(data).map_err(|e| DebugInfoError::Elf {
            path: path.into(),
            msg: e.to_string(),
        })?;
        let endian = if file.is_little_endian() {
            gimli::RunTimeEndian::Little
        } else {
            gimli::RunTimeEndian::Big
        };
        let has_info = file.section_by_name(".debug_info").is_some();
        let ctx = if has_info {
            let load = |id: gimli::SectionId| -> Result<Reader, gimli::Error> {
                let data: Cow<[u8]> = file
                    .section_by_name(id.name())
                    .and_then(|s| s.uncompressed_data().ok())
                    .unwrap_or(Cow::Borrowed(&[]));
                Ok(gimli::EndianArcSlice::new(Arc::from(&*data), endian))
            };
            let dwarf = gimli::Dwarf::load(load).map_err(|e| DebugInfoError::Dwarf {
                path: path.into(),
                msg: e.to_string(),
            })?;
            Some(
                addr2line::Context::from_dwarf(dwarf).map_err(|e| DebugInfoError::Dwarf {
                    path: path.into(),
                    msg: e.to_string(),
                })?,
            )
        } else {
            None
        };
        Ok(DebugInfo {
            ctx,
            cache: Mutex::new(HashMap::new()),
            sources: Mutex::new(HashMap::new()),
        })
    }

    /// True if the executable has DWARF line information.
    pub fn has_dwarf(&self) -> bool {
        self.ctx.is_some()
    }

    /// Source frames at `pc`, innermost first (empty when unknown). Memoized.
    pub fn frames(&self, pc: u32) -> Arc<[SourceFrame]> {
        if let Some(f) = self.cache.lock().ok().and_then(|c| c.get(&pc).cloned()) {
            return f;
        }
        let frames: Arc<[SourceFrame]> = self.lookup(pc).into();
        if let Ok(mut c) = self.cache.lock() {
            c.insert(pc, frames.clone());
        }
        frames
    }

    fn lookup(&self, pc: u32) -> Vec<SourceFrame> {
        let Some(ctx) = &self.ctx else {
            return Vec::new();
        };
        let mut out = Vec::new();
        let Ok(mut iter) = ctx.find_frames(pc as u64).skip_all_loads() else {
            return out;
        };
        while let Ok(Some(frame)) = iter.next() {
            let function = frame
                .function
                .as_ref()
                .and_then(|f| f.demangle().ok())
                .map(|s| s.into_owned());
            let (file, line, column) = match &frame.location {
                Some(l) => (
                    l.file.map(str::to_string),
                    l.line.unwrap_or(0),
                    l.column.unwrap_or(0),
                ),
                None => (None, 0, 0),
            };
            out.push(SourceFrame {
                function,
                file,
                line,
                column,
                inlined: true,
            });
        }
        if let Some(last) = out.last_mut() {
            last.inlined = false;
        }
        if out.is_empty() {
            if let Ok(Some(l)) = ctx.find_location(pc as u64) {
                out.push(SourceFrame {
                    function: None,
                    file: l.file.map(str::to_string),
                    line: l.line.unwrap_or(0),
                    column: l.column.unwrap_or(0),
                    inlined: false,
                });
            }
        }
        out
    }

    /// The text of `file` at `line` (1-based), if the file can be read. Files are cached.
    /// Prelude files are read from the prelude this trax was built with (the one the
    /// kernel was compiled against), not from the disk path DWARF names, which may have
    /// changed since or not exist where trax is installed.
    pub fn source_line(&self, file: &str, line: u32) -> Option<String> {
        if line == 0 {
            return None;
        }
        let mut cache = self.sources.lock().ok()?;
        let lines = cache
            .entry(file.to_string())
            .or_insert_with(|| {
                source_text(file).map(|s| Arc::new(s.lines().map(str::to_string).collect()))
            })
            .clone()?;
        lines.get(line as usize - 1).cloned()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn prelude_sources_are_the_embedded_ones() {
        let dir = trax_runtime::prelude::DIR;
        for (rel, text) in trax_runtime::prelude::FILES {
            assert_eq!(
                source_text(&format!("{dir}/{rel}")).as_deref(),
                Some(*text),
                "{rel}"
            );
        }
        // Other files come from disk; a missing one is no text, not an error.
        let me = concat!(env!("CARGO_MANIFEST_DIR"), "/src/debuginfo.rs");
        assert!(source_text(me)
            .unwrap()
            .contains("fn prelude_sources_are_the_embedded_ones"));
        assert_eq!(source_text(&format!("{dir}/no_such_file.rs")), None);
    }
}
