// TEMPORARY (not committed): dumps memory images for the before/after comparison.
use trax_assembler::bvh::{BvhOptions, TreeletOptions};
use trax_assembler::image::{build_image_from_symbols, on_demand_components, Perms, RenderOptions};
use trax_assembler::scene::{load_scene, LoadOptions};
use trax_runtime::abi;

fn fnv(b: &[u8]) -> u64 {
    let mut h = 0xcbf29ce484222325u64;
    for x in b {
        h ^= *x as u64;
        h = h.wrapping_mul(0x100000001b3);
    }
    h
}

#[test]
fn dump() {
    let mut out = String::new();
    for s in [
        "cornell",
        "/work/shared/scenes/bunny/stanford-bunny.obj",
        "procedural:5000",
        "icosphere:3",
    ] {
        let scene = load_scene(s, &LoadOptions::default()).unwrap();
        for tre in [false, true] {
            let all = on_demand_components();
            for subset in [
                &all[..],
                &["triangles", "materials"][..],
                &["treelet_ids"][..],
            ] {
                let opts = RenderOptions {
                    width: 33,
                    height: 17,
                    bvh: BvhOptions {
                        treelets: tre.then_some(TreeletOptions {
                            budget_bytes: 4096,
                            align_bytes: 2048,
                        }),
                        ..BvhOptions::default()
                    },
                    ..RenderOptions::default()
                };
                let prog = vec![trax_assembler::image::Segment::new(
                    "text",
                    abi::TEXT_BASE,
                    vec![1, 2, 3, 4, 5],
                    Perms::RX,
                )];
                let img =
                    build_image_from_symbols(prog, abi::TEXT_BASE, subset, &scene, &opts).unwrap();
                out += &format!(
                    "== {s} treelets={tre} subset={subset:?} end={:#x} program_end={:#x}\n",
                    img.end, img.program_end
                );
                for g in &img.memory.segments {
                    let mut d = g.data.clone();
                    d.resize(g.size as usize, 0);
                    out += &format!("  {} {:#x} {} {:016x}\n", g.name, g.addr, g.size, fnv(&d));
                }
                for c in &img.components {
                    out += &format!("  comp {} {:#x} {} {}\n", c.name, c.addr, c.count, c.bytes);
                }
            }
        }
    }
    std::fs::write("/tmp/wtK/imgdump-after.txt", out).unwrap();
}
