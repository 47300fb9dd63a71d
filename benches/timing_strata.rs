//! Timing-model speed on the streaming workload (issue 14): the treelet-streaming path
//! tracer (`examples/strata.rs`) beside the plain path tracer (`examples/pathtracer.rs`),
//! both on the same chip (the `strata` preset cut to 4 TMs x 32 threads: 16 KB L1, ray
//! stream memory, box/triangle pipelines) and the same frame (embedded Cornell box,
//! 128x128, 1 sample, depth 4), one host thread, runs alternating so a drift in the
//! host's speed weighs on both alike.
//!
//! Prints, per kernel, simulated thread-instructions per host second (and per CPU second),
//! rays per host second and simulated cycles per host second, then the streaming kernel's
//! rate over the plain one's. Target (issue 14): >= 0.8x in thread-instructions per host
//! second. The fastest of the repetitions counts for each kernel.
//!
//! Run: `cargo bench --bench timing_strata`. Environment: `TRAX_BENCH_SIZE` (image side,
//! default 128), `TRAX_BENCH_MAX_CYCLES` (cycle cap, default 50,000,000), `TRAX_BENCH_REPEAT`
//! (runs per kernel, default 3).

mod common;

use trax::pipeline::Prepared;
use trax_emulator::timing::{ChipConfig, TimingStats};

use common::{env_u64, prepare_example, selected, simulate};

/// Target: the streaming kernel's thread-instructions per host second over the plain
/// path tracer's (issue 14).
const TARGET_RATIO: f64 = 0.8;

fn main() {
    if !selected("timing_strata") {
        return;
    }
    let size = env_u64("TRAX_BENCH_SIZE", 128).clamp(1, 4096) as u32;
    let max_cycles = env_u64("TRAX_BENCH_MAX_CYCLES", 50_000_000);
    let repeat = env_u64("TRAX_BENCH_REPEAT", 3).max(1);
    let mut chip = ChipConfig::preset("strata").expect("strata preset");
    chip.tms = 4;
    chip.tms_per_l2 = 4;
    chip.name = "strata, 4 TMs".into();
    println!(
        "timing_strata: Cornell box {size}x{size}, 1 spp, depth 4; {} TMs x {} threads, {} KB L1, {} KB stream memory, pipelines {}; 1 host thread",
        chip.tms,
        chip.threads_per_tm,
        chip.memory.l1.capacity_bytes / 1024,
        chip.stream_memory.capacity_bytes / 1024,
        if chip.pipelines.enabled { "on" } else { "off" },
    );
    let kernels = ["pathtracer", "strata"];
    let prepared: Vec<Prepared> = kernels
        .iter()
        .map(|k| prepare_example(k, None, size, &chip))
        .collect();

    let mut best: Vec<Option<(TimingStats, f64, Option<f64>)>> = vec![None; kernels.len()];
    for _ in 0..repeat {
        for ((b, p), name) in best.iter_mut().zip(&prepared).zip(kernels) {
            let run = simulate(name, p, &chip, 1, max_cycles, None);
            if b.as_ref().is_none_or(|b| run.1 < b.1) {
                *b = Some(run);
            }
        }
    }
    let mut rates = Vec::new();
    for (b, name) in best.into_iter().zip(kernels) {
        let (s, secs, cpu) = b.expect("at least one run");
        let rate = s.instructions as f64 / secs;
        let cpu_text = cpu.map_or(String::new(), |c| {
            format!(
                " ({c:.2} CPU s: {:.2} M thread-instr per CPU s)",
                s.instructions as f64 / c.max(1e-9) / 1e6
            )
        });
        println!(
            "  {name:>10}: {} thread-instructions, {} rays, {} cycles in {secs:.3} s{cpu_text} = {:.2} M thread-instr/s, {:.1} k rays/s, {:.0} k cycles/s, issue rate {:.1}%",
            s.instructions,
            s.rays,
            s.cycles,
            rate / 1e6,
            s.rays as f64 / secs / 1e3,
            s.cycles as f64 / secs / 1e3,
            s.issue_rate * 100.0,
        );
        rates.push((
            rate,
            s.rays as f64 / secs,
            cpu.map(|c| s.instructions as f64 / c),
        ));
    }
    let ratio = rates[1].0 / rates[0].0;
    // Per CPU second as well: on a shared host, other load slows the wall clock of
    // either run by chance, not the CPU time it used.
    let cpu_ratio = rates[1].2.zip(rates[0].2).map_or(String::new(), |(s, p)| {
        format!(", {:.2}x per CPU second", s / p)
    });
    println!(
        "  strata / pathtracer: {ratio:.2}x thread-instr/s (target >= {TARGET_RATIO}x): {}{cpu_ratio}; {:.2}x rays/s",
        if ratio >= TARGET_RATIO {
            "met"
        } else {
            "MISSED"
        },
        rates[1].1 / rates[0].1,
    );
}
