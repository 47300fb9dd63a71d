//! Loading a linked MIPS32r6 executable: loadable segments, text range, entry, symbols.

use object::{Object, ObjectSection, ObjectSegment, ObjectSymbol, SectionFlags, SegmentFlags};

use crate::memory::Segment;

/// Errors reading an executable.
#[derive(Debug, thiserror::Error)]
pub enum ElfError {
    /// The file is not a parsable ELF.
    #[error("{path}: not a valid ELF file: {msg}")]
    Parse { path: String, msg: String },
    /// Wrong machine or class.
    #[error("{path}: not a 32-bit little-endian MIPS executable ({what})")]
    WrongTarget { path: String, what: String },
    /// No executable section.
    #[error("{path}: no executable (.text) section")]
    NoText { path: String },
    /// A segment's file data could not be read.
    #[error("{path}: segment at {addr:#010x}: {msg}")]
    Segment {
        path: String,
        addr: u32,
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
}

/// A function symbol.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Symbol {
    /// Name (as in the symbol table).
    pub name: String,
    /// Address.
    pub addr: u32,
    /// Size in bytes (0 if unknown).
    pub size: u32,
}

/// The parts of an executable the machine needs.
#[derive(Clone, Debug)]
pub struct Executable {
    /// Loadable segments.
    pub segments: Vec<Segment>,
    /// Entry point (`__trax_start`).
    pub entry: u32,
    /// Start of the executable sections.
    pub text_start: u32,
    /// End of the executable sections.
    pub text_end: u32,
    /// Function symbols sorted by address.
    pub symbols: Vec<Symbol>,
}

impl Executable {
    /// Parses an ELF executable; `path` only names the file in errors.
    pub fn parse(path: &str, data: &[u8]) -> Result<Executable, ElfError> {
        let file = object::File::parse(data).map_err(|e| ElfError::Parse {
            path: path.into(),
            msg: e.to_string(),
        })?;
        let wrong = |what: &str| ElfError::WrongTarget {
            path: path.into(),
            what: what.into(),
        };
        if file.architecture() != object::Architecture::Mips {
            return Err(wrong(&format!("architecture {:?}", file.architecture())));
        }
        if file.is_64() {
            return Err(wrong("64-bit"));
        }
        if !file.is_little_endian() {
            return Err(wrong("big-endian"));
        }
        let mut segments = Vec::new();
        for seg in file.segments() {
            let p_flags = match seg.flags() {
                SegmentFlags::Elf { p_flags, .. } => p_flags.0,
                _ => 0,
            };
            let addr = seg.address() as u32;
            let bytes = seg.data().map_err(|e| ElfError::Segment {
                path: path.into(),
                addr,
                msg: e.to_string(),
            })?;
            let mem_size = seg.size() as u32;
            if mem_size == 0 && bytes.is_empty() {
                continue;
            }
            segments.push(Segment {
                addr,
                data: bytes.to_vec(),
                mem_size,
                writable: p_flags & object::elf::PF_W.0 != 0,
            });
        }
        // The executable sections are predecoded word by word, so their sizes are checked
        // against the file and the segments before anything is allocated: a corrupt
        // section header must not make the loader decode gigabytes of nothing.
        let mut text_start = u32::MAX;
        let mut text_end = 0u32;
        let mut text_bytes = 0u64;
        for s in file.sections() {
            let exec = match s.flags() {
                SectionFlags::Elf { sh_flags, .. } => {
                    sh_flags.0 & object::elf::SHF_EXECINSTR.0 != 0
                }
                _ => false,
            };
            if !(exec && s.size() > 0 && s.address() != 0) {
                continue;
            }
            let (addr, size) = (s.address(), s.size());
            let bad = |msg: String| ElfError::Section {
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
            let end = addr + size;
            let inside = segments.iter().any(|g| {
                let g_end = g.addr as u64 + g.mem_size.max(g.data.len() as u32) as u64;
                addr >= g.addr as u64 && end <= g_end
            });
            if !inside {
                return Err(bad("is not inside any loadable segment".into()));
            }
            text_start = text_start.min(addr as u32);
            text_end = text_end.max(end as u32);
            text_bytes += size;
        }
        // Gaps between executable sections are predecoded too; they may not dwarf the file.
        if text_start < text_end
            && (text_end - text_start) as u64 > text_bytes.max(data.len() as u64)
        {
            return Err(ElfError::Section {
                path: path.into(),
                name: "(executable sections)".into(),
                addr: text_start as u64,
                size: (text_end - text_start) as u64,
                msg: format!(
                    "span more than the file's {} bytes (the gaps would be predecoded)",
                    data.len()
                ),
            });
        }
        if text_start >= text_end {
            return Err(ElfError::NoText { path: path.into() });
        }
        let mut symbols: Vec<Symbol> = file
            .symbols()
            .filter(|s| s.kind() == object::SymbolKind::Text && s.address() != 0)
            .filter_map(|s| {
                Some(Symbol {
                    name: s.name().ok()?.to_string(),
                    addr: s.address() as u32,
                    size: s.size() as u32,
                })
            })
            .collect();
        symbols.sort_by_key(|s| (s.addr, std::cmp::Reverse(s.size)));
        symbols.dedup_by_key(|s| s.addr);
        Ok(Executable {
            segments,
            entry: file.entry() as u32,
            text_start,
            text_end,
            symbols,
        })
    }

    /// The function symbol containing `addr`, and the offset into it.
    pub fn symbol_at(&self, addr: u32) -> Option<(&Symbol, u32)> {
        let i = self.symbols.partition_point(|s| s.addr <= addr);
        let s = self.symbols.get(i.checked_sub(1)?)?;
        let off = addr - s.addr;
        (s.size == 0 || off < s.size).then_some((s, off))
    }

    /// The address of a symbol by name.
    pub fn symbol_addr(&self, name: &str) -> Option<u32> {
        self.symbols.iter().find(|s| s.name == name).map(|s| s.addr)
    }
}
