//! The generated C/C++ kernel API (`trax.h`, `trax.hpp`) against the Rust definitions: a
//! probe compiled by clang-14 for the TRaX target checks every struct size and field
//! offset with `_Static_assert` against `abi::SceneHeader`, `abi::Camera` (`offset_of!`)
//! and the prelude's `layout.rs` (the byte layouts the Rust kernels read), and the C++
//! layer compiles.

#[path = "../prelude/layout.rs"]
#[allow(dead_code)]
mod layout;

use layout as L;
use std::fmt::Write;
use std::mem::{offset_of, size_of};
use std::path::{Path, PathBuf};
use std::process::Command;
use trax_runtime::abi::{self, Camera, Component, SceneHeader};
use trax_runtime::cheader::{self, header_field_type};

fn scratch(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("c-header-{name}"));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    std::fs::write(d.join("trax_isa.h"), cheader::render_c_header()).unwrap();
    std::fs::write(d.join("trax.h"), cheader::render_trax_h()).unwrap();
    std::fs::write(d.join("trax.hpp"), cheader::render_trax_hpp()).unwrap();
    d
}

/// Compiles `file` in `dir` with clang-14 for TRaX (syntax and semantic checks only).
fn compile(dir: &Path, file: &str, lang: &[&str]) {
    let out = clang(dir, file, lang);
    assert!(
        out.status.success(),
        "{file}:\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

fn clang(dir: &Path, file: &str, lang: &[&str]) -> std::process::Output {
    Command::new("clang-14")
        .args([
            "--target=mipsel-unknown-elf",
            "-march=mips32r6",
            "-mmsa",
            "-mfp64",
            "-fno-pic",
            "-mno-abicalls",
            "-G0",
            "-ffreestanding",
            "-nostdlibinc",
            "-Wall",
            "-Werror",
            "-fsyntax-only",
        ])
        .args(lang)
        .arg("-I")
        .arg(dir)
        .arg(dir.join(file))
        .output()
        .expect("clang-14 is installed (.ci/run installs it)")
}

/// A C struct's name, size and field offsets.
type Layout = (&'static str, usize, Vec<(&'static str, usize)>);

/// Every struct of `trax.h` with the size and field offsets the Rust side gives it.
fn expected_layouts() -> Vec<Layout> {
    let u = |v: u32| v as usize;
    vec![
        (
            "trax_component_t",
            size_of::<Component>(),
            vec![
                ("addr", offset_of!(Component, addr)),
                ("count", offset_of!(Component, count)),
            ],
        ),
        (
            "trax_camera_t",
            size_of::<Camera>(),
            vec![
                ("eye", offset_of!(Camera, eye)),
                ("u", offset_of!(Camera, u)),
                ("v", offset_of!(Camera, v)),
                ("w", offset_of!(Camera, w)),
                ("left", offset_of!(Camera, left)),
                ("right", offset_of!(Camera, right)),
                ("bottom", offset_of!(Camera, bottom)),
                ("top", offset_of!(Camera, top)),
                ("distance", offset_of!(Camera, distance)),
                ("aperture", offset_of!(Camera, aperture)),
            ],
        ),
        (
            "trax_pixel_t",
            u(L::PIXEL_SIZE),
            vec![("r", 0), ("g", 4), ("b", 8)],
        ),
        (
            "trax_bvh_node_t",
            u(L::BVH_NODES_STRIDE),
            vec![
                ("min", u(L::BVH_MIN)),
                ("max", u(L::BVH_MAX)),
                ("a", u(L::BVH_A)),
                ("b", u(L::BVH_B)),
            ],
        ),
        (
            "trax_triangle_t",
            u(L::TRIANGLES_STRIDE),
            vec![("v0", 0), ("v1", 12), ("v2", 24)],
        ),
        (
            "trax_normals_t",
            u(L::NORMALS_SIZE),
            vec![("n0", 0), ("n1", 12), ("n2", 24)],
        ),
        (
            "trax_texcoords_t",
            u(L::TEXCOORDS_SIZE),
            vec![("t0", 0), ("t1", 8), ("t2", 16)],
        ),
        (
            "trax_material_t",
            u(L::MATERIALS_STRIDE),
            vec![
                ("diffuse", u(L::MAT_DIFFUSE)),
                ("specular", u(L::MAT_SPECULAR)),
                ("emission", u(L::MAT_EMISSION)),
                ("shininess", u(L::MAT_SHININESS)),
                ("flags", u(L::MAT_FLAGS)),
            ],
        ),
        (
            "trax_point_light_t",
            u(L::POINT_LIGHTS_STRIDE),
            vec![
                ("position", u(L::LIGHT_POSITION)),
                ("color", u(L::LIGHT_COLOR)),
            ],
        ),
        (
            "trax_scene_header_t",
            size_of::<SceneHeader>(),
            abi::scene_header_fields(),
        ),
    ]
}

#[test]
fn every_header_field_has_a_c_type() {
    for (f, _) in abi::scene_header_fields() {
        assert!(
            header_field_type(f).is_some(),
            "abi::SceneHeader field `{f}` has no C type in cheader::header_field_type"
        );
    }
}

#[test]
fn every_c_struct_is_checked() {
    let checked: Vec<&str> = expected_layouts().iter().map(|e| e.0).collect();
    for s in cheader::c_structs() {
        assert!(
            checked.contains(&s.c_name),
            "{} has no layout check",
            s.c_name
        );
    }
}

#[test]
fn c_struct_layouts_match_the_rust_abi() {
    let dir = scratch("layout");
    let mut probe = String::from("#include <trax.h>\n#include <stddef.h>\n\n");
    let mut n = 0;
    for (name, size, fields) in expected_layouts() {
        let _ = writeln!(
            probe,
            "_Static_assert(sizeof({name}) == {size}, \"sizeof({name}) != {size}\");"
        );
        for (f, off) in fields {
            let _ = writeln!(
                probe,
                "_Static_assert(offsetof({name}, {f}) == {off}, \"offsetof({name}, {f}) != {off}\");"
            );
            n += 1;
        }
    }
    // Every header field accessor reads its own linker symbol.
    for (f, _) in abi::scene_header_fields() {
        assert!(
            cheader::render_trax_h().contains(&format!("{}{f}", abi::SCENE_SYMBOL_PREFIX)),
            "no symbol for header field {f}"
        );
    }
    std::fs::write(dir.join("probe.c"), probe).unwrap();
    compile(&dir, "probe.c", &["-x", "c", "-std=c11"]);
    assert!(n > 40, "only {n} offsets checked");
}

/// The probe is honest: a wrong expectation fails to compile.
#[test]
fn a_wrong_offset_fails_the_probe() {
    let dir = scratch("wrong");
    std::fs::write(
        dir.join("probe.c"),
        "#include <trax.h>\n#include <stddef.h>\n_Static_assert(offsetof(trax_bvh_node_t, b) == 24, \"b\");\n",
    )
    .unwrap();
    let out = clang(&dir, "probe.c", &["-x", "c", "-std=c11"]);
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("static_assert failed"), "{err}");
}

#[test]
fn cpp_layer_compiles() {
    let dir = scratch("cpp");
    std::fs::write(
        dir.join("k.cpp"),
        "#include <trax.hpp>\nvoid trax_main() {\n    trax::Ray r = trax::primary_ray(1, 2);\n    trax::Vec3 c = 0.5f * (r.dir + trax::Vec3(1, 1, 1));\n    trax::set_pixel(1, 2, c);\n}\n",
    )
    .unwrap();
    compile(
        &dir,
        "k.cpp",
        &["-x", "c++", "-std=c++17", "-fno-exceptions"],
    );
}

/// `trax.hpp`'s constants are the prelude's: each C++ value, as clang reads the generated
/// literal, has the bits rustc gives the prelude's constant (evaluated here by the same
/// reader, and checked against the values the Rust sources mean).
#[test]
fn cpp_constants_are_the_preludes() {
    use cheader::{prelude_const, PreludeConst, HPP_CONSTANTS};
    let dir = scratch("consts");
    let mut probe = String::from("#include <trax.hpp>\n");
    for &(file, name) in HPP_CONSTANTS {
        let c = prelude_const(file, name).unwrap_or_else(|e| panic!("{file}::{name}: {e}"));
        let (bits, ty) = match c {
            PreludeConst::U32(_, v) => (v, "unsigned int"),
            PreludeConst::F32(_, v) => (v.to_bits(), "unsigned int"),
        };
        writeln!(
            probe,
            "static_assert(__builtin_bit_cast({ty}, trax::{name}) == {bits}u, \"{name}\");"
        )
        .unwrap();
    }
    std::fs::write(dir.join("consts.cpp"), &probe).unwrap();
    compile(&dir, "consts.cpp", &["-x", "c++", "-std=c++17"]);
    // The reader against values written out here from the prelude's sources.
    let f = |file, name| match prelude_const(file, name).unwrap() {
        PreludeConst::F32(_, v) => v,
        c => panic!("{c:?}"),
    };
    assert_eq!(f("ray.rs", "POINT_ERROR"), 1.0 / 1_048_576.0);
    assert_eq!(f("bvh.rs", "ERR_Z"), 3.576_280_3e-6);
    assert_eq!(f("math.rs", "POW2_126"), 2f32.powi(126));
    assert_eq!(
        prelude_const("ray.rs", "NO_HIT"),
        Ok(PreludeConst::U32("NO_HIT", u32::MAX))
    );
    assert!(prelude_const("bvh.rs", "NO_SUCH").is_err());
    // The literal form: exact, subnormals and negative values included.
    for x in [
        1.0f32,
        -2.5,
        1e-45,
        f32::MIN_POSITIVE,
        f32::MAX,
        1.072_884e-6,
    ] {
        let lit = cheader::hex_float(x);
        std::fs::write(
            dir.join("hex.cpp"),
            format!(
                "static_assert(__builtin_bit_cast(unsigned int, {lit}f) == {}u, \"{lit}\");\n",
                x.to_bits()
            ),
        )
        .unwrap();
        compile(&dir, "hex.cpp", &["-x", "c++", "-std=c++17"]);
    }
}

/// Every public function of the prelude's `libm.rs` is in `trax.h` as `trax_<name>`,
/// with the C types of its Rust signature.
#[test]
fn libm_functions_cover_every_public_function() {
    let src = trax_runtime::prelude::file("libm.rs").unwrap();
    let public = src.lines().filter(|l| l.starts_with("pub fn ")).count();
    let fns = cheader::libm_functions();
    assert_eq!(
        fns.len(),
        public,
        "a libm signature the reader does not know"
    );
    assert!(public >= 30, "{public}");
    let h = cheader::render_trax_h();
    for f in &fns {
        assert!(
            h.contains(&f.c_decl()),
            "{} missing from trax.h",
            f.c_decl()
        );
    }
    assert!(h.contains("float trax_sinf(float x);"));
    assert!(h.contains("void trax_sincosf(float x, float *s, float *c);"));
    assert!(h.contains("float trax_powif(float x, int n);"));
    assert!(h.contains("double trax_atan2(double y, double x);"));
}

/// The whole C++ layer compiles cleanly (`-Wall -Wextra -Werror`) for the machine and,
/// with `TRAX_HOST`, for the host, every inline function instantiated.
#[test]
fn cpp_layer_compiles_warning_free_for_both_sides() {
    let dir = scratch("cpp-all");
    std::fs::write(dir.join("trax_host.h"), cheader::render_host_h()).unwrap();
    std::fs::write(
        dir.join("all.cpp"),
        r#"#include <trax.hpp>
using namespace trax;
extern "C" void trax_main() {
    Camera cam = Camera::load();
    Ray r = cam.jittered_ray(1, 2);
    Hit h = bvh::intersect(r, 0.0f, INFINITY_F);
    bool o = bvh::occluded(r, 0.0f, h.t);
    Triangle t = scene::triangle(h.tri);
    SurfacePoint sp(r, h, t);
    Vec3 v = sp.origin() + sp.origin_below() + sampling::cosine_hemisphere(sp.n) +
             sampling::unit_sphere() + sampling::triangle_point(t) +
             scene::shading_normal(h.tri, h.u, h.v) + scene::get_pixel(0, 0);
    sampling::EmitterGeometry eg = sampling::emitter_geometry(t, v, sp.p);
    Material m = scene::triangle_material(h.tri);
    PointLight l = scene::point_light(0);
    v += m.diffuse.lerp(l.color, eg.dist).reflect(eg.normal).clamp(0, 1).min(v).max(v);
    v -= v.cross(v) / v * (2.0f * v) / 3.0f;
    v *= Vec3::splat(v.luminance() + v.length() + v.min_component() + v.max_component());
    v /= v.normalize().abs() + Vec3::splat(t.area() + t.area_scaled(2.0f) + bvh::scene_bound());
    scene::PixelShare share = scene::pixel_share();
    unsigned int i = share.next_pixel();
    scene::set_pixel_index(i, o ? -v : v + scene::background());
    set_pixel(0, 0, primary_ray(0, 0).at(scene::epsilon()));
    (void)(scene::normals_count() + scene::material_count() + scene::spp() + scene::seed());
}
"#,
    )
    .unwrap();
    let cxx = [
        "-x",
        "c++",
        "-std=c++17",
        "-fno-exceptions",
        "-fno-rtti",
        "-Wextra",
    ];
    compile(&dir, "all.cpp", &cxx);
    let out = Command::new("clang-14")
        .args(cxx)
        .args(["-DTRAX_HOST", "-Wall", "-Werror", "-fsyntax-only", "-I"])
        .arg(&dir)
        .arg(dir.join("all.cpp"))
        .output()
        .expect("clang-14 is installed");
    assert!(
        out.status.success(),
        "host:\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
}
