//! A timing-only cache: tags, banks and MSHRs (the data lives in functional memory).
//!
//! Used for both L1 (direct-mapped) and L2 (set-associative, LRU). A line may be installed with
//! a future ready cycle (its fill time is known); accesses before then are "merged" hits under
//! miss that complete at the fill time. Lines whose fill time is not yet known (waiting on DRAM)
//! are tracked by MSHRs with a list of waiter tokens.

use super::config::BankInterleave;
use super::Cycle;
/// Counters of one cache (or a sum of several).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct CacheStats {
    /// Accepted accesses (loads + stores); refused (bank-conflicted) attempts are not counted.
    pub accesses: u64,
    /// Loads that found their line valid.
    pub hits: u64,
    /// Loads that did not (includes merged ones).
    pub misses: u64,
    /// Misses merged into an outstanding fill of the same line (hit under miss).
    pub merged: u64,
    /// Attempts refused because their bank was already used this cycle. A refused requester
    /// retries, so each is one requester-cycle lost to a busy bank (a thread-cycle for the
    /// L1, a request-cycle for the L2), not one conflict. Formerly `bank_conflicts`.
    pub bank_retries: u64,
    /// Bank conflicts: (bank, cycle) pairs in which at least one attempt was refused because
    /// another access had the bank, however many attempts lost.
    pub bank_conflict_events: u64,
    /// Attempts refused because every MSHR was busy.
    pub mshr_full: u64,
    /// Stores (write-around: forwarded to the next level, no allocation).
    pub stores: u64,
    /// Bytes delivered to requesters by loads.
    pub load_bytes: u64,
    /// Bytes of line fills received from the next level.
    pub fill_bytes: u64,
    /// Bytes of stores forwarded to the next level.
    pub store_bytes: u64,
}

impl CacheStats {
    /// Strict load hit rate, hits / (hits + misses), 0..1: a load merged into an outstanding
    /// fill of its line (MSHR or known fill time) counts as a miss.
    pub fn hit_rate(&self) -> f64 {
        let loads = self.hits + self.misses;
        if loads == 0 {
            0.0
        } else {
            self.hits as f64 / loads as f64
        }
    }

    /// Load hit rate counting merged loads as hits, (hits + merged) / (hits + misses), 0..1:
    /// the fraction of loads that sent no request to the next level.
    pub fn hit_rate_merged_as_hits(&self) -> f64 {
        let loads = self.hits + self.misses;
        if loads == 0 {
            0.0
        } else {
            (self.hits + self.merged) as f64 / loads as f64
        }
    }

    /// Adds `o` into `self`.
    pub fn add(&mut self, o: &CacheStats) {
        self.accesses += o.accesses;
        self.hits += o.hits;
        self.misses += o.misses;
        self.merged += o.merged;
        self.bank_retries += o.bank_retries;
        self.bank_conflict_events += o.bank_conflict_events;
        self.mshr_full += o.mshr_full;
        self.stores += o.stores;
        self.load_bytes += o.load_bytes;
        self.fill_bytes += o.fill_bytes;
        self.store_bytes += o.store_bytes;
    }
}

/// Result of a tag lookup.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Lookup {
    /// Line valid: data ready at this cycle (now + hit latency).
    Hit(Cycle),
    /// Line arriving at a known cycle: data ready at this cycle (fill + hit latency).
    Merged(Cycle),
    /// Line awaited from the next level with unknown fill time (MSHR index).
    Pending(usize),
    /// Line absent.
    Miss,
}

#[derive(Clone)]
struct Mshr {
    line: u32,
    waiters: Vec<u64>,
}

/// Geometry and timing of a cache.
#[derive(Clone, Copy, Debug)]
pub struct CacheGeometry {
    /// Capacity in bytes (power of two).
    pub capacity_bytes: u32,
    /// Line size in bytes (power of two).
    pub line_bytes: u32,
    /// Banks (power of two).
    pub banks: u32,
    /// Bank selection.
    pub interleave: BankInterleave,
    /// Ways (power of two).
    pub ways: u32,
    /// Hit latency in core cycles.
    pub hit_latency: u32,
    /// MSHR entries.
    pub mshrs: u32,
    /// Same-word accesses share a bank in one cycle.
    pub read_copy: bool,
}

/// A timing-only cache.
#[derive(Clone)]
pub struct Cache {
    line_shift: u32,
    set_mask: u32,
    ways: usize,
    /// Line number + 1 per way (0 = invalid).
    tags: Vec<u32>,
    ready: Vec<Cycle>,
    lru: Vec<u64>,
    lru_clock: u64,
    bank_shift: u32,
    bank_mask: u32,
    /// Per bank: cycle + 1 of its last use (0 = never).
    bank_used: Vec<Cycle>,
    /// Per bank: cycle + 1 of its last counted conflict event (0 = never).
    bank_conflicted: Vec<Cycle>,
    bank_word: Vec<u32>,
    read_copy: bool,
    hit_latency: Cycle,
    line_bytes: u32,
    mshrs: Vec<Mshr>,
    mshr_cap: usize,
    spare: Vec<Vec<u64>>,
    /// Counters.
    pub stats: CacheStats,
}

impl Cache {
    /// An empty cache (geometry must be validated: powers of two).
    pub fn new(g: CacheGeometry) -> Self {
        let lines = (g.capacity_bytes / g.line_bytes).max(1);
        let ways = g.ways.max(1).min(lines);
        let sets = lines / ways;
        let line_shift = g.line_bytes.trailing_zeros();
        Cache {
            line_shift,
            set_mask: sets - 1,
            ways: ways as usize,
            tags: vec![0; lines as usize],
            ready: vec![0; lines as usize],
            lru: if ways > 1 {
                vec![0; lines as usize]
            } else {
                Vec::new()
            },
            lru_clock: 0,
            bank_shift: match g.interleave {
                BankInterleave::Word => 2,
                BankInterleave::Line => line_shift,
            },
            bank_mask: g.banks - 1,
            bank_used: vec![0; g.banks as usize],
            bank_word: vec![0; g.banks as usize],
            bank_conflicted: vec![0; g.banks as usize],
            read_copy: g.read_copy,
            hit_latency: Cycle::from(g.hit_latency),
            line_bytes: g.line_bytes,
            mshrs: Vec::new(),
            mshr_cap: g.mshrs.max(1) as usize,
            spare: Vec::new(),
            stats: CacheStats::default(),
        }
    }

    /// Line number of a byte address.
    #[inline]
    pub fn line_of(&self, addr: u32) -> u32 {
        addr >> self.line_shift
    }

    /// Line size in bytes.
    pub fn line_bytes(&self) -> u32 {
        self.line_bytes
    }

    /// Hit latency in core cycles.
    pub fn hit_latency(&self) -> Cycle {
        self.hit_latency
    }

    /// Claims the bank of `addr` for cycle `now`; false (a counted retry, and a conflict event
    /// if it is the bank's first refusal this cycle) if it is taken.
    #[inline]
    pub fn claim_bank(&mut self, addr: u32, now: Cycle) -> bool {
        if self.refuses(addr, now) {
            return false;
        }
        let b = ((addr >> self.bank_shift) & self.bank_mask) as usize;
        self.bank_used[b] = now + 1;
        self.bank_word[b] = addr >> 2;
        true
    }

    /// Whether the bank of `addr` refuses an access at cycle `now` (counted as by
    /// [`Self::claim_bank`]); if not, the bank is not claimed.
    #[inline]
    pub fn refuses(&mut self, addr: u32, now: Cycle) -> bool {
        let b = ((addr >> self.bank_shift) & self.bank_mask) as usize;
        if self.bank_used[b] != now + 1 || self.read_copy && self.bank_word[b] == addr >> 2 {
            return false;
        }
        self.stats.bank_retries += 1;
        if self.bank_conflicted[b] != now + 1 {
            self.bank_conflicted[b] = now + 1;
            self.stats.bank_conflict_events += 1;
        }
        true
    }

    /// Bank index of `addr`.
    pub fn bank_of(&self, addr: u32) -> usize {
        ((addr >> self.bank_shift) & self.bank_mask) as usize
    }

    #[inline]
    fn set_range(&self, line: u32) -> std::ops::Range<usize> {
        let set = (line & self.set_mask) as usize;
        set * self.ways..(set + 1) * self.ways
    }

    /// Looks `line` up at cycle `now` without changing anything.
    pub fn lookup(&self, line: u32, now: Cycle) -> Lookup {
        let key = line.wrapping_add(1);
        for w in self.set_range(line) {
            if self.tags[w] == key {
                let r = self.ready[w];
                return if r <= now {
                    Lookup::Hit(now + self.hit_latency)
                } else {
                    Lookup::Merged(r + self.hit_latency)
                };
            }
        }
        match self.mshrs.iter().position(|m| m.line == line) {
            Some(i) => Lookup::Pending(i),
            None => Lookup::Miss,
        }
    }

    /// Marks `line` used (LRU) after a hit.
    pub fn touch(&mut self, line: u32) {
        if self.ways > 1 {
            let key = line.wrapping_add(1);
            self.lru_clock += 1;
            for w in self.set_range(line) {
                if self.tags[w] == key {
                    self.lru[w] = self.lru_clock;
                }
            }
        }
    }

    /// Installs `line`, valid from cycle `ready` (evicting the LRU or only way of its set).
    pub fn install(&mut self, line: u32, ready: Cycle) {
        self.place(line, ready);
        self.stats.fill_bytes += u64::from(self.line_bytes);
    }

    /// Functional warming (sampled simulation): a load of `line` that changes the tags and
    /// the LRU order as a timed access would once its fill arrived (a hit marks the line
    /// used, a miss installs it, valid at once), without timing or statistics. Returns
    /// whether it hit.
    pub fn warm(&mut self, line: u32) -> bool {
        let key = line.wrapping_add(1);
        if self.set_range(line).any(|w| self.tags[w] == key) {
            self.touch(line);
            true
        } else {
            self.place(line, 0);
            false
        }
    }

    /// The tags and the LRU order of every set (for comparing cache states).
    pub fn contents(&self) -> Vec<Vec<u32>> {
        let sets = self.tags.len() / self.ways;
        (0..sets)
            .map(|s| {
                let range = s * self.ways..(s + 1) * self.ways;
                let mut ways: Vec<(u64, u32)> = range
                    .filter(|&w| self.tags[w] != 0)
                    .map(|w| (self.lru.get(w).copied().unwrap_or(0), self.tags[w] - 1))
                    .collect();
                ways.sort_unstable();
                ways.into_iter().map(|(_, line)| line).collect()
            })
            .collect()
    }

    /// Puts `line` in its set, valid from cycle `ready`.
    fn place(&mut self, line: u32, ready: Cycle) {
        let key = line.wrapping_add(1);
        let range = self.set_range(line);
        let mut victim = range.start;
        if self.ways > 1 {
            let mut best = u64::MAX;
            for w in range {
                if self.tags[w] == key || self.tags[w] == 0 {
                    victim = w;
                    break;
                }
                if self.lru[w] < best {
                    best = self.lru[w];
                    victim = w;
                }
            }
            self.lru_clock += 1;
            self.lru[victim] = self.lru_clock;
        }
        self.tags[victim] = key;
        self.ready[victim] = ready;
    }

    /// Whether a new MSHR can be allocated.
    pub fn mshr_available(&self) -> bool {
        self.mshrs.len() < self.mshr_cap
    }

    /// Allocates an MSHR for `line` with a first waiter (check [`Self::mshr_available`] first).
    pub fn mshr_alloc(&mut self, line: u32, waiter: u64) {
        let mut waiters = self.spare.pop().unwrap_or_default();
        waiters.push(waiter);
        self.mshrs.push(Mshr { line, waiters });
    }

    /// Adds a waiter to MSHR `idx` (from [`Lookup::Pending`]).
    pub fn mshr_join(&mut self, idx: usize, waiter: u64) {
        self.mshrs[idx].waiters.push(waiter);
    }

    /// Number of busy MSHRs.
    pub fn mshrs_busy(&self) -> usize {
        self.mshrs.len()
    }

    /// The fill time of `line` became known: installs it valid from `fill` and appends the
    /// waiters of its MSHR (if any) to `out`.
    pub fn fill(&mut self, line: u32, fill: Cycle, out: &mut Vec<u64>) {
        self.install(line, fill);
        if let Some(i) = self.mshrs.iter().position(|m| m.line == line) {
            let mut m = self.mshrs.swap_remove(i);
            out.append(&mut m.waiters);
            self.spare.push(m.waiters);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `refuses` refuses exactly what `claim_bank` refuses, counting it the same way, and
    /// claims nothing when it lets an access through (the timing model's cheap retry of a
    /// refused access relies on both).
    #[test]
    fn refuses_agrees_with_claim_bank_and_claims_nothing() {
        for read_copy in [false, true] {
            let g = CacheGeometry {
                capacity_bytes: 1024,
                line_bytes: 32,
                banks: 4,
                interleave: BankInterleave::Word,
                ways: 1,
                hit_latency: 1,
                mshrs: 4,
                read_copy,
            };
            let (mut a, mut b) = (Cache::new(g), Cache::new(g));
            // Cycle 7: bank 1 taken by word 1; then another word of bank 1, the same word,
            // and a free bank.
            assert!(a.claim_bank(4, 7) && b.claim_bank(4, 7));
            for (addr, refused) in [(20, true), (20, true), (4, !read_copy), (8, false)] {
                assert_eq!(b.refuses(addr, 7), refused, "{addr} {read_copy}");
                assert_eq!(a.claim_bank(addr, 7), !refused, "{addr} {read_copy}");
                // Let through, `b` has not claimed it: claim it as `a` did.
                if !refused {
                    assert!(b.claim_bank(addr, 7));
                }
            }
            assert_eq!(a.stats.bank_retries, b.stats.bank_retries);
            assert_eq!(a.stats.bank_conflict_events, 1);
            assert_eq!(b.stats.bank_conflict_events, 1);
            // The next cycle every bank is free.
            assert!(!b.refuses(20, 8));
        }
    }
}
