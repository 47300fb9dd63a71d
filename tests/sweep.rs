//! `trax sweep` on this machine, `trax run --set`, and `trax plot`: sweep-file errors name
//! the field and line; a local sweep's table matches independent `trax run`s; failed points
//! are recorded without stopping the sweep; a killed sweep resumes without running a
//! finished point twice or losing one; charts have their title, labels and legend.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

mod common;
use common::{fresh_dir, read_json, root, text, trax_command};

/// A fresh scratch directory.
fn scratch(name: &str) -> PathBuf {
    fresh_dir(&format!("sweep-{name}"))
}

fn trax(args: &[&str]) -> Output {
    trax_command()
        .args(args)
        .stdin(Stdio::null())
        .output()
        .expect("run trax")
}

fn gradient() -> String {
    root().join("examples/gradient.rs").display().to_string()
}

/// Writes a sweep file; returns its path.
fn sweep_file(dir: &Path, body: &str) -> PathBuf {
    let f = dir.join("sweep.toml");
    std::fs::write(&f, body).unwrap();
    f
}

/// A parsed CSV: header and rows.
fn read_csv(path: &Path) -> (Vec<String>, Vec<BTreeMap<String, String>>) {
    let mut r = csv::Reader::from_path(path).unwrap();
    let header: Vec<String> = r.headers().unwrap().iter().map(str::to_string).collect();
    let rows = r
        .records()
        .map(|rec| {
            let rec = rec.unwrap();
            assert_eq!(rec.len(), header.len(), "ragged row in {}", path.display());
            header
                .iter()
                .cloned()
                .zip(rec.iter().map(str::to_string))
                .collect()
        })
        .collect();
    (header, rows)
}

fn sha256sum(path: &Path) -> String {
    let out = Command::new("sha256sum").arg(path).output().unwrap();
    text(&out.stdout)
        .split_whitespace()
        .next()
        .unwrap()
        .to_string()
}

/// Runs the sweep file `body` in `dir` (results in `dir/results`): the process output, the
/// results directory and the rows of its `results.csv`.
fn sweep_rows(dir: &Path, body: &str) -> (Output, PathBuf, Vec<BTreeMap<String, String>>) {
    let f = sweep_file(dir, body);
    let out_dir = dir.join("results");
    let out = trax(&[
        "sweep",
        f.to_str().unwrap(),
        "-o",
        out_dir.to_str().unwrap(),
    ]);
    let (_, rows) = read_csv(&out_dir.join("results.csv"));
    (out, out_dir, rows)
}

#[test]
fn bad_sweep_files_name_the_field_and_line() {
    let dir = scratch("errors");
    let k = gradient();
    // (file body, expected "file:line" position, expected field, expected text)
    let cases: &[(String, &str, &str, &str)] = &[
        (
            format!("kernel = {k:?}\nwidht = 4\n"),
            ":2:",
            "`widht`",
            "unknown parameter",
        ),
        (
            format!("kernel = {k:?}\n[axes]\nmemory.l2.capcity_bytes = [1, 2]\n"),
            ":3:",
            "`memory.l2.capcity_bytes`",
            "unknown field `capcity_bytes`",
        ),
        (
            format!("kernel = {k:?}\n\n[axes]\ntms = []\n"),
            ":4:",
            "`tms`",
            "empty axis",
        ),
        (
            format!("kernel = {k:?}\n[axes]\nwidth = [8, \"wide\"]\n"),
            ":3:",
            "`width`",
            "type mismatch",
        ),
        (
            format!("kernel = {k:?}\n[axes]\ntms = [1, \"two\"]\n"),
            ":3:",
            "`tms`",
            "invalid type: string \"two\"",
        ),
        (
            format!("kernel = {k:?}\n[axes]\ntms = [1,\n  0]\n"),
            ":4:",
            "`tms`",
            "tms = 0 must be in 1..=4096",
        ),
        (
            format!("kernel = {k:?}\n[axes]\ntms = 4\n"),
            ":3:",
            "`tms`",
            "an axis is a list of values",
        ),
        (
            format!("kernel = {k:?}\nmode = \"fast\"\n"),
            ":2:",
            "`mode`",
            "not one of timing, functional",
        ),
        (
            format!("kernel = {k:?}\ntms = 2\n[axes]\ntms = [1, 2]\n"),
            ":4:",
            "`tms`",
            "given twice (also at line 2)",
        ),
        (
            format!("kernel = {k:?}\n[slurm]\npartiton = \"x\"\n"),
            ":3:",
            "`slurm.partiton`",
            "unknown field",
        ),
        (
            format!("kernel = {k:?}\n[axes]\ntms = [1]\n[[plot]]\nx = \"tms\"\ny = \"fsp\"\n"),
            ":4:",
            "`plot[0].y`",
            "not a metric",
        ),
        (
            format!("kernel = {k:?}\n[axes\ntms = [1]\n"),
            ":2:",
            "",
            "invalid table header",
        ),
        (
            "kernel = \"no-such-kernel.rs\"\n".to_string(),
            ":1:",
            "`kernel`",
            "no such file",
        ),
        (
            format!("kernel = {k:?}\nsample = 5\n"),
            ":2:",
            "`sample`",
            "5 is out of range 10..=",
        ),
        (
            format!("kernel = {k:?}\n[axes]\nsample_warmup = [1000, 2000]\n"),
            ":3:",
            "`sample_warmup`",
            "needs `sample = N`",
        ),
        (
            format!("kernel = {k:?}\nmode = \"functional\"\nsample = 10\n"),
            ":3:",
            "`sample`",
            "a sampled run is a timing run",
        ),
        (
            format!("kernel = {k:?}\nsample = 10\nsample_window = 1500\n"),
            ":3:",
            "`sample_window`",
            "shorter than its warm-up (2000 cycles)",
        ),
    ];
    for (body, pos, field, want) in cases {
        let f = sweep_file(&dir, body);
        let out = trax(&["sweep", f.to_str().unwrap(), "--dry-run"]);
        let err = text(&out.stderr);
        assert!(!out.status.success(), "accepted:\n{body}");
        let at = format!("{}{pos}", f.display());
        assert!(
            err.contains(&at) && err.contains(field) && err.contains(want),
            "for\n{body}\nexpected {at} {field} {want:?}, got:\n{err}"
        );
        assert!(!err.contains("panicked"), "{err}");
    }
}

#[test]
fn run_set_overrides_config_fields_by_path() {
    let dir = scratch("set");
    let file = dir.join("chip.toml");
    std::fs::write(
        &file,
        "preset = \"tiny\"\ntms = 2\n[memory.l2]\ncapacity_bytes = 65536\nassociativity = 2\n",
    )
    .unwrap();
    let run = |extra: &[&str], json: &Path| {
        let mut args = vec![
            "run",
            "examples/gradient.rs",
            "--width",
            "12",
            "--height",
            "12",
            "--stats-json",
            json.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        let out = trax(&args);
        assert!(out.status.success(), "{}", text(&out.stderr));
        std::fs::read_to_string(json).unwrap()
    };
    let from_file = run(&["--config", file.to_str().unwrap()], &dir.join("a.json"));
    let from_set = run(
        &[
            "--set",
            "tms=2",
            "--set",
            "memory.l2.capacity_bytes=65536",
            "--set",
            "memory.l2.associativity=2",
        ],
        &dir.join("b.json"),
    );
    // The same chip, named after where it came from: the file (and its preset), or the
    // preset and its overrides.
    let doc = |text: &str| -> (serde_json::Value, String) {
        let mut v: serde_json::Value = serde_json::from_str(text).unwrap();
        let name = v["chip"]["name"].take();
        (v, name.as_str().unwrap_or_default().to_string())
    };
    let ((a, a_name), (b, b_name)) = (doc(&from_file), doc(&from_set));
    assert_eq!(a, b);
    assert!(a_name.ends_with("chip.toml (preset tiny)"), "{a_name}");
    assert_eq!(
        b_name,
        "tiny + 3 overrides (tms=2, memory.l2.capacity_bytes=65536, memory.l2.associativity=2)"
    );
    let out = trax(&["run", "examples/gradient.rs", "--set", "memory.l2.nope=1"]);
    assert!(!out.status.success());
    let err = text(&out.stderr);
    assert!(
        err.contains("memory.l2.nope") && err.contains("unknown field `nope`"),
        "{err}"
    );
}

/// The documented point id: SHA-256 of `trax-sweep-point/1\n` + sorted `name=value\n`
/// lines, first 16 hex digits (computed here with sha256sum).
fn documented_id(dir: &Path, params: &[(&str, &str)]) -> String {
    let mut sorted = params.to_vec();
    sorted.sort();
    let mut s = String::from("trax-sweep-point/1\n");
    for (k, v) in sorted {
        s.push_str(&format!("{k}={v}\n"));
    }
    let f = dir.join("canonical.txt");
    std::fs::write(&f, s).unwrap();
    sha256sum(&f)[..16].to_string()
}

#[test]
fn local_sweep_matches_independent_runs() {
    let dir = scratch("local");
    let k = gradient();
    let f = sweep_file(
        &dir,
        &format!(
            r#"
name = "small"
kernel = {k:?}
width = 12
height = 8

[axes]
mode = ["functional", "timing"]
tms = [1, 2]

[[plot]]
x = "tms"
y = "cycles"
where = {{ mode = "timing" }}
"#
        ),
    );
    let out_dir = dir.join("results");
    let out = trax(&[
        "sweep",
        f.to_str().unwrap(),
        "-o",
        out_dir.to_str().unwrap(),
        "-j",
        "2",
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let (header, rows) = read_csv(&out_dir.join("results.csv"));
    assert_eq!(
        &header[..5],
        ["id", "status", "mode", "tms", "kernel"],
        "{header:?}"
    );
    assert!(header.contains(&"cycles".to_string()) && header.contains(&"energy_j".to_string()));
    assert_eq!(header.last().unwrap(), "error");
    assert_eq!(rows.len(), 4);
    let order: Vec<(&str, &str)> = rows
        .iter()
        .map(|r| (r["mode"].as_str(), r["tms"].as_str()))
        .collect();
    assert_eq!(
        order,
        [
            ("functional", "1"),
            ("functional", "2"),
            ("timing", "1"),
            ("timing", "2")
        ]
    );
    for r in &rows {
        assert_eq!(r["status"], "ok", "{r:?}");
        // The documented id.
        let id = documented_id(
            &dir,
            &[
                ("config", "\"tiny\""),
                ("depth", "4"),
                ("height", "8"),
                ("kernel", &format!("{k:?}")),
                ("mode", &format!("{:?}", r["mode"])),
                ("opt_level", "2"),
                ("scene", "\"cornell\""),
                ("seed", "1"),
                ("spp", "1"),
                ("tms", &r["tms"]),
                ("width", "12"),
            ],
        );
        assert_eq!(r["id"], id, "{r:?}");
        // Against an independent `trax run` of the same point.
        let json = dir.join(format!("oracle-{}.json", r["id"]));
        let mut args = vec![
            "run",
            "examples/gradient.rs",
            "--width",
            "12",
            "--height",
            "8",
            "--tms",
            &r["tms"],
            "--stats-json",
            json.to_str().unwrap(),
        ];
        if r["mode"] == "functional" {
            args.push("--functional");
        }
        let o = trax(&args);
        assert!(o.status.success(), "{}", text(&o.stderr));
        let stats: serde_json::Value = read_json(&json);
        assert_eq!(
            r["instructions"],
            stats["instructions"].to_string(),
            "{r:?}"
        );
        if r["mode"] == "timing" {
            assert_eq!(r["cycles"], stats["cycles"].to_string());
            let e: f64 = r["energy_j"].parse().unwrap();
            assert_eq!(e, stats["timing"]["energy"]["total"].as_f64().unwrap());
            let dram: f64 = r["energy_dram_j"].parse().unwrap();
            assert_eq!(dram, stats["timing"]["energy"]["dram"].as_f64().unwrap());
        } else {
            assert_eq!(r["cycles"], "", "functional runs have no cycles");
        }
        // The point's record: full stats, exact config, version, kernel hashes.
        let rec: serde_json::Value = serde_json::from_str(
            &std::fs::read_to_string(out_dir.join("points").join(format!("{}.json", r["id"])))
                .unwrap(),
        )
        .unwrap();
        // The same document but for the inputs: the point ran the sweep's prebuilt ELF.
        let without_inputs = |v: &serde_json::Value| {
            let mut v = v.clone();
            v.as_object_mut().unwrap().remove("inputs");
            v
        };
        assert_eq!(without_inputs(&rec["stats"]), without_inputs(&stats));
        assert_eq!(rec["stats"]["inputs"]["kernel"], rec["command"][2]);
        assert_eq!(rec["stats"]["inputs"]["opt_level"], serde_json::Value::Null);
        assert_eq!(rec["config"]["tms"].to_string(), r["tms"]);
        assert_eq!(
            rec["config"]["name"],
            format!("tiny + 1 override (tms={})", r["tms"])
        );
        assert_eq!(rec["trax"]["version"], env!("CARGO_PKG_VERSION"));
        assert_eq!(
            rec["kernel"]["source_sha256"],
            sha256sum(&root().join("examples/gradient.rs"))
        );
        let elf = rec["command"][2].as_str().unwrap();
        assert_eq!(rec["kernel"]["elf_sha256"], sha256sum(Path::new(elf)));
    }
    // Dry runs list the same ids.
    let dry = trax(&["sweep", f.to_str().unwrap(), "--dry-run"]);
    let ids: BTreeSet<String> = text(&dry.stdout)
        .lines()
        .map(|l| l.split_whitespace().next().unwrap().to_string())
        .collect();
    let csv_ids: BTreeSet<String> = rows.iter().map(|r| r["id"].clone()).collect();
    assert_eq!(ids, csv_ids);
    // The sweep file's plot.
    let png = std::fs::read(out_dir.join("plots/cycles_vs_tms.png")).unwrap();
    assert_eq!(&png[1..4], b"PNG");
    let svg = std::fs::read_to_string(out_dir.join("plots/cycles_vs_tms.svg")).unwrap();
    assert!(svg.contains("Run time (cycles)"), "{svg}");
}

#[test]
fn a_failed_point_is_recorded_and_the_sweep_goes_on() {
    let dir = scratch("failed");
    let k = gradient();
    let (out, out_dir, rows) = sweep_rows(
        &dir,
        &format!(
            "kernel = {k:?}\nwidth = 8\nheight = 8\nmode = \"functional\"\n[axes]\nmax_instructions = [50, 1000000]\ntms = [1, 2]\n"
        ),
    );
    assert!(
        !out.status.success(),
        "a sweep with failed points exits non-zero"
    );
    assert!(
        text(&out.stderr).contains("2 point(s) failed"),
        "{}",
        text(&out.stderr)
    );
    assert_eq!(rows.len(), 4);
    for r in &rows {
        if r["max_instructions"] == "50" {
            assert_eq!(r["status"], "failed");
            assert!(r["error"].contains("instruction limit"), "{r:?}");
            assert_eq!(r["instructions"], "");
            let rec: serde_json::Value = serde_json::from_str(
                &std::fs::read_to_string(out_dir.join(format!("points/{}.json", r["id"]))).unwrap(),
            )
            .unwrap();
            assert!(rec["stderr"]
                .as_str()
                .unwrap()
                .contains("instruction limit"));
        } else {
            assert_eq!(r["status"], "ok", "{r:?}");
        }
    }
    // Failed points keep their record on a re-run, unless asked to retry.
    let f = dir.join("sweep.toml");
    let again = trax(&[
        "sweep",
        f.to_str().unwrap(),
        "-o",
        out_dir.to_str().unwrap(),
    ]);
    let err = text(&again.stderr);
    assert!(err.contains("4 of 4 points already done"), "{err}");
    let retry = trax(&[
        "sweep",
        f.to_str().unwrap(),
        "-o",
        out_dir.to_str().unwrap(),
        "--retry-failed",
    ]);
    let err = text(&retry.stderr);
    assert!(err.contains("running the other 2"), "{err}");
}

/// Ids and statuses of the finished points, with their files' contents.
fn finished(dir: &Path) -> BTreeMap<String, String> {
    let mut m = BTreeMap::new();
    for e in std::fs::read_dir(dir.join("points")).unwrap() {
        let p = e.unwrap().path();
        let name = p.file_name().unwrap().to_string_lossy().into_owned();
        if let Some(id) = name.strip_suffix(".json").filter(|n| !n.starts_with('.')) {
            m.insert(id.to_string(), std::fs::read_to_string(&p).unwrap());
        }
    }
    m
}

/// `trax run` processes a sweep process started (found by the environment variable).
fn children_of(pid: u32) -> Vec<u32> {
    let want = format!("TRAX_SWEEP_PARENT={pid}");
    std::fs::read_dir("/proc")
        .unwrap()
        .filter_map(|e| {
            let e = e.ok()?;
            let child: u32 = e.file_name().to_str()?.parse().ok()?;
            let env = std::fs::read(e.path().join("environ")).ok()?;
            env.split(|b| *b == 0)
                .any(|v| v == want.as_bytes())
                .then_some(child)
        })
        .collect()
}

#[test]
fn a_killed_sweep_resumes_without_repeating_or_losing_points() {
    let dir = scratch("resume");
    let k = gradient();
    // 60 points: 15 widths x 2 TM counts x 2 modes.
    let f = sweep_file(
        &dir,
        &format!(
            "name = \"resume\"\nkernel = {k:?}\nheight = 24\n[axes]\nmode = [\"functional\", \"timing\"]\ntms = [1, 2]\nwidth = [{}]\n",
            (0..15).map(|i| (16 + 2 * i).to_string()).collect::<Vec<_>>().join(", ")
        ),
    );
    let out_dir = dir.join("results");
    let args = [
        "sweep",
        f.to_str().unwrap(),
        "-o",
        out_dir.to_str().unwrap(),
        "-j",
        "2",
    ];
    let mut child = trax_command()
        .args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let pid = child.id();
    let start = Instant::now();
    loop {
        // Count finished results only, as the check after the kill does: the directory
        // also holds points being written (hidden temporary files), and counting those
        // let the kill come with 7 results done (seen on a fresh clone's `.ci/run`).
        let n = if out_dir.join("points").is_dir() {
            finished(&out_dir).len()
        } else {
            0
        };
        if n >= 8 {
            break;
        }
        assert!(
            child.try_wait().unwrap().is_none(),
            "the sweep ended before it could be killed"
        );
        assert!(start.elapsed() < Duration::from_secs(120), "no progress");
        std::thread::sleep(Duration::from_millis(20));
    }
    child.kill().unwrap(); // SIGKILL: no chance to clean up
    child.wait().unwrap();
    // Its running points end by themselves (they watch their parent).
    let t = Instant::now();
    while !children_of(pid).is_empty() {
        assert!(
            t.elapsed() < Duration::from_secs(10),
            "orphaned points still run"
        );
        std::thread::sleep(Duration::from_millis(50));
    }
    let before = finished(&out_dir);
    assert!(
        before.len() >= 8 && before.len() < 60,
        "killed mid-way: {} done",
        before.len()
    );
    for (id, json) in &before {
        let v: serde_json::Value =
            serde_json::from_str(json).unwrap_or_else(|e| panic!("half-written result {id}: {e}"));
        assert_eq!(v["status"], "ok");
    }
    let out = trax_command()
        .args(args)
        .stdin(Stdio::null())
        .output()
        .unwrap();
    let err = text(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert!(
        err.contains(&format!("{} of 60 points already done", before.len())),
        "{err}"
    );
    let after = finished(&out_dir);
    assert_eq!(after.len(), 60, "no point lost");
    // What the killed sweep's points left in tmp/ is gone (stale `ID.PID.*` files).
    let left: Vec<_> = std::fs::read_dir(out_dir.join("tmp")).unwrap().collect();
    assert!(left.is_empty(), "left in tmp/: {left:?}");
    for (id, json) in &before {
        assert_eq!(&after[id], json, "point {id} was run again");
    }
    // The audit trail: every point finished exactly once.
    let log = std::fs::read_to_string(out_dir.join("events.log")).unwrap();
    let mut done: BTreeMap<&str, usize> = BTreeMap::new();
    for l in log.lines() {
        let w: Vec<&str> = l.split_whitespace().collect();
        if w.get(1) == Some(&"done") {
            *done.entry(w[2]).or_default() += 1;
        }
    }
    assert_eq!(done.len(), 60);
    assert!(done.values().all(|&n| n == 1), "{done:?}");
    // A third run has nothing to do.
    let out = trax(&args);
    assert!(text(&out.stderr).contains("60 of 60 points already done"));
    assert_eq!(
        std::fs::read_to_string(out_dir.join("events.log")).unwrap(),
        log
    );

    // The table: a header and 60 rows of equal length; every metric cell is a number or empty.
    let (header, rows) = read_csv(&out_dir.join("results.csv"));
    assert_eq!(rows.len(), 60);
    for r in &rows {
        assert_eq!(r["status"], "ok");
        for h in &header {
            if ["instructions", "cycles", "fps", "energy_j", "wall_seconds"].contains(&h.as_str())
                && !r[h].is_empty()
            {
                r[h].parse::<f64>()
                    .unwrap_or_else(|_| panic!("{h} = {:?} is not a number", r[h]));
            }
        }
    }
    // pandas loads it as is (the issue's acceptance; .ci/run installs python3-pandas).
    // The first python3 on PATH, else Debian's (a pyenv shim may come first on PATH).
    let python = ["python3", "/usr/bin/python3"].into_iter().find(|p| {
        Command::new(p)
            .args(["-c", "import pandas"])
            .stderr(Stdio::null())
            .status()
            .is_ok_and(|s| s.success())
    });
    let python = python.expect(
        "python3 with pandas is needed to check results.csv: apt-get install python3-pandas (.ci/run does)",
    );
    {
        let csv = out_dir.join("results.csv");
        let o = Command::new(python)
            .args([
                "-c",
                "import sys, pandas; d = pandas.read_csv(sys.argv[1]); \
                 assert d.shape[0] == 60, d.shape; \
                 assert d['cycles'].dtype.kind == 'f', d['cycles'].dtype; \
                 assert d['tms'].dtype.kind == 'i'; \
                 assert (d['status'] == 'ok').all(); print('ok')",
                csv.to_str().unwrap(),
            ])
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", text(&o.stderr));
    }
}

#[test]
fn plots_have_title_labels_and_legend() {
    let dir = scratch("plot");
    let k = gradient();
    let f = sweep_file(
        &dir,
        &format!("kernel = {k:?}\nwidth = 8\nheight = 8\n[axes]\nspp = [1, 2]\ntms = [1, 2, 4]\n"),
    );
    let out_dir = dir.join("results");
    let out = trax(&[
        "sweep",
        f.to_str().unwrap(),
        "-o",
        out_dir.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let res = out_dir.to_str().unwrap();
    let chart = dir.join("fps");
    let out = trax(&[
        "plot",
        res,
        "--x",
        "tms",
        "--y",
        "fps",
        "--by",
        "spp",
        "-o",
        chart.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let svg = std::fs::read_to_string(dir.join("fps.svg")).unwrap();
    for want in [
        "Frame rate vs TMs by spp",
        "Frame rate (frames/s)",
        "Thread multiprocessors (TMs)",
        "spp = 1",
        "spp = 2",
    ] {
        assert!(svg.contains(want), "no {want:?} in the SVG");
    }
    // The PNG decodes, has the chart's size and is drawn in more than two colours.
    let dec = png::Decoder::new(std::fs::File::open(dir.join("fps.png")).unwrap());
    let mut reader = dec.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buf).unwrap();
    assert_eq!((info.width, info.height), (960, 600));
    let colours: BTreeSet<&[u8]> = buf[..info.buffer_size()].chunks(3).collect();
    assert!(colours.len() > 10, "{} colours", colours.len());

    // Energy stacked by component, and bars.
    let out = trax(&[
        "plot", res, "--x", "tms", "--kind", "energy", "--where", "spp=1",
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let svg = std::fs::read_to_string(out_dir.join("plots/energy_j_vs_tms.svg")).unwrap();
    for want in [
        "Energy per frame (J)",
        "DRAM",
        "Register files",
        "Execution units",
    ] {
        assert!(svg.contains(want), "no {want:?} in the energy chart");
    }
    let out = trax(&[
        "plot", res, "--x", "spp", "--y", "cycles", "--kind", "bar", "--by", "tms",
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert!(out_dir.join("plots/cycles_vs_spp_by_tms.png").is_file());

    // A parameter that varies but is neither x nor by would mix experiments.
    let out = trax(&["plot", res, "--x", "tms", "--y", "fps"]);
    assert!(!out.status.success());
    assert!(
        text(&out.stderr).contains("parameter `spp` also varies"),
        "{}",
        text(&out.stderr)
    );
    let out = trax(&["plot", res, "--x", "tms", "--y", "fsp", "--where", "spp=1"]);
    assert!(!out.status.success());
    assert!(
        text(&out.stderr).contains("no metric `fsp`"),
        "{}",
        text(&out.stderr)
    );
    let out = trax(&["plot", res, "--x", "tmz", "--y", "fps"]);
    assert!(
        text(&out.stderr).contains("no parameter `tmz`"),
        "{}",
        text(&out.stderr)
    );
}

#[test]
fn a_point_ends_when_its_sweep_is_gone() {
    // A point's `trax run` (TRAX_SWEEP_PARENT = its parent's pid) of a kernel that never
    // ends; its parent, a shell standing in for the sweep, is killed with SIGKILL.
    let dir = scratch("orphan");
    let k = dir.join("forever.rs");
    std::fs::write(
        &k,
        "fn trax_main() {\n    loop {\n        trax::atomic_inc(1);\n    }\n}\n",
    )
    .unwrap();
    let script = format!(
        "TRAX_SWEEP_PARENT=$$ '{}' run '{}' --functional >/dev/null 2>&1 & echo $!; wait",
        env!("CARGO_BIN_EXE_trax"),
        k.display()
    );
    let mut sh = Command::new("sh")
        .args(["-c", &script])
        .stdout(Stdio::piped())
        .spawn()
        .unwrap();
    let mut line = String::new();
    std::io::BufRead::read_line(
        &mut std::io::BufReader::new(sh.stdout.take().unwrap()),
        &mut line,
    )
    .unwrap();
    let point: u32 = line.trim().parse().unwrap();
    let alive = |pid: u32| {
        Path::new(&format!("/proc/{pid}")).exists() && {
            // A zombie has ended (its new parent reaps it).
            let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).unwrap_or_default();
            !stat.contains(") Z ")
        }
    };
    std::thread::sleep(Duration::from_millis(500));
    assert!(alive(point), "the point should still be running");
    sh.kill().unwrap();
    sh.wait().unwrap();
    let t = Instant::now();
    while alive(point) {
        if t.elapsed() > Duration::from_secs(10) {
            let _ = Command::new("kill")
                .args(["-9", &point.to_string()])
                .status();
            panic!("the point outlived its sweep by 10 s");
        }
        std::thread::sleep(Duration::from_millis(50));
    }
}

#[test]
fn the_example_experiments_are_valid_sweeps() {
    let mut n = 0;
    for e in std::fs::read_dir(root().join("experiments")).unwrap() {
        let p = e.unwrap().path();
        if p.extension().is_some_and(|x| x == "toml") {
            let out = trax(&["sweep", p.to_str().unwrap(), "--dry-run"]);
            assert!(
                out.status.success(),
                "{}: {}",
                p.display(),
                text(&out.stderr)
            );
            assert!(!out.stdout.is_empty());
            n += 1;
        }
    }
    assert!(n > 0);
}

/// How often each point finished, by `events.log`.
fn done_counts(out_dir: &Path) -> BTreeMap<String, usize> {
    let log = std::fs::read_to_string(out_dir.join("events.log")).unwrap_or_default();
    let mut done: BTreeMap<String, usize> = BTreeMap::new();
    for l in log.lines() {
        let w: Vec<&str> = l.split_whitespace().collect();
        if w.get(1) == Some(&"done") {
            *done.entry(w[2].to_string()).or_default() += 1;
        }
    }
    done
}

/// `kernel` built into `dir` (an executable: a sweep of it builds nothing, so the tests
/// that run a sweep many times take seconds).
fn prebuilt(dir: &Path, kernel: &str) -> String {
    let elf = dir.join(format!(
        "{}.elf",
        Path::new(kernel).file_stem().unwrap().to_string_lossy()
    ));
    let out = trax(&["build", kernel, "-o", elf.to_str().unwrap()]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    elf.display().to_string()
}

/// Runs a sweep file in `dir` (results in `dir/results`) and returns its stderr; it must
/// succeed.
fn sweep_ok(dir: &Path, f: &Path) -> String {
    let out = trax(&[
        "sweep",
        f.to_str().unwrap(),
        "-o",
        dir.join("results").to_str().unwrap(),
        "-j",
        "1",
    ]);
    let err = text(&out.stderr);
    assert!(out.status.success(), "{err}");
    err
}

/// `trax sweep status` of `dir/results`: its stdout and whether it said every point is
/// done (exit 0).
fn status(dir: &Path) -> (String, bool) {
    let out = trax(&["sweep", "status", dir.join("results").to_str().unwrap()]);
    assert!(
        !text(&out.stderr).contains("panicked"),
        "{}",
        text(&out.stderr)
    );
    (text(&out.stdout), out.status.success())
}

/// Edits `file` (replacing `from` by `to`), checks that `trax sweep status` reports the
/// sweep's point stale naming `why`, and that the sweep runs it again, saying so.
fn edit_and_see_stale(dir: &Path, f: &Path, file: &Path, from: &str, to: &str, why: &str) {
    let old = std::fs::read_to_string(file).unwrap();
    assert!(old.contains(from), "{} has no {from:?}", file.display());
    std::fs::write(file, old.replacen(from, to, 1)).unwrap();
    stale_then_rerun(dir, f, why);
}

/// `trax sweep status` reports the sweep's point stale naming `why`; the sweep runs it
/// again (saying why) and then it is done.
fn stale_then_rerun(dir: &Path, f: &Path, why: &str) {
    let before = done_counts(&dir.join("results"));
    let (st, all_done) = status(dir);
    assert!(!all_done, "status: {st}");
    assert!(
        st.contains("1 stale") && st.contains(why),
        "status should name {why:?}:\n{st}"
    );
    let err = sweep_ok(dir, f);
    assert!(
        err.contains("inputs changed since they ran") && err.contains(why),
        "{err}"
    );
    let after = done_counts(&dir.join("results"));
    assert_eq!(
        after.values().sum::<usize>(),
        before.values().sum::<usize>() + 1,
        "{err}"
    );
    let (st, all_done) = status(dir);
    assert!(all_done && st.contains("1 done"), "{st}");
    assert!(sweep_ok(dir, f).contains("1 of 1 points already done"));
}

/// The issue's reproduction: a point names a chip TOML; edit it and run the sweep again.
/// It used to say "1 of 1 points already done" and keep the old cycles.
#[test]
fn an_edited_chip_config_makes_the_result_stale() {
    let dir = scratch("stale-config");
    let k = prebuilt(&dir, &gradient());
    std::fs::write(dir.join("mychip.toml"), "preset = \"tiny\"\ntms = 1\n").unwrap();
    let f = sweep_file(
        &dir,
        &format!("kernel = {k:?}\nconfig = \"mychip.toml\"\nwidth = 16\nheight = 16\n"),
    );
    sweep_ok(&dir, &f);
    let (_, rows) = read_csv(&dir.join("results/results.csv"));
    let cycles_1tm = rows[0]["cycles"].clone();
    assert!(sweep_ok(&dir, &f).contains("1 of 1 points already done"));
    edit_and_see_stale(
        &dir,
        &f,
        &dir.join("mychip.toml"),
        "tms = 1",
        "tms = 2",
        "mychip.toml changed (chip config: tms 1 -> 2",
    );
    let (_, rows) = read_csv(&dir.join("results/results.csv"));
    assert_eq!(rows[0]["status"], "ok");
    assert_ne!(rows[0]["cycles"], cycles_1tm, "the new chip's cycles");
    // A comment changes the file, not the chip: still stale (by content), said so.
    edit_and_see_stale(
        &dir,
        &f,
        &dir.join("mychip.toml"),
        "tms = 2",
        "tms = 2 # two",
        "the chip config it makes is the same",
    );
}

/// A Rust kernel's `mod` file and a C kernel's header are inputs (through the executable
/// the sweep builds: its SHA-256 covers every file the build read).
#[test]
fn an_edited_mod_file_or_header_makes_the_result_stale() {
    let dir = scratch("stale-kernel");
    std::fs::write(
        dir.join("k.rs"),
        "mod helper;\nfn trax_main() {\n    if trax::global_id() == 0 {\n        println!(\"{}\", helper::value());\n    }\n}\n",
    )
    .unwrap();
    std::fs::write(dir.join("helper.rs"), "pub fn value() -> u32 {\n    1\n}\n").unwrap();
    std::fs::write(
        dir.join("c.c"),
        "#include <trax.h>\n#include \"value.h\"\nvoid trax_main(void) {\n    if (trax_global_id() == 0) {\n        trax_print_uint(VALUE);\n        trax_print_str(\"\\n\");\n    }\n}\n",
    )
    .unwrap();
    std::fs::write(dir.join("value.h"), "#define VALUE 10\n").unwrap();
    let f = sweep_file(
        &dir,
        "mode = \"functional\"\nwidth = 4\nheight = 4\n[axes]\nkernel = [\"k.rs\"]\n",
    );
    sweep_ok(&dir, &f);
    edit_and_see_stale(
        &dir,
        &f,
        &dir.join("helper.rs"),
        "1",
        "2",
        "k.rs builds differently now",
    );
    let out: Vec<String> = std::fs::read_dir(dir.join("results/output"))
        .unwrap()
        .map(|e| std::fs::read_to_string(e.unwrap().path()).unwrap())
        .collect();
    assert_eq!(out, ["2\n"], "the point ran the edited mod file");
    let f = sweep_file(
        &dir,
        "mode = \"functional\"\nwidth = 4\nheight = 4\n[axes]\nkernel = [\"c.c\"]\n",
    );
    let _ = std::fs::remove_dir_all(dir.join("results"));
    sweep_ok(&dir, &f);
    edit_and_see_stale(
        &dir,
        &f,
        &dir.join("value.h"),
        "10",
        "11",
        "c.c builds differently now",
    );
}

/// Scene files are inputs: the OBJ, its MTL library, the `.view`/`.light` beside it
/// (also one that appears later), and the file inside `box:`/`subdivide:` wrappers.
#[test]
fn edited_scene_files_make_the_result_stale() {
    let dir = scratch("stale-scene");
    let k = prebuilt(&dir, &gradient());
    std::fs::write(
        dir.join("tri.obj"),
        "mtllib tri.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl red\nf 1 2 3\n",
    )
    .unwrap();
    std::fs::write(dir.join("tri.mtl"), "newmtl red\nKd 1 0 0\n").unwrap();
    let body = |scene: &str| {
        format!("kernel = {k:?}\nmode = \"functional\"\nwidth = 4\nheight = 4\nscene = {scene:?}\n")
    };
    let f = sweep_file(&dir, &body("tri.obj"));
    sweep_ok(&dir, &f);
    assert!(sweep_ok(&dir, &f).contains("1 of 1 points already done"));
    let obj = dir.join("tri.obj");
    edit_and_see_stale(&dir, &f, &obj, "v 0 1 0", "v 0 2 0", "tri.obj changed");
    edit_and_see_stale(
        &dir,
        &f,
        &dir.join("tri.mtl"),
        "Kd 1 0 0",
        "Kd 0 1 0",
        "tri.mtl changed",
    );
    // No .view beside it: the camera frames the scene. One appearing changes that.
    let view = "0.2 0.2 3\n0 0 -1\n0 1 0\n0\n-0.5 0.5 -0.5 0.5\n1\n";
    std::fs::write(dir.join("tri.view"), view).unwrap();
    stale_then_rerun(&dir, &f, "tri.view exists now");
    edit_and_see_stale(
        &dir,
        &f,
        &dir.join("tri.view"),
        "0.2 0.2 3",
        "0.3 0.2 3",
        "tri.view changed",
    );
    std::fs::write(dir.join("tri.light"), "0 0 2\n").unwrap();
    stale_then_rerun(&dir, &f, "tri.light exists now");
    edit_and_see_stale(
        &dir,
        &f,
        &dir.join("tri.light"),
        "0 0 2",
        "0 0 3",
        "tri.light changed",
    );
    // The points parsed the scene once per version of its files (trax run --scene-cache).
    let cached: Vec<PathBuf> = std::fs::read_dir(dir.join("results/scenes"))
        .unwrap()
        .flat_map(|d| std::fs::read_dir(d.unwrap().path()).unwrap())
        .map(|e| e.unwrap().path())
        .collect();
    assert!(
        cached.len() == 1 && cached[0].extension().unwrap() == "scene",
        "{cached:?}"
    );
    // The file inside wrappers.
    let f = sweep_file(&dir, &body("box:subdivide:1:tri.obj"));
    let _ = std::fs::remove_dir_all(dir.join("results"));
    sweep_ok(&dir, &f);
    edit_and_see_stale(&dir, &f, &obj, "v 1 0 0", "v 1.5 0 0", "tri.obj changed");
}

/// The trax executable is an input: a point run by another build of trax is stale.
#[test]
fn another_trax_makes_the_result_stale() {
    let dir = scratch("stale-trax");
    let k = prebuilt(&dir, &gradient());
    let f = sweep_file(
        &dir,
        &format!("kernel = {k:?}\nmode = \"functional\"\nwidth = 4\nheight = 4\n"),
    );
    // "Another build": the same program with a byte appended (an ELF runs as before).
    let other = dir.join("trax-other");
    let mut bytes = std::fs::read(env!("CARGO_BIN_EXE_trax")).unwrap();
    bytes.push(0);
    std::fs::write(&other, bytes).unwrap();
    std::fs::set_permissions(&other, std::os::unix::fs::PermissionsExt::from_mode(0o755)).unwrap();
    let out = Command::new(&other)
        .args([
            "sweep",
            f.to_str().unwrap(),
            "-o",
            dir.join("results").to_str().unwrap(),
        ])
        .stdin(Stdio::null())
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", text(&out.stderr));
    stale_then_rerun(&dir, &f, "trax changed");
}

#[test]
fn cases_cross_the_grid_and_repetitions_repeat() {
    let dir = scratch("cases");
    let k = gradient();
    let body = |reps: u32| {
        format!(
            r#"kernel = {k:?}
width = 8
height = 8
mode = "functional"
repetitions = {reps}

[axes]
tms = [1, 2]

[[cases]]
threads = 4

[[cases]]
threads = 8
width = 16

[[cases]]
threads = 4
"#
        )
    };
    let f = sweep_file(&dir, &body(2));
    let out_dir = dir.join("results");
    let out = trax(&[
        "sweep",
        f.to_str().unwrap(),
        "-o",
        out_dir.to_str().unwrap(),
    ]);
    let err = text(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert!(
        err.contains("note: 4 point(s) repeat another's parameters"),
        "{err}"
    );
    let (header, rows) = read_csv(&out_dir.join("results.csv"));
    assert_eq!(
        &header[2..6],
        ["tms", "threads", "width", "kernel"],
        "{header:?}"
    );
    assert!(header.contains(&"rep".to_string()));
    let got: Vec<(&str, &str, &str, &str)> = rows
        .iter()
        .map(|r| {
            (
                r["threads"].as_str(),
                r["width"].as_str(),
                r["tms"].as_str(),
                r["rep"].as_str(),
            )
        })
        .collect();
    assert_eq!(
        got,
        [
            ("4", "8", "1", "0"),
            ("4", "8", "1", "1"),
            ("4", "8", "2", "0"),
            ("4", "8", "2", "1"),
            ("8", "16", "1", "0"),
            ("8", "16", "1", "1"),
            ("8", "16", "2", "0"),
            ("8", "16", "2", "1"),
        ]
    );
    for pair in rows.chunks(2) {
        assert_ne!(pair[0]["id"], pair[1]["id"]);
        assert_eq!(
            pair[0]["instructions"], pair[1]["instructions"],
            "deterministic"
        );
    }
    // Threads per TM reached the chip: 8 threads x 2 TMs print 16 hello lines... here, the
    // recorded config says so.
    let rec: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(out_dir.join(format!("points/{}.json", rows[6]["id"]))).unwrap(),
    )
    .unwrap();
    assert_eq!(rec["config"]["threads_per_tm"], 8);
    assert_eq!(rec["config"]["tms"], 2);
    // A repetition index of 0 is not hashed: without repetitions the ids are the rep-0 ids.
    let f1 = sweep_file(&dir, &body(1));
    let dry = trax(&["sweep", f1.to_str().unwrap(), "--dry-run"]);
    let ids: Vec<String> = text(&dry.stdout)
        .lines()
        .map(|l| l.split_whitespace().next().unwrap().to_string())
        .collect();
    let rep0: Vec<String> = rows
        .iter()
        .filter(|r| r["rep"] == "0")
        .map(|r| r["id"].clone())
        .collect();
    assert_eq!(ids, rep0);
    // Plots average repetitions.
    let out = trax(&[
        "plot",
        out_dir.to_str().unwrap(),
        "--x",
        "tms",
        "--y",
        "instructions",
        "--by",
        "threads",
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
}

/// `scene = "icosphere:N"` is a built-in scene (sweep plans took it for a file name and
/// refused it), and `max_cycles` is a knob: timing points stop at that cycle.
#[test]
fn icosphere_scenes_and_cycle_limits_are_sweep_parameters() {
    let dir = scratch("icosphere");
    let k = gradient();
    let (out, _, rows) = sweep_rows(
        &dir,
        &format!(
            "kernel = {k:?}\nwidth = 8\nheight = 8\nscene = \"icosphere:1\"\n[axes]\nmax_cycles = [100, 100000000]\n"
        ),
    );
    assert!(!out.status.success(), "the 100-cycle point fails");
    assert_eq!(rows.len(), 2, "{}", text(&out.stderr));
    for r in &rows {
        assert_eq!(r["scene"], "icosphere:1");
        if r["max_cycles"] == "100" {
            assert_eq!(r["status"], "failed", "{r:?}");
            assert!(
                r["error"].contains("cycle limit reached after 100 cycles"),
                "{r:?}"
            );
        } else {
            assert_eq!(r["status"], "ok", "{r:?}");
            assert!(r["cycles"].parse::<u64>().unwrap() > 100);
        }
    }
}

/// A file inside `box:`/`subdivide:N:` wrappers is found relative to the sweep file (not
/// the working directory), keeps its wrappers, and a missing one is named.
#[test]
fn wrapped_scene_files_resolve_relative_to_the_sweep_file() {
    let dir = scratch("wrapped-scene");
    std::fs::write(dir.join("tri.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    let k = gradient();
    let body = format!(
        "kernel = {k:?}\nmode = \"functional\"\nwidth = 4\nheight = 4\n\
         scene = \"box:subdivide:1:tri.obj\"\n"
    );
    let f = sweep_file(&dir, &body);
    let res = dir.join("res");
    let out = trax(&[
        "sweep",
        f.to_str().unwrap(),
        "-j",
        "1",
        "-o",
        res.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let points: Vec<PathBuf> = std::fs::read_dir(res.join("points"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    assert_eq!(points.len(), 1);
    let point = std::fs::read_to_string(&points[0]).unwrap();
    let want = format!("box:subdivide:1:{}", dir.join("tri.obj").display());
    assert!(point.contains(&want), "no {want} in {point}");
    let v: serde_json::Value = serde_json::from_str(&point).unwrap();
    assert_eq!(v["status"], "ok", "{point}");

    let f = sweep_file(&dir, &body.replace("tri.obj", "gone.obj"));
    let out = trax(&["sweep", f.to_str().unwrap(), "--dry-run"]);
    let err = text(&out.stderr);
    assert!(!out.status.success());
    assert!(
        err.contains(&format!("{}: no such file", dir.join("gone.obj").display())),
        "{err}"
    );
}

/// `label.NAME` parameters are recorded (id, `results.csv`, plots) but are not config
/// fields: cases that vary different fields share one x axis through a label.
#[test]
fn labels_are_columns_not_config_fields() {
    let dir = scratch("labels");
    let k = gradient();
    let body = format!(
        r#"kernel = {k:?}
width = 8
height = 8
mode = "functional"

[axes]
"label.size" = [1, 2]

[[cases]]
"label.chip" = "a"
threads = 4

[[cases]]
"label.chip" = "b"
tms = 3
"#
    );
    let (out, out_dir, rows) = sweep_rows(&dir, &body);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let got: Vec<(&str, &str)> = rows
        .iter()
        .map(|r| (r["label.chip"].as_str(), r["label.size"].as_str()))
        .collect();
    assert_eq!(got, [("a", "1"), ("a", "2"), ("b", "1"), ("b", "2")]);
    assert_ne!(rows[0]["id"], rows[1]["id"], "labels are part of the id");
    for r in &rows {
        assert_eq!(r["status"], "ok", "{r:?}");
        let rec: serde_json::Value = serde_json::from_str(
            &std::fs::read_to_string(out_dir.join(format!("points/{}.json", r["id"]))).unwrap(),
        )
        .unwrap();
        let cmd = rec["command"].to_string();
        assert!(!cmd.contains("label."), "a label reached trax run: {cmd}");
    }
    // One chart over the label, a line per case.
    let out = trax(&[
        "plot",
        out_dir.to_str().unwrap(),
        "--x",
        "label.size",
        "--y",
        "instructions",
        "--by",
        "label.chip",
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    // A bare `label` is not a label: an unknown parameter, with its line.
    let f = sweep_file(&dir, &format!("kernel = {k:?}\nlabel = 3\n"));
    let out = trax(&["sweep", f.to_str().unwrap(), "--dry-run"]);
    let err = text(&out.stderr);
    assert!(!out.status.success());
    assert!(err.contains(":2:") && err.contains("`label`"), "{err}");
    assert!(err.contains("label.NAME"), "{err}");
}

/// A kernel that never ends.
fn forever(dir: &Path) -> PathBuf {
    let k = dir.join("forever.rs");
    std::fs::write(
        &k,
        "fn trax_main() {\n    loop {\n        trax::atomic_inc(1);\n    }\n}\n",
    )
    .unwrap();
    k
}

/// The one point record of a results directory.
fn the_record(out_dir: &Path) -> serde_json::Value {
    let recs = finished(out_dir);
    assert_eq!(recs.len(), 1, "{recs:?}");
    serde_json::from_str(recs.values().next().unwrap()).unwrap()
}

/// Starts a sweep in the background and waits (bounded) for its point's `trax run`: the
/// sweep and the point's pid.
#[allow(clippy::zombie_processes)] // the callers wait for it
fn start_sweep(args: &[&str]) -> (std::process::Child, u32) {
    let child = trax_command()
        .args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let t = Instant::now();
    loop {
        if let Some(&point) = children_of(child.id()).first() {
            return (child, point);
        }
        assert!(t.elapsed() < Duration::from_secs(60), "no point started");
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// Points that die are failures with their cause, recorded once (not "interrupted" and
/// retried on every run): over the time limit, over the memory limit, killed with
/// SIGKILL from outside. Interrupting the sweep itself is not a failure: nothing is
/// recorded and the next run runs the point.
#[test]
fn a_point_that_dies_is_a_failure_with_its_cause() {
    let dir = scratch("deaths");
    let k = prebuilt(&dir, forever(&dir).to_str().unwrap());
    let res = dir.join("results");
    let body = |extra: &str| {
        format!("kernel = {k:?}\nmode = \"functional\"\nwidth = 4\nheight = 4\n{extra}")
    };
    let run = |f: &Path, extra: &[&str]| {
        let mut args = vec!["sweep", f.to_str().unwrap(), "-o", res.to_str().unwrap()];
        args.extend_from_slice(extra);
        trax(&args)
    };
    // Time limit (the sweep file's).
    let f = sweep_file(&dir, &body("[limits]\ntime = \"1s\"\n"));
    let out = run(&f, &[]);
    assert_eq!(out.status.code(), Some(1), "{}", text(&out.stderr));
    let rec = the_record(&res);
    assert_eq!(rec["status"], "failed");
    assert!(
        rec["error"]
            .as_str()
            .unwrap()
            .contains("time limit of 1 s exceeded"),
        "{rec}"
    );
    let wall = rec["wall_seconds"].as_f64().unwrap();
    assert!((1.0..10.0).contains(&wall), "stopped after {wall} s");
    let again = run(&f, &[]);
    assert!(
        text(&again.stderr).contains("1 of 1 points already done"),
        "{}",
        text(&again.stderr)
    );
    let (st, _) = status(&dir);
    assert!(
        st.contains("1 failed") && st.contains("time limit of 1 s exceeded"),
        "{st}"
    );

    // Memory limit (the command line's): a 2048x2048 frame needs more than 100 MiB.
    let _ = std::fs::remove_dir_all(&res);
    let f = sweep_file(
        &dir,
        &format!(
            "kernel = {:?}\nmode = \"functional\"\nwidth = 2048\nheight = 2048\n",
            gradient()
        ),
    );
    let out = run(&f, &["--point-memory", "100M"]);
    assert_eq!(out.status.code(), Some(1), "{}", text(&out.stderr));
    let rec = the_record(&res);
    assert!(
        rec["error"]
            .as_str()
            .unwrap()
            .contains("memory limit of 100M exceeded"),
        "{rec}"
    );
    assert!(rec["max_rss_bytes"].as_u64().unwrap() > 100 << 20, "{rec}");
    // Without the limit it runs.
    let out = run(&f, &["--retry-failed"]);
    assert!(out.status.success(), "{}", text(&out.stderr));

    // SIGKILL from outside (kill -9, the OOM killer).
    let _ = std::fs::remove_dir_all(&res);
    let f = sweep_file(&dir, &body(""));
    let (mut sweep, point) =
        start_sweep(&["sweep", f.to_str().unwrap(), "-o", res.to_str().unwrap()]);
    Command::new("kill")
        .args(["-9", &point.to_string()])
        .status()
        .unwrap();
    let status_ = sweep.wait().unwrap();
    assert_eq!(status_.code(), Some(1));
    let rec = the_record(&res);
    assert_eq!(rec["status"], "failed");
    assert!(
        rec["error"].as_str().unwrap().contains("killed by SIGKILL"),
        "{rec}"
    );
    assert!(run(&f, &[]).status.code() == Some(1), "kept, not retried");
    assert_eq!(done_counts(&res).values().sum::<usize>(), 1);

    // The user stops the sweep (SIGTERM to it; Ctrl-C is SIGINT to both): not a failure.
    let _ = std::fs::remove_dir_all(&res);
    let (sweep, _) = start_sweep(&["sweep", f.to_str().unwrap(), "-o", res.to_str().unwrap()]);
    Command::new("kill")
        .args(["-TERM", &sweep.id().to_string()])
        .status()
        .unwrap();
    let out = sweep.wait_with_output().unwrap();
    let err = text(&out.stderr);
    assert_eq!(out.status.code(), Some(130), "{err}");
    assert!(err.contains("interrupted"), "{err}");
    assert!(finished(&res).is_empty(), "nothing recorded");
    let (st, _) = status(&dir);
    assert!(st.contains("1 pending"), "{st}");
    let left: Vec<_> = std::fs::read_dir(res.join("tmp")).unwrap().collect();
    assert!(left.is_empty(), "left in tmp/: {left:?}");
}

/// Slurm job scripts ask for the points' limits: memory plus room for the task, and the
/// time limit times the points per task plus a minute.
#[test]
fn slurm_scripts_ask_for_the_point_limits() {
    let dir = scratch("slurm-limits");
    let f = sweep_file(
        &dir,
        &format!("kernel = {:?}\n[limits]\ntime = \"10m\"\nmemory = \"1G\"\n[slurm]\nper_task = 2\n[axes]\ntms = [1, 2, 3]\n", gradient()),
    );
    let res = dir.join("results");
    let out = trax(&[
        "sweep",
        f.to_str().unwrap(),
        "--slurm",
        "--no-submit",
        "-o",
        res.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let script = std::fs::read_to_string(res.join("slurm/sub-1.sbatch")).unwrap();
    assert!(script.contains("#SBATCH --time=0-00:21:00"), "{script}");
    assert!(script.contains("#SBATCH --mem=1280M"), "{script}");
    let out = trax(&[
        "sweep",
        f.to_str().unwrap(),
        "--slurm",
        "--no-submit",
        "-o",
        res.to_str().unwrap(),
        "--point-memory",
        "2G",
        "--time",
        "5:00",
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let script = std::fs::read_to_string(res.join("slurm/sub-2.sbatch")).unwrap();
    assert!(script.contains("#SBATCH --time=5:00"), "{script}");
    assert!(script.contains("#SBATCH --mem=2304M"), "{script}");
    for (bad, want) in [
        ("time = \"soon\"", "limits.time"),
        ("memory = \"4Q\"", "limits.memory"),
    ] {
        let f = sweep_file(
            &dir,
            &format!("kernel = {:?}\n[limits]\n{bad}\n", gradient()),
        );
        let out = trax(&["sweep", f.to_str().unwrap(), "--dry-run"]);
        let err = text(&out.stderr);
        assert!(
            !out.status.success() && err.contains(":3:") && err.contains(want),
            "{err}"
        );
    }
}

/// Sizes are computed without wrapping and refused against the cap, naming the file;
/// names are names, never paths out of the results directory; a prebuilt executable is a
/// kernel like a source file, and anything else is named for what it is.
#[test]
fn sizes_are_checked_names_are_names_and_executables_are_kernels() {
    let dir = scratch("size-names");
    let k = gradient();
    let values = (1..=16)
        .map(|i| i.to_string())
        .collect::<Vec<_>>()
        .join(", ");
    let axes: String = (0..16)
        .map(|a| format!("\"label.x{a}\" = [{values}]\n"))
        .collect();
    for (body, want) in [
        (format!("kernel = {k:?}\n[axes]\n{axes}"), "more than 2^64 points"),
        (
            format!("kernel = {k:?}\nrepetitions = 1000000\n[axes]\n\"label.a\" = [1, 2]\n"),
            "2000000 points (cases x axis values x repetitions: 1 x 2 x 1000000): a sweep may have at most 1000000",
        ),
    ] {
        let f = sweep_file(&dir, &body);
        let out = trax(&["sweep", f.to_str().unwrap(), "--dry-run"]);
        let err = text(&out.stderr);
        assert!(!out.status.success(), "accepted: {err}");
        assert!(err.contains(&f.display().to_string()) && err.contains(want), "{err}");
    }
    for (body, at, field) in [
        (format!("name = \"..\"\nkernel = {k:?}\n"), ":1:", "`name`"),
        (format!("kernel = {k:?}\nname = \"../../x\"\n"), ":2:", "`name`"),
        (format!("kernel = {k:?}\n[axes]\ntms = [1]\n[[plot]]\nx = \"tms\"\ny = \"fps\"\nname = \"/tmp/x\"\n"), ":7:", "`plot[0].name`"),
    ] {
        let f = sweep_file(&dir, &body);
        let work = dir.join("work");
        std::fs::create_dir_all(&work).unwrap();
        let out = Command::new(env!("CARGO_BIN_EXE_trax"))
            .args(["sweep", f.to_str().unwrap()])
            .current_dir(&work)
            .stdin(Stdio::null())
            .output()
            .unwrap();
        let err = text(&out.stderr);
        assert!(!out.status.success(), "accepted: {body}");
        assert!(err.contains(at) && err.contains(field) && err.contains("is not a name"), "{err}");
        assert_eq!(std::fs::read_dir(&work).unwrap().count(), 0, "wrote into {}", work.display());
    }
    // A prebuilt executable: it used to be "built", failing with "only sources ... can be
    // linked together".
    let elf = dir.join("gradient.elf");
    assert!(trax(&["build", &k, "-o", elf.to_str().unwrap()])
        .status
        .success());
    let (out, _, rows) = sweep_rows(
        &dir,
        "kernel = \"gradient.elf\"\nmode = \"functional\"\nwidth = 4\nheight = 4\n",
    );
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert_eq!(rows[0]["status"], "ok");
    std::fs::write(dir.join("notes.txt"), "not a kernel").unwrap();
    let f = sweep_file(&dir, "kernel = \"notes.txt\"\n");
    let out = trax(&[
        "sweep",
        f.to_str().unwrap(),
        "-o",
        dir.join("r2").to_str().unwrap(),
    ]);
    let err = text(&out.stderr);
    assert!(!out.status.success());
    assert!(
        err.contains(
            "notes.txt: not a kernel source (.rs, .c, .cpp, .cc, .cxx) nor a TRaX executable"
        ),
        "{err}"
    );
}

/// A sweep with sampled points (`sample = N`): results.csv carries each estimate and its
/// 95% half-width (`cycles`, `cycles_ci95`) as the point's statistics have them, empty
/// for full runs; plots draw the intervals as error bars; `trax sweep status` given the
/// results directory relative to the working directory finds the points done; a changed
/// sampling setting makes new points that run.
#[test]
fn sampled_points_carry_their_intervals_into_the_table_and_plots() {
    let dir = scratch("sampled");
    let k = root().join("examples/mandelbrot.rs").display().to_string();
    let body = |windows: u32| {
        format!(
            "kernel = {k:?}\nwidth = 64\nheight = 64\n[axes]\ntms = [1, 2]\n\
             [[cases]]\nlabel.how = \"full\"\n\
             [[cases]]\nlabel.how = \"sampled\"\nsample = {windows}\nsample_warmup = 1000\nsample_window = 1000\n\
             [[plot]]\nname = \"line\"\nx = \"tms\"\ny = \"cycles\"\nby = \"label.how\"\n\
             [[plot]]\nname = \"bars\"\nx = \"tms\"\ny = \"cycles\"\nkind = \"bar\"\nwhere = {{ \"label.how\" = \"sampled\" }}\n"
        )
    };
    let (out, out_dir, rows) = sweep_rows(&dir, &body(10));
    assert!(out.status.success(), "{}", text(&out.stderr));
    let (header, _) = read_csv(&out_dir.join("results.csv"));
    let at = |c: &str| {
        header
            .iter()
            .position(|h| h == c)
            .unwrap_or_else(|| panic!("no column {c}"))
    };
    assert_eq!(at("cycles_ci95"), at("cycles") + 1, "{header:?}");
    assert_eq!(at("energy_j_ci95"), at("energy_j") + 1, "{header:?}");
    assert!(
        header.iter().all(|h| h != "l1_accesses_ci95"),
        "not estimated: {header:?}"
    );
    assert_eq!(rows.len(), 4);
    let mut sampled_ids = Vec::new();
    for r in &rows {
        assert_eq!(r["status"], "ok", "{r:?}");
        let doc = read_json(&out_dir.join("points").join(format!("{}.json", r["id"])));
        let stats = &doc["stats"];
        if r["label.how"] == "full" {
            assert_eq!(stats["mode"], "timing");
            assert_eq!(r["cycles"], stats["cycles"].to_string());
            assert_eq!(r["cycles_ci95"], "", "a full run has no interval");
            continue;
        }
        sampled_ids.push(r["id"].clone());
        assert_eq!(stats["mode"], "sampled");
        assert_eq!(r["sample"], "10");
        for (col, name, scale) in [
            ("cycles", "cycles", 1.0),
            ("energy_j", "energy_j", 1.0),
            ("dram_dynamic_nj", "energy_dram_dynamic_j", 1e9),
        ] {
            let e = &stats["sampled"]["estimates"][name];
            let f = |k: &str| e[k].as_f64().unwrap() * scale;
            let cell = |c: &str| r[c].parse::<f64>().unwrap();
            let close = |a: f64, b: f64| (a - b).abs() <= 1e-9 * b.abs();
            assert!(close(cell(col), f("estimate")), "{col}: {r:?}");
            let half = (f("ci95_high") - f("ci95_low")) / 2.0;
            let ci = cell(&format!("{col}_ci95"));
            assert!(ci > 0.0 && close(ci, half), "{col}_ci95 {ci} vs {half}");
        }
    }
    // Error bars: in the legend, and drawn (the chart differs from one without them).
    for name in ["line", "bars"] {
        let svg = std::fs::read_to_string(out_dir.join(format!("plots/{name}.svg"))).unwrap();
        assert!(
            svg.contains("95% interval (sampled)"),
            "{name}: no interval legend"
        );
    }
    let bare = dir.join("bare.csv");
    let (header, rows) = read_csv(&out_dir.join("results.csv"));
    let mut w = csv::Writer::from_path(&bare).unwrap();
    let keep: Vec<usize> = (0..header.len())
        .filter(|&i| !header[i].ends_with("_ci95"))
        .collect();
    w.write_record(keep.iter().map(|&i| &header[i])).unwrap();
    for r in &rows {
        w.write_record(keep.iter().map(|&i| &r[&header[i]]))
            .unwrap();
    }
    w.flush().unwrap();
    drop(w);
    let plain = dir.join("plain");
    let out = trax(&[
        "plot",
        bare.to_str().unwrap(),
        "--x",
        "tms",
        "--y",
        "cycles",
        "--by",
        "label.how",
        "-o",
        plain.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let plain_svg = std::fs::read_to_string(dir.join("plain.svg")).unwrap();
    assert!(!plain_svg.contains("95% interval"));
    let line_svg = std::fs::read_to_string(out_dir.join("plots/line.svg")).unwrap();
    let paths = |s: &str| s.matches("<polyline").count() + s.matches("<path").count();
    assert!(
        paths(&line_svg) >= paths(&plain_svg) + 3 * 2,
        "no error bars drawn: {} vs {} paths",
        paths(&line_svg),
        paths(&plain_svg)
    );
    // Status from the directory above the results, naming them relatively.
    let status = trax_command()
        .args(["sweep", "status", "results"])
        .current_dir(&dir)
        .output()
        .unwrap();
    assert!(status.status.success(), "{}", text(&status.stdout));
    assert!(
        text(&status.stdout).contains("4 done, 0 stale"),
        "{}",
        text(&status.stdout)
    );
    // Another window count: new points, run; the full ones stay done.
    let (out, _, rows) = sweep_rows(&dir, &body(12));
    assert!(out.status.success(), "{}", text(&out.stderr));
    let err = text(&out.stderr);
    assert!(err.contains("2 of 4 points already done"), "{err}");
    for r in rows.iter().filter(|r| r["label.how"] == "sampled") {
        assert_eq!(r["sample"], "12");
        assert_eq!(r["status"], "ok");
        assert!(!sampled_ids.contains(&r["id"]), "the point kept its id");
    }
    // `trax sweep --sample N` samples every point, as `sample = N` in the file would; a
    // file that gives `sample` already is refused.
    let plain = sweep_file(&dir, &format!("kernel = {k:?}\n[axes]\ntms = [1, 2]\n"));
    let out = trax(&[
        "sweep",
        plain.to_str().unwrap(),
        "--sample",
        "12",
        "--dry-run",
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let listed = text(&out.stdout);
    assert_eq!(listed.matches("sample=12").count(), 2, "{listed}");
    let f = sweep_file(&dir, &body(10));
    let out = trax(&["sweep", f.to_str().unwrap(), "--sample", "12", "--dry-run"]);
    assert!(!out.status.success());
    assert!(
        text(&out.stderr).contains("gives `sample` already (line 10)"),
        "{}",
        text(&out.stderr)
    );
}
