//! The functional benchmark (an FP-heavy ray/box slab-test loop in C, built with
//! clang-14): the emulator's functional mode against qemu-mipsel on the same compiled loop.
//! Run by `cargo bench -p trax-emulator --bench functional` and, beside the timing
//! figures, by the root package's `cargo bench --bench thesis_frame`.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

use trax_emulator::Outcome;
use trax_emulator::{Machine, MachineConfig};

/// What one measurement found. Each time is the best of `repeat` runs, the emulator's and
/// qemu's alternating; wall clock and CPU time (this process's for the emulator, the
/// waited-for child's for qemu, from `/proc/self/stat` on Linux): on a shared machine other
/// load slows the wall clock of both, not their CPU time, so the CPU-time ratio is the one
/// to quote there.
pub struct Figures {
    /// Instructions the loop executes (the emulator's count).
    pub instructions: u64,
    /// How many runs each time is the best of (`TRAX_BENCH_REPEAT`, default 3).
    pub repeat: u32,
    /// The emulator's wall seconds, on one host thread.
    pub secs: f64,
    /// The emulator's CPU seconds (`None`: not measurable on this host).
    pub cpu_secs: Option<f64>,
    /// qemu-mipsel's wall seconds on the same loop (`None`: not installed or failed).
    pub qemu_secs: Option<f64>,
    /// qemu-mipsel's CPU seconds.
    pub qemu_cpu_secs: Option<f64>,
}

impl Figures {
    /// The emulator's M instructions per second (wall clock).
    pub fn mips(&self) -> f64 {
        self.instructions as f64 / self.secs / 1e6
    }

    /// qemu-mipsel's M instructions per second (the emulator's count over qemu's time;
    /// start-up differs by a handful of instructions).
    pub fn qemu_mips(&self) -> Option<f64> {
        self.qemu_secs.map(|s| self.instructions as f64 / s / 1e6)
    }

    /// The emulator's speed over qemu's: by CPU time where both were measured, else by
    /// wall clock.
    pub fn ratio(&self) -> Option<f64> {
        match (self.cpu_secs, self.qemu_cpu_secs) {
            (Some(a), Some(b)) => Some(b / a),
            _ => self.qemu_secs.map(|q| q / self.secs),
        }
    }
}

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

/// The smaller of two optional times.
fn min_opt(a: Option<f64>, b: Option<f64>) -> Option<f64> {
    match (a, b) {
        (Some(x), Some(y)) => Some(x.min(y)),
        (x, y) => x.or(y),
    }
}

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
    super::build(
        dir,
        name,
        entry,
        &super::FLAGS,
        &[(&start_file, start, &[]), ("k.c", KERNEL, &[&nr])],
    )
}

/// Builds and times the loop (`nrays` rays) in `dir`; `None` if clang-14/ld.lld-14 are
/// missing.
pub fn measure(dir: &Path, nrays: u32) -> Option<Figures> {
    std::fs::create_dir_all(dir).unwrap();
    let elf = build(dir, super::TRAX_START, "__trax_start", "trax", nrays)?;
    let data = std::fs::read(&elf).unwrap();
    let exe = trax_emulator::Executable::parse("bench", &data).unwrap();
    let config = MachineConfig {
        quantum: 1_000_000,
        ..MachineConfig::default()
    };
    let qemu_ok = Command::new("qemu-mipsel")
        .arg("--version")
        .output()
        .is_ok();
    let mut qemu = build(dir, LINUX_START, "__start", "linux", nrays).filter(|_| qemu_ok);
    let repeat = std::env::var("TRAX_BENCH_REPEAT")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(3u32)
        .max(1);
    let mut f = Figures {
        instructions: 0,
        repeat,
        secs: f64::MAX,
        cpu_secs: None,
        qemu_secs: None,
        qemu_cpu_secs: None,
    };
    for _ in 0..repeat {
        let mut m = Machine::load(&exe, None, config).unwrap();
        let cpu = cpu_seconds(false);
        let t = Instant::now();
        let s = m.run(&mut std::io::sink());
        let secs = t.elapsed().as_secs_f64();
        let cpu = cpu.zip(cpu_seconds(false)).map(|(a, b)| b - a);
        assert!(matches!(s.outcome, Outcome::Finished), "{:?}", s.outcome);
        f.instructions = s.instructions;
        f.secs = f.secs.min(secs);
        f.cpu_secs = min_opt(f.cpu_secs, cpu);
        if let Some(q) = &qemu {
            let cpu = cpu_seconds(true);
            let t = Instant::now();
            let ok = super::succeeds(
                Command::new("qemu-mipsel")
                    .args(["-cpu", "mips32r6-generic"])
                    .arg(q),
            );
            let secs = t.elapsed().as_secs_f64();
            let cpu = cpu.zip(cpu_seconds(true)).map(|(a, b)| b - a);
            if ok {
                f.qemu_secs = min_opt(f.qemu_secs, Some(secs));
                f.qemu_cpu_secs = min_opt(f.qemu_cpu_secs, cpu);
            } else {
                println!("  qemu-mipsel failed to run the loop: no comparison");
                (qemu, f.qemu_secs, f.qemu_cpu_secs) = (None, None, None);
            }
        }
    }
    let _ = std::fs::remove_dir_all(dir);
    Some(f)
}
