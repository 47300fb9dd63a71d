//! Profiling overhead: the same kernel run plainly ([`Machine::run`]) and under the exact
//! profiler ([`profile_run`]), best of 3 each, plus the one-off cost of resolving the
//! profile to source frames. Target: profiled / plain < 2.
//!
//! Run: `cargo bench -p trax-emulator --bench profile`.

#[path = "common/mod.rs"]
mod common;

use std::path::{Path, PathBuf};
use std::time::Instant;

use trax_emulator::profile::{profile_run, Profile};
use trax_emulator::DebugInfo;
use trax_emulator::Outcome;
use trax_emulator::{Machine, MachineConfig};

/// A ray/box slab test with real calls (a call per box), branches and FP work.
const KERNEL: &str = r#"
typedef struct { float mn[3], mx[3]; } Box;
static Box boxes[256];
volatile float sink;
static unsigned seed = 12345;
static float frand(void) { seed = seed * 1664525u + 1013904223u; return (float)(seed >> 8) * (1.0f / 16777216.0f); }
static inline float mn(float a, float b) { return a < b ? a : b; }
static inline float mx(float a, float b) { return a > b ? a : b; }
__attribute__((noinline)) float slab(const Box *x, const float *o, const float *inv) {
  float t0 = (x->mn[0] - o[0]) * inv[0], t1 = (x->mx[0] - o[0]) * inv[0];
  float tmin = mn(t0, t1), tmax = mx(t0, t1);
  t0 = (x->mn[1] - o[1]) * inv[1]; t1 = (x->mx[1] - o[1]) * inv[1];
  tmin = mx(tmin, mn(t0, t1)); tmax = mn(tmax, mx(t0, t1));
  t0 = (x->mn[2] - o[2]) * inv[2]; t1 = (x->mx[2] - o[2]) * inv[2];
  tmin = mx(tmin, mn(t0, t1)); tmax = mn(tmax, mx(t0, t1));
  return tmax >= mx(tmin, 0.0f) ? tmin : -1.0f;
}
void trax_main(void) {
  for (int i = 0; i < 256; i++) {
    for (int k = 0; k < 3; k++) {
      float c = frand() * 20.0f - 10.0f, e = frand() * 2.0f;
      boxes[i].mn[k] = c - e; boxes[i].mx[k] = c + e;
    }
  }
  float acc = 0.0f; int hits = 0;
  for (int r = 0; r < NRAYS; r++) {
    float o[3], inv[3];
    for (int k = 0; k < 3; k++) { o[k] = frand() * 4.0f - 2.0f; inv[k] = 1.0f / (frand() * 2.0f - 1.0f); }
    for (int b = 0; b < 256; b++) {
      float t = slab(&boxes[b], o, inv);
      if (t >= 0.0f) { hits++; acc += t; }
    }
  }
  sink = acc + (float)hits;
}
"#;

fn build(dir: &Path, nrays: u32) -> Option<PathBuf> {
    let nr = format!("-DNRAYS={nrays}");
    common::build(
        dir,
        "k",
        "__trax_start",
        &[&common::FLAGS[..], &["-g"]].concat(),
        &[
            ("start.s", common::TRAX_START, &[]),
            ("k.c", KERNEL, &[&nr]),
        ],
    )
}

fn main() {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("trax-bench-profile");
    std::fs::create_dir_all(&dir).unwrap();
    let Some(elf) = build(&dir, 10_000) else {
        println!("profile bench: clang-14/ld.lld-14 not available; skipped");
        return;
    };
    let data = std::fs::read(&elf).unwrap();
    let exe = trax_emulator::Executable::parse("bench", &data).unwrap();
    let config = MachineConfig {
        threads_per_tm: 4,
        ..MachineConfig::default()
    };
    let new = || Machine::load(&exe, None, config).unwrap();
    let (mut plain, mut profiled) = (f64::MAX, f64::MAX);
    let mut instructions = 0;
    let mut last = None;
    for _ in 0..3 {
        let mut m = new();
        let t = Instant::now();
        let s = m.run(&mut std::io::sink());
        plain = plain.min(t.elapsed().as_secs_f64());
        assert!(matches!(s.outcome, Outcome::Finished), "{:?}", s.outcome);
        instructions = s.instructions;

        let mut m = new();
        let t = Instant::now();
        let (summary, prof) = profile_run(&mut m, &mut std::io::sink(), None);
        let (o, n) = (summary.outcome, summary.instructions);
        profiled = profiled.min(t.elapsed().as_secs_f64());
        assert!(matches!(o, Outcome::Finished), "{o:?}");
        assert_eq!(n, instructions);
        last = Some(prof);
    }
    let dbg = DebugInfo::parse("bench", &data).unwrap();
    let t = Instant::now();
    let p = Profile::build(&last.unwrap(), Some(&dbg), Some(&exe));
    let resolve = t.elapsed().as_secs_f64();
    println!("profile overhead: {instructions} instructions, 4 threads, best of 3");
    println!(
        "  plain run:    {plain:.3} s  ({:.1} M instr/s)",
        instructions as f64 / plain / 1e6
    );
    println!(
        "  profiled run: {profiled:.3} s  ({:.1} M instr/s)",
        instructions as f64 / profiled / 1e6
    );
    println!("  slowdown:     {:.2}x (target < 2x)", profiled / plain);
    println!("  resolving to source frames: {resolve:.3} s");
    print!("{}", p.render_tree(1.0));
    let _ = std::fs::remove_dir_all(&dir);
}
