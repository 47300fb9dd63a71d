//! Host threads for the parallel phase: a fixed crew that, each round, runs one job per TM.
//!
//! Every TM has an owner (TMs are split evenly), and each host thread runs its own TMs
//! first, then takes any TM nobody has started yet: a host thread that the OS holds back
//! (a busy host) delays the round by at most the TM it is running. A round lasts tens of
//! microseconds, so waiting spins first and parks only when the wait drags on.
//!
//! Which host thread runs which TM never matters for results: the caller's jobs touch only
//! the TM's own state and sums that commute.

use std::sync::atomic::{AtomicBool, AtomicU64, AtomicUsize, Ordering::SeqCst};
use std::thread::{Scope, ScopedJoinHandle, Thread};
use std::time::Duration;

/// Spins before parking while waiting.
const SPINS_BEFORE_PARK: u32 = 1_000;

/// A value alone in its cache lines (host threads write different ones without ping-pong).
#[repr(align(128))]
struct Padded<T>(T);

impl<T> std::ops::Deref for Padded<T> {
    type Target = T;
    fn deref(&self) -> &T {
        &self.0
    }
}

/// The round protocol shared by the leader (host thread 0) and the members.
pub(crate) struct Rounds {
    round: Padded<AtomicU64>,
    /// Per TM: the last round that claimed it.
    claimed: Vec<Padded<AtomicU64>>,
    /// Per host thread: TMs it finished in the current round.
    done: Vec<Padded<AtomicUsize>>,
    stop: Padded<AtomicBool>,
    /// Host threads (leader included).
    threads: usize,
    /// Per host thread: parked, waiting for a round.
    parked: Vec<Padded<AtomicBool>>,
    leader: Thread,
}

impl Rounds {
    /// The protocol for `tms` TMs on `threads` host threads (the caller is the leader).
    pub fn new(tms: usize, threads: usize) -> Rounds {
        Rounds {
            round: Padded(AtomicU64::new(0)),
            claimed: (0..tms).map(|_| Padded(AtomicU64::new(0))).collect(),
            done: (0..threads).map(|_| Padded(AtomicUsize::new(0))).collect(),
            stop: Padded(AtomicBool::new(false)),
            threads,
            parked: (0..threads)
                .map(|_| Padded(AtomicBool::new(false)))
                .collect(),
            leader: std::thread::current(),
        }
    }

    /// The host thread that runs TM `tm` when nobody is late.
    pub fn owner(&self, tm: usize) -> usize {
        tm * self.threads / self.claimed.len()
    }

    /// Starts the members (host threads 1..) in `scope`; each round they run
    /// `job(thread, tm)` for the TMs they claim, until [`Self::finish`].
    pub fn spawn<'s, 'e, F>(
        &'s self,
        scope: &'s Scope<'s, 'e>,
        job: &'s F,
    ) -> Vec<ScopedJoinHandle<'s, ()>>
    where
        F: Fn(usize, &[usize]) + Sync,
    {
        (1..self.threads)
            .map(|w| {
                scope.spawn(move || {
                    let mut seen = 0;
                    loop {
                        let news = || self.round.load(SeqCst) != seen || self.stop.load(SeqCst);
                        wait_for(news, &self.parked[w]);
                        if self.stop.load(SeqCst) {
                            return;
                        }
                        seen = self.round.load(SeqCst);
                        self.work(w, seen, &mut |ks| job(w, ks));
                    }
                })
            })
            .collect()
    }

    /// Runs a round: wakes the members, runs `job(tm)` for the TMs the leader claims, and
    /// waits until every TM is done. Returns false if a member died (it panicked; the scope
    /// re-raises the panic when it joins).
    pub fn run(&self, crew: &[ScopedJoinHandle<'_, ()>], job: &mut dyn FnMut(&[usize])) -> bool {
        for d in &self.done {
            d.store(0, SeqCst);
        }
        let round = self.round.fetch_add(1, SeqCst) + 1;
        self.wake(crew);
        self.work(0, round, job);
        let tms = self.claimed.len();
        loop {
            let all_done = || self.done.iter().map(|d| d.load(SeqCst)).sum::<usize>() >= tms;
            let died = || crew.iter().any(|h| h.is_finished());
            wait_for(|| all_done() || died(), &self.parked[0]);
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

    /// Claims and runs TMs of `round`: host thread `w`'s own first, then any left.
    fn work(&self, w: usize, round: u64, job: &mut dyn FnMut(&[usize])) {
        let tms = self.claimed.len();
        let claim = |k: usize| {
            self.claimed[k]
                .compare_exchange(round - 1, round, SeqCst, SeqCst)
                .is_ok()
        };
        let finished = |n: usize| {
            self.done[w].fetch_add(n, SeqCst);
            if self.parked[0].load(SeqCst) && self.parked[0].swap(false, SeqCst) {
                self.leader.unpark();
            }
        };
        // Own TMs in one batch (one set of locks), then any left, one at a time.
        let own: Vec<usize> = (0..tms)
            .filter(|&k| self.owner(k) == w && claim(k))
            .collect();
        if !own.is_empty() {
            job(&own);
            finished(own.len());
        }
        for k in 0..tms {
            if self.owner(k) != w && claim(k) {
                job(&[k]);
                finished(1);
            }
        }
    }

    fn wake(&self, crew: &[ScopedJoinHandle<'_, ()>]) {
        for (i, h) in crew.iter().enumerate() {
            if self.parked[i + 1].load(SeqCst) && self.parked[i + 1].swap(false, SeqCst) {
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
        std::thread::park_timeout(Duration::from_millis(1));
    }
    parked.store(false, SeqCst);
}
