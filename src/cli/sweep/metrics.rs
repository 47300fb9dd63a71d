//! The headline metrics of a run: the columns of `results.csv` after the parameters, and the
//! y axes of `trax plot`. This is the one place that knows where they are in the statistics
//! document of `trax run --stats-json` (schema 1, `docs/STATS.md`: one shape for both modes;
//! what functional runs do not measure is `null` there, an empty cell here).

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
    /// Dotted path in the statistics document.
    pub path: &'static str,
    /// A component of the energy per frame (stacked in energy charts).
    pub energy_part: bool,
}

impl Metric {
    /// Whether functional runs report it (everything but cycles and the `timing` object).
    pub fn functional(&self) -> bool {
        self.path != "cycles" && !self.path.starts_with("timing.")
    }
}

const fn m(
    column: &'static str,
    label: &'static str,
    unit: &'static str,
    path: &'static str,
) -> Metric {
    Metric {
        column,
        label,
        unit,
        path,
        energy_part: false,
    }
}

const fn e(column: &'static str, label: &'static str, path: &'static str) -> Metric {
    Metric {
        energy_part: true,
        ..m(column, label, "J", path)
    }
}

/// The metrics, in table order.
pub const METRICS: &[Metric] = &[
    m("instructions", "Instructions", "", "instructions"),
    m("rays", "Rays", "", "rays"),
    m("cycles", "Run time", "cycles", "cycles"),
    m("seconds", "Simulated time", "s", "timing.seconds"),
    m("fps", "Frame rate", "frames/s", "timing.fps"),
    m("mrps", "Ray throughput", "Mrays/s", "timing.mrps"),
    m(
        "issue_rate",
        "Issue rate",
        "issued / thread-cycle",
        "timing.issue_rate",
    ),
    m("l1_hit_rate", "L1 hit rate", "", "timing.l1_hit_rate"),
    m("l2_hit_rate", "L2 hit rate", "", "timing.l2_hit_rate"),
    m("dram_gbps", "DRAM bandwidth", "GB/s", "timing.dram_gbps"),
    m("dram_reads", "DRAM reads", "", "timing.memory.dram.reads"),
    m(
        "dram_writes",
        "DRAM writes",
        "",
        "timing.memory.dram.writes",
    ),
    m(
        "dram_row_hit_rate",
        "DRAM row-buffer hit rate",
        "",
        "timing.memory.dram.row_hit_rate",
    ),
    m(
        "dram_read_latency",
        "DRAM read latency",
        "cycles",
        "timing.memory.dram.avg_read_latency_cycles",
    ),
    m("power_w", "Power", "W", "timing.power_w"),
    m("energy_j", "Energy per frame", "J", "timing.energy.total"),
    e(
        "energy_units_j",
        "Execution units",
        "timing.energy.execution_units",
    ),
    e(
        "energy_regs_j",
        "Register files",
        "timing.energy.register_files",
    ),
    e(
        "energy_icache_j",
        "Instruction caches",
        "timing.energy.instruction_caches",
    ),
    e(
        "energy_local_j",
        "Local stores",
        "timing.energy.local_stores",
    ),
    e("energy_l1_j", "L1", "timing.energy.l1"),
    e("energy_l2_j", "L2", "timing.energy.l2"),
    e(
        "energy_stream_j",
        "Stream memory",
        "timing.energy.stream_memory",
    ),
    e("energy_pipelines_j", "Pipelines", "timing.energy.pipelines"),
    e("energy_dram_j", "DRAM", "timing.energy.dram"),
    m(
        "stream_reads",
        "Stream memory reads",
        "",
        "timing.stream.reads",
    ),
    m(
        "stream_writes",
        "Stream memory writes",
        "",
        "timing.stream.writes",
    ),
    m(
        "rays_in_flight",
        "Rays in flight (mean)",
        "",
        "timing.stream.mean_rays_in_flight",
    ),
    m(
        "stream_idle_tm_cycles",
        "TM-cycles idle for lack of rays",
        "cycles",
        "timing.stream.idle_tm_cycles",
    ),
    m(
        "stream_schedules",
        "Stream buffer visits",
        "",
        "timing.stream.schedules",
    ),
    m(
        "stream_rays_per_visit",
        "Rays per buffer visit",
        "",
        "timing.stream.rays_per_visit",
    ),
    m("area_mm2", "Chip area", "mm²", "timing.area.total"),
    m(
        "mrps_per_mm2",
        "Ray throughput per area",
        "Mrays/s/mm²",
        "timing.mrps_per_mm2",
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

/// A metric's value in a run's statistics document (none where the run does not report
/// it: `null`, or a document of another schema).
pub fn extract(m: &Metric, stats: &Value) -> Option<f64> {
    if stats.get("schema").and_then(Value::as_u64) != Some(u64::from(trax::stats::SCHEMA)) {
        return None;
    }
    let mut v = stats;
    for k in m.path.split('.') {
        v = v.get(k)?;
    }
    v.as_f64()
}

/// The metric columns for runs in these modes (`functional`, `timing`).
pub fn columns_for(functional: bool, timing: bool) -> Vec<&'static Metric> {
    METRICS
        .iter()
        .filter(|m| timing || (functional && m.functional()))
        .collect()
}
