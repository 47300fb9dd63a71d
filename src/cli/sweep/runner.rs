//! Running one point: `trax run` as a child process of this executable (a crashing point
//! can't take the sweep down), its statistics and provenance written to `DIR/points/ID.json`
//! whole or not at all (temporary file + rename), so a killed sweep leaves no half result and
//! a restarted one runs exactly the points without a current result.
//!
//! One writer per point: a runner (a local worker or a Slurm array task, on any host that
//! shares the directory) first takes the point's claim, `DIR/claims/ID`, an exclusive
//! `flock` held while the point runs and released however the runner ends (its owner is
//! written in it for `trax sweep status`). Whoever finds a point claimed leaves it.
//!
//! Per-point limits ([`Limits`]): the runner polls the child's resident memory and its wall
//! time and kills it (SIGKILL) when over; the peak (`ru_maxrss` from `wait4`) is checked at
//! the end too. A point that dies — a limit, a signal from outside (SIGKILL from `kill -9` or
//! the OOM killer, SIGXCPU from a CPU-time limit), a Slurm time limit — is recorded as failed
//! with the cause. Only the user interrupting the sweep itself (SIGINT, SIGTERM, SIGHUP to
//! the sweep: [`catch_interrupts`]) leaves a point unrecorded, to run again next time.
//!
//! Every start and end is appended to `DIR/events.log` (`TIME start ID pid=N`, `TIME done ID
//! ok|failed`, `TIME interrupted ID ...`), an audit trail of what ran how often.

use std::collections::HashMap;
use std::fs::{File, OpenOptions};
use std::io::{Read, Seek, SeekFrom, Write};
use std::os::unix::fs::MetadataExt;
use std::os::unix::process::ExitStatusExt;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, OnceLock};
use std::time::{Duration, Instant, SystemTime, UNIX_EPOCH};

use serde_json::{json, Value};

use super::plan::{sha256_hex, write_atomic, Plan, PlanPoint};
use super::spec::{show_mib, Limits};

/// Format tag of a point's JSON.
pub const POINT_FORMAT: &str = "trax-sweep-point/2";

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
    /// The sweep was interrupted (by its user): nothing recorded, it runs again next time.
    Interrupted(String),
    /// Another runner holds the point's claim (its owner, as it wrote it).
    Claimed(String),
    /// Another runner finished it with these inputs meanwhile.
    DoneElsewhere,
}

/// The flag [`catch_interrupts`] sets.
fn interrupt_flag() -> &'static Arc<AtomicBool> {
    static FLAG: OnceLock<Arc<AtomicBool>> = OnceLock::new();
    FLAG.get_or_init(|| Arc::new(AtomicBool::new(false)))
}

/// From now on SIGINT, SIGTERM and SIGHUP to this process mean "the user stops the sweep":
/// runners stop their points without recording them ([`interrupted`]).
pub fn catch_interrupts() -> Result<(), String> {
    for sig in [
        signal_hook::consts::SIGINT,
        signal_hook::consts::SIGTERM,
        signal_hook::consts::SIGHUP,
    ] {
        signal_hook::flag::register(sig, Arc::clone(interrupt_flag()))
            .map_err(|e| format!("signal handler: {e}"))?;
    }
    Ok(())
}

/// Whether the sweep has been interrupted ([`catch_interrupts`]).
pub fn interrupted() -> bool {
    interrupt_flag().load(Ordering::SeqCst)
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
    /// Per-point limits.
    pub limits: Limits,
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

/// `DIR/claims/ID`.
fn claim_path(dir: &Path, id: &str) -> PathBuf {
    dir.join("claims").join(id)
}

/// Creates the directories of a results directory.
pub fn make_dirs(dir: &Path) -> Result<(), String> {
    for d in ["points", "tmp", "output", "build", "claims"] {
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

/// This host's name.
pub fn host_name() -> String {
    std::fs::read_to_string("/proc/sys/kernel/hostname")
        .map(|s| s.trim().to_string())
        .unwrap_or_default()
}

/// A point's claim, held while it runs (see the module documentation).
pub struct Claim {
    path: PathBuf,
    file: File,
}

impl Claim {
    /// Takes the claim of point `id`, writing `owner` into it; `Err(owner)` with the
    /// holder's description when another runner holds it.
    pub fn take(dir: &Path, id: &str, owner: &Value) -> Result<Result<Claim, String>, String> {
        let path = claim_path(dir, id);
        loop {
            let file = OpenOptions::new()
                .create(true)
                .truncate(false)
                .read(true)
                .write(true)
                .open(&path)
                .map_err(|e| format!("{}: {e}", path.display()))?;
            match file.try_lock() {
                Ok(()) => {}
                Err(std::fs::TryLockError::WouldBlock) => {
                    return Ok(Err(read_owner(&path)));
                }
                Err(std::fs::TryLockError::Error(e)) => {
                    return Err(format!("{}: {e}", path.display()))
                }
            }
            // The holder before us may have removed the file after we opened it: the
            // claim is the lock on the file that is at the path now.
            let same = match (file.metadata(), std::fs::metadata(&path)) {
                (Ok(a), Ok(b)) => a.ino() == b.ino() && a.dev() == b.dev(),
                _ => false,
            };
            if !same {
                continue;
            }
            let mut f = &file;
            let text = serde_json::to_string(owner).unwrap_or_default();
            let _ = f.set_len(0);
            let _ = f.write_all(text.as_bytes());
            return Ok(Ok(Claim { path, file }));
        }
    }

    /// What an earlier holder wrote, if the claim file is still there (it died holding
    /// it: a runner removes its claim when it is done).
    pub fn leftover(dir: &Path, id: &str) -> Option<String> {
        let path = claim_path(dir, id);
        path.is_file().then(|| read_owner(&path))
    }

    /// Whether a runner holds point `id`'s claim now, and who.
    pub fn holder(dir: &Path, id: &str) -> Option<String> {
        let path = claim_path(dir, id);
        let file = File::open(&path).ok()?;
        match file.try_lock_shared() {
            Ok(()) => None,
            Err(_) => Some(read_owner(&path)),
        }
    }
}

impl Drop for Claim {
    fn drop(&mut self) {
        // Removed while still locked, so no one takes a claim on a file about to go.
        let _ = std::fs::remove_file(&self.path);
        let _ = self.file.unlock();
    }
}

/// A claim's owner as a short text.
fn read_owner(path: &Path) -> String {
    let text = std::fs::read_to_string(path).unwrap_or_default();
    let Ok(v) = serde_json::from_str::<Value>(&text) else {
        return "another runner".into();
    };
    owner_text(&v)
}

/// `pid N on HOST (Slurm job J_T), since TIME`.
pub fn owner_text(v: &Value) -> String {
    let mut s = format!(
        "pid {} on {}",
        v["pid"].as_u64().unwrap_or(0),
        v["host"].as_str().unwrap_or("?")
    );
    if v["backend"]["backend"] == "slurm" {
        s += &format!(
            " (Slurm job {}_{})",
            v["backend"]["job"].as_str().unwrap_or("?"),
            v["backend"]["task"].as_str().unwrap_or("?")
        );
    }
    s
}

/// Removes what an earlier runner of point `id` left behind when it was killed (its
/// temporary files): called with the point's claim held, so no live runner owns them.
fn clean_leftovers(dir: &Path, id: &str) {
    let prefixes = [
        (dir.join("tmp"), format!("{id}.")),
        (dir.join("points"), format!(".{id}.json.tmp.")),
    ];
    for (d, prefix) in prefixes {
        if let Ok(entries) = std::fs::read_dir(&d) {
            for e in entries.flatten() {
                if e.file_name().to_string_lossy().starts_with(&prefix) {
                    let _ = std::fs::remove_file(e.path());
                }
            }
        }
    }
}

/// Removes the temporary files of points no runner holds (left by runners that were
/// killed): the start of a sweep.
pub fn clean_stale_tmp(dir: &Path) {
    let Ok(entries) = std::fs::read_dir(dir.join("tmp")) else {
        return;
    };
    let mut ids: Vec<String> = entries
        .flatten()
        .filter_map(|e| {
            let name = e.file_name().to_string_lossy().into_owned();
            Some(name.split_once('.')?.0.to_string())
        })
        .collect();
    ids.sort();
    ids.dedup();
    for id in ids {
        if Claim::holder(dir, &id).is_none() {
            clean_leftovers(dir, &id);
        }
    }
}

/// The system-wide count of OOM kills (`/proc/vmstat` `oom_kill`).
fn oom_kills() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/vmstat").ok()?;
    text.lines()
        .find_map(|l| l.strip_prefix("oom_kill "))
        .and_then(|n| n.trim().parse().ok())
}

/// Resident bytes of process `pid` (`/proc/PID/statm`).
fn resident_bytes(pid: u32) -> Option<u64> {
    let text = std::fs::read_to_string(format!("/proc/{pid}/statm")).ok()?;
    let pages: u64 = text.split_whitespace().nth(1)?.parse().ok()?;
    // SAFETY: sysconf has no preconditions; it only reads a system constant.
    let page = unsafe { libc::sysconf(libc::_SC_PAGESIZE) };
    Some(pages * u64::try_from(page).unwrap_or(4096))
}

/// A child's end, from `wait4`.
struct Ended {
    status: std::process::ExitStatus,
    max_rss_bytes: u64,
}

/// Reaps `pid` if it has ended (`wait4` with `WNOHANG`), with its peak resident memory.
fn try_reap(pid: u32) -> Result<Option<Ended>, String> {
    let mut status: libc::c_int = 0;
    // SAFETY: an all-zero rusage is a valid value of this plain C struct.
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    // SAFETY: `pid` is our unreaped child (spawned by us and not waited for elsewhere), so
    // it names no other process; `status` and `usage` are valid for writes.
    let r = unsafe { libc::wait4(pid as libc::pid_t, &mut status, libc::WNOHANG, &mut usage) };
    match r {
        0 => Ok(None),
        r if r == pid as libc::pid_t => Ok(Some(Ended {
            status: std::process::ExitStatus::from_raw(status),
            max_rss_bytes: u64::try_from(usage.ru_maxrss).unwrap_or(0) * 1024,
        })),
        _ => Err(format!(
            "waiting for point process {pid}: {}",
            std::io::Error::last_os_error()
        )),
    }
}

/// The name of a signal.
fn signal_name(sig: i32) -> String {
    let name = match sig {
        libc::SIGHUP => "SIGHUP",
        libc::SIGINT => "SIGINT",
        libc::SIGKILL => "SIGKILL",
        libc::SIGTERM => "SIGTERM",
        libc::SIGXCPU => "SIGXCPU",
        libc::SIGSEGV => "SIGSEGV",
        libc::SIGABRT => "SIGABRT",
        libc::SIGBUS => "SIGBUS",
        libc::SIGXFSZ => "SIGXFSZ",
        _ => return format!("signal {sig}"),
    };
    format!("{name} (signal {sig})")
}

/// Why a point was stopped by its runner.
enum Stop {
    Time(f64),
    Memory(u64),
    Interrupt,
}

/// What a Slurm array task's job is doing now (`scontrol show job`): its state and reason.
fn slurm_job_state() -> Option<(String, String)> {
    let job = std::env::var("SLURM_JOB_ID").ok()?;
    let out = Command::new("timeout")
        .args(["10", "scontrol", "-o", "show", "job", &job])
        .stdin(Stdio::null())
        .stderr(Stdio::null())
        .output()
        .ok()?;
    let text = String::from_utf8_lossy(&out.stdout).into_owned();
    let field = |k: &str| {
        text.split_whitespace()
            .find_map(|w| w.strip_prefix(k))
            .map(str::to_string)
    };
    Some((field("JobState=")?, field("Reason=").unwrap_or_default()))
}

/// The cause of an interrupt in a Slurm array task: `Some(failure)` when Slurm is ending
/// the task for a limit (its time limit, memory), `None` when it was cancelled or
/// requeued (not the point's fault: it runs again).
fn slurm_interrupt_cause() -> Option<String> {
    let (state, reason) = slurm_job_state()?;
    let limit = ["TIMEOUT", "OUT_OF_MEMORY", "DEADLINE"]
        .iter()
        .any(|s| state.starts_with(s))
        || reason.contains("TimeLimit");
    limit.then(|| {
        format!(
            "Slurm ended the array task {}: job state {state}{}",
            std::env::var("SLURM_JOB_ID").unwrap_or_default(),
            if reason.is_empty() || reason == "None" {
                String::new()
            } else {
                format!(", reason {reason}")
            }
        )
    })
}

impl Runner {
    /// The description of this runner written into the claims it takes.
    fn owner(&self) -> Value {
        json!({
            "pid": std::process::id(),
            "host": host_name(),
            "backend": self.backend,
            "since_unix": unix_now(),
        })
    }

    /// Runs one point and records it (unless another runner has it, or the sweep is
    /// interrupted); `Err` only when the results directory can't be written. `judge` says
    /// whether a recorded result is current (it is checked again once the claim is held).
    pub fn run(
        &self,
        plan: &Plan,
        p: &PlanPoint,
        judge: &mut dyn FnMut(&PlanPoint) -> bool,
    ) -> Result<(Outcome, f64), String> {
        let claim = match Claim::take(&self.dir, &p.id, &self.owner())? {
            Ok(c) => c,
            Err(owner) => return Ok((Outcome::Claimed(owner), 0.0)),
        };
        if judge(p) {
            return Ok((Outcome::DoneElsewhere, 0.0));
        }
        clean_leftovers(&self.dir, &p.id);
        let r = self.run_claimed(plan, p);
        drop(claim);
        r
    }

    fn run_claimed(&self, plan: &Plan, p: &PlanPoint) -> Result<(Outcome, f64), String> {
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
        let open = |f: &Path| File::create(f).map_err(|e| format!("{}: {e}", f.display()));
        let kernel = &plan.kernels[p.kernel];
        // The inputs as they are now (the executable's content is checked: it is named by
        // it), then the run.
        let elf_now = std::fs::read(&kernel.elf)
            .map(|b| sha256_hex(&b))
            .map_err(|e| format!("{}: {e}", kernel.elf))?;
        if elf_now != kernel.elf_sha256 {
            return Err(format!(
                "{}: the kernel executable changed after the sweep built it (SHA-256 {elf_now}, built {})",
                kernel.elf, kernel.elf_sha256
            ));
        }
        let named = named_files(p);
        let mut command = p.command(plan);
        command.extend([
            "--stats-json".into(),
            stats_path.display().to_string(),
            "--host-threads".into(),
            self.host_threads.to_string(),
            "--scene-cache".into(),
            scene_cache(&self.dir, &self.exe_sha256)
                .display()
                .to_string(),
        ]);
        let started = unix_now();
        let clock = Instant::now();
        let oom_before = oom_kills();
        let child = Command::new(&self.exe)
            .args(&command)
            .env(PARENT_ENV, pid.to_string())
            .stdin(Stdio::null())
            .stdout(open(&out_path)?)
            .stderr(open(&err_path)?)
            .spawn()
            .map_err(|e| format!("{}: {e}", self.exe.display()))?;
        let cpid = child.id();
        log_event(&self.dir, &format!("start {} pid={pid} child={cpid}", p.id));
        let mut stop: Option<Stop> = None;
        let mut peak_polled = 0u64;
        let mut nap = Duration::from_millis(1);
        let ended = loop {
            if let Some(e) = try_reap(cpid)? {
                break e;
            }
            let kill = |child: &std::process::Child| {
                // SAFETY: kill(2) on our unreaped child's pid: it can only reach that process.
                unsafe { libc::kill(child.id() as libc::pid_t, libc::SIGKILL) };
            };
            if stop.is_none() {
                let wall = clock.elapsed().as_secs_f64();
                let rss = resident_bytes(cpid).unwrap_or(0);
                peak_polled = peak_polled.max(rss);
                if interrupted() {
                    stop = Some(Stop::Interrupt);
                } else if self.limits.time_s.is_some_and(|t| wall > t as f64) {
                    stop = Some(Stop::Time(wall));
                } else if self.limits.memory_bytes.is_some_and(|m| rss > m) {
                    stop = Some(Stop::Memory(rss));
                }
                if stop.is_some() {
                    kill(&child);
                }
            }
            std::thread::sleep(nap);
            nap = (nap * 2).min(Duration::from_millis(50));
        };
        drop(child);
        let wall = clock.elapsed().as_secs_f64();
        let status = ended.status;
        let max_rss = ended.max_rss_bytes.max(peak_polled);
        let status_text = match (status.code(), status.signal()) {
            (Some(c), _) => format!("exit status {c}"),
            (None, Some(s)) => format!("killed by {}", signal_name(s)),
            _ => "ended".into(),
        };
        // A signal the sweep's user sent to the whole process group (Ctrl-C) reaches the
        // point and the sweep at once: give the sweep's handler a moment to see it.
        if matches!(
            status.signal(),
            Some(libc::SIGINT | libc::SIGTERM | libc::SIGHUP)
        ) {
            std::thread::sleep(Duration::from_millis(200));
        }
        // Why it died, if it did; `None` = it ran to its end (ok, or failed on its own).
        let mut death: Option<String> = match &stop {
            Some(Stop::Time(w)) => Some(format!(
                "time limit of {} s exceeded (stopped after {w:.1} s)",
                self.limits.time_s.unwrap_or(0)
            )),
            Some(Stop::Memory(rss)) => Some(format!(
                "memory limit of {} exceeded (resident {}; stopped)",
                show_mib(self.limits.memory_bytes.unwrap_or(0)),
                show_mib(*rss)
            )),
            Some(Stop::Interrupt) => None,
            None => None,
        };
        // Interrupted, unless the point finished first (its result stands).
        let user_stop = (matches!(stop, Some(Stop::Interrupt)) || interrupted())
            && !(status.success() && stop.is_none());
        if user_stop && death.is_none() {
            // In a Slurm array task, SIGTERM also comes when Slurm ends the task for its
            // time limit: that is the point's failure, not the user's interrupt.
            let slurm = (self.backend["backend"] == "slurm")
                .then(slurm_interrupt_cause)
                .flatten();
            match slurm {
                Some(cause) => death = Some(cause),
                None => {
                    cleanup();
                    log_event(&self.dir, &format!("interrupted {} ({status_text})", p.id));
                    return Ok((Outcome::Interrupted(status_text), wall));
                }
            }
        }
        if death.is_none() {
            if let Some(sig) = status.signal() {
                let oom = oom_kills()
                    .zip(oom_before)
                    .is_some_and(|(after, before)| after > before);
                death = Some(match sig {
                    libc::SIGKILL if oom => format!(
                        "killed by SIGKILL while the kernel's OOM killer was killing processes (the host ran out of memory; peak resident {})",
                        show_mib(max_rss)
                    ),
                    libc::SIGKILL => "killed by SIGKILL from outside the sweep (kill -9, a container's memory limit or a scheduler)".into(),
                    libc::SIGXCPU => "CPU time limit (RLIMIT_CPU) exceeded: killed by SIGXCPU".into(),
                    s => format!("killed by {} from outside the sweep", signal_name(s)),
                });
            } else if let Some(m) = self.limits.memory_bytes.filter(|&m| max_rss > m) {
                death = Some(format!(
                    "memory limit of {} exceeded (peak resident {})",
                    show_mib(m),
                    show_mib(max_rss)
                ));
            }
        }
        let stats: Option<Value> = (status.success() && death.is_none())
            .then(|| std::fs::read_to_string(&stats_path).ok())
            .flatten()
            .and_then(|t| serde_json::from_str(&t).ok());
        let (outcome, error, stderr) = match (&stats, &death) {
            (Some(_), _) => (Outcome::Ok, Value::Null, Value::Null),
            (None, _) => {
                let stderr = tail(&err_path, STDERR_KEEP);
                let err = match &death {
                    Some(d) => d.clone(),
                    None if status.success() => {
                        format!("no statistics were written ({status_text})")
                    }
                    None => error_line(&stderr, &status_text),
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
        // What it ran with: the files it named, as they were when it started, and the
        // scene's files as `trax run` read them.
        let mut files = named;
        if let Some(sf) = stats
            .as_ref()
            .and_then(|s| s["inputs"]["scene_files"].as_array())
        {
            for f in sf {
                if !files.contains(f) {
                    files.push(f.clone());
                }
            }
        }
        let config = match &stats {
            Some(s) => s["chip"].clone(),
            None => p
                .chip()
                .ok()
                .and_then(|c| serde_json::to_value(c).ok())
                .unwrap_or(Value::Null),
        };
        let mut command_line = vec![self.exe.display().to_string()];
        command_line.extend(command);
        let record = json!({
            "format": POINT_FORMAT,
            "id": p.id,
            "status": if stats.is_some() { "ok" } else { "failed" },
            "params": p.params,
            "inputs": {
                "trax_sha256": self.exe_sha256,
                "kernel_elf_sha256": kernel.elf_sha256,
                "files": files,
            },
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
            "limits": {
                "time_s": self.limits.time_s,
                "memory_bytes": self.limits.memory_bytes,
            },
            "started_unix": started,
            "wall_seconds": wall,
            "max_rss_bytes": max_rss,
            "exit": status_text,
            "death": death,
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

/// The scene cache of the points a trax executable runs in a results directory:
/// `DIR/scenes/<its SHA-256 prefix>` (points that share a scene parse it once; the cache
/// file of a scene is checked against the scene's files before it is used).
pub fn scene_cache(dir: &Path, exe_sha256: &str) -> PathBuf {
    dir.join("scenes")
        .join(&exe_sha256[..exe_sha256.len().min(16)])
}

/// The files a point names (its chip config file, scene file and `.view`/`.light`), with
/// their SHA-256 now (`{"path", "sha256"}`, or `{"path", "absent": true}`).
pub fn named_files(p: &PlanPoint) -> Vec<Value> {
    let mut paths: Vec<String> = Vec::new();
    if trax_emulator::timing::ChipConfig::preset(&p.config).is_none() {
        paths.push(p.config.clone());
    }
    let arg = |flag: &str| {
        p.args
            .iter()
            .position(|a| a == flag)
            .and_then(|i| p.args.get(i + 1))
            .cloned()
    };
    if let Some(scene) = arg("--scene") {
        let (_, inner, is_file) = trax_assembler::scene::split_spec(&scene);
        if is_file {
            paths.push(inner.to_string());
        }
    }
    paths.extend(arg("--view"));
    paths.extend(arg("--light"));
    paths
        .into_iter()
        .map(|path| match std::fs::read(&path) {
            Ok(b) => json!({ "path": path, "sha256": sha256_hex(&b) }),
            Err(_) => json!({ "path": path, "absent": true }),
        })
        .collect()
}

/// Checks recorded input files against the file system, each distinct one once.
#[derive(Default)]
pub struct FileCheck {
    seen: HashMap<String, Result<(), String>>,
}

impl FileCheck {
    /// `Err(what differs)` for the first recorded file that is not as it was.
    pub fn check(&mut self, files: &[Value]) -> Result<(), String> {
        for f in files {
            let key = f.to_string();
            let r =
                self.seen
                    .entry(key)
                    .or_insert_with(|| match trax::stats::source_from_json(f) {
                        Some(s) => s.holds(),
                        None => Err(format!("unreadable input record {f}")),
                    });
            r.clone()?;
        }
        Ok(())
    }
}
