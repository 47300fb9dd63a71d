//! The STRaTA ray stream memory (thesis §3.2.1) as the kernel sees it, in both modes: a
//! fixed-capacity on-chip SRAM holding fixed-size ray records in per-buffer (per-treelet)
//! singly linked LIFO lists, with a free list.
//!
//! Layout (the SRAM's bytes, so the capacity in rays is exact): one head pointer per ray
//! buffer and one free-list head, then the ray slots, each a `ray_bytes` record followed by
//! its link pointer. Pointers are [`POINTER_BYTES`] wide. A slot lives wholly in bank
//! `slot % banks` (a bank's port is one record wide), so writing or reading a ray is one
//! access to one bank ([`StreamMemory::last_slot`] tells the timing model which).
//!
//! Instructions: `trax.strwstart`/`trax.strw` fill the thread's staging record and
//! `trax.strwend` pushes it onto its buffer (one SRAM write; a push to a full memory is
//! [`Fault::StreamFull`]); `trax.strrstart` pops the newest ray of the TM's current buffer
//! (one SRAM read when there is one) into the staging record that `trax.strr` reads word
//! by word. The head-pointer lookup and list bookkeeping count as part of that one access,
//! as the thesis assumes them to cost about what an L2's tag and bank circuitry does.
//! `trax.strsize`, `trax.strsched` and `trax.strcap` read the controller's counters (no
//! SRAM access). Everything here is the same in functional and timing mode, so images are
//! identical in both.
//!
//! With `stream_memory.overflow = "spill"` ([`SpillGeometry`]) a sentinel ([`spill`], thesis
//! §7.1.1) keeps the SRAM below a high watermark by moving blocks of rays to a DRAM spill
//! area and back; a buffer's rays then are those in its list plus those in DRAM or in
//! transit, and `trax.strsize`/`trax.strsched` count them all. In functional mode blocks
//! move at once; in timing mode ([`StreamMemory::set_timed`]) the timing engine carries the
//! transfers out ([`StreamMemory::take_transfers`]) and reports their progress, and a write
//! to a memory whose slots are all taken, or a read of rays still in transit, waits
//! ([`Flow::Wait`], [`Popped::Wait`]).

use crate::thread::Fault;

pub mod spill;

pub use spill::SpillGeometry;

/// Bytes of a head or link pointer.
pub const POINTER_BYTES: u32 = 4;

/// "No slot".
const NIL: u32 = u32::MAX;

/// Shape of the stream memory (from the chip config's `stream_memory`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct StreamGeometry {
    /// SRAM bytes.
    pub capacity_bytes: u32,
    /// Bytes of one ray record (a multiple of 4).
    pub ray_bytes: u32,
    /// Ray buffers (stream ids `0..buffers`), each with a head pointer in the SRAM.
    pub buffers: u32,
    /// Banks.
    pub banks: u32,
    /// The spill sentinel, when overflow spills.
    pub spill: Option<SpillGeometry>,
}

impl Default for StreamGeometry {
    /// The chip config's defaults (`timing::StreamMemoryConfig`).
    fn default() -> Self {
        StreamGeometry {
            capacity_bytes: 4 << 20,
            ray_bytes: 48,
            buffers: 1024,
            banks: 32,
            spill: None,
        }
    }
}

impl StreamGeometry {
    /// Bytes of pointers that are not ray links: the buffers' heads and the free list's.
    pub fn head_bytes(&self) -> u64 {
        u64::from(self.buffers + 1) * u64::from(POINTER_BYTES)
    }

    /// Rays that fit: `(capacity - head pointers) / (ray_bytes + link pointer)`.
    pub fn capacity_rays(&self) -> u32 {
        let room = u64::from(self.capacity_bytes).saturating_sub(self.head_bytes());
        (room / u64::from(self.ray_bytes + POINTER_BYTES)) as u32
    }

    /// Words of one ray record.
    pub fn ray_words(&self) -> usize {
        (self.ray_bytes / 4) as usize
    }
}

/// What a ray write did.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Flow {
    /// Done.
    Done,
    /// Every slot is taken while the sentinel moves rays out: retry later (timing mode).
    Wait,
}

/// What a ray read found.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Popped {
    /// A ray (its record's words).
    Ray(Vec<u32>),
    /// The buffer holds no ray.
    Empty,
    /// The buffer's rays are in DRAM or in transit: retry later (timing mode).
    Wait,
}

/// The stream memory's contents and counters.
#[derive(Clone, Debug, Default)]
pub struct StreamMemory {
    geom: StreamGeometry,
    capacity: u32,
    /// Per buffer: newest slot (NIL when empty), rays (in SRAM, DRAM or transit) and rays
    /// in its SRAM list (allocated on first use).
    heads: Vec<u32>,
    counts: Vec<u32>,
    listed: Vec<u32>,
    /// Per slot used so far: its link pointer and its record.
    link: Vec<u32>,
    data: Vec<u32>,
    /// Head of the free list of released slots; slots `fresh..capacity` were never used.
    free: u32,
    fresh: u32,
    /// Slots taken (rays in lists plus slots the sentinel holds), and rays in lists.
    slots_used: u32,
    resident: u32,
    /// The sentinel's state (blocks in DRAM, transfers).
    spill: spill::SpillState,
    /// Rays stored now (in SRAM, DRAM or transit).
    pub in_flight: u32,
    /// Most rays stored at once.
    pub max_in_flight: u32,
    /// Rays written (pushes).
    pub writes: u64,
    /// Rays read (successful pops).
    pub reads: u64,
    /// The slot the last push or pop accessed (taken by the timing model).
    pub last_slot: Option<u32>,
}

impl StreamMemory {
    /// An empty memory of this shape.
    pub fn new(geom: StreamGeometry) -> StreamMemory {
        StreamMemory {
            geom,
            capacity: geom.capacity_rays(),
            free: NIL,
            ..StreamMemory::default()
        }
    }

    /// Its shape.
    pub fn geometry(&self) -> &StreamGeometry {
        &self.geom
    }

    /// Rays that fit in the SRAM (what `trax.strcap` reports, spilling or not).
    pub fn capacity_rays(&self) -> u32 {
        self.capacity
    }

    /// Buffer index of stream id `id`.
    pub fn buffer(&self, id: u32) -> Result<usize, Fault> {
        if id < self.geom.buffers {
            Ok(id as usize)
        } else {
            Err(Fault::BadIndex {
                what: "ray stream",
                index: id,
            })
        }
    }

    /// Rays in buffer `b` (in SRAM, DRAM or transit).
    pub fn len(&self, b: usize) -> u32 {
        self.counts.get(b).copied().unwrap_or(0)
    }

    /// Pushes a ray (its words, zero-padded to a record) onto buffer `b`. When spilling, a
    /// push that leaves the SRAM above the high watermark makes the sentinel spill a block.
    pub fn push(&mut self, b: usize, words: &[u32]) -> Result<Flow, Fault> {
        if self.slots_used >= self.capacity {
            if self.geom.spill.is_some() && self.capacity > 0 {
                // The sentinel is draining a block (the watermarks leave a block of room
                // otherwise): the writer waits for it.
                return Ok(Flow::Wait);
            }
            return Err(Fault::StreamFull {
                stream: b as u32,
                capacity_rays: self.capacity,
                ray_bytes: self.geom.ray_bytes,
            });
        }
        self.ensure_buffers();
        let slot = self.alloc_slot();
        let w = self.geom.ray_words();
        let rec = &mut self.data[slot as usize * w..][..w];
        rec.fill(0);
        rec[..words.len()].copy_from_slice(words);
        self.link_slot(b, slot);
        self.counts[b] += 1;
        self.in_flight += 1;
        self.max_in_flight = self.max_in_flight.max(self.in_flight);
        self.writes += 1;
        self.last_slot = Some(slot);
        if self.geom.spill.is_some() {
            self.spill_over()?;
        }
        Ok(Flow::Done)
    }

    /// Pops the newest ray of buffer `b` (LIFO). When spilling, a buffer whose rays are all
    /// in DRAM is refilled first, and a pop that leaves the SRAM below the low watermark
    /// makes the sentinel refill a block.
    pub fn pop(&mut self, b: usize) -> Popped {
        if self.len(b) == 0 {
            return Popped::Empty;
        }
        if self.listed[b] == 0 && !self.refill_for(b) {
            return Popped::Wait;
        }
        let slot = self.unlink_slot(b);
        let w = self.geom.ray_words();
        let ray = self.data[slot as usize * w..][..w].to_vec();
        self.free_slot(slot);
        self.counts[b] -= 1;
        self.in_flight -= 1;
        self.reads += 1;
        self.last_slot = Some(slot);
        if self.geom.spill.is_some() {
            self.refill_under();
        }
        Popped::Ray(ray)
    }

    /// The non-empty buffer with the most rays (lowest id on ties), if any.
    pub fn fullest(&self) -> Option<u32> {
        self.counts
            .iter()
            .enumerate()
            .filter(|(_, &n)| n > 0)
            .max_by(|a, b| a.1.cmp(b.1).then(b.0.cmp(&a.0)))
            .map(|(i, _)| i as u32)
    }

    fn ensure_buffers(&mut self) {
        if self.heads.is_empty() {
            let n = self.geom.buffers as usize;
            self.heads = vec![NIL; n];
            self.counts = vec![0; n];
            self.listed = vec![0; n];
        }
    }

    /// Takes a free slot (the caller checked that one is).
    fn alloc_slot(&mut self) -> u32 {
        self.slots_used += 1;
        if self.free != NIL {
            let s = self.free;
            self.free = self.link[s as usize];
            s
        } else {
            let s = self.fresh;
            self.fresh += 1;
            self.link.push(NIL);
            self.data.resize(self.data.len() + self.geom.ray_words(), 0);
            s
        }
    }

    fn free_slot(&mut self, slot: u32) {
        self.link[slot as usize] = self.free;
        self.free = slot;
        self.slots_used -= 1;
    }

    /// Puts `slot` on top of buffer `b`'s list.
    fn link_slot(&mut self, b: usize, slot: u32) {
        self.link[slot as usize] = self.heads[b];
        self.heads[b] = slot;
        self.listed[b] += 1;
        self.resident += 1;
    }

    /// Takes the top slot of buffer `b`'s list (which is not empty).
    fn unlink_slot(&mut self, b: usize) -> u32 {
        let slot = self.heads[b];
        self.heads[b] = self.link[slot as usize];
        self.listed[b] -= 1;
        self.resident -= 1;
        slot
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn geom(capacity_bytes: u32) -> StreamGeometry {
        StreamGeometry {
            capacity_bytes,
            ray_bytes: 48,
            buffers: 4,
            banks: 2,
            spill: None,
        }
    }

    #[test]
    fn capacity_charges_heads_and_links() {
        // 5 head pointers (4 buffers + free list) = 20 B; each ray 48 + 4 B.
        let g = geom(20 + 3 * 52 + 51);
        assert_eq!(g.capacity_rays(), 3);
        assert_eq!(geom(20 + 3 * 52).capacity_rays(), 3);
        assert_eq!(geom(19).capacity_rays(), 0);
        // The thesis's "eight percent or less" (§3.2.1) for a 4 MB memory of 48-byte rays.
        let g = StreamGeometry::default();
        let overhead = 1.0 - f64::from(g.capacity_rays() * 48) / f64::from(g.capacity_bytes);
        assert!(overhead < 0.08, "{overhead}");
    }

    #[test]
    fn lifo_per_buffer_and_slots_reused() {
        let mut m = StreamMemory::new(geom(20 + 3 * 52));
        assert_eq!(m.push(1, &[1]), Ok(Flow::Done));
        m.push(2, &[2]).unwrap();
        m.push(1, &[3, 4]).unwrap();
        assert!(matches!(m.push(0, &[9]), Err(Fault::StreamFull { .. })));
        assert_eq!((m.len(1), m.len(2), m.fullest()), (2, 1, Some(1)));
        let Popped::Ray(r) = m.pop(1) else { panic!() };
        assert_eq!(&r[..3], &[3, 4, 0]);
        assert_eq!(r.len(), 12);
        assert_eq!(m.last_slot, Some(2));
        // The freed slot is the next one used.
        m.push(3, &[5]).unwrap();
        assert_eq!(m.last_slot, Some(2));
        assert!(matches!(m.pop(1), Popped::Ray(r) if r[0] == 1));
        assert_eq!(m.pop(1), Popped::Empty);
        assert!(matches!(m.pop(3), Popped::Ray(r) if r[0] == 5));
        assert_eq!(
            (m.in_flight, m.max_in_flight, m.writes, m.reads),
            (1, 3, 4, 3)
        );
    }
}
