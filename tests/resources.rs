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

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn scratch() -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join("resources");
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// What a bounded `trax` process did.
struct Ran {
    code: Option<i32>,
    stdout: String,
    stderr: String,
}

/// Runs `trax ARGS` in the checkout, killed (and the test failed) after `secs` seconds.
fn trax(name: &str, args: &[&str], secs: u64) -> Ran {
    let (out, err) = (
        scratch().join(format!("{name}.out")),
        scratch().join(format!("{name}.err")),
    );
    let mut child = Command::new(env!("CARGO_BIN_EXE_trax"))
        .args(args)
        .current_dir(root())
        .stdin(Stdio::null())
        .stdout(std::fs::File::create(&out).unwrap())
        .stderr(std::fs::File::create(&err).unwrap())
        .spawn()
        .expect("start trax");
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
