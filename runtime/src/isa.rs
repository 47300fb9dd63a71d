//! The TRaX instruction-set extension: one table, used by the compiler (intrinsics),
//! the emulator (decoder, executor, disassembler, timing classes) and the docs.
//!
//! Every extension instruction is an R-type word in the SPECIAL2 major opcode (0x1C),
//! which MIPS32 Release 6 leaves unallocated:
//!
//! ```text
//!  31    26 25  21 20  16 15  11 10   6 5      0
//! | 011100 |  rs  |  rt  |  rd  |  sa  | funct  |
//! ```
//!
//! `funct` selects the operation. Each operation names which of the four fields it uses
//! and how (register class, read or written, or a 5-bit immediate in `sa`). Unused fields
//! must be zero; a word with non-zero unused fields or an unknown `funct` is a reserved
//! instruction.
//!
//! Pipeline input registers of the fused box/triangle units live in coprocessor 2 and are
//! written with the standard r6 `mtc2`/read with `mfc2` (see [`COP2_REGS`]).

/// Major opcode of every TRaX extension instruction (SPECIAL2).
pub const TRAX_MAJOR_OPCODE: u32 = 0x1C;

/// An instruction field of the R-type layout.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Field {
    /// Bits 25..21.
    Rs,
    /// Bits 20..16.
    Rt,
    /// Bits 15..11.
    Rd,
    /// Bits 10..6 (a 5-bit immediate when used as [`OperandKind::Imm5`]).
    Sa,
}

impl Field {
    /// Bit position of the field's least significant bit.
    pub const fn shift(self) -> u32 {
        match self {
            Field::Rs => 21,
            Field::Rt => 16,
            Field::Rd => 11,
            Field::Sa => 6,
        }
    }

    /// Extracts this field from an instruction word.
    pub const fn extract(self, word: u32) -> u32 {
        (word >> self.shift()) & 0x1F
    }
}

/// What an operand field holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum OperandKind {
    /// A general-purpose register read by the instruction.
    GprUse,
    /// A general-purpose register written by the instruction.
    GprDef,
    /// A floating-point register (single precision unless stated) read by the instruction.
    FprUse,
    /// A floating-point register written by the instruction.
    FprDef,
    /// An unsigned 5-bit immediate.
    Imm5,
}

impl OperandKind {
    /// True for operands the instruction writes.
    pub const fn is_def(self) -> bool {
        matches!(self, OperandKind::GprDef | OperandKind::FprDef)
    }
}

/// One operand: where it is encoded and what it is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Operand {
    /// Encoding field.
    pub field: Field,
    /// Register class / role, or immediate.
    pub kind: OperandKind,
}

/// The execution-unit class an instruction issues to in the timing model.
///
/// Standard MIPS instructions are classified by the emulator; this enum is shared so
/// both kinds of instruction use the same classes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum UnitClass {
    /// Register moves and id reads: issue with no execution unit (register file only).
    RegFile,
    /// Integer add/subtract/compare.
    IntAdd,
    /// Integer multiply.
    IntMul,
    /// Integer divide/modulo.
    IntDiv,
    /// Logic and shifts.
    Bitwise,
    /// Branches and jumps.
    Branch,
    /// FP add/subtract (also the hardware random-number generator, as in simtrax).
    FpAdd,
    /// FP multiply.
    FpMul,
    /// FP min/max.
    FpMinMax,
    /// FP compares.
    FpCmp,
    /// FP divide/reciprocal.
    FpDiv,
    /// FP square root / inverse square root.
    FpInvSqrt,
    /// Conversions between integer and FP formats.
    Conv,
    /// Loads and stores to global memory (through L1).
    Memory,
    /// Loads and stores to the thread's local store (stack).
    LocalStore,
    /// Chip-wide global register file (atomics, barriers, semaphores).
    GlobalRegs,
    /// Debug/print/statistics: zero cost in the timing model.
    Debug,
    /// STRaTA ray stream buffer.
    Stream,
    /// Fused box-intersection pipeline.
    BoxPipe,
    /// Fused triangle-intersection pipeline.
    TriPipe,
}

impl UnitClass {
    /// Every class, in discriminant order (`ALL[c as usize] == c`).
    pub const ALL: [UnitClass; 20] = {
        use UnitClass::*;
        [
            RegFile, IntAdd, IntMul, IntDiv, Bitwise, Branch, FpAdd, FpMul, FpMinMax, FpCmp, FpDiv,
            FpInvSqrt, Conv, Memory, LocalStore, GlobalRegs, Debug, Stream, BoxPipe, TriPipe,
        ]
    };
    /// Number of classes.
    pub const COUNT: usize = UnitClass::ALL.len();
}

/// Every TRaX extension operation.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum TraxOp {
    ThreadId,
    TmId,
    GlobalId,
    NumThreads,
    NumTms,
    Clock,
    Rand,
    Seed,
    Halt,
    AtomicInc,
    AtomicDec,
    AtomicAdd,
    GlobalRead,
    GlobalWrite,
    IncReset,
    Barrier,
    SemAcquire,
    SemRelease,
    FMin,
    FMax,
    InvSqrt,
    PrintInt,
    PrintUint,
    PrintF32,
    PrintF64,
    PrintStr,
    PrintChar,
    PrintBool,
    PrintI64,
    PrintU64,
    PrintFmt,
    Abort,
    ProfBegin,
    ProfEnd,
    Stat,
    StatAdd,
    StreamWriteStart,
    StreamWrite,
    StreamWriteEnd,
    StreamReadStart,
    StreamRead,
    StreamReadEnd,
    StreamSize,
    StreamSchedule,
    StreamCapacity,
    SetPipe,
    BoxTest,
    TriTest,
}

impl TraxOp {
    /// True for operations whose result depends only on their operands and the thread
    /// (ids, thread counts, `fmin`/`fmax`/`invsqrt`): no effect, no memory access, so a
    /// compiler may merge, hoist or drop them (`trax_isa.h` emits them without `volatile`
    /// and without a memory clobber). Everything else is an effect in program order.
    pub fn is_pure(self) -> bool {
        matches!(
            self,
            TraxOp::ThreadId
                | TraxOp::TmId
                | TraxOp::GlobalId
                | TraxOp::NumThreads
                | TraxOp::NumTms
                | TraxOp::FMin
                | TraxOp::FMax
                | TraxOp::InvSqrt
        )
    }
}

/// Static description of one extension instruction.
#[derive(Clone, Copy, Debug)]
pub struct TraxInstr {
    /// The operation.
    pub op: TraxOp,
    /// Assembly mnemonic (lower case, as printed by the disassembler).
    pub mnemonic: &'static str,
    /// Value of the `funct` field.
    pub funct: u32,
    /// Operands in assembly order.
    pub operands: &'static [Operand],
    /// Execution-unit class.
    pub unit: UnitClass,
    /// One-line semantics summary.
    pub summary: &'static str,
}

impl TraxInstr {
    /// Encodes this instruction; `regs` gives the value of each operand in assembly order.
    ///
    /// Values are masked to 5 bits; fields not used by the instruction are zero.
    pub fn encode(&self, regs: &[u32]) -> u32 {
        assert_eq!(
            regs.len(),
            self.operands.len(),
            "operand count for {}",
            self.mnemonic
        );
        let mut w = (TRAX_MAJOR_OPCODE << 26) | self.funct;
        for (o, v) in self.operands.iter().zip(regs) {
            w |= (v & 0x1F) << o.field.shift();
        }
        w
    }

    /// The word with every operand field zero (the constant part of the encoding).
    pub fn base_word(&self) -> u32 {
        (TRAX_MAJOR_OPCODE << 26) | self.funct
    }

    /// Mask of the bits that are operand fields of this instruction.
    pub fn operand_mask(&self) -> u32 {
        self.operands
            .iter()
            .fold(0, |m, o| m | (0x1F << o.field.shift()))
    }
}

use Field::*;
use OperandKind::*;

const fn op(field: Field, kind: OperandKind) -> Operand {
    Operand { field, kind }
}

const D_GPR: Operand = op(Rd, GprDef);
const S_GPR: Operand = op(Rs, GprUse);
const T_GPR: Operand = op(Rt, GprUse);
const D_GPR_USE: Operand = op(Rd, GprUse);
const D_FPR: Operand = op(Rd, FprDef);
const S_FPR: Operand = op(Rs, FprUse);
const T_FPR: Operand = op(Rt, FprUse);
const IMM: Operand = op(Sa, Imm5);

macro_rules! instr {
    ($op:ident, $mn:literal, $funct:literal, [$($o:expr),*], $unit:ident, $sum:literal) => {
        TraxInstr {
            op: TraxOp::$op,
            mnemonic: $mn,
            funct: $funct,
            operands: &[$($o),*],
            unit: UnitClass::$unit,
            summary: $sum,
        }
    };
}

/// The instruction table. Order is by `funct`.
pub static TRAX_INSTRUCTIONS: &[TraxInstr] = &[
    instr!(ThreadId, "trax.tid", 0x00, [D_GPR], RegFile, "rd = thread index within its TM"),
    instr!(TmId, "trax.tmid", 0x01, [D_GPR], RegFile, "rd = index of the thread's TM"),
    instr!(GlobalId, "trax.gid", 0x02, [D_GPR], RegFile, "rd = chip-wide unique thread index (tm * threads_per_tm + tid)"),
    instr!(NumThreads, "trax.nthreads", 0x03, [D_GPR], RegFile, "rd = total hardware threads on the chip"),
    instr!(NumTms, "trax.ntms", 0x04, [D_GPR], RegFile, "rd = number of TMs on the chip"),
    instr!(Clock, "trax.clock", 0x05, [D_GPR], Debug, "rd = low 32 bits of the current cycle (instruction count in functional mode)"),
    instr!(Rand, "trax.rand", 0x06, [D_FPR], FpAdd, "fd = next per-thread deterministic random f32 in [0,1)"),
    instr!(Halt, "trax.halt", 0x07, [], RegFile, "stop this thread"),
    instr!(AtomicInc, "trax.atominc", 0x08, [D_GPR, S_GPR], GlobalRegs, "rd = G[rs]; G[rs] += 1 (atomic)"),
    instr!(AtomicDec, "trax.atomdec", 0x09, [D_GPR, S_GPR], GlobalRegs, "rd = G[rs]; G[rs] -= 1 (atomic)"),
    instr!(AtomicAdd, "trax.atomadd", 0x0A, [D_GPR, S_GPR, T_GPR], GlobalRegs, "rd = G[rs]; G[rs] += rt (atomic, wrapping)"),
    instr!(GlobalRead, "trax.gread", 0x0B, [D_GPR, S_GPR], GlobalRegs, "rd = G[rs]"),
    instr!(GlobalWrite, "trax.gwrite", 0x0C, [S_GPR, T_GPR], GlobalRegs, "G[rs] = rt"),
    instr!(IncReset, "trax.increset", 0x0D, [D_GPR, S_GPR], GlobalRegs, "rd = G[rs]; G[rs] += 1, wrapping to 0 when it reaches the thread count"),
    instr!(Barrier, "trax.barrier", 0x0E, [S_GPR], GlobalRegs, "wait until every live thread has reached barrier G[rs]"),
    instr!(SemAcquire, "trax.semacq", 0x0F, [S_GPR], GlobalRegs, "wait until G[rs] > 0, then G[rs] -= 1 (atomic)"),
    instr!(SemRelease, "trax.semrel", 0x10, [S_GPR], GlobalRegs, "G[rs] += 1 (atomic)"),
    instr!(FMin, "trax.fmin", 0x11, [D_FPR, S_FPR, T_FPR], FpMinMax, "fd = min(fs, ft) (f32, IEEE minNum)"),
    instr!(FMax, "trax.fmax", 0x12, [D_FPR, S_FPR, T_FPR], FpMinMax, "fd = max(fs, ft) (f32, IEEE maxNum)"),
    instr!(InvSqrt, "trax.invsqrt", 0x13, [D_FPR, S_FPR], FpInvSqrt, "fd = 1 / sqrt(fs) (f32, correctly rounded)"),
    instr!(PrintInt, "trax.printi", 0x14, [S_GPR], Debug, "print rs as i32"),
    instr!(PrintUint, "trax.printu", 0x15, [S_GPR], Debug, "print rs as u32"),
    instr!(PrintF32, "trax.printf", 0x16, [S_FPR], Debug, "print fs as f32 (Rust Display formatting)"),
    instr!(PrintF64, "trax.printd", 0x17, [S_FPR], Debug, "print fs as f64 (Rust Display formatting)"),
    instr!(PrintStr, "trax.prints", 0x18, [S_GPR, T_GPR], Debug, "print rt bytes of UTF-8 starting at address rs"),
    instr!(PrintChar, "trax.printc", 0x19, [S_GPR], Debug, "print the Unicode scalar value rs"),
    instr!(PrintBool, "trax.printb", 0x1A, [S_GPR], Debug, "print `true` if rs != 0 else `false`"),
    instr!(PrintI64, "trax.printl", 0x1B, [S_GPR, T_GPR], Debug, "print the i64 whose low word is rs and high word rt"),
    instr!(PrintU64, "trax.printul", 0x1C, [S_GPR, T_GPR], Debug, "print the u64 whose low word is rs and high word rt"),
    instr!(Abort, "trax.abort", 0x1D, [S_GPR, T_GPR, D_GPR_USE], Debug, "stop the program: rs = AbortKind code, message of rd bytes at address rt (with rs flag 0x100: rt/rd is an argument record, see abortmsg)"),
    instr!(Seed, "trax.seed", 0x1E, [S_GPR, T_GPR], FpAdd, "reseed this thread's trax.rand stream for pixel rs, sample rt (and the run's seed): the same numbers on any thread or chip"),
    instr!(PrintFmt, "trax.printfmt", 0x1F, [S_GPR, T_GPR], Debug, "print formatted text: rs = address of an argument record of rt bytes (template and values, see abortmsg)"),
    instr!(ProfBegin, "trax.profbegin", 0x20, [IMM], Debug, "begin profile region sa"),
    instr!(ProfEnd, "trax.profend", 0x21, [IMM], Debug, "end profile region sa"),
    instr!(Stat, "trax.stat", 0x22, [IMM], Debug, "increment statistics counter sa (counter 0 counts rays)"),
    instr!(StatAdd, "trax.statadd", 0x23, [S_GPR, T_GPR], Debug, "add rt to statistics counter rs (0..32; counter 0 counts rays); another index is a fault"),
    instr!(StreamWriteStart, "trax.strwstart", 0x28, [S_GPR], Stream, "begin writing a ray to stream rs"),
    instr!(StreamWrite, "trax.strw", 0x29, [S_GPR], Stream, "append word rs to the ray being written"),
    instr!(StreamWriteEnd, "trax.strwend", 0x2A, [], Stream, "push the ray being written onto its stream (LIFO); a full stream memory is a fault; idle TMs (drained, nothing to read) then schedule"),
    instr!(StreamReadStart, "trax.strrstart", 0x2B, [D_GPR], Stream, "pop the newest ray of the TM's current stream (the one trax.strsched gave it); rd = 1 if one was available else 0"),
    instr!(StreamRead, "trax.strr", 0x2C, [D_GPR], Stream, "rd = next word of the ray being read"),
    instr!(StreamReadEnd, "trax.strrend", 0x2D, [], Stream, "finish reading the current ray"),
    instr!(StreamSize, "trax.strsize", 0x2E, [D_GPR, S_GPR], Stream, "rd = number of rays queued in stream rs"),
    instr!(StreamSchedule, "trax.strsched", 0x2F, [D_GPR], Stream, "wait until every live thread of the TM waits here, then rd = the stream the TM's scheduler picked (stream_memory.schedule) as its current one; with all empty the TM idles until a write; rd = 0xFFFFFFFF when every live thread of the chip waits with all empty"),
    instr!(SetPipe, "trax.setpipe", 0x30, [IMM], RegFile, "configure this TM's shared units: 0 general purpose, 1 box pipeline, 2 triangle pipeline (reserves units; a change costs pipelines.reconfig_cycles, the current mode is free)"),
    instr!(BoxTest, "trax.boxtest", 0x31, [D_FPR], BoxPipe, "fd = entry distance of the ray (cop2 0..5) into the box (cop2 6..11), +inf on a miss; needs trax.setpipe 1"),
    instr!(TriTest, "trax.tritest", 0x32, [D_FPR], TriPipe, "fd = hit distance of the ray (cop2 0..5) with the triangle (cop2 12..20), +inf on a miss; barycentrics to cop2 21..22; needs trax.setpipe 2"),
    instr!(StreamCapacity, "trax.strcap", 0x33, [D_GPR], Stream, "rd = rays the stream memory holds (all streams together)"),
];

/// Meaning of coprocessor-2 registers, the fused pipelines' inputs and outputs.
pub static COP2_REGS: &[(u32, &str)] = &[
    (0, "ray origin x"),
    (1, "ray origin y"),
    (2, "ray origin z"),
    (3, "ray direction x (box pipe: inverse direction)"),
    (4, "ray direction y (box pipe: inverse direction)"),
    (5, "ray direction z (box pipe: inverse direction)"),
    (6, "box min x"),
    (7, "box min y"),
    (8, "box min z"),
    (9, "box max x"),
    (10, "box max y"),
    (11, "box max z"),
    (12, "triangle v0 x"),
    (13, "triangle v0 y"),
    (14, "triangle v0 z"),
    (15, "triangle v1 x"),
    (16, "triangle v1 y"),
    (17, "triangle v1 z"),
    (18, "triangle v2 x"),
    (19, "triangle v2 y"),
    (20, "triangle v2 z"),
    (21, "hit barycentric u (output)"),
    (22, "hit barycentric v (output)"),
];

/// Why a kernel stopped the program with `trax.abort` (the `rs` operand).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[repr(u32)]
pub enum AbortKind {
    /// `panic!`.
    Panic = 0,
    /// Array index out of bounds.
    Bounds = 1,
    /// Integer division or remainder by zero.
    DivideByZero = 2,
    /// `assert!` failed.
    Assert = 3,
    /// `unreachable!` reached.
    Unreachable = 4,
    /// Integer overflow in a checked operation (`i32::MIN / -1`).
    Overflow = 5,
}

impl AbortKind {
    /// Decodes an abort code (the [`crate::abortmsg::ABORT_FORMATTED`] flag is ignored).
    pub fn from_code(code: u32) -> Option<AbortKind> {
        Some(match code & !crate::abortmsg::ABORT_FORMATTED {
            0 => AbortKind::Panic,
            1 => AbortKind::Bounds,
            2 => AbortKind::DivideByZero,
            3 => AbortKind::Assert,
            4 => AbortKind::Unreachable,
            5 => AbortKind::Overflow,
            _ => return None,
        })
    }

    /// Human description.
    pub fn describe(self) -> &'static str {
        match self {
            AbortKind::Panic => "panic",
            AbortKind::Bounds => "index out of bounds",
            AbortKind::DivideByZero => "attempt to divide by zero",
            AbortKind::Assert => "assertion failed",
            AbortKind::Unreachable => "entered unreachable code",
            AbortKind::Overflow => "arithmetic overflow",
        }
    }
}

/// Statistics counter incremented once per ray cast (`trax.stat 0`).
pub const STAT_RAYS: u32 = 0;

/// Looks up an instruction by operation.
pub fn instr(op: TraxOp) -> &'static TraxInstr {
    TRAX_INSTRUCTIONS
        .iter()
        .find(|i| i.op == op)
        .expect("every TraxOp has a table row")
}

/// Decodes a word: the table row whose encoding matches, if any.
///
/// Returns `None` for words outside the SPECIAL2 opcode, unknown `funct` values and
/// words with non-zero bits in fields the instruction does not use.
pub fn decode(word: u32) -> Option<&'static TraxInstr> {
    if word >> 26 != TRAX_MAJOR_OPCODE {
        return None;
    }
    let funct = word & 0x3F;
    let row = TRAX_INSTRUCTIONS.iter().find(|i| i.funct == funct)?;
    let fixed = !row.operand_mask() & 0x03FF_FFC0;
    (word & fixed == 0).then_some(row)
}

#[cfg(test)]
mod tests {
    #[test]
    fn unit_class_all_is_every_class_in_discriminant_order() {
        use super::UnitClass;
        for (i, c) in UnitClass::ALL.iter().enumerate() {
            assert_eq!(*c as usize, i, "{c:?}");
        }
        // Exhaustive: a new variant does not compile until it is listed here (and named
        // by `timing::units`); one added before `TriPipe` but not to `ALL` moves the
        // discriminants checked above. (One added after `TriPipe` and not to `ALL` is not
        // caught: keep `TriPipe` last or extend `ALL`.)
        let listed = |c: UnitClass| {
            use UnitClass::*;
            match c {
                RegFile | IntAdd | IntMul | IntDiv | Bitwise | Branch | FpAdd | FpMul
                | FpMinMax | FpCmp | FpDiv | FpInvSqrt | Conv | Memory | LocalStore
                | GlobalRegs | Debug | Stream | BoxPipe | TriPipe => c as usize,
            }
        };
        assert_eq!(listed(UnitClass::TriPipe) + 1, UnitClass::COUNT);
    }

    use super::*;
    use std::collections::HashSet;

    #[test]
    fn functs_and_mnemonics_are_unique() {
        let mut f = HashSet::new();
        let mut m = HashSet::new();
        let mut ops = HashSet::new();
        for i in TRAX_INSTRUCTIONS {
            assert!(i.funct < 64, "{}", i.mnemonic);
            assert!(f.insert(i.funct), "duplicate funct {:#x}", i.funct);
            assert!(m.insert(i.mnemonic), "duplicate mnemonic {}", i.mnemonic);
            assert!(ops.insert(i.op), "duplicate op {:?}", i.op);
            let fields: HashSet<_> = i.operands.iter().map(|o| o.field).collect();
            assert_eq!(
                fields.len(),
                i.operands.len(),
                "{} reuses a field",
                i.mnemonic
            );
            for o in i.operands {
                assert_eq!(
                    o.kind == OperandKind::Imm5,
                    o.field == Field::Sa,
                    "{}",
                    i.mnemonic
                );
            }
        }
    }

    #[test]
    fn encode_decode_round_trip() {
        for i in TRAX_INSTRUCTIONS {
            let vals: Vec<u32> = (0..i.operands.len() as u32).map(|k| 3 + 7 * k).collect();
            let w = i.encode(&vals);
            let d = decode(w).expect("decodes");
            assert_eq!(d.op, i.op);
            for (o, v) in i.operands.iter().zip(&vals) {
                assert_eq!(o.field.extract(w), *v);
            }
        }
    }

    #[test]
    fn rejects_reserved_words() {
        // Unknown funct.
        assert!(decode((0x1C << 26) | 0x3F).is_none());
        // halt with a stray rd field.
        assert!(decode(instr(TraxOp::Halt).base_word() | (1 << 11)).is_none());
        // Not SPECIAL2 at all.
        assert!(decode(0x0000_0000).is_none());
    }
}
