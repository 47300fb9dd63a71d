//! Statistics of a timing run: performance, stalls, instruction mix, memory, energy, area.

use std::collections::BTreeMap;
use std::fmt::Write as _;

use serde::Serialize;
use trax_runtime::isa::UnitClass;

use super::config::ChipConfig;
use super::engine::{Counters, ThreadCycles};
use super::stat::{md_row, stat_group, summary_lines, walk};
use super::stats_doc;
use super::units::{self, UNITS};
use crate::memsys::{CacheStats, MemStats, RegionCounts};
use crate::program::Program;

/// One component of a breakdown ([`EnergyBreakdown::PARTS`], [`AreaBreakdown::PARTS`]).
pub struct Part<B> {
    /// Its path in the statistics document (`timing.energy.l1`).
    pub path: &'static str,
    /// Label in the text summary.
    pub short: &'static str,
    /// Sweep column (`results.csv`, `trax plot --y`; energy parts stack in energy charts).
    pub column: &'static str,
    /// Axis or legend label.
    pub label: &'static str,
    /// What it counts (the field's doc and its `docs/STATS.md` row).
    pub doc: &'static str,
    /// Its value.
    pub get: fn(&B) -> f64,
}

/// Declares a breakdown by component from one list — per component its field, summary
/// label, sweep column, chart label and doc — with a `total` that sums them in order: the
/// struct, its JSON, `PARTS` (which the summary line, the sweep's energy columns and the
/// `docs/STATS.md` rows walk).
macro_rules! breakdown {
    ($(#[$sdoc:meta])* $name:ident at $path:literal {
        $( $field:ident => ($short:literal, $column:literal, $label:literal, $doc:literal), )*
    }) => {
        $(#[$sdoc])*
        #[derive(Clone, Debug, Default, PartialEq, Serialize)]
        pub struct $name {
            $( #[doc = $doc] pub $field: f64, )*
            /// Sum of the above.
            pub total: f64,
        }

        impl $name {
            /// The components, in field order.
            pub const PARTS: &'static [Part<$name>] = &[
                $( Part {
                    path: concat!($path, ".", stringify!($field)),
                    short: $short,
                    column: $column,
                    label: $label,
                    doc: $doc,
                    get: |b| b.$field,
                }, )*
            ];

            /// `self` with `total` the sum of the components, in field order.
            fn totalled(mut self) -> Self {
                self.total = 0.0 $( + self.$field )*;
                self
            }
        }
    };
}

breakdown!(
    /// Energy per frame by component (thesis Figure 1.1 categories), joules.
    EnergyBreakdown at "timing.energy" {
        execution_units => ("units", "energy_units_j", "Execution units", "execution units"),
        register_files => ("regs", "energy_regs_j", "Register files", "register-file reads and writes"),
        instruction_caches => ("icache", "energy_icache_j", "Instruction caches", "instruction fetch"),
        local_stores => ("local", "energy_local_j", "Local stores", "local stores (stacks)"),
        l1 => ("L1", "energy_l1_j", "L1", "L1 data caches"),
        l2 => ("L2", "energy_l2_j", "L2", "L2 data caches"),
        stream_memory => ("stream", "energy_stream_j", "Stream memory", "ray stream memory: `timing.stream.energy_per_access_nj` × (reads + writes + rays the spill sentinel moved)"),
        pipelines => ("pipelines", "energy_pipelines_j", "Pipelines", "fused pipelines: box tests × `timing.pipelines.box_op_energy_nj` + triangle tests × `tri_op_energy_nj`"),
        dram => ("DRAM", "energy_dram_j", "DRAM", "off-chip DRAM"),
    }
);

breakdown!(
    /// Chip area by component, mm².
    AreaBreakdown at "timing.area" {
        execution_units => ("units", "area_units_mm2", "Execution units", "execution units, all TMs"),
        register_files => ("regs", "area_regs_mm2", "Register files", "register files"),
        instruction_caches => ("icache", "area_icache_mm2", "Instruction caches", "instruction caches"),
        local_stores => ("local", "area_local_mm2", "Local stores", "local stores"),
        l1 => ("L1", "area_l1_mm2", "L1", "L1 data caches"),
        l2 => ("L2", "area_l2_mm2", "L2", "L2 data caches"),
        stream_memory => ("stream", "area_stream_mm2", "Stream memory", "ray stream memory (`chip.stream_memory.area_mm2`, or a data cache's of its capacity and banks); 0 without one"),
        pipelines => ("pipelines", "area_pipelines_mm2", "Pipelines", "pipelines beyond the units they borrow (MUXes, latches: taken as negligible, thesis §3.2.3): 0"),
    }
);

/// `docs/STATS.md`'s rows of a breakdown: one per component, then the total.
pub fn stats_md_rows<B>(parts: &[Part<B>]) -> String {
    let mut s = String::new();
    for p in parts {
        let _ = writeln!(s, "| `{}` | float | {} |", p.path, p.doc);
    }
    if let Some((map, _)) = parts.first().and_then(|p| p.path.rsplit_once('.')) {
        let _ = writeln!(s, "| `{map}.total` | float | sum of the above |");
    }
    s
}

/// `title: short value  short value ...  total value` over a breakdown's parts.
fn summary_line<B>(
    title: &str,
    b: &B,
    parts: &[Part<B>],
    total: f64,
    fmt: fn(f64) -> String,
) -> String {
    let mut s = format!("{title}:");
    for p in parts {
        let _ = write!(s, " {} {} ", p.short, fmt((p.get)(b)));
    }
    let _ = write!(s, " total {}", fmt(total));
    s
}

stat_group!(
    /// The ray stream memory's activity (all zero when the kernel uses no stream).
    #[derive(Clone, Debug, Default, PartialEq, Serialize)]
    pub struct StreamStats at "timing.stream" {
        capacity_rays: u32 => ("int", "rays it holds (head pointers and links charged against its bytes)"),
        writes: u64 => ("int", "rays written (`trax.strwend`), one SRAM access each", column = ("stream_writes", "Stream memory writes", "")),
        reads: u64 => ("int", "rays read (`trax.strrstart` that found one), one SRAM access each", column = ("stream_reads", "Stream memory reads", "")),
        max_rays_in_flight: u32 => ("int", "most rays stored at once"),
        mean_rays_in_flight: f64 => ("float", "rays stored, averaged over `cycles`", column = ("rays_in_flight", "Rays in flight (mean)", "")),
        bank_conflicts: u64 => ("int", "accesses delayed by a busy bank"),
        bank_conflict_cycles: u64 => ("int", "cycles those accesses waited"),
        schedules: u64 => ("int", "decisions of the TMs' stream schedulers that gave a TM a buffer after `trax.strsched` drained it (buffer visits; the end of the frame's stream work, when all get 0xFFFFFFFF, is not one)", column = ("stream_schedules", "Stream buffer visits", "")),
        switches: u64 => ("int", "schedules that gave the TM another buffer than the one it had (the first of a TM counts)"),
        rays_per_visit: f64 => ("float", "rays read per buffer visit: `reads / schedules` (0 without schedules)", column = ("stream_rays_per_visit", "Rays per buffer visit", "")),
        idle_tm_cycles: u64 => ("int", "TM-cycles a TM was idle: drained (every live thread of it in `trax.strsched`) with every buffer empty, until a ray was written to any buffer or the frame's stream work was done (replaces `starved_tm_cycles`, which counted from a schedule that found nothing to the TM's next one that found rays)", column = ("stream_idle_tm_cycles", "TM-cycles idle for lack of rays", "cycles")),
        energy_per_access_nj: f64 => ("float", "energy per access, nJ (thesis Table 3.3 by capacity unless configured); 0 without a stream memory"),
        spill: SpillStats => ("object", "the ray-buffer sentinel (`chip.stream_memory.overflow = \"spill\"`, thesis §7.1.1); zeros otherwise", nested = { SpillStats::STATS }),
    }
);

stat_group!(
    /// The ray-buffer sentinel's activity (thesis §7.1.1).
    #[derive(Clone, Debug, Default, PartialEq, Serialize)]
    pub struct SpillStats at "timing.stream.spill" {
        spills: u64 => ("int", "blocks written to the DRAM spill area"),
        refills: u64 => ("int", "blocks read back"),
        spilled_bytes: u64 => ("int", "ray bytes spilled: rays × `chip.stream_memory.ray_bytes` (each ray also one SRAM access, counted in `timing.energy.stream_memory`)"),
        refilled_bytes: u64 => ("int", "ray bytes read back"),
        max_blocks: u32 => ("int", "most blocks in the spill area at once"),
        stall_cycles: u64 => ("int", "thread-cycles stream writes (memory full while a block drains) and reads (rays on their way back) waited for the sentinel"),
        dram_lines_written: u64 => ("int", "DRAM line writes of the transfers (included in `timing.memory.dram`)"),
        dram_lines_read: u64 => ("int", "DRAM line reads of the transfers (included in `timing.memory.dram`)"),
        dram_row_hit_rate: Option<f64> => ("float?", "row-buffer hit rate of those DRAM accesses, 0..1; `null` with the simple DRAM (it has no rows) or without such accesses"),
        busy_cycles: u64 => ("int", "cycles a transfer was under way"),
        transfer_gbps: f64 => ("float", "(spilled + refilled bytes) / busy time, GB/s"),
    }
);

stat_group!(
    /// The fused pipelines' activity.
    #[derive(Clone, Debug, Default, PartialEq, Serialize)]
    pub struct PipelineStats at "timing.pipelines" {
        box_ops: u64 => ("int", "`trax.boxtest` operations"),
        tri_ops: u64 => ("int", "`trax.tritest` operations"),
        reserved_unit_cycles: u64 => ("int", "FP multiplier and adder unit-cycles reserved by a pipeline mode, all TMs"),
        box_op_energy_nj: f64 => ("float", "energy of one box test, nJ: (fp_mul × E(fp_mul) + fp_add × E(fp_add)) × ii / width of `chip.pipelines.box`"),
        tri_op_energy_nj: f64 => ("float", "the same for one triangle test"),
    }
);

/// Energy of one pipeline op: the reserved units each do one operation per cycle of the
/// initiation interval, shared by the `width` tests of an initiation:
/// `(fp_mul x E(fp_mul) + fp_add x E(fp_add)) x ii / width`. For the box test that is the
/// thesis's 6 multiplies and 6 subtracts (§3.2.3); for the triangle test an upper bound
/// (every reserved unit busy every cycle).
pub fn pipe_op_energy_nj(cfg: &ChipConfig, p: &super::config::PipeConfig) -> f64 {
    let e = |c: UnitClass| cfg.unit(c).energy_nj;
    (f64::from(p.fp_mul) * e(UnitClass::FpMul) + f64::from(p.fp_add) * e(UnitClass::FpAdd))
        * f64::from(p.ii)
        / f64::from(p.width)
}

stat_group!(
    /// Everything a timing run reports. Serialized as the `timing` object of the statistics
    /// document (`--stats-json`, see `docs/STATS.md`); the fields marked `skip` are there at
    /// the top level (`chip`, `cycles`, `instructions`, `rays`, `counters`).
    #[derive(Clone, Debug, Serialize)]
    pub struct TimingStats at "timing" {
        #[serde(skip)]
        /// Chip config name.
        chip: String,
        #[serde(skip)]
        /// TMs.
        tms: u32,
        #[serde(skip)]
        /// Threads per TM.
        threads_per_tm: u32,
        #[serde(skip)]
        /// Core clock, GHz.
        clock_ghz: f64,
        #[serde(skip)]
        /// Core cycles until the last thread halted (the document's `cycles`).
        cycles: u64,
        seconds: f64 => ("float", "simulated seconds, `cycles` / clock", column = ("seconds", "Simulated time", "s")),
        fps: f64 => ("float", "frames per second (one run = one frame)", column = ("fps", "Frame rate", "frames/s")),
        #[serde(skip)]
        /// Thread-instructions issued, debug-class ops excluded (the document's `instructions`).
        instructions: u64,
        debug_ops: u64 => ("int", "debug-class ops (prints, counters, profile markers) executed at zero cost"),
        #[serde(skip)]
        /// Rays, statistics counter 0 (the document's `rays`).
        rays: u64,
        mrps: f64 => ("float", "million rays per simulated second", column = ("mrps", "Ray throughput", "Mrays/s")),
        issue_rate: f64 => ("float", "issued instructions / (cycles × threads), 0..1", column = ("issue_rate", "Issue rate", "issued / thread-cycle")),
        avg_threads_issuing: f64 => ("float", "issued instructions / cycles"),
        #[serde(serialize_with = "stats_doc::thread_cycles")]
        thread_cycles: ThreadCycles => ("object", "where every live thread-cycle went (each in one bucket)", rows = { ThreadCycles::md_rows }),
        data_stalls_by_producer: BTreeMap<String, u64> => ("map", "data-dependence stall thread-cycles by the mnemonic of the producing instruction", rows = { |p| md_row(&format!("{p}.*"), "int", "stalls on one mnemonic") }),
        unit_conflicts: BTreeMap<String, u64> => ("map", "execution-unit conflict thread-cycles by unit class", rows = { |p| md_row(&format!("{p}.*"), "int", "conflicts of one class") }),
        instruction_mix: BTreeMap<String, u64> => ("map", "issued instructions (debug ops included) by mnemonic", rows = { |p| md_row(&format!("{p}.*"), "int", "count of one mnemonic") }),
        class_mix: BTreeMap<String, u64> => ("map", "issued operations by unit class", rows = { |p| md_row(&format!("{p}.*"), "int", "count of one class") }),
        l1_hit_rate: f64 => ("float", "strict L1 load hit rate, all TMs, 0..1: `hits / (hits + misses)`; a load merged into an outstanding fill of its line is a miss", column = ("l1_hit_rate", "L1 hit rate", "")),
        l1_hit_rate_merged_as_hits: f64 => ("float", "L1 load hit rate counting merged loads as hits, 0..1: `(hits + merged) / (hits + misses)`, the loads that sent no request to the L2", column = ("l1_hit_rate_merged", "L1 hit rate (merged loads as hits)", "")),
        l2_hit_rate: f64 => ("float", "strict L2 load hit rate, all L2s, 0..1 (as for the L1)", column = ("l2_hit_rate", "L2 hit rate", "")),
        l2_hit_rate_merged_as_hits: f64 => ("float", "L2 load hit rate counting merged requests as hits, 0..1: the requests that sent none to DRAM"),
        l1_to_register_gbps: f64 => ("float", "L1 → register bandwidth, GB/s"),
        l2_to_l1_gbps: f64 => ("float", "L2 → L1 bandwidth, GB/s"),
        dram_gbps: f64 => ("float", "DRAM → L2 bandwidth, GB/s", column = ("dram_gbps", "DRAM bandwidth", "GB/s")),
        #[serde(serialize_with = "stats_doc::memory")]
        /// Memory-system statistics, caches and DRAM (`docs/STATS.md`'s own section).
        memory: MemStats,
        energy: EnergyBreakdown => ("object", "energy per frame by component, joules (thesis Figure 1.1 categories)", rows = { |_| stats_md_rows(EnergyBreakdown::PARTS) }),
        power_w: f64 => ("float", "average power, watts", column = ("power_w", "Power", "W")),
        energy_per_ray_nj: f64 => ("float", "energy per ray, nJ: `timing.energy.total` over `rays` (the kernel's ray counter, `trax.stat 0`, once per ray cast: camera, shadow and bounce rays alike; 0 without rays). DRAM background vs dynamic energy: `timing.memory.dram.energy` (background + refresh vs activate + read + write)", column = ("energy_per_ray_nj", "Energy per ray (per trax.stat 0 ray)", "nJ")),
        area: AreaBreakdown => ("object", "chip area by component, mm² (`timing::area_breakdown`; the `baseline` preset's sources, line by line against thesis Tables 2.2/2.4/2.5, are in `ChipConfig::preset`: 142.9 mm² vs the thesis's 147)", rows = { |_| stats_md_rows(AreaBreakdown::PARTS) }),
        mrps_per_mm2: f64 => ("float", "`timing.mrps` / `timing.area.total`", column = ("mrps_per_mm2", "Ray throughput per area", "Mrays/s/mm²")),
        stream: StreamStats => ("object", "the ray stream memory (STRaTA, thesis §3.2.1); zeros when no stream is used", nested = { StreamStats::STATS }),
        pipelines: PipelineStats => ("object", "the fused box and triangle pipelines (`trax.setpipe`, thesis §3.2.3)", nested = { PipelineStats::STATS }),
        #[serde(skip)]
        /// The `trax.stat` counters (the document's `counters`).
        counters: Vec<u64>,
        /// `--stats-interval`: cycles per interval (`None`: no intervals recorded). The
        /// intervals themselves went to the run's interval sink as they completed; the
        /// statistics document adds them as `timing.intervals` (`docs/STATS.md`'s own section).
        interval_cycles: Option<u64>,
    }
);

/// Energy so far, by component: `c` the engine's counters, `mem` the memory system's
/// statistics, `stream_accesses` the stream memory's reads plus writes.
pub(crate) fn energy_of(
    cfg: &ChipConfig,
    c: &Counters,
    mem: &MemStats,
    stream_accesses: u64,
) -> EnergyBreakdown {
    let nj = 1e-9;
    let mut eu_energy = 0.0;
    for (k, &ops) in c.class_ops.iter().enumerate() {
        if let Some(u) = units::unit_at(k) {
            eu_energy += cfg.unit_named(u.name).energy_nj * ops as f64;
        }
    }
    let sm = &cfg.stream_memory;
    let stream_nj = if sm.capacity_bytes > 0 {
        sm.energy_per_access_nj()
    } else {
        0.0
    };
    let e = |p: &super::config::PipeConfig, ops: UnitClass| {
        c.class_ops[ops as usize] as f64 * pipe_op_energy_nj(cfg, p)
    };
    EnergyBreakdown {
        execution_units: eu_energy * nj,
        register_files: cfg.register_file.energy_nj * c.reg_accesses as f64 * nj,
        instruction_caches: cfg.icache.energy_nj * c.fetches as f64 * nj,
        local_stores: cfg.local_store.energy_nj * c.local_accesses as f64 * nj,
        l1: mem.l1_energy_nj * nj,
        l2: mem.l2_energy_nj * nj,
        stream_memory: stream_nj * stream_accesses as f64 * nj,
        pipelines: (e(&cfg.pipelines.box_pipe, UnitClass::BoxPipe)
            + e(&cfg.pipelines.tri, UnitClass::TriPipe))
            * nj,
        dram: mem.dram.energy.total_nj() * nj,
        total: 0.0,
    }
    .totalled()
}

fn mnemonic(p: &Program, idx: usize) -> String {
    match p.insts.get(idx) {
        Some(i) => {
            let s = i.to_string();
            s.split_whitespace().next().unwrap_or("?").to_string()
        }
        None => "(outside text)".into(),
    }
}

fn by_mnemonic(p: &Program, counts: &[u64]) -> BTreeMap<String, u64> {
    let mut m = BTreeMap::new();
    for (i, &c) in counts.iter().enumerate() {
        if c > 0 {
            *m.entry(mnemonic(p, i)).or_insert(0) += c;
        }
    }
    m
}

fn ratio(a: f64, b: f64) -> f64 {
    if b > 0.0 {
        a / b
    } else {
        0.0
    }
}

/// Chip area by component: units, register files, I-caches and local stores from the chip
/// config, the L1s' and L2s' total areas (`MemStats::l1_area_mm2`, `l2_area_mm2`) as given,
/// the stream memory when it has a capacity. The sources of the `baseline` preset's figures
/// (thesis Tables 2.2, 2.4, 2.5) are at `ChipConfig::preset`.
pub fn area_breakdown(cfg: &ChipConfig, l1_area_mm2: f64, l2_area_mm2: f64) -> AreaBreakdown {
    let threads = cfg.tms as u64 * cfg.threads_per_tm as u64;
    let sm = &cfg.stream_memory;
    let has_stream = sm.capacity_bytes > 0;
    let tms = cfg.tms as f64;
    // A unit that takes instructions is on the chip only when its config lists it.
    let per_tm_units: f64 = UNITS
        .iter()
        .filter(|d| d.takes.is_none() || cfg.units.contains_key(d.name))
        .map(|d| {
            let u = cfg.unit_named(d.name);
            u.area_mm2 * u.count as f64
        })
        .sum();
    AreaBreakdown {
        execution_units: per_tm_units * tms,
        register_files: cfg.register_file.area_mm2 * threads as f64,
        instruction_caches: cfg.icache.area_mm2 * cfg.icache.per_tm as f64 * tms,
        local_stores: cfg.local_store.area_mm2 * threads as f64,
        l1: l1_area_mm2,
        l2: l2_area_mm2,
        stream_memory: if has_stream { sm.area() } else { 0.0 },
        pipelines: 0.0,
        total: 0.0,
    }
    .totalled()
}

/// Builds the statistics from the raw counters and the chip after the run (program,
/// `trax.stat` counters, stream memory and schedulers).
pub fn build(
    cfg: &ChipConfig,
    c: &Counters,
    cycles: u64,
    mem: MemStats,
    sh: &crate::thread::Shared,
) -> TimingStats {
    let (program, counters) = (&sh.program, &sh.stats[..]);
    let (streams, sched) = (&sh.streams, &sh.sched);
    let threads = cfg.tms as u64 * cfg.threads_per_tm as u64;
    let hz = cfg.clock_ghz * 1e9;
    let seconds = cycles as f64 / hz;
    let rays = counters.first().copied().unwrap_or(0);
    let mrps = ratio(rays as f64 / 1e6, seconds);
    let mut unit_conflicts = BTreeMap::new();
    let mut class_mix = BTreeMap::new();
    for k in 0..c.class_ops.len() {
        let name = units::counter_name(k);
        if c.unit_conflicts[k] > 0 {
            unit_conflicts.insert(name.to_string(), c.unit_conflicts[k]);
        }
        if c.class_ops[k] > 0 {
            class_mix.insert(name.to_string(), c.class_ops[k]);
        }
    }
    let mut l2 = CacheStats::default();
    for s in &mem.l2 {
        l2.add(s);
    }
    let bw = |bytes: u64| ratio(bytes as f64, seconds) / 1e9;
    let sm = &cfg.stream_memory;
    let has_stream = sm.capacity_bytes > 0;
    let stream = StreamStats {
        capacity_rays: streams.capacity_rays(),
        writes: streams.writes,
        reads: streams.reads,
        max_rays_in_flight: streams.max_in_flight,
        mean_rays_in_flight: ratio(c.stream_ray_cycles as f64, cycles as f64),
        bank_conflicts: c.stream_bank_conflicts,
        bank_conflict_cycles: c.stream_conflict_cycles,
        schedules: sched.schedules,
        switches: sched.switches,
        rays_per_visit: ratio(streams.reads as f64, sched.schedules as f64),
        idle_tm_cycles: sched.idle_tm_cycles,
        energy_per_access_nj: if has_stream {
            sm.energy_per_access_nj()
        } else {
            0.0
        },
        spill: {
            let s = streams.spill_stats();
            let moved = s.spilled_bytes + s.refilled_bytes;
            SpillStats {
                spills: s.spills,
                refills: s.refills,
                spilled_bytes: s.spilled_bytes,
                refilled_bytes: s.refilled_bytes,
                max_blocks: s.max_blocks,
                stall_cycles: c.stream_spill_stall_cycles,
                dram_lines_written: mem.dma.lines_written,
                dram_lines_read: mem.dma.lines_read,
                dram_row_hit_rate: (mem.dma_columns > 0)
                    .then(|| ratio(mem.dma_row_hits as f64, mem.dma_columns as f64)),
                busy_cycles: mem.dma.busy_cycles,
                transfer_gbps: ratio(moved as f64, mem.dma.busy_cycles as f64 / hz) / 1e9,
            }
        },
    };
    let pipelines = PipelineStats {
        box_ops: c.class_ops[UnitClass::BoxPipe as usize],
        tri_ops: c.class_ops[UnitClass::TriPipe as usize],
        reserved_unit_cycles: c.reserved_unit_cycles,
        box_op_energy_nj: pipe_op_energy_nj(cfg, &cfg.pipelines.box_pipe),
        tri_op_energy_nj: pipe_op_energy_nj(cfg, &cfg.pipelines.tri),
    };
    let energy = energy_of(cfg, c, &mem, streams.sram_accesses());
    let area = area_breakdown(cfg, mem.l1_area_mm2, mem.l2_area_mm2);
    TimingStats {
        chip: cfg.name.clone(),
        tms: cfg.tms,
        threads_per_tm: cfg.threads_per_tm,
        clock_ghz: cfg.clock_ghz,
        cycles,
        seconds,
        fps: ratio(1.0, seconds),
        instructions: c.tc.issued,
        debug_ops: c.debug_ops,
        rays,
        mrps,
        issue_rate: ratio(c.tc.issued as f64, (cycles * threads) as f64),
        avg_threads_issuing: ratio(c.tc.issued as f64, cycles as f64),
        thread_cycles: c.tc.clone(),
        data_stalls_by_producer: by_mnemonic(program, &c.dep_by_producer),
        unit_conflicts,
        instruction_mix: by_mnemonic(program, &c.issued_at),
        class_mix,
        l1_hit_rate: mem.l1.hit_rate(),
        l1_hit_rate_merged_as_hits: mem.l1.hit_rate_merged_as_hits(),
        l2_hit_rate: l2.hit_rate(),
        l2_hit_rate_merged_as_hits: l2.hit_rate_merged_as_hits(),
        l1_to_register_gbps: bw(mem.l1.load_bytes),
        l2_to_l1_gbps: bw(l2.load_bytes),
        dram_gbps: bw(mem.dram.bytes),
        power_w: ratio(energy.total, seconds),
        energy_per_ray_nj: ratio(energy.total * 1e9, rays as f64),
        mrps_per_mm2: ratio(mrps, area.total),
        energy,
        area,
        memory: mem,
        counters: counters.to_vec(),
        stream,
        pipelines,
        interval_cycles: None,
    }
}

fn pct(a: u64, b: u64) -> f64 {
    ratio(a as f64 * 100.0, b as f64)
}

fn top(out: &mut String, title: &str, m: &BTreeMap<String, u64>, total: u64, n: usize) {
    let _ = writeln!(out, "{title}");
    let mut v: Vec<(&String, &u64)> = m.iter().collect();
    v.sort_by(|a, b| b.1.cmp(a.1).then(a.0.cmp(b.0)));
    for (k, c) in v.into_iter().take(n) {
        let _ = writeln!(out, "   {k:<14} {c:>14} ({:5.2}%)", pct(*c, total));
    }
}

/// The summary's table of L1 and L2 loads by memory region: per region with accesses, its
/// loads, strict and merged-as-hit hit rates, and its share of the cache's misses (strict)
/// and of the requests it sent on (misses not merged).
fn by_region(out: &mut String, m: &MemStats) {
    let (l1, l2) = (&m.l1_by_region, &m.l2_by_region);
    if l1.iter().chain(l2).all(|r| r.accesses == 0) {
        return;
    }
    let _ = writeln!(
        out,
        "loads by region, L1 | L2: loads, hit % (counting merged as hits), share of the misses (of the requests sent on):"
    );
    let total = |b: &[RegionCounts]| {
        b.iter()
            .fold((0, 0), |(m, s), r| (m + r.misses, s + r.misses - r.merged))
    };
    let (t1, t2) = (total(l1), total(l2));
    let cols = |r: &RegionCounts, (tm, ts): (u64, u64)| {
        let loads = r.hits + r.misses;
        format!(
            "{loads:>12} {:6.2}% ({:6.2}%) {:5.1}% ({:5.1}%)",
            pct(r.hits, loads),
            pct(r.hits + r.merged, loads),
            pct(r.misses, tm),
            pct(r.misses - r.merged, ts)
        )
    };
    for (i, (a, b)) in l1.iter().zip(l2).enumerate() {
        if a.accesses + b.accesses > 0 {
            let _ = writeln!(
                out,
                "   {:<30} {} | {}",
                m.region_names[i],
                cols(a, t1),
                cols(b, t2)
            );
        }
    }
}

impl TimingStats {
    /// Human-readable summary.
    pub fn summary(&self) -> String {
        let mut s = String::new();
        let tc = &self.thread_cycles;
        let thread_cycles = self.cycles * self.tms as u64 * self.threads_per_tm as u64;
        let _ = writeln!(
            s,
            "chip: {} ({} TMs x {} threads, {} GHz)",
            self.chip, self.tms, self.threads_per_tm, self.clock_ghz
        );
        let _ = writeln!(
            s,
            "cycles: {}  ({:.6} s, {:.3} frames/s)",
            self.cycles, self.seconds, self.fps
        );
        let _ = writeln!(
            s,
            "instructions: {}  issue rate {:.2}%  ({:.2} threads issuing per cycle)",
            self.instructions,
            self.issue_rate * 100.0,
            self.avg_threads_issuing
        );
        let _ = writeln!(
            s,
            "rays: {}  {:.3} MRPS  {:.4} MRPS/mm2",
            self.rays, self.mrps, self.mrps_per_mm2
        );
        let _ = writeln!(s, "thread-cycles:");
        for b in ThreadCycles::BUCKETS {
            let (name, v) = (b.label, (b.get)(tc));
            let _ = writeln!(s, "   {name:<18} {v:>14} ({:5.2}%)", pct(v, thread_cycles));
        }
        let dep_total: u64 = self.data_stalls_by_producer.values().sum();
        top(
            &mut s,
            "data dependence stalls by producer:",
            &self.data_stalls_by_producer,
            dep_total,
            12,
        );
        let uc: u64 = self.unit_conflicts.values().sum();
        top(
            &mut s,
            "execution-unit conflicts:",
            &self.unit_conflicts,
            uc,
            12,
        );
        top(
            &mut s,
            "instruction mix:",
            &self.instruction_mix,
            self.instructions + self.debug_ops,
            16,
        );
        let m = &self.memory;
        let _ = writeln!(
            s,
            "L1: {} accesses, {:.2}% hit ({:.2}% counting merged loads as hits), {} bank-busy retry thread-cycles ({} bank conflicts), {} stores; L2: {:.2}% hit ({:.2}% counting merged) ({} L2s)",
            m.l1.accesses,
            self.l1_hit_rate * 100.0,
            self.l1_hit_rate_merged_as_hits * 100.0,
            m.l1.bank_retries,
            m.l1.bank_conflict_events,
            m.l1.stores,
            self.l2_hit_rate * 100.0,
            self.l2_hit_rate_merged_as_hits * 100.0,
            m.l2.len()
        );
        let l2_bank: u64 = m.l2.iter().map(|c| c.bank_retries).sum();
        let l2_mshr: u64 = m.l2.iter().map(|c| c.mshr_full).sum();
        let _ = writeln!(
            s,
            "L2 requests delayed (request-cycles): bank conflict {l2_bank}, MSHRs full {l2_mshr}, DRAM queue full {}",
            m.dram_queue_full
        );
        by_region(&mut s, m);
        let _ = writeln!(
            s,
            "bandwidth (GB/s): L1->reg {:.2}  L2->L1 {:.2}  DRAM {:.2}",
            self.l1_to_register_gbps, self.l2_to_l1_gbps, self.dram_gbps
        );
        let d = &m.dram;
        let _ = writeln!(
            s,
            "DRAM: {} reads, {} writes, row-hit {}, avg read latency {:.1} cycles, avg read queue {:.2}",
            d.reads,
            d.writes,
            // The simple model has no rows (nor a detailed one that was never accessed).
            d.row_hit_rate
                .map_or("n/a".into(), |r| format!("{:.2}%", r * 100.0)),
            d.avg_read_latency_cycles,
            d.avg_read_queue
        );
        let (a, e) = (&self.area, &self.energy);
        let area = summary_line("area (mm2)", a, AreaBreakdown::PARTS, a.total, |v| {
            format!("{v:.2}")
        });
        let energy = summary_line("energy (J)", e, EnergyBreakdown::PARTS, e.total, |v| {
            format!("{v:.3e}")
        });
        let _ = writeln!(s, "{area}");
        let _ = writeln!(s, "{energy}  ({:.2} W)", self.power_w);
        let de = &d.energy;
        let _ = writeln!(
            s,
            "energy per ray: {:.1} nJ over {} rays (trax.stat 0); DRAM background (standby + refresh) {:.3e} J, dynamic (activate + read + write) {:.3e} J",
            self.energy_per_ray_nj,
            self.rays,
            (de.background_nj + de.refresh_nj) * 1e-9,
            (de.activate_nj + de.read_nj + de.write_nj) * 1e-9
        );
        let st = &self.stream;
        if st.reads + st.writes > 0 {
            let _ = writeln!(
                s,
                "stream memory: {} rays capacity, {} writes, {} reads, rays in flight max {} mean {:.1}, {} bank conflicts ({} cycles); {} schedules ({} switches, {:.1} rays per visit), {} idle TM-cycles",
                st.capacity_rays, st.writes, st.reads, st.max_rays_in_flight, st.mean_rays_in_flight,
                st.bank_conflicts, st.bank_conflict_cycles, st.schedules, st.switches, st.rays_per_visit,
                st.idle_tm_cycles
            );
        }
        let p = &self.pipelines;
        if p.box_ops + p.tri_ops + p.reserved_unit_cycles > 0 {
            let _ = writeln!(
                s,
                "pipelines: {} box tests ({:.4} nJ each), {} triangle tests ({:.4} nJ each), {} FP unit-cycles reserved",
                p.box_ops, p.box_op_energy_nj, p.tri_ops, p.tri_op_energy_nj, p.reserved_unit_cycles
            );
        }
        // The statistics declared with a summary label (the lines above print the older
        // ones in their own words).
        if walk(Self::STATS).iter().any(|st| st.summary.is_some()) {
            let json = serde_json::to_value(self).unwrap_or_default();
            s += &summary_lines(Self::STATS, &json, "timing");
        }
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The total is the sum of the parts, and every part is read by its own field.
    #[test]
    fn parts_read_their_fields_and_total_sums_them() {
        let mut e = EnergyBreakdown::default();
        let fields = [
            &mut e.execution_units,
            &mut e.register_files,
            &mut e.instruction_caches,
            &mut e.local_stores,
            &mut e.l1,
            &mut e.l2,
            &mut e.stream_memory,
            &mut e.pipelines,
            &mut e.dram,
        ];
        assert_eq!(fields.len(), EnergyBreakdown::PARTS.len());
        for (i, f) in fields.into_iter().enumerate() {
            *f = (1u64 << i) as f64;
        }
        let e = e.totalled();
        for (i, p) in EnergyBreakdown::PARTS.iter().enumerate() {
            assert_eq!((p.get)(&e), (1u64 << i) as f64, "{}", p.path);
        }
        assert_eq!(e.total, 511.0);
        let line = summary_line("energy (J)", &e, EnergyBreakdown::PARTS, e.total, |v| {
            format!("{v}")
        });
        let mut want = String::from("energy (J):");
        for (i, p) in EnergyBreakdown::PARTS.iter().enumerate() {
            want += &format!(" {} {} ", p.short, 1u64 << i);
        }
        assert_eq!(line, want + " total 511");
        let json = serde_json::to_value(&e).unwrap();
        for p in EnergyBreakdown::PARTS {
            let key = p.path.rsplit_once('.').unwrap().1;
            assert_eq!(json[key].as_f64(), Some((p.get)(&e)), "{}", p.path);
        }
    }
}
