//! The memory map and the scene header: the contract between the assembler, which lays out
//! memory, the emulator, which runs it, and kernels, which read it through the prelude.
//!
//! Addresses are bytes in a flat 32-bit space:
//!
//! | range | contents |
//! |---|---|
//! | `0 .. NULL_GUARD_END` | null guard: any access is reported as a null dereference |
//! | `SCENE_HEADER_ADDR ..` | the [`SceneHeader`] (one per image) |
//! | `TEXT_BASE ..` | program text, then read-only data, data and bss (as linked) |
//! | after the program | scene components, framebuffer (placed by the assembler, 64-byte aligned) |
//! | `STACK_TOP - stack_size .. STACK_TOP` | the running thread's own local store (its stack) |
//!
//! Every thread sees its own local store in the stack window: the same address in two
//! threads names two different bytes. Stack data must not be shared between threads.

/// First address past the null guard region.
pub const NULL_GUARD_END: u32 = 0x0001_0000;
/// Address of the scene header.
pub const SCENE_HEADER_ADDR: u32 = 0x0001_0000;
/// Address of the start of program text (the ELF's first loadable segment).
pub const TEXT_BASE: u32 = 0x0010_0000;
/// One past the highest stack address; the initial `$sp` of every thread.
pub const STACK_TOP: u32 = 0x8000_0000;
/// Default per-thread local store (stack) size in bytes.
pub const DEFAULT_STACK_SIZE: u32 = 64 * 1024;
/// Name of the kernel entry point.
pub const ENTRY_SYMBOL: &str = "trax_main";
/// Name of the start-up routine (ELF entry): sets up the thread, calls `trax_main`, halts.
pub const START_SYMBOL: &str = "__trax_start";
/// Magic value of [`SceneHeader::magic`] ("TRAX" little-endian).
pub const SCENE_MAGIC: u32 = u32::from_le_bytes(*b"TRAX");
/// Prefix of the symbols through which a program references scene components: the symbol
/// `__trax_scene_<field>` (field names as in [`scene_header_fields`]) is the absolute address
/// of that header field. The linker defines these; the image builder loads exactly the
/// components whose symbol the program references.
pub const SCENE_SYMBOL_PREFIX: &str = "__trax_scene_";
/// Version of the header layout; bump on any change.
pub const SCENE_VERSION: u32 = 1;

/// A pointer-and-count pair describing one scene component in simulated memory.
///
/// `addr` is 0 and `count` is 0 when the component is absent (not built because the
/// program does not reference it, or the scene has none).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Component {
    /// Address of the first element.
    pub addr: u32,
    /// Number of elements.
    pub count: u32,
}

/// The camera, as stored in simulated memory (simtrax `.view` semantics).
///
/// A primary ray through pixel `(x, y)` with image-plane coordinates
/// `s = left + (right-left)*(x+0.5)/width`, `t = bottom + (top-bottom)*(y+0.5)/height`
/// has origin `eye` and direction `normalize(distance*w + s*u + t*v)`, where `w` is the
/// normalized gaze direction, `u` = normalize(gaze × up) (right) and `v` = u × w (up).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Camera {
    pub eye: [f32; 3],
    pub u: [f32; 3],
    pub v: [f32; 3],
    pub w: [f32; 3],
    pub left: f32,
    pub right: f32,
    pub bottom: f32,
    pub top: f32,
    pub distance: f32,
    pub aperture: f32,
}

/// The scene header at [`SCENE_HEADER_ADDR`].
///
/// All fields are 4 bytes, so the layout has no padding. Component element layouts are
/// documented on each field.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SceneHeader {
    /// [`SCENE_MAGIC`].
    pub magic: u32,
    /// [`SCENE_VERSION`].
    pub version: u32,
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// `1.0 / width`.
    pub inv_width: f32,
    /// `1.0 / height`.
    pub inv_height: f32,
    /// Samples per pixel requested on the command line.
    pub spp: u32,
    /// Maximum path depth requested on the command line.
    pub max_depth: u32,
    /// Ray offset epsilon, scaled to the scene.
    pub epsilon: f32,
    /// Seed for per-thread random streams.
    pub seed: u32,
    /// Background (sky) colour, linear RGB.
    pub background: [f32; 3],
    /// The [`Camera`].
    pub camera: u32,
    /// Framebuffer: `width*height` pixels of 3 × f32 linear RGB, row 0 at the top.
    pub framebuffer: Component,
    /// BVH nodes, 32 bytes each, root at index 0: `min: [f32; 3]`, `max: [f32; 3]`, `a: u32`,
    /// `b: u32`. Interior node: `b == 0`, children at node indices `a` and `a + 1`.
    /// Leaf: `b` = triangle count (>= 1), triangles `a .. a + b` of [`SceneHeader::triangles`].
    pub bvh_nodes: Component,
    /// Triangles, 36 bytes each: three vertices of 3 × f32, in BVH leaf order.
    pub triangles: Component,
    /// Per-vertex normals, 36 bytes per triangle (3 × 3 × f32), same order as triangles.
    pub normals: Component,
    /// Per-vertex texture coordinates, 24 bytes per triangle (3 × 2 × f32).
    pub texcoords: Component,
    /// Material index per triangle (u32), same order as triangles.
    pub material_ids: Component,
    /// Materials, 48 bytes each: diffuse, specular, emission (3 × f32 each), then
    /// shininess (f32), flags (u32), reserved (u32).
    pub materials: Component,
    /// Indices (u32) of emissive triangles, for light sampling.
    pub emitters: Component,
    /// Point lights, 24 bytes each: position (3 × f32), colour (3 × f32).
    pub point_lights: Component,
    /// BVH parent pointers (u32 node index per node; root's is 0xFFFFFFFF).
    pub bvh_parents: Component,
    /// Treelet id per BVH node (u32).
    pub treelet_ids: Component,
    /// Reserved for future components; zero.
    pub reserved: [u32; 8],
}

/// Size of [`SceneHeader`] in bytes.
pub const SCENE_HEADER_SIZE: usize = std::mem::size_of::<SceneHeader>();

/// Byte offset of each header field, by name, for tools that lay out or check memory.
pub fn scene_header_fields() -> Vec<(&'static str, usize)> {
    use std::mem::offset_of;
    vec![
        ("magic", offset_of!(SceneHeader, magic)),
        ("version", offset_of!(SceneHeader, version)),
        ("width", offset_of!(SceneHeader, width)),
        ("height", offset_of!(SceneHeader, height)),
        ("inv_width", offset_of!(SceneHeader, inv_width)),
        ("inv_height", offset_of!(SceneHeader, inv_height)),
        ("spp", offset_of!(SceneHeader, spp)),
        ("max_depth", offset_of!(SceneHeader, max_depth)),
        ("epsilon", offset_of!(SceneHeader, epsilon)),
        ("seed", offset_of!(SceneHeader, seed)),
        ("background", offset_of!(SceneHeader, background)),
        ("camera", offset_of!(SceneHeader, camera)),
        ("framebuffer", offset_of!(SceneHeader, framebuffer)),
        ("bvh_nodes", offset_of!(SceneHeader, bvh_nodes)),
        ("triangles", offset_of!(SceneHeader, triangles)),
        ("normals", offset_of!(SceneHeader, normals)),
        ("texcoords", offset_of!(SceneHeader, texcoords)),
        ("material_ids", offset_of!(SceneHeader, material_ids)),
        ("materials", offset_of!(SceneHeader, materials)),
        ("emitters", offset_of!(SceneHeader, emitters)),
        ("point_lights", offset_of!(SceneHeader, point_lights)),
        ("bvh_parents", offset_of!(SceneHeader, bvh_parents)),
        ("treelet_ids", offset_of!(SceneHeader, treelet_ids)),
        ("reserved", offset_of!(SceneHeader, reserved)),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn header_has_no_padding() {
        let fields = scene_header_fields();
        // Each field starts where the previous one ends; all fields are 4-byte words.
        let mut sizes: Vec<usize> = fields.windows(2).map(|w| w[1].1 - w[0].1).collect();
        sizes.push(SCENE_HEADER_SIZE - fields.last().unwrap().1);
        assert!(sizes.iter().all(|s| s % 4 == 0 && *s > 0));
        assert_eq!(fields[0].1, 0);
        assert_eq!(std::mem::align_of::<SceneHeader>(), 4);
    }

    // The memory regions do not overlap (checked at compile time).
    const _: () = assert!(NULL_GUARD_END <= SCENE_HEADER_ADDR);
    const _: () = assert!(SCENE_HEADER_ADDR as usize + SCENE_HEADER_SIZE <= TEXT_BASE as usize);
    const _: () = assert!(TEXT_BASE < STACK_TOP - DEFAULT_STACK_SIZE);
}
