//! The functional machine: TMs x threads, a deterministic round-robin interleaving,
//! barriers and semaphores, and the run loop.
//!
//! Every thread starts at the executable's entry (`__trax_start`) with its own registers
//! and local store. Threads run in a fixed order (TM-major, then thread index) for
//! `quantum` instructions each; a context switch clears the thread's LL link. A thread at
//! a barrier is skipped until the barrier releases. The run ends when every thread has
//! halted, when one faults (the crash stops the whole chip), on deadlock, or at the
//! optional instruction limit.

use std::io::Write;

use crate::elf::Executable;
use crate::livelock::Detection;
use crate::memory::{LayoutError, Memory, Segment};
use crate::program::Program;
use crate::sched::{Executor, PlainExec, Scheduler};
use crate::thread::{CallFrame, ChipShape, Fault, Shared, Thread};
use crate::RegFile;
use trax_runtime::abi;

/// Machine configuration for functional runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MachineConfig {
    /// Thread multiprocessors.
    pub tms: u32,
    /// Threads per TM.
    pub threads_per_tm: u32,
    /// Local store (stack) bytes per thread.
    pub stack_size: u32,
    /// Instructions a thread runs before the next one gets its turn.
    pub quantum: u32,
    /// Stop after this many instructions in total (None: no limit).
    pub max_instructions: Option<u64>,
}

impl Default for MachineConfig {
    fn default() -> Self {
        MachineConfig {
            tms: 1,
            threads_per_tm: 1,
            stack_size: abi::DEFAULT_STACK_SIZE,
            quantum: 1000,
            max_instructions: None,
        }
    }
}

/// Errors setting up a machine.
#[derive(Debug, thiserror::Error)]
pub enum SetupError {
    /// The segments do not form a valid memory layout.
    #[error("memory image: {0}")]
    Layout(#[from] LayoutError),
    /// Zero threads or an absurd configuration.
    #[error("machine config: {0}")]
    Config(String),
}

/// A thread that stopped the chip.
#[derive(Clone, Debug)]
pub struct Crash {
    /// What went wrong.
    pub fault: Fault,
    /// Chip-wide thread id.
    pub gid: u32,
    /// Thread index within its TM.
    pub tid: u32,
    /// TM index.
    pub tm: u32,
    /// Instructions the thread retired before the fault.
    pub retired: u64,
    /// Core cycle of the fault (timing mode; `None` in functional mode).
    pub cycle: Option<u64>,
    /// Address of the faulting instruction.
    pub pc: u32,
    /// The faulting instruction was in a delay slot or forbidden slot.
    pub in_slot: bool,
    /// Shadow call stack at the fault (outermost first).
    pub calls: Vec<CallFrame>,
    /// Registers at the fault.
    pub regs: RegFile,
}

impl Crash {
    /// The crash of thread `t` with `fault`, capturing its state at the fault.
    pub fn capture(t: &Thread, fault: Fault) -> Crash {
        Crash {
            fault,
            gid: t.gid,
            tid: t.tid,
            tm: t.tm,
            retired: t.retired,
            cycle: None,
            pc: t.pc,
            in_slot: t.slot_pc == t.pc,
            calls: t.calls.clone(),
            regs: t.regs.clone(),
        }
    }
}

/// How a run ended.
#[derive(Clone, Debug)]
pub enum Outcome {
    /// Every thread halted.
    Finished,
    /// A thread faulted.
    Crashed(Box<Crash>),
    /// Live threads remain but none can make progress.
    Deadlock {
        /// Threads waiting at barriers or semaphores.
        waiting: u32,
    },
    /// The instruction limit was reached.
    InstructionLimit,
    /// The cycle limit was reached (timing mode).
    CycleLimit,
    /// The run was proved never to end ([`crate::livelock`]) and asked to stop there.
    Livelock,
}

/// Summary of a run.
#[derive(Clone, Debug)]
pub struct RunSummary {
    /// How it ended.
    pub outcome: Outcome,
    /// Instructions retired by all threads.
    pub instructions: u64,
    /// Statistics counters (`trax.stat`).
    pub stats: Vec<u64>,
    /// Instructions per profile region.
    pub profile: Vec<u64>,
}

/// The chip: shared state plus every thread.
#[derive(Debug)]
pub struct Machine {
    /// Chip-wide state.
    pub shared: Shared,
    /// Threads in scheduling order.
    pub threads: Vec<Thread>,
    /// Configuration.
    pub config: MachineConfig,
}

impl Machine {
    /// Builds a machine running the text `[text_start, text_end)` of `segments` from
    /// `entry` on every thread.
    pub fn new(
        segments: &[Segment],
        text_start: u32,
        text_end: u32,
        entry: u32,
        config: MachineConfig,
    ) -> Result<Machine, SetupError> {
        if config.tms == 0 || config.threads_per_tm == 0 {
            return Err(SetupError::Config(
                "need at least one TM and one thread per TM".into(),
            ));
        }
        let total = config.tms as u64 * config.threads_per_tm as u64;
        if total > 1 << 20 {
            return Err(SetupError::Config(format!(
                "{total} threads is more than supported (2^20)"
            )));
        }
        if config.stack_size == 0
            || !config.stack_size.is_multiple_of(16)
            || config.stack_size > 64 << 20
        {
            return Err(SetupError::Config(format!(
                "stack size {} must be a non-zero multiple of 16 up to 64 MiB",
                config.stack_size
            )));
        }
        let mem = Memory::new(segments, config.stack_size)?;
        if !mem.executable(text_start, text_end) {
            return Err(SetupError::Layout(LayoutError::TextNotExecutable {
                start: text_start,
                end: text_end,
            }));
        }
        let seed = scene_seed(&mem);
        let program = Program::decode_range(&mem, text_start, text_end, entry);
        let shape = ChipShape {
            tms: config.tms,
            threads_per_tm: config.threads_per_tm,
        };
        let mut threads = Vec::with_capacity(total as usize);
        for tm in 0..config.tms {
            for tid in 0..config.threads_per_tm {
                let gid = tm * config.threads_per_tm + tid;
                threads.push(Thread::new(entry, tid, tm, gid, config.stack_size, seed));
            }
        }
        Ok(Machine {
            shared: Shared::new(mem, program, shape),
            threads,
            config,
        })
    }

    /// A machine running the executable `exe` on every thread, with memory `segments`
    /// (`None`: the executable's own segments).
    pub fn load(
        exe: &Executable,
        segments: Option<&[Segment]>,
        config: MachineConfig,
    ) -> Result<Machine, SetupError> {
        let segments = segments.unwrap_or(&exe.segments);
        Machine::new(segments, exe.text_start, exe.text_end, exe.entry, config)
    }

    /// Runs to completion, writing print output to `out` as it is produced.
    ///
    /// The interleaving (TM-major round robin, `quantum` instructions per turn) is
    /// [`Scheduler`]'s, shared with the profiler and the debugger so their runs equal this one.
    pub fn run(&mut self, out: &mut dyn Write) -> RunSummary {
        self.run_with(out, &mut PlainExec, None)
    }

    /// Like [`Self::run`], executing each thread's turn with `e` (e.g. to watch progress)
    /// and, with `on_livelock`, watching for a livelock
    /// ([`Scheduler::run_to_end`]).
    pub fn run_with(
        &mut self,
        out: &mut dyn Write,
        e: &mut dyn Executor,
        on_livelock: Option<&mut dyn FnMut(&Detection) -> bool>,
    ) -> RunSummary {
        let mut sched = Scheduler::new(self);
        let outcome = sched.run_to_end(self, out, e, on_livelock);
        RunSummary {
            outcome,
            instructions: sched.total,
            stats: self.shared.stats.to_vec(),
            profile: self.shared.profile.to_vec(),
        }
    }
}

/// Releases barriers whose arrivals now cover every live thread (after a thread halts).
pub(crate) fn release_barriers(sh: &mut Shared) {
    for i in 0..sh.barrier_waiting.len() {
        if sh.barrier_waiting[i] > 0 && sh.globals[i] >= sh.live_threads {
            sh.globals[i] = 0;
            sh.barrier_generation[i] += 1;
            sh.barrier_waiting[i] = 0;
        }
    }
}

/// Writes buffered print output to `out`.
pub(crate) fn drain(buf: &mut Vec<u8>, out: &mut dyn Write) {
    if !buf.is_empty() {
        // Output errors (closed pipe) must not stop the simulation.
        let _ = out.write_all(buf);
        let _ = out.flush();
        buf.clear();
    }
}

/// The random seed from the scene header, or 0 when no header is loaded.
fn scene_seed(mem: &Memory) -> u32 {
    let off = std::mem::offset_of!(abi::SceneHeader, seed) as u32;
    match mem.peek_u32(abi::SCENE_HEADER_ADDR) {
        Some(abi::SCENE_MAGIC) => mem.peek_u32(abi::SCENE_HEADER_ADDR + off).unwrap_or(0),
        _ => 0,
    }
}
