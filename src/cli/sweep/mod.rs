//! `trax sweep SWEEP.toml`: design-space sweeps. A sweep file ([`spec`]) names the kernel,
//! scene, render settings and chip config, and the parameters to vary; every point is a
//! `trax run` ([`runner`]) whose statistics and provenance go to `DIR/points/ID.json`;
//! `DIR/results.csv` ([`table`]) has a row per point. Points run on this machine
//! (`--local -j N`, the default) or as a Slurm job array (`--slurm`, [`slurm`]); either way a
//! re-run skips the points already done, and `trax sweep collect DIR` merges the results.
//!
//! A results directory holds `plan.json` ([`plan`]), `sweep.toml` (a copy of the sweep file),
//! `build/` (the kernels), `points/`, `output/` (kernel output, when any), `events.log`,
//! `results.csv`, `plots/` and, for Slurm, `slurm/`.

pub mod metrics;
pub mod plan;
pub mod runner;
pub mod slurm;
pub mod spec;
pub mod table;

use std::collections::{BTreeSet, VecDeque};
use std::fs::File;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Mutex;
use std::time::Duration;

use clap::{Args, Subcommand};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use serde_json::json;

use super::run::fail;
use plan::{sha256_hex, Plan};
use runner::{Outcome, Runner};

/// Arguments of `trax sweep`.
#[derive(Args, Debug)]
#[command(args_conflicts_with_subcommands = true, subcommand_negates_reqs = true)]
pub struct SweepArgs {
    #[command(subcommand)]
    cmd: Option<SweepCmd>,
    /// The sweep file (TOML; see docs/ARCHITECTURE.md and experiments/).
    #[arg(required = true)]
    file: Option<PathBuf>,
    /// Results directory (default: results/NAME, NAME being the sweep's name).
    #[arg(short = 'o', long)]
    out: Option<PathBuf>,
    /// Run the points on this machine (the default).
    #[arg(long, conflicts_with = "slurm")]
    local: bool,
    /// Points run at once on this machine (default: the host's cores); each gets
    /// `--host-threads` = cores / N (at least 1), so the cores are not oversubscribed.
    #[arg(short = 'j', long, conflicts_with = "slurm")]
    jobs: Option<usize>,
    /// Submit the points as a Slurm job array (sbatch) instead of running them here.
    #[arg(long)]
    slurm: bool,
    /// Slurm partition (default: the sweep file's [slurm] partition, else Slurm's default).
    #[arg(long, requires = "slurm")]
    partition: Option<String>,
    /// Slurm time limit per array task (e.g. 30:00, 1-00:00:00).
    #[arg(long, requires = "slurm")]
    time: Option<String>,
    /// Slurm account.
    #[arg(long, requires = "slurm")]
    account: Option<String>,
    /// Points per array task, run one after the other (default: 1, or enough to keep the
    /// array within 1000 tasks).
    #[arg(long, requires = "slurm")]
    per_task: Option<u32>,
    /// Array tasks running at once (`--array=...%K`).
    #[arg(long, requires = "slurm")]
    max_running: Option<u32>,
    /// CPUs per array task (each point's --host-threads). Default 1.
    #[arg(long, requires = "slurm")]
    cpus_per_task: Option<u32>,
    /// Write the job script but do not submit it.
    #[arg(long, requires = "slurm")]
    no_submit: bool,
    /// Run the points that failed before again (default: they keep their recorded error).
    #[arg(long)]
    retry_failed: bool,
    /// Run the finished points whose kernel has changed since (its executable's SHA-256
    /// differs from the one they ran) again.
    #[arg(long)]
    rerun_stale: bool,
    /// List the points (id and parameters) and run nothing.
    #[arg(long)]
    dry_run: bool,
}

#[derive(Subcommand, Debug)]
enum SweepCmd {
    /// Merge the points' results into DIR/results.csv and draw the sweep's plots.
    Collect {
        /// The results directory.
        dir: PathBuf,
    },
    /// Run the points of one Slurm array task (used by the job script).
    #[command(hide = true)]
    Task {
        /// The results directory.
        dir: PathBuf,
        /// The submission's task list.
        #[arg(long)]
        tasks: PathBuf,
        /// The array task index.
        #[arg(long)]
        index: usize,
    },
}

/// Runs `trax sweep`.
pub fn run(a: SweepArgs) -> ExitCode {
    let r = match &a.cmd {
        Some(SweepCmd::Collect { dir }) => table::collect(dir).map(|c| {
            table::report(dir, &c);
            ExitCode::SUCCESS
        }),
        Some(SweepCmd::Task { dir, tasks, index }) => run_task(dir, tasks, *index),
        None => sweep(&a),
    };
    r.unwrap_or_else(fail)
}

/// The host's cores.
fn cores() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

fn this_exe() -> Result<(PathBuf, String), String> {
    let exe = std::env::current_exe().map_err(|e| format!("this executable: {e}"))?;
    let bytes = std::fs::read(&exe).map_err(|e| format!("{}: {e}", exe.display()))?;
    Ok((exe, sha256_hex(&bytes)))
}

/// Holds `DIR/.lock` while a sweep plans or runs points here (released when the process
/// ends, however it ends).
fn lock(dir: &Path) -> Result<File, String> {
    let path = dir.join(".lock");
    let f = File::create(&path).map_err(|e| format!("{}: {e}", path.display()))?;
    match f.try_lock() {
        Ok(()) => Ok(f),
        Err(std::fs::TryLockError::WouldBlock) => Err(format!(
            "another `trax sweep` is running in {} (it holds {})",
            dir.display(),
            path.display()
        )),
        Err(std::fs::TryLockError::Error(e)) => Err(format!("{}: {e}", path.display())),
    }
}

fn sweep(a: &SweepArgs) -> Result<ExitCode, String> {
    let file = a.file.as_deref().ok_or("no sweep file given")?;
    let spec = spec::load(file).map_err(|e| e.to_string())?;
    let (points, merged) = spec::expand(&spec).map_err(|e| e.to_string())?;
    let dir = match &a.out {
        Some(d) => d.clone(),
        None => {
            let safe: String = spec
                .name
                .chars()
                .map(|c| {
                    if c.is_alphanumeric() || "-_.".contains(c) {
                        c
                    } else {
                        '_'
                    }
                })
                .collect();
            PathBuf::from("results").join(safe)
        }
    };
    std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let dir = std::path::absolute(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let mut plan =
        plan::make_plan(&spec, &points, &dir.join("build")).map_err(|e| e.to_string())?;
    if merged > 0 {
        eprintln!("note: {merged} point(s) repeat another's parameters and run once");
    }
    for (i, p) in plan.plots.iter().enumerate() {
        check_plot(&plan, p).map_err(|(field, msg)| {
            spec::SpecError {
                file: spec.file.display().to_string(),
                loc: p.loc,
                field: format!("plot[{i}].{field}"),
                msg,
            }
            .to_string()
        })?;
    }
    if a.dry_run {
        for (p, pt) in plan.points.iter().zip(&points) {
            println!("{} {}", p.id, plan::describe(pt));
        }
        eprintln!("{} points", plan.points.len());
        return Ok(ExitCode::SUCCESS);
    }
    runner::make_dirs(&dir)?;
    let guard = lock(&dir)?;
    let (exe, exe_sha256) = this_exe()?;
    plan::build_kernels(&mut plan, &exe)?;
    plan.save(&dir)?;
    let copy = dir.join("sweep.toml");
    let same = |a: &Path, b: &Path| matches!((a.canonicalize(), b.canonicalize()), (Ok(a), Ok(b)) if a == b);
    if !same(file, &copy) {
        std::fs::copy(file, &copy).map_err(|e| format!("{}: {e}", file.display()))?;
    }
    // Points to run: not run yet; failed (with --retry-failed); run with another build of
    // their kernel (with --rerun-stale; otherwise they are only counted and reported).
    let mut stale = 0;
    let mut pending: Vec<usize> = Vec::new();
    for (i, p) in plan.points.iter().enumerate() {
        let run = match runner::recorded(&dir, &p.id) {
            None => true,
            Some(r) => {
                let old = r.elf_sha256 != plan.kernels[p.kernel].elf_sha256;
                stale += usize::from(old);
                (r.status == "failed" && a.retry_failed) || (old && a.rerun_stale)
            }
        };
        if run {
            pending.push(i);
        }
    }
    if stale > 0 && !a.rerun_stale {
        eprintln!(
            "warning: {stale} finished point(s) ran a different build of their kernel (the source or compiler changed since); --rerun-stale runs them again"
        );
    }
    let done = plan.points.len() - pending.len();
    if a.slurm {
        let ids: Vec<String> = pending.iter().map(|&i| plan.points[i].id.clone()).collect();
        drop(guard);
        return submit_slurm(a, &dir, &plan, &exe, &ids, done);
    }
    let jobs = a.jobs.unwrap_or_else(cores).max(1);
    let runner = Runner {
        dir: dir.clone(),
        exe,
        exe_sha256,
        host_threads: (cores() / jobs).max(1),
        backend: json!({ "backend": "local", "jobs": jobs }),
    };
    if done > 0 {
        eprintln!(
            "{done} of {} points already done in {}; running the other {}",
            plan.points.len(),
            dir.display(),
            pending.len()
        );
    }
    let failed = run_local(&runner, &plan, &pending, jobs)?;
    let c = table::collect(&dir)?;
    table::report(&dir, &c);
    drop(guard);
    if c.failed > 0 || failed > 0 {
        eprintln!(
            "error: {} point(s) failed: see the error column of results.csv and {}",
            c.failed,
            dir.join("points").join("ID.json").display()
        );
        return Ok(ExitCode::FAILURE);
    }
    if c.pending > 0 {
        eprintln!(
            "error: {} point(s) were interrupted; run the sweep again to finish them",
            c.pending
        );
        return Ok(ExitCode::FAILURE);
    }
    Ok(ExitCode::SUCCESS)
}

/// Checks a plot of the sweep file against the plan's parameters and the metrics; an error
/// names the plot's field.
fn check_plot(plan: &Plan, p: &spec::PlotSpec) -> Result<(), (String, String)> {
    for (what, name) in [("x", Some(&p.x)), ("by", p.by.as_ref())]
        .into_iter()
        .filter_map(|(w, n)| Some((w, n?)))
        .chain(p.filter.iter().map(|(k, _)| ("where", k)))
    {
        if !plan.columns.contains(name) {
            return Err((
                what.to_string(),
                format!(
                    "{name:?} is not a parameter of the sweep (parameters: {})",
                    plan.columns.join(", ")
                ),
            ));
        }
    }
    if metrics::metric(&p.y).is_none() {
        let all: Vec<&str> = metrics::METRICS.iter().map(|m| m.column).collect();
        return Err((
            "y".into(),
            format!("{:?} is not a metric (metrics: {})", p.y, all.join(", ")),
        ));
    }
    Ok(())
}

/// Short description of a point for progress lines: the parameters that vary in the plan.
fn varying(plan: &Plan) -> Vec<String> {
    plan.columns
        .iter()
        .filter(|c| {
            let vals: BTreeSet<String> = plan
                .points
                .iter()
                .map(|p| p.params.get(*c).map(|v| v.canonical()).unwrap_or_default())
                .collect();
            vals.len() > 1
        })
        .cloned()
        .collect()
}

fn label(p: &plan::PlanPoint, cols: &[String]) -> String {
    cols.iter()
        .filter_map(|c| Some(format!("{c}={}", p.params.get(c)?.plain())))
        .collect::<Vec<_>>()
        .join(" ")
}

/// Runs `pending` points on `jobs` worker threads, each point a child process; returns how
/// many failed.
fn run_local(
    runner: &Runner,
    plan: &Plan,
    pending: &[usize],
    jobs: usize,
) -> Result<usize, String> {
    if pending.is_empty() {
        return Ok(0);
    }
    let bar =
        ProgressBar::with_draw_target(Some(pending.len() as u64), ProgressDrawTarget::stderr());
    bar.set_style(
        ProgressStyle::with_template(
            "{bar:30} {pos}/{len} points [{elapsed_precise}, ETA {eta_precise}] {msg}",
        )
        .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    bar.enable_steady_tick(Duration::from_millis(500));
    let cols = varying(plan);
    let queue = Mutex::new(pending.iter().copied().collect::<VecDeque<usize>>());
    let failed = Mutex::new(0usize);
    let stop = AtomicBool::new(false);
    let fatal: Mutex<Option<String>> = Mutex::new(None);
    let total = pending.len();
    std::thread::scope(|s| {
        for _ in 0..jobs.min(pending.len()) {
            s.spawn(|| loop {
                if stop.load(Ordering::Relaxed) {
                    return;
                }
                let Some(i) = queue.lock().map_or(None, |mut q| q.pop_front()) else {
                    return;
                };
                let p = &plan.points[i];
                match runner.run(plan, p) {
                    Ok((outcome, wall)) => {
                        let word = match &outcome {
                            Outcome::Ok => "ok".to_string(),
                            Outcome::Failed(e) => {
                                if let Ok(mut f) = failed.lock() {
                                    *f += 1;
                                }
                                format!("FAILED: {e}")
                            }
                            Outcome::Interrupted(e) => format!("interrupted ({e})"),
                        };
                        bar.inc(1);
                        let line = format!(
                            "[{}/{total}] {} {} {word} ({wall:.1} s)",
                            bar.position(),
                            p.id,
                            label(p, &cols)
                        );
                        if bar.is_hidden() {
                            eprintln!("{line}");
                        } else {
                            bar.println(line);
                        }
                    }
                    Err(e) => {
                        stop.store(true, Ordering::Relaxed);
                        if let Ok(mut f) = fatal.lock() {
                            *f = Some(e);
                        }
                        return;
                    }
                }
            });
        }
    });
    bar.finish_and_clear();
    if let Some(e) = fatal.into_inner().ok().flatten() {
        return Err(e);
    }
    Ok(failed.into_inner().unwrap_or(0))
}

fn submit_slurm(
    a: &SweepArgs,
    dir: &Path,
    plan: &Plan,
    exe: &Path,
    ids: &[String],
    done: usize,
) -> Result<ExitCode, String> {
    if ids.is_empty() {
        eprintln!("all {done} points are done; nothing to submit");
        let c = table::collect(dir)?;
        table::report(dir, &c);
        return Ok(ExitCode::SUCCESS);
    }
    let f = &plan.slurm;
    let settings = spec::SlurmSettings {
        partition: a.partition.clone().or_else(|| f.partition.clone()),
        time: a.time.clone().or_else(|| f.time.clone()),
        account: a.account.clone().or_else(|| f.account.clone()),
        per_task: a.per_task.or(f.per_task),
        max_running: a.max_running.or(f.max_running),
        cpus_per_task: a.cpus_per_task.or(f.cpus_per_task),
    };
    let sub = slurm::prepare(dir, &plan.name, exe, ids, &settings)?;
    if a.no_submit {
        eprintln!(
            "wrote {} ({} tasks for {} points); submit it with sbatch",
            sub.script.display(),
            sub.tasks,
            sub.points
        );
        return Ok(ExitCode::SUCCESS);
    }
    let job = slurm::submit(&sub.script)?;
    println!("{job}");
    eprintln!(
        "submitted job {job}: {} array task(s) for {} point(s) ({} already done); when it is done: trax sweep collect {}",
        sub.tasks,
        sub.points,
        done,
        dir.display()
    );
    Ok(ExitCode::SUCCESS)
}

/// `trax sweep task`: one Slurm array task's points, one after the other.
fn run_task(dir: &Path, tasks: &Path, index: usize) -> Result<ExitCode, String> {
    let plan = Plan::load(dir)?;
    let ids = slurm::task_points(tasks, index)?;
    let (exe, exe_sha256) = this_exe()?;
    let env = |k: &str| std::env::var(k).ok();
    let host_threads = env("SLURM_CPUS_PER_TASK")
        .and_then(|v| v.parse::<usize>().ok())
        .unwrap_or(1)
        .max(1);
    let runner = Runner {
        dir: dir.to_path_buf(),
        exe,
        exe_sha256,
        host_threads,
        backend: json!({
            "backend": "slurm",
            "job": env("SLURM_ARRAY_JOB_ID"),
            "task": env("SLURM_ARRAY_TASK_ID"),
            "node": env("SLURMD_NODENAME"),
        }),
    };
    let cols = varying(&plan);
    let mut failed = 0;
    for id in &ids {
        let p =
            plan.points.iter().find(|p| &p.id == id).ok_or_else(|| {
                format!("point {id} is not in {}", dir.join("plan.json").display())
            })?;
        // Done already (a requeued task) with this build of the kernel.
        if runner::recorded(dir, id)
            .is_some_and(|r| r.status == "ok" && r.elf_sha256 == plan.kernels[p.kernel].elf_sha256)
        {
            eprintln!("{id} already done");
            continue;
        }
        let (outcome, wall) = runner.run(&plan, p)?;
        let word = match outcome {
            Outcome::Ok => "ok".to_string(),
            Outcome::Failed(e) => {
                failed += 1;
                format!("FAILED: {e}")
            }
            Outcome::Interrupted(e) => format!("interrupted ({e})"),
        };
        eprintln!("{id} {} {word} ({wall:.1} s)", label(p, &cols));
    }
    Ok(if failed > 0 {
        ExitCode::FAILURE
    } else {
        ExitCode::SUCCESS
    })
}
