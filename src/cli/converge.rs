//! `trax converge KERNEL --spp 1,2,4,8 --reference-spp N`: image error against samples
//! per pixel. A reference is rendered with `trax native` at `N` spp (or read with
//! `--reference FILE`), then the kernel runs on the simulated machine once per level
//! (functional; `--timing` for the cycle-level model and simulated cycles per frame), and
//! each image is measured against the reference ([`trax::compare`]). Prints a table (spp,
//! RMSE, relative MSE, simulated cycles, host seconds; with `--repeats R`, means over R
//! seeds) and the least-squares slope of
//! log RMSE against log spp — about −1/2 for an unbiased Monte Carlo estimator, whose
//! error falls as spp^-1/2 — and writes `convergence.csv`, `convergence.png` (log-log
//! chart) and `reference.bin` to `--out`.
//!
//! The reference uses another seed (`--reference-seed`, default `--seed` + 1): with the
//! same seed its first samples would be the levels' samples (`trax::seed_pixel` hashes
//! seed, pixel and sample), and the error would be underestimated. Its own noise adds
//! `σ²/N` to each level's MSE; keep N well above the largest level.

use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode};
use std::time::Instant;

use clap::Args;
use plotters::prelude::*;

use super::plot::axis::{Axis, Unit};
use trax::compare::{compare, decode_raw, log_log_slope, read_image, Image, Metrics};
use trax::pipeline::{self, chip_config, executable, lay_out, load_scene};
use trax_emulator::Mode;

use super::common::{RenderArgs, ShapeArgs};

/// Arguments of `trax converge`.
#[derive(Args, Debug)]
pub struct ConvergeArgs {
    /// The kernel (TRaX-Rust, C or C++ source; it reads `spp` from the scene header).
    pub kernel: PathBuf,
    /// Samples per pixel of each level, comma-separated.
    #[arg(long, value_delimiter = ',', default_values_t = [1u32, 2, 4, 8, 16])]
    pub spp: Vec<u32>,
    /// Samples per pixel of the reference (rendered with `trax native`).
    #[arg(long, default_value_t = 1024)]
    pub reference_spp: u32,
    /// Renders per level, with seeds `--seed`, `--seed` + 1, ...: the level's MSE and
    /// relative MSE are their mean (the RMSE of a path tracer is heavy-tailed: a few
    /// bright paths dominate one render's error).
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..))]
    pub repeats: u32,
    /// Seed of the reference (default: `--seed` + `--repeats`, independent of the levels).
    #[arg(long)]
    pub reference_seed: Option<u32>,
    /// Use this reference image (PNG or raw framebuffer) instead of rendering one.
    #[arg(long, conflicts_with_all = ["reference_spp", "reference_seed"])]
    pub reference: Option<PathBuf>,
    /// Run the levels on the cycle-level timing model and report simulated cycles per
    /// frame (default: functional).
    #[arg(long)]
    pub timing: bool,
    /// Host threads for the timing simulation (default: the host's cores).
    #[arg(long)]
    pub host_threads: Option<usize>,
    /// Optimisation level of the kernel on the simulated machine.
    #[arg(short = 'O', default_value_t = pipeline::DEFAULT_OPT_LEVEL, value_parser = clap::value_parser!(u8).range(0..=3))]
    pub opt_level: u8,
    /// Scene (as `trax run --scene`).
    #[arg(long, default_value = "cornell")]
    pub scene: String,
    /// Scale the whole scene (as `trax run --scene-scale`).
    #[arg(long, value_name = "S", allow_negative_numbers = true)]
    pub scene_scale: Option<f64>,
    /// Camera file (simtrax .view).
    #[arg(long)]
    pub view: Option<PathBuf>,
    /// Light file (simtrax .light).
    #[arg(long)]
    pub light: Option<PathBuf>,
    /// Image width in pixels.
    #[arg(long, default_value_t = 32)]
    pub width: u32,
    /// Image height in pixels.
    #[arg(long, default_value_t = 32)]
    pub height: u32,
    /// Maximum path depth.
    #[arg(long, default_value_t = 4)]
    pub depth: u32,
    /// Seed of the levels' random streams.
    #[arg(long, default_value_t = 1)]
    pub seed: u32,
    /// Chip and thread shape (of the simulated runs and the native reference).
    #[command(flatten)]
    pub shape: ShapeArgs,
    /// Directory for reference.bin, convergence.csv and convergence.png.
    #[arg(short = 'o', long, default_value = "converge")]
    pub out: PathBuf,
}

/// One level of the table.
#[derive(Clone, Debug)]
pub struct Level {
    /// Samples per pixel.
    pub spp: u32,
    /// Error against the reference.
    pub metrics: Metrics,
    /// Simulated core cycles of the frame (timing mode).
    pub cycles: Option<u64>,
    /// Host seconds of the simulation.
    pub host_seconds: f64,
}

/// Runs `trax converge`.
pub fn run(a: ConvergeArgs) -> ExitCode {
    match converge(&a) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => super::run::fail(e),
    }
}

impl ConvergeArgs {
    fn render(&self, spp: u32, seed: u32) -> RenderArgs {
        RenderArgs {
            scene: self.scene.clone(),
            scene_scale: self.scene_scale,
            view: self.view.clone(),
            light: self.light.clone(),
            width: self.width,
            height: self.height,
            spp,
            depth: self.depth,
            seed,
            scene_cache: None,
        }
    }
}

fn converge(a: &ConvergeArgs) -> Result<(), String> {
    if a.spp.is_empty() || a.spp.contains(&0) {
        return Err("--spp: give one or more levels of at least 1 sample".into());
    }
    if a.reference_spp == 0 || a.width == 0 || a.height == 0 {
        return Err("--reference-spp, --width and --height must be at least 1".into());
    }
    if a.host_threads == Some(0) {
        return Err("--host-threads must be at least 1".into());
    }
    std::fs::create_dir_all(&a.out).map_err(|e| format!("{}: {e}", a.out.display()))?;
    let s = &a.shape;
    let chip = chip_config(&s.config, &s.set, s.tms, s.threads, None)?;
    let size = (a.width, a.height);
    let reference = match &a.reference {
        Some(path) => {
            let mut r = read_image(path, None)?;
            let want = a.width as u64 * a.height as u64;
            match r.size {
                Some(s) if s != size => {
                    return Err(format!(
                        "{}: the reference is {}x{}, not {}x{} (--width, --height)",
                        path.display(),
                        s.0,
                        s.1,
                        a.width,
                        a.height
                    ))
                }
                None if r.pixels.len() as u64 != want => {
                    return Err(format!(
                        "{} has {} pixels, not {}x{} = {want} (--width, --height)",
                        path.display(),
                        r.pixels.len(),
                        a.width,
                        a.height
                    ))
                }
                _ => r.size = Some(size),
            }
            r
        }
        None => render_reference(a)?,
    };
    let elf = executable(&a.kernel, a.opt_level).map_err(|e| {
        eprint!("{}", e.render());
        format!("{}: the kernel does not build", a.kernel.display())
    })?;
    let render = a.render(1, a.seed);
    let scene = load_scene(&a.scene, &render.load_options()).map_err(|e| e.to_string())?;
    let name = a.kernel.display().to_string();
    let mode = if a.timing {
        Mode::Timing
    } else {
        Mode::Functional
    };
    let mut levels = Vec::new();
    println!(
        "{:>6}  {:>12}  {:>12}  {:>14}  {:>10}",
        "spp",
        "RMSE",
        "relMSE",
        if a.timing { "cycles/frame" } else { "" },
        "host s"
    );
    for &spp in &a.spp {
        let mut runs = Vec::new();
        for rep in 0..a.repeats {
            let seed = a.seed.wrapping_add(rep);
            let opts = a.render(spp, seed).render_options();
            let prepared =
                lay_out(&name, elf.clone(), &scene, &opts, &chip).map_err(|e| e.to_string())?;
            let mut req = prepared.run_request(&chip, mode);
            req.host_threads = a.host_threads;
            let start = Instant::now();
            let r = trax_emulator::run(req, &mut std::io::sink())
                .map_err(|e| format!("{name} at {spp} spp, seed {seed}: {e}"))?;
            let host_seconds = start.elapsed().as_secs_f64();
            if let Some(f) = &r.failure {
                return Err(format!(
                    "{name} at {spp} spp, seed {seed} did not finish:\n{f}"
                ));
            }
            let bytes = prepared.framebuffer(&r).unwrap_or_default();
            let mut img = decode_raw(&format!("{name} at {spp} spp, seed {seed}"), &bytes)?;
            img.size = Some(size);
            let metrics = compare(&img, &reference)?;
            runs.push(Level {
                spp,
                metrics,
                cycles: r.cycles,
                host_seconds,
            });
        }
        let level = mean_level(&runs);
        println!("{}", row(&level));
        levels.push(level);
    }
    let points: Vec<(f64, f64)> = levels
        .iter()
        .map(|l| (l.spp as f64, l.metrics.rmse))
        .collect();
    let slope = log_log_slope(&points);
    match slope {
        Some(k) => println!("slope of log RMSE vs log spp: {k:.3} (Monte Carlo: -0.5)"),
        None => println!("slope of log RMSE vs log spp: none (needs two levels with error)"),
    }
    let csv = a.out.join("convergence.csv");
    std::fs::write(&csv, csv_text(&levels)).map_err(|e| format!("{}: {e}", csv.display()))?;
    let png = a.out.join("convergence.png");
    plot(&png, &levels, slope, &name)?;
    eprintln!("wrote {} and {}", csv.display(), png.display());
    Ok(())
}

/// The mean of one level's repeats: MSE, relative MSE, cycles and host seconds averaged
/// (RMSE and PSNR from the mean MSE), the largest error and the summed pixel counts.
fn mean_level(runs: &[Level]) -> Level {
    let n = runs.len() as f64;
    let mean = |f: &dyn Fn(&Level) -> f64| runs.iter().map(f).sum::<f64>() / n;
    let mse = mean(&|l| l.metrics.mse);
    Level {
        spp: runs[0].spp,
        metrics: Metrics {
            pixels: runs.iter().map(|l| l.metrics.pixels).sum(),
            left_out: runs.iter().map(|l| l.metrics.left_out).sum(),
            rmse: mse.sqrt(),
            mse,
            rel_mse: mean(&|l| l.metrics.rel_mse),
            psnr_db: (mse > 0.0).then(|| -10.0 * mse.log10()),
            max_abs_error: runs
                .iter()
                .map(|l| l.metrics.max_abs_error)
                .fold(0.0, f64::max),
        },
        cycles: runs[0]
            .cycles
            .map(|_| (mean(&|l| l.cycles.unwrap_or(0) as f64)).round() as u64),
        host_seconds: mean(&|l| l.host_seconds),
    }
}

fn row(l: &Level) -> String {
    let cycles = l.cycles.map_or(String::new(), |c| c.to_string());
    format!(
        "{:>6}  {:>12.5e}  {:>12.5e}  {:>14}  {:>10.3}",
        l.spp, l.metrics.rmse, l.metrics.rel_mse, cycles, l.host_seconds
    )
}

fn csv_text(levels: &[Level]) -> String {
    let mut s = String::from("spp,rmse,rel_mse,psnr_db,max_abs_error,cycles,host_seconds\n");
    for l in levels {
        let m = &l.metrics;
        s += &format!(
            "{},{},{},{},{},{},{}\n",
            l.spp,
            m.rmse,
            m.rel_mse,
            m.psnr_db.map_or(String::new(), |p| p.to_string()),
            m.max_abs_error,
            l.cycles.map_or(String::new(), |c| c.to_string()),
            l.host_seconds
        );
    }
    s
}

/// Renders the reference with `trax native` (this executable) into `OUT/reference.bin`.
fn render_reference(a: &ConvergeArgs) -> Result<Image, String> {
    let path = a.out.join("reference.bin");
    let seed = a.reference_seed.unwrap_or(a.seed.wrapping_add(a.repeats));
    let exe = std::env::current_exe().map_err(|e| format!("the trax executable: {e}"))?;
    let mut cmd = Command::new(exe);
    cmd.arg("native").arg(&a.kernel);
    for (flag, v) in [
        ("--scene", a.scene.clone()),
        ("--width", a.width.to_string()),
        ("--height", a.height.to_string()),
        ("--spp", a.reference_spp.to_string()),
        ("--depth", a.depth.to_string()),
        ("--seed", seed.to_string()),
        ("--config", a.shape.config.clone()),
    ] {
        cmd.arg(flag).arg(v);
    }
    let optional = [
        ("--scene-scale", a.scene_scale.map(|s| s.to_string())),
        ("--view", a.view.as_ref().map(|p| p.display().to_string())),
        ("--light", a.light.as_ref().map(|p| p.display().to_string())),
        ("--tms", a.shape.tms.map(|v| v.to_string())),
        ("--threads", a.shape.threads.map(|v| v.to_string())),
    ];
    for (flag, v) in optional {
        if let Some(v) = v {
            cmd.arg(flag).arg(v);
        }
    }
    // The same chip: its thread shape and treelet layout give the same image.
    for (path, value) in &a.shape.set {
        cmd.arg("--set").arg(format!("{path}={value}"));
    }
    cmd.arg("--raw-framebuffer").arg(&path);
    let start = Instant::now();
    let out = cmd
        .output()
        .map_err(|e| format!("running trax native: {e}"))?;
    if !out.status.success() {
        return Err(format!(
            "the reference (trax native {} at {} spp) failed:\n{}",
            a.kernel.display(),
            a.reference_spp,
            String::from_utf8_lossy(&out.stderr)
        ));
    }
    eprintln!(
        "reference: {} spp, seed {seed}, trax native, {:.3} s -> {}",
        a.reference_spp,
        start.elapsed().as_secs_f64(),
        path.display()
    );
    read_image(&path, Some((a.width, a.height)))
}

/// Draws RMSE against spp on log-log axes, with the fitted line and a −1/2 guide.
fn plot(path: &Path, levels: &[Level], slope: Option<f64>, name: &str) -> Result<(), String> {
    let pts: Vec<(f64, f64)> = levels
        .iter()
        .map(|l| (l.spp as f64, l.metrics.rmse))
        .filter(|(_, y)| *y > 0.0)
        .collect();
    if pts.is_empty() {
        return Err("nothing to plot: every level matches the reference exactly".into());
    }
    let (xlo, xhi) = pts.iter().fold((f64::MAX, f64::MIN), |(lo, hi), p| {
        (lo.min(p.0), hi.max(p.0))
    });
    let (ylo, yhi) = pts.iter().fold((f64::MAX, f64::MIN), |(lo, hi), p| {
        (lo.min(p.1), hi.max(p.1))
    });
    // The kernel's file name: a full path would crowd the title.
    let name = Path::new(name)
        .file_name()
        .map_or_else(|| name.to_string(), |f| f.to_string_lossy().into_owned());
    let title = match slope {
        Some(k) => format!("{name}: RMSE vs spp (fitted slope {k:.3})"),
        None => format!("{name}: RMSE vs spp"),
    };
    // Log10 axes from the shared axis helper (src/cli/plot/axis.rs): every decade
    // labelled once, 1-2-5 ticks within a few decades, below 0.1 too.
    let xa = Axis::fit(
        &[xlo / 1.5, xhi * 1.5],
        Unit::Number,
        Some(true),
        false,
        0.0,
    )?;
    let ya = Axis::fit(
        &[ylo / 2.0, yhi * 2.0],
        Unit::Number,
        Some(true),
        false,
        0.0,
    )?;
    super::plot::png_chart(path, |root| {
        let e = |x: &dyn std::fmt::Display| format!("{}: {x}", path.display());
        let (main, legend) = root.split_horizontally(super::plot::SIZE.0 - 230);
        let mut chart = super::plot::axes_chart(
            &main,
            &title,
            (&xa, "samples per pixel"),
            (&ya, "RMSE vs reference"),
        )
        .map_err(|x| e(&x))?;
        let at = |(x, y): (f64, f64)| (xa.to_axis(x), ya.to_axis(y));
        let pts: Vec<(f64, f64)> = pts.iter().map(|p| at(*p)).collect();
        chart
            .draw_series(LineSeries::new(pts.clone(), BLUE.stroke_width(2)))
            .map_err(|x| e(&x))?;
        chart
            .draw_series(pts.iter().map(|&p| Circle::new(p, 4, BLUE.filled())))
            .map_err(|x| e(&x))?;
        let (x0, y0) = (xa.value(pts[0].0), ya.value(pts[0].1));
        let guide = [
            at((xlo, y0 * (xlo / x0).powf(-0.5))),
            at((xhi, y0 * (xhi / x0).powf(-0.5))),
        ];
        chart
            .draw_series(LineSeries::new(guide, RED.stroke_width(1)))
            .map_err(|x| e(&x))?;
        super::plot::draw_legend(
            &legend,
            &[
                ("measured".into(), BLUE, super::plot::Mark::Line),
                (
                    "slope -1/2 (Monte Carlo)".into(),
                    RED,
                    super::plot::Mark::Line,
                ),
            ],
        )
        .map_err(|x| e(&x))?;
        Ok(())
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The convergence chart fits its canvas (legend beside the plot), from 1 to 1024 spp
    /// and RMSE across three decades.
    #[test]
    fn convergence_chart_fits_its_canvas() {
        let levels: Vec<Level> = [1u32, 4, 16, 64, 256, 1024]
            .iter()
            .map(|&spp| Level {
                spp,
                metrics: Metrics {
                    pixels: 1024,
                    left_out: 0,
                    rmse: 0.5 / f64::from(spp).sqrt(),
                    mse: 0.25 / f64::from(spp),
                    rel_mse: 0.0,
                    psnr_db: None,
                    max_abs_error: 1.0,
                },
                cycles: None,
                host_seconds: 1.0,
            })
            .collect();
        let path = std::env::temp_dir().join(format!("trax-converge-{}.png", std::process::id()));
        plot(
            &path,
            &levels,
            Some(-0.5),
            "/some/long/path/to/pathtracer.rs",
        )
        .unwrap();
        let fits = crate::cli::plot::margins_blank(&path);
        let _ = std::fs::remove_file(&path);
        fits.unwrap();
    }
}
