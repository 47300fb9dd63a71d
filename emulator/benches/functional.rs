//! Functional-mode speed: simulated instructions per host second on one host thread, on
//! an FP-heavy ray/box slab-test loop, next to qemu-mipsel's figure on the same compiled
//! loop when qemu is installed. The loop is C (clang-14) so that qemu's Linux user mode
//! runs the very same code; the Rust path tracer's figure is `cargo bench --bench
//! functional_pathtracer` (root package).
//!
//! Both are timed by wall clock and by CPU time (this process's for the emulator, the
//! waited-for child's for qemu, from `/proc/self/stat` on Linux): on a shared machine
//! other load slows the wall clock of both, not their CPU time, so the CPU-time ratio is
//! the one to quote there. Each figure is the best of `TRAX_BENCH_REPEAT` runs (default
//! 3), the emulator's and qemu's alternating.
//!
//! Run: `cargo bench -p trax-emulator --bench functional`. Target (issue 26): >= 3x
//! qemu-mipsel.

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

/// Target: the emulator's speed over qemu-mipsel's on the same loop.
const TARGET_RATIO: f64 = 3.0;

/// CPU seconds (user + system) of this process (`children`: false) or of its waited-for
/// children (true) so far, from `/proc/self/stat` (Linux; `None` elsewhere). Fields 14-17
/// count them in USER_HZ ticks, which Linux fixes at 100 per second for user space.
fn cpu_seconds(children: bool) -> Option<f64> {
    let stat = std::fs::read_to_string("/proc/self/stat").ok()?;
    // The command name (field 2) is parenthesised and may hold spaces: split after it.
    let rest = &stat[stat.rfind(')')? + 1..];
    let fields: Vec<&str> = rest.split_whitespace().collect();
    // `rest` starts at field 3, so field n is fields[n - 3].
    let first = if children { 13 } else { 11 };
    let user: f64 = fields.get(first)?.parse().ok()?;
    let system: f64 = fields.get(first + 1)?.parse().ok()?;
    Some((user + system) / 100.0)
}

/// The best (wall, CPU) seconds seen and one more measurement.
fn best(b: &mut (f64, Option<f64>), wall: f64, cpu: Option<f64>) {
    b.0 = b.0.min(wall);
    b.1 = match (b.1, cpu) {
        (Some(x), Some(y)) => Some(x.min(y)),
        (x, y) => x.or(y),
    };
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
    let qemu_elf = build(&dir, LINUX_START, "__start", "linux", nrays);
    let qemu_ok = Command::new("qemu-mipsel")
        .arg("--version")
        .output()
        .is_ok();
    let qemu = qemu_elf.filter(|_| qemu_ok);
    let repeat = std::env::var("TRAX_BENCH_REPEAT")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(3u32)
        .max(1);
    let (mut ours, mut theirs) = ((f64::MAX, None), (f64::MAX, None));
    let mut instructions = 0;
    for _ in 0..repeat {
        let mut m = Machine::load(&exe, None, config).unwrap();
        let cpu = cpu_seconds(false);
        let t = Instant::now();
        let s = m.run(&mut std::io::sink());
        let secs = t.elapsed().as_secs_f64();
        let cpu = cpu.zip(cpu_seconds(false)).map(|(a, b)| b - a);
        assert!(matches!(s.outcome, Outcome::Finished), "{:?}", s.outcome);
        instructions = s.instructions;
        best(&mut ours, secs, cpu);
        if let Some(q) = &qemu {
            let cpu = cpu_seconds(true);
            let t = Instant::now();
            let ok = common::succeeds(
                Command::new("qemu-mipsel")
                    .args(["-cpu", "mips32r6-generic"])
                    .arg(q),
            );
            let secs = t.elapsed().as_secs_f64();
            let cpu = cpu.zip(cpu_seconds(true)).map(|(a, b)| b - a);
            if !ok {
                println!("  qemu-mipsel failed to run the loop");
                return;
            }
            best(&mut theirs, secs, cpu);
        }
    }
    let n = instructions as f64;
    let rate = |secs: f64| n / secs / 1e6;
    let show = |(wall, cpu): (f64, Option<f64>)| {
        format!(
            "{:8.1} M instr/s wall ({wall:.3} s){}",
            rate(wall),
            cpu.map_or(String::new(), |c| format!(
                ", {:8.1} M instr per CPU s ({c:.2} s)",
                rate(c)
            ))
        )
    };
    println!("functional ray-box loop: {instructions} instructions, best of {repeat}");
    println!("  trax emulator (1 host thread): {}", show(ours));
    if qemu.is_none() {
        println!("  qemu-mipsel not installed: no comparison");
    } else {
        // Same compiled loop; the instruction count is the emulator's (start-up differs
        // by a handful of instructions).
        println!("  qemu-mipsel (same program):    {}", show(theirs));
        let by_cpu = ours.1.zip(theirs.1).map(|(a, b)| b / a);
        println!(
            "  ratio trax/qemu: {:.2} by wall clock{} (target >= {TARGET_RATIO}: {})",
            theirs.0 / ours.0,
            by_cpu.map_or(String::new(), |r| format!(", {r:.2} by CPU time")),
            if by_cpu.unwrap_or(theirs.0 / ours.0) >= TARGET_RATIO {
                "met"
            } else {
                "MISSED"
            }
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}
