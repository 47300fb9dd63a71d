//! C and C++ kernels end to end: clang-14 builds them against the generated `trax.h`, the
//! trax linker links them (with each other, with TRaX-Rust objects, with the C runtime on
//! demand), and they run on the functional and timing models. Oracles: the TRaX-Rust
//! examples (which `tests/native_vs_emulator.rs` checks against native execution) draw
//! bit-identical images; printed values are computed here on the host; crash reports and
//! annotations name C source lines; bad input gets clang's diagnostic and exit 1.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use trax::pipeline::{prepare, Request};
use trax_emulator::{run, Mode};

mod common;
use common::{fresh_dir, root, text, tmp_path, trax_command};

fn scratch(name: &str) -> PathBuf {
    fresh_dir(&format!("c-kernels-{name}"))
}

fn cache() -> PathBuf {
    tmp_path("c-kernels-cache")
}

fn trax(args: &[&str]) -> Output {
    trax_command()
        .args(args)
        .env("TRAX_CACHE_DIR", cache())
        .env_remove("TRAX_CLANG")
        .output()
        .expect("run trax")
}

/// Runs `files` (the first is the kernel) on a 2-TM, 4-thread chip: stdout, framebuffer
/// and the run's cycles (timing mode).
fn emulate(files: &[PathBuf], opt: u8, mode: Mode, w: u32, h: u32) -> (String, Vec<u8>, u64) {
    let mut req = Request::new(&files[0]);
    req.more = files[1..].to_vec();
    req.opt_level = opt;
    req.render.width = w;
    req.render.height = h;
    req.chip.tms = 2;
    req.chip.threads_per_tm = 4;
    let name = format!("{files:?} -O{opt}");
    let prepared = prepare(&req).unwrap_or_else(|e| panic!("{name}: {}", e.render()));
    let mut out = Vec::new();
    let result = run(prepared.run_request(&req.chip, mode), &mut out)
        .unwrap_or_else(|e| panic!("{name}: {e}"));
    assert!(
        result.finished(),
        "{name}: {:?}\n{}",
        result.outcome,
        result.failure.clone().unwrap_or_default()
    );
    let fb = prepared.framebuffer(&result).unwrap();
    (
        String::from_utf8(out).unwrap(),
        fb,
        result.cycles.unwrap_or(0),
    )
}

#[test]
fn c_examples_draw_the_rust_examples_images_in_both_modes() {
    for k in ["gradient", "mandelbrot"] {
        let rust = root().join(format!("examples/{k}.rs"));
        let c = root().join(format!("examples/c/{k}.c"));
        let (_, reference, _) = emulate(&[rust], 2, Mode::Functional, 40, 24);
        assert!(reference.iter().any(|&b| b != 0));
        for opt in [0, 2, 3] {
            let (_, fb, _) = emulate(std::slice::from_ref(&c), opt, Mode::Functional, 40, 24);
            assert!(fb == reference, "{k}.c -O{opt}: image differs from {k}.rs");
        }
        let (_, fb, cycles) = emulate(std::slice::from_ref(&c), 2, Mode::Timing, 40, 24);
        assert!(fb == reference, "{k}.c timing: image differs from {k}.rs");
        assert!(cycles > 0, "{k}.c: a timing run counts cycles");
    }
}

/// The gradient against the formula computed here (an oracle independent of both
/// compilers): pixel (x, y) = ((x + 0.5) / w, (y + 0.5) / h, 0.25) in f32.
#[test]
fn c_gradient_matches_the_host_formula() {
    let (w, h) = (13u32, 7u32);
    let (_, fb, _) = emulate(
        &[root().join("examples/c/gradient.c")],
        2,
        Mode::Functional,
        w,
        h,
    );
    let (iw, ih) = (1.0f32 / w as f32, 1.0f32 / h as f32);
    for y in 0..h {
        for x in 0..w {
            let i = ((y * w + x) * 12) as usize;
            let px: Vec<f32> = (0..3)
                .map(|c| f32::from_le_bytes(fb[i + 4 * c..i + 4 * c + 4].try_into().unwrap()))
                .collect();
            let want = [(x as f32 + 0.5) * iw, (y as f32 + 0.5) * ih, 0.25];
            assert_eq!(px, want, "pixel ({x}, {y})");
        }
    }
}

const MAIN_C: &str = r#"#include <trax.h>

struct pair { unsigned long long num; unsigned int den; unsigned int pad[6]; };

unsigned long long mix(struct pair p); /* in lib.cpp */

void trax_main(void) {
    unsigned int id = trax_global_id();
    while (trax_global_read(1) != id) {}
    struct pair p = {0};
    p.num = 0x123456789abcdefULL * (id + 1);
    p.den = 7 + id;
    struct pair q = p; /* a struct copy */
    trax_print_str("thread ");
    trax_print_uint(id);
    trax_print_str(": ");
    trax_print_u64(mix(q));
    trax_print_char('\n');
    trax_atomic_inc(1);
}
"#;

const LIB_CPP: &str = r#"#include <trax.h>

struct pair { unsigned long long num; unsigned int den; unsigned int pad[6]; };

namespace {
template <typename T> T div_plus_rem(T a, T b) { return a / b + a % b; }
}

extern "C" unsigned long long mix(struct pair p) {
    return div_plus_rem<unsigned long long>(p.num, p.den) + (unsigned long long)(long long)(-3.75 * p.den);
}
"#;

/// A C kernel and a C++ file linked together; 64-bit division (the compiler's 64-bit
/// helpers) and struct copies (memcpy) come from the trax C runtime, linked on demand.
#[test]
fn c_and_cpp_files_link_together_with_the_runtime() {
    let dir = scratch("multi");
    std::fs::write(dir.join("main.c"), MAIN_C).unwrap();
    std::fs::write(dir.join("lib.cpp"), LIB_CPP).unwrap();
    for opt in [0, 2] {
        let (out, _, _) = emulate(
            &[dir.join("main.c"), dir.join("lib.cpp")],
            opt,
            Mode::Functional,
            4,
            4,
        );
        let mut want = String::new();
        for id in 0..8u64 {
            let num = 0x123456789abcdefu64.wrapping_mul(id + 1);
            let den = 7 + id;
            let v = (num / den + num % den).wrapping_add((-3.75 * den as f64) as i64 as u64);
            want += &format!("thread {id}: {v}\n");
        }
        assert_eq!(out, want, "-O{opt}");
    }
}

/// A TRaX-Rust kernel linked with a C file: the C constructor runs (start-up code,
/// `.init_array`) before the Rust `trax_main` on every thread.
#[test]
fn rust_and_c_objects_link_together() {
    let dir = scratch("mixed");
    std::fs::write(
        dir.join("k.rs"),
        "fn trax_main() {\n    if trax::global_id() == 0 {\n        println!(\"from C: {}\", trax::global_read(7));\n    }\n}\n",
    )
    .unwrap();
    std::fs::write(
        dir.join("init.c"),
        "#include <trax.h>\n__attribute__((constructor)) static void init(void) { trax_global_write(7, 6 * 7); }\n",
    )
    .unwrap();
    let (out, _, _) = emulate(
        &[dir.join("k.rs"), dir.join("init.c")],
        2,
        Mode::Functional,
        4,
        4,
    );
    assert_eq!(out, "from C: 42\n");
}

/// The C++ layer: primary rays through the Cornell box's camera (`trax::primary_ray`, the
/// prelude's `Camera::pixel_ray`), shaded by direction, against the same arithmetic on the
/// host (the camera from the scene loader, `1/sqrt` from the runtime's `fops::invsqrt`,
/// the machine's semantics).
#[test]
fn cpp_kernel_with_trax_hpp_matches_the_host() {
    let dir = scratch("cpp");
    std::fs::write(
        dir.join("rays.cpp"),
        r#"#include <trax.hpp>

void trax_main() {
    unsigned int w = trax_scene_width(), n = w * trax_scene_height();
    for (unsigned int i = trax_atomic_inc(0); i < n; i = trax_atomic_inc(0)) {
        trax::Ray r = trax::primary_ray(i % w, i / w);
        trax::set_pixel(i % w, i / w, (r.dir + trax::Vec3(1, 1, 1)) * 0.5f);
    }
}
"#,
    )
    .unwrap();
    let (w, h) = (9u32, 6u32);
    let (_, fb, _) = emulate(&[dir.join("rays.cpp")], 2, Mode::Functional, w, h);
    let scene = trax::pipeline::load_scene("cornell", &Default::default()).unwrap();
    let c = scene.view.camera().unwrap();
    let (iw, ih) = (1.0f32 / w as f32, 1.0f32 / h as f32);
    for y in 0..h {
        for x in 0..w {
            // The prelude's `Camera::pixel_ray`: row 0 at the top.
            let s = c.left + (c.right - c.left) * ((x as f32 + 0.5) * iw);
            let t = c.top - (c.top - c.bottom) * ((y as f32 + 0.5) * ih);
            let d: Vec<f32> = (0..3)
                .map(|k| c.w[k] * c.distance + c.u[k] * s + c.v[k] * t)
                .collect();
            let len2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
            let inv = trax_runtime::fops::invsqrt(len2);
            let i = ((y * w + x) * 12) as usize;
            for k in 0..3 {
                let got = f32::from_le_bytes(fb[i + 4 * k..i + 4 * k + 4].try_into().unwrap());
                let want = (d[k] * inv + 1.0) * 0.5;
                assert_eq!(got, want, "pixel ({x}, {y}) channel {k}");
            }
        }
    }
}

#[test]
fn syntax_error_shows_clangs_diagnostic_and_exits_1() {
    let dir = scratch("syntax");
    let bad = dir.join("bad.c");
    std::fs::write(
        &bad,
        "#include <trax.h>\n\nvoid trax_main(void) {\n    unsigned int x = 1\n}\n",
    )
    .unwrap();
    for cmd in ["build", "run"] {
        let mut args = vec![cmd, bad.to_str().unwrap()];
        let out_file = dir.join("x.elf");
        if cmd == "build" {
            args.extend(["-o", out_file.to_str().unwrap()]);
        }
        let out = trax(&args);
        assert_eq!(out.status.code(), Some(1), "{cmd}: {}", text(&out.stderr));
        let err = text(&out.stderr);
        assert!(
            err.contains("bad.c:4:23: error: expected ';'"),
            "{cmd}: clang's diagnostic with file:line:col expected:\n{err}"
        );
        assert!(!err.contains("panicked"), "{err}");
    }
}

#[test]
fn missing_clang_names_the_debian_package() {
    let dir = scratch("noclang");
    let out = trax_command()
        .args(["build", "examples/c/gradient.c", "-o"])
        .arg(dir.join("g.elf"))
        .env("TRAX_CACHE_DIR", cache())
        .env("PATH", &dir)
        .env_remove("TRAX_CLANG")
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let err = text(&out.stderr);
    assert!(
        err.starts_with("error: examples/c/gradient.c: building C and C++ kernels needs clang-14")
            && err.contains("Debian package `clang-14`"),
        "{err}"
    );
}

const FAULT_C: &str = r#"#include <trax.h>

static unsigned int read_at(const unsigned int *p) {
    return *p;
}

void trax_main(void) {
    const unsigned int *bad = (const unsigned int *)(trax_global_id() * 0u + 8u);
    trax_print_uint(read_at(bad));
}
"#;

/// A C kernel that dereferences a null-guard address: the crash report names the C
/// file, line and column, the inline chain and the source line, at -O0 and -O2.
#[test]
fn c_kernel_crash_reports_file_and_line() {
    let dir = scratch("fault");
    let f = dir.join("fault.c");
    std::fs::write(&f, FAULT_C).unwrap();
    for opt in ["-O0", "-O2"] {
        let out = trax(&["run", "--functional", opt, f.to_str().unwrap()]);
        assert!(!out.status.success());
        let err = text(&out.stderr);
        assert!(
            err.contains("null pointer dereference: 4-byte load at address 0x00000008"),
            "{err}"
        );
        assert!(err.contains("fault.c:4:12 in read_at"), "{opt}: {err}");
        assert!(err.contains("    return *p;"), "{opt}: {err}");
        assert!(err.contains("trax_main at "), "{opt}: {err}");
        assert!(err.contains("fault.c:9:"), "{opt}: {err}");
    }
}

/// `trax run --panic` style abort from C: `trax_panic` stops the program with the message.
#[test]
fn trax_panic_reports_the_message_and_line() {
    let dir = scratch("panic");
    let f = dir.join("p.c");
    std::fs::write(
        &f,
        "#include <trax.h>\n\nvoid trax_main(void) {\n    if (trax_global_id() == 3)\n        trax_panic(\"thread three gives up\");\n}\n",
    )
    .unwrap();
    let out = trax(&["run", "--functional", f.to_str().unwrap()]);
    assert!(!out.status.success());
    let err = text(&out.stderr);
    assert!(err.contains("thread three gives up"), "{err}");
    assert!(err.contains("p.c:5:"), "{err}");
}

#[test]
fn annotate_shows_c_source_lines() {
    let out = trax(&[
        "annotate",
        "--functional",
        "examples/c/mandelbrot.c",
        "--width",
        "16",
        "--height",
        "8",
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let s = text(&out.stdout);
    let line = s
        .lines()
        .find(|l| l.contains("if (zx2 + zy2 > 4.0f)"))
        .unwrap_or_else(|| panic!("no annotated inner-loop line in\n{s}"));
    // The inner loop runs thousands of times on 128 pixels: its line has a cost.
    assert!(
        line.chars().any(|c| c.is_ascii_digit() && c != '0'),
        "{line}"
    );
    assert!(s.contains("examples/c/mandelbrot.c"), "{s}");
}

#[test]
fn header_command_writes_the_headers() {
    let dir = scratch("header");
    let out = trax(&["header", "-o", dir.join("c").to_str().unwrap()]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert!(dir.join("c/trax.h").is_file() && dir.join("c/trax_isa.h").is_file());
    assert!(!dir.join("c/trax.hpp").exists());
    let out = trax(&["header", "--cpp", "-o", dir.join("cpp").to_str().unwrap()]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let h = std::fs::read_to_string(dir.join("cpp/trax.h")).unwrap();
    assert_eq!(h, trax_runtime::cheader::render_trax_h());
    assert!(dir.join("cpp/trax.hpp").is_file());
}

#[test]
fn build_emits_objects_assembly_and_ir_for_c() {
    let dir = scratch("emit");
    for (emit, check) in [
        ("obj", b"\x7fELF".as_slice()),
        ("asm", b"trax_main".as_slice()),
        ("llvm-ir", b"define".as_slice()),
    ] {
        let o = dir.join(format!("g.{emit}"));
        let out = trax(&[
            "build",
            "examples/c/gradient.c",
            "--emit",
            emit,
            "-o",
            o.to_str().unwrap(),
        ]);
        assert!(out.status.success(), "{emit}: {}", text(&out.stderr));
        let bytes = std::fs::read(&o).unwrap();
        assert!(
            bytes.windows(check.len()).any(|w| w == check),
            "{emit} output lacks {check:?}"
        );
    }
    // An object from `--emit obj` runs once linked by `trax run`.
    let out = trax(&[
        "run",
        "--functional",
        dir.join("g.obj").to_str().unwrap(),
        "--width",
        "4",
        "--height",
        "4",
    ]);
    assert!(
        !out.status.success(),
        "a `.obj` name is not an object by extension"
    );
    std::fs::rename(dir.join("g.obj"), dir.join("g.o")).unwrap();
    let out = trax(&[
        "run",
        "--functional",
        dir.join("g.o").to_str().unwrap(),
        "--width",
        "4",
        "--height",
        "4",
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    // Several files only link into an executable.
    let out = trax(&[
        "build",
        "examples/c/gradient.c",
        "examples/c/mandelbrot.c",
        "--emit",
        "obj",
        "-o",
        dir.join("x.o").to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(1));
    assert!(text(&out.stderr).contains("only `--emit exe` links several files"));
    // Two kernels define `trax_main` twice: the linker says so.
    let out = trax(&[
        "build",
        "examples/c/gradient.c",
        "examples/c/mandelbrot.c",
        "-o",
        dir.join("x.elf").to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(1));
    assert!(
        text(&out.stderr).contains("trax_main"),
        "{}",
        text(&out.stderr)
    );
}

fn raw_framebuffer(cmd: &[&str], kernel: &Path, tag: &str) -> (String, Vec<u8>) {
    let dir = scratch(&format!("fb-{tag}"));
    let raw = dir.join("fb.bin");
    let mut args = cmd.to_vec();
    let k = kernel.to_str().unwrap();
    let r = raw.to_str().unwrap();
    args.extend([
        k,
        "--width",
        "24",
        "--height",
        "16",
        "--tms",
        "2",
        "--threads",
        "3",
        "--raw-framebuffer",
        r,
    ]);
    let out = trax(&args);
    assert!(out.status.success(), "{cmd:?} {k}: {}", text(&out.stderr));
    (text(&out.stdout), std::fs::read(&raw).unwrap())
}

const HELLO_C: &str = r#"#include <trax.h>

/* Every thread prints once, in thread order (global register 1 is a ticket). */
void trax_main(void) {
    unsigned int id = trax_global_id();
    while (trax_global_read(1) != id) {}
    trax_print_str("hello from thread ");
    trax_print_uint(id);
    trax_print_str(" of ");
    trax_print_uint(trax_num_threads());
    trax_print_str(": x = ");
    trax_print_float((float)id * 0.1f + 0.25f);
    trax_print_str(", d = ");
    trax_print_double(1.0 / (id + 3));
    trax_print_str(", neg = ");
    trax_print_int(-(int)id);
    trax_print_str(", big = ");
    trax_print_i64(-1234567890123LL * (long long)(id + 1));
    trax_print_str(", even = ");
    trax_print_bool(id % 2 == 0);
    trax_print_char(0x2713);
    trax_print_char('\n');
    trax_atomic_inc(1);
}
"#;

/// `trax native k.c`: clang compiles the kernel for the host against `trax.h`'s host side
/// and it runs on host threads. Same framebuffers as `trax run` (the examples, and C++
/// camera rays through `trax.hpp`), and the same printed text, float formatting included.
#[test]
fn native_c_and_cpp_kernels_match_the_emulator() {
    for k in ["examples/c/gradient.c", "examples/c/mandelbrot.c"] {
        let (_, run) = raw_framebuffer(&["run", "--functional"], &root().join(k), "run");
        let (_, native) = raw_framebuffer(&["native"], &root().join(k), "native");
        assert!(run == native, "{k}: native image differs from trax run");
    }
    let dir = scratch("native-src");
    std::fs::write(
        dir.join("rays.cpp"),
        "#include <trax.hpp>\nvoid trax_main() {\n    unsigned int w = trax_scene_width(), n = w * trax_scene_height();\n    for (unsigned int i = trax_atomic_inc(0); i < n; i = trax_atomic_inc(0)) {\n        trax::Ray r = trax::primary_ray(i % w, i / w);\n        trax::set_pixel(i % w, i / w, (r.dir + trax::Vec3(1, 1, 1)) * 0.5f);\n    }\n}\n",
    )
    .unwrap();
    let (_, run) = raw_framebuffer(&["run", "--functional"], &dir.join("rays.cpp"), "run");
    let (_, native) = raw_framebuffer(&["native"], &dir.join("rays.cpp"), "native");
    assert!(
        run == native,
        "rays.cpp: native image differs from trax run"
    );

    std::fs::write(dir.join("hello.c"), HELLO_C).unwrap();
    let (run_out, _) = raw_framebuffer(&["run", "--functional"], &dir.join("hello.c"), "run");
    let (native_out, _) = raw_framebuffer(&["native"], &dir.join("hello.c"), "native");
    assert!(
        run_out.contains("hello from thread 5 of 6: x = 0.75, d = 0.125, neg = -5, big = -7407407340738, even = false✓\n"),
        "{run_out}"
    );
    assert_eq!(run_out, native_out);
}

#[test]
fn native_c_syntax_error_shows_clangs_diagnostic() {
    let dir = scratch("native-bad");
    let bad = dir.join("bad.c");
    std::fs::write(
        &bad,
        "#include <trax.h>\nvoid trax_main(void) { int x = }\n",
    )
    .unwrap();
    let out = trax(&["native", bad.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(1));
    let err = text(&out.stderr);
    assert!(err.contains("bad.c:2:"), "{err}");
    assert!(err.contains("error: expected expression"), "{err}");
}

/// gdb-multiarch on a C++ kernel built by `trax build`: a breakpoint at file:line inside
/// a class template's method, a backtrace with demangled C++ names, locals and members,
/// then the run to its end (clang's DWARF 5 through the trax linker and GDB server).
#[test]
fn gdb_breaks_and_prints_locals_in_a_cpp_kernel() {
    use std::io::{BufRead, BufReader, Read};
    use std::process::Stdio;
    let src = r#"#include "trax.h"
template <typename T> struct Accum {
  T total;
  T scale;
  __attribute__((noinline)) void add(T x) {
    T scaled = x * scale;
    total += scaled; // BREAK
  }
};
namespace k {
__attribute__((noinline)) int run(int n) {
  Accum<int> acc{0, 3};
  for (int i = 1; i <= n; i++) acc.add(i);
  return acc.total;
}
}
extern "C" void trax_main(void) { trax_printi(k::run(4)); }
"#;
    let brk = src.lines().position(|l| l.contains("// BREAK")).unwrap() + 1;
    let dir = scratch("gdb-cpp");
    let k = dir.join("accum.cpp");
    std::fs::write(&k, src).unwrap();
    let elf = dir.join("accum.elf");
    let out = trax(&[
        "build",
        k.to_str().unwrap(),
        "-O0",
        "-o",
        elf.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let mut child = trax_command()
        .args(["run", elf.to_str().unwrap(), "--functional", "--tms", "1"])
        .args(["--threads", "1", "--gdb", "127.0.0.1:0"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("spawn trax");
    let mut err = BufReader::new(child.stderr.take().unwrap());
    let mut line = String::new();
    err.read_line(&mut line).unwrap();
    let addr = line
        .trim()
        .strip_prefix("waiting for gdb on ")
        .unwrap_or_else(|| panic!("unexpected first line {line:?}"))
        .to_string();
    let mut args: Vec<String> = vec!["-batch".into(), "-nx".into()];
    for c in [
        "set pagination off".to_string(),
        "set architecture mips:isa32r6".into(),
        format!("file {}", elf.display()),
        format!("target remote {addr}"),
        format!("break accum.cpp:{brk}"),
        "continue".into(),
        "bt".into(),
        "info locals".into(),
        "print x".into(),
        "print this->scale".into(),
        "continue".into(),
        "print scaled".into(),
        "delete".into(),
        "continue".into(),
    ] {
        args.push("-ex".into());
        args.push(c);
    }
    let g = Command::new("timeout")
        .arg("60")
        .arg("gdb-multiarch")
        .args(&args)
        .output()
        .expect("run gdb-multiarch");
    let gdb_out = text(&g.stdout) + &text(&g.stderr);
    let status = child.wait().unwrap();
    let mut rest = String::new();
    err.read_to_string(&mut rest).unwrap();
    let mut stdout = String::new();
    child
        .stdout
        .take()
        .unwrap()
        .read_to_string(&mut stdout)
        .unwrap();
    assert!(status.success(), "trax: {rest}\ngdb: {gdb_out}");
    assert!(gdb_out.contains(&format!("accum.cpp:{brk}")), "{gdb_out}");
    let bt: Vec<&str> = gdb_out.lines().filter(|l| l.starts_with('#')).collect();
    assert!(
        bt.iter().any(|l| l.contains("Accum<int>::add")),
        "demangled method in the backtrace:\n{gdb_out}"
    );
    assert!(bt.iter().any(|l| l.contains("k::run")), "{gdb_out}");
    assert!(bt.iter().any(|l| l.contains("trax_main")), "{gdb_out}");
    // First stop: x = 1, scaled = 3; second stop: x = 2, scaled = 6.
    assert!(gdb_out.contains("scaled = 3"), "info locals:\n{gdb_out}");
    assert!(gdb_out.contains("$1 = 1"), "{gdb_out}");
    assert!(gdb_out.contains("$2 = 3"), "{gdb_out}");
    assert!(gdb_out.contains("$3 = 6"), "{gdb_out}");
    assert!(gdb_out.contains("exited normally"), "{gdb_out}");
    // 3 * (1 + 2 + 3 + 4)
    assert_eq!(stdout.trim(), "30", "{stdout}");
}

/// A TRaX-Rust kernel and a C file calling each other: Rust declares the C functions in an
/// `extern "C"` block, C calls Rust's `#[no_mangle] pub extern "C" fn`s. Narrow integers
/// cross the boundary in registers with upper bits the callee relies on (clang's
/// `signext`/`zeroext`): `rust_wrap_add` wraps past `i8` (a callee that did not re-extend
/// its return value would hand C 200 + id instead of -56 + id) and `c_widen16` returns its
/// `unsigned short` argument as it finds it. Expected lines are computed here; functional,
/// timing and `trax native` agree.
const CALLS_RS: &str = r#"extern "C" {
    fn c_shade(id: u32, x: f32) -> f32;
    fn c_widen16(x: u16) -> u32;
    fn c_widen8(x: i8) -> i32;
    fn c_is_odd(x: i32) -> bool;
    fn c_neg16(x: i16) -> i16;
}

#[no_mangle]
pub extern "C" fn rust_scale(x: f32, k: i64) -> f32 {
    x * k as f32
}

#[no_mangle]
pub extern "C" fn rust_wrap_add(a: i8, b: i8) -> i8 {
    a.wrapping_add(b)
}

#[no_mangle]
pub extern "C" fn rust_is_big(x: u16) -> bool {
    x > 300
}

fn trax_main() {
    let id = trax::global_id();
    while trax::global_read(1) != id {}
    let s = unsafe { c_shade(id, 1.5) };
    let a = unsafe { c_widen16(0xFFF0u16.wrapping_add(id as u16 * 8)) };
    let b = unsafe { c_widen8((id as i8).wrapping_mul(50)) };
    let o = unsafe { c_is_odd(id as i32) };
    let n = unsafe { c_neg16(-(id as i16) - 1) };
    println!("thread {id}: shade {s} w16 {a} w8 {b} odd {o} neg {n}");
    trax::atomic_inc(1);
}
"#;

const CALLS_C: &str = r#"#include <trax.h>

float rust_scale(float x, long long k);
signed char rust_wrap_add(signed char a, signed char b);
_Bool rust_is_big(unsigned short x);

float c_shade(unsigned id, float x) {
    int w = rust_wrap_add((signed char)(100 + id), 100);
    return rust_scale(x, (long long)id - 3) + (float)w + (rust_is_big(250 + 20 * id) ? 1000.0f : 0.0f);
}
unsigned c_widen16(unsigned short x) { return x; }
int c_widen8(signed char x) { return x; }
_Bool c_is_odd(int x) { return x & 1; }
short c_neg16(short x) { return -x; }
"#;

#[test]
fn rust_and_c_call_each_other() {
    let dir = scratch("calls");
    let (k, c) = (dir.join("k.rs"), dir.join("lib.c"));
    std::fs::write(&k, CALLS_RS).unwrap();
    std::fs::write(&c, CALLS_C).unwrap();
    let mut want = String::new();
    for id in 0..8u32 {
        let w = (200 + id) as u8 as i8 as i32;
        let big = if 250 + 20 * id > 300 { 1000.0 } else { 0.0 };
        let s = 1.5f32 * (id as i64 - 3) as f32 + w as f32 + big;
        let a = 0xFFF0u16.wrapping_add(id as u16 * 8) as u32;
        let b = (id as i8).wrapping_mul(50) as i32;
        let n = id + 1;
        want += &format!(
            "thread {id}: shade {s} w16 {a} w8 {b} odd {} neg {n}\n",
            id % 2 == 1
        );
    }
    let files = [k.clone(), c.clone()];
    for opt in [0, 2] {
        let (out, _, _) = emulate(&files, opt, Mode::Functional, 4, 4);
        assert_eq!(out, want, "functional -O{opt}");
    }
    let (out, _, cycles) = emulate(&files, 2, Mode::Timing, 4, 4);
    assert_eq!(out, want, "timing");
    assert!(cycles > 0);
    let out = trax(&[
        "native",
        k.to_str().unwrap(),
        c.to_str().unwrap(),
        "--width",
        "4",
        "--height",
        "4",
        "--tms",
        "2",
        "--threads",
        "4",
    ]);
    assert!(out.status.success(), "native: {}", text(&out.stderr));
    assert_eq!(text(&out.stdout), want, "native");
}

/// The attributes of the C boundary against clang's own (the oracle for the ABI): every
/// integer width, `bool`, floats and pointers, as exports and as `extern "C"` imports,
/// carry the `signext`/`zeroext` attributes clang-14 gives the same C prototypes.
#[test]
fn c_boundary_attributes_match_clangs() {
    use trax_compiler::{compile_source, CompileOptions, Emit};
    let types = [
        ("bool", "_Bool"),
        ("i8", "signed char"),
        ("u8", "unsigned char"),
        ("i16", "short"),
        ("u16", "unsigned short"),
        ("i32", "int"),
        ("u32", "unsigned"),
        ("i64", "long long"),
        ("u64", "unsigned long long"),
        ("usize", "unsigned long"),
        ("f32", "float"),
        ("f64", "double"),
        ("*const f32", "const float *"),
    ];
    let mut rs = String::from("extern \"C\" {\n");
    let mut c = String::new();
    for (i, (r, ct)) in types.iter().enumerate() {
        rs += &format!("    fn imp{i}(a: {r}, b: {r}) -> {r};\n");
        c += &format!("{ct} imp{i}({ct} a, {ct} b);\n{ct} exp{i}({ct} a, {ct} b) {{ return imp{i}(a, b); }}\n");
    }
    rs += "}\n";
    for (i, (r, _)) in types.iter().enumerate() {
        rs += &format!(
            "#[no_mangle]\npub extern \"C\" fn exp{i}(a: {r}, b: {r}) -> {r} {{\n    let _ = b;\n    unsafe {{ imp{i}(a, a) }}\n}}\n"
        );
    }
    rs += "fn trax_main() {}\n";
    let opts = CompileOptions {
        opt_level: 0,
        emit: Emit::LlvmIr,
        ..Default::default()
    };
    let ours = compile_source("abi", &rs, &opts).unwrap_or_else(|e| panic!("{e}"));
    let ours = String::from_utf8(ours.bytes).unwrap();
    let dir = scratch("abi");
    let src = dir.join("abi.c");
    std::fs::write(&src, &c).unwrap();
    let theirs = trax::clang::compile(&src, trax::clang::Lang::C, 0, Emit::LlvmIr)
        .unwrap_or_else(|e| panic!("{e}"));
    let theirs = String::from_utf8(theirs).unwrap();
    // `signext`/`zeroext` of the return value and each parameter, per function.
    let sig = |ir: &str, name: &str| -> Vec<String> {
        let line = ir
            .lines()
            .find(|l| {
                (l.starts_with("define") || l.starts_with("declare"))
                    && l.contains(&format!("@{name}("))
            })
            .unwrap_or_else(|| panic!("no {name} in\n{ir}"));
        let (head, rest) = line.split_once(&format!("@{name}(")).unwrap();
        let params = rest.rsplit_once(')').unwrap().0;
        let exts = |s: &str| {
            let mut e: Vec<&str> = s
                .split_whitespace()
                .filter(|w| *w == "signext" || *w == "zeroext")
                .collect();
            e.sort();
            e.join(" ")
        };
        std::iter::once(exts(head))
            .chain(params.split(',').map(exts))
            .collect()
    };
    for (i, (r, _)) in types.iter().enumerate() {
        for name in [format!("imp{i}"), format!("exp{i}")] {
            assert_eq!(sig(&ours, &name), sig(&theirs, &name), "{name} ({r})");
        }
    }
}

/// A C kernel calling a TRaX-Rust file that only exports functions (no `trax_main`):
/// `trax run` and `trax native` link it either way round.
#[test]
fn c_kernel_calls_a_rust_library() {
    let dir = scratch("rust-lib");
    let (main, lib) = (dir.join("main.c"), dir.join("lib.rs"));
    std::fs::write(
        &main,
        "#include <trax.h>\nfloat rust_twice(float x);\nvoid trax_main(void) {\n    if (trax_global_id() == 0) {\n        trax_print_float(rust_twice(1.25f));\n        trax_print_char('\\n');\n    }\n}\n",
    )
    .unwrap();
    std::fs::write(
        &lib,
        "#[no_mangle]\npub extern \"C\" fn rust_twice(x: f32) -> f32 {\n    x * 2.0\n}\n",
    )
    .unwrap();
    let (m, l) = (main.to_str().unwrap(), lib.to_str().unwrap());
    for cmd in [["run", "--functional"].as_slice(), &["native"]] {
        for files in [[m, l], [l, m]] {
            let mut args = cmd.to_vec();
            args.extend(files);
            args.extend(["--width", "4", "--height", "4"]);
            let out = trax(&args);
            assert!(out.status.success(), "{args:?}: {}", text(&out.stderr));
            assert_eq!(text(&out.stdout), "2.5\n", "{args:?}");
        }
    }
}

/// `long double` is `double` on o32 (clang's mipsel target); `trax native` builds with
/// `-mlong-double-64` so x86's 80-bit format does not give other digits: 1/3 rounded to
/// double loses the 1e-17 that the 80-bit format keeps.
#[test]
fn long_double_is_double_on_the_machine_and_natively() {
    let dir = scratch("long-double");
    let k = dir.join("ld.c");
    std::fs::write(
        &k,
        "#include <trax.h>\nvoid trax_main(void) {\n    if (trax_global_id()) return;\n    long double x = 1.0L / 3.0L;\n    trax_print_uint(sizeof(long double));\n    trax_print_char(' ');\n    trax_print_double((double)(x + 1e-17L - x));\n    trax_print_char('\\n');\n}\n",
    )
    .unwrap();
    let (run, _) = raw_framebuffer(&["run", "--functional"], &k, "run");
    let (native, _) = raw_framebuffer(&["native"], &k, "native");
    assert_eq!(run, "8 0\n");
    assert_eq!(native, run);
}

/// A libc call has no implementation on the machine: the link error says so and points
/// to trax.h, exit 1.
#[test]
fn libc_calls_get_a_clear_message() {
    let dir = scratch("libc");
    let k = dir.join("heap.c");
    std::fs::write(
        &k,
        "#include <trax.h>\nvoid *malloc(unsigned long n);\nvoid trax_main(void) {\n    char *p = malloc(4);\n    trax_print_int(p[0]);\n}\n",
    )
    .unwrap();
    let out = trax(&["run", k.to_str().unwrap()]);
    let err = text(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(
        err.contains("undefined symbol `malloc`") && err.contains("no C library"),
        "{err}"
    );
}
