//! `trax ladder`: each rung is the run `trax run` makes with the matching flags (same
//! instructions, cycles, estimates and intervals), errors are against the detailed full
//! run, and the table, CSV, JSON and chart are written.

use std::path::PathBuf;

use serde_json::Value;

mod common;
use common::{read_json, scratch_dir, text, trax};

fn scratch() -> PathBuf {
    scratch_dir("ladder")
}

const FRAME: &[&str] = &[
    "examples/pathtracer.rs",
    "--width",
    "32",
    "--height",
    "32",
    "--config",
    "baseline",
    "--tms",
    "1",
    "--host-threads",
    "1",
];

/// `trax run FRAME EXTRA --stats-json`: the document.
fn run(name: &str, extra: &[&str]) -> Value {
    let json = scratch().join(format!("{name}.json"));
    let j = json.display().to_string();
    let mut args = vec!["run"];
    args.extend_from_slice(FRAME);
    args.extend_from_slice(extra);
    args.extend_from_slice(&["--stats-json", &j]);
    let out = trax(&args);
    assert!(out.status.success(), "{name}: {}", text(&out.stderr));
    read_json(&json)
}

#[test]
fn every_rung_is_the_matching_trax_run() {
    let dir = scratch().join("out");
    let d = dir.display().to_string();
    let mut args = vec!["ladder"];
    args.extend_from_slice(FRAME);
    args.extend_from_slice(&["--rates", "10,20", "-o", &d]);
    let out = trax(&args);
    let table = text(&out.stdout);
    assert!(out.status.success(), "{}", text(&out.stderr));
    for name in [
        "functional",
        "timing, simple DRAM",
        "sampled, 10 windows",
        "sampled, 20 windows",
        "timing, detailed DRAM",
    ] {
        assert!(table.contains(name), "no {name:?} in {table}");
    }
    let doc: Value = read_json(&dir.join("ladder.json"));
    let rungs = doc["rungs"].as_array().unwrap();
    assert_eq!(rungs.len(), 5);
    let f = |v: &Value| v.as_f64().unwrap();

    let functional = run("functional", &["--functional"]);
    assert_eq!(rungs[0]["mode"], "functional");
    assert_eq!(rungs[0]["instructions"], functional["instructions"]);
    assert!(rungs[0]["cycles"].is_null());

    let simple = run("simple", &["--set", "memory.dram.model=simple"]);
    assert_eq!(rungs[1]["dram"], "simple");
    assert_eq!(f(&rungs[1]["cycles"]), f(&simple["cycles"]));
    assert_eq!(
        f(&rungs[1]["energy_j"]),
        f(&simple["timing"]["energy"]["total"])
    );

    for (i, n) in [(2, "10"), (3, "20")] {
        let sampled = run(&format!("sampled-{n}"), &["--sample", n]);
        let e = &sampled["sampled"]["estimates"];
        let r = &rungs[i];
        assert_eq!(r["mode"], "sampled");
        assert_eq!(f(&r["cycles"]), f(&e["cycles"]["estimate"]), "{n} windows");
        assert_eq!(f(&r["cycles_ci"][0]), f(&e["cycles"]["ci95_low"]));
        assert_eq!(f(&r["mrps"]), f(&e["mrps"]["estimate"]));
        assert_eq!(f(&r["energy_j"]), f(&e["energy_j"]["estimate"]));
        assert!(r["detailed_fraction"].as_f64().unwrap() < 1.0);
    }

    let detailed = run("detailed", &["--set", "memory.dram.model=detailed"]);
    let reference = &rungs[4];
    assert_eq!(reference["dram"], "detailed");
    assert_eq!(f(&reference["cycles"]), f(&detailed["cycles"]));
    assert_eq!(f(&reference["mrps"]), f(&detailed["timing"]["mrps"]));
    assert_eq!(f(&reference["cycles_error"]), 0.0);
    // Errors are against the reference.
    let err = f(&rungs[1]["cycles_error"]);
    let want = (f(&simple["cycles"]) - f(&detailed["cycles"])) / f(&detailed["cycles"]);
    assert!((err - want).abs() < 1e-12, "{err} vs {want}");
    // Every mode draws the reference's image.
    for r in rungs {
        assert_eq!(r["same_image"], true, "{}", r["name"]);
    }
    let csv = std::fs::read_to_string(dir.join("ladder.csv")).unwrap();
    assert_eq!(csv.lines().count(), 6, "{csv}");
    assert!(csv.starts_with("mode,kind,dram,windows,wall_seconds"));
    let png = std::fs::read(dir.join("ladder.png")).unwrap();
    assert!(png.starts_with(b"\x89PNG"));
}

#[test]
fn ladder_refuses_unsound_rates() {
    let mut args = vec!["ladder"];
    args.extend_from_slice(FRAME);
    let d = scratch().join("bad").display().to_string();
    args.extend_from_slice(&["--rates", "10,4", "-o", &d]);
    let out = trax(&args);
    assert!(!out.status.success());
    assert!(
        text(&out.stderr).contains("too few windows"),
        "{}",
        text(&out.stderr)
    );
}
