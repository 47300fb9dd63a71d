//! The statistics document (`trax run --stats-json`, schema 1) against its documentation
//! (`docs/STATS.md`), and the run limits (`--max-instructions`, `--max-cycles`) it reports.
//!
//! - Every field real output of either mode has is documented, and every documented field
//!   is in real output; both modes have the same fields (a mode's unmeasured ones `null`).
//! - Values agree with the independent view of the same run: the summary on stderr.
//! - `--max-instructions` counts instructions in timing mode too (it used to count cycles
//!   there), `--max-cycles` counts cycles, and functional mode refuses `--max-cycles`.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use serde_json::Value;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn scratch() -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join("stats-json");
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

/// `trax run KERNEL ARGS --stats-json FILE`: the process output and the document.
fn run(name: &str, kernel: &str, args: &[&str]) -> (Output, Value) {
    let json = scratch().join(format!("{name}.json"));
    let _ = std::fs::remove_file(&json);
    let out = Command::new(env!("CARGO_BIN_EXE_trax"))
        .args(["run", kernel, "--width", "16", "--height", "12"])
        .args(args)
        .arg("--stats-json")
        .arg(&json)
        .current_dir(root())
        .output()
        .expect("run trax");
    let doc = std::fs::read_to_string(&json)
        .unwrap_or_else(|e| panic!("{name}: no stats ({e}): {}", text(&out.stderr)));
    (out, serde_json::from_str(&doc).expect("stats parse"))
}

/// The documented fields: the first column of every table row in docs/STATS.md.
fn documented() -> BTreeSet<String> {
    let doc = std::fs::read_to_string(root().join("docs/STATS.md")).unwrap();
    doc.lines()
        .filter_map(|l| l.strip_prefix("| `"))
        .map(|l| l.split('`').next().unwrap().to_string())
        .collect()
}

/// The field paths of `v` in the notation of docs/STATS.md; `maps` are the paths whose
/// entries are documented as `path.*` (not descended into).
fn fields(v: &Value, path: &str, maps: &BTreeSet<String>, out: &mut BTreeSet<String>) {
    if !path.is_empty() {
        out.insert(path.to_string());
    }
    let join = |k: &str| {
        if path.is_empty() {
            k.to_string()
        } else {
            format!("{path}.{k}")
        }
    };
    match v {
        Value::Object(m) if maps.contains(path) && !m.is_empty() => {
            out.insert(join("*"));
        }
        Value::Object(_) if maps.contains(path) => {}
        Value::Object(m) => {
            for (k, x) in m {
                fields(x, &join(k), maps, out);
            }
        }
        Value::Array(a) => {
            for x in a {
                fields(x, &format!("{path}[]"), maps, out);
            }
        }
        _ => {}
    }
}

#[test]
fn documented_fields_are_exactly_the_fields_of_both_modes() {
    let doc = documented();
    let maps: BTreeSet<String> = doc
        .iter()
        .filter_map(|p| p.strip_suffix(".*"))
        .map(str::to_string)
        .collect();
    let mut seen = BTreeSet::new();
    let mut tops = Vec::new();
    for (name, args) in [
        ("functional", &["--functional"][..]),
        ("timing", &["--tms", "2", "--l2s", "2"][..]),
    ] {
        let (out, v) = run(name, "examples/raycast.rs", args);
        assert!(out.status.success(), "{name}: {}", text(&out.stderr));
        assert_eq!(v["schema"], 1, "{name}");
        assert_eq!(v["mode"], name);
        assert_eq!(v["outcome"], "finished");
        let mut f = BTreeSet::new();
        fields(&v, "", &maps, &mut f);
        let undocumented: Vec<&String> = f.difference(&doc).collect();
        assert!(
            undocumented.is_empty(),
            "{name}: fields missing from docs/STATS.md: {undocumented:?}"
        );
        tops.push(v.as_object().unwrap().keys().cloned().collect::<Vec<_>>());
        seen.extend(f);
    }
    assert_eq!(tops[0], tops[1], "one shape: the same top-level fields");
    let absent: Vec<&String> = doc.difference(&seen).collect();
    assert!(
        absent.is_empty(),
        "documented in docs/STATS.md but in no output: {absent:?}"
    );
}

#[test]
fn values_match_the_run_summary() {
    let (out, v) = run("func-summary", "examples/raycast.rs", &["--functional"]);
    assert!(out.status.success());
    let err = text(&out.stderr);
    let n = v["instructions"].as_u64().unwrap();
    assert!(err.contains(&format!("{n} instructions in ")), "{err}");
    assert!(err.contains(&format!("rays: {}", v["rays"])), "{err}");
    assert!(v["cycles"].is_null() && v["timing"].is_null());
    let shape = v["chip"]["tms"].as_u64().unwrap() * v["chip"]["threads_per_tm"].as_u64().unwrap();
    assert_eq!(v["threads"], shape);
    assert_eq!(v["inputs"]["quantum"], 1000);
    assert_eq!(v["inputs"]["kernel"], "examples/raycast.rs");
    assert_eq!(v["inputs"]["opt_level"], 2);
    assert_eq!(v["inputs"]["width"], 16);

    let (out, v) = run("timing-summary", "examples/raycast.rs", &[]);
    assert!(out.status.success());
    let err = text(&out.stderr);
    let line = format!(
        "cycles: {}  ({:.6} s",
        v["cycles"],
        v["timing"]["seconds"].as_f64().unwrap()
    );
    assert!(err.contains(&line), "no {line:?} in {err}");
    assert!(
        err.contains(&format!("instructions: {}  issue rate", v["instructions"])),
        "{err}"
    );
    assert!(v["inputs"]["quantum"].is_null());
    assert_eq!(v["chip"]["name"], "tiny");
}

#[test]
fn max_instructions_counts_instructions_in_timing_mode() {
    const LIMIT: u64 = 20_000;
    let (out, v) = run(
        "imax",
        "examples/raycast.rs",
        &["--max-instructions", &LIMIT.to_string()],
    );
    assert!(!out.status.success(), "stopped early: a failure exit");
    let err = text(&out.stderr);
    assert!(
        err.contains("error: instruction limit reached after"),
        "{err}"
    );
    assert_eq!(v["outcome"], "instruction_limit");
    assert_eq!(v["inputs"]["max_instructions"], LIMIT);
    let executed = v["instructions"].as_u64().unwrap() + v["timing"]["debug_ops"].as_u64().unwrap();
    // Checked at the end of each quantum (L1 + L2 hit latency cycles): at most one
    // quantum of every thread issuing past the limit.
    let chip = &v["chip"];
    let quantum = chip["memory"]["l1"]["hit_latency"].as_u64().unwrap()
        + chip["memory"]["l2"]["hit_latency"].as_u64().unwrap();
    let threads = v["threads"].as_u64().unwrap();
    assert!(
        (LIMIT..LIMIT + quantum * threads).contains(&executed),
        "{executed} executed for a limit of {LIMIT}"
    );
    assert!(
        err.contains(&format!("after {executed} instructions")),
        "{err}"
    );
    // The same stop with any number of host threads.
    let limited = |host_threads: &str| {
        let args = [
            "--max-instructions",
            &LIMIT.to_string(),
            "--tms",
            "2",
            "--host-threads",
            host_threads,
        ];
        run(&format!("imax{host_threads}"), "examples/raycast.rs", &args).1
    };
    let (v1, v2) = (limited("1"), limited("2"));
    assert_eq!(v1["timing"], v2["timing"]);
    assert_eq!(v1["cycles"], v2["cycles"]);
}

#[test]
fn max_cycles_counts_cycles_and_needs_timing_mode() {
    let (out, v) = run("cmax", "examples/raycast.rs", &["--max-cycles", "3000"]);
    assert!(!out.status.success());
    let err = text(&out.stderr);
    assert!(
        err.contains("error: cycle limit reached after 3000 cycles"),
        "{err}"
    );
    assert_eq!(v["outcome"], "cycle_limit");
    assert_eq!(v["cycles"], 3000);
    let out = Command::new(env!("CARGO_BIN_EXE_trax"))
        .args([
            "run",
            "examples/hello.rs",
            "--functional",
            "--max-cycles",
            "10",
        ])
        .current_dir(root())
        .output()
        .unwrap();
    assert!(!out.status.success());
    let err = text(&out.stderr);
    assert!(
        err.contains("--max-cycles") && err.contains("--functional"),
        "{err}"
    );
}

#[test]
fn functional_max_instructions_stops_exactly() {
    let (out, v) = run(
        "fmax",
        "examples/raycast.rs",
        &["--functional", "--max-instructions", "12345"],
    );
    assert!(!out.status.success());
    assert_eq!(v["outcome"], "instruction_limit");
    assert_eq!(v["instructions"], 12345);
    assert!(text(&out.stderr).contains("instruction limit reached after 12345 instructions"));
}
