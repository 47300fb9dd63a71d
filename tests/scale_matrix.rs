//! The scale matrix: the Cornell box, a closed icosphere and a closed thin slab, scaled by
//! 10^k for k = -20 ..= 20, rendered by the ray caster, ambient occlusion and the path
//! tracer (functional emulator, 64 × 64 pixels), each checked against its unit-scale image.
//!
//! Every kernel here is scale-invariant by construction: the ray caster's point lights have
//! no falloff, the AO radius is a multiple of the header epsilon, which is relative to the
//! scene's size, and the path tracer runs on the Cornell box without its point light, so
//! only the emitter, whose radiance does not depend on scale, lights it. So the image at
//! every scale should be the unit-scale image, up to the rounding of 10^k-scaled vertices
//! (relative 6e-8, about 1e-5 pixel), which can only move samples lying that close to an
//! edge or a shadow boundary to its other side. (Power-of-two scales, which round nothing,
//! must give bit-identical images: the second test.)
//!
//! "Green" per case:
//! - every kernel: no NaN or infinite pixel;
//! - ray caster and AO: no hole. On the icosphere, every pixel whose centre ray passes
//!   within 0.999 of the mesh's inscribed radius of the centre hits it (the margin is 10^4
//!   times the rounding above); on the Cornell box and the slab, every pixel whose 3 × 3
//!   neighbourhood hits at unit scale hits at every scale. Misses are told apart by a
//!   background colour no surface can have.
//! - ray caster (no random numbers): at most 1% of the pixels differ from the unit-scale
//!   image by more than 1e-3 (edge and shadow-boundary pixels only; the failures this
//!   guards against, lost shading normals, self-shadowing, holes, escaping shadow rays,
//!   change 10% to 100% of them);
//! - AO on the icosphere and the slab: every pixel inside the silhouette is exactly the
//!   diffuse colour: nothing leaving a convex mesh outwards can hit it again, so any
//!   occlusion is self-intersection. (The slab is 2000 times wider than thick and tilted
//!   slightly, so its large faces are close to a coordinate plane without lying in it:
//!   the case where an offset from the hit point's own rounding error alone is far too
//!   small, as on the Cornell box's left wall.)
//! - AO and path tracer on the Cornell box: the mean displayed brightness (pixels clamped
//!   to [0, 1]) within 3% (AO) and 7% (path tracer) of the unit-scale image's. Random
//!   streams are the same at every scale, so the images agree pixel for pixel until a
//!   sample near an edge goes the other way and shifts its thread's stream; from then on
//!   they are independent. Over ten seeds, one image's mean varies by 0.47% (AO, 4 samples
//!   per pixel) and 1.2-1.3% (path tracer, 2 samples, 1 or 3 bounces), so the thresholds
//!   are about 4 standard deviations of the difference of two independent images; losing
//!   direct light or escaping the box costs more than a third of the brightness.

use trax::pipeline::{build_executable, lay_out};
use trax_assembler::image::RenderOptions;
use trax_assembler::scene::{load_scene, LoadOptions, Material, PointLight, Scene, View};
use trax_emulator::timing::{ChipConfig, DEFAULT_CHIP};
use trax_emulator::{run, Mode};

mod common;
use common::root;

const W: u32 = 64;
const H: u32 = 64;
const SCALES: std::ops::RangeInclusive<i32> = -20..=20;

fn compile(kernel: &str) -> Vec<u8> {
    build_executable(&root().join(kernel), 2).unwrap_or_else(|e| panic!("{kernel}: {e}"))
}

/// Renders `scene` with the linked kernel `elf`; returns the framebuffer (row 0 at the top).
fn render(elf: &[u8], scene: &Scene, k: &Kernel) -> Vec<[f32; 3]> {
    let opts = RenderOptions {
        width: W,
        height: H,
        spp: k.spp,
        max_depth: k.depth,
        background: k.background,
        ..RenderOptions::default()
    };
    let mut chip = ChipConfig::preset(DEFAULT_CHIP).unwrap();
    chip.tms = 2;
    chip.threads_per_tm = 4;
    let prepared = lay_out("kernel", elf.to_vec(), scene, &opts, &chip).unwrap();
    let mut out = Vec::new();
    let result = run(prepared.run_request(&chip, Mode::Functional), &mut out).unwrap();
    assert!(
        result.finished(),
        "{:?}\n{}",
        result.outcome,
        result.failure.clone().unwrap_or_default()
    );
    prepared
        .framebuffer(&result)
        .unwrap()
        .chunks(12)
        .map(|p| [0, 1, 2].map(|c| f32::from_le_bytes(p[c * 4..c * 4 + 4].try_into().unwrap())))
        .collect()
}

fn load(spec: &str, k: i32) -> Scene {
    load_scaled(spec, 10f64.powi(k))
}

/// A closed box 200 × 200 × 0.1 centred at the origin, its large faces nearly parallel to
/// and close to the plane z = 0 while 100 across, seen obliquely from above, with a point
/// light.
fn slab() -> Scene {
    let view = View {
        eye: [30.0, -250.0, 120.0],
        gaze: [-30.0, 250.0, -120.0],
        up: [0.0, 0.0, 1.0],
        aperture: 0.0,
        left: -1.0,
        right: 1.0,
        bottom: -1.0,
        top: 1.0,
        distance: 2.0,
    };
    let mut s = Scene::new("slab", view);
    s.materials = vec![Material {
        diffuse: [0.73; 3],
        ..Material::default_grey()
    }];
    // Tilted slightly (rotations of 0.02 and 0.013 radians about x and y), so its faces
    // are not axis-aligned and their coordinates are not exact.
    let (x, y, z) = (100.0f64, 100.0f64, 0.05f64);
    let (sa, ca) = 0.02f64.sin_cos();
    let (sb, cb) = 0.013f64.sin_cos();
    let c = |i: u32| {
        let p = [
            if i & 1 == 0 { -x } else { x },
            if i & 2 == 0 { -y } else { y },
            if i & 4 == 0 { -z } else { z },
        ];
        let q = [p[0], ca * p[1] - sa * p[2], sa * p[1] + ca * p[2]];
        [
            (cb * q[0] + sb * q[2]) as f32,
            q[1] as f32,
            (-sb * q[0] + cb * q[2]) as f32,
        ]
    };
    // Faces as corner indices, counter-clockwise from outside.
    for f in [
        [0, 2, 3, 1],
        [4, 5, 7, 6],
        [0, 1, 5, 4],
        [2, 6, 7, 3],
        [0, 4, 6, 2],
        [1, 3, 7, 5],
    ] {
        s.push_flat([c(f[0]), c(f[1]), c(f[2])], 0);
        s.push_flat([c(f[0]), c(f[2]), c(f[3])], 0);
    }
    s.point_lights = vec![PointLight {
        position: [-60.0, -80.0, 150.0],
        color: [1.0; 3],
    }];
    s.validate().unwrap();
    s
}

fn load_scaled(spec: &str, scale: f64) -> Scene {
    let k = scale.log10();
    if spec == "slab" {
        let mut s = slab();
        s.scale(scale).unwrap();
        return s;
    }
    let mut s = load_scene(
        spec,
        &LoadOptions {
            scale: Some(scale),
            ..LoadOptions::default()
        },
    )
    .unwrap_or_else(|e| panic!("{spec} at 1e{k}: {e}"));
    if spec == "cornell" {
        // Lit by its emitter only, whose radiance does not depend on scale.
        s.point_lights.clear();
    }
    s
}

/// Background of the ray caster and AO: a colour no surface of these scenes can show (it
/// is no multiple of a material's colour), so a pixel equal to it is a miss, whatever the
/// shading (AO can make a hit black).
const MISS: [f32; 3] = [0.125, 0.375, 0.875];

struct Kernel {
    name: &'static str,
    path: &'static str,
    spp: u32,
    depth: u32,
    background: [f32; 3],
}

const KERNELS: [Kernel; 4] = [
    Kernel {
        name: "raycast",
        path: "examples/raycast.rs",
        spp: 1,
        depth: 1,
        background: MISS,
    },
    Kernel {
        name: "ao",
        path: "examples/ao.rs",
        spp: 4,
        depth: 1,
        background: MISS,
    },
    // Direct light only (camera ray, light sample, shadow ray).
    Kernel {
        name: "pt-direct",
        path: "examples/pathtracer.rs",
        spp: 2,
        depth: 1,
        background: [0.0; 3],
    },
    // Paths of up to three bounces.
    Kernel {
        name: "pathtracer",
        path: "examples/pathtracer.rs",
        spp: 2,
        depth: 3,
        background: [0.0; 3],
    },
];

/// Pixels that must hit the scene: on the icosphere (`Some(..)`), those whose centre ray
/// passes within 0.999 × the inscribed radius of the centre (computed in f64 from the
/// unit-scale camera, with the prelude's ray formula); otherwise those whose 3 × 3
/// neighbourhood hits (is not [`MISS`]) in the unit-scale image `unit`.
fn must_hit(scene: &Scene, unit: &[[f32; 3]], icosphere: bool) -> Vec<bool> {
    let hit = |i: usize| unit[i] != MISS;
    if !icosphere {
        return (0..(W * H) as usize)
            .map(|i| {
                let (x, y) = ((i as u32 % W) as i64, (i as u32 / W) as i64);
                (-1..=1).all(|dy| {
                    (-1..=1).all(|dx| {
                        let (nx, ny) = (x + dx, y + dy);
                        nx < 0
                            || ny < 0
                            || nx >= W as i64
                            || ny >= H as i64
                            || hit((ny * W as i64 + nx) as usize)
                    })
                })
            })
            .collect();
    }
    let f = |v: [f32; 3]| v.map(|c| c as f64);
    let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let r_in = scene
        .triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(f);
            let e1 = [0, 1, 2].map(|i| b[i] - a[i]);
            let e2 = [0, 1, 2].map(|i| c[i] - a[i]);
            let n = [
                e1[1] * e2[2] - e1[2] * e2[1],
                e1[2] * e2[0] - e1[0] * e2[2],
                e1[0] * e2[1] - e1[1] * e2[0],
            ];
            dot(n, a).abs() / dot(n, n).sqrt()
        })
        .fold(f64::INFINITY, f64::min);
    let cam = scene.view.camera().unwrap();
    let (u, v, w, eye) = (f(cam.u), f(cam.v), f(cam.w), f(cam.eye));
    (0..(W * H) as usize)
        .map(|i| {
            let (px, py) = ((i as u32 % W) as f64 + 0.5, (i as u32 / W) as f64 + 0.5);
            let s = cam.left as f64 + (cam.right - cam.left) as f64 * px / W as f64;
            let t = cam.top as f64 - (cam.top - cam.bottom) as f64 * py / H as f64;
            let d = [0, 1, 2].map(|k| w[k] * cam.distance as f64 + u[k] * s + v[k] * t);
            let dl = dot(d, d).sqrt();
            let d = d.map(|c| c / dl);
            // Distance from the centre (the origin) to the ray's line.
            let along = -dot(eye, d);
            let closest = [0, 1, 2].map(|k| eye[k] + along * d[k]);
            dot(closest, closest).sqrt() < 0.999 * r_in
        })
        .collect()
}

#[derive(Default)]
struct Verdict {
    non_finite: usize,
    holes: usize,
    differ: usize,
    not_diffuse: usize,
    mean_ratio: f64,
}

/// Mean displayed brightness: channels clamped to [0, 1] (NaN counts as 0).
fn mean(img: &[[f32; 3]]) -> f64 {
    img.iter()
        .map(|p| p.iter().map(|&c| c.clamp(0.0, 1.0) as f64).sum::<f64>())
        .sum::<f64>()
        / (3 * img.len()) as f64
}

#[test]
fn scale_matrix_is_green_from_1e_minus_20_to_1e20() {
    let elfs: Vec<Vec<u8>> = KERNELS.iter().map(|k| compile(k.path)).collect();
    let verbose = std::env::var_os("TRAX_SCALE_MATRIX_REPORT").is_some();
    let mut failures = Vec::new();
    for spec in ["cornell", "icosphere:3", "slab"] {
        let icosphere = spec.starts_with("icosphere");
        // Closed convex meshes: AO must be exactly the diffuse colour inside.
        let convex = spec != "cornell";
        for (kernel, elf) in KERNELS.iter().zip(&elfs) {
            let name = kernel.name;
            let path_traced = kernel.path.ends_with("pathtracer.rs");
            if path_traced && convex {
                // No emitter: lit only by a point light, whose 1/d² falloff is not
                // scale-invariant.
                continue;
            }
            let unit_scene = load(spec, 0);
            let unit = render(elf, &unit_scene, kernel);
            let must = must_hit(&unit_scene, &unit, icosphere);
            if !path_traced {
                assert!(
                    must.iter().filter(|&&m| m).count() > (W * H / 8) as usize,
                    "{spec}: the silhouette test covers too few pixels"
                );
            }
            let unit_mean = mean(&unit);
            assert!(unit_mean > 0.01, "{spec} {name}: black unit-scale image");
            for k in SCALES {
                let img = render(elf, &load(spec, k), kernel);
                let mut v = Verdict {
                    mean_ratio: mean(&img) / unit_mean,
                    ..Verdict::default()
                };
                for (i, (p, q)) in img.iter().zip(&unit).enumerate() {
                    if p.iter().any(|c| !c.is_finite()) {
                        v.non_finite += 1;
                    }
                    if must[i] && *p == MISS {
                        v.holes += 1;
                    }
                    // NaN differs too.
                    let same = |a: f32, b: f32| (a - b).abs() <= 1e-3;
                    if p.iter().zip(q).any(|(&a, &b)| !same(a, b)) {
                        v.differ += 1;
                    }
                    if convex && must[i] && name == "ao" && *p != [0.73; 3] {
                        v.not_diffuse += 1;
                    }
                }
                let few_differ = v.differ * 100 <= (W * H) as usize;
                let mean_within = |x: f64| (v.mean_ratio - 1.0).abs() <= x;
                let green = v.non_finite == 0
                    && match (name, convex) {
                        ("raycast", _) => v.holes == 0 && few_differ,
                        ("ao", true) => v.holes == 0 && v.not_diffuse == 0,
                        ("ao", false) => v.holes == 0 && mean_within(0.03),
                        _ => mean_within(0.07),
                    };
                let line = format!(
                    "{spec:<12} {name:<10} 1e{k:<4} non-finite {:>4}  holes {:>4}  differ {:>4}  not-diffuse {:>4}  mean/unit {:.4}{}",
                    v.non_finite,
                    v.holes,
                    v.differ,
                    v.not_diffuse,
                    v.mean_ratio,
                    if green { "" } else { "  RED" }
                );
                if verbose {
                    eprintln!("{line}");
                }
                if !green {
                    failures.push(line);
                }
            }
        }
    }
    assert!(
        failures.is_empty(),
        "{} red case(s):\n{}",
        failures.len(),
        failures.join("\n")
    );
}

/// Scaling by a power of two is exact, and every step of the kernels is either
/// scale-invariant or scales exactly (the prelude's rescaling factors are powers of two),
/// so such scales must give bit-identical images, as far out as 2^±64 (about 1.8e±19).
#[test]
fn power_of_two_scales_render_bit_identical_images() {
    for kernel in &KERNELS {
        let elf = compile(kernel.path);
        for spec in ["cornell", "icosphere:2"] {
            if kernel.path.ends_with("pathtracer.rs") && spec != "cornell" {
                continue;
            }
            let unit = render(&elf, &load_scaled(spec, 1.0), kernel);
            for e in [-64, -20, 20, 64] {
                let img = render(&elf, &load_scaled(spec, 2f64.powi(e)), kernel);
                let first = img
                    .iter()
                    .zip(&unit)
                    .position(|(a, b)| a.iter().zip(b).any(|(x, y)| x.to_bits() != y.to_bits()));
                assert!(
                    first.is_none(),
                    "{spec} {} at 2^{e}: pixel {} is {:?}, {:?} at unit scale",
                    kernel.name,
                    first.unwrap(),
                    img[first.unwrap()],
                    unit[first.unwrap()]
                );
            }
        }
    }
}
