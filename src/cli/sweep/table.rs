//! `trax sweep collect DIR`: merges the points' JSON files into `DIR/results.csv` (one row
//! per point of the plan, in sweep order; one column per parameter and per headline metric)
//! and draws the sweep file's plots. It does not matter what ran the points.
//!
//! Columns: `id`, `status` (`ok`; `failed`; `stale` = its result's inputs changed since, see
//! [`super::state`]; `running`; `pending` = not run yet), the parameters, the metrics
//! ([`super::metrics::all`]; timing-only ones when the sweep has timing points; only
//! for `ok` rows: a stale result is not reported; a sampled point's are its estimates, and
//! in a sweep with sampled points each estimated metric is followed by `METRIC_ci95`, the
//! half-width of its 95% interval, empty for full runs), `wall_seconds` (host time of the run)
//! and `error` (a failed point's error, what changed for a stale one). Empty cells are
//! missing values.

use std::path::Path;

use serde_json::Value;

use super::metrics::{self, Metric};
use super::plan::Plan;
use super::spec::PVal;
use super::state::{current_plan, Judge, State};

/// Counts of a collected table.
#[derive(Debug, Default)]
pub struct Collected {
    /// Points in the plan.
    pub points: u64,
    /// Finished, with current inputs.
    pub ok: u64,
    /// Failed, with current inputs.
    pub failed: u64,
    /// With a result whose inputs changed since.
    pub stale: u64,
    /// Running now (another runner).
    pub running: u64,
    /// Not run yet.
    pub pending: u64,
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
        plan.grid
            .indices()
            .any(|i| plan.grid.point(i).params.get("mode") == Some(&PVal::Str(m.into())))
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

/// Writes `DIR/results.csv` and the plots, judging each point against its inputs as they
/// are now (the kernels built anew).
pub fn collect(dir: &Path) -> Result<Collected, String> {
    let (exe, exe_sha256) = super::this_exe()?;
    let (plan, errors) = current_plan(dir, &exe)?;
    let mut judge = Judge::new(&plan, dir, &exe_sha256).with_kernel_errors(errors);
    collect_with(dir, &plan, &mut judge)
}

/// [`collect`] with a plan whose kernels are built and a judge of it.
pub fn collect_with(dir: &Path, plan: &Plan, judge: &mut Judge) -> Result<Collected, String> {
    let mcols = metric_columns(plan);
    let mut header: Vec<String> = vec!["id".into(), "status".into()];
    header.extend(plan.columns.iter().cloned());
    // In a sweep with sampled points, each estimated metric's 95% half-width follows it.
    let sampled = plan.columns.iter().any(|c| c == "sample");
    let cells: Vec<(&Metric, bool)> = mcols
        .iter()
        .flat_map(|m| {
            let ci = sampled && metrics::ci_column(m).is_some();
            std::iter::once((*m, false)).chain(ci.then_some((*m, true)))
        })
        .collect();
    header.extend(cells.iter().map(|(m, ci)| match ci {
        false => m.column.to_string(),
        true => metrics::ci_column(m).unwrap_or_default(),
    }));
    header.extend(["wall_seconds".into(), "error".into()]);
    // Streamed to a temporary file, renamed when whole.
    let out = dir.join("results.csv");
    let tmp = dir.join(format!(".results.csv.tmp.{}", std::process::id()));
    let file = std::fs::File::create(&tmp).map_err(|e| format!("{}: {e}", tmp.display()))?;
    let mut w = csv::Writer::from_writer(std::io::BufWriter::new(file));
    let werr = |e: csv::Error| format!("{}: {e}", tmp.display());
    w.write_record(&header).map_err(werr)?;
    let mut c = Collected {
        points: plan.grid.point_count(),
        ..Collected::default()
    };
    let mut ids: std::collections::HashSet<u64> = std::collections::HashSet::new();
    for p in plan.points() {
        let p = p?;
        if let Ok(bits) = u64::from_str_radix(&p.id, 16) {
            ids.insert(bits);
        }
        let mut row: Vec<String> = vec![p.id.clone()];
        let (state, record) = judge.state(&p);
        let record = record.filter(|_| state == State::Done);
        let stats = record
            .as_ref()
            .and_then(|v| v.get("stats"))
            .filter(|s| !s.is_null());
        let wall = record
            .as_ref()
            .and_then(|v| v.get("wall_seconds"))
            .and_then(Value::as_f64);
        let error = match &state {
            State::Done | State::Running(_) | State::Pending(None) => String::new(),
            State::Pending(Some(n)) => n.clone(),
            State::Failed(e) => e.clone(),
            State::Stale(why) => why.join("; "),
        };
        match state {
            State::Done => c.ok += 1,
            State::Failed(_) => c.failed += 1,
            State::Stale(_) => c.stale += 1,
            State::Running(_) => c.running += 1,
            State::Pending(_) => c.pending += 1,
        }
        row.push(state.word().into());
        for col in &plan.columns {
            row.push(p.params.get(col).map(PVal::plain).unwrap_or_default());
        }
        for (m, ci) in &cells {
            let get = if *ci {
                metrics::extract_ci95
            } else {
                metrics::extract
            };
            row.push(stats.and_then(|s| get(m, s)).map(num).unwrap_or_default());
        }
        row.push(wall.map(num).unwrap_or_default());
        row.push(error);
        w.write_record(&row).map_err(werr)?;
    }
    w.flush().map_err(|e| format!("{}: {e}", tmp.display()))?;
    drop(w);
    std::fs::rename(&tmp, &out).map_err(|e| format!("{}: {e}", out.display()))?;
    if let Ok(entries) = std::fs::read_dir(dir.join("points")) {
        c.extra = entries
            .filter_map(|e| e.ok()?.file_name().into_string().ok())
            .filter(|n| !n.starts_with('.'))
            .filter_map(|n| n.strip_suffix(".json").map(str::to_string))
            .filter(|id| u64::from_str_radix(id, 16).map_or(true, |b| !ids.contains(&b)))
            .count();
    }
    let (plots, errors) = crate::cli::plot::draw_plan_plots(dir, &plan.plots);
    c.plots = plots;
    c.plot_errors = errors;
    Ok(c)
}

/// Prints what `collect` found.
pub fn report(dir: &Path, c: &Collected) {
    let mut others = String::new();
    if c.stale > 0 {
        others += &format!(", {} stale", c.stale);
    }
    if c.running > 0 {
        others += &format!(", {} running", c.running);
    }
    eprintln!(
        "{} points: {} ok, {} failed{others}, {} not run -> {}",
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
