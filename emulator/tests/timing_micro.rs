//! Analytic microbenchmarks for the timing model: kernels whose cycle counts are known.

mod common;

use std::path::Path;

use common::chip;
use trax_emulator::timing::{ChipConfig, TimingStats};
use trax_emulator::{run, Limits, Mode, Outcome, RunReport, RunRequest};

/// A finished timing run: its statistics and the report.
struct Sim {
    stats: TimingStats,
    run: RunReport,
}

fn sim(elf: &Path, chip: &ChipConfig, host_threads: usize) -> (Sim, String) {
    let data = std::fs::read(elf).unwrap();
    let path = elf.display().to_string();
    let mut out = Vec::new();
    let mut req = RunRequest::new(&path, &data, chip, Mode::Timing);
    req.host_threads = Some(host_threads);
    req.limits = Limits {
        max_cycles: Some(50_000_000),
        ..Limits::default()
    };
    let mut r = run(req, &mut out).unwrap();
    assert!(
        matches!(r.outcome, Outcome::Finished),
        "{:?}: {:?}",
        r.outcome,
        r.failure
    );
    let stats = r.timing.take().unwrap();
    (Sim { stats, run: r }, String::from_utf8(out).unwrap())
}

fn numbers(out: &str) -> Vec<u64> {
    out.split_whitespace().map(|w| w.parse().unwrap()).collect()
}

const FP_CHAIN: &str = r#"
#include "trax.h"
void trax_main(void) {
    float a = 1.0f, b = 0.5f;
    // Wait for both operands (loaded from memory) before starting the clock.
    __asm__ volatile("mov.s %0, %0\n mov.s %1, %1" : "+f"(a), "+f"(b));
    unsigned t0 = trax_clock();
    __asm__ volatile(".rept 100\n add.s %0, %0, %1\n .endr\n mov.s %0, %0" : "+f"(a) : "f"(b));
    unsigned t1 = trax_clock();
    trax_printu(t1 - t0);
    trax_printc(' ');
    trax_printf(a);
}
"#;

#[test]
fn dependent_fp_add_chain_costs_latency_per_add() {
    let elf = common::build_c("t_fpchain", FP_CHAIN, "-O1");
    let mut dts = Vec::new();
    for lat in [2u32, 5] {
        let mut c = chip(1, 1);
        c.units.get_mut("fp_add").unwrap().latency = lat;
        let (r, out) = sim(&elf, &c, 1);
        let mut it = out.split_whitespace();
        let dt: u64 = it.next().unwrap().parse().unwrap();
        // 100 dependent adds and a consumer: the consumer issues 100 x latency after the
        // first add; the clock read after it runs the next cycle (plus at most a couple of
        // compiler-scheduled instructions between the clock reads).
        let base = 100 * lat as u64 + 1;
        assert!((base..=base + 2).contains(&dt), "latency {lat}: {out}");
        dts.push(dt);
        assert_eq!(it.next().unwrap(), "51", "functional result");
        assert!(
            r.stats
                .data_stalls_by_producer
                .get("add.s")
                .copied()
                .unwrap_or(0)
                >= 99 * (lat as u64 - 1)
        );
    }
    assert_eq!(dts[1] - dts[0], 300, "exactly 3 more cycles per add");
}

const LOAD_CHAIN: &str = r#"
#include "trax.h"
static unsigned arr[64 * 16] __attribute__((aligned(64)));
void trax_main(void) {
    for (int i = 0; i < 63; i++) arr[i * 16] = (unsigned)&arr[(i + 1) * 16];
    arr[63 * 16] = (unsigned)&arr[0];
    unsigned p = (unsigned)&arr[0];
    for (int pass = 0; pass < 2; pass++) {
        unsigned t0 = trax_clock();
        __asm__ volatile(".rept 64\n lw %0, 0(%0)\n .endr\n addu %0, %0, $0" : "+r"(p));
        unsigned t1 = trax_clock();
        trax_printu(t1 - t0);
        trax_printc(' ');
    }
}
"#;

#[test]
fn l1_hit_and_miss_latencies() {
    let elf = common::build_c("t_loadchain", LOAD_CHAIN, "-O1");
    let mut c = chip(1, 1);
    c.memory.l1.hit_latency = 3;
    c.memory.l2.hit_latency = 7;
    c.memory.dram.simple.latency = 40;
    let (r, out) = sim(&elf, &c, 1);
    let v = numbers(&out);
    // Second pass: 64 dependent L1 hits of 3 cycles (+ the clock read, + at most two
    // compiler-scheduled instructions).
    assert!((64 * 3 + 1..=64 * 3 + 3).contains(&v[1]), "{out}");
    let mut c5 = c.clone();
    c5.memory.l1.hit_latency = 5;
    let (_, out5) = sim(&elf, &c5, 1);
    assert_eq!(numbers(&out5)[1] - v[1], 64 * 2, "{out} / {out5}");
    // First pass: every load misses L1 and L2 (stores are write-around): L1 + L2 + DRAM.
    let per = (v[0] - 1) as f64 / 64.0;
    assert!((50.0..=52.0).contains(&per), "miss latency {per} ({out})");
    let m = &r.stats.memory;
    assert!(m.l1.hits >= 64 && m.l1.misses >= 64, "{:?}", m.l1);
}

const FP_THREADS: &str = r#"
#include "trax.h"
void trax_main(void) {
    float a = 1.0f, b = 0.5f;
    __asm__ volatile(".rept 200\n add.s %0, %0, %1\n .endr" : "+f"(a) : "f"(b));
    if (a != 101.0f) trax_printc('X');
}
"#;

#[test]
fn shared_unit_conflicts_when_more_threads_than_units() {
    let elf = common::build_c("t_fpthreads", FP_THREADS, "-O1");
    let mut cycles = Vec::new();
    for units in [1u32, 2, 8] {
        let mut c = chip(1, 8);
        c.units.get_mut("fp_add").unwrap().count = units;
        let (r, out) = sim(&elf, &c, 1);
        assert_eq!(out, "", "functional results");
        let conflicts = r.stats.unit_conflicts.get("fp_add").copied().unwrap_or(0);
        if units < 4 {
            // 8 threads x 200 adds through `units` units at one op per cycle each.
            assert!(
                r.stats.cycles >= 1600 / units as u64,
                "{units}: {}",
                r.stats.cycles
            );
            assert!(conflicts > 0);
        } else {
            assert_eq!(conflicts, 0);
            // One unit per thread: latency bound, 2 cycles per add.
            assert!(
                r.stats.cycles >= 400 && r.stats.cycles < 500,
                "{}",
                r.stats.cycles
            );
        }
        cycles.push(r.stats.cycles);
    }
    assert!(cycles[0] > cycles[1] && cycles[1] > cycles[2], "{cycles:?}");
}

const WORK: &str = r#"
#include "trax.h"
float data[1 << 14];
void trax_main(void) {
    for (;;) {
        unsigned i = trax_atominc(0);
        if (i >= 512) break;
        float s = 0.0f;
        for (int k = 0; k < 8; k++) s += data[(i * 32 + k * 4) & ((1 << 14) - 1)] * 0.5f + (float)k;
        trax_stat(0);
        if (s < 0.0f) trax_printc('X');
    }
}
"#;

/// Chip-wide traffic of every kind: atomics, stores to global memory read back by other
/// TMs after a barrier, prints, semaphores and counters.
const SHARED_TRAFFIC: &str = r#"
#include "trax.h"
unsigned out[2048];
void trax_main(void) {
    for (;;) {
        unsigned i = trax_atominc(0);
        if (i >= 2048) break;
        unsigned h = i * 2654435761u;
        unsigned n = h >> 29;
        for (unsigned k = 0; k < n; k++) h = h * 1664525u + 1013904223u;
        out[i] = h;
        trax_stat(0);
        if ((h & 63) == 0) { trax_printu(i); trax_printc(' '); }
    }
    if (trax_gid() == 0) trax_semrel(2);
    trax_barrier(1);
    unsigned g = trax_gid();
    unsigned sum = 0;
    for (unsigned k = g; k < 2048; k += 64) sum += out[k];
    trax_semacq(2);
    trax_atomadd(3, sum);
    trax_semrel(2);
    trax_barrier(1);
    if (g == 0) { trax_printc('='); trax_printu(trax_gread(3)); }
}
"#;

#[test]
fn host_threads_do_not_change_chip_wide_traffic() {
    let elf = common::build_c("t_shared_ht", SHARED_TRAFFIC, "-O1");
    let mut c = chip(4, 16);
    c.tms_per_l2 = 2;
    let (a, out_a) = sim(&elf, &c, 1);
    // The kernel's own check: the sum of every slot, gathered through stores to global
    // memory, a barrier, a semaphore and an atomic add.
    let expect = (0..2048u32).fold(0u32, |acc, i| {
        let mut h = i.wrapping_mul(2_654_435_761);
        for _ in 0..(h >> 29) {
            h = h.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
        }
        acc.wrapping_add(h)
    });
    assert!(out_a.ends_with(&format!("={expect}")), "{out_a}");
    assert_eq!(a.stats.rays, 2048);
    assert!(a.stats.thread_cycles.global_sync > 0);
    for n in [2, 3, 4] {
        let (b, out_b) = sim(&elf, &c, n);
        assert_eq!(out_a, out_b, "{n} host threads");
        assert_eq!(
            format!("{:?}", a.stats),
            format!("{:?}", b.stats),
            "{n} host threads"
        );
    }
}

#[test]
fn host_threads_do_not_change_results() {
    let elf = common::build_c("t_work_ht", WORK, "-O1");
    // 5 TMs over 1..=5 host threads: uneven and one-TM-per-thread splits.
    let mut c = chip(5, 8);
    c.tms_per_l2 = 2;
    let (a, out_a) = sim(&elf, &c, 1);
    assert_eq!(a.stats.rays, 512);
    for n in 2..=5 {
        let (b, out_b) = sim(&elf, &c, n);
        assert_eq!(
            format!("{:?}", a.stats),
            format!("{:?}", b.stats),
            "{n} host threads"
        );
        assert_eq!(out_a, out_b, "{n} host threads");
        let regs = |r: &Sim| {
            r.run
                .machine
                .threads
                .iter()
                .map(|t| t.regs.gpr)
                .collect::<Vec<_>>()
        };
        assert_eq!(regs(&a), regs(&b), "{n} host threads");
    }
}

#[test]
fn more_tms_fewer_cycles_until_dram_saturates() {
    let elf = common::build_c("t_work_tms", WORK, "-O1");
    let run = |tms: u32, bw: u32| {
        let mut c = chip(tms, 8);
        c.memory.dram.simple.bandwidth_bytes_per_cycle = bw;
        let (r, _) = sim(&elf, &c, 1);
        assert_eq!(r.stats.rays, 512);
        r.stats.cycles
    };
    // Ample bandwidth: 4x the TMs gives a large speed-up.
    let (c1, c4) = (run(1, 512), run(4, 512));
    assert!((c1 as f64) / (c4 as f64) > 2.0, "{c1} vs {c4}");
    // Starved DRAM (1 byte per cycle): the speed-up collapses.
    let (s1, s4) = (run(1, 1), run(4, 1));
    assert!((s1 as f64) / (s4 as f64) < 1.6, "{s1} vs {s4}");
    assert!(s4 > c4);
}

#[test]
fn icache_and_l1_bank_conflicts() {
    let elf = common::build_c("t_fpthreads_ic", FP_THREADS, "-O1");
    let mut c = chip(1, 8);
    c.units.get_mut("fp_add").unwrap().count = 8;
    c.icache.per_tm = 1;
    c.icache.banks = 1;
    c.icache.fetches_per_bank = 1;
    let (r, _) = sim(&elf, &c, 1);
    // One fetch per cycle for the whole TM: at most one instruction issues per cycle.
    assert!(r.stats.thread_cycles.icache_conflict > 0);
    assert!(
        r.stats.cycles >= r.stats.instructions,
        "{} < {}",
        r.stats.cycles,
        r.stats.instructions
    );

    let elf = common::build_c("t_loadchain_bank", LOAD_CHAIN, "-O1");
    let mut c = chip(1, 8);
    c.memory.l1.banks = 1;
    let (r, _) = sim(&elf, &c, 1);
    assert!(r.stats.thread_cycles.l1_bank_conflict > 0);
    assert!(r.stats.memory.l1.bank_retries > 0);
    // A refused L1 access costs its thread one cycle: the retries are the thread-cycles.
    assert_eq!(
        r.stats.memory.l1.bank_retries,
        r.stats.thread_cycles.l1_bank_conflict
    );
    let events = r.stats.memory.l1.bank_conflict_events;
    assert!(events > 0 && events <= r.stats.memory.l1.bank_retries);
    // Every thread walks the same words: sharing same-word reads removes most conflicts.
    let mut c4 = c.clone();
    c4.memory.l1.read_copy = true;
    let (r4, _) = sim(&elf, &c4, 1);
    assert!(r4.stats.thread_cycles.l1_bank_conflict < r.stats.thread_cycles.l1_bank_conflict);
}

#[test]
fn stats_summary_and_json_fields() {
    let elf = common::build_c("t_work_sum", WORK, "-O1");
    let (r, _) = sim(&elf, &chip(1, 8), 1);
    let s = r.stats.summary();
    for k in [
        "cycles:",
        "issue rate",
        "MRPS",
        "data dependence",
        "instruction mix",
        "L1:",
        "DRAM:",
        "area",
        "energy",
    ] {
        assert!(s.contains(k), "{k} missing from\n{s}");
    }
    assert_eq!(r.stats.rays, 512);
    assert!(r.stats.mrps > 0.0 && r.stats.area.total > 0.0 && r.stats.energy.total > 0.0);
    let tc = &r.stats.thread_cycles;
    let sum = tc.issued
        + tc.data_dependence
        + tc.unit_conflict
        + tc.icache_conflict
        + tc.l1_bank_conflict
        + tc.l1_mshr_full
        + tc.sync_wait
        + tc.global_sync
        + tc.halted;
    assert_eq!(
        sum,
        r.stats.cycles * 8,
        "every thread-cycle is accounted once"
    );
}
