//! The runtime's start-up routine ([`trax_runtime::startup`]) as an ELF relocatable object.
//!
//! [`link`](super::link) adds this object as the first input unless
//! [`LinkOptions::startup`](super::LinkOptions::startup) is off, so `__trax_start` is the
//! first code at [`trax_runtime::abi::TEXT_BASE`]. The same bytes can be written to a `.o`
//! file and given to another linker (the tests link it with `ld.lld`). The object also
//! carries a `.debug_frame` entry marking `$ra` undefined in `__trax_start`, so debuggers
//! end backtraces there.

use object::elf;
use object::write::SectionId;
use object::write::{Object, Relocation, StandardSection, Symbol, SymbolSection};
use object::{
    Architecture, BinaryFormat, Endianness, FileFlags, RelocationFlags, SectionFlags, SectionKind,
    SymbolFlags, SymbolKind, SymbolScope,
};
use trax_runtime::startup::{startup_code, StartupRelocKind};

use super::LinkError;

/// Input name the start-up object carries in link errors.
pub const STARTUP_OBJECT_NAME: &str = "<trax startup>";

/// `e_flags` of the start-up object: MIPS32r6, o32, NaN-2008, `.set noreorder` (the same as
/// LLVM's objects for the TRaX target).
pub const STARTUP_E_FLAGS: u32 = elf::EF_MIPS_ARCH_32R6.0
    | elf::EF_MIPS_ABI_O32.0
    | elf::EF_MIPS_NAN2008.0
    | elf::EF_MIPS_NOREORDER.0;

/// Builds the start-up routine as an ELF32 little-endian MIPS relocatable object with a
/// global function `__trax_start` in `.text` and relocations against `__init_array_start`,
/// `__init_array_end` and `trax_main`.
pub fn startup_object() -> Result<Vec<u8>, LinkError> {
    let code = startup_code();
    let mut obj = Object::new(BinaryFormat::Elf, Architecture::Mips, Endianness::Little);
    obj.flags = FileFlags::Elf {
        os_abi: elf::ELFOSABI_NONE,
        abi_version: 0,
        e_flags: elf::FileFlags(STARTUP_E_FLAGS),
    };
    let text = obj.section_id(StandardSection::Text);
    obj.set_section_data(text, code.bytes(), 16);
    obj.add_symbol(Symbol {
        name: trax_runtime::abi::START_SYMBOL.as_bytes().to_vec(),
        value: 0,
        size: u64::from(code.size()),
        kind: SymbolKind::Text,
        scope: SymbolScope::Dynamic,
        weak: false,
        section: SymbolSection::Section(text),
        flags: SymbolFlags::None,
    });
    add_debug_frame(&mut obj, text, code.size())?;
    let mut undefined = std::collections::HashMap::new();
    for r in &code.relocs {
        let sym = *undefined.entry(r.symbol).or_insert_with(|| {
            obj.add_symbol(Symbol {
                name: r.symbol.as_bytes().to_vec(),
                value: 0,
                size: 0,
                kind: SymbolKind::Unknown,
                scope: SymbolScope::Linkage,
                weak: false,
                section: SymbolSection::Undefined,
                flags: SymbolFlags::None,
            })
        });
        let r_type = match r.kind {
            StartupRelocKind::Hi16 => elf::R_MIPS_HI16,
            StartupRelocKind::Lo16 => elf::R_MIPS_LO16,
            StartupRelocKind::Jump26 => elf::R_MIPS_26,
        };
        obj.add_relocation(
            text,
            Relocation {
                offset: u64::from(r.offset),
                symbol: sym,
                addend: 0,
                flags: RelocationFlags::Elf { r_type },
            },
        )
        .map_err(|e| LinkError::Write(format!("start-up object: {e}")))?;
    }
    obj.write()
        .map_err(|e| LinkError::Write(format!("start-up object: {e}")))
}

/// `SHT_MIPS_DWARF`.
const SHT_MIPS_DWARF: u32 = 0x7000_001e;

/// Adds a `.debug_frame` with one CIE and one FDE covering the start-up code, whose return
/// address column is undefined: debuggers and the crash reporter stop unwinding at
/// `__trax_start` (the outermost frame).
fn add_debug_frame(obj: &mut Object, text: SectionId, code_size: u32) -> Result<(), LinkError> {
    let frame = obj.add_section(Vec::new(), b".debug_frame".to_vec(), SectionKind::Debug);
    obj.section_mut(frame).flags = SectionFlags::Elf {
        sh_type: elf::SectionType(SHT_MIPS_DWARF),
        sh_flags: elf::SectionFlags(0),
    };
    let mut d = Vec::new();
    // CIE: length, CIE id, version 1, no augmentation, code align 1, data align -4,
    // return address register 31; CFA = $sp + 0; $ra undefined; padding.
    d.extend_from_slice(&16u32.to_le_bytes());
    d.extend_from_slice(&0xFFFF_FFFFu32.to_le_bytes());
    d.extend_from_slice(&[1, 0, 1, 0x7C, 31]);
    d.extend_from_slice(&[0x0C, 29, 0, 0x07, 31, 0, 0]); // def_cfa, undefined, nops
                                                         // FDE: length, CIE pointer (relocated), initial location (relocated), range.
    d.extend_from_slice(&12u32.to_le_bytes());
    d.extend_from_slice(&0u32.to_le_bytes());
    d.extend_from_slice(&0u32.to_le_bytes());
    d.extend_from_slice(&code_size.to_le_bytes());
    obj.set_section_data(frame, d, 4);
    let frame_sym = obj.section_symbol(frame);
    let text_sym = obj.section_symbol(text);
    for (offset, symbol) in [(24, frame_sym), (28, text_sym)] {
        obj.add_relocation(
            frame,
            Relocation {
                offset,
                symbol,
                addend: 0,
                flags: RelocationFlags::Elf {
                    r_type: elf::R_MIPS_32,
                },
            },
        )
        .map_err(|e| LinkError::Write(format!("start-up object: {e}")))?;
    }
    Ok(())
}
