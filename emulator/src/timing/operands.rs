//! What an instruction needs from the timing model: its execution-unit class, the
//! registers it reads and writes, and its memory access.
//!
//! Register numbering of the scoreboard: 0..32 GPRs (`$0` is never pending), 32..64 FPU
//! registers (aliased by the MSA vector registers), 64..96 coprocessor-2 registers.

use crate::decode::Inst;
use trax_runtime::isa::{self, OperandKind, TraxOp, UnitClass};

/// Scoreboard slots per thread.
pub const NUM_SLOTS: usize = 96;
/// Scoreboard slot of FPU register `n`.
pub const FPR: u8 = 32;
/// Scoreboard slot of coprocessor-2 register `n`.
pub const COP2: u8 = 64;

/// A memory access: effective address = `gpr[base] + off` (or `pc + off` when `base` is
/// [`PC_BASE`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MemOp {
    /// Base GPR, or [`PC_BASE`].
    pub base: u8,
    /// Byte offset.
    pub off: i32,
    /// Bytes accessed.
    pub size: u8,
    /// True for stores.
    pub store: bool,
}

/// `MemOp::base` of PC-relative loads.
pub const PC_BASE: u8 = 255;

/// Timing-relevant facts about one decoded instruction.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct OpInfo {
    /// Execution-unit class.
    pub class: UnitClass,
    /// Scoreboard slots read (0 = none).
    pub src: [u8; 4],
    /// Scoreboard slot written (0 = none).
    pub dst: u8,
    /// Memory access, if any (the class is `Memory`, refined to `LocalStore` by address).
    pub mem: Option<MemOp>,
    /// Register-file accesses: the slots read and written other than 0 (for energy).
    pub reg_accesses: u8,
}

fn info(class: UnitClass, src: &[u8], dst: u8) -> OpInfo {
    let mut s = [0u8; 4];
    for (d, v) in s.iter_mut().zip(src) {
        *d = *v;
    }
    OpInfo {
        class,
        src: s,
        dst,
        mem: None,
        reg_accesses: 0,
    }
}

fn load(dst: u8, base: u8, off: i32, size: u8) -> OpInfo {
    OpInfo {
        class: UnitClass::Memory,
        src: [base, 0, 0, 0],
        dst,
        mem: Some(MemOp {
            base,
            off,
            size,
            store: false,
        }),
        reg_accesses: 0,
    }
}

fn store(val: u8, base: u8, off: i32, size: u8) -> OpInfo {
    OpInfo {
        class: UnitClass::Memory,
        src: [base, val, 0, 0],
        dst: 0,
        mem: Some(MemOp {
            base,
            off,
            size,
            store: true,
        }),
        reg_accesses: 0,
    }
}

/// A branch or jump reading `src`, writing its link register if it has one.
fn branch(inst: &Inst, src: &[u8]) -> OpInfo {
    info(UnitClass::Branch, src, inst.link_reg().unwrap_or(0))
}

const fn f(n: u8) -> u8 {
    FPR + (n & 31)
}

/// Classifies one instruction.
pub fn classify(inst: &Inst) -> OpInfo {
    let mut o = classify_operands(inst);
    o.reg_accesses = o.src.iter().filter(|&&r| r != 0).count() as u8 + u8::from(o.dst != 0);
    o
}

/// [`classify`] without `reg_accesses`.
fn classify_operands(inst: &Inst) -> OpInfo {
    use Inst::*;
    use UnitClass as U;
    match *inst {
        Add { rd, rs, rt } | Addu { rd, rs, rt } | Sub { rd, rs, rt } | Subu { rd, rs, rt } => {
            info(U::IntAdd, &[rs, rt], rd)
        }
        Slt { rd, rs, rt } | Sltu { rd, rs, rt } => info(U::IntAdd, &[rs, rt], rd),
        And { rd, rs, rt } | Or { rd, rs, rt } | Xor { rd, rs, rt } | Nor { rd, rs, rt } => {
            info(U::Bitwise, &[rs, rt], rd)
        }
        Seleqz { rd, rs, rt } | Selnez { rd, rs, rt } => info(U::Bitwise, &[rs, rt], rd),
        Mul { rd, rs, rt } | Muh { rd, rs, rt } | Mulu { rd, rs, rt } | Muhu { rd, rs, rt } => {
            info(U::IntMul, &[rs, rt], rd)
        }
        Div { rd, rs, rt } | Mod { rd, rs, rt } | Divu { rd, rs, rt } | Modu { rd, rs, rt } => {
            info(U::IntDiv, &[rs, rt], rd)
        }
        Sllv { rd, rt, rs } | Srlv { rd, rt, rs } | Srav { rd, rt, rs } | Rotrv { rd, rt, rs } => {
            info(U::Bitwise, &[rs, rt], rd)
        }
        Sll { rd, rt, .. } | Srl { rd, rt, .. } | Sra { rd, rt, .. } | Rotr { rd, rt, .. } => {
            info(U::Bitwise, &[rt], rd)
        }
        Lsa { rd, rs, rt, .. } => info(U::IntAdd, &[rs, rt], rd),
        Clz { rd, rs } | Clo { rd, rs } => info(U::Bitwise, &[rs], rd),
        Addiu { rt, rs, .. } | Slti { rt, rs, .. } | Sltiu { rt, rs, .. } | Aui { rt, rs, .. } => {
            info(U::IntAdd, &[rs], rt)
        }
        Andi { rt, rs, .. } | Ori { rt, rs, .. } | Xori { rt, rs, .. } => {
            info(U::Bitwise, &[rs], rt)
        }
        Align { rd, rs, rt, .. } => info(U::Bitwise, &[rs, rt], rd),
        Bitswap { rd, rt } | Wsbh { rd, rt } | Seb { rd, rt } | Seh { rd, rt } => {
            info(U::Bitwise, &[rt], rd)
        }
        Ext { rt, rs, .. } => info(U::Bitwise, &[rs], rt),
        Ins { rt, rs, .. } => info(U::Bitwise, &[rs, rt], rt),
        Addiupc { rs, .. } | Auipc { rs, .. } | Aluipc { rs, .. } => info(U::IntAdd, &[], rs),
        Lwpc { rs, off } => load(rs, PC_BASE, off, 4),
        Lb { rt, base, off } | Lbu { rt, base, off } => load(rt, base, off.into(), 1),
        Lh { rt, base, off } | Lhu { rt, base, off } => load(rt, base, off.into(), 2),
        Lw { rt, base, off } | Ll { rt, base, off } => load(rt, base, off.into(), 4),
        Sb { rt, base, off } => store(rt, base, off.into(), 1),
        Sh { rt, base, off } => store(rt, base, off.into(), 2),
        Sw { rt, base, off } => store(rt, base, off.into(), 4),
        Sc { rt, base, off } => {
            let mut s = store(rt, base, off.into(), 4);
            s.dst = rt;
            s
        }
        Lwc1 { ft, base, off } => load(f(ft), base, off.into(), 4),
        Ldc1 { ft, base, off } => load(f(ft), base, off.into(), 8),
        Swc1 { ft, base, off } => store(f(ft), base, off.into(), 4),
        Sdc1 { ft, base, off } => store(f(ft), base, off.into(), 8),
        Pref { .. } | Synci { .. } | Sync { .. } => info(U::RegFile, &[], 0),
        Sigrie { .. } | Syscall { .. } | Break { .. } | Sdbbp { .. } | Reserved(_) => {
            info(U::RegFile, &[], 0)
        }
        Teq { rs, rt, .. }
        | Tne { rs, rt, .. }
        | Tge { rs, rt, .. }
        | Tgeu { rs, rt, .. }
        | Tlt { rs, rt, .. }
        | Tltu { rs, rt, .. } => info(U::IntAdd, &[rs, rt], 0),
        Rdhwr { rt, .. } => info(U::RegFile, &[], rt),
        // Branches and jumps: the registers they test; the link register they write is
        // the instruction's own fact (`Inst::link_reg`).
        Bal { .. } | J { .. } | Jal { .. } | Bc { .. } | Balc { .. } => branch(inst, &[]),
        Beq { rs, rt, .. }
        | Bne { rs, rt, .. }
        | Beqc { rs, rt, .. }
        | Bnec { rs, rt, .. }
        | Bltc { rs, rt, .. }
        | Bgec { rs, rt, .. }
        | Bltuc { rs, rt, .. }
        | Bgeuc { rs, rt, .. }
        | Bovc { rs, rt, .. }
        | Bnvc { rs, rt, .. } => branch(inst, &[rs, rt]),
        Blez { rs, .. }
        | Bgtz { rs, .. }
        | Bltz { rs, .. }
        | Bgez { rs, .. }
        | Beqzc { rs, .. }
        | Bnezc { rs, .. }
        | Jalr { rs, .. } => branch(inst, &[rs]),
        Blezc { rt, .. }
        | Bgezc { rt, .. }
        | Bgtzc { rt, .. }
        | Bltzc { rt, .. }
        | Blezalc { rt, .. }
        | Bgezalc { rt, .. }
        | Bgtzalc { rt, .. }
        | Bltzalc { rt, .. }
        | Beqzalc { rt, .. }
        | Bnezalc { rt, .. }
        | Jic { rt, .. }
        | Jialc { rt, .. } => branch(inst, &[rt]),
        Bc1eqz { ft, .. } | Bc1nez { ft, .. } => branch(inst, &[f(ft)]),
        AddS(x) | AddD(x) | SubS(x) | SubD(x) => info(U::FpAdd, &[f(x.fs), f(x.ft)], f(x.fd)),
        MulS(x) | MulD(x) => info(U::FpMul, &[f(x.fs), f(x.ft)], f(x.fd)),
        DivS(x) | DivD(x) => info(U::FpDiv, &[f(x.fs), f(x.ft)], f(x.fd)),
        MaddfS(x) | MaddfD(x) | MsubfS(x) | MsubfD(x) => {
            info(U::FpMul, &[f(x.fs), f(x.ft), f(x.fd)], f(x.fd))
        }
        SqrtS(x) | SqrtD(x) | RsqrtS(x) | RsqrtD(x) => info(U::FpInvSqrt, &[f(x.fs)], f(x.fd)),
        RecipS(x) | RecipD(x) => info(U::FpDiv, &[f(x.fs)], f(x.fd)),
        AbsS(x) | AbsD(x) | NegS(x) | NegD(x) | ClassS(x) | ClassD(x) => {
            info(U::FpCmp, &[f(x.fs)], f(x.fd))
        }
        MovS(x) | MovD(x) => info(U::RegFile, &[f(x.fs)], f(x.fd)),
        RintS(x) | RintD(x) => info(U::Conv, &[f(x.fs)], f(x.fd)),
        SelS(x) | SelD(x) => info(U::Bitwise, &[f(x.fs), f(x.ft), f(x.fd)], f(x.fd)),
        SeleqzS(x) | SeleqzD(x) | SelnezS(x) | SelnezD(x) => {
            info(U::Bitwise, &[f(x.fs), f(x.ft)], f(x.fd))
        }
        MinS(x) | MinD(x) | MaxS(x) | MaxD(x) | MinaS(x) | MinaD(x) | MaxaS(x) | MaxaD(x) => {
            info(U::FpMinMax, &[f(x.fs), f(x.ft)], f(x.fd))
        }
        CmpS { f: x, .. } | CmpD { f: x, .. } => info(U::FpCmp, &[f(x.fs), f(x.ft)], f(x.fd)),
        Cvt { f: x, .. } => info(U::Conv, &[f(x.fs)], f(x.fd)),
        Mfc1 { rt, fs } | Mfhc1 { rt, fs } => info(U::RegFile, &[f(fs)], rt),
        Mtc1 { rt, fs } | Mthc1 { rt, fs } => info(U::RegFile, &[rt, f(fs)], f(fs)),
        Cfc1 { rt, .. } => info(U::RegFile, &[], rt),
        Ctc1 { rt, .. } => info(U::RegFile, &[rt], 0),
        Mfc2 { rt, rd, .. } => info(U::RegFile, &[COP2 + (rd & 31)], rt),
        Mtc2 { rt, rd, .. } => info(U::RegFile, &[rt], COP2 + (rd & 31)),
        Trax { op, rd, rs, rt, .. } => trax(op, rd, rs, rt),
        Msa(m) => msa(&m),
    }
}

fn trax(op: TraxOp, rd: u8, rs: u8, rt: u8) -> OpInfo {
    let row = isa::instr(op);
    let mut src = [0u8; 4];
    let mut n = 0;
    let mut dst = 0;
    for o in row.operands {
        let v = match o.field {
            isa::Field::Rd => rd,
            isa::Field::Rs => rs,
            isa::Field::Rt => rt,
            isa::Field::Sa => continue,
        } & 31;
        match o.kind {
            OperandKind::GprUse => {
                src[n] = v;
                n += 1;
            }
            OperandKind::FprUse => {
                src[n] = FPR + v;
                n += 1;
            }
            OperandKind::GprDef => dst = v,
            OperandKind::FprDef => dst = FPR + v,
            OperandKind::Imm5 => {}
        }
    }
    // The fused pipelines read their inputs from coprocessor 2; the last input register
    // written by the kernel is the one most likely pending (written in order).
    match op {
        TraxOp::BoxTest => src[n.min(3)] = COP2 + 11,
        TraxOp::TriTest => src[n.min(3)] = COP2 + 20,
        _ => {}
    }
    OpInfo {
        class: row.unit,
        src,
        dst,
        mem: None,
        reg_accesses: 0,
    }
}

fn msa(m: &crate::msa::MsaInst) -> OpInfo {
    use crate::msa::{Form, MsaOp};
    let (wd, ws, wt) = (f(m.wd), f(m.ws), f(m.wt));
    let class = m.unit();
    match m.op.form() {
        Form::R3 => info(class, &[ws, wt, wd], wd),
        Form::R3Gpr => info(class, &[ws, m.wt & 31], wd),
        Form::Imm | Form::Elm | Form::R2 | Form::Insve => info(class, &[ws, wd], wd),
        Form::Ldi => info(class, &[], wd),
        Form::Copy => info(class, &[ws], m.wd & 31),
        Form::Insert | Form::Fill => info(class, &[m.ws & 31, wd], wd),
        Form::Ctc => info(class, &[m.ws & 31], 0),
        Form::Cfc => info(class, &[], m.wd & 31),
        Form::Branch => info(UnitClass::Branch, &[wt], 0),
        Form::Mem => {
            // The decoder stores the byte offset (already scaled by the element size).
            let off = m.imm;
            if m.op == MsaOp::St {
                store(wd, m.ws & 31, off, 16)
            } else {
                load(wd, m.ws & 31, off, 16)
            }
        }
    }
}
