//! Functional-mode speed: simulated instructions per host second on one host thread, on
//! an FP-heavy ray/box slab-test loop, next to qemu-mipsel's figure on the same compiled
//! loop when qemu is installed. The loop is C (clang-14) so that qemu's Linux user mode
//! runs the very same code; the Rust path tracer's figure is the one `trax run
//! examples/pathtracer.rs --functional` prints.
//!
//! Run: `cargo bench -p trax-emulator --bench functional`. Target: >= 300 M instr/s and
//! faster than qemu.

#[path = "common/mod.rs"]
mod common;

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

use trax_emulator::Outcome;
use trax_emulator::{Machine, MachineConfig};

const KERNEL: &str = r#"
typedef struct { float mn[3], mx[3]; } Box;
static Box boxes[256];
volatile float sink;
static unsigned seed = 12345;
static float frand(void) { seed = seed * 1664525u + 1013904223u; return (float)(seed >> 8) * (1.0f / 16777216.0f); }
static inline float mn(float a, float b) { return a < b ? a : b; }
static inline float mx(float a, float b) { return a > b ? a : b; }
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
      const Box *x = &boxes[b];
      float t0 = (x->mn[0] - o[0]) * inv[0], t1 = (x->mx[0] - o[0]) * inv[0];
      float tmin = mn(t0, t1), tmax = mx(t0, t1);
      t0 = (x->mn[1] - o[1]) * inv[1]; t1 = (x->mx[1] - o[1]) * inv[1];
      tmin = mx(tmin, mn(t0, t1)); tmax = mn(tmax, mx(t0, t1));
      t0 = (x->mn[2] - o[2]) * inv[2]; t1 = (x->mx[2] - o[2]) * inv[2];
      tmin = mx(tmin, mn(t0, t1)); tmax = mn(tmax, mx(t0, t1));
      if (tmax >= mx(tmin, 0.0f)) { hits++; acc += tmin; }
    }
  }
  sink = acc + (float)hits;
}
"#;

const LINUX_START: &str = "
    .text
    .globl __start
__start:
    jal trax_main
    nop
    li $2, 4001
    li $4, 0
    syscall
";

fn build(dir: &Path, start: &str, entry: &str, name: &str, nrays: u32) -> Option<PathBuf> {
    let nr = format!("-DNRAYS={nrays}");
    let start_file = format!("{name}.s");
    common::build(
        dir,
        name,
        entry,
        &common::FLAGS,
        &[(&start_file, start, &[]), ("k.c", KERNEL, &[&nr])],
    )
}

fn main() {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("trax-bench-functional");
    std::fs::create_dir_all(&dir).unwrap();
    let nrays = 40_000;
    let Some(elf) = build(&dir, common::TRAX_START, "__trax_start", "trax", nrays) else {
        println!("functional bench: clang-14/ld.lld-14 not available; skipped");
        return;
    };
    let data = std::fs::read(&elf).unwrap();
    let exe = trax_emulator::Executable::parse("bench", &data).unwrap();
    let config = MachineConfig {
        quantum: 1_000_000,
        ..MachineConfig::default()
    };
    let mut best = f64::MAX;
    let mut instructions = 0;
    for _ in 0..3 {
        let mut m = Machine::load(&exe, None, config).unwrap();
        let t = Instant::now();
        let s = m.run(&mut std::io::sink());
        let secs = t.elapsed().as_secs_f64();
        assert!(matches!(s.outcome, Outcome::Finished), "{:?}", s.outcome);
        instructions = s.instructions;
        best = best.min(secs);
    }
    let ours = instructions as f64 / best / 1e6;
    println!("functional ray-box loop: {instructions} instructions, best of 3: {best:.3} s");
    println!("  trax emulator (1 host thread): {ours:8.1} M instr/s");
    let qemu_elf = build(&dir, LINUX_START, "__start", "linux", nrays);
    let qemu_ok = Command::new("qemu-mipsel")
        .arg("--version")
        .output()
        .is_ok();
    match (qemu_elf, qemu_ok) {
        (Some(q), true) => {
            let mut qbest = f64::MAX;
            for _ in 0..3 {
                let t = Instant::now();
                let ok = common::succeeds(
                    Command::new("qemu-mipsel")
                        .args(["-cpu", "mips32r6-generic"])
                        .arg(&q),
                );
                if !ok {
                    println!("  qemu-mipsel failed to run the loop");
                    return;
                }
                qbest = qbest.min(t.elapsed().as_secs_f64());
            }
            // Same compiled loop; the instruction count is the emulator's (start-up differs
            // by a handful of instructions).
            let q = instructions as f64 / qbest / 1e6;
            println!("  qemu-mipsel (same program):    {q:8.1} M instr/s  ({qbest:.3} s)");
            println!("  ratio trax/qemu: {:.2}", ours / q);
        }
        _ => println!("  qemu-mipsel not installed: no comparison"),
    }
    let _ = std::fs::remove_dir_all(&dir);
}
