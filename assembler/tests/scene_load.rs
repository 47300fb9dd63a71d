//! Loading scenes: embedded Cornell box, procedural scenes, the shared OBJ scenes, `.objl`
//! lists, `.view`/`.light` files.

use std::path::{Path, PathBuf};

use trax_assembler::scene::{
    cornell_box, load_obj, load_objl, load_scene, parse_light, parse_view, procedural, LoadOptions,
    Scene,
};

fn shared(rel: &str) -> PathBuf {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../../shared/scenes")).join(rel)
}

fn tmpdir(name: &str) -> PathBuf {
    let d =
        std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("trax-scene-test-{name}"));
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn close(a: [f32; 3], b: [f32; 3]) -> bool {
    (0..3).all(|i| (a[i] - b[i]).abs() < 1e-4)
}

#[test]
fn embedded_cornell_box() {
    let mut s = cornell_box();
    s.validate().unwrap();
    assert_eq!(s.len(), 32);
    assert_eq!(s.materials.len(), 4);
    assert_eq!(
        s.emitters().len(),
        2,
        "the light quad is two emissive triangles"
    );
    let b = s.bounds();
    assert!(close(b.min, [0.0, 0.0, 0.0]), "{b:?}");
    assert!(close(b.max, [556.0, 559.2, 548.8]), "{b:?}");
    // Red wall on the left as seen from the camera: camera right vector is +x, red at small x.
    let cam = s.view.camera().unwrap();
    assert!(close(cam.u, [1.0, 0.0, 0.0]), "{:?}", cam.u);
    let red = s.materials.iter().position(|m| m.name == "red").unwrap() as u32;
    let red_x: Vec<f32> = (0..s.len())
        .filter(|&i| s.material_ids[i] == red)
        .flat_map(|i| s.triangles[i].map(|v| v[0]))
        .collect();
    assert!(red_x.iter().all(|&x| x < 10.0), "{red_x:?}");
    // Normals of the walls face into the room: the floor's normal points up.
    let floor = (0..s.len())
        .find(|&i| s.triangles[i].iter().all(|v| v[2] == 0.0))
        .unwrap();
    assert!(s.normals[floor][0][2] > 0.99);
    assert_eq!(s.point_lights.len(), 1);
    assert!(close(s.point_lights[0].position, [278.0, 279.5, 540.0]));
}

#[test]
fn shared_cornell_obj_with_view_and_light() {
    let s = load_scene(
        shared("cornell/CornellBox.obj").to_str().unwrap(),
        &LoadOptions::default(),
    )
    .unwrap();
    assert_eq!(s.len(), 32);
    let names: Vec<&str> = s.materials.iter().map(|m| m.name.as_str()).collect();
    assert_eq!(names, ["White", "Red", "Green", "Light"]);
    let light = &s.materials[3];
    assert_eq!(light.emission, [15.0, 15.0, 5.0]);
    assert_eq!(light.diffuse, [15.0, 15.0, 15.0]);
    assert_eq!(s.emitters().len(), 2);
    // cornell.view is found as the only .view beside the file.
    assert_eq!(s.view.eye, [278.0, -549.0, 274.0]);
    assert_eq!(s.view.gaze, [0.0, 1.0, 0.0]);
    assert_eq!(s.view.distance, 2.0);
    assert_eq!(s.point_lights[0].position, [278.0, 279.5, 540.0]);
    // The file has texture coordinates but no normals: normals are geometric and unit length.
    for n in s.normals.iter().flatten() {
        let l = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
        assert!((l - 1.0).abs() < 1e-5);
    }
    assert!(s.texcoords.iter().flatten().any(|t| t[0] == 1.0));
}

#[test]
fn view_gaze_is_a_direction() {
    // sponza.view's second triple equals the light position; simtrax reads it as a direction.
    let v = parse_view(&shared("sponza/sponza.view")).unwrap();
    assert_eq!(v.gaze, [7.97, 1.4, -1.74]);
    let c = v.camera().unwrap();
    let g = v.gaze;
    let l = (g[0] * g[0] + g[1] * g[1] + g[2] * g[2]).sqrt();
    assert!(close(c.w, [g[0] / l, g[1] / l, g[2] / l]));
    // dragon.view ends in many blank lines; .2 style numbers in dragon.light.
    let d = parse_view(&shared("dragon/dragon.view")).unwrap();
    assert_eq!(d.distance, 1.015);
    assert_eq!(
        parse_light(&shared("dragon/dragon.light"))
            .unwrap()
            .position,
        [0.0, 0.2, 0.0]
    );
}

fn check_scene(s: &Scene, triangles: usize) {
    assert_eq!(s.len(), triangles, "{}", s.name);
    assert_eq!(s.normals.len(), triangles);
    assert_eq!(s.texcoords.len(), triangles);
    assert_eq!(s.material_ids.len(), triangles);
    assert!(s
        .material_ids
        .iter()
        .all(|&m| (m as usize) < s.materials.len()));
    assert!(s.view.camera().is_ok());
}

#[test]
fn shared_scenes_parse() {
    for (file, tris, view) in [
        ("bunny/stanford-bunny.obj", 69_451, "bunny/bunny.view"),
        ("dragon/dragon-100k.obj", 100_000, "dragon/dragon-100k.view"),
        ("buddha/buddha-100k.obj", 100_000, "buddha/buddha-100k.view"),
        ("sponza/sponza.obj", 66_450, "sponza/sponza.view"),
    ] {
        let s = load_scene(shared(file).to_str().unwrap(), &LoadOptions::default()).unwrap();
        check_scene(&s, tris);
        assert_eq!(s.view, parse_view(&shared(view)).unwrap(), "{file}");
        assert_eq!(s.point_lights.len(), 1, "{file}");
    }
}

#[test]
fn sponza_without_mtl_warns_and_uses_grey() {
    let s = load_obj(&shared("sponza/sponza.obj")).unwrap();
    assert!(
        s.warnings.iter().any(|w| w.contains("sponza.mtl")),
        "{:?}",
        s.warnings
    );
    assert_eq!(s.materials.len(), 1);
    assert_eq!(s.materials[0].diffuse, [0.78; 3]);
}

#[test]
fn objl_lists_offset_materials() {
    let d = tmpdir("objl");
    let list = d.join("box.objl");
    std::fs::write(
        &list,
        format!(
            "{}\n\n# comment\n{}\n",
            shared("cornell/CornellBox.obj").display(),
            shared("dragon/dragon_box.obj").display()
        ),
    )
    .unwrap();
    let s = load_objl(&list).unwrap();
    assert_eq!(s.len(), 32 + 12);
    // Cornell's 4 materials, then a grey default for dragon_box's unknown `dragon_walls`.
    assert_eq!(s.materials.len(), 5);
    assert!(s.material_ids[32..].iter().all(|&m| m == 4));
    assert_eq!(s.material_ids[31], 3, "the light quad keeps material 3");
    // Names relative to the list file; each file's MTL ids offset by the materials before it.
    std::fs::write(d.join("a.mtl"), "newmtl m\nKd 1 0 0\n").unwrap();
    std::fs::write(d.join("b.mtl"), "newmtl m\nKd 0 1 0\nnewmtl n\nKd 0 0 1\n").unwrap();
    std::fs::write(
        d.join("a.obj"),
        "mtllib a.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl m\nf 1 2 3\n",
    )
    .unwrap();
    std::fs::write(
        d.join("b.obj"),
        "mtllib b.mtl\nv 0 0 1\nv 1 0 1\nv 0 1 1\nusemtl n\nf 1 2 3\nusemtl m\nf 3 2 1\n",
    )
    .unwrap();
    std::fs::write(d.join("rel.objl"), "a.obj\nb.obj\n").unwrap();
    let s = load_objl(&d.join("rel.objl")).unwrap();
    assert_eq!(s.len(), 3);
    assert_eq!(s.material_ids, [0, 2, 1]);
    assert_eq!(s.materials[2].diffuse, [0.0, 0.0, 1.0]);
}

#[test]
fn quads_polygons_negative_indices_and_missing_attributes() {
    let d = tmpdir("poly");
    let obj = d.join("poly.obj");
    std::fs::write(
        &obj,
        "mtllib poly.mtl\n\
         v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0.5 1.5 0\n\
         vn 0 0 1\nvt 0 0\nvt 1 0\nvt 1 1\n\
         usemtl shiny\n\
         f 1 2 3 4\n\
         f -5 -4 -3 -1 -2\n\
         usemtl glow\n\
         f 1/1/1 2/2/1 3/3/1\n\
         g other\n\
         usemtl glow\n\
         f 1//1 2//1 3//1\n",
    )
    .unwrap();
    std::fs::write(
        d.join("poly.mtl"),
        "newmtl shiny\nKd 0.5\nKs 0.9 0.9 0.9\nNs 64\nillum 2\n\nnewmtl glow\nKd 0 0 0\nKe 4 5 6\n",
    )
    .unwrap();
    let s = load_obj(&obj).unwrap();
    // quad -> 2, pentagon -> 3, two triangles.
    assert_eq!(s.len(), 2 + 3 + 2);
    assert_eq!(s.materials[0].diffuse, [0.5; 3], "single-value Kd expands");
    assert_eq!(s.materials[0].shininess, 64.0);
    assert_eq!(s.materials[0].illum, 2);
    assert_eq!(s.materials[1].emission, [4.0, 5.0, 6.0]);
    assert_eq!(&s.material_ids[..], &[0, 0, 0, 0, 0, 1, 1]);
    assert_eq!(s.emitters(), vec![5, 6]);
    // Pentagon with negative indices uses vertices 1,2,3,5,4 (fan).
    assert!(s.triangles[2..5]
        .iter()
        .flatten()
        .any(|v| *v == [0.5, 1.5, 0.0]));
    // Texcoords where given, zero where not (a mesh mixing both gets none: tobj cannot
    // keep them apart, so keep textured faces in their own group).
    assert_eq!(s.texcoords[5][2], [1.0, 1.0]);
    assert_eq!(s.texcoords[0], [[0.0; 2]; 3]);
    for n in s.normals.iter().flatten() {
        assert!(close(*n, [0.0, 0.0, 1.0]), "{n:?}");
    }
}

#[test]
fn procedural_scenes_scale_and_repeat() {
    for n in [100u64, 5_000, 50_000] {
        let a = procedural(n).unwrap();
        let b = procedural(n).unwrap();
        assert_eq!(a.triangles, b.triangles, "deterministic");
        let got = a.len() as f64;
        assert!(
            (got - n as f64).abs() <= 0.1 * n as f64,
            "asked {n}, got {got}"
        );
        assert!(a.emitters().len() >= 2);
        let bd = a.bounds();
        assert!(bd.min.iter().all(|&c| c >= 0.0) && bd.max.iter().all(|&c| c <= 10.0));
    }
    let s = load_scene("procedural:1000", &LoadOptions::default()).unwrap();
    assert!(s.len() > 900);
}
