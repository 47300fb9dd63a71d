//! The ray sentinel's DMA engine (thesis §7.1.1) alone on the thesis GDDR5: a 2 MB block
//! transfer, Table 7.1's experiment ("2MB represents half of the ray buffer capacity"), to
//! DRAM and back. The thesis's USIMM run: 99% row-buffer hits, 47.5 GB/s (bounded by the
//! ray buffer's 48 GB/s: one 48-byte ray per cycle at 1 GHz), 0.04 ms, 34.5 W.

use trax_emulator::memsys::sentinel::DmaJob;
use trax_emulator::memsys::{DramConfig, MemSysConfig, MemSystem};

/// Runs one transfer of `rays` 48-byte rays from address 0x8000_0000; returns (cycles,
/// DRAM row-hit rate of its accesses, DRAM power in W, DRAM column accesses).
fn transfer(write: bool, rays: u32) -> (u64, f64, f64, u64) {
    let cfg = MemSysConfig {
        dram: DramConfig::gddr5_thesis(),
        ..MemSysConfig::default()
    };
    let mut mem = MemSystem::new(&cfg, 1, 1, 1000).unwrap();
    let mut tms = mem.take_tms();
    let chip = mem.chip_mut();
    chip.dma_start(DmaJob {
        id: 7,
        write,
        addr: 0x8000_0000,
        rays,
        ray_bytes: 48,
        start: 0,
    });
    let mut now = 0;
    let end = loop {
        now += 64;
        chip.serve_until(now, &mut tms);
        if let Some(e) = chip.dma_events().into_iter().find(|e| e.done) {
            assert_eq!((e.id, e.rays), (7, rays));
            break now;
        }
        assert!(now < 10_000_000, "the transfer never finished");
    };
    // Let posted writes drain before reading the DRAM's counters.
    let mut now = end;
    while chip.next_event().is_some() {
        now += 64;
        chip.serve_until(now, &mut tms);
    }
    let s = mem.stats_with(&tms);
    let rate = s.dma_row_hits as f64 / s.dma_columns as f64;
    // Power over the DRAM's simulated time (transfer and write drain), W = nJ / ns.
    let watts = s.dram.energy.total_nj() / s.dram.core_cycles as f64;
    (s.dma.busy_cycles, rate, watts, s.dma_columns)
}

#[test]
fn a_2mb_block_moves_at_the_ray_rate_in_whole_rows() {
    // 2 MB of 48-byte rays.
    let rays = (2 << 20) / 48;
    let lines = u64::from(rays * 48).div_ceil(64);
    for write in [true, false] {
        let (cycles, hit_rate, watts, cols) = transfer(write, rays);
        assert_eq!(cols, lines);
        // One ACT per 8 KB row (128 lines): 127/128 = 99.2% hits, less rows a refresh
        // closes mid-transfer (a few of the 256 rows).
        assert!(hit_rate > 0.98, "write {write}: {hit_rate}");
        // The ray rate bounds it: one ray per 1 GHz core cycle = 48 GB/s.
        let gbps = f64::from(rays * 48) / cycles as f64;
        assert!((45.0..=48.0).contains(&gbps), "write {write}: {gbps} GB/s");
        eprintln!(
            "{}: {} bytes in {cycles} cycles = {gbps:.1} GB/s ({:.3} ms), row hits {:.1}%, DRAM {:.1} W",
            if write { "spill" } else { "refill" },
            rays * 48,
            cycles as f64 / 1e6,
            100.0 * hit_rate,
            watts
        );
    }
}
