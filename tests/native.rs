//! End-to-end tests of `trax native`: the example kernels built with rustc against the
//! host prelude and run on host threads.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

mod common;
use common::{native_cache, scratch_dir, text, trax_command};

/// A scratch directory for this test (outputs and a private build cache).
fn scratch(name: &str) -> PathBuf {
    scratch_dir(&format!("native-{name}"))
}

/// Runs `trax native ARGS` with a build cache in the target directory (keyed by content,
/// so it is safe to keep between runs).
fn native(args: &[&str]) -> Output {
    let cache = native_cache();
    trax_command()
        .arg("native")
        .args(args)
        .env("TRAX_CACHE_DIR", &cache)
        .env_remove("RUST_BACKTRACE")
        .output()
        .expect("run trax")
}

/// Decodes an 8-bit RGB PNG: (width, height, pixels).
fn read_png(path: &Path) -> (u32, u32, Vec<u8>) {
    let dec = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(path).unwrap()));
    let mut r = dec.read_info().unwrap();
    let mut buf = vec![0; r.output_buffer_size()];
    let info = r.next_frame(&mut buf).unwrap();
    assert_eq!(info.color_type, png::ColorType::Rgb);
    assert_eq!(info.bit_depth, png::BitDepth::Eight);
    buf.truncate(info.buffer_size());
    (info.width, info.height, buf)
}

#[test]
fn hello_prints_every_thread_in_order() {
    let out = native(&["examples/hello.rs", "--tms", "2", "--threads", "3"]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let stdout = text(&out.stdout);
    let mut want = String::new();
    for id in 0..6u32 {
        want += &format!(
            "hello from thread {id} of 6 (TM {}, thread {})\n",
            id / 3,
            id % 3
        );
        let x = id as f32 * 0.5 + 0.25;
        want += &format!(
            "  x = {x}, x * x = {}, even = {}, neg = {}\n",
            x * x,
            id % 2 == 0,
            -(id as i32)
        );
    }
    assert_eq!(stdout, want);
}

#[test]
fn gradient_image() {
    let dir = scratch("gradient");
    let png = dir.join("g.png");
    let out = native(&[
        "examples/gradient.rs",
        "--width",
        "40",
        "--height",
        "30",
        "--threads",
        "4",
        "-o",
        png.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let (w, h, px) = read_png(&png);
    assert_eq!((w, h), (40, 30));
    let at = |x: u32, y: u32| {
        let i = ((y * w + x) * 3) as usize;
        (px[i], px[i + 1], px[i + 2])
    };
    for (x, y) in [(0, 0), (39, 0), (0, 29), (17, 11), (39, 29)] {
        let r = ((x as f32 + 0.5) / 40.0 * 255.0 + 0.5) as u8;
        let g = ((y as f32 + 0.5) / 30.0 * 255.0 + 0.5) as u8;
        assert_eq!(at(x, y), (r, g, 64), "pixel ({x}, {y})");
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn mandelbrot_scalar_and_simd_agree() {
    let dir = scratch("mandel");
    let a = dir.join("scalar.png");
    let b = dir.join("simd.png");
    // 37 × 23 pixels: not a multiple of 4, so the SIMD kernel's tail is exercised.
    let size = [
        "--width",
        "37",
        "--height",
        "23",
        "--tms",
        "2",
        "--threads",
        "3",
    ];
    for (k, p) in [
        ("examples/mandelbrot.rs", &a),
        ("examples/mandelbrot_simd.rs", &b),
    ] {
        let mut args = vec![k];
        args.extend_from_slice(&size);
        args.extend_from_slice(&["-o", p.to_str().unwrap()]);
        let out = native(&args);
        assert!(out.status.success(), "{k}: {}", text(&out.stderr));
    }
    let (_, _, pa) = read_png(&a);
    let (_, _, pb) = read_png(&b);
    assert_eq!(pa, pb);
    // Both inside (black) and outside (coloured) points are present.
    assert!(pa.chunks(3).any(|p| p == [0, 0, 0]));
    assert!(pa.chunks(3).any(|p| p[2] > 100));
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn compile_errors_name_the_kernel_file() {
    let dir = scratch("bad");
    let k = dir.join("bad.rs");
    std::fs::write(&k, "fn trax_main() {\n    let x: u32 = \"no\";\n}\n").unwrap();
    let out = native(&[k.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(1));
    let err = text(&out.stderr);
    assert!(err.contains(&format!("{}:2:", k.display())), "{err}");
    assert!(err.contains("compilation failed"), "{err}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn kernel_panics_report_the_source_line_and_fail() {
    let dir = scratch("crash");
    let k = dir.join("crash.rs");
    std::fs::write(
        &k,
        "fn trax_main() {\n    let a = [1u32, 2];\n    let i = trax::global_id() + 5;\n    println!(\"{}\", a[i as usize]);\n}\n",
    )
    .unwrap();
    let out = native(&[k.to_str().unwrap(), "--threads", "2"]);
    assert_eq!(out.status.code(), Some(1));
    let err = text(&out.stderr);
    assert!(err.contains(&format!("{}:4:", k.display())), "{err}");
    assert!(err.contains("index out of bounds"), "{err}");
    assert!(err.contains("crashed"), "{err}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn mod_files_beside_the_kernel_resolve() {
    let dir = scratch("mods");
    std::fs::write(
        dir.join("helper.rs"),
        "pub fn twice(x: u32) -> u32 {\n    x * 2\n}\n",
    )
    .unwrap();
    let k = dir.join("k.rs");
    std::fs::write(
        &k,
        "mod helper;\nfn trax_main() {\n    println!(\"{}\", helper::twice(21));\n}\n",
    )
    .unwrap();
    let out = native(&[k.to_str().unwrap(), "--threads", "1"]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert_eq!(text(&out.stdout), "42\n");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn bad_arguments_are_errors() {
    let out = native(&["examples/does_not_exist.rs"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(text(&out.stderr).contains("does_not_exist.rs"));
    let out = native(&["examples/hello.rs", "--threads", "0"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(text(&out.stderr).contains("--threads"));
    let dir = scratch("noentry");
    let k = dir.join("k.rs");
    std::fs::write(&k, "fn main() {}\n").unwrap();
    let out = native(&[k.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(1));
    assert!(
        text(&out.stderr).contains("trax_main"),
        "{}",
        text(&out.stderr)
    );
    let out = native(&["examples/hello.rs", "--light", "/nonexistent.light"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(text(&out.stderr).contains("nonexistent.light"));
    let out = native(&["examples/hello.rs", "--view", "/nonexistent.view"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(text(&out.stderr).contains("nonexistent.view"));
    let out = native(&["examples/gradient.rs", "-o", "/nonexistent-dir/x.png"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(text(&out.stderr).contains("x.png"));
}

/// Renders `kernel` on the Cornell box; returns the decoded pixels.
fn render_cornell(kernel: &str, name: &str, extra: &[&str]) -> Vec<u8> {
    let dir = scratch(name);
    let png = dir.join("out.png");
    let mut args = vec![
        kernel, "--scene", "cornell", "--width", "32", "--height", "32",
    ];
    args.extend_from_slice(extra);
    args.extend_from_slice(&["-o", png.to_str().unwrap()]);
    let out = native(&args);
    assert!(out.status.success(), "{kernel}: {}", text(&out.stderr));
    let (w, h, px) = read_png(&png);
    assert_eq!((w, h), (32, 32));
    std::fs::remove_dir_all(&dir).ok();
    px
}

/// Mean colour of the pixels in columns `x0..x1`, rows `8..24` of a 32×32 image.
fn mean_rgb(px: &[u8], x0: usize, x1: usize) -> [f32; 3] {
    let mut s = [0.0; 3];
    let mut n = 0.0;
    for y in 8..24 {
        for x in x0..x1 {
            for c in 0..3 {
                s[c] += px[(y * 32 + x) * 3 + c] as f32;
            }
            n += 1.0;
        }
    }
    s.map(|v| v / n)
}

#[test]
fn raycast_shows_the_cornell_walls() {
    let px = render_cornell("examples/raycast.rs", "raycast", &["--threads", "4"]);
    // Red wall on the left, green wall on the right.
    let left = mean_rgb(&px, 0, 3);
    let right = mean_rgb(&px, 29, 32);
    assert!(left[0] > 2.0 * left[1] && left[0] > 40.0, "left {left:?}");
    assert!(
        right[1] > 2.0 * right[0] && right[1] > 20.0,
        "right {right:?}"
    );
}

#[test]
fn ao_and_pathtracer_render_and_are_deterministic() {
    let ao = render_cornell("examples/ao.rs", "ao", &["--spp", "4", "--threads", "4"]);
    let centre = mean_rgb(&ao, 8, 24);
    assert!(centre.iter().all(|&c| c > 10.0), "{centre:?}");
    let args = ["--spp", "2", "--depth", "3", "--tms", "2", "--threads", "3"];
    let a = render_cornell("examples/pathtracer.rs", "pt-a", &args);
    let b = render_cornell("examples/pathtracer.rs", "pt-b", &args);
    assert_eq!(a, b, "same configuration, same image");
    let left = mean_rgb(&a, 0, 3);
    assert!(left[0] > left[1], "red wall {left:?}");
    // The light, seen directly in the top rows, is saturated.
    let top = &a[..32 * 8 * 3];
    assert!(
        top.chunks(3).any(|p| p == [255, 255, 255]),
        "no light visible"
    );
}

/// White-furnace-style check of the path tracer: inside a closed cube whose walls all
/// emit `Le` and reflect diffusely with albedo `a`, every camera path sees exactly
/// `Le * (1 + a + ... + a^D)` in expectation for `--depth D` (emission on the camera ray,
/// then one next-event estimate per bounce). With `Le = 0.2`, `a = 0.5`, `D = 3` that is
/// 0.375, i.e. 95.6 in the 8-bit image. The mean over 32×32 pixels × 64 samples has a
/// relative standard error well under 1% (measured: -0.7% at 16 spp, +0.3% at 256 spp);
/// the test allows 3%.
#[test]
fn pathtracer_converges_in_a_closed_emissive_box() {
    let dir = scratch("furnace");
    let corners: Vec<[i32; 3]> = (0..8)
        .map(|i| [i >> 2 & 1, i >> 1 & 1, i & 1].map(|b| 2 * b - 1))
        .collect();
    let quads: [[usize; 4]; 6] = [
        [0, 4, 6, 2],
        [1, 5, 7, 3],
        [0, 4, 5, 1],
        [2, 6, 7, 3],
        [0, 2, 3, 1],
        [4, 6, 7, 5],
    ];
    let mut obj = String::from("mtllib furnace.mtl\n");
    for c in &corners {
        obj += &format!("v {} {} {}\n", c[0], c[1], c[2]);
    }
    obj += "usemtl wall\n";
    for q in quads {
        let [a, b, c, d] = q.map(|i| i + 1);
        obj += &format!("f {a} {b} {c}\nf {a} {c} {d}\n");
    }
    std::fs::write(dir.join("furnace.obj"), obj).unwrap();
    std::fs::write(
        dir.join("furnace.mtl"),
        "newmtl wall\nKd 0.5 0.5 0.5\nKe 0.2 0.2 0.2\n",
    )
    .unwrap();
    // Camera inside the box, off-centre, looking at a corner region.
    std::fs::write(
        dir.join("furnace.view"),
        "0.1 -0.2 0.05  0.3 1 0.2  0 0 1  0  -1 1 -1 1  1\n",
    )
    .unwrap();
    let png = dir.join("f.png");
    let scene = dir.join("furnace.obj");
    let out = native(&[
        "examples/pathtracer.rs",
        "--scene",
        scene.to_str().unwrap(),
        "--width",
        "32",
        "--height",
        "32",
        "--spp",
        "64",
        "--depth",
        "3",
        "--threads",
        "4",
        "-o",
        png.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let (_, _, px) = read_png(&png);
    let mean = px.iter().map(|&v| v as f64).sum::<f64>() / px.len() as f64;
    let expected = 0.2 * (1.0 + 0.5 + 0.25 + 0.125) * 255.0;
    assert!(
        (mean / expected - 1.0).abs() < 0.03,
        "mean {mean}, expected {expected}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// Writes a closed cube `[-s, s]^3` whose faces are `n × n` grids of quads (shared
/// edges and vertices everywhere), with a camera inside, as `dir/box.obj` + `.view`.
fn grid_cube(dir: &Path, s: f32, n: u32) -> PathBuf {
    let mut obj = String::from("mtllib box.mtl\nusemtl wall\n");
    let mut count = 0;
    // Face = (fixed axis, sign); the other two axes span the grid.
    for axis in 0..3 {
        for sign in [-1.0f32, 1.0] {
            let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
            for i in 0..=n {
                for j in 0..=n {
                    let mut p = [0.0f32; 3];
                    p[axis] = sign * s;
                    p[u] = s * (2.0 * i as f32 / n as f32 - 1.0);
                    p[v] = s * (2.0 * j as f32 / n as f32 - 1.0);
                    obj += &format!("v {:e} {:e} {:e}\n", p[0], p[1], p[2]);
                }
            }
            for i in 0..n {
                for j in 0..n {
                    let k = |a: u32, b: u32| count + a * (n + 1) + b + 1;
                    obj += &format!("f {} {} {}\n", k(i, j), k(i + 1, j), k(i + 1, j + 1));
                    obj += &format!("f {} {} {}\n", k(i, j), k(i + 1, j + 1), k(i, j + 1));
                }
            }
            count += (n + 1) * (n + 1);
        }
    }
    std::fs::write(dir.join("box.obj"), obj).unwrap();
    std::fs::write(dir.join("box.mtl"), "newmtl wall\nKd 1 1 1\n").unwrap();
    // Inside, off-centre, a wide field of view so rays cross many grid edges and corners.
    let e = [0.1 * s, -0.2 * s, 0.05 * s];
    std::fs::write(
        dir.join("box.view"),
        format!(
            "{:e} {:e} {:e}  1 1 1  0 0 1  0  -2 2 -2 2  1\n",
            e[0], e[1], e[2]
        ),
    )
    .unwrap();
    dir.join("box.obj")
}

/// Robustness: from inside a closed, finely tessellated cube at very small, unit and very
/// large scale, every primary ray must hit a wall (no holes at shared edges and vertices,
/// no lost BVH nodes) and no pixel may be NaN.
#[test]
fn closed_mesh_has_no_holes_at_any_scale() {
    for (k, scale) in [1e-4f32, 1.0, 1e5].into_iter().enumerate() {
        let dir = scratch(&format!("holes-{k}"));
        let obj = grid_cube(&dir, scale, 6);
        let raw = dir.join("fb.bin");
        let out = native(&[
            "examples/raycast.rs",
            "--scene",
            obj.to_str().unwrap(),
            "--width",
            "64",
            "--height",
            "64",
            "--threads",
            "4",
            "--raw-framebuffer",
            raw.to_str().unwrap(),
        ]);
        assert!(out.status.success(), "{}", text(&out.stderr));
        let fb: Vec<f32> = std::fs::read(&raw)
            .unwrap()
            .chunks(4)
            .map(|b| f32::from_le_bytes(b.try_into().unwrap()))
            .collect();
        assert_eq!(fb.len(), 64 * 64 * 3);
        for (i, px) in fb.chunks(3).enumerate() {
            assert!(
                px.iter().all(|c| !c.is_nan()),
                "scale {scale}: NaN at pixel {i}"
            );
            // A hit shows at least the ambient term (0.1 × albedo 1); a miss is black.
            assert!(px[0] >= 0.1, "scale {scale}: hole at pixel {i} ({px:?})");
        }
        std::fs::remove_dir_all(&dir).ok();
    }
}

/// A kernel that rustc builds but the trax compiler does not (a heap `Vec`) still runs
/// natively, with a warning that every scene component is laid out (there is no `trax run`
/// image to match); a kernel rustc rejects gets rustc's errors and no such warning.
#[test]
fn kernels_outside_the_trax_subset_run_with_a_warning() {
    let dir = scratch("outside-subset");
    let k = dir.join("k.rs");
    std::fs::write(
        &k,
        "fn trax_main() {\n    let v: Vec<u32> = (0..3).collect();\n    if trax::global_id() == 0 {\n        println!(\"{}\", v.len());\n    }\n}\n",
    )
    .unwrap();
    let out = native(&[k.to_str().unwrap()]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert_eq!(text(&out.stdout), "3\n");
    let err = text(&out.stderr);
    assert!(
        err.contains("warning:") && err.contains("the trax compiler cannot build this kernel"),
        "{err}"
    );
    assert!(err.contains("left out: none"), "{err}");
    let bad = dir.join("bad.rs");
    std::fs::write(&bad, "fn trax_main() {\n    let x: u32 = \"no\";\n}\n").unwrap();
    let out = native(&[bad.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(1));
    let err = text(&out.stderr);
    assert!(err.contains("mismatched types"), "{err}");
    assert!(!err.contains("trax compiler cannot build"), "{err}");
    std::fs::remove_dir_all(&dir).ok();
}

/// The kernel of `panic_messages_match_native`: `--width` picks the case; each case panics
/// on its own line (line = case + 3).
const PANICS: &str = r#"fn trax_main() {
    let case = trax::scene::width(); let id = trax::global_id(); let n = 4u32;
    let x = 5 + id as i32; let y = -2.5f32 + id as f32; let s = "q\"\n"; let c = '\''; let z = case as i32 - 12;
    if case == 1 { panic!("bad id {} of {}", id, n); }
    if case == 2 { unreachable!(); }
    if case == 3 { let a = [1u32, 2, 3, 4]; println!("{}", a[(id + 7) as usize]); }
    if case == 4 { assert!(x < 3); }
    if case == 5 { assert_eq!(x, 3); }
    if case == 6 { assert!(x<3 && !false, "x={} y={:?} s={:?} c={:?} {{}} {}", x, y, s, c, 1u64 << 40); }
    if case == 7 { assert_ne!(x, 5, "ne {}", x); }
    if case == 8 { unreachable!("at {}", x); }
    if case == 9 { todo!(); }
    if case == 10 { unimplemented!("nope {}", y); }
    if case == 11 { panic!(); }
    if case == 12 { println!("{}", 10 / z); }
    if case == 13 { println!("{}", (z - 2147483647 - 1) / (z - 1)); }
    if case == 14 { assert_eq!(y as f64 * 1e20, 0.5, "{} {:?} {:?}", -7i64 - id as i64, c, y); }
    if case == 15 { println!("{}", 10 % (z - 3)); }
    if case == 16 { debug_assert!(false, "debug assertions are off"); panic!("after {}", y); }
    if case == 17 { assert!(trax::scene::height() as usize
        == [1, 2].len()); }
    if case == 19 { let a = [1u32, 2, 3]; let s: &[u32] = &a[1..]; println!("{}", s[(id + 2) as usize]); }
    if case == 20 { let a = [1u32, 2, 3]; let e = 4 + id as usize; println!("{:?}", &a[..e]); }
    if case == 21 { let a = [1u32, 2, 3]; let b = 2 + id as usize; println!("{:?}", &a[b..1]); }
    if case == 22 { #[derive(Debug, PartialEq)] struct P { x: i32, t: (f32, char) } assert_eq!(P { x, t: (y, c) }, P { x: 0, t: (0.5, 'a') }, "p {:?}", Some(x)); }
    if case == 23 { let r: Result<u8, (i32, bool)> = Err((x, true)); println!("{}", r.is_ok()); panic!("{:?} {:>6.2}", r, y); }
}
"#;

/// Each panicking macro, bounds check and division check prints the same message at the
/// same source location under `trax run` (crash report) and `trax native` (Rust's panic
/// handler): formatted arguments, `{:?}`, assert_eq!'s left/right, bounds index and length.
#[test]
fn panic_messages_match_native() {
    let dir = scratch("panics");
    let k = dir.join("panics.rs");
    std::fs::write(&k, PANICS).unwrap();
    let k = k.to_str().unwrap();
    for case in (1..=17u32).chain(19..=23) {
        let w = case.to_string();
        let args = [k, "--threads", "1", "--width", &w, "--height", "1"];
        let nat = native(&args);
        assert_eq!(nat.status.code(), Some(1), "case {case}");
        let nerr = text(&nat.stderr);
        // "thread '...' panicked at FILE:L:C:\nMESSAGE\nstack backtrace:|note: ..."
        let (_, rest) = nerr
            .split_once("panicked at ")
            .unwrap_or_else(|| panic!("case {case}: {nerr}"));
        let (loc, rest) = rest.split_once(":\n").unwrap();
        let nloc = loc.rsplitn(3, ':').take(2).collect::<Vec<_>>();
        let end = ["\nstack backtrace:", "\nnote:"]
            .iter()
            .filter_map(|m| rest.find(m))
            .min()
            .unwrap_or(rest.len());
        let nmsg = &rest[..end];

        let out = trax_command()
            .args(["run", "--functional"])
            .args(args)
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(1), "case {case}");
        let eerr = text(&out.stderr);
        let (_, rest) = eerr
            .split_once("  what: panicked: ")
            .unwrap_or_else(|| panic!("case {case}: {eerr}"));
        let emsg = rest
            .split_once("\n  pc:")
            .unwrap()
            .0
            .replace("\n        ", "\n");
        let eloc = eerr.split_once("  at:   ").unwrap().1;
        let eloc = eloc.split_once(" in ").unwrap().0;
        let eloc = eloc.rsplitn(3, ':').take(2).collect::<Vec<_>>();
        assert_eq!(emsg, nmsg, "case {case}: message\n{eerr}\n{nerr}");
        assert_eq!(eloc, nloc, "case {case}: line and column\n{eerr}\n{nerr}");
        assert_eq!(
            nloc[1],
            (case + 3).to_string(),
            "case {case}: the panicking line"
        );
    }
}

/// The fused pipelines give the same results natively and on the machine, and a test in
/// the wrong `trax.setpipe` mode fails on both with the source line.
#[test]
fn pipeline_modes_are_checked_natively_as_on_the_machine() {
    let dir = scratch("pipes");
    let k = dir.join("pipes.rs");
    std::fs::write(
        &k,
        "use trax::{pipe, Vec3};\n\
         fn trax_main() {\n\
         \x20   let inf = f32::INFINITY;\n\
         \x20   let o = Vec3::new(-1.0, 0.5, 0.5);\n\
         \x20   let inv = Vec3::new(1.0, inf, inf);\n\
         \x20   let lo = Vec3::new(0.0, 0.0, 0.0);\n\
         \x20   let hi = Vec3::new(1.0, 1.0, 1.0);\n\
         \x20   pipe::use_box_pipeline();\n\
         \x20   println!(\"{}\", pipe::box_test(o, inv, lo, hi));\n\
         \x20   pipe::use_triangle_pipeline();\n\
         \x20   println!(\"{}\", pipe::box_test(o, inv, lo, hi));\n\
         }\n",
    )
    .unwrap();
    let ks = k.to_str().unwrap();
    let shape = ["--tms", "1", "--threads", "1"];
    let nat = native(&[&[ks][..], &shape].concat());
    let emu = Command::new(env!("CARGO_BIN_EXE_trax"))
        .args([&["run", ks, "--config", "baseline"][..], &shape].concat())
        .output()
        .unwrap();
    for (what, out) in [("native", &nat), ("emulator", &emu)] {
        assert_eq!(out.status.code(), Some(1), "{what}");
        assert_eq!(text(&out.stdout), "1\n", "{what}");
        let err = text(&out.stderr);
        assert!(
            err.contains("trax.boxtest while this TM's units are in triangle-pipeline mode"),
            "{what}: {err}"
        );
    }
    assert!(
        text(&emu.stderr).contains(&format!("{ks}:11")),
        "{}",
        text(&emu.stderr)
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// The shipped scenes' path-traced images are viewable with default flags, their `.light`
/// files (a position, intensity 1) as they are: auto exposure brightens the PNG by whole
/// stops (before it, Sponza had a mean of 0.3% of white and 93% black pixels), and the raw
/// framebuffer is the unscaled radiance. Bounds: mean between 5% and 40% of white (a dark
/// interior lit by one point light, noisy at 4 spp; 0.09..0.18 is auto's target before
/// clipping), at most 20% of pixels pure black.
#[test]
fn path_traced_shipped_scenes_are_viewable_with_default_flags() {
    let dir = scratch("viewable");
    for scene in ["sponza/sponza", "sibenik/sibenik"] {
        let obj = format!("../shared/scenes/{scene}.obj");
        let name = scene.split('/').next().unwrap();
        let png = dir.join(format!("{name}.png"));
        let raw = dir.join(format!("{name}.raw"));
        let out = native(&[
            "examples/pathtracer.rs",
            "--scene",
            &obj,
            "--spp",
            "4",
            "--width",
            "64",
            "--height",
            "64",
            "-o",
            png.to_str().unwrap(),
            "--raw-framebuffer",
            raw.to_str().unwrap(),
        ]);
        let err = text(&out.stderr);
        assert!(out.status.success(), "{scene}: {err}");
        let (w, h, px) = read_png(&png);
        assert_eq!((w, h), (64, 64));
        let mean = px.iter().map(|&v| f64::from(v)).sum::<f64>() / px.len() as f64 / 255.0;
        let black = px.chunks(3).filter(|p| p == &[0, 0, 0]).count() as f64 / 4096.0;
        assert!((0.05..0.4).contains(&mean), "{scene}: mean {mean}");
        assert!(black <= 0.2, "{scene}: {black} black");
        // The exposure is said, and the PNG is the raw framebuffer at that exposure.
        let ev: f32 = err
            .split("(exposure auto, ")
            .nth(1)
            .and_then(|s| s.split(" EV)").next())
            .and_then(|s| s.parse().ok())
            .unwrap_or_else(|| panic!("{scene}: no exposure in {err}"));
        assert!(ev >= 1.0, "{scene}: a dark image is brightened ({ev})");
        let fb = std::fs::read(&raw).unwrap();
        let raw_mean = fb
            .chunks(4)
            .map(|b| f64::from(f32::from_le_bytes([b[0], b[1], b[2], b[3]])))
            .sum::<f64>()
            / 12288.0;
        assert!(
            raw_mean < 0.02,
            "{scene}: the raw framebuffer is not scaled ({raw_mean})"
        );
        for (i, &p) in px.iter().enumerate() {
            let v = f32::from_le_bytes(fb[4 * i..4 * i + 4].try_into().unwrap());
            let want = ((v * ev.exp2()).clamp(0.0, 1.0) * 255.0 + 0.5) as u8;
            assert_eq!(p, want, "{scene}: value {i}");
        }
    }
    std::fs::remove_dir_all(&dir).ok();
}
