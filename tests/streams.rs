//! Ray streams end to end (STRaTA, thesis §3.2): `trax::stream` and `trax.h`'s
//! `trax_stream_*` on the machine (functional and timing) and with `trax native` (the
//! host streams), the stream memory's shape in the scene header, capacity and deadlock
//! errors on both sides, and the prelude's instruction cost.

use std::path::{Path, PathBuf};

use trax::pipeline::{chip_config, prepare, Request};
use trax_emulator::timing::ChipConfig;
use trax_emulator::{run, Mode};

mod common;
use common::{root, scratch_dir, text, trax_cached as trax};

fn scratch(name: &str) -> PathBuf {
    scratch_dir(&format!("streams-{name}"))
}

/// The chip of these tests: `tiny` with a 64 KiB stream memory of 16 buffers (1259 rays
/// of 48 bytes), 2 TMs x 3 threads.
const SETS: [&str; 4] = [
    "--set",
    "stream_memory.capacity_bytes=65536",
    "--set",
    "stream_memory.buffers=16",
];
const SHAPE: [&str; 8] = [
    "--tms",
    "2",
    "--threads",
    "3",
    "--width",
    "16",
    "--height",
    "12",
];

fn chip(schedule: &str) -> ChipConfig {
    let sets: Vec<(String, toml::Value)> = vec![
        ("stream_memory.capacity_bytes".into(), 65536.into()),
        ("stream_memory.buffers".into(), 16.into()),
        ("stream_memory.schedule".into(), schedule.into()),
    ];
    chip_config("tiny", &sets, Some(2), Some(3), None).unwrap()
}

/// Printed output and framebuffer of `kernel` on the machine.
fn machine(kernel: &Path, chip: &ChipConfig, mode: Mode) -> (String, Vec<u8>) {
    let mut req = Request::new(kernel);
    req.render.width = 16;
    req.render.height = 12;
    req.chip = chip.clone();
    let p = prepare(&req).unwrap_or_else(|e| panic!("{e}"));
    // The header tells kernels the stream memory's shape.
    let h = &p.image.header;
    assert_eq!(
        (h.stream_rays, h.stream_ray_bytes, h.stream_buffers),
        (1259, 48, 16)
    );
    let mut out = Vec::new();
    let mut r = p.run_request(chip, mode);
    r.host_threads = Some(2);
    let r = run(r, &mut out).unwrap();
    assert!(r.finished(), "{:?}: {:?}", mode, r.failure);
    (String::from_utf8(out).unwrap(), p.framebuffer(&r).unwrap())
}

/// Every pixel's ray is read twice (192 each stage), the pixel indices sum to
/// 192 * 191 / 2, all six threads got "done", and the memory holds 1259 rays.
const EXPECTED: &str = "192 192 18336 6 1259\n";

#[test]
fn a_streaming_kernel_draws_the_same_image_natively_and_on_the_machine() {
    for kernel in ["stream_bounce.rs", "stream_bounce.c"] {
        let k = root().join("tests/kernels").join(kernel);
        let ks = k.to_str().unwrap();
        let dir = scratch(kernel);
        let raw = dir.join("native.fb");
        let out = trax(
            &[
                &["native", ks, "--raw-framebuffer", raw.to_str().unwrap()][..],
                &SETS,
                &SHAPE,
            ]
            .concat(),
        );
        assert!(out.status.success(), "{kernel}: {}", text(&out.stderr));
        assert_eq!(text(&out.stdout), EXPECTED, "{kernel} natively");
        let native_fb = std::fs::read(&raw).unwrap();
        assert!(native_fb.iter().any(|&b| b != 0), "{kernel}: black image");
        for (mode, schedule) in [
            (Mode::Functional, "fullest"),
            (Mode::Timing, "fullest"),
            (Mode::Timing, "round-robin"),
        ] {
            let (stdout, fb) = machine(&k, &chip(schedule), mode);
            assert_eq!(stdout, EXPECTED, "{kernel} {mode:?} {schedule}");
            assert!(
                fb == native_fb,
                "{kernel} {mode:?} {schedule}: images differ"
            );
        }
        // The host runner takes the policy too.
        let out = trax(
            &[
                &["native", ks, "--set", "stream_memory.schedule=sticky"][..],
                &SETS,
                &SHAPE,
            ]
            .concat(),
        );
        assert_eq!(text(&out.stdout), EXPECTED, "{}", text(&out.stderr));
    }
}

/// A stream memory of 38 rays that spills blocks of 8 rays to DRAM (`overflow = "spill"`):
/// the 192 rays of the bounce kernel do not fit, so buffers' rays sit in DRAM when TMs
/// schedule them and the frame's stream work may end only when the spill area is empty
/// too. Every ray still comes back twice, and natively (blocks move at once) as on the
/// machine in both modes.
#[test]
fn a_spilling_stream_memory_loses_no_ray_and_ends_the_frame_only_when_dram_is_empty() {
    let sets: Vec<(String, toml::Value)> = vec![
        ("stream_memory.capacity_bytes".into(), 2048.into()),
        ("stream_memory.buffers".into(), 16.into()),
        ("stream_memory.overflow".into(), "spill".into()),
        ("stream_memory.spill.block_bytes".into(), 384.into()),
        ("stream_memory.spill.area_bytes".into(), (384 * 64).into()),
    ];
    let chip = chip_config("tiny", &sets, Some(2), Some(3), None).unwrap();
    assert_eq!(chip.stream_memory.geometry().capacity_rays(), 38);
    let expected = "192 192 18336 6 38\n";
    let k = root().join("tests/kernels/stream_bounce.rs");
    let dir = scratch("spill");
    let raw = dir.join("native.fb");
    let mut args = vec![
        "native".to_string(),
        k.to_str().unwrap().to_string(),
        "--raw-framebuffer".into(),
        raw.to_str().unwrap().into(),
    ];
    for (f, v) in &sets {
        args.push("--set".into());
        args.push(format!("{f}={v}"));
    }
    args.extend(SHAPE.iter().map(|s| s.to_string()));
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let out = trax(&args);
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert_eq!(text(&out.stdout), expected, "natively");
    let native_fb = std::fs::read(&raw).unwrap();
    for mode in [Mode::Functional, Mode::Timing] {
        let mut req = Request::new(&k);
        req.render.width = 16;
        req.render.height = 12;
        req.chip = chip.clone();
        let p = prepare(&req).unwrap_or_else(|e| panic!("{e}"));
        let mut out = Vec::new();
        let r = run(p.run_request(&chip, mode), &mut out).unwrap();
        assert!(r.finished(), "{mode:?}: {:?}", r.failure);
        assert_eq!(String::from_utf8(out).unwrap(), expected, "{mode:?}");
        assert!(
            p.framebuffer(&r).unwrap() == native_fb,
            "{mode:?}: images differ"
        );
        if mode == Mode::Timing {
            let spill = &r.timing.as_ref().unwrap().stream.spill;
            assert!(
                spill.spills > 0 && spill.spills == spill.refills,
                "{spill:?}"
            );
        }
    }
}

/// Writes `trax::stream::capacity() + EXTRA` rays to buffer 0, one per line of source.
const FILL: &str = "use trax::stream;\n\
fn trax_main() {\n\
    let rec: stream::Record = [0; stream::RECORD_WORDS];\n\
    for _ in 0..stream::capacity() + EXTRA {\n\
        stream::write(0, &rec);\n\
    }\n\
    println!(\"{}\", stream::size(0));\n\
}\n";

#[test]
fn a_full_stream_memory_stops_the_program_natively_and_on_the_machine() {
    let dir = scratch("fill");
    let shape = ["--tms", "1", "--threads", "1"];
    for (extra, fits) in [("0", true), ("1", false)] {
        let k = dir.join(format!("fill{extra}.rs"));
        std::fs::write(&k, FILL.replace("EXTRA", extra)).unwrap();
        let ks = k.to_str().unwrap();
        let nat = trax(&[&["native", ks][..], &SETS, &shape].concat());
        let emu = trax(&[&["run", ks, "--functional"][..], &SETS, &shape].concat());
        for (what, out) in [("native", &nat), ("machine", &emu)] {
            if fits {
                assert!(out.status.success(), "{what}: {}", text(&out.stderr));
                assert_eq!(text(&out.stdout), "1259\n", "{what}");
            } else {
                assert_eq!(out.status.code(), Some(1), "{what}");
                let err = text(&out.stderr);
                assert!(
                    err.contains("ray stream memory full: writing a ray to stream 0, but all 1259 slots of 48-byte rays are taken"),
                    "{what}: {err}"
                );
            }
        }
        if !fits {
            // The machine names the thread and the kernel's line.
            let err = text(&emu.stderr);
            assert!(err.contains("thread 0 (TM 0, thread 0) crashed"), "{err}");
            assert!(err.contains(&format!("{ks}:5")), "{err}");
        }
    }
}

#[test]
fn a_deadlock_is_reported_natively_and_on_the_machine() {
    let dir = scratch("deadlock");
    let k = dir.join("dead.rs");
    std::fs::write(
        &k,
        "fn trax_main() {\n\
         \x20   if trax::tm_id() == 0 {\n\
         \x20       trax::barrier(4);\n\
         \x20   } else {\n\
         \x20       while let Some(_b) = trax::stream::schedule() {}\n\
         \x20   }\n\
         }\n",
    )
    .unwrap();
    let ks = k.to_str().unwrap();
    let nat = trax(&[&["native", ks][..], &SETS, &SHAPE].concat());
    let emu = trax(&[&["run", ks][..], &SETS, &SHAPE].concat());
    for (what, out) in [("native", &nat), ("machine", &emu)] {
        assert_eq!(out.status.code(), Some(1), "{what}");
        let err = text(&out.stderr);
        assert!(err.contains("deadlock"), "{what}: {err}");
        assert!(
            err.contains("threads 0-2 (TM 0): trax.barrier G[4] (3 of 6 live threads arrived)"),
            "{what}: {err}"
        );
        assert!(
            err.contains("threads 3-5 (TM 1): trax.strsched (its TM drained and every ray buffer is empty: waiting for a ray)"),
            "{what}: {err}"
        );
    }
    let err = text(&emu.stderr);
    assert!(
        err.contains(&format!("{ks}:3")) && err.contains(&format!("{ks}:5")),
        "{err}"
    );
}

#[test]
fn native_takes_set_and_rejects_bad_fields() {
    let k = root().join("tests/kernels/stream_bounce.rs");
    let out = trax(&[
        "native",
        k.to_str().unwrap(),
        "--set",
        "stream_memory.schedule=random",
    ]);
    assert_eq!(out.status.code(), Some(1));
    let err = text(&out.stderr);
    assert!(
        err.contains(
            "unknown schedule policy `random` (expected one of fullest, sticky, round-robin, claimed)"
        ),
        "{err}"
    );
}

/// Out-of-line wrappers around the prelude's stream functions, to read their code.
const WRAPPERS: &str = "use trax::stream::{self, Record, RECORD_WORDS};\n\
#[inline(never)]\nfn push(b: u32, rec: &Record) { stream::write(b, rec); }\n\
#[inline(never)]\nfn pop(rec: &mut Record) -> bool { stream::read(rec) }\n\
fn trax_main() {\n\
    let mut rec: Record = [0; RECORD_WORDS];\n\
    push(trax::global_id(), &rec);\n\
    while let Some(_b) = stream::schedule() {\n\
        while pop(&mut rec) {}\n\
    }\n\
}\n";

/// The instructions of function `name` in `trax disasm` output: mnemonics.
fn body<'a>(dis: &'a str, name: &str) -> Vec<&'a str> {
    let start = dis
        .find(&format!("<{name}>:"))
        .unwrap_or_else(|| panic!("{name} in\n{dis}"));
    dis[start..]
        .lines()
        .skip(1)
        .take_while(|l| !l.trim().is_empty() && !l.contains(">:"))
        .filter_map(|l| l.split('\t').nth(2))
        .collect()
}

#[test]
fn the_prelude_adds_only_the_records_loads_and_stores() {
    let dir = scratch("asm");
    let k = dir.join("wrap.rs");
    std::fs::write(&k, WRAPPERS).unwrap();
    let elf = dir.join("wrap.elf");
    let b = trax(&["build", k.to_str().unwrap(), "-o", elf.to_str().unwrap()]);
    assert!(b.status.success(), "{}", text(&b.stderr));
    let d = trax(&["disasm", elf.to_str().unwrap()]);
    let dis = text(&d.stdout);
    let count = |v: &[&str], m: &str| v.iter().filter(|x| **x == m).count();
    // write: strwstart, 12 x (lw, strw), strwend, return.
    let push = body(&dis, "wrap::push");
    assert_eq!(count(&push, "lw"), 12, "{push:?}");
    assert_eq!(count(&push, "trax.strw"), 12, "{push:?}");
    assert_eq!(
        push.iter()
            .filter(|m| ![
                "lw",
                "trax.strw",
                "trax.strwstart",
                "trax.strwend",
                "jic",
                "jrc"
            ]
            .contains(m))
            .count(),
        0,
        "{push:?}"
    );
    // read: strrstart, the branch on its result (and its forbidden-slot nop), 12 x
    // (strr, sw), strrend; and the bool this out-of-line copy returns.
    let pop = body(&dis, "wrap::pop");
    assert_eq!(count(&pop, "sw"), 12, "{pop:?}");
    assert_eq!(count(&pop, "trax.strr"), 12, "{pop:?}");
    let other: Vec<&&str> = pop
        .iter()
        .filter(|m| {
            ![
                "sw",
                "trax.strr",
                "trax.strrstart",
                "trax.strrend",
                "jic",
                "jrc",
                "beqzc",
                "nop",
            ]
            .contains(m)
        })
        .collect();
    assert!(other.len() <= 1, "{pop:?}");
}
