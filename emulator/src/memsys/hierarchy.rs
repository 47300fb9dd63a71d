//! The memory system as the core sees it: per-TM L1s, L2s shared by groups of TMs, one DRAM.
//!
//! Split in two so TMs can be simulated in parallel: [`TmMem`] (one TM's L1; its accesses
//! touch nothing else) and [`ChipMem`] (L2s and DRAM, which serve the requests the L1s sent,
//! in a fixed order, and send fills back). A request sent at cycle `c` reaches its L2 at
//! `c` and an L2 hit is valid in the L1 at `c + l2.hit_latency`, so a caller that runs the
//! TMs `l1.hit_latency + l2.hit_latency` cycles ahead of the L2s loses no timing.

use super::cache::{Cache, CacheGeometry, CacheStats, Lookup};
use super::cacti::{self, CacheCost};
use super::config::MemSysConfig;
use super::dram::{Dram, DramStats};
use super::regions::{self, ByRegion, RegionCounts, RegionMap};
use super::sentinel::{is_dma, DmaEvent, DmaJob, DmaStats, Sentinel};
use super::{AccessKind, Completion, Cycle, MemRequest, MemSysError};

/// Outcome of [`MemSystem::access`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Access {
    /// Done: a load's data is ready (a store is acknowledged) at this core cycle.
    Ready(Cycle),
    /// Accepted; a [`Completion`] with the request's id will be reported by a later
    /// [`MemSystem::advance_to`].
    Pending,
    /// Refused this cycle (nothing changed except conflict counters); retry later.
    Stall(Stall),
}

/// Why an access was refused.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stall {
    /// The L1 bank was used by another access this cycle.
    L1Bank,
    /// All L1 MSHRs are busy.
    L1Mshr,
}

/// Statistics of the whole memory system.
#[derive(Clone, Debug, PartialEq)]
pub struct MemStats {
    /// Sum over all L1s.
    pub l1: CacheStats,
    /// One entry per L2.
    pub l2: Vec<CacheStats>,
    /// Main memory.
    pub dram: DramStats,
    /// Area and read energy of one L1.
    pub l1_cost: CacheCost,
    /// Area and read energy of one L2.
    pub l2_cost: CacheCost,
    /// L1 energy, nJ: energy per access x (accesses - stores) (write-around: stores excluded).
    pub l1_energy_nj: f64,
    /// L2 energy, nJ, same rule.
    pub l2_energy_nj: f64,
    /// Total L1 area, mm².
    pub l1_area_mm2: f64,
    /// Total L2 area, mm².
    pub l2_area_mm2: f64,
    /// Request-cycles an L2 request waited because its DRAM channel queue was full.
    pub dram_queue_full: u64,
    /// The ray sentinel's DMA engine.
    pub dma: DmaStats,
    /// DRAM column accesses of its requests, and how many found their row open.
    pub dma_columns: u64,
    /// See `dma_columns`.
    pub dma_row_hits: u64,
    /// The memory regions' names, by id (see [`super::regions`]).
    pub region_names: Vec<String>,
    /// All L1s' accesses by memory region.
    pub l1_by_region: ByRegion,
    /// All L2s' accesses by memory region.
    pub l2_by_region: ByRegion,
}

/// A load or store leaving a TM's L1 for its L2.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct L2Request {
    /// Core cycle the L1 sent it.
    pub cycle: Cycle,
    /// Byte address.
    pub addr: u32,
    /// The sending TM.
    pub tm: u32,
    /// Store (write-around) rather than a line fill.
    pub write: bool,
    /// The memory region of `addr` ([`super::regions`]).
    pub region: u16,
}

/// The TM side of the memory system: one L1 and the requests it sends to its L2.
///
/// A TM's accesses touch only this (so TMs can be simulated on different host threads);
/// the L2s and DRAM ([`ChipMem`]) serve the sent requests later, in a fixed order, and
/// send line fills back ([`TmMem::apply_fills`]).
#[derive(Clone)]
pub struct TmMem {
    l1: Cache,
    tm: u32,
    /// Requests sent to the L2 (served by [`ChipMem::serve_until`]).
    sent: Vec<L2Request>,
    /// Line fills received (line, cycle the line is valid in the L1).
    fills: Vec<(u32, Cycle)>,
    waiters: Vec<u64>,
    /// Address → memory region, for `by_region`.
    regions: RegionMap,
    /// The L1's accesses by memory region.
    by_region: ByRegion,
}

impl TmMem {
    /// One access by this TM at core cycle `now`: an L1 hit or a merge with a known fill
    /// time is `Ready`; a miss sends a request to the L2 and is `Pending` (its
    /// [`Completion`] comes from [`Self::apply_fills`]); a store is posted (`Ready` after
    /// the L1 latency). Calls within a cycle are served in call order.
    pub fn access(&mut self, req: &MemRequest, now: Cycle) -> Access {
        let addr = req.addr;
        let l1 = &mut self.l1;
        if !l1.claim_bank(addr, now) {
            return Access::Stall(Stall::L1Bank);
        }
        let region = self.regions.region_of(addr);
        let rc = &mut self.by_region[region as usize];
        if req.kind == AccessKind::Write {
            l1.stats.accesses += 1;
            l1.stats.stores += 1;
            l1.stats.store_bytes += u64::from(req.size);
            rc.accesses += 1;
            rc.stores += 1;
            self.sent.push(L2Request {
                cycle: now,
                addr,
                tm: self.tm,
                write: true,
                region,
            });
            return Access::Ready(now + l1.hit_latency());
        }
        let line = l1.line_of(addr);
        match l1.lookup(line, now) {
            Lookup::Hit(r) => {
                l1.stats.accesses += 1;
                l1.stats.hits += 1;
                l1.stats.load_bytes += u64::from(req.size);
                rc.accesses += 1;
                rc.hits += 1;
                l1.touch(line);
                Access::Ready(r)
            }
            Lookup::Merged(r) => {
                count_merged(l1, rc, req);
                Access::Ready(r)
            }
            Lookup::Pending(i) => {
                count_merged(l1, rc, req);
                l1.mshr_join(i, req.id);
                Access::Pending
            }
            Lookup::Miss => {
                if !l1.mshr_available() {
                    l1.stats.mshr_full += 1;
                    return Access::Stall(Stall::L1Mshr);
                }
                l1.stats.accesses += 1;
                l1.stats.misses += 1;
                l1.stats.load_bytes += u64::from(req.size);
                rc.accesses += 1;
                rc.misses += 1;
                l1.mshr_alloc(line, req.id);
                self.sent.push(L2Request {
                    cycle: now,
                    addr,
                    tm: self.tm,
                    write: false,
                    region,
                });
                Access::Pending
            }
        }
    }

    /// Whether the L1 bank of `addr` refuses an access at cycle `now` (a counted retry, as
    /// [`Self::access`] would count it); if not, nothing changes. A thread refused the cycle
    /// before retries the same access: when this refuses it, its retry ends here.
    #[inline]
    pub fn l1_bank_refuses(&mut self, addr: u32, now: Cycle) -> bool {
        self.l1.refuses(addr, now)
    }

    /// Installs the line fills received from the L2 and appends the completions of the
    /// loads waiting for them to `out`.
    pub fn apply_fills(&mut self, out: &mut Vec<Completion>) {
        if self.fills.is_empty() {
            return;
        }
        let hit = self.l1.hit_latency();
        for (line, at) in self.fills.drain(..) {
            self.waiters.clear();
            self.l1.fill(line, at, &mut self.waiters);
            out.extend(self.waiters.iter().map(|&id| Completion {
                id,
                cycle: at + hit,
            }));
        }
    }

    /// The L1's counters.
    pub fn l1_stats(&self) -> &CacheStats {
        &self.l1.stats
    }

    /// Whether requests were sent since the chip side last collected them.
    pub fn has_sent(&self) -> bool {
        !self.sent.is_empty()
    }

    /// Whether requests or fills are in flight between this L1 and its L2.
    pub fn busy(&self) -> bool {
        !self.sent.is_empty() || !self.fills.is_empty()
    }
}

impl AsMut<TmMem> for TmMem {
    fn as_mut(&mut self) -> &mut TmMem {
        self
    }
}

fn count_merged(l1: &mut Cache, rc: &mut RegionCounts, req: &MemRequest) {
    l1.stats.accesses += 1;
    l1.stats.misses += 1;
    l1.stats.merged += 1;
    l1.stats.load_bytes += u64::from(req.size);
    rc.accesses += 1;
    rc.misses += 1;
    rc.merged += 1;
}

/// The chip side of the memory system: the L2s and DRAM.
pub struct ChipMem {
    l2: Vec<Cache>,
    dram: Dram,
    tms: usize,
    tms_per_l2: usize,
    l1_line_shift: u32,
    /// First core cycle not yet served.
    clock: Cycle,
    /// Requests not yet served, oldest first (once sorted).
    queue: Vec<L2Request>,
    /// Requests were collected since the queue was last sorted.
    unsorted: bool,
    dram_out: Vec<Completion>,
    waiters_l2: Vec<u64>,
    /// Request-cycles a DRAM channel queue was full.
    dram_queue_full: u64,
    /// The ray stream memory's DMA engine (spills and refills).
    sentinel: Sentinel,
    /// The L2s' accesses by memory region.
    by_region: ByRegion,
}

impl ChipMem {
    /// Takes the requests `tm` sent, to be served by [`Self::serve_until`].
    pub fn collect(&mut self, tm: &mut TmMem) {
        if !tm.sent.is_empty() {
            self.queue.append(&mut tm.sent);
            self.unsorted = true;
        }
    }

    /// Serves, cycle by cycle up to `end` (exclusive), the requests collected from the TMs
    /// ([`Self::collect`]) and the DRAM; line fills go back to the TMs' [`TmMem::apply_fills`]. Requests
    /// of one cycle are served oldest first, then in TM order rotating with the cycle; a
    /// request refused (L2 bank taken, L2 MSHRs or the DRAM queue full) is retried the next
    /// cycle.
    pub fn serve_until<T: AsMut<TmMem>>(&mut self, end: Cycle, tms: &mut [T]) {
        if self.unsorted {
            self.unsorted = false;
            let n = self.tms as u64;
            self.queue
                .sort_by_key(|r| (r.cycle, (u64::from(r.tm) + n - r.cycle % n) % n));
        }
        while self.clock < end {
            // While no request waits and no read is outstanding (only writes can be in
            // the DRAM, and they complete nothing), the cycles before the next request
            // change nothing the DRAM model does not catch up exactly in one step.
            let due = self.queue.first().is_some_and(|r| r.cycle <= self.clock);
            if !due && self.reads_done() && self.sentinel.is_idle() {
                let next = self.queue.first().map_or(end, |r| r.cycle.min(end));
                self.clock = self.clock.max(next - 1);
            }
            let c = self.clock;
            self.dram.advance_to(c, &mut self.dram_out);
            self.route_dram(tms);
            if !self.sentinel.is_idle() {
                self.sentinel.step(c, &mut self.dram, &mut self.dram_out);
                self.route_dram(tms);
            }
            let mut i = 0;
            while i < self.queue.len() && self.queue[i].cycle <= c {
                let r = self.queue[i];
                if self.serve(&r, c, tms) {
                    self.queue.remove(i);
                } else {
                    i += 1;
                }
            }
            self.clock += 1;
        }
    }

    /// Serves one request at cycle `c`; false if refused.
    fn serve<T: AsMut<TmMem>>(&mut self, r: &L2Request, c: Cycle, tms: &mut [T]) -> bool {
        let tm = r.tm as usize;
        let g = tm / self.tms_per_l2;
        let l2 = &mut self.l2[g];
        if !l2.claim_bank(r.addr, c) {
            return false;
        }
        if r.write {
            if !self.dram.can_accept(r.addr, true) {
                self.dram_queue_full += 1;
                return false;
            }
            l2.stats.accesses += 1;
            l2.stats.stores += 1;
            l2.stats.store_bytes += u64::from(l2.line_bytes());
            let rc = &mut self.by_region[r.region as usize];
            rc.accesses += 1;
            rc.stores += 1;
            let line_addr = r.addr & !(l2.line_bytes() - 1);
            let ok = self
                .dram
                .submit(u64::MAX, line_addr, true, c, &mut self.dram_out);
            debug_assert!(ok, "can_accept was checked");
            self.route_dram(tms);
            return true;
        }
        let line = r.addr >> self.l1_line_shift;
        let res = l2.lookup(line, c);
        if res == Lookup::Miss {
            if !l2.mshr_available() {
                l2.stats.mshr_full += 1;
                return false;
            }
            if !self.dram.can_accept(r.addr, false) {
                self.dram_queue_full += 1;
                return false;
            }
        }
        l2.stats.accesses += 1;
        l2.stats.load_bytes += u64::from(l2.line_bytes());
        let rc = &mut self.by_region[r.region as usize];
        rc.accesses += 1;
        match res {
            Lookup::Hit(at) => {
                l2.stats.hits += 1;
                rc.hits += 1;
                l2.touch(line);
                tms[tm].as_mut().fills.push((line, at));
            }
            Lookup::Merged(at) => {
                l2.stats.misses += 1;
                l2.stats.merged += 1;
                rc.misses += 1;
                rc.merged += 1;
                tms[tm].as_mut().fills.push((line, at));
            }
            Lookup::Pending(j) => {
                l2.stats.misses += 1;
                l2.stats.merged += 1;
                rc.misses += 1;
                rc.merged += 1;
                l2.mshr_join(j, tm as u64);
            }
            Lookup::Miss => {
                l2.stats.misses += 1;
                rc.misses += 1;
                l2.mshr_alloc(line, tm as u64);
                let line_addr = line << self.l1_line_shift;
                let id = ((g as u64) << 32) | u64::from(line);
                let ok = self
                    .dram
                    .submit(id, line_addr, false, c, &mut self.dram_out);
                debug_assert!(ok, "can_accept was checked");
                self.route_dram(tms);
            }
        }
        true
    }

    /// Routes DRAM read completions through the L2 MSHRs to the TMs' L1s.
    fn route_dram<T: AsMut<TmMem>>(&mut self, tms: &mut [T]) {
        for c in self.dram_out.drain(..) {
            if is_dma(c.id) {
                self.sentinel.arrived(&c);
                continue;
            }
            let g = (c.id >> 32) as usize;
            let line = c.id as u32;
            let l2 = &mut self.l2[g];
            self.waiters_l2.clear();
            l2.fill(line, c.cycle, &mut self.waiters_l2);
            let l1_fill = c.cycle + l2.hit_latency();
            for &tm in &self.waiters_l2 {
                tms[tm as usize].as_mut().fills.push((line, l1_fill));
            }
        }
    }

    /// Whether serving can send the L1s nothing (no request waits, no L2 miss is
    /// outstanding) until new requests are collected. Then the clock may be left behind:
    /// a later [`Self::serve_until`] serves the skipped cycles (DRAM writes, refresh) one by
    /// one before the new requests, exactly as if it had kept up.
    pub fn owes_nothing(&self) -> bool {
        self.queue.is_empty() && self.reads_done() && self.sentinel.is_idle()
    }

    /// Starts a block transfer of the ray stream memory (see [`super::sentinel`]).
    pub fn dma_start(&mut self, job: DmaJob) {
        self.sentinel.start(job);
    }

    /// The transfers' progress since the last call.
    pub fn dma_events(&mut self) -> Vec<DmaEvent> {
        self.sentinel.take_events()
    }

    /// Whether no L2 miss waits for the DRAM.
    fn reads_done(&self) -> bool {
        self.l2.iter().all(|c| c.mshrs_busy() == 0)
    }

    /// Lower bound on the next cycle with news: `None` if nothing is outstanding below the
    /// L1s.
    pub fn next_event(&self) -> Option<Cycle> {
        if !self.queue.is_empty() || !self.sentinel.is_idle() {
            return Some(self.clock);
        }
        self.dram.next_event()
    }
}

/// Per-TM L1s, shared L2s and DRAM.
pub struct MemSystem {
    tm: Vec<TmMem>,
    chip: ChipMem,
    region_names: Vec<String>,
    l1_cost: CacheCost,
    l2_cost: CacheCost,
}

impl MemSystem {
    /// `tms` TMs, each group of `tms_per_l2` consecutive TMs sharing one L2; core clock
    /// `core_mhz`.
    pub fn new(
        cfg: &MemSysConfig,
        tms: usize,
        tms_per_l2: usize,
        core_mhz: u32,
    ) -> Result<Self, MemSysError> {
        cfg.validate()?;
        if tms == 0 || tms_per_l2 == 0 {
            return Err(MemSysError::Config(
                "need at least one TM and one TM per L2".into(),
            ));
        }
        if cfg.dram.model == super::dram_config::DramModel::Detailed
            && cfg.dram.detailed.line_bytes != cfg.l2.line_bytes
        {
            return Err(MemSysError::Config(format!(
                "dram.detailed.line_bytes ({}) must equal l2.line_bytes ({})",
                cfg.dram.detailed.line_bytes, cfg.l2.line_bytes
            )));
        }
        if cfg.l1.line_bytes != cfg.l2.line_bytes {
            return Err(MemSysError::Config(format!(
                "l1.line_bytes ({}) must equal l2.line_bytes ({})",
                cfg.l1.line_bytes, cfg.l2.line_bytes
            )));
        }
        let l1g = CacheGeometry {
            capacity_bytes: cfg.l1.capacity_bytes,
            line_bytes: cfg.l1.line_bytes,
            banks: cfg.l1.banks,
            interleave: cfg.l1.interleave,
            ways: 1,
            hit_latency: cfg.l1.hit_latency,
            mshrs: cfg.l1.mshrs,
            read_copy: cfg.l1.read_copy,
        };
        let l2g = CacheGeometry {
            capacity_bytes: cfg.l2.capacity_bytes,
            line_bytes: cfg.l2.line_bytes,
            banks: cfg.l2.banks,
            interleave: cfg.l2.interleave,
            ways: cfg.l2.associativity,
            hit_latency: cfg.l2.hit_latency,
            mshrs: cfg.l2.mshrs,
            read_copy: false,
        };
        let n_l2 = tms.div_ceil(tms_per_l2);
        Ok(MemSystem {
            tm: (0..tms)
                .map(|i| TmMem {
                    l1: Cache::new(l1g),
                    tm: i as u32,
                    sent: Vec::new(),
                    fills: Vec::new(),
                    waiters: Vec::new(),
                    regions: RegionMap::default(),
                    by_region: vec![RegionCounts::default(); regions::FIXED_REGIONS],
                })
                .collect(),
            chip: ChipMem {
                l2: (0..n_l2).map(|_| Cache::new(l2g)).collect(),
                dram: Dram::new(&cfg.dram, core_mhz)?,
                tms,
                tms_per_l2,
                l1_line_shift: cfg.l1.line_bytes.trailing_zeros(),
                clock: 0,
                queue: Vec::new(),
                unsorted: false,
                dram_out: Vec::new(),
                waiters_l2: Vec::new(),
                dram_queue_full: 0,
                sentinel: Sentinel::new(cfg.l2.line_bytes),
                by_region: vec![RegionCounts::default(); regions::FIXED_REGIONS],
            },
            region_names: RegionMap::default().names().to_vec(),
            l1_cost: cacti::resolve(
                cfg.l1.capacity_bytes,
                cfg.l1.banks,
                cfg.l1.line_bytes,
                cfg.l1.area_mm2,
                cfg.l1.energy_nj,
            ),
            l2_cost: cacti::resolve(
                cfg.l2.capacity_bytes,
                cfg.l2.banks,
                cfg.l2.line_bytes,
                cfg.l2.area_mm2,
                cfg.l2.energy_nj,
            ),
        })
    }

    /// Sets the address → region map of the statistics by region (by default every
    /// address is `other`); call it before the first access.
    pub fn set_regions(&mut self, map: &RegionMap) {
        for t in &mut self.tm {
            t.regions = map.clone();
            t.by_region = vec![RegionCounts::default(); map.len()];
        }
        self.chip.by_region = vec![RegionCounts::default(); map.len()];
        self.region_names = map.names().to_vec();
    }

    /// Number of L2 caches.
    pub fn num_l2(&self) -> usize {
        self.chip.l2.len()
    }

    /// The DRAM model.
    pub fn dram(&self) -> &Dram {
        &self.chip.dram
    }

    /// Takes the TM sides out, for a caller that drives them apart from the chip side
    /// (the timing engine simulates TMs on several host threads); put them back with
    /// [`Self::restore_tms`] before reading statistics.
    pub fn take_tms(&mut self) -> Vec<TmMem> {
        std::mem::take(&mut self.tm)
    }

    /// Puts back the TM sides taken by [`Self::take_tms`].
    pub fn restore_tms(&mut self, tms: Vec<TmMem>) {
        self.tm = tms;
    }

    /// The chip side (L2s and DRAM).
    pub fn chip_mut(&mut self) -> &mut ChipMem {
        &mut self.chip
    }

    /// One access by TM `tm` at core cycle `now` (see [`TmMem::access`]). `now` must not
    /// decrease between calls.
    pub fn access(&mut self, tm: usize, req: &MemRequest, now: Cycle) -> Access {
        self.tm[tm].access(req, now)
    }

    /// Serves everything sent before core cycle `now` and appends every completion learnt
    /// so far to `out`. A completion's cycle is when the load's data is ready; it may lie
    /// after `now` (a DRAM read's return time is known once it is scheduled).
    pub fn advance_to(&mut self, now: Cycle, out: &mut Vec<Completion>) {
        for t in &mut self.tm {
            self.chip.collect(t);
        }
        self.chip.serve_until(now, &mut self.tm);
        for t in &mut self.tm {
            t.apply_fills(out);
        }
    }

    /// Lower bound on the next core cycle at which [`Self::advance_to`] may report something;
    /// `None` if no request is outstanding below the L1s.
    pub fn next_event(&self) -> Option<Cycle> {
        if self.tm.iter().any(TmMem::busy) {
            return Some(0);
        }
        self.chip.next_event()
    }

    /// Functional warming (sampled simulation): the load (`write` false) or store of TM
    /// `tm` at `addr` changes the cache tags and DRAM row buffers as its timed access
    /// would, at once and without statistics: a load looks up the L1, on a miss the L2
    /// (both install the line), on a miss the DRAM opens the line's row; a store goes
    /// around both caches (write-around, no allocation) and opens its row. Call it only
    /// while nothing is in flight ([`Self::is_drained`]).
    /// Returns where a load was served: 0 the L1, 1 the L2, 2 the DRAM (a store: 0).
    pub fn warm(&mut self, tm: usize, addr: u32, write: bool) -> u8 {
        if write {
            self.chip.dram.warm(addr);
            return 0;
        }
        let l1 = &mut self.tm[tm].l1;
        if l1.warm(l1.line_of(addr)) {
            return 0;
        }
        let chip = &mut self.chip;
        if chip.l2[tm / chip.tms_per_l2].warm(addr >> chip.l1_line_shift) {
            return 1;
        }
        self.chip.dram.warm(addr);
        2
    }

    /// Whether nothing is in flight anywhere: no request waits between an L1 and its L2,
    /// no L1 or L2 miss is outstanding, no DRAM request is queued.
    pub fn is_drained(&self) -> bool {
        self.tm.iter().all(|t| !t.busy() && t.l1.mshrs_busy() == 0)
            && self.chip.owes_nothing()
            && self.chip.dram.is_idle()
    }

    /// Serves everything in flight (requests, fills, DRAM reads and writes) from core cycle
    /// `from` on, the TMs issuing nothing; returns the first cycle at which nothing is left
    /// ([`Self::is_drained`]). Load completions are dropped: their threads are not waiting
    /// for them any more. Gives up after `limit` cycles (`None`: the memory system does not
    /// come to rest).
    pub fn drain(&mut self, from: Cycle, limit: Cycle) -> Option<Cycle> {
        let mut now = from;
        let mut dropped = Vec::new();
        while !self.is_drained() {
            if now - from > limit {
                return None;
            }
            now += 1;
            self.advance_to(now, &mut dropped);
            dropped.clear();
        }
        Some(now)
    }

    /// The L1 of TM `tm` and the L2s (for comparing cache states).
    pub fn caches(&self, tm: usize) -> (&Cache, &[Cache]) {
        (&self.tm[tm].l1, &self.chip.l2)
    }

    /// Statistics so far.
    pub fn stats(&self) -> MemStats {
        self.stats_with(&self.tm)
    }

    /// Statistics so far, with the TM sides `tms` (taken by [`Self::take_tms`]).
    pub fn stats_with<'a>(&self, tms: impl IntoIterator<Item = &'a TmMem>) -> MemStats {
        let mut l1 = CacheStats::default();
        let mut l1_by_region = ByRegion::new();
        let mut n = 0usize;
        for t in tms {
            l1.add(&t.l1.stats);
            regions::add(&mut l1_by_region, &t.by_region);
            n += 1;
        }
        let l2: Vec<CacheStats> = self.chip.l2.iter().map(|c| c.stats.clone()).collect();
        let l2_reads: u64 = l2.iter().map(|s| s.accesses - s.stores).sum();
        MemStats {
            l1_energy_nj: self.l1_cost.energy_nj * (l1.accesses - l1.stores) as f64,
            l2_energy_nj: self.l2_cost.energy_nj * l2_reads as f64,
            l1_area_mm2: self.l1_cost.area_mm2 * n as f64,
            l2_area_mm2: self.l2_cost.area_mm2 * self.chip.l2.len() as f64,
            dram_queue_full: self.chip.dram_queue_full,
            dma: self.chip.sentinel.stats,
            dma_columns: self.chip.dram.dma_row_hits().0,
            dma_row_hits: self.chip.dram.dma_row_hits().1,
            l1,
            l2,
            dram: self.chip.dram.stats(),
            l1_cost: self.l1_cost,
            l2_cost: self.l2_cost,
            l1_by_region,
            l2_by_region: self.chip.by_region.clone(),
            region_names: self.region_names.clone(),
        }
    }
}
