//! OBJ/MTL loading through `tobj`, with our own line-by-line check first.
//!
//! tobj reports errors without a line number and accepts some input it should not (NaN
//! coordinates, `Kd` with one value panics inside it), so every OBJ and MTL file is first
//! scanned here: each line is checked for what tobj will expect, and the first problem is
//! reported as `file:line: what was expected`. Only then is the text handed to tobj, which
//! triangulates polygons, resolves negative indices and builds the meshes.

use std::cell::RefCell;
use std::io::Cursor;
use std::path::{Path, PathBuf};

use super::{geometric_normal, Material, Scene, SceneError, View, MAX_TRIANGLES};

fn syntax(path: &Path, line: usize, message: impl Into<String>) -> SceneError {
    SceneError::Syntax {
        path: path.to_path_buf(),
        line,
        message: message.into(),
    }
}

/// Parses `tok` as an f32, naming `what` in the error.
fn float(path: &Path, line: usize, tok: Option<&str>, what: &str) -> Result<f32, SceneError> {
    let tok =
        tok.ok_or_else(|| syntax(path, line, format!("expected {what}, found end of line")))?;
    tok.parse::<f32>()
        .map_err(|_| syntax(path, line, format!("expected {what}, found `{tok}`")))
}

/// Checks one OBJ file line by line (see the module doc).
fn check_obj(path: &Path, text: &str) -> Result<(), SceneError> {
    let (mut nv, mut nt, mut nn) = (0i64, 0i64, 0i64);
    for (i, line) in text.lines().enumerate() {
        let ln = i + 1;
        let mut w = line.split_whitespace();
        let Some(key) = w.next() else { continue };
        match key {
            "v" => {
                for axis in ["x", "y", "z"] {
                    let tok = w.next();
                    let v = float(path, ln, tok, &format!("vertex {axis} coordinate"))?;
                    if !v.is_finite() {
                        return Err(SceneError::NonFiniteVertex {
                            path: path.to_path_buf(),
                            line: ln,
                            value: tok.unwrap_or_default().to_string(),
                        });
                    }
                }
                let rest: Vec<&str> = w.collect();
                match rest.len() {
                    0 => {}
                    1 => {
                        let wv = float(path, ln, Some(rest[0]), "vertex weight w")?;
                        if wv == 0.0 || !wv.is_finite() {
                            return Err(syntax(
                                path,
                                ln,
                                "vertex weight w must be finite and non-zero",
                            ));
                        }
                    }
                    3 => {
                        for c in rest {
                            float(path, ln, Some(c), "vertex colour component")?;
                        }
                    }
                    n => {
                        return Err(syntax(
                            path,
                            ln,
                            format!(
                                "expected `v x y z [w]` or `v x y z r g b`, found {} numbers",
                                3 + n
                            ),
                        ))
                    }
                }
                nv += 1;
            }
            "vt" => {
                float(path, ln, w.next(), "texture coordinate u")?;
                float(path, ln, w.next(), "texture coordinate v")?;
                nt += 1;
            }
            "vn" => {
                for axis in ["x", "y", "z"] {
                    float(path, ln, w.next(), &format!("normal {axis} component"))?;
                }
                nn += 1;
            }
            "f" => {
                let mut count = 0;
                for r in w {
                    check_face_ref(path, ln, r, [nv, nt, nn])?;
                    count += 1;
                }
                if count < 3 {
                    return Err(syntax(
                        path,
                        ln,
                        format!("a face needs at least 3 vertex references, found {count}"),
                    ));
                }
            }
            "l" => {
                for r in w {
                    check_face_ref(path, ln, r, [nv, nt, nn])?;
                }
            }
            "usemtl" | "mtllib" if w.next().is_none() => {
                let what = if key == "usemtl" {
                    "material name"
                } else {
                    "file name"
                };
                return Err(syntax(path, ln, format!("expected a {what} after `{key}`")));
            }
            _ => {}
        }
    }
    Ok(())
}

/// Checks one face vertex reference `v`, `v/t`, `v//n` or `v/t/n` against the element counts so far.
fn check_face_ref(path: &Path, ln: usize, r: &str, counts: [i64; 3]) -> Result<(), SceneError> {
    let parts: Vec<&str> = r.split('/').collect();
    if parts.len() > 3 {
        return Err(syntax(
            path,
            ln,
            format!("expected a vertex reference `v`, `v/t`, `v//n` or `v/t/n`, found `{r}`"),
        ));
    }
    const NAMES: [&str; 3] = ["vertex", "texture coordinate", "normal"];
    for (k, p) in parts.iter().enumerate() {
        if p.is_empty() {
            if k == 0 {
                return Err(syntax(path, ln, format!("missing vertex index in `{r}`")));
            }
            continue;
        }
        let idx: i64 = p.parse().map_err(|_| {
            syntax(
                path,
                ln,
                format!(
                    "expected an integer {} index, found `{p}` in `{r}`",
                    NAMES[k]
                ),
            )
        })?;
        let n = counts[k];
        if idx == 0 || idx > n || idx < -n {
            return Err(syntax(
                path,
                ln,
                format!(
                    "{} index {idx} is out of range: {n} defined so far (indices are 1..={n} or -{n}..=-1)",
                    NAMES[k]
                ),
            ));
        }
    }
    Ok(())
}

/// Checks one MTL file line by line and returns it normalized for tobj: tabs become spaces
/// and single-value colours (`Kd 0.5`) are expanded to three values.
fn check_mtl(path: &Path, text: &str) -> Result<String, SceneError> {
    let mut out = String::with_capacity(text.len());
    for (i, line) in text.lines().enumerate() {
        let ln = i + 1;
        let mut w = line.split_whitespace();
        let key = w.next();
        match key {
            Some(k @ ("Ka" | "Kd" | "Ks" | "Ke" | "Tf")) => {
                let vals: Vec<&str> = w.collect();
                if vals
                    .first()
                    .is_some_and(|v| *v == "spectral" || *v == "xyz")
                {
                    return Err(syntax(
                        path,
                        ln,
                        format!(
                            "`{k} {}` colours are not supported; expected `{k} r g b`",
                            vals[0]
                        ),
                    ));
                }
                let mut rgb = Vec::new();
                for v in &vals {
                    rgb.push(float(path, ln, Some(v), &format!("a number for `{k}`"))?);
                }
                if rgb.iter().any(|c| !c.is_finite()) {
                    return Err(syntax(path, ln, format!("`{k}` values must be finite")));
                }
                match rgb.len() {
                    1 => out.push_str(&format!("{k} {0} {0} {0}", rgb[0])),
                    3 => out.push_str(&format!("{k} {} {} {}", rgb[0], rgb[1], rgb[2])),
                    n => {
                        return Err(syntax(
                            path,
                            ln,
                            format!("expected `{k} r g b`, found {n} numbers"),
                        ))
                    }
                }
                out.push('\n');
                continue;
            }
            Some(k @ ("Ns" | "Ni" | "d" | "Tr")) => {
                let v = float(path, ln, w.next(), &format!("a number after `{k}`"))?;
                if !v.is_finite() {
                    return Err(syntax(path, ln, format!("`{k}` must be finite")));
                }
            }
            Some("illum") => {
                let tok = w.next();
                if tok.and_then(|t| t.parse::<u8>().ok()).is_none() {
                    return Err(syntax(
                        path,
                        ln,
                        format!("expected an illumination model number 0..=255 after `illum`, found `{}`", tok.unwrap_or("")),
                    ));
                }
            }
            Some("newmtl") if w.next().is_none() => {
                return Err(syntax(path, ln, "expected a material name after `newmtl`"));
            }
            Some(k) if (k.starts_with("map_") || k == "bump") && w.next().is_none() => {
                return Err(syntax(
                    path,
                    ln,
                    format!("expected a file name after `{k}`"),
                ));
            }
            _ => {}
        }
        out.push_str(&line.replace('\t', " "));
        out.push('\n');
    }
    Ok(out)
}

fn convert_material(m: &tobj::Material) -> Material {
    Material {
        name: m.name.clone(),
        diffuse: m.diffuse.unwrap_or([0.0; 3]),
        specular: m.specular.unwrap_or([0.0; 3]),
        emission: m.emissive.unwrap_or([0.0; 3]),
        shininess: m.shininess.unwrap_or(0.0),
        illum: m.illumination_model.unwrap_or(0),
    }
}

/// Loads one OBJ file and its MTL libraries into `scene`, offsetting material ids by the
/// materials already in the scene. Unknown material names map to `u32::MAX` (resolved to
/// the grey default by [`Scene::validate`]).
fn append_obj(scene: &mut Scene, path: &Path, limit: u64) -> Result<(), SceneError> {
    append_obj_with(scene, path, &|p| std::fs::read_to_string(p), limit)
}

/// Triangles the faces of an OBJ text make (a face of k vertices is k - 2 triangles), counted
/// without parsing anything else: a scene too large is refused before the full parse.
fn count_triangles(text: &str) -> u64 {
    text.lines()
        .filter_map(|l| l.trim_start().strip_prefix("f"))
        .filter(|rest| rest.starts_with([' ', '\t']))
        .map(|rest| (rest.split_whitespace().count() as u64).saturating_sub(2))
        .sum()
}

/// Reads a file's text for the OBJ loader (the file system, or memory when fuzzing).
pub type ReadText<'a> = &'a dyn Fn(&Path) -> std::io::Result<String>;

/// [`append_obj`] reading files (the OBJ and its MTL libraries) through `read_text`.
fn append_obj_with(
    scene: &mut Scene,
    path: &Path,
    read_text: ReadText,
    limit: u64,
) -> Result<(), SceneError> {
    let text = read_text(path).map_err(|source| SceneError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    scene.sources.push(super::Source::Read {
        path: path.to_path_buf(),
        sha256: super::sha256_hex(text.as_bytes()),
    });
    let count = scene.len() as u64 + count_triangles(&text);
    if count > limit {
        return Err(SceneError::TooManyTriangles {
            scene: path.display().to_string(),
            count,
            limit,
        });
    }
    check_obj(path, &text)?;
    let text = if text.contains('\t') {
        text.replace('\t', " ")
    } else {
        text
    };
    let dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
    // Errors and warnings from MTL loading, collected from inside tobj's callback.
    let mtl_error: RefCell<Option<SceneError>> = RefCell::new(None);
    let warnings: RefCell<Vec<String>> = RefCell::new(Vec::new());
    let sources: RefCell<Vec<super::Source>> = RefCell::new(Vec::new());
    let opts = tobj::LoadOptions {
        triangulate: true,
        single_index: true,
        ignore_points: true,
        ignore_lines: true,
    };
    let result = tobj::load_obj_buf(&mut Cursor::new(text.as_bytes()), &opts, |mtl: &Path| {
        let full: PathBuf = dir.join(mtl);
        let mtl_text = match read_text(&full) {
            Ok(t) => {
                sources.borrow_mut().push(super::Source::Read {
                    path: full.clone(),
                    sha256: super::sha256_hex(t.as_bytes()),
                });
                t
            }
            Err(e) => {
                if e.kind() == std::io::ErrorKind::NotFound {
                    sources
                        .borrow_mut()
                        .push(super::Source::Absent { path: full.clone() });
                }
                warnings.borrow_mut().push(format!(
                    "{}: material library {} not loaded ({e}); its materials become grey",
                    path.display(),
                    full.display()
                ));
                return Err(tobj::LoadError::OpenFileFailed);
            }
        };
        match check_mtl(&full, &mtl_text) {
            Ok(norm) => tobj::load_mtl_buf(&mut Cursor::new(norm.as_bytes())).inspect_err(|e| {
                mtl_error.borrow_mut().get_or_insert(SceneError::Obj {
                    path: full.clone(),
                    message: e.to_string(),
                });
            }),
            Err(e) => {
                mtl_error.borrow_mut().get_or_insert(e);
                Err(tobj::LoadError::MaterialParseError)
            }
        }
    });
    if let Some(e) = mtl_error.into_inner() {
        return Err(e);
    }
    scene.sources.extend(sources.into_inner());
    scene.warnings.extend(warnings.into_inner());
    let (models, materials) = result.map_err(|e| SceneError::Obj {
        path: path.to_path_buf(),
        message: e.to_string(),
    })?;
    // A failed library leaves tobj's material list as an error; the warning above says why.
    let materials = materials.unwrap_or_default();
    let base = scene.materials.len() as u32;
    scene
        .materials
        .extend(materials.iter().map(convert_material));
    for model in &models {
        let m = &model.mesh;
        let mat = m.material_id.map_or(u32::MAX, |id| base + id as u32);
        let nverts = m.positions.len() / 3;
        let has_n = m.normals.len() == m.positions.len();
        let has_t = m.texcoords.len() / 2 == nverts && !m.texcoords.is_empty();
        let pos = |i: u32| {
            let i = i as usize * 3;
            [m.positions[i], m.positions[i + 1], m.positions[i + 2]]
        };
        for tri in m.indices.chunks_exact(3) {
            let tri = [tri[0], tri[1], tri[2]];
            if tri.iter().any(|&i| i as usize >= nverts) {
                return Err(SceneError::Obj {
                    path: path.to_path_buf(),
                    message: "face index out of bounds after triangulation".into(),
                });
            }
            let t = [pos(tri[0]), pos(tri[1]), pos(tri[2])];
            let normals = if has_n {
                tri.map(|i| {
                    let i = i as usize * 3;
                    super::normalize_or_zero([m.normals[i], m.normals[i + 1], m.normals[i + 2]])
                })
            } else {
                [geometric_normal(&t); 3]
            };
            let uv = if has_t {
                tri.map(|i| {
                    let i = i as usize * 2;
                    [m.texcoords[i], m.texcoords[i + 1]]
                })
            } else {
                [[0.0; 2]; 3]
            };
            scene.triangles.push(t);
            scene.normals.push(normals);
            scene.texcoords.push(uv);
            scene.material_ids.push(mat);
        }
    }
    Ok(())
}

fn file_name(path: &Path) -> String {
    path.file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| path.display().to_string())
}

/// Loads an OBJ file (and its MTL libraries). The camera is a framing default; see
/// [`super::load_scene`] for `.view`/`.light` lookup.
pub fn load_obj(path: &Path) -> Result<Scene, SceneError> {
    load_obj_with(path, &|p| std::fs::read_to_string(p))
}

/// [`load_obj`] reading the OBJ and MTL files through `read_text`.
pub fn load_obj_with(path: &Path, read_text: ReadText) -> Result<Scene, SceneError> {
    let mut scene = read_obj_with(path, read_text, MAX_TRIANGLES)?;
    scene.view = View::framing(&scene.bounds());
    scene.validate()?;
    Ok(scene)
}

/// A scene with a placeholder camera, before anything is validated.
fn unframed(path: &Path) -> Scene {
    Scene::new(
        file_name(path),
        View::framing(&super::Bounds {
            min: [0.0; 3],
            max: [1.0; 3],
        }),
    )
}

/// [`load_obj`] without the framing camera and validation (the caller sets the camera first).
pub(crate) fn read_obj(path: &Path, limit: u64) -> Result<Scene, SceneError> {
    read_obj_with(path, &|p| std::fs::read_to_string(p), limit)
}

/// [`read_obj`] reading the OBJ and MTL files through `read_text`.
fn read_obj_with(path: &Path, read_text: ReadText, limit: u64) -> Result<Scene, SceneError> {
    let mut scene = unframed(path);
    append_obj_with(&mut scene, path, read_text, limit)?;
    Ok(scene)
}

/// Loads a simtrax `.objl` list: one OBJ file name per line, relative to the list file;
/// material ids of later files are offset by the materials loaded before them.
pub fn load_objl(path: &Path) -> Result<Scene, SceneError> {
    let mut scene = read_objl(path, MAX_TRIANGLES)?;
    scene.view = View::framing(&scene.bounds());
    scene.validate()?;
    Ok(scene)
}

/// [`load_objl`] without the framing camera and validation.
pub(crate) fn read_objl(path: &Path, limit: u64) -> Result<Scene, SceneError> {
    let mut scene = unframed(path);
    let text = super::read_source(path, &mut scene.sources).map_err(|source| SceneError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    let dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
    let mut files = 0;
    for (i, line) in text.lines().enumerate() {
        let name = line.trim();
        if name.is_empty() || name.starts_with('#') {
            continue;
        }
        let file = dir.join(name);
        if !file
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("obj"))
        {
            return Err(syntax(
                path,
                i + 1,
                format!("expected an .obj file name, found `{name}`"),
            ));
        }
        if !file.is_file() {
            return Err(SceneError::Io {
                path: file,
                source: std::io::Error::new(
                    std::io::ErrorKind::NotFound,
                    format!("listed at {}:{}", path.display(), i + 1),
                ),
            });
        }
        append_obj(&mut scene, &file, limit)?;
        files += 1;
    }
    if files == 0 {
        return Err(SceneError::Empty(scene.name));
    }
    Ok(scene)
}
