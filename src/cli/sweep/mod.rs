//! `trax sweep SWEEP.toml`: design-space sweeps. A sweep file ([`spec`]) names the kernel,
//! scene, render settings and chip config, and the parameters to vary; every point is a
//! `trax run` ([`runner`]) whose statistics and provenance go to `DIR/points/ID.json`;
//! `DIR/results.csv` ([`table`]) has a row per point. Points run on this machine
//! (`--local -j N`, the default) or as a Slurm job array (`--slurm`, [`slurm`]); either way a
//! re-run skips the points already done, and `trax sweep collect DIR` merges the results.
//!
//! A point's result stands only while its inputs are as they were ([`state`]): a changed
//! kernel, chip config, scene file or trax runs it again, and `trax sweep status DIR` says
//! which points are done, stale (and why), failed, running or pending.
//!
//! A results directory holds `plan.json` ([`plan`]), `sweep.toml` (a copy of the sweep file),
//! `build/` (the kernels), `points/`, `claims/` (one per running point, [`runner`]),
//! `output/` (kernel output, when any), `events.log`, `results.csv`, `plots/` and, for
//! Slurm, `slurm/`.

pub mod metrics;
pub mod runner;
pub mod slurm;
pub mod state;
pub mod table;

pub use trax::sweep::{plan, spec};

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
use plan::{sha256_hex, Plan, PlanPoint};
use runner::{interrupted, Outcome, Runner};
use state::{Judge, State};

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
    /// Slurm time limit per array task (e.g. 30:00, 1-00:00:00; default: the points'
    /// time limit times the points per task, plus a minute).
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
    /// Wall-clock time a point may run (e.g. 90, 30m, 1.5h, 1:30:00; default: the sweep
    /// file's [limits] time, else none); a point over it is stopped and recorded as failed.
    #[arg(long, value_parser = spec::parse_duration, value_name = "TIME")]
    point_time: Option<u64>,
    /// Resident memory a point may use (e.g. 512M, 4G; a bare number is MiB; default: the
    /// sweep file's [limits] memory, else none); a point over it is stopped and recorded
    /// as failed. On Slurm also the array tasks' --mem.
    #[arg(long, value_parser = spec::parse_memory, value_name = "SIZE")]
    point_memory: Option<u64>,
    /// Run the points that failed before again (default: they keep their recorded error,
    /// unless an input changed since).
    #[arg(long)]
    retry_failed: bool,
    /// Sample every point (`trax run --sample N`), as `sample = N` at the top of the sweep
    /// file would: results.csv then has each estimate's 95% half-width (`METRIC_ci95`),
    /// and the points are others than the full runs' (their ids hold the setting).
    #[arg(long, value_name = "N")]
    sample: Option<u32>,
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
    /// Where each point stands: done, stale (its inputs changed since: what changed),
    /// failed (why), running (where) or pending. Exits 0 when every point is done.
    Status {
        /// The results directory.
        dir: PathBuf,
        /// List every point that is not done (default: the first 20 of each kind).
        #[arg(long)]
        all: bool,
    },
    /// Run the points of one Slurm array task (used by the job script).
    #[command(hide = true)]
    Task {
        /// The results directory.
        dir: PathBuf,
        /// The submission's plan.
        #[arg(long)]
        plan: PathBuf,
        /// The submission's task list.
        #[arg(long)]
        tasks: PathBuf,
        /// The array task index.
        #[arg(long)]
        index: usize,
        /// When the submission was made (Unix seconds): a point that failed after it
        /// (run by another runner) is not run again.
        #[arg(long)]
        since: f64,
    },
}

/// Runs `trax sweep`.
pub fn run(a: SweepArgs) -> ExitCode {
    let r = match &a.cmd {
        Some(SweepCmd::Collect { dir }) => table::collect(dir).map(|c| {
            table::report(dir, &c);
            ExitCode::SUCCESS
        }),
        Some(SweepCmd::Status { dir, all }) => state::status(dir, *all),
        Some(SweepCmd::Task {
            dir,
            plan,
            tasks,
            index,
            since,
        }) => run_task(dir, plan, tasks, *index, *since),
        None => sweep(&a),
    };
    r.unwrap_or_else(fail)
}

/// The host's cores.
fn cores() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

/// This executable and its SHA-256.
pub fn this_exe() -> Result<(PathBuf, String), String> {
    let exe = std::env::current_exe().map_err(|e| format!("this executable: {e}"))?;
    let bytes = std::fs::read(&exe).map_err(|e| format!("{}: {e}", exe.display()))?;
    Ok((exe, sha256_hex(&bytes)))
}

/// Holds `DIR/.lock` while a sweep plans or runs points here (released when the process
/// ends, however it ends): one planner at a time. Points themselves are claimed one by one
/// ([`runner::Claim`]), so Slurm array tasks run beside it.
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

/// Removes what a killed planner left (temporary files of the plan, the table and kernel
/// builds; only the holder of `DIR/.lock` writes those) and the temporary files of points
/// no runner holds.
fn clean_stale(dir: &Path) {
    for d in [dir.to_path_buf(), dir.join("build")] {
        if let Ok(entries) = std::fs::read_dir(&d) {
            for e in entries.flatten() {
                let name = e.file_name().to_string_lossy().into_owned();
                if name.starts_with('.') && name.contains(".tmp") {
                    let _ = std::fs::remove_file(e.path());
                }
            }
        }
    }
    runner::clean_stale_tmp(dir);
}

/// Whether a point needs no run by a runner that started at `since` and holds its claim:
/// its result is current, or it failed with current inputs in a run that began after
/// `since` (another runner tried it meanwhile).
fn settled(judge: &Mutex<Judge>, p: &PlanPoint, since: f64) -> bool {
    let Ok(mut j) = judge.lock() else {
        return false;
    };
    match j.recorded_state(p) {
        (State::Done, _) => true,
        (State::Failed(_), Some(rec)) => rec["started_unix"].as_f64().is_some_and(|t| t >= since),
        _ => false,
    }
}

fn sweep(a: &SweepArgs) -> Result<ExitCode, String> {
    let file = a.file.as_deref().ok_or("no sweep file given")?;
    let mut spec = spec::load(file).map_err(|e| e.to_string())?;
    if let Some(n) = a.sample {
        spec.add_fixed("--sample", "sample", spec::PVal::Int(n.into()))?;
    }
    let dir = a
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from("results").join(&spec.name));
    let mut plan = Plan::new(&spec).map_err(|e| e.to_string())?;
    if let Some(t) = a.point_time {
        plan.limits.time_s = Some(t);
    }
    if let Some(m) = a.point_memory {
        plan.limits.memory_bytes = Some(m);
    }
    let merged = plan.grid.merged.len();
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
        let mut out = std::io::BufWriter::new(std::io::stdout().lock());
        for i in plan.grid.indices() {
            let p = plan.grid.point(i);
            use std::io::Write;
            writeln!(out, "{} {}", p.id, plan::describe(&p)).map_err(|e| e.to_string())?;
        }
        eprintln!("{} points", plan.grid.point_count());
        return Ok(ExitCode::SUCCESS);
    }
    std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let dir = std::path::absolute(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    runner::make_dirs(&dir)?;
    let guard = lock(&dir)?;
    clean_stale(&dir);
    runner::catch_interrupts()?;
    let since = runner::unix_now();
    let (exe, exe_sha256) = this_exe()?;
    plan::build_kernels(&mut plan, &exe, &dir.join("build"))?;
    plan.save(&dir)?;
    let copy = dir.join("sweep.toml");
    let same = |a: &Path, b: &Path| matches!((a.canonicalize(), b.canonicalize()), (Ok(a), Ok(b)) if a == b);
    if !same(file, &copy) {
        std::fs::copy(file, &copy).map_err(|e| format!("{}: {e}", file.display()))?;
    }
    // Points to run: not run yet; stale (an input changed since their result); failed
    // (with --retry-failed). Points another runner has now are waited for.
    let judge = Mutex::new(Judge::new(&plan, &dir, &exe_sha256));
    let mut pending: Vec<u64> = Vec::new();
    let mut stale_lines: Vec<String> = Vec::new();
    let mut stale = 0u64;
    let mut running = 0u64;
    for p in plan.points() {
        let p = p?;
        let (state, _) = judge.lock().map_err(|e| e.to_string())?.state(&p);
        let run = match state {
            State::Done => false,
            State::Failed(_) => a.retry_failed,
            State::Stale(why) => {
                stale += 1;
                if stale_lines.len() < 5 {
                    stale_lines.push(format!("  {}: {}", p.id, why.join("; ")));
                }
                true
            }
            State::Running(_) => {
                running += 1;
                true
            }
            State::Pending(_) => true,
        };
        if run {
            pending.push(p.index);
        }
    }
    let total = plan.grid.point_count();
    let done = total - pending.len() as u64;
    if stale > 0 {
        eprintln!(
            "{stale} point(s) have results whose inputs changed since they ran; running them again:"
        );
        for l in &stale_lines {
            eprintln!("{l}");
        }
        if stale > stale_lines.len() as u64 {
            eprintln!(
                "  ... and {} more (`trax sweep status` lists them)",
                stale - stale_lines.len() as u64
            );
        }
    }
    if a.slurm {
        let ids: Vec<(u64, String)> = pending
            .iter()
            .map(|&i| (i, plan.grid.point(i).id))
            .collect();
        let r = submit_slurm(a, &dir, &plan, &exe, &ids, done, since);
        drop(guard);
        return r;
    }
    let jobs = a.jobs.unwrap_or_else(cores).max(1);
    let runner = Runner {
        dir: dir.clone(),
        exe,
        exe_sha256,
        host_threads: (cores() / jobs).max(1),
        backend: json!({ "backend": "local", "jobs": jobs }),
        limits: plan.limits.clone(),
    };
    if done > 0 {
        eprintln!(
            "{done} of {total} points already done in {}; running the other {}",
            dir.display(),
            pending.len()
        );
    }
    if running > 0 {
        eprintln!("{running} point(s) are running elsewhere (another runner holds them); waiting for them");
    }
    let failed = run_local(&runner, &plan, &pending, jobs, &judge, since)?;
    let mut judge = judge.into_inner().map_err(|e| e.to_string())?;
    let c = table::collect_with(&dir, &plan, &mut judge)?;
    table::report(&dir, &c);
    drop(guard);
    if interrupted() {
        eprintln!(
            "interrupted: {} point(s) not run yet; run the sweep again to finish them",
            c.pending + c.stale
        );
        return Ok(ExitCode::from(130));
    }
    if c.failed > 0 || failed > 0 {
        eprintln!(
            "error: {} point(s) failed: see the error column of results.csv and {}",
            c.failed,
            dir.join("points").join("ID.json").display()
        );
        return Ok(ExitCode::FAILURE);
    }
    if c.pending + c.stale + c.running > 0 {
        eprintln!(
            "error: {} point(s) were not run; run the sweep again to finish them (`trax sweep status {}` says why)",
            c.pending + c.stale + c.running,
            dir.display()
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
        let all: Vec<&str> = metrics::all().iter().map(|m| m.column).collect();
        return Err((
            "y".into(),
            format!("{:?} is not a metric (metrics: {})", p.y, all.join(", ")),
        ));
    }
    Ok(())
}

/// Short description of a point for progress lines: the parameters that vary in the plan
/// (one pass over the points, keeping each column's first value).
fn varying(plan: &Plan) -> Vec<String> {
    let mut first: Vec<Option<String>> = vec![None; plan.columns.len()];
    let mut varies: BTreeSet<usize> = BTreeSet::new();
    for i in plan.grid.indices() {
        let p = plan.grid.point(i);
        for (c, col) in plan.columns.iter().enumerate() {
            let v = p.params.get(col).map(|v| v.canonical()).unwrap_or_default();
            match &first[c] {
                None => first[c] = Some(v),
                Some(f) if *f != v => {
                    varies.insert(c);
                }
                _ => {}
            }
        }
        if varies.len() == plan.columns.len() {
            break;
        }
    }
    varies
        .into_iter()
        .map(|c| plan.columns[c].clone())
        .collect()
}

fn label(p: &PlanPoint, cols: &[String]) -> String {
    cols.iter()
        .filter_map(|c| Some(format!("{c}={}", p.params.get(c)?.plain())))
        .collect::<Vec<_>>()
        .join(" ")
}

/// Runs `pending` points (combination indices) on `jobs` worker threads, each point a
/// child process; points another runner holds are left to it and waited for (run here if it
/// ends without a current result). Returns how many failed.
fn run_local(
    runner: &Runner,
    plan: &Plan,
    pending: &[u64],
    jobs: usize,
    judge: &Mutex<Judge>,
    since: f64,
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
    let queue = Mutex::new(pending.iter().copied().collect::<VecDeque<u64>>());
    // Points another runner held when we came to them: (index, owner).
    let elsewhere: Mutex<Vec<(u64, String)>> = Mutex::new(Vec::new());
    let failed = Mutex::new(0usize);
    let stop = AtomicBool::new(false);
    let fatal: Mutex<Option<String>> = Mutex::new(None);
    let total = pending.len();
    let say = |line: String| {
        if bar.is_hidden() {
            eprintln!("{line}");
        } else {
            bar.println(line);
        }
    };
    let next = || -> Option<u64> {
        if let Some(i) = queue.lock().ok()?.pop_front() {
            return Some(i);
        }
        // Then the points held elsewhere, once their holder lets go.
        loop {
            if stop.load(Ordering::Relaxed) || interrupted() {
                return None;
            }
            let mut e = elsewhere.lock().ok()?;
            if e.is_empty() {
                return None;
            }
            if let Some(k) = e.iter().position(|(i, _)| {
                runner::Claim::holder(&runner.dir, &plan.grid.point(*i).id).is_none()
            }) {
                return Some(e.remove(k).0);
            }
            bar.set_message(format!(
                "waiting for {} point(s) running elsewhere",
                e.len()
            ));
            drop(e);
            std::thread::sleep(Duration::from_millis(500));
        }
    };
    std::thread::scope(|s| {
        for _ in 0..jobs.min(pending.len()) {
            s.spawn(|| loop {
                if stop.load(Ordering::Relaxed) || interrupted() {
                    return;
                }
                let Some(i) = next() else {
                    return;
                };
                let p = match plan.point(i) {
                    Ok(p) => p,
                    Err(e) => {
                        stop.store(true, Ordering::Relaxed);
                        if let Ok(mut f) = fatal.lock() {
                            *f = Some(e);
                        }
                        return;
                    }
                };
                match runner.run(plan, &p, &mut |p| settled(judge, p, since)) {
                    Ok((Outcome::Claimed(owner), _)) => {
                        if let Ok(mut e) = elsewhere.lock() {
                            e.push((i, owner));
                        }
                    }
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
                            Outcome::DoneElsewhere => "done by another runner".into(),
                            Outcome::Claimed(_) => unreachable!("handled above"),
                        };
                        bar.inc(1);
                        say(format!(
                            "[{}/{total}] {} {} {word} ({wall:.1} s)",
                            bar.position(),
                            p.id,
                            label(&p, &cols)
                        ));
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
    ids: &[(u64, String)],
    done: u64,
    since: f64,
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
    let sub = slurm::prepare(dir, plan, exe, ids, &settings, since)?;
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
fn run_task(
    dir: &Path,
    plan_file: &Path,
    tasks: &Path,
    index: usize,
    since: f64,
) -> Result<ExitCode, String> {
    runner::catch_interrupts()?;
    let plan = Plan::load_file(plan_file)?;
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
        exe_sha256: exe_sha256.clone(),
        host_threads,
        backend: json!({
            "backend": "slurm",
            "job": env("SLURM_ARRAY_JOB_ID"),
            "task": env("SLURM_ARRAY_TASK_ID"),
            "node": env("SLURMD_NODENAME"),
        }),
        limits: plan.limits.clone(),
    };
    let judge = Mutex::new(Judge::new(&plan, dir, &exe_sha256));
    let cols = varying(&plan);
    let mut failed = 0;
    for (i, id) in &ids {
        if interrupted() {
            break;
        }
        let p = plan.point_with_id(*i, id)?;
        let (outcome, wall) = runner.run(&plan, &p, &mut |p| settled(&judge, p, since))?;
        let word = match outcome {
            Outcome::Ok => "ok".to_string(),
            Outcome::Failed(e) => {
                failed += 1;
                format!("FAILED: {e}")
            }
            Outcome::Interrupted(e) => format!("interrupted ({e})"),
            Outcome::Claimed(owner) => format!("left to {owner}, who runs it"),
            Outcome::DoneElsewhere => "already done".into(),
        };
        eprintln!("{id} {} {word} ({wall:.1} s)", label(&p, &cols));
    }
    Ok(if failed > 0 || interrupted() {
        ExitCode::FAILURE
    } else {
        ExitCode::SUCCESS
    })
}
