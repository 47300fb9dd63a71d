//! Planning a sweep takes memory for the sweep file, not for its points: a sweep of 200 000
//! points plans in a fraction of what the eager plan this replaced took (6.8 KB a point:
//! 1272 MB here). Its own test binary, so the peak resident memory of this process's
//! children (`getrusage(RUSAGE_CHILDREN)`) is the sweep's alone.

use std::process::{Command, Stdio};

mod common;
use common::{root, tmp_path};

#[test]
fn planning_a_large_sweep_takes_bounded_memory() {
    let dir = tmp_path("sweep-memory");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let kernel = root().join("examples/gradient.rs");
    let values = |n: u32| {
        (1..=n)
            .map(|i| i.to_string())
            .collect::<Vec<_>>()
            .join(", ")
    };
    let f = dir.join("big.toml");
    std::fs::write(
        &f,
        format!(
            "kernel = {:?}\nmode = \"functional\"\n[axes]\n\"label.a\" = [{}]\n\"label.b\" = [{}]\n",
            kernel.display().to_string(),
            values(200),
            values(1000)
        ),
    )
    .unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_trax"))
        .args(["sweep", f.to_str().unwrap(), "--dry-run"])
        .stdin(Stdio::null())
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(
        String::from_utf8_lossy(&out.stdout).lines().count(),
        200_000
    );
    // SAFETY: an all-zero rusage is a valid value of this plain C struct, and getrusage
    // only writes into it.
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    // SAFETY: `usage` is valid for writes.
    assert_eq!(
        unsafe { libc::getrusage(libc::RUSAGE_CHILDREN, &mut usage) },
        0
    );
    let peak_mb = usage.ru_maxrss / 1024;
    // The process alone (LLVM and the rest of trax mapped) is about 55 MB; planning adds
    // 16 bytes a point while repeated points are found (3 MB here). 150 MB leaves room for
    // allocator and library differences, and is a ninth of the eager plan (1.27 GB on main).
    assert!(
        peak_mb < 150,
        "planning 200 000 points peaked at {peak_mb} MB"
    );
}
