//! Execution of decoded MSA instructions on a thread's registers and memory.
//!
//! Choices where the architecture leaves behaviour open:
//! - `div_s x, 0` gives -1 for `x >= 0` and 1 for `x < 0`; `div_u x, 0` gives all ones;
//!   `mod_s/mod_u x, 0` give `x`. `INT_MIN / -1` gives `INT_MIN` and `INT_MIN mod -1` gives 0.
//! - `ld.df`/`st.df` have no alignment restriction (as in the MSA specification); the
//!   memory trait still checks null/range/stack.
//! - Control registers: `cfcmsa` reads MSAIR (0) and MSAAccess..MSAUnmap (2..7) as 0;
//!   `ctcmsa` writes only MSACSR (1), masked to its writable fields (RM, Flags, Enables,
//!   Cause, NX, FS); writing Cause bits with matching Enables does not trap.
//! - Floating-point exceptions: every floating-point instruction (except `fclass`, `ffql`,
//!   `ffqr`, which cannot raise any) sets MSACSR.Cause to the OR of all lanes'
//!   exceptions. If a Cause bit is enabled and MSACSR.NX is clear, the instruction faults
//!   ([`MsaFault::FpException`]) without writing its destination or the Flags; otherwise
//!   the destination is written and Flags |= Cause. With NX set, a lane whose exceptions
//!   include an enabled one is written as a signaling NaN carrying its cause bits in the
//!   low bits of the payload (`0x7F80_0000 | cause` for words) and its exceptions are not
//!   recorded; the other lanes are normal. The Unimplemented (E) cause is never raised.

use super::{Df, Form, MsaInst, MsaOp};
use crate::softfloat::{self as float, vector_fast, Env, FastOp, Fmt, MinMax, Round};
use crate::RegFile;
use MsaOp::*;

/// Memory as seen by MSA loads and stores; the core's implementation applies its
/// null/range/stack checks and reports failures as `Self::Error`.
pub trait MsaMemory {
    /// The core's memory error.
    type Error;
    /// Reads one vector (`buf.len()` = 16 bytes) starting at `addr`; any alignment.
    fn load(&mut self, addr: u32, buf: &mut [u8]) -> Result<(), Self::Error>;
    /// Writes one vector (16 bytes) starting at `addr` (all or nothing); any alignment.
    fn store(&mut self, addr: u32, data: &[u8]) -> Result<(), Self::Error>;
}

/// Why an MSA instruction did not complete.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum MsaFault<E> {
    /// A load or store failed in the memory system.
    Memory(E),
    /// An enabled floating-point exception (MSA floating-point exception); `cause` is the
    /// MSACSR Cause field (bit 0 Inexact, 1 Underflow, 2 Overflow, 3 Divide-by-zero,
    /// 4 Invalid). The destination was not written.
    FpException {
        /// Raised exception bits.
        cause: u32,
    },
}

/// Result of executing one MSA instruction.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum MsaOutcome<E> {
    /// Completed; continue with the next instruction.
    Done,
    /// An MSA branch: whether it is taken. The core executes the delay slot and, if taken,
    /// jumps to `pc + 4 + inst.imm`.
    Branch(bool),
    /// The instruction faulted.
    Fault(MsaFault<E>),
}

/// MSACSR bits that `ctcmsa` can write.
pub const MSACSR_WRITABLE: u32 = 0x0107_FFFF;
const MSACSR_NX: u32 = 1 << 18;

fn mask(n: u32) -> u64 {
    if n >= 64 {
        u64::MAX
    } else {
        (1u64 << n) - 1
    }
}

fn sx(x: u64, n: u32) -> i64 {
    ((x << (64 - n)) as i64) >> (64 - n)
}

/// Element `i` of `v` in format `df`, zero-extended.
pub fn lane(v: u128, df: Df, i: usize) -> u64 {
    let n = df.bits();
    ((v >> (n as usize * i)) as u64) & mask(n)
}

/// Builds a vector from per-element values (truncated to the element size).
fn build(df: Df, mut f: impl FnMut(usize) -> u64) -> u128 {
    let n = df.bits();
    (0..df.lanes()).fold(0u128, |acc, i| {
        acc | (((f(i) & mask(n)) as u128) << (n as usize * i))
    })
}

/// Every element set to `v` (truncated to the element size).
fn splat(df: Df, v: u64) -> u128 {
    // A 1 in the lowest bit of every element.
    let ones: u128 = match df {
        Df::B => u128::from_le_bytes([1; 16]),
        Df::H => u128::MAX / 0xFFFF,
        Df::W => u128::MAX / 0xFFFF_FFFF,
        Df::D => 1 | 1 << 64,
        Df::V => 1,
    };
    ((v & mask(df.bits())) as u128).wrapping_mul(ones)
}

/// `v` with element `i` replaced by `x` (truncated to the element size).
fn set_lane(v: u128, df: Df, i: usize, x: u64) -> u128 {
    let n = df.bits();
    let sh = n as usize * i;
    let m = (mask(n) as u128) << sh;
    (v & !m) | (((x & mask(n)) as u128) << sh)
}

fn fmt(df: Df) -> Fmt {
    if df == Df::D {
        Fmt::D
    } else {
        Fmt::S
    }
}

/// Executes `inst` against `regs` (MSA registers alias `regs.fpr`) and `mem`.
pub fn execute<M: MsaMemory>(
    inst: &MsaInst,
    regs: &mut RegFile,
    mem: &mut M,
) -> MsaOutcome<M::Error> {
    let df = inst.df;
    let (wd, ws, wt) = (inst.wd as usize, inst.ws as usize, inst.wt as usize);
    let d = regs.fpr[wd];
    let s = regs.fpr[ws];
    let t = regs.fpr[wt];
    let result = match inst.op.form() {
        Form::Branch => {
            let t = regs.fpr[wt];
            let taken = match (inst.op, df) {
                (Bz, Df::V) => t == 0,
                (Bnz, Df::V) => t != 0,
                (Bz, _) => (0..df.lanes()).any(|i| lane(t, df, i) == 0),
                _ => (0..df.lanes()).all(|i| lane(t, df, i) != 0),
            };
            return MsaOutcome::Branch(taken);
        }
        Form::Mem => {
            let addr = regs.gpr[ws].wrapping_add(inst.imm as u32);
            if inst.op == Ld {
                let mut buf = [0u8; 16];
                if let Err(e) = mem.load(addr, &mut buf) {
                    return MsaOutcome::Fault(MsaFault::Memory(e));
                }
                u128::from_le_bytes(buf)
            } else {
                return match mem.store(addr, &d.to_le_bytes()) {
                    Ok(()) => MsaOutcome::Done,
                    Err(e) => MsaOutcome::Fault(MsaFault::Memory(e)),
                };
            }
        }
        Form::Copy => {
            let v = lane(s, df, inst.imm as usize);
            let v = if inst.op == CopyS {
                sx(v, df.bits()) as u64
            } else {
                v
            };
            set_gpr(regs, wd, v as u32);
            return MsaOutcome::Done;
        }
        Form::Cfc => {
            let v = if ws == 1 { regs.msacsr } else { 0 };
            set_gpr(regs, wd, v);
            return MsaOutcome::Done;
        }
        Form::Ctc => {
            if wd == 1 {
                regs.msacsr = regs.gpr[ws] & MSACSR_WRITABLE;
            }
            return MsaOutcome::Done;
        }
        Form::Insert => {
            let idx = inst.imm as usize;
            let g = regs.gpr[ws] as u64;
            set_lane(d, df, idx, g)
        }
        Form::Insve => {
            let idx = inst.imm as usize;
            let v = lane(s, df, 0);
            set_lane(d, df, idx, v)
        }
        Form::Fill => {
            let g = regs.gpr[ws] as u64;
            splat(df, g)
        }
        Form::Ldi => splat(df, inst.imm as i64 as u64),
        _ if !is_float(inst.op) => match vector_op(inst, d, s, t, &regs.gpr) {
            Some(r) => r,
            None => int_op(inst, d, s, t),
        },
        _ => {
            let (r, cause) = float_op(inst, regs.msacsr, d, s, t);
            // fclass and the exact fixed-point conversions leave MSACSR alone.
            if !matches!(inst.op, Fclass | Ffql | Ffqr) {
                let csr = regs.msacsr & !(0x3F << 12);
                regs.msacsr = csr | (cause << 12);
                let enables = (csr >> 7) & 0x1F;
                if cause & enables != 0 && csr & MSACSR_NX == 0 {
                    return MsaOutcome::Fault(MsaFault::FpException { cause });
                }
                regs.msacsr |= cause << 2;
            }
            r
        }
    };
    regs.fpr[wd] = result;
    MsaOutcome::Done
}

fn set_gpr(regs: &mut RegFile, r: usize, v: u32) {
    if r != 0 {
        regs.gpr[r] = v;
    }
}

/// Whole-vector, shuffle and element-move operations; `None` if `inst` is not one.
fn vector_op(inst: &MsaInst, d: u128, s: u128, t: u128, gpr: &[u32; 32]) -> Option<u128> {
    let df = inst.df;
    let n = df.lanes();
    let imm = inst.imm as u32 as u128;
    let i8v = u128::from_le_bytes([imm as u8; 16]);
    let l = |v: u128, i: usize| lane(v, df, i);
    Some(match inst.op {
        AndV => s & t,
        OrV => s | t,
        NorV => !(s | t),
        XorV => s ^ t,
        BmnzV => (s & t) | (d & !t),
        BmzV => (s & !t) | (d & t),
        BselV => (s & !d) | (t & d),
        Andi => s & i8v,
        Ori => s | i8v,
        Nori => !(s | i8v),
        Xori => s ^ i8v,
        Bmnzi => (s & i8v) | (d & !i8v),
        Bmzi => (s & !i8v) | (d & i8v),
        Bseli => (s & !d) | (i8v & d),
        Move => s,
        Shf => build(df, |i| {
            l(s, (i & !3) + ((inst.imm as usize >> (2 * (i & 3))) & 3))
        }),
        Vshf => build(df, |i| {
            let c = l(d, i);
            if c & 0xC0 != 0 {
                0
            } else {
                let k = (c as usize) % (2 * n);
                if k < n {
                    l(t, k)
                } else {
                    l(s, k - n)
                }
            }
        }),
        Sld | Sldi => {
            let shift = if inst.op == Sld {
                gpr[inst.wt as usize] as usize
            } else {
                inst.imm as usize
            };
            // Each of the `bytes(elem)` partitions of 16/bytes(elem) bytes slides independently
            // over the concatenation wd:ws (ws in the low half).
            let part = n;
            let k = shift % part;
            let sb = s.to_le_bytes();
            let db = d.to_le_bytes();
            let mut out = [0u8; 16];
            for p in 0..16 / part {
                for i in 0..part {
                    let j = i + k;
                    out[p * part + i] = if j < part {
                        sb[p * part + j]
                    } else {
                        db[p * part + j - part]
                    };
                }
            }
            u128::from_le_bytes(out)
        }
        Splat => {
            let k = gpr[inst.wt as usize] as usize % n;
            splat(df, l(s, k))
        }
        Splati => splat(df, l(s, inst.imm as usize)),
        Pckev => build(df, |i| {
            if i < n / 2 {
                l(t, 2 * i)
            } else {
                l(s, 2 * (i - n / 2))
            }
        }),
        Pckod => build(df, |i| {
            if i < n / 2 {
                l(t, 2 * i + 1)
            } else {
                l(s, 2 * (i - n / 2) + 1)
            }
        }),
        Ilvev => build(df, |i| if i % 2 == 0 { l(t, i) } else { l(s, i - 1) }),
        Ilvod => build(df, |i| if i % 2 == 0 { l(t, i + 1) } else { l(s, i) }),
        Ilvl => build(df, |i| {
            if i % 2 == 0 {
                l(t, n / 2 + i / 2)
            } else {
                l(s, n / 2 + i / 2)
            }
        }),
        Ilvr => build(df, |i| if i % 2 == 0 { l(t, i / 2) } else { l(s, i / 2) }),
        _ => return None,
    })
}

/// Per-element integer operations.
fn int_op(inst: &MsaInst, d: u128, s: u128, t: u128) -> u128 {
    let df = inst.df;
    let n = df.bits();
    let imm_form = inst.op.form() == Form::Imm;
    let imm = inst.imm as i64 as u64 & mask(n);
    let t_or_imm = if imm_form { splat(df, imm) } else { t };
    if let Some(r) = super::int_fast::int_fast(inst.op, df, s, t_or_imm) {
        return r;
    }
    build(df, |i| {
        let a = lane(s, df, i);
        let b = if imm_form { imm } else { lane(t, df, i) };
        int_lane(inst.op, n, a, b, lane(d, df, i), inst.imm)
    })
}

/// One element of an integer operation: `a` = ws, `b` = wt (or the immediate), `c` = wd.
fn int_lane(op: MsaOp, n: u32, a: u64, b: u64, c: u64, imm: i32) -> u64 {
    let m = mask(n);
    let (sa, sb, sc) = (sx(a, n) as i128, sx(b, n) as i128, sx(c, n) as i128);
    let (ua, ub) = (a as i128, b as i128);
    let smax = (1i128 << (n - 1)) - 1;
    let smin = -(1i128 << (n - 1));
    let umax = (1i128 << n) - 1;
    let sat_s = |v: i128| v.clamp(smin, smax);
    let sat_u = |v: i128| v.clamp(0, umax);
    let flag = |c: bool| if c { -1i128 } else { 0 };
    let sh = (b % n as u64) as u32;
    let half = n / 2;
    // Lower and upper half-width elements of a lane (dot products, horizontal ops).
    let halves = |v: u64, signed: bool| -> (i128, i128) {
        if signed {
            (
                sx(v & mask(half), half) as i128,
                sx(v >> half, half) as i128,
            )
        } else {
            ((v & mask(half)) as i128, (v >> half) as i128)
        }
    };
    let dot = |signed: bool| {
        let (a0, a1) = halves(a, signed);
        let (b0, b1) = halves(b, signed);
        a0 * b0 + a1 * b1
    };
    let r: i128 = match op {
        Addv | Addvi => ua + ub,
        Subv | Subvi => ua - ub,
        Mulv => return a.wrapping_mul(b) & m,
        Maddv => return c.wrapping_add(a.wrapping_mul(b)) & m,
        Msubv => return c.wrapping_sub(a.wrapping_mul(b)) & m,
        MaxS | MaxiS => sa.max(sb),
        MaxU | MaxiU => ua.max(ub),
        MinS | MiniS => sa.min(sb),
        MinU | MiniU => ua.min(ub),
        MaxA => {
            if sa.abs() > sb.abs() {
                sa
            } else {
                sb
            }
        }
        MinA => {
            if sa.abs() < sb.abs() {
                sa
            } else {
                sb
            }
        }
        Ceq | Ceqi => flag(a == b),
        CltS | CltiS => flag(sa < sb),
        CltU | CltiU => flag(ua < ub),
        CleS | CleiS => flag(sa <= sb),
        CleU | CleiU => flag(ua <= ub),
        AddA => sa.abs() + sb.abs(),
        AddsA => sat_s(sa.abs() + sb.abs()),
        AddsS => sat_s(sa + sb),
        AddsU => sat_u(ua + ub),
        AveS => (sa + sb) >> 1,
        AveU => (ua + ub) >> 1,
        AverS => (sa + sb + 1) >> 1,
        AverU => (ua + ub + 1) >> 1,
        SubsS => sat_s(sa - sb),
        SubsU => sat_u(ua - ub),
        SubsusU => sat_u(ua - sb),
        SubsuuS => sat_s(ua - ub),
        AsubS => (sa - sb).abs(),
        AsubU => (ua - ub).abs(),
        DivS => match sb {
            0 if sa >= 0 => -1,
            0 => 1,
            _ => sa / sb,
        },
        DivU => {
            if ub == 0 {
                umax
            } else {
                ua / ub
            }
        }
        ModS => {
            if sb == 0 {
                sa
            } else {
                sa % sb
            }
        }
        ModU => {
            if ub == 0 {
                ua
            } else {
                ua % ub
            }
        }
        DotpS => dot(true),
        DotpU => dot(false),
        DpaddS => c as i128 + dot(true),
        DpaddU => c as i128 + dot(false),
        DpsubS => c as i128 - dot(true),
        DpsubU => c as i128 - dot(false),
        HaddS => halves(a, true).1 + halves(b, true).0,
        HaddU => halves(a, false).1 + halves(b, false).0,
        HsubS => halves(a, true).1 - halves(b, true).0,
        HsubU => halves(a, false).1 - halves(b, false).0,
        Sll | Slli => ua << sh,
        Sra | Srai => sa >> sh,
        Srl | Srli => ua >> sh,
        Srar | Srari => {
            if sh == 0 {
                sa
            } else {
                (sa >> sh) + ((sa >> (sh - 1)) & 1)
            }
        }
        Srlr | Srlri => {
            if sh == 0 {
                ua
            } else {
                (ua >> sh) + ((ua >> (sh - 1)) & 1)
            }
        }
        Bclr | Bclri => ua & !(1i128 << sh),
        Bset | Bseti => ua | (1i128 << sh),
        Bneg | Bnegi => ua ^ (1i128 << sh),
        Binsl | Binsli => {
            let keep = ((1i128 << (sh + 1)) - 1) << (n - sh - 1);
            (ua & keep) | (c as i128 & !keep)
        }
        Binsr | Binsri => {
            let keep = (1i128 << (sh + 1)) - 1;
            (ua & keep) | (c as i128 & !keep)
        }
        SatS => sa.clamp(-(1i128 << imm), (1i128 << imm) - 1),
        SatU => ua.min((1i128 << (imm + 1)) - 1),
        Pcnt => a.count_ones() as i128,
        Nlzc => (a.leading_zeros() - (64 - n)) as i128,
        Nloc => ((!a & m).leading_zeros() - (64 - n)) as i128,
        MulQ | MulrQ | MaddQ | MaddrQ | MsubQ | MsubrQ => {
            let q = n - 1;
            let p = sa * sb;
            let round = if matches!(op, MulrQ | MaddrQ | MsubrQ) {
                1i128 << (q - 1)
            } else {
                0
            };
            let acc = match op {
                MaddQ | MaddrQ => (sc << q) + p,
                MsubQ | MsubrQ => (sc << q) - p,
                _ => p,
            };
            sat_s((acc + round) >> q)
        }
        _ => 0,
    };
    r as u64 & m
}

/// Builds a floating-point result lane by lane, accumulating each lane's exceptions in
/// `e.flags`; a lane raising an exception in `trap` (the enabled exceptions in
/// non-trapping mode) instead becomes a signaling NaN carrying its cause in the low bits,
/// and its exceptions are not recorded.
fn lanes_nx(df: Df, trap: u32, e: &mut Env, g: &mut dyn FnMut(&mut Env, usize) -> u64) -> u128 {
    build(df, |i| {
        let before = e.flags;
        e.flags = 0;
        let r = g(e, i);
        let cause = e.flags;
        if cause & trap != 0 {
            e.flags = before;
            let snan: u64 = match df {
                Df::H => 0x7C00,
                Df::D => 0x7FF0_0000_0000_0000,
                _ => 0x7F80_0000,
            };
            snan | cause as u64
        } else {
            e.flags = before | cause;
            r
        }
    })
}

/// True for the floating-point operations (those that go through [`float_op`]).
fn is_float(op: MsaOp) -> bool {
    use trax_runtime::isa::UnitClass as U;
    matches!(
        op.unit(),
        U::FpAdd | U::FpMul | U::FpDiv | U::FpInvSqrt | U::FpCmp | U::FpMinMax | U::Conv
    )
}

/// Floating-point operations: the result and the raised exception flags.
fn float_op(inst: &MsaInst, csr: u32, d: u128, s: u128, t: u128) -> (u128, u32) {
    let df = inst.df;
    let mut env = Env::from_msacsr(csr);
    let f = fmt(df);
    let fast_op = match inst.op {
        Fadd => Some(FastOp::Add),
        Fsub => Some(FastOp::Sub),
        Fmul => Some(FastOp::Mul),
        Fdiv => Some(FastOp::Div),
        Fmadd => Some(FastOp::Fmadd),
        Fmsub => Some(FastOp::Fmsub),
        _ => None,
    };
    // In non-trapping mode (NX) lanes with enabled exceptions become signaling NaNs.
    let trap = if csr & MSACSR_NX != 0 {
        (csr >> 7) & 0x1F
    } else {
        0
    };
    if let Some(op) = fast_op.filter(|_| trap == 0) {
        if let Some(res) = vector_fast(&env, f, op, s, t, d) {
            return res;
        }
    }
    let e = &mut env;
    let fb = |e: &mut Env, g: &mut dyn FnMut(&mut Env, usize) -> u64| lanes_nx(df, trap, e, g);
    let l = |v: u128, i: usize| lane(v, df, i);
    let bin = |e: &mut Env, g: &dyn Fn(&mut Env, u64, u64) -> u64| {
        lanes_nx(df, trap, e, &mut |e, i| {
            g(e, lane(s, df, i), lane(t, df, i))
        })
    };
    // `cond` in the encoding of scalar `cmp.cond.fmt` (unordered 1, equal 2, less 4,
    // negate 16); the signalling forms are `Fs*`.
    let cmp = |e: &mut Env, signaling: bool, cond: u8| {
        lanes_nx(df, trap, e, &mut |e, i| {
            let rel = float::compare(e, f, l(s, i), l(t, i), signaling);
            if float::cond_holds(rel, cond) {
                u64::MAX
            } else {
                0
            }
        })
    };
    let r = match inst.op {
        Fadd => bin(e, &|e, a, b| float::add(e, f, a, b)),
        Fsub => bin(e, &|e, a, b| float::sub(e, f, a, b)),
        Fmul => bin(e, &|e, a, b| float::mul(e, f, a, b)),
        Fdiv => bin(e, &|e, a, b| float::div(e, f, a, b)),
        Fmadd | Fmsub => {
            let neg = inst.op == Fmsub;
            fb(e, &mut |e, i| {
                float::fma(e, f, l(s, i), l(t, i), l(d, i), neg)
            })
        }
        Fmax => bin(e, &|e, a, b| float::min_max(e, f, a, b, MinMax::Max)),
        Fmin => bin(e, &|e, a, b| float::min_max(e, f, a, b, MinMax::Min)),
        FmaxA => bin(e, &|e, a, b| float::min_max(e, f, a, b, MinMax::MaxA)),
        FminA => bin(e, &|e, a, b| float::min_max(e, f, a, b, MinMax::MinA)),
        Fexp2 => {
            let n = df.bits();
            bin(e, &|e, a, b| float::exp2(e, f, a, sx(b, n)))
        }
        Fcaf | Fsaf => cmp(e, inst.op == Fsaf, 0),
        Fcun | Fsun => cmp(e, inst.op == Fsun, 1),
        Fceq | Fseq => cmp(e, inst.op == Fseq, 2),
        Fcueq | Fsueq => cmp(e, inst.op == Fsueq, 3),
        Fclt | Fslt => cmp(e, inst.op == Fslt, 4),
        Fcult | Fsult => cmp(e, inst.op == Fsult, 5),
        Fcle | Fsle => cmp(e, inst.op == Fsle, 6),
        Fcule | Fsule => cmp(e, inst.op == Fsule, 7),
        Fcor | Fsor => cmp(e, inst.op == Fsor, 17),
        Fcune | Fsune => cmp(e, inst.op == Fsune, 18),
        Fcne | Fsne => cmp(e, inst.op == Fsne, 19),
        Fclass => build(df, |i| float::class(f, l(s, i))),
        FtruncS | FtruncU => fb(e, &mut |e, i| {
            float::to_int(e, f, l(s, i), Round::Zero, inst.op == FtruncS, df.bits())
        }),
        FtintS | FtintU => {
            let mode = e.mode;
            fb(e, &mut |e, i| {
                float::to_int(e, f, l(s, i), mode, inst.op == FtintS, df.bits())
            })
        }
        FfintS => fb(e, &mut |e, i| {
            float::from_int(e, f, sx(l(s, i), df.bits()) as i128)
        }),
        FfintU => fb(e, &mut |e, i| float::from_int(e, f, l(s, i) as i128)),
        Fsqrt => fb(e, &mut |e, i| float::sqrt(e, f, l(s, i))),
        Frsqrt => fb(e, &mut |e, i| float::rsqrt(e, f, l(s, i))),
        Frcp => fb(e, &mut |e, i| float::rcp(e, f, l(s, i))),
        Frint => fb(e, &mut |e, i| float::rint(e, f, l(s, i))),
        Flog2 => fb(e, &mut |e, i| float::log2(e, f, l(s, i))),
        Fexupl | Fexupr | Ffql | Ffqr => {
            // Source elements are half as wide; "left" takes the upper half of the vector.
            let hdf = df.half();
            let base = if matches!(inst.op, Fexupl | Ffql) {
                df.lanes()
            } else {
                0
            };
            let src = |i: usize| lane(s, hdf, base + i);
            let (from, frac) = if df == Df::D {
                (Fmt::S, 31)
            } else {
                (Fmt::H, 15)
            };
            if matches!(inst.op, Fexupl | Fexupr) {
                fb(e, &mut |e, i| float::convert(e, from, f, src(i)))
            } else {
                fb(e, &mut |e, i| {
                    float::from_fixed(e, f, sx(src(i), hdf.bits()), frac)
                })
            }
        }
        Fexdo | Ftq => {
            // Destination elements are half as wide: ws fills the upper half, wt the lower.
            let wdf = if df == Df::W { Df::D } else { Df::W };
            let half = wdf.lanes();
            let from = fmt(wdf);
            let src = |i: usize| {
                if i < half {
                    lane(t, wdf, i)
                } else {
                    lane(s, wdf, i - half)
                }
            };
            if inst.op == Fexdo {
                let to = if df == Df::W { Fmt::S } else { Fmt::H };
                fb(e, &mut |e, i| float::convert(e, from, to, src(i)))
            } else {
                fb(e, &mut |e, i| {
                    float::to_fixed(e, from, src(i), df.bits() as i32 - 1, df.bits())
                })
            }
        }
        // Not a floating-point op (excluded by `is_float`): leave wd unchanged.
        _ => d,
    };
    (r, env.flags)
}
