//! The cycle loop: TMs of in-order single-issue thread processors sharing execution units,
//! I-cache banks, an L1; L2s, DRAM and global registers shared chip-wide.
//!
//! Time advances in *quanta* of `l1.hit_latency + l2.hit_latency` cycles, each in two
//! phases:
//! 1. Parallel: every TM simulates the quantum's cycles on its own ([`super::tm`]): each
//!    cycle its threads, in a rotating order (round-robin arbitration for units, banks
//!    and fetch slots), fetch (I-cache bank conflict = stall), check their scoreboard
//!    (sources and destination ready; a stall is charged to the instruction that produced
//!    the pending register), claim their unit or the L1, and execute functionally; the
//!    destination is ready at issue + latency, or when the memory system delivers the
//!    line. Debug-class TRaX ops (prints, counters, profile markers) cost zero cycles. L1
//!    misses and stores are *sent* to the L2. TMs are spread over the host threads.
//! 2. Serial: prints and counters are merged in TM order; deferred chip-wide
//!    instructions (stores to global memory, global-register, barrier, semaphore, stream
//!    and halt operations) execute in (issue cycle, rotating TM, thread) order, global
//!    registers serving `ops_per_cycle` per cycle; the L2s and DRAM serve the sent
//!    requests cycle by cycle ([`crate::memsys::ChipMem`]) and send fills back.
//!
//! An L2 reply can never be due inside the quantum that sent its request (the quantum is
//! the L1 + L2 hit latency), so the split loses no memory timing. A thread that issued a
//! deferred instruction waits for the rest of the quantum (`global_sync` cycles): its
//! effect becomes visible to the other TMs at the quantum's end. Every order is fixed
//! and no phase depends on how TMs are spread over host threads, so cycles, statistics
//! and output are identical for any `host_threads`.

use std::io::Write;
use std::sync::Mutex;

use trax_runtime::isa::UnitClass;

use super::config::ChipConfig;
use super::intervals::{IntervalStream, Snapshot};
use super::operands::{classify, OpInfo};
use super::tm::{Claim, Deferred, Op, Summary, TmSim};
use super::units;
use super::workers::{rebalance, Batch, Crew, RoundCell, Rounds};
use crate::chip::Effects;
use crate::exec::Stop;
use crate::livelock::{self, Detection, Watch};
use crate::machine::{drain, Crash, Machine, Outcome};
use crate::memsys::sentinel::DmaJob;
use crate::memsys::{CacheStats, MemStats, MemSystem, RegionMap};
use crate::profile::Profiler;
use crate::run::{Limits, Progress};
use crate::thread::{Shared, Thread};

pub use super::units::NUM_CLASSES;

/// Declares [`ThreadCycles`] and its bucket table [`ThreadCycles::BUCKETS`] from one list:
/// each bucket's field (also its name in the statistics document, `thread_cycles.NAME`, and
/// the interval series `--over-time --y thread_cycles.NAME`), its label in the text
/// summary and what it counts (the field's doc and its `docs/STATS.md` row). Sums,
/// differences, the JSON, the docs and the plots walk the table, so a bucket added here
/// appears in all of them.
macro_rules! thread_cycles {
    ($( $field:ident => ($label:literal, $doc:literal), )*) => {
        /// Thread-cycle accounting (each live thread lands in exactly one bucket per cycle).
        #[derive(Clone, Debug, Default, PartialEq, Eq)]
        pub struct ThreadCycles {
            $( #[doc = $doc] pub $field: u64, )*
        }

        impl ThreadCycles {
            /// Every bucket, in the document's order.
            pub const BUCKETS: &'static [ThreadCycleBucket] = &[
                $( ThreadCycleBucket {
                    name: stringify!($field),
                    label: $label,
                    doc: $doc,
                    get: |t| t.$field,
                    get_mut: |t| &mut t.$field,
                }, )*
            ];
        }
    };
}

thread_cycles! {
    issued => ("issued", "issued an instruction"),
    data_dependence => ("data dependence", "waited for a source or destination register"),
    unit_conflict => ("unit conflict", "its execution unit (or the global registers) was taken"),
    icache_conflict => ("icache conflict", "its I-cache bank was out of fetch slots"),
    l1_bank_conflict => ("L1 bank conflict", "its L1 access was refused because another access had the bank that cycle (equals `timing.memory.l1.bank_retries`)"),
    l1_mshr_full => ("L1 MSHRs full", "every L1 MSHR was busy"),
    sync_wait => ("barrier/semaphore", "waiting at a barrier or semaphore"),
    stream_drain => ("stream drain", "waiting in `trax.strsched` for the TM's other live threads to finish their rays, and for the scheduling decision (`chip.stream_memory.schedule_cycles`)"),
    stream_idle => ("stream idle", "waiting in `trax.strsched` with the TM drained and every ray buffer empty (the TM idles until a ray is written or the frame's stream work is done)"),
    global_sync => ("chip-wide order", "waiting, after a chip-wide instruction (store to global memory, global-register, barrier, semaphore, stream or halt operation), for the end of the quantum in which it is ordered with the other TMs"),
    halted => ("halted", "halted while other threads ran"),
}

/// One thread-cycle bucket of [`ThreadCycles::BUCKETS`].
pub struct ThreadCycleBucket {
    /// Field name: the key in `timing.thread_cycles` of the statistics document.
    pub name: &'static str,
    /// Label in the text summary.
    pub label: &'static str,
    /// What it counts (its `docs/STATS.md` row).
    pub doc: &'static str,
    /// Reads the bucket.
    pub get: fn(&ThreadCycles) -> u64,
    /// The bucket's counter.
    pub get_mut: fn(&mut ThreadCycles) -> &mut u64,
}

impl ThreadCycles {
    /// The bucket-wise difference `self - earlier` (`earlier` a sample of the same run).
    pub fn minus(&self, earlier: &ThreadCycles) -> ThreadCycles {
        let mut d = ThreadCycles::default();
        for b in Self::BUCKETS {
            *(b.get_mut)(&mut d) = (b.get)(self) - (b.get)(earlier);
        }
        d
    }

    /// `docs/STATS.md` rows of the buckets of the object at `path`.
    pub fn md_rows(path: &str) -> String {
        Self::BUCKETS
            .iter()
            .map(|b| super::stat::md_row(&format!("{path}.{}", b.name), "int", b.doc))
            .collect()
    }

    /// `docs/STATS.md` rows of the buckets of the object at `path`, each `as` the bucket of
    /// the object at `of`, `suffix`.
    pub fn md_rows_as(path: &str, of: &str, suffix: &str) -> String {
        let row = |b: &ThreadCycleBucket| {
            let doc = format!("as `{of}.{}`, {suffix}", b.name);
            super::stat::md_row(&format!("{path}.{}", b.name), "int", &doc)
        };
        Self::BUCKETS.iter().map(row).collect()
    }

    /// Adds `o`'s buckets into `self`.
    pub fn add(&mut self, o: &ThreadCycles) {
        for b in Self::BUCKETS {
            *(b.get_mut)(self) += (b.get)(o);
        }
    }
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
    /// FP unit-cycles reserved by fused pipelines (units x cycles in a pipeline mode).
    pub reserved_unit_cycles: u64,
    /// Stream memory: accesses delayed by a busy bank, and the cycles they waited.
    pub stream_bank_conflicts: u64,
    pub stream_conflict_cycles: u64,
    /// Stream memory: rays in flight integrated over cycles (for the mean).
    pub stream_ray_cycles: u64,
    /// Thread-cycles a stream write or read waited for the spill sentinel (from its first
    /// attempt to the one that went through).
    pub stream_spill_stall_cycles: u64,
}

/// Receives a [`Progress`] report every few host milliseconds.
pub type ProgressFn<'a> = &'a mut dyn FnMut(&Progress);

/// Told of a proven livelock; returns whether to stop the run there.
pub type LivelockFn<'a> = &'a mut dyn FnMut(&Detection) -> bool;

/// Cycles between checks of the chip's progress count for the livelock detector.
const LOOK_EVERY: u64 = 1 << 14;

/// Quanta between checks of the host clock for progress reports, at most.
const PROGRESS_EVERY: u64 = 1024;

/// Thread-cycles between checks of the host clock for progress reports (1024 quanta of the
/// `tiny` chip): a chip of many threads or a long quantum checks every few quanta, every
/// quantum at worst, so its reports come as often as a small chip's.
const PROGRESS_THREAD_CYCLES: u64 = 1024 * 4 * 8;

/// Quanta between rebalancings of TMs over host threads (tens of host milliseconds: long
/// enough to measure loads and to repay moving a TM's state to another core).
const REBALANCE_EVERY: u64 = 4096;

/// Most rounds the TMs run without the serial phase (bounds the time between progress
/// reports and rebalancings).
const MAX_FREE_ROUNDS: u64 = 256;

/// A rebalancing must cut the busiest host thread's load by this fraction.
const REBALANCE_MIN_GAIN: f64 = 0.01;

/// Timing facts of one execution-unit class.
#[derive(Clone, Copy, Debug)]
pub(crate) struct UnitSpec {
    pub count: u32,
    pub latency: u64,
    pub pipelined: bool,
}

/// Timing facts of one fused pipeline.
#[derive(Clone, Copy, Debug)]
pub(crate) struct PipeSpec {
    pub ii: u64,
    pub latency: u64,
    pub width: u32,
    /// FP multipliers and adders reserved.
    pub fp_mul: u32,
    pub fp_add: u32,
}

/// What every TM reads and nobody changes during a run.
pub(crate) struct Shape {
    /// Timing facts per text word.
    pub info: Vec<OpInfo>,
    /// Per text word, what issuing it needs (`info` resolved against the units).
    pub ops: Vec<Op>,
    /// First text address.
    pub base: u32,
    /// Per unit class (index = `UnitClass as usize`).
    pub units: Vec<UnitSpec>,
    pub icaches: usize,
    pub icache_banks: usize,
    /// `icache_banks - 1` when it is a power of two.
    pub icache_bank_mask: Option<usize>,
    pub fetches_per_bank: u32,
    /// I-cache bank slots per TM.
    pub icache_slots: usize,
    pub local_latency: u64,
    /// The box (0) and triangle (1) pipelines.
    pub pipes: [PipeSpec; 2],
    /// Cycles a mode change keeps the FP multipliers and adders unavailable.
    pub reconfig_cycles: u64,
}

impl Shape {
    /// The pipeline of `trax.setpipe` mode `mode`, if any.
    pub fn pipe(&self, mode: u8) -> Option<&PipeSpec> {
        match mode {
            1 => Some(&self.pipes[0]),
            2 => Some(&self.pipes[1]),
            _ => None,
        }
    }

    /// Units of `class` (FP multiply or add) the pipeline of `mode` reserves.
    pub fn reserve(&self, mode: u8, class: UnitClass) -> u32 {
        match (self.pipe(mode), class) {
            (Some(p), UnitClass::FpMul) => p.fp_mul,
            (Some(p), UnitClass::FpAdd) => p.fp_add,
            _ => 0,
        }
    }

    /// Units the pipeline of `mode` reserves.
    pub fn reserved(&self, mode: u8) -> u64 {
        self.pipe(mode)
            .map_or(0, |p| u64::from(p.fp_mul + p.fp_add))
    }

    /// What issuing an instruction of timing facts `info` needs on this chip, on its
    /// class's unit (instructions outside the text: no unit takes them).
    pub fn resolve(&self, info: &OpInfo) -> Op {
        resolve(info, info.class as usize, &self.units)
    }

    /// Text index of `pc` (`info.len()` when outside the text or misaligned).
    #[inline(always)]
    pub fn slot_idx(&self, pc: u32) -> usize {
        let len = self.info.len();
        let i = (pc.wrapping_sub(self.base) >> 2) as usize;
        if pc.wrapping_sub(self.base) & 3 == 0 && i < len {
            i
        } else {
            len
        }
    }
}

/// One host thread's counters (aligned apart so two host threads never write the same
/// cache line).
#[repr(align(128))]
struct Part {
    c: Counters,
    /// Whether the counters were reallocated by the host thread that uses them.
    local: bool,
}

/// The timing simulation of one machine.
pub struct Engine<'c> {
    cfg: &'c ChipConfig,
    shape: Shape,
    mem: MemSystem,
    /// Counters (complete after [`Self::run`]).
    pub c: Counters,
    /// Current cycle.
    pub now: u64,
    limits: Limits,
    host_threads: usize,
    /// When set, every live thread-cycle (issue or stall) is charged to the thread's
    /// call stack and pc: issue, data-dependence (on a non-load producer), resource
    /// (unit, I-cache, cache bank), memory (waiting for a load's data, MSHRs full) and
    /// other (barrier/semaphore wait, chip-wide ordering) cycles. Halted threads are not
    /// charged, so the profile total is the live thread-cycles. Profiling runs on one
    /// host thread (with the same results).
    pub profiler: Option<Profiler>,
    /// Called with the run's progress about every 100 ms of host time.
    pub progress: Option<ProgressFn<'c>>,
    /// When set, the run is watched for a livelock ([`crate::livelock`], checked every
    /// 2^14 cycles) and this is told of one; it returns whether to stop the run there
    /// ([`Outcome::Livelock`]). Watching stops after the first.
    pub on_livelock: Option<LivelockFn<'c>>,
    /// The livelock watch (kept across [`Self::run`]s).
    watch: Option<Watch>,
    /// Whether a livelock was found.
    livelocked: bool,
    /// Cycles per statistics interval (`--stats-interval`; a multiple of the quantum,
    /// see [`Self::quantum`]): the counters are sampled at every multiple.
    pub interval: Option<u64>,
    /// Where the samples at interval ends go (required with [`Self::interval`]).
    pub intervals: Option<IntervalStream<'c>>,
    /// The sample taken at [`Self::snap_at`] (after [`Self::run`]).
    pub samples: Vec<Snapshot>,
    /// Also sample the counters at this cycle (a quantum end), for sampled simulation.
    pub snap_at: Option<u64>,
    /// Stop (with [`Outcome::CycleLimit`], setting [`Self::paused`]) at the first quantum
    /// end at which, for any pair, global register `.0` holds at least `.1` (sampled
    /// simulation: the work counter reached a window's end, or the kernel declared its
    /// work counter).
    pub pause_at: Vec<(u32, u32)>,
    /// Whether the last [`Self::run`] stopped at [`Self::pause_at`].
    pub paused: bool,
}

impl<'c> Engine<'c> {
    /// Prepares the model for `machine` (already built with the chip's shape), to be
    /// simulated with `host_threads` host threads until the end or a limit.
    pub fn new(
        cfg: &'c ChipConfig,
        machine: &Machine,
        limits: Limits,
        host_threads: usize,
    ) -> Result<Self, String> {
        let tms = cfg.tms as usize;
        let mut mem = MemSystem::new(&cfg.memory, tms, cfg.tms_per_l2 as usize, cfg.clock_mhz())
            .map_err(|e| e.to_string())?;
        mem.set_regions(&RegionMap::new(
            (machine.shared.mem.segments().iter()).map(|s| (s.name.as_str(), s.addr, s.size)),
            [],
        ));
        let units: Vec<UnitSpec> = (0..NUM_CLASSES)
            .map(
                |k| match units::unit_at(k).map(|u| cfg.unit_named(u.name)) {
                    Some(u) => UnitSpec {
                        count: u.count,
                        latency: u.latency as u64,
                        pipelined: u.pipelined,
                    },
                    None => UnitSpec {
                        count: 1,
                        latency: 1,
                        pipelined: true,
                    },
                },
            )
            .collect();
        let prog = &machine.shared.program;
        let info: Vec<OpInfo> = prog.insts.iter().map(classify).collect();
        let takers = units::takers_present(cfg.units.keys());
        let ops = (prog.insts.iter().zip(&info))
            .map(|(inst, i)| resolve(i, units::counter_of(&takers, inst, i.class), &units))
            .collect();
        let n = info.len() + 1;
        let ic = &cfg.icache;
        Ok(Engine {
            cfg,
            shape: Shape {
                info,
                ops,
                base: prog.base,
                units,
                icaches: ic.per_tm as usize,
                icache_banks: ic.banks as usize,
                icache_bank_mask: ic.banks.is_power_of_two().then(|| ic.banks as usize - 1),
                fetches_per_bank: ic.fetches_per_bank,
                icache_slots: (ic.per_tm * ic.banks) as usize,
                local_latency: cfg.local_store.latency as u64,
                pipes: [&cfg.pipelines.box_pipe, &cfg.pipelines.tri].map(|p| PipeSpec {
                    ii: u64::from(p.ii),
                    latency: u64::from(p.latency),
                    width: p.width,
                    fp_mul: p.fp_mul,
                    fp_add: p.fp_add,
                }),
                reconfig_cycles: u64::from(cfg.pipelines.reconfig_cycles),
            },
            mem,
            c: Counters {
                issued_at: vec![0; n],
                dep_by_producer: vec![0; n],
                ..Counters::default()
            },
            now: 0,
            limits,
            host_threads: host_threads.clamp(1, tms),
            profiler: None,
            progress: None,
            on_livelock: None,
            watch: None,
            livelocked: false,
            interval: None,
            intervals: None,
            samples: Vec::new(),
            snap_at: None,
            pause_at: Vec::new(),
            paused: false,
        })
    }

    /// Replaces the run limits (a later [`Self::run`] continues under these).
    pub fn set_limits(&mut self, limits: Limits) {
        self.limits = limits;
    }

    /// The cumulative counters now, between runs (every counter of earlier
    /// [`Self::run`]s, the memory system's, the stream memory's accesses of `m`).
    pub fn snapshot(&self, m: &Machine) -> Snapshot {
        snapshot_of(self.cfg, &self.c, &self.mem.stats(), &m.shared, self.now)
    }

    /// The memory system, for functional warming between runs (sampled simulation).
    pub fn mem_mut(&mut self) -> &mut MemSystem {
        &mut self.mem
    }

    /// Cycles per quantum: the L1 plus L2 hit latency (an L2 reply is never due sooner).
    pub fn quantum(cfg: &ChipConfig) -> u64 {
        let m = &cfg.memory;
        (u64::from(m.l1.hit_latency) + u64::from(m.l2.hit_latency)).max(1)
    }

    /// The memory system (for statistics).
    pub fn mem(&self) -> &MemSystem {
        &self.mem
    }

    /// Runs `machine` to the end (or a limit); print output goes to `out`. A later call
    /// continues from where this one stopped: the threads' timing state (scoreboards,
    /// units) starts afresh, the memory system's is kept.
    pub fn run(&mut self, m: &mut Machine, out: &mut dyn Write) -> Outcome {
        self.paused = false;
        let tms = self.cfg.tms as usize;
        let n = self.cfg.threads_per_tm as usize;
        let workers = if self.profiler.is_some() {
            1
        } else {
            self.host_threads
        };
        // Hand the threads and L1s to the TMs, the TMs to the host threads.
        let mut threads = std::mem::take(&mut m.threads).into_iter();
        let mut tm_mems = self.mem.take_tms().into_iter();
        let parts: Vec<Mutex<Part>> = (0..workers)
            .map(|_| {
                Mutex::new(Part {
                    c: Counters {
                        issued_at: vec![0; self.c.issued_at.len()],
                        dep_by_producer: vec![0; self.c.issued_at.len()],
                        ..Counters::default()
                    },
                    local: false,
                })
            })
            .collect();
        let sims: Vec<RoundCell<TmSim>> = (0..tms)
            .map(|tm| {
                let ts: Vec<Thread> = threads.by_ref().take(n).collect();
                let mem = tm_mems.next().expect("one L1 per TM");
                RoundCell::new(TmSim::new(tm, ts, mem, &self.shape))
            })
            .collect();
        let mut profiler = self.profiler.take();
        let mut progress = self.progress.take();
        let mut intervals = self.intervals.take();
        let mut on_livelock = self.on_livelock.take();
        // Watch until the first livelock (the watch is then gone for good).
        let mut watch = match (&on_livelock, self.watch.take()) {
            (None, _) => None,
            (Some(_), Some(w)) => Some(w),
            (Some(_), None) if !self.livelocked => Some(Watch::default()),
            (Some(_), None) => None,
        };
        let mut halted_excess = 0u64;
        let mut paused = false;
        let mut base = Counters::default();
        base.add_scalars(&self.c);
        let check_at = match watch {
            Some(_) => self.now + LOOK_EVERY,
            None => u64::MAX,
        };
        let outcome = {
            let shared = RoundCell::new(&mut m.shared);
            let rounds = Rounds::new(tms, workers);
            let Engine {
                cfg,
                shape,
                mem,
                now,
                limits,
                ..
            } = self;
            let (cfg, shape, limits) = (*cfg, &*shape, *limits);
            // Host thread `w` simulates TM `k` over the window `from..to`.
            let job = |w: usize, k: usize, (from, to): (u64, u64), prof: Option<&mut Profiler>| {
                // SAFETY: a round job; the chip state is only read during rounds.
                let sh: &Shared = unsafe { shared.get() };
                let mut p = parts[w].lock().unwrap_or_else(|e| e.into_inner());
                // Reallocate state from the host thread that normally runs it (its own
                // heap arena), so host threads do not write the same cache lines.
                if !p.local {
                    p.local = true;
                    p.c = p.c.clone();
                }
                // SAFETY: the round job of TM `k`: this host thread claimed it.
                let t = unsafe { sims[k].get_mut() };
                if !t.local && rounds.owner(k) == w {
                    t.relocate();
                }
                t.run_quantum(shape, sh, &mut p.c, prof, from, to);
                t.summary.0
            };
            let member_job = |w: usize, k: usize, window: (u64, u64)| job(w, k, window, None);
            std::thread::scope(|scope| {
                let crew = rounds.spawn(scope, &member_job);
                let mut d = Driver {
                    cfg,
                    shape,
                    mem,
                    now,
                    limits,
                    halted_excess: &mut halted_excess,
                    progress: progress.as_deref_mut(),
                    fx: Effects::default(),
                    streams: StreamTiming::default(),
                    interval: self.interval,
                    intervals: intervals.as_mut(),
                    snap_at: self.snap_at,
                    next_sample: u64::MAX,
                    samples: Vec::new(),
                    pause_at: self.pause_at.clone(),
                    paused: &mut paused,
                    base,
                    check_at,
                    watch: &mut watch,
                    on_livelock: on_livelock.as_deref_mut(),
                };
                d.next_sample = d.next_sample_after(*d.now);
                let mut leader_job = |k: usize, window| job(0, k, window, profiler.as_mut());
                let outcome = d.drive(&shared, &parts, &sims, &rounds, &crew, &mut leader_job, out);
                (outcome, d.fx, d.streams, d.samples)
            })
        };
        let (outcome, mut fx, mut streams, samples) = outcome;
        self.samples = samples;
        self.paused = paused;
        streams.finish(&mut self.c, self.now);
        m.shared.sched.finish(self.now);
        self.profiler = profiler;
        self.progress = progress;
        self.intervals = intervals;
        self.livelocked |= on_livelock.is_some() && self.watch.is_none() && watch.is_none();
        self.on_livelock = on_livelock;
        self.watch = watch;
        // Take everything back.
        for p in parts {
            let p = p.into_inner().unwrap_or_else(|e| e.into_inner());
            self.c.add(&p.c);
        }
        let mut tm_mems = Vec::with_capacity(tms);
        for t in sims {
            let mut t = t.into_inner();
            // The sleeping threads' cycles.
            t.flush(&self.shape, &mut self.c, self.profiler.as_mut());
            // The last pipeline mode's reserved unit-cycles.
            let mode = t.mode;
            t.set_mode(&self.shape, &mut self.c, mode, self.now);
            // Counters stay with their TM until the end (only prints are merged as they
            // come; sums do not depend on when they are taken).
            t.fx.merge_into(&mut fx, None);
            m.threads.extend(t.threads);
            tm_mems.push(t.mem);
        }
        self.mem.restore_tms(tm_mems);
        fx.fold_into(&mut m.shared);
        self.c.tc.halted -= halted_excess.min(self.c.tc.halted);
        drain(&mut m.shared.output, out);
        outcome
    }
}

/// The stream memory's timing state (serial phase).
#[derive(Default)]
struct StreamTiming {
    /// Per bank: first cycle it accepts an access (allocated on the first access).
    bank_free: Vec<u64>,
    /// Rays in flight since cycle `last`.
    in_flight: u64,
    last: u64,
    /// Per thread (TM x threads + thread): the cycle its stream op first waited for the
    /// spill sentinel, until it goes through.
    spill_wait: Vec<Option<u64>>,
}

impl StreamTiming {
    /// An access to ray slot `slot` issued at `cycle`: returns the cycle its data is ready.
    fn access(&mut self, cfg: &ChipConfig, c: &mut Counters, slot: u32, cycle: u64) -> u64 {
        let sm = &cfg.stream_memory;
        if self.bank_free.is_empty() {
            self.bank_free = vec![0; sm.banks as usize];
        }
        let bank = &mut self.bank_free[(slot % sm.banks) as usize];
        let start = cycle.max(*bank);
        if start > cycle {
            c.stream_bank_conflicts += 1;
            c.stream_conflict_cycles += start - cycle;
        }
        *bank = start + u64::from(sm.bank_busy_cycles);
        start + u64::from(sm.latency)
    }

    /// Integrates rays in flight up to `cycle`, when the count becomes `now_in_flight`.
    fn rays(&mut self, c: &mut Counters, cycle: u64, now_in_flight: u32) {
        c.stream_ray_cycles += self.in_flight * cycle.saturating_sub(self.last);
        self.last = self.last.max(cycle);
        self.in_flight = u64::from(now_in_flight);
    }

    /// Thread `gid`'s stream op at `cycle` waited for the sentinel (`waited`) or went
    /// through.
    fn spill_wait(
        &mut self,
        c: &mut Counters,
        threads: usize,
        gid: usize,
        cycle: u64,
        waited: bool,
    ) {
        if self.spill_wait.is_empty() {
            if !waited {
                return;
            }
            self.spill_wait = vec![None; threads];
        }
        match (waited, self.spill_wait[gid]) {
            (true, None) => self.spill_wait[gid] = Some(cycle),
            (false, Some(s)) => {
                c.stream_spill_stall_cycles += cycle.saturating_sub(s);
                self.spill_wait[gid] = None;
            }
            _ => {}
        }
    }

    /// Closes the open intervals at the end of the run (`end`).
    fn finish(&mut self, c: &mut Counters, end: u64) {
        c.stream_ray_cycles += self.in_flight * end.saturating_sub(self.last);
    }
}

/// What the leader thread changes while the TMs run.
struct Driver<'a, 'p> {
    cfg: &'a ChipConfig,
    shape: &'a Shape,
    mem: &'a mut MemSystem,
    now: &'a mut u64,
    limits: Limits,
    /// Halted thread-cycles counted after the end of the run (subtracted at the end).
    halted_excess: &'a mut u64,
    progress: Option<&'a mut (dyn FnMut(&Progress) + 'p)>,
    /// Counters and prints of the TMs, merged each quantum; folded into the chip at the
    /// end (the chip's own lines stay unwritten, so TMs keep reading them from cache).
    fx: Effects,
    /// The stream memory's timing.
    streams: StreamTiming,
    /// Cycles per statistics interval, and where their samples go.
    interval: Option<u64>,
    intervals: Option<&'a mut IntervalStream<'p>>,
    /// A single extra sample's cycle.
    snap_at: Option<u64>,
    /// The next interval end or `snap_at` (`u64::MAX`: none).
    next_sample: u64,
    /// The counters at `snap_at`.
    samples: Vec<Snapshot>,
    /// Stop when a global register reaches a value, and whether it did.
    pause_at: Vec<(u32, u32)>,
    paused: &'a mut bool,
    /// The counters of earlier runs of the engine (samples are cumulative).
    base: Counters,
    /// The next cycle at which the livelock watch looks at the progress count
    /// (`u64::MAX`: not watching).
    check_at: u64,
    /// The livelock watch (`None` once one was found).
    watch: &'a mut Option<Watch>,
    /// Told of a livelock; says whether to stop.
    on_livelock: Option<&'a mut (dyn FnMut(&Detection) -> bool + 'p)>,
}

impl Driver<'_, '_> {
    /// Cycles per quantum: the L1 plus L2 hit latency (an L2 reply is never due sooner).
    fn quantum(&self) -> u64 {
        Engine::quantum(self.cfg)
    }

    /// Samples the cumulative counters at interval end `at` (a quantum end: every TM,
    /// the L2s and DRAM have simulated up to it). Out of line: the quantum loop stays as
    /// it was without intervals.
    #[cold]
    #[inline(never)]
    fn sample(&mut self, sh: &Shared, sims: &mut [&mut TmSim], parts: &[Mutex<Part>], at: u64) {
        // The sleeping threads' cycles so far.
        {
            let mut p = parts[0].lock().unwrap_or_else(|e| e.into_inner());
            for t in sims.iter_mut() {
                t.flush(self.shape, &mut p.c, None);
            }
        }
        let mut c = Counters::default();
        c.add_scalars(&self.base);
        for p in parts {
            c.add_scalars(&p.lock().unwrap_or_else(|e| e.into_inner()).c);
        }
        let mem = self.mem.stats_with(sims.iter().map(|t| &t.mem));
        let mut snap = snapshot_of(self.cfg, &c, &mem, sh, at);
        snap.ray_cycles += self.streams.in_flight * at.saturating_sub(self.streams.last);
        if self.snap_at == Some(at) {
            self.samples.push(snap.clone());
        }
        if self.interval.is_some_and(|n| at.is_multiple_of(n)) {
            if let Some(st) = self.intervals.as_deref_mut() {
                st.push(snap);
            }
        }
        self.next_sample = self.next_sample_after(at);
    }

    /// The livelock watch at quantum end `at`: looks for a livelock when nothing has
    /// changed for long ([`Watch::due`]); returns the outcome if one was found and the
    /// caller said to stop. Out of line: checked every [`LOOK_EVERY`] cycles.
    #[cold]
    #[inline(never)]
    fn look_for_livelock(
        &mut self,
        sh: &Shared,
        sims: &[&mut TmSim],
        parts: &[Mutex<Part>],
        at: u64,
    ) -> Option<Outcome> {
        self.check_at = at + LOOK_EVERY;
        let w = self.watch.as_mut()?;
        // Prints and counts stay in the TMs' effects (their `changes` never reset).
        let count = sh.progress_count() + sims.iter().map(|t| t.fx.changes).sum::<u64>();
        if !w.due(at, count) {
            return None;
        }
        let Some((threads, halted)) = livelock::prove(sims.iter().flat_map(|t| &t.threads), sh)
        else {
            w.failed();
            return None;
        };
        let d = Detection {
            cycle: Some(at),
            instructions: executed(parts),
            quiet: w.quiet(at),
            threads,
            halted,
        };
        *self.watch = None;
        self.check_at = u64::MAX;
        let stop = self.on_livelock.as_deref_mut().is_some_and(|f| f(&d));
        stop.then_some(Outcome::Livelock)
    }

    /// The first interval end or extra sample cycle after `at` (`u64::MAX`: none).
    fn next_sample_after(&self, at: u64) -> u64 {
        let interval = self
            .interval
            .map_or(u64::MAX, |n| (at / n).saturating_add(1).saturating_mul(n));
        let snap = self.snap_at.filter(|&s| s > at).unwrap_or(u64::MAX);
        interval.min(snap)
    }

    /// The quantum loop (on the leader thread).
    #[allow(clippy::too_many_arguments)]
    fn drive(
        &mut self,
        shared: &RoundCell<&mut Shared>,
        parts: &[Mutex<Part>],
        tm_sims: &[RoundCell<TmSim>],
        rounds: &Rounds,
        crew: &Crew<'_>,
        leader_job: &mut dyn FnMut(usize, (u64, u64)) -> u8,
        out: &mut dyn Write,
    ) -> Outcome {
        let q = self.quantum();
        let tms = self.cfg.tms as u64;
        let threads = tms * u64::from(self.cfg.threads_per_tm);
        let progress_every = (PROGRESS_THREAD_CYCLES / (q * threads)).clamp(1, PROGRESS_EVERY);
        let mut idle_cycles = 0u64;
        let mut deferred: Vec<Deferred> = Vec::new();
        let mut gr = (0u64, 0u32); // global registers: (cycle, ops served in it)
        let mut quanta = 0u64;
        // Per TM: its work at the last rebalancing.
        let mut work_at = vec![0u64; tm_sims.len()];
        // The TMs, between rounds (refilled each quantum).
        let mut sims: Vec<&mut TmSim> = Vec::with_capacity(tm_sims.len());
        let mut last_report = std::time::Instant::now();
        loop {
            // SAFETY: the leader between rounds.
            if unsafe { shared.get() }.live_threads == 0 {
                return Outcome::Finished;
            }
            let from = *self.now;
            let max = self.limits.max_cycles.unwrap_or(u64::MAX);
            if from >= max {
                return Outcome::CycleLimit;
            }
            if !self.pause_at.is_empty() {
                // SAFETY: the leader between rounds.
                let g = &unsafe { shared.get() }.globals;
                if self.pause_at.iter().any(|&(r, v)| g[r as usize] >= v) {
                    *self.paused = true;
                    return Outcome::CycleLimit;
                }
            }
            let to = (from + q).min(max);
            // Phase 1: the TMs, in parallel. While the L2s and DRAM owe the L1s nothing
            // and the TMs only issue (nothing for this phase), rounds follow each other
            // without it: it would only advance the memory system's clock, which the
            // next serial phase catches up cycle by cycle (DRAM writes, refresh).
            let idle = self.mem.chip_mut().owes_nothing();
            let batch = Batch {
                from,
                to,
                step: q,
                free_flags: idle.then_some(Summary::PROGRESSED),
                // Under an instruction limit, one round per serial phase (where the
                // count is checked); skipping serial phases does not change results.
                until: match self.limits.max_instructions {
                    Some(_) => to,
                    None => max.min(from + q * MAX_FREE_ROUNDS),
                }
                .min(self.next_sample)
                .min(self.check_at),
            };
            let Some(end) = rounds.run(crew, &batch, leader_job) else {
                // A host thread died; the scope re-raises its panic.
                return Outcome::Deadlock { waiting: 0 };
            };
            let (from, to, flags) = (end.from, end.to, Summary(end.flags));
            let quanta_before = quanta;
            quanta += end.rounds;
            let crossed = |every: u64| quanta / every != quanta_before / every;
            // Phase 2: chip-wide, serial.
            // Only the leader's own counters are touched unless the host threads' flags
            // say there is work: other state stays in its host thread's cache.
            let mut part0 = parts[0].lock().unwrap_or_else(|e| e.into_inner());
            // SAFETY: the leader between rounds (every TM of the round reported done);
            // `sims` is cleared before the next round.
            let sh: &mut Shared = unsafe { shared.get_mut() };
            sims.extend(tm_sims.iter().map(|t| unsafe { t.get_mut() }));
            let c = &mut part0.c;
            let issued_before = c.tc.issued;
            let mut progressed = flags.any(Summary::PROGRESSED);
            let mut crash: Option<(u64, Box<Crash>)> = None;
            if flags.any(Summary::CRASH) {
                for t in sims.iter_mut().filter(|t| t.summary.any(Summary::CRASH)) {
                    // The first fault, in (cycle, TM) order.
                    if let Some((cyc, _, cr)) = t.crash.take() {
                        if crash.as_ref().is_none_or(|(c0, _)| cyc < *c0) {
                            crash = Some((cyc, cr));
                        }
                    }
                }
            }
            // Prints (with the TM's counters so far), in TM order (prints after a fault's
            // cycle are dropped).
            let until = crash.as_ref().map(|(c0, _)| *c0);
            if flags.any(Summary::EFFECTS) {
                for t in sims.iter_mut().filter(|t| t.summary.any(Summary::EFFECTS)) {
                    t.fx.merge_into(&mut self.fx, until);
                }
                if !self.fx.output.is_empty() {
                    drain(&mut self.fx.output, out);
                }
            }
            // Deferred chip-wide instructions.
            deferred.clear();
            if flags.any(Summary::DEFERRED) {
                for t in sims.iter_mut().filter(|t| t.summary.any(Summary::DEFERRED)) {
                    deferred.append(&mut t.deferred);
                }
            }
            deferred.sort_by_key(|d| (d.cycle, (u64::from(d.tm) + tms - d.cycle % tms) % tms));
            let mut last_halt = None;
            for d in &deferred {
                if crash.as_ref().is_some_and(|(c0, _)| d.cycle >= *c0) {
                    break;
                }
                let sim = &mut *sims[d.tm as usize];
                let tid = d.tid as usize;
                sh.clock = d.cycle;
                // A halt (executed in the parallel phase, or here: it is never deferred
                // today) ends its thread.
                let halted = d.halted || {
                    let t = &mut sim.threads[tid];
                    match t.step_once(sh) {
                        Stop::Fault(f) => {
                            crash = Some((d.cycle, Box::new(Crash::capture(t, f))));
                            break;
                        }
                        // A semaphore that is not available, or a stream op waiting
                        // for the spill sentinel: retry next quantum.
                        Stop::Retry | Stop::Defer => {
                            c.tc.sync_wait += 1;
                            if d.op.unit() == UnitClass::Stream as usize {
                                let gid = d.tm as usize * sim.threads.len() + tid;
                                let n = tms as usize * sim.threads.len();
                                self.streams.spill_wait(c, n, gid, d.cycle, true);
                                dispatch_transfers(self.mem, sh, d.cycle);
                            }
                            continue;
                        }
                        Stop::Halted => true,
                        Stop::Budget | Stop::Blocked => false,
                    }
                };
                if halted {
                    sh.thread_halted(d.tm);
                    last_halt = Some(d.cycle);
                }
                if d.halted {
                    continue;
                }
                let idx = d.idx as usize;
                let last = c.issued_at.len() - 1;
                c.issued_at[idx.min(last)] += 1;
                let op = d.op;
                let mut ready = d.ready_at;
                if op.unit() == UnitClass::Stream as usize {
                    let gid = d.tm as usize * sim.threads.len() + tid;
                    let n = tms as usize * sim.threads.len();
                    self.streams.spill_wait(c, n, gid, d.cycle, false);
                    dispatch_transfers(self.mem, sh, d.cycle);
                    // A ray pushed or popped: one access to its slot's bank.
                    if let Some(slot) = sh.streams.last_slot.take() {
                        ready = self.streams.access(self.cfg, c, slot, d.cycle);
                        self.streams.rays(c, d.cycle, sh.streams.in_flight);
                    }
                }
                if op.unit() == UnitClass::GlobalRegs as usize {
                    let g = &self.cfg.global_registers;
                    if gr.0 < d.cycle {
                        gr = (d.cycle, 0);
                    }
                    if gr.1 >= g.ops_per_cycle {
                        gr = (gr.0 + 1, 0);
                    }
                    gr.1 += 1;
                    c.unit_conflicts[UnitClass::GlobalRegs as usize] += gr.0 - d.cycle;
                    ready = gr.0 + g.latency as u64;
                }
                sim.retire(c, tid, &op, idx, ready.max(to));
            }
            // Stop on a fault.
            if let Some((cyc, mut cr)) = crash {
                *self.now = cyc;
                cr.cycle = Some(cyc);
                return Outcome::Crashed(cr);
            }
            // The L2s and DRAM serve what the L1s sent.
            let chip = self.mem.chip_mut();
            if flags.any(Summary::SENT) {
                for t in sims.iter_mut().filter(|t| t.summary.any(Summary::SENT)) {
                    chip.collect(&mut t.mem);
                }
            }
            chip.serve_until(to, &mut sims);
            // The sentinel's transfers free slots and bring rays back (seen next quantum).
            for e in chip.dma_events() {
                if e.done {
                    sh.streams.dma_done(e.id);
                } else {
                    sh.streams.dma_progress(e.id, e.rays);
                }
            }
            if rounds.threads() > 1 && crossed(REBALANCE_EVERY) {
                let loads: Vec<u64> = sims
                    .iter()
                    .zip(&mut work_at)
                    .map(|(t, at)| t.work - std::mem::replace(at, t.work))
                    .collect();
                let owner: Vec<usize> = (0..sims.len()).map(|k| rounds.owner(k)).collect();
                for (k, w) in rebalance(&loads, &owner, rounds.threads(), REBALANCE_MIN_GAIN) {
                    rounds.set_owner(k, w);
                    // The new owner reallocates it from its own heap.
                    sims[k].local = false;
                }
            }
            progressed |= c.tc.issued != issued_before;
            drop(part0);
            if let Some(h) = last_halt {
                if sh.live_threads == 0 {
                    // The run ends after the last halt; every thread was halted in the
                    // rest of the quantum.
                    *self.now = h + 1;
                    *self.halted_excess = (to - h - 1) * sh.shape.total() as u64;
                    return Outcome::Finished;
                }
            }
            // Every live thread waits for another (barriers, stream schedulers): nothing
            // can run again.
            // (Threads block and halt only through deferred instructions.)
            if flags.any(Summary::DEFERRED)
                && sh.live_threads > 0
                && sh.blocked_threads() >= sh.live_threads
            {
                *self.now = to;
                return Outcome::Deadlock {
                    waiting: sh.live_threads,
                };
            }
            if progressed {
                idle_cycles = 0;
            } else {
                // The batch's earlier rounds progressed.
                idle_cycles = if end.rounds > 1 { 0 } else { idle_cycles } + (to - from);
            }
            *self.now = to;
            if to >= self.next_sample {
                self.sample(sh, &mut sims, parts, to);
            }
            if let Some(limit) = self.limits.max_instructions {
                if executed(parts) >= limit {
                    return Outcome::InstructionLimit;
                }
            }
            if to >= self.check_at {
                if let Some(o) = self.look_for_livelock(sh, &sims, parts, to) {
                    return o;
                }
            }
            if crossed(progress_every) {
                if let Some(report) = self.progress.as_deref_mut() {
                    if last_report.elapsed().as_millis() >= 100 {
                        last_report = std::time::Instant::now();
                        report(&Progress {
                            cycles: Some(to),
                            instructions: executed(parts),
                            rays: sh.stats[0]
                                + self.fx.stats[0]
                                + sims.iter().map(|t| t.fx.stats[0]).sum::<u64>(),
                            live_threads: sh.live_threads,
                        });
                    }
                }
            }
            sims.clear();
            // Nobody issued for a long time: a deadlock (or a memory system that stopped
            // making progress). While the memory system owes the TMs data, a wait is as
            // long as its latencies and queues make it (each bounded by the config's
            // validation): ten times longer before it counts as stopped.
            let chip = self.mem.chip_mut();
            if (idle_cycles > 1_000_000 && chip.next_event().is_none())
                || (idle_cycles > 10_000_000 && chip.owes_nothing())
                || idle_cycles > 100_000_000
            {
                return Outcome::Deadlock {
                    waiting: sh.live_threads,
                };
            }
        }
    }
}

/// Hands the block transfers a stream op started at `cycle` to the sentinel's DMA engine.
fn dispatch_transfers(mem: &mut MemSystem, sh: &mut Shared, cycle: u64) {
    for t in sh.streams.take_transfers() {
        mem.chip_mut().dma_start(DmaJob {
            id: t.id,
            write: t.write,
            addr: t.addr,
            rays: t.rays,
            ray_bytes: t.ray_bytes,
            start: cycle,
        });
    }
}

/// The cumulative [`Snapshot`] of counters `c` and memory statistics `mem` at `cycle`,
/// with `streams` stream-memory accesses.
fn snapshot_of(
    cfg: &ChipConfig,
    c: &Counters,
    mem: &MemStats,
    sh: &Shared,
    cycle: u64,
) -> Snapshot {
    let mut l2 = CacheStats::default();
    for x in &mem.l2 {
        l2.add(x);
    }
    let energy = super::stats::energy_of(cfg, c, mem, sh.streams.sram_accesses());
    Snapshot {
        cycle,
        tc: c.tc.clone(),
        debug_ops: c.debug_ops,
        l1: mem.l1.clone(),
        l2,
        dram_reads: mem.dram.reads,
        dram_writes: mem.dram.writes,
        dram_bytes: mem.dram.bytes,
        ray_cycles: c.stream_ray_cycles,
        energy_j: energy.total,
        energy,
        dram: mem.dram.clone(),
        dram_queue_full: mem.dram_queue_full,
        stream_writes: sh.streams.writes,
        stream_reads: sh.streams.reads,
        stream_schedules: sh.sched.schedules,
        idle_tm_cycles: sh.sched.idle_tm_cycles_at(cycle),
    }
}

/// Instructions executed so far: issued plus zero-cost debug ops, over every host thread.
fn executed(parts: &[Mutex<Part>]) -> u64 {
    parts
        .iter()
        .map(|p| {
            let p = p.lock().unwrap_or_else(|e| e.into_inner());
            p.c.tc.issued + p.c.debug_ops
        })
        .sum()
}

impl Counters {
    /// Adds `o` into `self`.
    fn add(&mut self, o: &Counters) {
        self.add_scalars(o);
        for (x, y) in self.issued_at.iter_mut().zip(&o.issued_at) {
            *x += y;
        }
        for (x, y) in self.dep_by_producer.iter_mut().zip(&o.dep_by_producer) {
            *x += y;
        }
    }

    /// Adds `o`'s counters into `self`, except the per-text-word ones.
    fn add_scalars(&mut self, o: &Counters) {
        self.tc.add(&o.tc);
        for k in 0..NUM_CLASSES {
            self.unit_conflicts[k] += o.unit_conflicts[k];
            self.class_ops[k] += o.class_ops[k];
        }
        self.reg_accesses += o.reg_accesses;
        self.local_accesses += o.local_accesses;
        self.fetches += o.fetches;
        self.debug_ops += o.debug_ops;
        self.reserved_unit_cycles += o.reserved_unit_cycles;
        self.stream_bank_conflicts += o.stream_bank_conflicts;
        self.stream_conflict_cycles += o.stream_conflict_cycles;
        self.stream_ray_cycles += o.stream_ray_cycles;
        self.stream_spill_stall_cycles += o.stream_spill_stall_cycles;
    }
}

/// What issuing an instruction of timing facts `info` needs, on a chip of `units`, when
/// the unit at counter index `unit` executes it.
fn resolve(info: &OpInfo, unit: usize, units: &[UnitSpec]) -> Op {
    let claim = match (info.class, info.mem) {
        (UnitClass::Debug, _) => Claim::Slow,
        (_, Some(mo)) => Claim::Mem(mo),
        (UnitClass::RegFile | UnitClass::GlobalRegs, None) => Claim::Free,
        (UnitClass::BoxPipe, None) => Claim::Pipe(0),
        (UnitClass::TriPipe, None) => Claim::Pipe(1),
        (_, None) => {
            let u = &units[unit];
            let latency = u32::try_from(u.latency).expect("unit latencies are configured as u32");
            Claim::Unit {
                latency,
                busy: if u.pipelined { 1 } else { latency },
            }
        }
    };
    Op::new(info.src, info.dst, unit, info.reg_accesses, claim)
}
