//! The one way to run a program: a [`RunRequest`] (executable, initial memory, chip, mode,
//! limits, profiling, GDB, progress) in, a [`RunReport`] out. `trax run`, `trax annotate`,
//! the tests and the benchmarks all come through [`run`].
//!
//! - Functional mode executes on the [`Machine`] with the fixed round-robin interleaving of
//!   [`crate::sched`] (`quantum` instructions per turn); with `profile` every retired
//!   instruction is charged to its call stack, with `gdb` the run is served to a debugger.
//! - Timing mode simulates the chip cycle by cycle ([`crate::timing`]) on host threads
//!   chosen by [`host_threads`]; with `profile` every thread-cycle is charged.
//!
//! A run that does not finish (a crash, a deadlock, a limit) is described once, by the text
//! in [`RunReport::failure`].

use std::io::Write;
use std::net::TcpListener;

use crate::crash;
use crate::debuginfo::DebugInfo;
use crate::elf::{ElfError, Executable};
use crate::exec::Stop;
use crate::gdb::{self, GdbError};
use crate::livelock::Detection;
use crate::machine::{Machine, MachineConfig, Outcome, SetupError};
use crate::memory::Segment;
use crate::profile::{profile_run, Profile, Profiler};
use crate::sched::Executor;
use crate::thread::{Shared, Thread};
use crate::timing::{self, ChipConfig, ConfigError, TimingStats};

/// Instructions a thread runs per turn of the functional interleaving by default.
pub const DEFAULT_QUANTUM: u32 = 1000;

/// Functional (execution only) or timing (cycle-level chip model).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    /// Execute without the timing model: no cycles, no memory-system statistics.
    Functional,
    /// Simulate the chip cycle by cycle.
    Timing,
}

impl Mode {
    /// `functional` or `timing`.
    pub fn name(self) -> &'static str {
        match self {
            Mode::Functional => "functional",
            Mode::Timing => "timing",
        }
    }
}

/// Where a run stops early.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Limits {
    /// Stop once the threads have executed this many instructions in total. Functional
    /// mode stops exactly there; timing mode counts issued instructions plus zero-cost
    /// debug ops (the same count) and stops at the end of the quantum (the L1 plus L2 hit
    /// latency in cycles) in which the total reaches the limit, whatever the host threads.
    pub max_instructions: Option<u64>,
    /// Stop at this core cycle (timing mode only: functional runs have no cycles).
    pub max_cycles: Option<u64>,
}

/// What a run does about a livelock ([`crate::livelock`]: proven never to end).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OnLivelock {
    /// Do not watch.
    Ignore,
    /// Tell it ([`RunRequest::livelock_notice`], [`RunReport::livelock`]) and go on.
    Warn,
    /// Tell it and stop the run ([`Outcome::Livelock`]).
    Stop,
}

/// A livelock as reported: when it was found and where every live thread was.
#[derive(Clone, Debug, serde::Serialize)]
pub struct Livelock {
    /// Cycle at which it was found (timing mode; `null` in functional mode).
    pub cycle: Option<u64>,
    /// Instructions executed by all threads by then.
    pub instructions: u64,
    /// How long nothing outside the threads had changed: cycles (timing mode), or
    /// instructions per thread (functional mode: rounds of the interleaving times the
    /// quantum).
    pub quiet: u64,
    /// Whether the run stopped there (`--stop-on-livelock`).
    pub stopped: bool,
    /// Where the threads were: a looping thread at the first instruction of its loop.
    pub threads: crate::ThreadPlaces,
}

impl Livelock {
    /// The message: `error:` when it stopped the run, else `warning:`, then where the
    /// threads are.
    pub fn render(&self) -> String {
        let (at, unit) = match self.cycle {
            Some(c) => (format!("cycle {c}"), "cycles"),
            None => (
                format!("{} instructions", self.instructions),
                "instructions per thread",
            ),
        };
        let (level, then) = if self.stopped {
            ("error", "stopped here")
        } else {
            (
                "warning",
                "still running: stop it, or run with --stop-on-livelock",
            )
        };
        format!(
            "{level}: livelock at {at}: every running thread repeats a loop that changes \
             nothing outside it (no store to global memory, no global-register, barrier or \
             stream operation, print, counter or halt: none for {} {unit}) and no waiting \
             thread can be released: the run can never finish ({then})\n{}",
            self.quiet,
            self.threads.render()
        )
    }
}

/// What to run, and how.
pub struct RunRequest<'a> {
    /// Path of the ELF (for messages and DWARF source paths).
    pub elf_path: &'a str,
    /// ELF bytes.
    pub elf: &'a [u8],
    /// The complete initial memory (program and scene); `None` loads the ELF's segments.
    pub segments: Option<Vec<Segment>>,
    /// The chip: its shape (TMs x threads, local-store bytes = stack size) in both modes,
    /// all of it in timing mode.
    pub chip: &'a ChipConfig,
    /// Functional or timing.
    pub mode: Mode,
    /// Functional mode: instructions each thread runs per turn of the interleaving.
    pub quantum: u32,
    /// Early stops.
    pub limits: Limits,
    /// Timing mode: host threads to simulate with (see [`host_threads`]); results are
    /// identical for any value.
    pub host_threads: Option<usize>,
    /// Charge every instruction (functional) or thread-cycle (timing) to its call stack.
    pub profile: bool,
    /// Functional mode: serve the run to one GDB connection on this listener.
    pub gdb: Option<TcpListener>,
    /// Called with the run's [`Progress`] about every 100 ms of host time.
    pub progress: Option<&'a mut dyn FnMut(&Progress)>,
    /// What to do about a livelock (functional and timing runs, not under GDB nor
    /// sampled): [`OnLivelock::Warn`] by default.
    pub livelock: OnLivelock,
    /// Told of a livelock as soon as it is found (e.g. to print the warning while the
    /// run goes on); it is in [`RunReport::livelock`] either way.
    pub livelock_notice: Option<&'a mut dyn FnMut(&Livelock)>,
    /// Timing mode: statistics for every interval of this many cycles (a multiple of the
    /// quantum, the L1 plus L2 hit latency), each handed to [`Self::interval_sink`] (which
    /// it needs) as it completes; the run keeps none of them.
    pub stats_interval: Option<u64>,
    /// Receives the intervals of [`Self::stats_interval`], in order.
    pub interval_sink: Option<crate::timing::intervals::IntervalSink<'a>>,
    /// Timing mode: simulate sampled windows in detail and fast-forward between them
    /// ([`crate::timing::sample`]); the report then has estimates with confidence
    /// intervals ([`RunReport::sampled`]) instead of exact timing statistics.
    pub sample: Option<crate::timing::SampleRequest>,
    /// Functional mode: run every instruction in the reference interpreter instead of the
    /// fast engine ([`crate::ReferenceExec`]; same results, slower). Plain runs only: not
    /// with a profile or the debugger.
    pub reference: bool,
}

impl<'a> RunRequest<'a> {
    /// A plain run of `elf` (its own segments) on `chip` in `mode`: default quantum, no
    /// limits, no profile, no debugger, automatic host threads.
    pub fn new(elf_path: &'a str, elf: &'a [u8], chip: &'a ChipConfig, mode: Mode) -> Self {
        RunRequest {
            elf_path,
            elf,
            segments: None,
            chip,
            mode,
            quantum: DEFAULT_QUANTUM,
            limits: Limits::default(),
            host_threads: None,
            profile: false,
            gdb: None,
            progress: None,
            livelock: OnLivelock::Warn,
            livelock_notice: None,
            stats_interval: None,
            interval_sink: None,
            sample: None,
            reference: false,
        }
    }
}

/// How far a run has got (for progress displays).
#[derive(Clone, Copy, Debug, Default)]
pub struct Progress {
    /// Cycles simulated (timing mode).
    pub cycles: Option<u64>,
    /// Instructions executed by all threads (timing: issued plus zero-cost debug ops).
    pub instructions: u64,
    /// Rays counted so far (`trax.stat 0`).
    pub rays: u64,
    /// Threads not yet halted.
    pub live_threads: u32,
}

/// Errors before the program starts.
#[derive(Debug, thiserror::Error)]
pub enum RunError {
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
    /// The GDB server failed.
    #[error(transparent)]
    Gdb(#[from] GdbError),
    /// The request asks for something its mode cannot do.
    #[error("{0}")]
    Request(String),
}

/// A finished run (finished or stopped early).
#[derive(Debug)]
pub struct RunReport {
    /// The mode it ran in.
    pub mode: Mode,
    /// How it ended.
    pub outcome: Outcome,
    /// Functional: instructions retired by all threads. Timing: instructions issued, not
    /// counting zero-cost debug ops (`TimingStats::debug_ops`).
    pub instructions: u64,
    /// Core cycles (timing mode).
    pub cycles: Option<u64>,
    /// The `trax.stat` counters (counter 0 counts rays).
    pub counters: Vec<u64>,
    /// Timing statistics (timing mode, not sampled).
    pub timing: Option<TimingStats>,
    /// A sampled run's estimates, costs and parameters.
    pub sampled: Option<crate::timing::SampledStats>,
    /// The resolved profile, when asked for.
    pub profile: Option<Profile>,
    /// The DWARF, when a profile or a crash report needed it.
    pub debug: Option<DebugInfo>,
    /// Hardware threads (TMs x threads per TM).
    pub threads: u32,
    /// Host threads the simulation ran on.
    pub host_threads: usize,
    /// Things the caller should tell the user (an oversubscribed host, a debugger that
    /// detached early).
    pub warnings: Vec<String>,
    /// The text describing a run that did not finish (crash report, deadlock, limit).
    pub failure: Option<String>,
    /// A run stopped by `--max-instructions`, `--max-cycles` or a livelock: where its
    /// threads were (also at the end of [`Self::failure`]).
    pub stopped_at: Option<crate::ThreadPlaces>,
    /// The livelock found, if one was (whether or not it stopped the run).
    pub livelock: Option<Livelock>,
    /// The machine after the run (memory can be read back, e.g. the framebuffer).
    pub machine: Machine,
    /// The parsed executable.
    pub exe: Executable,
}

impl RunReport {
    /// Rays counted (`trax.stat 0`).
    pub fn rays(&self) -> u64 {
        self.counters.first().copied().unwrap_or(0)
    }

    /// Whether every thread halted.
    pub fn finished(&self) -> bool {
        matches!(self.outcome, Outcome::Finished)
    }

    /// `len` bytes of global memory at `addr` (e.g. the framebuffer), if mapped.
    pub fn read_memory(&self, addr: u32, len: u32) -> Option<Vec<u8>> {
        self.machine.shared.mem.read_bytes(&[], addr, len).ok()
    }
}

/// The host-thread policy of timing runs: the requested number, else the host's cores;
/// never more than one per TM; one when profiling (same results). Returns the number
/// and, when it is more than the host's cores, a warning.
pub fn host_threads(requested: Option<usize>, tms: u32, profile: bool) -> (usize, Option<String>) {
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let n = if profile {
        1
    } else {
        requested.unwrap_or(cores).min(tms as usize).max(1)
    };
    let warning = (n > cores).then(|| {
        format!(
            "{n} host threads on {cores} available core(s): host threads work in lock-step rounds, so more of them than cores makes the run slower (results are the same)"
        )
    });
    (n, warning)
}

/// Loads and runs a program; print output goes to `out` as it is produced.
pub fn run(req: RunRequest<'_>, out: &mut dyn Write) -> Result<RunReport, RunError> {
    if req.quantum == 0 {
        return Err(RunError::Request("the quantum must be at least 1".into()));
    }
    if req.host_threads == Some(0) {
        return Err(RunError::Request(
            "at least one host thread is needed".into(),
        ));
    }
    match req.mode {
        Mode::Functional if req.limits.max_cycles.is_some() => Err(RunError::Request(
            "a cycle limit needs timing mode (functional runs count no cycles)".into(),
        )),
        Mode::Functional if req.stats_interval.is_some() => Err(RunError::Request(
            "statistics intervals need timing mode (functional runs count no cycles)".into(),
        )),
        Mode::Timing if req.gdb.is_some() => Err(RunError::Request(
            "the debugger needs functional mode (it drives the functional core)".into(),
        )),
        _ if req.reference && (req.mode == Mode::Timing || req.profile || req.gdb.is_some()) => {
            Err(RunError::Request(
                "the reference interpreter runs plain functional runs only (no timing, \
                 profile or debugger)"
                    .into(),
            ))
        }
        Mode::Functional if req.sample.is_some() => Err(RunError::Request(
            "sampling needs timing mode (it estimates what the timing model measures)".into(),
        )),
        Mode::Timing if req.sample.is_some() => {
            let what = [
                (req.profile, "a profile"),
                (req.stats_interval.is_some(), "statistics intervals"),
                (req.limits.max_cycles.is_some(), "a cycle limit"),
                (
                    req.limits.max_instructions.is_some(),
                    "an instruction limit",
                ),
            ];
            match what.iter().find(|(on, _)| *on) {
                Some((_, name)) => Err(RunError::Request(format!(
                    "a sampled run cannot take {name}: it simulates only windows of the run in \
                     detail"
                ))),
                None => run_timing(req, out),
            }
        }
        Mode::Functional => run_functional(req, out),
        Mode::Timing => run_timing(req, out),
    }
}

/// The executable and the machine of a request, ready to run.
fn load(req: &RunRequest<'_>, quantum: u32) -> Result<(Executable, Machine), RunError> {
    let exe = Executable::parse(req.elf_path, req.elf)?;
    let config = MachineConfig {
        tms: req.chip.tms,
        threads_per_tm: req.chip.threads_per_tm,
        stack_size: req.chip.local_store.bytes,
        quantum,
        max_instructions: match req.mode {
            Mode::Functional => req.limits.max_instructions,
            Mode::Timing => None,
        },
    };
    let mut machine = Machine::load(&exe, req.segments.as_deref(), config)?;
    // The stream memory and the pipelines the chip has (the same in both modes).
    let sm = &req.chip.stream_memory;
    machine.shared.streams = crate::streams::StreamMemory::new(sm.geometry());
    machine.shared.sched = crate::streams::StreamScheduler::new(
        req.chip.tms,
        req.chip.threads_per_tm,
        sm.schedule,
        u64::from(sm.schedule_cycles),
    );
    machine.shared.pipe_modes = req.chip.pipe_modes();
    Ok((exe, machine))
}

/// Turns livelock [`Detection`]s into [`Livelock`]s (the DWARF parsed once, when the
/// first comes) and tells the requester.
struct LivelockSink<'r> {
    elf_path: &'r str,
    elf: &'r [u8],
    stop: bool,
    notice: Option<&'r mut dyn FnMut(&Livelock)>,
    debug: Option<Option<DebugInfo>>,
    found: Option<Livelock>,
}

impl<'r> LivelockSink<'r> {
    /// The sink of `req` (its notice taken), or `None` when it does not watch.
    fn of(req: &mut RunRequest<'r>) -> Option<Self> {
        let stop = match req.livelock {
            OnLivelock::Ignore => return None,
            OnLivelock::Warn => false,
            OnLivelock::Stop => true,
        };
        Some(LivelockSink {
            elf_path: req.elf_path,
            elf: req.elf,
            stop,
            notice: req.livelock_notice.take(),
            debug: None,
            found: None,
        })
    }

    /// Takes detection `d` in a run of `exe`; returns whether to stop.
    fn take(&mut self, d: &Detection, exe: &Executable) -> bool {
        let (path, elf) = (self.elf_path, self.elf);
        let debug = self
            .debug
            .get_or_insert_with(|| DebugInfo::parse(path, elf).ok());
        let l = Livelock {
            cycle: d.cycle,
            instructions: d.instructions,
            quiet: d.quiet,
            stopped: self.stop,
            threads: crate::whereabouts::places(&d.threads, d.halted, Some(exe), debug.as_ref()),
        };
        if let Some(tell) = self.notice.as_deref_mut() {
            tell(&l);
        }
        self.found.get_or_insert(l);
        self.stop
    }

    /// The livelock found and the DWARF, if parsed.
    fn into_parts(sink: Option<Self>) -> (Option<Livelock>, Option<DebugInfo>) {
        match sink {
            Some(s) => (s.found, s.debug.flatten()),
            None => (None, None),
        }
    }
}

fn run_functional(mut req: RunRequest<'_>, out: &mut dyn Write) -> Result<RunReport, RunError> {
    let (exe, mut machine) = load(&req, req.quantum)?;
    let mut warnings = Vec::new();
    let mut profiler = None;
    let mut sink = match req.gdb {
        Some(_) => None,
        None => LivelockSink::of(&mut req),
    };
    let mut hook = |d: &Detection| sink.as_mut().is_some_and(|s| s.take(d, &exe));
    let watching = req.gdb.is_none() && req.livelock != OnLivelock::Ignore;
    let on_livelock: Option<&mut dyn FnMut(&Detection) -> bool> = match watching {
        true => Some(&mut hook),
        false => None,
    };
    let (outcome, instructions) = if let Some(listener) = req.gdb.take() {
        match gdb::serve_listener(&mut machine, listener, out)? {
            Some(o) => (o, retired(&machine)),
            None => {
                warnings.push("gdb detached before the program ended; ran it to completion".into());
                let s = machine.run(out);
                (s.outcome, retired(&machine))
            }
        }
    } else if req.profile {
        let (s, p) = profile_run(&mut machine, out, on_livelock);
        profiler = Some(p);
        (s.outcome, s.instructions)
    } else if req.reference {
        let s = machine.run_with(out, &mut crate::ReferenceExec, on_livelock);
        (s.outcome, s.instructions)
    } else {
        let s = match req.progress.take() {
            Some(report) => machine.run_with(
                out,
                &mut Watched {
                    report,
                    retired: 0,
                    turns: 0,
                    last: std::time::Instant::now(),
                },
                on_livelock,
            ),
            None => machine.run_with(out, &mut crate::sched::PlainExec, on_livelock),
        };
        (s.outcome, s.instructions)
    };
    let (livelock, debug) = LivelockSink::into_parts(sink);
    finish(
        &req,
        Ended {
            outcome,
            instructions,
            cycles: None,
            timing: None,
            sampled: None,
            profiler,
            host_threads: 1,
            warnings,
            livelock,
            debug,
        },
        machine,
        exe,
    )
}

fn run_timing(mut req: RunRequest<'_>, out: &mut dyn Write) -> Result<RunReport, RunError> {
    let chip = req.chip;
    chip.validate()?;
    let (exe, mut machine) = load(&req, 1)?;
    if let Some(n) = req.stats_interval {
        if req.interval_sink.is_none() {
            return Err(RunError::Request(
                "statistics intervals need an interval sink (the run keeps none of them)".into(),
            ));
        }
        let q = timing::engine::Engine::quantum(chip);
        if n == 0 || n % q != 0 {
            return Err(RunError::Request(format!(
                "the statistics interval ({n} cycles) must be a positive multiple of the \
                 chip's quantum, memory.l1.hit_latency + memory.l2.hit_latency = {q} cycles \
                 (intervals end where the TMs and the memory system meet)"
            )));
        }
    }
    let (host_threads, warning) = host_threads(req.host_threads, chip.tms, req.profile);
    // Sampled runs do not watch for livelocks.
    let mut sink = match req.sample {
        Some(_) => None,
        None => LivelockSink::of(&mut req),
    };
    let watching = sink.is_some();
    let mut hook = |d: &Detection| sink.as_mut().is_some_and(|s| s.take(d, &exe));
    let mut engine = timing::engine::Engine::new(chip, &machine, req.limits, host_threads)
        .map_err(RunError::Memory)?;
    // The statistics by region name the program's data objects too.
    engine.mem_mut().set_regions(&crate::memsys::RegionMap::new(
        (machine.shared.mem.segments().iter()).map(|s| (s.name.as_str(), s.addr, s.size)),
        (exe.symbols.iter())
            .filter(|s| !s.is_function && !s.is_absolute)
            .map(|s| (s.name.as_str(), s.addr, s.size)),
    ));
    if watching {
        engine.on_livelock = Some(&mut hook);
    }
    // Coerced to the engine's (shorter) lifetime.
    if let Some(p) = req.progress.take() {
        engine.progress = Some(p);
    }
    if let Some(spec) = &req.sample {
        let s = timing::sample::run(&mut engine, &mut machine, chip, spec, out)
            .map_err(RunError::Request)?;
        let instructions = s
            .stats
            .as_ref()
            .map_or_else(|| retired(&machine), |st| st.executed_instructions);
        return finish(
            &req,
            Ended {
                outcome: s.outcome,
                instructions,
                cycles: None,
                timing: None,
                sampled: s.stats,
                profiler: None,
                host_threads,
                warnings: warning.into_iter().collect(),
                livelock: None,
                debug: None,
            },
            machine,
            exe,
        );
    }
    engine.interval = req.stats_interval;
    let threads = u64::from(chip.tms) * u64::from(chip.threads_per_tm);
    let stream = chip.stream_memory.capacity_bytes > 0;
    if let (Some(n), Some(sink)) = (req.stats_interval, req.interval_sink.take()) {
        engine.intervals = Some(timing::intervals::IntervalStream::new(
            n,
            threads,
            chip.clock_ghz,
            stream,
            sink,
        ));
    }
    if req.profile {
        engine.profiler = Some(Profiler::new(
            &machine.shared.program,
            machine.threads.len(),
        ));
    }
    // Spill transfers take time on this chip (functional runs move blocks at once).
    machine.shared.streams.set_timed(true);
    let outcome = engine.run(&mut machine, out);
    let profiler = engine.profiler.take();
    let cycles = engine.now;
    let mut stats = timing::stats::build(
        chip,
        &engine.c,
        cycles,
        engine.mem().stats(),
        &machine.shared,
    );
    if let Some(st) = engine.intervals.take() {
        st.finish(timing::intervals::Snapshot::of_stats(
            &stats,
            engine.c.stream_ray_cycles,
        ));
        stats.interval_cycles = req.stats_interval;
    }
    drop(engine);
    let (livelock, debug) = LivelockSink::into_parts(sink);
    finish(
        &req,
        Ended {
            outcome,
            instructions: stats.instructions,
            cycles: Some(cycles),
            timing: Some(stats),
            sampled: None,
            profiler,
            host_threads,
            warnings: warning.into_iter().collect(),
            livelock,
            debug,
        },
        machine,
        exe,
    )
}

/// What a run's driver hands back.
struct Ended {
    outcome: Outcome,
    instructions: u64,
    cycles: Option<u64>,
    timing: Option<TimingStats>,
    sampled: Option<crate::timing::SampledStats>,
    profiler: Option<Profiler>,
    host_threads: usize,
    warnings: Vec<String>,
    /// The livelock found, if any.
    livelock: Option<Livelock>,
    /// The DWARF, if parsed during the run.
    debug: Option<DebugInfo>,
}

/// The report of an ended run: the failure text (the one place it is rendered) and the
/// resolved profile.
fn finish(
    req: &RunRequest<'_>,
    e: Ended,
    machine: Machine,
    exe: Executable,
) -> Result<RunReport, RunError> {
    let limit = matches!(e.outcome, Outcome::InstructionLimit | Outcome::CycleLimit);
    let needs_debug = e.profiler.is_some()
        || limit
        || matches!(e.outcome, Outcome::Crashed(_) | Outcome::Deadlock { .. });
    let debug = match e.debug {
        Some(d) => Some(d),
        None => needs_debug
            .then(|| DebugInfo::parse(req.elf_path, req.elf).ok())
            .flatten(),
    };
    // A run stopped by a limit says where its threads are; one stopped by a livelock,
    // where they were when it was found (a looping thread at its loop's start).
    let stopped_at = match (&e.outcome, &e.livelock) {
        (Outcome::Livelock, Some(l)) => Some(l.threads.clone()),
        _ => limit.then(|| {
            crate::whereabouts::thread_places(&machine.threads, Some(&exe), debug.as_ref())
        }),
    };
    let mut warnings = e.warnings;
    // A livelock the run went on after (told as it was found, when asked to).
    if let Some(l) = e.livelock.as_ref().filter(|l| !l.stopped) {
        if req.livelock_notice.is_none() {
            let text = l.render();
            warnings.push(text.strip_prefix("warning: ").unwrap_or(&text).to_string());
        }
    }
    let failure = match (&e.outcome, e.cycles) {
        (Outcome::Finished, _) => None,
        (Outcome::Crashed(c), _) => Some(crash::report(
            c,
            &machine.shared,
            Some(&exe),
            debug.as_ref(),
        )),
        (Outcome::Deadlock { .. }, cycles) => Some(crash::deadlock_report(
            &machine,
            cycles,
            Some(&exe),
            debug.as_ref(),
        )),
        (Outcome::InstructionLimit, _) => Some(format!(
            "error: instruction limit reached after {} instructions",
            // The count the limit counts (timing: issued plus debug ops).
            e.timing
                .as_ref()
                .map_or(e.instructions, |t| t.instructions + t.debug_ops)
        )),
        (Outcome::CycleLimit, cycles) => Some(format!(
            "error: cycle limit reached after {} cycles",
            cycles.unwrap_or(0)
        )),
        // The message ends with where the threads are.
        (Outcome::Livelock, _) => e.livelock.as_ref().map(Livelock::render),
    }
    .map(|text| match (&stopped_at, &e.outcome) {
        (Some(p), Outcome::InstructionLimit | Outcome::CycleLimit) => {
            format!("{text}\n{}", p.render())
        }
        _ => text,
    });
    let profile = e
        .profiler
        .map(|p| Profile::build(&p, debug.as_ref(), Some(&exe)));
    Ok(RunReport {
        mode: req.mode,
        outcome: e.outcome,
        instructions: e.instructions,
        cycles: e.cycles,
        counters: machine.shared.stats.to_vec(),
        timing: e.timing,
        sampled: e.sampled,
        profile,
        debug,
        threads: req.chip.tms * req.chip.threads_per_tm,
        host_threads: e.host_threads,
        warnings,
        failure,
        stopped_at,
        livelock: e.livelock,
        machine,
        exe,
    })
}

/// Instructions retired by every thread so far.
fn retired(m: &Machine) -> u64 {
    m.threads.iter().map(|t| t.retired).sum()
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
                    cycles: None,
                    instructions: self.retired,
                    rays: sh.stats[0],
                    live_threads: sh.live_threads,
                });
            }
        }
        stop
    }
}
