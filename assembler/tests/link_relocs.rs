//! Relocation arithmetic on hand-built objects: several R_MIPS_HI16 sharing one R_MIPS_LO16
//! (the GNU extension of the ABI's pairing rule), carries, and absolute data words.

use object::write::{Object, Relocation, StandardSection, Symbol, SymbolSection};
use object::{
    elf, Architecture, BinaryFormat, Endianness, FileFlags, RelocationFlags, SymbolFlags,
    SymbolKind, SymbolScope,
};
use trax_assembler::link::{link, Input, LinkOptions};
use trax_runtime::exe::Executable;

/// An object with `.text` = `words` (global `__trax_start` at 0), `.data` of 0x20 bytes
/// with global `target` at offset 0x10, and `relocs` (offset, type) in `.text` against
/// `target`, in the given order.
fn object(words: &[u32], relocs: &[(u64, elf::RelocationType)]) -> Vec<u8> {
    let mut obj = Object::new(BinaryFormat::Elf, Architecture::Mips, Endianness::Little);
    obj.flags = FileFlags::Elf {
        os_abi: elf::ELFOSABI_NONE,
        abi_version: 0,
        e_flags: elf::FileFlags(trax_assembler::link::startup::STARTUP_E_FLAGS),
    };
    let text = obj.section_id(StandardSection::Text);
    let bytes: Vec<u8> = words.iter().flat_map(|w| w.to_le_bytes()).collect();
    obj.set_section_data(text, bytes, 16);
    let data = obj.section_id(StandardSection::Data);
    obj.set_section_data(data, vec![0u8; 0x20], 16);
    let sym = |name: &str, section, value, kind| Symbol {
        name: name.as_bytes().to_vec(),
        value,
        size: 0,
        kind,
        scope: SymbolScope::Linkage,
        weak: false,
        section: SymbolSection::Section(section),
        flags: SymbolFlags::None,
    };
    obj.add_symbol(sym("__trax_start", text, 0, SymbolKind::Text));
    let target = obj.add_symbol(sym("target", data, 0x10, SymbolKind::Data));
    for &(offset, r_type) in relocs {
        obj.add_relocation(
            text,
            Relocation {
                offset,
                symbol: target,
                addend: 0,
                flags: RelocationFlags::Elf { r_type },
            },
        )
        .unwrap();
    }
    obj.write().unwrap()
}

fn link_words(words: &[u32], relocs: &[(u64, elf::RelocationType)]) -> (Vec<u32>, u32) {
    let input = Input {
        name: "hand.o".into(),
        bytes: object(words, relocs),
    };
    let opts = LinkOptions {
        startup: false,
        ..LinkOptions::default()
    };
    let linked = link(&[input], &opts).expect("link");
    let exe = Executable::parse("out", &linked.elf).unwrap();
    let text = &exe.segments[0].data;
    let out = text
        .chunks(4)
        .take(words.len())
        .map(|c| u32::from_le_bytes(c.try_into().unwrap()));
    (out.collect(), exe.symbol("target").unwrap().addr)
}

#[test]
fn two_hi16_share_one_lo16_with_carry() {
    // lui $2, 0 ; lui $3, 0 ; addiu $2, $2, 0x7ffc ; lw $3, 0x7ffc($3)
    let words = [0x3C02_0000, 0x3C03_0000, 0x2442_7FFC, 0x8C63_7FFC];
    let relocs = [
        (0, elf::R_MIPS_HI16),
        (4, elf::R_MIPS_HI16),
        (8, elf::R_MIPS_LO16),
        (12, elf::R_MIPS_LO16),
    ];
    let (out, target) = link_words(&words, &relocs);
    let value = target + 0x7FFC;
    let hi = (value.wrapping_add(0x8000) >> 16) & 0xFFFF;
    assert_eq!(out[0], 0x3C02_0000 | hi);
    assert_eq!(out[1], 0x3C03_0000 | hi);
    assert_eq!(out[2] & 0xFFFF, value & 0xFFFF);
    assert_eq!(out[3] & 0xFFFF, value & 0xFFFF);
    // The pair reassembles the address (lo is sign-extended by the CPU).
    assert_eq!((hi << 16).wrapping_add(out[2] as u16 as i16 as u32), value);
}

#[test]
fn negative_lo_addend_borrows_from_hi() {
    // %hi/%lo of target-4: lo addend 0xfffc (= -4).
    let words = [0x3C02_0000, 0x2442_FFFC];
    let (out, target) = link_words(&words, &[(0, elf::R_MIPS_HI16), (4, elf::R_MIPS_LO16)]);
    let value = target - 4;
    assert_eq!(
        ((out[0] & 0xFFFF) << 16).wrapping_add(out[1] as u16 as i16 as u32),
        value
    );
}

#[test]
fn pc_relative_hi_lo_pair() {
    // auipc $2, %pcrel_hi(target) ; addiu $2, $2, %pcrel_lo(target + 4)
    // (R_MIPS_PCHI16 = 64, R_MIPS_PCLO16 = 65)
    let words = [0xEC5E_0000, 0x2442_0004];
    let (out, target) = link_words(
        &words,
        &[(0, elf::RelocationType(64)), (4, elf::RelocationType(65))],
    );
    // auipc adds hi<<16 to its own address; addiu adds sign-extended lo.
    let p = trax_runtime::abi::TEXT_BASE;
    let computed = p
        .wrapping_add((out[0] & 0xFFFF) << 16)
        .wrapping_add(out[1] as u16 as i16 as u32);
    assert_eq!(computed, target);
}

#[test]
fn jump26_and_absolute_words() {
    // jal target (data address, just to exercise arithmetic); .word target via R_MIPS_32.
    let words = [0x0C00_0000, 0x0000_0008];
    let (out, target) = link_words(&words, &[(0, elf::R_MIPS_26), (4, elf::R_MIPS_32)]);
    assert_eq!(out[0], 0x0C00_0000 | ((target >> 2) & 0x03FF_FFFF));
    assert_eq!(out[1], target + 8);
}
