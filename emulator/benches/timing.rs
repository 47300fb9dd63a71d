//! Timing-model speed on a C microkernel: simulated thread-instructions per host second on
//! an FP-heavy ray/box slab-test kernel (C via clang-14), 4 TMs x 32 threads, detailed GDDR5
//! DRAM, with 1 and 2 host threads. The issue's workload (the path tracer) is measured by the
//! root package's `cargo bench --bench timing_pathtracer`.
//!
//! Run: `cargo bench -p trax-emulator --bench timing`. Target: >= 20 M thread-instr/s per core.

#[path = "common/mod.rs"]
mod common;

use std::path::{Path, PathBuf};
use std::time::Instant;

use trax_emulator::timing::ChipConfig;
use trax_emulator::{run, Limits, Mode, Outcome, RunReport, RunRequest};

const KERNEL: &str = r#"
typedef struct { float mn[3], mx[3]; } Box;
Box boxes[1024];
volatile float sink;
static unsigned hash(unsigned x) { x ^= x >> 16; x *= 0x7feb352dU; x ^= x >> 15; x *= 0x846ca68bU; x ^= x >> 16; return x; }
static float frand(unsigned *s) { *s = *s * 1664525u + 1013904223u; return (float)(*s >> 8) * (1.0f / 16777216.0f); }
static inline float mn(float a, float b) { return a < b ? a : b; }
static inline float mx(float a, float b) { return a > b ? a : b; }
static inline unsigned atominc(unsigned r) {
  register unsigned a asm("$4") = r; register unsigned v asm("$2");
  __asm__ volatile(".word 0x70801008" : "=r"(v) : "r"(a) : "memory"); return v;
}
static inline unsigned gid(void) {
  register unsigned v asm("$2"); __asm__ volatile(".word 0x70001002" : "=r"(v) :: "memory"); return v;
}
void trax_main(void) {
  if (gid() == 0) {
    unsigned s = 7;
    for (int i = 0; i < 1024; i++)
      for (int k = 0; k < 3; k++) {
        float c = frand(&s) * 20.0f - 10.0f, e = frand(&s) * 2.0f;
        boxes[i].mn[k] = c - e; boxes[i].mx[k] = c + e;
      }
  }
  float acc = 0.0f; int hits = 0;
  for (;;) {
    unsigned r = atominc(1);
    if (r >= NRAYS) break;
    unsigned s = hash(r + 1);
    float o[3], inv[3];
    for (int k = 0; k < 3; k++) { o[k] = frand(&s) * 4.0f - 2.0f; inv[k] = 1.0f / (frand(&s) * 2.0f - 1.0f); }
    unsigned start = hash(r) & 1023;
    for (int j = 0; j < 64; j++) {
      const Box *x = &boxes[(start + j * 17) & 1023];
      float t0 = (x->mn[0] - o[0]) * inv[0], t1 = (x->mx[0] - o[0]) * inv[0];
      float tmin = mn(t0, t1), tmax = mx(t0, t1);
      t0 = (x->mn[1] - o[1]) * inv[1]; t1 = (x->mx[1] - o[1]) * inv[1];
      tmin = mx(tmin, mn(t0, t1)); tmax = mn(tmax, mx(t0, t1));
      t0 = (x->mn[2] - o[2]) * inv[2]; t1 = (x->mx[2] - o[2]) * inv[2];
      tmin = mx(tmin, mn(t0, t1)); tmax = mn(tmax, mx(t0, t1));
      if (tmax >= mx(tmin, 0.0f)) { hits++; acc += tmin; }
    }
    __asm__ volatile(".word 0x70000022"); /* trax.stat 0: one ray */
  }
  sink = acc + (float)hits;
}
"#;

const START: &str = "
    .text
    .globl __trax_start
__trax_start:
    lui $sp, 0x8000
    lui $gp, %hi(_gp)
    addiu $gp, $gp, %lo(_gp)
    jal trax_main
    nop
    .word 0x70000007
";

fn build(dir: &Path) -> PathBuf {
    // Its own flags: `$gp`-relative small data (the stub sets `$gp`), freestanding.
    let flags = [
        "--target=mipsel-unknown-linux-gnu",
        "-march=mips32r6",
        "-mfp64",
        "-mabi=32",
        "-O2",
        "-fno-pic",
        "-mno-abicalls",
        "-nostdlib",
        "-ffreestanding",
        "-fno-builtin",
        "-DNRAYS=512",
        "-Wno-unused-command-line-argument",
    ];
    common::build(
        dir,
        "k",
        "__trax_start",
        &flags,
        &[("s.s", START, &[]), ("k.c", KERNEL, &[])],
    )
    .expect("clang-14 and ld.lld-14 build the kernel")
}

/// A timing run of the kernel on `chip` with `host_threads`, stopped at `cap` cycles.
fn simulate(
    elf: &Path,
    data: &[u8],
    chip: &ChipConfig,
    host_threads: usize,
    cap: u64,
) -> RunReport {
    let path = elf.display().to_string();
    let mut req = RunRequest::new(&path, data, chip, Mode::Timing);
    req.host_threads = Some(host_threads);
    req.limits = Limits {
        max_cycles: Some(cap),
        ..Limits::default()
    };
    run(req, &mut std::io::sink()).unwrap()
}

fn probe_detailed(c: &ChipConfig) -> bool {
    c.memory.dram.model == trax_emulator::memsys::DramModel::Detailed
}

fn main() {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("trax-timing-bench");
    let elf = build(&dir);
    let data = std::fs::read(&elf).unwrap();
    let mut chip = ChipConfig::preset("baseline").unwrap();
    chip.tms = 4;
    chip.tms_per_l2 = 4;
    chip.name = "baseline, 4 TMs".into();
    // The detailed DRAM is the target; if a run does not finish within the cycle cap (a
    // memory-system problem), fall back to the simple DRAM so the bench still measures.
    let cap = std::env::var("TRAX_BENCH_MAX_CYCLES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(5_000_000u64);
    let probe = simulate(&elf, &data, &chip, 1, cap);
    if !matches!(probe.outcome, Outcome::Finished) {
        println!(
            "timing: detailed DRAM run did not finish within {cap} cycles ({:?}); measuring with the simple DRAM",
            probe.failure
        );
        chip.memory.dram = trax_emulator::memsys::DramConfig::preset("simple").unwrap();
    }
    let mut first = None;
    for host_threads in [1usize, 2] {
        let t = Instant::now();
        let r = simulate(&elf, &data, &chip, host_threads, cap);
        let secs = t.elapsed().as_secs_f64();
        let s = r.timing.as_ref().expect("timing statistics");
        if !matches!(r.outcome, Outcome::Finished) {
            println!("{}", s.summary());
            panic!("{:?}", r.failure);
        }
        println!(
            "timing: {} DRAM, {} host thread(s): {} thread-instructions, {} cycles in {:.3} s = {:.2} M thread-instr/s (issue rate {:.1}%, {} DRAM reads)",
            if probe_detailed(&chip) { "detailed" } else { "simple" },
            host_threads,
            s.instructions,
            s.cycles,
            secs,
            s.instructions as f64 / secs / 1e6,
            s.issue_rate * 100.0,
            s.memory.dram.reads
        );
        match &first {
            None => first = Some(format!("{s:?}")),
            Some(f) => assert_eq!(*f, format!("{s:?}"), "host threads changed the stats"),
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}
