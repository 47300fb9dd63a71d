//! The functional fast engine against the reference interpreter on whole programs: every
//! example kernel (TRaX-Rust, C, C++; scalar, MSA, ray streams) run both ways
//! (`RunRequest::reference`) gives the same outcome, instruction count, printed text,
//! counters, framebuffer and final state of every thread, with the default quantum and
//! with a quantum of 7 (turns end inside blocks and between branches and their delay
//! slots). Instruction-level checks on random programs are the emulator's
//! (`block::tests`).

use trax::pipeline::{prepare, Prepared, Request};
use trax_emulator::timing::ChipConfig;
use trax_emulator::{run, Mode, RunReport};

mod common;
use common::root;

/// Everything a run leaves that the other interpreter must match (locals compared
/// whole, printed as a length).
fn state(r: &RunReport, p: &Prepared, out: &[u8]) -> String {
    let threads: Vec<String> = r
        .machine
        .threads
        .iter()
        .map(|t| {
            format!(
                "{}: pc {:#x} npc {:#x} slot {:#x} retired {} {:?} regs {:?} calls {:?}+{} \
                 cop2 {:?} rng {:?} ll {:?} local {}",
                t.gid,
                t.pc,
                t.npc,
                t.slot_pc,
                t.retired,
                t.state,
                t.regs,
                t.calls,
                t.dropped_calls,
                t.cop2,
                t.rng,
                t.ll_addr,
                t.local.len()
            )
        })
        .collect();
    format!(
        "{:?} {} instructions, failure {:?}, counters {:?}, output {:?}, framebuffer {:?}\n{}",
        r.outcome,
        r.instructions,
        r.failure,
        r.counters,
        String::from_utf8_lossy(out),
        p.framebuffer(r).map(|f| fnv(&f)),
        threads.join("\n")
    )
}

fn fnv(b: &[u8]) -> u64 {
    b.iter().fold(0xcbf2_9ce4_8422_2325u64, |h, &x| {
        (h ^ x as u64).wrapping_mul(0x100_0000_01b3)
    })
}

/// Runs `p` on `chip` with `quantum`, in the fast engine or the reference interpreter.
fn go(p: &Prepared, chip: &ChipConfig, quantum: u32, reference: bool) -> (String, Vec<u8>) {
    let mut req = p.run_request(chip, Mode::Functional);
    req.quantum = quantum;
    req.reference = reference;
    let mut out = Vec::new();
    let r = run(req, &mut out).expect("the run starts");
    let locals: Vec<u8> = r
        .machine
        .threads
        .iter()
        .flat_map(|t| t.local.clone())
        .collect();
    (state(&r, p, &out), locals)
}

fn check(kernel: &str, scene: &str, size: u32, chip: &ChipConfig) {
    let mut request = Request::new(root().join(kernel));
    request.scene = scene.into();
    request.render.width = size;
    request.render.height = size;
    request.render.max_depth = 3;
    request.chip = chip.clone();
    let p = prepare(&request).unwrap_or_else(|e| panic!("{kernel}: {e}"));
    for quantum in [trax_emulator::DEFAULT_QUANTUM, 7] {
        let (fast, fast_locals) = go(&p, chip, quantum, false);
        let (reference, reference_locals) = go(&p, chip, quantum, true);
        assert_eq!(fast, reference, "{kernel}, quantum {quantum}");
        assert!(
            fast_locals == reference_locals,
            "{kernel}, quantum {quantum}: local stores differ"
        );
        assert!(fast.contains("Finished"), "{kernel}: {fast}");
    }
}

fn chip(tms: u32, threads: u32) -> ChipConfig {
    let mut c = ChipConfig::preset(trax_emulator::timing::DEFAULT_CHIP).unwrap();
    c.tms = tms;
    c.threads_per_tm = threads;
    c.tms_per_l2 = tms;
    c
}

#[test]
fn every_example_runs_alike_in_the_fast_engine_and_the_reference() {
    let c = chip(2, 3);
    for kernel in [
        "examples/hello.rs",
        "examples/gradient.rs",
        "examples/mandelbrot.rs",
        "examples/mandelbrot_simd.rs",
        "examples/raycast.rs",
        "examples/ao.rs",
        "examples/pathtracer.rs",
        "examples/c/gradient.c",
        "examples/c/mandelbrot.c",
        "examples/cpp/raycast.cpp",
    ] {
        check(kernel, "cornell", 12, &c);
    }
}

#[test]
fn the_streaming_path_tracer_runs_alike_in_the_fast_engine_and_the_reference() {
    let mut c = ChipConfig::preset("strata").unwrap();
    c.tms = 2;
    c.threads_per_tm = 4;
    c.tms_per_l2 = 2;
    check("examples/strata.rs", "cornell", 8, &c);
}

/// A request for the reference interpreter with something it does not run is refused.
#[test]
fn the_reference_interpreter_runs_plain_functional_runs_only() {
    let p = prepare(&Request::new(root().join("examples/hello.rs"))).unwrap();
    let c = chip(1, 1);
    for (mode, profile) in [(Mode::Timing, false), (Mode::Functional, true)] {
        let mut req = p.run_request(&c, mode);
        req.reference = true;
        req.profile = profile;
        let e = run(req, &mut Vec::new()).expect_err("refused");
        assert!(e.to_string().contains("reference interpreter"), "{e}");
    }
}
