//! Bad scene input gets a typed error naming the file and line, never a panic.

use std::path::PathBuf;

use trax_assembler::scene::{
    load_obj, load_objl, load_scene, parse_view, procedural, LoadOptions, SceneError,
};

fn tmpdir(name: &str) -> PathBuf {
    let d =
        std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("trax-scene-err-{name}"));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Writes `obj` (and an optional `bad.mtl`) to a fresh directory and loads it.
fn load(
    name: &str,
    obj: &str,
    mtl: Option<&str>,
) -> Result<trax_assembler::scene::Scene, SceneError> {
    let d = tmpdir(name);
    if let Some(m) = mtl {
        std::fs::write(d.join("bad.mtl"), m).unwrap();
    }
    let p = d.join("bad.obj");
    std::fs::write(&p, obj).unwrap();
    load_obj(&p)
}

fn expect_syntax(
    r: Result<trax_assembler::scene::Scene, SceneError>,
    file: &str,
    line: usize,
    needle: &str,
) {
    match r {
        Err(e @ SceneError::Syntax { .. }) => {
            let SceneError::Syntax {
                ref path,
                line: l,
                ref message,
            } = e
            else {
                unreachable!()
            };
            assert!(path.ends_with(file), "{e}");
            assert_eq!(l, line, "{e}");
            assert!(
                message.contains(needle),
                "`{message}` should mention `{needle}`"
            );
            assert!(e.to_string().contains(&format!("{file}:{line}:")), "{e}");
        }
        other => panic!("expected a syntax error, got {other:?}"),
    }
}

const TRI: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";

#[test]
fn malformed_obj_lines() {
    expect_syntax(
        load("v2", "v 0 0 0\nv 1 0\n", None),
        "bad.obj",
        2,
        "vertex z coordinate",
    );
    expect_syntax(load("vx", "v 0 zero 0\n", None), "bad.obj", 1, "`zero`");
    expect_syntax(
        load("vn", &format!("{TRI}vn 0 1\n"), None),
        "bad.obj",
        4,
        "normal z",
    );
    expect_syntax(
        load("vt", &format!("{TRI}vt a b\n"), None),
        "bad.obj",
        4,
        "texture coordinate u",
    );
    expect_syntax(
        load("f2", &format!("{TRI}f 1 2\n"), None),
        "bad.obj",
        4,
        "at least 3",
    );
    expect_syntax(
        load("fx", &format!("{TRI}f 1 2 x\n"), None),
        "bad.obj",
        4,
        "integer vertex index",
    );
    expect_syntax(
        load("f0", &format!("{TRI}f 0 1 2\n"), None),
        "bad.obj",
        4,
        "out of range",
    );
    expect_syntax(
        load("f9", &format!("{TRI}f 1 2 9\n"), None),
        "bad.obj",
        4,
        "out of range",
    );
    expect_syntax(
        load("fneg", &format!("{TRI}f -1 -2 -4\n"), None),
        "bad.obj",
        4,
        "out of range",
    );
    expect_syntax(
        load("ft", &format!("{TRI}vt 0 0\nf 1/2 2/1 3/1\n"), None),
        "bad.obj",
        5,
        "texture coordinate index",
    );
    expect_syntax(
        load("fn", &format!("{TRI}f 1//1 2//1 3//1\n"), None),
        "bad.obj",
        4,
        "normal index",
    );
    expect_syntax(
        load("um", &format!("{TRI}usemtl\nf 1 2 3\n"), None),
        "bad.obj",
        4,
        "material name",
    );
    expect_syntax(load("w0", "v 0 0 0 0\n", None), "bad.obj", 1, "weight");
}

#[test]
fn malformed_mtl_lines() {
    let obj = format!("mtllib bad.mtl\n{TRI}usemtl a\nf 1 2 3\n");
    expect_syntax(
        load("kd2", &obj, Some("newmtl a\nKd 0.5 0.5\n")),
        "bad.mtl",
        2,
        "Kd r g b",
    );
    expect_syntax(
        load("ns", &obj, Some("newmtl a\n\nNs shiny\n")),
        "bad.mtl",
        3,
        "after `Ns`",
    );
    expect_syntax(
        load("ill", &obj, Some("newmtl a\nillum 300\n")),
        "bad.mtl",
        2,
        "illumination model",
    );
    expect_syntax(
        load("nm", &obj, Some("newmtl\n")),
        "bad.mtl",
        1,
        "material name",
    );
    expect_syntax(
        load("ke", &obj, Some("newmtl a\nKe 1 x 1\n")),
        "bad.mtl",
        2,
        "`x`",
    );
}

#[test]
fn non_finite_vertices() {
    for (name, v) in [
        ("nan", "nan"),
        ("inf", "inf"),
        ("ninf", "-inf"),
        ("big", "1e39"),
    ] {
        match load(
            name,
            &format!("v 0 0 0\nv 1 {v} 0\nv 0 1 0\nf 1 2 3\n"),
            None,
        ) {
            Err(SceneError::NonFiniteVertex { line, value, .. }) => {
                assert_eq!(line, 2);
                assert_eq!(value, v);
            }
            other => panic!("{name}: expected NonFiniteVertex, got {other:?}"),
        }
    }
    // A finite but tiny w makes the coordinate overflow after division: caught after loading.
    match load("w", "v 1e30 0 0 1e-30\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", None) {
        Err(SceneError::NonFiniteTriangle {
            triangle: 0,
            what: "vertex",
            ..
        }) => {}
        other => panic!("expected NonFiniteTriangle, got {other:?}"),
    }
}

#[test]
fn missing_files() {
    let d = tmpdir("missing");
    match load_obj(&d.join("nope.obj")) {
        Err(SceneError::Io { path, .. }) => assert!(path.ends_with("nope.obj")),
        other => panic!("{other:?}"),
    }
    let list = d.join("l.objl");
    std::fs::write(&list, "gone.obj\n").unwrap();
    match load_objl(&list) {
        Err(e @ SceneError::Io { .. }) => assert!(e.to_string().contains("l.objl:1"), "{e}"),
        other => panic!("{other:?}"),
    }
    std::fs::write(&list, "notes.txt\n").unwrap();
    assert!(matches!(
        load_objl(&list),
        Err(SceneError::Syntax { line: 1, .. })
    ));
    match load_scene(
        d.join("x.obj").to_str().unwrap(),
        &LoadOptions {
            view: Some(d.join("none.view")),
            ..LoadOptions::default()
        },
    ) {
        Err(SceneError::Io { .. }) => {}
        other => panic!("{other:?}"),
    }
    let obj = d.join("t.obj");
    std::fs::write(&obj, format!("{TRI}f 1 2 3\n")).unwrap();
    match load_scene(
        obj.to_str().unwrap(),
        &LoadOptions {
            view: Some(d.join("none.view")),
            ..LoadOptions::default()
        },
    ) {
        Err(SceneError::Io { path, .. }) => assert!(path.ends_with("none.view")),
        other => panic!("{other:?}"),
    }
}

#[test]
fn empty_scenes() {
    assert!(matches!(load("empty", "", None), Err(SceneError::Empty(_))));
    assert!(matches!(
        load("verts", TRI, None),
        Err(SceneError::Empty(_))
    ));
    let d = tmpdir("emptylist");
    let list = d.join("e.objl");
    std::fs::write(&list, "# nothing\n").unwrap();
    assert!(matches!(load_objl(&list), Err(SceneError::Empty(_))));
}

#[test]
fn bad_view_and_light_files() {
    let d = tmpdir("view");
    let v = d.join("c.view");
    std::fs::write(&v, "0 0 0  0 1 0  0 0 1  0 -1 1 -1 1\n").unwrap();
    assert!(matches!(
        parse_view(&v),
        Err(SceneError::Syntax { line: 1, .. })
    ));
    std::fs::write(&v, "0 0 0  0 1 0\n0 0 one  0 -1 1 -1 1 2\n").unwrap();
    assert!(matches!(
        parse_view(&v),
        Err(SceneError::Syntax { line: 2, .. })
    ));
    std::fs::write(&v, "0 0 0  0 1 0  0 0 1  0 -1 1 -1 1 2 7\n").unwrap();
    assert!(matches!(
        parse_view(&v),
        Err(SceneError::Syntax { line: 1, .. })
    ));
    std::fs::write(&v, "0 0 0  0 0 1  0 0 1  0 -1 1 -1 1 2\n").unwrap();
    match parse_view(&v) {
        Err(SceneError::BadCamera(m)) => assert!(m.contains("parallel"), "{m}"),
        other => panic!("{other:?}"),
    }
    std::fs::write(&v, "0 0 0  0 0 0  0 0 1  0 -1 1 -1 1 2\n").unwrap();
    assert!(matches!(parse_view(&v), Err(SceneError::BadCamera(_))));
    let l = d.join("c.light");
    std::fs::write(&l, "1 2\n").unwrap();
    assert!(matches!(
        trax_assembler::scene::parse_light(&l),
        Err(SceneError::Syntax { .. })
    ));
    std::fs::write(&l, "1 2 nan\n").unwrap();
    assert!(matches!(
        trax_assembler::scene::parse_light(&l),
        Err(SceneError::Syntax { .. })
    ));
    // An optional intensity: one number (white) or three (RGB), never negative or 2.
    let light = |text: &str| {
        std::fs::write(&l, text).unwrap();
        trax_assembler::scene::parse_light(&l)
    };
    let p = light("1 2 3\n").unwrap();
    assert_eq!((p.position, p.color), ([1.0, 2.0, 3.0], [1.0; 3]));
    assert_eq!(light("1 2 3\n40\n").unwrap().color, [40.0; 3]);
    assert_eq!(light("1 2 3  4 5 6").unwrap().color, [4.0, 5.0, 6.0]);
    for bad in ["1 2 3 4 5", "1 2 3 4 5 6 7", "1 2 3 -4"] {
        match light(bad) {
            Err(e @ SceneError::Syntax { .. }) => {
                let m = e.to_string();
                assert!(
                    m.contains("c.light") && m.contains("intensity"),
                    "{bad}: {m}"
                );
            }
            other => panic!("{bad}: {other:?}"),
        }
    }
}

#[test]
fn bad_scene_names_and_sizes() {
    assert!(matches!(
        load_scene("kitchen", &LoadOptions::default()),
        Err(SceneError::UnknownScene(_))
    ));
    assert!(matches!(
        load_scene("procedural:lots", &LoadOptions::default()),
        Err(SceneError::Procedural { .. })
    ));
    assert!(matches!(
        load_scene("procedural", &LoadOptions::default()),
        Err(SceneError::Procedural { .. })
    ));
    assert!(matches!(procedural(3), Err(SceneError::Procedural { .. })));
    // More triangles than the 32-bit address space holds: refused before allocating.
    match procedural(100_000_000) {
        Err(e @ SceneError::TooLarge { .. }) => assert!(e.to_string().contains("32-bit"), "{e}"),
        other => panic!("{other:?}"),
    }
}
