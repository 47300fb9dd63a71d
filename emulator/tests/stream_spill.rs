//! Ray stream overflow (`stream_memory.overflow = "spill"`, the sentinel of thesis §7.1.1):
//! a kernel that writes more rays than the SRAM holds reads every one back, in both modes;
//! the spill traffic matches the analytic block count; writers stall while the memory is
//! full; a full spill area is a fault naming the field.

mod common;

use std::path::Path;

use trax_emulator::memsys::DramConfig;
use trax_emulator::timing::{ChipConfig, Overflow, TimingStats};
use trax_emulator::{run, Limits, Mode, Outcome, RunReport, RunRequest};

fn go(elf: &Path, chip: &ChipConfig, mode: Mode) -> (RunReport, Option<TimingStats>, String) {
    let data = std::fs::read(elf).unwrap();
    let path = elf.display().to_string();
    let mut out = Vec::new();
    let mut req = RunRequest::new(&path, &data, chip, mode);
    req.host_threads = Some(1);
    if mode == Mode::Timing {
        req.limits = Limits {
            max_cycles: Some(50_000_000),
            ..Limits::default()
        };
    }
    let mut r = run(req, &mut out).unwrap();
    let t = r.timing.take();
    (r, t, String::from_utf8(out).unwrap())
}

/// Every thread writes PER rays (ray k of thread g holds g x PER + k) round-robin into
/// streams 0..2, then all threads read every stream empty and add up what they read.
const SPILL: &str = r#"
#include "trax.h"
void trax_main(void) {
    unsigned me = trax_gid();
    for (unsigned i = 0; i < PER; i++) {
        trax_strwstart(i % 3);
        trax_strw(me * PER + i);
        trax_strwend();
    }
    trax_barrier(1);
    unsigned count = 0, sum = 0;
    while (trax_strsched() != 0xFFFFFFFFu) {
        while (trax_strrstart()) {
            unsigned v = trax_strr();
            trax_strrend();
            count++;
            sum += v;
        }
    }
    trax_atomadd(2, count);
    trax_atomadd(3, sum);
    trax_barrier(1);
    if (me == 0) {
        trax_printu(trax_gread(2));
        trax_printc(' ');
        trax_printu(trax_gread(3));
    }
}
"#;

/// 48-byte rays, 200 of them in SRAM (4 buffers); blocks of 960 bytes = 20 rays = 15
/// lines; spill above 150 rays, refill below 50; the thesis GDDR5.
fn spill_chip(threads: u32) -> ChipConfig {
    let mut c = common::chip(1, threads);
    c.memory.dram = DramConfig::gddr5_thesis();
    let sm = &mut c.stream_memory;
    sm.buffers = 4;
    sm.capacity_bytes = 4 * 5 + 200 * 52;
    sm.overflow = Overflow::Spill;
    sm.spill.block_bytes = 960;
    sm.spill.area_bytes = 960 * 4096;
    c.validate().unwrap();
    c
}

fn expected(threads: u32, per: u32) -> String {
    let n = threads * per;
    format!("{n} {}", (0..n).fold(0u32, |a, v| a.wrapping_add(v)))
}

#[test]
fn every_ray_written_past_the_capacity_comes_back_in_both_modes() {
    let per = 1000;
    let elf = common::build_c("spill1", &SPILL.replace("PER", &per.to_string()), "-O1");
    let chip = spill_chip(1);
    let want = expected(1, per);
    let (r, _, out) = go(&elf, &chip, Mode::Functional);
    assert!(matches!(r.outcome, Outcome::Finished), "{:?}", r.failure);
    assert_eq!(out, want, "functional");
    let (r, t, out) = go(&elf, &chip, Mode::Timing);
    assert!(matches!(r.outcome, Outcome::Finished), "{:?}", r.failure);
    assert_eq!(out, want, "timing");
    let t = t.unwrap();
    let s = &t.stream.spill;
    // One writer: the SRAM lists pass 150 rays at the 151st write and every 20 writes
    // after, each time losing a block of 20: floor((1000 - 151) / 20) + 1 = 43 blocks,
    // every one read back once. Bytes = rays x 48, lines = 960 / 64 = 15 per block.
    let blocks = (per - 151) / 20 + 1;
    assert_eq!(
        (s.spills, s.refills),
        (u64::from(blocks), u64::from(blocks))
    );
    assert_eq!(s.spilled_bytes, u64::from(blocks * 20 * 48));
    assert_eq!(s.refilled_bytes, s.spilled_bytes);
    assert_eq!(
        (s.dram_lines_written, s.dram_lines_read),
        (u64::from(blocks * 15), u64::from(blocks * 15))
    );
    // The kernel itself touches no DRAM: every DRAM access is the sentinel's.
    let d = &t.memory.dram;
    assert_eq!(
        (d.writes, d.reads),
        (s.dram_lines_written, s.dram_lines_read)
    );
    assert!(
        s.dram_row_hit_rate.unwrap() > 0.5 && s.busy_cycles > 0,
        "{s:?}"
    );
    // The rays left in SRAM at most: the high watermark.
    assert!(t.stream.max_rays_in_flight >= per);
}

#[test]
fn writers_stall_while_the_sentinel_drains_and_lose_nothing() {
    let (threads, per) = (8, 300);
    let elf = common::build_c("spill8", &SPILL.replace("PER", &per.to_string()), "-O1");
    let mut chip = spill_chip(threads);
    // A stream unit and fetch slots per thread: 8 writes per 4-cycle quantum outrun the
    // sentinel's one ray per cycle, so the SRAM fills while a block drains.
    chip.units.get_mut("stream").unwrap().count = threads;
    chip.icache.fetches_per_bank = threads;
    let want = expected(threads, per);
    let (r, _, out) = go(&elf, &chip, Mode::Functional);
    assert!(matches!(r.outcome, Outcome::Finished), "{:?}", r.failure);
    assert_eq!(out, want, "functional");
    let (r, t, out) = go(&elf, &chip, Mode::Timing);
    assert!(matches!(r.outcome, Outcome::Finished), "{:?}", r.failure);
    assert_eq!(out, want, "timing");
    let s = t.unwrap().stream.spill;
    assert!(s.stall_cycles > 0, "{s:?}");
    assert_eq!(s.spills, s.refills);
    // The same chip with overflow = fault: the first write past 200 rays is a fault.
    let mut fault = chip.clone();
    fault.stream_memory.overflow = Overflow::Fault;
    let (r, _, _) = go(&elf, &fault, Mode::Functional);
    assert!(r
        .failure
        .unwrap_or_default()
        .contains("ray stream memory full"));
}

#[test]
fn a_full_spill_area_is_a_fault_naming_the_field() {
    let elf = common::build_c("spill_area", &SPILL.replace("PER", "1000"), "-O1");
    let mut chip = spill_chip(1);
    chip.stream_memory.spill.area_bytes = 960 * 10;
    chip.validate().unwrap();
    for mode in [Mode::Functional, Mode::Timing] {
        let (r, _, _) = go(&elf, &chip, mode);
        let report = r.failure.unwrap_or_default();
        assert!(matches!(r.outcome, Outcome::Crashed(_)), "{mode:?}");
        assert!(
            report.contains("ray spill area full")
                && report.contains("10 blocks of 960 bytes")
                && report.contains("stream_memory.spill.area_bytes"),
            "{report}"
        );
    }
}

#[test]
fn spill_fields_are_checked_by_name() {
    let base = spill_chip(1);
    let err = |path: &str, v: toml::Value| {
        let mut c = base.clone();
        c.set_field(path, v).unwrap_err().to_string()
    };
    let e = err(
        "stream_memory.spill.block_bytes",
        toml::Value::Integer(1000),
    );
    assert!(e.contains("stream_memory.spill.block_bytes = 1000"), "{e}");
    let e = err("stream_memory.spill.area_bytes", toml::Value::Integer(1000));
    assert!(e.contains("stream_memory.spill.area_bytes"), "{e}");
    let e = err("stream_memory.spill.low_watermark", toml::Value::Float(0.7));
    assert!(e.contains("must fit between low_watermark"), "{e}");
    let e = err(
        "stream_memory.spill.high_watermark",
        toml::Value::Float(1.5),
    );
    assert!(e.contains("fractions of the capacity"), "{e}");
    let e = err("stream_memory.overflow", toml::Value::String("drop".into()));
    assert!(e.contains("drop"), "{e}");
}
