//! The machine: MIPS32r6 + FPU + MSA + TRaX execution, threads, timing, tooling.
//!
//! Layers (private modules): `decode` (word -> [`Inst`], once per word) and `disasm` (LLVM
//! syntax); `exec` (the interpreter loop over a [`Thread`]) with `fpu` (FCSR), [`softfloat`]
//! (IEEE arithmetic shared by the FPU and MSA), `trax` (extension ops) and [`msa`] (SIMD); `memory` (global memory, null
//! guard, per-thread local stores); `machine` (the chip's threads) and `sched` (the
//! functional interleaving, shared by plain, profiled and debugged runs); `elf`, `debuginfo`
//! and `crash` (loading and reports); [`timing`] (the cycle-level chip over [`memsys`]).
//!
//! The public surface:
//! - [`run()`]: the one run API — a [`RunRequest`] (functional or timing, limits, profile,
//!   GDB, progress) in, a [`RunReport`] (outcome, counts, timing statistics, profile, the
//!   failure text, the machine) out.
//! - [`timing`]: chip configurations ([`timing::ChipConfig`], presets) and statistics.
//! - [`profile`]: the profiler and its reports; [`gdb`]: the debugger server.
//! - [`memsys`] and [`msa`]: the memory-system model and the MSA unit, components with
//!   their own tests and benchmarks.
//! - The machine, for callers that drive it themselves (tests, the profiler, the debugger):
//!   [`Machine`], [`Scheduler`] and [`Executor`], [`Thread`], [`Shared`], [`Stop`], [`Fault`].
//! - Reading executables: [`Executable`], [`DebugInfo`], [`decode()`], [`demangle`].

mod block;
mod chip;
mod crash;
mod debuginfo;
mod decode;
mod disasm;
mod elf;
mod exec;
mod fpu;
#[doc(hidden)]
pub mod fuzzing;
pub mod gdb;
pub mod livelock;
mod machine;
mod memory;
pub mod memsys;
pub mod msa;
mod msa_glue;
pub mod profile;
mod program;
mod regs;
mod run;
mod sched;
pub mod softfloat;
mod streams;
mod thread;
pub mod timing;
mod tomlerr;
mod trax;
mod whereabouts;

pub use crash::demangle;
pub use debuginfo::{DebugInfo, DebugInfoError, SourceFrame};
pub use decode::{decode, Inst};
pub use elf::{ElfError, Executable, Symbol};
pub use exec::Stop;
pub use machine::{Crash, Machine, MachineConfig, Outcome, RunSummary, SetupError};
pub use memory::{LayoutError, MemFault, MemFaultKind, Segment};
pub use program::Program;
pub use regs::RegFile;
pub use run::{
    host_threads, run, Limits, Livelock, Mode, OnLivelock, Progress, RunError, RunReport,
    RunRequest, DEFAULT_QUANTUM,
};
pub use sched::{Driven, Executor, PlainExec, ReferenceExec, Scheduler};
pub use thread::{CallFrame, Fault, RunState, Shared, Thread, NUM_GLOBALS};
pub use whereabouts::{PlaceFrame, PlaceGroup, ThreadAt, ThreadPlaces};
