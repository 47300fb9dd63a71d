//! The headline metrics of a run: the columns of `results.csv` after the parameters, and the
//! y axes of `trax plot`. This is the one place that knows where they are in the statistics
//! JSON of `trax run --stats-json` (timing runs: `emulator/src/timing/stats.rs`; functional
//! runs: `{"mode": "functional", "instructions", "rays", "threads"}`).

use serde_json::Value;

/// One headline metric.
#[derive(Debug)]
pub struct Metric {
    /// Column name.
    pub column: &'static str,
    /// Axis label (without the unit).
    pub label: &'static str,
    /// Unit (empty: a count or a ratio).
    pub unit: &'static str,
    /// Dotted path in a timing run's statistics.
    pub timing: &'static str,
    /// Dotted path in a functional run's statistics (none: timing only).
    pub functional: Option<&'static str>,
    /// A component of the energy per frame (stacked in energy charts).
    pub energy_part: bool,
}

const fn m(
    column: &'static str,
    label: &'static str,
    unit: &'static str,
    timing: &'static str,
    functional: Option<&'static str>,
) -> Metric {
    Metric {
        column,
        label,
        unit,
        timing,
        functional,
        energy_part: false,
    }
}

const fn e(column: &'static str, label: &'static str, timing: &'static str) -> Metric {
    Metric {
        column,
        label,
        unit: "J",
        timing,
        functional: None,
        energy_part: true,
    }
}

/// The metrics, in table order.
pub const METRICS: &[Metric] = &[
    m(
        "instructions",
        "Instructions",
        "",
        "instructions",
        Some("instructions"),
    ),
    m("rays", "Rays", "", "rays", Some("rays")),
    m("cycles", "Run time", "cycles", "cycles", None),
    m("seconds", "Simulated time", "s", "seconds", None),
    m("fps", "Frame rate", "frames/s", "fps", None),
    m("mrps", "Ray throughput", "Mrays/s", "mrps", None),
    m(
        "issue_rate",
        "Issue rate",
        "issued / thread-cycle",
        "issue_rate",
        None,
    ),
    m("l1_hit_rate", "L1 hit rate", "", "l1_hit_rate", None),
    m("l2_hit_rate", "L2 hit rate", "", "l2_hit_rate", None),
    m("dram_gbps", "DRAM bandwidth", "GB/s", "dram_gbps", None),
    m("dram_reads", "DRAM reads", "", "memory.dram.reads", None),
    m("dram_writes", "DRAM writes", "", "memory.dram.writes", None),
    m(
        "dram_row_hit_rate",
        "DRAM row-buffer hit rate",
        "",
        "memory.dram.row_hit_rate",
        None,
    ),
    m(
        "dram_read_latency",
        "DRAM read latency",
        "cycles",
        "memory.dram.avg_read_latency_cycles",
        None,
    ),
    m("power_w", "Power", "W", "power_w", None),
    m("energy_j", "Energy per frame", "J", "energy.total", None),
    e(
        "energy_units_j",
        "Execution units",
        "energy.execution_units",
    ),
    e("energy_regs_j", "Register files", "energy.register_files"),
    e(
        "energy_icache_j",
        "Instruction caches",
        "energy.instruction_caches",
    ),
    e("energy_local_j", "Local stores", "energy.local_stores"),
    e("energy_l1_j", "L1", "energy.l1"),
    e("energy_l2_j", "L2", "energy.l2"),
    e("energy_dram_j", "DRAM", "energy.dram"),
    m("area_mm2", "Chip area", "mm²", "area.total", None),
    m(
        "mrps_per_mm2",
        "Ray throughput per area",
        "Mrays/s/mm²",
        "mrps_per_mm2",
        None,
    ),
];

/// The metric of a column.
pub fn metric(column: &str) -> Option<&'static Metric> {
    METRICS.iter().find(|m| m.column == column)
}

/// `label (unit)`.
pub fn axis_label(m: &Metric) -> String {
    if m.unit.is_empty() {
        m.label.to_string()
    } else {
        format!("{} ({})", m.label, m.unit)
    }
}

/// Whether statistics JSON comes from a functional run.
pub fn is_functional(stats: &Value) -> bool {
    stats.get("mode").and_then(Value::as_str) == Some("functional")
}

/// A metric's value in a run's statistics (none where the run does not report it).
pub fn extract(m: &Metric, stats: &Value) -> Option<f64> {
    let path = if is_functional(stats) {
        m.functional?
    } else {
        m.timing
    };
    let mut v = stats;
    for k in path.split('.') {
        v = v.get(k)?;
    }
    v.as_f64()
}

/// The metric columns for runs in these modes (`functional`, `timing`).
pub fn columns_for(functional: bool, timing: bool) -> Vec<&'static Metric> {
    METRICS
        .iter()
        .filter(|m| timing || (functional && m.functional.is_some()))
        .collect()
}
