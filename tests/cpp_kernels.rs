//! The C++ layer (`trax.hpp`) and the C++ examples end to end. Oracles: the TRaX-Rust
//! prelude and examples (ray for ray and pixel for pixel, on the machine and natively),
//! the host build of the prelude's `libm.rs` (for `trax_sinf` & co.), and, where two
//! renderers draw only the same distribution, a per-block z test with a control that
//! must fail. Also: C++ names in profiles and crash reports, C++ ABI support, `trax
//! native` with several files and per-thread constructors, missing entry points.

use std::fmt::Write as _;
use std::path::PathBuf;
use std::process::Output;

use trax::pipeline::{prepare, Request};
use trax_emulator::{run, Mode};

mod common;
use common::{fresh_dir, root, text, tmp_path, trax_command};

/// The host build of the prelude's libm: the oracle for `trax_sinf` & co.
#[allow(dead_code)]
#[path = "../runtime/prelude/libm.rs"]
mod libm;
#[path = "../runtime/tests/libm_ref/mod.rs"]
mod libm_ref;

fn scratch(name: &str) -> PathBuf {
    fresh_dir(&format!("cpp-kernels-{name}"))
}

fn cache() -> PathBuf {
    tmp_path("cpp-kernels-cache")
}

fn trax(args: &[&str]) -> Output {
    trax_command()
        .args(args)
        .env("TRAX_CACHE_DIR", cache())
        .output()
        .expect("run trax")
}

/// What to render: scene, image, chip shape.
#[derive(Clone)]
struct Setup {
    scene: String,
    scale: Option<f64>,
    width: u32,
    height: u32,
    spp: u32,
    depth: u32,
    seed: u32,
    tms: u32,
    threads: u32,
}

impl Setup {
    fn new(width: u32, height: u32) -> Setup {
        Setup {
            scene: "cornell".into(),
            scale: None,
            width,
            height,
            spp: 1,
            depth: 3,
            seed: 0,
            tms: 2,
            threads: 4,
        }
    }

    /// The same settings as `trax` command-line flags.
    fn flags(&self) -> Vec<String> {
        let mut f: Vec<String> = vec!["--scene".into(), self.scene.clone()];
        if let Some(s) = self.scale {
            f.extend(["--scene-scale".into(), format!("{s:e}")]);
        }
        for (flag, v) in [
            ("--width", self.width),
            ("--height", self.height),
            ("--spp", self.spp),
            ("--depth", self.depth),
            ("--seed", self.seed),
            ("--tms", self.tms),
            ("--threads", self.threads),
        ] {
            f.extend([flag.to_string(), v.to_string()]);
        }
        f
    }
}

/// Runs `files` on the emulator: stdout and framebuffer.
fn emulate(files: &[PathBuf], opt: u8, mode: Mode, s: &Setup) -> (String, Vec<u8>) {
    let mut req = Request::new(&files[0]);
    req.more = files[1..].to_vec();
    req.opt_level = opt;
    req.scene = s.scene.clone();
    req.load.scale = s.scale;
    req.render.width = s.width;
    req.render.height = s.height;
    req.render.spp = s.spp;
    req.render.max_depth = s.depth;
    req.render.seed = s.seed;
    req.chip.tms = s.tms;
    req.chip.threads_per_tm = s.threads;
    let name = format!("{files:?} -O{opt} {mode:?}");
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
    (String::from_utf8(out).unwrap(), fb)
}

/// Runs `files` with `trax native`: stdout and framebuffer.
fn native(files: &[PathBuf], s: &Setup, tag: &str) -> (String, Vec<u8>) {
    let dir = scratch(&format!("native-{tag}"));
    let raw = dir.join("fb.bin");
    let mut args: Vec<String> = vec!["native".into()];
    args.extend(files.iter().map(|f| f.display().to_string()));
    args.extend(s.flags());
    args.extend(["--raw-framebuffer".into(), raw.display().to_string()]);
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let out = trax(&args);
    assert!(
        out.status.success(),
        "trax native {files:?}: {}",
        text(&out.stderr)
    );
    (text(&out.stdout), std::fs::read(&raw).unwrap())
}

fn sorted(out: &str) -> Vec<String> {
    let mut v: Vec<String> = out.lines().map(str::to_string).collect();
    v.sort_by_key(|l| {
        l.split(' ')
            .next()
            .and_then(|n| n.parse::<u32>().ok())
            .unwrap_or(u32::MAX)
    });
    v
}

/// `trax.hpp` against the prelude, ray for ray: `tests/kernels/hits.rs` and `hits.cpp`
/// trace the same 2048 rays (camera rays, rays from random points of the scene's box,
/// diffuse rays leaving surface points, shadow rays towards random triangles) and print
/// closest hit, any-hit over the same interval and before the closest hit, surface point
/// and emitter geometry as f32 bits. On the Cornell box, Sponza and the Cornell box scaled
/// by 1e-20 and 1e25 (the scale-invariant tests at their limits), the Rust kernel on the
/// machine and natively and the C++ kernel on the machine (-O2; -O0 on the Cornell box)
/// and natively print the same lines.
#[test]
fn trax_hpp_matches_the_prelude_ray_for_ray() {
    let rs = root().join("tests/kernels/hits.rs");
    let cpp = root().join("tests/kernels/hits.cpp");
    let mut cases = vec![
        Setup::new(64, 32),
        Setup {
            scene: "../shared/scenes/sponza/sponza.obj".into(),
            ..Setup::new(64, 32)
        },
    ];
    for scale in [1e-20, 1e25] {
        cases.push(Setup {
            scale: Some(scale),
            ..Setup::new(64, 32)
        });
    }
    for (n, mut s) in cases.into_iter().enumerate() {
        // One thread: a line is printed value by value, and threads' lines would mix.
        s.tms = 1;
        s.threads = 1;
        let what = format!("{} (scale {:?})", s.scene, s.scale);
        let reference = sorted(&emulate(std::slice::from_ref(&rs), 2, Mode::Functional, &s).0);
        assert_eq!(reference.len(), 2048, "{what}");
        // The record is worth comparing: hits, misses and shadow rays; any-hit agrees with
        // the closest hit, and nothing is hit before the closest hit.
        let hits = reference
            .iter()
            .filter(|l| !l.contains(" hit 4294967295 "))
            .count();
        assert!((1000..2048).contains(&hits), "{what}: {hits} hits");
        assert!(reference.iter().filter(|l| l.contains(" eg ")).count() > 300);
        for l in &reference {
            let any = l.contains(" any 1 ");
            assert_eq!(any, !l.contains(" hit 4294967295 "), "{what}: {l}");
            assert!(
                l.contains(" any 0 0") || l.contains(" any 1 0"),
                "{what}: {l}"
            );
        }
        let mut runs = vec![
            (
                "C++ -O2 on the machine",
                emulate(std::slice::from_ref(&cpp), 2, Mode::Functional, &s).0,
            ),
            (
                "Rust natively",
                native(std::slice::from_ref(&rs), &s, "hits-rs").0,
            ),
            (
                "C++ natively",
                native(std::slice::from_ref(&cpp), &s, "hits-cpp").0,
            ),
        ];
        if n == 0 {
            runs.push((
                "C++ -O0 on the machine",
                emulate(std::slice::from_ref(&cpp), 0, Mode::Functional, &s).0,
            ));
        }
        for (who, out) in runs {
            let got = sorted(&out);
            let first = reference.iter().zip(&got).position(|(a, b)| a != b);
            assert!(
                got.len() == reference.len() && first.is_none(),
                "{what}: {who} differs from the Rust prelude on the machine ({} lines):\n  rust: {}\n  got:  {}",
                got.len(),
                first.map(|i| reference[i].as_str()).unwrap_or(""),
                first.map(|i| got[i].as_str()).unwrap_or("")
            );
        }
    }
}

/// `examples/cpp/raycast.cpp` draws `examples/raycast.rs`'s image, bit for bit, at -O0
/// and -O2, in functional and timing mode, and natively.
#[test]
fn cpp_raycast_draws_the_rust_image_everywhere() {
    let s = Setup::new(48, 32);
    let rust = root().join("examples/raycast.rs");
    let cpp = root().join("examples/cpp/raycast.cpp");
    let (_, reference) = emulate(&[rust], 2, Mode::Functional, &s);
    assert!(reference.chunks(4).filter(|c| c != &[0; 4]).count() > 1000);
    for (who, fb) in [
        (
            "-O0",
            emulate(std::slice::from_ref(&cpp), 0, Mode::Functional, &s).1,
        ),
        (
            "-O2",
            emulate(std::slice::from_ref(&cpp), 2, Mode::Functional, &s).1,
        ),
        (
            "timing",
            emulate(std::slice::from_ref(&cpp), 2, Mode::Timing, &s).1,
        ),
        (
            "native",
            native(std::slice::from_ref(&cpp), &s, "raycast").1,
        ),
    ] {
        assert!(
            fb == reference,
            "raycast.cpp {who}: image differs from raycast.rs"
        );
    }
}

/// `examples/cpp/pathtracer.cpp` gives one image at -O0 and -O2, in functional and timing
/// mode and natively; it is also `pathtracer.rs`'s image bit for bit (the same estimator
/// and random draws in the same order, the same libm).
#[test]
fn cpp_pathtracer_is_one_image_everywhere() {
    let s = Setup {
        spp: 2,
        ..Setup::new(24, 16)
    };
    let cpp = root().join("examples/cpp/pathtracer.cpp");
    let (_, reference) = native(std::slice::from_ref(&cpp), &s, "pt-cpp");
    assert!(reference.chunks(4).filter(|c| c != &[0; 4]).count() > 500);
    for (who, fb) in [
        (
            "-O0",
            emulate(std::slice::from_ref(&cpp), 0, Mode::Functional, &s).1,
        ),
        (
            "-O2",
            emulate(std::slice::from_ref(&cpp), 2, Mode::Functional, &s).1,
        ),
        (
            "timing",
            emulate(std::slice::from_ref(&cpp), 2, Mode::Timing, &s).1,
        ),
        (
            "pathtracer.rs",
            native(&[root().join("examples/pathtracer.rs")], &s, "pt-rs").1,
        ),
    ] {
        assert!(
            fb == reference,
            "pathtracer.cpp natively vs {who}: images differ"
        );
    }
}

/// Per 8x8 block and channel, `z = (mean_a - mean_b) / sqrt(var_a + var_b)` of two
/// renderers, each rendered twice with independent seeds: the block mean's variance is
/// estimated from the pixels' differences between the two renders (`(x1 - x2)^2 / 2` is
/// an unbiased estimate of a pixel's variance). Returns the largest |z|.
fn max_block_z(a: [&[f32]; 2], b: [&[f32]; 2], w: usize, h: usize) -> f64 {
    let mut worst = 0.0f64;
    for by in 0..h / 8 {
        for bx in 0..w / 8 {
            for ch in 0..3 {
                let (mut mean, mut var) = ([0.0f64; 2], [0.0f64; 2]);
                for (k, r) in [a, b].iter().enumerate() {
                    for y in by * 8..by * 8 + 8 {
                        for x in bx * 8..bx * 8 + 8 {
                            let i = (y * w + x) * 3 + ch;
                            let (p, q) = (r[0][i] as f64, r[1][i] as f64);
                            mean[k] += (p + q) / 2.0;
                            // Var((p + q) / 2) = var / 2, estimated by (p - q)^2 / 4.
                            var[k] += (p - q) * (p - q) / 4.0;
                        }
                    }
                    mean[k] /= 64.0;
                    var[k] /= 64.0 * 64.0;
                }
                let z = (mean[0] - mean[1]) / (var[0] + var[1]).max(1e-30).sqrt();
                worst = worst.max(z.abs());
            }
        }
    }
    worst
}

fn floats(b: &[u8]) -> Vec<f32> {
    b.chunks(4)
        .map(|c| f32::from_le_bytes(c.try_into().unwrap()))
        .collect()
}

/// `pathtracer.cpp` and `pathtracer.rs` render the same picture as a distribution, not
/// only for equal random streams: each is rendered with its own seeds (natively, which
/// the test above ties to the machine), and every 8x8 block's mean agrees within |z| < 5
/// (48 blocks x 3 channels: for normal noise P(max |z| > 5) is about 1e-4; block sums of
/// 64 pixels are close enough to normal). The control, depth 2 against depth 3 (one
/// bounce of indirect light missing), must fail the same test.
#[test]
fn cpp_and_rust_path_tracers_agree_statistically() {
    let (w, h) = (64usize, 48usize);
    let render = |k: &str, seed: u32, depth: u32| {
        let s = Setup {
            spp: 16,
            depth,
            seed,
            ..Setup::new(w as u32, h as u32)
        };
        floats(&native(&[root().join(k)], &s, &format!("stat-{seed}-{depth}")).1)
    };
    let rs = [
        render("examples/pathtracer.rs", 11, 3),
        render("examples/pathtracer.rs", 12, 3),
    ];
    let cpp = [
        render("examples/cpp/pathtracer.cpp", 21, 3),
        render("examples/cpp/pathtracer.cpp", 22, 3),
    ];
    let z = max_block_z([&rs[0], &rs[1]], [&cpp[0], &cpp[1]], w, h);
    assert!(
        z < 5.0,
        "C++ and Rust path tracers differ: max block |z| = {z:.2}"
    );
    let shallow = [
        render("examples/cpp/pathtracer.cpp", 31, 2),
        render("examples/cpp/pathtracer.cpp", 32, 2),
    ];
    let control = max_block_z([&rs[0], &rs[1]], [&shallow[0], &shallow[1]], w, h);
    assert!(
        control > 10.0,
        "the test cannot tell depth 2 from depth 3: max block |z| = {control:.2}"
    );
    eprintln!("max block |z|: C++ vs Rust {z:.2}, depth 2 vs 3 {control:.2}");
}

/// The path tracer's profile names its C++ classes' methods, nested as they call each
/// other (`Path::radiance` > `Lambertian::shade` > `Path::direct<AreaLights>` >
/// `bvh::occluded`), with namespaces and parameter lists as C++ spells them.
#[test]
fn cpp_profile_shows_class_methods_by_name() {
    let dir = scratch("profile");
    let folded = dir.join("p.folded");
    let out = trax(&[
        "run",
        "examples/cpp/pathtracer.cpp",
        "--functional",
        "--width",
        "16",
        "--height",
        "16",
        "--profile",
        "--profile-format",
        "folded",
        "--profile-out",
        folded.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let f = std::fs::read_to_string(&folded).unwrap();
    let stacks: Vec<Vec<&str>> = f
        .lines()
        .filter_map(|l| l.rsplit_once(' '))
        .map(|(s, _)| s.split(';').collect())
        .collect();
    let has = |chain: &[&str]| {
        stacks.iter().any(|s| {
            let mut it = s.iter();
            chain.iter().all(|c| it.any(|f| f.starts_with(c)))
        })
    };
    for chain in [
        &[
            "trax_main",
            "Path::radiance(trax::Ray) const",
            "Lambertian::shade(",
        ][..],
        &[
            "Path::radiance(",
            "Emissive::shade(",
            "Material::direct_light(",
        ],
        &[
            "Lambertian::shade(",
            "trax::Vec3 Path::direct<AreaLights>(",
            "trax::bvh::occluded(",
        ],
        &[
            "Path::radiance(",
            "trax::bvh::intersect(",
            "trax::bvh::TriRay::intersect(",
        ],
        &["RenderSettings::RenderSettings()"],
    ] {
        assert!(has(chain), "no stack with {chain:?} in\n{f}");
    }
}

const CRASH_CPP: &str = r#"#include <trax.hpp>

namespace grid {
template <typename T, unsigned int N> class Array {
  public:
    T &operator[](unsigned int i) {
        if (i >= N)
            __builtin_trap();
        return items_[i];
    }
    const T &at(unsigned int i) const {
        if (i >= N)
            trax_panic("grid::Array::at: index out of bounds");
        return items_[i];
    }

  private:
    T items_[N] = {};
};
} // namespace grid

static unsigned int sum(const grid::Array<unsigned int, 4> &a, unsigned int n) {
    unsigned int s = 0;
    for (unsigned int i = 0; i <= n; i++)
        s += a.at(i);
    return s;
}

extern "C" void trax_main() {
    grid::Array<unsigned int, 4> a;
    unsigned int id = trax_global_id();
    if (trax_scene_width() == 5)
        a[id] = 1;
    trax_print_uint(sum(a, id));
}
"#;

/// A crash inside an inlined C++ template method is reported at its file:line:col with
/// the inline chain, at -O0 and -O2: `__builtin_trap()` (a `break`) in `operator[]`, and
/// `trax_panic` in `at()` as a panic with its message.
#[test]
fn crash_in_an_inlined_template_reports_line_and_inline_chain() {
    let dir = scratch("crash");
    let k = dir.join("grid.cpp");
    std::fs::write(&k, CRASH_CPP).unwrap();
    let ks = k.to_str().unwrap();
    for opt in ["-O0", "-O2"] {
        // Width 5: thread 4 writes a[4].
        let out = trax(&[
            "run",
            "--functional",
            opt,
            ks,
            "--width",
            "5",
            "--height",
            "2",
        ]);
        assert_eq!(out.status.code(), Some(1), "{opt}");
        let err = text(&out.stderr);
        assert!(err.contains("crashed after"), "{opt}: {err}");
        assert!(err.contains("break instruction (code 0)"), "{opt}: {err}");
        assert!(
            err.contains("grid.cpp:8:13 in grid::Array<unsigned int, (unsigned int)4>::operator[](unsigned int)"),
            "{opt}: {err}"
        );
        assert!(
            err.contains("            __builtin_trap();"),
            "{opt}: {err}"
        );
        assert!(err.contains("trax_main"), "{opt}: {err}");
        if opt == "-O2" {
            assert!(err.contains("inlined into trax_main at"), "{err}");
            assert!(err.contains("grid.cpp:33:"), "{err}");
        }
        // Width 4: thread 4 reads a.at(4) in sum().
        let out = trax(&[
            "run",
            "--functional",
            opt,
            ks,
            "--width",
            "4",
            "--height",
            "2",
        ]);
        assert_eq!(out.status.code(), Some(1), "{opt}");
        let err = text(&out.stderr);
        assert!(
            err.contains("panicked: grid::Array::at: index out of bounds"),
            "{opt}: {err}"
        );
        assert!(
            err.contains("grid.cpp:13:13 in grid::Array<unsigned int, (unsigned int)4>::at(unsigned int) const"),
            "{opt}: {err}"
        );
        assert!(
            err.contains("sum(grid::Array<unsigned int, (unsigned int)4> const&, unsigned int)")
        );
        if opt == "-O2" {
            assert!(err.contains("inlined into sum("), "{err}");
        }
    }
}

const PURE_VIRTUAL_CPP: &str = r#"#include <trax.h>

struct Shape {
    Shape() { init(); }
    void init() { area(); }
    virtual float area() const = 0;
    virtual ~Shape() {}
};

struct Square : Shape {
    float side = 2.0f;
    float area() const override { return side * side; }
};

extern "C" void trax_main() {
    Square s;
    trax_print_float(s.area());
}
"#;

/// A pure virtual call (from a base-class constructor) stops the program like a panic,
/// reported at the call's line, on the machine (`__cxa_pure_virtual` from the trax C++ runtime, linked on demand with
/// `operator delete` for the virtual destructor) and natively.
#[test]
fn pure_virtual_call_is_reported_as_a_panic() {
    let dir = scratch("pure");
    let k = dir.join("shape.cpp");
    std::fs::write(&k, PURE_VIRTUAL_CPP).unwrap();
    let ks = k.to_str().unwrap();
    for opt in ["-O0", "-O2"] {
        let out = trax(&["run", "--functional", opt, ks]);
        assert_eq!(out.status.code(), Some(1), "{opt}");
        let err = text(&out.stderr);
        assert!(
            err.contains("panicked: pure virtual method called"),
            "{opt}: {err}"
        );
        // Reported at the virtual call (the runtime function has no debug information).
        assert!(
            err.contains("shape.cpp:5:19 in Shape::init(), calling __cxa_pure_virtual"),
            "{opt}: {err}"
        );
        assert!(err.contains("    void init() { area(); }"), "{opt}: {err}");
        assert!(err.contains("Shape::Shape()"), "{opt}: {err}");
    }
    let out = trax(&["native", ks]);
    assert_eq!(out.status.code(), Some(1));
    assert!(text(&out.stderr).contains("pure virtual method called"));
}

const CTORS_C: &str = r#"#include <trax.h>
/* Constructors run on every hardware thread before trax_main (start-up code). */
__attribute__((constructor)) static void count(void) { trax_atomic_inc(7); }
void trax_main(void) {
    trax_barrier(3);
    if (trax_global_id() == 0) {
        trax_print_str("constructors run: ");
        trax_print_uint(trax_global_read(7));
        trax_print_str(", table: ");
        trax_print_float(table_sum());
        trax_print_char('\n');
    }
}
"#;

const TABLE_CPP: &str = r#"#include <trax.hpp>
/* A global object with a constructor, and a function C calls. */
namespace {
struct Table {
    float v[4];
    Table() {
        for (int i = 0; i < 4; i++)
            v[i] = trax_sinf(0.5f * (float)i);
        trax_atomic_inc(7);
    }
};
const Table table;
}
extern "C" float table_sum() { return table.v[0] + table.v[1] + table.v[2] + table.v[3]; }
"#;

/// `trax native` links several C and C++ files, or a TRaX-Rust kernel with C++ files, and
/// runs their constructors on every kernel thread before `trax_main`, as the machine's
/// start-up code does (2 TMs x 3 threads and two constructors: 12 calls). Printed text is
/// the machine's.
#[test]
fn native_links_several_files_and_runs_constructors_per_thread() {
    let dir = scratch("multi");
    let c = dir.join("main.c");
    let cpp = dir.join("table.cpp");
    std::fs::write(
        &c,
        CTORS_C.replace(
            "#include <trax.h>",
            "#include <trax.h>\nfloat table_sum(void);",
        ),
    )
    .unwrap();
    std::fs::write(&cpp, TABLE_CPP).unwrap();
    let s = Setup {
        threads: 3,
        ..Setup::new(4, 4)
    };
    let want_sum = libm::sinf(0.0) + libm::sinf(0.5) + libm::sinf(1.0) + libm::sinf(1.5);
    let want = format!("constructors run: 12, table: {want_sum}\n");
    let files = [c.clone(), cpp.clone()];
    assert_eq!(emulate(&files, 2, Mode::Functional, &s).0, want);
    assert_eq!(native(&files, &s, "multi-c").0, want);
    // A Rust kernel with the C++ file.
    let rs = dir.join("k.rs");
    std::fs::write(
        &rs,
        "fn trax_main() {\n    trax::barrier(3);\n    if trax::global_id() == 0 {\n        println!(\"constructors run: {}\", trax::global_read(7));\n    }\n}\n",
    )
    .unwrap();
    let files = [rs, cpp];
    let want = "constructors run: 6\n";
    assert_eq!(emulate(&files, 2, Mode::Functional, &s).0, want);
    assert_eq!(native(&files, &s, "multi-rs").0, want);
}

/// C and C++ sources without `trax_main` get an error that says what to write (and, for
/// a C++ `trax_main()` with C++ linkage, why it does not count), from `trax run` and
/// `trax native` alike, exit 1; `trax native` refuses objects and a second Rust crate.
#[test]
fn missing_entry_point_is_a_clear_error() {
    let dir = scratch("noentry");
    let c = dir.join("lib.c");
    let cpp = dir.join("k.cpp");
    std::fs::write(&c, "int helper(int x) { return x + 1; }\n").unwrap();
    std::fs::write(&cpp, "void trax_main() {}\n").unwrap();
    for cmd in ["run", "native"] {
        let out = trax(&[cmd, c.to_str().unwrap()]);
        assert_eq!(out.status.code(), Some(1), "{cmd}");
        let err = text(&out.stderr);
        assert!(err.contains("lib.c: no `trax_main`"), "{cmd}: {err}");
        assert!(err.contains("void trax_main(void)"), "{cmd}: {err}");
        assert!(
            !err.contains("linker") && !err.contains("rust-lld"),
            "{cmd}: {err}"
        );
        let out = trax(&[cmd, cpp.to_str().unwrap(), c.to_str().unwrap()]);
        assert_eq!(out.status.code(), Some(1), "{cmd}");
        let err = text(&out.stderr);
        assert!(err.contains("with C++ linkage"), "{cmd}: {err}");
        assert!(err.contains("extern \"C\""), "{cmd}: {err}");
    }
    let obj = dir.join("x.o");
    std::fs::write(&obj, b"\x7fELF").unwrap();
    let out = trax(&["native", cpp.to_str().unwrap(), obj.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(1));
    assert!(text(&out.stderr).contains("objects and executables are for the machine"));
    let out = trax(&["native", "examples/hello.rs", "examples/gradient.rs"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(text(&out.stderr).contains("builds one TRaX-Rust crate"));
}

/// `trax_sinf` & co. are the prelude's libm: a generated C kernel applies every function
/// of `trax.h`'s libm section to edge values (±0, subnormals, ±inf, NaNs with payloads,
/// overflow thresholds, ...) and random points and prints the results' bits; on the
/// machine (-O2) and natively they equal the host build of `runtime/prelude/libm.rs`,
/// which `tests/libm_differential.rs` ties to Rust's `x.sin()` on both sides.
#[test]
fn c_libm_is_the_preludes_bit_for_bit() {
    use libm_ref::{edge_f32, edge_f64, sample_f32, sample_f64, Rng};
    let fns = trax_runtime::cheader::libm_functions();
    let mut rng = Rng(0x00c1_1b17);
    let (e32, e64) = (edge_f32(), edge_f64());
    const N: usize = 300;
    let mut a = Vec::new();
    let mut b = Vec::new();
    let mut c = Vec::new();
    let mut d = Vec::new();
    let mut n = Vec::new();
    for i in 0..N {
        let (lo, hi) = [(-1.0, 1.0), (-10.0, 10.0), (-1e6, 1e6), (0.0, 4.0)][i % 4];
        a.push(
            e32.get(i)
                .copied()
                .unwrap_or_else(|| sample_f32(&mut rng, lo, hi)),
        );
        b.push(sample_f32(&mut rng, lo, hi));
        c.push(
            e64.get(i)
                .copied()
                .unwrap_or_else(|| sample_f64(&mut rng, lo, hi)),
        );
        d.push(sample_f64(&mut rng, lo, hi));
        n.push((rng.next() % 41) as i32 - 20);
    }
    // The kernel: operands from tables XORed with global register 0 (0 at run time), so
    // nothing is folded at compile time.
    let mut k = String::from("#include <trax.h>\n");
    let table = |k: &mut String, name: &str, ty: &str, v: &[u64]| {
        writeln!(k, "static const {ty} {name}[{N}] = {{").unwrap();
        for x in v {
            writeln!(k, "    {x:#x}u,").unwrap();
        }
        k.push_str("};\n");
    };
    table(
        &mut k,
        "A",
        "unsigned int",
        &a.iter()
            .map(|x: &f32| x.to_bits() as u64)
            .collect::<Vec<_>>(),
    );
    table(
        &mut k,
        "B",
        "unsigned int",
        &b.iter()
            .map(|x: &f32| x.to_bits() as u64)
            .collect::<Vec<_>>(),
    );
    table(
        &mut k,
        "C",
        "unsigned long long",
        &c.iter().map(|x: &f64| x.to_bits()).collect::<Vec<_>>(),
    );
    table(
        &mut k,
        "D",
        "unsigned long long",
        &d.iter().map(|x: &f64| x.to_bits()).collect::<Vec<_>>(),
    );
    table(
        &mut k,
        "NN",
        "unsigned int",
        &n.iter().map(|&x| x as u32 as u64).collect::<Vec<_>>(),
    );
    k.push_str(
        "static float f32(unsigned int b) { float x; __builtin_memcpy(&x, &b, 4); return x; }\n\
         static double f64(unsigned long long b) { double x; __builtin_memcpy(&x, &b, 8); return x; }\n\
         static void pf(float x) { unsigned int b; __builtin_memcpy(&b, &x, 4); trax_print_uint(b); trax_print_char(' '); }\n\
         static void pd(double x) { unsigned long long b; __builtin_memcpy(&b, &x, 8); trax_print_u64(b); trax_print_char(' '); }\n\
         void trax_main(void) {\n    if (trax_global_id() != 0) return;\n    unsigned int z = trax_global_read(0);\n\
         \x20   for (unsigned int i = 0; i < sizeof A / sizeof A[0]; i++) {\n\
         \x20       float a = f32(A[i] ^ z), b = f32(B[i] ^ z);\n\
         \x20       double c = f64(C[i] ^ z), d = f64(D[i] ^ z);\n\
         \x20       int n = (int)(NN[i] ^ z);\n\
         \x20       float fs, fc; double ds, dc;\n\
         \x20       (void)fs; (void)fc; (void)ds; (void)dc; (void)n; (void)b; (void)d;\n",
    );
    let mut want = String::new();
    for i in 0..N {
        for f in &fns {
            want += &host_libm(&f.name, a[i], b[i], c[i], d[i], n[i]);
        }
        want.push('\n');
    }
    for f in &fns {
        let args: Vec<&str> = f
            .params
            .iter()
            .enumerate()
            .map(|(j, (_, t))| {
                use trax_runtime::cheader::LibmTy as T;
                let wide = f
                    .params
                    .iter()
                    .any(|(_, t)| *t == T::F64 || *t == T::MutF64);
                match (t, j, wide) {
                    (T::F32, 0, _) => "a",
                    (T::F32, _, _) => "b",
                    (T::F64, 0, _) => "c",
                    (T::F64, _, _) => "d",
                    (T::I32, _, _) => "n",
                    (T::MutF32, 1, _) => "&fs",
                    (T::MutF32, _, _) => "&fc",
                    (T::MutF64, 1, _) => "&ds",
                    (T::MutF64, _, _) => "&dc",
                }
            })
            .collect();
        let call = format!("trax_{}({})", f.name, args.join(", "));
        use trax_runtime::cheader::LibmTy as T;
        match f.ret {
            Some(T::F32) => writeln!(k, "        pf({call});").unwrap(),
            Some(T::F64) => writeln!(k, "        pd({call});").unwrap(),
            None if f.params.iter().any(|(_, t)| *t == T::MutF32) => {
                writeln!(k, "        {call}; pf(fs); pf(fc);").unwrap()
            }
            None => writeln!(k, "        {call}; pd(ds); pd(dc);").unwrap(),
            Some(t) => panic!("{}: result {t:?}", f.name),
        }
    }
    k.push_str("        trax_print_char('\\n');\n    }\n}\n");
    let dir = scratch("libm");
    let src = dir.join("libm.c");
    std::fs::write(&src, k).unwrap();
    let s = Setup {
        tms: 1,
        threads: 1,
        ..Setup::new(4, 4)
    };
    let machine = emulate(std::slice::from_ref(&src), 2, Mode::Functional, &s).0;
    let host = native(std::slice::from_ref(&src), &s, "libm").0;
    for (who, got) in [("machine", machine), ("native", host)] {
        let first = want.lines().zip(got.lines()).position(|(x, y)| x != y);
        assert!(
            got == want,
            "{who}: line {first:?} differs from the host build of libm.rs\n  want: {}\n  got:  {}",
            first.and_then(|i| want.lines().nth(i)).unwrap_or(""),
            first.and_then(|i| got.lines().nth(i)).unwrap_or("")
        );
    }
}

/// The host value(s) the kernel prints for `trax_<name>`, as text.
fn host_libm(name: &str, a: f32, b: f32, c: f64, d: f64, n: i32) -> String {
    let f = |x: f32| format!("{} ", x.to_bits());
    let g = |x: f64| format!("{} ", x.to_bits());
    match name {
        "sinf" => f(libm::sinf(a)),
        "cosf" => f(libm::cosf(a)),
        "tanf" => f(libm::tanf(a)),
        "asinf" => f(libm::asinf(a)),
        "acosf" => f(libm::acosf(a)),
        "atanf" => f(libm::atanf(a)),
        "atan2f" => f(libm::atan2f(a, b)),
        "expf" => f(libm::expf(a)),
        "exp2f" => f(libm::exp2f(a)),
        "logf" => f(libm::logf(a)),
        "log2f" => f(libm::log2f(a)),
        "log10f" => f(libm::log10f(a)),
        "powf" => f(libm::powf(a, b)),
        "powif" => f(libm::powif(a, n)),
        "hypotf" => f(libm::hypotf(a, b)),
        "cbrtf" => f(libm::cbrtf(a)),
        "sincosf" => {
            let (mut s, mut c) = (0.0, 0.0);
            libm::sincosf(a, &mut s, &mut c);
            f(s) + &f(c)
        }
        "sin" => g(libm::sin(c)),
        "cos" => g(libm::cos(c)),
        "tan" => g(libm::tan(c)),
        "asin" => g(libm::asin(c)),
        "acos" => g(libm::acos(c)),
        "atan" => g(libm::atan(c)),
        "atan2" => g(libm::atan2(c, d)),
        "exp" => g(libm::exp(c)),
        "exp2" => g(libm::exp2(c)),
        "log" => g(libm::log(c)),
        "log2" => g(libm::log2(c)),
        "log10" => g(libm::log10(c)),
        "pow" => g(libm::pow(c, d)),
        "powi" => g(libm::powi(c, n)),
        "hypot" => g(libm::hypot(c, d)),
        "cbrt" => g(libm::cbrt(c)),
        "sincos" => {
            let (mut s, mut co) = (0.0, 0.0);
            libm::sincos(c, &mut s, &mut co);
            g(s) + &g(co)
        }
        other => panic!("libm function `{other}` has no oracle here: add it"),
    }
}
