//! Functional-mode speed: simulated instructions per host second on one host thread, on
//! an FP-heavy ray/box slab-test loop, next to qemu-mipsel's figure on the same compiled
//! loop when qemu is installed (`common/functional.rs`, wall clock and CPU time). The loop
//! is C (clang-14) so that qemu's Linux user mode runs the very same code; the Rust path
//! tracer's figure is `cargo bench --bench functional_pathtracer` (root package).
//!
//! Run: `cargo bench -p trax-emulator --bench functional`. Target (issue 26): >= 3x
//! qemu-mipsel.

#[path = "common/mod.rs"]
mod common;

/// Target: the emulator's speed over qemu-mipsel's on the same loop.
const TARGET_RATIO: f64 = 3.0;

fn main() {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("trax-bench-functional");
    let Some(f) = common::functional::measure(&dir, 40_000) else {
        println!("functional bench: clang-14/ld.lld-14 not available; skipped");
        return;
    };
    let rate = |secs: f64| f.instructions as f64 / secs / 1e6;
    let show = |wall: f64, cpu: Option<f64>| {
        format!(
            "{:8.1} M instr/s wall ({wall:.3} s){}",
            rate(wall),
            cpu.map_or(String::new(), |c| format!(
                ", {:8.1} M instr per CPU s ({c:.2} s)",
                rate(c)
            ))
        )
    };
    println!(
        "functional ray-box loop: {} instructions, best of {}",
        f.instructions, f.repeat
    );
    println!(
        "  trax emulator (1 host thread): {}",
        show(f.secs, f.cpu_secs)
    );
    match (f.qemu_secs, f.ratio()) {
        (Some(q), Some(r)) => {
            println!(
                "  qemu-mipsel (same program):    {}",
                show(q, f.qemu_cpu_secs)
            );
            let by = if f.cpu_secs.is_some() && f.qemu_cpu_secs.is_some() {
                "CPU time"
            } else {
                "wall clock"
            };
            println!(
                "  ratio trax/qemu: {:.2} by wall clock, {r:.2} by {by} (target >= {TARGET_RATIO}: {})",
                q / f.secs,
                if r >= TARGET_RATIO { "met" } else { "MISSED" }
            );
        }
        _ => println!("  qemu-mipsel not installed (or failed): no comparison"),
    }
}
