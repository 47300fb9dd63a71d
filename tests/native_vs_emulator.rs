//! Every example kernel gives the same printed output and the bit-identical framebuffer
//! on the emulator (compiled by the trax compiler, linked, functional mode) and with
//! `trax native` (rustc against the host prelude), on the same scene and chip shape.
//!
//! Bit-exactness holds because every f32 operation the kernels use is exactly specified:
//! IEEE add/sub/mul/div/sqrt, conversions, and the TRaX ops (`trax.fmin/fmax/invsqrt`,
//! `trax.rand`, `trax.seed`) whose results both sides take from `trax_runtime::{fops, rng}`;
//! the kernels that use random numbers seed each sample's stream by pixel and sample, so
//! which thread renders a pixel does not matter (`tests/same_image.rs` varies the chip).

use std::path::Path;
use std::process::Command;

use trax::pipeline::{chip_config, prepare, Request};
use trax_emulator::{run, Mode};

mod common;
use common::{native_cache, root, scratch_dir};

struct Frame {
    stdout: String,
    framebuffer: Vec<u8>,
}

/// Scene and chip used on both sides.
struct Setup<'a> {
    kernel: &'a str,
    width: u32,
    height: u32,
    spp: u32,
    depth: u32,
    tms: u32,
    threads: u32,
    opt_level: u8,
    /// A chip preset (`--config`) instead of the default chip.
    config: Option<&'a str>,
}

fn emulate(s: &Setup) -> Frame {
    let mut req = Request::new(root().join(s.kernel));
    req.opt_level = s.opt_level;
    req.render.width = s.width;
    req.render.height = s.height;
    req.render.spp = s.spp;
    req.render.max_depth = s.depth;
    if let Some(preset) = s.config {
        req.chip = chip_config(preset, &[], Some(s.tms), Some(s.threads), None).unwrap();
    }
    req.chip.tms = s.tms;
    req.chip.threads_per_tm = s.threads;
    let prepared = prepare(&req).unwrap_or_else(|e| panic!("{}: {e}", s.kernel));
    let mut out = Vec::new();
    let result = run(prepared.run_request(&req.chip, Mode::Functional), &mut out)
        .unwrap_or_else(|e| panic!("{}: {e}", s.kernel));
    assert!(
        result.finished(),
        "{}: {:?}\n{}",
        s.kernel,
        result.outcome,
        result.failure.clone().unwrap_or_default()
    );
    Frame {
        stdout: String::from_utf8(out).unwrap(),
        framebuffer: prepared.framebuffer(&result).unwrap(),
    }
}

fn native(s: &Setup) -> Frame {
    let cache = native_cache();
    let dir = scratch_dir("native-vs-emulator");
    let stem = Path::new(s.kernel)
        .file_stem()
        .unwrap()
        .to_string_lossy()
        .into_owned();
    let raw = dir.join(format!("{stem}.fb"));
    let out = Command::new(env!("CARGO_BIN_EXE_trax"))
        .args(["native", s.kernel, "--scene", "cornell"])
        .args([
            "--width",
            &s.width.to_string(),
            "--height",
            &s.height.to_string(),
        ])
        .args(["--spp", &s.spp.to_string(), "--depth", &s.depth.to_string()])
        .args([
            "--tms",
            &s.tms.to_string(),
            "--threads",
            &s.threads.to_string(),
        ])
        .args(s.config.map(|c| ["--config", c]).into_iter().flatten())
        .arg("--raw-framebuffer")
        .arg(&raw)
        .env("TRAX_CACHE_DIR", &cache)
        .current_dir(root())
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}: {}",
        s.kernel,
        String::from_utf8_lossy(&out.stderr)
    );
    Frame {
        stdout: String::from_utf8(out.stdout).unwrap(),
        framebuffer: std::fs::read(&raw).unwrap(),
    }
}

fn check(s: Setup) {
    let e = emulate(&s);
    let n = native(&s);
    assert_eq!(e.stdout, n.stdout, "{}: printed output", s.kernel);
    assert_eq!(
        e.framebuffer.len(),
        (s.width * s.height * trax_runtime::abi::PIXEL_BYTES) as usize,
        "{}",
        s.kernel
    );
    if e.framebuffer != n.framebuffer {
        let first = e
            .framebuffer
            .chunks(4)
            .zip(n.framebuffer.chunks(4))
            .position(|(a, b)| a != b)
            .unwrap_or(0);
        let f = |b: &[u8]| f32::from_le_bytes(b[first * 4..first * 4 + 4].try_into().unwrap());
        panic!(
            "{}: framebuffers differ first at pixel {} channel {}: emulator {} native {}",
            s.kernel,
            first / 3,
            first % 3,
            f(&e.framebuffer),
            f(&n.framebuffer)
        );
    }
    // Not vacuous: kernels print or draw something.
    if s.kernel.ends_with("features.rs")
        || s.kernel.ends_with("memfill.rs")
        || s.kernel.contains("/lang_")
    {
        assert!(e.stdout.lines().count() > 10, "{}", e.stdout);
    } else if s.kernel.ends_with("pipe_reload.rs") {
        assert_eq!(e.stdout.lines().count(), 5, "{}", e.stdout);
    } else if s.kernel.ends_with("hello.rs") {
        let lines = e.stdout.lines().filter(|l| l.starts_with("hello")).count();
        assert_eq!(lines as u32, s.tms * s.threads, "{}", e.stdout);
    } else {
        assert!(
            e.framebuffer.iter().any(|&b| b != 0),
            "{}: black image",
            s.kernel
        );
    }
}

fn setup(kernel: &str) -> Setup<'_> {
    Setup {
        kernel,
        width: 16,
        height: 12,
        spp: 2,
        depth: 2,
        tms: 2,
        threads: 3,
        opt_level: 2,
        config: None,
    }
}

#[test]
fn hello() {
    check(setup("examples/hello.rs"));
}

#[test]
fn gradient() {
    check(setup("examples/gradient.rs"));
}

#[test]
fn mandelbrot() {
    check(setup("examples/mandelbrot.rs"));
}

#[test]
fn mandelbrot_simd() {
    check(setup("examples/mandelbrot_simd.rs"));
}

#[test]
fn raycast() {
    check(setup("examples/raycast.rs"));
}

#[test]
fn counters() {
    check(setup("examples/counters.rs"));
}

#[test]
fn ao() {
    check(setup("examples/ao.rs"));
}

#[test]
fn pathtracer() {
    check(setup("examples/pathtracer.rs"));
}

/// A one-off pipeline test between a `PipeTests`' tests reloads the ray on both sides
/// (the host kept the `PipeTests`' ray, so its third line printed a hit the machine
/// did not).
#[test]
fn pipelines_keep_the_last_loaded_ray() {
    let s = Setup {
        config: Some("strata"),
        ..setup("tests/kernels/pipe_reload.rs")
    };
    let e = emulate(&s);
    assert!(e.stdout.contains("A's tests after B: inf"), "{}", e.stdout);
    assert!(e.stdout.contains("A: 2\n"), "{}", e.stdout);
    check(s);
}

/// The compiler's every-feature kernel prints what rustc's build prints, at -O0 and -O3.
#[test]
fn language_features() {
    for opt_level in [0, 3] {
        check(Setup {
            tms: 1,
            threads: 1,
            opt_level,
            ..setup("compiler/tests/kernels/features.rs")
        });
    }
}

/// The language suite (`compiler/tests/kernels/lang_*.rs`: enums and patterns, traits and
/// generics, slices and iterators, format specs, float helpers, closures, libm methods) prints exactly what
/// rustc's build prints, at -O0 and -O2.
#[test]
fn language_suite() {
    for kernel in [
        "compiler/tests/kernels/lang_enums.rs",
        "compiler/tests/kernels/lang_traits.rs",
        "compiler/tests/kernels/lang_slices.rs",
        "compiler/tests/kernels/lang_format.rs",
        "compiler/tests/kernels/lang_math.rs",
        "compiler/tests/kernels/lang_closures.rs",
        "compiler/tests/kernels/lang_libm.rs",
    ] {
        for opt_level in [0, 2] {
            check(Setup {
                tms: 1,
                threads: 1,
                opt_level,
                ..setup(kernel)
            });
        }
    }
}

/// Filled local arrays (the compiler's own `memset`, word and byte paths) match rustc.
#[test]
fn memory_fill() {
    for opt_level in [0, 2] {
        check(Setup {
            tms: 1,
            threads: 1,
            opt_level,
            ..setup("compiler/tests/kernels/memfill.rs")
        });
    }
}
