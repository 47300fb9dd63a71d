//! Functional warming (`MemSystem::warm`, sampled simulation's fast-forward) leaves the
//! memory system as timed accesses of the same stream would: the same L1 and L2 tags in
//! the same LRU order, and DRAM rows open such that a later timed probe sees the same L1,
//! L2 and row-buffer hits as after the timed stream.

use trax_emulator::memsys::{
    AccessKind, DramConfig, MemRequest, MemStats, MemSysConfig, MemSystem, TimeSpec,
};
use trax_runtime::rng::Rng;

fn config() -> MemSysConfig {
    let mut c = MemSysConfig::default();
    // Small caches, a 4-way L2: the stream evicts, and LRU order matters.
    c.l1.capacity_bytes = 2048;
    c.l2.capacity_bytes = 8192;
    c.l2.associativity = 4;
    c.dram = DramConfig::preset("gddr5-thesis").unwrap();
    // No refresh: rows stay open until a conflict (time passes only in the timed stream).
    c.dram.detailed.timing.t_refi = TimeSpec::Cycles(0);
    c
}

/// 4 TMs, 2 per L2.
fn system() -> MemSystem {
    MemSystem::new(&config(), 4, 2, 1000).unwrap()
}

/// A seeded stream of (TM, address, store) over 256 KB with some locality.
fn stream(n: usize, seed: u32) -> Vec<(usize, u32, bool)> {
    let mut r = Rng::new(seed, 0);
    let mut hot = 0u32;
    (0..n)
        .map(|_| {
            let tm = (r.next_u32() % 4) as usize;
            if r.next_u32().is_multiple_of(4) {
                hot = r.next_u32() % (256 * 1024);
            }
            let addr = (hot + (r.next_u32() % 512)) & !3;
            (tm, addr, r.next_u32().is_multiple_of(8))
        })
        .collect()
}

/// Each access timed, the memory system drained after it (so fills land in access order).
fn timed(m: &mut MemSystem, s: &[(usize, u32, bool)], mut now: u64) -> u64 {
    for (i, &(tm, addr, store)) in s.iter().enumerate() {
        let req = MemRequest {
            addr,
            kind: if store {
                AccessKind::Write
            } else {
                AccessKind::Read
            },
            size: 4,
            requester: tm as u32,
            id: i as u64,
        };
        let _ = m.access(tm, &req, now);
        now = m.drain(now, 1_000_000).expect("drains") + 1;
    }
    now
}

fn hits(s: &MemStats) -> (u64, u64, u64) {
    (
        s.l1.hits,
        s.l2.iter().map(|c| c.hits).sum(),
        s.dram.row_hits,
    )
}

#[test]
fn warming_leaves_the_caches_and_rows_of_the_timed_stream() {
    let s = stream(20_000, 7);
    let mut a = system();
    let now = timed(&mut a, &s, 0);
    let mut b = system();
    for &(tm, addr, store) in &s {
        b.warm(tm, addr, store);
    }
    for tm in 0..4 {
        let (l1a, l2a) = a.caches(tm);
        let (l1b, l2b) = b.caches(tm);
        assert_eq!(l1a.contents(), l1b.contents(), "L1 of TM {tm}");
        for (x, y) in l2a.iter().zip(l2b) {
            assert_eq!(x.contents(), y.contents(), "L2 tags and LRU order");
        }
    }
    // Warming counts nothing.
    assert_eq!(hits(&b.stats()), (0, 0, 0));
    // DRAM rows: a timed probe sees the same hits at every level on both.
    let probe = stream(5_000, 8);
    let (before_a, before_b) = (hits(&a.stats()), hits(&b.stats()));
    timed(&mut a, &probe, now);
    timed(&mut b, &probe, 0);
    let (after_a, after_b) = (hits(&a.stats()), hits(&b.stats()));
    let d = |x: (u64, u64, u64), y: (u64, u64, u64)| (x.0 - y.0, x.1 - y.1, x.2 - y.2);
    let (pa, pb) = (d(after_a, before_a), d(after_b, before_b));
    assert_eq!(
        pa, pb,
        "probe hits (L1, L2, DRAM rows) after timed vs warmed"
    );
    // The probe found warm state (not a cold system's).
    let mut cold = system();
    timed(&mut cold, &probe, 0);
    assert_ne!(
        hits(&cold.stats()),
        pa,
        "the probe does not see the warmed state"
    );
}
