//! The host's memory limit, so that a run the host cannot hold is refused up front with the
//! simulator's estimate ([`trax_emulator::timing::footprint`]) instead of aborting part-way
//! through allocation.
//!
//! The limit is the smallest of: the memory the kernel reports available (`MemAvailable` in
//! `/proc/meminfo`), the address-space limit (`RLIMIT_AS`, from `/proc/self/limits`) less
//! what the process already maps, and the cgroup's `memory.max` less its `memory.current`.
//! Where none can be read (not Linux), nothing is refused.

use trax_emulator::timing::footprint::{self, human_bytes};
use trax_emulator::timing::ChipConfig;

/// The host's limit in bytes and where it comes from, if any is known.
pub fn host_memory_limit() -> Option<(u64, &'static str)> {
    let mut best: Option<(u64, &'static str)> = None;
    let mut take = |v: Option<u64>, what: &'static str| {
        if let Some(v) = v {
            if best.is_none_or(|(b, _)| v < b) {
                best = Some((v, what));
            }
        }
    };
    take(
        kib_field("/proc/meminfo", "MemAvailable:"),
        "available memory (MemAvailable)",
    );
    take(address_space_left(), "address-space limit (RLIMIT_AS)");
    take(cgroup_left(), "cgroup memory limit (memory.max)");
    best
}

/// A `NAME: N kB` field of a /proc file, in bytes.
fn kib_field(path: &str, name: &str) -> Option<u64> {
    let text = std::fs::read_to_string(path).ok()?;
    let line = text.lines().find(|l| l.starts_with(name))?;
    let kib: u64 = line[name.len()..].split_whitespace().next()?.parse().ok()?;
    Some(kib * 1024)
}

/// The soft `RLIMIT_AS` less the process's current virtual size.
fn address_space_left() -> Option<u64> {
    let limits = std::fs::read_to_string("/proc/self/limits").ok()?;
    let line = limits
        .lines()
        .find(|l| l.starts_with("Max address space"))?;
    let soft: u64 = line["Max address space".len()..]
        .split_whitespace()
        .next()?
        .parse()
        .ok()?;
    let used = kib_field("/proc/self/status", "VmSize:").unwrap_or(0);
    Some(soft.saturating_sub(used))
}

/// The cgroup (v2) `memory.max` less `memory.current`.
fn cgroup_left() -> Option<u64> {
    let cg = std::fs::read_to_string("/proc/self/cgroup").ok()?;
    let path = cg.lines().find_map(|l| l.strip_prefix("0::"))?;
    let dir = std::path::Path::new("/sys/fs/cgroup").join(path.trim_start_matches('/'));
    let read = |f: &str| -> Option<u64> {
        std::fs::read_to_string(dir.join(f))
            .ok()?
            .trim()
            .parse()
            .ok()
    };
    let max = read("memory.max")?;
    Some(max.saturating_sub(read("memory.current").unwrap_or(0)))
}

/// Refuses a chip whose simulation (timing mode or not) needs more host memory than the
/// host's limit, naming the estimate, its largest parts and the limit.
pub fn check_chip_memory(chip: &ChipConfig, timing: bool) -> Result<(), String> {
    let need = footprint::estimate(chip, timing);
    match host_memory_limit() {
        Some((limit, what)) if need.total() > limit => Err(format!(
            "simulating this chip ({} TMs x {} threads) needs about {} of host memory, more \
             than the host's {what} of {}: use fewer TMs or threads (--tms, --threads), \
             smaller local stores or caches",
            chip.tms,
            chip.threads_per_tm,
            need.describe(),
            human_bytes(limit)
        )),
        _ => Ok(()),
    }
}
