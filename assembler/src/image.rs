//! The machine's initial memory for a program and a scene: program segments from the
//! linked executable (with its permissions), the scene header at
//! [`abi::SCENE_HEADER_ADDR`], scene components after the program (each after an unmapped
//! guard gap of [`GUARD_GAP`] bytes, so an index just past one component faults instead of
//! reading the next), the framebuffer, and descriptions of the null guard and the
//! per-thread stack window. The result is a [`SceneImage`]: the one [`MemoryImage`] type of
//! the runtime, plus the header, the placed components and the BVH it was built from.
//!
//! What is laid out comes from the scene contract, [`abi::SCENE_COMPONENTS`]: each
//! component's element type, alignment, permissions and whether it is always present or
//! built on demand. Components are linked on demand: a program that references the header
//! field `<field>` carries the absolute symbol `__trax_scene_<field>` in its `.symtab` (the
//! linker defines it as the field's address). Only components named that way are built and
//! placed; the camera and framebuffer are always present. The BVH is built only when a
//! component built from it is referenced; then every per-triangle component is stored in
//! BVH leaf order. Read-only components are placed first, in table order, then the
//! writable ones (the framebuffer), so the data kernels only read stays contiguous.
//!
//! Adding a component: one entry in `abi::SCENE_COMPONENTS` (plus its element struct, if
//! new), saying what it has one element per (`abi::Per`), and its producer here
//! ([`produce`]).

use std::ops::Range;

use trax_runtime::abi::{
    self, Access, Align, Component, ComponentDesc, Field, Need, Per, SceneHeader, SCENE_COMPONENTS,
};
use trax_runtime::exe::{ExeError, Executable};
pub use trax_runtime::image::{MemoryImage, Perms, Segment};

use crate::bvh::{Bvh, BvhError, BvhOptions, TreeletLayout, PAD};
use crate::scene::{Scene, SceneError};

/// Alignment of every placed component.
pub const COMPONENT_ALIGN: u32 = 64;
/// Unmapped bytes left before every placed component (after the program and between
/// components): accesses up to this far past a component's end or before its start fault.
pub const GUARD_GAP: u32 = 4096;

/// One placed scene component.
#[derive(Clone, Debug, PartialEq)]
pub struct ComponentInfo {
    /// Header field name (`camera`, `framebuffer`, `triangles`...).
    pub name: &'static str,
    /// Address of the first element.
    pub addr: u32,
    /// Element count.
    pub count: u32,
    /// Bytes occupied.
    pub bytes: u32,
}

/// Image and rendering parameters written into the scene header.
#[derive(Clone, Debug, PartialEq)]
pub struct RenderOptions {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Samples per pixel.
    pub spp: u32,
    /// Maximum path depth.
    pub max_depth: u32,
    /// Ray offset; `None` = 1e-4 × the scene's bounding-box diagonal (see [`default_epsilon`]).
    pub epsilon: Option<f32>,
    /// Seed for per-thread random streams.
    pub seed: u32,
    /// Background colour (linear RGB).
    pub background: [f32; 3],
    /// Per-thread stack (local store) size in bytes.
    pub stack_size: u32,
    /// BVH build settings; `bvh.treelets` must be `None` (the treelets come from
    /// `treelets`).
    pub bvh: BvhOptions,
    /// When treelets are formed and how (from the chip's `[treelets]`: see
    /// `trax::pipeline::image_options`). Treelet-aligned components (`bvh_nodes`,
    /// `triangles`) start on the alignment of the treelets actually formed.
    pub treelets: TreeletLayout,
    /// The shape of the chip's ray stream memory, written into the header for kernels.
    pub stream: StreamShape,
    /// The chip's `trax.setpipe` modes (header `pipe_modes`: bit m for mode m).
    pub pipe_modes: u32,
}

/// The ray stream memory's shape as kernels see it (header fields `stream_rays`,
/// `stream_ray_bytes`, `stream_buffers`); all zero when the chip has none.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct StreamShape {
    /// Rays it holds.
    pub rays: u32,
    /// Bytes of one ray record.
    pub ray_bytes: u32,
    /// Ray buffers.
    pub buffers: u32,
}

impl Default for RenderOptions {
    fn default() -> Self {
        RenderOptions {
            width: 128,
            height: 128,
            spp: 1,
            max_depth: 4,
            epsilon: None,
            seed: 1,
            background: [0.0; 3],
            stack_size: abi::DEFAULT_STACK_SIZE,
            bvh: BvhOptions::default(),
            treelets: TreeletLayout::default(),
            stream: StreamShape::default(),
            pipe_modes: 1,
        }
    }
}

/// The header's default `epsilon`: 1e-4 × the scene's bounding-box diagonal, computed in
/// f64, with no absolute floor, so it scales with the scene at every scale (an absolute
/// floor would swamp scenes smaller than it). A scene of zero size gets 1e-4 × 2^-20 × its
/// distance from the origin (or the smallest positive f32 at the origin).
pub fn default_epsilon(scene: &Scene) -> f32 {
    let b = scene.bounds();
    let mut size = b.diagonal_f64();
    if size == 0.0 {
        size = b.magnitude() as f64 * f64::powi(2.0, -20);
    }
    ((1e-4 * size) as f32).max(f32::from_bits(1))
}
/// The per-thread stack window: every thread sees its own `size` bytes below `top`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct StackLayout {
    /// One past the highest stack address (initial `$sp`).
    pub top: u32,
    /// Bytes per thread.
    pub size: u32,
}

/// A memory image laid out for a program and a scene, with what the layout decided.
#[derive(Clone, Debug)]
pub struct SceneImage {
    /// The machine's initial memory: program segments, the scene header and the
    /// components, in address order, each with its permissions.
    pub memory: MemoryImage,
    /// The header as written at [`abi::SCENE_HEADER_ADDR`].
    pub header: SceneHeader,
    /// Placed components (camera and framebuffer first), with their bytes.
    pub components: Vec<ComponentInfo>,
    /// Entry point (ELF entry).
    pub entry: u32,
    /// Addresses where any access is a null dereference.
    pub null_guard: Range<u32>,
    /// The stack window (described, not materialised).
    pub stack: StackLayout,
    /// First address after the program's segments.
    pub program_end: u32,
    /// First address after all global data.
    pub end: u32,
    /// The BVH, when one was built.
    pub bvh: Option<Bvh>,
}

impl SceneImage {
    /// The placed component with this header name.
    pub fn component(&self, name: &str) -> Option<&ComponentInfo> {
        self.components.iter().find(|c| c.name == name)
    }

    /// Total bytes of scene components (framebuffer and camera included).
    pub fn scene_bytes(&self) -> u64 {
        self.components.iter().map(|c| c.bytes as u64).sum()
    }
}

/// The components built only when a program references them, in table order.
pub fn on_demand_components() -> Vec<&'static str> {
    SCENE_COMPONENTS
        .iter()
        .filter(|c| c.need == Need::OnDemand)
        .map(|c| c.name)
        .collect()
}

/// Errors from building a memory image.
#[derive(Debug, thiserror::Error)]
pub enum ImageError {
    /// The executable is unusable (including `__trax_scene_*` symbols that name no header
    /// field or sit at the wrong address).
    #[error(transparent)]
    Exe(#[from] ExeError),
    /// A referenced name is no header field.
    #[error("symbol `{0}` names no scene header field (see trax_runtime::abi::SceneHeader)")]
    UnknownSceneField(String),
    /// A program segment overlaps a reserved region.
    #[error("program segment `{segment}` ({start:#x}..{end:#x}) overlaps {region}")]
    Overlap {
        /// Segment name.
        segment: String,
        /// First address.
        start: u64,
        /// One past the last address.
        end: u64,
        /// The reserved region.
        region: &'static str,
    },
    /// The image does not fit below the stack window.
    #[error("memory image too large: {what} would end at {end:#x}, past the limit {limit:#x} (stack window start)")]
    TooLarge {
        /// The component that does not fit.
        what: &'static str,
        /// Where it would end.
        end: u64,
        /// The limit.
        limit: u64,
    },
    /// A render option is out of range.
    #[error("invalid render option: {0}")]
    BadOption(String),
    /// The scene is invalid.
    #[error(transparent)]
    Scene(#[from] SceneError),
    /// The BVH could not be built.
    #[error(transparent)]
    Bvh(#[from] BvhError),
    /// A component of the contract has no producer here (a bug: see the module docs).
    #[error("internal error: scene component `{0}` has no producer in the image builder")]
    NoProducer(&'static str),
}

/// Builds the initial memory for a linked executable and a scene.
pub fn build_image(
    elf: &[u8],
    scene: &Scene,
    opts: &RenderOptions,
) -> Result<SceneImage, ImageError> {
    let exe = Executable::parse("program ELF", elf)?;
    let refs: Vec<&str> = exe.referenced.iter().map(String::as_str).collect();
    build_image_from_symbols(exe.segments, exe.entry, &refs, scene, opts)
}

/// Builds the initial memory from program segments and the list of referenced header fields
/// (e.g. for native runs or tests, without an ELF). Unknown field names are an error.
pub fn build_image_from_symbols(
    program: Vec<Segment>,
    entry: u32,
    referenced: &[&str],
    scene: &Scene,
    opts: &RenderOptions,
) -> Result<SceneImage, ImageError> {
    let fields = abi::scene_header_fields();
    for r in referenced {
        if !fields.iter().any(|(f, _)| f == r) {
            return Err(ImageError::UnknownSceneField(format!(
                "{}{r}",
                abi::SCENE_SYMBOL_PREFIX
            )));
        }
    }
    check_options(opts)?;
    let limit = abi::STACK_TOP as u64 - opts.stack_size as u64;
    check_program(&program, limit)?;
    scene.check()?;
    let camera = scene.view.camera()?;
    // The components to build, read-only ones first (table order), then writable ones.
    let mut wanted: Vec<&ComponentDesc> = SCENE_COMPONENTS
        .iter()
        .filter(|c| c.need == Need::Always || referenced.contains(&c.name))
        .collect();
    wanted.sort_by_key(|c| c.access == Access::ReadWrite);

    let program_end = program
        .iter()
        .map(Segment::end)
        .max()
        .unwrap_or(abi::TEXT_BASE as u64)
        .max(abi::TEXT_BASE as u64);
    let mut placer = Placer {
        cursor: program_end,
        limit,
    };
    // A conservative pre-check with upper bounds of the sizes, before anything is built.
    precheck(&wanted, &Sizes::of(scene, opts), placer.cursor, limit)?;

    // The BVH, only when the program reads a component built from it.
    let bvh = if wanted.iter().any(|c| c.per.from_bvh()) {
        let bo = BvhOptions {
            treelets: opts.treelets.for_program(referenced),
            ..opts.bvh.clone()
        };
        Some(Bvh::build(&scene.triangles, &bo)?)
    } else {
        None
    };
    // Slot order of per-triangle data.
    let order: Vec<u32> = match &bvh {
        Some(b) => b.tri_order.clone(),
        None => (0..scene.triangles.len() as u32).collect(),
    };
    // Treelet-aligned components start on the alignment of the treelets formed (treelet
    // starts are offsets from the arrays' starts).
    let row_align = bvh
        .as_ref()
        .and_then(|b| b.treelets.as_ref())
        .map_or(0, |t| t.options.align_bytes)
        .max(COMPONENT_ALIGN);

    let mut header = SceneHeader {
        spp: opts.spp,
        max_depth: opts.max_depth,
        epsilon: opts.epsilon.unwrap_or_else(|| default_epsilon(scene)),
        seed: opts.seed,
        background: opts.background,
        stream_rays: opts.stream.rays,
        stream_ray_bytes: opts.stream.ray_bytes,
        stream_buffers: opts.stream.buffers,
        pipe_modes: opts.pipe_modes,
        ..SceneHeader::new(opts.width, opts.height)
    };
    let ctx = Ctx {
        scene,
        bvh: bvh.as_ref(),
        order: &order,
        camera,
        opts,
    };
    let mut segments = program;
    let mut components = Vec::new();
    for c in wanted {
        let p = produce(c, &ctx)?;
        let align = match c.align {
            Align::Component => COMPONENT_ALIGN,
            Align::Rows => row_align,
        };
        let bytes = p.count as u64 * c.element_bytes as u64;
        let addr = placer.place(c.name, bytes, align)?;
        components.push(ComponentInfo {
            name: c.name,
            addr,
            count: p.count,
            bytes: bytes as u32,
        });
        let perms = match c.access {
            Access::ReadOnly => Perms::R,
            Access::ReadWrite => Perms::RW,
        };
        segments.push(Segment {
            name: c.name.to_string(),
            addr,
            data: p.data,
            size: bytes as u32,
            perms,
        });
        (c.set)(
            &mut header,
            Component {
                addr,
                count: p.count,
            },
        );
    }
    let end = placer.cursor as u32;
    segments.push(Segment::new(
        "scene_header",
        abi::SCENE_HEADER_ADDR,
        header.to_bytes(),
        Perms::R,
    ));
    segments.sort_by_key(|s| s.addr);
    // Always-present components first (table order), the rest in address order.
    let rank = |name: &str| {
        SCENE_COMPONENTS
            .iter()
            .position(|c| c.name == name && c.need == Need::Always)
            .unwrap_or(usize::MAX)
    };
    components.sort_by_key(|c| (rank(c.name), c.addr));
    Ok(SceneImage {
        memory: MemoryImage { segments },
        header,
        components,
        entry,
        null_guard: 0..abi::NULL_GUARD_END,
        stack: StackLayout {
            top: abi::STACK_TOP,
            size: opts.stack_size,
        },
        program_end: program_end as u32,
        end,
        bvh,
    })
}

/// What the producers read.
struct Ctx<'a> {
    scene: &'a Scene,
    bvh: Option<&'a Bvh>,
    /// Per-triangle slot order: scene triangle index per slot, or [`PAD`].
    order: &'a [u32],
    camera: abi::Camera,
    opts: &'a RenderOptions,
}

/// A produced component: its element count and initial bytes (a zero tail up to
/// `count` elements is implied).
struct Produced {
    count: u32,
    data: Vec<u8>,
}

impl Produced {
    fn of<T: Field>(items: impl IntoIterator<Item = T>) -> Produced {
        let data = abi::encode(items);
        Produced {
            count: (data.len() / std::mem::size_of::<T>()) as u32,
            data,
        }
    }

    /// One element per triangle slot: `f` of the scene triangle, zero for padding.
    fn per_slot<T: Field>(order: &[u32], f: impl Fn(usize) -> T) -> Produced {
        Produced::of(order.iter().map(|&s| {
            if s == PAD {
                T::default()
            } else {
                f(s as usize)
            }
        }))
    }
}

/// What the sizes of the components depend on, known before anything is built.
struct Sizes {
    tris: u64,
    materials: u64,
    lights: u64,
    pixels: u64,
}

impl Sizes {
    fn of(scene: &Scene, opts: &RenderOptions) -> Sizes {
        Sizes {
            tris: scene.triangles.len() as u64,
            materials: scene.materials.len() as u64,
            lights: scene.point_lights.len() as u64,
            pixels: opts.width as u64 * opts.height as u64,
        }
    }
}

/// A bound of component `c`'s element count, known before anything is built (treelet
/// padding slots can exceed it; placement checks the real sizes).
fn count_bound(c: &ComponentDesc, n: &Sizes) -> u64 {
    match c.per {
        Per::Scene => 1,
        Per::Pixel => n.pixels,
        // A binary BVH over n triangles has fewer than 2n nodes.
        Per::Node => 2 * n.tris,
        Per::Triangle | Per::LeafSlot => n.tris,
        Per::Material => n.materials,
        Per::Light => n.lights,
    }
}

/// Refuses components of sizes `n` that cannot fit between `start` and `limit` (upper
/// bounds of their sizes, guard gaps and alignment included): the image's pre-check.
fn precheck(
    wanted: &[&ComponentDesc],
    n: &Sizes,
    start: u64,
    limit: u64,
) -> Result<(), ImageError> {
    let mut probe = start;
    let mut fb_bytes = 0;
    for c in wanted {
        let bytes = c.element_bytes as u64 * count_bound(c, n);
        if c.name == "framebuffer" {
            fb_bytes = bytes;
        }
        probe += bytes + (GUARD_GAP + COMPONENT_ALIGN) as u64;
    }
    if probe > limit {
        let what = if fb_bytes > limit {
            "framebuffer"
        } else {
            "scene"
        };
        return Err(ImageError::TooLarge {
            what,
            end: probe,
            limit,
        });
    }
    Ok(())
}

/// The most triangles a scene can have for a program that reads the `referenced` header
/// fields, rendered with `opts`: the largest count the image's pre-check accepts with an
/// empty program, one material and no point lights (so an upper bound: a real program and
/// its materials take a little more). Scene loaders refuse larger scenes before building
/// them (`LoadOptions::max_triangles`).
pub fn max_triangles(referenced: &[&str], opts: &RenderOptions) -> u64 {
    let wanted: Vec<&ComponentDesc> = SCENE_COMPONENTS
        .iter()
        .filter(|c| c.need == Need::Always || referenced.contains(&c.name))
        .collect();
    let limit = (abi::STACK_TOP as u64).saturating_sub(opts.stack_size as u64);
    let fits = |tris: u64| {
        let n = Sizes {
            tris,
            materials: 1,
            lights: 0,
            pixels: opts.width as u64 * opts.height as u64,
        };
        precheck(&wanted, &n, abi::TEXT_BASE as u64, limit).is_ok()
    };
    if !fits(0) {
        return 0;
    }
    // The largest count that fits: fits(lo), not fits(hi).
    let (mut lo, mut hi) = (0u64, 1u64 << 32);
    while hi - lo > 1 {
        let mid = lo + (hi - lo) / 2;
        if fits(mid) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    lo.min(crate::scene::MAX_TRIANGLES)
}

/// The elements of component `c`.
fn produce(c: &ComponentDesc, x: &Ctx) -> Result<Produced, ImageError> {
    let s = x.scene;
    let bvh = || x.bvh.ok_or(ImageError::NoProducer(c.name));
    Ok(match c.name {
        "camera" => Produced::of([x.camera]),
        "framebuffer" => Produced {
            count: x.opts.width * x.opts.height,
            data: Vec::new(),
        },
        "bvh_nodes" => Produced::of(bvh()?.nodes.iter().map(|n| n.to_abi())),
        "triangles" => Produced::per_slot(x.order, |i| {
            let [v0, v1, v2] = s.triangles[i];
            abi::Triangle { v0, v1, v2 }
        }),
        "normals" => Produced::per_slot(x.order, |i| {
            let [n0, n1, n2] = s.normals[i];
            abi::VertexNormals { n0, n1, n2 }
        }),
        "texcoords" => Produced::per_slot(x.order, |i| {
            let [t0, t1, t2] = s.texcoords[i];
            abi::TexCoords { t0, t1, t2 }
        }),
        "material_ids" => Produced::per_slot(x.order, |i| s.material_ids[i]),
        "materials" => Produced::of(s.materials.iter().map(|m| abi::Material {
            diffuse: m.diffuse,
            specular: m.specular,
            emission: m.emission,
            shininess: m.shininess,
            flags: m.flags(),
            reserved: 0,
        })),
        "emitters" => {
            let emissive: Vec<bool> = s.materials.iter().map(|m| m.is_emissive()).collect();
            Produced::of((0..x.order.len() as u32).filter(|&i| {
                let t = x.order[i as usize];
                t != PAD && emissive[s.material_ids[t as usize] as usize]
            }))
        }
        "point_lights" => Produced::of(s.point_lights.iter().map(|l| abi::PointLight {
            position: l.position,
            color: l.color,
        })),
        "bvh_parents" => Produced::of(bvh()?.parents()),
        "treelet_ids" => Produced::of(
            bvh()?
                .treelets
                .as_ref()
                .map(|t| t.node_treelet.clone())
                .unwrap_or_default(),
        ),
        "tri_treelet_ids" => {
            let b = bvh()?;
            let mut ids = vec![u32::MAX; b.tri_order.len()];
            if let Some(t) = &b.treelets {
                let first = t.node_ranges.len() as u32;
                for (k, r) in t.tri_ranges.iter().enumerate() {
                    for slot in r.clone() {
                        if b.tri_order[slot as usize] != PAD {
                            ids[slot as usize] = first + k as u32;
                        }
                    }
                }
            }
            Produced::of(ids)
        }
        "tri_leaf_ids" => {
            let b = bvh()?;
            let mut ids = vec![u32::MAX; b.tri_order.len()];
            for (i, n) in b.nodes.iter().enumerate() {
                if n.is_leaf() {
                    ids[n.a as usize..(n.a + n.b) as usize].fill(i as u32);
                }
            }
            Produced::of(ids)
        }
        other => return Err(ImageError::NoProducer(table_name(other))),
    })
}

/// The table's own `&'static str` for a component name.
fn table_name(name: &str) -> &'static str {
    abi::component(name).map_or("?", |c| c.name)
}

/// Places components one after another below a limit, each after a guard gap.
struct Placer {
    cursor: u64,
    limit: u64,
}

impl Placer {
    fn place(&mut self, what: &'static str, bytes: u64, align: u32) -> Result<u32, ImageError> {
        let addr = (self.cursor + GUARD_GAP as u64).div_ceil(align as u64) * align as u64;
        let end = addr + bytes;
        if end > self.limit {
            return Err(ImageError::TooLarge {
                what,
                end,
                limit: self.limit,
            });
        }
        self.cursor = end;
        Ok(addr as u32)
    }
}

fn check_options(o: &RenderOptions) -> Result<(), ImageError> {
    if o.width == 0 || o.height == 0 {
        return Err(ImageError::BadOption(format!(
            "image size must be at least 1x1, got {}x{}",
            o.width, o.height
        )));
    }
    if o.spp == 0 {
        return Err(ImageError::BadOption(
            "samples per pixel (spp) must be at least 1".into(),
        ));
    }
    if o.stack_size == 0
        || !o.stack_size.is_multiple_of(8)
        || o.stack_size > abi::STACK_TOP - abi::TEXT_BASE
    {
        return Err(ImageError::BadOption(format!(
            "stack size must be a positive multiple of 8 below {:#x}, got {}",
            abi::STACK_TOP - abi::TEXT_BASE,
            o.stack_size
        )));
    }
    if o.bvh.treelets.is_some() {
        return Err(ImageError::BadOption(
            "bvh.treelets is set by the image builder: give the treelet layout as `treelets`"
                .into(),
        ));
    }
    if let Some(e) = o.epsilon {
        if !(e.is_finite() && e >= 0.0) {
            return Err(ImageError::BadOption(format!(
                "epsilon must be finite and >= 0, got {e}"
            )));
        }
    }
    if !o.background.iter().all(|c| c.is_finite()) {
        return Err(ImageError::BadOption(
            "background colour must be finite".into(),
        ));
    }
    Ok(())
}

fn check_program(program: &[Segment], limit: u64) -> Result<(), ImageError> {
    let header_end = abi::SCENE_HEADER_ADDR as u64 + abi::SCENE_HEADER_SIZE as u64;
    for s in program {
        let (start, end) = (s.addr as u64, s.end());
        let overlap = |region: &'static str| ImageError::Overlap {
            segment: s.name.clone(),
            start,
            end,
            region,
        };
        if start < abi::NULL_GUARD_END as u64 {
            return Err(overlap("the null guard"));
        }
        if start < header_end && end > abi::SCENE_HEADER_ADDR as u64 {
            return Err(overlap("the scene header"));
        }
        if end > limit {
            return Err(overlap("the stack window"));
        }
    }
    let mut sorted: Vec<&Segment> = program.iter().collect();
    sorted.sort_by_key(|s| s.addr);
    for w in sorted.windows(2) {
        if (w[1].addr as u64) < w[0].end() {
            return Err(ImageError::Overlap {
                segment: w[1].name.clone(),
                start: w[1].addr as u64,
                end: w[1].end(),
                region: "another program segment",
            });
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `max_triangles` is the image pre-check's boundary: that many triangles pass it, one
    /// more does not, for a triangle-only program, a path tracer's fields and every field.
    /// (`subdivide` once estimated with the triangle array alone, 3x too many for a path
    /// tracer: its scenes were built for minutes, then refused by the image.)
    #[test]
    fn max_triangles_is_the_precheck_boundary() {
        let every: Vec<&str> = SCENE_COMPONENTS.iter().map(|c| c.name).collect();
        let pathtracer = [
            "bvh_nodes",
            "triangles",
            "material_ids",
            "materials",
            "emitters",
        ];
        let opts = RenderOptions::default();
        let mut seen = Vec::new();
        for refs in [&["triangles"][..], &pathtracer[..], &every[..]] {
            let n = max_triangles(refs, &opts);
            let wanted: Vec<&ComponentDesc> = SCENE_COMPONENTS
                .iter()
                .filter(|c| c.need == Need::Always || refs.contains(&c.name))
                .collect();
            let sizes = |tris| Sizes {
                tris,
                materials: 1,
                lights: 0,
                pixels: u64::from(opts.width) * u64::from(opts.height),
            };
            let limit = abi::STACK_TOP as u64 - opts.stack_size as u64;
            let start = abi::TEXT_BASE as u64;
            assert!(
                precheck(&wanted, &sizes(n), start, limit).is_ok(),
                "{refs:?}: {n}"
            );
            assert!(
                precheck(&wanted, &sizes(n + 1), start, limit).is_err(),
                "{refs:?}"
            );
            seen.push(n);
        }
        // More fields, fewer triangles; the path tracer's limit is under half the
        // triangle array's alone.
        assert!(seen[0] > seen[1] && seen[1] > seen[2], "{seen:?}");
        assert!(seen[1] * 2 < seen[0], "{seen:?}");
    }
}
