//! Corrupt executables are rejected with an error naming the file and the section, before
//! anything is sized from the corrupt header (a `.text` claiming 3 GB once made the loader
//! predecode 11.8 GB).

mod common;
use common::*;
use trax_emulator::Executable;
use trax_emulator::{Machine, MachineConfig};

const SRC: &str = "#include \"trax.h\"\nvoid trax_main(void) { trax_printi(7); }\n";

/// Byte offset of the first executable section header of an ELF32 LE file.
fn exec_section_header(elf: &[u8]) -> usize {
    let u32_at = |o: usize| u32::from_le_bytes(elf[o..o + 4].try_into().unwrap());
    let u16_at = |o: usize| u16::from_le_bytes(elf[o..o + 2].try_into().unwrap()) as usize;
    let (shoff, shentsize, shnum) = (u32_at(0x20) as usize, u16_at(0x2e), u16_at(0x30));
    (0..shnum)
        .map(|i| shoff + i * shentsize)
        .find(|&h| u32_at(h + 8) & 4 != 0 && u32_at(h + 20) != 0)
        .expect("an executable section")
}

fn load(elf: &[u8]) -> Result<(), String> {
    let exe = Executable::parse("bad.elf", elf).map_err(|e| e.to_string())?;
    Machine::new(
        &exe.segments,
        exe.text_start,
        exe.text_end,
        exe.entry,
        MachineConfig::default(),
    )
    .map(|_: Machine| ())
    .map_err(|e| e.to_string())
}

#[test]
fn huge_text_section_is_rejected() {
    let elf = std::fs::read(build_c("bad_elf_huge", SRC, "-O1")).unwrap();
    assert!(load(&elf).is_ok());
    let mut bad = elf.clone();
    let h = exec_section_header(&bad);
    bad[h + 20..h + 24].copy_from_slice(&0xC000_0000u32.to_le_bytes());
    let e = load(&bad).expect_err("a 3 GB .text must be rejected");
    assert!(e.contains("bad.elf") && e.contains(".text"), "{e}");
    assert!(e.contains("outside the file"), "{e}");
}

#[test]
fn text_section_outside_the_segments_is_rejected() {
    let elf = std::fs::read(build_c("bad_elf_moved", SRC, "-O1")).unwrap();
    let mut bad = elf.clone();
    let h = exec_section_header(&bad);
    bad[h + 12..h + 16].copy_from_slice(&0x3000_0000u32.to_le_bytes());
    let e = load(&bad).expect_err("a .text outside every segment must be rejected");
    assert!(
        e.contains(".text") && e.contains("not inside any loadable segment"),
        "{e}"
    );
}
