//! Fuzz target bodies of this crate (`fuzz/fuzz_targets/`), also run on the committed
//! inputs by `tests/fuzz_regressions.rs` on stable Rust.

use std::path::Path;

use crate::sweep::spec::{self, Grid};

/// Sweeps planned in full by the fuzz target at most (bigger ones are only sized: planning
/// a million points takes seconds).
const FUZZ_MAX_POINTS: u64 = 4096;

/// A sweep file: parsed and checked; when it is small, its points made and listed. It may
/// be refused, never panic, hang or allocate without bound.
pub fn sweep_file(data: &[u8]) {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let Ok(s) = spec::parse(text, Path::new("fuzz/sweep.toml")) else {
        return;
    };
    let size = std::iter::once(s.cases.len().max(1) as u64)
        .chain(s.axes.iter().map(|a| a.values.len() as u64))
        .chain(std::iter::once(u64::from(s.repetitions)))
        .try_fold(1u64, |a, f| a.checked_mul(f));
    match size {
        // Sized and refused before anything is made.
        None => assert!(Grid::new(&s).is_err(), "a sweep of more than 2^64 points"),
        Some(n) if n > spec::MAX_POINTS => assert!(Grid::new(&s).is_err(), "{n} points"),
        Some(n) if n > FUZZ_MAX_POINTS => return,
        Some(_) => {}
    }
    let _ = spec::columns(&s);
    if let Ok(grid) = Grid::new(&s) {
        for i in grid.indices() {
            let p = grid.point(i);
            assert_eq!(p.index, i);
            assert!(grid.point_at(i, &p.id).is_some());
        }
    }
}
