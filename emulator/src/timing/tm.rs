//! One TM during the parallel phase of a quantum: its thread processors, scoreboards,
//! execution units, I-cache banks and L1, stepped cycle by cycle.
//!
//! A TM touches only its own state here (and reads the chip): its threads execute
//! through a [`TmView`], so an instruction that would change chip-wide state (a store to
//! global memory, a global-register, barrier, semaphore, stream or halt operation) claims
//! its timing resources at its issue cycle but is *deferred*: it is recorded, its thread
//! waits for the rest of the quantum, and the serial phase executes it in a fixed order
//! ([`super::engine`]).

use trax_runtime::isa::{TraxOp, UnitClass};

use super::engine::{Counters, Shape, NUM_CLASSES};
use super::naps::{ThreadSet, Wheel};
use super::operands::{classify, MemOp, OpInfo, NUM_SLOTS, PC_BASE};
use crate::chip::{Effects, TmView};
use crate::decode::Inst;
use crate::exec::Stop;
use crate::machine::Crash;
use crate::memsys::{Access, AccessKind, Completion, MemRequest, Stall, TmMem};
use crate::profile::{CostKind, Profiler};
use crate::thread::{RunState, Shared, Thread};

/// Scoreboard slots: [`NUM_SLOTS`] rounded up to a power of two, so that a slot number
/// masked by `SB_SLOTS - 1` indexes without a bounds check.
const SB_SLOTS: usize = NUM_SLOTS.next_power_of_two();

/// A pending register in the scoreboard (its cycles are 32-bit, relative to an epoch).
const PENDING32: u32 = u32::MAX;

/// The scoreboard's cycles are rebased when the epoch is this far behind (so they stay
/// far below [`PENDING32`]).
const REBASE_AFTER: u64 = 1 << 31;

/// The timing state of one thread that its turns touch, in one place: whether its next
/// instruction was fetched, its I-cache and units, and its scoreboard: per slot the cycle
/// its value is ready, relative to the TM's epoch ([`PENDING32`] while a load waits for
/// memory), and the text word of the instruction that wrote it. (32-bit cycles: half the
/// bytes a TM's threads touch.)
#[derive(Clone)]
#[repr(C, align(64))]
pub(crate) struct Lane {
    /// Its next instruction was fetched (its I-cache slot taken).
    fetched: bool,
    /// Index in `TmSim::icache_use` of its I-cache's first bank.
    icache: u32,
    /// The cycle after its last L1 bank refusal, relative to the epoch, plus one (0: none
    /// since its last visit), and the refused address: a thread refused at cycle `t`
    /// retries the same access at `t + 1` (nothing else of it changed), so that retry
    /// looks at the bank alone.
    refused: u32,
    bank_addr: u32,
    /// Per unit class: the unit (index in `TmSim::unit_free`) wired to the thread.
    units: [u32; NUM_CLASSES],
    ready: [u32; SB_SLOTS],
    producer: [u32; SB_SLOTS],
}

impl Lane {
    /// The ready cycle of slot `r`, relative to the epoch.
    #[inline(always)]
    fn ready(&self, r: u8) -> u32 {
        self.ready[r as usize & (SB_SLOTS - 1)]
    }

    /// Moves the epoch `shift` cycles later: a ready cycle before the new epoch becomes
    /// the epoch (it is past either way), a pending one stays pending.
    fn rebase(&mut self, shift: u32) {
        self.refused = 0;
        for r in &mut self.ready {
            if *r != PENDING32 {
                *r = r.saturating_sub(shift);
            }
        }
    }
}

/// What a sleeping thread waits for, and so how its cycles count.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum NapKind {
    /// A register (data dependence on a producer).
    Register,
    /// Nothing: the thread halted.
    Halted,
    /// A barrier or semaphore (opened only by the serial phase).
    Barrier,
}

/// A sleeping thread's account: the cycles from `since` on are not counted yet.
#[derive(Clone, Copy, Debug)]
struct Nap {
    kind: NapKind,
    /// The text word of the instruction whose result it waits for (`Register`).
    producer: u32,
    /// First cycle not yet in the counters.
    since: u64,
    /// First cycle not yet charged to the profile.
    prof_since: u64,
}

/// A pending register (waits for a memory completion).
pub(crate) const PENDING: u64 = u64::MAX;

/// An instruction waiting for the serial phase.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Deferred {
    /// Issue cycle.
    pub cycle: u64,
    /// TM and thread within it.
    pub tm: u32,
    pub tid: u32,
    /// Text index of the instruction.
    pub idx: u32,
    /// Its timing facts.
    pub op: Op,
    /// When its destination is ready, before chip-wide ordering (global-register ops are
    /// given their service cycle in the serial phase).
    pub ready_at: u64,
    /// Not an instruction to run: the thread halted (executed already) and the chip's
    /// live-thread count and barriers must learn it.
    pub halted: bool,
}

/// How an instruction claims its timing resource at issue (resolved against the chip's
/// units once per text word, [`super::engine::Shape::resolve`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Claim {
    /// An execution unit of its class: the result is ready `latency` cycles after issue,
    /// the unit accepts its next op `busy` cycles after issue.
    Unit { latency: u32, busy: u32 },
    /// A load or store: the L1, or the local store by address.
    Mem(MemOp),
    /// The TM's fused pipeline: 0 box, 1 triangle.
    Pipe(u8),
    /// No unit: the register file only, or the global registers (ordered chip-wide in
    /// the serial phase).
    Free,
    /// A debug-class op (zero cost) or no instruction (outside the text): the slow path.
    Slow,
}

/// What issuing one instruction needs: the scoreboard slots it reads and writes, its
/// unit (for the counters) and its claim.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Op {
    pub src: [u8; 4],
    pub dst: u8,
    /// Counter index of its unit or class (`UnitClass as u8`, or a unit that takes
    /// instructions: `timing::units`), below `NUM_CLASSES`: private, see [`Op::unit`].
    unit: u8,
    pub reg_accesses: u8,
    pub claim: Claim,
}

const _: () = assert!(NUM_CLASSES <= 256, "counter indices are u8");

impl Op {
    /// An op on the unit of counter index `unit` (panics unless `unit < NUM_CLASSES`;
    /// ops are made once per text word, when a run starts).
    pub fn new(src: [u8; 4], dst: u8, unit: usize, reg_accesses: u8, claim: Claim) -> Op {
        assert!(unit < NUM_CLASSES, "counter index {unit}");
        Op {
            src,
            dst,
            unit: unit as u8,
            reg_accesses,
            claim,
        }
    }

    /// Counter index of its unit, below `NUM_CLASSES`: indexes the counters and the
    /// thread's units without bounds checks (the issue loop's hottest lines).
    #[inline(always)]
    pub fn unit(&self) -> usize {
        let k = usize::from(self.unit);
        // SAFETY: `unit` is private to this module; an `Op` is made by `Op::new`, which
        // checks `unit < NUM_CLASSES`, and in this module only changed to
        // `UnitClass::LocalStore` (`issue`), an ISA class index, below
        // `UnitClass::COUNT <= NUM_CLASSES`. Every timing run exercises it
        // (`units::toy::tests` with a unit index beyond the ISA classes).
        unsafe { std::hint::assert_unchecked(k < NUM_CLASSES) };
        k
    }
}

/// What a TM's quantum left for the serial phase, as bits: host threads OR them into the
/// word that reports their finished TMs, so the serial phase learns from one cache line per
/// host thread whether it must look at any TM at all (other TM state stays in its host
/// thread's cache).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct Summary(pub u8);

impl Summary {
    /// An instruction issued.
    pub const PROGRESSED: u8 = 1;
    /// Prints to merge (counters stay with the TM until the end of the run).
    pub const EFFECTS: u8 = 2;
    /// Deferred instructions to run.
    pub const DEFERRED: u8 = 4;
    /// A thread faulted.
    pub const CRASH: u8 = 8;
    /// Requests sent to the L2.
    pub const SENT: u8 = 16;

    /// Whether any of `bits` is set.
    pub fn any(self, bits: u8) -> bool {
        self.0 & bits != 0
    }
}

/// How an instruction executed in the parallel phase ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Executed {
    /// Executed.
    Done,
    /// Executed `trax.halt`.
    Halted,
    /// Not executed: chip-wide, for the serial phase.
    Defer,
    /// Faulted (recorded) or waits.
    Stopped,
}

/// A TM's simulation state (aligned apart: TMs run on different host threads).
#[derive(Clone)]
#[repr(align(128))]
pub(crate) struct TmSim {
    pub tm: usize,
    /// Whether the state was reallocated by the host thread that owns the TM.
    pub local: bool,
    /// The last quantum's results.
    pub summary: Summary,
    /// Instructions issued so far (the host's work, for balancing TMs over host threads).
    pub work: u64,
    pub threads: Vec<Thread>,
    lanes: Vec<Lane>,
    /// The cycle the scoreboards' cycles count from.
    epoch: u64,
    /// The threads visited each cycle: those that may issue, or whose wait must be looked
    /// at every cycle (resource conflicts, stream scheduling). The others sleep: frozen,
    /// or in `asleep` with a [`Nap`], on the wheel (a register ready at a known cycle),
    /// in `pending` (a load whose line has not arrived), in `barrier`, or halted.
    active: ThreadSet,
    /// Waiting for their deferred instruction (until the next quantum); their cycles are
    /// counted when they freeze.
    frozen: ThreadSet,
    /// Sleeping with cycles counted when they wake ([`Nap`]).
    asleep: ThreadSet,
    naps: Vec<Nap>,
    wheel: Wheel,
    pending: ThreadSet,
    barrier: ThreadSet,
    /// Scratch: threads the wheel wakes this cycle.
    woken: ThreadSet,
    /// The end of the quantum being simulated, and of the last one simulated.
    quantum_end: u64,
    ran_to: u64,
    /// Per unit (class after class, see [`unit_base`]): first cycle it accepts an op.
    unit_free: Vec<u64>,
    /// Per I-cache bank: (cycle, fetches it served in that cycle).
    icache_use: Vec<(u64, u32)>,
    pub mem: TmMem,
    pub fx: Effects,
    pub deferred: Vec<Deferred>,
    /// The first fault of this quantum: (cycle, thread, report).
    pub crash: Option<(u64, usize, Box<Crash>)>,
    completions: Vec<Completion>,
    /// The `trax.setpipe` mode the units are configured for, and since when.
    pub mode: u8,
    pub mode_since: u64,
    /// The fused pipeline: next initiation cycle, cycle of the current initiation, tests
    /// it has accepted.
    pipe_next: u64,
    pipe_init: u64,
    pipe_used: u32,
}

impl TmSim {
    /// Reallocates the state from the calling host thread (its own heap arena), so host
    /// threads do not write the same cache lines; marks it [`Self::local`]. The threads'
    /// local stores stay where they are: each is a large block of its own (64 KiB by
    /// default) that shares a cache line with other state at its ends at most, and
    /// copying them (256 MiB at 128 TMs x 32 threads) cost every
    /// [`super::engine::Engine::run`], so every detailed window of a sampled run.
    pub fn relocate(&mut self) {
        let stores: Vec<Vec<u8>> = self
            .threads
            .iter_mut()
            .map(|t| std::mem::take(&mut t.local))
            .collect();
        *self = self.clone();
        for (t, store) in self.threads.iter_mut().zip(stores) {
            t.local = store;
        }
        self.local = true;
    }

    pub fn new(tm: usize, threads: Vec<Thread>, mem: TmMem, shape: &Shape) -> TmSim {
        let n = threads.len();
        let lanes = (0..n)
            .map(|tid| Lane {
                fetched: false,
                icache: (tid % shape.icaches * shape.icache_banks) as u32,
                refused: 0,
                bank_addr: 0,
                units: std::array::from_fn(|k| {
                    let count = shape.units.get(k).map_or(1, |u| u.count as usize);
                    (unit_base(shape, k) + tid * count / n) as u32
                }),
                ready: [0; SB_SLOTS],
                producer: [u32::MAX; SB_SLOTS],
            })
            .collect();
        let nap = Nap {
            kind: NapKind::Register,
            producer: 0,
            since: 0,
            prof_since: 0,
        };
        TmSim {
            tm,
            local: false,
            summary: Summary::default(),
            work: 0,
            lanes,
            epoch: 0,
            active: ThreadSet::full(n),
            frozen: ThreadSet::new(n),
            asleep: ThreadSet::new(n),
            naps: vec![nap; n],
            wheel: Wheel::new(n),
            pending: ThreadSet::new(n),
            barrier: ThreadSet::new(n),
            woken: ThreadSet::new(n),
            quantum_end: 0,
            ran_to: 0,
            unit_free: vec![0; shape.units.iter().map(|u| u.count as usize).sum()],
            icache_use: vec![(0, 0); shape.icache_slots],
            threads,
            mem,
            fx: Effects::default(),
            deferred: Vec::new(),
            crash: None,
            completions: Vec::new(),
            mode: 0,
            mode_since: 0,
            pipe_next: 0,
            pipe_init: 0,
            pipe_used: 0,
        }
    }

    /// Reconfigures the units for `trax.setpipe` mode `mode` at cycle `now`: the FP
    /// multipliers and adders are unavailable for `reconfig_cycles`, then ordinary
    /// instructions share those the pipeline does not reserve. Closes the old mode's
    /// reserved unit-cycles into `c`.
    pub fn set_mode(&mut self, shape: &Shape, c: &mut Counters, mode: u8, now: u64) {
        c.reserved_unit_cycles += (now - self.mode_since.min(now)) * shape.reserved(self.mode);
        self.mode = mode;
        self.mode_since = now;
        let n = self.threads.len();
        for class in [UnitClass::FpMul, UnitClass::FpAdd] {
            let k = class as usize;
            let total = shape.units[k].count as usize;
            let avail = total - shape.reserve(mode, class) as usize;
            let base = unit_base(shape, k);
            for (tid, lane) in self.lanes.iter_mut().enumerate() {
                lane.units[k] = (base + tid * avail / n) as u32;
            }
            for f in &mut self.unit_free[base..base + total] {
                *f = (*f).max(now + shape.reconfig_cycles);
            }
        }
        self.pipe_next = self.pipe_next.max(now + shape.reconfig_cycles);
        self.pipe_used = u32::MAX;
    }

    /// Simulates cycles `[from, to)`.
    pub fn run_quantum(
        &mut self,
        shape: &Shape,
        shared: &Shared,
        c: &mut Counters,
        prof: Option<&mut Profiler>,
        from: u64,
        to: u64,
    ) {
        // Two copies of the cycle loop: without a profiler it has no profiling branches.
        match prof {
            Some(p) => self.run_cycles::<true>(shape, shared, c, &mut Some(p), from, to),
            None => self.run_cycles::<false>(shape, shared, c, &mut None, from, to),
        }
    }

    /// [`Self::run_quantum`], charging the profiler `prof` when `P`.
    // Out of line on purpose: inlined into the engine's worker closure (as LLVM chose once the
    // memory image changed around it) it executed 3% more host instructions (callgrind,
    // path tracer, timing mode).
    #[inline(never)]
    fn run_cycles<const P: bool>(
        &mut self,
        shape: &Shape,
        shared: &Shared,
        c: &mut Counters,
        prof: &mut Option<&mut Profiler>,
        from: u64,
        to: u64,
    ) {
        self.quantum_end = to;
        if from - self.epoch >= REBASE_AFTER {
            let shift = u32::try_from(from - self.epoch).expect("rebased every 2^31 cycles");
            self.lanes.iter_mut().for_each(|s| s.rebase(shift));
            self.epoch = from;
        }
        // Line fills sent by the L2s in the last serial phase.
        let mut completions = std::mem::take(&mut self.completions);
        self.mem.apply_fills(&mut completions);
        for comp in completions.drain(..) {
            let tid = (comp.id >> 8) as usize % self.threads.len();
            let slot = (comp.id & 0xFF) as u8;
            if self.lanes[tid].ready(slot) == PENDING32 {
                let ready = self.rel(comp.cycle.max(from));
                self.lanes[tid].ready[slot as usize & (SB_SLOTS - 1)] = ready;
                // Look at the scoreboard again on the thread's next turn.
                if self.pending.contains(tid) {
                    self.pending.remove(tid);
                    self.wake(shape, c, prof.as_deref_mut(), tid, from);
                }
            }
        }
        self.completions = completions;
        // Threads that waited for the serial phase look again.
        self.active.add_all(&self.frozen);
        self.frozen.clear();
        if !self.barrier.is_empty() {
            let waiting = std::mem::replace(&mut self.barrier, ThreadSet::new(0));
            for tid in waiting.iter() {
                self.wake(shape, c, prof.as_deref_mut(), tid, from);
            }
            self.barrier = waiting;
            self.barrier.clear();
        }
        // A `trax.setpipe` ordered in the last serial phase takes effect now.
        let mode = shared.tm_pipe_mode[self.tm];
        if mode != self.mode {
            self.set_mode(shape, c, mode, from);
        }
        let issued_before = c.tc.issued + c.debug_ops;
        let n = self.threads.len();
        let mut first = (from % n as u64) as usize;
        for now in from..to {
            if self.wheel.due(now, &mut self.woken) {
                let woken = std::mem::replace(&mut self.woken, ThreadSet::new(0));
                for tid in woken.iter() {
                    self.wake(shape, c, prof.as_deref_mut(), tid, now);
                }
                self.woken = woken;
                self.woken.clear();
            }
            // The active threads in rotating order (a thread visited may leave the set,
            // nobody joins it during the cycle).
            for (lo, hi) in [(first, n), (0, first)] {
                let mut k = lo / 64;
                while k * 64 < hi {
                    let mut bits = self.active.word_in(k, lo, hi);
                    while bits != 0 {
                        let tid = k * 64 + bits.trailing_zeros() as usize;
                        bits &= bits - 1;
                        self.visit::<P>(shape, shared, c, prof, tid, now);
                    }
                    k += 1;
                }
            }
            first = if first + 1 == n { 0 } else { first + 1 };
        }
        self.ran_to = to;
        let issued = c.tc.issued + c.debug_ops - issued_before;
        self.work += issued;
        let bit = |b: bool, bit: u8| if b { bit } else { 0 };
        self.summary = Summary(
            bit(issued != 0, Summary::PROGRESSED)
                | bit(self.fx.dirty, Summary::EFFECTS)
                | bit(!self.deferred.is_empty(), Summary::DEFERRED)
                | bit(self.crash.is_some(), Summary::CRASH)
                | bit(self.mem.has_sent(), Summary::SENT),
        );
    }

    /// Active thread `tid`'s turn at cycle `now`: it issues its next instruction or
    /// counts the cycle as a stall.
    #[inline(always)]
    fn visit<const P: bool>(
        &mut self,
        shape: &Shape,
        shared: &Shared,
        c: &mut Counters,
        prof: &mut Option<&mut Profiler>,
        tid: usize,
        now: u64,
    ) {
        // Refused by its L1 bank last cycle: the same access again (fetched, its operands
        // ready), which only its bank can refuse.
        let rel = (now - self.epoch) as u32;
        let lane = &mut self.lanes[tid];
        if lane.refused != 0 {
            let again = lane.refused == rel;
            lane.refused = 0;
            if again && self.mem.l1_bank_refuses(lane.bank_addr, now) {
                lane.refused = rel + 1;
                c.tc.l1_bank_conflict += 1;
                if P {
                    charge(prof, &self.threads[tid], CostKind::ResourceStall);
                }
                return;
            }
        }
        let t = &self.threads[tid];
        if t.state != RunState::Running && !self.resume::<P>(shared, c, prof, tid, now) {
            return;
        }
        let pc = self.threads[tid].pc;
        // Outside the text, a misaligned pc (rotated out of range) or a debug op: the
        // slow path.
        let idx = pc.wrapping_sub(shape.base).rotate_right(2) as usize;
        match shape.ops.get(idx) {
            Some(op) if op.claim != Claim::Slow => {
                self.issue::<P>(shape, shared, c, prof, tid, idx, pc, op, now)
            }
            _ => {
                if let Some((idx, pc, op)) = self.run_slow::<P>(shape, shared, c, prof, tid, now) {
                    self.issue::<P>(shape, shared, c, prof, tid, idx, pc, &op, now);
                }
            }
        }
    }

    /// A thread that is not running at cycle `now`: whether what it waits for happened
    /// (then it runs); if not, the cycle is counted and it may go to sleep.
    #[cold]
    #[inline(never)]
    fn resume<const P: bool>(
        &mut self,
        shared: &Shared,
        c: &mut Counters,
        prof: &mut Option<&mut Profiler>,
        tid: usize,
        now: u64,
    ) -> bool {
        let t = &mut self.threads[tid];
        if t.wake(shared, now) {
            return true;
        }
        match t.state {
            RunState::Halted => {
                c.tc.halted += 1;
                self.sleep(tid, NapKind::Halted, 0, now);
                return false;
            }
            RunState::Barrier { .. } => {
                c.tc.sync_wait += 1;
                if P {
                    charge(prof, &self.threads[tid], CostKind::OtherStall);
                }
                // Only the serial phase opens it: look again next quantum.
                self.sleep(tid, NapKind::Barrier, 0, now);
                self.barrier.insert(tid);
                return false;
            }
            // Released (paying for the decision) or waiting for peers: draining; the
            // TM drained with nothing to read: idle.
            RunState::StreamWait { generation, .. } => {
                let s = &shared.sched.tms[self.tm];
                if s.idle && s.generation == generation {
                    c.tc.stream_idle += 1;
                } else {
                    c.tc.stream_drain += 1;
                }
            }
            RunState::Running => {}
        }
        if P {
            charge(prof, &self.threads[tid], CostKind::OtherStall);
        }
        false
    }

    /// The next instruction of thread `tid` is a debug-class op (zero cost: run it and
    /// look at the one after, up to 64 of them) or outside the text: the instruction to
    /// issue, if the thread still runs.
    #[cold]
    #[inline(never)]
    fn run_slow<const P: bool>(
        &mut self,
        shape: &Shape,
        shared: &Shared,
        c: &mut Counters,
        prof: &mut Option<&mut Profiler>,
        tid: usize,
        now: u64,
    ) -> Option<(usize, u32, Op)> {
        for _ in 0..64 {
            let pc = self.threads[tid].pc;
            let idx = shape.slot_idx(pc);
            let info = if idx < shape.info.len() {
                shape.info[idx]
            } else {
                match self.threads[tid].current_inst(shared) {
                    Some(i) => classify(&i),
                    // A fetch fault: let the functional core report it.
                    None => classify(&Inst::Sync { stype: 0 }),
                }
            };
            if info.class != UnitClass::Debug {
                // The text's resolved op: its unit may be one that takes it.
                let op = shape.ops.get(idx).copied();
                return Some((idx, pc, op.unwrap_or_else(|| shape.resolve(&info))));
            }
            c.debug_ops += 1;
            let done = self.execute(shared, c, tid, idx, now);
            // `trax.clock` (a debug op) reads the cycle counter.
            patch_clock(&shared.program.insts, &mut self.threads[tid], idx, now);
            match done {
                Executed::Done => {}
                Executed::Defer => {
                    let op = shape.resolve(&info);
                    self.defer(c, prof.as_deref_mut(), tid, idx, op, now, now);
                    return None;
                }
                _ => return None,
            }
            if self.threads[tid].state != RunState::Running {
                return None;
            }
        }
        None
    }

    /// Thread `tid` tries to issue `op` (text word `idx` at `pc`) at cycle `now`: fetch,
    /// scoreboard, its unit, the L1 or local store, then functional execution.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn issue<const P: bool>(
        &mut self,
        shape: &Shape,
        shared: &Shared,
        c: &mut Counters,
        prof: &mut Option<&mut Profiler>,
        tid: usize,
        idx: usize,
        pc: u32,
        op: &Op,
        now: u64,
    ) {
        macro_rules! charge {
            ($kind:expr) => {
                if P {
                    charge(prof, &self.threads[tid], $kind)
                }
            };
        }
        let lane = &mut self.lanes[tid];
        // Fetch.
        if !lane.fetched {
            let bank = match shape.icache_bank_mask {
                Some(mask) => (pc >> 2) as usize & mask,
                None => (pc >> 2) as usize % shape.icache_banks,
            };
            let slot = &mut self.icache_use[lane.icache as usize + bank];
            // A slot counts the fetches of the cycle it names.
            if slot.0 != now {
                *slot = (now, 0);
            }
            if slot.1 >= shape.fetches_per_bank {
                c.tc.icache_conflict += 1;
                charge!(CostKind::ResourceStall);
                return;
            }
            slot.1 += 1;
            c.fetches += 1;
            lane.fetched = true;
        }
        // Scoreboard (slot 0, `$0`, is always ready: one branch for the common case).
        let s = &*lane;
        let rel = (now - self.epoch) as u32;
        let latest = s
            .ready(op.src[0])
            .max(s.ready(op.src[1]))
            .max(s.ready(op.src[2]))
            .max(s.ready(op.src[3]))
            .max(s.ready(op.dst));
        if latest > rel {
            self.stall_on_register::<P>(shape, c, prof, tid, op, now);
            return;
        }
        // Unit, memory or local store.
        let mut unit = op.unit();
        let mut ready_at = now + 1;
        let mut pending_load = false;
        match op.claim {
            Claim::Unit { latency, busy } => {
                let free = &mut self.unit_free[lane.units[unit] as usize];
                if *free > now {
                    c.tc.unit_conflict += 1;
                    c.unit_conflicts[unit] += 1;
                    charge!(CostKind::ResourceStall);
                    return;
                }
                *free = now + u64::from(busy);
                ready_at = now + u64::from(latency);
            }
            Claim::Mem(mo) => {
                let t = &self.threads[tid];
                let addr = if mo.base == PC_BASE {
                    pc.wrapping_add(mo.off as u32)
                } else {
                    t.regs.gpr[mo.base as usize & 31].wrapping_add(mo.off as u32)
                };
                if addr >= shared.mem.global_end() {
                    unit = UnitClass::LocalStore as usize;
                    c.local_accesses += 1;
                    ready_at = now + shape.local_latency;
                } else {
                    let req = MemRequest {
                        addr,
                        kind: if mo.store {
                            AccessKind::Write
                        } else {
                            AccessKind::Read
                        },
                        size: mo.size as u32,
                        requester: t.gid,
                        id: ((tid as u64) << 8) | op.dst as u64,
                    };
                    match self.mem.access(&req, now) {
                        Access::Ready(r) => ready_at = r.max(now + 1),
                        Access::Pending => pending_load = true,
                        Access::Stall(st) => {
                            let kind = match st {
                                Stall::L1Bank => {
                                    c.tc.l1_bank_conflict += 1;
                                    let lane = &mut self.lanes[tid];
                                    lane.refused = (now - self.epoch) as u32 + 1;
                                    lane.bank_addr = addr;
                                    CostKind::ResourceStall
                                }
                                Stall::L1Mshr => {
                                    c.tc.l1_mshr_full += 1;
                                    CostKind::MemoryStall
                                }
                            };
                            charge!(kind);
                            return;
                        }
                    }
                }
            }
            // The TM's one fused pipeline: an initiation every `ii` cycles, each taking
            // up to `width` tests issued in its cycle.
            Claim::Pipe(k) => {
                let p = &shape.pipes[k as usize & 1];
                if now >= self.pipe_next {
                    self.pipe_init = now;
                    self.pipe_used = 1;
                    self.pipe_next = now + p.ii;
                } else if now == self.pipe_init && self.pipe_used < p.width {
                    self.pipe_used += 1;
                } else {
                    c.tc.unit_conflict += 1;
                    c.unit_conflicts[unit] += 1;
                    charge!(CostKind::ResourceStall);
                    return;
                }
                ready_at = now + p.latency;
            }
            // Global-register throughput is chip-wide: the serial phase orders them.
            Claim::Free | Claim::Slow => {}
        }
        // Issue: execute functionally now. The issue cycle belongs to the stack and pc
        // before execution (a call pushes, a return pops).
        charge!(CostKind::Issue);
        let op = Op {
            unit: unit as u8,
            ..*op
        };
        match self.execute(shared, c, tid, idx, now) {
            Executed::Done => {}
            Executed::Halted => self.record(tid, idx, op, now, ready_at, true),
            Executed::Defer => {
                self.defer(c, prof.as_deref_mut(), tid, idx, op, now, ready_at);
                return;
            }
            // Barriers and semaphores are chip-wide (deferred); a fault was recorded.
            Executed::Stopped => return,
        }
        let ready = if pending_load { PENDING } else { ready_at };
        self.retire(c, tid, &op, idx, ready);
    }

    /// Thread `tid` cannot issue `op` at cycle `now`: a source or its destination is not
    /// ready. The cycle is charged to the first such register's producer and the thread
    /// sleeps until the register is ready (or its load completes).
    #[inline(never)]
    fn stall_on_register<const P: bool>(
        &mut self,
        shape: &Shape,
        c: &mut Counters,
        prof: &mut Option<&mut Profiler>,
        tid: usize,
        op: &Op,
        now: u64,
    ) {
        let s = &self.lanes[tid];
        let rel = (now - self.epoch) as u32;
        for r in op.src.into_iter().chain(std::iter::once(op.dst)) {
            if r == 0 || s.ready(r) <= rel {
                continue;
            }
            c.tc.data_dependence += 1;
            let p = (s.producer[r as usize & (SB_SLOTS - 1)] as usize).min(shape.info.len());
            c.dep_by_producer[p] += 1;
            let until = match s.ready(r) {
                PENDING32 => PENDING,
                r => self.epoch + u64::from(r),
            };
            if P {
                charge(prof, &self.threads[tid], dep_kind(&shape.info, p));
            }
            // Nothing to do until then.
            self.sleep(tid, NapKind::Register, p as u32, now);
            if until == PENDING {
                self.pending.insert(tid);
            } else {
                self.wheel.put(tid, now, until);
            }
            return;
        }
    }

    /// Counts an issued instruction of thread `tid` (text word `idx`) and makes its
    /// destination ready at `ready` ([`PENDING`] for a load waiting for memory).
    #[inline(always)]
    pub fn retire(&mut self, c: &mut Counters, tid: usize, op: &Op, idx: usize, ready: u64) {
        c.tc.issued += 1;
        c.class_ops[op.unit()] += 1;
        c.reg_accesses += u64::from(op.reg_accesses);
        self.lanes[tid].fetched = false;
        if op.dst != 0 {
            let ready = self.rel(ready);
            let s = &mut self.lanes[tid];
            let slot = op.dst as usize & (SB_SLOTS - 1);
            s.ready[slot] = ready;
            s.producer[slot] = idx as u32;
        }
    }

    /// Cycle `cycle` (at or after the epoch, or [`PENDING`]) in the scoreboard's form.
    #[inline(always)]
    fn rel(&self, cycle: u64) -> u32 {
        if cycle == PENDING {
            return PENDING32;
        }
        match u32::try_from(cycle - self.epoch) {
            Ok(r) if r != PENDING32 => r,
            _ => panic!(
                "ready cycle {cycle} is 2^32 cycles beyond the epoch {}",
                self.epoch
            ),
        }
    }

    /// Records a deferred instruction; its thread waits until the next quantum (those
    /// cycles count as `global_sync` now).
    #[allow(clippy::too_many_arguments)]
    fn defer(
        &mut self,
        c: &mut Counters,
        prof: Option<&mut Profiler>,
        tid: usize,
        idx: usize,
        op: Op,
        now: u64,
        ready_at: u64,
    ) {
        self.record(tid, idx, op, now, ready_at, false);
        self.active.remove(tid);
        self.frozen.insert(tid);
        let rest = self.quantum_end - now - 1;
        c.tc.global_sync += rest;
        if rest > 0 {
            if let Some(p) = prof {
                let t = &self.threads[tid];
                p.charge(t.gid as usize, t, CostKind::OtherStall, rest);
            }
        }
    }

    /// Thread `tid` stalled at cycle `now` (counted) and sleeps from the next cycle on,
    /// waiting for `kind`; the caller puts it where it will be woken.
    #[inline(always)]
    fn sleep(&mut self, tid: usize, kind: NapKind, producer: u32, now: u64) {
        self.active.remove(tid);
        self.asleep.insert(tid);
        self.naps[tid] = Nap {
            kind,
            producer,
            since: now + 1,
            prof_since: now + 1,
        };
    }

    /// Wakes sleeping thread `tid` at cycle `now`, counting the cycles it slept.
    fn wake(
        &mut self,
        shape: &Shape,
        c: &mut Counters,
        prof: Option<&mut Profiler>,
        tid: usize,
        now: u64,
    ) {
        self.account(shape, c, prof, tid, now);
        self.asleep.remove(tid);
        self.active.insert(tid);
    }

    /// Counts sleeping thread `tid`'s cycles up to `upto` (and charges them to `prof`).
    fn account(
        &mut self,
        shape: &Shape,
        c: &mut Counters,
        prof: Option<&mut Profiler>,
        tid: usize,
        upto: u64,
    ) {
        let nap = &mut self.naps[tid];
        let n = upto - nap.since;
        nap.since = upto;
        match nap.kind {
            NapKind::Register => {
                c.tc.data_dependence += n;
                c.dep_by_producer[nap.producer as usize] += n;
            }
            NapKind::Halted => c.tc.halted += n,
            NapKind::Barrier => c.tc.sync_wait += n,
        }
        if let Some(p) = prof {
            let m = upto - nap.prof_since;
            nap.prof_since = upto;
            let kind = match nap.kind {
                NapKind::Register => dep_kind(&shape.info, nap.producer as usize),
                NapKind::Barrier => CostKind::OtherStall,
                NapKind::Halted => return,
            };
            if m > 0 {
                let t = &self.threads[tid];
                p.charge(t.gid as usize, t, kind, m);
            }
        }
    }

    /// Counts the sleeping threads' cycles up to the end of the last quantum simulated,
    /// into `c` (and `prof`, given at the end of a run): before the counters are read.
    pub fn flush(&mut self, shape: &Shape, c: &mut Counters, mut prof: Option<&mut Profiler>) {
        let asleep = std::mem::replace(&mut self.asleep, ThreadSet::new(0));
        for tid in asleep.iter() {
            self.account(shape, c, prof.as_deref_mut(), tid, self.ran_to);
        }
        self.asleep = asleep;
    }

    /// Leaves an instruction (or a halt) for the serial phase.
    fn record(&mut self, tid: usize, idx: usize, op: Op, now: u64, ready_at: u64, halted: bool) {
        self.deferred.push(Deferred {
            cycle: now,
            tm: self.tm as u32,
            tid: tid as u32,
            idx: idx as u32,
            op,
            ready_at,
            halted,
        });
    }

    /// Executes the thread's next instruction functionally with this TM's view.
    #[inline(always)]
    fn execute(
        &mut self,
        shared: &Shared,
        c: &mut Counters,
        tid: usize,
        idx: usize,
        now: u64,
    ) -> Executed {
        let t = &mut self.threads[tid];
        let mut view = TmView {
            shared,
            fx: &mut self.fx,
            cycle: now,
        };
        let done = match t.step_once(&mut view) {
            Stop::Budget => Executed::Done,
            Stop::Halted => Executed::Halted,
            Stop::Defer => return Executed::Defer,
            Stop::Fault(f) => {
                if self.crash.is_none() {
                    self.crash = Some((now, tid, Box::new(Crash::capture(t, f))));
                    // It stops here: it is not visited again (the run ends with the
                    // quantum).
                    self.active.remove(tid);
                }
                return Executed::Stopped;
            }
            Stop::Blocked | Stop::Retry => Executed::Stopped,
        };
        c.issued_at[idx] += 1;
        done
    }
}

/// Charges one cycle of `kind` to thread `t` when profiling.
#[inline(always)]
fn charge(prof: &mut Option<&mut Profiler>, t: &Thread, kind: CostKind) {
    if let Some(p) = prof.as_deref_mut() {
        p.charge(t.gid as usize, t, kind, 1);
    }
}

/// Index in `TmSim::unit_free` of the first unit of class `k`.
fn unit_base(shape: &Shape, k: usize) -> usize {
    shape.units[..k].iter().map(|u| u.count as usize).sum()
}

/// `trax.clock` reads the cycle counter in the timing model.
fn patch_clock(insts: &[Inst], t: &mut Thread, idx: usize, now: u64) {
    if let Some(Inst::Trax {
        op: TraxOp::Clock,
        rd,
        ..
    }) = insts.get(idx)
    {
        if *rd != 0 {
            t.regs.gpr[*rd as usize & 31] = now as u32;
        }
    }
}

/// The profile kind of a data-dependence stall on producer word `p`: waiting for a
/// load's data is a memory stall, anything else a data stall.
#[inline(always)]
fn dep_kind(info: &[OpInfo], p: usize) -> CostKind {
    match info.get(p) {
        Some(i) if i.mem.is_some_and(|mo| !mo.store) => CostKind::MemoryStall,
        _ => CostKind::DataStall,
    }
}

impl AsMut<TmMem> for TmSim {
    fn as_mut(&mut self) -> &mut TmMem {
        &mut self.mem
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Rebasing the scoreboard keeps every future ready cycle and every pending load, and
    /// leaves past cycles past.
    #[test]
    fn rebasing_the_scoreboard_keeps_what_is_not_ready() {
        let mut s = Lane {
            fetched: false,
            icache: 0,
            refused: 0,
            bank_addr: 0,
            units: [0; NUM_CLASSES],
            ready: [0; SB_SLOTS],
            producer: [0; SB_SLOTS],
        };
        s.ready[1] = 10;
        s.ready[2] = 1000;
        s.ready[3] = PENDING32;
        s.ready[4] = 999;
        s.rebase(999);
        assert_eq!(&s.ready[..5], &[0, 0, 1, PENDING32, 0]);
    }

    /// Relocating a TM's state for its host thread copies everything but the threads'
    /// local stores, which stay where they are with their contents.
    #[test]
    fn relocating_keeps_the_local_stores_in_place() {
        use super::super::engine::{PipeSpec, UnitSpec};
        let cfg = crate::timing::config::ChipConfig::preset("tiny").expect("a preset");
        let mut mem =
            crate::memsys::MemSystem::new(&cfg.memory, 1, 1, cfg.clock_mhz()).expect("memory");
        let threads: Vec<Thread> = (0..4u32)
            .map(|i| {
                let mut t = Thread::new(0x1000, i, 0, i, 1024, 7);
                t.local[5] = i as u8 + 1;
                t.regs.gpr[3] = i + 10;
                t
            })
            .collect();
        let pipe = PipeSpec {
            ii: 1,
            latency: 1,
            width: 1,
            fp_mul: 0,
            fp_add: 0,
        };
        let shape = Shape {
            info: Vec::new(),
            ops: Vec::new(),
            base: 0x1000,
            units: vec![
                UnitSpec {
                    count: 1,
                    latency: 1,
                    pipelined: true,
                };
                NUM_CLASSES
            ],
            icaches: 1,
            icache_banks: 1,
            icache_bank_mask: Some(0),
            fetches_per_bank: 1,
            icache_slots: 1,
            local_latency: 1,
            pipes: [pipe, pipe],
            reconfig_cycles: 0,
        };
        let mut sim = TmSim::new(0, threads, mem.take_tms().remove(0), &shape);
        let stores: Vec<*const u8> = sim.threads.iter().map(|t| t.local.as_ptr()).collect();
        let regs: Vec<*const u32> = sim.threads.iter().map(|t| t.regs.gpr.as_ptr()).collect();
        sim.relocate();
        assert!(sim.local);
        for (i, t) in sim.threads.iter().enumerate() {
            assert_eq!(
                t.local.as_ptr(),
                stores[i],
                "thread {i}'s local store was copied"
            );
            assert_ne!(
                t.regs.gpr.as_ptr(),
                regs[i],
                "thread {i} was not reallocated"
            );
            assert_eq!((t.local.len(), t.local[5]), (1024, i as u8 + 1));
            assert_eq!(t.regs.gpr[3], i as u32 + 10);
        }
    }
}
