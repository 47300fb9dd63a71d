//! The machine's initial memory: one [`MemoryImage`] type, a list of [`Segment`]s with
//! permissions. The assembler produces it (program segments from the executable, the scene
//! header and components), the emulator loads it (and honours the permissions: a store to
//! read-only memory, e.g. program text, and an instruction fetch from non-executable memory
//! fault), and `trax native` writes it to a file for the host runner, which reads it with
//! this same code (the host prelude includes this file by `#[path]`, so it uses `std`
//! only).
//!
//! File format (all integers little-endian):
//!
//! ```text
//! magic      8 bytes  "TRAXIMG2"
//! count      u32      number of segments
//! count × {
//!   addr     u32      first byte's simulated address
//!   size     u32      bytes in memory (the data, then zeros)
//!   perms    u32      Perms bits: 4 read, 2 write, 1 execute (ELF p_flags)
//!   name_len u32      bytes of the name (UTF-8, at most 255)
//!   data_len u32      bytes of initial data (<= size)
//!   name     name_len bytes
//!   data     data_len bytes
//! }
//! ```
//!
//! Segments do not overlap. Memory outside every segment does not exist.

use std::fmt;

/// File magic of a memory image (version 2: segments carry names and permissions).
pub const IMAGE_MAGIC: &[u8; 8] = b"TRAXIMG2";

/// Longest segment name in a file.
pub const MAX_NAME_LEN: usize = 255;

/// Access permissions of a segment, as ELF `p_flags` bits.
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
pub struct Perms(u8);

impl Perms {
    /// No access.
    pub const NONE: Perms = Perms(0);
    /// Execute (`PF_X`).
    pub const X: Perms = Perms(1);
    /// Write (`PF_W`).
    pub const W: Perms = Perms(2);
    /// Read (`PF_R`).
    pub const R: Perms = Perms(4);
    /// Read and write (data, framebuffer).
    pub const RW: Perms = Perms(6);
    /// Read and execute (program text).
    pub const RX: Perms = Perms(5);

    /// From ELF `p_flags` (bits other than R/W/X are ignored).
    pub fn from_elf(p_flags: u32) -> Perms {
        Perms((p_flags & 7) as u8)
    }

    /// As ELF `p_flags` bits.
    pub fn bits(self) -> u32 {
        self.0 as u32
    }

    /// Loads allowed.
    pub fn read(self) -> bool {
        self.0 & 4 != 0
    }

    /// Stores allowed.
    pub fn write(self) -> bool {
        self.0 & 2 != 0
    }

    /// Instruction fetch allowed.
    pub fn exec(self) -> bool {
        self.0 & 1 != 0
    }
}

impl std::ops::BitOr for Perms {
    type Output = Perms;
    fn bitor(self, o: Perms) -> Perms {
        Perms(self.0 | o.0)
    }
}

impl fmt::Display for Perms {
    /// `rwx` with `-` for a missing permission (`r-x`).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let c = |on: bool, ch: char| if on { ch } else { '-' };
        write!(
            f,
            "{}{}{}",
            c(self.read(), 'r'),
            c(self.write(), 'w'),
            c(self.exec(), 'x')
        )
    }
}

impl fmt::Debug for Perms {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "Perms({self})")
    }
}

/// A contiguous range of initial memory. Bytes past `data.len()` up to `size` are zero.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Segment {
    /// What it holds (`text`, `data`, `scene_header`, a component name...).
    pub name: String,
    /// First address.
    pub addr: u32,
    /// Initial bytes.
    pub data: Vec<u8>,
    /// Size in memory (>= `data.len()`).
    pub size: u32,
    /// What may be done to it.
    pub perms: Perms,
}

impl Segment {
    /// A segment whose bytes are all given.
    pub fn new(name: impl Into<String>, addr: u32, data: Vec<u8>, perms: Perms) -> Segment {
        Segment {
            name: name.into(),
            addr,
            size: data.len() as u32,
            data,
            perms,
        }
    }

    /// One past the last address (as u64, so a segment ending at 4 GiB is representable).
    pub fn end(&self) -> u64 {
        self.addr as u64 + self.size as u64
    }

    /// Whether `[addr, addr + len)` lies inside the segment.
    pub fn holds(&self, addr: u32, len: u32) -> bool {
        addr >= self.addr && addr as u64 + len as u64 <= self.end()
    }
}

/// The machine's initial (or final) memory.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct MemoryImage {
    /// Segments (the builders keep them in address order).
    pub segments: Vec<Segment>,
}

/// Why a memory image is unusable or could not be read.
#[derive(Debug)]
pub enum ImageError {
    /// A file could not be read or written.
    Io {
        /// The file.
        path: String,
        /// What the system said.
        source: std::io::Error,
    },
    /// The file does not start with [`IMAGE_MAGIC`].
    BadMagic,
    /// The file ends inside a record.
    Truncated {
        /// Byte offset where it ended.
        offset: usize,
        /// What was being read.
        what: &'static str,
    },
    /// A segment breaks a rule of the format.
    BadSegment {
        /// Its index.
        index: usize,
        /// Its address.
        addr: u32,
        /// The rule.
        problem: &'static str,
    },
    /// Bytes follow the last segment.
    Trailing {
        /// How many.
        len: usize,
    },
}

impl fmt::Display for ImageError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ImageError::Io { path, source } => write!(f, "{path}: {source}"),
            ImageError::BadMagic => write!(
                f,
                "not a trax memory image (bad magic; this trax reads version 2, `TRAXIMG2`)"
            ),
            ImageError::Truncated { offset, what } => {
                write!(
                    f,
                    "memory image truncated at byte {offset} (reading {what})"
                )
            }
            ImageError::BadSegment {
                index,
                addr,
                problem,
            } => write!(f, "segment {index} at {addr:#010x}: {problem}"),
            ImageError::Trailing { len } => {
                write!(f, "{len} trailing bytes after the last segment")
            }
        }
    }
}

impl std::error::Error for ImageError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            ImageError::Io { source, .. } => Some(source),
            _ => None,
        }
    }
}

impl MemoryImage {
    /// Checks each segment (data within its size, inside the 32-bit space, a short name,
    /// known permission bits) and that no two overlap.
    pub fn validate(&self) -> Result<(), ImageError> {
        let mut ranges: Vec<(u64, u64, usize)> = Vec::new();
        for (index, s) in self.segments.iter().enumerate() {
            let bad = |problem| ImageError::BadSegment {
                index,
                addr: s.addr,
                problem,
            };
            if s.data.len() as u64 > s.size as u64 {
                return Err(bad("holds more data than its size"));
            }
            if s.end() > 1 << 32 {
                return Err(bad("extends past the 32-bit address space"));
            }
            if s.name.len() > MAX_NAME_LEN {
                return Err(bad("name longer than 255 bytes"));
            }
            if s.perms.bits() > 7 {
                return Err(bad("unknown permission bits"));
            }
            if s.size > 0 {
                ranges.push((s.addr as u64, s.end(), index));
            }
        }
        ranges.sort();
        for w in ranges.windows(2) {
            if w[1].0 < w[0].1 {
                return Err(ImageError::BadSegment {
                    index: w[1].2,
                    addr: w[1].0 as u32,
                    problem: "overlaps another segment",
                });
            }
        }
        Ok(())
    }

    /// The segment holding all of `[addr, addr + len)`.
    pub fn segment_at(&self, addr: u32, len: u32) -> Option<&Segment> {
        self.segments.iter().find(|s| s.holds(addr, len))
    }

    /// The segment called `name`.
    pub fn segment(&self, name: &str) -> Option<&Segment> {
        self.segments.iter().find(|s| s.name == name)
    }

    /// The `len` initial bytes at `addr` (zeros in a segment's zero tail), if one segment
    /// holds all of them.
    pub fn read(&self, addr: u32, len: u32) -> Option<Vec<u8>> {
        let s = self.segment_at(addr, len)?;
        let off = (addr - s.addr) as usize;
        let mut out = vec![0; len as usize];
        if let Some(d) = s.data.get(off..) {
            let n = d.len().min(len as usize);
            out[..n].copy_from_slice(&d[..n]);
        }
        Some(out)
    }

    /// The little-endian word at `addr`.
    pub fn read_u32(&self, addr: u32) -> Option<u32> {
        let b = self.read(addr, 4)?;
        Some(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
    }

    /// Serialises the image (format in the module docs).
    pub fn to_bytes(&self) -> Vec<u8> {
        let total: usize = self
            .segments
            .iter()
            .map(|s| 20 + s.name.len() + s.data.len())
            .sum();
        let mut out = Vec::with_capacity(12 + total);
        out.extend_from_slice(IMAGE_MAGIC);
        out.extend_from_slice(&(self.segments.len() as u32).to_le_bytes());
        for s in &self.segments {
            for w in [
                s.addr,
                s.size,
                s.perms.bits(),
                s.name.len() as u32,
                s.data.len() as u32,
            ] {
                out.extend_from_slice(&w.to_le_bytes());
            }
            out.extend_from_slice(s.name.as_bytes());
            out.extend_from_slice(&s.data);
        }
        out
    }

    /// Parses and validates an image.
    pub fn parse(data: &[u8]) -> Result<MemoryImage, ImageError> {
        let mut pos = 0usize;
        let mut take = |n: usize, what: &'static str| -> Result<&[u8], ImageError> {
            let end = pos.checked_add(n).filter(|&e| e <= data.len());
            let end = end.ok_or(ImageError::Truncated { offset: pos, what })?;
            let s = &data[pos..end];
            pos = end;
            Ok(s)
        };
        if take(8, "magic")? != IMAGE_MAGIC {
            return Err(ImageError::BadMagic);
        }
        let word = |b: &[u8]| u32::from_le_bytes([b[0], b[1], b[2], b[3]]);
        let count = word(take(4, "segment count")?);
        let mut segments = Vec::new();
        for index in 0..count as usize {
            let addr = word(take(4, "segment address")?);
            let size = word(take(4, "segment size")?);
            let perms = word(take(4, "segment permissions")?);
            let name_len = word(take(4, "segment name length")?) as usize;
            let data_len = word(take(4, "segment data length")?) as usize;
            let bad = |problem| ImageError::BadSegment {
                index,
                addr,
                problem,
            };
            if perms > 7 {
                return Err(bad("unknown permission bits"));
            }
            if name_len > MAX_NAME_LEN {
                return Err(bad("name longer than 255 bytes"));
            }
            if data_len as u64 > size as u64 {
                return Err(bad("holds more data than its size"));
            }
            let name = std::str::from_utf8(take(name_len, "segment name")?)
                .map_err(|_| bad("name is not UTF-8"))?
                .to_string();
            let bytes = take(data_len, "segment data")?.to_vec();
            segments.push(Segment {
                name,
                addr,
                data: bytes,
                size,
                perms: Perms(perms as u8),
            });
        }
        if pos != data.len() {
            return Err(ImageError::Trailing {
                len: data.len() - pos,
            });
        }
        let image = MemoryImage { segments };
        image.validate()?;
        Ok(image)
    }

    /// Reads and parses an image file.
    pub fn read_file(path: &std::path::Path) -> Result<MemoryImage, ImageError> {
        let data = std::fs::read(path).map_err(|source| ImageError::Io {
            path: path.display().to_string(),
            source,
        })?;
        MemoryImage::parse(&data)
    }

    /// Writes the image to a file.
    pub fn write_file(&self, path: &std::path::Path) -> Result<(), ImageError> {
        std::fs::write(path, self.to_bytes()).map_err(|source| ImageError::Io {
            path: path.display().to_string(),
            source,
        })
    }
}
