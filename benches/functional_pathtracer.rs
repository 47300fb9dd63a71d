//! Functional-mode speed on the real workload: the path tracer (`examples/pathtracer.rs`)
//! on Sibenik, 256x256, 1 sample, depth 4, on the default chip's threads (`tiny`), as
//! `trax run examples/pathtracer.rs --scene .../sibenik.obj --width 256 --height 256
//! --functional` runs it. This is also what the sampled mode's fast-forward executes.
//!
//! Prints instructions per host second (wall clock, and per CPU second: on a shared
//! machine other load slows the wall clock, not the CPU time) of the fastest of
//! `TRAX_BENCH_REPEAT` runs (default 3). The loop alone, beside qemu-mipsel, is
//! `cargo bench -p trax-emulator --bench functional`.
//!
//! Run: `cargo bench --bench functional_pathtracer`. Environment: `TRAX_BENCH_SCENE` (scene
//! spec; default `../shared/scenes/sibenik/sibenik.obj`, relative to the checkout; the
//! bench says so and stops when it is missing), `TRAX_BENCH_SIZE` (image side, default 256),
//! `TRAX_BENCH_REPEAT`.

#[allow(dead_code)] // `simulate` is the timing benches'
mod common;

use std::path::Path;
use std::time::Instant;
use trax_emulator::timing::ChipConfig;
use trax_emulator::{run, Mode};

use common::{env_u64, prepare_example, process_cpu_seconds, selected};

fn main() {
    if !selected("functional_pathtracer") {
        return;
    }
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let scene = std::env::var("TRAX_BENCH_SCENE").unwrap_or_else(|_| {
        root.join("../shared/scenes/sibenik/sibenik.obj")
            .display()
            .to_string()
    });
    if !scene.contains(':') && !Path::new(&scene).exists() {
        println!("functional_pathtracer: scene {scene} not found; skipped (set TRAX_BENCH_SCENE)");
        return;
    }
    let size = env_u64("TRAX_BENCH_SIZE", 256).clamp(1, 4096) as u32;
    let repeat = env_u64("TRAX_BENCH_REPEAT", 3).max(1);
    let chip = ChipConfig::preset(trax_emulator::timing::DEFAULT_CHIP).expect("default chip");
    let prepared = prepare_example("pathtracer", Some(&scene), size, &chip);
    println!(
        "functional_pathtracer: path tracer, {scene} {size}x{size}, 1 spp, depth 4; {} TMs x {} threads, functional, 1 host thread",
        chip.tms, chip.threads_per_tm
    );
    let mut best: Option<(f64, Option<f64>)> = None;
    let mut count = None;
    for _ in 0..repeat {
        let req = prepared.run_request(&chip, Mode::Functional);
        let cpu0 = process_cpu_seconds();
        let t = Instant::now();
        let r = run(req, &mut std::io::sink()).expect("functional run starts");
        let secs = t.elapsed().as_secs_f64();
        let cpu = cpu0.zip(process_cpu_seconds()).map(|(a, b)| b - a);
        assert!(
            r.finished(),
            "the path tracer did not finish: {:?}",
            r.failure
        );
        // Same program, same count every time.
        assert!(count.is_none_or(|c| c == r.instructions));
        count = Some(r.instructions);
        if best.is_none_or(|(b, _)| secs < b) {
            best = Some((secs, cpu));
        }
    }
    let (secs, cpu) = best.expect("at least one run");
    let n = count.expect("at least one run") as f64;
    let cpu_text = cpu.map_or(String::new(), |c| {
        format!(
            ", {c:.2} CPU s: {:.1} M instr per CPU s",
            n / c.max(1e-9) / 1e6
        )
    });
    println!(
        "  {n:.0} instructions, fastest of {repeat}: {secs:.3} s = {:.1} M instr/s{cpu_text}",
        n / secs / 1e6
    );
}
