//! One hardware thread's architectural state and the chip state its instructions touch.

use crate::memory::{MemFault, Memory};
use crate::program::Program;
use crate::regs::RegFile;
use trax_runtime::abi;
use trax_runtime::isa::AbortKind;
use trax_runtime::rng::Rng;

/// Number of chip-wide global registers (`G[0..NUM_GLOBALS)`).
pub const NUM_GLOBALS: usize = 256;
/// Number of statistics counters (`trax.stat`, `trax.statadd`).
pub use trax_runtime::counters::NUM_STATS;
/// Number of coprocessor-2 (pipeline) registers per thread.
pub const NUM_COP2: usize = 32;
/// Deepest shadow call stack kept for backtraces (deeper calls are counted, not stored).
pub const MAX_SHADOW_FRAMES: usize = 4096;

/// One entry of the shadow call stack.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CallFrame {
    /// Address of the call instruction.
    pub call_pc: u32,
    /// Address it returns to.
    pub return_addr: u32,
    /// Called address.
    pub target: u32,
}

/// Whether a thread can run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RunState {
    /// Runnable.
    Running,
    /// Executed `trax.halt`.
    Halted,
    /// Waiting at barrier register `reg` for release number `generation`.
    Barrier {
        /// Global register of the barrier.
        reg: u32,
        /// Release count of that barrier when the thread arrived.
        generation: u64,
    },
    /// Waiting in `trax.strsched` for its TM's stream scheduler to pass `generation`
    /// (see `crate::streams`); the buffer id it gets goes to GPR `rd`.
    StreamWait {
        /// Destination register of the `trax.strsched`.
        rd: u8,
        /// The TM scheduler's release count when the thread arrived.
        generation: u64,
    },
}

/// What stopped a thread (the crash report's "what went wrong").
#[derive(Clone, Debug, PartialEq)]
pub enum Fault {
    /// A load, store or instruction fetch failed.
    Memory {
        /// The failed access.
        fault: MemFault,
        /// True for instruction fetches.
        fetch: bool,
    },
    /// A reserved (undefined) instruction word.
    ReservedInstruction(u32),
    /// A branch or jump in a delay slot or forbidden slot.
    BranchInSlot,
    /// `add`/`sub` signed overflow (Integer Overflow exception).
    IntegerOverflow,
    /// A conditional trap (`teq` etc.); LLVM uses code 7 for integer division by zero.
    Trap {
        /// The trap code field.
        code: u16,
    },
    /// `break`.
    Break(u32),
    /// `syscall` (there is no operating system).
    Syscall(u32),
    /// `sdbbp`.
    DebugBreakpoint(u32),
    /// An enabled floating-point exception (FCSR or MSACSR Enables).
    FpException {
        /// Cause bits (`softfloat::FLAG_*`).
        cause: u32,
        /// Raised by an MSA instruction.
        msa: bool,
    },
    /// The kernel stopped the program with `trax.abort`.
    Abort {
        /// The abort kind, if the code is known.
        kind: Option<AbortKind>,
        /// Raw code.
        code: u32,
        /// Message from the kernel (lossy UTF-8).
        message: String,
    },
    /// A TRaX global-register, stream or counter index out of range.
    BadIndex {
        /// What was indexed.
        what: &'static str,
        /// The index.
        index: u32,
    },
    /// `trax.strwend` with every slot of the ray stream memory taken.
    StreamFull {
        /// The stream written.
        stream: u32,
        /// Rays the memory holds.
        capacity_rays: u32,
        /// Bytes of a ray record.
        ray_bytes: u32,
    },
    /// A spill of the ray stream memory found its DRAM spill area full.
    SpillAreaFull {
        /// The stream a block was spilled from.
        stream: u32,
        /// Blocks the area holds.
        blocks: u32,
        /// Bytes of a block.
        block_bytes: u32,
    },
    /// `trax.strw` past the end of a ray record.
    RayTooLong {
        /// Bytes of a ray record.
        ray_bytes: u32,
    },
    /// A fused-pipeline instruction while the TM's units are configured otherwise.
    PipeMode {
        /// The instruction's mnemonic.
        instr: &'static str,
        /// The TM's current `trax.setpipe` mode.
        mode: u8,
        /// The mode it needs.
        needed: u8,
    },
}

/// Name of a `trax.setpipe` mode.
pub fn pipe_mode_name(mode: u8) -> &'static str {
    match mode {
        0 => "general-purpose",
        1 => "box-pipeline",
        2 => "triangle-pipeline",
        _ => "unknown",
    }
}

impl std::fmt::Display for Fault {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        use crate::memory::MemFaultKind::*;
        match self {
            Fault::Memory { fault, fetch } => {
                let access = if *fetch {
                    "instruction fetch".to_string()
                } else {
                    format!(
                        "{}-byte {}",
                        fault.size,
                        if fault.write { "store" } else { "load" }
                    )
                };
                let what = match fault.kind {
                    Null => "null pointer dereference",
                    Misaligned => "misaligned access",
                    StackOverflow => "stack overflow",
                    BadAddress => "bad address",
                    ReadOnly => "store to read-only memory",
                    NotReadable => "load from non-readable memory",
                    NotExecutable => "instruction fetch from non-executable memory",
                };
                write!(f, "{what}: {access} at address {:#010x}", fault.addr)
            }
            Fault::ReservedInstruction(w) => write!(f, "reserved instruction {w:#010x}"),
            Fault::BranchInSlot => {
                write!(
                    f,
                    "reserved instruction: branch or jump in a delay or forbidden slot"
                )
            }
            Fault::IntegerOverflow => write!(f, "integer overflow (add/sub trap)"),
            Fault::Trap { code: 7 } => write!(f, "integer divide by zero (trap code 7)"),
            Fault::Trap { code: 6 } => write!(f, "integer overflow (trap code 6)"),
            Fault::Trap { code } => write!(f, "conditional trap (code {code})"),
            Fault::Break(0) => write!(
                f,
                "break instruction (code 0): a trap, such as C's `__builtin_trap()`"
            ),
            Fault::Break(c) => write!(f, "break instruction (code {c})"),
            Fault::Syscall(c) => write!(f, "syscall (code {c}): there is no operating system"),
            Fault::DebugBreakpoint(c) => write!(f, "sdbbp (code {c})"),
            Fault::FpException { cause, msa } => write!(
                f,
                "{}floating-point exception: {}",
                if *msa { "MSA " } else { "" },
                crate::softfloat::describe_flags(*cause)
            ),
            Fault::Abort {
                kind,
                code,
                message,
            } => {
                // The message is the whole panic message, as Rust's panic handler prints
                // it after "panicked at FILE:LINE:COL:"; the kind speaks only for an empty one.
                match (kind, message.is_empty()) {
                    (Some(k), true) => write!(f, "{}", k.describe()),
                    (None, true) => write!(f, "abort code {code}"),
                    (Some(_), false) => write!(f, "panicked: {message}"),
                    (None, false) => write!(f, "panicked: {message} (abort code {code})"),
                }
            }
            Fault::BadIndex { what, index } => write!(f, "{what} index {index} out of range"),
            Fault::StreamFull {
                capacity_rays: 0, ..
            } => write!(
                f,
                "this chip has no ray stream memory (stream_memory.capacity_bytes = 0)"
            ),
            Fault::StreamFull {
                stream,
                capacity_rays,
                ray_bytes,
            } => write!(
                f,
                "ray stream memory full: writing a ray to stream {stream}, but all \
                 {capacity_rays} slots of {ray_bytes}-byte rays are taken"
            ),
            Fault::SpillAreaFull {
                stream,
                blocks,
                block_bytes,
            } => write!(
                f,
                "ray spill area full: spilling a block of stream {stream}, but all {blocks} \
                 blocks of {block_bytes} bytes are taken (stream_memory.spill.area_bytes)"
            ),
            Fault::RayTooLong { ray_bytes } => write!(
                f,
                "ray too long: trax.strw past the end of a {ray_bytes}-byte ray record \
                 (stream_memory.ray_bytes)"
            ),
            Fault::PipeMode {
                instr,
                mode,
                needed,
            } => write!(
                f,
                "{instr} while this TM's units are in {} mode (needs trax.setpipe {needed}, {} mode)",
                pipe_mode_name(*mode),
                pipe_mode_name(*needed)
            ),
        }
    }
}

/// Chip configuration that instructions observe.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ChipShape {
    /// Number of thread multiprocessors.
    pub tms: u32,
    /// Threads per TM.
    pub threads_per_tm: u32,
}

impl ChipShape {
    /// Total hardware threads.
    pub fn total(&self) -> u32 {
        self.tms * self.threads_per_tm
    }
}

/// Chip-wide state shared by every thread.
#[derive(Debug)]
pub struct Shared {
    /// Global memory.
    pub mem: Memory,
    /// Predecoded program text.
    pub program: Program,
    /// Chip shape.
    pub shape: ChipShape,
    /// Global registers.
    pub globals: Vec<u32>,
    /// Release count per barrier register.
    pub barrier_generation: Vec<u64>,
    /// Threads currently waiting at each barrier register.
    pub barrier_waiting: Vec<u32>,
    /// Threads not yet halted.
    pub live_threads: u32,
    /// Output of the print instructions not yet drained.
    pub output: Vec<u8>,
    /// Statistics counters (`trax.stat`).
    pub stats: [u64; NUM_STATS],
    /// Instructions executed inside each profile region (`trax.profbegin/profend`).
    pub profile: [u64; 32],
    /// The ray stream memory (STRaTA).
    pub streams: crate::streams::StreamMemory,
    /// Each TM's stream scheduler (`trax.strsched`; its current buffer is the one
    /// `trax.strrstart` reads).
    pub sched: crate::streams::StreamScheduler,
    /// The cycle of the chip-wide operation being executed (timing mode's serial phase; 0
    /// in functional mode): stream scheduling reads it for idle time and resume cycles.
    pub clock: u64,
    /// Pipeline mode per TM (`trax.setpipe`).
    pub tm_pipe_mode: Vec<u8>,
    /// Bit `m` set when the chip's TMs have the units for `trax.setpipe m`.
    pub pipe_modes: u8,
    /// Chip-wide changes so far other than global stores (which [`Memory`] counts):
    /// global-register, barrier, semaphore, stream and pipeline-mode operations, prints,
    /// `trax.stat` counts and halts. The livelock detector ([`crate::livelock`]) takes a
    /// run in which this and the store count stay still for long as a reason to look.
    pub changes: u64,
}

impl Shared {
    /// Chip state for a program loaded into `mem`.
    pub fn new(mem: Memory, program: Program, shape: ChipShape) -> Shared {
        Shared {
            mem,
            program,
            shape,
            globals: vec![0; NUM_GLOBALS],
            barrier_generation: vec![0; NUM_GLOBALS],
            barrier_waiting: vec![0; NUM_GLOBALS],
            live_threads: shape.total(),
            output: Vec::new(),
            stats: [0; NUM_STATS],
            profile: [0; 32],
            streams: crate::streams::StreamMemory::new(Default::default()),
            sched: crate::streams::StreamScheduler::new(
                shape.tms,
                shape.threads_per_tm,
                Default::default(),
                1,
            ),
            clock: 0,
            tm_pipe_mode: vec![0; shape.tms as usize],
            pipe_modes: 0b111,
            changes: 0,
        }
    }
}

#[cfg(test)]
impl Shared {
    /// A one-thread chip for tests: memory from `segments` (local stores of 4 KiB), the
    /// `words` words at `text` predecoded.
    pub(crate) fn one_thread(segments: &[crate::memory::Segment], text: u32, words: u32) -> Shared {
        let mem = Memory::new(segments, 4096).unwrap();
        let program = Program::decode_range(&mem, text, text + 4 * words, text);
        let shape = ChipShape {
            tms: 1,
            threads_per_tm: 1,
        };
        Shared::new(mem, program, shape)
    }
}

impl Shared {
    /// The count of every chip-wide change so far (global stores included): still while
    /// nothing outside the threads changes.
    pub fn progress_count(&self) -> u64 {
        self.changes + self.mem.stores
    }

    /// A thread of TM `tm` halted: one live thread less for barriers and the TM's stream
    /// scheduler (whose peers may now have drained).
    pub fn thread_halted(&mut self, tm: u32) {
        self.live_threads -= 1;
        self.changes += 1;
        crate::machine::release_barriers(self);
        self.sched
            .halted(tm as usize, &self.streams, self.live_threads, self.clock);
    }

    /// A thread of TM `tm` enters `trax.strsched`: the generation it waits to pass.
    pub fn stream_arrive(&mut self, tm: u32) -> u64 {
        self.sched
            .arrive(tm as usize, &self.streams, self.live_threads, self.clock)
    }

    /// Threads blocked until another thread acts: waiting at a barrier that has not
    /// released or in `trax.strsched` with their TM not yet scheduled. When this is every
    /// live thread, nothing can ever run again (a deadlock).
    pub fn blocked_threads(&self) -> u32 {
        self.barrier_waiting.iter().sum::<u32>() + self.sched.waiting
    }
}

/// One hardware thread.
#[derive(Clone, Debug)]
pub struct Thread {
    /// Registers.
    pub regs: RegFile,
    /// Address of the next instruction to execute.
    pub pc: u32,
    /// Address of the instruction after it (differs from `pc + 4` in a delay slot).
    pub npc: u32,
    /// Address of the instruction currently in a delay or forbidden slot (a branch there
    /// is a reserved instruction).
    pub slot_pc: u32,
    /// The thread's local store (stack window).
    pub local: Vec<u8>,
    /// Instructions retired.
    pub retired: u64,
    /// Thread index within its TM.
    pub tid: u32,
    /// TM index.
    pub tm: u32,
    /// Chip-wide id.
    pub gid: u32,
    /// Run state.
    pub state: RunState,
    /// LL/SC link: the address of the last `ll`, cleared on a context switch.
    pub ll_addr: Option<u32>,
    /// Shadow call stack (calls and returns), for backtraces.
    pub calls: Vec<CallFrame>,
    /// Calls not recorded because the shadow stack was full.
    pub dropped_calls: u32,
    /// Coprocessor-2 registers (pipeline inputs and outputs).
    pub cop2: [u32; NUM_COP2],
    /// Random stream.
    pub rng: Rng,
    /// Ray being written to a stream: (stream id, words).
    pub stream_write: Option<(u32, Vec<u32>)>,
    /// Ray being read and the read position.
    pub stream_read: Option<(Vec<u32>, usize)>,
    /// Open profile regions: (region, retired count at begin).
    pub profile_open: Vec<(u8, u64)>,
    /// The fault of the instruction being executed (set on the interpreter's cold path).
    pub pending_fault: Option<Fault>,
    /// Address of the instruction the thread last blocked at (barrier, `trax.strsched`),
    /// for deadlock reports.
    pub wait_pc: u32,
}

impl Thread {
    /// A thread about to execute `entry`, with `$sp` at the top of its stack.
    pub fn new(entry: u32, tid: u32, tm: u32, gid: u32, stack_size: u32, seed: u32) -> Thread {
        let mut regs = RegFile::default();
        regs.gpr[29] = abi::STACK_TOP;
        Thread {
            regs,
            pc: entry,
            npc: entry.wrapping_add(4),
            slot_pc: u32::MAX,
            local: vec![0; stack_size as usize],
            retired: 0,
            tid,
            tm,
            gid,
            state: RunState::Running,
            ll_addr: None,
            calls: Vec::new(),
            dropped_calls: 0,
            cop2: [0; NUM_COP2],
            rng: Rng::new(seed, gid),
            stream_write: None,
            stream_read: None,
            profile_open: Vec::new(),
            pending_fault: None,
            wait_pc: 0,
        }
    }

    /// Makes a waiting thread runnable if what it waits for has happened by cycle `now`
    /// (functional mode: `u64::MAX`): a barrier released, or its TM's stream scheduler
    /// released it (its `trax.strsched` result is written then). Returns whether it can run.
    #[inline]
    pub fn wake(&mut self, sh: &Shared, now: u64) -> bool {
        match self.state {
            RunState::Running => true,
            RunState::Halted => false,
            RunState::Barrier { reg, generation } => {
                if sh.barrier_generation[reg as usize] > generation {
                    self.state = RunState::Running;
                    true
                } else {
                    false
                }
            }
            RunState::StreamWait { rd, generation } => {
                let tm = self.tm as usize;
                if sh.sched.released(tm, generation, now) {
                    if rd & 31 != 0 {
                        self.regs.gpr[(rd & 31) as usize] = sh.sched.tms[tm].current;
                    }
                    self.state = RunState::Running;
                    true
                } else {
                    false
                }
            }
        }
    }

    /// Whether [`Thread::wake`] would make this waiting thread runnable (ignoring cycles).
    pub fn releasable(&self, sh: &Shared) -> bool {
        match self.state {
            RunState::Barrier { reg, generation } => {
                sh.barrier_generation[reg as usize] > generation
            }
            RunState::StreamWait { generation, .. } => {
                sh.sched.released(self.tm as usize, generation, u64::MAX)
            }
            RunState::Running | RunState::Halted => false,
        }
    }
}
