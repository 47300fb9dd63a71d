//! `trax sweep --slurm` end to end on a real Slurm cluster: the sweep is submitted with
//! sbatch as a job array, and the table `trax sweep collect` merges equals the one the local
//! backend gives (but for host wall time). Needs a cluster: `.ci/slurm-up` starts a one-node
//! one on this machine (`.ci/run` does). Every wait is bounded.

use std::collections::BTreeMap;
use std::path::Path;
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

mod common;
use common::{root, text, tmp_path, trax_command};

/// Runs a command with a time limit (killed after it); `None` if it could not start or ran
/// too long.
fn bounded(cmd: &str, args: &[&str], limit: Duration) -> Option<Output> {
    let mut child = Command::new(cmd)
        .args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .ok()?;
    let start = Instant::now();
    loop {
        if child.try_wait().ok()?.is_some() {
            return child.wait_with_output().ok();
        }
        if start.elapsed() > limit {
            let _ = child.kill();
            let _ = child.wait();
            return None;
        }
        std::thread::sleep(Duration::from_millis(50));
    }
}

/// Fails with what to do when no cluster answers.
fn require_cluster() {
    let out = bounded("sinfo", &["-h", "-o", "%T"], Duration::from_secs(15));
    let states = out
        .as_ref()
        .filter(|o| o.status.success())
        .map(|o| text(&o.stdout))
        .unwrap_or_default();
    let usable = states
        .lines()
        .any(|s| ["idle", "mixed", "allocated", "completing"].contains(&s.trim()));
    if !usable {
        let why = match &out {
            None => "sinfo is missing or did not answer within 15 s".to_string(),
            Some(o) => format!(
                "sinfo: {}{}",
                text(&o.stdout).trim(),
                text(&o.stderr).trim()
            ),
        };
        panic!(
            "no Slurm cluster reachable ({why}): start the one-node test cluster with `.ci/slurm-up` (as root; .ci/run does this)"
        );
    }
}

fn trax(args: &[&str]) -> Output {
    trax_command()
        .args(args)
        .stdin(Stdio::null())
        .output()
        .expect("run trax")
}

/// The table without the host wall-time column, by id.
fn table(path: &Path) -> (Vec<String>, BTreeMap<String, Vec<String>>) {
    let mut r = csv::Reader::from_path(path).unwrap();
    let header: Vec<String> = r.headers().unwrap().iter().map(str::to_string).collect();
    let wall = header.iter().position(|h| h == "wall_seconds").unwrap();
    let mut rows = BTreeMap::new();
    for rec in r.records() {
        let mut row: Vec<String> = rec.unwrap().iter().map(str::to_string).collect();
        row.remove(wall);
        rows.insert(row[0].clone(), row);
    }
    let mut header = header;
    header.remove(wall);
    (header, rows)
}

#[test]
fn slurm_sweep_collects_the_same_table_as_a_local_one() {
    require_cluster();
    let dir = tmp_path("sweep-slurm");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let kernel = root().join("examples/gradient.rs");
    let f = dir.join("sweep.toml");
    std::fs::write(
        &f,
        format!(
            "name = \"slurm-test\"\nkernel = {:?}\nwidth = 12\nheight = 10\n\n[axes]\nmode = [\"functional\", \"timing\"]\ntms = [1, 2, 3]\n\n[slurm]\nper_task = 2\nmax_running = 2\ntime = \"10:00\"\n",
            kernel.display().to_string()
        ),
    )
    .unwrap();
    let local = dir.join("local");
    let out = trax(&[
        "sweep",
        f.to_str().unwrap(),
        "--local",
        "-o",
        local.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));

    let remote = dir.join("slurm");
    let out = trax(&[
        "sweep",
        f.to_str().unwrap(),
        "--slurm",
        "-o",
        remote.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let job = text(&out.stdout).trim().to_string();
    assert!(
        !job.is_empty() && job.chars().all(|c| c.is_ascii_digit()),
        "job id {job:?}; {}",
        text(&out.stderr)
    );
    let script = std::fs::read_to_string(remote.join("slurm/sub-1.sbatch")).unwrap();
    assert!(script.contains("#SBATCH --array=0-2%2"), "{script}");
    assert!(script.contains("#SBATCH --time=10:00"), "{script}");
    // Wait (bounded) until the job has left the queue.
    let start = Instant::now();
    loop {
        let q = bounded(
            "squeue",
            &["-h", "-j", &job, "-o", "%i %T"],
            Duration::from_secs(15),
        );
        let listed = q
            .as_ref()
            .filter(|o| o.status.success())
            .map(|o| text(&o.stdout).trim().to_string());
        // squeue forgets a finished job (or says it is invalid): either way it is done.
        if q.as_ref().is_some_and(|o| !o.status.success()) || listed.as_deref() == Some("") {
            break;
        }
        if start.elapsed() > Duration::from_secs(300) {
            let logs: String = std::fs::read_dir(remote.join("slurm/logs"))
                .map(|d| {
                    d.filter_map(|e| std::fs::read_to_string(e.ok()?.path()).ok())
                        .collect()
                })
                .unwrap_or_default();
            let _ = bounded("scancel", &[&job], Duration::from_secs(15));
            panic!("job {job} still queued after 300 s: {listed:?}\nlogs:\n{logs}");
        }
        std::thread::sleep(Duration::from_millis(500));
    }
    let out = trax(&["sweep", "collect", remote.to_str().unwrap()]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert!(
        text(&out.stderr).contains("6 points: 6 ok"),
        "{}",
        text(&out.stderr)
    );

    let (lh, lrows) = table(&local.join("results.csv"));
    let (rh, rrows) = table(&remote.join("results.csv"));
    assert_eq!(lh, rh);
    assert_eq!(lrows.len(), 6);
    assert_eq!(lrows, rrows);
    // Slurm ran them: the records name the job.
    for id in rrows.keys() {
        let rec: serde_json::Value = serde_json::from_str(
            &std::fs::read_to_string(remote.join(format!("points/{id}.json"))).unwrap(),
        )
        .unwrap();
        assert_eq!(rec["runner"]["backend"]["backend"], "slurm");
        assert_eq!(rec["runner"]["backend"]["job"], job.as_str());
    }
    // Submitting again has nothing to do.
    let out = trax(&[
        "sweep",
        f.to_str().unwrap(),
        "--slurm",
        "-o",
        remote.to_str().unwrap(),
    ]);
    assert!(out.status.success());
    assert!(
        text(&out.stderr).contains("nothing to submit"),
        "{}",
        text(&out.stderr)
    );
}

/// Waits (bounded) until Slurm has forgotten job `job` (it finished).
fn wait_for_job(job: &str, logs: &Path) {
    let start = Instant::now();
    loop {
        let q = bounded(
            "squeue",
            &["-h", "-j", job, "-o", "%i %T"],
            Duration::from_secs(15),
        );
        let listed = q
            .as_ref()
            .filter(|o| o.status.success())
            .map(|o| text(&o.stdout).trim().to_string());
        if q.as_ref().is_some_and(|o| !o.status.success()) || listed.as_deref() == Some("") {
            return;
        }
        if start.elapsed() > Duration::from_secs(300) {
            let text: String = std::fs::read_dir(logs)
                .map(|d| {
                    d.filter_map(|e| std::fs::read_to_string(e.ok()?.path()).ok())
                        .collect()
                })
                .unwrap_or_default();
            let _ = bounded("scancel", &[job], Duration::from_secs(15));
            panic!("job {job} still queued after 300 s: {listed:?}\nlogs:\n{text}");
        }
        std::thread::sleep(Duration::from_millis(500));
    }
}

/// One writer per point: a local sweep run in the folder of a running Slurm array (which
/// used to run every point a second time: the array tasks took no lock) shares the points
/// with it through per-point claims; every point runs exactly once.
#[test]
fn a_local_sweep_beside_its_slurm_array_runs_each_point_once() {
    require_cluster();
    let dir = tmp_path("sweep-slurm-both");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let kernel = root().join("examples/mandelbrot.rs");
    let f = dir.join("sweep.toml");
    // 8 points of about a second each.
    std::fs::write(
        &f,
        format!(
            "name = \"both\"\nkernel = {:?}\nmode = \"functional\"\nwidth = 512\nheight = 512\n\n[axes]\n\"label.n\" = [1, 2, 3, 4, 5, 6, 7, 8]\n\n[slurm]\nmax_running = 2\ntime = \"10:00\"\n",
            kernel.display().to_string()
        ),
    )
    .unwrap();
    let res = dir.join("res");
    let out = trax(&[
        "sweep",
        f.to_str().unwrap(),
        "--slurm",
        "-o",
        res.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let job = text(&out.stdout).trim().to_string();
    // Once the array has started a point, run the same sweep here.
    let start = Instant::now();
    while !std::fs::read_to_string(res.join("events.log")).is_ok_and(|l| l.contains(" start ")) {
        assert!(
            start.elapsed() < Duration::from_secs(120),
            "the array started no point"
        );
        std::thread::sleep(Duration::from_millis(100));
    }
    let local = trax(&[
        "sweep",
        f.to_str().unwrap(),
        "-o",
        res.to_str().unwrap(),
        "-j",
        "1",
    ]);
    let err = text(&local.stderr);
    assert!(local.status.success(), "{err}");
    wait_for_job(&job, &res.join("slurm/logs"));
    let log = std::fs::read_to_string(res.join("events.log")).unwrap();
    let mut done: BTreeMap<&str, usize> = BTreeMap::new();
    for l in log.lines() {
        let w: Vec<&str> = l.split_whitespace().collect();
        if w.get(1) == Some(&"done") {
            *done.entry(w[2]).or_default() += 1;
        }
    }
    assert_eq!(done.len(), 8, "{log}");
    assert!(done.values().all(|&n| n == 1), "a point ran twice:\n{log}");
    // Both ran points (the local sweep started while the array had 7 or more to go, and
    // the array runs 2 at a time).
    let mut by: BTreeMap<String, usize> = BTreeMap::new();
    for id in done.keys() {
        let rec: serde_json::Value = serde_json::from_str(
            &std::fs::read_to_string(res.join(format!("points/{id}.json"))).unwrap(),
        )
        .unwrap();
        assert_eq!(rec["status"], "ok", "{rec}");
        *by.entry(
            rec["runner"]["backend"]["backend"]
                .as_str()
                .unwrap()
                .to_string(),
        )
        .or_default() += 1;
    }
    assert!(by.len() == 2, "runs by backend: {by:?}\n{err}");
    let out = trax(&["sweep", "status", res.to_str().unwrap()]);
    assert!(out.status.success(), "{}", text(&out.stdout));
    assert!(text(&out.stdout).contains("8 points: 8 done"));
}
