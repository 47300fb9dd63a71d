//! Reading one MIPS32 little-endian ELF relocatable object into the linker's own model.

use object::elf::{self, FileHeader32};
use object::read::elf::{FileHeader, SectionHeader, Sym};
use object::LittleEndian;

use super::LinkError;

/// Where a symbol is defined.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum SymDef {
    /// Undefined (`SHN_UNDEF`).
    Undef,
    /// Absolute value (`SHN_ABS`).
    Abs,
    /// Common block: `value` is the alignment.
    Common,
    /// Defined in the input section with this index.
    Section(usize),
}

/// One symbol-table entry of an input.
#[derive(Clone, Debug)]
pub(crate) struct InSymbol {
    pub name: String,
    pub value: u32,
    pub size: u32,
    pub bind: u8,
    pub kind: u8,
    pub other: u8,
    pub def: SymDef,
}

impl InSymbol {
    pub fn is_local(&self) -> bool {
        self.bind == elf::STB_LOCAL.0
    }
    pub fn is_weak(&self) -> bool {
        self.bind == elf::STB_WEAK.0
    }
}

/// One REL relocation (implicit addend, read from the patched location).
#[derive(Clone, Copy, Debug)]
pub(crate) struct InReloc {
    pub offset: u32,
    pub r_type: u32,
    pub sym: usize,
}

/// One section of an input.
#[derive(Clone, Debug)]
pub(crate) struct InSection {
    pub name: String,
    pub sh_type: u32,
    pub flags: u32,
    pub align: u32,
    pub size: u32,
    /// Contents (empty for `SHT_NOBITS`).
    pub data: Vec<u8>,
    /// Relocations applying to this section, in table order.
    pub relocs: Vec<InReloc>,
    /// Member of a COMDAT group whose signature was already seen: dropped.
    pub discarded: bool,
}

impl InSection {
    pub fn is_alloc(&self) -> bool {
        self.flags & elf::SHF_ALLOC.0 as u32 != 0
    }
}

/// A parsed input object.
#[derive(Clone, Debug)]
pub(crate) struct InObject {
    pub name: String,
    pub e_flags: u32,
    /// Indexed by ELF section index (index 0 is the null section).
    pub sections: Vec<InSection>,
    /// Indexed by ELF symbol index (index 0 is the null symbol).
    pub symbols: Vec<InSymbol>,
    /// COMDAT group signatures with the section indices of their members.
    pub groups: Vec<(String, Vec<usize>)>,
}

fn malformed(file: &str, detail: impl Into<String>) -> LinkError {
    LinkError::Malformed {
        file: file.to_string(),
        detail: detail.into(),
    }
}

/// Parses `bytes` (named `name` in errors) as an ELF32 little-endian MIPS relocatable object.
pub(crate) fn parse(name: &str, bytes: &[u8]) -> Result<InObject, LinkError> {
    let bad = |e: object::read::Error| malformed(name, e.to_string());
    let header = FileHeader32::<LittleEndian>::parse(bytes)
        .map_err(|e| malformed(name, format!("not a 32-bit little-endian ELF file ({e})")))?;
    let endian = header.endian().map_err(bad)?;
    if header.e_machine(endian) != elf::EM_MIPS {
        return Err(malformed(
            name,
            format!(
                "machine is {}, expected MIPS (EM_MIPS = 8)",
                header.e_machine(endian).0
            ),
        ));
    }
    if header.e_type(endian) != elf::ET_REL {
        return Err(malformed(
            name,
            format!(
                "ELF type {} is not a relocatable object (ET_REL); pass .o files",
                header.e_type(endian).0
            ),
        ));
    }
    let e_flags = header.e_flags(endian).0;
    let table = header.sections(endian, bytes).map_err(bad)?;
    let mut sections = Vec::with_capacity(table.len());
    for (index, sh) in table.enumerate() {
        let sec_name = table
            .section_name(endian, sh)
            .map(|n| String::from_utf8_lossy(n).into_owned())
            .map_err(|e| malformed(name, format!("section {}: {e}", index.0)))?;
        let sh_type = sh.sh_type(endian).0;
        let size = sh.sh_size(endian);
        let data = if sh_type == elf::SHT_NOBITS.0 || sh_type == elf::SHT_NULL.0 {
            Vec::new()
        } else {
            sh.data(endian, bytes)
                .map_err(|_| {
                    malformed(name, format!("section `{sec_name}` lies outside the file"))
                })?
                .to_vec()
        };
        let align = sh.sh_addralign(endian).max(1);
        if !align.is_power_of_two() {
            return Err(malformed(
                name,
                format!("section `{sec_name}` alignment {align} is not a power of two"),
            ));
        }
        sections.push(InSection {
            name: sec_name,
            sh_type,
            flags: sh.sh_flags(endian).0 as u32,
            align,
            size,
            data,
            relocs: Vec::new(),
            discarded: false,
        });
    }

    if sections.is_empty() {
        return Err(malformed(name, "the object has no sections"));
    }
    let symtab = table.symbols(endian, bytes, elf::SHT_SYMTAB).map_err(bad)?;
    let mut symbols = Vec::with_capacity(symtab.len());
    for (index, sym) in symtab.enumerate() {
        let sym_name = symtab
            .symbol_name(endian, sym)
            .map(|n| String::from_utf8_lossy(n).into_owned())
            .map_err(|e| malformed(name, format!("symbol {}: {e}", index.0)))?;
        let shndx = sym.st_shndx(endian).0;
        let def = if shndx == elf::SHN_UNDEF.0 {
            SymDef::Undef
        } else if shndx == elf::SHN_ABS.0 {
            SymDef::Abs
        } else if shndx == elf::SHN_COMMON.0 || shndx == elf::SHN_MIPS_ACOMMON.0 {
            SymDef::Common
        } else if shndx == elf::SHN_MIPS_SCOMMON.0 {
            return Err(LinkError::GpRelative {
                file: name.to_string(),
                what: format!("small common symbol `{sym_name}` (SHN_MIPS_SCOMMON)"),
            });
        } else {
            match symtab.symbol_section(endian, sym, index).map_err(bad)? {
                Some(sec) if sec.0 < sections.len() => SymDef::Section(sec.0),
                _ => {
                    return Err(malformed(
                        name,
                        format!("symbol `{sym_name}` has invalid section index {shndx}"),
                    ))
                }
            }
        };
        symbols.push(InSymbol {
            name: sym_name,
            value: sym.st_value(endian),
            size: sym.st_size(endian),
            bind: sym.st_bind().0,
            kind: sym.st_type().0,
            other: sym.st_other().0,
            def,
        });
    }
    if symbols.is_empty() {
        symbols.push(InSymbol {
            name: String::new(),
            value: 0,
            size: 0,
            bind: 0,
            kind: 0,
            other: 0,
            def: SymDef::Undef,
        });
    }

    let mut groups = Vec::new();
    for (index, sh) in table.enumerate() {
        let sh_type = sh.sh_type(endian);
        if sh_type == elf::SHT_RELA {
            return Err(malformed(
                name,
                format!(
                    "section `{}` holds RELA relocations; o32 objects use REL",
                    sections[index.0].name
                ),
            ));
        }
        if sh_type == elf::SHT_GROUP {
            let words: &[object::U32<LittleEndian>] = sh
                .data_as_array(endian, bytes)
                .map_err(|_| malformed(name, "group section lies outside the file"))?;
            let sig = symbols
                .get(sh.sh_info(endian) as usize)
                .map(|s| s.name.clone())
                .ok_or_else(|| malformed(name, "group signature symbol out of range"))?;
            if words.first().map(|w| w.get(endian)) != Some(elf::GRP_COMDAT.0) {
                continue;
            }
            let mut members = Vec::new();
            for w in &words[1..] {
                let m = w.get(endian) as usize;
                if m >= sections.len() {
                    return Err(malformed(name, format!("group `{sig}` names section {m}")));
                }
                members.push(m);
            }
            groups.push((sig, members));
            continue;
        }
        let Some((rels, _link)) = sh.rel(endian, bytes).map_err(bad)? else {
            continue;
        };
        let target = sh.sh_info(endian) as usize;
        let target_size = match sections.get(target) {
            Some(t) if target != 0 => t.data.len(),
            _ => {
                return Err(malformed(
                    name,
                    format!(
                        "relocation section `{}` applies to invalid section {target}",
                        sections[index.0].name
                    ),
                ))
            }
        };
        let mut relocs = Vec::with_capacity(rels.len());
        for rel in rels {
            let offset = rel.r_offset.get(endian);
            let sym = rel.r_sym(endian) as usize;
            if sym >= symbols.len() {
                return Err(malformed(
                    name,
                    format!(
                        "relocation at {offset:#x} in `{}` names symbol {sym} of {}",
                        sections[target].name,
                        symbols.len()
                    ),
                ));
            }
            // Every relocation we apply patches a 4-byte word.
            if offset as usize + 4 > target_size {
                return Err(malformed(
                    name,
                    format!(
                        "relocation at {offset:#x} lies outside section `{}` ({target_size} bytes)",
                        sections[target].name
                    ),
                ));
            }
            relocs.push(InReloc {
                offset,
                r_type: rel.r_type(endian).0,
                sym,
            });
        }
        sections[target].relocs.extend(relocs);
    }
    Ok(InObject {
        name: name.to_string(),
        e_flags,
        sections,
        symbols,
        groups,
    })
}
