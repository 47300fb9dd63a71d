//! csmith differential: random C programs built by trax (clang-14 for TRaX, the trax
//! linker, the emulator) and for i386 on the host print the same checksum (see
//! `tests/csmith/driver.rs`). A handful of fixed seeds here, at -O0 and -O2;
//! `cargo bench --bench csmith` runs many more.

#[path = "csmith/driver.rs"]
mod driver;

use driver::{differential, Verdict};
use std::path::Path;

/// Seeds 1..=SEEDS, alternately at -O0 and -O2.
const SEEDS: u64 = 12;

#[test]
fn random_c_programs_print_the_host_checksum() {
    let base = Path::new(env!("CARGO_TARGET_TMPDIR")).join("csmith-test");
    let mut agreed = 0;
    let mut report = String::new();
    for seed in 1..=SEEDS {
        let opt = if seed % 2 == 0 { 2 } else { 0 };
        let dir = base.join(format!("seed-{seed}"));
        let _ = std::fs::remove_dir_all(&dir);
        match differential(seed, opt, &dir).unwrap_or_else(|e| panic!("seed {seed}: {e}")) {
            Verdict::Agree(_) => agreed += 1,
            Verdict::NoOracle(why) => report += &format!("seed {seed}: no oracle ({why})\n"),
            Verdict::Disagree { host, trax } => {
                panic!(
                    "seed {seed} -O{opt} ({}): host printed\n{host}\ntrax printed\n{trax}",
                    dir.display()
                )
            }
        }
    }
    // Any wrong checksum fails above. A seed without an oracle (did not finish on the
    // host) compares nothing, so demand that a third of the seeds did compare, so the test cannot pass comparing
    // nothing (csmith's own docs expect many programs not to terminate quickly).
    eprint!("{report}");
    assert!(
        agreed * 3 >= SEEDS,
        "only {agreed} of {SEEDS} seeds compared:\n{report}"
    );
}
