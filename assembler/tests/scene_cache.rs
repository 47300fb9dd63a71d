//! The scene cache (`trax_assembler::scene::cache`): a cached scene is the loaded one bit
//! for bit, and is loaded anew when any file it was read from changes, or when the cache
//! file is damaged.

use std::path::{Path, PathBuf};

use trax_assembler::scene::cache::{cache_file, decode, load_scene_cached, CacheUse};
use trax_assembler::scene::{load_scene, LoadOptions, Scene};

fn scene_dir(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("scene-cache-{name}"));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn same(a: &Scene, b: &Scene) {
    assert_eq!(a.name, b.name);
    let bits = |s: &Scene| -> Vec<u32> {
        s.triangles
            .iter()
            .flat_map(|t| t.as_flattened().to_vec())
            .chain(s.normals.iter().flat_map(|t| t.as_flattened().to_vec()))
            .chain(s.texcoords.iter().flat_map(|t| t.as_flattened().to_vec()))
            .map(f32::to_bits)
            .collect()
    };
    assert_eq!(bits(a), bits(b));
    assert_eq!(a.material_ids, b.material_ids);
    assert_eq!(a.materials, b.materials);
    assert_eq!(a.view, b.view);
    assert_eq!(a.point_lights, b.point_lights);
    assert_eq!(a.warnings, b.warnings);
    assert_eq!(a.sources, b.sources);
}

/// A cached scene is the loaded one bit for bit; an edited source is loaded anew; a
/// damaged cache file is loaded anew, never trusted.
#[test]
fn cached_scenes_are_the_loaded_ones_until_a_source_changes() {
    let d = scene_dir("roundtrip");
    let obj = d.join("t.obj");
    std::fs::write(
        &obj,
        "mtllib t.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0.5\nvt 0 1\nvn 0 0 1\nusemtl m\nf 1 2 3\n",
    )
    .unwrap();
    std::fs::write(
        d.join("t.mtl"),
        "newmtl m\nKd 0.1 0.2 0.3\nKe 1 1 1\nillum 2\n",
    )
    .unwrap();
    std::fs::write(d.join("t.light"), "0 0 2\n").unwrap();
    let cache = d.join("cache");
    let spec = format!("subdivide:1:{}", obj.display());
    let opts = LoadOptions::default();
    let fresh = load_scene(&spec, &opts).unwrap();
    let (a, u) = load_scene_cached(&spec, &opts, &cache).unwrap();
    assert_eq!(u, CacheUse::Stored);
    same(&a, &fresh);
    let (b, u) = load_scene_cached(&spec, &opts, &cache).unwrap();
    assert_eq!(u, CacheUse::Hit);
    same(&b, &fresh);
    // Every prefix of the file is refused (no panic, no huge allocation).
    let file = cache_file(&cache, &spec, &opts);
    let bytes = std::fs::read(&file).unwrap();
    for n in 0..bytes.len() {
        assert!(decode(&bytes[..n]).is_err(), "prefix {n}");
    }
    std::fs::write(&file, &bytes[..bytes.len() / 2]).unwrap();
    assert_eq!(
        load_scene_cached(&spec, &opts, &cache).unwrap().1,
        CacheUse::Stored
    );
    // An edited MTL (not the OBJ) is noticed.
    std::fs::write(d.join("t.mtl"), "newmtl m\nKd 0.9 0.2 0.3\n").unwrap();
    let (c, u) = load_scene_cached(&spec, &opts, &cache).unwrap();
    assert_eq!(u, CacheUse::Stored);
    assert_eq!(c.materials[0].diffuse, [0.9, 0.2, 0.3]);
    // A .view appearing beside the OBJ is noticed.
    std::fs::write(
        d.join("t.view"),
        "0.2 0.2 3\n0 0 -1\n0 1 0\n0\n-0.5 0.5 -0.5 0.5\n1\n",
    )
    .unwrap();
    let (v, u) = load_scene_cached(&spec, &opts, &cache).unwrap();
    assert_eq!(u, CacheUse::Stored);
    assert_eq!(v.view.eye, [0.2, 0.2, 3.0]);
    let _ = std::fs::remove_dir_all(&d);
}
