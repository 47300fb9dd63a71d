//! Detailed DRAM: per channel an FR-FCFS open-row controller with read and write queues, write
//! drain, refresh, and bank/rank/bus timing constraints.
//!
//! The model is event-driven but cycle-exact with respect to a controller that issues at most
//! one command per channel per DRAM cycle: at each decision it computes, for every bank with
//! queued work, the earliest cycle its next command (ACT, PRE or column) satisfies every timing
//! constraint; the earliest candidate wins, ties broken by row hits first, then age (FR-FCFS).
//! Cycles in which nothing can issue are skipped, and idle channels cost nothing (refreshes are
//! caught up when the channel is next used or its stats are read).

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
}

struct Channel {
    /// First DRAM cycle at which the command bus is free (and up to which time is simulated).
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
    local: Vec<Local>,
    local_writes: bool,
    /// No command can issue before this DRAM cycle unless a request arrives.
    wake: u64,
    c: ChanCounters,
}

/// The bank-local part of a bank's next command (what only that bank's state decides),
/// cached until the bank, its queue or the read/write mode changes.
#[derive(Clone, Copy)]
struct Local {
    valid: bool,
    cmd: Cmd,
    /// Earliest time by the bank's own constraints.
    t: u64,
    seq: u64,
    idx: usize,
}

const INVALID: Local = Local {
    valid: false,
    cmd: Cmd::Act,
    t: 0,
    seq: 0,
    idx: 0,
};

#[derive(Clone, Copy)]
enum Cmd {
    Act,
    Pre,
    Col,
    PreAll,
    Refresh,
}

#[derive(Clone, Copy)]
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
    fn better(&self, o: &Cand) -> bool {
        (self.t, self.class, self.seq) < (o.t, o.class, o.seq)
    }
}

/// The detailed DRAM model (all channels).
pub struct DetailedDram {
    cfg: DetailedDramConfig,
    t: DramTiming,
    channels: Vec<Channel>,
    banks_per_rank: usize,
    col_bits: u32,
    chan_bits: u32,
    bank_bits: u32,
    rank_bits: u32,
    row_mask: u32,
    line_shift: u32,
    /// DRAM cycles per core cycle = dram_mhz / core_mhz.
    dram_mhz: u64,
    core_mhz: u64,
    seq: u64,
    /// DRAM cycle up to which all channels have been advanced.
    now: u64,
}

fn log2(v: u32) -> u32 {
    v.trailing_zeros()
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
            local: vec![INVALID; nb],
            local_writes: false,
            wake: 0,
            c: ChanCounters::default(),
        };
        DetailedDram {
            cfg: cfg.clone(),
            t,
            channels: (0..cfg.channels).map(|_| mk_chan()).collect(),
            banks_per_rank: cfg.banks as usize,
            col_bits: log2(cfg.columns),
            chan_bits: log2(cfg.channels),
            bank_bits: log2(cfg.banks),
            rank_bits: log2(cfg.ranks),
            row_mask: cfg.rows - 1,
            line_shift: log2(cfg.line_bytes),
            dram_mhz: u64::from(cfg.clock_mhz),
            core_mhz: u64::from(core_mhz.max(1)),
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
        self.core_mhz
    }

    /// Timing resolved to DRAM cycles.
    pub fn timing(&self) -> &DramTiming {
        &self.t
    }

    /// Core cycle -> DRAM cycle (floor).
    pub fn to_dram(&self, core: Cycle) -> u64 {
        (u128::from(core) * u128::from(self.dram_mhz) / u128::from(self.core_mhz)) as u64
    }

    /// DRAM cycle -> core cycle (ceil: data is usable at the first core edge after it arrives).
    pub fn to_core(&self, dram: u64) -> Cycle {
        let n = u128::from(dram) * u128::from(self.core_mhz);
        let d = u128::from(self.dram_mhz);
        n.div_ceil(d) as u64
    }

    /// Splits a byte address into (channel, rank, bank index within channel, row).
    pub fn decode(&self, addr: u32) -> (usize, usize, usize, u32) {
        let line = addr >> self.line_shift;
        let take = |v: &mut u32, bits: u32| {
            let f = *v & ((1u32 << bits) - 1);
            *v = v.checked_shr(bits).unwrap_or(0);
            f
        };
        let mut v = line;
        let (chan, rank, bank, row);
        match self.cfg.mapping {
            AddressMapping::RowRankBankChannelColumn => {
                let _col = take(&mut v, self.col_bits);
                chan = take(&mut v, self.chan_bits);
                bank = take(&mut v, self.bank_bits);
                rank = take(&mut v, self.rank_bits);
                row = v & self.row_mask;
            }
            AddressMapping::RowColumnRankBankChannel => {
                chan = take(&mut v, self.chan_bits);
                bank = take(&mut v, self.bank_bits);
                rank = take(&mut v, self.rank_bits);
                let _col = take(&mut v, self.col_bits);
                row = v & self.row_mask;
            }
        }
        let r = rank as usize;
        (
            chan as usize,
            r,
            r * self.banks_per_rank + bank as usize,
            row,
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
        let to_core = |d: u64| -> Cycle {
            let n = u128::from(d) * u128::from(self.core_mhz);
            n.div_ceil(u128::from(self.dram_mhz)) as u64
        };
        let c = &mut self.channels[ch];
        c.catch_up_occupancy(arrival);
        c.local[b].valid = false;
        c.wake = 0;
        if write {
            if c.banks[b].writes.iter().any(|r| r.line == line) {
                c.c.writes_merged += 1;
                return true;
            }
            if c.n_writes >= cap_w {
                return false;
            }
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
                    cycle: to_core(arrival + 1),
                });
                return true;
            }
            if c.n_reads >= cap_r {
                return false;
            }
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
        true
    }

    /// Simulates every DRAM cycle before the one that core cycle `now` starts in; read
    /// completions (data-return cycle, in core cycles; may lie after `now`) go to `out`.
    pub fn advance_to(&mut self, now: Cycle, out: &mut Vec<Completion>) {
        let target = self.to_dram(now);
        if target <= self.now {
            return;
        }
        for ch in 0..self.channels.len() {
            self.advance_channel(ch, target, out);
        }
        self.now = target;
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
            .map(|c| self.to_core(c.now))
            .min()
    }

    fn advance_channel(&mut self, ch: usize, target: u64, out: &mut Vec<Completion>) {
        let t = self.t;
        let bpr = self.banks_per_rank;
        let core_mhz = self.core_mhz;
        let dram_mhz = self.dram_mhz;
        let c = &mut self.channels[ch];
        if target <= c.wake {
            c.now = c.now.max(target);
            c.catch_up_occupancy(target);
            return;
        }
        loop {
            let next_ref = c.ranks.iter().map(|r| r.next_ref).min().unwrap_or(u64::MAX);
            let Some(best) = c.best_candidate(&t, bpr, target) else {
                c.wake = next_ref;
                break;
            };
            if best.t >= target {
                c.wake = best.t.min(next_ref);
                break;
            }
            c.issue(best, &t, bpr, |id, d| {
                let n = u128::from(d) * u128::from(core_mhz);
                out.push(Completion {
                    id,
                    cycle: n.div_ceil(u128::from(dram_mhz)) as u64,
                });
            });
        }
        if c.now < target {
            c.now = target;
        }
        c.catch_up_occupancy(target);
    }

    pub(crate) fn counters(&self) -> impl Iterator<Item = &ChanCounters> {
        self.channels.iter().map(|c| &c.c)
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

/// The bank's next command for the oldest request it can serve (FR: a row hit first).
fn bank_local(bank: &Bank, writes: bool) -> Local {
    let list = if writes { &bank.writes } else { &bank.reads };
    if bank.open_row != NO_ROW {
        if let Some(idx) = list.iter().position(|r| r.row == bank.open_row) {
            return Local {
                valid: true,
                cmd: Cmd::Col,
                t: bank.col_ok,
                seq: list[idx].seq,
                idx,
            };
        }
        return Local {
            valid: true,
            cmd: Cmd::Pre,
            t: bank.pre_ok,
            seq: list[0].seq,
            idx: 0,
        };
    }
    Local {
        valid: true,
        cmd: Cmd::Act,
        t: bank.act_ok,
        seq: list[0].seq,
        idx: 0,
    }
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

    /// The FR-FCFS choice among all ready-able commands (None if nothing to do before `target`).
    fn best_candidate(&mut self, t: &DramTiming, bpr: usize, target: u64) -> Option<Cand> {
        let mut best: Option<Cand> = None;
        // Refreshes.
        for (ri, rank) in self.ranks.iter().enumerate() {
            if rank.next_ref >= target {
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
            if best.as_ref().is_none_or(|b| cand.better(b)) {
                best = Some(cand);
            }
        }
        if self.n_reads + self.n_writes == 0 {
            return best;
        }
        // Write drain mode.
        if self.drain && self.n_writes <= self.cfg_low() {
            self.drain = false;
        }
        let writes = self.drain || self.n_reads == 0;
        if writes != self.local_writes {
            self.local_writes = writes;
            self.local.iter_mut().for_each(|l| l.valid = false);
        }
        let mut mask = if writes {
            self.write_mask
        } else {
            self.read_mask
        };
        while mask != 0 {
            let bi = mask.trailing_zeros() as usize;
            mask &= mask - 1;
            let ri = bi / bpr;
            if !self.local[bi].valid {
                self.local[bi] = bank_local(&self.banks[bi], writes);
            }
            let l = self.local[bi];
            // Every candidate time is at least the bank-local one: prune hopeless banks.
            if best.as_ref().is_some_and(|b| l.t > b.t) {
                continue;
            }
            let rank = &self.ranks[ri];
            let cand = match l.cmd {
                Cmd::Col => {
                    let mut tc = self.now.max(l.t).max(rank.col_ok);
                    let turn = if ri as u32 != self.last_rank {
                        t.t_rtrs
                    } else {
                        0
                    };
                    if writes {
                        let turn = if !self.last_write { t.t_rtrs } else { turn };
                        // Write data starts at tc + tCWD; must follow the bus.
                        tc = tc.max((self.bus_free + turn).saturating_sub(t.t_cwd));
                    } else {
                        tc = tc.max(rank.rd_ok);
                        tc = tc.max((self.bus_free + turn).saturating_sub(t.t_cas));
                    }
                    Cand {
                        t: tc,
                        class: 1,
                        seq: l.seq,
                        bank: bi,
                        rank: ri,
                        idx: l.idx,
                        cmd: Cmd::Col,
                    }
                }
                Cmd::Pre => {
                    let tp = self.now.max(l.t);
                    Cand {
                        t: tp,
                        class: 2,
                        seq: l.seq,
                        bank: bi,
                        rank: ri,
                        idx: 0,
                        cmd: Cmd::Pre,
                    }
                }
                _ => {
                    let ta = self
                        .now
                        .max(l.t)
                        .max(rank.act_ok)
                        .max(rank.faw[rank.faw_pos]);
                    Cand {
                        t: ta,
                        class: 2,
                        seq: l.seq,
                        bank: bi,
                        rank: ri,
                        idx: 0,
                        cmd: Cmd::Act,
                    }
                }
            };
            // From a rank's refresh due time on, only the refresh may issue to it.
            if cand.t >= self.ranks[ri].next_ref {
                continue;
            }
            if best.as_ref().is_none_or(|b| cand.better(b)) {
                best = Some(cand);
            }
        }
        best
    }

    fn cfg_low(&self) -> u32 {
        self.low_wm
    }

    fn issue(&mut self, cand: Cand, t: &DramTiming, bpr: usize, mut done: impl FnMut(u64, u64)) {
        let tc = cand.t;
        self.now = tc + 1;
        let writes = self.drain || self.n_reads == 0;
        match cand.cmd {
            Cmd::PreAll | Cmd::Refresh => {
                let r = cand.rank * bpr..(cand.rank + 1) * bpr;
                self.local[r].iter_mut().for_each(|l| l.valid = false);
            }
            _ => self.local[cand.bank].valid = false,
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
