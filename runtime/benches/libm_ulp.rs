//! Accuracy of `trax::libm` (`runtime/prelude/libm.rs`, host build): every f32 input of
//! the unary f32 functions (2^32 each, on all cores), random points for the binary f32
//! and the f64 functions, against the host's f64 libm (see `tests/libm_ref/mod.rs`).
//! Prints max and mean error in ULPs, the worst input, how many results are not
//! correctly rounded (f32 only; the f64 reference is not exact), and the time per point
//! (our function, the reference and the comparison).
//!
//! `cargo bench -p trax-runtime --bench libm_ulp`. Environment:
//! - `TRAX_LIBM_ONLY=sinf,cosf`: only these functions;
//! - `TRAX_LIBM_STRIDE=k`: every k-th f32 bit pattern instead of all (default 1);
//! - `TRAX_LIBM_RANDOM=n`: random points per binary or f64 function (default 10^7);
//! - `TRAX_LIBM_DUMP=FILE`: also write 20000 f64 results per f64 function to FILE for
//!   `prelude/tools/libm_ref.py check FILE` (exact errors against mpmath).

#[path = "../prelude/libm.rs"]
#[allow(dead_code)]
mod libm;
#[path = "../tests/libm_ref/mod.rs"]
mod libm_ref;

use std::io::Write;
use std::time::Instant;

use libm_ref::*;

fn env_u64(name: &str, default: u64) -> u64 {
    std::env::var(name)
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

fn wanted(name: &str) -> bool {
    match std::env::var("TRAX_LIBM_ONLY") {
        Ok(list) => list.split(',').any(|n| n.trim() == name),
        Err(_) => true,
    }
}

/// Error figures plus the count of results more than half an ULP away (beyond the
/// reference's own uncertainty).
#[derive(Default, Clone)]
struct Run {
    st: Stats,
    misrounded: u64,
}

impl Run {
    fn add(&mut self, err: Option<f64>, what: impl FnOnce() -> String) {
        if let Some(e) = err {
            if e > 0.5 + 1e-6 {
                self.misrounded += 1;
            }
        }
        self.st.add(err, what);
    }

    fn merge(&mut self, o: &Run) {
        self.st.merge(&o.st);
        self.misrounded += o.misrounded;
    }
}

fn row(name: &str, r: &Run, secs: f64) {
    let s = &r.st;
    println!(
        "{name:12} {:>11} {:>8.4} {:>8.4} {:>11} {:>7} {:>8.1}  {}",
        s.n,
        s.max,
        s.mean(),
        r.misrounded,
        s.special_mismatches,
        secs * 1e9 / s.n.max(1) as f64,
        s.worst
    );
}

fn threads() -> u64 {
    std::thread::available_parallelism()
        .map(|n| n.get() as u64)
        .unwrap_or(1)
}

/// Every `stride`-th f32 bit pattern, split over the cores.
fn exhaustive(u: &Unary32, stride: u64) -> Run {
    let t = threads();
    let chunk = (1u64 << 32) / t;
    let runs: Vec<Run> = std::thread::scope(|sc| {
        let hs: Vec<_> = (0..t)
            .map(|k| {
                sc.spawn(move || {
                    let mut r = Run::default();
                    let end = if k + 1 == t {
                        1u64 << 32
                    } else {
                        (k + 1) * chunk
                    };
                    let mut b = k * chunk;
                    while b < end {
                        let x = f32::from_bits(b as u32);
                        let got = (u.f)(x);
                        r.add(ulp32(got, (u.reference)(x as f64)), || {
                            format!("{}({:e} = {:#010x}) = {:e}", u.name, x, b, got)
                        });
                        b += stride;
                    }
                    r
                })
            })
            .collect();
        hs.into_iter().map(|h| h.join().unwrap()).collect()
    });
    let mut all = Run::default();
    for r in &runs {
        all.merge(r);
    }
    all
}

fn main() {
    let stride = env_u64("TRAX_LIBM_STRIDE", 1).max(1);
    let n = env_u64("TRAX_LIBM_RANDOM", 10_000_000);
    println!(
        "{:12} {:>11} {:>8} {:>8} {:>11} {:>7} {:>8}  worst input",
        "function", "points", "max ULP", "mean", "misrounded", "special", "ns/point"
    );
    for u in unary32().iter().filter(|u| wanted(u.name)) {
        let t0 = Instant::now();
        let r = exhaustive(u, stride);
        row(u.name, &r, t0.elapsed().as_secs_f64() * threads() as f64);
    }
    for (i, b) in binary32()
        .iter()
        .enumerate()
        .filter(|(_, b)| wanted(b.name))
    {
        let t0 = Instant::now();
        let st = measure_binary32(b, n, 0x5000 + i as u64);
        let r = Run { misrounded: 0, st };
        row(b.name, &r, t0.elapsed().as_secs_f64());
    }
    println!("(f64 functions: ULPs against the host's f64 libm, not the exact value)");
    for (i, u) in unary64().iter().enumerate().filter(|(_, u)| wanted(u.name)) {
        let t0 = Instant::now();
        let st = measure_unary64(u, n, 0x6000 + i as u64);
        row(
            u.name,
            &Run { misrounded: 0, st },
            t0.elapsed().as_secs_f64(),
        );
    }
    for (i, b) in binary64()
        .iter()
        .enumerate()
        .filter(|(_, b)| wanted(b.name))
    {
        let t0 = Instant::now();
        // Signalling NaNs left out: C99 gives pow(sNaN, 0) = 1, glibc a NaN.
        let snan = |v: f64| v.is_nan() && v.to_bits() & 0x0008_0000_0000_0000 == 0;
        let st = measure_binary64(b, n, 0x7000 + i as u64, |x, y| !snan(x) && !snan(y));
        row(
            b.name,
            &Run { misrounded: 0, st },
            t0.elapsed().as_secs_f64(),
        );
    }
    if let Ok(path) = std::env::var("TRAX_LIBM_DUMP") {
        let mut o = std::io::BufWriter::new(std::fs::File::create(&path).unwrap());
        let edges = edge_f64();
        for u in unary64() {
            let mut rng = Rng(0x8000);
            for k in 0..20_000 {
                let x = if k < edges.len() {
                    edges[k]
                } else {
                    sample_f64(&mut rng, u.lo, u.hi)
                };
                writeln!(
                    o,
                    "{} {:016x} {:016x}",
                    u.name,
                    x.to_bits(),
                    (u.f)(x).to_bits()
                )
                .unwrap();
            }
        }
        for b in binary64() {
            let mut rng = Rng(0x9000);
            for _ in 0..20_000 {
                let (x, y) = match b.name {
                    "pow" => {
                        let x = rng.logu(-30.0, 30.0).abs();
                        (x, rng.range(-1070.0, 1020.0) / x.log2().abs().max(1e-6))
                    }
                    "powi" => (rng.range(-4.0, 4.0), rng.range(-1500.0, 1500.0).round()),
                    _ => (
                        sample_f64(&mut rng, b.lo, b.hi),
                        sample_f64(&mut rng, b.lo, b.hi),
                    ),
                };
                writeln!(
                    o,
                    "{} {:016x} {:016x} {:016x}",
                    b.name,
                    x.to_bits(),
                    y.to_bits(),
                    (b.f)(x, y).to_bits()
                )
                .unwrap();
            }
        }
        println!("f64 results written to {path}");
    }
}
