//! The reference interpreter: executes one predecoded instruction ([`Inst`]) at a time,
//! every instruction of the ISA (decoding on the fly outside the text).
//!
//! [`Thread::step_once`] runs it alone (the timing model issues one instruction per
//! call); [`Thread::run`] runs the fast engine of [`crate::block`], which hands it every
//! instruction the engine does not execute itself, so the two share one definition of
//! every rare case (faults, traps, enabled FPU exceptions, TRaX operations, MSA). It
//! performs no I/O: prints go to [`Shared::output`]. FPU cause/flag bits wait in an
//! `FpPending` and reach FCSR before anything reads it and when the call returns.
//!
//! Behaviour chosen where MIPS32r6 leaves it open (UNPREDICTABLE or implementation
//! defined):
//! - `div`/`mod`/`divu`/`modu` by zero give `rs` / `0` (QEMU's choice); `INT_MIN / -1`
//!   gives `INT_MIN` and `INT_MIN mod -1` gives 0 (LLVM guards division with `teq`).
//! - Misaligned loads/stores are performed; only `ll`/`sc` fault (see [`crate::memory`]).
//! - A branch or jump in a delay slot or forbidden slot is a reserved instruction.
//! - `jalr` with `rd == rs` reads `rs` before linking.
//! - Single-precision results leave the upper half of the 64-bit FPU register unchanged.
//! - `rdhwr`: `$0` = global thread id, `$2` = instruction count, `$3` = 1, `$29` = 0.
//! - `sc` succeeds if the thread's `ll` link is for the same address and the thread was
//!   not descheduled in between (a context switch clears the link).

use crate::chip::Chip;
use crate::decode::{Conv, Inst, F2, F3};
use crate::fpu;
use crate::memory::MemFault;
use crate::msa_glue::MsaStep;
use crate::softfloat::{self as sf, Arith, Env, Fmt, MinMax, Round};
use crate::thread::{CallFrame, Fault, Shared, Thread, MAX_SHADOW_FRAMES};
use crate::trax::{exec_trax, TraxFlow};
use trax_runtime::fops;
use trax_runtime::isa::TraxOp;

/// Why [`Thread::run`] returned.
#[derive(Clone, Debug, PartialEq)]
pub enum Stop {
    /// The instruction budget was used up.
    Budget,
    /// The thread executed `trax.halt`.
    Halted,
    /// The thread is waiting (barrier): do not run it until released.
    Blocked,
    /// The thread could not proceed now (semaphore); retry it later.
    Retry,
    /// The thread faulted at `pc` (not advanced; `retired` excludes it).
    Fault(Fault),
    /// The next instruction changes chip-wide state the [`Chip`] view may not change (a
    /// store to global memory, a global-register, stream or halt operation); nothing was
    /// done (pc unchanged). Replay it with exclusive access.
    Defer,
}

/// FCSR bits `ctc1 $31` can write (QEMU's r6 mask: RM, Flags, Enables, Cause, FS).
const FCSR_WRITABLE: u32 = 0x0103_FFFF;
/// FIR value read by `cfc1 $0` (F64, L, W, D, S, HAS2008, FREP; as QEMU's r6 core).
pub const FIR: u32 = 0x20F3_0300;

#[inline(always)]
fn mem_fault(f: MemFault) -> Fault {
    Fault::Memory {
        fault: f,
        fetch: false,
    }
}

impl Thread {
    #[cold]
    fn fetch_slow(&self, sh: &Shared, pc: u32) -> Result<Inst, Fault> {
        match sh.mem.fetch(&self.local, pc) {
            Ok(b) => Ok(crate::decode::decode(u32::from_le_bytes(b))),
            Err(f) => Err(Fault::Memory {
                fault: f,
                fetch: true,
            }),
        }
    }

    /// The instruction at the thread's pc (for crash reports and tools).
    pub fn current_inst(&self, sh: &Shared) -> Option<Inst> {
        match sh.program.get(self.pc) {
            Some(i) => Some(*i),
            None => self.fetch_slow(sh, self.pc).ok(),
        }
    }

    #[inline(always)]
    pub(crate) fn push_call(&mut self, call_pc: u32, return_addr: u32, target: u32) {
        if self.calls.len() < MAX_SHADOW_FRAMES {
            self.calls.push(CallFrame {
                call_pc,
                return_addr,
                target,
            });
        } else {
            self.dropped_calls += 1;
        }
    }

    #[inline(always)]
    pub(crate) fn note_jump(&mut self, target: u32) {
        // A jump to a recorded return address is a return: pop to that frame.
        let n = self.calls.len();
        for i in (n.saturating_sub(8)..n).rev() {
            if self.calls[i].return_addr == target {
                self.calls.truncate(i);
                return;
            }
        }
    }

    /// Runs up to `budget` instructions: the fast engine ([`crate::block`]) with this
    /// module's interpreter behind it for what the engine leaves to it.
    pub fn run<C: Chip>(&mut self, sh: &mut C, budget: u64) -> Stop {
        self.run_blocks(sh, budget)
    }

    /// Runs exactly one instruction in the reference interpreter (the timing model issues
    /// one instruction per call; the fast engine hands it what it does not run itself).
    #[inline(never)]
    pub fn step_once<C: Chip>(&mut self, sh: &mut C) -> Stop {
        let (pc, npc) = (self.pc, self.npc);
        let inst = match sh.shared().program.get(pc) {
            Some(i) => *i,
            None => {
                return match self.step_outside(sh, pc, npc) {
                    Ok((p, n)) => {
                        (self.pc, self.npc) = (p, n);
                        Stop::Budget
                    }
                    Err(stop) => stop,
                }
            }
        };
        let mut fp = FpPending::default();
        let r = self.step(sh, pc, npc, &inst, &mut fp);
        fp.flush(&mut self.regs.fcsr);
        match r {
            Ok((p, n)) => {
                self.retired += 1;
                (self.pc, self.npc) = (p, n);
                Stop::Budget
            }
            Err(exit) => self.stop_at(exit, pc, npc),
        }
    }

    /// Executes (and retires) one instruction outside the predecoded text, decoding it on
    /// the fly; kept out of line so the hot loop holds one copy of [`Thread::step`].
    #[cold]
    #[inline(never)]
    fn step_outside<C: Chip>(&mut self, sh: &mut C, pc: u32, npc: u32) -> Result<(u32, u32), Stop> {
        let inst = match self.fetch_slow(sh.shared(), pc) {
            Ok(i) => i,
            Err(f) => {
                (self.pc, self.npc) = (pc, npc);
                return Err(Stop::Fault(f));
            }
        };
        let mut fp = FpPending::default();
        let r = self.step(sh, pc, npc, &inst, &mut fp);
        fp.flush(&mut self.regs.fcsr);
        match r {
            Ok(next) => {
                self.retired += 1;
                Ok(next)
            }
            Err(exit) => Err(self.stop_at(exit, pc, npc)),
        }
    }

    /// The [`Stop`] for an early exit of the instruction at `pc` (followed by `npc`).
    #[cold]
    fn stop_at(&mut self, exit: StepExit, pc: u32, npc: u32) -> Stop {
        match exit {
            StepExit::Fault => {
                (self.pc, self.npc) = (pc, npc);
                match self.pending_fault.take() {
                    Some(f) => Stop::Fault(f),
                    None => Stop::Retry,
                }
            }
            StepExit::Flow(TraxFlow::Retry) => {
                (self.pc, self.npc) = (pc, npc);
                Stop::Retry
            }
            StepExit::Defer => {
                (self.pc, self.npc) = (pc, npc);
                Stop::Defer
            }
            // Halt and Block completed the instruction and set pc/npc.
            StepExit::Flow(TraxFlow::Halt) => Stop::Halted,
            StepExit::Flow(TraxFlow::Block | TraxFlow::Next | TraxFlow::Defer) => Stop::Blocked,
        }
    }

    /// Executes one instruction at `pc` (followed by `npc`). On `Ok` returns the new
    /// `(pc, npc)` and the caller counts the instruction as retired; on an error exit
    /// `self.pc`/`self.npc` are left for the caller. `self.retired` is up to date. FPU
    /// cause/flag bits go to `fp` and reach `regs.fcsr` when the caller flushes it.
    #[inline(always)]
    fn step<C: Chip>(
        &mut self,
        sh: &mut C,
        pc: u32,
        npc: u32,
        inst: &Inst,
        fp: &mut FpPending,
    ) -> Result<(u32, u32), StepExit> {
        use Inst::*;
        let mut next = npc.wrapping_add(4);
        macro_rules! g {
            ($r:expr) => {
                self.regs.gpr[($r & 31) as usize]
            };
        }
        macro_rules! fault {
            ($f:expr) => {
                return Err(self.set_fault($f))
            };
        }
        macro_rules! cti {
            () => {
                if pc == self.slot_pc {
                    fault!(Fault::BranchInSlot)
                }
            };
        }
        // Branch with a delay slot (`Cti::DelaySlot`; `npc` is `pc + 4`, as a branch in a
        // slot has faulted).
        macro_rules! branch {
            ($cond:expr, $off:expr) => {{
                cti!();
                self.slot_pc = npc;
                if $cond {
                    next = Inst::rel_target(pc, $off);
                }
            }};
        }
        // Compact branch: taken jumps now; not taken makes the next word a forbidden slot.
        macro_rules! compact {
            ($cond:expr, $off:expr) => {{
                cti!();
                if $cond {
                    let t = Inst::rel_target(pc, $off);
                    return Ok((t, t.wrapping_add(4)));
                }
                self.slot_pc = pc.wrapping_add(4);
            }};
        }
        macro_rules! ea {
            ($base:expr, $off:expr) => {
                g!($base).wrapping_add($off as i32 as u32)
            };
        }
        macro_rules! load {
            ($n:literal, $base:expr, $off:expr) => {{
                let a = ea!($base, $off);
                sh.note_load(a);
                match sh.shared().mem.read::<$n>(&self.local, a) {
                    Ok(b) => b,
                    Err(f) => fault!(mem_fault(f)),
                }
            }};
        }
        macro_rules! store {
            ($base:expr, $off:expr, $v:expr) => {
                match sh.store(&mut self.local, ea!($base, $off), $v) {
                    Ok(true) => {}
                    Ok(false) => return Err(StepExit::Defer),
                    Err(f) => fault!(mem_fault(f)),
                }
            };
        }
        macro_rules! fcsr {
            ($exc:expr) => {
                let e: u32 = $exc;
                if e & (self.regs.fcsr >> 7) & 0x1F != 0 {
                    // An enabled exception: FCSR takes the cause now, then the trap.
                    fp.flush(&mut self.regs.fcsr);
                    let _ = fpu::update(&mut self.regs.fcsr, e);
                    fault!(Fault::FpException {
                        cause: e,
                        msa: false
                    })
                }
                fp.record(e);
            };
        }
        macro_rules! fs32 {
            ($r:expr) => {
                self.regs.f32_bits(($r & 31) as usize)
            };
        }
        macro_rules! fs64 {
            ($r:expr) => {
                self.regs.f64_bits(($r & 31) as usize)
            };
        }
        macro_rules! set32 {
            ($r:expr, $v:expr) => {
                self.regs.set_f32_bits(($r & 31) as usize, $v)
            };
        }
        macro_rules! set64 {
            ($r:expr, $v:expr) => {
                self.regs.set_f64_bits(($r & 31) as usize, $v)
            };
        }
        // A scalar FPU operation: `$g` computes the result bits in `$e`, the environment
        // FCSR selects; its exceptions go to FCSR (or trap).
        macro_rules! fop {
            ($set:ident, $fd:expr, |$e:ident| $g:expr) => {{
                let mut $e = Env::from_fcsr(self.regs.fcsr);
                let v = $g;
                fcsr!($e.flags);
                $set!($fd, v as _);
            }};
        }
        // Arithmetic `fd = op(fs, ft, fd)` in the soft-float core's scalar entry.
        macro_rules! arith {
            ($set:ident, $fd:expr, $f:expr, $op:expr, $a:expr, $b:expr, $c:expr) => {{
                let (v, e) = sf::arith($op, $f, $a, $b, $c, self.regs.fcsr);
                fcsr!(e);
                $set!($fd, v as _);
            }};
        }
        // `$acc`: whether `fd` is also an operand (fused multiply-add).
        macro_rules! arith_s {
            ($x:expr, $op:expr, $acc:expr) => {{
                let F3 { fd, fs, ft } = $x;
                let (a, b) = (fs32!(fs) as u64, fs32!(ft) as u64);
                let c = if $acc { fs32!(fd) as u64 } else { 0 };
                arith!(set32, fd, Fmt::S, $op, a, b, c)
            }};
        }
        macro_rules! arith_d {
            ($x:expr, $op:expr, $acc:expr) => {{
                let F3 { fd, fs, ft } = $x;
                let c = if $acc { fs64!(fd) } else { 0 };
                arith!(set64, fd, Fmt::D, $op, fs64!(fs), fs64!(ft), c)
            }};
        }
        macro_rules! minmax_s {
            ($x:expr, $kind:expr) => {{
                let F3 { fd, fs, ft } = $x;
                let rm = self.regs.fcsr;
                let (v, e) = fp_min_max(Fmt::S, $kind, fs32!(fs) as u64, fs32!(ft) as u64, rm);
                fcsr!(e);
                set32!(fd, v as u32);
            }};
        }
        macro_rules! minmax_d {
            ($x:expr, $kind:expr) => {{
                let F3 { fd, fs, ft } = $x;
                let (v, e) = fp_min_max(Fmt::D, $kind, fs64!(fs), fs64!(ft), self.regs.fcsr);
                fcsr!(e);
                set64!(fd, v);
            }};
        }
        match *inst {
            Add { rd, rs, rt } => match (g!(rs) as i32).checked_add(g!(rt) as i32) {
                Some(v) => g!(rd) = v as u32,
                None => fault!(Fault::IntegerOverflow),
            },
            Addu { rd, rs, rt } => g!(rd) = g!(rs).wrapping_add(g!(rt)),
            Sub { rd, rs, rt } => match (g!(rs) as i32).checked_sub(g!(rt) as i32) {
                Some(v) => g!(rd) = v as u32,
                None => fault!(Fault::IntegerOverflow),
            },
            Subu { rd, rs, rt } => g!(rd) = g!(rs).wrapping_sub(g!(rt)),
            And { rd, rs, rt } => g!(rd) = g!(rs) & g!(rt),
            Or { rd, rs, rt } => g!(rd) = g!(rs) | g!(rt),
            Xor { rd, rs, rt } => g!(rd) = g!(rs) ^ g!(rt),
            Nor { rd, rs, rt } => g!(rd) = !(g!(rs) | g!(rt)),
            Slt { rd, rs, rt } => g!(rd) = ((g!(rs) as i32) < (g!(rt) as i32)) as u32,
            Sltu { rd, rs, rt } => g!(rd) = (g!(rs) < g!(rt)) as u32,
            Mul { rd, rs, rt } => g!(rd) = g!(rs).wrapping_mul(g!(rt)),
            Muh { rd, rs, rt } => {
                g!(rd) = ((g!(rs) as i32 as i64 * g!(rt) as i32 as i64) >> 32) as u32
            }
            Mulu { rd, rs, rt } => g!(rd) = g!(rs).wrapping_mul(g!(rt)),
            Muhu { rd, rs, rt } => g!(rd) = ((g!(rs) as u64 * g!(rt) as u64) >> 32) as u32,
            Div { rd, rs, rt } => {
                let (a, b) = (g!(rs) as i32, g!(rt) as i32);
                g!(rd) = if b == 0 {
                    a as u32
                } else {
                    a.wrapping_div(b) as u32
                };
            }
            Mod { rd, rs, rt } => {
                let (a, b) = (g!(rs) as i32, g!(rt) as i32);
                g!(rd) = if b == 0 { 0 } else { a.wrapping_rem(b) as u32 };
            }
            Divu { rd, rs, rt } => {
                let (a, b) = (g!(rs), g!(rt));
                g!(rd) = a.checked_div(b).unwrap_or(a);
            }
            Modu { rd, rs, rt } => {
                let (a, b) = (g!(rs), g!(rt));
                g!(rd) = a.checked_rem(b).unwrap_or(0);
            }
            Seleqz { rd, rs, rt } => g!(rd) = if g!(rt) == 0 { g!(rs) } else { 0 },
            Selnez { rd, rs, rt } => g!(rd) = if g!(rt) != 0 { g!(rs) } else { 0 },
            Sllv { rd, rt, rs } => g!(rd) = g!(rt) << (g!(rs) & 31),
            Srlv { rd, rt, rs } => g!(rd) = g!(rt) >> (g!(rs) & 31),
            Srav { rd, rt, rs } => g!(rd) = ((g!(rt) as i32) >> (g!(rs) & 31)) as u32,
            Rotrv { rd, rt, rs } => g!(rd) = g!(rt).rotate_right(g!(rs) & 31),
            Sll { rd, rt, sa } => g!(rd) = g!(rt) << (sa & 31),
            Srl { rd, rt, sa } => g!(rd) = g!(rt) >> (sa & 31),
            Sra { rd, rt, sa } => g!(rd) = ((g!(rt) as i32) >> (sa & 31)) as u32,
            Rotr { rd, rt, sa } => g!(rd) = g!(rt).rotate_right(sa as u32 & 31),
            Lsa { rd, rs, rt, sa } => g!(rd) = (g!(rs) << (sa & 7)).wrapping_add(g!(rt)),
            Clz { rd, rs } => g!(rd) = g!(rs).leading_zeros(),
            Clo { rd, rs } => g!(rd) = g!(rs).leading_ones(),
            Addiu { rt, rs, imm } => g!(rt) = g!(rs).wrapping_add(imm as i32 as u32),
            Slti { rt, rs, imm } => g!(rt) = ((g!(rs) as i32) < imm as i32) as u32,
            Sltiu { rt, rs, imm } => g!(rt) = (g!(rs) < imm as i32 as u32) as u32,
            Andi { rt, rs, imm } => g!(rt) = g!(rs) & imm as u32,
            Ori { rt, rs, imm } => g!(rt) = g!(rs) | imm as u32,
            Xori { rt, rs, imm } => g!(rt) = g!(rs) ^ imm as u32,
            Aui { rt, rs, imm } => g!(rt) = g!(rs).wrapping_add((imm as u32) << 16),
            Align { rd, rs, rt, bp } => {
                let bp = (bp & 3) as u32;
                g!(rd) = if bp == 0 {
                    g!(rt)
                } else {
                    (g!(rt) << (8 * bp)) | (g!(rs) >> (32 - 8 * bp))
                };
            }
            Bitswap { rd, rt } => {
                let b = g!(rt).to_le_bytes().map(u8::reverse_bits);
                g!(rd) = u32::from_le_bytes(b);
            }
            Wsbh { rd, rt } => {
                let v = g!(rt);
                g!(rd) = ((v & 0x00FF_00FF) << 8) | ((v >> 8) & 0x00FF_00FF);
            }
            Seb { rd, rt } => g!(rd) = g!(rt) as i8 as i32 as u32,
            Seh { rd, rt } => g!(rd) = g!(rt) as i16 as i32 as u32,
            Ext { rt, rs, pos, size } => {
                let mask = if size >= 32 {
                    u32::MAX
                } else {
                    (1u32 << size) - 1
                };
                g!(rt) = (g!(rs) >> (pos & 31)) & mask;
            }
            Ins { rt, rs, pos, size } => {
                let mask = if size >= 32 {
                    u32::MAX
                } else {
                    (1u32 << size) - 1
                };
                let p = (pos & 31) as u32;
                g!(rt) = (g!(rt) & !(mask << p)) | ((g!(rs) & mask) << p);
            }
            Addiupc { rs, off } => g!(rs) = pc.wrapping_add(off as u32),
            Lwpc { rs, off } => {
                let a = pc.wrapping_add(off as u32);
                sh.note_load(a);
                match sh.shared().mem.read::<4>(&self.local, a) {
                    Ok(b) => g!(rs) = u32::from_le_bytes(b),
                    Err(f) => fault!(mem_fault(f)),
                }
            }
            Auipc { rs, imm } => g!(rs) = pc.wrapping_add((imm as u32) << 16),
            Aluipc { rs, imm } => g!(rs) = pc.wrapping_add((imm as u32) << 16) & !0xFFFF,
            Lb { rt, base, off } => g!(rt) = load!(1, base, off)[0] as i8 as i32 as u32,
            Lbu { rt, base, off } => g!(rt) = load!(1, base, off)[0] as u32,
            Lh { rt, base, off } => g!(rt) = i16::from_le_bytes(load!(2, base, off)) as i32 as u32,
            Lhu { rt, base, off } => g!(rt) = u16::from_le_bytes(load!(2, base, off)) as u32,
            Lw { rt, base, off } => g!(rt) = u32::from_le_bytes(load!(4, base, off)),
            Sb { rt, base, off } => store!(base, off, [g!(rt) as u8]),
            Sh { rt, base, off } => store!(base, off, (g!(rt) as u16).to_le_bytes()),
            Sw { rt, base, off } => store!(base, off, g!(rt).to_le_bytes()),
            Ll { rt, base, off } => {
                let a = ea!(base, off);
                if a & 3 != 0 {
                    fault!(mem_fault(sh.shared().mem.misaligned(a, 4, false)));
                }
                g!(rt) = u32::from_le_bytes(load!(4, base, off));
                self.ll_addr = Some(a);
            }
            Sc { rt, base, off } => {
                let a = ea!(base, off);
                if a & 3 != 0 {
                    fault!(mem_fault(sh.shared().mem.misaligned(a, 4, true)));
                }
                if self.ll_addr == Some(a) {
                    store!(base, off, g!(rt).to_le_bytes());
                    g!(rt) = 1;
                } else {
                    g!(rt) = 0;
                }
                self.ll_addr = None;
            }
            Lwc1 { ft, base, off } => {
                let v = u32::from_le_bytes(load!(4, base, off));
                set32!(ft, v);
            }
            Swc1 { ft, base, off } => store!(base, off, fs32!(ft).to_le_bytes()),
            Ldc1 { ft, base, off } => {
                let v = u64::from_le_bytes(load!(8, base, off));
                set64!(ft, v);
            }
            Sdc1 { ft, base, off } => store!(base, off, fs64!(ft).to_le_bytes()),
            Pref { .. } | Sync { .. } | Synci { .. } => {}
            Sigrie { code } => fault!(Fault::ReservedInstruction(0x0417_0000 | code as u32)),
            Teq { rs, rt, code } => {
                if g!(rs) == g!(rt) {
                    fault!(Fault::Trap { code })
                }
            }
            Tne { rs, rt, code } => {
                if g!(rs) != g!(rt) {
                    fault!(Fault::Trap { code })
                }
            }
            Tge { rs, rt, code } => {
                if g!(rs) as i32 >= g!(rt) as i32 {
                    fault!(Fault::Trap { code })
                }
            }
            Tgeu { rs, rt, code } => {
                if g!(rs) >= g!(rt) {
                    fault!(Fault::Trap { code })
                }
            }
            Tlt { rs, rt, code } => {
                if (g!(rs) as i32) < g!(rt) as i32 {
                    fault!(Fault::Trap { code })
                }
            }
            Tltu { rs, rt, code } => {
                if g!(rs) < g!(rt) {
                    fault!(Fault::Trap { code })
                }
            }
            Syscall { code } => fault!(Fault::Syscall(code)),
            Break { code } => fault!(Fault::Break(code)),
            Sdbbp { code } => fault!(Fault::DebugBreakpoint(code)),
            Rdhwr { rt, rd, sel: _ } => {
                g!(rt) = match rd {
                    0 => self.gid,
                    2 => self.retired as u32,
                    3 => 1,
                    29 => 0,
                    _ => fault!(Fault::ReservedInstruction(
                        0x7C00_003B | (rt as u32) << 16 | (rd as u32) << 11
                    )),
                }
            }
            Beq { rs, rt, off } => branch!(g!(rs) == g!(rt), off),
            Bne { rs, rt, off } => branch!(g!(rs) != g!(rt), off),
            Blez { rs, off } => branch!((g!(rs) as i32) <= 0, off),
            Bgtz { rs, off } => branch!((g!(rs) as i32) > 0, off),
            Bltz { rs, off } => branch!((g!(rs) as i32) < 0, off),
            Bgez { rs, off } => branch!((g!(rs) as i32) >= 0, off),
            Bal { off } => {
                branch!(true, off);
                g!(31) = pc.wrapping_add(8);
                self.push_call(pc, pc.wrapping_add(8), next);
            }
            J { target } => {
                cti!();
                self.slot_pc = npc;
                next = Inst::region_target(pc, target);
                self.note_jump(next);
            }
            Jal { target } => {
                cti!();
                self.slot_pc = npc;
                next = Inst::region_target(pc, target);
                g!(31) = pc.wrapping_add(8);
                self.push_call(pc, pc.wrapping_add(8), next);
            }
            Jalr { rd, rs, hb: _ } => {
                cti!();
                self.slot_pc = npc;
                next = g!(rs);
                if rd != 0 {
                    g!(rd) = pc.wrapping_add(8);
                    self.push_call(pc, pc.wrapping_add(8), next);
                } else {
                    self.note_jump(next);
                }
            }
            Bc1eqz { ft, off } => branch!(fs64!(ft) & 1 == 0, off),
            Bc1nez { ft, off } => branch!(fs64!(ft) & 1 != 0, off),
            Bc { off } => compact!(true, off),
            Balc { off } => {
                cti!();
                g!(31) = pc.wrapping_add(4);
                let t = Inst::rel_target(pc, off);
                self.push_call(pc, pc.wrapping_add(4), t);
                compact!(true, off);
            }
            Beqc { rs, rt, off } => compact!(g!(rs) == g!(rt), off),
            Bnec { rs, rt, off } => compact!(g!(rs) != g!(rt), off),
            Bltc { rs, rt, off } => compact!((g!(rs) as i32) < (g!(rt) as i32), off),
            Bgec { rs, rt, off } => compact!((g!(rs) as i32) >= (g!(rt) as i32), off),
            Bltuc { rs, rt, off } => compact!(g!(rs) < g!(rt), off),
            Bgeuc { rs, rt, off } => compact!(g!(rs) >= g!(rt), off),
            Bovc { rs, rt, off } => {
                compact!((g!(rs) as i32).checked_add(g!(rt) as i32).is_none(), off)
            }
            Bnvc { rs, rt, off } => {
                compact!((g!(rs) as i32).checked_add(g!(rt) as i32).is_some(), off)
            }
            Beqzc { rs, off } => compact!(g!(rs) == 0, off),
            Bnezc { rs, off } => compact!(g!(rs) != 0, off),
            Blezc { rt, off } => compact!((g!(rt) as i32) <= 0, off),
            Bgezc { rt, off } => compact!((g!(rt) as i32) >= 0, off),
            Bgtzc { rt, off } => compact!((g!(rt) as i32) > 0, off),
            Bltzc { rt, off } => compact!((g!(rt) as i32) < 0, off),
            Blezalc { rt, off }
            | Bgezalc { rt, off }
            | Bgtzalc { rt, off }
            | Bltzalc { rt, off }
            | Beqzalc { rt, off }
            | Bnezalc { rt, off } => {
                cti!();
                let v = g!(rt) as i32;
                let cond = match *inst {
                    Blezalc { .. } => v <= 0,
                    Bgezalc { .. } => v >= 0,
                    Bgtzalc { .. } => v > 0,
                    Bltzalc { .. } => v < 0,
                    Beqzalc { .. } => v == 0,
                    _ => v != 0,
                };
                // The link register is written whether or not the branch is taken.
                g!(31) = pc.wrapping_add(4);
                if cond {
                    let t = Inst::rel_target(pc, off);
                    self.push_call(pc, pc.wrapping_add(4), t);
                }
                compact!(cond, off);
            }
            Jic { rt, off } => {
                cti!();
                let t = g!(rt).wrapping_add(off as i32 as u32);
                self.note_jump(t);
                return Ok((t, t.wrapping_add(4)));
            }
            Jialc { rt, off } => {
                cti!();
                let t = g!(rt).wrapping_add(off as i32 as u32);
                g!(31) = pc.wrapping_add(4);
                self.push_call(pc, pc.wrapping_add(4), t);
                return Ok((t, t.wrapping_add(4)));
            }
            AddS(x) => arith_s!(x, Arith::Add, false),
            SubS(x) => arith_s!(x, Arith::Sub, false),
            MulS(x) => arith_s!(x, Arith::Mul, false),
            DivS(x) => arith_s!(x, Arith::Div, false),
            AddD(x) => arith_d!(x, Arith::Add, false),
            SubD(x) => arith_d!(x, Arith::Sub, false),
            MulD(x) => arith_d!(x, Arith::Mul, false),
            DivD(x) => arith_d!(x, Arith::Div, false),
            SqrtS(F2 { fd, fs }) => arith!(set32, fd, Fmt::S, Arith::Sqrt, fs32!(fs) as u64, 0, 0),
            SqrtD(F2 { fd, fs }) => arith!(set64, fd, Fmt::D, Arith::Sqrt, fs64!(fs), 0, 0),
            AbsS(F2 { fd, fs }) => set32!(fd, fs32!(fs) & 0x7FFF_FFFF),
            AbsD(F2 { fd, fs }) => set64!(fd, fs64!(fs) & !(1 << 63)),
            NegS(F2 { fd, fs }) => set32!(fd, fs32!(fs) ^ 0x8000_0000),
            NegD(F2 { fd, fs }) => set64!(fd, fs64!(fs) ^ (1 << 63)),
            MovS(F2 { fd, fs }) => set32!(fd, fs32!(fs)),
            MovD(F2 { fd, fs }) => set64!(fd, fs64!(fs)),
            RecipS(F2 { fd, fs }) => {
                let one = Fmt::S.one();
                arith!(set32, fd, Fmt::S, Arith::Div, one, fs32!(fs) as u64, 0)
            }
            RecipD(F2 { fd, fs }) => {
                arith!(set64, fd, Fmt::D, Arith::Div, Fmt::D.one(), fs64!(fs), 0)
            }
            // Two roundings, both steps' exceptions.
            RsqrtS(F2 { fd, fs }) => {
                let rm = self.regs.fcsr;
                let (r, e1) = sf::arith(Arith::Sqrt, Fmt::S, fs32!(fs) as u64, 0, 0, rm);
                let (v, e2) = sf::arith(Arith::Div, Fmt::S, Fmt::S.one(), r, 0, rm);
                fcsr!(e1 | e2);
                set32!(fd, v as u32);
            }
            RsqrtD(F2 { fd, fs }) => {
                let rm = self.regs.fcsr;
                let (r, e1) = sf::arith(Arith::Sqrt, Fmt::D, fs64!(fs), 0, 0, rm);
                let (v, e2) = sf::arith(Arith::Div, Fmt::D, Fmt::D.one(), r, 0, rm);
                fcsr!(e1 | e2);
                set64!(fd, v);
            }
            RintS(F2 { fd, fs }) => fop!(set32, fd, |e| sf::rint(&mut e, Fmt::S, fs32!(fs) as u64)),
            RintD(F2 { fd, fs }) => fop!(set64, fd, |e| sf::rint(&mut e, Fmt::D, fs64!(fs))),
            ClassS(F2 { fd, fs }) => set32!(fd, sf::class(Fmt::S, fs32!(fs) as u64) as u32),
            ClassD(F2 { fd, fs }) => set64!(fd, sf::class(Fmt::D, fs64!(fs))),
            MaddfS(x) => arith_s!(x, Arith::Madd, true),
            MsubfS(x) => arith_s!(x, Arith::Msub, true),
            MaddfD(x) => arith_d!(x, Arith::Madd, true),
            MsubfD(x) => arith_d!(x, Arith::Msub, true),
            // Selects use masks, not branches: their conditions are data (ray tests).
            SelS(F3 { fd, fs, ft }) => {
                let m = (fs32!(fd) & 1).wrapping_neg();
                set32!(fd, (fs32!(ft) & m) | (fs32!(fs) & !m));
            }
            SelD(F3 { fd, fs, ft }) => {
                let m = (fs64!(fd) & 1).wrapping_neg();
                set64!(fd, (fs64!(ft) & m) | (fs64!(fs) & !m));
            }
            SeleqzS(F3 { fd, fs, ft }) => {
                set32!(fd, fs32!(fs) & (fs32!(ft) & 1).wrapping_sub(1))
            }
            SeleqzD(F3 { fd, fs, ft }) => {
                set64!(fd, fs64!(fs) & (fs64!(ft) & 1).wrapping_sub(1))
            }
            SelnezS(F3 { fd, fs, ft }) => {
                set32!(fd, fs32!(fs) & (fs32!(ft) & 1).wrapping_neg())
            }
            SelnezD(F3 { fd, fs, ft }) => {
                set64!(fd, fs64!(fs) & (fs64!(ft) & 1).wrapping_neg())
            }
            MinS(x) => minmax_s!(x, MinMax::Min),
            MaxS(x) => minmax_s!(x, MinMax::Max),
            MinaS(x) => minmax_s!(x, MinMax::MinA),
            MaxaS(x) => minmax_s!(x, MinMax::MaxA),
            MinD(x) => minmax_d!(x, MinMax::Min),
            MaxD(x) => minmax_d!(x, MinMax::Max),
            MinaD(x) => minmax_d!(x, MinMax::MinA),
            MaxaD(x) => minmax_d!(x, MinMax::MaxA),
            CmpS {
                cond,
                f: F3 { fd, fs, ft },
            } => {
                let rm = self.regs.fcsr;
                let (v, e) = fp_compare(Fmt::S, cond, fs32!(fs) as u64, fs32!(ft) as u64, rm);
                fcsr!(e);
                set32!(fd, v as u32);
            }
            CmpD {
                cond,
                f: F3 { fd, fs, ft },
            } => {
                let (v, e) = fp_compare(Fmt::D, cond, fs64!(fs), fs64!(ft), self.regs.fcsr);
                fcsr!(e);
                set64!(fd, v);
            }
            Cvt {
                op,
                f: F2 { fd, fs },
            } => {
                fp.flush(&mut self.regs.fcsr);
                if let Err(f) = self.convert(op, fd, fs) {
                    fault!(f)
                }
            }
            Mfc1 { rt, fs } => g!(rt) = fs32!(fs),
            Mtc1 { rt, fs } => set32!(fs, g!(rt)),
            Mfhc1 { rt, fs } => g!(rt) = (fs64!(fs) >> 32) as u32,
            Mthc1 { rt, fs } => {
                let v = (fs64!(fs) & 0xFFFF_FFFF) | ((g!(rt) as u64) << 32);
                set64!(fs, v);
            }
            Cfc1 { rt, fs } => {
                fp.flush(&mut self.regs.fcsr);
                let f = self.regs.fcsr;
                g!(rt) = match fs {
                    0 => FIR,
                    25 => 0,
                    26 => f & 0x0003_F07C,
                    28 => (f & 0x0000_0F83) | ((f >> 22) & 4),
                    31 => f,
                    _ => fault!(Fault::ReservedInstruction(
                        0x4440_0000 | (rt as u32) << 16 | (fs as u32) << 11
                    )),
                }
            }
            Ctc1 { rt, fs } => {
                fp.flush(&mut self.regs.fcsr);
                let v = g!(rt);
                let f = &mut self.regs.fcsr;
                match fs {
                    26 => *f = (*f & !0x0003_F07C) | (v & 0x0003_F07C),
                    28 => *f = (*f & !0x0100_0F83) | (v & 0x0000_0F83) | ((v & 4) << 22),
                    31 => *f = (*f & !FCSR_WRITABLE) | (v & FCSR_WRITABLE),
                    _ => fault!(Fault::ReservedInstruction(
                        0x44C0_0000 | (rt as u32) << 16 | (fs as u32) << 11
                    )),
                }
                let cause = (*f >> 12) & 0x3F;
                let enabled = ((*f >> 7) & 0x1F) | 0x20;
                if cause & enabled != 0 {
                    fault!(Fault::FpException { cause, msa: false })
                }
            }
            Mfc2 { rt, rd, sel: _ } => g!(rt) = self.cop2[(rd & 31) as usize],
            Mtc2 { rt, rd, sel: _ } => self.cop2[(rd & 31) as usize] = g!(rt),
            // The f32 helpers touch only registers: run them inline.
            Trax {
                op: op @ (TraxOp::FMin | TraxOp::FMax),
                rd,
                rs,
                rt,
                sa: _,
            } => set32!(rd, trax_fminmax(op == TraxOp::FMax, fs32!(rs), fs32!(rt))),
            Trax {
                op: TraxOp::InvSqrt,
                rd,
                rs,
                ..
            } => set32!(rd, fops::invsqrt(f32::from_bits(fs32!(rs))).to_bits()),
            Trax { op, rd, rs, rt, sa } => match exec_trax(self, sh, op, rd, rs, rt, sa) {
                Ok(TraxFlow::Next) => {}
                Ok(TraxFlow::Retry) => return Err(StepExit::Flow(TraxFlow::Retry)),
                Ok(TraxFlow::Defer) => return Err(StepExit::Defer),
                Ok(flow) => {
                    // Halt/Block complete the instruction, then stop the thread.
                    self.wait_pc = pc;
                    self.regs.gpr[0] = 0;
                    self.pc = npc;
                    self.npc = next;
                    self.retired += 1;
                    return Err(StepExit::Flow(flow));
                }
                Err(f) => fault!(f),
            },
            Msa(m) => match crate::msa_glue::execute(self, sh, &m) {
                Ok(MsaStep::Done) => {}
                Ok(MsaStep::Defer) => return Err(StepExit::Defer),
                Ok(MsaStep::Branch(taken)) => {
                    // MSA branches have a delay slot.
                    branch!(taken, m.imm);
                }
                Err(f) => fault!(f),
            },
            Reserved(w) => fault!(Fault::ReservedInstruction(w)),
        }
        self.regs.gpr[0] = 0;
        Ok((npc, next))
    }

    pub(crate) fn convert(&mut self, op: Conv, fd: u8, fs: u8) -> Result<(), Fault> {
        use Conv::*;
        let r = &mut self.regs;
        let (fd, fs) = ((fd & 31) as usize, (fs & 31) as usize);
        let mut e = Env::from_fcsr(r.fcsr);
        let e = &mut e;
        let s = r.f32_bits(fs) as u64;
        let d = r.f64_bits(fs);
        let rm = int_round(op, e.mode);
        let (bits, wide) = match op {
            CvtSD => (sf::convert(e, Fmt::D, Fmt::S, d), false),
            CvtSW => (sf::from_int(e, Fmt::S, s as i32 as i128), false),
            CvtSL => (sf::from_int(e, Fmt::S, d as i64 as i128), false),
            CvtDS => (sf::convert(e, Fmt::S, Fmt::D, s), true),
            CvtDW => (sf::from_int(e, Fmt::D, s as i32 as i128), true),
            CvtDL => (sf::from_int(e, Fmt::D, d as i64 as i128), true),
            CvtWS | RoundWS | TruncWS | CeilWS | FloorWS => {
                (sf::to_int(e, Fmt::S, s, rm, true, 32), false)
            }
            CvtWD | RoundWD | TruncWD | CeilWD | FloorWD => {
                (sf::to_int(e, Fmt::D, d, rm, true, 32), false)
            }
            CvtLS | RoundLS | TruncLS | CeilLS | FloorLS => {
                (sf::to_int(e, Fmt::S, s, rm, true, 64), true)
            }
            CvtLD | RoundLD | TruncLD | CeilLD | FloorLD => {
                (sf::to_int(e, Fmt::D, d, rm, true, 64), true)
            }
        };
        if let Err(t) = fpu::update(&mut r.fcsr, e.flags) {
            return Err(Fault::FpException {
                cause: t.cause,
                msa: false,
            });
        }
        if wide {
            r.set_f64_bits(fd, bits);
        } else {
            r.set_f32_bits(fd, bits as u32);
        }
        Ok(())
    }
}

/// `cmp.cond.fmt` in format `f` under FCSR rounding-mode bits `rm`: the result (all ones
/// when the condition holds, else 0) and the raised flags.
#[inline(always)]
pub(crate) fn fp_compare(f: Fmt, cond: u8, a: u64, b: u64, rm: u32) -> (u64, u32) {
    if let Some(rel) = sf::compare_ordered(f, a, b) {
        return ((sf::cond_holds(rel, cond) as u64).wrapping_neg(), 0);
    }
    fp_compare_unordered(f, cond, a, b, rm)
}

/// [`fp_compare`] with a NaN operand.
#[inline(never)]
fn fp_compare_unordered(f: Fmt, cond: u8, a: u64, b: u64, rm: u32) -> (u64, u32) {
    let mut e = Env::from_fcsr(rm);
    let rel = sf::compare(&mut e, f, a, b, cond & 8 != 0);
    ((sf::cond_holds(rel, cond) as u64).wrapping_neg(), e.flags)
}

/// `min`/`max`/`mina`/`maxa.fmt` under FCSR rounding-mode bits `rm`: result and flags.
#[inline(always)]
pub(crate) fn fp_min_max(f: Fmt, kind: MinMax, a: u64, b: u64, rm: u32) -> (u64, u32) {
    let mut e = Env::from_fcsr(rm);
    let v = sf::min_max(&mut e, f, a, b, kind);
    (v, e.flags)
}

/// `trax.fmin`/`trax.fmax` (`max`) of two f32 bit patterns.
#[inline(always)]
pub(crate) fn trax_fminmax(max: bool, a: u32, b: u32) -> u32 {
    let (a, b) = (f32::from_bits(a), f32::from_bits(b));
    if a.is_nan() || b.is_nan() {
        let v = if max {
            fops::fmax(a, b)
        } else {
            fops::fmin(a, b)
        };
        v.to_bits()
    } else {
        fminmax_num(a, b, max)
    }
}

/// `fops::fmin`/`fmax` of two numbers (no NaN), without data-dependent branches: the
/// smaller (larger) operand, or for equal operands the OR (AND) of their bits, which
/// picks -0 (+0) from a pair of zeros.
#[inline(always)]
fn fminmax_num(a: f32, b: f32, max: bool) -> u32 {
    let (ab, bb) = (a.to_bits(), b.to_bits());
    let first = if max { a > b } else { a < b };
    let pick = if first { ab } else { bb };
    let tie = if max { ab & bb } else { ab | bb };
    if a == b {
        tie
    } else {
        pick
    }
}

/// The rounding of a conversion to an integer: its own, or FCSR's (`current`).
fn int_round(op: Conv, current: Round) -> Round {
    use Conv::*;
    match op {
        RoundWS | RoundWD | RoundLS | RoundLD => Round::Nearest,
        TruncWS | TruncWD | TruncLS | TruncLD => Round::Zero,
        CeilWS | CeilWD | CeilLS | CeilLD => Round::Up,
        FloorWS | FloorWD | FloorLS | FloorLD => Round::Down,
        _ => current,
    }
}

/// FCSR cause and flag bits of FPU operations not yet written to `RegFile::fcsr`.
///
/// Writing FCSR after every FPU operation chains the operations through one memory word;
/// the interpreters keep these bits in registers instead and fold them in before anything
/// reads or writes FCSR (`cfc1`, `ctc1`, conversions, an FP trap) and when they return.
/// `cause`: the last operation's exceptions, with [`FpPending::DIRTY`] once there is
/// something to fold; `flags`: every exception raised since the last fold. (Flags only
/// accumulate and cause is overwritten, so the fold equals the per-operation updates.)
#[derive(Clone, Copy, Default)]
pub(crate) struct FpPending {
    cause: u32,
    flags: u32,
}

impl FpPending {
    const DIRTY: u32 = 1 << 31;

    /// Records an operation that raised `exc` (no enabled exception among it).
    #[inline(always)]
    pub(crate) fn record(&mut self, exc: u32) {
        self.cause = exc | Self::DIRTY;
        self.flags |= exc;
    }

    /// Folds the pending bits into `fcsr`.
    #[inline(always)]
    pub(crate) fn flush(&mut self, fcsr: &mut u32) {
        if self.cause & Self::DIRTY != 0 {
            let cause = self.cause & 0x3F;
            let flags = self.flags & 0x1F;
            *fcsr = (*fcsr & !(0x3F << 12)) | (cause << 12) | (flags << 2);
            *self = FpPending::default();
        }
    }
}

/// Internal early exit of [`Thread::step`] (small, so the hot path returns in registers;
/// the fault itself waits in `Thread::pending_fault`).
#[derive(Clone, Copy)]
enum StepExit {
    Fault,
    Defer,
    Flow(TraxFlow),
}

impl Thread {
    #[cold]
    #[inline(never)]
    fn set_fault(&mut self, f: Fault) -> StepExit {
        self.pending_fault = Some(f);
        StepExit::Fault
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::memory::{Perms, Segment};
    use crate::thread::Shared;

    /// A thread about to run `words` (then `trax.halt`); only the first `text` words (all
    /// if `None`) are predecoded, the rest is decoded on the fly.
    fn setup(words: &[u32], text: Option<usize>) -> (Thread, Shared) {
        let mut w = words.to_vec();
        w.push(0x7000_0007); // trax.halt
        let data: Vec<u8> = w.iter().flat_map(|x| x.to_le_bytes()).collect();
        let segs = vec![
            Segment::new("text", 0x10_0000, data, Perms::RX),
            Segment {
                name: "data".into(),
                addr: 0x20_0000,
                data: vec![0; 64],
                size: 64,
                perms: Perms::RW,
            },
        ];
        let n = text.unwrap_or(w.len()) as u32;
        let sh = Shared::one_thread(&segs, 0x10_0000, n);
        (Thread::new(0x10_0000, 0, 0, 0, 4096, 0), sh)
    }

    /// Runs `words` (then `trax.halt`) on one thread with `init` applied to its registers.
    fn run(words: &[u32], init: impl FnOnce(&mut Thread)) -> (Thread, Stop) {
        let (mut t, mut sh) = setup(words, None);
        init(&mut t);
        let stop = t.run(&mut sh, 1000);
        (t, stop)
    }

    /// One word per branch/jump variant (and two that are not), testing `$2`/`$3`, `$f1`
    /// or `$w1`, branching +16 bytes (from the instruction after it).
    fn cti_words() -> Vec<u32> {
        let (s, t) = (2u32 << 21, 3u32 << 16);
        let op = |o: u32| o << 26;
        let off16 = 4u32;
        vec![
            op(4) | s | t | off16,                       // beq
            op(5) | s | t | off16,                       // bne
            op(6) | s | off16,                           // blez
            op(7) | s | off16,                           // bgtz
            op(1) | s | off16,                           // bltz
            op(1) | s | (1 << 16) | off16,               // bgez
            op(1) | (0x11 << 16) | off16,                // bal
            op(2) | 0x4_0010,                            // j
            op(3) | 0x4_0010,                            // jal
            s | 9,                                       // jr $2
            s | (31 << 11) | 9,                          // jalr $2
            s | (5 << 11) | 9,                           // jalr $5, $2
            op(0x11) | (9 << 21) | (1 << 16) | off16,    // bc1eqz $f1
            op(0x11) | (13 << 21) | (1 << 16) | off16,   // bc1nez $f1
            op(0x32) | off16,                            // bc
            op(0x3A) | off16,                            // balc
            op(8) | (2 << 21) | t | off16,               // beqc $2, $3
            op(0x18) | (2 << 21) | t | off16,            // bnec $2, $3
            op(0x17) | (2 << 21) | t | off16,            // bltc $2, $3
            op(0x16) | (2 << 21) | t | off16,            // bgec $2, $3
            op(7) | (2 << 21) | t | off16,               // bltuc $2, $3
            op(6) | (2 << 21) | t | off16,               // bgeuc $2, $3
            op(8) | (3 << 21) | (2 << 16) | off16,       // bovc $3, $2
            op(0x18) | (3 << 21) | (2 << 16) | off16,    // bnvc $3, $2
            op(0x36) | s | off16,                        // beqzc $2
            op(0x3E) | s | off16,                        // bnezc $2
            op(0x16) | t | off16,                        // blezc $3
            op(0x16) | (3 << 21) | t | off16,            // bgezc $3
            op(0x17) | t | off16,                        // bgtzc $3
            op(0x17) | (3 << 21) | t | off16,            // bltzc $3
            op(6) | t | off16,                           // blezalc $3
            op(6) | (3 << 21) | t | off16,               // bgezalc $3
            op(7) | t | off16,                           // bgtzalc $3
            op(7) | (3 << 21) | t | off16,               // bltzalc $3
            op(8) | t | off16,                           // beqzalc $3
            op(0x18) | t | off16,                        // bnezalc $3
            op(0x36) | t | 0x10,                         // jic $3, 16
            op(0x3E) | t | 0x10,                         // jialc $3, 16
            op(0x11) | (0x0B << 21) | (1 << 16) | off16, // bz.v $w1
            op(0x11) | (0x0F << 21) | (1 << 16) | off16, // bnz.v $w1
            0x2404_0001,                                 // addiu $4, $0, 1
            0x7C08_103B,                                 // rdhwr $8, $2
        ]
    }

    /// Both interpreters do what `Inst`'s control-flow facts say: a delay slot follows
    /// exactly the `Cti::DelaySlot` instructions, a forbidden slot exactly the untaken
    /// `Cti::CompactBranch`es, taken branches go to `branch_target`, calls write
    /// `return_address` to `link_reg` (and nothing else writes `$31`).
    #[test]
    fn control_flow_facts_match_execution() {
        use crate::decode::{decode, Cti};
        let mut seen = std::collections::BTreeSet::new();
        let (mut taken, mut untaken) = (0, 0);
        // The reference interpreter (the branch first in the text), and the fast engine
        // (after a `nop`, so the branch is in a block: a branch first in the text may
        // follow a slot and is left to the reference).
        for (w, fast) in cti_words()
            .into_iter()
            .flat_map(|w| [(w, false), (w, true)])
        {
            let inst = decode(w);
            let name = format!("{inst:?}");
            seen.insert(name.split([' ', '(']).next().unwrap().to_string());
            let pc = if fast { 0x10_0004u32 } else { 0x10_0000 };
            for (v2, v3) in [
                (0u32, 0u32),
                (1, 0),
                (0, 1),
                (u32::MAX, 1),
                (0x7FFF_FFFF, 1),
                (5, 5),
            ] {
                let words = if fast {
                    [0, w, 0, 0, 0, 0, 0, 0]
                } else {
                    [w, 0, 0, 0, 0, 0, 0, 0]
                };
                let (mut t, mut sh) = setup(&words, None);
                t.regs.gpr[2] = v2;
                t.regs.gpr[3] = v3;
                t.regs.gpr[5] = 0xAAAA;
                t.regs.gpr[31] = 0x5555;
                t.regs.fpr[1] = v2 as u128;
                if fast {
                    assert_eq!(t.run(&mut sh, 2), Stop::Budget, "{name}");
                } else {
                    assert_eq!(t.step_once(&mut sh), Stop::Budget, "{name}");
                }
                let what = format!("{name} with $2={v2:#x} $3={v3:#x}, fast engine: {fast}");
                // Where a taken branch goes: its static target, or the register's.
                let dynamic = match inst {
                    Inst::Jalr { .. } => v2,
                    Inst::Jic { off, .. } | Inst::Jialc { off, .. } => {
                        v3.wrapping_add(off as i32 as u32)
                    }
                    _ => inst.branch_target(pc).unwrap_or(u32::MAX),
                };
                match inst.cti() {
                    Cti::None => {
                        assert_eq!((t.pc, t.npc), (pc + 4, pc + 8), "{what}");
                        assert_ne!(t.slot_pc, pc + 4, "{what}");
                    }
                    Cti::DelaySlot => {
                        assert_eq!((t.pc, t.slot_pc), (pc + 4, pc + 4), "{what}");
                        if t.npc == pc + 8 && dynamic != pc + 8 {
                            untaken += 1;
                        } else {
                            assert_eq!(t.npc, dynamic, "{what}");
                            taken += 1;
                        }
                    }
                    Cti::CompactBranch => {
                        if t.pc == pc + 4 {
                            assert_eq!(
                                (t.npc, t.slot_pc),
                                (pc + 8, pc + 4),
                                "{what}: forbidden slot"
                            );
                            untaken += 1;
                        } else {
                            assert_eq!((t.pc, t.npc), (dynamic, dynamic + 4), "{what}");
                            assert_ne!(t.slot_pc, pc + 4, "{what}");
                            taken += 1;
                        }
                    }
                    Cti::CompactJump => {
                        assert_eq!((t.pc, t.npc), (dynamic, dynamic + 4), "{what}");
                        assert_ne!(t.slot_pc, pc + 4, "{what}");
                    }
                }
                match inst.link_reg() {
                    Some(r) => {
                        assert_eq!(t.regs.gpr[r as usize], inst.return_address(pc), "{what}");
                        if r != 31 {
                            assert_eq!(t.regs.gpr[31], 0x5555, "{what}");
                        }
                    }
                    None => {
                        assert_eq!(t.regs.gpr[31], 0x5555, "{what}");
                        assert_eq!(t.regs.gpr[5], 0xAAAA, "{what}");
                    }
                }
            }
        }
        // Every branch and jump variant was run, taken and not.
        let all = "Beq Bne Blez Bgtz Bltz Bgez Bal J Jal Jalr Bc1eqz Bc1nez Bc Balc Beqc Bnec \
                   Bltc Bgec Bltuc Bgeuc Bovc Bnvc Beqzc Bnezc Blezc Bgezc Bgtzc Bltzc Blezalc \
                   Bgezalc Bgtzalc Bltzalc Beqzalc Bnezalc Jic Jialc Msa Addiu Rdhwr";
        let want: std::collections::BTreeSet<String> =
            all.split_whitespace().map(String::from).collect();
        assert_eq!(seen, want);
        assert!(taken > 50 && untaken > 50, "{taken} taken, {untaken} not");
    }

    /// addiu $4,$0,1 ; beq $0,$0,+8 ; addiu $5,$0,1 (delay slot) ; addiu $6,$0,1
    /// (skipped) ; addiu $7,$0,1 ; rdhwr $8,$2 ; mul.s $f2,$f0,$f1 (inexact)
    const MIXED: [u32; 7] = [
        0x2404_0001,
        0x1000_0002,
        0x2405_0001,
        0x2406_0001,
        0x2407_0001,
        0x7C08_103B,
        0x4601_0082,
    ];

    fn mixed_init(t: &mut Thread) {
        t.regs.set_f32_bits(0, (1.0f32 / 3.0).to_bits());
        t.regs.set_f32_bits(1, 3f32.to_bits());
    }

    #[test]
    fn retired_count_is_exact_mid_chunk() {
        let (t, stop) = run(&MIXED, mixed_init);
        assert_eq!(stop, Stop::Halted);
        let g = &t.regs.gpr;
        assert_eq!((g[4], g[5], g[6], g[7]), (1, 1, 0, 1));
        assert_eq!(g[8], 4, "rdhwr $2 counts the four instructions before it");
        assert_eq!(t.retired, 7, "six instructions and the halt");
    }

    #[test]
    fn budget_boundaries_and_code_outside_the_text_change_nothing() {
        let (whole, _) = run(&MIXED, mixed_init);
        // One instruction per call: every chunk is cut by the budget, including between a
        // branch and its delay slot.
        let (mut t, mut sh) = setup(&MIXED, None);
        mixed_init(&mut t);
        let mut calls = 0;
        while t.run(&mut sh, 1) == Stop::Budget {
            calls += 1;
            assert_eq!(t.retired, calls, "one instruction per call");
        }
        assert_eq!(
            (t.regs.clone(), t.retired),
            (whole.regs.clone(), whole.retired)
        );
        // Only the first two words predecoded: the rest (delay slot included) is decoded
        // on the fly.
        for text in [0, 2, 5] {
            let (mut t, mut sh) = setup(&MIXED, Some(text));
            mixed_init(&mut t);
            assert_eq!(t.run(&mut sh, 1000), Stop::Halted, "text {text}");
            assert_eq!(
                (t.regs.clone(), t.retired),
                (whole.regs.clone(), whole.retired),
                "text {text}"
            );
        }
    }

    #[test]
    fn division_edge_cases() {
        // div $4,$2,$3; mod $5,$2,$3; divu $6,$2,$7; modu $8,$2,$7 (with $7 = 0)
        let words = [0x0043_209A, 0x0043_28DA, 0x0047_309B, 0x0047_40DB];
        let (t, stop) = run(&words, |t| {
            t.regs.gpr[2] = 0x8000_0000;
            t.regs.gpr[3] = u32::MAX; // -1
        });
        assert_eq!(stop, Stop::Halted);
        assert_eq!(t.regs.gpr[4], 0x8000_0000, "INT_MIN / -1 = INT_MIN");
        assert_eq!(t.regs.gpr[5], 0, "INT_MIN mod -1 = 0");
        assert_eq!(t.regs.gpr[6], 0x8000_0000, "x / 0 = x");
        assert_eq!(t.regs.gpr[8], 0, "x mod 0 = 0");
    }

    #[test]
    fn shifts_by_0_and_31_and_multiply_high() {
        // sll $4,$2,0; sra $5,$2,31; srl $6,$2,31; rotr $7,$2,31; muh $8,$2,$2; muhu $9,$2,$2
        let words = [
            0x0002_2000,
            0x0002_2FC3,
            0x0002_37C2,
            0x0022_3FC2,
            0x0042_40D8,
            0x0042_48D9,
        ];
        let (t, _) = run(&words, |t| t.regs.gpr[2] = 0x8000_0001);
        assert_eq!(t.regs.gpr[4], 0x8000_0001);
        assert_eq!(t.regs.gpr[5], u32::MAX);
        assert_eq!(t.regs.gpr[6], 1);
        assert_eq!(t.regs.gpr[7], 0x0000_0003);
        let s = 0x8000_0001u32 as i32 as i64;
        assert_eq!(t.regs.gpr[8], ((s * s) >> 32) as u32);
        assert_eq!(t.regs.gpr[9], ((0x8000_0001u64 * 0x8000_0001) >> 32) as u32);
    }

    #[test]
    fn add_overflow_traps_and_zero_register_stays_zero() {
        // addu $0,$2,$2 then add $4,$2,$2 (overflows)
        let (t, stop) = run(&[0x0042_0021, 0x0042_2020], |t| t.regs.gpr[2] = 0x7FFF_FFFF);
        assert_eq!(t.regs.gpr[0], 0);
        assert_eq!(stop, Stop::Fault(Fault::IntegerOverflow));
        assert_eq!(t.pc, 0x10_0004, "pc stays at the faulting instruction");
        assert_eq!(t.retired, 1);
    }

    #[test]
    fn delay_slot_executes_and_branch_in_slot_is_reserved() {
        // beq $0,$0,+8 ; addiu $4,$0,1 (delay slot) ; addiu $5,$0,1 (skipped) ; addiu $6,$0,1
        let (t, _) = run(
            &[0x1000_0002, 0x2404_0001, 0x2405_0001, 0x2406_0001],
            |_| {},
        );
        assert_eq!((t.regs.gpr[4], t.regs.gpr[5], t.regs.gpr[6]), (1, 0, 1));
        // beq $0,$0,+8 with another beq in its delay slot.
        let (_, stop) = run(&[0x1000_0002, 0x1000_0001, 0, 0], |_| {});
        assert_eq!(stop, Stop::Fault(Fault::BranchInSlot));
    }

    #[test]
    fn compact_branches_and_forbidden_slot() {
        // bnezc $2, +4 (taken: skips one) ; addiu $4,$0,1 ; addiu $5,$0,1
        let (t, _) = run(&[0xF840_0001, 0x2404_0001, 0x2405_0001], |t| {
            t.regs.gpr[2] = 1
        });
        assert_eq!((t.regs.gpr[4], t.regs.gpr[5]), (0, 1));
        // Not taken: the forbidden slot executes; a branch there is reserved.
        let (t, _) = run(&[0xF840_0001, 0x2404_0001, 0x2405_0001], |_| {});
        assert_eq!((t.regs.gpr[4], t.regs.gpr[5]), (1, 1));
        let (_, stop) = run(&[0xF840_0001, 0xC800_0000, 0], |_| {});
        assert_eq!(stop, Stop::Fault(Fault::BranchInSlot));
        // bovc $2,$3 on INT_MAX + 1 is taken.
        let (t, _) = run(&[0x2062_0001, 0x2404_0001, 0x2405_0001], |t| {
            t.regs.gpr[2] = 1;
            t.regs.gpr[3] = 0x7FFF_FFFF;
        });
        assert_eq!((t.regs.gpr[4], t.regs.gpr[5]), (0, 1));
    }

    #[test]
    fn calls_are_tracked_for_backtraces() {
        // balc +4 ; trax.halt ; (callee) jr $ra ; nop
        let (t, stop) = run(&[0xE800_0001, 0x7000_0007, 0x03E0_0009, 0], |_| {});
        assert_eq!(stop, Stop::Halted);
        assert!(t.calls.is_empty(), "return popped the frame: {:?}", t.calls);
        assert_eq!(t.regs.gpr[31], 0x10_0004);
    }

    #[test]
    fn fcsr_cause_is_the_last_operation_and_flags_accumulate() {
        // mtc1 $2,$f0 ; mtc1 $3,$f1 ; mtc1 $5,$f4 ; mul.s $f2,$f0,$f1 (inexact) ;
        // add.s $f3,$f4,$f4 (exact) ; cfc1 $4,$31
        let words = [
            0x4482_0000,
            0x4483_0800,
            0x4485_2000,
            0x4601_0082,
            0x4604_20C0,
            0x4444_F800,
        ];
        let (t, stop) = run(&words, |t| {
            t.regs.gpr[2] = (1.0f32 / 3.0).to_bits();
            t.regs.gpr[3] = 3f32.to_bits();
            t.regs.gpr[5] = 1f32.to_bits();
        });
        assert_eq!(stop, Stop::Halted);
        assert_eq!((t.regs.gpr[4] >> 12) & 0x3F, 0, "cause of the exact add");
        assert_eq!((t.regs.gpr[4] >> 2) & 0x1F, sf::FLAG_I, "sticky flag");
        assert_eq!(t.regs.fcsr, t.regs.gpr[4], "FCSR is written back on exit");
        assert_eq!(t.regs.f32_bits(3), 2f32.to_bits());
        // Without cfc1, the pending bits still reach FCSR when run returns.
        let (t, _) = run(&words[..4], |t| {
            t.regs.gpr[2] = (1.0f32 / 3.0).to_bits();
            t.regs.gpr[3] = 3f32.to_bits();
        });
        assert_eq!((t.regs.fcsr >> 12) & 0x3F, sf::FLAG_I);
        assert_eq!((t.regs.fcsr >> 2) & 0x1F, sf::FLAG_I);
        // An enabled Inexact traps at the mul; the earlier flags are kept. ctc1 $6,$31
        // enables Inexact after a div.s $f5,$f4,$f7 by zero (flag DivZero).
        let words = [
            0x4485_2000,
            0x4600_0003 | 7 << 16 | 4 << 11 | 5 << 6,
            0x44C6_F800,
            0x4482_0000,
            0x4483_0800,
            0x4601_0082,
        ];
        let (t, stop) = run(&words, |t| {
            t.regs.gpr[2] = (1.0f32 / 3.0).to_bits();
            t.regs.gpr[3] = 3f32.to_bits();
            t.regs.gpr[5] = 1f32.to_bits();
            t.regs.gpr[6] = (1 << 7) | (sf::FLAG_Z << 2);
        });
        assert_eq!(
            stop,
            Stop::Fault(Fault::FpException {
                cause: sf::FLAG_I,
                msa: false
            })
        );
        assert_eq!((t.regs.fcsr >> 12) & 0x3F, sf::FLAG_I, "cause");
        assert_eq!((t.regs.fcsr >> 2) & 0x1F, sf::FLAG_Z, "flags");
    }

    #[test]
    fn fpu_conversions_and_fcsr() {
        // mtc1 $2,$f0 ; trunc.w.s $f1,$f0 ; mfc1 $4,$f1 ; cfc1 $5,$31
        let words = [0x4482_0000, 0x4600_004D, 0x4404_0800, 0x4445_F800];
        let (t, _) = run(&words, |t| t.regs.gpr[2] = 3e9f32.to_bits());
        assert_eq!(t.regs.gpr[4], i32::MAX as u32, "saturates");
        assert_eq!((t.regs.gpr[5] >> 12) & 0x3F, sf::FLAG_V, "cause = invalid");
        assert_eq!((t.regs.gpr[5] >> 2) & 0x1F, sf::FLAG_V, "flag = invalid");
        assert_eq!(t.regs.gpr[5] & 0x000C_0000, 0x000C_0000, "NaN2008/ABS2008");
        // An enabled exception traps: ctc1 enables Invalid, then the conversion faults.
        let words = [0x44C6_F800, 0x4482_0000, 0x4600_004D];
        let (_, stop) = run(&words, |t| {
            t.regs.gpr[2] = f32::NAN.to_bits();
            t.regs.gpr[6] = 1 << 11;
        });
        assert_eq!(
            stop,
            Stop::Fault(Fault::FpException {
                cause: sf::FLAG_V,
                msa: false
            })
        );
    }
}
