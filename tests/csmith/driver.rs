//! csmith differential testing of the C path (clang-14 for TRaX, the trax linker, the
//! functional emulator) against an independent oracle: the same random program built by
//! clang-14 for i386 (ILP32 like o32, so `long` and pointers have the same size) at the
//! same `-O` level, linked without libc against compiler-rt's builtins, run on the host
//! CPU. Both sides hash the program's globals with csmith's CRC-32
//! (`tests/csmith/csmith.h`) and print `checksum = %X`; they must print the same line.
//! Shared by `tests/csmith.rs` (a few hundred seeds) and `benches/csmith.rs` (many).
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use trax::pipeline::{prepare, Request};
use trax_emulator::{run, Mode, Outcome};

/// csmith options: small programs (packed structs included: their misaligned fields are
/// read with plain `lw`/`sw`, which the machine performs as MIPS32r6 allows).
pub const CSMITH_ARGS: &[&str] = &["--no-argc", "--max-funcs", "4", "--max-block-depth", "3"];

/// How long the host oracle may run before the program is counted as not terminating.
const HOST_TIMEOUT: Duration = Duration::from_secs(10);
/// Instructions the emulator may run (about 9 s of one core).
pub const MAX_INSTRUCTIONS: u64 = 2_000_000_000;
/// MIPS instructions per second of host CPU time that a csmith program may plausibly
/// need at most. Seed 5556 at -O0 runs 5.9 G instructions on the emulator and 0.42 s of
/// CPU on the host at -O0 (14 G per host second); this allows programs 3.5 times denser
/// (`cargo bench --bench csmith` prints the densest agreeing program it saw).
pub const MAX_INSTRUCTIONS_PER_HOST_SECOND: u64 = 50_000_000_000;
/// A trax run that stops at [`MAX_INSTRUCTIONS`] is over budget, not wrong, when the host
/// oracle used at least this much CPU time (40 ms: the limit at
/// [`MAX_INSTRUCTIONS_PER_HOST_SECOND`]); a quicker host run (seed 5556 at -O1: under
/// 10 ms) means the trax run at the limit has hung.
pub const OVER_BUDGET_HOST_TIME: Duration =
    Duration::from_nanos(MAX_INSTRUCTIONS * 1_000_000_000 / MAX_INSTRUCTIONS_PER_HOST_SECOND);

/// What one seed gave.
#[derive(Debug, PartialEq, Eq)]
pub enum Verdict {
    /// Both printed this checksum line; trax ran `instructions`, the host `host_time`.
    Agree {
        line: String,
        instructions: u64,
        host_time: Duration,
    },
    /// The oracle did not finish or crashed (csmith programs may loop for a very long time
    /// or recurse deeply): nothing to compare.
    NoOracle(String),
    /// trax stopped at its instruction limit and the oracle took at least
    /// [`OVER_BUDGET_HOST_TIME`] (it printed `host`): too long to compare here.
    OverBudget { host: String, host_time: Duration },
    /// The outputs differ, or trax failed (or stopped at its limit) where the oracle
    /// finished quickly.
    Disagree { host: String, trax: String },
}

/// How the oracle ran: its output (or why it has none) and its CPU time.
#[derive(Debug)]
pub struct HostRun {
    /// The printed text, or why the oracle did not finish.
    pub output: Result<String, String>,
    /// CPU time it used (user + system; wall time where `/proc` cannot tell), so a busy
    /// machine does not make a program look slow.
    pub time: Duration,
}

/// How the emulator ran.
#[derive(Debug, PartialEq, Eq)]
pub enum TraxRun {
    /// Every thread finished: the printed text and the instructions run.
    Finished { text: String, instructions: u64 },
    /// Stopped at [`MAX_INSTRUCTIONS`]; what it printed so far.
    OverLimit(String),
    /// Did not build, crashed or deadlocked; what went wrong.
    Failed(String),
}

/// The verdict on one seed from both runs.
pub fn classify(host: HostRun, trax: TraxRun) -> Verdict {
    let host_out = match host.output {
        Ok(s) => s,
        Err(e) => return Verdict::NoOracle(e),
    };
    match trax {
        TraxRun::Finished { text, instructions }
            if text == host_out && host_out.starts_with("checksum = ") =>
        {
            Verdict::Agree {
                line: host_out,
                instructions,
                host_time: host.time,
            }
        }
        TraxRun::OverLimit(_) if host.time >= OVER_BUDGET_HOST_TIME => Verdict::OverBudget {
            host: host_out,
            host_time: host.time,
        },
        TraxRun::Finished { text: t, .. } | TraxRun::Failed(t) => Verdict::Disagree {
            host: host_out,
            trax: t,
        },
        TraxRun::OverLimit(t) => Verdict::Disagree {
            host: host_out,
            trax: format!(
                "{t}stopped at the instruction limit ({MAX_INSTRUCTIONS}) while the host took {:?}",
                host.time
            ),
        },
    }
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

/// The oracle's run: built for i386 at `-O{opt}` without libc, run with a time limit.
fn host_output(wrapper: &Path, dir: &Path, opt: u8) -> HostRun {
    match host_build(wrapper, dir, opt) {
        Ok(exe) => host_run(&exe),
        Err(e) => HostRun {
            output: Err(e),
            time: Duration::ZERO,
        },
    }
}

fn host_build(wrapper: &Path, dir: &Path, opt: u8) -> Result<PathBuf, String> {
    let obj = dir.join("host.o");
    let exe = dir.join("host");
    run_cmd(
        Command::new("clang-14")
            .args([
                "-m32",
                &format!("-O{opt}"),
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
    Ok(exe)
}

/// Whether process `pid` (a child not yet reaped) has exited, from `/proc/PID/stat`:
/// `Some(Some(cpu))` once it is a zombie, with its CPU time (user + system: fields 14 and
/// 15, in the kernel's fixed 100 ticks per second); `Some(None)` while it runs; `None`
/// when `/proc` cannot tell.
fn proc_exit(pid: u32) -> Option<Option<Duration>> {
    let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).ok()?;
    // Fields after the command name, which is in parentheses and may hold spaces.
    let rest: Vec<&str> = stat.get(stat.rfind(')')? + 2..)?.split(' ').collect();
    if *rest.first()? != "Z" {
        return Some(None);
    }
    let ticks = |i: usize| rest.get(i).and_then(|v| v.parse::<u64>().ok());
    Some(Some(Duration::from_millis((ticks(11)? + ticks(12)?) * 10)))
}

fn host_run(exe: &Path) -> HostRun {
    let child = Command::new(exe)
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn();
    let mut child = match child {
        Ok(c) => c,
        Err(e) => {
            return HostRun {
                output: Err(e.to_string()),
                time: Duration::ZERO,
            }
        }
    };
    let start = Instant::now();
    let mut time = None;
    let status = loop {
        // The CPU time is read while the exited child is a zombie, then it is reaped.
        let waited = match proc_exit(child.id()) {
            Some(Some(cpu)) => {
                time = Some(cpu);
                child.wait().map(Some)
            }
            Some(None) => Ok(None),
            None => child.try_wait(),
        };
        match waited {
            Ok(Some(status)) => break Ok(status),
            Ok(None) => {}
            Err(e) => break Err(e.to_string()),
        }
        if start.elapsed() > HOST_TIMEOUT {
            let _ = child.kill();
            let _ = child.wait();
            break Err(format!("oracle ran over {HOST_TIMEOUT:?}"));
        }
        std::thread::sleep(Duration::from_millis(1));
    };
    let time = time.unwrap_or_else(|| start.elapsed());
    let output = status.and_then(|status| {
        let mut s = String::new();
        use std::io::Read;
        if let Some(mut o) = child.stdout.take() {
            let _ = o.read_to_string(&mut s);
        }
        if status.success() {
            Ok(s)
        } else {
            Err(format!("oracle exited with {status}"))
        }
    });
    HostRun { output, time }
}

/// The program's run on the emulator (one thread, functional), built at `opt`.
fn trax_output(wrapper: &Path, opt: u8) -> TraxRun {
    let mut req = Request::new(wrapper);
    req.opt_level = opt;
    req.chip.tms = 1;
    req.chip.threads_per_tm = 1;
    req.render.width = 1;
    req.render.height = 1;
    let prepared = match prepare(&req) {
        Ok(p) => p,
        Err(e) => return TraxRun::Failed(e.render()),
    };
    let mut out = Vec::new();
    let mut rr = prepared.run_request(&req.chip, Mode::Functional);
    rr.limits.max_instructions = Some(MAX_INSTRUCTIONS);
    let result = match run(rr, &mut out) {
        Ok(r) => r,
        Err(e) => return TraxRun::Failed(e.to_string()),
    };
    let text = String::from_utf8_lossy(&out).into_owned();
    match result.outcome {
        Outcome::Finished => TraxRun::Finished {
            text,
            instructions: result.instructions,
        },
        Outcome::InstructionLimit => TraxRun::OverLimit(text),
        o => TraxRun::Failed(format!(
            "{text}{o:?}\n{}",
            result.failure.unwrap_or_default()
        )),
    }
}

/// Generates, builds and runs seed `seed` both ways at `-O{opt}` in `dir`.
pub fn differential(seed: u64, opt: u8, dir: &Path) -> Result<Verdict, String> {
    let wrapper = generate(seed, dir)?;
    let host = host_output(&wrapper, dir, opt);
    if host.output.is_err() {
        return Ok(classify(host, TraxRun::Failed(String::new())));
    }
    Ok(classify(host, trax_output(&wrapper, opt)))
}
