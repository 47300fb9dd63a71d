//! The functional benchmark (an FP-heavy ray/box slab-test loop in C, built with
//! clang-14): the emulator's functional mode against qemu-mipsel on the same compiled loop.
//! Run by `cargo bench -p trax-emulator --bench functional` and, beside the timing
//! figures, by the root package's `cargo bench --bench thesis_frame`.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

use trax_emulator::Outcome;
use trax_emulator::{Machine, MachineConfig};

/// What one measurement found.
pub struct Figures {
    /// Instructions the loop executes (the emulator's count).
    pub instructions: u64,
    /// The emulator's best of three, seconds, on one host thread.
    pub secs: f64,
    /// qemu-mipsel's best of three on the same loop, seconds (`None`: not installed or
    /// failed).
    pub qemu_secs: Option<f64>,
}

impl Figures {
    /// The emulator's M instructions per second.
    pub fn mips(&self) -> f64 {
        self.instructions as f64 / self.secs / 1e6
    }

    /// qemu-mipsel's M instructions per second (the emulator's count over qemu's time;
    /// start-up differs by a handful of instructions).
    pub fn qemu_mips(&self) -> Option<f64> {
        self.qemu_secs.map(|s| self.instructions as f64 / s / 1e6)
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
    let qemu_ok = Command::new("qemu-mipsel")
        .arg("--version")
        .output()
        .is_ok();
    let qemu_elf = build(dir, LINUX_START, "__start", "linux", nrays).filter(|_| qemu_ok);
    let qemu_secs = qemu_elf.and_then(|q| {
        let mut qbest = f64::MAX;
        for _ in 0..3 {
            let t = Instant::now();
            let ok = super::succeeds(
                Command::new("qemu-mipsel")
                    .args(["-cpu", "mips32r6-generic"])
                    .arg(&q),
            );
            if !ok {
                return None;
            }
            qbest = qbest.min(t.elapsed().as_secs_f64());
        }
        Some(qbest)
    });
    let _ = std::fs::remove_dir_all(dir);
    Some(Figures {
        instructions,
        secs: best,
        qemu_secs,
    })
}
