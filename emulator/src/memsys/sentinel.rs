//! The ray-buffer sentinel's DMA engine (thesis §7.1.1; the stream memory's side is
//! `crate::streams::spill`): block transfers between the ray stream memory and DRAM, one
//! at a time in the order started.
//!
//! A spill reads its rays out of the SRAM at one ray per core cycle (the list controller's
//! rate, §7.1.1: "primarily limited by the need to update list pointers"), and writes each
//! line to DRAM once the rays covering it are read and the channel's write queue takes it;
//! a ray's slot is free once the line holding its last byte is accepted. A refill requests
//! the block's lines (one per cycle, as the read queues take them) and writes the rays into
//! the SRAM at one per cycle as their lines arrive; it is done when the last ray is
//! written. Lines are consecutive addresses, so with a row-per-line-run mapping a block is
//! whole rows. Requests carry [`DMA_ID_TAG`], so the DRAM counts their row-buffer outcomes
//! apart.

use std::collections::VecDeque;

use super::dram::Dram;
use super::{Completion, Cycle};

/// Bits 63..62 = 0b01 mark a DMA request's id (the L2s use ids below 2^62 for reads and
/// `u64::MAX` for writes).
pub const DMA_ID_TAG: u64 = 1 << 62;

/// Whether `id` is a DMA request's.
pub fn is_dma(id: u64) -> bool {
    id >> 62 == 1
}

/// One block transfer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DmaJob {
    /// The stream memory's transfer id.
    pub id: u64,
    /// Spill (to DRAM) or refill.
    pub write: bool,
    /// First byte in DRAM.
    pub addr: u32,
    /// Rays moved, packed from `addr`.
    pub rays: u32,
    /// Bytes per ray.
    pub ray_bytes: u32,
    /// Core cycle it was started (it runs once the transfers before it are done).
    pub start: Cycle,
}

/// Progress to report to the stream memory.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DmaEvent {
    /// The transfer.
    pub id: u64,
    /// Rays out of the SRAM so far (spills), or all rays once done.
    pub rays: u32,
    /// The transfer is complete.
    pub done: bool,
}

/// The DMA engine's counters.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct DmaStats {
    /// Line writes and reads sent to DRAM.
    pub lines_written: u64,
    /// Line reads sent to DRAM.
    pub lines_read: u64,
    /// Core cycles during which a transfer was under way.
    pub busy_cycles: u64,
}

#[derive(Clone, Copy, Debug)]
struct Current {
    job: DmaJob,
    began: Cycle,
    lines: u32,
    sent: u32,
    arrived: u32,
    last_arrival: Cycle,
    released: u32,
}

/// The DMA engine.
#[derive(Clone, Debug, Default)]
pub struct Sentinel {
    queue: VecDeque<DmaJob>,
    cur: Option<Current>,
    line_bytes: u32,
    /// Cycle the last transfer ended (the next begins after it).
    free_at: Cycle,
    events: Vec<DmaEvent>,
    /// Counters.
    pub stats: DmaStats,
}

impl Sentinel {
    /// An idle engine moving `line_bytes` per DRAM request.
    pub fn new(line_bytes: u32) -> Sentinel {
        Sentinel {
            line_bytes,
            ..Sentinel::default()
        }
    }

    /// Queues a transfer.
    pub fn start(&mut self, job: DmaJob) {
        self.queue.push_back(job);
    }

    /// Whether no transfer is queued or under way.
    pub fn is_idle(&self) -> bool {
        self.cur.is_none() && self.queue.is_empty()
    }

    /// Progress since the last call.
    pub fn take_events(&mut self) -> Vec<DmaEvent> {
        std::mem::take(&mut self.events)
    }

    /// A DMA read's data arrived (a completion whose id [`is_dma`]).
    pub fn arrived(&mut self, c: &Completion) {
        if let Some(cur) = &mut self.cur {
            cur.arrived += 1;
            cur.last_arrival = cur.last_arrival.max(c.cycle);
        }
    }

    /// Core cycle `now`: starts the next transfer when free, sends at most one line.
    pub fn step(&mut self, now: Cycle, dram: &mut Dram, out: &mut Vec<Completion>) {
        if self.cur.is_none() {
            match self.queue.front() {
                Some(j) if j.start.max(self.free_at) <= now => {
                    let job = self.queue.pop_front().expect("front exists");
                    let bytes = u64::from(job.rays) * u64::from(job.ray_bytes);
                    self.cur = Some(Current {
                        job,
                        began: now,
                        lines: bytes.div_ceil(u64::from(self.line_bytes)) as u32,
                        sent: 0,
                        arrived: 0,
                        last_arrival: 0,
                        released: 0,
                    });
                }
                _ => return,
            }
        }
        let lb = u64::from(self.line_bytes);
        let Some(cur) = &mut self.cur else { return };
        let job = cur.job;
        let rb = u64::from(job.ray_bytes);
        if job.write {
            // Rays read so far (one per cycle from `began`, this cycle's included).
            let read = (now - cur.began + 1).min(u64::from(job.rays));
            let ready = if read == u64::from(job.rays) {
                u64::from(cur.lines)
            } else {
                read * rb / lb
            };
            if u64::from(cur.sent) < ready {
                let addr = job.addr + cur.sent * self.line_bytes;
                if dram.can_accept(addr, true) {
                    let ok = dram.submit(DMA_ID_TAG | job.id, addr, true, now, out);
                    debug_assert!(ok, "can_accept was checked");
                    cur.sent += 1;
                    self.stats.lines_written += 1;
                    let freed = if cur.sent == cur.lines {
                        job.rays
                    } else {
                        (u64::from(cur.sent) * lb / rb) as u32
                    };
                    if freed > cur.released {
                        cur.released = freed;
                        self.events.push(DmaEvent {
                            id: job.id,
                            rays: freed,
                            done: false,
                        });
                    }
                }
            }
            if cur.sent == cur.lines {
                self.finish(now);
            }
        } else {
            if cur.sent < cur.lines {
                let addr = job.addr + cur.sent * self.line_bytes;
                if dram.can_accept(addr, false) {
                    let ok = dram.submit(DMA_ID_TAG | job.id, addr, false, now, out);
                    debug_assert!(ok, "can_accept was checked");
                    cur.sent += 1;
                    self.stats.lines_read += 1;
                }
            }
            // The rays go into the SRAM one per cycle once their data is here.
            if cur.arrived == cur.lines {
                let end = (cur.last_arrival + 1).max(cur.began + u64::from(job.rays));
                if now >= end {
                    self.finish(now);
                }
            }
        }
    }

    fn finish(&mut self, now: Cycle) {
        if let Some(cur) = self.cur.take() {
            self.stats.busy_cycles += now + 1 - cur.began;
            self.free_at = now + 1;
            self.events.push(DmaEvent {
                id: cur.job.id,
                rays: cur.job.rays,
                done: true,
            });
        }
    }
}
