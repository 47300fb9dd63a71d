//! rustc's checking of a TRaX-Rust kernel: a kernel trax builds must be one that rustc
//! accepts, so moves, borrows, initialisation, exhaustiveness, `unsafe`, privacy and
//! lifetimes are checked by rustc itself rather than re-implemented.
//!
//! [`start`] runs `rustc --emit=metadata` (type checking and borrow checking, no code
//! generation) on the kernel against the metadata of the host prelude (the `trax` crate
//! `trax native` links, built once per prelude and rustc version into the build cache,
//! [`crate::clang::cache_dir`]) while the trax compiler works; [`Pending::finish`] maps
//! rustc's JSON diagnostics to trax's ([`Diagnostic`] with rustc's code, `error[E0382]`,
//! its primary span, labels, notes and help). A kernel rustc accepted is remembered in
//! `<cache>/rustc-check/<key>` (key: rustc version, prelude, working directory, kernel
//! path) with the content hash of every source file rustc read (its dep-info), so an
//! unchanged kernel costs one hash of its files.
//!
//! `TRAX_RUSTC_CHECK` chooses what happens ([`RustcCheck`]): `auto` (default) checks
//! when rustc can be run (`$RUSTC`, else `rustc` on `PATH`) and otherwise warns once and
//! builds with the trax compiler's own checks; `require` makes a missing rustc an error;
//! `off` skips the check.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::process::{Child, Stdio};
use std::sync::atomic::{AtomicBool, Ordering};

use serde::Deserialize;
use trax_compiler::diag::{Diagnostic, FileId, Loc, SourceMap};
use trax_runtime::prelude::{self, Fnv1a};

use super::{build_prelude_as, io_err, scratch_dir, NativeError, Rustc};

/// The environment variable that chooses the check ([`RustcCheck::from_env`]).
pub const ENV: &str = "TRAX_RUSTC_CHECK";

/// Whether and how a TRaX-Rust kernel is checked by rustc before trax builds it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum RustcCheck {
    /// Check when rustc can be run; without rustc, warn once and build unchecked.
    #[default]
    Auto,
    /// Check; a missing rustc is an error.
    Require,
    /// Do not check (the caller has rustc's verdict already, or the user chose so).
    Off,
}

impl RustcCheck {
    /// The setting of `TRAX_RUSTC_CHECK` (`auto`, `require` or `off`; unset or empty:
    /// `auto`).
    pub fn from_env() -> Result<RustcCheck, CheckError> {
        match std::env::var(ENV) {
            Err(_) => Ok(RustcCheck::Auto),
            Ok(v) => match v.as_str() {
                "" | "auto" => Ok(RustcCheck::Auto),
                "require" => Ok(RustcCheck::Require),
                "off" => Ok(RustcCheck::Off),
                _ => Err(CheckError::BadSetting(v)),
            },
        }
    }
}

/// Why rustc's check could not give a verdict.
#[derive(Debug, thiserror::Error)]
pub enum CheckError {
    /// `TRAX_RUSTC_CHECK` holds something else than `auto`, `require` or `off`.
    #[error("{ENV}={0:?}: expected `auto` (the default), `require` or `off`")]
    BadSetting(String),
    /// `TRAX_RUSTC_CHECK=require` and rustc cannot be run.
    #[error("{kernel}: {ENV}=require, but rustc cannot be run: {source}")]
    NoRustc {
        /// The kernel.
        kernel: String,
        /// Why (names the program tried).
        source: Box<NativeError>,
    },
    /// rustc failed without a diagnostic (a crash), or the prelude's metadata could not
    /// be built.
    #[error("{kernel}: rustc could not check the kernel (set {ENV}=off to build without rustc's checks):\n{detail}")]
    Failed {
        /// The kernel.
        kernel: String,
        /// rustc's output or the error.
        detail: String,
    },
}

/// rustc's verdict on a kernel.
#[derive(Debug)]
pub enum Verdict {
    /// rustc accepts the kernel.
    Accepted,
    /// rustc rejects the kernel: its errors as trax diagnostics.
    Rejected(Vec<Diagnostic>),
    /// Not checked (`TRAX_RUSTC_CHECK=off`, or no rustc under `auto`).
    Skipped,
}

/// A check under way ([`start`]); [`Pending::finish`] waits for its verdict.
pub struct Pending {
    state: State,
}

enum State {
    Done(Verdict),
    Running(Box<Running>),
}

struct Running {
    kernel: PathBuf,
    child: Child,
    tmp: PathBuf,
    entry: PathBuf,
}

/// Warned once per process that rustc is missing.
static WARNED: AtomicBool = AtomicBool::new(false);

/// Starts rustc's check of the kernel crate rooted at `kernel` (or finds its verdict in
/// the cache); the check runs in a child process until [`Pending::finish`].
pub fn start(kernel: &Path, mode: RustcCheck) -> Result<Pending, CheckError> {
    let done = |v| Pending {
        state: State::Done(v),
    };
    // An unreadable kernel is the trax compiler's to report (it names the file).
    if mode == RustcCheck::Off || !kernel.is_file() {
        return Ok(done(Verdict::Skipped));
    }
    let shown = || kernel.display().to_string();
    let rustc = match Rustc::find() {
        Ok(r) => r,
        Err(e) if mode == RustcCheck::Require => {
            return Err(CheckError::NoRustc {
                kernel: shown(),
                source: Box::new(e),
            })
        }
        Err(e) => {
            if !WARNED.swap(true, Ordering::Relaxed) {
                eprintln!(
                    "warning: {e}\n  = note: kernels are built without rustc's checks (moves, borrows, initialisation, exhaustiveness, `unsafe`), so `trax native` may refuse a kernel trax accepts; {ENV}=off silences this, {ENV}=require makes it an error"
                );
            }
            return Ok(done(Verdict::Skipped));
        }
    };
    let failed = |e: NativeError| CheckError::Failed {
        kernel: shown(),
        detail: e.to_string(),
    };
    let cache = crate::clang::cache_dir();
    let meta = build_prelude_as(&rustc, &cache, true).map_err(failed)?;
    let entry = cache.join("rustc-check").join(format!(
        "{:016x}",
        cache_key(&rustc, kernel).map_err(failed)?
    ));
    if still_valid(&entry) {
        return Ok(done(Verdict::Accepted));
    }
    let tmp = scratch_dir(&cache, "check").map_err(failed)?;
    let stderr = std::fs::File::create(tmp.join("stderr"))
        .map_err(io_err(&tmp))
        .map_err(failed)?;
    let child = rustc
        .command()
        .args([
            "--crate-type",
            "lib",
            "--crate-name",
            "trax_kernel",
            "--error-format=json",
            "-A",
            "warnings",
        ])
        .arg(format!(
            "--emit=metadata={},dep-info={}",
            tmp.join("kernel.rmeta").display(),
            tmp.join("kernel.d").display()
        ))
        .arg("--extern")
        .arg(format!("trax={}", meta.display()))
        .arg(kernel)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(stderr)
        .spawn();
    let child = match child {
        Ok(c) => c,
        Err(source) => {
            let _ = std::fs::remove_dir_all(&tmp);
            return Err(failed(NativeError::NoRustc {
                rustc: rustc.program.to_string_lossy().into_owned(),
                source,
            }));
        }
    };
    Ok(Pending {
        state: State::Running(Box::new(Running {
            kernel: kernel.to_path_buf(),
            child,
            tmp,
            entry,
        })),
    })
}

impl Pending {
    /// Waits for rustc and returns its verdict.
    pub fn finish(mut self) -> Result<Verdict, CheckError> {
        let r = match std::mem::replace(&mut self.state, State::Done(Verdict::Skipped)) {
            State::Done(v) => return Ok(v),
            State::Running(r) => r,
        };
        let Running {
            kernel,
            mut child,
            tmp,
            entry,
        } = *r;
        let result = (|| {
            let failed = |detail: String| CheckError::Failed {
                kernel: kernel.display().to_string(),
                detail,
            };
            let status = child.wait().map_err(|e| failed(e.to_string()))?;
            let out = std::fs::read(tmp.join("stderr")).map_err(|e| failed(e.to_string()))?;
            let out = String::from_utf8_lossy(&out);
            let files = std::fs::read_to_string(tmp.join("kernel.d"))
                .map(|d| dep_files(&d))
                .unwrap_or_default();
            let diags = diagnostics(&out, &files, &kernel);
            if !diags.is_empty() {
                return Ok(Verdict::Rejected(diags));
            }
            if !status.success() {
                return Err(failed(out.into_owned()));
            }
            remember(&entry, &files);
            Ok(Verdict::Accepted)
        })();
        let _ = std::fs::remove_dir_all(&tmp);
        result
    }
}

impl Drop for Pending {
    /// A check that is not finished (its caller panicked) stops rustc and leaves nothing.
    fn drop(&mut self) {
        if let State::Running(r) = &mut self.state {
            let _ = r.child.kill();
            let _ = r.child.wait();
            let _ = std::fs::remove_dir_all(&r.tmp);
        }
    }
}

/// What identifies one check besides its files' contents: the check's flags, rustc, the
/// prelude, the working directory (dep-info paths are relative to it) and the kernel.
fn cache_key(rustc: &Rustc, kernel: &Path) -> Result<u64, NativeError> {
    let cwd = std::env::current_dir().map_err(io_err(Path::new(".")))?;
    let mut h = Fnv1a::new();
    for part in [
        "trax-rustc-check/1".as_bytes(),
        rustc.version.as_bytes(),
        &prelude::content_hash().to_le_bytes(),
        cwd.as_os_str().as_encoded_bytes(),
        kernel.as_os_str().as_encoded_bytes(),
    ] {
        h.write(part);
        h.write(&[0]);
    }
    Ok(h.finish())
}

/// The content hash of `path` (`None`: unreadable).
fn file_hash(path: &Path) -> Option<u64> {
    let bytes = std::fs::read(path).ok()?;
    let mut h = Fnv1a::new();
    h.write(&bytes);
    Some(h.finish())
}

/// True when `entry` records a check whose every file still has its recorded hash.
fn still_valid(entry: &Path) -> bool {
    let Ok(text) = std::fs::read_to_string(entry) else {
        return false;
    };
    let mut any = false;
    for line in text.lines() {
        let Some((hash, path)) = line.split_once(' ') else {
            return false;
        };
        if file_hash(Path::new(path)).map(|h| format!("{h:016x}")) != Some(hash.to_string()) {
            return false;
        }
        any = true;
    }
    any
}

/// Records that rustc accepted a kernel made of `files` (best effort: a cache that
/// cannot be written only costs a check next time).
fn remember(entry: &Path, files: &[String]) {
    let mut text = String::new();
    for f in files {
        let Some(h) = file_hash(Path::new(f)) else {
            return;
        };
        text.push_str(&format!("{h:016x} {f}\n"));
    }
    if text.is_empty() {
        return;
    }
    let Some(dir) = entry.parent() else { return };
    let tmp = entry.with_extension(format!("tmp{}", std::process::id()));
    if std::fs::create_dir_all(dir).is_ok() && std::fs::write(&tmp, text).is_ok() {
        let _ = std::fs::rename(&tmp, entry);
    }
}

/// The files of a Makefile-style dep-info file (each listed as a target of its own,
/// `path:`; spaces escaped with `\`): the kernel's sources and what they include.
fn dep_files(d: &str) -> Vec<String> {
    let mut files: Vec<String> = d
        .lines()
        .filter(|l| !l.starts_with('#') && l.ends_with(':'))
        .map(|l| l[..l.len() - 1].replace("\\ ", " "))
        .collect();
    files.sort();
    files.dedup();
    files
}

/// One diagnostic of rustc's `--error-format=json`.
#[derive(Deserialize)]
struct RDiag {
    message: String,
    code: Option<RCode>,
    level: String,
    #[serde(default)]
    spans: Vec<RSpan>,
    #[serde(default)]
    children: Vec<RDiag>,
}

#[derive(Deserialize)]
struct RCode {
    code: String,
}

#[derive(Clone, Deserialize)]
struct RSpan {
    file_name: String,
    line_start: u32,
    line_end: u32,
    column_start: u32,
    column_end: u32,
    is_primary: bool,
    label: Option<String>,
    suggested_replacement: Option<String>,
    expansion: Option<Box<RExpansion>>,
}

#[derive(Clone, Deserialize)]
struct RExpansion {
    span: RSpan,
}

impl RSpan {
    fn loc(&self) -> Loc {
        Loc {
            line: self.line_start,
            col: self.column_start,
            end_line: self.line_end,
            end_col: self.column_end,
        }
    }

    /// This span if it is in one of the kernel's `files`, else the innermost macro call
    /// in them that produced it (a span inside `println!` is shown at the call).
    fn in_kernel(&self, files: &[String]) -> Option<RSpan> {
        let mut s = self;
        loop {
            if files.contains(&s.file_name) {
                return Some(s.clone());
            }
            s = &s.expansion.as_ref()?.span;
        }
    }

    fn label(&self) -> &str {
        self.label.as_deref().unwrap_or("")
    }
}

/// The kernel's files loaded for rendering source lines.
struct Sources {
    map: SourceMap,
    ids: HashMap<String, FileId>,
}

impl Sources {
    fn id(&mut self, file: &str) -> FileId {
        if let Some(&id) = self.ids.get(file) {
            return id;
        }
        let text = std::fs::read_to_string(file).unwrap_or_default();
        let id = self.map.add(PathBuf::from(file), text);
        self.ids.insert(file.to_string(), id);
        id
    }
}

/// rustc's errors in `out` (its JSON lines; warnings and summaries dropped) as trax
/// diagnostics. `files` are the kernel's sources (rustc's dep-info); a diagnostic
/// without a span in them is placed at the top of `kernel`.
fn diagnostics(out: &str, files: &[String], kernel: &Path) -> Vec<Diagnostic> {
    let mut files = files.to_vec();
    let root = kernel.display().to_string();
    if !files.contains(&root) {
        files.push(root);
    }
    let mut sources = Sources {
        map: SourceMap::default(),
        ids: HashMap::new(),
    };
    out.lines()
        .filter_map(|l| serde_json::from_str::<RDiag>(l).ok())
        .filter(|d| d.level == "error" && !d.message.starts_with("aborting due to"))
        .map(|d| convert(&d, &files, kernel, &mut sources))
        .collect()
}

/// One rustc error as a trax diagnostic.
fn convert(d: &RDiag, files: &[String], kernel: &Path, src: &mut Sources) -> Diagnostic {
    let primary = d
        .spans
        .iter()
        .filter(|s| s.is_primary)
        .find_map(|s| s.in_kernel(files));
    let mut diag = match &primary {
        Some(p) => {
            let id = src.id(&p.file_name);
            Diagnostic::at(&src.map, id, p.loc(), "rustc", d.message.clone()).with_label(p.label())
        }
        None => Diagnostic::file_level(kernel, "rustc", d.message.clone()),
    };
    if let Some(c) = &d.code {
        // Lints (`arithmetic_overflow`) name themselves in a note, as rustc does.
        if is_error_code(&c.code) {
            diag = diag.with_code(c.code.clone());
        } else {
            diag = diag.with_note(format!("`#[deny({})]` on by default", c.code));
        }
    }
    let same_file = |s: &RSpan| primary.as_ref().is_some_and(|p| p.file_name == s.file_name);
    // Secondary spans: marked in the excerpt when in the primary's file, else a note.
    let mut marks: Vec<(RSpan, String)> = Vec::new();
    for s in d.spans.iter().filter(|s| !s.is_primary) {
        if let Some(k) = s.in_kernel(files) {
            let text = s.label().to_string();
            if k.loc() != primary.as_ref().map(RSpan::loc).unwrap_or_default() {
                marks.push((k, text));
            }
        }
    }
    for c in &d.children {
        let mut text = c.message.clone();
        let suggestion: Vec<String> = c
            .spans
            .iter()
            .filter_map(|s| s.suggested_replacement.as_deref())
            .map(one_line)
            .filter(|s| !s.is_empty())
            .collect();
        if !suggestion.is_empty() {
            text = format!("{text}: `{}`", suggestion.join("`, `"));
        } else {
            // A note about a place in the kernel: a mark there, labelled with the note.
            let spans: Vec<RSpan> = c.spans.iter().filter_map(|s| s.in_kernel(files)).collect();
            if !spans.is_empty() && spans.iter().all(same_file) {
                for s in &spans {
                    let label = if s.is_primary && s.label().is_empty() {
                        c.message.clone()
                    } else {
                        s.label().to_string()
                    };
                    marks.push((s.clone(), label));
                }
                continue;
            }
            if let Some(s) = spans.first() {
                text = format!(
                    "{text} ({}:{}:{})",
                    s.file_name, s.line_start, s.column_start
                );
            }
        }
        diag = if c.level == "help" {
            diag.with_help(text)
        } else {
            diag.with_note(text)
        };
    }
    for (s, text) in marks {
        if same_file(&s) {
            let id = src.id(&s.file_name);
            diag = diag.with_secondary(&src.map, id, s.loc(), text);
        } else {
            diag = diag.with_note(format!(
                "{text} ({}:{}:{})",
                s.file_name, s.line_start, s.column_start
            ));
        }
    }
    if d.message.starts_with("cannot find macro `__trax_") {
        diag = diag.with_help(
            "the `__trax_*` macros are the prelude's machine-side internals, which `trax native` does not have; use the prelude's API instead (`trax::stat::add` for statistics counters; docs/LANGUAGE.md)",
        );
    }
    diag
}

/// rustc's error codes are `E` and four digits; other codes are lint names.
fn is_error_code(code: &str) -> bool {
    code.len() == 5 && code.starts_with('E') && code[1..].bytes().all(|b| b.is_ascii_digit())
}

/// A suggested replacement on one line: lines trimmed and joined, a leading `,` dropped.
fn one_line(s: &str) -> String {
    let joined: Vec<&str> = s.lines().map(str::trim).filter(|l| !l.is_empty()).collect();
    joined.join(" ").trim_start_matches(',').trim().to_string()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dep_info_lists_sources() {
        let d = "out.rmeta: k.rs m/a\\ b.rs\n\nk.rs:\nm/a\\ b.rs:\n# env-dep:X\n";
        assert_eq!(
            dep_files(d),
            vec!["k.rs".to_string(), "m/a b.rs".to_string()]
        );
    }

    #[test]
    fn codes_and_lints_are_told_apart() {
        assert!(is_error_code("E0382"));
        assert!(!is_error_code("arithmetic_overflow"));
        assert!(!is_error_code("E038"));
    }

    #[test]
    fn suggestions_fold_to_one_line() {
        assert_eq!(
            one_line(",\n        Material::Glass => todo!()"),
            "Material::Glass => todo!()"
        );
    }
}
