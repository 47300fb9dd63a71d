//! Where each point of a sweep stands ([`Judge::state`]): done, stale (a result whose
//! inputs changed since, and what changed), failed (and why), running (and where) or
//! pending; and `trax sweep status DIR`, which reports them.
//!
//! A result is current when everything that could change it is as it was when it ran:
//! the trax executable (SHA-256), the kernel executable the sweep builds now (SHA-256: it
//! covers the source, every file it includes and the compiler), the files the point
//! named (chip config file, scene file, `.view`, `.light`) and the files its scene was read
//! from (MTL libraries, `.objl` members; files looked for and not found, which must still
//! be missing), each by SHA-256, and the `trax run` arguments it ran with. Anything else a
//! point's result depends on (chip presets, built-in scenes, the prelude, defaults) is part
//! of the trax executable.

use std::path::Path;
use std::process::ExitCode;

use serde_json::Value;

use super::plan::{build_kernel, Plan, PlanPoint};
use super::runner::{point_path, Claim, FileCheck};

/// Where a point stands.
#[derive(Debug, Clone, PartialEq)]
pub enum State {
    /// Not run (with a note when an earlier runner died running it).
    Pending(Option<String>),
    /// A runner holds its claim now (who).
    Running(String),
    /// Its result is current.
    Done,
    /// It has a result (ok or failed) whose inputs changed since: what changed.
    Stale(Vec<String>),
    /// It failed with these inputs: the error.
    Failed(String),
}

impl State {
    /// The `status` word of `results.csv`.
    pub fn word(&self) -> &'static str {
        match self {
            State::Pending(_) => "pending",
            State::Running(_) => "running",
            State::Done => "ok",
            State::Stale(_) => "stale",
            State::Failed(_) => "failed",
        }
    }
}

/// Judges points against the inputs as they are now.
pub struct Judge<'a> {
    plan: &'a Plan,
    dir: &'a Path,
    exe_sha256: String,
    /// The kernels' executables as built now (`Err`: can't be built now), by plan index.
    elf_now: Vec<Result<String, String>>,
    files: FileCheck,
}

impl<'a> Judge<'a> {
    /// A judge for `plan` (its kernels as just built) in `dir`, for trax executable
    /// `exe_sha256`.
    pub fn new(plan: &'a Plan, dir: &'a Path, exe_sha256: &str) -> Judge<'a> {
        Judge {
            plan,
            dir,
            exe_sha256: exe_sha256.to_string(),
            elf_now: plan
                .kernels
                .iter()
                .map(|k| Ok(k.elf_sha256.clone()))
                .collect(),
            files: FileCheck::default(),
        }
    }

    /// A judge whose kernels could not all be built now (their errors).
    pub fn with_kernel_errors(mut self, errors: Vec<Option<String>>) -> Judge<'a> {
        for (i, e) in errors.into_iter().enumerate() {
            if let (Some(e), Some(slot)) = (e, self.elf_now.get_mut(i)) {
                *slot = Err(e);
            }
        }
        self
    }

    /// The record of point `id`, if any (`Err` when it can't be read).
    pub fn record(&self, id: &str) -> Option<Result<Value, String>> {
        let path = point_path(self.dir, id);
        match std::fs::read_to_string(&path) {
            Ok(t) => Some(serde_json::from_str(&t).map_err(|e| format!("{}: {e}", path.display()))),
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => None,
            Err(e) => Some(Err(format!("{}: {e}", path.display()))),
        }
    }

    /// Where point `p` stands, and its record.
    pub fn state(&mut self, p: &PlanPoint) -> (State, Option<Value>) {
        if let Some(owner) = Claim::holder(self.dir, &p.id) {
            return (State::Running(owner), None);
        }
        self.recorded_state(p)
    }

    /// Where point `p` stands by its record alone, for the holder of its claim.
    pub fn recorded_state(&mut self, p: &PlanPoint) -> (State, Option<Value>) {
        match self.record(&p.id) {
            None => (
                State::Pending(
                    Claim::leftover(self.dir, &p.id)
                        .map(|o| format!("its last runner ({o}) ended without recording a result")),
                ),
                None,
            ),
            Some(Err(e)) => (State::Stale(vec![format!("unreadable record: {e}")]), None),
            Some(Ok(rec)) => {
                let why = self.changes(p, &rec);
                let state = if !why.is_empty() {
                    State::Stale(why)
                } else if rec["status"] == "ok" {
                    State::Done
                } else {
                    State::Failed(
                        rec["error"]
                            .as_str()
                            .unwrap_or("failed")
                            .lines()
                            .next()
                            .unwrap_or("failed")
                            .to_string(),
                    )
                };
                (state, Some(rec))
            }
        }
    }

    /// What changed since the point's recorded run (empty: nothing).
    fn changes(&mut self, p: &PlanPoint, rec: &Value) -> Vec<String> {
        let inputs = &rec["inputs"];
        if !inputs.is_object() {
            return vec!["recorded by an older trax, without its inputs".into()];
        }
        let short = |s: &str| s.chars().take(12).collect::<String>();
        let mut why = Vec::new();
        let trax = inputs["trax_sha256"].as_str().unwrap_or("");
        if trax != self.exe_sha256 {
            why.push(format!(
                "trax changed (it ran with executable {}, this is {})",
                short(trax),
                short(&self.exe_sha256)
            ));
        }
        let kernel = &self.plan.kernels[p.kernel];
        let elf = inputs["kernel_elf_sha256"].as_str().unwrap_or("");
        match &self.elf_now[p.kernel] {
            Ok(now) if now == elf => {}
            Ok(now) => why.push(format!(
                "kernel {} builds differently now: it, a file it includes or the compiler changed (executable {} -> {})",
                kernel.source,
                short(elf),
                short(now)
            )),
            Err(e) => why.push(format!("kernel {} can't be built now: {e}", kernel.source)),
        }
        let files: Vec<Value> = inputs["files"].as_array().cloned().unwrap_or_default();
        if let Err(what) = self.files.check(&files) {
            let mut s = format!("input {what}");
            if what.starts_with(&p.config) {
                s += &config_diff(p, &rec["config"]);
            }
            why.push(s);
        }
        let ran: Vec<String> = rec["command"]
            .as_array()
            .map(|c| {
                c.iter()
                    .filter_map(|v| v.as_str().map(str::to_string))
                    .collect()
            })
            .unwrap_or_default();
        // The command after the executable: the point's own arguments, then the
        // runner's (statistics file, host threads, scene cache).
        let now = p.command(self.plan);
        let ran_args = ran.get(1..).unwrap_or(&[]);
        if !ran_args.starts_with(&now) && why.is_empty() {
            why.push(format!(
                "it runs with other arguments now: `{}` (ran `{}`)",
                now.join(" "),
                ran_args.join(" ")
            ));
        }
        why
    }
}

/// ` (field: old -> new, ...)`: how a point's chip config differs now from the recorded.
fn config_diff(p: &PlanPoint, recorded: &Value) -> String {
    let Ok(now) = p
        .chip()
        .map_err(|e| e.to_string())
        .and_then(|c| serde_json::to_value(c).map_err(|e| e.to_string()))
    else {
        return " (its chip config does not load now)".into();
    };
    let mut diffs = Vec::new();
    diff_leaves("", recorded, &now, &mut diffs);
    if diffs.is_empty() {
        return " (the chip config it makes is the same)".into();
    }
    let n = diffs.len();
    diffs.truncate(4);
    let more = if n > 4 {
        format!(", and {} more", n - 4)
    } else {
        String::new()
    };
    format!(" (chip config: {}{more})", diffs.join(", "))
}

fn diff_leaves(path: &str, a: &Value, b: &Value, out: &mut Vec<String>) {
    match (a, b) {
        (Value::Object(x), Value::Object(y)) => {
            let keys: std::collections::BTreeSet<&String> = x.keys().chain(y.keys()).collect();
            for k in keys {
                let sub = if path.is_empty() {
                    k.clone()
                } else {
                    format!("{path}.{k}")
                };
                diff_leaves(
                    &sub,
                    x.get(k).unwrap_or(&Value::Null),
                    y.get(k).unwrap_or(&Value::Null),
                    out,
                );
            }
        }
        _ if a != b => out.push(format!("{path} {a} -> {b}")),
        _ => {}
    }
}

/// Loads a results directory's plan and builds its kernels as they are now (into its
/// `build/`, named by content, so nothing a running point reads changes); a kernel that
/// can't be built is an error of its points, not of the whole.
pub fn current_plan(dir: &Path, exe: &Path) -> Result<(Plan, Vec<Option<String>>), String> {
    // Absolute, as the sweep that ran the points named the kernels' executables (a
    // relative `DIR` would make every point's command differ from the one it ran).
    let dir = &std::path::absolute(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let mut plan = Plan::load(dir)?;
    let errors = plan
        .kernels
        .iter_mut()
        .map(|k| {
            build_kernel(k, exe, &dir.join("build"), true)
                .err()
                .map(|e| e.lines().last().unwrap_or("").trim().to_string())
        })
        .collect();
    Ok((plan, errors))
}

/// Counts of points by state.
#[derive(Debug, Default)]
pub struct Counts {
    /// Done.
    pub done: u64,
    /// Stale.
    pub stale: u64,
    /// Failed.
    pub failed: u64,
    /// Running.
    pub running: u64,
    /// Pending.
    pub pending: u64,
}

/// `trax sweep status DIR`: every point's state, the ones not done listed with why.
pub fn status(dir: &Path, all: bool) -> Result<ExitCode, String> {
    let (exe, exe_sha256) = super::this_exe()?;
    let (plan, errors) = current_plan(dir, &exe)?;
    let mut judge = Judge::new(&plan, dir, &exe_sha256).with_kernel_errors(errors);
    let mut c = Counts::default();
    const SHOWN: u64 = 20;
    let mut lines: [Vec<String>; 4] = Default::default();
    for p in plan.points() {
        let p = p?;
        let (state, _) = judge.state(&p);
        let (slot, n, text) = match &state {
            State::Done => {
                c.done += 1;
                continue;
            }
            State::Stale(why) => {
                c.stale += 1;
                (0, c.stale, format!("stale: {}", why.join("; ")))
            }
            State::Failed(e) => {
                c.failed += 1;
                (1, c.failed, format!("failed: {e}"))
            }
            State::Running(o) => {
                c.running += 1;
                (2, c.running, format!("running: {o}"))
            }
            State::Pending(note) => {
                c.pending += 1;
                (
                    3,
                    c.pending,
                    match note {
                        Some(n) => format!("pending: {n}"),
                        None => "pending".into(),
                    },
                )
            }
        };
        if all || n <= SHOWN {
            lines[slot].push(format!("{} {text}", p.id));
        }
    }
    let total = c.done + c.stale + c.failed + c.running + c.pending;
    println!(
        "{total} points: {} done, {} stale, {} failed, {} running, {} pending ({})",
        c.done,
        c.stale,
        c.failed,
        c.running,
        c.pending,
        dir.display()
    );
    for (l, n) in lines.iter().zip([c.stale, c.failed, c.running, c.pending]) {
        for line in l {
            println!("{line}");
        }
        if n > l.len() as u64 {
            println!(
                "... and {} more (--all lists every one)",
                n - l.len() as u64
            );
        }
    }
    let copy = dir.join("sweep.toml");
    if let (Ok(a), Ok(b)) = (std::fs::read(&plan.sweep_file), std::fs::read(&copy)) {
        if a != b {
            println!(
                "note: {} changed since it was planned: run the sweep to plan it anew",
                plan.sweep_file
            );
        }
    }
    Ok(if total == c.done {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    })
}
