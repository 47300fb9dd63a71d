//! Scenes at extreme scales: the scene scale option, the icosphere, the camera framing a
//! scene, the header epsilon, and camera errors that name the file they came from.

use std::path::PathBuf;

use trax_assembler::image::default_epsilon;
use trax_assembler::scene::{icosphere, load_scene, LoadOptions, Scene, SceneError};

fn tmpdir(name: &str) -> PathBuf {
    let d = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("scene-scale-{name}"));
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn scaled(spec: &str, scale: f64) -> Result<Scene, SceneError> {
    load_scene(
        spec,
        &LoadOptions {
            scale: Some(scale),
            ..LoadOptions::default()
        },
    )
}

fn rel(a: f64, b: f64) -> f64 {
    (a / b - 1.0).abs()
}

#[test]
fn scaling_multiplies_positions_and_keeps_directions() {
    let unit = load_scene("cornell", &LoadOptions::default()).unwrap();
    for k in [-30, -20, -1, 1, 20, 30] {
        let s = 10f64.powi(k);
        let big = scaled("cornell", s).unwrap();
        for (a, b) in unit
            .triangles
            .iter()
            .flatten()
            .zip(big.triangles.iter().flatten())
        {
            for i in 0..3 {
                assert_eq!(b[i], (a[i] as f64 * s) as f32, "1e{k}");
            }
        }
        assert_eq!(big.normals, unit.normals, "1e{k}: normals are directions");
        for i in 0..3 {
            assert_eq!(big.view.eye[i], (unit.view.eye[i] as f64 * s) as f32);
            let (p, q) = (
                unit.point_lights[0].position[i],
                big.point_lights[0].position[i],
            );
            assert_eq!(q, (p as f64 * s) as f32);
        }
        assert_eq!(big.view.gaze, unit.view.gaze);
        assert_eq!(big.view.distance, unit.view.distance);
        // The camera basis is the same direction at every scale.
        let (c1, c2) = (unit.view.camera().unwrap(), big.view.camera().unwrap());
        assert_eq!((c1.u, c1.v, c1.w), (c2.u, c2.v, c2.w));
        // Bounds, diagonal and the header epsilon scale with the scene (no absolute floor;
        // the f32 diagonal of a 1e30 box would overflow).
        let (d1, d2) = (unit.bounds().diagonal_f64(), big.bounds().diagonal_f64());
        assert!(rel(d2, d1 * s) < 1e-6, "1e{k}: diagonal {d2}");
        let (e1, e2) = (default_epsilon(&unit) as f64, default_epsilon(&big) as f64);
        assert!(rel(e2, e1 * s) < 1e-6, "1e{k}: epsilon {e2} vs {e1}");
        assert!(rel(e2, 1e-4 * d2) < 1e-6);
    }
}

#[test]
fn bad_scales_are_errors_naming_the_scale() {
    for s in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        match scaled("cornell", s) {
            Err(e @ SceneError::Scale { .. }) => {
                assert!(e.to_string().contains("positive finite"), "{e}")
            }
            other => panic!("scale {s}: {other:?}"),
        }
    }
    // 559.2 * 1e36 is beyond the largest f32.
    match scaled("cornell", 1e36) {
        Err(e @ SceneError::Scale { .. }) => {
            let m = e.to_string();
            assert!(m.contains("1e36") && m.contains("vertex"), "{m}");
        }
        other => panic!("{other:?}"),
    }
    // Tiny enough to make coordinates subnormal: allowed, with a warning.
    let s = scaled("cornell", 1e-40).unwrap();
    assert!(
        s.warnings.iter().any(|w| w.contains("subnormal")),
        "{:?}",
        s.warnings
    );
    assert!(scaled("cornell", 1e-20).unwrap().warnings.is_empty());
}

/// A scene file with coordinates near 1e37 (finite f32s) and a usable `.view` file loads:
/// the camera is checked after the view file is applied (the framing camera, whose
/// f32 diagonal overflowed, used to be checked first and fail without naming a file).
#[test]
fn huge_scene_files_load_with_their_view_and_camera_errors_name_the_file() {
    let d = tmpdir("huge");
    let obj = d.join("huge.obj");
    std::fs::write(
        &obj,
        "v 1e37 0 0\nv 3e37 0 0\nv 1e37 2e37 1e37\nv 2e37 1e37 3e37\nf 1 2 3\nf 1 3 4\n",
    )
    .unwrap();
    let view = d.join("huge.view");
    std::fs::write(&view, "2e37 -9e37 1e37  0 1 0  0 0 1  0 -1 1 -1 1 2\n").unwrap();
    let s = load_scene(obj.to_str().unwrap(), &LoadOptions::default()).unwrap();
    assert_eq!(s.view.eye, [2e37, -9e37, 1e37]);
    // Without a view file, the framing camera is finite too (computed in f64).
    std::fs::remove_file(&view).unwrap();
    let s = load_scene(obj.to_str().unwrap(), &LoadOptions::default()).unwrap();
    assert!(s.view.eye.iter().all(|c| c.is_finite()), "{:?}", s.view.eye);
    assert!(s.warnings.iter().any(|w| w.contains("framing")));
    // Where even the framing camera cannot be represented, the error says so and names
    // the scene file.
    std::fs::write(
        &obj,
        "v 3e38 3e38 3e38\nv -3e38 3e38 3e38\nv 3e38 -3e38 3e38\nf 1 2 3\n",
    )
    .unwrap();
    match load_scene(obj.to_str().unwrap(), &LoadOptions::default()) {
        Err(e @ SceneError::BadCamera(_)) => {
            let m = e.to_string();
            assert!(m.contains("huge.obj") && m.contains("--view"), "{m}");
        }
        other => panic!("{other:?}"),
    }
    // A view file whose eye overflows once scaled: the error names the file and the scale.
    let v2 = d.join("far.view");
    std::fs::write(&v2, "0 -3e37 0  0 1 0  0 0 1  0 -1 1 -1 1 2\n").unwrap();
    match load_scene(
        "cornell",
        &LoadOptions {
            view: Some(v2.clone()),
            scale: Some(100.0),
            ..LoadOptions::default()
        },
    ) {
        Err(e) => {
            let m = e.to_string();
            assert!(m.contains("camera eye") && m.contains("100"), "{m}");
        }
        other => panic!("{other:?}"),
    }
    // A view file with an unusable camera: named.
    let bad = d.join("bad.view");
    std::fs::write(&bad, "0 0 0  0 0 1  0 0 2  0 -1 1 -1 1 2\n").unwrap();
    match load_scene(
        "cornell",
        &LoadOptions {
            view: Some(bad),
            ..LoadOptions::default()
        },
    ) {
        Err(e) => assert!(e.to_string().contains("bad.view"), "{e}"),
        other => panic!("{other:?}"),
    }
}

/// A scene of zero size is framed relative to its distance from the origin, at every scale
/// (an absolute minimum radius of 1e-6 used to put the camera far away from tiny scenes).
#[test]
fn framing_is_relative_at_every_scale() {
    let d = tmpdir("framing");
    for k in [-30, -12, 0, 12, 30] {
        let s = 10f32.powi(k);
        let obj = d.join(format!("tri{k}.obj"));
        std::fs::write(
            &obj,
            format!(
                "v {s:e} 0 0\nv {:e} 0 0\nv {s:e} {s:e} 0\nf 1 2 3\n",
                2.0 * s
            ),
        )
        .unwrap();
        let scene = load_scene(obj.to_str().unwrap(), &LoadOptions::default()).unwrap();
        // Eye 2.5 half-diagonals above the centre.
        let expected = 2.5 * 0.5 * (2.0f64).sqrt() * s as f64;
        assert!(
            rel(scene.view.eye[2] as f64, expected) < 1e-6,
            "1e{k}: {:?}",
            scene.view.eye
        );
    }
}

#[test]
fn icosphere_scenes() {
    let s = load_scene("icosphere:2", &LoadOptions::default()).unwrap();
    assert_eq!(s.len(), 320);
    assert_eq!(s.point_lights.len(), 1);
    assert_eq!(icosphere(0).unwrap().len(), 20);
    for bad in ["icosphere:x", "icosphere:", "icosphere", "icosphere:11"] {
        match load_scene(bad, &LoadOptions::default()) {
            Err(e @ SceneError::Procedural { .. }) => {
                assert!(e.to_string().contains("icosphere"), "{e}")
            }
            other => panic!("{bad}: {other:?}"),
        }
    }
}
