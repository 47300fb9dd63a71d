//! Bounded resources: no input makes `trax` hang without output, grow its memory without
//! bound or abort the process. Each case here was once a hang, an abort or a silently wrong
//! run: a latency of 2·10^9 cycles ran silently for ever (the quantum is the L1 plus L2 hit
//! latency), L1 + L2 hit latencies near `u32::MAX` wrapped, a 4294967295-cycle DRAM ended in
//! a false deadlock. Every process runs under a deadline, so a hang fails the test instead
//! of stalling the suite.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::OnceLock;
use std::time::{Duration, Instant};

mod common;
use common::{read_json, root, scratch_dir, trax_command};

fn scratch() -> PathBuf {
    scratch_dir("resources")
}

/// What a bounded `trax` process did.
struct Ran {
    code: Option<i32>,
    stdout: String,
    stderr: String,
}

/// Starts `trax ARGS` in the checkout, its output to `out` and `err`.
fn spawn(args: &[&str], out: Stdio, err: Stdio) -> std::process::Child {
    trax_command()
        .args(args)
        .stdin(Stdio::null())
        .stdout(out)
        .stderr(err)
        .spawn()
        .expect("start trax")
}

/// Runs `trax ARGS` in the checkout, killed (and the test failed) after `secs` seconds.
fn trax(name: &str, args: &[&str], secs: u64) -> Ran {
    let (out, err) = (
        scratch().join(format!("{name}.out")),
        scratch().join(format!("{name}.err")),
    );
    let mut child = spawn(
        args,
        std::fs::File::create(&out).unwrap().into(),
        std::fs::File::create(&err).unwrap().into(),
    );
    let deadline = Instant::now() + Duration::from_secs(secs);
    let status = loop {
        if let Some(s) = child.try_wait().unwrap() {
            break s;
        }
        if Instant::now() > deadline {
            let _ = child.kill();
            let _ = child.wait();
            panic!(
                "{name}: `trax {}` still running after {secs} s (a hang); stderr so far:\n{}",
                args.join(" "),
                std::fs::read_to_string(&err).unwrap_or_default()
            );
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    Ran {
        code: status.code(),
        stdout: std::fs::read_to_string(&out).unwrap(),
        stderr: std::fs::read_to_string(&err).unwrap(),
    }
}

/// `examples/hello.rs`, built once.
fn hello() -> &'static str {
    static ELF: OnceLock<String> = OnceLock::new();
    ELF.get_or_init(|| {
        let elf = scratch().join("hello.elf");
        let r = trax(
            "build-hello",
            &["build", "examples/hello.rs", "-o", elf.to_str().unwrap()],
            300,
        );
        assert_eq!(r.code, Some(0), "{}", r.stderr);
        elf.to_str().unwrap().to_string()
    })
}

/// Every time-like chip field outside its documented range is refused before the run,
/// naming the field and the range; none runs silently or wraps.
#[test]
fn out_of_range_latencies_are_refused_naming_the_field_and_the_range() {
    let cases: &[(&str, &[&str])] = &[
        // Ran silently for ever: a 2·10^9-cycle quantum.
        ("l2", &["--set", "memory.l2.hit_latency=2000000000"]),
        // Wrapped: 4 + 4294967295 = 3 cycles of quantum.
        (
            "l1",
            &[
                "--set",
                "memory.l1.hit_latency=4294967295",
                "--set",
                "memory.l2.hit_latency=4",
            ],
        ),
        // Ended in a false deadlock.
        (
            "simple-dram",
            &["--set", "memory.dram.simple.latency=4294967295"],
        ),
        (
            "dram-timing",
            &[
                "--set",
                "memory.dram.preset=gddr5-thesis",
                "--set",
                "memory.dram.detailed.timing.tRFC=\"1000000ns\"",
            ],
        ),
        (
            "dram-clock",
            &[
                "--set",
                "memory.dram.preset=gddr5-thesis",
                "--set",
                "memory.dram.detailed.timing.tRCD=4000000000",
            ],
        ),
        ("unit", &["--set", "units.fp_add.latency=4000000000"]),
        ("local-store", &["--set", "local_store.latency=4000000000"]),
        (
            "global-regs",
            &["--set", "global_registers.latency=4000000000"],
        ),
        (
            "stream-latency",
            &["--set", "stream_memory.latency=4000000000"],
        ),
        (
            "stream-bank",
            &["--set", "stream_memory.bank_busy_cycles=4000000000"],
        ),
        (
            "schedule",
            &["--set", "stream_memory.schedule_cycles=4000000000"],
        ),
        (
            "reconfig",
            &["--set", "pipelines.reconfig_cycles=4000000000"],
        ),
        ("pipe-ii", &["--set", "pipelines.tri.ii=4000000000"]),
        (
            "dram-queue",
            &["--set", "memory.dram.detailed.read_queue=4000000000"],
        ),
        (
            "dram-line",
            &["--set", "memory.dram.simple.line_bytes=4000000000"],
        ),
    ];
    for (name, set) in cases {
        let field = set
            .iter()
            .rev()
            .find(|s| s.contains('='))
            .and_then(|s| s.split('=').next())
            .unwrap();
        let mut args = vec!["run", hello()];
        args.extend_from_slice(set);
        let r = trax(&format!("latency-{name}"), &args, 60);
        assert_eq!(r.code, Some(1), "{name}: {}{}", r.stdout, r.stderr);
        // The innermost name of the field (`--set` paths and the messages may differ in
        // their prefix: `memory.dram.detailed.timing.tRFC` is `dram.detailed.timing.tRFC`).
        let leaf = field.rsplit('.').next().unwrap();
        assert!(
            r.stderr.contains(leaf) && r.stderr.contains("..="),
            "{name}: the error names neither `{leaf}` nor a range:\n{}",
            r.stderr
        );
        assert!(r.stdout.is_empty(), "{name}: the run started: {}", r.stdout);
    }
}

/// A DRAM latency at its bound (10^6 cycles per line) is slow, not refused and not a
/// deadlock: the run ends with the same output as with the default latency.
#[test]
fn the_longest_allowed_dram_latency_runs_to_the_end() {
    let plain = trax("dram-plain", &["run", hello(), "--threads", "2"], 120);
    assert_eq!(plain.code, Some(0), "{}", plain.stderr);
    let slow = trax(
        "dram-slow",
        &[
            "run",
            hello(),
            "--threads",
            "2",
            "--set",
            "memory.dram.simple.latency=1000000",
        ],
        300,
    );
    assert_eq!(slow.code, Some(0), "{}", slow.stderr);
    assert_eq!(slow.stdout, plain.stdout);
    let cycles = |s: &str| -> u64 {
        let l = s.lines().find(|l| l.starts_with("cycles")).unwrap_or("");
        l.split_whitespace()
            .find_map(|w| w.replace(',', "").parse().ok())
            .unwrap_or_else(|| panic!("no cycle count in\n{s}"))
    };
    assert!(
        cycles(&slow.stderr) > 1_000_000,
        "a DRAM access took 10^6 cycles:\n{}",
        slow.stderr
    );
}

/// The peak resident memory (VmHWM) of a running process, in KiB, if it can be read.
fn peak_kib(pid: u32) -> Option<u64> {
    let s = std::fs::read_to_string(format!("/proc/{pid}/status")).ok()?;
    let l = s.lines().find(|l| l.starts_with("VmHWM:"))?;
    l.split_whitespace().nth(1)?.parse().ok()
}

/// `trax ARGS` to its end (under `secs`): its exit code and the last peak memory seen.
fn peak_of(args: &[&str], secs: u64) -> (Option<i32>, u64) {
    let mut child = spawn(args, Stdio::null(), Stdio::null());
    let deadline = Instant::now() + Duration::from_secs(secs);
    let mut peak = 0;
    loop {
        if let Some(p) = peak_kib(child.id()) {
            peak = peak.max(p);
        }
        if let Some(s) = child.try_wait().unwrap() {
            return (s.code(), peak);
        }
        assert!(Instant::now() < deadline, "`trax {}` hangs", args.join(" "));
        std::thread::sleep(Duration::from_millis(5));
    }
}

/// A run with `--stats-interval 4` (about 120 000 intervals) peaks within a few MB of the
/// same run without intervals: intervals go to the document as they complete. (Each held
/// about 1.25 KB, 150 MB here, even without `--stats-json`: a small interval on a long run
/// aborted and lost everything.)
#[test]
fn stats_intervals_do_not_grow_memory() {
    let json = scratch().join("intervals.json");
    let json = json.to_str().unwrap();
    let base = [
        "run",
        "examples/raycast.rs",
        "--width",
        "32",
        "--height",
        "32",
        "--stats-json",
        json,
    ];
    let (code, plain) = peak_of(&base, 300);
    assert_eq!(code, Some(0));
    let mut args = base.to_vec();
    args.extend(["--stats-interval", "4"]);
    let (code, with) = peak_of(&args, 300);
    assert_eq!(code, Some(0));
    let doc = read_json(Path::new(json));
    let t = &doc["timing"];
    let n = t["intervals"].as_array().unwrap().len() as u64;
    assert_eq!(
        n,
        doc["cycles"].as_u64().unwrap().div_ceil(4),
        "every interval written"
    );
    assert!(n > 100_000, "{n}");
    assert!(
        with < plain + 30 * 1024,
        "peak {with} KiB with {n} intervals, {plain} KiB without"
    );
    // Without a document to write them to, none is kept (and the user is told).
    let mut args = base[..6].to_vec();
    args.extend(["--stats-interval", "4"]);
    let (code, without) = peak_of(&args, 300);
    assert_eq!(code, Some(0));
    assert!(without < plain + 30 * 1024, "{without} KiB, {plain} KiB");
}

/// Values that ran and recorded nonsense, or failed only after the whole simulation, are
/// refused before anything runs.
#[test]
fn bad_run_values_are_refused_before_the_run() {
    // --spp 0 was accepted and recorded.
    let r = trax("spp0", &["run", hello(), "--spp", "0"], 60);
    assert_eq!(r.code, Some(2), "{}", r.stderr);
    assert!(
        r.stderr.contains("--spp") && r.stdout.is_empty(),
        "{}",
        r.stderr
    );
    // A zero-size .view window drew every pixel the same.
    let view = scratch().join("flat.view");
    std::fs::write(&view, "0 0 5\n0 0 -1\n0 1 0\n0\n-1 1\n0.5\n0.5\n1\n").unwrap();
    let r = trax(
        "flat-view",
        &["run", hello(), "--view", view.to_str().unwrap()],
        60,
    );
    assert_eq!(r.code, Some(1));
    assert!(
        r.stderr.contains("flat.view:7") && r.stderr.contains("zero size"),
        "{}",
        r.stderr
    );
    // --stats-json to a directory failed after the simulation (its output already printed).
    let dir = scratch();
    let r = trax(
        "json-dir",
        &["run", hello(), "--stats-json", dir.to_str().unwrap()],
        60,
    );
    assert_eq!(r.code, Some(1));
    assert!(r.stdout.is_empty(), "the run started: {}", r.stdout);
    assert!(r.stderr.contains("is a directory"), "{}", r.stderr);
}

/// Scenes larger than the kernel can lay out are refused before they are built, with the
/// count and the limit: `subdivide` against the path tracer's own limit (it once used the
/// triangle array's alone, 3x higher, and split for minutes before the image refused), an
/// OBJ by its faces before tobj parses it (a 20 M-triangle file took 51 s).
#[test]
fn oversized_scenes_are_refused_before_they_are_built() {
    // 32 Cornell triangles x 4^11 = 134 M: over every limit; x 4^10 = 33.6 M, under the
    // triangle array's 59.7 M but over the path tracer's 19.9 M.
    let r = trax(
        "subdivide",
        &[
            "run",
            "examples/pathtracer.rs",
            "--scene",
            "subdivide:10:cornell",
        ],
        120,
    );
    assert_eq!(r.code, Some(1));
    assert!(
        r.stderr.contains("33554432 triangles") && r.stderr.contains("19871662"),
        "{}",
        r.stderr
    );
    // One face of 20 000 002 vertices: 20 M triangles, in a 40 MB file.
    let obj = scratch().join("huge.obj");
    {
        use std::io::Write;
        let mut f = std::io::BufWriter::new(std::fs::File::create(&obj).unwrap());
        f.write_all(b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf").unwrap();
        for _ in 0..20_000_002 / 2 {
            f.write_all(b" 1 2").unwrap();
        }
        f.write_all(b"\n").unwrap();
    }
    let t = Instant::now();
    let r = trax(
        "huge-obj",
        &[
            "run",
            "examples/pathtracer.rs",
            "--scene",
            obj.to_str().unwrap(),
        ],
        120,
    );
    let secs = t.elapsed().as_secs_f64();
    let _ = std::fs::remove_file(&obj);
    assert_eq!(r.code, Some(1));
    assert!(
        r.stderr.contains("huge.obj")
            && r.stderr.contains("20000000 triangles")
            && r.stderr.contains("19871662"),
        "{}",
        r.stderr
    );
    // Counted, not parsed: well under the seconds a parse takes (the kernel's build is
    // most of it).
    assert!(secs < 30.0, "{secs} s");
}

/// Chips that validate but that the host cannot hold are refused before anything is
/// allocated, with the estimate and the host's limit (they once allocated until SIGABRT).
#[test]
fn chips_too_large_for_the_host_are_refused_with_the_estimate() {
    // 2^20 threads x 64 KiB local stores = 64 GiB, more than this machine class has.
    let r = trax(
        "huge-chip",
        &["run", hello(), "--tms", "1024", "--threads", "1024"],
        60,
    );
    assert_eq!(r.code, Some(1), "{}", r.stderr);
    assert!(
        r.stderr.contains("needs about") && r.stderr.contains("local stores 64.0 GiB"),
        "{}",
        r.stderr
    );
    // 80 L1s of 2 GiB: 30 GiB of tags.
    let r = trax(
        "huge-l1",
        &[
            "run",
            hello(),
            "--config",
            "baseline",
            "--set",
            "memory.l1.capacity_bytes=2147483648",
        ],
        60,
    );
    assert_eq!(r.code, Some(1), "{}", r.stderr);
    assert!(r.stderr.contains("L1 tags 30.0 GiB"), "{}", r.stderr);
    // Under an address-space limit (RLIMIT_AS of 3 GB), 16 L1s of 1 GiB (3 GiB of tags)
    // are refused naming that limit; the same chip without the limit is not refused for
    // memory (the functional run below allocates no caches).
    let big = [
        "--tms",
        "16",
        "--set",
        "memory.l1.capacity_bytes=1073741824",
    ];
    let mut args = vec![
        "-c",
        "ulimit -v 3000000 && exec \"$0\" \"$@\"",
        env!("CARGO_BIN_EXE_trax"),
        "run",
        hello(),
    ];
    args.extend(big);
    let out = Command::new("sh")
        .args(&args)
        .current_dir(root())
        .output()
        .expect("sh");
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(
        err.contains("RLIMIT_AS") && err.contains("L1 tags 3.0 GiB"),
        "{err}"
    );
    let mut f = vec!["run", hello(), "--functional"];
    f.extend(big);
    let r = trax("big-functional", &f, 60);
    assert_eq!(r.code, Some(0), "{}", r.stderr);
}

/// A kernel from `fuzz/seeds/kernel/`, built by `trax build` under a deadline.
fn build_seed(name: &str, secs: u64) -> (Ran, PathBuf) {
    let elf = scratch().join(format!("{name}.elf"));
    let src = format!("fuzz/seeds/kernel/{name}.rs");
    let r = trax(
        &format!("build-{name}"),
        &["build", &src, "-o", elf.to_str().unwrap()],
        secs,
    );
    (r, elf)
}

/// Deep but valid programs compile and run: a 4000-term `+` chain and 3000 nested `if`s
/// overflowed the compiler's stack (exit 134); a local `[0u32; 4·10^6]` was built as one
/// aggregate value (10^6 took 32 s and 1.3 GB, 4·10^6 crashed the compiler); an array
/// above the in-place fill threshold holds its values.
#[test]
fn deep_programs_and_large_arrays_compile() {
    for (name, expect) in [
        ("deep_add", "3999\n"),
        ("deep_if", "deep 0\n"),
        ("repeat_fill", "14330\n"),
    ] {
        let (r, elf) = build_seed(name, 240);
        assert_eq!(r.code, Some(0), "{name}: {}", r.stderr);
        let r = trax(
            &format!("run-{name}"),
            &[
                "run",
                elf.to_str().unwrap(),
                "--functional",
                "--threads",
                "1",
            ],
            120,
        );
        assert_eq!(r.code, Some(0), "{name}: {}", r.stderr);
        assert_eq!(r.stdout, expect, "{name}");
    }
    let (r, _) = build_seed("large_array", 60);
    assert_eq!(r.code, Some(0), "{}", r.stderr);
}
