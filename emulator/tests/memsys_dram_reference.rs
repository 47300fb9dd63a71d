//! Differential test of the detailed DRAM model against a plain reference controller.
//!
//! The reference below steps every channel one DRAM cycle at a time and, in each cycle, issues
//! the FR-FCFS choice among the commands whose timing constraints all hold in that cycle:
//! refresh first, then the oldest row hit, then the oldest ACT/PRE; at most one command per
//! channel and cycle; from a rank's refresh due time on, only the refresh may issue to it.
//! It shares no code with the model (address decoding, queues, timing and statistics are
//! re-derived here), so any change of the model's event-driven scheduler that changes a
//! completion cycle, the completion order, `next_event` or a statistic makes this test fail.

use trax_emulator::memsys::dram::DramOpEnergy;
use trax_emulator::memsys::dram_config::{
    AddressMapping, DetailedDramConfig, DramConfig, DramTiming,
};
use trax_emulator::memsys::{Completion, Dram, DramStats, TimeSpec};

const NO_ROW: u32 = u32::MAX;

#[derive(Clone, Debug)]
struct RReq {
    id: u64,
    line: u32,
    bank: usize,
    row: u32,
    write: bool,
    arrival: u64,
    seq: u64,
    /// 0 = row hit, 1 = miss (ACT), 2 = conflict (PRE + ACT).
    outcome: u8,
}

#[derive(Clone, Debug)]
struct RBank {
    open_row: u32,
    act_ok: u64,
    pre_ok: u64,
    col_ok: u64,
}

#[derive(Clone, Debug)]
struct RRank {
    act_ok: u64,
    /// Times of all ACTs so far (the tFAW rule looks at the fourth-last).
    acts: Vec<u64>,
    col_ok: u64,
    rd_ok: u64,
    next_ref: u64,
    open_banks: u32,
    active_since: u64,
    active_cycles: u64,
}

#[derive(Clone, Debug, Default)]
struct RCounters {
    reads: u64,
    writes: u64,
    writes_merged: u64,
    reads_forwarded: u64,
    row_hits: u64,
    row_misses: u64,
    row_conflicts: u64,
    activates: u64,
    refreshes: u64,
    latency: u64,
    occ_r: u128,
    occ_w: u128,
    max_r: u32,
    max_w: u32,
    drains: u64,
}

struct RChannel {
    /// Queued requests in arrival order.
    q: Vec<RReq>,
    banks: Vec<RBank>,
    ranks: Vec<RRank>,
    drain: bool,
    bus_free: u64,
    last_rank: usize,
    last_write: bool,
    /// One past the last command's cycle.
    cmd_next: u64,
    c: RCounters,
}

#[derive(Clone, Copy, PartialEq, Debug)]
enum RCmd {
    PreAll,
    Refresh,
    Col,
    Pre,
    Act,
}

/// The reference controller (all channels).
struct Reference {
    cfg: DetailedDramConfig,
    t: DramTiming,
    core_mhz: u64,
    ch: Vec<RChannel>,
    /// DRAM cycles simulated (all cycles before this one).
    now: u64,
    seq: u64,
}

impl Reference {
    fn new(cfg: &DetailedDramConfig, core_mhz: u32) -> Self {
        let t = cfg.timing.resolve(cfg.clock_mhz);
        let nb = (cfg.ranks * cfg.banks) as usize;
        let ch = (0..cfg.channels)
            .map(|_| RChannel {
                q: Vec::new(),
                banks: vec![
                    RBank {
                        open_row: NO_ROW,
                        act_ok: 0,
                        pre_ok: 0,
                        col_ok: 0,
                    };
                    nb
                ],
                ranks: (0..u64::from(cfg.ranks))
                    .map(|r| RRank {
                        act_ok: 0,
                        acts: Vec::new(),
                        col_ok: 0,
                        rd_ok: 0,
                        next_ref: if t.t_refi == 0 {
                            u64::MAX
                        } else {
                            t.t_refi + t.t_refi * r / u64::from(cfg.ranks)
                        },
                        open_banks: 0,
                        active_since: 0,
                        active_cycles: 0,
                    })
                    .collect(),
                drain: false,
                bus_free: 0,
                last_rank: 0,
                last_write: false,
                cmd_next: 0,
                c: RCounters::default(),
            })
            .collect();
        Reference {
            cfg: cfg.clone(),
            t,
            core_mhz: u64::from(core_mhz),
            ch,
            now: 0,
            seq: 0,
        }
    }

    fn to_dram(&self, core: u64) -> u64 {
        core * u64::from(self.cfg.clock_mhz) / self.core_mhz
    }

    fn to_core(&self, dram: u64) -> u64 {
        (dram * self.core_mhz).div_ceil(u64::from(self.cfg.clock_mhz))
    }

    /// (channel, bank within channel, row, line) of a byte address.
    fn decode(&self, addr: u32) -> (usize, usize, u32, u32) {
        let c = &self.cfg;
        let line = addr / c.line_bytes;
        let mut v = u64::from(line);
        let mut take = |n: u32| {
            let f = v % u64::from(n);
            v /= u64::from(n);
            f as usize
        };
        let (chan, bank, rank) = match c.mapping {
            AddressMapping::RowRankBankChannelColumn => {
                take(c.columns);
                let chan = take(c.channels);
                let bank = take(c.banks);
                (chan, bank, take(c.ranks))
            }
            AddressMapping::RowColumnRankBankChannel => {
                let chan = take(c.channels);
                let bank = take(c.banks);
                let rank = take(c.ranks);
                take(c.columns);
                (chan, bank, rank)
            }
        };
        let row = (v % u64::from(c.rows)) as u32;
        (chan, rank * c.banks as usize + bank, row, line)
    }

    fn can_accept(&self, addr: u32, write: bool) -> bool {
        let (ch, ..) = self.decode(addr);
        let q = &self.ch[ch].q;
        let n = q.iter().filter(|r| r.write == write).count() as u32;
        n < if write {
            self.cfg.write_queue
        } else {
            self.cfg.read_queue
        }
    }

    fn submit(&mut self, id: u64, addr: u32, write: bool, now: u64, out: &mut Vec<Completion>) {
        self.advance_to(now, out);
        let arrival = self.to_dram(now).max(self.now);
        let (chi, bank, row, line) = self.decode(addr);
        let done = self.to_core(arrival + 1);
        let cfg = self.cfg.clone();
        let c = &mut self.ch[chi];
        let queued_write = c.q.iter().any(|r| r.write && r.line == line);
        let n_r = c.q.iter().filter(|r| !r.write).count() as u32;
        let n_w = c.q.len() as u32 - n_r;
        if write {
            if queued_write {
                c.c.writes_merged += 1;
                return;
            }
            if n_w >= cfg.write_queue {
                return;
            }
        } else {
            if queued_write {
                c.c.reads_forwarded += 1;
                c.c.reads += 1;
                c.c.latency += 1;
                out.push(Completion { id, cycle: done });
                return;
            }
            if n_r >= cfg.read_queue {
                return;
            }
        }
        self.seq += 1;
        c.q.push(RReq {
            id,
            line,
            bank,
            row,
            write,
            arrival,
            seq: self.seq,
            outcome: 0,
        });
        if write {
            c.c.max_w = c.c.max_w.max(n_w + 1);
            if n_w + 1 >= cfg.write_high_watermark && !c.drain {
                c.drain = true;
                c.c.drains += 1;
            }
        } else {
            c.c.max_r = c.c.max_r.max(n_r + 1);
        }
    }

    fn advance_to(&mut self, now: u64, out: &mut Vec<Completion>) {
        let target = self.to_dram(now);
        if target <= self.now {
            return;
        }
        for chi in 0..self.ch.len() {
            let mut tc = self.now;
            while tc < target {
                let c = &self.ch[chi];
                if c.q.is_empty() {
                    // Nothing can happen before the next refresh falls due.
                    let due = c.ranks.iter().map(|r| r.next_ref).min().unwrap_or(u64::MAX);
                    if due > tc {
                        tc = due.min(target);
                        continue;
                    }
                }
                self.cycle(chi, tc, out);
                tc += 1;
            }
        }
        self.now = target;
    }

    /// Ends a drain at the low watermark (whenever something is queued).
    fn end_drain(&mut self, chi: usize) {
        let low = self.cfg.write_low_watermark;
        let c = &mut self.ch[chi];
        let n_w = c.q.iter().filter(|r| r.write).count() as u32;
        if !c.q.is_empty() && c.drain && n_w <= low {
            c.drain = false;
        }
    }

    /// One DRAM cycle `tc` of channel `chi`: issue the FR-FCFS choice among ready commands.
    fn cycle(&mut self, chi: usize, tc: u64, out: &mut Vec<Completion>) {
        self.end_drain(chi);
        let t = self.t;
        let bpr = self.cfg.banks as usize;
        let c = &self.ch[chi];
        // (class, seq, command, rank, bank, queue index); smallest wins.
        let mut best: Option<(u8, u64, RCmd, usize, usize, usize)> = None;
        let mut offer = |cand: (u8, u64, RCmd, usize, usize, usize)| {
            if best.is_none_or(|b| (cand.0, cand.1) < (b.0, b.1)) {
                best = Some(cand);
            }
        };
        for (ri, rank) in c.ranks.iter().enumerate() {
            if rank.next_ref > tc {
                continue;
            }
            let banks = &c.banks[ri * bpr..(ri + 1) * bpr];
            if rank.open_banks > 0 {
                if banks.iter().all(|b| b.open_row == NO_ROW || b.pre_ok <= tc) {
                    offer((0, 0, RCmd::PreAll, ri, 0, 0));
                }
            } else if banks.iter().all(|b| b.act_ok <= tc) {
                offer((0, 0, RCmd::Refresh, ri, 0, 0));
            }
        }
        let n_r = c.q.iter().filter(|r| !r.write).count();
        let writes = c.drain || n_r == 0;
        for (bi, bank) in c.banks.iter().enumerate() {
            let ri = bi / bpr;
            let rank = &c.ranks[ri];
            if tc >= rank.next_ref {
                continue;
            }
            let mine = |r: &&RReq| r.bank == bi && r.write == writes;
            let Some((oldest, _)) = c.q.iter().enumerate().find(|(_, r)| mine(r)) else {
                continue;
            };
            let hit =
                c.q.iter()
                    .enumerate()
                    .find(|(_, r)| mine(r) && bank.open_row != NO_ROW && r.row == bank.open_row);
            if let Some((qi, r)) = hit {
                let mut ok = tc >= bank.col_ok && tc >= rank.col_ok;
                let other_rank = ri != c.last_rank;
                if writes {
                    let turn = if !c.last_write || other_rank {
                        t.t_rtrs
                    } else {
                        0
                    };
                    ok &= tc + t.t_cwd >= c.bus_free + turn;
                } else {
                    let turn = if other_rank { t.t_rtrs } else { 0 };
                    ok &= tc >= rank.rd_ok && tc + t.t_cas >= c.bus_free + turn;
                }
                if ok {
                    offer((1, r.seq, RCmd::Col, ri, bi, qi));
                }
            } else if bank.open_row != NO_ROW {
                if tc >= bank.pre_ok {
                    offer((2, c.q[oldest].seq, RCmd::Pre, ri, bi, oldest));
                }
            } else {
                let n = rank.acts.len();
                let faw_ok = n < 4 || tc >= rank.acts[n - 4] + t.t_faw;
                if tc >= bank.act_ok && tc >= rank.act_ok && faw_ok {
                    offer((2, c.q[oldest].seq, RCmd::Act, ri, bi, oldest));
                }
            }
        }
        let chosen = best;
        let c = &mut self.ch[chi];
        // Queue occupancy over [tc, tc + 1) is counted after this cycle's command.
        if let Some((_, _, cmd, ri, bi, qi)) = chosen {
            c.cmd_next = tc + 1;
            match cmd {
                RCmd::PreAll => {
                    for b in &mut c.banks[ri * bpr..(ri + 1) * bpr] {
                        if b.open_row != NO_ROW {
                            b.open_row = NO_ROW;
                            b.act_ok = b.act_ok.max(tc + t.t_rp);
                        }
                    }
                    let rank = &mut c.ranks[ri];
                    rank.active_cycles += tc - rank.active_since;
                    rank.open_banks = 0;
                }
                RCmd::Refresh => {
                    for b in &mut c.banks[ri * bpr..(ri + 1) * bpr] {
                        b.act_ok = tc + t.t_rfc;
                    }
                    c.ranks[ri].next_ref += t.t_refi;
                    c.c.refreshes += 1;
                }
                RCmd::Act => {
                    let r = &mut c.q[qi];
                    if r.outcome == 0 {
                        r.outcome = 1;
                    }
                    let b = &mut c.banks[bi];
                    b.open_row = r.row;
                    b.col_ok = tc + t.t_rcd;
                    b.pre_ok = tc + t.t_ras;
                    b.act_ok = tc + t.t_rc;
                    let rank = &mut c.ranks[ri];
                    rank.act_ok = tc + t.t_rrd;
                    rank.acts.push(tc);
                    if rank.open_banks == 0 {
                        rank.active_since = tc;
                    }
                    rank.open_banks += 1;
                    c.c.activates += 1;
                }
                RCmd::Pre => {
                    c.q[qi].outcome = 2;
                    let b = &mut c.banks[bi];
                    b.open_row = NO_ROW;
                    b.act_ok = b.act_ok.max(tc + t.t_rp);
                    let rank = &mut c.ranks[ri];
                    rank.open_banks -= 1;
                    if rank.open_banks == 0 {
                        rank.active_cycles += tc - rank.active_since;
                    }
                }
                RCmd::Col => {
                    let r = c.q.remove(qi);
                    match r.outcome {
                        0 => c.c.row_hits += 1,
                        1 => c.c.row_misses += 1,
                        _ => c.c.row_conflicts += 1,
                    }
                    c.ranks[ri].col_ok = tc + t.t_ccd;
                    let b = &mut c.banks[bi];
                    if r.write {
                        b.pre_ok = b.pre_ok.max(tc + t.t_cwd + t.t_burst + t.t_wr);
                        let rank = &mut c.ranks[ri];
                        rank.rd_ok = rank.rd_ok.max(tc + t.t_cwd + t.t_burst + t.t_wtr);
                        c.bus_free = tc + t.t_cwd + t.t_burst;
                        c.last_write = true;
                        c.c.writes += 1;
                    } else {
                        b.pre_ok = b.pre_ok.max(tc + t.t_rtp);
                        let end = tc + t.t_cas + t.t_burst;
                        c.bus_free = end;
                        c.last_write = false;
                        c.c.reads += 1;
                        c.c.latency += end - r.arrival;
                        let cycle = (end * self.core_mhz).div_ceil(u64::from(self.cfg.clock_mhz));
                        out.push(Completion { id: r.id, cycle });
                    }
                    c.last_rank = ri;
                }
            }
        }
        let c = &mut self.ch[chi];
        let n_r = c.q.iter().filter(|r| !r.write).count() as u128;
        c.c.occ_r += n_r;
        c.c.occ_w += c.q.len() as u128 - n_r;
        if chosen.is_some() {
            self.end_drain(chi);
        }
    }

    /// Lower bound on the next core cycle with news (the model's definition: the first cycle
    /// a channel with queued requests may issue).
    fn next_event(&self) -> Option<u64> {
        self.ch
            .iter()
            .filter(|c| !c.q.is_empty())
            .map(|c| self.to_core(c.cmd_next.max(self.now)))
            .min()
    }

    fn is_idle(&self) -> bool {
        self.ch.iter().all(|c| c.q.is_empty())
    }

    /// Checks the model's statistics against the reference's counters.
    fn check_stats(&self, s: &DramStats, what: &str) {
        let mut k = RCounters::default();
        let mut active = 0u64;
        for c in &self.ch {
            let x = &c.c;
            k.reads += x.reads;
            k.writes += x.writes;
            k.writes_merged += x.writes_merged;
            k.reads_forwarded += x.reads_forwarded;
            k.row_hits += x.row_hits;
            k.row_misses += x.row_misses;
            k.row_conflicts += x.row_conflicts;
            k.activates += x.activates;
            k.refreshes += x.refreshes;
            k.latency += x.latency;
            k.occ_r += x.occ_r;
            k.occ_w += x.occ_w;
            k.max_r = k.max_r.max(x.max_r);
            k.max_w = k.max_w.max(x.max_w);
            k.drains += x.drains;
            for r in &c.ranks {
                active += r.active_cycles
                    + if r.open_banks > 0 {
                        self.now - r.active_since
                    } else {
                        0
                    };
            }
        }
        let ints = |s: &DramStats| {
            [
                s.reads,
                s.writes,
                s.writes_merged,
                s.reads_forwarded,
                s.row_hits,
                s.row_misses,
                s.row_conflicts,
                s.activates,
                s.refreshes,
                u64::from(s.max_read_queue),
                u64::from(s.max_write_queue),
                s.drain_episodes,
                s.dram_cycles,
            ]
        };
        let expect = [
            k.reads,
            k.writes,
            k.writes_merged,
            k.reads_forwarded,
            k.row_hits,
            k.row_misses,
            k.row_conflicts,
            k.activates,
            k.refreshes,
            u64::from(k.max_r),
            u64::from(k.max_w),
            k.drains,
            self.now,
        ];
        assert_eq!(ints(s), expect, "{what}: counters differ");
        let close = |a: f64, b: f64, name: &str| {
            assert!(
                (a - b).abs() <= 1e-9 * b.abs().max(1.0),
                "{what}: {name} {a} vs reference {b}"
            );
        };
        let dram_mhz = f64::from(self.cfg.clock_mhz);
        if k.reads > 0 {
            let lat = k.latency as f64 / k.reads as f64 * self.core_mhz as f64 / dram_mhz;
            close(s.avg_read_latency_cycles, lat, "avg_read_latency_cycles");
        }
        let denom = self.now as f64 * f64::from(self.cfg.channels);
        if denom > 0.0 {
            close(s.avg_read_queue, k.occ_r as f64 / denom, "avg_read_queue");
            close(s.avg_write_queue, k.occ_w as f64 / denom, "avg_write_queue");
        }
        let op = DramOpEnergy::from_config(&self.cfg.energy, &self.t, self.cfg.clock_mhz);
        let total = self.now * self.ch.len() as u64 * u64::from(self.cfg.ranks);
        let bg = op.active_standby_nj_per_cycle * active as f64
            + op.precharge_standby_nj_per_cycle * (total - active) as f64;
        close(s.energy.background_nj, bg, "energy.background_nj");
    }
}

struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }
}

/// Address patterns of a trace.
#[derive(Clone, Copy, Debug)]
enum Pattern {
    /// Uniform random lines.
    Random,
    /// A few hot lines among random ones (write merging, read forwarding, row hits).
    Hot,
    /// Interleaved sequential streams (row hits, bus and turnaround limits).
    Streams,
}

/// Runs the model and the reference side by side on one generated trace and compares every
/// completion (cycle and order), `next_event`, `can_accept`, `is_idle` and the statistics.
fn differential(cfg: &DramConfig, core_mhz: u32, seed: u64, pattern: Pattern, write_pct: u64) {
    let what = format!("seed {seed} {pattern:?} writes {write_pct}% core {core_mhz} MHz");
    let mut model = Dram::new(cfg, core_mhz).unwrap();
    let mut reference = Reference::new(&cfg.detailed, core_mhz);
    let mut rng = Rng(seed.wrapping_mul(0x9e37_79b9_7f4a_7c15) | 1);
    let hot: Vec<u32> = (0..6).map(|_| rng.next() as u32 & !63).collect();
    let (mut out_m, mut out_r) = (Vec::new(), Vec::new());
    let mut now = 0u64;
    let mut id = 0u64;
    let requests = 3000;
    let compare = |m: &mut Vec<Completion>, r: &mut Vec<Completion>, now: u64| {
        assert_eq!(m, r, "{what}: completions differ by core cycle {now}");
        m.clear();
        r.clear();
    };
    while id < requests {
        let x = rng.next();
        now += match x % 200 {
            0 => 2000 + (x >> 8) % 20_000,
            1..=8 => 1 + (x >> 8) % 200,
            _ => 1,
        };
        if x.is_multiple_of(5) {
            // Some advances in two steps.
            model.advance_to(now - 1, &mut out_m);
            reference.advance_to(now - 1, &mut out_r);
        }
        model.advance_to(now, &mut out_m);
        reference.advance_to(now, &mut out_r);
        compare(&mut out_m, &mut out_r, now);
        assert_eq!(
            model.next_event(),
            reference.next_event(),
            "{what}: next_event at {now}"
        );
        for _ in 0..rng.next() % 8 {
            let y = rng.next();
            let addr = match pattern {
                Pattern::Random => y as u32 & !63,
                Pattern::Hot if y.is_multiple_of(3) => hot[(y >> 8) as usize % hot.len()],
                Pattern::Hot => (y >> 20) as u32 & 0x3f_ffc0,
                Pattern::Streams => {
                    let s = (y >> 8) as u32 % 4;
                    ((s << 22) + (id as u32 / 4) * 64) ^ ((y % 2) as u32) << 16
                }
            };
            let write = (y >> 40) % 100 < write_pct;
            assert_eq!(
                model.can_accept(addr, write),
                reference.can_accept(addr, write),
                "{what}: can_accept at {now}"
            );
            model.submit(id, addr, write, now, &mut out_m);
            reference.submit(id, addr, write, now, &mut out_r);
            id += 1;
        }
        compare(&mut out_m, &mut out_r, now);
    }
    while !model.is_idle() {
        assert!(!reference.is_idle(), "{what}: reference drained first");
        now += 1 + now % 5;
        model.advance_to(now, &mut out_m);
        reference.advance_to(now, &mut out_r);
        compare(&mut out_m, &mut out_r, now);
        assert_eq!(
            model.next_event(),
            reference.next_event(),
            "{what}: next_event at {now}"
        );
    }
    assert!(reference.is_idle(), "{what}: model drained first");
    now += 30_000;
    model.advance_to(now, &mut out_m);
    reference.advance_to(now, &mut out_r);
    compare(&mut out_m, &mut out_r, now);
    reference.check_stats(&model.stats(), &what);
}

/// Shrinks a preset so the cycle-stepping reference stays quick and queues fill up.
fn small(mut cfg: DramConfig, channels: u32) -> DramConfig {
    cfg.detailed.channels = channels;
    cfg
}

fn run_all(cfg: &DramConfig, seeds: u64) {
    for seed in 1..=seeds {
        for (pattern, writes) in [
            (Pattern::Random, 0),
            (Pattern::Random, 30),
            (Pattern::Hot, 40),
            (Pattern::Streams, 10),
        ] {
            let core = if seed.is_multiple_of(2) { 1000 } else { 700 };
            differential(cfg, core, seed, pattern, writes);
        }
    }
}

#[test]
fn gddr5_thesis_matches_reference() {
    run_all(&small(DramConfig::gddr5_thesis(), 2), 3);
}

#[test]
fn ddr4_and_hbm2_match_reference() {
    run_all(&small(DramConfig::ddr4_2400(), 2), 1);
    run_all(&small(DramConfig::hbm2(), 2), 1);
}

#[test]
fn multi_rank_refresh_and_drain_match_reference() {
    // Four ranks of four banks, tiny rows and queues, frequent refresh, short drains:
    // exercises tRRD/tFAW per rank, rank turnaround, refresh blocking and drain hysteresis.
    let mut cfg = small(DramConfig::gddr5_usimm(), 2);
    let d = &mut cfg.detailed;
    d.ranks = 4;
    d.banks = 4;
    d.rows = 16;
    d.columns = 8;
    d.read_queue = 12;
    d.write_queue = 10;
    d.write_high_watermark = 6;
    d.write_low_watermark = 5;
    d.timing.t_refi = TimeSpec::Cycles(700);
    run_all(&cfg, 2);
    // Drain to empty (low watermark 0), the other mapping, no refresh.
    let mut cfg = small(DramConfig::gddr5_thesis(), 1);
    let d = &mut cfg.detailed;
    d.ranks = 2;
    d.write_high_watermark = 3;
    d.write_low_watermark = 0;
    d.mapping = AddressMapping::RowColumnRankBankChannel;
    d.timing.t_refi = TimeSpec::Cycles(0);
    run_all(&cfg, 2);
}
