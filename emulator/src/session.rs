//! One-call runs: an ELF (plus optional memory-image segments) and a machine config in,
//! output, statistics and a crash report out. The `trax run` command and tests use this.

use std::io::Write;

use crate::crash;
use crate::debuginfo::{DebugInfo, DebugInfoError};
use crate::elf::{ElfError, Executable};
use crate::machine::{Machine, MachineConfig, Outcome, RunSummary, SetupError};
use crate::memory::Segment;

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

/// Loads and runs a program; print output goes to `out` as it is produced.
pub fn run(req: RunRequest<'_>, out: &mut dyn Write) -> Result<RunResult, RunError> {
    let exe = Executable::parse(req.elf_path, req.elf)?;
    let segments = req.segments.clone().unwrap_or_else(|| exe.segments.clone());
    let mut machine = Machine::new(
        &segments,
        exe.text_start,
        exe.text_end,
        exe.entry,
        req.config,
    )?;
    let summary = machine.run(out);
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
