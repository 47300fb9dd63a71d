//! DRAM-model speed: simulated requests per host second on one thread, for a random and a
//! streaming trace, per preset. Run with `cargo bench -p trax-emulator --bench dram`.
//! Target: >= 5 M requests/s on the random trace with `gddr5-thesis`. Anchor (measured on this
//! machine kind, /work/shared/reference/anchors.md): DRAMsim3 does 0.09-0.87 M requests/s;
//! each row prints trax's rate as a multiple of both ends of that range.

use std::time::Instant;
use trax_emulator::memsys::{Completion, Dram, DramConfig};

const CORE_MHZ: u32 = 1000;

/// DRAMsim3's measured range on this machine kind, M requests per host second.
const DRAMSIM3_MREQ: (f64, f64) = (0.09, 0.87);

/// Offers up to `per_cycle` requests per core cycle from `next_addr`, retrying refused ones,
/// until `n` reads have completed. Returns (requests, host seconds, simulated core cycles).
fn run(
    cfg: &DramConfig,
    n: u64,
    per_cycle: u32,
    mut next_addr: impl FnMut() -> u32,
) -> (u64, f64, u64) {
    let mut d = Dram::new(cfg, CORE_MHZ).expect("preset is valid");
    let mut out: Vec<Completion> = Vec::with_capacity(1024);
    let mut submitted = 0u64;
    let mut done = 0u64;
    let mut held: Option<u32> = None;
    let mut c = 0u64;
    let mut last = 0u64;
    let start = Instant::now();
    while done < n {
        d.advance_to(c, &mut out);
        done += out.len() as u64;
        last = out.iter().fold(last, |m, x| m.max(x.cycle));
        out.clear();
        let mut k = 0;
        while k < per_cycle && submitted < n {
            let a = held.take().unwrap_or_else(&mut next_addr);
            if d.submit(submitted, a, false, c, &mut out) {
                submitted += 1;
                k += 1;
            } else {
                held = Some(a);
                break;
            }
        }
        c += 1;
    }
    (n, start.elapsed().as_secs_f64(), last.max(1))
}

fn main() {
    let n = 2_000_000u64;
    println!("DRAM model speed ({n} reads per run, one host thread)");
    println!(
        "{:<14} {:<10} {:>10} {:>12} {:>12} {:>14} {:>10}",
        "preset", "trace", "M req/s", "x DRAMsim3", "x DRAMsim3", "sim cycles", "GB/s sim"
    );
    println!(
        "{:<14} {:<10} {:>10} {:>12} {:>12}",
        "", "", "", "(0.87 M/s)", "(0.09 M/s)"
    );
    for name in ["gddr5-thesis", "gddr5-usimm", "ddr4-2400", "hbm2", "simple"] {
        let cfg = DramConfig::preset(name).expect("known preset");
        // Random lines over 4 GB (xorshift; deterministic).
        let mut x: u32 = 0x9e37_79b9;
        let random = move || {
            x ^= x << 13;
            x ^= x >> 17;
            x ^= x << 5;
            x & !63
        };
        // 16 sequential streams, each walking whole DRAM rows, interleaved.
        let cols = cfg.detailed.columns;
        let mut k: u32 = 0;
        let streaming = move || {
            let (s, i) = (k % 16, k / 16);
            k = k.wrapping_add(1);
            (((i / cols) * 16 + s) * cols + i % cols).wrapping_mul(64)
        };
        for (trace, res) in [
            ("random", run(&cfg, n, 16, random)),
            ("streaming", run(&cfg, n, 16, streaming)),
        ] {
            let (reqs, secs, cycles) = res;
            let gbps = reqs as f64 * 64.0 / cycles as f64 * f64::from(CORE_MHZ) * 1e6 / 1e9;
            let mreq = reqs as f64 / secs / 1e6;
            println!(
                "{:<14} {:<10} {:>10.2} {:>11.1}x {:>11.1}x {:>14} {:>10.1}",
                name,
                trace,
                mreq,
                mreq / DRAMSIM3_MREQ.1,
                mreq / DRAMSIM3_MREQ.0,
                cycles,
                gbps
            );
        }
    }
}
