//! The cycle loop: TMs of in-order single-issue thread processors sharing execution units,
//! I-cache banks, an L1; L2s, DRAM and global registers shared chip-wide.
//!
//! Each cycle, TMs are visited in a rotating order and, inside a TM, threads in a rotating
//! order (round-robin arbitration for shared units, banks and fetch slots). A thread
//! fetches (I-cache bank conflict = stall), checks its scoreboard (sources and destination
//! ready; a stall is charged to the instruction that produced the pending register), claims
//! its unit (or the memory system), then the instruction is executed functionally and its
//! destination becomes ready at issue + latency (or when the memory system delivers the
//! line). Debug-class TRaX ops (prints, counters, profile markers) execute in zero cycles.
//! Everything is visited in a fixed order, so a run is deterministic.

use std::io::Write;

use trax_runtime::isa::{TraxOp, UnitClass};

use super::config::ChipConfig;
use super::operands::{classify, OpInfo, NUM_SLOTS, PC_BASE};
use crate::decode::Inst;
use crate::exec::Stop;
use crate::machine::{drain, release_barriers, Crash, Machine, Outcome};
use crate::memsys::{Access, AccessKind, Completion, MemRequest, MemSystem, Stall};
use crate::profile::{CostKind, Profiler};
use crate::thread::{RunState, Shared, Thread};

/// Number of `UnitClass` values (array index bound).
pub const NUM_CLASSES: usize = 24;

/// Thread-cycle accounting (each live thread lands in exactly one bucket per cycle).
#[derive(Clone, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub struct ThreadCycles {
    /// Issued an instruction.
    pub issued: u64,
    /// Waited for a source or destination register.
    pub data_dependence: u64,
    /// Its execution unit (or the global register file) was taken.
    pub unit_conflict: u64,
    /// Its I-cache bank was out of fetch slots.
    pub icache_conflict: u64,
    /// L1 bank conflict.
    pub l1_bank_conflict: u64,
    /// L2 bank conflict.
    pub l2_bank_conflict: u64,
    /// All L1 MSHRs were busy.
    pub l1_mshr_full: u64,
    /// All L2 MSHRs were busy.
    pub l2_mshr_full: u64,
    /// The DRAM channel queue was full.
    pub dram_queue_full: u64,
    /// Waiting at a barrier or semaphore.
    pub sync_wait: u64,
    /// Halted (finished) while others ran.
    pub halted: u64,
}

/// Raw counters of a run (turned into [`super::stats::TimingStats`]).
#[derive(Clone, Debug, Default)]
pub struct Counters {
    /// Thread-cycle buckets.
    pub tc: ThreadCycles,
    /// Instructions issued per text word (index = (pc - base) / 4); the last entry
    /// collects instructions outside the text.
    pub issued_at: Vec<u64>,
    /// Data-dependence stalls charged to the producing instruction's text word.
    pub dep_by_producer: Vec<u64>,
    /// Unit conflicts by class.
    pub unit_conflicts: [u64; NUM_CLASSES],
    /// Operations by class (for energy).
    pub class_ops: [u64; NUM_CLASSES],
    /// Register-file reads plus writes.
    pub reg_accesses: u64,
    /// Local-store accesses.
    pub local_accesses: u64,
    /// Instruction fetches.
    pub fetches: u64,
    /// Debug-class ops (zero cost).
    pub debug_ops: u64,
}

#[derive(Clone)]
struct Sb {
    ready: [u64; NUM_SLOTS],
    producer: [u32; NUM_SLOTS],
    fetched: bool,
}

/// A pending register (waits for a memory completion).
const PENDING: u64 = u64::MAX;

struct Unit {
    count: u32,
    latency: u64,
    pipelined: bool,
    /// Per TM, per unit instance: first cycle the unit accepts an op.
    free_at: Vec<u64>,
}

/// The timing simulation of one machine.
pub struct Engine<'c> {
    cfg: &'c ChipConfig,
    sb: Vec<Sb>,
    /// Per thread: (cycle before which it stalls on a known data dependence, producer).
    wake: Vec<(u64, u32)>,
    units: Vec<Unit>,
    info: Vec<OpInfo>,
    base: u32,
    mem: MemSystem,
    icache_use: Vec<u32>,
    completions: Vec<Completion>,
    /// Counters.
    pub c: Counters,
    /// Current cycle.
    pub now: u64,
    global_ops: u32,
    max_cycles: Option<u64>,
    /// When set, every live thread-cycle (issue or stall) is charged to the thread's
    /// call stack and pc: issue, data-dependence (on a non-load producer), resource
    /// (unit, I-cache, cache bank), memory (waiting for a load's data, MSHRs full, DRAM
    /// queue full) and other (barrier/semaphore wait) cycles. Halted
    /// threads are not charged, so the profile total is the live thread-cycles.
    pub profiler: Option<Profiler>,
}

fn slot_idx(base: u32, len: usize, pc: u32) -> usize {
    let i = (pc.wrapping_sub(base) >> 2) as usize;
    if pc.wrapping_sub(base) & 3 == 0 && i < len {
        i
    } else {
        len
    }
}

impl<'c> Engine<'c> {
    /// Prepares the model for `machine` (already built with the chip's shape).
    pub fn new(
        cfg: &'c ChipConfig,
        machine: &Machine,
        max_cycles: Option<u64>,
    ) -> Result<Self, String> {
        let tms = cfg.tms as usize;
        let mem = MemSystem::new(&cfg.memory, tms, cfg.tms_per_l2 as usize, cfg.clock_mhz())
            .map_err(|e| e.to_string())?;
        let mut units = Vec::with_capacity(NUM_CLASSES);
        for k in 0..NUM_CLASSES {
            let class = class_from_index(k);
            let u = class.map(|c| cfg.unit(c));
            let (count, latency, pipelined) = match u {
                Some(u) => (u.count, u.latency as u64, u.pipelined),
                None => (1, 1, true),
            };
            units.push(Unit {
                count,
                latency,
                pipelined,
                free_at: vec![0; tms * count as usize],
            });
        }
        let prog = &machine.shared.program;
        let info: Vec<OpInfo> = prog.insts.iter().map(classify).collect();
        let n = info.len() + 1;
        let sb = Sb {
            ready: [0; NUM_SLOTS],
            producer: [u32::MAX; NUM_SLOTS],
            fetched: false,
        };
        Ok(Engine {
            cfg,
            sb: vec![sb; machine.threads.len()],
            wake: vec![(0, 0); machine.threads.len()],
            units,
            info,
            base: prog.base,
            mem,
            icache_use: vec![0; (cfg.icache.per_tm * cfg.icache.banks) as usize],
            completions: Vec::new(),
            c: Counters {
                issued_at: vec![0; n],
                dep_by_producer: vec![0; n],
                ..Counters::default()
            },
            now: 0,
            global_ops: 0,
            max_cycles,
            profiler: None,
        })
    }

    /// The memory system (for statistics).
    pub fn mem(&self) -> &MemSystem {
        &self.mem
    }

    /// Runs `machine` to the end; print output goes to `out`.
    pub fn run(&mut self, m: &mut Machine, out: &mut dyn Write) -> Outcome {
        let tms = self.cfg.tms as usize;
        let n = self.cfg.threads_per_tm as usize;
        let mut idle_cycles = 0u64;
        let outcome = loop {
            if m.shared.live_threads == 0 {
                break Outcome::Finished;
            }
            if let Some(max) = self.max_cycles {
                if self.now >= max {
                    break Outcome::InstructionLimit;
                }
            }
            self.mem.advance_to(self.now, &mut self.completions);
            for c in self.completions.drain(..) {
                let gid = (c.id >> 8) as usize;
                let slot = (c.id & 0xFF) as usize;
                if let Some(s) = self.sb.get_mut(gid) {
                    if s.ready[slot] == PENDING {
                        s.ready[slot] = c.cycle;
                    }
                }
            }
            self.global_ops = 0;
            let issued_before = self.c.tc.issued + self.c.debug_ops;
            let first_tm = (self.now % tms as u64) as usize;
            for k in 0..tms {
                let tm = (first_tm + k) % tms;
                self.icache_use.iter_mut().for_each(|x| *x = 0);
                let first = (self.now % n as u64) as usize;
                for j in 0..n {
                    let tid = (first + j) % n;
                    let gid = tm * n + tid;
                    if let Err(crash) = self.step_thread(m, tm, tid, gid) {
                        drain(&mut m.shared.output, out);
                        return Outcome::Crashed(crash);
                    }
                }
            }
            if !m.shared.output.is_empty() {
                drain(&mut m.shared.output, out);
            }
            if self.c.tc.issued + self.c.debug_ops == issued_before {
                idle_cycles += 1;
            } else {
                idle_cycles = 0;
            }
            self.now += 1;
            // Nobody issued for a long time: a deadlock (or a memory system that stopped
            // making progress).
            if (idle_cycles > 1_000_000 && self.mem.next_event().is_none())
                || idle_cycles > 10_000_000
            {
                let waiting = m.shared.live_threads;
                break Outcome::Deadlock { waiting };
            }
        };
        drain(&mut m.shared.output, out);
        outcome
    }

    fn step_thread(
        &mut self,
        m: &mut Machine,
        tm: usize,
        tid: usize,
        gid: usize,
    ) -> Result<(), Box<Crash>> {
        let now = self.now;
        // Still waiting for a register with a known ready cycle: same stall as last cycle.
        let (until, p) = self.wake[gid];
        if now < until {
            self.c.tc.data_dependence += 1;
            self.c.dep_by_producer[p as usize] += 1;
            let kind = self.dep_kind(p as usize);
            self.charge(m, gid, kind);
            return Ok(());
        }
        let t = &mut m.threads[gid];
        match t.state {
            RunState::Halted => {
                self.c.tc.halted += 1;
                return Ok(());
            }
            RunState::Barrier { reg, generation } => {
                if m.shared.barrier_generation[reg as usize] > generation {
                    t.state = RunState::Running;
                } else {
                    self.c.tc.sync_wait += 1;
                    self.charge(m, gid, CostKind::OtherStall);
                    return Ok(());
                }
            }
            RunState::Running => {}
        }
        // Debug-class ops cost nothing: run them and look at the next instruction.
        for _ in 0..64 {
            let pc = m.threads[gid].pc;
            let idx = slot_idx(self.base, self.info.len(), pc);
            let info = if idx < self.info.len() {
                self.info[idx]
            } else {
                match m.threads[gid].current_inst(&m.shared) {
                    Some(i) => classify(&i),
                    // A fetch fault: let the functional core report it.
                    None => classify(&Inst::Sync { stype: 0 }),
                }
            };
            if info.class == UnitClass::Debug {
                self.c.debug_ops += 1;
                self.execute(m, gid, idx)?;
                if m.threads[gid].state != RunState::Running {
                    return Ok(());
                }
                continue;
            }
            return self.try_issue(m, tm, tid, gid, idx, pc, info, now);
        }
        Ok(())
    }

    #[allow(clippy::too_many_arguments)]
    fn try_issue(
        &mut self,
        m: &mut Machine,
        tm: usize,
        tid: usize,
        gid: usize,
        idx: usize,
        pc: u32,
        mut info: OpInfo,
        now: u64,
    ) -> Result<(), Box<Crash>> {
        // Fetch.
        if !self.sb[gid].fetched {
            let ic = &self.cfg.icache;
            let cache = tid % ic.per_tm as usize;
            let bank = (pc >> 2) as usize % ic.banks as usize;
            let slot = &mut self.icache_use[cache * ic.banks as usize + bank];
            if *slot >= ic.fetches_per_bank {
                self.c.tc.icache_conflict += 1;
                self.charge(m, gid, CostKind::ResourceStall);
                return Ok(());
            }
            *slot += 1;
            self.c.fetches += 1;
            self.sb[gid].fetched = true;
        }
        // Scoreboard.
        let s = &self.sb[gid];
        for r in info.src.into_iter().chain(std::iter::once(info.dst)) {
            if r != 0 && s.ready[r as usize] > now {
                self.c.tc.data_dependence += 1;
                let p = s.producer[r as usize] as usize;
                let p = p.min(self.info.len());
                self.c.dep_by_producer[p] += 1;
                let ready = s.ready[r as usize];
                if ready != PENDING {
                    self.wake[gid] = (ready, p as u32);
                }
                let kind = self.dep_kind(p);
                self.charge(m, gid, kind);
                return Ok(());
            }
        }
        // Unit, memory or local store.
        let t = &m.threads[gid];
        let mut ready_at = now + 1;
        let mut pending_load = false;
        if let Some(mo) = info.mem {
            let addr = if mo.base == PC_BASE {
                pc.wrapping_add(mo.off as u32)
            } else {
                t.regs.gpr[mo.base as usize].wrapping_add(mo.off as u32)
            };
            if addr >= m.shared.mem.global_end() {
                info.class = UnitClass::LocalStore;
                self.c.local_accesses += 1;
                ready_at = now + self.cfg.local_store.latency as u64;
            } else {
                let req = MemRequest {
                    addr,
                    kind: if mo.store {
                        AccessKind::Write
                    } else {
                        AccessKind::Read
                    },
                    size: mo.size as u32,
                    requester: gid as u32,
                    id: ((gid as u64) << 8) | info.dst as u64,
                };
                match self.mem.access(tm, &req, now) {
                    Access::Ready(c) => ready_at = c.max(now + 1),
                    Access::Pending => pending_load = true,
                    Access::Stall(st) => {
                        let kind = match st {
                            Stall::L1Bank => {
                                self.c.tc.l1_bank_conflict += 1;
                                CostKind::ResourceStall
                            }
                            Stall::L2Bank => {
                                self.c.tc.l2_bank_conflict += 1;
                                CostKind::ResourceStall
                            }
                            Stall::L1Mshr => {
                                self.c.tc.l1_mshr_full += 1;
                                CostKind::MemoryStall
                            }
                            Stall::L2Mshr => {
                                self.c.tc.l2_mshr_full += 1;
                                CostKind::MemoryStall
                            }
                            Stall::DramQueue => {
                                self.c.tc.dram_queue_full += 1;
                                CostKind::MemoryStall
                            }
                        };
                        self.charge(m, gid, kind);
                        return Ok(());
                    }
                }
            }
        } else {
            match info.class {
                UnitClass::RegFile => {}
                UnitClass::GlobalRegs => {
                    if self.global_ops >= self.cfg.global_registers.ops_per_cycle {
                        self.c.tc.unit_conflict += 1;
                        self.c.unit_conflicts[UnitClass::GlobalRegs as usize] += 1;
                        self.charge(m, gid, CostKind::ResourceStall);
                        return Ok(());
                    }
                    self.global_ops += 1;
                    ready_at = now + self.cfg.global_registers.latency as u64;
                }
                c => {
                    let n = self.cfg.threads_per_tm as usize;
                    let u = &mut self.units[c as usize];
                    let cnt = u.count as usize;
                    let inst = tm * cnt + tid * cnt / n;
                    if u.free_at[inst] > now {
                        self.c.tc.unit_conflict += 1;
                        self.c.unit_conflicts[c as usize] += 1;
                        self.charge(m, gid, CostKind::ResourceStall);
                        return Ok(());
                    }
                    u.free_at[inst] = if u.pipelined {
                        now + 1
                    } else {
                        now + u.latency
                    };
                    ready_at = now + u.latency;
                }
            }
        }
        // Issue: execute functionally now.
        let gr_wait = info.class == UnitClass::GlobalRegs;
        let before = m.threads[gid].pc;
        // The issue cycle belongs to the stack and pc before execution (a call pushes,
        // a return pops). A global-register op may turn out to be a semaphore retry, so
        // its thread is snapshotted (rare ops, profiling only).
        let snapshot = match (&self.profiler, gr_wait) {
            (Some(_), true) => Some(m.threads[gid].clone()),
            (Some(_), false) => {
                self.charge(m, gid, CostKind::Issue);
                None
            }
            (None, _) => None,
        };
        self.execute(m, gid, idx)?;
        let t = &m.threads[gid];
        let retry = gr_wait && t.pc == before && t.state == RunState::Running;
        if let (Some(p), Some(snap)) = (self.profiler.as_mut(), snapshot) {
            let kind = if retry {
                CostKind::OtherStall
            } else {
                CostKind::Issue
            };
            p.charge(gid, &snap, kind, 1);
        }
        if retry {
            // A semaphore that is not available: retry next cycle.
            self.c.tc.sync_wait += 1;
            return Ok(());
        }
        self.c.tc.issued += 1;
        self.c.class_ops[info.class as usize] += 1;
        self.c.reg_accesses +=
            info.src.iter().filter(|&&r| r != 0).count() as u64 + (info.dst != 0) as u64;
        let s = &mut self.sb[gid];
        s.fetched = false;
        if info.dst != 0 {
            s.ready[info.dst as usize] = if pending_load { PENDING } else { ready_at };
            s.producer[info.dst as usize] = idx as u32;
        }
        Ok(())
    }

    /// The profile kind of a data-dependence stall on producer word `p`: waiting for a
    /// load's data is a memory stall, anything else a data stall.
    #[inline(always)]
    fn dep_kind(&self, p: usize) -> CostKind {
        match self.info.get(p) {
            Some(i) if i.mem.is_some_and(|mo| !mo.store) => CostKind::MemoryStall,
            _ => CostKind::DataStall,
        }
    }

    /// Charges one cycle of `kind` to thread `gid` when profiling.
    #[inline(always)]
    fn charge(&mut self, m: &Machine, gid: usize, kind: CostKind) {
        if let Some(p) = self.profiler.as_mut() {
            p.charge(gid, &m.threads[gid], kind, 1);
        }
    }

    /// Executes the thread's next instruction functionally.
    fn execute(&mut self, m: &mut Machine, gid: usize, idx: usize) -> Result<(), Box<Crash>> {
        let sh: &mut Shared = &mut m.shared;
        let t: &mut Thread = &mut m.threads[gid];
        let inst = if idx < self.info.len() {
            Some(sh.program.insts[idx])
        } else {
            None
        };
        self.c.issued_at[idx] += 1;
        match t.run(sh, 1) {
            Stop::Budget | Stop::Blocked | Stop::Retry => {}
            Stop::Halted => {
                sh.live_threads -= 1;
                release_barriers(sh);
            }
            Stop::Fault(fault) => return Err(Box::new(Crash::capture(t, fault))),
        }
        // `trax.clock` reads the cycle counter in the timing model.
        if let Some(Inst::Trax {
            op: TraxOp::Clock,
            rd,
            ..
        }) = inst
        {
            if rd != 0 {
                t.regs.gpr[rd as usize & 31] = self.now as u32;
            }
        }
        Ok(())
    }
}

/// The `UnitClass` with discriminant `k`, for classes that have configurable units.
fn class_from_index(k: usize) -> Option<UnitClass> {
    super::config::UNIT_NAMES
        .iter()
        .map(|(c, _)| *c)
        .find(|c| *c as usize == k)
}
