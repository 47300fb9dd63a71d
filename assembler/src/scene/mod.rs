//! Scenes: triangles, per-vertex attributes, materials, camera and point lights, loaded from
//! OBJ/MTL (`.obj`, simtrax `.objl` lists), the embedded Cornell box, or generated
//! procedurally. Every loader ends in [`Scene::validate`], so a [`Scene`] handed to the BVH
//! builder or the memory image has finite vertices and at least one triangle.

pub mod cache;
mod compose;
mod cornell;
mod obj;
mod procedural;
mod standin;
mod view;

use std::path::{Path, PathBuf};

pub use compose::{enclose_in_box, subdivide, BOX_MATERIAL, BOX_TRIANGLES};
pub use cornell::cornell_box;
pub use obj::{load_obj, load_obj_with, load_objl, ReadText};
pub use procedural::{icosphere, procedural};
pub use standin::{hairball, vegetation, DEFAULT_SEED, LEAF_TRIANGLES, STRAND_TRIANGLES};
pub use view::{parse_light, parse_light_str, parse_view, parse_view_str, View};

/// A 3-component vector.
pub type Vec3 = [f32; 3];

/// Material flag: the material emits light (non-zero emission).
pub const MATERIAL_EMISSIVE: u32 = 1;
/// Material flag: the material has a non-zero specular colour.
pub const MATERIAL_SPECULAR: u32 = 2;
/// Material flags: bits 8..16 hold the MTL `illum` model number.
pub const MATERIAL_ILLUM_SHIFT: u32 = 8;

/// A surface material (MTL `Kd`, `Ks`, `Ke`, `Ns`, `illum`).
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    /// Name from `newmtl` (or a generated name).
    pub name: String,
    /// Diffuse reflectance (`Kd`).
    pub diffuse: Vec3,
    /// Specular reflectance (`Ks`).
    pub specular: Vec3,
    /// Emitted radiance (`Ke`).
    pub emission: Vec3,
    /// Specular exponent (`Ns`).
    pub shininess: f32,
    /// MTL illumination model (`illum`), 0 when absent.
    pub illum: u8,
}

impl Material {
    /// The grey material used for triangles without a (known) material, as in simtrax.
    pub fn default_grey() -> Material {
        Material {
            name: "default".into(),
            diffuse: [0.78; 3],
            specular: [0.0; 3],
            emission: [0.0; 3],
            shininess: 0.0,
            illum: 0,
        }
    }

    /// Whether the material emits light.
    pub fn is_emissive(&self) -> bool {
        self.emission.iter().any(|&c| c > 0.0)
    }

    /// The flags word stored in memory ([`MATERIAL_EMISSIVE`], [`MATERIAL_SPECULAR`], illum).
    pub fn flags(&self) -> u32 {
        let mut f = (self.illum as u32) << MATERIAL_ILLUM_SHIFT;
        if self.is_emissive() {
            f |= MATERIAL_EMISSIVE;
        }
        if self.specular.iter().any(|&c| c > 0.0) {
            f |= MATERIAL_SPECULAR;
        }
        f
    }
}

/// A point light (simtrax `.light`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointLight {
    /// Position.
    pub position: Vec3,
    /// Colour (linear RGB).
    pub color: Vec3,
}

/// A loaded scene. All per-triangle arrays have one entry per triangle.
#[derive(Clone, Debug)]
pub struct Scene {
    /// Human-readable name (file name or built-in name).
    pub name: String,
    /// Triangle vertices.
    pub triangles: Vec<[Vec3; 3]>,
    /// Per-vertex normals (geometric normal where the file has none).
    pub normals: Vec<[Vec3; 3]>,
    /// Per-vertex texture coordinates (zero where the file has none).
    pub texcoords: Vec<[[f32; 2]; 3]>,
    /// Material index per triangle, into [`Scene::materials`].
    pub material_ids: Vec<u32>,
    /// Materials (never empty after validation: a grey default is appended when needed).
    pub materials: Vec<Material>,
    /// The camera.
    pub view: View,
    /// Point lights.
    pub point_lights: Vec<PointLight>,
    /// Non-fatal problems met while loading (e.g. a missing MTL library).
    pub warnings: Vec<String>,
    /// The files the scene was loaded from, and those looked for and not found, in the
    /// order [`load_scene`] met them: loading again gives the same scene when every one
    /// [`Source::holds`] (empty for built-in scenes).
    pub sources: Vec<Source>,
}

/// A file a scene was loaded from, or looked for ([`Scene::sources`]).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Source {
    /// A file read, and the SHA-256 of its bytes (lowercase hex).
    Read {
        /// The file.
        path: PathBuf,
        /// SHA-256 of its bytes.
        sha256: String,
    },
    /// A file looked for and not there (a material library, a `.view` or `.light` file with
    /// the scene file's stem).
    Absent {
        /// The file.
        path: PathBuf,
    },
    /// The names of the `*.EXT` files in a directory (looked for: the only `.view`/`.light`
    /// file beside a scene file is its camera/lights).
    Listing {
        /// The directory.
        dir: PathBuf,
        /// The extension.
        ext: String,
        /// File names, sorted.
        names: Vec<String>,
    },
}

/// Lowercase hex SHA-256 of `bytes`.
pub fn sha256_hex(bytes: &[u8]) -> String {
    use sha2::Digest;
    sha2::Sha256::digest(bytes)
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}

impl Source {
    /// `Ok` when the file system still answers as it did when the scene was loaded; else
    /// what differs now (the file changed, appeared, is gone, ...).
    pub fn holds(&self) -> Result<(), String> {
        match self {
            Source::Read { path, sha256 } => match std::fs::read(path) {
                Ok(b) if sha256_hex(&b) == *sha256 => Ok(()),
                Ok(_) => Err(format!("{} changed", path.display())),
                Err(e) => Err(format!("{} can't be read now ({e})", path.display())),
            },
            Source::Absent { path } => match path.is_file() {
                false => Ok(()),
                true => Err(format!("{} exists now", path.display())),
            },
            Source::Listing { dir, ext, names } => {
                let now = listing(dir, ext);
                if now == *names {
                    Ok(())
                } else {
                    Err(format!(
                        "the .{ext} files in {} are now [{}] (were [{}])",
                        dir.display(),
                        now.join(", "),
                        names.join(", ")
                    ))
                }
            }
        }
    }
}

/// The names of the `*.ext` files in `dir`, sorted (none when it can't be read).
fn listing(dir: &Path, ext: &str) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .map(|d| {
            d.filter_map(|e| e.ok())
                .map(|e| e.path())
                .filter(|p| p.extension().and_then(|e| e.to_str()) == Some(ext))
                .filter_map(|p| Some(p.file_name()?.to_string_lossy().into_owned()))
                .collect()
        })
        .unwrap_or_default();
    names.sort();
    names
}

/// Reads a text file a scene is loaded from, noting it in `sources`.
pub(crate) fn read_source(path: &Path, sources: &mut Vec<Source>) -> std::io::Result<String> {
    match std::fs::read(path) {
        Ok(bytes) => {
            sources.push(Source::Read {
                path: path.to_path_buf(),
                sha256: sha256_hex(&bytes),
            });
            String::from_utf8(bytes)
                .map_err(|e| std::io::Error::new(std::io::ErrorKind::InvalidData, e))
        }
        Err(e) => {
            if e.kind() == std::io::ErrorKind::NotFound {
                sources.push(Source::Absent {
                    path: path.to_path_buf(),
                });
            }
            Err(e)
        }
    }
}

/// An axis-aligned bounding box of a scene.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bounds {
    /// Minimum corner.
    pub min: Vec3,
    /// Maximum corner.
    pub max: Vec3,
}

impl Bounds {
    /// Length of the diagonal, computed in f64 so that boxes from the smallest to the largest
    /// finite f32 coordinates neither overflow nor underflow on the way (the result is
    /// `inf` only when the diagonal itself exceeds `f32::MAX`).
    pub fn diagonal(&self) -> f32 {
        self.diagonal_f64() as f32
    }

    /// [`Bounds::diagonal`] in f64.
    pub fn diagonal_f64(&self) -> f64 {
        let d: f64 = (0..3)
            .map(|i| (self.max[i] as f64 - self.min[i] as f64).powi(2))
            .sum();
        d.sqrt()
    }

    /// Centre point (halves first, so it cannot overflow).
    pub fn center(&self) -> Vec3 {
        [0, 1, 2].map(|i| 0.5 * self.min[i] + 0.5 * self.max[i])
    }

    /// Largest absolute coordinate of the box.
    pub fn magnitude(&self) -> f32 {
        self.min
            .iter()
            .chain(&self.max)
            .fold(0.0f32, |m, c| m.max(c.abs()))
    }
}

/// Errors from loading or validating a scene.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// A file could not be read.
    #[error("cannot read {path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The underlying error.
        source: std::io::Error,
    },
    /// A line of an OBJ, MTL, `.view`, `.light` or `.objl` file is malformed.
    #[error("{path}:{line}: {message}")]
    Syntax {
        /// The file.
        path: PathBuf,
        /// 1-based line number.
        line: usize,
        /// What was expected.
        message: String,
    },
    /// A vertex coordinate is NaN or infinite.
    #[error("{path}:{line}: vertex coordinate is not finite ({value})")]
    NonFiniteVertex {
        /// The file.
        path: PathBuf,
        /// 1-based line number (0 when only known after loading).
        line: usize,
        /// The offending value as written.
        value: String,
    },
    /// tobj rejected the file after our own checks passed.
    #[error("{path}: OBJ parse error: {message}")]
    Obj {
        /// The file.
        path: PathBuf,
        /// tobj's message.
        message: String,
    },
    /// The scene has no triangles.
    #[error("scene `{0}` has no triangles")]
    Empty(String),
    /// A triangle vertex, normal or the camera is not finite after loading.
    #[error("scene `{scene}`: triangle {triangle} has a non-finite {what}")]
    NonFiniteTriangle {
        /// Scene name.
        scene: String,
        /// Triangle index.
        triangle: usize,
        /// "vertex", "normal" or "texture coordinate".
        what: &'static str,
    },
    /// The camera is unusable (zero gaze, up parallel to gaze, zero distance...).
    #[error("{0}")]
    BadCamera(String),
    /// A scene name that is neither built in nor a file path with a known extension.
    #[error(
        "unknown scene `{0}`: expected `cornell`, `procedural:N`, `icosphere:N`, `hairball:N[:SEED]`, `vegetation:N[:SEED]`, `box:SCENE`, `subdivide:N:SCENE` or a path to a .obj/.objl file"
    )]
    UnknownScene(String),
    /// The scene scale (`--scene-scale`) is unusable or makes a coordinate overflow.
    #[error("scene scale {}: {message}", show_number(*scale))]
    Scale {
        /// The scale factor as given.
        scale: f64,
        /// What is wrong.
        message: String,
    },
    /// A procedural scene request is invalid.
    #[error("bad procedural scene `{spec}`: {message}")]
    Procedural {
        /// The request as written.
        spec: String,
        /// What is wrong.
        message: String,
    },
    /// Per-triangle arrays disagree, or an index is out of range (a scene built by hand).
    #[error("{0}")]
    Inconsistent(String),
    /// More triangles than the limit in force ([`LoadOptions::max_triangles`]).
    #[error("scene `{scene}` has {count} triangles, more than the {limit} that fit in memory with the scene data the kernel reads (refused before parsing)")]
    TooManyTriangles {
        /// Scene (file or spec).
        scene: String,
        /// Triangles it has (or would have).
        count: u64,
        /// The limit.
        limit: u64,
    },
    /// The scene does not fit in the 32-bit address space.
    #[error("scene `{scene}` is too large: {what} needs {bytes} bytes, more than the 32-bit address space")]
    TooLarge {
        /// Scene name.
        scene: String,
        /// Which array.
        what: &'static str,
        /// Bytes needed.
        bytes: u64,
    },
}

/// Bytes of one stored triangle ([`trax_runtime::abi::Triangle`]).
pub const TRIANGLE_BYTES: u64 = std::mem::size_of::<trax_runtime::abi::Triangle>() as u64;

/// Largest triangle count whose triangle array fits below the stack window.
pub const MAX_TRIANGLES: u64 = (abi_limit() as u64) / TRIANGLE_BYTES;

const fn abi_limit() -> u32 {
    trax_runtime::abi::STACK_TOP
}

impl Scene {
    /// Number of triangles.
    pub fn len(&self) -> usize {
        self.triangles.len()
    }

    /// Whether the scene has no triangles.
    pub fn is_empty(&self) -> bool {
        self.triangles.is_empty()
    }

    /// Bounding box of all vertices (zero box for an empty scene).
    pub fn bounds(&self) -> Bounds {
        let mut min = [f32::INFINITY; 3];
        let mut max = [f32::NEG_INFINITY; 3];
        for t in &self.triangles {
            for v in t {
                for i in 0..3 {
                    min[i] = min[i].min(v[i]);
                    max[i] = max[i].max(v[i]);
                }
            }
        }
        if self.triangles.is_empty() {
            return Bounds {
                min: [0.0; 3],
                max: [0.0; 3],
            };
        }
        Bounds { min, max }
    }

    /// Indices of triangles whose material is emissive.
    pub fn emitters(&self) -> Vec<u32> {
        (0..self.triangles.len() as u32)
            .filter(|&i| {
                self.materials
                    .get(self.material_ids[i as usize] as usize)
                    .is_some_and(Material::is_emissive)
            })
            .collect()
    }

    /// Resolves out-of-range material ids (unknown `usemtl` names) to an appended grey
    /// default, then runs [`Scene::check`].
    pub fn validate(&mut self) -> Result<(), SceneError> {
        let nm = self.materials.len() as u32;
        if self.material_ids.iter().any(|&m| m >= nm) || self.materials.is_empty() {
            self.materials.push(Material::default_grey());
            for m in &mut self.material_ids {
                if *m >= nm {
                    *m = nm;
                }
            }
        }
        self.check()
    }

    /// Checks the invariants every consumer relies on: at least one triangle, all
    /// per-triangle arrays the same length, material ids in range, finite
    /// vertices/normals/texcoords, a usable camera, and a size that fits the 32-bit
    /// address space.
    pub fn check(&self) -> Result<(), SceneError> {
        let n = self.triangles.len();
        if n == 0 {
            return Err(SceneError::Empty(self.name.clone()));
        }
        if n as u64 > MAX_TRIANGLES {
            return Err(SceneError::TooLarge {
                scene: self.name.clone(),
                what: "triangles",
                bytes: n as u64 * TRIANGLE_BYTES,
            });
        }
        for (what, len) in [
            ("normals", self.normals.len()),
            ("texcoords", self.texcoords.len()),
            ("material_ids", self.material_ids.len()),
        ] {
            if len != n {
                return Err(SceneError::Inconsistent(format!(
                    "scene `{}` has {n} triangles but {len} {what}",
                    self.name
                )));
            }
        }
        if let Some(i) = self
            .material_ids
            .iter()
            .position(|&m| m as usize >= self.materials.len())
        {
            return Err(SceneError::Inconsistent(format!(
                "scene `{}`: triangle {i} uses material {} of {}",
                self.name,
                self.material_ids[i],
                self.materials.len()
            )));
        }
        for (i, t) in self.triangles.iter().enumerate() {
            if !t.iter().flatten().all(|c| c.is_finite()) {
                return Err(self.non_finite(i, "vertex"));
            }
        }
        for (i, t) in self.normals.iter().enumerate() {
            if !t.iter().flatten().all(|c| c.is_finite()) {
                return Err(self.non_finite(i, "normal"));
            }
        }
        for (i, t) in self.texcoords.iter().enumerate() {
            if !t.iter().flatten().all(|c| c.is_finite()) {
                return Err(self.non_finite(i, "texture coordinate"));
            }
        }
        if let Some(l) = self
            .point_lights
            .iter()
            .find(|l| !l.position.iter().chain(&l.color).all(|c| c.is_finite()))
        {
            return Err(SceneError::Inconsistent(format!(
                "scene `{}`: point light {:?} is not finite",
                self.name, l.position
            )));
        }
        self.view.camera().map(|_| ())
    }

    fn non_finite(&self, triangle: usize, what: &'static str) -> SceneError {
        SceneError::NonFiniteTriangle {
            scene: self.name.clone(),
            triangle,
            what,
        }
    }

    /// Appends a triangle with flat (geometric) normals and zero texture coordinates.
    pub fn push_flat(&mut self, tri: [Vec3; 3], material: u32) {
        let n = geometric_normal(&tri);
        self.triangles.push(tri);
        self.normals.push([n; 3]);
        self.texcoords.push([[0.0; 2]; 3]);
        self.material_ids.push(material);
    }

    /// Scales the scene about the origin by `s`: vertices, the camera's eye and the point
    /// lights' positions are multiplied by `s` (in f64, rounded once to f32); directions,
    /// normals, the image-plane window, materials and light colours are unchanged, so every
    /// camera ray keeps its direction and a scale-invariant renderer draws the same image.
    /// (Point lights keep their intensity: under a `1/d²` falloff they look `1/s²` as
    /// bright.) Errors if `s` is not a positive finite number or a coordinate overflows
    /// f32; a warning is recorded when non-zero coordinates become subnormal or zero.
    pub fn scale(&mut self, s: f64) -> Result<(), SceneError> {
        if !(s.is_finite() && s > 0.0) {
            return Err(SceneError::Scale {
                scale: s,
                message: "the scale must be a positive finite number".into(),
            });
        }
        let mut underflow = 0usize;
        let mut scale3 = |v: &mut Vec3, what: &str| -> Result<(), SceneError> {
            for c in v.iter_mut() {
                let x = (*c as f64 * s) as f32;
                if !x.is_finite() {
                    return Err(SceneError::Scale {
                        scale: s,
                        message: format!(
                            "{what} coordinate {c} becomes {} (beyond the largest f32, {:e})",
                            show_number(*c as f64 * s),
                            f32::MAX
                        ),
                    });
                }
                if *c != 0.0 && !x.is_normal() {
                    underflow += 1;
                }
                *c = x;
            }
            Ok(())
        };
        for t in &mut self.triangles {
            for v in t.iter_mut() {
                scale3(v, "a vertex")?;
            }
        }
        scale3(&mut self.view.eye, "the camera eye")?;
        for l in &mut self.point_lights {
            scale3(&mut l.position, "a point light")?;
        }
        if underflow > 0 {
            self.warnings.push(format!(
                "scaling the scene by {} makes {underflow} non-zero coordinate(s) subnormal or zero (below {:e}): precision is lost",
                show_number(s),
                f32::MIN_POSITIVE
            ));
        }
        Ok(())
    }

    /// An empty scene with a given name and camera.
    pub fn new(name: impl Into<String>, view: View) -> Scene {
        Scene {
            name: name.into(),
            triangles: Vec::new(),
            normals: Vec::new(),
            texcoords: Vec::new(),
            material_ids: Vec::new(),
            materials: Vec::new(),
            view,
            point_lights: Vec::new(),
            warnings: Vec::new(),
            sources: Vec::new(),
        }
    }
}

/// `x` as written by a person: plain for moderate magnitudes, else in `1e20` notation.
fn show_number(x: f64) -> String {
    if x != 0.0 && x.is_finite() && !(1e-4..1e6).contains(&x.abs()) {
        format!("{x:e}")
    } else {
        format!("{x}")
    }
}

/// Unit geometric normal of a triangle (zero for a degenerate triangle).
/// The edges are rescaled by powers of two before the cross product ([`rescale_pow2`]), so
/// triangles of any size get the same normal (a plain f32 cross product overflows for
/// edges longer than about 1e19 and underflows for edges shorter than about 1e-19).
pub fn geometric_normal(t: &[Vec3; 3]) -> Vec3 {
    let e1 = rescale_pow2(sub(t[1], t[0]));
    let e2 = rescale_pow2(sub(t[2], t[0]));
    normalize_or_zero(cross(e1, e2))
}

pub(crate) fn sub(a: Vec3, b: Vec3) -> Vec3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

pub(crate) fn cross(a: Vec3, b: Vec3) -> Vec3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// `v` times the power of two that brings its largest absolute component into `[1, 2)`:
/// exact, so directions computed from the result (cross products, normalisation) are the
/// same as from `v` wherever those did not overflow or underflow, and are safe from both
/// at every scale. Zero and non-finite vectors are returned unchanged.
pub fn rescale_pow2(v: Vec3) -> Vec3 {
    let m = v.iter().fold(0.0f32, |m, c| m.max(c.abs()));
    if m == 0.0 || !m.is_finite() {
        return v;
    }
    let k = f64::powi(2.0, -(m.log2().floor() as i32));
    v.map(|c| (c as f64 * k) as f32)
}

pub(crate) fn normalize_or_zero(v: Vec3) -> Vec3 {
    // Compute in f64 so tiny (1e-6-scale) triangles do not underflow to a zero length.
    let l = (v.iter().map(|&c| (c as f64) * (c as f64)).sum::<f64>()).sqrt();
    if l > 0.0 && l.is_finite() {
        v.map(|c| (c as f64 / l) as f32)
    } else {
        [0.0; 3]
    }
}

/// Where to take the camera and lights from when loading a scene file, and how to scale it.
#[derive(Clone, Debug, Default)]
pub struct LoadOptions {
    /// Explicit `.view` file; otherwise one is looked for beside the scene file.
    pub view: Option<PathBuf>,
    /// Explicit `.light` file; otherwise one is looked for beside the scene file.
    pub light: Option<PathBuf>,
    /// Scale factor applied to the whole scene after the camera and lights are in place
    /// (see [`Scene::scale`]); `None` leaves it as loaded.
    pub scale: Option<f64>,
    /// Refuse scenes of more triangles than this, before building them (OBJ files are
    /// counted before they are parsed, `subdivide:` levels before they are split); `None`:
    /// [`MAX_TRIANGLES`]. `trax::pipeline` sets the program's own limit,
    /// [`crate::image::max_triangles`] of the fields it reads.
    pub max_triangles: Option<u64>,
}

impl LoadOptions {
    /// The triangle limit in force ([`Self::max_triangles`], at most [`MAX_TRIANGLES`]).
    pub fn triangle_limit(&self) -> u64 {
        self.max_triangles
            .map_or(MAX_TRIANGLES, |n| n.min(MAX_TRIANGLES))
    }
}

/// Where a scene's camera came from, for error messages.
enum ViewSource {
    BuiltIn,
    File(PathBuf),
    Framing,
}

/// Splits a scene spec into its `box:`/`subdivide:N:` wrappers and the innermost scene,
/// and tells whether that innermost scene is a file (to be resolved as a path) or built in:
/// `box:subdivide:2:dragon.obj` → `("box:subdivide:2:", "dragon.obj", true)`.
pub fn split_spec(spec: &str) -> (&str, &str, bool) {
    let mut rest = spec;
    loop {
        if let Some(r) = rest.strip_prefix("box:") {
            rest = r;
        } else if let Some((_, r)) = rest
            .strip_prefix("subdivide:")
            .and_then(|r| r.split_once(':'))
        {
            rest = r;
        } else {
            break;
        }
    }
    let built_in = rest == "cornell"
        || [
            "procedural",
            "icosphere",
            "hairball",
            "vegetation",
            "box",
            "subdivide",
        ]
        .iter()
        .any(|g| rest == *g || rest.starts_with(&format!("{g}:")));
    (&spec[..spec.len() - rest.len()], rest, !built_in)
}

/// Most `box:`/`subdivide:` wrappers one spec may nest.
const MAX_SPEC_NESTING: usize = 8;

/// Loads a scene by spec: `cornell` (embedded), `procedural:N` (about N triangles),
/// `icosphere:N` (a closed sphere mesh, `N` subdivisions), [`hairball`]`:N[:SEED]`,
/// [`vegetation`]`:N[:SEED]` (exactly N triangles, SEED default [`DEFAULT_SEED`]),
/// `box:SCENE` ([`enclose_in_box`]), `subdivide:N:SCENE` ([`subdivide`]; wrappers nest, at
/// most 8 deep, and the inner scene is loaded with these rules, scaling left to the
/// outermost), or a path to an `.obj` or `.objl` file. For files, the camera comes from
/// `opts.view`, else a `.view` file with the same stem, else the only `.view` file in the
/// same directory, else a camera framing the scene's bounds; lights likewise from `.light`
/// files. `opts.scale` then scales the scene, and the
/// result is validated once, with camera errors naming the `.view` file they came from.
pub fn load_scene(spec: &str, opts: &LoadOptions) -> Result<Scene, SceneError> {
    load_nested(spec, opts, 0)
}

/// A number in a scene spec: `part` of `spec`, naming `what` it should be when it is not.
fn spec_number(spec: &str, part: &str, what: &str) -> Result<u64, SceneError> {
    part.trim().parse().map_err(|_| SceneError::Procedural {
        spec: spec.into(),
        message: format!("`{part}` is not {what}"),
    })
}

/// `N[:SEED]` of a seeded generator's spec.
fn count_and_seed(spec: &str, rest: &str) -> Result<(u64, u64), SceneError> {
    let (n, seed) = match rest.split_once(':') {
        Some((n, seed)) => (n, Some(seed)),
        None => (rest, None),
    };
    let n = spec_number(spec, n, "a triangle count")?;
    let seed = match seed {
        Some(s) => spec_number(spec, s, "a seed (a whole number)")?,
        None => DEFAULT_SEED,
    };
    Ok((n, seed))
}

fn load_nested(spec: &str, opts: &LoadOptions, depth: usize) -> Result<Scene, SceneError> {
    let inner = |inner: &str, form: &str| -> Result<Scene, SceneError> {
        if inner.trim().is_empty() {
            return Err(SceneError::Procedural {
                spec: spec.into(),
                message: format!("expected `{form}` (no scene after the last `:`)"),
            });
        }
        if depth >= MAX_SPEC_NESTING {
            return Err(SceneError::Procedural {
                spec: spec.into(),
                message: format!("more than {MAX_SPEC_NESTING} nested `box:`/`subdivide:`"),
            });
        }
        // The inner scene gets its camera and lights; scaling is done once, outside.
        let o = LoadOptions {
            scale: None,
            ..opts.clone()
        };
        load_nested(inner, &o, depth + 1)
    };
    let count = |prefix: &str, what: &str| -> Result<Option<u64>, SceneError> {
        match spec.strip_prefix(prefix) {
            Some(n) => n
                .trim()
                .parse()
                .map(Some)
                .map_err(|_| SceneError::Procedural {
                    spec: spec.into(),
                    message: format!("expected {what} after `{prefix}`"),
                }),
            None => Ok(None),
        }
    };
    let mut is_file = false;
    let mut scene = if spec == "cornell" {
        cornell_box()
    } else if let Some(n) = count("procedural:", "a triangle count")? {
        procedural(n)?
    } else if let Some(n) = count("icosphere:", "a subdivision count")? {
        icosphere(n)?
    } else if let Some(rest) = spec.strip_prefix("hairball:") {
        let (n, seed) = count_and_seed(spec, rest)?;
        hairball(n, seed)?
    } else if let Some(rest) = spec.strip_prefix("vegetation:") {
        let (n, seed) = count_and_seed(spec, rest)?;
        vegetation(n, seed)?
    } else if let Some(rest) = spec.strip_prefix("box:") {
        enclose_in_box(inner(rest, "box:SCENE")?, spec)?
    } else if let Some(rest) = spec.strip_prefix("subdivide:") {
        let Some((n, rest)) = rest.split_once(':') else {
            return Err(SceneError::Procedural {
                spec: spec.into(),
                message: "expected `subdivide:N:SCENE`".into(),
            });
        };
        let levels = spec_number(spec, n, "a subdivision count")?;
        let levels = u32::try_from(levels).unwrap_or(u32::MAX);
        subdivide(
            inner(rest, "subdivide:N:SCENE")?,
            levels,
            spec,
            opts.triangle_limit(),
        )?
    } else {
        is_file = true;
        let path = Path::new(spec);
        match path.extension().and_then(|e| e.to_str()) {
            Some(e) if e.eq_ignore_ascii_case("obj") => obj::read_obj(path, opts.triangle_limit())?,
            Some(e) if e.eq_ignore_ascii_case("objl") => {
                obj::read_objl(path, opts.triangle_limit())?
            }
            _ if [
                "procedural",
                "icosphere",
                "hairball",
                "vegetation",
                "box",
                "subdivide",
            ]
            .contains(&spec) =>
            {
                return Err(SceneError::Procedural {
                    spec: spec.into(),
                    message: match spec {
                        "box" => "expected `box:SCENE`".into(),
                        "subdivide" => "expected `subdivide:N:SCENE`".into(),
                        "hairball" | "vegetation" => format!("expected `{spec}:N[:SEED]`"),
                        _ => format!("expected `{spec}:N`"),
                    },
                })
            }
            _ => return Err(SceneError::UnknownScene(spec.into())),
        }
    };
    let file = Path::new(spec);
    let view_path = opts.view.clone().or_else(|| {
        is_file
            .then(|| companion(file, "view", &mut scene.sources))
            .flatten()
    });
    let view_source = match view_path {
        Some(p) => {
            let text = read_source(&p, &mut scene.sources).map_err(|source| SceneError::Io {
                path: p.clone(),
                source,
            })?;
            scene.view = parse_view_str(&p, &text)?;
            ViewSource::File(p)
        }
        None if is_file => {
            scene.view = View::framing(&scene.bounds());
            scene.warnings.push(format!(
                "no .view file found for {}; using a camera framing the scene",
                file.display()
            ));
            ViewSource::Framing
        }
        None => ViewSource::BuiltIn,
    };
    let light_path = opts.light.clone().or_else(|| {
        is_file
            .then(|| companion(file, "light", &mut scene.sources))
            .flatten()
    });
    if let Some(p) = light_path {
        let text = read_source(&p, &mut scene.sources).map_err(|source| SceneError::Io {
            path: p.clone(),
            source,
        })?;
        scene.point_lights = vec![parse_light_str(&p, &text)?];
    }
    if let Some(s) = opts.scale {
        scene.scale(s)?;
    }
    // The camera is checked here, where its origin is known, before the rest.
    if let Err(e) = scene.view.camera() {
        let scaled = match opts.scale {
            Some(s) => format!(" (after scaling the scene by {})", show_number(s)),
            None => String::new(),
        };
        return Err(SceneError::BadCamera(match view_source {
            ViewSource::File(p) => format!("{}: {e}{scaled}", p.display()),
            ViewSource::Framing => format!(
                "{}: the camera framing the scene's bounds is unusable ({e}){scaled}; give a .view file with --view",
                file.display()
            ),
            ViewSource::BuiltIn => format!("scene `{spec}`: built-in camera: {e}{scaled}"),
        }));
    }
    scene.validate()?;
    Ok(scene)
}

/// A `.view`/`.light` file for a scene file: same stem, else the only one in the directory
/// (what was looked for goes to `sources`).
fn companion(file: &Path, ext: &str, sources: &mut Vec<Source>) -> Option<PathBuf> {
    let same = file.with_extension(ext);
    if same.is_file() {
        return Some(same);
    }
    sources.push(Source::Absent { path: same });
    let dir = file.parent().filter(|d| !d.as_os_str().is_empty());
    let dir = dir.unwrap_or(Path::new("."));
    let names = listing(dir, ext);
    sources.push(Source::Listing {
        dir: dir.to_path_buf(),
        ext: ext.to_string(),
        names: names.clone(),
    });
    match names.as_slice() {
        [one] => Some(dir.join(one)),
        _ => None,
    }
}
