//! Detailed DRAM: per channel an FR-FCFS open-row controller with read and write queues, write
//! drain, refresh, and bank/rank/bus timing constraints.
//!
//! The model is event-driven but cycle-exact with respect to a controller that issues at most
//! one command per channel per DRAM cycle: at each decision it computes, for every bank with
//! queued work, the earliest cycle its next command (ACT, PRE or column) satisfies every timing
//! constraint; the earliest candidate wins, ties broken by row hits first, then age (FR-FCFS).
//! Cycles in which nothing can issue are skipped, and idle channels cost nothing (refreshes are
//! caught up when the channel is next used or its stats are read).
//!
//! Speed: each channel caches its last decision (the winning command, valid up to the next
//! refresh due time) and every bank's bank-local next command. A decision is recomputed only
//! after a command issues, when a refresh falls due, or when a new request changes the winning
//! bank's next command; other new requests are folded in with one comparison or leave the
//! decision untouched. A decision scans the queued banks grouped by rank and command kind and
//! skips a group whose rank-wide earliest time already lies after the best candidate found.
//! `advance_to` skips channels whose cached decision issues nothing before the target; their
//! clock and queue-occupancy integrals are caught up lazily.

use super::dram_config::{AddressMapping, DetailedDramConfig, DramTiming};
use super::{Completion, Cycle};

const NO_ROW: u32 = u32::MAX;

/// Row-buffer outcome of one request (none = row hit).
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum RowOutcome {
    /// Bank was closed: needed an ACT.
    Miss,
    /// Another row was open: needed PRE + ACT.
    Conflict,
}

#[derive(Clone, Copy, Debug)]
struct Req {
    id: u64,
    line: u32,
    row: u32,
    /// Arrival in DRAM cycles.
    arrival: u64,
    seq: u64,
    outcome: Option<RowOutcome>,
}

#[derive(Clone, Debug)]
struct Bank {
    open_row: u32,
    /// Earliest ACT (tRP after PRE, tRC after ACT, tRFC after REF).
    act_ok: u64,
    /// Earliest PRE (tRAS after ACT, tRTP after RD, write recovery after WR).
    pre_ok: u64,
    /// Earliest column command (tRCD after ACT).
    col_ok: u64,
    reads: Vec<Req>,
    writes: Vec<Req>,
}

#[derive(Clone, Debug)]
struct Rank {
    /// Earliest ACT by tRRD.
    act_ok: u64,
    /// Ring over the last four ACTs: earliest next ACT each allows (ACT time + tFAW).
    faw: [u64; 4],
    faw_pos: usize,
    /// Earliest column command by tCCD.
    col_ok: u64,
    /// Earliest read by tWTR.
    rd_ok: u64,
    /// Next refresh due (DRAM cycle).
    next_ref: u64,
    /// Number of open banks, and since when at least one has been open.
    open_banks: u32,
    active_since: u64,
    active_cycles: u64,
}

/// Per-channel statistics counters.
#[derive(Clone, Debug, Default)]
pub(crate) struct ChanCounters {
    pub reads: u64,
    pub writes: u64,
    pub writes_merged: u64,
    pub reads_forwarded: u64,
    pub row_hits: u64,
    pub row_misses: u64,
    pub row_conflicts: u64,
    pub activates: u64,
    pub precharges: u64,
    pub refreshes: u64,
    pub read_latency_sum: u64,
    pub read_occupancy_integral: u128,
    pub write_occupancy_integral: u128,
    pub max_reads: u32,
    pub max_writes: u32,
    pub drain_episodes: u64,
    /// Column accesses of DMA requests (`sentinel::is_dma` ids), and those that hit.
    pub dma_cols: u64,
    pub dma_row_hits: u64,
}

struct Channel {
    /// First DRAM cycle at which the command bus is free (and up to which time is simulated;
    /// lags behind [`DetailedDram::now`] while the channel is skipped).
    now: u64,
    banks: Vec<Bank>,
    ranks: Vec<Rank>,
    n_reads: u32,
    n_writes: u32,
    /// Bit i set = bank i has queued reads / writes.
    read_mask: u64,
    write_mask: u64,
    drain: bool,
    bus_free: u64,
    last_rank: u32,
    last_write: bool,
    occ_t: u64,
    low_wm: u32,
    /// Cached bank-local next commands.
    local: Box<Locals>,
    local_writes: bool,
    /// The last FR-FCFS decision, still valid (nothing issued or queued since, except what
    /// [`DetailedDram::submit`] folded in) for every target up to `horizon`.
    decided: Decision,
    c: ChanCounters,
}

/// A cached scheduling decision of one channel.
#[derive(Clone, Copy)]
struct Decision {
    valid: bool,
    best: Option<Cand>,
    /// The decision holds for targets `<= horizon` (the next refresh due time not yet
    /// considered: a later target makes that refresh a candidate).
    horizon: u64,
    /// Whether the decision considered write requests (drain mode or no reads).
    writes: bool,
}

const UNDECIDED: Decision = Decision {
    valid: false,
    best: None,
    horizon: 0,
    writes: false,
};

/// Index of a command kind in [`Locals::kind`] and in a rank's floor array.
const K_COL: u8 = 0;
const K_PRE: u8 = 1;
const K_ACT: u8 = 2;

/// The bank-local part of every bank's next command (what only that bank's state decides),
/// cached until the bank, its queue or the read/write mode changes; one slot per bank
/// (at most 64 per channel), laid out for the scheduler's scan.
#[derive(Clone)]
struct Locals {
    /// Bit i set = slot i is current.
    valid: u64,
    /// Earliest time by the bank's own constraints.
    t: [u64; 64],
    /// Priority within a time: class (1 = column, 2 = ACT/PRE) << 62 | request sequence.
    ord: [u64; 64],
    /// Index of the request in the bank's queue (column commands).
    idx: [u32; 64],
    /// `K_COL`, `K_PRE` or `K_ACT`.
    kind: [u8; 64],
    /// Per kind, the banks whose current slot has that kind (stale slots may linger).
    kind_mask: [u64; 3],
}

#[derive(Clone, Copy, Debug)]
enum Cmd {
    Act,
    Pre,
    Col,
    PreAll,
    Refresh,
}

#[derive(Clone, Copy, Debug)]
struct Cand {
    t: u64,
    /// 0 = refresh, 1 = column (row hit), 2 = ACT/PRE.
    class: u8,
    seq: u64,
    bank: usize,
    rank: usize,
    idx: usize,
    cmd: Cmd,
}

impl Cand {
    /// FR-FCFS priority as one number: earliest time, then refresh before column (row hit)
    /// before ACT/PRE, then oldest. Smaller is better; distinct candidates never tie (bank
    /// commands carry distinct request sequence numbers, refreshes have distinct ranks and the
    /// earlier rank is examined first and kept on equal keys).
    fn key(&self) -> u128 {
        (u128::from(self.t) << 64) | (u128::from(self.class) << 62) | u128::from(self.seq)
    }
}

/// Core/DRAM clock conversion, exact (the ratio is reduced so that common clock pairs
/// convert without a division).
#[derive(Clone, Copy)]
struct Clocks {
    dram_mhz: u64,
    core_mhz: u64,
    /// dram_mhz / gcd and core_mhz / gcd.
    dram_red: u64,
    core_red: u64,
}

fn gcd(mut a: u64, mut b: u64) -> u64 {
    while b != 0 {
        (a, b) = (b, a % b);
    }
    a
}

impl Clocks {
    fn new(dram_mhz: u64, core_mhz: u64) -> Self {
        let g = gcd(dram_mhz, core_mhz).max(1);
        Clocks {
            dram_mhz,
            core_mhz,
            dram_red: dram_mhz / g,
            core_red: core_mhz / g,
        }
    }

    /// Core cycle -> DRAM cycle: `floor(core * dram_mhz / core_mhz)` (truncated to 64 bits).
    fn to_dram(self, core: Cycle) -> u64 {
        match core.checked_mul(self.dram_red) {
            Some(p) if self.core_red.is_power_of_two() => p >> self.core_red.trailing_zeros(),
            Some(p) => p / self.core_red,
            None => {
                (u128::from(core) * u128::from(self.dram_mhz) / u128::from(self.core_mhz)) as u64
            }
        }
    }

    /// DRAM cycle -> core cycle: `ceil(dram * core_mhz / dram_mhz)` (truncated to 64 bits).
    fn to_core(self, dram: u64) -> Cycle {
        match dram.checked_mul(self.core_red) {
            Some(p) if self.dram_red.is_power_of_two() => {
                let sh = self.dram_red.trailing_zeros();
                (p >> sh) + u64::from(p & (self.dram_red - 1) != 0)
            }
            Some(p) => p.div_ceil(self.dram_red),
            None => (u128::from(dram) * u128::from(self.core_mhz))
                .div_ceil(u128::from(self.dram_mhz)) as u64,
        }
    }
}

/// Bits of the banks of rank `ri` (`bpr` banks per rank, `bpr * ranks <= 64`).
fn rank_bits(ri: usize, bpr: usize) -> u64 {
    if bpr >= 64 {
        u64::MAX
    } else {
        ((1u64 << bpr) - 1) << (ri * bpr)
    }
}

/// The detailed DRAM model (all channels).
pub struct DetailedDram {
    cfg: DetailedDramConfig,
    t: DramTiming,
    channels: Vec<Channel>,
    banks_per_rank: usize,
    /// Where the address fields lie in a line number.
    fields: Fields,
    line_shift: u32,
    clocks: Clocks,
    /// Per channel: advancing to any DRAM cycle up to this one issues nothing (the channel's
    /// `now` and occupancy then lag behind [`Self::now`] and are caught up lazily).
    wake: Vec<u64>,
    /// The smallest of `wake`.
    min_wake: u64,
    seq: u64,
    /// DRAM cycle up to which all channels have been advanced.
    now: u64,
}

fn log2(v: u32) -> u32 {
    v.trailing_zeros()
}

/// (shift, mask) of each address field within a line number.
#[derive(Clone, Copy)]
struct Fields {
    chan: (u32, u32),
    bank: (u32, u32),
    rank: (u32, u32),
    row: (u32, u32),
}

impl Fields {
    fn new(cfg: &DetailedDramConfig) -> Self {
        let mask = |n: u32| n - 1;
        let (col, chan, bank, rank) = (
            log2(cfg.columns),
            log2(cfg.channels),
            log2(cfg.banks),
            log2(cfg.ranks),
        );
        // Field offsets from the least significant end, in mapping order.
        let (chan_sh, bank_sh, rank_sh, row_sh) = match cfg.mapping {
            AddressMapping::RowRankBankChannelColumn => {
                (col, col + chan, col + chan + bank, col + chan + bank + rank)
            }
            AddressMapping::RowColumnRankBankChannel => {
                (0, chan, chan + bank, chan + bank + rank + col)
            }
        };
        Fields {
            chan: (chan_sh, mask(cfg.channels)),
            bank: (bank_sh, mask(cfg.banks)),
            rank: (rank_sh, mask(cfg.ranks)),
            row: (row_sh, mask(cfg.rows)),
        }
    }
}

impl DetailedDram {
    /// Builds the model (config must be validated). `core_mhz` is the core clock.
    pub fn new(cfg: &DetailedDramConfig, core_mhz: u32) -> Self {
        let t = cfg.timing.resolve(cfg.clock_mhz);
        let nb = (cfg.ranks * cfg.banks) as usize;
        let mk_chan = || Channel {
            now: 0,
            banks: (0..nb)
                .map(|_| Bank {
                    open_row: NO_ROW,
                    act_ok: 0,
                    pre_ok: 0,
                    col_ok: 0,
                    reads: Vec::new(),
                    writes: Vec::new(),
                })
                .collect(),
            ranks: (0..cfg.ranks as usize)
                .map(|r| Rank {
                    act_ok: 0,
                    faw: [0; 4],
                    faw_pos: 0,
                    col_ok: 0,
                    rd_ok: 0,
                    // Stagger ranks' refreshes across the interval.
                    next_ref: if t.t_refi == 0 {
                        u64::MAX
                    } else {
                        t.t_refi + t.t_refi * r as u64 / u64::from(cfg.ranks)
                    },
                    open_banks: 0,
                    active_since: 0,
                    active_cycles: 0,
                })
                .collect(),
            n_reads: 0,
            n_writes: 0,
            read_mask: 0,
            write_mask: 0,
            drain: false,
            bus_free: 0,
            last_rank: 0,
            last_write: false,
            occ_t: 0,
            low_wm: cfg.write_low_watermark,
            local: Box::new(Locals {
                valid: 0,
                t: [0; 64],
                ord: [0; 64],
                idx: [0; 64],
                kind: [K_ACT; 64],
                kind_mask: [0; 3],
            }),
            local_writes: false,
            decided: UNDECIDED,
            c: ChanCounters::default(),
        };
        DetailedDram {
            cfg: cfg.clone(),
            t,
            channels: (0..cfg.channels).map(|_| mk_chan()).collect(),
            banks_per_rank: cfg.banks as usize,
            fields: Fields::new(cfg),
            line_shift: log2(cfg.line_bytes),
            clocks: Clocks::new(u64::from(cfg.clock_mhz), u64::from(core_mhz.max(1))),
            wake: vec![0; cfg.channels as usize],
            min_wake: 0,
            seq: 0,
            now: 0,
        }
    }

    /// The configuration this model runs.
    pub fn config(&self) -> &DetailedDramConfig {
        &self.cfg
    }

    /// The core clock in MHz.
    pub fn core_mhz(&self) -> u64 {
        self.clocks.core_mhz
    }

    /// Timing resolved to DRAM cycles.
    pub fn timing(&self) -> &DramTiming {
        &self.t
    }

    /// Core cycle -> DRAM cycle (floor).
    pub fn to_dram(&self, core: Cycle) -> u64 {
        self.clocks.to_dram(core)
    }

    /// DRAM cycle -> core cycle (ceil: data is usable at the first core edge after it arrives).
    pub fn to_core(&self, dram: u64) -> Cycle {
        self.clocks.to_core(dram)
    }

    /// Splits a byte address into (channel, rank, bank index within channel, row).
    pub fn decode(&self, addr: u32) -> (usize, usize, usize, u32) {
        let line = addr >> self.line_shift;
        let f = &self.fields;
        let field = |(sh, mask): (u32, u32)| line.checked_shr(sh).unwrap_or(0) & mask;
        let r = field(f.rank) as usize;
        (
            field(f.chan) as usize,
            r,
            r * self.banks_per_rank + field(f.bank) as usize,
            field(f.row),
        )
    }

    /// Whether a request to `addr` would be accepted now.
    pub fn can_accept(&self, addr: u32, write: bool) -> bool {
        let (ch, _, _, _) = self.decode(addr);
        let c = &self.channels[ch];
        if write {
            c.n_writes < self.cfg.write_queue
        } else {
            c.n_reads < self.cfg.read_queue
        }
    }

    /// Queues a request arriving at core cycle `now` (call [`Self::advance_to`]`(now)` first).
    /// Returns false (and changes nothing) if the channel's queue is full.
    /// Reads that hit a queued write are answered from the write queue one DRAM cycle later.
    pub fn submit(
        &mut self,
        id: u64,
        addr: u32,
        write: bool,
        now: Cycle,
        out: &mut Vec<Completion>,
    ) -> bool {
        let arrival = self.to_dram(now).max(self.now);
        let (ch, _rank, b, row) = self.decode(addr);
        let line = addr >> self.line_shift;
        let cap_r = self.cfg.read_queue;
        let cap_w = self.cfg.write_queue;
        let hi = self.cfg.write_high_watermark;
        let clocks = self.clocks;
        let t = &self.t;
        let bpr = self.banks_per_rank;
        let c = &mut self.channels[ch];
        c.now = c.now.max(self.now);
        let was_empty = c.n_reads + c.n_writes == 0;
        if write {
            if c.banks[b].writes.iter().any(|r| r.line == line) {
                c.c.writes_merged += 1;
                return true;
            }
            if c.n_writes >= cap_w {
                return false;
            }
            c.catch_up_occupancy(arrival);
            self.seq += 1;
            c.banks[b].writes.push(Req {
                id,
                line,
                row,
                arrival,
                seq: self.seq,
                outcome: None,
            });
            c.write_mask |= 1 << b;
            c.n_writes += 1;
            c.c.max_writes = c.c.max_writes.max(c.n_writes);
            if c.n_writes >= hi && !c.drain {
                c.drain = true;
                c.c.drain_episodes += 1;
            }
        } else {
            if c.banks[b].writes.iter().any(|r| r.line == line) {
                c.c.reads_forwarded += 1;
                c.c.reads += 1;
                c.c.read_latency_sum += 1;
                out.push(Completion {
                    id,
                    cycle: clocks.to_core(arrival + 1),
                });
                return true;
            }
            if c.n_reads >= cap_r {
                return false;
            }
            c.catch_up_occupancy(arrival);
            self.seq += 1;
            c.banks[b].reads.push(Req {
                id,
                line,
                row,
                arrival,
                seq: self.seq,
                outcome: None,
            });
            c.read_mask |= 1 << b;
            c.n_reads += 1;
            c.c.max_reads = c.c.max_reads.max(c.n_reads);
        }
        c.queued(b, row, write, was_empty, t, bpr);
        self.wake[ch] = c.wake();
        self.min_wake = self.min_wake.min(self.wake[ch]);
        true
    }

    /// Simulates every DRAM cycle before the one that core cycle `now` starts in; read
    /// completions (data-return cycle, in core cycles; may lie after `now`) go to `out`.
    pub fn advance_to(&mut self, now: Cycle, out: &mut Vec<Completion>) {
        let target = self.to_dram(now);
        if target <= self.now {
            return;
        }
        let t = self.t;
        let bpr = self.banks_per_rank;
        let clocks = self.clocks;
        let before = self.now;
        if target <= self.min_wake {
            self.now = target;
            return;
        }
        let mut min_wake = u64::MAX;
        for (c, wake) in self.channels.iter_mut().zip(self.wake.iter_mut()) {
            if target <= *wake {
                min_wake = min_wake.min(*wake);
                continue;
            }
            c.now = c.now.max(before);
            c.advance(target, &t, bpr, |id, d| {
                out.push(Completion {
                    id,
                    cycle: clocks.to_core(d),
                })
            });
            *wake = c.wake();
            min_wake = min_wake.min(*wake);
        }
        self.min_wake = min_wake;
        self.now = target;
    }

    /// Functional warming (sampled simulation): opens the row of `addr` in its bank, as
    /// the access's ACT would (open-row policy: it stays open until a conflict or a
    /// refresh), with the rank's active-time accounting; no command, timing constraint or
    /// counter changes. Call it only while nothing is queued ([`Self::is_idle`]).
    pub fn warm(&mut self, addr: u32) {
        let (ch, rank, b, row) = self.decode(addr);
        let now = self.now;
        let c = &mut self.channels[ch];
        let bank = &mut c.banks[b];
        if bank.open_row == row {
            return;
        }
        if bank.open_row == NO_ROW {
            let r = &mut c.ranks[rank];
            if r.open_banks == 0 {
                r.active_since = c.now.max(now);
            }
            r.open_banks += 1;
        }
        bank.open_row = row;
        c.local.valid &= !(1u64 << b);
        c.decided.valid = false;
    }

    /// Whether no request is queued anywhere.
    pub fn is_idle(&self) -> bool {
        self.channels
            .iter()
            .all(|c| c.n_reads == 0 && c.n_writes == 0)
    }

    /// Lower bound (core cycles) on the next cycle at which a queued request may make progress;
    /// `None` if nothing is queued.
    pub fn next_event(&self) -> Option<Cycle> {
        self.channels
            .iter()
            .filter(|c| c.n_reads + c.n_writes > 0)
            .map(|c| self.to_core(c.now.max(self.now)))
            .min()
    }

    /// Per-channel counters, with queue occupancy integrated up to now.
    pub(crate) fn counters(&self) -> impl Iterator<Item = ChanCounters> + '_ {
        self.channels.iter().map(|c| {
            let mut k = c.c.clone();
            let dt = u128::from(self.now.saturating_sub(c.occ_t));
            k.read_occupancy_integral += u128::from(c.n_reads) * dt;
            k.write_occupancy_integral += u128::from(c.n_writes) * dt;
            k
        })
    }

    /// DRAM cycles simulated so far.
    pub fn dram_cycles(&self) -> u64 {
        self.now
    }

    /// Total cycles (summed over ranks) in which at least one bank was open, up to now.
    pub(crate) fn active_rank_cycles(&self) -> (u64, u64) {
        let mut active = 0;
        let mut total = 0;
        for c in &self.channels {
            for r in &c.ranks {
                active += r.active_cycles
                    + if r.open_banks > 0 {
                        self.now.saturating_sub(r.active_since)
                    } else {
                        0
                    };
                total += self.now;
            }
        }
        (active, total)
    }
}

/// Bank `bi`'s next command for the oldest request it can serve (FR: a row hit first), into
/// slot `bi` of `l`.
#[inline(always)]
fn bank_local(l: &mut Locals, bi: usize, bank: &Bank, writes: bool) {
    let list = if writes { &bank.writes } else { &bank.reads };
    let (t, idx, kind) = match bank.open_row {
        NO_ROW => (bank.act_ok, 0, K_ACT),
        open => match list.iter().position(|r| r.row == open) {
            Some(idx) => (bank.col_ok, idx, K_COL),
            None => (bank.pre_ok, 0, K_PRE),
        },
    };
    let class: u64 = if kind == K_COL { 1 } else { 2 };
    l.t[bi] = t;
    l.ord[bi] = (class << 62) | list[idx].seq;
    l.idx[bi] = idx as u32;
    l.kind[bi] = kind;
    l.valid |= 1 << bi;
    for m in &mut l.kind_mask {
        *m &= !(1 << bi);
    }
    l.kind_mask[usize::from(kind)] |= 1 << bi;
}

/// Folds the banks in `mask` (all with current `local` slots) whose next command is of one
/// kind into the FR-FCFS choice so far (`best`, a [`Cand::key`], and its bank): a bank's
/// command can issue at the later of its bank-local time and `floor`, the rank-wide earliest
/// time for that kind of command, unless its rank's refresh is due by then (`next_ref`).
#[inline]
fn scan(
    local: &Locals,
    mut mask: u64,
    floor: u64,
    next_ref: u64,
    best: &mut u128,
    best_bank: &mut usize,
) {
    // Every candidate of the group is at `floor` or later, and its key above `floor << 64`.
    if mask == 0 || floor >= next_ref || *best <= u128::from(floor) << 64 {
        return;
    }
    let (mut key_min, mut bank) = (*best, *best_bank);
    while mask != 0 {
        let bi = mask.trailing_zeros() as usize & 63;
        mask &= mask - 1;
        let tc = local.t[bi].max(floor);
        // From a rank's refresh due time on, only the refresh may issue to it.
        if tc >= next_ref {
            continue;
        }
        let key = (u128::from(tc) << 64) | u128::from(local.ord[bi]);
        if key < key_min {
            key_min = key;
            bank = bi;
        }
    }
    *best = key_min;
    *best_bank = bank;
}

impl Channel {
    fn catch_up_occupancy(&mut self, t: u64) {
        if t > self.occ_t {
            let dt = u128::from(t - self.occ_t);
            self.c.read_occupancy_integral += u128::from(self.n_reads) * dt;
            self.c.write_occupancy_integral += u128::from(self.n_writes) * dt;
            self.occ_t = t;
        }
    }

    /// Issues every command the FR-FCFS controller issues before DRAM cycle `target`.
    fn advance(&mut self, target: u64, t: &DramTiming, bpr: usize, mut done: impl FnMut(u64, u64)) {
        loop {
            if !(self.decided.valid && target <= self.decided.horizon) {
                self.decide(t, bpr, target);
            }
            match self.decided.best {
                Some(best) if best.t < target => {
                    self.decided.valid = false;
                    self.issue(best, t, bpr, &mut done);
                }
                _ => break,
            }
        }
        if self.now < target {
            self.now = target;
        }
    }

    /// The last DRAM cycle up to which advancing issues nothing (0: a decision is needed).
    fn wake(&self) -> u64 {
        let d = &self.decided;
        if !d.valid {
            return 0;
        }
        d.best.map_or(d.horizon, |b| b.t.min(d.horizon))
    }

    /// The read/write mode of the next decision (ends a drain at the low watermark).
    fn mode(&mut self) -> bool {
        if self.drain && self.n_writes <= self.low_wm {
            self.drain = false;
        }
        self.drain || self.n_reads == 0
    }

    /// Per rank: the earliest column/PRE/ACT time by rank- and channel-wide constraints, and
    /// the refresh due time (from then on only the refresh may issue to the rank).
    fn rank_floor(&self, ri: usize, writes: bool, t: &DramTiming) -> [u64; 4] {
        let rank = &self.ranks[ri];
        let turn = if ri as u32 != self.last_rank {
            t.t_rtrs
        } else {
            0
        };
        let col = if writes {
            let turn = if !self.last_write { t.t_rtrs } else { turn };
            // Write data starts at tc + tCWD; must follow the bus.
            self.now
                .max(rank.col_ok)
                .max((self.bus_free + turn).saturating_sub(t.t_cwd))
        } else {
            self.now
                .max(rank.col_ok)
                .max(rank.rd_ok)
                .max((self.bus_free + turn).saturating_sub(t.t_cas))
        };
        let act = self.now.max(rank.act_ok).max(rank.faw[rank.faw_pos]);
        [col, self.now, act, rank.next_ref]
    }

    /// Bank `bi`'s candidate given its rank's floors; None if a due refresh blocks it.
    fn bank_cand(&mut self, bi: usize, ri: usize, writes: bool, fl: &[u64; 4]) -> Option<Cand> {
        self.refresh_locals(1 << bi, writes);
        let tc = self.local.t[bi].max(fl[usize::from(self.local.kind[bi])]);
        if tc >= fl[3] {
            return None;
        }
        Some(self.local_cand(bi, ri, tc))
    }

    /// The candidate of bank `bi` (rank `ri`, current slot) issuing at `tc`.
    fn local_cand(&self, bi: usize, ri: usize, tc: u64) -> Cand {
        let l = &self.local;
        Cand {
            t: tc,
            class: (l.ord[bi] >> 62) as u8,
            seq: l.ord[bi] & ((1 << 62) - 1),
            bank: bi,
            rank: ri,
            idx: l.idx[bi] as usize,
            cmd: match l.kind[bi] {
                K_COL => Cmd::Col,
                K_PRE => Cmd::Pre,
                _ => Cmd::Act,
            },
        }
    }

    /// Recomputes the stale bank-local slots among `mask`.
    #[inline(always)]
    fn refresh_locals(&mut self, mask: u64, writes: bool) {
        let mut stale = mask & !self.local.valid;
        while stale != 0 {
            let bi = stale.trailing_zeros() as usize;
            stale &= stale - 1;
            bank_local(&mut self.local, bi, &self.banks[bi], writes);
        }
    }

    /// Makes the FR-FCFS choice among all commands that could issue (refreshes due before
    /// `target`, every queued bank's next command) and caches it in `decided`.
    fn decide(&mut self, t: &DramTiming, bpr: usize, target: u64) {
        let mut best: Option<Cand> = None;
        let mut horizon = u64::MAX;
        // Refreshes.
        for (ri, rank) in self.ranks.iter().enumerate() {
            if rank.next_ref >= target {
                horizon = horizon.min(rank.next_ref);
                continue;
            }
            // Precharge-all first if a bank is open, then REF once every bank may activate.
            let banks = &self.banks[ri * bpr..(ri + 1) * bpr];
            let mut tr = rank.next_ref.max(self.now);
            let cmd = if rank.open_banks > 0 {
                for b in banks.iter().filter(|b| b.open_row != NO_ROW) {
                    tr = tr.max(b.pre_ok);
                }
                Cmd::PreAll
            } else {
                for b in banks {
                    tr = tr.max(b.act_ok);
                }
                Cmd::Refresh
            };
            let cand = Cand {
                t: tr,
                class: 0,
                seq: 0,
                bank: 0,
                rank: ri,
                idx: 0,
                cmd,
            };
            if best.is_none_or(|b| cand.key() < b.key()) {
                best = Some(cand);
            }
        }
        let mut writes = self.local_writes;
        if self.n_reads + self.n_writes > 0 {
            writes = self.mode();
            if writes != self.local_writes {
                self.local_writes = writes;
                self.local.valid = 0;
            }
            let mask = if writes {
                self.write_mask
            } else {
                self.read_mask
            };
            self.refresh_locals(mask, writes);
            let mut best_key = best.map_or(u128::MAX, |b| b.key());
            let mut best_bank = usize::MAX;
            let l = &self.local;
            for ri in 0..self.ranks.len() {
                let in_rank = mask & rank_bits(ri, bpr);
                if in_rank == 0 {
                    continue;
                }
                let fl = self.rank_floor(ri, writes, t);
                let (k, nr) = (&l.kind_mask, fl[3]);
                // PRE first: its floor is the lowest, which prunes the other kinds best.
                let (pre, col, act) = (usize::from(K_PRE), usize::from(K_COL), usize::from(K_ACT));
                scan(
                    l,
                    in_rank & k[pre],
                    fl[pre],
                    nr,
                    &mut best_key,
                    &mut best_bank,
                );
                scan(
                    l,
                    in_rank & k[col],
                    fl[col],
                    nr,
                    &mut best_key,
                    &mut best_bank,
                );
                scan(
                    l,
                    in_rank & k[act],
                    fl[act],
                    nr,
                    &mut best_key,
                    &mut best_bank,
                );
            }
            if best_bank != usize::MAX {
                let tc = (best_key >> 64) as u64;
                best = Some(self.local_cand(best_bank, best_bank / bpr, tc));
            }
        }
        self.decided = Decision {
            valid: true,
            best,
            horizon,
            writes,
        };
    }

    /// Folds a request just queued to bank `b` into the cached decision, or drops the
    /// decision when that needs a full [`Self::decide`].
    fn queued(
        &mut self,
        b: usize,
        row: u32,
        write: bool,
        was_empty: bool,
        t: &DramTiming,
        bpr: usize,
    ) {
        let bit = 1u64 << b;
        if write == self.local_writes && self.local.valid & bit != 0 {
            // A newer request changes the bank's next command only if it turns a PRE into a
            // row hit; otherwise the slot, and with it any cached decision, stays as it is
            // (a current slot means the bank's queue was non-empty, so the mode is unchanged).
            if self.local.kind[b] != K_PRE || self.banks[b].open_row != row {
                return;
            }
        }
        self.local.valid &= !bit;
        if !self.decided.valid || was_empty {
            self.decided.valid = false;
            return;
        }
        // The last decision left drain mode consistent (it ends a drain when queues are
        // non-empty), and queueing only adds requests: the mode changes only by this request.
        let writes = self.drain || self.n_reads == 0;
        if writes != self.decided.writes {
            self.decided.valid = false;
            return;
        }
        if write != writes {
            // A queue the scheduler does not look at now.
            return;
        }
        match self.decided.best {
            Some(best) if best.class != 0 && best.bank == b => {
                // The best bank's command may change: needs the runner-up.
                self.decided.valid = false;
            }
            best => {
                let ri = b / bpr;
                let fl = self.rank_floor(ri, writes, t);
                if let Some(cand) = self.bank_cand(b, ri, writes, &fl) {
                    if best.is_none_or(|x| cand.key() < x.key()) {
                        self.decided.best = Some(cand);
                    }
                }
            }
        }
    }

    fn issue(&mut self, cand: Cand, t: &DramTiming, bpr: usize, mut done: impl FnMut(u64, u64)) {
        let tc = cand.t;
        self.now = tc + 1;
        let writes = self.drain || self.n_reads == 0;
        match cand.cmd {
            Cmd::PreAll | Cmd::Refresh => {
                self.local.valid &= !rank_bits(cand.rank, bpr);
            }
            _ => self.local.valid &= !(1u64 << cand.bank),
        }
        match cand.cmd {
            Cmd::PreAll => {
                let ri = cand.rank;
                for b in &mut self.banks[ri * bpr..(ri + 1) * bpr] {
                    if b.open_row != NO_ROW {
                        b.open_row = NO_ROW;
                        b.act_ok = b.act_ok.max(tc + t.t_rp);
                        self.c.precharges += 1;
                    }
                }
                let rank = &mut self.ranks[ri];
                rank.active_cycles += tc.saturating_sub(rank.active_since);
                rank.open_banks = 0;
            }
            Cmd::Refresh => {
                let ri = cand.rank;
                for b in &mut self.banks[ri * bpr..(ri + 1) * bpr] {
                    b.act_ok = tc + t.t_rfc;
                }
                let rank = &mut self.ranks[ri];
                rank.next_ref += t.t_refi;
                self.c.refreshes += 1;
            }
            Cmd::Act => {
                let bank = &mut self.banks[cand.bank];
                let list = if writes {
                    &mut bank.writes
                } else {
                    &mut bank.reads
                };
                let req = &mut list[0];
                let row = req.row;
                if req.outcome.is_none() {
                    req.outcome = Some(RowOutcome::Miss);
                }
                bank.open_row = row;
                bank.col_ok = tc + t.t_rcd;
                bank.pre_ok = tc + t.t_ras;
                bank.act_ok = tc + t.t_rc;
                let rank = &mut self.ranks[cand.rank];
                rank.act_ok = tc + t.t_rrd;
                rank.faw[rank.faw_pos] = tc + t.t_faw;
                rank.faw_pos = (rank.faw_pos + 1) & 3;
                if rank.open_banks == 0 {
                    rank.active_since = tc;
                }
                rank.open_banks += 1;
                self.c.activates += 1;
            }
            Cmd::Pre => {
                let bank = &mut self.banks[cand.bank];
                let list = if writes {
                    &mut bank.writes
                } else {
                    &mut bank.reads
                };
                list[0].outcome = Some(RowOutcome::Conflict);
                bank.open_row = NO_ROW;
                bank.act_ok = bank.act_ok.max(tc + t.t_rp);
                let rank = &mut self.ranks[cand.rank];
                rank.open_banks -= 1;
                if rank.open_banks == 0 {
                    rank.active_cycles += tc.saturating_sub(rank.active_since);
                }
                self.c.precharges += 1;
            }
            Cmd::Col => {
                self.catch_up_occupancy(tc);
                let bi = cand.bank;
                let bank = &mut self.banks[bi];
                let req = if writes {
                    bank.writes.remove(cand.idx)
                } else {
                    bank.reads.remove(cand.idx)
                };
                let rank = &mut self.ranks[cand.rank];
                rank.col_ok = tc + t.t_ccd;
                match req.outcome {
                    None => self.c.row_hits += 1,
                    Some(RowOutcome::Miss) => self.c.row_misses += 1,
                    Some(RowOutcome::Conflict) => self.c.row_conflicts += 1,
                }
                if super::sentinel::is_dma(req.id) {
                    self.c.dma_cols += 1;
                    self.c.dma_row_hits += u64::from(req.outcome.is_none());
                }
                if writes {
                    bank.pre_ok = bank.pre_ok.max(tc + t.t_cwd + t.t_burst + t.t_wr);
                    rank.rd_ok = rank.rd_ok.max(tc + t.t_cwd + t.t_burst + t.t_wtr);
                    self.bus_free = tc + t.t_cwd + t.t_burst;
                    self.last_write = true;
                    self.n_writes -= 1;
                    if bank.writes.is_empty() {
                        self.write_mask &= !(1 << bi);
                    }
                    self.c.writes += 1;
                } else {
                    bank.pre_ok = bank.pre_ok.max(tc + t.t_rtp);
                    let end = tc + t.t_cas + t.t_burst;
                    self.bus_free = end;
                    self.last_write = false;
                    self.n_reads -= 1;
                    if bank.reads.is_empty() {
                        self.read_mask &= !(1 << bi);
                    }
                    self.c.reads += 1;
                    self.c.read_latency_sum += end - req.arrival;
                    done(req.id, end);
                }
                self.last_rank = cand.rank as u32;
            }
        }
    }
}
