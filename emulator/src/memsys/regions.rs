//! Cache accesses by memory region: which scene component, or which of the program's data
//! objects, each L1 and L2 access addressed, for the statistics `timing.memory.l1_by_region`
//! and `l2_by_region`.
//!
//! The regions are the scene components of [`SCENE_COMPONENTS`] (the one declaration of
//! the scene layout: the image builder names each component's segment after it), then
//! `scene_header`, `program` (the program's own data, `.rodata`, `.data`, `.bss`, outside
//! the objects named below), `other` (an address in no segment), then one region per data
//! object of the executable (`program:NAME`, a sized non-function symbol in a program
//! segment). Thread stacks live in the local stores and never reach a cache.

use std::sync::Arc;

use trax_runtime::abi::SCENE_COMPONENTS;

/// Number of fixed regions: the scene components, then `scene_header`, `program`, `other`.
pub const FIXED_REGIONS: usize = SCENE_COMPONENTS.len() + 3;
const HEADER: u16 = SCENE_COMPONENTS.len() as u16;
const PROGRAM: u16 = HEADER + 1;
const OTHER: u16 = HEADER + 2;

/// Name of fixed region `i` (`< FIXED_REGIONS`).
fn fixed_name(i: usize) -> &'static str {
    match i as u16 {
        HEADER => "scene_header",
        PROGRAM => "program",
        OTHER => "other",
        _ => SCENE_COMPONENTS[i].name,
    }
}

/// The region of a segment named `name`.
fn region_of_segment(name: &str) -> u16 {
    match SCENE_COMPONENTS.iter().position(|c| c.name == name) {
        Some(i) => i as u16,
        None if name == "scene_header" => HEADER,
        None => PROGRAM,
    }
}

/// Address → region, from the image's segments and the program's data objects.
#[derive(Clone, Debug)]
pub struct RegionMap {
    /// Interval starts, ascending; intervals do not overlap.
    starts: Vec<u32>,
    /// Interval ends (exclusive), by start.
    ends: Vec<u64>,
    /// Region id, by start.
    ids: Vec<u16>,
    /// Region names, by id.
    names: Vec<String>,
    /// Per 4 KiB page below the last interval's end: the region of every interval in it
    /// (`other` if none is), or [`MIXED`] when they differ (then the intervals decide).
    /// The unmapped bytes of a page are counted as its mapped bytes' region: no access
    /// reaches a cache there (it faults). Shared by the TMs' copies.
    pages: Arc<[u16]>,
}

/// A page of [`RegionMap::pages`] that the intervals decide.
const MIXED: u16 = u16::MAX;
const PAGE_SHIFT: u32 = 12;

impl Default for RegionMap {
    /// No segments: every address is `other`.
    fn default() -> Self {
        RegionMap::new([], [])
    }
}

impl RegionMap {
    /// The map of `segments` and the program's data `objects`, each given as (name, first
    /// address, size in bytes). Segments must not overlap (the loaded memory's never do);
    /// an object outside the program's segments, or overlapping an earlier one, is left out
    /// (its bytes stay `program`).
    pub fn new<'a>(
        segments: impl IntoIterator<Item = (&'a str, u32, u32)>,
        objects: impl IntoIterator<Item = (&'a str, u32, u32)>,
    ) -> RegionMap {
        let end = |addr: u32, size: u32| addr as u64 + size as u64;
        let mut segs: Vec<(u32, u64, u16)> = segments
            .into_iter()
            .map(|(name, addr, size)| (addr, end(addr, size), region_of_segment(name)))
            .collect();
        segs.sort_unstable();
        let mut objs: Vec<(u32, u64, &str)> = objects
            .into_iter()
            .filter(|o| o.2 > 0)
            .map(|(name, addr, size)| (addr, end(addr, size), name))
            .collect();
        objs.sort_unstable();
        let mut names: Vec<String> = (0..FIXED_REGIONS).map(|i| fixed_name(i).into()).collect();
        let mut out: Vec<(u32, u64, u16)> = Vec::new();
        let mut objs = objs.into_iter().peekable();
        for (s, e, id) in segs {
            if id != PROGRAM {
                out.push((s, e, id));
                continue;
            }
            let mut cur = s as u64;
            while let Some(&(os, oe, name)) = objs.peek() {
                if os as u64 >= e {
                    break;
                }
                objs.next();
                if (os as u64) < cur || oe > e {
                    continue;
                }
                if os as u64 > cur {
                    out.push((cur as u32, os as u64, PROGRAM));
                }
                let id = match names
                    .iter()
                    .position(|n| n.strip_prefix("program:") == Some(name))
                {
                    Some(i) => i as u16,
                    None => {
                        names.push(format!("program:{name}"));
                        (names.len() - 1) as u16
                    }
                };
                out.push((os, oe, id));
                cur = oe;
            }
            if cur < e {
                out.push((cur as u32, e, PROGRAM));
            }
        }
        // Region ids are `u16` below `MIXED`: objects past that stay `program`.
        names.truncate(MIXED as usize);
        for o in &mut out {
            if o.2 as usize >= names.len() {
                o.2 = PROGRAM;
            }
        }
        let mut m = RegionMap {
            starts: out.iter().map(|s| s.0).collect(),
            ends: out.iter().map(|s| s.1).collect(),
            ids: out.iter().map(|s| s.2).collect(),
            names,
            pages: Arc::new([]),
        };
        let end = m.ends.last().copied().unwrap_or(0);
        let pages: Vec<u16> = (0..end.div_ceil(1 << PAGE_SHIFT))
            .map(|p| {
                let (first, last) = (p << PAGE_SHIFT, ((p + 1) << PAGE_SHIFT) - 1);
                // The intervals that touch the page: the one holding its first byte, if
                // any, and those starting in it.
                let a = m.starts.partition_point(|&s| s as u64 <= first);
                let b = m.starts.partition_point(|&s| s as u64 <= last);
                let from = match a.checked_sub(1) {
                    Some(j) if m.ends[j] > first => j,
                    _ => a,
                };
                let mut ids = m.ids[from..b].iter();
                match ids.next() {
                    None => OTHER,
                    Some(&id) if ids.all(|&x| x == id) => id,
                    Some(_) => MIXED,
                }
            })
            .collect();
        m.pages = pages.into();
        m
    }

    /// The region holding `addr`, by the intervals.
    fn search(&self, addr: u32) -> u16 {
        let i = self.starts.partition_point(|&s| s <= addr);
        match i.checked_sub(1) {
            Some(j) if (addr as u64) < self.ends[j] => self.ids[j],
            _ => OTHER,
        }
    }

    /// The region holding `addr`.
    #[inline]
    pub fn region_of(&self, addr: u32) -> u16 {
        match self.pages.get((addr >> PAGE_SHIFT) as usize) {
            Some(&id) if id != MIXED => id,
            Some(_) => self.search(addr),
            None => OTHER,
        }
    }

    /// The regions' names, by id.
    pub fn names(&self) -> &[String] {
        &self.names
    }

    /// Number of regions.
    pub fn len(&self) -> usize {
        self.names.len()
    }

    /// Never: the fixed regions are always there.
    pub fn is_empty(&self) -> bool {
        self.names.is_empty()
    }
}

/// One cache's (or a sum of caches') accesses to one region; the fields count as
/// [`super::CacheStats`]'s do.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RegionCounts {
    /// Accepted accesses, loads + stores.
    pub accesses: u64,
    /// Loads that found their line valid.
    pub hits: u64,
    /// Loads that did not (merged ones included).
    pub misses: u64,
    /// Misses merged into an outstanding fill of the same line.
    pub merged: u64,
    /// Stores.
    pub stores: u64,
}

/// Counts by region, indexed by region id.
pub type ByRegion = Vec<RegionCounts>;

/// Adds `b` into `a` (grown to `b`'s length if shorter).
pub fn add(a: &mut ByRegion, b: &[RegionCounts]) {
    if a.len() < b.len() {
        a.resize(b.len(), RegionCounts::default());
    }
    for (x, y) in a.iter_mut().zip(b) {
        x.accesses += y.accesses;
        x.hits += y.hits;
        x.misses += y.misses;
        x.merged += y.merged;
        x.stores += y.stores;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Components by their segment names, the header, program data split around its
    /// objects, and gaps (before, between and after segments) as `other`; an object
    /// overlapping another or outside the program's segments is left out; the page table
    /// agrees with the intervals wherever memory is mapped.
    #[test]
    fn addresses_map_to_their_segments_and_objects() {
        let m = RegionMap::new(
            [
                ("triangles", 0x3000, 0x100),
                ("scene_header", 0x1000, 0x80),
                ("data", 0x2000, 0x40),
                ("camera", 0x4000, 0x40),
                ("bvh_nodes", 0xffff_ff00, 0x100),
            ],
            [
                ("B", 0x2020, 0x10),
                ("A", 0x2004, 0x8),
                ("A2", 0x2008, 0x8),
                ("T", 0x3000, 0x10),
                ("E", 0x2030, 0x0),
            ],
        );
        let id = |name: &str| m.names().iter().position(|n| n == name).unwrap() as u16;
        for (addr, want) in [
            (0x0fff, "other"),
            (0x1000, "scene_header"),
            (0x107f, "scene_header"),
            (0x1080, "other"),
            (0x2000, "program"),
            (0x2004, "program:A"),
            (0x200b, "program:A"),
            (0x200c, "program"),
            (0x201f, "program"),
            (0x2020, "program:B"),
            (0x2030, "program"),
            (0x203f, "program"),
            (0x2040, "other"),
            (0x3000, "triangles"),
            (0x30ff, "triangles"),
            (0x3100, "other"),
            (0x403c, "camera"),
            (0x4040, "other"),
            (0xffff_ffff, "bvh_nodes"),
        ] {
            assert_eq!(m.names()[m.search(addr) as usize], want, "{addr:#x}");
        }
        // By pages: unmapped pages are `other`; a page's unmapped bytes count as its
        // mapped bytes' region (no access reaches a cache there).
        for (addr, want) in [
            (0x0fff, "other"),
            (0x1080, "scene_header"),
            (0x5000, "other"),
            (0x3100, "triangles"),
        ] {
            assert_eq!(m.names()[m.region_of(addr) as usize], want, "{addr:#x}");
        }
        assert_eq!(m.len(), FIXED_REGIONS + 2, "{:?}", m.names());
        assert_eq!(id("program:B"), FIXED_REGIONS as u16 + 1);
        // The page table agrees with the intervals at every page edge and around every
        // interval's bounds.
        let mut probes: Vec<u32> = Vec::new();
        for p in 0..8u32 {
            probes.extend([p << 12, (p << 12).wrapping_sub(1), (p << 12) + 1]);
        }
        for (&s, &e) in m.starts.iter().zip(&m.ends) {
            probes.extend([s, s.wrapping_sub(1), s + 1, (e - 1) as u32, e as u32]);
        }
        for a in probes {
            if m.search(a) != OTHER {
                assert_eq!(m.region_of(a), m.search(a), "{a:#x}");
            }
        }
        assert!(m.pages.contains(&MIXED) && m.pages.len() == 0x10_0000);
        let d = RegionMap::default();
        assert_eq!(d.names()[d.region_of(0x1000) as usize], "other");
        let names: std::collections::BTreeSet<&String> = m.names().iter().collect();
        assert_eq!(names.len(), m.len());
    }
}
