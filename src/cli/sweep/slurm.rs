//! The Slurm backend: the points not yet done become a job array (`sbatch
//! --array=0-(T-1)%K`), each task running a group of points with `trax sweep task`; results
//! land in the same results directory (which must be on a file system the nodes share), and
//! `trax sweep collect DIR` merges them.
//!
//! Array tasks claim each point before running it, as local runners do
//! ([`super::runner::Claim`]), so a local sweep in the same directory runs beside them and
//! every point runs once. Per-point limits apply in each task ([`super::runner`]); the job
//! asks Slurm for the memory limit (`--mem`, plus room for the task itself) and, unless
//! given, a time limit of the points' limit times the points per task plus a minute.
//!
//! Files: `DIR/slurm/sub-N.plan.json` (the plan as submitted: the tasks run it even if the
//! sweep is planned anew meanwhile), `DIR/slurm/sub-N.tasks` (line `i` = `INDEX:ID` of
//! the points of array task `i`), `DIR/slurm/sub-N.sbatch` (the job script),
//! `DIR/slurm/logs/JOB_TASK.out`.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

use super::plan::Plan;
use super::spec::{show_mib, SlurmSettings};

/// Memory asked of Slurm for an array task beyond its points' limit (the task itself).
const TASK_MEMORY: u64 = 256 << 20;

/// Array tasks per job at most (Slurm's default `MaxArraySize` is 1001); more points are
/// grouped so the array stays within it.
pub const MAX_TASKS: usize = 1000;

/// A prepared submission.
#[derive(Debug)]
pub struct Submission {
    /// The job script.
    pub script: PathBuf,
    /// Array tasks.
    pub tasks: usize,
    /// Points.
    pub points: usize,
}

fn quote(s: &str) -> String {
    format!("'{}'", s.replace('\'', "'\\''"))
}

/// `secs` as Slurm's `D-HH:MM:SS`.
pub fn slurm_time(secs: u64) -> String {
    format!(
        "{}-{:02}:{:02}:{:02}",
        secs / 86400,
        secs / 3600 % 24,
        secs / 60 % 60,
        secs % 60
    )
}

/// Writes the plan, task list and job script for the `pending` points (combination index
/// and id), submitted at `since`.
pub fn prepare(
    dir: &Path,
    plan: &Plan,
    exe: &Path,
    pending: &[(u64, String)],
    s: &SlurmSettings,
    since: f64,
) -> Result<Submission, String> {
    let name = &plan.name;
    let sdir = dir.join("slurm");
    let logs = sdir.join("logs");
    std::fs::create_dir_all(&logs).map_err(|e| format!("{}: {e}", logs.display()))?;
    let per_task = s
        .per_task
        .map_or_else(|| pending.len().div_ceil(MAX_TASKS).max(1), |n| n as usize);
    let groups: Vec<&[(u64, String)]> = pending.chunks(per_task).collect();
    let mut n = 1;
    while sdir.join(format!("sub-{n}.tasks")).exists() {
        n += 1;
    }
    let tasks_file = sdir.join(format!("sub-{n}.tasks"));
    let plan_file = sdir.join(format!("sub-{n}.plan.json"));
    let script = sdir.join(format!("sub-{n}.sbatch"));
    plan.save_to(&plan_file)?;
    let mut lines = String::new();
    for g in &groups {
        let words: Vec<String> = g.iter().map(|(i, id)| format!("{i}:{id}")).collect();
        lines += &words.join(" ");
        lines.push('\n');
    }
    std::fs::write(&tasks_file, lines).map_err(|e| format!("{}: {e}", tasks_file.display()))?;
    let mut array = format!("0-{}", groups.len().saturating_sub(1));
    if let Some(k) = s.max_running {
        array.push_str(&format!("%{k}"));
    }
    let job_name: String = format!("trax-{name}")
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' || c == '_' {
                c
            } else {
                '_'
            }
        })
        .collect();
    let mut text = String::from("#!/bin/bash\n");
    text.push_str(&format!(
        "# trax sweep {name}: {} point(s) in {} task(s)\n",
        pending.len(),
        groups.len()
    ));
    text.push_str(&format!("#SBATCH --job-name={job_name}\n"));
    text.push_str(&format!("#SBATCH --array={array}\n"));
    text.push_str(&format!("#SBATCH --output={}/%A_%a.out\n", logs.display()));
    text.push_str(&format!(
        "#SBATCH --cpus-per-task={}\n",
        s.cpus_per_task.unwrap_or(1)
    ));
    text.push_str("#SBATCH --ntasks=1\n");
    if let Some(p) = &s.partition {
        text.push_str(&format!("#SBATCH --partition={p}\n"));
    }
    let time = s.time.clone().or_else(|| {
        plan.limits
            .time_s
            .map(|t| slurm_time(t.saturating_mul(per_task as u64).saturating_add(60)))
    });
    if let Some(t) = &time {
        text.push_str(&format!("#SBATCH --time={t}\n"));
    }
    if let Some(m) = plan.limits.memory_bytes {
        text.push_str(&format!(
            "#SBATCH --mem={}\n",
            show_mib(m.saturating_add(TASK_MEMORY))
        ));
    }
    if let Some(a) = &s.account {
        text.push_str(&format!("#SBATCH --account={a}\n"));
    }
    text.push_str(&format!(
        "exec {} sweep task {} --plan {} --tasks {} --since {since:.3} --index \"$SLURM_ARRAY_TASK_ID\"\n",
        quote(&exe.display().to_string()),
        quote(&dir.display().to_string()),
        quote(&plan_file.display().to_string()),
        quote(&tasks_file.display().to_string()),
    ));
    std::fs::write(&script, text).map_err(|e| format!("{}: {e}", script.display()))?;
    Ok(Submission {
        script,
        tasks: groups.len(),
        points: pending.len(),
    })
}

/// Submits a job script with `sbatch --parsable`; returns the job id.
pub fn submit(script: &Path) -> Result<String, String> {
    let out = Command::new("sbatch")
        .arg("--parsable")
        .arg(script)
        .stdin(Stdio::null())
        .output()
        .map_err(|e| {
            format!("sbatch: {e} (is Slurm installed? `.ci/slurm-up` starts a one-node cluster)")
        })?;
    if !out.status.success() {
        return Err(format!(
            "sbatch {} failed: {}",
            script.display(),
            String::from_utf8_lossy(&out.stderr).trim()
        ));
    }
    let text = String::from_utf8_lossy(&out.stdout);
    let id = text.trim().split(';').next().unwrap_or("").to_string();
    if id.is_empty() || !id.chars().all(|c| c.is_ascii_digit()) {
        return Err(format!("sbatch printed no job id: {:?}", text.trim()));
    }
    Ok(id)
}

/// The points (combination index, id) of array task `index` in a task list.
pub fn task_points(tasks_file: &Path, index: usize) -> Result<Vec<(u64, String)>, String> {
    let text = std::fs::read_to_string(tasks_file)
        .map_err(|e| format!("{}: {e}", tasks_file.display()))?;
    let line = text.lines().nth(index).ok_or_else(|| {
        format!(
            "{}: no task {index} (the list has {})",
            tasks_file.display(),
            text.lines().count()
        )
    })?;
    line.split_whitespace()
        .map(|w| {
            w.split_once(':')
                .and_then(|(i, id)| Some((i.parse().ok()?, id.to_string())))
                .ok_or_else(|| {
                    format!(
                        "{}: task {index}: `{w}` is not INDEX:ID",
                        tasks_file.display()
                    )
                })
        })
        .collect()
}
