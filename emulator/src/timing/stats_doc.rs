//! Serialization at the edge: the `timing` object of the statistics document (`--stats-json`,
//! `docs/STATS.md`) writes the model's counters through these mirror types, so the engine's
//! and the memory system's own types (`ThreadCycles`, `CacheStats`, `DramStats`, `MemStats`,
//! `CacheCost`) derive no `Serialize` and can change without changing the document's schema.
//! Field names and order are the document's; their meaning is documented there.

use serde::ser::SerializeMap;
use serde::{Serialize, Serializer};

use super::engine::ThreadCycles;
use crate::memsys::cacti::{CacheCost, Source};
use crate::memsys::RegionCounts;
use crate::memsys::{CacheStats, DramEnergy, DramStats, MemStats};

/// `timing.memory`.
#[derive(Serialize)]
struct MemStatsDoc {
    l1: CacheStatsDoc,
    l2: Vec<CacheStatsDoc>,
    dram: DramStatsDoc,
    l1_cost: CacheCostDoc,
    l2_cost: CacheCostDoc,
    l1_energy_nj: f64,
    l2_energy_nj: f64,
    l1_area_mm2: f64,
    l2_area_mm2: f64,
    dram_queue_full: u64,
    l1_by_region: Vec<RegionDoc>,
    l2_by_region: Vec<RegionDoc>,
}

/// `timing.memory.l1_by_region[]`, `timing.memory.l2_by_region[]`: one region's accesses.
#[derive(Serialize)]
struct RegionDoc {
    region: String,
    accesses: u64,
    hits: u64,
    misses: u64,
    merged: u64,
    stores: u64,
    hit_rate: f64,
    hit_rate_merged_as_hits: f64,
}

/// The regions with accesses, in region order.
fn by_region(names: &[String], b: &[RegionCounts]) -> Vec<RegionDoc> {
    let rate = |a: u64, loads: u64| {
        if loads > 0 {
            a as f64 / loads as f64
        } else {
            0.0
        }
    };
    (b.iter().enumerate())
        .filter(|(_, r)| r.accesses > 0)
        .map(|(i, r)| RegionDoc {
            region: names[i].clone(),
            accesses: r.accesses,
            hits: r.hits,
            misses: r.misses,
            merged: r.merged,
            stores: r.stores,
            hit_rate: rate(r.hits, r.hits + r.misses),
            hit_rate_merged_as_hits: rate(r.hits + r.merged, r.hits + r.misses),
        })
        .collect()
}

/// `timing.memory.l1`, `timing.memory.l2[]`.
#[derive(Serialize)]
struct CacheStatsDoc {
    accesses: u64,
    hits: u64,
    misses: u64,
    merged: u64,
    bank_retries: u64,
    bank_conflict_events: u64,
    mshr_full: u64,
    stores: u64,
    load_bytes: u64,
    fill_bytes: u64,
    store_bytes: u64,
}

/// `timing.memory.l1_cost`, `timing.memory.l2_cost`.
#[derive(Serialize)]
struct CacheCostDoc {
    area_mm2: f64,
    energy_nj: f64,
    source: &'static str,
}

/// `timing.memory.dram`.
#[derive(Serialize)]
struct DramStatsDoc {
    reads: u64,
    writes: u64,
    writes_merged: u64,
    reads_forwarded: u64,
    row_hits: u64,
    row_misses: u64,
    row_conflicts: u64,
    activates: u64,
    refreshes: u64,
    row_hit_rate: Option<f64>,
    avg_read_latency_cycles: f64,
    avg_read_queue: f64,
    avg_write_queue: f64,
    max_read_queue: u32,
    max_write_queue: u32,
    drain_episodes: u64,
    bytes: u64,
    core_cycles: u64,
    dram_cycles: u64,
    bytes_per_core_cycle: f64,
    energy: DramEnergyDoc,
}

/// `timing.memory.dram.energy`.
#[derive(Serialize)]
struct DramEnergyDoc {
    background_nj: f64,
    activate_nj: f64,
    read_nj: f64,
    write_nj: f64,
    refresh_nj: f64,
}

impl From<&CacheStats> for CacheStatsDoc {
    fn from(c: &CacheStats) -> Self {
        CacheStatsDoc {
            accesses: c.accesses,
            hits: c.hits,
            misses: c.misses,
            merged: c.merged,
            bank_retries: c.bank_retries,
            bank_conflict_events: c.bank_conflict_events,
            mshr_full: c.mshr_full,
            stores: c.stores,
            load_bytes: c.load_bytes,
            fill_bytes: c.fill_bytes,
            store_bytes: c.store_bytes,
        }
    }
}

impl From<&CacheCost> for CacheCostDoc {
    fn from(c: &CacheCost) -> Self {
        CacheCostDoc {
            area_mm2: c.area_mm2,
            energy_nj: c.energy_nj,
            source: match c.source {
                Source::Config => "Config",
                Source::Table => "Table",
                Source::Scaled => "Scaled",
            },
        }
    }
}

impl From<&DramEnergy> for DramEnergyDoc {
    fn from(e: &DramEnergy) -> Self {
        DramEnergyDoc {
            background_nj: e.background_nj,
            activate_nj: e.activate_nj,
            read_nj: e.read_nj,
            write_nj: e.write_nj,
            refresh_nj: e.refresh_nj,
        }
    }
}

impl From<&DramStats> for DramStatsDoc {
    fn from(d: &DramStats) -> Self {
        DramStatsDoc {
            reads: d.reads,
            writes: d.writes,
            writes_merged: d.writes_merged,
            reads_forwarded: d.reads_forwarded,
            row_hits: d.row_hits,
            row_misses: d.row_misses,
            row_conflicts: d.row_conflicts,
            activates: d.activates,
            refreshes: d.refreshes,
            row_hit_rate: d.row_hit_rate,
            avg_read_latency_cycles: d.avg_read_latency_cycles,
            avg_read_queue: d.avg_read_queue,
            avg_write_queue: d.avg_write_queue,
            max_read_queue: d.max_read_queue,
            max_write_queue: d.max_write_queue,
            drain_episodes: d.drain_episodes,
            bytes: d.bytes,
            core_cycles: d.core_cycles,
            dram_cycles: d.dram_cycles,
            bytes_per_core_cycle: d.bytes_per_core_cycle,
            energy: (&d.energy).into(),
        }
    }
}

/// Serializes `timing.thread_cycles`: every bucket of [`ThreadCycles::BUCKETS`], in its order.
pub(super) fn thread_cycles<S: Serializer>(t: &ThreadCycles, s: S) -> Result<S::Ok, S::Error> {
    let mut m = s.serialize_map(Some(ThreadCycles::BUCKETS.len()))?;
    for b in ThreadCycles::BUCKETS {
        m.serialize_entry(b.name, &(b.get)(t))?;
    }
    m.end()
}

/// Serializes `timing.memory`.
pub(super) fn memory<S: Serializer>(m: &MemStats, s: S) -> Result<S::Ok, S::Error> {
    MemStatsDoc {
        l1: (&m.l1).into(),
        l2: m.l2.iter().map(Into::into).collect(),
        dram: (&m.dram).into(),
        l1_cost: (&m.l1_cost).into(),
        l2_cost: (&m.l2_cost).into(),
        l1_energy_nj: m.l1_energy_nj,
        l2_energy_nj: m.l2_energy_nj,
        l1_area_mm2: m.l1_area_mm2,
        l2_area_mm2: m.l2_area_mm2,
        dram_queue_full: m.dram_queue_full,
        l1_by_region: by_region(&m.region_names, &m.l1_by_region),
        l2_by_region: by_region(&m.region_names, &m.l2_by_region),
    }
    .serialize(s)
}
