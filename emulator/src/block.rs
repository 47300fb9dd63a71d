//! The fast engine of functional execution: the predecoded text translated once more, into
//! micro-operations ([`Uop`]) with their operands extracted, run a basic block at a time.
//! The interpreter of `exec.rs` ([`Thread::step`]) stays the reference: it runs what the
//! engine leaves to it, and the timing model's [`Thread::step_once`] runs it alone.
//!
//! - One uop per text word, so the block starting at any word is a slice of the uops;
//!   `Program::runs` gives its length: the fast uops from there up to and including the
//!   first branch or jump (with its delay slot, when that is fast too). A run checks the
//!   instruction budget, the delay-slot state and the block's length once per block, not
//!   per instruction, and executes no per-instruction bookkeeping but the instruction.
//! - A uop either completes with exactly the reference's effects or *bails* before it has
//!   any effect; the reference then executes that instruction. Uops bail on an integer
//!   overflow, a trap whose condition holds, and any load or store the memory does not
//!   perform at once (a fault; a store the [`Chip`] view refuses). Instructions with no
//!   uop ([`K::Complex`]: TRaX operations other than `fmin`/`fmax`/`invsqrt`, MSA,
//!   `ll`/`sc`, `rdhwr`, FCSR moves, traps by nature, reserved words, ...) always go to
//!   the reference.
//! - FPU uops call the soft-float core's entries, as the reference does, without its
//!   check for an enabled exception: the engine runs blocks only while FCSR enables none
//!   (then no FPU instruction traps), and only the reference (`ctc1`) changes FCSR's
//!   enables and rounding mode.
//! - Forbidden and delay slots: a block starts only where the thread is not in a delay
//!   slot (`npc == pc + 4`). A branch or jump whose previous word has a slot (a branch
//!   with a delay slot or a compact conditional branch), or at the start of the text, is
//!   `Complex`: only there can it sit in a slot, and the reference raises the
//!   reserved-instruction fault. Every branch updates `Thread::slot_pc` as the reference
//!   does (crash reports read it).
//! - `$0`: a uop never writes `gpr[0]`: pure operations writing `$0` become `Nop`, the rest
//!   (loads, `add`/`sub`) are `Complex`, so `gpr[0]` stays 0 with no per-instruction reset.
//!
//! Checked against the reference instruction by instruction on random programs
//! (`block::tests`) and on whole programs (`emulator/tests/fast_engine.rs`).

use crate::chip::Chip;
use crate::decode::{Conv, Cti, Inst, F2, F3};
use crate::exec::{fp_compare, fp_min_max, trax_fminmax};
use crate::regs::RegFile;
use crate::softfloat::{self as sf, Arith, Fmt, MinMax};
use crate::thread::Thread;
use trax_runtime::fops;
use trax_runtime::isa::TraxOp;

/// Longest block (`Program::runs` entries are `u16`).
const MAX_RUN: usize = u16::MAX as usize;

/// Micro-operation kinds. Fields: `a` the destination (GPR, FPR or cop2 register), `b`
/// and `c` the sources, `imm` the immediate (sign- or zero-extended as the instruction
/// reads it), the absolute target of a PC-relative branch or `j`/`jal`, or the address
/// of a PC-relative load. Exceptions are noted.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u8)]
#[rustfmt::skip]
pub(crate) enum K {
    /// Left to the reference interpreter.
    Complex,
    Nop,
    /// `a = imm` (`addiupc`, `auipc`, `aluipc`: the pc is known).
    Li,
    /// `a = b + imm` (`addiu`; `aui` with `imm` shifted).
    AddImm, Slti, Sltiu, Andi, Ori, Xori,
    Addu, Subu, Add, Sub, And, Or, Xor, Nor, Slt, Sltu, Mul, Muh, Muhu,
    Div, Mod, Divu, Modu, Seleqz, Selnez,
    /// `a = b shift (c & 31)`.
    Sllv, Srlv, Srav, Rotrv,
    /// `a = b shift imm`.
    Sll, Srl, Sra, Rotr,
    /// `a = (b << imm) + c`.
    Lsa,
    Clz, Clo,
    /// `a = align(b, c)` by `imm` bytes.
    Align,
    Bitswap, Wsbh, Seb, Seh,
    /// `a = (b >> c) & imm` (`imm` the mask).
    Ext,
    /// Insert `b & imm` at bit `c` of `a`.
    Ins,
    /// Loads: `a = mem[b + imm]`; stores: `mem[b + imm] = a`.
    Lb, Lbu, Lh, Lhu, Lw, Sb, Sh, Sw, Lwc1, Swc1, Ldc1, Sdc1,
    /// Traps on `b` against `c` (bail when taken).
    Teq, Tne, Tge, Tgeu, Tlt, Tltu,
    // Branches and jumps with a delay slot (`Kind::Delay`).
    Beq, Bne, Blez, Bgtz, Bltz, Bgez, Bal, J, Jal,
    /// `jalr a, b` (`a` 0: `jr`).
    Jalr,
    Bc1eqz, Bc1nez,
    // Compact branches and jumps (`Kind::Compact`).
    Bc, Balc, Beqc, Bnec, Bltc, Bgec, Bltuc, Bgeuc, Bovc, Bnvc,
    Beqzc, Bnezc, Blezc, Bgezc, Bgtzc, Bltzc,
    Blezalc, Bgezalc, Bgtzalc, Bltzalc, Beqzalc, Bnezalc,
    /// Jump to `b + imm` (`jialc` links).
    Jic, Jialc,
    // FPU: `a = b op c` (`maddf`/`msubf`: `a` is also the accumulator).
    AddS, SubS, MulS, DivS, SqrtS, AddD, SubD, MulD, DivD, SqrtD,
    MaddfS, MsubfS, MaddfD, MsubfD,
    AbsS, AbsD, NegS, NegD, MovS, MovD,
    SelS, SelD, SeleqzS, SeleqzD, SelnezS, SelnezD,
    MinS, MaxS, MinaS, MaxaS, MinD, MaxD, MinaD, MaxaD,
    /// `cmp.cond.fmt`: `imm` is the condition field.
    CmpS, CmpD,
    /// `cmp.cond.s` whose condition, for operands that are not NaN, is `<` (`lt`, `ult`
    /// and their signalling forms), `<=` or `==`; `imm` is the condition field.
    CmpLtS, CmpLeS, CmpEqS,
    /// Format conversion `a = conv(b)`; `imm` indexes [`CONVS`].
    Cvt,
    /// `a` (GPR) from FPR `b`; `mthc1`/`mtc1`: FPR `a` from GPR `b`.
    Mfc1, Mtc1, Mfhc1, Mthc1,
    /// Coprocessor-2 register `a` from GPR `b`, or GPR `a` from cop2 `b`.
    Mtc2, Mfc2,
    /// `trax.fmin`/`fmax`/`invsqrt` on FPRs.
    FMin, FMax, InvSqrt,
}

/// How a uop ends a block.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    /// Falls through.
    Plain,
    /// A branch or jump with a delay slot.
    Delay,
    /// A compact branch or jump.
    Compact,
}

impl K {
    fn kind(self) -> Kind {
        use K::*;
        match self {
            Beq | Bne | Blez | Bgtz | Bltz | Bgez | Bal | J | Jal | Jalr | Bc1eqz | Bc1nez => {
                Kind::Delay
            }
            Bc | Balc | Beqc | Bnec | Bltc | Bgec | Bltuc | Bgeuc | Bovc | Bnvc | Beqzc | Bnezc
            | Blezc | Bgezc | Bgtzc | Bltzc | Blezalc | Bgezalc | Bgtzalc | Bltzalc | Beqzalc
            | Bnezalc | Jic | Jialc => Kind::Compact,
            _ => Kind::Plain,
        }
    }

    /// Whether this uop, with GPR destination `a`, only computes `a` from registers (so
    /// writing `$0` makes it a no-op).
    fn pure_gpr(self) -> bool {
        use K::*;
        matches!(
            self,
            Li | AddImm
                | Slti
                | Sltiu
                | Andi
                | Ori
                | Xori
                | Addu
                | Subu
                | And
                | Or
                | Xor
                | Nor
                | Slt
                | Sltu
                | Mul
                | Muh
                | Muhu
                | Div
                | Mod
                | Divu
                | Modu
                | Seleqz
                | Selnez
                | Sllv
                | Srlv
                | Srav
                | Rotrv
                | Sll
                | Srl
                | Sra
                | Rotr
                | Lsa
                | Clz
                | Clo
                | Align
                | Bitswap
                | Wsbh
                | Seb
                | Seh
                | Ext
                | Ins
                | Mfc1
                | Mfhc1
                | Mfc2
        )
    }

    /// A load into GPR `a` (which may fault: `$0` as its destination is left to the
    /// reference), or `add`/`sub` (which may trap).
    fn faulting_gpr(self) -> bool {
        use K::*;
        matches!(self, Lb | Lbu | Lh | Lhu | Lw | Add | Sub)
    }
}

/// The conversions, indexed by a [`K::Cvt`] uop's `imm`.
const CONVS: [Conv; 26] = {
    use Conv::*;
    [
        CvtSD, CvtSW, CvtSL, CvtDS, CvtDW, CvtDL, CvtWS, CvtWD, CvtLS, CvtLD, RoundWS, RoundWD,
        RoundLS, RoundLD, TruncWS, TruncWD, TruncLS, TruncLD, CeilWS, CeilWD, CeilLS, CeilLD,
        FloorWS, FloorWD, FloorLS, FloorLD,
    ]
};

/// One micro-operation (see [`K`] for its fields).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Uop {
    k: K,
    a: u8,
    b: u8,
    c: u8,
    imm: u32,
}

/// Largest uop field: `8 * 31`, FPU register 31.
const MAX_FIELD: u8 = 8 * 31;

impl Uop {
    const COMPLEX: Uop = Uop {
        k: K::Complex,
        a: 0,
        b: 0,
        c: 0,
        imm: 0,
    };

    /// A uop with fields as given (GPR and cop2 fields hold the register number, FPU
    /// register fields `8 n` for register `n`: see [`fr`]).
    ///
    /// Every field is at most [`MAX_FIELD`] (the only way to make a `Uop`: its fields are
    /// private to this module), so any field names a byte offset inside the FPU
    /// registers, whatever the kind ([`fr`] relies on it).
    fn new(k: K, a: u8, b: u8, c: u8, imm: u32) -> Uop {
        assert!(a.max(b).max(c) <= MAX_FIELD, "uop field out of range");
        Uop { k, a, b, c, imm }
    }
}

/// The uop of `inst` at `pc` (before the slot and `$0` rules of [`translate`]).
fn uop(inst: &Inst, pc: u32) -> Uop {
    use Inst::*;
    // Field encodings: a GPR (or cop2 register), an FPU register.
    let g = |n: u8| n & 31;
    let f = |n: u8| (n & 31) << 3;
    let r3 = |k, d: u8, s: u8, t: u8| Uop::new(k, g(d), g(s), g(t), 0);
    let ri = |k, d: u8, s: u8, imm: u32| Uop::new(k, g(d), g(s), 0, imm);
    let sx = |v: i16| v as i32 as u32;
    let rel = |off: i32| Inst::rel_target(pc, off);
    let f3 = |k, x: F3| Uop::new(k, f(x.fd), f(x.fs), f(x.ft), 0);
    let f2 = |k, x: F2| Uop::new(k, f(x.fd), f(x.fs), 0, 0);
    // FPU register `ft`, GPR base.
    let fm = |k, ft: u8, base: u8, off: i16| Uop::new(k, f(ft), g(base), 0, sx(off));
    match *inst {
        Add { rd, rs, rt } => r3(K::Add, rd, rs, rt),
        Addu { rd, rs, rt } => r3(K::Addu, rd, rs, rt),
        Sub { rd, rs, rt } => r3(K::Sub, rd, rs, rt),
        Subu { rd, rs, rt } => r3(K::Subu, rd, rs, rt),
        And { rd, rs, rt } => r3(K::And, rd, rs, rt),
        Or { rd, rs, rt } => r3(K::Or, rd, rs, rt),
        Xor { rd, rs, rt } => r3(K::Xor, rd, rs, rt),
        Nor { rd, rs, rt } => r3(K::Nor, rd, rs, rt),
        Slt { rd, rs, rt } => r3(K::Slt, rd, rs, rt),
        Sltu { rd, rs, rt } => r3(K::Sltu, rd, rs, rt),
        Mul { rd, rs, rt } | Mulu { rd, rs, rt } => r3(K::Mul, rd, rs, rt),
        Muh { rd, rs, rt } => r3(K::Muh, rd, rs, rt),
        Muhu { rd, rs, rt } => r3(K::Muhu, rd, rs, rt),
        Div { rd, rs, rt } => r3(K::Div, rd, rs, rt),
        Mod { rd, rs, rt } => r3(K::Mod, rd, rs, rt),
        Divu { rd, rs, rt } => r3(K::Divu, rd, rs, rt),
        Modu { rd, rs, rt } => r3(K::Modu, rd, rs, rt),
        Seleqz { rd, rs, rt } => r3(K::Seleqz, rd, rs, rt),
        Selnez { rd, rs, rt } => r3(K::Selnez, rd, rs, rt),
        Sllv { rd, rt, rs } => r3(K::Sllv, rd, rt, rs),
        Srlv { rd, rt, rs } => r3(K::Srlv, rd, rt, rs),
        Srav { rd, rt, rs } => r3(K::Srav, rd, rt, rs),
        Rotrv { rd, rt, rs } => r3(K::Rotrv, rd, rt, rs),
        Sll { rd, rt, sa } => ri(K::Sll, rd, rt, (sa & 31) as u32),
        Srl { rd, rt, sa } => ri(K::Srl, rd, rt, (sa & 31) as u32),
        Sra { rd, rt, sa } => ri(K::Sra, rd, rt, (sa & 31) as u32),
        Rotr { rd, rt, sa } => ri(K::Rotr, rd, rt, (sa & 31) as u32),
        Lsa { rd, rs, rt, sa } => Uop::new(K::Lsa, g(rd), g(rs), g(rt), (sa & 7) as u32),
        Clz { rd, rs } => ri(K::Clz, rd, rs, 0),
        Clo { rd, rs } => ri(K::Clo, rd, rs, 0),
        Addiu { rt, rs, imm } => ri(K::AddImm, rt, rs, sx(imm)),
        Slti { rt, rs, imm } => ri(K::Slti, rt, rs, sx(imm)),
        Sltiu { rt, rs, imm } => ri(K::Sltiu, rt, rs, sx(imm)),
        Andi { rt, rs, imm } => ri(K::Andi, rt, rs, imm as u32),
        Ori { rt, rs, imm } => ri(K::Ori, rt, rs, imm as u32),
        Xori { rt, rs, imm } => ri(K::Xori, rt, rs, imm as u32),
        Aui { rt, rs, imm } => ri(K::AddImm, rt, rs, (imm as u32) << 16),
        Align { rd, rs, rt, bp } => Uop::new(K::Align, g(rd), g(rs), g(rt), (bp & 3) as u32),
        Bitswap { rd, rt } => ri(K::Bitswap, rd, rt, 0),
        Wsbh { rd, rt } => ri(K::Wsbh, rd, rt, 0),
        Seb { rd, rt } => ri(K::Seb, rd, rt, 0),
        Seh { rd, rt } => ri(K::Seh, rd, rt, 0),
        Ext { rt, rs, pos, size } => Uop::new(K::Ext, g(rt), g(rs), pos & 31, field_mask(size)),
        Ins { rt, rs, pos, size } => Uop::new(K::Ins, g(rt), g(rs), pos & 31, field_mask(size)),
        Addiupc { rs, off } => ri(K::Li, rs, 0, pc.wrapping_add(off as u32)),
        // A load from a constant address: base `$0`.
        Lwpc { rs, off } => ri(K::Lw, rs, 0, pc.wrapping_add(off as u32)),
        Auipc { rs, imm } => ri(K::Li, rs, 0, pc.wrapping_add((imm as u32) << 16)),
        Aluipc { rs, imm } => ri(K::Li, rs, 0, pc.wrapping_add((imm as u32) << 16) & !0xFFFF),
        Lb { rt, base, off } => ri(K::Lb, rt, base, sx(off)),
        Lbu { rt, base, off } => ri(K::Lbu, rt, base, sx(off)),
        Lh { rt, base, off } => ri(K::Lh, rt, base, sx(off)),
        Lhu { rt, base, off } => ri(K::Lhu, rt, base, sx(off)),
        Lw { rt, base, off } => ri(K::Lw, rt, base, sx(off)),
        Sb { rt, base, off } => ri(K::Sb, rt, base, sx(off)),
        Sh { rt, base, off } => ri(K::Sh, rt, base, sx(off)),
        Sw { rt, base, off } => ri(K::Sw, rt, base, sx(off)),
        Lwc1 { ft, base, off } => fm(K::Lwc1, ft, base, off),
        Swc1 { ft, base, off } => fm(K::Swc1, ft, base, off),
        Ldc1 { ft, base, off } => fm(K::Ldc1, ft, base, off),
        Sdc1 { ft, base, off } => fm(K::Sdc1, ft, base, off),
        Pref { .. } | Sync { .. } | Synci { .. } => Uop::new(K::Nop, 0, 0, 0, 0),
        Teq { rs, rt, .. } => r3(K::Teq, 0, rs, rt),
        Tne { rs, rt, .. } => r3(K::Tne, 0, rs, rt),
        Tge { rs, rt, .. } => r3(K::Tge, 0, rs, rt),
        Tgeu { rs, rt, .. } => r3(K::Tgeu, 0, rs, rt),
        Tlt { rs, rt, .. } => r3(K::Tlt, 0, rs, rt),
        Tltu { rs, rt, .. } => r3(K::Tltu, 0, rs, rt),
        Beq { rs, rt, off } => Uop::new(K::Beq, 0, g(rs), g(rt), rel(off)),
        Bne { rs, rt, off } => Uop::new(K::Bne, 0, g(rs), g(rt), rel(off)),
        Blez { rs, off } => ri(K::Blez, 0, rs, rel(off)),
        Bgtz { rs, off } => ri(K::Bgtz, 0, rs, rel(off)),
        Bltz { rs, off } => ri(K::Bltz, 0, rs, rel(off)),
        Bgez { rs, off } => ri(K::Bgez, 0, rs, rel(off)),
        Bal { off } => ri(K::Bal, 0, 0, rel(off)),
        J { target } => ri(K::J, 0, 0, Inst::region_target(pc, target)),
        Jal { target } => ri(K::Jal, 0, 0, Inst::region_target(pc, target)),
        Jalr { rd, rs, .. } => ri(K::Jalr, rd, rs, 0),
        Bc1eqz { ft, off } => Uop::new(K::Bc1eqz, 0, f(ft), 0, rel(off)),
        Bc1nez { ft, off } => Uop::new(K::Bc1nez, 0, f(ft), 0, rel(off)),
        Bc { off } => ri(K::Bc, 0, 0, rel(off)),
        Balc { off } => ri(K::Balc, 0, 0, rel(off)),
        Beqc { rs, rt, off } => Uop::new(K::Beqc, 0, g(rs), g(rt), rel(off)),
        Bnec { rs, rt, off } => Uop::new(K::Bnec, 0, g(rs), g(rt), rel(off)),
        Bltc { rs, rt, off } => Uop::new(K::Bltc, 0, g(rs), g(rt), rel(off)),
        Bgec { rs, rt, off } => Uop::new(K::Bgec, 0, g(rs), g(rt), rel(off)),
        Bltuc { rs, rt, off } => Uop::new(K::Bltuc, 0, g(rs), g(rt), rel(off)),
        Bgeuc { rs, rt, off } => Uop::new(K::Bgeuc, 0, g(rs), g(rt), rel(off)),
        Bovc { rs, rt, off } => Uop::new(K::Bovc, 0, g(rs), g(rt), rel(off)),
        Bnvc { rs, rt, off } => Uop::new(K::Bnvc, 0, g(rs), g(rt), rel(off)),
        Beqzc { rs, off } => ri(K::Beqzc, 0, rs, rel(off)),
        Bnezc { rs, off } => ri(K::Bnezc, 0, rs, rel(off)),
        Blezc { rt, off } => ri(K::Blezc, 0, rt, rel(off)),
        Bgezc { rt, off } => ri(K::Bgezc, 0, rt, rel(off)),
        Bgtzc { rt, off } => ri(K::Bgtzc, 0, rt, rel(off)),
        Bltzc { rt, off } => ri(K::Bltzc, 0, rt, rel(off)),
        Blezalc { rt, off } => ri(K::Blezalc, 0, rt, rel(off)),
        Bgezalc { rt, off } => ri(K::Bgezalc, 0, rt, rel(off)),
        Bgtzalc { rt, off } => ri(K::Bgtzalc, 0, rt, rel(off)),
        Bltzalc { rt, off } => ri(K::Bltzalc, 0, rt, rel(off)),
        Beqzalc { rt, off } => ri(K::Beqzalc, 0, rt, rel(off)),
        Bnezalc { rt, off } => ri(K::Bnezalc, 0, rt, rel(off)),
        Jic { rt, off } => ri(K::Jic, 0, rt, sx(off)),
        Jialc { rt, off } => ri(K::Jialc, 0, rt, sx(off)),
        AddS(f) => f3(K::AddS, f),
        SubS(f) => f3(K::SubS, f),
        MulS(f) => f3(K::MulS, f),
        DivS(f) => f3(K::DivS, f),
        AddD(f) => f3(K::AddD, f),
        SubD(f) => f3(K::SubD, f),
        MulD(f) => f3(K::MulD, f),
        DivD(f) => f3(K::DivD, f),
        SqrtS(f) => f2(K::SqrtS, f),
        SqrtD(f) => f2(K::SqrtD, f),
        MaddfS(f) => f3(K::MaddfS, f),
        MsubfS(f) => f3(K::MsubfS, f),
        MaddfD(f) => f3(K::MaddfD, f),
        MsubfD(f) => f3(K::MsubfD, f),
        AbsS(f) => f2(K::AbsS, f),
        AbsD(f) => f2(K::AbsD, f),
        NegS(f) => f2(K::NegS, f),
        NegD(f) => f2(K::NegD, f),
        MovS(f) => f2(K::MovS, f),
        MovD(f) => f2(K::MovD, f),
        SelS(f) => f3(K::SelS, f),
        SelD(f) => f3(K::SelD, f),
        SeleqzS(f) => f3(K::SeleqzS, f),
        SeleqzD(f) => f3(K::SeleqzD, f),
        SelnezS(f) => f3(K::SelnezS, f),
        SelnezD(f) => f3(K::SelnezD, f),
        MinS(f) => f3(K::MinS, f),
        MaxS(f) => f3(K::MaxS, f),
        MinaS(f) => f3(K::MinaS, f),
        MaxaS(f) => f3(K::MaxaS, f),
        MinD(f) => f3(K::MinD, f),
        MaxD(f) => f3(K::MaxD, f),
        MinaD(f) => f3(K::MinaD, f),
        MaxaD(f) => f3(K::MaxaD, f),
        CmpS { cond, f: x } => {
            // Without a NaN, `rel` is LT, EQ or neither; bit 4 negates.
            let k = match cond & !8 {
                4 | 5 => K::CmpLtS,
                6 | 7 => K::CmpLeS,
                2 | 3 => K::CmpEqS,
                _ => K::CmpS,
            };
            Uop::new(k, f(x.fd), f(x.fs), f(x.ft), cond as u32)
        }
        CmpD { cond, f: x } => Uop::new(K::CmpD, f(x.fd), f(x.fs), f(x.ft), cond as u32),
        Cvt { op, f: x } => match CONVS.iter().position(|&c| c == op) {
            Some(i) => Uop::new(K::Cvt, f(x.fd), f(x.fs), 0, i as u32),
            None => Uop::COMPLEX,
        },
        Mfc1 { rt, fs } => Uop::new(K::Mfc1, g(rt), f(fs), 0, 0),
        Mtc1 { rt, fs } => Uop::new(K::Mtc1, f(fs), g(rt), 0, 0),
        Mfhc1 { rt, fs } => Uop::new(K::Mfhc1, g(rt), f(fs), 0, 0),
        Mthc1 { rt, fs } => Uop::new(K::Mthc1, f(fs), g(rt), 0, 0),
        Mfc2 { rt, rd, .. } => ri(K::Mfc2, rt, rd, 0),
        Mtc2 { rt, rd, .. } => ri(K::Mtc2, rd, rt, 0),
        Trax {
            op: TraxOp::FMin,
            rd,
            rs,
            rt,
            ..
        } => Uop::new(K::FMin, f(rd), f(rs), f(rt), 0),
        Trax {
            op: TraxOp::FMax,
            rd,
            rs,
            rt,
            ..
        } => Uop::new(K::FMax, f(rd), f(rs), f(rt), 0),
        Trax {
            op: TraxOp::InvSqrt,
            rd,
            rs,
            ..
        } => Uop::new(K::InvSqrt, f(rd), f(rs), 0, 0),
        // Ids, the clock, global registers, prints, streams, pipelines, halt; MSA; the
        // link of `ll`/`sc`; FCSR; `rdhwr` (may need the exact retired count); the rest
        // fault.
        Trax { .. }
        | Msa(_)
        | Ll { .. }
        | Sc { .. }
        | Rdhwr { .. }
        | Cfc1 { .. }
        | Ctc1 { .. }
        | RecipS(_)
        | RecipD(_)
        | RsqrtS(_)
        | RsqrtD(_)
        | RintS(_)
        | RintD(_)
        | ClassS(_)
        | ClassD(_)
        | Sigrie { .. }
        | Syscall { .. }
        | Break { .. }
        | Sdbbp { .. }
        | Reserved(_) => Uop::COMPLEX,
    }
}

/// The mask of an `ext`/`ins` field of `size` bits.
fn field_mask(size: u8) -> u32 {
    if size >= 32 {
        u32::MAX
    } else {
        (1u32 << size) - 1
    }
}

/// Translates the predecoded text at `base`: one uop per instruction, and per word the
/// length of the block starting there (0 where the word is `Complex`). A block ends with
/// a compact branch, a branch with a delay slot and its slot, or before a `Complex` word.
pub(crate) fn translate(insts: &[Inst], base: u32) -> (Vec<Uop>, Vec<u16>) {
    let mut uops: Vec<Uop> = insts
        .iter()
        .enumerate()
        .map(|(i, inst)| {
            let pc = base.wrapping_add(4 * i as u32);
            let u = uop(inst, pc);
            // A branch that may sit in a slot is the reference's (it checks).
            let may_be_in_slot =
                i == 0 || matches!(insts[i - 1].cti(), Cti::DelaySlot | Cti::CompactBranch);
            if u.k.kind() != Kind::Plain && may_be_in_slot {
                return Uop::COMPLEX;
            }
            // `$0` is never written: a pure write there is a no-op, the rest is the
            // reference's.
            if u.a == 0 && u.k.pure_gpr() {
                return Uop::new(K::Nop, 0, 0, 0, 0);
            }
            if u.a == 0 && u.k.faulting_gpr() {
                return Uop::COMPLEX;
            }
            u
        })
        .collect();
    // A branch whose delay slot the engine does not run (or that ends the text) is the
    // reference's: a completed block then always ends outside a delay slot.
    for i in 0..uops.len() {
        let slot_fast = uops
            .get(i + 1)
            .is_some_and(|u| u.k != K::Complex && u.k.kind() == Kind::Plain);
        if uops[i].k.kind() == Kind::Delay && !slot_fast {
            uops[i] = Uop::COMPLEX;
        }
    }
    let mut runs = vec![0u16; uops.len()];
    for i in (0..uops.len()).rev() {
        let next_fast = uops.get(i + 1).is_some_and(|u| u.k != K::Complex);
        runs[i] = match uops[i].k {
            K::Complex => 0,
            k => match k.kind() {
                Kind::Plain if next_fast => (runs[i + 1] as usize + 1).min(MAX_RUN) as u16,
                Kind::Plain => 1,
                Kind::Delay => 2,
                Kind::Compact => 1,
            },
        };
    }
    (uops, runs)
}

/// FCSR's Cause and Flags fields while the engine runs: `cause` the last FPU operation's
/// exceptions, `flags` those raised since the last [`FastFp::store`]. Loaded from FCSR and
/// stored back around everything else that reads or writes FCSR, so an operation costs a
/// register write and an OR (the reference's `FpPending` also marks itself dirty).
#[derive(Clone, Copy)]
struct FastFp {
    cause: u32,
    flags: u32,
}

impl FastFp {
    #[inline(always)]
    fn load(fcsr: u32) -> FastFp {
        FastFp {
            cause: (fcsr >> 12) & 0x3F,
            flags: 0,
        }
    }

    /// Records an operation that raised `exc`.
    #[inline(always)]
    fn record(&mut self, exc: u32) {
        self.cause = exc;
        self.flags |= exc;
    }

    /// Writes the fields into `fcsr` (then this still describes it).
    #[inline(always)]
    fn store(&mut self, fcsr: &mut u32) {
        *fcsr = (*fcsr & !(0x3F << 12)) | (self.cause << 12) | (self.flags << 2);
        self.flags = 0;
    }
}

/// How a block run ended: the uops executed and where control goes after the block.
struct Ran {
    done: usize,
    target: u32,
}

impl Thread {
    /// Runs up to `budget` instructions: blocks of uops where it can, the reference
    /// interpreter for one instruction where it cannot (see the module documentation).
    ///
    /// From one completed block to the next the pc stays in a register; the thread's pc,
    /// npc and retired count are written when the reference runs an instruction and when
    /// the call returns.
    pub(crate) fn run_blocks<C: Chip>(&mut self, sh: &mut C, budget: u64) -> crate::exec::Stop {
        use crate::exec::Stop;
        let prog = &sh.shared().program;
        let base = prog.base;
        let (uops, runs) = (prog.uops.as_ptr(), prog.runs.as_ptr());
        let n = prog.uops.len();
        let mut fp = FastFp::load(self.regs.fcsr);
        let mut left = budget;
        // Retired since `self.retired` was last written.
        let mut ran = 0u64;
        let (mut pc, mut npc) = (self.pc, self.npc);
        // Whether the next instruction is the reference's whatever its uop: in a delay
        // slot, after a bail, or while FCSR enables an exception or rounds otherwise than
        // to nearest.
        let fp_ok = |fcsr: u32| fcsr & (FCSR_ENABLES | FCSR_RM) == 0;
        let mut slow = !fp_ok(self.regs.fcsr) || npc != pc.wrapping_add(4);
        while left > 0 {
            let idx = pc.wrapping_sub(base).rotate_right(2) as usize;
            let len = if idx < n && !slow {
                // SAFETY: `idx < n`, the length of `runs` (one entry per uop). The
                // program is never written while a thread runs: see `run_block`.
                unsafe { *runs.add(idx) as usize }
            } else {
                0
            };
            if len == 0 {
                fp.store(&mut self.regs.fcsr);
                self.retired += std::mem::take(&mut ran);
                (self.pc, self.npc) = (pc, npc);
                let stop = self.step_once(sh);
                if stop != Stop::Budget {
                    return stop;
                }
                left -= 1;
                (pc, npc) = (self.pc, self.npc);
                fp = FastFp::load(self.regs.fcsr);
                slow = !fp_ok(self.regs.fcsr) || npc != pc.wrapping_add(4);
                continue;
            }
            let cnt = (len as u64).min(left) as usize;
            // SAFETY: `idx + len <= n` (a block never runs past the text), and
            // `cnt <= len`.
            let r = unsafe { self.run_block(sh, uops.add(idx), cnt, len, pc, &mut fp) };
            let k = r.done;
            ran += k as u64;
            left -= k as u64;
            if k == len {
                // Completed: never in a delay slot (see `translate`).
                pc = r.target;
                npc = pc.wrapping_add(4);
                continue;
            }
            // Cut by the budget, or a bail (the reference runs that instruction next).
            slow = k < cnt;
            let at = pc.wrapping_add(4 * k as u32);
            // SAFETY: `k >= 1` here, so `idx + k - 1 < idx + len <= n`.
            let after_delay = k > 0 && unsafe { (*uops.add(idx + k - 1)).k.kind() } == Kind::Delay;
            (pc, npc) = if after_delay {
                // In the delay slot: it runs next, then the branch's target.
                (at, r.target)
            } else {
                (at, at.wrapping_add(4))
            };
            slow |= after_delay;
        }
        fp.store(&mut self.regs.fcsr);
        self.retired += ran;
        (self.pc, self.npc) = (pc, npc);
        Stop::Budget
    }

    /// Runs up to `cnt` uops from `ops`, the block of `len` uops at `bpc`, with FCSR
    /// rounding to nearest and enabling no exception. Stops early at a uop that bails (not
    /// executed).
    ///
    /// # Safety
    /// `ops` points at `len >= cnt` consecutive uops of the chip's `Shared::program`.
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    unsafe fn run_block<C: Chip>(
        &mut self,
        sh: &mut C,
        ops: *const crate::block::Uop,
        cnt: usize,
        len: usize,
        bpc: u32,
        fp: &mut FastFp,
    ) -> Ran {
        // FCSR's rounding mode: to nearest.
        const RM: u32 = 0;
        let mut target = bpc.wrapping_add(4 * len as u32);
        // SAFETY: `cnt <= len`: one past the last uop to run at most.
        let end = unsafe { ops.add(cnt) };
        let mut at = ops;
        while at < end {
            // SAFETY: `ops <= at < end`, inside the uops (the caller's contract). They are
            // owned by the chip's `Shared::program`, which no uop writes (through any
            // `Chip` view they touch memory, prints/counters and TRaX state only), so they
            // stay allocated and unchanged while `sh` is borrowed mutably here.
            let u = unsafe { &*at };
            // Computed where needed only: most uops need neither.
            macro_rules! k {
                () => {
                    // SAFETY: `at` and `ops` point into the same uops, `at >= ops`.
                    unsafe { at.offset_from(ops) as usize }
                };
            }
            macro_rules! pc {
                () => {
                    bpc.wrapping_add(4 * k!() as u32)
                };
            }
            macro_rules! bail {
                () => {
                    return Ran { done: k!(), target }
                };
            }
            macro_rules! g {
                ($r:expr) => {
                    self.regs.gpr[($r & 31) as usize]
                };
            }
            macro_rules! ea {
                () => {
                    g!(u.b).wrapping_add(u.imm)
                };
            }
            macro_rules! load {
                ($n:literal) => {{
                    let a = ea!();
                    match sh.shared().mem.read::<$n>(&self.local, a) {
                        Ok(b) => {
                            sh.note_load(a);
                            b
                        }
                        Err(_) => bail!(),
                    }
                }};
            }
            macro_rules! store {
                ($v:expr) => {{
                    let v = $v;
                    match sh.store(&mut self.local, ea!(), v) {
                        Ok(true) => {}
                        // Refused or faulting: nothing was written.
                        _ => bail!(),
                    }
                }};
            }
            macro_rules! fs32 {
                ($f:expr) => {
                    f32_of(&self.regs, $f)
                };
            }
            macro_rules! fs64 {
                ($f:expr) => {
                    f64_of(&self.regs, $f)
                };
            }
            macro_rules! set32 {
                ($f:expr, $v:expr) => {{
                    let v = $v;
                    set_f32_of(&mut self.regs, $f, v)
                }};
            }
            macro_rules! set64 {
                ($f:expr, $v:expr) => {{
                    let v = $v;
                    set_f64_of(&mut self.regs, $f, v)
                }};
            }
            // A delay-slot branch: the slot runs next, then `target`.
            macro_rules! delay {
                ($cond:expr) => {{
                    self.slot_pc = pc!().wrapping_add(4);
                    target = if $cond { u.imm } else { pc!().wrapping_add(8) };
                }};
            }
            // A compact branch: not taken, the next word is a forbidden slot.
            macro_rules! compact {
                ($cond:expr) => {{
                    if $cond {
                        target = u.imm;
                    } else {
                        self.slot_pc = pc!().wrapping_add(4);
                        target = pc!().wrapping_add(4);
                    }
                }};
            }
            // A compact conditional call: links whether or not taken.
            macro_rules! compact_call {
                ($cond:expr) => {{
                    let cond = $cond;
                    g!(31) = pc!().wrapping_add(4);
                    if cond {
                        self.push_call(pc!(), pc!().wrapping_add(4), u.imm);
                    }
                    compact!(cond);
                }};
            }
            macro_rules! arith_s {
                ($op:expr, $acc:expr) => {{
                    let c = if $acc { fs32!(u.a) as u64 } else { 0 };
                    let (v, e) =
                        sf::arith($op, Fmt::S, fs32!(u.b) as u64, fs32!(u.c) as u64, c, RM);
                    fp.record(e);
                    set32!(u.a, v as u32);
                }};
            }
            macro_rules! arith_d {
                ($op:expr, $acc:expr) => {{
                    let c = if $acc { fs64!(u.a) } else { 0 };
                    let (v, e) = sf::arith($op, Fmt::D, fs64!(u.b), fs64!(u.c), c, RM);
                    fp.record(e);
                    set64!(u.a, v);
                }};
            }
            macro_rules! minmax_s {
                ($kind:expr) => {{
                    let (v, e) =
                        fp_min_max(Fmt::S, $kind, fs32!(u.b) as u64, fs32!(u.c) as u64, RM);
                    fp.record(e);
                    set32!(u.a, v as u32);
                }};
            }
            macro_rules! minmax_d {
                ($kind:expr) => {{
                    let (v, e) = fp_min_max(Fmt::D, $kind, fs64!(u.b), fs64!(u.c), RM);
                    fp.record(e);
                    set64!(u.a, v);
                }};
            }
            // A specialised `cmp.cond.s`: `$rel` for numbers (no exception), the general
            // compare for a NaN.
            macro_rules! cmp_s {
                (|$x:ident, $y:ident| $rel:expr) => {{
                    let (a, b) = (fs32!(u.b), fs32!(u.c));
                    let ($x, $y) = (f32::from_bits(a), f32::from_bits(b));
                    let v = if $x.is_nan() | $y.is_nan() {
                        let (v, e) = fp_compare(Fmt::S, u.imm as u8, a as u64, b as u64, RM);
                        fp.record(e);
                        v as u32
                    } else {
                        fp.record(0);
                        ($rel as u32).wrapping_neg()
                    };
                    set32!(u.a, v);
                }};
            }
            match u.k {
                K::Complex => bail!(),
                K::Nop => {}
                K::Li => g!(u.a) = u.imm,
                K::AddImm => g!(u.a) = g!(u.b).wrapping_add(u.imm),
                K::Slti => g!(u.a) = ((g!(u.b) as i32) < u.imm as i32) as u32,
                K::Sltiu => g!(u.a) = (g!(u.b) < u.imm) as u32,
                K::Andi => g!(u.a) = g!(u.b) & u.imm,
                K::Ori => g!(u.a) = g!(u.b) | u.imm,
                K::Xori => g!(u.a) = g!(u.b) ^ u.imm,
                K::Addu => g!(u.a) = g!(u.b).wrapping_add(g!(u.c)),
                K::Subu => g!(u.a) = g!(u.b).wrapping_sub(g!(u.c)),
                K::Add => match (g!(u.b) as i32).checked_add(g!(u.c) as i32) {
                    Some(v) => g!(u.a) = v as u32,
                    None => bail!(),
                },
                K::Sub => match (g!(u.b) as i32).checked_sub(g!(u.c) as i32) {
                    Some(v) => g!(u.a) = v as u32,
                    None => bail!(),
                },
                K::And => g!(u.a) = g!(u.b) & g!(u.c),
                K::Or => g!(u.a) = g!(u.b) | g!(u.c),
                K::Xor => g!(u.a) = g!(u.b) ^ g!(u.c),
                K::Nor => g!(u.a) = !(g!(u.b) | g!(u.c)),
                K::Slt => g!(u.a) = ((g!(u.b) as i32) < (g!(u.c) as i32)) as u32,
                K::Sltu => g!(u.a) = (g!(u.b) < g!(u.c)) as u32,
                K::Mul => g!(u.a) = g!(u.b).wrapping_mul(g!(u.c)),
                K::Muh => g!(u.a) = ((g!(u.b) as i32 as i64 * g!(u.c) as i32 as i64) >> 32) as u32,
                K::Muhu => g!(u.a) = ((g!(u.b) as u64 * g!(u.c) as u64) >> 32) as u32,
                K::Div => {
                    let (a, b) = (g!(u.b) as i32, g!(u.c) as i32);
                    g!(u.a) = if b == 0 {
                        a as u32
                    } else {
                        a.wrapping_div(b) as u32
                    };
                }
                K::Mod => {
                    let (a, b) = (g!(u.b) as i32, g!(u.c) as i32);
                    g!(u.a) = if b == 0 { 0 } else { a.wrapping_rem(b) as u32 };
                }
                K::Divu => {
                    let (a, b) = (g!(u.b), g!(u.c));
                    g!(u.a) = a.checked_div(b).unwrap_or(a);
                }
                K::Modu => {
                    let (a, b) = (g!(u.b), g!(u.c));
                    g!(u.a) = a.checked_rem(b).unwrap_or(0);
                }
                K::Seleqz => g!(u.a) = if g!(u.c) == 0 { g!(u.b) } else { 0 },
                K::Selnez => g!(u.a) = if g!(u.c) != 0 { g!(u.b) } else { 0 },
                K::Sllv => g!(u.a) = g!(u.b) << (g!(u.c) & 31),
                K::Srlv => g!(u.a) = g!(u.b) >> (g!(u.c) & 31),
                K::Srav => g!(u.a) = ((g!(u.b) as i32) >> (g!(u.c) & 31)) as u32,
                K::Rotrv => g!(u.a) = g!(u.b).rotate_right(g!(u.c) & 31),
                K::Sll => g!(u.a) = g!(u.b) << (u.imm & 31),
                K::Srl => g!(u.a) = g!(u.b) >> (u.imm & 31),
                K::Sra => g!(u.a) = ((g!(u.b) as i32) >> (u.imm & 31)) as u32,
                K::Rotr => g!(u.a) = g!(u.b).rotate_right(u.imm & 31),
                K::Lsa => g!(u.a) = (g!(u.b) << (u.imm & 7)).wrapping_add(g!(u.c)),
                K::Clz => g!(u.a) = g!(u.b).leading_zeros(),
                K::Clo => g!(u.a) = g!(u.b).leading_ones(),
                K::Align => {
                    let bp = u.imm & 3;
                    g!(u.a) = if bp == 0 {
                        g!(u.c)
                    } else {
                        (g!(u.c) << (8 * bp)) | (g!(u.b) >> (32 - 8 * bp))
                    };
                }
                K::Bitswap => {
                    let b = g!(u.b).to_le_bytes().map(u8::reverse_bits);
                    g!(u.a) = u32::from_le_bytes(b);
                }
                K::Wsbh => {
                    let v = g!(u.b);
                    g!(u.a) = ((v & 0x00FF_00FF) << 8) | ((v >> 8) & 0x00FF_00FF);
                }
                K::Seb => g!(u.a) = g!(u.b) as i8 as i32 as u32,
                K::Seh => g!(u.a) = g!(u.b) as i16 as i32 as u32,
                K::Ext => g!(u.a) = (g!(u.b) >> (u.c & 31)) & u.imm,
                K::Ins => {
                    let p = (u.c & 31) as u32;
                    g!(u.a) = (g!(u.a) & !(u.imm << p)) | ((g!(u.b) & u.imm) << p);
                }
                K::Lb => g!(u.a) = load!(1)[0] as i8 as i32 as u32,
                K::Lbu => g!(u.a) = load!(1)[0] as u32,
                K::Lh => g!(u.a) = i16::from_le_bytes(load!(2)) as i32 as u32,
                K::Lhu => g!(u.a) = u16::from_le_bytes(load!(2)) as u32,
                K::Lw => g!(u.a) = u32::from_le_bytes(load!(4)),
                K::Sb => store!([g!(u.a) as u8]),
                K::Sh => store!((g!(u.a) as u16).to_le_bytes()),
                K::Sw => store!(g!(u.a).to_le_bytes()),
                K::Lwc1 => {
                    let v = u32::from_le_bytes(load!(4));
                    set32!(u.a, v);
                }
                K::Swc1 => store!(fs32!(u.a).to_le_bytes()),
                K::Ldc1 => {
                    let v = u64::from_le_bytes(load!(8));
                    set64!(u.a, v);
                }
                K::Sdc1 => store!(fs64!(u.a).to_le_bytes()),
                K::Teq => {
                    if g!(u.b) == g!(u.c) {
                        bail!()
                    }
                }
                K::Tne => {
                    if g!(u.b) != g!(u.c) {
                        bail!()
                    }
                }
                K::Tge => {
                    if g!(u.b) as i32 >= g!(u.c) as i32 {
                        bail!()
                    }
                }
                K::Tgeu => {
                    if g!(u.b) >= g!(u.c) {
                        bail!()
                    }
                }
                K::Tlt => {
                    if (g!(u.b) as i32) < g!(u.c) as i32 {
                        bail!()
                    }
                }
                K::Tltu => {
                    if g!(u.b) < g!(u.c) {
                        bail!()
                    }
                }
                K::Beq => delay!(g!(u.b) == g!(u.c)),
                K::Bne => delay!(g!(u.b) != g!(u.c)),
                K::Blez => delay!((g!(u.b) as i32) <= 0),
                K::Bgtz => delay!((g!(u.b) as i32) > 0),
                K::Bltz => delay!((g!(u.b) as i32) < 0),
                K::Bgez => delay!((g!(u.b) as i32) >= 0),
                K::Bc1eqz => delay!(fs64!(u.b) & 1 == 0),
                K::Bc1nez => delay!(fs64!(u.b) & 1 != 0),
                K::Bal => {
                    delay!(true);
                    g!(31) = pc!().wrapping_add(8);
                    self.push_call(pc!(), pc!().wrapping_add(8), u.imm);
                }
                K::J => {
                    delay!(true);
                    self.note_jump(u.imm);
                }
                K::Jal => {
                    delay!(true);
                    g!(31) = pc!().wrapping_add(8);
                    self.push_call(pc!(), pc!().wrapping_add(8), u.imm);
                }
                K::Jalr => {
                    let t = g!(u.b);
                    self.slot_pc = pc!().wrapping_add(4);
                    target = t;
                    if u.a != 0 {
                        g!(u.a) = pc!().wrapping_add(8);
                        self.push_call(pc!(), pc!().wrapping_add(8), t);
                    } else {
                        self.note_jump(t);
                    }
                }
                K::Bc => target = u.imm,
                K::Balc => {
                    g!(31) = pc!().wrapping_add(4);
                    self.push_call(pc!(), pc!().wrapping_add(4), u.imm);
                    target = u.imm;
                }
                K::Beqc => compact!(g!(u.b) == g!(u.c)),
                K::Bnec => compact!(g!(u.b) != g!(u.c)),
                K::Bltc => compact!((g!(u.b) as i32) < (g!(u.c) as i32)),
                K::Bgec => compact!((g!(u.b) as i32) >= (g!(u.c) as i32)),
                K::Bltuc => compact!(g!(u.b) < g!(u.c)),
                K::Bgeuc => compact!(g!(u.b) >= g!(u.c)),
                K::Bovc => compact!((g!(u.b) as i32).checked_add(g!(u.c) as i32).is_none()),
                K::Bnvc => compact!((g!(u.b) as i32).checked_add(g!(u.c) as i32).is_some()),
                K::Beqzc => compact!(g!(u.b) == 0),
                K::Bnezc => compact!(g!(u.b) != 0),
                K::Blezc => compact!((g!(u.b) as i32) <= 0),
                K::Bgezc => compact!((g!(u.b) as i32) >= 0),
                K::Bgtzc => compact!((g!(u.b) as i32) > 0),
                K::Bltzc => compact!((g!(u.b) as i32) < 0),
                K::Blezalc => compact_call!((g!(u.b) as i32) <= 0),
                K::Bgezalc => compact_call!((g!(u.b) as i32) >= 0),
                K::Bgtzalc => compact_call!((g!(u.b) as i32) > 0),
                K::Bltzalc => compact_call!((g!(u.b) as i32) < 0),
                K::Beqzalc => compact_call!(g!(u.b) == 0),
                K::Bnezalc => compact_call!(g!(u.b) != 0),
                K::Jic => {
                    let t = g!(u.b).wrapping_add(u.imm);
                    self.note_jump(t);
                    target = t;
                }
                K::Jialc => {
                    let t = g!(u.b).wrapping_add(u.imm);
                    g!(31) = pc!().wrapping_add(4);
                    self.push_call(pc!(), pc!().wrapping_add(4), t);
                    target = t;
                }
                K::AddS => arith_s!(Arith::Add, false),
                K::SubS => arith_s!(Arith::Sub, false),
                K::MulS => arith_s!(Arith::Mul, false),
                K::DivS => arith_s!(Arith::Div, false),
                K::SqrtS => arith_s!(Arith::Sqrt, false),
                K::AddD => arith_d!(Arith::Add, false),
                K::SubD => arith_d!(Arith::Sub, false),
                K::MulD => arith_d!(Arith::Mul, false),
                K::DivD => arith_d!(Arith::Div, false),
                K::SqrtD => arith_d!(Arith::Sqrt, false),
                K::MaddfS => arith_s!(Arith::Madd, true),
                K::MsubfS => arith_s!(Arith::Msub, true),
                K::MaddfD => arith_d!(Arith::Madd, true),
                K::MsubfD => arith_d!(Arith::Msub, true),
                K::AbsS => set32!(u.a, fs32!(u.b) & 0x7FFF_FFFF),
                K::AbsD => set64!(u.a, fs64!(u.b) & !(1 << 63)),
                K::NegS => set32!(u.a, fs32!(u.b) ^ 0x8000_0000),
                K::NegD => set64!(u.a, fs64!(u.b) ^ (1 << 63)),
                K::MovS => set32!(u.a, fs32!(u.b)),
                K::MovD => set64!(u.a, fs64!(u.b)),
                K::SelS => {
                    let m = (fs32!(u.a) & 1).wrapping_neg();
                    set32!(u.a, (fs32!(u.c) & m) | (fs32!(u.b) & !m));
                }
                K::SelD => {
                    let m = (fs64!(u.a) & 1).wrapping_neg();
                    set64!(u.a, (fs64!(u.c) & m) | (fs64!(u.b) & !m));
                }
                K::SeleqzS => set32!(u.a, fs32!(u.b) & (fs32!(u.c) & 1).wrapping_sub(1)),
                K::SeleqzD => set64!(u.a, fs64!(u.b) & (fs64!(u.c) & 1).wrapping_sub(1)),
                K::SelnezS => set32!(u.a, fs32!(u.b) & (fs32!(u.c) & 1).wrapping_neg()),
                K::SelnezD => set64!(u.a, fs64!(u.b) & (fs64!(u.c) & 1).wrapping_neg()),
                K::MinS => minmax_s!(MinMax::Min),
                K::MaxS => minmax_s!(MinMax::Max),
                K::MinaS => minmax_s!(MinMax::MinA),
                K::MaxaS => minmax_s!(MinMax::MaxA),
                K::MinD => minmax_d!(MinMax::Min),
                K::MaxD => minmax_d!(MinMax::Max),
                K::MinaD => minmax_d!(MinMax::MinA),
                K::MaxaD => minmax_d!(MinMax::MaxA),
                K::CmpS => {
                    let (v, e) = fp_compare(
                        Fmt::S,
                        u.imm as u8,
                        fs32!(u.b) as u64,
                        fs32!(u.c) as u64,
                        RM,
                    );
                    fp.record(e);
                    set32!(u.a, v as u32);
                }
                K::CmpLtS => cmp_s!(|x, y| x < y),
                K::CmpLeS => cmp_s!(|x, y| x <= y),
                K::CmpEqS => cmp_s!(|x, y| x == y),
                K::CmpD => {
                    let (v, e) = fp_compare(Fmt::D, u.imm as u8, fs64!(u.b), fs64!(u.c), RM);
                    fp.record(e);
                    set64!(u.a, v);
                }
                K::Cvt => {
                    fp.store(&mut self.regs.fcsr);
                    let r = self.convert(CONVS[u.imm as usize % CONVS.len()], u.a >> 3, u.b >> 3);
                    // No exception is enabled, so a conversion does not trap.
                    debug_assert!(r.is_ok());
                    *fp = FastFp::load(self.regs.fcsr);
                }
                K::Mfc1 => g!(u.a) = fs32!(u.b),
                K::Mtc1 => set32!(u.a, g!(u.b)),
                K::Mfhc1 => g!(u.a) = (fs64!(u.b) >> 32) as u32,
                K::Mthc1 => {
                    let v = (fs64!(u.a) & 0xFFFF_FFFF) | ((g!(u.b) as u64) << 32);
                    set64!(u.a, v);
                }
                K::Mtc2 => self.cop2[(u.a & 31) as usize] = g!(u.b),
                K::Mfc2 => g!(u.a) = self.cop2[(u.b & 31) as usize],
                K::FMin => set32!(u.a, trax_fminmax(false, fs32!(u.b), fs32!(u.c))),
                K::FMax => set32!(u.a, trax_fminmax(true, fs32!(u.b), fs32!(u.c))),
                K::InvSqrt => set32!(u.a, fops::invsqrt(f32::from_bits(fs32!(u.b))).to_bits()),
            }
            // SAFETY: `at < end`, so `at + 1 <= end`.
            at = unsafe { at.add(1) };
        }
        Ran { done: cnt, target }
    }
}

/// Byte offset in `RegFile::fpr` of the FPU register of uop field `f` (`8 n` for register
/// `n`): `16 n`, one scaled index (`RegFile::f32_bits` would mask and shift). Any field
/// (at most [`MAX_FIELD`]: [`Uop::new`]) gives an offset of at most 496, so the 8 bytes
/// there lie inside the 512 of `fpr`.
#[inline(always)]
fn fr(f: u8) -> usize {
    debug_assert!(f <= MAX_FIELD && f.is_multiple_of(8));
    f as usize * 2
}

/// Low 32 bits of the FPU register of field `f` (see [`RegFile::f32_bits`]).
#[inline(always)]
fn f32_of(r: &RegFile, f: u8) -> u32 {
    #[cfg(target_endian = "little")]
    // SAFETY: `fr(f) <= 496` is the offset of one of the 32 16-byte registers of `fpr`; on
    // a little-endian host its first 4 bytes are its low 32 bits, aligned for `u32`.
    unsafe {
        (r.fpr.as_ptr() as *const u8)
            .add(fr(f))
            .cast::<u32>()
            .read()
    }
    #[cfg(not(target_endian = "little"))]
    r.f32_bits(fr(f) / 16)
}

/// Low 64 bits of the FPU register of field `f` (see [`RegFile::f64_bits`]).
#[inline(always)]
fn f64_of(r: &RegFile, f: u8) -> u64 {
    #[cfg(target_endian = "little")]
    // SAFETY: as in `f32_of`, for the first 8 bytes.
    unsafe {
        (r.fpr.as_ptr() as *const u8)
            .add(fr(f))
            .cast::<u64>()
            .read()
    }
    #[cfg(not(target_endian = "little"))]
    r.f64_bits(fr(f) / 16)
}

/// Writes the low 32 bits of the FPU register of field `f` (see
/// [`RegFile::set_f32_bits`]: the rest is kept).
#[inline(always)]
fn set_f32_of(r: &mut RegFile, f: u8, v: u32) {
    #[cfg(target_endian = "little")]
    // SAFETY: as in `f32_of`, through the exclusive borrow.
    unsafe {
        (r.fpr.as_mut_ptr() as *mut u8)
            .add(fr(f))
            .cast::<u32>()
            .write(v)
    }
    #[cfg(not(target_endian = "little"))]
    r.set_f32_bits(fr(f) / 16, v)
}

/// Writes the low 64 bits of the FPU register of field `f`.
#[inline(always)]
fn set_f64_of(r: &mut RegFile, f: u8, v: u64) {
    #[cfg(target_endian = "little")]
    // SAFETY: as in `f32_of`, for the first 8 bytes, through the exclusive borrow.
    unsafe {
        (r.fpr.as_mut_ptr() as *mut u8)
            .add(fr(f))
            .cast::<u64>()
            .write(v)
    }
    #[cfg(not(target_endian = "little"))]
    r.set_f64_bits(fr(f) / 16, v)
}

/// FCSR's Enables field.
const FCSR_ENABLES: u32 = 0x1F << 7;
/// FCSR's rounding-mode field.
const FCSR_RM: u32 = 3;

#[cfg(test)]
mod tests;
