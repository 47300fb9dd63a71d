//! csmith differential testing of the C path (clang-14 for TRaX, the trax linker, the
//! functional emulator) against an independent oracle: the same random program built by
//! clang-14 for i386 (ILP32 like o32, so `long` and pointers have the same size), linked
//! without libc against compiler-rt's builtins, run on the host CPU. Both sides hash the
//! program's globals with csmith's CRC-32 (`tests/csmith/csmith.h`) and print `checksum =
//! %X`; they must print the same line. Shared by `tests/csmith.rs` (a few seeds) and
//! `benches/csmith.rs` (many).
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use trax::pipeline::{prepare, Request};
use trax_emulator::{run, Mode};

/// csmith options: small programs (packed structs included: their misaligned fields are
/// read with plain `lw`/`sw`, which the machine performs as MIPS32r6 allows).
pub const CSMITH_ARGS: &[&str] = &["--no-argc", "--max-funcs", "4", "--max-block-depth", "3"];

/// How long the host oracle may run before the program is counted as not terminating.
const HOST_TIMEOUT: Duration = Duration::from_secs(10);
/// Instructions the emulator may run (the host oracle finished, so the program ends).
const MAX_INSTRUCTIONS: u64 = 2_000_000_000;

/// What one seed gave.
#[derive(Debug, PartialEq, Eq)]
pub enum Verdict {
    /// Both printed this checksum line.
    Agree(String),
    /// The oracle did not finish or crashed (csmith programs may loop for a very long time
    /// or recurse deeply): nothing to compare.
    NoOracle(String),
    /// The outputs differ, or trax failed where the oracle finished.
    Disagree { host: String, trax: String },
}

fn run_cmd(cmd: &mut Command) -> Result<(), String> {
    let out = cmd
        .output()
        .map_err(|e| format!("cannot run {cmd:?}: {e}"))?;
    if out.status.success() {
        Ok(())
    } else {
        Err(format!(
            "{cmd:?} failed:\n{}",
            String::from_utf8_lossy(&out.stderr)
        ))
    }
}

/// compiler-rt's builtins for i386 (64-bit division), from clang itself.
fn i386_builtins() -> Result<PathBuf, String> {
    let out = Command::new("clang-14")
        .args(["-m32", "--rtlib=compiler-rt", "-print-libgcc-file-name"])
        .output()
        .map_err(|e| format!("clang-14: {e}"))?;
    let p = PathBuf::from(String::from_utf8_lossy(&out.stdout).trim());
    if p.is_file() {
        Ok(p)
    } else {
        Err(format!(
            "no compiler-rt builtins for i386 at {}",
            p.display()
        ))
    }
}

/// The wrapper both sides compile: the csmith program with `main` renamed, and each
/// side's entry point.
const WRAPPER: &str = r#"#include "csmith.h"
#define main csmith_main
#include "prog.c"
#undef main
#ifdef __mips__
void trax_main(void) {
    if (trax_global_id() == 0)
        csmith_main();
}
#else
typedef __SIZE_TYPE__ size_t;
__attribute__((weak)) void *memcpy(void *d, const void *s, size_t n) {
    unsigned char *dp = d; const unsigned char *sp = s;
    while (n--) *dp++ = *sp++;
    return d;
}
__attribute__((weak)) void *memset(void *d, int c, size_t n) {
    unsigned char *dp = d;
    while (n--) *dp++ = (unsigned char)c;
    return d;
}
void _start(void) {
    csmith_main();
    __asm__ volatile("int $0x80" :: "a"(1), "b"(0));
    __builtin_unreachable();
}
#endif
"#;

/// Generates the program of `seed` into `dir` (with the harness headers).
pub fn generate(seed: u64, dir: &Path) -> Result<PathBuf, String> {
    std::fs::create_dir_all(dir).map_err(|e| e.to_string())?;
    let here = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/csmith");
    std::fs::copy(here.join("csmith.h"), dir.join("csmith.h")).map_err(|e| e.to_string())?;
    let safe_math = Path::new("/usr/include/csmith/safe_math.h");
    std::fs::copy(safe_math, dir.join("safe_math.h")).map_err(|e| {
        format!(
            "{}: {e} (install the Debian packages csmith and libcsmith-dev; .ci/run does)",
            safe_math.display()
        )
    })?;
    run_cmd(
        Command::new("csmith")
            .args(["--seed", &seed.to_string()])
            .args(CSMITH_ARGS)
            .arg("-o")
            .arg(dir.join("prog.c")),
    )
    .map_err(|e| format!("{e} (install the Debian package csmith; .ci/run does)"))?;
    let w = dir.join("wrapper.c");
    std::fs::write(&w, WRAPPER).map_err(|e| e.to_string())?;
    Ok(w)
}

/// The oracle's output: built for i386 without libc, run with a time limit.
fn host_output(wrapper: &Path, dir: &Path) -> Result<String, String> {
    let obj = dir.join("host.o");
    let exe = dir.join("host");
    run_cmd(
        Command::new("clang-14")
            .args([
                "-m32",
                "-O1",
                "-ffreestanding",
                "-fno-builtin",
                "-fno-pic",
                "-fno-stack-protector",
                "-w",
                "-c",
            ])
            .arg(wrapper)
            .arg("-o")
            .arg(&obj),
    )?;
    run_cmd(
        Command::new("ld.lld-14")
            .args(["-m", "elf_i386", "-static", "-e", "_start"])
            .arg(&obj)
            .arg(i386_builtins()?)
            .arg("-o")
            .arg(&exe),
    )?;
    let mut child = Command::new(&exe)
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .map_err(|e| e.to_string())?;
    let start = Instant::now();
    loop {
        if let Some(status) = child.try_wait().map_err(|e| e.to_string())? {
            let mut s = String::new();
            use std::io::Read;
            if let Some(mut o) = child.stdout.take() {
                let _ = o.read_to_string(&mut s);
            }
            return if status.success() {
                Ok(s)
            } else {
                Err(format!("oracle exited with {status}"))
            };
        }
        if start.elapsed() > HOST_TIMEOUT {
            let _ = child.kill();
            let _ = child.wait();
            return Err(format!("oracle ran over {HOST_TIMEOUT:?}"));
        }
        std::thread::sleep(Duration::from_millis(5));
    }
}

/// The program's output on the emulator (one thread, functional), built at `opt`.
fn trax_output(wrapper: &Path, opt: u8) -> Result<String, String> {
    let mut req = Request::new(wrapper);
    req.opt_level = opt;
    req.chip.tms = 1;
    req.chip.threads_per_tm = 1;
    req.render.width = 1;
    req.render.height = 1;
    let prepared = prepare(&req).map_err(|e| e.render())?;
    let mut out = Vec::new();
    let mut rr = prepared.run_request(&req.chip, Mode::Functional);
    rr.limits.max_instructions = Some(MAX_INSTRUCTIONS);
    let result = run(rr, &mut out).map_err(|e| e.to_string())?;
    let text = String::from_utf8_lossy(&out).into_owned();
    if result.finished() {
        Ok(text)
    } else {
        Err(format!(
            "{text}{:?}\n{}",
            result.outcome,
            result.failure.unwrap_or_default()
        ))
    }
}

/// Generates, builds and runs seed `seed` both ways (trax at `-O{opt}`) in `dir`.
pub fn differential(seed: u64, opt: u8, dir: &Path) -> Result<Verdict, String> {
    let wrapper = generate(seed, dir)?;
    let host = match host_output(&wrapper, dir) {
        Ok(s) => s,
        Err(e) => return Ok(Verdict::NoOracle(e)),
    };
    Ok(match trax_output(&wrapper, opt) {
        Ok(t) if t == host && host.starts_with("checksum = ") => Verdict::Agree(host),
        Ok(t) => Verdict::Disagree { host, trax: t },
        Err(e) => Verdict::Disagree { host, trax: e },
    })
}
