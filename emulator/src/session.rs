//! One-call runs: an ELF (plus optional memory-image segments) and a machine config in,
//! output, statistics and a crash report out. The `trax run` command and tests use this.

use std::io::Write;

use crate::crash;
use crate::debuginfo::{DebugInfo, DebugInfoError};
use crate::elf::{ElfError, Executable};
use crate::exec::Stop;
use crate::machine::{Machine, MachineConfig, Outcome, RunSummary, SetupError};
use crate::memory::Segment;
use crate::profile::sched::Executor;
use crate::thread::{Shared, Thread};

/// Errors before the program starts.
#[derive(Debug, thiserror::Error)]
pub enum RunError {
    /// The executable is unusable.
    #[error(transparent)]
    Elf(#[from] ElfError),
    /// The machine could not be set up.
    #[error(transparent)]
    Setup(#[from] SetupError),
}

/// What to run.
#[derive(Clone, Debug)]
pub struct RunRequest<'a> {
    /// Path of the ELF (for messages and DWARF source paths).
    pub elf_path: &'a str,
    /// ELF bytes.
    pub elf: &'a [u8],
    /// The complete memory image (program and scene); `None` loads the ELF's segments.
    pub segments: Option<Vec<Segment>>,
    /// Machine configuration.
    pub config: MachineConfig,
}

/// A finished run.
#[derive(Debug)]
pub struct RunResult {
    /// Summary (outcome, instruction count, counters).
    pub summary: RunSummary,
    /// Crash report text when a thread faulted, deadlocked or the limit was hit.
    pub report: Option<String>,
    /// The machine after the run (memory can be read back, e.g. the framebuffer).
    pub machine: Machine,
    /// The parsed executable.
    pub exe: Executable,
}

/// How far a functional run has got (for progress displays).
#[derive(Clone, Copy, Debug, Default)]
pub struct Progress {
    /// Instructions retired by all threads.
    pub instructions: u64,
    /// Rays counted so far (`trax.stat 0`).
    pub rays: u64,
    /// Threads not yet halted.
    pub live_threads: u32,
}

/// Plain execution that reports [`Progress`] about every 100 ms of host time.
struct Watched<'a> {
    report: &'a mut dyn FnMut(&Progress),
    retired: u64,
    turns: u32,
    last: std::time::Instant,
}

impl Executor for Watched<'_> {
    fn exec(&mut self, _idx: usize, t: &mut Thread, sh: &mut Shared, budget: u64) -> Stop {
        let before = t.retired;
        let stop = t.run(sh, budget);
        self.retired += t.retired - before;
        self.turns += 1;
        if self.turns >= 64 {
            self.turns = 0;
            if self.last.elapsed().as_millis() >= 100 {
                self.last = std::time::Instant::now();
                (self.report)(&Progress {
                    instructions: self.retired,
                    rays: sh.stats[0],
                    live_threads: sh.live_threads,
                });
            }
        }
        stop
    }
}

/// Loads and runs a program; print output goes to `out` as it is produced.
pub fn run(req: RunRequest<'_>, out: &mut dyn Write) -> Result<RunResult, RunError> {
    run_with(req, out, None)
}

/// Like [`run`], reporting the run's [`Progress`] about every 100 ms to `progress`.
pub fn run_with(
    req: RunRequest<'_>,
    out: &mut dyn Write,
    progress: Option<&mut dyn FnMut(&Progress)>,
) -> Result<RunResult, RunError> {
    let exe = Executable::parse(req.elf_path, req.elf)?;
    let segments = req.segments.clone().unwrap_or_else(|| exe.segments.clone());
    let mut machine = Machine::new(
        &segments,
        exe.text_start,
        exe.text_end,
        exe.entry,
        req.config,
    )?;
    let summary = match progress {
        Some(report) => {
            let mut w = Watched {
                report,
                retired: 0,
                turns: 0,
                last: std::time::Instant::now(),
            };
            machine.run_with(out, &mut w)
        }
        None => machine.run(out),
    };
    let report = match &summary.outcome {
        Outcome::Finished => None,
        Outcome::Crashed(c) => {
            let dbg = load_debug(req.elf_path, req.elf).ok();
            Some(crash::report(c, &machine.shared, Some(&exe), dbg.as_ref()))
        }
        Outcome::Deadlock { waiting } => Some(format!(
            "error: deadlock: {waiting} live thread(s) are all waiting at barriers or semaphores"
        )),
        Outcome::InstructionLimit => Some(format!(
            "error: instruction limit reached after {} instructions",
            summary.instructions
        )),
    };
    Ok(RunResult {
        summary,
        report,
        machine,
        exe,
    })
}

/// Reads the DWARF of an executable.
pub fn load_debug(path: &str, elf: &[u8]) -> Result<DebugInfo, DebugInfoError> {
    DebugInfo::parse(path, elf)
}
