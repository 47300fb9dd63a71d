//! Memory images: on-demand components, layout, header bytes, ELF input, errors.

use std::path::PathBuf;
use std::process::Command;

use std::mem::size_of;
use trax_assembler::bvh::{BvhOptions, TreeletLayout, TreeletOptions, PAD};
use trax_assembler::image::{
    build_image, build_image_from_symbols, on_demand_components, ImageError, Perms, RenderOptions,
    SceneImage, Segment,
};
use trax_assembler::scene::{cornell_box, procedural, Scene};

use trax_runtime::abi::{self, BvhNode, Field, Material, Pixel, SceneHeader, Triangle};
use trax_runtime::exe::{ExeError, Executable};

/// Bytes of one `T`, as a `u32`.
fn sz<T>() -> u32 {
    size_of::<T>() as u32
}

fn field_addr(name: &str) -> u32 {
    let off = abi::scene_header_fields()
        .into_iter()
        .find(|(f, _)| *f == name)
        .unwrap()
        .1;
    abi::SCENE_HEADER_ADDR + off as u32
}

fn scene() -> Scene {
    let mut s = cornell_box();
    s.validate().unwrap();
    s
}

/// Compiles a tiny C program with clang-14 and links it with ld.lld-14 at TEXT_BASE, with
/// `--defsym` for each (symbol, address).
fn link_elf(name: &str, defsyms: &[(String, u32)]) -> (Vec<u8>, PathBuf) {
    let d =
        std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("trax-image-test-{name}"));
    std::fs::create_dir_all(&d).unwrap();
    let c = d.join("k.c");
    std::fs::write(
        &c,
        "extern char __trax_scene_triangles[];\n\
         int data_word = 7;\nint bss_words[100];\n\
         int trax_main(void) { return (int)(unsigned)__trax_scene_triangles; }\n\
         void __trax_start(void) { bss_words[0] = trax_main() + data_word; for (;;) {} }\n",
    )
    .unwrap();
    let obj = d.join("k.o");
    let st = Command::new("clang-14")
        .args([
            "--target=mipsel-unknown-elf",
            "-mcpu=mips32r6",
            "-G0",
            "-fno-pic",
            "-mno-abicalls",
            "-O1",
            "-c",
        ])
        .arg(&c)
        .arg("-o")
        .arg(&obj)
        .status()
        .expect("clang-14 runs");
    assert!(st.success());
    let elf = d.join("k.elf");
    let mut ld = Command::new("ld.lld-14");
    ld.arg(&obj)
        .arg("-o")
        .arg(&elf)
        .args(["-e", "__trax_start", "--image-base=0x100000"]);
    for (s, a) in defsyms {
        ld.arg(format!("--defsym={s}={a:#x}"));
    }
    assert!(ld.status().expect("ld.lld-14 runs").success());
    (std::fs::read(&elf).unwrap(), obj)
}

fn check_layout(img: &SceneImage) {
    // Components 64-byte aligned, after the program, below the stack window, disjoint.
    let limit = abi::STACK_TOP - img.stack.size;
    let mut spans: Vec<(u64, u64, String)> = img
        .memory
        .segments
        .iter()
        .map(|s| (s.addr as u64, s.end(), s.name.clone()))
        .collect();
    spans.sort();
    for w in spans.windows(2) {
        assert!(w[0].1 <= w[1].0, "{:?} overlaps {:?}", w[0], w[1]);
    }
    for c in &img.components {
        // Permissions as the contract says: kernels only write the framebuffer.
        let want = match abi::component(c.name).unwrap().access {
            abi::Access::ReadOnly => Perms::R,
            abi::Access::ReadWrite => Perms::RW,
        };
        assert_eq!(
            img.memory.segment(c.name).unwrap().perms,
            want,
            "{}",
            c.name
        );
        assert_eq!(c.addr % 64, 0, "{} not aligned", c.name);
        assert!(c.addr >= img.program_end, "{} inside the program", c.name);
        assert!(c.addr as u64 + c.bytes as u64 <= limit as u64);
    }
    assert!(img.end <= limit);
    assert_eq!(img.null_guard, 0..abi::NULL_GUARD_END);
    // The header in memory is the header reported.
    let bytes = img
        .memory
        .read(abi::SCENE_HEADER_ADDR, abi::SCENE_HEADER_SIZE as u32)
        .unwrap();
    assert_eq!(bytes, img.header.to_bytes());
    assert_eq!(
        img.memory.read_u32(abi::SCENE_HEADER_ADDR),
        Some(abi::SCENE_MAGIC)
    );
}

#[test]
fn header_bytes_match_abi_offsets() {
    let mut h = SceneHeader {
        magic: 11,
        version: 12,
        width: 13,
        height: 14,
        spp: 17,
        max_depth: 18,
        seed: 20,
        camera: 24,
        ..SceneHeader::default()
    };
    h.triangles.addr = 0xABCD;
    h.triangles.count = 0x1234;
    h.treelet_ids.count = 99;
    h.reserved[0] = 77;
    h.stream_ray_bytes = 48;
    let b = h.to_bytes();
    assert_eq!(b.len(), abi::SCENE_HEADER_SIZE);
    let word = |name: &str, extra: usize| {
        let off = field_addr(name) as usize - abi::SCENE_HEADER_ADDR as usize + extra;
        u32::from_le_bytes(b[off..off + 4].try_into().unwrap())
    };
    assert_eq!(word("magic", 0), 11);
    assert_eq!(word("width", 0), 13);
    assert_eq!(word("max_depth", 0), 18);
    assert_eq!(word("seed", 0), 20);
    assert_eq!(word("camera", 0), 24);
    assert_eq!(word("triangles", 0), 0xABCD);
    assert_eq!(word("triangles", 4), 0x1234);
    assert_eq!(word("treelet_ids", 4), 99);
    assert_eq!(word("reserved", 0), 77);
    assert_eq!(word("stream_ray_bytes", 0), 48);
}

#[test]
fn elf_program_gets_only_what_it_references() {
    let (elf, _) = link_elf(
        "ondemand",
        &[("__trax_scene_triangles".into(), field_addr("triangles"))],
    );
    let p = Executable::parse("k.elf", &elf).unwrap();
    assert_eq!(p.referenced, ["triangles"]);
    let s = scene();
    let img = build_image(&elf, &s, &RenderOptions::default()).unwrap();
    check_layout(&img);
    let names: Vec<&str> = img.components.iter().map(|c| c.name).collect();
    assert_eq!(names, ["camera", "framebuffer", "triangles"]);
    assert!(img.bvh.is_none(), "no BVH without bvh_nodes");
    assert_eq!(img.header.bvh_nodes, abi::Component::default());
    assert_eq!(img.header.normals, abi::Component::default());
    assert_eq!(img.header.triangles.count, 32);
    assert_eq!(
        img.component("triangles").unwrap().bytes,
        32 * sz::<Triangle>()
    );
    assert_eq!(
        img.component("framebuffer").unwrap().bytes,
        128 * 128 * sz::<Pixel>()
    );
    // Program segments are loaded: text executable at its address, bss zero-filled.
    let text = img.memory.segment("text").unwrap();
    assert_eq!(text.perms, Perms::RX, "text keeps the ELF's permissions");
    assert!(text.addr >= abi::TEXT_BASE);
    assert!((text.addr..text.addr + text.size).contains(&img.entry));
    let data = img.memory.segment("data").unwrap();
    assert_eq!(data.perms, Perms::RW);
    assert!(
        data.size as usize > data.data.len(),
        "bss tail not materialised"
    );
    // Without a BVH, triangles keep scene order.
    let t0 = img.memory.read(img.header.triangles.addr, 36).unwrap();
    let want: Vec<u8> = s.triangles[0]
        .iter()
        .flatten()
        .flat_map(|f| f.to_le_bytes())
        .collect();
    assert_eq!(t0, want);
    // The camera is written.
    let cam = s.view.camera().unwrap();
    assert_eq!(
        img.memory.read_u32(img.header.camera),
        Some(cam.eye[0].to_bits())
    );
}

#[test]
fn all_components_with_bvh_and_treelets() {
    let s = procedural(3_000).unwrap();
    let opts = RenderOptions {
        width: 64,
        height: 32,
        treelets: TreeletLayout {
            always: true,
            options: TreeletOptions {
                budget_bytes: 4096,
                align_bytes: 2048,
            },
        },
        ..RenderOptions::default()
    };
    let img = build_image_from_symbols(
        Vec::new(),
        abi::TEXT_BASE,
        &on_demand_components(),
        &s,
        &opts,
    )
    .unwrap();
    check_layout(&img);
    let h = img.header;
    let bvh = img.bvh.as_ref().unwrap();
    let nodes = bvh.nodes.len() as u32;
    let slots = bvh.tri_order.len() as u32;
    let bytes = |n: &str| img.component(n).unwrap().bytes;
    assert_eq!(bytes("bvh_nodes"), sz::<BvhNode>() * nodes);
    assert_eq!(bytes("triangles"), sz::<Triangle>() * slots);
    assert_eq!(bytes("normals"), sz::<abi::VertexNormals>() * slots);
    assert_eq!(bytes("texcoords"), sz::<abi::TexCoords>() * slots);
    assert_eq!(bytes("material_ids"), 4 * slots);
    assert_eq!(
        bytes("materials"),
        sz::<Material>() * s.materials.len() as u32
    );
    assert_eq!(bytes("point_lights"), sz::<abi::PointLight>());
    assert_eq!(bytes("bvh_parents"), 4 * nodes);
    assert_eq!(bytes("treelet_ids"), 4 * nodes);
    assert_eq!(bytes("framebuffer"), 64 * 32 * sz::<Pixel>());
    assert_eq!(img.components.len(), 2 + on_demand_components().len());
    assert_eq!(h.bvh_nodes.addr % 2048, 0, "DRAM-row aligned node array");
    assert_eq!(
        h.triangles.addr % 2048,
        0,
        "DRAM-row aligned triangle array"
    );
    assert_eq!((h.width, h.height), (64, 32));
    assert_eq!(h.inv_width, 1.0 / 64.0);
    assert!(h.epsilon > 0.0);
    // Walk the BVH in memory: leaves point at triangles equal to the scene's.
    let node = |i: u32| {
        let n = sz::<BvhNode>();
        img.memory.read(h.bvh_nodes.addr + n * i, n).unwrap()
    };
    let mut stack = vec![0u32];
    let mut seen = 0;
    while let Some(i) = stack.pop() {
        let n = node(i);
        let w = |k: usize| u32::from_le_bytes(n[4 * k..4 * k + 4].try_into().unwrap());
        let (a, b) = (w(6), w(7));
        if b == 0 {
            stack.extend([a, a + 1]);
            assert_eq!(img.memory.read_u32(h.bvh_parents.addr + 4 * a), Some(i));
        } else {
            for slot in a..a + b {
                let t = img
                    .memory
                    .read(h.triangles.addr + sz::<Triangle>() * slot, sz::<Triangle>())
                    .unwrap();
                let orig = bvh.tri_order[slot as usize] as usize;
                let want: Vec<u8> = s.triangles[orig]
                    .iter()
                    .flatten()
                    .flat_map(|f| f.to_le_bytes())
                    .collect();
                assert_eq!(t, want);
                let m = img.memory.read_u32(h.material_ids.addr + 4 * slot).unwrap();
                assert_eq!(m, s.material_ids[orig]);
                seen += 1;
            }
        }
    }
    assert_eq!(seen, s.len());
    // Emitters name slots whose material emits.
    assert_eq!(h.emitters.count as usize, s.emitters().len());
    for k in 0..h.emitters.count {
        let slot = img.memory.read_u32(h.emitters.addr + 4 * k).unwrap();
        let m = img.memory.read_u32(h.material_ids.addr + 4 * slot).unwrap();
        let at = h.materials.addr + sz::<Material>() * m;
        let emission = img
            .memory
            .read_u32(at + std::mem::offset_of!(Material, emission) as u32)
            .unwrap();
        assert!(f32::from_bits(emission) > 0.0);
    }
    // Treelet ids in memory match the BVH's.
    let t = bvh.treelets.as_ref().unwrap();
    assert_eq!(
        img.memory.read_u32(h.treelet_ids.addr),
        Some(t.node_treelet[0])
    );
    // Triangle treelet ids: each slot's treelet (ids after the node treelets'), padding
    // slots none; the aligned layout here has padding.
    assert_eq!(bytes("tri_treelet_ids"), 4 * slots);
    assert!(bvh.tri_order.contains(&PAD) && t.tri_ranges.len() > 1);
    let first = t.node_ranges.len() as u32;
    for slot in 0..slots {
        let id = img
            .memory
            .read_u32(h.tri_treelet_ids.addr + 4 * slot)
            .unwrap();
        if bvh.tri_order[slot as usize] == PAD {
            assert_eq!(id, u32::MAX, "padding slot {slot}");
        } else {
            let k = (id - first) as usize;
            assert!(
                t.tri_ranges[k].contains(&slot),
                "slot {slot} in treelet {id}"
            );
        }
    }
}

/// A program that reads `treelet_ids` on a chip whose treelets are formed when read and
/// aligned gets its node and triangle arrays on the treelet alignment (treelet starts are
/// offsets from the arrays' starts). The arrays were placed on a 64-byte boundary only: the
/// alignment was taken from treelets set to be formed always.
#[test]
fn treelets_formed_when_read_align_the_arrays() {
    let s = procedural(3_000).unwrap();
    let layout = TreeletLayout {
        always: false,
        options: TreeletOptions {
            budget_bytes: 16384,
            align_bytes: 8192,
        },
    };
    let opts = RenderOptions {
        treelets: layout.clone(),
        ..RenderOptions::default()
    };
    let reads = ["treelet_ids", "bvh_nodes", "triangles"];
    let img = build_image_from_symbols(Vec::new(), abi::TEXT_BASE, &reads, &s, &opts).unwrap();
    check_layout(&img);
    assert_eq!(
        img.bvh.as_ref().unwrap().treelets.as_ref().unwrap().options,
        layout.options
    );
    let h = img.header;
    assert_eq!(
        h.bvh_nodes.addr % 8192,
        0,
        "node array on the treelet alignment"
    );
    assert_eq!(
        h.triangles.addr % 8192,
        0,
        "triangle array on the treelet alignment"
    );
    // A program that does not read `treelet_ids` sees the BVH in build order, its arrays on
    // the components' own alignment; with `always` it gets the treelets.
    let img = build_image_from_symbols(Vec::new(), abi::TEXT_BASE, &reads[1..], &s, &opts).unwrap();
    assert!(img.bvh.as_ref().unwrap().treelets.is_none());
    let always = RenderOptions {
        treelets: TreeletLayout {
            always: true,
            ..layout
        },
        ..RenderOptions::default()
    };
    let img =
        build_image_from_symbols(Vec::new(), abi::TEXT_BASE, &reads[1..], &s, &always).unwrap();
    assert!(img.bvh.as_ref().unwrap().treelets.is_some());
    assert_eq!(img.header.bvh_nodes.addr % 8192, 0);
    assert_eq!(img.header.triangles.addr % 8192, 0);
    // The treelets are the layout's alone: setting them in the BVH options is refused.
    let twice = RenderOptions {
        bvh: BvhOptions {
            treelets: Some(TreeletOptions::default()),
            ..BvhOptions::default()
        },
        ..RenderOptions::default()
    };
    let e = build_image_from_symbols(Vec::new(), abi::TEXT_BASE, &reads, &s, &twice).unwrap_err();
    assert!(e.to_string().contains("treelets"), "{e}");
}

#[test]
fn treelets_formed_when_the_program_reads_treelet_ids() {
    let s = scene();
    let img = build_image_from_symbols(
        Vec::new(),
        abi::TEXT_BASE,
        &["treelet_ids"],
        &s,
        &RenderOptions::default(),
    )
    .unwrap();
    assert!(img.bvh.as_ref().unwrap().treelets.is_some());
    assert!(img.component("bvh_nodes").is_none());
    assert_eq!(
        img.header.treelet_ids.count,
        img.bvh.as_ref().unwrap().nodes.len() as u32
    );
    // Or the triangle treelets' ids.
    let img = build_image_from_symbols(
        Vec::new(),
        abi::TEXT_BASE,
        &["tri_treelet_ids"],
        &s,
        &RenderOptions::default(),
    )
    .unwrap();
    let bvh = img.bvh.as_ref().unwrap();
    let t = bvh.treelets.as_ref().unwrap();
    assert_eq!(img.header.tri_treelet_ids.count, bvh.tri_order.len() as u32);
    assert_eq!(
        img.memory.read_u32(img.header.tri_treelet_ids.addr),
        Some(t.node_ranges.len() as u32)
    );
    let img = build_image_from_symbols(
        Vec::new(),
        abi::TEXT_BASE,
        &[],
        &s,
        &RenderOptions::default(),
    )
    .unwrap();
    assert!(img.bvh.is_none());
    assert_eq!(img.components.len(), 2);
    check_layout(&img);
}

#[test]
fn bad_programs_and_options() {
    let s = scene();
    let o = RenderOptions::default();
    // Not an ELF; a relocatable object; a symbol at the wrong address; an unknown field.
    assert!(matches!(
        build_image(b"not an elf", &s, &o),
        Err(ImageError::Exe(ExeError::Parse { .. }))
    ));
    let (_, obj) = link_elf(
        "obj",
        &[("__trax_scene_triangles".into(), field_addr("triangles"))],
    );
    let obj = std::fs::read(obj).unwrap();
    match build_image(&obj, &s, &o) {
        Err(e @ ImageError::Exe(ExeError::WrongTarget { .. })) => {
            assert!(e.to_string().contains("not an executable"), "{e}")
        }
        other => panic!("{other:?}"),
    }
    let (elf, _) = link_elf(
        "wrong",
        &[("__trax_scene_triangles".into(), field_addr("normals"))],
    );
    assert!(matches!(
        build_image(&elf, &s, &o),
        Err(ImageError::Exe(ExeError::SceneSymbolMismatch { .. }))
    ));
    let (elf, _) = link_elf(
        "unknown",
        &[
            ("__trax_scene_triangles".into(), field_addr("triangles")),
            ("__trax_scene_teapots".into(), abi::SCENE_HEADER_ADDR),
        ],
    );
    match build_image(&elf, &s, &o) {
        Err(ImageError::Exe(ExeError::UnknownSceneField { symbol, .. })) => {
            assert_eq!(symbol, "__trax_scene_teapots")
        }
        other => panic!("{other:?}"),
    }
    assert!(matches!(
        build_image_from_symbols(Vec::new(), 0, &["teapots"], &s, &o),
        Err(ImageError::UnknownSceneField(_))
    ));
    // A framebuffer larger than the address space: refused before allocating.
    let huge = RenderOptions {
        width: 100_000,
        height: 100_000,
        ..RenderOptions::default()
    };
    match build_image_from_symbols(Vec::new(), 0, &[], &s, &huge) {
        Err(e @ ImageError::TooLarge { .. }) => {
            assert!(e.to_string().contains("framebuffer"), "{e}")
        }
        other => panic!("{other:?}"),
    }
    let zero = RenderOptions {
        width: 0,
        ..RenderOptions::default()
    };
    assert!(matches!(
        build_image_from_symbols(Vec::new(), 0, &[], &s, &zero),
        Err(ImageError::BadOption(_))
    ));
    // Program segments in reserved regions.
    for (addr, region) in [
        (0x100, "null guard"),
        (abi::SCENE_HEADER_ADDR + 8, "scene header"),
        (abi::STACK_TOP - 16, "stack"),
    ] {
        let seg = Segment::new("text", addr, vec![0; 64], Perms::RX);
        match build_image_from_symbols(vec![seg], addr, &[], &s, &o) {
            Err(e @ ImageError::Overlap { .. }) => assert!(e.to_string().contains(region), "{e}"),
            other => panic!("{other:?}"),
        }
    }
    let a = Segment::new("text", abi::TEXT_BASE, vec![0; 64], Perms::RX);
    let b = Segment::new("data", abi::TEXT_BASE + 32, vec![0; 64], Perms::RW);
    assert!(matches!(
        build_image_from_symbols(vec![a, b], 0, &[], &s, &o),
        Err(ImageError::Overlap { .. })
    ));
    // A scene that is empty or has a bad BVH option.
    let mut empty = s.clone();
    empty.triangles.clear();
    assert!(matches!(
        build_image_from_symbols(Vec::new(), 0, &[], &empty, &o),
        Err(ImageError::Scene(_))
    ));
    // A hand-built scene whose arrays disagree or whose material ids are out of range.
    let mut odd = s.clone();
    odd.normals.pop();
    assert!(matches!(
        build_image_from_symbols(Vec::new(), 0, &["normals"], &odd, &o),
        Err(ImageError::Scene(
            trax_assembler::scene::SceneError::Inconsistent(_)
        ))
    ));
    let mut odd = s.clone();
    odd.material_ids[3] = 99;
    assert!(matches!(
        build_image_from_symbols(Vec::new(), 0, &["emitters"], &odd, &o),
        Err(ImageError::Scene(
            trax_assembler::scene::SceneError::Inconsistent(_)
        ))
    ));
    let bad = RenderOptions {
        bvh: BvhOptions {
            max_leaf: 0,
            ..BvhOptions::default()
        },
        ..RenderOptions::default()
    };
    assert!(matches!(
        build_image_from_symbols(Vec::new(), 0, &["bvh_nodes"], &s, &bad),
        Err(ImageError::Bvh(_))
    ));
}
