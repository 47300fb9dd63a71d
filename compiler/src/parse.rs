//! Stage 1: read and parse the kernel crate and the prelude crate with `syn`, following
//! `mod x;` declarations to their files and evaluating `#[cfg]` on items.

use crate::diag::{DResult, Diagnostic, FileId, SourceMap};
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use syn::punctuated::Punctuated;
use syn::{Attribute, Expr, Item, ItemMod, Lit, Meta, Token};

/// Where a crate's files come from.
pub enum CrateSource<'s> {
    /// The root file on disk; `mod` files are found relative to it.
    Disk(PathBuf),
    /// In-memory files `(path relative to the crate directory, text)`, root `lib.rs`,
    /// displayed under `dir`.
    Memory {
        /// Files of the crate.
        files: &'s [(&'s str, &'s str)],
        /// Directory shown in diagnostics and DWARF.
        dir: PathBuf,
    },
}

/// One parsed crate.
pub struct ParsedCrate {
    /// Root file.
    pub root: FileId,
    /// Parsed files by id (boxed so item addresses are stable).
    pub files: HashMap<FileId, Box<syn::File>>,
    /// For every out-of-line `mod x;` (by address of its `ItemMod`), the file it loads.
    pub mod_files: HashMap<usize, FileId>,
}

/// Parses a crate from `source`, adding its files to `sources`.
pub fn parse_crate(sources: &mut SourceMap, source: &CrateSource<'_>) -> DResult<ParsedCrate> {
    let (root_rel, display_root) = match source {
        CrateSource::Disk(p) => (p.clone(), p.clone()),
        CrateSource::Memory { dir, .. } => (PathBuf::from("lib.rs"), dir.join("lib.rs")),
    };
    let mut pc = ParsedCrate {
        root: FileId(0),
        files: HashMap::new(),
        mod_files: HashMap::new(),
    };
    let root_text = read(source, &root_rel, &display_root, None)?;
    pc.root = load_file(
        sources,
        source,
        &mut pc,
        root_rel,
        display_root,
        root_text,
        true,
    )?;
    Ok(pc)
}

/// Why a file could not be read.
enum ReadError {
    /// Missing or unreadable (the I/O error's text, if any).
    Missing(Option<std::io::Error>),
    /// Read, but not UTF-8: the diagnostic says where.
    NotUtf8(Diagnostic),
}

fn read(
    source: &CrateSource<'_>,
    rel: &Path,
    display: &Path,
    at: Option<(&SourceMap, FileId, &ItemMod)>,
) -> DResult<String> {
    let found = match source {
        CrateSource::Disk(_) => match std::fs::read(rel) {
            Ok(bytes) => String::from_utf8(bytes)
                .map_err(|e| ReadError::NotUtf8(not_utf8(display, e.as_bytes(), e.utf8_error()))),
            Err(e) => Err(ReadError::Missing(Some(e))),
        },
        CrateSource::Memory { files, .. } => files
            .iter()
            .find(|(p, _)| normalize(Path::new(p)) == normalize(rel))
            .map(|(_, s)| s.to_string())
            .ok_or(ReadError::Missing(None)),
    };
    found.map_err(|e| match (e, at) {
        (ReadError::NotUtf8(d), _) => d,
        (ReadError::Missing(_), Some((sm, file, item))) => Diagnostic::new(
            sm,
            file,
            item.ident.span(),
            "module-file-not-found",
            format!(
                "file not found for module `{}`: {}",
                item.ident,
                display.display()
            ),
        ),
        (ReadError::Missing(io), None) => Diagnostic::file_level(
            display,
            "file-not-found",
            match io {
                Some(e) => format!("cannot read {}: {e}", display.display()),
                None => format!("cannot read {}", display.display()),
            },
        ),
    })
}

/// The diagnostic for a file whose bytes are not UTF-8: the first bad byte's offset, line
/// and column (characters before it on its line, decoded lossily).
fn not_utf8(display: &Path, bytes: &[u8], e: std::str::Utf8Error) -> Diagnostic {
    let off = e.valid_up_to();
    let line_start = bytes[..off]
        .iter()
        .rposition(|&b| b == b'\n')
        .map_or(0, |i| i + 1);
    let line_end = bytes[off..]
        .iter()
        .position(|&b| b == b'\n')
        .map_or(bytes.len(), |i| off + i);
    let line = bytes[..off].iter().filter(|&&b| b == b'\n').count() as u32 + 1;
    let col = String::from_utf8_lossy(&bytes[line_start..off])
        .chars()
        .count() as u32
        + 1;
    let bad = bytes[off];
    let mut d = Diagnostic::file_level(
        display,
        "invalid-source-encoding",
        format!(
            "{} is not valid UTF-8: byte 0x{bad:02x} at byte offset {off} (line {line}, column {col})",
            display.display()
        ),
    );
    d.loc = crate::diag::Loc {
        line,
        col,
        end_line: line,
        end_col: col + 1,
    };
    d.source_line = String::from_utf8_lossy(&bytes[line_start..line_end])
        .trim_end_matches('\r')
        .to_string();
    d.with_label(format!("byte 0x{bad:02x} is not valid UTF-8"))
        .with_note("Rust source files must be UTF-8 text")
}

/// How deep a file's syntax may nest ([`check_nesting`]'s measure): syn's parser and
/// every pass of the compiler recurse once per level, on the compiler thread's stack
/// (`COMPILER_STACK_BYTES`); 10^6 levels overflowed it. Real kernels nest a few dozen;
/// `tests/robustness.rs` compiles each kind of nesting at this depth.
pub const MAX_NESTING: usize = 20_000;

/// Refuses a file whose syntax nests deeper than [`MAX_NESTING`], counted on its tokens
/// before syn parses them (an upper bound on the depth of the tree syn would build):
/// a bracketed group is one level below its opening, and within a statement every
/// operator and `else` one more (`a + b + c` and `else if` chains nest one level per
/// link); `;`, `,` and a block that ends a statement or item start again at the group's
/// level. Files the lexer refuses are left to syn's diagnostics.
fn check_nesting(sources: &SourceMap, id: FileId) -> DResult<()> {
    use proc_macro2::{Delimiter, TokenStream, TokenTree};
    let Ok(tokens) = sources.get(id).src.parse::<TokenStream>() else {
        return Ok(());
    };
    // Per open group: its tokens, its own level, the level reached in its current
    // statement, and whether the last token was a `{...}` block.
    struct Open {
        tokens: proc_macro2::token_stream::IntoIter,
        base: usize,
        level: usize,
        after_block: bool,
    }
    let mut stack = vec![Open {
        tokens: tokens.into_iter(),
        base: 0,
        level: 0,
        after_block: false,
    }];
    while let Some(top) = stack.last_mut() {
        let Some(t) = top.tokens.next() else {
            stack.pop();
            continue;
        };
        // After a block, a statement or item ends unless an operator, `.`, `?`, `else`
        // or `as` continues the expression.
        let continues = match &t {
            TokenTree::Punct(p) => !matches!(p.as_char(), '#' | ';' | ','),
            TokenTree::Ident(i) => i == "else" || i == "as",
            _ => false,
        };
        if top.after_block && !continues {
            top.level = top.base;
        }
        top.after_block = false;
        let (level, span) = match &t {
            TokenTree::Punct(p) if matches!(p.as_char(), ';' | ',') => {
                top.level = top.base;
                continue;
            }
            TokenTree::Punct(p) => {
                top.level += 1;
                (top.level, p.span())
            }
            TokenTree::Ident(i) if i == "else" => {
                top.level += 1;
                (top.level, i.span())
            }
            TokenTree::Group(g) => {
                top.after_block = g.delimiter() == Delimiter::Brace;
                let level = top.level + 1;
                stack.push(Open {
                    tokens: g.stream().into_iter(),
                    base: level,
                    level,
                    after_block: false,
                });
                (level, g.span_open())
            }
            _ => continue,
        };
        if level > MAX_NESTING {
            return Err(Diagnostic::new(
                sources,
                id,
                span,
                "nesting-too-deep",
                format!("this code nests more than {MAX_NESTING} levels deep"),
            )
            .with_label(format!("{MAX_NESTING} levels of brackets, operators or `else`s reached here"))
            .with_note("the compiler recurses once per level; split the expression or the nesting into functions or `let` statements"));
        }
    }
    Ok(())
}

fn load_file(
    sources: &mut SourceMap,
    source: &CrateSource<'_>,
    pc: &mut ParsedCrate,
    rel: PathBuf,
    display: PathBuf,
    text: String,
    owns_dir: bool,
) -> DResult<FileId> {
    let id = sources.add(display, text);
    check_nesting(sources, id)?;
    let mut ast =
        syn::parse_file(&sources.get(id).src).map_err(|e| syntax_error(sources, id, &e))?;
    crate::derive::expand(&mut ast, sources, id)?;
    let ast = Box::new(ast);
    // Directory where this file's child modules live.
    let dir = if owns_dir {
        rel.parent().map(Path::to_path_buf).unwrap_or_default()
    } else {
        rel.with_extension("")
    };
    let mut pending = Vec::new();
    collect_mods(&ast.items, &dir, &mut pending);
    pc.files.insert(id, ast);
    for (ptr, child_dir, item) in pending {
        // SAFETY: `item` points into the boxed AST just inserted into `pc.files`; boxes and
        // their item vectors are never mutated or dropped while `pc` lives.
        let item: &ItemMod = unsafe { &*item };
        let name = item.ident.to_string();
        let (cands, owns): (Vec<PathBuf>, bool) = match path_attr(&item.attrs) {
            Some(p) => (vec![child_dir.join(p)], true),
            None => (
                vec![
                    child_dir.join(format!("{name}.rs")),
                    child_dir.join(&name).join("mod.rs"),
                ],
                false,
            ),
        };
        let display_of = |p: &Path| match source {
            CrateSource::Disk(_) => p.to_path_buf(),
            CrateSource::Memory { dir, .. } => dir.join(p),
        };
        let mut loaded = None;
        for c in &cands {
            let t = match read(source, c, &display_of(c), None) {
                Ok(t) => Some(t),
                Err(d) if d.id == "invalid-source-encoding" => return Err(d),
                Err(_) => None,
            };
            if let Some(t) = t {
                let owns_dir = owns || c.file_name().is_some_and(|f| f == "mod.rs");
                loaded = Some(load_file(
                    sources,
                    source,
                    pc,
                    c.clone(),
                    display_of(c),
                    t,
                    owns_dir,
                )?);
                break;
            }
        }
        match loaded {
            Some(f) => {
                pc.mod_files.insert(ptr, f);
            }
            None => {
                let c = &cands[0];
                return Err(read(source, c, &display_of(c), Some((sources, id, item))).unwrap_err());
            }
        }
    }
    Ok(id)
}

/// The diagnostic for a file `syn` cannot parse. A failed tokenization says only "cannot
/// parse string into token stream"; the lexical check then names the delimiter or
/// literal at fault and every span rustc shows for it.
fn syntax_error(sources: &SourceMap, id: FileId, e: &syn::Error) -> Diagnostic {
    use crate::diag::Loc;
    use crate::lexcheck::LexProblem;
    let src = &sources.get(id).src;
    let lex = e.to_string() == "cannot parse string into token stream";
    let at = |off: usize| Loc::of_bytes(src, off, off + 1);
    let delim = |off: usize| (src.as_bytes()[off] as char).to_string();
    match crate::lexcheck::check(src).filter(|_| lex) {
        Some(LexProblem::Unclosed { open }) => {
            // Just past the last character of the file (before a final newline).
            let end = src.trim_end_matches(['\n', '\r']).len();
            let mut d = Diagnostic::at(
                sources,
                id,
                Loc::of_bytes(src, end, end + 1),
                "unclosed-delimiter",
                "this file contains an unclosed delimiter",
            );
            for o in open {
                d = d.with_secondary(sources, id, at(o), "unclosed delimiter");
            }
            d
        }
        Some(LexProblem::Mismatched {
            close,
            unclosed,
            candidate,
        }) => {
            let mut d = Diagnostic::at(
                sources,
                id,
                at(unclosed),
                "mismatched-delimiter",
                format!("mismatched closing delimiter: `{}`", delim(close)),
            )
            .with_label("unclosed delimiter")
            .with_secondary(sources, id, at(close), "mismatched closing delimiter");
            if let Some(c) = candidate {
                d = d.with_secondary(sources, id, at(c), "closing delimiter possibly meant for this");
            }
            d
        }
        Some(LexProblem::Unexpected { close, last_pair }) => {
            let mut d = Diagnostic::at(
                sources,
                id,
                at(close),
                "unexpected-delimiter",
                format!("unexpected closing delimiter: `{}`", delim(close)),
            )
            .with_label("unexpected closing delimiter");
            if let Some((o, c)) = last_pair {
                d = d
                    .with_secondary(sources, id, at(o), "this opening brace...")
                    .with_secondary(sources, id, at(c), "...matches this closing brace");
            }
            d
        }
        Some(LexProblem::Unterminated { start, what }) => Diagnostic::at(
            sources,
            id,
            at(start),
            "unterminated-literal",
            format!("unterminated {what}"),
        )
        .with_label(format!("this {what} is never closed")),
        None if lex => Diagnostic::new(
            sources,
            id,
            e.span(),
            "syntax-error",
            "syntax error: this is not a valid Rust token (unknown character, or a malformed literal or escape)",
        ),
        None => Diagnostic::new(sources, id, e.span(), "syntax-error", format!("syntax error: {e}")),
    }
}

/// Finds enabled out-of-line modules among `items` (descending into inline modules).
fn collect_mods(items: &[Item], dir: &Path, out: &mut Vec<(usize, PathBuf, *const ItemMod)>) {
    for it in items {
        if let Item::Mod(m) = it {
            if !cfg_enabled(&m.attrs) {
                continue;
            }
            match &m.content {
                Some((_, inner)) => {
                    let sub = match path_attr(&m.attrs) {
                        Some(p) => dir.join(p),
                        None => dir.join(m.ident.to_string()),
                    };
                    collect_mods(inner, &sub, out)
                }
                None => out.push((m as *const ItemMod as usize, dir.to_path_buf(), m)),
            }
        }
    }
}

fn path_attr(attrs: &[Attribute]) -> Option<String> {
    attrs.iter().find_map(|a| match &a.meta {
        Meta::NameValue(nv) if nv.path.is_ident("path") => match &nv.value {
            Expr::Lit(l) => match &l.lit {
                Lit::Str(s) => Some(s.value()),
                _ => None,
            },
            _ => None,
        },
        _ => None,
    })
}

/// Evaluates every `#[cfg(...)]` on an item for the TRaX target (`target_arch = "mips"`).
///
/// Malformed predicates count as false; the checker reports them.
pub fn cfg_enabled(attrs: &[Attribute]) -> bool {
    attrs.iter().all(|a| {
        if !a.path().is_ident("cfg") {
            return true;
        }
        match a.parse_args::<Meta>() {
            Ok(m) => eval_cfg(&m).unwrap_or(false),
            Err(_) => false,
        }
    })
}

/// Evaluates one cfg predicate; `None` when it is malformed.
pub fn eval_cfg(m: &Meta) -> Option<bool> {
    match m {
        Meta::Path(p) => {
            let name = p.get_ident()?.to_string();
            Some(matches!(name.as_str(), "target_pointer_width_32"))
        }
        Meta::NameValue(nv) => {
            let key = nv.path.get_ident()?.to_string();
            let val = match &nv.value {
                Expr::Lit(l) => match &l.lit {
                    Lit::Str(s) => s.value(),
                    _ => return None,
                },
                _ => return None,
            };
            Some(match key.as_str() {
                "target_arch" => val == "mips",
                "target_os" => val == "none",
                "target_endian" => val == "little",
                "target_pointer_width" => val == "32",
                _ => false,
            })
        }
        Meta::List(l) => {
            let name = l.path.get_ident()?.to_string();
            let args = l
                .parse_args_with(Punctuated::<Meta, Token![,]>::parse_terminated)
                .ok()?;
            let vals: Option<Vec<bool>> = args.iter().map(eval_cfg).collect();
            let vals = vals?;
            match name.as_str() {
                "not" if vals.len() == 1 => Some(!vals[0]),
                "all" => Some(vals.iter().all(|v| *v)),
                "any" => Some(vals.iter().any(|v| *v)),
                _ => None,
            }
        }
    }
}

/// Lexically removes `.` and `..` components.
fn normalize(p: &Path) -> PathBuf {
    use std::path::Component;
    let mut out: Vec<Component> = Vec::new();
    for c in p.components() {
        match c {
            Component::CurDir => {}
            Component::ParentDir if matches!(out.last(), Some(Component::Normal(_))) => {
                out.pop();
            }
            c => out.push(c),
        }
    }
    out.iter().collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn attrs(src: &str) -> Vec<Attribute> {
        let f: syn::File = syn::parse_str(&format!("{src} fn x() {{}}")).unwrap();
        match &f.items[0] {
            Item::Fn(f) => f.attrs.clone(),
            _ => unreachable!(),
        }
    }

    #[test]
    fn cfg_targets_mips() {
        assert!(cfg_enabled(&attrs("#[cfg(target_arch = \"mips\")]")));
        assert!(!cfg_enabled(&attrs("#[cfg(not(target_arch = \"mips\"))]")));
        assert!(cfg_enabled(&attrs(
            "#[cfg(all(target_arch = \"mips\", not(test)))]"
        )));
        assert!(!cfg_enabled(&attrs(
            "#[cfg(any(test, target_arch = \"x86_64\"))]"
        )));
        assert!(!cfg_enabled(&attrs("#[cfg(test)]")));
        assert!(cfg_enabled(&attrs("#[inline]")));
    }

    #[test]
    fn normalizes_parent_components() {
        assert_eq!(
            normalize(Path::new("a/../src/rng.rs")),
            PathBuf::from("src/rng.rs")
        );
        assert_eq!(
            normalize(Path::new("../src/rng.rs")),
            PathBuf::from("../src/rng.rs")
        );
    }
}
