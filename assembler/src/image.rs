//! The machine's initial memory: program segments from the linked ELF, the scene header at
//! [`abi::SCENE_HEADER_ADDR`], scene components after the program (64-byte aligned, each
//! after an unmapped guard gap of [`GUARD_GAP`] bytes, so an index just past one component
//! faults instead of reading the next), the framebuffer, and descriptions of the null guard
//! and the per-thread stack window.
//!
//! Scene components are linked on demand: a program that references the header field
//! `<field>` carries the absolute symbol `__trax_scene_<field>` in its `.symtab` (the linker
//! defines it as the field's address). Only components named that way are built and placed;
//! the camera and framebuffer are always present. The BVH is built only when `bvh_nodes`,
//! `bvh_parents` or `treelet_ids` is referenced; then every per-triangle component is stored
//! in BVH leaf order. Element layouts are those documented on [`abi::SceneHeader`].

use std::ops::Range;

use object::{Object, ObjectKind, ObjectSegment, ObjectSymbol};
use trax_runtime::abi::{self, Camera, Component, SceneHeader};

use crate::bvh::{Bvh, BvhError, BvhOptions, TreeletOptions, PAD};
use crate::scene::{Scene, SceneError};

/// Prefix of the symbols that mark a referenced header field.
pub const SCENE_SYMBOL_PREFIX: &str = "__trax_scene_";

/// Header fields that name optional, on-demand components.
pub const OPTIONAL_COMPONENTS: [&str; 10] = [
    "bvh_nodes",
    "triangles",
    "normals",
    "texcoords",
    "material_ids",
    "materials",
    "emitters",
    "point_lights",
    "bvh_parents",
    "treelet_ids",
];

/// Alignment of every placed component.
pub const COMPONENT_ALIGN: u32 = 64;
/// Unmapped bytes left before every placed component (after the program and between
/// components): accesses up to this far past a component's end or before its start fault.
pub const GUARD_GAP: u32 = 4096;
/// Bytes of the stored camera (18 × f32, [`Camera`]).
pub const CAMERA_BYTES: u32 = std::mem::size_of::<Camera>() as u32;

/// A contiguous range of initial memory. Bytes past `data.len()` up to `size` are zero.
#[derive(Clone, Debug, PartialEq)]
pub struct Segment {
    /// What it holds (`text`, `data`, `scene_header`, a component name...).
    pub name: String,
    /// First address.
    pub addr: u32,
    /// Initial bytes.
    pub data: Vec<u8>,
    /// Size in memory (>= `data.len()`).
    pub size: u32,
}

impl Segment {
    /// A segment whose bytes are all given.
    pub fn new(name: impl Into<String>, addr: u32, data: Vec<u8>) -> Segment {
        let size = data.len() as u32;
        Segment {
            name: name.into(),
            addr,
            data,
            size,
        }
    }

    /// One past the last address (as u64, so a segment ending at 4 GiB is representable).
    pub fn end(&self) -> u64 {
        self.addr as u64 + self.size as u64
    }
}

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
    /// BVH settings (treelets are formed when set here or when the program reads `treelet_ids`).
    pub bvh: BvhOptions,
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

/// The machine's initial memory.
#[derive(Clone, Debug)]
pub struct MemoryImage {
    /// Program segments, then the scene header, then components, in address order.
    pub segments: Vec<Segment>,
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

impl MemoryImage {
    /// The placed component with this header name.
    pub fn component(&self, name: &str) -> Option<&ComponentInfo> {
        self.components.iter().find(|c| c.name == name)
    }

    /// Total bytes of scene components (framebuffer and camera included).
    pub fn scene_bytes(&self) -> u64 {
        self.components.iter().map(|c| c.bytes as u64).sum()
    }

    /// Reads `len` initial bytes at `addr` (zeros inside a segment's zero tail), or `None`
    /// if any byte lies outside every segment.
    pub fn read(&self, addr: u32, len: u32) -> Option<Vec<u8>> {
        let mut out = Vec::with_capacity(len as usize);
        for a in addr as u64..addr as u64 + len as u64 {
            let s = self
                .segments
                .iter()
                .find(|s| (s.addr as u64..s.end()).contains(&a))?;
            let off = (a - s.addr as u64) as usize;
            out.push(s.data.get(off).copied().unwrap_or(0));
        }
        Some(out)
    }

    /// Reads a little-endian word.
    pub fn read_u32(&self, addr: u32) -> Option<u32> {
        let b = self.read(addr, 4)?;
        Some(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
    }
}

/// Errors from building a memory image.
#[derive(Debug, thiserror::Error)]
pub enum ImageError {
    /// The ELF could not be parsed.
    #[error("cannot read the program ELF: {0}")]
    Elf(String),
    /// The ELF is not a little-endian 32-bit MIPS executable.
    #[error("the program is not a little-endian ELF32 MIPS executable: {0}")]
    WrongKind(String),
    /// A `__trax_scene_*` symbol names no header field.
    #[error("symbol `{0}` names no scene header field (see trax_runtime::abi::SceneHeader)")]
    UnknownSceneField(String),
    /// A `__trax_scene_*` symbol has the wrong address.
    #[error("symbol `{symbol}` is at {found:#x}, but the header field is at {expected:#x}")]
    SceneSymbolMismatch {
        /// The symbol.
        symbol: String,
        /// Its value.
        found: u64,
        /// The field's address.
        expected: u64,
    },
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
}

/// A program read from an executable: loadable segments, entry, referenced header fields.
#[derive(Clone, Debug)]
pub struct Program {
    /// `PT_LOAD` segments (file bytes, zero tail up to the memory size).
    pub segments: Vec<Segment>,
    /// ELF entry point.
    pub entry: u32,
    /// Header fields named by `__trax_scene_<field>` symbols, sorted, deduplicated.
    pub referenced: Vec<String>,
}

/// Reads the loadable segments, entry and referenced scene fields of an ELF32 MIPS executable.
pub fn read_program(elf: &[u8]) -> Result<Program, ImageError> {
    let file = object::File::parse(elf).map_err(|e| ImageError::Elf(e.to_string()))?;
    if file.format() != object::BinaryFormat::Elf
        || file.is_64()
        || !file.is_little_endian()
        || file.architecture() != object::Architecture::Mips
    {
        return Err(ImageError::WrongKind(format!(
            "found {:?} {:?}, {}-bit, {}-endian",
            file.format(),
            file.architecture(),
            if file.is_64() { 64 } else { 32 },
            if file.is_little_endian() {
                "little"
            } else {
                "big"
            }
        )));
    }
    if file.kind() != ObjectKind::Executable {
        return Err(ImageError::WrongKind(format!(
            "file kind is {:?}, not an executable (was it linked?)",
            file.kind()
        )));
    }
    let mut segments = Vec::new();
    for (i, seg) in file.segments().enumerate() {
        let data = seg.data().map_err(|e| ImageError::Elf(e.to_string()))?;
        let (addr, size) = (seg.address(), seg.size());
        if size == 0 {
            continue;
        }
        if addr + size > u32::MAX as u64 + 1 || (data.len() as u64) > size {
            return Err(ImageError::Elf(format!(
                "segment {i} at {addr:#x} of {size} bytes does not fit in 32 bits"
            )));
        }
        let p = seg.permissions();
        let name = if p.executable() {
            "text"
        } else if p.writable() {
            "data"
        } else {
            "rodata"
        };
        segments.push(Segment {
            name: name.to_string(),
            addr: addr as u32,
            data: data.to_vec(),
            size: size as u32,
        });
    }
    let fields = abi::scene_header_fields();
    let mut referenced = Vec::new();
    for sym in file.symbols() {
        let Ok(name) = sym.name() else { continue };
        let Some(field) = name.strip_prefix(SCENE_SYMBOL_PREFIX) else {
            continue;
        };
        let Some(&(_, off)) = fields.iter().find(|(f, _)| *f == field) else {
            return Err(ImageError::UnknownSceneField(name.to_string()));
        };
        let expected = abi::SCENE_HEADER_ADDR as u64 + off as u64;
        if !sym.is_undefined() && sym.address() != expected {
            return Err(ImageError::SceneSymbolMismatch {
                symbol: name.to_string(),
                found: sym.address(),
                expected,
            });
        }
        referenced.push(field.to_string());
    }
    referenced.sort();
    referenced.dedup();
    Ok(Program {
        segments,
        entry: file.entry() as u32,
        referenced,
    })
}

/// Builds the initial memory for a linked executable and a scene.
pub fn build_image(
    elf: &[u8],
    scene: &Scene,
    opts: &RenderOptions,
) -> Result<MemoryImage, ImageError> {
    let p = read_program(elf)?;
    let refs: Vec<&str> = p.referenced.iter().map(String::as_str).collect();
    build_image_from_symbols(p.segments, p.entry, &refs, scene, opts)
}

/// Builds the initial memory from program segments and the list of referenced header fields
/// (e.g. for native runs or tests, without an ELF). Unknown field names are an error.
pub fn build_image_from_symbols(
    program: Vec<Segment>,
    entry: u32,
    referenced: &[&str],
    scene: &Scene,
    opts: &RenderOptions,
) -> Result<MemoryImage, ImageError> {
    let fields = abi::scene_header_fields();
    for r in referenced {
        if !fields.iter().any(|(f, _)| f == r) {
            return Err(ImageError::UnknownSceneField(format!(
                "{SCENE_SYMBOL_PREFIX}{r}"
            )));
        }
    }
    check_options(opts)?;
    let limit = abi::STACK_TOP as u64 - opts.stack_size as u64;
    check_program(&program, limit)?;
    let wants = |f: &str| referenced.contains(&f);
    scene.check()?;
    let camera = scene.view.camera()?;
    let n_tris = scene.triangles.len() as u64;

    // Sizes first (u64), so an oversized request fails before anything is allocated.
    let fb_bytes = opts.width as u64 * opts.height as u64 * 12;
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
    // A conservative pre-check with upper bounds (BVH < 2n nodes) before any building.
    {
        let mut probe = placer.cursor;
        for (f, per) in [
            ("triangles", 36u64),
            ("normals", 36),
            ("texcoords", 24),
            ("material_ids", 4),
            ("emitters", 4),
        ] {
            if wants(f) {
                probe += per * n_tris + (GUARD_GAP + COMPONENT_ALIGN) as u64;
            }
        }
        for (f, per) in [("bvh_nodes", 32u64), ("bvh_parents", 4), ("treelet_ids", 4)] {
            if wants(f) {
                probe += per * 2 * n_tris + (GUARD_GAP + COMPONENT_ALIGN) as u64;
            }
        }
        probe += fb_bytes + CAMERA_BYTES as u64 + 2 * (GUARD_GAP + COMPONENT_ALIGN) as u64;
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
    }

    // The BVH, only when the program reads it.
    let needs_bvh = wants("bvh_nodes") || wants("bvh_parents") || wants("treelet_ids");
    let bvh = if needs_bvh {
        let mut bo = opts.bvh.clone();
        if wants("treelet_ids") && bo.treelets.is_none() {
            bo.treelets = Some(TreeletOptions::default());
        }
        Some(Bvh::build(&scene.triangles, &bo)?)
    } else {
        None
    };
    // Slot order of per-triangle data.
    let order: Vec<u32> = match &bvh {
        Some(b) => b.tri_order.clone(),
        None => (0..n_tris as u32).collect(),
    };
    let row_align = opts
        .bvh
        .treelets
        .as_ref()
        .map_or(0, |t| t.align_bytes)
        .max(COMPONENT_ALIGN);

    let mut segments = program;
    let mut components = Vec::new();
    let mut header = SceneHeader {
        magic: abi::SCENE_MAGIC,
        version: abi::SCENE_VERSION,
        width: opts.width,
        height: opts.height,
        inv_width: 1.0 / opts.width as f32,
        inv_height: 1.0 / opts.height as f32,
        spp: opts.spp,
        max_depth: opts.max_depth,
        epsilon: opts.epsilon.unwrap_or_else(|| default_epsilon(scene)),
        seed: opts.seed,
        background: opts.background,
        ..SceneHeader::default()
    };
    let mut add = |segments: &mut Vec<Segment>,
                   name: &'static str,
                   count: u32,
                   data: Vec<u8>,
                   size: u64,
                   align: u32|
     -> Result<Component, ImageError> {
        let addr = placer.place(name, size, align)?;
        components.push(ComponentInfo {
            name,
            addr,
            count,
            bytes: size as u32,
        });
        segments.push(Segment {
            name: name.to_string(),
            addr,
            data,
            size: size as u32,
        });
        Ok(Component { addr, count })
    };

    header.camera = add(
        &mut segments,
        "camera",
        1,
        camera_bytes(&camera),
        CAMERA_BYTES as u64,
        COMPONENT_ALIGN,
    )?
    .addr;
    if let Some(b) = &bvh {
        if wants("bvh_nodes") {
            let data: Vec<u8> = b.nodes.iter().flat_map(|n| n.to_bytes()).collect();
            let len = data.len() as u64;
            header.bvh_nodes = add(
                &mut segments,
                "bvh_nodes",
                b.nodes.len() as u32,
                data,
                len,
                row_align,
            )?;
        }
    }
    let slots = order.len() as u32;
    if wants("triangles") {
        let data = words(order.iter().flat_map(|&s| {
            let t = if s == PAD {
                [[0.0; 3]; 3]
            } else {
                scene.triangles[s as usize]
            };
            t.into_iter().flatten().map(f32::to_bits)
        }));
        let len = data.len() as u64;
        header.triangles = add(&mut segments, "triangles", slots, data, len, row_align)?;
    }
    if wants("normals") {
        let data = words(order.iter().flat_map(|&s| {
            let t = if s == PAD {
                [[0.0; 3]; 3]
            } else {
                scene.normals[s as usize]
            };
            t.into_iter().flatten().map(f32::to_bits)
        }));
        let len = data.len() as u64;
        header.normals = add(&mut segments, "normals", slots, data, len, COMPONENT_ALIGN)?;
    }
    if wants("texcoords") {
        let data = words(order.iter().flat_map(|&s| {
            let t = if s == PAD {
                [[0.0; 2]; 3]
            } else {
                scene.texcoords[s as usize]
            };
            t.into_iter().flatten().map(f32::to_bits)
        }));
        let len = data.len() as u64;
        header.texcoords = add(
            &mut segments,
            "texcoords",
            slots,
            data,
            len,
            COMPONENT_ALIGN,
        )?;
    }
    if wants("material_ids") {
        let data = words(order.iter().map(|&s| {
            if s == PAD {
                0
            } else {
                scene.material_ids[s as usize]
            }
        }));
        let len = data.len() as u64;
        header.material_ids = add(
            &mut segments,
            "material_ids",
            slots,
            data,
            len,
            COMPONENT_ALIGN,
        )?;
    }
    if wants("materials") {
        let data = words(scene.materials.iter().flat_map(|m| {
            let mut w: Vec<u32> = m
                .diffuse
                .iter()
                .chain(&m.specular)
                .chain(&m.emission)
                .chain(std::iter::once(&m.shininess))
                .map(|f| f.to_bits())
                .collect();
            w.push(m.flags());
            w.push(0);
            w
        }));
        let len = data.len() as u64;
        header.materials = add(
            &mut segments,
            "materials",
            scene.materials.len() as u32,
            data,
            len,
            COMPONENT_ALIGN,
        )?;
    }
    if wants("emitters") {
        let emissive: Vec<bool> = scene.materials.iter().map(|m| m.is_emissive()).collect();
        let list: Vec<u32> = (0..slots)
            .filter(|&i| {
                let s = order[i as usize];
                s != PAD && emissive[scene.material_ids[s as usize] as usize]
            })
            .collect();
        let n = list.len() as u32;
        let data = words(list.into_iter());
        let len = data.len() as u64;
        header.emitters = add(&mut segments, "emitters", n, data, len, COMPONENT_ALIGN)?;
    }
    if wants("point_lights") {
        let data = words(
            scene
                .point_lights
                .iter()
                .flat_map(|l| l.position.into_iter().chain(l.color))
                .map(f32::to_bits),
        );
        let len = data.len() as u64;
        header.point_lights = add(
            &mut segments,
            "point_lights",
            scene.point_lights.len() as u32,
            data,
            len,
            COMPONENT_ALIGN,
        )?;
    }
    if let Some(b) = &bvh {
        if wants("bvh_parents") {
            let data = words(b.parents().into_iter());
            let len = data.len() as u64;
            header.bvh_parents = add(
                &mut segments,
                "bvh_parents",
                b.nodes.len() as u32,
                data,
                len,
                COMPONENT_ALIGN,
            )?;
        }
        if wants("treelet_ids") {
            let ids = b
                .treelets
                .as_ref()
                .map(|t| t.node_treelet.clone())
                .unwrap_or_default();
            let data = words(ids.into_iter());
            let len = data.len() as u64;
            header.treelet_ids = add(
                &mut segments,
                "treelet_ids",
                b.nodes.len() as u32,
                data,
                len,
                COMPONENT_ALIGN,
            )?;
        }
    }
    header.framebuffer = add(
        &mut segments,
        "framebuffer",
        opts.width * opts.height,
        Vec::new(),
        fb_bytes,
        COMPONENT_ALIGN,
    )?;
    let end = placer.cursor as u32;
    segments.push(Segment::new(
        "scene_header",
        abi::SCENE_HEADER_ADDR,
        header_bytes(&header),
    ));
    segments.sort_by_key(|s| s.addr);
    // Keep camera and framebuffer first in the report, the rest in address order.
    components.sort_by_key(|c| (c.name != "camera", c.name != "framebuffer", c.addr));
    Ok(MemoryImage {
        segments,
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

fn words(it: impl Iterator<Item = u32>) -> Vec<u8> {
    let mut out = Vec::with_capacity(it.size_hint().0 * 4);
    for w in it {
        out.extend_from_slice(&w.to_le_bytes());
    }
    out
}

/// The camera's 72 bytes: eye, u, v, w, left, right, bottom, top, distance, aperture.
pub fn camera_bytes(c: &Camera) -> Vec<u8> {
    words(
        c.eye
            .iter()
            .chain(&c.u)
            .chain(&c.v)
            .chain(&c.w)
            .chain(&[c.left, c.right, c.bottom, c.top, c.distance, c.aperture])
            .map(|f| f.to_bits()),
    )
}

/// The header's bytes, in field order (every field is a 4-byte word).
pub fn header_bytes(h: &SceneHeader) -> Vec<u8> {
    let comp = |c: &Component| [c.addr, c.count];
    let mut w: Vec<u32> = vec![
        h.magic,
        h.version,
        h.width,
        h.height,
        h.inv_width.to_bits(),
        h.inv_height.to_bits(),
        h.spp,
        h.max_depth,
        h.epsilon.to_bits(),
        h.seed,
    ];
    w.extend(h.background.map(f32::to_bits));
    w.push(h.camera);
    for c in [
        &h.framebuffer,
        &h.bvh_nodes,
        &h.triangles,
        &h.normals,
        &h.texcoords,
        &h.material_ids,
        &h.materials,
        &h.emitters,
        &h.point_lights,
        &h.bvh_parents,
        &h.treelet_ids,
    ] {
        w.extend(comp(c));
    }
    w.extend(h.reserved);
    let out = words(w.into_iter());
    debug_assert_eq!(out.len(), abi::SCENE_HEADER_SIZE);
    out
}
