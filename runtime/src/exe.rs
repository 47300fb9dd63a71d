//! Reading a linked TRaX executable (ELF32 little-endian MIPS, `ET_EXEC`): its loadable
//! segments as memory-image [`Segment`]s with their permissions, entry, the range of its
//! executable sections, its symbols and the scene components it references. The one reader
//! of executables: the image builder, the emulator and the linker's tests use it.
//!
//! Everything is checked before anything is sized from the file: a corrupt section header
//! must not make a loader predecode gigabytes of nothing.

use object::{
    Object, ObjectKind, ObjectSection, ObjectSegment, ObjectSymbol, SectionFlags, SegmentFlags,
    SymbolKind, SymbolSection,
};

use crate::abi;
use crate::image::{Perms, Segment};

/// The global symbols an ELF object or executable of any target defines (for the
/// entry-point check of C and C++ objects, the machine's and the host's alike); empty if
/// `data` is not an ELF file.
pub fn defined_global_symbols(data: &[u8]) -> Vec<String> {
    let Ok(file) = object::File::parse(data) else {
        return Vec::new();
    };
    file.symbols()
        .filter(|s| !s.is_undefined() && s.is_global())
        .filter_map(|s| s.name().ok().map(str::to_string))
        .collect()
}

/// Why an executable is unusable. Every message names the file.
#[derive(Debug, thiserror::Error)]
pub enum ExeError {
    /// The file is not a parsable ELF.
    #[error("{path}: not a valid ELF file: {msg}")]
    Parse { path: String, msg: String },
    /// Wrong machine, class, byte order or file kind.
    #[error("{path}: not a 32-bit little-endian MIPS executable ({what})")]
    WrongTarget { path: String, what: String },
    /// No executable section.
    #[error("{path}: no executable (.text) section")]
    NoText { path: String },
    /// A loadable segment is malformed.
    #[error("{path}: segment at {addr:#010x}: {msg}")]
    Segment {
        path: String,
        addr: u64,
        msg: String,
    },
    /// An executable section is not backed by the file or not inside a loadable segment.
    #[error("{path}: section `{name}` at {addr:#x} (+{size:#x} bytes): {msg}")]
    Section {
        path: String,
        name: String,
        addr: u64,
        size: u64,
        msg: String,
    },
    /// A `__trax_scene_*` symbol names no header field.
    #[error("{path}: symbol `{symbol}` names no scene header field (see trax_runtime::abi::SceneHeader)")]
    UnknownSceneField { path: String, symbol: String },
    /// A `__trax_scene_*` symbol has the wrong address.
    #[error(
        "{path}: symbol `{symbol}` is at {found:#x}, but the header field is at {expected:#x}"
    )]
    SceneSymbolMismatch {
        path: String,
        symbol: String,
        found: u64,
        expected: u64,
    },
}

/// A symbol of the executable's `.symtab` (defined, named, not a file or section symbol).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ExeSymbol {
    /// Name.
    pub name: String,
    /// Address (or absolute value).
    pub addr: u32,
    /// Size in bytes (0 if unknown).
    pub size: u32,
    /// A function (`STT_FUNC`).
    pub is_function: bool,
    /// Global or weak binding.
    pub is_global: bool,
    /// Absolute (`SHN_ABS`; scene header symbols are).
    pub is_absolute: bool,
}

/// A linked executable, as the machine loads it.
#[derive(Clone, Debug)]
pub struct Executable {
    /// Entry point (`__trax_start`).
    pub entry: u32,
    /// ELF `e_flags`.
    pub e_flags: u32,
    /// `PT_LOAD` segments in file order, named `text` (executable), `data` (writable) or
    /// `rodata`, with the segment's permissions.
    pub segments: Vec<Segment>,
    /// Start of the executable sections.
    pub text_start: u32,
    /// End of the executable sections.
    pub text_end: u32,
    /// Symbols in table order.
    pub symbols: Vec<ExeSymbol>,
    /// Function symbols with a non-zero address, sorted by address, one per address (the
    /// largest).
    pub functions: Vec<ExeSymbol>,
    /// Header fields named by `__trax_scene_<field>` symbols (checked against
    /// [`abi::SceneHeader`]), sorted, deduplicated.
    pub referenced: Vec<String>,
}

impl Executable {
    /// Parses and checks an executable; `path` names the file in errors.
    pub fn parse(path: &str, data: &[u8]) -> Result<Executable, ExeError> {
        let file = object::File::parse(data).map_err(|e| ExeError::Parse {
            path: path.into(),
            msg: e.to_string(),
        })?;
        let wrong = |what: String| ExeError::WrongTarget {
            path: path.into(),
            what,
        };
        if file.format() != object::BinaryFormat::Elf {
            return Err(wrong(format!("format {:?}", file.format())));
        }
        if file.architecture() != object::Architecture::Mips {
            return Err(wrong(format!("architecture {:?}", file.architecture())));
        }
        if file.is_64() {
            return Err(wrong("64-bit".into()));
        }
        if !file.is_little_endian() {
            return Err(wrong("big-endian".into()));
        }
        if file.kind() != ObjectKind::Executable {
            return Err(wrong(format!(
                "file kind is {:?}, not an executable (was it linked?)",
                file.kind()
            )));
        }
        let segments = segments(path, &file)?;
        let (text_start, text_end) = text_range(path, &file, &segments, data.len())?;
        let mut symbols = Vec::new();
        let mut referenced = Vec::new();
        for sym in file.symbols() {
            let Ok(name) = sym.name() else { continue };
            if let Some(field) = name.strip_prefix(abi::SCENE_SYMBOL_PREFIX) {
                check_scene_symbol(path, name, field, &sym)?;
                referenced.push(field.to_string());
            }
            if sym.is_undefined()
                || name.is_empty()
                || matches!(sym.kind(), SymbolKind::File | SymbolKind::Section)
            {
                continue;
            }
            symbols.push(ExeSymbol {
                name: name.to_string(),
                addr: sym.address() as u32,
                size: sym.size() as u32,
                is_function: sym.kind() == SymbolKind::Text,
                is_global: !sym.is_local(),
                is_absolute: sym.section() == SymbolSection::Absolute,
            });
        }
        referenced.sort();
        referenced.dedup();
        let mut functions: Vec<ExeSymbol> = symbols
            .iter()
            .filter(|s| s.is_function && s.addr != 0)
            .cloned()
            .collect();
        functions.sort_by_key(|s| (s.addr, std::cmp::Reverse(s.size)));
        functions.dedup_by_key(|s| s.addr);
        let e_flags = match file.flags() {
            object::FileFlags::Elf { e_flags, .. } => e_flags.0,
            _ => 0,
        };
        Ok(Executable {
            entry: file.entry() as u32,
            e_flags,
            segments,
            text_start,
            text_end,
            symbols,
            functions,
            referenced,
        })
    }

    /// The symbol named `name` (a global one if there are several).
    pub fn symbol(&self, name: &str) -> Option<&ExeSymbol> {
        self.symbols
            .iter()
            .filter(|s| s.name == name)
            .max_by_key(|s| s.is_global)
    }

    /// The function containing `addr`, and the offset into it.
    pub fn symbol_at(&self, addr: u32) -> Option<(&ExeSymbol, u32)> {
        let i = self.functions.partition_point(|s| s.addr <= addr);
        let s = self.functions.get(i.checked_sub(1)?)?;
        let off = addr - s.addr;
        (s.size == 0 || off < s.size).then_some((s, off))
    }
}

/// The `PT_LOAD` segments, checked: inside the 32-bit space, file bytes within the memory
/// size and inside the file.
fn segments(path: &str, file: &object::File) -> Result<Vec<Segment>, ExeError> {
    let mut out = Vec::new();
    for seg in file.segments() {
        let (addr, size) = (seg.address(), seg.size());
        let bad = |msg: String| ExeError::Segment {
            path: path.into(),
            addr,
            msg,
        };
        let data = seg.data().map_err(|e| bad(format!("{e}")))?;
        if size == 0 && data.is_empty() {
            continue;
        }
        if (data.len() as u64) > size {
            return Err(bad(format!(
                "memory size {size} is below file size {}",
                data.len()
            )));
        }
        if addr + size > 1 << 32 {
            return Err(bad(format!("{size} bytes do not fit in 32 bits")));
        }
        let p_flags = match seg.flags() {
            SegmentFlags::Elf { p_flags, .. } => p_flags.0,
            _ => 0,
        };
        let perms = Perms::from_elf(p_flags);
        let name = if perms.exec() {
            "text"
        } else if perms.write() {
            "data"
        } else {
            "rodata"
        };
        out.push(Segment {
            name: name.into(),
            addr: addr as u32,
            data: data.to_vec(),
            size: size as u32,
            perms,
        });
    }
    Ok(out)
}

/// `[start, end)` of the executable sections, each backed by the file and inside a loadable
/// segment, spanning no more than the file (the gaps are predecoded too).
fn text_range(
    path: &str,
    file: &object::File,
    segments: &[Segment],
    file_len: usize,
) -> Result<(u32, u32), ExeError> {
    let mut start = u32::MAX;
    let mut end = 0u32;
    let mut bytes = 0u64;
    for s in file.sections() {
        let exec = match s.flags() {
            SectionFlags::Elf { sh_flags, .. } => sh_flags.0 & object::elf::SHF_EXECINSTR.0 != 0,
            _ => false,
        };
        if !(exec && s.size() > 0 && s.address() != 0) {
            continue;
        }
        let (addr, size) = (s.address(), s.size());
        let bad = |msg: String| ExeError::Section {
            path: path.into(),
            name: s.name().unwrap_or("?").to_string(),
            addr,
            size,
            msg,
        };
        match s.data() {
            Ok(d) if d.len() as u64 == size => {}
            Ok(_) => return Err(bad("has no contents in the file".into())),
            Err(e) => return Err(bad(format!("contents lie outside the file ({e})"))),
        }
        let s_end = addr + size;
        if !segments
            .iter()
            .any(|g| addr >= g.addr as u64 && s_end <= g.end())
        {
            return Err(bad("is not inside any loadable segment".into()));
        }
        start = start.min(addr as u32);
        end = end.max(s_end as u32);
        bytes += size;
    }
    if start < end && (end - start) as u64 > bytes.max(file_len as u64) {
        return Err(ExeError::Section {
            path: path.into(),
            name: "(executable sections)".into(),
            addr: start as u64,
            size: (end - start) as u64,
            msg: format!(
                "span more than the file's {file_len} bytes (the gaps would be predecoded)"
            ),
        });
    }
    if start >= end {
        return Err(ExeError::NoText { path: path.into() });
    }
    Ok((start, end))
}

/// A `__trax_scene_<field>` symbol must name a header field and, when defined, sit at it.
fn check_scene_symbol(
    path: &str,
    name: &str,
    field: &str,
    sym: &object::Symbol,
) -> Result<(), ExeError> {
    let Some(&(_, off)) = abi::scene_header_fields().iter().find(|(f, _)| *f == field) else {
        return Err(ExeError::UnknownSceneField {
            path: path.into(),
            symbol: name.into(),
        });
    };
    let expected = abi::SCENE_HEADER_ADDR as u64 + off as u64;
    if !sym.is_undefined() && sym.address() != expected {
        return Err(ExeError::SceneSymbolMismatch {
            path: path.into(),
            symbol: name.into(),
            found: sym.address(),
            expected,
        });
    }
    Ok(())
}
