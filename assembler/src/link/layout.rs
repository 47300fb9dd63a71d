//! Section merging and address assignment.
//!
//! Output order (all in input order unless stated):
//!
//! | segment | sections |
//! |---|---|
//! | text (R+X) at `text_base` | `.text` (`.text`, `.text.*`), `.rodata` (`.rodata*`, other read-only alloc), `.MIPS.abiflags` (merged), `.eh_frame` |
//! | data (R+W), next page | `.init_array` (sorted by priority), `.data` (`.data*`, `.sdata*`, `.fini_array`...), `.bss` (`.bss*`, `.sbss*`, then COMMON symbols) |
//! | not loaded | `.debug_*`, `.comment`, `.mdebug.abi32` and other non-alloc sections, by name in first-seen order |
//!
//! Dropped: relocation and symbol tables, `.reginfo`, `.pdr`, `.note.GNU-stack`,
//! `.llvm_addrsig`, `SHF_EXCLUDE` sections and discarded COMDAT group members.

use object::elf;

use super::input::{InObject, InSection};
use super::symbols::{Globals, LinkerSym, Resolved};
use super::LinkError;

/// Alignment of the data segment's start address.
pub(crate) const PAGE: u32 = 0x1000;
/// `p_align` of the loadable segments: segment file offsets are congruent to their
/// addresses modulo this, so page-based loaders (qemu-user, gdb) can map them.
pub(crate) const SEGMENT_ALIGN: u32 = 0x1000;

/// An output section.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub(crate) enum OutKey {
    Text,
    Rodata,
    AbiFlags,
    EhFrame,
    InitArray,
    Data,
    Bss,
    /// A non-alloc section kept by name.
    Named(String),
}

impl OutKey {
    fn rank(&self) -> usize {
        match self {
            OutKey::Text => 0,
            OutKey::Rodata => 1,
            OutKey::AbiFlags => 2,
            OutKey::EhFrame => 3,
            OutKey::InitArray => 4,
            OutKey::Data => 5,
            OutKey::Bss => 6,
            OutKey::Named(_) => 7,
        }
    }
    /// True for sections in the data (R+W) segment.
    pub fn is_data_segment(&self) -> bool {
        matches!(self, OutKey::InitArray | OutKey::Data | OutKey::Bss)
    }
}

/// A merged output section.
#[derive(Clone, Debug)]
pub(crate) struct OutSection {
    pub key: OutKey,
    pub name: String,
    pub sh_type: u32,
    pub flags: u32,
    pub entsize: u32,
    pub align: u32,
    pub addr: u32,
    pub size: u32,
    /// Contents (empty for `.bss`), filled by the relocation pass.
    pub data: Vec<u8>,
}

impl OutSection {
    pub fn is_alloc(&self) -> bool {
        self.flags & elf::SHF_ALLOC.0 as u32 != 0
    }
    pub fn is_nobits(&self) -> bool {
        self.sh_type == elf::SHT_NOBITS.0
    }
}

/// Where each kept input section and each common symbol landed.
#[derive(Debug)]
pub(crate) struct Layout {
    /// Output sections in final order.
    pub sections: Vec<OutSection>,
    /// `[file][section]` → (output section index, offset in it); `None` when dropped.
    pub place: Vec<Vec<Option<(usize, u32)>>>,
    /// Common symbol name → (output section index, offset).
    pub commons: std::collections::HashMap<String, (usize, u32)>,
    /// Input `.MIPS.abiflags` sections: (file, section).
    pub abiflags_inputs: Vec<(usize, usize)>,
    /// First address of the text segment and one past its end.
    pub text: (u32, u32),
    /// Data segment: start, end of initialised data, end of memory.
    pub data: (u32, u32, u32),
}

enum Class {
    Drop,
    AbiFlags,
    Out(OutKey),
}

const SHT_LLVM_ADDRSIG: u32 = 0x6fff_4c03;
/// `SHT_MIPS_DWARF`.
const SHT_MIPS_DWARF: u32 = 0x7000_001e;
/// `SHT_MIPS_ABIFLAGS`.
pub(crate) const SHT_MIPS_ABIFLAGS: u32 = 0x7000_002a;

fn classify(file: &str, sec: &InSection) -> Result<Class, LinkError> {
    let t = sec.sh_type;
    let name = sec.name.as_str();
    if sec.discarded
        || [
            elf::SHT_NULL.0,
            elf::SHT_REL.0,
            elf::SHT_RELA.0,
            elf::SHT_SYMTAB.0,
            elf::SHT_STRTAB.0,
            elf::SHT_GROUP.0,
            elf::SHT_SYMTAB_SHNDX.0,
            elf::SHT_MIPS_REGINFO.0,
            elf::SHT_MIPS_OPTIONS.0,
            SHT_LLVM_ADDRSIG,
        ]
        .contains(&t)
        || sec.flags & elf::SHF_EXCLUDE.0 as u32 != 0
        || name == ".pdr"
        || name.starts_with(".note.GNU-stack")
    {
        return Ok(Class::Drop);
    }
    if t == SHT_MIPS_ABIFLAGS {
        return Ok(Class::AbiFlags);
    }
    if !sec.is_alloc() {
        return Ok(Class::Out(OutKey::Named(name.to_string())));
    }
    if sec.flags & elf::SHF_TLS.0 as u32 != 0 {
        return Err(LinkError::Malformed {
            file: file.to_string(),
            detail: format!("thread-local section `{name}` is not supported"),
        });
    }
    let write = sec.flags & elf::SHF_WRITE.0 as u32 != 0;
    let exec = sec.flags & elf::SHF_EXECINSTR.0 as u32 != 0;
    let nobits = t == elf::SHT_NOBITS.0;
    Ok(Class::Out(
        if t == elf::SHT_INIT_ARRAY.0 || name == ".init_array" || name.starts_with(".init_array.") {
            OutKey::InitArray
        } else if exec {
            OutKey::Text
        } else if name == ".eh_frame" {
            OutKey::EhFrame
        } else if nobits {
            OutKey::Bss
        } else if write {
            OutKey::Data
        } else {
            OutKey::Rodata
        },
    ))
}

/// `.init_array.N` runs in ascending N; plain `.init_array` counts as 65536 (as GNU ld/lld).
fn init_priority(name: &str) -> u32 {
    name.strip_prefix(".init_array.")
        .and_then(|p| p.parse().ok())
        .unwrap_or(65536)
}

fn align_up(v: u64, a: u32) -> u64 {
    let a = u64::from(a.max(1));
    v.div_ceil(a) * a
}

/// Largest input section alignment accepted (64 KiB: far above what code and data need).
pub const MAX_SECTION_ALIGN: u32 = 1 << 16;

fn section_props(key: &OutKey, first: &InSection) -> (String, u32, u32, u32) {
    let (wa, a, ax) = (
        (elf::SHF_WRITE.0 | elf::SHF_ALLOC.0) as u32,
        elf::SHF_ALLOC.0 as u32,
        (elf::SHF_ALLOC.0 | elf::SHF_EXECINSTR.0) as u32,
    );
    match key {
        OutKey::Text => (".text".into(), elf::SHT_PROGBITS.0, ax, 0),
        OutKey::Rodata => (".rodata".into(), elf::SHT_PROGBITS.0, a, 0),
        OutKey::AbiFlags => (".MIPS.abiflags".into(), SHT_MIPS_ABIFLAGS, a, 24),
        OutKey::EhFrame => (".eh_frame".into(), elf::SHT_PROGBITS.0, a, 0),
        OutKey::InitArray => (".init_array".into(), elf::SHT_INIT_ARRAY.0, wa, 4),
        OutKey::Data => (".data".into(), elf::SHT_PROGBITS.0, wa, 0),
        OutKey::Bss => (".bss".into(), elf::SHT_NOBITS.0, wa, 0),
        OutKey::Named(n) => {
            let merge = (elf::SHF_MERGE.0 | elf::SHF_STRINGS.0) as u32;
            let entsize = if first.flags & merge != 0 { 1 } else { 0 };
            // DWARF sections are SHT_MIPS_DWARF whatever the first input said.
            let sh_type = if n.starts_with(".debug_") {
                SHT_MIPS_DWARF
            } else {
                first.sh_type
            };
            (n.clone(), sh_type, first.flags & merge, entsize)
        }
    }
}

/// Size of the merged `.MIPS.abiflags` section.
pub(crate) const ABIFLAGS_SIZE: u32 = 24;

/// Merges sections and assigns addresses, starting the text segment at `text_base`.
pub(crate) fn layout(
    objs: &[InObject],
    globals: &Globals,
    text_base: u32,
) -> Result<Layout, LinkError> {
    // Collect (key, file, section) in input order.
    let mut members: Vec<(OutKey, usize, usize)> = Vec::new();
    let mut abiflags_inputs = Vec::new();
    for (fi, obj) in objs.iter().enumerate() {
        for (si, sec) in obj.sections.iter().enumerate().skip(1) {
            match classify(&obj.name, sec)? {
                Class::Drop => {}
                Class::AbiFlags => abiflags_inputs.push((fi, si)),
                Class::Out(key) => members.push((key, fi, si)),
            }
        }
    }
    // Output sections in rank order; non-alloc ones in first-seen order.
    let mut keys: Vec<OutKey> = Vec::new();
    for (key, _, _) in &members {
        if !keys.contains(key) {
            keys.push(key.clone());
        }
    }
    if !abiflags_inputs.is_empty() {
        keys.push(OutKey::AbiFlags);
    }
    let has_commons = globals
        .map
        .values()
        .any(|r| matches!(r, Resolved::Common { .. }));
    if has_commons && !keys.contains(&OutKey::Bss) {
        keys.push(OutKey::Bss);
    }
    keys.sort_by_key(OutKey::rank); // stable: Named keep first-seen order

    let mut place: Vec<Vec<Option<(usize, u32)>>> =
        objs.iter().map(|o| vec![None; o.sections.len()]).collect();
    let mut sections = Vec::with_capacity(keys.len());
    let mut commons = std::collections::HashMap::new();
    for key in keys {
        let mut mine: Vec<(usize, usize)> = members
            .iter()
            .filter(|m| m.0 == key)
            .map(|m| (m.1, m.2))
            .collect();
        if key == OutKey::InitArray {
            mine.sort_by_key(|&(f, s)| init_priority(&objs[f].sections[s].name));
        }
        let first = mine.first().map(|&(f, s)| &objs[f].sections[s]);
        let (name, sh_type, flags, entsize) = match first {
            Some(first) => section_props(&key, first),
            None => section_props(&key, &objs[0].sections[0]),
        };
        let out_index = sections.len();
        let mut size: u64 = 0;
        let mut align = 1u32;
        for (f, s) in mine {
            let sec = &objs[f].sections[s];
            // Contents are materialised for every output section but `.bss`: a member
            // without file contents (or a huge alignment) could size it at gigabytes.
            if sh_type != elf::SHT_NOBITS.0 && sec.sh_type == elf::SHT_NOBITS.0 && sec.size > 0 {
                return Err(LinkError::Malformed {
                    file: objs[f].name.clone(),
                    detail: format!(
                        "section `{}` has no contents in the file (SHT_NOBITS, {} bytes) but goes into `{name}`",
                        sec.name, sec.size
                    ),
                });
            }
            if sec.align > MAX_SECTION_ALIGN {
                return Err(LinkError::Malformed {
                    file: objs[f].name.clone(),
                    detail: format!(
                        "section `{}` alignment {} is above the supported {MAX_SECTION_ALIGN}",
                        sec.name, sec.align
                    ),
                });
            }
            size = align_up(size, sec.align);
            place[f][s] = Some((out_index, size as u32));
            size += u64::from(sec.size);
            align = align.max(sec.align);
        }
        if key == OutKey::AbiFlags {
            size = u64::from(ABIFLAGS_SIZE);
            align = 8;
        }
        if key == OutKey::Bss {
            // Common blocks, in the order their names first appear (input, symbol order).
            for (fi, obj) in objs.iter().enumerate() {
                for sym in obj.symbols.iter().skip(1).filter(|s| !s.is_local()) {
                    if let Some(Resolved::Common {
                        size: csize,
                        align: calign,
                        ..
                    }) = globals.map.get(&sym.name)
                    {
                        if commons.contains_key(&sym.name) {
                            continue;
                        }
                        if !calign.is_power_of_two() {
                            return Err(LinkError::Malformed {
                                file: objs[fi].name.clone(),
                                detail: format!(
                                    "common symbol `{}` alignment {calign} is not a power of two",
                                    sym.name
                                ),
                            });
                        }
                        size = align_up(size, *calign);
                        commons.insert(sym.name.clone(), (out_index, size as u32));
                        size += u64::from(*csize);
                        align = align.max(*calign);
                    }
                }
            }
        }
        if size > u64::from(u32::MAX) {
            return Err(LinkError::TooLarge(format!(
                "section `{name}` is {size} bytes"
            )));
        }
        sections.push(OutSection {
            key,
            name,
            sh_type,
            flags,
            entsize,
            align,
            addr: 0,
            size: size as u32,
            data: Vec::new(),
        });
    }

    // Addresses.
    let mut addr = u64::from(text_base);
    let mut data_start = None;
    for sec in sections.iter_mut().filter(|s| s.is_alloc()) {
        if sec.key.is_data_segment() && data_start.is_none() {
            let text_end = addr;
            addr = align_up(addr, PAGE);
            data_start = Some((text_end, addr));
        }
        addr = align_up(addr, sec.align);
        sec.addr = addr as u32;
        addr += u64::from(sec.size);
        if addr > u64::from(trax_runtime::abi::STACK_TOP - trax_runtime::abi::DEFAULT_STACK_SIZE) {
            return Err(LinkError::TooLarge(format!(
                "section `{}` ends at {addr:#x}, inside the stack window below {:#x}",
                sec.name,
                trax_runtime::abi::STACK_TOP
            )));
        }
    }
    let (text_end, data_start) = data_start.unwrap_or((addr, align_up(addr, PAGE)));
    let mem_end = addr.max(data_start) as u32;
    let file_end = sections
        .iter()
        .filter(|s| s.is_alloc() && s.key.is_data_segment() && !s.is_nobits())
        .map(|s| s.addr + s.size)
        .max()
        .unwrap_or(data_start as u32);
    Ok(Layout {
        sections,
        place,
        commons,
        abiflags_inputs,
        text: (text_base, text_end as u32),
        data: (data_start as u32, file_end, mem_end),
    })
}

impl Layout {
    /// Index of the output section with `key`.
    pub fn find(&self, key: &OutKey) -> Option<usize> {
        self.sections.iter().position(|s| &s.key == key)
    }

    /// Address of a linker-provided symbol, and the output section it belongs to.
    pub fn linker_symbol(&self, sym: LinkerSym) -> (u32, Option<usize>) {
        let data_start = self.data.0;
        let section = |key: &OutKey| self.find(key).map(|i| (i, &self.sections[i]));
        match sym {
            LinkerSym::InitArrayStart => {
                section(&OutKey::InitArray).map_or((data_start, None), |(i, s)| (s.addr, Some(i)))
            }
            LinkerSym::InitArrayEnd => section(&OutKey::InitArray)
                .map_or((data_start, None), |(i, s)| (s.addr + s.size, Some(i))),
            LinkerSym::BssStart => {
                section(&OutKey::Bss).map_or((self.data.1, None), |(i, s)| (s.addr, Some(i)))
            }
            LinkerSym::End => (self.data.2, None),
        }
    }
}
