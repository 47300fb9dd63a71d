//! Memory hierarchy and DRAM timing: per-TM L1s, shared L2s, simple or detailed DRAM.
//!
//! # Interface for the core timing model
//!
//! Everything here is a deterministic, single-threaded, cycle-driven component without I/O.
//! Time is counted in **core cycles** ([`Cycle`]); the detailed DRAM keeps its own clock and
//! converts (e.g. 2 DRAM cycles per core cycle for 2 GHz DRAM under a 1 GHz core).
//!
//! ```text
//! let mut mem = MemSystem::new(&cfg, tms, tms_per_l2, core_mhz)?;
//! each core cycle `now` (non-decreasing):
//!     mem.advance_to(now, &mut completions);      // L2s and DRAM serve what was sent before `now`
//!     for each memory op, in a deterministic order (e.g. TM, then thread):
//!         match mem.access(tm, &MemRequest { addr, kind, size, requester, id }, now) {
//!             Access::Ready(c)  => data ready (store acknowledged) at cycle c
//!             Access::Pending   => a Completion { id, cycle } arrives from a later advance_to
//!             Access::Stall(_)  => refused this cycle (L1 bank conflict or L1 MSHRs full)
//!         }
//! ```
//!
//! The same in two halves, for TMs simulated on several host threads: [`TmMem::access`] per
//! TM (L1 only; misses and stores are sent to the L2), [`ChipMem::serve_until`] for the L2s and
//! DRAM (requests served in (cycle, rotating TM) order; a refused request — L2 bank taken, L2
//! MSHRs or DRAM queue full — waits for the next cycle), [`TmMem::apply_fills`] back in the TM.
//! * A [`Completion`]'s `cycle` is when the data is ready; it may be later than the `now` of the
//!   `advance_to` that reports it (a DRAM read's return time is known once it is scheduled), so a
//!   scoreboard can simply record it as the register's ready cycle.
//! * Stores are write-around and posted: `Ready(now + L1 hit latency)`; a full line is written to
//!   DRAM (merged with a queued write of the same line).
//! * Skipping idle time is allowed: call `advance_to` with any later cycle; idle DRAM channels are
//!   not clocked (refreshes are caught up). [`MemSystem::next_event`] gives a lower bound on the
//!   next cycle with news (None if nothing is outstanding).
//! * Latencies add up level by level: L1 hit = `l1.hit_latency`; L2 hit = `l2.hit_latency +
//!   l1.hit_latency`; DRAM = DRAM data return + both hit latencies.
//! * The pieces are usable alone: [`cache::Cache`] (tags, banks, MSHRs), [`dram::Dram`]
//!   (`submit` / `advance_to` with ids and completions), configs in [`config`] and
//!   [`dram_config`] (TOML, presets), costs in [`cacti`].

pub mod cache;
pub mod cacti;
pub mod config;
pub mod dram;
pub mod dram_config;
pub mod dram_detailed;
pub mod hierarchy;
pub mod regions;
pub mod sentinel;
pub mod timespec;

pub use cache::{Cache, CacheStats};
pub use config::{BankInterleave, L1Config, L2Config, MemSysConfig};
pub use dram::{Dram, DramEnergy, DramStats};
pub use dram_config::{AddressMapping, DramConfig, DramModel, DRAM_PRESETS};
pub use hierarchy::{Access, ChipMem, L2Request, MemStats, MemSystem, Stall, TmMem};
pub use regions::{RegionCounts, RegionMap};
pub use timespec::{ns_to_cycles, TimeSpec};

/// A time in core cycles.
pub type Cycle = u64;

/// Load or store.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AccessKind {
    /// Load.
    Read,
    /// Store.
    Write,
}

/// One memory access from a thread processor.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MemRequest {
    /// Byte address.
    pub addr: u32,
    /// Load or store.
    pub kind: AccessKind,
    /// Bytes accessed (for bandwidth statistics).
    pub size: u32,
    /// Who asked (e.g. global thread id); informational.
    pub requester: u32,
    /// Caller's token, returned in the [`Completion`].
    pub id: u64,
}

/// A pending load finished: its data is ready at `cycle` (core cycles).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Completion {
    /// The request's id.
    pub id: u64,
    /// Core cycle at which the data is ready.
    pub cycle: Cycle,
}

/// Configuration errors (the message names the table and field).
#[derive(Debug, thiserror::Error)]
pub enum MemSysError {
    /// TOML syntax.
    #[error("memory config: {0}")]
    Toml(String),
    /// Bad or unknown field or value.
    #[error("memory config: {0}")]
    Config(String),
}
