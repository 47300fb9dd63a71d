//! BVH build throughput (triangles per second, one thread) on a 1M-triangle procedural
//! scene, plus the cost of treelet formation. Run with `cargo bench -p trax-assembler`.
//! Prints figures; the target is at least 2 M triangles/s for the plain build. Times are
//! this thread's CPU time (best of three), so other load on the machine does not skew them.

use std::time::{Duration, Instant};

use trax_assembler::bvh::{Bvh, BvhOptions, TreeletOptions};
use trax_assembler::scene::procedural;

/// CPU time this thread has run (Linux `/proc/thread-self/schedstat`), so figures stay
/// meaningful on a loaded machine; falls back to wall time elsewhere.
fn thread_cpu() -> Option<Duration> {
    let s = std::fs::read_to_string("/proc/thread-self/schedstat").ok()?;
    let ns: u64 = s.split_whitespace().next()?.parse().ok()?;
    Some(Duration::from_nanos(ns))
}

/// Best of `runs` timings of `f`: (wall, CPU) durations.
fn best<T>(runs: usize, mut f: impl FnMut() -> T) -> (Duration, T) {
    let mut best = Duration::MAX;
    let mut out = None;
    for _ in 0..runs {
        let (t, c) = (Instant::now(), thread_cpu());
        let r = f();
        let d = match (c, thread_cpu()) {
            (Some(a), Some(b)) => b - a,
            _ => t.elapsed(),
        };
        best = best.min(d);
        out = Some(r);
    }
    (best, out.expect("at least one run"))
}

fn main() {
    let n: u64 = std::env::var("TRAX_BENCH_TRIANGLES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(1_000_000);
    let t = Instant::now();
    let scene = procedural(n).expect("procedural scene");
    println!(
        "scene procedural:{n}: {} triangles generated in {:.3} s",
        scene.len(),
        t.elapsed().as_secs_f64()
    );
    let tris = &scene.triangles;
    let plain = BvhOptions::default();
    let (d, bvh) = best(3, || Bvh::build(tris, &plain).expect("build"));
    let s = bvh.stats();
    println!(
        "binned SAH build:        {:.3} s  {:6.2} M triangles/s  ({} nodes, depth {}, SAH {:.2})",
        d.as_secs_f64(),
        tris.len() as f64 / d.as_secs_f64() / 1e6,
        s.nodes,
        s.depth,
        s.sah_cost
    );
    let tl = BvhOptions {
        treelets: Some(TreeletOptions {
            budget_bytes: 32 * 1024,
            align_bytes: 2048,
        }),
        ..BvhOptions::default()
    };
    let (d, bvh) = best(3, || Bvh::build(tris, &tl).expect("build"));
    let t = bvh.treelets.as_ref().expect("treelets");
    println!(
        "build + 32 KiB treelets: {:.3} s  {:6.2} M triangles/s  ({} node treelets, {} triangle treelets)",
        d.as_secs_f64(),
        tris.len() as f64 / d.as_secs_f64() / 1e6,
        t.node_ranges.len(),
        t.tri_ranges.len()
    );
    let target = 2e6;
    let rate = tris.len() as f64 / best(1, || Bvh::build(tris, &plain)).0.as_secs_f64();
    println!(
        "target >= {:.1} M triangles/s: {}",
        target / 1e6,
        if rate >= target { "met" } else { "NOT met" }
    );
}
