//! Host threads for the parallel phase: a fixed crew that runs one job per round, started
//! and awaited by the leader. A round lasts tens of microseconds, so waiting spins first
//! and parks the host thread only when the wait drags on (a busy host with fewer free
//! cores than simulation threads).
//!
//! The leader publishes a round number; every member runs the round's job once and
//! counts itself done. Data is handed over through the caller's own locks (each member
//! locks what it works on), which also order memory between rounds.

use std::sync::atomic::{AtomicBool, AtomicU64, AtomicUsize, Ordering::SeqCst};
use std::thread::{Scope, ScopedJoinHandle, Thread};

/// Spins before parking while waiting.
const SPINS_BEFORE_PARK: u32 = 1_000;

/// The round protocol shared by the leader and the members.
pub(crate) struct Rounds {
    round: AtomicU64,
    done: AtomicUsize,
    stop: AtomicBool,
    /// Per member (index 0 unused): parked, waiting for a round.
    parked: Vec<AtomicBool>,
    leader: Thread,
    leader_parked: AtomicBool,
}

impl Rounds {
    /// The protocol for a leader (the calling thread) and `members` members.
    pub fn new(members: usize) -> Rounds {
        Rounds {
            round: AtomicU64::new(0),
            done: AtomicUsize::new(0),
            stop: AtomicBool::new(false),
            parked: (0..=members).map(|_| AtomicBool::new(false)).collect(),
            leader: std::thread::current(),
            leader_parked: AtomicBool::new(false),
        }
    }

    /// Starts the members in `scope`; member `i` (1-based) runs `job(i)` once per round
    /// until [`Self::finish`].
    pub fn spawn<'s, 'e, F>(
        &'s self,
        scope: &'s Scope<'s, 'e>,
        job: &'s F,
    ) -> Vec<ScopedJoinHandle<'s, ()>>
    where
        F: Fn(usize) + Sync,
    {
        (1..self.parked.len())
            .map(|i| {
                scope.spawn(move || {
                    let mut seen = 0;
                    loop {
                        let news = || self.round.load(SeqCst) != seen || self.stop.load(SeqCst);
                        wait_for(news, &self.parked[i]);
                        if self.stop.load(SeqCst) {
                            return;
                        }
                        seen = self.round.load(SeqCst);
                        job(i);
                        self.done.fetch_add(1, SeqCst);
                        if self.leader_parked.swap(false, SeqCst) {
                            self.leader.unpark();
                        }
                    }
                })
            })
            .collect()
    }

    /// Starts a round (the leader then does its own share).
    pub fn start(&self, crew: &[ScopedJoinHandle<'_, ()>]) {
        self.done.store(0, SeqCst);
        self.round.fetch_add(1, SeqCst);
        self.wake(crew);
    }

    /// Waits until every member finished the round. Returns false if a member thread
    /// ended (it panicked; the scope re-raises the panic when it joins).
    pub fn wait(&self, crew: &[ScopedJoinHandle<'_, ()>]) -> bool {
        loop {
            let all_done = || self.done.load(SeqCst) >= crew.len();
            let died = || crew.iter().any(|h| h.is_finished());
            wait_for(|| all_done() || died(), &self.leader_parked);
            if all_done() {
                return true;
            }
            if died() {
                return false;
            }
        }
    }

    /// Ends the members' loops.
    pub fn finish(&self, crew: &[ScopedJoinHandle<'_, ()>]) {
        self.stop.store(true, SeqCst);
        self.wake(crew);
    }

    fn wake(&self, crew: &[ScopedJoinHandle<'_, ()>]) {
        for (i, h) in crew.iter().enumerate() {
            if self.parked[i + 1].swap(false, SeqCst) {
                h.thread().unpark();
            }
        }
    }
}

/// Spins, then parks (announcing it in `parked`), until `ready()`. Whoever makes `ready`
/// true afterwards swaps `parked` to false and unparks this thread; checking `ready` after
/// announcing closes the race with a wake-up sent just before.
fn wait_for(ready: impl Fn() -> bool, parked: &AtomicBool) {
    for _ in 0..SPINS_BEFORE_PARK {
        if ready() {
            return;
        }
        std::hint::spin_loop();
    }
    while !ready() {
        parked.store(true, SeqCst);
        if ready() {
            parked.store(false, SeqCst);
            return;
        }
        // A timeout, so a leader notices a member that died instead of waking it.
        std::thread::park_timeout(std::time::Duration::from_millis(1));
    }
    parked.store(false, SeqCst);
}
