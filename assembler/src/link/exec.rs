//! Reading a linked executable back: entry, loadable segments and symbols, for the memory
//! image builder and the emulator.

use object::elf::{self, FileHeader32};
use object::read::elf::{FileHeader, ProgramHeader, Sym};
use object::LittleEndian;

use super::{LinkError, SCENE_SYMBOL_PREFIX};

/// A loadable segment (`PT_LOAD`).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Segment {
    /// Load address.
    pub vaddr: u32,
    /// Size in memory; bytes past `data.len()` are zero (bss).
    pub mem_size: u32,
    /// File contents.
    pub data: Vec<u8>,
    /// `PF_R`.
    pub read: bool,
    /// `PF_W`.
    pub write: bool,
    /// `PF_X`.
    pub execute: bool,
}

/// A symbol of the executable's `.symtab`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ExecSymbol {
    /// Name.
    pub name: String,
    /// Address (or absolute value).
    pub addr: u32,
    /// Size in bytes (0 if unknown).
    pub size: u32,
    /// `STT_FUNC`.
    pub is_function: bool,
    /// Global or weak binding.
    pub is_global: bool,
    /// `SHN_ABS` (scene header symbols are absolute).
    pub is_absolute: bool,
}

/// A MIPS ELF32 executable, as loaded.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Executable {
    /// Entry address.
    pub entry: u32,
    /// ELF `e_flags`.
    pub e_flags: u32,
    /// `PT_LOAD` segments in file order.
    pub segments: Vec<Segment>,
    /// Named, defined symbols of `.symtab`.
    pub symbols: Vec<ExecSymbol>,
}

impl Executable {
    /// The symbol named `name` (globals first).
    pub fn symbol(&self, name: &str) -> Option<&ExecSymbol> {
        self.symbols
            .iter()
            .filter(|s| s.name == name)
            .max_by_key(|s| s.is_global)
    }

    /// Scene header fields the program references (absolute `__trax_scene_<field>` globals).
    pub fn scene_components(&self) -> Vec<&str> {
        self.symbols
            .iter()
            .filter(|s| s.is_global && s.is_absolute)
            .filter_map(|s| s.name.strip_prefix(SCENE_SYMBOL_PREFIX))
            .collect()
    }
}

/// Reads an ELF32 little-endian MIPS executable; `name` is used in errors.
pub fn read_executable(name: &str, bytes: &[u8]) -> Result<Executable, LinkError> {
    let bad = |detail: String| LinkError::Malformed {
        file: name.to_string(),
        detail,
    };
    let header = FileHeader32::<LittleEndian>::parse(bytes)
        .map_err(|e| bad(format!("not a 32-bit little-endian ELF file ({e})")))?;
    let endian = header.endian().map_err(|e| bad(e.to_string()))?;
    if header.e_machine(endian) != elf::EM_MIPS {
        return Err(bad("not a MIPS ELF file".into()));
    }
    if header.e_type(endian) != elf::ET_EXEC {
        return Err(bad("not an executable (ET_EXEC); link it first".into()));
    }
    let mut segments = Vec::new();
    for ph in header
        .program_headers(endian, bytes)
        .map_err(|e| bad(e.to_string()))?
    {
        if ph.p_type(endian) != elf::PT_LOAD {
            continue;
        }
        let data = ph
            .data(endian, bytes)
            .map_err(|_| bad("segment lies outside the file".into()))?
            .to_vec();
        let mem_size = ph.p_memsz(endian);
        if (mem_size as usize) < data.len() {
            return Err(bad(format!(
                "segment at {:#x}: memory size {mem_size} is below file size {}",
                ph.p_vaddr(endian),
                data.len()
            )));
        }
        let flags = ph.p_flags(endian).0;
        segments.push(Segment {
            vaddr: ph.p_vaddr(endian),
            mem_size,
            data,
            read: flags & elf::PF_R.0 != 0,
            write: flags & elf::PF_W.0 != 0,
            execute: flags & elf::PF_X.0 != 0,
        });
    }
    let sections = header
        .sections(endian, bytes)
        .map_err(|e| bad(e.to_string()))?;
    let symtab = sections
        .symbols(endian, bytes, elf::SHT_SYMTAB)
        .map_err(|e| bad(e.to_string()))?;
    let mut symbols = Vec::new();
    for sym in symtab.iter() {
        let shndx = sym.st_shndx(endian);
        if shndx == elf::SHN_UNDEF
            || sym.st_type() == elf::STT_FILE
            || sym.st_type() == elf::STT_SECTION
        {
            continue;
        }
        let name = symtab
            .symbol_name(endian, sym)
            .map_err(|e| bad(e.to_string()))?;
        if name.is_empty() {
            continue;
        }
        symbols.push(ExecSymbol {
            name: String::from_utf8_lossy(name).into_owned(),
            addr: sym.st_value(endian),
            size: sym.st_size(endian),
            is_function: sym.st_type() == elf::STT_FUNC,
            is_global: sym.st_bind() != elf::STB_LOCAL,
            is_absolute: shndx == elf::SHN_ABS,
        });
    }
    Ok(Executable {
        entry: header.e_entry(endian),
        e_flags: header.e_flags(endian).0,
        segments,
        symbols,
    })
}
