//! csmith differential over many seeds (`TRAX_CSMITH_SEEDS`, default 100, from
//! `TRAX_CSMITH_FIRST`, default 1000): each random C program is built by trax and run on the
//! emulator, and built for i386 and run on the host; prints the agreement count and the
//! seeds that disagree (with their directories), and exits 1 if any does.

#[path = "../tests/csmith/driver.rs"]
mod driver;

use driver::{differential, Verdict};
use std::path::Path;

fn main() {
    let var = |name: &str, default: u64| {
        std::env::var(name)
            .ok()
            .and_then(|v| v.parse().ok())
            .unwrap_or(default)
    };
    let n = var("TRAX_CSMITH_SEEDS", 100);
    let first = var("TRAX_CSMITH_FIRST", 1000);
    let base = Path::new(env!("CARGO_TARGET_TMPDIR")).join("csmith-bench");
    let (mut agree, mut no_oracle, mut bad) = (0, 0, Vec::new());
    let start = std::time::Instant::now();
    for seed in first..first + n {
        let opt = (seed % 4) as u8;
        let dir = base.join(format!("seed-{seed}"));
        let _ = std::fs::remove_dir_all(&dir);
        match differential(seed, opt, &dir) {
            Ok(Verdict::Agree(_)) => {
                agree += 1;
                let _ = std::fs::remove_dir_all(&dir);
            }
            Ok(Verdict::NoOracle(_)) => no_oracle += 1,
            Ok(Verdict::Disagree { host, trax }) => {
                println!(
                    "seed {seed} -O{opt} DISAGREES ({}):\n  host: {host}  trax: {}",
                    dir.display(),
                    trax.lines().take(8).collect::<Vec<_>>().join("\n        ")
                );
                bad.push(seed);
            }
            Err(e) => {
                println!("seed {seed}: {e}");
                bad.push(seed);
            }
        }
    }
    println!(
        "csmith: {n} seeds from {first} in {:.1} s: {agree} agree, {no_oracle} without an oracle (did not finish on the host), {} disagree {bad:?}",
        start.elapsed().as_secs_f64(),
        bad.len()
    );
    if !bad.is_empty() {
        std::process::exit(1);
    }
}
