//! The `gdbstub` target: the machine as a multi-threaded GDB remote target.

use std::collections::BTreeSet;
use std::io::Write;
use std::net::TcpStream;

use gdbstub::common::{Signal, Tid};
use gdbstub::conn::ConnectionExt;
use gdbstub::stub::run_blocking::{BlockingEventLoop, Event, WaitForStopReasonError};
use gdbstub::stub::MultiThreadStopReason;
use gdbstub::target::ext::base::multithread::{
    MultiThreadBase, MultiThreadResume, MultiThreadResumeOps, MultiThreadSchedulerLocking,
    MultiThreadSchedulerLockingOps, MultiThreadSingleStep, MultiThreadSingleStepOps,
};
use gdbstub::target::ext::base::BaseOps;
use gdbstub::target::ext::breakpoints::{
    Breakpoints, BreakpointsOps, SwBreakpoint, SwBreakpointOps,
};
use gdbstub::target::{Target, TargetError, TargetResult};

use super::arch::{MipsRegs, TraxMips, BADVADDR, CAUSE, F0, FCSR, FIR, PC};
use crate::exec::Stop;
use crate::machine::{Machine, Outcome};
use crate::memory::MemFaultKind;
use crate::profile::collect::BlockTable;
use crate::sched::{Driven, Executor, Scheduler};
use crate::thread::{Fault, RunState, Shared, Thread};

/// Instructions run between checks for a GDB interrupt (Ctrl-C).
const POLL_EVERY: u64 = 1 << 20;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Action {
    None,
    Continue,
    Step,
}

/// The machine under GDB control.
pub struct DebugTarget<'a> {
    m: &'a mut Machine,
    out: &'a mut dyn Write,
    sched: Scheduler,
    blocks: BlockTable,
    breakpoints: BTreeSet<u32>,
    actions: Vec<Action>,
    /// The run ended and GDB was told: further resumes report the end again.
    ended: Option<Outcome>,
    /// Thread of the last reported stop.
    last_stop: Option<usize>,
}

impl<'a> DebugTarget<'a> {
    /// Wraps a machine that has not started (or is paused) for debugging.
    pub fn new(m: &'a mut Machine, out: &'a mut dyn Write) -> DebugTarget<'a> {
        DebugTarget {
            blocks: BlockTable::new(&m.shared.program),
            sched: Scheduler::new(m),
            actions: vec![Action::None; m.threads.len()],
            m,
            out,
            breakpoints: BTreeSet::new(),
            ended: None,
            last_stop: None,
        }
    }

    /// The final outcome once the program ended.
    pub fn outcome(&self) -> Option<&Outcome> {
        self.sched.outcome()
    }

    fn thread(&self, tid: Tid) -> Option<usize> {
        let i = tid.get() - 1;
        (i < self.m.threads.len()).then_some(i)
    }

    fn stop_for(&mut self, o: Outcome) -> MultiThreadStopReason<u32> {
        self.ended = Some(o.clone());
        match o {
            Outcome::Finished => MultiThreadStopReason::Exited(0),
            Outcome::Crashed(c) => {
                let idx = self
                    .m
                    .threads
                    .iter()
                    .position(|t| t.gid == c.gid)
                    .unwrap_or(0);
                MultiThreadStopReason::SignalWithThread {
                    tid: tid_of(idx),
                    signal: signal_for(&c.fault),
                }
            }
            Outcome::Deadlock { .. } => MultiThreadStopReason::Terminated(Signal::SIGABRT),
            Outcome::InstructionLimit | Outcome::CycleLimit | Outcome::Livelock => {
                MultiThreadStopReason::Terminated(Signal::SIGXCPU)
            }
        }
    }

    /// Runs the pending resume actions to the next stop. `None`: paused to poll GDB.
    fn advance(&mut self) -> Option<MultiThreadStopReason<u32>> {
        let stop = self.advance_inner();
        if let Some(
            MultiThreadStopReason::SwBreak(tid)
            | MultiThreadStopReason::SignalWithThread { tid, .. },
        ) = stop
        {
            self.last_stop = Some(tid.get() - 1);
        }
        stop
    }

    /// GDB single-steps MIPS by planting a breakpoint at the next pc it computes and
    /// continuing, but its next-pc logic predates MIPS32r6: it takes every compact
    /// branch or jump (`bc`, `balc`, `jic`, `beqzc`...) for a plain instruction. When
    /// GDB continues the thread it stopped last from such an instruction with a
    /// breakpoint right after it, it is stepping: run that one instruction and report
    /// a trap where it really went.
    fn gdb_soft_step(&mut self) -> Option<MultiThreadStopReason<u32>> {
        let i = self.last_stop?;
        let t = self.m.threads.get(i)?;
        if t.state != RunState::Running
            || t.npc != t.pc.wrapping_add(4)
            || !self.breakpoints.contains(&t.pc.wrapping_add(4))
            || !t
                .current_inst(&self.m.shared)
                .is_some_and(|x| x.is_compact())
        {
            return None;
        }
        if let Some(o) = self.sched.step_thread(self.m, self.out, i, 1) {
            return Some(self.stop_for(o));
        }
        let pc = self.m.threads[i].pc;
        Some(if self.breakpoints.contains(&pc) {
            MultiThreadStopReason::SwBreak(tid_of(i))
        } else {
            MultiThreadStopReason::SignalWithThread {
                tid: tid_of(i),
                signal: Signal::SIGTRAP,
            }
        })
    }

    fn advance_inner(&mut self) -> Option<MultiThreadStopReason<u32>> {
        if let Some(o) = self.ended.clone() {
            // A crashed program cannot go on: report its end.
            return Some(match o {
                Outcome::Crashed(c) => MultiThreadStopReason::Terminated(signal_for(&c.fault)),
                o => self.stop_for(o),
            });
        }
        if let Some(i) = self.actions.iter().position(|&a| a == Action::Step) {
            self.actions[i] = Action::None;
            // Step to the next boundary that is not a delay or forbidden slot.
            for _ in 0..4 {
                if let Some(o) = self.sched.step_thread(self.m, self.out, i, 1) {
                    return Some(self.stop_for(o));
                }
                let t = &self.m.threads[i];
                if t.pc != t.slot_pc || t.state != RunState::Running {
                    break;
                }
            }
            return Some(MultiThreadStopReason::SignalWithThread {
                tid: tid_of(i),
                signal: Signal::SIGTRAP,
            });
        }
        if let Some(stop) = self.gdb_soft_step() {
            return Some(stop);
        }
        let mut e = BreakExec {
            blocks: &self.blocks,
            breakpoints: &self.breakpoints,
            hit: false,
            poll: POLL_EVERY,
        };
        match self.sched.run(self.m, self.out, &mut e) {
            Driven::Done(o) => Some(self.stop_for(o)),
            Driven::Paused { thread } if e.hit => {
                Some(MultiThreadStopReason::SwBreak(tid_of(thread)))
            }
            // A debugged run does not watch for livelocks.
            Driven::Paused { .. } | Driven::Livelock(_) => None,
        }
    }
}

fn tid_of(idx: usize) -> Tid {
    Tid::new(idx + 1).unwrap_or(Tid::MIN)
}

/// The signal GDB shows for a fault.
pub fn signal_for(f: &Fault) -> Signal {
    match f {
        Fault::Memory { fault, .. } if fault.kind == MemFaultKind::Misaligned => Signal::SIGBUS,
        Fault::Memory { .. }
        | Fault::BadIndex { .. }
        | Fault::StreamFull { .. }
        | Fault::SpillAreaFull { .. }
        | Fault::RayTooLong { .. } => Signal::SIGSEGV,
        Fault::PipeMode { .. } => Signal::SIGILL,
        Fault::ReservedInstruction(_) | Fault::BranchInSlot => Signal::SIGILL,
        Fault::IntegerOverflow | Fault::FpException { .. } | Fault::Trap { code: 7 } => {
            Signal::SIGFPE
        }
        Fault::Trap { .. } | Fault::Break(_) | Fault::DebugBreakpoint(_) => Signal::SIGTRAP,
        Fault::Syscall(_) => Signal::SIGSYS,
        Fault::Abort { .. } => Signal::SIGABRT,
    }
}

/// Runs threads in basic-block chunks, stopping before a breakpoint address.
struct BreakExec<'b> {
    blocks: &'b BlockTable,
    breakpoints: &'b BTreeSet<u32>,
    hit: bool,
    poll: u64,
}

impl Executor for BreakExec<'_> {
    fn exec(&mut self, _idx: usize, t: &mut Thread, sh: &mut Shared, budget: u64) -> Stop {
        let budget = budget.min(self.poll);
        let end = t.retired.saturating_add(budget);
        loop {
            let left = end - t.retired;
            if left == 0 {
                break;
            }
            let pc = t.pc;
            let len = if t.npc == pc.wrapping_add(4) {
                self.blocks.len_at(pc)
            } else {
                1
            }
            .min(left);
            let span_end = pc.wrapping_add(4 * len as u32);
            // GDB steps over the breakpoint it resumes from, so any breakpoint stops.
            let len = match self.breakpoints.range(pc..span_end.max(pc)).next() {
                Some(&b) if b == pc => {
                    self.hit = true;
                    return Stop::Budget;
                }
                Some(&b) => ((b - pc) / 4) as u64,
                None => len,
            };
            let before = t.retired;
            let stop = t.run(sh, len);
            self.poll = self.poll.saturating_sub(t.retired - before);
            if stop != Stop::Budget {
                return stop;
            }
        }
        // With `poll` used up, `pause` lets the event loop look for a GDB interrupt.
        Stop::Budget
    }

    fn pause(&self) -> bool {
        self.hit || self.poll == 0
    }
}

impl Target for DebugTarget<'_> {
    type Arch = TraxMips;
    type Error = String;

    fn base_ops(&mut self) -> BaseOps<'_, TraxMips, String> {
        BaseOps::MultiThread(self)
    }

    fn support_breakpoints(&mut self) -> Option<BreakpointsOps<'_, Self>> {
        Some(self)
    }
}

impl MultiThreadBase for DebugTarget<'_> {
    fn read_registers(&mut self, regs: &mut MipsRegs, tid: Tid) -> TargetResult<(), Self> {
        let i = self.thread(tid).ok_or(TargetError::NonFatal)?;
        let t = &self.m.threads[i];
        regs.r = [0; super::arch::NUM_REGS];
        regs.r[..32].copy_from_slice(&t.regs.gpr);
        regs.r[PC] = t.pc;
        for n in 0..32 {
            regs.r[F0 + n] = t.regs.fpr[n] as u32;
        }
        regs.r[FCSR] = t.regs.fcsr;
        regs.r[FIR] = crate::exec::FIR;
        if let Some(Outcome::Crashed(c)) = self.sched.outcome() {
            if c.gid == t.gid {
                if let Fault::Memory { fault, .. } = &c.fault {
                    regs.r[BADVADDR] = fault.addr;
                }
                regs.r[CAUSE] = 0;
            }
        }
        Ok(())
    }

    fn write_registers(&mut self, regs: &MipsRegs, tid: Tid) -> TargetResult<(), Self> {
        let i = self.thread(tid).ok_or(TargetError::NonFatal)?;
        let t = &mut self.m.threads[i];
        t.regs.gpr.copy_from_slice(&regs.r[..32]);
        t.regs.gpr[0] = 0;
        if regs.r[PC] != t.pc {
            t.pc = regs.r[PC];
            t.npc = t.pc.wrapping_add(4);
            t.slot_pc = u32::MAX;
        }
        for n in 0..32 {
            t.regs.set_f32_bits(n, regs.r[F0 + n]);
        }
        t.regs.fcsr = regs.r[FCSR];
        Ok(())
    }

    fn read_addrs(&mut self, start: u32, data: &mut [u8], tid: Tid) -> TargetResult<usize, Self> {
        let i = self.thread(tid).unwrap_or(0);
        let t = &self.m.threads[i];
        for (k, b) in data.iter_mut().enumerate() {
            match self
                .m
                .shared
                .mem
                .read::<1>(&t.local, start.wrapping_add(k as u32))
            {
                Ok([v]) => *b = v,
                Err(_) if k == 0 => return Err(TargetError::NonFatal),
                Err(_) => return Ok(k),
            }
        }
        Ok(data.len())
    }

    fn write_addrs(&mut self, start: u32, data: &[u8], tid: Tid) -> TargetResult<(), Self> {
        let i = self.thread(tid).unwrap_or(0);
        let (sh, t) = (&mut self.m.shared, &mut self.m.threads[i]);
        for (k, &b) in data.iter().enumerate() {
            sh.mem
                .write::<1>(&mut t.local, start.wrapping_add(k as u32), [b])
                .map_err(|_| TargetError::NonFatal)?;
        }
        // Keep the predecoded text in step with memory.
        let (lo, hi) = (start & !3, start.wrapping_add(data.len() as u32));
        let mut a = lo;
        while a < hi {
            if let (Some(w), Some(_)) = (sh.mem.peek_u32(a), sh.program.get(a)) {
                let idx = ((a - sh.program.base) / 4) as usize;
                sh.program.insts[idx] = crate::decode::decode(w);
            }
            a = a.wrapping_add(4);
        }
        Ok(())
    }

    fn list_active_threads(&mut self, f: &mut dyn FnMut(Tid)) -> Result<(), String> {
        for (i, t) in self.m.threads.iter().enumerate() {
            if t.state != RunState::Halted {
                f(tid_of(i));
            }
        }
        Ok(())
    }

    fn support_resume(&mut self) -> Option<MultiThreadResumeOps<'_, Self>> {
        Some(self)
    }
}

impl MultiThreadResume for DebugTarget<'_> {
    fn resume(&mut self) -> Result<(), String> {
        Ok(())
    }

    fn clear_resume_actions(&mut self) -> Result<(), String> {
        self.actions.iter_mut().for_each(|a| *a = Action::None);
        Ok(())
    }

    fn set_resume_action_continue(
        &mut self,
        tid: Tid,
        _signal: Option<Signal>,
    ) -> Result<(), String> {
        if let Some(i) = self.thread(tid) {
            self.actions[i] = Action::Continue;
        }
        Ok(())
    }

    fn support_single_step(&mut self) -> Option<MultiThreadSingleStepOps<'_, Self>> {
        Some(self)
    }

    fn support_scheduler_locking(&mut self) -> Option<MultiThreadSchedulerLockingOps<'_, Self>> {
        Some(self)
    }
}

impl MultiThreadSchedulerLocking for DebugTarget<'_> {
    /// A step runs only the stepped thread anyway; a continue runs the whole chip
    /// (the interleaving of an ordinary run), so the lock changes nothing.
    fn set_resume_action_scheduler_lock(&mut self) -> Result<(), String> {
        Ok(())
    }
}

impl MultiThreadSingleStep for DebugTarget<'_> {
    fn set_resume_action_step(&mut self, tid: Tid, _signal: Option<Signal>) -> Result<(), String> {
        if let Some(i) = self.thread(tid) {
            self.actions[i] = Action::Step;
        }
        Ok(())
    }
}

impl Breakpoints for DebugTarget<'_> {
    fn support_sw_breakpoint(&mut self) -> Option<SwBreakpointOps<'_, Self>> {
        Some(self)
    }
}

impl SwBreakpoint for DebugTarget<'_> {
    fn add_sw_breakpoint(&mut self, addr: u32, _kind: usize) -> TargetResult<bool, Self> {
        self.breakpoints.insert(addr);
        Ok(true)
    }

    fn remove_sw_breakpoint(&mut self, addr: u32, _kind: usize) -> TargetResult<bool, Self> {
        Ok(self.breakpoints.remove(&addr))
    }
}

/// The blocking event loop: runs the machine between GDB packets.
pub enum EventLoop<'a> {
    #[doc(hidden)]
    _Marker(std::marker::PhantomData<&'a ()>),
}

impl<'a> BlockingEventLoop for EventLoop<'a> {
    type Target = DebugTarget<'a>;
    type Connection = TcpStream;
    type StopReason = MultiThreadStopReason<u32>;

    fn wait_for_stop_reason(
        target: &mut DebugTarget<'a>,
        conn: &mut TcpStream,
    ) -> Result<Event<MultiThreadStopReason<u32>>, WaitForStopReasonError<String, std::io::Error>>
    {
        loop {
            if let Some(stop) = target.advance() {
                return Ok(Event::TargetStopped(stop));
            }
            if conn
                .peek()
                .map_err(WaitForStopReasonError::Connection)?
                .is_some()
            {
                let b = conn.read().map_err(WaitForStopReasonError::Connection)?;
                return Ok(Event::IncomingData(b));
            }
        }
    }

    fn on_interrupt(
        target: &mut DebugTarget<'a>,
    ) -> Result<Option<MultiThreadStopReason<u32>>, String> {
        let i = target
            .m
            .threads
            .iter()
            .position(|t| t.state != RunState::Halted)
            .unwrap_or(0);
        Ok(Some(MultiThreadStopReason::SignalWithThread {
            tid: tid_of(i),
            signal: Signal::SIGINT,
        }))
    }
}
