//! The statistics document (`trax run --stats-json`, schema 1) against its documentation
//! (`docs/STATS.md`), and the run limits (`--max-instructions`, `--max-cycles`) it reports.
//!
//! - Every field real output of either mode has is documented, and every documented field
//!   is in real output; both modes have the same fields (a mode's unmeasured ones `null`).
//! - Values agree with the independent view of the same run: the summary on stderr.
//! - `--max-instructions` counts instructions in timing mode too (it used to count cycles
//!   there), `--max-cycles` counts cycles, and functional mode refuses `--max-cycles`.

use std::collections::BTreeSet;
use std::path::PathBuf;
use std::process::{Command, Output};

use serde_json::Value;

mod common;
use common::{root, scratch_dir, text, trax_command};

fn scratch() -> PathBuf {
    scratch_dir("stats-json")
}

/// `trax run KERNEL ARGS --stats-json FILE`: the process output and the document.
fn run(name: &str, kernel: &str, args: &[&str]) -> (Output, Value) {
    let json = scratch().join(format!("{name}.json"));
    let _ = std::fs::remove_file(&json);
    let out = trax_command()
        .args(["run", kernel, "--width", "16", "--height", "12"])
        .args(args)
        .arg("--stats-json")
        .arg(&json)
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

/// Whether output field `field` is documented by `pattern` (a `*` segment inside a path
/// stands for any key: `sampled.estimates.*.estimate`).
fn matches(pattern: &str, field: &str) -> bool {
    let (p, f): (Vec<&str>, Vec<&str>) = (pattern.split('.').collect(), field.split('.').collect());
    p.len() == f.len() && p.iter().zip(&f).all(|(a, b)| a == b || *a == "*")
}

#[test]
fn documented_fields_are_exactly_the_fields_of_every_mode() {
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
        (
            "timing",
            &["--tms", "2", "--l2s", "2", "--stats-interval", "1000"][..],
        ),
        (
            "sampled",
            &[
                "--tms",
                "2",
                "--sample",
                "10",
                "--sample-warmup",
                "1000",
                "--sample-window",
                "1000",
            ][..],
        ),
    ] {
        // The sampled run's counter is pixel_share's (the path tracer's).
        let kernel = match name {
            "sampled" => "examples/pathtracer.rs",
            _ => "examples/raycast.rs",
        };
        let (out, v) = run(name, kernel, args);
        assert!(out.status.success(), "{name}: {}", text(&out.stderr));
        assert_eq!(v["schema"], 1, "{name}");
        assert_eq!(v["mode"], name);
        assert_eq!(v["outcome"], "finished");
        let mut f = BTreeSet::new();
        fields(&v, "", &maps, &mut f);
        let undocumented: Vec<&String> = f
            .iter()
            .filter(|x| !doc.iter().any(|d| matches(d, x)))
            .collect();
        assert!(
            undocumented.is_empty(),
            "{name}: fields missing from docs/STATS.md: {undocumented:?}"
        );
        tops.push(v.as_object().unwrap().keys().cloned().collect::<Vec<_>>());
        seen.extend(f);
    }
    // A run stopped by a limit: where its threads were; one stopped by a livelock (a
    // thread spinning on a global register nobody sets): the livelock too.
    let spin = scratch().join("spin.rs");
    std::fs::write(
        &spin,
        "fn trax_main() {\n    while trax::global_read(5) == 0 {}\n}\n",
    )
    .unwrap();
    let spin = spin.to_str().unwrap();
    for (name, kernel, args, outcome) in [
        (
            "limit",
            "examples/pathtracer.rs",
            &["--max-instructions", "30000"][..],
            "instruction_limit",
        ),
        (
            "livelock",
            spin,
            &[
                "--functional",
                "--tms",
                "1",
                "--threads",
                "1",
                "--stop-on-livelock",
            ][..],
            "livelock",
        ),
    ] {
        let (out, v) = run(name, kernel, args);
        assert!(!out.status.success());
        assert_eq!(v["outcome"], outcome);
        let mut f = BTreeSet::new();
        fields(&v, "", &maps, &mut f);
        let undocumented: Vec<&String> = f
            .iter()
            .filter(|x| !doc.iter().any(|d| matches(d, x)))
            .collect();
        assert!(
            undocumented.is_empty(),
            "{name}: undocumented {undocumented:?}"
        );
        tops.push(v.as_object().unwrap().keys().cloned().collect::<Vec<_>>());
        seen.extend(f);
    }
    assert_eq!(tops[0], tops[3], "one shape: the same top-level fields");
    assert_eq!(tops[0], tops[4], "one shape: the same top-level fields");
    assert_eq!(tops[0], tops[1], "one shape: the same top-level fields");
    assert_eq!(tops[0], tops[2], "one shape: the same top-level fields");
    let absent: Vec<&String> = doc
        .iter()
        .filter(|d| !seen.iter().any(|x| matches(d, x)))
        .collect();
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

/// The simple DRAM model has no rows: no row-hit rate (`null`, `n/a` in the summary),
/// where the detailed model has one in both.
#[test]
fn row_hit_rate_only_where_dram_has_rows() {
    let (out, v) = run(
        "simple-dram",
        "examples/raycast.rs",
        &["--set", "memory.dram.model=simple"],
    );
    assert!(out.status.success());
    let err = text(&out.stderr);
    assert!(v["timing"]["memory"]["dram"]["reads"].as_u64().unwrap() > 0);
    assert!(
        v["timing"]["memory"]["dram"]["row_hit_rate"].is_null(),
        "{v}"
    );
    assert!(err.contains("row-hit n/a,"), "{err}");
    // A modified chip says so, in the summary and the document.
    let label = "tiny + 1 override (memory.dram.model=simple)";
    assert_eq!(v["chip"]["name"], label);
    assert!(err.contains(&format!("chip: {label} (")), "{err}");

    let (out, v) = run(
        "detailed-dram",
        "examples/raycast.rs",
        &["--set", "memory.dram.preset=gddr5-thesis"],
    );
    assert!(out.status.success());
    let rate = v["timing"]["memory"]["dram"]["row_hit_rate"]
        .as_f64()
        .expect("a detailed DRAM has a row-hit rate");
    assert!((0.0..=1.0).contains(&rate));
    let err = text(&out.stderr);
    assert!(
        err.contains(&format!("row-hit {:.2}%,", rate * 100.0)),
        "{err}"
    );
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

/// `trax run ... --stats-interval N` (timing): the intervals tile the run exactly, their
/// counts add up to the totals, they do not depend on the host threads, and the flag
/// changes no other statistic.
#[test]
fn stats_intervals_tile_the_run_and_sum_to_the_totals() {
    const N: u64 = 1000;
    let base = ["--tms", "2", "--l2s", "2"];
    let with = |threads: &str| {
        let mut a = base.to_vec();
        a.extend(["--stats-interval", "1000", "--host-threads", threads]);
        let (out, v) = run(&format!("intervals-{threads}"), "examples/raycast.rs", &a);
        assert!(out.status.success(), "{}", text(&out.stderr));
        v
    };
    let (v1, v2) = (with("1"), with("2"));
    let (out, plain) = run("intervals-none", "examples/raycast.rs", &base);
    assert!(out.status.success(), "{}", text(&out.stderr));
    // Without the flag: no intervals; with it, every other statistic is unchanged.
    assert!(plain["timing"]["interval_cycles"].is_null());
    assert_eq!(plain["timing"]["intervals"], serde_json::json!([]));
    let strip = |v: &Value| {
        let mut t = v["timing"].clone();
        let o = t.as_object_mut().unwrap();
        o.remove("intervals");
        o.remove("interval_cycles");
        (v["cycles"].clone(), v["instructions"].clone(), t)
    };
    assert_eq!(
        strip(&v1),
        strip(&plain),
        "--stats-interval changed the run"
    );
    // Identical for 1 and 2 host threads.
    assert_eq!(v1["timing"]["intervals"], v2["timing"]["intervals"]);

    let t = &v1["timing"];
    assert_eq!(t["interval_cycles"], N);
    let cycles = v1["cycles"].as_u64().unwrap();
    let ivs = t["intervals"].as_array().unwrap();
    assert_eq!(
        ivs.len() as u64,
        cycles.div_ceil(N),
        "ceil(cycles / N) intervals"
    );
    let threads = v1["threads"].as_u64().unwrap();
    let u = |v: &Value, f: &str| v[f].as_u64().unwrap_or_else(|| panic!("{f}: {v}"));
    let sum = |f: &str| ivs.iter().map(|i| u(i, f)).sum::<u64>();
    for (k, iv) in ivs.iter().enumerate() {
        let k = k as u64;
        let last = k + 1 == ivs.len() as u64;
        assert_eq!(u(iv, "start_cycle"), k * N);
        assert_eq!(u(iv, "end_cycle"), if last { cycles } else { (k + 1) * N });
        assert_eq!(u(iv, "cycles"), u(iv, "end_cycle") - u(iv, "start_cycle"));
        assert_eq!(iv["partial"], last && cycles % N != 0);
        // Every live or halted thread is in exactly one bucket per cycle: the buckets
        // of an interval add up to its cycles x threads only if it is cut at the right
        // cycle.
        let buckets: u64 = iv["thread_cycles"]
            .as_object()
            .unwrap()
            .values()
            .map(|x| x.as_u64().unwrap())
            .sum();
        assert_eq!(buckets, u(iv, "cycles") * threads, "interval {k}");
        assert_eq!(u(iv, "instructions"), u(&iv["thread_cycles"], "issued"));
        let rate = u(iv, "instructions") as f64 / (u(iv, "cycles") * threads) as f64;
        assert!((iv["issue_rate"].as_f64().unwrap() - rate).abs() < 1e-12);
        assert!(iv["mean_rays_in_flight"].is_null(), "no stream memory");
    }
    assert_eq!(sum("instructions"), u(&v1, "instructions"));
    for (b, total) in t["thread_cycles"].as_object().unwrap() {
        let s: u64 = ivs.iter().map(|i| u(&i["thread_cycles"], b)).sum();
        assert_eq!(s, total.as_u64().unwrap(), "thread_cycles.{b}");
    }
    let mem = &t["memory"];
    for f in ["accesses", "hits", "misses"] {
        assert_eq!(sum(&format!("l1_{f}")), u(&mem["l1"], f), "l1 {f}");
        let l2: u64 = mem["l2"].as_array().unwrap().iter().map(|c| u(c, f)).sum();
        assert_eq!(sum(&format!("l2_{f}")), l2, "l2 {f}");
    }
    assert!(sum("l1_accesses") > 0 && sum("l2_accesses") > 0);
    for f in ["reads", "writes", "bytes"] {
        assert_eq!(sum(&format!("dram_{f}")), u(&mem["dram"], f), "dram {f}");
    }
    let e: f64 = ivs.iter().map(|i| i["energy_j"].as_f64().unwrap()).sum();
    let total = t["energy"]["total"].as_f64().unwrap();
    assert!((e - total).abs() <= 1e-9 * total, "energy {e} vs {total}");
}

/// A run cut at an interval end has no partial interval; bad intervals are refused.
#[test]
fn stats_interval_edges_and_errors() {
    let (out, v) = run(
        "intervals-cut",
        "examples/raycast.rs",
        &["--max-cycles", "8000", "--stats-interval", "2000"],
    );
    assert!(
        out.status.success() || v["outcome"] == "cycle_limit",
        "{}",
        text(&out.stderr)
    );
    assert_eq!(v["cycles"], 8000);
    let ivs = v["timing"]["intervals"].as_array().unwrap();
    assert_eq!(ivs.len(), 4);
    assert!(ivs
        .iter()
        .all(|i| i["partial"] == false && i["cycles"] == 2000));

    for (args, want) in [
        (
            &["--functional", "--stats-interval", "100"][..],
            "need timing mode",
        ),
        (
            &["--stats-interval", "7"][..],
            "multiple of the chip's quantum",
        ),
        (&["--stats-interval", "0"][..], "positive multiple"),
    ] {
        let out = Command::new(env!("CARGO_BIN_EXE_trax"))
            .args([
                "run",
                "examples/raycast.rs",
                "--width",
                "4",
                "--height",
                "4",
            ])
            .args(args)
            .current_dir(root())
            .output()
            .unwrap();
        let err = text(&out.stderr);
        assert!(!out.status.success(), "{args:?} was accepted");
        assert!(err.contains(want), "{args:?}: {err}");
    }
}

/// `trax plot STATS.json --over-time --y METRIC` writes a PNG and an SVG with labelled
/// axes; documents without intervals are refused by name.
#[test]
fn plot_over_time_writes_png_and_svg() {
    let (out, _) = run(
        "plot-src",
        "examples/raycast.rs",
        &["--stats-interval", "1000"],
    );
    assert!(out.status.success(), "{}", text(&out.stderr));
    let json = scratch().join("plot-src.json");
    let base = scratch().join("over-time");
    let plot = |args: &[&str]| trax_command().arg("plot").args(args).output().unwrap();
    let p = plot(&[
        json.to_str().unwrap(),
        "--over-time",
        "--y",
        "dram_gbps",
        "-o",
        base.to_str().unwrap(),
    ]);
    assert!(p.status.success(), "{}", text(&p.stderr));
    let png = base.with_extension("png");
    let dec = png::Decoder::new(std::fs::File::open(&png).unwrap());
    let info = dec.read_info().unwrap().info().clone();
    assert_eq!((info.width, info.height), (960, 600));
    let svg = std::fs::read_to_string(base.with_extension("svg")).unwrap();
    for want in [
        "simulated time (µs)",
        "DRAM bandwidth (GB/s)",
        // The title names the metric as its axis label does, not by its field.
        "DRAM bandwidth over time",
    ] {
        assert!(svg.contains(want), "no {want:?} in the SVG");
    }
    // Refused: a functional document, an unknown metric.
    let (_, _) = run("plot-func", "examples/raycast.rs", &["--functional"]);
    let func = scratch().join("plot-func.json");
    let p = plot(&[func.to_str().unwrap(), "--over-time", "--y", "issue_rate"]);
    assert!(!p.status.success());
    assert!(
        text(&p.stderr).contains("functional run"),
        "{}",
        text(&p.stderr)
    );
    let p = plot(&[json.to_str().unwrap(), "--over-time", "--y", "nope"]);
    assert!(!p.status.success());
    assert!(
        text(&p.stderr).contains("no interval metric `nope`"),
        "{}",
        text(&p.stderr)
    );
}

/// Every series of a real `--stats-interval` document can be drawn over time: each field
/// of an interval but the four that place it in time, and each thread-cycle bucket. On a
/// streaming chip, so that every series (rays in flight, the stream buckets) is measured.
#[test]
fn every_interval_series_of_a_document_plots() {
    let (out, doc) = run(
        "series",
        "examples/strata.rs",
        &[
            "--config",
            "strata",
            "--tms",
            "2",
            "--stats-interval",
            "2000",
        ],
    );
    assert!(out.status.success(), "{}", text(&out.stderr));
    let ivs = doc["timing"]["intervals"].as_array().unwrap();
    assert!(ivs.len() >= 2, "{} intervals", ivs.len());
    let mut series = Vec::new();
    for (k, v) in ivs[0].as_object().unwrap() {
        match k.as_str() {
            "start_cycle" | "end_cycle" | "cycles" | "partial" => {}
            "thread_cycles" => series.extend(
                v.as_object()
                    .unwrap()
                    .keys()
                    .map(|b| format!("thread_cycles.{b}")),
            ),
            _ => {
                assert!(v.is_number(), "intervals[0].{k} = {v} is not a number");
                series.push(k.clone());
            }
        }
    }
    assert!(series.contains(&"thread_cycles.stream_idle".to_string()));
    let json = scratch().join("series.json");
    for y in &series {
        let base = scratch().join("series").join(y);
        let p = trax_command()
            .args([
                "plot",
                json.to_str().unwrap(),
                "--over-time",
                "--y",
                y,
                "-o",
            ])
            .arg(&base)
            .output()
            .unwrap();
        assert!(p.status.success(), "--y {y}: {}", text(&p.stderr));
        let svg = scratch().join("series").join(format!("{y}.svg"));
        assert!(svg.exists(), "--y {y}: no {}", svg.display());
    }
}

/// `docs/STATS.md`'s table under `heading` is `want`; `TRAX_BLESS=1` rewrites it.
fn check_stats_md_table(heading: &str, want: &str) {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/docs/STATS.md");
    let doc = std::fs::read_to_string(path).unwrap();
    let head = format!("{heading}\n");
    let at = doc
        .find(&head)
        .unwrap_or_else(|| panic!("docs/STATS.md lacks {heading}"));
    let table = "| field | type | meaning |\n|---|---|---|\n";
    let start = at + doc[at..].find(table).expect("the section has a table") + table.len();
    let end = start + doc[start..].find("\n\n").expect("the table ends") + 1;
    if doc[start..end] == *want {
        return;
    }
    assert!(
        std::env::var_os("TRAX_BLESS").is_some(),
        "docs/STATS.md's table under {heading} differs from its declaration: run \
         `TRAX_BLESS=1 cargo test --test stats_json stats_md` to rewrite it"
    );
    std::fs::write(path, format!("{}{want}{}", &doc[..start], &doc[end..])).unwrap();
}

/// `docs/STATS.md`'s tables of the `timing` object and of the intervals are the ones
/// their declarations (`TimingStats::STATS`, `intervals::md_table`)
/// give.
#[test]
fn stats_md_timing_section_is_generated() {
    use trax_emulator::timing::{intervals, stat, TimingStats};
    check_stats_md_table(
        "## Timing statistics (`timing`, timing mode)",
        &stat::md_rows(TimingStats::STATS),
    );
    check_stats_md_table(
        "## Statistics over time (`timing.intervals`, `trax run --stats-interval N`)",
        &intervals::md_table(),
    );
}

/// Cache accesses by memory region against a kernel that reads each region a known number
/// of times (volatile loads, one thread on one TM, cold caches): per region the L1 sees
/// exactly its loads, sends exactly its lines to the L2 (components start on 64-byte
/// boundaries, each read within one line here), whose cold misses they all are; stores go
/// around both; the regions sum to the caches' totals.
#[test]
fn cache_accesses_by_region_count_a_kernel_that_counts_them() {
    let kernel = scratch().join("regions.rs");
    std::fs::write(
        &kernel,
        r#"static mut TABLE: [u32; 64] = [0; 64];

fn load(a: u32) -> u32 {
    unsafe { std::ptr::read_volatile(a as *const u32) }
}

fn trax_main() {
    let cam = trax::scene::camera_addr();
    let nodes = trax::scene::bvh_base();
    let tris = trax::scene::triangles_base();
    let table = unsafe { &TABLE as *const [u32; 64] as u32 };
    let fb = trax::scene::pixel_addr(0, 0);
    let mut acc = 0u32;
    for _ in 0..5 {
        for w in 0..4 {
            acc = acc.wrapping_add(load(cam + w * 4));
        }
    }
    for _ in 0..3 {
        for w in 0..16 {
            acc = acc.wrapping_add(load(nodes + w * 4));
        }
    }
    for _ in 0..7 {
        acc = acc.wrapping_add(load(tris));
    }
    for _ in 0..9 {
        acc = acc.wrapping_add(load(table));
    }
    for i in 0..5 {
        unsafe { std::ptr::write_volatile((fb + i * 4) as *mut u32, acc) };
    }
}
"#,
    )
    .unwrap();
    let (out, v) = run(
        "regions",
        kernel.to_str().unwrap(),
        &["--tms", "1", "--threads", "1"],
    );
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert!(v["chip"]["memory"]["l1"]["line_bytes"].as_u64().unwrap() >= 64);
    let m = &v["timing"]["memory"];
    let region = |cache: &str, name: &str| -> Value {
        let rows = m[cache].as_array().unwrap();
        rows.iter()
            .find(|r| r["region"] == name)
            .unwrap_or_else(|| panic!("{cache} has no {name}: {rows:?}"))
            .clone()
    };
    let n = |r: &Value, k: &str| r[k].as_u64().unwrap();
    // (region, loads): camera 5 x 4 words, bvh_nodes 3 x 16 words (64 bytes), triangles
    // 7 x 1 word, the program's TABLE 9 x 1 word; each region one line.
    for (name, loads) in [
        ("camera", 20),
        ("bvh_nodes", 48),
        ("triangles", 7),
        ("program:regions::TABLE", 9),
    ] {
        let l1 = region("l1_by_region", name);
        assert_eq!(n(&l1, "accesses"), loads, "{name}: {l1}");
        assert_eq!(n(&l1, "stores"), 0, "{name}");
        assert_eq!(n(&l1, "hits") + n(&l1, "misses"), loads, "{name}");
        assert_eq!(n(&l1, "misses") - n(&l1, "merged"), 1, "{name}: {l1}");
        let rate = (n(&l1, "hits") + n(&l1, "merged")) as f64 / loads as f64;
        assert_eq!(l1["hit_rate_merged_as_hits"].as_f64(), Some(rate), "{name}");
        let l2 = region("l2_by_region", name);
        assert_eq!(
            [n(&l2, "accesses"), n(&l2, "hits"), n(&l2, "misses")],
            [1, 0, 1],
            "{name}: {l2}"
        );
    }
    let fb = region("l1_by_region", "framebuffer");
    assert_eq!([n(&fb, "accesses"), n(&fb, "stores")], [5, 5], "{fb}");
    let fb = region("l2_by_region", "framebuffer");
    assert_eq!([n(&fb, "accesses"), n(&fb, "stores")], [5, 5], "{fb}");
    assert!(n(&region("l1_by_region", "scene_header"), "accesses") > 0);
    // The regions tile the caches' counts.
    for (cache, totals) in [
        ("l1_by_region", vec![m["l1"].clone()]),
        ("l2_by_region", m["l2"].as_array().unwrap().clone()),
    ] {
        for k in ["accesses", "hits", "misses", "merged", "stores"] {
            let sum: u64 = m[cache].as_array().unwrap().iter().map(|r| n(r, k)).sum();
            let total: u64 = totals.iter().map(|t| n(t, k)).sum();
            assert_eq!(sum, total, "{cache}.{k}");
        }
    }
    // The summary's table has the same rows.
    let err = text(&out.stderr);
    assert!(
        err.lines()
            .any(|l| l.trim_start().starts_with("program:regions::TABLE") && l.contains(" 9 ")),
        "{err}"
    );
}
