//! The ray-buffer sentinel (thesis §7.1.1, beyond the thesis's STRaTA): with
//! `stream_memory.overflow = "spill"` the stream memory overflows into a DRAM spill area
//! instead of faulting.
//!
//! Policy (deterministic, the same in both modes):
//! - After a ray is written, while the rays in SRAM lists plus the rays arriving exceed the
//!   high watermark, the sentinel takes the newest `block_rays` rays (or all, if fewer) of
//!   the buffer with the most rays in its SRAM list (lowest id on ties) and writes them,
//!   packed, to a free block of the spill area (the lowest block never used, else the most
//!   recently freed): contiguous lines, so whole DRAM rows.
//! - After a ray is read, if the rays in lists plus the rays arriving are below the low
//!   watermark and a block fits in the free slots, the sentinel reads back the newest
//!   written block of the buffer with the most rays among those with a block in DRAM.
//! - A read of a buffer whose list is empty but which has rays elsewhere reads its newest
//!   written block back first (on demand), waiting (timing) while a block of it is still
//!   being written or read or no room is free.
//! - A block's rays stay in their buffer throughout: `trax.strsize` and `trax.strsched`
//!   count them, and the order rays come back in is LIFO by block (order within a buffer
//!   is not part of the contract, §3.2.1).
//!
//! Timing ([`StreamMemory::set_timed`]): a spill's rays leave their lists at once but hold
//! their SRAM slots until the DRAM has accepted the lines that carry them; a refill takes
//! its slots at once and its rays join the list when the last one is written. The timing
//! engine takes the transfers ([`StreamMemory::take_transfers`]), runs them through the
//! memory system's DMA engine (`memsys::sentinel`) and reports back
//! ([`StreamMemory::dma_progress`], [`StreamMemory::dma_done`]).

use std::collections::BTreeMap;

use super::{SpillAreaFull, StreamError, StreamMemory};

/// The first DRAM address of the spill area: the upper half of the 32-bit space, where the
/// memory image never lies (it ends below the stack window's top, `abi::STACK_TOP`), so
/// spilled rays share no DRAM row with program data.
pub const SPILL_AREA_BASE: u32 = 0x8000_0000;

/// The sentinel's shape, in rays (from `stream_memory.spill`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SpillGeometry {
    /// Spill when more rays than this are in SRAM lists.
    pub high_rays: u32,
    /// Refill when fewer rays than this are in SRAM lists.
    pub low_rays: u32,
    /// Rays per block (`block_bytes / ray_bytes`).
    pub block_rays: u32,
    /// Bytes per block in DRAM.
    pub block_bytes: u32,
    /// Blocks in the spill area.
    pub area_blocks: u32,
}

impl SpillGeometry {
    /// As one command-line word, `HIGH,LOW,BLOCK_RAYS,BLOCK_BYTES,AREA_BLOCKS` (how
    /// `trax native` hands the chip's sentinel to the host runner).
    pub fn to_arg(self) -> String {
        format!(
            "{},{},{},{},{}",
            self.high_rays, self.low_rays, self.block_rays, self.block_bytes, self.area_blocks
        )
    }

    /// Parses [`SpillGeometry::to_arg`]'s form; `None` if it is not five numbers with
    /// non-empty blocks.
    pub fn from_arg(s: &str) -> Option<SpillGeometry> {
        let v: Vec<u32> = s
            .split(',')
            .map(|x| x.parse().ok())
            .collect::<Option<Vec<u32>>>()?;
        match v[..] {
            [high_rays, low_rays, block_rays, block_bytes, area_blocks]
                if block_rays > 0 && block_bytes > 0 =>
            {
                Some(SpillGeometry {
                    high_rays,
                    low_rays,
                    block_rays,
                    block_bytes,
                    area_blocks,
                })
            }
            _ => None,
        }
    }
}

/// One block transfer for the timing model's DMA engine.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DmaTransfer {
    /// Its id (reported back with its progress).
    pub id: u64,
    /// True for a spill (SRAM to DRAM), false for a refill.
    pub write: bool,
    /// DRAM address of the block's first byte.
    pub addr: u32,
    /// Rays moved.
    pub rays: u32,
    /// Bytes of one ray (rays are packed: `rays x ray_bytes` bytes from `addr`).
    pub ray_bytes: u32,
}

/// The sentinel's counters (the same in both modes).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SpillStats {
    /// Blocks written to DRAM.
    pub spills: u64,
    /// Blocks read back.
    pub refills: u64,
    /// Ray bytes written (`rays x ray_bytes`).
    pub spilled_bytes: u64,
    /// Ray bytes read back.
    pub refilled_bytes: u64,
    /// Most blocks in the spill area at once.
    pub max_blocks: u32,
}

/// A block of one buffer's rays in the spill area.
#[derive(Clone, Debug)]
struct Block {
    /// Its place in the area.
    index: u32,
    /// The rays' words, newest first.
    words: Vec<u32>,
    rays: u32,
    /// Completely written (a refill may start).
    written: bool,
}

/// A transfer in progress (timing mode).
#[derive(Clone, Debug)]
enum Transit {
    /// Spilling: the block's buffer and index, the slots still held (released in order
    /// as the DMA reports rays moved).
    Out {
        buffer: usize,
        index: u32,
        held: Vec<u32>,
        released: u32,
    },
    /// Refilling: the buffer, the area block being read, the slots taken (in the order
    /// the rays join the list).
    In {
        buffer: usize,
        index: u32,
        slots: Vec<u32>,
    },
}

/// The sentinel's state inside [`StreamMemory`].
#[derive(Clone, Debug, Default)]
pub(super) struct SpillState {
    /// Per buffer: its blocks in DRAM, oldest first.
    blocks: Vec<Vec<Block>>,
    /// Area blocks freed (reused last freed first) and never used.
    free_blocks: Vec<u32>,
    next_block: u32,
    blocks_used: u32,
    /// Rays arriving in SRAM (slots taken, not yet in lists), in total and per buffer.
    arriving: u32,
    arriving_for: Vec<u32>,
    /// Transfers run by the timing model (else they complete at once).
    timed: bool,
    next_id: u64,
    transit: BTreeMap<u64, Transit>,
    started: Vec<DmaTransfer>,
    stats: SpillStats,
}

impl StreamMemory {
    /// Whether the timing model carries transfers out (set by the timing engine; a
    /// functional run moves blocks at once).
    pub fn set_timed(&mut self, timed: bool) {
        self.spill.timed = timed;
    }

    /// The transfers started since the last call (timing mode).
    pub fn take_transfers(&mut self) -> Vec<DmaTransfer> {
        std::mem::take(&mut self.spill.started)
    }

    /// Whether a transfer is still in progress.
    pub fn transfers_pending(&self) -> bool {
        !self.spill.transit.is_empty()
    }

    /// The sentinel's counters.
    pub fn spill_stats(&self) -> SpillStats {
        self.spill.stats
    }

    /// SRAM accesses: rays written and read by threads, and rays the sentinel moved out
    /// or in (one access each).
    pub fn sram_accesses(&self) -> u64 {
        let rb = u64::from(self.geom.ray_bytes.max(1));
        let s = &self.spill.stats;
        self.reads + self.writes + (s.spilled_bytes + s.refilled_bytes) / rb
    }

    /// Spill transfer `id` has moved its first `rays` rays out of the SRAM: their slots
    /// are free.
    pub fn dma_progress(&mut self, id: u64, rays: u32) {
        let mut free = Vec::new();
        if let Some(Transit::Out { held, released, .. }) = self.spill.transit.get_mut(&id) {
            let to = rays.min(held.len() as u32);
            free.extend_from_slice(&held[*released as usize..to as usize]);
            *released = (*released).max(to);
        }
        for s in free {
            self.free_slot(s);
        }
    }

    /// Transfer `id` is complete: a spilled block is written (its slots are all free), a
    /// refilled block's rays are in their list.
    pub fn dma_done(&mut self, id: u64) {
        let Some(t) = self.spill.transit.remove(&id) else {
            return;
        };
        match t {
            Transit::Out {
                buffer,
                index,
                held,
                released,
            } => {
                for &s in &held[released as usize..] {
                    self.free_slot(s);
                }
                if let Some(b) = self.spill.blocks[buffer]
                    .iter_mut()
                    .find(|b| b.index == index)
                {
                    b.written = true;
                }
            }
            Transit::In {
                buffer,
                index,
                slots,
            } => {
                for &s in &slots {
                    self.link_slot(buffer, s);
                }
                let n = slots.len() as u32;
                self.spill.arriving -= n;
                self.spill.arriving_for[buffer] -= n;
                self.release_block(index);
            }
        }
    }

    /// After a write: spill blocks while the SRAM lists hold more than the high watermark.
    pub(super) fn spill_over(&mut self) -> Result<(), StreamError> {
        let Some(g) = self.geom.spill else {
            return Ok(());
        };
        while self.resident + self.spill.arriving > g.high_rays {
            // The buffer with the most rays in its list (lowest id on ties).
            let Some(b) = (0..self.listed.len())
                .filter(|&b| self.listed[b] > 0)
                .max_by(|&x, &y| self.listed[x].cmp(&self.listed[y]).then(y.cmp(&x)))
            else {
                break;
            };
            self.spill_block(b, g)?;
        }
        Ok(())
    }

    fn spill_block(&mut self, b: usize, g: SpillGeometry) -> Result<(), StreamError> {
        let index = match self.spill.free_blocks.pop() {
            Some(i) => i,
            None if self.spill.next_block < g.area_blocks => {
                self.spill.next_block += 1;
                self.spill.next_block - 1
            }
            None => {
                return Err(StreamError::SpillAreaFull(SpillAreaFull {
                    stream: b as u32,
                    blocks: g.area_blocks,
                    block_bytes: g.block_bytes,
                }))
            }
        };
        let n = g.block_rays.min(self.listed[b]);
        let w = self.geom.ray_words();
        let mut words = Vec::with_capacity(n as usize * w);
        let mut held = Vec::with_capacity(n as usize);
        for _ in 0..n {
            let slot = self.unlink_slot(b);
            words.extend_from_slice(&self.data[slot as usize * w..][..w]);
            held.push(slot);
        }
        let sp = &mut self.spill;
        if sp.blocks.is_empty() {
            sp.blocks = vec![Vec::new(); self.geom.buffers as usize];
            sp.arriving_for = vec![0; self.geom.buffers as usize];
        }
        sp.blocks[b].push(Block {
            index,
            words,
            rays: n,
            written: !sp.timed,
        });
        sp.blocks_used += 1;
        sp.stats.max_blocks = sp.stats.max_blocks.max(sp.blocks_used);
        sp.stats.spills += 1;
        sp.stats.spilled_bytes += u64::from(n) * u64::from(self.geom.ray_bytes);
        if sp.timed {
            let id = sp.next_id;
            sp.next_id += 1;
            sp.started.push(DmaTransfer {
                id,
                write: true,
                addr: block_addr(index, g),
                rays: n,
                ray_bytes: self.geom.ray_bytes,
            });
            sp.transit.insert(
                id,
                Transit::Out {
                    buffer: b,
                    index,
                    held,
                    released: 0,
                },
            );
        } else {
            for s in held {
                self.free_slot(s);
            }
        }
        Ok(())
    }

    /// Before reading buffer `b`, whose list is empty but which has rays in DRAM or in
    /// transit: true once its list holds rays (a refill done at once), false to wait.
    pub(super) fn refill_for(&mut self, b: usize) -> bool {
        let Some(g) = self.geom.spill else {
            return false;
        };
        if self.spill.arriving_for.get(b).copied().unwrap_or(0) == 0 {
            self.refill_block(b, g);
        }
        self.listed[b] > 0
    }

    /// After a read: refill a block while the SRAM lists hold fewer than the low watermark.
    pub(super) fn refill_under(&mut self) {
        let Some(g) = self.geom.spill else {
            return;
        };
        if self.resident + self.spill.arriving >= g.low_rays {
            return;
        }
        // The buffer with the most rays among those with a written block in DRAM.
        let sp = &self.spill;
        let best = (0..sp.blocks.len())
            .filter(|&b| sp.blocks[b].iter().any(|k| k.written))
            .max_by(|&x, &y| self.counts[x].cmp(&self.counts[y]).then(y.cmp(&x)));
        if let Some(b) = best {
            self.refill_block(b, g);
        }
    }

    /// Starts reading back buffer `b`'s newest written block, if one fits in the free slots.
    fn refill_block(&mut self, b: usize, g: SpillGeometry) {
        let Some(blocks) = self.spill.blocks.get_mut(b) else {
            return;
        };
        let Some(k) = blocks.iter().rposition(|k| k.written) else {
            return;
        };
        if self.slots_used + blocks[k].rays > self.capacity {
            return;
        }
        let block = blocks.remove(k);
        let w = self.geom.ray_words();
        let mut slots = Vec::with_capacity(block.rays as usize);
        // Oldest first, so the newest spilled ray is on top again.
        for r in (0..block.rays as usize).rev() {
            let s = self.alloc_slot();
            self.data[s as usize * w..][..w].copy_from_slice(&block.words[r * w..][..w]);
            slots.push(s);
        }
        let sp = &mut self.spill;
        sp.stats.refills += 1;
        sp.stats.refilled_bytes += u64::from(block.rays) * u64::from(self.geom.ray_bytes);
        if sp.timed {
            let id = sp.next_id;
            sp.next_id += 1;
            sp.started.push(DmaTransfer {
                id,
                write: false,
                addr: block_addr(block.index, g),
                rays: block.rays,
                ray_bytes: self.geom.ray_bytes,
            });
            sp.arriving += block.rays;
            sp.arriving_for[b] += block.rays;
            sp.transit.insert(
                id,
                Transit::In {
                    buffer: b,
                    index: block.index,
                    slots,
                },
            );
        } else {
            for s in slots {
                self.link_slot(b, s);
            }
            self.release_block(block.index);
        }
    }

    fn release_block(&mut self, index: u32) {
        self.spill.free_blocks.push(index);
        self.spill.blocks_used -= 1;
    }
}

/// DRAM address of area block `index`.
fn block_addr(index: u32, g: SpillGeometry) -> u32 {
    SPILL_AREA_BASE + index * g.block_bytes
}

#[cfg(test)]
mod tests {
    use super::super::{Flow, Popped, StreamGeometry};
    use super::*;

    /// 4 buffers, 20 rays of 48 bytes in SRAM; blocks of 4 rays (192 bytes); spill above
    /// 12 rays, refill below 4; an area of `blocks` blocks.
    fn memory(blocks: u32, timed: bool) -> StreamMemory {
        let mut m = StreamMemory::new(StreamGeometry {
            capacity_bytes: 20 + 20 * 52,
            ray_bytes: 48,
            buffers: 4,
            banks: 2,
            spill: Some(SpillGeometry {
                high_rays: 12,
                low_rays: 4,
                block_rays: 4,
                block_bytes: 192,
                area_blocks: blocks,
            }),
        });
        m.set_timed(timed);
        m
    }

    fn drain(m: &mut StreamMemory) -> Vec<u32> {
        let mut got = Vec::new();
        while let Some(b) = m.fullest() {
            match m.pop(b as usize) {
                Popped::Ray(r) => got.push(r[0]),
                other => panic!("{other:?}"),
            }
        }
        got.sort_unstable();
        got
    }

    #[test]
    fn no_ray_is_lost_and_blocks_are_counted() {
        let mut m = memory(64, false);
        assert_eq!(m.capacity_rays(), 20);
        for i in 0..100 {
            assert_eq!(m.push((i % 3) as usize, &[i]), Ok(Flow::Done));
            assert!(m.resident <= 12);
        }
        assert_eq!(m.len(0) + m.len(1) + m.len(2), 100);
        // Spills at the 13th, 17th, ... write: (100 - 13) / 4 + 1 blocks of 4 rays.
        let s = m.spill_stats();
        assert_eq!((s.spills, s.spilled_bytes), (22, 22 * 4 * 48));
        assert_eq!(drain(&mut m), (0..100).collect::<Vec<_>>());
        let s = m.spill_stats();
        assert_eq!((s.refills, s.refilled_bytes), (22, 22 * 4 * 48));
        assert_eq!((m.in_flight, m.slots_used, m.spill.blocks_used), (0, 0, 0));
    }

    #[test]
    fn the_geometry_round_trips_through_its_argument_form() {
        let g = memory(3, false).geometry().spill.unwrap();
        assert_eq!(SpillGeometry::from_arg(&g.to_arg()), Some(g));
        for bad in ["", "1,2,3,4", "1,2,0,4,5", "1,2,3,4,5,6", "a,2,3,4,5"] {
            assert_eq!(SpillGeometry::from_arg(bad), None, "{bad}");
        }
    }

    #[test]
    fn a_full_spill_area_is_a_fault() {
        let mut m = memory(2, false);
        // Spills at the 13th and 17th writes fill the area; the 21st needs a third block.
        for i in 0..20 {
            m.push(0, &[i]).unwrap();
        }
        let e = m.push(0, &[20]).unwrap_err();
        assert!(
            matches!(
                e,
                StreamError::SpillAreaFull(SpillAreaFull {
                    stream: 0,
                    blocks: 2,
                    block_bytes: 192
                })
            ),
            "{e:?}"
        );
    }

    #[test]
    fn timed_transfers_hold_slots_until_reported() {
        let mut m = memory(64, true);
        for i in 0..13 {
            assert_eq!(m.push(0, &[i]), Ok(Flow::Done));
        }
        // The 13th write started a spill of 4 rays: out of the list, slots still held.
        let t = m.take_transfers();
        assert_eq!(t.len(), 1);
        assert!(t[0].write && t[0].rays == 4 && t[0].addr == SPILL_AREA_BASE);
        assert_eq!((m.resident, m.slots_used, m.len(0)), (9, 13, 13));
        let mut i = 13;
        while m.push(0, &[i]) == Ok(Flow::Done) {
            i += 1;
        }
        // Every slot taken, the rest held by spills in progress: the writer waits.
        assert_eq!(m.slots_used, 20);
        assert!(m.resident <= 12);
        m.dma_progress(t[0].id, 1);
        assert_eq!(m.slots_used, 19);
        assert_eq!(m.push(0, &[i]), Ok(Flow::Done));
        m.dma_done(t[0].id);
        let n = i + 1;
        // Reading: the list first, then the spilled block on demand (wait for it).
        let t2: Vec<_> = m.take_transfers();
        for t in &t2 {
            m.dma_done(t.id);
        }
        let mut got = Vec::new();
        while let Some(b) = m.fullest() {
            match m.pop(b as usize) {
                Popped::Ray(r) => got.push(r[0]),
                Popped::Wait => {
                    let ts = m.take_transfers();
                    assert!(!ts.is_empty() || m.transfers_pending());
                    for t in ts {
                        assert!(!t.write);
                        m.dma_done(t.id);
                    }
                }
                Popped::Empty => unreachable!(),
            }
        }
        got.sort_unstable();
        assert_eq!(got, (0..n).collect::<Vec<_>>());
        assert!(!m.transfers_pending());
    }
}
