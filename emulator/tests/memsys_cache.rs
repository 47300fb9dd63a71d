//! Analytic tests of the cache hierarchy and the memory-system configuration.

use trax_emulator::memsys::{
    Access, AccessKind, Completion, DramConfig, MemRequest, MemSysConfig, MemSystem, Stall,
};

fn load(addr: u32, id: u64) -> MemRequest {
    MemRequest {
        addr,
        kind: AccessKind::Read,
        size: 4,
        requester: 0,
        id,
    }
}

fn store(addr: u32) -> MemRequest {
    MemRequest {
        addr,
        kind: AccessKind::Write,
        size: 4,
        requester: 0,
        id: 0,
    }
}

fn simple_cfg() -> MemSysConfig {
    MemSysConfig {
        dram: DramConfig::preset("simple").unwrap(),
        ..MemSysConfig::default()
    }
}

/// L1 1 cycle, L2 3 cycles, simple DRAM: 100 cycles + 64 B at 512 B/cycle (1 cycle).
fn simple_system(tms: usize, per_l2: usize) -> MemSystem {
    MemSystem::new(&simple_cfg(), tms, per_l2, 1000).unwrap()
}

fn drain(m: &mut MemSystem, now: u64) -> Vec<Completion> {
    let mut out = Vec::new();
    m.advance_to(now, &mut out);
    out
}

#[test]
fn l1_l2_dram_latencies() {
    let mut m = simple_system(2, 2);
    // Cold miss: sent to the L2, which serves it when the memory system advances.
    assert_eq!(m.access(0, &load(0x1000, 1), 0), Access::Pending);
    // Same line, same cycle: joins the L1 MSHR.
    assert_eq!(m.access(0, &load(0x1004, 2), 0), Access::Pending);
    // DRAM 1 (transfer) + 100, then L2 3, then L1 1.
    assert_eq!(
        drain(&mut m, 1),
        vec![
            Completion { id: 1, cycle: 105 },
            Completion { id: 2, cycle: 105 }
        ]
    );
    // Between now and the fill, another access merges with the known ready time.
    assert_eq!(m.access(0, &load(0x1008, 3), 50), Access::Ready(105));
    // After the fill: L1 hit.
    assert_eq!(m.access(0, &load(0x1000, 4), 200), Access::Ready(201));
    // The other TM of the L2 group: L1 miss, L2 hit = 3 + 1.
    assert_eq!(m.access(1, &load(0x1010, 5), 300), Access::Pending);
    assert_eq!(drain(&mut m, 301), vec![Completion { id: 5, cycle: 304 }]);
    // Stores are write-around: acknowledged after the L1 latency, no allocation.
    assert_eq!(m.access(0, &store(0x9000), 400), Access::Ready(401));
    assert_eq!(m.access(0, &load(0x9000, 6), 401), Access::Pending);
    drain(&mut m, 402);
    let s = m.stats();
    assert_eq!(s.l1.accesses, 7);
    assert_eq!(s.l1.hits, 1);
    assert_eq!(s.l1.misses, 5);
    assert_eq!(s.l1.merged, 2);
    assert_eq!(s.l1.stores, 1);
    assert_eq!(s.l2[0].hits, 1);
    assert_eq!(s.l2[0].misses, 2);
    assert_eq!(s.l2[0].stores, 1);
    assert_eq!(s.dram.reads, 2);
    assert_eq!(s.dram.writes, 1);
    assert!((s.l1.hit_rate() - 1.0 / 6.0).abs() < 1e-12);
    // Cacti defaults: 32 KB / 4 banks / 64 B L1 = 0.391508 mm², 0.165190 nJ.
    assert_eq!(s.l1_cost.area_mm2, 0.391508);
    assert!((s.l1_energy_nj - 0.165190 * 6.0).abs() < 1e-9);
    assert!((s.l1_area_mm2 - 2.0 * 0.391508).abs() < 1e-12);
}

#[test]
fn bank_conflicts_for_known_pattern() {
    let mut m = simple_system(1, 1);
    // Warm 4 lines.
    for i in 0..4u32 {
        m.access(0, &load(i * 64, 100 + u64::from(i)), u64::from(i));
    }
    drain(&mut m, 10);
    let base = m.stats().l1.bank_retries;
    assert_eq!(base, 0);
    // Cycle 1000: 4 banks, word interleaved. Words 0..3 hit banks 0..3: no conflict.
    for w in 0..4u32 {
        assert!(matches!(
            m.access(0, &load(w * 4, 0), 1000),
            Access::Ready(1001)
        ));
    }
    // Cycle 1001: stride 16 B -> every access in bank 0: 1 served, 7 conflicts.
    let mut stalls = 0;
    for k in 0..8u32 {
        match m.access(0, &load(k * 16, 0), 1001) {
            Access::Stall(Stall::L1Bank) => stalls += 1,
            Access::Ready(_) => {}
            other => panic!("unexpected {other:?}"),
        }
    }
    assert_eq!(stalls, 7);
    assert_eq!(m.stats().l1.bank_retries, 7);
    // 7 refused attempts, but one conflict: bank 0 at cycle 1001.
    assert_eq!(m.stats().l1.bank_conflict_events, 1);
    // Cycle 1002: the same word 8 times: 7 conflicts without read_copy.
    for _ in 0..8 {
        m.access(0, &load(8, 0), 1002);
    }
    assert_eq!(m.stats().l1.bank_retries, 14);
    assert_eq!(m.stats().l1.bank_conflict_events, 2);
    // Cycle 1003: the 7 losers retry (bank 0 again: 6 refused, one event), and two
    // accesses each to banks 1 and 2 (one refused in each: two events).
    for k in 1..8u32 {
        m.access(0, &load(k * 16, 0), 1003);
    }
    for addr in [4, 20, 8, 24] {
        m.access(0, &load(addr, 0), 1003);
    }
    assert_eq!(m.stats().l1.bank_retries, 14 + 6 + 2);
    assert_eq!(m.stats().l1.bank_conflict_events, 2 + 3);

    // With read_copy, same-word accesses share the bank.
    let mut cfg = simple_cfg();
    cfg.l1.read_copy = true;
    let mut m = MemSystem::new(&cfg, 1, 1, 1000).unwrap();
    for _ in 0..8 {
        m.access(0, &load(8, 0), 5);
    }
    assert_eq!(m.stats().l1.bank_retries, 0);
}

#[test]
fn l2_bank_conflicts_between_tms() {
    let mut m = simple_system(2, 2);
    // Both TMs miss in L1 in the same cycle on words of the same L2 bank (16 banks, word
    // interleaved: 0x0 and 0x40 are both bank 0).
    assert_eq!(m.access(0, &load(0x0, 1), 0), Access::Pending);
    assert_eq!(m.access(1, &load(0x40, 2), 0), Access::Pending);
    // Cycle 0 serves TM 0 first (the order rotates with the cycle); TM 1's request waits
    // for the bank and is served at cycle 1, one cycle later.
    let done = drain(&mut m, 2);
    assert_eq!(m.stats().l2[0].bank_retries, 1);
    assert_eq!(
        done,
        vec![
            Completion { id: 1, cycle: 105 },
            Completion { id: 2, cycle: 106 }
        ]
    );
    // At odd cycles the order starts with TM 1.
    assert_eq!(m.access(0, &load(0x80, 3), 3), Access::Pending);
    assert_eq!(m.access(1, &load(0xC0, 4), 3), Access::Pending);
    let mut done = drain(&mut m, 5);
    done.sort_by_key(|c| c.id);
    assert_eq!(m.stats().l2[0].bank_retries, 2);
    assert!(done[1].cycle < done[0].cycle, "{done:?}");
}

#[test]
fn mshr_merge_and_limit_with_detailed_dram() {
    let mut cfg = MemSysConfig::default(); // gddr5-thesis: read time known only when scheduled
    cfg.l1.mshrs = 2;
    let mut m = MemSystem::new(&cfg, 1, 1, 1000).unwrap();
    // Different banks (word interleave: addr/4 % 4), different lines.
    assert_eq!(m.access(0, &load(0, 1), 0), Access::Pending);
    assert_eq!(m.access(0, &load(64 + 4, 2), 0), Access::Pending);
    assert_eq!(
        m.access(0, &load(128 + 8, 3), 0),
        Access::Stall(Stall::L1Mshr)
    );
    // Same line as id 1 while its fill time is unknown: joins the MSHR (hit under miss).
    assert_eq!(m.access(0, &load(8, 4), 1), Access::Pending);
    assert!(drain(&mut m, 2).is_empty());
    let mut done = drain(&mut m, 100);
    done.sort_by_key(|c| c.id);
    // ACT + tRCD + tCAS + burst = 58 DRAM cycles = 29 core cycles, then L2 3 + L1 1.
    let ids: Vec<u64> = done.iter().map(|c| c.id).collect();
    assert_eq!(ids, vec![1, 2, 4]);
    assert_eq!(done[0].cycle, 33);
    assert_eq!(done[2].cycle, 33);
    assert_eq!(m.stats().l1.merged, 1);
    assert_eq!(m.stats().l1.mshr_full, 1);
    assert_eq!(m.access(0, &load(128 + 8, 3), 100), Access::Pending);
}

#[test]
fn set_associative_l2_keeps_conflicting_lines() {
    let run = |ways: u32| {
        let mut cfg = simple_cfg();
        cfg.l2.associativity = ways;
        cfg.l1.capacity_bytes = 64; // one line: every other access misses L1
        let mut m = MemSystem::new(&cfg, 1, 1, 1000).unwrap();
        let stride = cfg.l2.capacity_bytes; // same direct-mapped set
        let mut c = 0;
        for round in 0..4 {
            for k in 0..2u32 {
                c += 1000;
                m.access(0, &load(k * stride, round), c);
                drain(&mut m, c + 1);
            }
        }
        m.stats().l2[0].hits
    };
    assert_eq!(run(1), 0);
    assert_eq!(run(2), 6);
}

#[test]
fn detailed_dram_behind_caches_and_determinism() {
    let run = || {
        let cfg = MemSysConfig::default(); // gddr5-thesis
        let mut m = MemSystem::new(&cfg, 4, 2, 1000).unwrap();
        let mut x: u32 = 7;
        let mut pending = 0u64;
        let mut done = Vec::new();
        let mut stalls = 0u64;
        for c in 0..20_000u64 {
            m.advance_to(c, &mut done);
            for tm in 0..4 {
                x = x.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
                let addr = (x >> 8) & 0x00ff_fffc;
                let req = if x & 0xf == 0 {
                    store(addr)
                } else {
                    load(addr, c * 4 + tm as u64)
                };
                match m.access(tm, &req, c) {
                    Access::Pending => pending += 1,
                    Access::Stall(_) => stalls += 1,
                    Access::Ready(r) => assert!(r > c),
                }
            }
        }
        m.advance_to(1_000_000, &mut done);
        assert_eq!(done.len() as u64, pending);
        (done, stalls, format!("{:?}", m.stats()))
    };
    let a = run();
    assert!(a.1 > 0);
    assert_eq!(a, run());
}

/// Serves the chip side late, as the timing engine does while the L2s and DRAM owe the L1s
/// nothing: the skipped cycles are caught up in one call, with the same fills, completions
/// and statistics as serving every cycle.
#[test]
fn serving_late_while_owing_nothing_changes_nothing() {
    let run = |cfg: &MemSysConfig, lazy: bool| {
        let mut m = MemSystem::new(cfg, 4, 2, 1000).unwrap();
        let mut x: u32 = 11;
        let mut done = Vec::new();
        let mut sent = false;
        let (mut skipped, mut calls) = (0u64, 0u64);
        for c in 0..30_000u64 {
            if !lazy || sent || !m.chip_mut().owes_nothing() {
                m.advance_to(c, &mut done);
                sent = false;
                calls += 1;
            } else {
                skipped += 1;
            }
            for tm in 0..4 {
                x = x.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
                // Mostly hits in a small working set, some misses, some stores (which
                // keep the DRAM busy while nothing is owed).
                let addr = if x & 0x1f0 == 0 {
                    (x >> 8) & 0x003f_fffc
                } else {
                    (x >> 8) & 0x0000_0ffc
                };
                let req = if x & 0x7f == 0 {
                    store(addr)
                } else {
                    load(addr, c * 4 + tm as u64)
                };
                match m.access(tm, &req, c) {
                    Access::Pending => sent = true,
                    Access::Ready(_) if req.kind == AccessKind::Write => sent = true,
                    _ => {}
                }
            }
        }
        m.advance_to(1_000_000, &mut done);
        done.sort_by_key(|d| d.id);
        (done, format!("{:?}", m.stats()), skipped, calls)
    };
    let detailed = MemSysConfig::default(); // gddr5-thesis
    for cfg in [simple_cfg(), detailed] {
        let every = run(&cfg, false);
        let late = run(&cfg, true);
        // The lazy driver skipped cycles with writes in flight, and it still served.
        assert!(late.2 > 1000 && late.3 > 1000, "{} {}", late.2, late.3);
        assert_eq!(every.0, late.0);
        assert_eq!(every.1, late.1);
    }
}

#[test]
fn toml_presets_overrides_and_errors() {
    let cfg = MemSysConfig::from_toml_str(
        r#"
        [l1]
        capacity_bytes = 65536
        banks = 8
        [dram]
        preset = "ddr4-2400"
        [dram.detailed]
        channels = 4
        [dram.detailed.timing]
        tCAS = "15ns"
        tRCD = 20
        "#,
    )
    .unwrap();
    assert_eq!(cfg.l1.capacity_bytes, 65536);
    assert_eq!(cfg.l2, MemSysConfig::default().l2);
    assert_eq!(cfg.dram.detailed.channels, 4);
    assert_eq!(cfg.dram.detailed.clock_mhz, 1200); // from the preset
    let t = cfg
        .dram
        .detailed
        .timing
        .resolve(cfg.dram.detailed.clock_mhz);
    assert_eq!((t.t_cas, t.t_rcd, t.t_rp), (18, 20, 16));

    for name in trax_emulator::memsys::DRAM_PRESETS {
        let c = MemSysConfig::from_toml_str(&format!("[dram]\npreset = \"{name}\"\n")).unwrap();
        assert_eq!(c.dram, DramConfig::preset(name).unwrap());
    }

    let err = |text: &str| MemSysConfig::from_toml_str(text).unwrap_err().to_string();
    let e = err("[l1]\ncapacity = 4\n");
    assert!(
        e.contains("`l1.capacity`") && e.contains("line 2, column 12"),
        "{e}"
    );
    let e = err("[dram]\npreset = \"gddr5-thesis\"\n[dram.detailed.timing]\ntXYZ = 3\n");
    assert!(e.contains("tXYZ"), "{e}");
    // Without a preset, partial tables override the default (gddr5-thesis).
    let c = MemSysConfig::from_toml_str("[dram.detailed.timing]\ntCAS = 3\n").unwrap();
    assert_eq!(
        c.dram.detailed.timing.t_cas,
        trax_emulator::memsys::TimeSpec::Cycles(3)
    );
    assert_eq!(c.dram.detailed.channels, 8);
    let e = err("[dram]\npreset = \"gddr7\"\n");
    assert!(e.contains("gddr7"), "{e}");
    let e = err("[dram]\npreset = \"hbm2\"\n[dram.detailed.timing]\ntRP = \"14us\"\n");
    assert!(e.contains("14us"), "{e}");
    let e = err("[l2]\nbanks = 3\n");
    assert!(e.contains("l2.banks"), "{e}");
    let e = err("[cache]\n");
    assert!(e.contains("cache"), "{e}");
    let e = err("[l1]\nline_bytes = 32\n");
    assert!(e.contains("line_bytes"), "{e}");
}

/// The two L1 hit rates on a stream whose counts are worked out by hand (one TM, simple
/// DRAM: a miss's line is valid at cycle 104 after the L2 fill is routed back).
#[test]
fn l1_hit_rate_strict_and_merged_as_hits() {
    let mut m = simple_system(1, 1);
    // Cycle 0: line 0x1000 misses (1 miss), a second word of it joins the MSHR (merged).
    assert_eq!(m.access(0, &load(0x1000, 1), 0), Access::Pending);
    assert_eq!(m.access(0, &load(0x1004, 2), 0), Access::Pending);
    // Cycle 1: a third line misses (1 miss).
    assert_eq!(m.access(0, &load(0x2000, 3), 1), Access::Pending);
    drain(&mut m, 2);
    // Cycle 50: both fills are known but not yet valid: two merged loads.
    assert!(matches!(
        m.access(0, &load(0x1008, 4), 50),
        Access::Ready(_)
    ));
    assert!(matches!(
        m.access(0, &load(0x2004, 5), 50),
        Access::Ready(_)
    ));
    // Cycle 300: three hits; a store (not a load: in neither rate).
    for (i, a) in [0x1000u32, 0x100c, 0x2008].into_iter().enumerate() {
        assert_eq!(
            m.access(0, &load(a, 10 + i as u64), 300),
            Access::Ready(301)
        );
    }
    assert_eq!(m.access(0, &store(0x3000), 301), Access::Ready(302));
    let s = m.stats().l1;
    // Loads: 8 = 3 hits + 5 misses, of which 3 merged (1 MSHR join + 2 known-fill).
    assert_eq!((s.hits, s.misses, s.merged, s.stores), (3, 5, 3, 1));
    assert!((s.hit_rate() - 3.0 / 8.0).abs() < 1e-12);
    assert!((s.hit_rate_merged_as_hits() - 6.0 / 8.0).abs() < 1e-12);
}
