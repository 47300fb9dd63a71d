//! `trax sweep collect DIR`: merges the points' JSON files into `DIR/results.csv` (one row
//! per point of the plan, in sweep order; one column per parameter and per headline metric)
//! and draws the sweep file's plots. It does not matter what ran the points.
//!
//! Columns: `id`, `status` (`ok`, `failed`, `pending` = not run yet), the parameters, the
//! metrics ([`super::metrics::METRICS`]; timing-only ones when the sweep has timing points),
//! `wall_seconds` (host time of the run) and `error`. Empty cells are missing values.

use std::path::Path;

use serde_json::Value;

use super::metrics::{self, Metric};
use super::plan::{write_atomic, Plan};
use super::runner::point_path;
use super::spec::PVal;

/// Counts of a collected table.
#[derive(Debug, Default)]
pub struct Collected {
    /// Points in the plan.
    pub points: usize,
    /// Finished.
    pub ok: usize,
    /// Failed.
    pub failed: usize,
    /// Not run yet.
    pub pending: usize,
    /// Results in `points/` of points the plan no longer has (left out of the table).
    pub extra: usize,
    /// Plot files written.
    pub plots: Vec<std::path::PathBuf>,
    /// Plots that could not be drawn.
    pub plot_errors: Vec<String>,
}

/// The metric columns of a plan (functional-only sweeps have no timing columns).
pub fn metric_columns(plan: &Plan) -> Vec<&'static Metric> {
    let mode = |m: &str| {
        plan.points
            .iter()
            .any(|p| p.params.get("mode") == Some(&PVal::Str(m.into())))
    };
    metrics::columns_for(mode("functional"), mode("timing"))
}

/// Formats a number for the table (shortest form that reads back the same).
fn num(v: f64) -> String {
    if v.is_finite() {
        format!("{v}")
    } else {
        String::new()
    }
}

/// Writes `DIR/results.csv` and the plots.
pub fn collect(dir: &Path) -> Result<Collected, String> {
    let plan = Plan::load(dir)?;
    let mcols = metric_columns(&plan);
    let mut header: Vec<String> = vec!["id".into(), "status".into()];
    header.extend(plan.columns.iter().cloned());
    header.extend(mcols.iter().map(|m| m.column.to_string()));
    header.extend(["wall_seconds".into(), "error".into()]);
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record(&header).map_err(|e| e.to_string())?;
    let mut c = Collected {
        points: plan.points.len(),
        ..Collected::default()
    };
    for p in &plan.points {
        let mut row: Vec<String> = vec![p.id.clone()];
        let path = point_path(dir, &p.id);
        let record: Option<Result<Value, String>> = match std::fs::read_to_string(&path) {
            Ok(t) => Some(serde_json::from_str(&t).map_err(|e| format!("{}: {e}", path.display()))),
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => None,
            Err(e) => Some(Err(format!("{}: {e}", path.display()))),
        };
        let (status, stats, wall, error) = match &record {
            None => ("pending", None, None, String::new()),
            Some(Err(e)) => ("failed", None, None, e.clone()),
            Some(Ok(v)) => {
                let status = match v.get("status").and_then(Value::as_str) {
                    Some("ok") => "ok",
                    _ => "failed",
                };
                let error = v
                    .get("error")
                    .and_then(Value::as_str)
                    .unwrap_or_default()
                    .lines()
                    .next()
                    .unwrap_or_default()
                    .to_string();
                (
                    status,
                    v.get("stats").filter(|s| !s.is_null()),
                    v.get("wall_seconds").and_then(Value::as_f64),
                    error,
                )
            }
        };
        match status {
            "ok" => c.ok += 1,
            "failed" => c.failed += 1,
            _ => c.pending += 1,
        }
        row.push(status.into());
        for col in &plan.columns {
            row.push(p.params.get(col).map(PVal::plain).unwrap_or_default());
        }
        for m in &mcols {
            row.push(
                stats
                    .and_then(|s| metrics::extract(m, s))
                    .map(num)
                    .unwrap_or_default(),
            );
        }
        row.push(wall.map(num).unwrap_or_default());
        row.push(error);
        w.write_record(&row).map_err(|e| e.to_string())?;
    }
    let ids: std::collections::HashSet<&str> = plan.points.iter().map(|p| p.id.as_str()).collect();
    if let Ok(entries) = std::fs::read_dir(dir.join("points")) {
        c.extra = entries
            .filter_map(|e| e.ok()?.file_name().into_string().ok())
            .filter(|n| !n.starts_with('.'))
            .filter_map(|n| n.strip_suffix(".json").map(str::to_string))
            .filter(|id| !ids.contains(id.as_str()))
            .count();
    }
    let bytes = w.into_inner().map_err(|e| e.to_string())?;
    write_atomic(&dir.join("results.csv"), &bytes)?;
    let (plots, errors) = crate::cli::plot::draw_plan_plots(dir, &plan.plots);
    c.plots = plots;
    c.plot_errors = errors;
    Ok(c)
}

/// Prints what `collect` found.
pub fn report(dir: &Path, c: &Collected) {
    eprintln!(
        "{} points: {} ok, {} failed, {} not run -> {}",
        c.points,
        c.ok,
        c.failed,
        c.pending,
        dir.join("results.csv").display()
    );
    if c.extra > 0 {
        eprintln!(
            "note: {} result(s) in {} are of points the sweep no longer has (left out)",
            c.extra,
            dir.join("points").display()
        );
    }
    for p in &c.plots {
        eprintln!("wrote {}", p.display());
    }
    for e in &c.plot_errors {
        eprintln!("warning: {e}");
    }
}
