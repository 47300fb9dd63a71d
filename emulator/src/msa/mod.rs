//! MSA (MIPS SIMD Architecture, 128-bit vectors) decode, disassembly and execution.
//!
//! Vector register `wN` is all 128 bits of `RegFile::fpr[N]`, element 0 in the least
//! significant bits. [`decode()`] turns one instruction word into an [`MsaInst`] (once per
//! word); [`execute()`] runs it against a [`RegFile`](crate::RegFile) and an [`MsaMemory`].
//! `MsaInst` implements `Display` in LLVM's syntax (`fadd.w $w0, $w1, $w2`).
//!
//! Choices where the architecture leaves behaviour open (UNPREDICTABLE or
//! implementation-defined) are documented in [`exec`] and, for floating point, in
//! [`crate::softfloat`] (shared with the scalar FPU).

pub mod decode;
pub mod disasm;
pub mod exec;
mod int_fast;
mod ops;

pub use decode::decode;
pub use exec::{execute, MsaFault, MsaMemory, MsaOutcome};
pub use ops::{Df, Form, MsaOp};

/// One decoded MSA instruction.
///
/// Field meaning depends on [`MsaOp::form`]: `wd`/`ws`/`wt` hold the 5-bit register
/// fields at bits 10..6, 15..11 and 20..16 (they name GPRs or MSA control registers
/// for the forms that use them so); `imm` holds the immediate, element index, bit
/// count, byte offset (loads/stores, already scaled by the element size) or branch
/// byte offset (`offset << 2`, relative to the delay slot).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct MsaInst {
    /// Operation.
    pub op: MsaOp,
    /// Data format (element size) of the operation.
    pub df: Df,
    /// Destination field (bits 10..6).
    pub wd: u8,
    /// First source field (bits 15..11).
    pub ws: u8,
    /// Second source field (bits 20..16).
    pub wt: u8,
    /// Immediate operand (meaning depends on the form).
    pub imm: i32,
}

impl MsaInst {
    /// Execution-unit class for the timing model.
    pub fn unit(&self) -> trax_runtime::isa::UnitClass {
        self.op.unit()
    }

    /// True for the MSA branches (`bz.v`, `bnz.v`, `bz.df`, `bnz.df`), which have a delay slot.
    pub fn is_branch(&self) -> bool {
        self.op.form() == Form::Branch
    }

    /// A branch's target offset in bytes from the branch itself (see
    /// [`crate::Inst::branch_offset`]).
    pub fn branch_offset(&self) -> Option<i32> {
        self.is_branch().then(|| self.imm.wrapping_add(4))
    }
}
