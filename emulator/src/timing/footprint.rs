//! The simulator's own host memory for a chip, estimated from its config before anything is
//! allocated, so a chip too large for the host is refused with the estimate instead of
//! aborting the process part-way through allocation (`trax::resources` compares it with the
//! host's limit).
//!
//! The estimate counts what grows with the config: per hardware thread its state, its local
//! store (`local_store.bytes`) and its timing-model scoreboard; per cache line of every L1
//! and L2 its tag, ready cycle and (set-associative) LRU stamp; the stream memory's bytes;
//! the DRAM controllers' queues. The program's memory image comes on top (it depends on the
//! scene, not on the chip).

use super::config::ChipConfig;

/// Bytes a chip's simulation takes, by part.
#[derive(Clone, Debug, PartialEq)]
pub struct Footprint {
    /// (part, bytes), in a fixed order.
    pub parts: Vec<(&'static str, u64)>,
}

impl Footprint {
    /// All parts together.
    pub fn total(&self) -> u64 {
        self.parts.iter().map(|p| p.1).sum()
    }

    /// `total (part bytes, ...)` in human units, the largest parts first.
    pub fn describe(&self) -> String {
        let mut parts: Vec<_> = self.parts.iter().filter(|p| p.1 > 0).collect();
        parts.sort_by_key(|p| std::cmp::Reverse(p.1));
        let list: Vec<String> = parts
            .iter()
            .map(|(n, b)| format!("{n} {}", human_bytes(*b)))
            .collect();
        format!("{} ({})", human_bytes(self.total()), list.join(", "))
    }
}

/// `bytes` as B, KiB, MiB, GiB or TiB with one decimal.
pub fn human_bytes(bytes: u64) -> String {
    let units = ["B", "KiB", "MiB", "GiB", "TiB"];
    let mut v = bytes as f64;
    let mut u = 0;
    while v >= 1024.0 && u + 1 < units.len() {
        v /= 1024.0;
        u += 1;
    }
    if u == 0 {
        format!("{bytes} B")
    } else {
        format!("{v:.1} {}", units[u])
    }
}

/// Bytes of one hardware thread's state outside its local store: the functional thread,
/// its timing-model lane (scoreboard, units) and wake slot, and its shadow call stack's first frames.
fn thread_bytes() -> u64 {
    (std::mem::size_of::<crate::thread::Thread>()
        + std::mem::size_of::<super::tm::Lane>()
        + std::mem::size_of::<(u64, u32)>()
        + 256) as u64
}

/// Bytes per cache line of the cache model: tag (u32) and ready cycle (u64), and an LRU
/// stamp (u64) when set-associative.
fn line_bytes(ways: u32) -> u64 {
    12 + if ways > 1 { 8 } else { 0 }
}

/// The estimate for `cfg` (a validated config) in timing mode (`timing`) or functional mode
/// (threads and local stores only).
pub fn estimate(cfg: &ChipConfig, timing: bool) -> Footprint {
    let threads = u64::from(cfg.tms) * u64::from(cfg.threads_per_tm);
    let m = &cfg.memory;
    let l1_lines = u64::from(m.l1.capacity_bytes / m.l1.line_bytes.max(1));
    let l2s = u64::from(cfg.tms.div_ceil(cfg.tms_per_l2.max(1)));
    let l2_lines = u64::from(m.l2.capacity_bytes / m.l2.line_bytes.max(1));
    let d = &m.dram.detailed;
    let dram = match m.dram.model {
        crate::memsys::DramModel::Detailed => {
            u64::from(d.channels) * (u64::from(d.read_queue) + u64::from(d.write_queue)) * 64
        }
        crate::memsys::DramModel::Simple => 0,
    };
    let t = u64::from(timing);
    Footprint {
        parts: vec![
            ("thread state", threads * thread_bytes()),
            ("local stores", threads * u64::from(cfg.local_store.bytes)),
            ("L1 tags", t * u64::from(cfg.tms) * l1_lines * line_bytes(1)),
            (
                "L2 tags",
                t * l2s * l2_lines * line_bytes(m.l2.associativity),
            ),
            ("stream memory", u64::from(cfg.stream_memory.capacity_bytes)),
            ("DRAM queues", t * dram),
        ],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The parts grow with the fields they name.
    #[test]
    fn the_estimate_follows_the_config() {
        let tiny = ChipConfig::preset("tiny").unwrap();
        let base = estimate(&tiny, true).total();
        let mut big = tiny.clone();
        big.tms = 1024;
        big.threads_per_tm = 1024;
        let e = estimate(&big, false);
        assert!(e.total() > 1 << 36, "{}", e.describe());
        assert!(
            e.describe().contains("local stores 64.0 GiB"),
            "{}",
            e.describe()
        );
        let mut l1 = tiny.clone();
        l1.memory.l1.capacity_bytes = 1 << 31;
        assert_eq!(
            estimate(&l1, true).total() - base,
            ((1u64 << 31) - (32 << 10)) / 64 * 12
        );
        assert_eq!(human_bytes(1536), "1.5 KiB");
    }
}
