//! Which of a TM's threads the cycle loop visits: sets of threads as bitsets, and the
//! wake-up wheel of the threads that sleep until a known cycle.
//!
//! A thread that cannot issue until a known cycle (a source register's ready cycle) or
//! until something outside its TM happens (a load's line arriving, a barrier opening)
//! costs nothing per cycle while it waits: it leaves the set of threads visited each
//! cycle and is put back at that cycle ([`Wheel`]) or event. The cycles it slept are
//! counted when it wakes (or when the counters are read), as visiting it each cycle would
//! have counted them (`tm.rs`).

/// A set of thread indices below a bound, one bit each. The first 64 threads' word is
/// inline (a TM of up to 64 threads keeps all its sets in its own few cache lines).
#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) struct ThreadSet {
    first: u64,
    rest: Vec<u64>,
}

impl ThreadSet {
    /// The empty set of threads `0..n`.
    pub fn new(n: usize) -> ThreadSet {
        ThreadSet {
            first: 0,
            rest: vec![0; n.div_ceil(64).saturating_sub(1)],
        }
    }

    /// The set of all threads `0..n`.
    pub fn full(n: usize) -> ThreadSet {
        let mut s = ThreadSet::new(n);
        for i in 0..n {
            s.insert(i);
        }
        s
    }

    #[inline(always)]
    fn word_mut(&mut self, k: usize) -> &mut u64 {
        if k == 0 {
            &mut self.first
        } else {
            &mut self.rest[k - 1]
        }
    }

    /// Word `k` (members `64 k ..`).
    #[inline(always)]
    pub fn word(&self, k: usize) -> u64 {
        if k == 0 {
            self.first
        } else {
            self.rest[k - 1]
        }
    }

    #[inline(always)]
    pub fn insert(&mut self, i: usize) {
        *self.word_mut(i / 64) |= 1 << (i % 64);
    }

    #[inline(always)]
    pub fn remove(&mut self, i: usize) {
        *self.word_mut(i / 64) &= !(1 << (i % 64));
    }

    #[inline(always)]
    pub fn contains(&self, i: usize) -> bool {
        self.word(i / 64) >> (i % 64) & 1 != 0
    }

    #[inline(always)]
    pub fn is_empty(&self) -> bool {
        self.first == 0 && self.rest.iter().all(|&w| w == 0)
    }

    /// Empties the set.
    pub fn clear(&mut self) {
        self.first = 0;
        self.rest.iter_mut().for_each(|w| *w = 0);
    }

    /// Adds every member of `o`.
    #[inline(always)]
    pub fn add_all(&mut self, o: &ThreadSet) {
        self.first |= o.first;
        for (a, b) in self.rest.iter_mut().zip(&o.rest) {
            *a |= b;
        }
    }

    /// The members, ascending.
    pub fn iter(&self) -> impl Iterator<Item = usize> + '_ {
        std::iter::once(self.first)
            .chain(self.rest.iter().copied())
            .enumerate()
            .flat_map(|(k, w)| {
                let mut bits = w;
                std::iter::from_fn(move || {
                    (bits != 0).then(|| {
                        let b = bits.trailing_zeros() as usize;
                        bits &= bits - 1;
                        k * 64 + b
                    })
                })
            })
    }

    /// The members of word `k` in `lo..hi`, as bits (`k * 64 + bit`): a caller that
    /// visits the members word by word may change the set meanwhile and sees each word
    /// as it is when it reaches it.
    #[inline(always)]
    pub fn word_in(&self, k: usize, lo: usize, hi: usize) -> u64 {
        let base = k * 64;
        let mut w = self.word(k);
        if lo > base {
            w &= !0 << (lo - base);
        }
        if hi < base + 64 {
            w &= (1u64 << (hi - base)) - 1;
        }
        w
    }
}

/// Cycles ahead a thread can be put on the wheel; later wake-ups wait in the far set.
pub(crate) const WHEEL_CYCLES: u64 = 64;

/// The threads asleep until a known cycle: those due within [`WHEEL_CYCLES`] in the slot
/// of their cycle (one array of words, slot after slot), the rest in a far set scanned
/// when its earliest is near.
#[derive(Clone, Debug)]
pub(crate) struct Wheel {
    /// Words per slot.
    words: usize,
    slots: Vec<u64>,
    /// Threads on the wheel.
    occupied: usize,
    /// Per thread: its wake-up cycle (meaningful while it is on the wheel or far).
    until: Vec<u64>,
    far: ThreadSet,
    /// The earliest wake-up in `far` (`u64::MAX`: none).
    next_far: u64,
}

impl Wheel {
    /// An empty wheel for threads `0..n`.
    pub fn new(n: usize) -> Wheel {
        let words = n.div_ceil(64);
        Wheel {
            words,
            slots: vec![0; words * WHEEL_CYCLES as usize],
            occupied: 0,
            until: vec![0; n],
            far: ThreadSet::new(n),
            next_far: u64::MAX,
        }
    }

    #[inline(always)]
    fn slot_insert(&mut self, tid: usize, until: u64) {
        let slot = (until % WHEEL_CYCLES) as usize;
        self.slots[slot * self.words + tid / 64] |= 1 << (tid % 64);
        self.occupied += 1;
    }

    /// Puts thread `tid` to sleep at cycle `now` until cycle `until` (> `now`).
    #[inline(always)]
    pub fn put(&mut self, tid: usize, now: u64, until: u64) {
        debug_assert!(until > now);
        self.until[tid] = until;
        if until - now < WHEEL_CYCLES {
            self.slot_insert(tid, until);
        } else {
            self.far.insert(tid);
            self.next_far = self.next_far.min(until);
        }
    }

    /// At the start of cycle `now` (called for every cycle in order): adds the threads
    /// whose wake-up cycle is `now` to `woken` (which the caller empties); whether any.
    #[inline(always)]
    pub fn due(&mut self, now: u64, woken: &mut ThreadSet) -> bool {
        if self.next_far < now + WHEEL_CYCLES {
            self.refill(now);
        }
        if self.occupied == 0 {
            return false;
        }
        let slot = (now % WHEEL_CYCLES) as usize * self.words;
        let mut any = false;
        for k in 0..self.words {
            let w = std::mem::take(&mut self.slots[slot + k]);
            if w != 0 {
                any = true;
                self.occupied -= w.count_ones() as usize;
                *woken.word_mut(k) |= w;
            }
        }
        any
    }

    /// Moves the far threads due within the wheel's reach of `now` onto it.
    #[cold]
    fn refill(&mut self, now: u64) {
        let mut next = u64::MAX;
        let far: Vec<usize> = self.far.iter().collect();
        for tid in far {
            let until = self.until[tid];
            if until < now + WHEEL_CYCLES {
                debug_assert!(until >= now, "far threads move to the wheel in time");
                self.far.remove(tid);
                self.slot_insert(tid, until);
            } else {
                next = next.min(until);
            }
        }
        self.next_far = next;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sets_hold_members_across_words() {
        let mut s = ThreadSet::new(130);
        for i in [0, 5, 63, 64, 100, 129] {
            s.insert(i);
        }
        assert_eq!(s.iter().collect::<Vec<_>>(), [0, 5, 63, 64, 100, 129]);
        s.remove(64);
        assert!(!s.contains(64) && s.contains(63));
        assert_eq!(s.word_in(0, 5, 64), (1 << 5) | (1 << 63));
        assert_eq!(s.word_in(0, 6, 63), 0);
        assert_eq!(s.word_in(2, 128, 130), 0b10);
        assert_eq!(ThreadSet::full(70).iter().count(), 70);
        assert!(ThreadSet::new(3).is_empty());
    }

    /// Every thread put on the wheel wakes exactly at its cycle, near or far.
    #[test]
    fn the_wheel_wakes_each_thread_at_its_cycle() {
        let n = 70;
        let mut w = Wheel::new(n);
        let mut expect: Vec<Option<u64>> = vec![None; n];
        let mut rng = 12345u64;
        let mut next = || {
            rng = rng
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            rng >> 33
        };
        for now in 0..5000u64 {
            let mut woken = ThreadSet::new(n);
            w.due(now, &mut woken);
            for (tid, e) in expect.iter_mut().enumerate() {
                assert_eq!(woken.contains(tid), *e == Some(now), "{tid} at {now}");
                if woken.contains(tid) {
                    *e = None;
                }
            }
            for (tid, e) in expect.iter_mut().enumerate() {
                if e.is_none() && next() % 3 == 0 {
                    let until = now + 1 + next() % 400;
                    w.put(tid, now, until);
                    *e = Some(until);
                }
            }
        }
    }
}
