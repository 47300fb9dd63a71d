//! `trax plot STATS.json --over-time --y METRIC`: one metric of a timing run's
//! `timing.intervals` (`trax run --stats-interval N`) against simulated time, in µs. Each
//! interval is drawn as a horizontal step over its cycles (the value is the interval's
//! count or average, not a sample at one instant); the partial last interval is as wide
//! as it is.

use std::path::{Path, PathBuf};

use plotters::coord::Shift;
use plotters::prelude::*;
use serde_json::Value;
use trax_emulator::timing::{Interval, ThreadCycles};

use super::axis::{Axis, Unit};
use super::{colour, register_font, PlotArgs, SIZE};

/// Every series the chart can draw: the interval's own ([`Interval::series`]) and its
/// thread-cycle buckets (`thread_cycles.NAME`, [`ThreadCycles::BUCKETS`]), both from their
/// one declaration in the emulator.
fn names() -> String {
    let mut v: Vec<String> = Interval::series().map(|(n, _)| n.to_string()).collect();
    v.extend(
        ThreadCycles::BUCKETS
            .iter()
            .map(|b| format!("thread_cycles.{}", b.name)),
    );
    v.join(", ")
}

/// One interval: its cycles and the metric's value (`None`: not measured, e.g. rays in
/// flight without a stream memory).
struct Step {
    start: u64,
    end: u64,
    value: Option<f64>,
}

/// Reads the intervals of the statistics document at `path` and the metric `y` of each.
fn load(path: &Path, y: &str) -> Result<(Vec<Step>, f64, String), String> {
    let name = path.display();
    let text = std::fs::read_to_string(path).map_err(|e| format!("{name}: {e}"))?;
    let doc: Value = serde_json::from_str(&text)
        .map_err(|e| format!("{name}: not a statistics document: {e}"))?;
    if doc.get("schema").and_then(Value::as_u64) != Some(1) {
        return Err(format!(
            "{name}: not a statistics document of schema 1 (`trax run --stats-json`)"
        ));
    }
    let timing = doc.get("timing").filter(|t| !t.is_null()).ok_or_else(|| {
        format!("{name}: a functional run has no statistics over time (run in timing mode with --stats-interval N)")
    })?;
    let ivs = timing
        .get("intervals")
        .and_then(Value::as_array)
        .filter(|a| !a.is_empty())
        .ok_or_else(|| format!("{name}: no timing.intervals (run with --stats-interval N)"))?;
    let ghz = doc
        .pointer("/chip/clock_ghz")
        .and_then(Value::as_f64)
        .filter(|g| *g > 0.0)
        .ok_or_else(|| format!("{name}: chip.clock_ghz missing or not positive"))?;
    let label = if let Some(b) = y.strip_prefix("thread_cycles.") {
        let bucket = ThreadCycles::BUCKETS
            .iter()
            .find(|k| k.name == b)
            .ok_or_else(|| format!("no interval metric `{y}`; one of: {}", names()))?;
        format!("{} (fraction of thread-cycles)", bucket.label)
    } else {
        Interval::series()
            .find(|(n, _)| *n == y)
            .map(|(_, l)| l.to_string())
            .ok_or_else(|| format!("no interval metric `{y}`; one of: {}", names()))?
    };
    let mut steps = Vec::with_capacity(ivs.len());
    for (i, iv) in ivs.iter().enumerate() {
        let int = |f: &str| {
            iv.get(f).and_then(Value::as_u64).ok_or_else(|| {
                format!("{name}: timing.intervals[{i}].{f} missing or not an integer")
            })
        };
        let (start, end) = (int("start_cycle")?, int("end_cycle")?);
        if end <= start || steps.last().is_some_and(|s: &Step| s.end != start) {
            return Err(format!(
                "{name}: timing.intervals[{i}] ({start}..{end}) does not follow the previous one"
            ));
        }
        let value =
            match y.strip_prefix("thread_cycles.") {
                Some(b) => {
                    let tc = iv
                        .get("thread_cycles")
                        .and_then(Value::as_object)
                        .ok_or_else(|| {
                            format!("{name}: timing.intervals[{i}].thread_cycles missing")
                        })?;
                    let all: f64 = tc.values().filter_map(Value::as_f64).sum();
                    let v = tc.get(b).and_then(Value::as_f64).ok_or_else(|| {
                        format!("{name}: timing.intervals[{i}].thread_cycles.{b} missing")
                    })?;
                    Some(if all > 0.0 { v / all } else { 0.0 })
                }
                None => match iv.get(y) {
                    Some(Value::Null) => None,
                    Some(v) => Some(v.as_f64().ok_or_else(|| {
                        format!("{name}: timing.intervals[{i}].{y} is not a number")
                    })?),
                    None => return Err(format!("{name}: timing.intervals[{i}].{y} missing")),
                },
            };
        steps.push(Step { start, end, value });
    }
    if steps.iter().all(|s| s.value.is_none()) {
        return Err(format!(
            "{name}: `{y}` is null in every interval (not measured on this chip)"
        ));
    }
    Ok((steps, ghz, label))
}

/// `trax plot STATS.json --over-time --y METRIC [--title T] [-o OUT]`.
pub(super) fn plot_cmd(a: &PlotArgs) -> Result<(PathBuf, PathBuf), String> {
    let y =
        a.y.as_deref()
            .ok_or_else(|| format!("--over-time needs --y METRIC, one of: {}", names()))?;
    let (steps, ghz, ylabel) = load(&a.results, y)?;
    let out = match &a.out {
        Some(o) => {
            let s = o.display().to_string();
            let s = s
                .strip_suffix(".png")
                .or_else(|| s.strip_suffix(".svg"))
                .unwrap_or(&s);
            PathBuf::from(s)
        }
        None => {
            let stem = a.results.with_extension("");
            PathBuf::from(format!(
                "{}_{}_over_time",
                stem.display(),
                y.replace('.', "_")
            ))
        }
    };
    // The metric's name from its axis label (`DRAM bytes (per interval)` -> `DRAM bytes`).
    let title = a.title.clone().unwrap_or_else(|| {
        let name = ylabel.split(" (").next().unwrap_or(y);
        format!("{name} over time")
    });
    let unit = if y.ends_with("bytes") {
        Unit::Bytes
    } else {
        Unit::Number
    };
    register_font();
    if let Some(dir) = out.parent().filter(|p| !p.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    }
    let with_ext = |ext: &str| {
        let mut s = out.as_os_str().to_owned();
        s.push(ext);
        PathBuf::from(s)
    };
    let (png, svg) = (with_ext(".png"), with_ext(".svg"));
    super::png_chart(&png, |root| {
        render(root, &steps, ghz, &title, &ylabel, unit)
    })?;
    let mut text = String::new();
    {
        let root = SVGBackend::with_string(&mut text, SIZE).into_drawing_area();
        render(&root, &steps, ghz, &title, &ylabel, unit)?;
        root.present().map_err(|e| e.to_string())?;
    }
    std::fs::write(&svg, text).map_err(|e| format!("{}: {e}", svg.display()))?;
    Ok((png, svg))
}

fn render<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    steps: &[Step],
    ghz: f64,
    title: &str,
    ylabel: &str,
    unit: Unit,
) -> Result<(), String> {
    let e = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    root.fill(&WHITE).map_err(e)?;
    // Simulated time in µs: cycles / (GHz x 1000).
    let us = |c: u64| c as f64 / (ghz * 1e3);
    let x_end = us(steps.last().map_or(1, |s| s.end));
    let values: Vec<f64> = steps.iter().filter_map(|s| s.value).collect();
    let yaxis = Axis::fit(&values, unit, Some(false), true, 0.08)?;
    let xaxis = Axis::fit(&[0.0, x_end], Unit::Number, Some(false), true, 0.0)?;
    let title_size = 26.0f64.min(1.9 * SIZE.0 as f64 / title.chars().count().max(1) as f64);
    let (title_area, plot_area) = root.split_vertically(50);
    title_area
        .draw(&Text::new(
            title.to_string(),
            (85, 14),
            ("sans-serif", title_size).into_font(),
        ))
        .map_err(e)?;
    let mut chart = ChartBuilder::on(&plot_area)
        .margin(18)
        .margin_top(4)
        .x_label_area_size(55)
        .y_label_area_size(85)
        .build_cartesian_2d(xaxis.coord(), yaxis.coord())
        .map_err(e)?;
    let x_fmt = |v: &f64| xaxis.label(*v);
    let y_fmt = |v: &f64| yaxis.label(*v);
    chart
        .configure_mesh()
        .x_desc("simulated time (µs)")
        .y_desc(ylabel)
        .axis_desc_style(("sans-serif", 18))
        .label_style(("sans-serif", 15))
        .light_line_style(TRANSPARENT)
        .x_label_formatter(&x_fmt)
        .y_label_formatter(&y_fmt)
        .draw()
        .map_err(e)?;
    // Runs of measured intervals, each a staircase.
    let c = colour(0);
    let mut run: Vec<(f64, f64)> = Vec::new();
    let mut runs = Vec::new();
    for s in steps {
        match s.value {
            Some(v) => run.extend([(us(s.start), v), (us(s.end), v)]),
            None => runs.push(std::mem::take(&mut run)),
        }
    }
    runs.push(run);
    for r in runs.into_iter().filter(|r| !r.is_empty()) {
        chart
            .draw_series(LineSeries::new(r, c.stroke_width(2)))
            .map_err(e)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The over-time chart fits its canvas, with byte values across decades of time steps.
    #[test]
    fn over_time_chart_fits_its_canvas() {
        let steps: Vec<Step> = (0..50u64)
            .map(|i| Step {
                start: i * 1000,
                end: (i + 1) * 1000,
                value: (i % 7 != 3).then(|| (i as f64 * 0.37).sin().abs() * 3.2e9),
            })
            .collect();
        let path = std::env::temp_dir().join(format!("trax-over-time-{}.png", std::process::id()));
        crate::cli::plot::png_chart(&path, |root| {
            render(
                root,
                &steps,
                1.0,
                "DRAM bytes over time",
                "DRAM bytes (per interval)",
                Unit::Bytes,
            )
        })
        .unwrap();
        let fits = crate::cli::plot::margins_blank(&path);
        let _ = std::fs::remove_file(&path);
        fits.unwrap();
    }
}
