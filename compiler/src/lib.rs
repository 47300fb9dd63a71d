//! TRaX-Rust compiler: kernel source → MIPS32r6 ELF relocatable object with DWARF.
//!
//! Pipeline (one module per stage):
//! - [`parse`]: `syn` parse of the kernel crate (from disk) and the prelude crate `trax`
//!   (from memory), following `mod x;`/`#[path]` and evaluating `#[cfg]` for
//!   `target_arch = "mips"`; [`derive`] expands `#[derive(PartialOrd)]` into its impl.
//! - [`resolve`]: modules, `use`, structs, enums, traits, impls, functions, consts/statics,
//!   type aliases (also items nested in bodies) into a [`resolve::Program`]; rejects items
//!   outside the subset with named diagnostics.
//! - [`typeck`]: types of every expression (literal inference variables default to
//!   `i32`/`f64`), path/method/trait/operator resolution, patterns, builtin macros; one
//!   body per instance of a generic function (monomorphised before lowering). Rejects
//!   everything the lowering cannot handle. [`builtins`] is the catalogue of builtin
//!   methods shared with the lowering; [`ops`] the operators.
//! - [`lower`]: LLVM IR via inkwell, on demand from `trax_main` and the `#[no_mangle]
//!   extern "C"` functions C code calls (only reachable code is emitted), with DWARF
//!   (subprograms, lexical blocks, 1-based line/column, typed parameters and locals).
//!   Functions of `extern "C"` blocks are declarations for the linker. Both sides of the
//!   C boundary carry clang's extension attributes. TRaX instructions are `.word`s in
//!   inline asm.
//! - [`target`]: `mipsel-unknown-none-elf`, `mips32r6`, `+msa,+fp64,+noabicalls`, static
//!   relocations, no `$gp`-relative data; LLVM's `default<On>` pipeline; object emission.
//!   [`memfns`] and [`rtlib`] add `memset`/`memcpy`/`memmove` and 64-bit division and
//!   conversion helpers when the optimised code needs them (TRaX has no libc).
//!
//! Errors are [`CompileError::Diagnostics`] (kernel errors with stable ids, exit code 1)
//! or [`CompileError::Internal`] (compiler bugs, exit code 101). Set
//! `TRAX_COMPILER_TIMINGS=1` to print the time of each stage.

pub mod builtins;
pub mod consteval;
pub mod derive;
pub mod diag;
pub mod lexcheck;
pub mod lower;
pub mod memfns;
pub mod ops;
pub mod parse;
pub mod pretty;
pub mod resolve;
pub mod rtlib;
pub mod span;
pub mod target;
pub mod ty;
pub mod typeck;

use diag::{Diagnostic, SourceMap};
use parse::CrateSource;
use std::path::{Path, PathBuf};

/// What to produce.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Emit {
    /// ELF relocatable object.
    #[default]
    Obj,
    /// Assembly text.
    Asm,
    /// LLVM IR text (after optimisation).
    LlvmIr,
}

/// The prelude crate (`trax`) compiled with every kernel.
#[derive(Clone, Debug)]
pub struct Prelude {
    /// Files `(path relative to the crate root, source)`; the root is `lib.rs`.
    pub files: Vec<(String, String)>,
    /// Directory shown in diagnostics and DWARF.
    pub dir: PathBuf,
}

impl Prelude {
    /// The runtime's prelude (`trax_runtime::prelude`).
    pub fn runtime() -> Prelude {
        Prelude {
            files: trax_runtime::prelude::FILES
                .iter()
                .map(|(p, s)| (p.to_string(), s.to_string()))
                .collect(),
            dir: PathBuf::from(trax_runtime::prelude::DIR),
        }
    }
}

/// Compiler options.
#[derive(Clone, Debug, Default)]
pub struct CompileOptions {
    /// Optimisation level 0..=3.
    pub opt_level: u8,
    /// Output kind.
    pub emit: Emit,
    /// Prelude crate; `None` compiles the kernel alone (then `trax::` paths only reach the
    /// builtin `trax::simd` module).
    pub prelude: Option<Prelude>,
}

/// Compiler output.
#[derive(Debug)]
pub struct Output {
    /// Object bytes, assembly text or LLVM IR text, per [`CompileOptions::emit`].
    pub bytes: Vec<u8>,
}

/// Why compilation failed.
#[derive(Debug, thiserror::Error)]
pub enum CompileError {
    /// Errors in the kernel (exit code 1).
    #[error("{}", render(.0))]
    Diagnostics(Vec<Diagnostic>),
    /// A bug in the compiler or LLVM failure (exit code 101).
    #[error("internal compiler error: {0}")]
    Internal(String),
}

impl CompileError {
    /// Process exit code for this error.
    pub fn exit_code(&self) -> u8 {
        match self {
            CompileError::Diagnostics(_) => 1,
            CompileError::Internal(_) => 101,
        }
    }
}

/// Renders diagnostics as text, one after the other.
pub fn render(d: &[Diagnostic]) -> String {
    let mut s = String::new();
    for x in d {
        s.push_str(&x.to_string());
        s.push('\n');
    }
    let n = d.len();
    s.push_str(&format!(
        "error: could not compile due to {n} previous error{}\n",
        if n == 1 { "" } else { "s" }
    ));
    s
}

/// Stack of the thread the compiler runs on: deep but valid programs (thousands of nested
/// blocks, operator chains of thousands of terms) recurse deeply in syn's parser and in every
/// walk over the tree, and overflowed the 8 MiB of a main thread. Only the pages a
/// compilation touches are ever used.
const COMPILER_STACK_BYTES: usize = 512 << 20;

/// Runs `f` on a thread with [`COMPILER_STACK_BYTES`] of stack (on this one if no thread
/// can be made) with an empty span memo ([`span::forget`]), passing its panics on.
fn on_compiler_stack<T: Send>(f: impl FnOnce() -> T + Send) -> T {
    let f = std::sync::Mutex::new(Some(f));
    let call = || {
        let f = f.lock().unwrap_or_else(|e| e.into_inner()).take();
        span::forget();
        (f.expect("called once"))()
    };
    std::thread::scope(|s| {
        match std::thread::Builder::new()
            .name("trax-compiler".into())
            .stack_size(COMPILER_STACK_BYTES)
            .spawn_scoped(s, call)
        {
            Ok(h) => h.join().unwrap_or_else(|p| std::panic::resume_unwind(p)),
            Err(_) => call(),
        }
    })
}

/// Compiles the kernel whose root file is `path`.
pub fn compile_file(path: &Path, opts: &CompileOptions) -> Result<Output, CompileError> {
    on_compiler_stack(|| compile_file_here(path, opts))
}

/// [`compile_file`] on the current thread.
fn compile_file_here(path: &Path, opts: &CompileOptions) -> Result<Output, CompileError> {
    let mut sources = SourceMap::default();
    let kernel = parse::parse_crate(&mut sources, &CrateSource::Disk(path.to_path_buf()))
        .map_err(|d| CompileError::Diagnostics(vec![d]))?;
    let prelude = match &opts.prelude {
        Some(p) => {
            let files: Vec<(&str, &str)> = p
                .files
                .iter()
                .map(|(a, b)| (a.as_str(), b.as_str()))
                .collect();
            let src = CrateSource::Memory {
                files: &files,
                dir: p.dir.clone(),
            };
            Some(
                parse::parse_crate(&mut sources, &src)
                    .map_err(|d| CompileError::Diagnostics(vec![d]))?,
            )
        }
        None => None,
    };
    let name = path
        .file_stem()
        .map(|s| s.to_string_lossy().replace('-', "_"))
        .unwrap_or_else(|| "kernel".into());
    compile_parsed(&sources, &kernel, &name, prelude.as_ref(), opts)
}

/// Compiles a kernel given as text (`name` is its crate and file name in diagnostics),
/// with the prelude of `opts`.
pub fn compile_source(
    name: &str,
    text: &str,
    opts: &CompileOptions,
) -> Result<Output, CompileError> {
    on_compiler_stack(|| compile_source_here(name, text, opts))
}

/// [`compile_source`] on the current thread.
fn compile_source_here(
    name: &str,
    text: &str,
    opts: &CompileOptions,
) -> Result<Output, CompileError> {
    let mut sources = SourceMap::default();
    let files = [("lib.rs", text)];
    let src = CrateSource::Memory {
        files: &files,
        dir: PathBuf::from(name),
    };
    let kernel =
        parse::parse_crate(&mut sources, &src).map_err(|d| CompileError::Diagnostics(vec![d]))?;
    let prelude = match &opts.prelude {
        Some(p) => {
            let files: Vec<(&str, &str)> = p
                .files
                .iter()
                .map(|(a, b)| (a.as_str(), b.as_str()))
                .collect();
            let src = CrateSource::Memory {
                files: &files,
                dir: p.dir.clone(),
            };
            Some(
                parse::parse_crate(&mut sources, &src)
                    .map_err(|d| CompileError::Diagnostics(vec![d]))?,
            )
        }
        None => None,
    };
    compile_parsed(&sources, &kernel, name, prelude.as_ref(), opts)
}

/// Entry point of the `kernel` fuzz target in `fuzz/` (and of its regression test): any
/// bytes must compile or give diagnostics, never panic or hang.
pub mod fuzzing {
    use super::*;

    /// Compiles `data` (if UTF-8) as a kernel with the prelude, at `-O0` when the first
    /// byte is even, else `-O1`.
    pub fn kernel(data: &[u8]) {
        let Ok(text) = std::str::from_utf8(data) else {
            return;
        };
        let opts = CompileOptions {
            opt_level: if data.first().is_some_and(|b| b % 2 == 1) {
                1
            } else {
                0
            },
            prelude: Some(Prelude::runtime()),
            ..CompileOptions::default()
        };
        if let Err(CompileError::Internal(msg)) = compile_source("fuzz", text, &opts) {
            panic!("internal compiler error: {msg}");
        }
    }
}

/// Prints the time of each stage to stderr when `TRAX_COMPILER_TIMINGS` is set.
struct Timer {
    on: bool,
    last: std::time::Instant,
}

impl Timer {
    fn new() -> Timer {
        Timer {
            on: std::env::var_os("TRAX_COMPILER_TIMINGS").is_some(),
            last: std::time::Instant::now(),
        }
    }

    fn lap(&mut self, stage: &str) {
        if self.on {
            eprintln!(
                "trax-compiler: {stage:<10} {:8.1} ms",
                self.last.elapsed().as_secs_f64() * 1e3
            );
        }
        self.last = std::time::Instant::now();
    }
}

fn compile_parsed(
    sources: &SourceMap,
    kernel: &parse::ParsedCrate,
    name: &str,
    prelude: Option<&parse::ParsedCrate>,
    opts: &CompileOptions,
) -> Result<Output, CompileError> {
    let mut timer = Timer::new();
    let program =
        resolve::collect(sources, kernel, name, prelude).map_err(CompileError::Diagnostics)?;
    timer.lap("resolve");
    // Type-check every function and global, then every generic instance they use.
    let (checked, mut errs) = typeck::check_program(&program);
    if let Some(e) = consteval::check_const_cycles(&program, &checked) {
        errs.push(e);
        return Err(CompileError::Diagnostics(errs));
    }
    // Literal ranges, const evaluation and rustc's deny-by-default arithmetic lints.
    // (An erroneous const named by an array length is reported once.)
    let mut items: Vec<(&typeck::Item, &typeck::Body)> = checked.bodies.iter().collect();
    items.sort_by_key(|(i, _)| match i {
        typeck::Item::Fn(f, s) => (0, *f, format!("{s:?}")),
        typeck::Item::Global(g, s) => (1, *g, format!("{s:?}")),
    });
    for (item, body) in items {
        let r = match item {
            typeck::Item::Fn(f, _) => consteval::check_fn(&program, &checked, *f, body),
            typeck::Item::Global(g, _) => consteval::check_global(&program, &checked, *g, body),
        };
        if let Err(e) = r {
            if !errs.contains(&e) {
                errs.push(e);
            }
        }
    }
    // Values of consts and statics (running `const fn` calls).
    let consts = if errs.is_empty() {
        match consteval::interp::evaluate_all(&program, &checked) {
            Ok(c) => c,
            Err(e) => {
                errs.push(e);
                Default::default()
            }
        }
    } else {
        Default::default()
    };
    let root = program.modules[program.kernel_root].file;
    let main = match program.modules[program.kernel_root].values_get("trax_main") {
        Some(resolve::PathRes::Fn(f)) => Some(f),
        _ => None,
    };
    // `#[no_mangle] extern "C"` functions C code calls (resolve admits `extern` only there).
    let exports: Vec<resolve::FnId> = (0..program.fns.len())
        .filter(|&f| program.fns[f].sig.abi.is_some() && Some(f) != main)
        .collect();
    let roots: Vec<resolve::FnId> = main.into_iter().chain(exports.iter().copied()).collect();
    if main.is_none() && exports.is_empty() {
        errs.push(Diagnostic::file_level(
            &sources.get(root).display,
            "missing-entry-point",
            "the kernel has no `fn trax_main()` at its root (nor `#[no_mangle] extern \"C\"` functions for C code to call)",
        ));
        return Err(CompileError::Diagnostics(errs));
    }
    if let Some(main) = main {
        let mf = &program.fns[main];
        if !mf.params.is_empty() || mf.ret != ty::Ty::Unit || !mf.generics.is_empty() {
            errs.push(Diagnostic::new(
                sources,
                mf.file,
                mf.sig.ident.span(),
                "invalid-entry-point",
                "`trax_main` must be declared as `fn trax_main()`",
            ));
        }
    }
    // One function per C name, exported or declared in an `extern "C"` block (LLVM would
    // rename a second one silently).
    let foreign = (0..program.fns.len()).filter(|&f| program.fns[f].foreign);
    let mut seen: std::collections::HashMap<&str, resolve::FnId> = Default::default();
    for f in roots.iter().copied().chain(foreign) {
        let fd = &program.fns[f];
        if let Some(&first) = seen.get(fd.symbol.as_str()) {
            let other = &program.fns[first];
            let at = sources.get(other.file).display.display().to_string();
            let line = other.sig.ident.span().start().line;
            errs.push(Diagnostic::new(
                sources,
                fd.file,
                fd.sig.ident.span(),
                "duplicate-c-symbol",
                format!(
                    "`{}` is already {} at {at}:{line}",
                    fd.symbol,
                    if other.foreign { "declared" } else { "defined" }
                ),
            ));
        } else {
            seen.insert(&fd.symbol, f);
        }
    }
    if !errs.is_empty() {
        return Err(CompileError::Diagnostics(errs));
    }
    timer.lap("typeck");
    let tm = target::machine(opts.opt_level).map_err(CompileError::Internal)?;
    let ctx = inkwell::context::Context::create();
    let empty = typeck::Body::default();
    let lowerer = lower::Lowerer::new(
        &ctx,
        name,
        tm.get_target_data(),
        &tm.get_triple(),
        &program,
        &checked,
        &consts,
        opts.opt_level > 0,
        &empty,
    );
    let module = match lowerer.run(&roots) {
        Ok(m) => m,
        Err(lower::LowerError::Internal(s)) => return Err(CompileError::Internal(s)),
    };
    timer.lap("lower");
    module
        .verify()
        .map_err(|e| CompileError::Internal(format!("invalid LLVM IR: {}", e.to_string())))?;
    target::optimize(&module, &tm, opts.opt_level).map_err(CompileError::Internal)?;
    memfns::provide(&ctx, &module).map_err(CompileError::Internal)?;
    rtlib::provide(&ctx, &module).map_err(CompileError::Internal)?;
    timer.lap("optimize");
    let bytes = match opts.emit {
        Emit::LlvmIr => module.print_to_string().to_string().into_bytes(),
        Emit::Asm => target::emit(&module, &tm, true).map_err(CompileError::Internal)?,
        Emit::Obj => target::emit(&module, &tm, false).map_err(CompileError::Internal)?,
    };
    timer.lap("emit");
    Ok(Output { bytes })
}
