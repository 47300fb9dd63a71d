//! `trax native`: builds a kernel with rustc against the host implementation of the
//! prelude (crate `trax`, `runtime/prelude/`) and runs it on host threads — a fast
//! functional reference for the emulator.
//!
//! The machine matches `trax run`'s: the thread shape comes from the same chip config
//! (`--config`, default `trax_emulator::timing::DEFAULT_CHIP`, with `--tms`/`--threads` overrides), and the
//! memory image holds the scene components `trax run` would lay out — the kernel is also
//! built with the trax compiler (as `trax run` does, at `-O2`) to learn which header
//! fields it references — so per-triangle data is in the same order (BVH leaf order only
//! when the kernel reads the BVH) and images are identical.
//!
//! Steps: (1) the prelude is written out from `trax_runtime::prelude::FILES` and built as
//! an rlib named `trax`; (2) the kernel is compiled from stdin with the current directory
//! set to the kernel's directory (so `mod x;` files resolve), with
//! `fn main() { trax::host::host_main(trax_main) }` appended (or the C kernel's entry when
//! the Rust crate only exports `#[no_mangle] extern "C"` functions) — C and C++ sources are
//! compiled by clang for the host (`trax::clang::compile_host`, constructors moved so they
//! run on every kernel thread) and linked in, with `trax::clang::host_shim()` (and, for a
//! C/C++ kernel alone, `HOST_MAIN_C` as the whole program); (3) a memory image (format:
//! `trax_runtime::image`, segments with permissions) is written, the program runs over it and writes the framebuffer
//! back; (4) the framebuffer becomes a PNG. Builds are cached in `$TRAX_CACHE_DIR` (default
//! `~/.cache/trax`) keyed by a hash of the sources and the rustc version. Diagnostics
//! and panic locations name the kernel file (rustc calls stdin `<anon>`; we rewrite it).

use std::ffi::OsString;
use std::io::{BufRead, BufReader, Write};
use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode, Stdio};

use clap::Args;

use super::common::{PngArgs, RenderArgs, ShapeArgs};
use trax::pipeline::{self, chip_config, scene_report, PrepareError, DEFAULT_OPT_LEVEL};
use trax_runtime::image::{ImageError, MemoryImage};
use trax_runtime::prelude::{self, Fnv1a};

/// Arguments of `trax native`.
#[derive(Args, Debug)]
pub struct NativeArgs {
    /// The kernel source: TRaX-Rust (`fn trax_main()`), or C/C++ (`void trax_main(void)`,
    /// compiled for the host by clang with `trax.h`'s host side).
    pub kernel: PathBuf,
    /// Further C and C++ sources linked with the kernel (as for `trax run`); their
    /// constructors run on every kernel thread before `trax_main`, as on the machine.
    #[arg(value_name = "MORE")]
    pub more: Vec<PathBuf>,
    /// Scene and image parameters.
    #[command(flatten)]
    pub render: RenderArgs,
    /// The chip whose thread shape (TMs x threads) to run, as for `trax run`.
    #[command(flatten)]
    pub shape: ShapeArgs,
    /// The PNG and its exposure.
    #[command(flatten)]
    pub png: PngArgs,
    /// Also write the raw framebuffer: `width*height` pixels of 3 little-endian f32.
    #[arg(long)]
    pub raw_framebuffer: Option<PathBuf>,
}

/// What went wrong in `trax native`.
#[derive(Debug, thiserror::Error)]
pub enum NativeError {
    #[error("{path}: {source}")]
    Io {
        path: String,
        source: std::io::Error,
    },
    #[error("cannot run `{rustc}` (set RUSTC or install Rust): {source}")]
    NoRustc {
        rustc: String,
        source: std::io::Error,
    },
    #[error("building the trax prelude with rustc failed:\n{0}")]
    PreludeBuild(String),
    #[error("{kernel}: no `fn trax_main()` (the kernel entry point) found")]
    NoEntry { kernel: String },
    #[error("{0}")]
    Files(String),
    #[error("{kernel}: compilation failed")]
    KernelBuild { kernel: String },
    #[error("{0}")]
    Clang(trax::clang::ClangError),
    #[error("{0}")]
    Prepare(#[from] PrepareError),
    #[error("{0}")]
    Image(#[from] ImageError),
    #[error("--{flag} must be at least 1")]
    BadFlag { flag: &'static str },
    #[error("{0}")]
    Chip(String),
    #[error("--tms × --threads = {0} is more than the host runner supports (4096)")]
    TooManyThreads(u64),
    #[error("{kernel}: the kernel crashed (exit status {status})")]
    Crashed { kernel: String, status: i32 },
    #[error("{path}: cannot write PNG: {message}")]
    Png { path: String, message: String },
}

fn io_err(path: &Path) -> impl FnOnce(std::io::Error) -> NativeError + '_ {
    move |source| NativeError::Io {
        path: path.display().to_string(),
        source,
    }
}

/// Runs `trax native`.
pub fn run(a: NativeArgs) -> ExitCode {
    match native(&a) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

fn native(a: &NativeArgs) -> Result<(), NativeError> {
    for (flag, v) in [("width", a.render.width), ("height", a.render.height)] {
        if v == 0 {
            return Err(NativeError::BadFlag { flag });
        }
    }
    let s = &a.shape;
    let chip = chip_config(&s.config, &s.set, s.tms, s.threads, None).map_err(NativeError::Chip)?;
    let (tms, threads) = (chip.tms, chip.threads_per_tm);
    let total = tms as u64 * threads as u64;
    if total > 4096 {
        return Err(NativeError::TooManyThreads(total));
    }
    for out in a.png.output.iter().chain(&a.raw_framebuffer) {
        check_writable(out)?;
    }
    // rustc first: a kernel it rejects gets rustc's diagnostics and nothing else.
    let cache = cache_dir();
    let rustc = Rustc::find()?;
    let rlib = build_prelude(&rustc, &cache)?;
    let files = NativeFiles::of(&a.kernel, &a.more)?;
    let exe = build(&rustc, &files, &rlib, &cache)?;
    let mut request = a.render.request(&a.kernel, DEFAULT_OPT_LEVEL, &chip);
    request.more = a.more.clone();
    let (scene_image, warnings) = pipeline::scene_image(&request)?;
    for w in &warnings {
        eprintln!("warning: {w}");
    }
    let shape = HostShape {
        tms,
        threads,
        schedule: chip.stream_memory.schedule.name(),
        spill: chip.stream_memory.geometry().spill.map(|g| g.to_arg()),
    };
    let fb = run_kernel(&exe, &a.kernel, &scene_image.memory, &shape, &cache)?;
    eprint!("{}", scene_report(&scene_image));
    let bytes = fb
        .segments
        .first()
        .map(|s| s.data.as_slice())
        .unwrap_or(&[]);
    a.png
        .write(bytes, a.render.width, a.render.height)
        .map_err(NativeError::Files)?;
    if let Some(raw) = &a.raw_framebuffer {
        std::fs::write(raw, bytes).map_err(io_err(raw))?;
    }
    Ok(())
}

/// Fails early (before building and running) if `out` cannot be created.
fn check_writable(out: &Path) -> Result<(), NativeError> {
    let dir = out.parent().filter(|p| !p.as_os_str().is_empty());
    if let Some(d) = dir {
        if !d.is_dir() {
            return Err(NativeError::Io {
                path: out.display().to_string(),
                source: std::io::Error::new(
                    std::io::ErrorKind::NotFound,
                    "the output directory does not exist",
                ),
            });
        }
    }
    Ok(())
}

/// The build cache directory (shared with the C/C++ builds, see `trax::clang::cache_dir`).
fn cache_dir() -> PathBuf {
    trax::clang::cache_dir()
}

/// The rustc to use and its version (part of every cache key).
struct Rustc {
    program: OsString,
    version: String,
}

impl Rustc {
    fn find() -> Result<Rustc, NativeError> {
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

    fn command(&self) -> Command {
        let mut c = Command::new(&self.program);
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
fn scratch_dir(parent: &Path, tag: &str) -> Result<PathBuf, NativeError> {
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
fn publish(tmp: &Path, fin: &Path) -> Result<(), NativeError> {
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
fn build_prelude(rustc: &Rustc, cache: &Path) -> Result<PathBuf, NativeError> {
    let mut h = Fnv1a::new();
    h.write(&prelude::content_hash().to_le_bytes());
    h.write(rustc.version.as_bytes());
    let dir = cache.join(format!("prelude-{:016x}", h.finish()));
    let rlib = dir.join("libtrax.rlib");
    if rlib.is_file() {
        return Ok(rlib);
    }
    std::fs::create_dir_all(cache).map_err(io_err(cache))?;
    let tmp = scratch_dir(cache, "prelude")?;
    for (p, src) in prelude::FILES {
        let path = tmp.join("prelude").join(p);
        if let Some(parent) = path.parent() {
            std::fs::create_dir_all(parent).map_err(io_err(parent))?;
        }
        std::fs::write(&path, src).map_err(io_err(&path))?;
    }
    let out = rustc
        .command()
        .args([
            "--crate-type",
            "rlib",
            "--crate-name",
            "trax",
            "--cap-lints",
            "allow",
        ])
        .arg(tmp.join("prelude").join(prelude::ROOT))
        .arg("-o")
        .arg(tmp.join("libtrax.rlib"))
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
    Ok(rlib)
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

fn kernel_dir(kernel: &Path) -> PathBuf {
    match kernel.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

/// The text appended to a kernel to make it a host program.
const MAIN_SHIM: &str = "\nfn main() {\n    trax::host::host_main(trax_main)\n}\n";

/// The files of one `trax native` program: at most one TRaX-Rust crate root and any
/// number of C and C++ sources.
struct NativeFiles {
    /// The TRaX-Rust kernel, if any.
    rust: Option<PathBuf>,
    /// C and C++ sources.
    c: Vec<(PathBuf, trax::clang::Lang)>,
}

impl NativeFiles {
    fn of(kernel: &Path, more: &[PathBuf]) -> Result<NativeFiles, NativeError> {
        let mut f = NativeFiles {
            rust: None,
            c: Vec::new(),
        };
        for p in std::iter::once(kernel).chain(more.iter().map(PathBuf::as_path)) {
            if let Some(lang) = trax::clang::lang_of(p) {
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

/// Builds the host program of `files`: a TRaX-Rust kernel (with any C/C++ objects
/// linked in) or C/C++ sources alone.
fn build(
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
/// `trax_inits`, see `trax::clang::move_constructors`), plus the constructor runner
/// when there are any; returns the objects.
fn compile_c_objects(files: &NativeFiles, dir: &Path) -> Result<Vec<PathBuf>, NativeError> {
    let mut objs = Vec::new();
    let clang_err = |e: trax::clang::ClangError, kernel: &Path| match e {
        trax::clang::ClangError::Diagnostics { diagnostics } => {
            eprint!("{diagnostics}");
            NativeError::KernelBuild {
                kernel: kernel.display().to_string(),
            }
        }
        e => NativeError::Clang(e),
    };
    for (i, (src, lang)) in files.c.iter().enumerate() {
        let obj = dir.join(format!("{i}.o"));
        trax::clang::compile_host(src, *lang, &obj).map_err(|e| clang_err(e, src))?;
        let mut bytes = std::fs::read(&obj).map_err(io_err(&obj))?;
        trax::clang::move_constructors(&mut bytes)
            .map_err(|e| NativeError::Files(format!("{}: {e}", src.display())))?;
        std::fs::write(&obj, &bytes).map_err(io_err(&obj))?;
        objs.push(obj);
    }
    if !objs.is_empty() {
        let src = dir.join("trax_inits.c");
        std::fs::write(&src, trax::clang::HOST_INITS_C).map_err(io_err(&src))?;
        let obj = dir.join("trax_inits.o");
        trax::clang::compile_host(&src, trax::clang::Lang::C, &obj)
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
/// objects; then with `trax::clang::host_shim()`); returns its path.
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
        c_entry |= trax::clang::entry_point(&bytes) == trax::clang::EntryPoint::Defined;
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
            trax::clang::HOST_MAIN_RUST_WITH_C,
            trax::clang::host_shim()
        )
    } else {
        format!("{}{}", trax::clang::HOST_MAIN_C, trax::clang::host_shim())
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
    let mut cmd = rustc.command();
    cmd.args(["--crate-type", "bin", "--crate-name", "trax_kernel", "-"])
        .arg("--extern")
        .arg(format!("trax={}", rlib.display()));
    for o in objs {
        cmd.arg("-C").arg(format!("link-arg={}", o.display()));
    }
    let mut child = cmd
        .arg("-o")
        .arg(tmp.join("kernel"))
        .current_dir(kernel_dir(kernel))
        .stdin(Stdio::piped())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|source| NativeError::NoRustc {
            rustc: rustc.program.to_string_lossy().into_owned(),
            source,
        })?;
    let full = format!("{src}{tail}");
    if let Some(mut stdin) = child.stdin.take() {
        // A write error shows up as a compile failure below.
        let _ = stdin.write_all(full.as_bytes());
    }
    let out = child.wait_with_output().map_err(io_err(kernel))?;
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

/// Builds (or finds in the cache) the host program of C and C++ sources: clang compiled
/// them with `trax.h`'s host side (`objs`), rustc links them with
/// `trax::clang::host_shim()` over the host prelude.
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
        match trax::clang::entry_point(&std::fs::read(o).map_err(io_err(o))?) {
            trax::clang::EntryPoint::Defined => defined = true,
            trax::clang::EntryPoint::CppLinkage => cpp_linkage = true,
            trax::clang::EntryPoint::Missing => {}
        }
    }
    if !defined {
        return Err(NativeError::Files(trax::clang::no_entry_message(
            &names(),
            cpp_linkage,
        )));
    }
    let shim = format!("{}{}", trax::clang::HOST_MAIN_C, trax::clang::host_shim());
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
    let mut cmd = rustc.command();
    cmd.args(["--crate-type", "bin", "--crate-name", "trax_kernel", "-"])
        .arg("--extern")
        .arg(format!("trax={}", rlib.display()));
    for o in objs {
        cmd.arg("-C").arg(format!("link-arg={}", o.display()));
    }
    cmd.arg("-o")
        .arg(tmp.join("kernel"))
        .stdin(Stdio::piped())
        .stdout(Stdio::null())
        .stderr(Stdio::piped());
    let mut child = cmd.spawn().map_err(|source| NativeError::NoRustc {
        rustc: rustc.program.to_string_lossy().into_owned(),
        source,
    })?;
    if let Some(mut stdin) = child.stdin.take() {
        // A write error shows up as a build failure below.
        let _ = stdin.write_all(shim.as_bytes());
    }
    let out = child.wait_with_output().map_err(io_err(&tmp))?;
    if !out.status.success() {
        eprint!("{}", String::from_utf8_lossy(&out.stderr));
        let _ = std::fs::remove_dir_all(&tmp);
        return Err(NativeError::KernelBuild { kernel: names() });
    }
    publish(&tmp, &dir)?;
    Ok(exe)
}

/// Runs the kernel program over `image`; returns the final framebuffer (one segment, or
/// none if the image has no framebuffer).
fn run_kernel(
    exe: &Path,
    kernel: &Path,
    image: &MemoryImage,
    shape: &HostShape,
    cache: &Path,
) -> Result<MemoryImage, NativeError> {
    let tmp = scratch_dir(cache, "run")?;
    let result = run_in(exe, kernel, image, shape, &tmp);
    let _ = std::fs::remove_dir_all(&tmp);
    result
}

/// What the host runner takes from the chip config besides the memory image (whose
/// header carries the stream memory's shape).
struct HostShape {
    tms: u32,
    threads: u32,
    /// `stream_memory.schedule`.
    schedule: &'static str,
    /// The spill sentinel (`stream_memory.overflow = "spill"`), in its argument form.
    spill: Option<String>,
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

/// Writes 8-bit RGB pixels (`width*height*3` bytes, top row first) as a PNG file.
pub fn write_png(path: &Path, width: u32, height: u32, rgb: &[u8]) -> Result<(), NativeError> {
    let png_err = |e: png::EncodingError| NativeError::Png {
        path: path.display().to_string(),
        message: e.to_string(),
    };
    let file = std::fs::File::create(path).map_err(io_err(path))?;
    let mut enc = png::Encoder::new(std::io::BufWriter::new(file), width, height);
    enc.set_color(png::ColorType::Rgb);
    enc.set_depth(png::BitDepth::Eight);
    let mut w = enc.write_header().map_err(png_err)?;
    w.write_image_data(rgb).map_err(png_err)?;
    w.finish().map_err(png_err)?;
    Ok(())
}
