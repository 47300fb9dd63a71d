//! csmith differential over many seeds (`TRAX_CSMITH_SEEDS`, default 100, from
//! `TRAX_CSMITH_FIRST`, default 1000): each random C program is built by trax and run on the
//! emulator, and built for i386 at the same -O level and run on the host; prints the
//! counts (agree, no oracle, over budget, disagree) and the seeds that disagree (with
//! their directories), and exits 1 if any does.

#[path = "../tests/csmith/driver.rs"]
mod driver;

use driver::{differential, Verdict, MAX_INSTRUCTIONS_PER_HOST_SECOND};
use std::path::Path;
use std::time::Duration;

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
    let (mut agree, mut no_oracle, mut over_budget, mut bad) = (0, 0, Vec::new(), Vec::new());
    let mut densest: Option<(u64, f64, u64, Duration)> = None;
    let start = std::time::Instant::now();
    for seed in first..first + n {
        let opt = (seed % 4) as u8;
        let dir = base.join(format!("seed-{seed}"));
        let _ = std::fs::remove_dir_all(&dir);
        match differential(seed, opt, &dir) {
            Ok(Verdict::Agree {
                instructions,
                host_time,
                ..
            }) => {
                agree += 1;
                // Instructions per host CPU second, where the host's time is long enough
                // for its 10 ms resolution.
                if host_time >= Duration::from_millis(50) {
                    let rate = instructions as f64 / host_time.as_secs_f64();
                    if densest.is_none_or(|(_, r, _, _)| rate > r) {
                        densest = Some((seed, rate, instructions, host_time));
                    }
                }
                let _ = std::fs::remove_dir_all(&dir);
            }
            Ok(Verdict::NoOracle(_)) => no_oracle += 1,
            Ok(Verdict::OverBudget { host_time, .. }) => {
                println!(
                    "seed {seed} -O{opt}: over budget (trax at its limit, host {host_time:?})"
                );
                over_budget.push(seed);
                let _ = std::fs::remove_dir_all(&dir);
            }
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
        "csmith: {n} seeds from {first} in {:.1} s: {agree} agree, {no_oracle} without an oracle (did not finish on the host), {} over budget {over_budget:?}, {} disagree {bad:?}",
        start.elapsed().as_secs_f64(),
        over_budget.len(),
        bad.len()
    );
    if let Some((seed, rate, n, t)) = densest {
        println!(
            "densest agreeing program (host CPU >= 50 ms): seed {seed}, {n} instructions in {t:?} of host CPU = {:.1} G per host second (bound for over budget: {} G)",
            rate / 1e9,
            MAX_INSTRUCTIONS_PER_HOST_SECOND / 1_000_000_000
        );
    }
    if !bad.is_empty() {
        std::process::exit(1);
    }
}
