//! Main memory: the simple and detailed models behind one type, and their statistics.

use super::dram_config::{DramConfig, DramEnergyConfig, DramModel, DramTiming, SimpleDramConfig};
use super::dram_detailed::DetailedDram;
use super::{Completion, Cycle, MemSysError};
use std::collections::VecDeque;

/// Fixed latency plus a bandwidth limit: requests share one pipe of
/// `bandwidth_bytes_per_cycle`, in arrival order; each is done `latency` cycles after its bytes
/// have passed.
pub struct SimpleDram {
    cfg: SimpleDramConfig,
    /// Time the pipe is next free, in units of 1/bandwidth cycles (1 unit = 1 byte slot).
    bus_free: u64,
    /// Done times of requests in flight (non-decreasing).
    in_flight: VecDeque<Cycle>,
    reads: u64,
    writes: u64,
    latency_sum: u64,
    now: Cycle,
}

impl SimpleDram {
    /// A simple model with `cfg`.
    pub fn new(cfg: &SimpleDramConfig) -> Self {
        SimpleDram {
            cfg: cfg.clone(),
            bus_free: 0,
            in_flight: VecDeque::new(),
            reads: 0,
            writes: 0,
            latency_sum: 0,
            now: 0,
        }
    }

    fn retire(&mut self, now: Cycle) {
        while self.in_flight.front().is_some_and(|&d| d <= now) {
            self.in_flight.pop_front();
        }
    }

    fn can_accept(&self) -> bool {
        self.cfg.max_outstanding == 0 || (self.in_flight.len() as u32) < self.cfg.max_outstanding
    }

    fn submit(&mut self, id: u64, write: bool, now: Cycle, out: &mut Vec<Completion>) -> bool {
        self.retire(now);
        if !self.can_accept() {
            return false;
        }
        let bw = u64::from(self.cfg.bandwidth_bytes_per_cycle);
        let start = self.bus_free.max(now * bw);
        let end = start + u64::from(self.cfg.line_bytes);
        self.bus_free = end;
        let done = end.div_ceil(bw) + u64::from(self.cfg.latency);
        self.in_flight.push_back(done);
        if write {
            self.writes += 1;
        } else {
            self.reads += 1;
            self.latency_sum += done - now;
            out.push(Completion { id, cycle: done });
        }
        true
    }
}

/// Main memory, simple or detailed. All cycles at this interface are core cycles.
pub enum Dram {
    /// Fixed latency + bandwidth.
    Simple(SimpleDram),
    /// Channels/ranks/banks with FR-FCFS.
    Detailed(Box<DetailedDram>),
}

/// DRAM energy by category, in nJ.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct DramEnergy {
    /// Standby (active or precharged) over the simulated time.
    pub background_nj: f64,
    /// ACT (+PRE) operations.
    pub activate_nj: f64,
    /// Read bursts.
    pub read_nj: f64,
    /// Write bursts.
    pub write_nj: f64,
    /// Refresh operations.
    pub refresh_nj: f64,
}

impl DramEnergy {
    /// Sum of all categories, nJ.
    pub fn total_nj(&self) -> f64 {
        self.background_nj + self.activate_nj + self.read_nj + self.write_nj + self.refresh_nj
    }
}

/// DRAM statistics (totals over all channels).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct DramStats {
    /// Read requests served (including ones answered from the write queue).
    pub reads: u64,
    /// Line writes performed.
    pub writes: u64,
    /// Writes merged into a queued write to the same line.
    pub writes_merged: u64,
    /// Reads answered from the write queue.
    pub reads_forwarded: u64,
    /// Column accesses that found their row open.
    pub row_hits: u64,
    /// Column accesses that needed an ACT of a closed bank.
    pub row_misses: u64,
    /// Column accesses that needed PRE + ACT (another row was open).
    pub row_conflicts: u64,
    /// ACT commands.
    pub activates: u64,
    /// Refresh commands.
    pub refreshes: u64,
    /// Row-buffer hit rate, hits / (hits + misses + conflicts), 0..1; `None` for the
    /// simple model, which has no rows, and when no column access was made.
    pub row_hit_rate: Option<f64>,
    /// Mean read latency (arrival to last data beat), in core cycles.
    pub avg_read_latency_cycles: f64,
    /// Time-averaged read-queue entries per channel.
    pub avg_read_queue: f64,
    /// Time-averaged write-queue entries per channel.
    pub avg_write_queue: f64,
    /// Largest read-queue occupancy seen in any channel.
    pub max_read_queue: u32,
    /// Largest write-queue occupancy seen in any channel.
    pub max_write_queue: u32,
    /// Write-drain episodes (high watermark reached).
    pub drain_episodes: u64,
    /// Bytes moved (reads + writes, line granularity).
    pub bytes: u64,
    /// Simulated time in core cycles.
    pub core_cycles: u64,
    /// Simulated time in DRAM cycles.
    pub dram_cycles: u64,
    /// Achieved bandwidth, bytes per core cycle.
    pub bytes_per_core_cycle: f64,
    /// Energy breakdown.
    pub energy: DramEnergy,
}

/// Per-operation energies in nJ per rank (derived from IDD values unless overridden).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DramOpEnergy {
    /// ACT with its PRE.
    pub act_nj: f64,
    /// One read burst.
    pub read_nj: f64,
    /// One write burst.
    pub write_nj: f64,
    /// One refresh.
    pub refresh_nj: f64,
    /// Active-standby power, nJ per DRAM cycle per rank.
    pub active_standby_nj_per_cycle: f64,
    /// Precharge-standby power, nJ per DRAM cycle per rank.
    pub precharge_standby_nj_per_cycle: f64,
}

impl DramOpEnergy {
    /// Micron TN-41-01 / USIMM 1.3 derivation, per device then x `devices_per_rank`:
    /// mA x V x ns = pJ, divided by 1000 for nJ. ACT = (IDD0 tRC - IDD3N tRAS - IDD2N (tRC -
    /// tRAS)) V tCK; read = ((IDD4R - IDD3N) V + read termination) tBURST tCK; write =
    /// (IDD4W - IDD3N) V tBURST tCK; refresh = (IDD5 - IDD3N) V tRFC tCK; standby = IDD3N
    /// (a row open) or IDD2N (all banks precharged) x V per cycle.
    pub fn from_config(e: &DramEnergyConfig, t: &DramTiming, clock_mhz: u32) -> Self {
        let tck_ns = 1000.0 / f64::from(clock_mhz);
        let k = e.vdd * f64::from(e.devices_per_rank) * tck_ns / 1000.0;
        let (trc, tras) = (t.t_rc as f64, t.t_ras as f64);
        let act = k * (e.idd0 * trc - (e.idd3n * tras + e.idd2n * (trc - tras))).max(0.0);
        let burst = t.t_burst as f64;
        // mW x ns = pJ, per device, over the burst (USIMM `psch_dq`).
        let read_term =
            e.read_termination_mw * f64::from(e.devices_per_rank) * tck_ns * burst / 1000.0;
        DramOpEnergy {
            act_nj: e.act_nj.unwrap_or(act),
            read_nj: e
                .read_nj
                .unwrap_or(k * (e.idd4r - e.idd3n).max(0.0) * burst + read_term),
            write_nj: e
                .write_nj
                .unwrap_or(k * (e.idd4w - e.idd3n).max(0.0) * burst),
            refresh_nj: e
                .refresh_nj
                .unwrap_or(k * (e.idd5 - e.idd3n).max(0.0) * t.t_rfc as f64),
            active_standby_nj_per_cycle: k * e.idd3n,
            precharge_standby_nj_per_cycle: k * e.idd2n,
        }
    }
}

impl Dram {
    /// Builds the configured model; `core_mhz` is the core clock (1000 for the thesis chip).
    pub fn new(cfg: &DramConfig, core_mhz: u32) -> Result<Self, MemSysError> {
        cfg.validate()?;
        if core_mhz == 0 {
            return Err(MemSysError::Config("core clock must be >= 1 MHz".into()));
        }
        Ok(match cfg.model {
            DramModel::Simple => Dram::Simple(SimpleDram::new(&cfg.simple)),
            DramModel::Detailed => {
                Dram::Detailed(Box::new(DetailedDram::new(&cfg.detailed, core_mhz)))
            }
        })
    }

    /// Bytes per request (the line size).
    pub fn line_bytes(&self) -> u32 {
        match self {
            Dram::Simple(s) => s.cfg.line_bytes,
            Dram::Detailed(d) => d.config().line_bytes,
        }
    }

    /// Whether a request to `addr` would be accepted (queue space).
    pub fn can_accept(&self, addr: u32, write: bool) -> bool {
        match self {
            Dram::Simple(s) => {
                // Conservative: entries whose done time has passed are retired on submit.
                s.can_accept() || s.in_flight.front().is_some_and(|&d| d <= s.now)
            }
            Dram::Detailed(d) => d.can_accept(addr, write),
        }
    }

    /// Submits a line request at core cycle `now` (advances the model to `now` first). Read
    /// completions go to `out` when their data-return cycle is known (it may lie in the future).
    /// Writes are posted: no completion. Returns false if the queue is full (nothing changed).
    pub fn submit(
        &mut self,
        id: u64,
        addr: u32,
        write: bool,
        now: Cycle,
        out: &mut Vec<Completion>,
    ) -> bool {
        self.advance_to(now, out);
        match self {
            Dram::Simple(s) => s.submit(id, write, now, out),
            Dram::Detailed(d) => d.submit(id, addr, write, now, out),
        }
    }

    /// Simulates up to (not including) core cycle `now`; completions go to `out`.
    pub fn advance_to(&mut self, now: Cycle, out: &mut Vec<Completion>) {
        match self {
            Dram::Simple(s) => {
                s.now = s.now.max(now);
                s.retire(now);
            }
            Dram::Detailed(d) => d.advance_to(now, out),
        }
    }

    /// Lower bound on the next core cycle at which something may happen; None when idle.
    pub fn next_event(&self) -> Option<Cycle> {
        match self {
            Dram::Simple(_) => None,
            Dram::Detailed(d) => d.next_event(),
        }
    }

    /// Functional warming (sampled simulation): the row of `addr` is open afterwards, as
    /// after a timed access (the simple model has no rows).
    pub fn warm(&mut self, addr: u32) {
        if let Dram::Detailed(d) = self {
            d.warm(addr);
        }
    }

    /// Whether nothing is queued.
    pub fn is_idle(&self) -> bool {
        match self {
            Dram::Simple(_) => true,
            Dram::Detailed(d) => d.is_idle(),
        }
    }

    /// Peak bandwidth in bytes per core cycle.
    pub fn peak_bytes_per_core_cycle(&self, core_mhz: u32) -> f64 {
        match self {
            Dram::Simple(s) => f64::from(s.cfg.bandwidth_bytes_per_cycle),
            Dram::Detailed(d) => d.config().peak_gbps() * 1000.0 / f64::from(core_mhz),
        }
    }

    /// Column accesses of DMA requests (the ray sentinel's) and how many found their row
    /// open; (0, 0) for the simple model, which has no rows.
    pub fn dma_row_hits(&self) -> (u64, u64) {
        match self {
            Dram::Simple(_) => (0, 0),
            Dram::Detailed(d) => d
                .counters()
                .fold((0, 0), |(c, h), k| (c + k.dma_cols, h + k.dma_row_hits)),
        }
    }

    /// Statistics up to the last `advance_to`.
    pub fn stats(&self) -> DramStats {
        match self {
            Dram::Simple(s) => {
                let bytes = (s.reads + s.writes) * u64::from(s.cfg.line_bytes);
                DramStats {
                    reads: s.reads,
                    writes: s.writes,
                    avg_read_latency_cycles: ratio(s.latency_sum, s.reads),
                    bytes,
                    core_cycles: s.now,
                    bytes_per_core_cycle: ratio(bytes, s.now),
                    energy: DramEnergy {
                        read_nj: s.reads as f64 * s.cfg.energy_per_access_nj,
                        write_nj: s.writes as f64 * s.cfg.energy_per_access_nj,
                        ..DramEnergy::default()
                    },
                    ..DramStats::default()
                }
            }
            Dram::Detailed(d) => detailed_stats(d),
        }
    }
}

fn ratio(a: u64, b: u64) -> f64 {
    if b == 0 {
        0.0
    } else {
        a as f64 / b as f64
    }
}

fn detailed_stats(d: &DetailedDram) -> DramStats {
    let cfg = d.config();
    let mut s = DramStats::default();
    let mut lat = 0u64;
    let (mut occ_r, mut occ_w) = (0u128, 0u128);
    for c in d.counters() {
        s.reads += c.reads;
        s.writes += c.writes;
        s.writes_merged += c.writes_merged;
        s.reads_forwarded += c.reads_forwarded;
        s.row_hits += c.row_hits;
        s.row_misses += c.row_misses;
        s.row_conflicts += c.row_conflicts;
        s.activates += c.activates;
        s.refreshes += c.refreshes;
        s.max_read_queue = s.max_read_queue.max(c.max_reads);
        s.max_write_queue = s.max_write_queue.max(c.max_writes);
        s.drain_episodes += c.drain_episodes;
        lat += c.read_latency_sum;
        occ_r += c.read_occupancy_integral;
        occ_w += c.write_occupancy_integral;
    }
    let cols = s.row_hits + s.row_misses + s.row_conflicts;
    s.row_hit_rate = (cols > 0).then(|| ratio(s.row_hits, cols));
    let dram_cycles = d.dram_cycles();
    s.dram_cycles = dram_cycles;
    s.core_cycles = d.to_core(dram_cycles);
    // Latency counters are in DRAM cycles; report core cycles.
    s.avg_read_latency_cycles =
        ratio(lat, s.reads) * d.core_mhz() as f64 / f64::from(cfg.clock_mhz);
    let denom = dram_cycles as f64 * f64::from(cfg.channels);
    if denom > 0.0 {
        s.avg_read_queue = occ_r as f64 / denom;
        s.avg_write_queue = occ_w as f64 / denom;
    }
    s.bytes = (s.reads - s.reads_forwarded + s.writes) * u64::from(cfg.line_bytes);
    s.bytes_per_core_cycle = ratio(s.bytes, s.core_cycles);
    let op = DramOpEnergy::from_config(&cfg.energy, d.timing(), cfg.clock_mhz);
    let (active, total) = d.active_rank_cycles();
    s.energy = DramEnergy {
        background_nj: op.active_standby_nj_per_cycle * active as f64
            + op.precharge_standby_nj_per_cycle * (total - active) as f64,
        activate_nj: op.act_nj * s.activates as f64,
        read_nj: op.read_nj * (s.reads - s.reads_forwarded) as f64,
        write_nj: op.write_nj * s.writes as f64,
        refresh_nj: op.refresh_nj * s.refreshes as f64,
    };
    s
}
