//! Running one point: `trax run` as a child process of this executable (a crashing point
//! can't take the sweep down), its statistics and provenance written to `DIR/points/ID.json`
//! whole or not at all (temporary file + rename), so a killed sweep leaves no half result and
//! a restarted one runs exactly the points without a JSON.
//!
//! Every start and end is appended to `DIR/events.log` (`TIME start ID pid=N`, `TIME done ID
//! ok|failed`, `TIME interrupted ID ...`), an audit trail of what ran how often.

use std::fs::{File, OpenOptions};
use std::io::{Read, Seek, SeekFrom, Write};
use std::os::unix::process::ExitStatusExt;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Instant, SystemTime, UNIX_EPOCH};

use serde_json::{json, Value};

use super::plan::{write_atomic, Plan, PlanPoint};

/// Format tag of a point's JSON.
pub const POINT_FORMAT: &str = "trax-sweep-point/1";

/// Environment variable naming the sweep process to a point's `trax run`: the child exits
/// when its parent is gone (see [`crate::cli::watch_sweep_parent`]).
pub const PARENT_ENV: &str = "TRAX_SWEEP_PARENT";

/// Bytes of a failed point's stderr kept in its JSON (the end of it).
const STDERR_KEEP: u64 = 64 * 1024;

/// How a point ended.
#[derive(Debug)]
pub enum Outcome {
    /// Statistics recorded.
    Ok,
    /// Recorded as failed, with the error.
    Failed(String),
    /// Killed by a signal from outside (the sweep being stopped): nothing recorded, it runs
    /// again next time.
    Interrupted(String),
}

/// What runs points, and how it describes itself in their JSON.
pub struct Runner {
    /// The results directory.
    pub dir: PathBuf,
    /// This executable.
    pub exe: PathBuf,
    /// Its SHA-256.
    pub exe_sha256: String,
    /// `--host-threads` of each point.
    pub host_threads: usize,
    /// `{"backend": "local"}` or the Slurm job and task.
    pub backend: Value,
}

/// Seconds since the Unix epoch.
pub fn unix_now() -> f64 {
    SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map_or(0.0, |d| d.as_secs_f64())
}

/// `DIR/points/ID.json`.
pub fn point_path(dir: &Path, id: &str) -> PathBuf {
    dir.join("points").join(format!("{id}.json"))
}

/// What a point's JSON says about its run.
#[derive(Debug)]
pub struct Recorded {
    /// `ok` or `failed`.
    pub status: String,
    /// SHA-256 of the kernel executable it ran.
    pub elf_sha256: String,
}

/// The record of a point, none if it has not run.
pub fn recorded(dir: &Path, id: &str) -> Option<Recorded> {
    let text = std::fs::read_to_string(point_path(dir, id)).ok()?;
    let v: Value = serde_json::from_str(&text).ok()?;
    Some(Recorded {
        status: v.get("status")?.as_str()?.to_string(),
        elf_sha256: v["kernel"]["elf_sha256"].as_str().unwrap_or("").to_string(),
    })
}

/// Creates the directories of a results directory.
pub fn make_dirs(dir: &Path) -> Result<(), String> {
    for d in ["points", "tmp", "output", "build"] {
        let p = dir.join(d);
        std::fs::create_dir_all(&p).map_err(|e| format!("{}: {e}", p.display()))?;
    }
    Ok(())
}

/// Appends a line to `DIR/events.log` (one write, so lines of concurrent runners don't mix).
pub fn log_event(dir: &Path, what: &str) {
    let line = format!("{:.3} {what}\n", unix_now());
    if let Ok(mut f) = OpenOptions::new()
        .create(true)
        .append(true)
        .open(dir.join("events.log"))
    {
        let _ = f.write_all(line.as_bytes());
    }
}

/// The last `max` bytes of a file, as text.
fn tail(path: &Path, max: u64) -> String {
    let Ok(mut f) = File::open(path) else {
        return String::new();
    };
    let len = f.metadata().map_or(0, |m| m.len());
    let _ = f.seek(SeekFrom::Start(len.saturating_sub(max)));
    let mut buf = Vec::new();
    let _ = f.take(max).read_to_end(&mut buf);
    String::from_utf8_lossy(&buf).into_owned()
}

/// The error line of a failed run's stderr: its last `error:` line, else its last line.
fn error_line(stderr: &str, status: &str) -> String {
    let lines: Vec<&str> = stderr
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty())
        .collect();
    lines
        .iter()
        .rev()
        .find(|l| l.starts_with("error"))
        .or(lines.last())
        .map_or_else(|| status.to_string(), |l| format!("{l} ({status})"))
}

fn host_name() -> String {
    std::fs::read_to_string("/proc/sys/kernel/hostname")
        .map(|s| s.trim().to_string())
        .unwrap_or_default()
}

impl Runner {
    /// Runs one point and records it; `Err` only when the results directory can't be written.
    pub fn run(&self, plan: &Plan, p: &PlanPoint) -> Result<(Outcome, f64), String> {
        let pid = std::process::id();
        let tmp = self.dir.join("tmp");
        let stats_path = tmp.join(format!("{}.{pid}.stats.json", p.id));
        let out_path = tmp.join(format!("{}.{pid}.stdout", p.id));
        let err_path = tmp.join(format!("{}.{pid}.stderr", p.id));
        let cleanup = || {
            for f in [&stats_path, &out_path, &err_path] {
                let _ = std::fs::remove_file(f);
            }
        };
        let _ = std::fs::remove_file(&stats_path);
        let open = |f: &Path| File::create(f).map_err(|e| format!("{}: {e}", f.display()));
        let mut command = p.command(plan);
        command.extend([
            "--stats-json".into(),
            stats_path.display().to_string(),
            "--host-threads".into(),
            self.host_threads.to_string(),
        ]);
        log_event(&self.dir, &format!("start {} pid={pid}", p.id));
        let started = unix_now();
        let clock = Instant::now();
        let status = Command::new(&self.exe)
            .args(&command)
            .env(PARENT_ENV, pid.to_string())
            .stdin(Stdio::null())
            .stdout(open(&out_path)?)
            .stderr(open(&err_path)?)
            .status()
            .map_err(|e| format!("{}: {e}", self.exe.display()))?;
        let wall = clock.elapsed().as_secs_f64();
        let status_text = match (status.code(), status.signal()) {
            (Some(c), _) => format!("exit status {c}"),
            (None, Some(s)) => format!("killed by signal {s}"),
            _ => "ended".into(),
        };
        if let Some(sig) = status.signal() {
            // SIGHUP, SIGINT, SIGKILL, SIGTERM: stopped from outside, not the point's fault.
            if [1, 2, 9, 15].contains(&sig) {
                cleanup();
                log_event(&self.dir, &format!("interrupted {} signal {sig}", p.id));
                return Ok((Outcome::Interrupted(status_text), wall));
            }
        }
        let stats: Option<Value> = if status.success() {
            std::fs::read_to_string(&stats_path)
                .ok()
                .and_then(|t| serde_json::from_str(&t).ok())
        } else {
            None
        };
        let kernel = &plan.kernels[p.kernel];
        let config = p
            .chip()
            .ok()
            .and_then(|c| serde_json::to_value(c).ok())
            .unwrap_or(Value::Null);
        let (outcome, error, stderr) = match &stats {
            Some(_) => (Outcome::Ok, Value::Null, Value::Null),
            None => {
                let stderr = tail(&err_path, STDERR_KEEP);
                let err = if status.success() {
                    format!("no statistics were written ({status_text})")
                } else {
                    error_line(&stderr, &status_text)
                };
                (
                    Outcome::Failed(err.clone()),
                    Value::String(err),
                    Value::String(stderr),
                )
            }
        };
        // The kernel's output, if any, beside the results.
        let has_output = std::fs::metadata(&out_path).is_ok_and(|m| m.len() > 0);
        let output = if has_output {
            let dest = self.dir.join("output").join(format!("{}.txt", p.id));
            std::fs::rename(&out_path, &dest).map_err(|e| format!("{}: {e}", dest.display()))?;
            Value::String(format!("output/{}.txt", p.id))
        } else {
            Value::Null
        };
        let mut command_line = vec![self.exe.display().to_string()];
        command_line.extend(command);
        let record = json!({
            "format": POINT_FORMAT,
            "id": p.id,
            "status": if stats.is_some() { "ok" } else { "failed" },
            "params": p.params,
            "trax": { "version": env!("CARGO_PKG_VERSION"), "exe_sha256": self.exe_sha256 },
            "kernel": {
                "source": kernel.source,
                "opt_level": kernel.opt_level,
                "source_sha256": kernel.source_sha256,
                "elf_sha256": kernel.elf_sha256,
            },
            "config": config,
            "command": command_line,
            "runner": {
                "backend": self.backend,
                "host": host_name(),
                "pid": pid,
                "host_threads": self.host_threads,
            },
            "started_unix": started,
            "wall_seconds": wall,
            "exit": status_text,
            "output": output,
            "stats": stats,
            "error": error,
            "stderr": stderr,
        });
        let text = serde_json::to_string_pretty(&record).map_err(|e| e.to_string())? + "\n";
        write_atomic(&point_path(&self.dir, &p.id), text.as_bytes())?;
        cleanup();
        let word = if matches!(outcome, Outcome::Ok) {
            "ok"
        } else {
            "failed"
        };
        log_event(&self.dir, &format!("done {} {word}", p.id));
        Ok((outcome, wall))
    }
}
