//! C and C++ kernels: clang-14 compiles them for the TRaX machine (MIPS32r6, o32, MSA,
//! FP64, static, no `$gp` data, freestanding) against the generated `trax.h`, and the trax
//! linker links the objects with the start-up code like the trax compiler's.
//!
//! Headers (`trax.h`, `trax_isa.h`, `trax.hpp`, rendered by `trax_runtime::cheader`) are
//! written once per header text into `<cache>/include-<hash>/` and put on the include
//! path, so kernels copy nothing. Memory functions and the 64-bit helpers clang calls
//! (there is no libc or compiler-rt) are compiled from [`RUNTIME_C`] and the trax
//! compiler's `int64.ll` and linked only when an object references them.

use std::hash::Hasher;
use std::path::{Path, PathBuf};
use std::process::Command;

use trax_compiler::Emit;

/// A C-family source language.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Lang {
    /// C11 (`.c`).
    C,
    /// C++17 (`.cpp`, `.cc`, `.cxx`).
    Cpp,
}

/// The Debian package that provides the compiler.
pub const CLANG_PACKAGE: &str = "clang-14";

/// Flags of every TRaX compilation: MIPS32r6 little-endian o32 with MSA and 64-bit FPU
/// registers (as the trax compiler's objects), static code without abicalls or `$gp`
/// data (`-G0`: the linker has no small-data section), freestanding (no libc, no errno:
/// `sqrtf` is the `sqrt.s` instruction), no FMA contraction (float semantics of the
/// TRaX-Rust kernels), DWARF 5 (clang-14's default, named so a
/// newer clang gives the same; the linker and the emulator's DWARF reader handle 5 and the
/// trax compiler's 4 in one executable, see docs/ARCHITECTURE.md).
pub const TARGET_FLAGS: &[&str] = &[
    "--target=mipsel-unknown-elf",
    "-march=mips32r6",
    "-mabi=32",
    "-mmsa",
    "-mfp64",
    "-fno-pic",
    "-mno-abicalls",
    "-G0",
    "-ffreestanding",
    "-nostdlib",
    "-nostdlibinc",
    "-fno-common",
    "-fno-math-errno",
    "-ffp-contract=off",
    "-g",
    "-gdwarf-5",
];

/// Why a C or C++ file could not be built.
#[derive(Debug, thiserror::Error)]
pub enum ClangError {
    /// No clang on `PATH`.
    #[error(
        "{file}: building C and C++ kernels needs clang-14, and neither `clang-14` nor `clang` is on PATH (install the Debian package `{CLANG_PACKAGE}`)"
    )]
    Missing {
        /// The source that needed it.
        file: String,
    },
    /// clang rejected the source; its diagnostics (`file:line:col: error: ...`).
    #[error("{diagnostics}")]
    Diagnostics {
        /// clang's stderr.
        diagnostics: String,
    },
    /// A file could not be written or read.
    #[error("{path}: {message}")]
    Io {
        /// The file.
        path: String,
        /// What went wrong.
        message: String,
    },
}

/// The language of `path` by extension, if it is C or C++.
pub fn lang_of(path: &Path) -> Option<Lang> {
    match path.extension().and_then(|e| e.to_str()) {
        Some("c") => Some(Lang::C),
        Some("cpp" | "cc" | "cxx" | "c++") => Some(Lang::Cpp),
        _ => None,
    }
}

/// The clang to run: `$TRAX_CLANG`, else `clang-14`, else `clang` from `PATH`.
pub fn find_clang() -> Option<PathBuf> {
    if let Some(c) = std::env::var_os("TRAX_CLANG").filter(|v| !v.is_empty()) {
        return Some(PathBuf::from(c));
    }
    let path = std::env::var_os("PATH")?;
    for name in ["clang-14", "clang"] {
        for dir in std::env::split_paths(&path) {
            let p = dir.join(name);
            if p.is_file() {
                return Some(p);
            }
        }
    }
    None
}

/// The build cache directory: `$TRAX_CACHE_DIR`, else the user's cache directory
/// (`$XDG_CACHE_HOME/trax` or `~/.cache/trax`), else `<temp>/trax-cache`.
pub fn cache_dir() -> PathBuf {
    let var = |name: &str| {
        std::env::var_os(name)
            .filter(|v| !v.is_empty())
            .map(PathBuf::from)
    };
    if let Some(d) = var("TRAX_CACHE_DIR") {
        return d;
    }
    match (var("XDG_CACHE_HOME"), var("HOME")) {
        (Some(x), _) => x.join("trax"),
        (None, Some(h)) => h.join(".cache").join("trax"),
        (None, None) => std::env::temp_dir().join("trax-cache"),
    }
}

/// The generated headers: `(file name, text)`.
pub fn headers() -> Vec<(&'static str, String)> {
    use trax_runtime::cheader;
    vec![
        ("trax_isa.h", cheader::render_c_header()),
        ("trax.h", cheader::render_trax_h()),
        ("trax.hpp", cheader::render_trax_hpp()),
        ("trax_host.h", cheader::render_host_h()),
    ]
}

/// Writes the generated headers into `dir` (created if needed).
pub fn write_headers(dir: &Path) -> Result<Vec<PathBuf>, ClangError> {
    std::fs::create_dir_all(dir).map_err(io(dir))?;
    let mut written = Vec::new();
    for (name, text) in headers() {
        let p = dir.join(name);
        std::fs::write(&p, text).map_err(io(&p))?;
        written.push(p);
    }
    Ok(written)
}

fn io(path: &Path) -> impl Fn(std::io::Error) -> ClangError + '_ {
    move |e| ClangError::Io {
        path: path.display().to_string(),
        message: e.to_string(),
    }
}

fn hash_texts<'a>(texts: impl IntoIterator<Item = &'a str>) -> u64 {
    // FNV-1a: stable across runs and Rust versions (a cache key).
    let mut h = Fnv(0xcbf2_9ce4_8422_2325);
    for t in texts {
        h.write(t.as_bytes());
        h.write(&[0xff]);
    }
    h.finish()
}

struct Fnv(u64);

impl Hasher for Fnv {
    fn finish(&self) -> u64 {
        self.0
    }
    fn write(&mut self, bytes: &[u8]) {
        for b in bytes {
            self.0 = (self.0 ^ u64::from(*b)).wrapping_mul(0x0000_0100_0000_01b3);
        }
    }
}

/// A fresh directory `<cache>/<prefix>-<pid>-<n>` for one compilation's temporary files.
fn scratch(prefix: &str) -> Result<PathBuf, ClangError> {
    use std::sync::atomic::{AtomicU32, Ordering};
    static N: AtomicU32 = AtomicU32::new(0);
    let d = cache_dir().join("tmp").join(format!(
        "{prefix}-{}-{}",
        std::process::id(),
        N.fetch_add(1, Ordering::Relaxed)
    ));
    std::fs::create_dir_all(&d).map_err(io(&d))?;
    Ok(d)
}

/// The include directory holding this trax's headers, written on first use
/// (`<cache>/include-<hash of the header texts>`).
pub fn include_dir() -> Result<PathBuf, ClangError> {
    let hs = headers();
    let key = hash_texts(hs.iter().map(|(_, t)| t.as_str()));
    let dir = cache_dir().join(format!("include-{key:016x}"));
    if hs.iter().all(|(n, _)| dir.join(n).is_file()) {
        return Ok(dir);
    }
    // Write into a private directory and rename, so a concurrent build never sees a
    // half-written header.
    let tmp = scratch("include")?;
    write_headers(&tmp)?;
    match std::fs::rename(&tmp, &dir) {
        Ok(()) => Ok(dir),
        Err(_) if hs.iter().all(|(n, _)| dir.join(n).is_file()) => {
            let _ = std::fs::remove_dir_all(&tmp);
            Ok(dir)
        }
        Err(e) => Err(io(&dir)(e)),
    }
}

/// The clang command line for `src` (without the output and mode flags).
pub fn command(clang: &Path, src: &Path, lang: Lang, opt_level: u8, include: &Path) -> Command {
    let mut cmd = Command::new(clang);
    cmd.args(TARGET_FLAGS);
    cmd.arg(format!("-O{opt_level}"));
    match lang {
        Lang::C => cmd.args(["-x", "c", "-std=c11"]),
        Lang::Cpp => cmd.args([
            "-x",
            "c++",
            "-std=c++17",
            "-fno-exceptions",
            "-fno-rtti",
            "-fno-threadsafe-statics",
            "-fno-use-cxa-atexit",
        ]),
    };
    cmd.arg("-fdiagnostics-color=never");
    cmd.arg("-I").arg(include);
    cmd.arg(src);
    cmd
}

/// Compiles a C or C++ file for TRaX: an object (ELF relocatable with DWARF), assembly or
/// LLVM IR, by `emit`.
pub fn compile(src: &Path, lang: Lang, opt_level: u8, emit: Emit) -> Result<Vec<u8>, ClangError> {
    let clang = find_clang().ok_or_else(|| ClangError::Missing {
        file: src.display().to_string(),
    })?;
    let include = include_dir()?;
    let dir = scratch("cc")?;
    let out = dir.join("out");
    let mut cmd = command(&clang, src, lang, opt_level, &include);
    match emit {
        Emit::Obj => cmd.arg("-c"),
        Emit::Asm => cmd.arg("-S"),
        Emit::LlvmIr => cmd.args(["-S", "-emit-llvm"]),
    };
    cmd.arg("-o").arg(&out);
    let result = run(&mut cmd, &clang).and_then(|()| {
        std::fs::read(&out).map_err(|e| ClangError::Io {
            path: out.display().to_string(),
            message: e.to_string(),
        })
    });
    let _ = std::fs::remove_dir_all(&dir);
    result
}

fn run(cmd: &mut Command, clang: &Path) -> Result<(), ClangError> {
    let o = cmd.output().map_err(|e| ClangError::Io {
        path: clang.display().to_string(),
        message: format!("cannot run: {e}"),
    })?;
    if o.status.success() {
        return Ok(());
    }
    let mut diagnostics = String::from_utf8_lossy(&o.stderr).into_owned();
    if diagnostics.trim().is_empty() {
        diagnostics = format!("error: {} failed ({})", clang.display(), o.status);
    }
    Err(ClangError::Diagnostics { diagnostics })
}

/// What clang-compiled code may call without defining it: memory functions (struct
/// copies, zeroing) and the C++ ABI's `__cxa_pure_virtual`/`__cxa_deleted_virtual` and
/// `operator delete` (referenced by every class with a virtual destructor; TRaX has no
/// heap, so it can only be reached by a bug). Weak, so a kernel may define its own;
/// `-fno-builtin` keeps clang from turning the loops back into calls. Compiled without
/// debug information: a pure virtual call is reported at its caller's line, as a panic.
pub const RUNTIME_C: &str = r#"#include <trax.h>
typedef unsigned int size_t;
__attribute__((weak)) void *memcpy(void *d, const void *s, size_t n) {
    unsigned char *dp = d; const unsigned char *sp = s;
    while (n--) *dp++ = *sp++;
    return d;
}
__attribute__((weak)) void *memmove(void *d, const void *s, size_t n) {
    unsigned char *dp = d; const unsigned char *sp = s;
    if (dp < sp) { while (n--) *dp++ = *sp++; }
    else { dp += n; sp += n; while (n--) *--dp = *--sp; }
    return d;
}
__attribute__((weak)) void *memset(void *d, int c, size_t n) {
    unsigned char *dp = d;
    while (n--) *dp++ = (unsigned char)c;
    return d;
}
__attribute__((weak)) int memcmp(const void *a, const void *b, size_t n) {
    const unsigned char *x = a, *y = b;
    for (; n; n--, x++, y++) if (*x != *y) return *x - *y;
    return 0;
}
__attribute__((weak, noreturn)) void __cxa_pure_virtual(void) {
    trax_panic("pure virtual method called");
}
__attribute__((weak, noreturn)) void __cxa_deleted_virtual(void) {
    trax_panic("deleted virtual method called");
}
__attribute__((weak, noreturn)) void trax_rt_delete(void *p) __asm__("_ZdlPv");
__attribute__((weak, noreturn)) void trax_rt_delete(void *p) {
    (void)p;
    trax_panic("operator delete called: TRaX kernels have no heap");
}
__attribute__((weak, noreturn)) void trax_rt_delete_sized(void *p, size_t n) __asm__("_ZdlPvj");
__attribute__((weak, noreturn)) void trax_rt_delete_sized(void *p, size_t n) {
    (void)p; (void)n;
    trax_panic("operator delete called: TRaX kernels have no heap");
}
"#;

/// Symbols [`RUNTIME_C`] defines.
pub const RUNTIME_C_SYMBOLS: &[&str] = &[
    "memcpy",
    "memmove",
    "memset",
    "memcmp",
    "__cxa_pure_virtual",
    "__cxa_deleted_virtual",
    "_ZdlPv",
    "_ZdlPvj",
];

/// True if `symbol` is a C name of the prelude's libm (`trax_sinf`, ...).
pub fn is_libm_symbol(symbol: &str) -> bool {
    symbol.strip_prefix("trax_").is_some_and(|n| {
        trax_runtime::cheader::libm_functions()
            .iter()
            .any(|f| f.name == n)
    })
}

/// True if the trax C runtime defines `symbol` (see [`runtime_object_for`]).
pub fn runtime_provides(symbol: &str) -> bool {
    RUNTIME_C_SYMBOLS.contains(&symbol)
        || trax_compiler::rtlib::HELPERS.contains(&symbol)
        || is_libm_symbol(symbol)
}

/// The runtime object (name, bytes) that defines `symbol`, if it is one the trax C
/// runtime provides: [`RUNTIME_C`] for memory functions and the C++ ABI, the trax
/// compiler's 64-bit helpers (`int64.ll`) for 64-bit division and conversions, the
/// prelude's libm built by the trax compiler for `trax_sinf` and the other functions of
/// `trax.h`'s libm section. The linker asks for them when an object references one that
/// no input defines.
pub fn runtime_object_for(symbol: &str) -> Option<Result<(String, Vec<u8>), ClangError>> {
    if RUNTIME_C_SYMBOLS.contains(&symbol) {
        return Some(
            compile_text(RUNTIME_C, "c", &["-O2", "-fno-builtin", "-g0"])
                .map(|o| ("<trax C runtime: memcpy, memset, C++ ABI>".to_string(), o)),
        );
    }
    if trax_compiler::rtlib::HELPERS.contains(&symbol) {
        return Some(
            compile_text(trax_compiler::rtlib::INT64_IR, "ir", &["-O2"])
                .map(|o| ("<trax 64-bit helpers>".to_string(), o)),
        );
    }
    if is_libm_symbol(symbol) {
        return Some(libm_object().map(|o| ("<trax libm (trax::libm)>".to_string(), o)));
    }
    None
}

/// The prelude's libm under its C names ([`trax_runtime::cheader::libm_c_exports`]),
/// built by the trax compiler at -O2 with the prelude: the very code a TRaX-Rust kernel's
/// `x.sin()` runs.
fn libm_object() -> Result<Vec<u8>, ClangError> {
    let opts = trax_compiler::CompileOptions {
        opt_level: 2,
        emit: Emit::Obj,
        prelude: Some(trax_compiler::Prelude::runtime()),
    };
    trax_compiler::compile_source("trax_libm", &trax_runtime::cheader::libm_c_exports(), &opts)
        .map(|o| o.bytes)
        .map_err(|e| {
            // The first diagnostic says why; the others repeat it for every function.
            let all = e.to_string();
            let first = all.split("\n\n").next().unwrap_or_default();
            ClangError::Diagnostics {
                diagnostics: format!(
                    "error: the kernel calls the prelude's libm (trax_sinf, ...), which the trax compiler builds from `extern \"C\"` exports of trax::libm, and that failed:\n{first}\n"
                ),
            }
        })
}

/// Compiles `text` (language `x` for clang's `-x`) to an object for TRaX.
fn compile_text(text: &str, x: &str, extra: &[&str]) -> Result<Vec<u8>, ClangError> {
    let clang = find_clang().ok_or_else(|| ClangError::Missing {
        file: "the trax C runtime".into(),
    })?;
    let dir = scratch("rt")?;
    let src = dir.join(if x == "ir" { "rt.ll" } else { "rt.c" });
    std::fs::write(&src, text).map_err(io(&src))?;
    let out = dir.join("rt.o");
    let include = include_dir()?;
    let mut cmd = Command::new(&clang);
    cmd.args(TARGET_FLAGS)
        .args(extra)
        .arg("-I")
        .arg(&include)
        .args(["-x", x, "-c"])
        .arg(&src)
        .arg("-o")
        .arg(&out);
    // IR carries no target; clang warns that it overrides the module's.
    cmd.arg("-Wno-override-module");
    let result = run(&mut cmd, &clang).and_then(|()| std::fs::read(&out).map_err(io(&out)));
    let _ = std::fs::remove_dir_all(&dir);
    result
}

/// Rust code `trax native` links host-compiled C and C++ objects with: module
/// `__trax_c_api` defines the functions of `trax_host.h` over the host prelude (the same
/// thread ids, global registers, barriers, `trax.rand`, `fmin`/`fmax`/`invsqrt`,
/// pipelines and print formatting as the machine), the C++ ABI functions of
/// [`RUNTIME_C`] and the prelude's libm under its C names
/// ([`trax_runtime::cheader::libm_c_exports`]). Appended to a TRaX-Rust kernel linked
/// with C files, or with [`HOST_MAIN_C`] the whole program of a C or C++ kernel.
pub fn host_shim() -> String {
    use trax_runtime::cheader::{c_name, rust_signature};
    use trax_runtime::isa::{TraxOp as Op, TRAX_INSTRUCTIONS};
    let mut s = String::from(HOST_SHIM_HEAD);
    for i in TRAX_INSTRUCTIONS {
        let (params, ret) = rust_signature(i);
        let imm = i
            .operands
            .iter()
            .any(|o| o.kind == trax_runtime::isa::OperandKind::Imm5);
        let name = if imm {
            format!("__trax_host_{}", c_name(i))
        } else {
            c_name(i)
        };
        let unsupported = |what: &str| format!("panic!(\"trax native: `{}` {what}\")", c_name(i));
        let body = match i.op {
            Op::ThreadId => "trax::thread_id()".into(),
            Op::TmId => "trax::tm_id()".into(),
            Op::GlobalId => "trax::global_id()".into(),
            Op::NumThreads => "trax::num_threads()".into(),
            Op::NumTms => "trax::num_tms()".into(),
            Op::Clock => "trax::clock()".into(),
            Op::Rand => "trax::rand()".into(),
            Op::Seed => "trax::host::seed(rs, rt)".into(),
            Op::AtomicInc => "trax::atomic_inc(rs)".into(),
            Op::AtomicDec => "trax::atomic_dec(rs)".into(),
            Op::AtomicAdd => "trax::atomic_add(rs, rt)".into(),
            Op::GlobalRead => "trax::global_read(rs)".into(),
            Op::GlobalWrite => "trax::global_write(rs, rt)".into(),
            Op::IncReset => "trax::inc_reset(rs)".into(),
            Op::Barrier => "trax::barrier(rs)".into(),
            Op::SemAcquire => "trax::sem_acquire(rs)".into(),
            Op::SemRelease => "trax::sem_release(rs)".into(),
            Op::FMin => "trax::min(rs, rt)".into(),
            Op::FMax => "trax::max(rs, rt)".into(),
            Op::InvSqrt => "trax::invsqrt(rs)".into(),
            Op::PrintInt => "out(&(rs as i32).to_string())".into(),
            Op::PrintUint => "out(&rs.to_string())".into(),
            Op::PrintF32 | Op::PrintF64 => "out(&rs.to_string())".into(),
            Op::PrintChar => "out(&char::from_u32(rs).unwrap_or('\\u{fffd}').to_string())".into(),
            Op::PrintBool => "out(if rs != 0 { \"true\" } else { \"false\" })".into(),
            Op::PrintI64 => "out(&((u64::from(rt) << 32 | u64::from(rs)) as i64).to_string())".into(),
            Op::PrintU64 => "out(&(u64::from(rt) << 32 | u64::from(rs)).to_string())".into(),
            Op::Stat => "trax::stat::add(sa, 1)".into(),
            Op::StatAdd => "trax::stat::add(rs, rt)".into(),
            Op::ProfBegin | Op::ProfEnd => "let _ = sa;".into(),
            Op::SetPipe => "match sa { 0 => trax::host::set_pipe_general(), 1 => trax::host::set_pipe_box(), 2 => trax::host::set_pipe_tri(), m => panic!(\"trax native: trax.setpipe {m}: no such pipeline mode\") }".into(),
            Op::BoxTest => "let r = cop2(); trax::host::pipe_box_test([r[0], r[1], r[2]], [r[3], r[4], r[5]], [r[6], r[7], r[8]], [r[9], r[10], r[11]])".into(),
            Op::TriTest => "let r = cop2(); let t = trax::host::pipe_tri_test([r[0], r[1], r[2]], [r[3], r[4], r[5]], [r[12], r[13], r[14]], [r[15], r[16], r[17]], [r[18], r[19], r[20]]); set_cop2(21, trax::host::pipe_tri_u()); set_cop2(22, trax::host::pipe_tri_v()); t".into(),
            Op::PrintStr | Op::Abort | Op::PrintFmt => unsupported("takes a simulated address; use trax_print_str / trax_panic"),
            Op::Halt => unsupported("is not available natively (return from trax_main)"),
            Op::StreamWriteStart => "trax::host::stream_write_start(rs)".into(),
            Op::StreamWrite => "trax::host::stream_write_word(rs)".into(),
            Op::StreamWriteEnd => "trax::host::stream_write_end()".into(),
            Op::StreamReadStart => "trax::host::stream_read_start()".into(),
            Op::StreamRead => "trax::host::stream_read_word()".into(),
            Op::StreamReadEnd => "trax::host::stream_read_end()".into(),
            Op::StreamSize => "trax::host::stream_size(rs)".into(),
            Op::StreamSchedule => "trax::host::stream_schedule()".into(),
            Op::StreamCapacity => "trax::host::stream_capacity()".into(),
        };
        let allow = if body.starts_with("panic!") {
            "#[allow(unused_variables)]\n"
        } else {
            ""
        };
        s += &format!(
            "{allow}#[no_mangle]\npub extern \"C\" fn {name}({params}){ret} {{\n    {body}\n}}\n\n"
        );
    }
    s += HOST_SHIM_CXX;
    s += &trax_runtime::cheader::libm_c_exports();
    s += "}\n";
    s
}

/// `main` of a C or C++ kernel's host program (with [`host_shim`]): every host thread
/// runs the C/C++ constructors, then `trax_main`, as every hardware thread does on the
/// machine (`runtime::startup`). Also appended to a TRaX-Rust crate without `trax_main`
/// that exports functions to the C kernel.
pub const HOST_MAIN_C: &str = r#"
extern "C" {
    #[link_name = "trax_main"]
    fn c_trax_main();
    fn __trax_run_inits();
}

fn kernel() {
    // SAFETY: `__trax_run_inits` calls the objects' constructors (HOST_INITS_C) and
    // `trax_main` is the C kernel's entry point, `void trax_main(void)`.
    unsafe {
        __trax_run_inits();
        c_trax_main()
    }
}

fn main() {
    trax::host::host_main(kernel)
}
"#;

/// `main` of a TRaX-Rust kernel's host program when C or C++ files are linked with it
/// (appended with [`host_shim`]): constructors, then the kernel's `trax_main`.
pub const HOST_MAIN_RUST_WITH_C: &str = r#"
extern "C" {
    fn __trax_run_inits();
}

fn __trax_entry() {
    // SAFETY: `__trax_run_inits` calls the C objects' constructors (HOST_INITS_C).
    unsafe { __trax_run_inits() };
    trax_main()
}

fn main() {
    trax::host::host_main(__trax_entry)
}
"#;

/// The C++ ABI functions of [`RUNTIME_C`] on the host.
const HOST_SHIM_CXX: &str = r#"#[no_mangle]
pub extern "C" fn __cxa_pure_virtual() -> ! {
    panic!("pure virtual method called")
}

#[no_mangle]
pub extern "C" fn __cxa_deleted_virtual() -> ! {
    panic!("deleted virtual method called")
}

#[no_mangle]
pub extern "C" fn _ZdlPv(_: *mut u8) -> ! {
    panic!("operator delete called: TRaX kernels have no heap")
}

#[no_mangle]
pub extern "C" fn _ZdlPvm(_: *mut u8, _: usize) -> ! {
    panic!("operator delete called: TRaX kernels have no heap")
}

"#;

/// Runs the constructors of host-compiled C and C++ objects, whose `.init_array`
/// sections [`move_constructors`] renamed to `trax_inits` (so the C library does not
/// run them once at start-up): the linker's `__start_`/`__stop_` symbols bound them.
pub const HOST_INITS_C: &str = r#"typedef void (*trax_init_fn)(void);
extern const trax_init_fn __start_trax_inits[] __attribute__((weak, visibility("hidden")));
extern const trax_init_fn __stop_trax_inits[] __attribute__((weak, visibility("hidden")));
void __trax_run_inits(void) {
    for (const trax_init_fn *p = __start_trax_inits; p < __stop_trax_inits; p++)
        (*p)();
}
"#;

const HOST_SHIM_HEAD: &str = r#"
/// The host side of trax_host.h (generated by trax::clang::host_shim).
#[allow(clippy::all, dead_code)]
mod __trax_c_api {
use std::cell::RefCell;
use std::io::Write;

/// Output of this thread up to its next newline (one line is printed at a time).
struct Line(RefCell<String>);

impl Drop for Line {
    fn drop(&mut self) {
        let s = self.0.borrow();
        if !s.is_empty() {
            let _ = std::io::stdout().lock().write_all(s.as_bytes());
        }
    }
}

thread_local! {
    static LINE: Line = Line(RefCell::new(String::new()));
    static COP2: RefCell<[f32; 32]> = const { RefCell::new([0.0; 32]) };
}

fn out(text: &str) {
    LINE.with(|l| {
        let mut s = l.0.borrow_mut();
        s.push_str(text);
        if let Some(end) = s.rfind('\n') {
            let _ = std::io::stdout().lock().write_all(s[..=end].as_bytes());
            s.drain(..=end);
        }
    });
}

fn cop2() -> [f32; 32] {
    COP2.with(|c| *c.borrow())
}

fn set_cop2(reg: u32, x: f32) {
    COP2.with(|c| c.borrow_mut()[(reg & 31) as usize] = x);
}

#[no_mangle]
pub extern "C" fn __trax_host_ptr(addr: u32) -> *mut u8 {
    trax::host::host_ptr(addr)
}

#[no_mangle]
pub extern "C" fn __trax_host_print_str(s: *const u8, n: u32) {
    // SAFETY: trax_print_str passes a C string and its length.
    let bytes = unsafe { std::slice::from_raw_parts(s, n as usize) };
    out(&String::from_utf8_lossy(bytes));
}

#[no_mangle]
pub extern "C" fn __trax_host_panic(s: *const u8, n: u32) -> ! {
    // SAFETY: trax_panic passes a C string and its length.
    let bytes = unsafe { std::slice::from_raw_parts(s, n as usize) };
    panic!("{}", String::from_utf8_lossy(bytes))
}

#[no_mangle]
pub extern "C" fn __trax_host_mtc2(reg: u32, x: f32) {
    set_cop2(reg, x)
}

#[no_mangle]
pub extern "C" fn __trax_host_mfc2(reg: u32) -> f32 {
    cop2()[(reg & 31) as usize]
}

"#;

/// Compiles a C or C++ kernel for the host (`trax native`): `-DTRAX_HOST` selects the
/// host side of `trax.h`; the float flags are the TRaX ones and `long double` is 64-bit,
/// as on the machine, so results match.
pub fn compile_host(src: &Path, lang: Lang, out: &Path) -> Result<(), ClangError> {
    let clang = find_clang().ok_or_else(|| ClangError::Missing {
        file: src.display().to_string(),
    })?;
    let include = include_dir()?;
    let mut cmd = Command::new(&clang);
    match lang {
        Lang::C => cmd.args(["-x", "c", "-std=c11"]),
        Lang::Cpp => cmd.args([
            "-x",
            "c++",
            "-std=c++17",
            "-fno-exceptions",
            "-fno-rtti",
            "-fno-threadsafe-statics",
        ]),
    };
    // `long double` is `double` on o32; x86 hosts would use the 80-bit format.
    if cfg!(any(target_arch = "x86_64", target_arch = "x86")) {
        cmd.arg("-mlong-double-64");
    }
    cmd.args([
        "-DTRAX_HOST",
        "-O2",
        "-g",
        "-fPIE",
        "-fno-math-errno",
        "-ffp-contract=off",
        "-fdiagnostics-color=never",
        "-c",
    ])
    .arg("-I")
    .arg(&include)
    .arg(src)
    .arg("-o")
    .arg(out);
    run(&mut cmd, &clang)
}

/// Renames the `.init_array` sections of a host object (ELF64 little-endian, as clang
/// writes for x86-64 and AArch64 Linux) to `trax_inits`, typed `SHT_PROGBITS` and marked
/// `SHF_GNU_RETAIN`, so the C library does not run the constructors once at start-up and
/// [`HOST_INITS_C`] runs them on every kernel thread, as the machine's start-up code does.
/// Returns how many sections were moved. The name is patched in place: `trax_inits` and
/// its terminating NUL take the bytes of `.init_array` (a `.rela.init_array` sharing the
/// string becomes `.relatrax_inits`, which linkers do not read; `.init_array.NNNNN`
/// priority sections become plain `trax_inits`, so priorities are not kept).
pub fn move_constructors(obj: &mut [u8]) -> Result<usize, String> {
    use object::read::elf::{FileHeader, SectionHeader};
    const NAME: &[u8] = b".init_array";
    const NEW: &[u8; 11] = b"trax_inits\0";
    let mut patches: Vec<(usize, usize)> = Vec::new(); // (header offset, name offset)
    {
        let data: &[u8] = obj;
        let header = object::elf::FileHeader64::<object::Endianness>::parse(data)
            .map_err(|e| format!("not an ELF64 object: {e}"))?;
        let endian = header.endian().map_err(|e| e.to_string())?;
        let shoff = header.e_shoff(endian) as usize;
        let entsize = header.e_shentsize(endian) as usize;
        let sections = header
            .section_headers(endian, data)
            .map_err(|e| e.to_string())?;
        let strndx = header
            .section_strings_index(endian, data)
            .map_err(|e| e.to_string())?;
        let strtab = sections
            .get(strndx.0)
            .and_then(|s| s.file_range(endian))
            .ok_or("no section name table")?
            .0 as usize;
        for (i, sh) in sections.iter().enumerate() {
            let name = strtab + sh.sh_name(endian) as usize;
            let starts = data.get(name..name + NAME.len()) == Some(NAME);
            if starts && sh.sh_type(endian) == object::elf::SHT_INIT_ARRAY {
                patches.push((shoff + i * entsize, name));
            }
        }
    }
    let little = obj.get(5) == Some(&1);
    for &(hdr, name) in &patches {
        obj[name..name + NEW.len()].copy_from_slice(NEW);
        // sh_type at +4 (u32), sh_flags at +8 (u64) in an Elf64_Shdr.
        let ty: u32 = object::elf::SHT_PROGBITS.0;
        let flags_at = hdr + 8..hdr + 16;
        let mut flags = [0u8; 8];
        flags.copy_from_slice(&obj[flags_at.clone()]);
        let flags = if little {
            u64::from_le_bytes(flags)
        } else {
            u64::from_be_bytes(flags)
        } | object::elf::SHF_GNU_RETAIN.0;
        let (t, f) = if little {
            (ty.to_le_bytes(), flags.to_le_bytes())
        } else {
            (ty.to_be_bytes(), flags.to_be_bytes())
        };
        obj[hdr + 4..hdr + 8].copy_from_slice(&t);
        obj[flags_at].copy_from_slice(&f);
    }
    Ok(patches.len())
}

/// How an object defines the kernel entry point.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EntryPoint {
    /// `trax_main` with C linkage.
    Defined,
    /// Only a C++ function `trax_main()` (mangled `_Z9trax_mainv`): C++ linkage.
    CppLinkage,
    /// Neither.
    Missing,
}

/// Whether the object `obj` (any ELF) defines `trax_main`.
pub fn entry_point(obj: &[u8]) -> EntryPoint {
    let mut found = EntryPoint::Missing;
    for name in trax_runtime::exe::defined_global_symbols(obj) {
        match name.as_str() {
            "trax_main" => return EntryPoint::Defined,
            "_Z9trax_mainv" => found = EntryPoint::CppLinkage,
            _ => {}
        }
    }
    found
}

/// The error for C and C++ sources of which none defines `trax_main` (`files` names
/// them), with a hint when a C++ file has `trax_main` with C++ linkage.
pub fn no_entry_message(files: &str, cpp_linkage: bool) -> String {
    let mut m = format!(
        "{files}: no `trax_main`, the kernel entry point every hardware thread runs: define `void trax_main(void)` (C) or `extern \"C\" void trax_main()` (C++)"
    );
    if cpp_linkage {
        m += "; a C++ `trax_main()` was found, but with C++ linkage (mangled `_Z9trax_mainv`): declare it `extern \"C\"` or include <trax.h>, which does";
    }
    m
}
