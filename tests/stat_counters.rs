//! The portable statistics counters (`trax::stat` in the prelude, `trax_stat_add` in
//! trax.h): the same counts on every chip, in functional and timing mode and natively,
//! reported in the run summaries and the stats document; an index past the counters
//! stops the program on both sides.

use std::path::{Path, PathBuf};

mod common;
use common::{read_json, scratch_dir, text, trax_cached as trax};

fn scratch(name: &str) -> PathBuf {
    scratch_dir(&format!("stat-{name}"))
}

/// The `counters:` line of a run's summary.
fn counters_line(stderr: &str) -> String {
    stderr
        .lines()
        .find(|l| l.starts_with("counters: "))
        .unwrap_or_else(|| panic!("no counters line in\n{stderr}"))
        .to_string()
}

/// The counters of a `--stats-json` document.
fn json_counters(path: &Path) -> Vec<u64> {
    let doc: serde_json::Value = read_json(path);
    doc["counters"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_u64().unwrap())
        .collect()
}

const IMAGE: [&str; 4] = ["--width", "16", "--height", "12"];

/// `examples/counters.rs` counts primary hits and misses, shadow rays and shadowed ones:
/// every pixel is a hit or a miss, and the counts are the same on three chips in both
/// modes and natively.
#[test]
fn the_counters_example_counts_alike_everywhere() {
    let dir = scratch("example");
    let k = "examples/counters.rs";
    let mut runs: Vec<(String, Vec<u64>, String)> = Vec::new();
    for chip in ["tiny", "baseline", "strata"] {
        for mode in ["--functional", "--timing"] {
            if mode == "--timing" && chip == "strata" {
                continue;
            }
            let json = dir.join(format!("{chip}{mode}.json"));
            let mut args = vec!["run", k, "--config", chip, "--tms", "2", "--threads", "4"];
            args.extend(IMAGE);
            if mode == "--functional" {
                args.push(mode);
            }
            args.extend(["--stats-json", json.to_str().unwrap()]);
            let out = trax(&args);
            assert!(out.status.success(), "{chip} {mode}: {}", text(&out.stderr));
            runs.push((
                format!("{chip} {mode}"),
                json_counters(&json),
                counters_line(&text(&out.stderr)),
            ));
        }
    }
    let (_, first, line) = &runs[0];
    let pixels = 16 * 12;
    assert_eq!(first[1] + first[2], pixels, "hits + misses: {first:?}");
    assert!(first[1] > 0, "{first:?}");
    assert!(
        first[3] > 0 && first[4] > 0 && first[4] < first[3],
        "{first:?}"
    );
    // Counter 0 is the traversal's rays: every primary ray and every shadow ray.
    assert_eq!(first[0], pixels + first[3], "{first:?}");
    assert_eq!(Some(line), trax_runtime::counters::summary(first).as_ref());
    for (what, c, l) in &runs {
        assert_eq!(c, first, "{what}");
        assert_eq!(l, line, "{what}");
    }
    let mut args = vec!["native", k, "--tms", "2", "--threads", "4"];
    args.extend(IMAGE);
    let out = trax(&args);
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert_eq!(counters_line(&text(&out.stderr)), *line, "native");
}

/// trax.h's `trax_stat_add` (and the immediate `trax_stat`) count on the machine and
/// natively; a TRaX-Rust kernel's counter past the last stops the program on both.
#[test]
fn c_counters_and_out_of_range_counters() {
    let dir = scratch("c");
    let c = dir.join("count.c");
    std::fs::write(
        &c,
        "#include <trax.h>\n\nvoid trax_main(void) {\n    trax_stat_add(7, trax_global_id() + 1);\n    trax_stat(9);\n}\n",
    )
    .unwrap();
    let shape = ["--tms", "1", "--threads", "3"];
    let expect = "counters: [7] 6, [9] 3";
    for cmd in [vec!["run", "--functional"], vec!["run"], vec!["native"]] {
        let mut args = cmd.clone();
        args.push(c.to_str().unwrap());
        args.extend(shape);
        let out = trax(&args);
        assert!(out.status.success(), "{cmd:?}: {}", text(&out.stderr));
        assert_eq!(counters_line(&text(&out.stderr)), expect, "{cmd:?}");
    }

    let k = dir.join("bad.rs");
    std::fs::write(
        &k,
        "fn trax_main() {\n    let i = trax::stat::COUNTERS + trax::global_id();\n    trax::stat::add(i, 1);\n}\n",
    )
    .unwrap();
    for mode in ["--functional", "--config=tiny"] {
        let out = trax(&["run", k.to_str().unwrap(), "--threads", "1", mode]);
        assert_eq!(out.status.code(), Some(1), "{mode}");
        let err = text(&out.stderr);
        assert!(
            err.contains("statistics counter index 32 out of range"),
            "{mode}: {err}"
        );
        assert!(err.contains("bad.rs:3:"), "{mode}: {err}");
    }
    let out = trax(&["native", k.to_str().unwrap(), "--threads", "1"]);
    assert_eq!(out.status.code(), Some(1));
    let err = text(&out.stderr);
    assert!(
        err.contains("statistics counter index 32 out of range (0..32)"),
        "{err}"
    );
}
