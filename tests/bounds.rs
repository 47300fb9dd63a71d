//! Out-of-bounds accesses to scene components fault in both run modes: an index just past
//! the end (or just before the start) of any component must not land in mapped slack or in
//! the next component. Once a store to `framebuffer[w*h + k]` (k up to ~340) ran with
//! exit 0, because the framebuffer's last 4 KiB page was mapped whole.

use std::path::{Path, PathBuf};
use std::process::Output;

mod common;
use common::{scratch_dir, text, trax};

/// Selects a component and an element index from `--seed`: `component * 1000 + mode * 500
/// + k`; mode 0 reads element `count + k - 250` (k = 249 is the last element), mode 1 reads
/// element `-k` (wrapping, so the address lies before the component).
const KERNEL: &str = r#"
use trax::scene::*;

fn trax_main() {
    if trax::global_id() != 0 {
        return;
    }
    let sel = seed();
    let comp = sel / 1000;
    let mode = sel % 1000 / 500;
    let k = sel % 500;
    let nodes = bvh_node_count();
    let pixels = width() * height();
    let count = match comp {
        0 => 1,
        1 => pixels,
        2 => triangle_count(),
        3 => normals_count(),
        4 => texcoords_count(),
        5 => triangle_count(),
        6 => material_count(),
        7 => emitter_count(),
        8 => point_light_count(),
        9 => nodes,
        10 => nodes,
        _ => nodes,
    };
    let i = if mode == 0 {
        count.wrapping_add(k).wrapping_sub(250)
    } else {
        0u32.wrapping_sub(k)
    };
    let mut acc = 0.0f32;
    let mut bits = 0u32;
    match comp {
        0 => acc = trax::load_f32(camera_addr() + trax::layout::CAM_SIZE * i),
        1 => set_pixel_index(i, trax::math::Vec3::splat(1.0)),
        2 => acc = triangle(i).v2.z,
        3 => acc = shading_normal(i, 0.25, 0.25).x,
        4 => acc = texcoord(i, 0.25, 0.25).y,
        5 => bits = material_id(i),
        6 => acc = material(i).emission.z + material(i).shininess,
        7 => bits = emitter(i),
        8 => acc = point_light(i).color.z,
        9 => bits = bvh_node(i).b,
        10 => bits = bvh_parent(i),
        _ => bits = treelet_id(i),
    }
    println!("ok {} {}", acc, bits);
}
"#;

const NAMES: [&str; 12] = [
    "camera",
    "framebuffer",
    "triangles",
    "normals",
    "texcoords",
    "material_ids",
    "materials",
    "emitters",
    "point_lights",
    "bvh_nodes",
    "bvh_parents",
    "treelet_ids",
];

fn build() -> PathBuf {
    let d = scratch_dir("bounds");
    let src = d.join("bounds.rs");
    std::fs::write(&src, KERNEL).unwrap();
    let elf = d.join("bounds.elf");
    let out = trax(&["build", src.to_str().unwrap(), "-o", elf.to_str().unwrap()]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    elf
}

fn run(elf: &Path, seed: u32, timing: bool) -> Output {
    let seed = seed.to_string();
    let mut args = vec![
        "run",
        elf.to_str().unwrap(),
        "--width",
        "20",
        "--height",
        "15",
    ];
    args.extend(["--seed", &seed, "--threads", "1"]);
    if !timing {
        args.push("--functional");
    }
    trax(&args)
}

#[test]
fn every_component_is_bounded_in_both_run_modes() {
    let elf = build();
    let mut failures = Vec::new();
    for timing in [false, true] {
        let mode = if timing { "timing" } else { "functional" };
        for (c, name) in NAMES.iter().enumerate() {
            let base = c as u32 * 1000;
            // The last element is fine (every component of the Cornell box is non-empty).
            let out = run(&elf, base + 249, timing);
            if !out.status.success() {
                failures.push(format!(
                    "{mode} {name}[count - 1] crashed:\n{}",
                    text(&out.stderr)
                ));
            }
            // Just past the end, a few elements on, the framebuffer's reported k = 300, and
            // just before the start.
            let mut cases = vec![(base + 250, "count"), (base + 253, "count + 3")];
            if *name == "framebuffer" {
                cases.push((base + 499, "count + 249"));
            }
            cases.push((base + 501, "-1"));
            for (seed, what) in cases {
                let out = run(&elf, seed, timing);
                let err = text(&out.stderr);
                if out.status.success() || !err.contains("bad address") {
                    failures.push(format!(
                        "{mode} {name}[{what}] did not fault (exit {:?}):\n{}{err}",
                        out.status.code(),
                        text(&out.stdout)
                    ));
                }
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// Stores through a pointer into the kernel's own code (`--seed 1`: the start-up code at
/// `TEXT_BASE`) or into read-only scene data (`--seed 2`: the camera).
const STORE_KERNEL: &str = r#"
fn trax_main() {
    if trax::global_id() != 0 {
        return;
    }
    let addr = if trax::scene::seed() == 1 { 0x0010_0000 } else { trax::scene::camera_addr() };
    trax::store_u32(addr, 0); // STORE
    println!("stored");
}
"#;

/// Program text and scene data are read-only in both run modes: the store faults, and the
/// report names the fault, the segment and the kernel's source line. (`trax run` once
/// loaded every segment writable, so such a store silently changed memory; worse for
/// text, the predecoded code no longer matched memory.)
#[test]
fn stores_to_code_and_scene_data_fault_in_both_run_modes() {
    let d = scratch_dir("code_store");
    let src = d.join("code_store.rs");
    std::fs::write(&src, STORE_KERNEL).unwrap();
    let line = STORE_KERNEL
        .lines()
        .position(|l| l.contains("// STORE"))
        .unwrap()
        + 1;
    let at = format!("code_store.rs:{line}");
    for timing in [false, true] {
        for (seed, segment) in [("1", "segment `text`"), ("2", "segment `camera`")] {
            let mut args = vec!["run", src.to_str().unwrap(), "--seed", seed];
            args.extend(["--width", "4", "--height", "4", "--threads", "1"]);
            if !timing {
                args.push("--functional");
            }
            let out = trax(&args);
            let err = text(&out.stderr);
            let what = format!("timing={timing} seed={seed}");
            assert!(!out.status.success(), "{what}: the store ran:\n{err}");
            assert!(!text(&out.stdout).contains("stored"), "{what}");
            for needle in ["store to read-only memory", segment, at.as_str()] {
                assert!(err.contains(needle), "{what}: no `{needle}` in:\n{err}");
            }
        }
    }
}
