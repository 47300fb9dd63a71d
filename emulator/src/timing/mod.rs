//! The cycle-level timing model of the TRaX chip (thesis chapter 2, simtrax §4).
//!
//! Runs come through [`crate::run`] (timing mode): an ELF (plus memory image) and a
//! [`ChipConfig`] in; print output, [`TimingStats`] and a crash report out. The model:
//! [`engine`] (TMs of in-order single-issue thread processors, shared execution units,
//! I-cache banks, scoreboards, local stores, global registers, the memory system of
//! [`crate::memsys`]), [`operands`] (what each instruction reads, writes and uses),
//! [`config`] (TOML chip configs and presets), [`units`] (the execution units, declared
//! once) and [`stats`] (summary and JSON).
//!
//! Determinism and parallelism: time advances in quanta; within a quantum every TM is
//! simulated on its own (TMs are spread over `host_threads` host threads), then chip-wide
//! work (L2s, DRAM, global registers, stores to global memory, barriers) is done serially
//! in a fixed order (see [`engine`]). The same inputs give the same cycles, statistics
//! and output for any number of host threads.

mod config;
mod config_doc;
pub(crate) mod engine;
pub mod footprint;
pub mod intervals;
mod naps;
pub(crate) mod operands;
pub mod sample;
pub mod stat;
pub(crate) mod stats;
mod stats_doc;
mod tm;
pub mod units;
mod workers;

pub use config::{
    stream_energy_nj, ChipConfig, ConfigError, GlobalRegConfig, ICacheConfig, LocalStoreConfig,
    Overflow, PipeConfig, PipelinesConfig, RegisterFileConfig, SpillConfig, StreamMemoryConfig,
    TreeletAlign, TreeletConfig, TreeletForm, UnitConfig, CHIP_PRESETS, DEFAULT_CHIP,
    STREAM_ENERGY_TABLE,
};
pub use engine::{ThreadCycleBucket, ThreadCycles};
pub use intervals::Interval;
pub use sample::{Estimate, Estimates, SampleRequest, SampledStats, VtCosts, WorkSource};
pub use stats::{
    area_breakdown, pipe_op_energy_nj, stats_md_rows, AreaBreakdown, EnergyBreakdown, Part,
    PipelineStats, SpillStats, StreamStats, TimingStats,
};
pub use units::{class_name, UnitDecl, UNITS};
