//! The flat 32-bit address space: chip-wide global memory built from segments, the null
//! guard, and each thread's private local store (its stack window below `STACK_TOP`).
//!
//! Global memory is built from a memory image's segments ([`Segment`], the runtime's one
//! image type) and honours their permissions: a load needs `r`, a store `w` (a store to
//! program text faults), an instruction fetch `x` (the predecoded text must lie in
//! executable segments, and code is never fetched from data or the stack).
//!
//! Global memory is one `Vec<u8>` from address 0 to the end of the highest segment, plus
//! a page table of permissions (4 KiB pages): the common access path is one bounds check,
//! one permission byte and one unaligned load. Bounds are exact to the byte: a page that a
//! segment covers only in part (its first or last page, or one shared by two segments) is
//! marked *partial*, and accesses there are checked against the segments themselves on a
//! slow path, so an access just past the end of a segment (e.g. the framebuffer) faults
//! even though it lies in the same page. Bytes outside every segment are unmapped; the
//! null guard `[0, NULL_GUARD_END)` is never mapped.
//!
//! Misaligned loads and stores (a `lw` at an address not a multiple of 4, etc.) are
//! performed, as MIPS32r6 allows and as LLVM's r6 backend assumes: it copies byte arrays
//! and packed fields with `lw`/`sw` at any address, with no option to stop it. Each byte is
//! checked like a one-byte access, and a store writes nothing unless every byte may be
//! written. Only `ll`/`sc` need alignment ([`Memory::misaligned`], an Address Error on
//! r6). The timing model charges a misaligned access that crosses a cache line as an
//! access to its first line.

use trax_runtime::abi;

/// Page size of the permission map.
pub const PAGE_SHIFT: u32 = 12;

/// Page permission bits (the low byte of a page's entry): one region covers the whole
/// page and is readable (`PERM_R`) and/or writable (`PERM_W`); one region covers part of
/// the page, readable (`PERM_PART`) and/or writable (`PERM_PART_W`), the mapped offsets
/// `[lo, hi]` inclusive packed above the permission byte (see [`page_entry`]); or several
/// regions share the page (`PERM_MULTI`: checked against the region list). Execute
/// permission is checked on the (cold) fetch path only, against the region list.
const PERM_NONE: u32 = 0;
const PERM_R: u32 = 1;
const PERM_W: u32 = 2;
const PERM_PART: u32 = 4;
const PERM_PART_W: u32 = 8;
const PERM_MULTI: u32 = 16;

/// A partial page's entry: `perm | lo << 8 | hi << 20`, offsets `lo..=hi` mapped.
const fn page_entry(perm: u32, lo: u32, hi: u32) -> u32 {
    perm | lo << 8 | hi << 20
}

/// Highest end address of global memory (it is backed by one host allocation).
pub const MAX_GLOBAL: u32 = 1 << 30;

/// Addresses this far below the stack window are reported as stack overflow.
pub const STACK_GUARD: u32 = 16 << 20;

pub use trax_runtime::image::{Perms, Segment};

/// Why an access failed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MemFaultKind {
    /// Address in the null guard.
    Null,
    /// Address not a multiple of the access size.
    Misaligned,
    /// Address below the thread's stack window (the stack grew past its local store).
    StackOverflow,
    /// Address not mapped.
    BadAddress,
    /// Store to read-only memory (program text, read-only data, scene data).
    ReadOnly,
    /// Load from memory without read permission.
    NotReadable,
    /// Instruction fetch from memory without execute permission (data, the stack).
    NotExecutable,
}

/// A failed access.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MemFault {
    /// What went wrong.
    pub kind: MemFaultKind,
    /// The effective address.
    pub addr: u32,
    /// Access size in bytes.
    pub size: u8,
    /// True for stores.
    pub write: bool,
}

/// Errors building memory from segments.
#[derive(Debug, thiserror::Error, PartialEq, Eq)]
pub enum LayoutError {
    /// A segment touches the null guard.
    #[error(
        "segment at {addr:#010x} (+{size:#x} bytes) overlaps the null guard [0, {:#x})",
        abi::NULL_GUARD_END
    )]
    NullGuard { addr: u32, size: u32 },
    /// A segment reaches the stack window or wraps around the address space.
    #[error("segment at {addr:#010x} (+{size:#x} bytes) overlaps the stack window starting at {stack_base:#010x}")]
    StackWindow {
        addr: u32,
        size: u32,
        stack_base: u32,
    },
    /// Global memory would exceed the supported size.
    #[error(
        "segment at {addr:#010x} ends above {MAX_GLOBAL:#x}: global memory is limited to 1 GiB"
    )]
    TooLarge { addr: u32 },
    /// Two segments overlap.
    #[error("segments at {a:#010x} and {b:#010x} overlap")]
    Overlap { a: u32, b: u32 },
    /// The program's executable sections are not all in executable segments.
    #[error("the program text {start:#010x}..{end:#010x} is not all in executable segments")]
    TextNotExecutable { start: u32, end: u32 },
    /// A segment holds more data than its size.
    #[error("segment `{name}` at {addr:#010x} holds more data than its size")]
    DataPastSize { name: String, addr: u32 },
}

/// A mapped address range `[start, end)` (adjacent segments of equal permissions merged).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Region {
    start: u32,
    end: u64,
    perms: Perms,
}

/// A segment as loaded, for reports (`crash`): name, range and permissions.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SegmentInfo {
    /// Segment name.
    pub name: String,
    /// First address.
    pub addr: u32,
    /// Size in bytes.
    pub size: u32,
    /// Permissions.
    pub perms: Perms,
}

/// Chip-wide global memory.
#[derive(Clone, Debug)]
pub struct Memory {
    bytes: Vec<u8>,
    /// One entry per page: permission bits and, for partial pages, the mapped offsets.
    perms: Vec<u32>,
    /// Mapped ranges in address order: the exact bounds behind `PERM_MULTI` pages.
    regions: Vec<Region>,
    /// The image's segments in address order (names for reports).
    segments: Vec<SegmentInfo>,
    /// Lowest address of the per-thread stack window.
    pub stack_base: u32,
    /// Size of each thread's local store.
    pub stack_size: u32,
    /// Stores to global memory so far (through [`Self::write`]): progress the livelock
    /// detector watches.
    pub(crate) stores: u64,
}

impl Memory {
    /// Builds global memory from segments. `stack_size` is each thread's local store size.
    pub fn new(segments: &[Segment], stack_size: u32) -> Result<Memory, LayoutError> {
        let stack_base = abi::STACK_TOP - stack_size;
        let mut end = 0u64;
        let mut sorted: Vec<&Segment> = segments.iter().collect();
        sorted.sort_by_key(|s| s.addr);
        for (i, s) in sorted.iter().enumerate() {
            let size = s.size;
            if s.data.len() as u64 > size as u64 {
                return Err(LayoutError::DataPastSize {
                    name: s.name.clone(),
                    addr: s.addr,
                });
            }
            let e = s.end();
            if s.addr < abi::NULL_GUARD_END {
                return Err(LayoutError::NullGuard { addr: s.addr, size });
            }
            if e > stack_base as u64 - STACK_GUARD as u64 {
                return Err(LayoutError::StackWindow {
                    addr: s.addr,
                    size,
                    stack_base,
                });
            }
            if i > 0 && sorted[i - 1].end() > s.addr as u64 {
                return Err(LayoutError::Overlap {
                    a: sorted[i - 1].addr,
                    b: s.addr,
                });
            }
            if e > MAX_GLOBAL as u64 {
                return Err(LayoutError::TooLarge { addr: s.addr });
            }
            end = end.max(e);
        }
        let pages = end.div_ceil(1 << PAGE_SHIFT) as usize;
        let mut bytes = vec![0u8; pages << PAGE_SHIFT];
        let mut regions: Vec<Region> = Vec::new();
        for s in &sorted {
            let a = s.addr as usize;
            bytes[a..a + s.data.len()].copy_from_slice(&s.data);
            if s.size == 0 {
                continue;
            }
            let r = Region {
                start: s.addr,
                end: s.end(),
                perms: s.perms,
            };
            match regions.last_mut() {
                Some(last) if last.end == r.start as u64 && last.perms == r.perms => {
                    last.end = r.end
                }
                _ => regions.push(r),
            }
        }
        // A page is fast-path mapped only when one region covers all of it.
        let mut perms = vec![PERM_NONE; pages];
        let mut touched = vec![false; pages];
        for r in &regions {
            let (start, end) = (r.start as u64, r.end);
            let (read, write) = (r.perms.read(), r.perms.write());
            let (p0, p1) = (start >> PAGE_SHIFT, end.div_ceil(1 << PAGE_SHIFT));
            for p in p0..p1 {
                let (lo, hi) = (p << PAGE_SHIFT, (p + 1) << PAGE_SHIFT);
                let slot = &mut perms[p as usize];
                *slot = if touched[p as usize] {
                    PERM_MULTI
                } else if start <= lo && hi <= end {
                    (if read { PERM_R } else { 0 }) | if write { PERM_W } else { 0 }
                } else {
                    let (a, b) = (start.max(lo) - lo, end.min(hi) - lo - 1);
                    let perm =
                        (if read { PERM_PART } else { 0 }) | if write { PERM_PART_W } else { 0 };
                    page_entry(perm, a as u32, b as u32)
                };
                touched[p as usize] = true;
            }
        }
        let segments = sorted
            .iter()
            .map(|s| SegmentInfo {
                name: s.name.clone(),
                addr: s.addr,
                size: s.size,
                perms: s.perms,
            })
            .collect();
        Ok(Memory {
            bytes,
            perms,
            regions,
            segments,
            stack_base,
            stack_size,
            stores: 0,
        })
    }

    /// Whether the `n` bytes at `a` (not crossing a page) lie inside the mapped part of a
    /// `PERM_PART` page whose entry is `e`.
    #[inline(always)]
    fn in_part(e: u32, a: usize, n: usize) -> bool {
        let off = (a & ((1 << PAGE_SHIFT) - 1)) as u32;
        let (lo, hi) = ((e >> 8) & 0xfff, e >> 20);
        off >= lo && off + (n as u32 - 1) <= hi
    }

    /// Whether `[addr, addr + n)` on a page shared by several regions is mapped (and writable, for `write`).
    #[inline(never)]
    fn partial_ok(&self, addr: u32, n: u32, write: bool) -> bool {
        self.region(addr, n).is_some_and(|r| {
            if write {
                r.perms.write()
            } else {
                r.perms.read()
            }
        })
    }

    /// The mapped region holding all of `[addr, addr + n)`, if any.
    fn region(&self, addr: u32, n: u32) -> Option<&Region> {
        let i = self.regions.partition_point(|r| r.start <= addr);
        let r = self.regions.get(i.checked_sub(1)?)?;
        (addr as u64 + n as u64 <= r.end).then_some(r)
    }

    /// One past the highest global address.
    pub fn global_end(&self) -> u32 {
        self.bytes.len() as u32
    }

    #[cold]
    fn fault(&self, addr: u32, size: u8, write: bool) -> MemFault {
        let kind = if addr < abi::NULL_GUARD_END {
            MemFaultKind::Null
        } else if addr < self.stack_base && addr >= self.stack_base.saturating_sub(STACK_GUARD) {
            MemFaultKind::StackOverflow
        } else if write
            && self
                .region(addr, size as u32)
                .is_some_and(|r| !r.perms.write())
        {
            MemFaultKind::ReadOnly
        } else if !write
            && self
                .region(addr, size as u32)
                .is_some_and(|r| !r.perms.read())
        {
            MemFaultKind::NotReadable
        } else {
            MemFaultKind::BadAddress
        };
        MemFault {
            kind,
            addr,
            size,
            write,
        }
    }

    /// Fetches the instruction word at `addr` outside the predecoded text: allowed only
    /// in executable memory (never from data or the stack).
    #[cold]
    pub fn fetch(&self, local: &[u8], addr: u32) -> Result<[u8; 4], MemFault> {
        if addr & 3 != 0 {
            return Err(self.fault(addr, 4, false));
        }
        let denied = MemFault {
            kind: MemFaultKind::NotExecutable,
            addr,
            size: 4,
            write: false,
        };
        match self.region(addr, 4) {
            Some(r) if r.perms.exec() => {
                let a = addr as usize;
                let mut out = [0u8; 4];
                out.copy_from_slice(&self.bytes[a..a + 4]);
                Ok(out)
            }
            Some(_) => Err(denied),
            // The stack window is mapped but never executable; anything else faults as a
            // load there would.
            None => match self.read::<4>(local, addr) {
                Ok(_) => Err(denied),
                Err(f) => Err(f),
            },
        }
    }

    /// Whether every byte of `[start, end)` is executable.
    pub fn executable(&self, start: u32, end: u32) -> bool {
        let mut at = start as u64;
        while at < end as u64 {
            let i = self.regions.partition_point(|r| r.start as u64 <= at);
            match i.checked_sub(1).map(|i| &self.regions[i]) {
                Some(r) if r.end > at && r.perms.exec() => at = r.end,
                _ => return false,
            }
        }
        true
    }

    /// The loaded segments, in address order.
    pub fn segments(&self) -> &[SegmentInfo] {
        &self.segments
    }

    /// The loaded segment holding `addr`.
    pub fn segment_at(&self, addr: u32) -> Option<&SegmentInfo> {
        let i = self.segments.partition_point(|s| s.addr <= addr);
        let s = self.segments.get(i.checked_sub(1)?)?;
        ((addr as u64) < s.addr as u64 + s.size as u64).then_some(s)
    }

    /// Reads `N` bytes at `addr` from global memory or `local` (any alignment; an aligned
    /// access is the fast path).
    #[inline(always)]
    pub fn read<const N: usize>(&self, local: &[u8], addr: u32) -> Result<[u8; N], MemFault> {
        const { assert!(N.is_power_of_two() && N <= 1 << PAGE_SHIFT) };
        if addr & (N as u32 - 1) != 0 {
            return self.read_misaligned(local, addr);
        }
        let a = addr as usize;
        if a < self.bytes.len() {
            // SAFETY: `a < bytes.len()`; `bytes.len()` is a multiple of the page size and
            // `perms.len()` is the page count, so `a >> PAGE_SHIFT < perms.len()`. `a` is a
            // multiple of N (checked above) and N divides the page size, so `a + N` does
            // not cross the end of `bytes`.
            let perm = unsafe { *self.perms.get_unchecked(a >> PAGE_SHIFT) };
            if perm & PERM_R != 0
                || (perm & PERM_PART != 0 && Self::in_part(perm, a, N))
                || (perm == PERM_MULTI && self.partial_ok(addr, N as u32, false))
            {
                let mut out = [0u8; N];
                out.copy_from_slice(unsafe { self.bytes.get_unchecked(a..a + N) });
                return Ok(out);
            }
        } else {
            let o = addr.wrapping_sub(self.stack_base) as usize;
            if let Some(b) = local.get(o..o + N) {
                let mut out = [0u8; N];
                out.copy_from_slice(b);
                return Ok(out);
            }
        }
        Err(self.fault(addr, N as u8, false))
    }

    /// Writes `N` bytes at `addr` to global memory or `local` (any alignment; an aligned
    /// access is the fast path).
    #[inline(always)]
    pub fn write<const N: usize>(
        &mut self,
        local: &mut [u8],
        addr: u32,
        v: [u8; N],
    ) -> Result<(), MemFault> {
        const { assert!(N.is_power_of_two() && N <= 1 << PAGE_SHIFT) };
        if addr & (N as u32 - 1) != 0 {
            return self.write_misaligned(local, addr, v);
        }
        let a = addr as usize;
        if a < self.bytes.len() {
            if self.global_writable::<N>(a) {
                // SAFETY: as in `read`: `a..a + N` is in bounds (`global_writable` read the
                // page entry under the same argument).
                unsafe { self.bytes.get_unchecked_mut(a..a + N) }.copy_from_slice(&v);
                self.stores += 1;
                return Ok(());
            }
        } else {
            let o = addr.wrapping_sub(self.stack_base) as usize;
            if let Some(b) = local.get_mut(o..o + N) {
                b.copy_from_slice(&v);
                return Ok(());
            }
        }
        Err(self.fault(addr, N as u8, true))
    }

    /// Like [`Self::write`] for a view that may not change global memory: writes `local`
    /// and returns `Ok(true)`, or returns `Ok(false)` without writing when `addr` is in
    /// global memory (a write there is done later with [`Self::write`], which reports
    /// its faults).
    #[inline(always)]
    pub fn write_local<const N: usize>(
        &self,
        local: &mut [u8],
        addr: u32,
        v: [u8; N],
    ) -> Result<bool, MemFault> {
        if (addr as usize) < self.bytes.len() {
            return Ok(false);
        }
        // Any alignment: the local store is one range (an access running off its end
        // faults below).
        let o = addr.wrapping_sub(self.stack_base) as usize;
        match local.get_mut(o..o + N) {
            Some(b) => {
                b.copy_from_slice(&v);
                Ok(true)
            }
            None => Err(self.fault(addr, N as u8, true)),
        }
    }

    /// Whether the `N`-aligned global address `a < bytes.len()` may be written.
    #[inline(always)]
    fn global_writable<const N: usize>(&self, a: usize) -> bool {
        debug_assert!(a < self.bytes.len() && a.is_multiple_of(N));
        // SAFETY: `a < bytes.len()` (callers check), a multiple of the page size, so the
        // page index `a >> PAGE_SHIFT` is below `perms.len()`, the page count.
        let perm = unsafe { *self.perms.get_unchecked(a >> PAGE_SHIFT) };
        perm & PERM_W != 0
            || (perm & PERM_PART_W != 0 && Self::in_part(perm, a, N))
            || (perm == PERM_MULTI && self.partial_ok(a as u32, N as u32, true))
    }

    /// A misaligned load: byte by byte, each byte checked as a one-byte load. A fault
    /// names the whole access (its address and size) with the first failing byte's kind.
    #[cold]
    #[inline(never)]
    fn read_misaligned<const N: usize>(
        &self,
        local: &[u8],
        addr: u32,
    ) -> Result<[u8; N], MemFault> {
        let mut out = [0u8; N];
        for (i, b) in out.iter_mut().enumerate() {
            match self.read::<1>(local, addr.wrapping_add(i as u32)) {
                Ok([v]) => *b = v,
                Err(f) => {
                    return Err(MemFault {
                        addr,
                        size: N as u8,
                        ..f
                    })
                }
            }
        }
        Ok(out)
    }

    /// A misaligned store: all or nothing. Every byte is checked as a one-byte store
    /// first; then the bytes are written.
    #[cold]
    #[inline(never)]
    fn write_misaligned<const N: usize>(
        &mut self,
        local: &mut [u8],
        addr: u32,
        v: [u8; N],
    ) -> Result<(), MemFault> {
        for i in 0..N as u32 {
            let b = addr.wrapping_add(i);
            let ok = if (b as usize) < self.bytes.len() {
                self.global_writable::<1>(b as usize)
            } else {
                (b.wrapping_sub(self.stack_base) as usize) < local.len()
            };
            if !ok {
                let f = self.fault(b, 1, true);
                return Err(MemFault {
                    addr,
                    size: N as u8,
                    ..f
                });
            }
        }
        for (i, b) in v.into_iter().enumerate() {
            self.write::<1>(local, addr.wrapping_add(i as u32), [b])?;
        }
        Ok(())
    }

    /// The Address Error of an access that must be aligned (`ll`/`sc`) at a misaligned
    /// `addr`.
    #[cold]
    pub fn misaligned(&self, addr: u32, size: u8, write: bool) -> MemFault {
        MemFault {
            kind: MemFaultKind::Misaligned,
            addr,
            size,
            write,
        }
    }

    /// Reads a byte string (for prints and abort messages); any byte may be unaligned.
    pub fn read_bytes(&self, local: &[u8], addr: u32, len: u32) -> Result<Vec<u8>, MemFault> {
        let mut out = Vec::with_capacity(len.min(1 << 16) as usize);
        for i in 0..len {
            let a = addr.wrapping_add(i);
            out.push(self.read::<1>(local, a)?[0]);
        }
        Ok(out)
    }

    /// Reads an aligned word of global memory without permission checks (tooling).
    pub fn peek_u32(&self, addr: u32) -> Option<u32> {
        let a = addr as usize;
        let b = self.bytes.get(a..a + 4)?;
        Some(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
    }

    /// Global memory bytes `[addr, addr+len)` if mapped (tooling, e.g. framebuffer read-back).
    pub fn global_slice(&self, addr: u32, len: u32) -> Option<&[u8]> {
        let (a, e) = (addr as usize, addr as usize + len as usize);
        if e > self.bytes.len() {
            return None;
        }
        // Every byte must be mapped; adjacent regions may split the range.
        let mut at = addr as u64;
        while at < e as u64 {
            let i = self.regions.partition_point(|r| r.start as u64 <= at);
            let r = self.regions.get(i.checked_sub(1)?)?;
            if r.end <= at {
                return None;
            }
            at = r.end;
        }
        Some(&self.bytes[a..e])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn mem() -> Memory {
        let segs = vec![
            Segment {
                name: "s".into(),
                addr: 0x10_0000,
                data: vec![1, 2, 3, 4],
                size: 4,
                perms: Perms::R,
            },
            Segment {
                name: "s".into(),
                addr: 0x20_0000,
                data: vec![],
                size: 0x2000,
                perms: Perms::RW,
            },
        ];
        Memory::new(&segs, 4096).unwrap()
    }

    #[test]
    fn classifies_faults() {
        let mut m = mem();
        let mut local = vec![0u8; 4096];
        assert_eq!(m.read::<4>(&local, 0x10_0000).unwrap(), [1, 2, 3, 4]);
        assert_eq!(m.read::<4>(&local, 8).unwrap_err().kind, MemFaultKind::Null);
        // Misaligned: performed inside the segment; running off its end is a bad address
        // naming the whole access.
        assert_eq!(m.read::<2>(&local, 0x10_0001).unwrap(), [2, 3]);
        let f = m.read::<4>(&local, 0x10_0002).unwrap_err();
        assert_eq!(
            (f.kind, f.addr, f.size),
            (MemFaultKind::BadAddress, 0x10_0002, 4)
        );
        assert_eq!(
            m.write::<4>(&mut local, 0x10_0000, [0; 4])
                .unwrap_err()
                .kind,
            MemFaultKind::ReadOnly
        );
        assert_eq!(
            m.read::<4>(&local, 0x15_0000).unwrap_err().kind,
            MemFaultKind::BadAddress
        );
        let below = abi::STACK_TOP - 4096 - 4;
        assert_eq!(
            m.read::<4>(&local, below).unwrap_err().kind,
            MemFaultKind::StackOverflow
        );
        m.write::<4>(&mut local, abi::STACK_TOP - 4, [9, 8, 7, 6])
            .unwrap();
        assert_eq!(local[4092..], [9, 8, 7, 6]);
        m.write::<2>(&mut local, 0x20_1ffe, [5, 5]).unwrap();
        assert_eq!(m.read::<2>(&local, 0x20_1ffe).unwrap(), [5, 5]);
    }

    #[test]
    fn misaligned_accesses_are_byte_exact_and_stores_all_or_nothing() {
        // A read-only page followed directly by a writable one, and the stack.
        let segs = vec![
            Segment {
                name: "ro".into(),
                addr: 0x10_0000,
                data: vec![7; 4096],
                size: 4096,
                perms: Perms::R,
            },
            Segment {
                name: "rw".into(),
                addr: 0x10_1000,
                data: vec![],
                size: 4096,
                perms: Perms::RW,
            },
        ];
        let mut m = Memory::new(&segs, 4096).unwrap();
        let mut local = vec![0u8; 4096];
        // Across the page boundary into the writable page: the store needs every byte.
        let f = m
            .write::<4>(&mut local, 0x10_0ffe, [1, 2, 3, 4])
            .unwrap_err();
        assert_eq!(
            (f.kind, f.addr, f.size),
            (MemFaultKind::ReadOnly, 0x10_0ffe, 4)
        );
        assert_eq!(
            m.read::<2>(&local, 0x10_1000).unwrap(),
            [0, 0],
            "nothing written"
        );
        assert_eq!(m.read::<4>(&local, 0x10_0ffe).unwrap(), [7, 7, 0, 0]);
        // An MSA vector store (16 bytes) across the same boundary: likewise.
        let f = m.write::<16>(&mut local, 0x10_0ff9, [5; 16]).unwrap_err();
        assert_eq!((f.kind, f.size), (MemFaultKind::ReadOnly, 16));
        assert_eq!(
            m.read::<8>(&local, 0x10_1000).unwrap(),
            [0; 8],
            "nothing written"
        );
        // Inside the writable page, every misalignment of every size.
        for (k, a) in (0x10_1001u32..0x10_1008).enumerate() {
            let v = [k as u8, 0x11, 0x22, 0x33, 0x44, 0x55, 0x66, 0x77];
            m.write::<8>(&mut local, a, v).unwrap();
            assert_eq!(m.read::<8>(&local, a).unwrap(), v);
            assert_eq!(
                m.read::<4>(&local, a + 2).unwrap(),
                [0x22, 0x33, 0x44, 0x55]
            );
            assert_eq!(m.read::<2>(&local, a + 5).unwrap(), [0x55, 0x66]);
        }
        // Off the end of the last page: faults, nothing written.
        let f = m.write::<4>(&mut local, 0x10_1ffe, [9; 4]).unwrap_err();
        assert_eq!((f.kind, f.addr), (MemFaultKind::BadAddress, 0x10_1ffe));
        assert_eq!(m.read::<2>(&local, 0x10_1ffe).unwrap(), [0, 0]);
        // The stack: any alignment inside; the top faults.
        let top = abi::STACK_TOP;
        m.write::<4>(&mut local, top - 7, [1, 2, 3, 4]).unwrap();
        assert_eq!(m.read::<4>(&local, top - 7).unwrap(), [1, 2, 3, 4]);
        assert_eq!(local[4089..4093], [1, 2, 3, 4]);
        assert!(m.write_local::<4>(&mut local, top - 3, [0; 4]).is_err());
        assert!(m.read::<4>(&local, top - 2).is_err());
    }

    #[test]
    fn bounds_are_exact_to_the_byte() {
        // A writable segment ending mid-page (like the framebuffer), a read-only and a
        // writable segment sharing one page, and a gap between them.
        let segs = vec![
            Segment {
                name: "s".into(),
                addr: 0x10_0000,
                data: vec![7; 0x10],
                size: 0x10,
                perms: Perms::R,
            },
            Segment {
                name: "s".into(),
                addr: 0x10_0010,
                data: vec![],
                size: 0x30,
                perms: Perms::RW,
            },
            Segment {
                name: "s".into(),
                addr: 0x10_0100,
                data: vec![],
                size: 0x1_2344,
                perms: Perms::RW,
            },
        ];
        let mut m = Memory::new(&segs, 4096).unwrap();
        let mut local = vec![0u8; 4096];
        let end = 0x10_0100 + 0x1_2344;
        m.write::<4>(&mut local, end - 4, [1; 4]).unwrap();
        assert_eq!(m.read::<4>(&local, end - 4).unwrap(), [1; 4]);
        for k in [0, 4, 12 * 300, 0xcb8] {
            let e = m.write::<4>(&mut local, end + k, [1; 4]).unwrap_err();
            assert_eq!(e.kind, MemFaultKind::BadAddress, "store at end + {k:#x}");
            let e = m.read::<4>(&local, end + k).unwrap_err();
            assert_eq!(e.kind, MemFaultKind::BadAddress, "load at end + {k:#x}");
        }
        // The page shared by read-only and writable data keeps both permissions.
        assert_eq!(m.read::<4>(&local, 0x10_000c).unwrap(), [7; 4]);
        let e = m.write::<4>(&mut local, 0x10_000c, [0; 4]).unwrap_err();
        assert_eq!(e.kind, MemFaultKind::ReadOnly);
        m.write::<8>(&mut local, 0x10_0010, [3; 8]).unwrap();
        // The gap between the small segments and the large one is unmapped.
        let e = m.read::<4>(&local, 0x10_0040).unwrap_err();
        assert_eq!(e.kind, MemFaultKind::BadAddress);
        assert_eq!(m.read::<4>(&local, 0x10_00fc).unwrap_err().addr, 0x10_00fc);
        // Tooling sees the same bounds.
        assert!(m.global_slice(0x10_0000, 0x40).is_some());
        assert!(m.global_slice(0x10_0000, 0x44).is_none());
        assert!(m.global_slice(end - 8, 8).is_some());
        assert!(m.global_slice(end - 8, 12).is_none());
    }

    #[test]
    fn rejects_bad_layouts() {
        let s = |addr, n| Segment::new("data", addr, vec![0; n], Perms::RW);
        assert!(matches!(
            Memory::new(&[s(0x100, 4)], 4096),
            Err(LayoutError::NullGuard { .. })
        ));
        assert!(matches!(
            Memory::new(&[s(0x10_0000, 8), s(0x10_0004, 8)], 4096),
            Err(LayoutError::Overlap { .. })
        ));
    }
}
