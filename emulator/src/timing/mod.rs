//! The cycle-level timing model of the TRaX chip (thesis chapter 2, simtrax §4).
//!
//! [`run`] mirrors [`crate::session::run`]: an ELF (plus optional memory image) and a
//! [`ChipConfig`] in; print output, [`TimingStats`] and a crash report out. The model:
//! [`engine`] (TMs of in-order single-issue thread processors, shared execution units,
//! I-cache banks, scoreboards, local stores, global registers, the memory system of
//! [`crate::memsys`]), [`operands`] (what each instruction reads, writes and uses),
//! [`config`] (TOML chip configs and presets) and [`stats`] (summary and JSON).
//!
//! Determinism and parallelism: time advances in quanta; within a quantum every TM is
//! simulated on its own (TMs are spread over `host_threads` host threads), then chip-wide
//! work (L2s, DRAM, global registers, stores to global memory, barriers) is done serially
//! in a fixed order (see [`engine`]). The same inputs give the same cycles, statistics
//! and output for any number of host threads.

pub mod config;
pub mod engine;
pub mod operands;
pub mod stats;
mod tm;
mod workers;

use std::io::Write;

pub use config::{ChipConfig, ConfigError, UnitConfig, CHIP_PRESETS, DEFAULT_CHIP};
pub use engine::{Progress, ProgressFn};
pub use stats::TimingStats;

use crate::crash;
use crate::elf::{ElfError, Executable};
use crate::machine::{Machine, MachineConfig, Outcome, SetupError};
use crate::memory::Segment;
use crate::profile::Profiler;

/// Errors before the simulation starts.
#[derive(Debug, thiserror::Error)]
pub enum TimingError {
    /// The executable is unusable.
    #[error(transparent)]
    Elf(#[from] ElfError),
    /// The machine could not be set up.
    #[error(transparent)]
    Setup(#[from] SetupError),
    /// The chip configuration is inconsistent.
    #[error(transparent)]
    Config(#[from] ConfigError),
    /// The memory system rejected the configuration.
    #[error("memory system: {0}")]
    Memory(String),
}

/// What to simulate.
#[derive(Clone, Debug)]
pub struct TimingRequest<'a> {
    /// Path of the ELF (for messages and DWARF source paths).
    pub elf_path: &'a str,
    /// ELF bytes.
    pub elf: &'a [u8],
    /// The complete memory image; `None` loads the ELF's segments.
    pub segments: Option<Vec<Segment>>,
    /// Host threads to simulate with (results are identical for any value).
    pub host_threads: usize,
    /// Stop after this many core cycles (None: run to the end).
    pub max_cycles: Option<u64>,
}

/// A finished timing run.
#[derive(Debug)]
pub struct TimingResult {
    /// How it ended (`InstructionLimit` = the cycle limit was reached).
    pub outcome: Outcome,
    /// Statistics.
    pub stats: TimingStats,
    /// Crash report text when a thread faulted, deadlocked or the limit was hit.
    pub report: Option<String>,
    /// The machine after the run (memory can be read back, e.g. the framebuffer).
    pub machine: Machine,
    /// The parsed executable.
    pub exe: Executable,
}

/// Loads a program and simulates it cycle by cycle on `chip`.
pub fn run(
    req: TimingRequest<'_>,
    chip: &ChipConfig,
    out: &mut dyn Write,
) -> Result<TimingResult, TimingError> {
    run_profiled(req, chip, out, false).map(|(r, _)| r)
}

/// Like [`run`]; with `profile`, also charges every live thread-cycle (issue and each
/// stall kind) to its call stack and returns the [`Profiler`] (see
/// [`engine::Engine::profiler`]).
pub fn run_profiled(
    req: TimingRequest<'_>,
    chip: &ChipConfig,
    out: &mut dyn Write,
    profile: bool,
) -> Result<(TimingResult, Option<Profiler>), TimingError> {
    run_with(req, chip, out, profile, None)
}

/// Like [`run_profiled`], reporting the run's [`Progress`] about every 100 ms to `progress`.
pub fn run_with<'a>(
    req: TimingRequest<'_>,
    chip: &'a ChipConfig,
    out: &mut dyn Write,
    profile: bool,
    progress: Option<ProgressFn<'a>>,
) -> Result<(TimingResult, Option<Profiler>), TimingError> {
    chip.validate()?;
    let exe = Executable::parse(req.elf_path, req.elf)?;
    let segments = req.segments.clone().unwrap_or_else(|| exe.segments.clone());
    let mcfg = MachineConfig {
        tms: chip.tms,
        threads_per_tm: chip.threads_per_tm,
        stack_size: chip.local_store.bytes,
        quantum: 1,
        max_instructions: None,
    };
    let mut machine = Machine::new(&segments, exe.text_start, exe.text_end, exe.entry, mcfg)?;
    let mut engine = engine::Engine::new(chip, &machine, req.max_cycles, req.host_threads)
        .map_err(TimingError::Memory)?;
    engine.progress = progress;
    if profile {
        engine.profiler = Some(Profiler::new(
            &machine.shared.program,
            machine.threads.len(),
        ));
    }
    let outcome = engine.run(&mut machine, out);
    let profiler = engine.profiler.take();
    let cycles = engine.now;
    let st = stats::build(
        chip,
        &engine.c,
        cycles,
        &machine.shared.program,
        engine.mem().stats(),
        &machine.shared.stats,
    );
    let report = match &outcome {
        Outcome::Finished => None,
        Outcome::Crashed(c) => {
            let dbg = crate::session::load_debug(req.elf_path, req.elf).ok();
            Some(crash::report(c, &machine.shared, Some(&exe), dbg.as_ref()))
        }
        Outcome::Deadlock { waiting } => Some(format!(
            "error: deadlock at cycle {cycles}: {waiting} live thread(s) are all waiting at barriers or semaphores"
        )),
        Outcome::InstructionLimit => Some(format!("error: cycle limit reached after {cycles} cycles")),
    };
    let result = TimingResult {
        outcome,
        stats: st,
        report,
        machine,
        exe,
    };
    Ok((result, profiler))
}
