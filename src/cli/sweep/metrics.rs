//! The headline metrics of a run: the columns of `results.csv` after the parameters, and the
//! y axes of `trax plot`. This is the one place that knows where they are in the statistics
//! document of `trax run --stats-json` (schema 1, `docs/STATS.md`: one shape for both modes;
//! what functional runs do not measure is `null` there, an empty cell here).

use serde_json::Value;

/// One headline metric.
#[derive(Clone, Copy, Debug)]
pub struct Metric {
    /// Column name.
    pub column: &'static str,
    /// Axis label (without the unit).
    pub label: &'static str,
    /// Unit (empty: a count or a ratio).
    pub unit: &'static str,
    /// Dotted path in the statistics document; `a+b` sums paths, and a segment `name[]`
    /// sums the rest of the path over the elements of array `name` (one L2 each, say).
    pub path: &'static str,
    /// A component of the energy per frame (stacked in energy charts).
    pub energy_part: bool,
    /// A count kept in a map that lists only what happened (`timing.class_mix.NAME`):
    /// absent from the map is 0.
    pub absent_is_zero: bool,
}

impl Metric {
    /// Whether functional runs report it (everything but cycles and the `timing` object).
    pub fn functional(&self) -> bool {
        self.path
            .split('+')
            .all(|p| p != "cycles" && !p.starts_with("timing."))
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
        absent_is_zero: false,
    }
}

/// A place in [`METRICS`] for the declared statistic whose column is `column`.
const fn stat(column: &'static str) -> Metric {
    m(column, "", "", "")
}

/// The metrics, in table order (the layout of `results.csv`): those of statistics
/// declared with a sweep column (`stat(COLUMN)`, label, unit and path from the
/// declaration: `trax_emulator::timing::TimingStats::STATS`) and the others, defined here
/// (counts at the document's top level, the memory system's, sums of paths).
pub const METRICS: &[Metric] = &[
    m("instructions", "Instructions", "", "instructions"),
    m("rays", "Rays", "", "rays"),
    m("cycles", "Run time", "cycles", "cycles"),
    stat("seconds"),
    stat("fps"),
    stat("mrps"),
    stat("issue_rate"),
    stat("l1_hit_rate"),
    stat("l1_hit_rate_merged"),
    m(
        "l1_accesses",
        "L1 accesses",
        "",
        "timing.memory.l1.accesses",
    ),
    m("l1_misses", "L1 misses", "", "timing.memory.l1.misses"),
    stat("l2_hit_rate"),
    m(
        "l2_accesses",
        "L2 accesses",
        "",
        "timing.memory.l2[].accesses",
    ),
    m("l2_misses", "L2 misses", "", "timing.memory.l2[].misses"),
    stat("dram_gbps"),
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
    stat("power_w"),
    m("energy_j", "Energy per frame", "J", "timing.energy.total"),
    m(
        "dram_background_nj",
        "DRAM background energy (standby + refresh)",
        "nJ",
        "timing.memory.dram.energy.background_nj+timing.memory.dram.energy.refresh_nj",
    ),
    m(
        "dram_dynamic_nj",
        "DRAM dynamic energy (activate + read + write)",
        "nJ",
        "timing.memory.dram.energy.activate_nj+timing.memory.dram.energy.read_nj+timing.memory.dram.energy.write_nj",
    ),
    stat("energy_per_ray_nj"),
    // Not parts of the stack: sums of the parts above.
    m(
        "energy_memsys_j",
        "Memory system energy (L2 + stream + DRAM)",
        "J",
        "timing.energy.l2+timing.energy.stream_memory+timing.energy.dram",
    ),
    m(
        "energy_fetch_rf_j",
        "Instruction fetch + register file energy",
        "J",
        "timing.energy.instruction_caches+timing.energy.register_files",
    ),
    stat("stream_reads"),
    stat("stream_writes"),
    m(
        "stream_accesses",
        "Stream memory accesses",
        "",
        "timing.stream.reads+timing.stream.writes",
    ),
    stat("rays_in_flight"),
    stat("stream_idle_tm_cycles"),
    stat("stream_schedules"),
    stat("stream_rays_per_visit"),
    m("area_mm2", "Chip area", "mm²", "timing.area.total"),
    stat("mrps_per_mm2"),
];

/// The metrics of the declared statistics with a sweep column, in declaration order.
fn declared() -> impl Iterator<Item = Metric> {
    use trax_emulator::timing::{stat, TimingStats};
    stat::walk(TimingStats::STATS).into_iter().filter_map(|st| {
        let c = st.column?;
        Some(m(c.name, c.label, c.unit, st.path))
    })
}

/// Every metric, in table order: [`METRICS`] (a declared statistic's in its place) with
/// the energy components after `energy_j` and the area components after `area_mm2` (their
/// declarations: `EnergyBreakdown::PARTS`, `AreaBreakdown::PARTS`), then the declared
/// statistics [`METRICS`] does not place, then per execution unit of the registry
/// (`trax_emulator::timing::UNITS`) the operations issued to it.
pub fn all() -> &'static [Metric] {
    use trax_emulator::timing::{AreaBreakdown, EnergyBreakdown};
    static ALL: std::sync::LazyLock<Vec<Metric>> = std::sync::LazyLock::new(|| {
        let mut v = Vec::new();
        for x in METRICS {
            match x.path {
                "" => v.push(
                    declared()
                        .find(|d| d.column == x.column)
                        .expect("METRICS places only declared statistics"),
                ),
                _ => v.push(*x),
            }
            if x.column == "energy_j" {
                v.extend(EnergyBreakdown::PARTS.iter().map(|p| Metric {
                    energy_part: true,
                    ..m(p.column, p.label, "J", p.path)
                }));
            }
            if x.column == "area_mm2" {
                let area = AreaBreakdown::PARTS.iter();
                v.extend(area.map(|p| m(p.column, p.label, "mm²", p.path)));
            }
        }
        v.extend(declared().filter(|d| !METRICS.iter().any(|x| x.column == d.column)));
        v.extend(trax_emulator::timing::UNITS.iter().map(|u| Metric {
            absent_is_zero: true,
            ..m(u.ops_column, u.ops_label, "", u.ops_path)
        }));
        v
    });
    &ALL
}

/// Where a sampled run (`trax run --sample N`) has the estimate of a metric:
/// `(column, name in sampled.estimates, factor to the column's unit)`. A sampled run's
/// other metrics are its exact counts (`rays`), or missing (it does not estimate them).
pub const SAMPLED: &[(&str, &str, f64)] = &[
    ("instructions", "instructions", 1.0),
    ("cycles", "cycles", 1.0),
    ("seconds", "seconds", 1.0),
    ("fps", "fps", 1.0),
    ("mrps", "mrps", 1.0),
    ("issue_rate", "issue_rate", 1.0),
    ("l1_hit_rate", "l1_hit_rate", 1.0),
    ("l1_hit_rate_merged", "l1_hit_rate_merged_as_hits", 1.0),
    ("l2_hit_rate", "l2_hit_rate", 1.0),
    ("l2_accesses", "l2_accesses", 1.0),
    ("dram_gbps", "dram_gbps", 1.0),
    ("dram_reads", "dram_reads", 1.0),
    ("dram_row_hit_rate", "dram_row_hit_rate", 1.0),
    ("dram_read_latency", "dram_read_latency_cycles", 1.0),
    ("power_w", "power_w", 1.0),
    ("energy_j", "energy_j", 1.0),
    ("energy_l1_j", "energy_l1_j", 1.0),
    ("energy_l2_j", "energy_l2_j", 1.0),
    ("energy_stream_j", "energy_stream_j", 1.0),
    ("energy_dram_j", "energy_dram_j", 1.0),
    ("dram_background_nj", "energy_dram_background_j", 1e9),
    ("dram_dynamic_nj", "energy_dram_dynamic_j", 1e9),
    ("energy_per_ray_nj", "energy_per_ray_nj", 1.0),
    ("energy_memsys_j", "energy_memsys_j", 1.0),
    ("stream_accesses", "stream_accesses", 1.0),
    ("rays_in_flight", "mean_rays_in_flight", 1.0),
    ("stream_idle_tm_cycles", "idle_tm_cycles", 1.0),
    ("stream_rays_per_visit", "rays_per_visit", 1.0),
];

/// Suffix of the column with a sampled estimate's 95% half-width (`cycles_ci95`).
pub const CI_SUFFIX: &str = "_ci95";

/// The estimate of `m` in a sampled run's statistics, and the factor to its unit.
fn sampled_estimate<'a>(m: &Metric, stats: &'a Value) -> Option<(&'a Value, f64)> {
    let (_, name, scale) = SAMPLED.iter().find(|(c, _, _)| *c == m.column)?;
    Some((stats.get("sampled")?.get("estimates")?.get(*name)?, *scale))
}

/// Whether a statistics document is a sampled run's.
fn is_sampled(stats: &Value) -> bool {
    stats.get("mode").and_then(Value::as_str) == Some("sampled")
}

/// The column of `m`'s 95% half-width in sampled sweeps (`None`: not estimated).
pub fn ci_column(m: &Metric) -> Option<String> {
    SAMPLED
        .iter()
        .any(|(c, _, _)| *c == m.column)
        .then(|| format!("{}{CI_SUFFIX}", m.column))
}

/// The metric whose half-width column this is (`cycles_ci95` -> cycles).
pub fn ci_of(column: &str) -> Option<&'static Metric> {
    let m = metric(column.strip_suffix(CI_SUFFIX)?)?;
    ci_column(m).is_some().then_some(m)
}

/// The half-width of `m`'s 95% interval in a sampled run's statistics (in the column's
/// unit; `None` for other runs, and metrics a sampled run does not estimate).
pub fn extract_ci95(m: &Metric, stats: &Value) -> Option<f64> {
    if !is_sampled(stats) {
        return None;
    }
    let (e, scale) = sampled_estimate(m, stats)?;
    let lo = e.get("ci95_low")?.as_f64()?;
    let hi = e.get("ci95_high")?.as_f64()?;
    Some((hi - lo) / 2.0 * scale)
}

/// The metric of a column.
pub fn metric(column: &str) -> Option<&'static Metric> {
    all().iter().find(|m| m.column == column)
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
/// it: `null`, or a document of another schema); a sampled run's estimate ([`SAMPLED`]).
pub fn extract(m: &Metric, stats: &Value) -> Option<f64> {
    if stats.get("schema").and_then(Value::as_u64) != Some(u64::from(trax::stats::SCHEMA)) {
        return None;
    }
    if is_sampled(stats) {
        if let Some((e, scale)) = sampled_estimate(m, stats) {
            return e.get("estimate")?.as_f64().map(|v| v * scale);
        }
    }
    m.path
        .split('+')
        .map(|p| match sum_at(stats, p) {
            None if m.absent_is_zero && absent_from_its_map(stats, p) => Some(0.0),
            v => v,
        })
        .sum()
}

/// Whether `path`'s last key is missing from a map that is there.
fn absent_from_its_map(v: &Value, path: &str) -> bool {
    let (map, key) = path.rsplit_once('.').unwrap_or(("", path));
    let parent = map
        .split('.')
        .filter(|k| !k.is_empty())
        .try_fold(v, |v, k| v.get(k));
    parent
        .and_then(Value::as_object)
        .is_some_and(|o| !o.contains_key(key))
}

/// The number at dotted `path` in `v`, summed over arrays marked `name[]`.
fn sum_at(v: &Value, path: &str) -> Option<f64> {
    let (head, rest) = match path.split_once('.') {
        Some((h, r)) => (h, Some(r)),
        None => (path, None),
    };
    match (head.strip_suffix("[]"), rest) {
        (Some(name), Some(rest)) => v
            .get(name)?
            .as_array()?
            .iter()
            .map(|e| sum_at(e, rest))
            .sum(),
        (Some(name), None) => v.get(name)?.as_array()?.iter().map(Value::as_f64).sum(),
        (None, Some(rest)) => sum_at(v.get(head)?, rest),
        (None, None) => v.get(head)?.as_f64(),
    }
}

/// The metric columns for runs in these modes (`functional`, `timing`).
pub fn columns_for(functional: bool, timing: bool) -> Vec<&'static Metric> {
    all()
        .iter()
        .filter(|m| timing || (functional && m.functional()))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn doc() -> Value {
        serde_json::json!({
            "schema": trax::stats::SCHEMA,
            "cycles": 10,
            "timing": {
                "energy": { "l2": 1.5, "stream_memory": 0.25, "dram": 2.0 },
                "memory": { "l2": [ { "accesses": 3 }, { "accesses": 4 } ] },
                "stream": { "reads": 5, "writes": null }
            }
        })
    }

    #[test]
    fn paths_sum_terms_and_arrays() {
        let d = doc();
        let get = |c: &str| extract(metric(c).unwrap(), &d);
        assert_eq!(get("energy_memsys_j"), Some(3.75));
        assert_eq!(get("l2_accesses"), Some(7.0));
        assert_eq!(get("cycles"), Some(10.0));
        // A missing or null term makes the sum missing, not partial.
        assert_eq!(get("stream_accesses"), None);
        assert_eq!(get("l2_misses"), None);
    }

    #[test]
    fn every_path_names_documented_fields() {
        let stats = include_str!("../../../docs/STATS.md");
        for m in all() {
            for field in m.path.split('+') {
                // A map's entries are documented as `MAP.*`.
                let field = match m.absent_is_zero {
                    true => format!("{}.*", field.rsplit_once('.').unwrap().0),
                    false => field.to_string(),
                };
                assert!(
                    stats.contains(&format!("`{field}`")),
                    "{}: `{field}` is not in docs/STATS.md",
                    m.column
                );
            }
        }
        for (column, name, _) in SAMPLED {
            assert!(metric(column).is_some(), "SAMPLED: no metric {column}");
            assert!(
                stats.contains(&format!("`sampled.estimates.{name}`")),
                "{column}: `sampled.estimates.{name}` is not in docs/STATS.md"
            );
        }
        assert_eq!(ci_of("cycles_ci95").map(|m| m.column), Some("cycles"));
        assert!(ci_of("l1_accesses_ci95").is_none() && ci_of("cycles").is_none());
        assert!(!metric("energy_memsys_j").unwrap().functional());
        assert!(metric("instructions").unwrap().functional());
    }

    /// Every statistic declared with a sweep column is a metric, once, with its declared
    /// label, unit and path; every metric `METRICS` places by name is declared.
    #[test]
    fn every_declared_column_is_a_metric() {
        use trax_emulator::timing::{stat, TimingStats};
        let mut n = 0;
        for st in stat::walk(TimingStats::STATS) {
            let Some(c) = st.column else { continue };
            n += 1;
            let m = metric(c.name).unwrap_or_else(|| panic!("{}", c.name));
            assert_eq!((m.label, m.unit, m.path), (c.label, c.unit, st.path));
            assert_eq!(all().iter().filter(|x| x.column == c.name).count(), 1);
        }
        assert!(n > 0);
        assert!(all()
            .iter()
            .all(|m| !m.path.is_empty() && !m.label.is_empty()));
    }

    /// Every energy and area component has its column at its path; energy ones stack.
    #[test]
    fn every_breakdown_part_has_a_column() {
        use trax_emulator::timing::{AreaBreakdown, EnergyBreakdown};
        let parts = EnergyBreakdown::PARTS
            .iter()
            .map(|p| (p.column, p.path, true));
        let area = AreaBreakdown::PARTS
            .iter()
            .map(|p| (p.column, p.path, false));
        for (column, path, energy) in parts.chain(area) {
            let m = metric(column).unwrap_or_else(|| panic!("{column}"));
            assert_eq!((m.path, m.energy_part), (path, energy), "{column}");
        }
    }

    /// Every execution unit of the registry has its column, read from the document's
    /// class mix, 0 when the map does not list it, none in functional runs.
    #[test]
    fn every_unit_has_an_operations_column() {
        let d = serde_json::json!({
            "schema": trax::stats::SCHEMA,
            "timing": { "class_mix": { "fp_mul": 12 } }
        });
        let f = serde_json::json!({ "schema": trax::stats::SCHEMA, "timing": null });
        for u in trax_emulator::timing::UNITS {
            let m = metric(u.ops_column).unwrap_or_else(|| panic!("{}", u.name));
            assert!(columns_for(false, true)
                .iter()
                .any(|c| c.column == m.column));
            assert!(!columns_for(true, false)
                .iter()
                .any(|c| c.column == m.column));
            let want = if u.name == "fp_mul" { 12.0 } else { 0.0 };
            assert_eq!(extract(m, &d), Some(want), "{}", u.name);
            assert_eq!(extract(m, &f), None, "{}", u.name);
        }
    }
}
