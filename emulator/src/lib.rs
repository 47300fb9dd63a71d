//! The machine: MIPS32r6 + FPU + MSA + TRaX execution, threads, timing, tooling.
//!
//! Layers: [`decode`] (word -> [`Inst`], once per word) and [`disasm`] (LLVM syntax);
//! [`exec`] (the interpreter loop over a [`thread::Thread`]) with [`fpu`] (FCSR),
//! [`softfloat`] (IEEE arithmetic shared by the FPU and MSA), [`trax`] (extension ops)
//! and [`msa`] (SIMD); [`memory`] (global memory, null guard, per-thread local stores);
//! [`machine`] (threads and scheduling);
//! [`elf`], [`debuginfo`] and [`crash`] (loading and reports); [`session`] (one-call runs).

pub mod chip;
pub mod crash;
pub mod debuginfo;
pub mod decode;
pub mod disasm;
pub mod elf;
pub mod exec;
pub mod fpu;
pub mod fuzzing;
pub mod gdb;
pub mod machine;
pub mod memory;
pub mod memsys;
pub mod msa;
mod msa_glue;
pub mod profile;
pub mod program;
pub mod regs;
pub mod session;
pub mod softfloat;
pub mod thread;
pub mod timing;
pub mod tomlerr;
pub mod trax;

pub use decode::{decode, Inst};
pub use machine::{Machine, MachineConfig, Outcome};
pub use regs::RegFile;
