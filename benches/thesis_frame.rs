//! Speed where the thesis lives (issue 26): the path tracer (`examples/pathtracer.rs`) on
//! the thesis's chip (`baseline-ch3`: 128 TMs x 32 threads) and on 16 TMs, 1024x1024,
//! depth 5, on the Cornell box and Sibenik, the first N cycles of the frame, with 1 and 2
//! host threads; then the functional benchmark against qemu-mipsel; optionally the whole
//! Sibenik frame sampled. Every figure is printed beside its anchor
//! (`shared/reference/anchors.md`) as a ratio.
//!
//! Runs go through the `trax` binary (`trax run` on a path tracer built once), timed by
//! the run's own `simulated in` line (simulation only, no scene loading). With
//! `TRAX_BENCH_BASELINE=/path/to/other/trax` every case also runs on that binary, each
//! pair back to back, and the ratio before -> after is printed: the way to compare two
//! builds on a shared machine, where absolute times drift.
//!
//! Run: `cargo bench --bench thesis_frame`. Environment: `TRAX_BENCH_CYCLES` (cycles of
//! the frame simulated per case, default 60000), `TRAX_BENCH_BASELINE` (see above),
//! `TRAX_BENCH_SAMPLED=1` (also the whole Sibenik frame, `--sample 20` on 2 host threads:
//! minutes), `TRAX_BENCH_FUNCTIONAL=0` (skip the functional comparison).

mod common;
#[path = "../emulator/benches/common/mod.rs"]
mod emulator_common;

use std::path::{Path, PathBuf};
use std::process::Command;

use common::{env_u64, selected};

/// The binary under test.
const TRAX: &str = env!("CARGO_BIN_EXE_trax");

/// Anchor: trax at 128 TMs on one host thread before issue 26 (anchors.md, 2026-12-07:
/// 6.3 M thread-instr/s on Cornell, Sponza and Sibenik alike).
const ANCHOR_128: f64 = 6.3e6;
/// Anchor: the same frame at 16 TMs (9.4-9.7 M).
const ANCHOR_16: f64 = 9.5e6;
/// Goal (issue 26): thread-instructions per second per host core at 128 TMs.
const GOAL_PER_CORE: f64 = 35e6;
/// The original simtrax's fastest single-thread figure in anchors.md (raycast, 4 TMs,
/// fixed-latency DRAM): M instructions per second.
const SIMTRAX: f64 = 1.80e6;
/// Arches (anchors.md), TRaX preset, Cornell 256^2, per host core.
const ARCHES: f64 = 0.99e6;
/// Instructions of the full Sibenik frame (1024^2, depth 5; anchors.md) and the goal for
/// it on 2 host threads, seconds.
const SIBENIK_FRAME_INSTRUCTIONS: f64 = 41.4e9;
const FRAME_GOAL_SECS: f64 = 600.0;
/// The sampled Sibenik frame before issue 26 (anchors.md): host seconds; goal.
const SAMPLED_ANCHOR_SECS: f64 = 712.0;
const SAMPLED_GOAL_SECS: f64 = 120.0;
/// Functional mode against qemu-mipsel before issue 26 (anchors.md), and the goal.
const FUNCTIONAL_ANCHOR_RATIO: f64 = 1.58;
const FUNCTIONAL_GOAL_RATIO: f64 = 3.0;

/// One timing case.
struct Case {
    scene: &'static str,
    tms: u32,
    host_threads: u32,
}

/// What a run printed: thread-instructions, simulated cycles, simulation wall seconds.
#[derive(Clone, Copy)]
struct Figures {
    instructions: u64,
    cycles: u64,
    secs: f64,
}

impl Figures {
    /// Thread-instructions per host second per host thread.
    fn per_core(&self, host_threads: u32) -> f64 {
        self.instructions as f64 / self.secs / f64::from(host_threads)
    }
}

fn main() {
    if !selected("thesis_frame") {
        return;
    }
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let scenes = root.join("../shared/scenes");
    let sibenik = scenes.join("sibenik/sibenik.obj");
    let cycles = env_u64("TRAX_BENCH_CYCLES", 60_000);
    let baseline = std::env::var("TRAX_BENCH_BASELINE").ok().map(PathBuf::from);
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("trax-bench-thesis-frame");
    std::fs::create_dir_all(&dir).unwrap();
    let elf = dir.join("pathtracer.elf");
    let built = Command::new(TRAX)
        .arg("build")
        .arg(root.join("examples/pathtracer.rs"))
        .arg("-o")
        .arg(&elf)
        .output()
        .expect("trax runs");
    assert!(
        built.status.success(),
        "{}",
        String::from_utf8_lossy(&built.stderr)
    );
    println!(
        "thesis_frame: path tracer, 1024x1024, depth 5, baseline-ch3 (128 TMs x 32 threads, \
         or --tms 16), first {cycles} cycles; rates are thread-instructions per host second \
         per host thread (simulation only){}",
        baseline
            .as_ref()
            .map_or(String::new(), |b| format!("; before = {}", b.display()))
    );
    let mut cases = Vec::new();
    for scene in ["cornell", "sibenik"] {
        if scene == "sibenik" && !sibenik.exists() {
            println!("  {} not found: Sibenik cases skipped", sibenik.display());
            continue;
        }
        for tms in [16, 128] {
            for host_threads in [1, 2] {
                cases.push(Case {
                    scene,
                    tms,
                    host_threads,
                });
            }
        }
    }
    let mut at_128_two = None;
    for case in &cases {
        let scene_arg = match case.scene {
            "cornell" => "cornell".to_string(),
            _ => sibenik.display().to_string(),
        };
        let args = |threads: u32| -> Vec<String> {
            [
                "run",
                elf.to_str().unwrap(),
                "--config",
                "baseline-ch3",
                "--scene",
                &scene_arg,
                "--width",
                "1024",
                "--height",
                "1024",
                "--depth",
                "5",
            ]
            .iter()
            .map(|s| s.to_string())
            .chain([
                "--tms".into(),
                case.tms.to_string(),
                "--host-threads".into(),
                threads.to_string(),
                "--max-cycles".into(),
                cycles.to_string(),
            ])
            .collect()
        };
        let before = baseline
            .as_ref()
            .map(|b| timing_run(b, &args(case.host_threads)));
        let after = timing_run(Path::new(TRAX), &args(case.host_threads));
        let rate = after.per_core(case.host_threads);
        let anchor = if case.tms == 128 {
            ANCHOR_128
        } else {
            ANCHOR_16
        };
        let mut line = format!(
            "  {:8} {:3} TMs, {} host thread(s): {:6.2} M/s per core ({} instr, {} cycles, \
             {:.2} s); x{:.2} the anchor ({:.1} M), x{:.2} the goal ({:.0} M), x{:.1} simtrax, \
             x{:.1} Arches",
            case.scene,
            case.tms,
            case.host_threads,
            rate / 1e6,
            after.instructions,
            after.cycles,
            after.secs,
            rate / anchor,
            anchor / 1e6,
            rate / GOAL_PER_CORE,
            GOAL_PER_CORE / 1e6,
            rate / SIMTRAX,
            rate / ARCHES,
        );
        if let Some(b) = before {
            assert_eq!(
                (b.instructions, b.cycles),
                (after.instructions, after.cycles),
                "the baseline binary simulated a different run"
            );
            line += &format!(
                "; before {:.2} M/s: x{:.2}",
                b.per_core(case.host_threads) / 1e6,
                b.secs / after.secs
            );
        }
        println!("{line}");
        if case.scene == "sibenik" && case.tms == 128 && case.host_threads == 2 {
            at_128_two = Some(after);
        }
    }
    if let Some(f) = at_128_two {
        let secs = SIBENIK_FRAME_INSTRUCTIONS / (f.per_core(2) * 2.0);
        println!(
            "  full Sibenik frame on 128 TMs, 2 host threads, at this rate: ~{:.0} s \
             (goal <= {FRAME_GOAL_SECS:.0} s: x{:.2}; 4080 s before issue 26)",
            secs,
            secs / FRAME_GOAL_SECS
        );
    }
    if std::env::var("TRAX_BENCH_FUNCTIONAL").as_deref() != Ok("0") {
        functional(&dir);
    }
    if std::env::var("TRAX_BENCH_SAMPLED").as_deref() == Ok("1") && sibenik.exists() {
        sampled(&elf, &sibenik);
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Runs `bin` with `args` (a timing run capped by `--max-cycles`) and reads its figures.
fn timing_run(bin: &Path, args: &[String]) -> Figures {
    let out = Command::new(bin).args(args).output().expect("trax runs");
    let text =
        String::from_utf8_lossy(&out.stdout).to_string() + &String::from_utf8_lossy(&out.stderr);
    let find = |prefix: &str| -> Option<&str> {
        text.lines()
            .find_map(|l| l.strip_prefix(prefix))
            .and_then(|rest| rest.split_whitespace().next())
    };
    let figures = (|| {
        Some(Figures {
            instructions: find("instructions: ")?.parse().ok()?,
            cycles: find("cycles: ")?.parse().ok()?,
            secs: find("simulated in ")?.parse().ok()?,
        })
    })();
    figures.unwrap_or_else(|| panic!("{} {args:?} printed no figures:\n{text}", bin.display()))
}

/// The functional benchmark (emulator/benches) against qemu-mipsel.
fn functional(dir: &Path) {
    let Some(f) = emulator_common::functional::measure(&dir.join("functional"), 40_000) else {
        println!("  functional: clang-14/ld.lld-14 not available; skipped");
        return;
    };
    let ours = f.mips();
    match f.qemu_mips() {
        Some(q) => println!(
            "  functional ray-box loop: {ours:.1} M instr/s, qemu-mipsel {q:.1} M: x{:.2} qemu \
             (anchor x{FUNCTIONAL_ANCHOR_RATIO}, goal x{FUNCTIONAL_GOAL_RATIO}: x{:.2} the goal)",
            ours / q,
            ours / q / FUNCTIONAL_GOAL_RATIO
        ),
        None => {
            println!("  functional ray-box loop: {ours:.1} M instr/s; qemu-mipsel not available")
        }
    }
}

/// The whole Sibenik frame, sampled (`--sample 20`, 2 host threads).
fn sampled(elf: &Path, sibenik: &Path) {
    let out = Command::new(TRAX)
        .arg("run")
        .arg(elf)
        .args(["--config", "baseline-ch3", "--scene"])
        .arg(sibenik)
        .args(["--width", "1024", "--height", "1024", "--depth", "5"])
        .args(["--sample", "20", "--host-threads", "2"])
        .output()
        .expect("trax runs");
    let text =
        String::from_utf8_lossy(&out.stdout).to_string() + &String::from_utf8_lossy(&out.stderr);
    let line = |prefix: &str| {
        text.lines()
            .find(|l| l.trim_start().starts_with(prefix))
            .unwrap_or("?")
            .trim()
            .to_string()
    };
    let secs: Option<f64> = text.lines().find_map(|l| {
        l.strip_prefix("simulated (sampled) in ")
            .and_then(|r| r.split_whitespace().next())
            .and_then(|s| s.parse().ok())
    });
    match secs {
        Some(s) => println!(
            "  sampled Sibenik frame (--sample 20, 2 host threads): {s:.0} s (anchor \
             {SAMPLED_ANCHOR_SECS:.0} s: x{:.2}; goal <= {SAMPLED_GOAL_SECS:.0} s: x{:.2}); {}; {}",
            SAMPLED_ANCHOR_SECS / s,
            s / SAMPLED_GOAL_SECS,
            line("cycles"),
            line("detailed:")
        ),
        None => println!("  sampled Sibenik frame failed:\n{text}"),
    }
}
