//! The STRaTA ray stream memory (thesis §3.2.1) as the kernel sees it: a fixed-capacity
//! on-chip SRAM holding fixed-size ray records in per-buffer (per-treelet) singly linked
//! LIFO lists, with a free list, and the TMs' stream schedulers behind `trax.strsched`.
//!
//! Exact semantics shared by the emulator (both modes) and the host implementation of the
//! kernel prelude (`prelude/hw_host.rs` includes this file with `#[path]`, as `pipes.rs`),
//! so `trax native` has the same capacity, order and scheduling. Dependency-free.
//!
//! Layout (the SRAM's bytes, so the capacity in rays is exact): one head pointer per ray
//! buffer and one free-list head, then the ray slots, each a `ray_bytes` record followed by
//! its link pointer. Pointers are [`POINTER_BYTES`] wide. A slot lives wholly in bank
//! `slot % banks` (a bank's port is one record wide), so writing or reading a ray is one
//! access to one bank ([`StreamMemory::last_slot`] tells the timing model which).
//!
//! Instructions: `trax.strwstart`/`trax.strw` fill the thread's staging record and
//! `trax.strwend` pushes it onto its buffer (one SRAM write; a push to a full memory is
//! [`StreamFull`]); `trax.strrstart` pops the newest ray of the TM's current buffer
//! (one SRAM read when there is one) into the staging record that `trax.strr` reads word
//! by word. The head-pointer lookup and list bookkeeping count as part of that one access,
//! as the thesis assumes them to cost about what an L2's tag and bank circuitry does.
//! `trax.strsize` and `trax.strcap` read the controller's counters (no SRAM access).
//!
//! `trax.strsched` is a hardware wait run by each TM's stream scheduler
//! ([`StreamScheduler`]): the calling thread is done with its TM's current buffer and waits
//! until every live thread of its TM waits there too (the TM has *drained*); then the
//! scheduler picks the TM's next buffer by the chip's [`SchedulePolicy`], makes it the
//! TM's current buffer and every waiting thread resumes with its id. When every buffer is
//! empty the TM *idles* until a ray is written to any buffer (then it schedules), or until
//! every live thread of the chip waits in `trax.strsched` with the memory empty: then all
//! resume with [`NO_BUFFER`] (the frame's stream work is done: nothing can write a ray).
//! Everything here is the same in functional and timing mode, so images are identical in
//! both; timing mode adds the cycles (the `clock` arguments) for idle time and the
//! decision's cost.
//!
//! With `stream_memory.overflow = "spill"` ([`SpillGeometry`]) a sentinel ([`spill`], thesis
//! §7.1.1) keeps the SRAM below a high watermark by moving blocks of rays to a DRAM spill
//! area and back; a buffer's rays then are those in its list plus those in DRAM or in
//! transit, and `trax.strsize`/`trax.strsched` count them all. In functional mode blocks
//! move at once; in timing mode ([`StreamMemory::set_timed`]) the timing engine carries the
//! transfers out ([`StreamMemory::take_transfers`]) and reports their progress, and a write
//! to a memory whose slots are all taken, or a read of rays still in transit, waits
//! ([`Flow::Wait`], [`Popped::Wait`]). The sentinel's state lives here, so `trax native`
//! spills as a functional run does (blocks move at once).

#[path = "stream_spill.rs"]
pub mod spill;

pub use spill::SpillGeometry;

/// What `trax.strsched` returns when the frame's stream work is done (and the TM's
/// current buffer before its first schedule).
pub const NO_BUFFER: u32 = u32::MAX;

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

    /// An empty memory holding exactly `rays` records of `ray_bytes` in `buffers` buffers
    /// (the shape the scene header gives a host run; banks do not matter there), spilling
    /// to DRAM as `spill` says.
    pub fn with_capacity_rays(
        rays: u32,
        ray_bytes: u32,
        buffers: u32,
        spill: Option<SpillGeometry>,
    ) -> StreamMemory {
        let geom = StreamGeometry {
            capacity_bytes: 0,
            ray_bytes,
            buffers,
            banks: 1,
            spill,
        };
        let bytes = geom.head_bytes() + u64::from(rays) * u64::from(ray_bytes + POINTER_BYTES);
        StreamMemory::new(StreamGeometry {
            capacity_bytes: bytes.min(u64::from(u32::MAX)) as u32,
            ..geom
        })
    }

    /// Its shape.
    pub fn geometry(&self) -> &StreamGeometry {
        &self.geom
    }

    /// Rays that fit in the SRAM (what `trax.strcap` reports, spilling or not).
    pub fn capacity_rays(&self) -> u32 {
        self.capacity
    }

    /// Buffer index of stream id `id` (`None`: no such buffer).
    pub fn buffer(&self, id: u32) -> Option<usize> {
        (id < self.geom.buffers).then_some(id as usize)
    }

    /// Rays in buffer `b` (in SRAM, DRAM or transit).
    pub fn len(&self, b: usize) -> u32 {
        self.counts.get(b).copied().unwrap_or(0)
    }

    /// Pushes a ray (its words, zero-padded to a record) onto buffer `b`. When spilling, a
    /// push that leaves the SRAM above the high watermark makes the sentinel spill a block.
    pub fn push(&mut self, b: usize, words: &[u32]) -> Result<Flow, StreamError> {
        if self.slots_used >= self.capacity {
            if self.geom.spill.is_some() && self.capacity > 0 {
                // The sentinel is draining a block (the watermarks leave a block of room
                // otherwise): the writer waits for it.
                return Ok(Flow::Wait);
            }
            return Err(StreamError::Full(StreamFull {
                stream: b as u32,
                capacity_rays: self.capacity,
                ray_bytes: self.geom.ray_bytes,
            }));
        }
        self.ensure_buffers();
        let slot = self.alloc_slot();
        let w = self.geom.ray_words();
        let rec = &mut self.data[slot as usize * w..][..w];
        rec.fill(0);
        let n = words.len().min(w);
        rec[..n].copy_from_slice(&words[..n]);
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
        if self.in_flight == 0 {
            return None;
        }
        self.counts
            .iter()
            .enumerate()
            .filter(|(_, &n)| n > 0)
            .max_by(|a, b| a.1.cmp(b.1).then(b.0.cmp(&a.0)))
            .map(|(i, _)| i as u32)
    }

    /// The buffer a TM whose current buffer is `current` ([`NO_BUFFER`]: none yet) visits
    /// next under `policy`, or `None` when every buffer is empty.
    pub fn pick(&self, policy: SchedulePolicy, current: u32) -> Option<u32> {
        if self.in_flight == 0 {
            return None;
        }
        match policy {
            // Without claims (see `StreamScheduler::pick`), `claimed` is `fullest`.
            SchedulePolicy::Fullest | SchedulePolicy::Claimed => self.fullest(),
            SchedulePolicy::Sticky if self.len(current as usize) > 0 => Some(current),
            SchedulePolicy::Sticky => self.fullest(),
            SchedulePolicy::RoundRobin => {
                let n = self.counts.len() as u32;
                let start = if current < n { current + 1 } else { 0 };
                (0..n)
                    .map(|k| (start + k) % n)
                    .find(|&b| self.counts[b as usize] > 0)
            }
        }
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

/// Why a ray write failed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StreamError {
    /// Every SRAM slot is taken and the memory does not spill.
    Full(StreamFull),
    /// Spilling, but every block of the DRAM spill area is taken.
    SpillAreaFull(SpillAreaFull),
}

/// A spill with every block of the spill area taken.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SpillAreaFull {
    /// The stream a block was spilled from.
    pub stream: u32,
    /// Blocks the area holds.
    pub blocks: u32,
    /// Bytes of a block.
    pub block_bytes: u32,
}

/// A write to a stream memory with every slot taken.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct StreamFull {
    /// The buffer written.
    pub stream: u32,
    /// Rays the memory holds (0: the chip has no stream memory).
    pub capacity_rays: u32,
    /// Bytes of a ray record.
    pub ray_bytes: u32,
}

/// How a TM's stream scheduler picks its next buffer (chip config
/// `stream_memory.schedule`). The thesis names no rule (§3.2.2 only says the TM picks a
/// treelet's buffer to work on), so each is an assumption.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum SchedulePolicy {
    /// The non-empty buffer with the most rays, lowest id on ties (the default: the most
    /// rays per treelet load).
    #[default]
    Fullest,
    /// The TM's current buffer while it has rays (its treelet is in the L1), else the
    /// fullest.
    Sticky,
    /// The next non-empty buffer after the current one, in id order, wrapping around.
    RoundRobin,
    /// The buffer with the most *unclaimed* rays, lowest id on ties: a TM that takes a
    /// buffer claims up to its thread count of the buffer's rays until its threads next
    /// drain, so other TMs see only the rest; a written ray (or a claim ending) wakes an
    /// idle TM only onto a buffer that still has unclaimed rays, one TM per thread-count of
    /// them, in TM order. Beyond the thesis: under `fullest` every idle TM wakes onto the
    /// buffer of a single written ray and all but one find it empty.
    Claimed,
}

impl SchedulePolicy {
    /// Every policy, by config name.
    pub const ALL: [(SchedulePolicy, &'static str); 4] = [
        (SchedulePolicy::Fullest, "fullest"),
        (SchedulePolicy::Sticky, "sticky"),
        (SchedulePolicy::RoundRobin, "round-robin"),
        (SchedulePolicy::Claimed, "claimed"),
    ];

    /// The config name.
    pub fn name(self) -> &'static str {
        match self {
            SchedulePolicy::Fullest => "fullest",
            SchedulePolicy::Sticky => "sticky",
            SchedulePolicy::RoundRobin => "round-robin",
            SchedulePolicy::Claimed => "claimed",
        }
    }

    /// The policy called `name`.
    pub fn from_name(name: &str) -> Option<SchedulePolicy> {
        Self::ALL.iter().find(|(_, n)| *n == name).map(|(p, _)| *p)
    }
}

/// One TM's stream scheduler state.
#[derive(Clone, Debug)]
pub struct TmSchedule {
    /// The buffer `trax.strrstart` reads ([`NO_BUFFER`] before the first schedule and
    /// after the frame's stream work is done).
    pub current: u32,
    /// Threads of the TM that have not halted.
    pub live: u32,
    /// Threads of the TM waiting in `trax.strsched`.
    pub waiting: u32,
    /// Releases so far: a waiting thread resumes once this has passed the value it
    /// arrived under.
    pub generation: u64,
    /// Drained with every buffer empty: waiting for a ray to be written.
    pub idle: bool,
    /// Cycle the TM became idle (timing mode).
    idle_since: u64,
    /// First cycle released threads may issue (timing mode: release + decision cost).
    pub resume_at: u64,
}

/// The chip's per-TM stream schedulers (the same in both modes), with their counters.
#[derive(Clone, Debug, Default)]
pub struct StreamScheduler {
    /// How a TM picks its next buffer.
    pub policy: SchedulePolicy,
    /// Cycles a scheduling decision takes (timing mode).
    pub cost: u64,
    /// Per TM.
    pub tms: Vec<TmSchedule>,
    /// Threads waiting in `trax.strsched`, chip-wide.
    pub waiting: u32,
    /// Decisions that gave a TM a buffer (buffer visits).
    pub schedules: u64,
    /// Those that gave it a different buffer than it had.
    pub switches: u64,
    /// TM-cycles spent idle (drained, every buffer empty) until a ray arrived or the
    /// frame's stream work was done (timing mode).
    pub idle_tm_cycles: u64,
    /// Times every live thread waited with the memory empty (all resumed with
    /// [`NO_BUFFER`]).
    pub completions: u64,
    /// Threads per TM (the rays a TM claims under [`SchedulePolicy::Claimed`]).
    threads_per_tm: u32,
    /// Per buffer, the TMs serving it (claims; [`SchedulePolicy::Claimed`] only).
    serving: Vec<u32>,
    /// Per TM, the buffer it claims, if any.
    claim: Vec<Option<u32>>,
}

impl StreamScheduler {
    /// Schedulers for `tms` TMs of `threads_per_tm` threads each.
    pub fn new(tms: u32, threads_per_tm: u32, policy: SchedulePolicy, cost: u64) -> Self {
        let tm = TmSchedule {
            current: NO_BUFFER,
            live: threads_per_tm,
            waiting: 0,
            generation: 0,
            idle: false,
            idle_since: 0,
            resume_at: 0,
        };
        StreamScheduler {
            policy,
            cost,
            tms: vec![tm; tms as usize],
            threads_per_tm,
            claim: vec![None; tms as usize],
            ..StreamScheduler::default()
        }
    }

    /// A thread of TM `tm` enters `trax.strsched` at `clock`; `live` = live threads of the
    /// chip. Returns the generation it waits to pass.
    pub fn arrive(&mut self, tm: usize, mem: &StreamMemory, live: u32, clock: u64) -> u64 {
        let g = self.tms[tm].generation;
        self.tms[tm].waiting += 1;
        self.waiting += 1;
        self.settle(Some(tm), mem, live, clock);
        g
    }

    /// A thread of TM `tm` halted (`live`: the chip's live threads, it excluded).
    pub fn halted(&mut self, tm: usize, mem: &StreamMemory, live: u32, clock: u64) {
        let s = &mut self.tms[tm];
        s.live = s.live.saturating_sub(1);
        if s.live == 0 && self.unclaim(tm) {
            self.pushed(mem, clock);
        }
        self.settle(Some(tm), mem, live, clock);
    }

    /// A ray was written: every idle TM schedules (in TM order).
    pub fn pushed(&mut self, mem: &StreamMemory, clock: u64) {
        for tm in 0..self.tms.len() {
            if self.tms[tm].idle {
                if let Some(b) = self.pick(mem, tm) {
                    self.release(tm, b, clock);
                }
            }
        }
    }

    /// TM `tm`'s next buffer by the policy (under `claimed`, the most unclaimed rays).
    fn pick(&self, mem: &StreamMemory, tm: usize) -> Option<u32> {
        if self.policy != SchedulePolicy::Claimed {
            return mem.pick(self.policy, self.tms[tm].current);
        }
        let mut best: Option<(u32, u32)> = None;
        for (b, &n) in self.serving.iter().enumerate() {
            let free = mem
                .len(b)
                .saturating_sub(n.saturating_mul(self.threads_per_tm));
            if free > 0 && best.is_none_or(|(_, f)| free > f) {
                best = Some((b as u32, free));
            }
        }
        // Buffers past the claims table have no claims.
        for b in self.serving.len()..mem.counts.len() {
            let free = mem.len(b);
            if free > 0 && best.is_none_or(|(_, f)| free > f) {
                best = Some((b as u32, free));
            }
        }
        best.map(|(b, _)| b)
    }

    /// Ends TM `tm`'s claim; true if it had one.
    fn unclaim(&mut self, tm: usize) -> bool {
        match self.claim.get_mut(tm).and_then(Option::take) {
            Some(b) => {
                self.serving[b as usize] -= 1;
                true
            }
            None => false,
        }
    }

    /// Schedules TM `tm` if it has drained, then ends the frame's stream work if every
    /// live thread waits with the memory empty.
    fn settle(&mut self, tm: Option<usize>, mem: &StreamMemory, live: u32, clock: u64) {
        if let Some(tm) = tm {
            let s = &self.tms[tm];
            if s.waiting > 0 && s.waiting >= s.live && !s.idle {
                // Drained: its claim ends (it may take the same buffer again), and what it
                // left unclaimed is offered to the idle TMs after it has chosen.
                let had = self.unclaim(tm);
                match self.pick(mem, tm) {
                    Some(b) => self.release(tm, b, clock),
                    None => {
                        let s = &mut self.tms[tm];
                        s.idle = true;
                        s.idle_since = clock;
                    }
                }
                if had {
                    self.pushed(mem, clock);
                }
            }
        }
        if self.waiting > 0 && self.waiting >= live && mem.in_flight == 0 {
            for tm in 0..self.tms.len() {
                if self.tms[tm].waiting > 0 {
                    self.release(tm, NO_BUFFER, clock);
                }
            }
            self.completions += 1;
        }
    }

    /// Resumes TM `tm`'s waiting threads with buffer `b` at `clock`.
    fn release(&mut self, tm: usize, b: u32, clock: u64) {
        let s = &mut self.tms[tm];
        if s.idle {
            self.idle_tm_cycles += clock.saturating_sub(s.idle_since);
            s.idle = false;
        }
        self.waiting -= s.waiting;
        s.waiting = 0;
        s.generation += 1;
        s.resume_at = clock + self.cost;
        if b != NO_BUFFER {
            self.schedules += 1;
            self.switches += u64::from(b != s.current);
            if self.policy == SchedulePolicy::Claimed {
                let b = b as usize;
                if self.serving.len() <= b {
                    self.serving.resize(b + 1, 0);
                }
                self.serving[b] += 1;
                self.claim[tm] = Some(b as u32);
            }
        }
        s.current = b;
    }

    /// [`Self::idle_tm_cycles`] with the idle intervals still open counted up to `now`.
    pub fn idle_tm_cycles_at(&self, now: u64) -> u64 {
        self.idle_tm_cycles
            + self
                .tms
                .iter()
                .filter(|s| s.idle)
                .map(|s| now.saturating_sub(s.idle_since))
                .sum::<u64>()
    }

    /// Closes the idle intervals still open when the run ended at `end`.
    pub fn finish(&mut self, end: u64) {
        for s in &mut self.tms {
            if s.idle {
                self.idle_tm_cycles += end.saturating_sub(s.idle_since);
                s.idle_since = end;
            }
        }
    }

    /// Whether a thread of TM `tm` that arrived under `generation` may resume at `now`.
    pub fn released(&self, tm: usize, generation: u64, now: u64) -> bool {
        let s = &self.tms[tm];
        s.generation > generation && now >= s.resume_at
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
        m.push(1, &[1]).unwrap();
        m.push(2, &[2]).unwrap();
        m.push(1, &[3, 4]).unwrap();
        assert_eq!(
            m.push(0, &[9]),
            Err(StreamError::Full(StreamFull {
                stream: 0,
                capacity_rays: 3,
                ray_bytes: 48
            }))
        );
        assert_eq!((m.len(1), m.len(2), m.fullest()), (2, 1, Some(1)));
        let Popped::Ray(r) = m.pop(1) else {
            panic!("buffer 1 has rays")
        };
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

    /// A memory with `counts[b]` rays in buffer `b`.
    fn filled(counts: &[u32]) -> StreamMemory {
        let mut m = StreamMemory::with_capacity_rays(100, 48, counts.len() as u32, None);
        for (b, &n) in counts.iter().enumerate() {
            for _ in 0..n {
                m.push(b, &[b as u32]).unwrap();
            }
        }
        m
    }

    #[test]
    fn with_capacity_rays_holds_exactly_that_many() {
        for rays in [1, 7, 1000] {
            let m = StreamMemory::with_capacity_rays(rays, 48, 16, None);
            assert_eq!(m.capacity_rays(), rays);
        }
    }

    #[test]
    fn fullest_takes_the_most_rays_lowest_id_on_ties() {
        let m = filled(&[0, 2, 5, 5, 1]);
        for cur in [NO_BUFFER, 0, 2, 3, 4] {
            assert_eq!(m.pick(SchedulePolicy::Fullest, cur), Some(2), "from {cur}");
        }
        assert_eq!(filled(&[0, 0, 0]).pick(SchedulePolicy::Fullest, 1), None);
    }

    #[test]
    fn sticky_keeps_a_buffer_while_it_has_rays() {
        let m = filled(&[0, 2, 5, 5, 1]);
        let p = SchedulePolicy::Sticky;
        assert_eq!(m.pick(p, 4), Some(4));
        assert_eq!(m.pick(p, 1), Some(1));
        // Empty or none: the fullest.
        assert_eq!(m.pick(p, 0), Some(2));
        assert_eq!(m.pick(p, NO_BUFFER), Some(2));
        assert_eq!(filled(&[0, 0]).pick(p, 1), None);
    }

    #[test]
    fn round_robin_takes_the_next_non_empty_buffer_wrapping() {
        let m = filled(&[0, 2, 0, 5, 1, 0]);
        let p = SchedulePolicy::RoundRobin;
        assert_eq!(m.pick(p, NO_BUFFER), Some(1));
        assert_eq!(m.pick(p, 1), Some(3));
        assert_eq!(m.pick(p, 3), Some(4));
        assert_eq!(m.pick(p, 4), Some(1));
        assert_eq!(m.pick(p, 5), Some(1));
        // The only non-empty buffer comes round again.
        assert_eq!(filled(&[0, 0, 3]).pick(p, 2), Some(2));
        assert_eq!(filled(&[0, 0, 0]).pick(p, 2), None);
        for (q, n) in SchedulePolicy::ALL {
            assert_eq!(SchedulePolicy::from_name(n), Some(q));
            assert_eq!(q.name(), n);
        }
        assert_eq!(SchedulePolicy::from_name("random"), None);
    }

    #[test]
    fn a_tm_schedules_only_when_every_live_thread_has_arrived() {
        // 2 TMs of 3 threads.
        let m = filled(&[1, 4]);
        let mut s = StreamScheduler::new(2, 3, SchedulePolicy::Fullest, 2);
        let g = s.arrive(0, &m, 6, 10);
        s.arrive(0, &m, 6, 11);
        assert!(
            !s.released(0, g, u64::MAX),
            "a thread of TM 0 is still working"
        );
        // A halted thread does not count: the TM has drained.
        s.halted(0, &m, 5, 12);
        assert!(!s.released(0, g, 13), "the decision takes 2 cycles");
        assert!(s.released(0, g, 14));
        assert_eq!(s.tms[0].current, 1);
        assert_eq!((s.schedules, s.switches, s.waiting), (1, 1, 0));
        // TM 1 is untouched.
        assert_eq!((s.tms[1].current, s.tms[1].generation), (NO_BUFFER, 0));
        // The same buffer again is a visit, not a switch.
        let g = s.arrive(0, &m, 5, 20);
        s.arrive(0, &m, 5, 20);
        assert!(s.released(0, g, 22));
        assert_eq!((s.schedules, s.switches), (2, 1));
    }

    #[test]
    fn an_idle_tm_wakes_on_a_write_and_all_end_when_every_thread_waits_empty() {
        let mut m = filled(&[0, 0, 0]);
        let mut s = StreamScheduler::new(2, 1, SchedulePolicy::Fullest, 1);
        let g0 = s.arrive(0, &m, 2, 100);
        assert!(s.tms[0].idle && !s.released(0, g0, u64::MAX));
        // TM 1 writes a ray at 130: TM 0 schedules buffer 2.
        m.push(2, &[9]).unwrap();
        s.pushed(&m, 130);
        assert!(s.released(0, g0, 131) && !s.tms[0].idle);
        assert_eq!((s.tms[0].current, s.idle_tm_cycles), (2, 30));
        // TM 0 reads it; both wait with the memory empty: the frame is done for both.
        assert!(matches!(m.pop(2), Popped::Ray(_)));
        let g0 = s.arrive(0, &m, 2, 140);
        let g1 = s.arrive(1, &m, 2, 150);
        assert!(s.released(0, g0, 151) && s.released(1, g1, 151));
        assert_eq!((s.tms[0].current, s.tms[1].current), (NO_BUFFER, NO_BUFFER));
        assert_eq!((s.completions, s.schedules, s.waiting), (1, 1, 0));
        // TM 0 idled 140..150, TM 1 not at all.
        assert_eq!(s.idle_tm_cycles, 30 + 10);
    }

    /// Three idle TMs of 2 threads and one written ray: `fullest` wakes all three onto it,
    /// `claimed` one; more rays wake one TM per 2 unclaimed.
    #[test]
    fn claimed_wakes_one_tm_per_threads_worth_of_unclaimed_rays() {
        for (policy, woken_by_one) in [(SchedulePolicy::Fullest, 3), (SchedulePolicy::Claimed, 1)] {
            let mut m = filled(&[0, 0]);
            let mut s = StreamScheduler::new(3, 2, policy, 0);
            let g: Vec<u64> = (0..3)
                .flat_map(|tm| [s.arrive(tm, &m, 7, 0), s.arrive(tm, &m, 7, 0)])
                .collect();
            assert!((0..3).all(|tm| s.tms[tm].idle));
            m.push(1, &[1]).unwrap();
            s.pushed(&m, 10);
            let woken = (0..3).filter(|&tm| s.released(tm, g[2 * tm], 10)).count();
            assert_eq!(woken, woken_by_one, "{policy:?}");
        }
        // Claimed: 1 ray claimed by TM 0 (2 threads); 4 more in buffer 1 leave 3 unclaimed:
        // TM 1 wakes (claims 2), 1 still unclaimed: TM 2 wakes too.
        let mut m = filled(&[0, 0]);
        let mut s = StreamScheduler::new(3, 2, SchedulePolicy::Claimed, 0);
        for tm in 0..3 {
            s.arrive(tm, &m, 7, 0);
            s.arrive(tm, &m, 7, 0);
        }
        m.push(1, &[1]).unwrap();
        s.pushed(&m, 1);
        assert_eq!(s.claim, vec![Some(1), None, None]);
        for _ in 0..2 {
            m.push(1, &[2]).unwrap();
            s.pushed(&m, 2);
        }
        // 3 rays, 2 claimed by TM 0: TM 1 takes the 1 unclaimed.
        assert_eq!(s.claim, vec![Some(1), Some(1), None]);
        m.push(0, &[3]).unwrap();
        s.pushed(&m, 3);
        assert_eq!(s.claim, vec![Some(1), Some(1), Some(0)]);
        assert_eq!(s.serving, vec![1, 2]);
    }

    /// A TM that drains ends its claim and the idle TMs are offered what it left; rays only
    /// in a claimed buffer keep the others idle without ending the frame; the last drain
    /// ends it.
    #[test]
    fn claimed_releases_on_drain_and_still_ends_the_frame() {
        let mut m = filled(&[0, 0]);
        let mut s = StreamScheduler::new(2, 1, SchedulePolicy::Claimed, 0);
        // `live` 3: a thread elsewhere still works (it writes the rays), so the frame goes on.
        let g0 = s.arrive(0, &m, 3, 0);
        let g1 = s.arrive(1, &m, 3, 0);
        m.push(0, &[1]).unwrap();
        s.pushed(&m, 5);
        assert!(
            s.released(0, g0, 5) && !s.released(1, g1, 5),
            "TM 0 claims the one ray"
        );
        assert_eq!(s.claim, vec![Some(0), None]);
        // TM 0 reads it and writes two rays into buffer 1 before draining: TM 1 wakes for
        // the first (unclaimed), the second stays unclaimed for TM 0's next choice.
        assert!(matches!(m.pop(0), Popped::Ray(_)));
        m.push(1, &[2]).unwrap();
        s.pushed(&m, 6);
        assert!(s.released(1, g1, 6));
        assert_eq!(s.claim, vec![Some(0), Some(1)]);
        m.push(1, &[3]).unwrap();
        s.pushed(&m, 7);
        // TM 0 drains: its claim on 0 ends, buffer 1 has 2 rays, 1 claimed: it takes 1.
        let g0 = s.arrive(0, &m, 3, 8);
        assert!(s.released(0, g0, 8));
        assert_eq!(
            (s.claim.clone(), s.serving.clone()),
            (vec![Some(1), Some(1)], vec![0, 2])
        );
        // Both read a ray, then drain with the memory empty (the writer has halted): the
        // frame is done.
        assert!(matches!(m.pop(1), Popped::Ray(_)));
        assert!(matches!(m.pop(1), Popped::Ray(_)));
        let g0 = s.arrive(0, &m, 2, 9);
        assert!(!s.released(0, g0, u64::MAX), "TM 1 still works");
        assert_eq!(s.claim, vec![None, Some(1)]);
        let g1 = s.arrive(1, &m, 2, 10);
        assert!(s.released(0, g0, 10) && s.released(1, g1, 10));
        assert_eq!((s.completions, s.serving.clone()), (1, vec![0, 0]));
    }

    /// Rays only in a buffer a TM claims: the other TMs stay idle (they would find it
    /// empty), the frame does not end while the claimant works, the claimant takes the
    /// buffer again when it drains, and the frame ends when it drains the memory empty.
    #[test]
    fn claimed_rays_keep_others_idle_without_deadlock() {
        let mut m = filled(&[0, 0]);
        let mut s = StreamScheduler::new(3, 2, SchedulePolicy::Claimed, 0);
        // TMs 0 and 1 idle; one thread of TM 2 waits, the other works.
        let g: Vec<u64> = [0, 0, 1, 1, 2]
            .into_iter()
            .map(|tm| s.arrive(tm, &m, 6, 0))
            .collect();
        assert!(s.tms[0].idle && s.tms[1].idle && !s.tms[2].idle);
        // It writes a ray: TM 0 alone takes it. It halts: TM 2 drains and idles, as the
        // one ray is claimed.
        m.push(1, &[1]).unwrap();
        s.pushed(&m, 1);
        assert!(s.released(0, g[0], 1) && s.released(0, g[1], 1));
        s.halted(2, &m, 5, 1);
        assert!(s.tms[1].idle && s.tms[2].idle && !s.released(2, g[4], u64::MAX));
        // TM 0 reads it and writes one more into its own buffer: still within its claim.
        assert!(matches!(m.pop(1), Popped::Ray(_)));
        m.push(1, &[2]).unwrap();
        s.pushed(&m, 2);
        assert!(s.tms[1].idle && s.tms[2].idle);
        assert_eq!(s.completions, 0);
        // TM 0 drains: its claim ends and it takes buffer 1 again; the others stay idle.
        let g0 = [s.arrive(0, &m, 5, 3), s.arrive(0, &m, 5, 3)];
        assert!(s.released(0, g0[0], 3));
        assert_eq!(
            (s.claim.clone(), s.schedules, s.completions),
            (vec![Some(1), None, None], 2, 0)
        );
        // It reads the ray and drains with the memory empty: every thread resumes, done.
        assert!(matches!(m.pop(1), Popped::Ray(_)));
        let g0 = [s.arrive(0, &m, 5, 4), s.arrive(0, &m, 5, 4)];
        assert!(s.released(0, g0[1], 4));
        assert!([g[2], g[3], g[4]]
            .iter()
            .zip([1, 1, 2])
            .all(|(&g, tm)| s.released(tm, g, 4) && s.tms[tm].current == NO_BUFFER));
        assert_eq!((s.completions, s.serving.clone()), (1, vec![0, 0]));
    }

    /// A TM whose last thread halts gives up its claim: an idle TM takes the rays.
    #[test]
    fn claimed_ends_with_the_tms_last_thread() {
        let mut m = filled(&[0]);
        let mut s = StreamScheduler::new(2, 1, SchedulePolicy::Claimed, 0);
        s.arrive(0, &m, 3, 0);
        let g1 = s.arrive(1, &m, 3, 0);
        m.push(0, &[1]).unwrap();
        s.pushed(&m, 1);
        assert_eq!(s.claim, vec![Some(0), None]);
        assert!(!s.released(1, g1, u64::MAX));
        s.halted(0, &m, 2, 2);
        assert!(s.released(1, g1, 2), "TM 1 takes the ray TM 0 left");
        assert_eq!(s.claim, vec![None, Some(0)]);
    }

    #[test]
    fn the_last_halt_can_end_the_frame() {
        let m = filled(&[0]);
        let mut s = StreamScheduler::new(2, 1, SchedulePolicy::Fullest, 1);
        let g = s.arrive(0, &m, 2, 5);
        assert!(!s.released(0, g, u64::MAX));
        // TM 1's only thread halts without scheduling: no one can write a ray.
        s.halted(1, &m, 1, 9);
        assert!(s.released(0, g, u64::MAX));
        assert_eq!((s.tms[0].current, s.completions), (NO_BUFFER, 1));
        let mut s2 = s.clone();
        s2.finish(1000);
        assert_eq!(s2.idle_tm_cycles, s.idle_tm_cycles, "nothing left open");
    }

    /// A thread of [`run_random_frame`]'s model kernel.
    #[derive(Clone, Copy, Debug, PartialEq)]
    enum Model {
        /// Has not written its primary ray yet.
        Start,
        /// Reads its TM's current buffer until it is empty.
        Working,
        /// In `trax.strsched`, arrived under this generation.
        Waiting(u64),
        Halted,
    }

    /// Runs a frame of a model streaming kernel on `tms` TMs of `threads` threads, in an
    /// order drawn from `seed`: each thread writes one ray of `depth` bounces to a random
    /// buffer, then reads its TM's buffer until empty, each ray it reads writing up to two
    /// rays of one bounce fewer to random buffers, and calls `trax.strsched`; a thread may
    /// halt instead of writing its primary ray, or after a ray unless it is the chip's last
    /// live thread (a TM may halt while claiming a buffer with rays). After every step: some thread can run (no deadlock) until every thread
    /// has halted; under `claimed`, the claims table matches the TMs' claims and no TM
    /// idles while a buffer has unclaimed rays. Returns the scheduler at the end.
    fn run_random_frame(
        policy: SchedulePolicy,
        tms: u32,
        threads: u32,
        seed: u64,
    ) -> StreamScheduler {
        let mut rng = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1;
        let mut next = |n: u64| {
            rng ^= rng << 13;
            rng ^= rng >> 7;
            rng ^= rng << 17;
            rng % n
        };
        let buffers = 5;
        let mut m = StreamMemory::with_capacity_rays(10_000, 48, buffers, None);
        let mut s = StreamScheduler::new(tms, threads, policy, 0);
        let n = (tms * threads) as usize;
        let mut th = vec![Model::Start; n];
        let mut live = n as u32;
        let mut rays_read = 0u64;
        for clock in 0.. {
            let runnable: Vec<usize> = (0..n)
                .filter(|&t| match th[t] {
                    Model::Start | Model::Working => true,
                    Model::Waiting(g) => s.released(t / threads as usize, g, clock),
                    Model::Halted => false,
                })
                .collect();
            if runnable.is_empty() {
                assert_eq!(
                    live, 0,
                    "{policy:?} seed {seed}: deadlock at step {clock}: {th:?}"
                );
                break;
            }
            let was_idle: Vec<bool> = s.tms.iter().map(|x| x.idle).collect();
            let t = runnable[next(runnable.len() as u64) as usize];
            let tm = t / threads as usize;
            match th[t] {
                Model::Start if next(8) == 0 => {
                    live -= 1;
                    s.halted(tm, &m, live, clock);
                    th[t] = Model::Halted;
                }
                Model::Start => {
                    m.push(next(u64::from(buffers)) as usize, &[3]).unwrap();
                    s.pushed(&m, clock);
                    th[t] = Model::Working;
                }
                Model::Working if s.tms[tm].current == NO_BUFFER => {
                    th[t] = Model::Waiting(s.arrive(tm, &m, live, clock));
                }
                Model::Working => match m.pop(s.tms[tm].current as usize) {
                    Popped::Ray(r) => {
                        rays_read += 1;
                        if r[0] > 0 {
                            for _ in 0..next(3) {
                                m.push(next(u64::from(buffers)) as usize, &[r[0] - 1])
                                    .unwrap();
                                s.pushed(&m, clock);
                            }
                        }
                        if live > 1 && next(16) == 0 {
                            live -= 1;
                            s.halted(tm, &m, live, clock);
                            th[t] = Model::Halted;
                        }
                    }
                    Popped::Empty => th[t] = Model::Waiting(s.arrive(tm, &m, live, clock)),
                    Popped::Wait => unreachable!("no spill"),
                },
                // Released: a buffer to read, or the frame's stream work is done.
                Model::Waiting(_) if s.tms[tm].current == NO_BUFFER => {
                    assert_eq!(
                        m.in_flight, 0,
                        "{policy:?} seed {seed}: ended with rays left"
                    );
                    live -= 1;
                    s.halted(tm, &m, live, clock);
                    th[t] = Model::Halted;
                }
                Model::Waiting(_) => th[t] = Model::Working,
                Model::Halted => unreachable!(),
            }
            if policy == SchedulePolicy::Claimed {
                // A TM woken in this step got rays beyond the other TMs' claims.
                for (k, x) in s.tms.iter().enumerate() {
                    if was_idle[k] && !x.idle && x.current != NO_BUFFER {
                        let b = x.current as usize;
                        let others = s.serving[b] - 1;
                        assert!(
                            m.len(b) > others * threads,
                            "seed {seed} step {clock}: TM {k} woke onto buffer {b}'s {} rays, \
                             all claimed by {others} TMs",
                            m.len(b)
                        );
                    }
                }
                for b in 0..buffers as usize {
                    let claims = s.claim.iter().filter(|&&c| c == Some(b as u32)).count();
                    assert_eq!(s.serving.get(b).copied().unwrap_or(0) as usize, claims);
                    let unclaimed = m.len(b).saturating_sub(claims as u32 * threads);
                    assert!(
                        unclaimed == 0 || !s.tms.iter().any(|x| x.idle),
                        "seed {seed} step {clock}: a TM idles while buffer {b} has {unclaimed} unclaimed rays"
                    );
                }
            }
        }
        assert_eq!((m.in_flight, m.reads), (0, rays_read));
        assert_eq!(m.reads, m.writes, "{policy:?} seed {seed}");
        assert!(
            s.claim.iter().all(Option::is_none),
            "{policy:?} seed {seed}: claims left"
        );
        s
    }

    /// Random frames under every policy: no deadlock, every ray read, the claims consistent
    /// and never hiding rays from an idle TM.
    #[test]
    fn random_frames_finish_under_every_policy() {
        for (policy, _) in SchedulePolicy::ALL {
            for seed in 0..200 {
                let (tms, threads) = (1 + seed as u32 % 4, 1 + (seed as u32 / 4) % 3);
                let s = run_random_frame(policy, tms, threads, seed);
                assert_eq!(s.waiting, 0);
            }
        }
    }
}
