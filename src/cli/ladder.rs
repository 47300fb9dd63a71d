//! `trax ladder KERNEL [run flags] [--rates 10,30] [-o DIR]`: the fidelity ladder. The same
//! frame runs in each simulation mode — functional, timing with the simple DRAM model,
//! sampled timing (`--sample N` for each rate) and full timing with the detailed DRAM
//! model, the reference — in this process, one after the other; a table gives each mode's
//! host time and its error in cycles, MRPS and energy against the reference (for sampled
//! rungs also the 95% interval and whether it covers the reference), and whether its image
//! is the reference's. `DIR` gets `ladder.csv`, `ladder.json` and `ladder.png` (error
//! against host time), so a user picks a mode knowing what it costs and what it gets wrong.
//!
//! The kernel, scene and chip flags are `trax run`'s ([`ProgramArgs`]); sampled rungs take
//! `trax run`'s `--sample-*` flags ([`SampleArgs`]). Each rung is the run `trax run` makes
//! with the matching flags: `--functional`, `--set memory.dram.model=simple`, `--sample N`,
//! `--set memory.dram.model=detailed` (`tests/ladder.rs` checks them against `trax run`).

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use clap::Args;
use plotters::prelude::*;
use serde::Serialize;
use trax::pipeline::{prepare, Prepared};
use trax_emulator::memsys::DramModel;
use trax_emulator::timing::{ChipConfig, Estimate, SampleRequest};
use trax_emulator::{Mode, RunReport};

use super::common::SampleArgs;
use super::run::{fail, ProgramArgs};

/// Arguments of `trax ladder`.
#[derive(Args, Debug)]
pub struct LadderArgs {
    /// The kernel, scene and chip (as `trax run`).
    #[command(flatten)]
    pub program: ProgramArgs,
    /// Sampling rates of the sampled rungs, as window counts (`trax run --sample N`),
    /// comma-separated.
    #[arg(long, value_delimiter = ',', default_values_t = [10u32, 30])]
    pub rates: Vec<u32>,
    /// How the sampled rungs sample (as `trax run`).
    #[command(flatten)]
    pub sampling: SampleArgs,
    /// Directory for ladder.csv, ladder.json and ladder.png (created if missing).
    #[arg(short = 'o', long, default_value = "ladder")]
    pub out: PathBuf,
}

/// One mode's run.
#[derive(Clone, Debug, Serialize)]
pub struct Rung {
    /// What ran (`functional`, `timing, simple DRAM`, `sampled, N windows`, ...).
    pub name: String,
    /// `functional`, `timing` or `sampled`.
    pub mode: &'static str,
    /// `simple` or `detailed` (`null` for functional).
    pub dram: Option<&'static str>,
    /// Windows of a sampled rung.
    pub windows: Option<u32>,
    /// Host seconds of the simulation (building and laying out excluded).
    pub wall_seconds: f64,
    /// The reference's host seconds / this rung's.
    pub speedup: f64,
    /// Instructions executed (functional and sampled) or issued (timing).
    pub instructions: u64,
    /// Cycles (timing), their estimate (sampled), `null` (functional).
    pub cycles: Option<f64>,
    /// Million rays per second, likewise.
    pub mrps: Option<f64>,
    /// Energy, joules, likewise.
    pub energy_j: Option<f64>,
    /// Relative errors against the reference (0.01 = 1%).
    pub cycles_error: Option<f64>,
    pub mrps_error: Option<f64>,
    pub energy_error: Option<f64>,
    /// Sampled rungs: the 95% intervals.
    pub cycles_ci: Option<[f64; 2]>,
    pub mrps_ci: Option<[f64; 2]>,
    pub energy_ci: Option<[f64; 2]>,
    /// Sampled rungs: whether each interval covers the reference's value.
    pub covers: Option<[bool; 3]>,
    /// Sampled rungs: the fraction of instructions simulated in detail.
    pub detailed_fraction: Option<f64>,
    /// Whether the framebuffer is bit for bit the reference's.
    pub same_image: bool,
}

/// The document `ladder.json`.
#[derive(Debug, Serialize)]
struct LadderDoc<'a> {
    kernel: String,
    scene: &'a str,
    width: u32,
    height: u32,
    spp: u32,
    depth: u32,
    chip: &'a ChipConfig,
    rungs: &'a [Rung],
}

/// Runs `trax ladder`.
pub fn run(a: LadderArgs) -> ExitCode {
    match ladder(&a) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => fail(e),
    }
}

/// One rung before comparison.
struct Ran {
    name: String,
    mode: Mode,
    dram: Option<&'static str>,
    windows: Option<u32>,
    wall: f64,
    report: RunReport,
    framebuffer: Vec<u8>,
}

fn ladder(a: &LadderArgs) -> Result<(), String> {
    let p = &a.program;
    if p.host_threads == Some(0) {
        return Err("--host-threads must be at least 1".into());
    }
    if a.rates.is_empty() {
        return Err("--rates: give one or more window counts".into());
    }
    let chip = p.chip_config()?;
    let with_dram = |model| {
        let mut c = chip.clone();
        c.memory.dram.model = model;
        c
    };
    let (simple, detailed) = (with_dram(DramModel::Simple), with_dram(DramModel::Detailed));
    let samples: Vec<SampleRequest> = a
        .rates
        .iter()
        .map(|&n| a.sampling.request(n, p.pixels(), &detailed))
        .collect::<Result<_, _>>()?;
    std::fs::create_dir_all(&a.out).map_err(|e| format!("{}: {e}", a.out.display()))?;
    let request = p.request(&detailed);
    let prepared = prepare(&request).map_err(|e| {
        eprint!("{}", e.render());
        format!("{}: could not be prepared", p.kernel.display())
    })?;
    for w in &prepared.warnings {
        eprintln!("warning: {w}");
    }
    let mut runs = vec![rung(
        &prepared,
        p,
        &chip,
        Mode::Functional,
        None,
        "functional",
    )?];
    runs.push(rung(
        &prepared,
        p,
        &simple,
        Mode::Timing,
        None,
        "timing, simple DRAM",
    )?);
    for s in samples {
        let name = format!("sampled, {} windows", s.windows);
        runs.push(rung(&prepared, p, &detailed, Mode::Timing, Some(s), &name)?);
    }
    runs.push(rung(
        &prepared,
        p,
        &detailed,
        Mode::Timing,
        None,
        "timing, detailed DRAM",
    )?);
    let rungs = compare(&runs);
    print!("{}", table(&rungs));
    let csv = a.out.join("ladder.csv");
    std::fs::write(&csv, csv_text(&rungs)).map_err(|e| format!("{}: {e}", csv.display()))?;
    let doc = LadderDoc {
        kernel: p.kernel.display().to_string(),
        scene: &p.render.scene,
        width: p.render.width,
        height: p.render.height,
        spp: p.render.spp,
        depth: p.render.depth,
        chip: &detailed,
        rungs: &rungs,
    };
    let json = a.out.join("ladder.json");
    let text = serde_json::to_string_pretty(&doc).map_err(|e| e.to_string())?;
    std::fs::write(&json, text + "\n").map_err(|e| format!("{}: {e}", json.display()))?;
    let png = a.out.join("ladder.png");
    let title = p.kernel.file_name().map_or_else(
        || p.kernel.display().to_string(),
        |f| f.to_string_lossy().into_owned(),
    );
    plot(&png, &rungs, &format!("{title} on {}", p.render.scene))?;
    eprintln!(
        "wrote {}, {} and {}",
        csv.display(),
        json.display(),
        png.display()
    );
    Ok(())
}

/// Runs one rung (the simulation timed alone).
fn rung(
    prepared: &Prepared,
    p: &ProgramArgs,
    chip: &ChipConfig,
    mode: Mode,
    sample: Option<SampleRequest>,
    name: &str,
) -> Result<Ran, String> {
    let windows = sample.as_ref().map(|s| s.windows);
    let mut req = prepared.run_request(chip, mode);
    req.host_threads = p.host_threads;
    req.sample = sample;
    let start = Instant::now();
    let report = trax_emulator::run(req, &mut std::io::sink())
        .map_err(|e| format!("{} ({name}): {e}", prepared.name))?;
    let wall = start.elapsed().as_secs_f64();
    if let Some(f) = &report.failure {
        return Err(format!("{} ({name}) did not finish:\n{f}", prepared.name));
    }
    eprintln!("{name}: {wall:.3} s");
    Ok(Ran {
        name: name.to_string(),
        mode,
        dram: (mode == Mode::Timing).then_some(match chip.memory.dram.model {
            DramModel::Simple => "simple",
            DramModel::Detailed => "detailed",
        }),
        windows,
        wall,
        framebuffer: prepared.framebuffer(&report).unwrap_or_default(),
        report,
    })
}

/// (cycles, MRPS, energy) of a run, with the intervals of a sampled one.
fn values(r: &RunReport) -> Option<([f64; 3], Option<[&Estimate; 3]>)> {
    if let Some(s) = &r.sampled {
        let e = &s.estimates;
        return Some((
            [e.cycles.estimate, e.mrps.estimate, e.energy_j.estimate],
            Some([&e.cycles, &e.mrps, &e.energy_j]),
        ));
    }
    r.timing
        .as_ref()
        .map(|t| ([t.cycles as f64, t.mrps, t.energy.total], None))
}

/// The rungs with their errors against the last one (the reference).
fn compare(runs: &[Ran]) -> Vec<Rung> {
    let reference = runs.last().expect("the reference rung");
    let (refv, _) = values(&reference.report).expect("the reference is a timing run");
    runs.iter()
        .map(|r| {
            let v = values(&r.report);
            let get = |i: usize| v.as_ref().map(|(x, _)| x[i]);
            let err = |i: usize| get(i).map(|x| (x - refv[i]) / refv[i]);
            let ci = |i: usize| {
                v.as_ref()
                    .and_then(|(_, e)| e.map(|e| [e[i].ci95_low, e[i].ci95_high]))
            };
            let covers = v
                .as_ref()
                .and_then(|(_, e)| e.map(|e| std::array::from_fn(|i| e[i].covers(refv[i]))));
            Rung {
                name: r.name.clone(),
                mode: match (r.mode, r.windows) {
                    (Mode::Functional, _) => "functional",
                    (_, Some(_)) => "sampled",
                    _ => "timing",
                },
                dram: r.dram,
                windows: r.windows,
                wall_seconds: r.wall,
                speedup: reference.wall / r.wall.max(1e-9),
                instructions: r.report.instructions,
                cycles: get(0),
                mrps: get(1),
                energy_j: get(2),
                cycles_error: err(0),
                mrps_error: err(1),
                energy_error: err(2),
                cycles_ci: ci(0),
                mrps_ci: ci(1),
                energy_ci: ci(2),
                covers,
                detailed_fraction: r.report.sampled.as_ref().map(|s| {
                    s.detailed_instructions as f64 / s.executed_instructions.max(1) as f64
                }),
                same_image: r.framebuffer == reference.framebuffer,
            }
        })
        .collect()
}

/// A relative error as a signed percentage, with the interval's half-width for sampled
/// rungs and a `*` where the interval misses the reference.
fn err_cell(e: Option<f64>, ci: Option<[f64; 2]>, v: Option<f64>, covers: Option<bool>) -> String {
    match (e, ci, v) {
        (None, ..) => "-".into(),
        (Some(e), Some([lo, hi]), Some(v)) if v != 0.0 => format!(
            "{:+.2}% ±{:.2}%{}",
            100.0 * e,
            50.0 * (hi - lo) / v.abs(),
            if covers == Some(false) { " *" } else { "" }
        ),
        (Some(e), ..) => format!("{:+.2}%", 100.0 * e),
    }
}

/// The readable table.
pub fn table(rungs: &[Rung]) -> String {
    let mut s = format!(
        "{:<24} {:>9} {:>8} {:>14} {:>20} {:>20} {:>20} {:>6}\n",
        "mode",
        "host s",
        "speed-up",
        "cycles",
        "cycles error",
        "MRPS error",
        "energy error",
        "image"
    );
    for r in rungs {
        let cov = |i: usize| r.covers.map(|c| c[i]);
        s += &format!(
            "{:<24} {:>9.3} {:>7.1}x {:>14} {:>20} {:>20} {:>20} {:>6}\n",
            r.name,
            r.wall_seconds,
            r.speedup,
            r.cycles.map_or("-".into(), |c| format!("{c:.0}")),
            err_cell(r.cycles_error, r.cycles_ci, r.cycles, cov(0)),
            err_cell(r.mrps_error, r.mrps_ci, r.mrps, cov(1)),
            err_cell(r.energy_error, r.energy_ci, r.energy_j, cov(2)),
            if r.same_image { "same" } else { "DIFFERS" }
        );
    }
    s += "errors against the last row (the reference); sampled: estimate's error ± its 95% \
          interval's half-width, * where the interval misses the reference\n";
    s
}

fn csv_text(rungs: &[Rung]) -> String {
    let mut s = String::from(
        "mode,kind,dram,windows,wall_seconds,speedup,instructions,cycles,mrps,energy_j,\
         cycles_error,mrps_error,energy_error,cycles_ci_low,cycles_ci_high,mrps_ci_low,\
         mrps_ci_high,energy_ci_low,energy_ci_high,covers_cycles,covers_mrps,covers_energy,\
         detailed_fraction,same_image\n",
    );
    let o = |v: Option<f64>| v.map_or(String::new(), |x| x.to_string());
    for r in rungs {
        let ci = |c: Option<[f64; 2]>, i: usize| o(c.map(|c| c[i]));
        let cov = |i: usize| r.covers.map_or(String::new(), |c| c[i].to_string());
        s += &format!(
            "\"{}\",{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}\n",
            r.name,
            r.mode,
            r.dram.unwrap_or(""),
            r.windows.map_or(String::new(), |w| w.to_string()),
            r.wall_seconds,
            r.speedup,
            r.instructions,
            o(r.cycles),
            o(r.mrps),
            o(r.energy_j),
            o(r.cycles_error),
            o(r.mrps_error),
            o(r.energy_error),
            ci(r.cycles_ci, 0),
            ci(r.cycles_ci, 1),
            ci(r.mrps_ci, 0),
            ci(r.mrps_ci, 1),
            ci(r.energy_ci, 0),
            ci(r.energy_ci, 1),
            cov(0),
            cov(1),
            cov(2),
            o(r.detailed_fraction),
            r.same_image
        );
    }
    s
}

/// Reads one error of a rung, and its 95% interval's bounds.
type ErrorOf = fn(&Rung) -> (Option<f64>, Option<[f64; 2]>);

/// A box in pixels: left, top, right, bottom.
type Rect = (i32, i32, i32, i32);

fn overlaps(a: Rect, b: Rect) -> bool {
    a.0 < b.2 && b.0 < a.2 && a.1 < b.3 && b.1 < a.3
}

/// Places labels of the given sizes (w, h) near their anchors: right of the anchor, else
/// left of it, else nudged up or down a line at a time (up to 20 lines), taking the first
/// place where the label stays inside `area` and overlaps no placed label and no marker
/// (`markers`, boxes).
/// Returns each label's top-left corner. A label that fits nowhere goes right of its anchor,
/// clamped inside `area`.
fn place_labels(
    anchors: &[(i32, i32)],
    sizes: &[(i32, i32)],
    markers: &[Rect],
    area: Rect,
) -> Vec<(i32, i32)> {
    const GAP: i32 = 11;
    let mut placed: Vec<Rect> = Vec::new();
    let mut out = Vec::new();
    for (&(ax, ay), &(w, h)) in anchors.iter().zip(sizes) {
        let mut best = None;
        'search: for step in 0..40 {
            let dy = (step + 1) / 2 * (h + 2) * if step % 2 == 1 { -1 } else { 1 };
            for x in [ax + GAP, ax - GAP - w] {
                let r = (x, ay - h / 2 + dy, x + w, ay - h / 2 + dy + h);
                let inside = r.0 >= area.0 && r.1 >= area.1 && r.2 <= area.2 && r.3 <= area.3;
                if inside
                    && !placed.iter().any(|p| overlaps(*p, r))
                    && !markers.iter().any(|m| overlaps(*m, r))
                {
                    best = Some(r);
                    break 'search;
                }
            }
        }
        let r = best.unwrap_or_else(|| {
            let x = (ax + GAP).min(area.2 - w).max(area.0);
            let y = (ay - h / 2).min(area.3 - h).max(area.1);
            (x, y, x + w, y + h)
        });
        placed.push(r);
        out.push((r.0, r.1));
    }
    out
}

/// The absolute error (%) of a relative error, floored at `floor`.
fn abs_pct(e: f64, floor: f64) -> f64 {
    (100.0 * e.abs()).max(floor)
}

/// Absolute error (%) against host seconds, log-log: one colour and marker per metric, one
/// point per rung, sampled rungs with their 95% intervals as error bars (a bar reaching the
/// floor: the interval includes the reference's value); each rung named beside its point
/// (placed so no name covers another or a marker, nor leaves the plot); the reference (no
/// error) and functional mode (no timing) as vertical lines at their host times. Errors
/// below 0.001% are drawn at 0.001%. The legend is right of the plot.
fn plot(path: &Path, rungs: &[Rung], name: &str) -> Result<(), String> {
    use super::plot::axis::{Axis, Unit};
    const FLOOR: f64 = 1e-3;
    let metrics: [(&str, ErrorOf); 3] = [
        ("cycles", |r| (r.cycles_error, r.cycles_ci)),
        ("MRPS", |r| (r.mrps_error, r.mrps_ci)),
        ("energy", |r| (r.energy_error, r.energy_ci)),
    ];
    let last = rungs.len() - 1;
    let reference = &rungs[last];
    let refv = [reference.cycles, reference.mrps, reference.energy_j];
    // Per metric: (host s, |error| %, the interval's |error| range %) of each rung.
    type Pt = (f64, f64, Option<(f64, f64)>);
    let pts = |k: usize, f: ErrorOf| -> Vec<Pt> {
        rungs[..last]
            .iter()
            .filter_map(|r| {
                let (e, ci) = f(r);
                let bar = match (ci, refv[k]) {
                    (Some([lo, hi]), Some(v)) if v != 0.0 => {
                        let (a, b) = (lo / v - 1.0, hi / v - 1.0);
                        let top = abs_pct(a, FLOOR).max(abs_pct(b, FLOOR));
                        let bottom = if a <= 0.0 && b >= 0.0 {
                            FLOOR
                        } else {
                            abs_pct(a, FLOOR).min(abs_pct(b, FLOOR))
                        };
                        Some((bottom, top))
                    }
                    _ => None,
                };
                e.map(|e| (r.wall_seconds.max(1e-3), abs_pct(e, FLOOR), bar))
            })
            .collect()
    };
    let series: Vec<Vec<Pt>> = metrics
        .iter()
        .enumerate()
        .map(|(k, (_, f))| pts(k, *f))
        .collect();
    let walls: Vec<f64> = rungs.iter().map(|r| r.wall_seconds.max(1e-3)).collect();
    let mut ys: Vec<f64> = vec![FLOOR];
    for p in series.iter().flatten() {
        ys.push(p.1);
        if let Some((_, top)) = p.2 {
            ys.push(top);
        }
    }
    let xa = Axis::fit(&walls, Unit::Number, Some(true), false, 0.12)?;
    let mut ya = Axis::fit(&ys, Unit::Percent, Some(true), false, 0.08)?;
    // Room above the highest point for the names of rungs without an error (functional).
    ya.range.end += 0.12 * (ya.range.end - ya.range.start);
    let top_y = ya.value(ya.range.end - 0.04 * (ya.range.end - ya.range.start));
    let size = super::plot::SIZE;
    let legend_width = 130;
    super::plot::png_chart(path, |root| {
        let e = |x: &dyn std::fmt::Display| format!("{}: {x}", path.display());
        let (main, legend) = root.split_horizontally(size.0 - legend_width);
        let chart = super::plot::axes_chart(
            &main,
            &format!("{name}: error against host time"),
            (&xa, "host seconds"),
            (&ya, "|error| vs full detailed timing, %"),
        )
        .map_err(|x| e(&x))?;
        let at = |x: f64, y: f64| chart.backend_coord(&(xa.to_axis(x), ya.to_axis(y)));
        // Cycles and MRPS errors are often equal (the rays are exact): a ring, a dot and
        // a cross keep every metric visible; their error bars sit side by side.
        let marker = |k: usize, (x, y): (i32, i32)| -> DynElement<BitMapBackend, (i32, i32)> {
            let c = super::plot::colour(k);
            match k {
                0 => Circle::new((x, y), 7, c.stroke_width(2)).into_dyn(),
                1 => Circle::new((x, y), 3, c.filled()).into_dyn(),
                _ => Cross::new((x, y), 5, c.stroke_width(2)).into_dyn(),
            }
        };
        let mut boxes: Vec<Rect> = Vec::new();
        for (k, p) in series.iter().enumerate() {
            let c = super::plot::colour(k);
            for &(x, y, bar) in p {
                let (px, py) = at(x, y);
                if let Some((lo, hi)) = bar {
                    let bx = px + 4 * (k as i32 - 1);
                    let (y0, y1) = (at(x, lo).1, at(x, hi).1);
                    root.draw(&PathElement::new([(bx, y0), (bx, y1)], c.stroke_width(2)))
                        .map_err(|x| e(&x))?;
                    for yy in [y0, y1] {
                        root.draw(&PathElement::new(
                            [(bx - 4, yy), (bx + 4, yy)],
                            c.stroke_width(2),
                        ))
                        .map_err(|x| e(&x))?;
                    }
                    boxes.push((bx - 5, y1.min(y0), bx + 5, y1.max(y0)));
                }
                root.draw(&marker(k, (px, py))).map_err(|x| e(&x))?;
                boxes.push((px - 8, py - 8, px + 8, py + 8));
            }
        }
        // Vertical lines at rungs without an error (functional) and at the reference.
        let (y_lo, y_hi) = (ya.value(ya.range.start), ya.value(ya.range.end));
        for (i, r) in rungs.iter().enumerate() {
            if r.cycles_error.is_none() || i == last {
                let x = r.wall_seconds.max(1e-3);
                let (p0, p1) = (at(x, y_lo), at(x, y_hi));
                root.draw(&PathElement::new([p0, p1], BLACK.mix(0.3).stroke_width(1)))
                    .map_err(|x| e(&x))?;
            }
        }
        // Rung names: beside their cycles point, at the top for rungs without one and at
        // the floor for the reference.
        let font = TextStyle::from(("sans-serif", 13).into_font());
        let mut anchors = Vec::new();
        let mut sizes = Vec::new();
        let mut texts = Vec::new();
        for (i, r) in rungs.iter().enumerate() {
            let y = match (i == last, r.cycles_error) {
                (true, _) => FLOOR,
                (false, Some(err)) => abs_pct(err, FLOOR),
                (false, None) => top_y,
            };
            let text = if i == last {
                format!("{} (reference)", r.name)
            } else {
                r.name.clone()
            };
            let (w, h) = root.estimate_text_size(&text, &font).map_err(|x| e(&x))?;
            anchors.push(at(r.wall_seconds.max(1e-3), y));
            sizes.push((w as i32, h as i32));
            texts.push(text);
        }
        let (lo, hi) = (
            at(xa.value(xa.range.start), y_hi),
            at(xa.value(xa.range.end), y_lo),
        );
        let area = (lo.0 + 2, lo.1 + 2, hi.0 - 2, hi.1 - 2);
        let placed = place_labels(&anchors, &sizes, &boxes, area);
        for (i, (x, y)) in placed.into_iter().enumerate() {
            root.draw(&Text::new(texts[i].clone(), (x, y), font.clone()))
                .map_err(|x| e(&x))?;
            // A name moved off its point's line gets a leader line to the point.
            let ((ax, ay), (w, h)) = (anchors[i], sizes[i]);
            if (y + h / 2 - ay).abs() > h {
                let ex = if x > ax { x - 2 } else { x + w + 2 };
                let ey = if y > ay { y } else { y + h };
                root.draw(&PathElement::new([(ax, ay), (ex, ey)], BLACK.mix(0.5)))
                    .map_err(|x| e(&x))?;
            }
        }
        let lfont = ("sans-serif", 15).into_font();
        for (k, (label, _)) in metrics.iter().enumerate() {
            let y = 90 + 26 * k as i32;
            legend.draw(&marker(k, (16, y))).map_err(|x| e(&x))?;
            legend
                .draw(&Text::new(label.to_string(), (32, y - 8), lfont.clone()))
                .map_err(|x| e(&x))?;
        }
        Ok(())
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rung(name: &str, wall: f64, err: Option<f64>, ci: Option<[f64; 2]>) -> Rung {
        let v = err.map(|e| 1000.0 * (1.0 + e));
        Rung {
            name: name.into(),
            mode: if ci.is_some() { "sampled" } else { "timing" },
            dram: None,
            windows: None,
            wall_seconds: wall,
            speedup: 1.0,
            instructions: 1,
            cycles: v,
            mrps: v,
            energy_j: v,
            cycles_error: err,
            mrps_error: err,
            energy_error: err.map(|e| 3.0 * e),
            cycles_ci: ci,
            mrps_ci: ci,
            energy_ci: ci,
            covers: None,
            detailed_fraction: None,
            same_image: true,
        }
    }

    /// Labels never overlap each other or a marker and stay in the plot, even when the
    /// rungs crowd one spot (the chart once drew names over markers and clipped the
    /// reference's name at the right edge).
    #[test]
    fn labels_are_placed_apart_and_inside() {
        let anchors = [(700, 300), (700, 306), (702, 300), (940, 580)];
        let sizes = [(150, 14), (150, 14), (120, 14), (200, 14)];
        let markers: Vec<Rect> = anchors
            .iter()
            .map(|&(x, y)| (x - 8, y - 8, x + 8, y + 8))
            .collect();
        let area = (100, 50, 950, 590);
        let at = place_labels(&anchors, &sizes, &markers, area);
        let boxes: Vec<Rect> = at
            .iter()
            .zip(sizes)
            .map(|(&(x, y), (w, h))| (x, y, x + w, y + h))
            .collect();
        for (i, b) in boxes.iter().enumerate() {
            assert!(
                b.0 >= area.0 && b.1 >= area.1 && b.2 <= area.2 && b.3 <= area.3,
                "{b:?}"
            );
            assert!(
                !markers.iter().any(|m| overlaps(*m, *b)),
                "{i}: {b:?} over a marker"
            );
            for c in &boxes[..i] {
                assert!(!overlaps(*b, *c), "{b:?} over {c:?}");
            }
        }
        // The reference's name at the right edge goes left of its point.
        assert!(boxes[3].2 <= 940);
    }

    /// The chart of a ladder with every kind of rung fits its canvas.
    #[test]
    fn ladder_chart_fits_its_canvas() {
        let rungs = [
            rung("functional", 0.3, None, None),
            rung("timing, simple DRAM", 9.0, Some(0.0076), None),
            rung(
                "sampled, 10 windows",
                3.3,
                Some(0.0007),
                Some([990.0, 1012.0]),
            ),
            rung(
                "sampled, 30 windows",
                3.8,
                Some(-0.0024),
                Some([988.0, 1006.0]),
            ),
            rung("timing, detailed DRAM", 9.5, Some(0.0), None),
        ];
        let path = std::env::temp_dir().join(format!("trax-ladder-{}.png", std::process::id()));
        plot(&path, &rungs, "pathtracer.rs on cornell").unwrap();
        let fits = crate::cli::plot::margins_blank(&path);
        let _ = std::fs::remove_file(&path);
        fits.unwrap();
    }
}
