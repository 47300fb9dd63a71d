//! A cache of loaded scenes: [`load_scene_cached`] keeps each scene it loads in a file of a
//! cache directory, named by the scene spec and load options, and the next load of the same
//! spec reads it instead of parsing the OBJ again, once every file the scene was read from
//! (its [`Scene::sources`]) is checked to be as it was (SHA-256). Points of a sweep that
//! share a scene parse it once (`trax run --scene-cache`).
//!
//! The file holds the scene as loaded (after `.view`/`.light` and scaling, before any
//! memory layout), bit for bit: f32 values as their bits, every count checked against the
//! bytes left when read back, so a damaged file is an error (and is rebuilt), never a huge
//! allocation. The cache does not know the loader's version: keep one directory per trax
//! build (`trax sweep` names it by the executable's SHA-256).

use std::path::{Path, PathBuf};

use super::{
    load_scene, sha256_hex, LoadOptions, Material, PointLight, Scene, SceneError, Source, View,
};

/// First bytes of a cache file (the format's version).
const MAGIC: &[u8; 16] = b"trax-scene/1\0\0\0\0";

/// How [`load_scene_cached`] got its scene.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CacheUse {
    /// Read from the cache.
    Hit,
    /// Loaded, and written to the cache.
    Stored,
    /// Loaded; the cache could not be written (the reason is a warning of the scene).
    Unwritable,
}

/// The cache file of a scene spec and its load options in `dir`.
pub fn cache_file(dir: &Path, spec: &str, opts: &LoadOptions) -> PathBuf {
    let show = |p: &Option<PathBuf>| p.as_ref().map(|p| p.display().to_string());
    let key = format!(
        "{}\n{spec}\n{:?}\n{:?}\n{:?}\n",
        String::from_utf8_lossy(MAGIC),
        show(&opts.view),
        show(&opts.light),
        opts.scale.map(f64::to_bits)
    );
    dir.join(format!("{}.scene", &sha256_hex(key.as_bytes())[..32]))
}

/// [`load_scene`] through the cache directory `dir` (created if missing): a cached scene
/// whose sources all hold, else the scene loaded and stored.
pub fn load_scene_cached(
    spec: &str,
    opts: &LoadOptions,
    dir: &Path,
) -> Result<(Scene, CacheUse), SceneError> {
    let file = cache_file(dir, spec, opts);
    if let Ok(bytes) = std::fs::read(&file) {
        if let Ok(scene) = decode(&bytes) {
            if scene.sources.iter().all(|s| s.holds().is_ok()) {
                // The limit is not part of the key: a cached scene is held to it here.
                let count = scene.len() as u64;
                let limit = opts.triangle_limit();
                if count > limit {
                    return Err(SceneError::TooManyTriangles {
                        scene: spec.to_string(),
                        count,
                        limit,
                    });
                }
                return Ok((scene, CacheUse::Hit));
            }
        }
    }
    let mut scene = load_scene(spec, opts)?;
    let stored = std::fs::create_dir_all(dir).and_then(|()| {
        let tmp = file.with_extension(format!("tmp.{}", std::process::id()));
        std::fs::write(&tmp, encode(&scene))?;
        std::fs::rename(&tmp, &file).inspect_err(|_| {
            let _ = std::fs::remove_file(&tmp);
        })
    });
    match stored {
        Ok(()) => Ok((scene, CacheUse::Stored)),
        Err(e) => {
            scene.warnings.push(format!(
                "scene cache {}: {e} (the scene was loaded without it)",
                file.display()
            ));
            Ok((scene, CacheUse::Unwritable))
        }
    }
}

struct W(Vec<u8>);

impl W {
    fn u32(&mut self, v: u32) {
        self.0.extend_from_slice(&v.to_le_bytes());
    }
    fn len(&mut self, n: usize) {
        self.0.extend_from_slice(&(n as u64).to_le_bytes());
    }
    fn f32s(&mut self, v: &[f32]) {
        for x in v {
            self.u32(x.to_bits());
        }
    }
    fn str(&mut self, s: &str) {
        self.len(s.len());
        self.0.extend_from_slice(s.as_bytes());
    }
}

/// The bytes of a cache file holding `scene`.
pub fn encode(scene: &Scene) -> Vec<u8> {
    let mut w = W(MAGIC.to_vec());
    w.str(&scene.name);
    w.len(scene.triangles.len());
    for t in &scene.triangles {
        w.f32s(t.as_flattened());
    }
    for n in &scene.normals {
        w.f32s(n.as_flattened());
    }
    for t in &scene.texcoords {
        for uv in t {
            w.f32s(uv);
        }
    }
    for m in &scene.material_ids {
        w.u32(*m);
    }
    w.len(scene.materials.len());
    for m in &scene.materials {
        w.str(&m.name);
        w.f32s(&m.diffuse);
        w.f32s(&m.specular);
        w.f32s(&m.emission);
        w.f32s(&[m.shininess]);
        w.u32(u32::from(m.illum));
    }
    let v = &scene.view;
    w.f32s(&v.eye);
    w.f32s(&v.gaze);
    w.f32s(&v.up);
    w.f32s(&[v.aperture, v.left, v.right, v.bottom, v.top, v.distance]);
    w.len(scene.point_lights.len());
    for l in &scene.point_lights {
        w.f32s(&l.position);
        w.f32s(&l.color);
    }
    w.len(scene.warnings.len());
    for s in &scene.warnings {
        w.str(s);
    }
    w.len(scene.sources.len());
    for s in &scene.sources {
        match s {
            Source::Read { path, sha256 } => {
                w.u32(0);
                w.str(&path.display().to_string());
                w.str(sha256);
            }
            Source::Absent { path } => {
                w.u32(1);
                w.str(&path.display().to_string());
            }
            Source::Listing { dir, ext, names } => {
                w.u32(2);
                w.str(&dir.display().to_string());
                w.str(ext);
                w.len(names.len());
                for n in names {
                    w.str(n);
                }
            }
        }
    }
    w.0
}

struct R<'a>(&'a [u8]);

impl R<'_> {
    fn take(&mut self, n: usize) -> Result<&[u8], String> {
        if n > self.0.len() {
            return Err("truncated".into());
        }
        let (a, b) = self.0.split_at(n);
        self.0 = b;
        Ok(a)
    }
    fn u32(&mut self) -> Result<u32, String> {
        let b = self.take(4)?;
        Ok(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
    }
    fn f32(&mut self) -> Result<f32, String> {
        self.u32().map(f32::from_bits)
    }
    fn v3(&mut self) -> Result<[f32; 3], String> {
        Ok([self.f32()?, self.f32()?, self.f32()?])
    }
    /// A count of items of at least `each` bytes, checked against the bytes left.
    fn len(&mut self, each: usize) -> Result<usize, String> {
        let b = self.take(8)?;
        let n = u64::from_le_bytes(b.try_into().map_err(|_| "truncated")?);
        let n = usize::try_from(n).map_err(|_| "count too large")?;
        if n.saturating_mul(each.max(1)) > self.0.len() {
            return Err(format!("count {n} is more than the file holds"));
        }
        Ok(n)
    }
    fn str(&mut self) -> Result<String, String> {
        let n = self.len(1)?;
        String::from_utf8(self.take(n)?.to_vec()).map_err(|e| e.to_string())
    }
}

/// The scene of a cache file's bytes ([`encode`]).
pub fn decode(bytes: &[u8]) -> Result<Scene, String> {
    let mut r = R(bytes);
    if r.take(MAGIC.len())? != MAGIC {
        return Err("not a trax scene cache file".into());
    }
    let name = r.str()?;
    // Per triangle: 9 + 9 + 6 floats and a material id.
    let n = r.len(100)?;
    let mut s = Scene::new(
        name,
        View::framing(&super::Bounds {
            min: [0.0; 3],
            max: [1.0; 3],
        }),
    );
    s.triangles = (0..n)
        .map(|_| Ok([r.v3()?, r.v3()?, r.v3()?]))
        .collect::<Result<_, String>>()?;
    s.normals = (0..n)
        .map(|_| Ok([r.v3()?, r.v3()?, r.v3()?]))
        .collect::<Result<_, String>>()?;
    s.texcoords = (0..n)
        .map(|_| {
            let mut uv = [[0.0; 2]; 3];
            for p in &mut uv {
                *p = [r.f32()?, r.f32()?];
            }
            Ok(uv)
        })
        .collect::<Result<_, String>>()?;
    s.material_ids = (0..n).map(|_| r.u32()).collect::<Result<_, String>>()?;
    let m = r.len(48)?;
    s.materials = (0..m)
        .map(|_| {
            Ok(Material {
                name: r.str()?,
                diffuse: r.v3()?,
                specular: r.v3()?,
                emission: r.v3()?,
                shininess: r.f32()?,
                illum: u8::try_from(r.u32()?).map_err(|_| "bad illum")?,
            })
        })
        .collect::<Result<_, String>>()?;
    s.view = View {
        eye: r.v3()?,
        gaze: r.v3()?,
        up: r.v3()?,
        aperture: r.f32()?,
        left: r.f32()?,
        right: r.f32()?,
        bottom: r.f32()?,
        top: r.f32()?,
        distance: r.f32()?,
    };
    let l = r.len(24)?;
    s.point_lights = (0..l)
        .map(|_| {
            Ok(PointLight {
                position: r.v3()?,
                color: r.v3()?,
            })
        })
        .collect::<Result<_, String>>()?;
    let w = r.len(8)?;
    s.warnings = (0..w).map(|_| r.str()).collect::<Result<_, String>>()?;
    let k = r.len(12)?;
    s.sources = (0..k)
        .map(|_| {
            Ok(match r.u32()? {
                0 => Source::Read {
                    path: r.str()?.into(),
                    sha256: r.str()?,
                },
                1 => Source::Absent {
                    path: r.str()?.into(),
                },
                2 => {
                    let dir = r.str()?.into();
                    let ext = r.str()?;
                    let c = r.len(8)?;
                    Source::Listing {
                        dir,
                        ext,
                        names: (0..c).map(|_| r.str()).collect::<Result<_, String>>()?,
                    }
                }
                t => return Err(format!("unknown source kind {t}")),
            })
        })
        .collect::<Result<_, String>>()?;
    if !r.0.is_empty() {
        return Err("trailing bytes".into());
    }
    Ok(s)
}
