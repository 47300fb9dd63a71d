//! The memory system as the core sees it: per-TM L1s, L2s shared by groups of TMs, one DRAM.

use super::cache::{Cache, CacheGeometry, CacheStats, Lookup};
use super::cacti::{self, CacheCost};
use super::config::MemSysConfig;
use super::dram::{Dram, DramStats};
use super::{AccessKind, Completion, Cycle, MemRequest, MemSysError};
use serde::Serialize;

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
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub enum Stall {
    /// The L1 bank was used by another access this cycle.
    L1Bank,
    /// All L1 MSHRs are busy.
    L1Mshr,
    /// The L2 bank was used this cycle.
    L2Bank,
    /// All L2 MSHRs are busy.
    L2Mshr,
    /// The DRAM channel's queue is full.
    DramQueue,
}

/// Statistics of the whole memory system.
#[derive(Clone, Debug, PartialEq, Serialize)]
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
}

/// Per-TM L1s, shared L2s and DRAM.
pub struct MemSystem {
    l1: Vec<Cache>,
    l2: Vec<Cache>,
    dram: Dram,
    tms_per_l2: usize,
    l1_cost: CacheCost,
    l2_cost: CacheCost,
    dram_out: Vec<Completion>,
    waiters_l2: Vec<u64>,
    waiters_l1: Vec<u64>,
    done: Vec<Completion>,
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
            l1: (0..tms).map(|_| Cache::new(l1g)).collect(),
            l2: (0..n_l2).map(|_| Cache::new(l2g)).collect(),
            dram: Dram::new(&cfg.dram, core_mhz)?,
            tms_per_l2,
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
            dram_out: Vec::new(),
            waiters_l2: Vec::new(),
            waiters_l1: Vec::new(),
            done: Vec::new(),
        })
    }

    /// Number of L2 caches.
    pub fn num_l2(&self) -> usize {
        self.l2.len()
    }

    /// The DRAM model.
    pub fn dram(&self) -> &Dram {
        &self.dram
    }

    /// One access by TM `tm` at core cycle `now`. Calls within a cycle are served in call order
    /// (the caller fixes a deterministic order); `now` must not decrease between calls.
    pub fn access(&mut self, tm: usize, req: &MemRequest, now: Cycle) -> Access {
        let g = tm / self.tms_per_l2;
        let addr = req.addr;
        if !self.l1[tm].claim_bank(addr, now) {
            return Access::Stall(Stall::L1Bank);
        }
        if req.kind == AccessKind::Write {
            return self.store(tm, g, req, now);
        }
        let l1 = &mut self.l1[tm];
        let line = l1.line_of(addr);
        match l1.lookup(line, now) {
            Lookup::Hit(r) => {
                l1.stats.accesses += 1;
                l1.stats.hits += 1;
                l1.stats.load_bytes += u64::from(req.size);
                l1.touch(line);
                return Access::Ready(r);
            }
            Lookup::Merged(r) => {
                Self::count_merged(l1, req);
                return Access::Ready(r);
            }
            Lookup::Pending(i) => {
                Self::count_merged(l1, req);
                l1.mshr_join(i, req.id);
                return Access::Pending;
            }
            Lookup::Miss => {}
        }
        if !l1.mshr_available() {
            l1.stats.mshr_full += 1;
            return Access::Stall(Stall::L1Mshr);
        }
        let l1_hit = l1.hit_latency();
        let l2 = &mut self.l2[g];
        if !l2.claim_bank(addr, now) {
            return Access::Stall(Stall::L2Bank);
        }
        let l2_res = l2.lookup(line, now);
        if l2_res == Lookup::Miss {
            if !l2.mshr_available() {
                l2.stats.mshr_full += 1;
                return Access::Stall(Stall::L2Mshr);
            }
            if !self.dram.can_accept(addr, false) {
                return Access::Stall(Stall::DramQueue);
            }
        }
        // Accepted from here on.
        let l1 = &mut self.l1[tm];
        l1.stats.accesses += 1;
        l1.stats.misses += 1;
        l1.stats.load_bytes += u64::from(req.size);
        let l2 = &mut self.l2[g];
        l2.stats.accesses += 1;
        l2.stats.load_bytes += u64::from(l2.line_bytes());
        match l2_res {
            Lookup::Hit(r) => {
                l2.stats.hits += 1;
                l2.touch(line);
                self.l1[tm].install(line, r);
                Access::Ready(r + l1_hit)
            }
            Lookup::Merged(r) => {
                l2.stats.misses += 1;
                l2.stats.merged += 1;
                self.l1[tm].install(line, r);
                Access::Ready(r + l1_hit)
            }
            Lookup::Pending(j) => {
                l2.stats.misses += 1;
                l2.stats.merged += 1;
                l2.mshr_join(j, tm as u64);
                self.l1[tm].mshr_alloc(line, req.id);
                Access::Pending
            }
            Lookup::Miss => {
                l2.stats.misses += 1;
                l2.mshr_alloc(line, tm as u64);
                self.l1[tm].mshr_alloc(line, req.id);
                let line_addr = line << self.l1[tm].line_bytes().trailing_zeros();
                let id = ((g as u64) << 32) | u64::from(line);
                let ok = self
                    .dram
                    .submit(id, line_addr, false, now, &mut self.dram_out);
                debug_assert!(ok, "can_accept was checked");
                self.route_dram();
                Access::Pending
            }
        }
    }

    fn count_merged(l1: &mut Cache, req: &MemRequest) {
        l1.stats.accesses += 1;
        l1.stats.misses += 1;
        l1.stats.merged += 1;
        l1.stats.load_bytes += u64::from(req.size);
    }

    fn store(&mut self, tm: usize, g: usize, req: &MemRequest, now: Cycle) -> Access {
        let addr = req.addr;
        if !self.l2[g].claim_bank(addr, now) {
            return Access::Stall(Stall::L2Bank);
        }
        if !self.dram.can_accept(addr, true) {
            return Access::Stall(Stall::DramQueue);
        }
        let l1 = &mut self.l1[tm];
        l1.stats.accesses += 1;
        l1.stats.stores += 1;
        l1.stats.store_bytes += u64::from(req.size);
        let l1_hit = l1.hit_latency();
        let l2 = &mut self.l2[g];
        l2.stats.accesses += 1;
        l2.stats.stores += 1;
        l2.stats.store_bytes += u64::from(l2.line_bytes());
        let line_addr = addr & !(l2.line_bytes() - 1);
        let ok = self
            .dram
            .submit(u64::MAX, line_addr, true, now, &mut self.dram_out);
        debug_assert!(ok, "can_accept was checked");
        self.route_dram();
        Access::Ready(now + l1_hit)
    }

    /// Routes DRAM read completions through the L2 and L1 MSHRs to the requesters.
    fn route_dram(&mut self) {
        let mut fresh = std::mem::take(&mut self.dram_out);
        for c in fresh.drain(..) {
            let g = (c.id >> 32) as usize;
            let line = c.id as u32;
            let l2 = &mut self.l2[g];
            let l2_hit = l2.hit_latency();
            self.waiters_l2.clear();
            l2.fill(line, c.cycle, &mut self.waiters_l2);
            let l1_fill = c.cycle + l2_hit;
            for &tm in &self.waiters_l2 {
                let l1 = &mut self.l1[tm as usize];
                let ready = l1_fill + l1.hit_latency();
                self.waiters_l1.clear();
                l1.fill(line, l1_fill, &mut self.waiters_l1);
                self.done.extend(
                    self.waiters_l1
                        .iter()
                        .map(|&id| Completion { id, cycle: ready }),
                );
            }
        }
        self.dram_out = fresh;
    }

    /// Advances DRAM to core cycle `now` (exclusive) and appends every completion learnt since
    /// the last call to `out`. A completion's cycle is when the load's data is ready; it may lie
    /// after `now` (DRAM data-return times are known once the read is scheduled).
    pub fn advance_to(&mut self, now: Cycle, out: &mut Vec<Completion>) {
        self.dram.advance_to(now, &mut self.dram_out);
        self.route_dram();
        out.append(&mut self.done);
    }

    /// Lower bound on the next core cycle at which [`Self::advance_to`] may report something;
    /// `None` if no request is outstanding below the L2s.
    pub fn next_event(&self) -> Option<Cycle> {
        if !self.done.is_empty() {
            return Some(0);
        }
        self.dram.next_event()
    }

    /// Statistics so far.
    pub fn stats(&self) -> MemStats {
        let mut l1 = CacheStats::default();
        for c in &self.l1 {
            l1.add(&c.stats);
        }
        let l2: Vec<CacheStats> = self.l2.iter().map(|c| c.stats.clone()).collect();
        let l2_reads: u64 = l2.iter().map(|s| s.accesses - s.stores).sum();
        MemStats {
            l1_energy_nj: self.l1_cost.energy_nj * (l1.accesses - l1.stores) as f64,
            l2_energy_nj: self.l2_cost.energy_nj * l2_reads as f64,
            l1_area_mm2: self.l1_cost.area_mm2 * self.l1.len() as f64,
            l2_area_mm2: self.l2_cost.area_mm2 * self.l2.len() as f64,
            l1,
            l2,
            dram: self.dram.stats(),
            l1_cost: self.l1_cost,
            l2_cost: self.l2_cost,
        }
    }
}
