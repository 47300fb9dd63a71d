//! Native builds (`trax native`): a TRaX-Rust kernel built by rustc against the host
//! implementation of the prelude (crate `trax`, `runtime/prelude/`), and C/C++ kernels
//! built by clang for the host, run on host threads over a memory-image file — a fast
//! functional reference for the emulator. [`check`] runs rustc's own checking (moves,
//! borrows, exhaustiveness, `unsafe`) on kernels the trax compiler builds.
//!
//! Steps of a native build: (1) the prelude is written out from
//! `trax_runtime::prelude::FILES` and built as an rlib named `trax` ([`build_prelude`]);
//! (2) the kernel is compiled from stdin with the current directory set to the kernel's
//! directory (so `mod x;` files resolve), with `fn main() { trax::host::host_main(trax_main)
//! }` appended (or the C kernel's entry when the Rust crate only exports `#[no_mangle]
//! extern "C"` functions) — C and C++ sources are compiled by clang for the host
//! (`crate::clang::compile_host`, constructors moved so they run on every kernel thread)
//! and linked in, with `crate::clang::host_shim()` (and, for a C/C++ kernel alone,
//! `HOST_MAIN_C` as the whole program) ([`build_program`]); (3) a memory image (format:
//! `trax_runtime::image`, segments with permissions) is written, the program runs over it
//! and writes the framebuffer back ([`run_kernel`]). Builds are cached in
//! `$TRAX_CACHE_DIR` (default `~/.cache/trax`, [`crate::clang::cache_dir`]) keyed by a hash
//! of the sources and the rustc version. Diagnostics and panic locations name the kernel
//! file (rustc calls stdin `<anon>`; we rewrite it).

pub mod check;

use std::ffi::OsString;
use std::io::{BufRead, BufReader, Write};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

use crate::pipeline::PrepareError;
use trax_runtime::image::{ImageError, MemoryImage};
use trax_runtime::prelude::{self, Fnv1a};

/// What went wrong in a native build or run; the message names the file or the program.
#[derive(Debug, thiserror::Error)]
pub enum NativeError {
    /// A file could not be read or written.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: String,
        /// What went wrong.
        source: std::io::Error,
    },
    /// rustc could not be run.
    #[error("cannot run `{rustc}` (set RUSTC or install Rust): {source}")]
    NoRustc {
        /// The program tried.
        rustc: String,
        /// What went wrong.
        source: std::io::Error,
    },
    /// rustc could not build the host prelude (its diagnostics).
    #[error("building the trax prelude with rustc failed:\n{0}")]
    PreludeBuild(String),
    /// Neither the Rust kernel nor a C file defines `trax_main`.
    #[error("{kernel}: no `fn trax_main()` (the kernel entry point) found")]
    NoEntry {
        /// The kernel.
        kernel: String,
    },
    /// The files cannot make one native program (the message says why).
    #[error("{0}")]
    Files(String),
    /// rustc or clang rejected the kernel (their diagnostics went to stderr).
    #[error("{kernel}: compilation failed")]
    KernelBuild {
        /// The kernel.
        kernel: String,
    },
    /// clang could not be run.
    #[error("{0}")]
    Clang(crate::clang::ClangError),
    /// The scene image could not be prepared.
    #[error("{0}")]
    Prepare(#[from] PrepareError),
    /// The memory image file could not be written or read back.
    #[error("{0}")]
    Image(#[from] ImageError),
    /// The kernel process failed (a panic: its message went to stderr).
    #[error("{kernel}: the kernel crashed (exit status {status})")]
    Crashed {
        /// The kernel.
        kernel: String,
        /// Its exit status.
        status: i32,
    },
}

pub(crate) fn io_err(path: &Path) -> impl FnOnce(std::io::Error) -> NativeError + '_ {
    move |source| NativeError::Io {
        path: path.display().to_string(),
        source,
    }
}

/// Stack bytes of rustc's compiler thread (`RUST_MIN_STACK`, unless the user set it): as
/// much as the trax compiler's own thread, so a program nested as deeply as trax accepts
/// (3000 nested `if`s, a 4000-term chain) is checked rather than crashing rustc. Only
/// address space: the pages a shallow program does not touch are never allocated.
pub const RUSTC_STACK: usize = 512 << 20;

/// The rustc to use (`$RUSTC`, else `rustc` on `PATH`) and its version (part of every
/// cache key).
pub struct Rustc {
    /// The program run.
    pub program: OsString,
    /// `rustc -vV`'s output.
    pub version: String,
}

impl Rustc {
    /// Finds rustc and reads its version; an error if it cannot be run.
    pub fn find() -> Result<Rustc, NativeError> {
        let program = std::env::var_os("RUSTC").unwrap_or_else(|| "rustc".into());
        let out = Command::new(&program)
            .arg("-vV")
            .output()
            .map_err(|source| NativeError::NoRustc {
                rustc: program.to_string_lossy().into_owned(),
                source,
            })?;
        Ok(Rustc {
            program,
            version: String::from_utf8_lossy(&out.stdout).into_owned(),
        })
    }

    /// A rustc command with the flags of every native build (edition 2021, `-O2`, integer
    /// overflow wrapping as on the machine), and the stack the trax compiler has
    /// ([`RUSTC_STACK`]): deep but valid kernels overflow rustc's default 8 MiB.
    pub fn command(&self) -> Command {
        let mut c = Command::new(&self.program);
        if std::env::var_os("RUST_MIN_STACK").is_none() {
            c.env("RUST_MIN_STACK", RUSTC_STACK.to_string());
        }
        c.args([
            "--edition",
            "2021",
            "-C",
            "opt-level=2",
            "-C",
            "overflow-checks=off",
            "-C",
            "debug-assertions=off",
        ]);
        c
    }
}

/// A fresh, unique scratch directory inside `parent`.
pub(crate) fn scratch_dir(parent: &Path, tag: &str) -> Result<PathBuf, NativeError> {
    let nanos = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map(|d| d.as_nanos())
        .unwrap_or(0);
    let d = parent.join(format!(".{tag}-{}-{nanos}", std::process::id()));
    std::fs::create_dir_all(&d).map_err(io_err(&d))?;
    Ok(d)
}

/// Moves a finished build from `tmp` to `fin` atomically; if another process won the
/// race, keeps theirs.
pub(crate) fn publish(tmp: &Path, fin: &Path) -> Result<(), NativeError> {
    match std::fs::rename(tmp, fin) {
        Ok(()) => Ok(()),
        Err(_) if fin.exists() => {
            let _ = std::fs::remove_dir_all(tmp);
            Ok(())
        }
        Err(e) => Err(io_err(fin)(e)),
    }
}

/// Builds (or finds in the cache) the host prelude rlib; returns its path.
pub fn build_prelude(rustc: &Rustc, cache: &Path) -> Result<PathBuf, NativeError> {
    build_prelude_as(rustc, cache, false)
}

/// Builds (or finds in the cache) the host prelude as an rlib, or only its metadata
/// (`libtrax.rmeta`: enough for checking a kernel, no code generated, a fraction of the
/// time); returns its path. Spans into the prelude name its files in the source tree
/// (`trax_runtime::prelude::DIR`).
pub(crate) fn build_prelude_as(
    rustc: &Rustc,
    cache: &Path,
    metadata_only: bool,
) -> Result<PathBuf, NativeError> {
    let mut h = Fnv1a::new();
    h.write(&prelude::content_hash().to_le_bytes());
    h.write(rustc.version.as_bytes());
    let (tag, file) = if metadata_only {
        ("prelude-meta", "libtrax.rmeta")
    } else {
        ("prelude", "libtrax.rlib")
    };
    let dir = cache.join(format!("{tag}-{:016x}", h.finish()));
    let out_file = dir.join(file);
    if out_file.is_file() {
        return Ok(out_file);
    }
    std::fs::create_dir_all(cache).map_err(io_err(cache))?;
    let tmp = scratch_dir(cache, tag)?;
    for (p, src) in prelude::FILES {
        let path = tmp.join("prelude").join(p);
        if let Some(parent) = path.parent() {
            std::fs::create_dir_all(parent).map_err(io_err(parent))?;
        }
        std::fs::write(&path, src).map_err(io_err(&path))?;
    }
    let mut cmd = rustc.command();
    cmd.args([
        "--crate-type",
        "rlib",
        "--crate-name",
        "trax",
        "--cap-lints",
        "allow",
    ]);
    if metadata_only {
        let source_root = Path::new(prelude::DIR).parent().unwrap_or(Path::new("/"));
        cmd.arg("--emit=metadata").arg(format!(
            "--remap-path-prefix={}={}",
            tmp.display(),
            source_root.display()
        ));
    }
    let out = cmd
        .arg(tmp.join("prelude").join(prelude::ROOT))
        .arg("-o")
        .arg(tmp.join(file))
        .output()
        .map_err(|source| NativeError::NoRustc {
            rustc: rustc.program.to_string_lossy().into_owned(),
            source,
        })?;
    if !out.status.success() {
        let _ = std::fs::remove_dir_all(&tmp);
        return Err(NativeError::PreludeBuild(
            String::from_utf8_lossy(&out.stderr).into_owned(),
        ));
    }
    publish(&tmp, &dir)?;
    Ok(out_file)
}

/// Builds (or finds in the cache) the host program of a kernel and the C/C++ sources
/// linked with it: finds rustc, builds the prelude rlib, compiles and links.
pub fn build_program(kernel: &Path, more: &[PathBuf]) -> Result<PathBuf, NativeError> {
    let cache = crate::clang::cache_dir();
    let rustc = Rustc::find()?;
    let rlib = build_prelude(&rustc, &cache)?;
    let files = NativeFiles::of(kernel, more)?;
    build(&rustc, &files, &rlib, &cache)
}

/// Hashes the kernel and every `.rs` file under its directory (its `mod` files).
fn kernel_hash(kernel: &Path, src: &str) -> Result<u64, NativeError> {
    let mut h = Fnv1a::new();
    h.write(src.as_bytes());
    let dir = kernel_dir(kernel);
    let mut files = Vec::new();
    collect_rs(&dir, 0, &mut files);
    files.sort();
    for f in files {
        if let Ok(bytes) = std::fs::read(&f) {
            h.write(f.to_string_lossy().as_bytes());
            h.write(&bytes);
        }
    }
    Ok(h.finish())
}

fn collect_rs(dir: &Path, depth: u32, out: &mut Vec<PathBuf>) {
    let Ok(rd) = std::fs::read_dir(dir) else {
        return;
    };
    for e in rd.flatten() {
        let p = e.path();
        if p.is_dir() && depth < 3 {
            collect_rs(&p, depth + 1, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

pub(crate) fn kernel_dir(kernel: &Path) -> PathBuf {
    match kernel.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

/// The text appended to a kernel to make it a host program.
const MAIN_SHIM: &str = "\nfn main() {\n    trax::host::host_main(trax_main)\n}\n";

/// The files of one `trax native` program: at most one TRaX-Rust crate root and any
/// number of C and C++ sources.
pub struct NativeFiles {
    /// The TRaX-Rust kernel, if any.
    rust: Option<PathBuf>,
    /// C and C++ sources.
    c: Vec<(PathBuf, crate::clang::Lang)>,
}

impl NativeFiles {
    /// Sorts `kernel` and `more` into the Rust crate root and the C/C++ sources; an error
    /// for a second Rust root or a file that is not a source.
    pub fn of(kernel: &Path, more: &[PathBuf]) -> Result<NativeFiles, NativeError> {
        let mut f = NativeFiles {
            rust: None,
            c: Vec::new(),
        };
        for p in std::iter::once(kernel).chain(more.iter().map(PathBuf::as_path)) {
            if let Some(lang) = crate::clang::lang_of(p) {
                f.c.push((p.to_path_buf(), lang));
            } else if p.extension().is_some_and(|e| e == "rs") {
                if let Some(first) = &f.rust {
                    return Err(NativeError::Files(format!(
                        "{}: `trax native` builds one TRaX-Rust crate (here {}); give further Rust code as `mod` files of it",
                        p.display(),
                        first.display()
                    )));
                }
                f.rust = Some(p.to_path_buf());
            } else {
                return Err(NativeError::Files(format!(
                    "{}: `trax native` builds sources (.rs, .c, .cpp, .cc); objects and executables are for the machine",
                    p.display()
                )));
            }
        }
        Ok(f)
    }
}

/// Builds (or finds in the cache) the host program of `files`: a TRaX-Rust kernel (with
/// any C/C++ objects linked in) or C/C++ sources alone; returns the executable.
pub fn build(
    rustc: &Rustc,
    files: &NativeFiles,
    rlib: &Path,
    cache: &Path,
) -> Result<PathBuf, NativeError> {
    let tmp = scratch_dir(cache, "cobjs")?;
    let result = (|| {
        let objs = compile_c_objects(files, &tmp)?;
        match &files.rust {
            Some(k) => build_kernel(rustc, k, &objs, rlib, cache),
            None => build_c_kernel(rustc, files, &objs, rlib, cache),
        }
    })();
    let _ = std::fs::remove_dir_all(&tmp);
    result
}

/// Compiles the C and C++ sources for the host into `dir` (constructors moved to
/// `trax_inits`, see `crate::clang::move_constructors`), plus the constructor runner
/// when there are any; returns the objects.
fn compile_c_objects(files: &NativeFiles, dir: &Path) -> Result<Vec<PathBuf>, NativeError> {
    let mut objs = Vec::new();
    let clang_err = |e: crate::clang::ClangError, kernel: &Path| match e {
        crate::clang::ClangError::Diagnostics { diagnostics } => {
            eprint!("{diagnostics}");
            NativeError::KernelBuild {
                kernel: kernel.display().to_string(),
            }
        }
        e => NativeError::Clang(e),
    };
    for (i, (src, lang)) in files.c.iter().enumerate() {
        let obj = dir.join(format!("{i}.o"));
        crate::clang::compile_host(src, *lang, &obj).map_err(|e| clang_err(e, src))?;
        let mut bytes = std::fs::read(&obj).map_err(io_err(&obj))?;
        crate::clang::move_constructors(&mut bytes)
            .map_err(|e| NativeError::Files(format!("{}: {e}", src.display())))?;
        std::fs::write(&obj, &bytes).map_err(io_err(&obj))?;
        objs.push(obj);
    }
    if !objs.is_empty() {
        let src = dir.join("trax_inits.c");
        std::fs::write(&src, crate::clang::HOST_INITS_C).map_err(io_err(&src))?;
        let obj = dir.join("trax_inits.o");
        crate::clang::compile_host(&src, crate::clang::Lang::C, &obj)
            .map_err(|e| clang_err(e, &src))?;
        objs.push(obj);
    }
    Ok(objs)
}

/// Hashes the bytes of `objs` into `h`.
fn hash_objects(h: &mut Fnv1a, objs: &[PathBuf]) -> Result<(), NativeError> {
    for o in objs {
        h.write(&std::fs::read(o).map_err(io_err(o))?);
        h.write(&[0xff]);
    }
    Ok(())
}

/// Builds (or finds in the cache) the kernel executable, linked with `objs` (C/C++
/// objects; then with `crate::clang::host_shim()`); returns its path.
fn build_kernel(
    rustc: &Rustc,
    kernel: &Path,
    objs: &[PathBuf],
    rlib: &Path,
    cache: &Path,
) -> Result<PathBuf, NativeError> {
    let src = std::fs::read_to_string(kernel).map_err(io_err(kernel))?;
    // The entry point is the Rust kernel's, or a C file's when the Rust crate only
    // exports functions to C (`#[no_mangle] extern "C" fn`).
    let rust_entry = src.contains("fn trax_main");
    let mut c_entry = false;
    for o in objs {
        let bytes = std::fs::read(o).map_err(io_err(o))?;
        c_entry |= crate::clang::entry_point(&bytes) == crate::clang::EntryPoint::Defined;
    }
    if !rust_entry && !c_entry {
        return Err(NativeError::NoEntry {
            kernel: kernel.display().to_string(),
        });
    }
    let tail = if objs.is_empty() {
        MAIN_SHIM.to_string()
    } else if rust_entry {
        format!(
            "{}{}",
            crate::clang::HOST_MAIN_RUST_WITH_C,
            crate::clang::host_shim()
        )
    } else {
        format!("{}{}", crate::clang::HOST_MAIN_C, crate::clang::host_shim())
    };
    let mut h = Fnv1a::new();
    h.write(&kernel_hash(kernel, &src)?.to_le_bytes());
    h.write(tail.as_bytes());
    hash_objects(&mut h, objs)?;
    h.write(rlib.to_string_lossy().as_bytes());
    h.write(rustc.version.as_bytes());
    let dir = cache.join(format!("kernel-{:016x}", h.finish()));
    let exe = dir.join("kernel");
    if exe.is_file() {
        return Ok(exe);
    }
    let tmp = scratch_dir(cache, "kernel")?;
    let full = format!("{src}{tail}");
    let link = Link {
        rlib,
        objs,
        out: &tmp.join("kernel"),
        cwd: Some(&kernel_dir(kernel)),
    };
    let out = link.run(rustc, &full, kernel)?;
    let diag = String::from_utf8_lossy(&out.stderr);
    let shown = kernel.display().to_string();
    if !diag.is_empty() {
        eprint!("{}", diag.replace("<anon>", &shown));
    }
    if !out.status.success() {
        let _ = std::fs::remove_dir_all(&tmp);
        return Err(NativeError::KernelBuild { kernel: shown });
    }
    publish(&tmp, &dir)?;
    Ok(exe)
}

/// One host program linked by rustc over the host prelude: the crate read from stdin,
/// `objs` (clang's objects) passed to the linker.
struct Link<'a> {
    /// The host prelude rlib (`--extern trax=`).
    rlib: &'a Path,
    /// Objects to link in.
    objs: &'a [PathBuf],
    /// The program to write.
    out: &'a Path,
    /// rustc's working directory (where relative `include!`s resolve), if not ours.
    cwd: Option<&'a Path>,
}

impl Link<'_> {
    /// Runs rustc on `source`; rustc's output, or an error naming `name` if it could not be
    /// waited for. (A failed write to its stdin shows up as a build failure.)
    fn run(
        &self,
        rustc: &Rustc,
        source: &str,
        name: &Path,
    ) -> Result<std::process::Output, NativeError> {
        let mut cmd = rustc.command();
        cmd.args(["--crate-type", "bin", "--crate-name", "trax_kernel", "-"])
            .arg("--extern")
            .arg(format!("trax={}", self.rlib.display()));
        for o in self.objs {
            cmd.arg("-C").arg(format!("link-arg={}", o.display()));
        }
        cmd.arg("-o").arg(self.out);
        if let Some(dir) = self.cwd {
            cmd.current_dir(dir);
        }
        let mut child = cmd
            .stdin(Stdio::piped())
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .map_err(|source| NativeError::NoRustc {
                rustc: rustc.program.to_string_lossy().into_owned(),
                source,
            })?;
        if let Some(mut stdin) = child.stdin.take() {
            let _ = stdin.write_all(source.as_bytes());
        }
        child.wait_with_output().map_err(io_err(name))
    }
}

/// Builds (or finds in the cache) the host program of C and C++ sources: clang compiled
/// them with `trax.h`'s host side (`objs`), rustc links them with
/// `crate::clang::host_shim()` over the host prelude.
fn build_c_kernel(
    rustc: &Rustc,
    files: &NativeFiles,
    objs: &[PathBuf],
    rlib: &Path,
    cache: &Path,
) -> Result<PathBuf, NativeError> {
    let names = || {
        files
            .c
            .iter()
            .map(|(p, _)| p.display().to_string())
            .collect::<Vec<_>>()
            .join(", ")
    };
    // The entry point: a clear error here instead of the system linker's.
    let mut cpp_linkage = false;
    let mut defined = false;
    for o in objs {
        match crate::clang::entry_point(&std::fs::read(o).map_err(io_err(o))?) {
            crate::clang::EntryPoint::Defined => defined = true,
            crate::clang::EntryPoint::CppLinkage => cpp_linkage = true,
            crate::clang::EntryPoint::Missing => {}
        }
    }
    if !defined {
        return Err(NativeError::Files(crate::clang::no_entry_message(
            &names(),
            cpp_linkage,
        )));
    }
    let shim = format!("{}{}", crate::clang::HOST_MAIN_C, crate::clang::host_shim());
    let mut h = Fnv1a::new();
    hash_objects(&mut h, objs)?;
    h.write(shim.as_bytes());
    h.write(rlib.to_string_lossy().as_bytes());
    h.write(rustc.version.as_bytes());
    let dir = cache.join(format!("ckernel-{:016x}", h.finish()));
    let exe = dir.join("kernel");
    if exe.is_file() {
        return Ok(exe);
    }
    let tmp = scratch_dir(cache, "ckernel")?;
    let link = Link {
        rlib,
        objs,
        out: &tmp.join("kernel"),
        cwd: None,
    };
    let out = link.run(rustc, &shim, &tmp)?;
    if !out.status.success() {
        eprint!("{}", String::from_utf8_lossy(&out.stderr));
        let _ = std::fs::remove_dir_all(&tmp);
        return Err(NativeError::KernelBuild { kernel: names() });
    }
    publish(&tmp, &dir)?;
    Ok(exe)
}

/// Runs the kernel program `exe` (built from `kernel`) over `image` on `shape`'s host
/// threads; returns the final framebuffer (one segment, or none if the image has no
/// framebuffer).
pub fn run_kernel(
    exe: &Path,
    kernel: &Path,
    image: &MemoryImage,
    shape: &HostShape,
) -> Result<MemoryImage, NativeError> {
    let tmp = scratch_dir(&crate::clang::cache_dir(), "run")?;
    let result = run_in(exe, kernel, image, shape, &tmp);
    let _ = std::fs::remove_dir_all(&tmp);
    result
}

/// What the host runner takes from the chip config besides the memory image (whose
/// header carries the stream memory's shape).
pub struct HostShape {
    /// TMs.
    pub tms: u32,
    /// Threads per TM.
    pub threads: u32,
    /// `stream_memory.schedule`.
    pub schedule: &'static str,
    /// The spill sentinel (`stream_memory.overflow = "spill"`), in its argument form.
    pub spill: Option<String>,
}

fn run_in(
    exe: &Path,
    kernel: &Path,
    image: &MemoryImage,
    shape: &HostShape,
    tmp: &Path,
) -> Result<MemoryImage, NativeError> {
    let input = tmp.join("image.bin");
    let output = tmp.join("framebuffer.bin");
    image.write_file(&input)?;
    let mut child = Command::new(exe)
        .arg(&input)
        .arg(&output)
        .arg(shape.tms.to_string())
        .arg(shape.threads.to_string())
        .arg(shape.schedule)
        .args(shape.spill.as_deref())
        .stdin(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(io_err(exe))?;
    // Forward the kernel's stderr, naming the kernel file in panic locations.
    let shown = kernel.display().to_string();
    if let Some(err) = child.stderr.take() {
        let stderr = std::io::stderr();
        for line in BufReader::new(err).lines() {
            let Ok(line) = line else { break };
            let _ = writeln!(stderr.lock(), "{}", line.replace("<anon>", &shown));
        }
    }
    let status = child.wait().map_err(io_err(exe))?;
    if !status.success() {
        return Err(NativeError::Crashed {
            kernel: shown,
            status: status.code().unwrap_or(-1),
        });
    }
    Ok(MemoryImage::read_file(&output)?)
}
