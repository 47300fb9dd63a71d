//! `trax plot RESULTS --x PARAM --y METRIC [--by PARAM]`: charts of a sweep's
//! `results.csv` as PNG and SVG — lines, grouped bars, or the energy per frame stacked by
//! component — with labelled axes (units from [`crate::cli::sweep::metrics`]), a legend and a
//! title. `trax plot STATS.json --over-time --y METRIC`: one run's statistics over time
//! (`trax run --stats-interval N`), a metric of `timing.intervals` against simulated time,
//! drawn as a step per interval (see [`over_time`]).
//!
//! Text is drawn with DejaVu Sans, embedded in the binary (crate `dejavu`), through plotters'
//! `ab_glyph` backend, so no system font library or font file is needed.
//!
//! Rows whose status is not `ok` are left out. Points that differ only in `rep` are averaged;
//! if another parameter varies among the rows of one (x, by) pair the chart would mix
//! different experiments, so that is an error naming the parameter (choose it with `--by`,
//! or fix it with `--where PARAM=VALUE`).

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::Once;

use clap::Args;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use plotters::style::FontStyle;

use super::sweep::metrics::{self, Metric};

pub(crate) mod axis;
mod over_time;
use super::sweep::spec::{default_plot_name, PlotKind, PlotSpec};
use axis::{Axis, Unit};

/// Arguments of `trax plot`.
#[derive(Args, Debug)]
pub struct PlotArgs {
    /// A sweep's results directory or its `results.csv`; with `--over-time`, a statistics
    /// document (`trax run --stats-json FILE --stats-interval N`).
    pub results: PathBuf,
    /// Parameter on the x axis.
    #[arg(long, required_unless_present = "over_time")]
    pub x: Option<String>,
    /// Draw METRIC (`--y`, a field of `timing.intervals[]`, e.g. issue_rate, dram_gbps,
    /// thread_cycles.data_dependence) against simulated time, from a statistics document.
    #[arg(long, conflicts_with_all = ["x", "by", "kind", "filter"])]
    pub over_time: bool,
    /// Metric on the y axis (a column of results.csv, e.g. fps, cycles, energy_j).
    #[arg(long, required_unless_present = "kind")]
    pub y: Option<String>,
    /// Parameter whose values get a line (or bar) each.
    #[arg(long)]
    pub by: Option<String>,
    /// Chart kind (`energy`: energy per frame stacked by component).
    #[arg(long, value_enum)]
    pub kind: Option<PlotKind>,
    /// Only rows where PARAM has this value (repeatable).
    #[arg(long = "where", value_name = "PARAM=VALUE")]
    pub filter: Vec<String>,
    /// Title (default: METRIC vs PARAM).
    #[arg(long)]
    pub title: Option<String>,
    /// X axis label (default: the parameter's name and unit).
    #[arg(long)]
    pub xlabel: Option<String>,
    /// Y axis label (default: the metric's name and unit).
    #[arg(long)]
    pub ylabel: Option<String>,
    /// Log x axis (default: log2 for power-of-two byte sizes spanning 4x or more, log10
    /// for positive values spanning 100x or more, else linear).
    #[arg(long, conflicts_with = "lin_x")]
    pub log_x: bool,
    /// Linear x axis.
    #[arg(long)]
    pub lin_x: bool,
    /// Log y axis (default: log10 for positive values spanning 100x or more; line charts).
    #[arg(long, conflicts_with = "lin_y")]
    pub log_y: bool,
    /// Linear y axis.
    #[arg(long)]
    pub lin_y: bool,
    /// Energy chart: the components to stack, bottom to top (comma-separated names such
    /// as `dram,l2,l1`, or columns such as `energy_dram_j`; default: every energy
    /// component the table has, in table order).
    #[arg(long, value_delimiter = ',', value_name = "NAMES")]
    pub components: Vec<String>,
    /// Output path without extension (`.png` and `.svg` are written); default:
    /// `plots/Y_vs_X[_by_BY]` in the results directory.
    #[arg(short = 'o', long)]
    pub out: Option<PathBuf>,
}

/// Runs `trax plot`.
pub fn run(a: PlotArgs) -> ExitCode {
    match plot_cmd(&a) {
        Ok((png, svg)) => {
            eprintln!("wrote {} and {}", png.display(), svg.display());
            ExitCode::SUCCESS
        }
        Err(e) => super::run::fail(e),
    }
}

fn plot_cmd(a: &PlotArgs) -> Result<(PathBuf, PathBuf), String> {
    if a.over_time {
        return over_time::plot_cmd(a);
    }
    let x =
        a.x.clone()
            .ok_or("--x PARAM is needed (unless --over-time)")?;
    let (csv, dir) = if a.results.is_dir() {
        (a.results.join("results.csv"), a.results.clone())
    } else {
        let dir = a
            .results
            .parent()
            .filter(|p| !p.as_os_str().is_empty())
            .map_or_else(|| PathBuf::from("."), Path::to_path_buf);
        (a.results.clone(), dir)
    };
    let kind = a.kind.unwrap_or(PlotKind::Line);
    let y = match (&a.y, kind) {
        (Some(y), _) => y.clone(),
        (None, PlotKind::Energy) => "energy_j".into(),
        (None, _) => return Err("--y METRIC is needed (unless --kind energy)".into()),
    };
    let mut filter = Vec::new();
    for f in &a.filter {
        let (k, v) = f
            .split_once('=')
            .ok_or_else(|| format!("--where {f:?}: expected PARAM=VALUE"))?;
        filter.push((k.trim().to_string(), v.trim().to_string()));
    }
    let name = default_plot_name(&x, &y, a.by.as_deref());
    let spec = PlotSpec {
        name: name.clone(),
        x,
        y,
        by: a.by.clone(),
        kind,
        title: a.title.clone(),
        filter,
        xlabel: a.xlabel.clone(),
        ylabel: a.ylabel.clone(),
        log_x: flag(a.log_x, a.lin_x),
        log_y: flag(a.log_y, a.lin_y),
        components: a.components.clone(),
        loc: None,
    };
    let out = match &a.out {
        Some(o) => {
            let s = o.display().to_string();
            let s = s
                .strip_suffix(".png")
                .or_else(|| s.strip_suffix(".svg"))
                .unwrap_or(&s);
            PathBuf::from(s)
        }
        None => dir.join("plots").join(&name),
    };
    let table = Table::load(&csv)?;
    draw(&table, &spec, &out)
}

/// `--log-*` / `--lin-*` as a choice (`None`: automatic).
fn flag(log: bool, lin: bool) -> Option<bool> {
    (log || lin).then_some(log)
}

/// A results table: header and rows of text cells.
pub struct Table {
    /// Column names.
    pub header: Vec<String>,
    /// Rows.
    pub rows: Vec<Vec<String>>,
}

/// Columns of results.csv that are neither parameters nor metrics.
pub const FIXED_COLUMNS: &[&str] = &["id", "status", "wall_seconds", "error"];

impl Table {
    /// Reads a CSV file with a header.
    pub fn load(path: &Path) -> Result<Table, String> {
        let mut r = csv::Reader::from_path(path).map_err(|e| format!("{}: {e}", path.display()))?;
        let header = r
            .headers()
            .map_err(|e| format!("{}: {e}", path.display()))?
            .iter()
            .map(str::to_string)
            .collect();
        let mut rows = Vec::new();
        for rec in r.records() {
            let rec = rec.map_err(|e| format!("{}: {e}", path.display()))?;
            rows.push(rec.iter().map(str::to_string).collect());
        }
        Ok(Table { header, rows })
    }

    fn col(&self, name: &str) -> Option<usize> {
        self.header.iter().position(|h| h == name)
    }

    /// Parameter columns (everything but the fixed columns and metrics).
    fn params(&self) -> Vec<&str> {
        self.header
            .iter()
            .map(String::as_str)
            .filter(|h| {
                !FIXED_COLUMNS.contains(h)
                    && metrics::metric(h).is_none()
                    && metrics::ci_of(h).is_none()
            })
            .collect()
    }
}

/// Axis label of a parameter.
pub fn param_label(name: &str) -> String {
    let known = [
        ("tms", "Thread multiprocessors (TMs)"),
        ("threads", "Threads per TM"),
        ("threads_per_tm", "Threads per TM"),
        ("l2s", "L2 caches"),
        ("tms_per_l2", "TMs per L2"),
        ("width", "Image width (pixels)"),
        ("height", "Image height (pixels)"),
        ("spp", "Samples per pixel"),
        ("depth", "Maximum path depth"),
        ("clock_ghz", "Core clock (GHz)"),
        ("opt_level", "Optimisation level"),
    ];
    if let Some((_, l)) = known.iter().find(|(k, _)| *k == name) {
        return l.to_string();
    }
    let (base, unit) = split_unit(name);
    let words = param_name(base);
    let mut c = words.chars();
    let words: String = match c.next() {
        Some(f) => f.to_uppercase().chain(c).collect(),
        None => words,
    };
    match unit {
        Some(u) => format!("{words} ({u})"),
        None => words,
    }
}

/// A parameter's unit from its name's suffix (`_ghz`: GHz, `latency`: cycles), and the name
/// without it. Byte sizes have none: their ticks carry it (`512 KiB`).
fn split_unit(name: &str) -> (&str, Option<&'static str>) {
    const UNITS: [(&str, Option<&str>); 8] = [
        ("_bytes", None),
        ("_kb", Some("KB")),
        ("_ghz", Some("GHz")),
        ("_mhz", Some("MHz")),
        ("_cycles", Some("cycles")),
        ("latency", Some("cycles")),
        ("_mm2", Some("mm²")),
        ("_nj", Some("nJ")),
    ];
    for (suffix, unit) in UNITS {
        if let Some(base) = name.strip_suffix(suffix).filter(|b| !b.is_empty()) {
            // `latency` is a word of the name as well as its unit's hint.
            let base = if suffix == "latency" { name } else { base };
            return (base, unit);
        }
    }
    (name, None)
}

/// A parameter's name as a reader says it (in titles and legends): a config path read as
/// words (`memory.l2.capacity` → `L2 capacity`, `stream_memory.buffers` → `stream memory buffers`), a label without its `label.`
/// prefix, `tms` as `TMs`; other run knobs as they are.
fn param_name(name: &str) -> String {
    let name = name.strip_prefix("label.").unwrap_or(name);
    if name == "tms" {
        return "TMs".into();
    }
    let segments: Vec<&str> = name.split('.').collect();
    let words: Vec<String> = segments
        .iter()
        .enumerate()
        // `memory.` only groups the caches and DRAM: `memory.l1.banks` reads `L1 banks`.
        .filter(|(i, s)| !(*s == &"memory" && i + 1 < segments.len()))
        .flat_map(|(_, s)| s.split('_'))
        .filter(|w| !w.is_empty())
        .map(|w| match w {
            "l1" | "l2" | "dram" | "tm" | "bvh" | "mshrs" | "ii" => w.to_uppercase(),
            "tms" => "TMs".into(),
            _ => w.to_string(),
        })
        .collect();
    words.join(" ")
}

/// Okabe–Ito colours (distinguishable with colour-vision deficiencies), then greys.
const COLOURS: &[RGBColor] = &[
    RGBColor(0, 114, 178),
    RGBColor(213, 94, 0),
    RGBColor(0, 158, 115),
    RGBColor(204, 121, 167),
    RGBColor(230, 159, 0),
    RGBColor(86, 180, 233),
    RGBColor(240, 228, 66),
    RGBColor(0, 0, 0),
    RGBColor(120, 120, 120),
];

pub(crate) fn colour(i: usize) -> RGBColor {
    COLOURS[i % COLOURS.len()]
}

/// Chart size in pixels.
pub(crate) const SIZE: (u32, u32) = (960, 600);

pub(crate) fn register_font() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        // The embedded font parses (checked by the plot tests); an error would only mean
        // text is missing, which drawing then reports.
        let _ = plotters::style::register_font(
            "sans-serif",
            FontStyle::Normal,
            dejavu::sans::regular(),
        );
    });
}

/// A PNG chart of [`SIZE`] at `path`: `draw` gets the white drawing area (the font
/// registered) and words its own errors. Every chart trax draws as a bitmap goes through
/// it (`trax plot`, `--over-time`, `trax ladder`, `trax converge`).
pub(crate) fn png_chart(
    path: &Path,
    draw: impl FnOnce(&DrawingArea<BitMapBackend, Shift>) -> Result<(), String>,
) -> Result<(), String> {
    register_font();
    let mut rgb = vec![0u8; (SIZE.0 * SIZE.1 * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut rgb, SIZE).into_drawing_area();
        root.fill(&WHITE).map_err(|x| x.to_string())?;
        draw(&root)?;
        root.present().map_err(|x| x.to_string())?;
    }
    super::native::write_png(path, SIZE.0, SIZE.1, &rgb).map_err(|x| x.to_string())
}

/// A chart on `area` with `title` over axes `xa` and `ya` (described `xdesc`, `ydesc`),
/// the mesh drawn: grid lines at the axes' ticks, tick labels from [`Axis::label`].
pub(crate) fn axes_chart<'a, 'b>(
    area: &'a DrawingArea<BitMapBackend<'b>, Shift>,
    title: &str,
    (xa, xdesc): (&Axis, &str),
    (ya, ydesc): (&Axis, &str),
) -> Result<ChartContext<'a, BitMapBackend<'b>, Cartesian2d<axis::Ticked, axis::Ticked>>, String> {
    let mut chart = ChartBuilder::on(area)
        .caption(title, ("sans-serif", 22))
        .margin(20)
        .x_label_area_size(50)
        .y_label_area_size(80)
        .build_cartesian_2d(xa.coord(), ya.coord())
        .map_err(|x| x.to_string())?;
    chart
        .configure_mesh()
        .x_desc(xdesc)
        .y_desc(ydesc)
        .label_style(("sans-serif", 15))
        .x_label_formatter(&|t| xa.label(*t))
        .y_label_formatter(&|t| ya.label(*t))
        .light_line_style(WHITE)
        .draw()
        .map_err(|x| x.to_string())?;
    Ok(chart)
}

/// Values in display order: numerically when all are numbers, else as first seen.
fn ordered(values: impl Iterator<Item = String>) -> Vec<String> {
    let mut seen: Vec<String> = Vec::new();
    for v in values {
        if !seen.contains(&v) {
            seen.push(v);
        }
    }
    if seen.iter().all(|v| v.parse::<f64>().is_ok()) {
        seen.sort_by(|a, b| {
            let (a, b) = (
                a.parse::<f64>().unwrap_or(0.0),
                b.parse::<f64>().unwrap_or(0.0),
            );
            a.total_cmp(&b)
        });
    }
    seen
}

/// Display labels for parameter values: in each value, every `:`-separated part that is a
/// path (holds a `/`) shortened to its file name, so `box:../../scenes/dragon/dragon.obj`
/// reads `box:dragon.obj` under a bar or in a legend. The values as given when two would
/// read the same.
pub(crate) fn short_labels(values: &[String]) -> Vec<String> {
    let short: Vec<String> = values
        .iter()
        .map(|v| {
            v.split(':')
                .map(|part| match part.trim_end_matches('/').rsplit_once('/') {
                    Some((_, name)) => name,
                    None => part,
                })
                .collect::<Vec<_>>()
                .join(":")
        })
        .collect();
    let mut sorted = short.clone();
    sorted.sort();
    sorted.dedup();
    if sorted.len() == short.len() {
        short
    } else {
        values.to_vec()
    }
}

/// The data of a chart: categories (x values), series (by values), and for each metric
/// column a value per (series, category).
struct Data {
    xs: Vec<String>,
    numeric_x: bool,
    series: Vec<String>,
    /// `values[m][s][x]` for metric column `m`.
    values: Vec<Vec<Vec<Option<f64>>>>,
    /// Half-widths of the values' 95% intervals (sampled points' `METRIC_ci95`), as
    /// `values`: `None` where there is none.
    ci95: Vec<Vec<Vec<Option<f64>>>>,
}

fn gather(t: &Table, spec: &PlotSpec, ycols: &[&str]) -> Result<Data, String> {
    let params = t.params();
    let need_param = |name: &str| -> Result<usize, String> {
        match t.col(name) {
            Some(c) if params.contains(&name) => Ok(c),
            _ => Err(format!(
                "no parameter `{name}` in the table (parameters: {})",
                params.join(", ")
            )),
        }
    };
    let xc = need_param(&spec.x)?;
    let bc = match &spec.by {
        Some(b) => Some(need_param(b)?),
        None => None,
    };
    let mut ycs = Vec::new();
    for y in ycols {
        match t.col(y) {
            Some(c) if metrics::metric(y).is_some() => ycs.push(c),
            _ => {
                let have: Vec<&str> = metrics::all()
                    .iter()
                    .map(|m| m.column)
                    .filter(|m| t.col(m).is_some())
                    .collect();
                return Err(format!(
                    "no metric `{y}` in the table (metrics: {})",
                    have.join(", ")
                ));
            }
        }
    }
    let mut filters = Vec::new();
    for (k, v) in &spec.filter {
        filters.push((need_param(k)?, v.as_str()));
    }
    let status = t.col("status");
    let rows: Vec<&Vec<String>> = t
        .rows
        .iter()
        .filter(|r| status.is_none_or(|s| r.get(s).map(String::as_str) == Some("ok")))
        .filter(|r| {
            filters
                .iter()
                .all(|(c, v)| r.get(*c).map(String::as_str) == Some(*v))
        })
        .collect();
    if rows.is_empty() {
        return Err("no finished points (status ok) match".into());
    }
    // Another parameter varying within one (x, by) pair would mix experiments in one mark.
    let group = |r: &Vec<String>| (r[xc].clone(), bc.map(|b| r[b].clone()));
    for p in &params {
        if *p == spec.x || Some(*p) == spec.by.as_deref() || *p == "rep" {
            continue;
        }
        let c = t.col(p).unwrap_or(0);
        let mut seen: std::collections::HashMap<_, &str> = std::collections::HashMap::new();
        for r in &rows {
            let v = r[c].as_str();
            if let Some(prev) = seen.insert(group(r), v).filter(|prev| *prev != v) {
                return Err(format!(
                    "parameter `{p}` also varies ({prev}, {v}) for the same {}: choose it with --by {p}, or one value with --where {p}=VALUE",
                    spec.x
                ));
            }
        }
    }
    let xs = ordered(rows.iter().map(|r| r[xc].clone()));
    let numeric_x = xs.iter().all(|v| v.parse::<f64>().is_ok());
    let series = match bc {
        Some(b) => ordered(rows.iter().map(|r| r[b].clone())),
        None => vec![String::new()],
    };
    let mut values = Vec::new();
    let mut ci95 = Vec::new();
    for (&yc, y) in ycs.iter().zip(ycols) {
        let cc = t.col(&format!("{y}{}", metrics::CI_SUFFIX));
        let mut per_series = Vec::new();
        let mut ci_series = Vec::new();
        for s in &series {
            let mut per_x = Vec::new();
            let mut ci_x = Vec::new();
            for x in &xs {
                let group: Vec<&&Vec<String>> = rows
                    .iter()
                    .filter(|r| &r[xc] == x && bc.is_none_or(|b| &r[b] == s))
                    .filter(|r| r[yc].parse::<f64>().is_ok())
                    .collect();
                let vals: Vec<f64> = group.iter().filter_map(|r| r[yc].parse().ok()).collect();
                let n = vals.len() as f64;
                per_x.push((!vals.is_empty()).then(|| vals.iter().sum::<f64>() / n));
                // The mean of independent estimates: its half-width is the root of the
                // sum of squares over n (only when every value has one).
                let halves: Vec<f64> = group
                    .iter()
                    .filter_map(|r| cc.and_then(|c| r[c].parse::<f64>().ok()))
                    .collect();
                ci_x.push(
                    (!halves.is_empty() && halves.len() == vals.len())
                        .then(|| halves.iter().map(|h| h * h).sum::<f64>().sqrt() / n),
                );
            }
            per_series.push(per_x);
            ci_series.push(ci_x);
        }
        values.push(per_series);
        ci95.push(ci_series);
    }
    Ok(Data {
        xs,
        numeric_x,
        series,
        values,
        ci95,
    })
}

/// Draws a chart to `OUT.png` and `OUT.svg`.
pub fn draw(t: &Table, spec: &PlotSpec, out: &Path) -> Result<(PathBuf, PathBuf), String> {
    register_font();
    let parts = match spec.kind {
        PlotKind::Energy => energy_parts(t, &spec.components)?,
        _ if !spec.components.is_empty() => {
            return Err("--components is for energy charts (--kind energy)".into())
        }
        _ => Vec::new(),
    };
    let ycols: Vec<&str> = match spec.kind {
        PlotKind::Energy => parts.iter().map(|m| m.column).collect(),
        _ => vec![spec.y.as_str()],
    };
    let mut data = gather(t, spec, &ycols)?;
    data.xs = short_labels(&data.xs);
    data.series = short_labels(&data.series);
    let mut xlabel = param_label(&spec.x);
    if let (PlotKind::Energy, Some(b)) = (spec.kind, &spec.by) {
        // One stacked bar per (x, by) pair, labelled with both.
        let mut xs = Vec::new();
        let mut values = vec![vec![Vec::new()]; data.values.len()];
        let mut ci95 = vec![vec![Vec::new()]; data.values.len()];
        for (x, xv) in data.xs.iter().enumerate() {
            for (s, sv) in data.series.iter().enumerate() {
                xs.push(format!("{xv} / {sv}"));
                for (m, per_series) in data.values.iter().enumerate() {
                    values[m][0].push(per_series[s][x]);
                    ci95[m][0].push(data.ci95[m][s][x]);
                }
            }
        }
        data = Data {
            xs,
            numeric_x: false,
            series: vec![String::new()],
            values,
            ci95,
        };
        xlabel = format!("{xlabel} / {b}");
    }
    let ymetric = metrics::metric(if spec.kind == PlotKind::Energy {
        "energy_j"
    } else {
        &spec.y
    })
    .ok_or_else(|| format!("no metric `{}`", spec.y))?;
    let ylabel = spec
        .ylabel
        .clone()
        .unwrap_or_else(|| metrics::axis_label(ymetric));
    if let Some(x) = &spec.xlabel {
        xlabel = x.clone();
    }
    if spec.log_y == Some(true) && spec.kind != PlotKind::Line {
        return Err("--log-y needs a line chart (bars start at 0)".into());
    }
    let title = spec.title.clone().unwrap_or_else(|| {
        let mut t = format!("{} vs {}", ymetric.label, param_name(split_unit(&spec.x).0));
        if let Some(b) = &spec.by {
            t.push_str(&format!(" by {}", param_name(split_unit(b).0)));
        }
        t
    });
    let labels = Labels {
        title,
        x: xlabel,
        y: ylabel,
        x_unit: if spec.x.ends_with("_bytes") {
            Unit::Bytes
        } else {
            Unit::Number
        },
        y_unit: if ymetric.unit == "bytes" {
            Unit::Bytes
        } else {
            Unit::Number
        },
        log_x: spec.log_x,
        log_y: spec.log_y,
        by: spec.by.clone().filter(|_| spec.kind != PlotKind::Energy),
        parts: parts.iter().map(|m| m.label).collect(),
    };
    if let Some(dir) = out.parent().filter(|p| !p.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    }
    // Appended, not `with_extension`: names may contain dots (`memory.l2.capacity_bytes`).
    let with_ext = |ext: &str| {
        let mut s = out.as_os_str().to_owned();
        s.push(ext);
        PathBuf::from(s)
    };
    let png = with_ext(".png");
    let svg = with_ext(".svg");
    png_chart(&png, |root| render(root, spec.kind, &data, &labels))?;
    let mut text = String::new();
    {
        let root = SVGBackend::with_string(&mut text, SIZE).into_drawing_area();
        render(&root, spec.kind, &data, &labels)?;
        root.present().map_err(|e| e.to_string())?;
    }
    std::fs::write(&svg, text).map_err(|e| format!("{}: {e}", svg.display()))?;
    Ok((png, svg))
}

/// The energy components a stacked chart draws: those named in `chosen` (a name such as
/// `dram`, its label or its column), in that order, or every one `t` has.
fn energy_parts(t: &Table, chosen: &[String]) -> Result<Vec<&'static Metric>, String> {
    let have: Vec<&'static Metric> = metrics::all()
        .iter()
        .filter(|m| m.energy_part && t.col(m.column).is_some())
        .collect();
    let short = |m: &Metric| {
        m.column
            .trim_start_matches("energy_")
            .trim_end_matches("_j")
            .to_string()
    };
    if chosen.is_empty() {
        return match have.is_empty() {
            true => Err("no energy components in the table (a functional sweep?)".into()),
            false => Ok(have),
        };
    }
    let mut parts = Vec::new();
    for name in chosen {
        let name = name.trim();
        let m = have
            .iter()
            .find(|m| m.column == name || short(m) == name || m.label.eq_ignore_ascii_case(name))
            .ok_or_else(|| {
                let names: Vec<String> = have.iter().map(|m| short(m)).collect();
                format!(
                    "--components: no energy component `{name}` in the table (components: {})",
                    names.join(", ")
                )
            })?;
        if !parts.iter().any(|p: &&Metric| p.column == m.column) {
            parts.push(*m);
        }
    }
    Ok(parts)
}

struct Labels {
    title: String,
    x: String,
    y: String,
    x_unit: Unit,
    y_unit: Unit,
    log_x: Option<bool>,
    log_y: Option<bool>,
    by: Option<String>,
    parts: Vec<&'static str>,
}

/// The values the y axis must show: every value and its interval's ends (those above 0, so
/// a log axis stays possible), or every stack's total.
fn y_values(data: &Data, stacked: bool) -> Vec<f64> {
    if stacked {
        let mut v = Vec::new();
        for s in 0..data.series.len() {
            for x in 0..data.xs.len() {
                v.push(data.values.iter().filter_map(|m| m[s][x]).sum());
            }
        }
        v
    } else {
        let mut v: Vec<f64> = Vec::new();
        for (vm, cm) in data.values.iter().zip(&data.ci95) {
            for (vs, cs) in vm.iter().zip(cm) {
                for (val, ci) in vs.iter().zip(cs) {
                    let Some(val) = *val else { continue };
                    v.push(val);
                    if let Some(h) = *ci {
                        v.push(val + h);
                        if val - h > 0.0 {
                            v.push(val - h);
                        }
                    }
                }
            }
        }
        v
    }
}

/// A legend entry's mark.
#[derive(Clone, Copy, PartialEq)]
pub(crate) enum Mark {
    Line,
    Box,
    /// An error bar with caps.
    Interval,
}

/// A legend entry: text, colour, mark.
pub(crate) type Entry = (String, RGBColor, Mark);

fn render<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    kind: PlotKind,
    data: &Data,
    l: &Labels,
) -> Result<(), String> {
    let e = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    root.fill(&WHITE).map_err(e)?;
    let categorical = kind != PlotKind::Line || !data.numeric_x;
    let n = data.xs.len();
    let xaxis = if categorical {
        None
    } else {
        let xv: Vec<f64> = data.xs.iter().filter_map(|x| x.parse().ok()).collect();
        Some(Axis::fit(&xv, l.x_unit, l.log_x, false, 0.05)?)
    };
    let xcoord = xaxis.clone().unwrap_or_else(|| Axis::categories(n));
    // Lines may take a log y axis; bars and stacks start at 0.
    let ylog = if kind == PlotKind::Line {
        l.log_y
    } else {
        Some(false)
    };
    let yaxis = Axis::fit(
        &y_values(data, kind == PlotKind::Energy),
        l.y_unit,
        ylog,
        true,
        0.08,
    )?;
    let mut entries: Vec<Entry> = Vec::new();
    match (kind, &l.by) {
        (PlotKind::Energy, _) => {
            for (m, part) in l.parts.iter().enumerate() {
                entries.push((part.to_string(), colour(m), Mark::Box));
            }
            entries.reverse(); // top of the stack first, as drawn
        }
        (_, Some(b)) => {
            for (s, name) in data.series.iter().enumerate() {
                let b = param_name(split_unit(b).0);
                let mark = if kind == PlotKind::Line {
                    Mark::Line
                } else {
                    Mark::Box
                };
                entries.push((format!("{b} = {name}"), colour(s), mark));
            }
        }
        (_, None) => {}
    }
    let intervals = kind != PlotKind::Energy && data.ci95[0].iter().flatten().any(Option::is_some);
    if intervals {
        entries.push(("95% interval (sampled)".into(), BLACK, Mark::Interval));
    }
    // The legend goes right of the plot, where it hides no data.
    let legend_width = match entries.iter().map(|(t, _, _)| t.chars().count()).max() {
        Some(chars) => (chars as u32 * 9 + 60).clamp(120, 420),
        None => 0,
    };
    let (plot_area, legend_area) = root.split_horizontally(SIZE.0 - legend_width);
    let title_size = 26.0f64.min(1.9 * SIZE.0 as f64 / l.title.chars().count().max(1) as f64);
    let (title_area, plot_area) = plot_area.split_vertically(50);
    title_area
        .draw(&Text::new(
            l.title.clone(),
            (85, 14),
            ("sans-serif", title_size).into_font(),
        ))
        .map_err(e)?;
    // Category labels too wide for their slot are drawn upright (rotated), the label area
    // as tall as the longest (about 8.5 px a character at 15 px).
    let longest = if categorical {
        data.xs.iter().map(|x| x.chars().count()).max().unwrap_or(0) as f64 * 8.5
    } else {
        0.0
    };
    let slot_px = (SIZE.0 - legend_width) as f64 - 121.0;
    let upright = categorical && longest > 0.9 * slot_px / n.max(1) as f64;
    let x_area = if upright {
        (longest as u32 + 40).min(220)
    } else {
        55
    };
    let mut chart = ChartBuilder::on(&plot_area)
        .margin(18)
        .margin_top(4)
        .x_label_area_size(x_area)
        .y_label_area_size(85)
        .build_cartesian_2d(xcoord.coord(), yaxis.coord())
        .map_err(e)?;
    let xs = data.xs.clone();
    let cat_fmt = move |v: &f64| {
        let i = v.round();
        if (v - i).abs() < 1e-6 && i >= 0.0 && (i as usize) < xs.len() {
            xs[i as usize].clone()
        } else {
            String::new()
        }
    };
    let y_fmt = |t: &f64| yaxis.label(*t);
    let x_fmt = |t: &f64| xaxis.as_ref().map_or_else(String::new, |a| a.label(*t));
    let mut mesh = chart.configure_mesh();
    mesh.x_desc(&l.x)
        .y_desc(&l.y)
        .axis_desc_style(("sans-serif", 18))
        .label_style(("sans-serif", 15))
        .light_line_style(TRANSPARENT)
        .y_label_formatter(&y_fmt);
    if categorical {
        mesh.x_label_formatter(&cat_fmt).disable_x_mesh();
        if upright {
            // Drawn below, each reading down from its tick.
            mesh.x_label_formatter(&|_: &f64| String::new());
        }
    } else {
        mesh.x_label_formatter(&x_fmt);
    }
    mesh.draw().map_err(e)?;
    if upright {
        let style = TextStyle::from(("sans-serif", 15).into_font())
            .transform(FontTransform::Rotate90)
            .pos(Pos::new(HPos::Left, VPos::Center));
        for (i, x) in data.xs.iter().enumerate() {
            let (px, py) = chart.backend_coord(&(i as f64, yaxis.range.start));
            root.draw(&Text::new(x.clone(), (px, py + 12), style.clone()))
                .map_err(e)?;
        }
    }
    // Points in axis coordinates.
    let px = |x: f64| xaxis.as_ref().map_or(x, |a| a.to_axis(x));
    let py = |y: f64| yaxis.to_axis(y);
    let groups = data.series.len();
    let slot = 0.8 / groups as f64;
    let width = slot * if groups > 1 { 0.85 } else { 1.0 };
    let bar_x = |s: usize, x: usize| x as f64 - 0.4 + s as f64 * slot;
    match kind {
        PlotKind::Line => {
            for s in 0..groups {
                let c = colour(s);
                let pts: Vec<(f64, f64)> = data.values[0][s]
                    .iter()
                    .enumerate()
                    .filter_map(|(i, v)| {
                        let x = if categorical {
                            i as f64
                        } else {
                            px(data.xs[i].parse().ok()?)
                        };
                        Some((x, py((*v)?)))
                    })
                    .collect();
                chart
                    .draw_series(LineSeries::new(pts.clone(), c.stroke_width(2)))
                    .map_err(e)?;
                chart
                    .draw_series(pts.iter().map(|p| Circle::new(*p, 4, c.filled())))
                    .map_err(e)?;
            }
        }
        PlotKind::Bar => {
            for s in 0..groups {
                let c = colour(s);
                let bars = data.values[0][s].iter().enumerate().filter_map(|(x, v)| {
                    let x0 = bar_x(s, x);
                    Some(Rectangle::new([(x0, 0.0), (x0 + width, (*v)?)], c.filled()))
                });
                chart.draw_series(bars).map_err(e)?;
            }
        }
        PlotKind::Energy => {
            // One stack per (series, category); components bottom to top in table order.
            let mut base = vec![vec![0.0f64; n]; groups];
            for m in 0..l.parts.len() {
                let c = colour(m);
                let mut rects = Vec::new();
                for (s, row) in base.iter_mut().enumerate() {
                    for (x, b) in row.iter_mut().enumerate() {
                        let v = data.values[m][s][x].unwrap_or(0.0);
                        let x0 = bar_x(s, x);
                        rects.push(Rectangle::new([(x0, *b), (x0 + width, *b + v)], c.filled()));
                        *b += v;
                    }
                }
                chart.draw_series(rects).map_err(e)?;
            }
        }
    }
    // 95% intervals of sampled points: a bar with caps over each mark.
    if intervals {
        let floor = yaxis.range.start;
        for s in 0..groups {
            let c = if kind == PlotKind::Bar {
                BLACK
            } else {
                colour(s)
            };
            for (i, (v, h)) in data.values[0][s].iter().zip(&data.ci95[0][s]).enumerate() {
                let (Some(v), Some(h)) = (*v, *h) else {
                    continue;
                };
                let (x, cap) = match kind {
                    PlotKind::Bar => (bar_x(s, i) + width / 2.0, width / 8.0),
                    _ if categorical => (i as f64, 0.08),
                    _ => match data.xs[i].parse::<f64>() {
                        Ok(xv) => (px(xv), 0.01 * (xcoord.range.end - xcoord.range.start)),
                        Err(_) => continue,
                    },
                };
                let lo = if v - h > 0.0 || yaxis.scale == axis::Scale::Linear {
                    py(v - h)
                } else {
                    floor
                };
                let hi = py(v + h);
                let style = c.stroke_width(2);
                chart
                    .draw_series([
                        PathElement::new(vec![(x, lo), (x, hi)], style),
                        PathElement::new(vec![(x - cap, lo), (x + cap, lo)], style),
                        PathElement::new(vec![(x - cap, hi), (x + cap, hi)], style),
                    ])
                    .map_err(e)?;
            }
        }
    }
    draw_legend(&legend_area, &entries)
}

/// Legend entries down `area` (a strip beside the plot, where they hide no data): a line, a
/// box or an error bar of each entry's colour, then its text.
pub(crate) fn draw_legend<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    entries: &[Entry],
) -> Result<(), String> {
    let e = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    let font =
        TextStyle::from(("sans-serif", 15).into_font()).pos(Pos::new(HPos::Left, VPos::Center));
    for (i, (text, c, mark)) in entries.iter().enumerate() {
        let y = 70 + 26 * i as i32;
        match mark {
            Mark::Line => area
                .draw(&PathElement::new(vec![(6, y), (30, y)], c.stroke_width(3)))
                .map_err(e)?,
            Mark::Box => area
                .draw(&Rectangle::new([(10, y - 7), (24, y + 7)], c.filled()))
                .map_err(e)?,
            Mark::Interval => {
                for seg in [
                    [(17, y - 9), (17, y + 9)],
                    [(12, y - 9), (22, y - 9)],
                    [(12, y + 9), (22, y + 9)],
                ] {
                    area.draw(&PathElement::new(seg.to_vec(), c.stroke_width(2)))
                        .map_err(e)?;
                }
            }
        }
        area.draw(&Text::new(text.clone(), (38, y), font.clone()))
            .map_err(e)?;
    }
    Ok(())
}

/// Draws the plots of a sweep's plan into `DIR/plots/`; returns the files written, and the
/// errors of plots that could not be drawn.
pub fn draw_plan_plots(dir: &Path, plots: &[PlotSpec]) -> (Vec<PathBuf>, Vec<String>) {
    let mut files = Vec::new();
    let mut errors = Vec::new();
    if plots.is_empty() {
        return (files, errors);
    }
    let table = match Table::load(&dir.join("results.csv")) {
        Ok(t) => t,
        Err(e) => return (files, vec![e]),
    };
    for p in plots {
        match draw(&table, p, &dir.join("plots").join(&p.name)) {
            Ok((png, svg)) => files.extend([png, svg]),
            Err(e) => errors.push(format!("plot {}: {e}", p.name)),
        }
    }
    (files, errors)
}

/// Tests: whether a chart PNG is [`SIZE`] and has nothing drawn in its outer 3 pixels (no
/// text outside the canvas or clipped at its edge).
#[cfg(test)]
pub(crate) fn margins_blank(png: &Path) -> Result<(), String> {
    let dec = png::Decoder::new(std::fs::File::open(png).map_err(|e| e.to_string())?);
    let mut reader = dec.read_info().map_err(|e| e.to_string())?;
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buf).map_err(|e| e.to_string())?;
    if (info.width, info.height) != SIZE {
        return Err(format!("size {}x{}", info.width, info.height));
    }
    let (w, h) = (info.width as usize, info.height as usize);
    let white = |x: usize, y: usize| buf[(y * w + x) * 3..][..3] == [255, 255, 255];
    for m in 0..3 {
        if let Some(x) = (0..w).find(|&x| !white(x, m) || !white(x, h - 1 - m)) {
            return Err(format!("ink at ({x}, edge)"));
        }
        if let Some(y) = (0..h).find(|&y| !white(m, y) || !white(w - 1 - m, y)) {
            return Err(format!("ink at (edge, {y})"));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::{energy_parts, short_labels, Table};

    /// `--components` picks energy components by name, label or column, in the order
    /// given; an unknown one is an error naming those the table has; without it, every
    /// component the table has (an older results.csv lacks the newer ones).
    #[test]
    fn energy_components_are_chosen_from_the_table() {
        let t = Table {
            header: owned(&["id", "tms", "energy_l1_j", "energy_l2_j", "energy_dram_j"]),
            rows: Vec::new(),
        };
        let cols = |v: &[&str]| -> Vec<&str> {
            energy_parts(&t, &owned(v))
                .unwrap()
                .iter()
                .map(|m| m.column)
                .collect()
        };
        assert_eq!(cols(&[]), ["energy_l1_j", "energy_l2_j", "energy_dram_j"]);
        assert_eq!(
            cols(&["dram", "L2", "energy_l1_j"]),
            ["energy_dram_j", "energy_l2_j", "energy_l1_j"]
        );
        let err = energy_parts(&t, &owned(&["stream"])).unwrap_err();
        assert!(
            err.contains("`stream`") && err.contains("l1, l2, dram"),
            "{err}"
        );
    }

    fn owned(v: &[&str]) -> Vec<String> {
        v.iter().map(|s| s.to_string()).collect()
    }

    #[test]
    fn paths_read_as_file_names() {
        let v = owned(&[
            "../../shared/scenes/sponza/sponza.obj",
            "box:../../shared/scenes/dragon/dragon-100k.obj",
            "hairball:300000",
            "cornell",
            "../examples/strata.rs",
        ]);
        assert_eq!(
            short_labels(&v),
            owned(&[
                "sponza.obj",
                "box:dragon-100k.obj",
                "hairball:300000",
                "cornell",
                "strata.rs"
            ])
        );
    }

    /// A line chart of power-of-two sizes: drawn at the chart's size, with nothing drawn
    /// in the outer margin (no text outside the canvas or clipped at its edge); bars and
    /// stacked energy (12 bars, 3 components) likewise; a log y axis is refused for bars.
    #[test]
    fn charts_fit_their_canvas() {
        use super::*;
        let header: Vec<String> = [
            "id",
            "status",
            "memory.l2.capacity_bytes",
            "tms",
            "fps",
            "energy_l1_j",
            "energy_l2_j",
            "energy_dram_j",
        ]
        .iter()
        .map(|s| s.to_string())
        .collect();
        let mut rows = Vec::new();
        for (i, kib) in [128u64, 256, 512, 1024, 2048, 4096].iter().enumerate() {
            for tms in ["4", "16"] {
                let fps = 1000.0 * (i as f64 + 1.0) * tms.parse::<f64>().unwrap();
                rows.push(vec![
                    format!("p{i}{tms}"),
                    "ok".into(),
                    (kib * 1024).to_string(),
                    tms.to_string(),
                    fps.to_string(),
                    (0.01 * fps).to_string(),
                    (0.002 * fps).to_string(),
                    (0.05 / (i as f64 + 1.0)).to_string(),
                ]);
            }
        }
        let table = Table { header, rows };
        let dir = std::env::temp_dir().join(format!("trax-plot-fit-{}", std::process::id()));
        for kind in [PlotKind::Line, PlotKind::Bar, PlotKind::Energy] {
            let spec = PlotSpec {
                name: "t".into(),
                x: "memory.l2.capacity_bytes".into(),
                y: if kind == PlotKind::Energy {
                    "energy_j"
                } else {
                    "fps"
                }
                .into(),
                by: Some("tms".into()),
                kind,
                title: None,
                filter: Vec::new(),
                xlabel: None,
                ylabel: None,
                log_x: None,
                log_y: None,
                components: Vec::new(),
                loc: None,
            };
            let (png, svg) = draw(&table, &spec, &dir.join(format!("{kind:?}"))).unwrap();
            if let Err(m) = margins_blank(&png) {
                panic!("{kind:?}: {m}");
            }
            let text = std::fs::read_to_string(svg).unwrap();
            if kind == PlotKind::Line {
                // Sizes read in binary prefixes on a log2 axis, never as 1.31e5.
                for t in ["128 KiB", "512 KiB", "4 MiB"] {
                    assert!(text.contains(t), "{t} missing");
                }
                assert!(
                    !text.contains("e5") && !text.contains("e6"),
                    "scientific ticks"
                );
            }
            let bad = PlotSpec {
                log_y: Some(true),
                ..spec
            };
            if kind == PlotKind::Bar {
                assert!(draw(&table, &bad, &dir.join("bad")).is_err());
            }
        }
        let _ = std::fs::remove_dir_all(&dir);
    }

    /// Config paths read as words, with the unit their suffix names (byte sizes none: their
    /// ticks say KiB/MiB); run knobs keep their names.
    #[test]
    fn parameters_read_as_words() {
        for (name, want) in [
            ("memory.l2.capacity_bytes", "L2 capacity"),
            ("memory.l1.banks", "L1 banks"),
            ("stream_memory.capacity_bytes", "Stream memory capacity"),
            ("memory.dram.preset", "DRAM preset"),
            ("memory.l2.latency", "L2 latency (cycles)"),
            ("label.size_kb", "Size (KB)"),
            ("clock_ghz", "Core clock (GHz)"),
            ("tms", "Thread multiprocessors (TMs)"),
            ("scene", "Scene"),
        ] {
            assert_eq!(super::param_label(name), want, "{name}");
        }
    }

    #[test]
    fn values_that_would_read_the_same_keep_their_paths() {
        let v = owned(&["a/scene.obj", "b/scene.obj"]);
        assert_eq!(short_labels(&v), v);
    }
}
