//! Entry points of the fuzz targets in `fuzz/` (run with `cargo fuzz`, see `.ci/fuzz`) and
//! of the regression test that replays their kept inputs on stable Rust. Each takes any
//! bytes and must return (errors are fine) without panicking, hanging or allocating
//! without bound.

use crate::crash;
use crate::debuginfo::DebugInfo;
use crate::decode::decode;
use crate::elf::Executable;
use crate::machine::{Machine, MachineConfig, Outcome};
use crate::memory::{Perms, Segment};
use crate::memsys::{DramConfig, MemSysConfig, MemSystem};
use crate::timing::ChipConfig;
use trax_runtime::abi;

/// A small machine: 1 TM x 2 threads, 4 KiB stacks, at most 20 000 instructions.
fn small_machine() -> MachineConfig {
    MachineConfig {
        tms: 1,
        threads_per_tm: 2,
        stack_size: 4096,
        quantum: 7,
        max_instructions: Some(20_000),
    }
}

/// Decodes and disassembles every little-endian word of `data`, then runs the words as a
/// program (text at `TEXT_BASE`, a 4 KiB writable data page after it).
pub fn decode_words(data: &[u8]) {
    let words: Vec<u32> = data
        .chunks_exact(4)
        .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]))
        .collect();
    for &w in &words {
        let _ = decode(w).to_string();
    }
    if words.is_empty() {
        return;
    }
    let text: Vec<u8> = words.iter().flat_map(|w| w.to_le_bytes()).collect();
    let end = abi::TEXT_BASE + text.len() as u32;
    let segments = [
        Segment::new("text", abi::TEXT_BASE, text, Perms::RX),
        Segment {
            name: "data".into(),
            addr: (end + 0xfff) & !0xfff,
            data: Vec::new(),
            size: 4096,
            perms: Perms::RW,
        },
    ];
    if let Ok(mut m) = Machine::new(
        &segments,
        abi::TEXT_BASE,
        end,
        abi::TEXT_BASE,
        small_machine(),
    ) {
        let s = m.run(&mut std::io::sink());
        if let Outcome::Crashed(c) = &s.outcome {
            let _ = crash::report(c, &m.shared, None, None);
        }
    }
}

/// Loads `data` as an executable, runs it briefly on a small machine and reports a crash
/// with its debug information (DWARF read from the same bytes).
pub fn elf(data: &[u8]) {
    let Ok(exe) = Executable::parse("fuzz.elf", data) else {
        return;
    };
    let dbg = DebugInfo::parse("fuzz.elf", data).ok();
    let Ok(mut m) = Machine::new(
        &exe.segments,
        exe.text_start,
        exe.text_end,
        exe.entry,
        small_machine(),
    ) else {
        return;
    };
    let s = m.run(&mut std::io::sink());
    if let Outcome::Crashed(c) = &s.outcome {
        let _ = crash::report(c, &m.shared, Some(&exe), dbg.as_ref());
    }
}

/// Parses `data` (if UTF-8) as a chip config, a memory-system config and a DRAM config;
/// builds the memory system of every config that is accepted.
pub fn chip_toml(data: &[u8]) {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    match ChipConfig::from_toml_str(text, "fuzz.toml") {
        Ok(c) => {
            let _ = c.to_toml();
            let _ = MemSystem::new(
                &c.memory,
                c.tms as usize,
                c.tms_per_l2 as usize,
                c.clock_mhz(),
            );
        }
        Err(e) => {
            let _ = e.to_string();
        }
    }
    if let Ok(c) = MemSysConfig::from_toml_str(text) {
        let _ = MemSystem::new(&c, 2, 1, 1000);
    }
    if let Ok(d) = DramConfig::from_toml_str(text) {
        let c = MemSysConfig {
            dram: d,
            ..MemSysConfig::default()
        };
        let _ = MemSystem::new(&c, 2, 1, 1000);
    }
}
