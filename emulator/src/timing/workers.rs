//! Host threads for the parallel phase: a fixed crew that, each round, runs one job per TM.
//!
//! A round lasts a few microseconds and moving a cache line between two cores costs a
//! fifth of one, so the protocol is built to move as few lines as possible:
//! - the leader (host thread 0) publishes the round number and its window in one line;
//!   nothing else is written by the leader during a round;
//! - every TM has an owner, which claims it in the TM's own line and reports finished TMs
//!   in a line of its own, with the OR of the flags their jobs returned (so the leader
//!   learns from one line per host thread whether it must look at that thread's TMs);
//! - TM and chip state is handed over by this protocol rather than by locks
//!   ([`RoundCell`]), so a round moves no lock words between cores.
//!
//! Between rounds the leader may give TMs new owners ([`Rounds::set_owner`], chosen by
//! [`rebalance`]) to balance the host threads' loads. A host thread that has waited a
//! while for the others (the OS held one back) takes their unclaimed TMs, so a late host
//! thread delays a round by at most the TM it is running. Waiting spins first and parks
//! when it drags on.
//!
//! Which host thread runs which TM never matters for results: the caller's jobs touch only
//! the TM's own state and sums that commute.

use std::cell::UnsafeCell;
use std::sync::atomic::{fence, AtomicBool, AtomicU64, AtomicUsize, Ordering::*};
use std::thread::{Scope, ScopedJoinHandle, Thread};
use std::time::{Duration, Instant};

/// How long a host thread waits for the others to finish a round before it takes their
/// unclaimed TMs (rounds last microseconds; an OS time slice, milliseconds).
const TAKE_AFTER: Duration = Duration::from_micros(50);

/// How long a host thread spins before parking.
const PARK_AFTER: Duration = Duration::from_micros(200);

/// `Head::round` value that ends the members' loops.
const STOP: u64 = u64::MAX;

/// Bits of a `done` word below the round: flags (8 bits) above the count.
const COUNT_BITS: u32 = 16;
const ROUND_SHIFT: u32 = COUNT_BITS + 8;

/// A value alone in its cache lines (host threads write different ones without ping-pong).
#[repr(align(128))]
struct Padded<T>(T);

impl<T> std::ops::Deref for Padded<T> {
    type Target = T;
    fn deref(&self) -> &T {
        &self.0
    }
}

/// What the leader publishes for a round (one cache line).
struct Head {
    /// The round being run ([`STOP`] ends the crew).
    round: AtomicU64,
    /// The round's window: `from..to`, in simulated cycles.
    from: AtomicU64,
    to: AtomicU64,
}

/// What a host thread has finished of a round: TMs and the OR of their jobs' flags.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
struct Finished {
    count: usize,
    flags: u8,
}

impl Finished {
    /// The `done` word of `self` in `round`.
    fn word(self, round: u64) -> u64 {
        (round << ROUND_SHIFT) | u64::from(self.flags) << COUNT_BITS | self.count as u64
    }

    /// What a `done` word says of `round` (nothing if it is about another round).
    fn of(word: u64, round: u64) -> Finished {
        if word >> ROUND_SHIFT != round {
            return Finished::default();
        }
        Finished {
            count: (word & ((1 << COUNT_BITS) - 1)) as usize,
            flags: (word >> COUNT_BITS) as u8,
        }
    }
}

/// The round protocol shared by the leader (host thread 0) and the members.
pub(crate) struct Rounds {
    head: Padded<Head>,
    /// Per TM: the last round that claimed it.
    claimed: Vec<Padded<AtomicU64>>,
    /// Per TM: the host thread that runs it unless it is late (set between rounds).
    owner: Vec<AtomicUsize>,
    /// Per host thread: a [`Finished::word`]: the TMs it finished (its own or taken) in a
    /// round.
    done: Vec<Padded<AtomicU64>>,
    /// Per host thread: parked, waiting.
    parked: Vec<Padded<AtomicBool>>,
    leader: Thread,
}

impl Rounds {
    /// The protocol for `tms` TMs on `threads` host threads (the caller is the leader);
    /// TMs start split evenly in index order.
    pub fn new(tms: usize, threads: usize) -> Rounds {
        assert!(
            (1..=tms).contains(&threads) && tms < 1 << COUNT_BITS,
            "1..=tms host threads"
        );
        Rounds {
            head: Padded(Head {
                round: AtomicU64::new(0),
                from: AtomicU64::new(0),
                to: AtomicU64::new(0),
            }),
            claimed: (0..tms).map(|_| Padded(AtomicU64::new(0))).collect(),
            owner: (0..tms)
                .map(|k| AtomicUsize::new(k * threads / tms))
                .collect(),
            done: (0..threads).map(|_| Padded(AtomicU64::new(0))).collect(),
            parked: (0..threads)
                .map(|_| Padded(AtomicBool::new(false)))
                .collect(),
            leader: std::thread::current(),
        }
    }

    /// Host threads (leader included).
    pub fn threads(&self) -> usize {
        self.done.len()
    }

    /// The host thread that runs TM `tm` when nobody is late.
    pub fn owner(&self, tm: usize) -> usize {
        self.owner[tm].load(Relaxed)
    }

    /// Makes host thread `w` the owner of TM `tm` from the next round on. Only the leader
    /// calls it, between rounds.
    pub fn set_owner(&self, tm: usize, w: usize) {
        assert!(w < self.threads(), "host thread in range");
        // Released by the next round's start.
        self.owner[tm].store(w, Relaxed);
    }

    /// Starts the members (host threads 1..) in `scope`; each round they run
    /// `job(thread, tm, window) -> flags` for the TMs they claim, until [`Self::finish`].
    pub fn spawn<'s, 'e, F>(
        &'s self,
        scope: &'s Scope<'s, 'e>,
        job: &'s F,
    ) -> Vec<ScopedJoinHandle<'s, ()>>
    where
        F: Fn(usize, usize, (u64, u64)) -> u8 + Sync,
    {
        (1..self.threads())
            .map(|w| {
                scope.spawn(move || {
                    let round = || self.head.round.load(Acquire);
                    let (mut seen, mut window) = (0, (0, 0));
                    let mut finished = Finished::default();
                    loop {
                        // Between rounds: take what a late host thread left of the last
                        // one, until the next begins.
                        let next = || round() != seen;
                        self.wait(w, seen, &mut finished, &next, &mut |k| job(w, k, window));
                        seen = round();
                        if seen == STOP {
                            return;
                        }
                        window = self.window();
                        finished = self.work(w, seen, &mut |k| job(w, k, window));
                    }
                })
            })
            .collect()
    }

    /// Runs a round over `window`: wakes the members, runs `job(tm, window) -> flags` for
    /// the TMs the leader claims, and waits until every TM is done. Returns the OR of all
    /// jobs' flags, or `None` if a member died (it panicked; the scope re-raises the panic
    /// when it joins).
    pub fn run(
        &self,
        crew: &[ScopedJoinHandle<'_, ()>],
        window: (u64, u64),
        job: &mut dyn FnMut(usize, (u64, u64)) -> u8,
    ) -> Option<u8> {
        let h = &self.head;
        h.from.store(window.0, Relaxed);
        h.to.store(window.1, Relaxed);
        let round = h.round.load(Relaxed) + 1;
        h.round.store(round, Release);
        self.wake(crew);
        let mut finished = self.work(0, round, &mut |k| job(k, window));
        let tms = self.claimed.len();
        let total = || {
            self.done.iter().fold(Finished::default(), |a, d| {
                let f = Finished::of(d.load(Acquire), round);
                Finished {
                    count: a.count + f.count,
                    flags: a.flags | f.flags,
                }
            })
        };
        let all_done = || total().count >= tms;
        let died = || crew.iter().any(|h| h.is_finished());
        let over = || all_done() || died();
        self.wait(0, round, &mut finished, &over, &mut |k| job(k, window));
        let t = total();
        (t.count >= tms).then_some(t.flags)
    }

    /// Ends the members' loops.
    pub fn finish(&self, crew: &[ScopedJoinHandle<'_, ()>]) {
        self.head.round.store(STOP, Release);
        self.wake(crew);
    }

    fn window(&self) -> (u64, u64) {
        (self.head.from.load(Relaxed), self.head.to.load(Relaxed))
    }

    /// Runs host thread `w`'s own TMs of `round`.
    fn work(&self, w: usize, round: u64, job: &mut dyn FnMut(usize) -> u8) -> Finished {
        let mut finished = Finished::default();
        for k in 0..self.claimed.len() {
            if self.owner(k) == w && self.claim(k, round) {
                self.run_job(w, round, k, &mut finished, job);
            }
        }
        finished
    }

    /// Claims TM `k` for `round`; false if it is taken (or `round` is over).
    fn claim(&self, k: usize, round: u64) -> bool {
        let c = &self.claimed[k];
        // Look before writing: a failed compare-exchange would still take the line.
        c.load(Relaxed) == round - 1
            && c.compare_exchange(round - 1, round, AcqRel, Relaxed)
                .is_ok()
    }

    /// Runs the job of TM `k`, claimed by host thread `w` in `round`, and reports it.
    fn run_job(
        &self,
        w: usize,
        round: u64,
        k: usize,
        finished: &mut Finished,
        job: &mut dyn FnMut(usize) -> u8,
    ) {
        finished.flags |= job(k);
        finished.count += 1;
        self.done[w].store(finished.word(round), Release);
        // Orders the store before the look at `parked` (pairs with the fence in `wait`).
        fence(SeqCst);
        if self.parked[0].load(Relaxed) && self.parked[0].swap(false, AcqRel) {
            self.leader.unpark();
        }
    }

    /// Host thread `w` waits until `ready()`; after [`TAKE_AFTER`] it runs the TMs of
    /// `round` that others left unclaimed (adding them to `finished`), after
    /// [`PARK_AFTER`] it parks.
    fn wait(
        &self,
        w: usize,
        round: u64,
        finished: &mut Finished,
        ready: &dyn Fn() -> bool,
        job: &mut dyn FnMut(usize) -> u8,
    ) {
        let start = Instant::now();
        let mut took = round == 0;
        let mut spins = 0u32;
        while !ready() {
            std::hint::spin_loop();
            spins += 1;
            if !spins.is_multiple_of(64) {
                continue;
            }
            let waited = start.elapsed();
            if !took && waited >= TAKE_AFTER {
                took = true;
                for k in 0..self.claimed.len() {
                    if self.claim(k, round) {
                        self.run_job(w, round, k, finished, job);
                    }
                }
            }
            if waited >= PARK_AFTER {
                break;
            }
        }
        let parked = &self.parked[w];
        while !ready() {
            parked.store(true, Relaxed);
            // Orders the announcement before the look at `ready` (pairs with the fences
            // in `run_job` and `wake`).
            fence(SeqCst);
            if ready() {
                parked.store(false, Relaxed);
                return;
            }
            // A timeout, so a leader notices a member that died instead of waking it.
            std::thread::park_timeout(Duration::from_millis(1));
        }
        parked.store(false, Relaxed);
    }

    fn wake(&self, crew: &[ScopedJoinHandle<'_, ()>]) {
        // Orders the caller's store before the looks at `parked` (pairs with `wait`).
        fence(SeqCst);
        for (i, h) in crew.iter().enumerate() {
            if self.parked[i + 1].load(Relaxed) && self.parked[i + 1].swap(false, AcqRel) {
                h.thread().unpark();
            }
        }
    }
}

/// New owners for TMs that balance the host threads' loads better: `loads[k]` is TM `k`'s
/// recent work, `owner[k]` its host thread (of `threads`). Moves or swaps single TMs
/// while that lowers the busiest host thread's load by at least `min_gain` of it;
/// returns the changed `(tm, owner)` pairs (none when balanced enough).
pub(crate) fn rebalance(
    loads: &[u64],
    owner: &[usize],
    threads: usize,
    min_gain: f64,
) -> Vec<(usize, usize)> {
    let original = owner;
    let mut owner = owner.to_vec();
    let mut group = vec![0u64; threads];
    for (k, &l) in loads.iter().enumerate() {
        group[owner[k]] += l;
    }
    for _ in 0..loads.len() {
        let hi = (0..threads)
            .max_by_key(|&w| (group[w], w))
            .expect("host threads");
        // The best single move (`j` = None) or swap between `hi` and another host thread:
        // (the larger of the two new loads, tm leaving `hi`, other host thread, tm coming).
        let mut best: Option<(u64, usize, usize, Option<usize>)> = None;
        for k in (0..loads.len()).filter(|&k| owner[k] == hi) {
            for w in (0..threads).filter(|&w| w != hi) {
                let candidates = std::iter::once(None)
                    .chain((0..loads.len()).filter(|&j| owner[j] == w).map(Some));
                for j in candidates {
                    let lj = j.map_or(0, |j| loads[j]);
                    let a = group[hi] - loads[k] + lj;
                    let b = group[w] + loads[k] - lj;
                    let worst = a.max(b);
                    if best.is_none_or(|(m, ..)| worst < m) {
                        best = Some((worst, k, w, j));
                    }
                }
            }
        }
        let Some((worst, k, w, j)) = best else { break };
        if (group[hi] - worst.min(group[hi])) as f64 <= min_gain * group[hi] as f64 {
            break;
        }
        let lj = j.map_or(0, |j| loads[j]);
        group[hi] = group[hi] - loads[k] + lj;
        group[w] = group[w] + loads[k] - lj;
        owner[k] = w;
        if let Some(j) = j {
            owner[j] = hi;
        }
    }
    (0..loads.len())
        .filter(|&k| owner[k] != original[k])
        .map(|k| (k, owner[k]))
        .collect()
}

/// State handed between host threads by the round protocol instead of a lock.
///
/// The protocol gives every access a happens-before order: the leader's writes before
/// a round are released by its store of the round number and acquired by each member's
/// load of it; a TM is claimed by exactly one host thread per round (a compare-exchange
/// of the TM's claim word from the previous round to this one, so a claim can never
/// succeed for a round that is over); a host thread's writes to a TM are released by its
/// report of the finished TM and acquired by the leader, which waits for every TM's report
/// before it touches TM or chip state between rounds.
pub(crate) struct RoundCell<T>(UnsafeCell<T>);

// SAFETY: access goes through `get`/`get_mut`, whose callers guarantee the exclusion a
// lock would (see their contracts); `T: Send` lets the value move between host threads.
unsafe impl<T: Send + Sync> Sync for RoundCell<T> {}

impl<T> RoundCell<T> {
    pub fn new(v: T) -> Self {
        RoundCell(UnsafeCell::new(v))
    }

    /// Shared access.
    ///
    /// # Safety
    /// No `&mut` to the value may be alive at the same time: call it inside a round job
    /// (while the leader waits) for state nobody changes during rounds, or on the leader
    /// between rounds.
    pub unsafe fn get(&self) -> &T {
        // SAFETY: the caller guarantees no live `&mut` (see above).
        unsafe { &*self.0.get() }
    }

    /// Exclusive access.
    ///
    /// # Safety
    /// No other reference to the value may be alive at the same time: call it inside the
    /// round job of the TM the value belongs to (the protocol gives it to one host
    /// thread), or on the leader between rounds.
    #[allow(clippy::mut_from_ref)]
    pub unsafe fn get_mut(&self) -> &mut T {
        // SAFETY: the caller guarantees exclusive access (see above).
        unsafe { &mut *self.0.get() }
    }

    pub fn into_inner(self) -> T {
        self.0.into_inner()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn groups(loads: &[u64], owner: &[usize], threads: usize) -> Vec<u64> {
        let mut g = vec![0; threads];
        for (k, &l) in loads.iter().enumerate() {
            g[owner[k]] += l;
        }
        g
    }

    #[test]
    fn rebalance_evens_out_host_threads() {
        // Two heavy TMs on host thread 0: one swap balances.
        let loads = [10, 10, 1, 1];
        let mut owner = vec![0, 0, 1, 1];
        let moves = rebalance(&loads, &owner, 2, 0.01);
        assert!(!moves.is_empty());
        for (k, w) in moves {
            owner[k] = w;
        }
        assert_eq!(groups(&loads, &owner, 2), [11, 11]);
        // Balanced: nothing moves.
        assert!(rebalance(&[5, 5, 5, 5], &[0, 0, 1, 1], 2, 0.01).is_empty());
        // One TM dominates: no move gains enough.
        assert!(rebalance(&[100, 1, 1, 1], &[0, 0, 1, 1], 2, 0.01).is_empty());
    }

    #[test]
    fn rebalance_never_raises_the_busiest_load() {
        let mut seed = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = |m: u64| {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            seed % m
        };
        for _ in 0..500 {
            let threads = 1 + next(4) as usize;
            let tms = threads + next(8) as usize;
            let loads: Vec<u64> = (0..tms).map(|_| next(1000)).collect();
            let mut owner: Vec<usize> = (0..tms).map(|_| next(threads as u64) as usize).collect();
            let before = *groups(&loads, &owner, threads).iter().max().unwrap();
            for (k, w) in rebalance(&loads, &owner, threads, 0.01) {
                assert!(w < threads);
                owner[k] = w;
            }
            let after = *groups(&loads, &owner, threads).iter().max().unwrap();
            assert!(after <= before, "{loads:?}: {before} -> {after}");
        }
    }

    /// Runs `rounds` rounds of `tms` TMs on `threads` host threads; each job counts its TM
    /// in a [`RoundCell`] and checks it runs once per round. `slow` host threads sleep in
    /// every job (others take their TMs). Returns per TM: rounds run, and per host thread:
    /// jobs run.
    fn crew_counts(
        tms: usize,
        threads: usize,
        rounds: u64,
        slow: &[usize],
    ) -> (Vec<u64>, Vec<u64>) {
        let jobs: Vec<AtomicU64> = (0..threads).map(|_| AtomicU64::new(0)).collect();
        let cells: Vec<RoundCell<(u64, u64)>> = (0..tms).map(|_| RoundCell::new((0, 0))).collect();
        let protocol = Rounds::new(tms, threads);
        let job = |w: usize, k: usize, (from, _to): (u64, u64)| -> u8 {
            jobs[w].fetch_add(1, Relaxed);
            if slow.contains(&w) {
                std::thread::sleep(Duration::from_micros(300));
            }
            // SAFETY: the round job of TM `k`.
            let c = unsafe { cells[k].get_mut() };
            assert_eq!(c.1, from, "TM {k} ran twice or skipped a round");
            c.0 += 1;
            c.1 = from + 1;
            // Flags: TM 1 reports on odd rounds.
            u8::from(k == 1 && from % 2 == 1) << 3
        };
        std::thread::scope(|scope| {
            let crew = protocol.spawn(scope, &job);
            for r in 0..rounds {
                if r == rounds / 2 {
                    // Move every TM to the next host thread.
                    for k in 0..tms {
                        protocol.set_owner(k, (protocol.owner(k) + 1) % threads);
                    }
                }
                let flags = protocol.run(&crew, (r, r + 1), &mut |k, win| job(0, k, win));
                assert_eq!(flags, Some(u8::from(r % 2 == 1) << 3));
                for c in &cells {
                    // SAFETY: the leader between rounds.
                    assert_eq!(unsafe { c.get() }.1, r + 1);
                }
            }
            protocol.finish(&crew);
        });
        let per_tm = cells.into_iter().map(|c| c.into_inner().0).collect();
        (per_tm, jobs.iter().map(|j| j.load(Relaxed)).collect())
    }

    #[test]
    fn every_tm_runs_once_per_round() {
        for threads in 1..=3 {
            let (per_tm, jobs) = crew_counts(5, threads, 3000, &[]);
            assert_eq!(per_tm, vec![3000; 5]);
            assert_eq!(jobs.iter().sum::<u64>(), 5 * 3000);
        }
    }

    #[test]
    fn late_host_threads_leave_their_tms_to_others() {
        // A slow host thread's second TM of each round is taken by the other one.
        let (per_tm, jobs) = crew_counts(4, 2, 40, &[1]);
        assert_eq!(per_tm, vec![40; 4]);
        assert!(jobs[0] > 2 * 40, "{jobs:?}");
        let (per_tm, jobs) = crew_counts(6, 3, 40, &[0, 2]);
        assert_eq!(per_tm, vec![40; 6]);
        assert!(jobs[1] > 2 * 40, "{jobs:?}");
    }
}
