//! Statistics over time (`trax run --stats-interval N`): the run cut into intervals of
//! `N` simulated cycles (the last one partial), each with its own issue rate, stall
//! breakdown, memory traffic, rays in flight and energy.
//!
//! The engine samples its cumulative counters at the serial phase that ends each interval
//! ([`Snapshot`]; `N` is a multiple of the quantum, so interval ends are quantum ends and
//! no sample needs a cycle inside a quantum); the intervals are differences of
//! consecutive samples, the last one taken from the run's final statistics. They are
//! streamed ([`IntervalStream`]): each goes to the caller's sink as it completes and the run
//! keeps none, so memory does not grow with the number of intervals. Every sample
//! is a sum over TMs at a quantum boundary, so intervals do not depend on the host
//! threads, and the intervals' counts add up to the run's totals exactly.

use serde::Serialize;

use super::engine::ThreadCycles;
use super::stat::stat_group;
use super::stats::{EnergyBreakdown, TimingStats};
use super::stats_doc;
use crate::memsys::{CacheStats, DramStats};

/// Cumulative counters at the end of an interval.
#[derive(Clone, Debug, Default)]
pub struct Snapshot {
    /// The cycle (an interval end).
    pub cycle: u64,
    /// Thread-cycle buckets so far.
    pub tc: ThreadCycles,
    /// Zero-cost debug ops executed so far.
    pub debug_ops: u64,
    /// L1 statistics (all TMs) and L2 statistics (all L2s) so far.
    pub l1: CacheStats,
    pub l2: CacheStats,
    /// DRAM reads, writes and bytes so far.
    pub dram_reads: u64,
    pub dram_writes: u64,
    pub dram_bytes: u64,
    /// Stream memory: rays in flight integrated over cycles so far.
    pub ray_cycles: u64,
    /// Energy so far, joules.
    pub energy_j: f64,
    /// Energy so far by component, joules.
    pub energy: EnergyBreakdown,
    /// DRAM statistics so far (row-buffer outcomes, read latency, energy by kind).
    pub dram: DramStats,
    /// Request-cycles L2 requests waited for a full DRAM queue so far.
    pub dram_queue_full: u64,
    /// Stream memory: rays written and read, buffer visits (schedules), and TM-cycles
    /// idle so far (intervals still open counted up to `cycle`).
    pub stream_writes: u64,
    pub stream_reads: u64,
    pub stream_schedules: u64,
    pub idle_tm_cycles: u64,
}

impl Snapshot {
    /// The final sample: the run's statistics (cycles, totals, energy).
    pub fn of_stats(s: &TimingStats, ray_cycles: u64) -> Self {
        let mut l2 = CacheStats::default();
        for c in &s.memory.l2 {
            l2.add(c);
        }
        Snapshot {
            cycle: s.cycles,
            tc: s.thread_cycles.clone(),
            debug_ops: s.debug_ops,
            l1: s.memory.l1.clone(),
            l2,
            dram_reads: s.memory.dram.reads,
            dram_writes: s.memory.dram.writes,
            dram_bytes: s.memory.dram.bytes,
            ray_cycles,
            energy_j: s.energy.total,
            energy: s.energy.clone(),
            dram: s.memory.dram.clone(),
            dram_queue_full: s.memory.dram_queue_full,
            stream_writes: s.stream.writes,
            stream_reads: s.stream.reads,
            stream_schedules: s.stream.schedules,
            idle_tm_cycles: s.stream.idle_tm_cycles,
        }
    }
}

stat_group!(
    /// One interval of the run (`timing.intervals[]` of the statistics document). A field
    /// declared with `series` is a series of `trax plot --over-time --y FIELD`, the label
    /// its axis label with its unit; the others place the interval in time. The
    /// thread-cycle buckets are series too ([`ThreadCycles::BUCKETS`]).
    #[derive(Clone, Debug, PartialEq, Serialize)]
    pub struct Interval at "timing.intervals[]" {
        start_cycle: u64 => ("int", "first cycle of the interval"),
        end_cycle: u64 => ("int", "cycle after its last (`start_cycle` of the next)"),
        cycles: u64 => ("int", "`end_cycle - start_cycle`"),
        partial: bool => ("bool", "shorter than N (only the last interval can be)"),
        instructions: u64 => ("int", "thread-instructions issued", series = "instructions issued (per interval)"),
        issue_rate: f64 => ("float", "`instructions` / (`cycles` × threads)", series = "issue rate (issued / thread-cycles)"),
        #[serde(serialize_with = "stats_doc::thread_cycles")]
        thread_cycles: ThreadCycles => ("object", "the interval's thread-cycles, bucketed as `timing.thread_cycles`", rows = { |p| ThreadCycles::md_rows_as(p, "timing.thread_cycles", "in this interval") }),
        l1_accesses: u64 => ("int", "L1 accesses, all TMs (as `timing.memory.l1.accesses`)", series = "L1 accesses (per interval)"),
        l1_hits: u64 => ("int", "L1 load hits", series = "L1 load hits (per interval)"),
        l1_misses: u64 => ("int", "L1 load misses", series = "L1 load misses (per interval)"),
        l1_hit_rate: f64 => ("float", "`l1_hits` / (`l1_hits` + `l1_misses`); 0 without loads", series = "L1 hit rate (fraction of loads)"),
        l1_to_register_gbps: f64 => ("float", "L1 load bytes / interval seconds, GB/s", series = "L1 → register bandwidth (GB/s)"),
        l2_accesses: u64 => ("int", "L2 accesses, all L2s", series = "L2 accesses (per interval)"),
        l2_hits: u64 => ("int", "L2 load hits", series = "L2 load hits (per interval)"),
        l2_misses: u64 => ("int", "L2 load misses", series = "L2 load misses (per interval)"),
        l2_hit_rate: f64 => ("float", "`l2_hits` / (`l2_hits` + `l2_misses`); 0 without loads", series = "L2 hit rate (fraction of loads)"),
        l2_to_l1_gbps: f64 => ("float", "L2 load bytes / interval seconds, GB/s", series = "L2 → L1 bandwidth (GB/s)"),
        dram_reads: u64 => ("int", "DRAM reads served", series = "DRAM reads (per interval)"),
        dram_writes: u64 => ("int", "DRAM line writes performed", series = "DRAM writes (per interval)"),
        dram_bytes: u64 => ("int", "DRAM bytes moved", series = "DRAM bytes (per interval)"),
        dram_gbps: f64 => ("float", "`dram_bytes` / interval seconds, GB/s", series = "DRAM bandwidth (GB/s)"),
        mean_rays_in_flight: Option<f64> => ("float?", "rays in the stream memory averaged over the interval; `null` for a chip without one", series = "rays in flight (mean over interval)"),
        energy_j: f64 => ("float", "energy spent in the interval, J (the difference of `timing.energy.total` so far)", series = "energy (J per interval)"),
        power_w: f64 => ("float", "`energy_j` / interval seconds, W", series = "power (W)"),
    }
);

/// `docs/STATS.md`'s table of the intervals: the rows that place them, then the rows of
/// [`Interval::STATS`].
pub fn md_table() -> String {
    use super::stat::{md_row, md_rows};
    md_row(
        "timing.interval_cycles",
        "int?",
        "N; `null` without `--stats-interval`",
    ) + &md_row(
        "timing.intervals",
        "array",
        "one entry per interval, in time order",
    ) + &md_row("timing.intervals[]", "object", "one interval")
        + &md_rows(Interval::STATS)
}

impl Interval {
    /// The plottable series, `(field, axis label)`, in the document's order.
    pub fn series() -> impl Iterator<Item = (&'static str, &'static str)> {
        Self::STATS.iter().filter_map(|st| {
            let name = st.path.rsplit_once('.').map_or(st.path, |(_, n)| n);
            Some((name, st.series?))
        })
    }
}

fn ratio(a: f64, b: f64) -> f64 {
    if b > 0.0 {
        a / b
    } else {
        0.0
    }
}

/// Receives each interval of a run as it completes (`RunRequest::interval_sink`): the run
/// holds none of them, so a long run with a short interval keeps its memory.
pub type IntervalSink<'a> = &'a mut dyn FnMut(&Interval);

/// The intervals of a run as its samples come (the first interval starts at cycle 0 with
/// zero counters): each is handed to the sink once the next sample shows it is not the
/// run's last, and [`Self::finish`] closes the run with its final statistics. Holds two
/// samples, whatever the length of the run.
pub struct IntervalStream<'a> {
    /// Interval length, cycles.
    len: u64,
    /// The chip's threads, clock, and whether it has a stream memory.
    threads: u64,
    clock_ghz: f64,
    stream: bool,
    /// The end of the last interval handed over, and the latest sample.
    prev: Snapshot,
    pending: Option<Snapshot>,
    sink: IntervalSink<'a>,
}

impl<'a> IntervalStream<'a> {
    /// Intervals of `len` cycles on a chip of `threads` threads at `clock_ghz`, with a
    /// stream memory (`stream`) or not, into `sink`.
    pub fn new(
        len: u64,
        threads: u64,
        clock_ghz: f64,
        stream: bool,
        sink: IntervalSink<'a>,
    ) -> Self {
        IntervalStream {
            len,
            threads,
            clock_ghz,
            stream,
            prev: Snapshot::default(),
            pending: None,
            sink,
        }
    }

    /// The counters at an interval end.
    pub fn push(&mut self, s: Snapshot) {
        if let Some(p) = self.pending.replace(s) {
            self.emit(p);
        }
    }

    /// Closes the run with `last`, its final statistics (a sample at the same cycle, where
    /// the run ended on an interval end, is replaced by them).
    pub fn finish(mut self, last: Snapshot) {
        if let Some(p) = self.pending.take() {
            if p.cycle < last.cycle {
                self.emit(p);
            }
        }
        self.emit(last);
    }

    fn emit(&mut self, s: Snapshot) {
        let iv = Interval::between(
            &self.prev,
            &s,
            self.len,
            self.threads,
            self.clock_ghz,
            self.stream,
        );
        (self.sink)(&iv);
        self.prev = s;
    }
}

impl Interval {
    /// The interval from sample `prev` to sample `s` (`len` the interval length, `threads`
    /// the chip's thread count, `stream` whether the chip has a stream memory).
    pub fn between(
        prev: &Snapshot,
        s: &Snapshot,
        len: u64,
        threads: u64,
        clock_ghz: f64,
        stream: bool,
    ) -> Interval {
        let cycles = s.cycle - prev.cycle;
        let secs = cycles as f64 / (clock_ghz * 1e9);
        let gbps = |bytes: u64| ratio(bytes as f64, secs) / 1e9;
        let tc = s.tc.minus(&prev.tc);
        let l1 = |f: fn(&CacheStats) -> u64| f(&s.l1) - f(&prev.l1);
        let l2 = |f: fn(&CacheStats) -> u64| f(&s.l2) - f(&prev.l2);
        let rate = |h: u64, m: u64| ratio(h as f64, (h + m) as f64);
        let (l1h, l1m) = (l1(|c| c.hits), l1(|c| c.misses));
        let (l2h, l2m) = (l2(|c| c.hits), l2(|c| c.misses));
        let energy_j = s.energy_j - prev.energy_j;
        Interval {
            start_cycle: prev.cycle,
            end_cycle: s.cycle,
            cycles,
            partial: cycles < len,
            instructions: tc.issued,
            issue_rate: ratio(tc.issued as f64, (cycles * threads) as f64),
            l1_accesses: l1(|c| c.accesses),
            l1_hits: l1h,
            l1_misses: l1m,
            l1_hit_rate: rate(l1h, l1m),
            l1_to_register_gbps: gbps(l1(|c| c.load_bytes)),
            l2_accesses: l2(|c| c.accesses),
            l2_hits: l2h,
            l2_misses: l2m,
            l2_hit_rate: rate(l2h, l2m),
            l2_to_l1_gbps: gbps(l2(|c| c.load_bytes)),
            dram_reads: s.dram_reads - prev.dram_reads,
            dram_writes: s.dram_writes - prev.dram_writes,
            dram_bytes: s.dram_bytes - prev.dram_bytes,
            dram_gbps: gbps(s.dram_bytes - prev.dram_bytes),
            mean_rays_in_flight: stream
                .then(|| ratio((s.ray_cycles - prev.ray_cycles) as f64, cycles as f64)),
            energy_j,
            power_w: ratio(energy_j, secs),
            thread_cycles: tc,
        }
    }
}
