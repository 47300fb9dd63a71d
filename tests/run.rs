//! End-to-end tests of `trax build` and `trax run`: kernel source to image, crash
//! reports by source line, and clear errors for bad input.

use std::path::{Path, PathBuf};
use std::process::Command;

mod common;
use common::{read_json, root, scratch_dir, text, trax, trax_command};

fn scratch(name: &str) -> PathBuf {
    scratch_dir(&format!("run-{name}"))
}

#[test]
fn hello_runs_from_source_with_every_thread() {
    let out = trax(&["run", "examples/hello.rs", "--tms", "2", "--threads", "3"]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let stdout = text(&out.stdout);
    for id in 0..6u32 {
        let line = format!(
            "hello from thread {id} of 6 (TM {}, thread {})",
            id / 3,
            id % 3
        );
        assert!(stdout.contains(&line), "missing {line:?} in\n{stdout}");
    }
}

#[test]
fn build_then_run_the_executable_gives_the_same_image() {
    let dir = scratch("build");
    let elf = dir.join("gradient.elf");
    let out = trax(&["build", "examples/gradient.rs", "-o", elf.to_str().unwrap()]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let bytes = std::fs::read(&elf).unwrap();
    assert_eq!(&bytes[..4], b"\x7fELF");
    assert_eq!(u16::from_le_bytes([bytes[16], bytes[17]]), 2, "ET_EXEC");

    let from_elf = dir.join("a.png");
    let from_src = dir.join("b.png");
    let size = ["--width", "24", "--height", "16"];
    let out = trax(
        &[
            &[
                "run",
                elf.to_str().unwrap(),
                "-o",
                from_elf.to_str().unwrap(),
            ][..],
            &size,
        ]
        .concat(),
    );
    assert!(out.status.success(), "{}", text(&out.stderr));
    let out = trax(
        &[
            &[
                "run",
                "examples/gradient.rs",
                "-o",
                from_src.to_str().unwrap(),
            ][..],
            &size,
        ]
        .concat(),
    );
    assert!(out.status.success(), "{}", text(&out.stderr));
    let a = std::fs::read(&from_elf).unwrap();
    assert_eq!(a, std::fs::read(&from_src).unwrap());
    let dec = png::Decoder::new(std::io::BufReader::new(
        std::fs::File::open(&from_elf).unwrap(),
    ));
    let info = dec.read_info().unwrap().info().clone();
    assert_eq!((info.width, info.height), (24, 16));
}

#[test]
fn out_of_bounds_crash_names_the_source_line() {
    let dir = scratch("crash");
    let k = dir.join("oob.rs");
    std::fs::write(
        &k,
        "fn get(a: &[u32; 4], i: u32) -> u32 {\n    a[i as usize]\n}\n\nfn trax_main() {\n    let a = [1u32, 2, 3, 4];\n    let v = get(&a, trax::global_id() + 3);\n    println!(\"v = {}\", v);\n}\n",
    )
    .unwrap();
    // Functional mode runs thread 0 to its end first (deterministic interleaving). The
    // cycle-level model interleaves per cycle: thread 1 fills in its panic message (index
    // and length) and aborts a few cycles before thread 0's one formatted print (its
    // argument record filled first), so nothing is printed.
    for (mode, stdout) in [("--functional", "v = 4\n"), ("--config=tiny", "")] {
        let out = trax(&["run", k.to_str().unwrap(), "--threads", "2", mode]);
        assert_eq!(out.status.code(), Some(1), "{}", text(&out.stderr));
        let err = text(&out.stderr);
        assert!(err.contains("thread 1"), "{mode}: {err}");
        // Rust's message with the index and the length, as `trax native` prints it.
        assert!(
            err.contains("what: panicked: index out of bounds: the len is 4 but the index is 4\n"),
            "{mode}: {err}"
        );
        assert!(err.contains("oob.rs:2:5"), "{mode}: {err}");
        assert!(err.contains("a[i as usize]"), "{mode}: {err}");
        assert_eq!(text(&out.stdout), stdout, "{mode}");
    }
}

#[test]
fn compile_errors_point_at_the_source() {
    let dir = scratch("diag");
    let k = dir.join("bad.rs");
    std::fs::write(&k, "fn trax_main() {\n    let x: u32 = 1.5;\n}\n").unwrap();
    for cmd in ["run", "build"] {
        let mut args = vec![cmd, k.to_str().unwrap()];
        if cmd == "build" {
            args.extend(["-o", "/dev/null"]);
        }
        let out = trax(&args);
        assert_eq!(out.status.code(), Some(1), "{cmd}");
        let err = text(&out.stderr);
        assert!(err.contains("bad.rs:2:"), "{cmd}: {err}");
        // Rendered diagnostics carry their own `error[id]:` prefix; the CLI adds none.
        // The kernel is not Rust: rustc's check names it, with rustc's code.
        assert!(
            err.starts_with("error[E0308]: mismatched types"),
            "{cmd}: {err}"
        );
        assert!(!err.contains("error: error"), "{cmd}: {err}");
    }
}

#[test]
fn bad_inputs_are_named() {
    let out = trax(&["run", "/nonexistent/kernel.elf"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(text(&out.stderr).contains("/nonexistent/kernel.elf"));

    let out = trax(&["run", "examples/hello.rs", "--scene", "/nonexistent.obj"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(text(&out.stderr).contains("nonexistent.obj"));

    let out = trax(&["run", "examples/hello.rs", "--threads", "0"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(text(&out.stderr).contains("--threads"));

    let out = trax(&["run", "examples/hello.rs", "--width", "0"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(text(&out.stderr).contains("--width"));

    let dir = scratch("notelf");
    let f = dir.join("junk.elf");
    std::fs::write(&f, b"not an elf").unwrap();
    let out = trax(&["run", f.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(1));
    assert!(
        text(&out.stderr).contains("junk.elf"),
        "{}",
        text(&out.stderr)
    );
}

/// `--scene-scale` and `icosphere:N` from the command line: a scaled run works, `trax scene
/// info` shows the scaled bounds, and unusable scales are errors naming the flag's value.
#[test]
fn scene_scale_flag() {
    let out = trax(&[
        "run",
        "examples/raycast.rs",
        "--functional",
        "--scene",
        "icosphere:2",
        "--scene-scale",
        "1e-20",
        "--width",
        "8",
        "--height",
        "8",
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let out = trax(&["scene", "info", "cornell", "--scene-scale", "1e20"]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let info = text(&out.stdout);
    assert!(info.contains("5.56e22"), "{info}");
    for bad in ["0", "-2", "1e36"] {
        let out = trax(&["scene", "info", "cornell", "--scene-scale", bad]);
        assert_eq!(out.status.code(), Some(1), "{bad}");
        assert!(
            text(&out.stderr).contains("scene scale"),
            "{}",
            text(&out.stderr)
        );
        let out = trax(&["run", "examples/hello.rs", "--scene-scale", bad]);
        assert_eq!(out.status.code(), Some(1), "{bad}");
        assert!(
            text(&out.stderr).contains("scene scale"),
            "{}",
            text(&out.stderr)
        );
    }
}

/// The acceptance check: the same path-tracer run on 1 and 2 host threads writes
/// identical JSON statistics and an identical image (4 TMs of detailed-DRAM baseline chip).
#[test]
fn host_threads_give_identical_stats_and_image() {
    let dir = scratch("host-threads");
    let run = |n: &str| {
        let json = dir.join(format!("stats{n}.json"));
        let png = dir.join(format!("img{n}.png"));
        let out = trax(&[
            "run",
            "examples/pathtracer.rs",
            "--config",
            "baseline",
            "--tms",
            "4",
            "--threads",
            "8",
            "--width",
            "24",
            "--height",
            "24",
            "--host-threads",
            n,
            "--stats-json",
            json.to_str().unwrap(),
            "-o",
            png.to_str().unwrap(),
        ]);
        assert!(out.status.success(), "{}", text(&out.stderr));
        assert!(
            text(&out.stderr).contains(&format!("on {n} host thread(s)")),
            "{}",
            text(&out.stderr)
        );
        (std::fs::read(json).unwrap(), std::fs::read(png).unwrap())
    };
    let (json1, png1) = run("1");
    let (json2, png2) = run("2");
    assert!(json1.len() > 1000);
    assert_eq!(text(&json1), text(&json2));
    assert_eq!(png1, png2);
}

#[test]
fn more_host_threads_than_cores_warns() {
    let dir = scratch("host-threads-warning");
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let n = (cores + 1).to_string();
    let png = dir.join("img.png");
    let run = |host_threads: &str| {
        let out = trax(&[
            "run",
            "examples/pathtracer.rs",
            "--tms",
            &n,
            "--width",
            "8",
            "--height",
            "8",
            "--host-threads",
            host_threads,
            "-o",
            png.to_str().unwrap(),
        ]);
        assert!(out.status.success(), "{}", text(&out.stderr));
        text(&out.stderr)
    };
    let warned = run(&n);
    assert!(
        warned.contains(&format!(
            "warning: {n} host threads on {cores} available core(s)"
        )),
        "{warned}"
    );
    let quiet = run("1");
    assert!(!quiet.contains("host threads on"), "{quiet}");
}

/// The run summary and the stats JSON list every scene component's bytes and the
/// components left out because the kernel never references them, in timing and in
/// functional mode; the ELF's symbol names (an independent look at the references) agree.
#[test]
fn run_reports_scene_components_and_what_was_left_out() {
    let dir = scratch("components");
    let all = [
        "bvh_nodes",
        "triangles",
        "normals",
        "texcoords",
        "material_ids",
        "materials",
        "emitters",
        "point_lights",
        "bvh_parents",
        "treelet_ids",
        "tri_treelet_ids",
        "tri_leaf_ids",
    ];
    for (kernel, left_out) in [
        (
            "examples/pathtracer.rs",
            &[
                "normals",
                "texcoords",
                "bvh_parents",
                "treelet_ids",
                "tri_treelet_ids",
                "tri_leaf_ids",
            ][..],
        ),
        ("examples/mandelbrot.rs", &all[..]),
    ] {
        let elf = dir.join("k.elf");
        let out = trax(&["build", kernel, "-o", elf.to_str().unwrap()]);
        assert!(out.status.success(), "{}", text(&out.stderr));
        let elf = std::fs::read(&elf).unwrap();
        let has_symbol = |field: &str| {
            let name = format!("__trax_scene_{field}\0");
            elf.windows(name.len()).any(|w| w == name.as_bytes())
        };
        for c in all {
            assert_eq!(
                has_symbol(c),
                !left_out.contains(&c),
                "{kernel}: symbol of {c}"
            );
        }
        for mode in [&[][..], &["--functional"][..]] {
            let json = dir.join("stats.json");
            let args = [
                &["run", kernel, "--width", "8", "--height", "6"][..],
                mode,
                &["--stats-json", json.to_str().unwrap()],
            ]
            .concat();
            let out = trax(&args);
            assert!(out.status.success(), "{}", text(&out.stderr));
            let stderr = text(&out.stderr);
            let v: serde_json::Value = read_json(&json);
            let scene = &v["scene"];
            let comps = scene["components"].as_array().expect("components");
            let names: Vec<&str> = comps.iter().map(|c| c["name"].as_str().unwrap()).collect();
            let mut want: Vec<&str> = vec!["camera", "framebuffer"];
            want.extend(all.iter().filter(|c| !left_out.contains(c)));
            let mut sorted = names.clone();
            sorted.sort();
            want.sort();
            assert_eq!(sorted, want, "{kernel} {mode:?}");
            let listed: Vec<&str> = scene["left_out"]
                .as_array()
                .unwrap()
                .iter()
                .map(|c| c.as_str().unwrap())
                .collect();
            assert_eq!(listed, left_out, "{kernel} {mode:?}");
            let sum: u64 = comps.iter().map(|c| c["bytes"].as_u64().unwrap()).sum();
            assert_eq!(scene["bytes"].as_u64(), Some(sum));
            for c in comps {
                let (name, count, bytes) = (
                    c["name"].as_str().unwrap(),
                    c["count"].as_u64().unwrap(),
                    c["bytes"].as_u64().unwrap(),
                );
                // Element sizes of the scene ABI.
                let per = match name {
                    "camera" => std::mem::size_of::<trax_runtime::abi::Camera>() as u64,
                    "framebuffer" => 12,
                    "triangles" => 36,
                    "bvh_nodes" => 32,
                    "materials" => 48,
                    "point_lights" => 24,
                    _ => 4,
                };
                assert_eq!(bytes, per * count, "{kernel}: {name}");
                let line = format!("   {name:<13} {bytes:>12} bytes {count:>10} elements");
                assert!(stderr.contains(&line), "{kernel}: no {line:?} in\n{stderr}");
            }
            assert_eq!(v["scene"]["components"][1]["count"], 48, "8x6 framebuffer");
            let text_left = format!(
                "left out (never referenced by the kernel): {}",
                left_out.join(", ")
            );
            assert!(stderr.contains(&text_left), "{kernel}: {stderr}");
            assert!(
                stderr.contains(&format!("scene data: {sum} bytes")),
                "{stderr}"
            );
        }
    }
}

/// LLVM 14 selects `fmax_a.d x, x` (which keeps the sign) for `llvm.fabs.v2f64`, and at
/// -O2 the SLP vectorizer makes that out of two scalar `f64::abs`: this kernel printed
/// 13.333333333333334 instead of 0.075 before the compiler rewrote vector `fabs`.
#[test]
fn scalar_abs_vectorized_by_llvm_clears_the_sign() {
    let dir = scratch("slp-abs");
    let src = dir.join("ratio.rs");
    std::fs::write(
        &src,
        "fn ratio(y: f64, x: f64) -> f64 {
    let mut ay = y.abs();
    let mut ax = x.abs();
    if ay > 1e300 {
        ay *= 0.25;
        ax *= 0.25;
    } else if ay < 1e-300 {
        ay *= 4.0;
        ax *= 4.0;
    }
    if ay > ax {
        ax / ay
    } else {
        ay / ax
    }
}

fn trax_main() {
    let z = trax::global_read(0) as f64;
    println!(\"{}\", ratio(-10.0 + z, -0.75 + z));
}
",
    )
    .unwrap();
    let s = src.to_str().unwrap();
    for opt in ["-O1", "-O2", "-O3"] {
        let out = trax(&[
            "run",
            s,
            opt,
            "--functional",
            "--tms",
            "1",
            "--threads",
            "1",
        ]);
        assert!(out.status.success(), "{opt}: {}", text(&out.stderr));
        assert_eq!(text(&out.stdout).lines().next(), Some("0.075"), "{opt}");
    }
    let asm = dir.join("ratio.s");
    let out = trax(&[
        "build",
        s,
        "-O2",
        "--emit",
        "asm",
        "-o",
        asm.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let asm = std::fs::read_to_string(&asm).unwrap();
    assert!(!asm.contains("fmax_a"), "{asm}");
}

/// Messages name each thing once, list the choices and say where a config is wrong.
#[test]
fn messages_name_the_input_once_and_list_choices() {
    let count = |hay: &str, needle: &str| hay.matches(needle).count();
    for (scene, name) in [
        ("/nonexistent.obj", "nonexistent.obj"),
        ("nosuch", "nosuch"),
        ("procedural:x", "procedural:x"),
    ] {
        let out = trax(&["run", "examples/hello.rs", "--scene", scene]);
        assert_eq!(out.status.code(), Some(1));
        let err = text(&out.stderr);
        assert_eq!(count(&err, name), 1, "scene named once:\n{err}");
    }
    // A scene error that does not name the scene itself still gets its name.
    let dir = scratch("messages");
    let empty = dir.join("empty.obj");
    std::fs::write(&empty, "# nothing\n").unwrap();
    let out = trax(&[
        "run",
        "examples/hello.rs",
        "--scene",
        empty.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(1));
    assert!(
        text(&out.stderr).contains("empty.obj"),
        "{}",
        text(&out.stderr)
    );

    let out = trax(&["run", "examples/hello.rs", "--config", "huge"]);
    assert_eq!(out.status.code(), Some(1));
    let err = text(&out.stderr);
    assert!(
        err.contains("`huge`") && err.contains("tiny, baseline, baseline-ch3, strata"),
        "{err}"
    );

    let bad = dir.join("bad.toml");
    std::fs::write(
        &bad,
        "preset = \"tiny\"\n[units.fp_add]\ncount = \"four\"\n",
    )
    .unwrap();
    let out = trax(&[
        "run",
        "examples/hello.rs",
        "--config",
        bad.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(1));
    let err = text(&out.stderr);
    assert!(
        err.contains("bad.toml:3:9") && err.contains("`units.fp_add.count`"),
        "{err}"
    );
}

/// A `.light` file's intensity reaches the kernel: Sponza (lit by its point light alone)
/// with the light at intensity 4 is, value for value, 4 times the image at intensity 1
/// (a power of two scales every path's contribution exactly), and an RGB intensity scales
/// each channel.
#[test]
fn light_file_intensity_scales_the_image() {
    let dir = scratch("light-intensity");
    let raw = |name: &str, light: &str| -> Vec<f32> {
        let l = dir.join(format!("{name}.light"));
        std::fs::write(&l, light).unwrap();
        let fb = dir.join(format!("{name}.raw"));
        let out = trax_command()
            .args(["run", "examples/pathtracer.rs", "--functional"])
            .args(["--scene", "../shared/scenes/sponza/sponza.obj"])
            .args(["--width", "12", "--height", "10", "--light"])
            .arg(&l)
            .arg("--raw-framebuffer")
            .arg(&fb)
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        std::fs::read(&fb)
            .unwrap()
            .chunks(4)
            .map(|b| f32::from_le_bytes(b.try_into().unwrap()))
            .collect()
    };
    let one = raw("one", "7.97 1.4 -1.74\n");
    let four = raw("four", "7.97 1.4 -1.74\n4\n");
    let rgb = raw("rgb", "7.97 1.4 -1.74  1 2 0.5\n");
    assert!(one.iter().any(|v| *v > 0.0));
    for (i, v) in one.iter().enumerate() {
        assert_eq!(four[i], 4.0 * v, "value {i}");
        assert_eq!(rgb[i], [1.0, 2.0, 0.5][i % 3] * v, "value {i}");
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// A run stopped by a limit says where its threads are, grouped by source stack with
/// counts, in the text and the stats document, in both modes.
#[test]
fn a_limit_stop_says_where_the_threads_are() {
    let dir = scratch("limit-places");
    let k = dir.join("spin.rs");
    std::fs::write(
        &k,
        "fn spin_a() -> u32 {\n    let mut x = 1u32;\n    loop { x = x.wrapping_mul(3) | 1; if x == 0 { return x; } }\n}\n\n\
         fn spin_b() -> u32 {\n    let mut x = 1u32;\n    loop { x = x.wrapping_mul(5) | 1; if x == 0 { return x; } }\n}\n\n\
         fn trax_main() {\n    if trax::global_id() % 2 == 0 {\n        spin_a();\n    } else {\n        spin_b();\n    }\n}\n",
    )
    .unwrap();
    for mode in [&["--functional"][..], &["--host-threads", "2"][..]] {
        let json = dir.join("stats.json");
        let out = Command::new(env!("CARGO_BIN_EXE_trax"))
            .arg("run")
            .arg(&k)
            .args([
                "-O0",
                "--tms",
                "2",
                "--threads",
                "2",
                "--max-instructions",
                "20000",
            ])
            .args(mode)
            .arg("--stats-json")
            .arg(&json)
            .current_dir(root())
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{mode:?}: {err}");
        assert!(err.contains("error: instruction limit reached"), "{err}");
        assert!(
            err.contains("where the threads are: 4 live, 0 halted"),
            "{err}"
        );
        for (ids, f, line) in [("0, 2", "spin_a", 3), ("1, 3", "spin_b", 8)] {
            let group = format!(
                "2 threads {ids} (running)\n        in spin::{f} at {}:{line}\n        called from trax_main at {}:",
                k.display(),
                k.display()
            );
            assert!(err.contains(&group), "{mode:?}: no {group:?} in\n{err}");
        }
        let v: serde_json::Value = read_json(&json);
        let p = &v["threads_at_stop"];
        assert_eq!(p["live"], 4);
        let groups = p["groups"].as_array().unwrap();
        assert_eq!(groups.len(), 2, "{p}");
        assert_eq!(groups[0]["count"], 2);
        assert_eq!(groups[0]["threads"], "0, 2");
        assert_eq!(groups[0]["frames"][0]["function"], "spin::spin_a");
        assert_eq!(groups[0]["frames"][0]["line"], 3);
        assert_eq!(groups[1]["frames"][0]["function"], "spin::spin_b");
    }
    // A finished run has none.
    std::fs::remove_dir_all(&dir).ok();
}

/// Runs `trax run KERNEL -O0 --tms 2 --threads 2 ARGS --stats-json JSON`: stderr, whether
/// it succeeded, and the statistics document.
fn run_small(k: &Path, args: &[&str], json: &Path) -> (String, bool, serde_json::Value) {
    let out = trax_command()
        .arg("run")
        .arg(k)
        .args(["-O0", "--tms", "2", "--threads", "2"])
        .args(args)
        .arg("--stats-json")
        .arg(json)
        .output()
        .unwrap();
    let doc = read_json(json);
    (text(&out.stderr), out.status.success(), doc)
}

/// Threads 0 and 2 wait for a global register nobody sets; 1 and 3 wait at a barrier
/// the spinning ones never reach: a livelock, found in both modes, told with where the
/// threads are (a looping thread at its loop), stopping the run only when asked.
#[test]
fn a_livelock_says_where_the_threads_are() {
    let dir = scratch("livelock");
    let k = dir.join("spin.rs");
    std::fs::write(
        &k,
        "fn wait_for(reg: u32) {\n    while trax::global_read(reg) == 0 {}\n}\n\n\
         fn trax_main() {\n    if trax::global_id() % 2 == 0 {\n        wait_for(5);\n    } else {\n        trax::barrier(7);\n    }\n}\n",
    )
    .unwrap();
    let json = dir.join("stats.json");
    let modes: [&[&str]; 3] = [
        &["--functional"],
        &["--host-threads", "1"],
        &["--host-threads", "2"],
    ];
    let mut cycles = Vec::new();
    for mode in modes {
        let stop = [mode, &["--stop-on-livelock"]].concat();
        let (err, ok, v) = run_small(&k, &stop, &json);
        assert!(!ok, "{mode:?}: {err}");
        assert!(err.contains("error: livelock at "), "{mode:?}: {err}");
        assert!(
            err.contains("the run can never finish (stopped here)"),
            "{err}"
        );
        assert!(
            err.contains("where the threads are: 4 live, 0 halted"),
            "{err}"
        );
        let spinning = format!(
            "2 threads 0, 2 (looping: 27 instructions, forever)\n        in spin::wait_for at {}:2\n        called from trax_main at {}:7\n",
            k.display(),
            k.display()
        );
        assert!(
            err.contains(&spinning),
            "{mode:?}: no {spinning:?} in\n{err}"
        );
        let waiting = "2 threads 1, 3 (barrier G[7])\n        in trax::hw::barrier at ";
        assert!(err.contains(waiting), "{mode:?}: no {waiting:?} in\n{err}");
        let waiter = format!("called from trax_main at {}:9\n", k.display());
        assert!(err.contains(&waiter), "{mode:?}: no {waiter:?} in\n{err}");
        assert_eq!(v["outcome"], "livelock");
        let l = &v["livelock"];
        assert_eq!(l["stopped"], true);
        // Looked for after 2^18 quiet cycles (instructions per thread): found at the
        // first look, within one check period (2^14 cycles; a round of 1000
        // instructions per thread).
        let quiet = l["quiet"].as_u64().unwrap();
        assert!((1 << 18..(1 << 18) + (1 << 14)).contains(&quiet), "{l}");
        assert_eq!(l["threads"]["groups"][0]["frames"][0]["line"], 2);
        assert_eq!(v["threads_at_stop"], l["threads"]);
        if mode[0] == "--host-threads" {
            assert!(l["cycle"].is_u64(), "{l}");
            cycles.push(l["cycle"].clone());
        } else {
            assert!(l["cycle"].is_null(), "{l}");
        }

        // Without --stop-on-livelock: told at once, the run goes on (here to a limit).
        let limit = [mode, &["--max-instructions", "3000000"]].concat();
        let (err, ok, v) = run_small(&k, &limit, &json);
        assert!(!ok, "{err}");
        let warn = err.find("warning: livelock at ").expect(&err);
        let stop = err.find("error: instruction limit reached").expect(&err);
        assert!(warn < stop, "{err}");
        assert!(err.contains("(still running: stop it, or run with --stop-on-livelock)"));
        assert_eq!(v["outcome"], "instruction_limit");
        assert_eq!(v["livelock"]["stopped"], false);
    }
    // The same cycle for any host-thread count.
    assert_eq!(cycles[0], cycles[1]);
    std::fs::remove_dir_all(&dir).ok();
}

/// The control: thread 0 computes in registers for longer than the quiet time (no store,
/// nothing chip-wide), the others spin waiting for its result. The detector looks (the
/// chip is quiet for 2^18 cycles or instructions per thread) but thread 0's state never
/// repeats (its loop counts), so there is no alarm, and the run finishes.
#[test]
fn a_long_quiet_computation_is_no_livelock() {
    let dir = scratch("no-livelock");
    let k = dir.join("work.rs");
    // About 6 instructions per iteration at -O0 and 400 000 iterations: 2.4 M
    // instructions (cycles), more than 2^18 * 8, so the detector looks 3 times.
    std::fs::write(
        &k,
        "fn trax_main() {\n    if trax::global_id() == 0 {\n        let mut x = 1u32;\n        let mut i = 0u32;\n        while i < 400000 {\n            x = x.wrapping_mul(3) ^ i;\n            i += 1;\n        }\n        trax::global_write(5, x | 1);\n    }\n    while trax::global_read(5) == 0 {}\n}\n",
    )
    .unwrap();
    let json = dir.join("stats.json");
    for mode in [&["--functional"][..], &["--host-threads", "2"][..]] {
        let (err, ok, v) = run_small(&k, mode, &json);
        assert!(ok, "{mode:?}: {err}");
        assert!(!err.contains("livelock"), "{mode:?}: {err}");
        assert_eq!(v["outcome"], "finished");
        assert!(v["livelock"].is_null());
        let n = v["instructions"].as_u64().unwrap();
        assert!(n > 8 << 18, "{mode:?}: only {n} instructions");
    }
    std::fs::remove_dir_all(&dir).ok();
}
