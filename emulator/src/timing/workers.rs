//! Host threads for the parallel phase: a fixed crew that, each round, runs one job per TM.
//!
//! A round lasts a few microseconds and moving a cache line between two cores costs a
//! fifth of one, so the protocol is built to move as few lines as possible:
//! - the leader (host thread 0) publishes a *batch* of rounds (first round, window,
//!   rules) in one line, under a sequence lock (a member late to read it must not mix it
//!   with the next batch); nothing else is written by the leader during a batch;
//! - every TM has an owner, which claims it in the TM's own line; each host thread reports
//!   the TMs it finished once a round, in a line of its own, with the OR of the flags their
//!   jobs returned;
//! - TM and chip state is handed over by this protocol rather than by locks
//!   ([`RoundCell`]), so a round moves no lock words between cores.
//!
//! After a round every host thread reads the others' reports. If the round's flags are
//! the batch's *free* flags (the caller's way of saying "nothing for the serial phase")
//! and the next window fits the batch, every host thread goes on to the next round by
//! itself: the same reports give every host thread the same verdict, and the leader's
//! serial phase and its start signal are skipped. Otherwise the batch ends, and the
//! leader runs the serial phase and publishes the next batch.
//!
//! Between batches the leader may give TMs new owners ([`Rounds::set_owner`], chosen by
//! [`rebalance`]) to balance the host threads' loads. A host thread that has waited a
//! while for the others (the OS held one back) takes their unclaimed TMs, so a late host
//! thread delays a round by at most the TM it is running; the TMs of a host thread that
//! finished nothing in the last round are taken at once. Waiting spins first and parks
//! when it drags on.
//!
//! Which host thread runs which TM never matters for results: the caller's jobs touch only
//! the TM's own state and sums that commute.

use std::cell::UnsafeCell;
use std::sync::atomic::{fence, AtomicBool, AtomicU64, AtomicUsize, Ordering::*};
use std::sync::OnceLock;
use std::thread::{Scope, ScopedJoinHandle, Thread};
use std::time::{Duration, Instant};

/// How long a host thread waits for the others to finish a round before it takes their
/// unclaimed TMs (rounds last microseconds; an OS time slice, milliseconds).
const TAKE_AFTER: Duration = Duration::from_micros(50);

/// How long a host thread spins before parking.
const PARK_AFTER: Duration = Duration::from_micros(200);

/// Longest nap of a parked host thread: wake-ups are best effort (a fence to make them
/// certain would cost every round a cache-line transfer), so a parked host thread also
/// looks again on its own.
const NAP: Duration = Duration::from_micros(100);

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

/// A batch of rounds, as the leader asks for it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Batch {
    /// The first round's window: `from..to`, in simulated cycles.
    pub from: u64,
    pub to: u64,
    /// Cycles per round.
    pub step: u64,
    /// Flags with which a round is followed by the next without the leader (`None`: the
    /// batch is one round).
    pub free_flags: Option<u8>,
    /// No free round's window ends after this cycle.
    pub until: u64,
}

impl Batch {
    /// Whether the round with window `..to` and `flags` is followed by the next one.
    fn goes_on(&self, to: u64, flags: u8) -> bool {
        self.free_flags == Some(flags) && to + self.step <= self.until
    }
}

/// How a batch ended: its rounds and the last one's window and flags.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct BatchEnd {
    pub rounds: u64,
    pub from: u64,
    pub to: u64,
    pub flags: u8,
}

/// What the leader publishes for a batch (one cache line), under a sequence lock: a
/// member that reads it while the leader writes the next batch must not mix the two.
struct Head {
    /// Odd while the leader writes.
    seq: AtomicU64,
    /// The batch's first round ([`STOP`] ends the crew).
    round: AtomicU64,
    from: AtomicU64,
    to: AtomicU64,
    step: AtomicU64,
    /// `Batch::free_flags`, or `u64::MAX` for none.
    free_flags: AtomicU64,
    until: AtomicU64,
}

/// What a host thread has finished of a round: TMs and the OR of their jobs' flags.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
struct Finished {
    count: usize,
    flags: u8,
}

impl Finished {
    /// Counts one more TM, whose job returned `flags`.
    fn add(&mut self, flags: u8) {
        self.flags |= flags;
        self.count += 1;
    }

    /// The `done` word of `self` in `round`.
    fn word(self, round: u64) -> u64 {
        (round << ROUND_SHIFT) | u64::from(self.flags) << COUNT_BITS | self.count as u64
    }

    /// The round of a `done` word.
    fn round_of(word: u64) -> u64 {
        word >> ROUND_SHIFT
    }

    /// What a `done` word of `round` says.
    fn of(word: u64) -> Finished {
        Finished {
            count: (word & ((1 << COUNT_BITS) - 1)) as usize,
            flags: (word >> COUNT_BITS) as u8,
        }
    }
}

/// What a host thread learns when it waits for the end of a round.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Verdict {
    /// Go on to the next round of the batch.
    Next,
    /// The batch ended with this round (its flags).
    End(u8),
    /// The leader published a new batch (members only).
    NewBatch,
    /// The crew is finishing (members) or a member died (leader).
    Stop,
}

/// The round protocol shared by the leader (host thread 0) and the members.
pub(crate) struct Rounds {
    head: Padded<Head>,
    /// Per TM: the last round that claimed it.
    claimed: Vec<Padded<AtomicU64>>,
    /// Per TM: the host thread that runs it unless it is late (set between batches).
    owner: Vec<AtomicUsize>,
    /// Per host thread: a [`Finished::word`]: the TMs it finished (its own or taken) in
    /// its latest round.
    done: Vec<Padded<AtomicU64>>,
    /// Per host thread: parked, waiting.
    parked: Vec<Padded<AtomicBool>>,
    /// Per host thread: its handle, for unparking (members register when they start).
    handles: Vec<OnceLock<Thread>>,
    /// The leader's next round.
    next_round: AtomicU64,
}

/// The members of a crew (see [`Rounds::spawn`]); dropping it ends their loops.
pub(crate) struct Crew<'s> {
    rounds: &'s Rounds,
    handles: Vec<ScopedJoinHandle<'s, ()>>,
}

impl Crew<'_> {
    /// Whether a member has ended (only by a panic before [`Drop`]).
    fn died(&self) -> bool {
        self.handles.iter().any(|h| h.is_finished())
    }
}

impl Drop for Crew<'_> {
    fn drop(&mut self) {
        self.rounds.finish();
    }
}

impl Rounds {
    /// The protocol for `tms` TMs on `threads` host threads (the caller is the leader);
    /// TMs start split evenly in index order.
    pub fn new(tms: usize, threads: usize) -> Rounds {
        assert!(
            (1..=tms).contains(&threads) && tms < 1 << COUNT_BITS,
            "1..=tms host threads"
        );
        let handles: Vec<OnceLock<Thread>> = (0..threads).map(|_| OnceLock::new()).collect();
        handles[0]
            .set(std::thread::current())
            .expect("a fresh cell");
        Rounds {
            head: Padded(Head {
                seq: AtomicU64::new(0),
                round: AtomicU64::new(0),
                from: AtomicU64::new(0),
                to: AtomicU64::new(0),
                step: AtomicU64::new(0),
                free_flags: AtomicU64::new(u64::MAX),
                until: AtomicU64::new(0),
            }),
            claimed: (0..tms).map(|_| Padded(AtomicU64::new(0))).collect(),
            owner: (0..tms)
                .map(|k| AtomicUsize::new(k * threads / tms))
                .collect(),
            done: (0..threads).map(|_| Padded(AtomicU64::new(0))).collect(),
            parked: (0..threads)
                .map(|_| Padded(AtomicBool::new(false)))
                .collect(),
            handles,
            next_round: AtomicU64::new(1),
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

    /// Makes host thread `w` the owner of TM `tm` from the next batch on. Only the leader
    /// calls it, between batches.
    pub fn set_owner(&self, tm: usize, w: usize) {
        assert!(w < self.threads(), "host thread in range");
        // Released by the next batch's start.
        self.owner[tm].store(w, Relaxed);
    }

    /// Starts the members (host threads 1..) in `scope`; each round they run
    /// `job(thread, tm, window) -> flags` for the TMs they claim, until the crew is
    /// dropped.
    pub fn spawn<'s, 'e, F>(&'s self, scope: &'s Scope<'s, 'e>, job: &'s F) -> Crew<'s>
    where
        F: Fn(usize, usize, (u64, u64)) -> u8 + Sync,
    {
        let handles = (1..self.threads())
            .map(|w| {
                scope.spawn(move || {
                    self.handles[w]
                        .set(std::thread::current())
                        .expect("a fresh cell");
                    let mut seen = 0;
                    loop {
                        let head = || self.head.round.load(Acquire);
                        self.wait(w, &mut || (head() != seen).then_some(()), &mut |_| {});
                        let (first, batch) = self.batch();
                        if first == STOP {
                            return;
                        }
                        seen = first;
                        let mut job = |k, window| job(w, k, window);
                        if self.run_batch(w, first, &batch, &mut job, None).is_none() {
                            return;
                        }
                    }
                })
            })
            .collect();
        Crew {
            rounds: self,
            handles,
        }
    }

    /// Runs a batch of rounds: wakes the members, runs `job(tm, window) -> flags` for the
    /// TMs the leader claims, round after round while the batch goes on. Returns how the
    /// batch ended, or `None` if a member died (it panicked; the scope re-raises the panic
    /// when it joins).
    pub fn run(
        &self,
        crew: &Crew<'_>,
        batch: &Batch,
        job: &mut dyn FnMut(usize, (u64, u64)) -> u8,
    ) -> Option<BatchEnd> {
        let first = self.next_round.load(Relaxed);
        self.publish(first, batch);
        let end = self.run_batch(0, first, batch, job, Some(crew))?;
        self.next_round.store(first + end.rounds, Relaxed);
        Some(end)
    }

    /// Ends the members' loops.
    fn finish(&self) {
        let batch = Batch {
            from: 0,
            to: 0,
            step: 0,
            free_flags: None,
            until: 0,
        };
        self.publish(STOP, &batch);
    }

    /// Publishes the batch starting at round `first` (the leader only) and wakes the
    /// members.
    fn publish(&self, first: u64, batch: &Batch) {
        let h = &self.head;
        let seq = h.seq.load(Relaxed);
        h.seq.store(seq + 1, Relaxed);
        // Orders the odd sequence number before the writes (pairs with `batch`).
        fence(Release);
        h.from.store(batch.from, Relaxed);
        h.to.store(batch.to, Relaxed);
        h.step.store(batch.step, Relaxed);
        h.free_flags
            .store(batch.free_flags.map_or(u64::MAX, u64::from), Relaxed);
        h.until.store(batch.until, Relaxed);
        h.round.store(first, Relaxed);
        h.seq.store(seq + 2, Release);
        self.wake_others(0);
    }

    /// The published batch and its first round, read as one.
    fn batch(&self) -> (u64, Batch) {
        let h = &self.head;
        loop {
            let seq = h.seq.load(Acquire);
            if seq % 2 == 1 {
                std::hint::spin_loop();
                continue;
            }
            let first = h.round.load(Relaxed);
            let free = h.free_flags.load(Relaxed);
            let batch = Batch {
                from: h.from.load(Relaxed),
                to: h.to.load(Relaxed),
                step: h.step.load(Relaxed),
                free_flags: (free != u64::MAX).then_some(free as u8),
                until: h.until.load(Relaxed),
            };
            // Orders the reads before the second look at the sequence number.
            fence(Acquire);
            if h.seq.load(Relaxed) == seq {
                return (first, batch);
            }
        }
    }

    /// Host thread `w` runs the batch starting at round `first`. `crew` is given to the
    /// leader (to notice a member that died). Returns how the batch ended for this host
    /// thread (`rounds` is 0 if it left for a new batch), `None` on a stop.
    fn run_batch(
        &self,
        w: usize,
        first: u64,
        batch: &Batch,
        job: &mut dyn FnMut(usize, (u64, u64)) -> u8,
        crew: Option<&Crew<'_>>,
    ) -> Option<BatchEnd> {
        let (mut round, mut from, mut to) = (first, batch.from, batch.to);
        loop {
            let mut job = |k| job(k, (from, to));
            let mut finished = Finished::default();
            for k in 0..self.claimed.len() {
                if self.owner(k) == w && self.claim(k, round) {
                    finished.add(job(k));
                }
            }
            // A host thread that finished nothing in the last round is held back by the
            // OS (for a time slice, many rounds): take its TMs at once.
            for k in 0..self.claimed.len() {
                let v = self.owner(k);
                let absent = || Finished::round_of(self.done[v].load(Relaxed)) + 1 < round;
                if v != w && absent() && self.claim(k, round) {
                    finished.add(job(k));
                }
            }
            // One report for the TMs run so far: a report after each would move the line
            // to the host threads watching it once per TM (and the next claim, a locked
            // instruction, would wait for that).
            if finished.count > 0 {
                self.report(w, round, finished);
            }
            let mut look = || self.verdict(round, first, to, batch, crew);
            let verdict = self.wait(w, &mut look, &mut |()| {
                // Take the round's unclaimed TMs.
                for k in 0..self.claimed.len() {
                    if self.claim(k, round) {
                        self.run_job(w, round, k, &mut finished, &mut job);
                    }
                }
            });
            match verdict {
                Verdict::Next => {
                    round += 1;
                    from = to;
                    to += batch.step;
                }
                Verdict::End(flags) => {
                    return Some(BatchEnd {
                        rounds: round - first + 1,
                        from,
                        to,
                        flags,
                    })
                }
                Verdict::NewBatch => {
                    return Some(BatchEnd {
                        rounds: 0,
                        from,
                        to,
                        flags: 0,
                    })
                }
                Verdict::Stop => return None,
            }
        }
    }

    /// The verdict on `round` (window `..to`) of the batch starting at `first`, if the
    /// reports allow one yet.
    fn verdict(
        &self,
        round: u64,
        first: u64,
        to: u64,
        batch: &Batch,
        crew: Option<&Crew<'_>>,
    ) -> Option<Verdict> {
        let mut total = Finished::default();
        let mut later = false;
        for d in &self.done {
            let word = d.load(Acquire);
            match Finished::round_of(word).cmp(&round) {
                std::cmp::Ordering::Equal => {
                    let f = Finished::of(word);
                    total.count += f.count;
                    total.flags |= f.flags;
                }
                std::cmp::Ordering::Greater => later = true,
                std::cmp::Ordering::Less => {}
            }
        }
        // A member sees a new head only after the leader ended the batch; the leader's
        // store of it happens before any report of a later round from the new batch.
        // (Only the round is read here: a torn read of the rest cannot matter.)
        let head = self.head.round.load(Acquire);
        if crew.is_none() && head != first {
            return Some(if head == STOP {
                Verdict::Stop
            } else {
                Verdict::NewBatch
            });
        }
        if later {
            // Another host thread went on past `round` in this batch.
            return Some(Verdict::Next);
        }
        if total.count >= self.claimed.len() {
            return Some(if batch.goes_on(to, total.flags) {
                Verdict::Next
            } else {
                Verdict::End(total.flags)
            });
        }
        if crew.is_some_and(|c| c.died()) {
            return Some(Verdict::Stop);
        }
        None
    }

    /// Claims TM `k` for `round`; false if it is taken (or `round` is over).
    fn claim(&self, k: usize, round: u64) -> bool {
        let c = &self.claimed[k];
        // Look before writing: a failed compare-exchange would still take the line.
        c.load(Relaxed) == round - 1
            && c.compare_exchange(round - 1, round, AcqRel, Relaxed)
                .is_ok()
    }

    /// Runs the job of TM `k`, taken by host thread `w` in `round` while the others
    /// wait, and reports it with the TMs `finished` before.
    fn run_job(
        &self,
        w: usize,
        round: u64,
        k: usize,
        finished: &mut Finished,
        job: &mut dyn FnMut(usize) -> u8,
    ) {
        finished.add(job(k));
        self.report(w, round, *finished);
    }

    /// Host thread `w` reports the TMs it has `finished` in `round`.
    fn report(&self, w: usize, round: u64, finished: Finished) {
        self.done[w].store(finished.word(round), Release);
        self.wake_others(w);
    }

    /// Host thread `w` waits until `look()` has an answer. After [`TAKE_AFTER`] it calls
    /// `take(())` once (to run TMs others left unclaimed), after [`PARK_AFTER`] it parks.
    fn wait<T>(
        &self,
        w: usize,
        look: &mut dyn FnMut() -> Option<T>,
        take: &mut dyn FnMut(()),
    ) -> T {
        let start = Instant::now();
        let mut took = false;
        let mut spins = 0u32;
        loop {
            if let Some(v) = look() {
                return v;
            }
            std::hint::spin_loop();
            spins += 1;
            if !spins.is_multiple_of(64) {
                continue;
            }
            let waited = start.elapsed();
            if !took && waited >= TAKE_AFTER {
                took = true;
                take(());
            }
            if waited >= PARK_AFTER {
                break;
            }
        }
        let parked = &self.parked[w];
        loop {
            parked.store(true, Relaxed);
            if let Some(v) = look() {
                parked.store(false, Relaxed);
                return v;
            }
            // A wake-up may be missed (see `NAP`); a leader also notices a member that died.
            std::thread::park_timeout(NAP);
        }
    }

    /// Unparks every other parked host thread (after a store they may wait for). Best
    /// effort: without a fence, a host thread parking at this moment may be missed and
    /// wakes after its [`NAP`].
    fn wake_others(&self, w: usize) {
        for (i, p) in self.parked.iter().enumerate() {
            if i != w && p.load(Relaxed) && p.swap(false, AcqRel) {
                if let Some(h) = self.handles[i].get() {
                    h.unpark();
                }
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
/// report (after the TM's job) and acquired by the leader, which waits for reports of every
/// TM before it touches TM or chip state between rounds.
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

    /// Runs `batches` batches of `tms` TMs on `threads` host threads, rounds of 10 cycles,
    /// every other batch with free rounds (flags 0) up to 7 rounds. Each job checks its TM
    /// runs every round once, in window order, and returns flag 8 for TM 1 in every third
    /// round. `slow` host threads sleep in every job (others take their TMs). Returns per
    /// TM: rounds run; per host thread: jobs run; rounds in all.
    fn crew_run(
        tms: usize,
        threads: usize,
        batches: u64,
        slow: &[usize],
    ) -> (Vec<u64>, Vec<u64>, u64) {
        let jobs: Vec<AtomicU64> = (0..threads).map(|_| AtomicU64::new(0)).collect();
        let cells: Vec<RoundCell<(u64, u64)>> = (0..tms).map(|_| RoundCell::new((0, 0))).collect();
        let flag_of = |k: usize, from: u64| if k == 1 && (from / 10) % 3 == 2 { 8 } else { 0 };
        let protocol = Rounds::new(tms, threads);
        let job = |w: usize, k: usize, (from, to): (u64, u64)| -> u8 {
            jobs[w].fetch_add(1, Relaxed);
            if slow.contains(&w) {
                std::thread::sleep(Duration::from_millis(2));
            }
            // SAFETY: the round job of TM `k`.
            let c = unsafe { cells[k].get_mut() };
            assert_eq!(c.1, from, "TM {k} ran twice or skipped a round");
            c.0 += 1;
            c.1 = to;
            flag_of(k, from)
        };
        let mut rounds = 0;
        std::thread::scope(|scope| {
            let crew = protocol.spawn(scope, &job);
            let mut now = 0;
            for b in 0..batches {
                if b == batches / 2 {
                    // Move every TM to the next host thread.
                    for k in 0..tms {
                        protocol.set_owner(k, (protocol.owner(k) + 1) % threads);
                    }
                }
                let free = b % 2 == 0;
                let batch = Batch {
                    from: now,
                    to: now + 10,
                    step: 10,
                    free_flags: free.then_some(0),
                    until: now + 70,
                };
                let end = protocol
                    .run(&crew, &batch, &mut |k, win| job(0, k, win))
                    .expect("no member died");
                // The batch ends at the first flagged round, or after 7.
                let flags_at = |i: u64| (0..tms).fold(0, |f, k| f | flag_of(k, now + 10 * i));
                let expect = if free {
                    (0..7).find(|&i| flags_at(i) != 0).map_or(7, |i| i + 1)
                } else {
                    1
                };
                assert_eq!(end.rounds, expect, "batch {b}");
                assert_eq!(end.flags, flags_at(expect - 1));
                assert_eq!(
                    (end.from, end.to),
                    (now + 10 * (expect - 1), now + 10 * expect)
                );
                for c in &cells {
                    // SAFETY: the leader between batches.
                    assert_eq!(unsafe { c.get() }.1, end.to);
                }
                now = end.to;
                rounds += end.rounds;
            }
        });
        let per_tm = cells.into_iter().map(|c| c.into_inner().0).collect();
        (
            per_tm,
            jobs.iter().map(|j| j.load(Relaxed)).collect(),
            rounds,
        )
    }

    #[test]
    fn every_tm_runs_once_per_round() {
        for threads in 1..=3 {
            let (per_tm, jobs, rounds) = crew_run(5, threads, 2000, &[]);
            assert!(rounds > 2000);
            assert_eq!(per_tm, vec![rounds; 5]);
            assert_eq!(jobs.iter().sum::<u64>(), 5 * rounds);
        }
    }

    #[test]
    fn late_host_threads_leave_their_tms_to_others() {
        // Slow host threads (owning 2 of 4 TMs, 4 of 6) run fewer than their own jobs:
        // the others take some.
        let (per_tm, jobs, rounds) = crew_run(4, 2, 10, &[1]);
        assert_eq!(per_tm, vec![rounds; 4]);
        assert!(jobs[1] < 2 * rounds, "{jobs:?}");
        let (per_tm, jobs, rounds) = crew_run(6, 3, 10, &[0, 2]);
        assert_eq!(per_tm, vec![rounds; 6]);
        assert!(jobs[0] + jobs[2] < 4 * rounds, "{jobs:?}");
    }
}
