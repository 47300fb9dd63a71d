//! Writing the linked program as an ELF32 little-endian MIPS executable.
//!
//! Program headers: `PT_LOAD` text (R+X), `PT_LOAD` data (R+W, bss as `p_memsz > p_filesz`)
//! when there is data, and `PT_MIPS_ABIFLAGS` when the inputs had `.MIPS.abiflags`. Segment
//! file offsets are congruent to their addresses modulo [`SEGMENT_ALIGN`]. Sections, `.symtab` (locals
//! of every input, then globals, scene symbols as `SHN_ABS`), `.strtab` and `.shstrtab` follow.

use object::elf;
use object::write::elf::{FileHeader, ProgramHeader, SectionHeader, SectionIndex, Sym, Writer};
use object::Endianness;

use super::input::{InObject, SymDef};
use super::layout::{Layout, SEGMENT_ALIGN, SHT_MIPS_ABIFLAGS};
use super::relocate::symbol_address;
use super::symbols::{Globals, Resolved};
use super::LinkError;

/// One symbol to write.
struct OutSym<'a> {
    name: &'a [u8],
    value: u32,
    size: u32,
    info: u8,
    other: u8,
    /// Output section index (1-based ELF index) or a special `SHN_*`.
    shndx: Shndx,
}

#[derive(Clone, Copy)]
enum Shndx {
    Section(usize),
    Abs,
    Undef,
}

fn info(bind: elf::SymbolBind, kind: elf::SymbolType) -> u8 {
    elf::SymbolInfo::new(bind, kind).0
}

/// Chooses the smallest file offset >= `cur` congruent to `addr` modulo [`SEGMENT_ALIGN`].
fn congruent(cur: u64, addr: u32) -> u64 {
    let align = u64::from(SEGMENT_ALIGN);
    let want = u64::from(addr) % align;
    cur + (want + align - cur % align) % align
}

/// Builds the output symbol list: (symbols, number of locals).
fn collect_symbols<'a>(
    objs: &'a [InObject],
    globals: &'a Globals,
    layout: &Layout,
) -> (Vec<OutSym<'a>>, usize) {
    let mut syms = Vec::new();
    let out_of = |file: usize, def: SymDef| match def {
        SymDef::Section(s) => layout.place[file][s].map(|(o, _)| Shndx::Section(o)),
        SymDef::Abs => Some(Shndx::Abs),
        _ => None,
    };
    for (fi, obj) in objs.iter().enumerate() {
        for (si, s) in obj.symbols.iter().enumerate().skip(1) {
            if !s.is_local() || s.name.is_empty() || s.kind == elf::STT_SECTION.0 {
                continue;
            }
            let shndx = if s.kind == elf::STT_FILE.0 {
                Shndx::Abs
            } else {
                match out_of(fi, s.def) {
                    Some(x) => x,
                    None => continue,
                }
            };
            syms.push(OutSym {
                name: s.name.as_bytes(),
                value: if s.kind == elf::STT_FILE.0 {
                    0
                } else {
                    symbol_address(objs, globals, layout, fi, si)
                },
                size: s.size,
                info: info(elf::SymbolBind(s.bind), elf::SymbolType(s.kind)),
                other: s.other,
                shndx,
            });
        }
    }
    let num_local = syms.len();
    for name in &globals.order {
        let Some(resolved) = globals.map.get(name) else {
            continue;
        };
        let sym = match resolved {
            Resolved::Defined { file, sym } => {
                let s = &objs[*file].symbols[*sym];
                let Some(shndx) = out_of(*file, s.def) else {
                    continue;
                };
                OutSym {
                    name: name.as_bytes(),
                    value: symbol_address(objs, globals, layout, *file, *sym),
                    size: s.size,
                    info: info(elf::SymbolBind(s.bind), elf::SymbolType(s.kind)),
                    other: s.other,
                    shndx,
                }
            }
            Resolved::Common { size, .. } => {
                let Some(&(out, off)) = layout.commons.get(name) else {
                    continue;
                };
                OutSym {
                    name: name.as_bytes(),
                    value: layout.sections[out].addr + off,
                    size: *size,
                    info: info(elf::STB_GLOBAL, elf::STT_OBJECT),
                    other: 0,
                    shndx: Shndx::Section(out),
                }
            }
            Resolved::Linker(l) => {
                let (value, sec) = layout.linker_symbol(*l);
                OutSym {
                    name: name.as_bytes(),
                    value,
                    size: 0,
                    info: info(elf::STB_GLOBAL, elf::STT_NOTYPE),
                    other: 0,
                    shndx: sec.map_or(Shndx::Abs, Shndx::Section),
                }
            }
            Resolved::Scene { addr, size } => OutSym {
                name: name.as_bytes(),
                value: *addr,
                size: *size,
                info: info(elf::STB_GLOBAL, elf::STT_OBJECT),
                other: 0,
                shndx: Shndx::Abs,
            },
            Resolved::WeakUndefined => OutSym {
                name: name.as_bytes(),
                value: 0,
                size: 0,
                info: info(elf::STB_WEAK, elf::STT_NOTYPE),
                other: 0,
                shndx: Shndx::Undef,
            },
        };
        syms.push(sym);
    }
    (syms, num_local)
}

/// Serialises the executable.
pub(crate) fn write(
    objs: &[InObject],
    globals: &Globals,
    layout: &Layout,
    entry: u32,
    e_flags: u32,
) -> Result<Vec<u8>, LinkError> {
    let (syms, num_local) = collect_symbols(objs, globals, layout);
    let abiflags = layout
        .sections
        .iter()
        .find(|s| s.sh_type == SHT_MIPS_ABIFLAGS);
    let (data_start, data_file_end, data_mem_end) = layout.data;
    let has_data = data_mem_end > data_start;
    let num_ph = 1 + u32::from(has_data) + u32::from(abiflags.is_some());

    let mut buf = Vec::new();
    let mut w = Writer::new(Endianness::Little, false, &mut buf);
    w.reserve_file_header();
    w.reserve_program_headers(num_ph);
    w.reserve_null_section_index();
    let mut sec_index = Vec::with_capacity(layout.sections.len());
    let mut sec_name = Vec::with_capacity(layout.sections.len());
    for s in &layout.sections {
        sec_index.push(w.reserve_section_index());
        sec_name.push(w.add_section_name(s.name.as_bytes()));
    }
    w.reserve_symtab_section_index();
    w.reserve_strtab_section_index();
    w.reserve_shstrtab_section_index();

    // Section file offsets.
    let mut offsets = vec![0u64; layout.sections.len()];
    let (text_start, text_end) = layout.text;
    let text_off = congruent(w.reserved_len(), text_start);
    w.reserve_until(text_off);
    for (i, s) in layout.sections.iter().enumerate() {
        if s.is_alloc() && !s.key.is_data_segment() {
            offsets[i] = text_off + u64::from(s.addr - text_start);
        }
    }
    w.reserve_until(text_off + u64::from(text_end - text_start));
    let data_off = congruent(w.reserved_len(), data_start);
    if has_data {
        w.reserve_until(data_off);
        for (i, s) in layout.sections.iter().enumerate() {
            if s.is_alloc() && s.key.is_data_segment() {
                offsets[i] = if s.is_nobits() {
                    data_off + u64::from(data_file_end - data_start)
                } else {
                    data_off + u64::from(s.addr - data_start)
                };
            }
        }
        w.reserve_until(data_off + u64::from(data_file_end - data_start));
    }
    for (i, s) in layout.sections.iter().enumerate() {
        if !s.is_alloc() {
            offsets[i] = if s.data.is_empty() {
                w.reserved_len()
            } else {
                w.reserve(s.data.len() as u64, u64::from(s.align))
            };
        }
    }
    // Symbols.
    w.reserve_null_symbol_index();
    let mut sym_names = Vec::with_capacity(syms.len());
    for s in &syms {
        let sec = match s.shndx {
            Shndx::Section(o) => Some(sec_index[o]),
            _ => None,
        };
        w.reserve_symbol_index(sec);
        sym_names.push(w.add_string(s.name));
    }
    w.reserve_symtab();
    let err = |e: object::write::Error| LinkError::Write(e.to_string());
    w.reserve_strtab().map_err(err)?;
    w.reserve_shstrtab().map_err(err)?;
    w.reserve_section_headers();

    // Write.
    w.write_file_header(&FileHeader {
        os_abi: elf::ELFOSABI_NONE,
        abi_version: 0,
        e_type: elf::ET_EXEC,
        e_machine: elf::EM_MIPS,
        e_entry: u64::from(entry),
        e_flags: elf::FileFlags(e_flags),
    })
    .map_err(err)?;
    w.write_align_program_headers();
    w.write_program_header(&ProgramHeader {
        p_type: elf::PT_LOAD,
        p_flags: elf::ProgramFlags(elf::PF_R.0 | elf::PF_X.0),
        p_offset: text_off,
        p_vaddr: u64::from(text_start),
        p_paddr: u64::from(text_start),
        p_filesz: u64::from(text_end - text_start),
        p_memsz: u64::from(text_end - text_start),
        p_align: u64::from(SEGMENT_ALIGN),
    });
    if has_data {
        w.write_program_header(&ProgramHeader {
            p_type: elf::PT_LOAD,
            p_flags: elf::ProgramFlags(elf::PF_R.0 | elf::PF_W.0),
            p_offset: data_off,
            p_vaddr: u64::from(data_start),
            p_paddr: u64::from(data_start),
            p_filesz: u64::from(data_file_end - data_start),
            p_memsz: u64::from(data_mem_end - data_start),
            p_align: u64::from(SEGMENT_ALIGN),
        });
    }
    if let Some(a) = abiflags {
        let i = layout
            .sections
            .iter()
            .position(|s| std::ptr::eq(s, a))
            .unwrap_or(0);
        w.write_program_header(&ProgramHeader {
            p_type: elf::PT_MIPS_ABIFLAGS,
            p_flags: elf::PF_R,
            p_offset: offsets[i],
            p_vaddr: u64::from(a.addr),
            p_paddr: u64::from(a.addr),
            p_filesz: u64::from(a.size),
            p_memsz: u64::from(a.size),
            p_align: 8,
        });
    }
    for (i, s) in layout.sections.iter().enumerate() {
        if s.is_nobits() || s.data.is_empty() {
            continue;
        }
        w.pad_until(offsets[i]);
        w.write(&s.data);
    }
    w.write_null_symbol();
    for (s, name) in syms.iter().zip(&sym_names) {
        let (section, st_shndx) = match s.shndx {
            Shndx::Section(o) => (Some(sec_index[o].0), elf::SHN_UNDEF),
            Shndx::Abs => (None, elf::SHN_ABS),
            Shndx::Undef => (None, elf::SHN_UNDEF),
        };
        w.write_symbol(&Sym {
            section,
            st_name: w.string_offset(Some(*name)),
            st_info: elf::SymbolInfo(s.info),
            st_other: elf::SymbolOther(s.other),
            st_shndx,
            st_value: u64::from(s.value),
            st_size: u64::from(s.size),
        });
    }
    w.write_strtab();
    w.write_shstrtab();
    w.write_null_section_header();
    for (i, s) in layout.sections.iter().enumerate() {
        let _: SectionIndex = sec_index[i];
        w.write_section_header(&SectionHeader {
            sh_name: w.section_name_offset(Some(sec_name[i])),
            sh_type: elf::SectionType(s.sh_type),
            sh_flags: elf::SectionFlags(u64::from(s.flags)),
            sh_addr: u64::from(s.addr),
            sh_offset: offsets[i],
            sh_size: u64::from(s.size),
            sh_link: 0,
            sh_info: 0,
            sh_addralign: u64::from(s.align),
            sh_entsize: u64::from(s.entsize),
        });
    }
    w.write_symtab_section_header(num_local as u32 + 1);
    w.write_strtab_section_header();
    w.write_shstrtab_section_header();
    drop(w);
    Ok(buf)
}
