//! The kernel prelude compiled by rustc for the host: proves it is valid Rust, that its
//! accessors read every scene component exactly as the runtime's encoders write it (real
//! bytes of the scene contract, `abi::SCENE_COMPONENTS`), that the TRaX side
//! only names real instructions and header symbols, and tests the host implementation
//! (threads, memory, RNG, Vec3 math, camera rays, BVH traversal, SIMD semantics).

#[path = "../prelude/lib.rs"]
#[allow(dead_code, unused_imports)]
mod trax;

use std::mem::{offset_of, size_of};
use trax::layout as L;
use trax::{Ray, Vec3};
use trax_runtime::abi::{self, Camera, Component, Field, SceneHeader, Struct};
use trax_runtime::host::{header_only_image, look_at_camera, HeaderParams};
use trax_runtime::image::{MemoryImage, Perms, Segment};

// ---------------------------------------------------------------------------------------
// Layout: the prelude's constants against the Rust definitions.

#[test]
fn header_offsets_match_abi() {
    let expected: Vec<(&str, u32)> = vec![
        ("magic", L::HDR_MAGIC),
        ("version", L::HDR_VERSION),
        ("width", L::HDR_WIDTH),
        ("height", L::HDR_HEIGHT),
        ("inv_width", L::HDR_INV_WIDTH),
        ("inv_height", L::HDR_INV_HEIGHT),
        ("spp", L::HDR_SPP),
        ("max_depth", L::HDR_MAX_DEPTH),
        ("epsilon", L::HDR_EPSILON),
        ("seed", L::HDR_SEED),
        ("background", L::HDR_BACKGROUND),
        ("camera", L::HDR_CAMERA),
        ("framebuffer", L::HDR_FRAMEBUFFER),
        ("bvh_nodes", L::HDR_BVH_NODES),
        ("triangles", L::HDR_TRIANGLES),
        ("normals", L::HDR_NORMALS),
        ("texcoords", L::HDR_TEXCOORDS),
        ("material_ids", L::HDR_MATERIAL_IDS),
        ("materials", L::HDR_MATERIALS),
        ("emitters", L::HDR_EMITTERS),
        ("point_lights", L::HDR_POINT_LIGHTS),
        ("bvh_parents", L::HDR_BVH_PARENTS),
        ("treelet_ids", L::HDR_TREELET_IDS),
        ("tri_treelet_ids", L::HDR_TRI_TREELET_IDS),
        ("tri_leaf_ids", L::HDR_TRI_LEAF_IDS),
        ("stream_rays", L::HDR_STREAM_RAYS),
        ("stream_ray_bytes", L::HDR_STREAM_RAY_BYTES),
        ("stream_buffers", L::HDR_STREAM_BUFFERS),
        ("pipe_modes", L::HDR_PIPE_MODES),
        ("reserved", L::HDR_RESERVED),
    ];
    let abi_fields = abi::scene_header_fields();
    assert_eq!(
        abi_fields.len(),
        expected.len(),
        "prelude misses a header field"
    );
    for ((name, off), (pname, poff)) in abi_fields.iter().zip(&expected) {
        assert_eq!(name, pname);
        assert_eq!(*off as u32, *poff, "offset of header field {name}");
    }
    assert_eq!(L::HDR_SIZE as usize, size_of::<SceneHeader>());
    assert_eq!(L::SCENE_HEADER_ADDR, abi::SCENE_HEADER_ADDR);
    assert_eq!(L::COMPONENT_ADDR as usize, offset_of!(Component, addr));
    assert_eq!(L::COMPONENT_COUNT as usize, offset_of!(Component, count));
}

#[test]
fn camera_offsets_match_abi() {
    let pairs = [
        (L::CAM_EYE, offset_of!(Camera, eye)),
        (L::CAM_U, offset_of!(Camera, u)),
        (L::CAM_V, offset_of!(Camera, v)),
        (L::CAM_W, offset_of!(Camera, w)),
        (L::CAM_LEFT, offset_of!(Camera, left)),
        (L::CAM_RIGHT, offset_of!(Camera, right)),
        (L::CAM_BOTTOM, offset_of!(Camera, bottom)),
        (L::CAM_TOP, offset_of!(Camera, top)),
        (L::CAM_DISTANCE, offset_of!(Camera, distance)),
        (L::CAM_APERTURE, offset_of!(Camera, aperture)),
        (L::CAM_SIZE, size_of::<Camera>()),
    ];
    for (i, (p, a)) in pairs.iter().enumerate() {
        assert_eq!(*p as usize, *a, "camera offset #{i}");
    }
}

/// Where the contract kernel writes back what it read.
const CONTRACT_PROBE: u32 = 0x0070_0000;
/// Elements per component in the contract image.
const N: u32 = 3;

/// A value of `T` whose every word is distinct (word `k` is `base + k`), as f32 bits
/// that are finite and exactly representable (so arithmetic on them stays exact).
fn distinct<T: Field>(base: u32) -> T {
    let bytes: Vec<u8> = (0..std::mem::size_of::<T>() as u32 / 4)
        .flat_map(|k| ((base + k) as f32).to_bits().to_le_bytes())
        .collect();
    abi::decode(&bytes).unwrap()
}

/// Every component of the contract with `N` distinct elements (unit normals, so the
/// prelude's normalisation is exact), encoded by the runtime, and the header pointing
/// at them.
fn contract_image() -> (MemoryImage, Vec<(&'static str, Vec<u8>)>) {
    let mut header = SceneHeader {
        magic: abi::SCENE_MAGIC,
        version: abi::SCENE_VERSION,
        width: 4,
        height: 2,
        ..distinct::<SceneHeader>(100)
    };
    let mut segments = Vec::new();
    let mut encoded = Vec::new();
    for (k, c) in abi::SCENE_COMPONENTS.iter().enumerate() {
        let addr = 0x0050_0000 + 0x1000 * k as u32;
        let base = 1000 * (k as u32 + 1);
        let (count, bytes) = match c.name {
            "camera" => (1, distinct::<Camera>(base).to_bytes()),
            "framebuffer" => (8, vec![0; 8 * abi::PIXEL_BYTES as usize]),
            "normals" => {
                let unit = |a: usize| {
                    let mut v = [0.0f32; 3];
                    v[a % 3] = 1.0;
                    v
                };
                let n = (0..N as usize).map(|i| abi::VertexNormals {
                    n0: unit(i),
                    n1: unit(i + 1),
                    n2: unit(i + 2),
                });
                (N, abi::encode(n))
            }
            // Index components hold small indices (the prelude indexes with them).
            "material_ids" | "emitters" | "bvh_parents" | "treelet_ids" | "tri_treelet_ids"
            | "tri_leaf_ids" => (N, abi::encode((0..N).map(|i| (i * 7 + k as u32) % 5))),
            _ => {
                let n = c.element_bytes / 4;
                let words = (0..N * n).map(|w| ((base + w) as f32).to_bits());
                (N, abi::encode(words))
            }
        };
        (c.set)(&mut header, Component { addr, count });
        let perms = match c.access {
            abi::Access::ReadOnly => Perms::R,
            abi::Access::ReadWrite => Perms::RW,
        };
        segments.push(Segment::new(c.name, addr, bytes.clone(), perms));
        encoded.push((c.name, bytes));
    }
    segments.push(Segment::new(
        "scene_header",
        abi::SCENE_HEADER_ADDR,
        header.to_bytes(),
        Perms::R,
    ));
    segments.push(Segment::new(
        "probe",
        CONTRACT_PROBE,
        vec![0; 0x1_0000],
        Perms::RW,
    ));
    (MemoryImage { segments }, encoded)
}

/// Reads every component through the prelude's accessors and writes what it read, field
/// by field in the contract's order, to `CONTRACT_PROBE` (one component after another,
/// in table order); writes the framebuffer through `set_pixel_index`.
fn contract_kernel() {
    use trax::scene as S;
    let mut at = CONTRACT_PROBE;
    let mut put = |w: u32| {
        trax::store_u32(at, w);
        at += 4;
    };
    let v3 = |put: &mut dyn FnMut(u32), v: Vec3| {
        for x in [v.x, v.y, v.z] {
            put(x.to_bits());
        }
    };
    let cam = trax::Camera::load();
    for v in [cam.eye, cam.u, cam.v, cam.w] {
        v3(&mut put, v);
    }
    for x in [cam.left, cam.right, cam.bottom, cam.top, cam.distance] {
        put(x.to_bits());
    }
    for i in 0..S::width() * S::height() {
        S::set_pixel_index(i, Vec3::new(i as f32, 0.5, -2.0));
    }
    for i in 0..S::bvh_node_count() {
        let n = S::bvh_node(i);
        v3(&mut put, n.min);
        v3(&mut put, n.max);
        put(n.a);
        put(n.b);
    }
    for i in 0..S::triangle_count() {
        let t = S::triangle(i);
        for v in [t.v0, t.v1, t.v2] {
            v3(&mut put, v);
        }
    }
    for i in 0..S::normals_count() {
        for (u, v) in [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0)] {
            v3(&mut put, S::shading_normal(i, u, v));
        }
    }
    for i in 0..S::texcoords_count() {
        for (u, v) in [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0)] {
            let t = S::texcoord(i, u, v);
            put(t.x.to_bits());
            put(t.y.to_bits());
        }
    }
    for i in 0..N {
        put(S::material_id(i));
    }
    for m in 0..S::material_count() {
        let m = S::material(m);
        for v in [m.diffuse, m.specular, m.emission] {
            v3(&mut put, v);
        }
        put(m.shininess.to_bits());
        put(m.flags);
    }
    for k in 0..S::emitter_count() {
        put(S::emitter(k));
    }
    for k in 0..S::point_light_count() {
        let l = S::point_light(k);
        v3(&mut put, l.position);
        v3(&mut put, l.color);
    }
    for i in 0..N {
        put(S::bvh_parent(i));
    }
    for i in 0..N {
        put(S::treelet_id(i));
    }
    for i in 0..N {
        put(S::tri_treelet_id(i));
    }
    let leaves = S::tri_leaf_ids_base();
    for i in 0..N {
        put(S::tri_leaf_at(leaves, i));
    }
}

#[test]
fn prelude_reads_every_component_as_the_runtime_encodes_it() {
    let (img, encoded) = contract_image();
    let out = trax::host::run_image(&to_image(&img), 1, 1, contract_kernel).unwrap();
    // What the kernel read, component by component, must be the encoded bytes (the
    // prelude does not read the camera's aperture nor a material's reserved word).
    let mut at = CONTRACT_PROBE;
    for (name, bytes) in &encoded {
        let want: Vec<u8> = match *name {
            "framebuffer" => continue,
            "camera" => bytes[..abi::Camera::layout().field("aperture").unwrap().offset].to_vec(),
            "materials" => bytes
                .chunks(std::mem::size_of::<abi::Material>())
                .flat_map(|m| m[..44].to_vec())
                .collect(),
            _ => bytes.clone(),
        };
        let got = out.read(at, want.len() as u32).unwrap();
        assert_eq!(got, want, "component `{name}` read through the prelude");
        at += want.len() as u32;
    }
    // The framebuffer the kernel wrote decodes as the runtime's pixels.
    let fb = img.segment("framebuffer").unwrap().addr;
    for i in 0..8u32 {
        let b = out
            .read(fb + i * abi::PIXEL_BYTES, abi::PIXEL_BYTES)
            .unwrap();
        let p: abi::Pixel = abi::decode(&b).unwrap();
        assert_eq!([p.r, p.g, p.b], [i as f32, 0.5, -2.0]);
    }
}

#[test]
fn prelude_stores_to_read_only_memory_panic() {
    fn store_to_scene() {
        trax::store_u32(trax::scene::camera_addr(), 1);
    }
    let (img, _) = contract_image();
    match trax::host::run_image(&to_image(&img), 1, 1, store_to_scene) {
        Err(trax::host::RunError::Panicked(ids)) => assert_eq!(ids, vec![0]),
        other => panic!("expected a panic, got {:?}", other.map(|_| ())),
    }
}

/// `fn NAME() -> u32 { BODY }` items of a source file, as (name, body).
fn functions(src: &str) -> Vec<(String, String)> {
    let mut out = Vec::new();
    let mut rest = src;
    while let Some(i) = rest.find("pub fn ") {
        rest = &rest[i + 7..];
        let name: String = rest
            .chars()
            .take_while(|c| c.is_alphanumeric() || *c == '_')
            .collect();
        let open = rest.find('{').unwrap();
        let mut depth = 0;
        let mut end = open;
        for (k, c) in rest[open..].char_indices() {
            match c {
                '{' => depth += 1,
                '}' => {
                    depth -= 1;
                    if depth == 0 {
                        end = open + k;
                        break;
                    }
                }
                _ => {}
            }
        }
        out.push((name, rest[open + 1..end].to_string()));
        rest = &rest[end..];
    }
    out
}

#[test]
fn trax_header_accessors_reference_only_their_own_symbol() {
    let src = trax_runtime::prelude::file("hw_trax.rs").unwrap();
    let fns = functions(src);
    for (name, _) in abi::scene_header_fields() {
        if name == "reserved" {
            continue;
        }
        let f = format!("hdr_{name}");
        let (_, body) = fns
            .iter()
            .find(|(n, _)| *n == f)
            .unwrap_or_else(|| panic!("hw_trax.rs lacks {f}"));
        assert_eq!(body.matches("__trax_symbol_addr!").count(), 1, "{f}");
        assert!(
            body.contains(&format!("__trax_symbol_addr!(\"__trax_scene_{name}\")")),
            "{f}: {body}"
        );
    }
    // No other function names a scene symbol.
    for (n, body) in &fns {
        if !n.starts_with("hdr_") {
            assert!(
                !body.contains("__trax_scene_"),
                "{n} references a scene symbol"
            );
        }
    }
}

#[test]
fn host_header_accessors_match_offsets() {
    // The host hw module is private; reach its header accessors through the scene API
    // by reading a header whose every word is distinct.
    let mut img = header_only_image(&HeaderParams::default()).unwrap();
    let words = abi::SCENE_HEADER_SIZE / 4;
    img.segments[0].data = (0..words as u32)
        .flat_map(|w| (1000 + w).to_le_bytes())
        .collect();
    let out = run(&img, 1, 1, read_header_kernel);
    let got = read_words(&out, FB_PROBE, 13);
    assert_eq!(got[0], 0, "a header with a wrong magic is not valid");
    let got = &got[1..];
    let word = |off: u32| 1000 + off / 4;
    assert_eq!(got[0], word(L::HDR_WIDTH));
    assert_eq!(got[1], word(L::HDR_HEIGHT));
    assert_eq!(got[2], word(L::HDR_SPP));
    assert_eq!(got[3], word(L::HDR_MAX_DEPTH));
    assert_eq!(got[4], word(L::HDR_SEED));
    assert_eq!(got[5], word(L::HDR_TRIANGLES + 4));
    assert_eq!(got[6], word(L::HDR_BVH_NODES + 4));
    assert_eq!(got[7], word(L::HDR_EMITTERS + 4));
    assert_eq!(got[8], word(L::HDR_POINT_LIGHTS + 4));
    assert_eq!(got[9], word(L::HDR_MATERIALS + 4));
    assert_eq!(got[10], word(L::HDR_CAMERA));
    assert_eq!(got[11], word(L::HDR_NORMALS + 4));
}

/// Where probe kernels write results: a scratch segment.
const FB_PROBE: u32 = 0x0040_0000;

fn read_header_kernel() {
    let vals = [
        trax::scene::header_is_valid() as u32,
        trax::scene::width(),
        trax::scene::height(),
        trax::scene::spp(),
        trax::scene::max_depth(),
        trax::scene::seed(),
        trax::scene::triangle_count(),
        trax::scene::bvh_node_count(),
        trax::scene::emitter_count(),
        trax::scene::point_light_count(),
        trax::scene::material_count(),
        trax::scene::camera_addr(),
        trax::scene::normals_count(),
    ];
    for (i, v) in vals.iter().enumerate() {
        trax::store_u32(FB_PROBE + 4 * i as u32, *v);
    }
}

fn magic_kernel() {
    trax::store_u32(FB_PROBE, trax::scene::header_is_valid() as u32);
}

#[test]
fn header_magic_and_version_are_recognised() {
    let img = header_only_image(&HeaderParams::default()).unwrap();
    assert_eq!(
        read_words(&run(&img, 1, 1, magic_kernel), FB_PROBE, 1)[0],
        1
    );
}

#[test]
fn trax_side_names_only_real_instructions() {
    use trax_runtime::isa::{OperandKind, TRAX_INSTRUCTIONS};
    let src = trax_runtime::prelude::file("hw_trax.rs").unwrap();
    let mut seen = 0;
    for (at, _) in src.match_indices("__trax_op!(") {
        let args = &src[at + 11..at + 11 + src[at + 11..].find(')').unwrap()];
        let parts: Vec<&str> = args.split(',').map(str::trim).collect();
        let mn = parts[0].trim_matches('"');
        let row = TRAX_INSTRUCTIONS
            .iter()
            .find(|i| i.mnemonic == mn)
            .unwrap_or_else(|| panic!("unknown mnemonic {mn}"));
        let uses = row.operands.iter().filter(|o| !o.kind.is_def()).count();
        assert_eq!(parts.len() - 1, uses, "{mn}: use-operand count");
        for (o, p) in row
            .operands
            .iter()
            .filter(|o| !o.kind.is_def())
            .zip(&parts[1..])
        {
            if o.kind == OperandKind::Imm5 {
                let v: u32 = p
                    .parse()
                    .unwrap_or_else(|_| panic!("{mn}: Imm5 must be a literal"));
                assert!(v < 32);
            }
        }
        seen += 1;
    }
    assert!(seen >= 20, "only {seen} ops");
}

#[test]
fn prelude_files_are_the_embedded_ones() {
    for (p, src) in trax_runtime::prelude::FILES {
        let disk = std::fs::read_to_string(format!("{}/{p}", trax_runtime::prelude::DIR)).unwrap();
        assert_eq!(&disk, src, "{p}");
    }
}

// ---------------------------------------------------------------------------------------
// Host runner helpers.

/// The runtime's image as the prelude's (the same source compiled into the prelude crate),
/// through the one file format.
fn to_image(m: &MemoryImage) -> trax::host::Image {
    trax::host::parse_image(&m.to_bytes()).unwrap()
}

fn with_probe(mut m: MemoryImage) -> MemoryImage {
    m.segments
        .push(Segment::new("probe", FB_PROBE, vec![0; 4096], Perms::RW));
    m
}

fn run(m: &MemoryImage, tms: u32, threads: u32, k: fn()) -> trax::host::Image {
    let m = with_probe(m.clone());
    trax::host::run_image(&to_image(&m), tms, threads, k).unwrap_or_else(|e| panic!("{e}"))
}

fn read_words(img: &trax::host::Image, addr: u32, n: usize) -> Vec<u32> {
    img.read(addr, 4 * n as u32)
        .unwrap()
        .chunks(4)
        .map(|c| u32::from_le_bytes(c.try_into().unwrap()))
        .collect()
}

fn read_f32s(img: &trax::host::Image, addr: u32, n: usize) -> Vec<f32> {
    read_words(img, addr, n)
        .into_iter()
        .map(f32::from_bits)
        .collect()
}

// ---------------------------------------------------------------------------------------
// Threads, global registers, RNG.

fn ids_kernel() {
    let g = trax::global_id();
    assert_eq!(g, trax::tm_id() * 4 + trax::thread_id());
    let slot = trax::atomic_inc(0);
    trax::store_u32(FB_PROBE + 4 * slot, g + 1);
    trax::atomic_add(1, g);
    trax::barrier(2);
    // After the barrier every thread has added.
    trax::store_u32(FB_PROBE + 256 + 4 * g, trax::global_read(1));
    trax::store_u32(FB_PROBE + 512, trax::num_threads() * 100 + trax::num_tms());
}

#[test]
fn threads_ids_atomics_and_barrier() {
    let img = header_only_image(&HeaderParams::default()).unwrap();
    let out = run(&img, 3, 4, ids_kernel);
    let mut slots = read_words(&out, FB_PROBE, 12);
    slots.sort();
    assert_eq!(slots, (1..=12).collect::<Vec<u32>>());
    let sums = read_words(&out, FB_PROBE + 256, 12);
    assert!(sums.iter().all(|&s| s == 66), "{sums:?}");
    assert_eq!(read_words(&out, FB_PROBE + 512, 1)[0], 1203);
}

fn stat_kernel() {
    let g = trax::global_id();
    trax::stat::add(5, g + 1);
    trax::stat::inc(31);
    trax::count_ray();
}

/// `trax::stat` counters are summed over every thread (counter 0 is `count_ray`'s), as
/// the machine sums `trax.statadd`; their count is the machine's.
#[test]
fn stat_counters_are_summed_over_threads() {
    assert_eq!(
        trax::stat::COUNTERS as usize,
        trax_runtime::counters::NUM_STATS
    );
    let img = header_only_image(&HeaderParams::default()).unwrap();
    let (_, stats) = trax::host::run_image_stats(&to_image(&img), 2, 3, stat_kernel).unwrap();
    let mut expected = [0u64; trax_runtime::counters::NUM_STATS];
    expected[0] = 6;
    expected[5] = (1..=6).sum();
    expected[31] = 6;
    assert_eq!(stats.counters, expected);
    assert_eq!(stats.rays, 6);
}

fn stat_out_of_range_kernel() {
    trax::stat::add(trax::stat::COUNTERS, 1);
}

/// A counter past the last stops the program, as `trax.statadd` faults on the machine.
#[test]
fn a_stat_counter_out_of_range_panics() {
    let img = header_only_image(&HeaderParams::default()).unwrap();
    let r = trax::host::run_image(&to_image(&img), 1, 1, stat_out_of_range_kernel);
    assert!(r.is_err());
}

fn early_exit_barrier_kernel() {
    // Odd threads return at once; the barrier must not wait for them.
    if trax::global_id() % 2 == 1 {
        return;
    }
    trax::barrier(5);
    trax::atomic_inc(6);
    trax::store_u32(FB_PROBE, trax::global_read(6));
}

#[test]
fn barrier_counts_only_live_threads() {
    let img = header_only_image(&HeaderParams::default()).unwrap();
    let out = run(&img, 1, 6, early_exit_barrier_kernel);
    assert!(read_words(&out, FB_PROBE, 1)[0] >= 1);
}

fn semaphore_kernel() {
    // A mutex from a semaphore: non-atomic read-modify-write of memory under it.
    if trax::global_id() == 0 {
        trax::sem_release(3);
    }
    let mut i = 0;
    while i < 200 {
        trax::sem_acquire(3);
        let v = trax::load_u32(FB_PROBE);
        trax::store_u32(FB_PROBE, v + 1);
        trax::sem_release(3);
        i += 1;
    }
    let _ = trax::inc_reset(7);
}

#[test]
fn semaphores_exclude() {
    let img = header_only_image(&HeaderParams::default()).unwrap();
    let out = run(&img, 2, 4, semaphore_kernel);
    assert_eq!(read_words(&out, FB_PROBE, 1)[0], 1600);
}

fn rand_kernel() {
    let g = trax::global_id();
    let mut i = 0;
    while i < 4 {
        trax::store_f32(FB_PROBE + 16 * g + 4 * i, trax::rand());
        i += 1;
    }
}

#[test]
fn rand_matches_the_emulator_rng() {
    let p = HeaderParams {
        seed: 77,
        ..HeaderParams::default()
    };
    let img = header_only_image(&p).unwrap();
    let out = run(&img, 1, 5, rand_kernel);
    for g in 0..5 {
        let mut r = trax_runtime::rng::Rng::new(77, g);
        let want: Vec<f32> = (0..4).map(|_| r.next_f32()).collect();
        assert_eq!(read_f32s(&out, FB_PROBE + 16 * g, 4), want, "thread {g}");
    }
}

fn seed_kernel() {
    let g = trax::global_id();
    // Every thread first draws from its own stream, then from pixel 500 or 501's.
    trax::store_f32(FB_PROBE + 16 * g, trax::rand());
    trax::seed_pixel(500 + g % 2, 7);
    let mut i = 1;
    while i < 4 {
        trax::store_f32(FB_PROBE + 16 * g + 4 * i, trax::rand());
        i += 1;
    }
}

#[test]
fn seed_pixel_matches_the_emulator_rng_on_every_thread() {
    let p = HeaderParams {
        seed: 77,
        ..HeaderParams::default()
    };
    let img = header_only_image(&p).unwrap();
    let out = run(&img, 2, 3, seed_kernel);
    for g in 0..6 {
        let mut want = vec![trax_runtime::rng::Rng::new(77, g).next_f32()];
        let mut r = trax_runtime::rng::Rng::for_sample(77, 500 + g % 2, 7);
        want.extend((0..3).map(|_| r.next_f32()));
        assert_eq!(read_f32s(&out, FB_PROBE + 16 * g, 4), want, "thread {g}");
    }
    // Threads 0 and 2 drew pixel 500's numbers, thread 1 pixel 501's.
    assert_eq!(
        read_f32s(&out, FB_PROBE + 4, 3),
        read_f32s(&out, FB_PROBE + 36, 3)
    );
    assert_ne!(
        read_f32s(&out, FB_PROBE + 4, 3),
        read_f32s(&out, FB_PROBE + 20, 3)
    );
}

/// Pixel `i`'s hand-out count lives at `FB_PROBE + 4 i`, thread `g`'s share size at
/// `FB_PROBE + 2048 + 4 g`.
fn pixel_share_kernel() {
    let mut share = trax::scene::pixel_share();
    let mut mine = 0;
    loop {
        let i = share.next_pixel();
        if i == trax::scene::NO_PIXEL {
            break;
        }
        let a = FB_PROBE + 4 * i;
        trax::store_u32(a, trax::load_u32(a) + 1);
        mine += 1;
    }
    // Stays exhausted.
    assert_eq!(share.next_pixel(), trax::scene::NO_PIXEL);
    trax::store_u32(FB_PROBE + 2048 + 4 * trax::global_id(), mine);
}

#[test]
fn pixel_share_hands_out_every_pixel_once() {
    let p = HeaderParams {
        width: 20,
        height: 15,
        ..HeaderParams::default()
    };
    let img = header_only_image(&p).unwrap();
    let out = run(&img, 3, 4, pixel_share_kernel);
    assert_eq!(read_words(&out, FB_PROBE, 300), vec![1; 300]);
    assert_eq!(read_words(&out, FB_PROBE + 4 * 300, 1), vec![0]);
    let shares = read_words(&out, FB_PROBE + 2048, 12);
    assert_eq!(shares.iter().sum::<u32>(), 300, "{shares:?}");
}

fn bad_address_kernel() {
    trax::load_u32(0x7000_0000);
}

#[test]
fn bad_address_panics_and_is_reported() {
    let img = to_image(&header_only_image(&HeaderParams::default()).unwrap());
    let r = trax::host::run_image(&img, 1, 2, bad_address_kernel);
    match r {
        Err(trax::host::RunError::Panicked(ids)) => assert_eq!(ids, vec![0, 1]),
        other => panic!("expected a panic, got {:?}", other.map(|_| ())),
    }
    assert!(matches!(
        trax::host::run_image(&img, 0, 2, bad_address_kernel),
        Err(trax::host::RunError::Setup(_))
    ));
}

#[test]
fn image_format_round_trips_between_runtime_and_prelude() {
    let img = header_only_image(&HeaderParams::default()).unwrap();
    let bytes = img.to_bytes();
    let parsed = trax::host::parse_image(&bytes).unwrap();
    assert_eq!(trax::host::image_bytes(&parsed), bytes);
    assert_eq!(parsed.segments.len(), img.segments.len());
    assert!(trax::host::parse_image(&bytes[..bytes.len() - 2]).is_err());
    assert!(trax::host::parse_image(b"TRAXIMG1\0\0\0\0").is_err());
    let fb = trax::host::framebuffer_segment(&parsed);
    assert_eq!(fb.segments.len(), 1);
    assert_eq!(
        fb.segments[0].data.len() as u32,
        128 * 128 * abi::PIXEL_BYTES
    );
    assert!(fb.segments[0].perms.write());
}

// ---------------------------------------------------------------------------------------
// Math.

fn close(a: f32, b: f32, tol: f32) -> bool {
    (a - b).abs() <= tol
}

#[test]
fn vec3_math() {
    let a = Vec3::new(1.0, 2.0, 3.0);
    let b = Vec3::new(-2.0, 0.5, 4.0);
    let s = a + b;
    assert_eq!((s.x, s.y, s.z), (-1.0, 2.5, 7.0));
    let d = a - b;
    assert_eq!((d.x, d.y, d.z), (3.0, 1.5, -1.0));
    let m = a * b;
    assert_eq!((m.x, m.y, m.z), (-2.0, 1.0, 12.0));
    let q = a / b;
    assert_eq!((q.x, q.y, q.z), (-0.5, 4.0, 0.75));
    let n = -a;
    assert_eq!((n.x, n.y, n.z), (-1.0, -2.0, -3.0));
    assert_eq!(a.dot(b), 11.0);
    let c = a.cross(b);
    assert_eq!((c.x, c.y, c.z), (6.5, -10.0, 4.5));
    assert_eq!(c.dot(a), 0.0);
    assert!(close(Vec3::new(3.0, 4.0, 0.0).length(), 5.0, 0.0));
    let u = Vec3::new(3.0, 4.0, 12.0).normalize();
    assert!(close(u.length(), 1.0, 1e-6));
    assert!(close(u.z, 12.0 / 13.0, 1e-6));
    let mut acc = Vec3::splat(1.0);
    acc += a;
    acc -= b;
    acc *= Vec3::splat(2.0);
    acc /= Vec3::splat(4.0);
    assert_eq!((acc.x, acc.y, acc.z), (2.0, 1.25, 0.0));
    assert_eq!(a.min(b).x, -2.0);
    assert_eq!(a.max(b).z, 4.0);
    assert_eq!(b.min_component(), -2.0);
    assert_eq!(b.max_component(), 4.0);
    assert_eq!(b.max_dimension(), 2);
    assert_eq!(Vec3::new(-5.0, 1.0, 2.0).max_dimension(), 0);
    assert_eq!((a.get(0), a.get(1), a.get(2)), (1.0, 2.0, 3.0));
    let cl = Vec3::new(-1.0, 0.5, 9.0).clamp(0.0, 1.0);
    assert_eq!((cl.x, cl.y, cl.z), (0.0, 0.5, 1.0));
    let r = Vec3::new(1.0, -1.0, 0.0).reflect(Vec3::new(0.0, 1.0, 0.0));
    assert_eq!((r.x, r.y, r.z), (1.0, 1.0, 0.0));
    assert!(close(Vec3::splat(1.0).luminance(), 1.0, 1e-6));
    assert_eq!(trax::min(-0.0, 0.0).to_bits(), (-0.0f32).to_bits());
    assert_eq!(trax::max(f32::NAN, 2.0), 2.0);
    assert_eq!(trax::invsqrt(16.0), 0.25);
    assert_eq!(trax::clamp(2.0, 0.0, 1.0), 1.0);
}

#[test]
fn onb_is_orthonormal() {
    for n in [
        Vec3::new(0.0, 0.0, 1.0),
        Vec3::new(0.0, 0.0, -1.0),
        Vec3::new(1.0, 2.0, -3.0).normalize(),
        Vec3::new(-0.3, 0.9, 0.1).normalize(),
    ] {
        let b = trax::sampling::Onb::new(n);
        assert!(close(b.t.length(), 1.0, 1e-5) && close(b.b.length(), 1.0, 1e-5));
        assert!(close(b.t.dot(b.b), 0.0, 1e-5) && close(b.t.dot(n), 0.0, 1e-5));
        assert!(close(b.b.dot(n), 0.0, 1e-5));
        let w = b.to_world(Vec3::new(0.0, 0.0, 1.0));
        assert!(close(w.dot(n), 1.0, 1e-5));
    }
}

fn sampling_kernel() {
    let n = Vec3::new(0.0, 1.0, 0.0);
    let mut sum_cos = 0.0;
    let mut below = 0u32;
    let k = 20000;
    let mut i = 0;
    while i < k {
        let d = trax::sampling::cosine_hemisphere(n);
        if d.dot(n) < 0.0 || (d.length() - 1.0).abs() > 1e-4 {
            below += 1;
        }
        sum_cos += d.dot(n);
        i += 1;
    }
    trax::store_f32(FB_PROBE, sum_cos / k as f32);
    trax::store_u32(FB_PROBE + 4, below);
}

#[test]
fn cosine_hemisphere_has_the_right_mean() {
    // E[cos theta] under the pdf cos/pi is 2/3.
    let img = header_only_image(&HeaderParams::default()).unwrap();
    let out = run(&img, 1, 1, sampling_kernel);
    let mean = read_f32s(&out, FB_PROBE, 1)[0];
    assert!(close(mean, 2.0 / 3.0, 0.01), "{mean}");
    assert_eq!(read_words(&out, FB_PROBE + 4, 1)[0], 0);
}

// ---------------------------------------------------------------------------------------
// Camera.

fn camera_kernel() {
    let cam = trax::Camera::load();
    let w = trax::scene::width();
    let h = trax::scene::height();
    let pix = [(0, 0), (w - 1, 0), (0, h - 1), (w / 2, h / 3)];
    for (i, (x, y)) in pix.iter().enumerate() {
        let r = cam.pixel_ray(*x, *y);
        let a = FB_PROBE + 24 * i as u32;
        trax::scene::store_vec3(a, r.origin);
        trax::scene::store_vec3(a + 12, r.dir);
    }
}

#[test]
fn camera_rays_follow_abi_semantics() {
    let (w, h) = (40u32, 30u32);
    let cam = look_at_camera(
        [1.0, 2.0, 8.0],
        [0.0, 0.5, 0.0],
        [0.0, 1.0, 0.0],
        50.0,
        4.0 / 3.0,
    );
    let p = HeaderParams {
        width: w,
        height: h,
        camera: cam,
        ..HeaderParams::default()
    };
    let out = run(&header_only_image(&p).unwrap(), 1, 1, camera_kernel);
    let pix = [(0, 0), (w - 1, 0), (0, h - 1), (w / 2, h / 3)];
    for (i, (x, row)) in pix.iter().enumerate() {
        // abi::Camera's formula, with y counted from the bottom (row 0 is the top).
        let y = h - 1 - row;
        let s = cam.left + (cam.right - cam.left) * (*x as f32 + 0.5) / w as f32;
        let t = cam.bottom + (cam.top - cam.bottom) * (y as f32 + 0.5) / h as f32;
        let d: Vec<f32> = (0..3)
            .map(|k| cam.distance * cam.w[k] + s * cam.u[k] + t * cam.v[k])
            .collect();
        let l = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        let got = read_f32s(&out, FB_PROBE + 24 * i as u32, 6);
        assert_eq!(&got[..3], &cam.eye[..]);
        for k in 0..3 {
            assert!(
                close(got[3 + k], d[k] / l, 2e-6),
                "pixel {i}: {got:?} vs {d:?}"
            );
        }
    }
    // Top-left pixel looks up and left.
    let tl = read_f32s(&out, FB_PROBE, 6);
    let dir = Vec3::new(tl[3], tl[4], tl[5]);
    let u = Vec3::new(cam.u[0], cam.u[1], cam.u[2]);
    let v = Vec3::new(cam.v[0], cam.v[1], cam.v[2]);
    assert!(dir.dot(u) < 0.0 && dir.dot(v) > 0.0);
}

// ---------------------------------------------------------------------------------------
// Intersection.

fn tri(a: [f32; 3], b: [f32; 3], c: [f32; 3]) -> trax::Triangle {
    let v = |p: [f32; 3]| Vec3::new(p[0], p[1], p[2]);
    trax::Triangle {
        v0: v(a),
        v1: v(b),
        v2: v(c),
    }
}

/// The 8 faces of the octahedron with vertices at ±s on each axis (a closed mesh).
fn octahedron(s: f32) -> Vec<trax::Triangle> {
    let px = [s, 0.0, 0.0];
    let nx = [-s, 0.0, 0.0];
    let py = [0.0, s, 0.0];
    let ny = [0.0, -s, 0.0];
    let pz = [0.0, 0.0, s];
    let nz = [0.0, 0.0, -s];
    vec![
        tri(px, py, pz),
        tri(py, nx, pz),
        tri(nx, ny, pz),
        tri(ny, px, pz),
        tri(py, px, nz),
        tri(nx, py, nz),
        tri(ny, nx, nz),
        tri(px, ny, nz),
    ]
}

/// Largest absolute coordinate of a mesh (the bound `TriRay::new` wants).
fn bound(tris: &[trax::Triangle]) -> f32 {
    tris.iter()
        .map(|t| t.v0.max_abs().max(t.v1.max_abs()).max(t.v2.max_abs()))
        .fold(0.0, f32::max)
}

fn hits_any(ray: &Ray, tris: &[trax::Triangle]) -> bool {
    let tr = trax::bvh::TriRay::new(ray, bound(tris));
    let mut hit = trax::Hit::none(f32::INFINITY);
    let mut any = false;
    for t in tris {
        any |= tr.intersect(t, 0.0, &mut hit);
    }
    any
}

#[test]
fn watertight_rays_through_edges_and_vertices_never_leak() {
    // Decimal scales from 1e-30 to 1e30 (the plain f32 test leaked beyond about 1e12 and
    // below about 1e-13), and powers of two.
    let scales = (-30..=30)
        .map(|k| 10f64.powi(k) as f32)
        .chain([2f32.powi(-100), 2f32.powi(100)]);
    for scale in scales {
        let mesh = octahedron(scale);
        let mut targets: Vec<Vec3> = Vec::new();
        for t in &mesh {
            for p in [t.v0, t.v1, t.v2] {
                targets.push(p);
            }
            targets.push((t.v0 + t.v1).scale(0.5));
            targets.push((t.v1 + t.v2).scale(0.5));
            targets.push((t.v0 + t.v1 + t.v2).scale(1.0 / 3.0));
        }
        // From inside (the centre, and off-centre) towards every vertex and edge.
        for origin in [Vec3::zero(), Vec3::new(0.1, -0.05, 0.2).scale(scale)] {
            for t in &targets {
                let ray = Ray::new(origin, *t - origin);
                assert!(
                    hits_any(&ray, &mesh),
                    "leak at scale {scale} towards ({}, {}, {})",
                    t.x,
                    t.y,
                    t.z
                );
            }
        }
        // From outside along the axes straight onto the vertices.
        for d in [
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.0, -1.0, 0.0),
            Vec3::new(0.0, 0.0, 1.0),
        ] {
            let ray = Ray::new(d.scale(-3.0 * scale), d);
            assert!(hits_any(&ray, &mesh), "axis ray at scale {scale}");
        }
    }
}

#[test]
fn triangle_hit_distance_and_barycentrics() {
    let t = tri([0.0, 0.0, -2.0], [1.0, 0.0, -2.0], [0.0, 1.0, -2.0]);
    let ray = Ray::new(Vec3::new(0.25, 0.5, 0.0), Vec3::new(0.0, 0.0, -1.0));
    let tr = trax::bvh::TriRay::new(&ray, 2.0);
    let mut h = trax::Hit::none(f32::INFINITY);
    assert!(tr.intersect(&t, 0.0, &mut h));
    assert_eq!(h.t, 2.0);
    assert!(close(h.u, 0.25, 1e-6) && close(h.v, 0.5, 1e-6));
    let p = t.point(h.u, h.v);
    assert!(close(p.x, 0.25, 1e-6) && close(p.y, 0.5, 1e-6));
    // Beyond t_max, behind t_min, and a clear miss.
    let mut h2 = trax::Hit::none(1.5);
    assert!(!tr.intersect(&t, 0.0, &mut h2));
    let mut h3 = trax::Hit::none(f32::INFINITY);
    assert!(!tr.intersect(&t, 2.5, &mut h3));
    let miss = Ray::new(Vec3::new(0.8, 0.8, 0.0), Vec3::new(0.0, 0.0, -1.0));
    assert!(!trax::bvh::TriRay::new(&miss, 2.0).intersect(
        &t,
        0.0,
        &mut trax::Hit::none(f32::INFINITY)
    ));
    // Both windings hit.
    let back = tri([0.0, 0.0, -2.0], [0.0, 1.0, -2.0], [1.0, 0.0, -2.0]);
    assert!(tr.intersect(&back, 0.0, &mut trax::Hit::none(f32::INFINITY)));
}

fn arr(v: Vec3) -> [f32; 3] {
    [v.x, v.y, v.z]
}

/// A deterministic generator for the tests below (SplitMix64), uniform in [-1, 1).
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> f32 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        (z >> 40) as f32 / (1u64 << 23) as f32 - 1.0
    }

    fn vec(&mut self) -> Vec3 {
        Vec3::new(self.next(), self.next(), self.next())
    }
}

/// The triangle test works in a frame scaled by a power of two; where the plain f32
/// computation is in range, every scale gives bit-identical hits.
#[test]
fn triangle_test_frame_scale_is_exact() {
    let mut rng = Rng(7);
    let mut hits = 0;
    for _ in 0..20_000 {
        let t = tri(
            [rng.next(), rng.next(), rng.next() - 3.0],
            [rng.next(), rng.next(), rng.next() - 3.0],
            [rng.next(), rng.next(), rng.next() - 3.0],
        );
        // Aimed at the triangle's plane, inside or just outside the triangle.
        let target = t.point(0.7 * rng.next() + 0.3, 0.7 * rng.next() + 0.3);
        let o = rng.vec().scale(0.5);
        let ray = Ray::new(o, (target - o).normalize());
        let mut results = Vec::new();
        for bound in [0.0f32, 1.0, 1e-3, 1e6, 3e9] {
            let tr = trax::bvh::TriRay::new(&ray, bound);
            let mut h = trax::Hit::none(f32::INFINITY);
            let hit = tr.intersect(&t, 0.0, &mut h);
            results.push((hit, h.t.to_bits(), h.u.to_bits(), h.v.to_bits()));
        }
        hits += results[0].0 as u32;
        assert!(results.iter().all(|r| *r == results[0]), "{results:?}");
    }
    assert!(hits > 1000, "too few hits ({hits}) to mean anything");
}

/// `math::pow2_scale` is the runtime's (the fused triangle pipeline's) `pow2_scale`.
#[test]
fn pow2_scale_matches_the_runtime() {
    let mut x = 1e-45f32;
    while x.is_finite() {
        for m in [x, x * 1.7, -0.0, f32::INFINITY, f32::NAN] {
            assert_eq!(
                trax::math::pow2_scale(m).to_bits(),
                trax_runtime::pipes::pow2_scale(m).to_bits(),
                "{m}"
            );
        }
        x *= 3.1;
    }
}

/// Rays spawned from a hit by `SurfacePoint::origin` into the hemisphere they may leave
/// by never hit the triangle they leave, at every scale, while staying within a
/// millionth of the hit point's magnitude of it; and triangle normals are the same
/// direction at every scale.
#[test]
fn spawned_rays_do_not_hit_their_own_surface_at_any_scale() {
    let mut rng = Rng(11);
    for k in -20..=20 {
        let s = 10f64.powi(k);
        for case in 0..4_000 {
            let unit = if case % 2 == 0 {
                let c = rng.vec().scale(4.0);
                tri(arr(c + rng.vec()), arr(c + rng.vec()), arr(c + rng.vec()))
            } else {
                // A large, slightly tilted wall close to a coordinate plane (like the
                // Cornell box's walls): its coordinates along the normal are tiny next to
                // the others, so an offset from the point's error along the normal alone
                // is far smaller than the intersection's rounding error.
                let axis = (case / 2) % 3;
                let mut v = [[0.0f32; 3]; 3];
                for p in v.iter_mut() {
                    for (i, c) in p.iter_mut().enumerate() {
                        *c = if i == axis {
                            3.0 + 0.02 * rng.next()
                        } else {
                            300.0 * rng.next() + 250.0
                        };
                    }
                }
                tri(v[0], v[1], v[2])
            };
            let sc = |v: Vec3| {
                Vec3::new(
                    (v.x as f64 * s) as f32,
                    (v.y as f64 * s) as f32,
                    (v.z as f64 * s) as f32,
                )
            };
            let t = trax::Triangle {
                v0: sc(unit.v0),
                v1: sc(unit.v1),
                v2: sc(unit.v2),
            };
            let n = t.normal();
            let n1 = unit.normal();
            assert!(
                n.dot(n1) > 0.9999,
                "1e{k}: normal {:?} vs {:?}",
                arr(n),
                arr(n1)
            );
            // A camera ray at a random point of the triangle.
            let (b1, b2) = ((rng.next() + 1.0) * 0.5, (rng.next() + 1.0) * 0.5);
            let (b1, b2) = if b1 + b2 > 1.0 {
                (1.0 - b1, 1.0 - b2)
            } else {
                (b1, b2)
            };
            let target = t.point(b1, b2);
            let eye = target + (n.scale(2.0) + rng.vec()).scale(s as f32);
            let ray = Ray::new(eye, (target - eye).normalize());
            let bnd = bound(std::slice::from_ref(&t)).max(eye.max_abs());
            let tr = trax::bvh::TriRay::new(&ray, bnd);
            let mut hit = trax::Hit::none(f32::INFINITY);
            if !tr.intersect(&t, 0.0, &mut hit) {
                continue; // grazing; nothing to spawn from
            }
            let sp = trax::ray::SurfacePoint::new(&ray, &hit, &t);
            let o = sp.origin();
            let moved = (o - sp.p).max_abs();
            assert!(
                moved <= 1e-5 * sp.p.max_abs().max(t.v0.max_abs()),
                "1e{k}: offset {moved} for a point of magnitude {}",
                sp.p.max_abs()
            );
            for _ in 0..8 {
                let mut d = rng.vec().normalize();
                if d.dot(sp.n) < 0.0 {
                    d = -d;
                }
                let r = Ray::new(o, d);
                let tr = trax::bvh::TriRay::new(&r, bnd);
                let mut h = trax::Hit::none(f32::INFINITY);
                assert!(
                    !tr.intersect(&t, 0.0, &mut h),
                    "1e{k}: self-hit at t {} leaving along {:?}",
                    h.t,
                    arr(d)
                );
            }
        }
    }
}

#[test]
fn slab_test_is_robust() {
    let lo = Vec3::new(0.0, 0.0, 0.0);
    let hi = Vec3::new(1.0, 1.0, 1.0);
    let entry = |o: Vec3, d: Vec3| {
        trax::bvh::BoxRay::new(&Ray::new(o, d)).entry(lo, hi, 0.0, f32::INFINITY)
    };
    // Plain hit and miss.
    assert_eq!(
        entry(Vec3::new(-1.0, 0.5, 0.5), Vec3::new(1.0, 0.0, 0.0)),
        1.0
    );
    assert_eq!(
        entry(Vec3::new(-1.0, 2.0, 0.5), Vec3::new(1.0, 0.0, 0.0)),
        f32::INFINITY
    );
    // Zero direction components (including -0) with the origin inside the slab.
    assert_eq!(
        entry(Vec3::new(0.5, 0.5, -3.0), Vec3::new(0.0, -0.0, 1.0)),
        3.0
    );
    // Rays lying exactly in a face plane (0 * inf = NaN) are inside: no false miss.
    assert_eq!(
        entry(Vec3::new(0.0, 0.5, -3.0), Vec3::new(0.0, 0.0, 1.0)),
        3.0
    );
    assert_eq!(
        entry(Vec3::new(1.0, 1.0, -3.0), Vec3::new(-0.0, 0.0, 1.0)),
        3.0
    );
    // Along an edge.
    assert_eq!(
        entry(Vec3::new(0.0, 0.0, 5.0), Vec3::new(0.0, 0.0, -1.0)),
        4.0
    );
    // Origin inside: entry clipped to t_min.
    assert_eq!(
        entry(Vec3::new(0.5, 0.5, 0.5), Vec3::new(1.0, 1.0, 0.0)),
        0.0
    );
    // Box behind the ray.
    assert_eq!(
        entry(Vec3::new(0.5, 0.5, 3.0), Vec3::new(0.0, 0.0, 1.0)),
        f32::INFINITY
    );
    // Grazing a corner exactly.
    assert!(entry(Vec3::new(-1.0, -1.0, 0.5), Vec3::new(1.0, 1.0, 0.0)) < f32::INFINITY);
}

/// A scene image: header + camera + framebuffer + the given triangles and BVH.
fn scene_image(
    tris: &[trax::Triangle],
    nodes: &[(Vec3, Vec3, u32, u32)],
    w: u32,
    h: u32,
) -> MemoryImage {
    let cam = look_at_camera([0.0, 0.0, 5.0], [0.0; 3], [0.0, 1.0, 0.0], 45.0, 1.0);
    let mut img = header_only_image(&HeaderParams {
        width: w,
        height: h,
        camera: cam,
        ..HeaderParams::default()
    })
    .unwrap();
    let f = |v: Vec3| {
        [v.x, v.y, v.z]
            .into_iter()
            .flat_map(f32::to_le_bytes)
            .collect::<Vec<u8>>()
    };
    let tri_bytes: Vec<u8> = tris
        .iter()
        .flat_map(|t| [f(t.v0), f(t.v1), f(t.v2)].concat())
        .collect();
    let node_bytes: Vec<u8> = nodes
        .iter()
        .flat_map(|(lo, hi, a, b)| {
            [
                f(*lo),
                f(*hi),
                a.to_le_bytes().to_vec(),
                b.to_le_bytes().to_vec(),
            ]
            .concat()
        })
        .collect();
    let (tri_addr, node_addr) = (0x0050_0000u32, 0x0060_0000u32);
    img.segments
        .push(Segment::new("triangles", tri_addr, tri_bytes, Perms::R));
    img.segments
        .push(Segment::new("bvh_nodes", node_addr, node_bytes, Perms::R));
    let hdr = &mut img.segments[0].data;
    let mut put =
        |off: u32, v: u32| hdr[off as usize..off as usize + 4].copy_from_slice(&v.to_le_bytes());
    put(L::HDR_TRIANGLES, tri_addr);
    put(L::HDR_TRIANGLES + 4, tris.len() as u32);
    put(L::HDR_BVH_NODES, node_addr);
    put(L::HDR_BVH_NODES + 4, nodes.len() as u32);
    img
}

fn trace_kernel() {
    let cam = trax::Camera::load();
    let w = trax::scene::width();
    let n = w * trax::scene::height();
    loop {
        let i = trax::atomic_inc(0);
        if i >= n {
            break;
        }
        let hit = trax::bvh::intersect(&cam.pixel_ray(i % w, i / w), 0.0, trax::INFINITY);
        let v = if hit.is_hit() { hit.tri as f32 } else { -1.0 };
        let occ = trax::bvh::occluded(&cam.pixel_ray(i % w, i / w), 0.0, trax::INFINITY);
        trax::scene::set_pixel_index(i, Vec3::new(v, hit.t, if occ { 1.0 } else { 0.0 }));
    }
}

#[test]
fn bvh_traversal_matches_brute_force() {
    // Two quads at different depths, the nearer one partly covering the farther one.
    let far = [
        tri([-1.0, -1.0, -1.0], [1.0, -1.0, -1.0], [1.0, 1.0, -1.0]),
        tri([-1.0, -1.0, -1.0], [1.0, 1.0, -1.0], [-1.0, 1.0, -1.0]),
    ];
    let near = [
        tri([-0.5, -0.5, 1.0], [0.5, -0.5, 1.0], [0.5, 0.5, 1.0]),
        tri([-0.5, -0.5, 1.0], [0.5, 0.5, 1.0], [-0.5, 0.5, 1.0]),
    ];
    let tris: Vec<trax::Triangle> = far.iter().chain(near.iter()).copied().collect();
    let nodes = [
        (Vec3::new(-1.0, -1.0, -1.0), Vec3::new(1.0, 1.0, 1.0), 1, 0),
        (Vec3::new(-1.0, -1.0, -1.0), Vec3::new(1.0, 1.0, -1.0), 0, 2),
        (Vec3::new(-0.5, -0.5, 1.0), Vec3::new(0.5, 0.5, 1.0), 2, 2),
    ];
    let (w, h) = (24, 24);
    let img = with_probe(scene_image(&tris, &nodes, w, h));
    let (with_bvh, stats) =
        trax::host::run_image_stats(&to_image(&img), 1, 3, trace_kernel).unwrap();
    // One closest-hit and one any-hit ray per pixel, each counted once.
    assert_eq!(stats.rays, 2 * (w * h) as u64);
    let brute = run(&scene_image(&tris, &[], w, h), 1, 3, trace_kernel);
    let fb = trax_runtime::host::HEADER_ONLY_FRAMEBUFFER_ADDR;
    let a = read_f32s(&with_bvh, fb, (w * h * 3) as usize);
    let b = read_f32s(&brute, fb, (w * h * 3) as usize);
    assert_eq!(a, b);
    // The centre pixel sees the near quad at distance 4, the corner misses everything.
    let c = ((h / 2) * w + w / 2) as usize * 3;
    assert!(a[c] == 2.0 || a[c] == 3.0, "{}", a[c]);
    assert!(close(a[c + 1], 4.0, 1e-2), "{}", a[c + 1]);
    assert_eq!(a[c + 2], 1.0);
    assert_eq!(a[0], -1.0);
    assert_eq!(a[2], 0.0);
    let seen: std::collections::HashSet<i32> = a.chunks(3).map(|p| p[0] as i32).collect();
    assert!(
        seen.contains(&0) || seen.contains(&1),
        "far quad visible around the near one"
    );
}

// ---------------------------------------------------------------------------------------
// SIMD.

#[test]
fn simd_semantics() {
    use trax::simd::{f32x4, i32x4};
    let a = f32x4::new(1.0, -2.0, 3.5, f32::NAN);
    let b = f32x4::splat(2.0);
    let lanes = |v: f32x4| [v.get(0), v.get(1), v.get(2), v.get(3)];
    let ilanes = |v: i32x4| [v.get(0), v.get(1), v.get(2), v.get(3)];
    assert_eq!(lanes(a + b)[..3], [3.0, 0.0, 5.5]);
    assert_eq!(lanes(a - b)[..3], [-1.0, -4.0, 1.5]);
    assert_eq!(lanes(a * b)[..3], [2.0, -4.0, 7.0]);
    assert_eq!(lanes(a / b)[..3], [0.5, -1.0, 1.75]);
    assert_eq!(lanes(-a)[..3], [-1.0, 2.0, -3.5]);
    assert_eq!(lanes(a.min(b)), [1.0, -2.0, 2.0, 2.0]);
    assert_eq!(lanes(a.max(b)), [2.0, 2.0, 3.5, 2.0]);
    assert_eq!(
        lanes(f32x4::new(4.0, 9.0, 0.0, 2.25).sqrt()),
        [2.0, 3.0, 0.0, 1.5]
    );
    assert_eq!(lanes(a.abs())[..3], [1.0, 2.0, 3.5]);
    // Fused multiply-add: one rounding.
    // (1 + 2^-12)^2 - 1 = 2^-11 + 2^-24 exactly; unfused, the square rounds to 1 + 2^-11.
    let e = 1.0 / 4096.0;
    let x = f32x4::splat(1.0 + e);
    let fused = x.mul_add(x, f32x4::splat(-1.0)).get(0);
    assert_eq!(fused, 2.0 * e + e * e);
    assert_eq!((1.0 + e) * (1.0 + e) - 1.0, 2.0 * e);
    assert_eq!(ilanes(a.lt(b)), [-1, -1, 0, 0]);
    assert_eq!(ilanes(a.le(f32x4::new(1.0, 0.0, 0.0, 0.0))), [-1, -1, 0, 0]);
    assert_eq!(ilanes(a.gt(b)), [0, 0, -1, 0]);
    assert_eq!(ilanes(a.ge(f32x4::splat(1.0))), [-1, 0, -1, 0]);
    assert_eq!(ilanes(a.eq(a)), [-1, -1, -1, 0]);
    let sel = f32x4::select(a.lt(b), a, b);
    assert_eq!(lanes(sel), [1.0, -2.0, 2.0, 2.0]);
    let big = f32x4::new(-1.9, 2.9, 3e10, f32::NAN);
    assert_eq!(ilanes(big.to_i32x4()), [-1, 2, i32::MAX, 0]);
    let i = i32x4::new(i32::MAX, 2, 0b1100, -1);
    let j = i32x4::splat(3);
    assert_eq!(ilanes(i + j), [i32::MIN + 2, 5, 15, 2]);
    assert_eq!(ilanes(i - j), [i32::MAX - 3, -1, 9, -4]);
    assert_eq!(ilanes(i * j), [i32::MAX.wrapping_mul(3), 6, 36, -3]);
    assert_eq!(ilanes(i & j), [3, 2, 0, 3]);
    assert_eq!(ilanes(i | j), [i32::MAX, 3, 15, -1]);
    assert_eq!(ilanes(i ^ j), [i32::MAX ^ 3, 1, 15, -4]);
    assert_eq!(
        ilanes(i32x4::select(i32x4::new(0, 1, 0, -1), i, j)),
        [3, 2, 3, -1]
    );
    assert!(i32x4::new(0, 0, 5, 0).any());
    assert!(!i32x4::splat(0).any());
    assert!(i32x4::new(1, -1, 2, 3).all());
    assert!(!i32x4::new(1, 0, 2, 3).all());
    assert_eq!(
        lanes(i32x4::new(-3, 0, 16_777_217, 7).to_f32x4()),
        [-3.0, 0.0, 16_777_216.0, 7.0]
    );
}

#[test]
fn pipelines_match_the_shared_semantics() {
    let t = tri([0.0, 0.0, -2.0], [1.0, 0.0, -2.0], [0.0, 1.0, -2.0]);
    let ray = Ray::new(Vec3::new(0.25, 0.5, 0.0), Vec3::new(0.0, 0.0, -1.0));
    let h = trax::pipe::tri_test(&ray, &t);
    assert_eq!((h.t, h.u, h.v), (2.0, 0.25, 0.5));
    let want = trax_runtime::pipes::tri_test(
        [0.25, 0.5, 0.0],
        [0.0, 0.0, -1.0],
        [0.0, 0.0, -2.0],
        [1.0, 0.0, -2.0],
        [0.0, 1.0, -2.0],
    );
    assert_eq!((h.t, h.u, h.v), want);
    let miss = trax::pipe::tri_test(&Ray::new(Vec3::new(0.9, 0.9, 0.0), ray.dir), &t);
    assert_eq!((miss.t, miss.u, miss.v), (f32::INFINITY, 0.0, 0.0));
    let inv = Vec3::new(f32::INFINITY, f32::INFINITY, 1.0);
    let e = trax::pipe::box_test(
        Vec3::new(0.0, 0.5, -2.0),
        inv,
        Vec3::zero(),
        Vec3::splat(1.0),
    );
    assert_eq!(e, 2.0);
    trax::pipe::use_box_pipeline();
    trax::pipe::use_triangle_pipeline();
    trax::pipe::use_general_units();
}

// ---------------------------------------------------------------------------------------
// Ray streams on the host: the runtime's `streams.rs` behind condition variables.

mod host_streams {
    use super::*;
    use std::sync::atomic::{AtomicU32, AtomicU64, Ordering::SeqCst};
    use std::sync::Mutex;
    use std::time::{Duration, Instant};
    use trax::stream;

    /// Streams tests share these statics: one at a time.
    static LOCK: Mutex<()> = Mutex::new(());
    static START: Mutex<Option<Instant>> = Mutex::new(None);
    static ARRIVE: [AtomicU64; 4] = [const { AtomicU64::new(0) }; 4];
    static RESUME: [AtomicU64; 4] = [const { AtomicU64::new(0) }; 4];
    static GOT: [AtomicU32; 4] = [const { AtomicU32::new(0) }; 4];
    static READS: AtomicU32 = AtomicU32::new(0);
    static DONE: AtomicU32 = AtomicU32::new(0);

    fn now_ns() -> u64 {
        START.lock().unwrap().unwrap().elapsed().as_nanos() as u64
    }

    /// A header-only image whose stream memory holds `rays` rays in 4 buffers.
    fn image(rays: u32) -> trax::host::Image {
        let p = HeaderParams {
            width: 4,
            height: 4,
            stream: [rays, 48, 4],
            ..HeaderParams::default()
        };
        to_image(&header_only_image(&p).unwrap())
    }

    fn reset() {
        *START.lock().unwrap() = Some(Instant::now());
        for a in ARRIVE.iter().chain(&RESUME) {
            a.store(0, SeqCst);
        }
        for g in &GOT {
            g.store(0, SeqCst);
        }
        READS.store(0, SeqCst);
        DONE.store(0, SeqCst);
    }

    /// Thread 3 returns at once; thread 0 writes three rays to buffer 2; threads 0..2
    /// sleep 30 ms x tid, then schedule, drain and schedule again.
    fn rendezvous_kernel() {
        let tid = trax::thread_id() as usize;
        if tid == 3 {
            return;
        }
        let mut rec: stream::Record = [7; stream::RECORD_WORDS];
        if tid == 0 {
            for _ in 0..3 {
                stream::write(2, &rec);
            }
        }
        std::thread::sleep(Duration::from_millis(30 * tid as u64));
        ARRIVE[tid].store(now_ns(), SeqCst);
        let b = stream::schedule();
        RESUME[tid].store(now_ns(), SeqCst);
        GOT[tid].store(b.unwrap_or(99), SeqCst);
        while stream::read(&mut rec) {
            assert_eq!(rec, [7; stream::RECORD_WORDS]);
            READS.fetch_add(1, SeqCst);
        }
        while stream::schedule().is_some() {}
        DONE.fetch_add(1, SeqCst);
    }

    #[test]
    fn schedule_waits_for_every_live_thread_of_the_tm() {
        let _g = LOCK.lock().unwrap_or_else(|e| e.into_inner());
        reset();
        trax::host::run_image(&image(100), 1, 4, rendezvous_kernel).unwrap();
        let last = ARRIVE[..3].iter().map(|a| a.load(SeqCst)).max().unwrap();
        let first = ARRIVE[..3].iter().map(|a| a.load(SeqCst)).min().unwrap();
        assert!(last - first >= 50_000_000, "{first}..{last}");
        for r in &RESUME[..3] {
            assert!(r.load(SeqCst) >= last, "resumed before the last arrival");
        }
        let got: Vec<u32> = GOT[..3].iter().map(|g| g.load(SeqCst)).collect();
        assert_eq!(got, [2, 2, 2]);
        assert_eq!((READS.load(SeqCst), DONE.load(SeqCst)), (3, 3));
    }

    /// TM 1 schedules with nothing to read; TM 0 writes one ray to buffer 1 after 50 ms.
    fn idle_kernel() {
        let mut rec: stream::Record = [0; stream::RECORD_WORDS];
        if trax::tm_id() == 0 {
            std::thread::sleep(Duration::from_millis(50));
            stream::write(1, &rec);
        } else {
            GOT[1].store(stream::schedule().unwrap_or(99), SeqCst);
            RESUME[1].store(now_ns(), SeqCst);
            while stream::read(&mut rec) {
                READS.fetch_add(1, SeqCst);
            }
        }
        while let Some(_b) = stream::schedule() {
            while stream::read(&mut rec) {
                READS.fetch_add(1, SeqCst);
            }
        }
        DONE.fetch_add(1, SeqCst);
    }

    #[test]
    fn an_idle_tm_sleeps_until_another_writes() {
        let _g = LOCK.lock().unwrap_or_else(|e| e.into_inner());
        reset();
        trax::host::run_image(&image(100), 2, 1, idle_kernel).unwrap();
        assert_eq!(GOT[1].load(SeqCst), 1);
        assert!(RESUME[1].load(SeqCst) >= 50_000_000);
        assert_eq!((READS.load(SeqCst), DONE.load(SeqCst)), (1, 2));
    }

    fn overflow_kernel() {
        let rec: stream::Record = [0; stream::RECORD_WORDS];
        for _ in 0..3 {
            stream::write(0, &rec);
        }
    }

    fn deadlock_kernel() {
        if trax::tm_id() == 0 {
            trax::barrier(4);
        } else {
            while stream::schedule().is_some() {}
        }
    }

    #[test]
    fn a_full_memory_and_a_deadlock_stop_the_run() {
        let _g = LOCK.lock().unwrap_or_else(|e| e.into_inner());
        assert_eq!(stream_capacity_of(2), 2);
        match trax::host::run_image(&image(2), 1, 1, overflow_kernel) {
            Err(trax::host::RunError::Panicked(ids)) => assert_eq!(ids, vec![0]),
            other => panic!("{:?}", other.map(|_| ())),
        }
        // Every thread ends (none hangs): the detecting one reports, the others stop.
        match trax::host::run_image(&image(8), 2, 2, deadlock_kernel) {
            Err(trax::host::RunError::Panicked(ids)) => assert_eq!(ids, vec![0, 1, 2, 3]),
            other => panic!("{:?}", other.map(|_| ())),
        }
    }

    static CAP: AtomicU32 = AtomicU32::new(0);

    fn capacity_kernel() {
        CAP.store(stream::capacity(), SeqCst);
        assert_eq!(stream::buffers(), 4);
    }

    fn stream_capacity_of(rays: u32) -> u32 {
        trax::host::run_image(&image(rays), 1, 1, capacity_kernel).unwrap();
        CAP.load(SeqCst)
    }
}
