//! Livelock detection: a run that can never finish although its threads keep issuing.
//!
//! The detector raises no false alarms: it fires only on a *proof* that the run cannot end.
//! It looks when nothing outside the threads has changed for a long time — no store to
//! global memory, no global-register, barrier, semaphore, stream or pipeline-mode
//! operation, no print, no `trax.stat` count, no halt ([`Shared::progress_count`]) — for
//! [`QUIET`] cycles (timing mode) or [`QUIET`] instructions per thread (functional mode,
//! `QUIET / quantum` rounds of the interleaving). It then runs each live thread alone, on
//! a copy, against the chip as it is, with every chip-wide change refused
//! ([`crate::chip::TmView`]), for up to [`ISOLATED_STEPS`] instructions, looking for a
//! repeated state (Brent's cycle finding over the pc, registers, coprocessor-2 registers,
//! random stream, stream records, shadow call stack, LL link and the whole local store).
//!
//! The run provably never ends when every running thread repeats a state that way
//! without a chip-wide change on the way, and every other live thread waits (barrier,
//! stream scheduler) with nothing that could release it but a chip-wide change: a
//! thread's instructions depend only on its own state and the chip's, nobody changes the
//! chip's, so every thread repeats its loop forever whatever the interleaving. What can
//! differ between the copy and the real thread — the retired-instruction count, read by
//! `trax.clock` and `rdhwr` (in timing mode the cycle) — makes states differ, so a loop
//! that reads the clock is never taken for a livelock; nor is one that counts (`i += 1`
//! never repeats a state before it wraps) or draws random numbers. Those are the misses:
//! a loop that spins with a counter, or longer than about `ISOLATED_STEPS / 3`
//! instructions, is not reported. A failed look doubles the quiet time before the next,
//! so a long legitimate computation costs a bounded, shrinking share of the run.

use crate::chip::{Effects, TmView};
use crate::exec::Stop;
use crate::thread::{RunState, Shared, Thread};
use crate::whereabouts::ThreadAt;

/// Quiet time before the first look: cycles in timing mode, instructions per thread in
/// functional mode (2^18: a fraction of a second of simulation on a small chip, longer
/// than any one-thread stretch without a store in the examples).
pub const QUIET: u64 = 1 << 18;

/// Instructions each thread runs alone, at most, to find its state repeating.
pub const ISOLATED_STEPS: u64 = 1 << 16;

/// Full compares of a thread's local store per look (a loop that keeps its registers but
/// writes its stack differently each time would otherwise cost one per iteration).
const MAX_LOCAL_COMPARES: u32 = 64;

/// A proven livelock, as found: when, and where every live thread is.
#[derive(Clone, Debug)]
pub struct Detection {
    /// Cycle of the look (timing mode).
    pub cycle: Option<u64>,
    /// Instructions executed by all threads at the look.
    pub instructions: u64,
    /// How long nothing outside the threads had changed: cycles (timing) or rounds times
    /// the quantum (functional).
    pub quiet: u64,
    /// Every live thread: a looping one at the first instruction of its loop (outermost
    /// frame, lowest address), state `looping: N instructions, forever`; a waiting one where it
    /// waits.
    pub threads: Vec<ThreadAt>,
    /// Threads halted.
    pub halted: u32,
}

/// When to look: the progress count and time of the last change seen.
#[derive(Clone, Debug)]
pub struct Watch {
    count: u64,
    since: u64,
    wait: u64,
}

impl Default for Watch {
    fn default() -> Self {
        Watch {
            count: 0,
            since: 0,
            wait: QUIET,
        }
    }
}

impl Watch {
    /// At time `now` with progress count `count`: whether a look is due (nothing changed
    /// for the current wait). A change restarts the wait at [`QUIET`].
    pub fn due(&mut self, now: u64, count: u64) -> bool {
        if count != self.count {
            *self = Watch {
                count,
                since: now,
                wait: QUIET,
            };
            return false;
        }
        now.saturating_sub(self.since) >= self.wait
    }

    /// A look found no livelock: wait twice as long for the next.
    pub fn failed(&mut self) {
        self.wait = self.wait.saturating_mul(2);
    }

    /// Time since the last change, at `now`.
    pub fn quiet(&self, now: u64) -> u64 {
        now.saturating_sub(self.since)
    }
}

/// Looks for a livelock among `threads` (every thread of the chip, halted ones too) on
/// chip `sh`: the live threads' places if the run provably never ends, else `None`.
pub fn prove<'t>(
    threads: impl Iterator<Item = &'t Thread>,
    sh: &Shared,
) -> Option<(Vec<ThreadAt>, u32)> {
    // Stream transfers in flight change the stream memory without an instruction.
    if sh.streams.transfers_pending() {
        return None;
    }
    let mut live = Vec::new();
    let mut halted = 0;
    let mut running = 0;
    for t in threads {
        match t.state {
            RunState::Halted => halted += 1,
            RunState::Running => {
                running += 1;
                live.push(isolated_loop(t, sh)?);
            }
            // Released only by a chip-wide change (or already releasable: not stuck).
            _ if t.releasable(sh) => return None,
            _ => live.push(ThreadAt::of(t)?),
        }
    }
    // With nobody running it is a deadlock, reported as such.
    (running > 0).then_some((live, halted))
}

/// Runs a copy of `t` alone until its state repeats: where its loop starts, or `None`
/// if it changes the chip, stops, or does not repeat within [`ISOLATED_STEPS`].
fn isolated_loop(t: &Thread, sh: &Shared) -> Option<ThreadAt> {
    let mut fx = Effects::default();
    let mut view = TmView {
        shared: sh,
        fx: &mut fx,
        cycle: 0,
    };
    let mut saved = t.clone();
    let mut hare = t.clone();
    let (mut power, mut lam) = (1u64, 0u64);
    let mut compares = 0u32;
    let mut steps = 0u64;
    // Brent: compare with the state saved at the last power of two.
    let lam = loop {
        if steps >= ISOLATED_STEPS || !step(&mut hare, &mut view) {
            return None;
        }
        steps += 1;
        lam += 1;
        if same_state(&hare, &saved, &mut compares)? {
            break lam;
        }
        if lam == power {
            saved.clone_from(&hare);
            power *= 2;
            lam = 0;
        }
    };
    // One more time round the loop: its first instruction (outermost frame, lowest pc).
    let mut best = (hare.calls.len(), hare.pc);
    let mut at = ThreadAt::of(&hare)?;
    for _ in 0..lam {
        if !step(&mut hare, &mut view) {
            return None;
        }
        let key = (hare.calls.len(), hare.pc);
        if key < best {
            best = key;
            at = ThreadAt::of(&hare)?;
        }
    }
    at.state = format!("looping: {lam} instructions, forever");
    Some(at)
}

/// Executes one instruction of an isolated thread: false if it stopped, or changed (or
/// would change) anything outside itself.
fn step(t: &mut Thread, view: &mut TmView<'_>) -> bool {
    matches!(t.step_once(view), Stop::Budget) && view.fx.changes == 0
}

/// Whether two states of one thread are the same for everything its future depends on
/// (not its retired count: what reads it puts it in a register). `None` when too many
/// local stores had to be compared.
fn same_state(a: &Thread, b: &Thread, compares: &mut u32) -> Option<bool> {
    if a.pc != b.pc
        || a.npc != b.npc
        || a.slot_pc != b.slot_pc
        || a.regs != b.regs
        || a.cop2 != b.cop2
        || a.rng != b.rng
        || a.ll_addr != b.ll_addr
        || a.calls != b.calls
        || a.dropped_calls != b.dropped_calls
        || a.stream_write != b.stream_write
        || a.stream_read != b.stream_read
        || !a
            .profile_open
            .iter()
            .map(|p| p.0)
            .eq(b.profile_open.iter().map(|p| p.0))
    {
        return Some(false);
    }
    *compares += 1;
    if *compares > MAX_LOCAL_COMPARES {
        return None;
    }
    Some(a.local == b.local)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_change_restarts_the_wait_and_a_failed_look_doubles_it() {
        let mut w = Watch::default();
        assert!(!w.due(10, 1));
        assert!(!w.due(10 + QUIET - 1, 1));
        assert!(w.due(10 + QUIET, 1));
        w.failed();
        assert!(!w.due(10 + QUIET, 1));
        assert!(w.due(10 + 2 * QUIET, 1));
        assert_eq!(w.quiet(10 + 2 * QUIET), 2 * QUIET);
        assert!(!w.due(20 + 2 * QUIET, 2));
        assert!(w.due(20 + 3 * QUIET, 2));
    }
}
