//! What an executing thread may touch beyond its own registers and local store.
//!
//! The interpreter ([`crate::exec`]) is generic over [`Chip`]. Two views exist:
//! - [`Shared`] itself: exclusive access to the whole chip (functional mode, the debugger,
//!   the profiler, and the serial phase of the timing model).
//! - [`TmView`]: what one TM may touch while other TMs run on other host threads (the
//!   parallel phase of the timing model): global memory and the chip state are read-only,
//!   prints and counters go to the TM's own [`Effects`], and anything that would change
//!   chip-wide state (a store to global memory, a global-register, barrier, semaphore or
//!   stream operation) is refused before it has any effect, so the caller can replay it
//!   later with exclusive access ([`crate::exec::Stop::Defer`]). `trax.halt` only changes
//!   the thread; the caller accounts for the chip's live-thread count.

use crate::memory::MemFault;
use crate::thread::{Shared, NUM_STATS};

/// The chip as seen by an executing thread.
pub trait Chip {
    /// Read access to everything (memory, program, chip state).
    fn shared(&self) -> &Shared;
    /// Stores `v` at `addr` (global memory or `local`). `Ok(false)`: the address is in
    /// global memory and this view may not write it; nothing was written.
    fn store<const N: usize>(
        &mut self,
        local: &mut [u8],
        addr: u32,
        v: [u8; N],
    ) -> Result<bool, MemFault>;
    /// Whether stores to global memory are allowed.
    fn writes_global(&self) -> bool;
    /// Chip-wide state for the operations that change it; `None` in a parallel phase.
    fn exclusive(&mut self) -> Option<&mut Shared>;
    /// Where print instructions write.
    fn output(&mut self) -> &mut Vec<u8>;
    /// `trax.stat` counters.
    fn stats(&mut self) -> &mut [u64; NUM_STATS];
    /// Instructions counted per profile region (`trax.profbegin/profend`).
    fn profile(&mut self) -> &mut [u64; 32];
    /// Told the address of every data load before it reads memory (global memory or the
    /// local store). Nothing by default; sampled simulation's functional warming
    /// ([`crate::timing::sample`]) warms the caches with it.
    #[inline(always)]
    fn note_load(&mut self, _addr: u32) {}
}

impl Chip for Shared {
    #[inline(always)]
    fn shared(&self) -> &Shared {
        self
    }
    #[inline(always)]
    fn store<const N: usize>(
        &mut self,
        local: &mut [u8],
        addr: u32,
        v: [u8; N],
    ) -> Result<bool, MemFault> {
        self.mem.write(local, addr, v).map(|()| true)
    }
    #[inline(always)]
    fn writes_global(&self) -> bool {
        true
    }
    #[inline(always)]
    fn exclusive(&mut self) -> Option<&mut Shared> {
        Some(self)
    }
    fn output(&mut self) -> &mut Vec<u8> {
        self.changes += 1;
        &mut self.output
    }
    fn stats(&mut self) -> &mut [u64; NUM_STATS] {
        self.changes += 1;
        &mut self.stats
    }
    fn profile(&mut self) -> &mut [u64; 32] {
        &mut self.profile
    }
}

/// Output and counters one TM produced during a parallel phase; merged into [`Shared`]
/// afterwards in TM order (so the result does not depend on how TMs were spread over
/// host threads).
#[derive(Clone, Debug)]
pub struct Effects {
    /// Printed text.
    pub output: Vec<u8>,
    /// `trax.stat` increments.
    pub stats: [u64; NUM_STATS],
    /// Profile-region instruction counts.
    pub profile: [u64; 32],
    /// (cycle, offset in `output` where that cycle's prints start), in cycle order.
    cycle_starts: Vec<(u64, usize)>,
    /// Whether anything was printed since the last merge (counters are sums: they can be
    /// merged whenever).
    pub dirty: bool,
    /// Prints and counts so far (never reset: the livelock detector's progress).
    pub changes: u64,
}

impl Default for Effects {
    fn default() -> Self {
        Effects {
            output: Vec::new(),
            stats: [0; NUM_STATS],
            profile: [0; 32],
            cycle_starts: Vec::new(),
            dirty: false,
            changes: 0,
        }
    }
}

impl Effects {
    /// Notes that what is printed from now on is printed at `cycle` (non-decreasing).
    fn at_cycle(&mut self, cycle: u64) {
        if self.cycle_starts.last().is_none_or(|&(c, _)| c != cycle) {
            self.cycle_starts.push((cycle, self.output.len()));
        }
    }

    /// Adds these effects to `into` and clears them; with `until`, prints made after that
    /// cycle are dropped (the run ended there).
    pub fn merge_into(&mut self, into: &mut Effects, until: Option<u64>) {
        if let Some(limit) = until {
            if let Some(&(_, at)) = self.cycle_starts.iter().find(|(c, _)| *c > limit) {
                self.output.truncate(at);
            }
        }
        self.cycle_starts.clear();
        self.dirty = false;
        into.output.append(&mut self.output);
        self.move_counts(&mut into.stats, &mut into.profile);
    }

    /// Adds these counters and prints to the chip and clears them.
    pub fn fold_into(&mut self, sh: &mut Shared) {
        sh.output.append(&mut self.output);
        self.move_counts(&mut sh.stats, &mut sh.profile);
    }

    /// Adds the counters to `stats` and `profile` and zeroes them here.
    fn move_counts(&mut self, stats: &mut [u64; NUM_STATS], profile: &mut [u64; 32]) {
        for (d, s) in stats.iter_mut().zip(&mut self.stats) {
            *d += std::mem::take(s);
        }
        for (d, s) in profile.iter_mut().zip(&mut self.profile) {
            *d += std::mem::take(s);
        }
    }
}

/// One TM's view during a parallel phase: read-only chip, own effects.
pub struct TmView<'a> {
    /// The chip, read-only.
    pub shared: &'a Shared,
    /// Where this TM's prints and counters go.
    pub fx: &'a mut Effects,
    /// The current cycle (prints are stamped with it).
    pub cycle: u64,
}

impl Chip for TmView<'_> {
    #[inline(always)]
    fn shared(&self) -> &Shared {
        self.shared
    }
    #[inline(always)]
    fn store<const N: usize>(
        &mut self,
        local: &mut [u8],
        addr: u32,
        v: [u8; N],
    ) -> Result<bool, MemFault> {
        self.shared.mem.write_local(local, addr, v)
    }
    #[inline(always)]
    fn writes_global(&self) -> bool {
        false
    }
    #[inline(always)]
    fn exclusive(&mut self) -> Option<&mut Shared> {
        None
    }
    fn output(&mut self) -> &mut Vec<u8> {
        self.fx.changes += 1;
        self.fx.dirty = true;
        self.fx.at_cycle(self.cycle);
        &mut self.fx.output
    }
    fn stats(&mut self) -> &mut [u64; NUM_STATS] {
        self.fx.changes += 1;
        &mut self.fx.stats
    }
    fn profile(&mut self) -> &mut [u64; 32] {
        &mut self.fx.profile
    }
}
