//! One kernel, one image: `trax run` (timing and functional, any `--tms`/`--threads`) and
//! `trax native` give bit-identical framebuffers.
//!
//! What makes it so: the examples draw each sample's random numbers from a stream seeded
//! by pixel and sample (`trax::seed_pixel`, one `trax.seed` instruction), not from the
//! rendering thread's stream, so the dynamic pixel handout (`trax::scene::pixel_share`)
//! does not change the picture; `trax native` lays out the same scene components as
//! `trax run` (triangles in file order unless the kernel reads the BVH); and both commands
//! default to the same chip.

use std::path::{Path, PathBuf};
use std::process::Output;

use trax_assembler::scene::{load_scene, LoadOptions};

mod common;
use common::{native_cache, scratch_dir, trax_command};

fn scratch(name: &str) -> PathBuf {
    scratch_dir(&format!("same-image-{name}"))
}

/// Runs `trax ARGS` (native builds cached in the target directory, keyed by content).
fn trax(args: &[&str]) -> Output {
    let cache = native_cache();
    let out = trax_command()
        .args(args)
        .env("TRAX_CACHE_DIR", &cache)
        .output()
        .expect("run trax");
    assert!(
        out.status.success(),
        "trax {args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

/// `trax CMD KERNEL SCENE_ARGS CHIP_ARGS --raw-framebuffer F`; returns the raw framebuffer.
fn framebuffer(cmd: &[&str], kernel: &str, scene: &[&str], chip: &[&str], tag: &str) -> Vec<u8> {
    let raw = scratch("fb").join(format!("{tag}.fb"));
    let raw_s = raw.to_str().unwrap();
    let args = [cmd, &[kernel], scene, chip, &["--raw-framebuffer", raw_s]].concat();
    trax(&args);
    std::fs::read(&raw).unwrap()
}

/// Index of the first differing f32 (as pixel, channel), for messages.
fn first_difference(a: &[u8], b: &[u8]) -> String {
    match a.chunks(4).zip(b.chunks(4)).position(|(x, y)| x != y) {
        Some(k) => format!("first difference at pixel {} channel {}", k / 3, k % 3),
        None => format!("lengths {} and {}", a.len(), b.len()),
    }
}

/// Every way of running `kernel` gives the reference (default `trax run`) framebuffer.
fn same_everywhere(kernel: &str, scene: &[&str]) {
    let name = Path::new(kernel).file_stem().unwrap().to_str().unwrap();
    let reference = framebuffer(&["run"], kernel, scene, &[], &format!("{name}-run"));
    assert!(
        reference.iter().any(|&b| b != 0),
        "{kernel}: black image (the comparison would be vacuous)"
    );
    let others: [(&[&str], &[&str], &str); 6] = [
        (&["run"], &["--tms", "2", "--threads", "3"], "run-2x3"),
        (
            &["run"],
            &["--config", "baseline", "--tms", "3", "--l2s", "1"],
            "run-baseline-3",
        ),
        (
            &["run", "--functional"],
            &["--tms", "3", "--threads", "5"],
            "functional-3x5",
        ),
        (
            &["run", "--functional"],
            &["--threads", "1"],
            "functional-1",
        ),
        (&["native"], &[], "native"),
        (&["native"], &["--tms", "2", "--threads", "7"], "native-2x7"),
    ];
    for (cmd, chip, tag) in others {
        let fb = framebuffer(cmd, kernel, scene, chip, &format!("{name}-{tag}"));
        assert!(
            fb == reference,
            "{kernel}: {tag} differs from the default `trax run` ({})",
            first_difference(&fb, &reference)
        );
    }
}

const SMALL_CORNELL: [&str; 10] = [
    "--scene", "cornell", "--width", "16", "--height", "12", "--spp", "2", "--depth", "3",
];

#[test]
fn pathtracer_image_does_not_depend_on_the_chip_or_native() {
    same_everywhere("examples/pathtracer.rs", &SMALL_CORNELL);
}

#[test]
fn ao_image_does_not_depend_on_the_chip_or_native() {
    same_everywhere("examples/ao.rs", &SMALL_CORNELL);
}

/// A kernel that reads the triangles but not the BVH sees them in the scene file's order,
/// under `trax run` and `trax native` alike (native used to lay out every component, so
/// its triangles were in BVH leaf order).
#[test]
fn triangles_are_in_file_order_in_run_and_native_without_a_bvh() {
    let kernel = "tests/kernels/triangle_order.rs";
    let scene = ["--scene", "cornell", "--width", "8", "--height", "8"];
    let run = framebuffer(&["run", "--functional"], kernel, &scene, &[], "order-run");
    let native = framebuffer(&["native"], kernel, &scene, &[], "order-native");
    assert!(
        run == native,
        "run vs native: {}",
        first_difference(&run, &native)
    );
    let cornell = load_scene("cornell", &LoadOptions::default()).unwrap();
    let f = |k: usize| f32::from_le_bytes(run[4 * k..4 * k + 4].try_into().unwrap());
    for (i, t) in cornell.triangles.iter().enumerate() {
        let got = [f(3 * i), f(3 * i + 1), f(3 * i + 2)];
        assert_eq!(got, t[0], "triangle {i}: first vertex");
    }
}

/// `trax run` and `trax native` without chip flags run the same number of threads (the
/// hello example prints one line per thread, with the thread count).
#[test]
fn run_and_native_default_to_the_same_threads() {
    let run = trax(&["run", "examples/hello.rs"]);
    let functional = trax(&["run", "--functional", "examples/hello.rs"]);
    let native = trax(&["native", "examples/hello.rs"]);
    let lines = |o: &Output| {
        let mut l: Vec<String> = String::from_utf8_lossy(&o.stdout)
            .lines()
            .map(str::to_string)
            .collect();
        l.sort();
        l
    };
    let hellos = |o: &Output| lines(o).iter().filter(|l| l.starts_with("hello")).count();
    // The default chip is `tiny`: 1 TM of 8 threads.
    assert_eq!(hellos(&run), 8, "{:?}", lines(&run));
    assert_eq!(lines(&run), lines(&native));
    assert_eq!(lines(&functional), lines(&native));
    // And a chip config file sets native's shape as it sets run's.
    let cfg = scratch("config").join("chip.toml");
    std::fs::write(&cfg, "preset = \"tiny\"\ntms = 2\nthreads_per_tm = 3\n").unwrap();
    let cfg = cfg.to_str().unwrap();
    let run = trax(&["run", "examples/hello.rs", "--config", cfg]);
    let native = trax(&["native", "examples/hello.rs", "--config", cfg]);
    assert_eq!(hellos(&run), 6, "{:?}", lines(&run));
    assert_eq!(lines(&run), lines(&native));
}

/// The other image examples take pixels from `atomic_inc` and use no random numbers: their
/// images are chip-independent too.
#[test]
fn other_examples_images_do_not_depend_on_the_chip_or_native() {
    for kernel in [
        "examples/raycast.rs",
        "examples/gradient.rs",
        "examples/mandelbrot.rs",
        "examples/mandelbrot_simd.rs",
    ] {
        same_everywhere(kernel, &SMALL_CORNELL);
    }
}

/// The BVH's layout is the chip's (`[treelets]`), and it changes where nodes and triangles
/// lie, not what a ray hits: the path tracer draws the same image on the BVH in build
/// order and on row-aligned treelets (`form = "always"`), under `trax run` and `trax
/// native` given the same chip flags. The layouts are checked to differ (padding makes the
/// node array larger), so the comparison is not vacuous.
#[test]
fn pathtracer_image_does_not_depend_on_the_treelet_layout() {
    let kernel = "examples/pathtracer.rs";
    let scene = [
        "--scene",
        "procedural:3000",
        "--width",
        "16",
        "--height",
        "12",
        "--spp",
        "2",
        "--depth",
        "3",
    ];
    let treelets = [
        "--set",
        "treelets.form=always",
        "--set",
        "treelets.align=dram-row",
        "--set",
        "treelets.bytes=8192",
    ];
    let build_order = ["--config", "baseline-ch5", "--tms", "2", "--threads", "4"];
    let aligned = [&build_order[..], &treelets].concat();
    let strata_plus = [
        &["--config", "strata-plus", "--tms", "2", "--threads", "4"][..],
        &treelets[..2],
    ]
    .concat();
    let reference = framebuffer(
        &["run", "--functional"],
        kernel,
        &scene,
        &build_order,
        "layout-build-order",
    );
    assert!(reference.iter().any(|&b| b != 0), "black image");
    for (cmd, chip, tag) in [
        (&["run", "--functional"][..], &aligned[..], "layout-aligned"),
        (&["run"][..], &aligned[..], "layout-aligned-timing"),
        (
            &["run", "--functional"][..],
            &strata_plus[..],
            "layout-strata-plus",
        ),
        (&["native"][..], &aligned[..], "layout-native-aligned"),
    ] {
        let fb = framebuffer(cmd, kernel, &scene, chip, tag);
        assert!(
            fb == reference,
            "{tag} differs from the build-order layout ({})",
            first_difference(&fb, &reference)
        );
    }
    // The layouts differ: the run summary's node array bytes.
    let nodes = |chip: &[&str]| -> u64 {
        let out = trax(&[&["run", "--functional", kernel], &scene[..], chip].concat());
        let err = String::from_utf8_lossy(&out.stderr).into_owned();
        let line = err
            .lines()
            .find(|l| l.trim_start().starts_with("bvh_nodes"))
            .unwrap_or_else(|| panic!("no bvh_nodes line in:\n{err}"));
        line.split_whitespace().nth(1).unwrap().parse().unwrap()
    };
    let (plain, padded) = (nodes(&build_order), nodes(&aligned));
    assert!(
        padded > plain,
        "node bytes {plain} (build order) vs {padded} (aligned)"
    );
}
